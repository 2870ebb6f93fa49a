"""REAL instrument files cut right after the line their table starts under (a copy cut short, or
a measurement stopped before its first point): one refusal naming the file and that line, as
delimited text and Gamry's ZCURVE table name theirs. The oracle is the file's own lines."""

from pathlib import Path

import pytest

import impedax as ix
from impedax.cli import main
from impedax.errors import DataError

REAL = Path(__file__).parent / "fixtures" / "real"

# file, the start of the line the rows follow (the column names; ZPlot's 'End Comments')
CASES = [
    ("exampleDataBioLogic.mpt", "freq/Hz"),
    ("test_data.txt", "freq/Hz"),
    ("exampleDataZPlot.z", "End Comments"),
    ("exampleDataCHInstruments.txt", "Freq/Hz"),
    ("exampleDataParstat.txt", "Potential (V)"),
    ("exampleDataPowersuite.txt", "Frequency"),
    ("exampleDataAutolab.txt", '"  Freq (Hz)'),
]


def _header_only(name: str, start: str, tmp_path: Path, tail: bytes = b"") -> tuple[Path, int]:
    """The REAL file ``name`` up to the line end of its line that starts with ``start``, then
    ``tail``; and that line's number, 1-based, as the file's lines count (CR, LF, CR LF each end one)."""
    lines = (REAL / name).read_bytes().splitlines(keepends=True)
    k = next(i for i, line in enumerate(lines) if line.startswith(start.encode()))
    head = b"".join(lines[: k + 1])
    path = tmp_path / f"head_{name}"
    path.write_bytes(head + tail)
    return path, k + 1


@pytest.mark.parametrize(("name", "start"), CASES)
@pytest.mark.parametrize("tail", [b"", b"\r\n\r\n"], ids=["ends-after-header", "blank-lines-after"])
def test_a_table_with_no_rows_names_its_header_line(name, start, tail, tmp_path):
    path, line = _header_only(name, start, tmp_path, tail)
    with pytest.raises(DataError) as err:
        ix.load(path)
    assert str(err.value).startswith(f"{path}, line {line}: ") and "no data rows" in str(err.value)


def test_cli_header_only_mpt_exits_2_with_one_line(tmp_path, capsys):
    path, line = _header_only("exampleDataBioLogic.mpt", "freq/Hz", tmp_path)
    out = tmp_path / "out.csv"
    assert main(["inspect", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.strip() == f"impedax inspect: error: {path}, line {line}: header but no data rows" and not out.exists()
