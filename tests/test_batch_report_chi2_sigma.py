"""A batch fitted with ``weighting="sigma"`` (``--weighting sigma``) gives each fit's χ²_red in
its report beside rms_rel, and their median in the header: about 1 where a fit is at the noise
σ states, the number such fits are judged by (until 2026-12-06 a SYNTHETIC σ-weighted batch's
report gave rms_rel alone). Values written by hand (no fit)."""

import numpy as np
import pytest
import xarray as xr

from impedax.fitting.least_squares import BatchFitResult

F = np.geomspace(1, 1e5, 8)
Z = 10 + 100 / (1 + 2j * np.pi * F * 1e-4)


def batch(chi2_red, weighting: str) -> BatchFitResult:
    n = len(chi2_red)
    ds = xr.Dataset(
        {
            "value": (("param", "cycle"), np.tile([[10.0], [100.0], [1e-6]], n)), "stderr": (("param", "cycle"), np.tile([[0.1], [1.0], [1e-8]], n)),
            "fixed": ("param", np.zeros(3, bool)), "at_bound": (("param", "cycle"), np.zeros((3, n), bool)),
            "rms_rel": ("cycle", np.full(n, 0.02)), "chi2_red": ("cycle", np.asarray(chi2_red, float)), "converged": ("cycle", np.ones(n, bool)),
            "Z": (("cycle", "frequency"), np.tile(Z, (n, 1))), "Z_model": (("cycle", "frequency"), np.tile(Z, (n, 1))), "sigma": (("cycle", "frequency"), np.tile(0.02 * np.abs(Z), (n, 1))),
        },
        coords={"param": ["R0", "R1", "C1"], "cycle": np.arange(n), "frequency": F},
        attrs={"model": "R0 + R1 || C1", "weighting": weighting, "impedax_kind": "batch_fit", "warnings": {}},
    )
    return BatchFitResult.from_xarray(ds)


def test_a_small_sigma_weighted_batch_has_a_chi2_red_row_and_its_median():
    lines = batch([1.18, 0.5, 3.0], "sigma").report().splitlines()
    assert "median rms_rel 2 %   median chi2_red 1.18   weighting sigma" in lines[1]
    row = next(line for line in lines if line.startswith("chi2_red "))
    assert row.split()[1:] == ["1.18", "0.5", "3"]


def test_a_sigma_weighted_batch_of_rows_has_a_chi2_red_column():
    values = [0.9, 1.1, 1.3, 0.7, 2.5, 1.0, 1.05, 0.95]  # (median 1.025)
    lines = batch(values, "sigma").report().splitlines()
    assert "median chi2_red 1.02" in lines[1]  # (1.025 in binary is just below it)
    head = next(line for line in lines if line.startswith("spectrum "))
    assert head.split()[-2:] == ["rms_rel", "chi2_red"]
    rows = [line.split() for line in lines if line.startswith("cycle=")]
    assert [r[-1] for r in rows] == ["0.9", "1.1", "1.3", "0.7", "2.5", "1", "1.05", "0.95"]


@pytest.mark.parametrize("weighting", ["modulus", "unit", "proportional"])
def test_other_weightings_have_no_chi2_red_in_the_report(weighting):
    report = batch([1.18, 0.5, 3.0], weighting).report()
    assert "chi2_red" not in report


def test_the_notebook_display_gives_the_median_chi2_red_too():
    assert "median rms_rel 2 %, median chi2_red 1.18, weighting sigma" in batch([1.18, 0.5, 3.0], "sigma")._repr_html_()
    assert "chi2_red" not in batch([1.18, 0.5, 3.0], "modulus")._repr_html_()
