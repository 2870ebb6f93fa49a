"""`drt`: the distribution of relaxation times of one spectrum or of a batch of spectra."""

from __future__ import annotations

import functools
import math

import numpy as np

from ...arguments import checked_arguments, count, flag, real, shown
from ...constants import DRT_POINTS_MIN
from ...errors import DataError, ParameterError
from ...io.sign_check import values_sign_hint
from ..grid import refuse_result_names
from ..kk import zero_impedance_text
from ..problem import frequency_and_z
from ..statistics import residual_noise
from ..stored import QUICK_COMPILE, StoredProgram
from .basis import impedance_integrals, penalty_matrix, rbf_basis
from .peaks import below_roundoff, split_peaks
from .result import BATCH_RESULT_NAMES, LAMBDA_FLOOR as _LAMBDA_FLOOR, DRTBatchResult, DRTResult, format_lambda  # λ chosen below the floor is raised to it
from .tikhonov import LAMBDA_METHODS, quantile_band, solve_batch

__all__ = ["drt"]

_ETA = 1e-10  # diagonal added to Γ so that it factors (see tikhonov.py)
_LOG_LAMBDA_GRID = np.log(np.logspace(-8, 2, 41))
_SAMPLES = 200  # Gaussian draws for the peaks' standard deviations
_TAIL_WIDTH = math.sqrt(math.log(1e5))  # the output grid reaches this far past the outer centres, in units of 1/ε


@functools.lru_cache(maxsize=8)
def _stored_solve(method: str, signed: bool, n_series: int, max_iter: int) -> StoredProgram:
    """`tikhonov.solve_batch` for these options, kept across processes (`stored`)."""
    return StoredProgram(
        "drt-solve", (method, signed, n_series, max_iter), functools.partial(solve_batch, method=method, signed=signed, n_series=n_series, max_iter=max_iter),
        compiler_options=QUICK_COMPILE,
    )


@functools.lru_cache(maxsize=16)
def _setup(freq_bytes: bytes, points_per_decade: float, extend_decades: float, fwhm_steps: float, derivative: int, inductance: bool, capacitance: bool, output_per_decade: float):
    """Everything that depends only on the frequencies and options (cached): the design, Γ,
    R⁻¹, the constraint mask and the output grid."""
    freq = np.frombuffer(freq_bytes)
    omega = 2 * np.pi * freq
    # γ at τ ≪ 1/ω_max is R(1 − jωτ): with a free series L it is indistinguishable from R_∞, and
    # γ at τ ≫ 1/ω_min is R/(jωτ), a series C; extend the basis only where no series term is
    # its twin (otherwise R_∞ drifts by the noise-level slack, several ohms on a 1 % spectrum)
    basis = rbf_basis(
        freq, points_per_decade=points_per_decade, extend_short=0.0 if inductance else extend_decades,
        extend_long=0.0 if capacitance else extend_decades, fwhm_steps=fwhm_steps,
    )
    a_re, a_im = impedance_integrals(omega, basis)
    w_max, w_min = omega.max(), omega.min()
    series_re, series_im, constrained, names = [np.ones_like(omega)], [np.zeros_like(omega)], [False], ["r_inf"]
    if inductance:  # variable L·ω_max/z_ref, free sign
        series_re.append(np.zeros_like(omega)), series_im.append(omega / w_max), constrained.append(False), names.append("l")
    if capacitance:  # variable 1/(C ω_min z_ref) ≥ 0
        series_re.append(np.zeros_like(omega)), series_im.append(-w_min / omega), constrained.append(True), names.append("c")
    n_series = len(names)
    design_re = np.column_stack([*series_re, a_re])
    design_im = np.column_stack([*series_im, a_im])
    p = design_re.shape[1]
    gamma_penalty = np.zeros((p, p))
    gamma_penalty[n_series:, n_series:] = penalty_matrix(basis, derivative)
    gamma_penalty += _ETA * np.eye(p)
    r = np.linalg.cholesky(gamma_penalty).T  # Γ + ηI = RᵀR
    r_inv = np.linalg.solve(r, np.eye(p))
    # the output grid: the centres' range at ``output_per_decade``, extended on both sides until
    # the outermost Gaussians have fallen to exp(−`_TAIL_WIDTH`²) (1e-5) of their height, so that
    # γ is seen to fall and ∫γ d ln τ on the grid is the whole expansion's (a peak at the last
    # centre was cut in half); the inner points are the unextended grid's
    lo, hi = basis.ln_tau[0], basis.ln_tau[-1]
    k = max(int(round((hi - lo) / math.log(10.0) * output_per_decade)) + 1, 2)
    step_out = (hi - lo) / (k - 1)
    extra = math.ceil(_TAIL_WIDTH / basis.epsilon / step_out)
    ln_tau_out = lo + step_out * np.arange(-extra, k + extra)
    ln_tau_out[extra], ln_tau_out[extra + k - 1] = lo, hi
    phi = np.zeros((ln_tau_out.size, p))
    phi[:, n_series:] = basis.evaluate(ln_tau_out)
    mask = np.array(constrained + [True] * basis.ln_tau.size)
    return basis, design_re, design_im, gamma_penalty, r_inv, mask, phi, ln_tau_out, tuple(names)


def _needs_capacitance(freq, z) -> bool:
    """A series capacitor is fitted when some spectrum is capacitive at its lowest frequency
    (phase below −60°: blocking electrodes, a double layer with no parallel path)."""
    k = int(np.argmin(freq))
    return bool(np.any(np.angle(z[..., k], deg=True) < -60.0))


def _check_finite(x: np.ndarray, fixed: float | None, source: str, lam: np.ndarray | None = None, lam_method: str = "gcv") -> None:
    """A solution that is not finite is an error, not a result: with a fixed λ too small for
    the spectrum, H = AᵀA + λΓ is numerically singular and its Cholesky factor NaN (the
    threshold depends on the spectrum: 1e-16 worked on one real file, 1e-9 failed on another).
    With an automatic λ the data are not to blame (`frequency_and_z` has refused non-finite and
    extreme values; the L-curve once gave NaN on exact data): the error names the solve, its λ
    (``lam``, per spectrum) and what to give instead."""
    bad = ~np.all(np.isfinite(x), axis=-1)
    if not np.any(bad):
        return
    which = "" if bad.size == 1 else f" (spectra {', '.join(str(int(i)) for i in np.flatnonzero(bad)[:5])}{', …' if bad.sum() > 5 else ''} of {bad.size}, in C order)"
    if fixed is not None:
        raise ParameterError(
            f"lam must be larger than {fixed:g} for this data{which}: the regularised system is numerically singular at that λ and its "
            f"solution is not finite (the smallest λ that works depends on the spectrum; an automatic λ is never below {_LAMBDA_FLOOR:g}); "
            "give a larger value or 'auto'"
        )
    lam_text = ""
    if lam is not None:
        values = np.atleast_1d(np.asarray(lam, float))[np.atleast_1d(bad)]
        lam_text = f" at λ = {', '.join(format_lambda(float(v)) if math.isfinite(v) else 'nan' for v in values[:3])}{', …' if values.size > 3 else ''}"
    other = "lcurve" if lam_method == "gcv" else "gcv"
    raise ParameterError(
        f"the DRT solve gave a non-finite solution{which}{lam_text} chosen by {lam_method}: a numerical failure of the solve, not of the data "
        f"(which are finite); give a fixed λ (lam=1e-3) or lam_method={other!r}"
    )


def _with_automatic_lambda(results: list, solve, design_re, design_im, flat, z_ref) -> list:
    """``results`` of a fixed λ with, on each that misfits (`DRTResult.misfits`), the λ the
    automatic choice gives the same spectrum and γ's rms_rel there (``auto_lambda``,
    ``auto_rms_rel``): `DRTResult.over_smoothed` tells a λ that smooths the data away from data
    no γ reproduces. One more call of the compiled solve (NaN: chosen, as ``lam='auto'``)."""
    import dataclasses

    out = {k: np.asarray(v) for k, v in solve(np.full(len(results), math.nan)).items()}
    mended = []
    for i, one in enumerate(results):
        if one.misfits:
            x = out["x"][i]
            z_fit = (design_re @ x + 1j * (design_im @ x)) * z_ref[i]
            rms = float(np.sqrt(np.mean(np.abs((flat[i] - z_fit) / flat[i]) ** 2)))
            one = dataclasses.replace(one, auto_lambda=float(math.exp(out["log_lambda"][i])), auto_rms_rel=rms)
        mended.append(one)
    return mended


def _lambda_note(method: str, choice: float, index: int) -> str:
    """How an automatic λ ended where it did, when not simply at the criterion's optimum
    ("" then): raised to `_LAMBDA_FLOOR`, or at the top of the grid. ``index``: the grid
    index of the optimum (the L-curve's curvature is not defined at the grid's ends)."""
    last = _LOG_LAMBDA_GRID.size - 1 - (method == "lcurve")
    if choice < _LAMBDA_FLOOR:
        where = f"{method}'s optimum is at the bottom of its grid, {format_lambda(math.exp(_LOG_LAMBDA_GRID[0]))}, or below" if index <= (method == "lcurve") else f"{method} chose {format_lambda(choice, 2)}"
        if method == "lcurve" and index <= 1:
            # `tikhonov._choose_log_lambda`: no finite curvature above the grid's first point
            where = (f"the L-curve has no corner inside its grid, as on exact or nearly exact data whose residual reaches its floor; "
                     f"its best finite grid point, {format_lambda(math.exp(_LOG_LAMBDA_GRID[1]))}, is used")
        return f"raised to the floor {format_lambda(_LAMBDA_FLOOR)} ({where})"
    if index >= last:
        return f"at the top of its grid ({format_lambda(math.exp(_LOG_LAMBDA_GRID[-1]))}; {method}'s optimum may lie above: the data ask for at least this much smoothing)"
    return ""


def _share_below_one(value: float, name: str) -> float:
    """A share of the DRT's area (``min_peak_fraction``): at least 0 (checked before) and below 1,
    one message for both ends, as the command line's (not "at most 1" for 5 and "in [0, 1)"
    for 1.0)."""
    if value >= 1:
        raise ParameterError(f"{name} must be at least 0 and below 1 (a share of the DRT's area, e.g. 0.05), got {value:g}")
    return value


@checked_arguments(
    signed=flag, derivative=count(1, 2), inductance=flag, points_per_decade=real(minimum=1, maximum=1000), extend_decades=real(minimum=0, maximum=10),
    fwhm_steps=real(positive=True, maximum=100), output_points_per_decade=real(minimum=1, maximum=10_000), max_iter=count(1, 100_000),
    min_peak_fraction=lambda value, name: _share_below_one(real(minimum=0)(value, name), name),
)
def drt(
    data,
    *,
    method: str = "tikhonov",
    basis: str = "rbf",
    lam: float | str = "auto",
    lam_method: str = "gcv",
    signed: bool = False,
    derivative: int = 2,
    inductance: bool = True,
    capacitance: bool | str = "auto",
    points_per_decade: float = 10.0,
    extend_decades: float = 1.0,
    fwhm_steps: float = 1.5,
    output_points_per_decade: float = 20.0,
    max_iter: int = 100,
    min_peak_fraction: float = 0.1,
) -> DRTResult | DRTBatchResult:
    """Distribution of relaxation times γ(τ) of a spectrum by Tikhonov regularisation on a
    Gaussian RBF basis (Wan et al., Electrochim. Acta 184 (2015) 483; docs/drt.md).

    Fits Z(ω) = R_∞ + jωL [+ 1/(jωC)] + Σ_m x_m ∫ φ_m(ln τ)/(1 + jωτ) d ln τ to the relative
    residuals (Z − Z_fit)/|Z| (data minus DRT model, the sign `DRTResult.residuals` holds) with
    the penalty λ ∫ (d^k γ/d ln τ^k)² d ln τ (k = ``derivative``).

    ``data``: a spectrum Dataset (extra dimensions → one vmapped solve, a `DRTBatchResult`; a
    dimension named as a variable or dimension of its Dataset, `result.BATCH_RESULT_NAMES`:
    ``tau``, ``peak``, …, is a DataError before any solve), a
    file path, or a (frequency, Z) pair with Z of shape (..., N). ``lam``: "auto" (chosen per
    spectrum by ``lam_method``, "gcv" (default) or "lcurve") or a positive number.
    ``signed``: allow γ < 0 (inductive loops, negative capacitances); otherwise γ ≥ 0 (x ≥ 0).
    ``inductance``: fit a series L (free sign); ``capacitance``: fit a series C (True/False, or
    "auto": when the lowest-frequency phase is below −60°). Basis: ``points_per_decade``
    centres per decade, ``extend_decades`` beyond the measured τ range (not on the short-τ side
    when L is fitted, nor on the long-τ side when C is: there γ and the series term are
    interchangeable), each ``fwhm_steps`` spacings wide; γ is reported at ``output_points_per_decade``.
    ``min_peak_fraction``: a peak needs this share of ∫|γ| d ln τ, half of it when resolved;
    below it a peak joins a neighbour within 2 decades or is dropped and reported
    (`peaks.split_peaks`, docs/drt.md "Peaks"). λ is relative to max|Z|² (docs/drt.md,
    "Choosing λ"). Raises DataError/ParameterError on bad input, and ParameterError naming
    ``lam`` when a fixed λ is too small for the data (the solution is not finite).
    """
    if method != "tikhonov":
        raise ParameterError(f"unknown DRT method {method!r}; available: 'tikhonov'")
    if basis != "rbf":
        raise ParameterError(f"unknown DRT basis {basis!r}; available: 'rbf' (Gaussian)")
    if lam_method not in LAMBDA_METHODS:
        raise ParameterError(f"lam_method must be one of {', '.join(map(repr, LAMBDA_METHODS))}, got {lam_method!r}")
    if isinstance(lam, str):
        if lam != "auto":
            rule = f"; the rule that chooses λ is lam_method={lam.lower()!r} (with lam='auto')" if lam.lower() in LAMBDA_METHODS else ""
            raise ParameterError(f"lam must be 'auto' or a positive number, got {shown(lam)}{rule}")
        fixed = None
    else:
        try:
            fixed = float(lam)
        except OverflowError:  # (an int beyond floating point, 10**400)
            raise ParameterError("lam must be a positive finite number, got an integer beyond floating point") from None
        except (TypeError, ValueError):
            raise ParameterError(f"lam must be 'auto' or a positive number, got {shown(lam)}") from None
        if not (math.isfinite(fixed) and fixed > 0):
            raise ParameterError(f"lam must be a positive finite number, got {shown(lam)}")
    if derivative not in (1, 2):
        raise ParameterError(f"derivative must be 1 or 2, got {derivative!r}")
    for name, flag in (("signed", signed), ("inductance", inductance)):
        if not isinstance(flag, (bool, np.bool_)):
            raise ParameterError(f"{name} must be True or False, got {flag!r}")
    if not (isinstance(capacitance, (bool, np.bool_)) or capacitance == "auto"):
        raise ParameterError(f"capacitance must be True, False or 'auto', got {capacitance!r}")
    for name, value, low in (("points_per_decade", points_per_decade, 1.0), ("extend_decades", extend_decades, 0.0), ("fwhm_steps", fwhm_steps, 0.5), ("output_points_per_decade", output_points_per_decade, 1.0)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= low):
            raise ParameterError(f"{name} must be a number ≥ {low:g}, got {value!r}")

    freq, z, dims, coords, source = frequency_and_z(data)
    attrs = getattr(data, "attrs", None)  # (a Dataset's: how its reader took the Z'' column, for the sign hint's fix)
    refuse_result_names(dims, BATCH_RESULT_NAMES, "a DRT batch result", source=source)
    if freq.size < DRT_POINTS_MIN:
        raise DataError(f"the DRT needs at least {DRT_POINTS_MIN} frequencies, got {freq.size}", path=source)
    if np.any(np.abs(z) == 0):
        raise DataError(f"{zero_impedance_text(freq, z)}; the relative weighting 1/|Z| needs |Z| > 0", path=source)
    use_c = _needs_capacitance(freq, z) if capacitance == "auto" else bool(capacitance)
    setup = _setup(np.ascontiguousarray(freq, np.float64).tobytes(), float(points_per_decade), float(extend_decades), float(fwhm_steps), int(derivative), bool(inductance), use_c, float(output_points_per_decade))
    rbf, design_re, design_im, gamma_penalty, r_inv, mask, phi, ln_tau_out, names = setup

    flat = z.reshape(-1, freq.size)
    z_ref = np.max(np.abs(flat), axis=1)  # per spectrum: λ is relative to max|Z|² (docs/drt.md)
    zn = flat / z_ref[:, None]
    weights = 1.0 / np.abs(zn)
    # a fixed λ goes in as a finite fixed_log (NaN: chosen by lam_method): one compiled solve serves both
    fixed_log = np.full(flat.shape[0], math.log(fixed) if fixed is not None else math.nan)
    out = _stored_solve(lam_method, bool(signed), len(names), int(max_iter))(
        design_re, design_im, weights, zn.real, zn.imag, gamma_penalty, r_inv, mask, phi, _LOG_LAMBDA_GRID, fixed_log, math.log(_LAMBDA_FLOOR),
    )
    out = {k: np.asarray(v) for k, v in out.items()}
    _check_finite(out["x"], fixed, source, np.exp(out["log_lambda"]), lam_method)
    q05, q95 = (np.asarray(v) for v in quantile_band(out["band_mean"], out["band_sd"], bool(signed), out["gamma"]))
    n_series = len(names)
    options = dict(signed=bool(signed), derivative=int(derivative), inductance=bool(inductance), capacitance=use_c, points_per_decade=float(points_per_decade),
                   extend_decades=float(extend_decades), fwhm_steps=float(fwhm_steps), output_points_per_decade=float(output_points_per_decade),
                   min_peak_fraction=float(min_peak_fraction))
    omega = 2 * np.pi * freq
    tau_out = np.exp(ln_tau_out)
    window = (1.0 / omega.max(), 1.0 / omega.min())
    # the draws' factor u·√|s| of every covariance at once (one batched eigh; the same numbers as
    # `Generator.multivariate_normal(method="eigh")` spectrum by spectrum, at half its time)
    eig_s, eig_u = np.linalg.eigh(out["covariance"])
    factors = eig_u * np.sqrt(np.abs(eig_s))[:, None, :]
    results = []
    for i in range(flat.shape[0]):
        x = out["x"][i]
        scale = z_ref[i]
        z_fit = (design_re @ x + 1j * (design_im @ x)) * scale
        residual = (flat[i] - z_fit) / np.abs(flat[i])
        series = dict(zip(names, x[:n_series]))
        l_h = float(series.get("l", 0.0) * scale / omega.max())
        inv_c = float(series.get("c", 0.0))
        c_f = math.inf if inv_c <= 0 else 1.0 / (inv_c * omega.min() * scale)
        # draws of γ for the peaks' uncertainty (Gaussian of the band, conditional on the active set);
        # a generator per spectrum: a spectrum's peaks are the same alone or at any place in a batch
        rng = np.random.default_rng(0)
        draws = (x + rng.standard_normal((_SAMPLES, x.size)) @ factors[i].T) @ phi.T * scale
        if not signed:
            draws = np.maximum(draws, 0.0)
        gamma = out["gamma"][i] * scale
        peaks, dropped = split_peaks(ln_tau_out, gamma, signed=bool(signed), window=window, samples=draws, min_rel_resistance=float(min_peak_fraction))
        if below_roundoff(ln_tau_out, gamma, scale):
            peaks, dropped = (), ()  # round-off of a flat spectrum, not a polarisation
        choice = float(math.exp(out["log_lambda_choice"][i])) if fixed is None else math.nan
        results.append(
            DRTResult(
                frequency=freq.copy(),
                impedance=flat[i].copy(),
                z_fit=z_fit,
                residuals=residual,
                tau=tau_out,
                gamma=gamma,
                gamma_q05=q05[i] * scale,
                gamma_q95=q95[i] * scale,
                r_inf_ohm=float(series["r_inf"] * scale),
                l_h=l_h,
                c_f=c_f,
                lam=float(math.exp(out["log_lambda"][i])),
                band_lambda=float(math.exp(out["log_lambda_band"][i])),
                lambda_method="fixed" if fixed is not None else lam_method,
                lambda_choice=choice,
                lambda_note=_lambda_note(lam_method, choice, int(out["choice_index"][i])) if fixed is None else "",
                signed=bool(signed),
                peaks=peaks,
                dropped_peaks=dropped,
                rms_rel=float(np.sqrt(np.mean(np.abs(residual) ** 2))),
                noise_estimate=float(out["sigma"][i]),
                difference_noise=residual_noise(residual.real, residual.imag, np.argsort(freq), float(out["effective_parameters"][i])),
                converged=bool(out["converged"][i]),
                effective_parameters=float(out["effective_parameters"][i]),
                lambda_grid=np.exp(_LOG_LAMBDA_GRID),
                gcv_curve=out["gcv"][i],
                basis_tau=rbf.tau,
                coefficients=x[n_series:] * scale,
                basis_fwhm_decades=rbf.fwhm_decades,
                derivative=int(derivative),
                z_ref=float(scale),
                source=source,
                options=options,
                sign_hint=values_sign_hint(freq, flat[i], attrs),
            )
        )
    if fixed is not None and any(r.misfits for r in results):
        results = _with_automatic_lambda(results, lambda log_lambda: _stored_solve(lam_method, bool(signed), len(names), int(max_iter))(
            design_re, design_im, weights, zn.real, zn.imag, gamma_penalty, r_inv, mask, phi, _LOG_LAMBDA_GRID, log_lambda, math.log(_LAMBDA_FLOOR),
        ), design_re, design_im, flat, z_ref)
    if not dims:
        return results[0]
    return DRTBatchResult(dims=dims, shape=z.shape[:-1], coords=coords, results=tuple(results))
