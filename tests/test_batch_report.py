"""The text report of a batch fit (docs/fitting.md, "Batch fits"): each spectrum's own column
(value ± relative standard error, as the single fit's table) up to `SPECTRA_AS_COLUMNS` spectra,
the median and 16/84 % quantiles beyond; "1 spectrum" in the singular. SYNTHETIC spectra of
R0 + R1 ∥ C1 written here as formulas, the expected cells from the batch's own values and
standard errors."""

import numpy as np
import xarray as xr

import impedax as ix
from impedax.fitting.least_squares.batch import SPECTRA_AS_COLUMNS

F = np.geomspace(1, 1e5, 30)
JW = 2j * np.pi * F


def stack(n):
    rng = np.random.default_rng(3)
    z = [10.0 * (1 + k) + 100.0 / (1 + 100.0 * 1e-6 * JW) for k in range(n)]
    z = [x * (1 + 0.002 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size))) for x in z]
    return xr.concat([ix.make_spectrum(F, x) for x in z], dim="trial").assign_coords(trial=[f"t{k}" for k in range(n)])


def table(report):
    lines = report.splitlines()
    start = next(i for i, ln in enumerate(lines) if ln.startswith("parameter"))
    return lines[start], {ln.split()[0]: ln for ln in lines[start + 1 :] if ln.strip()}


def test_a_small_batch_gives_each_spectrum_its_column():
    batch = ix.fit("R0 + R1 || C1", stack(3))
    head, rows = table(batch.report())
    assert head.split()[1:] == ["trial=t0", "trial=t1", "trial=t2", "unit"] and "median" not in head
    ds = batch.dataset
    for k in range(3):
        v = float(ds["value"].sel(param="R0").isel(trial=k))
        e = float(ds["stderr"].sel(param="R0").isel(trial=k))
        assert abs(v - 10.0 * (1 + k)) < 1.0
        assert f"{v:.5g} ± {ix.data.format_relative_error(e / v)}" in rows["R0"]
    assert rows["rms_rel"].count("%") == 3


def test_one_spectrum_is_one_spectrum():
    batch = ix.fit("R0 + R1 || C1", stack(1))
    text = batch.report()
    assert text.splitlines()[0] == "model R0 + R1 || C1: 1 spectrum over trial (1)"
    assert "1 spectra" not in text


def test_a_larger_batch_gives_median_and_quantiles():
    n = SPECTRA_AS_COLUMNS + 1
    batch = ix.fit("R0 + R1 || C1", stack(n))
    head, rows = table(batch.report())
    assert head.split()[1:4] == ["median", "16%", "84%"]
    r0 = batch.dataset["value"].sel(param="R0").values
    assert rows["R0"].split()[1:4] == [f"{x:.5g}" for x in np.quantile(r0, [0.5, 0.16, 0.84])]
