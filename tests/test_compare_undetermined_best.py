"""compare, when the best model by AIC leaves a parameter undetermined: it names the model
without the idle term (which the best's own warning names) and does not offer a determined
model that fits far worse. CH Instruments' REAL file (impedance.py's example data): the table
named R0 + R1 || C1 + R2 || C2, at 20.8 % against the best's 7.51 % (ΔAIC 297)."""

import json
from pathlib import Path

import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting.comparison import DECISIVE_DELTA_AIC

REAL = Path(__file__).resolve().parent / "fixtures" / "real"
MODELS = ("R0 + R1 || CPE1", "R0 + R1 || CPE1 + W1", "R0 + R1 || C1 + R2 || C2")


@pytest.fixture(scope="module")
def chi():
    data = ix.load(REAL / "exampleDataCHInstruments.txt")
    return data, ix.compare([ix.fit(m, data) for m in MODELS])


def test_the_reduced_model_fits_as_the_best_and_the_determined_one_far_worse(chi):
    data, c = chi
    note = c.undetermined_best()
    assert c.best == "R0 + R1 || CPE1 + W1" and note["undetermined"] == ["R1"]
    assert note["reduced"] == ["R0 + CPE1 + W1"] and note["best_determined"] == "R0 + R1 || C1 + R2 || C2"
    assert note["far_worse"] and note["delta_aic"] >= DECISIVE_DELTA_AIC
    # the claim checked by fitting the reduced model itself: the same misfit as the best (its R1
    # carries ~1e-13 of the block's current), and far ahead of the determined alternative
    reduced = ix.fit("R0 + CPE1 + W1", data)
    best = c.fits[c.best_index]
    assert reduced.rms_rel == pytest.approx(best.rms_rel, rel=1e-3)
    assert reduced.rms_rel < 0.5 * c.fits[2].rms_rel
    assert note["note"] in c.table() and "so compare the reduced model, not that one" in note["note"]


def test_the_json_carries_it_and_none_when_every_parameter_is_determined(tmp_path, capsys):
    path = str(REAL / "exampleDataCHInstruments.txt")
    args = ["compare", path, "--json"] + [a for m in MODELS for a in ("--model", m)]
    assert main(args) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["undetermined_best"]["reduced"] == ["R0 + CPE1 + W1"] and doc["undetermined_best"]["far_worse"] is True
    assert doc["best_determined"] == "R0 + R1 || C1 + R2 || C2"  # (the key keeps its meaning)
    assert main(["compare", path, "--json", "--model", "R0 + R1 || C1", "--model", "R0 + R1 || C1 + R2 || C2"]) == 0
    assert json.loads(capsys.readouterr().out)["undetermined_best"] is None
