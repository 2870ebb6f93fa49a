"""`impedax info FILE`: a user who points the model command at a spectrum file is told which
command reads files, not shown a circuit-syntax caret under the file name's '.'."""

from pathlib import Path

import pytest

from impedax.cli import main

REAL = Path(__file__).parent / "fixtures" / "real"


@pytest.mark.parametrize("name", ["exampleDataZPlot.z", "exampleData.csv", "exampleDataGamry.DTA"])
def test_info_on_a_real_file_points_to_inspect(name, capsys):
    path = REAL / name
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and "Traceback" not in err and "^" not in err
    assert f"'{path}' is a file, not a circuit" in err and f"impedax inspect {path}" in err


def test_info_on_a_missing_file_name_says_so(capsys, tmp_path):
    """A name ending in a spectrum file's extension that names no file: the same pointer, saying
    that no such file exists."""
    path = tmp_path / "run1.mpt"
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"'{path}' looks like a spectrum file's name (no such file), not a circuit" in err and "impedax inspect" in err


def test_info_on_circuit_text_is_unchanged(capsys):
    """Circuit text with a syntax error keeps the parser's message and caret."""
    assert main(["info", "R0 + R1 ||"]) == 2
    err = capsys.readouterr().err
    assert "^" in err and "impedax inspect" not in err


def test_info_on_standard_input_points_to_inspect(capsys):
    """`cat run.z | impedax info -`: '-' is standard input, which the model command does not
    read; it is told so and pointed at inspect, not shown a caret under '-' with a hint that
    series is written '+'."""
    assert main(["info", "-"]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and "^" not in err and "series is written" not in err
    assert "'-' is standard input, not a circuit: impedax info takes a model there (impedax info 'R0 + R1 || C1')" in err
    assert "what impedax reads from a spectrum piped in, and how: impedax inspect -" in err
