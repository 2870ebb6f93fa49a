"""The DRT after a walkthrough (2026-12-01): the L-curve on exact data floors λ instead of
failing and blaming the data; peaks whose R the credible band does not tell from zero are
listed but flagged and not counted; the misfit warning compares rms_rel with the noise; a
batch counts only resolved peaks inside the measured τ window and prints τ as the single
report does. Oracles: numpy formulas of R‖C spectra written here (SYNTHETIC), the 2-sd rule
applied by hand to each peak's R and sd, and hand numbers (1/(2π f) of the grid's ends).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import impedax as ix
from impedax.errors import ParameterError
from impedax.fitting.drt import _drt
from impedax.fitting.drt.result import DRTBatchResult

FREQ = np.logspace(-2, 5, 71)  # 10 mHz–100 kHz, 10 points per decade
OMEGA = 2 * np.pi * FREQ


def rc_spectrum(tau=1e-3, r=100.0, r_inf=10.0):
    """SYNTHETIC: R_inf + R/(1 + jωτ) at FREQ."""
    return r_inf + r / (1 + 1j * OMEGA * tau)


def noisy(z, level, seed):
    """SYNTHETIC: Z·(1 + s(n₁ + j n₂)), relative noise of ``level`` on each part."""
    rng = np.random.default_rng(seed)
    return z * (1 + level * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)))


@pytest.mark.parametrize("level", [0.0, 1e-4])
def test_lcurve_on_exact_data_gives_the_floored_lambda_and_says_why(level):
    """It failed with "non-finite solution: check the data": the curvature's maximum sat next
    to a −inf end of the grid and the parabola through it was NaN."""
    r = ix.drt((FREQ, noisy(rc_spectrum(), level, 1)), lam_method="lcurve")
    assert r.lam == pytest.approx(1e-4)  # the floor GCV uses
    assert "raised to the floor" in r.lambda_note and "no corner" in r.lambda_note
    assert len(r.peaks) == 1
    assert r.peaks[0].r_ohm == pytest.approx(100.0, rel=0.01)
    assert r.peaks[0].tau_s == pytest.approx(1e-3, rel=0.1)


def test_a_non_finite_automatic_solve_names_the_solve_not_the_data():
    x = np.array([[1.0, math.nan]])
    with pytest.raises(ParameterError) as info:
        _drt._check_finite(x, None, "rc.csv", np.array([1e-4]), "lcurve")
    text = str(info.value)
    assert "not of the data" in text and "check the data" not in text
    assert "lam_method='gcv'" in text and "λ = 0.0001" in text


@pytest.mark.parametrize("seed", [200, 205, 209])
def test_one_rc_at_5_percent_noise_counts_one_peak(seed):
    """Seeds 205 and 209 showed a second peak, 6.3 ± 5.2 Ω at 10.5 s and 9.9 ± 8.1 Ω at 53 s,
    that the report counted as an arc ("2 peak(s)")."""
    r = ix.drt((FREQ, noisy(rc_spectrum(), 0.05, seed)))
    for p in r.peaks:  # the 2-sd rule, by hand
        assert p.resolved == (abs(p.r_ohm) >= 2 * p.r_ohm_sd)
    summary = r.summary()
    assert summary["n_resolved_peaks"] == 1
    assert [p["resolved"] for p in summary["peaks"]] == [p.resolved for p in r.peaks]
    assert "\n1 peak(s)" in r.report()
    (main,) = [p for p in r.peaks if p.resolved]
    assert main.r_ohm == pytest.approx(100.0, rel=0.03)
    if len(r.peaks) > 1:
        assert "not told from zero" in r.report()
    # the misfit is the noise: √2 × 5 % on the complex residual, no KK warning
    assert 0.06 < r.rms_rel < 0.09
    assert not any("reproduces the data" in w for w in r.warnings)


def test_a_drift_in_re_z_keeps_the_misfit_warning():
    """SYNTHETIC non-KK data: Re Z grows by 110 Ω × f_min/f (a drift during the slow
    points, with no Im part), at 1 % noise: rms_rel ≈ 7.5 % against a first-difference noise of
    ≈ 1 %, so the misfit is not the noise."""
    z = noisy(rc_spectrum(), 0.01, 0) + 110.0 * FREQ.min() / FREQ
    r = ix.drt((FREQ, z))
    assert r.rms_rel > 0.05 and r.rms_rel > 3 * math.sqrt(2) * r.difference_noise
    assert any("reproduces the data to only" in w and "more than the noise explains" in w for w in r.warnings)


def test_a_batch_counts_resolved_peaks_inside_the_window_and_shades_the_rest():
    """Two SYNTHETIC spectra: an R‖C at 1 ms or 167 µs plus one at τ = 50 s, beyond the window's
    1/(2π · 10 mHz) = 15.9 s: 2 peaks listed each, 1 counted."""
    # the batch of two single solves (the same numbers as one batched solve, without compiling
    # the solve again for a batch of two)
    z = [rc_spectrum(1e-3) + rc_spectrum(50.0, 50.0, 0.0), rc_spectrum(1.67e-4) + rc_spectrum(50.0, 50.0, 0.0)]
    batch = DRTBatchResult(dims=("dim_0",), shape=(2,), coords={}, results=tuple(ix.drt((FREQ, one)) for one in z))
    assert batch.n_peaks.tolist() == [2, 2]  # unchanged meaning: every listed peak
    assert batch.n_resolved_peaks.tolist() == [1, 1]
    text = batch.report()
    assert text.splitlines()[0].startswith("DRT of 2 spectra over dim_0: 2 with 1 peak(s) (resolved, inside the measured τ window;")
    assert "171 µs (100 Ω)" in text and "0.000171 s" not in text  # the single report's formatter
    fig = batch.plot()
    try:
        assert "1 peak in the measured τ range" in fig._suptitle.get_text()
        spans = sorted((p.get_x(), p.get_x() + p.get_width()) for p in fig.axes[0].patches)
        assert spans[0][1] == pytest.approx(1 / (2 * math.pi * 1e5))
        assert spans[1][0] == pytest.approx(1 / (2 * math.pi * 1e-2))
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)
