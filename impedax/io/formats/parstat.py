"""Princeton Applied Research Parstat (PowerSine/VersaStudio text) exports.

Layout: one tab-separated header line ``Potential (V) Current (A) Elapsed Time (s) Frequency
(Hz) Zre (ohms) Zim (ohms) |Vac| (V) |Iac| (A)`` (with a trailing tab) and one row per sample.
Rows recorded at f = 0 are DC samples taken before the sweep: they are skipped and reported in
``attrs["skipped_rows"]``.

Conventions: frequency in Hz; Z = ``Zre`` + j·``Zim`` in Ω, Z'' stored as is (negative for
capacitive data).
"""

from __future__ import annotations

from pathlib import Path

import xarray as xr

from ..registry import Reader
from ..table import first_line_sniffer, read_headed_table

__all__ = ["read_parstat", "READER"]

CONVENTIONS = "Frequency (Hz); Z = Zre + j·Zim (ohms) as stored; DC rows (f = 0) skipped and reported"


def _is_header(line: str) -> bool:
    cells = [c.strip() for c in line.split("\t")]
    return "Frequency (Hz)" in cells and "Zre (ohms)" in cells and "Zim (ohms)" in cells


sniff = first_line_sniffer(_is_header, "'Frequency (Hz)', 'Zre (ohms)', 'Zim (ohms)'")


def read_parstat(path: str | Path) -> xr.Dataset:
    """Read a Parstat text export (see module docstring)."""
    return read_headed_table(path, {"format": "Parstat text", "instrument": "Princeton Applied Research Parstat"})


READER = Reader("Parstat text", (".txt",), sniff, read_parstat, CONVENTIONS)
