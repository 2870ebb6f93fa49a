"""One line above a table's header (Excel's 'sep=;' separator line) is named as one line, in full:
until 2026-12-06 attrs["preamble"] said "lines 1–1: … 'sep=;' …", as if more had been passed over."""

import impedax as ix


def test_excels_separator_line(tmp_path):
    # SYNTHETIC: a decimal-comma CSV as a European Excel saves it, with its 'sep=;' first line
    path = tmp_path / "excel.csv"
    path.write_text("sep=;\nFrequency (Hz);Z' (Ohm);Z'' (Ohm)\n1000;10,5;-5,25\n100;12,1;-8,3\n10;20,2;-9,1\n")
    ds = ix.load(path)
    assert ds.attrs["preamble"] == "line 1: text above the table's header (line 2), not read: 'sep=;'"
    assert ds["Z"].values.tolist() == [10.5 - 5.25j, 12.1 - 8.3j, 20.2 - 9.1j]


def test_several_lines_keep_their_range(tmp_path):
    path = tmp_path / "notes.csv"
    path.write_text("Instrument: FooStat 3000\nOperator: A\nFrequency (Hz),Z' (Ohm),Z'' (Ohm)\n1000,10,-5\n100,12,-8\n10,20,-9\n")
    assert ix.load(path).attrs["preamble"] == "lines 1–2: text above the table's header (line 3), not read: 'Instrument: FooStat 3000' …"
