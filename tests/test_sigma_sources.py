"""A remainder says what its σ is made of as data (attrs ``sigma_sources``: input → "trial scatter"
or "own sigma"), beside the words of ``sigma_method``; `sigma_origin` and `trial_means_of_sigma`
read it, and read the words only of a remainder saved before it (2026-12-06: both parsed the words
with regular expressions). SYNTHETIC inputs built here, their error known by construction."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main
from impedax.fitting.diagnosis.noise import sigma_origin
from impedax.fitting.least_squares.result import trial_means_of_sigma
from impedax.models.sirin import remaining_impedance

FREQ = np.geomspace(10.0, 1e5, 9)
Z = {"total": 3e5 - 4e5j, "skin": 2e4 - 1e4j, "touchscreen": 1e3 - 5e3j}


def _input(name: str, trials: int, rng, *, sigma: bool = True):
    """``trials`` noisy copies of a flat spectrum (a trial dim), or one spectrum, with a stated σ
    of 1 % of |Z| when ``sigma``."""
    z = np.full(FREQ.size, Z[name])
    if trials > 1:
        return ix.make_spectrum(FREQ, z * (1 + 0.01 * rng.standard_normal((trials, FREQ.size))), dims=("trial",))
    return ix.make_spectrum(FREQ, z, sigma=0.01 * np.abs(z) if sigma else None)


@pytest.mark.parametrize(("trials", "sources"), [
    ({"total": 4, "skin": 3, "touchscreen": 5}, {"total": "trial scatter", "skin": "trial scatter", "touchscreen": "trial scatter"}),
    ({"total": 1, "skin": 3, "touchscreen": 1}, {"total": "own sigma", "skin": "trial scatter", "touchscreen": "own sigma"}),
    ({"total": 1, "skin": 1, "touchscreen": 1}, {"total": "own sigma", "skin": "own sigma", "touchscreen": "own sigma"}),
    ({"total": 6}, {"total": "trial scatter"}),
])
def test_the_remainder_records_each_inputs_part_of_sigma(trials, sources):
    rng = np.random.default_rng(3)
    parts = {name: _input(name, n, rng) for name, n in trials.items()}
    remainder = remaining_impedance(parts["total"], parts.get("skin"), parts.get("touchscreen"))
    assert remainder.attrs["sigma_sources"] == sources


def test_an_input_without_error_gives_no_sigma_and_no_sources():
    rng = np.random.default_rng(4)
    remainder = remaining_impedance(_input("total", 4, rng), _input("skin", 1, rng, sigma=False), _input("touchscreen", 1, rng))
    assert "sigma" not in remainder and "sigma_sources" not in remainder.attrs


def test_the_readers_follow_the_sources_not_the_words():
    """Hand-written attrs whose words say nothing (as another tool might leave them): the sources decide."""
    attrs = {"sigma_method": "(words of another version)", "n_trials_total": 30, "n_trials_skin": 1, "n_trials_touchscreen": 30,
             "sigma_sources": {"total": "trial scatter", "skin": "own sigma", "touchscreen": "trial scatter"}}
    assert sigma_origin(attrs) == "the standard error of the trial means of total and touchscreen and the stated sigma of skin, added in quadrature"
    assert trial_means_of_sigma(attrs) == "30 total, 30 touchscreen spectra, and the stated sigma of skin (one spectrum), added in quadrature"
    every = {**attrs, "n_trials_skin": 8, "sigma_sources": {"total": "trial scatter", "skin": "trial scatter", "touchscreen": "trial scatter"}}
    assert sigma_origin(every) == "the standard error of trial means of 30 total, 8 skin, 30 touchscreen spectra"
    assert trial_means_of_sigma(every) == "30 total, 8 skin, 30 touchscreen spectra"
    stated = {"sigma_method": "(no words)", "n_trials_total": 1, "sigma_sources": {"total": "own sigma"}}
    assert sigma_origin(stated) == "the stated sigma of the one spectrum" and trial_means_of_sigma(stated) is None
    # a remainder saved before 2026-12-06 carries the words alone: read as before
    old = {"sigma_method": "SEM of Re and Im of each measurement over its trials, added in quadrature; sigma = sqrt((sigma_real^2 + sigma_imag^2)/2)",
           "n_trials_total": 5, "n_trials_skin": 4, "n_trials_touchscreen": 3}
    assert sigma_origin(old) == "the standard error of trial means of 5 total, 4 skin, 3 touchscreen spectra"
    assert trial_means_of_sigma(old) == "5 total, 4 skin, 3 touchscreen spectra"


def test_the_sources_survive_a_netcdf_file_and_reach_the_json(tmp_path, capsys):
    rng = np.random.default_rng(5)
    paths = [str(tmp_path / f"{name}.nc") for name in Z]
    for path, (name, n) in zip(paths, {"total": 4, "skin": 1, "touchscreen": 3}.items()):
        ix.save(_input(name, n, rng), path)
    assert main(["remaining", *paths, "--out", str(tmp_path / "rem.nc"), "--json", "-q"]) == 0
    summary = json.loads(capsys.readouterr().out)
    sources = {"total": "trial scatter", "skin": "own sigma", "touchscreen": "trial scatter"}
    assert summary["sigma_sources"] == sources
    assert ix.load(tmp_path / "rem.nc").attrs["sigma_sources"] == sources
    with xr.open_dataset(tmp_path / "rem.nc") as raw:  # (as stored: impedax's JSON text of a dict attr)
        assert trial_means_of_sigma(raw.attrs) == "4 total, 3 touchscreen spectra, and the stated sigma of skin (one spectrum), added in quadrature"
