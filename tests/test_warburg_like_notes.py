"""A finite Warburg or a Gerischer whose τ puts the whole band deep in its W limit is named as the
W it acts as (`reductions.warburg_like_elements`, `reductions.warburg_deviation`,
`result.warburg_like_notes`).

Oracles: the compiled elements themselves (Z_G, Z_Wo, Z_Ws against Z_W of σ = R/√(2τ), which
`warburg_deviation` writes in closed form), σ = R/√(2τ) by hand, and the threshold
`WARBURG_LIKE_DEVIATION`; an element off its limit, or a W itself, gets no note."""

from __future__ import annotations

import math

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.parameters import ParameterTable
from impedax.fitting.reductions import WARBURG_LIKE_DEVIATION, warburg_deviation, warburg_like_elements
from impedax.fitting.least_squares.result import warburg_like_notes


def test_the_w_that_would_take_the_place_is_named():
    circuit = ix.parse("R0 + G1 + Wo_d + Ws2 + W1")  # (each W named as if alone: W1 is taken, so G1 → W2; Ws2 → W2)
    found = warburg_like_elements(circuit, ix.DEFAULT_REGISTRY)
    assert {k: v[:3] for k, v in found.items()} == {"G1.tau": ("G1", "G1.R", "W2"), "Wo_d.tau": ("Wo_d", "Wo_d.R", "W_d"), "Ws2.tau": ("Ws2", "Ws2.R", "W2")}
    assert warburg_like_elements(ix.parse("R0 + R1 || C1 + W1"), ix.DEFAULT_REGISTRY) == {}


@pytest.mark.parametrize("symbol", ["G", "Wo", "Ws"])
@pytest.mark.parametrize("omega_tau", [1.0, 30.0, 1e4])
def test_the_deviation_is_the_compiled_elements(symbol, omega_tau):
    r, tau = 50.0, 2.0
    omega = omega_tau / tau
    f = np.array([omega / (2 * math.pi)])
    z_element = ix.compile_circuit(f"{symbol}1")({f"{symbol}1.R": r, f"{symbol}1.tau": tau}, f)
    z_w = ix.compile_circuit("W1")({"W1.sigma": r / math.sqrt(2 * tau)}, f)
    expected = float(np.abs(np.asarray(z_element) / np.asarray(z_w) - 1)[0])
    assert float(warburg_deviation(symbol, omega_tau)) == pytest.approx(expected, rel=1e-6, abs=1e-13)


def test_a_note_within_the_deviation_with_sigma_by_hand_and_none_beyond_it():
    table = ParameterTable.build(ix.parse("R0 + G1"))
    freq = np.logspace(-2, 4, 30)  # ω_min = 2π·0.01 rad/s
    omega_min = 2 * math.pi * 0.01
    # G: |Z/Z_W − 1| ≈ 1/(2ωτ): 5e-7 at ω_min·τ = 1e6, 5e-3 at 100
    deep, shallow = 1e6 / omega_min, 100 / omega_min
    values = np.array([[0.1, 500.0, deep], [0.1, 500.0, shallow]])  # (R0, G1.R, G1.tau)
    assert 1 / (2 * 100) > WARBURG_LIKE_DEVIATION > 1 / (2 * 1e6)
    notes = warburg_like_notes(table, values, freq)
    assert [b for b, _ in notes] == [0]
    text = notes[0][1]
    sigma = 500.0 / math.sqrt(2 * deep)
    assert "ω_min·τ = 1e+06: its Z is within 5e-07 of R/√(jωτ)" in text
    assert "the model with W1 in its place" in text and f"σ = R/√(2τ) = {sigma * 1e3:.3g} mΩ s^-1/2" in text  # (σ = 0.0886 Ω s^-1/2, in its prefix)
    # a fixed τ or R: the user chose the element; no note
    assert ParameterTable.build(ix.parse("R0 + G1"), fixed={"G1.tau": deep}).warburg_like == {}


def test_a_finite_warburg_seen_as_such_and_a_w_get_no_note():
    """SYNTHETIC R0 + Wo1 written out (R coth(x)/x, x = √(jωτ)) with its knee inside the band
    (τ = 1 s, 10 mHz–10 kHz): nothing to name; nor for a W fitted to it."""
    f = np.logspace(-2, 4, 37)
    rng = np.random.default_rng(5)
    x = np.sqrt(1j * 2 * np.pi * f * 1.0)
    z = 2.0 + 40.0 / (x * np.tanh(x))
    z = z * (1 + 0.002 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    data = ix.make_spectrum(f, z)
    finite = ix.fit("R0 + Wo1", data)
    assert finite.values["Wo1.tau"] == pytest.approx(1.0, rel=0.05)
    assert not any("acts as a semi-infinite Warburg" in w for w in finite.warnings)
    assert not any("acts as a semi-infinite Warburg" in w for w in ix.fit("R0 + W1", data).warnings)
