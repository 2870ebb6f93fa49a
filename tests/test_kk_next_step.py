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
    assert f"(the point at {format_frequency(FREQ[BAD])})" in band_line  # "316 Hz", not only the edges
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
    assert "verdict: valid" in out and "next:" not in out
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
    assert lines[0].startswith(f"linear KK test: M = {result.n_rc} RC elements, µ = {result.mu:.3f} (µ < c = {result.c:g}: few negative R")
    assert "a chain of M R‖C in series" in lines[1] and "Schönleber et al. 2014" in lines[1]
    assert lines[2].startswith(f"rms_rel = {result.rms_rel * 100:.3g} % (the chain's misfit relative to |Z|")
