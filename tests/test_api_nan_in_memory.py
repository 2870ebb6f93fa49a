"""A NaN in Z of data built in Python is answered in Python: which frequency and point, and the
call that leaves it out, not "leave that point out of the file". Both ways in: arrays (given to
``ix.make_spectrum``, or as a (frequency, Z) pair to ``ix.fit``), and an xarray Dataset passed to
``ix.fit`` (one built by make_spectrum and masked afterwards, and one built with xarray alone). Each remedy, run as the message words it,
gives data that fit and recover the RC's values. A file's NaN keeps the file's advice (a netCDF
file written with plain xarray). SYNTHETIC: R0 + R1 ∥ C1 written out with numpy."""

import re

import numpy as np
import pytest
import xarray as xr

import impedax as ix

RC = "R0 + R1 || C1"
FREQ = np.geomspace(1.0, 1e5, 31)


def rc_impedance(freq, r1=1e3):
    return 10.0 + r1 / (1 + 2j * np.pi * np.asarray(freq) * r1 * 1e-6)


def _masked(index=3):
    z = rc_impedance(FREQ)
    z[index] = np.nan
    return z


@pytest.mark.parametrize("given", ["make_spectrum", "pair"])
def test_arrays_name_the_point_and_the_python_that_leaves_it_out(given):
    frequency, Z = FREQ, _masked()
    with pytest.raises(ix.DataError) as info:
        ix.make_spectrum(frequency, Z) if given == "make_spectrum" else ix.fit(RC, (frequency, Z))
    text = str(info.value)
    assert text.startswith(f"in-memory data: Z has a non-finite value at f={FREQ[3]:.3g} Hz (point 3): (nan+0j); ")
    assert "file" not in text
    remedy = "keep = np.isfinite(Z); frequency, Z = frequency[keep], Z[keep]"
    assert text.endswith(f"leave that point out of the arrays: {remedy}"), text
    keep = np.isfinite(Z)  # (the remedy as worded)
    frequency, Z = frequency[keep], Z[keep]
    fitted = ix.fit(RC, ix.make_spectrum(frequency, Z) if given == "make_spectrum" else (frequency, Z))
    assert fitted.params["R1"] == pytest.approx(1e3, rel=1e-6)


def test_a_stack_of_arrays_names_the_spectrum_and_how_to_leave_the_frequency_out():
    frequency = FREQ
    Z = np.stack([rc_impedance(FREQ), rc_impedance(FREQ, r1=2e3)])
    Z[1, 3] = np.nan
    with pytest.raises(ix.DataError) as info:
        ix.make_spectrum(frequency, Z, dims="cycle")
    text = str(info.value)
    assert text.startswith(f"in-memory data: Z has a non-finite value at cycle #1, f={FREQ[3]:.3g} Hz (point 3): (nan+0j); ") and "file" not in text
    remedy = "keep = np.isfinite(Z).all(axis=tuple(range(Z.ndim - 1))); frequency, Z = frequency[keep], Z[..., keep], or that spectrum out of Z"
    assert remedy in text and text.endswith("not padded with NaN to one grid"), text
    keep = np.isfinite(Z).all(axis=tuple(range(Z.ndim - 1)))
    frequency, Z = frequency[keep], Z[..., keep]
    fitted = ix.fit(RC, ix.make_spectrum(frequency, Z, dims="cycle"))
    np.testing.assert_allclose(fitted.to_xarray()["value"].sel(param="R1").values, [1e3, 2e3], rtol=1e-6)


@pytest.mark.parametrize("built", ["make_spectrum", "xarray"])
def test_a_dataset_passed_to_fit_is_answered_with_dropna(built):
    clean = ix.make_spectrum(FREQ, rc_impedance(FREQ)) if built == "make_spectrum" else xr.Dataset({"Z": ("frequency", rc_impedance(FREQ))}, coords={"frequency": FREQ})
    ds = clean.assign(Z=("frequency", _masked(5)))
    with pytest.raises(ix.DataError) as info:
        ix.fit(RC, ds)
    text = str(info.value)
    where = "in-memory data" if built == "make_spectrum" else "dataset"
    assert text == f"{where}: Z has a non-finite value at f={FREQ[5]:.3g} Hz (point 5): (nan+0j); ds.dropna('frequency') leaves it out", text
    assert ds.dropna("frequency").sizes["frequency"] == 30
    assert ix.fit(RC, ds.dropna("frequency")).params["R1"] == pytest.approx(1e3, rel=1e-6)


def test_a_files_nan_keeps_the_files_advice(tmp_path):
    path = tmp_path / "masked.nc"
    ds = xr.Dataset({"Z": ("frequency", _masked())}, coords={"frequency": FREQ})
    ds["Z__real"], ds["Z__imag"] = ds["Z"].real, ds["Z"].imag
    ds.drop_vars("Z").to_netcdf(path)
    with pytest.raises(ix.DataError, match=re.escape("(point 3): (nan+0j); leave that point out of the file")):
        ix.load(path)
