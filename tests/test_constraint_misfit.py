"""A misfit that the user's fixed value or bound explains is said to be that constraint's, not
the model's, in single and batch fits alike, and the diagnosis names no missing effect for it.

SYNTHETIC spectra from the numpy formula R0 + R1 ∥ CPE1 written here (R0 = 0.05 Ω, R1 = 0.16 Ω,
Q = 3.2, α = 0.85) with 0.3 % relative complex noise: the right circuit, so a fit misses the
data only by what the user held."""

import warnings

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis.diagnosis import Verdict, _constraint_verdict, _fixed_words
from impedax.fitting.least_squares.constraints import binding_constraints, constraint_explains

MODEL = "R0 + R1 || CPE1"
F = np.geomspace(0.1, 1e5, 41)
R0 = 0.05


def truth(f):
    """R0 + 1/(1/R1 + Q (jω)^α) with the values of the module docstring [Ω]."""
    return R0 + 1 / (1 / 0.16 + 3.2 * (1j * 2 * np.pi * f) ** 0.85)


def noisy(seed, n=None):
    rng = np.random.default_rng(seed)
    shape = (F.size,) if n is None else (n, F.size)
    return truth(F) * (1 + 0.003 * (rng.standard_normal(shape) + 1j * rng.standard_normal(shape)))


def rms_rel(z_model, z):
    return float(np.sqrt(np.mean(np.abs((z_model - z) / np.abs(z)) ** 2)))


CONSTRAINT_NOTE = "the misfit is a constraint you set, not the model's"


@pytest.fixture(scope="module")
def wrong_fixed():
    z = noisy(0)
    return z, ix.fit(MODEL, ix.make_spectrum(F, z), fixed={"R0": 0.04}, n_starts=1)


def test_a_wrong_fixed_value_is_named_not_the_model(wrong_fixed):
    z, fit = wrong_fixed
    # the oracle: the formula itself is 0.3 % from the data; the fit held at R0 = 0.04 is far off
    assert rms_rel(truth(F), z) < 0.006 and fit.rms_rel > 0.05
    (note,) = [w for w in fit.warnings if CONSTRAINT_NOTE in w]
    assert "R0 fixed at 40 mΩ (your fixed=, --fix)" in note and "fit with R0 free" in note
    assert not any("misses structure" in w or "which effect is missing" in w for w in fit.warnings)


def test_a_bound_the_fit_sits_on_single_and_batch_give_the_same_note():
    z = noisy(1, 2)
    bounds = {"R0": (0.01, 0.048)}  # (one start each: the note's rule, not the start ladder, is tested)
    batch = ix.fit(MODEL, ix.make_spectrum(F, z, dims=("trial",)), bounds=bounds, n_starts=1)
    for i in range(2):
        single = ix.fit(MODEL, ix.make_spectrum(F, z[i]), bounds=bounds, n_starts=1)
        assert single.at_bound == ("R0",) and single.bounds == {"R0": (0.01, 0.048)}
        assert single.warnings == batch.warnings.get(f"trial={i}", ()), i
        (note,) = [w for w in single.warnings if CONSTRAINT_NOTE in w]
        assert "R0 on your upper bound 48 mΩ (bounds=)" in note


def test_a_right_fixed_value_gets_no_note():
    fit = ix.fit(MODEL, ix.make_spectrum(F, noisy(0)), fixed={"R0": R0}, n_starts=1)
    assert fit.rms_rel < 0.006 and fit.warnings == ()


def test_a_right_fixed_value_leaves_a_wrong_model_blamed():
    """Data with a second arc, 0.2 Ω ∥ 1 mF, that the model lacks, R0 fixed at its true value:
    freeing R0 does not remove the misfit, and the model's note stays (the same compiled
    programs as the fits above)."""
    second = 0.2 / (1 + 1j * 2 * np.pi * F * 0.2 * 1e-3)
    z = noisy(0) + second
    fit = ix.fit(MODEL, ix.make_spectrum(F, z), fixed={"R0": R0}, n_starts=1)
    assert rms_rel(truth(F) + second, z) < 0.006 and fit.rms_rel > 0.05
    assert any("misses structure" in w for w in fit.warnings)
    assert not any(CONSTRAINT_NOTE in w for w in fit.warnings)


def test_binding_constraints_and_the_rule():
    values = {"R0": 0.048, "R1": 0.1, "CPE1.Q": 3.0}
    # R1 at a natural bound (not the user's) and a user bound it does not sit on are not named
    assert binding_constraints(values, {"CPE1.Q": True}, ("R0", "R1"), {"R0": (0.01, 0.048), "CPE1.Q": (1, 5)}) == [("CPE1.Q", "fixed", 3.0), ("R0", "upper", 0.048)]
    assert constraint_explains(0.15, 0.004, 0.0039)
    assert not constraint_explains(0.15, 0.09, 0.0039)  # halved, but still far from what the data allow
    assert not constraint_explains(0.030, 0.019, 0.018)  # within what the data allow, but not halved
    # ... which, with the points and constraints counted, the χ²/AIC rule decides: (3.0/1.9)² =
    # 2.49 ≥ 1.25 and 2·50 ln 2.49 − 2 = 89 > 10; (2.1/1.9)² = 1.22 is under 1.25
    assert constraint_explains(0.030, 0.019, 0.018, 50, 1)
    assert not constraint_explains(0.021, 0.019, 0.018, 50, 1)
    assert not constraint_explains(0.15, 0.09, 0.0039, 50, 1)  # still far from what the data allow


def test_the_diagnosis_names_the_constraint_and_keeps_fix(wrong_fixed):
    z, fit = wrong_fixed
    verdict, reason = _constraint_verdict(fit, ix.make_spectrum(F, z), ix.kk_test(ix.make_spectrum(F, z)), 40.0)
    assert verdict == Verdict.CONSTRAINT == "constraint"
    assert "R0 fixed at 40 mΩ" in reason and "not a missing effect" in reason
    assert _fixed_words(fit) == " --fix R0=0.04"
    right = ix.fit(MODEL, ix.make_spectrum(F, z), fixed={"R0": R0}, n_starts=1)
    assert _constraint_verdict(right, ix.make_spectrum(F, z), None, 1.0) is None


def test_only_the_constraint_that_holds_the_fit_is_named():
    """R0 fixed wrong (0.04) beside CPE1.alpha fixed at its true 0.85: releasing R0 alone
    explains the misfit, so the note and the diagnosis name R0 and not the harmless alpha."""
    z = noisy(0)
    fit = ix.fit(MODEL, ix.make_spectrum(F, z), fixed={"R0": 0.04, "CPE1.alpha": 0.85}, n_starts=1)
    (note,) = [w for w in fit.warnings if CONSTRAINT_NOTE in w]
    assert "R0 fixed at 40 mΩ" in note and "fit with R0 free" in note and "alpha" not in note, note
    verdict, reason = _constraint_verdict(fit, ix.make_spectrum(F, z), ix.kk_test(ix.make_spectrum(F, z)), 40.0)
    assert verdict == Verdict.CONSTRAINT and "R0 fixed at 40 mΩ" in reason and "alpha" not in reason, reason


def test_a_constraint_within_twice_the_free_fit_is_still_named():
    """1.5 % noise (the KK chain at 2.1 %, valid): R0 fixed at 0.048 leaves 3.8 %, under 2× the
    free fit's 2.3 %, yet χ² 2.8× and ΔAIC = 82 ln 2.8 − 2 ≈ 83 on 41 points: the constraint's (the halving
    rule alone kept the note that the data limit the fit). At 0.0495, 2.5 % (χ² 1.18×), the data
    are still what limits it."""
    rng = np.random.default_rng(3)
    z = truth(F) * (1 + 0.015 * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)))
    data = ix.make_spectrum(F, z)
    held = ix.fit(MODEL, data, fixed={"R0": 0.048}, n_starts=1)
    free = ix.fit(MODEL, data)
    assert free.rms_rel < held.rms_rel < 2 * free.rms_rel and (held.rms_rel / free.rms_rel) ** 2 > 2.5
    assert any(CONSTRAINT_NOTE in w and "R0 fixed at 48 mΩ" in w for w in held.warnings), held.warnings
    close = ix.fit(MODEL, data, fixed={"R0": 0.0495}, n_starts=1)
    assert close.rms_rel > 0.02 and not any(CONSTRAINT_NOTE in w for w in close.warnings)
    assert any("limit the fit" in w for w in close.warnings), close.warnings


def finger_khz_read_as_hz(seed):
    """SYNTHETIC Meyer finger, C_s + C_i + R_sc ∥ C_sc + R_f (140 pF, 1.7 nF, 130 kΩ, 2.2 nF,
    500 Ω), 1 % complex noise, measured 1 Hz – 100 kHz but written with its kHz numbers under
    a Hz column (a walkthrough's file, 2026-12-02): at the labelled frequencies the data are
    those of every capacitance 1000× larger."""
    f_true = np.geomspace(1.0, 1e5, 40)
    w = 2j * np.pi * f_true
    z = 1 / (w * 140e-12) + 1 / (w * 1.7e-9) + 130e3 / (1 + w * 130e3 * 2.2e-9) + 500.0
    rng = np.random.default_rng(seed)
    return ix.make_spectrum(f_true / 1e3, z * (1 + 0.01 * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size))))


def test_a_wrong_fixed_value_that_drives_the_others_far_off_is_still_named():
    """C_i fixed at the true 1.7 nF on the mislabelled data (they need 1000× the capacitance): the fit misses
    them by thousands of per cent with C_s and C_sc driven to absurd values, from where one local
    fit with C_i freed does not come back; from the data-driven guess it reaches ~1.5 %, so the
    note names the fixed value and the diagnosis gives `constraint`, not a missing effect."""
    data = finger_khz_read_as_hz(0)
    model = "C_s + C_i + R_sc || C_sc + R_f"
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # (numpy's overflow in the covariance had leaked to stderr)
        held = ix.fit(model, data, fixed={"C_i": 1.7e-9})
    assert held.rms_rel > 10.0  # (over 1,000 %: the fixed C_i's impedance swamps the data)
    assert any(w.startswith(CONSTRAINT_NOTE) and "C_i fixed at 1.7 nF" in w for w in held.warnings), held.warnings
    free = ix.fit(model, data, n_starts=1)  # (what freeing C_i from the guess reaches: the note's claim)
    series_c = 1 / (1 / free.values["C_s"] + 1 / free.values["C_i"])  # (C_s and C_i in series: only this is determined)
    assert free.rms_rel < 0.03 and series_c == pytest.approx(1e3 / (1 / 140e-12 + 1 / 1.7e-9), rel=0.2)
    verdict, reason = _constraint_verdict(held, data, ix.kk_test(data), 1e3)  # (what ix.diagnose(held) decides first)
    assert verdict == Verdict.CONSTRAINT and "C_i fixed at 1.7 nF" in reason, reason
