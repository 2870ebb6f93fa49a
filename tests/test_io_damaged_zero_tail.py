"""A text file whose tail is zero bytes, as a copy or save that was interrupted leaves it (the
file has its full size, its last blocks never written): refused naming the line where the
zeros start, never read as the points before them, nor called 'a binary file'. The oracle is
the REAL files' own bytes."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.errors import DataError

REAL = Path(__file__).parent / "fixtures" / "real"


def _zero_tail(name: str, keep: float, tmp_path: Path) -> tuple[Path, int, int]:
    """The REAL file with all bytes from ``keep`` of its length on set to zero; the path, the
    first zero byte's offset and its line (1-based; CR, LF and CR LF each end a line)."""
    raw = (REAL / name).read_bytes()
    k = int(len(raw) * keep)
    path = tmp_path / f"zeroed_{name}"
    path.write_bytes(raw[:k] + b"\x00" * (len(raw) - k))
    return path, k, len(raw[:k].splitlines()) + (1 if raw[:k].endswith((b"\n", b"\r")) else 0)


@pytest.mark.parametrize(("name", "keep"), [
    ("exampleDataParstat.txt", 0.95),  # (read as 15 of its 31 points: the zeros began at a field's end)
    ("exampleData.csv", 0.7),  # (called 'a binary file that no reader claims')
    ("exampleDataPowersuite.txt", 0.95),
    ("exampleDataGamry.DTA", 0.95),
])
def test_zero_filled_tail_is_refused_naming_where_it_starts(name, keep, tmp_path):
    path, offset, line = _zero_tail(name, keep, tmp_path)
    zeros = path.stat().st_size - offset
    with pytest.raises(DataError) as err:
        ix.load(path)
    text = str(err.value)
    assert text.startswith(f"{path}, line {line}: ")
    assert f"the file's last {zeros} bytes (from byte {offset} on) are zero bytes" in text and "copy it again" in text
    assert "binary" not in text


def test_a_file_of_zero_bytes_only_says_so(tmp_path):
    path = tmp_path / "run.csv"
    path.write_bytes(b"\x00" * 4096)
    with pytest.raises(DataError) as err:
        ix.load(path)
    assert str(err.value).startswith(f"{path}: the file holds only zero bytes (4096)")


def test_utf16_text_ending_in_a_zero_byte_is_read(tmp_path):
    """UTF-16-LE text ends in the zero byte of its last line end: not a zeroed tail."""
    path = tmp_path / "utf16.csv"
    text = (REAL / "exampleData.csv").read_text()
    path.write_bytes(text.encode("utf-16-le"))
    assert path.read_bytes().endswith(b"\n\x00")
    np.testing.assert_array_equal(ix.load(path)["Z"].values, ix.load(REAL / "exampleData.csv")["Z"].values)


def test_cli_zero_tail_exit_2_one_line(tmp_path, capsys):
    path, offset, line = _zero_tail("exampleDataParstat.txt", 0.95, tmp_path)
    out = tmp_path / "out.csv"
    assert main(["fit", str(path), "--model", "R0 + R1 || CPE1", "--out", str(out), "-q"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"impedax fit: error: {path}, line {line}: ") and not out.exists()


def test_zero_tail_on_standard_input_names_stdin():
    """Piped in, the same file is named <stdin> with the line, not by the temporary file that
    holds it while read."""
    import subprocess
    import sys

    raw = (REAL / "exampleData.csv").read_bytes()
    k = int(len(raw) * 0.7)
    run = subprocess.run([sys.executable, "-m", "impedax", "inspect", "-"], input=raw[:k] + b"\x00" * (len(raw) - k), capture_output=True, timeout=300)
    line = len(raw[:k].splitlines()) + (1 if raw[:k].endswith(b"\n") else 0)
    err = run.stderr.decode()
    assert run.returncode == 2 and err.startswith(f"impedax inspect: error: <stdin>, line {line}: the file's last ") and "impedax-stdin" not in err


@pytest.mark.parametrize("name", ["exampleData.csv", "exampleDataBioLogic.mpt"])
def test_a_block_of_zero_bytes_inside_the_text_is_refused_naming_its_line(name, tmp_path):
    """512 bytes zeroed in the middle of the REAL file (a damaged block): named with its line and
    offset, not 'a binary file that no reader claims' (exampleData.csv) nor a field count
    (exampleDataBioLogic.mpt's row with the zeros in it)."""
    raw = bytearray((REAL / name).read_bytes())
    at = len(raw) // 2
    raw[at:at + 512] = b"\x00" * 512
    path = tmp_path / name
    path.write_bytes(bytes(raw))
    line = len(bytes(raw[:at]).splitlines()) + (1 if bytes(raw[:at]).endswith((b"\n", b"\r")) else 0)
    with pytest.raises(DataError) as err:
        ix.load(path)
    assert str(err.value).startswith(f"{path}, line {line}: 512 zero bytes (from byte {at} on) inside the text")
    assert "copy it again" in str(err.value)


def test_a_stray_zero_byte_is_left_to_the_readers(tmp_path):
    """One zero byte in text (a string terminator some programs leave, or a stray byte) is no
    block never written: the readers judge the file (here delimited text, whose last row, the
    zero byte alone without a line end, is short of fields)."""
    path = tmp_path / "terminated.csv"
    path.write_bytes((REAL / "exampleData.csv").read_bytes() + b"\x00")
    with pytest.raises(DataError) as err:
        ix.load(path)
    assert "zero bytes" not in str(err.value) and "line 67: the last row has 1 field," in str(err.value)
