"""Gamry's ``VDC  POTEN  -5.00000E-002  T`` holds the DC potential and, in its 4th field, whether it
is set against the open-circuit potential (T) or the reference electrode (F). The REAL
exampleDataGamry.DTA says T, and its own ZCURVE column Vdc (the DC potential measured against the
reference, at each point) shows it: about EOC + VDC = -0.2920 - 0.05 V, not -0.05 V. The oracle
is the file's bytes: its EOC line and its Vdc column."""

import statistics
from pathlib import Path

import pytest

import impedax as ix
from impedax.cli import main

GAMRY = Path(__file__).parent / "fixtures" / "real" / "exampleDataGamry.DTA"


def _file_facts() -> tuple[float, float, str, list[float]]:
    lines = GAMRY.read_bytes().decode("latin-1").splitlines()
    cells = {line.split("\t")[0]: line.split("\t") for line in lines if "\t" in line}
    start = next(k for k, line in enumerate(lines) if line.startswith("ZCURVE\t"))
    column = lines[start + 1].split("\t").index("Vdc")
    vdc = [float(line.split("\t")[column]) for line in lines[start + 3:] if line.startswith("\t")]
    return float(cells["VDC"][2]), float(cells["EOC"][2]), cells["VDC"][3], vdc


def test_the_dc_potential_says_what_it_is_set_against():
    vdc_set, eoc, flag, measured = _file_facts()
    assert flag == "T" and len(measured) == 72
    # the file's measured Vdc agrees with VDC against Eoc (within 2 mV), not against the reference (0.29 V off)
    assert abs(statistics.median(measured) - (eoc + vdc_set)) < 2e-3 and abs(statistics.median(measured) - vdc_set) > 0.2
    attrs = ix.load(GAMRY).attrs
    assert attrs["dc_voltage_v"] == vdc_set  # (as set: unchanged)
    assert attrs["dc_voltage_vs"] == "open circuit (Eoc)"
    assert attrs["ocp_v"] == eoc


@pytest.mark.parametrize(("flag", "said"), [("F", "reference electrode"), ("T", "open circuit (Eoc)")])
def test_either_flag_is_read(tmp_path, flag, said):
    raw = GAMRY.read_bytes().replace(b"VDC\tPOTEN\t-5.00000E-002\tT\t", b"VDC\tPOTEN\t-5.00000E-002\t" + flag.encode() + b"\t")
    path = tmp_path / "run.DTA"
    path.write_bytes(raw)
    assert ix.load(path).attrs["dc_voltage_vs"] == said


def test_inspect_prints_it(capsys):
    assert main(["inspect", str(GAMRY)]) == 0
    out = capsys.readouterr().out
    assert "  dc_voltage_vs: open circuit (Eoc)\n" in out and "  ocp_v: -0.2919803\n" in out
