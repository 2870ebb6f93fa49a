"""Bad bands of the KK test and Z-HIT on dense spectra: flagged points less than
`BAND_MERGE_DECADES` (0.05 decade) apart are one band, so noise that splits a drift's flags into
hundreds of runs leaves one or a few bands; the per-point flags are unchanged, and so are the
bands of spectra of up to 20 points a decade. Spectra are numpy closed forms or real files; the
expected bands are written here from the flags (runs, edges halfway in log f)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting.kk import BAND_MERGE_DECADES, band_rule_counts, bands_of_flags

ROOT = Path(__file__).resolve().parents[1]
REAL = ROOT / "tests" / "fixtures" / "real"
BATTERY = ROOT / "benchmarks" / "data" / "autoeis_battery_130.nc"


def rc(f):
    """10 Ω + 1 kΩ ‖ 10 µF (τ = 10 ms)."""
    return 10 + 1000 / (1 + 1j * 2 * np.pi * f * 1e-2)


def noisy(z, level, seed):
    rng = np.random.default_rng(seed)
    return z * (1 + level * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2))


def runs(flag):
    """[first, last] of each run of True."""
    flag = np.asarray(flag, bool)
    out, start = [], None
    for i, v in enumerate(flag):
        if v and start is None:
            start = i
        if not v and start is not None:
            out.append((start, i - 1))
            start = None
    if start is not None:
        out.append((start, flag.size - 1))
    return out


def edges(f, i, j):
    """A band over points i..j of sorted f: halfway in log f to the neighbours, or the end."""
    lo = f[i] if i == 0 else math.sqrt(f[i - 1] * f[i])
    hi = f[j] if j == f.size - 1 else math.sqrt(f[j] * f[j + 1])
    return lo, hi


def assert_bands(actual, expected):
    assert len(actual) == len(expected), (actual, expected)
    np.testing.assert_allclose(np.reshape(actual, (-1, 2)), np.reshape(expected, (-1, 2)), rtol=1e-12)


def test_the_merge_distance():
    # below the 0.1 decade between flagged points that one good point separates at 20 points a
    # decade, and a third of Z-HIT's smoothing scale (0.17 decade)
    assert BAND_MERGE_DECADES == 0.05


@pytest.mark.parametrize("per_decade", [10, 20])
def test_sparse_bands_are_the_runs_of_flags(per_decade):
    f = np.geomspace(1.0, 1e3, 3 * per_decade + 1)
    flag = np.zeros(f.size, bool)
    flag[[3, 5, 6, 7, 9, 20, 26]] = True  # single good points between bad ones, and lone points
    flag[-2:] = True  # up to the end of the data
    expected = tuple(edges(f, i, j) for i, j in runs(flag))
    assert_bands(bands_of_flags(f, flag), expected)
    assert len(expected) == 6
    masks = {"point": flag.copy(), "run": np.zeros(f.size, bool)}
    assert band_rule_counts(flag, masks, f) == [{"point": j - i + 1, "run": 0} for i, j in runs(flag)]


def test_dense_flags_closer_than_the_merge_distance_are_one_band():
    f = np.geomspace(1.0, 1e3, 3001)  # 1000 points a decade: 0.001 decade apart
    flag = np.zeros(f.size, bool)
    flag[[100, 101, 140, 180]] = True  # 0.039 and 0.040 decade apart: one band
    flag[[240, 241]] = True  # 0.060 decade after 180: a band of its own
    flag[[1000, 1049]] = True  # 0.049 decade: one band
    flag[[2000, 2051]] = True  # 0.051 decade: two
    assert_bands(bands_of_flags(f, flag), (edges(f, 100, 180), edges(f, 240, 241), edges(f, 1000, 1049), edges(f, 2000, 2000), edges(f, 2051, 2051)))
    masks = {"point": flag.copy()}
    assert band_rule_counts(flag, masks, f) == [{"point": 4}, {"point": 2}, {"point": 2}, {"point": 1}, {"point": 1}]
    # without frequencies: the runs alone (as before)
    assert len(band_rule_counts(flag, masks)) == len(runs(flag)) == 8


def test_zhit_outliers_a_tenth_of_a_decade_apart_stay_apart_at_any_density():
    # |Z| 10 % off at two points (the phase kept): at 20 points a decade one good point apart, two
    # bands as before; at 1000 a decade a tenth of a decade apart, still two, and 0.02 decade apart, one
    f = np.geomspace(1e-2, 1e5, 141)
    z = rc(f)
    z[[60, 62]] *= 1.1
    result = ix.zhit((f, z))
    assert np.flatnonzero(result.flagged).tolist() == [60, 62]
    assert_bands(result.bad_bands, (edges(f, 60, 60), edges(f, 62, 62)))
    f = np.geomspace(1e-2, 1e5, 7001)
    z = rc(f)
    z[[3000, 3020, 5000, 5100]] *= 1.1
    result = ix.zhit((f, z))
    assert np.flatnonzero(result.flagged).tolist() == [3000, 3020, 5000, 5100]  # the good points between them stay good
    assert_bands(result.bad_bands, (edges(f, 3000, 3020), edges(f, 5000, 5000), edges(f, 5100, 5100)))
    assert result.band_rules == (("point",), ("point",), ("point",))
    first_band = next(line for line in result.report().splitlines() if line.startswith("  bad band:"))
    assert "2 points with |residual|" in first_band


F_DENSE = np.geomspace(1e-3, 1e6, 100_000)  # 11,000 points a decade


def test_dense_zhit_drift_is_one_band_or_two():
    low = F_DENSE < 1e-2
    for seed in range(3):
        z = noisy(rc(F_DENSE), 0.01, seed)
        z[low] *= 1 + 0.05 * np.log10(1e-2 / F_DENSE[low])  # |Z| drifts up to 5 % over the slowest decade, the phase does not
        result = ix.zhit((F_DENSE, z))
        flag = np.asarray(result.flagged, bool)
        assert len(runs(flag)) > 100  # noise splits the flags (225–260 runs)
        assert 1 <= len(result.bad_bands) <= 2, result.bad_bands
        assert result.bad_bands[0][0] == F_DENSE[0] and result.bad_bands[-1][1] < 1e-2  # from the lowest frequency, inside the drift's decade
        assert all(any(lo <= fi <= hi for lo, hi in result.bad_bands) for fi in F_DENSE[flag])
        assert len(result.band_rules) == len(result.bad_bands)
        summary = result.summary()
        assert len(summary["bad_bands_hz"]) == len(summary["bad_band_rules"]) == len(result.bad_bands)
        assert sum(line.startswith("  bad band:") for line in result.report().splitlines()) == len(result.bad_bands)


def test_dense_kk_drift_is_a_few_bands():
    f = np.geomspace(1e-3, 1e6, 10_000)
    low = f < 1e-2
    for seed in (0,):  # (one draw of 10,000 points: 3 took 23 s of the suite's budget)
        z = noisy(rc(f), 0.01, seed)
        z[low] *= 1 + 0.2 * np.log10(1e-2 / f[low])  # Z' and Z'' drift up to 20 % over the slowest decade
        result = ix.kk_test((f, z))
        flag = np.asarray(result.flagged, bool)
        assert len(runs(flag)) >= 8
        assert 1 <= len(result.bad_bands) <= 3, result.bad_bands
        # the first covers the drift's decade; the Voigt fit spreads the misfit half a decade above it
        assert result.bad_bands[0][0] == f[0] and result.bad_bands[0][1] > 1e-2
        assert result.bad_bands[-1][1] < 10 ** -1.5
        assert all(any(lo <= fi <= hi for lo, hi in result.bad_bands) for fi in f[flag])
        assert len(result.band_rules) == len(result.bad_bands) and "window" in result.band_rules[0]
        summary = result.summary()
        assert len(summary["bad_bands_hz"]) == len(summary["bad_band_rules"]) == len(result.bad_bands)
        lines = result.report().splitlines()
        assert sum(line.startswith("  bad band:") for line in lines) == len(result.bad_bands)


def test_real_files_bands_are_the_runs_of_their_flags():
    # 1–12 points a decade: one band per run of flagged points, as before the merge
    for name in ("exampleDataBioLogic.mpt", "exampleDataCHInstruments.txt", "exampleDataPowersuite.txt", "exampleDataGamry.DTA"):
        data = ix.load(REAL / name)
        order = np.argsort(data["frequency"].values)
        for result in (ix.kk_test(data), ix.zhit(data)):
            f = result.frequency[order]
            flag = np.asarray(result.flagged, bool)[order]
            assert_bands(result.bad_bands, tuple(edges(f, i, j) for i, j in runs(flag)))
    bio = ix.zhit(ix.load(REAL / "exampleDataBioLogic.mpt"))
    assert len(bio.bad_bands) == 4  # one good point between two of them, 0.23 decade: not joined
    batch = ix.kk_test_batch(ix.load(BATTERY))
    for result in batch.results:
        order = np.argsort(result.frequency)
        f, flag = result.frequency[order], np.asarray(result.flagged, bool)[order]
        assert_bands(result.bad_bands, tuple(edges(f, i, j) for i, j in runs(flag)))


def test_cli_lists_the_merged_bands(tmp_path, capsys):
    low = F_DENSE < 1e-2
    z = noisy(rc(F_DENSE), 0.01, 0)
    z[low] *= 1 + 0.05 * np.log10(1e-2 / F_DENSE[low])
    path = tmp_path / "dense.csv"
    np.savetxt(path, np.column_stack([F_DENSE, z.real, z.imag]), delimiter=",", header="freq,zreal,zimag", comments="")
    assert main(["kk", str(path), "--method", "zhit", "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["bad_bands_hz"] == payload["bad_bands"] and 1 <= len(payload["bad_bands_hz"]) <= 2
    assert len(payload["bad_band_rules"]) == len(payload["bad_bands_hz"])
    assert main(["kk", str(path), "--method", "zhit"]) == 0
    assert sum(line.startswith("  bad band:") for line in capsys.readouterr().out.splitlines()) == len(payload["bad_bands_hz"])
