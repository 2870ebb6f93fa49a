"""When refine starts again on the band the Kramers–Kronig test passes (`_on_valid_band`,
docs/diagnosis.md section 1, "The band the KK test passes"), its steps — step 0 too — are on
that band, narrower than the data `diagnose` judges: ``refine --json`` says so in every step's
``band_hz`` and ``n_points`` and in the top-level ``restart`` (the band, the points kept and left
out, and why), and the text report in one line under the table (docs/diagnosis.md, "JSON")."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis.refinement import Refinement, RefinementStep

from cli_run import run

# SYNTHETIC: R0 + R1 ∥ CPE1 at 31 frequencies 10 Hz – 10 kHz (5 a decade), 0.2 % noise, whose 6
# highest points drift: each is turned by j·d with d = 1/6, 2/6, … 1 (an instrument drifting at the
# band's end, which no passive circuit gives). The KK test of all 31 points then flags all but the
# lowest 3, and passes without the 6 drifting ones; R0 + R1 ∥ C1 misses those 25 points by 6.6 %.
F = np.logspace(1, 4, 31)  # Hz
R0, R1, ALPHA, F_C = 20.0, 200.0, 0.92, 300.0  # Ω, Ω, 1, Hz (R1·Q·(2π F_C)^α = 1)
Q = 1 / (R1 * (2 * np.pi * F_C) ** ALPHA)
DRIFTING = 6
START = "R0 + R1 || C1"


def drifting_spectrum(seed: int = 3) -> np.ndarray:
    """Z [Ω] of the SYNTHETIC spectrum above."""
    z = R0 + R1 / (1 + R1 * Q * (2j * np.pi * F) ** ALPHA)
    drift = np.clip((np.arange(F.size) - (F.size - DRIFTING - 1)) / DRIFTING, 0, None)  # 0 …, then 1/6 … 1 on the top 6
    z = z * (1 + 1j * drift)
    rng = np.random.default_rng(seed)
    return z * (1 + 0.002 * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)))


def test_the_drift_is_the_top_six_points_only():
    """The oracle's own check: the formula leaves the 25 lowest points on the circuit (to the
    noise) and turns the 6 highest by 1/6 … 1."""
    z = drifting_spectrum()
    clean = R0 + R1 / (1 + R1 * Q * (2j * np.pi * F) ** ALPHA)
    assert np.max(np.abs(z[:25] / clean[:25] - 1)) < 0.01
    np.testing.assert_allclose(np.abs(z[25:] / clean[25:] - 1), np.arange(1, 7) / 6, atol=0.01)


def test_refine_s_json_says_its_steps_are_on_the_band_it_started_again_on(tmp_path, capsys):
    data = ix.make_spectrum(F, drifting_spectrum())
    r = ix.refine(data, START, progress=None)
    band = [10.0, pytest.approx(10 ** 3.4)]  # by hand: the 25th of 31 points 10^(1 + 3k/30), k = 24
    assert r.restart is not None, r.report()
    summary = json.loads(json.dumps(r.summary()))  # (what --json prints: plain JSON)
    restart = summary["restart"]
    assert restart["band_hz"] == band and restart["n_points_kept"] == 25 and restart["n_points_left_out"] == DRIFTING
    assert restart["reason"] == r.notes[0] and "refine started again on those points" in restart["reason"]
    # every step, step 0 too, is on the 25 points, not the 31 diagnose judges
    assert all(s["band_hz"] == band and s["n_points"] == 25 for s in summary["steps"]), summary["steps"]
    d = ix.diagnose(data, START, progress=None)
    assert d.baseline.n_points == F.size and summary["diagnose_verdict"] == d.verdict == "data_invalid"
    assert summary["steps"][0]["verdict"] != d.verdict  # (why a program needs the keys: step 0 is another diagnosis)
    # (the decisions are the code's: the drifting points left out, the CPE taken, as the formula has)
    assert summary["masked_points"] == [pytest.approx(f) for f in F[25:]] and summary["final_model"] == "R0 + R1 || CPE1"
    attrs = r.to_xarray().attrs  # (the .nc holds the band and the reason too)
    assert list(attrs["restart_band_hz"]) == band and attrs["restart_reason"] == r.notes[0]
    lines = r.report().splitlines()
    assert lines[lines.index("") - 1] == ("every step, step 0 too, is on 10 Hz – 2.51 kHz (25 of 31 points): "
                                          "refine started again where the KK test passes (the first note says why)")
    # the command line prints the same keys
    path = tmp_path / "drift.csv"
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{f!r},{v.real!r},{v.imag!r}\n" for f, v in zip(F.tolist(), data["Z"].values.tolist())))
    code, out, err = run(["refine", path, "--model", START, "--json", "-q"], capsys)
    assert code == 0, err
    printed = json.loads(out)
    assert printed["restart"]["band_hz"] == band and printed["restart"]["n_points_kept"] == 25 and printed["restart"]["n_points_left_out"] == DRIFTING
    assert [(s["band_hz"], s["n_points"]) for s in printed["steps"]] == [(band, 25)] * len(printed["steps"])


def test_a_refinement_on_the_data_it_was_given_has_no_restart_and_each_step_names_its_points():
    """A `Refinement` of one step (a real fit of SYNTHETIC R0 + R1 ∥ C1 on 20 points 2.5 kHz –
    200 kHz, no diagnosis): ``restart`` null, no restart line, and the step's ``band_hz`` and
    ``n_points`` are its points' (by hand: the grid's ends and its size)."""
    f = np.logspace(np.log10(2.5e3), np.log10(2e5), 20)
    rng = np.random.default_rng(12)
    z = 20 + 4e3 / (1 + 2j * np.pi * f * 4e3 * 3e-10)  # SYNTHETIC R0 + R1 ∥ C1, 0.5 % noise
    z = z * (1 + 0.005 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    fit = ix.fit("R0 + R1 || C1", (f, z), init={"R0": 20.0, "R1": 4e3, "C1": 3e-10})
    r = Refinement((RefinementStep(fit, None, None, None),), "adequate")
    summary = r.summary()
    assert summary["restart"] is None and "refine started again" not in r.report()
    assert list(r.to_xarray().attrs["restart_band_hz"]) == [] and r.to_xarray().attrs["restart_reason"] == ""
    assert summary["steps"][0]["band_hz"] == [pytest.approx(2.5e3), pytest.approx(2e5)] and summary["steps"][0]["n_points"] == 20
