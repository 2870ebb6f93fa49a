"""The readers registry: a tuple of `Reader` values that `load` tries in order.

A reader is one function that reads a file plus one that recognises it. To add a format from
your own package, write both and register them — a new tuple is returned, nothing global is
changed::

    from impedax.io import READERS, Reader, register_reader, load

    def sniff_mine(path, head):          # head: the file's first 64 kB
        return None if head.startswith(b"MYFORMAT") else "no 'MYFORMAT' signature"

    def read_mine(path):                 # -> impedax.make_spectrum(...)
        ...

    MY_READERS = register_reader(Reader("My format", (".my",), sniff_mine, read_mine))
    ds = load("run.my", readers=MY_READERS)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

import xarray as xr

__all__ = ["Reader", "register_reader"]


@dataclass(frozen=True)
class Reader:
    """One file format.

    ``sniff(path, head)`` looks at the file name and its first bytes and returns ``None`` when
    the file is in this format, otherwise a short reason it is not (shown when no reader fits);
    ``read(path)`` returns the spectrum Dataset or raises `impedax.DataError` naming the line.
    ``conventions`` says in one line how the file stores Z and its units (README, ``inspect``).
    """

    name: str
    extensions: tuple[str, ...]
    sniff: Callable[[Path, bytes], str | None]
    read: Callable[[Path], xr.Dataset]
    conventions: str = ""


def register_reader(reader: Reader, readers: Sequence[Reader] | None = None, *, first: bool = True) -> tuple[Reader, ...]:
    """A new registry: ``readers`` (default `impedax.io.READERS`) with ``reader`` added — tried
    before the built-in ones when ``first`` (so its sniff wins), else after them. A reader of
    the same name is replaced."""
    if not isinstance(reader, Reader):
        raise TypeError(f"register_reader expects an impedax.io.Reader, got {type(reader).__name__}")
    if readers is None:
        from .formats import READERS as readers
    rest = tuple(r for r in readers if r.name != reader.name)
    return (reader, *rest) if first else (*rest, reader)
