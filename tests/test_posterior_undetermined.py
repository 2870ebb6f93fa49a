"""A posterior's report and JSON mark the parameters the data do not determine
(`Posterior.undetermined`): their intervals are the priors', not a measurement."""

import numpy as np
import pytest

import impedax as ix


def _pad(seed=3):
    """SYNTHETIC electroadhesive pad: R_EP ∥ (C_EP + C_gap) with 1 % complex noise, written here;
    C_EP and C_gap in parallel are one capacitor to the data."""
    rng = np.random.default_rng(seed)
    f = np.geomspace(10, 1e6, 40)
    z = 1 / (1 / 50e6 + 2j * np.pi * f * (2e-9 + 120e-12))
    return ix.make_spectrum(f, z * (1 + 0.01 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)))


@pytest.fixture(scope="module")
def pad_posterior():
    return ix.sample("R_EP || C_EP || C_gap", _pad(), reparametrization=ix.gap_thickness_reparametrization("C_gap", area=4e-4), steps=600, progress=False)


def test_an_unidentified_pair_is_marked_in_the_report_and_the_json_a_reparametrized_one_by_what_it_replaces(pad_posterior):
    post = pad_posterior
    assert post.undetermined == ("C_EP", "u")
    rows = {line.split()[0]: line for line in post.report().splitlines() if line.split() and line.split()[0] in post.names}
    assert rows["u"].endswith("← NOT DETERMINED") and rows["C_EP"].endswith("← NOT DETERMINED")
    assert "NOT DETERMINED" not in rows["R_EP"] and "NOT DETERMINED" not in rows["sigma_rel"]
    assert "← C_EP, u: not determined by the data" in post.report()
    assert post.summary()["undetermined"] == ["C_EP", "u"]
    # what the data do fix: the sum of the two capacitors, 2.12 nF, within the noise
    assert abs(post.fit.values["C_EP"] + post.fit.values["C_gap"] - 2.12e-9) < 0.03 * 2.12e-9


def test_a_determined_model_has_no_mark():
    post = ix.sample("R_EP || C_gap", _pad(), steps=600, progress=False)
    assert post.undetermined == () and "NOT DETERMINED" not in post.report() and post.summary()["undetermined"] == []


def test_derive_names_the_undetermined_parameters_a_quantity_rests_on(pad_posterior):
    """The gap force rests on u (not determined here); R_EP's own square does not."""
    post = pad_posterior
    eps0 = 8.8541878128e-12
    force = post.derive(lambda p: 0.5 * eps0 * 4e-4 * 200.0**2 / p["u"] ** 2)
    assert force.attrs["undetermined"] == "u" and "priors take over" in force.attrs["warning"]
    assert "undetermined" not in post.derive(lambda p: p["R_EP"] ** 2).attrs


def test_a_parameter_run_out_of_z_to_a_bound_is_left_to_the_priors():
    """The rule of `Posterior.undetermined` and `SharedPosterior.undetermined` for one start-fit
    parameter: a relative standard error above 100 % off a bound; at a bound only with an infinite
    standard error (a vanishing term's, R2 open at ∞; other bounds give NaN)."""
    from impedax.fitting.least_squares.branches import left_to_priors

    assert left_to_priors(3.8e84, np.inf, True)  # R2 run to ∞ beside a CPE
    assert not left_to_priors(1.0, np.nan, True)  # CPE2.alpha at 1: its bound note speaks for it
    assert left_to_priors(2.0, 3.0, False) and not left_to_priors(2.0, 1.0, False)  # 150 % and 50 %


def test_a_start_fit_warning_is_repeated_without_advising_to_sample(pad_posterior):
    """The posterior is the sample the start fit's warning asks for: its report repeats the
    warning without "for an honest interval, sample the posterior (impedax sample)"."""
    import dataclasses

    text = "CPE1.alpha = 0.781 ± 0.11 lies within 2 standard errors of its upper bound 1: the ± is not symmetric there (no value lies beyond the bound)"
    post = dataclasses.replace(pad_posterior, fit=dataclasses.replace(pad_posterior.fit, warnings=(text + "; for an honest interval, sample the posterior (impedax sample)",)))
    assert f"least-squares start: {text}" in post.warnings
    assert not any("impedax sample" in w for w in post.warnings)


def test_a_parameter_whose_draws_pile_up_at_its_prior_edge_is_marked_as_the_undetermined_are():
    """REAL exampleData.csv with the EDL model: the start fit ends with C_gap at its bound 0 (NaN
    standard error: not the start fit's rule), and the draws pile up against the lower end of its
    log-uniform prior. The table said nothing on C_gap's row, the warning alone did (2026-12-06);
    its mark is AT PRIOR EDGE, as the line under the table says (NOT DETERMINED until 2026-12-06:
    tests/test_prior_edge_mark.py)."""
    from pathlib import Path

    data = ix.load(Path(__file__).parent / "fixtures" / "real" / "exampleData.csv")
    post = ix.sample("R_EP || CPE_EP || C_gap", data, steps=1500, progress=False)
    # the pile-up by hand, in the prior's log coordinate: the lowest 1 % of ln C_gap's range holds
    # the draws more densely than the draws' central 90 % does (1.4× here): the likelihood has not
    # fallen off by the prior's edge
    lo, hi = post.priors["C_gap"].a, post.priors["C_gap"].b
    t = np.log(post.samples["C_gap"] / lo) / np.log(hi / lo)
    t05, t95 = np.quantile(t, [0.05, 0.95])
    assert np.mean(t <= 0.01) / 0.01 > 0.9 / (t95 - t05)
    rows = {line.split()[0]: line for line in post.report().splitlines() if line.split() and line.split()[0] in post.names}
    assert rows["C_gap"].endswith("← AT PRIOR EDGE"), rows["C_gap"]
    assert "←" not in rows["CPE_EP.Q"] and "←" not in rows["sigma_rel"]
    assert "← C_gap: its draws pile up against an edge of its prior or bound" in post.report()
    assert post.summary()["piled_up"]["C_gap"] == "lower"
    table = {r["name"]: r["at_prior_edge"] for r in post.to_table()}  # (the CSV's column and the notebook view's mark, 2026-12-06)
    assert table["C_gap"] and not table["CPE_EP.Q"] and not table["sigma_rel"]
    assert post.summary()["at_prior_edge"] == ["C_gap"] and "C_gap" not in post.summary()["undetermined"]
    assert "← C_gap: its draws pile up" in post._repr_html_()


def test_the_table_and_the_notebook_view_mark_the_undetermined_rows(pad_posterior, tmp_path):
    """C_EP and C_gap in parallel are one capacitor to the data (`_pad`): C_EP, u and C_gap (which
    u replaces) are not determined, R_EP and sigma_rel are. The CSV (`to_table`) had no column for
    it and the notebook view no mark, where the text report marks the rows (2026-12-06)."""
    import csv

    post = pad_posterior
    ix.write_result(post, tmp_path / "post.csv")
    with open(tmp_path / "post.csv", newline="") as handle:
        rows = {r["name"]: r for r in csv.DictReader(line for line in handle if not line.startswith("#"))}
    assert {n: rows[n]["undetermined"] for n in ("C_EP", "u", "C_gap", "R_EP", "sigma_rel")} == {
        "C_EP": "true", "u": "true", "C_gap": "true", "R_EP": "false", "sigma_rel": "false"}  # (the CSV writes bools as true/false)
    html_rows = {row.split("</td>")[0].removeprefix("<td>"): row for row in post._repr_html_().split("<tr>")[2:]}
    assert "NOT DETERMINED" in html_rows["C_EP"] and "NOT DETERMINED" in html_rows["u"]
    assert "NOT DETERMINED" not in html_rows["R_EP"] and "NOT DETERMINED" not in html_rows["sigma_rel"]
    assert "← C_EP, u: not determined by the data" in post._repr_html_()


def test_an_undefined_waic_reads_undefined_in_text_and_null_in_json(pad_posterior):
    """The evidence line printed "WAIC = nan (p_waic nan)" where the Laplace part beside it said
    "undefined" (2026-12-06); the JSON keeps null for it (docs/bayesian.md, "Command line")."""
    import dataclasses
    import json
    import math

    from impedax.io.export import to_jsonable

    post = dataclasses.replace(pad_posterior, waic=math.nan, p_waic=math.nan)
    evidence = next(line for line in post.report().splitlines() if line.startswith("evidence"))
    assert evidence.endswith("WAIC undefined (see the warnings)") and "nan" not in evidence
    assert "WAIC undefined" in post._repr_html_() and "WAIC nan" not in post._repr_html_()
    doc = json.loads(json.dumps(to_jsonable(post.summary()), allow_nan=False))
    assert doc["waic"] is None and doc["p_waic"] is None  # (as before: an unknown figure is null)
    finite = next(line for line in pad_posterior.report().splitlines() if line.startswith("evidence"))
    assert f"WAIC = {pad_posterior.waic:.2f} (p_waic {pad_posterior.p_waic:.3g})" in finite


def test_both_figures_undefined_send_to_the_warnings_once(pad_posterior):
    """With Laplace ln Z and WAIC both undefined the evidence line said "(see the warnings)" twice
    (2026-12-06); it names both figures and says it once. One undefined figure keeps its own words."""
    import dataclasses
    import math

    both = dataclasses.replace(pad_posterior, waic=math.nan, p_waic=math.nan, log_evidence=math.nan)
    evidence = next(line for line in both.report().splitlines() if line.startswith("evidence"))
    assert evidence == "evidence   Laplace ln Z and WAIC undefined (see the warnings)"
    only_laplace = dataclasses.replace(pad_posterior, log_evidence=math.nan)
    evidence = next(line for line in only_laplace.report().splitlines() if line.startswith("evidence"))
    assert evidence.startswith("evidence   Laplace ln Z undefined (see the warnings)    WAIC = ") and evidence.count("see the warnings") == 1
