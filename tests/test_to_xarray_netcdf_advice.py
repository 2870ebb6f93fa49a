"""`FitResult.to_xarray()` and `BatchFitResult.to_xarray()` hold complex Z and Python-object
attrs (dicts of warnings, bounds, groups), which netCDF cannot store: ``ds.to_netcdf(path)``
refuses them, and its error says to write the result with ``impedax.write_result`` (or the
Dataset with ``impedax.io.write_netcdf``), for both alike. The file `write_result` writes reads
back with xarray to the same values. SYNTHETIC R0 + R1 ∥ C1 spectra, exact and 1 % off."""

import numpy as np
import pytest
import xarray as xr

import impedax as ix

F = np.geomspace(1.0, 1e5, 21)
Z = 10 + 100 / (1 + 1j * 2 * np.pi * F * 100e-6)


@pytest.fixture(scope="module")
def single():
    return ix.fit("R0 + R1 || C1", ix.make_spectrum(F, Z), progress=False)


@pytest.fixture(scope="module")
def batch():
    return ix.fit("R0 + R1 || C1", ix.make_spectrum(F, np.stack([Z, Z * 1.01]), dims=("trial",)), progress=False)


@pytest.mark.parametrize("which", ["single", "batch"])
def test_to_netcdf_error_names_write_result(which, request, tmp_path):
    ds = request.getfixturevalue(which).to_xarray()
    path = tmp_path / "x.nc"
    with pytest.raises(TypeError) as caught:
        ds.to_netcdf(path)
    assert "impedax.write_result(" in str(caught.value) and "impedax.io.write_netcdf(" in str(caught.value), str(caught.value)


@pytest.mark.parametrize("which", ["single", "batch"])
def test_the_advice_changes_no_attr_value(which, request):
    ds = request.getfixturevalue(which).to_xarray()
    for key, value in ds.attrs.items():
        if isinstance(value, dict):
            assert value == dict(value) and str(value) == repr(dict(value)), key  # (the Dataset's display is the dict's)


@pytest.mark.parametrize("which", ["single", "batch"])
def test_write_result_reads_back_with_xarray(which, request, tmp_path):
    result = request.getfixturevalue(which)
    ds = result.to_xarray()
    path = tmp_path / "x.nc"
    ix.write_result(result, str(path))
    with xr.open_dataset(path) as back:
        np.testing.assert_array_equal(back["value"].values, ds["value"].values)
        np.testing.assert_array_equal(back["Z__real"].values + 1j * back["Z__imag"].values, ds["Z"].values)
        assert list(back["param"].values) == list(ds["param"].values)
    again = type(result).from_xarray(xr.open_dataset(path))  # (as stored: from_xarray joins the parts)
    np.testing.assert_array_equal(again.to_xarray()["Z_model"].values, ds["Z_model"].values)
