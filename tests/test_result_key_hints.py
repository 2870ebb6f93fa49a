"""Every mapping a result hands out by parameter name raises the fits' `MissingKey` for a key it
lacks ("'R_1'; did you mean 'R1'? (the keys: …)"), as ``fit.values`` and a posterior's
``samples`` do. Until 2026-12-08 these said ``'R_1'`` alone: a fit's ``params`` and
``linearised_stderr``, a batch's ``user_bounds()``, a posterior's ``piled_up``, a joint
posterior's ``fixed``, and a hierarchical posterior's ``ess()``, ``rhat()``, ``mixing()``,
``population()``, ``spread_between_trials()`` and ``new_trial()``; its ``population("R_1")``
named the per-trial parameters without the one meant. Each stays a dict equal to what it was
(a new one at each call, yours to edit). Oracles: the text written here by hand; the values
against the result's own frozen mappings (``values``, ``stderr``, the bounds given) and, for
the hierarchical posterior built by hand, against NumPy's quantiles of its draws and a split-R̂
written out here from BDA3 §11.4. SYNTHETIC spectra: R0 + R1 ∥ C1 in closed form with 1 % noise
(fixed seeds)."""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.frozen import MissingKey
from test_hierarchical_new_session import by_hand  # (a HierarchicalPosterior built by hand)
from test_posterior_result_names import FREQ, MODEL, rc  # (31 frequencies, 0.1 Hz – 100 kHz; R0 + R1 ∥ C1 with 1 % noise)



def says(mapping, key: str, text: str) -> None:
    """``mapping[key]`` raises a KeyError (`MissingKey`) whose argument is the key and whose text is ``text``."""
    with pytest.raises(KeyError) as info:
        mapping[key]
    assert isinstance(info.value, MissingKey) and info.value.args == (key,)
    assert str(info.value) == text


def a_new_dict(make) -> None:
    """``make()`` gives a new dict at each call, editable without changing the next one."""
    first, second = make(), make()
    assert type(first) is not dict and isinstance(first, dict) and first == second and first is not second
    key = next(iter(first))
    first[key] = "edited"
    assert make()[key] != "edited"


@pytest.fixture(scope="module")
def fit():
    return ix.fit(MODEL, ix.make_spectrum(FREQ, rc(1e3, 0)), progress=False)


def test_a_fits_params_and_linearised_stderr_name_the_keys_there_are(fit):
    says(fit.params, "R_1", "'R_1'; did you mean 'R1'? (the keys: R0, R1, C1)")
    says(fit.linearised_stderr, "c1", "'c1'; did you mean 'C1'? (the keys: R0, R1, C1)")
    # (no parameter at a bound: the linearised errors are the errors)
    assert not fit.at_bound
    assert fit.params == dict(fit.values) and fit.linearised_stderr == dict(fit.stderr)
    assert list(fit.params) == ["R0", "R1", "C1"]
    a_new_dict(lambda: fit.params)
    a_new_dict(lambda: fit.linearised_stderr)


def test_a_batchs_user_bounds_name_the_keys_there_are():
    data = ix.make_spectrum(FREQ, np.stack([rc(1e3, 1), rc(1.2e3, 2)]), dims="cell", coords={"cell": ["a", "b"]})
    batch = ix.fit(MODEL, data, bounds={"R1": (10.0, 1e5)}, progress=False)
    assert batch.user_bounds() == {"R1": (10.0, 1e5)}
    says(batch.user_bounds(), "R_1", "'R_1'; did you mean 'R1'? (the keys: R1)")
    a_new_dict(batch.user_bounds)


@pytest.fixture(scope="module")
def capped():
    """R1 = 1 kΩ sampled under a bound of 700 Ω: its draws pile up against the upper edge."""
    return ix.sample(MODEL, ix.make_spectrum(FREQ, rc(1e3, 3)), bounds={"R1": (1.0, 700.0)}, steps=60, walkers=16, seed=1, progress=False)


def test_a_posteriors_piled_up_names_the_keys_there_are(capped):
    assert capped.piled_up == {"R1": "upper"}
    says(capped.piled_up, "R_1", "'R_1'; did you mean 'R1'? (the keys: R1)")
    a_new_dict(lambda: capped.piled_up)


def test_a_joint_posteriors_fixed_names_the_keys_there_are():
    data = ix.make_spectrum(FREQ, np.stack([rc(1e3, 4), rc(2e3, 5)]), dims="cell", coords={"cell": ["a", "b"]})
    joint = ix.sample(MODEL, data, shared=["C1"], fixed={"R0": 50.0}, steps=20, walkers=16, seed=2, progress=False)
    assert joint.fixed == {"R0": 50.0}
    says(joint.fixed, "r0", "'r0'; did you mean 'R0'? (the keys: R0)")
    a_new_dict(lambda: joint.fixed)


def split_rhat(x: np.ndarray) -> float:
    """Split-R̂ of draws (chains, draws) as BDA3 §11.4 writes it: each chain halved, then
    sqrt(var⁺/W), var⁺ = (n−1)/n W + B/n over the m half-chains of n draws."""
    halves = [half for chain in x for half in (chain[: x.shape[1] // 2], chain[x.shape[1] // 2 :])]
    m, n = len(halves), len(halves[0])
    means = [float(np.mean(h)) for h in halves]
    grand = sum(means) / m
    b = n / (m - 1) * sum((mean - grand) ** 2 for mean in means)
    w = sum(float(np.sum((h - mean) ** 2)) / (n - 1) for h, mean in zip(halves, means)) / m
    return math.sqrt(((n - 1) / n * w + b / n) / w)


@pytest.fixture(scope="module")
def hierarchical():
    """`by_hand`'s posterior (4 chains of 2000 draws, per-trial R1) with μ and the spread drawn
    at random (seed 5): ln R1's population median about ln 100, its spread about 0.1; the second
    chain's μ shifted by 0.05 so that R̂ is not 1."""
    post = by_hand(1)
    rng = np.random.default_rng(5)
    mu = math.log(100.0) + 0.02 * rng.standard_normal(post.mu.shape)
    mu[1] += 0.05
    spread = 0.1 * np.exp(0.1 * rng.standard_normal(post.spread.shape))
    return dataclasses.replace(post, mu=mu, spread=spread)


def test_a_hierarchical_posteriors_mixing_names_the_keys_there_are(hierarchical):
    post = hierarchical
    says(post.ess(), "R1", "'R1'; did you mean 'mu[R1]'? (the keys: mu[R1], spread[R1])")
    says(post.rhat(), "mu[R_1]", "'mu[R_1]'; did you mean 'mu[R1]'? (the keys: mu[R1], spread[R1])")
    rhat, ess = post.mixing()
    says(rhat, "C_1", "'C_1'; did you mean 'C1'? (the keys: mu[R1], spread[R1], R0, C1)")
    says(ess, "R_0", "'R_0'; did you mean 'R0'? (the keys: mu[R1], spread[R1], R0, C1)")
    assert post.rhat()["mu[R1]"] == pytest.approx(split_rhat(post.mu[..., 0]), rel=1e-12)
    assert post.rhat()["spread[R1]"] == pytest.approx(split_rhat(np.log(post.spread[..., 0])), rel=1e-12)
    assert post.rhat()["mu[R1]"] > 1.1  # (the shifted chain: the case can fail)
    assert 0.8 * 8000 <= post.ess()["spread[R1]"] <= 1.25 * 8000  # (independent draws: about chains × draws)
    assert {k: rhat[k] for k in post.rhat()} == post.rhat() and {k: ess[k] for k in post.ess()} == post.ess()
    for make in (post.ess, post.rhat):
        a_new_dict(make)


def test_a_hierarchical_posteriors_intervals_name_the_keys_there_are(hierarchical):
    post = hierarchical
    draws = np.exp(post.mu[..., 0]).ravel()
    expected = {"value": np.median(draws), "low": np.quantile(draws, 0.05), "high": np.quantile(draws, 0.95)}
    expected |= {"q05": expected["low"], "q95": expected["high"]}
    assert post.population("R1") == pytest.approx(expected, rel=1e-12)
    says(post.population("R1"), "q_05", "'q_05'; did you mean 'q05'? (the keys: value, low, high, q05, q95)")
    says(post.spread_between_trials("R1"), "median", "'median' (the keys: value, low, high, q05, q95)")
    says(post.new_trial("R1", level=0.8), "q95", "'q95' (the keys: value, low, high)")  # (q05/q95 only at 90 %)
    a_new_dict(lambda: post.population("R1"))
    with pytest.raises(ix.ParameterError, match=re.escape("'R_1' is not a per-trial parameter; did you mean R1?; per-trial: R1")):
        post.population("R_1")
    with pytest.raises(ix.ParameterError, match=re.escape("'R0' is not a per-trial parameter; per-trial: R1")):  # (a shared one: no other name meant)
        post.population("R0")
