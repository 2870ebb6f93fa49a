"""`DRTResult.suggested_circuit` (2026-12-02): a starting circuit read off the DRT — R0 + one
R‖CPE per resolved peak inside the measured τ window, + W1 on a diffusion tail — that
`impedax.fit` takes as it is. Oracles: SYNTHETIC spectra from numpy formulas written here (ZARCs
R/(1 + (jωτ)^α), a Warburg σ/√(jω), an R‖C) with their true R, and the noise floor √2 × the
relative noise per part.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.drt import SuggestedCircuit, suggest_circuit

from cli_run import run

FREQ = np.logspace(-2, 5, 71)  # 10 mHz–100 kHz, 10 points per decade
OMEGA = 2 * np.pi * FREQ


def two_zarcs():
    """SYNTHETIC: 10 Ω + 100 Ω/(1 + (jω·100 µs)^0.85) + 200 Ω/(1 + (jω·10 ms)^0.85)."""
    return 10.0 + 100.0 / (1 + (1j * OMEGA * 1e-4) ** 0.85) + 200.0 / (1 + (1j * OMEGA * 1e-2) ** 0.85)


def noisy(z, level, seed):
    """SYNTHETIC: Z·(1 + s(n₁ + j n₂)), relative noise of ``level`` on each part."""
    rng = np.random.default_rng(seed)
    return z * (1 + level * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)))


def test_two_zarcs_give_two_arcs_that_fit_to_the_noise_floor():
    z = noisy(two_zarcs(), 0.01, 0)
    suggestion = ix.drt((FREQ, z)).suggested_circuit()
    assert isinstance(suggestion, SuggestedCircuit)
    assert suggestion.model == "R0 + R1 || CPE1 + R2 || CPE2"
    assert suggestion.init["CPE1.alpha"] == 0.9 and suggestion.init["R0"] > 0
    # the start's τ = (R Q)^(1/α) is the peak's: within 0.2 decade of the true 100 µs and 10 ms
    for k, tau in ((1, 1e-4), (2, 1e-2)):
        start_tau = (suggestion.init[f"R{k}"] * suggestion.init[f"CPE{k}.Q"]) ** (1 / 0.9)
        assert abs(np.log10(start_tau / tau)) < 0.2
    assert len(suggestion.reasons) == 3 and suggestion.reasons[1].startswith("R1 || CPE1: the peak at τ = ")
    fit = ix.fit(suggestion.model, (FREQ, z), init=suggestion.init)
    assert 0.01 < fit.rms_rel < 1.2 * np.sqrt(2) * 0.01  # the noise floor: √2 × 1 % on the complex residual
    assert fit.values["R1"] == pytest.approx(100.0, rel=0.05)
    assert fit.values["R2"] == pytest.approx(200.0, rel=0.05)
    assert fit.values["CPE2.alpha"] == pytest.approx(0.85, abs=0.03)


def test_a_diffusion_tail_gets_a_warburg_and_its_peaks_are_not_arcs():
    """SYNTHETIC: the two ZARCs + σ/√(jω), σ = 50 Ω s^−½, 1 % noise: the DRT lists a third
    peak in the tail (τ ≈ 40 s); the suggestion holds it in W1, σ started within 50 %."""
    r = ix.drt((FREQ, noisy(two_zarcs() + 50.0 / np.sqrt(1j * OMEGA), 0.01, 0)))
    assert len(r.peaks) >= 3
    suggestion = suggest_circuit(r)
    assert suggestion.model == "R0 + R1 || CPE1 + R2 || CPE2 + W1"
    assert suggestion.init["W1.sigma"] == pytest.approx(50.0, rel=0.5)
    assert any("diffusion tail (W1 holds it)" in reason for reason in suggestion.reasons)


def test_one_arc_at_5_percent_noise_leaves_the_unresolved_peak_out():
    """SYNTHETIC R‖C (10 Ω + 100 Ω, 1 ms), 5 % noise, seed 205: the DRT lists a second peak
    inside the window, 6.3 ± 5.2 Ω at 10.5 s, not told from zero: one arc, not two."""
    r = ix.drt((FREQ, noisy(10.0 + 100.0 / (1 + 1j * OMEGA * 1e-3), 0.05, 205)))
    spurious = [p for p in r.peaks if not p.resolved]
    assert len(r.peaks) == 2 and len(spurious) == 1 and spurious[0].inside_window
    suggestion = r.suggested_circuit()
    assert suggestion.model == "R0 + R1 || C1"  # (an ideal R‖C's narrow peak: suggest.NARROW_FACTOR)
    assert suggestion.init["R1"] == pytest.approx(100.0, rel=0.05)
    assert any("left out: its R is not told from zero" in reason for reason in suggestion.reasons)


def test_drt_json_and_report_carry_the_suggestion(tmp_path, capsys):
    path = tmp_path / "two_zarcs.csv"
    z = noisy(two_zarcs(), 0.01, 0)
    np.savetxt(path, np.column_stack([FREQ, z.real, z.imag]), delimiter=",", header="frequency,Z_real,Z_imag", comments="")
    code, out, err = run(["drt", path, "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    assert summary["suggested_model"] == "R0 + R1 || CPE1 + R2 || CPE2"
    assert set(summary["suggested_init"]) == {"R0", "R1", "CPE1.Q", "CPE1.alpha", "R2", "CPE2.Q", "CPE2.alpha"}
    assert len(summary["suggestion_reasons"]) == 3
    assert summary["n_resolved_peaks"] == 2  # the existing keys stay
    code, out, err = run(["drt", path], capsys)
    assert code == 0, err
    line = out.splitlines()[-1]
    assert line.startswith("starting circuit from the DRT: R0 + R1 || CPE1 + R2 || CPE2 — fit it with: impedax fit ")
    assert "--model 'R0 + R1 || CPE1 + R2 || CPE2' --init R0=" in line


@pytest.mark.parametrize(
    "name, z_true, model",
    [
        ("a resistor: no arc, R0 + C1", 50.0 + 0 * OMEGA, "R0 + C1"),
        ("ωL = 13 % of |Z| at 100 kHz: L1", 10.0 + 100.0 / (1 + 1j * OMEGA * 1e-3) + 1j * OMEGA * 2e-6, "R0 + L1 + R1 || C1"),
        ("a ZARC at τ = 1000 s, beyond the slowest point (15.9 s): a series CPE", 10.0 + 100.0 / (1 + 1j * OMEGA * 1e-3) + 300.0 / (1 + (1j * OMEGA * 1e3) ** 0.9), "R0 + R1 || C1 + CPE2"),
    ],
    ids=["resistor", "inductor", "slow_zarc"],
)
def test_the_other_parts(name, z_true, model):
    """SYNTHETIC, 1 % noise, seed 1: the resistor's DRT lists two peaks not told from zero."""
    suggestion = ix.drt((FREQ, noisy(z_true, 0.01, 1))).suggested_circuit()
    assert suggestion.model == model, name
    assert set(suggestion.init) == set(ix.parse(model).parameter_names())
    assert all(value > 0 for value in suggestion.init.values())


def test_the_fit_command_keeps_the_band_the_drt_was_taken_on(capsys):
    """`impedax drt FILE --fmin 5000`: the suggestion's starts come from the DRT of the points
    above 5 kHz, so its `impedax fit` command leaves out the same points (it had dropped
    --fmin/--fmax/--exclude), and runs as written (REAL ZPlot file, impedance.py, MIT)."""
    import os
    import shlex

    from impedax.cli import main

    path = os.path.join(os.path.dirname(__file__), "fixtures", "real", "exampleDataZPlot.z")
    assert main(["drt", path, "--fmin", "5000", "--quiet"]) == 0
    command = capsys.readouterr().out.strip().splitlines()[-1].split("fit it with: ")[1]
    words = shlex.split(command)
    assert words[:3] == ["impedax", "fit", path] and words[words.index("--fmin") + 1] == "5000.0"
    assert main(words[1:] + ["--json", "--quiet"]) == 0
    assert json.loads(capsys.readouterr().out)["n_points"] == int(np.sum(ix.load(path)["frequency"].values >= 5000))


def test_a_flat_spectrum_has_no_peak_and_suggests_a_resistor_alone():
    """Noise-free 100 Ω (a flat spectrum): γ is the solve's round-off (it once made a 60 nΩ
    "peak" and an R‖CPE from it); a 10 mΩ R‖C beside it (10⁻⁴ of |Z|) is still a peak."""
    flat = ix.drt((FREQ, np.full(FREQ.size, 100.0 + 0j)))
    assert flat.flat and flat.peaks == () and flat.dropped_peaks == ()
    assert flat.suggested_circuit().model == "R0"
    assert flat.suggested_circuit().init["R0"] == pytest.approx(100.0, rel=1e-6)
    assert any("flat" in n for n in flat.notes)
    small = ix.drt((FREQ, 100.0 + 0.01 / (1 + 1j * OMEGA * 1e-3)))  # τ = 1 ms, inside 10 mHz–100 kHz
    assert not small.flat and len(small.peaks) == 1
    assert small.peaks[0].r_ohm == pytest.approx(0.01, rel=0.05)
    assert small.peaks[0].tau_s == pytest.approx(1e-3, rel=0.3)


L_SMALL = 0.03 * 10.0 / (2 * np.pi * 1e5)  # H: ωL = 3 % of the 10 Ω left at 100 kHz, under the 5 % rule


@pytest.mark.parametrize("level, with_l, expect_l", [(0.002, True, True), (0.01, True, False), (0.002, False, False)],
                         ids=["3 % against 0.2 % noise: L1", "3 % against 1 % noise: left out", "no inductance: none"])
def test_an_inductance_under_five_percent_joins_when_it_stands_out_of_the_noise(level, with_l, expect_l):
    """SYNTHETIC 10 Ω + 100 Ω ∥ 1 µF (+ jωL), seeds 0–4: ωL at the top frequency 3 % of |Z| is
    15× a 0.2 % noise (L1 joins, 2026-12-04) but 3× a 1 % one (`INDUCTIVE_NOISE_MULTIPLE` 4: left
    out); without an inductance no seed gets L1."""
    z_true = 10.0 + 100.0 / (1 + 1j * OMEGA * 1e-4) + (1j * OMEGA * L_SMALL if with_l else 0)
    for seed in range(5):
        model = ix.drt((FREQ, noisy(z_true, level, seed))).suggested_circuit().model
        assert ("L1" in model) == expect_l, (seed, model)


def test_a_real_lead_inductance_under_five_percent_is_suggested_and_fits():
    """REAL ZPlot file (impedance.py, MIT): the DRT's ωL is 4.9 % of |Z| at 300 kHz, 5.5× its
    residual σ; the suggestion with L1 fits the data at under half the rms_rel of the same
    circuit without it (0.35 % against 1.35 %)."""
    import os

    data = ix.load(os.path.join(os.path.dirname(__file__), "fixtures", "real", "exampleDataZPlot.z"))
    suggestion = ix.drt(data).suggested_circuit()
    assert suggestion.model == "R0 + L1 + R1 || CPE1"
    with_l = ix.fit(suggestion.model, data, init=dict(suggestion.init))
    without = ix.fit("R0 + R1 || CPE1", data)
    assert with_l.rms_rel < 0.5 * without.rms_rel and "L1" not in with_l.at_bound


# A narrow peak starts as R‖C (suggest.NARROW_FACTOR): SYNTHETIC one-arc spectra, 71 points over
# 0.1 Hz–1 MHz, relative noise 0.5 % on each part; oracles the formulas' own R, C = τ/R and α.
F_WIDE = np.logspace(-1, 6, 71)


def one_arc(alpha, seed, level=0.005):
    """SYNTHETIC: 1.2 kΩ + 85 kΩ/(1 + (jω·85 kΩ·22 nF)^alpha), noisy."""
    z = 1.2e3 + 85e3 / (1 + (1j * 2 * np.pi * F_WIDE * 85e3 * 22e-9) ** alpha)
    return noisy(z, level, seed)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_an_ideal_rc_arc_starts_as_r_parallel_c(seed):
    suggestion = ix.drt((F_WIDE, one_arc(1.0, seed))).suggested_circuit()
    assert suggestion.model == "R0 + R1 || C1"
    assert suggestion.init["R0"] == pytest.approx(1.2e3, rel=0.02)
    assert suggestion.init["R1"] == pytest.approx(85e3, rel=0.02)
    assert suggestion.init["C1"] == pytest.approx(22e-9, rel=0.06)  # τ/R, with the peak's τ
    assert suggestion.n_arcs == 1 and "as narrow as one ideal R‖C's" in suggestion.reasons[1]
    fit = ix.fit(suggestion.model, (F_WIDE, one_arc(1.0, seed)), init=suggestion.init, progress=False)
    assert fit.values["C1"] == pytest.approx(22e-9, rel=0.01)


@pytest.mark.parametrize("alpha, level", [(0.8, 0.005), (0.9, 0.005), (0.9, 0.03)])
def test_a_distributed_arc_keeps_its_cpe(alpha, level):
    suggestion = ix.drt((F_WIDE, one_arc(alpha, 4, level))).suggested_circuit()
    assert suggestion.model == "R0 + R1 || CPE1"
    assert suggestion.init["CPE1.alpha"] == 0.9


def test_an_ideal_rc_at_3_percent_noise_still_starts_as_r_parallel_c():
    assert ix.drt((F_WIDE, one_arc(1.0, 5, 0.03))).suggested_circuit().model == "R0 + R1 || C1"
