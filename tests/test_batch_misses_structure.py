"""`misses_structure` (a batch's, per spectrum, and a single fit's) follows one rule: a warning
says the model misses structure the data hold (the misfit checked from 2 % rms_rel), or the
misfit hint names the fit (rms_rel from 0.2 % to 2 % and over 5× what the Kramers–Kronig
test's chain reaches). Until 2026-12-06 it read the warnings alone: on the REAL 130 battery
cycles it was False for all 130 while `misfit_hints()` named 49 (and `derive` flagged none)."""

import os

import numpy as np
import pytest

import impedax as ix

BATTERY = os.path.join(os.path.dirname(__file__), "..", "benchmarks", "data", "autoeis_battery_130.nc")  # REAL, AutoEIS (MIT)


def two_arcs_and_one():
    """SYNTHETIC: four noisy copies (0.05 %) of R0 + R1 ∥ C1 (numpy formula), trials 0 and 2
    with a second arc of 50 Ω at 11 Hz that R0 + R1 ∥ C1 cannot hold."""
    f = np.geomspace(1.0, 1e5, 40)
    rng = np.random.default_rng(7)
    noise = 1 + 0.0005 * (rng.standard_normal((4, f.size)) + 1j * rng.standard_normal((4, f.size))) / np.sqrt(2)
    arc = 20 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6)
    second = 50 / (1 + 2j * np.pi * f * 50 * 3e-4)
    z = np.stack([arc + (second if k in (0, 2) else 0.0) for k in range(4)]) * noise
    return ix.make_spectrum(f, z, dims=("trial",))


@pytest.mark.slow  # (~10 s: a batch fit of 4 spectra, two single fits and their KK chains)
def test_misses_structure_marks_the_fits_missing_a_small_arc_batch_single_and_derive():
    """Oracle: the data's own making (trials 0 and 2 hold a second arc) and the rule computed
    apart, with `ix.kk_test`'s chain: rms_rel in [0.2 %, 2 %) and over 5× the chain's."""
    data = two_arcs_and_one()
    fits = ix.fit("R0 + R1 || C1", data, progress=False)
    rms = fits.dataset["rms_rel"].values
    chain = np.array([ix.kk_test(data.isel(trial=k)).rms_rel for k in range(4)])
    rule = (rms >= 0.002) & (rms < 0.02) & (rms > 5 * chain)
    assert rule.tolist() == [True, False, True, False]
    assert not any(w for ws in fits.warnings.values() for w in ws if "misses structure" in w)  # (below the warning's 2 %)
    assert fits.misses_structure.values.tolist() == [True, False, True, False]
    derived = ix.derive(fits, lambda p: p["R1"])
    assert derived["misses_structure"].values.tolist() == [True, False, True, False]
    assert derived.attrs["warning"].startswith("in 2 of 4 spectra (misses_structure)")
    assert ix.fit("R0 + R1 || C1", data.isel(trial=0), progress=False).misses_structure
    assert not ix.fit("R0 + R1 || C1", data.isel(trial=1), progress=False).misses_structure


@pytest.mark.slow  # (~18 s with compilation: a batch fit of the REAL 130 cycles and KK tests)
def test_on_the_real_battery_cycles_misses_structure_agrees_with_the_hints():
    """REAL 130 battery cycles, `R0 + R1 || CPE1 + R2 || CPE2 + W1`: misses_structure is True
    exactly on the cycles `misfit_hints` names and those whose warnings blame the model. Oracle
    of the hinted ones, apart from the rule's code: rms_rel in [0.2 %, 2 %) and above 4.5× the
    rms_rel of `ix.kk_test` on that cycle (the hint's own chain, fitted otherwise, differs by a
    few %: cycle 14 is 4.99× one and 5.3× the other)."""
    data = ix.load(BATTERY)
    fits = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + W1", data, progress=False)
    position = {int(c): i for i, c in enumerate(data["cycle"].values)}
    rms = fits.dataset["rms_rel"].transpose("cycle").values
    hinted = {position[labels["cycle"]] for labels in fits.misfit_hints()["labels"]}
    warned = {i for i, (key, _) in enumerate(fits.spectrum_keys()) if any("misses structure the data hold" in w or "the misfit is this model's" in w for w in fits.warnings.get(key, ()))}
    flags = fits.misses_structure.transpose("cycle").values
    assert len(hinted) >= 40  # (49 when this was written, none of them flagged)
    assert set(np.flatnonzero(flags).tolist()) == hinted | warned
    for i in sorted(hinted - warned):
        assert 0.002 <= rms[i] < 0.02 and rms[i] > 4.5 * ix.kk_test(data.isel(cycle=i)).rms_rel


def hand_written(rms_rel=(0.015, 0.001, 0.015, 0.05)):
    """A |Z|-weighted batch written by hand (no fit) of four SYNTHETIC RC arcs with 0.05 % noise
    (their KK chain reaches ~0.19 %) at the stated rms_rel, cycle 13 with the warning that
    blames the model."""
    import xarray as xr

    from impedax.fitting.least_squares import BatchFitResult

    f = np.geomspace(1.0, 1e5, 40)
    arc = 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6)
    rng = np.random.default_rng(1)
    z = arc * (1 + 0.0005 * (rng.standard_normal((4, f.size)) + 1j * rng.standard_normal((4, f.size))) / np.sqrt(2))
    blame = "the model misses structure the data hold: rms_rel 5 % is 26× what a Kramers–Kronig-consistent model reaches"
    ds = xr.Dataset(
        {
            "value": (("param", "cycle"), np.tile([[10.0], [100.0], [1e-6]], 4)), "stderr": (("param", "cycle"), np.tile([[0.1], [1.0], [1e-8]], 4)),
            "fixed": ("param", np.zeros(3, bool)), "at_bound": (("param", "cycle"), np.zeros((3, 4), bool)),
            "rms_rel": ("cycle", list(rms_rel)), "converged": ("cycle", np.ones(4, bool)),
            "Z": (("cycle", "frequency"), z), "Z_model": (("cycle", "frequency"), np.tile(arc, (4, 1))),
        },
        coords={"param": ["R0", "R1", "C1"], "cycle": [10, 11, 12, 13], "frequency": f},
        attrs={"model": "R0 + R1 || C1", "weighting": "modulus", "impedax_kind": "batch_fit", "warnings": {"cycle=13": [blame]} if rms_rel[3] >= 0.02 else {}},
    )
    return BatchFitResult.from_xarray(ds)


def test_each_spectrum_s_json_row_and_csv_rows_say_whether_its_model_misses_structure(tmp_path):
    """`hand_written`: stated rms_rel 1.5 %, 0.1 %, 1.5 % and 5 %. Oracle, by the rule: 1.5 % is
    over 5× the chain (hinted), 0.1 % is below the hint's 0.2 %, 5 % is the warning's. Before
    2026-12-06 neither the JSON's ``spectra`` nor the CSV said it (the REAL 130 cycles' CSV named
    none of the hint's 49)."""
    import csv

    fits = hand_written()
    expected = [True, False, True, True]
    assert fits.misses_structure.values.tolist() == expected
    assert [row["misses_structure"] for row in fits.summary()["spectra"]] == expected
    path = tmp_path / "fits.csv"
    ix.write_result(fits, str(path))
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert {row["cycle"]: row["misses_structure"] for row in rows} == {"10": "true", "11": "false", "12": "true", "13": "true"}


def test_the_batch_figure_rings_the_fits_whose_model_misses_structure():
    """`hand_written` (as above: cycles 10, 12 and 13 by the rule) in `plot`'s rms_rel panel:
    ringed and named in its legend; fits at 0.1 % (below the hint) are not."""
    import matplotlib.pyplot as plt

    fig = hand_written().plot()
    try:
        rms_panel = next(ax for ax in fig.axes if ax.get_title() == "rms_rel [%]")
        ringed = [line for line in rms_panel.get_lines() if line.get_label().startswith("model misses structure")]
        assert len(ringed) == 1 and list(ringed[0].get_xdata()) == [0, 2, 3]
        np.testing.assert_allclose(ringed[0].get_ydata(), [1.5, 1.5, 5.0])
        assert rms_panel.get_legend() is not None
    finally:
        plt.close(fig)
    fig = hand_written().plot_residual_map()  # (its rms_rel panel alike)
    try:
        ringed = [line for line in fig.axes[2].get_lines() if line.get_label().startswith("model misses structure")]
        assert len(ringed) == 1 and list(ringed[0].get_xdata()) == [0, 2, 3]
    finally:
        plt.close(fig)
    fig = hand_written((0.001,) * 4).plot()
    try:
        rms_panel = next(ax for ax in fig.axes if ax.get_title() == "rms_rel [%]")
        assert not [line for line in rms_panel.get_lines() if line.get_label().startswith("model misses structure")]
    finally:
        plt.close(fig)


ZPLOT = os.path.join(os.path.dirname(__file__), "fixtures", "real", "exampleDataZPlot.z")  # REAL, impedance.py (MIT)


@pytest.mark.slow  # (~15 s: two fits of a REAL spectrum, compilation included)
def test_a_single_fit_s_table_says_it_too():
    """REAL ZPlot file: `R0 + R1 || CPE1` misses the leads' inductance (1.35 % against the KK
    chain's 0.137 %, below the 2 % of the misfit warning: only the hint saw it; diagnose names
    the inductance); with `L0` in series it does not (0.35 %, 2.6× the chain's)."""
    without = ix.fit("R0 + R1 || CPE1", ZPLOT, progress=False)
    with_lead = ix.fit("R0 + L0 + R1 || CPE1", ZPLOT, progress=False)
    assert without.misses_structure and {row["misses_structure"] for row in without.to_table()} == {True}
    assert not with_lead.misses_structure and {row["misses_structure"] for row in with_lead.to_table()} == {False}


@pytest.mark.slow  # (~10 s: two batch fits of 4 spectra)
def test_a_batch_comparison_says_it_per_spectrum_and_model():
    """`impedax compare` of several spectra gives each model's ``misses_structure`` on each
    spectrum (JSON ``spectra[].models[]``, and the CSV's last column), as a batch fit's rows do;
    until 2026-12-06 only its warnings said it, and not below 2 % rms_rel. Oracle: the data's
    making (trials 0 and 2 hold the second arc R0 + R1 ∥ C1 cannot hold; R0 + R1 ∥ C1 + R2 ∥ C2
    holds every trial)."""
    data = two_arcs_and_one()
    one, two = (ix.fit(m, data, progress=False) for m in ("R0 + R1 || C1", "R0 + R1 || C1 + R2 || C2"))
    comparison = ix.compare([one, two])
    said = [[m["misses_structure"] for m in row["models"]] for row in comparison.spectra()]
    assert said == [[True, False], [False, False], [True, False], [False, False]]
    table = comparison.to_table()
    assert [r["misses_structure"] for r in table] == [x for pair in said for x in pair]
    assert list(table[0])[-1] == "misses_structure"  # (added last: the columns before keep their places)
