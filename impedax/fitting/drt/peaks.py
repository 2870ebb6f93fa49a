"""Peaks of a DRT: where they are, the resistance under each, their width and uncertainty."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Peak", "find_peaks"]

_LN10 = math.log(10.0)


@dataclass(frozen=True)
class Peak:
    """One peak of γ(τ).

    ``tau_s``: τ at the maximum [s]; ``r_ohm``: ∫ γ d ln τ between the valleys either side [Ω]
    (negative for a negative peak of a signed DRT); ``width_decades``: full width at half
    maximum in decades of τ; ``gamma_max_ohm``: γ at the peak [Ω];
    ``log10_tau_sd``/``r_ohm_sd``: standard deviations under the credible band's Gaussian;
    ``inside_window``: τ lies within 1/(2π f_max)..1/(2π f_min), the measured range.
    """

    tau_s: float
    r_ohm: float
    width_decades: float
    gamma_max_ohm: float
    log10_tau_sd: float = float("nan")
    r_ohm_sd: float = float("nan")
    inside_window: bool = True

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


def _windows(values: np.ndarray, ln_tau: np.ndarray, min_height: float, min_resistance: float):
    """Peaks that hold at least ``min_resistance`` each: the smallest of the local maxima is
    dropped (its area joins its neighbours) until every remaining one does. A DRT regularised
    under γ ≥ 0 rings beside broad (CPE-like) peaks and at the ends of the τ range; those
    side lobes hold a few percent of R_pol and are not relaxations."""
    maxima = _maxima(values, min_height)
    while maxima:
        parts = _split(np.maximum(values, 0.0), maxima)
        areas = [float(np.trapezoid(np.maximum(values[lo : hi + 1], 0.0), ln_tau[lo : hi + 1])) for _, lo, hi in parts]
        smallest = int(np.argmin(areas))
        if areas[smallest] >= min_resistance:
            return parts
        maxima.pop(smallest)
    return []


def _vertex(ln_tau, values, k) -> float:
    """ln τ of the maximum: the vertex of the parabola through grid points k−1, k, k+1."""
    y0, y1, y2 = values[k - 1], values[k], values[k + 1]
    denom = y0 - 2 * y1 + y2
    h = ln_tau[k] - ln_tau[k - 1]
    shift = 0.5 * h * (y0 - y2) / denom if denom < 0 else 0.0
    return float(ln_tau[k] + min(max(shift, -h / 2), h / 2))


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


def find_peaks(ln_tau, gamma, *, signed, window, samples=None, min_rel_height=0.02, min_rel_resistance=0.1) -> tuple[Peak, ...]:
    """Peaks of γ on the grid ``ln_tau`` (ascending), positive ones and, when ``signed``, negative
    ones. A peak needs γ_max ≥ ``min_rel_height``·max|γ| and |R| ≥ ``min_rel_resistance``·∫|γ|
    (10 %: the side lobes and tail ripples of a regularised broad peak hold up to ≈ 9 %, docs/drt.md); its R is
    the area from the lowest point towards the previous peak to the lowest towards the next.
    ``samples`` (S, K): draws of γ used for the peaks' standard deviations. ``window``: the
    measured (τ_min, τ_max). Sorted by τ."""
    ln_tau = np.asarray(ln_tau, float)
    gamma = np.asarray(gamma, float)
    total = float(np.trapezoid(np.abs(gamma), ln_tau))
    peaks = []
    for sign in ((1.0, -1.0) if signed else (1.0,)):
        values = sign * gamma
        for k, lo, hi in _windows(values, ln_tau, min_rel_height * float(np.max(np.abs(gamma))), min_rel_resistance * total):
            r = float(np.trapezoid(np.maximum(values[lo : hi + 1], 0.0), ln_tau[lo : hi + 1]))
            tau_sd = r_sd = float("nan")
            if samples is not None and samples.shape[0] > 1:
                part = sign * samples[:, lo : hi + 1]
                tau_sd = float(np.std(ln_tau[lo : hi + 1][np.argmax(part, axis=1)]) / _LN10)
                r_sd = float(np.std(np.trapezoid(part, ln_tau[lo : hi + 1], axis=1)))
            tau = math.exp(_vertex(ln_tau, values, k))
            peaks.append(
                Peak(
                    tau_s=tau,
                    r_ohm=sign * r,
                    width_decades=_fwhm(ln_tau, values, k, lo, hi),
                    gamma_max_ohm=float(gamma[k]),
                    log10_tau_sd=tau_sd,
                    r_ohm_sd=r_sd,
                    inside_window=bool(window[0] <= tau <= window[1]),
                )
            )
    peaks.sort(key=lambda p: p.tau_s)
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
                peaks = [dataclasses.replace(p, r_ohm=r) for p, r in zip(peaks, shares)]
                break
            peaks.pop(smallest)
    return tuple(peaks)
