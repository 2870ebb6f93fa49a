"""A value that starts with '-' after an option (``--noise -1%``): argparse reads it as an option
and said only "expected one argument"; the message now says how to write it, and the form it
suggests reaches the command's own check of the value."""

from __future__ import annotations

import numpy as np
import pytest

from impedax.cli import main


def run(argv, capsys) -> tuple[int, str]:
    """Exit code and stderr of ``impedax ARGV`` (argparse's errors exit by SystemExit)."""
    try:
        code = main(argv)
    except SystemExit as stop:
        code = stop.code
    return code, capsys.readouterr().err


@pytest.fixture(scope="module")
def data_file(tmp_path_factory):
    f = np.geomspace(1e5, 1, 30)
    z = 10 + 100 / (1 + 1j * 2 * np.pi * f * 100 * 1e-6)  # SYNTHETIC R ∥ C with a series R
    path = tmp_path_factory.mktemp("dash") / "d.csv"
    np.savetxt(path, np.c_[f, z.real, z.imag], delimiter=",", header="frequency,Z_real,Z_imag", comments="")
    return str(path)


@pytest.mark.parametrize("command, option, value", [("diagnose", "--noise", "-1%"), ("fit", "--weighting", "-x"), ("kk", "--fmin", "-1k")])
def test_a_dash_value_is_explained_and_its_written_form_reaches_the_check(data_file, command, option, value, capsys):
    model = ["--model", "R0 + R1 || C1"] if command != "kk" else []
    code, err = run([command, data_file, *model, option, value], capsys)
    assert code == 2
    assert f"argument {option}: expected one argument; its value {value} starts with '-', which reads as an option: write {option}={value}" in err
    assert err.count("\n") == 2  # (one message, one usage line)
    code, err = run([command, data_file, *model, f"{option}={value}"], capsys)
    assert code == 2
    assert "expected one argument" not in err and option.lstrip("-") in err  # (the command's own words on the value)


def test_an_option_missing_its_value_at_the_end_gets_no_dash_hint(data_file, capsys):
    code, err = run(["diagnose", data_file, "--model", "R0 + R1 || C1", "--noise"], capsys)
    assert code == 2
    assert "expected one argument" in err and "starts with '-'" not in err


def test_info_with_two_words_is_not_told_to_give_data(capsys):
    """`impedax info R0 R1`: info reads no DATA, so the hint is not "impedax info DATA --model R1"
    (walkthrough 2026-12-05) but that it takes one circuit, quoted when of several words."""
    from impedax.cli import main

    try:
        code = main(["info", "R0", "R1"])
    except SystemExit as exc:
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2 and "DATA" not in err and "takes one circuit and no data file" in err
