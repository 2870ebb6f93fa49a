"""A table below more than 100 lines of notes (a long instrument header) is read, as one below
fewer is (docs/io.md, `preamble`): until 2026-12-06 the header was looked for in the first 100
lines only, and the file was refused as "no frequency column in header ['note', '1:', 'value']"."""

import numpy as np
import pytest

import impedax as ix

# SYNTHETIC R0 + R1 || C1 (R0 = 10 Ω, R1 = 100 Ω, C1 = 1 µF) at 20 frequencies, below 150 lines of notes
F = np.logspace(5, -1, 20)
Z = 10 + 100 / (1 + 1j * 2 * np.pi * F * 1e-4)
NOTES = [f"setting {k}: value {k}" for k in range(1, 151)]


def test_a_csv_below_150_lines_of_notes(tmp_path):
    path = tmp_path / "long.csv"
    path.write_text("\n".join(NOTES + ["frequency,zreal,zimag"] + [f"{a!r},{b.real!r},{b.imag!r}" for a, b in zip(F.tolist(), Z.tolist())]) + "\n")
    ds = ix.load(path)
    np.testing.assert_array_equal(ds["frequency"].values, F)
    np.testing.assert_array_equal(ds["Z"].values, Z)
    assert ds.attrs["preamble"] == "lines 1–150: text above the table's header (line 151), not read: 'setting 1: value 1' …"


def test_a_sheet_below_150_rows_of_notes(tmp_path):
    pd = pytest.importorskip("pandas")
    pytest.importorskip("openpyxl")
    path = tmp_path / "long.xlsx"
    rows = [[note, None, None] for note in NOTES] + [["frequency", "zreal", "zimag"]] + [[a, b.real, b.imag] for a, b in zip(F.tolist(), Z.tolist())]
    pd.DataFrame(rows).to_excel(path, header=False, index=False)
    ds = ix.load(path)
    np.testing.assert_allclose(ds["Z"].values, Z, rtol=1e-14)  # (a workbook keeps 15 significant digits)
    assert ds.attrs["preamble"].startswith("rows 1–150: text above the table's header (row 151)")


def test_text_without_a_table_is_still_refused(tmp_path):
    path = tmp_path / "notes.txt"
    path.write_text("\n".join(NOTES + ["1.5 2,5 3", "no table here"]) + "\n")
    with pytest.raises(ix.DataError, match="no frequency column in header"):
        ix.load(path)
