"""REAL instrument files cut short while copying, at places the field count cannot show: the
last row ends on a delimiter (its last field missing), or a PowerSuite row is cut inside its
last number. The oracle is the file's own bytes: where the cut falls, and the row it cut."""

from pathlib import Path

import pytest

import impedax as ix
from impedax.cli import main
from impedax.errors import DataError

REAL = Path(__file__).parent / "fixtures" / "real"


def _cut_after_delimiter(raw: bytes, line_index: int, delimiter: bytes) -> bytes:
    """``raw`` up to and including the last ``delimiter`` of its line ``line_index`` (0-based)
    before that line's last value: the line's last field is missing, the delimiter before it kept."""
    lines = raw.splitlines(keepends=True)
    row = lines[line_index].rstrip(b"\r\n").rstrip(delimiter)
    kept = row[: row.rindex(delimiter) + len(delimiter)]
    return b"".join(lines[:line_index]) + kept


def test_biologic_mpt_cut_after_a_tab_of_its_last_row_is_refused(tmp_path):
    """The REAL exampleDataBioLogic.mpt ends every row with a tab; cut after the tab before the
    row's last value (Phase(Y)/deg), the last row keeps the header's field count with an empty
    last cell. Refused naming that line and column, as a file cut short."""
    raw = (REAL / "exampleDataBioLogic.mpt").read_bytes()
    lines = raw.splitlines(keepends=True)
    header = next(k for k, line in enumerate(lines) if line.startswith(b"freq/Hz"))
    row = header + 5  # (the 5th data row, 0-based line index)
    cut = tmp_path / "cut.mpt"
    cut.write_bytes(_cut_after_delimiter(raw, row, b"\t"))
    with pytest.raises(DataError) as err:
        ix.load(cut)
    text = str(err.value)
    assert f"line {row + 1}:" in text and "'Phase(Y)/deg'" in text and "empty on the last row" in text
    assert "the file ends without a line end" in text
    assert cut.read_bytes().endswith(b"\t")  # (the cut the test means: right after a delimiter)


def test_ch_instruments_cut_after_a_comma_of_its_last_row_is_refused(tmp_path):
    """The REAL exampleDataCHInstruments.txt (', ' between cells, no trailing one) cut after the
    ', ' before its 5th data row's Phase/deg: refused naming the line and 'Phase/deg'. The same
    rows with a line end after the cut are read: 5 points, the cut row's Z as the file holds it."""
    raw = (REAL / "exampleDataCHInstruments.txt").read_bytes()
    lines = raw.splitlines(keepends=True)
    header = next(k for k, line in enumerate(lines) if line.startswith(b"Freq/Hz"))
    row = header + 6  # (a blank line under the header, then the rows: this is the 5th)
    cut_bytes = _cut_after_delimiter(raw, row, b",")
    assert cut_bytes.endswith(b",") and lines[row].count(b",") == 4
    cut = tmp_path / "cut.txt"
    cut.write_bytes(cut_bytes)
    with pytest.raises(DataError) as err:
        ix.load(cut)
    assert f"line {row + 1}:" in str(err.value) and "'Phase/deg'" in str(err.value) and "ends without a line end" in str(err.value)
    # the same bytes with a line end: the empty phase cell is another column's gap, read as written
    ended = tmp_path / "ended.txt"
    ended.write_bytes(cut_bytes + b"\n")
    data = ix.load(ended)
    cells = [float(c) for c in lines[row].split(b",")[:3]]
    assert data.sizes["frequency"] == 5
    assert (data["frequency"].values[-1], data["Z"].values[-1]) == (cells[0], complex(cells[1], cells[2]))


def test_an_empty_last_cell_as_on_other_rows_is_no_cut(tmp_path):
    """A column empty on other rows too (a notes column) does not show a cut: a file whose last
    row leaves it empty, without a final line end, is read as written."""
    path = tmp_path / "notes.csv"
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm,note\n1000,10,-1,\n100,11,-2,drift\n10,12,-3,\n1,13,-4,")
    data = ix.load(path)
    assert data.sizes["frequency"] == 4 and data["Z"].values[-1] == 13 - 4j


def test_powersuite_cut_inside_its_last_number_is_refused(tmp_path):
    """PowerSuite writes its numbers in their shortest form ('-30050.48', '-1397.7358'), so a
    Zimg cut inside (``-30050.4``) has as many digits as other rows; but it ends every row with
    CR CR LF, the last included, which no editor writes: a file whose rows end so and whose
    last row ends without a line end is cut. The REAL exampleDataPowersuite.txt cut before the
    last digit of '-30050.48' is refused naming that line (its lines counted as the reader
    counts them, CR and CR LF each a line end); the rows above it, with their CR CR LF, are read."""
    raw = (REAL / "exampleDataPowersuite.txt").read_bytes()
    assert raw.endswith(b"\r\r\n") and raw.count(b"-30050.48\r\r\n") == 1
    at = raw.index(b"-30050.48\r\r\n") + len(b"-30050.4")
    cut = tmp_path / "cut.txt"
    cut.write_bytes(raw[:at])
    with pytest.raises(DataError) as err:
        ix.load(cut)
    text = str(err.value)
    line = len(raw[:at].decode().splitlines())
    assert f"line {line}:" in text and "ends without a line end" in text and "CR CR LF" in text
    whole = tmp_path / "whole.txt"
    whole.write_bytes(raw[: raw.rindex(b"\r\r\n", 0, at) + 3])
    rows = whole.read_bytes().count(b"\r\r\n") - 1
    assert rows >= 3 and ix.load(whole).sizes["frequency"] == rows


def test_powersuite_rows_an_editor_rewrote_are_read_without_a_final_line_end(tmp_path):
    """The same REAL file with its line ends rewritten to LF (an editor's save) and no line end
    after its last row: nothing shows a cut, and all 30 points are read as written."""
    raw = (REAL / "exampleDataPowersuite.txt").read_bytes()
    path = tmp_path / "edited.txt"
    path.write_bytes(raw.replace(b"\r\r\n", b"\n").rstrip(b"\n"))
    assert ix.load(path).sizes["frequency"] == ix.load(REAL / "exampleDataPowersuite.txt").sizes["frequency"] == 30


@pytest.mark.parametrize("command", [["inspect"], ["fit", "--model", "R0 + R1 || CPE1"]])
def test_cli_refuses_a_cut_file_with_one_message_and_writes_nothing(tmp_path, capsys, command):
    """`impedax inspect` and `impedax fit` on the cut .mpt: exit 2, one error line naming file and
    line on stderr, no traceback, and an existing --out target left as it was."""
    raw = (REAL / "exampleDataBioLogic.mpt").read_bytes()
    lines = raw.splitlines(keepends=True)
    row = next(k for k, line in enumerate(lines) if line.startswith(b"freq/Hz")) + 5
    cut = tmp_path / "cut.mpt"
    cut.write_bytes(_cut_after_delimiter(raw, row, b"\t"))
    out = tmp_path / "out.csv"
    out.write_text("kept\n")
    assert main([command[0], str(cut), *command[1:], "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and "Traceback" not in err and f"{cut}, line {row + 1}:" in err
    assert out.read_text() == "kept\n"


def test_a_last_row_of_one_cell_says_1_field(tmp_path):
    """The REAL exampleData.csv cut after the first character of a row: 'the last row has 1
    field', not '1 fields'."""
    raw = (REAL / "exampleData.csv").read_bytes()
    path = tmp_path / "cut.csv"
    path.write_bytes(raw + b"3")
    with pytest.raises(DataError) as err:
        ix.load(path)
    assert "line 67: the last row has 1 field, but" in str(err.value)
