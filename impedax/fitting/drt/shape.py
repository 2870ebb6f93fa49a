"""Shape notes on a DRT: peaks too broad for one relaxation, and a low-frequency diffusion tail.

`shape_notes(result)` gives the sentences `DRTResult.notes` adds (docs/drt.md, "Shape notes"):

- **broad peak**: a peak inside the measured range whose FWHM is `BROAD_FACTOR` or more times
  that of one ideal R‖C at the same τ, solved at the same frequencies, weights and λ
  (`reference_width`): it may hold more than one relaxation, or a distributed one (a CPE).
- **low-frequency tail**: −Im Z ∝ ω^slope over the lowest decade of the data, slope between
  −0.7 and −0.3 (`diffusion_slopes`, `low_frequency_tail`): a semi-infinite Warburg σ/√(jω)
  when the slope is −0.5 within `WARBURG_TOLERANCE` (or 3 standard errors), whose true
  γ = (σ/π)√τ rises with no peak; otherwise a constant-phase tail, a CPE in series
  (−Im Z = sin(απ/2)/(Q ω^α): slope −α). Either way the DRT's peaks at those τ are not
  separate arcs.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ...data import format_time
from .basis import impedance_integrals, penalty_matrix
from .peaks import find_peaks

__all__ = ["BROAD_FACTOR", "WARBURG_SLOPE_RANGE", "WARBURG_TOLERANCE", "WARBURG_STDERRS", "LowFrequencyTail", "diffusion_slopes", "low_frequency_tail", "diffusion_tail_tau", "reference_width", "shape_notes"]

BROAD_FACTOR = 1.4
"""A peak this many times as wide (FWHM, decades) as one R‖C's at the same λ is called broad.
SYNTHETIC, 71 points over 7 decades, noise 0.3–5 %: one R‖C 0.96–1.03×; two resolved R‖C 1
decade apart 0.97–1.16×, 0.7 decade apart up to 1.34×; a merged pair 1 decade apart 1.43–1.54×;
a ZARC α 0.8 1.3–2.0× (docs/drt.md, "Shape notes")."""

WARBURG_SLOPE_RANGE = (-0.7, -0.3)
"""d ln(−Im Z)/d ln ω of both halves of the lowest decade must lie here for a low-frequency tail
(a Warburg or a CPE in series): a Warburg gives −0.5, an arc below its corner +1, a series C or
an R‖C past its top −1 to −0.8."""

WARBURG_TOLERANCE = 0.05
WARBURG_STDERRS = 3.0
"""A tail is a Warburg's when its slope over the lowest decade is −0.5 within
max(`WARBURG_TOLERANCE`, `WARBURG_STDERRS` × its standard error); else a constant-phase tail.
SYNTHETIC (R0 + R1‖C1 + σ/√(jω) and Randles, 10 mHz–100 kHz at 10 and 7 points a decade, noise
1 % of |Z| on each part, 300 seeds): a Warburg dominating the lowest decade (σ 100 and 20 Ω s^−½,
|Z|/|Im Z| 1.6–2.6) has slopes −0.500 ± 0.008 and ± 0.017–0.019, all called a Warburg; a weak one
(σ 5, |Z|/|Im Z| 6.6) −0.50 ± 0.056–0.064, standard error ≈ 0.05, 96–98 % called (0.05 alone:
57–62 %); a series CPE of α 0.4 or 0.6 of the same size ± 0.02, called a Warburg in ≤ 1 % at 10
points a decade (α 0.4 at 7 a decade: 9 %), α 0.35 and 0.65 never. REAL: impedance.py's
exampleData.csv −0.515 ± 0.004 (a Warburg), exampleDataGamry.DTA −0.367 ± 0.009 (not
"ω^−½": its phase stays at −20 to −22° there: a constant-phase tail)."""

_ETA = 1e-10  # diagonal added to Γ so that it factors (as the DRT solve does, tikhonov.py)


def diffusion_slopes(frequency, impedance) -> tuple[float, float]:
    """The log-slopes d ln(−Im Z)/d ln ω [1] fitted over the lowest and the next half decade
    of ``frequency`` [Hz] (nan where fewer than 3 points or −Im Z ≤ 0)."""
    f = np.asarray(frequency, float)
    minus_im = -np.imag(np.asarray(impedance, complex))
    log_f = np.log10(f)
    lo = float(log_f.min())
    out = []
    for start in (lo, lo + 0.5):
        inside = (log_f >= start - 1e-9) & (log_f <= start + 0.5 + 1e-9)
        if inside.sum() < 3 or np.any(minus_im[inside] <= 0):
            out.append(math.nan)
            continue
        out.append(float(np.polyfit(np.log(f[inside]), np.log(minus_im[inside]), 1)[0]))
    return out[0], out[1]


@dataclass(frozen=True)
class LowFrequencyTail:
    """The lowest decade of a spectrum where −Im Z falls as a power of ω: ``slope`` = d ln(−Im Z)/
    d ln ω fitted over the whole decade and its ``stderr`` (least squares in log–log), ``below_hz``
    the decade's top (10 f_min), ``warburg``: the slope is a Warburg's −0.5 (`WARBURG_TOLERANCE`)."""

    slope: float
    stderr: float
    below_hz: float
    warburg: bool

    @property
    def alpha(self) -> float:
        """The exponent of a CPE in series with this tail: −Im Z = sin(απ/2)/(Q ω^α), slope −α."""
        return -self.slope

    @property
    def tau_s(self) -> float:
        """τ [s] from which the DRT's peaks are the tail's: 1/(2π · ``below_hz``)."""
        return 1.0 / (2 * math.pi * self.below_hz)

    def words(self) -> str:
        """"−Im Z goes as ω^−0.37 (± 0.01) below 0.159 Hz", the measured slope named."""
        return f"−Im Z goes as ω^{self.slope:.2f} (± {self.stderr:.1g}) below {self.below_hz:.3g} Hz".replace("^-", "^−")


def low_frequency_tail(frequency, impedance) -> LowFrequencyTail | None:
    """The spectrum's low-frequency tail (`LowFrequencyTail`) when both `diffusion_slopes` lie in
    `WARBURG_SLOPE_RANGE`; None when not."""
    lo, hi = WARBURG_SLOPE_RANGE
    if not all(lo <= s <= hi for s in diffusion_slopes(frequency, impedance)):
        return None
    f = np.asarray(frequency, float)
    f_min = float(f.min())
    inside = np.log10(f) <= math.log10(f_min) + 1.0 + 1e-9
    x, y = np.log(f[inside]), np.log(-np.imag(np.asarray(impedance, complex)[inside]))
    slope, intercept = np.polyfit(x, y, 1)
    dof = max(x.size - 2, 1)
    stderr = math.sqrt(float(np.sum((y - slope * x - intercept) ** 2)) / dof / float(np.sum((x - x.mean()) ** 2)))
    warburg = abs(slope + 0.5) <= max(WARBURG_TOLERANCE, WARBURG_STDERRS * stderr)
    return LowFrequencyTail(float(slope), stderr, 10.0 * f_min, bool(warburg))


def diffusion_tail_tau(result) -> float:
    """τ [s] from which ``result``'s spectrum is a low-frequency tail (a Warburg or a CPE in
    series, `low_frequency_tail`): 1/(2π · 10 f_min), the top of the lowest decade; inf when it
    has none. The DRT's peaks at or beyond it are the tail's, not arcs (`shape_notes`, `suggest`)."""
    tail = low_frequency_tail(result.frequency, result.impedance)
    return math.inf if tail is None else tail.tau_s


@functools.lru_cache(maxsize=16)
def _reference_design(freq_bytes: bytes, fwhm_decades: float, basis_bytes: bytes, derivative: int, inductance: bool, capacitance: bool, grid_bytes: bytes):
    """What depends only on the frequencies and the basis (cached across a batch's spectra): the
    design [A_re; A_im] with the series columns first, free series terms (R_∞, L) mirrored as
    −column so that NNLS holds every variable ≥ 0, the penalty's root R (Γ + ηI = RᵀR, mirrored
    alike), ω and γ's evaluation matrix on ``grid``."""
    from .basis import RBFBasis

    freq, basis_tau, ln_tau = (np.frombuffer(b) for b in (freq_bytes, basis_bytes, grid_bytes))
    omega = 2 * np.pi * freq
    ln_centres = np.log(basis_tau)
    basis = RBFBasis(ln_tau=ln_centres, step=float(np.mean(np.diff(ln_centres))), epsilon=2.0 * math.sqrt(math.log(2.0)) / (fwhm_decades * math.log(10.0)))
    a_re, a_im = impedance_integrals(omega, basis)
    cols_re, cols_im, free = [np.ones_like(omega)], [np.zeros_like(omega)], [True]
    if inductance:
        cols_re.append(np.zeros_like(omega)), cols_im.append(omega / omega.max()), free.append(True)
    if capacitance:
        cols_re.append(np.zeros_like(omega)), cols_im.append(-omega.min() / omega), free.append(False)
    n_series = len(free)
    design = np.vstack([np.column_stack([*cols_re, a_re]), np.column_stack([*cols_im, a_im])])
    p = design.shape[1]
    penalty = np.zeros((p, p))
    penalty[n_series:, n_series:] = penalty_matrix(basis, derivative)
    root = np.linalg.cholesky(penalty + _ETA * np.eye(p)).T
    mirror = [i for i, f in enumerate(free) if f]
    return np.hstack([-design[:, mirror], design]), np.hstack([-root[:, mirror], root]), omega, basis.evaluate(ln_tau)


def reference_width(result, tau_s: float) -> float:
    """FWHM [decades] of the DRT of one ideal R‖C at ``tau_s`` [s], solved as ``result``'s γ
    was: the same frequencies, relative weights 1/|Z_data| (scaled by max|Z|), basis, penalty,
    series terms and λ, under γ ≥ 0: NNLS on [W A; √λ R] (Γ + ηI = RᵀR)."""
    from scipy.optimize import nnls

    opts = result.options
    ln_tau = np.ascontiguousarray(np.log(result.tau), float)
    design, root, omega, evaluate = _reference_design(
        np.ascontiguousarray(result.frequency, float).tobytes(), float(result.basis_fwhm_decades), np.ascontiguousarray(result.basis_tau, float).tobytes(),
        int(result.derivative), bool(opts.get("inductance", True)), bool(opts.get("capacitance", False)), ln_tau.tobytes(),
    )
    weights = np.tile(result.z_ref / np.abs(result.impedance), 2)  # the solve's 1/|Z/z_ref|
    # the R‖C component alone, in units of z_ref (any R: scaling b scales x, γ ≥ 0 included)
    z = 1.0 / (1.0 + 1j * omega * float(tau_s))
    matrix = np.vstack([design * weights[:, None], math.sqrt(result.lam) * root])
    target = np.concatenate([np.concatenate([z.real, z.imag]) * weights, np.zeros(root.shape[0])])
    x = nnls(matrix, target, maxiter=50 * matrix.shape[1])[0]
    gamma = evaluate @ x[-evaluate.shape[1]:]
    peaks = find_peaks(ln_tau, gamma, signed=False, window=(0.0, math.inf))
    return max(peaks, key=lambda q: q.r_ohm).width_decades if peaks else math.nan


def shape_notes(result) -> tuple[str, ...]:
    """The low-frequency-tail note (`low_frequency_tail`: a Warburg's or a CPE's), then a
    broad-peak note per counted peak (resolved, inside the measured range; outside the tail's τ) `BROAD_FACTOR`
    times as wide as one R‖C's (`reference_width`). Empty for a signed DRT."""
    if result.signed or not result.peaks:
        return ()
    notes = []
    tail = low_frequency_tail(result.frequency, result.impedance)
    tail_from = math.inf if tail is None else tail.tau_s
    if tail is not None:
        inside = [p for p in result.peaks if p.tau_s >= tail_from]
        named = f": the peak(s) at τ = {', '.join(format_time(p.tau_s, 3) for p in inside)} are not separate arcs" if inside else ""
        if tail.warburg:
            notes.append(
                f"the low-frequency part looks like diffusion (a Warburg element): {tail.words()}, a Warburg's ω^−0.5, "
                f"where the true γ = (σ/π)√τ rises with no peak{named}; fit a Warburg (W) there, not R‖C arcs"
            )
        else:
            notes.append(
                f"the low-frequency part is a constant-phase tail: {tail.words()}, not a Warburg's ω^−0.5; "
                f"a CPE in series has −Im Z ∝ ω^−α, here α ≈ {tail.alpha:.2f}{named}; fit a CPE there (a Warburg is the case α = 0.5), not R‖C arcs"
            )
    for p in result.peaks:
        if not p.inside_window or not p.resolved or p.tau_s >= tail_from or not p.width_decades > 0:
            continue
        ref = reference_width(result, p.tau_s)
        if ref > 0 and p.width_decades >= BROAD_FACTOR * ref:
            notes.append(
                f"the peak at τ = {format_time(p.tau_s, 3)} is {p.width_decades / ref:.1f}× as wide as one R‖C's at this λ "
                f"({p.width_decades:.2f} against {ref:.2f} decades): it may hold more than one relaxation (or a distributed one, a CPE); "
                f"fit both there and compare them: two arcs (R‖C + R‖C) against one distributed arc (R‖CPE)"
            )
    return tuple(notes)
