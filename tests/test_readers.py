"""Instrument readers: hand-made fixtures in each format's real layout (tests/fixtures/).

Every fixture holds the same synthetic spectrum, Z = 100 + 1000/(1 + j·2πf·1 ms) Ω at
1e5 ... 1 Hz, written with each file's own precision, sign convention and decimal mark; the
oracle below is that formula, written here independently of the files.
"""

import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.io import READERS

FIXTURES = Path(__file__).parent / "fixtures"


def oracle(f):
    return 100 + 1000 / (1 + 1j * 2 * np.pi * np.asarray(f) * 1e-3)


DESCENDING = np.array([1e5, 1e4, 1e3, 100.0, 10.0, 1.0])


@pytest.mark.parametrize(
    "name, fmt, rtol, attrs",
    [
        ("gamry_eispot.DTA", "Gamry DTA", 1e-6, {"instrument": "Gamry", "date": "3/14/2024 10:29:09", "instrument_serial": "REF600-12345", "experiment": "EISPOT"}),
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
    with pytest.raises(ix.DataError) as info:
        ix.load(path)
    msg = str(info.value)
    assert str(path) in msg and fragment in msg
    if line is not None:
        assert f"line {line}:" in msg


def test_unrecognised_file_lists_every_format_tried(tmp_path):
    path = tmp_path / "mystery.txt"
    path.write_text("voltage,current\n1,2\n")
    with pytest.raises(ix.DataError) as info:
        ix.load(path)
    msg = str(info.value)
    assert "not a recognised spectrum file" in msg and "\n" not in msg
    for reader in READERS:
        assert reader.name + ": " in msg
    assert "delimited text" in msg and "no frequency column" in msg


def test_hdf5_without_h5py_says_how_to_get_it(tmp_path, monkeypatch):
    path = tmp_path / "sweep.h5"
    path.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(200))
    monkeypatch.setitem(sys.modules, "h5py", None)  # import h5py now raises ImportError
    with pytest.raises(ix.DataError, match=r"pip install h5py"):
        ix.load(path)


def test_labone_hdf5_with_h5py(tmp_path):
    h5py = pytest.importorskip("h5py")
    f = np.geomspace(1, 1e5, 7)
    z = oracle(f)
    path = tmp_path / "sweep.h5"
    with h5py.File(path, "w") as fh:
        g = fh.create_group("000/dev3000/imps/0/sample")
        g["grid"], g["frequency"], g["realz"], g["imagz"] = f, f, z.real, z.imag
    ds = ix.load(path)
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-15)
    assert ds.attrs["hdf5_group"] == "000/dev3000/imps/0/sample"
