"""A result with a dimension of length 0 (a KK test with no bad band, a DRT batch with no peak)
writes a netCDF file that every reader opens and that reads back whole (io.netcdf's
``impedax_empty``). netCDF3 holds a zero-length dimension only as its one record dimension,
first in each variable: a KK batch's (cell, band) bad bands wrote a file that neither xarray nor
impedax opened, and `read_netcdf` refused any empty dimension ("the file holds no spectrum")
even in a saved KK test. Spectra: SYNTHETIC closed forms."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.errors import DataError

FREQ = np.geomspace(0.1, 1e5, 41)
RC = 10 + 100 / (1 + 2j * np.pi * FREQ * 1e-3)  # SYNTHETIC R0 + R‖C, KK-consistent: no bad band
STACK = ix.make_spectrum(FREQ, np.stack([RC, 1.1 * RC]), dims=("cell",))


def _same(read: xr.Dataset, written: xr.Dataset) -> None:
    """Every variable of ``written`` in ``read``: dims, shape, dtype, values and attrs."""
    for name, var in {**written.coords, **written.data_vars}.items():
        got = read[name]
        assert got.dims == var.dims and got.shape == var.shape and got.dtype == var.dtype, (name, got.dims, got.shape, got.dtype)
        np.testing.assert_array_equal(got.values, var.values)
        assert got.attrs == var.attrs, name


@pytest.mark.parametrize("result", [ix.kk_test((FREQ, RC)), ix.kk_test_batch(STACK), ix.drt(ix.make_spectrum(FREQ, np.full((2, FREQ.size), 50.0 + 0j), dims=("cell",)))],
                         ids=["kk", "kk-batch", "drt-batch-of-resistors"])
def test_a_result_with_an_empty_dimension_reads_back_whole(result, tmp_path):
    written = result.to_xarray()
    assert 0 in written.sizes.values()  # (the case: no bad band, or no peak in any spectrum)
    path = tmp_path / "result.nc"
    ix.write_result(result, path)
    with xr.open_dataset(path, engine="scipy") as plain:  # (any netCDF3 reader opens it)
        assert set(written.data_vars) <= {n.removesuffix("__real").removesuffix("__imag") for n in plain.data_vars}
    _same(ix.io.read_netcdf(path), written)


def test_two_empty_dimensions_and_every_dtype(tmp_path):
    """netCDF3 has one record dimension: two empty ones, a complex, a bool and an int64
    variable of no values, and an empty coordinate, beside full variables."""
    ds = xr.Dataset(
        {"z": (("cell", "band"), np.zeros((2, 0), complex)), "flag": (("peak",), np.zeros(0, bool), {"long_name": "x"}),
         "n": (("band", "cell"), np.zeros((0, 2), np.int64)), "full": (("cell",), np.array([1.5, 2.5]))},
        coords={"cell": [3, 4], "peak": ("peak", np.zeros(0))},
        attrs={"note": "two empty"},
    )
    path = tmp_path / "two.nc"
    ix.io.write_netcdf(ds, path)
    read = ix.io.read_netcdf(path)
    _same(read, ds)
    assert read.attrs["note"] == "two empty"


def test_a_spectrum_over_an_empty_dimension_is_still_refused(tmp_path):
    path = tmp_path / "none.nc"
    ix.io.write_netcdf(xr.Dataset({"Z": (("trial", "frequency"), np.zeros((0, 3), complex))}, coords={"frequency": [1.0, 10.0, 100.0]}), path)
    with pytest.raises(DataError, match="dimension 'trial' has length 0: the file holds no spectrum"):
        ix.io.read_netcdf(path)


def test_a_damaged_empty_mark_is_a_data_error(tmp_path):
    path = tmp_path / "bad.nc"
    xr.Dataset({"v": ((), 0.0, {"impedax_empty": 'json:[["cell", 2], ["band", 3]]', "impedax_dtype": "float64"})}).to_netcdf(path, engine="scipy")
    with pytest.raises(DataError, match="gives 6 values where it marks a variable of none"):
        ix.io.read_netcdf(path)
