"""Shape notes on a DRT: peaks too broad for one relaxation, and a low-frequency diffusion tail.

`shape_notes(result)` gives the sentences `DRTResult.notes` adds (docs/drt.md, "Shape notes"):

- **broad peak**: a peak inside the measured range whose FWHM is `BROAD_FACTOR` or more times
  that of one ideal R‖C at the same τ, solved at the same frequencies, weights and λ
  (`reference_width`): it may hold more than one relaxation, or a distributed one (a CPE).
- **diffusion tail**: −Im Z ∝ ω^(−1/2) over the lowest decade of the data (`diffusion_slopes`),
  the semi-infinite Warburg σ/√(jω), whose true γ = (σ/π)√τ rises with no peak: the DRT's
  peaks at those τ are not separate arcs.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ...data import format_time
from .basis import impedance_integrals, penalty_matrix
from .peaks import find_peaks

__all__ = ["BROAD_FACTOR", "WARBURG_SLOPE_RANGE", "diffusion_slopes", "diffusion_tail_tau", "reference_width", "shape_notes"]

BROAD_FACTOR = 1.4
"""A peak this many times as wide (FWHM, decades) as one R‖C's at the same λ is called broad.
SYNTHETIC, 71 points over 7 decades, noise 0.3–5 %: one R‖C 0.96–1.03×; two resolved R‖C 1
decade apart 0.97–1.16×, 0.7 decade apart up to 1.34×; a merged pair 1 decade apart 1.43–1.54×;
a ZARC α 0.8 1.3–2.0× (docs/drt.md, "Shape notes")."""

WARBURG_SLOPE_RANGE = (-0.7, -0.3)
"""d ln(−Im Z)/d ln ω of both halves of the lowest decade must lie here for a diffusion tail:
a Warburg gives −0.5, an arc below its corner +1, a series C or an R‖C past its top −1 to −0.8."""

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


def diffusion_tail_tau(result) -> float:
    """τ [s] from which ``result``'s spectrum is a diffusion tail: 1/(2π · 10 f_min), the top of
    the lowest decade, when both `diffusion_slopes` lie in `WARBURG_SLOPE_RANGE`; inf when not.
    The DRT's peaks at or beyond it are the Warburg's, not arcs (`shape_notes`, `suggest`)."""
    lo, hi = WARBURG_SLOPE_RANGE
    if not all(lo <= s <= hi for s in diffusion_slopes(result.frequency, result.impedance)):
        return math.inf
    return 1.0 / (2 * math.pi * float(result.frequency.min()) * 10.0)


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
    """The diffusion-tail note (when the lowest decade's −Im Z goes as ω^(−1/2)), then a
    broad-peak note per peak inside the measured range (outside the tail's τ) `BROAD_FACTOR`
    times as wide as one R‖C's (`reference_width`). Empty for a signed DRT."""
    if result.signed or not result.peaks:
        return ()
    notes = []
    tail_from = diffusion_tail_tau(result)
    if not math.isinf(tail_from):
        f_min = float(result.frequency.min())
        inside = [p for p in result.peaks if p.tau_s >= tail_from]
        named = f": the peak(s) at τ = {', '.join(format_time(p.tau_s, 3) for p in inside)} are not separate arcs" if inside else ""
        notes.append(
            f"the low-frequency part looks like diffusion (a Warburg element): −Im Z goes as ω^−½ below {10 * f_min:.3g} Hz, "
            f"where the true γ = (σ/π)√τ rises with no peak{named}; fit a Warburg (W) there, not R‖C arcs"
        )
    for p in result.peaks:
        if not p.inside_window or p.tau_s >= tail_from or not p.width_decades > 0:
            continue
        ref = reference_width(result, p.tau_s)
        if ref > 0 and p.width_decades >= BROAD_FACTOR * ref:
            notes.append(
                f"the peak at τ = {format_time(p.tau_s, 3)} is {p.width_decades / ref:.1f}× as wide as one R‖C's at this λ "
                f"({p.width_decades:.2f} against {ref:.2f} decades): it may hold more than one relaxation (or a distributed one, a CPE); "
                f"fit both there and compare them: two arcs (R‖C + R‖C) against one distributed arc (R‖CPE)"
            )
    return tuple(notes)
