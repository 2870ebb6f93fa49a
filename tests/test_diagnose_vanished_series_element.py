"""A user's series element that a candidate makes redundant is left out of it, not the
candidate set aside (a walkthrough, 2026-12-05: a Randles spectrum fitted as R0 + R1 ∥ C1 + W1,
a Warburg misplaced in series; the candidate with the Warburg in R1's branch lowered AIC by 70
while W1.sigma fell to 0, was set aside as "the data do not determine W1.sigma", and the verdict
read ADEQUATE; refine's final C1 stood 15 σ off the truth).

Oracles: SYNTHETIC spectra from numpy formulas written here (a Randles cell, and a series
Warburg: the user's model itself, where nothing is missing), fixed seeds, 0.5 % noise; the true
values of the formulas.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from impedax.cli import main

F = np.logspace(5, -2, 71)
W = 2 * np.pi * F
TRUE = {"R0": 10.0, "R1": 50.0, "sigma": 30.0, "C1": 1e-5}


def warburg(sigma):
    return sigma * (1 - 1j) / np.sqrt(W)


def randles():
    """SYNTHETIC: R0 + (R1 + W) ∥ C1."""
    branch = TRUE["R1"] + warburg(TRUE["sigma"])
    return TRUE["R0"] + 1 / (1 / branch + 1j * W * TRUE["C1"])


def series_warburg():
    """SYNTHETIC: R0 + R1 ∥ C1 + W, the user's model itself."""
    return TRUE["R0"] + 1 / (1 / TRUE["R1"] + 1j * W * TRUE["C1"]) + warburg(TRUE["sigma"])


def saved(tmp_path, z, seed=5, level=0.005):
    rng = np.random.default_rng(seed)
    z = z + np.abs(z) * level * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size))
    path = tmp_path / "cell.csv"
    np.savetxt(path, np.c_[F, z.real, z.imag], delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm", comments="", fmt="%.10g")
    return str(path)


def run_json(argv, capsys):
    assert main([*argv, "--json", "-q"]) == 0
    return json.loads(capsys.readouterr().out)


MODEL = "R0 + R1 || C1 + W1"


def test_a_misplaced_warburg_moves_into_the_branch(tmp_path, capsys):
    path = saved(tmp_path, randles())
    result = run_json(["diagnose", path, "--model", MODEL], capsys)
    assert result["verdict"] == "missing_effect"
    best = result["suggestions"][0]
    assert best["model"] == "R0 + (R1 + W_d) || C1"
    assert "W1 left out (it fell to" in best["explanation"] and best["delta_aic"] < -10
    refined = run_json(["refine", path, "--model", MODEL], capsys)
    assert refined["final_model"] == "R0 + (R1 + W_d) || C1"
    values = {k: v["value"] for k, v in refined["final_params"].items()}
    for name, truth in (("R0", TRUE["R0"]), ("R1", TRUE["R1"]), ("W_d.sigma", TRUE["sigma"]), ("C1", TRUE["C1"])):
        assert values[name] == pytest.approx(truth, rel=0.02), name


def test_nothing_is_left_out_when_the_series_warburg_is_right(tmp_path, capsys):
    path = saved(tmp_path, series_warburg())
    result = run_json(["diagnose", path, "--model", MODEL], capsys)
    assert result["verdict"] == "adequate"
    assert not any("W1 left out" in s["explanation"] for s in result["suggestions"])


def test_a_refine_that_only_simplifies_says_rms_rel_stayed(tmp_path, capsys):
    """SYNTHETIC R0 + R1 ∥ C1 fitted as R0 + R1 ∥ C1 + W1: refine drops W1 and rms_rel stays
    where it was (it said "fell from 1.4 % to 1.4 %")."""
    rc = TRUE["R0"] + 1 / (1 / TRUE["R1"] + 1j * W * TRUE["C1"])
    path = saved(tmp_path, rc, seed=6, level=0.01)
    assert main(["refine", path, "--model", MODEL, "-q"]) == 0
    out = capsys.readouterr().out.splitlines()
    rows = [x.split() for x in out if x[:4].strip().isdigit()]  # the table's steps: index, rms_rel %, AIC, change
    before, after = rows[0][1].rstrip("%"), rows[-1][1].rstrip("%")
    line = next(x for x in out if x.startswith("rms_rel "))
    # by hand: the table's first and last rms_rel, as printed (the table's column holds one number
    # of decimals, "1.40", where the line writes 3 significant digits, "1.4": the same numbers)
    said = re.match(r"rms_rel (?:stayed at ([\d.]+) %|(fell|rose) from ([\d.]+) % to ([\d.]+) %) in ", line)
    assert said is not None, line
    if float(before) == float(after):
        assert said.group(1) is not None and float(said.group(1)) == float(after), line
    else:
        assert said.group(2) == ("fell" if float(after) < float(before) else "rose"), line
        assert (float(said.group(3)), float(said.group(4))) == (float(before), float(after)), line
    assert len(rows) == 2 and "− W1" in " ".join(rows[1])
