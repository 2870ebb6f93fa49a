"""A batch fit's JSON (`BatchFitResult.summary()`, ``impedax fit FILE --json`` on a file of several
spectra) carries a single fit's keys where they have one meaning for the batch: ``converged``
(every spectrum's fit converged), ``n_params``, ``aic_form``, ``params[NAME]["fixed"]``, and per
spectrum ``params`` in a single fit's shape and ``n_evaluations``; ``params[NAME]["stderr_median"]``
gives the spread's standard error. Checked against a fit of each spectrum alone and numpy on the
result's Dataset. SYNTHETIC spectra: R0 + R1 ∥ C1 written with numpy, 0.3 % noise."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

MODEL = "R0 + R1 || C1"
FREQ = np.geomspace(0.1, 1e5, 30)
TRUTHS = [(10.0, 100.0, 1e-5), (12.0, 150.0, 2e-5), (8.0, 90.0, 5e-6)]


@pytest.fixture(scope="module")
def stack():
    rng = np.random.default_rng(11)
    z = [(r0 + r1 / (1 + 2j * np.pi * FREQ * r1 * c1)) * (1 + 0.003 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size))) for r0, r1, c1 in TRUTHS]
    return ix.make_spectrum(FREQ, np.array(z), dims=("cycle",)).assign_coords(cycle=[1, 2, 3])


@pytest.fixture(scope="module")
def batch(stack):
    return ix.fit(MODEL, stack, fixed={"R0": 10.0}, n_starts=1)


def test_the_batch_has_a_single_fits_top_level_keys_where_they_mean_the_same(batch, stack):
    s = batch.summary()
    alone = ix.fit(MODEL, stack.sel(cycle=1), fixed={"R0": 10.0}, n_starts=1).summary()
    ds = batch.to_xarray()
    assert s["converged"] is bool(ds["converged"].values.all()) is True
    assert s["n_params"] == alone["n_params"] == 2
    assert s["aic_form"] == alone["aic_form"]
    assert {n: p["fixed"] for n, p in s["params"].items()} == {"R0": True, "R1": False, "C1": False}
    for name in ("R1", "C1"):  # the median over the spectra of each one's standard error
        assert s["params"][name]["stderr_median"] == pytest.approx(float(np.median(ds["stderr"].sel(param=name).values)), rel=1e-12)
    assert s["params"]["R0"]["stderr_median"] is None  # (fixed: no standard error)
    json.dumps(s, allow_nan=False)


def test_a_batch_of_unconverged_fits_is_not_converged(stack):
    s = ix.fit(MODEL, stack, n_starts=1, max_steps=1).summary()
    assert s["converged"] is False and s["converged_fraction"] < 1


def test_each_spectrums_row_holds_params_as_a_single_fit_does(batch, stack):
    rows = batch.summary()["spectra"]
    for row in rows:
        alone = ix.fit(MODEL, stack.sel(cycle=row["cycle"]), fixed={"R0": 10.0}, n_starts=1).summary()
        assert set(row["params"]) == set(alone["params"])
        for name, entry in row["params"].items():
            assert set(entry) == set(alone["params"][name])
            assert entry["value"] == row["values"][name] and entry["stderr"] == row["stderr"][name]
            assert entry["fixed"] is alone["params"][name]["fixed"] and entry["unit"] == alone["params"][name]["unit"]
            assert entry["value"] == pytest.approx(alone["params"][name]["value"], rel=1e-4)
        assert isinstance(row["n_evaluations"], int) and row["n_evaluations"] >= 1


def test_the_command_prints_the_same_keys(stack, tmp_path, capsys):
    path = tmp_path / "cycles.nc"
    ix.save(stack, path)
    assert main(["fit", str(path), "--model", MODEL, "--fix", "R0=10", "--json", "-q"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["converged"] is True and out["n_params"] == 2 and out["params"]["R0"]["fixed"] is True
    assert out["spectra"][0]["params"]["R1"]["value"] == out["spectra"][0]["values"]["R1"]


def test_the_command_gives_a_batchs_hint_under_a_single_fits_hints_key(stack, tmp_path, capsys):
    """``hints`` (a single fit's key: the text of its "hint:" line) holds a batch's hint too, the
    ``note`` of its ``misfit_hints``; [] where there is none (the right model at the noise)."""
    rng = np.random.default_rng(5)
    small_arc = [(r0 + r1 / (1 + 2j * np.pi * FREQ * r1 * c1) + 3.0 / (1 + 2j * np.pi * FREQ * 3.0 * 1e-7)) * (1 + 3e-4 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)))
                 for r0, r1, c1 in TRUTHS]  # (a 3 Ω arc at 530 kHz's tail the model lacks: a misfit far below 2 %, many times the noise)
    missing = tmp_path / "missing.nc"
    ix.save(ix.make_spectrum(FREQ, np.array(small_arc), dims=("cycle",)).assign_coords(cycle=[1, 2, 3]), missing)
    assert main(["fit", str(missing), "--model", MODEL, "--json", "-q"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["misfit_hints"] is not None and out["hints"] == [out["misfit_hints"]["note"]]
    right = tmp_path / "right.nc"
    ix.save(stack, right)
    assert main(["fit", str(right), "--model", MODEL, "--json", "-q"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["misfit_hints"] is None and out["hints"] == []
