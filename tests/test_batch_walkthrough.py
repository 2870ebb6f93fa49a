"""Batches after a user walkthrough on REAL battery spectra (benchmarks/data/autoeis_battery_130.nc):
a batch of fits as the starts of the next (docs/fitting.md, "What the default costs"), the
compare() of batches and its message for data that differ, the batch JSON's weighting, and
the labels of a shared fit's groups. Oracles: the first batch's own values and χ², the data's
labels and point counts, and the options given."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.errors import ParameterError

BATTERY = Path(__file__).resolve().parents[1] / "benchmarks" / "data" / "autoeis_battery_130.nc"
MODEL = "R0 + R1 || CPE1 + R2 || CPE2"


@pytest.fixture(scope="module")
def cycles():
    return ix.load(BATTERY).isel(cycle=[10, 11, 12, 13])


@pytest.fixture(scope="module")
def first(cycles):
    return ix.fit(MODEL, cycles, n_starts=1)


def test_a_batch_starts_each_spectrum_of_the_next_from_its_own_optimum(cycles, first):
    names = [str(p) for p in first.dataset["param"].values]
    starts = first.per_spectrum_starts(cycles, names)
    assert np.array_equal(starts, first.dataset["value"].transpose("cycle", "param").values)
    # a spectrum takes the fit with its label, in whatever order the data list them
    backwards = cycles.isel(cycle=[3, 2, 1, 0])
    assert np.array_equal(first.per_spectrum_starts(backwards, names), starts[::-1])
    # without arguments: this batch's own spectra and parameters (a bare call was Python's TypeError)
    assert np.array_equal(first.per_spectrum_starts(), starts)
    with pytest.raises(ix.ParameterError, match=r"data= takes the spectra to start .* not list; leave it out"):
        first.per_spectrum_starts(names)
    with pytest.raises(ix.ParameterError, match=r"names= takes a list of parameter names .* not 'R0'; leave it out"):
        first.per_spectrum_starts(cycles, "R0")
    again = ix.fit(MODEL, backwards, init=first, n_starts=1)
    # started at the optimum, each local fit stays there
    for label in cycles["cycle"].values:
        assert float(again.dataset["chi2"].sel(cycle=label)) <= float(first.dataset["chi2"].sel(cycle=label)) * (1 + 1e-6)
        for name in ("R0", "R1", "CPE1.alpha"):
            assert float(again.values(name).sel(cycle=label)) == pytest.approx(float(first.values(name).sel(cycle=label)), rel=1e-4)


def test_a_batch_read_back_from_netcdf_starts_the_next(tmp_path, cycles, first):
    ix.write_result(first, tmp_path / "b.nc")
    saved = ix.BatchFitResult.from_xarray(ix.load(tmp_path / "b.nc"))
    again = ix.fit(MODEL, cycles, init=saved, n_starts=1)
    assert np.all(again.dataset["chi2"].values <= first.dataset["chi2"].values * (1 + 1e-6))


def test_a_part_of_the_batch_or_its_dates_read_back_start_by_label(tmp_path, cycles, first):
    """Three of the four cycles take their own fits (the suggested data.sel(...) raised a
    KeyError on such a part); dates written to a file come back in ns where the data hold µs,
    and were refused as labels "not in" the batch (2026-12-03 walkthrough)."""
    part = ix.fit(MODEL, cycles.isel(cycle=[3, 0, 2]), init=first, n_starts=1)
    for label in cycles["cycle"].values[[3, 0, 2]]:
        assert float(part.values("R1").sel(cycle=label)) == pytest.approx(float(first.values("R1").sel(cycle=label)), rel=1e-4)
    dates = cycles.assign_coords(cycle=np.array(["2024-01-01", "2024-01-02", "2024-01-03", "2024-01-04"], dtype="datetime64[us]"))
    dated = ix.fit(MODEL, dates)
    ix.write_result(dated, tmp_path / "dated.nc")
    saved = ix.BatchFitResult.from_xarray(ix.load(tmp_path / "dated.nc"))
    again = ix.fit(MODEL, dates, init=saved, n_starts=1)
    assert np.all(again.dataset["chi2"].values <= dated.dataset["chi2"].values * (1 + 1e-6))


@pytest.mark.parametrize(
    "pick, message",
    [
        (lambda d: d.isel(cycle=0), "for one spectrum use one of its fits, e.g. init=batch.fit_of(cycle=…)"),
        (lambda d: d.isel(cycle=[0, 1, 2]).drop_vars("cycle"), "the batch of fits has 4 spectra along cycle, the data 3, and without labels along cycle they are matched by position"),
        (lambda d: d.assign_coords(cycle=d["cycle"].values + 100), "not in it: 110, 111, 112, 113"),
        (lambda d: d.rename(cycle="cell"), "the batch of fits is over cycle but the data's spectra are over cell"),
    ],
)
def test_a_batch_of_other_spectra_as_init_is_one_clear_error(cycles, first, pick, message):
    with pytest.raises(ParameterError, match="^init: ") as info:
        ix.fit(MODEL, pick(cycles), init=first, n_starts=1)
    assert message in str(info.value)


def test_what_the_user_tried_is_answered_with_what_works(cycles, first):
    with pytest.raises(ParameterError, match=r"got the method BatchFitResult\.values; pass the batch itself \(init=batch\)"):
        ix.fit(MODEL, cycles, init=first.values, n_starts=1)
    with pytest.raises(ParameterError, match=r"init\['R0'\] must be a number, got an array of shape \(4,\).*init=batch"):
        ix.fit(MODEL, cycles, init={n: first.values(n).values for n in ("R0", "R1")}, n_starts=1)
    with pytest.raises(ParameterError, match="a shared fit"):
        ix.fit(MODEL, cycles, init=first, shared=["R0"], over="cycle")


def test_batch_json_gives_the_weighting(first, cycles):
    assert first.summary()["weighting"] == "modulus"
    assert ix.fit(MODEL, cycles, init=first, n_starts=1, weighting="proportional").summary()["weighting"] == "proportional"


@pytest.mark.slow  # (the suite's 15-minute budget, 2026-12-01: make test-all runs it)
def test_a_shared_fit_per_cell_labels_each_row_and_f_test(capsys):
    """Two cells × three cycles, shared over cycle: one R0 and one CPE1.alpha per cell. The rows
    and F-tests printed were unlabelled duplicates; the oracle is the Dataset's values by cell."""
    from impedax.cli import main

    data = ix.load(BATTERY).isel(cycle=slice(0, 6))
    d2 = xr.Dataset({"Z": (("cell", "cycle", "frequency"), data["Z"].values.reshape(2, 3, -1))}, coords={"frequency": data["frequency"].values, "cell": ["A", "B"], "cycle": [0, 1, 2]})
    r = ix.fit("R0 + R1 || CPE1 + R2 || C2", d2, shared=["CPE1.alpha", "R0"], over="cycle")
    text = r.report()
    for cell in ("A", "B"):
        for name in ("R0", "CPE1.alpha"):
            value = float(r.dataset["shared_value"].sel(shared_param=name, cell=cell))
            (row,) = [ln for ln in text.splitlines() if ln.startswith(f"cell={cell} ") and ln.split()[1] == name]
            assert float(row.split()[2]) == pytest.approx(value, rel=1e-4)
        (test,) = [ln for ln in text.splitlines() if ln.startswith(f"sharing vs independent fits (cell={cell}): F = ")]
        assert f"F = {float(r.dataset['f_statistic'].sel(cell=cell)):.3g}," in test
    summary = r.summary()
    assert summary["shared"]["R0"]["labels"] == [{"cell": "A"}, {"cell": "B"}] == summary["sharing"]["labels"]
    assert summary["shared"]["R0"]["value"] == pytest.approx(r.dataset["shared_value"].sel(shared_param="R0").transpose("cell").values.tolist())
    # a shared fit over every dimension has one value and no labels
    one = ix.fit("R0 + R1 || CPE1 + R2 || C2", d2.isel(cell=0), shared=["R0"], over="cycle")
    assert "labels" not in one.summary()["shared"]["R0"] and "sharing vs independent fits: F = " in one.report()


def test_compare_of_batches_compares_them_spectrum_by_spectrum(cycles, first):
    """Refused until 2026-12-01 (compare took fits of one spectrum); now a `BatchComparison`
    (tests/test_compare_batches.py). The same batch twice: one fit, so every spectrum splits
    the weight 0.5/0.5 and the second is labelled "(2)", as the single path labels it."""
    from impedax.errors import ParameterError as PE

    both = ix.compare([first, first])
    assert both.labels == [MODEL, f"{MODEL} (2)"] and both.n_spectra == 4
    assert np.allclose(both.dataset["delta_aic"].values, 0.0) and np.allclose(both.dataset["akaike_weight"].values, 0.5)
    with pytest.raises(PE) as info:
        ix.compare([first, "R0 + R1"])
    assert str(info.value).startswith("fits[1] must be a FitResult (or Posterior, or BatchFitResult), got ")


def test_compare_of_fits_to_different_data_says_how_they_differ(cycles):
    from impedax.errors import FitError

    d = cycles.isel(cycle=0)
    whole = ix.fit("R0 + R1 || CPE1", d, n_starts=1)
    cut = ix.fit("R0 + R1 || CPE1", d, n_starts=1, fmin=1.0)
    n_cut = int((d["frequency"] >= 1.0).sum())
    with pytest.raises(FitError) as info:
        ix.compare([whole, cut])
    text = str(info.value)
    assert text.startswith("fits[0] and fits[1] (both R0 + R1 || CPE1) were fitted to different data: ")
    assert f"{d.sizes['frequency']} points" in text and f"against {n_cut} points" in text
    assert "(R0 + R1 || CPE1 vs R0 + R1 || CPE1)" not in text


def test_the_undetermined_legend_stays_inside_its_panel_off_the_overflow_markers():
    """R2 of R0 + R1 || CPE1 + R2 || C2 is undetermined on some REAL cycles (values far above the
    others, drawn as ▲ at the panel's top edge); the legend's one long line stuck out past the
    panel's left edge and covered those markers."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = ix.load(BATTERY).isel(cycle=[0, 4, 40, 44, 48, 52, 56, 60, 84, 88])
    batch = ix.fit("R0 + R1 || CPE1 + R2 || C2", data, n_starts=1)
    assert bool(batch.undetermined("R2").any())
    fig = batch.plot()
    try:
        fig.canvas.draw()
        (ax,) = [a for a in fig.axes if a.get_title().startswith("R2")]
        legend = ax.get_legend().get_window_extent()
        box = ax.get_window_extent()
        assert box.x0 <= legend.x0 and legend.x1 <= box.x1 and box.y0 <= legend.y0 and legend.y1 <= box.y1
        markers = [line for line in ax.get_lines() if line.get_marker() in ("^", "v")]
        for line in markers:
            for x, y in ax.transData.transform(line.get_xydata()):
                assert not legend.contains(x, y)
    finally:
        plt.close(fig)
