"""Gamry Framework ``.DTA`` (EISPOT, EISGALV, ... impedance experiments).

Layout: ``EXPLAIN`` on the first line, ``KEY<TAB>TYPE<TAB>VALUE<TAB>description`` header lines
(a ``NOTES`` entry is followed by as many note lines as its count), then one or more tables
``NAME<TAB>TABLE`` each with a column-name row (``Pt Time Freq Zreal Zimag ...``), a units row
(``# s Hz ohm ohm ...``) and tab-indented data rows. Impedance tables are named ``ZCURVE``
(several in one file become a ``curve`` dimension when they share their frequencies).

Conventions: frequency ``Freq`` in Hz; Z = ``Zreal`` + j·``Zimag`` in Ω, Z'' stored as is
(negative for capacitive data). Locale exports with decimal commas are accepted.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import xarray as xr

from ...errors import DataError
from .._common import Skipped, check_field_count, check_last_field_digits, column_entry, cut_short_note, decimal_comma, finish, frequency_plan_note, head_text, number, read_text, stack, unit_scale
from ..dates import record_date
from ..registry import Reader
from ..consistency import polar_columns_attrs
from ..table import NUMBER_CELL

__all__ = ["read_gamry", "READER"]

CONVENTIONS = "Freq [Hz]; Z = Zreal + j·Zimag [Ω] as stored (Z'' < 0 capacitive)"
#: The 4th field of a ``POTEN`` line: its potential is set against the open-circuit potential
#: (T) or the reference electrode (F). The REAL exampleDataGamry.DTA's ``VDC -0.05 T`` and its
#: measured ``Vdc`` column (about ``EOC`` − 0.05 V) show which is which.
_POTEN_VS = {"T": "open circuit (Eoc)", "F": "reference electrode"}
_ATTR_KEYS = {"TITLE": "title", "DATE": "date", "TIME": "time", "PSTAT": "instrument_serial", "AREA": "area_cm2",
              "VDC": "dc_voltage_v", "VAC": "ac_voltage_mv_rms", "FREQINIT": "initial_frequency_hz", "FREQFINAL": "final_frequency_hz"}


def sniff(path: Path, head: bytes) -> str | None:
    text = head_text(head)
    if text.lstrip().startswith("EXPLAIN") or re.search(r"^ZCURVE\d*\tTABLE", text, re.M):
        return None
    return "no 'EXPLAIN' first line and no 'ZCURVE<TAB>TABLE' line"


def read_gamry(path: str | Path) -> xr.Dataset:
    """Read the impedance table(s) (``ZCURVE``) of a Gamry ``.DTA`` file (see module docstring)."""
    path = Path(path)
    text = read_text(path)
    lines = text.splitlines()
    attrs: dict[str, object] = {"format": "Gamry DTA", "instrument": "Gamry"}
    tables: list[int] = []
    notes: list[str] = []
    calibrated: list[str] = []  # (DCCALDATE, ACCALDATE: dates in the file's own order of day and month)
    i = 0
    while i < len(lines):
        cells = lines[i].split("\t")
        key = cells[0].strip()
        if re.fullmatch(r"ZCURVE\d*", key) and len(cells) > 1 and cells[1].strip() == "TABLE":
            tables.append(i)
        elif key == "NOTES" and len(cells) > 2:
            try:
                count = int(cells[2])
            except ValueError:
                raise DataError(f"NOTES count {cells[2].strip()!r} is not a whole number", path=path, line=i + 1) from None
            if not 0 <= count <= len(lines) - i - 1:
                raise DataError(f"NOTES count {count} does not fit the {len(lines) - i - 1} lines that follow", path=path, line=i + 1)
            notes = [ln.strip() for ln in lines[i + 1 : i + 1 + count] if ln.strip()]
            i += 1 + count
            continue
        elif key == "TAG" and len(cells) >= 2:
            attrs["experiment"] = cells[1].strip()
        elif len(cells) >= 3 and key in ("DCCALDATE", "ACCALDATE") and cells[2].strip():
            calibrated.append(cells[2].strip())
        elif len(cells) >= 3 and key in _ATTR_KEYS:
            value = cells[2].strip()
            if len(cells) > 1 and cells[1].strip() in ("QUANT", "IQUANT", "POTEN"):  # (a number, a potential: "-5.00000E-002" read as -0.05)
                number = value.replace(",", ".") if value.count(",") == 1 and "." not in value else value  # (a decimal comma's locale: "1,00000E+000")
                try:
                    value = float(number)
                except ValueError:
                    pass
            attrs[_ATTR_KEYS[key]] = value
            if key == "VDC" and cells[1].strip() == "POTEN" and len(cells) > 3 and cells[3].strip() in _POTEN_VS:
                attrs["dc_voltage_vs"] = _POTEN_VS[cells[3].strip()]
        elif len(cells) >= 3 and key == "EOC" and cells[1].strip() == "QUANT":
            try:
                attrs["ocp_v"] = float(cells[2].strip())
            except ValueError:
                pass
        i += 1
    if not tables:
        raise DataError("no ZCURVE table (is this an impedance experiment?)" + cut_short_note(text), path=path)
    if "date" in attrs and "time" in attrs:
        attrs["date"] = f"{attrs['date']} {attrs.pop('time')}"
    if "date" in attrs:  # (ISO 8601 when the file's dates, its calibration dates too, establish the order of day and month)
        record_date(attrs, [str(attrs["date"]), *calibrated])
    if notes:
        attrs["comments"] = "\n".join(notes)
    attrs["sign_convention"] = "Zimag holds Z'' (negative for capacitive data), taken as stored"
    attrs["units"] = "Freq in Hz, Zreal and Zimag in ohm (from the units row)"
    names = [lines[start].split("\t")[0].strip() for start in tables]
    labels = [n if names.count(n) == 1 else f"{n} #{k + 1}" for k, n in enumerate(names)]
    ends_cut = not text.endswith(("\n", "\r"))
    spectra = [(label, _table(path, lines, start, dict(attrs), ends_cut=ends_cut)) for label, start in zip(labels, tables)]
    ds = stack(path, spectra, "curve")
    note = frequency_plan_note(ds["frequency"].values, attrs.get("initial_frequency_hz"), attrs.get("final_frequency_hz"))
    if note:
        ds.attrs["frequency_plan_note"] = note
    return ds


def _table(path: Path, lines: list[str], start: int, attrs: dict, *, ends_cut: bool = False) -> xr.Dataset:
    """One ``ZCURVE`` table from its column-name row on ``lines[start + 1]``. Every data row must
    have as many fields as that row (`check_field_count`: a row cut short is refused, never read
    as other numbers; so is a last row cut inside its last field, `check_last_field_digits`);
    ``ends_cut``: the file ends without a line end. Decimal commas are decided
    on every row (`decimal_comma`), so that a ',' below the first rows is not read as text, and
    a row with a '.' beside them is refused (`number`)."""
    if start + 2 >= len(lines):
        raise DataError("ZCURVE table has no column-name and units rows", path=path, line=start + 1)
    names = [c.strip() for c in lines[start + 1].split("\t")]
    units = [c.strip() for c in lines[start + 2].split("\t")]
    index = {name: k for k, name in enumerate(names) if name}
    n_fields = len(names)
    while n_fields and not names[n_fields - 1]:
        n_fields -= 1
    missing = [n for n in ("Freq", "Zreal", "Zimag") if n not in index]
    if missing:
        raise DataError(f"ZCURVE table lacks column(s) {missing}; found {[n for n in names if n]}", path=path, line=start + 2)
    scales = {}
    recorded = {}
    for name, quantity, role in (("Freq", "frequency", "frequency"), ("Zreal", "resistance", "z_real"), ("Zimag", "resistance", "z_imag")):
        unit = units[index[name]] if index[name] < len(units) else ""
        scale = unit_scale(unit, quantity) if unit else 1.0
        if scale is None:
            if NUMBER_CELL.fullmatch(unit):
                raise DataError(
                    f"ZCURVE table has no units row: the line under its column names holds numbers ({name} = {unit}); "
                    "Gamry writes one (#, s, Hz, ohm, ...) there: put it back, or save the table as CSV",
                    path=path, line=start + 3,
                )
            raise DataError(f"ZCURVE column {name} has unit {unit!r}, expected {'Hz' if quantity == 'frequency' else 'ohm'}", path=path, line=start + 3)
        scales[name] = scale
        recorded[role] = column_entry(role, name, unit, scale)
    attrs["columns"] = recorded
    rows = []
    for k in range(start + 3, len(lines)):
        line = lines[k]
        if not line.strip():
            continue
        if not line.startswith("\t"):
            break  # end of the table: the next KEY line (EXPERIMENTABORTED, another table ...)
        rows.append((k + 1, line.split("\t")))
    comma = decimal_comma([c for _, cells in rows for c in cells], "\t")
    if comma:  # (attrs["decimal_mark"], as every table reader says it)
        attrs["decimal_mark"] = "comma"
    wanted = {"Freq": index["Freq"], "Zreal": index["Zreal"], "Zimag": index["Zimag"]}
    if "Time" in index:
        wanted["Time"] = index["Time"]
    cols: dict[str, list[float]] = {n: [] for n in wanted}
    for line_no, cells in rows:
        while len(cells) > n_fields and not cells[-1].strip():
            cells = cells[:-1]  # (a trailing tab)
        check_field_count(cells, n_fields, path, line_no, last_of_cut_file=ends_cut and line_no == len(lines))
        if ends_cut and line_no == len(lines):
            check_last_field_digits([row[n_fields - 1] for _, row in rows], path, line_no, name=names[n_fields - 1])
        for name, col in wanted.items():
            cols[name].append(number(cells[col], path, line_no, name, comma=comma) * scales.get(name, 1.0))
    arr = {n: np.array(v) for n, v in cols.items()}
    extra = {"time": (arr["Time"], "s", "time of the measurement")} if "Time" in arr else None
    if not rows:
        raise DataError("the ZCURVE table has no data rows", path=path, line=start + 1)
    z = arr["Zreal"] + 1j * arr["Zimag"]
    attrs.update(_polar_attrs(path, z, rows, index, units, scales, comma))
    return finish(path, arr["Freq"], z, [n for n, _ in rows], attrs, skipped=Skipped(), extra=extra)


def _polar_attrs(path: Path, z: np.ndarray, rows: list, index: dict[str, int], units: list[str], scales: dict[str, float], comma: bool) -> dict[str, str]:
    """``attrs["polar_columns_note"]`` (and ``polar_columns_flipped_phase``) when the table's
    ``Zmod`` [Ω] or ``Zphz`` [deg] disagrees with Zreal + j·Zimag beyond the rounding of their
    digits (`consistency.polar_columns_attrs`); ``{}`` when they agree, or a column is missing,
    not numbers or in a unit not Ω."""
    values, polar_scales = {}, {}
    for name, role in (("Zmod", "modulus"), ("Zphz", "phase")):
        if name not in index:
            continue
        unit = units[index[name]] if index[name] < len(units) else ""
        try:
            scale = unit_scale(unit, "resistance") if role == "modulus" and unit else 1.0  # (Zphz: degrees, its unit a '°' often mis-encoded)
            column = np.array([number(cells[index[name]], path, line, name, comma=comma) for line, cells in rows]) * scale if scale else None
        except (DataError, IndexError):
            continue
        if column is not None:
            values[role], polar_scales[role] = column, scale
    if not values:
        return {}
    cell_index = {"real": index["Zreal"], "imag": index["Zimag"], **{role: index[name] for name, role in (("Zmod", "modulus"), ("Zphz", "phase")) if role in values}}

    def printed(at: np.ndarray) -> dict[str, list[str]]:
        return {role: [rows[i][1][k] for i in at] for role, k in cell_index.items()}

    names = {"real": "Zreal", "imag": "Zimag", "modulus": "Zmod", "phase": "Zphz"}
    return polar_columns_attrs(z, values.get("modulus"), values.get("phase"), [line for line, _ in rows], names,
                              {"real": scales["Zreal"], "imag": scales["Zimag"], **polar_scales}, printed, path.name)


READER = Reader("Gamry DTA", (".dta",), sniff, read_gamry, CONVENTIONS)
