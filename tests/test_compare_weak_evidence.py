"""`impedax.compare` says when the data barely tell the best model from another (ΔAIC below
`WEAK_DELTA_AIC`, or BIC picking another), names the models whose scatter the sigma overstate
under ``weighting="sigma"`` when others' they do not, and prints rms_rel to three significant digits.

Oracles: SYNTHETIC R0 + R1 ∥ CPE1 spectra (`test_compare_criteria.spectrum`), χ² from the
circuit's impedance written there with numpy, AIC = n ln(χ²/n) + 2k, BIC = n ln(χ²/n) + k ln n.
"""

import dataclasses
import json
import math
import re

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.comparison import SIGMA_CHI2_RED_RANGE, WEAK_DELTA_AIC, significant
from impedax.io.export import to_jsonable
from test_compare_criteria import MODELS, chi2_of, spectrum


def by_hand(c):
    """(AIC, BIC) of each row from χ² computed here (n = 80 real values)."""
    n = 80
    out = []
    for row, fit in zip(c.rows, c.fits):
        chi2, k = chi2_of(fit, row["model"]), row["n_params"]
        out.append((n * math.log(chi2 / n) + 2 * k, n * math.log(chi2 / n) + k * math.log(n)))
    return out


def test_a_weak_lead_and_bic_picking_the_other_model_are_said():
    """α = 0.997: the CPE's lead is ΔAIC ≈ 1 and BIC (ln 80 = 4.4 per parameter) takes the capacitor."""
    c = ix.compare([ix.fit(m, spectrum(alpha=0.997, seed=3)) for m in MODELS])
    (aic_rc, bic_rc), (aic_cpe, bic_cpe) = by_hand(c)
    assert aic_cpe < aic_rc and bic_rc < bic_cpe  # (the case: AIC and BIC disagree)
    assert aic_rc - aic_cpe < WEAK_DELTA_AIC
    weak = c.weak_evidence()
    assert weak["best"] == MODELS[1] and weak["rival"] == MODELS[0] and weak["bic_prefers"] == MODELS[0]
    assert weak["delta_aic"] == pytest.approx(aic_rc - aic_cpe, abs=1e-6) and weak["threshold"] == WEAK_DELTA_AIC
    assert weak["log_evidence_prefers"] is None
    line = f"the data barely tell {MODELS[1]} from {MODELS[0]}: ΔAIC {aic_rc - aic_cpe:.2f} < {WEAK_DELTA_AIC:g} and BIC prefers {MODELS[0]}"
    assert line in c.table().splitlines() and line in c.report()
    doc = json.loads(json.dumps(to_jsonable(c.summary()), allow_nan=False))
    assert doc["weak_evidence"]["rival"] == MODELS[0] and doc["best"] == MODELS[1]  # (added; the old keys stay)


def test_a_clear_lead_adds_nothing():
    c = ix.compare([ix.fit(m, spectrum(alpha=0.9, seed=1)) for m in MODELS])
    (aic_rc, bic_rc), (aic_cpe, bic_cpe) = by_hand(c)
    assert aic_rc - aic_cpe > WEAK_DELTA_AIC and bic_cpe < bic_rc
    assert c.weak_evidence() is None and c.summary()["weak_evidence"] is None
    assert "barely" not in c.report()


def test_the_log_evidence_picking_another_model_is_said_when_every_one_is_reliable():
    """Rows given log evidence (as posteriors give them) that prefers the model AIC puts far
    behind: said as the log evidence's pick; not when one of them is unreliable."""
    c = ix.compare([ix.fit(m, spectrum(alpha=0.9, seed=1)) for m in MODELS])
    rows = [{**c.rows[0], "log_evidence": -100.0, "log_evidence_reliable": True}, {**c.rows[1], "log_evidence": -120.0, "log_evidence_reliable": True}]
    weak = dataclasses.replace(c, rows=tuple(rows)).weak_evidence()
    assert weak["rival"] == weak["log_evidence_prefers"] == MODELS[0] and weak["bic_prefers"] is None
    assert weak["note"] == f"the data barely tell {MODELS[1]} from {MODELS[0]}: ΔAIC {c.rows[0]['delta_aic']:.2f}, but the log evidence prefers {MODELS[0]}"
    rows[1]["log_evidence_reliable"] = False
    assert dataclasses.replace(c, rows=tuple(rows)).weak_evidence() is None


def test_sigma_misdescribing_only_some_models_names_them():
    """σ twice the noise: the CPE (the true model) has reduced χ² ≈ 0.18, outside 0.5–2; the
    capacitor's misfit at α = 0.97 brings its own to ≈ 1.2, inside. Before, the table said the
    sigma overstate the scatter about every model."""
    data = spectrum(alpha=0.97, sigma=0.02 / np.sqrt(2))
    c = ix.compare([ix.fit(m, data, weighting="sigma") for m in MODELS])
    low, high = SIGMA_CHI2_RED_RANGE
    rc, cpe = (r["chi2_red"] for r in c.rows)
    n = 80
    assert cpe == pytest.approx(chi2_of(c.fits[1], MODELS[1], sigma=data["sigma"].values) / (n - 4), rel=1e-9)
    assert cpe < low and low <= rc <= high  # (the case)
    table = c.table()
    assert "every model" not in table
    assert f"the lowest reduced χ² is {cpe:.3g}: the sigma overstate the scatter about {MODELS[1]} {cpe:.3g}, not about the other models ({MODELS[0]} {rc:.3g}); these ΔAIC are about" in table


def test_rms_rel_keeps_its_significant_digits():
    assert [significant(x) for x in (1.0, 1.02, 0.931, 100.0, 123.4, 1e-5)] == ["1.00", "1.02", "0.931", "100", "123", "1.00e-05"]
    c = ix.compare([ix.fit(m, spectrum(alpha=0.9, seed=1)) for m in MODELS])
    lines = c.table().splitlines()[1 : 1 + len(c.rows)]
    points = set()
    for row, line in zip(c.rows, lines):  # (3 significant digits, trailing zeros kept)
        cell = re.search(r" (\S+) +% ", line)
        assert cell.group(1) == f"{row['rms_rel'] * 100:#.3g}".rstrip(".")
        points.add(cell.start(1) + (cell.group(1) + ".").index("."))
    assert len(points) == 1  # (and their decimal points line up, since 2026-12-07)


def test_a_rival_that_reduces_to_the_best_is_no_weak_evidence():
    """α = 1 (the capacitor true): CPE1.alpha runs to its bound 1, so the CPE model reduces to
    the capacitor (its F-test says so) and trails by ΔAIC = 2Δk = 2 with χ² no lower, the
    clearest lead AIC gives a smaller model. The table says it adds nothing, not "barely tell";
    the Akaike weights stay the standard ones, computed here by numpy."""
    c = ix.compare([ix.fit(m, spectrum(alpha=1.0, seed=2)) for m in MODELS])
    (aic_rc, _), (aic_cpe, _) = by_hand(c)
    test = c.f_tests[0]
    assert test["reason"] == "reduces_to_simple" or (test["valid"] and test["f"] <= 1)  # (the case)
    assert aic_cpe - aic_rc == pytest.approx(2, abs=0.02) and c.best_index == 0
    w = np.exp(-np.array([0.0, aic_cpe - aic_rc]) / 2)
    assert [r["akaike_weight"] for r in c.rows] == pytest.approx(w / w.sum(), abs=1e-4)
    assert c.weak_evidence() is None and "barely" not in c.report()
    reduced = c.reduces_to_best()
    assert reduced["best"] == MODELS[0] and reduced["rivals"] == [MODELS[1]]
    assert reduced["note"].startswith(f"{MODELS[1]} reduces to {MODELS[0]}: ") and f"the Akaike weight {c.rows[1]['akaike_weight']:.3f} is that penalty" in reduced["note"]
    assert reduced["note"] in c.table().splitlines()
    doc = json.loads(json.dumps(to_jsonable(c.summary()), allow_nan=False))
    assert doc["reduces_to_best"]["rivals"] == [MODELS[1]] and doc["weak_evidence"] is None


def test_a_clear_lead_has_no_reduction_line():
    c = ix.compare([ix.fit(m, spectrum(alpha=0.9, seed=1)) for m in MODELS])
    assert c.reduces_to_best() is None and c.summary()["reduces_to_best"] is None and "reduces to" not in c.table()
