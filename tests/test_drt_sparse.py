"""The DRT on sparse data says what it cannot tell (a walkthrough, 2026-12-05: on 6 exact
points over 5 decades, tests/fixtures/zplot_sweep.z, its 13 % misfit sat beside a
first-difference "noise" of 12 % and no word of the sparse grid, where `impedax kk` warned).

Oracles: SYNTHETIC exact spectra 100 Ω + 1 kΩ/(1 + jωτ) written here with numpy, whose τ is
known; the points a decade counted by hand (N / decades); the six-point instrument fixture,
whose points follow 100 Ω + 1 kΩ ∥ 1 µF (τ = 1 ms) to its 5 digits.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.drt.result import SPARSE_POINTS_PER_DECADE

FIXTURES = Path(__file__).parent / "fixtures"


def rc(n: int, tau: float) -> tuple[np.ndarray, np.ndarray]:
    """SYNTHETIC: 100 Ω + 1 kΩ/(1 + jωτ) at ``n`` frequencies over 1 Hz–100 kHz (5 decades)."""
    f = np.logspace(0, 5, n)
    return f, 100.0 + 1000.0 / (1 + 2j * np.pi * f * tau)


def main_peak(result):
    return max(result.peaks, key=lambda p: p.r_ohm)


@pytest.mark.parametrize("tau", [3e-4, 1e-3, 3e-3])
def test_six_points_over_five_decades_warn_and_the_warning_is_earned(tau):
    r = ix.drt(rc(6, tau))
    assert r.points_per_decade == pytest.approx(6 / 5)
    (warning,) = [w for w in r.warnings if w.startswith("sparse data")]
    assert "1.2 points a decade" in warning and f"{r.rms_rel * 100:.3g} %" in warning
    # what it warns of: exact data, yet a misfit of several % that the first differences call noise
    assert r.rms_rel > 0.03 and r.difference_noise > 0.02
    assert main_peak(r).tau_s / tau > 1.2  # τ long (30–50 %), as the warning says


@pytest.mark.parametrize("n", [11, 26, 51])
def test_two_points_a_decade_and_more_do_not_warn(n):
    r = ix.drt(rc(n, 1e-3))
    assert r.points_per_decade >= SPARSE_POINTS_PER_DECADE
    assert r.sparse_warning is None and not any(w.startswith("sparse data") for w in r.warnings)
    assert main_peak(r).tau_s == pytest.approx(1e-3, rel=0.06)


def test_the_six_point_instrument_file_warns_and_the_batch_report_says_it_once():
    r = ix.drt(FIXTURES / "zplot_sweep.z")
    assert r.sparse_warning and r.sparse_warning in r.summary()["warnings"]
    f, z = rc(6, 1e-3)
    batch = ix.drt((f, np.stack([z, z * 1.01])))
    assert batch.report().count("warning: sparse data") == 1
    assert all(one.sparse_warning for one in batch.results)


def test_one_point_a_decade_counts_as_the_kk_test_counts():
    """N / decades, as `impedax kk`'s sparse note counts (not (N − 1) / decades)."""
    f, z = rc(6, 1e-3)
    assert ix.drt((f, z)).points_per_decade == pytest.approx(len(f) / math.log10(f.max() / f.min()))
