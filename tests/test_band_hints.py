"""The Python expressions impedax's messages give for keeping a band of frequencies do what they
say on data in either order: impedax keeps a file's points in the order measured, and most
instruments sweep from the highest frequency down (the REAL ZPlot file: 300 kHz first), where
xarray's ``sel(frequency=slice(lo, hi))`` selects by position between the labels and keeps the
wrong end, or nothing."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from cli_run import run
from gap_files import saved_gap_files

REAL = Path(__file__).resolve().parent / "fixtures" / "real"


def _python_expression(message: str, start: str) -> str:
    """The Python expression of ``message`` that begins with ``start`` (up to its balanced closing parenthesis)."""
    i = message.index(start)
    depth = 0
    for j in range(i, len(message)):
        depth += {"(": 1, ")": -1}.get(message[j], 0)
        if message[j] == ")" and depth == 0:
            return message[i : j + 1]
    raise AssertionError(message)


@pytest.mark.parametrize("descending", [False, True])
def test_the_drt_s_advice_to_leave_the_top_points_out_leaves_them_out(descending):
    """REAL PowerSuite (ascending in its file), also in the descending order most instruments
    write: R_inf < 0 says to leave the top points out with a Python expression; evaluated with
    f = 630 kHz it keeps the 28 points at or below f (numpy's count), not the 2 above it."""
    data = ix.load(REAL / "exampleDataPowersuite.txt")
    if descending:
        data = data.isel(frequency=slice(None, None, -1))
    [warning] = [w for w in ix.drt(data).warnings if w.startswith("R_inf = ")]
    kept = eval(_python_expression(warning, "data."), {"data": data, "f": 6.3e5})
    expected = np.sort(data["frequency"].values[data["frequency"].values <= 6.3e5])
    assert np.array_equal(np.sort(kept["frequency"].values), expected) and expected.size == 28


@pytest.mark.parametrize("descending", [False, True])
def test_the_gap_grids_advice_keeps_the_band_the_three_files_share(tmp_path, capsys, descending):
    """SYNTHETIC total (10 Hz–100 kHz, 13 points, 3 a decade), skin from 46.4 Hz, screen up to
    21.5 kHz: the refusal names the shared band and a Python expression for each file, which keeps
    exactly the 9 shared frequencies of each (the grid by numpy), in either order; the band's
    ends written to 6 digits must not cut off the end points (46.4158883 Hz, not 46.4159)."""
    rng = np.random.default_rng(3)
    f = np.geomspace(10.0, 1e5, 13)
    parts = {"total": (f, 5e6 - 8e6j), "skin": (f[2:], 2e5 - 3e5j), "ts": (f[:11], 1e4 - 2e4j)}
    datasets = []
    for freq, scale in parts.values():
        z = scale * (1 + 0.05 * rng.normal(size=(3, freq.size)))
        ds = ix.make_spectrum(freq, z, dims=("trial",))
        datasets.append(ds.isel(frequency=slice(None, None, -1)) if descending else ds)
    paths = saved_gap_files(tmp_path, datasets)
    code, _, err = run(["remaining", *paths, "--out", tmp_path / "rem.nc"], capsys)
    assert code == 2 and "the grids agree on the 9 frequencies" in err, err
    expression = _python_expression(err, "data.")
    for path in paths:
        data = ix.load(path)
        kept = eval(expression, {"data": data})
        np.testing.assert_array_equal(np.sort(kept["frequency"].values), f[2:11])
