"""Least-squares and Bayesian fitting, model comparison, validation and diagnosis."""

from ._batch import BatchFitResult as BatchFitResult
from ._compare import Comparison as Comparison, compare as compare, is_nested as is_nested
from ._fit import WEIGHTINGS as WEIGHTINGS, FitResult as FitResult, fit as fit, information_criteria as information_criteria
from ._kk import KKBatchResult as KKBatchResult, KKResult as KKResult, kk_test as kk_test, kk_test_batch as kk_test_batch
from ._effects import DEFAULT_EFFECTS as DEFAULT_EFFECTS, Effect as Effect, EffectCatalog as EffectCatalog
from ._diagnose import Diagnosis as Diagnosis, Refinement as Refinement, diagnose as diagnose, refine as refine
