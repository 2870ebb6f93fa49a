"""Decimal commas in an instrument's table (EC-Lab .mpt, NOVA text: `impedax.io.table.spectrum_from_rows`)
are decided from every row, as delimited text decides them (docs/io.md, `decimal_mark`). Until
2026-12-06 the table engine looked at the first 20 rows only: whole numbers there and "109,607"
below made the file refused as "'109,607' is not a number"."""

import numpy as np
import pytest

import impedax as ix

# SYNTHETIC: R0 + R1 || C1, R0 = 10 Ω, R1 = 100 Ω, C1 = 1 µF (τ = 1e-4 s), 31 points 100 kHz … 100 mHz
F = np.logspace(5, -1, 31)
Z = 10 + 100 / (1 + 1j * 2 * np.pi * F * 1e-4)


def _cell(x: float, row: int) -> str:
    """The first 20 rows in whole numbers (a coarse export), later ones with decimal commas."""
    return f"{round(x)}" if row < 20 else f"{x:.6g}".replace(".", ",")


def _value(cell: str) -> float:  # (the oracle: the text written, read by Python)
    return float(cell.replace(",", "."))


def _mpt(rows) -> str:
    header = ["EC-Lab ASCII FILE", "Nb header lines : 5", "", "Potentio Electrochemical Impedance Spectroscopy",
              "freq/Hz\tRe(Z)/Ohm\t-Im(Z)/Ohm\tcycle number"]
    return "\n".join(header + ["\t".join([*r, "1"]) for r in rows]) + "\n"


def _nova(rows) -> str:
    header = ["Index;Frequency (Hz);Z' (Ω);-Z'' (Ω);Z (Ω);Time (s)"]
    return "\n".join(header + [";".join([str(k + 1), *r, "1", str(k)]) for k, r in enumerate(rows)]) + "\n"


@pytest.mark.parametrize("name, write, fmt", [("late.mpt", _mpt, "BioLogic EC-Lab mpt"), ("late.txt", _nova, "Metrohm Autolab NOVA text")])
def test_a_decimal_comma_first_met_below_row_20(tmp_path, name, write, fmt):
    rows = [[_cell(f, k), _cell(z.real, k), _cell(-z.imag, k)] for k, (f, z) in enumerate(zip(F, Z))]
    assert not any("," in c for r in rows[:20] for c in r) and "," in rows[20][1]
    path = tmp_path / name
    path.write_text(write(rows), encoding="utf-8")
    ds = ix.load(path)
    assert ds.attrs["format"] == fmt and ds.attrs["decimal_mark"] == "comma"
    table = np.array([[_value(c) for c in r] for r in rows])
    np.testing.assert_array_equal(ds["frequency"].values, table[:, 0])
    np.testing.assert_array_equal(ds["Z"].values, table[:, 1] - 1j * table[:, 2])


def test_decimal_points_above_decimal_commas_are_refused_naming_both_lines(tmp_path):
    # SYNTHETIC: the first 20 rows with decimal points, the rest with decimal commas (two locales in one
    # file): refused at the first point's line, saying where the first comma is
    rows = [[(f"{x:.6g}" if k < 20 else f"{x:.6g}".replace(".", ",")) for x in (f, z.real, -z.imag)] for k, (f, z) in enumerate(zip(F, Z))]
    path = tmp_path / "mixed.mpt"
    path.write_text(_mpt(rows))
    first_dot = next(6 + k for k, r in enumerate(rows) if any("." in c for c in r))
    with pytest.raises(ix.DataError, match=rf"mixed\.mpt, line {first_dot}: column '[^']+': '[^']+' has a '\.', and other numbers of this "
                                           rf"file a ',' \(the first on line {6 + 20}\)"):
        ix.load(path)
