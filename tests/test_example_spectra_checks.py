"""`impedax.models.example_spectra` and `sirin_trial_remainders` refuse what is not the SYNTHETIC
example with one `DataError` saying what it lacks (until 2026-12-06 a KeyError or TypeError from
inside xarray or a dict, which the public API promises never to raise)."""

import numpy as np
import pytest

import impedax as ix
from impedax.models import example_spectra
from impedax.models.synthetic import generate_sirin_synthetic, sirin_trial_remainders


@pytest.fixture(scope="module")
def small():
    return generate_sirin_synthetic(trials=2, points=5)


def test_a_spectrum_is_no_example():
    spectrum = ix.make_spectrum([1.0, 10.0], np.array([1 - 1j, 1 - 2j]))
    with pytest.raises(ix.DataError) as caught:
        example_spectra(spectrum)
    assert str(caught.value) == ("example_spectra: ds is not the SYNTHETIC example (impedax.models.load_example() or generate_sirin_synthetic()): "
                                 "no variable 'Z_total'; its variables: Z (a spectrum: analyse its Z as it is)")


def test_what_the_example_lacks_is_named(small):
    with pytest.raises(ix.DataError, match="no variable 'Z_skin'; its variables: Z_total, Z_touchscreen"):
        example_spectra(small.drop_vars("Z_skin")[["Z_total", "Z_touchscreen"]])
    with pytest.raises(ix.DataError, match=r"Z_total has no contact 'stationary' \(its contacts: sliding\)$"):
        example_spectra(small.sel(contact=["sliding"]))
    with pytest.raises(ix.DataError, match="ds must be the example Dataset .* got str"):
        example_spectra("sirin")


def test_the_example_itself_is_taken_apart(small):
    parts = example_spectra(small)
    assert list(parts) == ["total_sliding", "total_stationary", "skin", "touchscreen"]
    np.testing.assert_array_equal(parts["skin"]["Z"].values, small["Z_skin"].transpose("session", "trial", "frequency").values)


def test_an_unknown_contact_is_named(small):
    with pytest.raises(ix.DataError, match="contact must be 'sliding' or 'stationary' .* got 'standing'"):
        sirin_trial_remainders(small, "standing")
