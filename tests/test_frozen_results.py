"""Results are read-only (docs/fitting.md, "Results are read-only"): an edit in place of what
a result hands out raises or leaves the result as it was, and ``to_xarray`` gives a copy the
user may edit. On SYNTHETIC spectra of R0 + R1 || C1 written out in closed form."""

from __future__ import annotations

import copy
import dataclasses
import json
import pickle

import jax
import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.frozen import ReadOnlyDict, read_only_dataset

MODEL = "R0 + R1 || C1"
FREQ = np.geomspace(1e-1, 1e5, 30)


def rc_spectra(r1s) -> np.ndarray:
    """Z = R0 + R1/(1 + jωR1C1) [Ω] with R0 = 100 Ω, C1 = 1 µF, one row per R1, 0.1 % noise (seed 0)."""
    omega = 2 * np.pi * FREQ
    r1 = np.asarray(r1s, float)[:, None]
    z = 100.0 + r1 / (1 + 1j * omega * r1 * 1e-6)
    rng = np.random.default_rng(0)
    return z * (1 + 1e-3 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))


@pytest.fixture(scope="module")
def spectrum():
    return ix.make_spectrum(FREQ, rc_spectra([1e4])[0])


@pytest.fixture(scope="module")
def spectra():
    return ix.make_spectrum(FREQ, rc_spectra([5e3, 1e4, 2e4]), dims="cell", coords={"cell": [1, 2, 3]})


@pytest.fixture(scope="module")
def fit(spectrum):
    return ix.fit(MODEL, spectrum)


@pytest.fixture(scope="module")
def batch(spectra):
    return ix.fit(MODEL, spectra)


def assert_read_only(result) -> None:
    """Every array, mapping and Dataset ``result`` holds refuses an edit in place, and the
    result's numbers (its ``to_xarray``) are those of before the attempts."""
    before = result.to_xarray()
    tried = 0
    for f in dataclasses.fields(result):
        value = getattr(result, f.name)
        if isinstance(value, np.ndarray) and value.size and value.dtype != object:
            with pytest.raises(ValueError, match="read-only"):
                value[...] = 0
            tried += 1
        elif isinstance(value, dict):
            assert isinstance(value, ReadOnlyDict), f.name
            with pytest.raises(TypeError, match="read-only"):
                value["anything"] = 1
            tried += 1
        elif isinstance(value, xr.Dataset):
            for name, variable in value.variables.items():
                if variable.size and not isinstance(variable, xr.IndexVariable):
                    with pytest.raises(ValueError, match="read-only"):
                        value[name].values[...] = 0
                    tried += 1
    assert tried > 0
    xr.testing.assert_identical(result.to_xarray(), before)


def assert_to_xarray_is_a_copy(result) -> None:
    """Every number ``to_xarray`` gives may be edited, and the result does not change."""
    before = result.to_xarray()
    edited = result.to_xarray()
    numeric = [n for n, v in edited.data_vars.items() if v.size and v.dtype.kind in "fcib"]
    assert numeric
    for name in numeric:
        edited[name].values[...] = 0
    edited.attrs["model"] = "edited"
    xr.testing.assert_identical(result.to_xarray(), before)


def test_a_single_fits_mappings_refuse_item_assignment(fit):
    values, stderr = dict(fit.values), dict(fit.stderr)
    report = fit.report()
    with pytest.raises(TypeError, match="read-only"):
        fit.values["R0"] = 1.0
    for edit in (lambda d: d.update(R0=1.0), lambda d: d.pop("R0"), lambda d: d.clear(), lambda d: d.setdefault("X", 1.0), lambda d: d.__ior__({"R0": 1.0}), lambda d: d.__delitem__("R0")):
        with pytest.raises(TypeError):
            edit(fit.values)
    with pytest.raises(TypeError):
        fit.stderr["R1"] = 0.0
    assert dict(fit.values) == values and dict(fit.stderr) == stderr
    assert fit.report() == report


def test_a_single_fits_arrays_are_read_only(fit):
    z_model, covariance = fit.z_model.copy(), fit.covariance.copy()
    with pytest.raises(ValueError, match="read-only"):
        fit.z_model *= 2
    with pytest.raises(ValueError, match="read-only"):
        fit.covariance[0, 0] = 0.0
    np.testing.assert_array_equal(fit.z_model, z_model)
    np.testing.assert_array_equal(fit.covariance, covariance)
    assert_read_only(fit)
    assert_to_xarray_is_a_copy(fit)


def test_a_fits_values_work_where_a_dict_did(fit):
    """A copy by dict(), JSON, pickle, copy, and JAX (pytree leaves in a dict's order, jit)."""
    plain = dict(fit.values)
    assert type(plain) is dict and plain == fit.values
    plain["R0"] = 1.0  # (the copy is the user's)
    assert fit.values["R0"] != 1.0
    assert json.loads(json.dumps(fit.values)) == dict(fit.values)
    assert pickle.loads(pickle.dumps(fit)).values == fit.values
    assert copy.deepcopy(fit.values) == fit.values
    assert jax.tree_util.tree_leaves(fit.values) == jax.tree_util.tree_leaves(dict(fit.values))
    doubled = jax.tree_util.tree_map(lambda v: 2 * v, fit.values)
    assert list(doubled) == list(fit.values) and doubled["R1"] == 2 * fit.values["R1"]
    total = jax.jit(lambda p: p["R0"] + p["R1"])(fit.values)
    assert float(total) == pytest.approx(fit.values["R0"] + fit.values["R1"], rel=1e-12)
    np.testing.assert_allclose(fit.predict(FREQ), ix.compile_circuit(MODEL)(dict(fit.values), FREQ))


def test_the_callers_data_stay_writable(spectrum, fit):
    """The result copies what it keeps: the user's data are not made read-only under them."""
    assert spectrum["Z"].values.flags.writeable
    ds = fit.to_xarray()
    rebuilt = ix.FitResult.from_xarray(ds)
    assert ds["value"].values.flags.writeable
    assert not rebuilt.covariance.flags.writeable


def test_a_batchs_values_refuse_an_edit_in_place(batch):
    """The walkthrough's ``c = rc.values("C_sc"); c *= 1e9``."""
    before = batch.values("C1").values.copy()
    c = batch.values("C1")
    with pytest.raises(ValueError, match="read-only"):
        c *= 1e9
    with pytest.raises(ValueError, match="read-only"):
        batch.dataset["value"][0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        batch.stderr("R1").values[0] = 0.0
    with pytest.raises(TypeError, match="read-only"):
        batch.warnings["cell=1"] = ("edited",)
    np.testing.assert_array_equal(batch.values("C1").values, before)
    assert_read_only(batch)
    assert_to_xarray_is_a_copy(batch)


def test_a_batch_rebuilt_from_a_dataset_leaves_the_dataset_writable(batch, tmp_path):
    ds = batch.to_xarray()
    rebuilt = ix.BatchFitResult.from_xarray(ds)
    ds["value"].values[...] = 0  # (the user's Dataset is still the user's)
    assert np.all(rebuilt.values("R1").values > 0)
    path = tmp_path / "fits.nc"
    ix.write_result(batch, path)
    loaded = ix.BatchFitResult.from_xarray(ix.load(path))
    with pytest.raises(ValueError, match="read-only"):
        loaded.values("R1").values[...] = 0
    np.testing.assert_allclose(loaded.values("R1").values, batch.values("R1").values, rtol=1e-12)


def test_derive_and_the_csv_use_the_fitted_numbers_after_an_attempted_edit(batch, tmp_path):
    c = batch.values("C1")
    with pytest.raises(ValueError):
        c *= 1e9
    derived = ix.derive(batch, lambda p: p["R1"] * p["C1"])  # τ = R1 C1 [s]
    tau = batch.values("R1").values * batch.values("C1").values
    np.testing.assert_allclose(np.asarray(derived["value"]).ravel(), tau.ravel(), rtol=1e-9)
    path = tmp_path / "fits.csv"
    ix.write_result(batch, path)
    assert f"{batch.values('C1').values[0]:.6g}"[:5] in path.read_text()


def test_read_only_dataset_copies():
    mine = xr.Dataset({"a": ("x", np.arange(3.0))}, attrs={"notes": {"k": [1]}})
    frozen = read_only_dataset(mine)
    mine["a"].values[0] = 9.0
    mine.attrs["notes"]["k"].append(2)
    assert frozen["a"].values[0] == 0.0 and frozen.attrs["notes"] == {"k": [1]}
    with pytest.raises(ValueError, match="read-only"):
        frozen["a"].values[0] = 1.0


def test_kk_results_are_read_only(spectrum, spectra):
    for result in (ix.kk_test(spectrum), ix.kk_test_batch(spectra)):
        assert_read_only(result)
        assert_to_xarray_is_a_copy(result)


def test_zhit_and_drt_results_are_read_only(spectrum):
    for result in (ix.zhit(spectrum), ix.drt(spectrum)):
        assert_read_only(result)
        assert_to_xarray_is_a_copy(result)


def test_comparisons_are_read_only(spectrum, spectra, fit, batch):
    one = ix.compare([fit, ix.fit("R0 + R1 || C1 + C2", spectrum)])
    assert_to_xarray_is_a_copy(one)
    many = ix.compare([batch, ix.fit("R0 + R1 || C1 + C2", spectra)])
    assert_read_only(many)
    assert_to_xarray_is_a_copy(many)


def test_a_posterior_is_read_only(spectrum, fit):
    post = ix.sample(MODEL, spectrum, init=fit, steps=60, burn=20, seed=1, progress=False)
    draws = post.draws.copy()
    samples = post.samples["R1"]
    try:  # (a read-only view or a copy, as the draws' layout gives it: either leaves the draws)
        samples[...] = 0.0
    except ValueError as error:
        assert "read-only" in str(error)
    with pytest.raises(TypeError, match="read-only"):
        post.fit.values["R1"] = 0.0
    np.testing.assert_array_equal(post.draws, draws)
    assert_read_only(post)
    assert_to_xarray_is_a_copy(post)


@pytest.mark.slow
def test_a_diagnosis_and_a_refinement_are_read_only(spectrum):
    diagnosis = ix.diagnose(spectrum, "R0 + C1")
    assert_read_only(diagnosis)
    assert_to_xarray_is_a_copy(diagnosis)
    refinement = ix.refine(spectrum, "R0 + C1", max_effects=1)
    for step in refinement.steps:  # (a refinement holds its steps' fits, no arrays of its own)
        assert_read_only(step.fit)
    assert_to_xarray_is_a_copy(refinement)


@pytest.mark.slow
def test_a_gap_analysis_is_read_only():
    from impedax.models.gap import gap_analysis
    from spectra import sirin_measurements

    f, *spectra = sirin_measurements(np.random.default_rng(11), 4, noise=0.005, trial_scatter=0.0)
    total, skin, ts = (ix.make_spectrum(f, z, dims=("trial",)) for z in spectra)
    analysis = gap_analysis(total, skin, ts, area=130e-6, steps=100, progress=False, method="pooled")
    with pytest.raises(ValueError, match="read-only"):
        analysis.force["median"].values[...] = 0.0
    assert_read_only(analysis)
    assert_to_xarray_is_a_copy(analysis)


def test_a_copy_of_a_result_reuses_its_frozen_mappings_and_a_rebuilt_one_is_frozen_again(batch):
    """`dataclasses.replace` of a batch shares the mappings the batch froze (a 1,000-spectrum
    batch's warnings and tags were walked again in each copy: 9 ms); a mapping rebuilt by
    pickle or ``copy.deepcopy`` (new, writable arrays inside) is made read-only again."""
    same = dataclasses.replace(batch)
    assert same.warnings is batch.warnings and same.warning_tags is batch.warning_tags
    for rebuilt in (pickle.loads(pickle.dumps(batch)), copy.deepcopy(batch)):
        assert rebuilt.warnings is not batch.warnings and rebuilt.warnings == batch.warnings
    plain = ReadOnlyDict({"a": np.arange(3.0)})  # (made by a caller, not by a result: its array writable)
    frozen = dataclasses.replace(batch, warnings=plain, warning_tags=None).warnings
    assert frozen is not plain and not frozen["a"].flags.writeable


@pytest.mark.parametrize("key, said", [
    ("R_1", "'R_1'; did you mean 'R1'? (the keys: R0, R1, CPE1.Q, CPE1.alpha)"),
    ("CPE1.a", "'CPE1.a'; did you mean 'CPE1.alpha'? (the keys: R0, R1, CPE1.Q, CPE1.alpha)"),  # (the name it begins, not difflib's CPE1.Q)
    ("zzz", "'zzz' (the keys: R0, R1, CPE1.Q, CPE1.alpha)"),
])
def test_a_missing_key_names_the_keys_there_are(key, said):
    """``fit.values["R_1"]`` raised a plain KeyError: 'R_1'; it stays a KeyError with the key as
    its argument (code that catches it reads the same), and its text helps."""
    values = ReadOnlyDict({"R0": 1.0, "R1": 2.0, "CPE1.Q": 3.0, "CPE1.alpha": 0.9})
    with pytest.raises(KeyError) as info:
        values[key]
    assert info.value.args == (key,) and str(info.value) == said
    assert values.get(key) is None and key not in values  # (get and `in` unchanged)
