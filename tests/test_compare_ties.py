"""`impedax.compare` breaks a tie of AICs (equal to the solver's tolerance, `criteria_tie`) by
the fewer free parameters, then the order given, so float noise no longer picks "best"; checks
"reduces to the best" against every model tied with it; and says the tie in the title.

Oracles: χ² of each fit recomputed here with numpy from the impedance written out below
(R0 + R1 ∥ CPE1 and R0 + CC1 are one function, Z = R0 + R/(1 + (jωτ)^α) with τ^α = R·Q),
AIC = n ln(χ²/n) + 2k with n = 2N (docs/fitting.md), and hand numbers.
"""

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.comparison import TIE_CHI2_REL, UNKNOWN_VARIANCE, KNOWN_SIGMA, criteria_tie
from impedax.io.export import to_jsonable

REAL = Path(__file__).resolve().parent / "fixtures" / "real"
ZARC, CC, WITH_W = "R0 + R1 || CPE1", "R0 + CC1", "R0 + R1 || CPE1 + W1"


def zarc(f, r0, r1, q, alpha):
    return r0 + 1 / (1 / r1 + q * (2j * np.pi * f) ** alpha)


def aic_by_hand(fit) -> float:
    """n ln(χ²/n) + 2k, χ² of modulus weighting from the ZARC written above."""
    v = fit.values
    if "CC1.R" in v:  # R/(1 + (jωτ)^α) is R ∥ CPE with Q = τ^α/R
        z = zarc(fit.frequency, v["R0"], v["CC1.R"], v["CC1.tau"] ** v["CC1.alpha"] / v["CC1.R"], v["CC1.alpha"])
    else:
        z = zarc(fit.frequency, v["R0"], v["R1"], v["CPE1.Q"], v["CPE1.alpha"])
    r = (z - fit.z_data) / np.abs(fit.z_data)
    n = 2 * fit.frequency.size
    return n * math.log(float(np.sum(r.real**2 + r.imag**2)) / n) + 2 * fit.n_params


def test_criteria_tie_is_the_change_of_a_relative_chi2_change_of_the_solvers_tolerance():
    """Hand numbers: n = 100 real values, so AICs tie within 100 × 1e-6 = 1e-4 (n ln χ²);
    under sigma weighting within χ² × 1e-6."""
    assert TIE_CHI2_REL == 1e-6
    assert criteria_tie(-666.40610429392, -666.4061042939194, UNKNOWN_VARIANCE, 0.0338, 100)  # (BioLogic's 5.7e-13)
    assert criteria_tie(-10.0, -10.0 + 0.9e-4, UNKNOWN_VARIANCE, 1.0, 100)
    assert not criteria_tie(-10.0, -10.0 + 1.1e-4, UNKNOWN_VARIANCE, 1.0, 100)
    assert criteria_tie(250.0, 250.0 + 2.4e-4, KNOWN_SIGMA, 250.0, 100) and not criteria_tie(250.0, 250.0 + 2.6e-4, KNOWN_SIGMA, 250.0, 100)


@pytest.fixture(scope="module")
def biologic_fits():
    """REAL: BioLogic's file, where the two writings of the ZARC reach AICs 5.7e-13 apart and
    W1.sigma runs to its bound (the walkthrough's case)."""
    data = ix.load(REAL / "exampleDataBioLogic.mpt")
    return {m: ix.fit(m, data) for m in (ZARC, CC, WITH_W)}


@pytest.mark.slow  # (the fixture: three fits compiled, ~12 s)
@pytest.mark.parametrize("order", [(ZARC, CC, WITH_W), (CC, ZARC, WITH_W)])
def test_a_tie_goes_to_the_model_given_first_and_the_reduction_is_still_said(biologic_fits, order):
    c = ix.compare([biologic_fits[m] for m in order])
    first, second = order[0], order[1]
    a, b = aic_by_hand(biologic_fits[first]), aic_by_hand(biologic_fits[second])
    assert abs(a - b) < 1e-6 * 2 * biologic_fits[first].n_points  # (the case: one optimum, to the solver's tolerance)
    assert c.best == first and c.summary()["best"] == first  # (before: the lower AIC by rounding, CC for either order)
    assert c.summary()["tied_with_best"] == [second] and c.tied_with_best_indices() == [1]
    reduced = c.reduces_to_best()  # (before: None when CC won)
    assert reduced is not None and reduced["rivals"] == [WITH_W] and reduced["reduces_to"] == [ZARC] and reduced["best"] == first
    assert aic_by_hand(biologic_fits[WITH_W]) - aic_by_hand(biologic_fits[ZARC]) == pytest.approx(2, abs=0.01)
    expected_to = ZARC if first == ZARC else f"{ZARC} (tied with the best, {CC})"
    assert reduced["note"].startswith(f"{WITH_W} reduces to {expected_to}: ") and reduced["note"] in c.table().splitlines()
    assert c.weak_evidence() is None  # (the tied fit is the best's own, the W1 model reduces to it)
    doc = json.loads(json.dumps(to_jsonable(c.summary()), allow_nan=False))
    assert doc["reduces_to_best"]["rivals"] == [WITH_W] and doc["tied_with_best"] == [second]
    fig = c.plot()
    assert fig._suptitle.get_text() == f"model comparison — best by AIC: {first} (tied with {second}) (modulus weighting)"  # (the weighting named since 2026-12-06)


@pytest.mark.slow
def test_float_noise_either_way_leaves_the_best_and_the_fewer_parameters_win_a_tie(biologic_fits):
    """The AICs nudged by ±1e-9 (far below the tolerance 1e-6 n): the same best; a 5-parameter
    model given the best's AIC exactly loses the tie to the 4-parameter one even listed first."""
    c = ix.compare([biologic_fits[m] for m in (ZARC, CC, WITH_W)])
    for nudge in (1e-9, -1e-9):
        rows = [{**c.rows[0]}, {**c.rows[1], "aic": c.rows[0]["aic"] + nudge}, c.rows[2]]
        assert dataclasses.replace(c, rows=tuple(rows)).best_index == 0
    rows = [{**c.rows[2], "aic": c.rows[1]["aic"]}, c.rows[1], c.rows[0]]
    swapped = dataclasses.replace(c, rows=tuple(rows), fits=(c.fits[2], c.fits[1], c.fits[0]))
    assert swapped.best_index == 1 and swapped.tied_with_best_indices() == [0, 2]
    assert "with the same AIC as" not in c.table()  # (the BioLogic tie is the same fit, which the mark names)
    assert "tied with R0 + CC1: the same fit" in c.table()
