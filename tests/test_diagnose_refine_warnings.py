"""What diagnose and refine tell a JSON reader (walkthrough of 2026-12-05): the sign hint in
refine's JSON, an adequate verdict beyond the catalog as a warning, the effects ``effects=``
(--effects) left out named in the verdict, the baseline's undetermined parameters as a note,
refine's informative notes kept out of its warnings, and a spelling hint for an effect id.
Spectra are SYNTHETIC numpy formulas written here, with 0.5 % complex noise and fixed seeds."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting import DEFAULT_EFFECTS
from impedax.fitting.diagnosis.refinement import UNCHANGED_WORDS

FREQ = np.geomspace(1e6, 1, 61)
OMEGA = 2 * np.pi * FREQ


def parallel(*z):
    return 1 / sum(1 / np.asarray(x) for x in z)


def noisy(z, seed, rel=0.005):
    rng = np.random.default_rng(seed)
    return z + rel * np.abs(z) * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / np.sqrt(2)


# 20 Ω + 100 Ω ∥ 1 µF, plus 2 µH of lead inductance the model R0 + R1 ∥ C1 lacks
RC = 20 + parallel(100, 1 / (1j * OMEGA * 1e-6))
WITH_LEAD = noisy(RC + 1j * OMEGA * 2e-6, 1)
NOTHING_MISSING = noisy(RC, 2)
MODEL = "R0 + R1 || C1"


def write(path, z):
    np.savetxt(path, np.c_[FREQ, z.real, z.imag], delimiter=",", header="frequency,Z_real,Z_imag", comments="")
    return str(path)


@pytest.fixture(scope="module")
def restricted():
    """The lead inductance missing, diagnosed with the constant-phase effect alone."""
    return ix.diagnose(ix.make_spectrum(FREQ, WITH_LEAD), MODEL, effects=DEFAULT_EFFECTS.select(["constant_phase"]))


def test_effects_left_out_are_named_in_the_verdict_and_warned(restricted):
    assert restricted.verdict == "adequate" and restricted.beyond_catalog
    assert restricted.noise_ratio > 5  # (the lead's +j ω L is far above 0.5 % noise at 1 MHz: 2 µH → 12.6 Ω of 20 Ω)
    assert "series_inductance" in restricted.effects_left_out and "constant_phase" not in restricted.effects_left_out
    assert restricted.verdict_heading == "ADEQUATE WITHIN THE EFFECTS TRIED"
    assert "no effect tried explains them" in restricted.reason and "series_inductance" in restricted.reason
    (warning,) = [w for w in restricted.warnings if w.startswith("adequate only within the effects tried")]
    assert "series_inductance" in warning
    summary = restricted.summary()
    assert summary["effects_left_out"] == list(restricted.effects_left_out) and warning in summary["warnings"]


def test_the_whole_catalog_names_the_lead_and_warns_of_no_catalog():
    """The same data with every effect: the lead is found; nothing is left out or warned of."""
    d = ix.diagnose(ix.make_spectrum(FREQ, WITH_LEAD), MODEL)
    assert d.verdict == "missing_effect" and "series_inductance" in d.best.effect
    assert d.effects_left_out == () and not any(w.startswith("adequate only within") for w in d.warnings)


def test_nothing_missing_with_few_effects_is_adequate_without_warning():
    d = ix.diagnose(ix.make_spectrum(FREQ, NOTHING_MISSING), MODEL, effects=DEFAULT_EFFECTS.select(["constant_phase"]))
    assert d.verdict == "adequate" and not d.beyond_catalog and d.noise_ratio < 1.5
    assert d.warnings == [] and d.verdict_heading == "ADEQUATE"
    assert "series_inductance" in d.effects_left_out  # (recorded, but nothing to warn of)


def test_undetermined_parameters_of_the_users_model_are_a_note():
    """A second arc the data lack: its capacitor is undetermined (impedax fit warns); diagnose
    says so too. The same data with the model that fits them: no such note."""
    data = ix.make_spectrum(FREQ, NOTHING_MISSING)
    over = ix.diagnose(data, MODEL + " + R2 || C2")
    loose = ix.fitting.diagnosis.diagnosis.undetermined_parameters(over.baseline)
    assert loose  # (the oracle: the fit's own errors leave the second arc undetermined)
    (note,) = [n for n in over.notes if "the data do not determine" in n]
    assert all(name in note for name in loose) and note in over.warnings
    assert "impedax compare DATA --model 'R0 + R1 || C1 + R2 || C2'" in note
    assert not any("the data do not determine" in n for n in ix.diagnose(data, MODEL).notes)


def test_refine_json_gives_the_sign_hint_first(tmp_path, capsys):
    flipped = write(tmp_path / "flipped.csv", np.conj(NOTHING_MISSING))
    assert main(["refine", flipped, "--json", "-q"]) == 0
    out = json.loads(capsys.readouterr().out)
    hint = ix.kk_test((FREQ, np.conj(NOTHING_MISSING))).sign_hint
    assert hint and out["verdict"] == "data_invalid"
    # (the CLI names the file's own column in the remedy)
    assert out["sign_hint"].startswith(hint.partition("; if so")[0]) and "'-Z_imag'" in out["sign_hint"]
    assert out["warnings"][0] == out["sign_hint"] and out["sign_hint"] in out["reason"]
    sound = write(tmp_path / "sound.csv", NOTHING_MISSING)
    assert main(["refine", sound, "--json", "-q"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["sign_hint"] is None and out["verdict"] == "adequate" and out["warnings"] == [] and out["effects_left_out"] == []


def test_refine_keeps_a_path_that_changed_nothing_out_of_its_warnings():
    """Two arcs from a one-arc start: the second path's note is information, every other note
    a warning. (Seed 4: on seed 3's noise the second path, which starts from a Warburg, has led
    since 2026-12-05 to the first path's end, the Warburg left out once the arc took it over.)"""
    two_arcs = noisy(10 + parallel(100, 1 / (1j * OMEGA * 1e-6)) + parallel(200, 1 / (1j * OMEGA * 1e-3)), 4)
    result = ix.refine(ix.make_spectrum(FREQ, two_arcs), MODEL)
    assert result.verdict == "adequate"
    informative = [n for n in result.notes if UNCHANGED_WORDS in n]
    assert informative  # (this spectrum's second path changes nothing: the case under test)
    assert result.warnings == [n for n in result.notes if UNCHANGED_WORDS not in n]
    assert result.summary()["warnings"] == result.warnings


@pytest.mark.parametrize("word, meant", [("CPE", "constant_phase"), ("constant-phase", "constant_phase"), ("Series Inductance", "series_inductance"),
                                         ("warburg", "diffusion"), ("inductance", "series_inductance"), ("xyz", None), ("R", None)])
def test_a_mistyped_effect_gets_the_id_it_most_likely_means(word, meant):
    assert DEFAULT_EFFECTS.closest(word) == meant


def test_cli_effects_typo_exits_2_with_the_hint(tmp_path, capsys):
    data = write(tmp_path / "d.csv", NOTHING_MISSING)
    assert main(["diagnose", data, "--model", MODEL, "--effects", "CPE"]) == 2
    assert "unknown effect 'CPE' (did you mean constant_phase?)" in capsys.readouterr().err


# SYNTHETIC sparse spectrum (21 points over 6.5 decades) of R0 + R1 ∥ CPE1 + L1 at 0.1 % complex
# noise (0.071 % per component): the Kramers–Kronig chain the noise is estimated from misses the
# shape between the points and puts σ at 0.12–0.19 %, so an adequate model's residuals sit far below it
SPARSE = np.geomspace(3e5, 0.1, 21)
SPARSE_TRUTH = 150 + 1 / (1 / 500 + 3.3e-8 * (1j * 2 * np.pi * SPARSE) ** 0.99) + 1j * 2 * np.pi * SPARSE * 3.3e-6
TRUE_SIGMA = 0.001 / np.sqrt(2)


@pytest.mark.parametrize("seed", [0, 1])
def test_residuals_far_below_an_estimate_too_high_get_a_note(seed):
    z = noisy(SPARSE_TRUTH, seed, rel=0.001)
    d = ix.diagnose(ix.make_spectrum(SPARSE, z), "R0 + R1 || CPE1 + L1")
    assert d.verdict == "adequate" and d.noise_level > 1.4 * TRUE_SIGMA  # (the oracle: the estimate is too high)
    (note,) = [n for n in d.notes if "× the noise estimated" in n]
    assert "the verdict is lenient" in note and "--noise REL" in note and note in d.warnings
    # the true noise given: judged against it, no such note
    given = ix.diagnose(ix.make_spectrum(SPARSE, z), "R0 + R1 || CPE1 + L1", noise=float(TRUE_SIGMA))
    assert not any("× the noise" in n for n in given.notes)


def test_noise_free_data_are_said_to_be_below_the_floor_and_sound_noise_gets_no_note():
    clean = ix.diagnose(ix.make_spectrum(FREQ, RC), MODEL)
    (note,) = [n for n in clean.notes if "× the noise floor" in n]
    assert "nearly noise-free" in note
    noisy_estimate = ix.diagnose(ix.make_spectrum(FREQ, NOTHING_MISSING), MODEL)
    assert 0.5 * 0.005 / np.sqrt(2) < noisy_estimate.noise_level < 2 * 0.005 / np.sqrt(2)  # (an estimate near the truth ...)
    assert not any("× the noise" in n for n in noisy_estimate.notes)  # (... and no note)


def test_a_missing_effect_under_the_noise_overall_is_called_systematic():
    """A small second arc (2 Ω of 650 Ω, τ = 2 ms) on the sparse spectrum: missing, though the
    residuals are under the (too high) noise estimate; the reason says they are not noise alone
    rather than "0.63× the noise; adding …"."""
    omega = 2 * np.pi * SPARSE
    d = ix.diagnose(ix.make_spectrum(SPARSE, noisy(SPARSE_TRUTH + 2 / (1 + 1j * omega * 2e-3), 0, rel=0.001)), "R0 + R1 || CPE1 + L1")
    assert d.verdict == "missing_effect" and d.noise_ratio < 1 and d.best.effect == "extra_relaxation"
    assert d.reason.startswith(f"the residuals are {d.noise_ratio:.3g}× the noise overall, yet ")


def test_real_biologic_bands_of_the_data_and_points_kept_inside_are_explained():
    """REAL BioLogic example file (impedance.py 1.7, MIT): its one structured band is where the
    KK test flags the data, so the verdict does not say "no structured band" bare; the 4 flagged
    points kept inside the band come with why and the --exclude that leaves them out."""
    data = ix.load("tests/fixtures/real/exampleDataBioLogic.mpt")
    d = ix.diagnose(data, "R0 + R1 || CPE1")
    assert d.verdict == "adequate" and d.failing_bands and all(b.data_problem for b in d.failing_bands)
    assert "with no structured band but where the KK test flags the data" in d.reason
    kept = d.kk_flagged_kept
    assert "a diagnosis leaves out only a flagged run at an end of the band" in kept
    given = kept.split("--exclude ")[1].split(" ")[0]
    flagged = np.sort(d.kk.frequency[np.asarray(d.kk.flagged, bool)])
    # (exactly the points the KK test flags: the command's --exclude, as impedax kk writes it since
    # 2026-12-06 — 5.34,56.2,123,270 — leaves out those and no other)
    from impedax.cli.common import exclude_points

    left = exclude_points(data, given)["frequency"].values
    np.testing.assert_array_equal(np.sort(np.setdiff1d(data["frequency"].values, left)), flagged)
