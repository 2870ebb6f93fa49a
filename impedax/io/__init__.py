"""Reading and writing spectra: `load` recognises the file by content and extension."""

from __future__ import annotations

import os
from pathlib import Path

import xarray as xr

from ..data import validate_spectrum
from ..errors import DataError
from ._csv import CSV_HEADER as CSV_HEADER, read_csv as read_csv, write_csv as write_csv
from ._netcdf import read_netcdf as read_netcdf, write_netcdf as write_netcdf

__all__ = ["load", "save", "read_csv", "write_csv", "read_netcdf", "write_netcdf", "CSV_HEADER"]

_NETCDF_MAGIC = (b"CDF\x01", b"CDF\x02", b"CDF\x05", b"\x89HDF")


def load(path: str | os.PathLike) -> xr.Dataset:
    """Load a spectrum file into the impedax data model (see `impedax.data`).

    netCDF (``.nc``, written by `save`) and delimited text (CSV/TSV/whitespace) are recognised.
    Raises `DataError` naming the file (and line) on any problem.
    """
    if isinstance(path, xr.Dataset):
        return validate_spectrum(path)
    path = Path(path)
    if not path.exists():
        raise DataError("file not found", path=path)
    if path.is_dir():
        raise DataError("is a directory, not a spectrum file", path=path)
    with open(path, "rb") as fh:
        head = fh.read(8)
    if path.suffix.lower() in (".nc", ".nc4", ".cdf") or head.startswith(_NETCDF_MAGIC):
        ds = read_netcdf(path)
    else:
        ds = read_csv(path)
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
