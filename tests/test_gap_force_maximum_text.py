"""How the gap report words the largest force: a peak inside the band, an end of the band, a
plateau, a flat force. Forces are SYNTHETIC numpy curves over a log grid (no fit)."""

from __future__ import annotations

import numpy as np
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
    assert text.startswith("407 mN on a plateau over 1 Hz–") and text.endswith("(within 1%; largest at 1 Hz, the band's lower end)")


def test_a_force_rising_past_the_band_says_so():
    force = 0.1 * (FREQ / 1e6) ** 0.5  # (rises to the top of the band and past it: no plateau)
    assert force_maximum_shape(_median(force)) == {"index": FREQ.size - 1, "band_edge": "fmax", "plateau_hz": None}
    assert force_maximum_text(_median(force)) == "max 100 mN at 1 MHz, the band's upper end (it may rise past it)"


def test_a_flat_force_keeps_its_every_frequency_wording():
    assert force_maximum_text(_median(np.full(FREQ.size, 2.835))) == "2.83 N at every frequency (1 Hz–1 MHz)"


def test_a_flat_force_has_no_band_end_in_its_shape():
    """A single contact's force, ½ ε0 ε_gap A V0²/u², is the same at every frequency: its JSON
    ``force_max_n.band_edge`` said "fmin" (the force "may still rise past" 1 Hz) where the report
    said "at every frequency"; now "flat", the word of `impedax force`'s JSON for such a force."""
    shape = force_maximum_shape(_median(np.full(FREQ.size, 2.835)))
    assert shape["band_edge"] == "flat" and shape["index"] == 0 and shape["plateau_hz"] == (1.0, 1e6)
