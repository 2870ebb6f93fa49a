"""`load` and `save`: a spectrum file in, the impedax data model out (and back).

A file is recognised by its content: each reader's ``sniff`` looks at the first 64 kB (and the
name) and the first that claims the file reads it; plain delimited text is the fallback. A file
no reader claims raises one `DataError` listing, in one short line each, every format tried and
why it did not fit. Files that are not regular files (``/dev/zero``, pipes) or are larger than
`MAX_FILE_BYTES` are refused before anything is read.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Sequence

import xarray as xr

from ..data import validate_spectrum
from ..errors import DataError
from ._common import MAX_FILE_BYTES, check_file
from .csv import read_csv, write_csv
from .netcdf import write_netcdf
from .registry import Reader
from .table import NoLayout

__all__ = ["load", "save", "identify", "MAX_FILE_BYTES"]

SNIFF_BYTES = 65536


def _head(path: Path) -> bytes:
    check_file(path)
    try:
        with open(path, "rb") as fh:
            return fh.read(SNIFF_BYTES)
    except OSError as exc:
        raise DataError(f"cannot read file: {exc.strerror}", path=path) from None


def identify(path: str | os.PathLike, readers: Sequence[Reader] | None = None) -> tuple[Reader | None, list[str]]:
    """The reader that claims ``path`` (``None`` for plain text) and the reasons of those that did not."""
    if readers is None:
        from .formats import READERS as readers
    path = Path(path)
    head = _head(path)
    tried = []
    for reader in readers:
        try:
            reason = reader.sniff(path, head)
        except Exception as exc:  # a user's sniff must not hide the other formats
            reason = f"sniff failed ({type(exc).__name__})"
        if reason is None:
            return reader, tried
        tried.append(f"{reader.name}: {reason}")
    return None, tried


def load(path: str | os.PathLike, readers: Sequence[Reader] | None = None) -> xr.Dataset:
    """Load a spectrum file into the impedax data model (see `impedax.data`).

    ``readers`` is the registry to try, in order (default `impedax.io.READERS`; extend it with
    `impedax.io.register_reader`). Recognised by content: netCDF written by `save`, every
    instrument export in the registry (see docs/io.md) and delimited text with or without a
    header. Rows that are not impedance points (DC rows at f = 0, repeated headers) are skipped
    and listed in ``attrs["skipped_rows"]``; ``attrs["sign_convention"]`` and ``attrs["units"]``
    say how Z was read. Raises `DataError` naming the file (and line).
    """
    if isinstance(path, xr.Dataset):
        return validate_spectrum(path)
    path = Path(path)
    reader, tried = identify(path, readers)
    if reader is not None:
        ds = reader.read(path)
        ds.attrs.setdefault("format", reader.name)
        return validate_spectrum(ds, source=str(path))
    try:
        ds = read_csv(path)
    except NoLayout as exc:
        tried.append(f"delimited text: {exc.reason}")
        raise DataError(f"not a recognised spectrum file; formats tried: {'; '.join(tried)}", path=exc.path, line=exc.line) from None
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
