"""Bayesian fitting with emcee.

priors (the prior families and defaults) · reparam (physical reparametrizations) · logprob (the
jitted log-probability and noise models) · sampler (`sample`, step by step) · evidence (Laplace
log evidence, WAIC) · diagnostics (autocorrelation, HDI, warnings) · posterior (the `Posterior`
result: summaries, propagation, storage). Figures: `impedax.plotting.bayes`.
"""

from .logprob import NOISE_MODELS as NOISE_MODELS, NoiseModel as NoiseModel
from .posterior import Posterior as Posterior
from .priors import PRIOR_KINDS as PRIOR_KINDS, Prior as Prior, PriorKind as PriorKind, parse_prior as parse_prior
from .reparam import (
    Reparametrization as Reparametrization,
    ReparametrizationKind as ReparametrizationKind,
    gap_thickness_reparametrization as gap_thickness_reparametrization,
    stratum_corneum_reparametrization as stratum_corneum_reparametrization,
)
from .sampler import sample as sample
from .shared_posterior import SharedPosterior as SharedPosterior
