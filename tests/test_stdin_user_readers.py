"""Standard input and the user's readers (docs/io.md, "How a file is recognised"): a reader that
goes by the file's extension never claims ``-``; when none of the user's readers claims it, the
data's attrs and every command's stderr say which reader read it and why the user's did not."""

import io
import json
import sys

import numpy as np
import pytest

import impedax as ix
from impedax.io import Reader, register_reader

from cli_run import run

# SYNTHETIC: R0 + R1 || C1 in kHz and kΩ (the lab format's units), R0 = 0.1 kΩ, R1 = 2 kΩ, C1 = 1 µF
F_KHZ = np.logspace(-1, -5, 15)
W = 2 * np.pi * F_KHZ * 1e3
Z_KOHM = (100 + 1 / (1 / 2000 + 1j * W * 1e-6)) / 1e3
TEXT = "frequency,zreal,zimag\n" + "".join(f"{float(f)!r},{float(z.real)!r},{float(z.imag)!r}\n" for f, z in zip(F_KHZ, Z_KOHM))


def read_lab(path):
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    return ix.make_spectrum(table[:, 0] * 1e3, (table[:, 1] + 1j * table[:, 2]) * 1e3, attrs={"format": "LAB"})


BY_EXTENSION = Reader("LAB", (".lab",), lambda path, head: None if str(path).endswith(".lab") else "not a .lab file", read_lab)
BY_CONTENT = Reader("LAB", (".lab",), lambda path, head: None if head.startswith(b"frequency,zreal") else "no LAB header", read_lab)


def _stdin(monkeypatch):
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(TEXT.encode())))


def test_stdin_not_claimed_by_the_users_reader_says_so(monkeypatch):
    _stdin(monkeypatch)
    ds = ix.load("-", readers=register_reader(BY_EXTENSION))
    # read as delimited text, the file's own numbers (kHz taken as Hz): what the note warns of
    assert ds.attrs["format"] == "delimited text"
    np.testing.assert_allclose(ds.frequency.values, F_KHZ, rtol=1e-15)
    note = ds.attrs["stdin_note"]
    assert note.startswith("standard input read as delimited text: it has no file name, and your reader (reader 'LAB') did not claim it")
    assert "(LAB: not a .lab file)" in note and "give the file's path in place of '-'" in note


@pytest.mark.parametrize("readers", [None, "claimed"])
def test_no_note_without_users_readers_or_when_one_claims_it(monkeypatch, readers):
    _stdin(monkeypatch)
    ds = ix.load("-", readers=register_reader(BY_CONTENT) if readers else None)
    assert "stdin_note" not in ds.attrs
    if readers:
        np.testing.assert_allclose(ds.frequency.values, F_KHZ * 1e3, rtol=1e-12)
        np.testing.assert_allclose(ds.Z.values, Z_KOHM * 1e3, rtol=1e-12)


@pytest.mark.parametrize("command", [["inspect"], ["inspect", "--json"], ["kk"]])
def test_commands_show_the_note(monkeypatch, capsys, tmp_path, command):
    plugin = tmp_path / "lab.py"
    plugin.write_text("from impedax.io import Reader\n"
                      "READER = Reader('LAB', ('.lab',), lambda p, h: None if str(p).endswith('.lab') else 'not a .lab file', lambda p: None)\n")
    _stdin(monkeypatch)
    code, out, err = run([command[0], "-", "--plugin", plugin, *command[1:]], capsys)
    assert code == 0, err
    said = "standard input read as delimited text: it has no file name, and your reader (reader 'LAB' of --plugin"
    if command == ["kk"]:  # (every command but inspect prints it on stderr, as a phase unit's note)
        assert f"impedax: warning: <stdin>: {said}" in err and "(LAB: not a .lab file)" in err
    elif "--json" in command:
        assert json.loads(out)["attrs"]["stdin_note"].startswith(said)
    else:
        assert f"  stdin_note: {said}" in out


def test_identify_of_standard_input_says_what_to_do(monkeypatch):
    # (it said "-: file not found", as if a file named '-' were missing)
    _stdin(monkeypatch)
    with pytest.raises(ix.DataError, match=r"^<stdin>: identify looks at a file, and '-' is standard input, which only impedax\.load reads"):
        ix.io.identify("-")
    assert sys.stdin.read() == TEXT  # (left unread)


def test_inspect_help_names_standard_input(capsys):
    # (FILE was "spectrum file": nothing said that '-' reads standard input)
    code, out, _ = run(["inspect", "--help"], capsys)
    assert code == 0
    assert "'-' reads standard input" in " ".join(out.split())


@pytest.mark.parametrize("conventions, says", [
    ("f [kHz], Z' and Z'' [kOhm] as stored", "f [kHz], Z' and Z'' [kOhm] as stored (as reader 'LAB' declares its conventions)"),
    ("", "reader 'LAB' recorded no {what} (Reader.conventions is empty)"),
])
def test_a_users_reader_that_records_no_conventions(tmp_path, conventions, says):
    # SYNTHETIC kHz/kΩ file read by a reader that returns make_spectrum alone: impedax inspect said
    # "impedax data model: Z = Z' + jZ''" and "Hz, ohm", as if the file held Hz and ohm
    path = tmp_path / "run.lab"
    path.write_text(TEXT)
    ds = ix.load(path, readers=register_reader(Reader("LAB", (".lab",), lambda p, h: None, read_lab, conventions)))
    np.testing.assert_allclose(ds.frequency.values, F_KHZ * 1e3, rtol=1e-12)
    assert ds.attrs["sign_convention"] == says.format(what="sign convention")
    assert ds.attrs["units"] == says.format(what="units")
    # a reader that records its own keeps them
    own = ix.load(path, readers=register_reader(Reader("LAB", (".lab",), lambda p, h: None,
                                                       lambda p: read_lab(p).assign_attrs(sign_convention="zimag as stored", units="kHz, kOhm"), conventions)))
    assert (own.attrs["sign_convention"], own.attrs["units"]) == ("zimag as stored", "kHz, kOhm")


COUNTING_PLUGIN = """\
from pathlib import Path
from impedax.io import Reader
import numpy as np, impedax as ix
CALLS = Path({calls!r})

def sniff(path, head):
    with CALLS.open("a") as fh:
        fh.write("sniff\\n")
    return {answer}

def read(path):
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    return ix.make_spectrum(table[:, 0] * 1e3, (table[:, 1] + 1j * table[:, 2]) * 1e3, attrs={{"format": "LAB"}})

READER = Reader("LAB", (".lab",), sniff, read)
"""


@pytest.mark.parametrize("answer, command", [
    ("'not a .lab file'", ["inspect"]), ("'not a .lab file'", ["kk"]), ("None", ["inspect"]), ("None", ["kk"]),
    ("'not a .lab file'", ["inspect", "--select", "sweep=0"]),  # (the reader reads no sweeps: not claimed, read as a table)
])
def test_a_users_sniff_runs_once_on_standard_input(monkeypatch, capsys, tmp_path, answer, command):
    # a counting reader loaded with --plugin: its sniff ran twice on '-' (once for the stdin note,
    # once more in load), where a file's path runs it once
    calls = tmp_path / "calls.txt"
    plugin = tmp_path / "lab.py"
    plugin.write_text(COUNTING_PLUGIN.format(calls=str(calls), answer=answer))
    if "--select" in command:  # (two sweeps of the same SYNTHETIC grid one below the other: a sweep dimension to pick from)
        monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO((TEXT + TEXT.split("\n", 1)[1]).encode())))
    else:
        _stdin(monkeypatch)
    code, _, err = run([command[0], "-", "--plugin", plugin, *command[1:]], capsys)
    assert code == 0, err
    assert calls.read_text().splitlines() == ["sniff"]


def test_standard_input_that_is_a_terminal_is_refused_at_once(monkeypatch, capsys):
    # impedax kk - typed with nothing piped in waited silently for the keyboard; a REAL pseudo-terminal stands in
    import os

    leader, follower = os.openpty()
    os.write(leader, b"\x04")  # (Ctrl-D typed ahead: code that reads the terminal gets end-of-file, not a hang)
    try:
        with open(follower, "rb", buffering=0, closefd=False) as raw:
            monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BufferedReader(raw)))
            assert sys.stdin.buffer.isatty()
            code, out, err = run(["kk", "-"], capsys)
    finally:
        os.close(leader)
        os.close(follower)
    assert code == 2 and out == ""
    assert "impedax kk: error: <stdin>: standard input is a terminal, not a file: '-' reads a spectrum piped in (impedax kk - < run.csv" in err
