"""Diagnosis: where a fitted model fails, which physical effect of the catalog is missing, and
`refine`, which adds effects until the model is adequate."""

from .effects import DEFAULT_EFFECTS as DEFAULT_EFFECTS, Effect as Effect, EffectCatalog as EffectCatalog
from .diagnosis import Diagnosis as Diagnosis, Refinement as Refinement, diagnose as diagnose, refine as refine
