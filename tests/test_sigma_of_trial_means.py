"""A fit weighted by the σ of a trial-mean remainder (`remaining_impedance`, `impedax remaining`)
says what that σ is: the standard error of means over trials that differ, which a fit of the mean
absorbs, so residuals far below it are expected. Until 2026-12-06 it read "σ overstates the noise
… the standard errors … are then 3.4× too large", where the trials' own spread says the opposite."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting.least_squares.result import SIGMA_OF_TRIAL_MEANS_WORDS, SIGMA_OVERSTATES_WORDS
from impedax.models.sirin import remaining_impedance

EDL = "R_EP || CPE_EP || C_gap"
N_TRIALS = 20
FREQ = np.geomspace(1.0, 1e6, 49)


def edl_impedance(f, r_ep, q, alpha, c_gap):
    """R_EP ∥ CPE_EP ∥ C_gap written out in numpy (the oracle, not impedax's compiler)."""
    jw = 2j * np.pi * f
    return 1.0 / (1.0 / r_ep + q * jw**alpha + jw * c_gap)


@pytest.fixture(scope="module")
def trials():
    """SYNTHETIC single contact: 20 touches whose gap differs (C_gap log-normal, sd of ln 7 %, about
    413 pF; R_EP 15 %, Q 8 %, as the Sirin example's trials), each with complex noise of 0.3 % of |Z|."""
    rng = np.random.default_rng(11)
    c_gap = 413e-12 * np.exp(0.07 * rng.standard_normal(N_TRIALS))
    r_ep = 1e8 * np.exp(0.15 * rng.standard_normal(N_TRIALS))
    q = 4e-9 * np.exp(0.08 * rng.standard_normal(N_TRIALS))
    z = np.stack([edl_impedance(FREQ, r, qq, 0.3, c) for r, qq, c in zip(r_ep, q, c_gap)])
    z = z + 0.003 * np.abs(z) * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape))
    total = ix.make_spectrum(FREQ, z, dims=("trial",), coords={"trial": np.arange(1, N_TRIALS + 1)})
    return total, c_gap


@pytest.mark.slow  # (5.4 s: two fits, the first compiling the circuit)
def test_a_fit_of_trial_means_says_what_its_sigma_is(trials):
    total, c_gap = trials
    remainder = remaining_impedance(total, None, None)
    fitted = ix.fit(EDL, remainder, weighting="sigma")
    assert fitted.chi2_red < 0.3  # (the trials' difference, in σ, is taken up by the fit of their mean)
    (note,) = [w for w in fitted.warnings if "× the data's sigma in rms" in w]
    assert SIGMA_OF_TRIAL_MEANS_WORDS in note and f"{N_TRIALS} total spectra" in note and "impedax remaining --trials" in note
    assert SIGMA_OVERSTATES_WORDS not in note and "too large" not in note
    # the oracle of why "too large" was wrong: the generated C_gap values' own standard error of
    # their mean exceeds the fit's standard error (numpy, from the drawn truth)
    assert np.std(c_gap, ddof=1) / np.sqrt(N_TRIALS) > 2 * fitted.stderr["C_gap"]
    # the same numbers with σ of unknown origin: the values and standard errors unchanged, the old warning kept
    plain = ix.fit(EDL, ix.make_spectrum(FREQ, remainder["Z"].values, sigma=remainder["sigma"].values), weighting="sigma")
    for name in fitted.values:
        assert fitted.values[name] == pytest.approx(plain.values[name], rel=1e-6)
        assert fitted.stderr[name] == pytest.approx(plain.stderr[name], rel=1e-6)
    assert any(SIGMA_OVERSTATES_WORDS in w for w in plain.warnings)


def test_impedax_fit_of_an_impedax_remaining_file_says_it_too(tmp_path, capsys, trials):
    total, _ = trials
    ix.save(total, tmp_path / "pad.nc")
    assert main(["remaining", str(tmp_path / "pad.nc"), "--out", str(tmp_path / "rem.nc"), "-q"]) == 0
    capsys.readouterr()
    assert main(["fit", str(tmp_path / "rem.nc"), "--model", EDL, "--weighting", "sigma", "--json", "-q"]) == 0
    warnings = json.loads(capsys.readouterr().out)["warnings"]
    assert any(SIGMA_OF_TRIAL_MEANS_WORDS in w for w in warnings)
    assert not any(SIGMA_OVERSTATES_WORDS in w for w in warnings)


def test_residuals_uneven_against_trial_means_sigma_name_it_not_a_sigma_column():
    """SYNTHETIC Sirin example of seed 4 (numpy formulas): the EDL fit of its trial-mean remainder
    leaves residuals over 4× larger against σ at 63 kHz–1 MHz than at 10–50 kHz; until 2026-12-06
    the note said to "check the sigma column there", a column no file held: σ is the trials' SEM."""
    from impedax.fitting.least_squares.result import SIGMA_BAND_WORDS
    from impedax.models.synthetic import example_spectra, generate_sirin_synthetic

    parts = example_spectra(generate_sirin_synthetic(seed=4))
    remainder = remaining_impedance(parts["total_sliding"], parts["skin"], parts["touchscreen"])
    fitted = ix.fit(EDL, remainder, weighting="sigma")
    (note,) = [w for w in fitted.warnings if "weighted residuals are over" in w]
    assert SIGMA_OF_TRIAL_MEANS_WORDS in note and "30 total, 30 skin, 30 touchscreen spectra" in note and "impedax remaining --trials" in note
    assert SIGMA_BAND_WORDS not in note and "check the sigma column" not in note


@pytest.mark.slow  # (8.6 s: a first fit of a two-arc model, compiling)
def test_the_note_reads_for_a_real_cells_cycles_too(tmp_path, capsys):
    """REAL AutoEIS battery cycles (examples/data, MIT): `impedax remaining` of the file alone
    averages its 3 cycles, and the fit of that mean by its SEM has residuals far below it; the note
    spoke of "a contact that changes from touch to touch" only (2026-12-06)."""
    from pathlib import Path

    cycles = Path(__file__).parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc"
    assert main(["remaining", str(cycles), "--out", str(tmp_path / "mean.nc"), "-q"]) == 0
    fitted = ix.fit("R0 + R1 || CPE1 + R2 || CPE2", ix.load(tmp_path / "mean.nc"), weighting="sigma")
    (note,) = [w for w in fitted.warnings if SIGMA_OF_TRIAL_MEANS_WORDS in w and "× the data's sigma in rms" in w]
    assert "(3 total spectra;" in note and "a cell from cycle to cycle" in note
    assert fitted.chi2_red < 0.2  # (0.07: the cycles' difference, in σ, taken up by the fit of their mean)
