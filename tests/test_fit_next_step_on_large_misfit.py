"""`impedax fit` ends with the `impedax diagnose` command to run next when its warning says the
model misses structure the data hold (rms_rel over 5× what a Kramers–Kronig-consistent model
reaches), as it does for a misfit that looks small (the hint): on REAL Gamry, `R0 + R1 || C1`
ends at 30.1 % against the chain's 4.8 %, and the warning said "a diagnosis (impedax diagnose)
shows where it fails" with no command, where the README says each step says what to run next.
A fit with no such warning (SYNTHETIC, the model that made the data) gets no next line."""

from __future__ import annotations

import shlex
from pathlib import Path

import numpy as np

from cli_run import run

REAL = Path(__file__).parent / "fixtures" / "real"


def next_line(out: str) -> str | None:
    return next((line for line in out.splitlines() if line.startswith("next: ")), None)


def test_gamrys_large_misfit_ends_with_the_diagnose_command(capsys):
    path = REAL / "exampleDataGamry.DTA"
    code, out, err = run(["fit", path, "--model", "R0 + R1 || C1", "-q"], capsys)
    assert code == 0, err
    assert "warning: the model misses structure the data hold: its rms_rel is over 5×" in out
    line = next_line(out)
    assert line is not None, out
    command = line[len("next: "):].split(" (", 1)[0]
    assert shlex.split(command) == ["impedax", "diagnose", str(path), "--model", "R0 + R1 || C1"]
    assert line.endswith("(where the model fails and what it misses; the warning above)")


def test_a_fit_at_the_noise_gets_no_next_line(tmp_path, capsys):
    rng = np.random.default_rng(2)
    f = np.geomspace(1e5, 1.0, 31)
    z = (100.0 + 1000.0 / (1 + 2j * np.pi * f * 1e-3)) * (1 + 0.002 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2))
    path = tmp_path / "rc.csv"
    np.savetxt(path, np.column_stack([f, z.real, z.imag]), delimiter=",", header="freq,zreal,zimag", comments="")
    code, out, err = run(["fit", path, "--model", "R0 + R1 || C1", "-q"], capsys)
    assert code == 0, err
    assert next_line(out) is None and "warning" not in out, out
