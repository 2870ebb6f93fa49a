"""The sampler's chain length (``steps="auto"``), acceptance rule, interval warning, start-up
lines and signatures.

Oracles: emcee itself (its autocorrelation estimator, its stretch move on Gaussians and on a
flat log-probability), closed forms (τ of an AR(1) series, the stretch move's acceptance on a
flat target), numpy quantiles of the draws. Fixed seeds; bounds are several standard errors
wide and say why.
"""

import inspect
import json
import math

import emcee
import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting import Posterior
from impedax.fitting.bayes import chain, progress, sampler
from impedax.fitting.bayes.hierarchical import HierarchicalPosterior
from impedax.fitting.bayes.diagnostics import (
    ACCEPTANCE_STUCK, CHAIN_TAU_MULTIPLE, GAUSSIAN_ACCEPTANCE, acceptance_ceiling, acceptance_warnings, flat_acceptance, integrated_autocorr, interval_warnings,
)
from spectra import CASES, noisy, rc


def _flat_spectrum(seed=0, n=20):
    """A 100 Ω resistor with 1 % complex noise: ``R1`` has two sampled parameters (R1,
    sigma_rel) and a cheap log-probability."""
    f = np.geomspace(1, 1e4, n)
    rng = np.random.default_rng(seed)
    z = 100.0 * (1 + 0.01 * (rng.normal(size=n) + 1j * rng.normal(size=n)) / np.sqrt(2))
    return ix.make_spectrum(f, z)


def _emcee_tau(chain_y):
    """τ [draws] by emcee's own estimator (the oracle of `integrated_autocorr`)."""
    return emcee.autocorr.integrated_time(np.transpose(chain_y, (1, 0, 2)), c=5, tol=0, quiet=True)


def _ar1(phi, walkers, draws, params, seed):
    """AR(1) chains x_t = φ x_(t−1) + ε_t, started in their stationary law: τ = (1 + φ)/(1 − φ)."""
    rng = np.random.default_rng(seed)
    x = np.empty((walkers, draws, params))
    x[:, 0] = rng.normal(size=(walkers, params)) / math.sqrt(1 - phi**2)
    for t in range(1, draws):
        x[:, t] = phi * x[:, t - 1] + rng.normal(size=(walkers, params))
    return x


def _stretch_acceptance(log_prob, p0, steps, seed):
    s = emcee.EnsembleSampler(p0.shape[0], p0.shape[1], log_prob, vectorize=True)
    s.random_state = np.random.RandomState(seed).get_state()
    s.run_mcmc(p0, steps, skip_initial_state_check=True)
    return float(np.mean(s.acceptance_fraction))


# --- autocorrelation ---------------------------------------------------------------------------


def test_integrated_autocorr_is_emcees_estimator_and_the_ar1_closed_form():
    """One FFT per parameter for all walkers gives emcee's estimate to rounding, and on AR(1)
    chains of φ = 0.8 (τ = 9) and φ = 0 (τ = 1) it is near the closed form (the estimate of 32
    walkers × 2000 draws has a relative sd of ~3 %: 20 % is loose)."""
    chain = np.concatenate([_ar1(0.8, 32, 2000, 2, seed=1), _ar1(0.0, 32, 2000, 1, seed=2)], axis=2)
    ours = integrated_autocorr(chain)
    np.testing.assert_allclose(ours, _emcee_tau(chain), rtol=1e-10)
    np.testing.assert_allclose(ours, [9.0, 9.0, 1.0], rtol=0.2)
    stuck = chain.copy()
    stuck[5, :, 1] = stuck[5, 0, 1]  # one walker never moves in parameter 1
    tau = integrated_autocorr(stuck)
    assert math.isfinite(tau[0]) and math.isnan(tau[1]) and math.isfinite(tau[2])


# --- acceptance ----------------------------------------------------------------------------------


def test_flat_acceptance_is_the_stretch_moves_on_a_flat_log_probability():
    """With ln p ≡ 0 every proposal is accepted with probability min(1, z^(d−1)): the closed
    form matches emcee's count over 64 walkers × 400 steps (binomial sd ≤ 0.003; 0.015 allows
    for the correlation of a walker's decisions)."""
    assert flat_acceptance(1) == pytest.approx(1.0)
    for d in (2, 5, 12):
        p0 = np.random.default_rng(d).normal(size=(64, d))
        measured = _stretch_acceptance(lambda x: np.zeros(len(x)), p0, 400, seed=d)
        assert measured == pytest.approx(flat_acceptance(d), abs=0.015), d


@pytest.mark.parametrize("d", [1, 3, 6, 10, 15])
def test_a_healthy_gaussian_posterior_raises_no_acceptance_warning(d):
    """emcee on a correlated d-dimensional Gaussian (scales over four decades, random rotation),
    walkers drawn from it: the acceptance is the tabulated one (GAUSSIAN_ACCEPTANCE: the move is
    affine-invariant; 64 walkers × 1500 steps, sd ≈ 0.003, so 0.02 is loose) and below the
    ceiling, so no warning; a flat log-probability in d dimensions is above it."""
    rng = np.random.default_rng(100 + d)
    q, _ = np.linalg.qr(rng.normal(size=(d, d)))
    cov = (q * np.geomspace(1e-4, 1.0, d) ** 2) @ q.T
    precision = np.linalg.inv(cov)
    p0 = rng.multivariate_normal(np.zeros(d), cov, size=64)
    acc = _stretch_acceptance(lambda x: -0.5 * np.einsum("wi,ij,wj->w", x, precision, x), p0, 1500, seed=d)
    assert acc == pytest.approx(GAUSSIAN_ACCEPTANCE[d - 1], abs=0.02)
    assert acc < acceptance_ceiling(d) and acceptance_warnings(acc, d) == []
    flat = flat_acceptance(d)
    assert flat > acceptance_ceiling(d)
    (warning,) = acceptance_warnings(flat, d)
    assert "barely changes across the walkers' moves" in warning and "prior-dominated" in warning


def test_the_old_upper_limit_flagged_healthy_runs_the_new_one_does_not():
    """0.6 was below a healthy Gaussian's acceptance for up to 3 parameters (0.65–0.81), so R0 +
    R1 ∥ C1's 4 sampled parameters at 0.59–0.60 were on its edge; a stuck chain still warns."""
    assert all(GAUSSIAN_ACCEPTANCE[d - 1] > 0.6 for d in (1, 2, 3))
    assert not acceptance_warnings(0.62, 4) and not acceptance_warnings(0.80, 1)
    (stuck,) = acceptance_warnings(0.05, 5)
    assert stuck.startswith(f"mean acceptance fraction 0.050 is below {ACCEPTANCE_STUCK}: the sampler is stuck")


# --- which interval to trust ------------------------------------------------------------------------


def test_interval_warning_names_the_parameters_and_says_which_to_use():
    lin = {"R0": 1.0, "R1": 3.0, "C1": 0.4, "Q": math.nan}
    half = {"R0": 1.1, "R1": 1.0, "C1": 1.0, "Q": 1.0}
    (text,) = interval_warnings(lin, half, chain_converged=True, at_bound=("C1",))
    assert "R1 (3×)" in text and "C1 (0.4×; its fit is at a bound)" in text and "R0" not in text and "Q" not in text
    assert "use the posterior's intervals" in text
    (short,) = interval_warnings(lin, half, chain_converged=False)
    assert "too short to tell which is right" in short and "use the posterior's" not in short
    assert interval_warnings({"R0": 1.9}, {"R0": 1.0}, chain_converged=True) == []


def _named_by_interval_warning(post):
    """The parameters whose linearised stderr and numpy's q16–q84 half-width of the draws differ
    by more than 2×, and the interval warning(s) of ``post``."""
    lin, draws = post.fit.linearised_stderr, post.samples
    ratio = {n: lin[n] / (0.5 * (np.quantile(draws[n], 0.84) - np.quantile(draws[n], 0.16))) for n in post.fit.free_names}
    off = sorted(n for n, r in ratio.items() if r > 2 or r < 0.5)
    return off, ratio, [w for w in post.warnings if w.startswith("the least-squares start's linearised standard errors")]


def test_a_fit_at_a_bound_gets_the_interval_warning():
    """R0 + R1 ∥ C1 measured only below 30 Hz (R0 = 20 Ω): the fit stops at the bound R0 = 0,
    and its linearisation, which ignores the bound, makes R0, R1 and C1 (tied to R0 along the
    ridge R0 + R1 = const) 7–10× less certain than the posterior, which respects it. The warning
    names exactly the parameters numpy's quantiles put beyond 2×; with 1500 steps the chain is
    shorter than 50 τ, so it says neither is to be trusted yet."""
    truth = {"R0": 20.0, "R1": 1000.0, "C1": 1e-6}
    f = np.geomspace(0.1, 30, 30)
    data = ix.make_spectrum(f, noisy(rc(f, truth), 0.01, np.random.default_rng(0)))
    post = ix.sample("R0 + R1 || C1", data, steps=1500, seed=1, progress=False)
    off, ratio, found = _named_by_interval_warning(post)
    assert off == ["C1", "R0", "R1"], ratio
    (w,) = found
    assert sorted(n for n in post.fit.free_names if f"{n} (" in w) == off and "R0 (" in w and "its fit is at a bound" in w
    assert not post.chain_converged and "too short to tell which is right" in w


def test_a_posterior_the_data_pin_gets_no_interval_warning():
    """r_cpe data: the fit's linearised errors and the posterior's widths agree (within 2× by
    numpy's quantiles), and no warning is raised."""
    text, fn, truth, (lo, hi) = CASES["r_cpe"]
    f = np.geomspace(lo, hi, 40)
    data = ix.make_spectrum(f, noisy(fn(f, truth), 0.01, np.random.default_rng(7)))
    post = ix.sample(text, data, steps=600, seed=1, progress=False)
    off, ratio, found = _named_by_interval_warning(post)
    assert off == [] and found == [], (ratio, found)


@pytest.mark.slow
def test_on_the_real_battery_the_posterior_interval_is_the_one_to_use():
    """AutoEIS's real battery cycle 0 with R0 + R1 ∥ CPE1 + R2 ∥ CPE2 + W1 (CPE2's α at its
    bound 1): run to 50 τ, the posterior is 2–6× narrower than the linearisation for R1, R2 and
    CPE2.alpha, and the warning says to use the posterior's intervals."""
    from pathlib import Path

    data = ix.load(Path(__file__).resolve().parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc").isel(cycle=0)
    post = ix.sample("R0 + R1 || CPE1 + R2 || CPE2 + W1", data, seed=1, progress=False)
    off, ratio, found = _named_by_interval_warning(post)
    assert post.chain_converged and {"R1", "R2", "CPE2.alpha"} <= set(off), ratio
    (w,) = found
    assert sorted(n for n in post.fit.free_names if f"{n} (" in w) == off and "use the posterior's intervals" in w


# --- steps="auto" ---------------------------------------------------------------------------------


@pytest.mark.slow  # (the suite's 15-minute budget, 2026-12-01: make test-all runs it)
def test_auto_runs_until_the_kept_chain_is_fifty_tau_long():
    """steps="auto" stops on its own: the kept chain (after a quarter of the steps run) is at
    least 50 τ long by emcee's estimator (both parameters are sampled as ln x), so no
    chain-length warning; the settings say how many steps ran and that the length was
    automatic."""
    post = ix.sample("R1", _flat_spectrum(), walkers=16, seed=1, progress=False)
    steps = post.settings["steps"]
    assert post.settings["steps_mode"] == "auto" and post.settings["stopped"] == "converged"
    assert post.settings["burn"] == steps // 4 and post.n_draws == steps - steps // 4
    assert steps < sampler.AUTO_MAX_STEPS
    tau = _emcee_tau(np.log(post.draws))
    assert post.n_draws >= CHAIN_TAU_MULTIPLE * tau.max(), (post.n_draws, tau)
    assert not [w for w in post.warnings if "autocorrelation times" in w or "τ" in w], post.warnings
    summary = post.summary()
    assert summary["steps"] == steps and summary["steps_mode"] == "auto" and summary["step_cap"] == sampler.AUTO_MAX_STEPS
    assert "automatic: stopped at 50 τ" in post.report()


def test_auto_stops_at_its_cap_and_says_so(monkeypatch):
    """A cap of 300 steps (monkeypatched; the real one is 20 000): the run stops there, the
    kept chain is shorter than 50 τ by emcee's estimator, and the chain-length warning says the
    cap was reached."""
    monkeypatch.setattr(chain, "AUTO_MAX_STEPS", 300)
    post = ix.sample("R1", _flat_spectrum(), walkers=16, seed=1, progress=False)
    assert post.settings["steps"] == 300 and post.settings["stopped"] == "cap" and post.settings["step_cap"] == 300
    assert post.n_draws == 300 - 75
    assert post.n_draws < CHAIN_TAU_MULTIPLE * _emcee_tau(np.log(post.draws)).max()
    capped = [w for w in post.warnings if "the automatic chain length stopped at its cap of 300 steps" in w]
    assert len(capped) == 1 and "shorter than 50 autocorrelation times" in capped[0], post.warnings
    assert "automatic: stopped at its cap of 300 steps" in post.report()
    back = Posterior.from_xarray(post.to_xarray())  # (the settings travel with the draws)
    assert back.settings == post.settings and any("stopped at its cap of 300 steps" in w for w in back.warnings)


def _gaussian_with_a_trap(coords):
    """ln p of a standard 2-D Gaussian, and a constant −40 in a box 1e-3 wide about (100, 100):
    a walker started there never moves (every stretch proposal lands where ln p ≈ −5000), its
    median ln p ~39 nats below the others' (a straggler, `STRAGGLER_LOG_PROB_GAP` 20)."""
    coords = np.asarray(coords, float)
    trapped = np.all(np.abs(coords - 100.0) < 5e-4, axis=-1)
    return np.where(trapped, -40.0, -0.5 * np.sum(coords**2, axis=-1))


def test_auto_stops_on_the_kept_walkers_tau_a_stuck_straggler_does_not_hold_it(monkeypatch):
    """The stop rule estimates τ on the walkers the posterior keeps (stragglers left out, as
    `without_stragglers`): a straggler stuck since its start made every τ unknown (0/0), so the
    run went on to its cap (here 6 000 steps, monkeypatched) though the kept chain was 50 τ long
    long before. Oracle: emcee's own estimator on the kept chain."""
    monkeypatch.setattr(chain, "AUTO_MAX_STEPS", 6000)
    rng = np.random.default_rng(3)
    p0 = rng.normal(size=(16, 2))
    p0[0] = 100.0  # (walker 0 in the trap)
    run = chain.run_emcee(p0, _gaussian_with_a_trap, steps="auto", burn=None, thin=1, seed=3, progress=False)
    assert run.stragglers.walkers == (0,)
    assert run.stopped == "converged" and run.steps < 6000, (run.stopped, run.steps)
    assert run.chain_y.shape[0] == 15 and run.chain_y.shape[1] == run.steps - run.steps // 4
    tau = _emcee_tau(run.chain_y)
    assert run.chain_y.shape[1] >= CHAIN_TAU_MULTIPLE * tau.max(), (run.chain_y.shape, tau)
    # the straggler's chain is constant: with it τ is unknown, which is what held the old rule
    assert not np.all(np.isfinite(integrated_autocorr(np.concatenate([np.full((1, run.chain_y.shape[1], 2), 100.0), run.chain_y]))))


def _joint_stack(seed=0, n=20):
    """Two SYNTHETIC R0 + R1 || C1 spectra (1 % proportional noise) with R0 common."""
    f = np.geomspace(1.0, 1e5, n)
    rng = np.random.default_rng(seed)
    z = [noisy(rc(f, {"R0": 50.0, "R1": r1, "C1": c1}), 0.01 / np.sqrt(2), rng) for r1, c1 in ((800.0, 2e-7), (1500.0, 5e-7))]
    return ix.make_spectrum(f, np.stack(z), dims=("trial",))


def test_the_cap_keeps_a_large_joint_chain_in_memory():
    """20 000 steps for the battery circuit (64 walkers, 9 parameters: 12.8 M numbers); a joint
    posterior of 60 parameters and 240 walkers is held to 30 M numbers (2 049 steps, 240 MB;
    20 000 steps would keep 2.3 GB); 5 000 walkers of one parameter to 30 M / (5 000 × 2) =
    3 000 steps, and 10⁶ walkers to 15."""
    assert chain.auto_step_cap(64, 9) == 20_000
    assert chain.auto_step_cap(240, 60) == 30_000_000 // (240 * 61) == 2049
    assert chain.auto_step_cap(5000, 1) == 3000 and chain.auto_step_cap(5000, 0) == 6000
    assert chain.auto_step_cap(10**6, 1) == 15


@pytest.mark.slow  # (an end-to-end run of ~10 s: make test-all; the fast suite's 15-minute budget)
def test_a_joint_posterior_stops_by_the_same_rule(monkeypatch):
    """steps="auto" (the default) with ``shared=``: the joint sampler runs the single one's rule
    and says so (here stopped at a monkeypatched cap of 300 steps, then from the .nc)."""
    monkeypatch.setattr(chain, "AUTO_MAX_STEPS", 300)
    post = ix.sample("R0 + R1 || C1", _joint_stack(), shared=["R0"], over="trial", seed=1, progress=False)
    assert post.settings["steps"] == 300 and post.settings["stopped"] == "cap" and post.settings["steps_mode"] == "auto"
    assert post.settings["burn"] == 75 and post.n_draws == 225
    capped = [w for w in post.warnings if "the automatic chain length stopped at its cap of 300 steps" in w]
    assert len(capped) == 1 and "shorter than 50 autocorrelation times" in capped[0], post.warnings
    assert "300 steps (automatic: stopped at its cap of 300 steps; burn 75" in post.report()
    summary = post.summary()
    assert (summary["steps_mode"], summary["step_cap"], summary["stopped"]) == ("auto", 300, "cap")
    back = type(post).from_xarray(post.to_xarray())
    assert back.settings == post.settings and any("stopped at its cap of 300 steps" in w for w in back.warnings)
    fixed = ix.sample("R0 + R1 || C1", _joint_stack(), shared=["R0"], over="trial", steps=120, seed=1, progress=False)
    assert fixed.settings["steps_mode"] == "fixed" and fixed.settings["burn"] == 30 and "stopped" not in fixed.settings
    with pytest.raises(ix.ParameterError, match="burn must be below the 300 steps"):
        ix.sample("R0 + R1 || C1", _joint_stack(), shared=["R0"], over="trial", burn=300, progress=False)


@pytest.mark.slow  # (about 10–15 s)
def test_a_joint_posterior_run_to_50_tau_does_not_warn_of_its_length():
    post = ix.sample("R0 + R1 || C1", _joint_stack(), shared=["R0"], over="trial", seed=1, progress=False)
    assert post.settings["stopped"] == "converged" and post.settings["steps"] < chain.AUTO_MAX_STEPS
    assert post.n_draws >= CHAIN_TAU_MULTIPLE * _emcee_tau(np.log(post.draws)).max()  # (every parameter, sigma_rel too, is sampled as ln x)
    assert not any("autocorrelation times" in w for w in post.warnings), post.warnings


def test_auto_with_thin_and_burn_keeps_what_they_say():
    post = ix.sample("R1", _flat_spectrum(), walkers=16, seed=2, burn=100, thin=3, progress=False)
    steps = post.settings["steps"]
    assert post.settings["burn"] == 100 and post.n_draws == (steps - 100) // 3
    assert post.n_draws >= CHAIN_TAU_MULTIPLE * _emcee_tau(np.log(post.draws)).max()


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        ({"steps": "many"}, "steps must be an integer, got 'many'"),
        ({"steps": "Auto"}, "or 'auto'"),
        ({"steps": 0}, "steps must be at least 1"),
        ({"steps": "auto", "burn": -1}, "burn must be at least 0"),
        ({"steps": "auto", "burn": 10**6}, "burn must be below the 20000 steps"),
    ],
)
def test_bad_steps_name_the_parameter(kwargs, fragment):
    with pytest.raises(ix.ParameterError, match=fragment):
        ix.sample("R1", _flat_spectrum(), progress=False, **kwargs)


def test_cli_steps_auto_and_json_keys(tmp_path, capsys, monkeypatch):
    """``--steps auto`` is the default; the JSON keeps its keys and adds steps_mode and
    step_cap; a word that is neither a number nor auto exits 2."""
    monkeypatch.setattr(chain, "AUTO_MAX_STEPS", 400)  # (the run's length is not what is tested)
    path = tmp_path / "r.csv"
    ix.save(_flat_spectrum(), path)
    assert main(["sample", str(path), "--model", "R1", "--walkers", "16", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert {"model", "params", "acceptance", "autocorr", "ess", "warnings", "walkers", "draws", "steps", "burn", "thin", "seed", "map"} <= set(doc)
    assert doc["steps_mode"] == "auto" and doc["step_cap"] == 400 and doc["draws"] == doc["steps"] - doc["burn"]
    assert main(["sample", str(path), "--model", "R1", "--steps", "50", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["steps"] == 50 and doc["steps_mode"] == "fixed" and doc["step_cap"] is None
    with pytest.raises(SystemExit) as stop:
        main(["sample", str(path), "--model", "R1", "--steps", "lots"])
    assert stop.value.code == 2 and "invalid int value: 'lots'" in capsys.readouterr().err


# --- what the user sees while it runs ------------------------------------------------------------


def test_progress_of_an_open_ended_run_shows_steps_and_the_estimate(monkeypatch, capsys):
    """No percentage for a run of unknown length: the steps so far, the steps needed as last
    estimated and the cap; the time to that estimate as the least left (1 s per step after the
    first: steps 2 → 10 need 8 s; the run may go on after it); the last step is reported when the
    run stops early."""
    clock = iter([0.0, 30.0, 31.0, 31.5, 32.0])
    monkeypatch.setattr(progress.time, "perf_counter", lambda: next(clock))
    bar = progress.ProgressLine(20000, True, label="run", interactive=False, open_ended=True)
    bar.update(1)
    assert capsys.readouterr().err == "run: step 1 (steps needed not yet estimated; at most 20000), 30 s\n"
    bar.set_target(10, "50 τ")
    bar.update(2)
    assert capsys.readouterr().err == "run: step 2 (≈10 needed for 50 τ; at most 20000), 31 s, ≥ ~8 s left\n"
    bar.update(3)  # (within the log interval: not shown)
    bar.close()
    assert capsys.readouterr().err == "run: step 3 (≈10 needed for 50 τ; at most 20000), 32 s, ≥ ~7 s left\n"


def test_sample_says_what_it_does_before_the_first_step(capsys):
    ix.sample("R1", _flat_spectrum(), steps=20, walkers=8, progress=True)
    lines = capsys.readouterr().err.splitlines()
    start = [i for i, line in enumerate(lines) if line.startswith("sample: fitting the least-squares start")]
    compiling = [i for i, line in enumerate(lines) if line.startswith("sample: compiling the log-probability") and "8 walkers" in line]
    assert start and compiling and start[0] < compiling[0], lines
    ix.sample("R1", _flat_spectrum(), steps=20, walkers=8, progress=False)
    assert capsys.readouterr().err == ""


# --- signatures ------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "fn", [ix.sample, Posterior, Posterior.from_xarray, ix.SharedPosterior.from_xarray, HierarchicalPosterior.from_xarray],
    ids=["sample", "Posterior", "from_xarray", "shared-from_xarray", "hierarchical-from_xarray"],
)
def test_signatures_do_not_print_the_element_registry(fn):
    """help() showed the whole default registry (6,000+ characters) as the default of
    ``registry``; None stands for it now."""
    signature = inspect.signature(fn)
    assert signature.parameters["registry"].default is None
    assert len(str(signature)) < 1500, len(str(signature))


def test_a_posterior_built_without_a_registry_uses_the_default():
    post = ix.sample("R1", _flat_spectrum(), steps=60, walkers=8, progress=False)
    assert post.registry is ix.DEFAULT_REGISTRY
    back = Posterior.from_xarray(post.to_xarray())
    assert back.registry is ix.DEFAULT_REGISTRY and back.settings["steps_mode"] == "fixed"


def test_an_interval_ratio_of_hundreds_is_written_without_a_power_of_ten():
    """REAL Autolab spectrum, R0 + (R1 + W1) ∥ CPE1 sampled 1500 steps: the warning named "R0
    (1.8e+02×)" (``:.2g``); a factor is written out from 1 to 10⁶, two significant digits as
    before (by hand: 183/1 → 180, 0.0042/1 → 0.0042, 2.5e7 keeps its power of ten)."""
    (text,) = interval_warnings({"R0": 183.0, "R1": 0.0042, "C1": 2.5e7}, {"R0": 1.0, "R1": 1.0, "C1": 1.0}, chain_converged=True)
    assert "R0 (180×)" in text and "R1 (0.0042×)" in text and "C1 (2.5e+07×)" in text, text
