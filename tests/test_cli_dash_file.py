"""A data file whose name starts with '-' (``-data.csv``) reads as an option to argparse, which
then said only "the following arguments are required: FILE". The error now names the file and
the way to give it (``./-data.csv``); without such a file the message is argparse's alone."""

import shutil
from pathlib import Path

import pytest

from impedax.cli import main

REAL = Path(__file__).parent / "fixtures" / "real" / "exampleData.csv"  # REAL: impedance.py's example


@pytest.mark.parametrize("argv, required", [(["inspect", "-data.csv"], "FILE"), (["fit", "-data.csv", "--model", "R0 + R1 || C1"], "DATA")])
def test_a_file_named_like_an_option_is_named_in_the_error(tmp_path, monkeypatch, capsys, argv, required):
    monkeypatch.chdir(tmp_path)
    shutil.copy(REAL, tmp_path / "-data.csv")
    with pytest.raises(SystemExit) as stop:
        main(argv)
    err = capsys.readouterr().err
    assert stop.value.code == 2
    assert err.splitlines()[0] == f"impedax {argv[0]}: error: the following arguments are required: {required}; -data.csv is a file, but a word that starts with '-' reads as an option: write ./-data.csv"


def test_without_such_a_file_argparse_says_it_alone(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as stop:
        main(["inspect", "-data.csv"])
    assert stop.value.code == 2
    assert capsys.readouterr().err.splitlines()[0] == "impedax inspect: error: the following arguments are required: FILE"


def test_the_advised_name_is_read(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    shutil.copy(REAL, tmp_path / "-data.csv")
    assert main(["inspect", "./-data.csv"]) == 0
    assert capsys.readouterr().out.startswith("./-data.csv: delimited text, 66 frequencies")
