"""PalmSens PSTrace ``.pssession`` files.

Layout: UTF-16 text (byte-order mark, sometimes a second one at the end) holding one JSON
object. ``Measurements[i].DataSet`` of type ``...DataSetEIS`` lists ``Values``: arrays with a
``Description`` and a ``Unit`` (``Frequency`` in Hertz, ``ZRe`` and ``ZIm`` in Ω, ``Z``,
``Phase``, ``YRe``, ``YIm`` ...) whose points are ``DataValues[k].V``. Several EIS measurements
on one grid become a ``measurement`` dimension.

Conventions: frequency in Hz; Z' = ``ZRe``; the file stores −Z'' in ``ZIm`` (its ``YIm`` is
+Y'' and its ``Phase`` is −phase, consistent with that), negated here. Its ``Z`` [Ω] and
``Phase`` [°] arrays are compared with |Z'+jZ''| and atan2(Z'', Z') (`_polar_attrs`,
``attrs["polar_columns_note"]`` where they disagree); Z is read from ``ZRe`` and ``ZIm`` alone.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

from ...errors import DataError
from .._common import CUT_AS, column_entry, decode_text, finish, head_text, read_bytes, stack
from ..consistency import float_cells, polar_columns_attrs
from ..registry import Reader

__all__ = ["read_palmsens", "READER"]

CONVENTIONS = "JSON in UTF-16; Frequency [Hz], ZRe [Ω]; ZIm holds -Z'' (negated)"


def sniff(path: Path, head: bytes) -> str | None:
    text = head_text(head).lstrip()
    if text.startswith("{") and "PalmSens" in text[:2000]:
        return None
    return "not a PalmSens session (JSON naming PalmSens)"


def _array(values: list, description: str, path: Path, where: str) -> np.ndarray | None:
    for entry in values:
        if isinstance(entry, dict) and entry.get("Description") == description:
            points = entry.get("DataValues")
            if not isinstance(points, list):
                raise DataError(f"{where}: {description} has no DataValues list", path=path)
            out = []
            for k, p in enumerate(points):
                v = p.get("V") if isinstance(p, dict) else None
                if isinstance(v, bool) or not isinstance(v, (int, float)):
                    raise DataError(f"{where}: {description} point {k} is {v!r}, not a number", path=path)
                out.append(float(v))
            return np.array(out, dtype=float)
    return None


_OHM = ("\u2126", "\u03a9", "Ohm", "ohm")  # (PSTrace writes the ohm sign U+2126; the Greek capital omega looks the same)


def _polar_attrs(values: list, z: np.ndarray, stored: dict[str, np.ndarray], path: Path, where: str) -> dict[str, str]:
    """``polar_columns_note`` (`consistency.polar_columns_attrs`) when the measurement's ``Z``
    array [Ω] or its ``Phase`` [°] (−phase, as its ``Q`` ``-Phase`` says; +phase when it says
    ``Phase``) disagrees with Z read from ZRe and ZIm beyond a double's rounding; ``{}`` when they
    agree, or an array is missing, not numbers, of another length or in another unit. Points
    are counted from 0, as the reader's other messages count them."""
    polar, names = {}, {"real": "ZRe", "imag": "ZIm"}
    for role, name, symbols in (("modulus", "Z", _OHM), ("phase", "Phase", ("°",))):
        entry = next((e for e in values if isinstance(e, dict) and e.get("Description") == name), None)
        unit = entry.get("Unit") if entry is not None else None
        if not isinstance(unit, dict) or unit.get("S") not in symbols:
            continue
        try:
            array = _array(values, name, path, where)
        except DataError:
            continue
        if array is not None and array.size == z.size:
            polar[role], names[role] = (-array if role == "phase" and unit.get("Q") != "Phase" else array), name
    if not polar:
        return {}
    printed = float_cells({**stored, **polar})
    return polar_columns_attrs(z, polar.get("modulus"), polar.get("phase"), range(z.size), names,
                               {role: 1.0 for role in names}, printed, path.name, position="point")


def read_palmsens(path: str | Path) -> xr.Dataset:
    """Read the EIS measurements of a PalmSens ``.pssession`` file (see module docstring)."""
    path = Path(path)
    text = decode_text(read_bytes(path), path)
    padding = "\ufeff\x00 \r\n\t"
    try:  # (from the first character of the JSON, so that an error's line and column are the file's)
        session, _ = json.JSONDecoder().raw_decode(text, len(text) - len(text.lstrip(padding)))
    except json.JSONDecodeError as exc:  # (a cut file: its JSON stops at the end of the text, or inside a string that never ends)
        stops = exc.pos >= len(text.rstrip(padding)) or exc.msg.startswith("Unterminated string")
        cut = f"; the JSON stops at the end of the file before it is complete, {CUT_AS}" if stops else ""
        raise DataError(f"not a PalmSens session: invalid JSON at column {exc.colno}: {exc.msg.removesuffix(' starting at')}{cut}", path=path, line=exc.lineno) from None
    except RecursionError:
        raise DataError("not a PalmSens session: invalid JSON (nested too deeply)", path=path) from None
    measurements = session.get("Measurements") if isinstance(session, dict) else None
    if not isinstance(measurements, list):
        raise DataError("PalmSens session without a 'Measurements' list", path=path)
    spectra = []
    for i, m in enumerate(measurements):
        dataset = m.get("DataSet") if isinstance(m, dict) else None
        if not isinstance(dataset, dict) or "EIS" not in str(dataset.get("Type", "")):
            continue
        values = dataset.get("Values")
        title = str(m.get("Title", f"measurement {i}"))
        where = f"measurement {i} ({title})"
        if not isinstance(values, list):
            raise DataError(f"{where}: DataSet has no Values list", path=path)
        arrays = {name: _array(values, name, path, where) for name in ("Frequency", "ZRe", "ZIm")}
        missing = [name for name, a in arrays.items() if a is None]
        if missing:
            raise DataError(f"{where}: no {', '.join(missing)} array", path=path)
        f, re_, neg_im = arrays["Frequency"], arrays["ZRe"], arrays["ZIm"]
        if not (f.size == re_.size == neg_im.size):
            raise DataError(f"{where}: {f.size} frequencies, {re_.size} ZRe and {neg_im.size} ZIm values", path=path)
        label = title if title not in [s[0] for s in spectra] else f"{title} ({i})"
        attrs = {"format": "PalmSens pssession", "instrument": f"PalmSens {m.get('DeviceSerial', '')}".strip(), "title": title,
                 "sign_convention": "ZIm holds -Z''; negated to Z''", "units": "Frequency in Hz, ZRe and ZIm in ohm",
                 "columns": {"frequency": column_entry("frequency", "Frequency"), "z_real": column_entry("z_real", "ZRe"),
                             "z_imag": column_entry("z_imag", "ZIm", negated=True)}}
        attrs.update(_polar_attrs(values, re_ - 1j * neg_im, {"real": re_, "imag": neg_im}, path, where))
        spectra.append((label, finish(path, f, re_ - 1j * neg_im, list(range(1, f.size + 1)), attrs)))
    if not spectra:
        raise DataError(f"PalmSens session holds no EIS measurement ({len(measurements)} measurements of other kinds)", path=path)
    return stack(path, spectra, "measurement")


READER = Reader("PalmSens pssession", (".pssession",), sniff, read_palmsens, CONVENTIONS)
