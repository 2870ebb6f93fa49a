"""The refinement loop: diagnose → add the best significant effect → refit, until the model is
adequate (docs/diagnosis.md, section 6). The final model is refitted from scratch with `fit`,
so the result reproduces with ``impedax fit`` of the final model string."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import xarray as xr

from ...arguments import MAX_STARTS, checked_arguments, choice, count, flag, frequency, instance_of, real, seed as seed_rule
from ...circuits import Circuit, DEFAULT_REGISTRY, Registry
from ...errors import ParameterError
from ..least_squares import FitResult, fit
from ..problem import WEIGHTINGS, open_spectrum
from .catalog import EffectCatalog
from .diagnosis import Diagnosis, Verdict, diagnose, undetermined_parameters
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
    notes: tuple[str, ...] = ()
    masked_points: tuple[float, ...] = ()  # frequencies [Hz] left out of every fit (KK-flagged)

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
        final = self.final
        return {
            "steps": [s.as_json() for s in self.steps], "final_model": self.final_model, "verdict": self.verdict,
            "final_rms_rel": final.rms_rel, "n_params": final.n_params, "undetermined": sorted(undetermined_parameters(final)),
            "masked_points": [float(f) for f in self.masked_points], "notes": list(self.notes),
        }

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
        lines += [f"note: {n}" for n in self.notes]
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


def _reproduced(ds: xr.Dataset, last: FitResult, *, n_starts: int, seed: int) -> tuple[FitResult, str | None]:
    """The final model fitted from scratch with `fit` (what ``impedax fit`` of its model string
    does on the same points); when the loop's warm fit is better, `fit` started from it."""
    scratch = fit(last.circuit, ds, fixed={k: v for k, v in last.values.items() if last.fixed[k]} or None, weighting=last.weighting, registry=last.registry, seed=seed)
    if scratch.chi2 <= last.chi2 * (1 + 1e-6):
        return scratch, None
    warm = fit(last.circuit, ds, init=last, fixed={k: v for k, v in last.values.items() if last.fixed[k]} or None, weighting=last.weighting, registry=last.registry, seed=seed)
    note = f"fit of {last.model} from scratch reaches rms_rel {scratch.rms_rel * 100:.3g} %; started from the refinement's values it reaches {warm.rms_rel * 100:.3g} % (pass init=)"
    return (warm, note) if warm.chi2 <= scratch.chi2 else (scratch, None)


@checked_arguments(
    max_steps=count(0, 64, optional=True, why="each step adds one element"), max_effects=count(0, 64, optional=True, why="each step adds one element"),
    solver_steps=count(1, 100_000), effects=instance_of(EffectCatalog, what="an EffectCatalog (e.g. impedax.DEFAULT_EFFECTS)"),
    weighting=choice(WEIGHTINGS), noise=real(positive=True, optional=True), registry=instance_of(Registry), fmin=frequency, fmax=frequency,
    n_starts=count(1, MAX_STARTS), seed=seed_rule, drt_evidence=flag,
)
def refine(
    data,
    circuit: Circuit | str,
    *,
    max_steps: int | None = None,
    max_effects: int | None = None,
    solver_steps: int = 100,
    effects: EffectCatalog = DEFAULT_EFFECTS,
    weighting: str = "modulus",
    noise: float | None = None,
    registry: Registry = DEFAULT_REGISTRY,
    fmin: float | None = None,
    fmax: float | None = None,
    n_starts: int = 4,
    seed: int = 0,
    drt_evidence: bool = True,
    progress: Callable[[str], None] | None = None,
) -> Refinement:
    """Refine ``circuit`` on ``data``: diagnose → add the best significant effect → refit, until
    the verdict is not ``missing_effect`` (or no suggestion remains) or ``max_effects`` (default
    4; ``max_steps`` is its older name) effects were added. ``solver_steps``: the
    Levenberg–Marquardt step limit of the candidate fits (``--max-steps`` of the CLI).
    ``registry`` parses the circuit; only the points with ``fmin`` ≤ f ≤ ``fmax`` are used, at
    every step, less the points the first diagnosis masks (KK-flagged); ``drt_evidence`` as in
    `diagnose`; ``progress`` is called with a line of text as each step starts. The final model
    is refitted with `fit` on the same points (reproducible with ``impedax fit``); a last
    step whose refit leaves parameters undetermined is dropped. Returns a `Refinement`."""
    if max_steps is not None and max_effects is not None:
        raise ParameterError("give max_effects (max_steps is its older name), not both")
    limit = max_effects if max_effects is not None else (max_steps if max_steps is not None else 4)
    if not isinstance(limit, int) or isinstance(limit, bool) or limit < 0:
        raise ParameterError(f"max_effects must be a non-negative integer, got {limit!r}")
    if not isinstance(solver_steps, int) or solver_steps < 1:
        raise ParameterError(f"solver_steps must be a positive integer, got {solver_steps!r}")
    say = progress or (lambda text: None)
    ds = open_spectrum(data, fmin=fmin, fmax=fmax, single="refine").data
    steps: list[RefinementStep] = []
    added = effect = None
    verdict = Verdict.MISSING_EFFECT
    current = None
    masked: tuple[float, ...] = ()
    for i in range(limit + 1):
        say(f"step {i}: diagnosing {current.model if current is not None else circuit}")
        shape = steps[-1].diagnosis.solver_shape if steps else None  # every step through one compiled solver
        if current is None:
            d = diagnose(ds, circuit, effects=effects, noise=noise, weighting=weighting, registry=registry, n_starts=n_starts, max_steps=solver_steps, seed=seed, drt_evidence=drt_evidence)
            masked = d.masked_points
        else:
            d = diagnose(current, data=ds, effects=effects, kk=steps[0].diagnosis.kk_of_kept or steps[0].diagnosis.kk, noise=noise, n_starts=n_starts, max_steps=solver_steps, seed=seed, drt_evidence=drt_evidence, solver_shape=shape, mask=False)
        steps.append(RefinementStep(d.baseline, added, effect, d))
        verdict = d.verdict
        if d.verdict != Verdict.MISSING_EFFECT or d.best is None or i == limit:
            break
        best = d.best
        current, added, effect = best.fit, best.added, best.effect
    notes: list[str] = []
    used = ds if not masked else ds.sel(frequency=[f for f in ds["frequency"].values if float(f) not in set(masked)])
    say(f"refitting the final model {steps[-1].model} from scratch")
    final, note = _reproduced(used, steps[-1].fit, n_starts=n_starts, seed=seed)
    if note:
        notes.append(note)
    new_undetermined = undetermined_parameters(final) - undetermined_parameters(steps[0].fit)
    if new_undetermined and len(steps) > 1:
        notes.append(f"{final.model}: the data do not determine {', '.join(sorted(new_undetermined))} when fitted from scratch; the step that added {steps[-1].added} is dropped")
        steps.pop()
        final, note = _reproduced(used, steps[-1].fit, n_starts=n_starts, seed=seed)
        verdict = steps[-1].diagnosis.verdict if steps[-1].diagnosis is not None else verdict
    steps[-1] = RefinementStep(final, steps[-1].added, steps[-1].effect, steps[-1].diagnosis)
    return Refinement(tuple(steps), verdict, tuple(notes), masked)
