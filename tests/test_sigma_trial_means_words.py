"""The words by which a fit by σ names a remainder's σ, the standard error of trial means: with 30
total trials and skin and screen of one spectrum each, which gave their stated σ, the note read
"σ is the standard error of trial means (30 total, 1 skin, 1 touchscreen spectra)", as if skin and
screen were means of one trial each; it now names them by provenance, as
`diagnosis.noise.sigma_origin` does. SYNTHETIC spectra from numpy formulas written here."""

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.least_squares.result import trial_means_of_sigma
from impedax.models.sirin import remaining_impedance

F = np.geomspace(1.0, 1e5, 40)
W = 2 * np.pi * F
Z_SKIN = 1e4 / (1 + 1j * W * 1e4 * 1e-8)  # R ∥ C, 10 kΩ and 10 nF
Z_TS = np.full(F.size, 2e3 + 0j)  # the screen's 2 kΩ


def _gap(scale):
    """R_EP ∥ C_gap, 10 MΩ and 400 pF × ``scale`` (the contact from touch to touch)."""
    return 1 / (1 / 1e7 + 1j * W * 4e-10 * scale)


def _trials(z_of_trial, n, rng):
    z = np.stack([z_of_trial(rng) for _ in range(n)])
    return ix.make_spectrum(F, z * (1 + 0.002 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape))), dims=("trial",))


def _remainder(skin_trials, screen_trials, seed=3):
    rng = np.random.default_rng(seed)
    total = _trials(lambda r: _gap(np.exp(0.05 * r.standard_normal())) + Z_SKIN + Z_TS, 30, rng)
    parts = []
    for z, n in ((Z_SKIN, skin_trials), (Z_TS, screen_trials)):
        parts.append(ix.make_spectrum(F, z, sigma=0.01 * np.abs(z)) if n == 1 else _trials(lambda r, z=z: z, n, rng))
    return remaining_impedance(total, *parts)


def test_stated_sigma_of_single_spectra_is_named_as_such_not_counted_as_trial_means():
    rem = _remainder(1, 1)
    assert trial_means_of_sigma(rem.attrs) == "30 total spectra, and the stated sigma of skin and touchscreen (one spectrum each), added in quadrature"
    assert trial_means_of_sigma(_remainder(1, 30).attrs) == "30 total, 30 touchscreen spectra, and the stated sigma of skin (one spectrum), added in quadrature"
    assert trial_means_of_sigma(_remainder(30, 30).attrs) == "30 total, 30 skin, 30 touchscreen spectra"  # (every σ a SEM: as before)
    # the fit's note: residuals far below σ (the trials' 5 % spread of C_gap in the SEM, taken up by the fit of the mean)
    fitted = ix.fit("R_EP || C_gap", rem, weighting="sigma")
    (note,) = [w for w in fitted.warnings if "σ is the standard error of trial means" in w and "× the data's sigma in rms" in w]
    assert "(30 total spectra, and the stated sigma of skin and touchscreen (one spectrum each), added in quadrature; the data's sigma_method)" in note
    assert "1 skin" not in note and "1 touchscreen" not in note



def test_a_total_of_one_spectrum_less_means_of_trials_is_no_sigma_of_trial_means():
    """A total of one spectrum with its stated σ, less skin and screen means over 30 trials each:
    σ holds no variation of the contact between touches, and is mostly the total's stated σ (here
    by construction: 0.02 % of |Z_total| against skin and screen means of a 5 % spread over 30
    trials), so the fit's general note (σ overstates the noise) stands and no trial-means words
    replace it. 3a1af1ea named it trial means (2026-12-06), which this reverts."""
    rng = np.random.default_rng(8)
    z_total = _gap(1.0) + Z_SKIN + Z_TS
    stated = 0.0002 * np.abs(z_total)
    total = ix.make_spectrum(F, z_total, sigma=stated)
    skin, screen = (_trials(lambda r, z=z: z * np.exp(0.05 * r.standard_normal()), 30, rng) for z in (Z_SKIN, Z_TS))
    rem = remaining_impedance(total, skin, screen)
    assert np.median(stated**2 / rem["sigma"].values ** 2) > 0.9  # (σ² mostly the total's stated σ²)
    assert trial_means_of_sigma(rem.attrs) is None
    # a remainder saved before 2026-12-06 (no sigma_sources): its sigma_method's words, as that code wrote them
    old = {"sigma_method": "SEM of Re and Im over the trials of skin and touchscreen; the stated sigma of total (one spectrum), added in quadrature; "
                           "sigma = sqrt((sigma_real^2 + sigma_imag^2)/2)", "n_trials_total": 1, "n_trials_skin": 30, "n_trials_touchscreen": 30}
    assert trial_means_of_sigma(old) is None
    assert trial_means_of_sigma({**old, "sigma_method": "SEM of Re and Im of each measurement over its trials, added in quadrature", "n_trials_total": 30}) == "30 total, 30 skin, 30 touchscreen spectra"
