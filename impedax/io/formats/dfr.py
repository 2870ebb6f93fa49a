"""Eco Chemie / Autolab FRA ``.dfr`` files.

Layout: one value per line — ``VERSION8.0``, the number of points N, one more header value,
then N records of nine lines each: frequency [Hz], Z' [Ω], −Z'' [Ω] and six further values
(DC potential, DC current, time and three unused). A trailer (flags and dates) follows the
records and is not read. The record count is checked against N before anything is read.

Conventions: Z = Z' − j·(third value): the file stores −Z''.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from ...errors import DataError
from .._common import column_entry, cut_short_note, head_text, number, read_text, finish
from ..registry import Reader

__all__ = ["read_dfr", "READER"]

CONVENTIONS = "9 lines per point: f [Hz], Z' [Ω], -Z'' [Ω] (negated), 6 more"
_RECORD = 9


def sniff(path: Path, head: bytes) -> str | None:
    lines = head_text(head).lstrip().splitlines()[:2]
    if lines and lines[0].strip().upper().startswith("VERSION") and len(lines) > 1 and lines[1].strip().isdigit():
        return None
    return "first lines are not 'VERSION…' and a point count"


def read_dfr(path: str | Path) -> xr.Dataset:
    """Read an FRA ``.dfr`` file (see module docstring)."""
    path = Path(path)
    text = read_text(path)
    lines = text.splitlines()
    if len(lines) < 3 or not lines[1].strip().isdigit():
        raise DataError("second line should be the number of points", path=path, line=2)
    n = int(lines[1].strip())
    first = 3
    available = (len(lines) - first) // _RECORD
    if n < 1 or n > available:
        raise DataError(f"header announces {n} points but the file holds at most {available} records of {_RECORD} lines" + cut_short_note(text), path=path, line=2)
    freq, real, neg_imag, where = [], [], [], []
    for k in range(n):
        start = first + k * _RECORD  # 0-based index of the record's first line
        freq.append(number(lines[start], path, start + 1, "frequency"))
        real.append(number(lines[start + 1], path, start + 2, "Z'"))
        neg_imag.append(number(lines[start + 2], path, start + 3, "-Z''"))
        where.append(start + 1)
    attrs = {"format": "Autolab FRA dfr", "instrument": "Metrohm Autolab (FRA)", "version": lines[0].strip(),
             "sign_convention": "third value of each record holds -Z''; negated to Z''", "units": "record line 1 (f) in Hz, lines 2 (Z') and 3 (-Z'') in ohm",
             # (a record names no columns: its values are lines 1–3 of each record)
             "columns": {"frequency": column_entry("frequency", "record line 1"), "z_real": column_entry("z_real", "record line 2"),
                         "z_imag": column_entry("z_imag", "record line 3", negated=True)}}
    return finish(path, np.array(freq), np.array(real) - 1j * np.array(neg_imag), where, attrs)


READER = Reader("Autolab FRA dfr", (".dfr",), sniff, read_dfr, CONVENTIONS)
