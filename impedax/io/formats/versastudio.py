"""Princeton Applied Research VersaStudio ``.par`` files.

Layout: XML-like sections (``<Application>``, ``<Action0>``, ...); each data segment
``<SegmentN>`` holds ``Definition=`` (comma-separated column names, the last entry a trailing
``0``) and comma-separated rows until ``</SegmentN>``. Segments with ``Frequency(Hz)``, ``Z Real``
and ``Z Imag`` columns are impedance data; several become a ``segment`` dimension when they share
their frequencies.

The EIS action's ``Number of Points`` is the sweep's count only under ``Point Spacing=Linear``; a
logarithmic sweep's points are set by ``Points Per Decade`` (the REAL exampleDataVersaStudio.par:
``Number of Points=30``, 61 rows a ninth of a decade apart at ``Points Per Decade=9``).
``point_count_note`` says which count the header plans and how many rows the file holds, when
they differ (`_count_note`).

Conventions: frequency in Hz; Z = ``Z Real`` + j·``Z Imag`` in Ω as stored (it equals the
file's own E/I: ``(E Real + j·E Imag)/(I Real + j·I Imag)``).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import xarray as xr

from ...data import format_frequency
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
    agreed = _agreed(lines)
    settings = _settings(agreed)
    spacing = {key: agreed[key] for key in _SPACING if key in agreed}
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
        count = _count_note(ds["frequency"].values, spacing, settings.get("initial_frequency_hz"), settings.get("final_frequency_hz"))
        if count:
            ds.attrs["point_count_note"] = count
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


def _agreed(lines: list[str]) -> dict[str, str]:
    """The file's ``Key=value`` lines outside its data segments, key → value, each kept only when
    every line of that key agrees (one EIS action, or several alike): of several actions'
    differing values, none is the spectrum's for sure."""
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
            found.setdefault(key, set()).add(value.strip())
    return {key: next(iter(values)) for key, values in found.items() if len(values) == 1}


def _settings(agreed: dict[str, str]) -> dict[str, object]:
    """`_SETTINGS` as numbers and ``dc_voltage_vs`` from the agreed settings (`_agreed`)."""
    out: dict[str, object] = {}
    for key, value in agreed.items():
        if key == "Potential (V),Versus":
            if value in _VERSUS:
                out["dc_voltage_vs"] = _VERSUS[value]
        elif key in _SETTINGS:
            try:
                out[_SETTINGS[key]] = float(value)
            except ValueError:
                pass
    return out


#: The settings that say how the sweep's points are spaced and counted (`_count_note`).
_SPACING = ("Point Spacing", "Points Per Decade", "Number of Points")


def _count_note(freq, spacing: dict[str, str], initial, final) -> str | None:
    """``point_count_note`` of a segment whose frequencies ``freq`` [Hz] the header's
    ``spacing`` settings (`_SPACING`) plan otherwise. Logarithmic spacing: the points per decade
    set the count (over the planned band, ``initial`` to ``final`` [Hz], when known), and a
    ``Number of Points`` that is not the rows' count is said to be none of this sweep's: the REAL
    file's 30 beside its 61 rows, ``Points Per Decade=9``. Otherwise ``Number of Points`` is the
    count, told when the rows differ. None when the rows match, or without those settings."""
    rows = int(freq.size)
    try:
        per_decade = float(spacing["Points Per Decade"]) if "Points Per Decade" in spacing else None
        announced = int(spacing["Number of Points"]) if "Number of Points" in spacing else None
    except ValueError:
        return None
    if spacing.get("Point Spacing") != "Logarithmic" or not per_decade or per_decade <= 0:
        if announced is None or announced == rows:
            return None
        return f"header says 'Number of Points={announced}'; the file holds {rows} rows" + (" (sweep stopped early?)" if rows < announced else "")
    planned, exact = None, False
    if isinstance(initial, float) and isinstance(final, float) and min(initial, final) > 0:
        steps = abs(np.log10(initial / final)) * per_decade  # (a whole number when the band holds whole steps)
        exact = abs(steps - round(steps)) < 1e-6
        planned = round(steps) + 1 if exact else int(steps) + 1
    # (a band of a fraction of a step ends on either side of it: both counts match)
    if (announced is None or announced == rows) and (planned is None or rows in ((planned,) if exact else (planned, planned + 1))):
        return None
    span = (float(freq[0]), float(freq[-1]))
    decades = abs(np.log10(span[0] / span[1])) if rows > 1 else 0.0
    measured = (rows - 1) / decades if decades > 0 else None
    density = f", {format(round(measured, 1), 'g')} a decade" if measured else ""
    own = f"the file holds {rows} row{'s' if rows != 1 else ''}{density} from {format_frequency(span[0])} to {format_frequency(span[1])}"
    # (the rows' own spacing is the evidence that Points Per Decade, not Number of Points, set them)
    evidence = f" (the rows step by 1/{per_decade:g} decade, as Points Per Decade sets)" if measured and abs(measured / per_decade - 1) < 0.02 else ""
    unused = f"; its 'Number of Points={announced}' is not this sweep's count{evidence}" if announced is not None and announced != rows else ""
    plan = f": {'' if exact else 'about '}{planned} points planned from {format_frequency(initial)} to {format_frequency(final)}" if planned else ""
    head = f"Point Spacing=Logarithmic, Points Per Decade={per_decade:g}{plan}"
    return f"{head}; {own}{unused}"


READER = Reader("VersaStudio par", (".par",), sniff, read_versastudio, CONVENTIONS)
