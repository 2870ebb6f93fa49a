"""Descriptions of wide failing bands (impedax.fitting.diagnosis.bands._describe).

A band that spans many decades, or where the misfit changes sign, used to be described by band
averages of phase and |Z|, which cancel: the Autolab spectrum's inductive top (+28° against the
model's −2°) read as "more resistive than the model (phase -5° vs -7°)". The descriptions now
give the largest deviations and where they are. Every stated figure is checked here against
numbers computed independently: the circuit's impedance from `ix.fit`'s values with a numpy
formula written here, not impedax's compiler.
"""

from __future__ import annotations

import re
import types
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis.bands import _power_law, failing_bands
from impedax.fitting.diagnosis.effects import DEFAULT_EFFECTS

ROOT = Path(__file__).resolve().parents[1]
AUTOLAB = ROOT / "tests" / "fixtures" / "real" / "exampleDataAutolab.txt"
GAMRY = ROOT / "tests" / "fixtures" / "real" / "exampleDataGamry.DTA"
BATTERY = ROOT / "examples" / "data" / "autoeis_battery_cycles.nc"

_FREQ = r"([\d.]+ (?:MHz|kHz|Hz|mHz))"
_UNITS = {"MHz": 1e6, "kHz": 1e3, "Hz": 1.0, "mHz": 1e-3}


# --- the circuits, in numpy ----------------------------------------------------------------------


def _jw(f):
    return 1j * 2 * np.pi * np.asarray(f, float)


def _rq(f, r, q, a):
    """R ∥ CPE, CPE = 1/(Q (jω)^α)."""
    return r / (1 + r * q * _jw(f) ** a)


def _warburg(f, sigma):
    """Semi-infinite Warburg σ(1 − j)/√ω."""
    return sigma * (1 - 1j) / np.sqrt(2 * np.pi * np.asarray(f, float))


FORMULAS = {
    "R0 + R1 || CPE1": lambda f, v: v["R0"] + _rq(f, v["R1"], v["CPE1.Q"], v["CPE1.alpha"]),
    "R0 + R1 || CPE1 + R2 || CPE2": lambda f, v: v["R0"] + _rq(f, v["R1"], v["CPE1.Q"], v["CPE1.alpha"]) + _rq(f, v["R2"], v["CPE2.Q"], v["CPE2.alpha"]),
    "R0 + R1 || CPE1 + W1": lambda f, v: v["R0"] + _rq(f, v["R1"], v["CPE1.Q"], v["CPE1.alpha"]) + _warburg(f, v["W1.sigma"]),
}


def _fake_fit(f, z_data, z_model):
    return types.SimpleNamespace(frequency=f, z_data=z_data, z_model=z_model, residuals=(z_model - z_data) / np.abs(z_data))


def _hz(text: str) -> float:
    value, unit = text.split()
    return float(value) * _UNITS[unit]


# --- the real spectra: diagnose (for the words) and ix.fit + numpy (for the numbers) ------------


def _spectrum(name):
    if name == "battery129":
        data = ix.load(BATTERY)
        return data.isel(cycle=int(np.flatnonzero(data["cycle"].values == 129)[0]))
    return ix.load(AUTOLAB if name == "autolab" else GAMRY)


CASES = {
    "autolab": "R0 + R1 || CPE1",
    "gamry2": "R0 + R1 || CPE1 + R2 || CPE2",
    "gamry1": "R0 + R1 || CPE1",
    "battery129": "R0 + R1 || CPE1 + W1",
}


@pytest.fixture(scope="module")
def real():
    """name → (diagnosis, f, Z_data, Z_model from numpy) for each case, computed once, lazily."""
    cache = {}

    def get(name):
        if name not in cache:
            circuit = CASES[name]
            data = _spectrum(name)
            # the bands and their words come from the baseline fit alone: no candidate effects, no DRT
            d = ix.diagnose(data, circuit, effects=DEFAULT_EFFECTS.select(()), drt_evidence=False)
            fit = ix.fit(circuit, data)
            f = np.asarray(data["frequency"].values, float)
            z = np.asarray(data["Z"].values, complex)
            order = np.argsort(f)
            f, z = f[order], z[order]
            cache[name] = (d, f, z, FORMULAS[circuit](f, dict(fit.values)))
        return cache[name]

    return get


def _band_points(band, f):
    return (f >= band.f_min * (1 - 1e-9)) & (f <= band.f_max * (1 + 1e-9))


def _check_stated_extremes(text, f, zd, zm):
    """Every "up to N° above/below ... near F" and "up to N % above/below ... near F" in ``text``
    is the data's deviation at F (within rounding) and the largest on that side over the band's
    points ``f``. Returns {("phase"|"|Z|", "above"|"below"): (value, frequency)}."""
    dph = np.degrees(np.angle(zd / zm))
    rel = (np.abs(zd) / np.abs(zm) - 1) * 100
    found = {}
    for quantity, series, tol in (("phase", dph, lambda x: 0.51), ("|Z|", rel, lambda x: 0.051 * abs(x) + 0.051)):
        head = r"the data's phase is" if quantity == "phase" else r"\|Z\| is"
        unit = "°" if quantity == "phase" else " %"
        clause = re.search(head + r" up to ([\d.]+)" + unit + r" (above|below) [^;]*?near " + _FREQ + r"(?: \([^)]*\))?(?: and up to ([\d.]+)" + unit + r" (above|below) near " + _FREQ + ")?", text)
        if not clause:
            continue
        g = clause.groups()
        for value, side, freq in ((g[0], g[1], g[2]), (g[3], g[4], g[5])):
            if value is None:
                continue
            value, at = float(value), _hz(freq)
            k = int(np.argmin(np.abs(np.log(f / at))))
            assert abs(f[k] / at - 1) < 0.01, f"{freq} is not a measured frequency"
            signed = value if side == "above" else -value
            assert series[k] == pytest.approx(signed, abs=tol(signed)), f"{quantity} at {freq}: stated {signed}, computed {series[k]:.3g}"
            extreme = series.max() if side == "above" else series.min()
            assert abs(extreme) == pytest.approx(value, abs=tol(value)), f"{quantity}: stated up to {value} {side}, computed {extreme:.3g}"
            found[(quantity, side)] = (value, at)
    return found


def test_autolab_names_the_inductive_top_not_a_resistive_average(real):
    d, f, zd, zm = real("autolab")
    assert len(d.failing_bands) == 1
    band = d.failing_bands[0]
    assert band.f_min == pytest.approx(0.1) and band.f_max == pytest.approx(1e4)  # the whole spectrum
    text = band.pattern
    assert text in d.report()
    assert "more resistive" not in text and "whole band" not in text
    found = _check_stated_extremes(text, f, zd, zm)
    # independently: the phase excess peaks at the top, 10 kHz, where the data are inductive
    dph = np.degrees(np.angle(zd / zm))
    assert f[np.argmax(dph)] == pytest.approx(1e4) and dph.max() > 25
    assert found[("phase", "above")][1] == pytest.approx(1e4, rel=0.01)
    m = re.search(r"near " + _FREQ + r" \(([+-]?\d+)° vs ([+-]?\d+)°; inductive above " + _FREQ + r"\)", text)
    assert m, text
    assert float(m.group(2)) == pytest.approx(np.degrees(np.angle(zd[-1])), abs=0.51)
    assert float(m.group(3)) == pytest.approx(np.degrees(np.angle(zm[-1])), abs=0.51)
    # "inductive above X": every point above X has a positive phase, the point below does not
    edge = _hz(m.group(4))
    above = f > edge
    assert above.sum() >= 2 and above.sum() < f.size / 2  # a minority of the band, still named
    assert np.all(np.angle(zd[above]) > 0) and np.angle(zd[~above][-1]) <= 0
    assert ("|Z|", "above") in found and ("|Z|", "below") in found


def _stated_extremes(real, case):
    """The first failing band of ``case``, checked to be in the report without the same-phase
    wording; the points inside it, and the extremes its text states (each checked)."""
    d, f, zd, zm = real(case)
    band = d.failing_bands[0]
    assert band.pattern in d.report() and "same phase" not in band.pattern
    inside = _band_points(band, f)
    return d, _check_stated_extremes(band.pattern, f[inside], zd[inside], zm[inside]), zd[inside], zm[inside]


@pytest.mark.slow  # (5-8 s; the suite's budget: Autolab's case runs by default)
def test_battery_gives_the_swings_not_a_same_phase_average(real):
    d, found, zd, zm = _stated_extremes(real, "battery129")
    assert len(d.failing_bands) == 1
    ratio = np.abs(zd) / np.abs(zm)
    dph = np.degrees(np.angle(zd / zm))
    # independently: |Z| swings both ways by > 10 %, the phase by several degrees both ways
    assert ratio.min() < 0.9 and ratio.max() > 1.1 and dph.min() < -5 and dph.max() > 5
    assert set(found) == {("phase", "above"), ("phase", "below"), ("|Z|", "above"), ("|Z|", "below")}


@pytest.mark.slow  # (5-8 s; the suite's budget: Autolab's case runs by default)
def test_gamry_two_arcs_gives_a_magnitude_figure(real):
    _, found, _, _ = _stated_extremes(real, "gamry2")
    assert ("|Z|", "above") in found and ("|Z|", "below") in found


@pytest.mark.slow  # (5-8 s; the suite's budget: Autolab's case runs by default)
def test_gamry_one_arc_states_the_missing_arc_and_no_misworded_power_law(real):
    d, f, zd, zm = real("gamry1")
    band = d.failing_bands[0]
    text = band.pattern
    inside = _band_points(band, f)
    found = _check_stated_extremes(text, f[inside], zd[inside], zm[inside])
    # the missing low-frequency arc: |Z| several times the model's at the bottom of the band
    value, at = found[("|Z|", "above")]
    assert value > 100 and at == pytest.approx(f[inside].min(), rel=0.01)
    assert found[("phase", "below")][0] > 15
    for verb, exponent in re.findall(r"(rises|falls) as f\^([-\d.]+)", text):
        assert (float(exponent) > 0) == (verb == "rises"), text


# --- synthetic ------------------------------------------------------------------------------------


def _arc(f):
    return 10 + 100 / (1 + 100 * 3e-4 * _jw(f) ** 0.8)


def test_uniform_magnitude_offset_keeps_the_same_phase_wording(rng):
    """A 5 % |Z| offset at equal phase over seven decades: the band average is honest there."""
    f = np.logspace(-2, 5, 60)
    z_model = _arc(f)
    z_data = 1.05 * z_model * (1 + 0.003 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))
    bands = failing_bands(_fake_fit(f, z_data, z_model), 0.003)
    assert len(bands) == 1
    text = bands[0].pattern
    assert text.startswith("over the whole band the data and the model differ in magnitude at the same phase"), text
    m = re.search(r"\|Z\| is ([\d.]+) % above the model", text)
    assert m and float(m.group(1)) == pytest.approx(np.mean(np.abs(z_data) / np.abs(z_model) - 1) * 100, abs=0.051)
    assert float(m.group(1)) == pytest.approx(5, abs=0.2)


def test_nothing_missing_no_band_no_description(rng):
    f = np.logspace(-2, 5, 60)
    z = _arc(f)
    noisy = z * (1 + 0.005 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))
    assert failing_bands(_fake_fit(f, noisy, z), 0.005) == ()


def test_nothing_missing_end_to_end(rng):
    """The right circuit fitted to its own noisy spectrum: diagnose reports no failing band."""
    f = np.logspace(-1, 5, 50)
    z = 5.0 + _rq(f, 200.0, 2e-5, 0.85)
    noisy = z * (1 + 0.003 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))
    d = ix.diagnose((f, noisy), "R0 + R1 || CPE1", effects=DEFAULT_EFFECTS.select(()), drt_evidence=False)
    assert d.failing_bands == () and "where the model fails" not in d.report()


def test_minority_inductive_top_is_named():
    """A lead inductance shows at the top few points of a band that spans the spectrum."""
    f = np.logspace(-1, 5, 60)
    z_model = 2 + 100 / (1 + 100 * 1e-3 * _jw(f))  # an ideal RC
    z_data = 2 + _rq(f, 100, 1e-3, 0.8) + _jw(f) * 2e-5  # a CPE arc and a lead inductance
    bands = failing_bands(_fake_fit(f, z_data, z_model), 0.003)
    band = max(bands, key=lambda b: b.f_max / b.f_min)
    inside = _band_points(band, f)
    assert np.log10(band.f_max / band.f_min) > 1.5
    positive = inside & (z_data.imag > 0)
    assert 2 <= positive.sum() < inside.sum() / 2  # a minority of the band
    m = re.search(r"inductive above " + _FREQ, band.pattern)
    assert m, band.pattern
    edge = _hz(m.group(1))
    assert np.all(z_data.imag[inside & (f > edge)] > 0) and np.all(z_data.imag[inside & (f < edge)] <= 0)
    _check_stated_extremes(band.pattern, f[inside], z_data[inside], z_model[inside])


def test_power_law_verb_follows_the_sign():
    assert _power_law("−Z''", 0.72) == "−Z'' rises as f^0.72"
    assert _power_law("−Z''", -0.5) == "−Z'' falls as f^-0.50"
    # a narrow band below an arc's peak, where −Z'' rises with f: a CPE against an ideal capacitor
    f = np.logspace(0, 1.3, 14)
    z_model = 100 / (1 + _jw(f) / (2 * np.pi * 1e3))
    z_data = 100 / (1 + (_jw(f) / (2 * np.pi * 1e3)) ** 0.8)
    bands = failing_bands(_fake_fit(f, z_data, z_model), 0.005)
    assert len(bands) == 1
    m = re.search(r"−Z'' (rises|falls) as f\^([-\d.]+) where the model's (rises|falls) as f\^([-\d.]+)", bands[0].pattern)
    assert m, bands[0].pattern
    inside = _band_points(bands[0], f)
    slope_d = np.polyfit(np.log10(f[inside]), np.log10(-z_data.imag[inside]), 1)[0]
    slope_m = np.polyfit(np.log10(f[inside]), np.log10(-z_model.imag[inside]), 1)[0]
    assert slope_d > 0 and slope_m > 0
    assert m.group(1) == m.group(3) == "rises"
    assert float(m.group(2)) == pytest.approx(slope_d, abs=0.006) and float(m.group(4)) == pytest.approx(slope_m, abs=0.006)


def test_leak_band_rest_clause_excludes_the_resistive_end():
    """The resistive-vs-capacitive end keeps its words; "over the rest" gives the largest phase
    difference outside that end, and where it is."""
    f = np.logspace(0, 5, 50)
    w = 2 * np.pi * f
    z_model = 1 / (1j * w * 1e-8)
    z_data = 1 / (1 / 1e6 + 1j * w * 1e-8)
    (band,) = failing_bands(_fake_fit(f, z_data, z_model), 0.01)
    m = re.search(r"^below " + _FREQ + r" the data are resistive .*over the rest of .* the phases differ by up to (\d+)° \(near " + _FREQ + r"\)", band.pattern)
    assert m, band.pattern
    edge, value, at = _hz(m.group(1)), float(m.group(2)), _hz(m.group(3))
    rest = _band_points(band, f) & (f > edge)
    dph = np.abs(np.degrees(np.angle(z_data / z_model)))
    k = int(np.argmax(np.where(rest, dph, -1)))
    assert value == pytest.approx(dph[k], abs=0.51) and f[k] == pytest.approx(at, rel=0.01)
