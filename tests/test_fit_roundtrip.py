"""Fits read back from their netCDF files: `FitResult.from_xarray` and
`BatchFitResult.from_xarray` give back what was written (REAL files of impedance.py and AutoEIS),
a file of another kind or a damaged one is named, and a file written before the kind and the
counts were stored still reads."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.errors import DataError

REAL = Path(__file__).parent / "fixtures" / "real"
CYCLES = Path(__file__).resolve().parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc"


@pytest.fixture(scope="module")
def single():
    data = ix.load(REAL / "exampleDataBioLogic.mpt")
    return data, ix.fit("R0 + R1 || CPE1 + Wo1", data)


@pytest.fixture(scope="module")
def batch():
    return ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + W1", ix.load(CYCLES))


@pytest.mark.parametrize("how", ["in memory", "ix.load", "xr.open_dataset"])
def test_a_fit_reads_back_whole(single, how, tmp_path):
    data, fit = single
    path = tmp_path / "fit.nc"
    ix.write_result(fit, path)
    ds = fit.to_xarray() if how == "in memory" else ix.load(path) if how == "ix.load" else xr.open_dataset(path)
    back = ix.FitResult.from_xarray(ds)
    assert back.model == fit.model and back.values == fit.values and back.fixed == fit.fixed
    assert back.at_bound == fit.at_bound and fit.at_bound  # (this fit has one: Wo1's R at its bound)
    assert back.warnings == fit.warnings and fit.warnings
    np.testing.assert_array_equal(back.covariance, fit.covariance)
    np.testing.assert_array_equal(np.isnan(back.correlation), np.isnan(fit.correlation))
    for name in fit.values:
        assert back.stderr[name] == fit.stderr[name] or (np.isnan(back.stderr[name]) and np.isnan(fit.stderr[name]))
    assert (back.chi2, back.converged, back.n_evaluations, back.n_starts, back.weighting) == (fit.chi2, fit.converged, fit.n_evaluations, fit.n_starts, fit.weighting)
    f = np.geomspace(1e-2, 1e5, 31)
    np.testing.assert_array_equal(back.predict(f), fit.predict(f))
    assert back.rms_rel == fit.rms_rel and back.report() == fit.report()
    assert ix.fit("R0 + R1 || CPE1 + Wo1", data, init=back).rms_rel == pytest.approx(fit.rms_rel, rel=1e-6)


@pytest.mark.parametrize("how", ["in memory", "ix.load", "xr.open_dataset"])
def test_a_batch_reads_back_whole(batch, how, tmp_path):
    path = tmp_path / "batch.nc"
    ix.write_result(batch, path)
    ds = batch.to_xarray() if how == "in memory" else ix.load(path) if how == "ix.load" else xr.open_dataset(path)
    back = ix.BatchFitResult.from_xarray(ds)
    # the file also names where the data came from (`write_result` records the batch's source,
    # since 2026-12-01; ix.load keeps it as saved_from and names the file it read as source)
    file_attrs = {"source", "saved_from"}
    if how != "in memory":
        assert batch.source and (ds.attrs.get("saved_from") if how == "ix.load" else ds.attrs["source"]) == batch.source
    assert back.dataset.drop_attrs().identical(batch.dataset.drop_attrs())
    assert {k: v for k, v in back.dataset.attrs.items() if k not in file_attrs} == batch.dataset.attrs
    assert back.warnings == batch.warnings and any(batch.warnings.values())
    assert back.summary() == batch.summary() and back.model == batch.model
    label = int(batch.dataset["cycle"].values[1])
    one, again = back.fit_of(cycle=label), batch.fit_of(cycle=label)
    assert one.values == pytest.approx(again.values, rel=1e-9)


def test_a_file_of_another_kind_or_damaged_is_named(single, batch, tmp_path):
    _, fit = single
    with pytest.raises(DataError, match="a saved batch of least-squares fits, not a least-squares fit: read it with BatchFitResult.from_xarray"):
        ix.FitResult.from_xarray(batch.to_xarray())
    with pytest.raises(DataError, match="a saved least-squares fit, not a single-spectrum posterior: read it with FitResult.from_xarray"):
        ix.Posterior.from_xarray(fit.to_xarray())
    with pytest.raises(DataError, match="not a saved impedax batch of least-squares fits"):
        ix.BatchFitResult.from_xarray(ix.load(CYCLES))  # (a spectrum file)
    path = tmp_path / "cut.nc"
    ix.write_result(fit, path)
    cut = xr.open_dataset(path).drop_vars("covariance")
    with pytest.raises(DataError, match=r"incomplete saved least-squares fit: missing variable\(s\) 'covariance'"):
        ix.FitResult.from_xarray(cut)


# a result's .csv or .json loaded as a spectrum (a walkthrough, 2026-12-02: "not a recognised
# spectrum file … no frequency column"): named, with the call that reads its .nc back; following
# the message's own call gives the fit back (the oracle: the values written)
@pytest.mark.parametrize("suffix", [".csv", ".json"])
@pytest.mark.parametrize("kind", ["fit", "batch"])
def test_a_results_csv_or_json_loaded_as_data_names_the_nc_that_reads_back(single, batch, kind, suffix, tmp_path):
    result = single[1] if kind == "fit" else batch
    what, reader = ("a least-squares fit", "ix.FitResult") if kind == "fit" else ("a batch of least-squares fits", "ix.BatchFitResult")
    summary = tmp_path / f"out{suffix}"
    ix.write_result(result, summary)
    with pytest.raises(DataError) as e:
        ix.load(summary)
    text = str(e.value)
    assert f"this file is the {suffix[1:].upper()} summary of {what} (write_result, impedax fit --out), not a spectrum" in text
    assert f"ix.write_result(result, 'fit.nc') (impedax fit --out fit.nc), then {reader}.from_xarray(ix.load('fit.nc'))" in text
    assert "no frequency column" not in text
    ix.write_result(result, tmp_path / "out.nc")  # the .nc beside it: named by its path, and the call named reads it
    with pytest.raises(DataError) as e:
        ix.load(summary)
    call = str(e.value).split("the form that reads back is the .nc beside it: ")[1]
    assert call == f"{reader}.from_xarray(ix.load({str(tmp_path / 'out.nc')!r}))"
    back = eval(call, {"ix": ix})
    assert (back.values == result.values) if kind == "fit" else back.dataset["value"].equals(result.dataset["value"])


@pytest.mark.parametrize("name, text, what", [
    # the columns and keys docs/io.md ("Exporting results") gives each result's file
    ("post.csv", "name,median,q05,q16,q84,q95,unit,autocorr,ess\nR0,1,0.9,0.95,1.05,1.1,Ohm,10,400\n", "a posterior"),
    ("diag.csv", "section,name,value,stderr,unit,fixed,effect,model,rms_rel,delta_aic\nbaseline,R0,1,0.1,Ohm,false,,,,\n", "a diagnosis"),
    ("ref.json", '{"steps": [], "final_model": "R0", "verdict": "adequate", "final_rms_rel": 0.01}', "a refinement"),
    ("diag.json", '{"model": "R0", "baseline": {}, "kk": {}}', "a diagnosis"),
    ("post.json", '{"model": "R0", "params": {}, "acceptance": 0.3}', "a posterior"),
])
def test_other_results_summaries_are_named_too(tmp_path, name, text, what):
    (tmp_path / name).write_text(text)
    with pytest.raises(DataError, match=f"summary of {what} .*not a spectrum.*the form that reads back is a .nc"):
        ix.load(tmp_path / name)


def test_a_table_that_is_no_result_keeps_its_message(tmp_path):
    (tmp_path / "t.csv").write_text("name,value\nR0,1\n")
    with pytest.raises(DataError, match="no frequency column"):
        ix.load(tmp_path / "t.csv")


def test_the_command_lines_csv_loaded_as_data_is_named(tmp_path):
    out = tmp_path / "fit.csv"
    run = subprocess.run([sys.executable, "-m", "impedax", "fit", str(REAL / "exampleDataGamry.DTA"), "--model", "R0-p(R1,CPE1)", "--out", str(out), "--quiet"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    with pytest.raises(DataError, match=r"summary of a least-squares fit .*ix.FitResult.from_xarray\(ix.load\('fit.nc'\)\)"):
        ix.load(out)


def test_a_fit_written_before_the_kind_was_stored_reads(single, batch):
    _, fit = single
    old = fit.to_xarray()
    old.attrs = {k: v for k, v in old.attrs.items() if k not in ("impedax_kind", "n_evaluations", "n_starts", "elapsed_s")}
    back = ix.FitResult.from_xarray(old)
    assert back.values == fit.values and back.n_evaluations == 0 and back.n_starts == 1
    old_batch = batch.dataset  # (as to_xarray returned it before: no kind, no warnings)
    back_batch = ix.BatchFitResult.from_xarray(old_batch)
    assert back_batch.dataset.identical(batch.dataset) and not any(back_batch.warnings.values())


def test_the_command_line_file_reads_back(tmp_path):
    out = tmp_path / "fit.nc"
    run = subprocess.run([sys.executable, "-m", "impedax", "fit", str(REAL / "exampleData.csv"), "--model", "R0 + R1 || CPE1 + Wo1", "--out", str(out)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    back = ix.FitResult.from_xarray(ix.load(out))
    assert back.model == "R0 + R1 || CPE1 + Wo1" and 0 < back.rms_rel < 0.2 and back.n_evaluations > 0


def test_a_global_fit_reads_back_as_one(tmp_path):
    # a joint fit's file had been stamped a plain batch and read back without its sharing
    data = ix.load(CYCLES)
    joint = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + W1", data, shared=["R0"], over=["cycle"])
    path = tmp_path / "joint.nc"
    ix.write_result(joint, path)
    for ds in (joint.to_xarray(), ix.load(path), xr.open_dataset(path)):
        back = ix.SharedFitResult.from_xarray(ds)
        assert (back.shared, back.over) == (("R0",), ("cycle",))
        assert back.summary() == joint.summary() and back.warnings == joint.warnings
    with pytest.raises(DataError, match="a saved joint \\(shared-parameter\\) fit, not a batch of least-squares fits: read it with SharedFitResult.from_xarray"):
        ix.BatchFitResult.from_xarray(joint.to_xarray())
    old = ix.SharedFitResult.from_xarray(joint.dataset)  # (written before the kind was stored)
    assert (old.shared, old.over) == (("R0",), ("cycle",))
    kinds = joint.summary()["warning_kinds"]  # (a joint fit's own notes name no spectrum: their key is the scope)
    assert all("=" in p for k in kinds for p in k["spectra"])
    assert all(k["n_spectra"] == len(k["spectra"]) for k in kinds)


def test_results_of_other_kinds_without_a_kind_are_not_taken_for_fits(batch):
    data = ix.load(CYCLES)
    with pytest.raises(DataError, match="a saved Kramers-Kronig test \\(impedax kk\\), not a batch of least-squares fits"):
        ix.BatchFitResult.from_xarray(ix.kk_test_batch(data).to_xarray())
    with pytest.raises(DataError, match="not a saved impedax least-squares fit"):
        ix.FitResult.from_xarray(batch.dataset)  # (a batch written before the kind was stored)


@pytest.mark.parametrize("how", ["ix.load", "xr.open_dataset", "read_netcdf"])
def test_a_saved_fit_read_back_names_its_datas_file(how, tmp_path):
    """A fit read back from its netCDF has the ``source`` it was written with (its data's file;
    lost before 2026-12-01), for a single fit and a batch, however the file is opened; data built
    in memory name none. SYNTHETIC R0 + R1 || C1 (20 Ω, 1 kΩ, 1 µF), 1 % complex noise, seed 5."""
    rng = np.random.default_rng(5)
    f = np.logspace(0, 5, 25)
    z = (20 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6)) * (1 + 0.01 * rng.standard_normal(f.size) + 0.01j * rng.standard_normal(f.size))
    data_file = tmp_path / "rc.csv"
    np.savetxt(data_file, np.column_stack([f, z.real, z.imag]), delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm", comments="")
    stack_file = tmp_path / "two.nc"
    ix.save(ix.make_spectrum(f, np.stack([z, z * 1.01]), dims=("cell",)), stack_file)
    opened = {"ix.load": ix.load, "xr.open_dataset": xr.open_dataset, "read_netcdf": ix.io.read_netcdf}[how]
    for name, fitted, kind in (("fit", ix.fit("R0 + R1 || C1", ix.load(data_file), n_starts=1), ix.FitResult),
                               ("batch", ix.fit("R0 + R1 || C1", ix.load(stack_file), n_starts=1), ix.BatchFitResult),
                               ("memory", ix.fit("R0 + R1 || C1", (f, z), n_starts=1), ix.FitResult)):
        ix.write_result(fitted, tmp_path / f"{name}.nc")
        back = kind.from_xarray(opened(tmp_path / f"{name}.nc"))
        expected = {"fit": str(data_file), "batch": str(stack_file), "memory": None}[name]
        assert fitted.source == expected and back.source == expected, name
