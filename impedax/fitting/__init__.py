"""Least-squares and Bayesian fitting, model comparison, validation and diagnosis."""

from ._batch import BatchFitResult as BatchFitResult
from ._compare import Comparison as Comparison, compare as compare, is_nested as is_nested
from ._fit import WEIGHTINGS as WEIGHTINGS, FitResult as FitResult, fit as fit, information_criteria as information_criteria
from ._kk import KKBatchResult as KKBatchResult, KKResult as KKResult, kk_test as kk_test, kk_test_batch as kk_test_batch
from ._bayes import NOISE_MODELS as NOISE_MODELS, Posterior as Posterior, sample as sample
from ._derive import derive as derive, derive_fit as derive_fit
from ._priors import PRIOR_KINDS as PRIOR_KINDS, Prior as Prior, parse_prior as parse_prior
from ._reparam import (
    Reparametrization as Reparametrization,
    gap_thickness_reparametrization as gap_thickness_reparametrization,
    stratum_corneum_reparametrization as stratum_corneum_reparametrization,
)
from ._effects import DEFAULT_EFFECTS as DEFAULT_EFFECTS, Effect as Effect, EffectCatalog as EffectCatalog
from ._diagnose import Diagnosis as Diagnosis, Refinement as Refinement, diagnose as diagnose, refine as refine
