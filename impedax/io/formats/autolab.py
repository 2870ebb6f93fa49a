"""Metrohm Autolab NOVA ASCII exports of impedance (FRA) data.

Layout: optional comment lines, then a column-name line and rows separated by ``;``, tab or
``,``. NOVA's names: ``Index``, ``Frequency (Hz)``, ``Z' (Ω)``, ``-Z'' (Ω)``, ``Z (Ω)``,
``-Phase (°)``, ``Time (s)``; a header is taken as NOVA's when it has one of the last four
beside the first three.

Conventions: frequency in Hz; Z' = ``Z' (Ω)``; the file stores −Z'' (``-Z'' (Ω)``), negated
here. Unit prefixes in the names (``kΩ``, ``mHz``) are applied case-sensitively; decimal commas
are accepted when the separator is not a comma.
"""

from __future__ import annotations

import re
from pathlib import Path

import xarray as xr

from ...errors import DataError
from .._common import cut_last_line, head_text, read_text
from ..registry import Reader
from ..table import detect_layout, spectrum_from_rows

__all__ = ["read_autolab", "READER"]

CONVENTIONS = "Frequency (Hz); Z' (Ω); file stores -Z'' (Ω), negated"
_FREQ = re.compile(r"^Frequency \((?:[mkM]?Hz)\)$")
_NEG_IMAG = re.compile(r"^-Z'' \((?:[mkM]?(?:Ω|Ohm|ohm))\)$")
_NOVA_ONLY = re.compile(r"^(?:Index|Z \((?:[mkM]?(?:Ω|Ohm|ohm))\)|-Phase \(°\)|Time \(s\))$")
"""A column NOVA writes beside frequency, Z' and -Z'' (its index, |Z|, phase, time): a table of
those three alone is any program's, read by the generic table reader and not labelled Autolab."""


def _header(text: str):
    for k, line in enumerate(text.splitlines()[:50]):
        for delimiter in (";", "\t", ","):
            cells = [c.strip().strip('"') for c in line.split(delimiter)]
            if len(cells) >= 4 and any(_FREQ.match(c) for c in cells) and any(_NEG_IMAG.match(c) for c in cells) and any(_NOVA_ONLY.match(c) for c in cells):
                return k, delimiter, cells
    return None


def sniff(path: Path, head: bytes) -> str | None:
    return None if _header(head_text(head)) is not None else "no header with 'Frequency (Hz)' and \"-Z'' (Ω)\""


def read_autolab(path: str | Path) -> xr.Dataset:
    """Read a NOVA impedance export (see module docstring)."""
    path = Path(path)
    text = read_text(path)
    found = _header(text)
    if found is None:
        raise DataError("no header with 'Frequency (Hz)' and \"-Z'' (Ω)\" columns", path=path)
    k, delimiter, names = found
    lines = text.splitlines()
    layout = detect_layout(names, path, k + 1)
    if "real" not in layout.columns:
        raise DataError(f"no \"Z' (Ω)\" column in header {names}", path=path, line=k + 1)
    rows = [(j + 1, [c.strip().strip('"') for c in lines[j].split(delimiter)]) for j in range(k + 1, len(lines)) if lines[j].strip()]
    attrs = {"format": "Metrohm Autolab NOVA text", "instrument": "Metrohm Autolab"}
    if k > 0:
        attrs["comments"] = "\n".join(ln.strip() for ln in lines[:k] if ln.strip())
    return spectrum_from_rows(path, layout, rows, attrs, delimiter=delimiter, header_line=k + 1, cut_line=cut_last_line(text, lines))


READER = Reader("Metrohm Autolab NOVA text", (".txt", ".csv"), sniff, read_autolab, CONVENTIONS)
