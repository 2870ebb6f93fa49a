"""The EDL fit of the trial-mean remainder is weighted by the trial means' SEM, which holds the
contact's variation between trials: residuals far below it are expected, and gap does not warn
that σ overstates the noise (a walkthrough saw that warning on SYNTHETIC data that match the
model exactly). Where σ is the stated noise, the warning stays. No sampling here."""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.least_squares.result import SIGMA_OF_TRIAL_MEANS_WORDS, SIGMA_OVERSTATES_WORDS
from impedax.models.gap import _edl_chi2_text, _edl_fit_warnings
from impedax.models.sirin import remaining_impedance
from impedax.models.synthetic import example_spectra, generate_sirin_synthetic

EDL = "R_EP || CPE_EP || C_gap"


@pytest.fixture(scope="module")
def seed_one():
    """The SYNTHETIC Sirin example of seed 1 (numpy formulas), its trial-mean remainder and the EDL fit weighted by its SEM."""
    parts = example_spectra(generate_sirin_synthetic(seed=1))
    remaining = remaining_impedance(parts["total_sliding"], parts["skin"], parts["touchscreen"])
    return remaining, ix.fit(EDL, remaining, weighting="sigma")


def test_the_sem_exceeds_the_residuals_because_the_trials_differ(seed_one):
    remaining, edl = seed_one
    assert remaining.attrs["n_trials_total"] == 30
    assert edl.chi2_red < 0.3  # (0.133: the SEM holds the trials' variation, which the fit of the mean absorbs)
    assert any(SIGMA_OF_TRIAL_MEANS_WORDS in w for w in edl.warnings)  # (the fit says what its σ is, from the attrs; "σ overstates the noise" until 2026-12-06)


def test_gap_leaves_the_overstated_sigma_warning_out_and_says_why(seed_one):
    remaining, edl = seed_one
    kept = _edl_fit_warnings(edl, remaining)
    assert not any(SIGMA_OVERSTATES_WORDS in w for w in kept)
    assert len(kept) == len(edl.warnings) - 1 and all(w.startswith("EDL fit: ") for w in kept)
    text = _edl_chi2_text(edl, remaining)
    assert f"χ²_red {edl.chi2_red:.3g}" in text and "below 1 as expected" in text and "variation between trials" in text


def test_a_sigma_that_is_stated_noise_keeps_the_warning():
    """Nothing varies between trials here: one SYNTHETIC R_EP ∥ CPE_EP ∥ C_gap spectrum (numpy
    formula, the example's true values) with σ stated 3× the noise actually added."""
    f = np.geomspace(1.0, 1e6, 61)
    z = 1.0 / (1.0 / 1e8 + 4e-9 * (2j * np.pi * f) ** 0.30 + 2j * np.pi * f * 413e-12)
    noise = 0.005 * np.abs(z)
    rng = np.random.default_rng(3)
    data = ix.make_spectrum(f, z + noise * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)), sigma=3 * noise)
    edl = ix.fit(EDL, data, weighting="sigma")
    assert any(SIGMA_OVERSTATES_WORDS in w for w in _edl_fit_warnings(edl, data))  # (no n_trials_total: σ is no SEM of trials)
    assert _edl_chi2_text(edl, data) == ""
