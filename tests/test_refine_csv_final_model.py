"""`impedax refine --out FILE.csv` writes the final model's parameters with that model and the
verdict on every row (until 2026-12-06 the only model the file named was the starting one,
``setting_model``, beside parameters of another circuit)."""

import csv

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main


@pytest.mark.slow  # (~20-40 s: a refinement of one step, with its other paths)
def test_the_csv_names_the_final_model_its_parameters_belong_to(tmp_path, capsys):
    """SYNTHETIC two arcs (numpy formula: 10 Ω + 100 Ω ∥ 1 µF + 200 Ω ∥ 250 µF, 0.3 % noise,
    seed 5) refined from R0 + R1 ∥ C1 with one effect: the final circuit has the second arc, so
    its parameters are not the starting model's; the CSV's final_model is the circuit whose
    parameter names are the rows' names, and its verdict the JSON's."""
    f = np.geomspace(0.1, 1e5, 40)
    rng = np.random.default_rng(5)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6) + 200 / (1 + 2j * np.pi * f * 200 * 2.5e-4)
    z = z * (1 + 0.003 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2))
    data, table = tmp_path / "two_arcs.csv", tmp_path / "refined.csv"
    ix.save(ix.make_spectrum(f, z), data)
    assert main(["refine", str(data), "--max-effects", "1", "--out", str(table), "--json", "-q"]) == 0
    printed = __import__("json").loads(capsys.readouterr().out)
    with open(table, newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(row for row in handle if not row.startswith("#")))
    assert {row["setting_model"] for row in rows} == {"R0 + R1 || C1"}
    (final,) = {row["final_model"] for row in rows}
    assert final == printed["final_model"] and final != "R0 + R1 || C1"
    assert [row["name"] for row in rows] == list(ix.parse(final).parameter_names())
    assert len(rows) == 5  # (two arcs and the series resistance: R, R ∥ C, R ∥ C)
    assert {row["verdict"] for row in rows} == {printed["verdict"]}
