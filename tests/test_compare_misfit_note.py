"""The misfit note of a too-simple model: `impedax compare` and the data's sigma say that the
misfit is the model's where the note that the data limit the fit (`DATA_LIMIT_NOTE`) would send
the user to the data (docs/fitting.md, "Weighting sanity and the model's misfit")."""

import json

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.least_squares.result import DATA_LIMIT_NOTE, SIGMA_EXCEEDED, misfit_notes

FREQ = np.geomspace(0.1, 1e5, 50)
S = 2j * np.pi * FREQ
# SYNTHETIC R0 + R1 ∥ CPE1 (20 Ω, 1 kΩ, Q = 1e-5, α = 0.97), written here: R0 + R1 ∥ C1 stops at
# ~3 % on it, between 1.2× and 5× the ~1.1 % of the KK test's Voigt chain on 1 % noise
TRUTH = 20 + 1000 / (1 + 1000 * 1e-5 * S**0.97)
_RNG = np.random.default_rng(0)
NOISE = _RNG.normal(size=FREQ.size) + 1j * _RNG.normal(size=FREQ.size)
Z = TRUTH * (1 + 0.01 * NOISE)
SIGMA = 0.01 * np.abs(TRUTH)  # σ of Re and of Im, as the noise above has it


@pytest.fixture(scope="module")
def fits():
    """The two fits as on data the KK test cannot vouch for: the rule that a fit of data that
    pass the test is told its misfit is its own (`misfit_beyond_chain`, tested below)
    set out of reach, so that the too-simple fit keeps the note that the data limit it, the note
    `compare` replaces."""
    from impedax.fitting.least_squares import result

    data = ix.make_spectrum(FREQ, Z)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(result, "MODEL_MISFIT_OVER_CONSISTENT", np.inf)
        patch.setattr(result, "MODEL_MISFIT_NOISE_SHARE", np.inf)
        return [ix.fit(m, data) for m in ("R0 + R1 || C1", "R0 + R1 || CPE1")]


def test_a_fit_of_data_that_pass_the_kk_test_is_told_its_misfit_is_its_own():
    """The KK test passes on these data (1 % noise on an R0 + R1 ∥ CPE1 written here), so its
    chain's misfit is their noise, and R0 + R1 ∥ C1 at ~2.7× that is wrong, not limited by the
    data; the right model, at the noise, gets no note."""
    from impedax.fitting.least_squares.result import MODEL_MISFIT_OVER_CONSISTENT

    data = ix.make_spectrum(FREQ, Z)
    kk = ix.kk_test(data)
    simple, right = (ix.fit(m, data) for m in ("R0 + R1 || C1", "R0 + R1 || CPE1"))
    assert kk.valid and MODEL_MISFIT_OVER_CONSISTENT * kk.rms_rel < simple.rms_rel < 5 * kk.rms_rel
    (note,) = [w for w in simple.warnings if "misfit" in w]
    assert note.startswith(f"the misfit is this model's: the data pass the Kramers–Kronig test (their {kk.rms_rel * 100:.2g} % rms_rel")
    assert not any(DATA_LIMIT_NOTE in w for w in simple.warnings)
    assert not any("misfit" in w or "Kramers–Kronig" in w for w in right.warnings)


def test_compare_tells_the_too_simple_model_its_misfit_is_its_own(fits):
    simple, right = fits
    kk = ix.kk_test(ix.make_spectrum(FREQ, Z)).rms_rel
    assert 1.2 * kk < simple.rms_rel < 5 * kk and right.rms_rel < 1.2 * kk
    # the single fit cannot know: it keeps the note that the data limit the fit
    assert any(DATA_LIMIT_NOTE in w for w in simple.warnings)
    c = ix.compare(fits)
    (test,) = c.f_tests
    assert test["valid"] and test["p_value"] < 1e-20
    (note,) = [w for w in c.fits[0].warnings if "misfit" in w]
    assert note.startswith(f"R0 + R1 || CPE1 fits these data significantly better (rms_rel {right.rms_rel * 100:.3g} % against {simple.rms_rel * 100:.3g} %, F-test p = {test['p_value']:.2g})")
    assert "the misfit is this model's, not the data's noise" in note
    assert not any(DATA_LIMIT_NOTE in w for f in c.fits for w in f.warnings)
    assert not any("misfit" in w or "Kramers–Kronig" in w for w in c.fits[1].warnings)  # the right model at the noise: nothing
    assert simple.warnings != c.fits[0].warnings  # (the user's fit is left as it was)
    common, own = c.warnings_by_model()
    assert common == [] and note in own[0] and note in c.report() and c.summary()["models"][0]["warnings"] == list(c.fits[0].warnings)
    # with one model, or with only a fit no better than it (no F-test, rms_rel alike), the note stays as the fit has it
    assert ix.compare([simple]).fits[0].warnings == simple.warnings
    pair = ix.compare([simple, simple])
    assert pair.f_tests == () and [f.warnings for f in pair.fits] == [simple.warnings] * 2
    assert any(DATA_LIMIT_NOTE in w for w in pair.warnings_by_model()[0])  # once, under every model


def _mean_over_sigma(z_model, sigma):
    dz = z_model - Z
    return float(np.mean((dz.real**2 + dz.imag**2) / (2 * sigma**2)))


def test_a_misfit_far_above_the_stated_sigma_is_the_model_s(fits):
    # R0 + R1 ∥ C1 fitted to the α = 0.97 data: ~3 % rms_rel, mean (ΔRe² + ΔIm²)/2σ² ≈ 5
    RC = fits[0].z_model
    ratio = _mean_over_sigma(RC, SIGMA)
    assert ratio > SIGMA_EXCEEDED
    (without,), (with_sigma,) = misfit_notes(FREQ, Z, RC), misfit_notes(FREQ, Z, RC, sigma=SIGMA[None])
    assert without[0].startswith("the misfit is this model's: the data pass the Kramers–Kronig test")  # (without σ: the KK test's verdict)
    assert DATA_LIMIT_NOTE not in with_sigma[0]
    assert f"mean (ΔRe² + ΔIm²)/2σ² above {SIGMA_EXCEEDED:g}" in with_sigma[0] and "the misfit is this model's" in with_sigma[0]
    noise_rms = np.sqrt(np.mean(2 * SIGMA**2 / np.abs(Z) ** 2))
    assert f"within that noise ({noise_rms * 100:.2g} %)" in with_sigma[0]
    # a σ five times too small: the KK chain is far outside it too, so σ tells nothing; the KK
    # test's verdict (the data pass it) still says the misfit is the model's
    (understated,) = misfit_notes(FREQ, Z, RC, sigma=SIGMA[None] / 5)
    assert understated == without
    # the right model with 3 % noise and its σ: the residuals are the noise, no note at all
    z3 = TRUTH * (1 + 0.03 * NOISE)
    (right,) = misfit_notes(FREQ, z3, TRUTH, sigma=3 * SIGMA[None])
    assert np.sqrt(np.mean(np.abs((TRUTH - z3) / z3) ** 2)) > 0.02 and right == ()


def test_compare_command_with_the_data_s_sigma(tmp_path, capsys):
    from impedax.cli import main

    path = tmp_path / "cpe.csv"
    ix.save(ix.make_spectrum(FREQ, Z, sigma=SIGMA), path)
    assert main(["compare", str(path), "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "--weighting", "sigma", "--json"]) == 0
    simple, right = json.loads(capsys.readouterr().out)["models"]
    (note,) = [w for w in simple["warnings"] if "misfit" in w]
    assert "exceeds the noise the data's sigma states" in note and "the misfit is this model's" in note
    assert not any(DATA_LIMIT_NOTE in w for w in simple["warnings"]) and not any("misfit" in w for w in right["warnings"])


def test_without_an_f_test_a_clearly_lower_rms_rel_and_aic_decide(fits):
    # (models not nested, or the larger one short of its optimum): the rule of `CLEARLY_LOWER_RMS`
    from impedax.fitting.comparison import CLEARLY_LOWER_RMS, _model_not_data

    simple, right = fits
    labels = [simple.model, right.model]
    assert simple.rms_rel > CLEARLY_LOWER_RMS * right.rms_rel
    (note,) = _model_not_data(simple, 0, fits, labels, [], [simple.aic, right.aic]).warnings
    assert note.startswith(f"R0 + R1 || CPE1 fits these data significantly better (rms_rel {right.rms_rel * 100:.3g} % against {simple.rms_rel * 100:.3g} %, ΔAIC {right.aic - simple.aic:.1f})")
    assert _model_not_data(simple, 0, fits, labels, [], [right.aic, simple.aic]).warnings == simple.warnings  # a higher AIC: no
    assert _model_not_data(right, 1, fits, labels, [], [simple.aic, right.aic]) is right  # no note to replace


def test_without_an_f_test_an_aic_lower_by_ten_decides(fits):
    # non-nested models only 1.29× apart in rms_rel (R_EP ∥ C_gap against CPE_EP ∥ C_gap on a
    # haptics spectrum, ΔAIC 61): Burnham & Anderson's ΔAIC ≥ 10 alone says the misfit is the model's
    from dataclasses import replace

    from impedax.fitting.comparison import CLEARLY_LOWER_RMS, DECISIVE_DELTA_AIC, _model_not_data

    simple, right = fits
    close = replace(right, z_model=Z + (simple.z_model - Z) / 1.29)  # rms_rel 1.29× below simple's
    pair, labels = [simple, close], [simple.model, close.model]
    assert simple.rms_rel < CLEARLY_LOWER_RMS * close.rms_rel and DECISIVE_DELTA_AIC == 10
    (note,) = _model_not_data(simple, 0, pair, labels, [], [0.0, -61.0]).warnings
    assert note.startswith(f"R0 + R1 || CPE1 fits these data significantly better (rms_rel {close.rms_rel * 100:.3g} % against {simple.rms_rel * 100:.3g} %, ΔAIC -61.0)")
    assert _model_not_data(simple, 0, pair, labels, [], [0.0, -10.0]).warnings == (note.replace("-61.0", "-10.0"),)
    # ΔAIC below 10 with the rms ratio below 1.5: no evidence, the note stays
    assert _model_not_data(simple, 0, pair, labels, [], [0.0, -9.9]).warnings == simple.warnings
    # the better model keeps its own warnings (a higher AIC never names the worse one)
    with_note = replace(close, warnings=simple.warnings)
    assert _model_not_data(with_note, 1, [simple, with_note], labels, [], [0.0, -61.0]).warnings == simple.warnings


def test_a_fit_not_weighted_by_the_stated_sigma_is_told_to_refit_with_it():
    """SYNTHETIC R0 + R1 ∥ C1 (numpy) with σ rising from 1e-5 to 0.1 of |Z| over the band and
    noise of that σ: the right model fitted with the modulus weighting leaves residuals over
    9× σ² at the quiet low frequencies, and was told "the misfit is this model's"; now the
    note says to refit with the sigma weighting, which then fits within σ with no note."""
    f = np.geomspace(1, 1e5, 41)
    z = 100 + 1e4 / (1 + 1j * 2 * np.pi * f * 1e4 * 1e-7)
    sigma = np.abs(z) * np.geomspace(1e-5, 0.1, f.size)
    rng = np.random.default_rng(1)
    data = ix.make_spectrum(f, z + sigma * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)), sigma=sigma)
    by_modulus = ix.fit("R0 + R1 || C1", data, weighting="modulus")
    dz = by_modulus.z_model - data["Z"].values
    assert np.mean((dz.real**2 + dz.imag**2) / (2 * sigma**2)) > 4  # (the rule's SIGMA_EXCEEDED, computed here)
    (note,) = [w for w in by_modulus.warnings if "exceeds the noise the data's sigma states" in w]
    assert "refit with the sigma weighting (impedax fit --weighting sigma; impedax sample --noise sigma)" in note
    assert "the misfit is this model's" not in note
    by_sigma = ix.fit("R0 + R1 || C1", data, weighting="sigma")
    assert by_sigma.chi2_red < 2 and not any("sigma" in w for w in by_sigma.warnings)


# SYNTHETIC R0 + R1 ∥ CPE1 closer to an ideal arc (α = 0.985, τ = 1 ms), the same 1 % noise:
# R0 + R1 ∥ C1 stops at ~2.0 %, under 2× the chain's ~1.1 %, yet its χ² is ~3.4× the chain's
NEAR_TRUTH = 20 + 1000 / (1 + 1000 * 1e-6 * S**0.985)
NEAR_Z = NEAR_TRUTH * (1 + 0.01 * NOISE)


def test_misfit_beyond_chain_by_hand():
    """The rule on numbers worked by hand: N = 50 points (100 real residuals), a fit of 4
    parameters against a chain of 19. χ² 1.6² = 2.56×: ΔAIC = 100 ln 2.56 − 2·15 = 64 > 10, the
    model's; χ² 1.1² = 1.21× is under 1.25×; χ² 1.2² = 1.44× on 10 points: ΔAIC 20 ln 1.44 − 30
    = −22.7, not; over 2× the rms_rel is the model's whatever the counts (the older rule)."""
    from impedax.fitting.least_squares.result import misfit_beyond_chain

    assert misfit_beyond_chain(1.6, 1.0, 50, 4, 19)
    assert not misfit_beyond_chain(1.1, 1.0, 50, 4, 19)
    assert not misfit_beyond_chain(1.2, 1.0, 10, 4, 19)
    assert misfit_beyond_chain(1.2, 1.0, 200, 4, 19)  # 400 ln 1.44 − 30 = 116
    assert misfit_beyond_chain(2.1, 1.0, 5, 4, 19) and not misfit_beyond_chain(1.6, 1.0, 50, None, 19)


def test_fit_and_diagnose_agree_below_twice_the_chain_s_misfit():
    """R0 + R1 ∥ C1 on the near-ideal CPE arc: under 2× the chain's rms_rel but far beyond the
    noise by χ² and AIC. The fit says its misfit is its own (not the data's noise) as
    `impedax diagnose` does when it names the constant-phase element; in a batch alike. The
    right model, and the same model on 4 % noise with nothing missing, get no such note."""
    data = ix.make_spectrum(FREQ, NEAR_Z)
    kk = ix.kk_test(data)
    simple = ix.fit("R0 + R1 || C1", data)
    assert kk.valid and kk.rms_rel < simple.rms_rel < 2 * kk.rms_rel and (simple.rms_rel / kk.rms_rel) ** 2 > 1.25
    (note,) = [w for w in simple.warnings if "misfit" in w]
    assert note.startswith("the misfit is this model's") and "χ² is over 1.25× the chain's" in note, note
    assert not any(DATA_LIMIT_NOTE in w for w in simple.warnings)
    batch = ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, np.stack([NEAR_Z, NEAR_Z]), dims=("trial",)))
    assert note in batch.warnings["trial=0"] and note in batch.warnings["trial=1"]
    diagnosis = ix.diagnose(simple)
    assert diagnosis.verdict == "missing_effect" and diagnosis.best.effect == "constant_phase", diagnosis.reason
    assert not any("misfit" in w for w in ix.fit("R0 + R1 || CPE1", data).warnings)
    noisy = ix.fit("R0 + R1 || CPE1", ix.make_spectrum(FREQ, NEAR_TRUTH * (1 + 0.04 * NOISE)))
    assert noisy.rms_rel > 0.02 and not any("misfit is this model's" in w for w in noisy.warnings), noisy.warnings
