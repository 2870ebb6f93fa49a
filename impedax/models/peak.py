"""The largest force over a frequency band, located between grid points.

A force spectrum on a log grid puts its top at the nearest grid point (35.5 kHz for Meyer's
thesis values on 161 points, where the force peaks at 37.0 kHz). `force_maximum` refines the
grid maximum by Brent's bounded maximisation in ln f between the two neighbouring grid points,
and says when the largest force sits at an end of the band: the value is that end's, not a
peak, and the force may still rise past the band (`edge_slope` says how fast it does there).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Callable

import numpy as np

from ..data import format_percent
from ..errors import ParameterError

__all__ = ["ForceMaximum", "force_maximum", "force_plateau", "edge_slope", "grid_edge_slope", "band_end_words", "change_per_decade", "BAND_EDGES", "FORCE_PLATEAU_REL", "FORCE_PLATEAU_SPAN", "LEVELLED_SLOPE"]

# what `ForceMaximum.band_edge` may say besides None (a peak inside the band)
BAND_EDGES = ("fmin", "fmax", "fmin=fmax", "flat")
# Brent's tolerance on the position inside the bracket of two grid steps (0..1): the frequency
# to ~1e-9 of a step, far below what a force's flat top resolves in float64 (~1e-8)
_XATOL = 1e-10
# a refined maximum this close to an end of the band (in units of the bracket) is that end
_EDGE = 1e-6


FORCE_PLATEAU_REL = 0.01
"""A force's maximum lies on a plateau (`force_plateau`) where the force stays within this
fraction of it over more than `FORCE_PLATEAU_SPAN` in frequency: where on the plateau the grid's
largest value falls is then rounding's and noise's choice, not a peak (a SYNTHETIC remainder of
tests/test_gap_force_bound.py: the force with EP within 1 % of its largest, 412 mN, from 1 Hz to
22.4 Hz, would be reported as "max 412 mN at 1 Hz")."""
FORCE_PLATEAU_SPAN = 10.0
LEVELLED_SLOPE = math.log10(1.0 + FORCE_PLATEAU_REL)
"""A force largest at an end of the band has levelled off there when its slope d ln F/d ln f
(`edge_slope`) is below this in magnitude: it changes by less than `FORCE_PLATEAU_REL` (1 %) per
decade (Vezzoli's eq 10 at 50 kHz: 5.3e-5 = 2/(1 + (ωτ)²), where "still rises above it" was said)."""


# the step in ln f inward from a band's end over which `edge_slope` takes the force's slope (or the
# grid's step there, if smaller): local, where the grid's step is the whole band with --points 2
EDGE_SLOPE_STEP = 1e-3


def edge_slope(force_at: Callable[[float], float], freq, index: int) -> float | None:
    """d ln F/d ln f at the band's end ``index`` (0 or the last) of the grid ``freq``:
    ln(F(f_end)/F(f_in))/ln(f_end/f_in), f_in = f_end·e^(∓h) inside the band, h the smaller of
    `EDGE_SLOPE_STEP` and the grid's step there; None with one frequency or a force not
    positive there."""
    freq = np.asarray(freq, float).reshape(-1)
    if freq.size < 2 or index not in (0, freq.size - 1):
        return None
    other = 1 if index == 0 else freq.size - 2
    step = min(EDGE_SLOPE_STEP, abs(math.log(freq[other] / freq[index])))
    if not step > 0:
        return None
    inner = float(freq[index]) * math.exp(step if index == 0 else -step)
    end, near = float(force_at(float(freq[index]))), float(force_at(inner))
    if not (end > 0 and near > 0):
        return None
    slope = math.log(end / near) / math.log(float(freq[index]) / inner)
    return slope if math.isfinite(slope) else None


def grid_edge_slope(freq, force, index: int) -> float | None:
    """d ln F/d ln f over the grid's step at the band's end ``index`` (0 or the last) of the
    forces ``force`` on the grid ``freq``: ln(F_end/F_next)/ln(f_end/f_next), as `edge_slope`
    takes it of a force known between grid points; None with one frequency, or a force not
    positive there."""
    freq, force = np.asarray(freq, float).reshape(-1), np.asarray(force, float).reshape(-1)
    if freq.size < 2 or index not in (0, freq.size - 1):
        return None
    other = 1 if index == 0 else freq.size - 2
    if not (force[index] > 0 and force[other] > 0 and freq[index] > 0 and freq[other] > 0 and freq[index] != freq[other]):
        return None
    slope = math.log(force[index] / force[other]) / math.log(freq[index] / freq[other])
    return slope if math.isfinite(slope) else None


def change_per_decade(slope: float) -> str:
    """The relative change per decade of a force of log-slope ``slope``, 10^|slope| − 1, as impedax
    writes a percentage (``0.012 %``), "less than 0.001 %" below that."""
    change = 10.0 ** abs(slope) - 1.0
    return format_percent(change) if change >= 1e-5 else "less than 0.001 %"


def band_end_words(slope: float | None, side: str, past: str) -> str:
    """What a force largest at an end of the band does there, by its slope d ln F/d ln f
    (`edge_slope`, `grid_edge_slope`): "where it has levelled off: it changes by 0.012 % per
    decade there (it may still rise above --fmax, as slowly)" below `LEVELLED_SLOPE`, else "and
    still rises above it (∝ f^2 there)" (without the rate when ``slope`` is None). ``side``:
    "below" or "above"; ``past``: the end's name (``--fmax``, ``1 MHz``). The words of `impedax
    force` and `impedax gap` alike."""
    if slope is not None and abs(slope) < LEVELLED_SLOPE:
        return f"where it has levelled off: it changes by {change_per_decade(slope)} per decade there (it may still rise {side} {past}, as slowly)"
    return f"and still rises {side} it" + ("" if slope is None else f" (∝ f^{slope:.2g} there)")


def force_plateau(freq, force, index: int) -> tuple[float, float] | None:
    """(low, high) [Hz]: the contiguous grid frequencies about ``force[index]`` where ``force``
    stays within `FORCE_PLATEAU_REL` of it, when they span more than `FORCE_PLATEAU_SPAN`; else None."""
    freq, force = np.asarray(freq, float).reshape(-1), np.asarray(force, float).reshape(-1)
    if force.size < 2 or not np.all(np.isfinite(force)):
        return None
    near = force >= (1.0 - FORCE_PLATEAU_REL) * force[index]
    a = b = index
    while a > 0 and near[a - 1]:
        a -= 1
    while b < force.size - 1 and near[b + 1]:
        b += 1
    low, high = sorted((float(freq[a]), float(freq[b])))
    return (low, high) if high > FORCE_PLATEAU_SPAN * low else None


@dataclass(frozen=True)
class ForceMaximum:
    """The largest force over a band [N] and where it is [Hz].

    ``frequency_hz``/``force_n`` are refined between grid points; ``grid_frequency_hz``/
    ``grid_force_n`` are the grid's largest. ``at_band_edge`` is True when the force is largest
    at an end of the band (it may still rise past it: ``edge_slope``); ``band_edge`` then names that end ("fmin",
    "fmax"; "fmin=fmax" for a one-frequency band), "flat" for a force the same at every
    frequency, and None for a peak inside the band. ``plateau_hz`` (low, high) [Hz]: the grid
    frequencies about the grid's largest force where the force stays within 1 % of it, when they
    span more than a decade (`force_plateau`), else None (Vezzoli's eq 10, a
    high-pass, is within 1 % of its largest from 2.59 kHz to the band's 1 MHz, where "still rises
    above it" alone would read as a force still growing). ``edge_slope``: d ln F/d ln f at that end of
    the band (`edge_slope`, over a step of 1e-3 in ln f inward), None for a peak inside the band
    (over a band shorter than a decade, where no plateau is judged, it tells a force
    still rising, ∝ f² on eq 10's low side, from one that has levelled off)."""

    frequency_hz: float
    force_n: float
    grid_frequency_hz: float
    grid_force_n: float
    at_band_edge: bool
    band_edge: str | None
    plateau_hz: tuple[float, float] | None = None
    edge_slope: float | None = None

    @property
    def is_peak(self) -> bool:
        """True when the band holds a maximum of the force (not an end, not a flat force)."""
        return self.band_edge is None

    def to_dict(self) -> dict:
        return asdict(self)


def _numbers(values, name: str) -> np.ndarray:
    """``values`` as a flat float array, else one `ParameterError` naming ``name`` (text or
    objects that are no numbers: not NumPy's ValueError)."""
    try:
        return np.asarray(values, float).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name} must be numbers: {exc}") from None


def force_maximum(force_at: Callable[[float], float], freq, force=None) -> ForceMaximum:
    """The largest of ``force`` (``force_at`` on the grid ``freq`` [Hz] when not given), refined
    by Brent's bounded maximisation of ``force_at(f)`` in ln f between the grid maximum's
    neighbours (exact for a force with one maximum in that bracket).

    ``force_at`` takes one frequency [Hz] and returns the force [N] there, e.g.
    ``lambda f: float(meyer_force(params, np.array([f]))[0])``. ``freq`` rises (a log grid such as
    `impedax.data.log_frequencies`)."""
    from scipy.optimize import minimize_scalar

    if not callable(force_at):
        raise ParameterError(f"force_at must be a function of one frequency [Hz] returning the force [N], got {type(force_at).__name__}")
    freq = _numbers(freq, "freq")
    if freq.size == 0:
        raise ParameterError("freq: no frequencies given")
    if not np.all(np.isfinite(freq)) or np.any(freq <= 0) or np.any(np.diff(freq) < 0):
        raise ParameterError("freq: frequencies must be positive, finite and rising")
    force = _numbers([force_at(float(f)) for f in freq], "force_at's values") if force is None else _numbers(force, "force")
    if force.shape != freq.shape:
        raise ParameterError(f"force: {force.size} values for {freq.size} frequencies")
    if not np.all(np.isfinite(force)):
        bad = int(np.flatnonzero(~np.isfinite(force))[0])
        raise ParameterError(f"force: not finite at {freq[bad]:g} Hz; no maximum can be found")
    n = freq.size
    ties = np.flatnonzero(force == force.max())
    k = n - 1 if ties[-1] == n - 1 else int(ties[0])  # (on a flat top reaching fmax: the force rises to fmax)
    grid = {"grid_frequency_hz": float(freq[k]), "grid_force_n": float(force[k])}
    at_end = {"frequency_hz": float(freq[k]), "force_n": float(force[k]), **grid, "at_band_edge": True}
    if n > 1 and force.max() == force.min():  # (flat, e.g. zero: no end to call rising; its plateau the band, as impedax gap's JSON gives it)
        return ForceMaximum(**{**at_end, "frequency_hz": float(freq[0]), "grid_frequency_hz": float(freq[0]), "at_band_edge": False, "band_edge": "flat",
                               "plateau_hz": force_plateau(freq, force, 0)})
    if n == 1 or freq[0] == freq[-1]:
        return ForceMaximum(**at_end, band_edge="fmin=fmax")
    at_end["plateau_hz"] = force_plateau(freq, force, k)
    lo, hi = math.log(freq[max(k - 1, 0)]), math.log(freq[min(k + 1, n - 1)])
    best = minimize_scalar(lambda x: -force_at(math.exp(lo + x * (hi - lo))), bounds=(0.0, 1.0), method="bounded", options={"xatol": _XATOL})
    value = -float(best.fun)  # (force_at gave numbers on the grid: the bracket's are numbers too)
    if k in (0, n - 1):
        end = 0.0 if k == 0 else 1.0
        if abs(best.x - end) <= _EDGE or not value > force[k]:
            return ForceMaximum(**at_end, band_edge="fmin" if k == 0 else "fmax", edge_slope=edge_slope(force_at, freq, k))
    elif not value >= force[k]:  # (not one maximum between the neighbours: keep the grid's)
        return ForceMaximum(**{**at_end, "at_band_edge": False}, band_edge=None)
    return ForceMaximum(frequency_hz=math.exp(lo + float(best.x) * (hi - lo)), force_n=value, **grid, at_band_edge=False, band_edge=None, plateau_hz=at_end["plateau_hz"])
