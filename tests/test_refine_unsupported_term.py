"""refine's final model loses a term the data do not support when the model without it has an
AIC no higher (`refinement._pruned` with `unsupported.unsupported_terms`): an arc seen on one
flank only (REAL exampleData.csv: R_relax ∥ CPE_relax relaxing 360× below the band, R_relax
806 mΩ ± 89 %) and a redundant arc of the user's (R0 + R1 ∥ C1 + R2 ∥ C2 on SYNTHETIC one-arc
data, numpy formula, 1 % noise). Nothing is taken out of a correct model (an arc inside the
band; an arc relaxing 4× below the band whose resistor the data still need), and an adequate
end does not become an inadequate one."""

import json
from pathlib import Path
from types import SimpleNamespace as NS

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting.arcs import arc_taus
from impedax.fitting.diagnosis.diagnosis import Verdict, undetermined_parameters
from impedax.fitting.diagnosis import refinement
from impedax.fitting.diagnosis.refinement import RefinementStep, _pruned, _reproduced
from impedax.fitting.diagnosis.unsupported import unsupported_terms

EXAMPLE = Path(__file__).parent / "fixtures" / "real" / "exampleData.csv"
# step 3 of `impedax refine exampleData.csv` (before 2026-12-05 its final model)
EX_MODEL = "R0 + (R1 + R_relax2 || CPE_relax2) || CPE1 + R_relax || CPE_relax + L_lead"
EX_VALUES = {
    "R0": 0.0149691, "R1": 0.00630048, "R_relax2": 0.0112283, "CPE_relax2.Q": 5.75665, "CPE_relax2.alpha": 0.741517,
    "CPE1.Q": 0.334064, "CPE1.alpha": 0.822307, "R_relax": 0.806178, "CPE_relax.Q": 331.533, "CPE_relax.alpha": 0.569713, "L_lead": 1.66342e-07,
}

R0, R_ARC, C_ARC = 10.0, 50.0, 1e-5  # ohm, ohm, farad: τ = 0.5 ms, 318 Hz, inside 10 mHz–100 kHz


def _one_arc(frequency, r0=R0, r=R_ARC, c=C_ARC, noise=0.01, seed=6):
    """R0 + R ∥ C by its closed form, with 1 % complex Gaussian noise proportional to |Z|."""
    w = 2 * np.pi * np.asarray(frequency)
    z = r0 + r / (1 + 1j * w * r * c)
    rng = np.random.default_rng(seed)
    z = z + np.abs(z) * noise * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size))
    return ix.make_spectrum(frequency, z)


def _stub_pruned(fit, data, verdicts=None):
    """`_pruned` of a one-step path ending at ``fit``; each diagnosis a stand-in whose verdict is
    ``verdicts(model)`` (adequate by default)."""
    verdicts = verdicts or (lambda model: Verdict.ADEQUATE)
    first = NS(verdict=verdicts(fit.model), solver_shape=None)
    notes: list[str] = []
    out = _pruned([RefinementStep(fit, None, None, first)], data, n_starts=4, seed=0,
                  diagnosed=lambda f, shape: NS(verdict=verdicts(f.model), solver_shape=None), reproduced=_reproduced, say=lambda text: None, notes=notes)
    return out, notes


@pytest.fixture(scope="module")
def one_arc():
    return _one_arc(np.logspace(5, -2, 71))


@pytest.fixture(scope="module")
def oversized(one_arc):
    return ix.fit("R0 + R1 || C1 + R2 || C2", one_arc, n_starts=4, seed=0)


def test_a_redundant_arc_of_the_users_is_taken_out(one_arc, oversized):
    assert undetermined_parameters(oversized), "the over-sized model should leave a parameter undetermined"
    steps, notes = _stub_pruned(oversized, one_arc)
    final = steps[-1].fit
    assert final.circuit.structure_key() == ix.parse("R0 + R1 || C1").structure_key()
    assert final.n_params == 3 and final.aic <= oversized.aic
    assert not undetermined_parameters(final)
    r = [v for k, v in final.values.items() if k != "R0" and k.startswith("R")]
    c = [v for k, v in final.values.items() if k.startswith("C")]
    # the generating values, within 5 × the 1 % noise
    assert final.values["R0"] == pytest.approx(R0, rel=0.05) and r[0] == pytest.approx(R_ARC, rel=0.05) and c[0] == pytest.approx(C_ARC, rel=0.05)
    assert len(steps) == 2, "the redundant arc goes in one step, R and C together"
    assert any("the data do not determine" in n and "is as good by AIC as" in n for n in notes)


def test_a_correct_model_loses_nothing(one_arc):
    fit = ix.fit("R0 + R1 || C1", one_arc, n_starts=4, seed=0)
    assert unsupported_terms(fit) == []
    steps, notes = _stub_pruned(fit, one_arc)
    assert len(steps) == 1 and notes == []


def test_an_arc_below_the_band_whose_resistor_the_data_need_is_kept():
    # the arc relaxes at 318 Hz; the band starts 4× above it, at 1.27 kHz: at the band's bottom
    # ωτ = 4 and Z_arc = R/(1 + 4j) has Re = R/17 ≈ 2.9 Ω, which a capacitor alone (Re 0) misses
    f_relax = 1 / (2 * np.pi * R_ARC * C_ARC)
    data = _one_arc(np.logspace(np.log10(4 * f_relax), 6, 40), noise=0.005)
    fit = ix.fit("R0 + R1 || C1", data, n_starts=4, seed=0)
    terms = unsupported_terms(fit)
    assert [t.removed for t in terms] == [("R1",)], "the arc lies more than 2× below the band: it is named"
    assert "relaxes outside the band" in terms[0].why
    steps, notes = _stub_pruned(fit, data)
    assert len(steps) == 1 and notes == [], "without R1 the AIC is higher: R1 stays"


def test_an_adequate_end_stays_adequate(one_arc, oversized):
    steps, notes = _stub_pruned(oversized, one_arc, verdicts=lambda model: Verdict.ADEQUATE if model == oversized.model else Verdict.MISSING_EFFECT)
    assert len(steps) == 1 and notes == []


@pytest.fixture(scope="module")
def example():
    return ix.load(EXAMPLE)


def test_the_arc_exampledata_sees_on_one_flank_loses_its_resistor(example):
    fit = ix.fit(EX_MODEL, example, init=EX_VALUES, n_starts=1, seed=0)
    assert fit.aic == pytest.approx(-1342.5, abs=0.5)
    # the oracle: τ = (R Q)^(1/α) of R_relax ∥ CPE_relax, by hand, relaxes far below the band
    tau = (fit.values["R_relax"] * fit.values["CPE_relax.Q"]) ** (1 / fit.values["CPE_relax.alpha"])
    assert 1 / (2 * np.pi * tau) < float(example["frequency"].min()) / 100
    assert float(arc_taus("CPE", fit.values["R_relax"], fit.values["CPE_relax.Q"], fit.values["CPE_relax.alpha"])) == pytest.approx(tau, rel=1e-9)
    steps, notes = _stub_pruned(fit, example)
    final = steps[-1].fit
    assert set(fit.circuit.element_names) - set(final.circuit.element_names) == {"R_relax"}
    assert "CPE_relax" in final.circuit.element_names and final.n_params == fit.n_params - 1
    assert final.aic <= fit.aic
    assert any(n.startswith("R_relax || CPE_relax relaxes outside the band") and "R_relax is taken out" in n for n in notes)


@pytest.mark.slow
def test_refine_on_exampledata_ends_without_the_extrapolated_resistor(capsys, monkeypatch):
    # the greedy path's end, as refine kept it before it started a path from the DRT's circuit,
    # which is kept in its place since 2026-12-06 (tests/test_refine_drt_path.py)
    monkeypatch.setattr(refinement, "_drt_start", lambda *args: None)
    capsys.readouterr()
    assert main(["refine", str(EXAMPLE), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert "R_relax ||" not in out["final_model"] and "CPE_relax " in out["final_model"] + " "
    assert any("relaxes outside the band" in n for n in out["notes"])
