"""IviumSoft ``.idf`` (one measurement) and ``.ids`` (a sequence) files.

Layout: binary-framed ``Key=value`` text (``Peaks=``, ``Solarcell=``, ``Technique=``, ...);
each measurement's table starts at a line ``primary_data`` followed by the number of columns
(3), the number of points N and N rows ``Z'  Z''  f`` separated by spaces or tabs. Several
measurements of an ``.ids`` become a ``measurement`` dimension when they share their grid.

Conventions: Z' and Z'' in Ω as stored (Z'' negative for capacitive data), frequency in Hz
(third column).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import xarray as xr

from ...errors import DataError
from .._common import CUT_SHORT, check_last_field_digits, cut_short_note, column_entry, finish, lf_line_ends, number, read_bytes, stack
from ..registry import Reader

__all__ = ["read_ivium", "READER"]

CONVENTIONS = "after 'primary_data': columns, N, N rows Z' [Ω], Z'' [Ω] as stored, f [Hz]"


# the structure of an Ivium file's key block, not words that text may mention: ``Solarcell=``
# with a boolean at the start of a line, and another of its lines (``Technique=...``,
# ``Peaks=true|false`` or the ``primary_data`` table marker) at the start of a line too
_SOLARCELL_LINE = re.compile(rb"(?m)^Solarcell=(?:true|false)\r?$")
_OTHER_LINE = re.compile(rb"(?m)^(?:Technique=|Peaks=(?:true|false)\r?$|primary_data[ \t]*\r?$)")


def sniff(path: Path, head: bytes) -> str | None:
    head = lf_line_ends(head)
    if _SOLARCELL_LINE.search(head) and _OTHER_LINE.search(head):
        return None
    return "no IviumSoft key lines ('Solarcell=true|false' and 'Technique=' at line starts)"


def read_ivium(path: str | Path) -> xr.Dataset:
    """Read the impedance table(s) of an IviumSoft ``.idf``/``.ids`` file (see module docstring)."""
    path = Path(path)
    raw = read_bytes(path)
    lines = lf_line_ends(raw).decode("latin-1").split("\n")
    starts = [k for k, ln in enumerate(lines) if ln.strip() == "primary_data"]
    if not starts:
        raise DataError("no 'primary_data' table" + cut_short_note(raw), path=path)
    spectra = []
    for i, k in enumerate(starts):
        if k + 2 >= len(lines) or not (lines[k + 1].strip().isdigit() and lines[k + 2].strip().isdigit()):
            raise DataError("'primary_data' should be followed by the column and point counts", path=path, line=k + 2)
        n_cols, n = int(lines[k + 1]), int(lines[k + 2])
        if n_cols != 3:
            raise DataError(f"'primary_data' has {n_cols} columns; impedance tables have 3 (Z', Z'', f)", path=path, line=k + 2)
        if not 1 <= n <= len(lines) - k - 3:
            raise DataError(f"'primary_data' announces {n} points but {len(lines) - k - 3} lines follow" + cut_short_note(raw), path=path, line=k + 3)
        freq, real, imag, where = [], [], [], []
        last_fields: list[str] = []
        for j in range(k + 3, k + 3 + n):
            cells = re.split(r"[ \t]+", lines[j].strip())
            if len(cells) != 3:
                cut = f"; {CUT_SHORT}" if len(cells) < 3 and j == len(lines) - 1 and lines[j] else ""  # (the last line, with no line end after it)
                raise DataError(f"{len(cells)} fields, expected Z', Z'', f{cut}", path=path, line=j + 1)
            real.append(number(cells[0], path, j + 1, "Z'"))
            imag.append(number(cells[1], path, j + 1, "Z''"))
            freq.append(number(cells[2], path, j + 1, "f"))
            last_fields.append(cells[2])
            where.append(j + 1)
            if j == len(lines) - 1 and lines[j]:  # (the last line, with no line end after it: cut inside f?)
                check_last_field_digits(last_fields, path, j + 1, name="f")
        technique = re.search(rb"Technique=([^\r\n]*)", raw)
        attrs = {"format": "IviumSoft idf/ids", "instrument": "Ivium", "technique": technique.group(1).decode("latin-1").strip() if technique else "",
                 "sign_convention": "Z'' stored as is (negative for capacitive data)", "units": "column 1 (Z') and column 2 (Z'') in ohm, column 3 (f) in Hz",
                 # (the table names no columns: they are its positions, Z', Z'', f)
                 "columns": {"frequency": column_entry("frequency", "column 3"), "z_real": column_entry("z_real", "column 1"),
                             "z_imag": column_entry("z_imag", "column 2")}}
        spectra.append((str(i), finish(path, np.array(freq), np.array(real) + 1j * np.array(imag), where, attrs)))
    return stack(path, spectra, "measurement")


READER = Reader("IviumSoft idf/ids", (".idf", ".ids"), sniff, read_ivium, CONVENTIONS)
