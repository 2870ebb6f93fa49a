"""Batches after a user walkthrough on REAL battery spectra (benchmarks/data/autoeis_battery_130.nc):
a batch of fits as the starts of the next (docs/fitting.md, "What the default costs"), the
messages of compare() for batches and for data that differ, the batch JSON's weighting, and
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


@pytest.mark.parametrize(
    "pick, message",
    [
        (lambda d: d.isel(cycle=0), "for one spectrum use one of its fits, e.g. init=batch.fit_of(cycle=…)"),
        (lambda d: d.isel(cycle=[0, 1, 2]), "the batch of fits has 4 spectra along cycle, the data 3"),
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
