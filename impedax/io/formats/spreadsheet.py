"""Spreadsheets: Excel ``.xlsx`` (needs ``openpyxl``) and OpenDocument ``.ods`` (needs ``odfpy``),
read through pandas: ``pip install impedax[spreadsheet]``.

Each sheet is a table whose first non-empty row names the columns (or, below notes, the first row
that reads as a header followed by numbers: `impedax.io.table.find_header`, as for delimited
text; a units row under it is read as the columns' units), read by `impedax.io.table`
(``f``/``freq``/``frequency``, ``Z'``/``Zre``/``real``, ``Z''``/``imaginary`` or ``-Zim``,
``|Z|`` with ``phase`` or ``-phase``, units such as ``Frequency (mHz)`` case-sensitively). Sheets
on the same grid become a ``sheet`` dimension; sheets whose cycle numbers carry on (1, 2 / 3, 4)
become one ``cycle`` dimension (`impedax.io._common.stack`). Errors name the sheet and the cell
(``data.xlsx [sheet run 1], cell B10: …``), or the row when no one column is at fault
(`_in_cells`); ``DataError.line`` is the row. A formula cell with no stored value (a file written by a program that does not
compute formulas) is named by sheet and cell (`_formulas_without_values`).

Conventions: as named by each column header (a ``-`` prefix means the column stores the negated
quantity); numbers are taken as stored in the cells.
"""

from __future__ import annotations

import math
import re
import zipfile
from pathlib import Path

import xarray as xr

from ...errors import DataError, SweepGridsDiffer
from .._common import CUT_AS, check_file, max_file_bytes, stack
from ..registry import Reader
from ..table import Layout, NoLayout, find_header, header_layout, preamble_note, spectrum_from_rows, units_row_note

__all__ = ["read_spreadsheet", "READER"]

CONVENTIONS = "one table per sheet, columns named as for text (f, Z', Z'' or -Z'', |Z|, phase)"
_ZIP = b"PK\x03\x04"
_ODS = b"mimetypeapplication/vnd.oasis.opendocument.spreadsheet"
#: A zip file ends with its directory's end record: this signature, then 18 bytes and a comment
#: of at most 65 535 bytes.
_ZIP_END = b"PK\x05\x06"
_ZIP_END_SPAN = 22 + 65535


def _cut_zip_note(path: Path) -> str:
    """``"; "`` and what a cut is when the zip file ``path`` lacks the end record of its
    directory (`_ZIP_END`), or part of it, as a file cut short while copied does; ``""`` otherwise."""
    try:
        with open(path, "rb") as stream:
            stream.seek(max(0, path.stat().st_size - _ZIP_END_SPAN))
            tail = stream.read()
    except OSError:
        return ""
    at = tail.rfind(_ZIP_END)
    # (the record is whole when its 22 bytes and the comment whose length its last two give are all there)
    whole = at >= 0 and len(tail) - at >= 22 and len(tail) - at >= 22 + int.from_bytes(tail[at + 20:at + 22], "little")
    return "" if whole else f"; the file ends without the directory every zip file (.xlsx, .ods) ends with, {CUT_AS}"


def sniff(path: Path, head: bytes) -> str | None:
    if head.startswith(_ZIP) and (_ODS in head[:200] or b"xl/" in head or path.suffix.lower() in (".xlsx", ".xlsm", ".ods")):
        return None
    return "not a zip-based spreadsheet (.xlsx/.ods)"


def _kind(path: Path) -> str:
    try:
        with zipfile.ZipFile(path) as zf:
            names = zf.namelist()
            total = sum(i.file_size for i in zf.infolist())
    except (zipfile.BadZipFile, OSError, ValueError) as exc:
        raise DataError(f"not a readable spreadsheet ({exc}){_cut_zip_note(path)}", path=path) from None
    if total > 8 * max_file_bytes():
        raise DataError(f"spreadsheet expands to {total / 2**20:.0f} MB; too large for a spectrum", path=path)
    if "xl/workbook.xml" in names:
        return "openpyxl"
    if "content.xml" in names:
        return "odf"
    raise DataError("zip file is neither an Excel (.xlsx) nor an OpenDocument (.ods) spreadsheet", path=path)


def _cell(value) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, (int, float)):
        return repr(float(value))
    return str(value)


def _formulas_without_values(path: Path, sheet: str) -> list[tuple[str, str]]:
    """(cell, formula) of each formula cell of ``sheet`` with no stored value, in reading order:
    pandas (openpyxl with ``data_only``) reads such a cell as empty. A program that writes
    .xlsx without a spreadsheet engine (openpyxl, many exporters) stores formulas only."""
    import openpyxl

    try:
        formulas = openpyxl.load_workbook(path, data_only=False)[sheet]
        values = openpyxl.load_workbook(path, data_only=True)[sheet]
    except Exception:  # (the engines raise many types for damaged files: then the first error stands)
        return []
    found = []
    for row in formulas.iter_rows():
        for cell in row:
            text = cell.value if isinstance(cell.value, str) else getattr(cell.value, "text", None)  # (an ArrayFormula holds its text)
            if isinstance(text, str) and text.startswith("=") and values[cell.coordinate].value is None:
                found.append((cell.coordinate, text))
    return found


def column_letters(index: int) -> str:
    """The spreadsheet's name of column ``index`` (0-based): 0 → A, 25 → Z, 26 → AA."""
    letters = ""
    index += 1
    while index:
        index, rest = divmod(index - 1, 26)
        letters = chr(ord("A") + rest) + letters
    return letters


#: A message about one column's cell, as `impedax.io._common.number` words it: ``column 'Z'': …``
_NAMES_COLUMN = re.compile(r"column (['\"])(.*?)\1")
#: Messages about the frequency (or sigma) of a row, as `finish` words them.
_ROLE_OF_MESSAGE = (("frequency must be positive", "frequency"), ("duplicate frequency", "frequency"), ("sigma must be positive", "sigma"))


def _as_rows(text: str) -> str:
    """The table reader's "line 5", "lines 2–9" as a sheet's "row 5", "rows 2–9"."""
    return re.sub(r"\blines\b", "rows", re.sub(r"\bline\b", "row", text))


def _reports_in_rows(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` with the table reader's reports (``skipped_rows``, ``sweeps``) in a sheet's rows."""
    ds = ds.copy()
    if "skipped_rows" in ds.attrs:
        ds.attrs["skipped_rows"] = [_as_rows(text) for text in ds.attrs["skipped_rows"]]
    if "sweeps" in ds.attrs:
        ds.attrs["sweeps"] = _as_rows(ds.attrs["sweeps"])
    return ds


def _in_cells(exc: DataError, layout: Layout) -> DataError:
    """``exc`` (the table reader's, its line numbers the sheet's rows, its path ``FILE [sheet S]``)
    as a spreadsheet's user finds the place: ``cell B10`` when the message is about one column's
    cell (named in it, or the frequency or sigma of the row), else ``row 10``; "line N" in the
    message as "cell A15" (that column) or "row N". ``line`` stays the row; a `SweepGridsDiffer`
    keeps its sweeps."""
    detail = exc.detail
    named = _NAMES_COLUMN.match(detail)
    names = [cell.strip() for cell in layout.header]
    role = next((role for start, role in _ROLE_OF_MESSAGE if detail.startswith(start)), None)
    index = names.index(named.group(2).strip()) if named and named.group(2).strip() in names else layout.columns[role][0] if role in layout.columns else None
    letters = "" if index is None else column_letters(index)
    if letters:
        detail = re.sub(r"\b(?:on|in) line (\d+)", lambda m: f"in cell {letters}{m.group(1)}", detail)
    detail = _as_rows(detail)
    place = exc.path if exc.line is None else f"{exc.path}, {'cell ' + letters if letters else 'row '}{exc.line}"
    if isinstance(exc, SweepGridsDiffer):
        found = _as_rows(exc.found)
        spectra = {k: _reports_in_rows(exc.spectrum(k)) for k in exc.labels}
        out: DataError = SweepGridsDiffer(f"{place}: {detail}", path=None, line=None, dim=exc.dim, spectra=spectra, found=found)
    else:
        out = DataError(f"{place}: {detail}")
    out.path, out.line, out.detail = exc.path, exc.line, detail  # (the place is the sheet's cell, which DataError's "FILE, line N" cannot say)
    return out


def read_spreadsheet(path: str | Path) -> xr.Dataset:
    """Read every sheet of an ``.xlsx``/``.ods`` workbook (see module docstring)."""
    path = Path(path)
    check_file(path)
    engine = _kind(path)
    module = {"openpyxl": "openpyxl", "odf": "odf"}[engine]
    try:
        __import__(module)
        import pandas as pd
    except ImportError:
        extra = "openpyxl" if engine == "openpyxl" else "odfpy"
        raise DataError(f"reading this spreadsheet needs {extra}: pip install {extra} (or impedax[spreadsheet]), or export CSV", path=path) from None
    try:
        sheets = pd.read_excel(path, sheet_name=None, header=None, dtype=object, engine=engine)
    except Exception as exc:  # the engines raise many types for damaged files
        raise DataError(f"not a readable spreadsheet ({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}){_cut_zip_note(path)}",
                        path=path) from None
    spectra = []
    reasons = []
    for name, frame in sheets.items():
        rows = [(r + 1, [_cell(v) for v in values]) for r, values in enumerate(frame.itertuples(index=False, name=None))]
        rows = [(n, cells) for n, cells in rows if any(c.strip() for c in cells)]
        if not rows:
            reasons.append(f"sheet {name!r} is empty")
            continue
        header_row, header = rows[0]
        where = Path(f"{path} [sheet {name}]")
        attrs = {"format": "spreadsheet", "sheet": str(name)}
        try:
            layout, units_row = header_layout(header, rows[1][1] if len(rows) > 1 else None, where, header_row)
        except NoLayout as exc:
            found = find_header(len(rows), lambda at, k: rows[k][1], lambda k: rows[k][0], where)
            if found is None:
                reasons.append(f"sheet {name!r}: {exc.reason}")
                continue
            layout, units_row = found.layout, found.units_row
            first_text = " ".join(c for c in rows[0][1] if c.strip())
            attrs["preamble"] = preamble_note(rows[0][0], rows[found.at][0], first_text, "rows")
            rows = rows[found.at:]
        if units_row:
            attrs["units_row"] = units_row_note(rows[1][0], rows[1][1], "row")
        try:
            ds = spectrum_from_rows(where, layout, rows[2:] if units_row else rows[1:], attrs, comma=False, split_sweeps=True, position="row")
        except SweepGridsDiffer as exc:
            if len(sheets) == 1:
                raise _in_cells(exc, layout) from None
            # (one sweep of one sheet of several cannot be picked alone: the sheets would go)
            raise _in_cells(DataError(f"{exc.found}; impedax will not merge them into one spectrum: save each sweep to a sheet or file of its own",
                                      path=exc.path, line=exc.line), layout) from None
        except DataError as exc:
            uncomputed = _formulas_without_values(path, name) if engine == "openpyxl" else []
            if not uncomputed:
                raise _in_cells(exc, layout) from None
            (cell, formula), more = uncomputed[0], len(uncomputed) - 1
            raise DataError(
                f"cell {cell} holds a formula ({formula[:40]}) with no stored value" + (f", and so do {more} more cells" if more else "")
                + ": the file was written by a program that stores formulas without computing them; open it in a spreadsheet "
                "program (Excel, LibreOffice) and save it, so that their values are stored, or export the sheet as CSV",
                path=where,
            ) from None
        ds = _reports_in_rows(ds)
        ds.attrs["path"] = str(path)
        spectra.append((str(name), ds))
    if not spectra:
        raise DataError("no sheet holds a spectrum table: " + "; ".join(reasons), path=path)
    if reasons:
        for _, ds in spectra:
            ds.attrs["other_sheets"] = "; ".join(reasons)
    return stack(path, spectra, "sheet")


READER = Reader("spreadsheet", (".xlsx", ".ods"), sniff, read_spreadsheet, CONVENTIONS)
