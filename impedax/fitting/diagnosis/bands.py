"""Failing bands: where the residuals of a fit are structured beyond the noise, described in
words (docs/diagnosis.md, section 3).

Runs of one sign in Re or Im of the normalised residual e = r/σ, in frequency order; a run of
L ≥ 3 points is structured when Σe² exceeds the χ²(L) quantile 1 − `RUN_P`. Each band is
described by comparing data and model in it (resistive/capacitive/inductive, phase, slope).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..least_squares import FitResult

__all__ = ["FailingBand", "failing_bands", "format_frequency", "RUN_P"]

RUN_P = 1e-3
"""False-alarm probability of one run of one sign (χ² test of the run against the noise)."""


def format_frequency(f: float) -> str:
    """A frequency [Hz] in words: ``1.5 kHz``, ``20 mHz``."""
    for unit, scale in (("MHz", 1e6), ("kHz", 1e3), ("Hz", 1.0), ("mHz", 1e-3)):
        if f >= scale:
            return f"{f / scale:.3g} {unit}"
    return f"{f:.3g} Hz"


@dataclass(frozen=True)
class FailingBand:
    """A frequency band [Hz] where the residuals are structured, with a description."""

    f_min: float
    f_max: float
    pattern: str
    components: tuple[str, ...]
    score: float  # Σ(r/σ)² over the band divided by its point count
    data_problem: bool = False  # inside a band the KK test flags as not KK-consistent

    def as_json(self) -> dict:
        return {"f_min": self.f_min, "f_max": self.f_max, "pattern": self.pattern, "components": list(self.components), "data_problem": self.data_problem}


def _runs(sign: np.ndarray):
    """(start, stop) of maximal runs of equal sign."""
    start = 0
    for i in range(1, sign.size + 1):
        if i == sign.size or sign[i] != sign[start]:
            yield start, i
            start = i


@functools.lru_cache(maxsize=256)
def chi2_quantile(q: float, dof: int) -> float:
    """The χ²(dof) quantile q, by `scipy.special.chdtri` (the inverse survival function at
    1 − q; scipy.special imports in a fifth of the time scipy.stats takes)."""
    from scipy.special import chdtri

    return float(chdtri(dof, 1.0 - q))


def _structured_mask(e: np.ndarray, p: float = RUN_P, min_len: int = 3) -> np.ndarray:
    """Points in runs of one sign whose Σe² exceeds the χ²(L) quantile 1 − p (e sorted by f)."""
    out = np.zeros(e.size, bool)
    for i, j in _runs(np.sign(e)):
        length = j - i
        if length >= min_len and np.sum(e[i:j] ** 2) > chi2_quantile(1 - p, length):
            # trim the run's tails where the misfit is below the noise: the band is where it shows
            a, b = i, j
            while a < b and abs(e[a]) < 1:
                a += 1
            while b > a and abs(e[b - 1]) < 1:
                b -= 1
            out[a:b] = True
    return out


def _edges(f_sorted: np.ndarray, i: int, j: int) -> tuple[float, float]:
    """Band edges halfway (in log f) to the neighbouring points, clipped to the data."""
    lo = f_sorted[i] if i == 0 else math.sqrt(f_sorted[i] * f_sorted[i - 1])
    hi = f_sorted[j - 1] if j == f_sorted.size else math.sqrt(f_sorted[j - 1] * f_sorted[j])
    return float(lo), float(hi)


def _slope(f, y):
    ok = np.isfinite(y) & (y > 0)
    if ok.sum() < 3 or np.log10(f[ok].max() / f[ok].min()) < 0.5:
        return math.nan
    return float(np.polyfit(np.log10(f[ok]), np.log10(y[ok]), 1)[0])


def _where(f, i, j, n) -> str:
    lo, hi = f[i], f[j - 1]
    if i == 0 and j < n:
        return f"below {format_frequency(math.sqrt(hi * f[j]))}"
    if j == n and i > 0:
        return f"above {format_frequency(math.sqrt(lo * f[i - 1]))}"
    if i == 0 and j == n:
        return "over the whole band"
    return f"between {format_frequency(lo)} and {format_frequency(hi)}"


def _describe(f, zd, zm, i, j, n) -> str:
    """Words for how the data differ from the model over sorted points i..j-1."""
    where = _where(f, i, j, n)
    d, m = zd[i:j], zm[i:j]
    ph_d, ph_m = np.degrees(np.angle(d)), np.degrees(np.angle(m))
    # a resistive-vs-capacitive sub-band at one end of the band is the clearest story
    for flip, text in (((np.abs(ph_d) < 30) & (np.abs(ph_m) > 50), "resistive"), ((np.abs(ph_m) < 30) & (np.abs(ph_d) > 50), "capacitive")):
        idx = np.flatnonzero(flip)
        if idx.size >= 2 and (idx[0] == 0 or idx[-1] == j - i - 1):
            a, b = i + idx[0], i + idx[-1] + 1
            sub = _where(f, a, b, n)
            other = "capacitive" if text == "resistive" else "resistive"
            rest = f"; over the rest of {format_frequency(f[i])}–{format_frequency(f[j - 1])} the phases differ by up to {np.max(np.abs(ph_d - ph_m)):.0f}°" if b - a < j - i else ""
            return f"{sub} the data are {text} (phase {np.mean(ph_d[a - i:b - i]):.0f}°) while the model is {other} ({np.mean(ph_m[a - i:b - i]):.0f}°){rest}"
    mag = float(np.mean(np.abs(d) / np.abs(m)) - 1) * 100
    if np.mean(d.imag > 0) >= 0.5 and np.mean(d.imag) > np.mean(m.imag) and np.mean(m.imag > 0) < 0.5:
        return f"positive Z'' {where} the model cannot make: the data turn inductive (phase up to {ph_d.max():+.0f}°)"
    pd, pm = float(np.mean(ph_d)), float(np.mean(ph_m))
    parts = []
    if abs(pd) < 30 and abs(pm) > 50:
        parts.append(f"{where} the data are resistive (phase {pd:.0f}°) while the model is capacitive ({pm:.0f}°)")
    elif abs(pm) < 30 and abs(pd) > 50:
        parts.append(f"{where} the data are capacitive (phase {pd:.0f}°) while the model is resistive ({pm:.0f}°)")
    elif abs(pd - pm) >= 2:
        kind = "more resistive" if abs(pd) < abs(pm) else "more capacitive"
        parts.append(f"{where} the data are {kind} than the model (phase {pd:.0f}° vs {pm:.0f}°)")
    else:
        parts.append(f"{where} the data and the model differ in magnitude at the same phase")
    if abs(mag) >= 1:
        parts.append(f"|Z| is {abs(mag):.2g} % {'above' if mag > 0 else 'below'} the model")
    sd, sm = _slope(f[i:j], -d.imag), _slope(f[i:j], -m.imag)
    if np.isfinite(sd) and np.isfinite(sm) and abs(sd - sm) > 0.15:
        parts.append(f"−Z'' falls as f^{sd:.2f} where the model's falls as f^{sm:.2f}")
    # a band that holds the model's −Z'' peak with a lower, wider data peak: a depressed arc
    k_m = int(np.argmax(-zm.imag))
    if i < k_m < j - 1 and -zm.imag[k_m] > 0 and np.max(-d.imag) < 0.98 * -zm.imag[k_m]:
        drop = (1 - np.max(-d.imag) / -zm.imag[k_m]) * 100
        return f"the model's arc is too symmetric: the data are depressed (peak −Z'' {drop:.2g} % lower, spread over a wider band) {where}; " + "; ".join(parts[1:] or parts)
    return "; ".join(parts)


def failing_bands(fit: FitResult, noise, *, kk_bad_bands: Sequence[tuple[float, float]] = (), p: float = RUN_P) -> tuple[FailingBand, ...]:
    """Bands where the residuals of ``fit`` are structured relative to ``noise`` (relative σ per
    component, scalar or per point): runs of one sign in Re or Im with Σ(r/σ)² above the
    χ²(L) quantile 1 − ``p``; gaps of one point are closed. Each band gets a description."""
    order = np.argsort(fit.frequency)
    f = fit.frequency[order]
    sigma = np.broadcast_to(np.asarray(noise, float), fit.frequency.shape)[order]
    r = fit.residuals[order]
    e_re, e_im = r.real / sigma, r.imag / sigma
    m_re, m_im = _structured_mask(e_re, p), _structured_mask(e_im, p)
    mask = m_re | m_im
    for k in range(1, mask.size - 1):  # close single-point gaps
        if not mask[k] and mask[k - 1] and mask[k + 1]:
            mask[k] = True
    bands = []
    zd, zm = fit.z_data[order], fit.z_model[order]
    for i, j in _runs(mask.astype(int)):
        if not mask[i]:
            continue
        lo, hi = _edges(f, i, j)
        comps = tuple(c for c, m in (("real", m_re), ("imag", m_im)) if m[i:j].any())
        score = float(np.mean(e_re[i:j] ** 2 + e_im[i:j] ** 2) / 2)
        data_problem = any(blo <= f[i] * 1.0001 and f[j - 1] <= bhi * 1.0001 for blo, bhi in kk_bad_bands)
        bands.append(FailingBand(lo, hi, _describe(f, zd, zm, i, j, f.size), comps, score, data_problem))
    return tuple(bands)
