"""Princeton Applied Research PowerSuite text exports.

Layout: a tab-separated header ``Frequency<TAB> Zre<TAB> Zimg`` and one row per point (lines
often end in ``CR CR LF``; the empty lines this makes are ignored, and a file whose rows end so
but whose last row ends without a line end is refused as cut short).

Conventions: frequency in Hz; Z = ``Zre`` + j·``Zimg`` in Ω, Z'' stored as is (negative for
capacitive data).
"""

from __future__ import annotations

from pathlib import Path

import xarray as xr

from ..registry import Reader
from ..table import first_line_sniffer, read_headed_table

__all__ = ["read_powersuite", "READER"]

CONVENTIONS = "Frequency [Hz]; Z = Zre + j·Zimg [Ω] as stored"

#: PowerSuite ends every row with CR CR LF, the last included: a file whose rows end so and whose
#: last does not was cut short, though its numbers (shortest form) cannot show it.
ROW_END = ("\r\r\n", "CR CR LF")


def _is_header(line: str) -> bool:
    return [c.strip() for c in line.split("\t")][:3] == ["Frequency", "Zre", "Zimg"]


sniff = first_line_sniffer(_is_header, "'Frequency<TAB>Zre<TAB>Zimg'")


def read_powersuite(path: str | Path) -> xr.Dataset:
    """Read a PowerSuite text export (see module docstring)."""
    return read_headed_table(path, {"format": "PowerSuite text", "instrument": "Princeton Applied Research (PowerSuite)"}, row_end=ROW_END)


READER = Reader("PowerSuite text", (".txt",), sniff, read_powersuite, CONVENTIONS)
