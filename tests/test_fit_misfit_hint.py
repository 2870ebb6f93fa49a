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


EXAMPLE = os.path.join(os.path.dirname(__file__), "fixtures", "real", "exampleData.csv")  # REAL, impedance.py (MIT)


@pytest.mark.slow  # (12 s: two fits and a diagnosis of a REAL spectrum)
def test_a_comparison_whose_best_model_still_misses_structure_says_so_and_the_command_runs(capsys):
    """REAL exampleData: the best of two battery models fits at 1.14 %, 6.3× the 0.18 % the KK
    chain reaches (below the 2 % of the misfit warning, so the fits' own warnings are silent on
    it): the comparison's table, the JSON's ``best_misfit_hint`` and a runnable diagnose
    command say so. Oracle for "misses structure": the diagnosis then names an effect."""
    models = ["R0 + R1 || CPE1 + W1", "L0 + R0 + R1 || CPE1 + R2 || CPE2 + W1"]
    argv = ["compare", EXAMPLE] + [w for m in models for w in ("--model", m)]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert f"{models[1]} (the best): rms_rel 1.14 % is 6." in out
    command = next(line for line in out.splitlines() if line.startswith("hint: ")).split(": ", 2)[-1]
    assert command.startswith("impedax diagnose ") and command.endswith(shlex.quote(models[1]))
    assert main(shlex.split(command)[1:] + ["--json"]) == 0
    assert json.loads(capsys.readouterr().out)["verdict"] == "missing_effect"
    assert main(argv + ["--json"]) == 0
    assert json.loads(capsys.readouterr().out)["best_misfit_hint"].startswith("rms_rel 1.14 % is 6.")


def test_a_comparison_whose_best_model_misses_a_small_arc_says_so():
    """SYNTHETIC R0 + R1 ∥ C1 + R2 ∥ C2 (numpy formula; a second arc of 50 Ω at 11 Hz, where
    |Z| ≈ 1 kΩ; 0.05 % noise): of R0 + R1 ∥ C1 and R0 + C1 the first is the best, at 1.4 %
    rms_rel (below the misfit warning's 2 %), 7.6× the 0.18 % the KK test's chain reaches: the
    hint says so."""
    f = np.geomspace(1.0, 1e5, 50)
    rng = np.random.default_rng(6)
    z = 20 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6) + 50 / (1 + 2j * np.pi * f * 50 * 3e-4)
    z = z * (1 + 0.0005 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2))
    comparison = ix.compare([ix.fit("R0 + R1 || C1", (f, z)), ix.fit("R0 + C1", (f, z))])
    best = comparison.fits[comparison.best_index]
    assert comparison.best == "R0 + R1 || C1" and 0.002 < best.rms_rel < 0.02
    hint = comparison.best_misfit_hint()
    assert hint is not None and hint.startswith(f"rms_rel {best.rms_rel * 100:.3g} % is ") and f"R0 + R1 || C1 (the best): {hint}" in comparison.report()
    assert comparison.summary()["best_misfit_hint"] == hint


def test_no_comparison_hint_when_the_best_model_is_the_data_s(capsys):
    """SYNTHETIC R0 + R1 ∥ C1 (numpy formula, 0.5 % noise): the right model is the best and fits
    at the noise; the wrong one misfits by more than 2 % (its own warning says so): no hint."""
    f = np.geomspace(1.0, 1e5, 50)
    rng = np.random.default_rng(5)
    z = (20 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6)) * (1 + 0.005 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2))
    comparison = ix.compare([ix.fit("R0 + R1 || C1", (f, z)), ix.fit("R0 + C1", (f, z))])
    assert comparison.best == "R0 + R1 || C1" and comparison.best_misfit_hint() is None
    assert comparison.summary()["best_misfit_hint"] is None and "(the best)" not in comparison.report()
