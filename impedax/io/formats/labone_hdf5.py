"""Zurich Instruments LabOne HDF5 exports (needs the optional ``h5py``: ``pip install impedax[hdf5]``).

Every group holding ``realz`` and ``imagz`` (or ``absz`` and ``phasez``) with ``frequency`` (or
``grid``) datasets is one sweep; several sweeps on the same grid become a ``sweep`` dimension.

Conventions: as the LabOne CSV export: frequency in Hz; Z = ``realz`` + j·``imagz`` in Ω, or
``absz``·exp(j·``phasez``) with the phase in radians (``absz`` and ``phasez`` beside ``realz`` and
``imagz`` are compared with them: `labone_csv.polar_attrs`). Datasets larger than the file-size
limit are refused before they are read.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from ...errors import DataError
from .._common import finish, max_file_bytes, optional_module, stack
from ..registry import Reader
from .labone_csv import phasez_note, polar_attrs, recorded_columns, sign_convention

__all__ = ["read_labone_hdf5", "READER", "HDF5_MAGIC"]

CONVENTIONS = "HDF5 groups with frequency/grid [Hz] and realz, imagz [Ω] (or absz, phasez [rad])"
HDF5_MAGIC = b"\x89HDF\r\n\x1a\n"


def sniff(path: Path, head: bytes) -> str | None:
    if head.startswith(HDF5_MAGIC) and path.suffix.lower() not in (".nc", ".nc4", ".cdf"):
        return None
    return "no HDF5 signature"


def read_labone_hdf5(path: str | Path) -> xr.Dataset:
    """Read a LabOne HDF5 export (see module docstring)."""
    path = Path(path)
    h5py = optional_module("h5py", path, "this is an HDF5 file (e.g. a LabOne HDF5 export); reading HDF5 needs h5py: pip install h5py, or export CSV from LabOne")
    found: list[tuple[str, np.ndarray, np.ndarray]] = []

    def load(dataset) -> np.ndarray:
        if dataset.size * 16 > max_file_bytes():
            raise DataError(f"dataset {dataset.name} holds {dataset.size} values; too large for a spectrum", path=path)
        return np.asarray(dataset[()], dtype=float).ravel()

    try:
        with h5py.File(path, "r") as fh:

            def visit(name, obj):
                if not isinstance(obj, h5py.Group):
                    return
                keys = set(obj.keys())
                fkey = "frequency" if "frequency" in keys else "grid" if "grid" in keys else None
                if fkey is None:
                    return
                if {"realz", "imagz"} <= keys:
                    re_, im_ = load(obj["realz"]), load(obj["imagz"])
                    if re_.shape != im_.shape:
                        raise DataError(f"{name}: {re_.size} realz but {im_.size} imagz values", path=path)
                    z, parts = re_ + 1j * im_, ("realz", "imagz")
                    checked = {}
                    if all(isinstance(obj.get(k), h5py.Dataset) for k in ("absz", "phasez")):
                        try:  # (|Z| and the phase beside Z: compared, never a reason to refuse the file)
                            polar = {"realz": re_, "imagz": im_, "absz": load(obj["absz"]), "phasez": load(obj["phasez"])}
                        except (DataError, ValueError, TypeError):
                            polar = None
                        checked = polar_attrs(z, polar, range(z.size), path.name, "point") if polar else {}
                elif {"absz", "phasez"} <= keys:
                    mod, ph = load(obj["absz"]), load(obj["phasez"])
                    if mod.shape != ph.shape:
                        raise DataError(f"{name}: {mod.size} absz but {ph.size} phasez values", path=path)
                    z, parts = mod * np.exp(1j * ph), ("absz", "phasez")
                    checked = phasez_note(ph)
                else:
                    return
                found.append((name, load(obj[fkey]), z, parts, recorded_columns(fkey, parts), checked))

            fh.visititems(visit)
    except (OSError, ValueError, TypeError, KeyError) as exc:
        if isinstance(exc, DataError):
            raise
        raise DataError(f"not a readable HDF5 file ({str(exc).splitlines()[0] if str(exc) else type(exc).__name__})", path=path) from None
    if not found:
        raise DataError("HDF5 file holds no group with frequency/grid and realz/imagz datasets (LabOne impedance sweep)", path=path)
    spectra = []
    for name, freq, z, parts, columns, note in found:
        if freq.shape != z.shape:
            raise DataError(f"{name}: {freq.size} frequencies but {z.size} impedance values", path=path)
        bad = np.flatnonzero(~np.isfinite(freq) | ~np.isfinite(z))
        if bad.size:
            raise DataError(f"{name}: point {bad[0]} is not finite (unfinished sweep?)", path=path)
        attrs = {"format": "Zurich Instruments LabOne HDF5", "instrument": "Zurich Instruments", "hdf5_group": name,
                 "sign_convention": sign_convention(parts), "units": "Hz, ohm", "columns": columns, **note}
        spectra.append((name, finish(path, freq, z, list(range(freq.size)), attrs)))
    return stack(path, spectra, "sweep")


READER = Reader("LabOne HDF5", (".h5", ".hdf5"), sniff, read_labone_hdf5, CONVENTIONS)
