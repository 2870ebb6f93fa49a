"""Instrument readers: hand-made fixtures in each format's real layout (tests/fixtures/).

Every fixture holds the same synthetic spectrum, Z = 100 + 1000/(1 + j·2πf·1 ms) Ω at
1e5 ... 1 Hz, written with each file's own precision, sign convention and decimal mark; the
oracle below is that formula, written here independently of the files.
"""

import re
import shutil
import sys
import types
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.io import READERS, Reader, register_reader
from loading import assert_load_names

FIXTURES = Path(__file__).parent / "fixtures"


def oracle(f):
    return 100 + 1000 / (1 + 1j * 2 * np.pi * np.asarray(f) * 1e-3)


DESCENDING = np.array([1e5, 1e4, 1e3, 100.0, 10.0, 1.0])


@pytest.mark.parametrize(
    "name, fmt, rtol, attrs",
    [
        ("gamry_eispot.DTA", "Gamry DTA", 1e-6, {"instrument": "Gamry", "date": "2024-03-14T10:29:09", "date_as_written": "3/14/2024 10:29:09", "instrument_serial": "REF600-12345", "experiment": "EISPOT"}),
        ("biologic_peis.mpt", "BioLogic EC-Lab mpt", 1e-6, {"instrument": "BioLogic SP-150 (SN 10791079)", "date": "02/04/2024 10:02:46", "technique": "Potentio Electrochemical Impedance Spectroscopy"}),
        ("zplot_sweep.z", "Scribner ZPlot z", 1e-4, {"instrument": "Scribner ZPlot", "date": "10-12-2024 11:04:34", "experiment": "Sweep Frequency, Control Voltage"}),
        ("autolab_nova.txt", "Metrohm Autolab NOVA text", 1e-8, {"instrument": "Metrohm Autolab"}),
    ],
)
def test_instrument_file_matches_formula(name, fmt, rtol, attrs):
    ds = ix.load(FIXTURES / name)
    assert ds.attrs["format"] == fmt
    np.testing.assert_allclose(ds["frequency"].values, DESCENDING, rtol=1e-6)  # order kept, in Hz
    z = ds["Z"].values
    np.testing.assert_allclose(z, oracle(DESCENDING), rtol=rtol)
    assert np.all(z.imag < 0)  # capacitive: Z'' < 0 whatever the file stored
    for key, value in attrs.items():
        assert ds.attrs[key] == value
    np.testing.assert_allclose(ds["time"].values, np.arange(1, 7) * 2.5)


def test_biologic_comments_and_gamry_notes_are_kept():
    assert ix.load(FIXTURES / "biologic_peis.mpt").attrs["comments"] == "synthetic test file for impedax"
    assert ix.load(FIXTURES / "gamry_eispot.DTA").attrs["comments"] == "synthetic test file for impedax\nR0 + R1 || C1"


def test_labone_sweeps_become_a_dimension():
    ds = ix.load(FIXTURES / "dev3000_imps_0_sample_00000.csv")
    assert ds["Z"].dims == ("sweep", "frequency") and list(ds["sweep"].values) == ["0", "1"]
    np.testing.assert_allclose(ds["frequency"].values, DESCENDING[::-1])
    np.testing.assert_allclose(ds["Z"].values[0], oracle(DESCENDING[::-1]), rtol=1e-9)
    np.testing.assert_allclose(ds["Z"].values[1], 1.01 * oracle(DESCENDING[::-1]), rtol=1e-9)
    assert ds.attrs["device"] == "dev3000" and ds.attrs["instrument"].startswith("Zurich Instruments")


def test_labone_table_layout_and_polar_fields(tmp_path):
    f = np.array([10.0, 100.0, 1000.0])
    z = oracle(f)
    rows = ["timestamp;frequency;absz;phasez"] + [f"{i};{float(fi)!r};{float(abs(zi))!r};{float(np.angle(zi))!r}" for i, (fi, zi) in enumerate(zip(f, z))]
    path = tmp_path / "sweep.csv"
    path.write_text("\n".join(rows) + "\n")
    ds = ix.load(path)
    assert ds.attrs["format"] == "Zurich Instruments LabOne CSV"
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-12)


def test_content_wins_over_extension(tmp_path):
    """A BioLogic export renamed .txt, and a ZPlot file renamed .dat, are still recognised."""
    for name, new, fmt in (("biologic_peis.mpt", "export.txt", "BioLogic EC-Lab mpt"), ("zplot_sweep.z", "zplot.dat", "Scribner ZPlot z")):
        shutil.copy(FIXTURES / name, tmp_path / new)
        assert ix.load(tmp_path / new).attrs["format"] == fmt


def test_plain_csv_still_read_as_before(tmp_path):
    path = tmp_path / "plain.csv"
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n1,2,-3\n10,2,-0.3\n")
    ds = ix.load(path)
    assert ds.attrs["format"] == "delimited text"
    np.testing.assert_array_equal(ds["Z"].values, [2 - 3j, 2 - 0.3j])


def _corrupt(name, old, new):
    text = (FIXTURES / name).read_bytes().decode("latin-1")
    assert old in text
    return text.replace(old, new, 1)


@pytest.mark.parametrize(
    "name, old, new, fragment, line",
    [
        ("gamry_eispot.DTA", "ZCURVE\tTABLE", "ZCURVE_GONE\tTABLE", "no ZCURVE table", None),
        ("gamry_eispot.DTA", "\tFreq\t", "\tFrequency\t", "lacks column(s) ['Freq']", 22),
        ("gamry_eispot.DTA", "\t1000\t", "\t-1000\t", "frequency must be positive", 26),
        ("gamry_eispot.DTA", "\t1000\t", "\t100000\t", "duplicate frequency 100000 Hz (also on line 24)", 26),
        ("biologic_peis.mpt", "Nb header lines : 19", "Nb header lines : 99", "does not fit", 2),
        ("biologic_peis.mpt", "-Im(Z)/Ohm", "Im(Z)/Ohm", "['-Im(Z)/Ohm'] not found", 19),
        ("zplot_sweep.z", "End Comments", "End Of Header", "no 'End Comments' line", None),
        ("zplot_sweep.z", "1.000000E+03", "nan", "NaN/Inf", 19),
        ("autolab_nova.txt", "3;1000;", "3;abc;", "'abc' is not a number", 4),
        ("dev3000_imps_0_sample_00000.csv", ";frequency;1.0000000000e+00;", ";frequency;", "point 5: frequency missing", 3),
    ],
)
def test_broken_instrument_files_name_file_and_line(tmp_path, name, old, new, fragment, line):
    path = tmp_path / name
    path.write_bytes(_corrupt(name, old, new).encode("latin-1"))
    assert_load_names(path, fragment, None if line is None else f"{line}:")


def test_unrecognised_file_counts_the_formats_tried(tmp_path):
    path = tmp_path / "mystery.txt"
    path.write_text("voltage,current\n1,2\n")
    with pytest.raises(ix.DataError) as info:
        ix.load(path)
    msg = str(info.value)
    # why the text is not a table first (the reason a user of a text table needs), then a count,
    # not each format's reason (twenty of them buried that sentence: ~2,000 characters)
    assert msg.endswith(
        "not a recognised spectrum file: as delimited text, no frequency column in header ['voltage', 'current']; "
        f"{len(READERS)} other formats tried (each one's reason: impedax.io.identify; the formats: docs/io.md)"
    ) and "\n" not in msg
    assert not any(reader.name + ": " in msg for reader in READERS)
    # identify gives each reader's reason, as the message says
    reader, tried = ix.io.identify(path)
    assert reader is None and [t.split(": ")[0] for t in tried] == [r.name for r in READERS]


def test_a_missing_impedance_column_is_one_short_message(tmp_path, capsys):
    """A CSV with frequency and Re Z but no Im Z (a researcher's file): the one useful sentence, under 400 characters."""
    from impedax.cli import main

    path = tmp_path / "missing_col.csv"
    path.write_text("frequency_hz,z_real_ohm\n1,100\n10,90\n")
    assert main(["fit", str(path), "--model", "R1"]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "cannot find impedance columns in header ['frequency_hz', 'z_real_ohm']; expected Z' and Z'' (or -Z''), or |Z| and phase" in line
    assert f"; {len(READERS)} other formats tried" in line and len(line) - len(str(path)) < 300

def test_hdf5_without_h5py_says_how_to_get_it(tmp_path, monkeypatch):
    path = tmp_path / "sweep.h5"
    path.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(200))
    monkeypatch.setitem(sys.modules, "h5py", None)  # import h5py now raises ImportError
    with pytest.raises(ix.DataError, match=r"pip install h5py"):
        ix.load(path)


LABONE_F = np.geomspace(1, 1e5, 7)


def _labone_h5(path, sweeps, grid=False):
    """A LabOne HDF5 file with one sample group per spectrum in ``sweeps`` (on LABONE_F)."""
    h5py = pytest.importorskip("h5py")
    with h5py.File(path, "w") as fh:
        for k, z in enumerate(sweeps):
            g = fh.create_group(f"00{k}/dev3000/imps/0/sample")
            g["frequency"], g["realz"], g["imagz"] = LABONE_F, z.real, z.imag
            if grid:
                g["grid"] = LABONE_F
    return path


def test_labone_hdf5_with_h5py(tmp_path):
    z = oracle(LABONE_F)
    ds = ix.load(_labone_h5(tmp_path / "sweep.h5", [z], grid=True))
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-15)
    assert ds.attrs["hdf5_group"] == "000/dev3000/imps/0/sample"


# --- units, separators, decimal marks ---------------------------------------------------------

F_HZ = np.array([1e4, 1e3, 10.0, 0.1])


def _write_table(path, header, freq_values, z, sep=",", comma=False, neg=False):
    lines = [sep.join(header)]
    for f, zi in zip(freq_values, z):
        cells = [repr(float(f)), repr(float(zi.real)), repr(float(-zi.imag if neg else zi.imag))]
        if comma:
            cells = [c.replace(".", ",") for c in cells]
        lines.append(sep.join(cells))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "freq_header, freq_scale",
    [("Frequency (Hz)", 1.0), ("Frequency (mHz)", 1e-3), ("Frequency (kHz)", 1e3), ("Frequency (MHz)", 1e6), ("freq/mHz", 1e-3), ("f [KHz]", 1e3)],
)
@pytest.mark.parametrize("z_unit, z_scale", [("Ω", 1.0), ("mΩ", 1e-3), ("kΩ", 1e3), ("MΩ", 1e6), ("mOhm", 1e-3), ("kohm", 1e3)])
def test_unit_prefixes_are_case_sensitive(tmp_path, freq_header, freq_scale, z_unit, z_scale):
    """mHz is 1e-3 Hz and MHz 1e6 Hz: the old reader lower-cased units and read mHz as MHz."""
    z = oracle(F_HZ)
    path = _write_table(tmp_path / "units.csv", [freq_header, f"Z' ({z_unit})", f"Z'' ({z_unit})"], F_HZ / freq_scale, z / z_scale)
    ds = ix.load(path)
    np.testing.assert_allclose(ds["frequency"].values, F_HZ, rtol=1e-14)
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-14)


@pytest.mark.parametrize("header", ["Frequency (MHZ)", "Frequency (xHz)"])
def test_ambiguous_or_unknown_units_are_errors(tmp_path, header):
    path = _write_table(tmp_path / "u.csv", [header, "Z'", "Z''"], F_HZ, oracle(F_HZ))
    with pytest.raises(ix.DataError, match=r"line 1: column 'Frequency \(.*\)': .*(ambiguous|not understood)"):
        ix.load(path)


@pytest.mark.parametrize(
    "sep, comma, header",
    [(";", True, ["freq", "Zreal", "Zimag"]), ("\t", True, ["freq", "Zreal", "Zimag"]), (" ", False, ["freq", "Zreal", "Zimag"]), ("\t", False, None), (";", True, None)],
)
def test_separators_and_decimal_commas(tmp_path, sep, comma, header):
    z = oracle(F_HZ)
    path = tmp_path / "s.txt"
    _write_table(path, header or [], F_HZ, z, sep=sep, comma=comma)
    if header is None:  # no header line at all: 3 columns read as f, Z', Z'' with a note
        path.write_text("\n".join(path.read_text().splitlines()[1:]) + "\n")
    ds = ix.load(path)
    np.testing.assert_allclose(ds["frequency"].values, F_HZ, rtol=1e-15)
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-15)
    assert ("interpretation" in ds.attrs) == (header is None)


@pytest.mark.parametrize(
    "rows, at",
    [
        # a European export with '.' thousands in the frequency: 1.259 meant 1259 Hz, read as 1.259
        (["1.000;108,080;-7,924", "1.259;107,473;-9,660"], "'1.000' has a '.'"),
        # a US export with ',' thousands and '.' decimals: '1,000' made every comma a decimal mark
        (["1,000;108.080;-7.924", "1,259;107.473;-9.660"], "'108.080' has a '.'"),
    ],
)
def test_thousands_separators_are_refused_not_read_as_decimals(tmp_path, rows, at):
    """Before, both files read as 1–1.259 Hz (a thousandth of the truth) and fitted without a
    word; now one message names the line, column and cell, exit 2 in the CLI."""
    path = tmp_path / "t.csv"
    path.write_text("Frequency (Hz);Z' (Ohm);Z'' (Ohm)\n" + "\n".join(rows) + "\n")
    with pytest.raises(ix.DataError, match=rf"line 2: column .*: {re.escape(at)}, and other numbers of this file a ','") as err:
        ix.load(path)
    assert "thousands separator" in str(err.value)
    from impedax.cli import main

    assert main(["inspect", str(path)]) == 2


def test_polar_columns_with_negated_phase_and_radians(tmp_path):
    z = oracle(F_HZ)
    rows = ["frequency,|Z|,-phase"] + [f"{f!r},{abs(zi)!r},{float(-np.degrees(np.angle(zi)))!r}" for f, zi in zip(F_HZ.tolist(), z.tolist())]
    (tmp_path / "p.csv").write_text("\n".join(rows) + "\n")
    np.testing.assert_allclose(ix.load(tmp_path / "p.csv")["Z"].values, z, rtol=1e-13)
    rows = ["frequency,|Z|,phase (rad)"] + [f"{f!r},{abs(zi)!r},{float(np.angle(zi))!r}" for f, zi in zip(F_HZ.tolist(), z.tolist())]
    (tmp_path / "r.csv").write_text("\n".join(rows) + "\n")
    np.testing.assert_allclose(ix.load(tmp_path / "r.csv")["Z"].values, z, rtol=1e-13)


@pytest.mark.parametrize(
    "header, polar, neg, scale",
    [
        ("frequency_Hz,ReZ_Ohm,ImZ_Ohm", False, False, 1.0),  # unit suffixes after any role name
        ("Freq,Re,Im", False, False, 1.0),
        ("Frequency (Hz),Real(Z) (kOhm),Imag(Z) (kOhm)", False, False, 1e3),
        ("f,R,X", False, False, 1.0),  # an LCR meter's R-X mode: Z = R + jX
        ("Freq [Hz],Rs [Ohm],-Xs [Ohm]", False, True, 1.0),
        ("Frequency/Hz\tImpedance/Ohm\tPhase/deg", True, False, 1.0),  # |Z| named 'Impedance'
        ("Freq(Hz),|Z|(Ω),θ(°)", True, False, 1.0),
        ("Freq(Hz),|Z|(Ohm),theta-z(deg)", True, False, 1.0),  # a Keysight LCR meter's export: inner hyphens do not count
        ("Frequency,Impedance Magnitude (Ohm),Phase Angle (deg)", True, False, 1.0),
        ("frequency,Z_Magnitude_Ohm,-Z_Phase_Deg", True, True, 1.0),
    ],
)
def test_column_names_of_other_software(tmp_path, header, polar, neg, scale):
    z = oracle(F_HZ)
    sep = "\t" if "\t" in header else ","
    if polar:
        sign = -1 if neg else 1
        rows = [sep.join(repr(float(v)) for v in (f, abs(zi) / scale, sign * np.degrees(np.angle(zi)))) for f, zi in zip(F_HZ, z)]
    else:
        rows = [sep.join(repr(float(v)) for v in (f, zi.real / scale, (-zi.imag if neg else zi.imag) / scale)) for f, zi in zip(F_HZ, z)]
    path = tmp_path / "other.csv"
    path.write_text("\n".join([header, *rows]) + "\n", encoding="utf-8")
    ds = ix.load(path)
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-13)
    assert "phase_unit_note" not in ds.attrs


def test_a_phase_without_unit_that_looks_like_radians_is_noted(tmp_path, capsys):
    """Radians without a unit beside a |Z| that falls 10.8× (the arc of `oracle`): phases within
    ±0.894 read as degrees would let |Z| change at most e^((2/π)·0.894·π/180·ln 1e5) = 1.12×
    (Bode's gain–phase relation), so the file is refused (until 2026-12-01 it was read in degrees
    with a note). A nearly resistive sample with the same small values and a flat |Z| keeps the
    note; a unit, or values beyond ±π/2, say what they are."""
    from impedax.cli import main

    z = oracle(F_HZ)
    for name, unit, phase in [("rad.csv", "", np.angle(z)), ("radu.csv", " (rad)", np.angle(z)), ("deg.csv", "", np.degrees(np.angle(z)))]:
        rows = [f"{f!r},{abs(zi)!r},{p!r}" for f, zi, p in zip(F_HZ.tolist(), z.tolist(), phase.tolist())]
        (tmp_path / name).write_text("\n".join([f"frequency,|Z|,phase{unit}", *rows]) + "\n")
    with pytest.raises(ix.DataError, match=r"column 'phase' has no unit, and its values .* cannot be degrees: .* within about 1\.12× .* changes 10\.8×.*'phase \(rad\)'"):
        ix.load(tmp_path / "rad.csv")
    assert main(["fit", str(tmp_path / "rad.csv"), "--model", "R0 + R1 || C1"]) == 2
    capsys.readouterr()
    assert "phase_unit_note" not in ix.load(tmp_path / "radu.csv").attrs  # the unit says radians
    assert "phase_unit_note" not in ix.load(tmp_path / "deg.csv").attrs  # up to 84°: degrees
    # nearly resistive: phases of −0.3…−1.2 with |Z| within 0.2 %, degrees as likely as radians
    rows = [f"{f!r},{m!r},{p!r}" for f, m, p in zip(F_HZ.tolist(), [100.0, 100.1, 100.2, 100.15], [-0.3, -1.2, -0.8, -0.5])]
    (tmp_path / "flat.csv").write_text("\n".join(["frequency,|Z|,phase", *rows]) + "\n")
    note = ix.load(tmp_path / "flat.csv").attrs["phase_unit_note"]
    assert "'phase' has no unit" in note and "'phase (rad)'" in note
    # a resistor: the phase never leaves ±0.2°, far from a radian's range
    rows = [f"{f!r},100.0,{p!r}" for f, p in zip(F_HZ.tolist(), [0.1, -0.05, 0.0, -0.15])]
    (tmp_path / "resistor.csv").write_text("\n".join(["frequency,|Z|,phase", *rows]) + "\n")
    assert "phase_unit_note" not in ix.load(tmp_path / "resistor.csv").attrs
    assert main(["fit", str(tmp_path / "flat.csv"), "--model", "R0"]) == 0
    err = capsys.readouterr().err
    assert err.count("'phase' has no unit") == 1 and err.startswith(f"impedax: warning: {tmp_path / 'flat.csv'}: column 'phase'")
    assert main(["inspect", str(tmp_path / "flat.csv")]) == 0
    captured = capsys.readouterr()
    assert "phase unit note: column 'phase' has no unit" in captured.out and "warning" not in captured.err


def test_a_phase_in_radians_beyond_a_full_turn_is_noted(tmp_path, capsys):
    """A column named 'Phase (rad)' holding the degrees of `oracle`'s arc (down to −51.2): no
    impedance phase written in radians leaves ±2π, so the values are read as the unit says and
    noted as likely degrees (until 2026-12-06 they were read without a word)."""
    from impedax.cli import main

    z = oracle(F_HZ)
    degrees = np.degrees(np.angle(z))
    assert -52 < degrees.min() < -51  # the oracle's own numbers: the note quotes this extreme
    rows = [f"{f!r},{abs(zi)!r},{p!r}" for f, zi, p in zip(F_HZ.tolist(), z.tolist(), degrees.tolist())]
    (tmp_path / "deg_as_rad.csv").write_text("\n".join(["Frequency (Hz),|Z| (Ohm),Phase (rad)", *rows]) + "\n")
    ds = ix.load(tmp_path / "deg_as_rad.csv")
    np.testing.assert_allclose(ds["Z"].values, abs(z) * np.exp(1j * degrees), rtol=1e-12)  # read as the unit says
    note = ds.attrs["phase_unit_note"]
    assert "'Phase (rad)'" in note and "-51.2" in note and "±2π" in note and "'Phase (deg)'" in note
    assert main(["inspect", str(tmp_path / "deg_as_rad.csv")]) == 0
    assert "phase unit note: column 'Phase (rad)'" in capsys.readouterr().out
    # radians inside a turn, and the same values read as degrees, are not noted
    rows = [f"{f!r},{abs(zi)!r},{p!r}" for f, zi, p in zip(F_HZ.tolist(), z.tolist(), np.angle(z).tolist())]
    (tmp_path / "rad.csv").write_text("\n".join(["Frequency (Hz),|Z| (Ohm),Phase (rad)", *rows]) + "\n")
    assert "phase_unit_note" not in ix.load(tmp_path / "rad.csv").attrs


def _sweeps_file(path, grids, *, header="frequency,Zreal,Zimag,time/s", cycles=None):
    """Sweeps one after another in one table; sweep k is the oracle plus k Ω in series."""
    rows, t = [header], 0.0
    for k, grid in enumerate(grids):
        for f, zi in zip(grid.tolist(), (oracle(grid) + k).tolist()):
            t += 1.5
            rows.append(f"{f!r},{zi.real!r},{zi.imag!r},{t!r}" + ("" if cycles is None else f",{cycles[k]}"))
    path.write_text("\n".join(rows) + "\n")
    return path


def test_repeated_sweeps_in_one_table_become_a_dimension(tmp_path):
    ds = ix.load(_sweeps_file(tmp_path / "three.csv", [F_HZ] * 3))
    assert ds["Z"].dims == ("sweep", "frequency") and list(ds["sweep"].values) == ["0", "1", "2"]
    np.testing.assert_array_equal(ds["frequency"].values, F_HZ)
    for k in range(3):
        np.testing.assert_allclose(ds["Z"].values[k], oracle(F_HZ) + k, rtol=1e-15)
    np.testing.assert_allclose(ds["time"].values, 1.5 * np.arange(1, 13).reshape(3, 4))  # each point's own time
    assert ds.attrs["sweeps"] == "3 sweeps of 4 points (the frequency list restarts on lines 6, 10)"
    # measured frequencies that vary in their last digits from sweep to sweep: sweep 0's grid, said so
    ds = ix.load(_sweeps_file(tmp_path / "jitter.csv", [F_HZ, F_HZ * (1 + 2e-4)]))
    np.testing.assert_array_equal(ds["frequency"].values, F_HZ)
    np.testing.assert_allclose(ds["Z"].values[1], oracle(F_HZ * (1 + 2e-4)) + 1, rtol=1e-15)
    assert "differ from sweep 0's by up to 2.0e-04 relative" in ds.attrs["sweeps"]
    # the same in impedax's own CSV layout (read by its fast path when it holds one spectrum)
    grids = [F_HZ, F_HZ * (1 + 2e-4)]
    rows = [f"{f!r},{zi.real!r},{zi.imag!r}" for k, g in enumerate(grids) for f, zi in zip(g.tolist(), (oracle(g) + k).tolist())]
    (tmp_path / "canonical.csv").write_text("\n".join(["frequency_hz,z_real_ohm,z_imag_ohm", *rows]) + "\n")
    assert ix.load(tmp_path / "canonical.csv")["Z"].dims == ("sweep", "frequency")
    # EC-Lab's cycle number names the sweeps
    ds = ix.load(_sweeps_file(tmp_path / "cycles.csv", [F_HZ] * 2, header="frequency,Zreal,Zimag,time/s,cycle number", cycles=[3, 4]))
    assert ds["Z"].dims == ("cycle", "frequency") and list(ds["cycle"].values) == ["3", "4"]
    np.testing.assert_allclose(ds["Z"].values[1], oracle(F_HZ) + 1, rtol=1e-15)


def _workbook(path, sheets):
    """A workbook of sheets S0, S1, ...: ``sheets[s]`` lists each sweep's (cycle number or None,
    offset); a sweep is oracle(F_HZ) + offset, the cycle number in a `cycle number` column when
    given."""
    openpyxl = pytest.importorskip("openpyxl")
    workbook = openpyxl.Workbook()
    workbook.remove(workbook.active)
    for sheet, sweeps in enumerate(sheets):
        table = workbook.create_sheet(f"S{sheet}")
        numbered = any(cycle is not None for cycle, _ in sweeps)
        table.append(["Frequency (Hz)", "Z' (Ohm)", "Z'' (Ohm)", *(["cycle number"] if numbered else [])])
        for cycle, offset in sweeps:
            for f, zi in zip(F_HZ.tolist(), (oracle(F_HZ) + offset).tolist()):
                table.append([f, zi.real, zi.imag, *([cycle] if numbered else [])])
    workbook.save(path)
    return path


def test_a_spreadsheet_sheet_of_sweeps_becomes_a_dimension(tmp_path):
    """Sheets of repeated sweeps: (sheet, sweep, frequency), each sweep its own values; sheets
    that hold different numbers of sweeps are one error naming both."""
    def book(path, sweeps_per_sheet):
        return _workbook(path, [[(None, 10 * sheet + k) for k in range(n)] for sheet, n in enumerate(sweeps_per_sheet)])

    ds = ix.load(book(tmp_path / "two.xlsx", [3, 3]))
    assert ds["Z"].dims == ("sheet", "sweep", "frequency") and list(ds["sweep"].values) == ["0", "1", "2"]
    for sheet in range(2):
        for k in range(3):
            np.testing.assert_allclose(ds["Z"].values[sheet, k], oracle(F_HZ) + 10 * sheet + k, rtol=1e-15)
    assert ds.attrs["sweeps"] == "3 sweeps of 4 points (the frequency list restarts on rows 6, 10)"
    with pytest.raises(ix.DataError, match=r"sheet 'S1' holds one spectrum where sheet 'S0' holds 2 sweeps \(0, 1\)"):
        ix.load(book(tmp_path / "uneven.xlsx", [2, 1]))


def test_sheets_whose_cycle_numbers_carry_on_are_one_series_of_cycles(tmp_path):
    """Sheets of a cycling run split by size (cycles 1–2 on one sheet, 3–5 on the next): one
    `cycle` dimension in order, each cycle its own values, a `sheet` coordinate saying where
    each came from; sheets that number their cycles alike still stack as (sheet, cycle)."""
    def book(path, cycles_per_sheet):
        return _workbook(path, [[(cycle, 100 * sheet + cycle) for cycle in cycles] for sheet, cycles in enumerate(cycles_per_sheet)])

    ds = ix.load(book(tmp_path / "run.xlsx", [[1, 2], [3, 4, 5]]))
    assert ds.attrs["source"] == str(tmp_path / "run.xlsx")  # (messages name the file once, not each sheet's part)
    assert ds["Z"].dims == ("cycle", "frequency") and list(ds["cycle"].values) == ["1", "2", "3", "4", "5"]
    assert list(ds["sheet"].values) == ["S0", "S0", "S1", "S1", "S1"]
    for k, (sheet, cycle) in enumerate([(0, 1), (0, 2), (1, 3), (1, 4), (1, 5)]):
        np.testing.assert_allclose(ds["Z"].values[k], oracle(F_HZ) + 100 * sheet + cycle, rtol=1e-15)
    assert ds.attrs["sheets"] == "cycles 1–2 from sheet S0, 3–5 from sheet S1"
    same = ix.load(book(tmp_path / "repeats.xlsx", [[1, 2], [1, 2]]))
    assert same["Z"].dims == ("sheet", "cycle", "frequency")
    np.testing.assert_allclose(same["Z"].values[1, 0], oracle(F_HZ) + 101, rtol=1e-15)
    with pytest.raises(ix.DataError, match=r"sheet 'S1' holds 2 cycles \(2, 3\) where sheet 'S0' holds 2 cycles \(1, 2\)"):
        ix.load(book(tmp_path / "overlap.xlsx", [[1, 2], [2, 3]]))
    # numbers that go back (3, 4 / 1, 2) are no series
    with pytest.raises(ix.DataError, match=r"sheet 'S1' holds 2 cycles \(1, 2\) where sheet 'S0' holds 2 cycles \(3, 4\)"):
        ix.load(book(tmp_path / "backwards.xlsx", [[3, 4], [1, 2]]))
    # a last sheet of one cycle, and sheets of one cycle each, carry the numbering on too
    for cycles, labels in (([[1, 2], [3]], ["1", "2", "3"]), ([[1], [2], [3]], ["1", "2", "3"])):
        ds = ix.load(book(tmp_path / "short.xlsx", cycles))
        assert ds["Z"].dims == ("cycle", "frequency") and list(ds["cycle"].values) == labels
        assert list(ds["sheet"].values) == [f"S{s}" for s, sheet in enumerate(cycles) for _ in sheet]
        np.testing.assert_allclose(ds["Z"].values[2], oracle(F_HZ) + 100 * (len(cycles) - 1) + 3, rtol=1e-15)
        assert "sweeps" not in ds.attrs and "sheet" not in ds.attrs  # (each sheet's note is replaced by `sheets`)
    assert ds.attrs["sheets"] == "cycles 1 from sheet S0, 2 from sheet S1, 3 from sheet S2"


def test_ec_lab_cycles_become_a_dimension(tmp_path):
    """EC-Lab's real example file (impedance.py 1.7's), its data rows written a second time as
    cycle 2 with Z' 5 Ω higher: a `cycle` dimension, the file's values in each."""
    source = FIXTURES / "real" / "exampleDataBioLogic.mpt"
    text = source.read_text(encoding="latin-1")
    lines = text.splitlines()
    n_header = int(re.search(r"Nb header lines\s*:\s*(\d+)", text).group(1))
    header = lines[n_header - 1].split("\t")
    cycle, real = header.index("cycle number"), header.index("Re(Z)/Ohm")
    again = []
    for row in lines[n_header:]:
        cells = row.split("\t")
        cells[cycle], cells[real] = "2.000000000000000E+000", repr(float(cells[real]) + 5.0)
        again.append("\t".join(cells))
    path = tmp_path / "two_cycles.mpt"
    path.write_text("\n".join(lines + again) + "\n", encoding="latin-1")
    one, two = ix.load(source), ix.load(path)
    assert two["Z"].dims == ("cycle", "frequency") and list(two["cycle"].values) == ["1", "2"]
    np.testing.assert_array_equal(two["Z"].values[0], one["Z"].values)
    np.testing.assert_allclose(two["Z"].values[1], one["Z"].values + 5.0, rtol=1e-15)
    assert two.attrs["sweeps"] == f"2 cycles of {one['frequency'].size} points (the cycle number changes on line {len(lines) + 1})"


def test_generic_column_names_never_take_a_column_a_specific_name_holds(tmp_path):
    """EC-Lab's real example file with columns other software also writes: EC-Lab's own `x`, an
    `R/Ohm`, dielectric `Re(M)`/`Im(M)`, `Mag(Y)`; and a table with an `X (mm)`, a `Mag (dB)`, a
    `Z_deg`. Each loaded before the generic names (R, X, Re, Im, Mag ...) were added; they still
    load, with the same Z, and the extra columns are listed as other columns."""
    source = FIXTURES / "real" / "exampleDataBioLogic.mpt"
    lines = source.read_text(encoding="latin-1").splitlines()
    n_header = int(re.search(r"Nb header lines\s*:\s*(\d+)", "\n".join(lines[:3])).group(1))
    extra = ["x", "R/Ohm", "Re(M)", "Im(M)", "Mag(Y)"]
    lines[n_header - 1] = lines[n_header - 1].rstrip("\t") + "\t" + "\t".join(extra)
    for k in range(n_header, len(lines)):
        if lines[k].strip():
            lines[k] = lines[k].rstrip("\t") + "\t" + "\t".join(["0.5", "12.0", "1.0", "2.0", "3.0"])
    path = tmp_path / "more_columns.mpt"
    path.write_text("\n".join(lines) + "\n", encoding="latin-1")
    np.testing.assert_array_equal(ix.load(path)["Z"].values, ix.load(source)["Z"].values)
    assert all(name in ix.load(path).attrs["other_columns"] for name in extra)
    z = oracle(F_HZ)
    rows = [f"{f!r},{zi.real!r},{zi.imag!r},1.0,2.0,3.0" for f, zi in zip(F_HZ.tolist(), z.tolist())]
    (tmp_path / "t.csv").write_text("\n".join(["frequency,Z',Z'',X (mm),Mag (dB),Z_deg", *rows]) + "\n")
    ds = ix.load(tmp_path / "t.csv")
    np.testing.assert_array_equal(ds["Z"].values, z)
    assert ds.attrs["other_columns"] == "X (mm), Mag (dB), Z_deg"
    # two generic columns asking for one quantity: neither is taken, the table has no Z
    (tmp_path / "two.csv").write_text("f,R,Rs,X\n1,2,3,4\n")
    with pytest.raises(ix.DataError, match="cannot find impedance columns"):
        ix.load(tmp_path / "two.csv")


def test_a_cycle_column_of_text_and_a_late_check_point_are_no_sweeps(tmp_path):
    z = oracle(F_HZ)
    rows = [f"{f!r},{zi.real!r},{zi.imag!r},first" for f, zi in zip(F_HZ.tolist(), z.tolist())]
    (tmp_path / "text_cycle.csv").write_text("\n".join(["frequency,Zreal,Zimag,Cycle", *rows]) + "\n")
    ds = ix.load(tmp_path / "text_cycle.csv")
    assert ds["Z"].dims == ("frequency",) and ds.attrs["other_columns"] == "Cycle"
    # a sweep, then one more point near its first frequency (a drift check): one spectrum
    rows.append(f"{float(F_HZ[0]) * 1.0002!r},{float(z[0].real)!r},{float(z[0].imag)!r},first")
    (tmp_path / "check.csv").write_text("\n".join(["frequency,Zreal,Zimag,Cycle", *rows]) + "\n")
    ds = ix.load(tmp_path / "check.csv")
    assert ds["Z"].dims == ("frequency",) and ds["frequency"].size == F_HZ.size + 1


def test_stacked_spectra_keep_a_note_that_only_one_of_them_has():
    from impedax.io._common import stack

    a = ix.make_spectrum(F_HZ, oracle(F_HZ), attrs={"units": "Hz, Ω"})
    b = ix.make_spectrum(F_HZ, oracle(F_HZ), attrs={"units": "Hz, Ω", "phase_unit_note": "column 'phase' has no unit"})
    attrs = stack(Path("book.xlsx"), [("A", a), ("B", b)], "sheet").attrs
    assert attrs["units"] == "Hz, Ω" and attrs["phase_unit_note"] == "sheet B: column 'phase' has no unit"


def test_sweeps_that_are_not_repeats_of_one_list(tmp_path):
    # a sweep cut short: an error naming the line where it starts
    with pytest.raises(ix.DataError, match=r"short.csv, line 10: the table holds 3 sweeps of one frequency list .* of 4, 4, 2 points"):
        ix.load(_sweeps_file(tmp_path / "short.csv", [F_HZ, F_HZ, F_HZ[:2]]))
    # down and back up: one spectrum with a repeated frequency, as before
    with pytest.raises(ix.DataError, match=r"line 6: duplicate frequency 0.1 Hz \(also on line 5\)"):
        ix.load(_sweeps_file(tmp_path / "updown.csv", [F_HZ, F_HZ[::-1]]))
    # a second list on another grid: refused, naming where it starts (never merged into one spectrum)
    with pytest.raises(ix.SweepGridsDiffer, match=r"two_grids.csv, line 6: the table holds 2 sweeps on different frequency grids"):
        ix.load(_sweeps_file(tmp_path / "two_grids.csv", [F_HZ, F_HZ * 1.5]))


# --- nothing skipped silently, nothing shifted --------------------------------------------------


def test_dc_rows_and_repeated_headers_are_skipped_and_reported(tmp_path):
    path = tmp_path / "run.csv"
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n0,5,0\n100,2,-3\nfrequency_hz,z_real_ohm,z_imag_ohm\n10,2,-0.3\n")
    ds = ix.load(path)
    np.testing.assert_array_equal(ds["frequency"].values, [100.0, 10.0])
    np.testing.assert_array_equal(ds["Z"].values, [2 - 3j, 2 - 0.3j])
    assert ds.attrs["skipped_rows"] == ["line 2: f = 0 (DC row, not an impedance point)", "line 4: repeated header"]


def test_labone_empty_cells_are_an_error_not_a_shift(tmp_path):
    """The old reader dropped empty cells field by field, moving later Z values onto earlier frequencies."""
    text = (FIXTURES / "dev3000_imps_0_sample_00000.csv").read_text()
    lines = [ln for k, ln in enumerate(text.splitlines()) if k == 0 or ln.split(";")[0] == "0"]  # one sweep
    row = {ln.split(";")[3]: i for i, ln in enumerate(lines) if i > 0}
    for field, point in (("realz", 2), ("imagz", 2), ("frequency", 4)):  # equal counts: the old reader shifted silently
        cells = lines[row[field]].split(";")
        cells[4 + point] = ""
        lines[row[field]] = ";".join(cells)
    path = tmp_path / "dev3000_imps_0_sample_00000.csv"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ix.DataError, match=rf"line {row['realz'] + 1}: sweep \(chunk\) 0, point 2: realz, imagz missing"):
        ix.load(path)


def test_labone_padding_of_every_field_is_skipped_and_reported(tmp_path):
    f = DESCENDING[::-1]
    z = oracle(f)
    rows = ["chunk;timestamp;size;fieldname;" + ";".join(f"v{i}" for i in range(len(f) + 1))]
    for name, values in (("frequency", f), ("realz", z.real), ("imagz", z.imag)):
        rows.append(f"0;1;{len(f)};{name};" + ";".join(repr(float(v)) for v in values) + ";")
    path = tmp_path / "pad.csv"
    path.write_text("\n".join(rows) + "\n")
    ds = ix.load(path)
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-15)
    assert ds.attrs["skipped_rows"] == ["line 2: sweep 0 point 6: empty in every field (padding)"]


def test_netcdf_with_a_one_element_imaginary_part_is_refused(tmp_path):
    """The old decoder broadcast Z__imag of shape (1,) over every frequency."""
    import xarray as xr

    f = np.array([1.0, 10.0, 100.0])
    bad = xr.Dataset(
        {"Z__real": ("frequency", [1.0, 2.0, 3.0], {"impedax_part": "real"}), "Z__imag": ("one", [-1.0], {"impedax_part": "imag"})},
        coords={"frequency": f},
    )
    path = tmp_path / "bad.nc"
    bad.to_netcdf(path, engine="scipy")
    with pytest.raises(ix.DataError, match=r"bad.nc: Z__real has shape \{'frequency': 3\} but Z__imag has \{'one': 1\}"):
        ix.load(path)


# --- Gamry: several tables, hostile headers ---------------------------------------------------


def test_gamry_several_zcurve_tables_become_a_dimension(tmp_path):
    text = (FIXTURES / "gamry_eispot.DTA").read_bytes().decode("latin-1")
    start = text.index("ZCURVE\tTABLE")
    table = text[start:]
    path = tmp_path / "two.DTA"
    path.write_bytes((text + "\n" + table.replace("ZCURVE\tTABLE", "ZCURVE2\tTABLE", 1)).encode("latin-1"))
    ds = ix.load(path)
    assert ds["Z"].dims == ("curve", "frequency") and list(ds["curve"].values) == ["ZCURVE", "ZCURVE2"]
    np.testing.assert_allclose(ds["Z"].values, np.stack([oracle(DESCENDING)] * 2), rtol=1e-6)
    path.write_bytes((text + "\n" + table).encode("latin-1"))  # the same table name twice
    assert list(ix.load(path)["curve"].values) == ["ZCURVE #1", "ZCURVE #2"]


@pytest.mark.parametrize("count, fragment", [("-1", "does not fit"), ("99999", "does not fit"), ("x", "not a whole number")])
def test_gamry_notes_count_is_checked(tmp_path, count, fragment):
    """A negative count used to loop forever."""
    text = (FIXTURES / "gamry_eispot.DTA").read_bytes().decode("latin-1")
    text = re.sub(r"NOTES\tNOTES\t\d+", f"NOTES\tNOTES\t{count}", text, count=1)
    path = tmp_path / "n.DTA"
    path.write_bytes(text.encode("latin-1"))
    with pytest.raises(ix.DataError, match=fragment):
        ix.load(path)


# --- binary .mpr through an optional galvani -------------------------------------------------


def test_mpr_without_galvani_says_how_to_get_it(tmp_path, monkeypatch):
    path = tmp_path / "run.mpr"
    path.write_bytes(b"BIO-LOGIC MODULAR FILE\x1a" + bytes(100))
    monkeypatch.setitem(sys.modules, "galvani", None)
    with pytest.raises(ix.DataError, match=r"run.mpr: .*galvani.*GPL.*export .mpt"):
        ix.load(path)


def test_mpr_columns_through_galvani(tmp_path, monkeypatch):
    f = DESCENDING
    z = oracle(f)
    table = np.zeros(f.size, dtype=[("freq/Hz", "f4"), ("Re(Z)/Ohm", "f4"), ("-Im(Z)/Ohm", "f4"), ("time/s", "f8")])
    table["freq/Hz"], table["Re(Z)/Ohm"], table["-Im(Z)/Ohm"] = f, z.real, -z.imag

    class MPRfile:
        def __init__(self, name):
            assert name == str(path)
            self.data = table

    fake = types.ModuleType("galvani")
    fake.BioLogic = types.SimpleNamespace(MPRfile=MPRfile)
    monkeypatch.setitem(sys.modules, "galvani", fake)
    path = tmp_path / "run.mpr"
    path.write_bytes(b"BIO-LOGIC MODULAR FILE\x1a" + bytes(100))
    ds = ix.load(path)
    assert ds.attrs["format"] == "BioLogic EC-Lab mpr"
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-6)  # float32 in the file


# --- the registry -------------------------------------------------------------------------------


def test_a_user_reader_is_one_function_and_one_registration(tmp_path):
    def sniff(path, head):
        return None if head.startswith(b"MYFORMAT") else "no 'MYFORMAT' signature"

    def read(path):
        rows = np.loadtxt(path, skiprows=1)
        return ix.make_spectrum(rows[:, 0], rows[:, 1] + 1j * rows[:, 2], attrs={"format": "mine"})

    readers = register_reader(Reader("My format", (".my",), sniff, read))
    assert readers[0].name == "My format" and len(readers) == len(READERS) + 1 and READERS[0].name != "My format"
    path = tmp_path / "run.my"
    path.write_text("MYFORMAT\n1 2 -3\n10 2 -0.3\n")
    loaded = ix.load(path, readers=readers)
    np.testing.assert_array_equal(loaded["Z"].values, [2 - 3j, 2 - 0.3j])
    assert loaded.attrs["source"] == str(path)  # (built by make_spectrum, whose source is "memory": later errors name the file)
    with pytest.raises(ix.DataError, match=re.escape(str(path)) + ": the KK test needs at least 4 frequencies"):
        ix.kk_test(loaded)
    with pytest.raises(ix.DataError, match=f"; {len(readers)} other formats tried"):
        ix.load(_mystery(tmp_path), readers=readers)
    assert "My format: no 'MYFORMAT' signature" in ix.io.identify(_mystery(tmp_path), readers)[1]
    assert ix.load(FIXTURES / "zplot_sweep.z", readers=readers).attrs["format"] == "Scribner ZPlot z"


def test_a_user_reader_that_raises_is_one_data_error_naming_it_and_the_file(tmp_path):
    """A user's reader that raises something other than impedax's own errors (its float() of a
    bad field): `ix.load` raises one `DataError` naming the file, the reader, the line of the
    reader's code that raised and the original message, the original exception kept as
    ``__cause__`` (until 2026-12-06 only the command line did: in Python the ValueError came
    through as a bare traceback from inside the reader)."""
    def sniff(path, head):
        return None if head.startswith(b"MYFORMAT") else "no 'MYFORMAT' signature"

    def read(path):
        rows = [line.split() for line in path.read_text().splitlines()[1:]]
        values = [[float(cell) for cell in row] for row in rows]  # (the line that raises)
        return ix.make_spectrum([v[0] for v in values], [v[1] + 1j * v[2] for v in values])

    raising_line = read.__code__.co_firstlineno + 2
    readers = register_reader(Reader("My format", (".my",), sniff, read))
    path = tmp_path / "run.my"
    path.write_text("MYFORMAT\n1 2 -3\n10 oops -0.3\n")
    with pytest.raises(ix.DataError) as caught:
        ix.load(path, readers=readers)
    assert str(caught.value) == (f"{path}: the reader 'My format' ({__file__}, line {raising_line}) raised ValueError: "
                                 "could not convert string to float: 'oops'")
    assert isinstance(caught.value.__cause__, ValueError)
    with pytest.raises(ix.DataError, match="the reader 'My format'"):  # (picking one sweep reads it the same way)
        ix.load(path, readers=readers, sweep="0")


@pytest.mark.parametrize("text", [
    '{"frequency": [1, 10, 100], "z_real": [10, 9, 8], "z_imag": [-1, -2, -3]}\n',
    '[{"f": 1, "re": 10, "im": -1}, {"f": 10, "re": 9, "im": -2}]\n',
])
def test_a_json_file_that_is_no_result_is_named_as_json(tmp_path, text):
    """A JSON file of a user's own layout (SYNTHETIC numbers) given as a spectrum: it was told
    "as delimited text, no frequency column in header ['{"frequency": [1', '10', '100]', ...]",
    as if impedax had taken it for a table; now the message says it is JSON, which format of
    JSON impedax reads (PalmSens), and the table to write instead."""
    path = tmp_path / "my.json"
    path.write_text(text)
    with pytest.raises(ix.DataError) as err:
        ix.load(path)
    assert str(err.value) == (f"{path}: not a recognised spectrum file: a JSON file (it opens with '{{' or '['), which impedax reads only as a "
                              f"PalmSens .pssession ({len(READERS)} formats tried); write the spectrum as a table, frequency_hz,z_real_ohm,z_imag_ohm "
                              "(impedax.save(impedax.make_spectrum(f, Z), 'run.csv'))")
    # an instrument's "[Header]" section line is no JSON: the table's own reason stays
    path.write_text("[Header]\nvoltage,current\n1,2\n")
    with pytest.raises(ix.DataError, match=r"not a recognised spectrum file: as delimited text"):
        ix.load(path)


def test_readers_that_are_no_sequence_of_readers_are_one_parameter_error():
    """``readers=`` given a single Reader, a function or text: one ParameterError saying what
    was given and what to give (until 2026-12-06 "TypeError: 'Reader' object is not iterable" or
    "AttributeError: 'function' object has no attribute 'name'" from inside load)."""
    def sniff(path, head):
        return "not mine"

    mine = Reader("Mine", (".my",), sniff, lambda path: None)
    real = FIXTURES / "real" / "exampleDataZPlot.z"
    cases = [
        (mine, "readers must be a sequence of impedax.io.Reader, got the single Reader 'Mine': give impedax.io.register_reader(reader), "
               "which tries it before the built-in readers"),
        ([mine, sniff], "readers[1] is the function 'sniff', not an impedax.io.Reader: build one with impedax.io.Reader(name, extensions, sniff, read)"),
        ("zplot", "readers must be a sequence of impedax.io.Reader (impedax.io.register_reader(...)), got 'zplot' (str)"),
    ]
    for readers, message in cases:
        for call in (ix.load, ix.io.identify):
            with pytest.raises(ix.ParameterError) as err:
                call(real, readers=readers)
            assert str(err.value) == message
    assert ix.load(real, readers=list(register_reader(mine))).attrs["format"] == "Scribner ZPlot z"  # (a list of Readers is a sequence too)


def test_a_missing_file_is_named_with_what_may_be_wrong_with_its_name(tmp_path, monkeypatch, capsys):
    """"file not found" said nothing more: a name typed in another case than the REAL file's
    (exampleDataZPlot.Z), one letter off, a trailing space, an unexpanded '~', a folder that does
    not exist. The file itself, copied here, is what each message points to."""
    shutil.copy(FIXTURES / "real" / "exampleDataZPlot.z", tmp_path / "exampleDataZPlot.z")
    monkeypatch.chdir(tmp_path)
    cases = {
        "exampleDataZPlot.Z": "file not found; did you mean 'exampleDataZPlot.z'?",
        "exampleDataZPlto.z": "file not found; did you mean 'exampleDataZPlot.z'?",
        "exampleDataZPlot.z ": "file not found; the name 'exampleDataZPlot.z ' starts or ends with a space",
        "~/exampleDataZPlot.z": "file not found; '~' is not expanded here (a shell expands it when not quoted; in Python, give pathlib.Path(path).expanduser())",
        "runs/exampleDataZPlot.z": "file not found; there is no folder 'runs'",
        "other.csv": "file not found",
    }
    for name, message in cases.items():
        with pytest.raises(ix.DataError) as err:
            ix.load(name)
        assert str(err.value) == f"{name}: {message}"
    from impedax.cli import main
    assert main(["inspect", "exampleDataZPlot.Z"]) == 2
    assert capsys.readouterr().err.strip() == "impedax inspect: error: exampleDataZPlot.Z: file not found; did you mean 'exampleDataZPlot.z'?"


def test_a_netcdf_file_of_a_users_own_layout_says_how_to_make_it_a_spectrum(tmp_path):
    """A netCDF file written with xarray by a user (SYNTHETIC R ∥ C, Z' and Z'' as two real
    variables over 'f'): it was told "dataset has no variable 'Z' (its data variables: ...)"
    alone; now also what impedax loads and how to build and save the spectrum."""
    import xarray as xr

    f = np.geomspace(1, 1e5, 10)
    z = 100 / (1 + 1j * f / 1e3)
    path = tmp_path / "own.nc"
    xr.Dataset({"z_real": ("f", z.real), "z_imag": ("f", z.imag)}, coords={"f": f}).to_netcdf(path, engine="scipy")
    with pytest.raises(ix.DataError) as err:
        ix.load(path)
    assert str(err.value) == (f"{path}: a netCDF file that holds no spectrum (no variable 'Z'; its data variables: 'z_real', 'z_imag'): impedax loads "
                              "the spectra impedax.save writes (a saved result is read with its class's from_xarray); for data of your own layout, "
                              "build the spectrum in Python, impedax.make_spectrum(frequency_hz, Z) with Z complex, and save it with impedax.save(data, 'run.nc')")
    ix.save(ix.make_spectrum(f, z), path)  # (what the message says to do reads back)
    np.testing.assert_array_equal(ix.load(path)["Z"].values, z)


def _mystery(tmp_path):
    path = tmp_path / "mystery.txt"
    path.write_text("voltage,current\n1,2\n")
    return path


# --- files that must be refused quickly ---------------------------------------------------------


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
def test_dev_zero_is_refused_before_reading():
    with pytest.raises(ix.DataError, match="not a regular file"):
        ix.load("/dev/zero")


def test_oversized_file_is_refused_before_reading(tmp_path, monkeypatch):
    monkeypatch.setattr("impedax.io._common.MAX_FILE_BYTES", 1000)
    path = tmp_path / "big.csv"
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{k + 1},1,-1\n" for k in range(200)))
    with pytest.raises(ix.DataError, match="impedax reads spectrum files up to"):
        ix.load(path)


def test_a_netcdf_file_gets_four_times_the_limit_a_text_file_gets(tmp_path, monkeypatch):
    """A netCDF file is read into about its own size (no text to parse): its limit is
    `NETCDF_LIMIT_FACTOR` (4) × the text limit, so impedax reads back the larger files it writes
    (a joint posterior of 960,000 draws, 88 MB, was refused at 64 MB). Sizes from `os.stat`."""
    f = np.geomspace(1.0, 1e5, 400)
    path = tmp_path / "spectrum.nc"
    ix.save(ix.make_spectrum(f, 10 + 100 / (1 + 1j * f / 100)), path)
    size = path.stat().st_size
    monkeypatch.setattr("impedax.io._common.MAX_FILE_BYTES", size // 2)  # (over the text limit, within 4× it)
    np.testing.assert_allclose(ix.load(path)["frequency"].values, f)
    monkeypatch.setattr("impedax.io._common.MAX_FILE_BYTES", size // 5)  # (4× the limit is below the size)
    with pytest.raises(ix.DataError, match="impedax reads netCDF files up to"):
        ix.load(path)
    text = tmp_path / "spectrum.csv"
    text.write_bytes(b"frequency_hz,z_real_ohm,z_imag_ohm\n" + b"1,1,-1\n" * (size // 8))  # (a CSV of the netCDF's size: over the text limit)
    monkeypatch.setattr("impedax.io._common.MAX_FILE_BYTES", size // 2)
    with pytest.raises(ix.DataError, match="impedax reads spectrum files up to"):
        ix.load(text)


def test_labone_hdf5_several_sweeps(tmp_path):
    z = oracle(LABONE_F)
    ds = ix.load(_labone_h5(tmp_path / "sweeps.h5", [z, 2 * z]))
    assert ds["Z"].dims == ("sweep", "frequency")
    np.testing.assert_allclose(ds["Z"].values, np.stack([z, 2 * z]), rtol=1e-15)


@pytest.mark.parametrize(
    "preamble",
    [
        ["Instrument: FooStat 3000", "Date: 2026-11-30", "", "Area: 1 cm²"],  # notes, a blank line
        ["Instrument,FooStat 3000", "Points,4", "Area (cm2),1"],  # key,value rows in the table's delimiter
        ["Sample,1,2", "E_dc (V),0.1,0.0"],  # rows of as many cells, some of them numbers
    ],
)
def test_text_above_the_header_is_passed_over_and_named(tmp_path, preamble):
    """An instrument's or a user's lines above the table: the header is found below them (it was
    refused as "no frequency column in header ['Instrument:', 'FooStat', '3000']"), the data read
    as the oracle's, and attrs["preamble"] names the lines passed over."""
    z = oracle(F_HZ)
    rows = [f"{f!r},{zi.real!r},{zi.imag!r}" for f, zi in zip(F_HZ.tolist(), z.tolist())]
    (tmp_path / "m.csv").write_text("\n".join([*preamble, "Frequency (Hz),Z' (Ohm),Z'' (Ohm)", *rows]) + "\n", encoding="utf-8")
    ds = ix.load(tmp_path / "m.csv")
    np.testing.assert_allclose(ds["frequency"].values, F_HZ, rtol=1e-15)
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-15)
    header_line = len(preamble) + 1
    assert ds.attrs["preamble"].startswith(f"lines 1–{header_line - 1}: text above the table's header (line {header_line})")
    # a text with no header at all keeps its message
    (tmp_path / "n.csv").write_text("Instrument: FooStat\nnothing here\n")
    with pytest.raises(ix.DataError, match="line 1"):
        ix.load(tmp_path / "n.csv")


def test_a_comment_line_inside_the_table_is_reported_among_the_skipped_rows():
    """'# electrode re-seated here' between two rows was dropped without a word ("skipped rows:
    none"); it is still not read, and now named with its line."""
    import tempfile

    z = oracle(F_HZ)
    rows = [f"{f!r},{zi.real!r},{zi.imag!r}" for f, zi in zip(F_HZ.tolist(), z.tolist())]
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "c.csv"
        path.write_text("\n".join(["# exported by hand", "frequency,Z',Z''", *rows[:2], "# electrode re-seated here", *rows[2:]]) + "\n")
        ds = ix.load(path)
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-15)
    assert ds.attrs["skipped_rows"] == ["line 5: comment line ('# electrode re-seated here')"]  # (the one above the header is no row)


# --- a technician's files from five labs (2026-12-01) ---------------------------------------------
# SYNTHETIC: every table below is the RC spectrum Z = 100 + 300/(1 + j·2πf·1 ms) Ω on a log
# grid, with 0.1 % Gaussian noise (fixed seed), written by each test in the layout it exercises.


def _lab_spectrum(n=13):
    freq = np.logspace(5, -1, n)
    rng = np.random.default_rng(71)
    z = 100 + 300 / (1 + 1j * 2 * np.pi * freq * 1e-3)
    z = z * (1 + 1e-3 * (rng.standard_normal(n) + 1j * rng.standard_normal(n)))
    return freq, z


@pytest.mark.parametrize("header", ["omega", "ω", "omega (rad/s)", "w (rad/s)", "ω/rad s-1", "Frequency (rad/s)", "omega/rad/s", "omega / (rad/s)", "w/rad/sec"])
def test_an_angular_frequency_column_is_converted_to_hz_and_said(tmp_path, header, capsys):
    """'omega (rad/s)' and the like were 'no frequency column'; now f = ω/2π, and `units` (which
    `impedax inspect` prints) names the conversion. 'omega/rad/s', the unit after a slash with
    a slash of its own, was refused with the advice to name it 'omega' until 2026-12-04."""
    freq, z = _lab_spectrum()
    omega = 2 * np.pi * freq
    rows = [f"{w!r},{zi.real!r},{zi.imag!r}" for w, zi in zip(omega.tolist(), z.tolist())]
    path = tmp_path / "w.csv"
    path.write_text("\n".join([f"{header},Z',Z''", *rows]) + "\n", encoding="utf-8")
    ds = ix.load(path)
    np.testing.assert_allclose(ds["frequency"].values, omega / (2 * np.pi), rtol=1e-15)
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-15)
    assert f"{header!r} as angular frequency ω in rad/s, converted to Hz: f = ω/2π" in ds.attrs["units"]
    from impedax.cli import main

    assert main(["inspect", str(path)]) == 0
    assert "f = ω/2π" in capsys.readouterr().out


def test_freq_dot_is_a_frequency_a_bare_w_is_not_and_hz_wins_over_omega(tmp_path):
    freq, z = _lab_spectrum()
    rows = [f"{f!r},{zi.real!r},{zi.imag!r}" for f, zi in zip(freq.tolist(), z.tolist())]
    (tmp_path / "dot.csv").write_text("\n".join(["Freq.,Z',Z''", *rows]) + "\n")
    np.testing.assert_allclose(ix.load(tmp_path / "dot.csv")["frequency"].values, freq, rtol=1e-15)
    (tmp_path / "w.csv").write_text("\n".join(["w,Z',Z''", *rows]) + "\n")
    with pytest.raises(ix.DataError, match=r"no frequency column in header \['w'"):  # (a bare w is not guessed as ω)
        ix.load(tmp_path / "w.csv")
    both = [f"{f!r},{2 * np.pi * f!r},{zi.real!r},{zi.imag!r}" for f, zi in zip(freq.tolist(), z.tolist())]
    (tmp_path / "both.csv").write_text("\n".join(["f (Hz),omega (rad/s),Z',Z''", *both]) + "\n", encoding="utf-8")
    ds = ix.load(tmp_path / "both.csv")
    np.testing.assert_allclose(ds["frequency"].values, freq, rtol=1e-15)
    assert ds.attrs["other_columns"] == "omega (rad/s)"


@pytest.mark.parametrize("sep", [";", "\t", ","])
def test_quoted_decimal_commas_are_read_when_every_number_agrees(tmp_path, sep):
    """Excel's German export quotes every cell, "0,1";"120,5"; with ',' between cells such a
    file was refused ('0,1' is not a number), as was a file whose first decimal comma came below
    row 20 (integer frequencies first)."""
    freq, z = _lab_spectrum(30)
    freq[:25] = np.round(freq[:25])  # (integers first: 1e5 ... 1 Hz, the decimals below row 20)
    cells = [[f"{v:.6g}".replace(".", ",") for v in (f, zi.real, zi.imag)] for f, zi in zip(freq, z)]
    rows = [sep.join(f'"{c}"' for c in row) for row in cells]
    path = tmp_path / "de.csv"
    path.write_text("\n".join([sep.join(['"Frequency (Hz)"', '"Z\' (Ohm)"', '"Z\'\' (Ohm)"']), *rows]) + "\n", encoding="utf-8")
    ds = ix.load(path)
    expected = np.array([[float(c.replace(",", ".")) for c in row] for row in cells])
    np.testing.assert_allclose(ds["frequency"].values, expected[:, 0], rtol=1e-15)
    np.testing.assert_allclose(ds["Z"].values, expected[:, 1] + 1j * expected[:, 2], rtol=1e-15)
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-5)  # (6 digits kept)
    assert ds.attrs["decimal_mark"] == "comma"



def test_a_first_decimal_comma_below_row_20_is_still_a_decimal_comma(tmp_path):
    """Only the first 20 rows were looked at: a table of whole numbers there and "0,5" below was
    refused ('0,5' is not a number)."""
    # SYNTHETIC: whole hertz 1e4 ... 3 Hz on 22 rows, then 0.5, 0.2, 0.1 Hz; Z' and Z'' in whole ohms, as a coarse meter writes them
    freq = np.concatenate([np.round(np.logspace(4, 0.5, 22)), [0.5, 0.2, 0.1]])
    assert np.unique(freq).size == freq.size
    zc = 100 + 300 / (1 + 1j * 2 * np.pi * freq * 1e-3)
    z = np.round(zc.real) + 1j * np.round(zc.imag)
    rows = [";".join([f"{f:.6g}".replace(".", ","), f"{zi.real:.0f}", f"{zi.imag:.0f}"]) for f, zi in zip(freq, z)]
    (tmp_path / "late.csv").write_text("\n".join(["f (Hz);Z' (Ohm);Z'' (Ohm)", *rows]) + "\n")
    ds = ix.load(tmp_path / "late.csv")
    np.testing.assert_allclose(ds["frequency"].values, [float(f"{f:.6g}") for f in freq], rtol=1e-15)
    np.testing.assert_array_equal(ds["Z"].values, z)
    assert ds.attrs["decimal_mark"] == "comma"


def test_quoted_thousands_in_a_comma_separated_file_are_refused(tmp_path):
    """A US export quotes its thousands: "1,000" is a thousand there, one in a German file."""
    path = tmp_path / "us.csv"
    path.write_text('Frequency (Hz),Z\' (Ohm),Z\'\' (Ohm)\n"1,000",108,-7\n"1,259",107,-9\n"1,585",106,-11\n')
    with pytest.raises(ix.DataError, match=r"us\.csv, line 2: '1,000' is a quoted number .* thousands separator"):
        ix.load(path)


def _fixed_rows(freq, z, sep="\t"):
    return [sep.join(f"{v:.6E}" for v in (f, zi.real, zi.imag)) for f, zi in zip(freq, z)]


@pytest.mark.parametrize("cut, message", [
    (lambda row: row.rsplit("\t", 1)[0], "the last row has 2 fields, but the header has 3"),
    (lambda row: row[:-5], r"column \"Z'' \(Ohm\)\": '-[0-9.]+' on the last row has fewer digits than on every other row"),
    (lambda row: row[:-2], r"column \"Z'' \(Ohm\)\": '-[0-9.]+E-' on the last row has fewer digits"),
])
def test_a_last_row_cut_short_is_refused_naming_its_line(tmp_path, cut, message):
    """A file cut while copying ends without a line end inside its last row: a row of two fields,
    or a last number missing its last digits (read as another value, without a word, before)."""
    freq, z = _lab_spectrum()
    rows = _fixed_rows(freq, z)
    path = tmp_path / "cut.txt"
    path.write_text("\n".join(["Frequency (Hz)\tZ' (Ohm)\tZ'' (Ohm)", *rows[:-1], cut(rows[-1])]))
    with pytest.raises(ix.DataError, match=rf"cut\.txt, line 14: {message}") as err:
        ix.load(path)
    assert "ends without a line end" in str(err.value)
    # the whole file without a final line end, and a cut file's rows with varying digits, read as before
    path.write_text("\n".join(["Frequency (Hz)\tZ' (Ohm)\tZ'' (Ohm)", *rows]))
    np.testing.assert_allclose(ix.load(path)["Z"].values, z, rtol=1e-6)


def test_a_canonical_csv_cut_short_is_refused_as_any_table_is(tmp_path, capsys):
    """impedax's own header (frequency_hz,z_real_ohm,z_imag_ohm) over numpy's fixed '%.18e' rows,
    cut inside the last number (the REAL exampleData.csv's rows so cut: '-4.62397280' for
    -4.623972802104744234e-03, read as -4.62 Ω beside |Z| ≤ 0.054 Ω, silently, before)."""
    freq, z = _lab_spectrum()
    rows = [",".join(f"{v:.18e}" for v in (f, zi.real, zi.imag)) for f, zi in zip(freq, z)]
    path = tmp_path / "cut.csv"
    path.write_text("\n".join(["frequency_hz,z_real_ohm,z_imag_ohm", *rows[:-1], rows[-1][:-9]]))
    with pytest.raises(ix.DataError, match=r"cut\.csv, line 14: column 'z_imag_ohm': '-[0-9.]+' on the last row has fewer digits") as err:
        ix.load(path)
    assert "ends without a line end" in str(err.value)
    from impedax.cli import main
    assert main(["inspect", str(path)]) == 2
    assert "line 14" in capsys.readouterr().err
    # the whole file, with or without its last line end, reads exactly
    for end in ("", "\n"):
        path.write_text("\n".join(["frequency_hz,z_real_ohm,z_imag_ohm", *rows]) + end)
        np.testing.assert_array_equal(ix.load(path)["Z"].values, [complex(*map(float, r.split(",")[1:])) for r in rows])


@pytest.mark.parametrize("header_sep, row_sep, said", [
    (";", ",", "this row is separated by ',' where the header is by ';'"),
    (",", ";", "this row is separated by ';' where the header is by ','"),
    ("\t", ",", "this row is separated by ',' where the header is by a tab"),
    (";", " ", "this row is separated by spaces where the header is by ';'"),
])
def test_rows_separated_otherwise_than_the_header_are_named_as_such(tmp_path, header_sep, row_sep, said):
    """A header typed with ';' over rows exported with ',' was refused as '1 fields, but the
    header has 3', which does not say why; the message now names both delimiters."""
    freq, z = _lab_spectrum()
    rows = [row_sep.join(repr(v) for v in (f, zi.real, zi.imag)) for f, zi in zip(freq.tolist(), z.tolist())]
    path = tmp_path / "mixed.csv"
    path.write_text(header_sep.join(["frequency_hz", "z_real_ohm", "z_imag_ohm"]) + "\n" + "\n".join(rows) + "\n")
    with pytest.raises(ix.DataError) as err:
        ix.load(path)
    message = str(err.value)
    assert message.startswith(f"{path}, line 2: 1 field, but the header has 3 (")
    assert said in message and "one delimiter" in message
    # a row short of a cell, separated as its header is, gets no such note
    rows[3] = header_sep.join(rows[3].split(row_sep)[:2])
    path.write_text(header_sep.join(["frequency_hz", "z_real_ohm", "z_imag_ohm"]) + "\n" + "\n".join(r.replace(row_sep, header_sep) for r in rows) + "\n")
    with pytest.raises(ix.DataError, match=r"mixed\.csv, line 5: 2 fields, but the header has 3 \(a missing or extra cell would shift values\)$"):
        ix.load(path)
    # nor does a line of text under the table, whatever it splits into ('End of data': 3 words)
    path.write_text(header_sep.join(["frequency_hz", "z_real_ohm", "z_imag_ohm"]) + "\n" + "\n".join(r.replace(row_sep, header_sep) for r in rows[:3]) + "\nEnd of data\n")
    with pytest.raises(ix.DataError, match=r"mixed\.csv, line 5: 1 field, but the header has 3 \(a missing or extra cell would shift values\)$"):
        ix.load(path)


def test_decimal_commas_in_a_comma_separated_file_are_named_as_the_cause(tmp_path):
    """A spreadsheet in a decimal-comma locale saved as comma-separated values (SYNTHETIC rows
    "1000,5,120,25,-3,75": 1000.5 Hz, 120.25 Ω, -3.75 Ω): refused, as before, for its field
    count, and the message now says why (until 2026-12-06 only "6 fields, but the header has 3",
    which left users to find the decimal commas themselves); the same numbers separated by ';'
    read as the numbers written."""
    values = [(1000.5, 120.25, -3.75), (100.5, 130.5, -12.25), (10.5, 160.75, -30.5)]
    text = ["{:g}".format(v).replace(".", ",") for row in values for v in row]
    rows = [text[3 * k: 3 * k + 3] for k in range(3)]
    path = tmp_path / "decimal_commas.csv"
    path.write_text("frequency,z_real,z_imag\n" + "\n".join(",".join(r) for r in rows) + "\n")
    with pytest.raises(ix.DataError) as err:
        ix.load(path)
    assert str(err.value) == (f"{path}, line 2: 6 fields, but the header has 3 (a missing or extra cell would shift values); the numbers look written "
                              "with decimal commas in a file whose cells are separated by ',' too, so each comma splits a number ('1000,5' read as "
                              "'1000' and '5'): save it with ';' between cells, or with decimal points")
    path.write_text("frequency;z_real;z_imag\n" + "\n".join(";".join(r) for r in rows) + "\n")
    loaded = ix.load(path)
    np.testing.assert_array_equal(loaded["frequency"].values, [1000.5, 100.5, 10.5])
    np.testing.assert_array_equal(loaded["Z"].values, [120.25 - 3.75j, 130.5 - 12.25j, 160.75 - 30.5j])
    # a row with one cell too many that no decimal comma explains ('-12,-7' is no number): no such note
    path.write_text("frequency,z_real,z_imag\n1000,120,-3\n100,130,-12,-7\n")
    with pytest.raises(ix.DataError, match=r"line 3: 4 fields, but the header has 3 \(a missing or extra cell would shift values\)$"):
        ix.load(path)


def test_a_header_less_table_with_the_frequency_last_is_refused_naming_the_column(tmp_path):
    """Z', Z'', f without a header was read as f = Z', Z' = Z'', Z'' = f, silently."""
    freq, z = _lab_spectrum()
    path = tmp_path / "order.csv"
    path.write_text("\n".join(f"{zi.real!r},{zi.imag!r},{f!r}" for f, zi in zip(freq.tolist(), z.tolist())) + "\n")
    with pytest.raises(ix.DataError, match=r"order\.csv, line 1: no header, and column 1 does not look like frequencies .* where column 3 does.*z_real_ohm,z_imag_ohm,frequency_hz"):
        ix.load(path)
    # Z'', Z', f (column 1 negative: 'frequency must be positive' before) gets the same message
    path.write_text("\n".join(f"{zi.imag!r},{zi.real!r},{f!r}" for f, zi in zip(freq.tolist(), z.tolist())) + "\n")
    with pytest.raises(ix.DataError, match=r"order\.csv, line 1: no header, and column 1 does not look like frequencies .* where column 3 does"):
        ix.load(path)
    # in the order f, Z', Z'' (a DC row first) it reads as before
    path.write_text("\n".join(["0,350.0,0.0", *(f"{f!r},{zi.real!r},{zi.imag!r}" for f, zi in zip(freq.tolist(), z.tolist()))]) + "\n")
    np.testing.assert_allclose(ix.load(path)["Z"].values, z, rtol=1e-15)


def test_xlsx_formulas_without_stored_values_are_named_by_sheet_and_cell(tmp_path):
    """openpyxl (and other programs without a spreadsheet engine) store formulas but no values:
    the cells read empty ('column Z' is empty (missing value)'); now the message names the cell
    and says how to get the values stored."""
    openpyxl = pytest.importorskip("openpyxl")
    workbook = openpyxl.Workbook()
    sheet = workbook.active
    sheet.title = "run 1"
    sheet.append(["Frequency (Hz)", "Z' (Ohm)", "Z'' (Ohm)"])
    for row, f in enumerate(np.logspace(5, -1, 7).tolist(), start=2):  # SYNTHETIC: the RC spectrum, as formulas
        sheet.append([f, f"=100+300/(1+(2*PI()*A{row}*0.001)^2)", f"=-300*2*PI()*A{row}*0.001/(1+(2*PI()*A{row}*0.001)^2)"])
    workbook.save(tmp_path / "calc.xlsx")
    with pytest.raises(ix.DataError, match=r"calc\.xlsx \[sheet run 1\]: cell B2 holds a formula \(=100\+300/.*\) with no stored value, and so do 13 more cells.*open it in a spreadsheet program"):
        ix.load(tmp_path / "calc.xlsx")
