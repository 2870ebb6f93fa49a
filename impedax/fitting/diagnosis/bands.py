"""Failing bands: where the residuals of a fit are structured beyond the noise, described in
words (docs/diagnosis.md, section 3).

Runs of one sign in Re or Im of the normalised residual e = r/σ, in frequency order; a run of
L ≥ 3 points is structured when Σe² exceeds the χ²(L) quantile 1 − `RUN_P`. Each band is
described by comparing data and model in it (resistive/capacitive/inductive, phase, slope).
A band wider than `WIDE_DECADES`, or one where the phase or |Z| misfit changes sign, is
described by its largest deviations and where they are, not by band averages (which cancel).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ...data import format_frequency  # (re-exported: this module's own copy wrote REAL test_data.txt's 0.99991 mHz as "0.001 Hz")
from ..least_squares import FitResult

__all__ = ["FailingBand", "failing_bands", "format_frequency", "RUN_P"]

RUN_P = 1e-3
"""False-alarm probability of one run of one sign (χ² test of the run against the noise)."""

WIDE_DECADES = 1.5
"""A band spanning more decades than this is described by its extremes unless its misfit is uniform."""
PHASE_MIN_DEG = 2.0  # a phase difference worth a word [°]
MAGNITUDE_MIN_PERCENT = 1.0  # a |Z| difference worth a word [%]


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
    if format_frequency(lo) == format_frequency(hi):  # (one point: "at 56.2 Hz", not "between 56.2 Hz and 56.2 Hz")
        return f"at {format_frequency(lo)}"
    return f"between {format_frequency(lo)} and {format_frequency(hi)}"


def _power_law(what: str, exponent: float) -> str:
    """``−Z'' falls as f^-0.50`` / ``rises as f^0.72``: the verb follows the sign of the log-log
    slope d log y / d log f (positive: y grows with frequency)."""
    if abs(exponent) < 0.05:
        return f"{what} is flat (f^{exponent:.2f})"
    return f"{what} {'rises' if exponent > 0 else 'falls'} as f^{exponent:.2f}"


def _slopes(f, d, m) -> list[str]:
    """The power laws of the data's and the model's −Z'' when they differ by more than 0.15."""
    sd, sm = _slope(f, -d.imag), _slope(f, -m.imag)
    if np.isfinite(sd) and np.isfinite(sm) and abs(sd - sm) > 0.15:
        return [_power_law("−Z''", sd) + " where " + _power_law("the model's", sm)]
    return []


def _deg(x: float) -> str:
    """A phase in whole degrees, signed (``+28``, ``-2``, ``0``: no ``-0``)."""
    v = int(round(float(x)))
    return f"{v:+d}" if v else "0"


def _percent(x: float) -> str:
    """A percentage: two significant figures below 100, whole numbers above (not ``3e+02``)."""
    x = abs(float(x))
    return f"{x:.0f}" if x >= 100 else f"{x:.2g}"


def _span(f, a: int, b: int, i: int, j: int) -> str:
    """Where sorted points a..b-1 lie inside the band i..j-1: above/below the midpoint (in log f)
    to the band's next point when they reach an end of the band, else between their ends."""
    if b == j and a > i:
        return f"above {format_frequency(math.sqrt(f[a] * f[a - 1]))}"
    if a == i and b < j:
        return f"below {format_frequency(math.sqrt(f[b - 1] * f[b]))}"
    if a == i and b == j:
        return "throughout"
    return f"between {format_frequency(f[a])} and {format_frequency(f[b - 1])}" if b - a > 1 else f"at {format_frequency(f[a])}"


def _inductive(ph_d, ph_m) -> np.ndarray:
    """Points where the data are inductive (phase > 0) and the model is not: the runs of such
    points that hold at least one point `PHASE_MIN_DEG` above the model (not noise about 0°)."""
    loose = (ph_d > 0) & (ph_m <= 0)
    out = np.zeros(loose.size, bool)
    for a, b in _runs(loose.astype(int)):
        if loose[a] and np.any(ph_d[a:b] - ph_m[a:b] >= PHASE_MIN_DEG):
            out[a:b] = True
    return out


def _inductive_words(f, ind, i: int, j: int) -> str:
    """Where the inductive points (a mask over the band i..j-1) are, in words."""
    idx = np.flatnonzero(ind)
    if idx.size == idx[-1] - idx[0] + 1:  # one run
        return f"inductive {_span(f, i + idx[0], i + idx[-1] + 1, i, j)}"
    return f"inductive at {idx.size} points between {format_frequency(f[i + idx[0]])} and {format_frequency(f[i + idx[-1]])}"


def _needs_extremes(f, dph, rel, ind, i: int, j: int) -> bool:
    """True when band averages would misdescribe the band: it is wide (> `WIDE_DECADES`) or its
    phase or |Z| misfit changes sign, or it turns inductive, and the misfit is not uniform."""
    wide = math.log10(f[j - 1] / f[i]) > WIDE_DECADES
    oscillates = (dph.max() >= PHASE_MIN_DEG and dph.min() <= -PHASE_MIN_DEG) or (rel.max() >= MAGNITUDE_MIN_PERCENT and rel.min() <= -MAGNITUDE_MIN_PERCENT)
    uniform = (
        not ind.any()
        and np.max(np.abs(dph - dph.mean())) <= max(PHASE_MIN_DEG, 0.5 * abs(dph.mean()))
        and np.max(np.abs(rel - rel.mean())) <= max(MAGNITUDE_MIN_PERCENT, 0.5 * abs(rel.mean()))
    )
    return (wide or oscillates or bool(ind.any())) and not uniform


def _magnitude_extremes(fb, rel) -> str:
    """``|Z| is up to N % above the model near F and up to M % below near G``: the |Z| ratio at
    its extremes over the points ``fb`` (each side that passes `MAGNITUDE_MIN_PERCENT`, the
    larger first); empty when neither side does."""
    kp, kn = int(np.argmax(rel)), int(np.argmin(rel))
    sides = sorted([(kp, "above")] * bool(rel[kp] >= MAGNITUDE_MIN_PERCENT) + [(kn, "below")] * bool(rel[kn] <= -MAGNITUDE_MIN_PERCENT), key=lambda s: -abs(rel[s[0]]))
    if not sides:
        return ""
    k, side = sides[0]
    text = f"|Z| is up to {_percent(rel[k])} % {side} the model near {format_frequency(fb[k])}"
    if len(sides) > 1:
        k2, side2 = sides[1]
        text += f" and up to {_percent(rel[k2])} % {side2} near {format_frequency(fb[k2])}"
    return text


def _extremes(f, d, m, ph_d, ph_m, dph, rel, ind, i: int, j: int) -> str:
    """The band by its largest deviations: the phase difference and the |Z| ratio at their
    extremes (each side that passes `PHASE_MIN_DEG` / `MAGNITUDE_MIN_PERCENT`, the larger first),
    with the frequencies, and where the data turn inductive."""
    fb = f[i:j]
    parts = []
    kp, kn = int(np.argmax(dph)), int(np.argmin(dph))
    sides = sorted([(kp, "above")] * bool(dph[kp] >= PHASE_MIN_DEG) + [(kn, "below")] * bool(dph[kn] <= -PHASE_MIN_DEG), key=lambda s: -abs(dph[s[0]]))
    inductive = _inductive_words(f, ind, i, j) if ind.any() else ""
    if sides:
        k, side = sides[0]
        note = f"{_deg(ph_d[k])}° vs {_deg(ph_m[k])}°" + (f"; {inductive}" if inductive and ind[k] else "")
        text = f"the data's phase is up to {abs(dph[k]):.0f}° {side} the model's near {format_frequency(fb[k])} ({note})"
        if len(sides) > 1:
            k2, side2 = sides[1]
            text += f" and up to {abs(dph[k2]):.0f}° {side2} near {format_frequency(fb[k2])}"
        parts.append(text)
        if inductive and not ind[k]:
            parts.append(f"the data turn {inductive} (phase up to {_deg(ph_d[ind].max())}°)")
    elif inductive:
        parts.append(f"the data turn {inductive} (phase up to {_deg(ph_d[ind].max())}°)")
    magnitude = _magnitude_extremes(fb, rel)
    if magnitude:
        parts.append(magnitude)
    if not parts:  # structured in Re/Im but below both thresholds in phase and |Z|
        k = int(np.argmax(np.abs(rel)))
        parts.append(f"the data and the model differ by less than {PHASE_MIN_DEG:.0f}° in phase and {MAGNITUDE_MIN_PERCENT:.0f} % in |Z| (|Z| {rel[k]:+.2g} % near {format_frequency(fb[k])})")
    if math.log10(fb[-1] / fb[0]) <= WIDE_DECADES:  # over a narrow band one power law still says something
        parts.extend(_slopes(fb, d, m))
    return "; ".join(parts)


def _rest_of_flip(f, dph, rel, i: int, j: int, a: int, b: int) -> str:
    """Words for the band i..j-1 outside its resistive-vs-capacitive end a..b-1 (sorted
    points): the largest phase difference there and where; where the phases then agree within
    `PHASE_MIN_DEG` (a run reaching the band's other end: the largest difference is often the
    point next to the end, the flip's own tail); and the |Z| extremes there
    (`_magnitude_extremes`), which the flip's words do not give: on the SYNTHETIC Sirin
    remainder fitted by ``C_gap`` the phases agree within 2° above 562 Hz while |Z| is 2.3× the
    model's, the misfit that sets C_gap."""
    others = np.ones(j - i, bool)
    others[a - i : b - i] = False
    idx = np.flatnonzero(others)  # one run: the flip sits at an end of the band
    k = int(idx[np.argmax(np.abs(dph[idx]))])
    text = f"over the rest of {format_frequency(f[i])}–{format_frequency(f[j - 1])} the phases differ by up to {abs(dph[k]):.0f}° (near {format_frequency(f[i + k])})"
    if abs(dph[k]) >= PHASE_MIN_DEG:
        close = np.abs(dph[idx]) < PHASE_MIN_DEG
        far = close if idx[0] == 0 else close[::-1]  # from the band's other end inwards
        n_close = int(np.argmin(far)) if not far.all() else far.size
        if n_close >= 2:
            lo, hi = (idx[-n_close], idx[-1] + 1) if idx[0] > 0 else (idx[0], idx[0] + n_close)
            text += f" and by less than {PHASE_MIN_DEG:.0f}° {_span(f, i + lo, i + hi, i, j)}"
    magnitude = _magnitude_extremes(f[i:j][idx], rel[idx])
    return text + (f", and {magnitude}" if magnitude else "")


def _describe(f, zd, zm, i, j, n) -> str:
    """Words for how the data differ from the model over sorted points i..j-1: a resistive or
    capacitive end; else a mostly inductive band; else, for a band wider than `WIDE_DECADES` or
    whose misfit changes sign (unless the misfit is uniform), its largest phase and |Z|
    deviations and where they are (`_extremes`); else band averages of phase and |Z| and the
    power laws of −Z''."""
    where = _where(f, i, j, n)
    d, m = zd[i:j], zm[i:j]
    ph_d, ph_m = np.degrees(np.angle(d)), np.degrees(np.angle(m))
    dph = np.degrees(np.angle(d / m))  # data's phase minus the model's, wrapped to (−180°, 180°]
    rel = (np.abs(d) / np.abs(m) - 1) * 100  # |Z_data| above |Z_model| [%]
    ind = _inductive(ph_d, ph_m)
    wide = math.log10(f[j - 1] / f[i]) > WIDE_DECADES
    # a resistive-vs-capacitive sub-band at one end of the band is the clearest story (capacitive:
    # phase below −50°; an inductive phase above +50° is not capacitive and is described below)
    for flip, text in (((np.abs(ph_d) < 30) & (ph_m < -50), "resistive"), ((np.abs(ph_m) < 30) & (ph_d < -50), "capacitive")):
        idx = np.flatnonzero(flip)
        if idx.size >= 2 and (idx[0] == 0 or idx[-1] == j - i - 1):
            a, b = i + idx[0], i + idx[-1] + 1
            sub = _where(f, a, b, n)
            other = "capacitive" if text == "resistive" else "resistive"
            rest = ""
            if b - a < j - i:  # the rest of the band: its phase and |Z| extremes, and where
                rest = "; " + _rest_of_flip(f, dph, rel, i, j, a, b)
            outside = ind.copy()
            outside[a - i : b - i] = False
            if wide and outside.any():  # an inductive end the flip does not cover
                rest += f"; the data turn {_inductive_words(f, outside, i, j)} (phase up to {_deg(ph_d[outside].max())}°)"
            return f"{sub} the data are {text} (phase {np.mean(ph_d[a - i:b - i]):.0f}°) while the model is {other} ({np.mean(ph_m[a - i:b - i]):.0f}°){rest}"
    mag = float(np.mean(np.abs(d) / np.abs(m)) - 1) * 100
    if np.mean(d.imag > 0) >= 0.5 and np.mean(d.imag) > np.mean(m.imag) and np.mean(m.imag > 0) < 0.5:
        up = np.flatnonzero(d.imag > 0)
        if wide and up.size == up[-1] - up[0] + 1:  # say where, not "over the whole band"
            where = _where(f, i + up[0], i + up[-1] + 1, n)
        return f"positive Z'' {where} the model cannot make: the data turn inductive (phase up to {ph_d.max():+.0f}°)"
    # a band that holds the model's −Z'' peak with a lower, wider data peak: a depressed arc
    k_m = int(np.argmax(-zm.imag))
    depressed = ""
    if i < k_m < j - 1 and -zm.imag[k_m] > 0 and np.max(-d.imag) < 0.98 * -zm.imag[k_m]:
        drop = (1 - np.max(-d.imag) / -zm.imag[k_m]) * 100
        depressed = f"the model's arc is too symmetric: the data are depressed (peak −Z'' {drop:.2g} % lower, spread over a wider band)"
    pd, pm = float(np.mean(ph_d)), float(np.mean(ph_m))
    same_phase = abs(pd - pm) < PHASE_MIN_DEG and not (abs(pd) < 30 and pm < -50) and not (abs(pm) < 30 and pd < -50)
    if _needs_extremes(f, dph, rel, ind, i, j) or (same_phase and (abs(mag) < MAGNITUDE_MIN_PERCENT or np.max(np.abs(dph)) >= PHASE_MIN_DEG)):
        # averages over a wide or sign-changing band cancel: say where the largest deviations are
        return "; ".join(filter(None, (depressed, _extremes(f, d, m, ph_d, ph_m, dph, rel, ind, i, j))))
    parts = []
    if abs(pd) < 30 and pm < -50:
        parts.append(f"{where} the data are resistive (phase {pd:.0f}°) while the model is capacitive ({pm:.0f}°)")
    elif abs(pm) < 30 and pd < -50:
        parts.append(f"{where} the data are capacitive (phase {pd:.0f}°) while the model is resistive ({pm:.0f}°)")
    elif abs(pd - pm) >= PHASE_MIN_DEG:
        if max(pd, pm) > 0:  # an inductive (positive) mean phase: not "resistive" by its size
            kind = "more inductive" if pd > pm else "more capacitive"
        else:
            kind = "more resistive" if abs(pd) < abs(pm) else "more capacitive"
        parts.append(f"{where} the data are {kind} than the model (phase {pd:.0f}° vs {pm:.0f}°)")
    else:
        parts.append(f"{where} the data and the model differ in magnitude at the same phase")
    if abs(mag) >= MAGNITUDE_MIN_PERCENT:
        parts.append(f"|Z| is {abs(mag):.2g} % {'above' if mag > 0 else 'below'} the model")
    parts.extend(_slopes(f[i:j], d, m))
    if depressed:
        return f"{depressed} {where}; " + "; ".join(parts[1:] or parts)
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
    flagged = np.array([any(blo <= x * 1.0001 and x <= bhi * 1.0001 for blo, bhi in kk_bad_bands) for x in f], bool)
    for i, j in _runs(mask.astype(int)):
        if not mask[i]:
            continue
        lo, hi = _edges(f, i, j)
        comps = tuple(c for c, m in (("real", m_re), ("imag", m_im)) if m[i:j].any())
        score = float(np.mean(e_re[i:j] ** 2 + e_im[i:j] ** 2) / 2)
        errors = [e[i:j] for c, e in (("real", e_re), ("imag", e_im)) if c in comps]
        data_problem = bool(flagged[i:j].all() or (flagged[i:j].any() and _carried_by_flagged(errors, flagged[i:j], p)))
        bands.append(FailingBand(lo, hi, _describe(f, zd, zm, i, j, f.size), comps, score, data_problem))
    return tuple(bands)


def _carried_by_flagged(errors: list[np.ndarray], flagged: np.ndarray, p: float = RUN_P) -> bool:
    """True when a band's misfit is the KK-flagged points': without them its points' Σ(r/σ)²
    (``errors``: the band's structured components, each over its points) is within the χ²
    quantile 1 − ``p`` of as many terms, the test that made it a band (`_structured_mask`).
    REAL BioLogic file with R0 + R1 || C1: the band 49.3–83.3 Hz is its 6.7σ
    spike at 56.2 Hz, which the KK test flags, and one point at 1.04σ; without this test it would
    count as the model's failure ("structured in 2 bands") and be shaded "model fails"."""
    rest = np.concatenate([e[~flagged] for e in errors])
    return bool(np.sum(rest**2) <= chi2_quantile(1 - p, rest.size))
