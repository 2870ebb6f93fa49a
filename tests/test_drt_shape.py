"""Shape notes of the DRT (`impedax.fitting.drt.shape`, docs/drt.md "Shape notes"): a diffusion
tail (−Im Z ∝ ω^−½ at the low end: a Warburg, whose fitted γ shows fake peaks) and a peak too
broad for one R‖C at the chosen λ. SYNTHETIC spectra from numpy formulas written here: 71 points,
10 mHz–100 kHz, complex noise of relative σ `level`, fixed seeds. Oracles: the slopes' closed
forms (a Warburg's −Im Z = σ/√(2ω), an arc below its corner −Im Z ≈ Rωτ) and the width of an
ideal R‖C's own DRT at the same λ.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.drt.shape import BROAD_FACTOR, diffusion_slopes, low_frequency_tail, reference_width

F = np.logspace(-2, 5, 71)
W = 2 * np.pi * F


def rc(r, tau):
    return r / (1 + 1j * W * tau)


def noisy(z, level, seed):
    """SYNTHETIC: z with complex Gaussian noise of relative σ ``level``."""
    rng = np.random.default_rng(seed)
    return z + level * np.abs(z) * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2)


WARBURG = 10 + rc(100, 1e-3) + 50 / np.sqrt(1j * W)  # σ = 50 Ω s^-½: true γ = (σ/π)√τ, no peak
TWO_ARCS = 10 + rc(100, 1e-3) + rc(100, 10**-0.5)  # 2.5 decades apart


def test_diffusion_slopes_follow_the_closed_forms():
    """A Warburg alone: ln(−Im Z) = ln(σ/√2) − ½ ln ω exactly; an arc far below its corner:
    −Im Z = Rωτ/(1 + ω²τ²) ≈ Rωτ, slope +1; a series C: slope −1."""
    np.testing.assert_allclose(diffusion_slopes(F, 50 / np.sqrt(1j * W)), (-0.5, -0.5), atol=1e-9)
    np.testing.assert_allclose(diffusion_slopes(F, rc(100, 1e-4)), (1.0, 1.0), atol=1e-6)
    np.testing.assert_allclose(diffusion_slopes(F, 10 + 1 / (1j * W * 1e-3)), (-1.0, -1.0), atol=1e-9)


def test_warburg_tail_is_noted_and_its_peaks_are_named_not_arcs():
    """The walkthrough's case: the DRT of R‖C + 50/√(jω) shows peaks at ≈ 4 s and ≈ 60 s that
    are no arcs; the note names them and no broad-peak note is made of them."""
    result = ix.drt((F, noisy(WARBURG, 0.01, 3)))
    tail = [n for n in result.notes if "diffusion" in n]
    assert len(tail) == 1, result.notes
    slow = [p for p in result.peaks if p.tau_s > 1.0]
    assert slow, result.peaks  # the fake peaks this note is about (else the test is moot)
    assert all(ix.data.format_time(p.tau_s, 3) in tail[0] for p in slow)
    assert not any("as wide as one R‖C" in n for n in result.notes)
    assert "note: the low-frequency part looks like diffusion" in result.report()
    assert any("diffusion" in n for n in result.summary()["notes"])


def test_two_separate_arcs_get_no_shape_note():
    result = ix.drt((F, noisy(TWO_ARCS, 0.01, 4)))
    assert len(result.peaks) == 2
    assert not any("diffusion" in n or "as wide as one R‖C" in n for n in result.notes), result.notes


def test_reference_width_is_an_ideal_rc_drt_width():
    """On a single R‖C spectrum the reference (its own kind, same λ) is its peak's width."""
    result = ix.drt((F, noisy(10 + rc(100, 1e-3), 0.01, 5)))
    (peak,) = result.peaks
    assert reference_width(result, 1e-3) == pytest.approx(peak.width_decades, rel=0.05)


def test_two_rc_merged_by_a_large_lambda_get_a_broad_peak_note():
    """Two R‖C one decade apart at a fixed λ = 1 merge into one peak (as GCV's λ merged them at 5 %
    noise in the walkthrough, 1.50 decades wide); one R‖C at the same λ is not broad."""
    merged = ix.drt((F, noisy(10 + rc(100, 1e-3) + rc(100, 1e-2), 0.01, 6)), lam=1.0)
    assert len([p for p in merged.peaks if p.inside_window]) == 1
    broad = [n for n in merged.notes if "as wide as one R‖C" in n]
    assert len(broad) == 1 and "it may hold more than one relaxation" in broad[0]
    # (2026-12-02) it names what "both" are: it ended "; fit both" and left a beginner guessing
    assert broad[0].endswith("fit both there and compare them: two arcs (R‖C + R‖C) against one distributed arc (R‖CPE)"), broad[0]
    peak = max(merged.peaks, key=lambda p: p.r_ohm)
    assert peak.width_decades >= BROAD_FACTOR * reference_width(merged, peak.tau_s)
    single = ix.drt((F, noisy(10 + rc(200, 10**-2.5), 0.01, 6)), lam=1.0)
    assert not any("as wide as one R‖C" in n for n in single.notes), single.notes


def test_report_says_the_band_covers_noise_only():
    result = ix.drt((F, noisy(10 + rc(100, 1e-3), 0.01, 5)))
    assert "noise only: it leaves out the smoothing that lowers peaks" in result.report()
    assert "not the smoothing bias at peaks" in result.to_xarray().attrs["band"]


# --- a tail of another slope than a Warburg's (a walkthrough, 2026-12-02) ----------------------
# The REAL Gamry file's note said "−Im Z goes as ω^−½ … fit a Warburg"; its slope below 0.16 Hz
# is −0.37, with the phase flat at −21°: a constant-phase tail. A CPE in series,
# Z = 1/(Q (jω)^α) = ω^−α (cos(απ/2) − j sin(απ/2))/Q, has −Im Z = sin(απ/2)/(Q ω^α): slope −α.

REAL = Path(__file__).parent / "fixtures" / "real"


def series_cpe(alpha, q=1e-2):
    """SYNTHETIC: 10 Ω + R‖C (100 Ω, 1 ms) + 1/(Q (jω)^α)."""
    return 10 + rc(100, 1e-3) + 1 / (q * (1j * W) ** alpha)


def loglog_slope_below(f, z, f_top):
    """The oracle: numpy's least-squares slope of ln(−Im Z) against ln f for f ≤ f_top."""
    low = f <= f_top
    return np.polyfit(np.log(f[low]), np.log(-z.imag[low]), 1)[0]


@pytest.mark.parametrize("alpha", [0.4, 0.6, 0.7])
def test_a_series_cpe_tails_slope_is_minus_its_alpha(alpha):
    tail = low_frequency_tail(F, series_cpe(alpha))
    assert tail.slope == pytest.approx(-alpha, abs=1e-3) and tail.alpha == pytest.approx(alpha, abs=1e-3)
    assert not tail.warburg and tail.below_hz == pytest.approx(0.1)
    exact = low_frequency_tail(F, WARBURG)
    assert exact.slope == pytest.approx(-0.5, abs=1e-3) and exact.warburg


@pytest.mark.parametrize("seed", range(10))
def test_the_warburg_tolerance_tells_a_noisy_warburg_from_a_cpe_a_tenth_away(seed):
    """SYNTHETIC, 1 % noise (the constant's measurement: a Warburg of σ 50 Ω s^−½ scatters ± 0.02
    about −0.5, always called one; a CPE α 0.4 or 0.6 ± 0.02 about −α, called one in ≤ 1 %)."""
    assert low_frequency_tail(F, noisy(WARBURG, 0.01, seed)).warburg
    for alpha in (0.4, 0.6):
        tail = low_frequency_tail(F, noisy(series_cpe(alpha), 0.01, seed))
        assert tail is not None and not tail.warburg and abs(tail.slope + alpha) < 0.06


def test_the_real_gamry_tail_is_named_by_its_slope_not_as_a_warburg():
    data = ix.load(REAL / "exampleDataGamry.DTA")
    f, z = data.frequency.values, data.Z.values
    slope = loglog_slope_below(f, z, 10 * f.min() * (1 + 1e-9))
    assert slope == pytest.approx(-0.367, abs=0.005)  # the walkthrough's −0.38 below 0.16 Hz
    result = ix.drt(data)
    (note,) = [n for n in result.notes if "low-frequency part" in n]
    assert note.startswith(f"the low-frequency part is a constant-phase tail: −Im Z goes as ω^−{-slope:.2f} (± ")
    assert f"below 0.159 Hz, not a Warburg's ω^−0.5; a CPE in series has −Im Z ∝ ω^−α, here α ≈ {-slope:.2f}" in note
    assert "ω^−½" not in note and "diffusion" not in note
    suggestion = result.suggested_circuit()
    assert "W1" not in suggestion.model and suggestion.model.endswith(" + CPE2")
    alpha, q = suggestion.init["CPE2.alpha"], suggestion.init["CPE2.Q"]
    assert alpha == pytest.approx(-slope, abs=1e-6)
    # the start's −Im Z = sin(απ/2)/(Q ω^α) meets the data's at the lowest frequency within 15 %
    low = np.argmin(f)
    assert math.sin(alpha * math.pi / 2) / (q * (2 * math.pi * f[low]) ** alpha) == pytest.approx(-z.imag[low], rel=0.15)
    assert any("constant-phase tail (the tail's CPE holds it)" in r for r in suggestion.reasons)


def test_the_real_warburg_tail_of_impedance_pys_example_keeps_its_warburg():
    data = ix.load(REAL / "exampleData.csv")
    f, z = data.frequency.values, data.Z.values
    slope = loglog_slope_below(f, z, 10 * f.min() * (1 + 1e-9))
    assert slope == pytest.approx(-0.515, abs=0.005)
    result = ix.drt(data)
    (note,) = [n for n in result.notes if "low-frequency part" in n]
    assert note.startswith(f"the low-frequency part looks like diffusion (a Warburg element): −Im Z goes as ω^−{-slope:.2f} (± ")
    assert "a Warburg's ω^−0.5" in note and result.suggested_circuit().model.endswith(" + W1")


def test_a_broad_peak_not_told_from_zero_gets_no_broad_peak_note():
    """The merged peak of the test above, marked as not told from zero (a ripple the report
    lists but does not count): it gets no advice to fit two arcs there."""
    import dataclasses

    merged = ix.drt((F, noisy(10 + rc(100, 1e-3) + rc(100, 1e-2), 0.01, 6)), lam=1.0)
    assert any("as wide as one R‖C" in n for n in merged.notes)
    ripples = dataclasses.replace(merged, peaks=tuple(dataclasses.replace(p, resolved=False) for p in merged.peaks))
    assert not any("as wide as one R‖C" in n for n in ripples.notes), ripples.notes
