"""A second spectrum file given to a command that reads one (a shell glob, ``impedax inspect *.csv``)
is told what to do, as fit, kk and drt's were: until 2026-12-06 inspect, diagnose, refine, sample and
compare said "unrecognized arguments: b.csv" alone, and gap and remaining of a fourth file too."""

import numpy as np
import pytest

from cli_run import run

STACK = "join files of one spectrum each into one series with impedax stack FILE ... --out SERIES.nc, then impedax compare SERIES.nc"


@pytest.fixture
def files(tmp_path):
    # SYNTHETIC R0 + R1 || C1 (R0 = 10 Ω, R1 = 100 Ω, C1 = 1 µF) at 20 frequencies, written twice
    f = np.logspace(5, -1, 20)
    z = 10 + 100 / (1 + 1j * 2 * np.pi * f * 1e-4)
    text = "frequency,zreal,zimag\n" + "".join(f"{a!r},{b.real!r},{b.imag!r}\n" for a, b in zip(f.tolist(), z.tolist()))
    paths = [tmp_path / "a.csv", tmp_path / "b.csv"]
    for p in paths:
        p.write_text(text)
    return paths


@pytest.mark.parametrize("command, options, said", [
    ("inspect", [], "inspect reads one file: run impedax inspect once per file"),
    ("diagnose", ["--model", "R0 + R1 || C1"], "diagnose reads one DATA file: run impedax diagnose once per file"),
    ("refine", [], "refine reads one DATA file: run impedax refine once per file"),
    ("sample", ["--model", "R0 + R1 || C1"], "sample reads one DATA file: run impedax sample once per file"),
    ("compare", ["--model", "R0 + R1 || C1", "--model", "R0 + C1"], f"compare reads one DATA file: {STACK}"),
])
def test_a_second_file_is_told_what_to_do(files, capsys, command, options, said):
    code, out, err = run([command, *files, *options], capsys)
    assert code == 2 and out == ""
    assert f"unrecognized arguments: {files[1]}; {said}" in err


@pytest.mark.parametrize("command, options", [("gap", ["--area", "1e-4"]), ("remaining", [])])
def test_a_fourth_file_of_gap_and_remaining(files, capsys, command, options):
    code, _, err = run([command, *files, *files, *options], capsys)
    assert code == 2
    assert (f"unrecognized arguments: {files[1]}; {command} reads at most three files, DATA_TOTAL [DATA_SKIN DATA_TS]: the trials of one "
            "contact go in one file as an extra dimension (impedax stack TRIAL_FILE ... --dim trial --out TOTAL.nc)") in err
