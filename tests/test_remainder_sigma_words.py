"""What a remainder's σ is called in a diagnosis's noise line follows where it came from (SYNTHETIC
remainders of inputs whose error we chose: trials, a stated sigma, or both)."""

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis.noise import noise_model, sigma_origin
from impedax.models.sirin import remaining_impedance

from spectra import omega

FREQ = np.logspace(0, 6, 25)
RNG_SEED = 7


def _inputs():
    w = omega(FREQ)
    skin = 2e3 + 50e3 / (1 + 1j * w * 50e3 * 3e-9)
    screen = 500 + 1 / (1j * w * 1e-9)
    total = skin + screen + 1 / (1j * w * 400e-12 + 1 / 2e6)
    return {"total": total, "skin": skin, "touchscreen": screen}


def _spectrum(z, *, trials: int, rng):
    """``trials`` noisy copies of ``z`` (an extra dim), or one spectrum with a stated sigma of 1 % of |Z|."""
    sigma = 0.01 * np.abs(z)
    if trials > 1:
        noisy = z + sigma * (rng.standard_normal((trials, z.size)) + 1j * rng.standard_normal((trials, z.size)))
        return ix.make_spectrum(FREQ, noisy, dims=("trial",))
    return ix.make_spectrum(FREQ, z, sigma=sigma)


def _remainder(trials: dict[str, int]):
    rng = np.random.default_rng(RNG_SEED)
    z = _inputs()
    parts = {name: _spectrum(z[name], trials=trials[name], rng=rng) for name in trials}
    return remaining_impedance(parts["total"], parts.get("skin"), parts.get("touchscreen"))


@pytest.mark.parametrize(("trials", "words"), [
    # every input of trials: the standard error of their means, with the counts
    ({"total": 5, "skin": 4, "touchscreen": 3}, "the standard error of trial means of 5 total, 4 skin, 3 touchscreen spectra"),
    # one spectrum each with a stated sigma: no trial anywhere (until 2026-12-06: "trial scatter")
    ({"total": 1, "skin": 1, "touchscreen": 1}, "the stated sigma of total, skin and touchscreen, added in quadrature"),
    # trials of the total, a stated sigma for skin and screen
    ({"total": 5, "skin": 1, "touchscreen": 1}, "the standard error of the trial means of total and the stated sigma of skin and touchscreen, added in quadrature"),
    # a single contact (nothing subtracted): of one spectrum, or of trials
    ({"total": 1}, "the stated sigma of the one spectrum"),
    ({"total": 6}, "the standard error of trial means of 6 total spectra"),
])
def test_a_remainders_sigma_is_named_by_where_it_came_from(trials, words):
    remainder = _remainder(trials)
    assert "sigma" in remainder
    assert sigma_origin(remainder.attrs) == words
    model = noise_model(FREQ, remainder["Z"].values, noise=None, sigma=remainder["sigma"].values, kk=None, fallback_rms=0.01,
                        sigma_kind=sigma_origin(remainder.attrs))
    assert model.source == f"the data's sigma ({words})"
    assert ("trial" in model.source) == any(n > 1 for n in trials.values())


def test_a_sigma_column_and_a_trial_mean_keep_their_words():
    assert sigma_origin({"source": "edl.csv"}) == "sigma column"
    assert sigma_origin(None) == "sigma column"
    # a remainder without a sigma of its own whose data were given one afterwards: not the remainder's
    assert sigma_origin({"sigma_method": "not available: one remainder per total trial, as measured", "n_trials_total": 30}) == "sigma column"
    # sirin.trial_mean's attrs: of trials, or of one spectrum's own sigma
    assert sigma_origin({"n_trials": 5, "sigma_from": "trial scatter"}) == "the standard error of trial means"
    assert sigma_origin({"n_trials": 1, "sigma_from": "own sigma"}) == "the stated sigma of the one spectrum"
