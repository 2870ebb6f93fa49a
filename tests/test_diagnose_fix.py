"""``impedax diagnose/refine --fix`` and ``fixed=``: a value held in the baseline fit and in
every later fit that has the parameter, and the note on parameters the data do not determine
apart (`FitResult.unidentified_groups`), with the option that resolves it.

The case is the finger model of docs/PHYSICS.md, C_s + C_i + R_sc ∥ CPE_sc + R_f, on a
SYNTHETIC spectrum written here from its closed form: C_s and C_i in series enter Z only as
1/C_s + 1/C_i, so no data determine them apart; fixing C_i (the insulator's datasheet value)
does. Only the constant_phase effect is tried, without the DRT evidence, to keep the runs short."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

MEYER = "C_s + C_i + R_sc || C_sc + R_f"
C_S, C_I, R_SC, Q_SC, ALPHA_SC, R_F = 140e-12, 1.7e-9, 130e3, 2e-8, 0.8, 500.0
F = np.geomspace(1.0, 1e6, 21)  # (few points: short runs)


def meyer_cpe(rng) -> np.ndarray:
    """Z = 1/(jωC_s) + 1/(jωC_i) + R_sc ∥ CPE_sc + R_f, Z_CPE = 1/(Q (jω)^α), with 1 % complex noise of |Z|."""
    jw = 1j * 2 * np.pi * F
    z = 1 / (jw * C_S) + 1 / (jw * C_I) + 1 / (1 / R_SC + Q_SC * jw**ALPHA_SC) + R_F
    return z + 0.01 * np.abs(z) * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size))


@pytest.fixture(scope="module")
def finger(tmp_path_factory):
    path = tmp_path_factory.mktemp("fix") / "finger.csv"
    ix.save(ix.make_spectrum(F, meyer_cpe(np.random.default_rng(69))), path)
    return str(path)


def test_diagnose_without_fix_names_the_series_pair_and_the_fix_option(finger, capsys):
    assert main(["diagnose", finger, "--model", MEYER, "--effects", "constant_phase"]) == 0
    out = capsys.readouterr().out
    note = next(line for line in out.splitlines() if "not separately determined" in line)
    assert note.startswith("note: the baseline fit: C_s, C_i are not separately determined")
    assert "--fix C_i=VALUE" in note and "fixed=" not in note


def test_diagnose_fix_holds_the_value_and_drops_the_note(finger, capsys):
    assert main(["diagnose", finger, "--model", MEYER, "--effects", "constant_phase", "--fix", "C_i=1.7n", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    held = out["baseline"]["params"]["C_i"]
    assert held == {"value": pytest.approx(C_I, rel=1e-12), "stderr": None, "fixed": True, "unit": "F", "linearised_stderr": None}  # (unit: added 2026-12-01; linearised_stderr 2026-12-02)
    assert out["baseline"]["n_params"] == 4
    assert not any("not separately determined" in n for n in out["notes"])
    # the suggestions' fits keep it too, wherever the candidate still has C_i
    kept = [s for s in out["suggestions"] if "C_i" in s["values"]]
    assert kept and all(s["values"]["C_i"] == pytest.approx(C_I, rel=1e-12) for s in kept)
    assert "C_s + C_i + R_sc || CPE_sc + R_f" in [s["model"] for s in kept]


@pytest.mark.parametrize("item, says", [("C_I=1.7n", "did you mean C_i?"), ("C_i=-1n", "C_i"), ("C_i", "expected NAME=VALUE")])
def test_a_bad_fix_exits_2_naming_the_option(finger, item, says, capsys):
    assert main(["diagnose", finger, "--model", MEYER, "--fix", item]) == 2
    err = capsys.readouterr().err
    assert "--fix" in err and says in err


@pytest.mark.slow  # (5–7 s, a refine; the suite's budget: make test-all)
def test_refine_keeps_a_fixed_value_in_the_final_model():
    data = ix.make_spectrum(F, meyer_cpe(np.random.default_rng(69)))
    effects = ix.DEFAULT_EFFECTS.select(["constant_phase"])
    result = ix.refine(data, MEYER, fixed={"C_i": C_I}, effects=effects, max_effects=1, drt_evidence=False)
    final = result.final
    assert final.model == "C_s + C_i + R_sc || CPE_sc + R_f"
    assert final.fixed["C_i"] and final.values["C_i"] == C_I
    # with C_i held, C_s and the CPE's exponent are the spectrum's own (closed form above)
    assert final.values["C_s"] == pytest.approx(C_S, rel=0.05) and final.values["CPE_sc.alpha"] == pytest.approx(ALPHA_SC, abs=0.05)
    assert not final.unidentified_groups and not any("not separately determined" in n for n in result.notes)
    with pytest.raises(ix.ParameterError, match="did you mean C_i"):
        ix.diagnose(data, MEYER, fixed={"C_I": C_I})
