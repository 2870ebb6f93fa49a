"""The immutable circuit tree: `Element`, `Series`, `Parallel`.

A tree holds no arrays; parameter values live apart from it, in a mapping name → value.
Constructors normalise: nested nodes of the same kind are flattened and one-child nodes
collapse, so ``parse(str(c)) == c`` holds for every tree. A tree writes itself in the impedax
circuit language (``str``), in Boukamp's CDC (`Circuit.to_cdc`) and as an impedance.py string
(`Circuit.to_impedance_py`); the readers of those notations are in `impedax.circuits.convert`.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass
from typing import Iterator

from ..errors import CircuitError
from .elements import DEFAULT_REGISTRY
from .spec import ParameterSpec, Registry

__all__ = ["Circuit", "Element", "Series", "Parallel", "series", "parallel"]


class Circuit:
    """Base class of every circuit node. Use `impedax.parse` or the node constructors."""

    __slots__ = ()

    def elements(self) -> Iterator["Element"]:
        """The elements, left to right."""
        raise NotImplementedError

    @property
    def element_names(self) -> tuple[str, ...]:
        return tuple(e.name for e in self.elements())

    def parameter_names(self, registry: Registry = DEFAULT_REGISTRY) -> tuple[str, ...]:
        """Parameter names in canonical order (element order, then declaration order)."""
        return tuple(n for e in self.elements() for n in registry[e.symbol].parameter_names(e.name))

    def parameter_specs(self, registry: Registry = DEFAULT_REGISTRY) -> dict[str, ParameterSpec]:
        """Mapping parameter name → its `ParameterSpec` (unit, default, bounds)."""
        out = {}
        for e in self.elements():
            spec = registry[e.symbol]
            for p in spec.parameters:
                out[p.full_name(e.name)] = p
        return out

    def defaults(self, registry: Registry = DEFAULT_REGISTRY) -> dict[str, float]:
        return {n: p.default for n, p in self.parameter_specs(registry).items()}

    def structure_key(self, registry: Registry = DEFAULT_REGISTRY) -> str:
        """The circuit without its element names: each element as its kind (an alias as the
        symbol it stands for: ``Q`` → ``CPE``), the parts of a series or parallel node in sorted
        order (impedances and admittances add in any order; nested nodes of one kind are
        flattened by the constructors). Two circuits with one key are one network under other
        names: ``R_a || C_a + R_b || C_b`` and ``C_x || R_x + R_y || C_y`` give
        ``series(parallel(C, R), parallel(C, R))``, while ``R1 + C1 || R2`` and
        ``(R1 + C1) || R2`` differ."""
        if isinstance(self, Element):
            return registry[self.symbol].symbol
        parts = sorted(c.structure_key(registry) for c in self.children)
        return f"{'series' if isinstance(self, Series) else 'parallel'}({', '.join(parts)})"

    def element(self, name: str) -> "Element":
        for e in self.elements():
            if e.name == name:
                return e
        raise CircuitError(f"no element named {name!r} in {self}; elements: {', '.join(self.element_names)}")

    def replace(self, name: str, new: "Circuit") -> "Circuit":
        """A new tree with element ``name`` replaced by the subcircuit ``new``."""
        self.element(name)
        return _replace(self, name, new)

    def without(self, name: str) -> "Circuit":
        """A new tree without element ``name``; a series or parallel node left with one child
        becomes that child."""
        self.element(name)
        if isinstance(self, Element):
            raise CircuitError(f"{name} is the whole circuit: nothing would be left")
        return _without(self, name)

    def __add__(self, other: "Circuit") -> "Circuit":
        return series(self, other)

    def __or__(self, other: "Circuit") -> "Circuit":
        return parallel(self, other)

    def to_cdc(self, registry: Registry = DEFAULT_REGISTRY) -> str:
        """Boukamp's circuit description code, bracket convention: series elements side by
        side, ``(...)`` a parallel group, ``[...]`` a series group inside one (the Randles
        circuit ``R0 + C1 || (R1 + W1)`` is ``R(C[RW])``). CDC has no names: `impedax.from_cdc`
        numbers the elements per symbol in order of appearance (R1, R2, C1, ...).
        Raises `CircuitError` for an element without a CDC letter (``ElementSpec.cdc``)."""
        return _cdc_text(self, registry, inside_parallel=False)

    def to_impedance_py(self, registry: Registry = DEFAULT_REGISTRY) -> str:
        """The circuit as an impedance.py string, ``-`` series and ``p(a,b)`` parallel
        (``R0 + R1 || C1 + CPE1`` is ``R0-p(R1,C1)-CPE1``), with the element names of
        `impedance_py_names`. Raises `CircuitError` for an element impedance.py lacks
        (``ElementSpec.impedance_py``)."""
        return _impedance_py_text(self, self.impedance_py_names(registry))

    def impedance_py_names(self, registry: Registry = DEFAULT_REGISTRY) -> dict[str, str]:
        """Element name → its name in `to_impedance_py`: impedance.py names an element by its
        symbol and a number, so ``R0`` or ``CPE1`` stay, an impedax symbol and number keeps its
        number under impedance.py's symbol (``CC1`` → ``Zarc1``) and other names (``R_sc``,
        ``Q1``) take the symbol and the lowest number not yet used for it, in element order."""
        elements = list(self.elements())
        symbols = {e.name: _notation_symbol(e, registry, "impedance_py", "impedance.py") for e in elements}
        renamed = {name: name for name, sym in symbols.items() if re.fullmatch(re.escape(sym) + r"[0-9]+", name)}
        taken = set(renamed.values())
        for element in elements:  # an impedax name of symbol and number keeps its number (CC1 → Zarc1)
            number = re.fullmatch(re.escape(registry[element.symbol].symbol) + r"([0-9]+)", element.name)
            own = f"{symbols[element.name]}{number.group(1)}" if number else None
            if element.name not in renamed and own is not None and own not in taken:
                renamed[element.name] = own
                taken.add(own)
        for name, sym in symbols.items():
            if name not in renamed:
                number = next(k for k in itertools.count() if f"{sym}{k}" not in taken)
                renamed[name] = f"{sym}{number}"
                taken.add(renamed[name])
        return {name: renamed[name] for name in symbols}  # in element order


@dataclass(frozen=True, slots=True)
class Element(Circuit):
    """One element, e.g. ``Element("CPE", "CPE_sc")``; ``symbol`` is as written (``Q`` stays ``Q``)."""

    symbol: str
    name: str

    def elements(self):
        yield self

    def __str__(self) -> str:
        return self.name

    def __repr__(self) -> str:
        return f"Element({self.name!r})"


class _Combination(Circuit):
    """A series or parallel node: at least two children, none of its own kind (flattened)."""

    __slots__ = ()

    def __init__(self, children):
        object.__setattr__(self, "children", _flatten(children, type(self)))

    def elements(self):
        for c in self.children:
            yield from c.elements()

    def __repr__(self) -> str:
        return f"{type(self).__name__}({list(self.children)!r})"


@dataclass(frozen=True, slots=True, init=False, repr=False)
class Series(_Combination):
    """Impedances add: Z = Σ Z_i."""

    children: tuple[Circuit, ...]

    def __str__(self) -> str:
        return " + ".join(str(c) for c in self.children)


@dataclass(frozen=True, slots=True, init=False, repr=False)
class Parallel(_Combination):
    """Admittances add: 1/Z = Σ 1/Z_i."""

    children: tuple[Circuit, ...]

    def __str__(self) -> str:
        return " || ".join(f"({c})" if isinstance(c, Series) else str(c) for c in self.children)


def _flatten(children, kind) -> tuple[Circuit, ...]:
    out: list[Circuit] = []
    for c in children:
        if not isinstance(c, Circuit):
            raise CircuitError(f"circuit children must be circuits, got {type(c).__name__}")
        out.extend(c.children if isinstance(c, kind) else (c,))
    if len(out) < 2:
        raise CircuitError(f"{kind.__name__} needs at least two children (use the child itself)")
    return tuple(out)


def series(*parts: Circuit) -> Circuit:
    """Series combination; a single part is returned unchanged."""
    return parts[0] if len(parts) == 1 else Series(parts)


def parallel(*parts: Circuit) -> Circuit:
    """Parallel combination; a single part is returned unchanged."""
    return parts[0] if len(parts) == 1 else Parallel(parts)


def _replace(node: Circuit, name: str, new: Circuit) -> Circuit:
    if isinstance(node, Element):
        return new if node.name == name else node
    kind = series if isinstance(node, Series) else parallel
    return kind(*(_replace(c, name, new) for c in node.children))


def _without(node: Circuit, name: str) -> Circuit:
    kind = series if isinstance(node, Series) else parallel
    return kind(*(c if isinstance(c, Element) else _without(c, name) for c in node.children if not (isinstance(c, Element) and c.name == name)))


def _notation_symbol(element: "Element", registry: Registry, attribute: str, notation: str) -> str:
    """The element's symbol in another notation (``ElementSpec.cdc`` / ``.impedance_py``)."""
    spec = registry[element.symbol]
    symbol = getattr(spec, attribute)
    if symbol is None:
        known = ", ".join(f"{getattr(s, attribute)} ({s.symbol})" for s in registry if getattr(s, attribute) is not None)
        raise CircuitError(f"element {element.name} ({spec.name}) has no {notation} equivalent; {notation} can express: {known}")
    return symbol


def _cdc_text(node: Circuit, registry: Registry, inside_parallel: bool) -> str:
    if isinstance(node, Element):
        return _notation_symbol(node, registry, "cdc", "CDC")
    if isinstance(node, Series):
        inner = "".join(_cdc_text(c, registry, False) for c in node.children)
        return f"[{inner}]" if inside_parallel else inner
    return "(" + "".join(_cdc_text(c, registry, True) for c in node.children) + ")"


def _impedance_py_text(node: Circuit, names: dict[str, str]) -> str:
    if isinstance(node, Element):
        return names[node.name]
    if isinstance(node, Series):
        return "-".join(_impedance_py_text(c, names) for c in node.children)
    return "p(" + ",".join(_impedance_py_text(c, names) for c in node.children) + ")"
