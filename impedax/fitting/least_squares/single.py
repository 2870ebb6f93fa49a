"""Least-squares fitting of a circuit to a spectrum (or to many at once).

`fit` returns a frozen `FitResult` for a one-dimensional spectrum and a `BatchFitResult` when
the data have extra dimensions (trial, subject, ...), which are fitted in one vmapped call.
"""

from __future__ import annotations

import collections
import math
import time
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np
import xarray as xr

from ...circuits import Circuit, DEFAULT_REGISTRY, Registry, compile_circuit, parse
from ...errors import DataError, FitError, ParameterError
from ..problem import open_spectrum
from .solvers import solver_messages, tree_solver
from .order import canonical_order
from ..parameters import ParameterTable, to_internal
from .starts import SpectrumFeatures, data_driven_guess, data_driven_guesses, random_starts

__all__ = ["fit", "FitResult", "WEIGHTINGS", "information_criteria"]

WEIGHTINGS = {
    "unit": "no weighting: absolute residuals Z_model − Z_data [Ω]",
    "modulus": "both parts divided by |Z_data| (relative error; the default)",
    "proportional": "Re divided by |Re Z_data| and Im by |Im Z_data| separately",
    "sigma": "divided by the per-point standard deviation `sigma` of the data (true chi²)",
}

# identifiability thresholds (documented in the README)
CORRELATION_LIMIT = 0.99
RELATIVE_ERROR_LIMIT = 1.0
SINGULAR_RATIO_LIMIT = 1e-8
# Jacobians whose equilibrated JᵀJ has a condition number provably below this get its inverse
# directly (errors ~ cond · 1e-16: the same as the eigendecomposition's), the others its
# eigendecomposition or SVD; above this the two could differ by more than 1e-10
WELL_CONDITIONED = 1e6


def information_criteria(chi2: float, n_residuals: int, n_free: int) -> tuple[float, float]:
    """AIC = n ln(χ²/n) + 2k and BIC = n ln(χ²/n) + k ln n over the n = 2N real residuals
    (the convention of lmfit; differences between models on the same data are what matter)."""
    n = n_residuals
    base = n * math.log(max(chi2, 1e-300) / n)
    return base + 2 * n_free, base + n_free * math.log(n)


def _weights(z: np.ndarray, sigma: np.ndarray | None, weighting: str, source: str):
    if weighting not in WEIGHTINGS:
        raise ParameterError(f"unknown weighting {weighting!r}; choose one of {', '.join(WEIGHTINGS)}")
    if weighting == "unit":
        w_re = w_im = np.ones(z.shape)
    elif weighting == "modulus":
        w_re = w_im = np.abs(z)
    elif weighting == "proportional":
        floor = 1e-9 * np.abs(z)
        w_re, w_im = np.maximum(np.abs(z.real), floor), np.maximum(np.abs(z.imag), floor)
    else:
        if sigma is None:
            raise DataError("weighting='sigma' needs a 'sigma' variable in the data (e.g. the SEM of repeated trials)", path=source)
        w_re = w_im = sigma
    if np.any(~np.isfinite(w_re) | (w_re <= 0)) or np.any(~np.isfinite(w_im) | (w_im <= 0)):
        raise DataError(f"weighting {weighting!r}: zero or non-finite weights (|Z| = 0 somewhere?)", path=source)
    return 1.0 / w_re, 1.0 / w_im


@dataclass(frozen=True, eq=False)
class FitResult:
    """A least-squares fit of ``circuit`` to one spectrum. Immutable.

    ``values``/``stderr`` are keyed by parameter name (stderr NaN for fixed parameters);
    ``covariance``/``correlation`` are over ``free_names``. ``residuals`` are the complex
    relative residuals r_k = (Z_model,k − Z_data,k)/|Z_data,k| and
    ``rms_rel = sqrt(mean |r_k|²)`` (PHYSICS.md). ``chi2`` is the sum of the squared
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


def covariances(jac: np.ndarray, chi2_red, weighting: str):
    """Covariance and correlation matrices from Jacobians (..., M, K) in parameter space,
    with the singular values and right singular vectors of the column-equilibrated Jacobian
    (equilibrated, proportional columns give an evenly weighted null vector). Tikhonov-
    regularised, so undetermined directions show as huge variances and ±1 correlations, not
    NaN; scaled by the reduced chi² unless the weights are the data's sigma (as lmfit).

    Jacobians proven well-conditioned (`WELL_CONDITIONED`) take the plain inverse of JᵀJ and
    have NaN singular values and vectors: they have no near-null direction to report."""
    batch, (m, k) = jac.shape[:-2], jac.shape[-2:]
    jac = jac.reshape(-1, m, k)
    gram = np.swapaxes(jac, -1, -2) @ jac
    norms = np.sqrt(np.einsum("bkk->bk", gram))
    scale = np.where(norms > 0, 1.0 / np.where(norms > 0, norms, 1.0), 1.0)
    gram = gram * scale[:, :, None] * scale[:, None, :]  # of the column-equilibrated Jacobian
    inverse = np.full(gram.shape, np.nan)
    s, vt = np.full(norms.shape, np.nan), np.full(gram.shape, np.nan)
    regular = np.flatnonzero(np.all(norms > 0, axis=-1))
    try:
        inverse[regular] = np.linalg.inv(gram[regular])
    except np.linalg.LinAlgError:  # one of them exactly singular: all take the decomposition
        pass
    # cond(JᵀJ) = λ_max/λ_min ≤ trace(JᵀJ)·trace((JᵀJ)⁻¹) = bound; below the limit the inverse is
    # as accurate as the decomposition, and the regularisation below would change it by < 1e-20.
    # The inverse of a numerically singular JᵀJ has a trace of ±1e16 or more (the sign is
    # rounding's): the bound is then huge or negative
    with np.errstate(invalid="ignore"):
        bound = np.trace(gram, axis1=1, axis2=2) * np.trace(inverse, axis1=1, axis2=2)
        spectral = np.flatnonzero(~((bound > 0) & (bound < WELL_CONDITIONED)))
    if spectral.size:
        # singular values from the eigenvalues of JᵀJ (K×K, far cheaper than the SVD of J);
        # where they span more than 1e-4 (eigenvalues 1e-8), squaring the condition number
        # would cost accuracy, so those Jacobians get the SVD itself
        eigenvalues, vectors = np.linalg.eigh(gram[spectral])
        s[spectral] = np.sqrt(np.clip(eigenvalues[:, ::-1], 0, None))
        vt[spectral] = np.swapaxes(vectors[:, :, ::-1], -1, -2)
        ill = spectral[~(s[spectral, -1] > 1e-4 * s[spectral, 0])]
        if ill.size:
            _, s[ill], vt[ill] = np.linalg.svd(jac[ill] * scale[ill, None, :], full_matrices=False)
        s_max = np.where(s[spectral, :1] > 0, s[spectral, :1], 1.0)
        with np.errstate(over="ignore", invalid="ignore"):  # a column of zeros: infinite variance, said so
            inverse[spectral] = (np.swapaxes(vt[spectral], -1, -2) * (1.0 / (s[spectral] ** 2 + (1e-13 * s_max) ** 2))[:, None, :]) @ vt[spectral]
    with np.errstate(over="ignore", invalid="ignore"):
        cov = (inverse * scale[:, :, None] * scale[:, None, :]).reshape(*batch, k, k)
    s, vt = s.reshape(*batch, k), vt.reshape(*batch, k, k)
    if weighting != "sigma":
        chi2_red = np.asarray(chi2_red, float)
        cov = cov * np.where(np.isfinite(chi2_red), chi2_red, 1.0)[..., None, None]
    d = np.sqrt(np.clip(np.einsum("...ii->...i", cov), 0, None))
    with np.errstate(all="ignore"):
        corr = np.clip(np.nan_to_num(cov / (d[..., :, None] * d[..., None, :]), nan=0.0), -1, 1)
    k = jac.shape[-1]
    corr[..., np.arange(k), np.arange(k)] = 1.0
    return cov, corr, s, vt


def _null_sets(s: np.ndarray, vt: np.ndarray, names: Sequence[str]):
    """Groups of parameters along near-null directions of one equilibrated Jacobian, and the
    smallest-to-largest singular value ratio."""
    s_max = s[0] if s.size and s[0] > 0 else 1.0
    null = [[names[i] for i in np.flatnonzero(np.abs(vt[j]) > 0.2)] for j in np.flatnonzero(s < SINGULAR_RATIO_LIMIT * s_max)]
    return null, float(s[-1] / s_max) if s.size else 1.0


def _uncertainties(jac: np.ndarray, chi2_red: float, weighting: str, names: Sequence[str]):
    """(covariance, correlation, null sets, singular-value ratio) of one fit (`covariances`)."""
    if len(names) == 0:
        return np.zeros((0, 0)), np.zeros((0, 0)), [], 0.0
    cov, corr, s, vt = covariances(jac, chi2_red, weighting)
    return (cov, corr, *_null_sets(s, vt, names))


def _correlated_note(a: str, b: str, r: float) -> str:
    why = " (a CPE's Q and α correlate when the data lie far from ω = 1 rad/s; both can still be well determined)" if a.rsplit(".", 1)[0] == b.rsplit(".", 1)[0] else "; the data barely tell them apart"
    return f"{a} and {b} are strongly correlated (r = {r:+.3f}){why}"


def _undetermined_note(name: str, relative_error: float) -> str:
    return f"{name} has a relative standard error of {relative_error * 100:.3g}%: it is not determined by the data"


def _bound_note(name: str, value: float, bound: float, side: str) -> str:
    return f"{name} = {value:.6g} sits at its {side} bound {bound:g}"


def _diagnose_identifiability(names, values, stderr, corr, null_sets, ratio) -> list[str]:
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
            notes.append(_correlated_note(names[i], names[j], corr[i, j]))
    for n in names:
        v, e = values[n], stderr[n]
        if v != 0 and (not math.isfinite(e) or abs(e / v) > RELATIVE_ERROR_LIMIT) and not any(n in g for g in flagged):
            notes.append(_undetermined_note(n, abs(e / v)))
    return notes


def fit_notes(table: ParameterTable, values: dict, stderr: dict, corr, null_sets, ratio, *, finite: bool, converged: bool, message: str) -> tuple[str, ...]:
    """The warnings of a fit: not converged, identifiability (`_diagnose_identifiability`),
    parameters at a bound."""
    free_names = table.free_names
    notes = _diagnose_identifiability(list(free_names), values, stderr, corr, null_sets, ratio) if finite else []
    free = table.free_index
    for nm, lo, hi in zip(free_names, table.lower[free].tolist(), table.upper[free].tolist()):
        v = values[nm]
        if math.isfinite(hi) and abs(v - hi) <= 1e-4 * max(abs(hi), 1e-12):
            notes.append(_bound_note(nm, v, hi, "upper"))
        elif lo > 0 and abs(v - lo) <= 1e-4 * lo:
            notes.append(_bound_note(nm, v, lo, "lower"))
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
        notes[b].append(_correlated_note(names[i], names[j], r))
    with np.errstate(all="ignore"):
        relative_error = np.abs(e / v)
        undetermined = (v != 0) & (~np.isfinite(e) | (relative_error > RELATIVE_ERROR_LIMIT))
    for b, i in np.argwhere(undetermined).tolist():
        notes[b].append(_undetermined_note(names[i], float(relative_error[b, i])))
    lo, hi = table.lower[free], table.upper[free]
    with np.errstate(invalid="ignore"):
        at_upper = np.isfinite(hi) & (np.abs(v - hi) <= 1e-4 * np.maximum(np.abs(hi), 1e-12))
        at_lower = ~at_upper & (lo > 0) & (np.abs(v - lo) <= 1e-4 * lo)
    for b, i in np.argwhere(at_upper | at_lower).tolist():
        bound, side = (hi[i], "upper") if at_upper[b, i] else (lo[i], "lower")
        notes[b].append(_bound_note(names[i], float(v[b, i]), float(bound), side))
    return {b: tuple(n) for b, n in notes.items()}


def _prepare(circuit, data, *, init, fixed, bounds, weighting, fmin, fmax, registry):
    circuit = parse(circuit, registry)
    spectrum = open_spectrum(data, fmin=fmin, fmax=fmax)
    data, source = spectrum.data, spectrum.source
    table = ParameterTable.build(circuit, registry=registry, init=init, fixed=fixed, bounds=bounds)
    n_points = data.sizes["frequency"]
    k = int((~table.fixed).sum())
    if k >= 2 * n_points:
        raise FitError(f"{k} free parameters but only {2 * n_points} real data values ({n_points} frequencies); fix parameters or use more data")
    return circuit, data, table, source


def fit(
    circuit: Circuit | str,
    data: xr.Dataset | str,
    *,
    init: Mapping[str, float] | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    weighting: str = "modulus",
    fmin: float | None = None,
    fmax: float | None = None,
    n_starts: int = 16,
    max_steps: int = 400,
    seed: int = 0,
    registry: Registry = DEFAULT_REGISTRY,
):
    """Fit ``circuit`` to ``data`` by weighted least squares (optimistix Levenberg–Marquardt).

    Parameters are fitted in an unconstrained space (log for positive quantities, logistic
    for bounded ranges), float64. The data-driven guess (with any ``init`` values) is fitted
    first; when its residuals do not look like white noise, ``n_starts − 1`` further starts
    are solved with it in one vmapped call and the best is kept (``FitResult.n_starts`` says
    how many were used).
    ``fixed`` pins parameters; ``bounds`` narrows them; ``weighting`` is one of `WEIGHTINGS`.
    ``data`` is a spectrum Dataset or a path. Extra dimensions (trial, subject, ...) are fitted
    together and give a `BatchFitResult`; dask-backed data are fitted chunk by chunk.
    Returns a `FitResult` for a single spectrum.
    """
    t0 = time.perf_counter()
    circuit, data, table, source = _prepare(circuit, data, init=init, fixed=fixed, bounds=bounds, weighting=weighting, fmin=fmin, fmax=fmax, registry=registry)
    if n_starts < 1:
        raise ParameterError("n_starts must be at least 1")
    extra = [d for d in data["Z"].dims if d != "frequency"]
    if extra:
        from .batch import fit_batch

        return fit_batch(circuit, data, table, weighting=weighting, n_starts=n_starts, max_steps=max_steps, seed=seed, registry=registry, source=source, t0=t0)
    freq = np.asarray(data["frequency"].values, float)
    z = np.asarray(data["Z"].values, complex)
    sigma = np.asarray(data["sigma"].values, float) if "sigma" in data else None
    inv_re, inv_im = _weights(z, sigma, weighting, source)
    single = tree_solver(circuit, registry, max_steps, *table.free_structure)[0]
    scale = residual_scale(z, inv_re, inv_im, weighting)
    args = _args(table, freq, z, inv_re * scale, inv_im * scale)
    # the data-driven guess alone first; the multistart only when its fit is not at the noise
    features = SpectrumFeatures(freq, z)
    out = _unscale(_fetch(single(_guess_start(circuit, table, features, registry), args)), scale)
    used = 1
    if n_starts > 1 and not at_noise_floor(freq, z, out["z_model"], inv_re, inv_im, out["code"])[()]:
        starts = _starts_from(circuit, table, features, n_starts, seed, registry)
        out = _better(out, _unscale(_fetch(single(starts, args)), scale))
        used = n_starts
    out = canonical_order(circuit, table, freq, out, registry)
    return _result(circuit, table, freq, z, out, weighting, used, time.perf_counter() - t0, registry)


def _fetch(pending) -> dict:
    """The solver outputs a fit uses, copied to the host in one transfer."""
    return pending.fetch()


def residual_scale(z, inv_re, inv_im, weighting: str) -> np.ndarray:
    """A constant per spectrum that brings the weighted residuals to the size of relative
    ones (exactly 1 for modulus weighting). Levenberg–Marquardt's damping is absolute, so
    with residuals of 1e10 Ω (unit weighting of teraohm data) it would take undamped
    Gauss–Newton jumps; the minimiser is unchanged and chi² and the Jacobian are scaled back."""
    if weighting == "modulus":
        return np.ones(np.shape(z)[:-1])
    typical = np.median(np.abs(z) * np.sqrt(0.5 * (np.asarray(inv_re) ** 2 + np.asarray(inv_im) ** 2)), axis=-1)
    return 1.0 / np.where(np.isfinite(typical) & (typical > 0), typical, 1.0)


def _unscale(out: dict, scale) -> dict:
    scale = np.asarray(scale)
    if np.all(scale == 1.0):  # modulus weighting: nothing to undo
        return out
    out = dict(out)
    out["chi2"] = out["chi2"] / scale**2
    out["chi2_starts"] = out["chi2_starts"] / scale.reshape(scale.shape + (1,) * (np.ndim(out["chi2_starts"]) - scale.ndim)) ** 2
    out["jacobian"] = out["jacobian"] / scale.reshape(scale.shape + (1, 1))
    return out


# the guess's fit is accepted without a multistart when its weighted residuals look like noise:
# lag-1 autocorrelation along frequency below this (white noise: ≈ 0 ± 1/√(2N); a misfit
# that the multistart could improve leaves smooth, strongly correlated residuals)
WHITENESS_LIMIT = 0.5
MIN_POINTS_FOR_WHITENESS = 10


def at_noise_floor(freq, z, z_model, inv_re, inv_im, code) -> np.ndarray:
    """Whether fits (…, N) converged (``code == 0``) with residuals that look like white noise;
    broadcasts over leading batch dimensions."""
    order = np.argsort(freq)
    with np.errstate(all="ignore"):
        dz = (np.asarray(z_model) - z)[..., order]
        parts = [dz.real * np.asarray(inv_re)[..., order], dz.imag * np.asarray(inv_im)[..., order]]
        num = sum(np.sum(p[..., 1:] * p[..., :-1], axis=-1) for p in parts)
        den = sum(np.sum(p**2, axis=-1) for p in parts)
        rho = num / den
    ok = (np.asarray(code) == 0) & np.isfinite(den) & (den > 0) & (rho < WHITENESS_LIMIT)
    return ok & (len(order) >= MIN_POINTS_FOR_WHITENESS)


def _better(a: dict, b: dict) -> dict:
    """The solver output with the lower chi² (a on ties), elementwise over a batch axis
    (the per-start chi² of the screen, which differ in shape, are dropped)."""
    take_b = np.asarray(b["chi2"]) < np.asarray(a["chi2"])
    return {k: np.where(take_b.reshape(take_b.shape + (1,) * (np.ndim(a[k]) - take_b.ndim)), b[k], a[k]) for k in a if k != "chi2_starts"}


def _to_internal(table: ParameterTable, x: np.ndarray) -> np.ndarray:
    free = table.free_index
    return to_internal(x[..., free], table.lower[free], table.upper[free], table.kind[free])


def _guess_start(circuit, table, features, registry) -> np.ndarray:
    """The data-driven guess as one start in the solver's space: shape (1, K) for one
    spectrum's features, (B, K) for a stack's (one start per spectrum)."""
    return _to_internal(table, data_driven_guesses(circuit, table, features, registry))


def _starts_for(circuit, table, freq, z, n_starts, seed, registry) -> np.ndarray:
    """``n_starts`` starts (the guess first) in the solver's space, shape (n_starts, K)."""
    return _starts_from(circuit, table, SpectrumFeatures(freq, z), n_starts, seed, registry)


def _starts_from(circuit, table, features, n_starts, seed, registry) -> np.ndarray:
    guess = data_driven_guess(circuit, table, features, registry)
    return _to_internal(table, random_starts(table, features, guess, n_starts, seed))


def _args(table: ParameterTable, freq, z, inv_re, inv_im) -> dict:
    """The arrays a tree solver takes (`_core._tree_residuals`; which parameters are free and
    their transforms are compiled into it)."""
    # numpy arrays: jit transfers them on its fast path (jnp.asarray per array costs more)
    free = table.free_index
    return {
        "freq": np.asarray(freq, float),
        "z": np.asarray(z, complex),
        "inv_w_re": np.asarray(inv_re, float),
        "inv_w_im": np.asarray(inv_im, float),
        "x_fixed": np.where(np.isnan(table.values), 1.0, table.values),
        "lower": table.lower[free],
        "upper": table.upper[free],
    }


def _result(circuit, table, freq, z, out, weighting, n_starts, elapsed, registry) -> FitResult:
    names = table.names
    free_names = table.free_names
    x = out["x"]
    chi2 = float(out["chi2"])
    finite = np.isfinite(chi2) and np.all(np.isfinite(out["z_model"]))
    n = 2 * len(freq)
    k = len(free_names)
    chi2_red = chi2 / (n - k) if n > k else math.nan
    z_model = np.asarray(out["z_model"])
    if finite:
        cov, corr, null_sets, ratio = _uncertainties(out["jacobian"], chi2_red, weighting, free_names)
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
    code = int(out["code"])
    converged = bool(finite and code == 0)
    if not finite:
        message = "the model's impedance or weighted residuals are not finite (overflow) at every start; check bounds, fixed values and the frequency range"
    elif code == 0:
        start = "from the data-driven start" if n_starts == 1 else f"best of {n_starts} starts"
        message = f"converged in {int(out['steps'])} steps ({start})"
    else:
        message = solver_messages(code)
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
        n_evaluations=int(out["steps_total"]),
        warnings=notes,
        n_starts=n_starts,
        elapsed_s=elapsed,
        registry=registry,
    )
