"""`ix.compare` of fits it cannot rank together (of different spectra or weightings, fits of one
spectrum mixed with batches, none) is bad input: a `ValueError` as every other argument error of
the Python API (and a `FitError`, the class these messages have), naming the fits and what differs.
SYNTHETIC spectra written with numpy."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.errors import FitError

RC = "R0 + R1 || C1"


def _spectrum(r1: float = 100.0, n: int = 21) -> xr.Dataset:
    """R0 + R1 ∥ C1 written out with numpy, 1 Hz–100 kHz, no noise."""
    f = np.geomspace(1.0, 1e5, n)
    z = 10.0 + r1 / (1.0 + 2j * np.pi * f * r1 * 1e-5)
    return ix.make_spectrum(f, z)


@pytest.fixture(scope="module")
def fits():
    data = _spectrum()
    return {
        "modulus": ix.fit(RC, data, n_starts=1),
        "unit": ix.fit(RC, data, n_starts=1, weighting="unit"),
        "other": ix.fit(RC, _spectrum(r1=120.0), n_starts=1),
    }


def test_fits_of_different_weightings_are_a_value_error_naming_both(fits):
    with pytest.raises(ValueError) as caught:
        ix.compare([fits["modulus"], fits["unit"]])
    assert isinstance(caught.value, FitError)
    text = str(caught.value)
    assert "fits[0] (R0 + R1 || C1, weighting 'modulus') and fits[1] (R0 + R1 || C1, weighting 'unit')" in text
    assert "different weightings" in text and "unit, modulus, proportional, sigma" in text


def test_fits_of_different_data_are_a_value_error(fits):
    with pytest.raises(ValueError, match=r"fits\[0\] and fits\[1\] \(both R0 \+ R1 \|\| C1\) were fitted to different data: the same 21 frequencies, but Z differs") as caught:
        ix.compare([fits["modulus"], fits["other"]])
    assert isinstance(caught.value, FitError)


def test_no_fits_is_a_value_error():
    with pytest.raises(ValueError, match="compare needs at least one fit"):
        ix.compare([])


def test_batches_mixed_with_single_fits_are_value_errors_and_one_batch_alone_is_compared(fits):
    batch = ix.fit(RC, xr.concat([_spectrum(), _spectrum()], dim="trial"), n_starts=1)
    with pytest.raises(ValueError, match=r"fits\[0\] is a BatchFitResult of 2 spectra, fits\[1\] a fit of one spectrum"):
        ix.compare([batch, fits["modulus"]])
    assert ix.compare([batch]).labels == [RC]  # (one batch: a comparison of one model, as one fit gives)
