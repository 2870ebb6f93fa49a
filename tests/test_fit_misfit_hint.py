"""A single fit whose misfit looks small (below the 2 % from which the misfit warning is
checked) but is many times what a Kramers–Kronig-consistent model reaches gets a hint, in the
text and the JSON's ``hints`` (a beginner's walkthrough kept the values of such a fit)."""

import json
import os
import shlex

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting.least_squares.result import misfit_hint

ZPLOT = os.path.join(os.path.dirname(__file__), "fixtures", "real", "exampleDataZPlot.z")  # REAL, impedance.py (MIT)


def test_a_small_looking_misfit_far_above_the_kk_chain_gets_a_hint_that_runs(capsys):
    """REAL ZPlot file: `R0 + R1 || CPE1` ends at 1.35 % where the KK chain reaches 0.137 %
    (a lead inductance is missing: diagnose's first suggestion); the hint says so and its
    command runs."""
    assert main(["fit", ZPLOT, "--model", "R0 + R1 || CPE1", "--quiet"]) == 0
    hint = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("hint: "))
    assert hint.startswith("hint: rms_rel 1.35 % is 9.") and "0.137 % a Kramers–Kronig-consistent model reaches" in hint
    command = hint.split(": impedax ")[-1]
    assert command.startswith("diagnose ") and main(shlex.split(command)) == 0
    assert "series_inductance" in capsys.readouterr().out
    assert main(["fit", ZPLOT, "--model", "R0 + R1 || CPE1", "--json", "--quiet"]) == 0
    assert json.loads(capsys.readouterr().out)["hints"] == [hint[len("hint: "):hint.index(": impedax diagnose")]]


def test_no_hint_where_the_model_holds_the_data_structure(capsys):
    """With the lead inductance the fit reaches 0.35 %, 2.6× the chain's: no hint; JSON
    ``hints`` is empty."""
    assert main(["fit", ZPLOT, "--model", "R0 + L0 + R1 || CPE1", "--json", "--quiet"]) == 0
    assert json.loads(capsys.readouterr().out)["hints"] == []


@pytest.mark.parametrize("noise", [0.003, 0.01])
def test_no_hint_for_the_right_model_at_the_noise(noise):
    """SYNTHETIC R0 + R1 ∥ C1 (numpy formula) at 0.3 % and 1 % noise, fitted with that model:
    its misfit is the noise, which the chain reaches too (no hint)."""
    f = np.geomspace(1.0, 1e5, 50)
    rng = np.random.default_rng(4)
    z = 20 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6)
    z = z * (1 + noise * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2))
    fit = ix.fit("R0 + R1 || C1", (f, z))
    assert fit.rms_rel < 0.02 and misfit_hint(fit) is None
