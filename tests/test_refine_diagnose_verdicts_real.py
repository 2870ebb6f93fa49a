"""``impedax diagnose FILE --model M`` and ``impedax refine FILE --model M`` on the same REAL
file: refine's step 0 is that diagnosis (the same points, noise, weighting and starts), so its
verdict and proposal are diagnose's; refine's own verdict judges its final model, and where it
differs from diagnose's the report and the JSON say so (`Refinement.diagnose_note`,
docs/diagnosis.md "How diagnose and refine relate"). A newcomer's walkthrough on REAL Gamry and CH
Instruments files read MISSING_EFFECT from diagnose and DATA_INVALID from refine as two
contradictory verdicts on one file and circuit."""

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

REAL = Path(__file__).parent / "fixtures" / "real"


def _cli(capsys, tmp_path, command, *argv) -> tuple[dict, list[str]]:
    """``impedax COMMAND ARGV --out FILE.json -q``: the JSON written (its --json summary) and the report printed."""
    out = tmp_path / f"{command}.json"
    assert main([command, *argv, "--out", str(out), "-q"]) == 0
    return json.loads(out.read_text(encoding="utf-8")), capsys.readouterr().out.splitlines()


@pytest.mark.parametrize("name, model", [("exampleDataGamry.DTA", "R0 + R1 || C1"), ("exampleDataCHInstruments.txt", "R0 + R1 || C1")])
def test_refine_step_0_is_diagnose_and_its_other_verdict_names_diagnose_s(capsys, tmp_path, name, model):
    path = str(REAL / name)
    diagnosed, diagnose_report = _cli(capsys, tmp_path, "diagnose", path, "--model", model)
    refined, report = _cli(capsys, tmp_path, "refine", path, "--model", model)
    # the walkthrough's two verdicts, from the two commands as a user runs them
    assert diagnosed["verdict"] == "missing_effect" and refined["verdict"] == "data_invalid"
    assert any(line.startswith("verdict: MISSING_EFFECT") for line in diagnose_report)
    # refine's step 0 is diagnose: the same model, fit, verdict, points and proposal (step 1 adds it)
    step0, step1 = refined["steps"][0], refined["steps"][1]
    assert step0["model"] == model and step0["verdict"] == diagnosed["verdict"]
    assert step0["rms_rel"] == pytest.approx(diagnosed["baseline"]["rms_rel"], rel=1e-9)
    assert step0["noise_ratio"] == pytest.approx(diagnosed["noise"]["ratio"], rel=1e-9)
    assert refined["masked_points"] == diagnosed["masked_points"] == []
    best = diagnosed["suggestions"][0]
    assert step1["model"] == best["model"] and step1["effect"] == best["effect"]
    # refine says which verdict diagnose gives and why its own differs, in the JSON and the report
    assert refined["diagnose_verdict"] == "missing_effect"
    note = refined["diagnose_verdict_note"]
    assert note.startswith(f"diagnose of {model} (impedax diagnose, with the same options) says MISSING_EFFECT (adding {best['effect']}), as refine's step 0 does; "), note
    assert f"this verdict judges the final model {refined['final_model']}, after the {len(refined['steps']) - 1} step" in note, note
    assert note.endswith("that followed, not the start.") and note.count("; ") == 1, note
    at = next(i for i, line in enumerate(report) if line.startswith("verdict: DATA_INVALID"))
    assert note in report[at + 1: at + 3], report[at: at + 3]
    assert not any("impedax diagnose, with the same options" in line for line in diagnose_report)


def test_a_refinement_that_ends_at_diagnose_s_verdict_says_nothing_of_it():
    """SYNTHETIC R0 + R1 ∥ C1 (10 Ω, 100 Ω, 1 µF; numpy, 31 points 100 kHz–1 Hz, 0.2 % noise,
    seed 3): diagnose and refine of the generating model both end adequate at step 0."""
    f = np.logspace(5, 0, 31)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6)
    rng = np.random.default_rng(3)
    z = z * (1 + 0.002 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    data = ix.make_spectrum(f, z)
    r = ix.refine(data, "R0 + R1 || C1")
    assert len(r.steps) == 1 and r.verdict == "adequate"
    assert r.diagnose_verdict == ix.diagnose(data, "R0 + R1 || C1").verdict == "adequate"
    assert r.diagnose_note is None and r.summary()["diagnose_verdict_note"] is None
    assert "impedax diagnose, with the same options" not in r.report()
