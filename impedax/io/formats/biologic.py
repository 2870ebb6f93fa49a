"""BioLogic EC-Lab / BT-Lab text: the ``.mpt`` export and the bare column export.

``.mpt`` layout: ``EC-Lab ASCII FILE``, ``Nb header lines : N`` (N counts every header line,
the column names being line N), ``key : value`` settings, then tab-separated columns
``freq/Hz``, ``Re(Z)/Ohm``, ``-Im(Z)/Ohm``, ``|Z|/Ohm``, ``Phase(Z)/deg``, ``time/s``, ...
The "export as text" variant has only the column-name line and the data.

Conventions: frequency in Hz; Z' = ``Re(Z)/Ohm``; the file stores −Z'' (``-Im(Z)/Ohm``), negated
here. Decimal commas (locale exports) are accepted. Cycles one after another (the ``cycle
number`` column changes) become a ``cycle`` dimension (`impedax.io.table.spectrum_from_rows`).
"""

from __future__ import annotations

import re
from pathlib import Path

import xarray as xr

from ...errors import DataError
from .._common import cut_last_line, cut_short_note, frequency_plan_note, head_text, read_text, unit_scale
from ..dates import record_date
from ..registry import Reader
from ..table import NoLayout, RowBlock, detect_layout, spectrum_from_rows

__all__ = ["read_biologic", "read_biologic_text", "READER", "TEXT_READER"]

CONVENTIONS = "freq/Hz; Re(Z)/Ohm; file stores -Im(Z)/Ohm = -Z'', negated"
_MAGIC = ("EC-Lab ASCII FILE", "BT-Lab ASCII FILE")
# EC-Lab's "Electrode surface area : 0.001 cm²" (a decimal comma in a locale's export; cm2 where ² was lost)
_AREA_CM2 = re.compile(r"([0-9]+(?:[.,][0-9]*)?(?:[eE][-+]?[0-9]+)?)\s*cm(?:²|2|\^2)")


def sniff(path: Path, head: bytes) -> str | None:
    first = head_text(head).lstrip().split("\n", 1)[0].strip()
    return None if first in _MAGIC else "first line is not 'EC-Lab ASCII FILE'"


def sniff_text(path: Path, head: bytes) -> str | None:
    first = head_text(head).lstrip().split("\n", 1)[0]
    cells = [c.strip() for c in first.split("\t")]
    if cells[:1] == ["freq/Hz"] and ("-Im(Z)/Ohm" in cells or "Im(Z)/Ohm" in cells):
        return None
    return "first line is not an EC-Lab column header 'freq/Hz<TAB>Re(Z)/Ohm<TAB>-Im(Z)/Ohm'"


def read_biologic(path: str | Path) -> xr.Dataset:
    """Read a BioLogic EC-Lab ``.mpt`` text export (PEIS/GEIS); see the module docstring."""
    path = Path(path)
    text = read_text(path)
    lines = text.splitlines()
    if len(lines) < 2:
        raise DataError("EC-Lab file ends after its first line", path=path)
    m = re.match(r"\s*Nb header lines\s*:\s*(\d+)", lines[1])
    if not m:
        raise DataError("second line should be 'Nb header lines : N'", path=path, line=2)
    n_header = int(m.group(1))
    if n_header < 3 or n_header > len(lines):
        raise DataError(f"'Nb header lines : {n_header}' does not fit a file of {len(lines)} lines" + cut_short_note(text), path=path, line=2)
    attrs: dict[str, object] = {"format": "BioLogic EC-Lab mpt", "instrument": "BioLogic"}
    if len(lines) > 3 and lines[3].strip() and ":" not in lines[3]:
        attrs["technique"] = lines[3].strip()
    dates: list[str] = []  # (Acquisition started on, Technique started on: the order of day and month is told from both)
    for line in lines[2 : n_header - 1]:
        key, sep, value = line.partition(" : ")
        key = key.strip()
        if not sep:
            continue
        if key == "Device":
            attrs["instrument"] = f"BioLogic {value.strip()}"
        elif key in ("Acquisition started on", "Technique started on"):
            dates.append(value.strip())
        elif key == "Comments":
            attrs["comments"] = value.strip()
        elif key == "Electrode surface area":
            attrs["electrode_surface_area"] = value.strip()
            area = _AREA_CM2.fullmatch(value.strip())
            if area:  # (as a number, under Gamry's key: "0.001 cm²" → 0.001)
                attrs["area_cm2"] = float(area.group(1).replace(",", "."))
        elif key == "Run on channel":
            attrs["channel"] = value.strip()
    if dates:
        record_date(attrs, dates)  # (ISO 8601 when the file establishes the order of day and month, else as written)
    attrs.update(_settings(lines[2 : n_header - 1]))
    _check_header_count(path, lines, n_header)
    ds = _columns(path, lines, n_header - 1, attrs, cut_line=cut_last_line(text, lines))
    note = frequency_plan_note(ds["frequency"].values, attrs.get("initial_frequency_hz"), attrs.get("final_frequency_hz"))
    if note:
        ds.attrs["frequency_plan_note"] = note
    return ds


#: A technique's setting line: its name, two or more spaces, one value (linked techniques write
#: a column of values per technique: those lines are not kept, which one is this spectrum's being untold).
_SETTING_LINE = re.compile(r"(\S.*?)\s{2,}(\S+)\s*")
#: What ``vs.`` under ``E (V)`` sets the DC potential against, in the words Gamry's reader uses.
_VERSUS = {"Ref": "reference electrode", "Eoc": "open circuit (Eoc)"}


def _settings(header: list[str]) -> dict[str, float | str]:
    """The PEIS/GEIS settings of the header lines ``header``: ``fi``/``ff`` with their ``unit``
    lines as ``initial_frequency_hz``/``final_frequency_hz``, ``E (V)`` as ``dc_voltage_v`` and
    the ``vs.`` after it as ``dc_voltage_vs``, ``Va (mV)`` as ``ac_amplitude_mv``; a line that holds
    several values (linked techniques), or a unit impedax does not know, is left out."""
    values: dict[str, str] = {}
    versus = None
    for line in header:
        m = _SETTING_LINE.fullmatch(line)
        if not m:
            continue
        key, value = m.group(1), m.group(2)
        if key == "vs." and "E (V)" in values and versus is None:
            versus = value
        values.setdefault(key, value)
    out: dict[str, float | str] = {}
    for key, name in (("fi", "initial_frequency_hz"), ("ff", "final_frequency_hz")):
        try:
            scale = unit_scale(values[f"unit {key}"], "frequency")
            if scale:
                out[name] = float(values[key]) * scale
        except (KeyError, ValueError):  # (no such line, no number; DataError: a unit such as 'MHZ', milli or mega)
            pass
    for key, name in (("E (V)", "dc_voltage_v"), ("Va (mV)", "ac_amplitude_mv")):
        try:
            if key in values:
                out[name] = float(values[key])
        except ValueError:
            pass
    if "dc_voltage_v" in out and versus in _VERSUS:
        out["dc_voltage_vs"] = _VERSUS[versus]
    return out


#: The column names an EC-Lab impedance export holds (`_columns`).
REQUIRED_COLUMNS = ("freq/Hz", "Re(Z)/Ohm", "-Im(Z)/Ohm")


def _check_header_count(path: Path, lines: list[str], n_header: int) -> None:
    """``Nb header lines : N`` puts the column names on line N; when they are not there but on
    another line of the header (a line deleted or added by hand), `DataError` naming both."""
    names = [c.strip() for c in lines[n_header - 1].split("\t")]
    if all(n in names for n in REQUIRED_COLUMNS):
        return
    found = next((k for k, ln in enumerate(lines[: n_header + 20]) if all(n in [c.strip() for c in ln.split("\t")] for n in REQUIRED_COLUMNS)), None)
    if found is not None:
        raise DataError(
            f"'Nb header lines : {n_header}' puts the column names on line {n_header}, but they are on line {found + 1} "
            f"(was a header line {'deleted' if found + 1 < n_header else 'added'}?): write 'Nb header lines : {found + 1}' on line 2",
            path=path, line=2,
        )


def read_biologic_text(path: str | Path) -> xr.Dataset:
    """Read EC-Lab's bare column export: the ``freq/Hz  Re(Z)/Ohm  -Im(Z)/Ohm ...`` line, then data."""
    path = Path(path)
    text = read_text(path)
    lines = text.splitlines()
    return _columns(path, lines, 0, {"format": "BioLogic EC-Lab text", "instrument": "BioLogic"}, cut_line=cut_last_line(text, lines))


def _columns(path: Path, lines: list[str], header_index: int, attrs: dict, *, cut_line: int | None = None) -> xr.Dataset:
    """The table under the column names on ``lines[header_index]``; ``cut_line``: the file's last
    line when the file ends without a line end (a row there short of fields: cut short)."""
    if header_index >= len(lines):
        raise DataError("file ends before the column-name line", path=path, line=header_index + 1)
    names = [c.strip() for c in lines[header_index].split("\t")]
    missing = [n for n in REQUIRED_COLUMNS if n not in names]
    if missing:
        found = [n for n in names if n][:8]
        technique = attrs.get("technique")
        other = (f": the file holds a {technique!r} experiment (line 4), not an impedance spectrum (EC-Lab's PEIS or GEIS): "
                 "export the impedance technique's data") if technique and "freq/Hz" not in names and "impedance" not in str(technique).lower() else ""
        raise DataError(f"columns {missing} not found on header line {header_index + 1}; found {found}{other}", path=path, line=header_index + 1)
    try:
        layout = detect_layout(names, path, header_index + 1)
    except NoLayout as exc:
        raise DataError(exc.reason, path=path, line=header_index + 1) from None
    rows = RowBlock.split([(k + 1, lines[k]) for k in range(header_index + 1, len(lines)) if lines[k].strip()], "\t")  # (at once: a long file's rows)
    return spectrum_from_rows(path, layout, rows, attrs, delimiter="\t", split_sweeps=True, header_line=header_index + 1, cut_line=cut_line)


READER = Reader("BioLogic EC-Lab mpt", (".mpt",), sniff, read_biologic, CONVENTIONS)
TEXT_READER = Reader("BioLogic EC-Lab text", (".txt",), sniff_text, read_biologic_text, CONVENTIONS)
