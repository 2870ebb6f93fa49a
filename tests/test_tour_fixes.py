"""Fixes after a user tour (2026-11-30): a KK batch's Dataset holds each spectrum's series R, L,
1/C and conclusiveness (its attrs had cycle 0's 1/C as the batch's); n_rc and max_rc together are
refused; a batch's JSON groups its warnings by kind with their spectra; the batch figure's error
bars stop at a natural bound whether or not the value sits on it. REAL data: AutoEIS's battery
cycles (examples/data, MIT)."""

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import impedax as ix
from impedax.errors import ParameterError
from impedax.progress import DelayedPrinter

matplotlib.use("Agg")
CYCLES = Path(__file__).resolve().parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc"
REAL = Path(__file__).parent / "fixtures" / "real"


def test_kk_batch_dataset_holds_each_spectrum_series_terms():
    batch = ix.kk_test_batch(ix.load(CYCLES))
    ds = batch.to_xarray()
    assert not [k for k in ds.attrs if "series" in k]  # (cycle 0's values, labelled as the batch's)
    for name in ("series_resistance", "series_inductance", "inverse_series_capacitance"):
        np.testing.assert_array_equal(ds[name].values, [getattr(r, name) for r in batch.results])
    np.testing.assert_array_equal(ds["conclusive"].values, [r.conclusive for r in batch.results])
    assert len(set(ds["inverse_series_capacitance"].values.tolist())) == 3  # (they differ by cycle)


def test_n_rc_with_max_rc_is_refused():
    data = ix.load(REAL / "exampleData.csv")
    with pytest.raises(ParameterError, match=r"n_rc=10 fixes the number of RC elements and max_rc=5 caps the search for it"):
        ix.kk_test(data, n_rc=10, max_rc=5)
    assert ix.kk_test(data, n_rc=10).n_rc == 10


@pytest.mark.slow  # (10 s; the suite's budget: test_fit_roundtrip checks a joint fit's kinds by default)
def test_batch_json_groups_warnings_by_kind_with_their_spectra():
    batch = ix.fit("R0 + R1 || CPE1 + Wo1", ix.load(CYCLES))
    kinds = batch.summary()["warning_kinds"]
    # every (spectrum, text) pair is in exactly one kind, and the kinds come most frequent first
    pairs = {(p, t) for p, ts in batch.warnings.items() for t in ts}
    covered = [(p, k["warning"]) for k in kinds for p in k["spectra"]]
    assert len(covered) == len(pairs) and {p for p, _ in covered} == {p for p, _ in pairs}
    assert [k["n_spectra"] for k in kinds] == sorted((k["n_spectra"] for k in kinds), reverse=True)
    assert all(k["n_spectra"] == len(k["spectra"]) for k in kinds)
    misfit = [k for k in kinds if k["warning"].startswith("the model misses structure")]
    assert len(misfit) == 1 and misfit[0]["n_spectra"] == 3  # (one kind, the KK figures as a range)
    assert len(kinds) < len(batch.summary()["warnings"])


def test_batch_error_bars_stop_at_a_natural_bound_near_the_value():
    # cycle 14 of the 130 REAL cycles: CPE2's α = 0.979 ± 0.058, off its bound 1, was drawn up
    # to 1.037, where α cannot go; its neighbours sit on the bound
    data = ix.load(Path(__file__).resolve().parents[1] / "benchmarks" / "data" / "autoeis_battery_130.nc").isel(cycle=[12, 13, 14, 15, 16])
    batch = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + W1", data)
    alpha = batch.values("CPE2.alpha").values
    err = batch.dataset["stderr"].sel(param="CPE2.alpha").values
    off = np.flatnonzero(np.isfinite(err))
    assert off.size and (alpha[off] + err[off] > 1.0).all()  # (the case: a bar that would cross 1)
    fig = batch.plot()
    (panel,) = [ax for ax in fig.axes if ax.get_title() == "CPE2.alpha"]
    segments = {round(s[0][0]): s for s in panel.collections[0].get_segments()}
    for i in off:
        (low, high) = segments[i][0][1], segments[i][1][1]
        assert high == pytest.approx(1.0, abs=1e-12) and low == pytest.approx(alpha[i] - err[i], rel=1e-12)


def test_fit_and_compare_say_what_runs(monkeypatch, capsys):
    # a batch of 3 cycles took 15 s and a compare of 3 models 6-12 s without a word; the lines
    # come once a run has taken 2 s (here at once)
    from impedax.cli import common, main

    monkeypatch.setattr(common, "progress_printer", lambda after_s=0.0, stream=None, quiet=False: DelayedPrinter(0.0, stream))
    assert main(["fit", str(CYCLES), "--model", "R0 + R1 || CPE1 + R2 || CPE2 + W1", "--json"]) == 0
    err = capsys.readouterr().err
    assert "fitting R0 + R1 || CPE1 + R2 || CPE2 + W1 to 3 spectra together" in err
    assert main(["compare", str(REAL / "exampleData.csv"), "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "--json"]) == 0
    err = capsys.readouterr().err
    assert "fitting model 1 of 2: R0 + R1 || C1" in err and "fitting model 2 of 2: R0 + R1 || CPE1" in err


@pytest.mark.parametrize("call", ["diagnose", "refine"])
def test_a_noise_level_of_one_or_more_is_refused_in_python(call):
    # noise=5 meant as 5 % is 500 %: a 21 % misfit then reads as noise
    data = ix.load(REAL / "exampleData.csv")
    with pytest.raises(ParameterError, match=r"noise=5 is a fraction of \|Z\| \(0.05 for 5 %\), so it would be 500 %; give 0.05 for 5 %"):
        getattr(ix, call)(data, "R0 + R1 || C1", noise=5)
