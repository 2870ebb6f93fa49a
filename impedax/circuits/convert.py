"""Circuits in other tools' notations: impedance.py strings and Boukamp's CDC, both ways.

Readers (`from_impedance_py`, `from_cdc`) build an impedax tree; writers (`to_impedance_py`,
`to_cdc`) accept a tree or circuit text and call the tree's own `Circuit.to_impedance_py` /
`Circuit.to_cdc`. Which elements each notation can express is a fact of the element
(``ElementSpec.impedance_py``, ``ElementSpec.cdc``), so a user's element converts too, or is
refused with a message naming it.

CDC conventions. In Boukamp's bracket convention the top level and ``[...]`` are series and
``(...)`` is parallel: ``R(C[RW])`` is the Randles circuit R + C ∥ (R + W). In the classic
convention of older programs only parentheses are used and nesting alternates parallel and
series: the Randles circuit is ``R(C(RW))``. The two readings differ only where a ``(`` opens
directly inside another ``(`` — in the bracket convention that would repeat a parallel inside
a parallel, which nobody writes — so `from_cdc` reads such a string in the classic convention,
and refuses a string that also uses ``[...]`` (mixed: ambiguous) unless told which is meant.
"""

from __future__ import annotations

import enum
import re
from collections.abc import Mapping

from ..errors import CircuitError, CircuitSyntaxError
from .elements import DEFAULT_REGISTRY
from .parser import (
    EC_LAB_NAME_RE,
    EC_LAB_WITHOUT_EQUIVALENT,
    IMPEDANCE_PY_GROUP_RE,
    MAX_ELEMENTS,
    MAX_NESTING,
    ec_lab_symbols,
    impedance_py_spelling,
    lookalike,
    parse,
    require_text,
)
from .spec import ADDING_AN_ELEMENT, Registry
from .tree import Circuit, Element, parallel, series

__all__ = ["CDCConvention", "from_autoeis", "from_cdc", "from_ec_lab", "from_impedance_py", "to_cdc", "to_impedance_py"]

_IMPEDANCE_PY_ELEMENT_RE = re.compile(r"([A-Za-z]+)_?([0-9]+)")


class CDCConvention(enum.StrEnum):
    """How parentheses nest in a CDC string (see the module docstring)."""

    AUTO = "auto"  # bracket convention, or classic where a '(' opens directly inside a '('
    BRACKETS = "brackets"  # Boukamp: top level and [...] series, (...) parallel
    ALTERNATING = "alternating"  # classic: (...) alternates parallel and series with depth


def to_cdc(circuit: Circuit | str, registry: Registry = DEFAULT_REGISTRY) -> str:
    """``circuit`` (a tree or circuit text) in Boukamp's CDC, bracket convention; see `Circuit.to_cdc`."""
    return parse(circuit, registry).to_cdc(registry)


def to_impedance_py(circuit: Circuit | str, registry: Registry = DEFAULT_REGISTRY) -> str:
    """``circuit`` (a tree or circuit text) as an impedance.py string; see `Circuit.to_impedance_py`."""
    return parse(circuit, registry).to_impedance_py(registry)


def from_impedance_py(text: str, registry: Registry = DEFAULT_REGISTRY) -> Circuit:
    """Convert an impedance.py circuit string (``R0-p(R1,C1)-CPE1``) into an impedax circuit.

    ``-`` is series and ``p(a, b, ...)`` parallel; element names are kept (``CPE1`` → ``CPE1``,
    ``R_0`` → ``R0``); the symbols are those of ``ElementSpec.impedance_py`` in ``registry``.
    """
    src = require_text(text)
    if not src.strip():
        raise CircuitSyntaxError(src, 0, "empty circuit")
    return _ImpedancePyReader(src, registry).read()


class _ImpedancePyReader:
    """Recursive descent over an impedance.py string: ``series := item ('-' item)*``,
    ``item := 'p(' series (',' series)+ ')' | ELEMENT``."""

    def __init__(self, src: str, registry: Registry):
        self.src = src
        self.registry = registry
        self.pos = 0
        self.depth = 0
        self.names: set[str] = set()

    def read(self) -> Circuit:
        out = self.series()
        if self.pos != len(self.src):
            ch = self.src[self.pos]
            hint = "impedance.py strings use '-' and p(a,b)"
            if ch != "-" and lookalike(ch) == "-":  # a dash pasted from a paper
                hint = f"{'a minus sign' if ch == '−' else 'a dash'} '{ch}': impedance.py's series is the ASCII '-'"
            raise CircuitSyntaxError(self.src, self.pos, f"unexpected {ch!r}", hint)
        return out

    def skip(self) -> None:
        while self.pos < len(self.src) and self.src[self.pos].isspace():
            self.pos += 1

    def separated(self, separator: str, part) -> list[Circuit]:
        """``part ( separator part )*``, whitespace allowed around the separators."""
        parts = [part()]
        self.skip()
        while self.pos < len(self.src) and self.src[self.pos] == separator:
            self.pos += 1
            parts.append(part())
            self.skip()
        return parts

    def series(self) -> Circuit:
        return series(*self.separated("-", self.item))

    # the notation's words, in messages: its parallel group's opening and closing, an example element
    opening, closing, example, notation = "p(", ")", "R0", "impedance.py"

    def group_at(self) -> int | None:
        """Where the inside of a parallel group starting at ``self.pos`` begins, or None."""
        group = IMPEDANCE_PY_GROUP_RE.match(self.src, self.pos)
        return group.end() if group else None

    def spec_of(self, sym: str):
        return self.registry.by_impedance_py.get(sym)

    def item(self) -> Circuit:
        src = self.src
        self.skip()
        inside = self.group_at()
        if inside is not None:
            return self.parallel_group(inside)
        m = _IMPEDANCE_PY_ELEMENT_RE.match(src, self.pos)
        if m is None:
            raise CircuitSyntaxError(src, self.pos, f"expected an element such as {self.example} or {self.opening}", None)
        sym, digits = m.groups()
        spec = self.spec_of(sym)
        spelled = impedance_py_spelling(sym, self.registry)
        if spec is None and spelled is not None:  # cpe1, zarc1: symbols are case-sensitive
            meant = self.registry.by_impedance_py[spelled].symbol
            also = f" (impedax's {meant}{digits})" if meant != spelled else ""
            raise CircuitSyntaxError(src, self.pos, f"unknown impedance.py element {sym!r} in {m.group()!r}", f"symbols are case-sensitive: did you mean {spelled}{digits}{also}?")
        if spec is None:
            raise CircuitSyntaxError(
                src, self.pos, f"{self.notation} element {sym!r} has no impedax equivalent",
                "supported: " + ", ".join(self.supported())
                + f"; register your own: ElementSpec(..., impedance_py={sym!r}) {ADDING_AN_ELEMENT}",
            )
        name = f"{spec.symbol}{digits}"
        if name in self.names:
            raise CircuitSyntaxError(src, self.pos, f"duplicate element name {name!r}")
        self.names.add(name)
        if len(self.names) > MAX_ELEMENTS:
            raise CircuitSyntaxError(src, self.pos, f"more than {MAX_ELEMENTS} elements")
        self.pos = m.end()
        return Element(spec.symbol, name)

    def supported(self) -> list[str]:
        return list(self.registry.by_impedance_py)

    def parallel_group(self, inside: int) -> Circuit:
        """The group whose opening (``p(``) starts at ``self.pos`` and ends before ``inside``."""
        src, start = self.src, self.pos
        group = f"{self.opening}...{self.closing}"
        if self.depth >= MAX_NESTING:
            raise CircuitSyntaxError(src, start, f"{group} nested deeper than {MAX_NESTING} levels")
        self.depth += 1
        self.pos = inside
        parts = self.separated(",", self.series)
        if self.pos >= len(src) or src[self.pos] != self.closing:
            raise CircuitSyntaxError(src, self.pos, f"expected '{self.closing}' closing {self.opening}", f"{self.opening} opened at column {start + 1}")
        self.pos += 1
        self.depth -= 1
        if len(parts) < 2:
            raise CircuitSyntaxError(src, start, f"{group} needs at least two branches")
        return parallel(*parts)


def from_autoeis(text: str, registry: Registry = DEFAULT_REGISTRY) -> Circuit:
    """Convert an AutoEIS circuit string (``R1-C2-[R3,P4]``) into an impedax circuit.

    ``-`` is series and ``[a, b, ...]`` parallel; ``P`` is AutoEIS's constant phase element
    (``P4`` → ``CPE4``, its ``P4w``, ``P4n`` are ``CPE4.Q``, ``CPE4.alpha``), and the other
    symbols (``R``, ``C``, ``L``) are read as in impedance.py strings (`from_impedance_py`).
    """
    src = require_text(text)
    if not src.strip():
        raise CircuitSyntaxError(src, 0, "empty circuit")
    return _AutoEISReader(src, registry).read()


# AutoEIS's symbols that are not impedance.py's, and the impedance.py symbol of the same element
_AUTOEIS_SYMBOLS = {"P": "CPE"}


class _AutoEISReader(_ImpedancePyReader):
    """An AutoEIS string: impedance.py's grammar with ``[a,b]`` for ``p(a,b)`` and ``P`` for ``CPE``."""

    opening, closing, example, notation = "[", "]", "R1", "AutoEIS"

    def group_at(self) -> int | None:
        return self.pos + 1 if self.src.startswith("[", self.pos) else None

    def spec_of(self, sym: str):
        return self.registry.by_impedance_py.get(_AUTOEIS_SYMBOLS.get(sym, sym))

    def supported(self) -> list[str]:
        own = {impedance_py: autoeis for autoeis, impedance_py in _AUTOEIS_SYMBOLS.items()}
        return [own.get(sym, sym) for sym in self.registry.by_impedance_py]

    def read(self) -> Circuit:
        out = self.series()
        if self.pos != len(self.src):
            ch = self.src[self.pos]
            raise CircuitSyntaxError(self.src, self.pos, f"unexpected {ch!r}", "AutoEIS strings use '-' and [a,b]")
        return out


def from_ec_lab(text: str, registry: Registry = DEFAULT_REGISTRY) -> Circuit:
    """Convert an EC-Lab circuit string (``R1+Q2/(R2+Wd2)``) into an impedax circuit.

    ``+`` is series and ``/`` parallel, binding closer than ``+`` as impedax's ``||`` does
    (``C1/R1+C2/R2`` is ``C1 || R1 + C2 || R2``; a run of slashes, papers' ``R1//C1``, is one
    sign); parentheses group. EC-Lab's Wd and M are impedax's Ws and Wo, the same formulas with
    the same parameters R and tau (`EC_LAB_SYMBOLS`), where ``registry`` declares no element of
    that symbol; the other symbols are read as impedax's (R, C, L, Q the CPE, W, G). An EC-Lab
    element that impedax does not build in (Ma, Mg, Ga, Gb, La, Winf) is refused by name.
    """
    src = require_text(text)
    if not src.strip():
        raise CircuitSyntaxError(src, 0, "empty circuit")
    for m in EC_LAB_NAME_RE.finditer(src):
        symbol = m.group(1)
        if symbol in EC_LAB_WITHOUT_EQUIVALENT and symbol not in registry:
            raise CircuitSyntaxError(
                src, m.start(), f"EC-Lab's {symbol} ({EC_LAB_WITHOUT_EQUIVALENT[symbol]}) has no built-in impedax element",
                f"register one {ADDING_AN_ELEMENT}",
            )
    impedax_text, origin = _ec_lab_as_impedax(src, ec_lab_symbols(src, registry))
    try:
        return parse(impedax_text, registry)
    except CircuitSyntaxError as exc:  # (the caret, and a column a hint names, on the text as typed)
        at = lambda column: origin[min(column, len(origin) - 1)]  # noqa: E731
        typed = lambda text: text and re.sub(r"(?<=column )(\d+)", lambda m: str(at(int(m.group()) - 1) + 1), text)  # noqa: E731
        raise CircuitSyntaxError(src, at(exc.column), typed(exc.reason), typed(exc.hint), unknown_symbol=exc.unknown_symbol) from None


# what `from_ec_lab` rewrites: a run of slashes (with the spaces around it), the parallel sign of
# EC-Lab's circuits (R1+Q2/R2) and of papers (R1//C1), or the symbol that opens an element name
_EC_LAB_REWRITTEN_RE = re.compile(r"(?P<slash>\s*/+\s*)|(?<![\w.])(?P<symbol>[A-Za-z]+)")


def _ec_lab_as_impedax(src: str, renamed: Mapping[str, str]) -> tuple[str, list[int]]:
    """EC-Lab text ``src`` as impedax text (``/`` → ``||``, the ``renamed`` symbols), and for
    each of its characters (and its end) the offset in ``src`` it comes from."""
    out, origin, i = [], [], 0
    for m in _EC_LAB_REWRITTEN_RE.finditer(src):
        out.append(src[i:m.start()])
        origin.extend(range(i, m.start()))
        if m.group("slash"):
            new, start, width = " || ", src.index("/", m.start()), 1
        else:
            new, start, width = renamed.get(m.group("symbol"), m.group("symbol")), m.start(), len(m.group("symbol"))
        out.append(new)
        origin.extend(start + min(k, width - 1) for k in range(len(new)))
        i = m.end()
    out.append(src[i:])
    origin.extend(range(i, len(src) + 1))
    return "".join(out), origin


def from_cdc(text: str, registry: Registry = DEFAULT_REGISTRY, *, convention: CDCConvention | str = CDCConvention.AUTO) -> Circuit:
    """Convert a Boukamp circuit description code into an impedax circuit.

    Bracket convention (``R(RC)(RQ)``, ``R(C[RW])``): the top level and ``[...]`` are series,
    ``(...)`` parallel. Classic convention (``R(C(RW))``): nesting alternates parallel and
    series. ``convention="auto"`` reads the bracket convention unless a ``(`` opens directly
    inside a ``(`` (classic), and refuses a string that mixes that with ``[...]``; see the
    module docstring. Letters are those of ``ElementSpec.cdc`` in ``registry``; elements are
    numbered per symbol in order of appearance: ``R1, R2, C1, CPE1``.
    """
    src = require_text(text)
    try:
        convention = CDCConvention(convention)
    except ValueError:
        raise CircuitError(f"convention must be one of {', '.join(c.value for c in CDCConvention)}, got {convention!r}") from None
    if convention is CDCConvention.AUTO:
        convention = _cdc_convention(src)
    return _CDCReader(src, registry, convention).read()


def _cdc_convention(src: str) -> CDCConvention:
    """The convention of ``src`` (see the module docstring), or a syntax error if mixed."""
    open_groups: list[str] = []
    nested_at = None
    for i, ch in enumerate(src):
        if ch in "([":
            if ch == "(" and open_groups[-1:] == ["("] and nested_at is None:
                nested_at = i
            open_groups.append(ch)
        elif ch in ")]" and open_groups:
            open_groups.pop()
    if nested_at is None:
        return CDCConvention.BRACKETS  # the conventions read this string alike
    if "[" in src:
        raise CircuitSyntaxError(
            src, nested_at, "ambiguous CDC: '(' directly inside '(' in a string that also uses '[...]'",
            "in the bracket convention '(' is always parallel, in the classic one parentheses alternate "
            "parallel and series and '[' is not used: pass convention='brackets' or convention='alternating'",
        )
    return CDCConvention.ALTERNATING


class _CDCReader:
    """Recursive descent over a CDC string in one known convention."""

    def __init__(self, src: str, registry: Registry, convention: CDCConvention):
        self.src = src
        self.registry = registry
        self.alternating = convention is CDCConvention.ALTERNATING
        self.pos = 0
        self.depth = 0
        self.counts: dict[str, int] = {}

    def read(self) -> Circuit:
        return self.group(None, series)

    def group(self, closing: str | None, kind) -> Circuit:
        src = self.src
        start = self.pos
        if self.depth > MAX_NESTING:
            raise CircuitSyntaxError(src, max(self.pos - 1, 0), f"groups nested deeper than {MAX_NESTING} levels")
        self.depth += 1
        parts: list[Circuit] = []
        while self.pos < len(src):
            ch = src[self.pos]
            if ch.isspace():
                self.pos += 1
            elif ch == "(":
                self.pos += 1
                inner = (series if kind is parallel else parallel) if self.alternating else parallel
                parts.append(self.group(")", inner))
            elif ch == "[":
                if self.alternating:
                    raise CircuitSyntaxError(src, self.pos, "'[' in a classic (alternating) CDC string", "square brackets belong to the bracket convention: pass convention='brackets'")
                self.pos += 1
                parts.append(self.group("]", series))
            elif ch in ")]":
                if ch != closing:
                    raise CircuitSyntaxError(src, self.pos, f"unexpected {ch!r}", "brackets do not match")
                self.pos += 1
                break
            elif ch in self.registry.by_cdc:
                parts.append(self.element(ch))
            else:
                raise CircuitSyntaxError(src, self.pos, f"unknown CDC element {ch!r}", "known: " + " ".join(self.registry.by_cdc))
        else:
            if closing is not None:
                raise CircuitSyntaxError(src, start - 1, f"unclosed group, expected {closing!r}")
        if not parts:
            raise CircuitSyntaxError(src, max(start - 1, 0), "empty group")
        self.depth -= 1
        return kind(*parts)

    def element(self, letter: str) -> Element:
        sym = self.registry.by_cdc[letter].symbol
        self.counts[sym] = self.counts.get(sym, 0) + 1
        if sum(self.counts.values()) > MAX_ELEMENTS:
            raise CircuitSyntaxError(self.src, self.pos, f"more than {MAX_ELEMENTS} elements")
        self.pos += 1
        return Element(sym, f"{sym}{self.counts[sym]}")
