"""Scribner ZPlot / ZView ``.z`` files (ZPLOT2 ASCII and the header-less variant).

Layout: ``ZPLOT2 ASCII`` and ``Key: value`` lines ending with ``End Comments`` (the line before
it may name the columns), then one row per point separated by tabs or commas:
``Freq(Hz) Ampl Bias Time(Sec) Z'(a) Z''(b) GD Err Range``. The variant without metadata starts
with that column-name line. A ``Data Points: N`` header that differs from the rows is reported in ``attrs``;
so is a sweep whose points stop short of the one ``vs Freq-Initial`` and ``vs Freq-Final`` plan
(``frequency_plan_note``, as CH Instruments', Gamry's, BioLogic's and VersaStudio's).
Numbers with decimal commas are refused, saying so (`_check_decimal_commas`): a ',' separates fields.

Conventions: frequency in Hz; Z = ``Z'(a)`` + j·``Z''(b)`` in Ω, Z'' stored as is (negative for
capacitive data).
"""

from __future__ import annotations

import re
from pathlib import Path

import xarray as xr

from ...errors import DataError
from .._common import cut_last_line, cut_short_note, decimal_comma, frequency_plan_note, head_text, read_text
from ..dates import record_date
from ..registry import Reader
from ..table import Layout, NoLayout, detect_layout, spectrum_from_rows

__all__ = ["read_zplot", "READER", "FIXED_LAYOUT", "split_row"]

CONVENTIONS = "Freq(Hz); Z = Z'(a) + j·Z''(b) [Ω] as stored (Z'' < 0 capacitive)"
COLUMN_NAMES = ("Freq(Hz)", "Ampl", "Bias", "Time(Sec)", "Z'(a)", "Z''(b)", "GD", "Err", "Range")
#: ZPlot's fixed column order, used when the file does not name its columns.
FIXED_LAYOUT = Layout({"frequency": (0, 1.0), "real": (4, 1.0), "imag": (5, 1.0)}, COLUMN_NAMES)


#: The header's sweep plan (``vs Freq-Initial:  300000``), kept as numbers under the names
#: Gamry's are kept by.
_PLAN = {"vs Freq-Initial": "initial_frequency_hz", "vs Freq-Final": "final_frequency_hz"}


def split_row(line: str) -> list[str]:
    return [c.strip() for c in re.split(r"\t|,", line.strip())]


def _names_line(line: str) -> bool:
    return "Freq(Hz)" in line and "Z'(a)" in line


def sniff(path: Path, head: bytes) -> str | None:
    text = head_text(head)
    first = text.lstrip().split("\n", 1)[0]
    if first.upper().startswith("ZPLOT") or re.search(r"^End Comments\s*$", text, re.M) or _names_line(first):
        return None
    return "no 'ZPLOT' first line and no 'End Comments' line"


def read_zplot(path: str | Path) -> xr.Dataset:
    """Read a ZPlot/ZView ``.z`` file (see module docstring)."""
    path = Path(path)
    text = read_text(path)
    lines = text.splitlines()
    end = next((k for k, ln in enumerate(lines) if ln.strip() == "End Comments"), None)
    attrs: dict[str, object] = {"format": "Scribner ZPlot z", "instrument": "Scribner ZPlot"}
    announced = None
    if end is None:
        end = next((k for k, ln in enumerate(lines[:5]) if _names_line(ln)), None)
        if end is None:
            raise DataError("no 'End Comments' line ending the ZPlot header" + cut_short_note(text), path=path)
        names_line = lines[end]
    else:
        date = time = None
        for line in lines[:end]:
            key, sep, value = line.partition(":")
            key, value = key.strip(), value.strip()
            if not sep:
                continue
            if key == "Date":
                date = value
            elif key == "Time":
                time = value
            elif key == "Experiment Type":
                attrs["experiment"] = value
            elif key.startswith("Measured Data"):
                attrs["software"] = f"{key.split(',')[-1].strip()} {value}".strip()
            elif key == "Data Points" and value.isdigit():
                announced = int(value)
            elif key in _PLAN:
                try:
                    attrs[_PLAN[key]] = float(value)
                except ValueError:
                    pass
        if date or time:  # (ISO 8601 when the order of day and month is established)
            record_date(attrs, [" ".join(v for v in (date, time) if v)])
        names_line = lines[end - 1] if end > 0 else ""
    rows = [(k + 1, split_row(lines[k])) for k in range(end + 1, len(lines)) if lines[k].strip()]
    layout = FIXED_LAYOUT
    if _names_line(names_line):
        try:
            layout = detect_layout(split_row(names_line), path, end)
        except NoLayout:
            layout = FIXED_LAYOUT
    _check_decimal_commas(path, lines, rows, len(layout.header))
    if announced is not None and announced != len(rows):
        attrs["point_count_note"] = f"header says 'Data Points: {announced}'; the file holds {len(rows)} rows (sweep stopped early?)"
    ds = spectrum_from_rows(path, layout, rows, attrs, comma=False, header_line=end + 1, cut_line=cut_last_line(text, lines))
    note = frequency_plan_note(ds["frequency"].values, attrs.get("initial_frequency_hz"), attrs.get("final_frequency_hz"))
    if note:
        ds.attrs["frequency_plan_note"] = note
    return ds


def _check_decimal_commas(path: Path, lines: list[str], rows: list[tuple[int, list[str]]], n_fields: int) -> None:
    """A row with more fields than the column names whose tab-separated cells are numbers with
    decimal commas (``1,000000E+05``, as a Windows locale or a spreadsheet writes them): refused,
    naming the line and the decimal commas, since a ',' also separates ZPlot's fields."""
    for line, cells in rows:
        text = lines[line - 1]
        if len(cells) > n_fields and "\t" in text:
            tab_cells = [c.strip() for c in text.strip().split("\t")]
            if len(tab_cells) <= n_fields and decimal_comma(tab_cells, "\t"):
                raise DataError(
                    f"{len(cells)} fields, but the header has {n_fields}: the numbers are written with decimal commas "
                    f"({tab_cells[0]!r}), and a ',' also separates the fields of a ZPlot file, so each one splits a number; export "
                    "the file with decimal points (a Windows locale or a spreadsheet wrote the commas)",
                    path=path, line=line,
                )
            return


READER = Reader("Scribner ZPlot z", (".z",), sniff, read_zplot, CONVENTIONS)
