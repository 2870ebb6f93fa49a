"""Every result's ``to_xarray()`` Dataset and netCDF (`impedax.io.netcdf.result_dataset`, one
mechanism for all): netCDF has no complex type nor dict attributes, so ``ds.to_netcdf(path)``
refuses a fit's, a KK test's, a DRT's, ... Dataset; its error names ``impedax.write_result`` (and
``impedax.io.write_netcdf``) and the call that reads the file back, for every kind alike, whatever
the user did to the Dataset (selected, copied, pickled, read back from the file). The Dataset
itself is written by ``impedax.write_result(ds, path)`` to the file the result writes. A Dataset
``to_netcdf`` can write (a comparison's criteria, a gap analysis's bands) is left as it is and
reads back equal. SYNTHETIC R0 + R1 ∥ C1 spectra, exact and 1 % off; the hierarchical posterior
and the gap analysis are built by hand (tests/test_hierarchical_new_session.py,
tests/test_gap_outputs.py). Every kind, with those that sample, diagnose or compare batches, is
in tests/test_netcdf_every_result_kind.py (slow)."""

import pickle

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.errors import ParameterError
from impedax.io.provenance import PROVENANCE_ATTRS
from test_gap_outputs import _stub as gap_stub
from test_hierarchical_new_session import by_hand

F = np.geomspace(1.0, 1e5, 21)
Z = 10 + 100 / (1 + 1j * 2 * np.pi * F * 100e-6)

# the call that reads each kind's file back, as the error must name it (docs/io.md, "Exporting results")
READER = {
    "fit": "impedax.FitResult.from_xarray(impedax.io.read_netcdf('fit.nc'))",
    "batch fit": "impedax.BatchFitResult.from_xarray(impedax.io.read_netcdf('batch_fit.nc'))",
    "kk": "impedax.io.read_netcdf('kk.nc')",
    "kk batch": "impedax.io.read_netcdf('kk.nc')",
    "zhit": "impedax.io.read_netcdf('zhit.nc')",
    "zhit batch": "impedax.io.read_netcdf('zhit.nc')",
    "drt": "impedax.io.read_netcdf('drt.nc')",
    "drt batch": "impedax.io.read_netcdf('drt.nc')",
    "hierarchical posterior": "impedax.HierarchicalPosterior.from_xarray(impedax.io.read_netcdf('hierarchical_posterior.nc'))",
}
WRITABLE = ["comparison", "gap analysis"]  # (no complex values, no dict attribute: xarray writes them)


@pytest.fixture(scope="module")
def results():
    one = ix.make_spectrum(F, Z)
    stack = ix.make_spectrum(F, np.stack([Z, Z * 1.01]), dims=("trial",))
    fit, fit_c = ix.fit("R0 + R1 || C1", one, progress=False), ix.fit("R0 + C1", one, progress=False)
    batch = ix.fit("R0 + R1 || C1", stack, progress=False)
    return {
        "fit": fit, "batch fit": batch, "kk": ix.kk_test(one), "kk batch": ix.kk_test_batch(stack), "zhit": ix.zhit(one), "zhit batch": ix.zhit_batch(stack),
        "drt": ix.drt(one), "drt batch": ix.drt(stack), "comparison": ix.compare([fit, fit_c]),
        "hierarchical posterior": by_hand(2), "gap analysis": gap_stub(),
    }


def _refusal(ds, path) -> str:
    with pytest.raises(TypeError) as caught:
        ds.to_netcdf(path)
    return str(caught.value)


@pytest.mark.parametrize("kind", READER)
def test_to_netcdf_error_names_the_writing_and_reading_calls(results, kind, tmp_path):
    message = _refusal(results[kind].to_xarray(), tmp_path / "x.nc")
    assert "impedax.write_result(" in message and "impedax.io.write_netcdf(" in message and READER[kind] in message, message
    assert not (tmp_path / "x.nc").exists()


@pytest.mark.parametrize("kind", ["fit", "kk", "drt batch"])
def test_the_advice_survives_what_a_user_does_to_the_dataset(results, kind, tmp_path):
    ds = results[kind].to_xarray()
    for edited in (ds.isel(frequency=slice(0, 5)), ds.copy(), ds.copy(deep=True), pickle.loads(pickle.dumps(ds)), ds.assign_attrs(note="mine"),
                   ds.drop_vars("Z")):
        assert READER[kind] in _refusal(edited, tmp_path / "x.nc")
    # read back from the file impedax wrote, Z complex again: the attribute (a plain dict now) names the calls
    ix.write_result(ds, tmp_path / "r.nc")
    assert READER[kind] in _refusal(ix.io.read_netcdf(tmp_path / "r.nc"), tmp_path / "x.nc")


@pytest.mark.parametrize("kind", [*READER, *WRITABLE])
def test_the_dataset_writes_as_the_result_does(results, kind, tmp_path):
    result = results[kind]
    ds = result.to_xarray()
    ix.write_result(result, tmp_path / "result.nc")
    ix.write_result(ds, tmp_path / "dataset.nc")
    from_result, from_dataset = ix.io.read_netcdf(tmp_path / "result.nc"), ix.io.read_netcdf(tmp_path / "dataset.nc")
    for name, var in ds.variables.items():
        for back in (from_result, from_dataset):
            assert back[name].dims == var.dims, name
            if var.dtype.kind in "OUS":  # (text: an object array may read back as fixed-width str)
                assert [str(v) for v in back[name].values.ravel()] == [str(v) for v in var.values.ravel()], name
            else:
                assert back[name].dtype == var.dtype, name
                np.testing.assert_array_equal(back[name].values, var.values, err_msg=name)  # (complex Z exact: its two parts as stored)
    kept = [{k: repr(v) for k, v in back.attrs.items() if k not in PROVENANCE_ATTRS} for back in (from_result, from_dataset)]  # (repr: NaN as NaN)
    assert kept[0] == kept[1]


@pytest.mark.parametrize("kind", WRITABLE)
def test_a_dataset_xarray_writes_is_left_as_it_is(results, kind, tmp_path):
    ds = results[kind].to_xarray()
    assert "netcdf" not in ds.attrs
    ds.to_netcdf(tmp_path / "plain.nc")
    back = ix.io.read_netcdf(tmp_path / "plain.nc")
    for name, var in ds.data_vars.items():
        np.testing.assert_array_equal(back[name].values, var.values, err_msg=name)


@pytest.mark.parametrize("which", ["fit", "batch fit"])
def test_the_advice_changes_no_attr_value(results, which):
    ds = results[which].to_xarray()
    for key, value in ds.attrs.items():
        if isinstance(value, dict):
            assert value == dict(value) and str(value) == repr(dict(value)), key  # (the Dataset's display is the dict's)


def test_results_read_back_keep_no_advice_of_their_own(results, tmp_path):
    """A result rebuilt from its file holds its own data, not the advice: written again, its file
    has the attribute once."""
    ix.write_result(results["batch fit"], tmp_path / "b.nc")
    again = ix.BatchFitResult.from_xarray(ix.io.read_netcdf(tmp_path / "b.nc"))
    assert "netcdf" not in again.dataset.attrs
    assert list(again.to_xarray().attrs).count("netcdf") == 1


def test_a_dataset_is_written_as_netcdf_only(results, tmp_path):
    with pytest.raises(ParameterError, match=r"written as \.nc .*pass the result itself: impedax\.write_result\(result, "):
        ix.write_result(results["kk"].to_xarray(), tmp_path / "kk.csv")
    with pytest.raises(ParameterError, match=r"a spectrum Dataset is written with impedax\.save"):
        ix.write_result(ix.make_spectrum(F, Z), tmp_path / "spectrum.nc")


@pytest.mark.parametrize("which", ["fit", "batch fit"])
def test_write_result_reads_back_with_xarray(results, which, tmp_path):
    result = results[which]
    ds = result.to_xarray()
    path = tmp_path / "x.nc"
    ix.write_result(result, str(path))
    with xr.open_dataset(path) as back:
        np.testing.assert_array_equal(back["value"].values, ds["value"].values)
        np.testing.assert_array_equal(back["Z__real"].values + 1j * back["Z__imag"].values, ds["Z"].values)
        assert list(back["param"].values) == list(ds["param"].values)
    again = type(result).from_xarray(xr.open_dataset(path))  # (as stored: from_xarray joins the parts)
    np.testing.assert_array_equal(again.to_xarray()["Z_model"].values, ds["Z_model"].values)
