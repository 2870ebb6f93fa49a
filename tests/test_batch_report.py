"""The text report of a batch fit (docs/fitting.md, "Batch fits"): each spectrum's own column
(value ± relative standard error, as the single fit's table) up to `SPECTRA_AS_COLUMNS` spectra,
the median and 16/84 % quantiles beyond, said to be across the spectra (not uncertainties) and
followed by a row per spectrum up to `SPECTRA_AS_ROWS`; "1 spectrum" in the singular. SYNTHETIC spectra of
R0 + R1 ∥ C1 written here as formulas, the expected cells from the batch's own values and
standard errors."""

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.least_squares.batch import SPECTRA_AS_COLUMNS, SPECTRA_AS_ROWS

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
    assert head.split()[1:6] == ["median", "16", "%", "84", "%"]
    r0 = batch.dataset["value"].sel(param="R0").values
    assert rows["R0"].split()[1:4] == [f"{x:.5g}" for x in np.quantile(r0, [0.5, 0.16, 0.84])]


def test_the_quantiles_are_said_to_be_across_the_spectra_and_each_spectrum_gets_a_row():
    """Past `SPECTRA_AS_COLUMNS` the quantiles read like a confidence interval: a header says
    they are a spread across the spectra; up to `SPECTRA_AS_ROWS` each spectrum's value ±
    relative standard error and rms_rel follow, one row per spectrum."""
    n = SPECTRA_AS_COLUMNS + 2
    assert n <= SPECTRA_AS_ROWS
    batch = ix.fit("R0 + R1 || C1", stack(n))
    text = batch.report()
    lines = text.splitlines()
    head = lines.index(next(ln for ln in lines if ln.startswith("parameter")))
    assert lines[head - 1].startswith(f"across the {n} spectra (not uncertainties): median, 16th and 84th percentiles")
    start = lines.index("each spectrum's fit (value ± relative standard error):")
    assert lines[start + 1].split() == ["spectrum", "R0", "R1", "C1", "rms_rel"]
    rows = lines[start + 2 : start + 2 + n]
    ds = batch.dataset
    for k, row in enumerate(rows):
        assert row.startswith(f"trial=t{k} ")
        v, e = float(ds["value"].sel(param="R1").isel(trial=k)), float(ds["stderr"].sel(param="R1").isel(trial=k))
        assert f"{v:.5g} ± {ix.data.format_relative_error(e / v)}" in row
        # rms_rel last, 3 significant digits with their trailing zeros, the column's decimal points
        # in one place (tests/test_percent_columns.py; `{:.3g}`'s writing, unaligned, until 2026-12-07)
        cell = row.split()[-2]
        assert row.endswith("%") and cell == f"{float(ds['rms_rel'].isel(trial=k)) * 100:#.3g}".rstrip(".")
    points = {row.rindex(row.split()[-2]) + (row.split()[-2] + ".").index(".") for row in rows}
    assert len(points) == 1 and len({len(row) for row in rows}) == 1


def test_a_batch_beyond_the_rows_says_where_each_spectrums_fit_is(monkeypatch):
    """Beyond `SPECTRA_AS_ROWS` (lowered here to keep the test fast) no per-spectrum rows: the
    report names the table and the CSV, and the command line its options."""
    from impedax.cli.common import command_line_words
    from impedax.fitting.least_squares import batch as batch_module

    monkeypatch.setattr(batch_module, "SPECTRA_AS_ROWS", SPECTRA_AS_COLUMNS + 1)
    text = ix.fit("R0 + R1 || C1", stack(SPECTRA_AS_COLUMNS + 2)).report()
    assert "each spectrum's fit (value" not in text and "trial=t0" not in text
    assert "each spectrum's values, standard errors and rms_rel: batch.to_table()" in text
    assert "each spectrum's values, standard errors and rms_rel: --out FILE.csv (a row per spectrum and parameter) or --json" in command_line_words(text)
