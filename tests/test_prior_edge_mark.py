"""A row whose draws only pile up against an edge of its prior was marked "← NOT DETERMINED"
while the line under the table explained a pile-up at a prior's edge (REAL exampleDataGamry.DTA's
R0 with R0 + R1 ∥ CPE1, 2026-12-06). Such a row is now marked "← AT PRIOR EDGE", as the line
under it says, in the report, the notebook view, the JSON (key ``at_prior_edge``, added) and the
CSV (column ``at_prior_edge``, added last; ``undetermined`` keeps the start fit's rule); NOT
DETERMINED stays on the parameters the data do not determine.

Oracle: a SYNTHETIC R0 + R1 ∥ C1 spectrum (numpy formula) whose series R0 is 0: the data put R0
at the lower end of any prior, while R1 = 1 kΩ and C1 = 1 µF are well determined; the pile-up is
checked by hand in the prior's log coordinate."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

pytestmark = pytest.mark.slow  # (the sampler's compilation: ~10 s on the shared 2-core machine)

F = np.geomspace(0.1, 1e4, 30)


def _no_series_resistance():
    rng = np.random.default_rng(1)
    z = 0.0 + 1e3 / (1 + 2j * np.pi * F * 1e3 * 1e-6)  # R0 = 0
    return ix.make_spectrum(F, z * (1 + 0.05 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2)))


@pytest.fixture(scope="module")
def posterior():
    return ix.sample("R0 + R1 || C1", _no_series_resistance(), steps=400, walkers=16, progress=False)


def _rows(post):
    return {line.split()[0]: line for line in post.report().splitlines() if line.split() and line.split()[0] in post.names}


def test_a_row_at_its_prior_edge_is_marked_so_not_undetermined(posterior, tmp_path):
    post = posterior
    # by hand: the lowest 1 % of ln R0's prior range holds the draws more densely than their central 90 % does
    lo, hi = post.priors["R0"].a, post.priors["R0"].b
    t = np.log(post.samples["R0"] / lo) / np.log(hi / lo)
    t05, t95 = np.quantile(t, [0.05, 0.95])
    assert np.mean(t <= 0.01) / 0.01 > 0.9 / (t95 - t05)
    # R1 and C1 are determined: the truth inside their 90 % intervals, which are narrow
    for name, truth in (("R1", 1e3), ("C1", 1e-6)):
        q05, q95 = np.quantile(post.samples[name], [0.05, 0.95])
        assert q05 < truth < q95 and q95 / q05 < 1.2
    rows = _rows(post)
    assert rows["R0"].endswith("← AT PRIOR EDGE"), rows["R0"]
    assert not [n for n, line in rows.items() if "←" in line and n != "R0"]
    assert "NOT DETERMINED" not in post.report()
    assert "← R0: its draws pile up against an edge of its prior or bound" in post.report()
    summary = post.summary()
    assert summary["at_prior_edge"] == ["R0"] and summary["undetermined"] == [] and summary["piled_up"] == {"R0": "lower"}
    table = {r["name"]: r for r in post.to_table()}
    assert table["R0"]["at_prior_edge"] and not table["R0"]["undetermined"]
    assert not any(table[n]["at_prior_edge"] or table[n]["undetermined"] for n in ("R1", "C1", "sigma_rel"))
    assert list(table["R0"])[-5:] == ["undetermined", "fixed", "at_prior_edge", "chain_converged", "warnings"]  # (each added last: the columns before keep their places)
    ix.write_result(post, tmp_path / "post.csv")
    with open(tmp_path / "post.csv", newline="") as handle:
        written = {r["name"]: r for r in csv.DictReader(line for line in handle if not line.startswith("#"))}
    assert (written["R0"]["undetermined"], written["R0"]["at_prior_edge"]) == ("false", "true")
    html = {row.split("</td>")[0].removeprefix("<td>"): row for row in post._repr_html_().split("<tr>")[2:]}
    assert "AT PRIOR EDGE" in html["R0"] and "NOT DETERMINED" not in html["R0"] and "←" not in html["R1"]


def test_the_command_line_marks_it_in_text_and_json(tmp_path, capsys):
    path = tmp_path / "rc.csv"
    ix.save(_no_series_resistance(), path)
    argv = ["sample", str(path), "--model", "R0 + R1 || C1", "--steps", "400", "--walkers", "16", "--quiet"]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert next(line for line in text.splitlines() if line.startswith("R0 ")).endswith("← AT PRIOR EDGE")
    assert main([*argv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["at_prior_edge"] == ["R0"] and doc["undetermined"] == [] and doc["piled_up"] == {"R0": "lower"}
