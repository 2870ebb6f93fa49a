"""Damaged copies of REAL files, as a lab meets them, through `impedax inspect` and `impedax fit`:
each refused with one error line naming the file (and line and column where one is at fault),
exit code 2, no traceback and an existing --out target left as it was; or, where the data
are sound (CRLF, trailing blank lines, UTF-16, decimal commas, kHz), read as the original.
The oracles are the REAL files' own bytes and values."""

import os
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

REAL = Path(__file__).parent / "fixtures" / "real"
CSV = REAL / "exampleData.csv"  # (no header: f, Z', Z'')
HEADER = "frequency_hz,z_real_ohm,z_imag_ohm"


def _rows() -> list[list[str]]:
    return [line.split(",") for line in CSV.read_text().splitlines()]


def _table(rows, header=HEADER, sep=",") -> str:
    return header + "\n" + "\n".join(sep.join(row) for row in rows) + "\n"


def _damaged(kind: str, folder: Path) -> tuple[Path, str]:
    """A damaged copy and the text its one error line must hold after the file's name."""
    rows = _rows()
    if kind == "truncated mid-row":
        text = _table(rows)
        cut = text.index("\n".join(",".join(r) for r in rows[30:])) + len(",".join(rows[30])) // 2
        return _write(folder / "cut.csv", text[:cut]), ", line 32: the last row has 2 fields, but the header has 3; the file ends without a line end"
    if kind == "empty":
        return _write(folder / "empty.csv", ""), ": file is empty"
    if kind == "header only":
        return _write(folder / "header.csv", HEADER + "\n"), ", line 1: header but no data rows"
    if kind == "text in row 37":
        rows[36][1] = "n/a"
        return _write(folder / "text.csv", _table(rows)), ", line 38: column 'z_real_ohm': 'n/a' is not a number"
    if kind == "duplicated frequency row":
        rows.insert(21, rows[20])
        return _write(folder / "dup.csv", _table(rows)), f", line 23: duplicate frequency {float(rows[20][0]):g} Hz (also on line 22)"
    if kind == "NaN in Z":
        rows[10][2] = "NaN"
        return _write(folder / "nan.csv", _table(rows)), ", line 12: column 'z_imag_ohm' is 'NaN'"
    if kind == "a directory":
        (folder / "runs").mkdir()
        return folder / "runs", ": is a directory, not a spectrum file"
    raise AssertionError(kind)


def _write(path: Path, text: str) -> Path:
    path.write_bytes(text.encode())
    return path


KINDS = ["truncated mid-row", "empty", "header only", "text in row 37", "duplicated frequency row", "NaN in Z", "a directory"]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("command", [["inspect"], ["fit", "--model", "R0 + R1 || CPE1"]], ids=["inspect", "fit"])
def test_damaged_file_one_message_exit_2_nothing_written(kind, command, tmp_path, capsys):
    path, expected = _damaged(kind, tmp_path)
    out = tmp_path / "out.csv"
    out.write_text("kept\n")
    assert main([command[0], str(path), *command[1:], "--out", str(out), "-q"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"impedax {command[0]}: error: {path}{expected}")
    assert out.read_text() == "kept\n"


def test_unreadable_file_one_message_exit_2(tmp_path, capsys, monkeypatch):
    """A file without read permission (as root, whom permissions do not stop, os.access answers
    as for a user)."""
    path = _write(tmp_path / "locked.csv", _table(_rows()))
    path.chmod(0)
    real_access = os.access
    monkeypatch.setattr(os, "access", lambda p, mode, *a, **k: False if Path(p) == path and mode & os.R_OK else real_access(p, mode, *a, **k))
    try:
        assert main(["inspect", str(path), "-q"]) == 2
    finally:
        path.chmod(0o644)
    assert capsys.readouterr().err == f"impedax inspect: error: {path}: cannot read file: permission denied\n"


def _sound(kind: str, folder: Path) -> Path:
    rows = _rows()
    if kind == "CRLF":
        return _write(folder / "crlf.csv", _table(rows).replace("\n", "\r\n"))
    if kind == "trailing blank lines":
        return _write(folder / "blank.csv", _table(rows) + "\n\n  \n\r\n")
    if kind == "UTF-16":
        path = folder / "utf16.csv"
        path.write_bytes(_table(rows).encode("utf-16"))
        return path
    if kind == "semicolons":
        return _write(folder / "semi.csv", _table(rows, HEADER.replace(",", ";"), ";"))
    if kind == "decimal commas":
        return _write(folder / "de.csv", _table([[c.replace(".", ",") for c in r] for r in rows], HEADER.replace(",", ";"), ";"))
    if kind == "kHz":
        khz = [[repr(float(r[0]) / 1000), r[1], r[2]] for r in rows]
        return _write(folder / "khz.csv", _table(khz, "Frequency (kHz),Z' (Ohm),Z'' (Ohm)"))
    if kind == "Gamry DTA named .txt":
        path = folder / "gamry.txt"
        path.write_bytes((REAL / "exampleDataGamry.DTA").read_bytes())
        return path
    raise AssertionError(kind)


@pytest.mark.parametrize("kind", ["CRLF", "trailing blank lines", "UTF-16", "semicolons", "decimal commas", "kHz", "Gamry DTA named .txt"])
def test_sound_variants_read_as_the_original(kind, tmp_path, capsys):
    path = _sound(kind, tmp_path)
    original = ix.load(REAL / "exampleDataGamry.DTA") if kind.startswith("Gamry") else ix.load(CSV)
    data = ix.load(path)
    if kind == "kHz":  # (f/1000 written in its shortest form, then ×1000: within an ulp of the original)
        np.testing.assert_allclose(data["frequency"].values, original["frequency"].values, rtol=4e-16, atol=0)
    else:
        np.testing.assert_array_equal(data["frequency"].values, original["frequency"].values)
    np.testing.assert_array_equal(data["Z"].values, original["Z"].values)
    assert main(["inspect", str(path), "-q"]) == 0
    assert capsys.readouterr().err == ""
