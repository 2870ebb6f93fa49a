"""A suggestion cites the DRT's evidence only when its fit agrees with it (a walkthrough,
2026-12-05: on REAL Autolab data "the data's DRT peak … is wider than an R‖C's: α ≈ 0.80" stood
beside a fitted CPE1.alpha = 0.404). Oracles: a SYNTHETIC R ∥ CPE spectrum of α = 0.8 written
here with numpy (its fit and its DRT agree), the REAL file's fitted α read from the JSON, and
the agreement rule applied by hand."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from impedax.cli import main
from impedax.fitting.diagnosis.diagnosis import EVIDENCE_ALPHA_AGREEMENT

REAL = Path(__file__).parent / "fixtures" / "real"


def suggestions(argv, capsys):
    assert main([*argv, "--json", "-q"]) == 0
    return json.loads(capsys.readouterr().out)["suggestions"]


def test_an_agreeing_fit_cites_the_drt_peak(tmp_path, capsys):
    f = np.logspace(5, -2, 71)
    w = 2 * np.pi * f
    z = 20 + 1 / (1 / 100 + 1e-5 * (1j * w) ** 0.8)  # SYNTHETIC R0 + R1 ∥ CPE, α = 0.8
    rng = np.random.default_rng(2)
    z = z + np.abs(z) * 0.01 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
    path = tmp_path / "rcpe.csv"
    np.savetxt(path, np.c_[f, z.real, z.imag], delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm", comments="", fmt="%.10g")
    best = suggestions(["diagnose", str(path), "--model", "R0 + R1 || C1"], capsys)[0]
    assert best["effect"] == "constant_phase"
    assert "wider than an R‖C's: α ≈" in best["explanation"] and "but the fit took" not in best["explanation"]
    implied = float(best["explanation"].split("wider than an R‖C's: α ≈ ")[1][:4])
    assert abs(implied - best["values"]["CPE1.alpha"]) <= EVIDENCE_ALPHA_AGREEMENT  # by hand
    assert best["values"]["CPE1.alpha"] == pytest.approx(0.8, abs=0.02)  # the formula's α


def test_a_disagreeing_fit_says_what_the_cpe_spans_instead(capsys):
    found = [s for s in suggestions(["diagnose", str(REAL / "exampleDataAutolab.txt"), "--model", "R0 + R1 || C1"], capsys) if s["effect"].startswith("constant_phase")]
    assert found
    for s in found:
        text = s["explanation"]
        assert "wider than an R‖C's" not in text
        implied, took = (float(x) for x in text.split("implies CPE1.alpha ≈ ")[1].split(": the CPE")[0].split(", but the fit took "))
        assert took == pytest.approx(s["values"]["CPE1.alpha"], abs=0.005)  # the fit's own α
        assert abs(implied - took) > EVIDENCE_ALPHA_AGREEMENT  # by hand, from the words
