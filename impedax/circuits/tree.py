"""The immutable circuit tree: `Element`, `Series`, `Parallel`.

A tree holds no arrays; parameter values live apart from it, in a mapping name → value.
Constructors normalise: nested nodes of the same kind are flattened and one-child nodes
collapse, so ``parse(str(c)) == c`` holds for every tree.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterator

from ..errors import CircuitError
from .elements import DEFAULT_REGISTRY, ParameterSpec, Registry

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

    def element(self, name: str) -> "Element":
        for e in self.elements():
            if e.name == name:
                return e
        raise CircuitError(f"no element named {name!r} in {self}; elements: {', '.join(self.element_names)}")

    def replace(self, name: str, new: "Circuit") -> "Circuit":
        """A new tree with element ``name`` replaced by the subcircuit ``new``."""
        self.element(name)
        return _replace(self, name, new)

    def __add__(self, other: "Circuit") -> "Circuit":
        return series(self, other)

    def __or__(self, other: "Circuit") -> "Circuit":
        return parallel(self, other)

    def compile(self, registry: Registry = DEFAULT_REGISTRY):
        """Compile into a pure ``fn(params, freq) -> Z``; see `impedax.circuits.compile_circuit`."""
        from .compile import compile_circuit

        return compile_circuit(self, registry)


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


@dataclass(frozen=True, slots=True, init=False)
class Series(Circuit):
    """Impedances add: Z = Σ Z_i."""

    children: tuple[Circuit, ...]

    def __init__(self, children):
        object.__setattr__(self, "children", _flatten(children, Series))

    def elements(self):
        for c in self.children:
            yield from c.elements()

    def __str__(self) -> str:
        return " + ".join(str(c) for c in self.children)

    def __repr__(self) -> str:
        return f"Series({list(self.children)!r})"


@dataclass(frozen=True, slots=True, init=False)
class Parallel(Circuit):
    """Admittances add: 1/Z = Σ 1/Z_i."""

    children: tuple[Circuit, ...]

    def __init__(self, children):
        object.__setattr__(self, "children", _flatten(children, Parallel))

    def elements(self):
        for c in self.children:
            yield from c.elements()

    def __str__(self) -> str:
        return " || ".join(f"({c})" if isinstance(c, Series) else str(c) for c in self.children)

    def __repr__(self) -> str:
        return f"Parallel({list(self.children)!r})"


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
