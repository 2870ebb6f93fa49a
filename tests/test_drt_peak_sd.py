"""A DRT peak's ``log10_tau_sd`` against the spread of its τ over repeated noisy spectra (the
oracle: 40 SYNTHETIC copies of a closed-form two-arc spectrum, 1 % noise, seed fixed). The draws'
peaks were taken on the output grid alone (20 points a decade), so on clean data they all fell
on one point and the sd was exactly 0 ("±0.00 dec"); they are now interpolated as τ is."""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix

FREQ = np.geomspace(0.1, 1e5, 41)
OMEGA = 2 * np.pi * FREQ
# SYNTHETIC 10 Ω + 100 Ω (τ 1 ms) + 200 Ω (τ 0.1 s), both well inside the τ window
TRUTH = 10 + 100 / (1 + 1j * OMEGA * 1e-3) + 200 / (1 + 1j * OMEGA * 0.1)


def test_the_tau_sd_is_not_quantised_by_the_grid():
    rng = np.random.default_rng(5)
    z = TRUTH * (1 + 0.003 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)) / np.sqrt(2))
    result = ix.drt((FREQ, z))
    sds = [p.log10_tau_sd for p in result.peaks]
    assert len(sds) == 2 and all(0 < sd < 0.05 for sd in sds), sds  # (below the grid's 0.05-decade step, above 0)
    assert "±0.00 dec" not in result.report() and "±0 dec" not in result.report()
    assert f"±{result.peaks[0].log10_tau_sd:.2g} dec)" in result.report()  # (two significant digits: 0.004 read "±0.00")


def test_the_tau_sd_covers_the_spread_over_repeated_spectra():
    """Measured when written: spread 0.0019 and 0.0029 dec against a reported median of 0.0091
    and 0.018 (the draws come from GCV's λ, which oversmooths on purpose, docs/drt.md). Bounds:
    the reported sd at least the spread (it covers the noise) and within 30× of it (it is
    not a number of another scale)."""
    rng = np.random.default_rng(7)
    noisy = TRUTH * (1 + 0.01 * (rng.standard_normal((40, FREQ.size)) + 1j * rng.standard_normal((40, FREQ.size))) / np.sqrt(2))
    batch = ix.drt(ix.make_spectrum(FREQ, noisy, dims=("copy",)))
    for tau in (1e-3, 0.1):
        nearest = [min(r.peaks, key=lambda p: abs(np.log(p.tau_s / tau))) for r in batch.results]
        spread = np.std([np.log10(p.tau_s) for p in nearest])
        reported = np.median([p.log10_tau_sd for p in nearest])
        assert abs(np.mean([np.log10(p.tau_s) for p in nearest]) - np.log10(tau)) < 0.05
        assert spread <= reported <= 30 * spread, (tau, spread, reported)


def test_the_report_says_what_the_peaks_plus_minus_hold():
    report = ix.drt((FREQ, TRUTH)).report()
    assert "2 peak(s) (± from the noise alone: the smoothing's bias, at times larger, is not in it):" in report
