"""`impedax fit --shared` prints the hint that a fit misses structure small as its misfit looks
before the diagnose command it leads to, as a batch does (the REAL 3 battery cycles with
--shared CPE2.alpha printed "next: impedax diagnose ... --select cycle=0 ... (where the model
fails on the worst of those spectra ...)" with no line saying which spectra)."""

import re
from pathlib import Path

import pytest

from impedax.cli import main

THREE = Path(__file__).resolve().parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc"


@pytest.mark.slow  # (~40 s: a global fit of three REAL cycles, its solvers compiled, and its independent fits)
def test_the_diagnose_command_of_a_global_fit_follows_its_hint(capsys):
    assert main(["fit", str(THREE), "--model", "R0 + R1 || CPE1 + R2 || CPE2 + W1", "--shared", "CPE2.alpha", "-q"]) == 0
    lines = capsys.readouterr().out.splitlines()
    follow = [i for i, line in enumerate(lines) if line.startswith("next: impedax diagnose ")]
    assert follow, "the run leads to a diagnosis"
    hint = lines[follow[0] - 1]
    assert hint.startswith("hint: ")
    # the spectrum the hint names is the one the command selects
    named = re.search(r"(cycle=\d+)", hint).group(1)
    assert f"--select {named} " in lines[follow[0]]
