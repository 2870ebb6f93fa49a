"""Bayesian fitting with emcee: priors, reparametrizations, the log-probability, the sampler and
the `Posterior` it returns."""

from .priors import PRIOR_KINDS as PRIOR_KINDS, Prior as Prior, parse_prior as parse_prior
from .reparam import (
    Reparametrization as Reparametrization,
    gap_thickness_reparametrization as gap_thickness_reparametrization,
    stratum_corneum_reparametrization as stratum_corneum_reparametrization,
)
from .sampler import NOISE_MODELS as NOISE_MODELS, Posterior as Posterior, sample as sample
