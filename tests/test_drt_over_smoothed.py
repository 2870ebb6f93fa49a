"""A fixed λ that smooths the data away is named as the cause, not the data (a walkthrough,
2026-12-05: `impedax drt rc.csv --lam 1e6` said "the data are not Kramers–Kronig consistent in
part … or need γ < 0" and suggested R0 + C1 with C1 = 145 F for a plain R‖C spectrum).

Oracles: SYNTHETIC spectra from numpy formulas written here (R_inf + R/(1 + jωτ), and the same
with a drift of Re Z that no passive cell gives), the automatic λ's own fit of the same
spectrum, and the rule of `DRTResult.over_smoothed` applied by hand.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting.drt.result import OVER_SMOOTHED_FACTOR

FREQ = np.logspace(-2, 5, 71)
OMEGA = 2 * np.pi * FREQ


def rc(level: float = 1e-3, seed: int = 0) -> np.ndarray:
    """SYNTHETIC: 10 Ω + 100 Ω/(1 + jω·10 ms) with relative noise ``level`` on each part."""
    rng = np.random.default_rng(seed)
    z = 10.0 + 100.0 / (1 + 1j * OMEGA * 1e-2)
    return z * (1 + level * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)))


@pytest.mark.parametrize("lam", [1e6, 1.0])
def test_an_over_smoothing_lambda_is_named_not_the_data(lam):
    fixed = ix.drt((FREQ, rc()), lam=lam)
    auto = ix.drt((FREQ, rc()))
    assert fixed.misfits and not auto.misfits
    assert fixed.auto_lambda == pytest.approx(auto.lam)
    assert fixed.auto_rms_rel == pytest.approx(auto.rms_rel, rel=1e-6)
    assert fixed.rms_rel >= OVER_SMOOTHED_FACTOR * fixed.auto_rms_rel  # by hand: 70 % / 7.6 % against ≈ 1 %
    assert fixed.over_smoothed
    (warning,) = [w for w in fixed.warnings if "reproduces the data" in w]
    assert "over-smooths" in warning and "let it be chosen (lam='auto')" in warning  # (Python's words; impedax drt says --lam auto)
    assert "Kramers" not in warning and "γ < 0" not in warning
    assert f"{auto.rms_rel * 100:.3g} %" in warning
    assert fixed.suggested_circuit().reasons[0].startswith("read off a DRT whose λ")
    summary = fixed.summary()
    assert summary["over_smoothed"] is True and summary["auto_rms_rel"] == pytest.approx(auto.rms_rel, rel=1e-6)


def test_the_automatic_lambda_and_a_fitting_fixed_one_are_not_flagged():
    auto = ix.drt((FREQ, rc()))
    assert not auto.over_smoothed and math.isnan(auto.auto_lambda) and math.isnan(auto.auto_rms_rel)
    small = ix.drt((FREQ, rc()), lam=1e-3)  # (close to gcv's choice: γ reproduces the data)
    assert not small.misfits and not small.over_smoothed and math.isnan(small.auto_rms_rel)
    assert not any("reproduces the data" in w for w in auto.warnings + small.warnings)


def test_data_no_lambda_reproduces_keep_the_kk_words():
    """SYNTHETIC non-KK data: Re Z drifts by 110 Ω × f_min/f. At a small fixed λ γ misfits and
    so does the automatic λ: the data are the cause, and the warning says so."""
    z = rc(0.01) + 110.0 * FREQ.min() / FREQ
    fixed = ix.drt((FREQ, z), lam=1e-4)
    assert fixed.misfits
    assert fixed.auto_rms_rel > fixed.rms_rel / OVER_SMOOTHED_FACTOR  # by hand: the automatic λ misfits as much
    assert not fixed.over_smoothed
    (warning,) = [w for w in fixed.warnings if "reproduces the data" in w]
    assert "Kramers–Kronig" in warning and "over-smooths" not in warning


def test_a_batch_names_the_over_smoothed_spectra_alone():
    """Two spectra at one fixed λ: the exact R‖C is over-smoothed, the drifting one is not
    reproduced at any λ; each is told its own cause."""
    z = np.stack([rc(), rc(0.01) + 110.0 * FREQ.min() / FREQ])
    batch = ix.drt((FREQ, z), lam=0.3)
    flags = [r.over_smoothed for r in batch.results]
    assert flags[0] is True
    assert all(r.misfits for r in batch.results)
    assert flags[1] is False
    report = batch.report()
    assert "over-smooths 1 of 2 spectra (dim_0=0)" in report
    assert "γ reproduces 1 of 2 spectra (dim_0=1)" in report and "Kramers–Kronig" in report


def test_the_cli_withholds_the_suggested_circuit(tmp_path, capsys):
    path = tmp_path / "rc.csv"
    z = rc()
    np.savetxt(path, np.column_stack([FREQ, z.real, z.imag]), delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm", comments="")
    assert main(["drt", str(path), "--lam", "1e6"]) == 0
    text = capsys.readouterr().out
    assert "over-smooths" in text and "R0 + C1" not in text
    assert "starting circuit from the DRT: none while λ over-smooths the data" in text
    assert main(["drt", str(path), "--lam", "1e6", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["over_smoothed"] is True and record["auto_lambda"] < 1e6
    assert record["suggestion_withheld"].startswith("while λ over-smooths the data")  # (the text's reason, 2026-12-06)


def test_a_real_spectrum_at_an_over_smoothing_lambda_is_named_so():
    """REAL: impedance.py's ZPlot example at λ = 1; the automatic λ reproduces it at least 3× better."""
    from pathlib import Path

    path = Path(__file__).parent / "fixtures" / "real" / "exampleDataZPlot.z"
    fixed, auto = ix.drt(path, lam=1.0), ix.drt(path)
    assert fixed.misfits and fixed.rms_rel >= OVER_SMOOTHED_FACTOR * auto.rms_rel
    assert fixed.over_smoothed and any("over-smooths" in w for w in fixed.warnings)
