"""docs/io.md, "What the instrument's file says": the metadata keys documented for each reader
are the ones the REAL fixture files give (tests/fixtures/real, impedance.py and AutoEIS example
data), and a key documented as written "only when" the file holds it is one the reader's code
writes (its module's text names it)."""

import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
import impedax.io.formats as formats

ROOT = Path(__file__).resolve().parents[1]
REAL = ROOT / "tests" / "fixtures" / "real"
DOC = (ROOT / "docs" / "io.md").read_text(encoding="utf-8")
KEY = re.compile(r"`([a-z][a-z0-9_]*)`")


def _section(heading: str) -> str:
    start = DOC.index(heading)
    return DOC[start : DOC.index("\n#", start + len(heading))]


def _table_rows(text: str) -> list[list[str]]:
    """The cells of each row of the markdown table(s) in ``text`` (header and rule left out)."""
    rows = [[c.strip() for c in line.strip().strip("|").split("|")] for line in text.splitlines() if line.startswith("| ")]
    return [r for r in rows if not set("".join(r)) <= set("-")][1:]


# the keys that say how the file was read (the table above), and where from: not instrument metadata
HOW_READ = {KEY.match(row[0]).group(1) for row in _table_rows(_section("## What is reported in `attrs`"))} | {"path", "source"}
METADATA = [row for row in _table_rows(_section("### What the instrument's file says")) if row[0] != "format (`attrs[\"format\"]`)"]


def _documented(cell: str) -> tuple[set[str], set[str]]:
    """(keys always written, keys written only when the file holds them) of a table cell."""
    optional = {m.group(1) for m in re.finditer(r"`([a-z][a-z0-9_]*)` \(only when", cell)}
    return {k for k in KEY.findall(cell) if k not in optional} - {"none"}, optional


def test_every_reader_format_has_a_row():
    documented = {row[0] for row in METADATA}
    formats_written = set(re.findall(r'"format": "([^"]+)"', "".join(Path(m.__file__).read_text() for m in vars(formats).values()
                                                                          if getattr(m, "__name__", "").startswith("impedax.io.formats."))))
    assert len(formats_written) >= 17 and formats_written - {"impedax netCDF"} <= documented, formats_written - documented


@pytest.mark.parametrize("row", [r for r in METADATA if r[2]], ids=lambda r: r[0])
def test_documented_keys_are_what_the_real_file_gives(row):
    fmt, cell, file_name = row
    ds = ix.load(REAL / file_name)
    assert ds.attrs["format"] == fmt
    always, optional = _documented(cell)
    given = set(ds.attrs) - HOW_READ
    assert given - optional == always, f"{file_name}: gives {sorted(given)}, documented {sorted(always)}"


@pytest.mark.parametrize("row", [r for r in METADATA if _documented(r[1])[1]], ids=lambda r: r[0])
def test_optional_keys_are_written_by_the_reader(row):
    fmt, cell, _ = row
    sources = [Path(m.__file__).read_text() for m in vars(formats).values()
               if getattr(m, "__name__", "").startswith("impedax.io.formats.") and f'"{fmt}"' in Path(m.__file__).read_text()]
    assert sources, fmt
    sources.append((ROOT / "impedax" / "io" / "dates.py").read_text())  # (the date's keys, every reader's that records one: `record_date`)
    for key in _documented(cell)[1]:
        assert any(f'attrs["{key}"]' in text for text in sources), (fmt, key)


@pytest.mark.parametrize("written, area_cm2", [(b"0.001 cm\xb2", 0.001), (b"1,5 cm\xb2", 1.5), (b"2.5 cm2", 2.5), (b"0.5 mm\xb2", None)])
def test_biologic_area_as_a_number_in_cm2(tmp_path, written, area_cm2):
    # the REAL file says "Electrode surface area : 0.001 cm²" (Latin-1); SYNTHETIC variants of that line
    raw = (REAL / "exampleDataBioLogic.mpt").read_bytes()
    assert b"Electrode surface area : 0.001 cm\xb2" in raw
    path = tmp_path / "area.mpt"
    path.write_bytes(raw.replace(b"Electrode surface area : 0.001 cm\xb2", b"Electrode surface area : " + written))
    attrs = ix.load(path).attrs
    assert attrs["electrode_surface_area"] == written.decode("latin-1")
    assert attrs.get("area_cm2") == area_cm2


def test_gamry_header_numbers_with_decimal_commas(tmp_path):
    # SYNTHETIC: the REAL exampleDataGamry.DTA's header numbers as a decimal-comma locale writes them;
    # area_cm2 stayed the text '1,00000E+000' where the docs promise numbers
    real = ix.load(REAL / "exampleDataGamry.DTA").attrs
    keys = ("area_cm2", "dc_voltage_v", "ac_voltage_mv_rms", "initial_frequency_hz", "final_frequency_hz")
    lines = (REAL / "exampleDataGamry.DTA").read_bytes().split(b"\n")
    header = {b"AREA", b"VDC", b"VAC", b"FREQINIT", b"FREQFINAL"}
    swapped = [line.replace(b".", b",") if line.split(b"\t")[0] in header else line for line in lines]
    assert sum(a != b for a, b in zip(lines, swapped)) == len(header)
    path = tmp_path / "comma.DTA"
    path.write_bytes(b"\n".join(swapped))
    attrs = ix.load(path).attrs
    assert {k: attrs[k] for k in keys} == {k: real[k] for k in keys} == {
        "area_cm2": 1.0, "dc_voltage_v": -0.05, "ac_voltage_mv_rms": 10.0, "initial_frequency_hz": 200000.0, "final_frequency_hz": 0.02}


@pytest.mark.parametrize("name, header_lines", [("exampleDataBioLogic.mpt", 61), ("exampleDataGamry.DTA", None)])
def test_decimal_commas_of_an_instrument_table_are_reported(tmp_path, name, header_lines):
    # SYNTHETIC: the REAL file's table with decimal commas (tab-separated: unambiguous). The numbers were
    # read right, but attrs["decimal_mark"], documented for any file that used decimal commas, was absent
    raw = (REAL / name).read_bytes()
    lines = raw.split(b"\n")
    if header_lines:  # (EC-Lab: the rows below its header lines)
        swapped = lines[:header_lines] + [line.replace(b".", b",") for line in lines[header_lines:]]
    else:  # (Gamry: the ZCURVE table's rows start with a tab)
        swapped = [line.replace(b".", b",") if line.startswith(b"\t") else line for line in lines]
    path = tmp_path / name
    path.write_bytes(b"\n".join(swapped))
    real, comma = ix.load(REAL / name), ix.load(path)
    np.testing.assert_array_equal(comma["Z"].values, real["Z"].values)
    np.testing.assert_array_equal(comma["frequency"].values, real["frequency"].values)
    assert comma.attrs["decimal_mark"] == "comma" and "decimal_mark" not in real.attrs
