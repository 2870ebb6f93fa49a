"""A saved comparison's ``same_fit_as`` reads back as text whether or not a model tied: the
label of the model with the same fit, "" for none, as its CSV column and its ``bounds`` and
``undetermined`` variables give it. Until 2026-12-06 a .nc of a comparison where no model tied
(REAL exampleData.csv, R0 + R1 ∥ CPE1 against R0 + R1 ∥ C1) held NaN, a float, where the rows
say None. Oracle: the comparison's own rows and the CSV as Python's csv module reads it."""

import csv

import xarray as xr

import impedax as ix


def test_same_fit_as_reads_back_as_text_where_no_model_tied(tmp_path):
    data = ix.load("tests/fixtures/real/exampleData.csv")
    comparison = ix.compare([ix.fit("R0 + R1 || CPE1", data), ix.fit("R0 + R1 || C1", data)])
    assert [r["same_fit_as"] for r in comparison.rows] == [None, None]
    ix.write_result(comparison, tmp_path / "c.nc")
    ix.write_result(comparison, tmp_path / "c.csv")
    with xr.open_dataset(tmp_path / "c.nc", engine="scipy") as saved:
        read = list(saved["same_fit_as"].values)
    assert all(isinstance(v, str) for v in read) and read == ["", ""]
    with open(tmp_path / "c.csv", newline="") as fh:
        assert [row["same_fit_as"] for row in csv.DictReader(fh)] == read  # (the CSV's empty cells)
