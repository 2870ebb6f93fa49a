"""CH Instruments (CHI 600/700 series) A.C. impedance text exports.

Layout: a date line, ``A.C. Impedance``, ``Key: value`` / ``Key = value`` settings
(``Instrument Model:  CHI660E``), a blank line, the column names ``Freq/Hz, Z'/ohm, Z"/ohm,
Z/ohm, Phase/deg``, a blank line, then comma-separated rows.

Conventions: frequency in Hz; Z = ``Z'`` + j·``Z"`` in Ω, Z'' stored as is (negative for
capacitive data); ``Phase/deg`` is the phase of Z.
"""

from __future__ import annotations

from pathlib import Path

import xarray as xr

from ...errors import DataError
from .._common import cut_last_line, frequency_plan_note, head_text, read_text
from ..dates import record_date
from ..registry import Reader
from ..table import detect_layout, spectrum_from_rows

__all__ = ["read_chinstruments", "READER"]

CONVENTIONS = "Freq/Hz; Z = Z'/ohm + j·Z\"/ohm as stored"


def sniff(path: Path, head: bytes) -> str | None:
    lines = [ln.strip() for ln in head_text(head).splitlines()[:40]]
    if "A.C. Impedance" in lines[:5] and any(ln.startswith("Freq/Hz") for ln in lines):
        return None
    return "no 'A.C. Impedance' line and 'Freq/Hz' header"


def read_chinstruments(path: str | Path) -> xr.Dataset:
    """Read a CH Instruments impedance export (see module docstring)."""
    path = Path(path)
    text = read_text(path)
    lines = text.splitlines()
    k = next((i for i, ln in enumerate(lines) if ln.strip().startswith("Freq/Hz")), None)
    if k is None:
        raise DataError("no 'Freq/Hz, Z'/ohm, ...' column-name line", path=path)
    attrs: dict[str, object] = {"format": "CH Instruments text", "instrument": "CH Instruments"}
    for ln in lines[:k]:
        key, sep, value = ln.partition(":")
        if sep and key.strip() == "Instrument Model":
            attrs["instrument"] = f"CH Instruments {value.strip()}"
        key, sep, value = ln.partition("=")
        if sep and key.strip() in _SETTINGS:
            name, scale = _SETTINGS[key.strip()]
            try:
                attrs[name] = float(value.strip()) * scale
            except ValueError:
                pass
    if lines and lines[0].strip():
        record_date(attrs, [" ".join(lines[0].split())])  # ('Feb. 20, 2020 15:55:08' as 2020-02-20T15:55:08)
    layout = detect_layout(lines[k].split(","), path, k + 1)
    rows = [(j + 1, lines[j].split(",")) for j in range(k + 1, len(lines)) if lines[j].strip()]
    ds = spectrum_from_rows(path, layout, rows, attrs, delimiter=",", header_line=k + 1, cut_line=cut_last_line(text, lines))
    note = frequency_plan_note(ds["frequency"].values, attrs.get("initial_frequency_hz"), attrs.get("final_frequency_hz"))
    if note:
        ds.attrs["frequency_plan_note"] = note
    return ds


#: The settings kept (``Key = value`` lines above the table), as numbers: (attribute, scale). The
#: names say DC and mV, so that the gap analysis takes neither for a drive voltage
#: (`impedax.models.gap_inputs.is_voltage_name`).
_SETTINGS = {"High Frequency (Hz)": ("initial_frequency_hz", 1.0), "Low Frequency (Hz)": ("final_frequency_hz", 1.0),
             "Init E (V)": ("dc_voltage_v", 1.0), "Amplitude (V)": ("ac_amplitude_mv", 1e3)}


READER = Reader("CH Instruments text", (".txt",), sniff, read_chinstruments, CONVENTIONS)
