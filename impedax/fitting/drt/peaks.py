"""Peaks of a DRT: where they are, the resistance under each, their width and uncertainty."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Peak", "find_peaks", "split_peaks", "counted_peaks", "RESOLVED_SIGMAS", "ROUNDOFF_SHARE", "below_roundoff"]

_LN10 = math.log(10.0)

RESOLVED_SIGMAS = 2.0
"""A DRT peak is resolved (told from zero) when its R is at least this many of its standard
deviations under the credible band (``Peak.r_ohm_sd``) from zero: a peak of R ≈ 0.3 ± 0.5 Ω is
a ripple of the regularised solution, not a relaxation the data show (`evidence.is_resolved`).
On one SYNTHETIC R‖C at 5 % noise, 2 of 10 seeds showed such a second peak (9.4 ± 8.9 Ω at
50 s); REAL Parstat/PowerSuite files showed peaks of 3.8 ± 34 mΩ."""

ROUNDOFF_SHARE = 1e-6
"""A DRT whose whole ∫|γ| d ln τ is below this share of max|Z| has no peaks: no instrument
resolves a polarisation of 10⁻⁶ of |Z| (the best are accurate to ~0.1 %), so such a γ is the
solve's round-off on noise-free data (a pure resistor's 100 Ω gave a "peak" of 60 nΩ), and the
relative cut-offs, which scale with ∫|γ|, would count it (docs/drt.md, "Peaks")."""


def below_roundoff(ln_tau: np.ndarray, gamma: np.ndarray, z_ref: float) -> bool:
    """∫|γ| d ln τ (trapezoid on the grid ``ln_tau``) < `ROUNDOFF_SHARE` · ``z_ref`` (max|Z|):
    the spectrum is flat, a resistor, and γ holds no peak."""
    return float(np.trapezoid(np.abs(gamma), ln_tau)) < ROUNDOFF_SHARE * z_ref


@dataclass(frozen=True)
class Peak:
    """One peak of γ(τ).

    ``tau_s``: τ at the maximum [s]; ``r_ohm``: ∫ γ d ln τ between the valleys either side [Ω]
    (negative for a negative peak of a signed DRT); ``width_decades``: full width at half
    maximum in decades of τ; ``gamma_max_ohm``: γ at the peak [Ω];
    ``log10_tau_sd``/``r_ohm_sd``: standard deviations under the credible band's Gaussian;
    ``inside_window``: τ lies within 1/(2π f_max)..1/(2π f_min), the measured range;
    ``resolved``: |R| ≥ `RESOLVED_SIGMAS` × ``r_ohm_sd`` (True without a standard deviation):
    a peak that is not is listed but flagged, and not counted (`counted_peaks`).
    """

    tau_s: float
    r_ohm: float
    width_decades: float
    gamma_max_ohm: float
    log10_tau_sd: float = float("nan")
    r_ohm_sd: float = float("nan")
    inside_window: bool = True
    resolved: bool = True

    @property
    def frequency_hz(self) -> float:
        """The characteristic frequency 1/(2πτ) [Hz]."""
        return 1.0 / (2.0 * math.pi * self.tau_s)


def _maxima(values: np.ndarray, min_height: float) -> list[int]:
    """Interior local maxima of ``values`` at or above ``min_height`` (> 0)."""
    return [k for k in range(1, values.size - 1) if values[k] > values[k - 1] and values[k] >= values[k + 1] and values[k] >= min_height and values[k] > 0]


def _split(values: np.ndarray, maxima: list[int]) -> list[tuple[int, int, int]]:
    """(k, lo, hi) per maximum: the region between neighbouring maxima is split at its lowest
    point (or where the values end, for the outermost ones)."""
    out = []
    for i, k in enumerate(maxima):
        lo = 0 if i == 0 else maxima[i - 1] + int(np.argmin(values[maxima[i - 1] : k + 1]))
        hi = values.size - 1 if i == len(maxima) - 1 else k + int(np.argmin(values[k : maxima[i + 1] + 1]))
        out.append((k, lo, hi))
    return out


RESOLVED_DEPTH = 0.1
"""A peak is resolved when γ falls to this fraction of its maximum or below on both sides of
it (at the minima towards its neighbours, or at the ends of the τ axis)."""

RESOLVED_SHARE = 0.5
"""A resolved peak needs this share of ``min_rel_resistance`` (5 % of ∫|γ| by default): the
side lobes a regularised ZARC (α 0.9) or HN peak leaves beside itself, resolved by a deep
minimum, hold up to 3.7 % (docs/drt.md, "Peaks")."""

MERGE_DECADES = 2.0
"""A peak below the cut-off joins the neighbouring peak within this many decades of it (its
area counts in that peak's R: the side lobes a regularised peak leaves sit 0.7–1.6 decades
from it, and noise splits a small arc into halves 1.5 decades apart); a farther one is
dropped, its area given to no peak and reported (`split_peaks`)."""


def _windows(values: np.ndarray, ln_tau: np.ndarray, min_height: float, min_resistance: float):
    """(kept, dropped): lists of (k, lo, hi) — the maximum and the window [lo, hi] whose area
    ∫ max(values, 0) d ln τ is the peak's R. Windows start between neighbouring maxima, split
    at the lowest point. A window is kept when its area is ≥ ``min_resistance``, or ≥
    `RESOLVED_SHARE` of it when the peak is resolved (`RESOLVED_DEPTH`). Otherwise, smallest
    first, it joins the adjacent window on the side of the higher minimum (else the other)
    when that one's maximum is within `MERGE_DECADES`, or it is dropped: then no other window
    grows over it. A DRT regularised under γ ≥ 0 rings beside broad (CPE-like) peaks and at
    the ends of the τ range; those lobes are not relaxations, and they join their peak."""
    positive = np.maximum(values, 0.0)
    maxima = _maxima(values, min_height)
    parts = [list(p) for p in _split(positive, maxima)]
    alive = [True] * len(parts)

    def area(p) -> float:
        return float(np.trapezoid(positive[p[1] : p[2] + 1], ln_tau[p[1] : p[2] + 1]))

    def keeps(p) -> bool:
        a = area(p)
        resolved = max(positive[p[1]], positive[p[2]]) <= RESOLVED_DEPTH * positive[p[0]]
        return a >= min_resistance or (resolved and a >= RESOLVED_SHARE * min_resistance)

    reach = MERGE_DECADES * _LN10
    while True:
        failing = [i for i, p in enumerate(parts) if alive[i] and not keeps(p)]
        if not failing:
            break
        i = min(failing, key=lambda i: area(parts[i]))
        k, lo, hi = parts[i]
        # the live neighbours (a dropped window between blocks the way), higher minimum first
        sides = [(positive[lo], j) for j in (i - 1,) if j >= 0 and alive[j]] + [(positive[hi], j) for j in (i + 1,) if j < len(parts) and alive[j]]
        sides.sort(key=lambda side: -side[0])
        target = next((j for _, j in sides if abs(ln_tau[parts[j][0]] - ln_tau[k]) <= reach), None)
        if target is None:
            alive[i] = False
            continue
        parts[target] = [parts[target][0], min(lo, parts[target][1]), max(hi, parts[target][2])]
        parts.pop(i)
        alive.pop(i)
    return [tuple(p) for p, a in zip(parts, alive) if a], [tuple(p) for p, a in zip(parts, alive) if not a]


def _vertex(ln_tau, values, k) -> float:
    """ln τ of the maximum: the vertex of the parabola through grid points k−1, k, k+1."""
    y0, y1, y2 = values[k - 1], values[k], values[k + 1]
    denom = y0 - 2 * y1 + y2
    h = ln_tau[k] - ln_tau[k - 1]
    shift = 0.5 * h * (y0 - y2) / denom if denom < 0 else 0.0
    return float(ln_tau[k] + min(max(shift, -h / 2), h / 2))


def _vertices(ln_tau, rows, k) -> np.ndarray:
    """`_vertex` of each row of ``rows`` (S, K) at its index ``k`` (S,): the draws' peak τ
    between grid points, as the peak's own. On the grid alone (20 points a decade) the draws of
    a clean spectrum's peak would all fall on one point and ``log10_tau_sd`` be exactly 0, printed
    "±0.00 dec"."""
    k = np.asarray(k)
    inner = (k > 0) & (k < rows.shape[1] - 1)
    at = np.clip(k, 1, rows.shape[1] - 2)
    picked = np.arange(rows.shape[0])
    y0, y1, y2 = rows[picked, at - 1], rows[picked, at], rows[picked, at + 1]
    denom = y0 - 2 * y1 + y2
    h = ln_tau[at] - ln_tau[at - 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        shift = np.where(inner & (denom < 0), 0.5 * h * (y0 - y2) / np.where(denom < 0, denom, -1.0), 0.0)
    return ln_tau[k] + np.clip(shift, -h / 2, h / 2)


def _fwhm(ln_tau, values, k, lo, hi) -> float:
    half = values[k] / 2.0

    def crossing(indices):
        prev = k
        for i in indices:
            if values[i] <= half:
                # linear interpolation between prev (above half) and i (at or below)
                t = (values[prev] - half) / max(values[prev] - values[i], 1e-300)
                return ln_tau[prev] + t * (ln_tau[i] - ln_tau[prev])
            prev = i
        return ln_tau[indices[-1]] if len(indices) else ln_tau[k]

    left = crossing(list(range(k - 1, lo - 1, -1)))
    right = crossing(list(range(k + 1, hi + 1)))
    return float(right - left) / _LN10


def _peak(ln_tau, gamma, sign, k, lo, hi, samples, window) -> Peak:
    """The `Peak` of the maximum k whose window is [lo, hi] (``sign`` −1: a negative peak)."""
    values = sign * gamma
    r = float(np.trapezoid(np.maximum(values[lo : hi + 1], 0.0), ln_tau[lo : hi + 1]))
    tau_sd = r_sd = float("nan")
    if samples is not None and samples.shape[0] > 1:
        part = sign * samples[:, lo : hi + 1]
        tau_sd = float(np.std(_vertices(ln_tau, sign * samples, lo + np.argmax(part, axis=1))) / _LN10)
        r_sd = float(np.std(np.trapezoid(part, ln_tau[lo : hi + 1], axis=1)))
    tau = math.exp(_vertex(ln_tau, values, k))
    return Peak(
        tau_s=tau, r_ohm=sign * r, width_decades=_fwhm(ln_tau, values, k, lo, hi), gamma_max_ohm=float(gamma[k]),
        log10_tau_sd=tau_sd, r_ohm_sd=r_sd, inside_window=bool(window[0] <= tau <= window[1]), resolved=_told_from_zero(sign * r, r_sd),
    )


def _told_from_zero(r_ohm: float, r_ohm_sd: float) -> bool:
    """|R| ≥ `RESOLVED_SIGMAS` × its sd (True when the sd is nan: nothing says otherwise)."""
    return not abs(r_ohm) < RESOLVED_SIGMAS * r_ohm_sd


def counted_peaks(peaks) -> tuple[Peak, ...]:
    """The peaks a report counts as relaxations of the data: resolved (R told from zero,
    `RESOLVED_SIGMAS`) and inside the measured τ window 1/(2π f_max)..1/(2π f_min); the others
    stay listed, flagged (docs/drt.md, "Peaks")."""
    return tuple(p for p in peaks if p.resolved and p.inside_window)


def split_peaks(ln_tau, gamma, *, signed, window, samples=None, min_rel_height=0.02, min_rel_resistance=0.1) -> tuple[tuple[Peak, ...], tuple[Peak, ...]]:
    """(peaks, dropped) of γ on the grid ``ln_tau`` (ascending): positive peaks and, when
    ``signed``, negative ones. A peak needs γ_max ≥ ``min_rel_height``·max|γ| and
    |R| ≥ ``min_rel_resistance``·∫|γ| d ln τ, or half that when resolved (`_windows`;
    docs/drt.md, "Peaks"); R = ∫ γ d ln τ over its window, from the minimum towards the
    previous peak to the minimum towards the next. ``dropped``: the peaks below the cut-off
    whose area no reported peak holds (farther than `MERGE_DECADES` from any), each with the
    area of its own window; empty for a signed DRT, where every peak's R is its share of the
    whole τ axis (a single peak's: all of it). ``samples`` (S, K): draws of γ for the peaks' standard deviations.
    ``window``: the measured (τ_min, τ_max). Sorted by τ."""
    ln_tau = np.asarray(ln_tau, float)
    gamma = np.asarray(gamma, float)
    total = float(np.trapezoid(np.abs(gamma), ln_tau))
    peaks, dropped = [], []
    for sign in ((1.0, -1.0) if signed else (1.0,)):
        kept, lost = _windows(sign * gamma, ln_tau, min_rel_height * float(np.max(np.abs(gamma))), min_rel_resistance * total)
        peaks += [_peak(ln_tau, gamma, sign, k, lo, hi, samples, window) for k, lo, hi in kept]
        dropped += [_peak(ln_tau, gamma, sign, k, lo, hi, None, window) for k, lo, hi in lost]
    peaks.sort(key=lambda p: p.tau_s)
    dropped.sort(key=lambda p: p.tau_s)
    if signed:
        dropped = []
    if signed and len(peaks) > 1:
        # a signed solution rings: each peak is flanked by lobes of the other sign that belong to
        # it, so R is the signed area of its share of the τ axis (split at the smallest |γ|
        # between neighbouring peaks); a lobe whose share is below the threshold is dropped
        while len(peaks) > 1:
            centres = [int(np.argmin(np.abs(ln_tau - math.log(p.tau_s)))) for p in peaks]
            cuts = [0] + [a + int(np.argmin(np.abs(gamma[a : b + 1]))) for a, b in zip(centres[:-1], centres[1:])] + [gamma.size - 1]
            shares = [float(np.trapezoid(gamma[lo : hi + 1], ln_tau[lo : hi + 1])) for lo, hi in zip(cuts[:-1], cuts[1:])]
            smallest = int(np.argmin(np.abs(shares)))
            if abs(shares[smallest]) >= min_rel_resistance * total:
                peaks = [dataclasses.replace(p, r_ohm=r, resolved=_told_from_zero(r, p.r_ohm_sd)) for p, r in zip(peaks, shares)]
                break
            peaks.pop(smallest)
    if signed and len(peaks) == 1:
        # ... and a single peak's share is the whole axis, its lobes included (the area
        # of its positive lobe alone is 128.4 Ω for an exact 100 Ω ∥ 100 µF arc whose R_pol reads
        # 99.87 Ω, and would be passed on as the suggested fit's R1)
        (p,) = peaks
        r = float(np.trapezoid(gamma, ln_tau))
        peaks = [dataclasses.replace(p, r_ohm=r, resolved=_told_from_zero(r, p.r_ohm_sd))]
    return tuple(peaks), tuple(dropped)


def find_peaks(ln_tau, gamma, *, signed, window, samples=None, min_rel_height=0.02, min_rel_resistance=0.1) -> tuple[Peak, ...]:
    """The peaks of `split_peaks` (without the dropped ones)."""
    return split_peaks(ln_tau, gamma, signed=signed, window=window, samples=samples, min_rel_height=min_rel_height, min_rel_resistance=min_rel_resistance)[0]
