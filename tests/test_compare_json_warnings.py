"""`impedax compare --json` has a top-level `warnings` list, as every other command's JSON: each
model's warnings prefixed by its label (until 2026-12-06 only `models[].warnings`, so a
pipeline's `warnings == []` check raised KeyError on compare alone)."""

import csv
import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main


def _compare_json(argv, capsys):
    assert main([*argv, "--json", "-q"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.slow  # (~4 s: two fits, the first run compiling)
def test_single_compare_lists_every_models_warnings_with_its_label(tmp_path, capsys):
    """SYNTHETIC R0 + R1 ∥ C1 (numpy formula, 10 Ω, 100 Ω, 1 µF, no noise): R0 + R1 ∥ C1 fits it
    exactly (no warning), R0 + R1 ∥ CPE1 puts α at its bound 1 (an ideal capacitor), a warning
    that model's list and the top-level list both carry, the latter as "R0 + R1 || CPE1: …"."""
    f = np.geomspace(1.0, 1e5, 30)
    path = tmp_path / "rc.csv"
    ix.save(ix.make_spectrum(f, 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6)), path)
    table = tmp_path / "compared.csv"
    printed = _compare_json(["compare", str(path), "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "--out", str(table)], capsys)
    by_label = {m["label"]: m["warnings"] for m in printed["models"]}
    assert by_label["R0 + R1 || C1"] == []
    assert any("CPE1.alpha" in w for w in by_label["R0 + R1 || CPE1"])
    assert printed["warnings"] == [f"R0 + R1 || CPE1: {w}" for w in by_label["R0 + R1 || CPE1"]]
    # (--out FILE.csv: each model's warnings joined by "; ", as fit's and a batch comparison's CSV; no column until 2026-12-06)
    with open(table, newline="", encoding="utf-8") as handle:
        rows = {row["label"]: row for row in csv.DictReader(line for line in handle if not line.startswith("#"))}
    assert {label: row["warnings"] for label, row in rows.items()} == {label: "; ".join(warnings) for label, warnings in by_label.items()}


@pytest.mark.slow  # (~8 s: two models over two spectra)
def test_batch_compare_lists_each_models_distinct_warnings_with_its_label(tmp_path, capsys):
    """SYNTHETIC: two cells of R0 + R1 ∥ C1 (numpy formula, R1 = 100 and 300 Ω): R0 + R1 ∥ CPE1's
    α at its bound 1 on both; the top-level list has each distinct warning of a model once, with
    its label, the union of `spectra[].models[].warnings`."""
    f = np.geomspace(1.0, 1e5, 30)
    r1 = np.array([[100.0], [300.0]])
    path = tmp_path / "cells.nc"
    ix.save(ix.make_spectrum(f, 10 + r1 / (1 + 2j * np.pi * f * r1 * 1e-6), dims=("cell",), coords={"cell": ["a", "b"]}), path)
    printed = _compare_json(["compare", str(path), "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1"], capsys)
    expected = []
    for label in ("R0 + R1 || C1", "R0 + R1 || CPE1"):
        distinct = sorted({w for s in printed["spectra"] for m in s["models"] if m["label"] == label for w in m["warnings"]})
        expected += [f"{label}: {w}" for w in distinct]
    assert printed["warnings"] == expected
    assert any(w.startswith("R0 + R1 || CPE1: ") and "CPE1.alpha" in w for w in expected)
