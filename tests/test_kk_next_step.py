"""`impedax kk`'s bad points and next step: a band of a few points names the measured
frequencies (its edges lie halfway to the neighbours, which --exclude does not take), the report
ends with the command that leaves the failing points out (--exclude inside the range, --fmin or
--fmax at an end), that command runs and passes, and lone points just over the point level are
called the place to stop. Spectra are SYNTHETIC (numpy formulas written here, fixed seeds)."""

from __future__ import annotations

import dataclasses
import json
import math
import shlex

import numpy as np
import pytest

import impedax as ix
from impedax.data import format_frequency
from cli_run import run

# SYNTHETIC: 100 Ω + 1 kΩ ‖ 1 µF (τ = 1 ms), 41 points from 100 kHz to 1 Hz (8 a decade), 0.5 % noise
FREQ = np.geomspace(1e5, 1.0, 41)
BAD = 20  # 316 Hz, inside the range


def rc_spectrum(seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    z = 100.0 + 1000.0 / (1.0 + 1j * 2 * np.pi * FREQ * 1e-3)
    return z * (1.0 + 0.005 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)) / math.sqrt(2))


def saved(tmp_path, z, name="spectrum.csv"):
    path = tmp_path / name
    np.savetxt(path, np.column_stack([FREQ, z.real, z.imag]), delimiter=",", header="freq,zreal,zimag", comments="")
    return path


def one_corrupted(seed: int = 0) -> np.ndarray:
    z = rc_spectrum(seed)
    z[BAD] *= 1.2  # one point 20 % off
    return z


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_point_20_percent_off_is_a_band_of_that_one_point(seed):
    assert ix.kk_test((FREQ, rc_spectrum(seed))).valid  # (the clean spectrum passes)
    result = ix.kk_test((FREQ, one_corrupted(seed)))
    assert result.band_frequencies == ((FREQ[BAD],),)
    lo, hi = result.bad_bands[0]
    assert lo < FREQ[BAD] < hi and lo > FREQ[BAD + 1] and hi < FREQ[BAD - 1]
    band_line = next(line for line in result.report().splitlines() if line.startswith("  bad band:"))
    assert band_line.startswith(f"  bad band: the point at {format_frequency(FREQ[BAD])}:")  # "316 Hz", the measured point, not the halfway edges
    assert result.suggested_options == ["--exclude", "316"]


def test_the_suggested_exclude_command_runs_and_passes(tmp_path, capsys):
    path = saved(tmp_path, one_corrupted())
    code, out, _ = run(["kk", path], capsys)
    assert code == 0 and "NOT valid" in out
    command = next(line for line in out.splitlines() if line.startswith("next:")).split(": ", 2)[-1]
    argv = shlex.split(command)
    assert argv[:3] == ["impedax", "kk", str(path)] and argv[3:] == ["--exclude", "316"]
    code, out, err = run(argv[1:], capsys)
    assert code == 0, err
    assert "verdict: valid" in out and [line for line in out.splitlines() if line.startswith("next:")] == [
        f"next: impedax drt {path} --exclude 316 (how many arcs; it ends with a starting circuit to fit)"]  # (no further point to leave out; the DRT next: 2026-12-07)
    code, out, _ = run(["kk", path, "--json"], capsys)
    payload = json.loads(out)
    assert payload["suggested_options"] == ["--exclude", "316"] and payload["bad_band_frequencies_hz"] == [[pytest.approx(FREQ[BAD])]]
    assert payload["bad_bands_hz"] and payload["marginal_points_only"] is False  # (the old keys stay)
    # the same options in `impedax fit` (it parses --exclude the same way)
    code, _, err = run(["fit", path, "--model", "R0-p(R1,C1)", *payload["suggested_options"]], capsys)
    assert code == 0, err


def test_a_run_s_own_exclude_is_merged_into_the_suggestion(tmp_path, capsys):
    z = one_corrupted()
    z[30] *= 0.8  # a second point off (17.8 Hz); the user already left out 316 Hz
    path = saved(tmp_path, z)
    code, out, _ = run(["kk", path, "--exclude", "316", "--json"], capsys)
    assert json.loads(out)["suggested_options"] == ["--exclude", "316,17.8"]  # (argparse keeps only the last --exclude)
    code, out, _ = run(["kk", path, "--exclude", "316"], capsys)
    argv = shlex.split(next(line for line in out.splitlines() if line.startswith("next:")).split(": ", 2)[-1])
    code, out, err = run(argv[1:], capsys)
    assert code == 0 and "verdict: valid" in out, err


def test_a_band_at_the_low_end_gets_fmin(tmp_path, capsys):
    z = rc_spectrum(3)
    z[-4:] *= 1.0 + np.array([0.05, 0.10, 0.15, 0.20])  # SYNTHETIC drift over the last (lowest) 4 points
    result = ix.kk_test((FREQ, z))
    assert result.bad_bands and result.bad_bands[0][0] == FREQ[-1]  # a band from the lowest frequency
    words = result.suggested_options
    assert words[0] == "--fmin" and "--exclude" not in words
    fmin = float(words[1])
    assert max(result.band_frequencies[0]) < fmin <= FREQ[FREQ > max(result.band_frequencies[0])].min()
    path = saved(tmp_path, z)
    code, out, _ = run(["kk", path], capsys)
    argv = shlex.split(next(line for line in out.splitlines() if line.startswith("next:")).split(": ", 2)[-1])
    assert argv[3] == "--fmin"
    code, out, err = run(argv[1:], capsys)
    assert code == 0 and "verdict: valid" in out, err


def test_lone_points_just_over_the_level_are_where_to_stop():
    """The rule on hand-set residuals: one point at 5.5 s (level 5 s, marginal below 6 s) is
    where to stop; at 8 s it is to be left out."""
    clean = ix.kk_test((FREQ, rc_spectrum()))
    s = clean.threshold_scale
    for size, marginal in ((5.5, True), (8.0, False)):
        real = np.zeros(FREQ.size)
        real[BAD] = size * s
        flagged = np.zeros(FREQ.size, bool)
        flagged[BAD] = True
        lo, hi = math.sqrt(FREQ[BAD] * FREQ[BAD + 1]), math.sqrt(FREQ[BAD] * FREQ[BAD - 1])
        result = dataclasses.replace(clean, residuals_real=real, residuals_imag=np.zeros(FREQ.size), flagged=flagged, valid=False, bad_bands=((lo, hi),))
        assert result.marginal_points_only is marginal
        last = result.report().splitlines()[-1]
        assert ("stop leaving points out" in last) is marginal and ("5.5 s" in last) is marginal
        # the verdict agrees with the next step: a marginal point is not called proof of KK inconsistency
        verdict = next(line for line in result.report().splitlines() if line.startswith("verdict:"))
        assert ("only just: an isolated point barely over its level" in verdict) is marginal
        assert ("NOT valid: data are not KK-consistent" in verdict) is not marginal


def test_a_valid_spectrum_has_no_next_step():
    result = ix.kk_test((FREQ, rc_spectrum()))
    assert result.suggested_options == [] and result.band_frequencies == () and "next:" not in result.report()
    assert result.summary()["suggested_options"] == [] and result.summary()["bad_band_frequencies_hz"] == []


def test_the_report_says_what_m_mu_and_rms_rel_are():
    """A beginner met "M = 9 RC elements, µ = 0.745" and the chain's rms_rel unexplained: the
    report says what the chain is, what µ < c means, and what its rms_rel stands for (REAL ZPlot
    file, impedance.py's example data)."""
    import os

    result = ix.kk_test(ix.load(os.path.join(os.path.dirname(__file__), "fixtures", "real", "exampleDataZPlot.z")))
    lines = result.report().splitlines()
    r = result.resistances
    assert result.mu > 2 * result.c - 1  # (µ just below c: the onset of negative R)
    assert lines[0].startswith(f"linear KK test: M = {result.n_rc} RC elements, µ = {result.mu:.3f} (µ < c = {result.c:g}: negative R are starting to appear "
                               f"({np.count_nonzero(r < 0)} of {r.size} R negative, Σ|R<0| = {-r[r < 0].sum() / r[r >= 0].sum() * 100:.0f} % of Σ R≥0)")
    assert "a chain of M R‖C in series" in lines[1] and "Schönleber et al. 2014" in lines[1]
    assert lines[2].startswith(f"rms_rel = {result.rms_rel * 100:.3g} % (the chain's misfit relative to |Z|: about what a sound model can reach")


REAL = __import__("pathlib").Path(__file__).parent / "fixtures" / "real"


def test_mu_far_below_c_is_read_as_many_negative_r():
    """REAL exampleData.csv without the series C (walkthrough 77b): M = 32, µ = 0.038, 16 of 32
    R_k negative; the report had said "few negative R ... follows the data, not their noise"."""
    result = ix.kk_test(ix.load(REAL / "exampleData.csv"), capacitance=False)
    r = result.resistances
    negative, positive = -r[r < 0].sum(), r[r >= 0].sum()
    assert result.mu == pytest.approx(1 - negative / positive, rel=1e-9) and result.mu < 0.2  # Schönleber 2014 eq 21
    first = result.report().splitlines()[0]
    assert f"(µ far below c = 0.85: many negative R ({np.count_nonzero(r < 0)} of {r.size} R negative, Σ|R<0| = {negative / positive * 100:.0f} % of Σ R≥0)" in first
    assert "the chain may follow the noise at this M" in first and "not yet their noise" not in first and "few negative" not in first


def test_mu_far_below_c_on_noise_free_data_names_the_grid_not_only_noise():
    """SYNTHETIC, noise-free 10 Ω + 100 Ω‖1 µF (closed form), 61 points 1 Hz–1 MHz: µ falls far
    below c with no noise to follow (negative R make up for the τ grid missing τ = 100 µs), and
    the line says that reading too."""
    freq = np.geomspace(1.0, 1e6, 61)
    z = 10.0 + 100.0 / (1 + 1j * 2 * np.pi * freq * 1e-4)
    result = ix.kk_test((freq, z))
    assert result.mu < 0.7 and bool(result.valid)
    first = result.report().splitlines()[0]
    assert "µ far below c" in first and "fixed τ grid missing the data's time constants, as on noise-free data" in first


@pytest.mark.parametrize("resistances, words", [
    ([60.0, 40.0, -20.0], "µ < c = 0.85: negative R are starting to appear (1 of 3 R negative, Σ|R<0| = 20 % of Σ R≥0), Schönleber's sign"),  # µ = 0.80
    ([60.0, 40.0, -29.0], "µ < c = 0.85: negative R are starting to appear (1 of 3 R negative, Σ|R<0| = 29 % of Σ R≥0)"),  # µ = 0.71
    ([60.0, 40.0, -31.0], "µ far below c = 0.85: many negative R (1 of 3 R negative, Σ|R<0| = 31 % of Σ R≥0): the chain may follow the noise"),  # µ = 0.69
])
def test_the_mu_words_follow_the_negative_share(resistances, words):
    """Hand numbers on a SYNTHETIC result: µ = 1 − 20/100 just below c reads as the onset; past
    twice the 1 − c = 15 % the cut-off allows (µ ≤ 0.7) as a chain that may follow the noise."""
    clean = ix.kk_test((FREQ, rc_spectrum()))
    r = np.array(resistances)
    mu = 1 - (-r[r < 0].sum()) / r[r >= 0].sum()
    result = dataclasses.replace(clean, resistances=r, mu=mu, mu_reached=True)
    assert words in result.report().splitlines()[0]
    fixed = dataclasses.replace(result, n_rc_given=True).report().splitlines()[0]
    assert "Choosing M" not in fixed and ("Schönleber's sign" not in fixed)


def test_a_near_c_synthetic_chain_reads_as_the_onset():
    """SYNTHETIC 100 Ω + 1 kΩ‖1 ms, 61 points from 100 kHz to 0.1 Hz, 0.5 % noise, seed 1: the
    chain's µ lies just below c (0.82 when written), and the report says negative R are starting."""
    rng = np.random.default_rng(1)
    freq = np.logspace(-1, 5, 61)
    z = (100 + 1000 / (1 + 1j * 2 * np.pi * freq * 1e-3)) * (1 + 0.005 * (rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size)))
    result = ix.kk_test((freq, z))
    r = result.resistances
    share = -r[r < 0].sum() / r[r >= 0].sum()
    assert result.valid and result.mu < 0.85 and share < 2 * 0.15
    assert f"negative R are starting to appear ({np.count_nonzero(r < 0)} of {r.size} R negative, Σ|R<0| = {share * 100:.0f} % of Σ R≥0)" in result.report()


def test_the_report_names_the_stray_points_left_out_of_the_chain():
    """A point 20 % off (SYNTHETIC, `one_corrupted`) is left out of the chain's fit: the report
    and the JSON (``stray_points_hz``) name it; a clean spectrum has none."""
    result = ix.kk_test((FREQ, one_corrupted()))
    np.testing.assert_array_equal(result.stray_frequencies, [FREQ[BAD]])
    assert json.loads(json.dumps(result.summary(), default=list))["stray_points_hz"] == [FREQ[BAD]]
    assert f"left out of the chain's fit as stray (lone spikes over the point level): {format_frequency(FREQ[BAD])};" in result.report()
    clean = ix.kk_test((FREQ, rc_spectrum()))
    assert clean.stray_frequencies.size == 0 and "left out of the chain's fit" not in clean.report()


def test_gamrys_report_does_not_praise_its_misfit_nor_call_a_drifts_end_a_lone_spike():
    """REAL Gamry file (walkthrough 77b): rms_rel stood next to "NOT valid" as "about what a
    sound model can reach". Its lowest point, 15.9 mHz, was left out as a lone spike until
    2026-12-05, though it ends a band of 32 points over the point level: against the chain
    without it, its neighbour stays over that level (`kk._neighbours_off`), so the test keeps it
    and judges the band as a whole (rms_rel 4.79 %, the figure of the chain on every point)."""
    data = ix.load(REAL / "exampleDataGamry.DTA")
    result = ix.kk_test(data)
    assert not result.valid and result.stray_frequencies.size == 0
    assert result.bad_bands[0][0] == pytest.approx(float(data.frequency.min()))
    text = result.report()
    assert "left out of the chain's fit" not in text and abs(result.rms_rel - 0.0479) < 0.0005
    assert "sound model can reach" not in text and "failing points included: no circuit is expected to fit closer" in text


def test_the_end_of_a_drift_is_no_stray_point():
    """SYNTHETIC R0 + R1 ∥ C1 + R2 ∥ C2 on 71 points, 0.3 % noise, +8 % falling to 0 over the 15
    lowest points (the walkthrough's case): 10 mHz was left out "as a lone spike", 2.4 times its
    neighbour, whose own |Δ| stayed 1.7 times the point level. Now none is; a lone +20 % point
    in the same spectrum without the drift still is (the oracle of what a lone spike is)."""
    freq = np.geomspace(0.01, 1e5, 71)
    omega = 2 * np.pi * freq
    z = 10 + 100 / (1 + 1j * omega * 1e-3) + 300 / (1 + 1j * omega * 3.0)
    rng = np.random.default_rng(1)
    z = z * (1 + 0.003 * (rng.standard_normal(71) + 1j * rng.standard_normal(71)) / np.sqrt(2))
    drift = np.zeros(71)
    drift[:15] = 0.08 * np.linspace(1, 0, 15)
    drifted = ix.kk_test((freq, z * (1 + drift)))
    assert not drifted.valid and drifted.stray_frequencies.size == 0
    assert drifted.bad_bands[0][0] == pytest.approx(freq[0])
    spiked = z.copy()
    spiked[35] *= 1.2
    assert list(ix.kk_test((freq, spiked)).stray_frequencies) == [freq[35]]


def test_a_sparse_files_chain_misfit_is_no_bound_for_a_circuit():
    """The six-point instrument file (1.2 points a decade): the chain's rms_rel 19.9 % stood
    beside "inconclusive" as "about what a sound model can reach", where 100 Ω + 1 kΩ/(1 + jω·1 ms),
    written here, meets the same points to 2e-8 (walkthrough, 2026-12-05)."""
    data = ix.load(REAL.parent / "biologic_peis.mpt")
    f, z = data.frequency.values, data.Z.values
    closed_form = 100.0 + 1000.0 / (1 + 2j * np.pi * f * 1e-3)
    assert np.sqrt(np.mean(np.abs((z - closed_form) / z) ** 2)) < 1e-6
    result = ix.kk_test(data)
    assert result.sparse_note and not result.conclusive and result.rms_rel > 0.1
    line = result.report().splitlines()[2]
    assert "sound model can reach" not in line
    assert "the chain's own approximation" in line and "no bound for a circuit" in line
    assert f"{result.chain_error * 100:.2g} %" in line


def test_biologics_report_names_the_flagged_point_that_was_no_stray_and_its_retest_is_marginal():
    """REAL BioLogic file: three points were left out as stray, four were flagged and
    `--exclude` named four, the fourth (123 Hz) unexplained; testing again without them called
    one point at 5.03 s both "NOT valid: data are not KK-consistent" and "the tail of the data's
    own scatter" (walkthrough, 2026-12-05)."""
    data = ix.load(REAL / "exampleDataBioLogic.mpt")
    result = ix.kk_test(data)
    flagged = set(np.round(result.frequency[result.flagged], 6))
    strays = set(np.round(result.stray_frequencies, 6))
    (kept,) = sorted(flagged - strays)  # by hand: the flagged points the chain was fitted with
    assert format_frequency(float(kept)) == "123 Hz"
    stray_line = next(line for line in result.report().splitlines() if line.startswith("left out of the chain's fit"))
    assert "123 Hz, kept in it, fails against it too" in stray_line
    again = ix.kk_test(data.sel(frequency=~np.isin(np.round(data.frequency.values, 6), sorted(flagged))))
    assert again.marginal_points_only
    text = again.report()
    assert "NOT valid: data are not KK-consistent" not in text and "only just" in text and "stop leaving points out" in text


def test_a_band_at_an_end_too_wide_to_leave_out_is_said_so():
    """REAL Gamry: one band at the low end, 52 of 72 points (15.9 mHz–2.02 kHz), found no passing
    band; the report ended "next: the bands: too many points to leave out one by one", as of a
    disturbance inside the range, where --fmin would leave them out at once but keep fewer than
    half of the points. Oracle: the file's frequencies, counted from the lowest through the highest
    the test flags."""
    from pathlib import Path

    data = ix.load(Path(__file__).parent / "fixtures" / "real" / "exampleDataGamry.DTA")
    result = ix.kk_test(data, find_passing_band=True)
    f = np.sort(data["frequency"].values)
    top = f[np.flatnonzero(np.isin(f, result.frequency[result.flagged]))].max()
    n_end = int(np.count_nonzero(f <= top))
    assert (n_end, f.size) == (52, 72)
    (line,) = [x for x in result.report().splitlines() if x.startswith("next:")]
    assert "one by one" not in line and "the bands" not in line, line
    assert f"{format_frequency(f[0])} – {format_frequency(top)}" in line and f"{n_end} of {f.size} points" in line, line
    assert "fewer than half" in line, line


def test_the_flagged_points_a_passing_band_clears_are_named_run_by_run():
    """REAL CH Instruments passes on 4.64 Hz–82.5 kHz; the points flagged within it lie in two runs,
    4.64 Hz–684 Hz and 56.2 kHz–82.5 kHz, with the unflagged decades between, and the report named
    them "(4.64 Hz–82.5 kHz)", the whole band. Oracle: the file's frequencies and the test's flags,
    split where an unflagged point lies between two flagged ones."""
    from pathlib import Path

    from impedax.data import format_band

    result = ix.kk_test(ix.load(Path(__file__).parent / "fixtures" / "real" / "exampleDataCHInstruments.txt"), find_passing_band=True)
    lo, hi = result.passing_band
    order = np.argsort(result.frequency)
    f, flagged = result.frequency[order], np.asarray(result.flagged, bool)[order]
    inside = np.flatnonzero(flagged & (f >= lo) & (f <= hi))
    runs = np.split(inside, np.flatnonzero(np.diff(inside) > 1) + 1)
    assert len(runs) == 2
    (line,) = [x for x in result.report().splitlines() if "flagged within it" in x]
    named = line.split("flagged within it (")[1].split(")")[0]
    assert named == ", ".join(format_band(f[r[0]], f[r[-1]]) for r in runs), line
