"""Diagnosis: where a fitted model fails, which physical effect of the catalog is missing, and
`refine`, which adds effects until the model is adequate (docs/diagnosis.md).

``catalog`` (the types), ``effects`` (the effects: the one file to add one), ``bands`` (failing
bands), ``diagnosis`` (`diagnose`, `Diagnosis`, `Verdict`), ``refinement`` (`refine`, the refinement loop)."""

from .catalog import BaselineContext as BaselineContext, Effect as Effect, EffectCatalog as EffectCatalog, Proposal as Proposal
from .diagnosis import Diagnosis as Diagnosis, Verdict as Verdict, diagnose as diagnose
from .effects import DEFAULT_EFFECTS as DEFAULT_EFFECTS
from .refinement import Refinement as Refinement, refine as refine
