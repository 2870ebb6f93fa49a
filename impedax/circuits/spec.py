"""What impedax knows about an element: `ParameterSpec`, `ElementSpec` and the `Registry`.

An element is one declaration: symbol, name, equation, parameters (unit, default, bounds,
description, role in starting guesses), a pure JAX impedance function, and the facts other
code needs — whether it passes DC (diagnosis), how it is drawn (diagrams), its letter in
Boukamp's CDC and its symbol in impedance.py (converters), and how many slots the padded
fitting program reserves for it. Every fact has a default, so a user's element works in
compiling, fitting, diagnosis, drawing and conversion without edits anywhere else.
The registry is an immutable value; `Registry.register` returns a new registry.
"""

from __future__ import annotations

import enum
import inspect
import math
import numbers
import re
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Callable, Iterator, Mapping

import numpy as np

from ..arguments import number_text
from ..errors import CircuitError

if TYPE_CHECKING:  # (JAX is imported where an impedance is first evaluated: a registry is read without it)
    import jax.numpy as jnp

__all__ = ["ParameterSpec", "ElementLimit", "ElementSpec", "Registry", "DCPath", "StartRole", "MAX_ELEMENT_PARAMS", "ADDING_AN_ELEMENT", "PASS_OWN_REGISTRY", "PASS_DECLARING_REGISTRY"]

# the words that send a user to declare an element of their own, in Python's terms (the
# command line says the same in its own, --plugin FILE.py: `impedax.cli.common.plugin_words`)
ADDING_AN_ELEMENT = '(docs/circuits.md, "Adding an element")'
PASS_OWN_REGISTRY = ("an element of your own registry: pass it here too, "
                     "e.g. circuit.parameter_names(registry), compile_circuit(circuit, registry), fit(..., registry=registry)")
PASS_DECLARING_REGISTRY = "pass the registry that declares it (registry= in Python)"

MAX_ELEMENT_PARAMS = 4  # Havriliak–Negami has four; the padded fitting program relies on this
_SYMBOL_RE = re.compile(r"[A-Z][A-Za-z]*\Z")
_SUFFIX_RE = re.compile(r"[A-Za-z][A-Za-z0-9]*\Z")
_CDC_RE = re.compile(r"[A-Z]\Z")
_IMPEDANCE_PY_RE = re.compile(r"[A-Za-z]+\Z")
_DRAW_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
# where the built-in elements' formulas live (a clash with one says "built-in"; that module
# imports this one, so it is named, not imported)
BUILT_IN_MODULE = f"{__package__}.elements"


class DCPath(enum.StrEnum):
    """How an element behaves at DC (ω → 0)."""

    CONDUCTS = "conducts"  # a finite, non-zero DC resistance: R, Ws, G, Cole–Cole, HN
    BLOCKS = "blocks"  # |Z| → ∞: C, CPE, W, Wo
    SHORTS = "shorts"  # |Z| → 0: L


class StartRole(enum.StrEnum):
    """What a parameter is, for the data-driven starting guess (`impedax.fitting`'s starts).

    Inside an arc (a parallel block of the outer series chain) an element's resistances share
    the arc's resistance and its time constants are the arc's; in the outer chain:
    """

    RESISTANCE = "resistance"  # a resistor: the high-frequency intercept, shared by the chain's resistors
    ARC_RESISTANCE = "arc_resistance"  # a dispersion's own resistance: the spectrum's total arc resistance
    CAPACITANCE = "capacitance"  # τ/R of its arc; in the chain, from Z'' at the lowest frequency
    ARC_CAPACITANCE = "arc_capacitance"  # a dispersion's own capacitance: τ/R of its arc, or of the spectrum's
    INDUCTANCE = "inductance"  # from positive Z'' at the highest frequencies
    CPE_Q = "cpe_q"  # C·ω^(1−α) with C and α as for a capacitance and a CPE exponent
    CPE_EXPONENT = "cpe_exponent"  # 0.85 in an arc; in the chain, the low-frequency slope of log −Z''
    EXPONENT = "exponent"  # a broadening exponent: 0.85
    WARBURG = "warburg"  # σ from |Z| √ω at the lowest frequencies
    TIME_CONSTANT = "time_constant"  # 1/(2π f_peak) of its arc, or of the largest −Z'' peak
    DEFAULT = "default"  # the parameter's declared default


# the role of a parameter that declares none, by its unit
_ROLE_BY_UNIT = {
    "Ohm": StartRole.ARC_RESISTANCE,
    "F": StartRole.CAPACITANCE,
    "H": StartRole.INDUCTANCE,
    "s": StartRole.TIME_CONSTANT,
    "1": StartRole.EXPONENT,
}


class _Required:
    """The marker of a `ParameterSpec` built without a default."""

    def __repr__(self) -> str:
        return "<required>"


_NO_DEFAULT = _Required()


@dataclass(frozen=True)
class ParameterSpec:
    """One parameter of an element.

    ``suffix`` is ``None`` for an element whose single parameter is named after the element
    itself (``R_sc``); otherwise the full name is ``f"{element}.{suffix}"`` (``CPE_sc.alpha``).
    Bounds are open at ``lower``; ``upper`` is inclusive when ``upper_inclusive``.
    ``role`` says how the data-driven starting guess finds a value (`StartRole`); ``None``
    infers it from the unit (Ohm: arc resistance, F: capacitance, H: inductance, s: time
    constant, 1: exponent, anything else: the default), see `start_role`.
    Refused when declared (`CircuitError` naming the parameter and the field): bounds or default
    that are not numbers, ``lower >= upper``, a default that is not finite or outside its bounds.
    """

    suffix: str | None
    unit: str
    default: float = _NO_DEFAULT  # (required; the marker only lets a unit left out be named: `_unit_hint`)
    lower: float = 0.0
    upper: float = math.inf
    description: str = ""
    upper_inclusive: bool = False
    role: StartRole | None = None

    def __post_init__(self):
        what = self.label
        if self.suffix is not None and not isinstance(self.suffix, str):
            raise CircuitError(f"parameter suffix must be text or None (the element's single parameter), got {_value_text(self.suffix)}")
        if self.default is _NO_DEFAULT:
            if isinstance(self.unit, str):
                raise CircuitError(f"{what}: no default: its starting value comes third, ParameterSpec({self.suffix!r}, {self.unit!r}, DEFAULT)")
            raise CircuitError(f"{what}: no unit: ParameterSpec({self.suffix!r}, {self.unit!r}) takes {self.unit!r} for the unit and has no default; "
                               f"{self._unit_hint(self.unit)}")
        for name in ("unit", "description"):
            if not isinstance(getattr(self, name), str):
                hint = f"; {self._unit_hint(self.unit)}" if name == "unit" and isinstance(self.unit, numbers.Real) else ""
                raise CircuitError(f"{what}: {name} must be text, got {_value_text(getattr(self, name))}{hint}")
        if not isinstance(self.upper_inclusive, bool):
            raise CircuitError(f"{what}: upper_inclusive must be True or False, got {_value_text(self.upper_inclusive)}")
        for name in ("default", "lower", "upper"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real):
                raise CircuitError(f"{what}: {name} must be a number, got {_value_text(value)}")
            object.__setattr__(self, name, float(value))
        if math.isnan(self.lower) or math.isnan(self.upper) or self.lower == math.inf or self.upper == -math.inf:
            raise CircuitError(f"{what}: bounds must be numbers (lower may be -inf, upper inf), got lower={self.lower}, upper={self.upper}")
        if not self.lower < self.upper:
            raise CircuitError(f"{what}: lower={number_text(self.lower)} must be below upper={number_text(self.upper)}")
        if not math.isfinite(self.default):
            raise CircuitError(f"{what}: default must be a finite number, got {self.default}")
        if not self.contains(self.default):
            raise CircuitError(f"{what}: default={number_text(self.default)} is outside its bounds {self.bounds_text()}")
        if self.role is not None:
            object.__setattr__(self, "role", _enum_value(StartRole, self.role, f"{what}: start role"))

    def _unit_hint(self, default) -> str:
        """How to write this parameter with its unit second (a number given where the unit goes)."""
        return f"the unit comes second: ParameterSpec({self.suffix!r}, UNIT, {default!r}), UNIT text such as 'Ohm', 'F', 's' or '1' (none)"

    @property
    def label(self) -> str:
        """How messages name it: ``parameter 'tau'``, or ``the unnamed parameter``."""
        return "the unnamed parameter" if self.suffix is None else f"parameter {self.suffix!r}"

    @property
    def start_role(self) -> StartRole:
        """The declared role, or the one inferred from the unit."""
        if self.role is not None:
            return self.role
        return _ROLE_BY_UNIT.get(self.unit, StartRole.DEFAULT)

    def narrowed_sides(self, lower: float | None, upper: float | None) -> frozenset[str]:
        """The sides ("lower", "upper") on which the bounds (``lower``, ``upper``; None: not
        given) differ from this parameter's own: the bounds a user set (``bounds=``,
        ``--bound``). ``R1=:10M`` narrows only R1's "upper" (its lower is R's own 0)."""
        return frozenset(side for side, value, own in (("lower", lower, self.lower), ("upper", upper, self.upper)) if value is not None and float(value) != float(own))

    def full_name(self, element_name: str) -> str:
        return element_name if self.suffix is None else f"{element_name}.{self.suffix}"

    def contains(self, value: float) -> bool:
        if not math.isfinite(value) or value <= self.lower:
            return False
        return value <= self.upper if self.upper_inclusive else value < self.upper

    def bounds_text(self) -> str:
        right = "]" if self.upper_inclusive else ")"
        return f"({number_text(self.lower)}, {number_text(self.upper)}{right}"


@dataclass(frozen=True)
class ElementLimit:
    """An element's reduction to a simpler element in a limit of its parameters: a Wo is a W
    as τ → ∞, a CPE a capacitor at α = 1 (docs/circuits.md, "Elements that contain others").

    ``symbol``: the simpler element; ``where``: the limit in words (``"tau -> inf"``);
    ``values(params, omega_min, omega_max)``: this element's parameters (a tuple in declaration
    order) that give the simpler element's impedance with parameters ``params`` (a tuple, of
    numbers or of numpy arrays over spectra) within ω_min..ω_max [rad/s] to about 1e-6
    relative: what a fit of the larger circuit starts from to reach at least the smaller one's
    optimum (`impedax.circuits.nesting.carried_values`). ``toward(params, omega_min,
    omega_max)``, optional: this element's own parameters moved into the limit, keeping what the
    data see of it (a Wo's R/√τ, its Warburg coefficient at high frequency, as τ → 200/ω_min): a
    batch of fits also solves each spectrum from its optimum so moved, as a limit at τ → ∞ is one
    no step of the solver reaches (`least_squares.batch`). ``edge(params, omega_min, omega_max)``,
    optional: the element just off its limit with the same kept, where it starts to differ from
    the simpler one inside the window (a Wo's knee at ω_min·τ = 3): a start from which a fit at
    the limit finds an optimum near it (`least_squares.starts.limit_starts`)."""

    symbol: str
    where: str
    values: Callable[..., tuple]
    toward: Callable[..., tuple] | None = None
    edge: Callable[..., tuple] | None = None

    def __post_init__(self):
        if not isinstance(self.symbol, str) or not _SYMBOL_RE.match(self.symbol):
            raise CircuitError(f"ElementLimit: symbol must be an element symbol (e.g. 'W'), got {_value_text(self.symbol)}")
        if not isinstance(self.where, str):
            raise CircuitError(f"ElementLimit {self.symbol}: where must be text (e.g. 'tau -> inf'), got {_value_text(self.where)}")
        if not callable(self.values):
            raise CircuitError(f"ElementLimit {self.symbol}: values must be a function f(params, omega_min, omega_max) -> this element's parameters, got {_value_text(self.values)}")
        for name in ("toward", "edge"):
            if getattr(self, name) is not None and not callable(getattr(self, name)):
                raise CircuitError(f"ElementLimit {self.symbol}: {name} must be None or a function f(params, omega_min, omega_max) -> this element's parameters, got {_value_text(getattr(self, name))}")


@dataclass(frozen=True)
class ElementSpec:
    """Declaration of one circuit element.

    ``impedance(omega, *params)`` takes the angular frequency ω [rad/s] and the parameters in
    declaration order and returns the complex impedance [Ω]; it must be pure JAX.
    ``admittance(omega, *params)``, optional, returns 1/Z [S] where that is the simpler
    formula (R, C, CPE): parallel nodes sum admittances, so it saves a division per frequency.

    Facts for the rest of impedax, each optional:

    * ``dc``: `DCPath` (or its value, ``"conducts"``, ``"blocks"``, ``"shorts"``); ``None``
      infers it from the impedance at the default parameters (`dc_path`);
    * ``draw``: the schemdraw element that draws it (``"Resistor"``); ``None``: a labelled box;
    * ``cdc``: its letter in Boukamp's circuit description code, ``impedance_py`` its symbol in
      impedance.py; ``None``: the notation cannot express it and converters refuse it;
    * ``program_capacity``: slots reserved for it in the smallest padded program layout
      (`impedax.circuits.ProgramLayout.sized`; larger layouts multiply it).
    * ``limits``: `ElementLimit` of each simpler element it reduces to (a Wo to a W as τ → ∞):
      a circuit with the simpler one in its place is nested in it (model comparison), and a
      fit of it can start from that circuit's optimum (`impedax.circuits.nesting`).

    ``parameters`` may be given as a list (or one `ParameterSpec` alone); formulas whose
    signature cannot take ω and one argument per parameter are refused when declared.
    """

    symbol: str
    name: str
    equation: str
    parameters: tuple[ParameterSpec, ...]
    impedance: Callable[..., jnp.ndarray]
    aliases: tuple[str, ...] = ()
    admittance: Callable[..., jnp.ndarray] | None = None
    dc: DCPath | None = None
    draw: str | None = None
    cdc: str | None = None
    impedance_py: str | None = None
    program_capacity: int = 2
    limits: tuple[ElementLimit, ...] = ()

    def __post_init__(self):
        if not isinstance(self.symbol, str):
            raise CircuitError(f"element symbol must be text, got {_value_text(self.symbol)}")
        for name in ("name", "equation"):
            if not isinstance(getattr(self, name), str):
                raise CircuitError(f"element {self.symbol}: {name} must be text, got {_value_text(getattr(self, name))}")
        if isinstance(self.aliases, str):
            raise CircuitError(f"element {self.symbol}: aliases must be a tuple of symbols, e.g. ({self.aliases!r},), got the text {self.aliases!r}")
        object.__setattr__(self, "aliases", tuple(self.aliases))
        for sym in (self.symbol, *self.aliases):
            if not isinstance(sym, str) or not _SYMBOL_RE.match(sym):
                raise CircuitError(
                    f"element symbol {sym!r} must be a capital letter followed by letters only "
                    "(digits and '_' start the element's label)"
                )
        self._check_parameters()
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
        self._check_formulas()
        self._check_facts()

    def _check_parameters(self) -> None:
        """``parameters`` as a tuple of `ParameterSpec` (a list, or one spec alone, is taken)."""
        parameters = self.parameters
        if isinstance(parameters, ParameterSpec):
            parameters = (parameters,)
        elif isinstance(parameters, list):
            parameters = tuple(parameters)
        if not isinstance(parameters, tuple):
            raise CircuitError(f"element {self.symbol}: parameters must be a tuple of ParameterSpec, got {_value_text(parameters)}")
        for i, p in enumerate(parameters):
            if not isinstance(p, ParameterSpec):
                raise CircuitError(f"element {self.symbol}: parameters[{i}] must be a ParameterSpec(suffix, unit, default, ...), got {_value_text(p)}")
        object.__setattr__(self, "parameters", parameters)

    def _check_formulas(self) -> None:
        """``impedance`` (and ``admittance`` when given) callable with ω and one argument per
        parameter, where the signature can be read (``*args`` takes any number)."""
        count = len(self.parameters)
        for name in ("impedance", "admittance"):
            formula = getattr(self, name)
            if formula is None and name == "admittance":
                continue
            if not callable(formula):
                raise CircuitError(f"element {self.symbol}: {name} must be a function f(omega, {', '.join(self._argument_names())}), got {_value_text(formula)}")
            try:
                signature = inspect.signature(formula)
            except (TypeError, ValueError):  # (a builtin or C function: nothing to check)
                continue
            try:
                signature.bind(*range(count + 1))
            except TypeError:
                takes = [p.name for p in signature.parameters.values() if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
                raise CircuitError(
                    f"element {self.symbol}: its {name} function takes ({', '.join(takes)}), but it is called as "
                    f"f(omega, {', '.join(self._argument_names())}): omega and one argument per parameter ({count})"
                ) from None

    def _argument_names(self) -> list[str]:
        return [p.suffix or self.symbol.lower() for p in self.parameters]

    def _check_facts(self) -> None:
        if self.dc is not None:
            object.__setattr__(self, "dc", _enum_value(DCPath, self.dc, f"element {self.symbol}: dc"))
        for value, pattern, what in (
            (self.cdc, _CDC_RE, "a CDC letter is one capital letter"),
            (self.impedance_py, _IMPEDANCE_PY_RE, "an impedance.py symbol is letters only"),
            (self.draw, _DRAW_RE, "draw names a schemdraw element, e.g. 'Resistor'"),
        ):
            if value is not None and not (isinstance(value, str) and pattern.match(value)):
                raise CircuitError(f"element {self.symbol}: bad value {value!r}: {what}")
        if not isinstance(self.program_capacity, int) or self.program_capacity < 1:
            raise CircuitError(f"element {self.symbol}: program_capacity must be a positive integer")
        limits = (self.limits,) if isinstance(self.limits, ElementLimit) else self.limits
        if not isinstance(limits, (tuple, list)) or not all(isinstance(x, ElementLimit) for x in limits):
            raise CircuitError(f"element {self.symbol}: limits must be a tuple of ElementLimit(symbol, where, values), got {_value_text(self.limits)}")
        object.__setattr__(self, "limits", tuple(limits))

    def parameter_names(self, element_name: str) -> tuple[str, ...]:
        return tuple(p.full_name(element_name) for p in self.parameters)

    @property
    def start_roles(self) -> tuple[StartRole, ...]:
        """Each parameter's `StartRole`, in declaration order."""
        return tuple(p.start_role for p in self.parameters)

    @cached_property
    def dc_path(self) -> DCPath:
        """The declared ``dc``, or inferred from |Z| at the default parameters at two tiny
        angular frequencies ω₁ = 1e-9 rad/s and ω₂ = 1e-12 rad/s: |Z(ω₂)|/|Z(ω₁)| above 2
        (|Z| ∝ ω^−a with a > 0.1) blocks, below 1/2 shorts, anything between conducts.
        Declare ``dc`` for an element whose defaults put a time constant beyond ~10⁸ s."""
        if self.dc is not None:
            return self.dc
        import jax.numpy as jnp

        omega = np.array([1e-9, 1e-12])
        z = np.abs(np.asarray(self.impedance(jnp.asarray(omega), *(p.default for p in self.parameters))))
        z = np.broadcast_to(z, omega.shape)
        if np.isnan(z).any():
            raise CircuitError(f"element {self.symbol}: cannot infer its DC behaviour (NaN impedance at ω → 0); declare dc=")
        if z[1] > 2.0 * z[0]:  # also z[1] = inf
            return DCPath.BLOCKS
        if z[1] < 0.5 * z[0] or z[1] == 0.0:
            return DCPath.SHORTS
        return DCPath.CONDUCTS


@dataclass(frozen=True)
class Registry:
    """An immutable set of element specs, looked up by symbol (aliases included)."""

    specs: tuple[ElementSpec, ...]

    def __post_init__(self):
        if not isinstance(self.specs, tuple):
            object.__setattr__(self, "specs", tuple(self.specs))
        for spec in self.specs:
            if not isinstance(spec, ElementSpec):
                raise CircuitError(f"a Registry holds ElementSpec declarations, got {_value_text(spec)}")
        _check_unique([sym for spec in self.specs for sym in (spec.symbol, *spec.aliases)], "element symbol")
        _check_unique([spec.cdc for spec in self.specs if spec.cdc is not None], "CDC letter")
        _check_unique([spec.impedance_py for spec in self.specs if spec.impedance_py is not None], "impedance.py symbol")

    def __hash__(self) -> int:
        return self._hash

    def __repr__(self) -> str:
        # short: a registry is the default of many functions' `registry=`, and help() printed
        # every spec's fields (kilobytes) in their signatures
        return f"Registry({len(self.specs)} elements: {', '.join(spec.symbol for spec in self.specs)})"

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

    @cached_property
    def by_cdc(self) -> Mapping[str, ElementSpec]:
        """CDC letter → spec, for the elements that have one."""
        return {s.cdc: s for s in self.specs if s.cdc is not None}

    @cached_property
    def by_impedance_py(self) -> Mapping[str, ElementSpec]:
        """impedance.py symbol → spec, for the elements that have one."""
        return {s.impedance_py: s for s in self.specs if s.impedance_py is not None}

    @cached_property
    def impedance_py_symbols(self) -> Mapping[str, str]:
        """impedance.py symbol → impedax symbol, where they differ (``Zarc`` → ``CC``): how an
        impedance.py parameter name (``Zarc1_2``) is read in a hint (`impedax.arguments.closest_name`)."""
        return {s.impedance_py: s.symbol for s in self.specs if s.impedance_py is not None and s.impedance_py != s.symbol}

    def __contains__(self, symbol: str) -> bool:
        return symbol in self._by_symbol

    def __getitem__(self, symbol: str) -> ElementSpec:
        try:
            return self._by_symbol[symbol]
        except KeyError:
            raise CircuitError(
                f"unknown element symbol {symbol!r}; known: {self.symbols()} ({PASS_OWN_REGISTRY})"
            ) from None

    def __iter__(self) -> Iterator[ElementSpec]:
        return iter(self.specs)

    def symbols(self) -> tuple[str, ...]:
        return tuple(sorted(self._by_symbol, key=lambda s: (-len(s), s)))

    def kind_index(self, symbol: str) -> int:
        """Position of the element's spec in ``specs`` (used by the padded fitting program)."""
        spec = self[symbol]
        return self.specs.index(spec)

    def register(self, spec: ElementSpec) -> "Registry":
        """Return a new registry with ``spec`` added (the original is unchanged). A symbol,
        alias, CDC letter or impedance.py symbol already taken is refused naming who has it."""
        if not isinstance(spec, ElementSpec):
            raise CircuitError(f"Registry.register expects an ElementSpec(symbol, name, equation, parameters, impedance), got {_value_text(spec)}")
        for what, taken, wanted in (
            ("element symbol", self._by_symbol, (spec.symbol, *spec.aliases)),
            ("CDC letter", self.by_cdc, (spec.cdc,)),
            ("impedance.py symbol", self.by_impedance_py, (spec.impedance_py,)),
        ):
            for value in wanted:
                holder = taken.get(value)
                if holder is None:
                    continue
                whose = "the built-in" if getattr(holder.impedance, "__module__", None) == BUILT_IN_MODULE else "this registry's"
                ours = "symbol" if what == "element symbol" else what
                called = holder.name if holder.name.endswith("element") else f"{holder.name} element"
                raise CircuitError(
                    f"element {spec.symbol}: {what} {value!r} is already taken by {whose} {called} "
                    f"({holder.symbol}: {holder.equation}); choose another {ours}"
                )
        return Registry(self.specs + (spec,))


def _value_text(value) -> str:
    """A value in a message: its type and a short repr (``str '0'``, ``function``)."""
    text = repr(value)
    return f"{type(value).__name__} {text if len(text) <= 60 else text[:57] + '...'}"


def _enum_value(kind: type[enum.StrEnum], value, what: str):
    try:
        return kind(value)
    except ValueError:
        raise CircuitError(f"{what} must be one of {', '.join(repr(m.value) for m in kind)}, got {value!r}") from None


def _check_unique(symbols: list[str], what: str) -> None:
    seen: set[str] = set()
    for sym in symbols:
        if sym in seen:
            raise CircuitError(f"{what} {sym!r} is declared twice")
        seen.add(sym)
