"""Reading and writing spectra: `load` recognises the file by content and extension."""

from __future__ import annotations

import os
from pathlib import Path

import xarray as xr

from ..data import validate_spectrum
from ..errors import DataError
from .csv import CSV_HEADER as CSV_HEADER, UnrecognisedText, read_csv as read_csv, write_csv as write_csv
from ._instruments import (
    READERS as READERS,
    Reader as Reader,
    read_autolab as read_autolab,
    read_biologic as read_biologic,
    read_gamry as read_gamry,
    read_labone_csv as read_labone_csv,
    read_labone_hdf5 as read_labone_hdf5,
    read_zplot as read_zplot,
)
from .netcdf import read_netcdf as read_netcdf, write_netcdf as write_netcdf

__all__ = [
    "load", "save", "read_csv", "write_csv", "read_netcdf", "write_netcdf", "CSV_HEADER", "READERS", "Reader",
    "read_gamry", "read_biologic", "read_zplot", "read_autolab", "read_labone_csv", "read_labone_hdf5",
]

_NETCDF_MAGIC = (b"CDF\x01", b"CDF\x02", b"CDF\x05", b"\x89HDF")
_NETCDF_SUFFIXES = (".nc", ".nc4", ".cdf")
_SNIFF_BYTES = 65536


def load(path: str | os.PathLike) -> xr.Dataset:
    """Load a spectrum file into the impedax data model (see `impedax.data`).

    Recognised by content and extension: netCDF written by `save`, the instrument exports in
    `READERS` (Gamry .DTA, BioLogic .mpt, Scribner ZPlot .z, Metrohm Autolab NOVA text,
    Zurich Instruments LabOne CSV/HDF5) and delimited text (CSV/TSV/whitespace). Raises
    `DataError` naming the file (and line); an unrecognised file's error lists each format
    tried and why it did not fit.
    """
    if isinstance(path, xr.Dataset):
        return validate_spectrum(path)
    path = Path(path)
    if not path.exists():
        raise DataError("file not found", path=path)
    if path.is_dir():
        raise DataError("is a directory, not a spectrum file", path=path)
    try:
        with open(path, "rb") as fh:
            head = fh.read(_SNIFF_BYTES)
    except OSError as exc:
        raise DataError(f"cannot read file: {exc.strerror}", path=path) from None
    suffix = path.suffix.lower()
    if suffix in _NETCDF_SUFFIXES or (head.startswith(_NETCDF_MAGIC[:3])):
        return validate_spectrum(read_netcdf(path), source=str(path))
    # readers whose extension matches go first, so a .mpt is not mistaken for generic text
    ordered = sorted(READERS, key=lambda r: suffix not in r.extensions)
    tried = []
    for reader in ordered:
        reason = reader.sniff(path, head)
        if reason is None:
            return validate_spectrum(reader.read(path), source=str(path))
        tried.append(f"{reader.name}: {reason}")
    try:
        ds = read_csv(path)
    except UnrecognisedText as exc:
        tried.append("delimited text: the reason given first")
        raise DataError(f"{exc.reason} — not a recognised spectrum file; formats tried: {'; '.join(tried)}", path=exc.path, line=exc.line) from None
    return validate_spectrum(ds, source=str(path))


def save(ds: xr.Dataset, path: str | os.PathLike) -> None:
    """Save a spectrum: ``.nc`` → lossless netCDF, ``.csv``/``.txt`` → canonical CSV. Atomic."""
    path = Path(path)
    validate_spectrum(ds)
    if path.suffix.lower() in (".nc", ".nc4", ".cdf"):
        write_netcdf(ds, path)
    elif path.suffix.lower() in (".csv", ".txt", ".tsv", ""):
        write_csv(ds, path)
    else:
        raise DataError(f"unknown output format {path.suffix!r}; use .nc or .csv", path=path)
