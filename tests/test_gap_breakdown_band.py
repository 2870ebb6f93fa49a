"""The air-breakdown warning of the gap analysis reads the gap-voltage band (median and 90 %
interval at the force's peak) against air's Paschen minimum, so an interval whose upper end
crosses it is warned even when the median does not (2026-12-01). The oracle is the node
equations of docs/physics.md (Sirin §2.4) in numpy."""

import numpy as np
import pytest

from impedax.models.gap import _force_bands, _gap_breakdown_notes
from impedax.models.plausible import AIR_BREAKDOWN_V

EPS0 = 8.8541878128e-12  # vacuum permittivity [F/m], CODATA 2018
EPS_GAP = 1.00059  # air's relative permittivity (docs/physics.md, Sirin et al.)
AREA = 130e-6  # Sirin et al.'s apparent contact area [m²]
FREQ = np.logspace(0, 6, 25)


def parallel_rc(r, c, freq):
    return r / (1 + 2j * np.pi * freq * r * c)


# SYNTHETIC posterior draws of the EDL model R_EP || C_gap: u lognormal about 3 µm (30 %),
# R_EP about 1 MΩ; skin and touchscreen trial means as R || C
RNG = np.random.default_rng(20261201)
U_DRAWS = 3e-6 * np.exp(0.3 * RNG.standard_normal(400))
DRAWS = {"R_EP": 1e6 * np.exp(0.2 * RNG.standard_normal(400)), "C_gap": EPS0 * EPS_GAP * AREA / U_DRAWS}
Z_SKIN = parallel_rc(1e5, 1e-9, FREQ)
Z_TS = parallel_rc(1e6, 2e-9, FREQ)


def oracle(v0):
    """Per draw and frequency: |ΔV_gap| [V] and the PEAK force [N]. Node voltages: I = V0/Z_total,
    V1 = V0 − Z_TS I, V2 = Z_skin I, ΔV = V1 − V2, all of it across C_gap (R_EP || C_gap is one
    parallel pair); F = ½ ε0 ε_gap A |ΔV|²/u² (eq 1)."""
    w = 2 * np.pi * FREQ
    z_r = 1 / (1 / DRAWS["R_EP"][:, None] + 1j * w * DRAWS["C_gap"][:, None])
    current = v0 / (Z_TS + z_r + Z_SKIN)
    volts = np.abs((v0 - Z_TS * current) - Z_SKIN * current)
    force = 0.5 * EPS0 * EPS_GAP * AREA * volts**2 / U_DRAWS[:, None] ** 2
    return volts, force


def at_force_peak(v0):
    """The oracle's (median, q05, q95) of |ΔV_gap| at the peak of the median force."""
    volts, force = oracle(v0)
    i = int(np.argmax(np.median(force, axis=0)))
    return i, np.quantile(volts[:, i], [0.5, 0.05, 0.95])


def notes_for(v0):
    force = _force_bands(DRAWS, FREQ, Z_SKIN, Z_TS, "R_EP || C_gap", area=AREA, v0=v0, eps_gap=EPS_GAP)
    i, (median, low, high) = at_force_peak(v0)
    band = force.sel(branch="with_ep")
    assert int(np.argmax(band["median"].values)) == i
    np.testing.assert_allclose([band[f"gap_voltage_{k}"].values[i] for k in ("median", "q05", "q95")], [median, low, high], rtol=1e-9)
    return _gap_breakdown_notes(force, float(np.median(U_DRAWS)), AREA, EPS_GAP), (median, low, high)


def test_upper_end_of_the_interval_above_breakdown_is_warned():
    _, (m1, _, h1) = at_force_peak(1.0)
    assert h1 / m1 > 1.05  # (the case is built with an interval wide enough to straddle: 0.74–0.80 V per volt of drive)
    v0 = AIR_BREAKDOWN_V / np.sqrt(m1 * h1)  # median below 330 V, q95 above (|ΔV| ∝ V0)
    notes, (median, low, high) = notes_for(v0)
    assert median < AIR_BREAKDOWN_V < high
    assert len(notes) == 1
    assert f"carries {median:.3g} V (90 % interval {low:.3g}–{high:.3g} V)" in notes[0]
    assert f"upper end of the 90 % interval ({high:.3g} V) is above it" in notes[0] and "may spark" in notes[0]


def test_median_above_breakdown_is_warned_with_its_interval():
    _, (m1, _, _) = at_force_peak(1.0)
    notes, (median, low, high) = notes_for(1.2 * AIR_BREAKDOWN_V / m1)
    assert len(notes) == 1 and f"carries {median:.3g} V (90 % interval {low:.3g}–{high:.3g} V)" in notes[0]
    assert "above the ~330 V at which air breaks down" in notes[0] and "would spark" in notes[0]


def test_interval_below_breakdown_gives_no_warning():
    _, (_, _, h1) = at_force_peak(1.0)
    notes, (_, _, high) = notes_for(0.9 * AIR_BREAKDOWN_V / h1)
    assert high == pytest.approx(0.9 * AIR_BREAKDOWN_V, rel=1e-9) and notes == []
