"""A posterior's table (`to_table`, the CSV of `impedax sample --out x.csv`) lists the
parameters held fixed, as a fit's does: on REAL exampleDataZPlot.z, `sample --fix R0=5` printed
"R0 5 (fixed)" in its report while the CSV had no R0 row, so the table alone no longer gave the
model's values (`impedax fit --fix R0=5 --out f.csv` has the row, `fixed` true). SYNTHETIC data:
R0 + R1 ∥ C1 by formula, 1 % noise."""

import csv

import numpy as np

import impedax as ix
from test_shared_posterior_roundtrip import with_sigma  # noqa: F401  (a fixture: a joint posterior with R0 fixed at 50 Ω)

FREQ = np.geomspace(1.0, 1e5, 30)


def test_a_fixed_parameter_has_its_row_and_the_fixed_column(tmp_path):
    rng = np.random.default_rng(2)
    z = 20 + 500 / (1 + 2j * np.pi * FREQ * 500 * 1e-6)
    data = ix.make_spectrum(FREQ, z * (1 + 0.01 * (rng.normal(size=FREQ.size) + 1j * rng.normal(size=FREQ.size))))
    post = ix.sample("R0 + R1 || C1", data, fixed={"R0": 20.0}, steps=40, walkers=16, seed=1, progress=False)
    path = tmp_path / "post.csv"
    ix.write_result(post, path)
    with open(path, newline="", encoding="utf-8") as fh:
        rows = {row["name"]: row for row in csv.DictReader(fh)}
    assert set(rows) == {"R1", "C1", "sigma_rel", "R0"}
    r0 = rows["R0"]
    assert r0["fixed"] == "true" and r0["unit"] == "Ohm" and r0["autocorr"] == "" and r0["undetermined"] == "false"
    assert all(float(r0[k]) == 20.0 for k in ("median", "q05", "q16", "q84", "q95"))
    for name in ("R1", "C1", "sigma_rel"):
        assert rows[name]["fixed"] == "false"
        assert float(rows[name]["median"]) == np.median(post.samples[name])  # (the sampled rows as before)


def test_a_joint_posteriors_table_has_its_fixed_rows_too(with_sigma):  # noqa: F811
    table = with_sigma.to_table()
    fixed = [row for row in table if row["fixed"]]
    assert [(row["name"], row["median"], row["q95"], row["unit"]) for row in fixed] == [("R0", 50.0, 50.0, "Ohm")]
    assert [row["name"] for row in table if not row["fixed"]] == list(with_sigma.names)


def test_a_joint_posteriors_report_lists_its_fixed_values(with_sigma):  # noqa: F811
    """A single spectrum's report ends its table with "R0  5  (fixed)  Ω"; a joint posterior's
    (`sample --shared ... --fix R0=50`) left R0 out of its report altogether."""
    lines = with_sigma.report().splitlines()
    (row,) = [line for line in lines if line.split()[:1] == ["R0"]]
    assert row.split() == ["R0", "50", "(fixed)", "Ω"]
    header = next(i for i, line in enumerate(lines) if line.startswith("parameter"))
    assert lines.index(row) == header + len(with_sigma.names) + 1  # (after the sampled rows, before the footnotes)
