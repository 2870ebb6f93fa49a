"""A joint posterior (`sample(..., shared=, over=)`) written to .nc and read back: every draw,
name, unit, setting, the data and the start fit equal, its report and derived quantities the
same; bad files one `DataError` naming the file and what is missing; the CLI's --out file."""

import json

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main
from impedax.io import read_netcdf, write_netcdf

FREQ = np.geomspace(1.0, 1e5, 30)
MODEL = "R0 + R1 || C1"


def rc_impedance(f, r0, r1, c1):
    return r0 + r1 / (1 + 2j * np.pi * np.asarray(f) * r1 * c1)


def stack(seed, shape):
    """Noisy RC spectra (1 % proportional) over an array of the given shape, R0 common."""
    rng = np.random.default_rng(seed)
    r1 = rng.uniform(500.0, 2000.0, shape)
    c1 = rng.uniform(1e-7, 1e-6, shape)
    z = rc_impedance(FREQ, 50.0, r1[..., None], c1[..., None])
    return z * (1 + 0.01 * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape)))


@pytest.fixture(scope="module")
def proportional():
    data = ix.make_spectrum(FREQ, stack(1, (2,)), dims=("trial",), coords={"trial": [3, 7]})
    return ix.sample(MODEL, data, shared=["R0"], over="trial", steps=30, walkers=16, seed=3, progress=False)


@pytest.fixture(scope="module")
def with_sigma():
    """σ noise, the data's sigma, two dimensions shared over (one without coordinates), R0 fixed."""
    z = stack(2, (2, 1))
    data = ix.make_spectrum(FREQ, z, sigma=0.01 * np.abs(z), dims=("session", "trial"), coords={"session": ["a", "b"]})
    return ix.sample(MODEL, data, shared=["C1"], over=["session", "trial"], noise="sigma", fixed={"R0": 50.0}, steps=30, walkers=16, seed=4, progress=False)


def without_attrs(ds, *names):
    out = ds.copy()
    out.attrs = {k: v for k, v in ds.attrs.items() if k not in names}
    return out


def tau(p):
    return p["R1[trial=3]"] * p["C1[trial=3]"]


def assert_same(back, post):
    assert isinstance(back, ix.SharedPosterior)
    for name in ("draws", "log_prob", "acceptance", "sigma"):
        np.testing.assert_array_equal(getattr(back, name), getattr(post, name))
    for name in ("model", "shared", "over", "spectra", "names", "units", "log_scale", "priors", "noise", "notes", "settings", "warnings"):
        assert getattr(back, name) == getattr(post, name), name
    xr.testing.assert_identical(back.fit.dataset["Z"], post.fit.dataset["Z"])  # the data
    xr.testing.assert_equal(back.fit.dataset, post.fit.dataset)
    assert (back.fit.shared, back.fit.over, back.fit.weighting, back.fit.warnings, back.fit.elapsed_s) == (post.fit.shared, post.fit.over, post.fit.weighting, post.fit.warnings, post.fit.elapsed_s)
    assert back.fit.report() == post.fit.report() and back.fit.to_table() == post.fit.to_table()
    assert post.fit.warning_tags is not None and dict(back.fit.warning_tags) == dict(post.fit.warning_tags)  # (what each warning says: docs/fitting.md "What a warning says")
    assert back.report() == post.report()
    assert json.dumps(back.summary(), sort_keys=True) == json.dumps(post.summary(), sort_keys=True)  # (NaN τ: compared as text)
    assert back.to_table() == post.to_table()
    xr.testing.assert_identical(back.quantiles(), post.quantiles())


def test_write_result_file_reads_back_whole(proportional, tmp_path):
    path = tmp_path / "joint.nc"
    ix.write_result(proportional, path)
    back = ix.SharedPosterior.from_xarray(ix.load(path))  # the way a Posterior file is read
    assert_same(back, proportional)
    xr.testing.assert_identical(back.derive(tau), proportional.derive(tau))
    band = lambda p, f: p["R0"] + 0 * f  # noqa: E731  (a quantity over the data's frequencies)
    xr.testing.assert_identical(ix.derive(back, band), ix.derive(proportional, band))
    assert_same(ix.SharedPosterior.from_xarray(read_netcdf(path)), proportional)
    with xr.open_dataset(path) as raw:  # opened as stored: encoded attrs and split complex Z
        assert_same(ix.SharedPosterior.from_xarray(raw.load()), proportional)
    again = tmp_path / "again.nc"  # read back, written again: the same file content
    ix.write_result(back, again)
    # (but for when it was written: each file records its own time, docs/io.md "Provenance")
    undated = lambda ds: ds.drop_encoding().assign_attrs(written_utc="", provenance="")  # noqa: E731
    xr.testing.assert_identical(undated(read_netcdf(again)), undated(read_netcdf(path)))


def test_sigma_noise_fixed_parameter_and_two_dimensions_round_trip(with_sigma, tmp_path):
    path = tmp_path / "joint.nc"
    ix.write_result(with_sigma, path)
    back = ix.SharedPosterior.from_xarray(ix.load(path))
    assert_same(back, with_sigma)
    np.testing.assert_array_equal(back.sigma, with_sigma.sigma)
    np.testing.assert_array_equal(ix.load(path)["sigma"].transpose("session", "trial", "frequency").values, 0.01 * np.abs(stack(2, (2, 1))))
    assert back.over == ("session", "trial") and back.spectra == ("session=a, trial=0", "session=b, trial=0")
    assert with_sigma.summary()["fixed"] == back.summary()["fixed"] == {"R0": 50.0}  # (--json's key, as a single posterior's)
    fn = lambda p: p["R0"] * p["C1"]  # noqa: E731  (R0 fixed: given by value)
    out = back.derive(fn)
    xr.testing.assert_identical(out, with_sigma.derive(fn))
    assert float(out["median"]) == pytest.approx(50.0 * float(np.median(with_sigma.samples["C1"])), rel=1e-12)


def test_to_xarray_in_memory_round_trip(proportional):
    assert_same(ix.SharedPosterior.from_xarray(proportional.to_xarray()), proportional)


def test_posterior_file_read_as_a_joint_one_names_the_file(tmp_path):
    post = ix.sample(MODEL, ix.make_spectrum(FREQ, stack(5, ())), steps=20, walkers=16, seed=1, progress=False)
    path = tmp_path / "single.nc"
    ix.write_result(post, path)
    with pytest.raises(ix.DataError) as info:
        ix.SharedPosterior.from_xarray(ix.load(path))
    assert str(info.value).startswith(f"{path}: ") and "single-spectrum posterior" in str(info.value) and "Posterior.from_xarray" in str(info.value)


def test_spectrum_file_is_not_a_joint_posterior(tmp_path):
    path = tmp_path / "spectrum.nc"
    ix.save(ix.make_spectrum(FREQ, stack(6, ())), path)
    with pytest.raises(ix.DataError, match=r"not a saved impedax joint \(shared-parameter\) posterior \(impedax_kind None") as info:
        ix.SharedPosterior.from_xarray(ix.load(path))
    assert info.value.path == str(path)
    with pytest.raises(ix.DataError, match="from_xarray takes an xarray.Dataset, got str"):
        ix.SharedPosterior.from_xarray(str(path))


@pytest.mark.parametrize(
    "damage, text",
    [
        (lambda ds: ds.drop_vars("log_prob"), "missing variable(s) 'log_prob'"),
        (lambda ds: ds.drop_vars(["draws", "fit_covariance"]), "missing variable(s) 'draws', 'fit_covariance'"),
        (lambda ds: without_attrs(ds, "priors"), "missing attribute(s) 'priors'"),
        (lambda ds: ds.assign_attrs(units=["Ohm"]), "damaged saved joint (shared-parameter) posterior: 6 sampled parameters but 1 units"),
        (lambda ds: ds.assign_attrs(model="R0 +"), "damaged saved joint (shared-parameter) posterior: "),
    ],
    ids=["log_prob", "draws-and-fit", "priors-attr", "units", "model"],
)
def test_damaged_file_is_one_data_error_naming_file_and_what_is_missing(proportional, tmp_path, damage, text):
    path = tmp_path / "damaged.nc"
    write_netcdf(damage(proportional.to_xarray()), path)
    with pytest.raises(ix.DataError) as info:
        ix.SharedPosterior.from_xarray(read_netcdf(path))
    assert str(info.value).startswith(f"{path}: ") and text in str(info.value)
    assert info.value.__cause__ is None and (info.value.__context__ is None or info.value.__suppress_context__)  # one error, no xarray traceback under it


def test_old_file_without_data_or_start_fit_says_what_is_missing(proportional, tmp_path):
    """A file of the former to_xarray (draws and summaries only) names what it lacks."""
    ds = proportional.to_xarray()
    old = ds.drop_vars([k for k in ds.variables if str(k).startswith("fit_") or k in ("Z", "frequency", "trial")])
    old = without_attrs(old, "spectra", "notes", "fit", "fit_variables", "fit_dims")
    path = tmp_path / "old.nc"
    write_netcdf(old, path)
    with pytest.raises(ix.DataError, match=r"missing variable\(s\) 'Z', 'frequency' and attribute\(s\) 'spectra', 'fit', 'fit_variables', 'fit_dims'"):
        ix.SharedPosterior.from_xarray(read_netcdf(path))


def test_joint_file_read_as_single_posterior_is_a_data_error(proportional, tmp_path):
    path = tmp_path / "joint.nc"
    ix.write_result(proportional, path)
    with pytest.raises(ix.DataError, match=r"joint\.nc: a saved joint \(shared-parameter\) posterior, not a single-spectrum posterior: read it with SharedPosterior\.from_xarray"):
        ix.Posterior.from_xarray(ix.load(path))


def test_cli_sample_shared_out_reads_back(tmp_path, capsys):
    data, out = tmp_path / "two.nc", tmp_path / "joint.nc"
    ix.save(ix.make_spectrum(FREQ, stack(7, (2,)), dims=("trial",), coords={"trial": [3, 7]}), data)
    assert main(["sample", str(data), "--model", MODEL, "--shared", "R0", "--steps", "30", "--walkers", "16", "--seed", "2", "--json", "--out", str(out)]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed.pop("source") == str(data)  # (the command's JSON names its data file; the saved posterior's summary does not)
    assert printed.pop("provenance")["settings"]["seed"] == 2  # (nor what made it: the file's attributes hold that)
    assert printed.pop("skipped_rows") == []  # (nor what its reader skipped: a key of the command's JSON, as fit's)
    back = ix.SharedPosterior.from_xarray(ix.load(out))
    assert json.loads(json.dumps(ix.io.export.to_jsonable(back.summary()))) == printed
    assert back.settings["seed"] == 2 and back.settings["steps"] == 30 and back.n_walkers == 16
    np.testing.assert_array_equal(back.fit.dataset["Z"].values, ix.load(data)["Z"].values)
    assert back.derive(tau)["median"].size == 1


# --- the hierarchical model's result (`sample_hierarchical`) --------------------------------


@pytest.fixture(scope="module")
def hierarchical():
    from impedax.fitting.bayes.hierarchical import sample_hierarchical

    data = ix.make_spectrum(FREQ, stack(8, (3,)), dims=("trial",))
    return sample_hierarchical(MODEL, data, per_trial=("R1",), chains=2, warmup=20, draws=20, seed=1)


def constructed_hierarchical():
    """A `HierarchicalPosterior` built by hand (no sampling): sessions × trials stacked, a gap
    reparametrization, a fixed parameter and both error sds, the fields a small run lacks."""
    from impedax.fitting.bayes.hierarchical import HierarchicalPosterior
    from impedax.fitting.bayes.reparam import gap_thickness_reparametrization

    rng = np.random.default_rng(9)
    index = xr.Dataset(coords={"session": ["a", "b"], "trial": [4, 5]}).stack(trial_index=("session", "trial"))["trial_index"]
    c, d, t, n = 2, 6, 4, FREQ.size
    mu = np.log([1000.0, 3e-9]) + 0.05 * rng.normal(size=(c, d, 2))
    return HierarchicalPosterior(
        circuit=ix.parse("R0 + R1 || C1 + R2"), trial_names=("R1", "u"), shared_names=("R0",), mu=mu, spread=rng.uniform(0.05, 0.2, (c, d, 2)),
        spread_session=rng.uniform(0.01, 0.1, (c, d, 2)), trial_values=np.exp(mu[:, :, None, :] + 0.1 * rng.normal(size=(c, d, t, 2))),
        shared=rng.uniform(49.0, 51.0, (c, d, 1)), delta=rng.uniform(0.001, 0.01, (c, d)), frequency=FREQ, z_data=stack(9, (t,)), nu=rng.uniform(0.005, 0.02, n),
        trial_index=index, sessions=2, discrepancy=True, divergences=3, step_size=rng.uniform(0.1, 0.5, c), mean_tree_steps=7.5, mean_acceptance=0.81, elapsed_s=1.25,
        fixed={"R2": 5.0}, common_sd=rng.uniform(0.1, 1.0, (2, n)), trial_sd=rng.uniform(0.1, 1.0, (2, n)),
        reparametrization=gap_thickness_reparametrization("C1", area=1e-4),
    )


def assert_same_hierarchical(back, post):
    for name in ("mu", "spread", "spread_session", "trial_values", "shared", "delta", "frequency", "z_data", "nu", "step_size", "common_sd", "trial_sd"):
        np.testing.assert_array_equal(getattr(back, name), getattr(post, name), err_msg=name)
    for name in ("model", "trial_names", "shared_names", "sessions", "discrepancy", "divergences", "mean_tree_steps", "mean_acceptance", "elapsed_s", "fixed", "warnings"):
        assert getattr(back, name) == getattr(post, name), name
    xr.testing.assert_identical(back.trial_index, post.trial_index)
    assert (back.reparametrization and back.reparametrization.describe()) == (post.reparametrization and post.reparametrization.describe())
    assert back.report() == post.report()
    assert json.dumps(back.summary(), sort_keys=True) == json.dumps(post.summary(), sort_keys=True)
    np.testing.assert_array_equal(back.predict(max_draws=8), post.predict(max_draws=8))
    for k, v in post.population_parameters().items():
        np.testing.assert_array_equal(back.population_parameters()[k], v, err_msg=k)


@pytest.mark.slow  # (a real NUTS run, 20 s; the hand-built hierarchical result below covers the format)
def test_hierarchical_result_reads_back(hierarchical, tmp_path):
    path = tmp_path / "hierarchical.nc"
    ix.write_result(hierarchical, path)
    assert_same_hierarchical(type(hierarchical).from_xarray(ix.load(path)), hierarchical)


def test_hierarchical_with_sessions_reparametrization_and_error_sds_reads_back(tmp_path):
    post = constructed_hierarchical()
    path = tmp_path / "hierarchical.nc"
    ix.write_result(post, path)
    back = type(post).from_xarray(ix.load(path))
    assert_same_hierarchical(back, post)
    assert back.trial_index.to_index().names == ["session", "trial"] and back.population_parameters()["C1"].shape == (12,)
    assert post.summary()["fixed"] == back.summary()["fixed"] == {"R2": 5.0}
    with xr.open_dataset(path) as raw:  # opened as stored
        assert_same_hierarchical(type(post).from_xarray(raw.load()), post)


def test_hierarchical_bad_files_name_the_file(proportional, tmp_path):
    from impedax.fitting.bayes.hierarchical import HierarchicalPosterior

    joint = tmp_path / "joint.nc"
    ix.write_result(proportional, joint)
    with pytest.raises(ix.DataError, match="a saved joint .* not a hierarchical posterior: read it with SharedPosterior.from_xarray") as info:
        HierarchicalPosterior.from_xarray(ix.load(joint))
    assert info.value.path == str(joint)
    path = tmp_path / "damaged.nc"
    write_netcdf(constructed_hierarchical().to_xarray().drop_vars("trial_values"), path)
    with pytest.raises(ix.DataError) as info:
        HierarchicalPosterior.from_xarray(read_netcdf(path))
    assert str(info.value) == f"{path}: incomplete saved hierarchical posterior: missing variable(s) 'trial_values'"
    write_netcdf(constructed_hierarchical().to_xarray().assign_attrs(trial_levels=["session", "cycle"]), path)
    with pytest.raises(ix.DataError, match=r"damaged saved hierarchical posterior: .*cycle") as info:
        HierarchicalPosterior.from_xarray(read_netcdf(path))
    assert info.value.path == str(path)


def test_a_joint_posterior_without_straggler_walkers_counts_the_runs_walkers(proportional):
    """The joint posterior's JSON, as the single one's: ``walkers`` the run's, ``walkers_kept``
    those whose draws it holds, ``draws_total`` their draws (one walker left out by hand)."""
    import dataclasses

    from impedax.fitting.bayes.diagnostics import Stragglers

    run = proportional.n_walkers
    fewer = dataclasses.replace(proportional, draws=proportional.draws[1:], log_prob=proportional.log_prob[1:], acceptance=proportional.acceptance[1:],
                                stragglers=Stragglers((0,), (31.5,), (0.09,), 0.6, proportional.n_draws))
    s = fewer.summary()
    assert (s["walkers"], s["walkers_kept"], s["straggler_walkers"]) == (run, run - 1, [0])
    assert s["draws_total"] == (run - 1) * proportional.n_draws
    assert proportional.summary()["walkers"] == proportional.summary()["walkers_kept"] == run
