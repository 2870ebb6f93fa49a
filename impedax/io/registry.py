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

from ..arguments import shown
from ..errors import ParameterError

__all__ = ["Reader", "ReaderDefinitionError", "given_value"]


class ReaderDefinitionError(ParameterError, TypeError):
    """A `Reader` or `register_reader` given a missing or wrong argument, named with what was
    given; a `ParameterError`, and a TypeError for code that catches those."""


def given_value(value) -> str:
    """``value`` as a message names it: a function by its name, anything else shortened."""
    if callable(value) and hasattr(value, "__name__"):
        return f"the function {value.__name__!r}"
    return f"{shown(value)} ({type(value).__name__})"


@dataclass(frozen=True)
class Reader:
    """One file format.

    ``sniff(path, head)`` looks at the file name and its first bytes and returns ``None`` when
    the file is in this format, otherwise a short reason it is not (shown when no reader fits);
    ``True`` and ``False`` are read as "mine" and "not mine". A sniff that raises or returns
    anything else is named with what it did when no reader claims the file (`impedax.load`).
    ``read(path)`` returns the spectrum Dataset or raises `impedax.DataError` naming the line.
    ``extensions``: the suffixes it is known by (``(".lab",)``; one text alone is one suffix); content
    decides, but a file no reader claims is told first why the one reader that alone lists its suffix refused it.
    ``conventions`` says in one line how the file stores Z and its units: a user's reader whose
    Dataset records no ``sign_convention`` or ``units`` gets it there (``impedax inspect`` shows them).
    ``origin``: where the reader was declared, as a message names it before the file and line of
    its code that raised (`impedax.load`): ``--plugin lab.py`` or ``$IMPEDAX_PLUGINS lab.py`` for a
    plugin's reader on the command line (which sets it); "" for one made in Python.
    """

    name: str
    extensions: tuple[str, ...] = None  # (None: not given, named by __post_init__; all four are needed)
    sniff: Callable[[Path, bytes], str | bool | None] = None
    read: Callable[[Path], xr.Dataset] = None
    conventions: str = ""
    origin: str = ""

    def __post_init__(self):
        # Every fault is one ReaderDefinitionError naming the argument (with the extensions
        # forgotten, Reader("lab", sniff, read), Python alone would say "missing 'read'")
        usage = "Reader(name, extensions, sniff, read), e.g. Reader('My format', ('.my',), sniff_mine, read_mine)"
        if not isinstance(self.name, str) or not self.name.strip():
            raise ReaderDefinitionError(f"Reader: name must be non-empty text, got {given_value(self.name)}; {usage}")
        if callable(self.extensions) and not isinstance(self.extensions, (str, tuple, list)):
            raise ReaderDefinitionError(f"Reader {self.name!r}: extensions, the second argument, is {given_value(self.extensions)}: "
                                        f"were the suffixes left out? {usage}")
        missing = [field_name for field_name in ("extensions", "sniff", "read") if getattr(self, field_name) is None]
        if missing:
            raise ReaderDefinitionError(f"Reader {self.name!r}: {', '.join(missing)} not given; {usage}")
        extensions = (self.extensions,) if isinstance(self.extensions, str) else self.extensions
        try:
            extensions = tuple(extensions)
        except TypeError:
            raise ReaderDefinitionError(f"Reader {self.name!r}: extensions must be a tuple of suffixes such as ('.lab',), got {given_value(self.extensions)}") from None
        for ext in extensions:
            if not isinstance(ext, str):
                raise ReaderDefinitionError(f"Reader {self.name!r}: each extension is a suffix such as '.lab', got {given_value(ext)}")
            if not (ext.startswith(".") and len(ext) > 1):
                raise ParameterError(f"Reader {self.name!r}: each extension is a suffix that starts with '.', such as '.lab', got {ext!r}")
        object.__setattr__(self, "extensions", extensions)
        for field_name in ("sniff", "read"):
            if not callable(getattr(self, field_name)):
                raise ReaderDefinitionError(f"Reader {self.name!r}: {field_name} must be a function, got {type(getattr(self, field_name)).__name__}")
        if not isinstance(self.conventions, str):
            raise ReaderDefinitionError(f"Reader {self.name!r}: conventions must be text, got {type(self.conventions).__name__}")
        if not isinstance(self.origin, str):
            raise ReaderDefinitionError(f"Reader {self.name!r}: origin must be text, got {type(self.origin).__name__}")
