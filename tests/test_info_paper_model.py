"""`impedax info meyer` (meyer-rc, meyer-cpe): the thesis's eq 3.13 values that `simulate` takes
as defaults and `fit` as starting values, with their source, in the text and in --json (the
elements' own defaults stay under "default")."""

import json
import math
import re
from pathlib import Path

import pytest

from impedax.cli import main

PHYSICS = (Path(__file__).resolve().parents[1] / "docs" / "physics.md").read_text(encoding="utf-8")
PREFIX = {"p": 1e-12, "n": 1e-9, "k": 1e3, "": 1.0}


def thesis_values() -> dict[str, float]:
    """The eq 3.13 circuit values as docs/physics.md writes them ("R_sc ≈ 130 kΩ, ... C_s = 140 pF"),
    an independent copy of the thesis numbers (not impedax.models.meyer's table)."""
    line = next(ln for ln in PHYSICS.split("- Parameters (eq 3.13):", 1)[1].split("\n- ", 1)[0].splitlines() if "R_sc ≈" in ln)
    found = {name: float(v) * PREFIX[p] for name, v, p in re.findall(r"\b(R_sc|C_sc|C_i|R_f|C_s)\s*[≈=]\s*([0-9.]+)\s*([pnk]?)[FΩ]", line)}
    assert set(found) == {"R_sc", "C_sc", "C_i", "R_f", "C_s"}, found
    return found


def run_json(capsys, model):
    assert main(["info", model, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("model", ["meyer", "meyer-rc", "MEYER"])
def test_info_json_gives_the_thesis_values_of_the_rc_variant(capsys, model):
    expected = thesis_values()
    assert expected == pytest.approx({"R_sc": 130e3, "C_sc": 2.2e-9, "C_i": 1.7e-9, "R_f": 500.0, "C_s": 140e-12}, rel=1e-12)
    info = run_json(capsys, model)
    assert info["paper_model"] == model.lower()
    rows = {r["name"]: r for r in info["parameters"]}
    assert set(rows) == set(expected)
    for name, value in expected.items():
        assert rows[name]["paper_value"] == pytest.approx(value, rel=1e-12)
        assert "eq 3.13" in rows[name]["paper_value_source"]
    assert rows["C_s"]["default"] == 1e-6 and rows["R_f"]["default"] == 100.0  # (the element's own default, unchanged)


def test_info_json_gives_the_cpe_variant_values(capsys):
    c_sc = thesis_values()["C_sc"]
    rows = {r["name"]: r for r in run_json(capsys, "meyer-cpe")["parameters"]}
    # Q with |Z| of the capacitor C_sc at 1 kHz: Q (2π·1 kHz)^(α−1) = C_sc, α = 0.8 (docs/models.md)
    assert rows["CPE_sc.alpha"]["paper_value"] == 0.8
    assert rows["CPE_sc.Q"]["paper_value"] == pytest.approx(c_sc * (2 * math.pi * 1e3) ** 0.2, rel=1e-12)
    assert "1 kHz" in rows["CPE_sc.Q"]["paper_value_source"]
    assert rows["R_sc"]["paper_value"] == 130e3


def test_info_text_shows_the_thesis_values_and_says_where_they_come_from(capsys):
    assert main(["info", "meyer"]) == 0
    out = capsys.readouterr().out
    assert "eq 3.13" in out and "simulate" in out
    table = {ln.split()[0]: ln.split() for ln in out.splitlines() if ln.split() and ln.split()[0] in thesis_values()}
    for name, value in thesis_values().items():
        assert float(table[name][2]) == pytest.approx(value, rel=1e-12), table[name]


def test_info_of_a_circuit_has_no_paper_keys(capsys):
    info = run_json(capsys, "C_s + R_f")
    assert "paper_model" not in info and all("paper_value" not in r for r in info["parameters"])
