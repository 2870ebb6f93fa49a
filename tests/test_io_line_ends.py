"""REAL instrument files with classic-Mac line ends (CR alone after every line, no LF): the
same lines as the file's own, each ended by CR. The oracle is the unchanged file: the CR-only
copy reads to the same frequencies, Z and metadata, and its errors name the line that a
count of CRs gives."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.errors import DataError

REAL = Path(__file__).parent / "fixtures" / "real"

#: every REAL file made of lines (the spreadsheets and numpy arrays are not text; data.pssession
#: is one line of JSON, without a line end)
TEXT_FILES = sorted(
    p.name for p in REAL.iterdir()
    if p.suffix not in (".md", ".json", ".py", ".npz", ".xlsx", ".ods", ".pssession") and not p.name.startswith("LICENSE")
)


def _cr_only(path: Path) -> bytes:
    """``path``'s bytes with each line end (CR CR LF as PowerSuite writes it, CR LF or LF) a CR alone."""
    lf = path.read_bytes().replace(b"\r\r\n", b"\n").replace(b"\r\n", b"\n")
    assert b"\r" not in lf and lf.count(b"\n") > 5  # (the real file's line ends were all of those kinds)
    return lf.replace(b"\n", b"\r")


def test_every_real_text_file_is_listed():
    assert {"exampleDataBioLogic.mpt", "data.idf", "data.ids", "exampleDataVersaStudio.par", "exampleDataPowersuite.txt"} <= set(TEXT_FILES)
    assert len(TEXT_FILES) == 13


@pytest.mark.parametrize("name", TEXT_FILES)
def test_cr_only_copy_reads_as_the_real_file(tmp_path, name):
    """Frequencies, Z (bit for bit) and every attribute but the file's name as the REAL file's."""
    copy = tmp_path / name
    copy.write_bytes(_cr_only(REAL / name))
    assert b"\n" not in copy.read_bytes()
    want, got = ix.load(REAL / name), ix.load(copy)
    assert np.array_equal(got["frequency"].values, want["frequency"].values)
    assert np.array_equal(got["Z"].values, want["Z"].values)
    differ = {k: (want.attrs.get(k), got.attrs.get(k)) for k in set(want.attrs) | set(got.attrs)
              if k not in ("source", "path") and str(want.attrs.get(k)) != str(got.attrs.get(k))}
    assert not differ


@pytest.mark.parametrize(("name", "row_start", "freq_name"),
                         [("exampleDataBioLogic.mpt", b"freq/Hz", b"freq/Hz"), ("exampleDataVersaStudio.par", b"Definition=", b"Frequency(Hz)")])
def test_cr_only_error_names_the_line_a_count_of_crs_gives(tmp_path, name, row_start, freq_name):
    """A frequency spoilt on the 3rd row under the column names of a CR-only copy: the error
    names that line, its number one more than the CRs before it."""
    lines = _cr_only(REAL / name).split(b"\r")
    header = next(k for k, line in enumerate(lines) if line.startswith(row_start))
    sep = b"\t" if b"\t" in lines[header] else b","
    column = [c.strip() for c in lines[header].removeprefix(b"Definition=").split(sep)].index(freq_name)
    row = header + 3
    cells = lines[row].split(sep)
    cells[column] = b"1.2.3"
    lines[row] = sep.join(cells)
    spoilt = b"\r".join(lines)
    copy = tmp_path / name
    copy.write_bytes(spoilt)
    with pytest.raises(DataError) as err:
        ix.load(copy)
    crs_before = spoilt[: spoilt.index(b"1.2.3")].count(b"\r")
    assert crs_before == row and err.value.line == crs_before + 1 and f"line {crs_before + 1}:" in str(err.value)


@pytest.mark.parametrize("name", ["exampleDataBioLogic.mpt", "data.idf", "exampleDataVersaStudio.par"])
def test_cli_inspect_reads_a_cr_only_copy(tmp_path, capsys, name):
    copy = tmp_path / name
    copy.write_bytes(_cr_only(REAL / name))
    assert main(["inspect", str(copy)]) == 0
    n = ix.load(REAL / name)["frequency"].size
    assert f"{n} frequencies" in capsys.readouterr().out
