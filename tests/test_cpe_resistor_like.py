"""A fitted CPE exponent below `RESISTOR_LIKE_ALPHA` gets a note that the CPE acts nearly as a
resistor, whose value 1/(Q ω^α) still varies with frequency, naming the R that may take its
place (as α at 1 names the C) — in single fits and in batches alike; no note at ordinary α.

Oracles: SYNTHETIC R0 + CPE1 spectra written here with numpy, Z = R0 + (jω)^−α/Q, 1 % complex
noise (fixed seeds); the note's resistances 1/(Q ω^α) at the band's ends computed here from the
fitted Q and α; hand numbers for the phase −90α°.
"""

import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.circuits import DEFAULT_REGISTRY, parse
from impedax.fitting.reductions import RESISTOR_LIKE_ALPHA, resistor_like_exponents

REAL = Path(__file__).resolve().parent / "fixtures" / "real"
FREQ = np.geomspace(0.01, 1e4, 31)
MODEL = "R0 + CPE1"
LEAD = "acts nearly as a resistor"


def cpe_spectrum(alpha, q, r0=5.0, seed=0):
    """SYNTHETIC: R0 + CPE, 1 % complex noise."""
    z = r0 + 1 / (q * (2j * np.pi * FREQ) ** alpha)
    rng = np.random.default_rng(seed)
    return z * (1 + 0.01 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)) / np.sqrt(2))


def resistor_notes(warnings):
    return [w for w in warnings if LEAD in w]


def test_threshold_and_the_names_of_the_resistor():
    assert RESISTOR_LIKE_ALPHA == 0.2 and 90 * RESISTOR_LIKE_ALPHA == pytest.approx(18)  # (the phase, degrees)
    circuit = parse("R0 + R1 || CPE1 + CPE2 || (R2 + Wo1)")
    assert resistor_like_exponents(circuit, DEFAULT_REGISTRY) == {"CPE1.alpha": ("CPE1", "CPE1.Q", "R3"), "CPE2.alpha": ("CPE2", "CPE2.Q", "R3")}
    assert resistor_like_exponents(parse("R0 + CPE_dl"), DEFAULT_REGISTRY)["CPE_dl.alpha"][2] == "R_dl"


def test_a_cpe_near_alpha_zero_is_said_to_act_as_a_resistor():
    fit = ix.fit(MODEL, ix.make_spectrum(FREQ, cpe_spectrum(alpha=0.1, q=0.05)))
    alpha, q = fit.values["CPE1.alpha"], fit.values["CPE1.Q"]
    assert alpha == pytest.approx(0.1, abs=0.02)  # (the case)
    (note,) = resistor_notes(fit.warnings)
    r_hi, r_lo = (1 / (q * (2 * np.pi * f) ** alpha) for f in (FREQ.max(), FREQ.min()))  # ~5.6 Ω and ~15 Ω
    assert note.startswith(f"CPE1.alpha = {alpha:.2g} is below 0.2: CPE1 {LEAD} (Z = (jω)^−α/Q, phase −{90 * alpha:.2g}°)")
    assert f"{r_hi:.3g} Ω at 10 kHz to {r_lo:.3g} Ω at 10 mHz" in note
    assert note.endswith("the model with R1 in its place may be enough")


def test_no_note_at_ordinary_alpha_nor_for_a_fixed_alpha():
    data = ix.make_spectrum(FREQ, cpe_spectrum(alpha=0.8, q=1e-3, seed=1))
    assert not resistor_notes(ix.fit(MODEL, data).warnings)
    low = ix.make_spectrum(FREQ, cpe_spectrum(alpha=0.1, q=0.05, seed=2))
    assert not resistor_notes(ix.fit(MODEL, low, fixed={"CPE1.alpha": 0.1}).warnings)  # (the user's choice)


def test_a_batch_says_it_of_the_spectra_where_it_holds_as_the_single_fit_does():
    z = np.array([cpe_spectrum(alpha=0.1, q=0.05, seed=3), cpe_spectrum(alpha=0.8, q=1e-3, seed=4)])
    stack = ix.make_spectrum(FREQ, z, dims=("cycle",)).assign_coords(cycle=[1, 2])
    batch = ix.fit(MODEL, stack)
    first, second = batch.fit_of(cycle=1), batch.fit_of(cycle=2)
    (note,) = resistor_notes(first.warnings)
    assert not resistor_notes(second.warnings)
    alone = ix.fit(MODEL, stack.sel(cycle=1))
    (note_alone,) = resistor_notes(alone.warnings)
    assert first.values["CPE1.alpha"] == pytest.approx(alone.values["CPE1.alpha"], abs=1e-4)
    assert re.sub(r"[\d.]+", "#", note) == re.sub(r"[\d.]+", "#", note_alone)


def test_real_files_alpha_015_is_said_and_alpha_092_is_not():
    """REAL: impedance.py's example data (|Z| ≈ 0.05 Ω) reach α = 0.15 with R1 = 2.4 kΩ; BioLogic's
    file α = 0.92."""
    fit = ix.fit("R0 + R1 || CPE1", ix.load(REAL / "exampleData.csv"))
    (note,) = resistor_notes(fit.warnings)
    assert fit.values["CPE1.alpha"] < 0.2 and note.startswith(f"CPE1.alpha = {fit.values['CPE1.alpha']:.2g} is below 0.2") and "R2 in its place" in note
    fit = ix.fit("R0 + R1 || CPE1", ix.load(REAL / "exampleDataBioLogic.mpt"))
    assert fit.values["CPE1.alpha"] > 0.9 and not resistor_notes(fit.warnings)


def test_battery_cycle_64_cpe2_near_alpha_zero_is_said():
    """REAL: AutoEIS's battery cycle 64, CPE2.alpha ends at 0.031 with R2 at its bound 0 (the
    global optimum, by 400 scipy starts in the walkthrough); CPE1 at α = 1 keeps its capacitor note."""
    data = ix.load(Path(__file__).resolve().parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc").sel(cycle=64)
    fit = ix.fit("R0 + R1 || CPE1 + CPE2 || (R2 + Wo1)", data)
    alpha, q = fit.values["CPE2.alpha"], fit.values["CPE2.Q"]
    (note,) = resistor_notes(fit.warnings)
    f = fit.frequency
    r_hi, r_lo = (1 / (q * (2 * np.pi * x) ** alpha) for x in (f.max(), f.min()))
    assert alpha < 0.05 and note.startswith(f"CPE2.alpha = {alpha:.2g} is below 0.2: CPE2 {LEAD}") and f"{r_hi:.3g} Ω at" in note and f"{r_lo:.3g} Ω at" in note
    assert note.endswith("the model with R3 in its place may be enough")
    assert any(w.startswith("CPE1.alpha is at its upper bound 1 (CPE1 with alpha = 1 is a capacitor") for w in fit.warnings)
