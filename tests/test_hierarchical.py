"""The hierarchical model across trials: it recovers the population median and the spread
between trials of synthetic two-arc spectra (written by an independent numpy formula), its
discrepancy floor widens intervals under structured misfit and not without it, an error shared by
every trial is marginalised exactly (against a dense Gaussian) and adds its variance to a
parameter it is confounded with, the noise from trial scatter matches the generator's, and bad
input gives impedax's errors.

All runs share one data shape (8 trials × 31 points) and sampler settings, so the NUTS
program compiles once per discrepancy setting."""

import os

import jax
import numpy as np
import pytest
import xarray as xr

import impedax as ix
from scipy.stats import multivariate_normal

from impedax.fitting.bayes.hierarchical import hierarchical_log_density, sample_hierarchical, trial_scatter_noise
from impedax.models import synthetic

MODEL = "R0 + R1 || CPE1 + R2 || CPE2"
PER_TRIAL = ("R1", "CPE1.Q", "R2", "CPE2.Q")
SETTINGS = dict(per_trial=PER_TRIAL, chains=2, warmup=200, draws=200)


def _data(seed, misfit=0.0):
    ds = synthetic.generate_two_arc_trials(seed, trials=8, points=31)
    if misfit:
        # a ripple common to every trial that no two-arc circuit has: structured misfit
        f = ds["frequency"].values
        ds["Z"] = ds["Z"] * (1.0 + misfit * np.sin(2.0 * np.log(f)))
    return ds


@pytest.fixture(scope="module")
def clean():
    return _data(4)


@pytest.fixture(scope="module")
def clean_post(clean):
    return sample_hierarchical(MODEL, clean, seed=1, **SETTINGS)


def test_recovers_population_median_and_spread(clean, clean_post):
    """Truth: population medians R1 = 100 Ω, R2 = 300 Ω, spreads 0.10 and 0.12. With 8 trials the
    sd of the mean of ln R1 is 0.10/√8 = 0.035, so ±12 % is > 3 sd; a spread estimated from 8
    trials has a relative sd ≈ 1/√14 ≈ 27 %, hence the factor-2 bounds. The 90 % interval of
    each population median must contain the realised geometric mean of the trials."""
    post = clean_post
    for name, truth in (("R1", 100.0), ("R2", 300.0)):
        pop = post.population(name)
        assert pop["value"] == pytest.approx(truth, rel=0.12), name
        realised = float(np.exp(np.log(clean[f"trial_{name}"].values).mean()))
        assert pop["q05"] <= realised <= pop["q95"], (name, pop, realised)
    for name, spread in (("R1", 0.10), ("R2", 0.12)):
        assert spread / 2 < post.spread_between_trials(name)["value"] < 2 * spread, name
    r0 = post.shared[..., post.shared_names.index("R0")]
    assert np.median(r0) == pytest.approx(20.0, rel=0.05)
    new = post.new_trial("R1")
    pop = post.population("R1")
    assert new["q05"] < pop["q05"] and new["q95"] > pop["q95"]  # a new trial varies more than the median
    assert post.divergences <= 5
    assert all(r < 1.1 for r in post.rhat().values())


def test_chains_are_split_evenly_over_the_devices():
    """The chains run on as many devices (cores) as divide them evenly: 4 chains on 2 devices
    2 each, 3 chains on 2 devices all on one, never more devices than chains or than JAX has."""
    import jax

    from impedax.fitting.bayes.hierarchical import _chain_devices

    devices = len(jax.devices())
    for chains in range(1, 13):
        used = _chain_devices(chains)
        assert 1 <= used <= min(chains, devices) and chains % used == 0
        assert not any(chains % d == 0 for d in range(used + 1, min(chains, devices) + 1))  # the most that divide
    if devices == 2:
        assert [_chain_devices(c) for c in (1, 2, 3, 4, 5, 6)] == [1, 2, 1, 2, 1, 2]


def test_vector_cholesky_and_triangular_solve_match_numpy():
    """The likelihood's own factorisation (no LAPACK) against numpy's, batched and unbatched."""
    from impedax.fitting.bayes.hierarchical import _cholesky, _forward_substitution, _log_diagonal_sum

    rng = np.random.default_rng(3)
    x = rng.standard_normal((5, 12, 30))
    a = np.eye(12) + x @ np.swapaxes(x, -1, -2)  # (5, 12, 12), SPD
    b = rng.standard_normal((5, 12, 4))
    low = np.asarray(_cholesky(a))
    np.testing.assert_allclose(low, np.linalg.cholesky(a), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(np.asarray(_forward_substitution(low, b)), np.linalg.solve(low, b), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(np.asarray(_log_diagonal_sum(low)), 0.5 * np.linalg.slogdet(a)[1], rtol=1e-12)
    single = np.asarray(_forward_substitution(_cholesky(a[0]), b[0, :, :1]))[:, 0]
    np.testing.assert_allclose(single, np.linalg.solve(np.linalg.cholesky(a[0]), b[0, :, 0]), rtol=1e-9, atol=1e-12)


def test_progress_counts_every_step_once_and_changes_nothing(clean, clean_post, monkeypatch, capsys):
    """With ``progress`` every warm-up and draw step reaches the progress line once for all
    (vmapped) chains (the sampler runs in blocks of steps, the line advancing between them), and
    the draws are those of the run without it. A line marks
    each phase: compiling, warm-up, draws (the compilation took 30–70 s with no other output).
    The run takes its steps in blocks of one (`BLOCK_SECONDS` 0: the line advances after every
    step), so it also checks what test_blocks_of_one_step_draw_what_growing_blocks_draw does
    (slow-marked: a third sampling of the fixture's): the cut into blocks changes no draw."""
    from impedax.fitting.bayes import hierarchical

    seen = []

    class Recording(hierarchical.ProgressLine):
        def close(self):
            seen.append(self.done)
            super().close()

    monkeypatch.setattr(hierarchical, "ProgressLine", Recording)
    monkeypatch.setattr(hierarchical, "BLOCK_SECONDS", 0.0)
    post = sample_hierarchical(MODEL, clean, seed=1, progress=True, **SETTINGS)
    assert seen == [SETTINGS["warmup"] + SETTINGS["draws"]]
    for name in ("mu", "spread", "trial_values", "shared", "delta", "step_size"):
        np.testing.assert_array_equal(getattr(post, name), getattr(clean_post, name), err_msg=name)
    err = capsys.readouterr().err
    phases = ["tracing and compiling the sampler", "compiled in", "warm-up done", f"drawing {SETTINGS['draws']} draws"]
    assert all(p in err for p in phases) and [err.index(p) for p in phases] == sorted(err.index(p) for p in phases)
    # the compilation's time says for which machine, and where the cache that makes the next run fast is (conftest's)
    assert "30–70 s on a quiet 2-core machine, longer on a busy one" in err
    assert f"JAX's persistent cache in {jax.config.jax_compilation_cache_dir} keeps it for the next run" in err


@pytest.mark.slow  # (slow: 9 s; the fast suite keeps test_progress_counts_every_step_once_and_changes_nothing, whose run also takes blocks of one step)
def test_blocks_of_one_step_draw_what_growing_blocks_draw(clean, clean_post, monkeypatch):
    """The sampler runs its steps as calls of blocks that grow while a call is short
    (`BLOCK_SECONDS`); how the steps are cut into blocks changes no draw: one step per call
    (never growing) gives the run of the fixture bit for bit."""
    from impedax.fitting.bayes import hierarchical

    monkeypatch.setattr(hierarchical, "BLOCK_SECONDS", 0.0)
    post = sample_hierarchical(MODEL, clean, seed=1, **SETTINGS)
    for name in ("mu", "spread", "trial_values", "shared", "delta", "step_size"):
        np.testing.assert_array_equal(getattr(post, name), getattr(clean_post, name), err_msg=name)


def test_progress_function_gets_every_line_and_stderr_none(clean, clean_post, capsys):
    """``progress=lines.append`` (as `fit` and `sample` take it): the function is handed the
    phase lines (compiling, warm-up, draws) as well as the progress line, and nothing goes to
    stderr; until 2026-12-06 the phase lines went to stderr even with a function. The draws are
    the run's without progress (the fixture's)."""
    lines = []
    post = sample_hierarchical(MODEL, clean, seed=1, progress=lines.append, **SETTINGS)
    assert capsys.readouterr().err == ""
    text = "\n".join(lines)
    phases = ["fitting the 8 trials by least squares", "tracing and compiling the sampler", "compiled in", "warm-up done", f"drawing {SETTINGS['draws']} draws"]
    assert all(p in text for p in phases), lines
    assert all(isinstance(line, str) and "\n" not in line for line in lines)
    np.testing.assert_array_equal(post.mu, clean_post.mu)


class _Stop(Exception):
    pass


@pytest.mark.parametrize("progress, on_stderr", [("default", True), (None, True), (True, True), (False, False)])
def test_progress_default_and_false(clean, monkeypatch, capsys, progress, on_stderr):
    """None (the default) and True: its own phase lines on stderr, as `sample` does (until
    2026-12-06 the default was False: a long compilation without a word); False: nothing at all.
    The start fits say nothing of their own, as `sample`'s: with False they wrote "[0.0 s]
    fitting …" lines (shown at once here: `PROGRESS_AFTER_S` 0). The run is stopped where the
    sampler would start."""
    import impedax.progress
    from impedax.fitting.bayes import hierarchical

    def stop(*args, **kwargs):
        raise _Stop

    monkeypatch.setattr(hierarchical, "_sample", stop)
    monkeypatch.setattr(impedax.progress, "PROGRESS_AFTER_S", 0.0)
    options = {} if progress == "default" else {"progress": progress}
    with pytest.raises(_Stop):
        sample_hierarchical(MODEL, clean, seed=1, **SETTINGS, **options)
    err = capsys.readouterr().err
    if on_stderr:
        assert "fitting the 8 trials by least squares" in err and "tracing and compiling the sampler" in err, err
        assert f"fitting {MODEL}" not in err, err
    else:
        assert err == ""


@pytest.mark.parametrize("value", ["no", 1, 0.5, [print]])
def test_progress_other_values_are_refused_naming_it(clean, value):
    """progress="no" printed lines (any truthy value was taken as True, unchecked); now anything
    but None, a bool or a function is a ParameterError naming the argument, before any fit."""
    with pytest.raises(ix.ParameterError, match=r"^progress must be True or False"):
        sample_hierarchical(MODEL, clean, seed=1, progress=value, **SETTINGS)


def test_warnings_cover_the_shared_parameters_and_delta(clean_post):
    """R-hat and ESS warned of μ and the spreads only: a shared parameter whose chains disagree
    (R0 ≈ 10 Ω in one chain, 12 Ω in the other: between-chain variance ≫ within, so split-R̂ ≫
    1.05 by construction) or that barely moves (a random walk: ESS ≪ 100) went unsaid, and so did
    δ's R-hat. Draws written here; the same draws iid in both chains raise no such warning (split-R̂
    of 2 × 200 iid normals is 1 ± 0.01, ESS ≈ 400)."""
    import dataclasses

    rng = np.random.default_rng(0)
    chains, draws = clean_post.shared.shape[:2]
    j = clean_post.shared_names.index("R0")

    def with_r0(r0):
        shared = np.array(clean_post.shared)
        shared[..., j] = r0
        return dataclasses.replace(clean_post, shared=shared)

    iid = 10.0 * np.exp(0.01 * rng.standard_normal((chains, draws)))
    assert not [w for w in with_r0(iid).warnings if ("R-hat" in w or "effective sample size" in w) and "R0" in w]
    apart = iid * np.array([1.0, 1.2])[:, None]
    assert any(w.startswith("R-hat above 1.05 for") and "R0" in w for w in with_r0(apart).warnings)
    walk = 10.0 * np.exp(0.01 * np.cumsum(rng.standard_normal((chains, draws)), axis=1) / np.sqrt(draws))
    walk = walk / np.exp(np.log(walk).mean(axis=1, keepdims=True)) * 10.0  # (the chains agree in mean: ESS alone)
    assert any(w.startswith("effective sample size below 100 for") and "R0" in w for w in with_r0(walk).warnings)
    delta = np.array(clean_post.delta) * np.array([1.0, 100.0])[:, None]  # (ln 100 = 4.6, beyond the spread of ln δ)
    assert any(w.startswith("R-hat above 1.05 for") and "discrepancy δ" in w for w in dataclasses.replace(clean_post, delta=delta).warnings)


def test_divergence_warning_names_the_remedy(clean_post):
    """The warning said "run longer warm-up"; NUTS's remedy for divergent transitions is a higher
    target acceptance (smaller steps, Stan's adapt_delta), which `gap_analysis` itself applies:
    the warning now names target_accept and the draws the count is of."""
    import dataclasses

    post = dataclasses.replace(clean_post, divergences=7)
    (warning,) = [w for w in post.warnings if "divergent" in w]
    assert f"7 divergent NUTS transitions of {post.mu.shape[0] * post.mu.shape[1]} draws" in warning and "target_accept" in warning


def test_report_gives_units_and_the_sampler_diagnostics(clean_post):
    """The report's rows had no unit and it said nothing of the sampling's health unless a
    warning fired (`sample`'s report has a unit column): each row now ends with its parameter's
    unit (a resistor's Ω, a CPE's Q in F s^(α-1), α dimensionless: none), the shared rows say
    "shared", and a line gives the divergent transitions of all draws (2 chains × 200), R-hat
    and ESS, and what "spread" is."""
    lines = clean_post.report().splitlines()
    row = {line.split()[0]: line for line in lines if line.split() and line.split()[0] in ("R1", "CPE1.Q", "R0", "CPE1.alpha")}
    assert row["R1"].endswith(" Ω") and row["CPE1.Q"].endswith(" F s^(α-1)") and row["R0"].endswith(" Ω")
    assert row["R0"].split()[4] == "shared" and row["CPE1.alpha"].split()[-1] == "shared"
    assert lines[2].split()[-1] == "unit"
    assert lines[1].startswith(f"sampler: {clean_post.divergences} divergent transitions of 400 draws, R-hat up to ")
    assert any(line.startswith("population: the median over trials") and "spread: sd of ln between trials" in line for line in lines)


def test_notebook_display(clean_post):
    """A notebook showed the dataclass's repr of the draws (no ``_repr_html_``); it now shows the
    report's content: the sampler's line, a row per quantity with its unit (R1 in Ω), the shared
    ones marked, δ, the warnings."""
    import html

    page = clean_post._repr_html_()
    assert page.startswith('<div class="impedax-result">') and "hierarchical posterior over 8 trials" in page
    assert f"sampler: {clean_post.divergences} divergent transitions of 400 draws" in page
    assert "<td>R1</td>" in page and "<td>Ω</td>" in page and "<td>shared</td>" in page and "discrepancy δ" in page
    assert f"{clean_post.population('R1')['value']:.5g}" in page
    for warning in clean_post.warnings:
        assert html.escape(warning) in page


def test_population_figure(clean, clean_post):
    """A hierarchical posterior had no figure at all (`sample`'s has its bands). `plot()`: a panel
    per per-trial quantity, its unit on the axis, each trial's posterior median (the median of
    its stored draws, numpy) with its 90 % interval, the population median as a line, the trials
    named by their coordinate, the noise model in the title."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = clean_post.plot()
    try:
        axes = fig.axes
        assert [ax.get_ylabel() for ax in axes] == ["R1 [Ω]", "CPE1.Q [F s^(α-1)]", "R2 [Ω]", "CPE2.Q [F s^(α-1)]"]
        draws = np.asarray(clean_post.trial_values).reshape(-1, 8, 4)
        for j, ax in enumerate(axes):
            points = [line for line in ax.get_lines() if line.get_marker() == "o"]
            np.testing.assert_allclose(points[0].get_ydata(), np.median(draws[:, :, j], axis=0), rtol=1e-12)
            level = [line.get_ydata()[0] for line in ax.get_lines() if line.get_marker() != "o" and len(set(line.get_ydata())) == 1]
            assert np.median(np.exp(np.asarray(clean_post.mu)[..., j])) == pytest.approx(level[0], rel=1e-12)
        assert [t.get_text() for t in axes[-1].get_xticklabels()] == [str(v) for v in clean["trial"].values]
        title = fig._suptitle.get_text()
        assert "8 trials" in title and "noise ν_k from the trials' scatter" in title and "δ" in title
    finally:
        plt.close(fig)


def test_a_small_block_capacity_draws_the_same(clean, clean_post, monkeypatch):
    """A call runs at most `BLOCK_CAPACITY` steps, its keys, schedule and draws in arrays of that
    length: with a capacity of 8 the 200 warm-up steps and 200 draws run as 25 + 25 calls and
    give the fixture's run (blocks doubling from one step while a call is short) bit for bit."""
    from impedax.fitting.bayes import hierarchical

    monkeypatch.setattr(hierarchical, "BLOCK_CAPACITY", 8)
    monkeypatch.setattr(hierarchical, "BLOCK_SECONDS", 1e9)
    post = sample_hierarchical(MODEL, clean, seed=1, **SETTINGS)
    for name in ("mu", "spread", "trial_values", "shared", "delta", "step_size"):
        np.testing.assert_array_equal(getattr(post, name), getattr(clean_post, name), err_msg=name)


def test_a_new_number_of_steps_compiles_nothing(clean, clean_post, monkeypatch):
    """The compiled sampler does not depend on the numbers of warm-up steps and draws (a new
    ``--steps`` used to compile it again, ~30 s on the Sirin remainders): after the fixture's
    run, one of 60 + 300 steps on the same data adds no entry to the program's cache of
    compilations, and returns its 300 draws per chain."""
    from impedax.fitting.bayes import hierarchical

    seen = []
    original = hierarchical._compiled_sampler

    def recording(*args):
        sampler = original(*args)
        seen.append((sampler, sampler.run._cache_size()))
        return sampler

    monkeypatch.setattr(hierarchical, "_compiled_sampler", recording)
    post = sample_hierarchical(MODEL, clean, seed=2, **{**SETTINGS, "warmup": 60, "draws": 300})
    assert post.mu.shape[:2] == (SETTINGS["chains"], 300)
    [(sampler, compiled_before)] = seen
    assert compiled_before >= 1  # the fixture's run compiled it, and this run found it
    assert sampler.run._cache_size() == compiled_before


def test_the_sampler_is_kept_in_the_persistent_cache(clean_post):
    """The sampler's program is in JAX's persistent cache (the suite's own, tests/conftest.py)
    after a run: it holds no host callback, which JAX refuses to store, so a new process reads
    it instead of compiling it again (docs/bayesian.md, "Compilation")."""
    import jax

    names = {entry.name.split("-")[0] for entry in os.scandir(jax.config.jax_compilation_cache_dir)}
    assert "jit_hierarchical_nuts" in names


def test_noise_from_trial_scatter_matches_the_generator(clean_post):
    """Generator: relative sd 0.5 % + 1 %·f^-½ of the complex noise (Re, Im each /√2 of it)."""
    f = clean_post.frequency
    expected = (0.005 + 0.01 / np.sqrt(f)) / np.sqrt(2.0)
    ratio = clean_post.nu / expected
    assert 0.6 < np.median(ratio) < 1.4
    assert clean_post.nu[0] > 2 * clean_post.nu[-1]  # larger at low frequency


def test_trial_scatter_noise_removes_a_common_misfit():
    rng = np.random.default_rng(0)
    z_fit = np.ones((40, 10), complex) * 100.0
    common = 5.0 * np.exp(1j * np.linspace(0, 3, 10))
    z = z_fit + common + 2.0 * (rng.standard_normal((40, 10)) + 1j * rng.standard_normal((40, 10))) / np.sqrt(2)
    nu = trial_scatter_noise(z, z_fit, window=1)
    # Re and Im each carry sd √2 Ω; the common misfit (5 Ω) must not enter ν (40 trials: ν ± 8 %)
    assert np.allclose(nu * np.abs(z).mean(0), np.sqrt(2.0), rtol=0.3)


@pytest.mark.slow  # ~45 s: two more hierarchical samplings
def test_discrepancy_widens_intervals_only_under_structured_misfit(clean, clean_post):
    """R0 is shared, so its interval is set by the noise: with a 3 % ripple common to all
    trials, the sampled floor δ must grow and widen it (> 1.5×) against the run without δ;
    on clean data δ stays below the noise and the width changes by < 30 %."""

    def width(post):
        r0 = post.shared[..., post.shared_names.index("R0")].ravel()
        q05, q95 = np.quantile(r0, [0.05, 0.95])
        return q95 - q05

    clean_off = sample_hierarchical(MODEL, clean, seed=1, discrepancy=False, **SETTINGS)
    assert 0.7 < width(clean_post) / width(clean_off) < 1.3
    assert np.median(clean_post.delta) < np.median(clean_post.nu)
    bent = _data(4, misfit=0.03)
    on = sample_hierarchical(MODEL, bent, seed=1, **SETTINGS)
    off = sample_hierarchical(MODEL, bent, seed=1, discrepancy=False, **SETTINGS)
    assert np.median(on.delta) > 0.005
    assert width(on) > 1.5 * width(off)


def _stacked(a):
    """Re and Im of a complex array side by side along its last axis."""
    return np.concatenate([a.real, a.imag], axis=-1)


def _resistor_trials(rng):
    """Four trials of a resistor (per-trial R1, 2 % complex noise, 6 frequencies): the data, the
    `hierarchical_log_density` options, the density without modes, a position near the truth,
    its residuals (trials, frequencies) and the independent noise sd σ_tk = |Z_tk| ν_k."""
    f = np.geomspace(10.0, 1e4, 6)
    r_true = 100.0 * np.exp(0.1 * rng.standard_normal((4, 1)))
    z = r_true * (1.0 + 0.02 * (rng.standard_normal((4, 6)) + 1j * rng.standard_normal((4, 6))))
    data = ix.make_spectrum(f, z, dims=("trial",))
    batch = ix.fit("R1", data, weighting="modulus")
    options = dict(per_trial=("R1",), discrepancy=False, parameterisation="centred", init=batch)
    plain, position = hierarchical_log_density("R1", data, **options)
    position = dict(position, log_theta=np.log(r_true * np.array([[1.01], [0.98], [1.0], [1.03]])))
    resid = np.exp(position["log_theta"]) - z
    sd = np.abs(z) * trial_scatter_noise(z, batch.dataset["Z_model"].values)[None, :]
    return data, options, plain, position, resid, sd


def test_shared_error_is_marginalised_exactly():
    """Trials of a resistor (Z_tk = R_t, per-trial R1) told of an error shared by every trial
    (three complex modes d_j): the log density must change by exactly
    ln N(r; 0, D + 11ᵀ ⊗ C) − ln N(r; 0, D), r the real-stacked residuals of all trials, D the
    independent noise (σ_tk = |Z_tk| ν_k), C = Σ_j [Re d_j; Im d_j][Re d_j; Im d_j]ᵀ (scipy's
    dense multivariate normal as the oracle)."""
    rng = np.random.default_rng(5)
    data, options, plain, position, resid, sd = _resistor_trials(rng)
    modes = 0.8 * (rng.standard_normal((3, 6)) + 1j * rng.standard_normal((3, 6)))
    told = data.assign(common_error_modes=(("common_mode", "frequency"), modes))
    shared, _ = hierarchical_log_density("R1", told, **options)
    c = _stacked(modes).T @ _stacked(modes)
    cov = np.diag(np.concatenate([sd, sd], axis=1).ravel() ** 2) + np.kron(np.ones((4, 4)), c)
    dense = multivariate_normal(np.zeros(cov.shape[0]), cov).logpdf(_stacked(resid).ravel())
    independent = multivariate_normal(np.zeros(cov.shape[0]), np.diag(np.diag(cov) - np.diag(np.kron(np.ones((4, 4)), c)))).logpdf(_stacked(resid).ravel())
    assert float(shared(position)) - float(plain(position)) == pytest.approx(dense - independent, rel=1e-8, abs=1e-8)


def test_each_trials_own_smooth_error_is_marginalised_exactly():
    """As above, plus an error of each trial's own that is smooth in frequency (two complex
    modes m_j, ζ_tj ~ N(0, 1) independent between trials): the covariance gains a block
    Σ_j [Re m_j; Im m_j][Re m_j; Im m_j]ᵀ on each trial's diagonal, and the log density must
    again equal scipy's dense multivariate normal (the arrowhead Woodbury factorisation of
    `_structured_error_log_likelihood` against the dense 48 × 48 covariance)."""
    rng = np.random.default_rng(6)
    data, options, plain, position, resid, sd = _resistor_trials(rng)
    common = 0.8 * (rng.standard_normal((3, 6)) + 1j * rng.standard_normal((3, 6)))
    own = 1.5 * (rng.standard_normal((2, 6)) + 1j * rng.standard_normal((2, 6)))
    independent_cov = np.diag(np.concatenate([sd, sd], axis=1).ravel() ** 2)
    own_cov = np.kron(np.eye(4), _stacked(own).T @ _stacked(own))
    x = _stacked(resid).ravel()
    logpdf = lambda cov: multivariate_normal(np.zeros(cov.shape[0]), cov).logpdf(x)  # noqa: E731
    for modes in ({"trial_error_modes": own}, {"trial_error_modes": own, "common_error_modes": common}):
        told = data.assign({k: ((k.split("_")[0] + "_mode", "frequency"), v) for k, v in modes.items()})
        density, _ = hierarchical_log_density("R1", told, **options)
        cov = independent_cov + own_cov + (np.kron(np.ones((4, 4)), _stacked(common).T @ _stacked(common)) if "common_error_modes" in modes else 0.0)
        assert float(density(position)) - float(plain(position)) == pytest.approx(logpdf(cov) - logpdf(independent_cov), rel=1e-8, abs=1e-8)


@pytest.mark.slow  # (25 s: the default suite keeps a margin under 15 minutes)
def test_a_shared_error_confounded_with_a_parameter_adds_its_variance(clean, clean_post):
    """A real, frequency-independent error ε ~ N(0, c²) shared by every trial is exactly
    confounded with the shared series resistance R0: the data fix R0 + ε, so the posterior
    variance of R0 grows by c² (Gaussian posteriors add variances). c = 0.1 Ω, about 3× the
    posterior sd of R0 without it; the variance estimates from 400 draws (ESS ≳ 150) are good to
    ≈ 15 %, hence ±35 %."""
    c = 0.1
    told = clean.assign(common_error_modes=(("common_mode", "frequency"), np.full((1, clean.sizes["frequency"]), c + 0j)))
    post = sample_hierarchical(MODEL, told, seed=1, **SETTINGS)
    var = lambda p: np.var(p.shared[..., p.shared_names.index("R0")])  # noqa: E731
    assert var(post) - var(clean_post) == pytest.approx(c**2, rel=0.35)
    assert post.common_sd is not None and np.allclose(post.common_sd[0], c) and np.allclose(post.common_sd[1], 0.0)


def test_predictive_bands_include_the_noise(clean_post):
    with_noise = clean_post.predict(noise=True, max_draws=100)
    without = clean_post.predict(noise=False, max_draws=100)
    spread = lambda z: np.std(z.real, axis=0)  # noqa: E731
    assert np.median(spread(with_noise) / spread(without)) > 1.2
    # 90 % of the data's points fall inside the 90 % predictive band of their trial (±8 %: 248 points)
    lo, hi = np.quantile(with_noise.real, [0.05, 0.95], axis=0)
    inside = np.mean((clean_post.z_data.real >= lo) & (clean_post.z_data.real <= hi))
    assert 0.8 < inside <= 1.0


@pytest.mark.parametrize(
    "kwargs, error, fragment",
    [
        (dict(per_trial=("R9",)), ix.ParameterError, "per-trial parameter 'R9'"),
        (dict(per_trial=("R1",), session_dim="session"), ix.DataError, "session_dim 'session'"),
        (dict(per_trial=("R1",), parameterisation="sideways"), ix.ParameterError, "parameterisation"),
    ],
)
def test_bad_input(clean, kwargs, error, fragment):
    with pytest.raises(error, match=fragment):
        sample_hierarchical(MODEL, clean, **kwargs)


@pytest.mark.parametrize(
    "option, value, fragment",
    [
        ("chains", 0, "chains must be at least 1, got 0"),  # was IndexError: list index out of range
        ("warmup", -1, "warmup must be at least 1, got -1"),  # was a TypeError from JAX's broadcast_in_dim
        ("draws", 0, "draws must be at least 1, got 0"),  # was a posterior of no draws (NaN summaries)
        ("draws", 2.5, r"draws must be an integer, got 2.5"),  # was taken as 2
        ("target_accept", 1.5, "target_accept is NUTS's target acceptance rate, strictly between 0 and 1"),  # was taken
        ("seed", -1, "seed must be at least 0, got -1"),  # was NumPy's ValueError
        ("session_spread_scale", -1.0, "session_spread_scale must be positive"),  # was taken
        ("per_trial", (), "per_trial is empty: name at least one parameter drawn per trial, of R0, R1, CPE1.Q"),  # was NumPy's 'need at least one array to stack'
        ("per_trial", "R1", r"per_trial must be a list"),  # was read letter by letter: "per-trial parameter 'R'"
        ("per_trial", ("R1", "R1"), "per_trial names R1 more than once"),
    ],
)
def test_bad_settings_are_parameter_errors_naming_them(clean, option, value, fragment):
    """Each setting outside its range is refused before any fit with a ParameterError naming it
    (until 2026-12-06 none was checked: Python, NumPy or JAX errors from deep inside, or a run
    that silently did something else; the comment of each case says what)."""
    with pytest.raises(ix.ParameterError, match=fragment):
        sample_hierarchical(MODEL, clean, progress=False, **{**SETTINGS, option: value})


def test_a_batch_init_of_other_trials_is_refused(rng):
    """init=batch of the same frequencies but other impedances centred the priors and set the
    noise from other data without a word; it is refused as `compare` refuses such fits."""
    f = np.geomspace(10.0, 1e4, 6)  # (the shapes of `_resistor_trials`: its batch fit's program)
    z = 100.0 * (1.0 + 0.02 * (rng.standard_normal((4, 6)) + 1j * rng.standard_normal((4, 6))))
    batch = ix.fit("R1", ix.make_spectrum(f, z, dims=("trial",)), weighting="modulus")
    other = ix.make_spectrum(f, z * 1.01, dims=("trial",))
    with pytest.raises(ix.ParameterError, match=r"init was fitted to different data: trial 0 \(trial stacked\): the same 6 frequencies, but Z differs"):
        hierarchical_log_density("R1", other, per_trial=("R1",), init=batch)


def test_needs_replicates():
    ds = synthetic.generate_two_arc_trials(1, trials=8, points=31).isel(trial=0)
    with pytest.raises(ix.DataError, match="replicate"):
        sample_hierarchical(MODEL, ds, per_trial=("R1",))


def test_sample_predictive_band_includes_the_noise():
    """`Posterior.predict(noise=True)`: draws carry σ = sigma_rel·|Z|, so the band is several
    times wider than the model's and holds most data points (2 % noise, 31 points)."""
    f = np.geomspace(1.0, 1e5, 31)
    z = 100.0 + 1000.0 / (1.0 + 1j * 2 * np.pi * f * 1000.0 * 1e-6)
    rng = np.random.default_rng(3)
    z = z * (1.0 + 0.02 * (rng.standard_normal(31) + 1j * rng.standard_normal(31)) / np.sqrt(2.0))
    post = ix.sample("R0 + R1 || C1", ix.make_spectrum(f, z), steps=400, seed=1, progress=False)
    with_noise, without = post.predict(noise=True), post.predict()
    assert np.median(np.std(with_noise.real, axis=0) / np.std(without.real, axis=0)) > 2.0
    lo, hi = np.quantile(with_noise.real, [0.05, 0.95], axis=0)
    assert np.mean((z.real >= lo) & (z.real <= hi)) > 0.75
    fig = post.plot()
    assert any("predictive" in str(line.get_label()) for ax in fig.axes for line in ax.get_lines())
    # copies: each draw with several noise draws, rows draws × copies; the band's edges settle
    many = post.predict(noise=True, copies=10)
    assert many.shape == (10 * without.shape[0], f.size)
    np.testing.assert_allclose(many.reshape(-1, 10, f.size).mean(axis=1).real, without.real, rtol=0.05)  # copies of one draw
    rough = np.abs(np.diff(np.quantile(with_noise.real / without.real.mean(axis=0), 0.95, axis=0), 2)).mean()
    smooth = np.abs(np.diff(np.quantile(many.real / without.real.mean(axis=0), 0.95, axis=0), 2)).mean()
    assert smooth < 0.6 * rough, (smooth, rough)
    with pytest.raises(ix.ParameterError, match="copies"):
        post.predict(noise=True, copies=0)


def _constructed_edges_posterior(*, centres: bool = True):
    """A `HierarchicalPosterior` built by hand (no sampling; SYNTHETIC draws, 2 chains × 2000):
    R1's population median is drawn from its own prior (lognormal about 100 Ω, S = 2: the data
    said nothing, so the draws fill the prior to both tails), CPE1.Q's is a narrow posterior
    about 1e-5, the shared CPE1.alpha crowds its bound 1 (1 − |N(0, 0.01)|) and the shared R0
    is a narrow posterior about 20 Ω inside its prior."""
    from impedax.fitting.bayes.hierarchical import HierarchicalPosterior

    rng = np.random.default_rng(11)
    c, d, t = 2, 2000, 3  # (4000 draws: ~80 in each 2 % band of a prior the draws fill, above `EDGE_MIN_DRAWS`)
    freq = np.geomspace(1.0, 1e5, 12)
    centre = np.log([100.0, 1e-5])
    mu = np.stack([centre[0] + 2.0 * rng.standard_normal((c, d)), centre[1] + 0.01 * rng.standard_normal((c, d))], axis=-1)
    shared = np.stack([20.0 * np.exp(0.01 * rng.standard_normal((c, d))), 1.0 - np.abs(0.01 * rng.standard_normal((c, d)))], axis=-1)
    index = xr.Dataset(coords={"trial": [0, 1, 2]}).stack(trial_index=("trial",))["trial_index"]
    return HierarchicalPosterior(
        circuit=ix.parse("R0 + R1 || CPE1"), trial_names=("R1", "CPE1.Q"), shared_names=("R0", "CPE1.alpha"), mu=mu, spread=np.full((c, d, 2), 0.1),
        spread_session=np.zeros((c, d, 2)), trial_values=np.exp(mu[:, :, None, :] + np.zeros((1, 1, t, 1))), shared=shared, delta=np.full((c, d), 0.01),
        frequency=freq, z_data=np.full((t, freq.size), 100.0 + 0j), nu=np.full(freq.size, 0.01), trial_index=index, sessions=1, discrepancy=True, divergences=0,
        step_size=np.full(c, 0.3), mean_tree_steps=7.0, mean_acceptance=0.8, elapsed_s=0.0,
        mu_prior_centre=centre if centres else None, shared_prior_centre=np.log([20.0, 0.5]) if centres else None,
    )


def test_prior_edges_of_the_population_medians_and_shared_parameters(tmp_path):
    """The check of `Posterior` (`diagnostics.prior_edges`) on the quantities with a prior of
    their own. Oracle by construction: draws that are the prior itself fill both tails of it
    in its cumulative coordinate (as dense there as in the middle: "both"), a half-normal
    against a bound crowds that bound ("upper"), narrow posteriors inside their priors do not.
    The prior centres survive the .nc file; a result without them (written before they were
    stored) checks only what its bounds give: the shared parameter in a bounded (uniform) prior."""
    post = _constructed_edges_posterior()
    assert post.piled_up == {"R1": "both", "CPE1.alpha": "upper"}
    edge_notes = [w for w in post.warnings if "not the data, sets" in w]
    assert len(edge_notes) == 3  # (one per side)
    assert edge_notes[0].startswith("R1 (population median) follows its prior lognormal:100,2 into the lower tail (")
    assert "the data do not cut that tail off, so the prior, not the data, sets the lower end of its 90 % interval" in edge_notes[0]
    assert any(w.startswith("CPE1.alpha piles up against its upper bound 1 (") and "the bound, not the data, sets the upper end of its 90 % interval" in w for w in edge_notes)
    assert post.summary()["piled_up"] == post.piled_up and all(w in post.summary()["warnings"] for w in edge_notes)
    path = tmp_path / "edges.nc"
    ix.write_result(post, path)
    back = type(post).from_xarray(ix.load(path))
    np.testing.assert_array_equal(back.mu_prior_centre, post.mu_prior_centre)
    assert back.piled_up == post.piled_up and back.warnings == post.warnings
    older = _constructed_edges_posterior(centres=False)
    assert older.piled_up == {"CPE1.alpha": "upper"}


def test_population_figure_stands_long_trial_labels_upright():
    """Trials of a session level are labelled "session=0, trial=0": eight of them ran into each
    other along the axis (SYNTHETIC 2 × 4 trials read back from a file); long labels now stand
    upright and the figure grows by their length. Arrays written here, no sampling."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from impedax.plotting.hierarchical import plot_population

    draws = np.exp(np.random.default_rng(0).normal(np.log(100.0), 0.1, (50, 8, 1)))
    band = {"R1": {"value": 100.0, "q05": 95.0, "q95": 105.0}}
    wide = {"R1": {"value": 100.0, "q05": 80.0, "q95": 125.0}}
    short = plot_population(["R1"], ["Ohm"], draws, band, wide, [str(i) for i in range(8)], title="t")
    long = plot_population(["R1"], ["Ohm"], draws, band, wide, [f"session={i // 4}, trial={i % 4}" for i in range(8)], title="t", xlabel="session, trial")
    try:
        assert short.axes[0].get_xticklabels()[0].get_rotation() == 0.0 and long.axes[0].get_xticklabels()[0].get_rotation() == 90.0
        assert long.get_size_inches()[1] > short.get_size_inches()[1] + 1.0
        assert long.axes[0].get_ylabel() == "R1 [Ω]" and long.axes[0].get_xlabel() == "session, trial"
    finally:
        plt.close(short)
        plt.close(long)


def test_summary_gives_units_and_the_run_size(clean_post):
    """summary() gave numbers without units and not the run's size: it now adds ``units`` (the
    element's: a resistor in Ohm, a CPE's Q in F s^(alpha-1), α dimensionless "1"), ``chains``,
    ``draws`` per chain (2 and 200: the settings) and ``mean_acceptance``; the keys it had stay."""
    summary = clean_post.summary()
    assert summary["units"] == {"R1": "Ohm", "CPE1.Q": "F s^(alpha-1)", "R2": "Ohm", "CPE2.Q": "F s^(alpha-1)", "R0": "Ohm", "CPE1.alpha": "1", "CPE2.alpha": "1"}
    assert (summary["chains"], summary["draws"]) == (SETTINGS["chains"], SETTINGS["draws"])
    assert 0.0 < summary["mean_acceptance"] <= 1.0
    assert {"population", "spread", "new_trial", "shared", "rhat", "ess", "divergences", "warnings", "piled_up", "fixed"} <= set(summary)
