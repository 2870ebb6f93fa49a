"""The result of a least-squares fit of one spectrum (`FitResult`), built from the solver's
outputs with its uncertainties and warnings; the warning rules are shared with batch fits
(`stack_notes` builds the same text for a stack of fits at once)."""

from __future__ import annotations

import collections
import math
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from ...circuits import Circuit, DEFAULT_REGISTRY, Registry, compile_circuit
from ..parameters import ParameterTable
from ..statistics import information_criteria, uncertainties
from .solvers import SolverOutput, SolverStatus

__all__ = ["FitResult", "fit_result", "fit_notes", "stack_notes", "CORRELATION_LIMIT", "RELATIVE_ERROR_LIMIT"]

# identifiability thresholds (documented in the README)
CORRELATION_LIMIT = 0.99
RELATIVE_ERROR_LIMIT = 1.0


@dataclass(frozen=True, eq=False)
class FitResult:
    """A least-squares fit of ``circuit`` to one spectrum. Immutable.

    ``values``/``stderr`` are keyed by parameter name (stderr NaN for fixed parameters);
    ``covariance``/``correlation`` are over ``free_names``. ``residuals`` are the complex
    relative residuals r_k = (Z_model,k − Z_data,k)/|Z_data,k| and
    ``rms_rel = sqrt(mean |r_k|²)`` (docs/physics.md, "Goodness of fit"). ``chi2`` is the sum of the squared
    weighted residuals, ``chi2_red = chi2/(2N − k)``; AIC/BIC see `information_criteria`.
    """

    circuit: Circuit
    values: dict[str, float]
    stderr: dict[str, float]
    fixed: dict[str, bool]
    free_names: tuple[str, ...]
    covariance: np.ndarray
    correlation: np.ndarray
    frequency: np.ndarray
    z_data: np.ndarray
    z_model: np.ndarray
    weighting: str
    chi2: float
    converged: bool
    message: str
    n_evaluations: int
    warnings: tuple[str, ...] = ()
    n_starts: int = 1
    elapsed_s: float = 0.0
    registry: Registry = field(default=DEFAULT_REGISTRY, repr=False)

    @property
    def model(self) -> str:
        return str(self.circuit)

    @property
    def n_points(self) -> int:
        return int(self.frequency.size)

    @property
    def n_params(self) -> int:
        """Number of free parameters k."""
        return len(self.free_names)

    @property
    def dof(self) -> int:
        return 2 * self.n_points - self.n_params

    @property
    def chi2_red(self) -> float:
        return self.chi2 / self.dof if self.dof > 0 else math.nan

    @property
    def aic(self) -> float:
        return information_criteria(self.chi2, 2 * self.n_points, self.n_params)[0]

    @property
    def bic(self) -> float:
        return information_criteria(self.chi2, 2 * self.n_points, self.n_params)[1]

    @property
    def residuals(self) -> np.ndarray:
        with np.errstate(all="ignore"):  # an overflowed model is +inf: its residuals are too
            return (self.z_model - self.z_data) / np.abs(self.z_data)

    @property
    def rms_rel(self) -> float:
        with np.errstate(over="ignore"):
            return float(np.sqrt(np.mean(np.abs(self.residuals) ** 2)))

    @property
    def params(self) -> dict[str, float]:
        return dict(self.values)

    def predict(self, freq) -> np.ndarray:
        """Model impedance [Ω] at ``freq`` [Hz] with the fitted parameters."""
        return np.asarray(compile_circuit(self.circuit, self.registry)(self.values, np.asarray(freq, float)))

    def summary(self) -> dict:
        """The JSON summary used by ``impedax fit --json``."""
        return {
            "model": self.model,
            "n_points": self.n_points,
            "n_params": self.n_params,
            "params": {n: {"value": self.values[n], "stderr": None if self.fixed[n] else self.stderr[n], "fixed": self.fixed[n]} for n in self.values},
            "rms_rel": self.rms_rel,
            "chi2": self.chi2,
            "chi2_red": self.chi2_red,
            "aic": self.aic,
            "bic": self.bic,
            "converged": self.converged,
            "message": self.message,
            "warnings": list(self.warnings),
            "weighting": self.weighting,
            "n_evaluations": self.n_evaluations,
        }

    def report(self) -> str:
        """A readable table of the fit."""
        specs = self.circuit.parameter_specs(self.registry)
        width = max(len(n) for n in self.values)
        lines = [
            f"model      {self.model}",
            f"weighting  {self.weighting}    points {self.n_points}    free parameters {self.n_params}",
            f"rms_rel    {self.rms_rel:.4g}    chi2 {self.chi2:.4g}    chi2_red {self.chi2_red:.4g}    AIC {self.aic:.2f}    BIC {self.bic:.2f}",
            f"status     {'converged' if self.converged else 'NOT converged'}: {self.message}",
            "",
            f"{'parameter':<{width}}  {'value':>12}  {'stderr':>10}  {'rel':>8}  unit",
        ]
        for n, v in self.values.items():
            if self.fixed[n]:
                lines.append(f"{n:<{width}}  {v:>12.5g}  {'(fixed)':>10}  {'':>8}  {specs[n].unit}")
            else:
                e = self.stderr[n]
                rel = f"{abs(e / v) * 100:.2g}%" if v and np.isfinite(e) else "—"
                lines.append(f"{n:<{width}}  {v:>12.5g}  {e:>10.3g}  {rel:>8}  {specs[n].unit}")
        for w in self.warnings:
            lines.append(f"warning: {w}")
        return "\n".join(lines)

    def derive(self, fn, freq=None):
        """Propagate the fit to ``fn(params[, freq])`` by the delta method (`derive_fit`)."""
        from ..derived import derive_fit

        return derive_fit(self, fn, freq)

    def plot(self, *, title: str | None = None, bands=None):
        """Data vs model: Nyquist, Bode and relative residuals (matplotlib Figure)."""
        from ...plotting import plot_spectrum

        return plot_spectrum(
            (self.frequency, self.z_data),
            (self.frequency, self.z_model),
            title=title or f"{self.model}   rms_rel = {self.rms_rel:.3g}",
            bands=bands,
            model_label="fit",
        )

    def to_xarray(self) -> xr.Dataset:
        """Parameters (with stderr), covariance and the spectra as a Dataset."""
        names = list(self.values)
        free = list(self.free_names)
        return xr.Dataset(
            {
                "value": ("param", [self.values[n] for n in names]),
                "stderr": ("param", [self.stderr[n] for n in names]),
                "fixed": ("param", [self.fixed[n] for n in names]),
                "covariance": (("free_param", "free_param_2"), self.covariance),
                "correlation": (("free_param", "free_param_2"), self.correlation),
                "Z": ("frequency", self.z_data, {"units": "ohm"}),
                "Z_model": ("frequency", self.z_model, {"units": "ohm"}),
                "residual_rel": ("frequency", self.residuals),
            },
            coords={"param": names, "free_param": free, "free_param_2": free, "frequency": ("frequency", self.frequency, {"units": "Hz"})},
            attrs={
                "model": self.model, "weighting": self.weighting, "rms_rel": self.rms_rel, "chi2": self.chi2,
                "chi2_red": self.chi2_red, "aic": self.aic, "bic": self.bic, "converged": int(self.converged),
                "message": self.message, "warnings": list(self.warnings),
            },
        )


def correlated_note(a: str, b: str, r: float) -> str:
    why = " (a CPE's Q and α correlate when the data lie far from ω = 1 rad/s; both can still be well determined)" if a.rsplit(".", 1)[0] == b.rsplit(".", 1)[0] else "; the data barely tell them apart"
    return f"{a} and {b} are strongly correlated (r = {r:+.3f}){why}"


def undetermined_note(name: str, relative_error: float) -> str:
    return f"{name} has a relative standard error of {relative_error * 100:.3g}%: it is not determined by the data"


def bound_note(name: str, value: float, bound: float, side: str) -> str:
    return f"{name} = {value:.6g} sits at its {side} bound {bound:g}"


def diagnose_identifiability(names, values, stderr, corr, null_sets, ratio) -> list[str]:
    """Identifiability warnings."""
    notes = []
    flagged: set[frozenset] = set()
    for group in null_sets:
        notes.append(
            f"{', '.join(group)} are not separately determined by the data (near-singular Jacobian, "
            f"singular-value ratio {ratio:.1e}): only a combination of them changes Z; fix one of them"
        )
        flagged.add(frozenset(group))
    for i, j in np.argwhere(np.abs(corr) > CORRELATION_LIMIT).tolist():  # in (i, j) order
        if i < j and not any({names[i], names[j]} <= g for g in flagged):
            notes.append(correlated_note(names[i], names[j], corr[i, j]))
    for n in names:
        v, e = values[n], stderr[n]
        if v != 0 and (not math.isfinite(e) or abs(e / v) > RELATIVE_ERROR_LIMIT) and not any(n in g for g in flagged):
            notes.append(undetermined_note(n, abs(e / v)))
    return notes


def fit_notes(table: ParameterTable, values: dict, stderr: dict, corr, null_sets, ratio, *, finite: bool, converged: bool, message: str) -> tuple[str, ...]:
    """The warnings of a fit: not converged, identifiability (`diagnose_identifiability`),
    parameters at a bound."""
    free_names = table.free_names
    notes = diagnose_identifiability(list(free_names), values, stderr, corr, null_sets, ratio) if finite else []
    free = table.free_index
    for nm, lo, hi in zip(free_names, table.lower[free].tolist(), table.upper[free].tolist()):
        v = values[nm]
        if math.isfinite(hi) and abs(v - hi) <= 1e-4 * max(abs(hi), 1e-12):
            notes.append(bound_note(nm, v, hi, "upper"))
        elif lo > 0 and abs(v - lo) <= 1e-4 * lo:
            notes.append(bound_note(nm, v, lo, "lower"))
    if not converged:
        notes.insert(0, f"fit did not converge: {message}")
    return tuple(notes)


def stack_notes(table: ParameterTable, values: np.ndarray, stderr: np.ndarray, corr: np.ndarray) -> dict[int, tuple[str, ...]]:
    """`fit_notes` of a stack of converged fits without near-null directions: values and
    stderr (B, P), correlations (B, K, K). The conditions are evaluated for all fits at once
    and text is built only for the notes due, in `fit_notes`' order; fits without notes are
    left out of the returned {row: notes}."""
    names = table.free_names
    free = table.free_index
    v, e = values[:, free], stderr[:, free]
    notes: dict[int, list[str]] = collections.defaultdict(list)
    upper_triangle = np.triu(np.ones((len(names),) * 2, bool), 1)
    correlated = np.argwhere((np.abs(corr) > CORRELATION_LIMIT) & upper_triangle)
    for (b, i, j), r in zip(correlated.tolist(), corr[tuple(correlated.T)].tolist()):
        notes[b].append(correlated_note(names[i], names[j], r))
    with np.errstate(all="ignore"):
        relative_error = np.abs(e / v)
        undetermined = (v != 0) & (~np.isfinite(e) | (relative_error > RELATIVE_ERROR_LIMIT))
    for b, i in np.argwhere(undetermined).tolist():
        notes[b].append(undetermined_note(names[i], float(relative_error[b, i])))
    lo, hi = table.lower[free], table.upper[free]
    with np.errstate(invalid="ignore"):
        at_upper = np.isfinite(hi) & (np.abs(v - hi) <= 1e-4 * np.maximum(np.abs(hi), 1e-12))
        at_lower = ~at_upper & (lo > 0) & (np.abs(v - lo) <= 1e-4 * lo)
    for b, i in np.argwhere(at_upper | at_lower).tolist():
        bound, side = (hi[i], "upper") if at_upper[b, i] else (lo[i], "lower")
        notes[b].append(bound_note(names[i], float(v[b, i]), float(bound), side))
    return {b: tuple(n) for b, n in notes.items()}


def fit_result(circuit, table: ParameterTable, freq, z, out: SolverOutput, weighting: str, n_starts: int, elapsed: float, registry: Registry) -> FitResult:
    """The `FitResult` of one spectrum's `SolverOutput`: uncertainties, status and warnings."""
    names = table.names
    free_names = table.free_names
    x = out.x
    chi2 = float(out.chi2)
    finite = np.isfinite(chi2) and np.all(np.isfinite(out.z_model))
    n = 2 * len(freq)
    k = len(free_names)
    chi2_red = chi2 / (n - k) if n > k else math.nan
    z_model = np.asarray(out.z_model)
    if finite:
        cov, corr, null_sets, ratio = uncertainties(out.jacobian, chi2_red, weighting, free_names)
        stderr_free = np.sqrt(np.clip(np.diag(cov), 0, None)) if k else np.zeros(0)
    else:
        # overflow: nothing is determined; say so with infinities, never NaN dressed as a result
        chi2 = math.inf
        z_model = np.where(np.isfinite(z_model), z_model, np.inf)
        cov, corr, null_sets, ratio = np.diag(np.full(k, np.inf)), np.eye(k), [], 0.0
        stderr_free = np.full(k, np.inf)
    values = {nm: float(v) for nm, v in zip(names, x)}
    stderr = {nm: math.nan for nm in names}
    stderr.update({nm: float(e) for nm, e in zip(free_names, stderr_free)})
    code = SolverStatus(int(out.code))
    converged = bool(finite and code == SolverStatus.CONVERGED)
    if not finite:
        message = "the model's impedance or weighted residuals are not finite (overflow) at every start; check bounds, fixed values and the frequency range"
    elif code == SolverStatus.CONVERGED:
        start = "from the data-driven start" if n_starts == 1 else f"best of {n_starts} starts"
        message = f"converged in {int(out.steps)} steps ({start})"
    else:
        message = code.message
    notes = fit_notes(table, values, stderr, corr, null_sets, ratio, finite=finite, converged=converged, message=message)
    return FitResult(
        circuit=circuit,
        values=values,
        stderr=stderr,
        fixed={nm: bool(f) for nm, f in zip(names, table.fixed)},
        free_names=free_names,
        covariance=cov,
        correlation=corr,
        frequency=np.asarray(freq),
        z_data=np.asarray(z),
        z_model=z_model,
        weighting=weighting,
        chi2=chi2,
        converged=converged,
        message=message,
        n_evaluations=int(out.steps_total),
        warnings=notes,
        n_starts=n_starts,
        elapsed_s=elapsed,
        registry=registry,
    )
