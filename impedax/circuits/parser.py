"""Tokenizer and recursive-descent parser of the impedax circuit language.

Grammar (stable; later tools rely on it)::

    circuit  := series
    series   := parallel ( '+' parallel )*      # impedances add
    parallel := term ( '||' term )*             # admittances add; binds tighter than '+'
    term     := ELEMENT | '(' series ')'
    ELEMENT  := SYMBOL ( DIGITS | '_' LABEL )   # R0, R_sc, C_gap, CPE_skin, Wo1

Also converters from impedance.py strings (``R0-p(R1,C1)-CPE1``) and Boukamp CDC strings
(``R(RC)(RQ)``).
"""

from __future__ import annotations

import functools

import re
from dataclasses import dataclass

from ..errors import CircuitSyntaxError
from .elements import DEFAULT_REGISTRY, Registry
from .tree import Circuit, Element, parallel, series

__all__ = ["parse", "from_impedance_py", "from_cdc", "Token", "tokenize", "MAX_NESTING", "MAX_ELEMENTS"]

# Limits that keep every recursive walk of a tree (parser, str, compile) far from Python's
# recursion limit, and a compile within seconds; real equivalent circuits are far smaller.
MAX_NESTING = 64
MAX_ELEMENTS = 256

_IDENT_RE = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
_NUMBERED_RE = re.compile(r"([A-Za-z]+)([0-9]+)\Z")
_LABEL_RE = re.compile(r"[A-Za-z0-9]+(?:_[A-Za-z0-9]+)*\Z")


@dataclass(frozen=True)
class Token:
    kind: str  # "element", "+", "||", "(", ")", "end"
    text: str
    column: int  # 0-based offset in the source


def tokenize(source: str) -> list[Token]:
    """Split ``source`` into tokens that keep their character offsets."""
    tokens: list[Token] = []
    i, n = 0, len(source)
    while i < n:
        ch = source[i]
        if ch.isspace():
            i += 1
        elif ch in "+()":
            tokens.append(Token(ch, ch, i))
            i += 1
        elif source.startswith("||", i):
            tokens.append(Token("||", "||", i))
            i += 2
        elif ch == "|":
            raise CircuitSyntaxError(source, i, "a single '|' is not an operator", "parallel is written '||'")
        elif ch == "-" or ch == ",":
            hint = "series is written '+'" + (" (impedance.py strings: impedax.from_impedance_py)" if ch == "-" else "")
            raise CircuitSyntaxError(source, i, f"unexpected {ch!r}", hint)
        else:
            m = _IDENT_RE.match(source, i)
            if m is None:
                raise CircuitSyntaxError(source, i, f"unexpected character {ch!r}", "expected an element such as R1 or C_gap, '(' , '+' or '||'")
            tokens.append(Token("element", m.group(), i))
            i = m.end()
    tokens.append(Token("end", "", n))
    return tokens


def _split_element(source: str, tok: Token, registry: Registry) -> str:
    """Return the element's symbol, or raise with a precise hint."""
    text = tok.text
    if "_" in text:
        symbol, _, label = text.partition("_")
        if symbol not in registry:
            raise CircuitSyntaxError(source, tok.column, f"unknown element symbol {symbol!r} in {text!r}", _symbol_hint(symbol, "_" + label, registry))
        if not _LABEL_RE.match(label):
            raise CircuitSyntaxError(source, tok.column + len(symbol) + 1, f"bad label {label!r} in {text!r}", "a label is letters and digits, optionally joined by single '_'")
        return symbol
    m = _NUMBERED_RE.match(text)
    if m is None:
        # letters only (Csc) or letters after digits (R1a)
        letters = re.match(r"[A-Za-z]+", text).group()
        rest = text[len(letters):]
        if letters in registry and not rest:
            raise CircuitSyntaxError(source, tok.column, f"element {text!r} needs a number or a label", f"write {text}1 or {text}_name")
        if letters in registry:
            raise CircuitSyntaxError(source, tok.column, f"cannot read element name {text!r}", f"did you mean {letters}_{rest}?")
        raise CircuitSyntaxError(source, tok.column, f"unknown element {text!r}", _symbol_hint(letters, rest, registry))
    symbol, _digits = m.groups()
    if symbol not in registry:
        raise CircuitSyntaxError(source, tok.column, f"unknown element symbol {symbol!r} in {text!r}", _symbol_hint(symbol, _digits, registry))
    return symbol


def _symbol_hint(letters: str, rest: str, registry: Registry) -> str:
    if letters.upper() in registry or letters.capitalize() in registry:
        fixed = letters.upper() if letters.upper() in registry else letters.capitalize()
        return f"symbols are case-sensitive: did you mean {fixed}{rest}?"
    for sym in registry.symbols():  # longest first, so CPE wins over C
        if letters.startswith(sym) and len(letters) > len(sym):
            label = letters[len(sym):] + rest.lstrip("_")
            return f"did you mean {sym}_{label}?"
    return "known symbols: " + ", ".join(sorted(registry.symbols()))


class _Parser:
    def __init__(self, source: str, registry: Registry):
        self.source = source
        self.registry = registry
        self.tokens = tokenize(source)
        self.pos = 0
        self.names: dict[str, int] = {}
        self.depth = 0
        elements = [t for t in self.tokens if t.kind == "element"]
        if len(elements) > MAX_ELEMENTS:
            raise CircuitSyntaxError(source, elements[MAX_ELEMENTS].column, f"more than {MAX_ELEMENTS} elements", "impedax circuits are limited to a few hundred elements")

    def peek(self) -> Token:
        return self.tokens[self.pos]

    def take(self) -> Token:
        tok = self.tokens[self.pos]
        self.pos += 1
        return tok

    def error(self, tok: Token, expected: str, hint: str | None = None):
        found = "end of input" if tok.kind == "end" else repr(tok.text)
        raise CircuitSyntaxError(self.source, tok.column, f"expected {expected}, found {found}", hint)

    def parse(self) -> Circuit:
        if self.peek().kind == "end":
            raise CircuitSyntaxError(self.source, 0, "empty circuit", "write e.g. R0 + R1 || C1")
        node = self.series()
        tok = self.peek()
        if tok.kind != "end":
            hint = "unbalanced ')'" if tok.kind == ")" else "join parts with '+' (series) or '||' (parallel)"
            self.error(tok, "'+', '||' or end of input", hint)
        return node

    def series(self) -> Circuit:
        parts = [self.parallel()]
        while self.peek().kind == "+":
            self.take()
            parts.append(self.parallel())
        return series(*parts)

    def parallel(self) -> Circuit:
        parts = [self.term()]
        while self.peek().kind == "||":
            self.take()
            parts.append(self.term())
        return parallel(*parts)

    def term(self) -> Circuit:
        tok = self.take()
        if tok.kind == "element":
            symbol = _split_element(self.source, tok, self.registry)
            if tok.text in self.names:
                first = self.names[tok.text] + 1
                raise CircuitSyntaxError(self.source, tok.column, f"duplicate element name {tok.text!r} (first at column {first})", "every element needs its own name")
            self.names[tok.text] = tok.column
            return Element(symbol, tok.text)
        if tok.kind == "(":
            if self.depth >= MAX_NESTING:
                raise CircuitSyntaxError(self.source, tok.column, f"parentheses nested deeper than {MAX_NESTING} levels", "flatten the circuit; nesting this deep is not a real network")
            self.depth += 1
            inner = self.series()
            self.depth -= 1
            close = self.take()
            if close.kind != ")":
                self.pos -= 1
                self.error(close, "')'", f"the '(' at column {tok.column + 1} is not closed")
            return inner
        self.pos -= 1
        self.error(tok, "an element or '('")


def parse(text: str, registry: Registry = DEFAULT_REGISTRY) -> Circuit:
    """Parse circuit text such as ``"R_f + R_sc || CPE_sc"`` into an immutable `Circuit`.

    Raises `CircuitSyntaxError` (with column, caret and hint) on invalid input.
    """
    if isinstance(text, Circuit):
        return text
    if not isinstance(text, str):
        raise CircuitSyntaxError(repr(text), 0, f"a circuit must be text, got {type(text).__name__}")
    return _parse_text(text, registry)


@functools.lru_cache(maxsize=256)
def _parse_text(text: str, registry: Registry) -> Circuit:
    # circuits are immutable, so a repeated text (a fit per spectrum) is parsed once
    return _Parser(text, registry).parse()


# --- converters from other tools' notations -------------------------------------------------

_IMPEDANCE_PY_SYMBOLS = {"R": "R", "C": "C", "L": "L", "CPE": "CPE", "W": "W", "Wo": "Wo", "Ws": "Ws", "G": "G"}


def from_impedance_py(text: str, registry: Registry = DEFAULT_REGISTRY) -> Circuit:
    """Convert an impedance.py circuit string (``R0-p(R1,C1)-CPE1``) into an impedax circuit.

    ``-`` is series and ``p(a, b, ...)`` parallel; element names are kept (``CPE1`` → ``CPE1``).
    """
    if not isinstance(text, str):
        raise CircuitSyntaxError(repr(text), 0, f"a circuit must be text, got {type(text).__name__}")
    pos = 0
    src = text
    names: set[str] = set()
    depth = 0

    def skip():
        nonlocal pos
        while pos < len(src) and src[pos].isspace():
            pos += 1

    def parse_series() -> Circuit:
        nonlocal pos
        parts = [parse_item()]
        skip()
        while pos < len(src) and src[pos] == "-":
            pos += 1
            parts.append(parse_item())
            skip()
        return series(*parts)

    def parse_item() -> Circuit:
        nonlocal pos
        skip()
        if src.startswith("p(", pos):
            nonlocal depth
            start = pos
            if depth >= MAX_NESTING:
                raise CircuitSyntaxError(src, pos, f"p(...) nested deeper than {MAX_NESTING} levels")
            depth += 1
            pos += 2
            parts = [parse_series()]
            skip()
            while pos < len(src) and src[pos] == ",":
                pos += 1
                parts.append(parse_series())
                skip()
            if pos >= len(src) or src[pos] != ")":
                raise CircuitSyntaxError(src, pos, "expected ')' closing p(", f"p( opened at column {start + 1}")
            pos += 1
            depth -= 1
            if len(parts) < 2:
                raise CircuitSyntaxError(src, start, "p(...) needs at least two branches")
            return parallel(*parts)
        m = re.compile(r"([A-Za-z]+)_?([0-9]+)").match(src, pos)
        if m is None:
            raise CircuitSyntaxError(src, pos, "expected an element such as R0 or p(", None)
        sym, digits = m.groups()
        if sym not in _IMPEDANCE_PY_SYMBOLS or _IMPEDANCE_PY_SYMBOLS[sym] not in registry:
            raise CircuitSyntaxError(src, pos, f"impedance.py element {sym!r} has no impedax equivalent", "supported: " + ", ".join(_IMPEDANCE_PY_SYMBOLS))
        name = f"{_IMPEDANCE_PY_SYMBOLS[sym]}{digits}"
        if name in names:
            raise CircuitSyntaxError(src, pos, f"duplicate element name {name!r}")
        names.add(name)
        if len(names) > MAX_ELEMENTS:
            raise CircuitSyntaxError(src, pos, f"more than {MAX_ELEMENTS} elements")
        pos = m.end()
        return Element(_IMPEDANCE_PY_SYMBOLS[sym], name)

    if not text.strip():
        raise CircuitSyntaxError(text, 0, "empty circuit")
    out = parse_series()
    skip()
    if pos != len(src):
        raise CircuitSyntaxError(src, pos, f"unexpected {src[pos]!r}", "impedance.py strings use '-' and p(a,b)")
    return out


# Boukamp's CDC letters; O is the finite-length Warburg with a transmissive boundary (tanh,
# impedax Ws) and T the one with a reflective boundary (coth, impedax Wo).
_CDC_SYMBOLS = {"R": "R", "C": "C", "L": "L", "Q": "CPE", "W": "W", "O": "Ws", "T": "Wo", "G": "G"}


def from_cdc(text: str, registry: Registry = DEFAULT_REGISTRY) -> Circuit:
    """Convert a Boukamp circuit description code (``R(RC)(RQ)``, ``R([RW]C)``).

    At the top level and inside ``[...]`` elements are in series; inside ``(...)`` in parallel.
    Elements are numbered per symbol in order of appearance: ``R1, R2, C1, CPE1``.
    """
    if not isinstance(text, str):
        raise CircuitSyntaxError(repr(text), 0, f"a circuit must be text, got {type(text).__name__}")
    counts: dict[str, int] = {}
    pos = 0
    depth = 0

    def group(closing: str | None, kind) -> Circuit:
        nonlocal pos, depth
        start = pos
        if depth > MAX_NESTING:
            raise CircuitSyntaxError(text, max(pos - 1, 0), f"groups nested deeper than {MAX_NESTING} levels")
        depth += 1
        parts: list[Circuit] = []
        while pos < len(text):
            ch = text[pos]
            if ch.isspace():
                pos += 1
            elif ch == "(":
                pos += 1
                parts.append(group(")", parallel))
            elif ch == "[":
                pos += 1
                parts.append(group("]", series))
            elif ch in ")]":
                if ch != closing:
                    raise CircuitSyntaxError(text, pos, f"unexpected {ch!r}", "brackets do not match")
                pos += 1
                break
            elif ch in _CDC_SYMBOLS:
                sym = _CDC_SYMBOLS[ch]
                counts[sym] = counts.get(sym, 0) + 1
                if sum(counts.values()) > MAX_ELEMENTS:
                    raise CircuitSyntaxError(text, pos, f"more than {MAX_ELEMENTS} elements")
                parts.append(Element(sym, f"{sym}{counts[sym]}"))
                pos += 1
            else:
                raise CircuitSyntaxError(text, pos, f"unknown CDC element {ch!r}", "known: " + " ".join(_CDC_SYMBOLS))
        else:
            if closing is not None:
                raise CircuitSyntaxError(text, start - 1, f"unclosed group, expected {closing!r}")
        if not parts:
            raise CircuitSyntaxError(text, max(start - 1, 0), "empty group")
        depth -= 1
        return kind(*parts)

    out = group(None, series)
    return out
