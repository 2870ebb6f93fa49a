"""`impedax.models.force_maximum`: the largest force over a band, refined between grid points,
against closed forms and a dense grid of Meyer's eq 3.6 (thesis values: 164.2 mN at 37 kHz)."""

import math

import numpy as np
import pytest

import impedax as ix
from impedax.errors import ParameterError
from impedax.models import ForceMaximum, force_maximum, meyer_force

THESIS = {"C_s": 140e-12, "C_i": 1.7e-9, "R_sc": 130e3, "C_sc": 2.2e-9, "R_f": 500.0}
AREA = math.pi * 0.004**2


def test_a_peak_between_grid_points_of_a_lorentzian_in_ln_f():
    """1/(1 + (ln f/f0)²) peaks at f0 = 3,333 Hz, between the points of a 7-point grid."""
    f0 = 3333.0

    def lorentz(f):
        return 2.5 / (1.0 + math.log(f / f0) ** 2)

    freq = np.geomspace(1.0, 1e6, 7)
    peak = force_maximum(lorentz, freq)
    assert isinstance(peak, ForceMaximum) and peak.is_peak and not peak.at_band_edge
    assert peak.frequency_hz == pytest.approx(f0, rel=1e-6) and peak.force_n == pytest.approx(2.5, rel=1e-12)
    assert peak.grid_frequency_hz == 1e4 and peak.grid_force_n == pytest.approx(lorentz(1e4), rel=1e-15)  # (ln 1e4 is nearer ln f0)
    assert peak.to_dict()["band_edge"] is None


@pytest.mark.parametrize(
    ("force", "edge"),
    [(lambda f: 1.0 / f, "fmin"), (lambda f: math.sqrt(f), "fmax"), (lambda f: 0.0, "flat")],
)
def test_a_force_largest_at_an_end_or_flat_is_not_a_peak(force, edge):
    freq = np.geomspace(10.0, 1e4, 13)
    out = force_maximum(force, freq)
    assert out.band_edge == edge and not out.is_peak
    assert out.at_band_edge is (edge != "flat")
    expected = {"fmin": 10.0, "fmax": 1e4, "flat": 10.0}[edge]
    assert out.frequency_hz == expected


def test_one_frequency_is_not_a_peak():
    out = force_maximum(lambda f: 4.0, [50.0])
    assert out.band_edge == "fmin=fmax" and out.force_n == 4.0 and out.frequency_hz == 50.0


def test_meyer_thesis_values_against_a_dense_grid():
    """Refined on 161 points, the peak equals the maximum of 200,001 points around it."""

    def force_at(f):
        return float(np.asarray(meyer_force(THESIS, np.array([f]), area=AREA, v_a=140.0))[0])

    freq = ix.log_frequencies(10.0, 1e9, 161)
    peak = force_maximum(force_at, freq, np.asarray(meyer_force(THESIS, freq, area=AREA, v_a=140.0)))
    dense = np.geomspace(20e3, 60e3, 200_001)
    force = np.asarray(meyer_force(THESIS, dense, area=AREA, v_a=140.0))
    assert peak.force_n == pytest.approx(force.max(), rel=1e-9)
    assert peak.frequency_hz == pytest.approx(dense[np.argmax(force)], rel=1e-4)
    assert peak.force_n == pytest.approx(164.2e-3, abs=0.05e-3) and peak.frequency_hz == pytest.approx(37.0e3, rel=0.01)
    assert peak.force_n > peak.grid_force_n


@pytest.mark.parametrize(
    ("freq", "force", "says"),
    [
        ([], None, "no frequencies"),
        ([10.0, -1.0], None, "positive"),
        ([100.0, 10.0], None, "rising"),
        ([10.0, 100.0], [1.0], "1 values for 2 frequencies"),
        ([10.0, 100.0], [1.0, float("nan")], "not finite at 100 Hz"),
    ],
)
def test_bad_input_is_named(freq, force, says):
    with pytest.raises(ParameterError, match=says):
        force_maximum(lambda f: 1.0, freq, force)


def test_a_force_at_that_is_no_function_or_gives_no_number_is_named():
    """Until 2026-12-06 TypeError "'int' object is not callable" and NumPy's ValueError "could not
    convert string to float" came out of force_maximum."""
    with pytest.raises(ParameterError, match="force_at must be a function of one frequency .* got int"):
        force_maximum(3, [1.0, 10.0])
    with pytest.raises(ParameterError, match="freq must be numbers: could not convert string to float: 'abc'"):
        force_maximum(lambda f: 1.0, "abc")
    with pytest.raises(ParameterError, match="force_at's values must be numbers: could not convert string to float: 'a'"):
        force_maximum(lambda f: "a", [1.0, 10.0])


def test_a_flat_force_lies_on_a_plateau_over_the_band_as_gap_says_it():
    """A force the same at every frequency is within 1 % of its largest over the whole band: its
    plateau_hz is the band when that spans more than a decade (`force_plateau`'s rule), as
    `impedax gap`'s force_maximum_shape gives it; it was None (until 2026-12-06)."""
    from impedax.models.gap import force_maximum_shape
    import xarray as xr

    freq = np.geomspace(1.0, 1e3, 7)
    flat = force_maximum(lambda f: 2.0, freq)
    assert flat.band_edge == "flat" and flat.plateau_hz == (1.0, 1e3)
    shape = force_maximum_shape(xr.DataArray(np.full(freq.size, 2.0), dims="frequency", coords={"frequency": freq}))
    assert shape["band_edge"] == "flat" and shape["plateau_hz"] == flat.plateau_hz
    assert force_maximum(lambda f: 2.0, [1.0, 5.0]).plateau_hz is None  # (less than a decade: no plateau judged)
