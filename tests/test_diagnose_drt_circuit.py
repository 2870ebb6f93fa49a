"""diagnose names the circuit the data's DRT reads (`impedax drt`'s starting circuit) when it is
better than every suggestion, each of which is one change to the user's circuit
(`diagnosis._drt_circuit_fit`, JSON ``drt_circuit``): on REAL ZPlot data R0 + L1 + R1 ∥ CPE1 (a
CPE and a lead at once) against the best suggestion's lead alone; on REAL exampleData.csv
R0 + L1 + R1 ∥ CPE1 + W1 against R_relax ∥ CPE_relax + L_lead, as good by AIC with a parameter
fewer. Not named when a suggestion is that circuit (SYNTHETIC R0 + R ∥ CPE, numpy formula),
when the model is adequate, nor on REAL data.dfr (pyimpspec's noise-free test spectrum), where
both fits reach the values to 1e-13 and the DRT's is no better beyond rounding."""

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

REAL = Path(__file__).parent / "fixtures" / "real"


def _diagnose_json(path, model, capsys) -> dict:
    capsys.readouterr()
    assert main(["diagnose", str(path), "--model", model, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _fit_json(argv, capsys) -> dict:
    capsys.readouterr()
    assert main(argv + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_zplot_the_drt_circuit_fits_better_than_the_best_single_change(capsys):
    out = _diagnose_json(REAL / "exampleDataZPlot.z", "R0 + R1 || C1", capsys)
    d = out["drt_circuit"]
    assert out["verdict"] == "missing_effect" and d is not None
    assert d["model"] == "R0 + L1 + R1 || CPE1" and d["better_fit"] is True
    assert d["compared_model"] == out["suggestions"][0]["model"]
    # the rules of a significant suggestion, against the best one: ΔAIC lower by more than 10
    assert d["delta_aic"] < d["compared_delta_aic"] - 10
    assert d["rms_rel"] < d["compared_rms_rel"]
    # the oracle: impedax fit of the same circuit from scratch, an independent start, reaches the same optimum
    scratch = _fit_json(["fit", str(REAL / "exampleDataZPlot.z"), "--model", d["model"]], capsys)
    assert scratch["rms_rel"] == pytest.approx(d["rms_rel"], rel=0.02)
    # and the line the report prints
    capsys.readouterr()
    assert main(["diagnose", str(REAL / "exampleDataZPlot.z"), "--model", "R0 + R1 || C1"]) == 0
    text = capsys.readouterr().out
    assert "the data's DRT reads another circuit (impedax drt), R0 + L1 + R1 || CPE1, which fits better than 1." in text
    assert "  to apply it: impedax fit " in text and "--model 'R0 + L1 + R1 || CPE1' --init R0=" in text


@pytest.mark.slow
def test_exampledata_the_drt_circuit_is_as_good_with_fewer_parameters(capsys):
    out = _diagnose_json(REAL / "exampleData.csv", "R0 + R1 || C1", capsys)
    d = out["drt_circuit"]
    assert d["model"] == "R0 + L1 + R1 || CPE1 + W1" and d["better_fit"] is False
    assert d["n_params"] == 6 and d["compared_n_params"] == 7 and d["delta_aic"] < d["compared_delta_aic"]
    # the printed values reproduce the fit (impedax fit from them)
    inits = [w for k, v in d["values"].items() for w in ("--init", f"{k}={v!r}")]
    again = _fit_json(["fit", str(REAL / "exampleData.csv"), "--model", d["model"]] + inits, capsys)
    assert again["rms_rel"] == pytest.approx(d["rms_rel"], rel=1e-3)


def test_no_drt_circuit_on_noise_free_data_where_it_is_no_better(capsys):
    out = _diagnose_json(REAL / "data.dfr", "R0 + R1 || C1", capsys)
    assert out["verdict"] == "missing_effect" and out["drt_circuit"] is None


def _r_cpe(f, r0=20.0, r=100.0, q=1e-5, alpha=0.8, noise=0.005, seed=3):
    """R0 + R ∥ CPE by its closed form, R/(1 + R Q (jω)^α), with 0.5 % noise proportional to |Z|."""
    jw = 2j * np.pi * f
    z = r0 + r / (1 + r * q * jw**alpha)
    rng = np.random.default_rng(seed)
    return ix.make_spectrum(f, z + np.abs(z) * noise * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))


def test_no_drt_circuit_when_a_suggestion_is_the_circuit_or_nothing_is_missing():
    data = _r_cpe(np.logspace(5, -2, 57))
    missing = ix.diagnose(data, "R0 + R1 || C1", progress=False)
    assert missing.verdict == "missing_effect" and missing.best.fit.circuit.structure_key() == ix.parse("R0 + R1 || CPE1").structure_key()
    assert missing.drt_circuit is None and missing.summary()["drt_circuit"] is None
    adequate = ix.diagnose(data, "R0 + R1 || CPE1", progress=False)
    assert adequate.verdict == "adequate" and adequate.drt_circuit is None
