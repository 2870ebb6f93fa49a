"""Where the walkers of a joint posterior (`sample(..., shared=, over=)`) start, and what it
warns about: every walker strictly inside the priors' supports when a fit sits at a bound, a
parameter one spectrum cannot determine spread over its prior (a wide interval, and a warning
naming it with its spectrum), well-determined parameters as least squares says, and no
RuntimeWarning from emcee.

Synthetic spectra: three of R0 + R1||C1 + R2||C2 (R0 shared) with 0.5 % complex noise, fixed
seeds; in the "open" set R2 of trial 2 is 1e12 Ω beside C2 = 10 mF (its branch carries ~1e-13
of the current at 0.05 Hz, so the data cannot tell R2 from an open circuit); in the "bound" set
R2||CPE2 has α = 1.03, so the fit stops at α = 1 in every spectrum.
"""

import warnings

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.bayes import chain, shared_posterior

FREQ = np.geomspace(0.05, 1e5, 36)
MODEL = "R0 + R1 || C1 + R2 || C2"
BOUND_MODEL = "R0 + R1 || C1 + R2 || CPE2"


def parallel(f, r, q, alpha=1.0):
    """R || CPE (a capacitor for α = 1): r / (1 + r q (jω)^α)."""
    return r / (1 + r * q * (2j * np.pi * f) ** alpha)


def spectra(r2, *, alpha=1.0, seed=0):
    """Three noisy spectra along ``trial``: R0 = 10 Ω, R1 = 100/120/140 Ω, C1 = 1 µF, R2 as given,
    C2 (or CPE2's Q) = 10 mF with exponent ``alpha``."""
    rng = np.random.default_rng(seed)
    z = np.array([10.0 + parallel(FREQ, 100.0 * (1 + 0.2 * k), 1e-6) + parallel(FREQ, r, 1e-2, alpha) for k, r in enumerate(r2)])
    noise = 0.005 * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape)) / np.sqrt(2)
    return ix.make_spectrum(FREQ, z * (1 + noise), dims=("trial",), coords={"trial": [0, 1, 2]})


def quiet_sample(model, data, **kw):
    """`ix.sample` with every RuntimeWarning an error (emcee's red_blue.py warns when it subtracts
    the −∞ log-probabilities of walkers started outside the support)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        return ix.sample(model, data, shared=["R0"], over="trial", progress=False, **kw)


@pytest.fixture(scope="module")
def open_branch():
    return quiet_sample(MODEL, spectra([50.0, 80.0, 1e12]), steps=300, seed=1)


@pytest.fixture(scope="module")
def determined():
    return quiet_sample(MODEL, spectra([50.0, 80.0, 60.0]), steps=300, seed=1)


# --- (a) the start ------------------------------------------------------------------------------


def test_start_at_bounds_is_strictly_inside_the_support():
    """α fitted at its upper bound 1 (sampled as ln α: y0 = 0 = the top of its support) and R at
    the bottom of its prior: a ball around the start would put half the walkers outside. Every
    walker starts inside, finite, and spread on the inner side (not piled on the bound)."""
    lo_y, hi_y = chain.support_in_sampled_space([(0.0, 1.0), (1e-3, 1e3)], [True, True])

    def log_prob(y):
        y = np.atleast_2d(y)
        inside = (y[:, 0] <= hi_y[0]) & (y[:, 1] > lo_y[1]) & (y[:, 1] <= hi_y[1])
        return np.where(inside, -0.5 * ((np.exp(y[:, 0]) - 0.99) / 0.01) ** 2 - 0.5 * (y[:, 1] / 0.5) ** 2, -np.inf)

    start = [1.0, 1e-3 * (1 + 1e-6)]
    kw = dict(walkers=40, seed=5, lo_y=lo_y, hi_y=hi_y, log_prob_one=lambda y: float(log_prob(y)[0]), log_prob_all=log_prob, where="the test start")
    p0 = chain.start_walkers(start, [True, True], np.array([0.01, 0.01]), **kw)
    assert np.all(np.isfinite(log_prob(p0)))
    assert np.all((p0 > lo_y) & (p0 < hi_y))
    assert np.unique(p0[:, 0]).size == 40 and np.unique(p0[:, 1]).size == 40  # reflected, not clipped onto the bound
    np.testing.assert_array_equal(p0, chain.start_walkers(start, [True, True], np.array([0.01, 0.01]), **kw))  # deterministic for a seed


def test_joint_start_with_fits_at_bound_has_no_infinite_walkers(monkeypatch):
    """The joint posterior's own log-probability at its own start: CPE2.α at 1 in all three
    spectra (before the fix 58 of 68 walkers started at −∞)."""
    seen = {}

    def recording(*args, **kw):
        p0 = chain.start_walkers(*args, **kw)
        seen["lp"] = np.asarray(kw["log_prob_all"](p0))
        seen["p0"], seen["lo"], seen["hi"] = p0, kw["lo_y"], kw["hi_y"]
        return p0

    monkeypatch.setattr(shared_posterior, "start_walkers", recording)
    post = quiet_sample(BOUND_MODEL, spectra([50.0, 70.0, 90.0], alpha=1.03), steps=2, burn=0, seed=2)
    assert bool(post.fit.dataset["at_bound"].sel(param="CPE2.alpha").all())  # the case under test
    assert np.all(np.isfinite(seen["lp"]))
    assert np.all((seen["p0"] > seen["lo"]) & (seen["p0"] < seen["hi"]))


def test_spread_walkers_do_not_follow_a_meaningless_covariance():
    """A parameter spread over 90 decades whose fit covariance is numerical noise (the battery
    cycle's R2 at 3.8e84 Ω, variance 6e22): the others follow it only within 2 standard errors,
    so no walker is thrown outside the support."""
    lo_y, hi_y = chain.support_in_sampled_space([(1e-4, 1e88), (1e-3, 1e3)], [True, True])

    def log_prob(y):
        y = np.atleast_2d(y)
        return np.where((y[:, 0] > lo_y[0]) & (y[:, 0] <= hi_y[0]) & (y[:, 1] > lo_y[1]) & (y[:, 1] <= hi_y[1]), -0.5 * ((np.exp(y[:, 1]) - 2.4) / 0.05) ** 2, -np.inf)

    cov = np.array([[6e22, 3.3e7], [3.3e7, 2.8e-3]])
    p0 = chain.start_walkers(
        [3.8e84, 2.4], [True, True], np.array([1e-3, 1e-3]), walkers=40, seed=0, lo_y=lo_y, hi_y=hi_y,
        log_prob_one=lambda y: float(log_prob(y)[0]), log_prob_all=log_prob, where="the test start", wide=[(1e-4, 1e88), None], covariance=cov,
    )
    assert np.all(np.isfinite(log_prob(p0)))
    assert np.ptp(p0[:, 0]) / np.log(10) > 20  # R spread over tens of decades
    assert np.all(np.abs(np.exp(p0[:, 1]) - 2.4) < 0.01)  # its follower stays at its fit


# --- (b) a parameter one spectrum cannot determine --------------------------------------------


def test_undetermined_parameter_gets_a_wide_interval_and_a_named_warning(open_branch):
    """R2 of trial 2 runs open: its 90 % interval spans many decades (before the fix 2, 4.8e36 to
    6.2e38 Ω, near the fit, with no warning naming it), and a warning names R2[trial=2]; the
    determined R2 of the other spectra stay narrow."""
    q = open_branch.quantiles()
    decades = float(np.log10(q["q95"].sel(param="R2[trial=2]") / q["q05"].sel(param="R2[trial=2]")))
    assert decades > 5  # (30 with seed 1: log-uniform over its prior from ~1e7 Ω, where R2 starts to matter, up)
    assert float(q["q05"].sel(param="R2[trial=2]")) > 1e4  # still bounded below by the data (R2 ≲ 1e3 Ω would show)
    assert any("R2[trial=2]" in w for w in open_branch.warnings)
    for n in ("R2[trial=0]", "R2[trial=1]"):
        assert float(q["q95"].sel(param=n) / q["q05"].sel(param=n)) < 1.2  # ±2 % where the data fix R2
        assert not any(n in w for w in open_branch.warnings)


# --- (c) a well-determined joint posterior ------------------------------------------------------


def test_determined_parameters_match_least_squares_without_spurious_warnings(determined):
    """Every parameter determined: the posterior's 90 % half-width within a factor 2 of the
    linearised 1.645·stderr of the global fit (a Gaussian posterior gives 1; 300 steps, ESS ≳ 600
    per parameter, so the quantiles are good to ~10 %), and no prior-edge or interval warning."""
    q = determined.quantiles()
    se = determined.fit.dataset["linearised_stderr"]
    for n in determined.names:
        if n == "sigma_rel":
            continue
        base, trial = (n.split("[")[0], int(n.split("=")[1][:-1])) if "[" in n else (n, 0)
        half = 0.5 * float(q["q95"].sel(param=n) - q["q05"].sel(param=n))
        ratio = half / (1.645 * float(se.sel(param=base, trial=trial)))
        assert 0.5 < ratio < 2.0, (n, ratio)
    assert not [w for w in determined.warnings if "piles up" in w or "linearised" in w]


def test_interval_warning_reuses_the_single_spectrum_rule(open_branch, determined):
    """The joint posterior's convergence rule is `Posterior`'s; its bounds strip the spectrum."""
    assert type(open_branch).chain_converged is ix.Posterior.chain_converged
    lower, upper = open_branch.bounds
    assert lower[open_branch.names.index("R2[trial=2]")] == 0.0 and upper[open_branch.names.index("R2[trial=2]")] == np.inf


# --- (d) no RuntimeWarning ------------------------------------------------------------------------


def test_no_runtime_warning_when_fits_sit_at_bounds():
    """The at-bound case that leaked emcee's 'invalid value encountered in scalar subtract'
    (walkers at −∞ before the fix), sampled with RuntimeWarning as an error."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        post = ix.sample(BOUND_MODEL, spectra([50.0, 70.0, 90.0], alpha=1.03), shared=["R0"], over="trial", steps=60, seed=3, progress=False)
    assert np.all(np.isfinite(post.log_prob))
    assert any(w.startswith("CPE2.alpha[trial=") for w in post.warnings)  # piled up against α = 1, named per spectrum
