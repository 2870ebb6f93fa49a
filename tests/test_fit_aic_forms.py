"""A fit weighted by sigma states its AIC's form and gives the known-noise AIC that compare ranks by."""

import json
import math

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main


@pytest.fixture(scope="module")
def spectrum():
    # SYNTHETIC R0 + R1 || CPE1 (numpy formula), noise 1 % of |Z| stated as sigma
    f = np.logspace(5, -1, 40)
    z = 50.0 + 1.0 / (1.0 / 1000.0 + 1e-5 * (2j * np.pi * f) ** 0.85)
    sigma = 0.01 * np.abs(z)
    rng = np.random.default_rng(7)
    z = z + sigma * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
    return ix.make_spectrum(f, z, sigma=sigma)


def test_known_noise_criteria_are_chi2_plus_2k_of_the_weighted_residuals(spectrum):
    fit = ix.fit("R0 + R1 || CPE1", spectrum, weighting="sigma")
    dz = (fit.z_model - spectrum["Z"].values) / spectrum["sigma"].values
    chi2 = float(np.sum(dz.real**2 + dz.imag**2))
    aic, bic = fit.known_noise_criteria
    assert aic == pytest.approx(chi2 + 2 * 4, rel=1e-9)
    assert bic == pytest.approx(chi2 + 4 * math.log(2 * 40), rel=1e-9)
    assert fit.aic == pytest.approx(80 * math.log(chi2 / 80) + 8, rel=1e-9)
    assert ix.fit("R0 + R1 || CPE1", spectrum).known_noise_criteria is None  # (modulus weighting: one form)


def test_fit_and_compare_give_one_known_noise_aic(spectrum, tmp_path, capsys):
    path = tmp_path / "s.nc"
    ix.save(spectrum, path)
    assert main(["fit", str(path), "--model", "R0 + R1 || CPE1", "--weighting", "sigma", "--json"]) == 0
    fitted = json.loads(capsys.readouterr().out)
    assert main(["compare", str(path), "--model", "R0 + R1 || CPE1", "--model", "R0 + R1 || C1", "--weighting", "sigma", "--json"]) == 0
    compared = json.loads(capsys.readouterr().out)
    row = next(r for r in compared["models"] if r["model"] == "R0 + R1 || CPE1")
    assert compared["aic_form"] == row["aic_form"] == fitted["known_noise_form"] == "chi2 + 2k"  # (a model's entry: its aic is the comparison's)
    assert fitted["aic_form"] == "n ln(chi2/n) + 2k"
    assert row["aic"] == pytest.approx(fitted["aic_known_noise"], rel=1e-6)
    assert row["bic"] == pytest.approx(fitted["bic_known_noise"], rel=1e-6)
    assert abs(fitted["aic"] - fitted["aic_known_noise"]) > 10  # (the two forms differ here: 0.5 < χ²_red but n ln(χ²/n) ≠ χ²)


def test_the_report_names_both_forms_under_sigma_weighting_only(spectrum):
    fit = ix.fit("R0 + R1 || CPE1", spectrum, weighting="sigma")
    line = next(l for l in fit.report().splitlines() if l.startswith("rms_rel"))
    assert "n ln(χ²/n) + 2k" in line and f"AIC {fit.known_noise_criteria[0]:.2f}" in line and "impedax compare" in line
    plain = ix.fit("R0 + R1 || CPE1", spectrum).report()
    assert "known noise" not in plain
