"""Posteriors' results read as the fits' do (docs/io.md, "Names and signs in a result's Dataset";
docs/cli.md, "From Python"): the draws a posterior hands out by name raise the fits' `MissingKey`
for a key they lack and stay a dict to edit, a single posterior's Dataset holds its start fit's
rms_rel as a joint one's does (``fit_rms_rel``), a hierarchical one's names its parameters'
units, and a KK or Z-HIT test given a stack names the batch call that takes it. SYNTHETIC
spectra: R0 + R1 ∥ C1 in closed form with 1 % noise (fixed seeds); the hierarchical posterior
is built by hand (tests/test_hierarchical_new_session.py)."""

from __future__ import annotations

import dataclasses
import pickle
import re

import jax
import numpy as np
import pandas as pd
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.frozen import MissingKey
from test_hierarchical_new_session import by_hand

FREQ = np.geomspace(0.1, 1e5, 31)
MODEL = "R0 + R1 || C1"


def rc(r1: float, seed: int) -> np.ndarray:
    """Z = R0 + R1/(1 + jωR1C1) [Ω], R0 = 50 Ω, C1 = 1 µF, 1 % proportional noise."""
    z = 50.0 + r1 / (1 + 2j * np.pi * FREQ * r1 * 1e-6)
    rng = np.random.default_rng(seed)
    return z * (1 + 0.01 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)))


@pytest.fixture(scope="module")
def post():
    return ix.sample(MODEL, ix.make_spectrum(FREQ, rc(1e3, 0)), steps=60, walkers=16, seed=1, progress=False)


@pytest.fixture(scope="module")
def joint():
    data = ix.make_spectrum(FREQ, np.stack([rc(1e3, 1), rc(2e3, 2)]), dims="cell", coords={"cell": ["a", "b"]})
    return ix.sample(MODEL, data, shared=["C1"], steps=30, walkers=16, seed=2, progress=False)


def test_a_posteriors_samples_name_the_keys_there_are(post):
    """``post.samples["R_1"]`` said ``'R_1'`` alone: now the fits' text, the keys being the
    sampled parameters (R0, R1, C1 and the proportional noise's sigma_rel)."""
    with pytest.raises(MissingKey) as info:
        post.samples["R_1"]
    assert isinstance(info.value, KeyError) and info.value.args == ("R_1",)
    assert str(info.value) == "'R_1'; did you mean 'R1'? (the keys: R0, R1, C1, sigma_rel)"
    with pytest.raises(MissingKey, match=re.escape("(the keys: R0, R1, C1)")):  # (the circuit's: no sigma_rel)
        post.circuit_samples()["R9"]
    with pytest.raises(MissingKey, match=re.escape("(the keys: R0, R1, C1, sigma_rel)")):
        post.parameter_draws()["R9"]


def test_the_samples_are_still_the_draws_in_a_dict_yours_to_edit(post):
    """docs/fitting.md: a posterior's ``samples`` is a new object at each call, yours to edit;
    its arrays are the draws (walker, draw, param) flattened, for pickle, JSON keys and ``jit``."""
    samples = post.samples
    for i, name in enumerate(["R0", "R1", "C1", "sigma_rel"]):
        np.testing.assert_array_equal(samples[name], post.draws[:, :, i].reshape(-1))
    samples["R1_twice"] = 2 * samples["R1"]
    del samples["R0"]
    assert "R0" in post.samples and "R1_twice" not in post.samples
    back = pickle.loads(pickle.dumps(post.samples))
    assert list(back) == ["R0", "R1", "C1", "sigma_rel"]
    with pytest.raises(MissingKey):
        back["R9"]
    total = jax.jit(lambda p: p["R1"].sum() + p["C1"].sum())(post.samples)
    assert float(total) == pytest.approx(float(np.sum(post.draws[:, :, 1]) + np.sum(post.draws[:, :, 2])), rel=1e-12)


def test_a_joint_and_a_hierarchical_posteriors_draws_name_the_keys_there_are(joint):
    with pytest.raises(MissingKey) as info:
        joint.samples["R1"]  # (a joint posterior's per-spectrum names are R1[cell=a], R1[cell=b])
    assert info.value.args == ("R1",) and str(info.value).startswith("'R1'; did you mean 'R1[cell=a]'?")
    for name in ("R0", "R1[cell=a]", "R1[cell=b]", "C1", "sigma_rel"):
        assert name in str(info.value)
    with pytest.raises(MissingKey, match=re.escape("'R_1'; did you mean 'R1'? (the keys: R1, R0, C1)")):
        by_hand(2).population_parameters()["R_1"]


def test_a_posteriors_dataset_holds_its_start_fits_rms_rel(post, joint):
    """Its ``fit_rms_rel`` () is the start fit's rms of (Z_fit − Z)/|Z|, computed here from the
    Dataset's own ``Z`` and ``Z_fit``; the joint posterior's of that name is per spectrum."""
    ds = post.to_xarray()
    z, z_fit = ds["Z"].values, ds["Z_fit"].values
    assert ds["fit_rms_rel"].dims == ()
    assert float(ds["fit_rms_rel"]) == pytest.approx(np.sqrt(np.mean(np.abs((z_fit - z) / z) ** 2)), rel=1e-12)
    assert 5e-3 < float(ds["fit_rms_rel"]) < 3e-2  # (1 % on Re and Im: about √2 %)
    assert joint.to_xarray()["fit_rms_rel"].dims == ("cell",)


def test_the_start_fits_rms_rel_survives_the_file(post, tmp_path):
    path = tmp_path / "post.nc"
    ix.write_result(post, path)
    with xr.open_dataset(path) as stored:
        assert float(stored["fit_rms_rel"]) == float(post.to_xarray()["fit_rms_rel"])
    assert ix.Posterior.from_xarray(ix.load(path)).to_xarray()["fit_rms_rel"].identical(post.to_xarray()["fit_rms_rel"])


def test_a_hierarchical_posteriors_dataset_names_the_units():
    """R1 per trial is in Ω; the shared R0 and C1 in Ω and F (the element specs' units: R an
    ohm, C a farad); the Dataset reads back to the same posterior."""
    post = by_hand(2)
    ds = post.to_xarray()
    assert ds["unit"].dims == ("param",) and list(ds["unit"].values) == ["Ohm"]
    assert ds["shared_unit"].dims == ("shared_param",) and list(ds["shared_unit"].values) == ["Ohm", "F"]
    back = type(post).from_xarray(ds)
    assert back.trial_names == ("R1",) and back.shared_names == ("R0", "C1")
    assert back.to_xarray().identical(ds)


def test_a_trial_level_named_unit_keeps_its_name():
    """Data stacked over a dimension called ``unit`` (say, the test unit) stored before: its
    coordinate stays, and the parameters' unit coordinate gives way (docs/io.md)."""
    post = by_hand(2)
    index = pd.MultiIndex.from_arrays([post.trial_index[level].values for level in ("session", "trial")], names=["session", "unit"])
    renamed = dataclasses.replace(post, trial_index=xr.Coordinates.from_pandas_multiindex(index, "trial_index")["trial_index"])
    ds = renamed.to_xarray()
    assert ds["unit"].dims == ("trial_index",) and list(ds["unit"].values) == list(post.trial_index["trial"].values)
    assert list(ds["shared_unit"].values) == ["Ohm", "F"]
    assert type(post).from_xarray(ds).to_xarray().identical(ds)


@pytest.mark.parametrize("single", ["kk_test", "zhit"])
def test_a_test_of_one_spectrum_given_a_stack_names_the_batch_call_that_takes_it(single):
    """The message names the call (``impedax.NAME(data)``); that call on the same stack gives
    each spectrum's test as the single call on that spectrum alone does."""
    data = ix.make_spectrum(FREQ, np.stack([rc(1e3, 3), rc(2e3, 4)]), dims="cell")
    with pytest.raises(ix.DataError) as info:
        getattr(ix, single)(data)
    named = re.search(r"use impedax\.(\w+)\(data\) for one test per spectrum", str(info.value))
    assert named and named.group(1) == f"{single}_batch", str(info.value)
    batch = getattr(ix, named.group(1))(data)
    for i in range(2):
        alone = getattr(ix, single)(data.isel(cell=i))
        assert batch[i].rms_rel == pytest.approx(alone.rms_rel, rel=1e-9) and batch[i].valid == alone.valid


def test_a_posteriors_autocorr_and_ess_refuse_an_edit(post, joint):
    """The τ and ESS a posterior keeps (computed once) were plain dicts: ``post.autocorr["R1"] =
    12345`` went into its Dataset and summary. They refuse, as ``fit.values`` does, and the
    Dataset's ``autocorr`` and ``ess`` are those of before the attempt."""
    for result in (post, joint):
        before = result.to_xarray()
        for mapping in (result.autocorr, result.ess):
            with pytest.raises(TypeError, match="read-only"):
                mapping[result.names[0]] = 12345.0
            with pytest.raises(MissingKey):
                mapping["R9"]
        after = result.to_xarray()
        for name in ("autocorr", "ess"):
            np.testing.assert_array_equal(after[name].values, before[name].values)
