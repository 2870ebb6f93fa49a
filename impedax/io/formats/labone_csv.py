"""Zurich Instruments LabOne sweeper CSV exports of impedance (MFIA ``imps``) data.

Two layouts: one line per field and sweep (``chunk;timestamp;size;fieldname;v0;v1;...``, the
LabOne UI's sweeper export) or one column per field (``frequency;realz;imagz;...``). Several
sweeps (chunks) on the same grid become a ``sweep`` dimension.

Conventions: frequency from ``frequency`` (else the sweep ``grid``) in Hz; Z = ``realz`` +
j·``imagz`` in Ω as stored, or ``absz``·exp(j·``phasez``) with the phase in radians; ``absz`` and
``phasez`` beside ``realz`` and ``imagz`` are compared with them (`polar_attrs`). A point
whose cells are empty in every field (padding of a shorter sweep) is skipped and reported; an
empty cell in some fields only is an error naming the line and point — values are never moved
onto other frequencies.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Sequence

import numpy as np
import xarray as xr

from ...errors import DataError
from .._common import CUT_SHORT, Skipped, check_field_count, check_last_field_digits, column_entry, cut_last_line, finish, head_text, number, radians_beyond_turn_note, read_text, stack
from ..consistency import polar_columns_attrs
from ..registry import Reader

__all__ = ["read_labone_csv", "READER", "recorded_columns", "phasez_note", "polar_attrs"]

CONVENTIONS = "frequency (or grid) [Hz]; Z = realz + j·imagz [Ω], or absz·exp(j·phasez [rad])"


def _layout(text: str):
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


def sniff(path: Path, head: bytes) -> str | None:
    if _layout(head_text(head)) is not None:
        return None
    return "first line is neither 'chunk;timestamp;size;fieldname' nor a table with frequency, realz, imagz"


def read_labone_csv(path: str | Path) -> xr.Dataset:
    """Read a LabOne sweeper CSV export (see module docstring)."""
    path = Path(path)
    text = read_text(path)
    layout = _layout(text)
    if layout is None:
        raise DataError("not a LabOne sweeper CSV export", path=path)
    kind, delimiter = layout
    lines = text.splitlines()
    cut_line = cut_last_line(text, lines)
    # chunk -> field -> [(line, cell) per point]
    chunks: dict[str, dict[str, list[tuple[int, str]]]] = {}
    cut_field = None  # (the values, line and field name of the last line, when the file ends without a line end)
    if kind == "rows":
        for k, line in enumerate(lines[1:], start=2):
            if not line.strip():
                continue
            cells = line.split(delimiter)
            if len(cells) < 5:
                cut = f"; {CUT_SHORT}" if k == cut_line else ""
                raise DataError(f"expected chunk;timestamp;size;fieldname;values..., got {len(cells)} fields{cut}", path=path, line=k)
            if k == cut_line:  # the values of one field along the line: judged after the sweeps (a value missing is said first)
                cut_field = (cells[4:], k, cells[3].strip())
            chunks.setdefault(cells[0].strip(), {})[cells[3].strip().lower()] = [(k, c) for c in cells[4:]]
    else:
        names = [c.strip().lower() for c in lines[0].split(delimiter)]
        chunk_col = names.index("chunk") if "chunk" in names else None
        last_fields: list[str] = []  # (the last cell of each row, for `check_last_field_digits`)
        for k, line in enumerate(lines[1:], start=2):
            if not line.strip():
                continue
            cells = line.split(delimiter)
            check_field_count(cells, len(names), path, k, last_of_cut_file=k == cut_line)
            last_fields.append(cells[-1])
            if k == cut_line:
                check_last_field_digits(last_fields, path, k, name=names[-1])
            fields = chunks.setdefault(cells[chunk_col].strip() if chunk_col is not None else "0", {})
            for name, cell in zip(names, cells):
                fields.setdefault(name, []).append((k, cell))
    sweeps = [(chunk, _sweep(path, chunk, fields, cut_line, by_line=kind == "table")) for chunk, fields in chunks.items()]
    if not sweeps:
        raise DataError("no sweep data after the header line", path=path, line=1)
    if cut_field is not None:
        values, line, name = cut_field
        check_last_field_digits(values, path, line, name=name)
    for _, sweep in sweeps:  # (on each: a sweep read alone, its grid not the others', keeps them too)
        sweep.attrs.update({"format": "Zurich Instruments LabOne CSV", "instrument": "Zurich Instruments"})
    ds = stack(path, sweeps, "sweep")
    ds.attrs.update({"format": "Zurich Instruments LabOne CSV", "instrument": "Zurich Instruments"})
    device = re.search(r"dev\d+", path.name, re.I)
    if device:
        ds.attrs["device"] = device.group().lower()
    return ds


def _sweep(path: Path, chunk: str, fields: dict[str, list[tuple[int, str]]], cut_line: int | None = None, *, by_line: bool = False) -> xr.Dataset:
    """One sweep from its fields' (line, cell) lists; ``cut_line``: the file's last line when the
    file ends without a line end (a field missing there: the file looks cut short); ``by_line``:
    a point per line (one column per field), which `polar_attrs` names by line, else by point."""
    fkey = "frequency" if "frequency" in fields else "grid" if "grid" in fields else None
    if fkey is None:
        raise DataError(f"sweep (chunk) {chunk}: no 'frequency' or 'grid' field", path=path)
    if "realz" in fields and "imagz" in fields:
        parts = ("realz", "imagz")
    elif "absz" in fields and "phasez" in fields:
        parts = ("absz", "phasez")
    else:
        found = sorted(fields)
        raise DataError(f"sweep (chunk) {chunk}: no 'realz'/'imagz' (or 'absz'/'phasez') fields; found {found}", path=path)
    used = (fkey, *parts)
    n = max(len(fields[name]) for name in used)
    skipped = Skipped()
    values: dict[str, list[float]] = {name: [] for name in used}
    where: list[int] = []
    kept: list[int] = []
    for i in range(n):
        cells = {name: fields[name][i] if i < len(fields[name]) else (fields[name][-1][0] if fields[name] else None, "") for name in used}
        empty = [name for name in used if not cells[name][1].strip()]
        line_of_point = cells[fkey][0]
        if len(empty) == len(used):
            skipped.add(line_of_point, f"sweep {chunk} point {i}: empty in every field (padding)")
            continue
        if empty:
            name = empty[0]
            cut = f"; {CUT_SHORT}" if cells[name][0] == cut_line else ""
            raise DataError(f"sweep (chunk) {chunk}, point {i}: {', '.join(empty)} missing (the other fields have a value there){cut}", path=path, line=cells[name][0])
        for name in used:
            values[name].append(number(cells[name][1], path, cells[name][0], f"{name}[{i}]"))
        where.append(line_of_point)
        kept.append(i)
    a = {k: np.array(v) for k, v in values.items()}
    z = a["realz"] + 1j * a["imagz"] if parts == ("realz", "imagz") else a["absz"] * np.exp(1j * a["phasez"])
    attrs = {"sign_convention": sign_convention(parts),
             "units": f"{fkey} in Hz, Z in ohm", "columns": recorded_columns(fkey, parts)}
    if parts == ("absz", "phasez"):
        attrs.update(phasez_note(a["phasez"]))
    elif "absz" in fields and "phasez" in fields:
        polar = {name: [fields[name][i][1] if i < len(fields[name]) else "" for i in kept] for name in ("realz", "imagz", "absz", "phasez")}
        at = where if by_line else kept
        attrs.update(polar_attrs(z, polar, at, path.name, "line" if by_line else "point"))
    return finish(path, a[fkey], z, where, attrs, skipped=skipped)


def polar_attrs(z: np.ndarray, cells: dict[str, Sequence], at: Sequence[int], file_name: str, position: str) -> dict[str, str]:
    """``polar_columns_note`` (`consistency.polar_columns_attrs`) when the fields ``absz`` [Ω] and
    ``phasez`` [rad] beside ``realz`` and ``imagz`` disagree with Z read from those beyond the
    rounding of their digits; ``{}`` when they agree or a cell is not a number. ``cells``: each
    field's cells at Z's points, text as printed (CSV) or numbers (HDF5: their shortest exact
    text); ``at``: each point's place in the file, a ``position`` ('line' or 'point', from 0 as
    the reader's other messages count them); the HDF5 reader's too."""
    try:
        numbers = {name: np.array([float(c) for c in column], dtype=float) for name, column in cells.items()}
    except (TypeError, ValueError):
        return {}
    if not all(np.isfinite(v).all() and v.size == z.size for v in numbers.values()):
        return {}
    text = {name: [c if isinstance(c, str) else repr(float(c)) for c in column] for name, column in cells.items()}
    roles = {"real": "realz", "imag": "imagz", "modulus": "absz", "phase": "phasez"}

    def printed(rows: np.ndarray) -> dict[str, list[str]]:
        return {role: [text[name][i] for i in rows] for role, name in roles.items()}

    return polar_columns_attrs(z, numbers["absz"], np.degrees(numbers["phasez"]), list(at), roles,
                               {"real": 1.0, "imag": 1.0, "modulus": 1.0, "phase": 180 / np.pi}, printed, file_name, position=position)


def phasez_note(phasez: np.ndarray) -> dict:
    """The ``phase_unit_note`` of a LabOne ``phasez`` (radians by the format) beyond ±2π; the HDF5 reader's too."""
    return radians_beyond_turn_note(phasez, "LabOne's field 'phasez'", "if they are degrees, export realz and imagz instead (or phasez in radians)")


def sign_convention(parts: tuple[str, str]) -> str:
    """``attrs["sign_convention"]`` of a sweep read from the fields ``parts``; the HDF5 reader's too."""
    return "realz, imagz hold Z', Z'' as stored" if parts == ("realz", "imagz") else "Z = absz·exp(j·phasez), phase in radians"


def recorded_columns(fkey: str, parts: tuple[str, str]) -> dict[str, dict]:
    """``attrs["columns"]`` of a sweep read from the fields ``fkey`` and ``parts`` (LabOne's units: Hz, Ω, rad); the HDF5 reader's too."""
    roles = ("z_real", "z_imag") if parts == ("realz", "imagz") else ("z_modulus", "z_phase")
    out = {"frequency": column_entry("frequency", fkey)}
    for role, name in zip(roles, parts):
        out[role] = column_entry(role, name, "rad", 180 / np.pi) if role == "z_phase" else column_entry(role, name)
    return out


READER = Reader("Zurich Instruments LabOne CSV", (".csv",), sniff, read_labone_csv, CONVENTIONS)
