"""Results out: tidy CSV, JSON and netCDF by extension (`impedax.io.write_result`), ``--out`` on
the commands, ``fit(init=fit_result)`` and the notebook display (``_repr_html_``).

Files are read back with the standard library's csv/json and compared with the results'
own attributes and with quantiles computed here, not with the writer's code."""

import csv
import dataclasses
import json

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main
from impedax.fitting import Refinement
from impedax.fitting.parameters import ParameterTable
from impedax.fitting.diagnosis.refinement import RefinementStep
from impedax.plotting.html import result_html
from spectra import CASES, noisy

RC_UNITS = {"R0": "Ohm", "R1": "Ohm", "C1": "F"}  # the units of R and C, written by hand


def _rc_data(seed=0, n=40):
    text, fn, truth, (lo, hi) = CASES["rc"]
    f = np.geomspace(lo, hi, n)
    return ix.make_spectrum(f, noisy(fn(f, truth), 0.01, np.random.default_rng(seed)))


@pytest.fixture(scope="module")
def rc_fit():
    return ix.fit("R0 + R1 || C1", _rc_data(), fixed={"R0": 50.0})


@pytest.fixture(scope="module")
def rc_batch():
    text, fn, truth, (lo, hi) = CASES["rc"]
    f = np.geomspace(lo, hi, 40)
    rng = np.random.default_rng(1)
    z = np.stack([noisy(fn(f, {**truth, "R1": r1}), 0.01, rng) for r1 in (1000.0, 2000.0, 4000.0)])
    data = ix.make_spectrum(f, z, dims=("cell",), coords={"cell": ["a", "b", "c"]})
    return ix.fit(text, data)


def _read_csv(path):
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def test_fit_csv_rows_are_the_fitted_parameters(rc_fit, tmp_path):
    ix.write_result(rc_fit, tmp_path / "fit.csv")
    rows = _read_csv(tmp_path / "fit.csv")
    assert list(rows[0]) == ["name", "value", "stderr", "unit", "fixed", "rms_rel", "chi2", "chi2_red", "aic", "bic", "converged", "at_bound", "undetermined", "warnings", "weighting", "misses_structure"]  # (goodness of fit and flags: added 2026-12-01; warnings 2026-12-06, as a batch's; weighting 2026-12-06: what chi2 is against) (misses_structure added 2026-12-06)
    assert [r["name"] for r in rows] == ["R0", "R1", "C1"]
    for r in rows:
        assert float(r["value"]) == rc_fit.values[r["name"]]  # shortest exact text: no rounding
        assert r["unit"] == RC_UNITS[r["name"]]
    r0, r1, c1 = rows
    assert (r0["fixed"], r0["stderr"]) == ("true", "")  # a fixed parameter has no stderr
    assert r1["fixed"] == "false" and float(r1["stderr"]) == rc_fit.stderr["R1"] > 0
    numeric = np.genfromtxt(tmp_path / "fit.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    np.testing.assert_array_equal(numeric["value"], [rc_fit.values[n] for n in ("R0", "R1", "C1")])


def test_fit_json_is_the_summary_and_netcdf_reopens(rc_fit, tmp_path):
    ix.write_result(rc_fit, tmp_path / "fit.json")
    assert json.loads((tmp_path / "fit.json").read_text()) == json.loads(json.dumps(rc_fit.summary()))
    ix.write_result(rc_fit, tmp_path / "fit.NC")  # extensions are case-insensitive
    ds = ix.io.read_netcdf(tmp_path / "fit.NC")
    assert list(ds["param"].values) == ["R0", "R1", "C1"]
    np.testing.assert_array_equal(ds["value"].values, [rc_fit.values[n] for n in ("R0", "R1", "C1")])
    np.testing.assert_array_equal(ds["Z"].values, rc_fit.z_data)


def test_batch_csv_has_a_row_per_spectrum_and_parameter_with_coordinates(rc_batch, tmp_path):
    ix.write_result(rc_batch, tmp_path / "batch.csv")
    rows = _read_csv(tmp_path / "batch.csv")
    assert list(rows[0]) == ["cell", "name", "value", "stderr", "unit", "fixed", "rms_rel", "chi2", "chi2_red", "aic", "bic", "converged", "at_bound", "undetermined", "warnings", "weighting", "misses_structure"]  # (goodness of fit and flags: added 2026-12-01; warnings 2026-12-02; weighting 2026-12-06: what chi2 is against) (misses_structure added 2026-12-06)
    assert [(r["cell"], r["name"]) for r in rows] == [(c, n) for c in "abc" for n in ("R0", "R1", "C1")]
    for r in rows:  # each spectrum's warnings, on each of its rows
        assert r["warnings"] == "; ".join(rc_batch.warnings.get(f"cell={r['cell']}", ()))
    for r in rows:
        assert float(r["value"]) == float(rc_batch.values(r["name"]).sel(cell=r["cell"]))
        assert float(r["stderr"]) == float(rc_batch.dataset["stderr"].sel(param=r["name"], cell=r["cell"]))
        assert r["unit"] == RC_UNITS[r["name"]] and r["fixed"] == "false"
    r1 = [float(r["value"]) for r in rows if r["name"] == "R1"]
    np.testing.assert_allclose(r1, [1000.0, 2000.0, 4000.0], rtol=0.05)  # the truth of each cell
    ix.write_result(rc_batch, tmp_path / "batch.json")
    assert json.loads((tmp_path / "batch.json").read_text()) == json.loads(json.dumps(rc_batch.summary()))


def test_csv_rows_flag_a_value_at_a_bound_or_undetermined_and_an_unconverged_spectrum(rc_fit, rc_batch, tmp_path):
    # the batch's values edited by hand: cell b's R1 with a relative error of 5e24 (undetermined,
    # as R2 = 1.08e25 ± 5e49 on a real battery cycle), cell c's C1 on its bound, cell a not converged
    ds = rc_batch.dataset.copy(deep=True)
    ds["stderr"].loc[dict(param="R1", cell="b")] = 5e27
    ds["at_bound"].loc[dict(param="C1", cell="c")] = True
    ds["converged"].loc[dict(cell="a")] = False
    edited = dataclasses.replace(rc_batch, dataset=ds)
    ix.write_result(edited, tmp_path / "batch.csv")
    rows = {(r["cell"], r["name"]): r for r in _read_csv(tmp_path / "batch.csv")}
    assert {k for k, r in rows.items() if r["undetermined"] == "true"} == {("b", "R1")}
    assert {k for k, r in rows.items() if r["at_bound"] == "true"} == {("c", "C1")}
    assert {k for k, r in rows.items() if r["converged"] == "false"} == {("a", n) for n in ("R0", "R1", "C1")}
    # a spectrum's warnings (here one written in by hand) in its rows' warnings column
    warned = dataclasses.replace(edited, warnings={**edited.warnings, "cell=b": ("first note", "second note")})
    assert {(r["cell"], r["warnings"]) for r in warned.to_table()} >= {("b", "first note; second note")}
    for (cell, name), r in rows.items():  # the same rule as the batch's own `undetermined`
        assert (r["undetermined"] == "true") == bool(edited.undetermined(name).sel(cell=cell))
    # a single fit's rows: its R1 made undetermined, its C1 put at a bound; R0 is fixed (never flagged)
    single = dataclasses.replace(rc_fit, stderr={**rc_fit.stderr, "R1": 3.0 * rc_fit.values["R1"]}, at_bound=("C1",), converged=False)
    table = {r["name"]: r for r in single.to_table()}
    assert [(n, r["converged"], r["at_bound"], r["undetermined"]) for n, r in table.items()] == [("R0", False, False, False), ("R1", False, False, True), ("C1", False, True, False)]
    assert all(r["converged"] and not r["undetermined"] and not r["at_bound"] for r in rc_fit.to_table())


def test_netcdf_of_a_fit_names_each_parameters_unit_and_reads_back_with_or_without_it(rc_fit, rc_batch, tmp_path):
    for result, reader in ((rc_fit, ix.FitResult), (rc_batch, ix.BatchFitResult)):
        ds = result.to_xarray()
        assert dict(zip(ds["param"].values.tolist(), ds["unit"].values.tolist())) == RC_UNITS  # (added 2026-12-01)
        path = tmp_path / f"{reader.__name__}.nc"
        ix.write_result(result, path)
        with xr.open_dataset(path) as stored:
            assert dict(zip(stored["param"].values.tolist(), stored["unit"].values.tolist())) == RC_UNITS
            np.testing.assert_array_equal(stored["value"].values, ds["value"].values)
        loaded = ix.load(path)
        back = reader.from_xarray(loaded)
        assert back.to_table() == result.to_table()
        older = reader.from_xarray(loaded.drop_vars("unit"))  # a file written before the units were
        assert older.to_table() == result.to_table()
        assert dict(zip(older.to_xarray()["param"].values.tolist(), older.to_xarray()["unit"].values.tolist())) == RC_UNITS
    assert ix.BatchFitResult.from_xarray(rc_batch.to_xarray()).dataset.identical(rc_batch.dataset)  # (the unit is not kept twice)


def test_save_given_a_result_names_write_result(rc_fit, rc_batch, tmp_path):
    class Table:  # anything write_result takes: here a summary
        def summary(self):
            return {"a": 1}

    for result in (rc_fit, rc_batch, Table()):
        with pytest.raises(ix.DataError) as info:
            ix.save(result, tmp_path / "x.nc")
        assert f"impedax.write_result(result, '{tmp_path / 'x.nc'}')" in str(info.value) and type(result).__name__ in str(info.value)
    with pytest.raises(ix.DataError, match=r"save takes a spectrum Dataset \(impedax.make_spectrum, impedax.load\), got None") as info:
        ix.save(None, tmp_path / "x.nc")  # (not a result: the message as before)
    assert "write_result" not in str(info.value) and list(tmp_path.iterdir()) == []
    ix.write_result(rc_batch, tmp_path / "x.nc")  # what it names works
    assert ix.BatchFitResult.from_xarray(ix.load(tmp_path / "x.nc")).to_table() == rc_batch.to_table()


def test_posterior_csv_holds_the_quantiles_of_the_draws(rc_fit, tmp_path):
    post = ix.sample("R0 + R1 || C1", _rc_data(), steps=120, burn=40, walkers=16, seed=0, progress=False)
    ix.write_result(post, tmp_path / "post.csv")
    rows = _read_csv(tmp_path / "post.csv")
    assert list(rows[0]) == ["name", "median", "q05", "q16", "q84", "q95", "unit", "autocorr", "ess", "undetermined", "fixed", "at_prior_edge", "chain_converged", "warnings"]  # (undetermined, fixed and at_prior_edge: added 2026-12-06; chain_converged and warnings 2026-12-07)
    # τ and ESS as the JSON's keys: emcee's own estimator on the kept draws in the sampled
    # space (c = 5, tol = 0; log for a log-sampled parameter), ESS = walkers × draws / τ
    import emcee

    for r in rows:
        i = post.names.index(r["name"])
        y = post.draws[..., i]
        y = np.log(y) if post.log_scale[i] else y
        tau = float(emcee.autocorr.integrated_time(np.transpose(y)[:, :, None], c=5, tol=0)[0])
        assert float(r["autocorr"]) == pytest.approx(tau, rel=1e-8)
        assert float(r["ess"]) == pytest.approx(post.n_walkers * post.n_draws / max(tau, 1.0), rel=1e-8)
        assert float(r["autocorr"]) == post.summary()["autocorr"][r["name"]] and float(r["ess"]) == post.summary()["ess"][r["name"]]
    names = [r["name"] for r in rows]
    assert {"R0", "R1", "C1"} <= set(names)
    for r in rows:
        draws = post.samples[r["name"]]
        expected = np.quantile(draws, [0.5, 0.05, 0.16, 0.84, 0.95])
        np.testing.assert_allclose([float(r[k]) for k in ("median", "q05", "q16", "q84", "q95")], expected, rtol=1e-12)
        if r["name"] in RC_UNITS:
            assert r["unit"] == RC_UNITS[r["name"]]
    ix.write_result(post, tmp_path / "post.nc")
    assert ix.io.read_netcdf(tmp_path / "post.nc")["draws"].shape == post.draws.shape
    html = post._repr_html_()
    assert "<table>" in html and "R1" in html


def test_diagnosis_csv_has_the_baseline_then_the_candidates(tmp_path):
    text, fn, truth, (lo, hi) = CASES["r_cpe"]
    f = np.geomspace(lo, hi, 40)
    data = ix.make_spectrum(f, noisy(fn(f, truth), 0.005, np.random.default_rng(2)))
    d = ix.diagnose(data, "R0 + R1 || C1", effects=ix.fitting.DEFAULT_EFFECTS.select(["constant_phase", "extra_relaxation"]))
    ix.write_result(d, tmp_path / "d.csv")
    rows = _read_csv(tmp_path / "d.csv")
    baseline = [r for r in rows if r["section"] == "baseline"]
    candidates = [r for r in rows if r["section"] == "candidate"]
    assert len(baseline) + len(candidates) == len(rows) and len(candidates) == len(d.candidates) > 0
    assert [(r["name"], float(r["value"]), r["unit"]) for r in baseline] == [(n, v, RC_UNITS[n]) for n, v in d.baseline.values.items()]
    assert [(r["model"], float(r["delta_aic"])) for r in candidates] == [(s.model, s.delta_aic) for s in d.candidates]
    ix.write_result(d, tmp_path / "d.json")
    assert json.loads((tmp_path / "d.json").read_text())["verdict"] == str(d.verdict)
    html = d._repr_html_()
    assert str(d.verdict) in html and d.candidates[0].effect in html


@pytest.mark.parametrize(
    "command",
    [
        ["fit", "--model", "R0 + R1 || C1"],
        ["sample", "--model", "R0 + R1 || C1"],
        ["diagnose", "--model", "R0 + R1 || C1"],
        ["refine", "--model", "R0 + R1 || C1"],
        ["gap", "missing2.csv", "missing3.csv", "--area", "1e-4"],
    ],
)
def test_unknown_out_extension_is_refused_before_any_work(command, tmp_path, capsys):
    out = tmp_path / "result.txt"
    # the data file does not exist: a refusal naming the extension shows nothing was read
    args = [command[0], str(tmp_path / "missing.csv"), *command[1:], "--out", str(out)]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "'.txt'" in err and ".csv, .json, .nc" in err and "Traceback" not in err
    assert err.count("\n") == 1 and not out.exists()


def test_cli_out_picks_the_format_by_extension(tmp_path, capsys):
    data = tmp_path / "rc.csv"
    ix.save(_rc_data(), data)
    assert main(["fit", str(data), "--model", "R0 + R1 || C1", "--json", "--out", str(tmp_path / "fit.csv")]) == 0
    printed = json.loads(capsys.readouterr().out)
    rows = _read_csv(tmp_path / "fit.csv")
    assert {r["name"]: float(r["value"]) for r in rows} == {n: p["value"] for n, p in printed["params"].items()}
    assert main(["fit", str(data), "--model", "R0 + R1 || C1", "--out", str(tmp_path / "fit.json")]) == 0
    assert json.loads((tmp_path / "fit.json").read_text())["params"] == printed["params"]


def test_single_fit_csv_carries_its_warnings_as_a_batch_csv_does(tmp_path, capsys):
    # synthetic R0 + R1 || C1 fitted with a CPE in place of C1: the truth is alpha = 1, the CPE's
    # upper bound, so the fit must warn "CPE1.alpha is at its upper bound 1" (known by construction)
    text, fn, truth, (lo, hi) = CASES["rc"]
    f = np.geomspace(lo, hi, 40)
    data = tmp_path / "rc.csv"
    ix.save(ix.make_spectrum(f, noisy(fn(f, truth), 0.005, np.random.default_rng(0))), data)
    assert main(["fit", str(data), "--model", "R0 + R1 || CPE1", "-q", "--json", "--out", str(tmp_path / "fit.csv")]) == 0
    printed = json.loads(capsys.readouterr().out)
    rows = _read_csv(tmp_path / "fit.csv")
    assert list(rows[0])[:14] == ["name", "value", "stderr", "unit", "fixed", "rms_rel", "chi2", "chi2_red", "aic", "bic", "converged", "at_bound", "undetermined", "warnings"]
    # the batch's column: the spectrum's warnings joined by "; ", the same on every row
    assert {r["warnings"] for r in rows} == {"; ".join(printed["warnings"])}
    assert rows[0]["warnings"].startswith("CPE1.alpha is at its upper bound 1")
    # a fit without warnings: the column is there, empty
    assert main(["fit", str(data), "--model", "R0 + R1 || C1", "-q", "--json", "--out", str(tmp_path / "clean.csv")]) == 0
    assert json.loads(capsys.readouterr().out)["warnings"] == [] and {r["warnings"] for r in _read_csv(tmp_path / "clean.csv")} == {""}


def test_init_from_a_fit_result(rc_fit):
    bigger = ix.parse("R0 + R1 || C1 + R2 || C2")
    table = ParameterTable.build(bigger, init=rc_fit)
    starts = dict(zip(table.names, table.values))
    assert {n: starts[n] for n in ("R0", "R1", "C1")} == rc_fit.values  # the names both circuits have
    assert np.isnan(starts["R2"]) and np.isnan(starts["C2"]) and not table.fixed.any()  # a start, never a fixed value
    refit = ix.fit("R0 + R1 || C1", _rc_data(), init=rc_fit, n_starts=1)
    assert refit.converged
    np.testing.assert_allclose([refit.values[n] for n in ("R1", "C1")], [rc_fit.values[n] for n in ("R1", "C1")], rtol=1e-3)
    with pytest.raises(ix.errors.ParameterError, match="FitResult"):
        ParameterTable.build(bigger, init=42)


def test_repr_html_shows_the_table_and_the_figure(rc_fit, rc_batch):
    html = rc_fit._repr_html_()
    assert all(f"<td>{n}</td>" in html for n in ("R0", "R1", "C1"))
    assert '<img alt="R0 + R1 || C1" src="data:image/png;base64,' in html
    noted = dataclasses.replace(rc_fit, warnings=("R1 < 0 & <b>bold</b>",))._repr_html_()
    assert "R1 &lt; 0 &amp; &lt;b&gt;bold&lt;/b&gt;" in noted and "<b>bold" not in noted
    assert "<td>R1</td>" in rc_batch._repr_html_()
    refinement = Refinement(steps=(RefinementStep(fit=rc_fit, added=None, effect=None, diagnosis=None),), verdict="adequate")
    assert "R0 + R1 || C1" in refinement._repr_html_()
    assert "<table>" in ix.kk_test(_rc_data())._repr_html_()
    assert "relaxation times" in ix.drt(_rc_data())._repr_html_()



def test_print_of_a_result_is_its_report_and_its_repr_stays_short(rc_fit, rc_batch):
    """``print(fit)`` is the first thing a user types (a walkthrough of 2026-12-04 found it
    printing the dataclass's fields): every result prints its report; ``repr`` stays one line."""
    data = _rc_data()
    refinement = Refinement(steps=(RefinementStep(fit=rc_fit, added=None, effect=None, diagnosis=None),), verdict="adequate")
    results = [rc_fit, rc_batch, refinement, ix.kk_test(data), ix.zhit(data), ix.drt(data)]
    for result in results:
        assert str(result) == result.report() and f"{result}" == result.report()
        assert repr(result).startswith(type(result).__name__ + "(") and "\n" not in repr(result)
    assert str(rc_fit).startswith("model      R0 + R1 || C1") and "parameter" in str(rc_fit)


def test_result_html_escapes_every_text():
    html = result_html("<script>x</script>", [{"na<me": "R&D", "value": 1.5}], lines=["a > b"])
    assert "<script>" not in html and "&lt;script&gt;" in html
    assert "<th>na&lt;me</th>" in html and "<td>R&amp;D</td>" in html and "<td>1.5</td>" in html and "a &gt; b" in html


@pytest.mark.parametrize("command", [["kk"], ["kk", "--method", "zhit"], ["drt"]])
def test_check_results_json_is_the_command_lines_json(command, tmp_path, capsys):
    """`write_result(..., ".json")` of a KK, Z-HIT or DRT result writes what `impedax kk|drt
    --json` prints (it wrote the text report as one JSON string)."""
    data = _rc_data()
    ix.save(data, tmp_path / "rc.nc")
    assert main([*command[:1], str(tmp_path / "rc.nc"), *command[1:], "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    result = ix.drt(data) if command == ["drt"] else ix.zhit(data) if "zhit" in command else ix.kk_test(data)
    ix.write_result(result, tmp_path / "r.json")
    written = json.loads((tmp_path / "r.json").read_text())
    # the command line names the file it read; the API's result has none (drt too since 2026-12-01)
    assert printed.pop("source") == str(tmp_path / "rc.nc")
    assert printed.pop("provenance")["command"] == f"impedax {command[0]}"  # (and what made it: docs/io.md, "Provenance")
    assert printed.pop("skipped_rows") == []  # (the reader's, which the file's data carry: added 2026-12-01)
    if command == ["drt"]:
        assert printed.pop("kk_note") is None  # (the command line's KK test of these sound data: added 2026-12-05)
        assert printed.pop("suggestion_withheld") is None  # (the command line's: a circuit is given; added 2026-12-06)
    assert isinstance(written, dict) and written == printed


def test_fit_residuals_are_model_minus_data_as_their_long_name_says(rc_fit):
    """`FitResult.residuals` = (Z_model − Z_data)/|Z_data| (docs/physics.md): the model evaluated
    here by hand, R0 + R1/(1 + jωR1C1), and the netCDF's long_name say the same sign."""
    v = rc_fit.values
    w = 2 * np.pi * rc_fit.frequency
    z_model = v["R0"] + v["R1"] / (1 + 1j * w * v["R1"] * v["C1"])
    z_data = rc_fit.z_data
    by_hand = (z_model - z_data) / np.abs(z_data)
    assert np.abs(by_hand).max() > 1e-3  # 1 % noise: the sign is measurable
    np.testing.assert_allclose(rc_fit.residuals, by_hand, atol=1e-9)
    assert rc_fit.to_xarray()["residual_rel"].attrs["long_name"] == "(Z_model - Z_data)/|Z_data|"


@pytest.mark.slow  # (about 7 s: a KK test, a batch of two, a Z-HIT test and a DRT)
def test_saved_kk_zhit_and_drt_results_are_named_as_results_by_inspect(tmp_path, capsys):
    """A KK test's, a Z-HIT test's and a DRT's .nc (one SYNTHETIC R0 + R1 ∥ C1 spectrum, and a
    batch of two for the KK test) carry ``impedax_kind`` as every other saved result does, so
    ``impedax inspect`` says what the file holds and how to read it in full, where until
    2026-12-06 it showed them as plain spectra (``result_kind`` absent from its --json).
    The spectrum inside is still the data tested: ix.load gives back their Z bit for bit."""
    from cli_run import run

    data = _rc_data(n=30)
    batch = ix.make_spectrum(data["frequency"].values, np.stack([data["Z"].values, 1.1 * data["Z"].values]), dims=("cell",), coords={"cell": ["a", "b"]})
    results = {
        "kk": (ix.kk_test(data), "Kramers-Kronig test (impedax kk)"),
        "kk_batch": (ix.kk_test_batch(batch), "Kramers-Kronig test (impedax kk)"),
        "zhit": (ix.zhit(data), "Z-HIT test (impedax kk --method zhit)"),
        "drt": (ix.drt(data), "distribution of relaxation times (impedax drt)"),
    }
    for name, (result, described) in results.items():
        path = tmp_path / f"{name}.nc"
        ix.write_result(result, path)
        kind = name.removesuffix("_batch")
        assert xr.open_dataset(path).attrs["impedax_kind"] == kind
        code, out, err = run(["inspect", path, "--json"], capsys)
        assert code == 0, err
        summary = json.loads(out)
        assert (summary["result_kind"], summary["result"], summary["read_with"]) == (kind, described, "impedax.io.read_netcdf(path)")
        code, out, err = run(["inspect", path], capsys)
        assert code == 0 and f"holding a saved {described} (its data shown here" in out.splitlines()[0]
        expected = (batch if name == "kk_batch" else data)["Z"].values
        np.testing.assert_array_equal(ix.load(path)["Z"].values, expected)
