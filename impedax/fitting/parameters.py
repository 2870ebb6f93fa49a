"""Parameter tables: names, bounds, fixed values, and the map to an unconstrained space.

A bounded parameter x is fitted through an unconstrained u (lmfit's idea, with a log scale
for positive quantities that span decades):

* `Transform.LOG`,          (0, ∞):          x = e^u
* `Transform.LOG_LOGISTIC`, (a, b), 0 < a:   log x = log a + (log b − log a)·s(u),  s = logistic
* `Transform.LOGISTIC`,     (a, b), a ≤ 0 or a fraction (unit "1"): x = a + (b − a)·s(u)
* `Transform.SHIFTED_LOG`,  (a, ∞), a > 0:   x = a + e^u
* `Transform.IDENTITY`,     (−∞, ∞):         x = u
"""

from __future__ import annotations

import enum
import functools
import math
from dataclasses import dataclass, field
from typing import Mapping

import jax.numpy as jnp
import numpy as np

from ..arguments import number_text, unknown_parameter
from ..circuits import Circuit, DEFAULT_REGISTRY, Registry
from ..circuits.nesting import carried_values
from ..errors import FitError, ParameterError
from .arcs import circuit_arcs
from .reductions import reducing_bounds, resistor_like_exponents, warburg_like_elements

__all__ = ["ParameterTable", "Transform", "starting_values", "to_external", "external_of_kind", "to_internal", "data_scales", "CPE_Q_UNIT", "checked_bounds", "outside_bounds_message"]


class Transform(enum.IntEnum):
    """How a parameter x is reached from the solver's unconstrained u (module docstring).
    Integer-valued: tables keep them in integer arrays and compiled solvers specialise on them."""

    LOG = 0
    LOG_LOGISTIC = 1
    LOGISTIC = 2
    SHIFTED_LOG = 3
    IDENTITY = 4

    @classmethod
    def for_bounds(cls, lower: float, upper: float, unit: str) -> "Transform":
        if math.isinf(lower) and math.isinf(upper):
            return cls.IDENTITY
        if lower == 0 and math.isinf(upper):
            return cls.LOG
        if lower > 0 and math.isinf(upper):
            return cls.SHIFTED_LOG
        if lower > 0 and unit != "1":
            return cls.LOG_LOGISTIC
        return cls.LOGISTIC


# how the impedance of an element scales with a parameter of this unit: the element alone has
# |Z| at angular frequency ω when x = |Z|^a · ω^b (R = |Z|, C = 1/(ω|Z|), L = |Z|/ω, τ = 1/ω,
# Warburg σ = |Z|·√ω); a CPE's Q = 1/(|Z| ω^α) with α anywhere in (0, 1]
UNIT_SCALING = {"Ohm": (1.0, 0.0), "F": (-1.0, -1.0), "H": (1.0, -1.0), "s": (0.0, -1.0), "Ohm s^-1/2": (1.0, 0.5)}
CPE_Q_UNIT = "F s^(alpha-1)"


def data_scales(unit: str, freq, z_abs) -> np.ndarray | None:
    """The values of a parameter of ``unit`` at which its element alone would have impedance
    ``z_abs`` [Ω] (..., N) at ``freq`` [Hz] (N,): (..., N), or (..., 2N) for a CPE's Q (α = 1
    and α → 0 at each point); None for a unit with no such scaling (a user element's, a
    physical parameter's, a dimensionless one)."""
    omega = 2 * np.pi * np.asarray(freq, float)
    z_abs = np.asarray(z_abs, float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if unit == CPE_Q_UNIT:  # α ∈ (0, 1]: ω^α lies between 1 and ω
            return np.concatenate([1.0 / z_abs, 1.0 / (z_abs * omega)], axis=-1)
        if unit in UNIT_SCALING:
            a, b = UNIT_SCALING[unit]
            return z_abs**a * omega**b
    return None


def starting_values(init, names: tuple[str, ...], circuit: Circuit | None = None, registry: Registry = DEFAULT_REGISTRY) -> Mapping[str, float] | None:
    """``init`` as name → value: a mapping as given, or a fit result (anything with a
    ``values`` mapping, e.g. a `FitResult`) whose fitted values become the starts of the
    parameters ``names`` that it has (the others are guessed from the data as usual). A fit of
    a circuit nested in ``circuit`` (a W where ``circuit`` has a Wo, an element fewer) starts
    the elements that stand for its own where its optimum lies (`nesting.carried_values`, over
    the fit's frequency range), so the new fit ends no higher than it."""
    if init is None or isinstance(init, Mapping):
        return init
    values = getattr(init, "values", None)
    if isinstance(values, Mapping):
        own = getattr(init, "circuit", None)
        frequency = getattr(init, "frequency", None)
        if circuit is not None and isinstance(own, Circuit) and frequency is not None and np.size(frequency):
            omega = 2 * np.pi * np.asarray(frequency, float)
            values = carried_values(own, values, circuit, float(omega.min()), float(omega.max()), registry)
        return {n: float(v) for n, v in values.items() if n in names}
    raise ParameterError(f"init: expected a mapping name → value or a FitResult, got {type(init).__name__}")


@dataclass(frozen=True, eq=False)
class ParameterTable:
    """Everything a fitter needs to know about a circuit's parameters (all arrays length P)."""

    names: tuple[str, ...]
    units: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    kind: np.ndarray  # `Transform` values
    fixed: np.ndarray  # bool
    values: np.ndarray  # fixed values and user starts (NaN where no start was given)
    reductions: Mapping[str, tuple[str, str]] = field(default_factory=dict)  # {name: (side, words)}: free parameters whose element's own bound on that side makes it a simpler one (`reductions.reducing_bounds`), as the bound notes name it
    resistor_like: Mapping[str, tuple[str, str, str | None]] = field(default_factory=dict)  # {alpha: (CPE, Q, R or None)}: free CPE exponents, whose element acts nearly as a resistor below `reductions.RESISTOR_LIKE_ALPHA` (`reductions.resistor_like_exponents`), as the fits' notes name it
    arcs: tuple[tuple[str, str, str, tuple[str, ...]], ...] = ()  # (R, C or CPE, its symbol, its parameters) of each R ∥ C and R ∥ CPE block with every parameter free (`arcs.circuit_arcs`), whose relaxation frequency the fits' notes hold against the band
    warburg_like: Mapping[str, tuple[str, str, str, str, str]] = field(default_factory=dict)  # {tau: (element, R, W, σ's unit, symbol)}: free τ of a Wo, Ws or G with its R free, which acts as a W within `reductions.WARBURG_LIKE_DEVIATION` (`reductions.warburg_like_elements`), as the fits' notes name it

    @functools.cached_property
    def free_names(self) -> tuple[str, ...]:
        return tuple(n for n, f in zip(self.names, self.fixed) if not f)

    @functools.cached_property
    def free_index(self) -> np.ndarray:
        index = np.flatnonzero(~self.fixed)
        index.setflags(write=False)
        return index

    @functools.cached_property
    def free_structure(self) -> tuple[tuple[int, ...], tuple[int, ...]]:
        """(positions, transform kinds) of the free parameters, as hashable tuples: what a
        compiled solver specialises on (`least_squares.solvers.tree_solver`)."""
        return tuple(self.free_index.tolist()), tuple(Transform(k) for k in self.kind[self.free_index].tolist())

    @classmethod
    def build(
        cls,
        circuit: Circuit,
        *,
        registry: Registry = DEFAULT_REGISTRY,
        init: Mapping[str, float] | None = None,
        fixed: Mapping[str, float] | None = None,
        bounds: Mapping[str, tuple[float, float]] | None = None,
    ) -> "ParameterTable":
        specs = circuit.parameter_specs(registry)
        names = tuple(specs)
        from_fit = init is not None and not isinstance(init, Mapping)  # (a fit's values: on or past this fit's bounds they are moved, not refused)
        init = starting_values(init, names, circuit, registry)
        for what, mapping in (("init", init), ("fixed", fixed), ("bounds", bounds)):
            for name in mapping or {}:
                if name not in specs:
                    raise unknown_parameter(what, name, names, circuit, impedance_py_symbols=registry.impedance_py_symbols)
        lower = np.array([specs[n].lower for n in names], float)
        upper = np.array([specs[n].upper for n in names], float)
        inclusive = np.array([specs[n].upper_inclusive for n in names])
        for name, (lo, hi) in (bounds or {}).items():
            i = names.index(name)
            lower[i], upper[i] = checked_bounds(name, lo, hi, specs[name])
            inclusive[i] = False
        values = np.full(len(names), np.nan)
        is_fixed = np.zeros(len(names), bool)
        for what, mapping in (("init", init), ("fixed", fixed)):
            for name, value in (mapping or {}).items():
                i = names.index(name)
                value = float(value)
                ok = math.isfinite(value) and value > lower[i] and (value <= upper[i] if inclusive[i] else value < upper[i])
                if not ok and what == "init" and from_fit:
                    value = nudged_inside(value, lower[i], upper[i])
                    if not math.isfinite(value):
                        continue
                elif not ok:
                    raise ParameterError(outside_bounds_message(what, name, value, lower[i], upper[i], bool(inclusive[i])))
                values[i] = value
                is_fixed[i] |= what == "fixed"
        kind = np.array([Transform.for_bounds(lower[i], upper[i], specs[n].unit) for i, n in enumerate(names)], np.int32)
        if is_fixed.all():
            raise FitError("every parameter is fixed; nothing to fit")
        reductions = {n: (side, words) for n, (side, words) in reducing_bounds(circuit, registry).items() if not is_fixed[names.index(n)] and (upper if side == "upper" else lower)[names.index(n)] == getattr(specs[n], side)}
        resistor_like = {n: what for n, what in resistor_like_exponents(circuit, registry).items() if not is_fixed[names.index(n)]}
        warburg_like = {n: what for n, what in warburg_like_elements(circuit, registry).items() if not is_fixed[names.index(n)] and not is_fixed[names.index(what[1])]}
        arcs = tuple(
            (r, c, symbol, params) for r, c, symbol in circuit_arcs(circuit, registry)
            for params in [registry[symbol].parameter_names(c) if symbol == "CPE" else (c,)] if not any(is_fixed[names.index(n)] for n in (r, *params))
        )
        return cls(names, tuple(specs[n].unit for n in names), lower, upper, kind, is_fixed, values, reductions, resistor_like, arcs, warburg_like)


def inner_edges(lower, upper) -> tuple[np.ndarray, np.ndarray]:
    """The points just inside bounds (``lower``, ``upper``; arrays or numbers), where a start
    on or past a bound is moved, as a start must lie strictly inside: 1e-6 of the bound
    (relative; of the span or absolute where the bound is ≤ 0 or ≥ 0), 1e-300 for a (0, ∞)
    parameter, which is fitted in log space (a floor of 1e-6 would lift every capacitance and
    CPE Q guess to 1 µF); ∞ where there is no upper bound."""
    lo, hi = np.asarray(lower, float), np.asarray(upper, float)
    with np.errstate(invalid="ignore"):
        low = np.where(lo > 0, lo * (1 + 1e-6), lo + 1e-6 * np.where(np.isfinite(hi), hi - lo, 1.0))
        low = np.where((lo == 0) & ~np.isfinite(hi), 1e-300, low)
        high = np.where(np.isfinite(hi), np.where(hi > 0, hi * (1 - 1e-6), hi - 1e-6), np.inf)
    return low, high


def nudged_inside(value: float, lower: float, upper: float) -> float:
    """A fitted ``value`` on or past a bound moved to the bound's `inner_edges`, as a start
    must lie strictly inside (a smaller model's R0 at 0, a τ carried to 200/ω_min where the
    user bounded it; a value at 0 of a (0, ∞) parameter to 1e-300); NaN where the value is
    not finite."""
    if not math.isfinite(value):
        return math.nan
    low, high = (float(e) for e in inner_edges(lower, upper))
    return min(max(value, low), high)


def checked_bounds(name: str, lower, upper, spec) -> tuple[float, float]:
    """The user's bounds (lower, upper) of parameter ``name`` (its element's `ParameterSpec`
    ``spec``) as floats: a `ParameterError` unless lower < upper within the element's own bounds."""
    lo, hi = float(lower), float(upper)
    if not lo < hi:
        raise ParameterError(f"bounds for {name}: lower {number_text(lo)} must be below upper {number_text(hi)}")
    if lo < spec.lower or hi > spec.upper:
        raise ParameterError(f"bounds for {name}: ({number_text(lo)}, {number_text(hi)}) reach outside the element's own bounds {spec.bounds_text()}")
    return lo, hi


def outside_bounds_message(what: str, name: str, value: float, lower: float, upper: float, inclusive: bool, unit: str = "") -> str:
    """The message for an ``init`` or ``fixed`` value (``what``) outside the bounds (lower,
    upper) (upper included when ``inclusive``), every number exact (`number_text`: 1.0000001 is
    not printed as 1). A value on an end the bounds exclude is told so: a start or a fixed value
    must lie strictly inside (the lower end is never included, nor the upper end of bounds you
    set; a CPE's α may be exactly 1). ``unit``: shown after the bounds, e.g. ``[Ω]``."""
    text = f"({number_text(lower)}, {number_text(upper)}{']' if inclusive else ')'}" + (f" [{unit}]" if unit else "")
    if value == lower or (value == upper and not inclusive):
        side = "lower" if value == lower else "upper"
        kind = {"init": "a starting value", "fixed": "a fixed value"}.get(what, "a value")
        return f"{what}: {name}={number_text(value)} is on its {side} bound, which its bounds {text} exclude: {kind} must lie strictly inside"
    return f"{what}: {name}={number_text(value)} is outside its bounds {text}"


def _logistic(u):
    return 1.0 / (1.0 + jnp.exp(-u))


def to_external(u, lower, upper, kind):
    """Unconstrained u → parameter x (elementwise; JAX). See the module docstring."""
    out = external_of_kind(u, lower, upper, Transform.LOG)
    for k in list(Transform)[1:]:
        out = jnp.where(kind == k, external_of_kind(u, lower, upper, k), out)
    return out


def external_of_kind(u, lower, upper, kind: Transform):
    """`to_external` for one transform ``kind`` known when tracing: only that formula is traced."""
    if kind == Transform.LOG:
        return jnp.exp(u)
    if kind == Transform.IDENTITY:
        return u
    finite_lo = jnp.where(jnp.isfinite(lower), lower, 0.0)
    if kind == Transform.SHIFTED_LOG:
        return finite_lo + jnp.exp(u)
    finite_hi = jnp.where(jnp.isfinite(upper), upper, 1.0)
    if kind == Transform.LOGISTIC:
        return finite_lo + (finite_hi - finite_lo) * _logistic(u)
    pos_lo = jnp.where(finite_lo > 0, finite_lo, 1.0)
    pos_hi = jnp.where(finite_hi > pos_lo, finite_hi, pos_lo * 10.0)
    return jnp.exp(jnp.log(pos_lo) + (jnp.log(pos_hi) - jnp.log(pos_lo)) * _logistic(u))


def to_internal(x, lower, upper, kind) -> np.ndarray:
    """Inverse of `to_external` (numpy, broadcasting), with x nudged strictly inside its bounds."""
    x, lower, upper, kind = np.broadcast_arrays(np.asarray(x, float), lower, upper, kind)

    def logit(s, eps):
        s = np.clip(s, eps, 1 - eps)
        return np.log(s / (1 - s))

    with np.errstate(all="ignore"):
        u0 = np.log(np.maximum(x, 1e-300))
        u1 = logit((np.log(x) - np.log(lower)) / (np.log(upper) - np.log(lower)), 1e-9)
        u2 = logit((x - lower) / (upper - lower), 1e-6)
        u3 = np.log(np.maximum(x - lower, 1e-300))
    t = Transform
    return np.select([kind == t.LOG, kind == t.LOG_LOGISTIC, kind == t.LOGISTIC, kind == t.SHIFTED_LOG], [u0, u1, u2, u3], x)
