"""Readers on files as users make them (a walkthrough of 2026-12-01): a Gamry table cut short,
a units row under a CSV or spreadsheet header, notes above a spreadsheet's header, rows of bare
delimiters, and refusals that say what to do next.

Every file is written by its test. Data are SYNTHETIC: Z = R0 + R1 ∥ CPE(Q, n) with R0 = 20 Ω,
R1 = 500 Ω, Q = 2e-5 F·s^(n−1), n = 0.85 on 12 log-spaced frequencies from 100 kHz down to
0.1 Hz, with 1 % complex Gaussian noise (seed 73); the oracle is that array, written into each
file in the file's own layout.
"""

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.errors import DataError
from impedax.io._common import CUT_SHORT

FREQ = np.logspace(5, -1, 12)
_RNG = np.random.default_rng(73)
# SYNTHETIC: R0 + R1 || CPE, Z_CPE = 1 / (Q (j w)^n); 1 % noise on each part
_Z_TRUE = 20 + 500 / (1 + 500 * 2e-5 * (2j * np.pi * FREQ) ** 0.85)
Z = _Z_TRUE * (1 + 0.01 * (_RNG.standard_normal(FREQ.size) + 1j * _RNG.standard_normal(FREQ.size)))


def _gamry(rows_text: list[str], *, end: str = "\r\n") -> str:
    """A Gamry .DTA (EISPOT) around ``rows_text``, the ZCURVE rows without their line ends."""
    head = [
        "EXPLAIN", "TAG\tEISPOT", "TITLE\tLABEL\tPotentiostatic EIS\tTest &Identifier",
        "ZCURVE\tTABLE",
        "\tPt\tTime\tFreq\tZreal\tZimag\tZsig\tZmod\tZphz\tIdc\tVdc\tIERange",
        "\t#\ts\tHz\tohm\tohm\tV\tohm\t°\tA\tV\t#",
    ]
    return "\r\n".join(head + rows_text) + end


def _gamry_rows(decimal: str = ".") -> list[str]:
    rows = []
    for k, (f, z) in enumerate(zip(FREQ, Z)):
        cells = [k, 2 * k, f"{f:.7g}", f"{z.real:.7g}", f"{z.imag:.7g}", 1, f"{abs(z):.7g}", f"{np.degrees(np.angle(z)):.7g}", "-1E-006", "-0.34", 7]
        rows.append("\t" + "\t".join(str(c).replace(".", decimal) for c in cells))
    return rows


# --- 1. Gamry: a row with another field count than the header is refused --------------------


def test_gamry_reads_the_synthetic_table(tmp_path):
    path = tmp_path / "g.DTA"
    path.write_text(_gamry(_gamry_rows()), encoding="latin-1")
    ds = ix.load(path)
    np.testing.assert_allclose(ds["Z"].values, Z, rtol=1e-6)
    np.testing.assert_allclose(ds["frequency"].values, FREQ, rtol=1e-6)


def test_gamry_last_row_cut_mid_number_is_refused_not_read(tmp_path):
    rows = _gamry_rows()
    cut = rows[-1][: rows[-1].index("\t", rows[-1].index(f"{Z[-1].real:.7g}")) + 5]  # (Zimag cut after 4 characters)
    path = tmp_path / "cut.DTA"
    path.write_text(_gamry(rows[:-1] + [cut], end=""), encoding="latin-1")
    with pytest.raises(DataError) as info:
        ix.load(path)
    message = str(info.value)
    assert "line 18: 6 fields, but the header has 12" in message
    assert "cut short" in message and "cut.DTA" in message
    assert main(["inspect", str(path)]) == 2


def test_gamry_row_short_of_fields_inside_the_table_is_refused(tmp_path):
    rows = _gamry_rows()
    rows[3] = rows[3].rsplit("\t", 2)[0]  # (two cells lost: Vdc and IERange)
    path = tmp_path / "short.DTA"
    path.write_text(_gamry(rows), encoding="latin-1")
    with pytest.raises(DataError, match=r"line 10: 10 fields, but the header has 12") as info:
        ix.load(path)
    assert "cut short" not in str(info.value)


def test_gamry_trailing_tab_is_not_a_field(tmp_path):
    path = tmp_path / "tab.DTA"
    path.write_text(_gamry([r + "\t" for r in _gamry_rows()]), encoding="latin-1")
    np.testing.assert_allclose(ix.load(path)["Z"].values, Z, rtol=1e-6)


def _refused(path) -> str:
    """The message `ix.load` refuses ``path`` with; ``impedax inspect`` exits 2 on it."""
    with pytest.raises(DataError) as info:
        ix.load(path)
    assert main(["inspect", str(path)]) == 2
    return str(info.value)


def test_gamry_table_without_its_units_row_says_the_row_is_missing(tmp_path):
    text = _gamry(_gamry_rows()).replace("\t#\ts\tHz\tohm\tohm\tV\tohm\t°\tA\tV\t#\r\n", "")
    path = tmp_path / "nounits.DTA"
    path.write_text(text, encoding="latin-1")
    message = _refused(path)
    # (the column names are on line 5, so the missing units row would be line 6: the first data row)
    assert "line 6" in message and "no units row" in message and "Freq = " in message


def test_gamry_decimal_comma_is_decided_on_every_row(tmp_path):
    # the first 20 rows' numbers carry no ',' (whole numbers), a later row's do: read as decimal commas
    freq = np.arange(30, 0, -1) * 1000.0
    z = 100.0 - 10j * np.arange(1, 31)
    rows = [f"\t{k}\t{k}\t{f:g}\t{zk.real:g}\t{zk.imag:g}\t1\t1\t1\t1\t1\t7" for k, (f, zk) in enumerate(zip(freq, z))]
    rows[25] = rows[25].replace("\t100\t", "\t100,5\t")
    path = tmp_path / "late_comma.DTA"
    path.write_text(_gamry(rows), encoding="latin-1")
    ds = ix.load(path)
    expected = z.copy()
    expected[25] += 0.5
    np.testing.assert_allclose(ds["Z"].values, expected)
    # a '.' beside them is two locales in one file: refused, naming the line
    rows[28] = rows[28].replace("\t100\t", "\t100.25\t")
    path.write_text(_gamry(rows), encoding="latin-1")
    with pytest.raises(DataError, match=r"line 35: column 'Zreal': '100.25' has a '.'"):
        ix.load(path)


# --- 2. a units row under the header ---------------------------------------------------------


def _comma(x: float) -> str:
    return f"{x:.9g}".replace(".", ",")


def test_csv_units_row_is_read_as_the_header_units_and_applied(tmp_path):
    # SYNTHETIC: f in kHz, |Z| in kOhm, phase in degrees, decimal commas, units on line 2
    lines = ["Frequency;|Z|;Phase", "kHz;kOhm;deg"]
    lines += [f"{_comma(f / 1e3)};{_comma(abs(z) / 1e3)};{_comma(np.degrees(np.angle(z)))}" for f, z in zip(FREQ, Z)]
    path = tmp_path / "units_row.csv"
    path.write_text("\n".join(lines) + "\n")
    ds = ix.load(path)
    np.testing.assert_allclose(ds["frequency"].values, FREQ, rtol=1e-8)
    np.testing.assert_allclose(ds["Z"].values, Z, rtol=1e-7)
    assert ds.attrs["units_row"] == "line 2: units under the header (kHz, kOhm, deg), read as the columns' units"
    assert "'Frequency (kHz)' ×1000" in ds.attrs["units"]


def test_csv_units_row_in_milliohm_and_minus_z_imag(tmp_path):
    lines = ["Frequency;Z';-Z''", "Hz;mOhm;mOhm"] + [f"{_comma(f)};{_comma(z.real * 1e3)};{_comma(-z.imag * 1e3)}" for f, z in zip(FREQ, Z)]
    path = tmp_path / "milliohm.csv"
    path.write_text("\n".join(lines) + "\n")
    np.testing.assert_allclose(ix.load(path)["Z"].values, Z, rtol=1e-7)


def test_csv_units_row_below_a_preamble(tmp_path):
    lines = ["Instrument: FooStat 3000", "Operator: J. Doe", "Frequency,Z',Z''", "Hz,Ohm,Ohm"] + [f"{f:.17g},{z.real:.17g},{z.imag:.17g}" for f, z in zip(FREQ, Z)]
    path = tmp_path / "preamble_units.csv"
    path.write_text("\n".join(lines) + "\n")
    ds = ix.load(path)
    np.testing.assert_array_equal(ds["Z"].values, Z)
    assert ds.attrs["units_row"].startswith("line 4: ")


@pytest.mark.parametrize("second", ["Hz;1;Ohm", "Hz;Ohm;note"])
def test_a_row_that_is_not_all_units_is_still_a_data_row(tmp_path, second):
    path = tmp_path / "not_units.csv"
    path.write_text("\n".join(["Frequency;Z';-Z''", second, "100;1;2"]) + "\n")
    with pytest.raises(DataError, match=r"line 2: column 'Frequency': 'Hz' is not a number"):
        ix.load(path)


def test_xlsx_units_row_is_read_and_applied(tmp_path):
    openpyxl = pytest.importorskip("openpyxl")
    workbook = openpyxl.Workbook()
    sheet = workbook.active
    sheet.append(["Frequency", "Z'", "-Z''"])
    sheet.append(["kHz", "kOhm", "kOhm"])
    for f, z in zip(FREQ, Z):
        sheet.append([f / 1e3, z.real / 1e3, -z.imag / 1e3])
    path = tmp_path / "units.xlsx"
    workbook.save(path)
    ds = ix.load(path)
    np.testing.assert_allclose(ds["frequency"].values, FREQ, rtol=1e-12)
    np.testing.assert_allclose(ds["Z"].values, Z, rtol=1e-12)
    assert ds.attrs["units_row"].startswith("row 2: units under the header (kHz, kOhm, kOhm)")


# --- 3. notes above a spreadsheet's header ---------------------------------------------------


def test_xlsx_with_notes_above_the_header_loads_as_the_same_csv_does(tmp_path):
    openpyxl = pytest.importorskip("openpyxl")
    preamble = [["Instrument: FooStat"], ["Date", "2026-11-30"], []]
    table = [["Frequency (Hz)", "Z' (Ohm)", "-Z'' (Ohm)"]] + [[float(f), float(z.real), float(-z.imag)] for f, z in zip(FREQ, Z)]
    workbook = openpyxl.Workbook()
    for row in preamble + table:
        workbook.active.append(row)
    path = tmp_path / "notes.xlsx"
    workbook.save(path)
    text = tmp_path / "notes.csv"
    text.write_text("\n".join(",".join(str(c) for c in row) for row in preamble + table) + "\n")
    ds, same = ix.load(path), ix.load(text)
    np.testing.assert_allclose(ds["Z"].values, Z, rtol=1e-14)  # (the .xlsx keeps 15 digits or so)
    np.testing.assert_allclose(ds["Z"].values, same["Z"].values, rtol=1e-14)
    assert ds.attrs["preamble"].startswith("rows 1–3: text above the table's header (row 4), not read: 'Instrument: FooStat'")


def test_xlsx_of_notes_only_still_names_the_missing_frequency_column(tmp_path):
    openpyxl = pytest.importorskip("openpyxl")
    workbook = openpyxl.Workbook()
    for row in (["Instrument: FooStat"], ["Operator", "J. Doe"], ["Points", 50]):
        workbook.active.append(row)
    path = tmp_path / "notes_only.xlsx"
    workbook.save(path)
    with pytest.raises(DataError, match=r"no sheet holds a spectrum table: sheet 'Sheet': no frequency column"):
        ix.load(path)


# --- 4. rows of delimiters only --------------------------------------------------------------


@pytest.mark.parametrize("end", ["\n", ""])
def test_csv_rows_of_commas_at_the_end_are_skipped_and_listed(tmp_path, end):
    lines = ["frequency_hz,z_real_ohm,z_imag_ohm"] + [f"{f:.17g},{z.real:.17g},{z.imag:.17g}" for f, z in zip(FREQ, Z)] + [",,", ",,"]
    path = tmp_path / "excel_tail.csv"
    path.write_text("\n".join(lines) + end)
    ds = ix.load(path)
    np.testing.assert_array_equal(ds["Z"].values, Z)
    assert ds.attrs["skipped_rows"] == ["lines 14–15: empty row (delimiters only)"]


def test_semicolon_row_in_the_middle_is_skipped_and_inspect_lists_it(tmp_path, capsys):
    rows = [f"{_comma(f)};{_comma(z.real)};{_comma(-z.imag)}" for f, z in zip(FREQ, Z)]
    lines = ["Frequency (Hz);Z' (Ohm);-Z'' (Ohm)"] + rows[:5] + [";;"] + rows[5:]
    path = tmp_path / "excel_gap.csv"
    path.write_text("\n".join(lines) + "\n")
    ds = ix.load(path)
    np.testing.assert_allclose(ds["Z"].values, Z, rtol=1e-8)
    assert ds.attrs["skipped_rows"] == ["line 7: empty row (delimiters only)"]
    assert main(["inspect", str(path), "--json"]) == 0
    assert '"line 7: empty row (delimiters only)"' in capsys.readouterr().out


def test_a_row_with_one_empty_cell_is_still_a_missing_value(tmp_path):
    lines = ["frequency_hz,z_real_ohm,z_imag_ohm", "100,1,-2", "10,,-3", "1,1,-4"]
    path = tmp_path / "gap_cell.csv"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(DataError, match=r"line 3: column 'z_real_ohm' is empty \(missing value\)"):
        ix.load(path)


# --- 5. refusals that say what to do next ----------------------------------------------------


def _canonical(rows) -> str:
    return "frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{f:.17g},{z.real:.17g},{z.imag:.17g}\n" for f, z in rows)


def test_second_sweep_turning_back_is_named_with_its_line_and_a_way_out(tmp_path):
    path = tmp_path / "down_up.csv"
    path.write_text(_canonical(list(zip(FREQ, Z)) + list(zip(FREQ[::-1], Z[::-1]))))
    with pytest.raises(DataError) as info:
        ix.load(path)
    message = str(info.value)
    assert "line 14: duplicate frequency 0.1 Hz (also on line 13): a second sweep starts on line 14" in message
    assert "lines 2–13 and 14–25" in message and "--select sweep=0" in message


def test_single_repeated_point_is_named_with_a_remedy(tmp_path):
    rows = list(zip(FREQ, Z))
    path = tmp_path / "dupe.csv"
    path.write_text(_canonical(rows[:6] + [rows[5]] + rows[6:]))
    with pytest.raises(DataError, match=r"line 8: duplicate frequency 187.382 Hz \(also on line 7\): a point measured twice\? delete one"):
        ix.load(path)


@pytest.mark.parametrize("header", [
    "Frequency (Hz),Z' cell1 (Ohm),Z'' cell1 (Ohm),Z' cell2 (Ohm),Z'' cell2 (Ohm)",
    "f1 (Hz),Z' 1 (Ohm),Z'' 1 (Ohm),f2 (Hz),Z' 2 (Ohm),Z'' 2 (Ohm)",
])
def test_spectra_side_by_side_are_named_as_such(tmp_path, header):
    n = header.count(",") + 1
    path = tmp_path / "side.csv"
    path.write_text(header + "\n" + "\n".join(",".join(["1"] * n) for _ in range(3)) + "\n")
    with pytest.raises(DataError) as info:
        ix.load(path)
    message = str(info.value)
    assert "the header holds spectra side by side (" in message and "Z'' 2 (Ohm)" in message.replace("cell", "")
    assert "a sheet of its own" in message and "one below the other" in message


def test_one_labelled_spectrum_is_not_side_by_side(tmp_path):
    path = tmp_path / "one.csv"
    path.write_text("Frequency (Hz),Z' cell1 (Ohm),Z'' cell1 (Ohm)\n1,2,3\n")
    with pytest.raises(DataError, match="cannot find impedance columns") as info:
        ix.load(path)
    assert "side by side" not in str(info.value)


def test_no_frequency_column_lists_the_accepted_names_for_a_spectrum_header(tmp_path):
    path = tmp_path / "frequenz.csv"
    path.write_text("Frequenz (Hz);Z' / Ohm;-Z'' / Ohm\n100;1;2\n")
    with pytest.raises(DataError, match=r"'Frequenz \(Hz\)' is in a frequency unit, but a frequency column is named 'Frequency', 'Freq', 'Freq.', 'f'"):
        ix.load(path)


def test_question_mark_unit_hints_at_a_lost_ohm(tmp_path):
    path = tmp_path / "cp1252.csv"
    path.write_bytes("Frequency / Hz;Z' / ?;-Z'' / ?\n100;1;2\n".encode("cp1252"))
    with pytest.raises(DataError, match=r"unit '\?' not understood .*an Ω lost when the file was saved in an encoding without it"):
        ix.load(path)


FIXTURES = __import__("pathlib").Path(__file__).parent / "fixtures"


def test_biologic_header_count_that_misses_the_column_names_says_where_they_are(tmp_path):
    lines = (FIXTURES / "biologic_peis.mpt").read_bytes().decode("latin-1").split("\n")
    del lines[5]  # (a header line deleted by hand: the names move from line 19 to 18; the count still says 19)
    path = tmp_path / "edited.mpt"
    path.write_bytes("\n".join(lines).encode("latin-1"))
    with pytest.raises(DataError, match=r"line 2: 'Nb header lines : 19' puts the column names on line 19, but they are on line 18 "
                                        r"\(was a header line deleted\?\): write 'Nb header lines : 18'"):
        ix.load(path)


def test_biologic_file_of_another_technique_names_it(tmp_path, capsys):
    """The REAL exampleDataBioLogic.mpt's header over a cyclic voltammetry table (EC-Lab's CV
    columns): refused as "columns ['freq/Hz', ...] not found on header line 61", which does not
    say that the file holds another experiment; the technique on its line 4 is now named."""
    lines = (FIXTURES / "real" / "exampleDataBioLogic.mpt").read_bytes().decode("latin-1").split("\n")
    lines[3] = "Cyclic Voltammetry"
    names = "mode\tox/red\terror\tcontrol changes\tcounter inc.\ttime/s\tcontrol/V\tEwe/V\t<I>/mA\tcycle number"
    rows = [f"2\t1\t0\t0\t0\t{k}\t0.1\t0.2\t0.003\t1" for k in range(20)]
    path = tmp_path / "cv.mpt"
    path.write_bytes("\n".join(lines[:60] + [names] + rows + [""]).encode("latin-1"))
    with pytest.raises(DataError, match=r"cv\.mpt, line 61: columns \['freq/Hz', 'Re\(Z\)/Ohm', '-Im\(Z\)/Ohm'\] not found on header line 61; .*"
                                        r"the file holds a 'Cyclic Voltammetry' experiment \(line 4\), not an impedance spectrum"):
        ix.load(path)
    assert main(["inspect", str(path)]) == 2
    assert "Cyclic Voltammetry" in capsys.readouterr().err
    # an impedance file (line 4: Potentio Electrochemical Impedance Spectroscopy) whose names were
    # edited away is not told it holds another technique
    lines = (FIXTURES / "real" / "exampleDataBioLogic.mpt").read_bytes().decode("latin-1").split("\n")
    lines[60] = lines[60].replace("freq/Hz", "frequency")
    path.write_bytes("\n".join(lines).encode("latin-1"))
    with pytest.raises(DataError, match=r"not found on header line 61") as info:
        ix.load(path)
    assert "experiment" not in str(info.value)


def test_zplot_with_decimal_commas_says_so(tmp_path):
    names = "Freq(Hz)\tAmpl\tBias\tTime(Sec)\tZ'(a)\tZ''(b)\tGD\tErr\tRange"
    rows = [f"{f:.6E}\t1.0000E-02\t0.0000E+00\t{k:.6E}\t{z.real:.4E}\t{z.imag:.4E}\t0.0000E+00\t0\t3" for k, (f, z) in enumerate(zip(FREQ, Z))]
    head = ["ZPLOT2 ASCII", "  Data Points:                12", "  " + names, "End Comments"]
    path = tmp_path / "points.z"
    path.write_text("\r\n".join(head + rows) + "\r\n")
    np.testing.assert_allclose(ix.load(path)["Z"].values, Z, rtol=1e-4)  # (5 significant digits in the file)
    path.write_text("\r\n".join(head + [r.replace(".", ",") for r in rows]) + "\r\n")
    with pytest.raises(DataError, match=r"line 5: 16 fields, but the header has 9: the numbers are written with decimal commas \('1,000000E\+05'\)"):
        ix.load(path)


# --- inspect shows the values as read ----------------------------------------------------------


def test_inspect_shows_the_first_and_last_points_as_read_with_their_signs(tmp_path, capsys):
    # SYNTHETIC: a semicolon, decimal-comma table with -Z'' in kOhm, written in the file's order
    # (descending frequency); the truth is typed here, not taken from the reader
    path = tmp_path / "euro.csv"
    path.write_text("Frequency (Hz);Z' (kOhm);-Z'' (kOhm)\n1000;0,5;0,25\n10;2,5;1,5\n", encoding="utf-8")
    assert main(["inspect", str(path)]) == 0
    text = capsys.readouterr().out
    assert "first point f = 1 kHz: Z' = 500 Ω, Z'' = -250 Ω" in text
    assert "last point f = 10 Hz: Z' = 2500 Ω, Z'' = -1500 Ω" in text
    assert main(["inspect", str(path), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["first_point"] == {"frequency_hz": 1000.0, "z_real_ohm": 500.0, "z_imag_ohm": -250.0}
    assert summary["last_point"] == {"frequency_hz": 10.0, "z_real_ohm": 2500.0, "z_imag_ohm": -1500.0}


@pytest.mark.parametrize("unit", ["Ohm cm2", "Ω·cm²", "ohm*m^2"])
def test_an_area_specific_impedance_is_refused_with_the_conversion_to_ohm(tmp_path, unit):
    path = tmp_path / "area.csv"
    path.write_text(f"Frequency (Hz),Z' ({unit}),Z'' ({unit})\n1000,0.5,-0.25\n10,2.5,-1.5\n", encoding="utf-8")
    message = _refused(path)
    assert "area-specific" in message and "divide the column by the electrode area" in message and "line 1" in message


def test_a_plain_ohm_unit_gets_no_area_hint(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("Frequency (Hz),Z' (Siemens),Z'' (Siemens)\n1000,0.5,-0.25\n10,2.5,-1.5\n", encoding="utf-8")
    with pytest.raises(DataError) as info:
        ix.load(path)
    assert "not understood" in str(info.value) and "area-specific" not in str(info.value)


# --- a last row cut short: every reader that counts fields says the file looks cut short ------


def _cut_file(head: list[str], rows: list[list[str]], delimiter: str, *, end: str) -> str:
    """``head`` lines, then ``rows`` joined by ``delimiter``, the last row cut inside its middle
    field (half its fields and two characters of the next kept), then ``end``."""
    last = rows[-1]
    keep = len(last) // 2
    cut = delimiter.join(last[:keep]) + delimiter + last[keep][:2]
    return "\n".join(head + [delimiter.join(r) for r in rows[:-1]] + [cut]) + end


def _g(x: float) -> str:
    return f"{x:.7E}"


# SYNTHETIC: each layout holds FREQ and Z above, written by the test in the instrument's own form
_CUT_LAYOUTS = {
    "biologic.mpt": (
        ["EC-Lab ASCII FILE", "Nb header lines : 5", "", "Potentio Electrochemical Impedance Spectroscopy",
         "freq/Hz\tRe(Z)/Ohm\t-Im(Z)/Ohm\t|Z|/Ohm\tPhase(Z)/deg\ttime/s\tcycle number"],
        lambda f, z, k: [_g(f), _g(z.real), _g(-z.imag), _g(abs(z)), _g(np.degrees(np.angle(z))), _g(k), "1"], "\t", "BioLogic EC-Lab mpt"),
    "biologic_text.txt": (
        ["freq/Hz\tRe(Z)/Ohm\t-Im(Z)/Ohm\t|Z|/Ohm\tPhase(Z)/deg"],
        lambda f, z, k: [_g(f), _g(z.real), _g(-z.imag), _g(abs(z)), _g(np.degrees(np.angle(z)))], "\t", "BioLogic EC-Lab text"),
    "zplot.z": (
        ["ZPLOT2 ASCII", "  Data Points:                12", "  Freq(Hz)\tAmpl\tBias\tTime(Sec)\tZ'(a)\tZ''(b)\tGD\tErr\tRange", "End Comments"],
        lambda f, z, k: [_g(f), "1.0000E-02", "0.0000E+00", _g(k), _g(z.real), _g(z.imag), "0.0000E+00", "0", "3"], "\t", "Scribner ZPlot z"),
    "nova.txt": (
        ["Index;Frequency (Hz);Z' (Ω);-Z'' (Ω);Z (Ω);-Phase (°);Time (s)"],
        lambda f, z, k: [str(k + 1), _g(f), _g(z.real), _g(-z.imag), _g(abs(z)), _g(-np.degrees(np.angle(z))), _g(k)], ";", "Metrohm Autolab NOVA text"),
    "chi.txt": (
        ["Dec. 1, 2026   10:00:00", "A.C. Impedance", "Instrument Model:  CHI660E", "", 'Freq/Hz, Z\'/ohm, Z"/ohm, Z/ohm, Phase/deg', ""],
        lambda f, z, k: [_g(f), _g(z.real), _g(z.imag), _g(abs(z)), _g(np.degrees(np.angle(z)))], ", ", "CH Instruments text"),
    "parstat.txt": (
        ["Potential (V)\tCurrent (A)\tElapsed Time (s)\tFrequency (Hz)\tZre (ohms)\tZim (ohms)\t|Vac| (V)\t|Iac| (A)"],
        lambda f, z, k: ["0.1", "1E-06", _g(k), _g(f), _g(z.real), _g(z.imag), "0.01", "1E-05"], "\t", "Parstat text"),
    "z60w.txt": (
        ['"Z60W Data File: Version 1.1"', *(f'"comment {i}"' for i in range(7)), "1,0,0", "12",
         '"Freq (Hz) Ampl Bias Time(Sec) Z\'(a) Z\'\'(b) GD Err Range"'],
        lambda f, z, k: [_g(f), "0.01", "0", _g(k), _g(z.real), _g(z.imag), "0", "0", "3"], ",", "Autolab FRA Z60W"),
    "labone_table.csv": (
        ["frequency;realz;imagz;absz"],
        lambda f, z, k: [_g(f), _g(z.real), _g(z.imag), _g(abs(z))], ";", "Zurich Instruments LabOne CSV"),
}


@pytest.mark.parametrize("name", sorted(_CUT_LAYOUTS))
def test_a_last_row_cut_short_says_the_file_looks_cut_short_in_every_table_reader(tmp_path, name):
    head, cells, delimiter, fmt = _CUT_LAYOUTS[name]
    rows = [cells(f, z, k) for k, (f, z) in enumerate(zip(FREQ, Z))]
    last_line = len(head) + len(rows)
    path = tmp_path / name
    # the whole table, with no line end after its last row: read exactly (the oracle)
    path.write_text("\n".join(head + [delimiter.join(r) for r in rows]), encoding="utf-8")
    ds = ix.load(path)
    assert ds.attrs["format"] == fmt
    np.testing.assert_allclose(ds["Z"].values, Z, rtol=1e-6)
    # its last row cut inside a number: refused, naming the line, saying the file looks cut short
    path.write_text(_cut_file(head, rows, delimiter, end=""), encoding="utf-8")
    with pytest.raises(DataError) as info:
        ix.load(path)
    message = str(info.value)
    assert f"line {last_line}:" in message and name in message
    assert CUT_SHORT in message
    assert main(["inspect", str(path)]) == 2
    # the same short row with a line end after it: refused, but the file is not said to be cut
    path.write_text(_cut_file(head, rows, delimiter, end="\n"), encoding="utf-8")
    with pytest.raises(DataError, match=rf"line {last_line}:") as info:
        ix.load(path)
    assert "cut short" not in str(info.value)


def test_a_labone_field_line_cut_short_says_the_file_looks_cut_short(tmp_path):
    # SYNTHETIC: one line per field (the LabOne sweeper layout), the imagz line last and cut
    head = ["chunk;timestamp;size;fieldname"]
    rows = [["0", "1", "12", name, *map(_g, values)] for name, values in (("frequency", FREQ), ("realz", Z.real), ("imagz", Z.imag))]
    path = tmp_path / "sweep.csv"
    path.write_text("\n".join(head + [";".join(r) for r in rows]), encoding="utf-8")
    np.testing.assert_allclose(ix.load(path)["Z"].values, Z, rtol=1e-6)
    path.write_text(_cut_file(head, rows, ";", end=""), encoding="utf-8")
    with pytest.raises(DataError, match=r"line 4: sweep \(chunk\) 0, point 5: imagz missing") as info:
        ix.load(path)
    assert CUT_SHORT in str(info.value)


def test_an_ivium_table_cut_short_at_the_end_says_so(tmp_path):
    # SYNTHETIC: an .idf's key lines and its primary_data table (Z', Z'', f per row), the file's last
    head = ["Technique=Impedance", "Solarcell=false", "primary_data", "3", "12"]
    rows = [[_g(z.real), _g(z.imag), _g(f)] for f, z in zip(FREQ, Z)]
    path = tmp_path / "m.idf"
    path.write_text("\n".join(head + ["  ".join(r) for r in rows]), encoding="latin-1")
    np.testing.assert_allclose(ix.load(path)["Z"].values, Z, rtol=1e-6)
    path.write_text(_cut_file(head, rows, "  ", end=""), encoding="latin-1")
    with pytest.raises(DataError, match=r"line 17: 2 fields, expected Z', Z'', f") as info:
        ix.load(path)
    assert CUT_SHORT in str(info.value)


# --- a file cut before its table ends: the part missing is named, and the cut too ---------------

# REAL files of tests/fixtures/real, each cut inside a line before or inside its impedance table
# (at a byte offset, or at a line and a character), and what the reader finds missing there
_CUT_REAL = [
    ("exampleDataGamry.DTA", ("bytes", 0.6), "no ZCURVE table"),
    ("exampleDataZPlot.z", ("bytes", 300), "no 'End Comments' line ending the ZPlot header"),
    ("exampleDataBioLogic.mpt", ("bytes", 300), "'Nb header lines : 61' does not fit a file of 12 lines"),
    ("exampleDataVersaStudio.par", ("bytes", 300), "no segment with Frequency(Hz), Z Real and Z Imag columns"),
    ("exampleDataVersaStudio.par", ("line", 150, 40), "<Segment1> is not closed by </Segment1>"),
    ("data.idf", ("bytes", 300), "no 'primary_data' table"),
    ("data.idf", ("line", 185, 20), "'primary_data' announces 29 points but 17 lines follow"),
    ("data.dfr", ("bytes", 0.6), "header announces 29 points but the file holds at most 17 records"),
]


@pytest.mark.parametrize("name, cut, missing", _CUT_REAL, ids=[f"{n}-{c[0]}" for n, c, _ in _CUT_REAL])
def test_a_real_file_cut_before_its_table_ends_says_the_file_looks_cut_short(tmp_path, capsys, name, cut, missing):
    """A file copied before it was complete, cut before its table's end: the reader's refusal of the
    part it lacks used to be all ('no ZCURVE table (is this an impedance experiment?)' for a Gamry
    file cut at 60 %); it now adds that the file ends without a line end, as a cut file does."""
    raw = (FIXTURES / "real" / name).read_bytes()
    if cut[0] == "bytes":
        text = raw[: int(len(raw) * cut[1]) if isinstance(cut[1], float) else cut[1]]
    else:
        lines = raw.split(b"\n")
        text = b"\n".join(lines[: cut[1] - 1]) + b"\n" + lines[cut[1] - 1][: cut[2]]
    assert not text.endswith((b"\n", b"\r"))
    path = tmp_path / name
    path.write_bytes(text)
    with pytest.raises(DataError) as info:
        ix.load(path)
    message = str(info.value)
    assert missing in message and name in message
    assert "the file ends without a line end, as a file cut short does (copied before it was complete?): copy it again" in message
    assert main(["inspect", str(path)]) == 2
    assert "cut short" in capsys.readouterr().err
    # cut at a line end instead: the same refusal, and no word of a cut (nothing shows one)
    path.write_bytes(text[: text.rstrip(b"\r\n").rfind(b"\n") + 1])
    with pytest.raises(DataError) as info:
        ix.load(path)
    assert "cut short" not in str(info.value)


@pytest.mark.parametrize("keep, refusal", [
    (1001, "starts with a UTF-16 byte-order mark but is not UTF-16 text"),
    (0.6, "Expecting ',' delimiter"),
    (0.3, "Unterminated string"),
])
def test_a_real_palmsens_session_cut_short_says_so(tmp_path, capsys, keep, refusal):
    """The REAL data.pssession (UTF-16 JSON) cut while copying: to an odd byte count it was
    refused as 'not UTF-16 text', to an even one as 'invalid JSON (Expecting ',' delimiter)',
    neither saying that the file stops early nor where; both now say so, and a JSON error its
    line and column."""
    raw = (FIXTURES / "real" / "data.pssession").read_bytes()
    n = keep if isinstance(keep, int) else int(len(raw) * keep) // 2 * 2
    path = tmp_path / "cut.pssession"
    path.write_bytes(raw[:n])
    with pytest.raises(DataError) as info:
        ix.load(path)
    message = str(info.value)
    assert refusal in message and "cut.pssession" in message
    assert "as a file cut short does (copied before it was complete?): copy it again" in message
    if n % 2:
        assert f"its {n} bytes are an odd count" in message
    else:  # the column: the text's end, or where the string that never ends opens (the file's one line)
        text = raw[:n].decode("utf-16").lstrip("\ufeff")
        column = len(text) + 1 if "delimiter" in refusal else text.rindex('"') + 1
        assert f"line 1: not a PalmSens session: invalid JSON at column {column}: {refusal}; the JSON stops" in message
    assert main(["inspect", str(path)]) == 2
    capsys.readouterr()
    # JSON broken inside, with its end intact: invalid JSON, and no word of a cut
    text = raw.decode("utf-16").lstrip("\ufeff")
    at = text.index(",", len(text) // 2)
    path.write_bytes((text[:at] + "#" + text[at + 1:]).encode("utf-16"))
    with pytest.raises(DataError, match=rf"line 1: not a PalmSens session: invalid JSON at column {at + 1}: ") as info:
        ix.load(path)
    assert "cut short" not in str(info.value)
    # blank lines and spaces before the JSON: the line and column are still the file's
    path.write_bytes(("\n\n  " + text[:at] + "#" + text[at + 1:]).encode("utf-16"))
    with pytest.raises(DataError, match=rf"line 3: not a PalmSens session: invalid JSON at column {at + 3}: "):
        ix.load(path)


# --- a last row cut inside its LAST field keeps its field count: its digits say it was cut ------


def _gamry_vdc_last(cut_to: str | None = None) -> str:
    """A Gamry .DTA-like ZCURVE table whose last column is Vdc, written %.7g like Gamry's
    numbers (SYNTHETIC: -8.440604 V drifting by 1e-4 V per point, 7 significant digits on every
    row), with no line end after its last row; ``cut_to``: that row's Vdc as the cut left it."""
    head = ["EXPLAIN", "TAG\tEISPOT", "ZCURVE\tTABLE", "\tPt\tTime\tFreq\tZreal\tZimag\tVdc", "\t#\ts\tHz\tohm\tohm\tV"]
    rows = [f"\t{k}\t{2 * k}\t{f:.7g}\t{z.real:.7g}\t{z.imag:.7g}\t{-8.440604 - 1e-4 * k:.7g}" for k, (f, z) in enumerate(zip(FREQ, Z))]
    if cut_to is not None:
        rows[-1] = rows[-1].rsplit("\t", 1)[0] + "\t" + cut_to
    return "\r\n".join(head + rows)


def test_gamry_last_row_cut_inside_its_last_field_is_refused(tmp_path):
    path = tmp_path / "vdc.DTA"
    # control: no line end after the last row, but every digit there: read exactly
    path.write_text(_gamry_vdc_last(), encoding="latin-1")
    np.testing.assert_allclose(ix.load(path)["Z"].values, Z, rtol=1e-6)
    full = f"{-8.440604 - 1e-4 * 11:.7g}"
    assert full == "-8.441704"
    # cut after '-8.44': the same field count, 3 significant digits under rows of 7
    path.write_text(_gamry_vdc_last(cut_to=full[:5]), encoding="latin-1")
    message = _refused(path)
    assert "vdc.DTA" in message and "line 17:" in message
    assert "column 'Vdc': '-8.44' on the last row has 3 significant digits, every other row at least 7" in message
    assert CUT_SHORT in message
    # the same row with a line end after it: the file was not cut, so it is read as written
    path.write_text(_gamry_vdc_last(cut_to=full[:5]) + "\r\n", encoding="latin-1")
    np.testing.assert_allclose(ix.load(path)["Z"].values, Z, rtol=1e-6)


def test_cli_inspect_of_a_gamry_file_cut_inside_its_last_field_exits_2(tmp_path, capsys):
    path = tmp_path / "vdc.DTA"
    path.write_text(_gamry_vdc_last(cut_to="-8.4"), encoding="latin-1")
    assert main(["inspect", str(path)]) == 2
    err = capsys.readouterr().err
    assert "vdc.DTA" in err and "line 17" in err and "cut short" in err and "Traceback" not in err


# the layouts above whose last field is a measured number (not a constant such as a range or cycle)
_LAST_FIELD_MEASURED = ("biologic_text.txt", "chi.txt", "labone_table.csv", "nova.txt")


@pytest.mark.parametrize("name", _LAST_FIELD_MEASURED)
def test_a_last_row_cut_inside_its_last_field_says_the_file_looks_cut_short(tmp_path, name):
    head, cells, delimiter, _ = _CUT_LAYOUTS[name]
    rows = [cells(f, z, k) for k, (f, z) in enumerate(zip(FREQ, Z))]
    last_line = len(head) + len(rows)
    kept = rows[-1][-1][:4]  # (1.2345670E+01 cut to '1.23', -3.1877124E-02 to '-3.1': a number still, of 3 or 2 digits, not 10)
    digits = sum(c.isdigit() for c in kept)
    rows[-1] = rows[-1][:-1] + [kept]
    path = tmp_path / name
    path.write_text("\n".join(head + [delimiter.join(r) for r in rows]), encoding="utf-8")
    message = _refused(path)
    assert f"line {last_line}:" in message and name in message
    assert f"{kept!r} on the last row has {digits} significant digits, every other row at least 10" in message and CUT_SHORT in message
    # with a line end after it, the short value is what the file says: read as written
    path.write_text("\n".join(head + [delimiter.join(r) for r in rows]) + "\n", encoding="utf-8")
    assert ix.load(path)["Z"].size == FREQ.size


def test_an_ivium_table_cut_inside_its_last_frequency_says_so(tmp_path):
    # SYNTHETIC: the .idf table above, its last f (1.0000000E-01) cut to '1.00'
    head = ["Technique=Impedance", "Solarcell=false", "primary_data", "3", "12"]
    rows = [[_g(z.real), _g(z.imag), _g(f)] for f, z in zip(FREQ, Z)]
    rows[-1][-1] = rows[-1][-1][:4]
    path = tmp_path / "m.idf"
    path.write_text("\n".join(head + ["  ".join(r) for r in rows]), encoding="latin-1")
    message = _refused(path)
    assert "line 17:" in message and "column 'f': '1.00' on the last row has 3 significant digits" in message and CUT_SHORT in message


def test_a_labone_field_line_cut_inside_its_last_value_says_so(tmp_path):
    # SYNTHETIC: one line per field, the imagz line last, its last value cut to 4 characters
    head = ["chunk;timestamp;size;fieldname"]
    rows = [["0", "1", "12", name, *map(_g, values)] for name, values in (("frequency", FREQ), ("realz", Z.real), ("imagz", Z.imag))]
    rows[-1][-1] = rows[-1][-1][:4]
    path = tmp_path / "sweep.csv"
    path.write_text("\n".join(head + [";".join(r) for r in rows]), encoding="utf-8")
    message = _refused(path)
    assert "line 4:" in message and "column 'imagz'" in message and CUT_SHORT in message


def test_significant_digits_of_number_cells():
    from impedax.io._common import significant_digits

    cases = {"-8.440604": 7, "-8.44": 3, "0.00120": 3, "1.5E+03": 4, "1E-0": 2, "100000": 6, "0": 1, "0.0000000E+00": 10, '"3.25"': 3, "1,25": 3, "abc": None, "": None, "-": None}
    assert {cell: significant_digits(cell) for cell in cases} == cases


# --- inspect names the columns it read: sigma's, and every role's in --json "columns" --------


def _entry(column, unit, scale=1.0, negated=False):
    return {"column": column, "unit": unit, "scale": scale, "negated": negated}


def test_inspect_names_the_sigma_column_and_maps_each_column_to_its_role(tmp_path, capsys):
    # SYNTHETIC: the spectrum above in kHz and kOhm, -Z'' stored, sigma = 1 % of |Z| in Ohm
    sigma = 0.01 * np.abs(Z)
    rows = [f"{f / 1e3:.17g};{z.real / 1e3:.17g};{-z.imag / 1e3:.17g};{s:.17g}" for f, z, s in zip(FREQ, Z, sigma)]
    path = tmp_path / "kohm.csv"
    path.write_text("Frequency (kHz);Z' (kOhm);-Z'' (kOhm);sigma (Ohm)\n" + "\n".join(rows) + "\n", encoding="utf-8")
    ds = ix.load(path)
    np.testing.assert_allclose(ds["Z"].values, Z, rtol=1e-12)
    np.testing.assert_allclose(ds["sigma"].values, sigma, rtol=1e-12)
    assert main(["inspect", str(path)]) == 0
    text = capsys.readouterr().out
    assert f"sigma: a standard deviation of Z per point, {sigma.min():.3g}–{sigma.max():.3g} Ω, from column 'sigma (Ohm)' (" in text
    assert main(["inspect", str(path), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["columns"] == {
        "frequency": _entry("Frequency (kHz)", "kHz", 1000.0),
        "z_real": _entry("Z' (kOhm)", "kOhm", 1000.0),
        "z_imag": _entry("-Z'' (kOhm)", "kOhm", 1000.0, negated=True),
        "sigma": _entry("sigma (Ohm)", "Ohm"),
    }
    # the free-text key stays as it was (JSON keys are a public contract)
    assert summary["units"] == "columns used (scaled to Hz, Ω, degrees): 'Frequency (kHz)' ×1000, \"Z' (kOhm)\" ×1000, \"-Z'' (kOhm)\" ×1000"
    # a netCDF file saved from it keeps the record of the columns its data were first read from
    saved = tmp_path / "kohm.nc"
    ix.save(ds, saved)
    assert main(["inspect", str(saved), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["columns"] == summary["columns"]


def test_inspect_columns_of_an_instrument_file_polar_columns_and_omega(tmp_path, capsys):
    # Gamry: names from its column row, units from its units row
    path = tmp_path / "g.DTA"
    path.write_text(_gamry(_gamry_rows()), encoding="latin-1")
    assert main(["inspect", str(path), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["columns"] == {"frequency": _entry("Freq", "Hz"), "z_real": _entry("Zreal", "ohm"), "z_imag": _entry("Zimag", "ohm")}
    assert not summary["has_sigma"] and "sigma" not in capsys.readouterr().out
    # SYNTHETIC: |Z| with -phase in radians beside an angular frequency in rad/s; no sigma column
    omega = 2 * np.pi * FREQ
    rows = [f"{w:.17g},{abs(z):.17g},{-np.angle(z):.17g}" for w, z in zip(omega, Z)]
    path = tmp_path / "polar.csv"
    path.write_text("omega (rad/s),|Z| (Ohm),-phase (rad)\n" + "\n".join(rows) + "\n", encoding="utf-8")
    np.testing.assert_allclose(ix.load(path)["Z"].values, Z, rtol=1e-12)
    assert main(["inspect", str(path), "--json"]) == 0
    columns = json.loads(capsys.readouterr().out)["columns"]
    assert columns == {
        "frequency": _entry("omega (rad/s)", "rad/s", pytest.approx(1 / (2 * np.pi), rel=1e-15)),
        "z_modulus": _entry("|Z| (Ohm)", "Ohm"),
        "z_phase": _entry("-phase (rad)", "rad", pytest.approx(180 / np.pi, rel=1e-15), negated=True),
    }
    assert main(["inspect", str(path)]) == 0
    assert "sigma" not in capsys.readouterr().out


def test_biologic_records_its_negated_imaginary_column(tmp_path):
    head, cells, delimiter, _ = _CUT_LAYOUTS["biologic.mpt"]
    path = tmp_path / "b.mpt"
    path.write_text("\n".join(head + [delimiter.join(cells(f, z, k)) for k, (f, z) in enumerate(zip(FREQ, Z))]) + "\n", encoding="utf-8")
    ds = ix.load(path)
    np.testing.assert_allclose(ds["Z"].values, Z, rtol=1e-6)
    assert ds.attrs["columns"] == {"frequency": _entry("freq/Hz", "Hz"), "z_real": _entry("Re(Z)/Ohm", "Ohm"),
                                   "z_imag": _entry("-Im(Z)/Ohm", "Ohm", negated=True)}
