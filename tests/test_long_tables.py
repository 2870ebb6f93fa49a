"""Long delimited tables are read a column at a time (`impedax.io.table._columns_at_once`, and
`impedax.io.csv._split_rows` splits the rows at once), where the table engine read each row in
Python (a SYNTHETIC 200,000-row table took 2–10 s; benchmarks/README.md, 2026-12-06). Every
behaviour stays: a bad cell deep in the table is named by its line and column, decimal commas
are decided from the whole table, a '.' beside them is refused naming both lines, rows that are
no points are skipped and reported. The oracles: the numbers written, read back by Python's
float, and the line numbers the file was built with; and the row-by-row loop itself (the fast
path switched off), which must give the same data or the same message on every case."""

import numpy as np
import pytest

import impedax as ix
from impedax.io import table

N = 5_000  # rows: long enough to be read at once, short enough for a quick test
# SYNTHETIC: R0 + R1 || C1, R0 = 10 Ω, R1 = 100 Ω, C1 = 10 µF, N points 1 MHz … 10 mHz
F = np.logspace(6, -2, N)
Z = 10 + 100 / (1 + 1j * 2 * np.pi * F * 1e-3)


def _rows(mark: str = ".") -> list[list[str]]:
    return [[f"{c:.10g}".replace(".", mark) for c in (f, z.real, -z.imag)] for f, z in zip(F, Z)]


def _write(path, header: str, rows, delimiter: str, *, above=(), end="\n") -> None:
    path.write_text("\n".join([*above, header, *(delimiter.join(r) for r in rows)]) + end, encoding="utf-8")


def _read(cells: list[list[str]]) -> np.ndarray:  # (the oracle: the text written, read by Python)
    return np.array([[float(c.replace(",", ".")) for c in r] for r in cells])


def test_a_long_table_reads_the_numbers_written(tmp_path):
    rows = _rows()
    path = tmp_path / "long.csv"
    _write(path, "Freq (Hz),Z' (Ohm),-Z'' (Ohm)", rows, ",")
    ds = ix.load(path)
    expected = _read(rows)
    np.testing.assert_array_equal(ds["frequency"].values, expected[:, 0])
    np.testing.assert_array_equal(ds["Z"].values, expected[:, 1] - 1j * expected[:, 2])


def test_decimal_commas_first_met_deep_in_a_long_table(tmp_path):
    # whole numbers for every row but the last 100, which hold decimal commas: the whole table decides
    # (frequencies N … 1 Hz in whole numbers throughout)
    rows = [[str(N - k), *(f"{round(x)}" if k < N - 100 else f"{x:.4f}".replace(".", ",") for x in (z.real * 1e3, -z.imag * 1e3))]
            for k, z in enumerate(Z)]
    assert not any("," in c for r in rows[: N - 100] for c in r) and "," in rows[N - 100][1]
    path = tmp_path / "late_comma.txt"
    _write(path, "Frequency (Hz);Z' (mOhm);-Z'' (mOhm)", rows, ";")
    ds = ix.load(path)
    assert ds.attrs["decimal_mark"] == "comma"
    expected = _read(rows) * [1, 1e-3, 1e-3]
    np.testing.assert_array_equal(ds["frequency"].values, expected[:, 0])
    np.testing.assert_array_equal(ds["Z"].values, expected[:, 1] - 1j * expected[:, 2])


def test_a_decimal_point_deep_below_decimal_commas_names_both_lines(tmp_path):
    rows = _rows(",")
    rows[3_700][2] = rows[3_700][2].replace(",", ".")
    path = tmp_path / "mixed.txt"
    _write(path, "Frequency (Hz);Z' (Ohm);-Z'' (Ohm)", rows, ";", above=["# exported by hand"])
    # line 1 the note, line 2 the header, row k on line k + 3
    with pytest.raises(ix.DataError, match=rf"mixed\.txt, line {3_700 + 3}: column \"-Z'' \(Ohm\)\": '[0-9.e+-]+' has a '\.', and other "
                                           rf"numbers of this file a ',' \(the first on line 3\)"):
        ix.load(path)


@pytest.mark.parametrize("cell, message", [
    ("abc", r"column \"Z' \(Ohm\)\": 'abc' is not a number"),
    ("", r"column \"Z' \(Ohm\)\" is empty \(missing value\)"),
    ("nan", r"column \"Z' \(Ohm\)\" is 'nan' \(NaN/Inf are not accepted\)"),
    ("1e999", r"column \"Z' \(Ohm\)\" is '1e999' \(NaN/Inf are not accepted\)"),
    ("1.5.2", r"column \"Z' \(Ohm\)\": '1\.5\.2' is not a number"),
])
def test_a_bad_cell_deep_in_a_long_table_names_its_line_and_column(tmp_path, cell, message):
    rows = _rows()
    rows[4_321][1] = cell
    path = tmp_path / "bad.csv"
    _write(path, "Freq (Hz),Z' (Ohm),-Z'' (Ohm)", rows, ",")
    with pytest.raises(ix.DataError, match=rf"bad\.csv, line {4_321 + 2}: {message}"):
        ix.load(path)


def test_a_field_too_many_deep_in_a_long_table_names_its_line(tmp_path):
    rows = _rows()
    rows[4_900].append("7")
    path = tmp_path / "extra.tsv"
    _write(path, "Freq (Hz)\tZ' (Ohm)\t-Z'' (Ohm)", rows, "\t")
    with pytest.raises(ix.DataError, match=rf"extra\.tsv, line {4_900 + 2}: 4 fields, but the header has 3"):
        ix.load(path)


def test_rows_that_are_no_points_deep_in_a_long_table_are_skipped_and_reported(tmp_path):
    rows = _rows()
    header = "Freq (Hz),Z' (Ohm),-Z'' (Ohm)"
    lines = [header, *(",".join(r) for r in rows[:3_000]), header, ",,", "# electrode re-seated", *(",".join(r) for r in rows[3_000:])]
    path = tmp_path / "skips.csv"
    path.write_text("\n".join(lines) + "\n")
    ds = ix.load(path)
    assert ds["frequency"].size == N
    assert sorted(ds.attrs["skipped_rows"]) == [f"line {3_002}: repeated header", f"line {3_003}: empty row (delimiters only)",
                                                f"line {3_004}: comment line ('# electrode re-seated')"]


def test_a_long_file_cut_in_its_last_cell_is_refused(tmp_path):
    rows = [[f"{c:.6E}" for c in (f, z.real, -z.imag)] for f, z in zip(F, Z)]
    rows[-1][2] = rows[-1][2][:5]  # (the copy stopped inside the last number)
    path = tmp_path / "cut.csv"
    _write(path, "Freq (Hz),Z' (Ohm),-Z'' (Ohm)", rows, ",", end="")
    with pytest.raises(ix.DataError, match=rf"cut\.csv, line {N + 1}: column \"-Z'' \(Ohm\)\": '{rows[-1][2]}' on the last row has fewer digits"):
        ix.load(path)


def test_a_time_column_of_a_long_table_is_read(tmp_path):
    rows = [[f"{0.25 * k:g}", *r] for k, r in enumerate(_rows())]
    path = tmp_path / "timed.txt"
    _write(path, "Time (s)\tFrequency (Hz)\t|Z| (Ohm)\tPhase (deg)", rows, "\t")
    ds = ix.load(path)
    np.testing.assert_array_equal(ds["time"].values, 0.25 * np.arange(N))


# the row-by-row loop as the oracle: every case read both ways gives the same data or the same message
_CASES = {
    "quoted": lambda r: [[f'"{c}"' for c in row] for row in r],
    "spaces": lambda r: [[f" {c} " for c in row] for row in r],
    "underscore": lambda r: [row if k != 400 else [row[0], "1_0", row[2]] for k, row in enumerate(r)],
    "inf": lambda r: [row if k != 400 else [row[0], "inf", row[2]] for k, row in enumerate(r)],
    "dc row": lambda r: [row if k != 400 else ["0", *row[1:]] for k, row in enumerate(r)],
    "negative frequency": lambda r: [row if k != 400 else ["-" + row[0], *row[1:]] for k, row in enumerate(r)],
    "repeated frequency": lambda r: [row if k != 400 else [r[399][0], *row[1:]] for k, row in enumerate(r)],
    "plus and exponent": lambda r: [[f"+{float(c.replace(',', '.')):.4E}".replace(".", "," if "," in "".join(row) else ".") for c in row] for row in r],
    "bare mark": lambda r: [row if k != 400 else [row[0], ".", row[2]] for k, row in enumerate(r)],
    "sign alone": lambda r: [row if k != 400 else [row[0], "-", row[2]] for k, row in enumerate(r)],
    "trailing delimiter": lambda r: [[*row, ""] for row in r],
    "trailing delimiter and a cell": lambda r: [[*row, "" if k != 400 else "x"] for k, row in enumerate(r)],
}


@pytest.mark.parametrize("case", sorted(_CASES))
@pytest.mark.parametrize("delimiter, mark", [(",", "."), (";", ","), ("\t", "."), (" ", ".")])
def test_read_at_once_as_row_by_row(tmp_path, monkeypatch, case, delimiter, mark):
    rows = _CASES[case]([r for r in _rows(mark)[:500]])
    path = tmp_path / "case.txt"
    _write(path, delimiter.join(["Freq/Hz", "Re(Z)/Ohm", "-Im(Z)/Ohm"]), rows, delimiter)

    def read():
        try:
            return ix.load(path)
        except ix.DataError as exc:
            return str(exc)

    fast = read()
    monkeypatch.setattr(table, "_columns_at_once", lambda *args: None, raising=False)  # (the loop alone)
    slow = read()
    if isinstance(slow, str):
        assert fast == slow
    else:
        assert not isinstance(fast, str), fast
        assert fast.identical(slow)


# EC-Lab's text export, split at once too (`RowBlock.split`): the numbers written, and a deep fault named as before
@pytest.mark.parametrize("mark", [".", ","])
def test_a_long_ec_lab_export_reads_the_numbers_written(tmp_path, mark):
    rows = _rows(mark)
    path = tmp_path / "eclab.txt"
    _write(path, "freq/Hz\tRe(Z)/Ohm\t-Im(Z)/Ohm", rows, "\t")
    ds = ix.load(path)
    assert ds.attrs["format"] == "BioLogic EC-Lab text" and ds.attrs.get("decimal_mark") == ("comma" if mark == "," else None)
    expected = _read(rows)
    np.testing.assert_array_equal(ds["frequency"].values, expected[:, 0])
    np.testing.assert_array_equal(ds["Z"].values, expected[:, 1] - 1j * expected[:, 2])


def test_a_short_row_deep_in_a_long_ec_lab_export_names_its_line(tmp_path):
    rows = _rows()
    rows[4_321] = rows[4_321][:2]
    path = tmp_path / "eclab.txt"
    _write(path, "freq/Hz\tRe(Z)/Ohm\t-Im(Z)/Ohm", rows, "\t")
    with pytest.raises(ix.DataError, match=rf"eclab\.txt, line {4_321 + 2}: 2 fields, but the header has 3"):
        ix.load(path)


@pytest.mark.parametrize("header", ["", "Freq (Hz),Z' (Ohm),-Z'' (Ohm)\n", "Frequency,Z',-Z''\nHz,Ohm,Ohm\n"], ids=["no header", "header", "units row"])
def test_a_comment_line_inside_a_table_is_reported(tmp_path, header):
    # (the look for comment lines is skipped when every line below the header is a row: not when one is a comment)
    path = tmp_path / "commented.csv"
    path.write_text(header + "1000,10,1\n100,12,3\n# electrode moved\n10,15,5\n1,20,2\n")
    line = header.count("\n") + 3
    assert ix.load(path).attrs["skipped_rows"] == [f"line {line}: comment line ('# electrode moved')"]


# quoted cells, unquoted at once when plain (`impedax.io.csv._unquoted_cells`): the oracle is
# `split_line`, which reads a row with the csv module
_QUOTED_ROWS = ['"1.5","2","3"', ' "1.5", "2" ,"3"  ', '"1,5";"2";"3"', '"a,b",2,3', '"a""b",2,3', 'a"b,2,3', '\t"1",2,3', '"1" x,2,3',
                '"",2,3', '"1",2,"', '"1.5"\t"2"\t"3"', "1,'2',3"]


@pytest.mark.parametrize("text", _QUOTED_ROWS)
@pytest.mark.parametrize("delimiter", [",", ";", "\t"])
def test_quoted_rows_split_at_once_as_row_by_row(text, delimiter):
    from impedax.io.csv import _split_rows, split_line

    rows = [(k + 2, text) for k in range(3)] + [(5, '"7","8","9"'.replace(",", delimiter))]
    assert [(n, list(cells)) for n, cells in _split_rows(rows, delimiter)] == [(n, split_line(t, delimiter)) for n, t in rows]


def test_a_long_quoted_table_is_read_at_once(tmp_path, monkeypatch):
    from impedax.io import csv as delimited

    rows = [[f'"{c}"' for c in r] for r in _rows()]
    path = tmp_path / "quoted.csv"
    _write(path, '"Freq (Hz)","Z\' (Ohm)","-Z\'\' (Ohm)"', rows, ",")
    calls = []
    split_line = delimited.split_line
    monkeypatch.setattr(delimited, "split_line", lambda *args: calls.append(args) or split_line(*args))
    expected = _read([[c.strip('"') for c in r] for r in rows])
    np.testing.assert_array_equal(ix.load(path)["Z"].values, expected[:, 1] - 1j * expected[:, 2])
    assert len(calls) < 25  # (the header, the row under it, the first 20 rows' look for decimal commas: not each of 5,000 rows)
