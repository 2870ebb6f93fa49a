"""A table without header is read as f, Z', Z''. Written in another order, a column of Z' that
falls monotonically over decades (an RC's, Meyer's finger circuit's) passed for the frequencies:
Z', Z'', f of `impedax simulate meyer`'s output was read with Z' as f and fitted to nonsense,
with a hint that the real part's sign was flipped (walkthrough 2026-12-07). It is refused,
naming the column that steps by a constant ratio as a sweep does. Oracle: SYNTHETIC spectra
written here with numpy; the REAL header-less exampleData.csv (impedance.py, MIT) still reads."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix

REAL = Path(__file__).resolve().parent / "fixtures" / "real"


def meyer(f):
    s = 2j * np.pi * f
    return 1 / (s * 140e-12) + 1 / (s * 1.7e-9) + 130e3 / (1 + s * 130e3 * 2.2e-9) + 500.0


def rc(f):
    return 100.0 + 1e4 / (1 + 2j * np.pi * f * 1e4 * 1e-6)


def write(path, columns):
    path.write_text("".join(",".join(repr(float(v)) for v in row) + "\n" for row in zip(*columns)))
    return path


@pytest.mark.parametrize("spectrum", [meyer, rc])
@pytest.mark.parametrize("order, at, header", [
    ("re im f", 3, "z_real_ohm,z_imag_ohm,frequency_hz"),
    ("re f im", 2, "z_real_ohm,frequency_hz,z_imag_ohm"),
    ("im re f", 3, "z_real_ohm,z_imag_ohm,frequency_hz"),
])
def test_a_headerless_table_in_another_order_is_refused(tmp_path, spectrum, order, at, header):
    f = np.geomspace(1e6, 1.0, 61)
    z = spectrum(f)
    named = {"f": f, "re": z.real, "im": z.imag}
    path = write(tmp_path / "s.csv", [named[k] for k in order.split()])
    with pytest.raises(ix.DataError) as info:
        ix.load(path)
    text = str(info.value)
    assert "no header" in text and f"column {at} does" in text and header in text


@pytest.mark.parametrize("spectrum", [meyer, rc])
def test_the_same_values_as_f_re_im_read(tmp_path, spectrum):
    f = np.geomspace(1e6, 1.0, 61)
    f = f[np.abs(f - 50.0) > 5.0]  # (a sweep that skips the mains frequency: its steps are not all one ratio)
    z = spectrum(f)
    ds = ix.load(write(tmp_path / "s.csv", [f, z.real, z.imag]))
    np.testing.assert_array_equal(ds["frequency"].values, f)
    np.testing.assert_array_equal(ds["Z"].values, z)


def test_real_headerless_file_still_reads():
    ds = ix.load(REAL / "exampleData.csv")
    assert ds.sizes["frequency"] == 66 and ds.attrs["interpretation"].startswith("no header")
