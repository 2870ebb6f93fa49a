"""Parse-error hints for text that mixes notations or is pasted from elsewhere: each case's
column and message fragments are written by hand from the input."""

from __future__ import annotations

import json

import pytest

import impedax as ix
from impedax.cli import main


def syntax_error(text: str) -> ix.CircuitSyntaxError:
    with pytest.raises(ix.CircuitSyntaxError) as caught:
        ix.parse(text)
    return caught.value


def assert_caret(err: ix.CircuitSyntaxError, text: str, column: int) -> None:
    assert err.column == column
    lines = str(err).splitlines()
    assert lines[1] == "  " + text and lines[2] == "  " + " " * column + "^"


# --- impedance.py's p(a,b) inside impedax text ------------------------------------------------

MIXED = "p(a,b) is a || b in impedax's notation, and the two notations cannot be mixed: write the whole string in one, "


@pytest.mark.parametrize(
    "text, column, found, rewrites",
    [
        ("R0 + p(R1,C1)", 9, "unexpected ','", "R0 + R1 || C1 (impedax) or R0-p(R1,C1) (impedance.py)"),
        ("p(R1,C1) + R0", 4, "unexpected ','", "R1 || C1 + R0 (impedax) or p(R1,C1)-R0 (impedance.py)"),
        ("R0 || p(R1, C1)", 10, "unexpected ','", "R0 || R1 || C1 (impedax) or p(R0,R1,C1) (impedance.py)"),
        ("R0+p(R1-C1,C2)", 7, "unexpected '-'", "R0 + (R1 + C1) || C2 (impedax) or R0-p(R1-C1,C2) (impedance.py)"),
        ("R0 + p(R1||C1)", 5, "unexpected 'p('", "R0 + R1 || C1 (impedax) or R0-p(R1,C1) (impedance.py)"),
        ("R0 + p(R1,HN1)", 9, "unexpected ','", "R0 + R1 || HN1 (impedax)"),  # HN: no impedance.py element
        ("R0 + p(R1,X1)", 9, "unexpected ','", "e.g. R0 + R1 || C1 (impedax) or R0-p(R1,C1) (impedance.py)"),  # X: unreadable
    ],
)
def test_p_group_in_impedax_text_says_the_notations_cannot_be_mixed(text, column, found, rewrites):
    err = syntax_error(text)
    assert_caret(err, text, column)
    assert err.reason == found
    assert err.hint == MIXED + rewrites


def test_p_group_alone_is_answered_with_from_impedance_py():
    err = syntax_error("p(R1,C1)-R0")
    assert_caret(err, "p(R1,C1)-R0", 4)
    assert err.hint == "p(a,b) is impedance.py's notation for a || b; in Python an impedance.py string is passed as ix.from_impedance_py('p(R1,C1)-R0') (the command line reads it by itself)"


def test_comma_and_dash_without_p_group_keep_their_hints():
    assert syntax_error("R0 + R1, C1").hint == "series is written '+'"
    assert syntax_error("R0 + R1 - C1").hint.startswith("series is written '+'; in Python")


def test_long_mixed_text_gets_the_example_not_a_rewrite():
    text = " + ".join(f"R{k}" for k in range(30)) + " + p(R99,C99)"
    assert syntax_error(text).hint == MIXED + "e.g. R0 + R1 || C1 (impedax) or R0-p(R1,C1) (impedance.py)"


def test_cli_mixed_notation_exits_2_with_the_hint(capsys):
    assert main(["info", "R0 + p(R1,C1)"]) == 2
    err = capsys.readouterr().err
    assert "unexpected ',' at column 10" in err
    assert "hint: " + MIXED + "R0 + R1 || C1 (impedax) or R0-p(R1,C1) (impedance.py)" in err
    assert "series is written" not in err and "read as impedance.py" not in err and "Traceback" not in err


# --- a space between an element's symbol and its number or label ---------------------------


@pytest.mark.parametrize(
    "text, column, shown, name",
    [
        ("R0 + R 1", 6, "'R 1'", "R1"),
        ("R0 + Ws 2", 7, "'Ws 2'", "Ws2"),
        ("R 1", 1, "'R 1'", "R1"),
        ("R0 + R  12 || C1", 6, "'R  12'", "R12"),  # caret on the first space
        ("R0 + R _sc", 6, "'R _sc'", "R_sc"),
        ("R0 + R_ 1", 7, "'R_ 1'", "R_1"),
    ],
)
def test_space_inside_an_element_name_is_named(text, column, shown, name):
    err = syntax_error(text)
    assert_caret(err, text, column)
    assert err.reason == f"space inside the element name {shown}"
    assert err.hint == f"no space inside an element name: {name}"


def test_digit_after_a_whole_element_name_keeps_the_generic_message():
    err = syntax_error("R0 + R1 2")  # 'R1' already has its number: not a split name
    assert_caret(err, "R0 + R1 2", 8)
    assert err.reason == "unexpected character '2' (U+0032 DIGIT TWO)"


# --- impedance.py's element names --------------------------------------------------------------


@pytest.mark.parametrize(
    "text, column, reason, hint",
    [
        ("R0 + Zarc1", 5, "unknown element symbol 'Zarc' in 'Zarc1'", "impedance.py's Zarc is impedax's CC: CC1"),
        ("Zarc_skin + R0", 0, "unknown element symbol 'Zarc' in 'Zarc_skin'", "impedance.py's Zarc is impedax's CC: CC_skin"),
        ("R0 + Zarc", 5, "unknown element 'Zarc'", "impedance.py's Zarc is impedax's CC: e.g. CC1"),
        ("R0 + La1", 5, "unknown element symbol 'La' in 'La1'", "impedance.py's La has no built-in impedax element: register one with impedance_py='La' (docs/circuits.md, \"Adding an element\")"),
        ("R0 + TLMQ2", 5, "unknown element symbol 'TLMQ' in 'TLMQ2'", "impedance.py's TLMQ has no built-in impedax element: register one with impedance_py='TLMQ' (docs/circuits.md, \"Adding an element\")"),
        ("R0 + X1", 5, "unknown element symbol 'X' in 'X1'", "if X is an element of your own, pass the registry that declares it (registry= in Python); known symbols: C, CC, CPE, G, HN, L, Q, R, W, Wo, Ws"),
        # lower-case names: the right spelling (2026-12-01)
        ("zarc1", 0, "unknown element symbol 'zarc' in 'zarc1'", "symbols are case-sensitive, and impedance.py's Zarc is impedax's CC: CC1"),
        ("R0 + zarc_skin", 5, "unknown element symbol 'zarc' in 'zarc_skin'", "symbols are case-sensitive, and impedance.py's Zarc is impedax's CC: CC_skin"),
        ("r0 + R1", 0, "unknown element symbol 'r' in 'r0'", "symbols are case-sensitive: did you mean R0?"),
        ("R0 + cpe1", 5, "unknown element symbol 'cpe' in 'cpe1'", "symbols are case-sensitive: did you mean CPE1?"),
    ],
)
def test_impedance_py_and_lower_case_element_names_are_named_with_impedaxs(text, column, reason, hint):
    err = syntax_error(text)
    assert_caret(err, text, column)
    assert err.reason == reason and err.hint == hint


def test_a_users_element_with_an_impedance_py_name_is_named_too():
    from impedax.circuits import ElementSpec, ParameterSpec

    lead = ElementSpec("Lk", "lead inductance", "Z = jωL", (ParameterSpec("L", "H", 1e-6),), lambda omega, l: 1j * omega * l, impedance_py="La")
    registry = ix.DEFAULT_REGISTRY.register(lead)
    with pytest.raises(ix.CircuitSyntaxError) as caught:
        ix.parse("R0 + La1", registry)
    assert caught.value.hint == "impedance.py's La is impedax's Lk: Lk1"


# --- dashes pasted from a paper ----------------------------------------------------------------

DASH_HINT = "series is written '+' (or '-' in impedance.py's notation)"


@pytest.mark.parametrize(
    "text, column, described, kind",
    [
        ("R0 \u2013 R1", 3, "'\u2013' (U+2013 EN DASH)", "a dash '\u2013'"),
        ("R0 \u2014 R1", 3, "'\u2014' (U+2014 EM DASH)", "a dash '\u2014'"),
        ("R0 \u2212 R1", 3, "'\u2212' (U+2212 MINUS SIGN)", "a minus sign '\u2212'"),
        ("R0 + R1\u2011C1", 7, "'\u2011' (U+2011 NON-BREAKING HYPHEN)", "a dash '\u2011'"),
        ("R0 \uff0d R1", 3, "'\uff0d' (U+FF0D FULLWIDTH HYPHEN-MINUS)", "a dash '\uff0d'"),  # by NFKC
    ],
)
def test_dashes_say_how_series_is_written(text, column, described, kind):
    err = syntax_error(text)
    assert err.column == column  # (a full-width '－' takes two terminal columns: no caret check)
    assert err.reason == f"unexpected character {described}"
    assert err.hint == f"{kind}: {DASH_HINT}"


def test_dash_in_a_caret_line():
    assert_caret(syntax_error("R0 \u2013 R1"), "R0 \u2013 R1", 3)


def test_cli_en_dash_in_an_impedance_py_string_names_the_ascii_dash(capsys):
    assert main(["info", "R0\u2013p(R1,C1)"]) == 2  # read by from_impedance_py: it has 'p(' and no '+'
    err = capsys.readouterr().err
    assert "unexpected '\u2013' at column 3" in err
    assert "hint: a dash '\u2013': impedance.py's series is the ASCII '-'" in err and "Traceback" not in err


# --- impedance.py strings: series inside p( ), 'p (' with a space, lower-case names --------------


def test_series_inside_a_p_group_is_read_with_its_impedance():
    # R0-p(R1-C1,C2) is valid impedance.py (series inside a parallel branch): Z = R0 + 1/(1/(R1 + 1/(jωC1)) + jωC2)
    import numpy as np

    circuit = ix.from_impedance_py("R0-p(R1-C1,C2)")
    assert str(circuit) == "R0 + (R1 + C1) || C2"
    values = {"R0": 12.0, "R1": 300.0, "C1": 4e-6, "C2": 7e-8}
    f = np.logspace(-2, 6, 9)
    w = 2 * np.pi * f
    expected = 12.0 + 1 / (1 / (300.0 + 1 / (1j * w * 4e-6)) + 1j * w * 7e-8)
    np.testing.assert_allclose(np.asarray(ix.compile_circuit(circuit)(values, f)), expected, rtol=1e-12)


@pytest.mark.parametrize("text", ["R0-p (R1,C1)", "R0-p  (R1,C1)", "R0 - p (R1, C1)"])
def test_space_before_a_p_groups_parenthesis_is_read_as_impedance_py_reads_it(text):
    # impedance.py removes every space from a circuit string (CustomCircuit.__init__), so 'p (' is 'p('
    assert ix.from_impedance_py(text) == ix.parse("R0 + R1 || C1")


def test_p_space_group_in_impedax_text_is_rewritten_like_p_group():
    err = syntax_error("R0 + p (R1,C1)")
    assert_caret(err, "R0 + p (R1,C1)", 10)
    assert err.hint == MIXED + "R0 + R1 || C1 (impedax) or R0-p(R1,C1) (impedance.py)"


@pytest.mark.parametrize(
    "text, column, reason, hint",
    [
        ("R0-p(R1,zarc1)", 8, "unknown impedance.py element 'zarc' in 'zarc1'", "symbols are case-sensitive: did you mean Zarc1 (impedax's CC1)?"),
        ("r0-p(R1,C1)", 0, "unknown impedance.py element 'r' in 'r0'", "symbols are case-sensitive: did you mean R0?"),
        ("R0-p(R1,cpe1)", 8, "unknown impedance.py element 'cpe' in 'cpe1'", "symbols are case-sensitive: did you mean CPE1?"),
        ("R0-p(R1,wo1)", 8, "unknown impedance.py element 'wo' in 'wo1'", "symbols are case-sensitive: did you mean Wo1?"),
    ],
)
def test_lower_case_names_in_impedance_py_strings_are_named_in_the_right_spelling(text, column, reason, hint):
    with pytest.raises(ix.CircuitSyntaxError) as caught:
        ix.from_impedance_py(text)
    assert_caret(caught.value, text, column)
    assert caught.value.reason == reason and caught.value.hint == hint


@pytest.mark.parametrize(
    "model, shown, caret, hint",
    [
        ("zarc1", "zarc1", 0, "symbols are case-sensitive, and impedance.py's Zarc is impedax's CC: CC1"),
        ("R0-p(R1,zarc1)", "R0-p(R1,zarc1)", 8, "symbols are case-sensitive: did you mean Zarc1 (impedax's CC1)?"),
        ("R0 + cpe1", "R0 + cpe1", 5, "symbols are case-sensitive: did you mean CPE1?"),
    ],
)
def test_cli_fit_lower_case_names_exit_2_with_the_hint(tmp_path, capsys, model, shown, caret, hint):
    data = tmp_path / "spectrum.csv"  # SYNTHETIC: never read, the model is refused first
    data.write_text("freq,zreal,zimag\n1000,10,-1\n100,12,-5\n10,20,-9\n")
    assert main(["fit", str(data), "--model", model]) == 2
    err = capsys.readouterr().err
    assert f"  {shown}\n  {' ' * caret}^\n" in err and f"hint: {hint}" in err and "Traceback" not in err


def rc_spectrum_csv(tmp_path):
    """A SYNTHETIC spectrum of R + R || C (10 Ω, 100 Ω, 1 µF) from its closed form, 1 % noise, seed 7."""
    import numpy as np

    f = np.logspace(5, -1, 25)
    z = 10 + 100 / (1 + 1j * 2 * np.pi * f * 100 * 1e-6)
    z = z * (1 + 0.01 * np.random.default_rng(7).standard_normal(f.size))
    data = tmp_path / "spectrum.csv"
    data.write_text("freq,zreal,zimag\n" + "".join(f"{a:.6e},{b.real:.6e},{b.imag:.6e}\n" for a, b in zip(f, z)))
    return data


def test_cli_fit_reads_p_space_group(tmp_path, capsys):
    data = rc_spectrum_csv(tmp_path)
    assert main(["fit", str(data), "--model", "R0-p (R1,C1)"]) == 0
    assert "read as impedance.py notation: R0 + R1 || C1" in capsys.readouterr().err


# --- Boukamp's CDC (pyimpspec's and older programs' notation) where impedax text goes -----------

CDC = "this reads as Boukamp's circuit description code (CDC), which has no element names; in Python it is passed as "


@pytest.mark.parametrize(
    "text, column, reason",
    [
        ("R(RC)", 0, "element 'R' needs a number or a label"),
        ("R(C[RW])", 3, "unexpected character '['"),
        (" R ( Q ) ", 1, "element 'R' needs a number or a label"),
    ],
)
def test_cdc_text_is_named_with_the_call_that_reads_it(text, column, reason):
    err = syntax_error(text)
    assert_caret(err, text, column)
    assert err.reason.startswith(reason)
    assert err.hint == CDC + f"ix.from_cdc({text!r}) (the command line reads it by itself)"


@pytest.mark.parametrize(
    "text",
    [
        "R(RX)",  # X is no CDC letter
        "R(Rc)",  # lower case
        "R(RC)+",  # an impedax operator
        "",
        "()",
    ],
)
def test_text_that_is_no_cdc_gets_no_cdc_hint(text):
    assert not ix.circuits.looks_like_cdc(text)
    with pytest.raises(ix.CircuitSyntaxError) as caught:
        ix.parse(text)
    assert "circuit description code" not in str(caught.value)


def test_valid_impedax_and_impedance_py_text_never_looks_like_cdc():
    # every impedax element name carries a number or a label, and so does impedance.py's
    for text in ("R0 + R1 || C1", "R_f + R_sc || CPE_sc", "R0-p(R1,C1)", "L0 + R0 + R1 || CPE1 + W1"):
        assert not ix.circuits.looks_like_cdc(text)


@pytest.mark.parametrize("text", ["R1/C1", "R0 + R1//C1"])
def test_a_slash_is_answered_with_the_parallel_operator_and_the_ec_lab_reader(text):
    err = syntax_error(text)
    assert_caret(err, text, text.index("/"))
    assert err.hint == f"parallel is written '||': R1 || C1; in Python an EC-Lab string is passed as ix.from_ec_lab({text!r}) (the command line reads it by itself)"


def test_a_slash_beside_bars_is_in_no_notation_and_gets_no_reader():
    err = syntax_error("R0 + R1 || C1/R2")
    assert err.hint == "parallel is written '||': R1 || C1"


@pytest.mark.parametrize(
    "text, hint",
    [
        ("R1 + Wd2", "EC-Lab's Wd is impedax's Ws (Z = R tanh(√(jωτ))/√(jωτ)): Ws2"),
        ("R1 + M2", "EC-Lab's M is impedax's Wo (Z = R coth(√(jωτ))/√(jωτ)): Wo2"),
    ],
)
def test_ec_labs_diffusion_elements_are_named_with_impedaxs(text, hint):
    err = syntax_error(text)
    assert_caret(err, text, 5)
    assert err.hint == f"{hint}; in Python an EC-Lab string is passed as ix.from_ec_lab(...) (the command line reads it by itself)"


@pytest.mark.parametrize(
    "cdc, impedax_text",
    [
        ("R(RC)", "R1 + R2 || C1"),
        ("R(C[RW])", "R1 + C1 || (R2 + W1)"),  # bracket convention
        ("R(C(RW))", "R1 + C1 || (R2 + W1)"),  # classic convention: the same Randles circuit
    ],
)
def test_cli_info_reads_cdc_and_says_how(capsys, cdc, impedax_text):
    assert main(["info", cdc]) == 0
    captured = capsys.readouterr()
    assert f"impedax info: read as Boukamp's circuit description code (CDC): {impedax_text}\n" in captured.err
    assert f"model: {impedax_text}" in captured.out


def test_cli_fit_reads_cdc_without_the_impedance_py_weighting_note(tmp_path, capsys):
    data = rc_spectrum_csv(tmp_path)
    assert main(["fit", str(data), "--model", "R(RC)", "--json"]) == 0
    captured = capsys.readouterr()
    assert "read as Boukamp's circuit description code (CDC): R1 + R2 || C1" in captured.err
    assert "weight_by_modulus" not in captured.err  # that note is for impedance.py's users
    params = json.loads(captured.out)["params"]
    assert params["R1"]["value"] == pytest.approx(10, rel=0.05) and params["R2"]["value"] == pytest.approx(100, rel=0.05)
    assert params["C1"]["value"] == pytest.approx(1e-6, rel=0.05)


def test_cli_cdc_that_does_not_read_exits_2_with_the_cdc_readers_caret(capsys):
    assert main(["info", "R(RC"]) == 2
    err = capsys.readouterr().err
    assert "  R(RC\n" in err and "Traceback" not in err


# --- AutoEIS's and EC-Lab's notations on the command line --------------------------------------


@pytest.mark.parametrize(
    "model, note",
    [
        ("R1-[R2,P3]", "read as AutoEIS notation: R1 + R2 || CPE3"),
        ("R1-C2-[R3,P4]-[R5,[R6,C7]]", "read as AutoEIS notation: R1 + C2 + R3 || CPE4 + R5 || R6 || C7"),
        ("R1-P2", "read as AutoEIS notation: R1 + CPE2"),  # P is no impedance.py symbol
        ("R1+Q2/R2", "read with '/' as parallel (EC-Lab's notation): R1 + Q2 || R2"),
        ("C1/R1+C2/R2", "read with '/' as parallel (EC-Lab's notation): C1 || R1 + C2 || R2"),  # '/' binds closer than '+'
        ("C1/(R1+C2/R2)", "read with '/' as parallel (EC-Lab's notation): C1 || (R1 + C2 || R2)"),
        ("R0 + R1//C1", "read with '/' as parallel (EC-Lab's notation): R0 + R1 || C1"),
        ("R1+Q2/(R2+Wd2)", "read as EC-Lab notation (its Wd is impedax's Ws, with the same R and tau; '/' as parallel): R1 + Q2 || (R2 + Ws2)"),
        ("R1 + M2", "read as EC-Lab notation (its M is impedax's Wo, with the same R and tau): R1 + Wo2"),
        ("R1+Wd2+M3", "read as EC-Lab notation (its Wd is impedax's Ws and its M is impedax's Wo, with the same R and tau): R1 + Ws2 + Wo3"),
    ],
)
def test_cli_info_reads_autoeis_and_ec_lab_notation_and_says_how(capsys, model, note):
    assert main(["info", model]) == 0
    captured = capsys.readouterr()
    assert f"impedax info: {note}\n" in captured.err
    assert f"model: {note.rpartition(': ')[2]}" in captured.out


def test_autoeis_text_in_python_is_named_with_the_call_that_reads_it():
    err = syntax_error("R1-[R2,P3]")
    assert_caret(err, "R1-[R2,P3]", 2)
    assert err.hint == "series is written '+' and parallel '||'; in Python an AutoEIS string is passed as ix.from_autoeis('R1-[R2,P3]') (the command line reads it by itself)"
    for text in ("R0-p(R1,C1)", "R0 + R1 || C1", "R(C[RW])"):  # impedance.py, impedax, CDC
        assert not ix.circuits.looks_like_autoeis(text)


def test_cli_compare_reads_each_notation_and_notes_the_weighting_only_for_impedance_py(tmp_path, capsys):
    data = rc_spectrum_csv(tmp_path)
    assert main(["compare", str(data), "--model", "R1-[R2,C3]", "--model", "R(RQ)", "--json"]) == 0
    err = capsys.readouterr().err
    assert "read as AutoEIS notation: R1 + R2 || C3" in err and "read as Boukamp's circuit description code (CDC): R1 + R2 || CPE1" in err
    assert "weight_by_modulus" not in err


def test_a_users_element_p_is_impedax_text_not_an_autoeis_cpe(tmp_path, capsys):
    plugin = tmp_path / "mine.py"  # a user's element whose symbol is AutoEIS's CPE letter
    plugin.write_text(
        "import impedax as ix\n"
        "ELEMENTS = [ix.ElementSpec('P', 'my resistor', 'Z = R', (ix.ParameterSpec('R', 'Ohm', 1.0),), lambda w, r: r + 0 * w)]\n"
    )
    assert main(["--plugin", str(plugin), "info", "P1"]) == 0
    captured = capsys.readouterr()
    assert "AutoEIS" not in captured.err and "model: P1" in captured.out and "P1.R" in captured.out


def test_an_autoeis_string_with_a_dash_before_p_gets_no_impedance_py_weighting_note(tmp_path, capsys):
    data = rc_spectrum_csv(tmp_path)  # ('1-P' is also what marks impedance.py's series)
    assert main(["fit", str(data), "--model", "R1-P2", "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "read as AutoEIS notation: R1 + CPE2" in err and "weight_by_modulus" not in err


def test_cli_refuses_an_ec_lab_element_impedax_lacks_by_name(capsys):
    assert main(["info", "R1+Ma2/R2"]) == 2
    err = capsys.readouterr().err
    assert "EC-Lab's Ma (modified restricted diffusion) has no built-in impedax element at column 4\n  R1+Ma2/R2\n     ^" in err
    assert "Traceback" not in err


def test_cli_keeps_a_users_element_m_and_reads_no_ec_lab_notation(tmp_path, capsys):
    plugin = tmp_path / "mine.py"  # a user's element whose symbol is EC-Lab's restricted diffusion
    plugin.write_text(
        "import impedax as ix\n"
        "ELEMENTS = [ix.ElementSpec('M', 'my resistor', 'Z = R', (ix.ParameterSpec('R', 'Ohm', 1.0),), lambda w, r: r + 0 * w)]\n"
    )
    assert main(["--plugin", str(plugin), "info", "R1 + M2"]) == 0
    captured = capsys.readouterr()
    assert "EC-Lab" not in captured.err and "model: R1 + M2" in captured.out and "M2.R" in captured.out


@pytest.mark.parametrize(
    "text, hint",
    [
        ("R0 + CPEE1", "did you mean CPE1 (or CPE_E1, an element CPE with a label)?"),  # a letter doubled
        ("R0 + RR1", "did you mean R1 (or R_R1, an element R with a label)?"),
        ("R0 + Wss1", "did you mean Ws1 (or Ws_s1, an element Ws with a label)?"),
        ("R0 + CP1", "did you mean CPE1 (or C_P1, an element C with a label)?"),  # a letter dropped
        ("R0 + CPF1", "did you mean CPE1 (or C_PF1, an element C with a label)?"),  # one replaced
        ("R0 + Csc1", "did you mean C_sc1?"),  # a label, as before
        ("R0 + Rx1", "did you mean R_x1?"),  # (an x is no doubled R)
        ("R0 + Wx1", "did you mean W_x1?"),  # (Wo or Ws: two letters replaced by any)
    ],
)
def test_a_slip_of_the_keyboard_in_a_symbol_is_answered_with_the_symbol(text, hint):
    err = syntax_error(text)
    assert_caret(err, text, 5)
    assert err.hint.endswith("; else " + hint), err.hint


def test_a_lone_unknown_letter_gets_the_list_not_a_guess():
    assert syntax_error("R0 + X1").hint.endswith("known symbols: C, CC, CPE, G, HN, L, Q, R, W, Wo, Ws")
