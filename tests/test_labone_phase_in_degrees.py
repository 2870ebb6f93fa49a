"""LabOne stores ``phasez`` in radians (its format says so; impedax reads absz·exp(j·phasez)).
A phase beyond ±2π cannot be radians: like a ``Phase (rad)`` column of a delimited table, such a
file now gets a ``phase_unit_note`` (SYNTHETIC RC spectra written here)."""

import numpy as np
import pytest

import impedax as ix

F = np.array([10.0, 100.0, 1000.0, 10000.0])
R, C = 1000.0, 1e-6  # an RC parallel: its phase −atan(ωRC) runs from −3.6° to −89.1° over F
Z = R / (1 + 2j * np.pi * F * R * C)
DEGREES = np.degrees(np.angle(Z))


def _csv(path, phase):
    rows = ["timestamp;frequency;absz;phasez"] + [f"{i};{f!r};{abs(z)!r};{p!r}" for i, (f, z, p) in enumerate(zip(F.tolist(), Z.tolist(), phase.tolist()))]
    path.write_text("\n".join(rows) + "\n")
    return path


def _h5(path, phase):
    h5py = pytest.importorskip("h5py")
    with h5py.File(path, "w") as fh:
        g = fh.create_group("000/dev3000/imps/0/sample")
        g["frequency"], g["absz"], g["phasez"] = F, np.abs(Z), phase
    return path


@pytest.mark.parametrize("write, name", [(_csv, "sweep.csv"), (_h5, "sweep.h5")])
def test_labone_phasez_in_degrees_gets_the_note(tmp_path, write, name):
    """phasez written in degrees, −3.6 to −89.1 (−89.1 = −atan(2π·10 kHz·1 ms) in degrees, by
    hand): read as radians, as the format says, with a note naming the field and −89.1."""
    assert DEGREES.min() == pytest.approx(-np.degrees(np.arctan(2 * np.pi * 1e4 * 1e-3)))
    ds = ix.load(write(tmp_path / name, DEGREES))
    np.testing.assert_allclose(ds["Z"].values, np.abs(Z) * np.exp(1j * DEGREES), rtol=1e-12)  # (as radians: no guess)
    note = ds.attrs["phase_unit_note"]
    assert "'phasez'" in note and "-89.1" in note and "±2π" in note, note


@pytest.mark.parametrize("write, name", [(_csv, "sweep.csv"), (_h5, "sweep.h5")])
def test_labone_phasez_in_radians_gets_none(tmp_path, write, name):
    ds = ix.load(write(tmp_path / name, np.angle(Z)))
    np.testing.assert_allclose(ds["Z"].values, Z, rtol=1e-12)
    assert "phase_unit_note" not in ds.attrs


@pytest.mark.parametrize("write, name", [(_csv, "sweep.csv"), (_h5, "sweep.h5")])
def test_labone_sign_convention_names_the_fields_read(tmp_path, write, name):
    """A sweep of absz and phasez says so in ``sign_convention`` (what `impedax inspect` prints);
    the HDF5 reader said "realz, imagz hold Z', Z'' as stored" until 2026-12-06."""
    ds = ix.load(write(tmp_path / name, np.angle(Z)))
    assert ds.attrs["sign_convention"] == "Z = absz·exp(j·phasez), phase in radians"
