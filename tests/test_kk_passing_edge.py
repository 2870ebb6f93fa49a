"""A passing band's end that still holds part of what was left out (a walkthrough, 2026-12-05:
on a drift of Re Z fading out at 1 Hz, `impedax kk` advised --fmin 0.3, keeping points the drift
still moved by 2–7 %, with no word). Oracles: SYNTHETIC spectra from numpy formulas written here,
whose drift is known point by point; noisy copies (fixed seeds) where the noise hides the edge;
the REAL files whose passing bands the module docstring lists, whose ends stand at the rest's level.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.kk import EDGE_DECADES, EDGE_EXCESS

FREQ = np.logspace(-2, 5, 71)  # 10 mHz–100 kHz, 10 a decade
Z_CELL = 10.0 + 100.0 / (1 + 2j * np.pi * FREQ * 1e-2)  # 10 Ω + 100 Ω ∥ 100 µF
DRIFT = np.where(FREQ < 1.0, 120.0 * (np.log10(1.0 / FREQ) / 2) ** 2, 0.0)  # Re Z only: 120 Ω at 10 mHz, 0 from 1 Hz
REAL = Path(__file__).parent / "fixtures" / "real"


def test_an_exact_drift_fading_into_the_band_is_named_with_a_cut_further_in():
    result = ix.kk_test((FREQ, Z_CELL + DRIFT), find_passing_band=True)
    assert not result.valid and result.passing_band is not None
    lo, hi = result.passing_band
    assert lo == pytest.approx(0.316, rel=0.01) and hi == pytest.approx(1e5)
    f_lo, f_hi, d_lo, d_hi, median = result.passing_edge
    assert f_lo == pytest.approx(lo) and f_hi <= lo * 10**EDGE_DECADES * (1 + 1e-9)
    # by hand: the true drift at the edge's points, a share of |Z| the band's end still holds
    edge = (FREQ >= f_lo) & (FREQ <= f_hi)
    assert np.all(DRIFT[edge][:-1] / np.abs(Z_CELL[edge][:-1]) > 0.001)
    assert d_hi > EDGE_EXCESS * median
    words = result.passing_edge_words()
    assert words.startswith("its lowest points (316 mHz–1 Hz) still stand") and "(data.where(data.frequency >= 1, drop=True))" in words  # (Python's words)
    assert words in result.report()
    assert result.summary()["passing_edge"] is not None


def test_the_command_line_gives_the_cut_as_its_option(tmp_path, capsys):
    """`impedax kk` says --fmin 1 where Python says data.where(data.frequency >= 1, drop=True)
    (text and JSON; until 2026-12-06 Python read the option too)."""
    import json

    from cli_run import run

    path = tmp_path / "drift.csv"
    z = Z_CELL + DRIFT
    np.savetxt(path, np.c_[FREQ, z.real, z.imag], delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm", comments="")
    code, out, _ = run(["kk", path], capsys)
    assert code == 0 and "check that a fit on it agrees with one a half decade further in (--fmin 1)" in out and "data.where" not in out
    code, out, _ = run(["kk", path, "--json"], capsys)
    assert code == 0 and json.loads(out)["passing_edge"]["words"].endswith("a half decade further in (--fmin 1)")


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_noise_hides_the_edge_and_nothing_is_said(seed):
    """At 0.3 % noise the drift's tail inside the band is below the noise: a passing band may be
    found, its end is not named (no false alarm)."""
    rng = np.random.default_rng(seed)
    z = (Z_CELL + DRIFT) * (1 + 0.003 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)))
    result = ix.kk_test((FREQ, z), find_passing_band=True)
    assert result.passing_edge is None and "still stand" not in result.report()


@pytest.mark.parametrize("name", ["exampleDataParstat.txt", "exampleDataPowersuite.txt", "exampleDataCHInstruments.txt"])
def test_the_real_passing_bands_have_no_edge_to_name(name):
    result = ix.kk_test(ix.load(REAL / name), find_passing_band=True)
    assert result.passing_band is not None and result.passing_edge is None
