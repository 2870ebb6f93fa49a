"""A failing band whose misfit is a point the KK test flags is the data's problem, not the model's.

REAL BioLogic file with `R0 + R1 || C1` (2026-12-06 walkthrough): the band 49.3–83.3 Hz was a
6.7σ spike at 56.2 Hz, which the KK test flags, and one point at 1.04σ; the report counted it
as the model's failure ("structured in 2 band(s)") and the figure shaded it "model fails". The
SYNTHETIC cases write their residuals directly (model = data × (1 + r)), so the χ² sums below
are computed by hand: a run's points at e = r/σ."""

import types
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis.bands import RUN_P, chi2_quantile, failing_bands

REAL = Path(__file__).parent / "fixtures" / "real"
SIGMA = 0.01
F = np.logspace(0, 4, 41)  # (10 points a decade: the point at 100 Hz is index 20)


def fake_fit(errors_re: np.ndarray) -> types.SimpleNamespace:
    """Data 1 Ω, resistive; the model off by ``errors_re`` × σ in Re (relative residuals)."""
    z_data = np.ones(F.size, complex)
    z_model = z_data * (1 + errors_re * SIGMA)
    return types.SimpleNamespace(frequency=F, z_data=z_data, z_model=z_model, residuals=(z_model - z_data) / np.abs(z_data))


def spike(rest: dict[int, float]) -> np.ndarray:
    """A 7σ spike at 100 Hz (index 20) with ``rest`` (index → e) beside it, zeros elsewhere."""
    e = np.zeros(F.size)
    e[20] = 7.0
    for k, v in rest.items():
        e[k] = v
    return e


KK_BAD = [(90.0, 110.0)]  # (flags the spike's point alone)


def test_a_flagged_spike_with_a_neighbour_at_the_noise_is_a_data_problem():
    # run 19..22 of one sign: Σe² = 0.5² + 49 + 1.1² + 0.3² ≫ χ²(4, 0.999) = 18.5, so a band
    # (trimmed to |e| ≥ 1: points 20 and 21); without the spike, 1.1² = 1.21 ≤ χ²(1, 0.999) = 10.8
    e = spike({19: 0.5, 21: 1.1, 22: 0.3})
    (band,) = failing_bands(fake_fit(e), SIGMA)
    assert band.data_problem is False  # (nothing flagged: the model's, as before)
    (band,) = failing_bands(fake_fit(e), SIGMA, kk_bad_bands=KK_BAD)
    assert band.f_min < 100 < band.f_max and band.data_problem is True
    assert 1.1**2 <= chi2_quantile(1 - RUN_P, 1)


def test_a_band_structured_without_its_flagged_point_stays_the_models():
    # the spike and four points at 3σ of its sign: without the spike Σe² = 4 × 9 = 36 > χ²(4, 0.999) = 18.5
    e = spike({21: 3.0, 22: 3.0, 23: 3.0, 24: 3.0})
    (band,) = failing_bands(fake_fit(e), SIGMA, kk_bad_bands=KK_BAD)
    assert band.data_problem is False and 4 * 9.0 > chi2_quantile(1 - RUN_P, 4)


def test_a_band_wholly_inside_a_flagged_band_is_a_data_problem_as_before():
    e = spike({21: 5.0, 19: 5.0})
    (band,) = failing_bands(fake_fit(e), SIGMA, kk_bad_bands=[(70.0, 140.0)])
    assert band.data_problem is True


def test_a_flagged_band_elsewhere_leaves_the_models_band_alone():
    e = spike({19: 0.5, 21: 1.1, 22: 0.3})
    (band,) = failing_bands(fake_fit(e), SIGMA, kk_bad_bands=[(1.0, 10.0)])
    assert band.data_problem is False


@pytest.mark.slow
def test_biologic_spike_band_is_tagged_the_datas_problem():
    """REAL exampleDataBioLogic.mpt: the KK test flags 5.34, 56.2, 123 and 270 Hz (kept in every
    fit); the band around 56.2 Hz is the data's, the low-frequency band 342 mHz–3.6 Hz (the
    missing CPE) stays the model's, and the verdict counts one band."""
    d = ix.diagnose(ix.load(REAL / "exampleDataBioLogic.mpt"), "R0 + R1 || C1")
    by_edge = {round(b.f_min, 1): b for b in d.failing_bands}
    spike_band = next(b for b in d.failing_bands if b.f_min < 56.2 < b.f_max)
    low = next(b for b in d.failing_bands if b.f_min < 1.0 < b.f_max)
    assert spike_band.data_problem and not low.data_problem, by_edge
    assert d.verdict == "missing_effect" and "structured in 1 band" in d.reason
    assert "[data problem: the KK test flags the data behind this misfit]" in d.report()
