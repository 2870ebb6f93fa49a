"""Errors in a spreadsheet name the sheet and the cell (``cell B10``), as its user finds it in
the spreadsheet program, not a "line". The workbooks are the REAL data.xlsx and data.ods with
one cell spoilt; the oracle is the spoilt cell's own coordinate (openpyxl's ``coordinate``,
or the row and column the cell was written to)."""

import subprocess
import sys
from pathlib import Path

import pytest

import impedax as ix
from impedax.cli import main
from impedax.errors import DataError

openpyxl = pytest.importorskip("openpyxl")
pd = pytest.importorskip("pandas")
pytest.importorskip("odf")

REAL = Path(__file__).parent / "fixtures" / "real"
SHEET = "header-variant-1"  # (f, Z', Z'' in columns A, B, C; the header on row 1, 29 points on rows 2–30)


def _spoilt_xlsx(tmp_path: Path, cells: dict) -> Path:
    wb = openpyxl.load_workbook(REAL / "data.xlsx")
    for coordinate, value in cells.items():
        wb[SHEET][coordinate] = value
    out = tmp_path / "spoilt.xlsx"
    wb.save(out)
    return out


def _spoilt_ods(tmp_path: Path, cells: dict) -> Path:
    """The REAL data.ods's sheets, as pandas reads them, written again with ``cells`` (A1 style) set."""
    sheets = pd.read_excel(REAL / "data.ods", sheet_name=None, header=None, dtype=object, engine="odf")
    for coordinate, value in cells.items():
        col, row = openpyxl.utils.cell.coordinate_from_string(coordinate)
        sheets[SHEET].iloc[row - 1, openpyxl.utils.cell.column_index_from_string(col) - 1] = value
    out = tmp_path / "spoilt.ods"
    with pd.ExcelWriter(out, engine="odf") as writer:
        for name, frame in sheets.items():
            frame.to_excel(writer, sheet_name=name, header=False, index=False)
    return out


SPOIL = {"xlsx": _spoilt_xlsx, "ods": _spoilt_ods}


@pytest.mark.parametrize("kind", SPOIL)
@pytest.mark.parametrize(
    ("cells", "where", "says"),
    [
        ({"B10": "abc"}, "cell B10", "column \"Z'\": 'abc' is not a number"),
        ({"C12": None}, "cell C12", "column \"Z''\" is empty (missing value)"),
        ({"B17": "inf"}, "cell B17", "column \"Z'\" is 'inf' (NaN/Inf are not accepted)"),
        ({"A15": -5}, "cell A15", "frequency must be positive, got -5"),
    ],
)
def test_a_bad_cell_is_named_by_sheet_and_cell(tmp_path, kind, cells, where, says):
    path = SPOIL[kind](tmp_path, cells)
    with pytest.raises(DataError) as err:
        ix.load(path)
    text = str(err.value)
    assert text.startswith(f"{path} [sheet {SHEET}], {where}: {says}"), text
    assert "line" not in text
    assert err.value.line == int(where[len("cell ") + 1:])  # (the row, for a program that reads it)


@pytest.mark.parametrize("kind", SPOIL)
def test_a_duplicate_frequency_names_both_cells(tmp_path, kind):
    """A16 set to A15's frequency (138.95 Hz in the REAL file): both cells are named, and the
    remedy speaks of rows."""
    a15 = openpyxl.load_workbook(REAL / "data.xlsx")[SHEET]["A15"].value
    path = SPOIL[kind](tmp_path, {"A16": a15})
    with pytest.raises(DataError) as err:
        ix.load(path)
    text = str(err.value)
    assert f"[sheet {SHEET}], cell A16: duplicate frequency {a15:g} Hz (also in cell A15)" in text, text
    assert "delete one of the two rows" in text and "line" not in text


def test_a_table_placed_away_from_a1_is_named_by_its_own_cells(tmp_path):
    """The REAL sheet copied to start at C5 (rows and columns left empty before it): a bad Z' is
    named at the cell it was written to, D14 (the REAL B10, moved by 2 columns and 4 rows)."""
    source = openpyxl.load_workbook(REAL / "data.xlsx")[SHEET]
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "moved"
    for r, row in enumerate(source.iter_rows(values_only=True)):
        for c, value in enumerate(row):
            ws.cell(row=r + 5, column=c + 3, value=value)
    target = ws.cell(row=10 + 4, column=2 + 2)
    target.value = "abc"
    path = tmp_path / "moved.xlsx"
    wb.save(path)
    with pytest.raises(DataError) as err:
        ix.load(path)
    assert target.coordinate == "D14"
    assert f"[sheet moved], cell {target.coordinate}: column \"Z'\": 'abc' is not a number" in str(err.value)


def test_an_error_on_another_sheet_names_that_sheet(tmp_path):
    wb = openpyxl.load_workbook(REAL / "data.xlsx")
    wb["header-variant-3"]["B7"] = "x1"
    path = tmp_path / "third.xlsx"
    wb.save(path)
    with pytest.raises(DataError, match=r"\[sheet header-variant-3\], cell B7: column 'real': 'x1' is not a number"):
        ix.load(path)


def test_cli_names_the_cell_with_exit_code_2(tmp_path, capsys):
    path = _spoilt_xlsx(tmp_path, {"B10": "abc"})
    assert main(["inspect", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"[sheet {SHEET}], cell B10: column \"Z'\"" in err and "line" not in err and "Traceback" not in err


def test_stdin_names_the_cell_once(tmp_path):
    """A spreadsheet piped in: '<stdin> [sheet S], cell B10: …', the place said once."""
    path = _spoilt_xlsx(tmp_path, {"B10": "abc"})
    with open(path, "rb") as stdin:
        run = subprocess.run([sys.executable, "-m", "impedax", "inspect", "-"], stdin=stdin, capture_output=True, text=True)
    assert run.returncode == 2
    assert f"error: <stdin> [sheet {SHEET}], cell B10: column \"Z'\": 'abc' is not a number" in run.stderr, run.stderr
    assert run.stderr.count("<stdin>") == 1 and "line" not in run.stderr


def test_skipped_rows_and_sweeps_of_a_sheet_are_rows(tmp_path, capsys):
    """A DC row (f = 0) inserted as row 2 of the REAL sheet: skipped, reported as 'row 2', as
    inspect prints it; a sheet of two sweeps of one grid (the REAL rows twice) says where the
    second starts as a row."""
    wb = openpyxl.load_workbook(REAL / "data.xlsx")
    ws = wb[SHEET]
    for other in [s for s in wb.worksheets if s.title != SHEET]:
        wb.remove(other)
    ws.insert_rows(2)
    ws["A2"], ws["B2"], ws["C2"] = 0, 5.0, 0.0
    path = tmp_path / "dc.xlsx"
    wb.save(path)
    assert ix.load(path).attrs["skipped_rows"] == ["row 2: f = 0 (DC row, not an impedance point)"]
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert "    row 2: f = 0 (DC row, not an impedance point)" in out and "line 2" not in out
    ws.delete_rows(2)
    rows = [[c.value for c in row] for row in ws.iter_rows(min_row=2)]
    for row in rows:
        ws.append(row)
    wb.save(path)
    sweeps = ix.load(path).attrs["sweeps"]
    assert f"restarts on row {2 + len(rows)}" in sweeps and "line" not in sweeps, sweeps


def test_stdin_sheet_of_sweeps_on_two_grids_is_said_once_and_keeps_its_sweeps(tmp_path):
    """The REAL sheet, then its rows again with each frequency ×1.01 (a second sweep on another
    grid), piped in: the refusal names '<stdin> [sheet S], row 31' once, and load(sweep=...) of
    standard input is still offered (a SweepGridsDiffer carrying both sweeps)."""
    wb = openpyxl.load_workbook(REAL / "data.xlsx")
    ws = wb[SHEET]
    for other in [s for s in wb.worksheets if s.title != SHEET]:
        wb.remove(other)
    rows = [[c.value for c in row] for row in ws.iter_rows(min_row=2)]
    for f, re_, im in rows:
        ws.append([f * 1.01, re_, im])
    path = tmp_path / "two.xlsx"
    wb.save(path)
    with open(path, "rb") as stdin:
        run = subprocess.run([sys.executable, "-m", "impedax", "inspect", "-"], stdin=stdin, capture_output=True, text=True)
    assert run.returncode == 2
    assert f"error: <stdin> [sheet {SHEET}], row {2 + len(rows)}: the table holds 2 sweeps on different frequency grids" in run.stderr, run.stderr
    assert run.stderr.count("<stdin>") == 1 and "line" not in run.stderr
    with open(path, "rb") as stdin:
        run = subprocess.run([sys.executable, "-m", "impedax", "inspect", "-", "--select", "sweep=1", "--json"], stdin=stdin, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert '"points": 29' in run.stdout
