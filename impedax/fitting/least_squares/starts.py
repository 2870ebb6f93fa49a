"""Starting values without the user's help.

1. A data-driven guess per element from its place in the circuit: the high-frequency intercept
   of Z' for resistors in the outer series chain, the low-frequency limit minus it for
   resistors inside arcs, τ = 1/(2π f_peak) at the maximum of −Z'' for time constants and
   capacitances (C = τ/R_arc), the low-frequency slope of log|Z''| for CPE exponents, a series
   capacitance from Z'' at the lowest frequency, an inductance from positive Z'' at the top.
   Features and guesses are computed for a whole stack of spectra at once (numpy over the
   spectra axis); one spectrum is a stack of one.
2. Jittered copies of that guess and log-uniform draws over ranges scaled to the data (|Z| and
   the frequency span), all fitted together in one vmapped call; the best is kept.
3. The escalation rule (`ESCALATION_RUNGS`): more starts while a fit is poor relative to what
   the data allow — its misfit against that of a flexible Kramers–Kronig-consistent model
   (`attainable_misfit`), or, in a batch, against the other spectra's (`batch_outliers`) —
   never relative to the noise alone: real spectra leave structured misfit above the noise
   at their global optimum, and a rule on the noise would escalate every one of them.
"""

from __future__ import annotations

import functools
import math
from typing import Mapping

import numpy as np

from ...circuits import Circuit, DEFAULT_REGISTRY, Element, ElementLimit, Parallel, Registry, StartRole
from ...errors import ImpedaxError
from ..kk import kk_misfits
from ..parameters import ParameterTable, Transform, inner_edges, to_internal

__all__ = [
    "SpectrumFeatures", "data_driven_guess", "data_driven_guesses", "limit_draw_count", "random_starts", "start_split", "draw_size", "draw_words", "guess_start", "multistart", "rung_starts", "rung_draws", "to_solver_space",
    "INSIDE_FRACTION", "well_inside", "values_inside", "inward_start",
    "ESCALATION_RUNGS", "LARGE_CIRCUIT_FREE", "LARGE_CIRCUIT_RUNG", "escalation_rungs", "KK_MISFIT_FACTOR", "ESCALATION_FLOOR", "climb_target", "BATCH_OUTLIER_FACTOR", "attainable_misfit", "rms_rel_of", "rung_seed", "batch_outliers",
]

# features with one value per spectrum (scalars for one spectrum, arrays (B,) for a stack)
_PER_SPECTRUM = ("z_min", "z_max", "r_hf", "r_lf", "f_peak", "c_series", "l_series", "alpha_lf", "warburg")


def _larger(a, b):
    """Python's ``max(a, b)`` elementwise: ``a`` unless ``b > a`` (NaN in ``b`` keeps ``a``)."""
    return np.where(b > a, b, a)


class SpectrumFeatures:
    """Features of one spectrum ``z`` (N,) or of a stack ``z`` (B, N) over shared frequencies
    ``freq`` (N,), used for guesses and start ranges.

    One spectrum: every feature is a scalar and ``arcs(n)`` gives (n,) arrays. A stack: the
    per-spectrum features (``z_min``, ``z_max``, ``r_hf``, ``r_lf``, ``f_peak``, ``c_series``,
    ``l_series``, ``alpha_lf``, ``warburg``) are arrays (B,), ``arcs(n)`` gives (B, n) arrays,
    ``f_min``/``f_max`` stay scalars, and ``features[i]`` is spectrum i's own features."""

    def __init__(self, freq, z):
        order = np.argsort(freq)
        f = np.asarray(freq, float)[order]
        z = np.asarray(z, complex)
        stacked = z.ndim == 2
        z = np.atleast_2d(z)[:, order]
        w = 2 * np.pi * f
        mag = np.abs(z)
        neg_im = -z.imag
        rows = {"z_min": _larger(mag.min(axis=1), 1e-300), "z_max": mag.max(axis=1)}
        rows["r_hf"] = _larger(z.real[:, -1], 1e-3 * rows["z_min"])
        rows["r_lf"] = _larger(z.real[:, 0], rows["r_hf"] * 1.01)
        rows["f_peak"] = np.where(np.any(neg_im > 0, axis=1), f[np.argmax(neg_im, axis=1)], np.sqrt(f[0] * f[-1]))
        with np.errstate(divide="ignore", invalid="ignore"):
            rows["c_series"] = np.where(neg_im[:, 0] > 0, 1.0 / (w[0] * neg_im[:, 0]), 1.0 / (w[0] * mag[:, 0]))
        rows["l_series"] = np.where(z.imag[:, -1] > 0, z.imag[:, -1] / w[-1], rows["z_min"] / w[-1] * 1e-2)
        rows["alpha_lf"] = _low_frequency_alpha(f, neg_im)
        rows["warburg"] = mag[:, 0] * np.sqrt(w[0]) * 0.3
        self._set(f, neg_im, rows, stacked)

    def _set(self, f, neg_im, rows, stacked):
        self.f_min, self.f_max = f[0], f[-1]
        self._f, self._neg_im, self._rows, self._stacked = f, neg_im, rows, stacked
        for name in _PER_SPECTRUM:
            setattr(self, name, rows[name] if stacked else rows[name][0])
        if not stacked:
            self.alpha_lf = float(self.alpha_lf)

    def __len__(self) -> int:
        if not self._stacked:
            raise TypeError("features of one spectrum have no length")
        return self._neg_im.shape[0]

    def __getitem__(self, index) -> "SpectrumFeatures":
        """Spectrum ``index``'s features (an integer), or a sub-stack (a slice or index array)."""
        if not self._stacked:
            raise TypeError("features of one spectrum cannot be indexed")
        one = np.ndim(index) == 0 and not isinstance(index, slice)
        pick = np.arange(len(self))[index]
        pick = np.atleast_1d(pick)
        out = object.__new__(SpectrumFeatures)
        out._set(self._f, self._neg_im[pick], {k: v[pick] for k, v in self._rows.items()}, not one)
        return out

    def arcs(self, n_arc: int) -> tuple[np.ndarray, np.ndarray]:
        """(R, τ) of ``n_arc`` arcs, highest frequency first: the tallest local maxima of −Z''
        over log f give τ = 1/(2π f_peak) and R ∝ the peak height (−Z''_max = R/2 for an RC
        arc); missing peaks are spread a decade apart. R sums to the low-minus-high-frequency
        span. Shapes (n_arc,) for one spectrum, (B, n_arc) for a stack."""
        r, tau = self._arc_rows(n_arc)
        return (r, tau) if self._stacked else (r[0], tau[0])

    def _arc_rows(self, n_arc: int) -> tuple[np.ndarray, np.ndarray]:
        f, y = self._f, self._neg_im
        b, n = y.shape
        rows = np.arange(b)
        r_total = _larger(self._rows["r_lf"] - self._rows["r_hf"], 0.05 * self._rows["z_max"])
        is_peak = np.zeros((b, n), bool)
        is_peak[:, 1:-1] = (y[:, 1:-1] > y[:, :-2]) & (y[:, 1:-1] >= y[:, 2:]) & (y[:, 1:-1] > 0)
        if n > 1:  # the ends count when they rise above their only neighbour
            is_peak[:, 0] = (y[:, 0] > 0) & (y[:, 0] > y[:, 1])
            is_peak[:, -1] = (y[:, -1] > 0) & (y[:, -1] > y[:, -2])
        # candidates listed interior maxima first (by rising frequency), then the two ends:
        # equal heights are taken in that order
        columns = np.concatenate([np.arange(1, n - 1), [0, n - 1]]) if n > 1 else np.zeros(0, int)
        height = np.where(is_peak[:, columns], y[:, columns], -np.inf)
        found = np.minimum(is_peak.sum(axis=1), n_arc)
        f_peaks = np.zeros((b, n_arc))
        heights = np.zeros((b, n_arc))
        for k in range(min(n_arc, columns.size)):  # the k-th tallest (argmax: first of equals)
            j = np.argmax(height, axis=1)
            f_peaks[:, k], heights[:, k] = f[columns[j]], height[rows, j]
            height[rows, j] = -np.inf
        none = found == 0
        f_peaks[:, 0] = np.where(none, self._rows["f_peak"], f_peaks[:, 0])
        heights[:, 0] = np.where(none, r_total / 2, heights[:, 0])
        # overlapping arcs: split the dominant one a decade apart
        k = np.arange(n_arc)
        fill = k >= np.maximum(found, 1)[:, None]
        f_peaks = np.where(fill, f_peaks[:, :1] / 10.0**k, f_peaks)
        heights = np.where(fill, heights[:, :1], heights)
        order = np.argsort(f_peaks, axis=1, kind="stable")[:, ::-1]
        f_peaks = np.take_along_axis(f_peaks, order, axis=1)
        r = np.take_along_axis(heights, order, axis=1)
        r = r_total[:, None] * r / r.sum(axis=1, keepdims=True)
        return r, 1.0 / (2 * np.pi * f_peaks)


def _low_frequency_alpha(f, neg_im) -> np.ndarray:
    """CPE exponent from the least-squares slope of log(−Z'') over log f at the three lowest
    frequencies (0.85 where −Z'' is not positive there), clipped to [0.4, 1]."""
    k = min(3, f.size)
    if k < 2:
        return np.full(neg_im.shape[0], 0.85)
    ok = np.all(neg_im[:, :k] > 0, axis=1)
    lx = np.log(f[:k])
    weights = (lx - lx.mean()) / np.sum((lx - lx.mean()) ** 2)  # slope = Σ w·log y (Σ w = 0)
    slope = np.log(np.where(ok[:, None], neg_im[:, :k], 1.0)) @ weights
    return np.where(ok, np.clip(-slope, 0.4, 1.0), 0.85)


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


@functools.lru_cache(maxsize=256)
def _circuit_layout(circuit: Circuit, registry: Registry):
    """What the guess needs of the circuit alone: element → arc (-1: outer series chain), the
    number of arcs to look for (at least one), the resistors of the outer chain (≥ 1), and per
    arc its resistive elements (≥ 1), which share that arc's resistance."""
    elements = tuple(circuit.elements())
    roles, n_blocks = _roles(circuit)
    resistances = (StartRole.RESISTANCE, StartRole.ARC_RESISTANCE)
    n_series_r = max(1, sum(StartRole.RESISTANCE in registry[e.symbol].start_roles and roles[e.name] < 0 for e in elements))
    resistive = np.array([roles[e.name] for e in elements if roles[e.name] >= 0 and any(r in resistances for r in registry[e.symbol].start_roles)], int)
    n_res = np.maximum(np.bincount(resistive, minlength=max(n_blocks, 1)), 1).astype(float)
    n_res.setflags(write=False)  # (cached: shared by every call)
    return roles, max(n_blocks, 1), n_series_r, n_res


def data_driven_guesses(circuit: Circuit, table: ParameterTable, features: SpectrumFeatures, registry: Registry = DEFAULT_REGISTRY) -> np.ndarray:
    """A starting value for every parameter and spectrum, shape (B, P) (B = 1 for the features
    of one spectrum); user starts and fixed values take precedence."""
    elements = list(circuit.elements())
    roles, n_arcs, n_series_r, n_res = _circuit_layout(circuit, registry)
    rows = features._rows
    r_arcs, taus = features._arc_rows(n_arcs)
    r_series = r_arcs.sum(axis=1)
    tau_series = 1.0 / (2 * np.pi * rows["f_peak"])
    guess: dict[str, np.ndarray | float] = {}
    for e in elements:
        block = roles[e.name]
        inside = block >= 0
        r_arc = r_arcs[:, block] / n_res[block] if inside else r_series
        tau = taus[:, block] if inside else tau_series
        f_arc = 1.0 / (2 * np.pi * tau)
        spec = registry[e.symbol]
        for p, n in zip(spec.parameters, spec.parameter_names(e.name)):
            role = p.start_role  # see StartRole for what each guess means
            if role is StartRole.RESISTANCE:
                guess[n] = r_arc if inside else rows["r_hf"] / n_series_r
            elif role is StartRole.ARC_RESISTANCE:
                guess[n] = r_arc
            elif role is StartRole.CAPACITANCE:
                guess[n] = tau / r_arc if inside else rows["c_series"]
            elif role is StartRole.ARC_CAPACITANCE:
                guess[n] = tau / r_arc
            elif role is StartRole.INDUCTANCE:
                guess[n] = rows["l_series"]
            elif role is StartRole.CPE_Q:
                alpha = 0.85 if inside else rows["alpha_lf"]
                c = tau / r_arc if inside else rows["c_series"]
                guess[n] = c * (2 * np.pi * (f_arc if inside else features.f_min)) ** (1 - alpha)
            elif role is StartRole.CPE_EXPONENT:
                guess[n] = 0.85 if inside else rows["alpha_lf"]
            elif role is StartRole.EXPONENT:
                guess[n] = 0.85
            elif role is StartRole.WARBURG:
                guess[n] = rows["warburg"]
            elif role is StartRole.TIME_CONSTANT:
                guess[n] = tau
            else:
                guess[n] = p.default
    x = np.full((r_arcs.shape[0], len(table.names)), np.nan)
    for j, name in enumerate(table.names):
        x[:, j] = guess.get(name, np.nan)
    given = ~np.isnan(table.values)
    x[:, given] = table.values[given]
    bad = ~np.isfinite(x)
    if bad.any():
        specs = circuit.parameter_specs(registry)
        x = np.where(bad, np.array([specs[n].default for n in table.names], float), x)
    return _clip_inside(x, table)


def data_driven_guess(circuit: Circuit, table: ParameterTable, features: SpectrumFeatures, registry: Registry = DEFAULT_REGISTRY) -> np.ndarray:
    """A starting value for every parameter (user starts and fixed values take precedence):
    shape (P,) for the features of one spectrum, (B, P) for a stack."""
    guesses = data_driven_guesses(circuit, table, features, registry)
    return guesses if features._stacked else guesses[0]


# a start outside a parameter's bounds (a data-driven guess beyond a bound you set, a random
# draw over the data's ranges) is placed this fraction of the solver's span inside the bound it
# crossed (the span of the logistic's argument: log x for a positive bounded parameter, x for
# an exponent). Nudged just inside (1e-6), it would sit where the logistic is flat:
# its gradient in the solver's coordinates ~1e-4 of the parameter's, Levenberg–Marquardt
# stopping there, and a fit with bounds R0 ∈ (63, 64) around the optimum 63.56 of BioLogic's
# real file ending at R0 = 63.99994, "at its upper bound" (docs/fitting.md, "Convergence and bounds")
INSIDE_FRACTION = 0.1


def _clip_inside(x, table: ParameterTable) -> np.ndarray:
    """Values x (…, P) inside their bounds: a value outside moved `INSIDE_FRACTION` of the
    solver's span inside (`well_inside`); a value on a bound (an exponent's start at 1) nudged
    1e-6 inside, as before."""
    lo, hi = table.lower, table.upper
    x = np.asarray(x, float)
    with np.errstate(invalid="ignore"):
        outside = (x < lo) | (x > hi)
    x = np.where(outside, well_inside(x, table, INSIDE_FRACTION), x)
    return np.clip(x, *inner_edges(lo, hi))


def values_inside(values: Mapping[str, float], table: ParameterTable) -> dict[str, float]:
    """Starting values by name moved inside ``table``'s bounds as a batch's own starts are
    (`guess_start`, ``init=batch``; `_clip_inside`): a value on a bound nudged 1e-6 inside, one
    outside moved `INSIDE_FRACTION` of the span inside. A fitted value may sit on a bound that
    a start must lie strictly inside (`parameters.outside_bounds_message`)."""
    x = np.array([float(values.get(n, math.nan)) for n in table.names])
    moved = _clip_inside(np.where(np.isfinite(x), x, 1.0), table)
    return {n: float(moved[i]) for i, n in enumerate(table.names) if n in values and math.isfinite(x[i])}


def well_inside(x, table: ParameterTable, fraction: float = INSIDE_FRACTION) -> np.ndarray:
    """Values x (…, P) at least ``fraction`` of the solver's span away from each finite bound:
    for a parameter bounded on both sides, the span of log x (positive lower bound, a unit
    other than 1: `Transform.LOG_LOGISTIC`) or of x (`Transform.LOGISTIC`); for one with a
    positive lower bound only, ``fraction`` × the bound above it; a parameter without a
    positive or finite bound (log space: any positive value) is only kept positive."""
    lo, hi = table.lower, table.upper
    x = np.asarray(x, float)
    logged = np.asarray(table.kind) == Transform.LOG_LOGISTIC
    with np.errstate(all="ignore"):
        g_lo = np.where(logged, np.log(np.where(lo > 0, lo, 1.0)), lo)
        g_hi = np.where(logged, np.log(np.where(hi > 0, hi, 1.0)), hi)
        g = np.where(logged, np.log(np.where(x > 0, x, np.where(lo > 0, lo, 1.0))), x)
        two_sided = np.isfinite(lo) & np.isfinite(hi) & (hi > lo)
        span = np.where(two_sided, g_hi - g_lo, 0.0)
        g2 = np.clip(g, g_lo + fraction * span, g_hi - fraction * span)
        inside2 = np.where(logged, np.exp(g2), g2)
        floor = np.where(lo > 0, lo * (1 + fraction), np.where(lo == 0, 1e-300, lo + fraction))
        one_sided = np.where(np.isfinite(lo) & ~np.isfinite(hi), np.maximum(x, floor), x)
    return np.where(two_sided, inside2, one_sided)


def inward_start(table: ParameterTable, x, sides, step, fraction: float = INSIDE_FRACTION) -> np.ndarray:
    """A restart for fits x (…, P) stopped at a bound while chi² falls inward (``sides`` (…, K)
    nonzero over the free parameters: `result.falling_inward`): each such parameter moved by
    ``step`` (…, K) (the Newton step along it alone, the others held) and kept at least
    ``fraction`` of the solver's span inside its bounds (`well_inside`); the others
    unchanged."""
    x = np.array(x, float)
    free = table.free_index
    moved = np.zeros(x.shape, bool)
    moved[..., free] = np.asarray(sides) != 0
    target = x.copy()
    target[..., free] = x[..., free] + np.where(moved[..., free], np.nan_to_num(np.asarray(step, float)), 0.0)
    return np.where(moved, well_inside(target, table, fraction), x)


def _log_range(table: ParameterTable, features: SpectrumFeatures, i: int):
    """log of the (low, high) range of parameter i's random draws, per spectrum (B,)."""
    unit = table.units[i]
    rows = features._rows
    w_lo, w_hi = 2 * np.pi * features.f_min, 2 * np.pi * features.f_max
    zlo, zhi = rows["z_min"], rows["z_max"]
    if unit == "Ohm":
        lo, hi = zlo / 30, zhi * 3
    elif unit == "F":
        lo, hi = 1 / (w_hi * zhi) / 10, 1 / (w_lo * zlo) * 10
    elif unit == "H":
        lo, hi = zlo / w_hi / 100, zhi / w_lo
    elif unit == "s":
        lo, hi = 1 / w_hi / 10, 1 / w_lo * 10
    elif unit == "Ohm s^-1/2":
        lo, hi = zlo * np.sqrt(w_lo) / 30, zhi * np.sqrt(w_hi) * 3
    elif unit.startswith("F s^"):
        lo, hi = 1 / (w_hi * zhi) / 100, 1 / (w_lo * zlo) * 100
    else:
        lo, hi = 1e-3, 1e3
    lo, hi = np.broadcast_to(lo, zlo.shape), np.broadcast_to(hi, zlo.shape)
    return np.log(_larger(lo, 1e-300)), np.log(_larger(_larger(hi, lo * 10), 1e-299))


def _exponents(table: ParameterTable) -> np.ndarray:
    """Which parameters are exponents (unit "1": drawn linearly, jittered additively)."""
    return np.array([u == "1" for u in table.units], bool)


def _draw_ranges(table: ParameterTable, features: SpectrumFeatures) -> tuple[np.ndarray, np.ndarray]:
    """log (low, high) of the random draws of the parameters not fixed, each (B, n drawn);
    exponents get (0, 0) (drawn linearly in `random_starts`)."""
    exponent, zero = _exponents(table), np.zeros_like(features._rows["z_min"])
    rows = [_log_range(table, features, i) if not exponent[i] else (zero, zero) for i in np.flatnonzero(~table.fixed)]
    if not rows:  # every parameter fixed
        return np.zeros(zero.shape + (0,)), np.zeros(zero.shape + (0,))
    lo, hi = zip(*rows)
    return np.stack(lo, axis=-1), np.stack(hi, axis=-1)


def random_starts(table: ParameterTable, features: SpectrumFeatures, guess: np.ndarray, n_starts: int, seed: int = 0, ranges=None) -> np.ndarray:
    """``n_starts`` starting points (first: the guess; then jittered guesses; then draws over
    data-scaled log ranges). Fixed parameters keep their values. Shape (n_starts, P) for one
    spectrum's features and guess (P,); (B, n_starts, P) for a stack's, every spectrum with
    the random numbers that it would draw alone (the same for all, scaled to its data).

    The random numbers are those of one scalar draw per start and parameter, start by start
    (jittered starts: a normal per parameter neither fixed nor given; random starts: a
    uniform per parameter not fixed), drawn in two array calls: a Generator's array of
    normals (or of uniforms) is the sequence of its scalar draws, and every jitter draw comes
    before every uniform one. (``ranges``: `_draw_ranges` of the parameters not fixed, when
    the caller draws several times for one table and spectrum.)"""
    rng = np.random.default_rng(seed)
    guesses = np.atleast_2d(guess)
    starts = np.repeat(guesses[:, None, :], n_starts, axis=1)
    n_jitter, n_random = start_split(n_starts)
    fixed, given = table.fixed, ~np.isnan(table.values)
    exponent = _exponents(table)
    jittered, drawn = np.flatnonzero(~fixed & ~given), np.flatnonzero(~fixed)
    if n_jitter and jittered.size:
        normal = rng.standard_normal((n_jitter, jittered.size))  # rng.normal(0, σ) = σ × this
        g = guesses[:, None, jittered]
        is_exp = exponent[jittered]
        starts[:, 1 : 1 + n_jitter, jittered] = np.where(is_exp, np.clip(g + 0.1 * normal, 0.3, 1.0), g * 10 ** (0.7 * normal))
    if n_random and drawn.size:
        uniform = rng.random((n_random, drawn.size))  # rng.uniform(a, b) = a + (b − a) × this
        lo, hi = _draw_ranges(table, features) if ranges is None else ranges
        starts[:, 1 + n_jitter :, drawn] = np.where(exponent[drawn], 0.45 + (1.0 - 0.45) * uniform, np.exp(lo[:, None, :] + (hi - lo)[:, None, :] * uniform))
    starts[..., fixed] = table.values[fixed]
    starts = _clip_inside(starts, table)
    return starts if features._stacked else starts[0]


def to_solver_space(table: ParameterTable, x: np.ndarray) -> np.ndarray:
    """Parameter values (…, P) → the solver's unconstrained coordinates of the free ones (…, K)."""
    free = table.free_index
    return to_internal(x[..., free], table.lower[free], table.upper[free], table.kind[free])


def guess_start(circuit, table, features, registry, starts=None) -> np.ndarray:
    """The data-driven guess as one start in the solver's space: shape (1, K) for one
    spectrum's features, (B, K) for a stack's (one start per spectrum). ``starts`` (B, P):
    each spectrum's own starting values where finite (a fixed parameter keeps its value),
    moved inside the bounds as any start."""
    x = data_driven_guesses(circuit, table, features, registry)
    if starts is not None:
        x = _clip_inside(np.where(np.isfinite(starts) & ~table.fixed, starts, x), table)
    return to_solver_space(table, x)


def limit_starts(circuit: Circuit, table: ParameterTable, x: np.ndarray, freq, registry: Registry) -> list[np.ndarray]:
    """Starts (B, P) for a further local fit: each spectrum's optimum ``x`` (B, P) with one
    element moved into a limit that keeps what the data see of it (`ElementLimit.toward`: a Wo at
    τ → ∞ with its Warburg coefficient kept) and, where the limit says so, at the edge of it
    (`ElementLimit.edge`: the knee at ω_min·τ = 3, the same coefficient kept), for each element
    whose parameters are all free. A limit at τ → ∞ is reached by no step of the solver, and the
    reference spectrum's optimum, which every spectrum is offered, can hold the batch on the
    other side: on the 130 REAL battery cycles the Wo model's batch fits ended above the W
    model's χ² on 58 cycles (up to 1.40×), on none with this start solved too, and single fits
    after the start ladder on 2 of 26 cycles (up to 6 %) (2026-12-02)."""
    omega = 2 * np.pi * np.asarray(freq, float)
    out = []
    for index, limit in _limits_of_free_elements(circuit, table, registry):
        for move in (limit.toward, limit.edge):
            moved = move(tuple(x[:, i] for i in index), float(omega.min()), float(omega.max()))
            start = np.array(x, float)
            start[:, index] = np.stack([np.broadcast_to(np.asarray(v, float), (x.shape[0],)) for v in moved], axis=-1)
            out.append(start)
    return out


def _limits_of_free_elements(circuit: Circuit, table: ParameterTable, registry: Registry) -> list[tuple[list[int], ElementLimit]]:
    """(parameter indices, `ElementLimit`) of each element's limit that no step of the solver
    reaches (one with a ``toward``; its ``edge`` is None or given with it) for the elements whose
    parameters are all free."""
    out = []
    for element in circuit.elements():
        spec = registry[element.symbol]
        index = [table.names.index(n) for n in spec.parameter_names(element.name)]
        if not table.fixed[index].any():
            out += [(index, limit) for limit in spec.limits if limit.toward is not None]
    return out


def multistart(circuit, table, features, n_starts, seed, registry) -> np.ndarray:
    """``n_starts`` starts (the data-driven guess first, then random ones) in the solver's
    space: shape (n_starts, K) for one spectrum's features, (B, n_starts, K) for a stack's."""
    guess = data_driven_guess(circuit, table, features, registry)
    return to_solver_space(table, random_starts(table, features, guess, n_starts, seed))


def rung_starts(circuit, table, features, n_starts, seeds, registry) -> np.ndarray:
    """The starts of one rung of the ladder: `multistart`'s ``n_starts`` for each of
    ``seeds``, one after the other, the guess computed once (`rung_draws`: `draw_size` starts
    each). Shape (len(seeds)·size, K) for one spectrum's features, (B, len(seeds)·size, K) for
    a stack's."""
    return to_solver_space(table, np.concatenate(rung_draws(circuit, table, features, n_starts, seeds, registry), axis=-2))


def start_split(n_starts: int) -> tuple[int, int]:
    """How `random_starts` fills one draw of ``n_starts`` beside the guess: (jittered copies of
    it, starts drawn at random), (n − 1)//2 and the rest."""
    n_jitter = (n_starts - 1) // 2
    return n_jitter, max(n_starts - 1 - n_jitter, 0)


def _nothing_to_jitter(table: ParameterTable) -> bool:
    """Every parameter fixed or given: `random_starts`' jittered copies are the guess itself."""
    return not np.any(~table.fixed & np.isnan(table.values))


def draw_size(table: ParameterTable, n_starts: int) -> int:
    """How many starts one draw of ``n_starts`` runs (`rung_draws`): ``n_starts``, or, where
    nothing is jittered (every free parameter given), the given start once and the random
    ones: its (n − 1)//2 copies would be the same local fit again (9 of 16 by default)."""
    n_jitter, _ = start_split(n_starts)
    return n_starts - n_jitter if n_jitter and _nothing_to_jitter(table) else n_starts


def draw_words(table: ParameterTable, n_starts: int, start: str, at_limit: int = 0) -> str:
    """What one draw of ``n_starts`` starts (`rung_draws`) holds, in words: ``start`` (the
    guess: "the given start", "the data-driven start"), its jittered copies and the starts drawn
    at random ("the given start, 7 jittered copies of it and 8 drawn at random"), ``at_limit`` of
    them with an element at its limit (`limit_draw_count`). Only the parameters neither fixed
    nor given are jittered: with every free one given, the draw runs the given start once
    (`draw_size`), and the words say why there are no copies."""
    n_jitter, n_random = start_split(n_starts)
    if not n_jitter:
        copies = start
    elif not _nothing_to_jitter(table):
        copies = f"{start}, {n_jitter} jittered cop{'y' if n_jitter == 1 else 'ies'} of it"
    else:
        copies = f"{start} (every free parameter given: none to jitter)"
    limits = f" ({at_limit} of them with an element at its limit)" if at_limit else ""
    return f"{copies} and {n_random} drawn at random{limits}" if n_random else copies


def rung_draws(circuit, table, features, n_starts, seeds, registry) -> list[np.ndarray]:
    """`random_starts`' ``n_starts`` starts for each of ``seeds`` (parameter values; the
    numbers of `multistart` with each seed), the guess and the draws' ranges computed once;
    some of the random starts with an element at its limit (`_some_at_limits`). Where nothing
    is jittered, each draw holds the guess once and its random starts (`draw_size`): copies
    of the guess would run the same local fit 8 times per draw of 16."""
    guess = data_driven_guess(circuit, table, features, registry)
    ranges = _draw_ranges(table, features)
    limits = _limits_of_free_elements(circuit, table, registry)
    n_jitter, _ = start_split(n_starts)
    copies = slice(1, 1 + n_jitter) if draw_size(table, n_starts) < n_starts else slice(1, 1)
    return [np.delete(_some_at_limits(random_starts(table, features, guess, n_starts, seed, ranges=ranges), limits, table, features, n_starts), copies, axis=-2) for seed in seeds]


# one random start in this many of a draw has an element moved to its limit (`_some_at_limits`)
LIMIT_DRAW_EVERY = 4


def _limit_draws(n_random: int, i: int) -> list[int]:
    """Which of a draw's ``n_random`` random starts hold the ``i``-th element with a limit at it."""
    return [j for j in range(n_random) if (j + i) % LIMIT_DRAW_EVERY == LIMIT_DRAW_EVERY - 1]


def limit_draw_count(circuit: Circuit, table: ParameterTable, registry: Registry, n_starts: int) -> int:
    """How many of one draw's random starts hold an element at its limit (`_some_at_limits`)."""
    _, n_random = start_split(n_starts)
    return len({j for i in range(len(_limits_of_free_elements(circuit, table, registry))) for j in _limit_draws(n_random, i)})


def _some_at_limits(starts: np.ndarray, limits, table: ParameterTable, features: SpectrumFeatures, n_starts: int) -> np.ndarray:
    """``starts`` (one draw of `random_starts`: (n, P) or (B, n, P)) with one random start in
    `LIMIT_DRAW_EVERY` holding an element moved into its limit (``limits``:
    `_limits_of_free_elements`; `ElementLimit.toward`: a Wo or Ws at τ = 200/ω_min, a G deeper,
    the Warburg coefficient of its drawn values kept; the i-th such element in the random starts j with
    (j + i) mod 4 = 3). Draws of τ over the data's band never come
    near that limit, and a start from the ladder's optimum moved there (`limit_starts`) keeps
    that optimum's roles: on REAL battery cycle 64 (AutoEIS) the G model's ladder stopped at
    rms_rel 1.173 %, its limit start at 4.71 %, where 21 of 30 random starts with G at its limit
    reach the 1.130 % of the W limit (2026-12-04)."""
    if not limits:
        return starts
    n_jitter, n_random = start_split(n_starts)
    omega = 2 * np.pi * features._f
    out = np.array(starts, float)
    for i, (index, limit) in enumerate(limits):
        chosen = [1 + n_jitter + j for j in _limit_draws(n_random, i)]
        if not chosen:
            continue
        moved = limit.toward(tuple(out[..., chosen, k] for k in index), float(omega.min()), float(omega.max()))
        for k, value in zip(index, moved):
            out[..., chosen, k] = value
    return _clip_inside(out, table)


# the start ladder of a poor fit, as multiples of ``n_starts`` (16, 64 and 256 starts by
# default); each rung draws new starts (its own seed) and stops the climb once the fit is no
# longer poor. The trap of AutoEIS's test spectrum with R0 + R1 || CPE1 + (R2 + W1) || CPE2
# (rms_rel 4.9 % where 1.3 % is attainable) escapes 16 starts and is found by 64
ESCALATION_RUNGS = (1, 4, 16)
# circuits of this many free parameters or more climb one rung further (64 draws: 1,024 starts
# by default): their starts spread over a space of twelve and more dimensions, and the
# evaluation set's 8-element ladder (12 free parameters) reached its global optimum with this
# rung where 336 starts left it 2.3× above it (docs/fitting.md, "Starts")
LARGE_CIRCUIT_FREE = 12
LARGE_CIRCUIT_RUNG = 64


def escalation_rungs(n_free: int) -> tuple[int, ...]:
    """The ladder's rungs (multiples of ``n_starts``) for a fit of ``n_free`` free parameters:
    `ESCALATION_RUNGS`, and `LARGE_CIRCUIT_RUNG` after them from `LARGE_CIRCUIT_FREE` on."""
    return ESCALATION_RUNGS + ((LARGE_CIRCUIT_RUNG,) if n_free >= LARGE_CIRCUIT_FREE else ())

# a fit is poor relative to the data when its rms_rel exceeds this multiple of the misfit of
# the linear Kramers–Kronig test's Voigt chain (`attainable_misfit`): a circuit at its global
# optimum may well miss the data by more (too few elements), but a fit far above it has
# room to improve, so the climb continues (docs/fitting.md, "Starts": at 1.5 a finger circuit
# stopped in a local minimum at 1.45× where its optimum is 1.02×)
KK_MISFIT_FACTOR = 1.2
# ... and never below this rms_rel (0.01 %): a fit that close to the data (noise-free or
# typed-in spectra) has nothing left for more starts to find
ESCALATION_FLOOR = 1e-4
# in a batch of at least `batch.REFERENCE_MIN_SPECTRA` spectra, a fit is poor relative to the
# others when its rms_rel exceeds this multiple of their median (or it did not converge)
BATCH_OUTLIER_FACTOR = 1.5


def rung_seed(seed: int, rung: int, call: int) -> int:
    """The seed of the ``call``-th draw of starts on ``rung`` of the ladder (rung 0: ``seed``)."""
    return seed if rung == 0 else seed + 7919 * rung + call


def attainable_misfit(freq, z) -> np.ndarray:
    """rms_rel (B,) of the linear Kramers–Kronig test's fit (a Voigt chain with a series R, L
    and C; `kk.kk_misfits`) of each spectrum of the stack z (B, N): what a flexible
    KK-consistent model leaves, the yardstick of `KK_MISFIT_FACTOR`. 0 where the test cannot
    run (too few points): every rung is then climbed (down to `ESCALATION_FLOOR`)."""
    z = np.atleast_2d(z)
    try:
        return kk_misfits((np.asarray(freq, float), z)).reshape(len(z))
    except ImpedaxError:
        return np.zeros(len(z))


def climb_target(freq, z, attainable=None) -> np.ndarray:
    """The rms_rel (B,) above which a fit of spectra z (B, N) climbs the next rung:
    `KK_MISFIT_FACTOR` × `attainable_misfit` (``attainable``, when the fit call's `kk.KKChains`
    knows it), at least `ESCALATION_FLOOR`."""
    return np.maximum(KK_MISFIT_FACTOR * (attainable_misfit(freq, z) if attainable is None else np.asarray(attainable, float)), ESCALATION_FLOOR)


def rms_rel_of(z_model, z) -> np.ndarray:
    """rms_rel = sqrt(mean |(Z_model − Z)/|Z||²) over the last axis."""
    with np.errstate(all="ignore"):
        rms = np.sqrt(np.mean(np.abs((np.asarray(z_model) - z) / np.abs(z)) ** 2, axis=-1))
    return np.where(np.isfinite(rms), rms, np.inf)


def batch_outliers(rms_rel: np.ndarray, converged: np.ndarray) -> np.ndarray:
    """Indices of the fits of a batch that are poor relative to the others: not converged, or
    rms_rel above `BATCH_OUTLIER_FACTOR` × the median of the converged ones."""
    ok = converged & np.isfinite(rms_rel)
    typical = np.median(rms_rel[ok]) if ok.any() else np.inf
    return np.flatnonzero(~ok | (rms_rel > BATCH_OUTLIER_FACTOR * typical))
