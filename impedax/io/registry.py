"""`Reader`: one file format for `impedax.load`. The registry is a tuple of them
(`impedax.io.READERS`, built in `impedax.io.formats`), extended with `register_reader`.

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
from typing import Callable

import xarray as xr

__all__ = ["Reader"]


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
