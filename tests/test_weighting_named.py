"""Every output of a fit names the weighting it was made with: the figures' titles (single fit,
batch, comparison) and the text of a batch and of a comparison, as the single fit's report and
every JSON do. A walkthrough (2026-12-06) fitted REAL exampleData.csv (impedance.py's milliohm
battery spectrum) with ``--weighting proportional`` and ``unit``: the report said so, but the
figure, the comparison's table and figure and a batch of REAL battery cycles did not, so a
figure of a proportional fit read as one of the default.

Oracles: the titles read back from matplotlib (``Figure._suptitle``), the report's lines, and
the chi2_red of a unit-weighted fit recomputed with numpy (Σ|ΔZ|² [Ω²] / (2N − k)).
"""

import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.io.export import to_jsonable  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "tests" / "fixtures" / "real" / "exampleData.csv"
BATTERY = ROOT / "benchmarks" / "data" / "autoeis_battery_130.nc"
MODEL, SMALLER = "R0 + R1 || CPE1 + L0", "R0 + R1 || C1 + L0"


def title_of(fig) -> str:
    """The figure's title (its suptitle), the figure closed."""
    try:
        return fig._suptitle.get_text()
    finally:
        plt.close(fig)


@pytest.fixture(scope="module")
def unit_fits():
    data = ix.load(EXAMPLE)
    return ix.fit(MODEL, data, weighting="unit", progress=None), ix.fit(SMALLER, data, weighting="unit", progress=None)


def test_a_single_fits_figure_names_its_weighting(unit_fits):
    fit = unit_fits[0]
    assert "unit weighting" in title_of(fit.plot())


def test_a_comparison_names_its_weighting_in_its_table_and_figure(unit_fits):
    fit = unit_fits[0]
    d = fit.z_model - fit.z_data
    assert fit.chi2_red == pytest.approx(float(np.sum(d.real**2 + d.imag**2)) / (2 * fit.n_points - fit.n_params), rel=1e-9)
    comparison = ix.compare(list(unit_fits))
    lines = comparison.table().splitlines()
    assert any(ln.startswith("weighting unit: chi2_red relative to 1 Ω, not to the noise") for ln in lines[len(unit_fits) + 1:]), lines
    assert "unit weighting" in title_of(comparison.plot())


def test_a_comparisons_csv_names_its_weighting(unit_fits, tmp_path):
    import csv

    ix.write_result(ix.compare(list(unit_fits)), tmp_path / "c.csv")
    assert [row["weighting"] for row in csv.DictReader((tmp_path / "c.csv").open())] == ["unit", "unit"]


@pytest.fixture(scope="module")
def proportional_batches():
    cycles = ix.load(BATTERY).isel(cycle=[0, 64])
    return [ix.fit(m, cycles, weighting="proportional", progress=None) for m in ("R0 + R1 || CPE1 + W1", "R0 + R1 || C1 + W1")]


def test_a_batch_names_its_weighting_in_its_report_and_figure(proportional_batches):
    batch = proportional_batches[0]
    assert "weighting proportional" in batch.report().splitlines()[1]
    assert "proportional weighting" in title_of(batch.plot())


def test_a_comparison_of_batches_names_its_weighting_in_its_figure(proportional_batches):
    comparison = ix.compare(proportional_batches)
    assert comparison.report().splitlines()[0].endswith("weighting proportional")
    assert "proportional weighting" in title_of(comparison.plot())


@pytest.fixture(scope="module")
def proportional_diagnosis():
    return ix.diagnose(ix.load(EXAMPLE), "R0 + R1 || CPE1 + R2 || CPE2 + W1", weighting="proportional", progress=None)


def test_diagnose_passes_on_a_baseline_dominated_by_a_few_points(proportional_diagnosis):
    """REAL exampleData.csv crosses Z'' = 0 near 1.4 kHz (its lead inductance): under the
    proportional weighting the residuals of Im Z there are divided by a tiny |Im Z|. ``impedax fit``
    warned that 2 points carry most of the weight; ``diagnose --weighting proportional`` of the same
    fit said nothing (its baseline's warnings were dropped). Oracle: the points that carry over
    half of Σ (|Z|/|Re Z|)² + (|Z|/|Im Z|)², the file's own numbers read with numpy."""
    f, re_z, im_z = np.loadtxt(EXAMPLE, delimiter=",", unpack=True)
    modulus = np.hypot(re_z, im_z)
    weight = np.concatenate([(modulus / np.abs(re_z)) ** 2, (modulus / np.abs(im_z)) ** 2])
    order = np.argsort(-weight)
    heavy = order[: int(np.searchsorted(np.cumsum(weight[order]), 0.5 * weight.sum())) + 1] % f.size
    named = sorted(set(f[heavy].tolist()))
    assert len(named) == 2 and 1e3 < named[0] < named[1] < 2e3  # (1.26 kHz and 1.58 kHz, beside the zero crossing)
    diagnosis = proportional_diagnosis
    lines = [w for w in diagnosis.warnings if "proportional weighting gives 2 of 66 points" in w]
    assert len(lines) == 1 and lines[0].startswith("the baseline fit: "), diagnosis.warnings
    assert "(" + ", ".join(ix.data.format_frequency(x) for x in named) + ")" in lines[0]
    assert lines[0] in diagnosis.report()


def test_a_diagnosis_figure_names_its_weighting(proportional_diagnosis):
    assert "proportional weighting" in title_of(proportional_diagnosis.plot())


def test_diagnose_json_names_the_weighting_its_baseline_chi2_red_is_against(proportional_diagnosis):
    """The baseline's chi2_red (0.124 here, against |Re Z| and |Im Z|) means another thing under
    each weighting: the JSON's ``baseline`` says which, as fit --json's ``weighting`` does (the
    text's first line said it; the JSON of ``ix.write_result(diagnosis, ...)`` did not)."""
    doc = json.loads(json.dumps(to_jsonable(proportional_diagnosis.summary())))
    assert doc["baseline"]["weighting"] == "proportional"
    assert "(proportional weighting: residuals relative to |Re Z| and |Im Z|" in proportional_diagnosis.report().splitlines()[0]


@pytest.mark.parametrize("noise, words", [("proportional", "noise σ ∝ |Z|"), ("sigma", "noise σ: the data's sigma")])
def test_a_posteriors_figures_name_its_noise_model(noise, words):
    """``impedax sample --noise sigma`` and the default proportional noise give other bands and
    intervals (the predictive band is model + noise): the figures' titles say which, as the
    report's ``noise`` line does. REAL exampleData.csv with a sigma of 0.2 % of |Z| added."""
    data = ix.load(EXAMPLE)
    data = data.assign(sigma=0.002 * np.abs(data["Z"]))
    posterior = ix.sample("R0 + R1 || CPE1 + L0", data, noise=noise, walkers=16, steps=60, burn=20, progress=False)
    for fig in (posterior.plot(), posterior.corner()):
        try:
            assert words in fig._suptitle.get_text(), fig._suptitle.get_text()
        finally:
            plt.close(fig)


@pytest.mark.parametrize("words, expected", [
    (["--weighting", "sigma"], "impedax sample has no --weighting: its noise model is --noise proportional"),
    (["--weighting=unit"], "impedax sample has no --weighting: its noise model is --noise proportional"),
    (["--noise", "modulus"], "'modulus' is a weighting of impedax fit: sample's --noise proportional is that weighting's noise model"),
    (["--noise", "unit"], "'unit' is a weighting of impedax fit: sample's noise models are proportional"),
])
def test_sample_refuses_a_weighting_with_its_noise_model_named(words, expected, capsys):
    """A user who fits with --weighting reaches for it on sample: argparse said "unrecognized
    arguments: --weighting sigma" (or "invalid choice: 'modulus'"), not that sample's noise model
    is its --noise. One message, exit 2, before any work."""
    from impedax.cli import main

    with pytest.raises(SystemExit) as stopped:
        main(["sample", str(EXAMPLE), "--model", "R0 + R1 || C1", *words])
    assert stopped.value.code == 2
    err = capsys.readouterr().err
    assert expected in err and err.count("error:") == 1, err


def test_diagnose_under_sigma_weighting_names_it_and_sets_chi2_red_beside_the_noise_it_judges_by():
    """REAL exampleData.csv with a sigma of 0.2 % of |Z| (0.6 % below 0.1 Hz) added, diagnosed
    with --weighting sigma: the first line read "chi2_red 9.56" bare (no weighting named), and the
    noise line under it "the residuals are 1.81× the noise" (the sigma with the model-discrepancy
    floor), 1.81² = 3.3, not 9.56: the contradiction the other weightings' note resolves. Oracles:
    χ² against the data's sigma with numpy, and the report's own noise ratio squared."""
    data = ix.load(EXAMPLE)
    f = data["frequency"].values
    data = data.assign(sigma=0.002 * np.abs(data["Z"]) * np.where(f < 0.1, 3.0, 1.0))
    diagnosis = ix.diagnose(data, "R0 + R1 || CPE1 + R2 || CPE2 + W1 + L0", weighting="sigma", progress=None)
    base = diagnosis.baseline
    sigma = data["sigma"].sel(frequency=base.frequency).values
    d = (base.z_model - base.z_data) / sigma
    assert base.chi2_red == pytest.approx(float(np.sum(d.real**2 + d.imag**2)) / (2 * base.n_points - base.n_params), rel=1e-9)
    first, *rest = diagnosis.report().splitlines()
    ratio = float(next(ln for ln in rest if ln.startswith("noise: ")).split("the residuals are ")[1].split("×")[0])
    assert f"chi2_red {base.chi2_red:.3g} (sigma weighting: residuals relative to the data's sigma" in first, first
    if not 0.8 < ratio**2 / base.chi2_red < 1.25:
        shown = float(first.split("against the noise σ given below, chi2_red ≈ ")[1].split(",")[0])
        assert shown == pytest.approx(ratio**2, rel=0.01), first  # (the ratio printed to 3 digits)


def test_the_notebook_displays_name_the_weighting(unit_fits, proportional_batches):
    """`_repr_html_` of a fit and of a batch (what a notebook shows): the weighting, as the text
    reports give it (a sigma-weighted fit's HTML had no word of it)."""
    assert "weighting unit" in unit_fits[0]._repr_html_()
    assert "weighting proportional" in proportional_batches[0]._repr_html_()


def test_a_long_models_fit_figure_keeps_its_title_inside():
    """The title now ends with the weighting: a long model's ran off the figure (it did before
    with the rms_rel alone; it is wrapped before a ' + ' now). Oracle: matplotlib's extents."""
    from test_cli_review import outside_the_figure

    model = "R0 + (R1 + (R_relax + (R_relax2 + R_relax4 || C_relax3) || C_relax2) || C_relax) || CPE1 + CPE_relax + L_lead + C_stray"
    fit = ix.fit(model, ix.load(EXAMPLE), weighting="proportional", max_steps=5, n_starts=1, progress=None)
    fig = fit.plot()
    try:
        assert outside_the_figure(fig) == [] and fig._suptitle.get_text().endswith("proportional weighting")
    finally:
        plt.close(fig)


def test_a_fits_csv_written_from_python_names_its_weighting(unit_fits, proportional_batches, tmp_path):
    """``ix.write_result(fit, "fit.csv")``: chi2, chi2_red and aic on every row mean another thing
    under each weighting, and only the command line's provenance columns (``setting_weighting``)
    said which; a CSV written from Python had no word of it. Oracle: the file read back with
    the csv module."""
    import csv

    for result, weighting in ((unit_fits[0], "unit"), (proportional_batches[0], "proportional")):
        path = tmp_path / f"{weighting}.csv"
        ix.write_result(result, path)
        rows = list(csv.DictReader(path.open()))
        assert rows and {row["weighting"] for row in rows} == {weighting}
