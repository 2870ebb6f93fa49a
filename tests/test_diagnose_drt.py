"""DRT evidence in the diagnosis: the data's DRT peaks that the baseline does not explain guide
`extra_relaxation` (τ, R) and `constant_phase` (α), the report and JSON say so, and the
diagnosis runs as before when the DRT is off or fails. SYNTHETIC spectra from numpy formulas
(tests/multi_arc.py); the evaluation study is marked slow."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import impedax as ix
from impedax.errors import FitError, ParameterError
from impedax.fitting.diagnosis import diagnosis as diagnosis_module
from impedax.fitting.diagnosis.catalog import BaselineContext
from impedax.fitting.diagnosis.effects import DEFAULT_EFFECTS
from impedax.fitting.drt import drt, unexplained_peaks

import multi_arc

TWO_ARCS = "R0 + R1 || C1 + R2 || C2"
TRUE_ARCS = [(50.0, 1e-4, 1.0), (80.0, 1e-2, 1.0), (40.0, 1.0, 1.0)]  # (R [Ω], τ [s], α)


@pytest.fixture(scope="module")
def three_arc_data():
    rng = np.random.default_rng(1)
    f = np.logspace(-2, 5, 60)
    z = multi_arc.arcs_impedance(f, 10.0, TRUE_ARCS)
    z = z * (1 + 0.01 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    return ix.make_spectrum(f, z)


@pytest.fixture(scope="module")
def with_and_without(three_arc_data):
    return ix.diagnose(three_arc_data, TWO_ARCS), ix.diagnose(three_arc_data, TWO_ARCS, drt_evidence=False)


def _context(fit, evidence):
    o = np.argsort(fit.frequency)
    return BaselineContext(fit.circuit, fit.values, fit.frequency[o], fit.z_data[o], fit.z_model[o], fit.registry, frozenset(), evidence)


def test_unexplained_peak_starts_the_new_arc_at_its_tau(three_arc_data):
    fit = ix.fit(TWO_ARCS, three_arc_data, n_starts=8)
    evidence = unexplained_peaks(drt(three_arc_data), fit)
    assert len(evidence.unexplained) == 1
    peak = evidence.unexplained[0]
    proposals = DEFAULT_EFFECTS["extra_relaxation"].propose(fit.circuit, _context(fit, evidence))
    rc = [p for p in proposals if "C_relax" in p.added]
    assert rc
    for p in rc:  # the first warm start is the peak's: R_relax = R_peak, R_relax·C_relax = τ_peak
        first = p.starts[0]
        assert first["R_relax"] == pytest.approx(peak.r_ohm)
        assert first["R_relax"] * first["C_relax"] == pytest.approx(peak.tau_s)
    # the truth's third arc: τ = 1 s, R = 40 Ω (DRT peak within 0.15 decade, R within 15 %)
    assert abs(math.log10(peak.tau_s)) < 0.15 and peak.r_ohm == pytest.approx(40.0, rel=0.15)
    # no proposal names a peak before its fit (a suggestion does after it, from its fitted τ:
    # `effects.cited_where`, tests/test_effect_drt_text.py)
    assert all("DRT" not in p.where for p in proposals)
    without = DEFAULT_EFFECTS["extra_relaxation"].propose(fit.circuit, _context(fit, None))
    assert [str(p.circuit) for p in without] == [str(p.circuit) for p in proposals]  # same circuits, other starts
    assert all("DRT" not in p.where for p in without)


def test_a_cpe_with_alpha_near_zero_does_not_break_the_placement(three_arc_data):
    """(R·Q)^(1/α) of a CPE whose α fell near 0 is beyond floating point (it raised
    OverflowError from deep inside the diagnosis): the proposals are made, and a fitted arc with
    such a CPE cites no DRT peak."""
    fit = ix.fit(TWO_ARCS, three_arc_data, n_starts=8)
    evidence = unexplained_peaks(drt(three_arc_data), fit)
    circuit = ix.parse("R0 + R1 || CPE1 + R2 || C2")
    values = {"R0": 10.0, "R1": 1e3, "CPE1.Q": 10.0, "CPE1.alpha": 0.005, "R2": 80.0, "C2": 1.25e-4}
    o = np.argsort(fit.frequency)
    ctx = BaselineContext(circuit, values, fit.frequency[o], fit.z_data[o], fit.z_model[o], fit.registry, frozenset(), evidence)
    proposals = DEFAULT_EFFECTS["extra_relaxation"].propose(circuit, ctx)
    assert len(proposals) == 6  # C and CPE, each in series and nested behind R1 and R2
    from impedax.fitting.diagnosis.effects import drt_citation

    cpe = next(p for p in proposals if "CPE_relax" in p.added)
    fitted = {**values, "R_relax": 1e3, "CPE_relax.Q": 10.0, "CPE_relax.alpha": 0.005}
    assert drt_citation("extra_relaxation", cpe, fitted, fit.registry, evidence) == ""


def test_distributed_peak_starts_the_cpe_at_the_alpha_of_its_width():
    rng = np.random.default_rng(2)
    f = np.logspace(-2, 5, 60)
    alpha_true = 0.7
    z = multi_arc.arcs_impedance(f, 10.0, [(100.0, 1e-3, alpha_true)])
    data = ix.make_spectrum(f, z * (1 + 0.003 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))))
    fit = ix.fit("R0 + R1 || C1", data, n_starts=8)
    evidence = unexplained_peaks(drt(data), fit)
    assert evidence.distributed
    (proposal,) = DEFAULT_EFFECTS["constant_phase"].propose(fit.circuit, _context(fit, evidence))
    # the DRT peak is the proposal's evidence (`Proposal.evidence`, cited once the fitted α agrees, since 2026-12-05), not its placement
    assert "DRT" in proposal.evidence and "DRT" not in proposal.where
    assert proposal.starts[0]["CPE1.alpha"] == pytest.approx(alpha_true, abs=0.1)
    (plain,) = DEFAULT_EFFECTS["constant_phase"].propose(fit.circuit, _context(fit, None))
    assert [s["CPE1.alpha"] for s in plain.starts] == [0.85, 0.7, 0.55]


def test_report_and_json_say_what_the_drt_shows(with_and_without):
    d, _ = with_and_without
    text = d.report()
    assert "the data's DRT has 3 peaks" in text and "the model explains 2" in text
    s = d.summary()
    json.dumps(s)
    peaks = s["drt_peaks"]
    assert len(peaks) == 3 and [p["explained"] for p in peaks] == [True, True, False]
    for p, (r, tau, _) in zip(peaks, TRUE_ARCS):
        assert abs(math.log10(p["tau_s"] / tau)) < 0.15 and p["r_ohm"] == pytest.approx(r, rel=0.15)
        assert set(p) >= {"tau_s", "r_ohm", "width_decades", "explained"}
    assert "1 s" in s["drt_summary"]
    assert d.best.effect == "extra_relaxation"
    v = d.best.fit.values
    assert abs(math.log10(v["R_relax"] * v["C_relax"] / 1.0)) < 0.2


def test_every_existing_json_key_stays(with_and_without):
    d, off = with_and_without
    keys = {"model", "baseline", "kk", "noise", "failing_bands", "verdict", "reason", "suggestions", "candidates", "thresholds", "notes"}
    assert keys <= set(d.summary()) and keys <= set(off.summary())
    assert off.summary()["drt_peaks"] is None and off.summary()["drt_summary"] is None
    assert off.drt is None and "DRT" not in off.report()


@pytest.mark.parametrize("error", [FitError("solver failed"), np.linalg.LinAlgError("singular"), ValueError("bad")])
def test_diagnosis_without_a_drt_works_as_before(three_arc_data, with_and_without, monkeypatch, error):
    def failing_drt(*args, **kwargs):
        raise error

    monkeypatch.setattr(diagnosis_module, "drt", failing_drt)
    d = ix.diagnose(three_arc_data, TWO_ARCS)
    _, off = with_and_without
    assert d.drt is None and any("DRT evidence not used" in n for n in d.notes)
    assert d.verdict == off.verdict
    assert [(s.model, s.where) for s in d.candidates] == [(s.model, s.where) for s in off.candidates]
    assert [s.aic for s in d.candidates] == pytest.approx([s.aic for s in off.candidates], rel=1e-9, abs=1e-9)


def test_too_few_points_for_a_drt():
    f = np.logspace(0, 3, 4)
    z = multi_arc.arcs_impedance(f, 5.0, [(20.0, 1e-2, 1.0)]) * (1 + 0.01 * np.array([1, -1, 1, -1]))
    # (on fewer than 10 points the noise is given; one effect: the DRT's note, not the catalog, is under test)
    d = ix.diagnose(ix.make_spectrum(f, z), "R0 + R1 || C1", noise=0.01, effects=DEFAULT_EFFECTS.select(["series_resistance"]))
    assert d.drt is None and any("DRT evidence not used: the DRT needs at least 5 frequencies" in n for n in d.notes)
    assert d.summary()["drt_peaks"] is None


def test_drt_evidence_flag_is_checked(three_arc_data):
    with pytest.raises(ParameterError, match="drt_evidence"):
        ix.diagnose(three_arc_data, TWO_ARCS, drt_evidence="yes")


# --- the evaluation study (slow) --------------------------------------------------------------


def added_tau(fit) -> float:
    """τ of the added arc R_relax ∥ C_relax (R·C) or R_relax ∥ CPE_relax ((R·Q)^(1/α))."""
    v = fit.values
    if "C_relax" in v:
        return v["R_relax"] * v["C_relax"]
    return (v["R_relax"] * v["CPE_relax.Q"]) ** (1 / v["CPE_relax.alpha"])


def run_study(split: str, n: int):
    """Each case diagnosed with and without the DRT evidence: (case, outcome with, outcome
    without); an outcome is (top effect or verdict, τ of the added arc or nan)."""
    rows = []
    for case in multi_arc.cases(split, n):
        data = ix.make_spectrum(case.frequency, case.z)
        outcomes = []
        for flag in (True, False):
            d = ix.diagnose(data, case.circuit, drt_evidence=flag)
            top = d.best.effect if d.best is not None else str(d.verdict)
            tau = added_tau(d.best.fit) if top == "extra_relaxation" else float("nan")
            outcomes.append((top, tau, d.best.rms_rel if d.best is not None else d.baseline.rms_rel))
        rows.append((case, *outcomes))
    return rows


def score(rows):
    """Top-1 hits on the missing-arc cases, with and without the DRT: ``named`` (the top
    suggestion is ``extra_relaxation``) and ``fixed`` (named, and its fit reaches the noise:
    rms_rel ≤ 1.5·√2·σ, so the new arc sits where the missing one was); false alarms (any
    verdict but adequate) on the cases where nothing is missing."""
    missing = [r for r in rows if r[0].missing_tau is not None]
    clean = [r for r in rows if r[0].missing_tau is None]
    out = {"n_missing": len(missing), "n_clean": len(clean)}
    for k, label in ((1, "drt"), (2, "no_drt")):
        out[f"named_{label}"] = sum(r[k][0] == "extra_relaxation" for r in missing)
        out[f"fixed_{label}"] = sum(r[k][0] == "extra_relaxation" and r[k][2] <= 1.5 * math.sqrt(2) * r[0].noise for r in missing)
        out[f"false_alarms_{label}"] = sum(r[k][0] != "adequate" for r in clean)
    return out


def print_study(split, rows, s):
    print(f"\n{split}: {s}")
    for case, (top, tau, rms), (top0, tau0, rms0) in rows:
        truth = f"{case.missing_tau:.2g} s" if case.missing_tau else "-"
        print(f"  {case.name:28s} noise {case.noise:.1%} missing τ {truth:9s} | DRT: {top:18s} τ {tau:7.2g} rms {rms:.2%} | no DRT: {top0:18s} τ {tau0:7.2g} rms {rms0:.2%}")


@pytest.mark.slow
@pytest.mark.parametrize("split,n", [("dev", 40), ("heldout", 40)])
def test_drt_evidence_study(split, n):
    rows = run_study(split, n)
    s = score(rows)
    print_study(split, rows, s)
    assert s["n_missing"] >= 20 and s["n_clean"] >= 5
    assert s["named_drt"] >= s["named_no_drt"] and s["fixed_drt"] >= s["fixed_no_drt"]
    assert s["named_drt"] >= 0.6 * s["n_missing"]
    assert s["false_alarms_drt"] <= max(1, 0.2 * s["n_clean"])


def test_an_unexplained_peak_of_milliohms_is_written_with_its_prefix():
    """The three arcs at 1/1000 of their size (a battery's scale): the unexplained peak at 1 s,
    R = 40 mΩ by construction, reads "R ≈ 4x mΩ" as impedax writes quantities, not "0.04 Ω"
    (the DRT line of a diagnosis of REAL exampleData.csv read "R ≈ 0.00746 Ω" until 2026-12-06)."""
    rng = np.random.default_rng(1)
    f = np.logspace(-2, 5, 60)
    z = multi_arc.arcs_impedance(f, 0.010, [(r / 1000, tau, alpha) for r, tau, alpha in TRUE_ARCS])
    data = ix.make_spectrum(f, z * (1 + 0.01 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))))
    evidence = unexplained_peaks(drt(data), ix.fit(TWO_ARCS, data, n_starts=8))
    (peak,) = evidence.unexplained
    assert peak.r_ohm == pytest.approx(0.040, rel=0.15)
    written = f"R ≈ {float(f'{peak.r_ohm * 1000:.3g}'):g} mΩ"
    assert written in evidence.text, evidence.text
