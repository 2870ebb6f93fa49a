"""The refinement loop: diagnose → add the best significant effect → refit, until the model is
adequate (docs/diagnosis.md, section 6)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from ...arguments import MAX_STARTS, checked_arguments, choice, count, flag, frequency, instance_of, real, seed as seed_rule
from ...circuits import Circuit, DEFAULT_REGISTRY, Registry
from ...errors import ParameterError
from ..least_squares import FitResult
from ..problem import WEIGHTINGS, open_spectrum
from .catalog import EffectCatalog
from .diagnosis import Diagnosis, Verdict, diagnose
from .effects import DEFAULT_EFFECTS

__all__ = ["Refinement", "RefinementStep", "refine"]


@dataclass(frozen=True, eq=False)
class RefinementStep:
    """One model of the loop: its fit, what was added to get it, and its diagnosis."""

    fit: FitResult
    added: str | None
    effect: str | None
    diagnosis: Diagnosis | None

    @property
    def model(self) -> str:
        return self.fit.model

    def as_json(self) -> dict:
        return {"model": self.model, "rms_rel": self.fit.rms_rel, "aic": self.fit.aic, "added": self.added, "effect": self.effect, "bic": self.fit.bic, "chi2_red": self.fit.chi2_red, "verdict": self.diagnosis.verdict if self.diagnosis else None}


@dataclass(frozen=True, eq=False)
class Refinement:
    """Outcome of `refine`: the steps (first: the user's model), the final model and verdict."""

    steps: tuple[RefinementStep, ...]
    verdict: Verdict

    def __post_init__(self):
        object.__setattr__(self, "verdict", Verdict(self.verdict))

    @property
    def final(self) -> FitResult:
        return self.steps[-1].fit

    @property
    def final_model(self) -> str:
        return self.final.model

    def summary(self) -> dict:
        """The JSON of ``impedax refine --json``."""
        return {"steps": [s.as_json() for s in self.steps], "final_model": self.final_model, "verdict": self.verdict}

    def to_table(self) -> list[dict[str, object]]:
        """The tidy table of the final model's parameters (`FitResult.to_table`)."""
        return self.final.to_table()

    def _repr_html_(self) -> str:
        from ...plotting.html import result_html

        rows = [{"step": i, "added": s.added or "(start)", "model": s.model, "rms_rel": s.fit.rms_rel, "AIC": s.fit.aic} for i, s in enumerate(self.steps)]
        return result_html(f"refinement: {self.final_model}", rows, lines=[f"verdict: {self.verdict}"])

    def table(self) -> str:
        lines = [f"{'step':>4}  {'rms_rel':>9}  {'AIC':>9}  added / model"]
        for i, s in enumerate(self.steps):
            what = f"+ {s.added} [{s.effect}]" if s.added else "(start)"
            lines.append(f"{i:>4}  {s.fit.rms_rel * 100:>8.3g}%  {s.fit.aic:>9.1f}  {what}")
            lines.append(f"{'':>4}  {'':>9}  {'':>9}  {s.model}")
        return "\n".join(lines)

    def report(self) -> str:
        first, last = self.steps[0].fit, self.final
        lines = [self.table(), ""]
        if len(self.steps) > 1:
            lines.append(f"rms_rel fell from {first.rms_rel * 100:.3g} % to {last.rms_rel * 100:.3g} % in {len(self.steps) - 1} step(s); AIC {first.aic:.1f} → {last.aic:.1f}.")
        last_d = self.steps[-1].diagnosis
        lines.append(f"verdict: {self.verdict.upper()}" + (f" — {last_d.reason}" if last_d is not None else ""))
        return "\n".join(lines)

    def plot(self, *, title: str | None = None):
        """Error per step (rms_rel, log scale) and the relative residuals of every step vs
        frequency, with the failing bands shaded (matplotlib Figure; `impedax.plotting.diagnosis`)."""
        from ...plotting.diagnosis import plot_refinement

        return plot_refinement(self, title=title)

    def to_xarray(self) -> xr.Dataset:
        """Per-step model, rms_rel, AIC, BIC, added element, and residuals over (step, frequency)."""
        f = self.steps[0].fit.frequency
        return xr.Dataset(
            {
                "model": ("step", [s.model for s in self.steps]),
                "added": ("step", [s.added or "" for s in self.steps]),
                "effect": ("step", [s.effect or "" for s in self.steps]),
                "rms_rel": ("step", [s.fit.rms_rel for s in self.steps]),
                "aic": ("step", [s.fit.aic for s in self.steps]),
                "bic": ("step", [s.fit.bic for s in self.steps]),
                "residual_rel": (("step", "frequency"), np.stack([s.fit.residuals for s in self.steps])),
                "Z": ("frequency", self.steps[0].fit.z_data, {"units": "ohm"}),
            },
            coords={"step": np.arange(len(self.steps)), "frequency": ("frequency", f, {"units": "Hz"})},
            attrs={"final_model": self.final_model, "verdict": str(self.verdict)},
        )


@checked_arguments(
    max_steps=count(0, 64, why="each step adds one element"), effects=instance_of(EffectCatalog, what="an EffectCatalog (e.g. impedax.DEFAULT_EFFECTS)"),
    weighting=choice(WEIGHTINGS), noise=real(positive=True, optional=True), registry=instance_of(Registry), fmin=frequency, fmax=frequency,
    n_starts=count(1, MAX_STARTS), seed=seed_rule, drt_evidence=flag,
)
def refine(
    data,
    circuit: Circuit | str,
    *,
    max_steps: int = 4,
    effects: EffectCatalog = DEFAULT_EFFECTS,
    weighting: str = "modulus",
    noise: float | None = None,
    registry: Registry = DEFAULT_REGISTRY,
    fmin: float | None = None,
    fmax: float | None = None,
    n_starts: int = 4,
    seed: int = 0,
    drt_evidence: bool = True,
) -> Refinement:
    """Refine ``circuit`` on ``data``: diagnose → add the best significant effect → refit, until
    the verdict is not ``missing_effect`` (or no suggestion remains) or ``max_steps`` effects
    were added. ``registry`` parses the circuit; only the points with ``fmin`` ≤ f ≤ ``fmax`` are
    used, at every step; ``drt_evidence`` as in `diagnose`. Returns a `Refinement` (steps with model, rms_rel, AIC and what was added)."""
    if not isinstance(max_steps, int) or max_steps < 0:
        raise ParameterError(f"max_steps must be a non-negative integer, got {max_steps!r}")
    ds = open_spectrum(data, fmin=fmin, fmax=fmax, single="refine").data
    steps: list[RefinementStep] = []
    added = effect = None
    verdict = Verdict.MISSING_EFFECT
    current = None
    for i in range(max_steps + 1):
        if current is None:
            d = diagnose(ds, circuit, effects=effects, noise=noise, weighting=weighting, registry=registry, n_starts=n_starts, seed=seed, drt_evidence=drt_evidence)
        else:
            d = diagnose(current, data=ds, effects=effects, kk=steps[0].diagnosis.kk, noise=noise, n_starts=n_starts, seed=seed, drt_evidence=drt_evidence)
        steps.append(RefinementStep(d.baseline, added, effect, d))
        verdict = d.verdict
        if d.verdict != Verdict.MISSING_EFFECT or d.best is None or i == max_steps:
            break
        best = d.best
        current, added, effect = best.fit, best.added, best.effect
    return Refinement(tuple(steps), verdict)
