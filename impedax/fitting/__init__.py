"""Fitting circuits to spectra: least squares (`least_squares/`), Bayesian sampling (`bayes/`),
diagnosis of missing effects (`diagnosis/`), model comparison and the Kramers–Kronig test.

Each name is imported with its module on first use (PEP 562, `__getattr__` below), so that a
least-squares fit does not import the sampler, the diagnosis and the comparison (nor `impedax
kk` the fitter's solvers), and a submodule (``impedax.fitting.kk``) is there when first named.
"""

from __future__ import annotations

import importlib

# a function named as its module (``impedax.fitting.drt``, ``zhit``) is bound here at import, as
# before: bound lazily, it would be hidden by the submodule the first time that is imported
from .drt import DRTResult as DRTResult, drt as drt
from .zhit import ZHITBatchResult as ZHITBatchResult, ZHITResult as ZHITResult, zhit as zhit, zhit_batch as zhit_batch

# public name → the submodule that defines it
_NAMES = {
    **dict.fromkeys(("NOISE_MODELS", "PRIOR_KINDS", "Posterior", "Prior", "Reparametrization", "SharedPosterior", "gap_thickness_reparametrization",
                     "parse_prior", "sample", "stratum_corneum_reparametrization"), ".bayes"),
    **dict.fromkeys(("Comparison", "compare", "is_nested"), ".comparison"),
    "BatchComparison": ".batch_comparison",
    **dict.fromkeys(("derive", "derive_fit"), ".derived"),
    **dict.fromkeys(("DEFAULT_EFFECTS", "Diagnosis", "Effect", "EffectCatalog", "Refinement", "diagnose", "refine"), ".diagnosis"),
    **dict.fromkeys(("KKBatchResult", "KKResult", "kk_test", "kk_test_batch"), ".kk"),
    **dict.fromkeys(("BatchFitResult", "FitResult", "SharedFitResult", "WEIGHTINGS", "fit"), ".least_squares"),
    "information_criteria": ".statistics",
}
_SUBMODULES = ("arcs", "batch_comparison", "bayes", "comparison", "derived", "diagnosis", "frozen", "grid", "kk", "least_squares",
               "parameters", "problem", "reductions", "statistics", "stored")


def __getattr__(name: str):
    """A public name or a submodule, imported on first use."""
    if name in _SUBMODULES:
        return importlib.import_module(f".{name}", __name__)
    try:
        module = _NAMES[name]
    except KeyError:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    if module in (".comparison", ".batch_comparison"):
        importlib.import_module(".batch_comparison", __name__)  # (registers compare's batch path: `comparison.register_batch_compare`)
    value = getattr(importlib.import_module(module, __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_NAMES) | set(_SUBMODULES))


__all__ = sorted([*_NAMES, "DRTResult", "drt", "ZHITBatchResult", "ZHITResult", "zhit", "zhit_batch"])
