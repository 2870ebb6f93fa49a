"""How the gap report words the largest force: a peak inside the band, an end of the band, a
plateau, a flat force. Forces are SYNTHETIC numpy curves over a log grid (no fit)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from impedax.models.gap import force_maximum_text, force_maximum_shape

FREQ = np.geomspace(1.0, 1e6, 61)


def _median(values):
    return xr.DataArray(np.asarray(values, float), dims="frequency", coords={"frequency": FREQ})


def test_a_peak_inside_the_band_is_a_max_at_its_frequency():
    force = 0.36 * np.exp(-0.5 * ((np.log10(FREQ) - 1.5) / 0.6) ** 2)  # (peak at 10^1.5 = 31.6 Hz, a grid point)
    shape = force_maximum_shape(_median(force))
    assert shape["band_edge"] is None and shape["plateau_hz"] is None
    assert force_maximum_text(_median(force)) == "max 360 mN at 31.6 Hz"


def test_a_plateau_at_the_band_end_is_named_as_one():
    """The force without EP: V_gap → V0 below the screen's corner, so F = F0 / (1 + (f/fc)²) with
    fc = 30 kHz is within 1 % of F0 up to fc/10 ≈ 3 kHz (1/(1 + 0.01) = 0.990)."""
    f0, fc = 0.407, 3e4
    force = f0 / (1.0 + (FREQ / fc) ** 2)
    shape = force_maximum_shape(_median(force))
    low, high = shape["plateau_hz"]
    assert shape["band_edge"] == "fmin" and low == 1.0
    assert 2e3 <= high <= fc * np.sqrt(1 / 0.99 - 1)  # (the last grid point with F ≥ 0.99 F0: fc·√(1/0.99 − 1) = 3.0 kHz)
    text = force_maximum_text(_median(force))
    assert text.startswith("407 mN on a plateau over 1 Hz–") and text.endswith("(within 1 %; largest at 1 Hz, the band's lower end)")


def test_a_force_rising_past_the_band_says_so():
    """∝ f^0.5: d ln F/d ln f = 0.5 over every grid step; said as `impedax force` says it (until
    2026-12-06 "(it may rise past it)" whatever the slope)."""
    force = 0.1 * (FREQ / 1e6) ** 0.5  # (rises to the top of the band and past it: no plateau)
    shape = force_maximum_shape(_median(force))
    assert shape == {"index": FREQ.size - 1, "band_edge": "fmax", "plateau_hz": None, "edge_slope": pytest.approx(0.5, rel=1e-12)}
    assert force_maximum_text(_median(force)) == "max 100 mN at 1 MHz, the band's upper end, and still rises above it (∝ f^0.5 there)"
    # the lower end of a force falling with frequency, ∝ f^-2
    assert force_maximum_text(_median(0.3 * FREQ ** -2.0)) == "max 300 mN at 1 Hz, the band's lower end, and still rises below it (∝ f^-2 there)"


def test_a_force_levelled_off_at_the_band_end_says_so():
    """F = 0.2 N/(1 + (fc/f)²), fc = 1 MHz/30: within 1 % of its largest only from 316 kHz (less
    than a decade: no plateau), and levelled off at 1 MHz, where over the grid's last step (0.1
    decade) ln F changes by ln(1 + 1/900·10^0.2) − ln(1 + 1/900) = 6.489e-4, a slope of
    6.489e-4/ln 10^0.1 = 2.818e-3, 10^2.818e-3 − 1 = 0.651 % per decade (by hand). It read "(it may
    rise past it)", as of a force still growing."""
    force = 0.2 / (1.0 + (1e6 / 30 / FREQ) ** 2)
    shape = force_maximum_shape(_median(force))
    assert shape["band_edge"] == "fmax" and shape["plateau_hz"] is None
    assert shape["edge_slope"] == pytest.approx(2.818e-3, rel=1e-3)
    assert force_maximum_text(_median(force)) == ("max 200 mN at 1 MHz, the band's upper end, where it has levelled off: it changes by 0.651 % "
                                                 "per decade there (it may still rise above 1 MHz, as slowly)")


def test_a_flat_force_keeps_its_every_frequency_wording():
    assert force_maximum_text(_median(np.full(FREQ.size, 2.835))) == "2.83 N at every frequency (1 Hz–1 MHz)"


def test_a_flat_force_has_no_band_end_in_its_shape():
    """A single contact's force, ½ ε0 ε_gap A V0²/u², is the same at every frequency: its JSON
    ``force_max_n.band_edge`` said "fmin" (the force "may still rise past" 1 Hz) where the report
    said "at every frequency"; now "flat", the word of `impedax force`'s JSON for such a force."""
    shape = force_maximum_shape(_median(np.full(FREQ.size, 2.835)))
    assert shape["band_edge"] == "flat" and shape["index"] == 0 and shape["plateau_hz"] == (1.0, 1e6)
