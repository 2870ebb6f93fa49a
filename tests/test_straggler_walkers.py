"""Straggler walkers: walkers of an emcee run whose median log-probability over the kept draws
lies more than `STRAGGLER_LOG_PROB_GAP` below the median of all walkers' medians sit where the
posterior has no weight; their draws are left out of the posterior, with a warning, and
`straggler_walkers` names them (docs/bayesian.md, "Diagnostics")."""

import dataclasses
import json

import numpy as np
import pytest
from scipy import stats

import impedax as ix
from impedax.cli import main
from impedax.fitting import Posterior
from impedax.fitting.bayes import chain as chain_module
from impedax.fitting.bayes.chain import Chain, without_stragglers
from impedax.fitting.bayes.diagnostics import STRAGGLER_LOG_PROB_GAP, Stragglers, find_stragglers, straggler_warnings
from impedax.io import read_netcdf

STRAGGLERS = (4, 17, 40)


def _hand_made_log_prob(rng, gap=57.0, walkers=64, draws=500, d=5):
    """A kept chain's log-probabilities (walker, draw): a d-parameter Gaussian posterior's, its
    peak at 560.95 less χ²_d/2, with the walkers `STRAGGLERS` in a mode ``gap`` nats lower."""
    peak = np.full(walkers, 560.95)
    peak[list(STRAGGLERS)] -= gap
    return peak[:, None] - rng.chisquare(d, size=(walkers, draws)) / 2


def test_three_walkers_57_nats_below_are_found_with_their_gap_and_acceptance():
    rng = np.random.default_rng(57)
    log_prob = _hand_made_log_prob(rng)
    acceptance = np.where(np.isin(np.arange(64), STRAGGLERS), 0.08, 0.47)
    found = find_stragglers(log_prob, acceptance)
    assert found.walkers == STRAGGLERS
    # the oracle: every walker's median is its peak less the median of χ²_5/2 (2.18), to a few hundredths
    np.testing.assert_allclose(found.log_prob_gap, 57.0, atol=0.3)
    assert found.acceptance == (0.08, 0.08, 0.08) and found.others_acceptance == 0.47 and found.draws == 500
    (warning,) = straggler_warnings(found, 64)
    for fragment in ("3 of 64 walkers (walkers 4, 17, 40) are stragglers", "nats below the median of all walkers'", "acceptance 0.080 against a median 0.470 for the others",
                     "negligible posterior weight", "a second mode, or walkers stuck since the start", "1500 draws are left out of the posterior", "the other 61 walkers"):
        assert fragment in warning
    assert f"{min(found.log_prob_gap):.1f}" in warning


def test_the_kept_chain_leaves_out_exactly_the_stragglers_and_a_healthy_chain_is_the_same_object():
    rng = np.random.default_rng(3)
    log_prob = _hand_made_log_prob(rng, draws=60)
    chain_y = rng.standard_normal((64, 60, 5))
    acceptance = rng.uniform(0.4, 0.5, 64)
    run = Chain(chain_y, log_prob, acceptance, 1.0, 80, 20, None)
    kept = without_stragglers(run)
    others = [w for w in range(64) if w not in STRAGGLERS]
    assert kept.stragglers.walkers == STRAGGLERS
    assert np.array_equal(kept.chain_y, chain_y[others]) and np.array_equal(kept.log_prob, log_prob[others]) and np.array_equal(kept.acceptance, acceptance[others])
    healthy = Chain(chain_y, _hand_made_log_prob(rng, gap=0.0, draws=60), acceptance, 1.0, 80, 20, None)
    assert without_stragglers(healthy) is healthy and not healthy.stragglers.walkers


def test_a_walker_15_nats_below_stays_and_one_at_minus_infinity_goes():
    rng = np.random.default_rng(5)
    log_prob = _hand_made_log_prob(rng, gap=15.0)
    assert find_stragglers(log_prob, np.full(64, 0.5)).walkers == ()
    log_prob[9] = -np.inf
    assert find_stragglers(log_prob, np.full(64, 0.5)).walkers == (9,)


@pytest.mark.parametrize("d", [1, 5, 10, 20])
def test_the_gap_is_beyond_a_gaussian_posteriors_spread_of_log_probability(d):
    # a single draw's log-probability lies more than (χ²_d quantile 0.9999 − median)/2 below the
    # median with probability 1e-4: 7.3 nats for d = 1 … 16.5 for d = 20, all below the gap
    spread = (stats.chi2.ppf(0.9999, d) - stats.chi2.ppf(0.5, d)) / 2
    assert spread < STRAGGLER_LOG_PROB_GAP


# --- a healthy SYNTHETIC run: nothing changes -----------------------------------------------------


def _rc_spectrum():
    """SYNTHETIC R0 + R1 ∥ C1 (20 Ω, 500 Ω, 2 µF), 40 points 0.1 Hz–100 kHz, 1 % of |Z| noise on Re and Im."""
    f = np.geomspace(0.1, 1e5, 40)
    z = 20.0 + 500.0 / (1 + 1j * 2 * np.pi * f * 500.0 * 2e-6)
    rng = np.random.default_rng(11)
    z = z + 0.01 * np.abs(z) * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
    return ix.make_spectrum(f, z)


@pytest.fixture(scope="module")
def healthy():
    return _rc_spectrum(), ix.sample("R0 + R1 || C1", _rc_spectrum(), steps=300, burn=100, seed=3, progress=False)


def test_a_healthy_run_has_no_stragglers_and_the_draws_of_a_run_without_the_check(healthy, monkeypatch):
    data, post = healthy
    assert post.stragglers.walkers == () and post.summary()["straggler_walkers"] == [] and post.n_walkers == 64
    assert not any("straggler" in w for w in post.warnings)
    assert "64 walkers," in post.report()
    monkeypatch.setattr(chain_module, "without_stragglers", lambda chain: chain)
    unchecked = ix.sample("R0 + R1 || C1", data, steps=300, burn=100, seed=3, progress=False)
    for name in ("draws", "log_prob", "acceptance"):
        assert np.array_equal(getattr(post, name), getattr(unchecked, name))
    assert post.summary() == unchecked.summary()


def test_stragglers_are_saved_and_read_back(healthy, tmp_path):
    _, post = healthy
    left_out = Stragglers((0,), (31.5,), (0.09,), 0.6, post.n_draws)
    fewer = dataclasses.replace(post, draws=post.draws[1:], log_prob=post.log_prob[1:], acceptance=post.acceptance[1:], stragglers=left_out)
    assert fewer.summary()["walkers"] == 64 and fewer.summary()["walkers_kept"] == 63
    assert fewer.summary()["straggler_walkers"] == [0] and fewer.warnings[0].startswith("1 of 64 walkers (walker 0) is a straggler")
    assert "64 walkers (1 straggler left out)" in fewer.report()
    ix.write_result(fewer, tmp_path / "post.nc")
    stored = read_netcdf(tmp_path / "post.nc")
    assert stored.attrs["straggler_walkers"] == [0] and list(stored["walker"].values) == list(range(1, 64))
    back = Posterior.from_xarray(stored)
    assert back.stragglers == left_out and back.warnings == fewer.warnings and np.array_equal(back.draws, fewer.draws)


# --- the REAL BioLogic example of the walkthrough -------------------------------------------------


@pytest.mark.slow
def test_the_biologic_example_leaves_out_its_stragglers_in_a_second_mode(tmp_path, capsys):
    # REAL data: 3 walkers sat in a mode ~57 nats down (R1 1e4–1e6 Ω, CPE1.Q ≈ 170) and set
    # CPE1.Q's q95 to 74 in an empty gap between 20 and 100 (~22 s)
    out_nc = tmp_path / "post.nc"
    code = main(["sample", "tests/fixtures/real/exampleData.csv", "--model", "R0 + R1 || CPE1", "--seed", "2", "--prior", "CPE1.alpha=uniform:0.5,1", "--json", "--out", str(out_nc)])
    out, err = capsys.readouterr()
    assert code == 0, err
    doc = json.loads(out)
    assert doc["straggler_walkers"] and doc["walkers"] == 64 and doc["walkers_kept"] == 64 - len(doc["straggler_walkers"])
    assert doc["draws_total"] == doc["walkers_kept"] * doc["draws"]
    assert any("are stragglers" in w and "left out of the posterior" in w for w in doc["warnings"])
    assert doc["params"]["CPE1.Q"]["q95"] < 20
    assert read_netcdf(out_nc).attrs["straggler_walkers"] == doc["straggler_walkers"]


def test_the_json_holds_the_least_squares_start_beside_the_intervals(healthy):
    """`summary()["start_fit"]` (added 2026-12-01) is the least-squares fit the walkers started
    around: its values and ± as `impedax fit --json` gives them, so the posterior's interval can
    be set beside the linearised one without a second run; for R ∥ C data (SYNTHETIC, 1 %), R1's
    90 % interval is close to ± 1.645 standard errors (a near-Gaussian posterior)."""
    data, post = healthy
    start = post.summary()["start_fit"]
    fitted = ix.fit("R0 + R1 || C1", data)
    assert start["model"] == "R0 + R1 || C1" and start["weighting"] == fitted.weighting and start["converged"]
    for name in ("R0", "R1", "C1"):
        assert start["values"][name] == pytest.approx(fitted.values[name], rel=1e-6)
        assert start["stderr"][name] == pytest.approx(fitted.stderr[name], rel=1e-4)
    q = post.summary()["params"]["R1"]
    assert (q["q95"] - q["q05"]) / (2 * 1.645 * start["stderr"]["R1"]) == pytest.approx(1.0, abs=0.35)
    assert json.loads(json.dumps(start)) == start
