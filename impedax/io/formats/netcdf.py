"""impedax's own netCDF files (written by `impedax.save`), read losslessly.

Conventions: the impedax data model itself: ``Z`` complex in Ω (stored as ``Z__real`` and
``Z__imag``, which must have the same shape), ``frequency`` in Hz.
"""

from __future__ import annotations

from pathlib import Path

from ..netcdf import NETCDF_FORMAT, read_netcdf
from ..registry import Reader

__all__ = ["READER"]

CONVENTIONS = "impedax data model: complex Z [Ω] as Z__real/Z__imag, frequency [Hz]"
SUFFIXES = (".nc", ".nc4", ".cdf")


def sniff(path: Path, head: bytes) -> str | None:
    if head.startswith(b"CDF") or path.suffix.lower() in SUFFIXES:
        return None
    return "no netCDF signature"


READER = Reader(NETCDF_FORMAT, SUFFIXES, sniff, read_netcdf, CONVENTIONS)
