"""The shipped REAL battery files (AutoEIS 0.0.44's autoeis/assets/battery_data.npy, MIT) name the
file they were built from as their stored ``source``, which `impedax.load` keeps as
``attrs["saved_from"]`` and `impedax inspect` prints. Until 2026-12-06
examples/data/autoeis_battery_cycles.nc named itself ("saved_from: autoeis_battery_cycles.nc")
and benchmarks/data/autoeis_battery_130.nc named impedax's in-memory marker ("memory"), so a
user could not tell where the data came from. Only the attribute changed: the data sections of
the files are byte for byte those they had, and the three example cycles are cycles 0, 64 and
129 of the 130, as their LICENSE notes say."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.errors import IN_MEMORY

ROOT = Path(__file__).parent.parent
SHIPPED = [ROOT / "examples" / "data" / "autoeis_battery_cycles.nc", ROOT / "benchmarks" / "data" / "autoeis_battery_130.nc"]


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.name)
def test_a_shipped_file_names_the_file_it_was_built_from(path):
    with xr.open_dataset(path, engine="scipy") as raw:
        stored = raw.attrs["source"]
        origin = raw.attrs["origin"]
    data = ix.load(path)
    saved_from = data.attrs["saved_from"]
    assert saved_from == stored and saved_from not in (IN_MEMORY, path.name, str(path))
    assert Path(saved_from.split(" ")[0]).name == "battery_data.npy" and "battery_data.npy" in origin
    assert data.attrs["source"] == str(path)


def test_the_shipped_values_are_the_battery_cycles():
    cycles, all_cycles = (ix.load(p) for p in SHIPPED)
    assert cycles["Z"].shape == (3, 57) and all_cycles["Z"].shape == (130, 57)
    # the three example cycles are cycles 0, 64 and 129 of the 130, bit for bit
    np.testing.assert_array_equal(cycles["Z"].values, all_cycles["Z"].sel(cycle=[0, 64, 129]).values)
    np.testing.assert_array_equal(cycles["frequency"].values, all_cycles["frequency"].values)
