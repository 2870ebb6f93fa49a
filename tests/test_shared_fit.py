"""Global fits with shared parameters (`fit(..., shared=, over=)`): the Schur-complement solve
against a brute-force joint least squares, recovery of the truth, results, errors and the CLI."""

import json

import numpy as np
import pytest
from scipy.optimize import least_squares

import impedax as ix
from impedax.cli import main

FREQ = np.geomspace(1.0, 1e5, 30)
R0_TRUE = 50.0


def rc_impedance(f, r0, r1, c1):
    """R0 + R1 || C1 written out: R0 + R1 / (1 + jωR1C1)."""
    w = 2 * np.pi * np.asarray(f)
    return r0 + r1 / (1 + 1j * w * r1 * c1)


def rc_stack(rng, m=4, noise=0.01, r0=R0_TRUE):
    r1 = rng.uniform(500.0, 2000.0, m)
    c1 = rng.uniform(1e-7, 1e-6, m)
    z = np.stack([rc_impedance(FREQ, r0, a, b) for a, b in zip(r1, c1)])
    z = z * (1 + noise * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape)))
    return z, r1, c1


def brute_force(z):
    """The joint least squares written out: all residuals of all spectra stacked, modulus
    weighting, parameters [R0, R1_1..R1_M, C1_1..C1_M]; scipy in log space, then a dense
    central-difference Jacobian in natural parameters for the covariance."""
    m = z.shape[0]

    def residual(x):
        r0, r1, c1 = x[0], x[1 : m + 1], x[m + 1 :]
        d = np.stack([(rc_impedance(FREQ, r0, a, b) - zi) / np.abs(zi) for zi, a, b in zip(z, r1, c1)])
        return np.concatenate([d.real.ravel(), d.imag.ravel()])

    x0 = np.concatenate([[np.median(z.real[:, -1])], z.real[:, 0] - z.real[:, -1], np.full(m, 3e-7)])
    sol = least_squares(lambda y: residual(np.exp(y)), np.log(x0), method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=20000)
    x = np.exp(sol.x)
    jac = np.empty((2 * z.size, x.size))
    for j in range(x.size):
        h = 1e-6 * x[j]
        up, down = x.copy(), x.copy()
        up[j] += h
        down[j] -= h
        jac[:, j] = (residual(up) - residual(down)) / (2 * h)
    r = residual(x)
    chi2 = float(r @ r)
    cov = np.linalg.inv(jac.T @ jac) * chi2 / (r.size - x.size)
    return x, np.sqrt(np.diag(cov)), chi2


@pytest.fixture(scope="module")
def problem():
    rng = np.random.default_rng(20261125)
    z, r1, c1 = rc_stack(rng)
    data = ix.make_spectrum(FREQ, z, dims=("trial",), coords={"trial": [1, 2, 3, 4]})
    return data, z, r1, c1


@pytest.fixture(scope="module")
def shared_fit(problem):
    return ix.fit("R0 + R1 || C1", problem[0], shared=["R0"], over="trial")


def test_global_fit_equals_brute_force_joint_least_squares(problem, shared_fit):
    _, z, _, _ = problem
    x, se, chi2 = brute_force(z)
    r = shared_fit
    assert isinstance(r, ix.SharedFitResult) and isinstance(r, ix.BatchFitResult)
    assert float(r.values("R0")) == pytest.approx(x[0], rel=1e-7)
    np.testing.assert_allclose(r.values("R1").values, x[1:5], rtol=1e-6)
    np.testing.assert_allclose(r.values("C1").values, x[5:], rtol=1e-6)
    assert float(r.dataset["joint_chi2"]) == pytest.approx(chi2, rel=1e-9)
    # standard errors: block inverse vs the inverse of the dense (9 × 9) JᵀJ
    assert float(r.dataset["shared_stderr"].sel(shared_param="R0")) == pytest.approx(se[0], rel=1e-4)
    np.testing.assert_allclose(r.dataset["stderr"].sel(param="R1").values, se[1:5], rtol=1e-4)
    np.testing.assert_allclose(r.dataset["stderr"].sel(param="C1").values, se[5:], rtol=1e-4)
    assert int(r.dataset["joint_dof"]) == 2 * z.size - 9


def test_shared_parameter_recovers_truth_and_beats_independent_fits(problem, shared_fit):
    data, _, r1, c1 = problem
    r = shared_fit
    value, stderr = float(r.values("R0")), float(r.dataset["shared_stderr"].sel(shared_param="R0"))
    assert abs(value - R0_TRUE) < 4 * stderr  # 4σ: fails by chance with p < 1e-4
    independent = ix.fit("R0 + R1 || C1", data)
    # pooling 4 spectra: the shared R0 is better determined than any one spectrum's
    assert stderr < float(independent.dataset["stderr"].sel(param="R0").min())
    np.testing.assert_allclose(r.values("R1").values, r1, rtol=0.05)
    np.testing.assert_allclose(r.values("C1").values, c1, rtol=0.05)
    # the data were made with one R0: the F-test does not reject sharing
    assert float(r.dataset["f_pvalue"]) > 0.01 and float(r.dataset["delta_aic"]) < 0
    assert not any("disagree" in w for ws in r.warnings.values() for w in ws)


def test_result_layout_summary_and_report(shared_fit):
    r = shared_fit
    ds = r.to_xarray()
    assert ds["shared_value"].dims == ("shared_param",) and ds["value"].dims == ("param", "trial")
    assert ds["covariance"].dims == ("trial", "free_param", "free_param_2")
    np.testing.assert_allclose(ds["value"].sel(param="R0").values, float(r.values("R0")))  # repeated along trial
    corr = ds["correlation"].values
    np.testing.assert_allclose(np.diagonal(corr, axis1=1, axis2=2), 1.0)
    s = r.summary()
    assert set(s["shared"]["R0"]) == {"value", "stderr", "fixed", "unit"} and s["shared"]["R0"]["unit"] == "Ohm" and s["over"] == ["trial"]  # (unit: added 2026-12-01)
    assert {"chi2", "dof", "f_statistic", "f_pvalue", "delta_aic", "independent_chi2"} <= set(s["sharing"])
    assert {"model", "dims", "n_spectra", "params", "rms_rel_median", "converged_fraction", "at_bound", "warnings"} <= set(s)
    assert "shared over trial" in r.report() and "F =" in r.report()
    assert len(r.to_table()) == 12


def test_sharing_contradicted_by_data_is_reported():
    rng = np.random.default_rng(5)
    z = np.stack([rc_impedance(FREQ, r0, 1000.0, 3e-7) for r0 in (20.0, 40.0, 80.0, 160.0)])
    z = z * (1 + 0.002 * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape)))
    r = ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, z, dims=("trial",)), shared="R0")  # over: the only extra dim
    assert float(r.dataset["f_pvalue"]) < 1e-6 and float(r.dataset["delta_aic"]) > 0
    assert any("disagree with sharing R0 over trial" in w for ws in r.warnings.values() for w in ws)


def rc_cpe_warburg_impedance(f, r1, q=1e-5, alpha=0.8, sigma=50.0):
    """R0 + R1 || CPE1 + W1 written out: 10 + 1/(1/R1 + Q(jω)^α) + σ/√(jω), R0 = 10 Ω."""
    jw = 2j * np.pi * np.asarray(f)
    return 10.0 + 1.0 / (1.0 / r1 + q * jw**alpha) + sigma / np.sqrt(jw)


def test_noise_free_sharing_is_not_contradicted_by_rounding():
    # SYNTHETIC, no noise, one CPE1.alpha and W1.sigma in all three: the global fit matches every
    # spectrum to rounding (1e-16 relative), where the F-test once read F ≈ 400 into rounding and
    # the uneven-residual rule a 4× band ratio of rounding errors
    freq = np.logspace(-1, 5, 40)
    z = np.stack([rc_cpe_warburg_impedance(freq, r1) for r1 in (100.0, 150.0, 220.0)])
    r = ix.fit("R0 + R1 || CPE1 + W1", ix.make_spectrum(freq, z, dims=("trial",)), shared=["CPE1.alpha", "W1.sigma"])
    assert float(r.dataset["rms_rel"].max()) < 1e-12
    assert r.warnings == {}
    # ... and a sharing the same noise-free spectra contradict is still told (the same sharing, so
    # the same compiled program: sharing W1.sigma alone compiled a second one)
    z = np.stack([rc_cpe_warburg_impedance(freq, 150.0, sigma=s) for s in (30.0, 50.0, 80.0)])
    r = ix.fit("R0 + R1 || CPE1 + W1", ix.make_spectrum(freq, z, dims=("trial",)), shared=["CPE1.alpha", "W1.sigma"])
    assert any("disagree with sharing CPE1.alpha, W1.sigma over trial" in w for ws in r.warnings.values() for w in ws)


def test_keep_dimension_gives_one_global_fit_per_index(rng):
    z_a, _, _ = rc_stack(rng, m=3, r0=30.0)
    z_b, _, _ = rc_stack(rng, m=3, r0=90.0)
    z = np.stack([z_a, z_b])  # (session, trial, frequency)
    data = ix.make_spectrum(FREQ, z, dims=("session", "trial"), coords={"session": ["a", "b"]})
    r = ix.fit("R0 + R1 || C1", data, shared=["R0"], over="trial")
    assert r.values("R0").dims == ("session",)
    alone = ix.fit("R0 + R1 || C1", data.sel(session="b"), shared=["R0"], over="trial")
    assert float(r.values("R0").sel(session="b")) == pytest.approx(float(alone.values("R0")), rel=1e-7)
    assert float(r.values("R0").sel(session="a")) == pytest.approx(30.0, rel=0.05)
    assert r.summary()["shared"]["R0"]["value"] == pytest.approx([float(r.values("R0")[0]), float(r.values("R0")[1])])
    # plot(x=): one series per session against the trials' numbers, shifted apart by 4 % of a step
    import dataclasses

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    numbered = dataclasses.replace(r, dataset=r.dataset.assign_coords(trial=[10.0, 20.0, 30.0]))
    fig = numbered.plot(x="trial", params=["R1"])
    dots = [ln for ln in fig.axes[0].get_lines() if ln.get_marker() == "o"]
    np.testing.assert_allclose([ln.get_xdata() for ln in dots], [[9.8, 19.8, 29.8], [10.2, 20.2, 30.2]])
    np.testing.assert_allclose([ln.get_ydata() for ln in dots], r.values("R1").transpose("session", "trial").values)
    assert [t.get_text() for t in fig.legends[0].get_texts()] == ["session=a", "session=b"]  # (below the panels since 2026-12-02)
    plt.close(fig)
    with pytest.raises(ix.ParameterError, match="no numeric coordinate"):
        r.plot(x="session")


@pytest.mark.parametrize(
    "kwargs, error, text",
    [
        ({"shared": ["R9"]}, ix.ParameterError, "unknown parameter 'R9'"),
        ({"shared": ["R_0"]}, ix.ParameterError, "parameters: R0, R1, C1"),
        ({"shared": ["R0"], "over": "session"}, ix.ParameterError, "'session' is not a dimension of the data (extra dimensions: trial)"),
        ({"over": "trial"}, ix.ParameterError, "without shared="),
        ({"shared": ["R0", "R0"]}, ix.ParameterError, "given twice"),
        ({"shared": ["R0"], "fixed": {"R0": 50.0}}, ix.ParameterError, "R0 is fixed"),
        ({"shared": ["R0"], "max_steps": 0}, ix.ParameterError, "max_steps"),
    ],
)
def test_bad_shared_arguments(problem, kwargs, error, text):
    with pytest.raises(error) as info:
        ix.fit("R0 + R1 || C1", problem[0], **kwargs)
    assert text in str(info.value)


def test_shared_needs_extra_dimensions_and_over_among_several(problem):
    data = problem[0]
    with pytest.raises(ix.DataError, match="need data with extra dimensions"):
        ix.fit("R0 + R1 || C1", data.isel(trial=0), shared=["R0"])
    two = ix.make_spectrum(FREQ, np.stack([data["Z"].values[:2], data["Z"].values[2:]]), dims=("session", "trial"))
    with pytest.raises(ix.ParameterError, match=r"several extra dimensions \(session, trial\)"):
        ix.fit("R0 + R1 || C1", two, shared=["R0"])


def test_cli_fit_shared_json(problem, shared_fit, tmp_path, capsys):
    path = tmp_path / "trials.nc"
    ix.save(problem[0], path)
    assert main(["fit", str(path), "--model", "R0 + R1 || C1", "--shared", "R0", "--over", "trial", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["shared"]["R0"]["value"] == pytest.approx(float(shared_fit.values("R0")), rel=1e-9)
    assert out["shared"]["R0"]["stderr"] > 0 and out["shared"]["R0"]["fixed"] is False
    assert {"model", "dims", "n_spectra", "params", "rms_rel_median", "converged_fraction", "at_bound", "warnings", "over", "sharing"} <= set(out)
    assert main(["fit", str(path), "--model", "R0 + R1 || C1", "--shared", "R7"]) == 2
    assert "unknown parameter 'R7'" in capsys.readouterr().err
    assert main(["fit", str(path), "--model", "R0 + R1 || C1", "--shared", "R0", "--over", "cycle"]) == 2
    assert "extra dimensions: trial" in capsys.readouterr().err


def test_sample_joint_posterior_agrees_with_the_global_fit(problem):
    data = problem[0].isel(trial=slice(0, 3))
    post = ix.sample("R0 + R1 || C1", data, shared=["R0"], over="trial", steps=400, walkers=32, seed=3, progress=False)
    assert isinstance(post, ix.SharedPosterior)
    assert post.names[0] == "R0" and "R1[trial=2]" in post.names and post.names[-1] == "sigma_rel"
    assert post.draws.shape == (32, 300, 1 + 3 * 2 + 1)
    fit_value = float(post.fit.values("R0"))
    fit_se = float(post.fit.dataset["shared_stderr"].sel(shared_param="R0"))
    q = post.summary()["shared"]["R0"]
    # flat priors, near-linear model: the posterior median sits on the fit (within half a σ,
    # a short chain's Monte Carlo error) and its 90 % width is 2 × 1.645 σ (within 35 %)
    assert abs(q["median"] - fit_value) < 0.5 * fit_se
    assert (q["q95"] - q["q05"]) == pytest.approx(2 * 1.645 * fit_se, rel=0.35)
    assert set(post.summary()) >= {"model", "over", "shared", "params", "acceptance", "autocorr", "ess", "warnings"}
    assert post.to_xarray()["is_shared"].values.sum() == 1
    rows = [line for line in post.report().splitlines() if line.startswith(("R0 ", "R1[", "C1["))]
    assert rows and all(line.endswith(" Ω") for line in rows if line.startswith("R")) and "Ohm" not in post.report()  # (it wrote "Ohm")


def test_sample_shared_limits_and_errors(problem):
    data = problem[0]
    with pytest.raises(ix.ParameterError, match=r"sampled parameters .* emcee mixes up to 60"):
        big = ix.make_spectrum(FREQ, np.repeat(data["Z"].values, 8, axis=0), dims=("trial",))  # 32 spectra × 2 own
        ix.sample("R0 + R1 || C1", big, shared=["R0"], steps=10, progress=False)
    with pytest.raises(ix.ParameterError, match="unknown parameter 'Rx'"):
        ix.sample("R0 + R1 || C1", data, shared=["Rx"], steps=10, progress=False)


def test_cli_sample_shared_json(problem, tmp_path, capsys):
    path = tmp_path / "three.nc"
    ix.save(problem[0].isel(trial=slice(0, 3)), path)
    assert main(["sample", str(path), "--model", "R0 + R1 || C1", "--shared", "R0", "--steps", "60", "--walkers", "16", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out["shared"]["R0"]) >= {"median", "q05", "q95"} and out["over"] == ["trial"]


@pytest.mark.parametrize("weighting", ["modulus", "unit"])
def test_everything_shared_over_copies_of_one_spectrum_is_the_single_fit(problem, weighting):
    """M identical spectra, every parameter shared: the same minimum as one spectrum's fit, χ²
    M times larger and JᵀJ M times larger, so stderr_joint = stderr_one·√((2N − K)/(2NM − K))."""
    z = problem[1][0]
    m, n, k = 3, FREQ.size, 3
    one = ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, z), weighting=weighting)
    copies = ix.make_spectrum(FREQ, np.stack([z] * m), dims=("trial",))
    r = ix.fit("R0 + R1 || C1", copies, shared=["R0", "R1", "C1"], weighting=weighting)
    for name in ("R0", "R1", "C1"):
        assert float(r.values(name)) == pytest.approx(one.values[name], rel=1e-6)
        expected = one.stderr[name] * np.sqrt((2 * n - k) / (2 * n * m - k))
        assert float(r.dataset["shared_stderr"].sel(shared_param=name)) == pytest.approx(expected, rel=1e-4)
    assert float(r.dataset["joint_chi2"]) == pytest.approx(m * one.chi2, rel=1e-8)


def test_poorly_determined_shared_parameter_is_reported():
    """Data far above the arc's corner (f ≫ 1/(2πR1C1) ≈ 0.2 Hz): R1 barely changes Z."""
    rng = np.random.default_rng(2)
    f = np.geomspace(1e4, 1e6, 30)
    z = np.stack([rc_impedance(f, r0, 1e6, c1) for r0, c1 in ((50.0, 1e-6), (60.0, 2e-6), (55.0, 1.5e-6))])
    z = z * (1 + 0.01 * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape)))
    r = ix.fit("R0 + R1 || C1", ix.make_spectrum(f, z, dims=("trial",)), shared=["R1"])
    (notes,) = [w for key, w in r.warnings.items() if key == "shared over trial"]
    assert any(n.startswith("shared R1 has a relative standard error") for n in notes)
    assert not r.dataset["at_bound"].sel(param="R1").any()  # near 0 within its huge stderr, but not at it


SERIES_PAIR = "R0 + R1 + R2 || C2"  # R0 and R1 in series: only R0 + R1 changes Z
R_SERIES = (20.0, 30.0)  # Ω: R0, R1
PAIR_WORDS = "R0, R1 are not separately determined by the data (near-singular Jacobian, singular-value ratio "  # (a single fit's warning, `result.unidentified_group_note`)


def series_pair_data(noise: float, seed: int = 7):
    """SYNTHETIC: two spectra of R0 + R1 + R2 ∥ C2 written out, R0 + R1/(… ) = R0 + R1 + R2/(1 + jωR2C2),
    one R0, R1, C2 and R2 of 800 and 1500 Ω, with ``noise`` relative complex noise (fixed seed)."""
    rng = np.random.default_rng(seed)
    r2 = np.array([800.0, 1500.0])
    w = 2 * np.pi * FREQ
    z = np.stack([sum(R_SERIES) + r / (1 + 1j * w * r * 4e-7) for r in r2])
    z = z * (1 + noise * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape)))
    return ix.make_spectrum(FREQ, z, dims=("trial",), coords={"trial": [1, 2]}), r2


@pytest.mark.parametrize("noise", [0.0, 0.01])
def test_series_pair_with_one_shared_is_reported_unidentified_in_each_spectrum(noise, tmp_path):
    """R0 shared, R1 each spectrum's own: moving R0 by δ and every R1 by −δ leaves every
    spectrum's Z alone, a null direction of the joint Jacobian through shared and own
    parameters. Each spectrum reports the group (as `FitResult.unidentified_groups`, in a single
    fit's words) and both have no standard error, on noise-free data too (where χ²_red ≈ 1e-30
    shrank the regularised variance to a finite stderr before); the identified R2, C2 keep theirs."""
    data, r2 = series_pair_data(noise)
    r = ix.fit(SERIES_PAIR, data, shared=["R0"])
    for trial in (1, 2):
        assert r.unidentified_groups_of(trial=trial) == (("R0", "R1"),)
        assert any(w.startswith(PAIR_WORDS) and w.endswith("only a combination of them changes Z; fix one of them") for w in r.warnings[f"trial={trial}"])
    assert [row["unidentified_groups"] for row in r.summary()["spectra"]] == [[["R0", "R1"]]] * 2
    assert np.all(np.isinf(r.dataset["stderr"].sel(param=["R0", "R1"]).values))
    assert np.isinf(float(r.dataset["shared_stderr"].sel(shared_param="R0")))
    assert np.all(np.isinf(r.dataset["linearised_stderr"].sel(param=["R0", "R1"]).values))
    # oracle: the sum and the identified parameters are those written above, with finite errors
    total = r.dataset["value"].sel(param="R0").values + r.dataset["value"].sel(param="R1").values
    np.testing.assert_allclose(total, sum(R_SERIES), rtol=1e-6 if noise == 0 else 0.02)
    np.testing.assert_allclose(r.values("R2").values, r2, rtol=1e-6 if noise == 0 else 0.05)
    assert np.all(np.isfinite(r.dataset["stderr"].sel(param=["R2", "C2"]).values))
    assert not any("R2" in w or "C2" in w for ws in r.warnings.values() for w in ws if "not separately determined" in w)
    if noise:  # (the groups survive the .nc file)
        ix.write_result(r, tmp_path / "shared.nc")
        back = ix.SharedFitResult.from_xarray(ix.load(tmp_path / "shared.nc"))
        assert back.unidentified_groups_of(trial=2) == (("R0", "R1"),)


def test_series_pair_both_shared_is_said_once_per_global_fit():
    """R0 and R1 both shared: a direction of shared parameters alone, said once under the
    global fit's key ("shared " + a single fit's words), its pair's −1 correlation not said
    again in each spectrum; each spectrum's groups still hold it (its fit's parameters)."""
    data, _ = series_pair_data(0.01)
    r = ix.fit(SERIES_PAIR, data, shared=["R0", "R1"])
    (notes,) = [w for key, w in r.warnings.items() if key == "shared over trial"]
    assert any(n.startswith("shared " + PAIR_WORDS) for n in notes)
    assert not any(n.startswith(("shared R0 has", "shared R1 has")) for n in notes)
    assert not any("R0 and R1 are strongly correlated" in w for ws in r.warnings.values() for w in ws)
    assert r.unidentified_groups_of(trial=1) == r.unidentified_groups_of(trial=2) == (("R0", "R1"),)
    assert np.all(np.isinf(r.dataset["shared_stderr"].values))


def test_no_group_where_the_data_determine_every_parameter(problem, shared_fit):
    """R0 + R1 ∥ C1 with R0 shared over 4 noisy spectra: no near-null direction, so no groups
    (an empty record, not a missing one), finite standard errors near each spectrum's fit alone
    (the independent batch, `test_batch_json`: equal to single fits): R1, C1 within 2×, the
    pooled R0 below the single fits' but above a quarter of them (4 spectra: about 1/√4)."""
    r = shared_fit
    assert r.dataset.attrs["unidentified_groups"] == {}
    assert all(r.unidentified_groups_of(trial=t) == () for t in (1, 2, 3, 4))
    assert all(row["unidentified_groups"] == [] for row in r.summary()["spectra"])
    assert not any("not separately determined" in w or "not determined by the data" in w for ws in r.warnings.values() for w in ws)
    single = ix.fit("R0 + R1 || C1", problem[0])
    for name in ("R1", "C1"):
        ratio = r.dataset["stderr"].sel(param=name).values / single.dataset["stderr"].sel(param=name).values
        assert np.all(np.isfinite(ratio)) and np.all((ratio > 0.5) & (ratio < 2.0))
    pooled = float(r.dataset["shared_stderr"].sel(shared_param="R0"))
    alone = single.dataset["stderr"].sel(param="R0").values
    assert np.all((pooled < alone) & (pooled > alone / 4))


def test_cli_sample_shared_corner(problem, tmp_path, capsys):
    # (the band figure, --plot, since 2026-12-03: tests/test_shared_posterior_bands.py)
    path, png = tmp_path / "three.nc", tmp_path / "corner.png"
    ix.save(problem[0].isel(trial=slice(0, 2)), path)
    assert main(["sample", str(path), "--model", "R0 + R1 || C1", "--shared", "R0", "--steps", "40", "--walkers", "16", "--quiet", "--corner", str(png)]) == 0
    assert png.stat().st_size > 1000 and "R0" in capsys.readouterr().out


def test_a_joint_corner_of_many_parameters_draws_the_shared_ones_and_the_first_spectrum_s(tmp_path, capsys):
    """(walkthrough 2026-12-03: 20 parameters on one 16 in figure overprinted their labels.)
    Five trials of R0 + R1 || C1 sharing R0: 12 names, beyond `CORNER_MAX_PARAMS` (10); by
    default R0, trial 1's R1 and C1 and sigma_rel; ``params=`` / ``--corner-params`` any others."""
    z, _, _ = rc_stack(np.random.default_rng(5), m=5)
    path, out, png = tmp_path / "five.nc", tmp_path / "post.nc", tmp_path / "corner.png"
    ix.save(ix.make_spectrum(FREQ, z, dims=("trial",), coords={"trial": [1, 2, 3, 4, 5]}), path)
    base = ["sample", str(path), "--model", "R0 + R1 || C1", "--shared", "R0", "--steps", "30", "--walkers", "26", "--quiet"]
    assert main(base + ["--corner", str(png), "--corner-params", "R0,R1[trial=3]", "--corner-params", "sigma_rel", "--out", str(out)]) == 0
    assert png.stat().st_size > 1000
    capsys.readouterr()
    post = ix.SharedPosterior.from_xarray(ix.load(out))
    assert len(post.names) == 12
    fig = post.corner()
    diagonal = [ax.get_title().split(" =")[0] for ax in fig.axes if ax.get_visible() and ax.get_title()]
    assert diagonal == ["R0", "R1[trial=1]", "C1[trial=1]", "sigma_rel"]
    assert "the shared parameters, trial=1's and the noise" in fig._suptitle.get_text() and "4 of 12 parameters" in fig._suptitle.get_text()
    fig = post.corner(params=["R1[trial=5]", "R0"])
    assert [ax.get_title().split(" =")[0] for ax in fig.axes if ax.get_visible() and ax.get_title()] == ["R1[trial=5]", "R0"]
    with pytest.raises(ix.ParameterError, match=r"params: unknown parameter 'R1\[trial=9\]'"):
        post.corner(params=["R1[trial=9]"])
    # the command line names its option, before any output is written
    bad = tmp_path / "bad.png"
    assert main(base + ["--corner", str(bad), "--corner-params", "R0,R9"]) == 2
    assert "--corner-params: unknown parameter 'R9'" in capsys.readouterr().err and not bad.exists()
    assert main(base + ["--corner-params", "R0"]) == 2
    assert "give --corner too" in capsys.readouterr().err


def test_table_and_csv_mark_the_shared_rows(problem, shared_fit, tmp_path):
    # (walkthrough 2026-12-02: the CSV repeated the shared R0 on each trial's row unmarked, so
    # averaging rows counted its one estimate 4 times)
    rows = shared_fit.to_table()
    assert list(rows[0])[list(rows[0]).index("fixed") + 1] == "shared"  # (after fixed; every other column kept)
    assert {r["name"] for r in rows if r["shared"]} == {"R0"} and sum(r["shared"] for r in rows) == 4
    assert [r["stderr"] for r in rows if r["shared"]] == [pytest.approx(shared_fit.summary()["shared"]["R0"]["stderr"])] * 4
    path = tmp_path / "shared.csv"
    ix.write_result(shared_fit, path)
    header, *lines = path.read_text().splitlines()
    columns = header.split(",")
    assert {"value", "stderr", "fixed", "shared"} <= set(columns)
    marked = [line.split(",")[columns.index("name")] for line in lines if line.split(",")[columns.index("shared")] == "true"]
    assert marked == ["R0"] * 4


def test_stderr_has_the_shape_of_values(problem, shared_fit):
    _, z, _, _ = problem
    _, se, _ = brute_force(z)  # the dense joint least squares' standard errors: the oracle
    assert float(shared_fit.stderr("R0")) == pytest.approx(se[0], rel=1e-4)
    assert shared_fit.stderr("R0").dims == shared_fit.values("R0").dims == ()
    np.testing.assert_allclose(shared_fit.stderr("R1").values, se[1:5], rtol=1e-4)
    assert shared_fit.stderr("R1").dims == shared_fit.values("R1").dims == ("trial",)
    with pytest.raises(ix.ParameterError, match="R1"):
        shared_fit.stderr("R7")


def test_plot_against_a_numeric_coordinate(shared_fit):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = shared_fit.plot(x="trial", params=["R1"])
    ax = fig.axes[0]
    assert ax.get_xlabel() == "trial"
    (line,) = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
    np.testing.assert_allclose(line.get_xdata(), [1, 2, 3, 4])  # (the trials' coordinate, one series)
    np.testing.assert_allclose(line.get_ydata(), shared_fit.values("R1").values)
    plt.close(fig)
    with pytest.raises(ix.ParameterError, match=r"a dimension of the batch \(trial\)"):
        shared_fit.plot(x="voltage")


def test_bad_shared_arguments_are_caught_before_the_progress_line(problem):
    lines = []
    with pytest.raises(ix.ParameterError, match="unknown parameter 'R9'"):
        ix.fit("R0 + R1 || C1", problem[0], shared=["R9"], progress=lines.append)
    with pytest.raises(ix.ParameterError, match="'session' is not a dimension"):
        ix.fit("R0 + R1 || C1", problem[0], shared=["R0"], over="session", progress=lines.append)
    assert lines == []  # (docs/cli.md, "From Python": inputs are checked before any work; "fitting … together" came first until 2026-12-02)


def test_a_global_fit_per_group_names_its_groups_in_the_grouped_warning_line():
    """R0, R1 shared over trial, one global fit per session: each fit's note is filed under
    "shared over trial (session=a)" and "(session=b)", and the report's line names both fits
    (until 2026-12-03: "2 of 4 spectra: shared over trial (session a), b)")."""
    pairs = [series_pair_data(0.01, seed) for seed in (7, 8)]
    z = np.stack([data["Z"].values for data, _ in pairs])
    data = ix.make_spectrum(FREQ, z, dims=("session", "trial"), coords={"session": ["a", "b"], "trial": [1, 2]})
    r = ix.fit(SERIES_PAIR, data, shared=["R0", "R1"], over="trial")
    assert set(r.warnings) >= {"shared over trial (session=a)", "shared over trial (session=b)"}
    (line,) = [ln for ln in r.report().splitlines() if "not separately determined" in ln]
    assert line.startswith("warning (shared over trial (session a, b)): shared " + PAIR_WORDS)


def test_two_near_null_directions_over_the_same_parameters_give_one_group_in_a_global_fit():
    """`joint_null_sets` by the rule of `null_sets` (fixed there 2026-12-03): two near-null
    directions over the same parameters are one group, whether they move each spectrum's own
    parameters or the shared ones alone. A Jacobian written here from its SVD: unit-norm-equal
    columns (a Hadamard Vt), singular values 1, 1, 1e-14, 1e-15, both null rows over all four
    parameters (components ±0.5); then the REAL CHInstruments spectrum, twice, L1 shared, whose
    Havriliak–Negami element has two such directions (listed and warned twice before)."""
    from pathlib import Path

    from impedax.fitting.least_squares.shared import joint_null_sets

    hadamard = 0.5 * np.array([[1, 1, 1, 1], [1, -1, 1, -1], [1, 1, -1, -1], [1, -1, -1, 1]], float)
    u, _ = np.linalg.qr(np.random.default_rng(1).normal(size=(10, 4)))
    jac = np.stack([u @ np.diag([1.0, 1.0, 1e-14, 1e-15]) @ hadamard] * 2)
    names = ["A", "B", "C", "D"]
    alone = joint_null_sets(jac, [], [0, 1, 2, 3], names)  # (every parameter shared)
    assert alone.shared_groups == [names] and alone.groups == [[names], [names]]
    own = joint_null_sets(jac, [0, 1, 2, 3], [], names)  # (every parameter each spectrum's own)
    assert own.groups == [[names], [names]] and own.shared_groups == []
    real = ix.load(Path(__file__).parent / "fixtures" / "real" / "exampleDataCHInstruments.txt")
    twice = ix.make_spectrum(real["frequency"].values, np.stack([real["Z"].values] * 2), dims=("copy",), coords={"copy": [0, 1]})
    r = ix.fit("R0 + HN1 + L1", twice, shared=["L1"], over="copy")
    hn = ("HN1.R", "HN1.tau", "HN1.alpha", "HN1.beta")
    for copy in (0, 1):
        assert r.unidentified_groups_of(copy=copy) == (hn,)
        assert sum("are not separately determined" in w for w in r.warnings[f"copy={copy}"]) == 1
