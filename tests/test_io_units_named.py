"""The ``units`` line of a table whose headers name no unit says which units impedax read them
in (Hz, Ω, degrees), so that a researcher checks them against the instrument's; a header that
names its unit is not listed. REAL files: data.xlsx (headers 'f', "Z'", "Z''"; 'frequency',
'|Z|', '-phase'), exampleDataAutolab.txt ('Freq(Hz)', "Z'(a)", "Z''(b)"), exampleDataBioLogic.mpt
(every header with its unit)."""

from pathlib import Path

import impedax as ix

REAL = Path(__file__).parent / "fixtures" / "real"


def test_headers_without_units_are_named_with_the_unit_read():
    units = ix.load(REAL / "data.xlsx").attrs["units"]  # (each sheet's, joined: 'sheet S: …; sheet T: …')
    assert "'f', \"Z'\", \"Z''\"; no unit in the header of 'f' (read as Hz), \"Z'\" and \"Z''\" (read as Ω); sheet header-variant-2" in units, units
    assert units.endswith("; no unit in the header of 'frequency' (read as Hz), '|Z|' (read as Ω), '-phase' (read as degrees)"), units


def test_inspect_prints_each_sheets_units_on_its_line(capsys):
    from impedax.cli import main

    assert main(["inspect", str(REAL / "data.xlsx")]) == 0
    out = capsys.readouterr().out
    assert "    sheet header-variant-1: columns used (scaled to Hz, Ω, degrees): 'f', \"Z'\", \"Z''\"; no unit in the header of 'f' (read as Hz), \"Z'\" and \"Z''\" (read as Ω)\n" in out, out


def test_only_the_headers_without_a_unit_are_listed():
    autolab = ix.load(REAL / "exampleDataAutolab.txt").attrs["units"]
    assert autolab.endswith("; no unit in the header of \"Z'(a)\" and \"Z''(b)\" (read as Ω)"), autolab
    assert "no unit" not in ix.load(REAL / "exampleDataBioLogic.mpt").attrs["units"]
    # a file without header: its interpretation note says what the columns were read as
    assert "no unit" not in ix.load(REAL / "exampleData.csv").attrs["units"]
