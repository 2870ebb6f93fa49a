"""An arc a diagnosis adds that relaxes outside the measured band is flagged, not offered as a
relaxation the data resolve (`arcs.arcs_beyond_band`, `Suggestion.beyond_band`,
`Refinement.beyond_band`).

Oracles: the relaxation frequency 1/(2πτ) of R ∥ C (τ = RC) and of R ∥ CPE (τ = (RQ)^(1/α)),
computed here by hand from the fitted values; the band of the REAL Scribner ZPlot file of
impedance.py (MIT; 3 kHz–300 kHz), where refine from ``R0 + R1 || CPE1`` adds an R ∥ C that
relaxes near 2.2 MHz; and the SYNTHETIC evaluation set's arc built above its band (flagged)
and one inside it (nothing to flag)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.arcs import arcs_beyond_band
from impedax.fitting.diagnosis.effects import added_resistors, placement

ZPLOT = Path(__file__).parent / "fixtures" / "real" / "exampleDataZPlot.z"


def test_relaxation_frequencies_and_sides_match_hand_values():
    circuit = ix.parse("R0 + R1 || C1 + R2 || CPE2 + R3 || C3 + R4 || C4")
    values = {"R0": 10.0, "R1": 100.0, "C1": 1e-9, "R2": 1e3, "CPE2.Q": 1e-2, "CPE2.alpha": 0.8, "R3": 50.0, "C3": 1e-6, "R4": 100.0, "C4": 1e-8}
    band = np.logspace(0, 5, 26)  # 1 Hz – 100 kHz
    arcs = arcs_beyond_band(circuit, values, ix.DEFAULT_REGISTRY, band)
    # R1 ∥ C1: τ = 100 Ω · 1 nF = 1e-7 s, 1.59 MHz, 15.9× above 100 kHz; R2 ∥ CPE2: τ = (10)^(1/0.8)
    # = 17.78 s, 8.95 mHz, 112× below 1 Hz; R3 ∥ C3 at 3.18 kHz is inside; R4 ∥ C4 at 159 kHz is
    # 1.59× above, within BEYOND_BAND_FACTOR = 2 (the data reach 80 % of its peak); R0 is no arc
    assert [(a.resistor, a.capacitance, a.side) for a in arcs] == [("R1", "C1", "above"), ("R2", "CPE2", "below")]
    assert arcs[0].frequency_hz == pytest.approx(1 / (2 * math.pi * 1e-7), rel=1e-12)
    assert arcs[0].factor == pytest.approx(1e7 / (2 * math.pi) / 1e5, rel=1e-12)
    assert arcs[1].tau_s == pytest.approx(10.0 ** (1 / 0.8), rel=1e-12)
    assert arcs[1].factor == pytest.approx(2 * math.pi * 10.0 ** 1.25, rel=1e-12)
    # above, the arc acts as its resistor and its capacitance is the extrapolation; below, the reverse
    assert arcs[0].as_json()["extrapolated"] == "C1" and arcs[1].as_json()["extrapolated"] == "R2"
    assert "low-frequency flank" in arcs[0].sentence() and "high-frequency flank" in arcs[1].sentence()
    assert "1.59 MHz, 16× above the band's top, 100 kHz" in arcs[0].sentence()
    assert "a band reaching past 1.59 MHz" in arcs[0].remedy() and "a band reaching below 8.95 mHz" in arcs[1].remedy()


def test_only_an_added_relaxation_is_judged_and_its_words_leave_the_placement():
    circuit = ix.parse("R0 || C_stray + R1 || C1 + R_relax || C_relax")
    # a stray capacitance is meant to lie beyond the band: only extra_relaxation's arcs count
    assert added_resistors("stray_capacitance", "C_stray", circuit, ix.DEFAULT_REGISTRY) == ()
    assert added_resistors("extra_relaxation", "R_relax || C_relax", circuit, ix.DEFAULT_REGISTRY) == ("R_relax",)
    assert added_resistors("extra_relaxation+diffusion", "R_relax || C_relax", circuit, ix.DEFAULT_REGISTRY) == ("R_relax",)
    arc = arcs_beyond_band(circuit, {"R_relax": 150.0, "C_relax": 4.75e-10}, ix.DEFAULT_REGISTRY, [3e3, 3e5], ("R_relax",))[0]
    where = "in series with the whole circuit" + arc.words() + ", and R0 left out (it fell to 132 µΩ: the data do not reach a series-resistance plateau)"
    assert placement(where) == "in series with the whole circuit, and R0 left out (it fell to 132 µΩ: the data do not reach a series-resistance plateau)"


@pytest.fixture(scope="module")
def zplot():
    return ix.load(ZPLOT)


def test_diagnose_flags_the_real_zplot_arc_above_the_band(zplot):
    band = (float(zplot.frequency.min()), float(zplot.frequency.max()))
    assert band == (3e3, 3e5)
    d = ix.diagnose(zplot, "R0 + R1 || CPE1 + L_lead")
    best = d.suggestions[0]
    assert best.effect == "extra_relaxation" and "R_relax" in best.fit.values
    v = best.fit.values
    f_hand = 1 / (2 * math.pi * v["R_relax"] * v["C_relax"])
    assert f_hand > 2 * band[1]  # (near 2.2 MHz: the oracle of what is flagged)
    (arc,) = best.beyond_band
    assert (arc.resistor, arc.capacitance, arc.side) == ("R_relax", "C_relax", "above")
    assert arc.frequency_hz == pytest.approx(f_hand, rel=1e-9)
    assert "above the band's top, 300 kHz" in best.where and "not a relaxation the data resolve" in best.explanation
    assert d.reason.endswith(f"though R_relax || C_relax relaxes at {arc.frequency_hz / 1e6:.3g} MHz, above the band: the data see one flank of it.")
    entry = json.loads(json.dumps(d.summary()))["suggestions"][0]
    assert entry["beyond_band"][0]["side"] == "above" and entry["beyond_band"][0]["frequency_hz"] == pytest.approx(f_hand, rel=1e-9)
    assert entry["beyond_band"][0]["band_hz"] == [3e3, 3e5]
    # the nested arc of the second placement relaxes inside the band: nothing to flag
    nested = next(s for s in d.candidates if s.effect == "extra_relaxation" and "nested" in s.where and "C_relax" in s.fit.values)
    assert 3e3 <= 1 / (2 * math.pi * nested.fit.values["R_relax"] * nested.fit.values["C_relax"]) <= 3e5
    assert nested.beyond_band == () and "relaxes at" not in nested.where


def test_refine_reports_the_real_zplot_arc_it_added_outside_the_band(zplot):
    r = ix.refine(zplot, "R0 + R1 || CPE1")
    assert "R_relax" in r.final.values
    v = r.final.values
    f_hand = 1 / (2 * math.pi * v["R_relax"] * v["C_relax"])
    summary = json.loads(json.dumps(r.summary()))
    assert [(a["elements"], a["side"]) for a in summary["final_beyond_band"]] == [(["R_relax", "C_relax"], "above")]
    assert summary["final_beyond_band"][0]["frequency_hz"] == pytest.approx(f_hand, rel=1e-9)
    step = next(i for i, s in enumerate(r.steps) if s.added and "R_relax" in s.added)
    assert f"step {step} adds R_relax || C_relax, outside the band: fitted τ" in r.report()
    assert "a band reaching past" in r.report()


def _evaluation_case(name):
    from evaluation_set import cases

    return next(c for c in cases("dev") if c.name == name)


@pytest.mark.parametrize("name, flagged", [("extra_relaxation/edge", True), ("extra_relaxation/rc#0", False)])
def test_the_evaluation_sets_arc_above_the_band_is_flagged_and_one_inside_is_not(name, flagged):
    """SYNTHETIC (tests/evaluation_set.py, numpy formulas): the edge template's missing arc is
    built at 1/(2π·300 Ω·2 nF) = 265 kHz, above its 0.1 Hz–100 kHz band; rc#0's lies inside.
    Both are named first; only the edge one is flagged, above, and more than 2× past the top."""
    case = _evaluation_case(name)
    d = ix.diagnose(ix.make_spectrum(case.frequency, case.z), case.circuit)
    best = d.suggestions[0]
    assert best.effect == "extra_relaxation"
    if flagged:
        (arc,) = best.beyond_band
        assert arc.side == "above" and arc.frequency_hz > 2 * case.frequency.max() and "above the band's top, 100 kHz" in best.where
    else:
        assert best.beyond_band == () and "relaxes at" not in best.where and "relaxes at" not in d.reason


def test_a_fit_names_its_own_arc_outside_the_band_single_and_batch_alike():
    """SYNTHETIC R0 + R1 ∥ C1 + R2 ∥ C2 written out: R1 ∥ C1 at 159 Hz inside 1 Hz–100 kHz, R2 ∥ C2
    at 1/(2π·200 Ω·0.5 nF) = 1.59 MHz, 16× above the top. The fit warns of R2 ∥ C2 alone, at the
    frequency its own values give; a batch of two copies says the same of each."""
    f = np.logspace(0, 5, 41)
    rng = np.random.default_rng(11)
    w = 2 * np.pi * f
    z = 20.0 + 1e3 / (1 + 1j * w * 1e3 * 1e-6) + 200.0 / (1 + 1j * w * 200.0 * 5e-10)
    z = z * (1 + 0.001 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    circuit = "R0 + R1 || C1 + R2 || C2"
    single = ix.fit(circuit, ix.make_spectrum(f, z))
    v = single.values
    named = [x for x in single.warnings if "relaxes at" in x]
    f_hand = {k: 1 / (2 * math.pi * v[f"R{k}"] * v[f"C{k}"]) for k in (1, 2)}  # (the fit may swap the two blocks' names)
    (high,) = [k for k in (1, 2) if f_hand[k] > 2 * f.max()]
    (low,) = [k for k in (1, 2) if k != high]
    assert f_hand[low] < f.max()
    assert len(named) == 1 and named[0].startswith(f"R{high} || C{high}: fitted τ = ")
    assert f"{f_hand[high] / f.max():.2g}× above the band's top, 100 kHz" in named[0] and f"C{high} is an extrapolation" in named[0]
    batch = ix.fit(circuit, ix.make_spectrum(f, np.stack([z, z]), dims=("copy",)))
    for ws in batch.warnings.values():
        assert [x for x in ws if "relaxes at" in x] == named
    # a fixed capacitance is the user's choice: no note (C2 at the truth makes R2 ∥ C2 the high block)
    held = ix.fit(circuit, ix.make_spectrum(f, z), fixed={"C2": 5e-10})
    assert not any("relaxes at" in x for x in held.warnings)


def test_a_block_with_a_parameter_at_a_bound_or_undetermined_is_left_to_those_notes():
    """R1 ∥ C1 at 1.59 MHz above 1 Hz–100 kHz (τ = 1e-7 s by hand): noted when every parameter
    is settled, not when R1 is at a bound or undetermined (an open branch's notes say why)."""
    from impedax.fitting.least_squares.result import arc_beyond_band_notes
    from impedax.fitting.parameters import ParameterTable

    table = ParameterTable.build(ix.parse("R0 + R1 || C1"))
    values = np.array([[10.0, 100.0, 1e-9]] * 2)  # (R0, R1, C1)
    settled = np.array([[True, True, True], [True, False, True]])
    notes = arc_beyond_band_notes(table, values, np.logspace(0, 5, 11), settled)
    assert [b for b, _ in notes] == [0] and notes[0][1].startswith("R1 || C1: fitted τ = 100 ns: it relaxes at 1.59 MHz, 16× above")


def test_a_resistor_run_open_has_no_relaxation_time_and_no_numpy_warning():
    """R·C beyond floating point (a resistor run open, 1e300 Ω) is τ = inf, quietly: the random
    command lines of the robustness test reached it."""
    import warnings

    from impedax.fitting.arcs import arc_taus

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.isinf(arc_taus("C", 1e300, 1e300)) and np.isinf(arc_taus("CPE", 1e300, 1e300, 0.5))
        assert np.isnan(arc_taus("C", 0.0, 1e-6)) and np.isnan(arc_taus("CPE", 100.0, 1e-6, 0.0))
    assert float(arc_taus("CPE", 100.0, 1e-6, 0.8)) == pytest.approx(1e-4 ** 1.25, rel=1e-12)


def test_an_arc_far_beyond_the_band_is_named_by_what_it_acts_as_not_by_its_figures():
    """Refine on REAL CH Instruments data printed "τ = 8.02e+33 s: it relaxes at 1.98e-35 Hz,
    5e+33× below the band's bottom" (a walkthrough): beyond FAR_BEYOND_FACTOR the arc acts as
    one of its elements alone, and the words say which."""
    from impedax.fitting.arcs import FAR_BEYOND_FACTOR, ArcBeyondBand

    band = (0.1, 1e5)
    below = ArcBeyondBand("R_relax2", "CPE_relax2", 8.02e33, band)
    assert below.factor > FAR_BEYOND_FACTOR and below.side == "below"
    assert below.sentence().startswith("it relaxes more than 1000× below the band's bottom, 100 mHz (fitted τ = 8.02e+33 s), so over the whole band it acts as CPE_relax2 alone")
    assert "e-35 Hz" not in below.sentence() and below.remedy() == "the model with CPE_relax2 alone in place of R_relax2 || CPE_relax2 may be enough"
    above = ArcBeyondBand("R_x", "C_x", 1e-15, band)  # 1/(2π·1 fs) = 1.6e14 Hz, 1.6e9× the top
    assert "acts as R_x alone and C_x does not show in the data" in above.sentence() and "R_x alone in place of R_x || C_x" in above.remedy()
    # at most FAR_BEYOND_FACTOR outside: the figures, as before
    near = ArcBeyondBand("R_x", "C_x", 1 / (2 * np.pi * band[0] / 900), band)
    assert near.factor == pytest.approx(900) and near.sentence().startswith("fitted τ = ") and near.remedy().startswith("a band reaching below")


def test_refine_names_a_start_arc_the_final_fit_puts_outside_the_band(zplot):
    """From the default start the REAL ZPlot file ends with the start's R1 ∥ C1 at about
    2.2 MHz (R0 left out: it acts as the series resistance), above 3 kHz–300 kHz; the report and
    the JSON name it, with the frequency 1/(2π R1 C1) computed here."""
    r = ix.refine(zplot)
    v = r.final.values
    assert "R0" not in v and {"R1", "C1"} <= set(v)  # (the path this test is about)
    f_hand = 1 / (2 * math.pi * v["R1"] * v["C1"])
    assert f_hand > 2 * 3e5
    summary = json.loads(json.dumps(r.summary()))
    (entry,) = [a for a in summary["final_beyond_band"] if a["elements"] == ["R1", "C1"]]
    assert entry["side"] == "above" and entry["frequency_hz"] == pytest.approx(f_hand, rel=1e-9)
    assert "the final model has R1 || C1, outside the band" in r.report() and "where it acts as a resistance" in r.report()
