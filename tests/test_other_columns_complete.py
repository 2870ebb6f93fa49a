"""``attrs["other_columns"]`` is "columns present but not used" (docs/io.md): every named column of
the table is either read (``attrs["columns"]``) or listed there. Until 2026-12-06 the |Z| and phase
columns beside Z' and Z'' were in neither: the REAL EC-Lab files listed 13 (and 3) other columns
but not their |Z|/Ohm and Phase(Z)/deg, and the REAL CH Instruments file listed none, though it
holds Z/ohm and Phase/deg. The oracle: each file's own header line."""

from pathlib import Path

import pytest

import impedax as ix

REAL = Path(__file__).parent / "fixtures" / "real"


@pytest.mark.parametrize("name, header_line, delimiter, polar", [
    ("exampleDataBioLogic.mpt", 61, "\t", ["|Z|/Ohm", "Phase(Z)/deg"]),
    ("test_data.txt", 1, "\t", ["|Z|/Ohm", "Phase(Z)/deg"]),
    ("exampleDataCHInstruments.txt", 17, ",", ["Z/ohm", "Phase/deg"]),
])
def test_every_named_column_is_read_or_listed_as_another(name, header_line, delimiter, polar):
    path = REAL / name
    header = [c.strip() for c in path.read_text(encoding="latin-1").splitlines()[header_line - 1].split(delimiter) if c.strip()]
    ds = ix.load(path)
    read = [entry["column"] for entry in ds.attrs["columns"].values()]
    others = ds.attrs["other_columns"].split(", ")
    assert all(column in others for column in polar) and not set(read) & set(others)
    assert others == [c for c in header if c not in read]  # (in the header's order)
