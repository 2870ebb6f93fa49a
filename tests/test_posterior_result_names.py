"""Posteriors' results read as the fits' do (docs/cli.md, "From Python"): the draws a posterior
hands out by name raise the fits' `MissingKey` for a key they lack and stay a dict to edit. SYNTHETIC
spectra: R0 + R1 ∥ C1 in closed form with 1 % noise (fixed seeds); the hierarchical posterior
is built by hand (tests/test_hierarchical_new_session.py)."""

from __future__ import annotations

import pickle
import re

import jax
import numpy as np
import pytest

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
