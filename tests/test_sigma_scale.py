"""A fit weighted by the data's σ is told when σ misstates the noise (`result.sigma_scale_notes`):
a walkthrough's SYNTHETIC R0 + R1 ∥ C1 with σ stated 3× too small got χ²_red 7.2, R0 6.5 stderr
from the truth and no word of it. Also: the uneven-noise note's advice follows the weighting, and
the CLI says when the data's σ goes unused."""

import json

import numpy as np
import pytest
from scipy import stats

import impedax as ix
from impedax.fitting.bayes.evidence import START_BEYOND_SIGMA, waic_cause
from impedax.fitting.least_squares.result import chi2_red_range, uneven_residual_notes

FREQ = np.logspace(-2, 5, 50)
MARK = "× the data's sigma in rms"
TRUTH = {"R0": 20.0, "R1": 500.0, "C1": 1e-5}


def z_rc(f, r0=20.0, r1=500.0, c1=1e-5):
    """R0 + R1 ∥ C1, written here as the oracle."""
    return r0 + r1 / (1.0 + 2j * np.pi * f * r1 * c1)


def spectrum(seed, relative=0.01, stated=1.0):
    """SYNTHETIC: complex Gaussian noise of σ = relative·|Z| on Re and on Im; the file's σ is
    ``stated`` × the true one."""
    rng = np.random.default_rng(seed)
    z = z_rc(FREQ)
    sigma = relative * np.abs(z)
    return z + sigma * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)), stated * sigma


def scale_notes(warnings):
    return [w for w in warnings if MARK in w]


@pytest.mark.parametrize("dof", [10, 97, 1000])
def test_chi2_red_range_matches_the_chi2_quantiles(dof):
    """The 0.1 % and 99.9 % quantiles of χ²_ν/ν, against scipy.stats' χ² distribution."""
    low, high = chi2_red_range(dof)
    np.testing.assert_allclose([low, high], stats.chi2.ppf([0.001, 0.999], dof) / dof, rtol=1e-9)


@pytest.mark.parametrize("stated, word, factor", [(1 / 3, "understates", 3.0), (3.0, "overstates", 1 / 3)])
def test_a_misstated_sigma_is_told_with_its_factor(stated, word, factor):
    """σ stated 3× too small (too large): the residuals are ~3× (~1/3×) σ, and the note says so
    with that factor (from √χ²_red; the truth's factor is 3, χ²'s scatter at ν = 97 ± 10 %)."""
    z, sigma = spectrum(1, stated=stated)
    result = ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, z, sigma=sigma), weighting="sigma")
    (note,) = scale_notes(result.warnings)
    printed = float(note.split("× the data's sigma")[0].split()[-1])
    assert 0.8 * factor < printed < 1.25 * factor and word in note
    assert printed == pytest.approx(np.sqrt(result.chi2_red), rel=0.05)  # (two significant digits)
    if word == "understates":  # the stderr the note calls too small: R0 off by several of them, by about one of them × the factor
        off = abs(result.values["R0"] - TRUTH["R0"]) / result.stderr["R0"]
        assert off / printed < 3.5


@pytest.mark.parametrize("seed", range(6))
def test_the_true_sigma_gives_no_note(seed):
    """Nothing misstated (the right σ, the right model): no note, in six spectra."""
    z, sigma = spectrum(seed)
    assert not scale_notes(ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, z, sigma=sigma), weighting="sigma").warnings)


def test_only_sigma_weighting_is_checked_and_batch_equals_single():
    z_low, s_low = spectrum(2, stated=1 / 3)
    z_ok, s_ok = spectrum(3)
    assert not scale_notes(ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, z_low, sigma=s_low)).warnings)  # (modulus: σ not the noise model)
    stack = ix.make_spectrum(FREQ, np.stack([z_low, z_ok]), sigma=np.stack([s_low, s_ok]), dims=("trial",), coords={"trial": [0, 1]})
    batch = ix.fit("R0 + R1 || C1", stack, weighting="sigma")
    for i, (z, s) in enumerate([(z_low, s_low), (z_ok, s_ok)]):
        single = ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, z, sigma=s), weighting="sigma")
        assert batch.fit_of(trial=i).warnings == single.warnings
    assert scale_notes(batch.fit_of(trial=0).warnings) and not scale_notes(batch.fit_of(trial=1).warnings)


def test_uneven_note_advice_follows_the_weighting():
    """Band rms 1, 1, 5 (×1e-3): over 4×. Under modulus without σ: give σ and weigh by it, in
    fit and sample alike (no "use impedax sample": its default noise model is the same); with σ
    in the data: it is there, unused; under sigma: σ misstates the noise in one of the bands."""
    f = np.logspace(0, 3, 24)
    z = np.full(24, 100.0 + 0j)
    z_model = z + 100.0 * np.repeat([1e-3, 1e-3, 5e-3], 8) * (1 + 1j)
    w = 1 / np.abs(z)
    (plain,) = uneven_residual_notes(f, z, z_model, w, w, "modulus")[0]
    assert "give sigma" in plain and "impedax sample --noise sigma" in plain and "or use impedax sample" not in plain
    (carried,) = uneven_residual_notes(f, z, z_model, w, w, "modulus", has_sigma=True)[0]
    assert "the data carry a sigma column, which this weighting does not use" in carried
    (stated,) = uneven_residual_notes(f, z, z_model, w, w, "sigma", has_sigma=True)[0]
    assert "the data's sigma understates the noise at 122 Hz – 1 kHz or overstates it at 1 Hz – 8.19 Hz" in stated and "give sigma" not in stated


def test_waic_cause_names_sigma_or_model_when_only_chi2_says_misfit():
    rng = np.random.default_rng(0)
    start = np.array([np.log(20.0), np.log(500.0)])
    chain = start + 0.01 * rng.standard_normal((32, 200, 2))
    text = waic_cause(chain, ("R0", "R1"), start_y=start, converged=True, model_misfit=START_BEYOND_SIGMA)
    assert text.startswith("the start fit's residuals are several times the data's sigma") and "σ understates the noise" in text and "impedax diagnose" in text


def test_cli_says_when_the_files_sigma_is_not_used(tmp_path, capsys):
    """(In-process, `impedax.cli.main` with stdout and stderr apart: three `impedax` processes
    took 9 s of the suite.)"""
    from impedax.cli import main

    z, sigma = spectrum(4)
    path = tmp_path / "with_sigma.csv"
    np.savetxt(path, np.column_stack([FREQ, z.real, z.imag, sigma]), delimiter=",", header="frequency,z_real,z_imag,sigma", comments="")

    def run(*extra):
        code = main(["fit", str(path), "--model", "R0 + R1 || C1", *extra])
        return code, capsys.readouterr()

    (code, default), (code_weighted, weighted) = run(), run("--weighting", "sigma")
    # (since 2026-12-02 the fit's report says it, once, as the Python result's notes: not stderr too)
    assert code == 0 and "note: the data carry sigma (σ per point), which this fit's modulus weighting does not use: --weighting sigma weighs each point by it" in default.out
    assert "does not use" not in default.err
    assert code_weighted == 0 and "does not use" not in weighted.err + weighted.out
    as_json = json.loads(run("--json")[1].out)
    assert len(as_json["notes"]) == 1 and "does not use" in as_json["notes"][0]


def test_sigma_weighting_without_sigma_names_the_columns_it_reads():
    """A walkthrough's file with sigma_re, sigma_im columns was told only "needs a 'sigma' variable"."""
    z, _ = spectrum(5)
    with pytest.raises(ix.DataError, match=r"a column headed sem, sigma, sigma_z or std \(σ in Ω, one for Re and for Im: separate σ of Re and of Im are not read\)"):
        ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, z), weighting="sigma")
