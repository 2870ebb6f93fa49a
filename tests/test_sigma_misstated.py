"""A stated σ that misstates the noise is said to, not blamed on the model; the KK test weighs and
judges by the data's σ (2026-12-02). All spectra are SYNTHETIC: R_s + R_p ∥ CPE_p written out in
numpy, complex Gaussian noise 3 % of |Z| below 10 Hz and 0.3 % above, fixed seeds (a user's
electroadhesive-pad walkthrough)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting.least_squares.result import MODEL_MISFIT_MARKS

F = np.logspace(0, 5, 51)  # 1 Hz – 100 kHz
W = 2 * np.pi * F
MODEL = "R_s + R_p || CPE_p"
LOW_BAND = F < 10.0


def pad(r_p=5e6):
    """R_s + R_p ∥ CPE_p: 2 kΩ, R_p, Q = 2 nF s^(α−1), α = 0.92."""
    return 2e3 + 1.0 / (1.0 / r_p + 2e-9 * (1j * W) ** 0.92)


def noisy(z0, seed):
    """SYNTHETIC: z0 plus complex noise of σ = 3 % |z0| below 10 Hz, 0.3 % above (σ of Re and of Im); (Z, σ)."""
    sigma = np.where(LOW_BAND, 0.03, 0.003) * np.abs(z0)
    rng = np.random.default_rng(seed)
    return z0 + sigma * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)), sigma


def chi2_red(fit, z, sigma):
    """Σ (ΔRe² + ΔIm²)/σ² / (2N − P), written out from the fitted R_s + R_p ∥ CPE_p or R_s + R_p ∥ C_p."""
    v = fit.values
    if "CPE_p.Q" in v:
        model = v["R_s"] + 1.0 / (1.0 / v["R_p"] + v["CPE_p.Q"] * (1j * W) ** v["CPE_p.alpha"])
    else:
        model = v["R_s"] + 1.0 / (1.0 / v["R_p"] + 1j * W * v["C_p"])
    dz = model - z
    return float(np.sum((dz.real**2 + dz.imag**2) / sigma**2) / (2 * F.size - len(v)))


def blames_model(warnings):
    return any(mark in w for w in warnings for mark in MODEL_MISFIT_MARKS)


@pytest.fixture(scope="module")
def spectrum():
    return noisy(pad(), seed=2)


def test_right_sigma_gets_no_sigma_warning_and_no_model_blame(spectrum):
    z, sigma = spectrum
    fit = ix.fit(MODEL, ix.make_spectrum(F, z, sigma=sigma), weighting="sigma")
    assert 0.62 < chi2_red(fit, z, sigma) < 1.5  # (the χ²_ν/ν range of 98 degrees of freedom, 99.8 %)
    assert not blames_model(fit.warnings), fit.warnings
    assert not any("sigma" in w or "σ" in w for w in fit.warnings), fit.warnings


def test_swapped_sigma_is_said_to_misstate_the_noise_not_blamed_on_the_model(spectrum):
    z, _ = spectrum
    swapped = np.where(LOW_BAND, 0.003, 0.03) * np.abs(z)  # (the two bands' σ swapped by mistake)
    fit = ix.fit(MODEL, ix.make_spectrum(F, z, sigma=swapped), weighting="sigma")
    assert chi2_red(fit, z, swapped) > 10  # (the walkthrough's 23: residuals ~10× σ below 10 Hz)
    assert not blames_model(fit.warnings), fit.warnings
    (scale,) = [w for w in fit.warnings if "σ misstates the noise" in w]
    assert "Kramers–Kronig-consistent model weighted by the same σ" in scale
    # the uneven-residual note names the low band, where σ understates the noise
    (uneven,) = [w for w in fit.warnings if "weighted residuals are over 4× larger" in w]
    assert "understates the noise at 1 Hz" in uneven


def test_right_sigma_and_a_missing_element_blame_the_model(spectrum):
    z, sigma = spectrum
    fit = ix.fit("R_s + R_p || C_p", ix.make_spectrum(F, z, sigma=sigma), weighting="sigma")  # (C for the CPE of α = 0.92)
    assert chi2_red(fit, z, sigma) > 100
    assert blames_model(fit.warnings), fit.warnings
    assert not any("σ misstates the noise" in w for w in fit.warnings)


def test_the_chain_is_weighted_by_sigma():
    """Z_kk of a fixed chain (n_rc = 10, series R, L and 1/C) equals the weighted least squares
    solved here in numpy: rows Re/σ and Im/σ, τ log-spaced over 1/ω_max … 1/ω_min (Schönleber eq 12)."""
    z, sigma = noisy(pad(), seed=5)
    result = ix.kk_test(ix.make_spectrum(F, z, sigma=sigma), n_rc=10)
    tau = np.geomspace(1 / W.max(), 1 / W.min(), 10)
    design = np.column_stack([np.ones(F.size), 1j * W, -1j / W, 1 / (1 + 1j * W[:, None] * tau)])
    rows = np.vstack([design.real / sigma[:, None], design.imag / sigma[:, None]])
    coef, *_ = np.linalg.lstsq(rows, np.concatenate([z.real / sigma, z.imag / sigma]), rcond=None)
    expected = design @ coef
    assert np.max(np.abs(result.kk_impedance - expected) / np.abs(z)) < 1e-6  # (the two solvers' rounding: 3e-7)
    assert result.noise_from == "sigma"
    modulus = ix.kk_test((F, z), n_rc=10)  # (no σ: weighted by 1/|Z|, as before, and another chain)
    assert modulus.noise_from == "residuals" and np.max(np.abs(modulus.kk_impedance - expected) / np.abs(z)) > 1e-3


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_kk_with_sigma_passes_causal_data_of_uneven_noise(seed):
    z, sigma = noisy(pad(), seed)
    data = ix.make_spectrum(F, z, sigma=sigma)
    by_sigma = ix.kk_test(data)
    assert by_sigma.valid and by_sigma.noise_from == "sigma", by_sigma.report()
    # each point's scale is its σ/|Z| (floored at 0.2 %), written out
    np.testing.assert_allclose(by_sigma.point_scale, np.maximum(sigma / np.abs(z), 0.002))
    by_residuals = ix.kk_test(data, noise="residuals")  # (the one global estimate: the noisy band reads as bad)
    assert not by_residuals.valid and by_residuals.noise_from == "residuals"
    # the scales travel with the exports (added 2026-12-02): per point by σ, one value by the residuals
    np.testing.assert_allclose(by_sigma.to_xarray()["point_scale"].values, np.maximum(sigma / np.abs(z), 0.002))
    assert np.all(by_residuals.to_xarray()["point_scale"].values == by_residuals.threshold_scale)


def test_kk_with_sigma_still_flags_a_drift():
    """R_p grows 20 % in time during a sweep from 100 kHz down to 1 Hz: not stationary."""
    elapsed = np.empty(F.size)
    elapsed[np.argsort(F)[::-1]] = np.linspace(0.0, 1.0, F.size)
    z, sigma = noisy(pad(r_p=5e6 * (1 + 0.2 * elapsed)), seed=3)
    result = ix.kk_test(ix.make_spectrum(F, z, sigma=sigma))
    assert result.noise_from == "sigma" and not result.valid
    lo, hi = min(b[0] for b in result.bad_bands), max(b[1] for b in result.bad_bands)
    assert lo < 100 and hi > 10, result.bad_bands  # (where R_p shows: below the arc's ~16 Hz corner and around it)


def test_cli_kk_says_which_noise_it_used(tmp_path, capsys):
    z, sigma = noisy(pad(), seed=1)
    path = tmp_path / "pad.nc"
    ix.save(ix.make_spectrum(F, z, sigma=sigma), path)
    assert main(["kk", str(path), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["valid"] and summary["noise_from"] == "sigma"
    assert main(["kk", str(path), "--json", "--noise", "residuals"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert not summary["valid"] and summary["noise_from"] == "residuals"
    assert main(["kk", str(path)]) == 0
    assert "noise: the data's sigma" in capsys.readouterr().out
    plain = tmp_path / "plain.nc"
    ix.save(ix.make_spectrum(F, z), plain)
    assert main(["kk", str(plain), "--noise", "sigma"]) == 2
    assert "needs a 'sigma' variable" in capsys.readouterr().err
