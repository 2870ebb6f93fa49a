"""Fitting circuits to spectra: least squares (`least_squares/`), Bayesian sampling (`bayes/`),
diagnosis of missing effects (`diagnosis/`), model comparison and the Kramers–Kronig test."""

from .bayes import (
    NOISE_MODELS as NOISE_MODELS,
    PRIOR_KINDS as PRIOR_KINDS,
    Posterior as Posterior,
    Prior as Prior,
    Reparametrization as Reparametrization,
    SharedPosterior as SharedPosterior,
    gap_thickness_reparametrization as gap_thickness_reparametrization,
    parse_prior as parse_prior,
    sample as sample,
    stratum_corneum_reparametrization as stratum_corneum_reparametrization,
)
from .comparison import Comparison as Comparison, compare as compare, is_nested as is_nested
from .batch_comparison import BatchComparison as BatchComparison  # (registers compare's batch path)
from .derived import derive as derive, derive_fit as derive_fit
from .diagnosis import (
    DEFAULT_EFFECTS as DEFAULT_EFFECTS,
    Diagnosis as Diagnosis,
    Effect as Effect,
    EffectCatalog as EffectCatalog,
    Refinement as Refinement,
    diagnose as diagnose,
    refine as refine,
)
from .drt import DRTResult as DRTResult, drt as drt
from .zhit import ZHITBatchResult as ZHITBatchResult, ZHITResult as ZHITResult, zhit as zhit, zhit_batch as zhit_batch
from .kk import KKBatchResult as KKBatchResult, KKResult as KKResult, kk_test as kk_test, kk_test_batch as kk_test_batch
from .least_squares import BatchFitResult as BatchFitResult, FitResult as FitResult, SharedFitResult as SharedFitResult, WEIGHTINGS as WEIGHTINGS, fit as fit
from .statistics import information_criteria as information_criteria
