"""`DRTResult` (one spectrum) and `DRTBatchResult` (a Dataset with extra dimensions)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np
import xarray as xr

from ...data import checked_frequencies, concise_repr, report_text, counted, format_lambda, format_quantity, format_time, format_uncertain, label_text
from ...errors import IN_MEMORY, ParameterError
from ...io.netcdf import result_dataset
from .peaks import ROUNDOFF_SHARE, Peak, below_roundoff, counted_peaks
from ..grid import ResultGrid
from ..frozen import FrozenResult, freeze_fields

__all__ = ["DRTResult", "DRTBatchResult", "format_lambda"]

LAMBDA_FLOOR = 1e-4
"""An automatic λ is never below this (docs/drt.md, "Choosing λ")."""



# a DRT fit worse than this (rms_rel) does not reproduce the data (`DRTResult.warnings`)
DRT_MISFIT_MAX = 0.05

OVER_SMOOTHED_FACTOR = 3.0
"""A fixed λ over-smooths (`DRTResult.over_smoothed`) when the automatic λ reproduces the same
spectrum this many times better, or within the noise: a SYNTHETIC 10 Ω + 100 Ω ∥ 100 µF
spectrum at λ = 10⁶ misfits by 70 %, at gcv's λ by 1.1 % (tests/test_drt_over_smoothed.py)."""

SPARSE_POINTS_PER_DECADE = 2.0
"""Below this many frequencies a decade (N over the measured band's decades) the DRT warns
(`DRTResult.sparse_warning`): its residuals there hold the smoothing's misfit as well as the
noise, so neither noise estimate is the noise, and the automatic λ smooths more. SYNTHETIC exact
100 Ω + 1 kΩ/(1 + jωτ) spectra over 1 Hz–100 kHz (τ = 0.3, 1, 3 ms): at 1.2 a decade (6 points)
λ = 0.35–1.1, rms_rel 11–13 % beside a first-difference "noise" of 9–12 % and peak τ 30–50 %
long; at 1.4 τ 19–33 % long; at 1.8 8–11 %; at 2 and above 2–7 % (tests/test_drt_sparse.py)."""

MISFIT_NOISE_RATIO = 1.5
"""... and rms_rel must also exceed this many times the misfit the noise alone gives,
√2 × ``difference_noise`` (rms_rel is of the complex residual, σ per part): on SYNTHETIC R‖C
spectra at 5 % noise rms_rel is 1.0–1.1 × that (7.3 % against a 5.3 % first-difference
estimate), while a drift of Re Z at low frequency, which first differences barely see, stands
at 5× (tests/test_drt_counted_peaks.py; docs/drt.md, "Model", 2026-12-01)."""


PREDICT_BLOCK = 32
"""Frequencies whose basis integrals `DRTResult.predict` evaluates at once."""


@dataclass(frozen=True, eq=False)
class DRTResult(FrozenResult):
    """The distribution of relaxation times of one spectrum (see `impedax.drt`).

    Z(ω) = R_∞ + jωL + 1/(jωC) + ∫ γ(ln τ)/(1 + jωτ) d ln τ.
    ``tau`` (K,) [s] and ``gamma`` [Ω] on the output grid, ``gamma_q05``/``gamma_q95`` the 90 %
    credible band (Gaussian posterior at the evidence-chosen ``band_lambda``, widened to
    contain ``gamma``); ``r_inf_ohm``, ``l_h``, ``c_f`` (inf when no series capacitor was fitted);
    ``z_fit`` the DRT model at ``frequency``; ``residuals`` = (Z_data − Z_fit)/|Z_data|;
    ``lam`` the regularisation parameter (relative to ``z_ref``² = max|Z|²: the residuals are
    relative to |Z| and the penalty acts on γ/``z_ref``; γ itself is in Ω; docs/drt.md, "Choosing λ"),
    ``lambda_method`` how it was chosen ("gcv", "lcurve" or "fixed"), ``lambda_choice`` the
    criterion's own choice (before the floor; nan when fixed) and ``lambda_note`` what moved λ
    from it ("" when nothing did); ``peaks`` sorted by τ, ``dropped_peaks`` the peaks below
    the cut-off whose area no reported peak holds; ``noise_estimate`` the fit's residual σ
    (relative), ``difference_noise`` the KK test's first-difference estimate on the same
    residuals; ``sign_hint`` why and how Z'' (or Z', or Z) may be stored with the opposite sign
    (`io.sign_check.values_sign_hint`), or None.
    """

    __repr__ = concise_repr  # (the generated one printed every array)
    __str__ = report_text  # (print(result): its report)

    frequency: np.ndarray
    impedance: np.ndarray
    z_fit: np.ndarray
    residuals: np.ndarray
    tau: np.ndarray
    gamma: np.ndarray
    gamma_q05: np.ndarray
    gamma_q95: np.ndarray
    r_inf_ohm: float
    l_h: float
    c_f: float
    lam: float
    lambda_method: str
    signed: bool
    peaks: tuple[Peak, ...]
    rms_rel: float
    noise_estimate: float
    converged: bool
    effective_parameters: float
    lambda_grid: np.ndarray
    gcv_curve: np.ndarray
    basis_tau: np.ndarray
    coefficients: np.ndarray
    basis_fwhm_decades: float
    derivative: int
    z_ref: float
    source: str = IN_MEMORY
    band_lambda: float = math.nan  # λ of the credible band (evidence-chosen; docs/drt.md)
    options: Mapping[str, object] = field(default_factory=dict)  # the drt() keywords that shape γ (reused by unexplained_peaks)
    lambda_choice: float = math.nan
    lambda_note: str = ""
    dropped_peaks: tuple[Peak, ...] = ()
    difference_noise: float = math.nan
    sign_hint: str | None = None  # `io.sign_check.values_sign_hint`: Z'' (or Z') may be stored with the opposite sign
    auto_lambda: float = math.nan  # a fixed λ that misfits: the λ ``lambda_method`` would choose (nan otherwise)
    auto_rms_rel: float = math.nan  # … and γ's rms_rel at it (`over_smoothed`)

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def basis(self):
        """The fitted Gaussian RBFs (`basis.RBFBasis`): centres ``basis_tau``, width from
        ``basis_fwhm_decades``; γ(y) = Σ_m ``coefficients``_m φ_m(y)."""
        from .basis import RBFBasis

        ln_tau = np.log(self.basis_tau)
        return RBFBasis(ln_tau=ln_tau, step=float(np.mean(np.diff(ln_tau))) if ln_tau.size > 1 else 1.0, epsilon=2.0 * math.sqrt(math.log(2.0)) / (self.basis_fwhm_decades * math.log(10.0)))

    @property
    def polarization_resistance(self) -> float:
        """R_pol = ∫ γ d ln τ [Ω] over all ln τ, of the fitted expansion itself: Σ_m x_m √π/ε
        (each Gaussian's closed-form area), so R_∞ + R_pol is `predict` at f → 0 when there is
        no series capacitor (not the output grid's trapezoid, which leaves out the tails)."""
        return float(self.basis.integral() @ self.coefficients)

    @property
    def window(self) -> tuple[float, float]:
        """The measured τ range 1/(2π f_max) .. 1/(2π f_min) [s]."""
        return 1.0 / (2 * math.pi * float(self.frequency.max())), 1.0 / (2 * math.pi * float(self.frequency.min()))

    def predict(self, freq) -> np.ndarray:
        """The DRT model's impedance [Ω] at ``freq`` [Hz], as ``z_fit`` is at the data's:
        R_∞ + jωL (+ 1/(jωC)) + Σ_m x_m ∫ φ_m(y)/(1 + jω e^y) dy over the fitted Gaussian RBFs
        (docs/drt.md)."""
        from .basis import impedance_integrals

        freq = checked_frequencies(freq)
        shape = freq.shape
        omega = 2 * np.pi * freq.ravel()
        basis = self.basis
        z_pol = np.empty(omega.size, complex)
        # in blocks of `PREDICT_BLOCK` frequencies: the integrals' work array is frequencies ×
        # basis functions × quadrature nodes (a figure's 400 points at once took ~0.3 GB)
        for start in range(0, omega.size, PREDICT_BLOCK):
            a_re, a_im = impedance_integrals(omega[start : start + PREDICT_BLOCK], basis)
            z_pol[start : start + PREDICT_BLOCK] = (a_re + 1j * a_im) @ self.coefficients
        z = self.r_inf_ohm + 1j * omega * self.l_h + z_pol
        z = z if math.isinf(self.c_f) else z + 1 / (1j * omega * self.c_f)
        return z.reshape(shape)

    def gamma_at(self, tau) -> np.ndarray:
        """γ [Ω] at arbitrary τ [s] (interpolated in ln τ on the output grid; 0 outside it)."""
        return np.interp(np.log(np.asarray(tau, float)), np.log(self.tau), self.gamma, left=0.0, right=0.0)

    def to_xarray(self) -> xr.Dataset:
        """γ and its band over ``tau``, data and fit over ``frequency``, peaks over ``peak``;
        ``residuals`` = (Z − Z_fit)/|Z| (data minus model)."""
        peaks = self.peaks
        return result_dataset(xr.Dataset(
            {
                "gamma": ("tau", self.gamma, {"units": "ohm", "long_name": "distribution of relaxation times γ(ln τ)"}),
                "gamma_q05": ("tau", self.gamma_q05, {"units": "ohm", "long_name": "5 % credible quantile of γ"}),
                "gamma_q95": ("tau", self.gamma_q95, {"units": "ohm", "long_name": "95 % credible quantile of γ"}),
                "Z": ("frequency", self.impedance, {"units": "ohm", "long_name": "measured impedance"}),
                "Z_fit": ("frequency", self.z_fit, {"units": "ohm", "long_name": "DRT model impedance"}),
                "residuals": ("frequency", self.residuals, {"units": "1", "long_name": RESIDUAL_LONG_NAME}),
                "peak_tau": ("peak", np.array([p.tau_s for p in peaks], float), {"units": "s"}),
                "peak_r": ("peak", np.array([p.r_ohm for p in peaks], float), {"units": "ohm"}),
                "peak_width": ("peak", np.array([p.width_decades for p in peaks], float), {"units": "decades"}),
                "peak_log10_tau_sd": ("peak", np.array([p.log10_tau_sd for p in peaks], float), {"units": "decades"}),
                "peak_r_sd": ("peak", np.array([p.r_ohm_sd for p in peaks], float), {"units": "ohm"}),
                "r_inf": ((), self.r_inf_ohm, {"units": "ohm"}),
                "inductance": ((), self.l_h, {"units": "H"}),
                "capacitance": ((), self.c_f, {"units": "F"}),
                "peak_inside_window": ("peak", np.array([int(p.inside_window) for p in peaks], np.int8), {"long_name": "1: the peak's tau lies in the measured range"}),
                "peak_resolved": ("peak", np.array([int(p.resolved) for p in peaks], np.int8), {"long_name": "1: the peak's R is told from zero (|R| >= 2 sd)"}),
                "lam": ((), self.lam),
                "rms_rel": ((), self.rms_rel, {"units": "1"}),
                "residual_sigma": ((), self.noise_estimate, {"units": "1", "long_name": "residual standard deviation of the DRT fit (relative)"}),
                "difference_noise": ((), self.difference_noise, {"units": "1", "long_name": "first-difference noise estimate of the residuals (the KK test's)"}),
                "dropped_r": ((), float(sum(p.r_ohm for p in self.dropped_peaks)), {"units": "ohm", "long_name": "R of the peaks dropped below the cut-off"}),
                **_setting_variables((), (), [self]),
                **_warnings_variable((), (), [self]),
            },
            coords={"tau": ("tau", self.tau, {"units": "s"}), "frequency": ("frequency", self.frequency, {"units": "Hz"})},
            attrs={
                "impedax_kind": "drt",  # (impedax inspect names the file a DRT's, as other results)
                "method": "Tikhonov-regularised DRT on a Gaussian RBF basis (impedax, docs/drt.md)",
                "lambda_method": self.lambda_method,
                "lambda_note": self.lambda_note,
                "lambda_scale": f"relative to z_ref_ohm^2, z_ref_ohm = max|Z| = {self.z_ref:.6g}",
                "min_peak_fraction": float(self.options.get("min_peak_fraction", 0.1)),
                "signed": int(self.signed),
                "derivative_order": self.derivative,
                "basis_fwhm_decades": self.basis_fwhm_decades,
                "band_lambda": self.band_lambda,
                **({"sign_hint": self.sign_hint} if self.sign_hint else {}),
                "band": "90 % credible band: Gaussian posterior at the evidence-chosen band_lambda, widened to contain gamma; it covers the noise, not the smoothing bias at peaks (docs/drt.md)",
                "source": self.source,
            },
        ).copy(deep=True))

    @property
    def warnings(self) -> tuple[str, ...]:
        """What makes R_∞, L or γ unlike a passive cell's: R_∞ below −1 % of |Z| at the top
        frequency (a passive cell has R_∞ ≥ 0), L < 0 beyond 5 % of that |Z| (the high end more
        capacitive than the arcs), and rms_rel above `DRT_MISFIT_MAX` and above
        `MISFIT_NOISE_RATIO` × √2 × ``difference_noise`` (γ does not reproduce the data, by
        more than the noise explains). ``sign_hint`` leads when there is one: a sign stored flipped
        is the cause of the rest (no passive cell's γ reproduces conj(Z))."""
        top = int(np.argmax(self.frequency))
        z_top = abs(self.impedance[top])
        out = [self.sign_hint] if self.sign_hint else []
        if self.r_inf_ohm < -0.01 * z_top:
            out.append(
                f"R_inf = {format_quantity(self.r_inf_ohm, 'Ω')} is negative, which no passive cell has: the data stop before the high-frequency "
                "limit or carry an instrument's phase error there; leave the top points out (`data.where(data.frequency <= f, drop=True)`, in either order of the points) or check the sign convention"
            )
        if self.l_h < 0 and 2 * math.pi * float(self.frequency[top]) * -self.l_h > 0.05 * z_top:
            top_share = -float(self.impedance[top].imag) / z_top
            if top_share >= OPEN_ARC_SHARE:  # (the band ends inside an arc: Gamry's REAL file, 86 %)
                cause = (f"; the data end inside an arc (−Z'' is still {top_share * 100:.0f} % of |Z| at the top frequency): an arc above the measured band or a stray "
                         "capacitance, which R_inf and L stand in for; measure higher frequencies, or read R_inf as an upper bound of the series resistance")
            else:
                cause = " (stray capacitance, or a cable's phase error)"
            out.append(f"L = {format_quantity(self.l_h, 'H')} is negative: the high-frequency end is more capacitive than the arcs explain{cause}")
        if self.sparse_warning:
            out.append(self.sparse_warning)
        if self.misfits:
            noise_misfit = math.sqrt(2.0) * self.difference_noise
            short = (f"γ reproduces the data to only {self.rms_rel * 100:.3g} % (rms_rel), more than the noise explains (first-difference noise "
                     f"{self.difference_noise * 100:.2g} %, which alone gives rms_rel ≈ {noise_misfit * 100:.2g} %)")
            if self.over_smoothed:
                out.append(
                    f"{short}: λ = {format_lambda(self.lam)} as given over-smooths them; at λ = {format_lambda(self.auto_lambda)}, the automatic "
                    f"choice, γ reproduces them to {self.auto_rms_rel * 100:.3g} %: give a smaller λ (lam) or let it be chosen (lam='auto'); "
                    "peaks read off this γ come out too broad, and close ones merge"
                )
            else:
                out.append(f"{short}: the data are not Kramers–Kronig consistent in part (impedax kk)" + ("" if self.signed else " or need γ < 0 somewhere (signed=True)"))
        return tuple(out)

    @property
    def points_per_decade(self) -> float:
        """Frequencies a decade over the measured band (N / decades; inf for one frequency)."""
        decades = math.log10(float(self.frequency.max() / self.frequency.min()))
        return self.frequency.size / decades if decades > 0 else math.inf

    @property
    def sparse_warning(self) -> str | None:
        """On data sparser than `SPARSE_POINTS_PER_DECADE`: what the DRT cannot tell there (the
        noise from the smoothing's misfit; a peak's τ and width as closely). None otherwise."""
        if self.points_per_decade >= SPARSE_POINTS_PER_DECADE:
            return None
        smooths = ", and the automatic λ smooths more" if self.lambda_method != "fixed" else ""
        return (f"sparse data: at {self.points_per_decade:.2g} points a decade the residuals hold the smoothing's misfit as well as the noise (rms_rel "
                f"{self.rms_rel * 100:.3g} % need not be noise){smooths}: peaks come out broader and "
                f"their τ less sure (on SYNTHETIC exact R‖C spectra at 1.2 a decade, τ came out 30–50 % long); measure at least {SPARSE_POINTS_PER_DECADE:g} "
                "points a decade, or fit a circuit to these points (impedax fit)")

    @property
    def misfits(self) -> bool:
        """γ does not reproduce the data: rms_rel above `DRT_MISFIT_MAX` and above
        `MISFIT_NOISE_RATIO` × √2 × ``difference_noise`` (more than the noise explains)."""
        return _beyond_noise(self.rms_rel, self.difference_noise)

    @property
    def over_smoothed(self) -> bool:
        """A fixed λ is the cause of the misfit (`misfits`), not the data: at the λ
        ``lambda_method`` chooses (``auto_lambda``, smaller) γ reproduces the same spectrum to
        `OVER_SMOOTHED_FACTOR` × less, or within the noise (docs/drt.md, "Choosing λ")."""
        if not (self.lambda_method == "fixed" and self.misfits and math.isfinite(self.auto_rms_rel) and self.auto_lambda < self.lam):
            return False
        return self.auto_rms_rel * OVER_SMOOTHED_FACTOR <= self.rms_rel or not _beyond_noise(self.auto_rms_rel, self.difference_noise)

    @property
    def notes(self) -> tuple[str, ...]:
        """What the report says below `warnings`' thresholds: L < 0 of any size (no cell has a
        negative inductance; `warnings` only names one beyond 5 % of |Z| at the top frequency),
        then `shape.shape_notes` (a diffusion tail, peaks broader than one R‖C's)."""
        from .shape import shape_notes

        return self._flat_notes() + self._band_lambda_edge_notes() + self._negative_l_notes() + shape_notes(self)

    @property
    def band_lambda_at_grid_edge(self) -> str | None:
        """``"bottom"`` or ``"top"`` when the credible band's λ (``band_lambda``, the evidence's
        optimum on ``lambda_grid``) is an end of that grid, where the evidence's maximum lies
        there or beyond, so no optimum; None inside it (or with no band λ)."""
        grid = np.asarray(self.lambda_grid, float)
        if not (math.isfinite(self.band_lambda) and grid.size):
            return None
        if self.band_lambda <= grid[0] * (1 + 1e-9):
            return "bottom"
        if self.band_lambda >= grid[-1] * (1 - 1e-9):
            return "top"
        return None

    def _band_lambda_edge_notes(self) -> tuple[str, ...]:
        edge = self.band_lambda_at_grid_edge
        if edge is None:
            return ()
        grid = np.asarray(self.lambda_grid, float)
        beyond, kind = ("below", "roughest") if edge == "bottom" else ("above", "smoothest")
        return (f"the credible band's λ = {format_lambda(self.band_lambda)} (the evidence's) is at the {edge} of its search grid, "
                f"{format_lambda(float(grid[0]))}–{format_lambda(float(grid[-1]))}: not an optimum, the evidence's maximum is there or {beyond}, "
                f"so the band is that of the {kind} γ the grid holds (γ, its λ and the peaks do not depend on it)",)

    @property
    def flat(self) -> bool:
        """γ is round-off: ∫|γ| d ln τ < `peaks.ROUNDOFF_SHARE` · max|Z| (a resistor; no peaks)."""
        return below_roundoff(np.log(self.tau), self.gamma, self.z_ref)

    def _flat_notes(self) -> tuple[str, ...]:
        if self.flat:
            return (f"∫|γ| d ln τ is below {ROUNDOFF_SHARE:g} of max|Z|: the spectrum is flat (a resistor); γ holds the solve's round-off, no peak",)
        return ()

    def _negative_l_notes(self) -> tuple[str, ...]:
        if self.l_h < 0 and not any(w.startswith("L = ") for w in self.warnings):
            return (f"L = {format_quantity(self.l_h, 'H')} is negative, which no physical cell or lead has (below the 5 % of |Z| that makes it a warning): "
                    "likely a cable or sign-convention artefact, a high-frequency arc above the measured band that L stands in for, "
                    "or noise about L = 0; read R_inf with care",)
        return ()

    @property
    def lambda_text(self) -> str:
        """λ and how it was chosen, as the report's first line says it."""
        how = "as given" if self.lambda_method == "fixed" else f"by {self.lambda_method}" + (f", {self.lambda_note}" if self.lambda_note else "")
        return f"λ = {format_lambda(self.lam)} {how}"

    @property
    def lambda_scale_text(self) -> str:
        """What λ is relative to, and the credible band's λ: where it is not γ's (beyond 1 %, the
        figure legend's rule, `plotting.drt.band_label`), γ's λ beside it and what the band then
        is: the band of a smoother (larger λ) or rougher γ, widened to contain the γ shown, so its
        width is not that γ's uncertainty (REAL exampleDataParstat.txt: band at λ = 12, γ at 10⁻⁴)."""
        scale = f"λ is relative to max|Z|² = ({format_quantity(self.z_ref, 'Ω')})² (residuals relative to |Z|, penalty on γ/max|Z|; γ is reported in Ω); "
        noise = "noise only: it leaves out the smoothing that lowers peaks, docs/drt.md"
        band = f"credible band at λ = {format_lambda(self.band_lambda, 2)}"
        if not (math.isfinite(self.band_lambda) and math.isfinite(self.lam)) or abs(self.band_lambda - self.lam) <= 0.01 * self.lam:
            return scale + f"{band} (γ's λ; {noise})"
        kind = "smoother" if self.band_lambda > self.lam else "rougher"
        return (scale + f"{band} (the evidence's), not at γ's λ = {format_lambda(self.lam, 2)}: the band of a {kind} γ, widened to contain the γ shown, "
                f"so its width is not the uncertainty of the γ shown (the peaks' ± are, at γ's λ); {noise}")

    @property
    def cutoff_text(self) -> str:
        """The peak cut-off in words (docs/drt.md, "Peaks")."""
        from .peaks import RESOLVED_SHARE

        share = float(self.options.get("min_peak_fraction", 0.1))
        return f"{share * 100:.3g} % of ∫|γ|, {share * RESOLVED_SHARE * 100:.3g} % when resolved"

    def report(self) -> str:
        """A few lines: λ, how it was chosen and its scale, R_∞, L, C, R_pol, the fit error
        against the residual σ and the first-difference noise, the peaks, the peaks dropped
        below the cut-off and the warnings."""
        lines = [
            f"DRT ({'signed' if self.signed else 'non-negative'}, Tikhonov on Gaussian RBFs, derivative order {self.derivative}): {self.lambda_text}",
            self.lambda_scale_text,
            f"R_inf = {format_quantity(self.r_inf_ohm, 'Ω', 4)}, L = {format_quantity(self.l_h, 'H')}" + ("" if math.isinf(self.c_f) else f", C = {format_quantity(self.c_f, 'F')}")
            + f", R_pol = {format_quantity(self.polarization_resistance, 'Ω', 4)}",
            f"rms_rel = {self.rms_rel * 100:.3g} % (residual σ {self.noise_estimate * 100:.3g} %, first-difference noise {self.difference_noise * 100:.2g} %)"
            + ("" if self.converged else "; active-set solve did NOT converge"),
            f"{_peak_count_text(self.peaks)}" + (f" ({PEAK_SD_WORDS}):" if self.peaks else ":"),
        ]
        for p in self.peaks:
            where = ("" if p.inside_window else "  (outside the measured range)") + ("" if p.resolved else "  (R not told from zero: a ripple, not counted)")
            lines.append(
                f"  τ = {format_time(p.tau_s)} (f = {format_quantity(p.frequency_hz, 'Hz')}, ±{p.log10_tau_sd:.2g} dec)  R = {format_uncertain(p.r_ohm, p.r_ohm_sd, 'Ω')}  "
                f"width {p.width_decades:.2f} dec{where}"
            )
        if self.dropped_peaks:
            d = self.dropped_peaks
            lines.append(
                f"{len(d)} peak(s) below the cut-off ({self.cutoff_text}: min_peak_fraction) dropped, R = {format_quantity(sum(p.r_ohm for p in d), 'Ω')} in all "
                f"(at τ = {', '.join(format_time(p.tau_s, 2) for p in d)})"
            )
        lines += [f"note: {n}" for n in self.notes]
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines)

    def to_table(self) -> list[dict]:
        """γ over τ as tidy rows ``tau_s, gamma_ohm, gamma_q05_ohm, gamma_q95_ohm``, then
        ``warnings`` (`warnings` joined by "; ", "" if none, on every row, as a fit's table has
        them, so that the CSV keeps REAL PowerSuite's "R_inf < 0" warning) (the ``.csv``
        of `impedax.write_result` and of ``impedax drt --out``, whose provenance columns come
        before ``warnings``: it stays the last column)."""
        warned = "; ".join(self.warnings)
        return [{"tau_s": t, "gamma_ohm": g, "gamma_q05_ohm": lo, "gamma_q95_ohm": hi, "warnings": warned}
                for t, g, lo, hi in zip(self.tau, self.gamma, self.gamma_q05, self.gamma_q95)]

    def summary(self) -> dict:
        """The JSON of ``impedax drt --json`` (the keys are the public contract: keys are added,
        never renamed; NaN and inf are written as null)."""
        return self._summary(self.suggested_circuit())

    def _summary(self, suggestion) -> dict:
        """`summary` with the starting circuit read off this DRT given (`suggested_circuit`: a
        batch reads each once for its rows and its most common one)."""
        return {
            "tau_s": self.tau,
            "gamma_ohm": self.gamma,
            "gamma_q05": self.gamma_q05,
            "gamma_q95": self.gamma_q95,
            "r_inf_ohm": self.r_inf_ohm,
            "l_h": self.l_h,
            "lambda": self.lam,
            "lambda_method": self.lambda_method,
            "peaks": [
                {"tau_s": p.tau_s, "r_ohm": p.r_ohm, "width_decades": p.width_decades, "r_ohm_sd": p.r_ohm_sd, "log10_tau_sd": p.log10_tau_sd,
                 "inside_window": p.inside_window, "frequency_hz": p.frequency_hz, "gamma_max_ohm": p.gamma_max_ohm, "resolved": p.resolved}
                for p in self.peaks
            ],
            "n_resolved_peaks": len(counted_peaks(self.peaks)),
            "rms_rel": self.rms_rel,
            "warnings": list(self.warnings),
            "sign_hint": self.sign_hint,
            "c_f": None if math.isinf(self.c_f) else self.c_f,
            "r_pol_ohm": self.polarization_resistance,
            "residual_sigma": self.noise_estimate,
            "difference_noise": self.difference_noise,
            "converged": self.converged,
            "lambda_choice": self.lambda_choice,
            "lambda_note": self.lambda_note or None,
            "over_smoothed": self.over_smoothed,
            "auto_lambda": self.auto_lambda,
            "auto_rms_rel": self.auto_rms_rel,
            "lambda_floor": LAMBDA_FLOOR,
            "lambda_scale": "relative to z_ref_ohm^2 (z_ref_ohm = max|Z|; residuals relative to |Z|)",
            "z_ref_ohm": self.z_ref,
            "band_lambda": self.band_lambda,
            "band_lambda_at_grid_edge": self.band_lambda_at_grid_edge,
            "min_peak_fraction": self.options.get("min_peak_fraction"),
            "dropped_peaks": [{"tau_s": p.tau_s, "r_ohm": p.r_ohm, "inside_window": p.inside_window} for p in self.dropped_peaks],
            "dropped_r_ohm": float(sum(p.r_ohm for p in self.dropped_peaks)),
            "window_tau_s": list(self.window),
            "notes": list(self.notes),
            **_suggestion_keys(suggestion),
        }

    def _repr_html_(self) -> str:
        from ...plotting.html import result_html

        rows = [{"τ [s]": p.tau_s, "f [Hz]": p.frequency_hz, "R [Ω]": p.r_ohm, "R sd [Ω]": p.r_ohm_sd, "width [dec]": p.width_decades} for p in self.peaks]
        lines = [f"{self.lambda_text}; R_inf = {self.r_inf_ohm:.4g} Ω, R_pol = {self.polarization_resistance:.4g} Ω; rms_rel {self.rms_rel * 100:.3g} %; {_peak_count_text(self.peaks)}"]
        return result_html("distribution of relaxation times", rows, lines=lines)

    def suggested_circuit(self):
        """A starting circuit read off this DRT (`suggest.SuggestedCircuit`: ``model``, ``init``,
        ``reasons``): R0 + one R‖CPE per counted peak (R‖C when as narrow as an ideal R‖C's), + W1 on a diffusion tail (a CPE on a constant-phase tail), + L1 when L is
        visible (`suggest.suggest_circuit`; docs/drt.md, "From the DRT to a circuit")."""
        from .suggest import suggest_circuit

        return suggest_circuit(self)

    def plot(self, *, overlay=None, title: str | None = None):
        """γ vs τ with the credible band and peaks marked, and the fit on Nyquist/Bode; ``overlay``
        (an `AnalyticDRT` or another `DRTResult`, e.g. of a fitted circuit) is drawn on the γ
        axes. Returns a matplotlib Figure (see `impedax.plotting.drt.plot_drt`)."""
        from ...plotting.drt import plot_drt

        if overlay is not None and not (hasattr(overlay, "tau") and hasattr(overlay, "gamma")):  # (a FitResult raised "'FitResult' object has no attribute 'tau'" from the figure code)
            fit = " (a fit's DRT is impedax.fitting.drt.circuit_drt(fit))" if hasattr(overlay, "circuit") else ""
            raise ParameterError(f"overlay must be a DRT, an AnalyticDRT or a DRTResult{fit}; got {type(overlay).__name__}")
        return plot_drt(self, overlay=overlay, title=title)


def _beyond_noise(rms_rel: float, difference_noise: float) -> bool:
    """A DRT's misfit ``rms_rel`` is more than the noise explains: above `DRT_MISFIT_MAX` and
    above `MISFIT_NOISE_RATIO` × √2 × ``difference_noise`` (`DRTResult.misfits`)."""
    return rms_rel > DRT_MISFIT_MAX and not rms_rel <= MISFIT_NOISE_RATIO * math.sqrt(2.0) * difference_noise


def _suggestion_keys(suggestion) -> dict:
    """The JSON keys of `DRTResult.suggested_circuit`."""
    return {"suggested_model": suggestion.model, "suggested_init": dict(suggestion.init), "suggestion_reasons": list(suggestion.reasons)}


def _common_attrs(result: "DRTResult") -> dict:
    """The global attributes of a batch's .nc: the options every spectrum shares."""
    return {
        "impedax_kind": "drt",
        "method": "Tikhonov-regularised DRT on a Gaussian RBF basis (impedax, docs/drt.md)",
        "lambda_method": result.lambda_method,
        "lambda_scale": "relative to z_ref^2 per spectrum, z_ref = max|Z| of that spectrum (variable z_ref, ohm)",
        "min_peak_fraction": float(result.options.get("min_peak_fraction", 0.1)),
        "signed": int(result.signed),
        "derivative_order": result.derivative,
        "basis_fwhm_decades": result.basis_fwhm_decades,
        "band": "90 % credible band: Gaussian posterior at the evidence-chosen band_lambda (variable, per spectrum), widened to contain gamma; it covers the noise, not the smoothing bias at peaks (docs/drt.md)",
    }


def _setting_variables(dims: tuple, shape: tuple, results) -> dict:
    """What λ was for each spectrum, as variables over ``dims`` (the batch file's global
    attributes held the first spectrum's): ``z_ref``, ``lambda_choice``, ``band_lambda``, ``lambda_note``."""

    def column(values, dtype):
        return np.asarray(values, dtype).reshape(shape)

    return {
        "z_ref": (dims, column([r.z_ref for r in results], float), {"units": "ohm", "long_name": "max|Z|: lam is relative to z_ref^2"}),
        "lambda_choice": (dims, column([r.lambda_choice for r in results], float), {"long_name": "lambda_method's own choice of lam, before the floor (NaN when lam was fixed)"}),
        "band_lambda": (dims, column([r.band_lambda for r in results], float), {"long_name": "lam of the credible band (evidence-chosen)"}),
        "lambda_note": (dims, column([r.lambda_note for r in results], object), {"long_name": "what moved lam from lambda_choice ('' when nothing did)"}),
    }


def _warnings_variable(dims: tuple, shape: tuple, results) -> dict:
    """Each spectrum's `DRTResult.warnings` joined by "; " ("" for none), as the variable
    ``warnings`` over ``dims`` (so that the .nc, as the CSV, keeps them: REAL
    PowerSuite's "R_inf … is negative")."""
    text = np.asarray(["; ".join(r.warnings) for r in results], object).reshape(shape)
    return {"warnings": (dims, text, {"long_name": "the DRT's warnings, joined by '; ' ('' when none)"})}


OPEN_ARC_SHARE = 0.1
"""A negative L's warning says that the data end inside an arc when −Z'' at the top frequency
is at least this share of |Z| there (a spectrum measured to its high-frequency limit ends near
the real axis: 1.6 % on a SYNTHETIC two-arc spectrum to 100 kHz; Gamry's REAL file ends at 86 %)."""

PEAK_SD_WORDS = "± from the noise alone: the smoothing's bias, at times larger, is not in it"
"""What the peaks' ± hold (docs/drt.md, "Credible band and calibration"). A KK/DRT walkthrough
read "R = 201.26 ± 0.41 Ω" of a SYNTHETIC 200 Ω arc as an error bar that missed by 3 sd."""


def _peak_count_text(peaks) -> str:
    """"N peak(s)" of the report: the resolved ones inside the measured τ window
    (`peaks.counted_peaks`), and how many more are listed."""
    n = len(counted_peaks(peaks))
    more = len(peaks) - n
    return f"{n} peak(s)" + (f" (+{more} listed, outside the measured range or not told from zero, not counted)" if more else "")


def _span(low, high, form: str) -> str:
    """``low``–``high`` in ``form``, or one value when they are equal as written."""
    a, b = form.format(low), form.format(high)
    return a if a == b else f"{a}–{b}"


RESIDUAL_LONG_NAME = "(Z_data - Z_fit)/|Z_data|"
"""The sign of `DRTResult.residuals`, data minus DRT model (the KK test's; a circuit fit's are
model minus data: docs/physics.md), as their ``long_name``."""

BATCH_RESULT_NAMES = frozenset({
    "tau", "frequency", "peak", "gamma", "gamma_q05", "gamma_q95", "Z", "Z_fit", "peak_tau", "peak_r", "peak_width", "peak_inside_window",
    "peak_resolved", "dropped_r", "r_inf", "inductance", "lam", "rms_rel", "z_ref", "lambda_choice", "band_lambda", "lambda_note",
    "residuals", "peak_log10_tau_sd", "peak_r_sd", "capacitance", "residual_sigma", "difference_noise", "warnings",
})
"""The dimensions and variables of `DRTBatchResult.to_xarray`'s Dataset: `drt` refuses a batch
dimension of one of these names (`grid.refuse_result_names`), where ``to_xarray`` had failed
with xarray's "conflicting sizes for dimension 'tau'"."""


@dataclass(frozen=True, eq=False)
class DRTBatchResult(ResultGrid):
    """DRTs of every spectrum of a Dataset with extra dimensions (trial, session, ...), computed
    in one vmapped solve. ``results`` in C order over ``dims``; ``batch[i, j]`` gives one."""

    __str__ = report_text  # (print(result): its report)

    results: tuple[DRTResult, ...]

    def __repr__(self) -> str:
        """One line: how many spectra over which dimensions, the counted peaks of each and rms_rel
        (the generated repr printed every spectrum's arrays)."""
        peaks = [len(counted_peaks(r.peaks)) for r in self.results]
        rms = [r.rms_rel * 100 for r in self.results]
        return (f"DRTBatchResult({counted(len(self.results), 'spectrum', 'spectra')} over {', '.join(self.dims)}: "
                f"{_span(min(peaks), max(peaks), '{}')} counted peak(s){' each' if len(peaks) > 1 else ''}, rms_rel {_span(min(rms), max(rms), '{:.3g}')} %)")

    def _repr_html_(self) -> str:
        """In a notebook: the report's summary line and a row per spectrum (its labels, counted
        peaks, rms_rel, R_inf and R_pol)."""
        from ...plotting.html import result_html

        rows = [{**where, "peaks": len(counted_peaks(r.peaks)), "rms_rel [%]": f"{r.rms_rel * 100:.3g}", "R_inf [Ω]": r.r_inf_ohm, "R_pol [Ω]": r.polarization_resistance}
                for where, r in zip(self.labels(), self.results)]
        return result_html("distributions of relaxation times", rows, lines=[self.report().splitlines()[0]])

    @property
    def gamma(self) -> np.ndarray:
        return np.stack([r.gamma for r in self.results]).reshape(*self.shape, -1)

    @property
    def n_peaks(self) -> np.ndarray:
        return np.array([len(r.peaks) for r in self.results]).reshape(self.shape)

    @property
    def lam(self) -> np.ndarray:
        return self.per_spectrum("lam")

    @property
    def n_resolved_peaks(self) -> np.ndarray:
        """Per spectrum, the peaks counted as relaxations (`peaks.counted_peaks`: resolved and
        inside the measured τ window); ``n_peaks`` counts every listed peak."""
        return np.array([len(counted_peaks(r.peaks)) for r in self.results]).reshape(self.shape)

    def report(self) -> str:
        """A summary line (how many spectra have how many resolved peaks inside the measured τ window, rms_rel's median and maximum),
        then one line per spectrum: its labels, rms_rel, R_inf, R_pol, the peaks (τ and R, those
        outside the measured range marked), the peaks dropped below the cut-off and a note on λ
        when it was not simply the criterion's optimum (docs/drt.md)."""
        counts = self.n_resolved_peaks.ravel()
        values, freq = np.unique(counts, return_counts=True)
        spread = ", ".join(f"{int(f)} with {int(v)} peak(s)" for v, f in zip(values, freq))
        extra = int(self.n_peaks.sum() - counts.sum())
        spread += f" (resolved, inside the measured τ window; {extra} more listed outside it or not told from zero)" if extra else ""
        rms = np.array([r.rms_rel for r in self.results])
        floored, note_of = self._lambda_notes()
        lines = [f"DRT of {counted(len(self.results), 'spectrum', 'spectra')} over {' × '.join(self.dims)}: {spread}; rms_rel median {np.median(rms) * 100:.3g} %, max {rms.max() * 100:.3g} %{floored}"]
        for where, one in zip(self.labels(), self.results):
            peaks = "; ".join(
                f"{format_time(p.tau_s)} ({format_quantity(p.r_ohm, 'Ω')}{'' if p.inside_window else ', outside the measured range'}{'' if p.resolved else ', not told from zero'})" for p in one.peaks
            ) or "none"
            dropped = f"; {len(one.dropped_peaks)} below the cut-off dropped ({format_quantity(sum(p.r_ohm for p in one.dropped_peaks), 'Ω')})" if one.dropped_peaks else ""
            note = note_of(one)
            lines.append(
                f"  {', '.join(f'{d}={label_text(v)}' for d, v in where.items())}: rms_rel {one.rms_rel * 100:.3g} %, R_inf {format_quantity(one.r_inf_ohm, 'Ω', 4)}, "
                f"R_pol {format_quantity(one.polarization_resistance, 'Ω', 4)}, peaks {peaks}{dropped}{note}"
            )
        hinted = [(where, one.sign_hint) for where, one in zip(self.labels(), self.results) if one.sign_hint]
        if hinted:  # (as the KK batch report's hint line: the first spectrum's hint, the others counted)
            listed = "; ".join(", ".join(f"{d}={label_text(v)}" for d, v in where.items()) for where, _ in hinted[:3]) + ("; …" if len(hinted) > 3 else "")
            lines.append(f"warning: in {len(hinted)} of {counted(len(self.results), 'spectrum', 'spectra')} ({listed}): {hinted[0][1]}")
        lines += self._band_edge_notes()
        lines += self._misfit_warnings()
        return "\n".join(lines)

    def _band_edge_notes(self) -> list[str]:
        """One note per end of the λ grid that holds the credible band's λ of some spectra
        (`DRTResult.band_lambda_at_grid_edge`), counting them."""
        out = []
        grid = np.asarray(self.results[0].lambda_grid, float)
        for edge, beyond in (("bottom", "below"), ("top", "above")):
            count = sum(r.band_lambda_at_grid_edge == edge for r in self.results)
            if count:
                out.append(f"note: the credible band's λ (the evidence's) is at the {edge} of its search grid, {format_lambda(float(grid[0]))}–{format_lambda(float(grid[-1]))}, "
                           f"on {count} of {counted(len(self.results), 'spectrum', 'spectra')}: not an optimum, the evidence's maximum is there or {beyond} "
                           "(γ, its λ and the peaks do not depend on it)")
        return out

    def _misfit_warnings(self) -> list[str]:
        """The report's warnings on sparse data (`DRTResult.sparse_warning`, one grid for all), then
        on the spectra γ does not reproduce (`DRTResult.misfits`): those a fixed λ over-smooths
        (`DRTResult.over_smoothed`), then the others (their data)."""
        labels = self.labels()

        def named(indices) -> str:
            return "; ".join(", ".join(f"{d}={label_text(v)}" for d, v in labels[i].items()) for i in indices[:3]) + ("; …" if len(indices) > 3 else "")

        def span(values) -> str:
            lo, hi = min(values) * 100, max(values) * 100
            return f"{lo:.3g} %" if f"{lo:.3g}" == f"{hi:.3g}" else f"{lo:.3g}–{hi:.3g} %"

        total = counted(len(self.results), "spectrum", "spectra")
        smoothed = [i for i, r in enumerate(self.results) if r.over_smoothed]
        others = [i for i, r in enumerate(self.results) if r.misfits and not r.over_smoothed and not r.sign_hint]
        sparse = self.results[0].sparse_warning  # (one frequency grid: every spectrum's or none)
        out = [f"warning: {sparse}"] if sparse else []
        if smoothed:
            first = self.results[smoothed[0]]
            out.append(f"warning: λ = {format_lambda(first.lam)} as given over-smooths {len(smoothed)} of {total} ({named(smoothed)}): γ reproduces them to "
                       f"{span([self.results[i].rms_rel for i in smoothed])}, at the automatic λ to {span([self.results[i].auto_rms_rel for i in smoothed])}; "
                       "give a smaller λ (lam) or let it be chosen (lam='auto')")
        if others:
            out.append(f"warning: γ reproduces {len(others)} of {total} ({named(others)}) to only {span([self.results[i].rms_rel for i in others])}, more than their noise explains: "
                       "their data are not Kramers–Kronig consistent in part (impedax kk)" + ("" if self.results[0].signed else " or need γ < 0 somewhere (signed=True)"))
        return out

    def _lambda_notes(self):
        """(the summary line's words on the spectra whose λ was raised to the floor, the note
        each spectrum's line keeps): the floor is said once with the criterion's range; a line
        names λ only when it differs from that (its criterion's optimum, or the grid's top)."""
        low = [r for r in self.results if r.lambda_note.startswith("raised to the floor")]
        if not low:
            return "", lambda one: f"; λ {one.lam:.2g}, {one.lambda_note}" if one.lambda_note else ""
        method = low[0].lambda_method
        choices = [r.lambda_choice for r in low]
        lo, hi = format_lambda(min(choices), 2), format_lambda(max(choices), 2)
        bottom = sum("bottom of its grid" in r.lambda_note for r in low)
        at_bottom = f"; {bottom} at the bottom of its grid, {format_lambda(float(low[0].lambda_grid[0]))}, or below" if bottom else ""
        text = f"; λ raised to the floor {format_lambda(LAMBDA_FLOOR)} on {len(low)} of {counted(len(self.results), 'spectrum', 'spectra')} ({method} chose {lo if lo == hi else f'{lo}–{hi}'}{at_bottom})"

        def note_of(one) -> str:
            if one.lambda_note.startswith("raised to the floor"):
                return ""
            if one.lambda_note:
                return f"; λ {one.lam:.2g}, {one.lambda_note}"
            return f"; λ {one.lam:.2g} ({one.lambda_method}'s optimum, above the floor)" if one.lambda_method != "fixed" else ""

        return text, note_of

    def summary(self) -> dict:
        """The JSON of ``impedax drt --json`` for several spectra: ``dims`` (their names),
        ``sizes`` ({dimension: length}, the shape `impedax fit --json` gives its ``dims``),
        ``n_spectra`` and ``spectra``, each spectrum's ``labels`` then its `DRTResult.summary` keys;
        then the starting circuit ``impedax drt``'s last line gives: the one most
        spectra suggest (`suggest.most_common_suggestion`), as ``suggested_model``,
        ``suggested_init`` and ``suggestion_reasons`` of the first spectrum that suggests it, whose
        ``labels`` are ``suggested_from``, and ``n_suggesting``, how many suggest it; and
        ``warnings``, the spectra's warnings, each once (as ``impedax kk --json``'s)."""
        from .suggest import most_common_suggestion_at

        labels = self.labels()
        suggestions = [one.suggested_circuit() for one in self.results]  # (each read once: for its row and the most common)
        spectra = [{"labels": where, **one._summary(s)} for where, one, s in zip(labels, self.results, suggestions)]
        index, suggestion, count = most_common_suggestion_at(self.results, suggestions)
        return {"dims": list(self.dims), "sizes": dict(zip(self.dims, map(int, self.shape))), "n_spectra": len(self.results), "spectra": spectra,
                **_suggestion_keys(suggestion), "suggested_from": labels[index], "n_suggesting": count,
                "warnings": sorted({w for row in spectra for w in row["warnings"]})}

    def to_table(self) -> list[dict]:
        """`DRTResult.to_table` of every spectrum after a column per dimension (its label)."""
        return [{**where, **row} for where, one in zip(self.labels(), self.results) for row in one.to_table()]

    def to_xarray(self) -> xr.Dataset:
        """γ, band, fit and scalars stacked over ``dims`` (peaks padded with NaN);
        ``residuals`` = (Z − Z_fit)/|Z| (data minus model)."""
        shape, dims = self.shape, self.dims
        n_peak = max([len(r.peaks) for r in self.results] + [0])

        def stack(get, pad=None):
            rows = [np.asarray(get(r)) for r in self.results]
            if pad is not None:
                rows = [np.pad(v.astype(float), (0, pad - v.size), constant_values=np.nan) for v in rows]
            return np.stack(rows).reshape(*shape, *rows[0].shape)

        first = self.results[0]
        ds = xr.Dataset(
            {
                "gamma": ((*dims, "tau"), stack(lambda r: r.gamma), {"units": "ohm"}),
                "gamma_q05": ((*dims, "tau"), stack(lambda r: r.gamma_q05), {"units": "ohm"}),
                "gamma_q95": ((*dims, "tau"), stack(lambda r: r.gamma_q95), {"units": "ohm"}),
                "Z": ((*dims, "frequency"), stack(lambda r: r.impedance), {"units": "ohm"}),
                "Z_fit": ((*dims, "frequency"), stack(lambda r: r.z_fit), {"units": "ohm"}),
                "residuals": ((*dims, "frequency"), stack(lambda r: r.residuals), {"units": "1", "long_name": RESIDUAL_LONG_NAME}),
                "peak_log10_tau_sd": ((*dims, "peak"), stack(lambda r: np.array([p.log10_tau_sd for p in r.peaks]), n_peak), {"units": "decades"}),
                "peak_r_sd": ((*dims, "peak"), stack(lambda r: np.array([p.r_ohm_sd for p in r.peaks]), n_peak), {"units": "ohm"}),
                "capacitance": (dims, stack(lambda r: r.c_f), {"units": "F"}),
                "residual_sigma": (dims, stack(lambda r: r.noise_estimate), {"units": "1", "long_name": "residual standard deviation of the DRT fit (relative)"}),
                "difference_noise": (dims, stack(lambda r: r.difference_noise), {"units": "1", "long_name": "first-difference noise estimate of the residuals (the KK test's)"}),
                "peak_tau": ((*dims, "peak"), stack(lambda r: np.array([p.tau_s for p in r.peaks]), n_peak), {"units": "s"}),
                "peak_r": ((*dims, "peak"), stack(lambda r: np.array([p.r_ohm for p in r.peaks]), n_peak), {"units": "ohm"}),
                "peak_width": ((*dims, "peak"), stack(lambda r: np.array([p.width_decades for p in r.peaks]), n_peak), {"units": "decades"}),
                "peak_inside_window": ((*dims, "peak"), stack(lambda r: np.array([float(p.inside_window) for p in r.peaks]), n_peak), {"long_name": "1: the peak's tau lies in the measured range (NaN: no peak)"}),
                "peak_resolved": ((*dims, "peak"), stack(lambda r: np.array([float(p.resolved) for p in r.peaks]), n_peak), {"long_name": "1: the peak's R is told from zero, |R| >= 2 sd (NaN: no peak)"}),
                "dropped_r": (dims, stack(lambda r: float(sum(p.r_ohm for p in r.dropped_peaks))), {"units": "ohm", "long_name": "R of the peaks dropped below the cut-off"}),
                "r_inf": (dims, stack(lambda r: r.r_inf_ohm), {"units": "ohm"}),
                "inductance": (dims, stack(lambda r: r.l_h), {"units": "H"}),
                "lam": (dims, stack(lambda r: r.lam)),
                "rms_rel": (dims, stack(lambda r: r.rms_rel), {"units": "1"}),
                **_setting_variables(dims, shape, self.results),
                **_warnings_variable(dims, shape, self.results),
            },
            coords={"tau": ("tau", first.tau, {"units": "s"}), "frequency": ("frequency", first.frequency, {"units": "Hz"}), **{d: (d, np.asarray(v)) for d, v in self.coords.items()}},
        )
        # global attributes: only what every spectrum shares (λ's scale, note and band λ are
        # per spectrum: the variables z_ref, lambda_choice, lambda_note, band_lambda)
        common = _common_attrs(first)
        ds.attrs.update(common)
        return result_dataset(ds.copy(deep=True))

    def plot(self, *, title: str | None = None):
        """γ(τ) of every spectrum on one axes, coloured along the batch (a legend of the labels
        for up to `plotting.drt.LEGEND_MAX` spectra, a colour bar beyond), and rms_rel of each
        DRT fit. Returns a matplotlib Figure (`impedax.plotting.drt.plot_drt_batch`)."""
        from ...plotting.drt import plot_drt_batch

        return plot_drt_batch(self, title=title)
