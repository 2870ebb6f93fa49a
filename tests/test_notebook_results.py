"""The Python API as a notebook uses it on REAL data (impedance.py's BioLogic example, MIT):
what a result's ``to_xarray`` and its written ``.nc`` hold, and what reading one back says."""

from __future__ import annotations

import copy
import dataclasses
import pickle
import re

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.errors import DataError

REAL = "tests/fixtures/real/exampleDataBioLogic.mpt"


@pytest.fixture(scope="module")
def data():
    return ix.load(REAL)


def test_a_comparison_nc_given_as_data_is_named(data, tmp_path):
    """``ix.write_result(ix.compare(...), "c.nc")`` then ``ix.load("c.nc")``: the file holds the
    models' table, not a spectrum; it was told "dataset has no variable 'Z'" and the table's
    column names, as if the file were a damaged spectrum."""
    comparison = ix.compare([ix.fit("R0 + R1 || C1", data), ix.fit("R0 + R1 || CPE1", data)])
    out = tmp_path / "c.nc"
    ix.write_result(comparison, out)
    with pytest.raises(DataError, match=re.escape("holds a comparison of models on one spectrum (impedax compare), not a spectrum; read it with impedax.io.read_netcdf(path)")):
        ix.load(out)
    back = ix.io.read_netcdf(out)
    assert list(back["model"].values) == ["R0 + R1 || C1", "R0 + R1 || CPE1"]
    np.testing.assert_allclose(back["aic"].values, [row["aic"] for row in comparison.rows])


def _report_strays(report: str) -> list[float]:
    """The stray points the report names, in Hz, read off its words ("5.34 Hz, 56.2 Hz, 270 Hz")."""
    line = next(l for l in report.splitlines() if l.startswith("left out of the chain's fit as stray"))
    scale = {"m": 1e-3, "": 1.0, "k": 1e3}
    return [float(v) * scale[p] for v, p in re.findall(r"([\d.]+) (m|k|)Hz", line.split(":", 1)[1].split(";")[0])]


def test_a_kk_tests_nc_holds_the_stray_points_its_report_names(data, tmp_path):
    """The REAL BioLogic file's report says the chain was fitted without 5.34, 56.2 and 270 Hz;
    ``to_xarray`` (and so ``impedax kk --out kk.nc``) held the chain (``Z_kk``, ``resistance``)
    with no word of which points it was fitted without."""
    result = ix.kk_test(data)
    named = _report_strays(result.report())
    assert len(named) == 3
    out = tmp_path / "kk.nc"
    ix.write_result(result, out)
    for ds in (result.to_xarray(), ix.io.read_netcdf(out)):
        stray = ds["stray"]
        assert stray.dtype == bool and stray.dims == ("frequency",)
        np.testing.assert_allclose(np.sort(ds["frequency"].values[stray.values]), named, rtol=5e-3)


def test_a_kk_batchs_dataset_holds_each_spectrums_stray_points(data):
    """`KKBatchResult.to_xarray` holds the same ``stray`` per spectrum as each one's own."""
    stacked = ix.make_spectrum(data["frequency"].values, np.stack([data["Z"].values, data["Z"].values * 2]), dims=("cell",))
    batch = ix.kk_test_batch(stacked)
    ds = batch.to_xarray()
    single = ix.kk_test(data).to_xarray()["stray"].values
    assert ds["stray"].dims == ("cell", "frequency")
    np.testing.assert_array_equal(ds["stray"].values, [single, single])


@pytest.mark.parametrize("typed, meant", [("CPE1.n", "CPE1.alpha"), ("CPE1.P", "CPE1.alpha"), ("CPE1.phi", "CPE1.alpha"),
                                          ("CPE1.T", "CPE1.Q"), ("CPE1.Y0", "CPE1.Q"), ("Wo1.T", "Wo1.tau")])
def test_other_tools_names_of_a_parameter_are_hinted(data, typed, meant):
    """A CPE's exponent is n in most papers (ZView's CPE-P), its magnitude T (ZView)
    or Y0 (Gamry): ``init={"CPE1.n": 0.9}`` was told "did you mean CPE1.Q?", the closer spelling
    and the wrong parameter. The hint names the parameter those names mean, for init, fixed and
    bounds alike, before any fit."""
    model = "R0 + R1 || CPE1 + Wo1"
    for keyword, value in (("init", {typed: 0.9}), ("fixed", {typed: 0.9}), ("bounds", {typed: (0.5, 1.0)})):
        with pytest.raises(ix.ParameterError, match=re.escape(f"{keyword}: unknown parameter {typed!r} for {model}; did you mean {meant}?")):
            ix.fit(model, data, **{keyword: value})


def test_sample_given_a_progress_callback_hands_it_the_lines(data):
    """docs/cli.md ("From Python") says a long call's stages go to ``progress=print``: `fit`, `diagnose` and
    `refine` take a callback, and `sample` refused one ("progress must be True or False, got
    <built-in function print>", then a message naming the functions that take one); since
    2026-12-06 it takes one as they do (tests/test_sample_progress_like_fit.py)."""
    lines = []
    ix.sample("R0 + R1 || CPE1", data, progress=lines.append, steps=20)
    assert lines and lines[0].startswith("sample: fitting the least-squares start")


@pytest.mark.parametrize("command, named", [("kk", "impedax.kk_test"), ("stack", "impedax.stack_files"), ("draw", "impedax.draw_circuit"),
                                            ("gap", "impedax.models.gap_analysis"), ("remaining", "impedax.models.gap.gap_remainder")])
def test_a_command_name_used_in_python_names_its_function(command, named):
    """``ix.kk(data)``, the command's name, raised "module 'impedax' has no attribute 'kk'" with no
    hint (Python suggests close spellings only, and kk_test is not one); the command names whose
    function has another name point at it. Each named function exists."""
    with pytest.raises(AttributeError, match=re.escape(f"module 'impedax' has no attribute {command!r}; the command impedax {command} is {named}")):
        getattr(ix, command)
    module, _, name = named.rpartition(".")
    assert callable(getattr(__import__(module, fromlist=[name]), name))


@pytest.mark.parametrize("copier", [lambda r: pickle.loads(pickle.dumps(r)), copy.deepcopy], ids=["pickle", "deepcopy"])
def test_a_result_copied_by_pickle_or_deepcopy_stays_read_only(data, copier):
    """A fit, a KK test, a DRT, a Z-HIT and a comparison sent through pickle (a notebook's saved
    state, multiprocessing, joblib) or ``copy.deepcopy`` came back with writable arrays: ``r.z_data[0]
    = 0`` changed the copy's report silently, which the original refuses ("Results are
    read-only"). Each copy holds the same numbers and refuses edits as the original does."""
    from test_frozen_results import assert_read_only

    fit = ix.fit("R0 + R1 || CPE1", data, progress=False)
    for result in (fit, ix.kk_test(data), ix.drt(data), ix.zhit(data), ix.compare([ix.fit("R0 + R1 || C1", data, progress=False), fit])):
        copied = copier(result)
        xr.testing.assert_identical(copied.to_xarray(), result.to_xarray())
        if dataclasses.is_dataclass(copied) and any(isinstance(getattr(copied, f.name), (np.ndarray, dict, xr.Dataset)) for f in dataclasses.fields(copied)):
            assert_read_only(copied)
    copied = copier(fit)
    with pytest.raises(ValueError, match="read-only"):
        copied.z_data[0] = 0


@pytest.mark.parametrize("rule", ["gcv", "lcurve", "GCV"])
def test_a_drts_rule_given_as_lam_names_lam_method(data, rule):
    """``ix.drt(data, lam="gcv")``, the rule where λ goes (the command's ``--lam auto|VALUE`` beside
    ``--lam-method gcv|lcurve``), was told only "lam must be 'auto' or a positive number"."""
    with pytest.raises(ix.ParameterError, match=re.escape(f"lam must be 'auto' or a positive number, got {rule!r}; the rule that chooses λ is lam_method={rule.lower()!r} (with lam='auto')")):
        ix.drt(data, lam=rule)


def test_a_comparisons_dataset_holds_its_f_tests(data, tmp_path):
    """The report's F-test line ("F = 19.3, p = 1.66e-05" on REAL BioLogic, C1 nested in CPE1 at
    α = 1) was in ``summary()`` but not in ``to_xarray`` nor the ``.nc`` it writes. Oracle: F from
    the two fits' χ² and degrees of freedom, p from scipy's F distribution, halved for the
    boundary (the 50:50 chi-bar-squared mixture the note names)."""
    from scipy import stats

    simple, complex_ = ix.fit("R0 + R1 || C1", data, progress=False), ix.fit("R0 + R1 || CPE1", data, progress=False)
    comparison = ix.compare([simple, complex_])
    n = 2 * data.sizes["frequency"]
    f = (simple.chi2 - complex_.chi2) / (4 - 3) / (complex_.chi2 / (n - 4))
    out = tmp_path / "c.nc"
    ix.write_result(comparison, out)
    for ds in (comparison.to_xarray(), ix.io.read_netcdf(out)):
        assert ds.sizes["f_test"] == 1
        assert str(ds["f_test_simple"].values[0]) == "R0 + R1 || C1" and str(ds["f_test_complex"].values[0]) == "R0 + R1 || CPE1"
        np.testing.assert_allclose(ds["f_test_f"].values, [f], rtol=1e-9)
        np.testing.assert_allclose(ds["f_test_p_value"].values, [0.5 * stats.f.sf(f, 1, n - 4)], rtol=1e-6)
        assert list(ds["f_test_df2"].values) == [n - 4]
        assert "chi-bar-squared" in str(ds["f_test_note"].values[0])
        assert ds.attrs["aic_form"] == comparison.aic_form


def test_a_diagnosis_dataset_and_view_say_which_candidates_the_data_do_not_determine(data):
    """On REAL BioLogic the report says "not proposed: R0 + (R1 + R_relax || C_relax) || C1 (rms_rel
    2.77 %): the data do not determine R1, R_relax"; ``to_xarray`` (and ``diagnose --out d.nc``)
    and the notebook table showed that candidate as ΔAIC −58 and "significant: no" with no word why.
    Oracle: the names the report's "not proposed" lines give."""
    diagnosis = ix.diagnose(data, "R0 + R1 || C1", progress=False)
    # (the rule in brackets is said once, after the first such line: the names end there or at the line's end)
    named = {m: names.split(", ") for m, names in re.findall(r"not proposed: (.+?) \(rms_rel [^)]*\): the data do not determine ([^(\n]+?)(?: \(|$)", diagnosis.report(), flags=re.M)}
    assert len(named) == diagnosis.report().count("the data do not determine")
    assert "R0 + (R1 + R_relax || C_relax) || C1" in named
    ds = diagnosis.to_xarray()
    by_model = dict(zip(ds["candidate_model"].values, ds["candidate_undetermined"].values))
    for model, names in named.items():
        assert by_model[model].split(";") == names
    warnings = dict(zip(ds["candidate_model"].values, ds["candidate_warning"].values))
    for model, names in by_model.items():  # (the report names the nearest few; every one's warning says its names)
        assert (str(names) == "") == ("do not determine" not in str(warnings[model]))
        assert str(names).replace(";", ", ") in str(warnings[model])
    assert "do not determine R1, R_relax" in warnings["R0 + (R1 + R_relax || C_relax) || C1"]
    view = diagnosis._repr_html_()
    assert "undetermined" in view and "R1, R_relax" in view
