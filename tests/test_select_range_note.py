"""`--select DIM=FIRST:LAST` is a range of labels; where the same ends read as positions would
pick other spectra, one note on stderr says which it kept (REAL battery cycles labelled 0, 64,
129: `--select cycle=0:20` keeps cycle 0 alone)."""

from pathlib import Path

import xarray as xr

from impedax.cli import main

ROOT = Path(__file__).resolve().parents[1]
THREE = ROOT / "examples" / "data" / "autoeis_battery_cycles.nc"
ALL_130 = ROOT / "benchmarks" / "data" / "autoeis_battery_130.nc"


def test_a_range_of_labels_that_positions_would_read_otherwise_is_noted(tmp_path, capsys):
    with xr.open_dataset(THREE) as ds:
        labels = [int(v) for v in ds["cycle"].values]
    assert labels == [0, 64, 129]  # (the file's own labels: positions 0..20 would be all three)
    assert main(["inspect", str(THREE), "--select", "cycle=0:20"]) == 0
    err = capsys.readouterr().err
    assert "note: --select cycle=0:20 keeps cycle 0 (1 of 3): a range is of cycle labels, by value (the file's: 0, 64, 129), not of positions" in err
    # labels that are the positions (0..129): the same spectra either way, no note
    assert main(["inspect", str(ALL_130), "--select", "cycle=10:40"]) == 0
    assert "note: --select" not in capsys.readouterr().err
    # ends past the last position (temperatures 20, 25.5, 30: 20:30 as positions picks nothing): no note
    path = tmp_path / "temperatures.nc"
    with xr.open_dataset(THREE) as ds:
        ds.load().assign_coords(cycle=[20.0, 25.5, 30.0]).rename(cycle="temperature").to_netcdf(path)
    assert main(["inspect", str(path), "--select", "temperature=20:30"]) == 0
    assert "note: --select" not in capsys.readouterr().err
    # a range inside a list: the note names it
    assert main(["inspect", str(THREE), "--select", "cycle=129,0:20"]) == 0
    assert "note: --select cycle=129,0:20 (its range 0:20) keeps cycle 0 (1 of 3)" in capsys.readouterr().err
    # a list names labels one by one: no note
    assert main(["inspect", str(THREE), "--select", "cycle=0,64"]) == 0
    assert "note: --select" not in capsys.readouterr().err
