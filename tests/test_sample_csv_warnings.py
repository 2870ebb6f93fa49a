"""``impedax sample --out x.csv`` tells a CSV user that the sampling was unreliable: the columns
``chain_converged`` (the JSON's key) and ``warnings`` (the run's warnings joined by "; ", as
``impedax fit``'s CSV has them) on every row, after the columns that were there. The JSON and
netCDF had the warnings; the CSV had none. SYNTHETIC R0 + R1 ∥ C1 written in numpy, a chain of
20 steps: too short to estimate τ."""

from __future__ import annotations

import csv
import json

import numpy as np

import impedax as ix
from impedax.cli import main

COLUMNS = ["name", "median", "q05", "q16", "q84", "q95", "unit", "autocorr", "ess", "undetermined", "fixed", "at_prior_edge"]


def _rows(path):
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(line for line in handle if not line.startswith("#")))


def test_a_short_chain_s_csv_says_it_is_unreliable(tmp_path, capsys):
    f = np.logspace(0, 5, 25)
    z = 10 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6)
    z = z * (1 + 0.01 * (np.random.default_rng(2).standard_normal(25) + 1j * np.random.default_rng(3).standard_normal(25)))
    ix.save(ix.make_spectrum(f, z), tmp_path / "rc.csv")
    out = tmp_path / "post.csv"
    assert main(["sample", str(tmp_path / "rc.csv"), "--model", "R0 + R1 || C1", "--steps", "20", "--seed", "1", "--fix", "R0=10", "--quiet", "--out", str(out)]) == 0
    capsys.readouterr()  # (the report)
    assert main(["sample", str(tmp_path / "rc.csv"), "--model", "R0 + R1 || C1", "--steps", "20", "--seed", "1", "--fix", "R0=10", "--quiet", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    rows = _rows(out)
    assert list(rows[0])[: len(COLUMNS)] == COLUMNS  # (the columns before keep their places)
    assert list(rows[0])[len(COLUMNS):][:2] == ["chain_converged", "warnings"]
    assert {r["name"] for r in rows} == {"R0", "R1", "C1", "sigma_rel"}  # (the fixed R0's row too)
    assert all(r["chain_converged"] == "false" for r in rows) and doc["chain_converged"] is False
    assert all(r["warnings"] == "; ".join(doc["warnings"]) for r in rows)
    assert "the chain is too short to estimate τ (15 draws per walker after burn-in" in rows[0]["warnings"]  # (20 steps, burn 5)
