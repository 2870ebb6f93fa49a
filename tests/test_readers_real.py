"""Real instrument files (tests/fixtures/real/, from AutoEIS 0.0.44 and impedance.py 1.7.1, MIT;
licence notices beside them) read exactly as the reference says.

Oracles, written independently of impedax's readers:
* impedance.py 1.7.1: its test module's arrays and what its ``readFile`` returns, stored in
  ``impedance_py_reference.npz`` (regenerate with ``make_reference.py``); compared live when
  impedance.py is installed.
* the pyimpspec-format set (``data.*``): pyimpspec's documented test circuit
  ``R{R=100}(R{R=200}C{C=8e-7})(R{R=500}W{Y=4e-4})`` at 29 frequencies 10 kHz … 1 Hz (7 per
  decade), evaluated below with numpy.
* where impedance.py is wrong or silent, a direct numpy parse of the file.
"""

import importlib.util
import shutil
from pathlib import Path

import numpy as np
import pytest

import impedax as ix

REAL = Path(__file__).parent / "fixtures" / "real"
REFERENCE = np.load(REAL / "impedance_py_reference.npz")

IMPEDANCE_PY_FILES = {
    "gamry": ("exampleDataGamry.DTA", "Gamry DTA"),
    "autolab": ("exampleDataAutolab.txt", "Autolab FRA Z60W"),
    "parstat": ("exampleDataParstat.txt", "Parstat text"),
    "zplot": ("exampleDataZPlot.z", "Scribner ZPlot z"),
    "versastudio": ("exampleDataVersaStudio.par", "VersaStudio par"),
    "powersuite": ("exampleDataPowersuite.txt", "PowerSuite text"),
    "biologic": ("exampleDataBioLogic.mpt", "BioLogic EC-Lab mpt"),
    "chinstruments": ("exampleDataCHInstruments.txt", "CH Instruments text"),
    "csv": ("exampleData.csv", "delimited text"),
}


@pytest.mark.parametrize("instrument", sorted(IMPEDANCE_PY_FILES))
def test_reads_exactly_the_points_impedance_py_reads(instrument):
    name, fmt = IMPEDANCE_PY_FILES[instrument]
    ds = ix.load(REAL / name)
    assert ds.attrs["format"] == fmt
    f, z = ds["frequency"].values, ds["Z"].values
    # bit-for-bit what impedance.py's readFile returns (same points, same order, same sign) ...
    np.testing.assert_array_equal(f, REFERENCE[f"{instrument}_readFile_f"])
    np.testing.assert_array_equal(z, REFERENCE[f"{instrument}_readFile_Z"])
    # ... and its test module's hand-written arrays (typed with 7 significant digits)
    np.testing.assert_allclose(f, REFERENCE[f"{instrument}_test_f"], rtol=1e-6)
    np.testing.assert_allclose(z, REFERENCE[f"{instrument}_test_Z"], rtol=1e-6, atol=1e-12)
    assert ds.attrs["sign_convention"] and ds.attrs["units"]


@pytest.mark.skipif(importlib.util.find_spec("impedance") is None, reason="impedance.py not installed")
@pytest.mark.parametrize("instrument", sorted(IMPEDANCE_PY_FILES))
def test_against_impedance_py_live(instrument):
    from impedance.preprocessing import readFile

    name, _ = IMPEDANCE_PY_FILES[instrument]
    f_ref, z_ref = readFile(str(REAL / name), None if instrument == "csv" else instrument)
    ds = ix.load(REAL / name)
    np.testing.assert_array_equal(ds["frequency"].values, f_ref)
    np.testing.assert_array_equal(ds["Z"].values, z_ref)


def test_parstat_dc_rows_are_skipped_and_reported():
    """impedance.py drops the 781 DC rows (f = 0) of this file without a word; impedax reports them."""
    ds = ix.load(REAL / "exampleDataParstat.txt")
    assert ds.attrs["skipped_rows"] == ["lines 2–782: f = 0 (DC row, not an impedance point)"]
    text = (REAL / "exampleDataParstat.txt").read_text().splitlines()
    dc = [k + 1 for k, ln in enumerate(text[1:], start=1) if float(ln.split("\t")[3]) == 0]
    assert dc == list(range(2, 783))
    assert ds.sizes["frequency"] == len(text) - 1 - len(dc)


def test_biologic_text_export_where_impedance_py_crashes():
    """``test_data.txt`` is EC-Lab's bare column export. impedance.py is wrong here: readBioLogic
    crashes (it expects 'Nb header lines' on line 2) and so does readFile's default CSV reader
    (comma-separated only). Oracle: numpy's own parse of the tab-separated columns, with -Im(Z) negated."""
    ds = ix.load(REAL / "test_data.txt")
    assert ds.attrs["format"] == "BioLogic EC-Lab text"
    table = np.loadtxt(REAL / "test_data.txt", delimiter="\t", skiprows=1)
    np.testing.assert_array_equal(ds["frequency"].values, table[:, 0])
    np.testing.assert_array_equal(ds["Z"].values, table[:, 1] - 1j * table[:, 2])
    # the file's own |Z| and phase columns agree with the sign chosen
    np.testing.assert_allclose(np.abs(ds["Z"].values), table[:, 3], rtol=1e-6)
    np.testing.assert_allclose(np.degrees(np.angle(ds["Z"].values)), table[:, 4], atol=1e-5)
    np.testing.assert_array_equal(ds["time"].values, table[:, 5])
    if importlib.util.find_spec("impedance") is not None:
        from impedance.preprocessing import readBioLogic, readFile

        for read in (readBioLogic, readFile):
            with pytest.raises((ValueError, IndexError)):
                read(str(REAL / "test_data.txt"))


def test_versastudio_z_is_the_files_own_e_over_i():
    ds = ix.load(REAL / "exampleDataVersaStudio.par")
    lines = (REAL / "exampleDataVersaStudio.par").read_text().splitlines()
    start = lines.index("<Segment1>")
    rows = np.array([[float(c) for c in ln.split(",")] for ln in lines[start + 4 : lines.index("</Segment1>")]])
    e = rows[:, 10] + 1j * rows[:, 11]
    i = rows[:, 12] + 1j * rows[:, 13]
    np.testing.assert_allclose(ds["Z"].values, e / i, rtol=2e-5)  # the file rounds Z to 7 digits


def test_headerless_csv_says_how_it_was_read():
    ds = ix.load(REAL / "exampleData.csv")
    assert "no header" in ds.attrs["interpretation"] and "Z''" in ds.attrs["interpretation"]


def test_zplot_point_count_mismatch_is_reported():
    ds = ix.load(REAL / "exampleDataZPlot.z")
    assert ds.sizes["frequency"] == 21
    assert "Data Points: 56" in ds.attrs["point_count_note"]


# --- the pyimpspec-format set ---------------------------------------------------------------


def pyimpspec_circuit(f):
    """R{R=100}(R{R=200}C{C=8e-7})(R{R=500}W{Y=4e-4}): Z_W = 1/(Y·sqrt(jω))."""
    s = 2j * np.pi * f
    z_rc = 200 / (1 + 200 * 8e-7 * s)
    z_w = 1 / (4e-4 * np.sqrt(s))
    return 100 + z_rc + 500 * z_w / (500 + z_w)


PYIMPSPEC_F = 10 ** np.linspace(4, 0, 29)


@pytest.mark.parametrize(
    "name, fmt, dim, count, rtol",
    [
        ("data.dfr", "Autolab FRA dfr", None, 1, 1e-12),
        ("data.idf", "IviumSoft idf/ids", None, 1, 1e-5),  # 6 significant digits in the file
        ("data.ids", "IviumSoft idf/ids", "measurement", 2, 1e-5),
        ("data.pssession", "PalmSens pssession", None, 1, 1e-12),
        ("data.xlsx", "spreadsheet", "sheet", 4, 1e-12),
        ("data.ods", "spreadsheet", "sheet", 4, 1e-12),
    ],
)
def test_pyimpspec_formats_match_the_circuit(name, fmt, dim, count, rtol):
    if name.endswith(".xlsx"):
        pytest.importorskip("openpyxl")
    if name.endswith(".ods"):
        pytest.importorskip("odf")
    ds = ix.load(REAL / name)
    assert ds.attrs["format"] == fmt
    np.testing.assert_allclose(ds["frequency"].values, PYIMPSPEC_F, rtol=rtol)
    z = ds["Z"].values.reshape(count, -1)
    if dim is not None:
        assert ds["Z"].dims == (dim, "frequency")
    for row in z:
        np.testing.assert_allclose(row, pyimpspec_circuit(PYIMPSPEC_F), rtol=rtol)
    assert np.all(z.imag < 0)  # capacitive whatever sign the file stored


def test_spreadsheet_sheets_use_four_header_conventions():
    pytest.importorskip("openpyxl")
    ds = ix.load(REAL / "data.xlsx")
    assert list(ds["sheet"].values) == [f"header-variant-{k}" for k in (1, 2, 3, 4)]
    conventions = ds.attrs["sign_convention"]
    assert "'-Zim' holds -Z''" in conventions and "-phase" in conventions


@pytest.mark.parametrize("name", sorted(p.name for p in REAL.iterdir() if p.suffix not in (".npz", ".py", ".md", ".json") and not p.name.startswith("LICENSE")))
def test_every_real_file_loads_under_another_name(tmp_path, name):
    """Content, not the extension, decides the format."""
    if name.endswith(".xlsx"):
        pytest.importorskip("openpyxl")
    if name.endswith(".ods"):
        pytest.importorskip("odf")
    fmt = ix.load(REAL / name).attrs["format"]
    shutil.copy(REAL / name, tmp_path / "renamed.dat")
    assert ix.load(tmp_path / "renamed.dat").attrs["format"] == fmt


# --- impedax inspect ------------------------------------------------------------------------


def test_inspect_says_what_was_read_and_how(capsys, tmp_path):
    from impedax.cli import main

    assert main(["inspect", str(REAL / "exampleDataParstat.txt"), "--plot", str(tmp_path / "preview.png")]) == 0
    out = capsys.readouterr().out
    assert "Parstat text, 31 frequencies" in out
    assert "sign convention: column 'Zim (ohms)' holds Z''" in out
    assert "'Frequency (Hz)', 'Zre (ohms)', 'Zim (ohms)'" in out
    assert "lines 2–782: f = 0 (DC row, not an impedance point)" in out
    assert (tmp_path / "preview.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_inspect_json_reports_interpretation_and_skipped_rows(capsys):
    import json

    from impedax.cli import main

    assert main(["inspect", str(REAL / "exampleData.csv"), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["format"] == "delimited text" and report["points"] == 66 and report["skipped_rows"] == []
    assert report["attrs"]["interpretation"].startswith("no header: columns read as frequency [Hz], Z' [Ω], Z'' [Ω]")
    assert main(["inspect", str(REAL / "data.ids"), "--json", "--plot", "/nonexistent-dir/x.png"]) == 2  # refused before reading


def test_palmsens_sign_agrees_with_the_files_own_admittance_and_phase():
    """The session also stores Y = 1/Z and the phase: ZIm = −Z'' is the only reading that agrees."""
    import json

    text = (REAL / "data.pssession").read_bytes().decode("utf-16").strip("\ufeff")
    session, _ = json.JSONDecoder().raw_decode(text)
    arrays = {v["Description"]: np.array([p["V"] for p in v["DataValues"]]) for v in session["Measurements"][0]["DataSet"]["Values"]}
    z = ix.load(REAL / "data.pssession")["Z"].values
    np.testing.assert_allclose(1 / z, arrays["YRe"] + 1j * arrays["YIm"], rtol=1e-12)
    np.testing.assert_allclose(np.degrees(np.angle(z)), -arrays["Phase"], rtol=1e-12)
    np.testing.assert_allclose(np.abs(z), arrays["Z"], rtol=1e-12)


def test_zplot_without_metadata_header(tmp_path):
    """The ZPlot variant that starts with the column names (impedance.py's ``_noComments`` case),
    hand-made from the pyimpspec circuit."""
    z = pyimpspec_circuit(PYIMPSPEC_F)
    rows = ["Freq(Hz)\tAmpl\tBias\tTime(Sec)\tZ'(a)\tZ''(b)\tGD\tErr\tRange"]
    rows += [f"{f:.6E}\t1.0000E-02\t0.0000E+00\t{k:.6E}\t{zi.real:.6E}\t{zi.imag:.6E}\t0.0000E+00\t0\t3" for k, (f, zi) in enumerate(zip(PYIMPSPEC_F, z))]
    path = tmp_path / "nocomments.z"
    path.write_text("\n".join(rows) + "\n")
    ds = ix.load(path)
    assert ds.attrs["format"] == "Scribner ZPlot z"
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-6)
    np.testing.assert_array_equal(ds["time"].values, np.arange(29.0))


def test_gamry_header_numbers_are_numbers():
    """The DTA header's QUANT/POTEN values, read as the numbers the file writes (they were kept
    as text, "-5.00000E-002"): lines 10–15 of the file, VDC −0.05 V, VAC 10 mV rms, area 1 cm²,
    the sweep from 200 kHz to 20 mHz; the title stays text."""
    attrs = ix.load(REAL / "exampleDataGamry.DTA").attrs
    assert attrs["dc_voltage_v"] == -0.05 and attrs["ac_voltage_mv_rms"] == 10.0 and attrs["area_cm2"] == 1.0
    assert (attrs["initial_frequency_hz"], attrs["final_frequency_hz"]) == (2e5, 0.02)
    assert isinstance(attrs["title"], str)


@pytest.mark.parametrize("name", ["data.xlsx", "data.ods"])
@pytest.mark.parametrize("kept", [0.4, 0.999])
def test_a_spreadsheet_cut_short_says_so(tmp_path, name, kept):
    """The REAL workbooks cut short (the first 40 %, or all but their last bytes): a zip ends with
    its directory (the 'PK\\x05\\x06' record, 22 bytes from the end of data.xlsx), which a cut
    file lacks, so the refusal names the cut as the likely cause. A whole file damaged inside
    keeps its directory and is refused without that note."""
    raw = (REAL / name).read_bytes()
    assert raw.rfind(b"PK\x05\x06") == len(raw) - 22  # the file's own layout: the directory ends it
    cut = tmp_path / name
    cut.write_bytes(raw[: int(len(raw) * kept)])
    with pytest.raises(ix.DataError) as info:
        ix.load(cut)
    message = str(info.value)
    assert "not a readable spreadsheet" in message and "cut short" in message and "copy it again" in message
    pytest.importorskip("openpyxl" if name.endswith(".xlsx") else "odf")
    damaged = bytearray(raw)
    damaged[2000:2400] = b"x" * 400
    (tmp_path / f"damaged{cut.suffix}").write_bytes(bytes(damaged))
    with pytest.raises(ix.DataError) as info:
        ix.load(tmp_path / f"damaged{cut.suffix}")
    assert "cut short" not in str(info.value)


def test_files_without_column_names_say_which_position_holds_what_in_which_unit():
    """REAL data.idf (Ivium) and data.dfr (Autolab FRA) name no columns; their `units` said
    "ohm, ohm, Hz" and "Hz, ohm" (walkthrough 2026-12-06), which `impedax inspect` printed
    without saying which value was which. The files' own layout, parsed here: Ivium's rows are
    Z', Z'', f (the first row ends in 1.00000E+04, the highest frequency); a FRA record is f,
    Z', −Z'' (its first record starts 10000.0)."""
    ivium_lines = (REAL / "data.idf").read_bytes().decode("latin-1").splitlines()
    first_row = ivium_lines[ivium_lines.index(next(line for line in ivium_lines if line.startswith("primary_data"))) + 3].split()
    assert float(first_row[2]) == 1e4 and float(first_row[1]) < 0
    assert ix.load(REAL / "data.idf").attrs["units"] == "column 1 (Z') and column 2 (Z'') in ohm, column 3 (f) in Hz"
    fra_lines = (REAL / "data.dfr").read_text().splitlines()
    assert float(fra_lines[3]) == 1e4 and float(fra_lines[5]) > 0  # f, then Z', then −Z'' (positive for this capacitive point)
    assert ix.load(REAL / "data.dfr").attrs["units"] == "record line 1 (f) in Hz, lines 2 (Z') and 3 (-Z'') in ohm"
