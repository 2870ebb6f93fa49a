"""A diagnosis' candidates in the order every fit reports, saved refinements and diagnoses that
hold their fit, the note of a refine side path's refit, and the KK report when µ never fell
below c (docs/diagnosis.md, docs/io.md, docs/kk.md)."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting.diagnosis import refinement as rf
from impedax.fitting.diagnosis.diagnosis import Diagnosis
from impedax.fitting.diagnosis.refinement import Refinement, RefinementStep
from impedax.fitting.drt import Peak
from impedax.fitting.least_squares.candidates import fit_candidates
from impedax.io.netcdf import read_netcdf, write_netcdf

REAL = Path(__file__).parent / "fixtures" / "real"
TWO_ARCS = "R0 + R1 || C1 + R2 || C2"
# SYNTHETIC: a fast arc (100 Ω ∥ 1 µF, peak at 1/(2π·1e-4 s) ≈ 1.6 kHz) and a slow one (50 Ω ∥ 10 mF, ≈ 0.32 Hz)
FAST, SLOW = (100.0, 1e-6), (50.0, 1e-2)


@pytest.fixture(scope="module")
def two_arcs():
    f = np.logspace(-2, 5, 36)
    w = 2 * np.pi * f
    z = 10.0 + sum(r / (1 + 1j * w * r * c) for r, c in (FAST, SLOW))
    rng = np.random.default_rng(7)
    z = z * (1 + 0.002 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    return ix.make_spectrum(f, z)


@pytest.fixture(scope="module")
def swapped_candidate(two_arcs):
    """A candidate fit started with R1 ∥ C1 on the slow arc (as a diagnosis' warm start may be):
    one start besides the data-driven guess, and few steps, so that the warm start's optimum is
    the one kept (from the truth two steps come near it; from the guess they do not)."""
    start = {"R0": 10.0, "R1": SLOW[0], "C1": SLOW[1], "R2": FAST[0], "C2": FAST[1]}
    (cand,) = fit_candidates([TWO_ARCS], two_arcs, init=[start], n_starts=1, max_steps=2, seed=0)
    return cand


def _peak_hz(r: float, c: float) -> float:
    """Where −Z'' of R ∥ C peaks: ω = 1/(RC)."""
    return 1.0 / (2 * np.pi * r * c)


def test_candidates_list_the_fastest_block_first(swapped_candidate):
    v = swapped_candidate.values
    assert _peak_hz(v["R1"], v["C1"]) > _peak_hz(v["R2"], v["C2"])
    np.testing.assert_allclose([v["R1"], v["C1"], v["R2"], v["C2"]], [*FAST, *SLOW], rtol=0.03)
    # the errors and the covariance moved with the values: R1's error is the fast arc's
    cov = dict(zip(swapped_candidate.free_names, np.sqrt(np.diag(swapped_candidate.covariance))))
    assert cov["R1"] == pytest.approx(swapped_candidate.stderr["R1"], rel=1e-9)


def test_the_fit_from_a_candidates_values_reports_the_same_values(swapped_candidate, two_arcs):
    """What ``impedax fit --model … --init …`` of the diagnosis' printed command does."""
    refit = ix.fit(TWO_ARCS, two_arcs, init=dict(swapped_candidate.values), n_starts=1)
    for name, value in swapped_candidate.values.items():
        assert refit.values[name] == pytest.approx(value, rel=1e-4), name
        assert refit.stderr[name] == pytest.approx(swapped_candidate.stderr[name], rel=1e-2), name


def test_a_saved_refinement_holds_its_final_fit(swapped_candidate, tmp_path, capsys):
    fit = swapped_candidate
    refinement = Refinement((RefinementStep(fit, None, None, None),), "adequate", notes=("a note",), masked_points=(3.0, 40.0))
    path = tmp_path / "r.nc"
    write_netcdf(refinement.to_xarray(), path)
    ds = read_netcdf(path)
    for kept in ("Z", "residual_rel", "model", "effect", "added", "rms_rel", "aic", "bic"):  # (the names before: a public contract)
        assert kept in ds.variables
    assert ds.attrs["final_model"] == fit.model and ds.attrs["impedax_kind"] == "refinement"
    assert ds.attrs["masked_points_hz"] == [3.0, 40.0]
    back = Refinement.final_fit_of(ds)
    assert back.values == fit.values and back.stderr == fit.stderr
    np.testing.assert_array_equal(back.covariance, fit.covariance)
    np.testing.assert_array_equal(back.z_model, fit.z_model)
    assert main(["inspect", str(path), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["result_kind"] == "refinement"
    assert main(["inspect", str(path)]) == 0
    assert "holding a saved refinement (impedax refine) with its final fit" in capsys.readouterr().out


def test_a_saved_diagnosis_holds_its_baseline(swapped_candidate, tmp_path, capsys):
    fit = swapped_candidate
    candidate = SimpleNamespace(model=TWO_ARCS + " + L1", effect="inductance", rms_rel=0.01, delta_aic=-3.0, delta_bic=-1.0, significant=False, undetermined=(), warning=None)
    diagnosis = Diagnosis(
        baseline=fit, kk=None, noise=np.full(fit.frequency.size, 0.002), noise_source="given", failing_bands=(), candidates=(candidate,),
        verdict="adequate", reason="no effect", masked_points=(5.0,), masked_impedance=(3 - 4j,),
    )
    path = tmp_path / "d.nc"
    write_netcdf(diagnosis.to_xarray(), path)
    ds = read_netcdf(path)
    assert ds.attrs["impedax_kind"] == "diagnosis" and ds.attrs["baseline_aic"] == fit.aic
    assert ds.attrs["masked_points_hz"] == [5.0]
    assert (ds.attrs["masked_impedance_real_ohm"], ds.attrs["masked_impedance_imag_ohm"]) == ([3.0], [-4.0])
    back = Diagnosis.baseline_of(ds)
    assert back.values == fit.values and back.model == fit.model
    np.testing.assert_array_equal(back.correlation, fit.correlation)
    assert main(["inspect", str(path)]) == 0
    assert "holding a saved diagnosis (impedax diagnose) with its baseline fit" in capsys.readouterr().out


def test_a_side_paths_refit_note_speaks_of_that_path(monkeypatch):
    """A second path's refit had said "the refinement's 0.281 % … the refinement's values are
    reported" of its own fit, which the next note discarded (stand-in fits: χ² and AIC only)."""
    last = SimpleNamespace(model="R0 + R1 || CPE1", values={"R0": 1.0}, fixed={"R0": False}, bounds={}, circuit=None, weighting="modulus", registry=None, chi2=1.0, aic=-1000.0, rms_rel=0.00281)
    scratch = SimpleNamespace(chi2=1.001, aic=-1000.0 + 0.047, rms_rel=0.00282)
    warm = SimpleNamespace(chi2=1.0, aic=-1000.0, rms_rel=0.00281)
    monkeypatch.setattr(rf, "fit", lambda *a, init=None, **k: warm if init is not None else scratch)
    monkeypatch.setattr(rf, "undetermined_parameters", lambda f: set())
    _, main_note = rf._reproduced(None, last, n_starts=1, seed=0)
    assert "from the refinement's 0.281 %" in main_note and "the refinement's values are reported" in main_note
    # through `_finish` with a path's label, as `_second_path` calls it
    asked = []

    def reproduced(used, fit, **options):
        asked.append(options.get("whose"))
        return rf._reproduced(used, fit, **options)

    notes = []
    steps = [RefinementStep(last, None, None, None)]
    rf._finish(steps, None, n_starts=1, seed=0, say=lambda text: None, notes=notes, label="second path: ", reproduced=reproduced)
    assert asked == [rf.SIDE_PATH]
    (note,) = notes
    assert note.startswith("second path: fit of R0 + R1 || CPE1 from scratch reaches rms_rel 0.282 %")
    assert "from this path's 0.281 %" in note and "this path ends at its own values" in note and "refinement" not in note


def test_kk_says_m_fit_was_used_when_mu_never_fell_below_c():
    """pyimpspec's data.dfr: µ stays above 0.85 for every M tried; M_fit (12, under the cap) is used."""
    data = ix.load(REAL / "data.dfr")
    result = ix.kk_test(data)
    assert not result.mu_reached and result.mu >= result.c
    text = result.report()
    assert "M = M_fit, the smallest M that fits them, is used" in text and "capped" not in text
    given = ix.kk_test(data, n_rc=result.n_rc)
    assert given.n_rc == result.n_rc and not given.mu_reached
    assert f"(µ ≥ c = {given.c:g} at the M given)" in given.report()


def test_drt_support_follows_the_new_arc_under_a_baseline_arcs_name(swapped_candidate):
    """An added R_relax ∥ C_relax in series with R1 ∥ C1 is exchangeable with it: in the order
    every fit reports, the new arc's values may sit under R1, C1. The DRT still backs it."""
    from impedax.fitting.diagnosis.diagnosis import _drt_supports

    values = swapped_candidate.values
    fit = SimpleNamespace(circuit=ix.parse("R0 + R1 || C1 + R_relax || C_relax"), registry=swapped_candidate.registry,
                          values={"R0": values["R0"], "R1": values["R1"], "C1": values["C1"], "R_relax": values["R2"], "C_relax": values["C2"]})
    fast_tau = FAST[0] * FAST[1]  # the new arc is the fast one, now listed first as R1 ∥ C1
    def peak(tau, r_sd=0.1):
        return Peak(tau_s=tau, r_ohm=1.0, width_decades=0.8, gamma_max_ohm=1.0, r_ohm_sd=r_sd)

    evidence = SimpleNamespace(unexplained=[peak(fast_tau)], distributed=[])
    assert _drt_supports(SimpleNamespace(effect="extra_relaxation", fit=fit), evidence)
    # a peak no arc of the fit lies near is no support, nor one whose R the DRT's band does not
    # tell from zero (1 ± 0.8 Ω: under 2σ)
    assert not _drt_supports(SimpleNamespace(effect="extra_relaxation", fit=fit), SimpleNamespace(unexplained=[peak(1e3)], distributed=[]))
    assert not _drt_supports(SimpleNamespace(effect="extra_relaxation", fit=fit), SimpleNamespace(unexplained=[peak(fast_tau, 0.8)], distributed=[]))
