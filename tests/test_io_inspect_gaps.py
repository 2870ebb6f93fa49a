"""`impedax inspect` names a gap in a sweep's frequencies: a step at least 1.8 times both
neighbouring steps (on a log scale), as a point the instrument skipped leaves. The REAL
exampleDataGamry.DTA with its point 40 (19.9 Hz) left out is the oracle: the gap runs between
the two points beside it, one point wide. A sweep whose density changes (fewer points per decade
from some frequency on) has no such step, and no REAL file has a gap."""

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.data import format_frequency

REAL = Path(__file__).parent / "fixtures" / "real"
REAL_FILES = sorted(p.name for p in REAL.iterdir() if p.suffix not in (".md", ".json", ".py", ".npz") and not p.name.startswith("LICENSE"))


def test_a_skipped_point_is_named_as_a_gap(tmp_path, capsys):
    ds = ix.load(REAL / "exampleDataGamry.DTA")
    f = ds["frequency"].values
    path = tmp_path / "skipped.csv"
    ix.save(ds.drop_isel(frequency=40), path)
    assert main(["inspect", str(path), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["frequency_gaps_hz"] == [[float(f[41]), float(f[39])]]  # (a falling sweep: 41 is below 39)
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    step = np.log10(f[39] / f[41])
    assert (f"  frequency gaps: {format_frequency(f[41])}–{format_frequency(f[39])} ({step:.2f} decade, where the steps beside it are "
            in out), out
    assert "a point skipped?" in out


def test_a_change_of_density_is_no_gap(tmp_path, capsys):
    """SYNTHETIC grid: 10 points per decade from 100 kHz to 100 Hz, then 5 per decade to 0.1 Hz."""
    f = np.concatenate([np.logspace(5, 2, 31), np.logspace(2, -1, 16)[1:]])
    z = 10 + 100 / (1 + 2j * np.pi * f * 1e-3)
    path = tmp_path / "two_densities.csv"
    ix.save(ix.make_spectrum(f, z), path)
    assert main(["inspect", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["frequency_gaps_hz"] == []


@pytest.mark.parametrize("name", REAL_FILES)
def test_no_real_file_has_a_gap(capsys, name):
    assert main(["inspect", str(REAL / name), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["frequency_gaps_hz"] == []
