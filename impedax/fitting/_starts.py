"""Starting values without the user's help.

1. A data-driven guess per element from its place in the circuit: the high-frequency intercept
   of Z' for resistors in the outer series chain, the low-frequency limit minus it for
   resistors inside arcs, τ = 1/(2π f_peak) at the maximum of −Z'' for time constants and
   capacitances (C = τ/R_arc), the low-frequency slope of log|Z''| for CPE exponents, a series
   capacitance from Z'' at the lowest frequency, an inductance from positive Z'' at the top.
2. Jittered copies of that guess and log-uniform draws over ranges scaled to the data (|Z| and
   the frequency span), all fitted together in one vmapped call; the best is kept.
"""

from __future__ import annotations

import numpy as np

from ..circuits import Circuit, DEFAULT_REGISTRY, Element, Parallel, Registry
from ._parameters import ParameterTable

__all__ = ["SpectrumFeatures", "data_driven_guess", "random_starts"]


class SpectrumFeatures:
    """Scalar features of one spectrum used for guesses and start ranges."""

    def __init__(self, freq, z):
        order = np.argsort(freq)
        f, z = np.asarray(freq, float)[order], np.asarray(z, complex)[order]
        w = 2 * np.pi * f
        mag = np.abs(z)
        self.f_min, self.f_max = f[0], f[-1]
        self.z_min, self.z_max = max(mag.min(), 1e-300), mag.max()
        self.r_hf = max(z.real[-1], 1e-3 * self.z_min)
        self.r_lf = max(z.real[0], self.r_hf * 1.01)
        neg_im = -z.imag
        self.f_peak = f[np.argmax(neg_im)] if np.any(neg_im > 0) else np.sqrt(f[0] * f[-1])
        self.c_series = 1.0 / (w[0] * neg_im[0]) if neg_im[0] > 0 else 1.0 / (w[0] * mag[0])
        self.l_series = z.imag[-1] / w[-1] if z.imag[-1] > 0 else self.z_min / w[-1] * 1e-2
        k = min(3, len(f))
        if k >= 2 and np.all(neg_im[:k] > 0):
            lx, ly = np.log(f[:k]), np.log(neg_im[:k])
            slope = np.sum((lx - lx.mean()) * (ly - ly.mean())) / np.sum((lx - lx.mean()) ** 2)  # least-squares line
            self.alpha_lf = float(np.clip(-slope, 0.4, 1.0))
        else:
            self.alpha_lf = 0.85
        self.warburg = mag[0] * np.sqrt(w[0]) * 0.3
        self._f, self._neg_im = f, neg_im

    def arcs(self, n_arc: int) -> tuple[np.ndarray, np.ndarray]:
        """(R, τ) of ``n_arc`` arcs, highest frequency first: the tallest local maxima of −Z''
        over log f give τ = 1/(2π f_peak) and R ∝ the peak height (−Z''_max = R/2 for an RC
        arc); missing peaks are spread a decade apart. R sums to the low-minus-high-frequency
        span."""
        f, y = self._f, self._neg_im
        r_total = max(self.r_lf - self.r_hf, 0.05 * self.z_max)
        inner = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:]) & (y[1:-1] > 0)) + 1
        ends = [i for i in (0, len(f) - 1) if len(f) > 1 and y[i] > 0 and y[i] > y[1 if i == 0 else -2]]
        peaks = np.concatenate([inner, np.asarray(ends, int)])
        peaks = peaks[np.argsort(-y[peaks])][:n_arc] if peaks.size else np.asarray([], int)
        f_peaks = list(f[peaks]) if peaks.size else [self.f_peak]
        heights = list(y[peaks]) if peaks.size else [r_total / 2]
        while len(f_peaks) < n_arc:  # overlapping arcs: split the dominant one a decade apart
            f_peaks.append(f_peaks[0] / 10 ** len(f_peaks))
            heights.append(heights[0])
        order = np.argsort(f_peaks)[::-1]
        f_peaks = np.asarray(f_peaks)[order]
        r = np.asarray(heights, float)[order]
        r = r_total * r / r.sum()
        return r, 1.0 / (2 * np.pi * f_peaks)


def _roles(circuit: Circuit):
    """element name → index of the outermost parallel block (arc) holding it, or -1 for the
    outer series chain; arcs are numbered in the order they are written."""
    roles = {}
    count = [0]

    def walk(node, block):
        if isinstance(node, Element):
            roles[node.name] = block
            return
        if isinstance(node, Parallel) and block < 0:
            block = count[0]
            count[0] += 1
        for child in node.children:
            walk(child, block)

    walk(circuit, -1)
    return roles, count[0]


def data_driven_guess(circuit: Circuit, table: ParameterTable, features: SpectrumFeatures, registry: Registry = DEFAULT_REGISTRY) -> np.ndarray:
    """A starting value for every parameter (user starts and fixed values take precedence)."""
    roles, n_blocks = _roles(circuit)
    elements = list(circuit.elements())
    n_series_r = max(1, sum(1 for e in elements if e.symbol == "R" and roles[e.name] < 0))
    # resistive elements per arc share that arc's resistance
    n_res = np.ones(max(n_blocks, 1))
    for e in elements:
        if roles[e.name] >= 0 and registry[e.symbol].parameters[0].unit == "Ohm":
            n_res[roles[e.name]] += 1
    n_res = np.maximum(n_res - 1, 1)
    r_arcs, taus = features.arcs(max(n_blocks, 1))
    guess: dict[str, float] = {}
    for e in elements:
        block = roles[e.name]
        inside = block >= 0
        r_arc = r_arcs[block] / n_res[block] if inside else r_arcs.sum()
        tau = taus[block] if inside else 1.0 / (2 * np.pi * features.f_peak)
        f_arc = 1.0 / (2 * np.pi * tau)
        spec = registry[e.symbol]
        names = spec.parameter_names(e.name)
        sym = registry[e.symbol].symbol
        if sym == "R":
            guess[names[0]] = r_arc if inside else features.r_hf / n_series_r
        elif sym == "C":
            guess[names[0]] = tau / r_arc if inside else features.c_series
        elif sym == "L":
            guess[names[0]] = features.l_series
        elif sym == "CPE":
            alpha = 0.85 if inside else features.alpha_lf
            c = tau / r_arc if inside else features.c_series
            guess[names[0]] = c * (2 * np.pi * (f_arc if inside else features.f_min)) ** (1 - alpha)
            guess[names[1]] = alpha
        elif sym == "W":
            guess[names[0]] = features.warburg
        else:
            for p, n in zip(spec.parameters, names):
                if p.unit == "Ohm":
                    guess[n] = r_arc
                elif p.unit == "s":
                    guess[n] = tau
                elif p.unit == "1":
                    guess[n] = 0.85
                else:
                    guess[n] = p.default
    x = np.array([guess.get(n, np.nan) for n in table.names])
    given = ~np.isnan(table.values)
    x[given] = table.values[given]
    bad = ~np.isfinite(x)
    x[bad] = [circuit.parameter_specs(registry)[n].default for n in np.asarray(table.names)[bad]]
    return _clip_inside(x, table)


def _clip_inside(x, table: ParameterTable) -> np.ndarray:
    lo, hi = table.lower, table.upper
    # (0, ∞) is fitted in log space: any positive value is inside (a floor of lower + 1e-6
    # would lift every capacitance and CPE Q guess to 1 µF)
    span_lo = np.where(lo > 0, lo * (1 + 1e-6), lo + 1e-6 * np.where(np.isfinite(hi), hi - lo, 1.0))
    span_lo = np.where((lo == 0) & ~np.isfinite(hi), 1e-300, span_lo)
    span_hi = np.where(np.isfinite(hi), np.where(hi > 0, hi * (1 - 1e-6), hi - 1e-6), np.inf)
    return np.clip(x, span_lo, span_hi)


def _log_range(table: ParameterTable, features: SpectrumFeatures, i: int):
    unit = table.units[i]
    w_lo, w_hi = 2 * np.pi * features.f_min, 2 * np.pi * features.f_max
    zlo, zhi = features.z_min, features.z_max
    ranges = {
        "Ohm": (zlo / 30, zhi * 3),
        "F": (1 / (w_hi * zhi) / 10, 1 / (w_lo * zlo) * 10),
        "H": (zlo / w_hi / 100, zhi / w_lo),
        "s": (1 / w_hi / 10, 1 / w_lo * 10),
        "Ohm s^-1/2": (zlo * np.sqrt(w_lo) / 30, zhi * np.sqrt(w_hi) * 3),
    }
    if unit.startswith("F s^"):
        lo, hi = 1 / (w_hi * zhi) / 100, 1 / (w_lo * zlo) * 100
    else:
        lo, hi = ranges.get(unit, (1e-3, 1e3))
    return np.log(max(lo, 1e-300)), np.log(max(hi, lo * 10, 1e-299))


def random_starts(table: ParameterTable, features: SpectrumFeatures, guess: np.ndarray, n_starts: int, seed: int = 0) -> np.ndarray:
    """``n_starts`` starting points (first: the guess; then jittered guesses; then draws over
    data-scaled log ranges). Fixed parameters keep their values. Shape (n_starts, P)."""
    rng = np.random.default_rng(seed)
    starts = np.tile(guess, (n_starts, 1))
    n_jitter = (n_starts - 1) // 2
    for s in range(1, n_starts):
        for i in range(len(guess)):
            if table.fixed[i] or not np.isnan(table.values[i]) and s <= n_jitter:
                continue
            if table.units[i] == "1":
                starts[s, i] = rng.uniform(0.45, 1.0) if s > n_jitter else np.clip(guess[i] + rng.normal(0, 0.1), 0.3, 1.0)
            elif s <= n_jitter:
                starts[s, i] = guess[i] * 10 ** rng.normal(0, 0.7)
            else:
                lo, hi = _log_range(table, features, i)
                starts[s, i] = np.exp(rng.uniform(lo, hi))
    starts[:, table.fixed] = table.values[table.fixed]
    return _clip_inside(starts, table)
