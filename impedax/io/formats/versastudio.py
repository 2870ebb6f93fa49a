"""Princeton Applied Research VersaStudio ``.par`` files.

Layout: XML-like sections (``<Application>``, ``<Action0>``, ...); each data segment
``<SegmentN>`` holds ``Definition=`` (comma-separated column names, the last entry a trailing
``0``) and comma-separated rows until ``</SegmentN>``. Segments with ``Frequency(Hz)``, ``Z Real``
and ``Z Imag`` columns are impedance data; several become a ``segment`` dimension when they share
their frequencies.

Conventions: frequency in Hz; Z = ``Z Real`` + j·``Z Imag`` in Ω as stored (it equals the
file's own E/I: ``(E Real + j·E Imag)/(I Real + j·I Imag)``).
"""

from __future__ import annotations

import re
from pathlib import Path

import xarray as xr

from ...errors import DataError
from .._common import cut_short_note, frequency_plan_note, head_text, read_text, stack
from ..registry import Reader
from ..table import NoLayout, detect_layout, spectrum_from_rows

__all__ = ["read_versastudio", "READER"]

CONVENTIONS = "Frequency(Hz); Z = Z Real + j·Z Imag [Ω] as stored (= E/I)"


def sniff(path: Path, head: bytes) -> str | None:
    text = head_text(head)
    if text.lstrip().startswith("<Application>") and re.search(r"^Name=VersaStudio", text, re.M):
        return None
    return "no '<Application>' section naming VersaStudio"


def read_versastudio(path: str | Path) -> xr.Dataset:
    """Read the impedance segment(s) of a VersaStudio ``.par`` file (see module docstring)."""
    path = Path(path)
    text = read_text(path)
    lines = text.splitlines()
    spectra = []
    tried = []
    settings = _settings(lines)
    k = 0
    while k < len(lines):
        m = re.fullmatch(r"\s*<Segment(\d+)>\s*", lines[k])
        if not m:
            k += 1
            continue
        tag = m.group(1)
        end = next((j for j in range(k + 1, len(lines)) if lines[j].strip() == f"</Segment{tag}>"), None)
        if end is None:
            raise DataError(f"<Segment{tag}> is not closed by </Segment{tag}>" + cut_short_note(text), path=path, line=k + 1)
        definition = next((j for j in range(k + 1, end) if lines[j].startswith("Definition=")), None)
        if definition is None:
            tried.append(f"segment {tag}: no Definition= line")
            k = end + 1
            continue
        names = [c.strip() for c in lines[definition][len("Definition="):].split(",")]
        if names and names[-1] == "0":
            names = names[:-1]
        try:
            layout = detect_layout(names, path, definition + 1)
        except NoLayout as exc:
            tried.append(f"segment {tag}: {exc.reason}")
            k = end + 1
            continue
        rows = [(j + 1, lines[j].split(",")) for j in range(definition + 1, end) if lines[j].strip()]
        attrs = {"format": "VersaStudio par", "instrument": "Princeton Applied Research (VersaStudio)", "segment": tag, **settings}
        ds = spectrum_from_rows(path, layout, rows, attrs, delimiter=",", where=f"segment {tag}: ", header_line=definition + 1)
        note = frequency_plan_note(ds["frequency"].values, settings.get("initial_frequency_hz"), settings.get("final_frequency_hz"))
        if note:
            ds.attrs["frequency_plan_note"] = note
        spectra.append((tag, ds))
        k = end + 1
    if not spectra:
        raise DataError("no segment with Frequency(Hz), Z Real and Z Imag columns" + (f" ({'; '.join(tried)})" if tried else "") + cut_short_note(text), path=path)
    return stack(path, spectra, "segment")


#: The settings kept (``Key=value`` lines of the file's sections), as numbers, under the names
#: Gamry's are kept by (DC and mV RMS: names the gap analysis takes for no drive voltage).
_SETTINGS = {"Start Frequency (Hz)": "initial_frequency_hz", "End Frequency (Hz)": "final_frequency_hz", "Potential (V),Value": "dc_voltage_v",
             "Amplitude (mV RMS)": "ac_voltage_mv_rms", "Working Electrode Area (cm2)": "area_cm2"}
#: What ``Potential (V),Versus=`` sets the DC potential against, in the words Gamry's reader uses.
_VERSUS = {"vs Ref": "reference electrode", "vs OC": "open circuit (Eoc)"}


def _settings(lines: list[str]) -> dict[str, object]:
    """`_SETTINGS` and ``dc_voltage_vs`` from the file's ``Key=value`` lines outside its data
    segments, each kept only when every line of that key agrees (one EIS action, or several
    alike): of several actions' differing values, none is the spectrum's for sure."""
    found: dict[str, set[str]] = {}
    inside = False
    for line in lines:
        text = line.strip()
        if re.fullmatch(r"<Segment\d+>", text):
            inside = True
        elif re.fullmatch(r"</Segment\d+>", text):
            inside = False
        elif not inside and "=" in text:
            key, _, value = text.partition("=")
            if key in _SETTINGS or key == "Potential (V),Versus":
                found.setdefault(key, set()).add(value.strip())
    out: dict[str, object] = {}
    for key, values in found.items():
        if len(values) != 1:
            continue
        (value,) = values
        if key == "Potential (V),Versus":
            if value in _VERSUS:
                out["dc_voltage_vs"] = _VERSUS[value]
            continue
        try:
            out[_SETTINGS[key]] = float(value)
        except ValueError:
            pass
    return out


READER = Reader("VersaStudio par", (".par",), sniff, read_versastudio, CONVENTIONS)
