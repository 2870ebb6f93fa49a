"""The misfit warning of global fits with shared parameters (`fit(..., shared=)`): each
spectrum of the joint fit is set against its own Kramers–Kronig misfit by the rule of single
and batch fits (`result.misfit_notes`, docs/fitting.md "Weighting sanity and the model's
misfit"), under the spectrum's key; and a model this wrong leaks no numpy RuntimeWarning."""

import warnings

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.kk import KKChains
from impedax.fitting.least_squares.result import MISFIT_CHECKED_FROM, misfit_notes
from impedax.fitting.least_squares.shared import joint_covariance

FREQ = np.geomspace(1.0, 1e5, 30)
MISSES = "the model misses structure the data hold: its rms_rel is over 5×"


def stack(z_of_trial, noise=0.001, seed=0):
    """Spectra (closed form) over ``trial`` with 0.1 % multiplicative noise, fixed seed."""
    rng = np.random.default_rng(seed)
    z = np.array([z * (1 + noise * rng.standard_normal(z.size)) for z in z_of_trial])
    return xr.Dataset({"Z": (("trial", "frequency"), z)}, coords={"frequency": FREQ, "trial": list(range(len(z)))})


def rc(r0, r1, c1, f=FREQ):
    return r0 + r1 / (1 + 2j * np.pi * f * r1 * c1)


@pytest.fixture(scope="module")
def one_arc():
    """R0 + R1 || C1 with one C1 and three R1: the circuit the nothing-wrong fit shares C1 of."""
    return stack([rc(10.0, r1, 1e-6) for r1 in (1000.0, 1200.0, 1500.0)])


@pytest.fixture(scope="module")
def two_arcs():
    """Three noisy copies of a two-arc spectrum: R0 + R1 || C1 misses one arc."""
    return stack([rc(10.0, 100.0, 1e-6) + rc(0.0, 500.0, 1e-3)] * 3, seed=1)


def test_gross_misfit_warns_per_spectrum_with_the_rule_s_words(two_arcs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a model this wrong leaks no RuntimeWarning (divide, invalid)
        r = ix.fit("R0 + R1 || C1", two_arcs, shared=["C1"])
    rms = r.dataset["rms_rel"].values
    assert np.all(rms > 0.1)  # (one arc of two: ~22 %)
    # the same texts a batch or single fit of these spectra gets from the rule, one per spectrum
    z, z_model = two_arcs["Z"].transpose("trial", "frequency").values, r.dataset["Z_model"].transpose("trial", "frequency").values
    expected = misfit_notes(FREQ, z, z_model)
    for i, note in enumerate(expected):
        assert note and note[0].startswith(MISSES)
        assert note[0] in r.warnings[f"trial={i}"]  # named by spectrum, as a batch names them
    assert not any(w.startswith(MISSES) for w in r.warnings.get("shared over trial", ()))
    assert MISSES in r.report()
    assert any(w.startswith(MISSES) for w in r.summary()["warnings"])


def test_grossly_wrong_fixed_value_warns_on_every_spectrum(one_arc):
    # the case of the report: joint chi2_red ~1e15, every parameter off
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = ix.fit("R0 + R1 || C1 + R2", one_arc, shared=["C1"], fixed={"R2": 1e9})
    assert float(r.dataset["joint_chi2_red"]) > 1e10
    for i in range(3):
        assert any(w.startswith(MISSES) and "impedax diagnose" in w for w in r.warnings[f"trial={i}"])


def test_cli_fit_shared_names_the_spectra(two_arcs, tmp_path, capsys):
    from impedax.cli import main

    path = tmp_path / "two_arcs.nc"
    ix.save(two_arcs, path)
    assert main(["fit", str(path), "--model", "R0 + R1 || C1", "--shared", "C1"]) == 0
    out = capsys.readouterr().out
    assert "warning (all 3 spectra): " + MISSES in out
    assert out.count(MISSES) == 1  # once, grouped (the report listed each text a second time, unnamed)


def test_correct_model_gives_no_misfit_warning_and_runs_no_kk_test(one_arc, monkeypatch):
    calls = []
    kk = KKChains.misfits  # (every misfit note's KK chain is fitted through a call's KKChains)
    monkeypatch.setattr(KKChains, "misfits", lambda self, f, z, rows: calls.append(len(rows)) or kk(self, f, z, rows))
    r = ix.fit("R0 + R1 || C1", one_arc, shared=["C1"])
    assert float(r.dataset["rms_rel"].max()) < MISFIT_CHECKED_FROM
    assert float(r.values("C1")) == pytest.approx(1e-6, rel=0.01)
    assert not any("Kramers–Kronig" in w for ws in r.warnings.values() for w in ws)
    assert calls == []  # good fits cost nothing more: the KK test runs only from MISFIT_CHECKED_FROM on


def test_shared_parameter_without_effect_gives_huge_finite_variance_without_warning(one_arc):
    # R1 fixed at 1e-200: C1 changes Z by nothing (dZ/dC1 ∝ R1² underflows to 0), so the
    # Schur complement is 0; its inverse was a division by zero (RuntimeWarning, inf and NaN)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = ix.fit("R0 + R1 || C1", one_arc, shared=["C1"], fixed={"R1": 1e-200})
    # C1 cannot be told from its bound 0: no standard error (docs/fitting.md, "Standard errors
    # at a bound"); the linearisation's is huge and finite
    assert np.isnan(float(r.dataset["shared_stderr"].sel(shared_param="C1")))
    e = float(r.dataset["shared_linearised_stderr"].sel(shared_param="C1"))
    assert np.isfinite(e) and e > 1e3 * abs(float(r.values("C1")))


def test_joint_covariance_of_blocks_without_effect_is_finite():
    # a zero own column and a zero shared column: huge finite variances, no warning
    rng = np.random.default_rng(3)
    jac = rng.standard_normal((3, 20, 3))
    jac[:, :, 2] = 0.0  # the shared parameter does nothing
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cov_shared, cov_full = joint_covariance(jac, [0, 1], [2])
        _, all_zero = joint_covariance(np.zeros((2, 10, 2)), [0], [1])
    assert np.all(np.isfinite(cov_shared)) and cov_shared[0, 0] > 1e20
    assert np.all(np.isfinite(cov_full)) and np.all(np.isfinite(all_zero))
    assert np.all(np.diagonal(all_zero, axis1=1, axis2=2) > 1e20)


def test_a_global_fit_gives_the_data_warnings_of_a_batch(one_arc):
    """Points with Re Z < 0 and a weighting that a few points dominate: the texts a batch fit of
    the same spectra gives (`batch.data_notes`), under each spectrum's key. Before, a global fit
    gave neither."""
    z = one_arc["Z"].values.copy()
    z[1, -1] = -0.2 * abs(z[1, -1]) + 1j * z[1, -1].imag  # an instrument's phase error at the top of trial 1
    data = one_arc.copy()
    data["Z"] = (("trial", "frequency"), z)
    shared = ix.fit("R0 + R1 || C1", data, shared=["C1"])
    batch = ix.fit("R0 + R1 || C1", data)
    negative = [w for w in shared.warnings["trial=1"] if "Re Z < 0" in w]
    assert negative and negative == [w for w in batch.warnings["trial=1"] if "Re Z < 0" in w]
    assert not any("Re Z < 0" in w for k in ("trial=0", "trial=2") for w in shared.warnings.get(k, ()))
    # proportional weighting: the points of smallest |Re| or |Im| carry the weight
    proportional = ix.fit("R0 + R1 || C1", one_arc, shared=["C1"], weighting="proportional")
    batch_p = ix.fit("R0 + R1 || C1", one_arc, weighting="proportional")
    for key, texts in batch_p.warnings.items():
        weighted = [w for w in texts if "weight" in w]
        assert weighted and all(w in proportional.warnings[key] for w in weighted)


def test_reports_write_ohm_as_the_symbol(one_arc):
    # the parameter tables of single and global fits wrote the element spec's spelling "Ohm"
    # where every other text of impedax writes Ω, and a batch's table had no unit column
    shared = ix.fit("R0 + R1 || C1", one_arc, shared=["R0"])
    single = ix.fit("R0 + R1 || C1", one_arc.isel(trial=0))
    batch = ix.fit("R0 + R1 || C1", one_arc)
    for report in (shared.report(), single.report(), batch.report()):
        rows = [line for line in report.splitlines() if line.startswith(("R0 ", "R1 ", "C1 "))]
        assert rows and all(line.endswith(" Ω") for line in rows if line.startswith("R")), rows
        assert all(line.endswith(" F") for line in rows if line.startswith("C1")), rows
        assert "Ohm" not in report


def test_unit_text_writes_the_symbols():
    from impedax.data import unit_text

    assert unit_text("Ohm") == "Ω" and unit_text("Ohm s^-1/2") == "Ω s^-1/2"
    assert unit_text("F s^(alpha-1)") == "F s^(α-1)"  # (a CPE's Q: "alpha" spelled out before)
    assert unit_text("1") == "" and unit_text("H") == "H"
