"""The circuit language: grammar, canonical text, errors with columns, converters."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import impedax as ix
from impedax.circuits import Element, Parallel, Series, from_cdc, from_impedance_py


def test_precedence_and_canonical_text():
    c = ix.parse("R_f + R_sc || CPE_sc")
    assert c == Series([Element("R", "R_f"), Parallel([Element("R", "R_sc"), Element("CPE", "CPE_sc")])])
    assert str(c) == "R_f + R_sc || CPE_sc"
    assert ix.parse("  R_f+R_sc||CPE_sc ") == c
    nested = ix.parse("R0 + (R1 + C1) || (R2 || C2)")
    assert str(nested) == "R0 + (R1 + C1) || R2 || C2"
    assert ix.parse(str(nested)) == nested
    assert ix.parse("((R1))") == Element("R", "R1")


@pytest.mark.parametrize(
    "text, symbol",
    [("CPE1", "CPE"), ("C1", "C"), ("CC1", "CC"), ("Q1", "Q"), ("Wo1", "Wo"), ("Ws_x", "Ws"), ("W0", "W"), ("HN_skin", "HN"), ("G1", "G"), ("L_lead", "L"), ("C_gap", "C"), ("R_sc_2", "R")],
)
def test_symbols_are_matched_unambiguously(text, symbol):
    assert ix.parse(text) == Element(symbol, text)


@pytest.mark.parametrize(
    "text, column, fragment",
    [
        ("Csc", 0, "did you mean C_sc?"),
        ("Rp1 + C1", 0, "did you mean R_p1?"),
        ("R0 + R1 || CEP1", 11, "did you mean CPE1?"),
        ("R1 + r2", 5, "case-sensitive: did you mean R2?"),
        ("R1 +", 4, "expected an element or '('"),
        ("R1 + + C1", 5, "expected an element or '('"),
        ("R1 | C1", 3, "parallel is written '||'"),
        ("R1 - C1", 3, "series is written '+'"),
        ("R1 + R1", 5, "duplicate element name 'R1'"),
        ("(R1 + C1", 8, "is not closed"),
        ("R1 + C1)", 7, "unbalanced ')'"),
        ("R1 C1", 3, "expected '+', '||' or end of input"),
        ("", 0, "empty circuit"),
        ("   ", 0, "empty circuit"),
        ("R", 0, "needs a number or a label"),
        ("X1", 0, "unknown element symbol 'X'"),
        ("R_", 2, "bad label"),
        ("R1 + C_a__b", 7, "bad label"),
        ("R1 + 5", 5, "unexpected character '5'"),
        ("()", 1, "expected an element or '('"),
        ("R1 || ", 6, "found end of input"),
        ("R1 + C1 ||| C2", 10, "a single '|'"),
    ],
)
def test_invalid_circuits_give_column_and_hint(text, column, fragment):
    with pytest.raises(ix.CircuitSyntaxError) as info:
        ix.parse(text)
    err = info.value
    assert err.column == column
    assert fragment in str(err)
    lines = str(err).splitlines()
    assert lines[1] == "  " + text and lines[2] == "  " + " " * column + "^"


_SYMBOLS = ["R", "C", "L", "CPE", "Q", "W", "Wo", "Ws", "G", "CC", "HN"]


@st.composite
def circuits(draw, depth=3):
    counter = draw(st.shared(st.just([0]), key="counter"))

    def element():
        counter[0] += 1
        sym = draw(st.sampled_from(_SYMBOLS))
        name = f"{sym}{counter[0]}" if draw(st.booleans()) else f"{sym}_n{counter[0]}"
        return Element(sym, name)

    def node(d):
        if d == 0 or draw(st.integers(0, 2)) == 0:
            return element()
        kids = [node(d - 1) for _ in range(draw(st.integers(2, 3)))]
        return (Series if draw(st.booleans()) else Parallel)(kids)

    return node(depth)


@settings(max_examples=200, deadline=None)
@given(circuits())
def test_round_trip(c):
    assert ix.parse(str(c)) == c
    assert ix.parse(str(c).replace(" ", "")) == c


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet="RCLQWoGHNPE_0123456789+|() -,xs", max_size=25))
def test_garbage_raises_only_impedax_errors(text):
    try:
        c = ix.parse(text)
    except ix.ImpedaxError:
        return
    assert ix.parse(str(c)) == c


def test_tree_is_immutable_and_edits_build_new_trees():
    c = ix.parse("R0 + C1")
    with pytest.raises(AttributeError):
        c.children = ()
    d = c.replace("C1", ix.parse("R2 || C1"))
    assert str(c) == "R0 + C1" and str(d) == "R0 + R2 || C1"
    assert hash(ix.parse("R0 + C1")) == hash(c)


# --- robustness: hostile input raises impedax errors, never RecursionError -----------------


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=60))
def test_random_unicode_raises_only_impedax_errors(text):
    for convert in (ix.parse, from_impedance_py, from_cdc):
        try:
            convert(text)
        except ix.ImpedaxError:
            pass


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 3000), st.sampled_from(["R1", "R1 + C1", "R1 || C1"]))
def test_deep_parentheses_parse_or_raise_syntax_error(depth, core):
    from impedax.circuits.parser import MAX_NESTING

    text = "(" * depth + core + ")" * depth
    if depth <= MAX_NESTING:
        assert ix.parse(text) == ix.parse(core)
    else:
        with pytest.raises(ix.CircuitSyntaxError, match="nested deeper") as info:
            ix.parse(text)
        assert info.value.column == MAX_NESTING


@pytest.mark.parametrize("depth", [65, 500, 5000])
def test_deep_nesting_in_converters_is_a_syntax_error(depth):
    with pytest.raises(ix.CircuitSyntaxError, match="nested deeper"):
        from_impedance_py("R0-" + "p(" * depth + "C1" + ",R9)" * depth)
    with pytest.raises(ix.CircuitSyntaxError, match="nested deeper"):
        from_cdc("R" + "([" * depth + "C" + "]R)" * depth)


def test_alternating_deep_tree_within_limit_round_trips():
    text = "R0"
    for k in range(1, 31):
        text = f"(R{k} || ({text} + C{k}))"
    c = ix.parse(text)
    assert ix.parse(str(c)) == c and len(c.element_names) == 61


def test_too_many_elements_and_very_long_inputs():
    from impedax.circuits.parser import MAX_ELEMENTS

    ok = " + ".join(f"R{k}" for k in range(MAX_ELEMENTS))
    assert len(ix.parse(ok).element_names) == MAX_ELEMENTS
    with pytest.raises(ix.CircuitSyntaxError, match=f"more than {MAX_ELEMENTS} elements"):
        ix.parse(ok + f" + R{MAX_ELEMENTS}")
    with pytest.raises(ix.CircuitSyntaxError, match="more than"):
        ix.parse(" + ".join(f"R{k}" for k in range(100_000)))
    with pytest.raises(ix.CircuitSyntaxError, match="unexpected character"):
        ix.parse("R1 + " + "€" * 1_000_000)
    with pytest.raises(ix.CircuitSyntaxError, match="more than"):
        from_cdc("R" * 10_000)


@pytest.mark.parametrize(
    "text, name, left",
    [
        ("C_i + R_sc || C_sc + R2 || CPE2", "C_sc", "C_i + R_sc + R2 || CPE2"),  # a two-child block becomes its other child
        ("C_i + R_sc || C_sc", "C_i", "R_sc || C_sc"),
        ("R0 + (R1 + R2 || C2) || C1", "C2", "R0 + (R1 + R2) || C1"),  # nested series flattened
        ("R1 || C1 || CPE1", "C1", "R1 || CPE1"),
    ],
)
def test_without_removes_one_element(text, name, left):
    assert ix.parse(text).without(name) == ix.parse(left)


def test_without_an_unknown_or_the_only_element_is_an_error():
    with pytest.raises(ix.CircuitError, match="no element named 'C9'"):
        ix.parse("R1 || C1").without("C9")
    with pytest.raises(ix.CircuitError, match="nothing would be left"):
        ix.parse("R1").without("R1")
