"""One module per file format; `READERS` is the order `impedax.load` tries them in.

Order matters: binary signatures first, then text formats with a distinctive first line, then
the table exports recognised by their column names. Plain delimited text is `load`'s fallback.
To add a format, write ``formats/<name>.py`` with ``sniff``, ``read_<name>`` and ``READER``, and
add ``READER`` below (or, from your own package, `impedax.io.register_reader`).
"""

from __future__ import annotations

from typing import Sequence

from ..registry import Reader, ReaderDefinitionError, given_value
from . import (
    autolab, biologic, biologic_mpr, chinstruments, dfr, gamry, ivium, labone_csv, labone_hdf5, netcdf, palmsens,
    parstat, powersuite, spreadsheet, versastudio, z60w, zplot,
)

__all__ = ["READERS", "register_reader"]

READERS: tuple[Reader, ...] = (
    netcdf.READER,
    labone_hdf5.READER,
    biologic_mpr.READER,
    spreadsheet.READER,
    palmsens.READER,
    ivium.READER,
    gamry.READER,
    biologic.READER,
    biologic.TEXT_READER,
    zplot.READER,
    z60w.READER,
    dfr.READER,
    versastudio.READER,
    chinstruments.READER,
    parstat.READER,
    powersuite.READER,
    labone_csv.READER,
    autolab.READER,
)


def register_reader(reader: Reader, readers: Sequence[Reader] | None = None, *, first: bool = True) -> tuple[Reader, ...]:
    """A new registry: ``readers`` (default `READERS`) with ``reader`` added — tried before the
    built-in ones when ``first`` (so its sniff wins), else after them. A reader of the same name
    is replaced. Nothing global changes: pass the result to ``load(path, readers=...)``.
    A wrong argument is a `ReaderDefinitionError` (a `ParameterError`) naming it (not a
    TypeError, and ``first='yes'`` is not taken as true)."""
    if not isinstance(reader, Reader):
        raise ReaderDefinitionError(f"register_reader expects an impedax.io.Reader, got {given_value(reader)}: "
                                    "build one with impedax.io.Reader(name, extensions, sniff, read)")
    if not isinstance(first, bool):
        raise ReaderDefinitionError(f"register_reader: first must be True (try the reader before the built-in ones) or False (after them), got {given_value(first)}")
    if readers is not None and (isinstance(readers, (str, bytes, Reader)) or not isinstance(readers, Sequence)
                                or not all(isinstance(r, Reader) for r in readers)):
        raise ReaderDefinitionError(f"register_reader: readers must be a sequence of impedax.io.Reader (impedax.io.READERS or what "
                                    f"register_reader returned), got {given_value(readers)}")
    rest = tuple(r for r in (READERS if readers is None else readers) if r.name != reader.name)
    return (reader, *rest) if first else (*rest, reader)
