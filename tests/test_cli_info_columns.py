"""``impedax info``'s table: each column as wide as its widest entry, so a circuit of resistors
and capacitors reads within 80 columns (fixed widths put "R_sc  Ω" then 17 blanks and Meyer's
rows at 108 characters, walkthrough 2026-12-07), and the paper models' "default:" line wrapped."""

import pytest

from impedax.cli import main


def info_lines(capsys, model):
    assert main(["info", model]) == 0
    return capsys.readouterr().out.splitlines()


def test_an_rc_circuit_reads_in_its_columns(capsys):
    lines = info_lines(capsys, "R0 + C_long")
    # written out by hand: name column 9 ("parameter"), unit 4, default 7, bounds 8, two blanks between
    assert lines[1:4] == [
        "parameter  unit  default  bounds    description",
        "R0         Ω         100  (0, inf)  resistor: resistance",
        "C_long     F       1e-06  (0, inf)  capacitor: capacitance",
    ]


@pytest.mark.parametrize("model", ["meyer", "R0 + R1 || C1"])
def test_rows_of_resistors_and_capacitors_fit_80_columns(capsys, model):
    lines = info_lines(capsys, model)
    assert lines and all(len(line) <= 80 for line in lines), [line for line in lines if len(line) > 80]


def test_a_paper_models_default_line_is_wrapped_not_cut(capsys):
    lines = info_lines(capsys, "meyer")
    start = next(i for i, line in enumerate(lines) if line.startswith("default: "))
    end = next(i for i, line in enumerate(lines) if line.startswith("parameter "))
    paragraph = " ".join(line.strip() for line in lines[start:end])
    assert end - start >= 2 and all(len(line) <= 80 for line in lines[start:end])
    assert paragraph.endswith("(source in [ ]; the elements' own defaults are --json's \"default\")")
