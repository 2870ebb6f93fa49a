"""Every kind of result written to netCDF and read back: fit, batch fit, global (shared) fit,
KK, KK batch, Z-HIT, Z-HIT batch, DRT, DRT batch, comparison, batch comparison, diagnosis,
refinement, posterior, joint posterior, hierarchical posterior. Each `to_xarray()` holds complex
spectra and attributes that are Python dicts, lists, None and bools, which a netCDF3 file cannot
hold as such (the only writer the package needs is scipy's netCDF3: no complex type), so plain
``to_xarray().to_netcdf(path)`` raises xarray's TypeError, which names the calls that write and
read the file (docs/io.md, "A result's Dataset and `to_netcdf`"; a comparison's criteria alone
it writes); `impedax.write_result` (`impedax.io.write_netcdf`) writes every one, or its Dataset. The
file opens in plain xarray (any netCDF3 reader) and `read_netcdf` gives back each variable
(dims, values, dtype but for text, attrs) and each attribute of the result's dataset.
SYNTHETIC spectra: R0 + R1 ∥ CPE1 by formula with 1 % noise; the hierarchical posterior is
built by hand (tests/test_hierarchical_new_session.py), so nothing here samples NUTS."""

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.io import read_netcdf
from impedax.io.provenance import PROVENANCE_ATTRS
from test_hierarchical_new_session import by_hand

FREQ = np.geomspace(0.1, 1e5, 41)
CIRCUIT = "R0 + R1 || CPE1"


def _spectra():
    z = 10 + 100 / (1 + (2j * np.pi * FREQ * 1e-3) ** 0.9)
    rng = np.random.default_rng(0)
    z = z * (1 + 0.01 * (rng.normal(size=FREQ.size) + 1j * rng.normal(size=FREQ.size)))
    return ix.make_spectrum(FREQ, z), ix.make_spectrum(FREQ, np.stack([z, 1.1 * z, 0.9 * z]), dims=("cell",))


@pytest.fixture(scope="module")
def results():
    one, stack = _spectra()
    fit, fit_rc = ix.fit(CIRCUIT, one), ix.fit("R0 + R1 || C1", one)
    batch, batch_rc = ix.fit(CIRCUIT, stack), ix.fit("R0 + R1 || C1", stack)
    return {
        "fit": fit, "batch fit": batch, "shared fit": ix.fit(CIRCUIT, stack, shared=["CPE1.alpha"]),
        "kk": ix.kk_test(one), "kk batch": ix.kk_test_batch(stack), "zhit": ix.zhit(one), "zhit batch": ix.zhit_batch(stack),
        "drt": ix.drt(one), "drt batch": ix.drt(stack), "comparison": ix.compare([fit, fit_rc]), "batch comparison": ix.compare([batch, batch_rc]),
        "diagnosis": ix.diagnose(one, "R0 + R1 || C1"), "refinement": ix.refine(one, "R0 + R1 || C1"),
        "posterior": ix.sample(CIRCUIT, one, seed=1, steps=60, walkers=16, progress=False),
        "joint posterior": ix.sample(CIRCUIT, stack, shared=["CPE1.alpha"], seed=1, steps=30, walkers=32, progress=False),
        "hierarchical posterior": by_hand(2),
    }


KINDS = ["fit", "batch fit", "shared fit", "kk", "kk batch", "zhit", "zhit batch", "drt", "drt batch", "comparison", "batch comparison",
         "diagnosis", "refinement", "posterior", "joint posterior", "hierarchical posterior"]


def _equal(a, b) -> bool:
    """Attribute values equal as Python values (a tuple reads back as a list)."""
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple, np.ndarray)):
        return isinstance(b, (list, tuple, np.ndarray)) and len(a) == len(b) and all(_equal(x, y) for x, y in zip(a, b))
    if isinstance(a, float) and isinstance(b, float) and np.isnan(a):
        return np.isnan(b)
    return a == b and (a is None) == (b is None) and isinstance(a, bool) == isinstance(b, bool)


@pytest.mark.slow  # (the module's results take 30–100 s to build on a shared 2-core machine)
@pytest.mark.parametrize("kind", KINDS)
def test_each_kind_writes_and_reads_back_whole(results, kind, tmp_path):
    result = results[kind]
    written = result.to_xarray()
    path = tmp_path / "result.nc"
    ix.write_result(result, path)
    with xr.open_dataset(path, engine="scipy") as plain:  # (any netCDF3 reader opens it)
        plain.load()
    read = read_netcdf(path)
    for name, var in {**written.coords, **written.data_vars}.items():
        got = read[name]
        assert got.dims == var.dims, (name, got.dims, var.dims)
        if var.dtype.kind in "OUS":  # (text: an object array may read back as fixed-width str; a None as NaN)
            assert [str(v) for v in got.values.ravel()] == [str(v).replace("None", "nan") for v in var.values.ravel()], name
        else:
            assert got.dtype == var.dtype, (name, got.dtype, var.dtype)
            np.testing.assert_array_equal(got.values, var.values, err_msg=name)
        assert _equal(dict(var.attrs), dict(got.attrs)), name
    # every attribute of the result's dataset; "source" of data built in memory is where a DRT
    # file is read from (io.netcdf reads a dataset with Z and no impedax_kind as a spectrum)
    skipped = set(PROVENANCE_ATTRS) | ({"source"} if kind.startswith("drt") else set())
    for key, value in written.attrs.items():
        if key not in skipped:
            assert key in read.attrs and _equal(value, read.attrs[key]), (key, value, read.attrs.get(key))


def test_a_hierarchical_posterior_reads_back_with_the_same_report(tmp_path):
    post = by_hand(2)
    ix.write_result(post, tmp_path / "h.nc")
    back = ix.HierarchicalPosterior.from_xarray(ix.load(tmp_path / "h.nc"))
    assert back.report() == post.report() and back.new_trial("R1") == post.new_trial("R1")


# the call that reads each kind's file back, as ``ds.to_netcdf``'s error names it (`impedax.io.netcdf.result_dataset`)
READER = {
    "fit": "impedax.FitResult.from_xarray(", "batch fit": "impedax.BatchFitResult.from_xarray(", "shared fit": "impedax.SharedFitResult.from_xarray(",
    "kk": "impedax.io.read_netcdf('kk.nc')", "kk batch": "impedax.io.read_netcdf('kk.nc')", "zhit": "impedax.io.read_netcdf('zhit.nc')",
    "zhit batch": "impedax.io.read_netcdf('zhit.nc')", "drt": "impedax.io.read_netcdf('drt.nc')", "drt batch": "impedax.io.read_netcdf('drt.nc')",
    "comparison": None, "batch comparison": "impedax.BatchComparison.from_xarray(", "diagnosis": "impedax.Diagnosis.baseline_of(",
    "refinement": "impedax.Refinement.final_fit_of(", "posterior": "impedax.Posterior.from_xarray(", "joint posterior": "impedax.SharedPosterior.from_xarray(",
    "hierarchical posterior": "impedax.HierarchicalPosterior.from_xarray(",
}


@pytest.mark.slow  # (the module's results)
@pytest.mark.parametrize("kind", KINDS)
def test_each_kind_to_netcdf_names_impedax_or_writes(results, kind, tmp_path):
    """``to_xarray().to_netcdf(path)`` either names the calls that write and read the result
    (every kind with complex spectra or dict attributes) or writes a file that reads back
    equal (a comparison's criteria); ``impedax.write_result(ds, path)`` writes the Dataset
    itself, as the result would be written."""
    ds = results[kind].to_xarray()
    if READER[kind] is None:
        ds.to_netcdf(tmp_path / "plain.nc")
        back = read_netcdf(tmp_path / "plain.nc")
        for name, var in ds.data_vars.items():
            np.testing.assert_array_equal(back[name].values, var.values, err_msg=name)
    else:
        with pytest.raises(TypeError) as caught:
            ds.to_netcdf(tmp_path / "plain.nc")
        assert "impedax.write_result(" in str(caught.value) and READER[kind] in str(caught.value), str(caught.value)
    ix.write_result(ds, tmp_path / "dataset.nc")
    back = read_netcdf(tmp_path / "dataset.nc")
    for name in ("Z", "batch0_Z", "final_fit_Z_model", "baseline_fit_Z_model"):
        if name in ds.variables:  # (complex spectra exact)
            np.testing.assert_array_equal(back[name].values, ds[name].values, err_msg=name)
    assert [k for k in ds.attrs if k.endswith("netcdf")] == ([] if READER[kind] is None else ["netcdf"])  # (an embedded fit's advice is the host's)


# each parameter's unit, from the element specs (docs/circuits.md): R in Ω, a CPE's Q in F s^(α-1), α and sigma_rel none
UNITS = {"R0": "Ohm", "R1": "Ohm", "CPE1.Q": "F s^(alpha-1)", "CPE1.alpha": "1", "sigma_rel": "1"}


@pytest.mark.slow  # (the module's results)
@pytest.mark.parametrize("kind", ["posterior", "joint posterior"])
def test_a_posterior_names_its_parameters_units_as_a_fit_does(results, kind, tmp_path):
    """A fit's Dataset had a ``unit`` coordinate along ``param``, a posterior's only an attribute
    list ``units``: the same quantity, found in two places."""
    ds = results[kind].to_xarray()
    units = dict(zip(ds["param"].values.tolist(), ds["unit"].values.tolist()))
    assert units == {name: UNITS[name.split("[")[0]] for name in units}, units  # (a joint posterior's per-spectrum names: R0[cell=1])
    fit = results["fit"].to_xarray()
    assert all(units[p] == u for p, u in zip(fit["param"].values.tolist(), fit["unit"].values.tolist()) if p in units)
    ix.write_result(results[kind], tmp_path / "p.nc")
    assert read_netcdf(tmp_path / "p.nc")["unit"].values.tolist() == ds["unit"].values.tolist()


@pytest.mark.slow  # (the module's results)
def test_a_joint_posterior_repr_is_one_short_line(results):
    """Its generated repr printed every draw: 215 lines after 20 steps (tests/test_result_reprs.py)."""
    text = repr(results["joint posterior"])
    assert text.startswith("SharedPosterior(") and "draws=<float64 array (32, " in text and "\n" not in text and len(text) < 2000, text[:300]
