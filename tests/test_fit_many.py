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
