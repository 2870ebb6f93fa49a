"""The remainder's sigma when an input is a single spectrum (`remaining_impedance`, ``impedax
remaining``): its own sigma (a sigma column) stands for its error and is added in quadrature to the
other inputs' standard errors; without one the remainder has none and says which input lacks it.
Until 2026-12-06 any input of one spectrum dropped the remainder's sigma, even one that carried
its own ("no sigma (an input has one spectrum or no scatter)"). Oracle: the propagation by hand
in NumPy on SYNTHETIC spectra."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.models.sirin import remaining_impedance

N_TRIALS = 5
FREQ = np.geomspace(10.0, 1e5, 11)


@pytest.fixture(scope="module")
def parts():
    """SYNTHETIC: a total of 5 trials (no sigma), a skin and a screen of one spectrum each with a
    sigma of 1 % and 2 % of |Z| (random passive-looking values; the total well above the two)."""
    rng = np.random.default_rng(5)
    total = 5e6 * (1 + 0.05 * rng.normal(size=(N_TRIALS, FREQ.size))) - 8e6j * (1 + 0.05 * rng.normal(size=(N_TRIALS, FREQ.size)))
    skin = 2e5 * (1 + 0.05 * rng.normal(size=FREQ.size)) - 3e5j * (1 + 0.05 * rng.normal(size=FREQ.size))
    screen = 1e4 * (1 + 0.05 * rng.normal(size=FREQ.size)) - 2e4j * (1 + 0.05 * rng.normal(size=FREQ.size))
    return total, (skin, 0.01 * np.abs(skin)), (screen, 0.02 * np.abs(screen))


def test_single_spectra_with_sigma_add_it_to_the_totals_standard_error(parts):
    total, (skin, s_skin), (screen, s_screen) = parts
    out = remaining_impedance(ix.make_spectrum(FREQ, total, dims=("trial",)), ix.make_spectrum(FREQ, skin, sigma=s_skin), ix.make_spectrum(FREQ, screen, sigma=s_screen))
    var_re = total.real.std(0, ddof=1) ** 2 / N_TRIALS + s_skin**2 + s_screen**2
    var_im = total.imag.std(0, ddof=1) ** 2 / N_TRIALS + s_skin**2 + s_screen**2
    np.testing.assert_allclose(out["Z"].values, total.mean(0) - skin - screen, rtol=1e-12)
    np.testing.assert_allclose(out["sigma"].values, np.sqrt((var_re + var_im) / 2), rtol=1e-12)
    np.testing.assert_allclose(out["sigma_real"].values, np.sqrt(var_re), rtol=1e-12)
    assert "stated sigma of skin and touchscreen" in out.attrs["sigma_method"]


def test_one_spectrum_each_with_sigma_and_a_single_contact_keep_it(parts):
    total, (skin, s_skin), (screen, s_screen) = parts
    s_total = 0.005 * np.abs(total[0])
    one = ix.make_spectrum(FREQ, total[0], sigma=s_total)
    out = remaining_impedance(one, ix.make_spectrum(FREQ, skin, sigma=s_skin), ix.make_spectrum(FREQ, screen, sigma=s_screen))
    np.testing.assert_allclose(out["sigma"].values, np.sqrt(s_total**2 + s_skin**2 + s_screen**2), rtol=1e-12)
    alone = remaining_impedance(one, None, None)  # (a single contact: its own sigma, unchanged)
    np.testing.assert_allclose(alone["sigma"].values, s_total, rtol=1e-12)


def test_a_single_spectrum_without_sigma_is_named(parts):
    total, (skin, _), (screen, s_screen) = parts
    out = remaining_impedance(ix.make_spectrum(FREQ, total, dims=("trial",)), ix.make_spectrum(FREQ, skin), ix.make_spectrum(FREQ, screen, sigma=s_screen))
    assert "sigma" not in out
    assert out.attrs["sigma_method"].startswith("not available: skin is one spectrum without a sigma of its own")


def test_impedax_remaining_writes_the_propagated_sigma_and_says_how(tmp_path, capsys, parts):
    total, (skin, s_skin), (screen, s_screen) = parts
    paths = [str(tmp_path / name) for name in ("total.nc", "skin.csv", "ts.csv")]
    ix.save(ix.make_spectrum(FREQ, total, dims=("trial",)), paths[0])
    ix.save(ix.make_spectrum(FREQ, skin, sigma=s_skin), paths[1])
    ix.save(ix.make_spectrum(FREQ, screen), paths[2])  # (no sigma column: the remainder has none)
    assert main(["remaining", *paths, "--out", str(tmp_path / "none.nc"), "--json"]) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    assert summary["has_sigma"] is False and summary["sigma_method"].startswith("not available: touchscreen is one spectrum without a sigma")
    ix.save(ix.make_spectrum(FREQ, screen, sigma=s_screen), paths[2])
    assert main(["remaining", *paths, "--out", str(tmp_path / "rem.nc")]) == 0
    assert "sigma: SEM of Re and Im over the trials of total; the stated sigma of skin and touchscreen (one spectrum each)" in capsys.readouterr().err
    var = (total.real.std(0, ddof=1) ** 2 + total.imag.std(0, ddof=1) ** 2) / N_TRIALS / 2 + s_skin**2 + s_screen**2
    np.testing.assert_allclose(ix.load(tmp_path / "rem.nc")["sigma"].values, np.sqrt(var), rtol=1e-12)


def test_remaining_trials_say_why_they_have_no_sigma(tmp_path, capsys, parts):
    """--trials writes each total trial minus the skin and screen means, without sigma; its JSON's
    sigma_method was "" (2026-12-06), and now says why."""
    total, (skin, s_skin), (screen, s_screen) = parts
    paths = [str(tmp_path / name) for name in ("total.nc", "skin.nc", "ts.nc")]
    for path, ds in zip(paths, (ix.make_spectrum(FREQ, total, dims=("trial",)), ix.make_spectrum(FREQ, skin, sigma=s_skin), ix.make_spectrum(FREQ, screen, sigma=s_screen))):
        ix.save(ds, path)
    assert main(["remaining", *paths, "--trials", "--out", str(tmp_path / "t.nc"), "--json", "-q"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["has_sigma"] is False and summary["sigma_method"].startswith("not available: one remainder per total trial")
    written = ix.load(tmp_path / "t.nc")
    np.testing.assert_allclose(written["Z"].values, total - skin - screen, rtol=1e-12)
    assert written.attrs["sigma_method"] == summary["sigma_method"]


def test_remaining_help_says_what_a_single_spectrum_gives(capsys):
    """The help said only "the trial means with sigma from their standard errors" (2026-12-06)."""
    with pytest.raises(SystemExit):
        main(["remaining", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "a file of one spectrum adds its own sigma column" in text and "which file lacks it" in text


def test_the_force_bands_say_skin_and_screen_as_measured_when_one_spectrum_each(parts):
    """`impedax gap`'s "force bands" line (and JSON force_conditions) said "skin and screen as their
    trial means" of one sweep each (SYNTHETIC, 2026-12-06)."""
    from impedax.models.gap import FORCE_CONDITIONS, force_conditions_of

    total, (skin, s_skin), (screen, _) = parts
    trials = ix.make_spectrum(FREQ, total, dims=("trial",))
    one_each = remaining_impedance(trials, ix.make_spectrum(FREQ, skin, sigma=s_skin), ix.make_spectrum(FREQ, screen))
    assert force_conditions_of(one_each) == "A taken as exact; skin and screen as measured (one spectrum each), without their errors"
    mixed = remaining_impedance(trials, ix.make_spectrum(FREQ, skin), trials)
    assert force_conditions_of(mixed) == "A taken as exact; skin as measured (one spectrum), screen as its trial mean, without their errors"
    assert force_conditions_of(remaining_impedance(trials, trials, trials)) == FORCE_CONDITIONS


def test_gaps_fit_line_says_what_the_sigma_holds(parts):
    """gap's fits line said "χ²_red … against the trial means' SEM" where the remainder's sigma also
    holds the stated sigma of skin and screen files of one spectrum (SYNTHETIC, 2026-12-06)."""
    from types import SimpleNamespace

    from impedax.models.gap import _edl_chi2_text

    total, (skin, s_skin), (screen, s_screen) = parts
    trials = ix.make_spectrum(FREQ, total, dims=("trial",))
    fitted = SimpleNamespace(weighting="sigma", chi2_red=0.9)
    mixed = remaining_impedance(trials, ix.make_spectrum(FREQ, skin, sigma=s_skin), ix.make_spectrum(FREQ, screen, sigma=s_screen))
    assert "against the remainder's sigma (the SEM of the trial means of total with the stated sigma of skin and touchscreen, one spectrum each)" in _edl_chi2_text(fitted, mixed)
    assert "against the trial means' SEM" in _edl_chi2_text(fitted, remaining_impedance(trials, trials, trials))


def test_the_hierarchical_weights_leave_a_single_spectrums_stated_sigma_out(parts):
    """`trial_remainder_sigma` matches the hierarchical likelihood, which has no error modes of a
    subtracted file of one spectrum: its stated sigma stays out, as before 2026-12-06 (the trials'
    sample sd alone, by hand), though the trial-mean remainder now carries it."""
    from impedax.models.gap import trial_remainder_sigma

    total, (skin, s_skin), (screen, s_screen) = parts
    sigma = trial_remainder_sigma(ix.make_spectrum(FREQ, total, dims=("trial",)), ix.make_spectrum(FREQ, skin, sigma=s_skin), ix.make_spectrum(FREQ, screen, sigma=s_screen))
    np.testing.assert_allclose(sigma, np.sqrt((total.real.std(0, ddof=1) ** 2 + total.imag.std(0, ddof=1) ** 2) / 2), rtol=1e-12)


def test_the_pooled_interval_says_one_spectrum_per_file_with_their_stated_sigma(parts):
    """`impedax gap --pooled` of one spectrum per file, each with a sigma column, now fits by that
    sigma; its interval's words said "Bayesian on the trial means" of it (SYNTHETIC)."""
    from types import SimpleNamespace

    from impedax.models.gap import GapAnalysis

    total, (skin, s_skin), (screen, s_screen) = parts
    remainder = remaining_impedance(ix.make_spectrum(FREQ, total[0], sigma=0.005 * np.abs(total[0])), ix.make_spectrum(FREQ, skin, sigma=s_skin), ix.make_spectrum(FREQ, screen, sigma=s_screen))
    analysis = SimpleNamespace(remaining=remainder, averages_trials=False, paper_has_bounds=False)
    assert GapAnalysis._pooled_noise_text(analysis).startswith("Bayesian on one spectrum per file, weighted by their stated sigma")


@pytest.mark.parametrize("name, noted", [("rem.csv", True), ("rem.nc", False)])
def test_a_csv_remainder_is_said_to_lose_what_its_sigma_is(tmp_path, capsys, parts, name, noted):
    """A CSV keeps no attrs: `impedax fit` of it cannot tell the trial means' SEM from a sigma
    column and may warn that σ overstates the noise; `impedax remaining` says so, and .nc keeps it."""
    total = ix.make_spectrum(FREQ, parts[0], dims=("trial",))
    ix.save(total, tmp_path / "pad.nc")
    assert main(["remaining", str(tmp_path / "pad.nc"), "--out", str(tmp_path / name)]) == 0
    err = capsys.readouterr().err
    assert (f"note: {tmp_path / name} keeps no attributes" in err) is noted
    assert ("sigma_method" in ix.load(tmp_path / name).attrs) is not noted  # (what the note is about)
