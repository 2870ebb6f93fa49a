"""A hierarchical posterior's R-hat and ESS warnings name what its report shows and how to
mend it: they named the internal keys (``mu[R1]``, ``spread[R1]``, ``delta``), which the report
never shows (its rows are "R1 … population … spread" and "discrepancy δ", its prior-edge warnings "R1 (population median)"), gave no value and,
for a low ESS, no remedy (seen on the REAL battery cycles 120–129, 2 chains × 200 draws:
"effective sample size below 100 for mu[R0], mu[R1], spread[R0], spread[R1]"). SYNTHETIC draws
built by hand (tests/test_hierarchical_new_session.py), no sampling."""

import dataclasses
import re

import numpy as np

from impedax.fitting.bayes.hierarchical import mixing_name
from test_hierarchical_new_session import CHAINS, DRAWS, by_hand


def test_mixing_warnings_use_the_reports_words_and_say_what_to_do():
    rng = np.random.default_rng(0)
    post = by_hand(1)
    iid = rng.standard_normal((CHAINS, DRAWS))
    # μ of R1: the two chains 0.5 apart in ln R1 with within-chain sd 0.01 → R-hat ≫ 1.05 (between ≫ within)
    mu = np.log(100.0) + 0.01 * iid + np.array([0.0, 0.5])[:, None]
    # the spread of R1: a slow random walk in ln s, the chains' means equal → ESS ≪ 100, R-hat near 1
    walk = 0.01 * np.cumsum(rng.standard_normal((CHAINS, DRAWS)), axis=1) / np.sqrt(DRAWS)
    walk -= walk.mean(axis=1, keepdims=True)
    shared = np.array(post.shared) * np.exp(0.001 * rng.standard_normal(post.shared.shape))  # (iid: no warning)
    post = dataclasses.replace(post, mu=mu[..., None], spread=(0.1 * np.exp(walk))[..., None], shared=shared,
                               discrepancy=True, delta=0.02 * np.exp(0.01 * rng.standard_normal((CHAINS, DRAWS))))
    warnings = post.warnings
    (rhat,) = [w for w in warnings if w.startswith("R-hat above 1.05 for")]
    (ess,) = [w for w in warnings if w.startswith("effective sample size below 100 for")]
    assert "mu[" not in rhat + ess and "spread[" not in rhat + ess and "delta" not in rhat + ess
    value = float(re.search(r"R1 \(population median\) \(([0-9.]+)\)", rhat).group(1))
    assert value > 1.05
    assert float(re.search(r"R1 \(spread\) \(([0-9.]+)\)", ess).group(1)) < 100
    remedy = f"run more draws per chain ({DRAWS} now): draws={2 * DRAWS}, or more chains ({CHAINS} now): chains={2 * CHAINS}"
    assert rhat.endswith(remedy) and ess.endswith(remedy) and f"of {CHAINS * DRAWS} draws" in ess
    assert "R0" not in rhat + ess and "C1" not in rhat + ess  # (iid shared draws mix)


def test_the_names_are_the_reports():
    assert [mixing_name(k) for k in ("mu[R_EP]", "spread[CPE1.Q]", "delta", "R0")] == ["R_EP (population median)", "CPE1.Q (spread)", "discrepancy δ", "R0"]


def test_one_quantity_of_low_ess_is_spoken_of_in_the_singular():
    """"effective sample size below 100 for R1 (spread) (…): their medians are uncertain and their
    90 % intervals' ends more so" spoke of one quantity in the plural (2026-12-06). SYNTHETIC: the
    spread of R1 a slow random walk (ESS ≪ 100), everything else iid."""
    rng = np.random.default_rng(0)
    post = by_hand(1)
    walk = 0.01 * np.cumsum(rng.standard_normal((CHAINS, DRAWS)), axis=1) / np.sqrt(DRAWS)
    walk -= walk.mean(axis=1, keepdims=True)
    mu = np.log(100.0) + 0.01 * rng.standard_normal((CHAINS, DRAWS))
    shared = np.array(post.shared) * np.exp(0.001 * rng.standard_normal(post.shared.shape))
    post = dataclasses.replace(post, mu=mu[..., None], spread=(0.1 * np.exp(walk))[..., None], shared=shared)
    (ess,) = [w for w in post.warnings if w.startswith("effective sample size below 100 for")]
    assert ess.startswith("effective sample size below 100 for R1 (spread) (") and ": its median is uncertain and its 90 % interval's ends more so; " in ess
