"""An empty file name (``impedax kk "$DATA"`` of an unset variable, ``ix.load("")``) is named as
such: until 2026-12-06 pathlib read '' as the current folder and users were told "'.': is a
directory, not a spectrum file"."""

import pytest

import impedax as ix

from cli_run import run

SAID = "empty file name: no spectrum file was named (an unset shell variable, \"$DATA\" with nothing in it?)"


@pytest.mark.parametrize("argv, named", [
    (["kk", ""], "DATA"),
    (["inspect", ""], "FILE"),
    (["fit", "", "--model", "R0 + R1 || C1"], "DATA"),
    (["gap", "total.csv", "", "ts.csv", "--area", "1e-4"], "DATA_SKIN"),
    (["stack", "a.csv", "", "--out", "series.nc"], "FILE"),
    (["simulate", "R0", "--frequencies", ""], "--frequencies"),
])
def test_the_command_line_names_the_empty_argument(tmp_path, monkeypatch, capsys, argv, named):
    monkeypatch.chdir(tmp_path)
    code, out, err = run(argv, capsys)
    assert code == 2 and out == ""
    assert f"error: argument {named}: {SAID}" in err and "directory" not in err
    assert list(tmp_path.iterdir()) == []  # (nothing written)


@pytest.mark.parametrize("call", [ix.load, ix.io.identify])
def test_python_says_the_name_is_empty(call):
    with pytest.raises(ix.DataError, match=r"^empty file name: no spectrum file was named"):
        call("")
