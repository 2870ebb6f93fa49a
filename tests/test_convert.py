"""Circuits in other tools' notations: impedance.py strings, Boukamp's CDC and AutoEIS strings, read and written.

Expected trees and strings are written out by hand from the notations' definitions; the
bracket-convention writer is also checked against pyimpspec's CDC parser (another package's
reading of the same string) where it is installed.
"""

import cmath
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import impedax as ix
from impedax.circuits import CDCConvention, Element, Parallel, Series, from_autoeis, from_cdc, from_ec_lab, from_impedance_py, to_cdc, to_impedance_py

# --- impedance.py ---------------------------------------------------------------------------


# impedance.py strings and CDC (bracket convention) read into trees written out by hand
READS = [
    (from_impedance_py, "R0-p(R1,C1)-CPE1", "R0 + R1 || C1 + CPE1"),
    (from_impedance_py, "R0-p(R1-Wo1,CPE1)", "R0 + (R1 + Wo1) || CPE1"),
    (from_impedance_py, "R_0-Ws1-G2-L3", "R0 + Ws1 + G2 + L3"),
    (from_cdc, "R(RC)(RQ)", "R1 + R2 || C1 + R3 || CPE1"),
    (from_cdc, "R([RW]C)", "R1 + (R2 + W1) || C1"),
    (from_cdc, "R(C[RW])", "R1 + C1 || (R2 + W1)"),
    (from_cdc, "R(C[R(CR)])", "R1 + C1 || (R2 + C2 || R3)"),
    (from_cdc, "LOTG", "L1 + Ws1 + Wo1 + G1"),
    # AutoEIS's documented example (its circuit notation page): '-' series, [a,b] parallel, P a CPE
    (from_autoeis, "R1-C2-[R3,P4]-[R5,[R6,C7]]", "R1 + C2 + R3 || CPE4 + R5 || R6 || C7"),
    (from_autoeis, "R1-[R2-P3,C4] - L5", "R1 + (R2 + CPE3) || C4 + L5"),
    (from_autoeis, "P1", "CPE1"),
    # EC-Lab: '/' parallel, binding closer than '+'; its Wd and M are impedax's Ws and Wo
    (from_ec_lab, "R1+Q2/(R2+Wd2)", "R1 + Q2 || (R2 + Ws2)"),
    (from_ec_lab, "L1+R1+C2/(R2+M2)", "L1 + R1 + C2 || (R2 + Wo2)"),
    (from_ec_lab, "C1/R1+C2/R2", "C1 || R1 + C2 || R2"),
    (from_ec_lab, "R0 + R1//C1 + W2 + G3", "R0 + R1 || C1 + W2 + G3"),
    (from_ec_lab, "R1+Wd2", "R1 + Ws2"),
]
REFUSED = [
    (from_impedance_py, "R0-TLMQ1", "no impedax equivalent"),
    (from_impedance_py, "R0-p(R1,C1", "closing p"),
    (from_cdc, "R(RX)", "unknown CDC element"),
    (from_cdc, "R(RC", "unclosed group"),
    (from_autoeis, "R1-[R2,P3", r"expected '\]' closing \["),
    (from_autoeis, "R1-[R2]", r"\[\.\.\.\] needs at least two branches"),
    (from_autoeis, "R1-[R2,X3]", "AutoEIS element 'X' has no impedax equivalent"),
    (from_autoeis, "R1-p(R2,C3)", r"expected an element such as R1 or \["),  # (impedance.py's group)
    (from_autoeis, "R1-R1", "duplicate element name 'R1'"),
    (from_ec_lab, "R1+Ma2/R2", r"EC-Lab's Ma \(modified restricted diffusion\) has no built-in impedax element"),
    (from_ec_lab, "R1+Q2/(R2", "expected '\\)'"),
    (from_ec_lab, " ", "empty circuit"),
]


@pytest.mark.parametrize("read, text, expected", READS)
def test_other_notations_read(read, text, expected):
    assert read(text) == ix.parse(expected)


@pytest.mark.parametrize("read, text, match", REFUSED)
def test_other_notations_refused_with_a_message(read, text, match):
    with pytest.raises(ix.CircuitSyntaxError, match=match):
        read(text)


@pytest.mark.parametrize(
    "text, expected",
    [
        ("R0 + R1 || C1 + CPE1", "R0-p(R1,C1)-CPE1"),
        ("R0 + (R1 + Wo1) || CPE1", "R0-p(R1-Wo1,CPE1)"),
        ("(R1 + C1) || (L1 + R2 || CPE1)", "p(R1-C1,L1-p(R2,CPE1))"),
        ("R_s + R_ct || C_dl + W_d", "R0-p(R1,C0)-W0"),  # labels become numbers
        ("R_a + R0 + Q1", "R1-R0-CPE0"),  # R0 is kept, so R_a takes R1; the alias Q is written CPE
    ],
)
def test_to_impedance_py(text, expected):
    c = ix.parse(text)
    assert c.to_impedance_py() == expected
    assert to_impedance_py(text) == expected


def test_impedance_py_names_say_how_elements_were_renamed():
    c = ix.parse("R_s + R_ct || C_dl + R1")
    assert c.impedance_py_names() == {"R_s": "R0", "R_ct": "R2", "C_dl": "C0", "R1": "R1"}
    renamed = from_impedance_py(c.to_impedance_py())
    assert renamed == ix.parse("R0 + R2 || C0 + R1")


def test_elements_impedance_py_lacks_are_refused_by_name():
    with pytest.raises(ix.CircuitError, match=r"HN1 \(Havriliak–Negami relaxation\) has no impedance.py equivalent"):
        ix.parse("R0 + HN1").to_impedance_py()


# --- CDC: reading both conventions ----------------------------------------------------------


def test_classic_randles_string_is_the_randles_circuit():
    # the classic convention: nesting alternates parallel and series, so R(C(RW)) is
    # R + C ∥ (R + W), not C ∥ R ∥ W (what the bracket reading of '((' would give)
    assert from_cdc("R(C(RW))") == ix.parse("R1 + C1 || (R2 + W1)")
    assert from_cdc("R(C(RW))") == from_cdc("R(C[RW])")


@pytest.mark.parametrize(
    "classic, impedax_text",
    [
        ("R(C(R(CR)))", "R1 + C1 || (R2 + C2 || R3)"),  # depth 3 is parallel again
        ("(R(CW))", "R1 || (C1 + W1)"),  # a whole-circuit parallel group
        ("R(Q(R(QR)))(RC)", "R1 + CPE1 || (R2 + CPE2 || R3) + R4 || C1"),
    ],
)
def test_classic_convention_alternates_with_depth(classic, impedax_text):
    assert from_cdc(classic) == ix.parse(impedax_text)
    assert from_cdc(classic, convention="alternating") == ix.parse(impedax_text)


def test_mixed_conventions_are_refused_with_a_hint_not_guessed():
    text = "R(C(R[RW]))"
    with pytest.raises(ix.CircuitSyntaxError) as info:
        from_cdc(text)
    assert info.value.column == 3  # the '(' that opens inside a '('
    message = str(info.value)
    assert "ambiguous" in message and "convention='brackets'" in message and "convention='alternating'" in message
    # told which is meant, it reads it
    assert from_cdc(text, convention="brackets") == ix.parse("R1 + C1 || R2 || (R3 + W1)")
    with pytest.raises(ix.CircuitSyntaxError, match=r"'\[' in a classic"):
        from_cdc(text, convention=CDCConvention.ALTERNATING)


def test_explicit_bracket_convention_reads_nested_parentheses_as_parallel():
    assert from_cdc("R(C(RW))", convention="brackets") == ix.parse("R1 + C1 || R2 || W1")


def test_unknown_convention_is_an_error():
    with pytest.raises(ix.CircuitError, match="convention must be one of"):
        from_cdc("R(RC)", convention="boukamp")


# --- CDC: writing ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "text, expected",
    [
        ("R_s + C_dl || (R_ct + W_d)", "R(C[RW])"),
        ("R0 + R1 || CPE1 + R2 || Q2", "R(RQ)(RQ)"),
        ("(R1 + C1) || (L1 + R2 || CPE1)", "([RC][L(RQ)])"),
        ("L1 + Ws1 + Wo1 + G1", "LOTG"),
        ("R1", "R"),
    ],
)
def test_to_cdc(text, expected):
    assert ix.parse(text).to_cdc() == expected
    assert to_cdc(text) == expected


def test_elements_cdc_lacks_are_refused_by_name():
    with pytest.raises(ix.CircuitError, match=r"CC1 \(Cole–Cole relaxation\) has no CDC equivalent; CDC can express: R \(R\), C \(C\)"):
        ix.parse("R0 + CC1 || C1").to_cdc()


# --- round trips over random trees ----------------------------------------------------------

_SYMBOLS = ("R", "C", "L", "CPE", "W", "Wo", "Ws", "G")
_shapes = st.recursive(
    st.sampled_from(_SYMBOLS),
    lambda inner: st.tuples(st.sampled_from(["series", "parallel"]), st.lists(inner, min_size=2, max_size=3)),
    max_leaves=12,
)


def _numbered_tree(shape) -> ix.Circuit:
    """The tree of ``shape`` with elements numbered per symbol from 1 in order of appearance
    (the names the CDC reader gives)."""
    counts: dict[str, int] = {}

    def build(node):
        if isinstance(node, str):
            counts[node] = counts.get(node, 0) + 1
            return Element(node, f"{node}{counts[node]}")
        kind, children = node
        built = [build(c) for c in children]
        return Series(built) if kind == "series" else Parallel(built)

    return build(shape)


def _classic_cdc(c: ix.Circuit, top: bool = True) -> str:
    """The classic (alternating) CDC of ``c``, written from the convention's definition: every
    group but the top-level series chain is one pair of parentheses."""
    letters = {"R": "R", "C": "C", "L": "L", "CPE": "Q", "W": "W", "Wo": "T", "Ws": "O", "G": "G"}
    if isinstance(c, Element):
        return letters[c.symbol]
    inner = "".join(_classic_cdc(child, top=False) for child in c.children)
    return inner if top and isinstance(c, Series) else f"({inner})"


@settings(max_examples=150, deadline=None)
@given(_shapes)
def test_cdc_and_impedance_py_round_trip(shape):
    c = _numbered_tree(shape)
    assert from_cdc(c.to_cdc()) == c
    assert from_cdc(c.to_cdc(), convention="brackets") == c
    assert from_impedance_py(c.to_impedance_py()) == c
    assert from_cdc(_classic_cdc(c)) == c


# --- another package's reading of the written CDC -------------------------------------------


@pytest.mark.parametrize(
    "text",
    ["R_s + C_dl || (R_ct + CPE_d)", "(R1 + C1) || (L1 + R2 || CPE1)", "R0 || C0", "R1 + (R2 + C1 || (R3 + L1)) || CPE1 + C2"],
)
def test_written_cdc_means_the_same_circuit_to_pyimpspec(text):
    pyimpspec = pytest.importorskip("pyimpspec")
    c = ix.parse(text)
    rng = np.random.default_rng(7)
    values = {}
    theirs = pyimpspec.parse_cdc(c.to_cdc())
    for e, element in zip(c.elements(), theirs.get_elements()):
        # pyimpspec names: R, C, L and Q(Y, n) with Z = 1/(Y (jω)^n), as impedax's CPE(Q, α)
        if e.symbol == "CPE":
            q, alpha = 10 ** rng.uniform(-7, -4), rng.uniform(0.5, 1.0)
            values[f"{e.name}.Q"], values[f"{e.name}.alpha"] = q, alpha
            element.set_values(Y=q, n=alpha)
        else:
            v = {"R": 10 ** rng.uniform(0, 4), "C": 10 ** rng.uniform(-8, -5), "L": 10 ** rng.uniform(-6, -3)}[e.symbol]
            values[e.name] = v
            element.set_values(**{e.symbol: v})
    f = np.logspace(-1, 6, 15)
    ours = np.asarray(ix.compile_circuit(c)(values, f))
    np.testing.assert_allclose(ours, theirs.get_impedances(f), rtol=1e-10)


def test_autoeis_cpe_has_the_cpe_impedance_of_its_w_and_n():
    # AutoEIS's CPE: Z = 1/(Q (jω)^α), Q its P·w and α its P·n; R1-[R2,P3] by hand
    c = from_autoeis("R1-[R2,P3]")
    assert c.parameter_names() == ("R1", "R2", "CPE3.Q", "CPE3.alpha")
    values = {"R1": 10.0, "R2": 250.0, "CPE3.Q": 3e-5, "CPE3.alpha": 0.85}
    for f in (0.1, 10.0, 1e4):
        cpe = 1 / (3e-5 * (2j * math.pi * f) ** 0.85)
        expected = 10.0 + 1 / (1 / 250.0 + 1 / cpe)
        assert complex(ix.compile_circuit(c)(values, np.array([f]))[0]) == pytest.approx(expected, rel=1e-12)


def test_randles_read_from_classic_cdc_has_the_randles_impedance():
    # closed form of R_s + C_dl ∥ (R_ct + W): Z = R_s + 1/(jωC + 1/(R_ct + σ(1 − j)/√ω))
    c = from_cdc("R(C(RW))")
    values = {"R1": 20.0, "C1": 2e-5, "R2": 150.0, "W1.sigma": 40.0}
    for f in (0.1, 10.0, 1e4):
        w = 2 * math.pi * f
        expected = 20.0 + 1 / (1j * w * 2e-5 + 1 / (150.0 + 40.0 * (1 - 1j) / cmath.sqrt(w)))
        assert complex(ix.compile_circuit(c)(values, np.array([f]))[0]) == pytest.approx(expected, rel=1e-12)


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet="RCLQWOTGX()[] ", max_size=30))
def test_cdc_garbage_raises_only_impedax_errors_and_what_reads_round_trips(text):
    try:
        c = from_cdc(text)
    except ix.ImpedaxError:
        return
    assert from_cdc(c.to_cdc()) == c


def test_ec_lab_circuits_evaluate_as_ec_labs_own_formulas():
    """EC-Lab's manual (ZFit, section 4.3.1.1.4): Wd = R_d tanh(√(τ_d jω))/√(τ_d jω), M =
    R_d coth(√(τ_d jω))/√(τ_d jω), Q = 1/(Q (jω)^a): a supercapacitor's L1 + R1 + C2/(R2 + M2)
    and a Randles cell with Wd, written out here by hand."""
    f = np.logspace(-3, 5, 41)
    s = 2j * np.pi * f
    values = {"L1": 98.45e-9, "R1": 31.61e-3, "C2": 15.59e-3, "R2": 4.23e-3, "Wo2.R": 37.89e-3, "Wo2.tau": 1.044}
    x = np.sqrt(values["Wo2.tau"] * s)
    m2 = values["Wo2.R"] / (np.tanh(x) * x)
    expected = s * values["L1"] + values["R1"] + 1 / (s * values["C2"] + 1 / (values["R2"] + m2))
    ours = np.asarray(ix.compile_circuit(from_ec_lab("L1+R1+C2/(R2+M2)"))(values, f))
    assert np.allclose(ours, expected, rtol=1e-12, atol=0)

    values = {"R1": 10.0, "Q2.Q": 2e-5, "Q2.alpha": 0.9, "R2": 50.0, "Ws2.R": 80.0, "Ws2.tau": 0.3}
    x = np.sqrt(values["Ws2.tau"] * s)
    wd2 = values["Ws2.R"] * np.tanh(x) / x
    expected = values["R1"] + 1 / (values["Q2.Q"] * s ** values["Q2.alpha"] + 1 / (values["R2"] + wd2))
    ours = np.asarray(ix.compile_circuit(from_ec_lab("R1+Q2/(R2+Wd2)"))(values, f))
    assert np.allclose(ours, expected, rtol=1e-12, atol=0)


def test_a_users_element_named_as_an_ec_lab_symbol_stays_the_users():
    mine = ix.Registry((*ix.DEFAULT_REGISTRY.specs, ix.ElementSpec("M", "my resistor", "Z = R", (ix.ParameterSpec("R", "Ohm", 1.0),), lambda w, r: r + 0 * w)))
    assert from_ec_lab("R1+M2/C3", mine) == ix.parse("R1 + M2 || C3", mine)
    assert from_ec_lab("R1+M2/C3") == ix.parse("R1 + Wo2 || C3")


@pytest.mark.parametrize(
    "text, column, in_message",
    [
        ("R1+Q2/(R2+Wd2", 13, "the '(' at column 7 is not closed"),  # (end of input; the hint's column on the typed text too)
        ("R1+Q2/(R2+M2)+X3", 14, "unknown element symbol 'X'"),
        ("R1 // Q2 / R2 + + C3", 16, "expected an element or '('"),
        ("R1+Q2/R2+Wd2+Wd2", 13, "(first at column 10)"),
    ],
)
def test_an_ec_lab_string_that_does_not_read_is_shown_as_typed(text, column, in_message):
    """The parse error of `from_ec_lab` shows the text as typed (not as rewritten, with '||' for
    '/' and Ws for Wd), its caret and every column it names on that text."""
    with pytest.raises(ix.CircuitSyntaxError) as caught:
        from_ec_lab(text)
    err = caught.value
    assert err.source == text and err.column == column
    assert f"\n  {text}\n  {' ' * column}^" in str(err) and in_message in str(err)
