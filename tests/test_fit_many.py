"""Candidate fits through padded programs agree with one-by-one fits of compiled trees."""

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.least_squares.candidates import fit_candidates
from spectra import CASES, noisy


def test_candidates_match_single_fits(rng):
    text, fn, truth, (lo, hi) = CASES["r_cpe"]
    f = np.geomspace(lo, hi, 40)
    data = ix.make_spectrum(f, noisy(fn(f, truth), 0.01, rng))
    candidates = ["R0 + R1 || C1", "R0 + R1 || CPE1", "R0 + R1 || CPE1 + L1"]
    baseline = ix.fit("R0 + R1 || C1", data)
    init = [baseline.values, {k: v for k, v in baseline.values.items() if k != "C1"}, None]
    results = fit_candidates(candidates, data, init=init)
    assert [r.model for r in results] == candidates
    for text, r in zip(candidates, results):
        single = ix.fit(text, data)
        assert r.rms_rel == pytest.approx(single.rms_rel, rel=1e-3), text
        assert r.aic == pytest.approx(single.aic, abs=0.5), text
    best = min(results, key=lambda r: r.aic)
    assert best.model == "R0 + R1 || CPE1"
    assert best.values["CPE1.alpha"] == pytest.approx(truth["CPE1.alpha"], abs=0.03)


def test_candidates_respect_fixed_values(rng):
    text, fn, truth, (lo, hi) = CASES["rc"]
    f = np.geomspace(lo, hi, 30)
    data = ix.make_spectrum(f, noisy(fn(f, truth), 0.01, rng))
    (r,) = fit_candidates(["R0 + R1 || C1"], data, fixed={"R0": 50.0, "X9": 1.0})
    assert r.values["R0"] == 50.0 and r.fixed["R0"] and r.n_params == 2


def test_cold_starts_damped_with_identity_reach_the_optimum_of_impedax_fit():
    """Some random starts of a 9-element ladder begin with an inductance or a diffusion
    resistance ~10⁸ times too large (χ² ≈ 1e17). Damped with Marquardt's scaling they stall
    where they began, and the best of 16 starts ends at rms_rel 2.9 % where `impedax.fit`
    of the same circuit reaches 1.7 %; the diagnosis's baseline, fitted so, proposed a CPE
    for the ideal C3: a false alarm. Damped with λI (the baseline runs every start with both
    dampings) they do not. The
    SYNTHETIC spectrum is the evaluation set's adequate ladder (its own formulas, 1 % noise
    growing toward low frequency)."""
    import evaluation_set as es

    template = next(t for t in es.TEMPLATES if t.name == "adequate/ladder9")
    case = es.make_case(template, template.variants[0], "dev", 0)
    data = ix.make_spectrum(case.frequency, case.z)
    single = ix.fit(case.circuit, data)
    candidate = fit_candidates([case.circuit], data, n_starts=16, seed=0, max_steps=300, damping="identity")[0]
    # within 5 %: the ladder has a second optimum at 1.77 % that `impedax.fit` itself ends in
    # with 64 starts; the stalled starts ended 70 % above
    assert candidate.rms_rel <= single.rms_rel * 1.05
    with pytest.raises(ix.FitError, match="damping must be one of marquardt, identity"):
        fit_candidates([case.circuit], data, damping="scaled")
    with pytest.raises(ix.FitError, match="one per circuit"):
        fit_candidates([case.circuit], data, damping=["identity", "marquardt"])
    assert ix.diagnose(data, case.circuit).verdict == "adequate"
