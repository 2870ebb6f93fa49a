"""Delimited text spectra (CSV, TSV, semicolon or whitespace separated), with or without header.

Canonical header: ``frequency_hz,z_real_ohm,z_imag_ohm`` with Z = Z' + jZ'' (Z'' < 0 for
capacitive data). Other headers are read by `impedax.io.table` (``freq``, ``Zreal``, ``Z''``,
``-Z''``, ``|Z|`` with ``phase``, units such as ``Frequency (mHz)`` — case-sensitive prefixes).
A file of exactly three numeric columns and no header is read as f [Hz], Z' [Ω], Z'' [Ω], and
``attrs["interpretation"]`` says so; refused when column 1 does not look like frequencies and
exactly one other column does (`_check_headerless_order`). Decimal commas are accepted when the
separator is not a comma, and in quoted cells when it is (`_decimal_mark`). A last row cut short
(no line end, fields or digits missing) is refused (`_check_last_row_complete`). Lines starting
with ``#``, ``%`` or ``!`` are comments.
"""

from __future__ import annotations

import csv as _csv
import io
import re
import warnings
from pathlib import Path
from typing import Mapping

import numpy as np
import xarray as xr

from ..arguments import number_text
from ..errors import DataError
from ._common import CUT_SHORT, Skipped, decimal_comma, decode_text, finish, read_bytes
from .atomic import atomic_path
from .export import table_cell
from .table import (
    NUMBER_CELL, PREAMBLE_ROWS_MAX, SWEEP_RTOL, Layout, NoLayout, RowBlock, detect_layout, find_header, header_layout, preamble_note, spectrum_from_rows,
    units_row_note,
)

__all__ = ["read_csv", "write_csv", "CSV_HEADER", "split_line", "find_delimiter"]

UnrecognisedText = NoLayout  # the name `load` used before the table engine

CSV_HEADER = ("frequency_hz", "z_real_ohm", "z_imag_ohm")

HEADERLESS_NOTE = "no header: columns read as frequency [Hz], Z' [Ω], Z'' [Ω] (Z'' < 0 for capacitive data); add a header to say otherwise"
_NUMBER = NUMBER_CELL
#: A line that may be a row of numbers: digits with only what numbers, delimiters and quotes hold
#: (every row `NUMBER_CELL` reads matches; `find_header`'s quick test).
_NUMBERS_ONLY = re.compile(r'[\d\s.,;eE+"\-]*\d[\d\s.,;eE+"\-]*')


def find_delimiter(line: str) -> str | None:
    """Tab, then ``;``, then ``,`` (outside double quotes); ``None`` means runs of spaces."""
    bare = re.sub(r'"[^"]*"', "", line)
    return next((d for d in ("\t", ";", ",") if d in bare), None)


def split_line(line: str, delimiter: str | None) -> list[str]:
    """The cells of ``line``, stripped; a cell in double quotes may hold the delimiter
    (``"Point, no."``) and loses its quotes, as in any CSV."""
    if not delimiter:
        return line.split()
    if '"' not in line:
        cells = line.split(delimiter)
        # (no space and nothing unprintable: no whitespace in the line, so no cell to strip; a long file's rows skip the strip)
        return cells if " " not in line and line.isprintable() else [c.strip() for c in cells]
    try:
        return [c.strip() for c in next(_csv.reader([line], delimiter=delimiter, skipinitialspace=True))]
    except _csv.Error:  # (a quoted cell beyond the csv module's field limit): the cells as split
        return [c.strip() for c in line.split(delimiter)]


def _read_canonical(path: Path, raw: bytes) -> xr.Dataset | None:
    """impedax's own layout (the canonical header, then rows of three finite numbers with
    positive, distinct frequencies) parsed straight into arrays, without a Python object per
    row: a million points take ~0.1 GB instead of ~1 GB. None for anything else, which the
    general reader then reads, or refuses with its line-numbered message; so is a file that ends
    without a line end, whose last row the general reader checks for a cut (`_check_last_row_complete`)."""
    header = ",".join(CSV_HEADER).encode()
    if not (raw.startswith(header + b"\n") or raw.startswith(header + b"\r\n")) or not raw.endswith((b"\n", b"\r")):
        return None
    try:
        with warnings.catch_warnings():  # (a header without rows: the general reader says so, by line)
            warnings.simplefilter("ignore", UserWarning)
            table = np.loadtxt(io.BytesIO(raw), delimiter=",", skiprows=1, dtype=np.float64, comments=None, ndmin=2, encoding="ascii")
    except (ValueError, UnicodeDecodeError):
        return None
    if table.shape[0] == 0 or table.shape[1] != 3 or not np.isfinite(table).all():
        return None
    freq = table[:, 0]
    if not (freq > 0).all() or np.unique(freq).size != freq.size:
        return None  # (the general reader names the line)
    near_first = np.abs(freq / freq[0] - 1) <= SWEEP_RTOL
    if np.any(near_first[1:] & ~near_first[:-1]):
        return None  # the first frequency came back: the general reader reads the sweeps
    steps = np.diff(freq)
    if not (np.all(steps > 0) or np.all(steps < 0)):
        return None  # the list turns (a sweep restarting on another grid?): the general reader decides
    layout = detect_layout(list(CSV_HEADER), path, 1)
    lines = range(2, 2 + freq.size) if b"\n\n" not in raw and b"\n\r\n" not in raw else [None] * freq.size
    return finish(path, freq, table[:, 1] + 1j * table[:, 2], lines, {"format": "delimited text", **layout.notes()})


COMMENT_MARKS = ("#", "%", "!")
"""A line of delimited text starting with one of these is a comment: not read; inside the table
it is reported among the skipped rows."""

PREAMBLE_LINES_MAX = PREAMBLE_ROWS_MAX
"""Not used: `read_csv` looks through the whole file for a table's header when the first line
is not one (`impedax.io.table.find_header`). Kept for code that imports it."""


_QUOTED_DECIMAL_COMMA = re.compile(r"[-+]?\d*,\d+(?:[eE][-+]?\d+)?")
#: One comma followed by three digits: '1,000' is a thousand in a US export, one in a German one.
_THOUSANDS_SHAPE = re.compile(r"[-+]?\d{1,3},\d{3}")


def _decimal_mark(path: Path, rows: list[tuple[int, str]], delimiter: str | None) -> bool:
    """Whether the numbers of ``rows`` are written with decimal commas: any cell of the first 20
    rows, or of every row when a later one holds a ',' (`decimal_comma`). In a comma-separated
    file a decimal comma can only stand in a quoted cell (``"0,1","120,5"``); there '1,000' may
    be a thousand (a US export quotes its thousands separators), so a file whose every such cell
    has that shape is refused as ambiguous, naming the first."""
    if delimiter == ",":
        with_quotes = [ln for _, ln in rows if '"' in ln]
        if with_quotes and _unquoted_cells(with_quotes, delimiter) is not None:
            return False  # (every quoted cell plain: none holds a ',', as each would have been split in two)
        quoted = [(n, c.strip()) for n, ln in rows if '"' in ln for c in split_line(ln, delimiter) if "," in c]
        numeric = [(n, c) for n, c in quoted if _QUOTED_DECIMAL_COMMA.fullmatch(c)]
        if numeric and all(_THOUSANDS_SHAPE.fullmatch(c) for _, c in numeric):
            raise DataError(
                f"{numeric[0][1]!r} is a quoted number with a ',' in a comma-separated file, and every such number has the shape of a "
                "thousands separator (1,000): impedax does not guess whether it is a thousand or one; export the numbers without "
                "thousands separators (or with a ';' between cells when ',' is the decimal mark)",
                path=path, line=numeric[0][0],
            )
        return bool(numeric)
    comma = decimal_comma([c for _, ln in rows[:20] for c in split_line(ln, delimiter)], delimiter)
    if not comma and any("," in ln for _, ln in rows[20:]):  # (the first decimal comma below the 20th row)
        comma = decimal_comma([c for _, ln in rows for c in split_line(ln, delimiter)], delimiter)
    return comma


FREQUENCY_SPAN_MIN = 10.0
"""Smallest max/min ratio (one decade) of the values of a column that looks like a frequency
list (`_looks_like_frequencies`): a sweep spans decades, a Z' column rarely one."""


def _looks_like_frequencies(values: np.ndarray) -> bool:
    """Whether a column reads as a frequency sweep: its non-zero values (a DC row is f = 0)
    positive, strictly monotonic and spanning at least `FREQUENCY_SPAN_MIN`."""
    v = values[values != 0]
    if v.size < 3 or not np.all(v > 0):
        return False
    steps = np.diff(v)
    return bool((np.all(steps > 0) or np.all(steps < 0)) and v.max() / v.min() >= FREQUENCY_SPAN_MIN)


# a column is log-spaced (`_log_spaced`) when this share of its steps in ln f is within
# `LOG_STEP_RTOL` of their median step: an instrument's sweep at so many points a decade, a
# skipped mains frequency or a rounded value allowed
LOG_STEP_SHARE = 0.8
LOG_STEP_RTOL = 0.1


def _log_spaced(values: np.ndarray) -> bool:
    """Whether a column's non-zero values step by a constant ratio (`LOG_STEP_SHARE` of the steps
    within `LOG_STEP_RTOL` of the median), as a logarithmic frequency sweep does; an RC's Z',
    monotonic over decades too, steps by a ratio that changes across its corner."""
    v = values[values != 0]
    if v.size < 4 or not np.all(v > 0):
        return False
    steps = np.diff(np.log(v))
    median = float(np.median(steps))
    return median != 0 and float(np.mean(np.abs(steps - median) <= LOG_STEP_RTOL * abs(median))) >= LOG_STEP_SHARE


def _check_headerless_order(path: Path, line: int, columns: list[np.ndarray]) -> None:
    """A header-less table is read as f, Z', Z'' (`HEADERLESS_NOTE`); refused, naming the column
    that looks like the frequencies, when column 1 does not (`_looks_like_frequencies`) and
    exactly one other column does (Z', Z'', f read as f, Z', Z'' gives nonsense without a word);
    or when column 1 and another look like frequencies and only the other is log-spaced as a
    sweep (`_log_spaced`: an RC's Z' falls monotonically over decades too, and Z', Z'', f of
    Meyer's circuit was read with Z' as the frequencies and Z'' as Z')."""
    looks = [_looks_like_frequencies(c) for c in columns]
    spaced = [k for k in (1, 2) if looks[k] and _log_spaced(columns[k])]
    if not looks[0] and sum(looks[1:]) == 1:
        at = looks.index(True)
        why = "column 1 does not look like frequencies (positive, strictly monotonic, spanning a decade or more)"
    elif (not looks[0] or not _log_spaced(columns[0])) and len(spaced) == 1:
        at = spaced[0]
        why = ("column 1 does not look like frequencies (positive, strictly monotonic, spanning a decade or more)" if not looks[0]
               else "column 1 does not step by a constant ratio as a frequency sweep does")
    else:
        return
    names = ["z_real_ohm", "z_imag_ohm"]
    header = ",".join(names.pop(0) if k != at else "frequency_hz" for k in range(3))
    raise DataError(
        f"no header, and {why} where column {at + 1} does: a header-less table is read as f, Z', Z'' only when column 1 holds the frequencies; "
        f"add a header naming the columns, e.g. {header}",
        path=path, line=line,
    )


def _headerless_columns(rows: list[tuple[int, str]], delimiter: str | None, comma: bool) -> list[np.ndarray] | None:
    """The three columns of a header-less table as numbers, or None when a row is not three numbers."""
    table = []
    for _, text in rows:
        cells = [c.strip().strip('"') for c in split_line(text, delimiter)]
        if len(cells) != 3:
            return None
        try:
            table.append([float(c.replace(",", ".") if comma else c) for c in cells])
        except ValueError:
            return None
    return list(np.array(table, dtype=np.float64).T)


def _digit_shape(cell: str) -> tuple[int, int] | None:
    """(digits after the decimal mark, digits of the exponent) of a number cell; None for other text."""
    m = re.fullmatch(r"[-+]?\d*(?:[.,](\d*))?(?:[eE][-+]?(\d*))?", cell.strip().strip('"').strip())
    return None if m is None else (len(m.group(1) or ""), len(m.group(2) or ""))


LAST_ROW_SAMPLE = 1000
"""How many rows above the last `_check_last_row_complete` compares its digits with (all of a
short file's; a long file's nearest, to keep reading it fast)."""


def _check_last_row_complete(path: Path, layout: Layout, rows: list[tuple[int, str]], delimiter: str | None) -> None:
    """For a file that ends without a line end (cut while copying?): its last row is refused,
    naming its line, when it has fewer fields than the header, or when its last cell, read as a
    column, has fewer digits (after the decimal mark, or of the exponent) than that cell of
    every other row (up to `LAST_ROW_SAMPLE` above it), which all have the same (a fixed format
    such as 1.234560E+02)."""
    if not rows:
        return
    header = list(layout.header)
    while header and not header[-1]:
        header.pop()
    line, text = rows[-1]
    cells = split_line(text, delimiter)
    if not any(c.strip('"') for c in cells):
        return  # (a row of delimiters only: skipped as a blank line)
    while len(cells) > len(header) and not cells[-1]:
        cells.pop()
    cut = CUT_SHORT
    if len(cells) < len(header):
        fields = "1 field" if len(cells) == 1 else f"{len(cells)} fields"
        raise DataError(f"the last row has {fields}, but {layout.field_count_text(len(header))}; {cut}", path=path, line=line)
    column = len(header) - 1
    if len(cells) != len(header) or len(rows) < 3 or column not in {index for index, _ in layout.columns.values()}:
        return
    shapes = set()
    for _, other in rows[-1 - LAST_ROW_SAMPLE:-1]:
        others = split_line(other, delimiter)
        shapes.add(_digit_shape(others[column]) if len(others) > column else None)
        if len(shapes) > 1:
            return
    (usual,) = shapes
    last = _digit_shape(cells[column])
    if usual is not None and last is not None and last != usual and all(a <= b for a, b in zip(last, usual)):
        what = f"{usual[0]} digits after the decimal mark" + (f" and {usual[1]} in the exponent" if usual[1] else "")
        raise DataError(
            f"column {header[column]!r}: {cells[column]!r} on the last row has fewer digits than on every other row ({what}); {cut}",
            path=path, line=line,
        )


def read_csv(path: str | Path) -> xr.Dataset:
    """Read one spectrum from delimited text. Errors name the file and line."""
    path = Path(path)
    raw = read_bytes(path)
    canonical = _read_canonical(path, raw)
    if canonical is not None:
        return canonical
    try:
        text = decode_text(raw, path)
    except DataError:
        raise NoLayout("its bytes are not text (UTF-8, Latin-1 or UTF-16)", path=path) from None
    all_lines = text.splitlines()
    lines = [(i + 1, ln) for i, ln in enumerate(all_lines) if (bare := ln.lstrip()) and not bare.startswith(COMMENT_MARKS)]
    if not lines:
        raise NoLayout("file is empty (no header, no data)", path=path)
    header_no, header = lines[0]
    delimiter = find_delimiter(header)
    cells = split_line(header, delimiter)
    attrs: dict[str, object] = {"format": "delimited text"}
    if all(_NUMBER.fullmatch(c) for c in cells):
        if len(cells) != 3:
            raise NoLayout(
                f"the first line is {len(cells)} numbers, not a header; a file without header must have 3 columns "
                f"(f, Z', Z''), else start it with a header such as {','.join(CSV_HEADER)}",
                path=path, line=header_no,
            )
        layout = Layout({"frequency": (0, 1.0), "real": (1, 1.0), "imag": (2, 1.0)}, ("column 1 (f)", "column 2 (Z')", "column 3 (Z'')"),
                        headerless="f, Z', Z''")
        rows = lines
        attrs["interpretation"] = HEADERLESS_NOTE
    else:
        try:
            layout, units_row = header_layout(cells, split_line(lines[1][1], delimiter) if len(lines) > 1 else None, path, header_no)
        except NoLayout:
            delimiters: dict[int, str | None] = {}  # (each candidate header's delimiter, found once: the whole file is searched)

            def cells(at: int, k: int) -> list[str]:
                if at not in delimiters:
                    delimiters[at] = find_delimiter(lines[at][1])
                return split_line(lines[k][1], delimiters[at])

            found = find_header(len(lines), cells, lambda k: lines[k][0], path, maybe_numbers=lambda k: _NUMBERS_ONLY.fullmatch(lines[k][1]) is not None)
            if found is None:
                raise
            delimiter, layout, units_row = find_delimiter(lines[found.at][1]), found.layout, found.units_row
            attrs["preamble"] = preamble_note(lines[0][0], lines[found.at][0], lines[0][1])
            header_no, lines = lines[found.at][0], lines[found.at:]
        if units_row:
            attrs["units_row"] = units_row_note(lines[1][0], split_line(lines[1][1], delimiter))
        rows = lines[2:] if units_row else lines[1:]
    comma = _decimal_mark(path, rows, delimiter)
    if comma:
        attrs["decimal_mark"] = "comma"
    if not text.endswith(("\n", "\r")):
        _check_last_row_complete(path, layout, rows, delimiter)
    skipped = Skipped()  # (a comment line inside the table, "# electrode re-seated here", is reported, not dropped unseen)
    last = rows[-1][0] if rows else header_no
    below = len(rows) - (1 if rows and rows[0][0] == header_no else 0) + ("units_row" in attrs)  # (the lines below the header that are rows; a file without header's first row is its line header_no)
    if last - header_no > below:  # (a line within the table that is no row: blank, or a comment)
        for number, text_line in enumerate(all_lines[header_no:last], start=header_no + 1):
            if text_line.lstrip().startswith(COMMENT_MARKS):
                skipped.add(number, f"comment line ({text_line.strip()[:40]!r})")
    headerless = "interpretation" in attrs
    try:
        ds = spectrum_from_rows(path, layout, _split_rows(rows, delimiter), attrs, comma=comma, delimiter=delimiter, header_line=header_no, split_sweeps=True, skipped=skipped, delimited=True)
    except DataError:
        columns = _headerless_columns(rows, delimiter, comma) if headerless else None
        if columns is not None:  # (Z'', Z', f fails as 'frequency must be positive': the column order is the cause)
            _check_headerless_order(path, rows[0][0], columns)
        raise
    if headerless and ds["Z"].ndim == 1:  # (the columns in file order, but for DC rows: `finish` never reorders)
        _check_headerless_order(path, rows[0][0], [ds["frequency"].values, ds["Z"].values.real, ds["Z"].values.imag])
    if not headerless:
        ds.attrs.update(_written_provenance(list(layout.header), [ln for _, ln in rows], delimiter, path))
    return ds


def _split_rows(rows: list[tuple[int, str]], delimiter: str | None) -> RowBlock | list[tuple[int, list[str]]]:
    """``(line, split_line(text))`` of each row: a `RowBlock`, split at once, when no cell is
    quoted and every row has as many cells as the first (a 200,000-row file split row by row
    spent most of its second in the garbage collector); else a list, row by row."""
    texts = [text for _, text in rows]
    if not texts:
        return []
    if any('"' in text for text in texts):
        cells = _unquoted_cells(texts, delimiter)
        if cells is None:
            return [(n, split_line(text, delimiter)) for n, text in rows]
        counts = [text.count(delimiter) + 1 for text in texts]
    elif delimiter is None:
        counts = [len(text.split()) for text in texts]
        cells = "\n".join(texts).split()
    else:
        counts = [text.count(delimiter) + 1 for text in texts]
        cells = delimiter.join(texts).split(delimiter)
        block = "".join(texts)
        if " " in block or not block.isprintable():  # (as split_line strips them)
            cells = [cell.strip() for cell in cells]
    if counts.count(counts[0]) != len(counts) or counts[0] < 1:
        return [(n, split_line(text, delimiter)) for n, text in rows]
    return RowBlock([n for n, _ in rows], cells, counts[0])


def _unquoted_cells(texts: list[str], delimiter: str | None) -> list[str] | None:
    """The cells of ``texts`` (rows holding double quotes), one flat list, as `split_line` gives
    them, when every cell is plain: no quote, or one value in quotes with nothing but spaces
    before the opening one and whitespace after the closing one (``"1.5"``, a whole file quoted,
    as some programs write it); None for anything else (a delimiter or a quote inside quotes, a
    quote inside a cell), which `split_line` splits row by row with the csv module."""
    if delimiter is None or any(len(text) >= _csv.field_size_limit() or "\x00" in text for text in texts):
        return None  # (a cell beyond the csv module's limit, or a NUL: `split_line` splits such a row as it is)
    cells = delimiter.join(texts).split(delimiter)
    out = []
    for cell in cells:
        if '"' not in cell:
            out.append(cell.strip())
            continue
        quoted = cell.lstrip(" ").rstrip()
        if len(quoted) < 2 or quoted[0] != '"' or quoted[-1] != '"' or '"' in quoted[1:-1]:
            return None
        out.append(quoted[1:-1].strip())
    return out


def _setting_value(cell: str):
    """A ``setting_NAME`` cell as a value: empty → None, ``true``/``false`` → bool, a number →
    int or float, anything else (a list joined by ``; ``, a circuit) the text."""
    if cell == "":
        return None
    if cell.lower() in ("true", "false"):  # (`export.table_cell` writes true/false)
        return cell.lower() == "true"
    for kind in (int, float):
        try:
            return kind(cell)
        except ValueError:
            pass
    return cell


def _written_provenance(header: list[str], rows: list[str], delimiter: str | None, path: Path) -> dict[str, object]:
    """The provenance of a CSV impedax wrote (`impedax.io.provenance.provenance_columns` after
    the spectrum's columns, the same on every row) as a netCDF file of it holds it: the attrs
    ``impedax_version``, ``written_utc``, ``provenance`` (the record as JSON text: command,
    settings, source, data_files) and ``saved_from`` (the data's own ``source``). {} for any
    other table, or one whose cells differ from row to row. So ``impedax inspect`` of a CSV
    impedax wrote says what wrote it, as of the same data saved as .nc."""
    import json

    from .provenance import PROVENANCE_KEY

    names = [h.strip().strip('"') for h in header]
    keys = ("impedax_version", "written_utc", "command", "source", "data_files")
    if not rows or not all(k in names for k in keys):
        return {}
    rows = [split_line(row, delimiter) for row in rows]  # (split only here: a table of other columns is not split again)
    at = {name: names.index(name) for name in names if name in keys or name.startswith("setting_")}
    cells = {name: {row[i] if i < len(row) else "" for row in rows} for name, i in at.items()}
    if any(len(values) != 1 for values in cells.values()):
        return {}
    value = {name: next(iter(values)) for name, values in cells.items()}
    record = {
        "impedax_version": value["impedax_version"], "written_utc": value["written_utc"], "command": value["command"] or None,
        "settings": {name.removeprefix("setting_"): _setting_value(text) for name, text in value.items() if name.startswith("setting_")},
        "source": value["source"] or None, "data_files": value["data_files"].split("; ") if value["data_files"] else [],
    }
    attrs = {"impedax_version": record["impedax_version"], "written_utc": record["written_utc"], PROVENANCE_KEY: json.dumps(record)}
    if record["source"] and record["source"] != str(path):
        attrs["saved_from"] = record["source"]
    return attrs


def write_csv(ds: xr.Dataset, path: str | Path | None = None, *, delimiter: str = ",", columns: Mapping[str, object] | None = None) -> str:
    """Write one spectrum as ``frequency_hz,z_real_ohm,z_imag_ohm``, each number in its
    shortest exact form (`number_text`: 9904.999 stays ``9904.999``, where 17 significant
    digits print ``9904.9989999999998``; read back bit for bit); ``delimiter`` "\t" for a .tsv file.
    ``columns`` (name → value, e.g. `impedax.io.provenance.provenance_columns`) follow the
    spectrum's own, the same on every row (`table_cell`, quoted where CSV needs it); `read_csv`
    reads the spectrum back and lists them in ``attrs["other_columns"]``.

    Returns the text; writes it atomically to ``path`` when given.
    """
    z = ds["Z"]
    if z.ndim != 1:
        raise DataError(f"CSV holds one spectrum; this one has dimensions {z.dims} (save it as .nc)", path=path)
    f = ds["frequency"].values
    zv = z.values
    header = list(CSV_HEADER)
    values = [f, zv.real, zv.imag]
    if "sigma" in ds:
        header.append("sigma_ohm")
        values.append(ds["sigma"].values)
    constant = ""
    if columns:
        buffer = io.StringIO()
        writer = _csv.writer(buffer, delimiter=delimiter, lineterminator="")
        writer.writerow([table_cell(v) for v in columns.values()])
        constant = delimiter + buffer.getvalue()
        header.extend(columns)
    lines = [delimiter.join(header)]
    for row in zip(*values):
        lines.append(delimiter.join(number_text(v) for v in row) + constant)
    text = "\n".join(lines) + "\n"
    if path is not None:
        with atomic_path(path) as tmp:
            tmp.write_text(text)
    return text
