"""Tokenizer and recursive-descent parser of the impedax circuit language.

Grammar (stable; later tools rely on it)::

    circuit  := series
    series   := parallel ( '+' parallel )*      # impedances add
    parallel := term ( '||' term )*             # admittances add; binds tighter than '+'
    term     := ELEMENT | '(' series ')'
    ELEMENT  := SYMBOL ( DIGITS | '_' LABEL )   # R0, R_sc, C_gap, CPE_skin, Wo1

Other tools' notations (impedance.py, Boukamp's CDC) are read in `impedax.circuits.convert`.
"""

from __future__ import annotations

import functools
import re
import unicodedata
from dataclasses import dataclass

from ..errors import CircuitError, CircuitSyntaxError, ImpedaxError, ParameterError, escape_text
from .elements import DEFAULT_REGISTRY
from .spec import ADDING_AN_ELEMENT, PASS_DECLARING_REGISTRY, Registry
from .tree import Circuit, Element, parallel, series

__all__ = ["parse", "require_text", "Token", "tokenize", "MAX_NESTING", "MAX_ELEMENTS"]

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


IMPEDANCE_PY_CALL = "ix.from_impedance_py"  # the reader of impedance.py strings, as docs/migrating.md writes it
MAX_CALL_TEXT = 60  # characters of the user's text quoted in that call; a longer text is shown as "..."
MAX_REWRITE_TEXT = 40  # characters of each rewrite of a mixed-notation text in its hint (a longer one: an example), so the message stays under 300


def _call_text(source: str) -> str:
    return repr(source) if len(source) <= MAX_CALL_TEXT else '"..."'


def tokenize(source: str, registry: Registry = DEFAULT_REGISTRY) -> list[Token]:
    """Split ``source`` into tokens that keep their character offsets (``registry``: the
    elements a hint's rewrite of the text may name)."""
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
            raise CircuitSyntaxError(source, i, f"unexpected {ch!r}", _notation_hint(source, ch, registry))
        else:
            m = _IDENT_RE.match(source, i)
            if m is None:
                _check_spaced_name(source, i, tokens)
                raise CircuitSyntaxError(source, i, f"unexpected character {describe_character(ch)}", _character_hint(ch, source))
            tokens.append(Token("element", m.group(), i))
            i = m.end()
    tokens.append(Token("end", "", n))
    return tokens


_SYMBOL_ONLY_RE = re.compile(r"[A-Za-z]+_?\Z")  # an element name cut before its number or label: R, Ws, R_
_NAME_REST_RE = re.compile(r"[A-Za-z0-9_]*")


def _check_spaced_name(source: str, i: int, tokens: list[Token]) -> None:
    """Raise for a digit or '_' at ``i`` that continues the previous word across spaces
    (``R 1``, ``Ws 2``, ``R _sc``): an element name with a space inside. Caret on the space."""
    previous = tokens[-1] if tokens else None
    if not (source[i].isdigit() or source[i] == "_") or previous is None or previous.kind != "element":
        return
    end = previous.column + len(previous.text)
    if not _SYMBOL_ONLY_RE.match(previous.text) or source[end:i].strip():
        return
    rest = _NAME_REST_RE.match(source, i).group()
    raise CircuitSyntaxError(source, end, f"space inside the element name {source[previous.column:i + len(rest)]!r}", f"no space inside an element name: {previous.text}{rest}")


# impedance.py's parallel group ``p(``: a 'p' that is no part of a longer name, then '(' (after
# spaces too: impedance.py removes every space from a circuit string before reading it)
IMPEDANCE_PY_GROUP_RE = re.compile(r"(?<![A-Za-z0-9_])p\s*\(")


def _notation_hint(source: str, ch: str, registry: Registry) -> str:
    """The hint for a ``-``, ``,`` or ``p(``: impedance.py's series, branches and parallel. Mixed with
    impedax's ``+`` / ``||`` the string is in neither notation (say so, and write it in each);
    alone, it is an impedance.py string passed where impedax text goes."""
    has_group = IMPEDANCE_PY_GROUP_RE.search(source) is not None
    if has_group and ("+" in source or "||" in source):
        return "p(a,b) is a || b in impedax's notation, and the two notations cannot be mixed: write the whole string in one, " + _in_one_notation(source, registry)
    if looks_like_autoeis(source):
        return f"series is written '+' and parallel '||'; in Python an AutoEIS string is passed as {AUTOEIS_CALL}({_call_text(source)}) (the command line reads it by itself)"
    call = f"in Python an impedance.py string is passed as {IMPEDANCE_PY_CALL}({_call_text(source)}) (the command line reads it by itself)"
    if ch == "-":
        return "series is written '+'; " + call
    if has_group:
        return "p(a,b) is impedance.py's notation for a || b; " + call
    return "series is written '+'"


AUTOEIS_CALL = "ix.from_autoeis"  # the reader of AutoEIS strings, as docs/circuits.md writes it
_AUTOEIS_CPE_RE = re.compile(r"(?<![A-Za-z0-9_])P[0-9]")  # AutoEIS's CPE, P4 (no impedance.py or impedax symbol)


def looks_like_autoeis(text: str) -> bool:
    """Whether ``text`` is written in AutoEIS's notation (``R1-C2-[R3,P4]``): ``[a,b]`` groups or
    its CPE symbol ``P``, and none of impedax's operators or impedance.py's ``p(``. impedax text
    never holds ``[`` or ``,``; CDC has ``[`` but no ``,`` and no numbers."""
    if "+" in text or "|" in text or IMPEDANCE_PY_GROUP_RE.search(text):
        return False
    return ("[" in text and "," in text) or _AUTOEIS_CPE_RE.search(text) is not None


def _in_one_notation(source: str, registry: Registry) -> str:
    """``source``, which mixes impedax's ``+`` / ``||`` with impedance.py's ``-`` / ``p(a,b)``,
    written in each notation alone (``R0 + R1 || C1 (impedax) or R0-p(R1,C1) (impedance.py)``),
    read as ``-`` → ``+`` and ``p(a,b)`` → ``((a) || (b))``; an example if it does not read so
    or a rewrite would be longer than `MAX_REWRITE_TEXT`."""
    example = "e.g. R0 + R1 || C1 (impedax) or R0-p(R1,C1) (impedance.py)"
    if len(source) > 4 * MAX_REWRITE_TEXT:
        return example
    out: list[str] = []
    groups: list[str] = []  # the open parentheses: "p(" or "("
    i = 0
    while i < len(source):
        ch = source[i]
        group = IMPEDANCE_PY_GROUP_RE.match(source, i)
        if group:
            groups.append("p(")
            out.append("((")
            i = group.end()
            continue
        if ch == "(":
            groups.append("(")
        elif ch == ")" and groups:
            ch = "))" if groups.pop() == "p(" else ")"
        elif ch == ",":
            if groups[-1:] != ["p("]:
                return example
            ch = ") || ("
        elif ch == "-":
            ch = "+"
        out.append(ch)
        i += 1
    try:
        circuit = parse("".join(out), registry)
    except ImpedaxError:
        return example
    impedax_text = str(circuit)
    if len(impedax_text) > MAX_REWRITE_TEXT:
        return example
    try:
        impedance_py_text = circuit.to_impedance_py(registry)
    except ImpedaxError:  # an element impedance.py lacks (HN)
        return f"{impedax_text} (impedax)"
    return f"{impedax_text} (impedax) or {impedance_py_text} (impedance.py)" if len(impedance_py_text) <= MAX_REWRITE_TEXT else f"{impedax_text} (impedax)"


# Letters of other scripts drawn exactly like Latin ones (after Unicode's confusables list,
# restricted to what can be typed into a circuit: symbols are Latin letters and digits).
# Full-width forms (Ｒ, ＋, （) and mathematical letters (𝐑) are caught by NFKC normalisation.
LOOKALIKES = {
    # Cyrillic capitals and small letters
    "А": "A", "В": "B", "С": "C", "Е": "E", "Н": "H", "І": "I", "Ј": "J", "К": "K", "М": "M",
    "О": "O", "Р": "P", "Ѕ": "S", "Т": "T", "Х": "X", "Ү": "Y", "Ԛ": "Q", "Ԝ": "W",
    "а": "a", "с": "c", "е": "e", "і": "i", "ј": "j", "о": "o", "р": "p", "ѕ": "s", "у": "y", "х": "x", "ԛ": "q", "ԝ": "w",
    # Greek capitals and small letters
    "Α": "A", "Β": "B", "Ε": "E", "Ζ": "Z", "Η": "H", "Ι": "I", "Κ": "K", "Μ": "M", "Ν": "N",
    "Ο": "O", "Ρ": "P", "Τ": "T", "Υ": "Y", "Χ": "X", "ο": "o", "ν": "v",
    # digits and operators that look like the circuit language's
    "−": "-", "∥": "||", "‖": "||", "ǀ": "|",
    # dashes, as pasted from a paper or a word processor (NFKC keeps them): hyphen, non-breaking
    # hyphen, figure dash, en dash, em dash, horizontal bar
    "‐": "-", "‑": "-", "‒": "-", "–": "-", "—": "-", "―": "-",
}


def describe_character(ch: str) -> str:
    """``'С' (U+0421 CYRILLIC CAPITAL LETTER ES)``: the character (escaped if invisible or a
    control character) and its code point and Unicode name."""
    name = unicodedata.name(ch, "")
    return f"'{escape_text(ch)}' (U+{ord(ch):04X}{' ' + name if name else ''})"


def lookalike(ch: str) -> str | None:
    """The ASCII text ``ch`` is drawn like (Cyrillic 'С' → 'C', full-width 'Ｒ' → 'R'), or None."""
    if ch in LOOKALIKES:
        return LOOKALIKES[ch]
    normal = unicodedata.normalize("NFKC", ch)
    return normal if normal != ch and normal.isascii() and normal.isprintable() and normal.strip() else None


def _character_hint(ch: str, source: str) -> str:
    ascii_twin = lookalike(ch)
    if ch == "/":  # the parallel sign of papers (R//C) and of EC-Lab's circuits (R1+C2/R2)
        if "|" in source:  # (both signs: in neither notation)
            return "parallel is written '||': R1 || C1"
        return f"parallel is written '||': R1 || C1; in Python an EC-Lab string is passed as {EC_LAB_CALL}({_call_text(source)}) (the command line reads it by itself)"
    if ascii_twin is None:
        return "expected an element such as R1 or C_gap, '(' , '+' or '||'"
    if ascii_twin == "-":  # '-' is series in impedance.py's notation; impedax writes '+'
        kind = "a minus sign" if ch == "−" else "a dash"
        return f"{kind} '{ch}': series is written '+' (or '-' in impedance.py's notation)"
    if ascii_twin.isalpha():
        return f"did you mean the Latin {ascii_twin!r}? this character only looks like it; retype it"
    return f"did you mean {ascii_twin!r}? this character only looks like it; retype it"


def _split_element(source: str, tok: Token, registry: Registry) -> str:
    """Return the element's symbol, or raise with a precise hint."""
    text = tok.text
    if "_" in text:
        symbol, _, label = text.partition("_")
        if symbol not in registry:
            raise CircuitSyntaxError(source, tok.column, f"unknown element symbol {symbol!r} in {text!r}", _symbol_hint(symbol, "_" + label, registry), unknown_symbol=symbol)
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
        raise CircuitSyntaxError(source, tok.column, f"unknown element {text!r}", _symbol_hint(letters, rest, registry), unknown_symbol=letters)
    symbol, _digits = m.groups()
    if symbol not in registry:
        raise CircuitSyntaxError(source, tok.column, f"unknown element symbol {symbol!r} in {text!r}", _symbol_hint(symbol, _digits, registry), unknown_symbol=symbol)
    return symbol


# impedance.py's elements that no built-in impedax element implements (docs/migrating.md,
# "Elements"); the others are read through `Registry.by_impedance_py`
IMPEDANCE_PY_WITHOUT_EQUIVALENT = ("Gs", "K", "La", "T", "TLMQ")


# EC-Lab's element symbols for impedax's elements of another symbol, with the same formula and
# parameters (R, tau): its ZFit manual's Wd, R_d tanh(√(τ_d jω))/√(τ_d jω), is impedax's Ws, and
# its M (restricted linear diffusion), R_d coth(√(τ_d jω))/√(τ_d jω), impedax's Wo. Its R, C, L,
# Q, W and G are impedax's symbols (`from_ec_lab`).
EC_LAB_SYMBOLS = {"Wd": "Ws", "M": "Wo"}
# EC-Lab's elements that no built-in impedax element implements, by what they are
EC_LAB_WITHOUT_EQUIVALENT = {
    "Ma": "modified restricted diffusion", "Mg": "anomalous diffusion", "Ga": "modified Gerischer",
    "Gb": "modified Gerischer", "La": "modified inductor", "Winf": "convective diffusion",
}
EC_LAB_CALL = "ix.from_ec_lab"  # the reader of EC-Lab strings, as docs/circuits.md writes it


def ec_lab_symbols(text: str, registry: Registry) -> dict[str, str]:
    """EC-Lab's symbols in ``text`` that name an impedax element by another symbol
    (`EC_LAB_SYMBOLS`, ``{"Wd": "Ws"}``), where ``registry`` has no element of that symbol (a
    user's element M stays the user's)."""
    found = {}
    for m in EC_LAB_NAME_RE.finditer(text):
        letters = m.group(1)
        if letters in EC_LAB_SYMBOLS and letters not in registry and EC_LAB_SYMBOLS[letters] in registry:
            found[letters] = EC_LAB_SYMBOLS[letters]
    return found


# an element name: the letters that open it (its symbol: Wd of Wd2, R of R_ct) and the rest; not
# the letters of a number (1e-3)
EC_LAB_NAME_RE = re.compile(r"(?<![\w.])([A-Za-z]+)(\w*)")


def _symbol_hint(letters: str, rest: str, registry: Registry) -> str:
    spec = registry.by_impedance_py.get(letters)
    if spec is not None:  # Zarc1: impedance.py's name of CC
        name = f"{spec.symbol}{rest}" if rest.isdigit() or rest.startswith("_") else f"e.g. {spec.symbol}1"
        return f"impedance.py's {letters} is impedax's {spec.symbol}: {name}"
    spelled = impedance_py_spelling(letters, registry)
    if spelled is not None and spelled not in registry:  # zarc1: impedance.py's Zarc in lower case
        spec = registry.by_impedance_py[spelled]
        name = f"{spec.symbol}{rest}" if rest.isdigit() or rest.startswith("_") else f"e.g. {spec.symbol}1"
        return f"symbols are case-sensitive, and impedance.py's {spelled} is impedax's {spec.symbol}: {name}"
    if letters in EC_LAB_SYMBOLS and EC_LAB_SYMBOLS[letters] in registry:  # Wd2: EC-Lab's Ws
        spec = registry[EC_LAB_SYMBOLS[letters]]
        name = f"{spec.symbol}{rest}" if rest.isdigit() or rest.startswith("_") else f"e.g. {spec.symbol}1"
        return f"EC-Lab's {letters} is impedax's {spec.symbol} ({spec.equation}): {name}; in Python an EC-Lab string is passed as {EC_LAB_CALL}(...) (the command line reads it by itself)"
    if letters in IMPEDANCE_PY_WITHOUT_EQUIVALENT:
        return f"impedance.py's {letters} has no built-in impedax element: register one with impedance_py={letters!r} {ADDING_AN_ELEMENT}"
    if letters.upper() in registry or letters.capitalize() in registry:
        fixed = letters.upper() if letters.upper() in registry else letters.capitalize()
        return f"symbols are case-sensitive: did you mean {fixed}{rest}?"
    # a symbol of the user's own (Gfl) is unknown to a registry that lacks it: say so before a
    # built-in it resembles, which would fit another element under a label (G_fl1)
    own = f"if {letters} is an element of your own, {PASS_DECLARING_REGISTRY}; " if letters.isascii() and letters.isalpha() and letters[0].isupper() else ""
    for sym in registry.symbols():  # letters swapped: CEP1 is CPE1 (not C with label EP1)
        if len(sym) == len(letters) > 1 and sorted(sym) == sorted(letters):
            return f"{own}{'else ' if own else ''}did you mean {sym}{rest}?"
    labelled = next((f"{sym}_{letters[len(sym):]}{rest.lstrip('_')}" for sym in registry.symbols() if letters.startswith(sym) and len(letters) > len(sym)), None)  # (longest first, so CPE wins over C)
    typed = [sym for sym in registry.symbols() if _one_edit_apart(letters, sym)]  # a letter doubled, dropped or mistyped: CPEE1, CP1, Wss1
    if typed:
        return f"{own}{'else ' if own else ''}did you mean {max(typed, key=len)}{rest}" + (f" (or {labelled}, an element {labelled.partition('_')[0]} with a label)?" if labelled else "?")
    if labelled:
        return f"{own}{'else ' if own else ''}did you mean {labelled}?"
    return f"{own}known symbols: " + ", ".join(sorted(registry.symbols()))


def _one_edit_apart(typed: str, symbol: str) -> bool:
    """Whether ``typed`` is ``symbol`` with one slip of the keyboard: a letter doubled (CPEE,
    RR, Wss), a letter dropped (CP, from two letters on) or one replaced (CPF, from three on: in
    shorter symbols any letter would do, X for C). Case counts."""
    if len(typed) == len(symbol) + 1:
        return any(typed[:i] + typed[i + 1:] == symbol and typed[i] == typed[i - 1] for i in range(1, len(typed)))
    if len(typed) + 1 == len(symbol):
        return len(typed) >= 2 and any(symbol[:i] + symbol[i + 1:] == typed for i in range(len(symbol)))
    return len(typed) == len(symbol) >= 3 and sum(x != y for x, y in zip(typed, symbol)) == 1


def impedance_py_spelling(letters: str, registry: Registry) -> str | None:
    """The impedance.py symbol ``letters`` spells in another case (``zarc`` → ``Zarc``,
    ``cpe`` → ``CPE``), or None; symbols are case-sensitive in both notations."""
    return next((symbol for symbol in registry.by_impedance_py if symbol.lower() == letters.lower() and symbol != letters), None)


class _Parser:
    def __init__(self, source: str, registry: Registry):
        self.source = source
        self.registry = registry
        self.tokens = tokenize(source, registry)
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
        return series(*self.joined("+", self.parallel))

    def parallel(self) -> Circuit:
        return parallel(*self.joined("||", self.term))

    def joined(self, operator: str, part) -> list[Circuit]:
        """``part ( operator part )*``."""
        parts = [part()]
        while self.peek().kind == operator:
            self.take()
            parts.append(part())
        return parts

    def term(self) -> Circuit:
        tok = self.take()
        if tok.kind == "element":
            if tok.text == "p" and self.peek().kind == "(":
                raise CircuitSyntaxError(self.source, tok.column, "unexpected 'p('", _notation_hint(self.source, "p(", self.registry))
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
    """Parse circuit text such as ``"R_f + R_sc || CPE_sc"`` into an immutable `Circuit`
    (a `Circuit` is returned as it is, so every function taking a circuit accepts either).
    ``+`` joins in series, ``||`` in parallel and binds tighter (``R0 + R1 || C1`` is R0 in
    series with R1 ∥ C1); brackets group. An element is its type and a label (``R1``,
    ``CPE_sc``); the grammar is in docs/circuits.md.

    Raises `CircuitSyntaxError` (with column, caret and hint) on invalid input.
    """
    if not isinstance(registry, Registry):
        raise ParameterError(f"registry must be a Registry (e.g. impedax.DEFAULT_REGISTRY.register(spec)), got {type(registry).__name__}")
    if isinstance(text, Circuit):
        return text
    return _parse_text(require_text(text), registry)


# the argument orders of the functions that take a circuit and data (said when they look swapped)
ARGUMENT_ORDERS = "fit and sample take (circuit, data), diagnose and refine take (data, circuit)"


def looks_like_data(source) -> bool:
    """Whether ``source`` is a spectrum rather than a circuit: an xarray Dataset or DataArray
    (duck-typed: this layer does not import xarray) or a path object."""
    return hasattr(source, "data_vars") or (hasattr(source, "dims") and hasattr(source, "coords")) or hasattr(source, "__fspath__")


def require_text(source) -> str:
    """``source`` if it is a string; otherwise a `CircuitSyntaxError` naming its type (a
    `CircuitError` for a spectrum where the circuit goes: the arguments look swapped,
    `ARGUMENT_ORDERS`)."""
    if not isinstance(source, str):
        kind = type(source).__name__
        if looks_like_data(source):
            raise CircuitError(f"a circuit must be text, got a {kind} (data) where the circuit goes: the arguments look swapped ({ARGUMENT_ORDERS})")
        raise CircuitSyntaxError(repr(source), 0, f"a circuit must be text, got {kind}")
    return source


@functools.lru_cache(maxsize=256)
def _parse_text(text: str, registry: Registry) -> Circuit:
    # circuits are immutable, so a repeated text (a fit per spectrum) is parsed once
    try:
        return _Parser(text, registry).parse()
    except CircuitSyntaxError as exc:
        if not looks_like_cdc(text, registry):
            raise
        raise CircuitSyntaxError(exc.source, exc.column, exc.reason, CDC_HINT.format(call=f"{CDC_CALL}({_call_text(text)})"), unknown_symbol=exc.unknown_symbol) from None


CDC_CALL = "ix.from_cdc"  # the reader of Boukamp's circuit description code, as docs/circuits.md writes it
CDC_HINT = "this reads as Boukamp's circuit description code (CDC), which has no element names; in Python it is passed as {call} (the command line reads it by itself)"
_CDC_TEXT_RE = re.compile(r"[\sA-Z()\[\]]*[A-Z][\sA-Z()\[\]]*\Z")


def looks_like_cdc(text: str, registry: Registry = DEFAULT_REGISTRY) -> bool:
    """Whether ``text`` is written in Boukamp's circuit description code (``R(RC)``, ``R(C[RW])``):
    only capital letters, each one of ``registry``'s CDC letters, brackets and spaces. impedax
    text never is (its element names carry a number or a label), nor is impedance.py's."""
    return _CDC_TEXT_RE.match(text) is not None and all(ch in registry.by_cdc for ch in text if ch.isalpha())
