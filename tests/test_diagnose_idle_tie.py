"""Candidates the data cannot tell apart: the one changing an element the baseline leaves idle
goes first (`diagnosis._idle_first`), so that the working elements keep their values and roles.

R ∥ CPE ∥ C fitted from R1 || C1 || C2: the two parallel capacitors are degenerate, the fit puts
the capacitance into one and leaves the other idle; "CPE in place of C1" and "CPE in place of C2"
are the same fit, and the one replacing the idle capacitor keeps the working one's value."""

import dataclasses

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis.diagnosis import _rank, _same_fit, _undetermined_elements, undetermined_parameters
from impedax.fitting.diagnosis.vanishing import idle_elements

R_TRUE, Q_TRUE, ALPHA_TRUE, C_TRUE = 80e6, 5e-9, 0.35, 420e-12  # the haptics remainder: R_EP ∥ CPE_EP ∥ C_gap
REL_NOISE = 0.005  # relative complex noise of the synthetic spectrum
AIC_NUDGE = 0.5  # a ΔAIC change well inside a tie (the same-fit rule allows 2)
IDLE_SHARE = 1e-3  # a capacitor carrying below this share of the block's admittance is idle (as branches.IDLE_BRANCH_SHARE)


def remainder_spectrum():
    """Z = 1 / (1/R + Q (jω)^α + jωC) with REL_NOISE complex noise (the oracle, in numpy)."""
    rng = np.random.default_rng(7)
    f = np.geomspace(1.0, 1e6, 41)
    jw = 2j * np.pi * f
    z = 1.0 / (1.0 / R_TRUE + Q_TRUE * jw**ALPHA_TRUE + jw * C_TRUE)
    z = z * (1 + REL_NOISE * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2))
    return ix.make_spectrum(f, z)


@pytest.fixture(scope="module")
def diagnosed():
    return ix.diagnose(remainder_spectrum(), "R1 || C1 || C2", noise=REL_NOISE)


def idle_and_working(fit):
    """(idle capacitor, working capacitor) of a fit of R1 || C1 || C2, by their admittance share
    ωC / |Σ Y| over the band, computed here from the fitted values."""
    jw = 2j * np.pi * fit.frequency
    y = {n: jw * fit.values[n] for n in ("C1", "C2")}
    total = 1.0 / fit.values["R1"] + y["C1"] + y["C2"]
    share = {n: float(np.max(np.abs(y[n] / total))) for n in y}
    idle = min(share, key=share.get)
    assert share[idle] < IDLE_SHARE, share
    return idle, ("C2" if idle == "C1" else "C1")


def test_the_candidate_replacing_the_idle_capacitor_ranks_first(diagnosed):
    d = diagnosed
    idle, working = idle_and_working(d.baseline)
    assert idle_elements(d.baseline, undetermined_parameters(d.baseline)) == {idle}
    assert d.verdict == "missing_effect", d.report()
    best = d.best
    assert best.effect == "constant_phase" and f"in place of the ideal capacitor {idle}" in best.where, d.report()
    names = best.fit.circuit.element_names
    assert idle not in names and working in names
    assert best.fit.values[working] == pytest.approx(C_TRUE, rel=0.05)
    # the other placement is the same fit within the noise, but moves the capacitance into the idle one
    other = next(s for s in d.suggestions if f"in place of the ideal capacitor {working}" in s.where)
    assert other in d.same_fits(best)
    assert other.fit.values[idle] == pytest.approx(C_TRUE, rel=0.05)
    report = d.report()
    assert report.index(best.model) < report.index(f"the same fit within the noise (the data cannot tell them apart): {other.model}")


def test_the_tie_break_moves_only_the_tied_candidate(diagnosed):
    d = diagnosed
    loose, idle = _undetermined_elements(d.baseline), idle_elements(d.baseline, undetermined_parameters(d.baseline))
    # the two placements' ΔAIC differ in the 6th digit, either way: make the idle one's slightly
    # worse (the fit, by which `_same_fit` judges, stays the same), so AIC alone puts the other first
    keeps = d.best
    cands = [dataclasses.replace(s, delta_aic=s.delta_aic + AIC_NUDGE) if s is keeps else s for s in d.candidates]
    keeps = next(s for s in cands if s.added == d.best.added)
    plain = _rank(list(cands), d.drt, loose)  # the ranking without the tie-break
    assert plain[0] is not keeps and _same_fit(plain[0].fit, keeps.fit, d.noise)
    tied = _rank(list(cands), d.drt, loose, idle, d.baseline.circuit, d.noise)
    assert tied[0] is keeps
    assert [s for s in tied if s is not keeps] == [s for s in plain if s is not keeps]  # the rest keep their order
    # no idle element, or no noise to tell ties by: the ranking is the one without the tie-break
    assert _rank(list(cands), d.drt, loose, frozenset(), d.baseline.circuit, d.noise) == plain
    assert _rank(list(cands), d.drt, loose, idle, d.baseline.circuit, None) == plain


def test_refine_keeps_the_working_capacitor_and_names_the_alternative():
    r = ix.refine(remainder_spectrum(), "R1 || C1 || C2", noise=REL_NOISE, max_effects=1)
    idle, working = idle_and_working(r.steps[0].fit)
    final = r.final
    assert idle not in final.circuit.element_names
    assert final.values[working] == pytest.approx(C_TRUE, rel=0.05)
    cpe = next(n for n in final.values if n.endswith(".alpha"))
    assert final.values[cpe] == pytest.approx(ALPHA_TRUE, abs=0.05)
    alternative = r.steps[1].same_fit
    assert len(alternative) == 1 and working not in ix.parse(alternative[0]).element_names
    assert r.summary()["steps"][1]["same_fit"] == list(alternative) and r.summary()["steps"][0]["same_fit"] == []
    assert f"step 1 has an alternative, the same fit within the noise (the data cannot tell them apart): {alternative[0]}" in r.report()


def test_diagnose_json_lists_each_suggestions_same_fits(diagnosed):
    """``impedax diagnose --json``'s suggestions[].same_fit: the models of `Diagnosis.same_fits`,
    as refine's steps[].same_fit; the two capacitor placements name each other, and a suggestion
    the data tell from every other has []."""
    d = diagnosed
    listed = d.summary()["suggestions"]
    assert [s["model"] for s in listed] == [s.model for s in d.suggestions]
    for entry, s in zip(listed, d.suggestions):
        assert entry["same_fit"] == [t.model for t in d.same_fits(s)]
    best, = (entry for entry in listed if entry["model"] == d.best.model)
    other = next(s for s in d.suggestions if s is not d.best and s.effect == d.best.effect and "in place of the ideal capacitor" in s.where)
    assert other.model in best["same_fit"] and d.best.model in next(e for e in listed if e["model"] == other.model)["same_fit"]
    # "none", checked in numpy from the fits' curves: a suggestion whose model spectrum leaves
    # every other's by twice the noise σ_k at some point cannot be the same fit as any
    def apart(s, t):
        return bool(np.any(np.abs(s.fit.z_model - t.fit.z_model) > 2 * d.noise * np.abs(s.fit.z_data)))

    alone = [entry for entry, s in zip(listed, d.suggestions) if all(apart(s, t) for t in d.suggestions if t is not s)]
    assert alone and all(entry["same_fit"] == [] for entry in alone)
