"""`impedax.compare`'s information criteria against closed forms computed here with numpy.

Oracles: χ² from the circuit's impedance written here (R0 + R1 ∥ C1, R0 + R1 ∥ CPE1) at the
fitted values, then AIC, AICc, BIC and Akaike weights by their formulas:
AIC = n ln(χ²/n) + 2k (unknown variance) or χ² + 2k (``weighting="sigma"``: known noise),
AICc = AIC + 2k(k + 1)/(n − k − 1), BIC = … + k ln n, w_i = exp(−Δ_i/2)/Σ exp(−Δ_j/2),
n = 2N real data values.
"""

import json
import math
import re

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.io.export import to_jsonable

MODELS = ("R0 + R1 || C1", "R0 + R1 || CPE1")


def z_of(model, v, f):
    jw = 2j * np.pi * np.asarray(f)
    y = v["C1"] * jw if model == MODELS[0] else v["CPE1.Q"] * jw ** v["CPE1.alpha"]
    return v["R0"] + 1 / (1 / v["R1"] + y)


def chi2_of(fit, model, sigma=None):
    """Σ of the squared weighted real and imaginary residuals: by |Z_data| (modulus) or σ."""
    z = fit.z_data
    r = (z_of(model, fit.values, fit.frequency) - z) / (np.abs(z) if sigma is None else sigma)
    return float(np.sum(r.real**2 + r.imag**2))


def weights(x):
    x = np.asarray(x, float)
    w = np.exp(-(x - x.min()) / 2)
    return w / w.sum()


def spectrum(n_freq=40, alpha=0.9, noise=0.01, seed=1, sigma=None, fmax=1e5):
    f = np.geomspace(1.0, fmax, n_freq)
    z0 = 10 + 1 / (1 / 100 + 1e-5 * (2j * np.pi * f) ** alpha)
    rng = np.random.default_rng(seed)
    z = z0 * (1 + noise * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2))
    return ix.make_spectrum(f, z, sigma=None if sigma is None else sigma * np.abs(z0))


def test_aic_aicc_bic_and_weights_by_hand_under_modulus_weighting():
    data = spectrum()
    c = ix.compare([ix.fit(m, data) for m in MODELS])
    n = 2 * 40
    expected = []
    for model, row in zip(MODELS, c.rows):
        k = row["n_params"]
        chi2 = chi2_of(c.fits[MODELS.index(model)], model)
        assert row["chi2"] == pytest.approx(chi2, rel=1e-9)
        aic = n * math.log(chi2 / n) + 2 * k
        expected.append((aic, aic + 2 * k * (k + 1) / (n - k - 1), n * math.log(chi2 / n) + k * math.log(n)))
        assert row["aic"] == pytest.approx(aic, abs=1e-6) and row["aic"] == pytest.approx(c.fits[MODELS.index(model)].aic, abs=1e-9)
    aic, aicc, bic = (np.array(x) for x in zip(*expected))
    assert [r["aicc"] for r in c.rows] == pytest.approx(aicc, abs=1e-6)
    assert [r["bic"] for r in c.rows] == pytest.approx(bic, abs=1e-6)
    assert [r["akaike_weight"] for r in c.rows] == pytest.approx(weights(aic), abs=1e-9)
    assert [r["akaike_weight_aicc"] for r in c.rows] == pytest.approx(weights(aicc), abs=1e-9)
    assert [r["delta_aicc"] for r in c.rows] == pytest.approx(aicc - aicc.min(), abs=1e-6)
    assert c.aic_form == "n ln(chi2/n) + 2k" and c.summary()["aic_form"] == c.aic_form
    assert c.summary()["ranked_by"] == "aic" and c.summary()["best_aicc"] == MODELS[int(np.argmin(aicc))]
    head = c.table().splitlines()[0].split()
    assert head[head.index("AIC") + 1] == "AICc"
    assert f"{aicc[1]:.2f}" in c.table().splitlines()[2]


def test_sigma_weighting_takes_the_sigma_as_the_known_noise():
    """AIC = χ² + 2k with χ² = Σ (ΔRe/σ)² + (ΔIm/σ)²: −2 ln L of Gaussian noise of known σ."""
    data = spectrum(sigma=0.01 / np.sqrt(2))  # (the noise above: 1 %/√2 per part)
    c = ix.compare([ix.fit(m, data, weighting="sigma") for m in MODELS])
    n, sigma = 80, data["sigma"].values
    aics = []
    for model, row, fit in zip(MODELS, c.rows, c.fits):
        k = row["n_params"]
        chi2 = chi2_of(fit, model, sigma)
        assert row["chi2"] == pytest.approx(chi2, rel=1e-9)
        assert row["aic"] == pytest.approx(chi2 + 2 * k, rel=1e-9)
        assert row["bic"] == pytest.approx(chi2 + k * math.log(n), rel=1e-9)
        assert row["aicc"] == pytest.approx(chi2 + 2 * k + 2 * k * (k + 1) / (n - k - 1), rel=1e-9)
        # (the unknown-variance form stays the fit's own AIC: not the comparison's here)
        assert fit.aic == pytest.approx(n * math.log(chi2 / n) + 2 * k, abs=1e-6) and abs(fit.aic - row["aic"]) > 1
        aics.append(chi2 + 2 * k)
    assert [r["akaike_weight"] for r in c.rows] == pytest.approx(weights(aics), abs=1e-9)
    assert c.aic_form == "chi2 + 2k"
    table = c.table()
    assert "AIC = χ² + 2k and BIC = χ² + k ln n: the data's sigma taken as the known noise" in table
    assert min(r["chi2_red"] for r in c.rows) == pytest.approx(1.0, abs=0.5) and "the sigma understate" not in table


def test_sigma_ten_times_too_small_is_said():
    data = spectrum(sigma=0.001 / np.sqrt(2))
    c = ix.compare([ix.fit(m, data, weighting="sigma") for m in MODELS])
    lowest = min(r["chi2_red"] for r in c.rows)
    assert lowest > 50  # (≈ 100: the noise is 10× the sigma)
    assert f"the lowest reduced χ² is {lowest:.3g}: the sigma understate the scatter about every model" in c.table()


def test_aicc_undefined_when_n_minus_k_minus_1_is_not_positive():
    """Two frequencies: n = 4 real values; R0 + R1 ∥ C1 has k = 3, n − k − 1 = 0."""
    f = np.array([10.0, 1000.0])
    data = ix.make_spectrum(f, (10 + 1 / (1 / 100 + 2j * np.pi * f * 1e-5)) * np.array([1.01, 0.99 - 0.01j]))
    c = ix.compare([ix.fit(m, data) for m in ("R1", "R0 + C1", "R0 + R1 || C1")])
    rows = {r["model"]: r for r in c.rows}
    assert math.isnan(rows["R0 + R1 || C1"]["aicc"]) and math.isnan(rows["R0 + R1 || C1"]["akaike_weight_aicc"])
    # the others: AIC + 2k(k+1)/(n−k−1), weights among them only
    expected = {m: rows[m]["aic"] + 2 * k * (k + 1) / (4 - k - 1) for m, k in (("R1", 1), ("R0 + C1", 2))}
    assert {m: rows[m]["aicc"] for m in expected} == pytest.approx(expected, abs=1e-9)
    w = weights(list(expected.values()))
    assert [rows[m]["akaike_weight_aicc"] for m in expected] == pytest.approx(w, abs=1e-12)
    table = c.table()
    assert "AICc is undefined for R0 + R1 || C1: n − k − 1 = 0 with n = 4 real data values and k = 3" in table
    assert next(line for line in table.splitlines() if line.startswith("R0 + R1 || C1")).split()[10] == "—"
    assert not re.search(r"(?<!-> )\binf\b", table), table  # (no number printed as inf; an F-test's "R1 -> inf" names a limit)
    doc = json.loads(json.dumps(to_jsonable(c.summary()), allow_nan=False))
    assert next(m for m in doc["models"] if m["model"] == "R0 + R1 || C1")["aicc"] is None


def test_the_table_says_when_aicc_ranks_another_model_first():
    """Five frequencies (n = 10): the CPE's α (0.97 in the data, 2 % noise) lowers AIC by 1.8
    but costs 2·4·5/5 − 2·3·4/6 = 4 more in AICc's correction."""
    data = spectrum(n_freq=5, alpha=0.97, noise=0.02, seed=18, fmax=1e4)
    c = ix.compare([ix.fit(m, data) for m in MODELS])
    aic = np.array([r["aic"] for r in c.rows])
    aicc = aic + np.array([2 * 3 * 4 / 6, 2 * 4 * 5 / 5])
    assert [r["aicc"] for r in c.rows] == pytest.approx(aicc, abs=1e-9)
    assert np.argmin(aic) == 1 and np.argmin(aicc) == 0  # (the case: the two disagree)
    assert c.best == MODELS[1] and c.summary()["best_aicc"] == MODELS[0]
    w = weights(aicc)[0]
    assert f"by AICc (small-sample correction) the best is {MODELS[0]} (AICc weight {w:.3f}); the ranking above is by AIC" in c.table()


def test_compare_json_keeps_its_keys_and_adds_the_new_ones(tmp_path, capsys):
    path = tmp_path / "arc.csv"
    ix.save(spectrum(), path)
    assert main(["compare", str(path), "--model", MODELS[0], "--model", MODELS[1], "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert {"models", "best", "best_determined", "f_tests"} <= set(doc) and {"ranked_by", "aic_form", "best_aicc"} <= set(doc)
    old = {"model", "n_points", "n_params", "params", "rms_rel", "chi2", "chi2_red", "aic", "bic", "converged", "message", "at_bound", "warnings",
           "weighting", "n_evaluations", "delta_aic", "akaike_weight"}
    for m in doc["models"]:
        assert old <= set(m) and {"aicc", "delta_aicc", "akaike_weight_aicc"} <= set(m)
    assert sum(m["akaike_weight_aicc"] for m in doc["models"]) == pytest.approx(1.0)
