"""A hierarchical posterior writes a CSV (`to_table`, `impedax.write_result(post, "h.csv")`): it
was refused ("HierarchicalPosterior has no table of parameters; write it as .json or .nc") where
every other posterior writes one. The rows are the report's: population median, 90 % interval,
spread, a new trial's interval, unit; shared values; δ. SYNTHETIC posterior built by hand
(tests/test_hierarchical_new_session.py): μ = ln 100 Ω, s = 0.1, τ = 0.2 in every draw."""

import csv
import dataclasses
import math

import numpy as np
import pytest

import impedax as ix
from test_hierarchical_new_session import by_hand


def test_the_csv_holds_the_reports_rows(tmp_path):
    post = by_hand(2)
    post = dataclasses.replace(post, discrepancy=True, delta=np.full(post.delta.shape, 0.02))
    ix.write_result(post, tmp_path / "h.csv")
    with open(tmp_path / "h.csv", newline="", encoding="utf-8") as fh:
        rows = {row["name"]: row for row in csv.DictReader(fh)}
    assert list(rows) == ["R1", "R0", "C1", "delta"]
    r1 = rows["R1"]
    assert (r1["level"], r1["unit"]) == ("population", "Ohm")
    assert float(r1["median"]) == pytest.approx(100.0, rel=1e-12) and float(r1["spread"]) == pytest.approx(0.1, rel=1e-12)
    z90, sd = 1.6448536269514722, math.hypot(0.1, 0.2)  # (a new trial of a new session: log-normal, closed form)
    assert float(r1["new_trial_q05"]) == pytest.approx(100 * math.exp(-z90 * sd), rel=0.03)
    assert float(r1["new_trial_q95"]) == pytest.approx(100 * math.exp(z90 * sd), rel=0.03)
    assert (rows["R0"]["level"], float(rows["R0"]["median"]), rows["R0"]["unit"], rows["R0"]["spread"]) == ("shared", 10.0, "Ohm", "")
    assert (rows["C1"]["unit"], float(rows["C1"]["q95"])) == ("F", 1e-5)
    assert (rows["delta"]["level"], float(rows["delta"]["median"])) == ("discrepancy", 0.02)
