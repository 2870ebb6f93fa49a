"""Spectrum data model, CSV and netCDF readers/writers, and their errors."""

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.io import read_csv, write_csv
from loading import assert_load_names


def _spectrum(n=12):
    f = np.geomspace(1, 1e5, n)
    z = 100 + 1000 / (1 + 1j * 2 * np.pi * f * 1e-4)
    return ix.make_spectrum(f, z)


def test_csv_round_trip_is_exact(tmp_path):
    ds = _spectrum()
    path = tmp_path / "s.csv"
    ix.save(ds, path)
    assert path.read_text().splitlines()[0] == "frequency_hz,z_real_ohm,z_imag_ohm"
    back = ix.load(path)
    np.testing.assert_array_equal(back["Z"].values, ds["Z"].values)
    np.testing.assert_array_equal(back["frequency"].values, ds["frequency"].values)


def test_csv_numbers_are_written_in_their_shortest_exact_form(tmp_path):
    """9904.999 is written ``9904.999``, not 17 digits' ``9904.9989999999998``, and every
    value (awkward ones included) reads back bit for bit."""
    f = np.array([9904.999, 0.1, 1e-300, 123456789.123])
    z = np.array([9904.999 - 0.3j, 1 / 3 - 2e-17j, 5e-324 - 1e300j, 2.0**0.5 - 7j])
    sigma = np.array([0.1, 0.2, 0.30000000000000004, 1e-5])
    ds = ix.make_spectrum(f, z)
    ds["sigma"] = ("frequency", sigma)
    path = tmp_path / "s.csv"
    ix.save(ds, path)
    rows = [line.split(",") for line in path.read_text().splitlines()[1:]]
    assert rows[0][:2] == ["9904.999", "9904.999"] and rows[0][3] == "0.1"
    assert rows[2][3] == "0.30000000000000004"  # (not the neighbouring 0.3)
    back = ix.load(path)
    assert back["frequency"].values.tobytes() == ds["frequency"].values.tobytes()
    assert back["Z"].values.tobytes() == ds["Z"].values.tobytes()
    assert back["sigma"].values.tobytes() == ds["sigma"].values.tobytes()


def test_a_tsv_file_is_tab_separated_and_reads_back_exactly(tmp_path):
    ds = _spectrum()
    path = tmp_path / "s.tsv"
    ix.save(ds, path)
    assert path.read_text().splitlines()[0] == "frequency_hz\tz_real_ohm\tz_imag_ohm"
    np.testing.assert_array_equal(ix.load(path)["Z"].values, ds["Z"].values)


def test_netcdf_round_trip_is_lossless_with_extra_dims_and_sigma(tmp_path):
    rng = np.random.default_rng(0)
    f = np.geomspace(1, 1e6, 20)
    z = rng.normal(size=(3, 10, 20)) + 1j * rng.normal(size=(3, 10, 20))
    ds = ix.make_spectrum(f, z, sigma=np.abs(z) * 0.01 + 1e-3, dims=("session", "trial"), coords={"session": [1, 2, 3], "trial": np.arange(10)}, attrs={"synthetic": "yes", "meta": {"a": 1}})
    path = tmp_path / "s.nc"
    ix.save(ds, path)
    back = ix.load(path)
    assert back["Z"].dims == ("session", "trial", "frequency")
    np.testing.assert_array_equal(back["Z"].values, z)
    np.testing.assert_array_equal(back["sigma"].values, ds["sigma"].values)
    np.testing.assert_array_equal(back["trial"].values, np.arange(10))
    assert back["trial"].dtype == np.arange(10).dtype
    assert back.attrs["meta"] == {"a": 1} and back.attrs["synthetic"] == "yes"
    xr.testing.assert_identical(back.drop_attrs(deep=False), ds.drop_attrs(deep=False))


@pytest.mark.parametrize(
    "header, transform",
    [
        ("freq,Zreal,Zimag", lambda z: (z.real, z.imag)),
        ("Frequency (Hz)\tZ' (Ohm)\t-Z'' (Ohm)", lambda z: (z.real, -z.imag)),
        ("f;re(z);im(z)", lambda z: (z.real, z.imag)),
        ("freq -Zimag Zreal", None),
        ("Frequency (kHz),|Z|,phase", "polar"),
    ],
)
def test_csv_header_variants(tmp_path, header, transform):
    ds = _spectrum(6)
    f, z = ds["frequency"].values, ds["Z"].values
    delim = "\t" if "\t" in header else ";" if ";" in header else "," if "," in header else " "
    rows = []
    for fi, zi in zip(f, z):
        if transform is None:
            vals = (fi, -zi.imag, zi.real)
        elif transform == "polar":
            vals = (fi / 1e3, abs(zi), np.degrees(np.angle(zi)))
        else:
            vals = (fi, *transform(np.array(zi)))
        rows.append(delim.join(f"{v:.17g}" for v in vals))
    path = tmp_path / "v.txt"
    path.write_text("# comment line\n" + header + "\n" + "\n".join(rows) + "\n")
    back = read_csv(path)
    np.testing.assert_allclose(back["frequency"].values, f, rtol=1e-15)
    np.testing.assert_allclose(back["Z"].values, z, rtol=1e-13)


@pytest.mark.parametrize(
    "content, line, fragment",
    [
        ("", None, "empty"),
        ("frequency_hz,z_real_ohm,z_imag_ohm\n", 1, "no data rows"),
        ("frequency_hz,foo,bar\n1,2,3\n", 1, "cannot find impedance columns"),
        ("foo,z_real_ohm,z_imag_ohm\n1,2,3\n", 1, "no frequency column"),
        ("1,2,3,4\n4,5,6,7\n", 1, "not a header"),
        ("frequency_hz,z_real_ohm,z_imag_ohm\n1,2,3\n2,abc,3\n", 3, "is not a number"),
        ("frequency_hz,z_real_ohm,z_imag_ohm\n1,2,3\n2,nan,3\n", 3, "NaN/Inf"),
        ("frequency_hz,z_real_ohm,z_imag_ohm\n1,2,3\n2,inf,3\n", 3, "NaN/Inf"),
        ("frequency_hz,z_real_ohm,z_imag_ohm\n1,2,3\n-5,2,3\n", 3, "positive"),
        ("frequency_hz,z_real_ohm,z_imag_ohm\n1,2,3\n\n1,2,3\n", 4, "duplicate frequency 1 Hz (also on line 2)"),
        ("frequency_hz,z_real_ohm,z_imag_ohm\n1,2,3\n2,2\n", 3, "2 fields"),
        ("frequency_hz,z_real_ohm,z_imag_ohm,-z_imag_ohm\n1,2,3,4\n", 1, "keep one"),
        # a missing or extra cell is an error naming the row, never a shift of values
        ("frequency_hz,z_real_ohm,z_imag_ohm\n1,2,-3\n2,,-3\n", 3, "'z_real_ohm' is empty (missing value)"),
        ("frequency_hz,z_real_ohm,z_imag_ohm\n1,2,-3\n2,3\n", 3, "2 fields, but the header has 3"),
        ("f\tZ'\tZ''\n1\t2\t-3\n2\t3\t-4\t5\n", 3, "4 fields, but the header has 3"),
        ("freq Zreal Zimag\n1 2 -3\n2 -3\n", 3, "2 fields"),
    ],
)
def test_bad_csv_names_file_and_line(tmp_path, content, line, fragment):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    assert_load_names(path, fragment, line)


@pytest.mark.parametrize(
    "content, line",
    [
        ("1000,10.5,-3.2\n100,12.1,-8.4\n10,20.3,-15.6\n1,40", 4),  # the last row, cut short
        ("1000,10.5,-3.2\n100,12.1\n10,20.3,-15.6\n1,40,-30\n", 2),  # a middle row missing a cell
    ],
)
def test_headerless_csv_row_short_of_fields_names_no_header(tmp_path, content, line):
    """A file without header has no header to count against: a row short of fields is refused
    against the three columns (f, Z', Z'') every other row has."""
    path = tmp_path / "cut.csv"
    path.write_text(content)
    with pytest.raises(ix.DataError) as info:
        ix.load(path)
    message = str(info.value)
    assert f"line {line}" in message and "2 fields" in message
    assert "the header has" not in message
    assert "without header has 3 (f, Z', Z'')" in message


def test_binary_and_missing_files(tmp_path):
    path = tmp_path / "garbage.csv"
    path.write_bytes(bytes(range(256)) * 4)
    with pytest.raises(ix.DataError, match="binary"):
        ix.load(path)
    with pytest.raises(ix.DataError, match="not found"):
        ix.load(tmp_path / "nope.csv")
    with pytest.raises(ix.DataError, match="not a readable netCDF"):
        (tmp_path / "x.nc").write_text("hello")
        ix.load(tmp_path / "x.nc")


def test_data_model_validation():
    f = np.array([1.0, 2.0, 3.0])
    with pytest.raises(ix.DataError, match="duplicate"):
        ix.make_spectrum([1.0, 1.0, 2.0], np.ones(3) + 0j)
    with pytest.raises(ix.DataError, match="non-finite"):
        ix.make_spectrum(f, np.array([1, np.nan, 2]) + 0j)
    with pytest.raises(ix.DataError, match="dimensions"):
        ix.make_spectrum(f, np.ones((2, 3)) + 0j)
    ds = ix.make_spectrum(f[::-1], np.ones(3) * (1 - 1j))
    assert list(ds["frequency"].values) == [3.0, 2.0, 1.0]  # order kept, never silently sorted
    with pytest.raises(ix.DataError, match="one spectrum"):
        write_csv(ix.make_spectrum(f, np.ones((2, 3)) + 0j, dims=("trial",)))


def test_failed_write_leaves_no_partial_file(tmp_path, monkeypatch):
    ds = _spectrum()
    target = tmp_path / "keep.csv"
    target.write_text("old content\n")

    def boom(self, *a, **k):
        raise OSError("disk full")

    monkeypatch.setattr("pathlib.Path.write_text", boom)
    with pytest.raises(OSError):
        ix.save(ds, target)
    monkeypatch.undo()
    assert target.read_text() == "old content\n"
    assert [p.name for p in tmp_path.iterdir()] == ["keep.csv"]
    with pytest.raises(ix.DataError, match="does not exist"):
        ix.save(ds, tmp_path / "no" / "dir.csv")


def test_written_files_get_the_usual_permissions(tmp_path):
    import os

    umask = os.umask(0o022)
    try:
        ix.save(_spectrum(), tmp_path / "p.csv")
    finally:
        os.umask(umask)
    assert (tmp_path / "p.csv").stat().st_mode & 0o777 == 0o644


def test_a_saved_spectrum_read_back_names_its_file(tmp_path):
    """A spectrum built in a session (source "memory") and saved: read back, its errors name the
    file (they had said "memory: ..."), and where it came from stays as ``saved_from``."""
    f = np.geomspace(1, 1e4, 10)
    ds = ix.make_spectrum(f, 10 + 100 / (1 + 1j * f / 100))
    assert ds.attrs["source"] == "memory"
    path = tmp_path / "spec.nc"
    ix.save(ds, path)
    back = ix.load(path)
    assert back.attrs["source"] == str(path) and back.attrs["saved_from"] == "memory"
    with pytest.raises(ix.DataError, match=str(path)):
        ix.fit("R0 + R1 || C1", back.assign_coords(frequency=-back["frequency"]))


def test_a_csv_impedax_wrote_gives_back_its_provenance_as_a_netcdf_file_does(tmp_path, capsys):
    """A spectrum saved as CSV with a provenance record (as every command's --out writes it:
    the record's columns after the spectrum's) read back: the attrs impedax_version,
    written_utc, provenance (the record, settings as typed back from their cells) and
    saved_from (the data's source), as the same spectrum saved as .nc has them; until
    2026-12-06 the columns were only listed in other_columns, and `impedax inspect` did not say
    what wrote the file. SYNTHETIC spectrum; the record is written here by hand."""
    import json

    from impedax.cli import main

    record = {"impedax_version": "0.1.0", "written_utc": "2026-12-06T10:00:00Z", "command": "impedax simulate",
              "settings": {"model": "R0 + R1 || C1", "seed": 5, "c": 0.85, "quiet": False, "select": None, "param": ["R1=1k", "C1=1u"]},
              "source": "run1.mpt", "data_files": ["/data/run1.mpt", "/data/run2.mpt"]}
    path = tmp_path / "saved.csv"
    ix.save(_spectrum(), path, provenance=record)
    data = ix.load(path)
    assert (data.attrs["impedax_version"], data.attrs["written_utc"], data.attrs["saved_from"]) == ("0.1.0", "2026-12-06T10:00:00Z", "run1.mpt")
    # (a list setting comes back as its cell, the items joined by "; ", as docs/io.md says to split it)
    assert json.loads(data.attrs["provenance"]) == {**record, "settings": {**record["settings"], "param": "R1=1k; C1=1u"}}
    assert main(["inspect", str(path)]) == 0
    assert ("  provenance: impedax simulate, 2026-12-06T10:00:00Z (impedax 0.1.0); settings model=R0 + R1 || C1, seed=5, c=0.85, param=R1=1k; C1=1u; "
            "data /data/run1.mpt, /data/run2.mpt") in capsys.readouterr().out.splitlines()
    np.testing.assert_array_equal(data["Z"].values, _spectrum()["Z"].values)
    # a CSV without the record, or whose cells differ from row to row, has none
    ix.save(_spectrum(), path)
    assert "provenance" not in ix.load(path).attrs
    ix.save(_spectrum(), path, provenance=record)
    lines = path.read_text().splitlines()
    lines[2] = lines[2].replace("impedax simulate", "impedax fit")
    path.write_text("\n".join(lines) + "\n")
    assert "provenance" not in ix.load(path).attrs
