"""``impedax sample --exclude F,F``: the points `impedax diagnose` and `refine` mask, and that
the `impedax fit` commands they print leave out, can be left out of the posterior too."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from cli_run import run


@pytest.mark.slow  # (a short emcee run through the command line: ~5–10 s on the 2-core machine)
def test_sample_leaves_out_the_points_exclude_names(tmp_path, capsys):
    """SYNTHETIC R0 + R1 ‖ C1 (10 Ω, 100 Ω, 10 µF; numpy), exact but for the point at 1 kHz, 30 %
    off: with --exclude 1k the start fit reproduces the rest (rms_rel < 1e-6, where the outlier
    kept would leave a misfit of percents) and the posterior's data hold the other 24
    frequencies, 1 kHz not among them; the JSON's provenance records the option. Before
    2026-12-06 sample had no --exclude ("unrecognized arguments")."""
    freq = np.logspace(5, -1, 25)
    z = 10 + 100 / (1 + 2j * np.pi * freq * 100 * 1e-5)
    z[np.argmin(abs(freq - 1e3))] *= 1.3
    path = tmp_path / "outlier.csv"
    ix.save(ix.make_spectrum(freq, z), path)
    out = tmp_path / "post.nc"
    code, printed, err = run(["sample", path, "--model", "R0 + R1 || C1", "--exclude", "1k", "--steps", "200", "--json", "-q", "--out", out], capsys)
    assert code == 0, err
    summary = json.loads(printed)
    assert summary["start_fit"]["rms_rel"] < 1e-6
    assert summary["provenance"]["settings"]["exclude"] == "1k"
    with xr.open_dataset(out) as saved:
        kept = np.sort(saved["frequency"].values)
    np.testing.assert_allclose(kept, np.sort(freq[abs(freq - 1e3) > 1]), rtol=1e-12)
