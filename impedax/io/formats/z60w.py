"""Autolab FRA / ZView "Z60W Data File" exports (the ASCII export of Eco Chemie's FRA software).

Layout: ``"Z60W Data File: Version 1.1"``, seven quoted comment lines, a settings line, the
number of points, a quoted column-name line ``"Freq (Hz) Ampl Bias Time(Sec) Z'(a) Z''(b) GD
Err Range"`` (names separated by spaces), then one comma-separated row per point.

Conventions: frequency in Hz; Z = ``Z'(a)`` + j·``Z''(b)`` in Ω, Z'' stored as is (negative
for capacitive data) — the ZPlot column order. An announced point count that differs from the rows is reported in ``attrs``.
"""

from __future__ import annotations

from pathlib import Path

import xarray as xr

from ...errors import DataError
from .._common import cut_last_line, head_text, read_text
from ..registry import Reader
from ..table import spectrum_from_rows
from .zplot import FIXED_LAYOUT

__all__ = ["read_z60w", "READER"]

CONVENTIONS = "Freq (Hz); Z = Z'(a) + j·Z''(b) [Ω] as stored (ZPlot column order)"
_MAGIC = "Z60W Data File"


def sniff(path: Path, head: bytes) -> str | None:
    first = head_text(head).lstrip().split("\n", 1)[0]
    return None if _MAGIC in first else "first line is not 'Z60W Data File'"


def read_z60w(path: str | Path) -> xr.Dataset:
    """Read an FRA ``Z60W Data File`` export (see module docstring)."""
    path = Path(path)
    text = read_text(path)
    lines = text.splitlines()
    header = next((k for k, ln in enumerate(lines[:40]) if "Freq" in ln and "Z'(a)" in ln and "Z''(b)" in ln), None)
    if header is None:
        raise DataError("no column-name line with Freq, Z'(a) and Z''(b)", path=path)
    names = lines[header].strip().strip('"').split()
    order = [n for n in names if n in ("Freq", "Time(Sec)", "Z'(a)", "Z''(b)")]
    if order != ["Freq", "Time(Sec)", "Z'(a)", "Z''(b)"] or names.index("Z'(a)") != 5:  # 'Freq' '(Hz)' split by spaces
        raise DataError(f"columns are not in the ZPlot order {' '.join(FIXED_LAYOUT.header)}: {names}", path=path, line=header + 1)
    announced = lines[header - 1].strip() if header > 0 else ""
    rows = [(k + 1, [c.strip() for c in lines[k].split(",")]) for k in range(header + 1, len(lines)) if lines[k].strip()]
    attrs = {"format": "Autolab FRA Z60W", "instrument": "Metrohm Autolab (FRA)", "version": lines[0].strip().strip('"')}
    if announced.isdigit() and int(announced) != len(rows):
        attrs["point_count_note"] = f"header announces {announced} points; the file holds {len(rows)} rows (sweep stopped early?)"
    return spectrum_from_rows(path, FIXED_LAYOUT, rows, attrs, comma=False, header_line=header + 1, cut_line=cut_last_line(text, lines))


READER = Reader("Autolab FRA Z60W", (".txt", ".z60w"), sniff, read_z60w, CONVENTIONS)
