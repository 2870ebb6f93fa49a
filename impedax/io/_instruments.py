"""Readers for impedance analyzers' own export files, and the registry `load` dispatches on.

Every reader returns the impedax data model (`impedax.data`): frequency in Hz, complex
Z = Z' + jZ'' [Ω] with Z'' < 0 for capacitive data, the instrument's metadata in attrs
(``format``, ``instrument``, ``date``, ``comments``, ... whatever the file offers), and never
reorders or drops points. Sign conventions of the files:

* Gamry ``.DTA`` (ZCURVE table): ``Zreal``, ``Zimag`` store Z' and Z'' as they are.
* BioLogic EC-Lab ``.mpt``: ``Re(Z)/Ohm`` and ``-Im(Z)/Ohm``; the file stores −Z'', negated here.
* Scribner ZPlot ``.z``: ``Z'(a)``, ``Z''(b)`` (columns 5 and 6) store Z' and Z'' as they are.
* Metrohm Autolab NOVA text: ``Z' (Ω)`` and ``-Z'' (Ω)``; the file stores −Z'', negated here.
* Zurich Instruments LabOne (MFIA impedance sweeps): ``realz``, ``imagz`` store Z' and Z''
  (or ``absz`` and ``phasez`` in radians). HDF5 exports need the optional ``h5py``.

A reader is a `Reader(name, extensions, sniff, read)`: ``sniff(path, head)`` looks at the
file name and its first bytes and returns ``None`` when the file is its format, otherwise the
reason it is not; ``read(path)`` returns the Dataset or raises `DataError` naming the line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

import numpy as np
import xarray as xr

from ..data import make_spectrum
from ..errors import DataError

__all__ = ["Reader", "READERS", "read_gamry", "read_biologic", "read_zplot", "read_autolab", "read_labone_csv", "read_labone_hdf5"]


@dataclass(frozen=True)
class Reader:
    """One file format: ``sniff(path, head) -> None | reason``, ``read(path) -> Dataset``."""

    name: str
    extensions: tuple[str, ...]
    sniff: Callable[[Path, bytes], str | None]
    read: Callable[[Path], xr.Dataset]


# --- shared helpers -------------------------------------------------------------------------


def _text(path: Path) -> str:
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise DataError(f"cannot read file: {exc.strerror}", path=path) from None
    if b"\x00" in raw[:4096]:
        raise DataError("binary file, not text", path=path)
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        # instrument software on Windows writes cp1252/latin-1 (µ, °, Ω as single bytes)
        return raw.decode("latin-1")


def _head_text(head: bytes) -> str:
    if b"\x00" in head[:4096]:
        return ""
    return head.decode("utf-8-sig", errors="replace")


def _number(cell: str, decimal_comma: bool, path: Path, line: int, column: str) -> float:
    text = cell.strip()
    if decimal_comma:
        text = text.replace(",", ".")
    try:
        value = float(text)
    except ValueError:
        raise DataError(f"column {column!r}: {cell.strip()!r} is not a number", path=path, line=line) from None
    if not np.isfinite(value):
        raise DataError(f"column {column!r} is {cell.strip()!r} (NaN/Inf are not accepted)", path=path, line=line)
    return value


def _columns(
    rows: Sequence[tuple[int, list[str]]], wanted: dict[str, int], path: Path, decimal_comma: bool, n_fields: int | None = None
) -> dict[str, np.ndarray]:
    """Numbers of the ``wanted`` columns (name → index) of ``rows`` (line number, cells)."""
    out: dict[str, list[float]] = {name: [] for name in wanted}
    for line_no, cells in rows:
        if n_fields is not None and len(cells) < n_fields:
            raise DataError(f"{len(cells)} fields, but the header has {n_fields}", path=path, line=line_no)
        for name, index in wanted.items():
            if index >= len(cells):
                raise DataError(f"row has {len(cells)} fields; column {name!r} is missing", path=path, line=line_no)
            out[name].append(_number(cells[index], decimal_comma, path, line_no, name))
    return {name: np.array(values, dtype=np.float64) for name, values in out.items()}


def _check_frequencies(freq: np.ndarray, lines: Sequence[int], path: Path) -> None:
    seen: dict[float, int] = {}
    for f, line in zip(freq, lines):
        if f <= 0:
            raise DataError(f"frequency must be positive, got {f:g}", path=path, line=line)
        if f in seen:
            raise DataError(f"duplicate frequency {f:g} Hz (also on line {seen[f]})", path=path, line=line)
        seen[f] = line


def _spectrum(path: Path, freq, z, lines, attrs: dict, extra: dict[str, np.ndarray] | None = None) -> xr.Dataset:
    if len(freq) == 0:
        raise DataError("the impedance table has no data rows", path=path)
    _check_frequencies(freq, lines, path)
    ds = make_spectrum(freq, z, attrs={"path": str(path), **{k: v for k, v in attrs.items() if v not in (None, "")}}, source=str(path))
    for name, (values, units, long_name) in (extra or {}).items():
        ds[name] = ("frequency", values, {"units": units, "long_name": long_name})
    return ds


def _decimal_comma(rows: Sequence[tuple[int, list[str]]], delimiter: str) -> bool:
    """Locale exports write ``1,5E+003`` when the field separator is not a comma."""
    if delimiter == ",":
        return False
    sample = [c for _, cells in rows[:20] for c in cells]
    return any(re.fullmatch(r"\s*[-+]?\d+,\d*(?:[eE][-+]?\d+)?\s*", c) for c in sample)


# --- Gamry .DTA -----------------------------------------------------------------------------


def _sniff_gamry(path: Path, head: bytes) -> str | None:
    text = _head_text(head)
    if re.search(r"^ZCURVE\tTABLE", text, re.M) or text.startswith("EXPLAIN") or path.suffix.lower() == ".dta":
        return None
    return "no 'EXPLAIN' first line and no 'ZCURVE<TAB>TABLE' line"


def read_gamry(path: str | Path) -> xr.Dataset:
    """Read the impedance table (``ZCURVE``) of a Gamry Framework ``.DTA`` file.

    Layout: ``KEY<TAB>TYPE<TAB>VALUE<TAB>description`` header lines, then ``ZCURVE<TAB>TABLE``,
    a column-name row (``Pt Time Freq Zreal Zimag ...``), a units row (``# s Hz ohm ohm ...``)
    and tab-indented data rows. Z = Zreal + j·Zimag as stored.
    """
    path = Path(path)
    lines = _text(path).splitlines()
    attrs: dict[str, object] = {"format": "Gamry DTA", "instrument": "Gamry"}
    start = None
    notes: list[str] = []
    i = 0
    while i < len(lines):
        cells = lines[i].split("\t")
        key = cells[0].strip()
        if key == "ZCURVE":
            start = i
            break
        if key == "NOTES" and len(cells) > 2:
            try:
                count = int(cells[2])
            except ValueError:
                count = 0
            notes = [ln.strip() for ln in lines[i + 1 : i + 1 + count] if ln.strip()]
            i += 1 + count
            continue
        if key == "TAG" and len(cells) >= 2:
            attrs["experiment"] = cells[1].strip()
        elif len(cells) >= 3 and key in {"TITLE", "DATE", "TIME", "PSTAT", "AREA", "VDC", "VAC", "FREQINIT", "FREQFINAL"}:
            attrs[{"TITLE": "title", "PSTAT": "instrument_serial", "AREA": "area_cm2", "VDC": "dc_voltage_v", "VAC": "ac_voltage_mv_rms", "FREQINIT": "initial_frequency_hz", "FREQFINAL": "final_frequency_hz"}.get(key, key.lower())] = cells[2].strip()
        i += 1
    if start is None:
        raise DataError("no ZCURVE table (is this an impedance experiment?)", path=path)
    if "date" in attrs and "time" in attrs:
        attrs["date"] = f"{attrs['date']} {attrs.pop('time')}"
    if notes:
        attrs["comments"] = "\n".join(notes)
    if start + 2 >= len(lines):
        raise DataError("ZCURVE table has no column-name and units rows", path=path, line=start + 1)
    names = [c.strip() for c in lines[start + 1].split("\t")]
    units = [c.strip() for c in lines[start + 2].split("\t")]
    index = {name: k for k, name in enumerate(names) if name}
    missing = [n for n in ("Freq", "Zreal", "Zimag") if n not in index]
    if missing:
        raise DataError(f"ZCURVE table lacks column(s) {missing}; found {[n for n in names if n]}", path=path, line=start + 2)
    freq_unit = units[index["Freq"]] if index["Freq"] < len(units) else ""
    if freq_unit and freq_unit.lower() != "hz":
        raise DataError(f"ZCURVE frequency unit is {freq_unit!r}, expected Hz", path=path, line=start + 3)
    rows = []
    for k in range(start + 3, len(lines)):
        line = lines[k]
        if not line.strip():
            continue
        if not line.startswith("\t"):
            break  # end of table (next KEY line, e.g. EXPERIMENTABORTED)
        rows.append((k + 1, line.split("\t")))
    wanted = {"Freq": index["Freq"], "Zreal": index["Zreal"], "Zimag": index["Zimag"]}
    if "Time" in index:
        wanted["Time"] = index["Time"]
    cols = _columns(rows, wanted, path, _decimal_comma(rows, "\t"))
    extra = {"time": (cols["Time"], "s", "time of the measurement")} if "Time" in cols else None
    return _spectrum(path, cols["Freq"], cols["Zreal"] + 1j * cols["Zimag"], [n for n, _ in rows], attrs, extra)


# --- BioLogic EC-Lab .mpt -------------------------------------------------------------------

_MPT_MAGIC = ("EC-Lab ASCII FILE", "BT-Lab ASCII FILE")


def _sniff_biologic(path: Path, head: bytes) -> str | None:
    first = _head_text(head).lstrip().split("\n", 1)[0].strip()
    if first in _MPT_MAGIC:
        return None
    return "first line is not 'EC-Lab ASCII FILE'"


def read_biologic(path: str | Path) -> xr.Dataset:
    """Read a BioLogic EC-Lab ``.mpt`` text export (PEIS/GEIS).

    Layout: ``EC-Lab ASCII FILE``, ``Nb header lines : N`` (N counts every header line
    including the column names on line N), ``key : value`` settings, then tab-separated
    columns ``freq/Hz``, ``Re(Z)/Ohm``, ``-Im(Z)/Ohm``, ... The file stores −Im Z: Z'' = −value.
    Decimal commas (locale exports) are accepted.
    """
    path = Path(path)
    lines = _text(path).splitlines()
    if len(lines) < 2:
        raise DataError("EC-Lab file ends after its first line", path=path)
    m = re.match(r"\s*Nb header lines\s*:\s*(\d+)", lines[1])
    if not m:
        raise DataError("second line should be 'Nb header lines : N'", path=path, line=2)
    n_header = int(m.group(1))
    if n_header < 3 or n_header > len(lines):
        raise DataError(f"'Nb header lines : {n_header}' does not fit a file of {len(lines)} lines", path=path, line=2)
    attrs: dict[str, object] = {"format": "BioLogic EC-Lab mpt", "instrument": "BioLogic"}
    if len(lines) > 3 and lines[3].strip() and ":" not in lines[3]:
        attrs["technique"] = lines[3].strip()
    for line in lines[2 : n_header - 1]:
        key, sep, value = line.partition(" : ")
        key = key.strip()
        if not sep:
            continue
        if key == "Device":
            attrs["instrument"] = f"BioLogic {value.strip()}"
        elif key in ("Acquisition started on", "Technique started on") and "date" not in attrs:
            attrs["date"] = value.strip()
        elif key == "Comments":
            attrs["comments"] = value.strip()
        elif key == "Electrode surface area":
            attrs["electrode_surface_area"] = value.strip()
        elif key == "Run on channel":
            attrs["channel"] = value.strip()
    names = [c.strip() for c in lines[n_header - 1].split("\t")]
    index = {name: k for k, name in enumerate(names) if name}
    required = ("freq/Hz", "Re(Z)/Ohm", "-Im(Z)/Ohm")
    missing = [n for n in required if n not in index]
    if missing:
        raise DataError(f"columns {missing} not found on header line {n_header}; found {[n for n in names if n][:8]}", path=path, line=n_header)
    rows = [(k + 1, lines[k].split("\t")) for k in range(n_header, len(lines)) if lines[k].strip()]
    wanted = {name: index[name] for name in required}
    if "time/s" in index:
        wanted["time/s"] = index["time/s"]
    cols = _columns(rows, wanted, path, _decimal_comma(rows, "\t"))
    extra = {"time": (cols["time/s"], "s", "time of the measurement")} if "time/s" in cols else None
    attrs["sign_note"] = "file stores -Im(Z); converted to Z''"
    return _spectrum(path, cols["freq/Hz"], cols["Re(Z)/Ohm"] - 1j * cols["-Im(Z)/Ohm"], [n for n, _ in rows], attrs, extra)


# --- Scribner ZPlot .z ----------------------------------------------------------------------


def _sniff_zplot(path: Path, head: bytes) -> str | None:
    text = _head_text(head)
    if text.lstrip().upper().startswith("ZPLOT") or re.search(r"^End Comments\s*$", text, re.M):
        return None
    return "no 'ZPLOT' first line and no 'End Comments' line"


def read_zplot(path: str | Path) -> xr.Dataset:
    """Read a Scribner ZPlot/ZView ``.z`` file.

    Layout: a header of ``Key: value`` lines ending with a line ``End Comments``, then one row
    per point, separated by commas or tabs: ``Freq(Hz), Ampl, Bias, Time(Sec), Z'(a), Z''(b),
    GD, Err, Range``. Z = Z'(a) + j·Z''(b) as stored.
    """
    path = Path(path)
    lines = _text(path).splitlines()
    end = next((k for k, ln in enumerate(lines) if ln.strip() == "End Comments"), None)
    if end is None:
        raise DataError("no 'End Comments' line ending the ZPlot header", path=path)
    attrs: dict[str, object] = {"format": "Scribner ZPlot z", "instrument": "Scribner ZPlot"}
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
    attrs["date"] = " ".join(v for v in (date, time) if v)
    columns = {"Freq(Hz)": 0, "Time(Sec)": 3, "Z'(a)": 4, "Z''(b)": 5}
    names_line = lines[end - 1] if end > 0 else ""
    if "Freq(Hz)" in names_line:
        names = [c.strip() for c in re.split(r"\t|,", names_line.strip())]
        located = {n: names.index(n) for n in columns if n in names}
        if len(located) >= 3 and "Time(Sec)" not in located:
            columns = {n: located[n] for n in ("Freq(Hz)", "Z'(a)", "Z''(b)")}
        elif len(located) == 4:
            columns = located
    rows = []
    for k in range(end + 1, len(lines)):
        if lines[k].strip():
            rows.append((k + 1, [c for c in re.split(r"\t|,", lines[k].strip())]))
    cols = _columns(rows, columns, path, decimal_comma=False)
    extra = {"time": (cols["Time(Sec)"], "s", "time of the measurement")} if "Time(Sec)" in cols else None
    return _spectrum(path, cols["Freq(Hz)"], cols["Z'(a)"] + 1j * cols["Z''(b)"], [n for n, _ in rows], attrs, extra)


# --- Metrohm Autolab (NOVA) text exports ----------------------------------------------------

_AUTOLAB_FREQ = re.compile(r"^Frequency \(Hz\)$")
_AUTOLAB_REAL = re.compile(r"^Z' \((Ω|Ohm|ohm)\)$")
_AUTOLAB_NEG_IMAG = re.compile(r"^-Z'' \((Ω|Ohm|ohm)\)$")


def _autolab_header(text: str):
    for k, line in enumerate(text.splitlines()[:50]):
        for delimiter in (";", "\t", ","):
            cells = [c.strip().strip('"') for c in line.split(delimiter)]
            if len(cells) >= 3 and any(_AUTOLAB_FREQ.match(c) for c in cells) and any(_AUTOLAB_NEG_IMAG.match(c) for c in cells):
                return k, delimiter, cells
    return None


def _sniff_autolab(path: Path, head: bytes) -> str | None:
    if _autolab_header(_head_text(head)) is not None:
        return None
    return "no header with 'Frequency (Hz)' and \"-Z'' (Ω)\""


def read_autolab(path: str | Path) -> xr.Dataset:
    """Read a Metrohm Autolab NOVA impedance export (ASCII, ``;``, tab or ``,`` separated).

    Columns (NOVA names): ``Index``, ``Frequency (Hz)``, ``Z' (Ω)``, ``-Z'' (Ω)``, ``Z (Ω)``,
    ``-Phase (°)``, ``Time (s)``. The file stores −Z'': Z'' = −value. Decimal commas accepted.
    """
    path = Path(path)
    text = _text(path)
    found = _autolab_header(text)
    if found is None:
        raise DataError("no header with 'Frequency (Hz)' and \"-Z'' (Ω)\" columns", path=path)
    k, delimiter, names = found
    lines = text.splitlines()
    index = {}
    for col, name in enumerate(names):
        if _AUTOLAB_FREQ.match(name):
            index["Frequency (Hz)"] = col
        elif _AUTOLAB_REAL.match(name):
            index["Z'"] = col
        elif _AUTOLAB_NEG_IMAG.match(name):
            index["-Z''"] = col
        elif name == "Time (s)":
            index["Time (s)"] = col
    if "Z'" not in index:
        raise DataError(f"no \"Z' (Ω)\" column in header {names}", path=path, line=k + 1)
    rows = [(j + 1, [c.strip().strip('"') for c in lines[j].split(delimiter)]) for j in range(k + 1, len(lines)) if lines[j].strip()]
    cols = _columns(rows, index, path, _decimal_comma(rows, delimiter), n_fields=len(names))
    attrs = {"format": "Metrohm Autolab NOVA text", "instrument": "Metrohm Autolab", "sign_note": "file stores -Z''; converted to Z''"}
    if k > 0:
        attrs["comments"] = "\n".join(ln.strip() for ln in lines[:k] if ln.strip())
    extra = {"time": (cols["Time (s)"], "s", "time of the measurement")} if "Time (s)" in cols else None
    return _spectrum(path, cols["Frequency (Hz)"], cols["Z'"] - 1j * cols["-Z''"], [n for n, _ in rows], attrs, extra)


# --- Zurich Instruments LabOne --------------------------------------------------------------


def _labone_layout(text: str):
    """('rows', delimiter) for one-line-per-field exports, ('table', delimiter) for one column per field."""
    first = next((ln for ln in text.splitlines() if ln.strip()), "")
    for delimiter in (";", ","):
        cells = [c.strip().lower() for c in first.split(delimiter)]
        if cells[:4] == ["chunk", "timestamp", "size", "fieldname"]:
            return "rows", delimiter
        if ("realz" in cells and "imagz" in cells) or ("absz" in cells and "phasez" in cells):
            if "frequency" in cells or "grid" in cells:
                return "table", delimiter
    return None


def _sniff_labone_csv(path: Path, head: bytes) -> str | None:
    if _labone_layout(_head_text(head)) is not None:
        return None
    return "first line is neither 'chunk;timestamp;size;fieldname' nor a table with frequency, realz, imagz"


def read_labone_csv(path: str | Path) -> xr.Dataset:
    """Read a Zurich Instruments LabOne sweeper CSV export of impedance (MFIA ``imps``) data.

    Two layouts: one line per field and sweep (``chunk;timestamp;size;fieldname;v0;v1;...``,
    the LabOne UI's sweeper export) or one column per field (``frequency;realz;imagz;...``).
    Z = realz + j·imagz (or absz·e^{j·phasez}, phase in radians); frequency from ``frequency``
    (else the sweep ``grid``). Several sweeps (chunks) on the same grid become a ``sweep``
    dimension.
    """
    path = Path(path)
    text = _text(path)
    layout = _labone_layout(text)
    if layout is None:
        raise DataError("not a LabOne sweeper CSV export", path=path)
    kind, delimiter = layout
    lines = text.splitlines()
    chunks: dict[str, dict[str, tuple[int, list[str]]]] = {}
    if kind == "rows":
        for k, line in enumerate(lines[1:], start=2):
            if not line.strip():
                continue
            cells = line.split(delimiter)
            if len(cells) < 5:
                raise DataError(f"expected chunk;timestamp;size;fieldname;values..., got {len(cells)} fields", path=path, line=k)
            chunks.setdefault(cells[0].strip(), {})[cells[3].strip().lower()] = (k, cells[4:])
    else:
        names = [c.strip().lower() for c in lines[0].split(delimiter)]
        chunk_col = names.index("chunk") if "chunk" in names else None
        per_chunk: dict[str, list[tuple[int, list[str]]]] = {}
        for k, line in enumerate(lines[1:], start=2):
            if not line.strip():
                continue
            cells = line.split(delimiter)
            if len(cells) != len(names):
                raise DataError(f"{len(cells)} fields, but the header has {len(names)}", path=path, line=k)
            per_chunk.setdefault(cells[chunk_col].strip() if chunk_col is not None else "0", []).append((k, cells))
        for chunk, rows in per_chunk.items():
            # columns become pseudo field-rows; a value's line is its own row
            chunks[chunk] = {name: (rows[0][0], [r[1][c] for r in rows]) for c, name in enumerate(names)}
            chunks[chunk]["__lines__"] = (rows[0][0], [str(r[0]) for r in rows])
    sweeps = []
    for chunk, fields in chunks.items():
        fkey = "frequency" if "frequency" in fields else "grid" if "grid" in fields else None
        if fkey is None:
            raise DataError(f"sweep (chunk) {chunk}: no 'frequency' or 'grid' field", path=path)
        cart = "realz" in fields and "imagz" in fields
        if not cart and not ("absz" in fields and "phasez" in fields):
            raise DataError(f"sweep (chunk) {chunk}: no 'realz'/'imagz' (or 'absz'/'phasez') fields; found {sorted(k for k in fields if k != '__lines__')}", path=path)

        def values(name):
            line, cells = fields[name]
            return np.array([_number(c, False, path, line if kind == "rows" else int(fields["__lines__"][1][i]), name) for i, c in enumerate(cells) if c.strip() != ""])

        freq = values(fkey)
        if cart:
            z = values("realz") + 1j * values("imagz")
        else:
            z = values("absz") * np.exp(1j * values("phasez"))
        if z.shape != freq.shape:
            raise DataError(f"sweep (chunk) {chunk}: {freq.size} frequencies but {z.size} impedance values", path=path, line=fields[fkey][0])
        lines_of_points = [fields[fkey][0]] * freq.size if kind == "rows" else [int(v) for v in fields["__lines__"][1]]
        _check_frequencies(freq, lines_of_points, path)
        sweeps.append((chunk, freq, z, lines_of_points))
    if not sweeps:
        raise DataError("no sweep data after the header line", path=path, line=1)
    attrs = {"format": "Zurich Instruments LabOne CSV", "instrument": "Zurich Instruments", "path": str(path)}
    device = re.search(r"dev\d+", path.name, re.I)
    if device:
        attrs["device"] = device.group().lower()
    if len(sweeps) == 1:
        _, freq, z, lines_of_points = sweeps[0]
        return _spectrum(path, freq, z, lines_of_points, attrs)
    freq0 = sweeps[0][1]
    for chunk, freq, _, lines_of_points in sweeps[1:]:
        if freq.shape != freq0.shape or not np.array_equal(freq, freq0):
            raise DataError(f"sweep (chunk) {chunk} has a different frequency grid from sweep {sweeps[0][0]}; export the sweeps separately", path=path, line=lines_of_points[0])
    return make_spectrum(freq0, np.stack([s[2] for s in sweeps]), dims=("sweep",), coords={"sweep": [s[0] for s in sweeps]}, attrs=attrs, source=str(path))


_HDF5_MAGIC = b"\x89HDF\r\n\x1a\n"


def _sniff_labone_hdf5(path: Path, head: bytes) -> str | None:
    if head.startswith(_HDF5_MAGIC) and path.suffix.lower() not in (".nc", ".nc4", ".cdf"):
        return None
    return "no HDF5 signature"


def read_labone_hdf5(path: str | Path) -> xr.Dataset:
    """Read a LabOne HDF5 export: every group holding ``realz`` and ``imagz`` (or ``absz`` and
    ``phasez``) with ``frequency`` (or ``grid``) datasets is one sweep. Needs ``h5py``
    (``pip install h5py``); impedax itself does not depend on it.
    """
    path = Path(path)
    try:
        import h5py
    except ImportError:
        raise DataError("this is an HDF5 file (e.g. a LabOne HDF5 export); reading HDF5 needs h5py: pip install h5py, or export CSV from LabOne", path=path) from None
    found: list[tuple[str, np.ndarray, np.ndarray]] = []
    try:
        with h5py.File(path, "r") as fh:

            def visit(name, obj):
                if not isinstance(obj, h5py.Group):
                    return
                keys = set(obj.keys())
                fkey = "frequency" if "frequency" in keys else "grid" if "grid" in keys else None
                if fkey is None:
                    return
                if {"realz", "imagz"} <= keys:
                    z = np.asarray(obj["realz"][()], float) + 1j * np.asarray(obj["imagz"][()], float)
                elif {"absz", "phasez"} <= keys:
                    z = np.asarray(obj["absz"][()], float) * np.exp(1j * np.asarray(obj["phasez"][()], float))
                else:
                    return
                found.append((name, np.asarray(obj[fkey][()], float).ravel(), z.ravel()))

            fh.visititems(visit)
    except OSError as exc:
        raise DataError(f"not a readable HDF5 file ({exc})", path=path) from None
    if not found:
        raise DataError("HDF5 file holds no group with frequency/grid and realz/imagz datasets (LabOne impedance sweep)", path=path)
    if len(found) > 1:
        names = ", ".join(n for n, _, _ in found[:5])
        raise DataError(f"HDF5 file holds {len(found)} impedance sweeps ({names}); impedax reads one per file", path=path)
    name, freq, z = found[0]
    if freq.shape != z.shape:
        raise DataError(f"{name}: {freq.size} frequencies but {z.size} impedance values", path=path)
    bad = np.flatnonzero(~np.isfinite(freq) | ~np.isfinite(z))
    if bad.size:
        raise DataError(f"{name}: point {bad[0]} is not finite (unfinished sweep?)", path=path)
    _check_frequencies(freq, list(range(freq.size)), path)
    attrs = {"format": "Zurich Instruments LabOne HDF5", "instrument": "Zurich Instruments", "path": str(path), "hdf5_group": name}
    return make_spectrum(freq, z, attrs=attrs, source=str(path))


# Order matters: the most specific signatures first; delimited text is `load`'s fallback.
READERS: tuple[Reader, ...] = (
    Reader("LabOne HDF5", (".h5", ".hdf5"), _sniff_labone_hdf5, read_labone_hdf5),
    Reader("Gamry DTA", (".dta",), _sniff_gamry, read_gamry),
    Reader("BioLogic EC-Lab mpt", (".mpt",), _sniff_biologic, read_biologic),
    Reader("Scribner ZPlot z", (".z",), _sniff_zplot, read_zplot),
    Reader("Zurich Instruments LabOne CSV", (".csv",), _sniff_labone_csv, read_labone_csv),
    Reader("Metrohm Autolab NOVA text", (".txt", ".csv"), _sniff_autolab, read_autolab),
)
