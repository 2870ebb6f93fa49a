"""The Python API as a notebook uses it on REAL data (impedance.py's BioLogic example, MIT):
what a result's ``to_xarray`` and its written ``.nc`` hold, and what reading one back says."""

from __future__ import annotations

import re

import numpy as np
import pytest

import impedax as ix
from impedax.errors import DataError

REAL = "tests/fixtures/real/exampleDataBioLogic.mpt"


@pytest.fixture(scope="module")
def data():
    return ix.load(REAL)


def test_a_comparison_nc_given_as_data_is_named(data, tmp_path):
    """``ix.write_result(ix.compare(...), "c.nc")`` then ``ix.load("c.nc")``: the file holds the
    models' table, not a spectrum; it was told "dataset has no variable 'Z'" and the table's
    column names, as if the file were a damaged spectrum."""
    comparison = ix.compare([ix.fit("R0 + R1 || C1", data), ix.fit("R0 + R1 || CPE1", data)])
    out = tmp_path / "c.nc"
    ix.write_result(comparison, out)
    with pytest.raises(DataError, match=re.escape("holds a comparison of models on one spectrum (impedax compare), not a spectrum; read it with impedax.io.read_netcdf(path)")):
        ix.load(out)
    back = ix.io.read_netcdf(out)
    assert list(back["model"].values) == ["R0 + R1 || C1", "R0 + R1 || CPE1"]
    np.testing.assert_allclose(back["aic"].values, [row["aic"] for row in comparison.rows])
