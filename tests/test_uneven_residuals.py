"""The warning that a fit's weighted residuals are uneven across the band (`result.uneven_residual_notes`):
an audit's SYNTHETIC R0 + R1 ∥ CPE1 with noise 5× larger below 1 Hz got wrong standard errors and
no warning under the modulus weighting."""

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.least_squares.result import UNEVEN_RESIDUAL_RATIO, residual_band_rms, uneven_residual_notes

FREQ = np.logspace(-2, 5, 50)
MARK = "weighted residuals are over"


def z_r_cpe(f, r0=50.0, r1=1000.0, q=1e-5, alpha=0.85):
    """R0 + R1 ∥ CPE1 (Z_CPE = 1/(Q (jω)^α)), written here as the oracle."""
    return r0 + 1.0 / (1.0 / r1 + q * (2j * np.pi * f) ** alpha)


def noisy(z, relative, rng):
    """SYNTHETIC complex Gaussian noise of σ = relative·|Z| on Re and on Im."""
    return z + relative * np.abs(z) * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape))


def uneven_warnings(warnings):
    return [w for w in warnings if MARK in w]


def test_band_rms_is_the_rms_of_each_block_of_eight_points():
    rng = np.random.default_rng(0)
    f = np.logspace(0, 3, 20)[::-1]  # (descending: bands follow ascending frequency)
    z = z_r_cpe(f)
    z_model = noisy(z, 0.01, rng)
    rms, lo, hi = residual_band_rms(f, z, z_model, 1 / np.abs(z), 1 / np.abs(z))
    up = np.argsort(f)
    r = ((z_model - z) / np.abs(z))[up]
    blocks = [r[0:8], r[8:20]]  # 20 points: 8, then the last 4 join the second band
    expected = [np.sqrt(np.mean(np.concatenate([b.real, b.imag]) ** 2)) for b in blocks]
    np.testing.assert_allclose(rms[0], expected, rtol=1e-12)
    np.testing.assert_allclose(lo, [f[up][0], f[up][8]])
    np.testing.assert_allclose(hi, [f[up][7], f[up][19]])


def test_notes_rule_by_hand():
    """Band rms 1, 1, 5 (×1e-3) is over 4×; 1, 1, 3 is not; a model-blaming misfit note suppresses it."""
    f = np.logspace(0, 3, 24)
    z = np.full(24, 100.0 + 0j)
    scale = np.repeat([1e-3, 1e-3, 5e-3], 8)
    z_model = z + 100.0 * scale * (1 + 1j)  # |ΔRe|/|Z| = |ΔIm|/|Z| = scale: each band's rms is its scale
    w = 1 / np.abs(z)
    (note,) = uneven_residual_notes(f, z, z_model, w, w, "modulus")[0]
    assert f"over {UNEVEN_RESIDUAL_RATIO:g}× larger" in note and "impedax fit --weighting sigma" in note
    even = z + 100.0 * np.repeat([1e-3, 1e-3, 3e-3], 8) * (1 + 1j)
    assert uneven_residual_notes(f, z, even, w, w, "modulus") == [()]
    assert uneven_residual_notes(f, z, z_model, w, w, "modulus", [("the model misses structure the data hold: ...",)]) == [()]
    assert uneven_residual_notes(f, z, z_model, w, w, "unit") == [()]  # (not a noise model)


def test_uneven_noise_warns_single_and_batch_alike():
    """SYNTHETIC: the audit's case, 0.2 % noise, 5× larger below 1 Hz, and one spectrum with uniform noise."""
    rng = np.random.default_rng(11)
    zt = z_r_cpe(FREQ)
    uneven = noisy(zt, 0.002 * np.where(FREQ < 1, 5.0, 1.0), rng)
    z = np.stack([uneven, noisy(zt, 0.002, rng)])
    # the oracle: rms of (ΔRe, ΔIm)/|Z| per block of 8 points of the true model, max over min
    r = (z - zt) / np.abs(zt)
    band = [np.sqrt(np.mean(np.concatenate([r[:, a:b].real, r[:, a:b].imag], axis=-1) ** 2, axis=-1)) for a, b in [(0, 8), (8, 16), (16, 24), (24, 32), (32, 40), (40, 50)]]
    ratio = np.max(band, axis=0) / np.min(band, axis=0)
    assert ratio[0] > 5 and np.all(ratio[1:] < 3)
    batch = ix.fit("R0 + R1 || CPE1", ix.make_spectrum(FREQ, z, dims=("problem",), coords={"problem": [0, 1]}))
    singles = [ix.fit("R0 + R1 || CPE1", ix.make_spectrum(FREQ, row)) for row in z]
    for i, single in enumerate(singles):
        assert batch.fit_of(problem=i).warnings == single.warnings
    (note,) = uneven_warnings(singles[0].warnings)
    loud, quiet = note.split(" than at ")[0].split(" (rms) at ")[1], note.split(" than at ")[1].split(":")[0]
    assert loud.split(" – ")[0].endswith("mHz") and not quiet.split(" – ")[0].endswith("mHz")  # (the loud band starts below 1 Hz, the quiet one above)
    assert "(modulus weighting)" in note
    assert not uneven_warnings(singles[1].warnings)


def test_the_true_sigma_evens_the_residuals():
    """SYNTHETIC: the audit's uneven case, its true σ given and weighted by: no warning."""
    rng = np.random.default_rng(11)
    zt = z_r_cpe(FREQ)
    sigma = 0.002 * np.where(FREQ < 1, 5.0, 1.0) * np.abs(zt)
    uneven = zt + sigma * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size))
    assert uneven_warnings(ix.fit("R0 + R1 || CPE1", ix.make_spectrum(FREQ, uneven)).warnings)
    assert not uneven_warnings(ix.fit("R0 + R1 || CPE1", ix.make_spectrum(FREQ, uneven, sigma=sigma), weighting="sigma").warnings)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_uniform_noise_never_warns(seed):
    """SYNTHETIC: the right model, uniform relative noise 0.2–2 %, eight spectra a seed."""
    rng = np.random.default_rng(seed)
    zt = np.stack([z_r_cpe(FREQ, 50 * rng.uniform(0.5, 2), 1000 * rng.uniform(0.5, 2), 1e-5 * rng.uniform(0.5, 2), rng.uniform(0.75, 0.95)) for _ in range(8)])
    z = noisy(zt, np.exp(rng.uniform(np.log(0.002), np.log(0.02), (8, 1))), rng)
    batch = ix.fit("R0 + R1 || CPE1", ix.make_spectrum(FREQ, z, dims=("problem",), coords={"problem": np.arange(8)}))
    assert not [w for ws in batch.warnings.values() for w in uneven_warnings(ws)]


def test_gross_misfit_is_left_to_the_misfit_note():
    """SYNTHETIC two arcs fitted with one: the model's misfit note, not the noise note."""
    rng = np.random.default_rng(5)
    zt = z_r_cpe(FREQ, 20.0, 300.0, 1e-6, 0.9) + z_r_cpe(FREQ, 0.0, 2000.0, 1e-3, 0.8)
    result = ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, noisy(zt, 0.002, rng)))
    assert any("the model misses structure" in w for w in result.warnings)
    assert not uneven_warnings(result.warnings)


def test_the_advice_to_give_sigma_reads_the_same_in_the_text_and_the_json(capsys):
    """REAL Parstat file, R0 + R1 ∥ CPE1: the residuals are over 4× larger at 398 Hz – 10 kHz than at
    10 – 50 Hz. The report told a command-line user to give "a 'sigma' variable of a netCDF file",
    its JSON "make_spectrum(sigma=...)" (2026-12-06); now both give the file's and Python's ways."""
    import json
    from pathlib import Path

    from impedax.cli import main

    argv = ["fit", str(Path(__file__).parent / "fixtures" / "real" / "exampleDataParstat.txt"), "--model", "R0 + R1 || CPE1"]
    assert main([*argv, "--json"]) == 0
    in_json = uneven_warnings(json.loads(capsys.readouterr().out)["warnings"])
    assert main(argv) == 0
    in_text = [line.removeprefix("warning: ") for line in capsys.readouterr().out.splitlines() if MARK in line]
    assert len(in_json) == 1 and in_text == in_json, (in_text, in_json)
    assert "sigma column" in in_json[0] and "make_spectrum(sigma=...)" in in_json[0]
