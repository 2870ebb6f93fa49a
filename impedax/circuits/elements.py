"""Element specifications and the registry that holds them.

An element is one declaration: symbol, name, equation, parameters (unit, default, bounds,
description) and a pure JAX impedance function ``impedance(omega, *params) -> complex``.
The registry is an immutable value; `Registry.register` returns a new registry.
Formulas: docs/physics.md, "Element formulas" (time dependence e^{jωt}).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable, Iterator, Mapping

import jax.numpy as jnp

from ..errors import CircuitError

__all__ = ["ParameterSpec", "ElementSpec", "Registry", "DEFAULT_REGISTRY", "MAX_ELEMENT_PARAMS"]

MAX_ELEMENT_PARAMS = 4  # Havriliak–Negami has four; the padded fitting program relies on this
_SYMBOL_RE = re.compile(r"[A-Z][A-Za-z]*\Z")
_SUFFIX_RE = re.compile(r"[A-Za-z][A-Za-z0-9]*\Z")


@dataclass(frozen=True)
class ParameterSpec:
    """One parameter of an element.

    ``suffix`` is ``None`` for an element whose single parameter is named after the element
    itself (``R_sc``); otherwise the full name is ``f"{element}.{suffix}"`` (``CPE_sc.alpha``).
    Bounds are open at ``lower``; ``upper`` is inclusive when ``upper_inclusive``.
    """

    suffix: str | None
    unit: str
    default: float
    lower: float = 0.0
    upper: float = math.inf
    description: str = ""
    upper_inclusive: bool = False

    def full_name(self, element_name: str) -> str:
        return element_name if self.suffix is None else f"{element_name}.{self.suffix}"

    def contains(self, value: float) -> bool:
        if not math.isfinite(value) or value <= self.lower:
            return False
        return value <= self.upper if self.upper_inclusive else value < self.upper

    def bounds_text(self) -> str:
        right = "]" if self.upper_inclusive else ")"
        return f"({self.lower:g}, {self.upper:g}{right}"


@dataclass(frozen=True)
class ElementSpec:
    """Declaration of one circuit element.

    ``impedance(omega, *params)`` takes the angular frequency ω [rad/s] and the parameters in
    declaration order and returns the complex impedance [Ω]; it must be pure JAX.
    ``admittance(omega, *params)``, optional, returns 1/Z [S] where that is the simpler
    formula (R, C, CPE): parallel nodes sum admittances, so it saves a division per frequency.
    """

    symbol: str
    name: str
    equation: str
    parameters: tuple[ParameterSpec, ...]
    impedance: Callable[..., jnp.ndarray] = field(compare=False)
    aliases: tuple[str, ...] = ()
    admittance: Callable[..., jnp.ndarray] | None = field(default=None, compare=False)

    def __post_init__(self):
        for sym in (self.symbol, *self.aliases):
            if not _SYMBOL_RE.match(sym):
                raise CircuitError(
                    f"element symbol {sym!r} must be a capital letter followed by letters only "
                    "(digits and '_' start the element's label)"
                )
        if not 1 <= len(self.parameters) <= MAX_ELEMENT_PARAMS:
            raise CircuitError(
                f"element {self.symbol} must have 1 to {MAX_ELEMENT_PARAMS} parameters"
            )
        suffixes = [p.suffix for p in self.parameters]
        if None in suffixes and len(suffixes) > 1:
            raise CircuitError(f"element {self.symbol}: only a single parameter may be unnamed")
        for s in suffixes:
            if s is not None and not _SUFFIX_RE.match(s):
                raise CircuitError(f"element {self.symbol}: bad parameter suffix {s!r}")
        if len(set(suffixes)) != len(suffixes):
            raise CircuitError(f"element {self.symbol}: duplicate parameter suffixes")

    def parameter_names(self, element_name: str) -> tuple[str, ...]:
        return tuple(p.full_name(element_name) for p in self.parameters)


@dataclass(frozen=True)
class Registry:
    """An immutable set of element specs, looked up by symbol (aliases included)."""

    specs: tuple[ElementSpec, ...]

    def __post_init__(self):
        seen: dict[str, str] = {}
        for spec in self.specs:
            for sym in (spec.symbol, *spec.aliases):
                if sym in seen:
                    raise CircuitError(f"element symbol {sym!r} is declared twice")
                seen[sym] = spec.symbol

    def __hash__(self) -> int:
        return self._hash

    @cached_property
    def _hash(self) -> int:
        # computed once: compiled solvers are cached by registry, and hashing every spec's
        # fields on each lookup cost more than a solver step
        return hash(self.specs)

    @cached_property
    def _by_symbol(self) -> Mapping[str, ElementSpec]:
        table = {}
        for spec in self.specs:
            for sym in (spec.symbol, *spec.aliases):
                table[sym] = spec
        return table

    def __contains__(self, symbol: str) -> bool:
        return symbol in self._by_symbol

    def __getitem__(self, symbol: str) -> ElementSpec:
        try:
            return self._by_symbol[symbol]
        except KeyError:
            raise CircuitError(f"unknown element symbol {symbol!r}; known: {self.symbols()}") from None

    def __iter__(self) -> Iterator[ElementSpec]:
        return iter(self.specs)

    def symbols(self) -> tuple[str, ...]:
        return tuple(sorted(self._by_symbol, key=lambda s: (-len(s), s)))

    def kind_index(self, symbol: str) -> int:
        """Position of the element's spec in ``specs`` (used by the padded fitting program)."""
        spec = self[symbol]
        return self.specs.index(spec)

    def register(self, spec: ElementSpec) -> "Registry":
        """Return a new registry with ``spec`` added (the original is unchanged)."""
        return Registry(self.specs + (spec,))


# --- element formulas -----------------------------------------------------------------------
# Powers of jω are written in polar form, (jx)^a = x^a e^{jπa/2}, which is exact, never
# overflows for x>0 and keeps gradients finite.


def _j_power(x, a):
    """(j x)^a for real x > 0 and real a."""
    return jnp.exp(a * jnp.log(x)) * jnp.exp(1j * (jnp.pi / 2) * a)


def _coth_over_x(x):
    """coth(x)/x for complex x with Re x > 0, without overflow: (1 + e^{-2x})/((1 − e^{-2x}) x)."""
    e = jnp.exp(-2.0 * x)
    return (1.0 + e) / (-jnp.expm1(-2.0 * x) * x)


def _tanh_over_x(x):
    """tanh(x)/x for complex x with Re x > 0, without overflow: (1 − e^{-2x})/((1 + e^{-2x}) x)."""
    e = jnp.exp(-2.0 * x)
    return -jnp.expm1(-2.0 * x) / ((1.0 + e) * x)


def _resistor(w, r):
    return r + 0j * w


def _resistor_admittance(w, r):
    return 1.0 / r + 0j * w


def _capacitor(w, c):
    return 1.0 / (1j * w * c)


def _capacitor_admittance(w, c):
    return 1j * w * c


def _inductor(w, l):  # noqa: E741 - L is the physics symbol
    return 1j * w * l


def _cpe(w, q, alpha):
    return 1.0 / (q * _j_power(w, alpha))


def _cpe_admittance(w, q, alpha):
    return q * _j_power(w, alpha)


def _warburg(w, sigma):
    return sigma * (1.0 - 1j) / jnp.sqrt(w)


def _warburg_open(w, r, tau):
    return r * _coth_over_x(jnp.sqrt(1j * w * tau))


def _warburg_short(w, r, tau):
    return r * _tanh_over_x(jnp.sqrt(1j * w * tau))


def _gerischer(w, r, tau):
    return r / jnp.sqrt(1.0 + 1j * w * tau)


def _cole_cole(w, r, tau, alpha):
    return r / (1.0 + _j_power(w * tau, alpha))


def _havriliak_negami(w, r, tau, alpha, beta):
    base = 1.0 + _j_power(w * tau, alpha)
    return r * jnp.exp(-beta * jnp.log(base))


_POS = dict(lower=0.0, upper=math.inf)
_FRACTION = dict(lower=0.0, upper=1.0, upper_inclusive=True)

DEFAULT_REGISTRY = Registry(
    (
        ElementSpec("R", "resistor", "Z = R", (ParameterSpec(None, "Ohm", 100.0, **_POS, description="resistance"),), _resistor, admittance=_resistor_admittance),
        ElementSpec("C", "capacitor", "Z = 1/(jωC)", (ParameterSpec(None, "F", 1e-6, **_POS, description="capacitance"),), _capacitor, admittance=_capacitor_admittance),
        ElementSpec("L", "inductor", "Z = jωL", (ParameterSpec(None, "H", 1e-6, **_POS, description="inductance"),), _inductor),
        ElementSpec(
            "CPE",
            "constant phase element",
            "Z = 1/(Q (jω)^α)",
            (
                ParameterSpec("Q", "F s^(alpha-1)", 1e-6, **_POS, description="CPE coefficient"),
                ParameterSpec("alpha", "1", 0.9, **_FRACTION, description="CPE exponent (1 = capacitor)"),
            ),
            _cpe,
            aliases=("Q",),
            admittance=_cpe_admittance,
        ),
        ElementSpec("W", "semi-infinite Warburg", "Z = σ(1 − j)/√ω", (ParameterSpec("sigma", "Ohm s^-1/2", 100.0, **_POS, description="Warburg coefficient"),), _warburg),
        ElementSpec(
            "Wo",
            "finite Warburg, open (reflective)",
            "Z = R coth(√(jωτ))/√(jωτ)",
            (ParameterSpec("R", "Ohm", 100.0, **_POS, description="diffusion resistance"), ParameterSpec("tau", "s", 1.0, **_POS, description="diffusion time constant")),
            _warburg_open,
        ),
        ElementSpec(
            "Ws",
            "finite Warburg, short (transmissive)",
            "Z = R tanh(√(jωτ))/√(jωτ)",
            (ParameterSpec("R", "Ohm", 100.0, **_POS, description="diffusion resistance"), ParameterSpec("tau", "s", 1.0, **_POS, description="diffusion time constant")),
            _warburg_short,
        ),
        ElementSpec(
            "G",
            "Gerischer",
            "Z = R/√(1 + jωτ)",
            (ParameterSpec("R", "Ohm", 100.0, **_POS, description="Gerischer resistance"), ParameterSpec("tau", "s", 1e-3, **_POS, description="time constant")),
            _gerischer,
        ),
        ElementSpec(
            "CC",
            "Cole–Cole relaxation",
            "Z = R/(1 + (jωτ)^α)",
            (
                ParameterSpec("R", "Ohm", 100.0, **_POS, description="relaxation strength"),
                ParameterSpec("tau", "s", 1e-3, **_POS, description="time constant"),
                ParameterSpec("alpha", "1", 0.9, **_FRACTION, description="broadening exponent"),
            ),
            _cole_cole,
        ),
        ElementSpec(
            "HN",
            "Havriliak–Negami relaxation",
            "Z = R/(1 + (jωτ)^α)^β",
            (
                ParameterSpec("R", "Ohm", 100.0, **_POS, description="relaxation strength"),
                ParameterSpec("tau", "s", 1e-3, **_POS, description="time constant"),
                ParameterSpec("alpha", "1", 0.9, **_FRACTION, description="symmetric broadening"),
                ParameterSpec("beta", "1", 0.9, **_FRACTION, description="asymmetric broadening"),
            ),
            _havriliak_negami,
        ),
    )
)
