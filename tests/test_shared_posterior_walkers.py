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


@pytest.mark.slow  # (the suite's 15-minute budget, 2026-12-01: make test-all runs it)
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


@pytest.fixture(scope="module")
def capacitor_and_open():
    """R2 || CPE2 with α truly 1 (a capacitor) in every spectrum, R2 of trial 2 open (1e12 Ω)."""
    return ix.sample("R0 + R1 || C1 + R2 || CPE2", spectra([50.0, 80.0, 1e12], alpha=1.0), shared=["R0"], over="trial", steps=300, seed=1, progress=False)


def test_a_joint_posterior_words_an_exponent_at_one_as_a_single_spectrum_does(capacitor_and_open):
    """α piled up against 1 where it is truly 1: a CPE that is a capacitor, as a single spectrum's
    posterior says (`diagnostics.reducing_bounds`, keyed by circuit parameter), not "the data
    would take larger values (is the model missing something?)" (before 2026-12-03, every
    per-spectrum CPE2.alpha[trial=k])."""
    piled = [w for w in capacitor_and_open.warnings if w.startswith("CPE2.alpha[trial=") and "piles up against its upper bound 1" in w]
    assert piled  # (trial 0 and 2 with seed 1)
    for w in piled:
        name = w.split(" ")[0]
        assert f"the data are consistent with {name} = 1, and CPE2 with alpha = 1 is a capacitor: the model with C2 in its place may be enough" in w
        assert "missing something" not in w


def test_a_joint_posterior_marks_a_parameter_its_start_leaves_undetermined(capacitor_and_open):
    """The open R2 of trial 2 (run to ∞ by the start fit, no standard error) is marked in the
    table, named under it and listed in the JSON, as a single spectrum's posterior does; the
    determined R2 of trials 0 and 1 are not."""
    post = capacitor_and_open
    assert post.undetermined == ("R2[trial=2]",) and post.summary()["undetermined"] == ["R2[trial=2]"]
    rows = {line.split()[0]: line for line in post.report().splitlines() if line.split() and line.split()[0] in post.names}
    assert rows["R2[trial=2]"].endswith("← NOT DETERMINED")
    assert not [n for n, line in rows.items() if "NOT DETERMINED" in line and n != "R2[trial=2]"]
    assert "← R2[trial=2]: not determined by the data" in post.report()


def test_a_joint_posterior_repeats_its_start_fits_warnings_without_advising_to_sample(capacitor_and_open):
    """The start fit's "α within 2 standard errors of its bound" ends "for an honest interval,
    sample the posterior (impedax sample)": the posterior's report, that sample, leaves it out."""
    advice = "for an honest interval, sample the posterior (impedax sample)"
    assert any(advice in w for ws in capacitor_and_open.fit.warnings.values() for w in ws)  # (the case under test)
    near = [w for w in capacitor_and_open.warnings if "lies within 2 standard errors of its upper bound 1" in w]
    assert near and all(w.endswith("the ± is not symmetric there (no value lies beyond the bound)") for w in near)
    assert not any("impedax sample" in w for w in capacitor_and_open.warnings)


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
    assert not [w for w in determined.warnings if "not the data, sets" in w or "linearised" in w]
    assert determined.undetermined == () and "NOT DETERMINED" not in determined.report()


def test_a_short_chain_is_not_converged_and_the_interval_warning_says_so(open_branch):
    """300 steps against τ ≈ 20 steps (the rule: a kept chain of 50 τ, as a single spectrum's):
    not converged, the chain-length warning given, and the interval warning about the open R2
    says the chain is too short to tell which interval is right; its bounds strip the spectrum."""
    assert open_branch.chain_converged is False
    assert any(w.startswith("the chain (225 draws per walker after burn-in) is shorter than 50 autocorrelation times") for w in open_branch.warnings)
    interval = [w for w in open_branch.warnings if w.startswith("the least-squares start's linearised standard errors")]
    assert len(interval) == 1 and "R2[trial=2]" in interval[0]
    assert interval[0].endswith("the chain is too short to tell which is right (see the chain-length warning); run more steps before using either")
    lower, upper = open_branch.bounds
    assert lower[open_branch.names.index("R2[trial=2]")] == 0.0 and upper[open_branch.names.index("R2[trial=2]")] == np.inf


def test_too_few_draws_to_estimate_tau_is_not_converged():
    """40 kept draws per walker: τ unknown (NaN), so not converged, and the warning says the
    chain is too short to estimate τ."""
    post = quiet_sample(MODEL, spectra([50.0, 80.0, 60.0]), steps=40, burn=0, seed=1)
    assert post.chain_converged is False and all(np.isnan(t) for t in post.autocorr.values())
    assert any(w.startswith("the chain is too short to estimate τ (40 draws per walker after burn-in") for w in post.warnings)


def _with_draws(post, draws, log_prob):
    """``post`` with its chain replaced (walker, draw[, param]); its caches start empty."""
    import dataclasses

    return dataclasses.replace(post, draws=draws, log_prob=log_prob)


def test_a_chain_many_autocorrelation_times_long_is_converged(determined):
    """The determined joint posterior's own draws, 200 per walker: independent (each walker's
    drawn at random from all of them, τ ≈ 1 step) they are ≥ 50 τ long, so converged, with no
    chain-length warning; the same values sorted along each walker's chain (a slow drift, τ of
    the order of the chain) are not. (A real run of this case needs ≳ 9000 steps to reach 50 τ,
    τ ≳ 140 steps: too slow for a unit test.) With the start's standard errors made 10× too
    large, the converged chain's interval warning says to use the posterior's intervals."""
    import dataclasses

    rng = np.random.default_rng(0)
    w, p = determined.n_walkers, len(determined.names)
    flat, flat_lp = determined.draws.reshape(-1, p), determined.log_prob.reshape(-1)
    pick = rng.integers(0, flat.shape[0], size=(w, 200))
    independent = _with_draws(determined, flat[pick], flat_lp[pick])
    assert independent.chain_converged is True
    assert independent.n_draws >= 50 * max(independent.autocorr.values())
    assert not [x for x in independent.warnings if "autocorrelation times" in x or "too short" in x]

    drifting = _with_draws(determined, np.sort(flat[pick], axis=1), flat_lp[pick])
    assert drifting.chain_converged is False
    assert any("is shorter than 50 autocorrelation times" in x for x in drifting.warnings)

    ds = independent.fit.dataset
    inflated = dataclasses.replace(independent, fit=dataclasses.replace(independent.fit, dataset=ds.assign(linearised_stderr=ds["linearised_stderr"] * 10)))
    interval = [x for x in inflated.warnings if x.startswith("the least-squares start's linearised standard errors")]
    assert len(interval) == 1 and "R1[trial=0] (" in interval[0]
    assert interval[0].endswith("use the posterior's intervals — they follow the model's non-linearity, the parameters' bounds and the priors; the linearised errors are a local approximation at the fit")


# --- the start fit's warnings, by spectrum ------------------------------------------------------


def test_start_fit_warnings_name_their_spectrum(open_branch):
    """The open R2 of trial 2: the start fit's warnings are trial 2's alone, and each line says so
    (before: "least-squares start: R2 has ..." with no spectrum)."""
    start = [w for w in open_branch.warnings if w.startswith("least-squares start")]
    assert len(start) == len(open_branch.fit.warnings["trial=2"]) == 2
    assert all(w.startswith("least-squares start (1 of 3 spectra: trial 2): ") for w in start)
    assert {w.split("): ", 1)[1] for w in start} == set(open_branch.fit.warnings["trial=2"])


def test_start_fit_warnings_shared_by_spectra_are_given_once(determined):
    """The same text in every spectrum is one line naming all of them; texts equal but for their
    numbers one line with the numbers as a range and the spectra named; a global fit's own note
    as its scope (the grouping of a batch fit's report)."""
    import dataclasses

    notes = {
        "trial=0": ("C2 is near its bound", "R2 has a relative standard error of 120 %: it is not determined by the data"),
        "trial=1": ("C2 is near its bound",),
        "trial=2": ("C2 is near its bound", "R2 has a relative standard error of 340 %: it is not determined by the data"),
        "shared over trial": ("the shared R0 moves the others",),
    }
    post = dataclasses.replace(determined, fit=dataclasses.replace(determined.fit, warnings=notes))
    start = [w for w in post.warnings if w.startswith("least-squares start")]
    assert start == [
        "least-squares start (all 3 spectra): C2 is near its bound",
        "least-squares start (2 of 3 spectra: trial 0, 2): R2 has a relative standard error of 120 to 340 %: it is not determined by the data",
        "least-squares start (shared over trial): the shared R0 moves the others",
    ]


def test_many_kinds_of_start_fit_warning_say_how_many_more():
    """Past the kinds a report lists (`WARNING_GROUPS_SHOWN`), one line counts the rest."""
    from impedax.warning_groups import WARNING_GROUPS_SHOWN

    notes = {f"trial={i}": (f"note {chr(97 + i)}",) for i in range(WARNING_GROUPS_SHOWN + 3)}
    lines = shared_posterior._start_fit_warnings(notes, len(notes))
    assert len(lines) == WARNING_GROUPS_SHOWN + 1
    assert all(line.startswith(f"least-squares start (1 of {len(notes)} spectra: trial ") for line in lines[:-1])
    assert lines[-1].startswith("least-squares start: 3 more kinds of warning")


# --- (d) no RuntimeWarning ------------------------------------------------------------------------


@pytest.mark.slow  # (15 s: make test-all; the suite's budget)
def test_no_runtime_warning_when_fits_sit_at_bounds():
    """The at-bound case that leaked emcee's 'invalid value encountered in scalar subtract'
    (walkers at −∞ before the fix), sampled with RuntimeWarning as an error."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        post = ix.sample(BOUND_MODEL, spectra([50.0, 70.0, 90.0], alpha=1.03), shared=["R0"], over="trial", steps=60, seed=3, progress=False)
    assert np.all(np.isfinite(post.log_prob))
    assert any(w.startswith("CPE2.alpha[trial=") for w in post.warnings)  # piled up against α = 1, named per spectrum


def test_a_joint_posteriors_table_marks_the_rows_its_report_marks(capacitor_and_open):
    """The CSV table (`to_table`) has the ``undetermined`` column of a single spectrum's posterior
    (added 2026-12-06): true on the rows the text report marks NOT DETERMINED (read back from it)."""
    post = capacitor_and_open
    marked = {line.split()[0] for line in post.report().splitlines() if line.split() and line.split()[0] in post.names and line.endswith("← NOT DETERMINED")}
    assert "R2[trial=2]" in marked
    assert {r["name"] for r in post.to_table() if r["undetermined"]} == marked
