"""A batch fit's JSON gives each spectrum's own fit (``"spectra"``): its labels, values,
standard errors, rms_rel, flags and warnings. Checked against the SYNTHETIC truths the spectra
were built from (R0 + R1 ∥ C1 written in numpy, 0.3 % noise), against one fit of each spectrum
alone, and through ``impedax fit --json``."""

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

MODEL = "R0 + R1 || C1"
FREQ = np.geomspace(0.1, 1e5, 40)
TRUTHS = [(10.0, 100.0, 1e-5), (12.0, 150.0, 2e-5), (8.0, 90.0, 5e-6)]
CYCLES = [10, 20, 30, 40]


def _rc(r0, r1, c1):
    return r0 + r1 / (1 + 2j * np.pi * FREQ * r1 * c1)


@pytest.fixture(scope="module")
def stack():
    """Three R0 + R1 ∥ C1 spectra and a fourth with a Warburg tail the model lacks (cycle 40)."""
    rng = np.random.default_rng(3)
    noisy = [_rc(*t) * (1 + 0.003 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size))) for t in TRUTHS]
    warburg = 30.0 / np.sqrt(2j * np.pi * FREQ)
    z = np.array(noisy + [_rc(10.0, 100.0, 1e-5) + warburg])
    return ix.make_spectrum(FREQ, z, dims=("cycle",)).assign_coords(cycle=CYCLES)


@pytest.fixture(scope="module")
def batch(stack):
    return ix.fit(MODEL, stack)


def test_each_spectrum_is_reported_with_its_label_and_fit(batch, stack):
    rows = batch.summary()["spectra"]
    assert [r["cycle"] for r in rows] == CYCLES
    for row, (r0, r1, c1) in zip(rows, TRUTHS):
        assert row["values"] == pytest.approx({"R0": r0, "R1": r1, "C1": c1}, rel=0.02)
        assert all(0 < row["stderr"][n] < 0.02 * row["values"][n] for n in ("R0", "R1", "C1"))
        assert row["converged"] is True and row["at_bound"] == [] and row["warnings"] == []
        assert 0.001 < row["rms_rel"] < 0.01  # (0.3 % noise on each component)
    # the spectrum the model cannot fit carries its own warning, and only it
    last = rows[-1]
    assert last["rms_rel"] > 0.03 and last["warnings"] == list(batch.warnings["cycle=40"])
    assert any("misses structure" in w for w in last["warnings"])


def test_each_row_equals_a_fit_of_that_spectrum_alone(batch, stack):
    for row in batch.summary()["spectra"][:3]:
        alone = ix.fit(MODEL, stack.sel(cycle=row["cycle"]))
        assert row["values"] == pytest.approx(alone.values, rel=1e-4)
        assert row["rms_rel"] == pytest.approx(alone.rms_rel, rel=1e-4)


def test_fit_of_starts_a_value_on_a_user_bound_inside_it(batch):
    """A batch value on a user bound (here the bound is put at cycle 10's optimum R0) was given
    to the refit as its init and refused ("init: R0=… is on its upper bound"), an init the user
    never gave; it starts nudged inside, as init=batch starts it, and the refit returns to it."""
    ds = batch.to_xarray()
    r0 = float(ds["value"].sel(cycle=10, param="R0"))
    bounded = ix.BatchFitResult.from_xarray(ds.assign(upper=ds["upper"].where(ds["param"] != "R0", r0)))
    one = bounded.fit_of(cycle=10)
    assert one.bounds == {"R0": (0.0, r0)} and one.values["R0"] <= r0
    assert one.values == pytest.approx({n: float(ds["value"].sel(cycle=10, param=n)) for n in ("R0", "R1", "C1")}, rel=1e-4)


def test_the_command_line_json_has_the_spectra(stack, tmp_path, capsys):
    path = tmp_path / "stack.nc"
    ix.save(stack, path)
    capsys.readouterr()
    assert main(["fit", str(path), "--model", MODEL, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["n_spectra"] == 4 and [r["cycle"] for r in out["spectra"]] == CYCLES
    assert out["spectra"][1]["values"] == pytest.approx({"R0": 12.0, "R1": 150.0, "C1": 2e-5}, rel=0.02)
    assert out["spectra"][3]["warnings"] and not out["spectra"][0]["warnings"]
    assert [r["unidentified_groups"] for r in out["spectra"]] == [[], [], [], []]  # (every parameter determined: as each single fit)


def test_a_dimension_without_coordinates_is_labelled_by_position(stack):
    rows = ix.fit(MODEL, stack.drop_vars("cycle").isel(cycle=slice(0, 2))).summary()["spectra"]
    assert [r["cycle"] for r in rows] == [0, 1]


def test_date_labels_are_written_as_text(stack):
    """A batch over measurement times: each spectrum's label is the date as text (a numpy
    datetime64 had no JSON form), and it still finds the spectrum's warnings."""
    from impedax.io.export import to_jsonable

    times = np.array(["2026-11-01T10:00", "2026-11-02T10:00", "2026-11-03T10:00", "2026-11-04T10:00"], dtype="datetime64[ns]")
    result = ix.fit(MODEL, stack.assign_coords(cycle=times))
    rows = json.loads(json.dumps(to_jsonable(result.summary())))["spectra"]
    assert [r["cycle"] for r in rows] == [str(t) for t in times]
    assert rows[3]["warnings"] == list(result.warnings[f"cycle={times[3]}"]) and rows[3]["warnings"]
    # the tidy table (the CSV's rows) gave each date as its count of nanoseconds (numpy's .tolist())
    assert sorted({r["cycle"] for r in result.to_table()}) == [str(t) for t in times]


def test_fit_of_takes_a_date_in_any_form_and_names_the_nearest_dates(stack):
    """`fit_of(cycle=...)` on a batch over dates finds the spectrum by the date's value, given
    as a user would type it (only a pandas.Timestamp was found before 2026-12-03); a date it has
    no fit for is a ParameterError naming the nearest dates, nearest first."""
    import datetime

    import pandas as pd

    times = np.array(["2026-11-01T10:00", "2026-11-02T10:00", "2026-11-03T10:00", "2026-11-04T10:00"], dtype="datetime64[ns]")
    result = ix.fit(MODEL, stack.assign_coords(cycle=times))
    alone = ix.fit(MODEL, stack.isel(cycle=1)).values["R1"]  # (the spectrum stored second)
    for label in ("2026-11-02T10:00", "2026-11-02 10:00:00", np.datetime64("2026-11-02T10:00", "s"), datetime.datetime(2026, 11, 2, 10), pd.Timestamp("2026-11-02T10:00")):
        assert result.fit_of(cycle=label).values["R1"] == pytest.approx(alone, rel=1e-5), label
    with pytest.raises(ix.ParameterError) as info:
        result.fit_of(cycle="2026-11-03")  # (midnight: 10 h before the third, 14 h after the second)
    assert str(info.value) == "cycle='2026-11-03' is not among the batch's labels (nearest labels: 2026-11-03T10:00:00, 2026-11-02T10:00:00, 2026-11-04T10:00:00, 2026-11-01T10:00:00)"
    with pytest.raises(ix.ParameterError, match=r"cycle='last week' is not among .*; a cycle label is an ISO date"):
        result.fit_of(cycle="last week")


def test_a_date_label_is_selected_by_its_iso_text(stack, tmp_path, capsys):
    """`--select cycle=2026-11-02T10:00` finds the spectrum whose label is that date (stored to
    the nanosecond: its full text has ':' and '.', which --select had read as a range)."""
    from impedax.cli import main

    times = np.array(["2026-11-01T10:00", "2026-11-02T10:00", "2026-11-03T10:00", "2026-11-04T10:00"], dtype="datetime64[ns]")
    path = tmp_path / "dated.nc"
    ix.save(stack.assign_coords(cycle=times), path)
    assert main(["fit", str(path), "--model", MODEL, "--select", "cycle=2026-11-02T10:00", "--json", "--quiet"]) == 0
    picked = json.loads(capsys.readouterr().out)
    assert picked["params"]["R1"]["value"] == pytest.approx(ix.fit(MODEL, stack.isel(cycle=1)).values["R1"], rel=1e-6)
    assert main(["fit", str(path), "--model", MODEL, "--select", "cycle=2026-11-09T10:00", "--quiet"]) == 2
    assert "no spectrum of" in capsys.readouterr().err


def test_every_row_has_its_labels_by_dimension(batch):
    """Each row also gives its labels as ``labels`` (dimension → label, as a KK or DRT batch's
    rows do), beside the flat ``cycle`` key kept for existing readers."""
    rows = batch.summary()["spectra"]
    assert [r["labels"] for r in rows] == [{"cycle": c} for c in CYCLES]
    assert [r["cycle"] for r in rows] == CYCLES


@pytest.mark.parametrize("dim", ["values", "warnings"])
def test_a_dimension_named_like_a_row_key_does_not_clobber_it(stack, dim):
    """A batch over a dimension called ``values`` or ``warnings``: before the fix its label was
    merged into the row and then overwritten by the fit's key of that name (the label lost, for
    ``values`` the parameters kept; nothing said so). Now the label is under ``labels`` and the
    fit's keys are the fit's."""
    labels = [7, 8]
    result = ix.fit(MODEL, stack.isel(cycle=slice(0, 2)).rename(cycle=dim).assign_coords({dim: labels}))
    rows = json.loads(json.dumps(result.summary()))["spectra"]
    assert [r["labels"] for r in rows] == [{dim: c} for c in labels]
    for row, (r0, r1, c1) in zip(rows, TRUTHS):
        assert row["values"] == pytest.approx({"R0": r0, "R1": r1, "C1": c1}, rel=0.02)
        assert isinstance(row["warnings"], list) and row["warnings"] == list(result.warnings.get(f"{dim}={row['labels'][dim]}", ()))


@pytest.mark.parametrize("dim", ["stderr", "rms_rel", "param"])
def test_a_dimension_named_like_a_result_variable_is_refused_before_fitting(stack, dim, tmp_path, capsys):
    """A batch over ``stderr`` or ``rms_rel`` had failed inside the fit with xarray's "variables
    {'stderr'} are found in both data_vars and coords"; over ``param`` it built a result with
    that dimension twice. Now one message names the dimension, and the CLI exits with 2."""
    data = stack.isel(cycle=slice(0, 2)).rename(cycle=dim).assign_coords({dim: [7, 8]})
    with pytest.raises(ix.DataError, match=f"batch dimension\\(s\\) '{dim}' have the name of a fit result's variable.*rename"):
        ix.fit(MODEL, data)
    path = tmp_path / "clash.nc"
    ix.save(data, path)
    capsys.readouterr()
    assert main(["fit", str(path), "--model", MODEL, "--json"]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and f"'{dim}'" in err and "Traceback" not in err


@pytest.fixture(scope="module")
def unidentifiable_stack(stack):
    """Cycle 10 of ``stack`` (a noisy arc: every parameter determined) beside a noise-free
    SYNTHETIC spectrum of R0 + R1 = 110 Ω whose arc lies far above the band (C1 = 1e-20 F):
    there Z depends on R0 + R1 only, so R0 and R1 are a null direction of the Jacobian."""
    resistor = _rc(10.0, 100.0, 1e-20)
    return ix.make_spectrum(FREQ, np.array([stack["Z"].sel(cycle=10).values, resistor]), dims=("cycle",)).assign_coords(cycle=[10, 20])


@pytest.mark.parametrize("max_steps", [2000, None], ids=["converged", "step-limited"])
def test_each_spectrum_has_the_unidentified_groups_of_its_fit_alone(unidentifiable_stack, max_steps, tmp_path):
    """The batch's groups per spectrum equal a single fit's `unidentified_groups` (the oracle),
    whether the batch converges there (the stacked path, max_steps 2000) or stops at its step
    limit on the pure resistance (the path through `fit_result`): the null direction is the
    model's along R0 + R1, not the optimum's. They survive the .nc file."""
    options = {} if max_steps is None else {"max_steps": max_steps}
    batch = ix.fit(MODEL, unidentifiable_stack, **options)
    rows = batch.summary()["spectra"]
    for row in rows:
        alone = ix.fit(MODEL, unidentifiable_stack.sel(cycle=row["cycle"]))
        assert batch.unidentified_groups_of(cycle=row["cycle"]) == alone.unidentified_groups
        assert row["unidentified_groups"] == alone.summary()["unidentified_groups"]
    assert [r["unidentified_groups"] for r in rows] == [[], [["R0", "R1"]]]
    assert any("R0, R1 are not separately determined" in w for w in rows[1]["warnings"])
    path = tmp_path / "batch.nc"
    ix.write_result(batch, path)
    back = ix.BatchFitResult.from_xarray(ix.load(path))
    assert back.unidentified_groups_of(cycle=20) == (("R0", "R1"),) and back.unidentified_groups_of(cycle=10) == ()
    assert back.summary()["spectra"] == rows


def test_a_result_without_recorded_groups_says_so(batch):
    """A batch saved before the groups were recorded (attribute removed): its rows have no
    ``unidentified_groups`` key rather than a false [], and `unidentified_groups_of` says how
    to get them; a label not in the batch is named."""
    old = ix.BatchFitResult.from_xarray(batch.to_xarray().drop_attrs(deep=False).assign_attrs({k: v for k, v in batch.to_xarray().attrs.items() if k != "unidentified_groups"}))
    assert all("unidentified_groups" not in r for r in old.summary()["spectra"])
    with pytest.raises(ix.ParameterError, match="does not record each spectrum's unidentified groups; fit_of"):
        old.unidentified_groups_of(cycle=10)
    with pytest.raises(ix.ParameterError, match="cycle=99 is not among the batch's labels"):
        batch.unidentified_groups_of(cycle=99)
    assert batch.unidentified_groups_of(cycle=10) == ()


STATISTICS = ("rms_rel", "chi2", "chi2_red", "aic", "bic")


def test_each_row_has_the_goodness_of_fit_of_a_fit_of_that_spectrum_alone(batch, stack):
    """rms_rel, chi2, chi2_red, aic, bic of each spectrum (the single fit's JSON keys): the
    dataset's values, a fit of the spectrum alone's (to rounding: the optimum is reached from
    other starts), and the textbook formulas on the residuals (oracle: modulus weighting,
    n = 2N real residuals, k = 3 free parameters, AIC = n ln(χ²/n) + 2k, BIC = n ln(χ²/n) + k ln n)."""
    rows = batch.summary()["spectra"]
    ds = batch.dataset
    n, k = 2 * FREQ.size, 3
    for row in rows:
        for key in STATISTICS:
            assert row[key] == float(ds[key].sel(cycle=row["cycle"]))
        z, z_model = stack["Z"].sel(cycle=row["cycle"]).values, ds["Z_model"].sel(cycle=row["cycle"]).values
        chi2 = np.sum(np.abs((z - z_model) / np.abs(z)) ** 2)
        assert row["chi2"] == pytest.approx(chi2, rel=1e-9)
        assert row["chi2_red"] == pytest.approx(chi2 / (n - k), rel=1e-9)
        assert row["aic"] == pytest.approx(n * np.log(chi2 / n) + 2 * k, rel=1e-9)
        assert row["bic"] == pytest.approx(n * np.log(chi2 / n) + k * np.log(n), rel=1e-9)
    for row in rows[:3]:
        alone = ix.fit(MODEL, stack.sel(cycle=row["cycle"])).summary()
        for key in ("rms_rel", "chi2", "chi2_red"):
            assert row[key] == pytest.approx(alone[key], rel=1e-4), key
        for key in ("aic", "bic"):  # (n · relative change of chi2: 80 × 1e-4)
            assert row[key] == pytest.approx(alone[key], abs=0.01), key
    # models compared spectrum by spectrum: the Warburg spectrum's misfit shows in its own AIC
    assert rows[3]["aic"] > max(r["aic"] for r in rows[:3]) + 100


def test_the_csv_rows_carry_their_spectrums_goodness_of_fit(batch, tmp_path):
    ix.write_result(batch, tmp_path / "batch.csv")
    table = np.genfromtxt(tmp_path / "batch.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert list(table.dtype.names) == ["cycle", "name", "value", "stderr", "unit", "fixed", *STATISTICS, "converged", "at_bound", "undetermined", "warnings", "weighting", "misses_structure"]  # (weighting and misses_structure added 2026-12-06)
    for key in STATISTICS:
        expected = np.repeat(batch.dataset[key].sel(cycle=CYCLES).values, 3)  # (one row per parameter)
        np.testing.assert_array_equal(table[key], expected)


def test_each_warning_kind_gives_its_spectra_labels_as_dicts(batch):
    kinds = batch.summary()["warning_kinds"]
    assert kinds
    for kind in kinds:
        assert len(kind["labels"]) == len(kind["spectra"]) == kind["n_spectra"]
        assert [", ".join(f"{d}={v}" for d, v in lab.items()) for lab in kind["labels"]] == kind["spectra"]  # same order
    misfit = next(k for k in kinds if "misses structure" in k["warning"])
    assert misfit["spectra"] == ["cycle=40"] and misfit["labels"] == [{"cycle": 40}]
    json.dumps(kinds)  # (plain JSON values)


def test_a_batch_whose_labels_repeat_is_refused():
    """Ten spectra labelled cycle=1 were fitted, their warnings folded into one entry and
    fit_of(cycle=1) gave one of them without a word (2026-12-03 walkthrough); now one DataError
    names the dimension and the repeated label, before any fit."""
    f = np.geomspace(1.0, 1e5, 20)
    z = 10 + 100 / (1 + 2j * np.pi * f * 1e-4)  # (R0 + R1 ∥ C1 written here)
    data = ix.make_spectrum(f, np.tile(z, (3, 1)), dims=("cycle",), coords={"cycle": [1, 1, 2]})
    with pytest.raises(ix.DataError, match=r"the labels along cycle repeat \(1\): each spectrum of a batch is found by its label"):
        ix.fit(MODEL, data)
    assert ix.fit(MODEL, data.assign_coords(cycle=[1, 2, 3])).n_spectra == 3


def test_a_batch_says_how_many_points_each_fit_used_after_the_band_and_exclusions(stack, tmp_path, capsys):
    """--fmin 0.5 --fmax 20k --exclude 119.378 on the 40-point grid 0.1 Hz–100 kHz: the 30
    frequencies 0.588 Hz–17 kHz inside the band (counted on the grid here) less the one left out,
    29, in the JSON's ``n_points`` (a single fit's key) and in the report's second line."""
    path = tmp_path / "stack.nc"
    ix.save(stack.isel(cycle=slice(0, 3)), path)
    inside = np.count_nonzero((FREQ >= 0.5) & (FREQ <= 2e4))
    assert inside == 30
    band = ["--fmin", "0.5", "--fmax", "20k", "--exclude", "119.378", "-q"]
    capsys.readouterr()
    assert main(["fit", str(path), "--model", MODEL, *band, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["n_points"] == inside - 1
    assert main(["fit", str(path), "--model", MODEL, *band]) == 0
    second = capsys.readouterr().out.splitlines()[1]
    assert second.endswith("   29 points each (588 mHz–17 kHz)"), second
    assert ix.fit(MODEL, stack).summary()["n_points"] == FREQ.size  # (no band: every point)


def test_a_bound_note_quotes_the_linearised_error_the_json_gives_not_a_standard_error_it_lacks(tmp_path, capsys):
    """SYNTHETIC R0 + R1 ∥ CPE1 (closed form, R1 3 and 4 kΩ, Q 1 µF s^(α-1), α 0.9) fitted with R0
    fixed at 1e9 Ω (the `--fix R0=1e9` case of docs/fitting.md): the misfit swamps the arc, and
    CPE1.Q ends far off its lower bound 0 yet flagged at it. A parameter at a bound has no
    standard error (JSON null, docs/fitting.md "Standard errors at a bound"); the warning read
    "CPE1.Q = 2.11e+04 F s^(α-1) cannot be told from its lower bound 0 (standard error 6.2e+18 ...)",
    quoting one. It now names the number what it is, the linearisation's, which each spectrum's
    ``linearised_stderr`` in the JSON gives (the key of a single fit's parameters)."""
    import re

    f = np.geomspace(0.1, 1e5, 25)

    def r_cpe(r1):  # R0 + R1 ∥ CPE1 written here: Z_CPE = 1 / (Q (jω)^α)
        return 30.0 + r1 / (1 + r1 * 1e-6 * (2j * np.pi * f) ** 0.9)

    path = tmp_path / "cells.nc"
    ix.save(ix.make_spectrum(f, np.stack([r_cpe(3000.0), r_cpe(4000.0)]), dims=("cell",), coords={"cell": ["a", "b"]}), path)
    capsys.readouterr()
    assert main(["fit", str(path), "--model", "R0 + R1 || CPE1", "--fix", "R0=1e9", "-q", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    quoted = 0
    for row in out["spectra"]:
        for name in row["at_bound"]:
            assert row["stderr"][name] is None  # (the contract: no standard error at a bound)
            for w in row["warnings"]:
                if w.startswith(f"{name} = ") and "cannot be told from" in w:
                    assert "(standard error" not in w, w
                    shown = re.search(r"linearised standard error ([0-9.e+-]+)", w).group(1)
                    assert float(shown) == float(f"{row['linearised_stderr'][name]:.2g}"), (w, row["linearised_stderr"])
                    quoted += 1
    assert quoted == 2  # (CPE1.Q of both cells)
    assert all(r["linearised_stderr"]["R0"] is None for r in out["spectra"])  # (fixed: none, as its stderr)
