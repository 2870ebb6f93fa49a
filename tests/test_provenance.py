"""Provenance of written results (docs/io.md, "Provenance"): every ``--out`` and ``--json`` of
fit, sample, gap, force, kk, drt and (since 2026-12-01) the spectra of simulate, inspect, stack and remaining records impedax's version, the command with its settings
(defaults included: the seed a run used without naming it), the data file and the UTC time; the
force CSV says its convention and parameters; the gap exports hold the EDL parameters and u's
draws. Each file is read back with the reader a user would take (json, csv, xarray)."""

import contextlib
import csv
import datetime
import io
import json

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main
from impedax.errors import ParameterError
from gap_files import saved_gap_files
from spectra import sirin_measurements

EPS0 = 8.8541878128e-12  # F/m, CODATA 2018
AREA = 130e-6  # m², the area of Sirin et al.


@pytest.fixture(scope="module")
def rc_file(tmp_path_factory):
    """SYNTHETIC R0 + R1 || C1 (20 Ω, 1 kΩ, 1 µF) with 0.5 % complex noise, seed 3, as CSV."""
    rng = np.random.default_rng(3)
    f = np.logspace(0, 5, 30)
    z = 20 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6)
    z = z * (1 + 0.005 * rng.standard_normal(f.size) + 0.005j * rng.standard_normal(f.size))
    path = tmp_path_factory.mktemp("rc") / "rc.csv"
    np.savetxt(path, np.column_stack([f, z.real, z.imag]), delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm", comments="")
    return path


def _recent(stamp: str) -> bool:
    """``stamp`` is ISO 8601 UTC ending in Z, within the last 10 minutes."""
    written = datetime.datetime.fromisoformat(stamp.replace("Z", "+00:00"))
    return stamp.endswith("Z") and abs((datetime.datetime.now(datetime.timezone.utc) - written).total_seconds()) < 600


def test_fit_json_csv_nc_record_version_settings_and_source(rc_file, tmp_path, capsys):
    """`impedax fit --out` in all three formats and --json: the same provenance, the model and
    the weighting (the default, unnamed), the --fix as typed, and the data file."""
    model = "R0 + R1 || C1"
    outs = {ext: tmp_path / f"fit{ext}" for ext in (".json", ".csv", ".nc")}
    for path in outs.values():
        assert main(["fit", str(rc_file), "--model", model, "--fix", "R0=20", "--out", str(path)]) == 0
    capsys.readouterr()
    for record in (json.loads(outs[".json"].read_text())["provenance"],
                   json.loads(xr.open_dataset(outs[".nc"]).attrs["provenance"])):
        assert record["impedax_version"] == ix.__version__ and _recent(record["written_utc"])
        assert record["command"] == "impedax fit" and record["source"] == str(rc_file)
        assert record["data_files"] == [str(rc_file.resolve())]
        settings = record["settings"]
        assert settings["model"] == model and settings["weighting"] == "modulus" and settings["fix"] == ["R0=20"] and settings["fmin"] is None
        # every setting is an option of the command (a parser's own flag, circuit_model, was listed until 2026-12-03)
        from impedax.cli import _subparser, build_parser

        options = {a.dest for a in _subparser(build_parser("fit"), "fit")._actions if a.option_strings}
        assert set(settings) <= options, set(settings) - options
    with xr.open_dataset(outs[".nc"]) as ds:
        assert ds.attrs["impedax_version"] == ix.__version__
        back = ix.FitResult.from_xarray(ds.load())  # (the attributes added do not stop it reading back)
    assert back.values["R0"] == 20.0
    rows = list(csv.DictReader(outs[".csv"].open(newline="")))
    assert [r["name"] for r in rows] == ["R0", "R1", "C1"]  # (the table's own columns first, as before)
    assert list(rows[0])[:5] == ["name", "value", "stderr", "unit", "fixed"]
    assert {r["impedax_version"] for r in rows} == {ix.__version__}
    assert {(r["setting_model"], r["setting_weighting"], r["setting_fix"], r["source"]) for r in rows} == {(model, "modulus", "R0=20", str(rc_file))}
    # numpy reads the table by name as before (text columns alongside)
    table = np.genfromtxt(outs[".csv"], delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert float(table["value"][0]) == 20.0


def test_fit_json_stdout_has_the_provenance(rc_file, capsys):
    assert main(["fit", str(rc_file), "--model", "R0 + R1 || C1", "--weighting", "proportional", "--fmin", "2", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)["provenance"]
    assert record["impedax_version"] == ix.__version__
    assert record["settings"]["weighting"] == "proportional" and record["settings"]["fmin"] == 2.0


def test_python_write_result_records_the_version_without_changing_the_result(rc_file, tmp_path):
    """From Python: the netCDF names the version (and ``source``) by default, and reads back
    without it (about the file, not the fit); the result's own dataset is not changed by writing
    it; JSON and CSV stay the summary and the table unless a record is passed, then hold it."""
    from impedax.io.provenance import provenance

    result = ix.fit("R0 + R1 || C1", ix.load(rc_file))
    ix.write_result(result, tmp_path / "r.nc", source="lab book p. 12")
    with xr.open_dataset(tmp_path / "r.nc") as ds:
        record = json.loads(ds.attrs["provenance"])
        back = ix.FitResult.from_xarray(ds.load())
    assert record["impedax_version"] == ix.__version__ and record["command"] is None and record["source"] == "lab book p. 12"
    assert "provenance" not in result.to_xarray().attrs and "written_utc" not in back.to_xarray().attrs
    ix.write_result(result, tmp_path / "r.csv")
    assert list(next(csv.DictReader((tmp_path / "r.csv").open()))) == ["name", "value", "stderr", "unit", "fixed", "rms_rel", "chi2", "chi2_red", "aic", "bic", "converged", "at_bound", "undetermined", "warnings", "weighting", "misses_structure"]  # (weighting added 2026-12-06) (misses_structure added 2026-12-06)
    assert "provenance" not in json.loads((ix.write_result(result, tmp_path / "r.json") or tmp_path / "r.json").read_text())
    given = provenance(settings={"seed": 11, "model": "R0 + R1 || C1"}, data_files=[str(rc_file)])
    ix.write_result(result, tmp_path / "p.json", provenance=given)
    assert json.loads((tmp_path / "p.json").read_text())["provenance"] == given
    ix.write_result(result, tmp_path / "p.csv", provenance=given)
    assert {r["setting_seed"] for r in csv.DictReader((tmp_path / "p.csv").open())} == {"11"}


def test_python_write_result_records_the_loaded_files_source_by_default(rc_file, tmp_path):
    """No ``source=``: the netCDF attribute, the provenance record and the JSON name the CSV
    that `ix.load` read (its ``attrs["source"]``), for a fit and for a comparison of fits of it;
    data built in memory record none."""
    data = ix.load(rc_file)
    fit = ix.fit("R0 + R1 || C1", data, n_starts=1)
    comparison = ix.compare([fit, ix.fit("R0 + R1 || CPE1", data, n_starts=1)])
    for name, result in (("fit", fit), ("comparison", comparison)):
        ix.write_result(result, tmp_path / f"{name}.nc")
        with xr.open_dataset(tmp_path / f"{name}.nc") as ds:
            assert ds.attrs["source"] == str(rc_file), name
            assert json.loads(ds.attrs["provenance"])["source"] == str(rc_file), name
    ix.write_result(fit, tmp_path / "fit.json")
    assert json.loads((tmp_path / "fit.json").read_text())["source"] == str(rc_file)
    in_memory = ix.fit("R0 + R1 || C1", (data["frequency"].values, data["Z"].values), n_starts=1)
    ix.write_result(in_memory, tmp_path / "memory.nc")
    with xr.open_dataset(tmp_path / "memory.nc") as ds:
        assert "source" not in ds.attrs and json.loads(ds.attrs["provenance"])["source"] is None


def test_sample_records_the_default_seed_and_the_steps_run(rc_file, tmp_path, capsys):
    """A short chain (SYNTHETIC data, 60 steps): the seed not given is the default 0, the one
    given is recorded as given, and the steps and walkers the run used."""
    for seed, extra in ((None, []), (7, ["--seed", "7"])):
        path = tmp_path / f"post{seed}.nc"
        assert main(["sample", str(rc_file), "--model", "R0 + R1 || C1", "--steps", "60", "--walkers", "16", "--quiet", *extra, "--out", str(path)]) == 0
        with xr.open_dataset(path) as ds:
            record = json.loads(ds.attrs["provenance"])
        assert record["impedax_version"] == ix.__version__
        assert record["settings"]["seed"] == (0 if seed is None else seed)
        assert record["settings"]["steps"] == 60 and record["settings"]["steps_used"] == 60 and record["settings"]["walkers_used"] == 16
    capsys.readouterr()


def _force_csv(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def test_force_csv_says_its_convention_and_drive(tmp_path, capsys):
    """`force --convention peak` and the default write distinguishable CSVs: the convention and
    the drive v_a on every row; the time average is half the peak for Vezzoli (exactly 2×, the
    --convention help) and the numbers read back as before from the first two columns."""
    peak, mean = tmp_path / "peak.csv", tmp_path / "mean.csv"
    assert main(["force", "vezzoli", "--points", "4", "--convention", "peak", "--param", "v_m=100", "--out", str(peak)]) == 0
    assert main(["force", "vezzoli", "--points", "4", "--param", "v_m=100", "--out", str(mean)]) == 0
    p, m = _force_csv(peak), _force_csv(mean)
    assert {r["convention"] for r in p} == {"peak"} and {r["convention"] for r in m} == {"time-average"}
    assert {r["param_v_m"] for r in p} == {"100"} and {r["impedax_version"] for r in m} == {ix.__version__}
    np.testing.assert_allclose([float(r["force_n"]) for r in p], [2 * float(r["force_n"]) for r in m], rtol=1e-12)
    table = np.loadtxt(peak, delimiter=",", skiprows=1, usecols=(0, 1))
    assert table.shape == (4, 2)
    assert main(["force", "vezzoli", "--points", "4", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)["provenance"]
    assert record["settings"]["convention"] == "time-average" and record["settings"]["points_used"] == 4


def test_kk_and_drt_json_record_their_settings(rc_file, tmp_path, capsys):
    assert main(["kk", str(rc_file), "--json"]) == 0
    record = json.loads(capsys.readouterr().out)["provenance"]
    assert record["command"] == "impedax kk" and record["settings"]["c"] == 0.85 and record["impedax_version"] == ix.__version__
    out = tmp_path / "drt.nc"
    assert main(["drt", str(rc_file), "--lam-method", "lcurve", "--out", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        record = json.loads(ds.attrs["provenance"])
    assert record["command"] == "impedax drt" and record["settings"]["lam_method"] == "lcurve"
    capsys.readouterr()


@pytest.fixture(scope="module")
def gap_outputs(tmp_path_factory):
    """`impedax gap --pooled --steps 40 --seed 5` on SYNTHETIC Sirin-style trials (6 per file,
    seed 11): --json with --out .csv in one run, --out .nc in another (the pooled runs are the
    fastest documented; two take about 5 s)."""
    folder = tmp_path_factory.mktemp("gap")
    f, *spectra = sirin_measurements(np.random.default_rng(11), 6)
    paths = saved_gap_files(folder, [ix.make_spectrum(f, z, dims=("trial",)) for z in spectra])
    outs = {ext: folder / f"g{ext}" for ext in (".json", ".csv", ".nc")}
    common = ["gap", *paths, "--area", "130e-6", "--pooled", "--steps", "40", "--seed", "5", "--quiet"]
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        assert main([*common, "--json", "--out", str(outs[".csv"])]) == 0
    outs[".json"].write_text(printed.getvalue())
    assert main([*common, "--out", str(outs[".nc"])]) == 0
    return paths, outs


def test_gap_outputs_record_settings_and_the_edl_parameters(gap_outputs):
    paths, outs = gap_outputs
    summary = json.loads(outs[".json"].read_text())
    record = summary["provenance"]
    assert record["impedax_version"] == ix.__version__ and record["settings"]["seed"] == 5 and record["settings"]["steps"] == 40
    assert record["settings"]["eps_gap_used"] == pytest.approx(1.00059) and record["settings"]["cutoff_hz_used"] == 30.0
    assert record["source"] == dict(zip(("total", "skin", "touchscreen"), paths))
    assert summary["settings"]["seed"] == 5 and summary["settings"]["steps"] == 40
    params = summary["edl_parameters"]
    assert {"R_EP", "CPE_EP.Q", "CPE_EP.alpha", "C_gap", "u"} <= set(params)
    for name, q in params.items():
        assert q["q05"] <= q["value"] <= q["q95"], name
    # u = ε0 ε_air A / C_gap holds draw by draw, so for the medians too (SYNTHETIC C_gap 413 pF)
    assert params["u"]["value"] == pytest.approx(EPS0 * 1.00059 * AREA / params["C_gap"]["value"], rel=1e-9)
    assert params["u"]["value"] * 1e6 == pytest.approx(summary["gap_um"]["value"], rel=1e-12)
    assert params["R_EP"]["unit"] == "Ohm" and params["R_EP"]["fit_stderr"] > 0 and params["u"]["fit_value"] is None

    rows = list(csv.DictReader(outs[".csv"].open(newline="")))
    assert [r["method"] for r in rows[:2]] == ["bayes", "paper"]
    by_name = {r["parameter"]: r for r in rows if r["method"] == "bayes_parameter"}
    assert set(by_name) == set(params)
    assert float(by_name["R_EP"]["value"]) == params["R_EP"]["value"] and by_name["CPE_EP.Q"]["unit"] == params["CPE_EP.Q"]["unit"]
    assert {r["setting_seed"] for r in rows} == {"5"} and {r["written_utc"] for r in rows} == {record["written_utc"]}  # (one record for --json and --out)

    with xr.open_dataset(outs[".nc"]) as ds:
        assert json.loads(ds.attrs["provenance"])["settings"]["seed"] == 5 and ds.attrs["setting_seed"] == 5
        u = ds["u_draws"].values
        assert ds["u_draws"].attrs["units"] == "m" and 0 < u.size <= 4000
        # the median of the saved draws is the u the file reports, and another run of the same seed's (the same draws)
        assert np.median(u) == pytest.approx(ds.attrs["gap_um_value"] * 1e-6, rel=0.02)
        assert ds.attrs["gap_um_value"] == pytest.approx(summary["gap_um"]["value"], rel=1e-12)
        names = list(ds["parameter"].values)
        assert "R_EP" in names and ds["parameter_unit"].values[names.index("u")] == "m"


def test_gap_draws_accept_the_property_names_and_say_which_exist():
    """`GapAnalysis.draws("gap")` (the property's name) is u; an unknown name is a ParameterError
    listing the names, not a KeyError."""
    f, *spectra = sirin_measurements(np.random.default_rng(11), 6)
    total, skin, ts = (ix.make_spectrum(f, z, dims=("trial",)) for z in spectra)
    g = ix.models.gap.gap_analysis(total, skin, ts, area=AREA, method="pooled", steps=40, progress=False)
    np.testing.assert_array_equal(g.draws("gap"), g.draws("u"))
    np.testing.assert_allclose(g.draws("c_gap"), EPS0 * 1.00059 * AREA / g.draws("u"), rtol=1e-9)
    with pytest.raises(ParameterError, match=r"no draws named 'thickness'.*gap, u, c_gap, C_gap.*R_EP"):
        g.draws("thickness")
    assert g.u_draws(max_draws=100).size <= 100


def test_compare_records_its_provenance(tmp_path, capsys):
    """compare's --json carries the same record as the other commands: version, command, the
    models as read, the default weighting; how the figure looks (--dpi, --title) is no setting."""
    import impedax
    from impedax.cli import main

    data = tmp_path / "spectrum.csv"
    f = np.logspace(-1, 5, 30)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6)  # SYNTHETIC R0 + R1 || C1, noise-free
    np.savetxt(data, np.column_stack([f, z.real, z.imag]), delimiter=",", header="frequency,z_real,z_imag", comments="")
    assert main(["compare", str(data), "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)["provenance"]
    assert record["impedax_version"] == impedax.__version__ and record["command"] == "impedax compare"
    assert record["settings"]["model"] == ["R0 + R1 || C1", "R0 + R1 || CPE1"] and record["settings"]["weighting"] == "modulus"
    assert "dpi" not in record["settings"] and "title" not in record["settings"]


def test_a_list_setting_reads_back_from_the_csv(tmp_path):
    """Circuit texts hold spaces: a list of them in a CSV cell is joined by '; ' and splits back
    whole; --init repeated (a list of lists) is one flat list of assignments."""
    from impedax.io.provenance import provenance, provenance_columns

    models = ["R0 + R1 || C1", "R0 + R1 || CPE1"]
    columns = provenance_columns(provenance(settings={"model": models, "init": [["R0=1", "R1=2"], ["C1=3u"]], "seed": 0}))
    assert columns["setting_model"].split("; ") == models and "," not in columns["setting_model"]
    assert columns["setting_init"].split("; ") == ["R0=1", "R1=2", "C1=3u"] and columns["setting_seed"] == 0


# --- the commands that write spectra (since 2026-12-01): simulate, inspect, stack, remaining ----------


def _nc_record(path):
    with xr.open_dataset(path) as ds:
        return json.loads(ds.attrs["provenance"])


def test_simulate_out_records_the_model_and_its_values(tmp_path, capsys):
    """`impedax simulate --out` (CSV and netCDF): the command, the model, the values used
    (defaults included) and no data file; the CSV's spectrum is still read back whole: R0 +
    R1/(1 + jωR1C1) by hand (10 Ω, 100 Ω, 1 µF)."""
    args = ["simulate", "R0 + R1 || C1", "--param", "R0=10", "R1=100", "C1=1u", "--points", "7"]
    for ext in (".csv", ".nc"):
        assert main([*args, "--out", str(tmp_path / f"s{ext}")]) == 0
    capsys.readouterr()
    rows = list(csv.DictReader((tmp_path / "s.csv").open(newline="")))
    assert list(rows[0])[:3] == ["frequency_hz", "z_real_ohm", "z_imag_ohm"]  # (the spectrum's own columns first)
    assert {(r["command"], r["setting_model"], r["setting_points_used"], r["data_files"], r["impedax_version"]) for r in rows} == {("impedax simulate", "R0 + R1 || C1", "7", "", ix.__version__)}
    back = ix.load(tmp_path / "s.csv")
    f = np.logspace(0, 6, 7)
    np.testing.assert_allclose(back["Z"].values, 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6), rtol=1e-12)
    record = _nc_record(tmp_path / "s.nc")
    assert record["command"] == "impedax simulate" and record["data_files"] == [] and _recent(record["written_utc"])
    assert record["settings"]["params_used"] == {"R0": 10.0, "R1": 100.0, "C1": 1e-6}


def test_simulate_help_names_every_column_its_out_file_writes(tmp_path, capsys):
    """`impedax simulate --help` named three CSV columns while --out wrote fifteen (a
    walkthrough, 2026-12-05): it now names the three of standard output and each provenance
    column of --out, read here from a file it wrote."""
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert main(["simulate", "R0 + R1 || C1", "--points", "3", "--out", str(tmp_path / "s.csv")]) == 0
    capsys.readouterr()
    columns = next(csv.reader((tmp_path / "s.csv").open(newline="")))
    assert "three columns on standard output" in text
    for name in columns:
        assert (name in text) or (name.startswith("setting_") and "setting_*" in text), name
    assert main(["simulate", "R0 + R1 || C1", "--points", "3"]) == 0
    assert next(csv.reader(io.StringIO(capsys.readouterr().out))) == ["frequency_hz", "z_real_ohm", "z_imag_ohm"]


def test_inspect_json_and_out_record_the_file(rc_file, tmp_path, capsys):
    """`impedax inspect --json` and its --out (netCDF, CSV) name the command and the file read."""
    assert main(["inspect", str(rc_file), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["file"] == str(rc_file)  # (the keys it had stay)
    record = summary["provenance"]
    assert record["command"] == "impedax inspect" and record["data_files"] == [str(rc_file.resolve())] and record["source"] == str(rc_file)
    for ext in (".nc", ".csv"):
        assert main(["inspect", str(rc_file), "--out", str(tmp_path / f"c{ext}")]) == 0
    capsys.readouterr()
    assert _nc_record(tmp_path / "c.nc")["data_files"] == [str(rc_file.resolve())]
    assert {r["command"] for r in csv.DictReader((tmp_path / "c.csv").open(newline=""))} == {"impedax inspect"}


def test_stack_out_records_every_file(rc_file, tmp_path, capsys):
    """`impedax stack --out`: the command, --dim and --coords, and every file stacked, in order."""
    second = tmp_path / "second.csv"
    second.write_text(rc_file.read_text())
    out = tmp_path / "days.nc"
    assert main(["stack", str(rc_file), str(second), "--dim", "day", "--coords", "1", "2", "--out", str(out)]) == 0
    capsys.readouterr()
    record = _nc_record(out)
    assert record["command"] == "impedax stack" and record["settings"] == {"dim": "day", "coords": ["1", "2"], "common_frequencies": False}
    assert record["data_files"] == [str(rc_file.resolve()), str(second.resolve())]
    assert ix.load(out).sizes["day"] == 2  # (the stack reads back as before)


def test_remaining_out_records_the_three_files(tmp_path, capsys):
    """`impedax remaining --out` (netCDF and CSV): the three inputs by role, as `gap` records them.
    SYNTHETIC parts: 3 trials × 6 frequencies of constant passive spectra with 1 % noise, seed 4."""
    rng = np.random.default_rng(4)
    f = np.geomspace(10.0, 1e5, 6)
    parts = [ix.make_spectrum(f, level * (1 - 1j) * (1 + 0.01 * rng.standard_normal((3, f.size))), dims=("trial",))
             for level in (1e6, 1e4, 1e3)]
    paths = saved_gap_files(tmp_path, parts)
    for ext in (".nc", ".csv"):
        assert main(["remaining", *paths, "--out", str(tmp_path / f"rem{ext}")]) == 0
    capsys.readouterr()
    record = _nc_record(tmp_path / "rem.nc")
    assert record["command"] == "impedax remaining" and record["source"] == dict(zip(("total", "skin", "touchscreen"), paths))
    assert record["data_files"] == [str((tmp_path / n).resolve()) for n in ("total.nc", "skin.nc", "ts.nc")]
    assert record["settings"]["trials"] is False
    rows = list(csv.DictReader((tmp_path / "rem.csv").open(newline="")))
    assert len(rows) == f.size and {r["command"] for r in rows} == {"impedax remaining"}
    assert {r["data_files"] for r in rows} == {"; ".join(record["data_files"])}
