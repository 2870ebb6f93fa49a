"""refine starts a further path from the circuit the data's DRT reads (`refinement._drt_start`)
when its first diagnosis named that circuit (`Diagnosis.drt_circuit`) and the greedy path still
ends ``missing_effect``: on REAL exampleData.csv from R0 + R1 ∥ C1 the greedy path stops at its
limit of 4 effects (0.809 %, AIC −1343.2, missing_effect: the figures before 2026-12-06, in
docs/diagnosis.md's real-spectra table), and the path from R0 + L1 + R1 ∥ CPE1 + W1 ends
adequate. No such path where the greedy path ends adequate (REAL ZPlot, whose DRT circuit the
first diagnosis names too), nor with no effect allowed."""

import json
import shlex
from pathlib import Path
from types import SimpleNamespace

import matplotlib.pyplot as plt
import pytest

import impedax as ix
from impedax.cli import main
from impedax.cli.refine import reproduce_line
from impedax.fitting.diagnosis import refinement
from impedax.fitting.diagnosis.diagnosis import Verdict
from impedax.fitting.diagnosis.refinement import DRT_EFFECT, RefinementStep, _drt_start, effect_count

REAL = Path(__file__).parent / "fixtures" / "real"


def _stand_in(start: str, drt: str | None, end_verdict: str):
    """A first diagnosis of ``start`` naming ``drt`` (or none), and a greedy path ending at ``end_verdict``."""
    fit = lambda model: SimpleNamespace(circuit=ix.parse(model), model=model)  # noqa: E731
    first = SimpleNamespace(baseline=fit(start), drt_circuit=SimpleNamespace(fit=fit(drt)) if drt else None)
    return first, [SimpleNamespace(diagnosis=first), SimpleNamespace(diagnosis=SimpleNamespace(verdict=end_verdict))]


def test_the_drt_start_names_what_it_adds_and_leaves_out():
    first, steps = _stand_in("R0 + R1 || C1", "R0 + L1 + R1 || CPE1 + W1", Verdict.MISSING_EFFECT)
    start = _drt_start(first, steps, 4)
    # by hand: the DRT's circuit has L1, CPE1 and W1 that R0 + R1 || C1 has not, and no C1
    assert start.added == "L1, CPE1, W1" and start.removed == ("C1",) and start.effect == DRT_EFFECT == "drt_circuit"
    step = RefinementStep(start.fit, start.added, start.effect, None, start.removed, where=start.where)
    assert step.change == "+ L1, CPE1, W1 [drt_circuit], − C1"
    assert step.removal_reasons == {"C1": "not in the circuit the data's DRT reads"}
    # a start read off the data, not an effect of the catalog: the path from it may add max_effects effects
    assert effect_count(DRT_EFFECT) == 0 and effect_count("extra_relaxation+series_inductance") == 2


@pytest.mark.parametrize(("drt", "verdict", "limit"), [
    (None, Verdict.MISSING_EFFECT, 4),  # the first diagnosis named no DRT circuit
    ("R0 + L1 + R1 || CPE1 + W1", Verdict.ADEQUATE, 4),  # the greedy path reached the noise
    ("R0 + L1 + R1 || CPE1 + W1", Verdict.DATA_INVALID, 4),  # the misfit left is the data's own
    ("R0 + L1 + R1 || CPE1 + W1", Verdict.MISSING_EFFECT, 0),  # --max-effects 0: no change to the user's circuit
])
def test_no_drt_start(drt, verdict, limit):
    first, steps = _stand_in("R0 + R1 || C1", drt, verdict)
    assert _drt_start(first, steps, limit) is None


def test_zplot_ends_adequate_without_a_drt_path():
    """REAL ZPlot: the first diagnosis names R0 + L1 + R1 ∥ CPE1 (tests/test_diagnose_drt_circuit.py),
    but the greedy path ends adequate, so no path starts from it and the end is as before (the
    real-spectra table: R1 ∥ C1 + L_lead + R_relax ∥ CPE_relax, 0.153 %)."""
    r = ix.refine(ix.load(REAL / "exampleDataZPlot.z"))
    assert r.steps[0].diagnosis.drt_circuit is not None
    assert r.verdict == Verdict.ADEQUATE and DRT_EFFECT not in [s.effect for s in r.steps]
    assert r.final_model == "R1 || C1 + L_lead + R_relax || CPE_relax" and r.final.rms_rel == pytest.approx(0.00153, rel=0.02)
    assert not any("DRT reads" in n for n in r.notes)


@pytest.mark.slow  # (~40 s)
def test_exampledata_reaches_the_noise_from_the_drt_circuit(capsys):
    path = REAL / "exampleData.csv"
    capsys.readouterr()
    assert main(["diagnose", str(path), "--model", "R0 + R1 || C1", "--json"]) == 0
    named = json.loads(capsys.readouterr().out)["drt_circuit"]["model"]
    r = ix.refine(ix.load(path))
    out = r.summary()  # (what impedax refine --json prints)
    steps = out["steps"]
    # the path kept starts at the circuit `impedax diagnose` named, one step from the user's circuit
    assert steps[1]["effect"] == "drt_circuit" and steps[1]["model"] == named == "R0 + L1 + R1 || CPE1 + W1"
    assert steps[1]["removed"] == ["C1"] and steps[1]["removal_reasons"] == {"C1": "not in the circuit the data's DRT reads"}
    # it ends at the noise, well below the greedy path's end (AIC −1343.2, missing_effect, before 2026-12-06)
    assert out["verdict"] == "adequate" and steps[-1]["aic"] < -1343.2 - 10 and out["final_rms_rel"] < 0.00809
    assert sum(effect_count(s["effect"]) for s in steps) <= 4
    assert any("started from the circuit the data's DRT reads (impedax drt), R0 + L1 + R1 || CPE1 + W1" in n and "is kept in place of" in n for n in out["notes"])
    assert not any("stopped at its limit" in n for n in out["notes"])
    # the oracle: impedax fit of the final model, as the report's reproduce line gives it (from its values or from scratch), reaches the same fit
    line = reproduce_line(r, SimpleNamespace(data=str(path), weighting="modulus"))
    argv = shlex.split(line.split(": ", 1)[1].split(" (impedax fit keeps")[0])[1:] if line else ["fit", str(path), "--model", r.final_model]
    capsys.readouterr()
    assert main(argv + ["--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["rms_rel"] == pytest.approx(out["final_rms_rel"], rel=1e-3)
    # its 7 steps of close rms_rel: the step labels of the figure's error panel stay apart (before
    # 2026-12-06 they ran leftwards into each other, "extra_relaxation − W1" across "diffusion")
    fig = r.plot()
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        labels = [(t.get_text(), t.get_window_extent(renderer)) for t in fig.axes[0].texts]
        assert len(labels) == len(steps)
        for i, (a, box_a) in enumerate(labels):
            assert all(not box_a.overlaps(box_b) for _, box_b in labels[i + 1:]), a
    finally:
        plt.close(fig)


def test_nothing_missing_starts_no_drt_path(monkeypatch):
    """SYNTHETIC R0 + R1 ∥ C1 (numpy formula, 0.5 % noise) refined from that circuit: adequate at
    once, the generating values, and no path from the DRT's circuit."""
    import numpy as np

    f = np.logspace(-1, 5, 50)
    z = 20.0 + 1000.0 / (1 + 2j * np.pi * f * 1000.0 * 1e-6)
    rng = np.random.default_rng(3)
    z = z * (1 + 0.005 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2))
    data = ix.make_spectrum(f, z)
    calls = []
    real = refinement._drt_start
    monkeypatch.setattr(refinement, "_drt_start", lambda *a: calls.append(real(*a)) or calls[-1])
    r = ix.refine(data, "R0 + R1 || C1")
    assert r.verdict == Verdict.ADEQUATE and r.final_model == "R0 + R1 || C1"
    assert r.final.values["R1"] == pytest.approx(1000.0, rel=0.03) and r.final.values["C1"] == pytest.approx(1e-6, rel=0.03)
    assert calls in ([], [None])  # (nothing is missing: no DRT path)
