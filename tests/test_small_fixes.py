"""Small fixes, each pinned by a test that failed before it: the notebook display's rms_rel in
percent (as the text reports), the bound note's wording off the bound, and ``impedax gap
--select``. Spectra from closed-form formulas (tests/spectra.py); results built by hand where
a fit is not what is tested."""

import math
import re

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.least_squares import FitResult
from impedax.fitting.least_squares.batch import BatchFitResult
from spectra import rc

RC = {"R0": 50.0, "R1": 2000.0, "C1": 1e-7}
F = np.geomspace(1.0, 1e6, 30)


def _misfit_by(z, rms_rel, seed=0):
    """z moved by complex relative residuals of modulus exactly ``rms_rel`` (random phases)."""
    phase = np.random.default_rng(seed).uniform(0, 2 * np.pi, z.shape)
    return z * (1 + rms_rel * np.exp(1j * phase))


def _fit_result(rms_rel=0.0472, **changes):
    """A FitResult of R0 + R1 || C1 built by hand: model = the formula, data off by ``rms_rel``."""
    circuit = ix.parse("R0 + R1 || C1")
    z_model = rc(F, RC)
    # residual (z_model − z_data)/|z_data| of modulus rms_rel at every point
    z_data = z_model / (1 + rms_rel * np.exp(1j * np.random.default_rng(1).uniform(0, 2 * np.pi, F.size)))
    fields = dict(
        circuit=circuit, values=dict(RC), stderr={"R0": 1.0, "R1": 20.0, "C1": 1e-9}, fixed={n: False for n in RC}, free_names=tuple(RC),
        covariance=np.eye(3), correlation=np.eye(3), frequency=F, z_data=z_data, z_model=z_model, weighting="modulus", chi2=1.0,
        converged=True, message="converged", n_evaluations=10,
    )
    fields.update(changes)
    return FitResult(**fields)


# -- 1. notebook summaries: rms_rel in percent, as the text reports ---------------------------------------


def test_fit_result_html_shows_rms_rel_in_percent_as_its_report():
    result = _fit_result()
    assert result.rms_rel == pytest.approx(0.0472, rel=1e-12)
    html = result._repr_html_()
    assert "rms_rel 4.72 %" in html and "rms_rel 0.0472" not in html
    assert re.search(r"rms_rel +4\.72 %", result.report())  # the same number as the text report
    assert result.summary()["rms_rel"] == pytest.approx(0.0472, rel=1e-12)  # the JSON stays a fraction


def test_batch_html_shows_the_median_rms_rel_in_percent():
    cells = ["a", "b", "c"]
    value = np.array([[50.0, 51.0, 52.0], [2000.0, 2100.0, 2200.0], [1e-7, 1e-7, 1e-7]])
    ds = xr.Dataset(
        {
            "value": (("param", "cell"), value),
            "stderr": (("param", "cell"), value * 0.01),
            "fixed": ("param", [False] * 3),
            "at_bound": (("param", "cell"), np.zeros((3, 3), bool)),
            "rms_rel": ("cell", [0.0100, 0.0472, 0.2000]),
            "converged": ("cell", [True] * 3),
        },
        coords={"param": list(RC), "cell": cells},
    )
    batch = BatchFitResult(circuit=ix.parse("R0 + R1 || C1"), dataset=ds, weighting="modulus", warnings={})
    html = batch._repr_html_()
    assert "median rms_rel 4.72 %" in html and "0.0472" not in html
    assert "median rms_rel 4.72 %" in batch.report()
    assert batch.summary()["rms_rel_median"] == pytest.approx(0.0472)


@pytest.fixture(scope="module")
def misfit_data():
    """An R‖C spectrum off by 3 % at every point: a KK test and a DRT of it leave ~1–3 %."""
    return ix.make_spectrum(F, _misfit_by(rc(F, RC), 0.03, seed=2))


def test_kk_html_shows_rms_rel_and_noise_in_percent(misfit_data):
    result = ix.kk_test(misfit_data)
    html = result._repr_html_()
    rms, noise = f"{result.rms_rel * 100:.3g}", f"{result.noise_estimate * 100:.3g}"
    assert f"rms_rel = {rms} %" in result.report() and f"noise estimate = {noise} %" in result.report()
    assert f"<td>rms_rel [%]</td><td>{rms}</td>" in html
    assert f"<td>noise estimate [%]</td><td>{noise}</td>" in html
    assert f"{result.rms_rel:.5g}" not in html  # the fraction is gone
    assert result.summary()["rms_rel"] == result.rms_rel


def test_drt_html_shows_rms_rel_in_percent(misfit_data):
    result = ix.drt(misfit_data)
    html = result._repr_html_()
    rms = f"{result.rms_rel * 100:.3g}"
    assert f"rms_rel = {rms} %" in result.report()
    assert f"rms_rel {rms} %;" in html and f"rms_rel {result.rms_rel:.3g};" not in html
    assert result.summary()["rms_rel"] == result.rms_rel
