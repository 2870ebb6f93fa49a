"""Tables with named columns → one spectrum: the engine behind delimited text, spreadsheets and
the instrument exports that are tables (BioLogic, Autolab, Parstat, PowerSuite, CH Instruments,
VersaStudio ...).

A header cell is a name and an optional unit, ``Frequency (mHz)``, ``Re(Z)/Ohm``, ``Z' (kΩ)``;
unit prefixes are case-sensitive (mHz is 1e-3 Hz, MHz 1e6 Hz) and an all-capitals ``MHZ`` is
refused as ambiguous. An angular frequency (``omega``, ``ω``, ``w (rad/s)``) is converted to Hz,
f = ω/2π, and ``attrs["units"]`` says so. Z comes from Z' with Z'' or −Z'' columns, or from |Z| with the phase (or
−phase) in degrees or radians. Rows equal to the header are skipped and reported; a row with a
field too many or too few, or an empty Z cell, is an error naming the line: values are never
shifted onto other columns. A row of delimiters only (``,,``) is skipped and reported, as a blank line.
"""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

import numpy as np
import xarray as xr

from ..errors import DataError, SweepGridsDiffer
from ._common import CUT_SHORT, SWEEP_RTOL, UNIT_CELL, Skipped, check_field_count, check_last_field_digits, column_entry, cut_last_line, decimal_comma, finish, first_line, head_text, number, radians_beyond_turn_note, read_text, split_header_cell, unit_scale, unquoted

__all__ = ["ROLES", "FALLBACK_ROLES", "Layout", "detect_layout", "role_of", "fallback_role", "spectrum_from_rows",
           "NUMBER_CELL", "PREAMBLE_ROWS_MAX", "HeaderFound", "RowBlock", "with_units_row", "header_layout", "find_header", "preamble_note", "units_row_note", "EMPTY_ROW"]


_IMAG = {"z_imag", "z_im", "im_z", "im(z)", "imag(z)", "z''", "imag", "imaginary", "zi", "imagz", "zimg", "z''(b)", "zimaginary"}
_PHASE = {"phase", "phase(z)", "z_phase", "phi", "theta", "zphz", "phase_angle", "arg(z)", "argz", "θz", "θ(z)", "theta_z",
          "phase_z", "phi_z", "phasedeg"}
ROLES: dict[str, set[str]] = {
    "frequency": {"frequency", "freq", "freq.", "f", "frequencyhz", "freqhz", "fhz"},
    "real": {"z_real", "z_re", "re_z", "re(z)", "real(z)", "z'", "real", "zr", "realz", "z'(a)"},
    "imag": _IMAG,
    "neg_imag": {"-" + k for k in _IMAG} | {"neg_z_imag", "minus_z_imag"},
    "modulus": {"|z|", "z_mod", "mod(z)", "modz", "magnitude", "abs(z)", "absz", "z_abs", "z", "z_magnitude", "z_mag",
                "mag(z)", "magnitude(z)", "impedance_magnitude", "impedance_modulus"},
    "phase": _PHASE,
    "neg_phase": {"-" + k for k in _PHASE},
    "sigma": {"sigma", "sigma_z", "std", "sem"},
}
"""Header names of each column role, in the form `_key` gives them: a column so named holds that
role, and a unit that does not fit it is an error. Underscores and inner hyphens do not count
(``z_real`` is ``ZReal``, ``theta-z`` is ``theta_z``), and a name may end in a unit suffix of
`_SUFFIX_UNITS` (``ReZ_Ohm``)."""

FALLBACK_ROLES: dict[str, set[str]] = {
    "real": {"re", "r", "rs", "resistance"},
    "imag": {"im", "x", "xs", "reactance"},
    "neg_imag": {"-im", "-x", "-xs", "-reactance"},
    "modulus": {"mag", "impedance", "|impedance|"},
    "phase": {"angle", "θ"},
    "neg_phase": {"-angle", "-θ"},
}
"""Generic names (an LCR meter's R and X, Zahner's Impedance and Phase, Re and Im): a column so
named takes its role only when no column of `ROLES` took it, no other generic column asks for it,
and its unit fits; otherwise it is another column (EC-Lab's ``x``, ``R/Ohm``, ``Re(M)``, a
``Mag (dB)``)."""

_QUANTITY = {"frequency": "frequency", "real": "resistance", "imag": "resistance", "neg_imag": "resistance",
             "modulus": "resistance", "sigma": "resistance", "phase": "angle", "neg_phase": "angle"}
_SLOT = {"neg_imag": "imag", "neg_phase": "phase"}  # a role and its negation hold one quantity
_SUFFIX_UNITS = {"_hz": "Hz", "_ohm": "Ω", "_ohms": "Ω", "_deg": "deg", "_rad": "rad"}


def _squash(key: str) -> str:
    """``key`` without separators: underscores, and hyphens but a leading one (which negates:
    ``-Z''``), so that ``z_real``, ``zreal`` and ``theta-z`` read as ``zreal``, ``thetaz``."""
    return key[:1] + key[1:].replace("_", "").replace("-", "") if key.startswith("-") else key.replace("_", "").replace("-", "")


_ROLE_OF_NAME = {_squash(name): role for role, names in ROLES.items() for name in names}
_FALLBACK_OF_NAME = {_squash(name): role for role, names in FALLBACK_ROLES.items() for name in names}


def _key(name: str) -> str:
    key = re.sub(r"\s+", "", name.lower())
    for old, new in (("’", "'"), ("′", "'"), ("″", "''"), ('"', "''"), ("−", "-")):
        key = key.replace(old, new)
    return key


def _suffix(key: str) -> str:
    """The unit suffix ``key`` ends in (``'_ohm'`` of ``'rez_ohm'``), or ``''``."""
    return next((s for s in _SUFFIX_UNITS if key.endswith(s) and len(key) > len(s)), "")


def _named(key: str, names: dict[str, str]) -> tuple[str | None, str]:
    """The role ``names`` give ``key``, and the unit of its suffix when the role came from the
    name without it (``'rez_ohm'`` → ``('real', 'Ω')``)."""
    role = names.get(_squash(key))
    if role is not None:
        unit = _SUFFIX_UNITS[_suffix(key)] if _suffix(key) else ("deg" if role in ("phase", "neg_phase") and key.endswith("deg") else "")
        return role, unit
    suffix = _suffix(key)
    if suffix and names.get(_squash(key[: -len(suffix)])) is not None:
        return names[_squash(key[: -len(suffix)])], _SUFFIX_UNITS[suffix]
    return None, ""


ANGULAR_NAMES = {"omega", "ω", "angularfrequency", "angfreq"}
"""Header names (as `_key` gives them) of an angular-frequency column, read in rad/s when it
carries no unit. A bare ``w`` is not among them: ``w (rad/s)`` is, by its unit."""
_RAD_PER_SECOND = {"rad/s", "rads-1", "rad/sec", "rads^-1", "rads⁻¹", "rad·s-1", "rad·s⁻¹", "rad*s-1", "rad*s^-1"}
#: Hz per rad/s: f = ω/2π.
ANGULAR_SCALE = 1 / (2 * np.pi)
ANGULAR_UNIT = "rad/s"


# a name and rad/s after a slash, the unit's own slash in it: ``omega/rad/s``, ``ω / (rad/s)``
# (`UNIT_CELL` reads a unit after a slash only when it holds no slash)
_SLASHED_RAD_PER_SECOND = re.compile(r"^(?P<name>.*?\S)\s*/\s*(?:\(\s*rad\s*/\s*s(?:ec)?\s*\)|rad\s*/\s*s(?:ec)?)\s*$", re.IGNORECASE)


def _angular(cell: str) -> bool:
    """Whether a header cell names an angular frequency ω in rad/s: ``omega``, ``ω``, ``angular
    frequency`` without a unit or with rad/s, and ``w``, ``f``, ``frequency`` with rad/s
    (``w (rad/s)``, ``ω/rad s-1``, ``Frequency (rad/s)``, ``omega/rad/s``)."""
    slashed = _SLASHED_RAD_PER_SECOND.match(unquoted(cell))
    m = UNIT_CELL.match(unquoted(cell))
    if slashed:
        name, unit = slashed.group("name"), "rad/s"
    else:
        name, unit = (m.group("name"), m.group("u1") if m.group("u1") is not None else m.group("u2")) if m else (unquoted(cell), "")
    if m and not slashed and not re.sub(r"\s+", "", unit or "").lower() in _RAD_PER_SECOND:
        name, unit = unquoted(cell), ""  # ('omega (Hz)' is no angular frequency with a unit)
    if "Ω" in name or "Ω" in name:  # (the ohm sign, which lower() would turn into ω)
        return False
    key = _squash(_key(name))
    if unit:
        return key in ANGULAR_NAMES or key in ("w", *(_squash(n) for n in ROLES["frequency"]))
    return key in ANGULAR_NAMES


_PREFIXED_SUFFIX = re.compile(r"^(?P<name>.+?)_(?P<unit>[mµμukKMG](?:Hz|hz|HZ|Ohms?|ohms?|OHMS?))$")


def _prefixed_suffix(name: str) -> tuple[str | None, str]:
    """The role and unit of a name ending in a prefixed unit suffix, read in the name's own case
    (``z_real_mohm`` → ``('real', 'mohm')``: milliohm; ``freq_kHz`` → kHz; an all-capitals
    ``_MOHM`` is ambiguous, `unit_scale` says so); ``(None, '')`` otherwise. `_SUFFIX_UNITS`
    holds the unprefixed ones, read from the lowercased key."""
    m = _PREFIXED_SUFFIX.match(name.strip())
    if m is None:
        return None, ""
    role = _ROLE_OF_NAME.get(_squash(_key(m.group("name"))))
    return (role, m.group("unit")) if role is not None else (None, "")


def role_of(cell: str) -> tuple[str, float, str] | None:
    """``(role, scale to SI, unit)`` of a header cell named as in `ROLES`, or ``None`` when it
    names no role (generic names: `fallback_role`). An angular frequency (`_angular`) is the
    frequency role with the scale ``1/2π`` (f = ω/2π) and the unit ``rad/s``."""
    if _angular(cell):
        return "frequency", ANGULAR_SCALE, ANGULAR_UNIT
    name, unit = split_header_cell(cell)
    key = _key(name)
    role, suffix_unit = _named(key, _ROLE_OF_NAME)
    if role is None and not unit:
        role, suffix_unit = _prefixed_suffix(name)
    if role is None:
        m = UNIT_CELL.match(unquoted(cell))
        if m and _named(_key(m.group("name")), _ROLE_OF_NAME)[0] is not None:  # a role with a unit we do not know
            unit = m.group("u1") if m.group("u1") is not None else m.group("u2")
            role = _named(_key(m.group("name")), _ROLE_OF_NAME)[0]
        else:
            return None
    from_suffix = not unit and bool(suffix_unit)
    unit = unit or suffix_unit
    if not unit:
        return role, 1.0, ""
    try:
        scale = unit_scale(unit, _QUANTITY[role])
    except DataError as exc:
        raise DataError(f"column {cell.strip()!r}: {exc}") from None
    if scale is None:
        if from_suffix:  # 'Z_deg' is no modulus in degrees: another column
            return None
        expected = {"frequency": "Hz, mHz, kHz, MHz", "resistance": "Ω (Ohm), mΩ, kΩ, MΩ", "angle": "deg or rad"}[_QUANTITY[role]]
        lost = ""
        if _QUANTITY[role] == "resistance" and ("?" in unit or "\ufffd" in unit):
            lost = ("; a '?' where a unit stands is most often an Ω lost when the file was saved in an encoding without it (Windows' "
                    "cp1252, a Latin-1 CSV): write Ohm in the header, or save the file as UTF-8")
        elif _QUANTITY[role] == "resistance" and _AREA_SPECIFIC.search(unit):
            lost = ("; an area-specific impedance (Ω·cm²) is not read as such: impedax fits Z in Ω, and the gap and force "
                    "need it; divide the column by the electrode area (Ω·cm² / cm² = Ω) and write Ohm in the header, "
                    "or write Ohm to fit per unit area (R then reads in Ω·cm², C in F/cm²)")
        raise DataError(f"column {cell.strip()!r}: unit {unit!r} not understood (expected {expected}){lost}")
    return role, scale, unit


# a resistance unit times an area (Ohm cm2, Ω·cm², ohm*m^2): area-specific impedance
_AREA_SPECIFIC = re.compile(r"[cm]?m\s*(?:\^?2|²)\s*$", re.IGNORECASE)


def fallback_role(cell: str) -> tuple[str, float, str] | None:
    """``(role, scale to SI, unit)`` of a header cell with a generic name of `FALLBACK_ROLES`
    whose unit fits the role (none, or Ω, Hz, degrees ... as for `role_of`); ``None`` otherwise,
    never an error."""
    name, unit = split_header_cell(cell)
    role, suffix_unit = _named(_key(name), _FALLBACK_OF_NAME)
    if role is None:
        return None
    unit = unit or suffix_unit
    if not unit:
        return role, 1.0, ""
    try:
        scale = unit_scale(unit, _QUANTITY[role])
    except DataError:
        return None
    return None if scale is None else (role, scale, unit)


@dataclass(frozen=True)
class Layout:
    """Which column holds what: ``columns[role] = (index, scale to SI)``; ``header[index]`` its name.
    ``headerless``: for a file without header, what its columns are read as (``"f, Z', Z''"``);
    "" for a table under a header."""

    columns: dict[str, tuple[int, float]]
    header: tuple[str, ...]
    ignored: tuple[str, ...] = field(default=())
    headerless: str = ""

    def field_count_text(self, n_fields: int) -> str:
        """What sets a row's number of fields, for `check_field_count`: ``the header has 3``, or
        for a file without header ``a file without header has 3 (f, Z', Z'')``."""
        return f"a file without header has {n_fields} ({self.headerless})" if self.headerless else f"the header has {n_fields}"

    @property
    def cartesian(self) -> bool:
        return "real" in self.columns and ("imag" in self.columns or "neg_imag" in self.columns)

    def name(self, role: str) -> str:
        return self.header[self.columns[role][0]]

    def other_columns(self) -> tuple[str, ...]:
        """The named columns not read, in the header's order: `ignored`, and those of a role Z is
        not read from (|Z| and the phase beside Z' and Z'': EC-Lab's ``|Z|/Ohm`` and
        ``Phase(Z)/deg``)."""
        read = {"frequency", "sigma", *(("real", "imag", "neg_imag") if self.cartesian else ("modulus", "phase", "neg_phase"))}
        unread = {index for role, (index, _) in self.columns.items() if role not in read}
        ignored = set(self.ignored)
        return tuple(cell.strip() for index, cell in enumerate(self.header) if index in unread or (cell.strip() and cell.strip() in ignored))

    def notes(self) -> dict[str, str]:
        """``sign_convention`` and ``units`` attrs saying how the columns were read."""
        if self.cartesian:
            if "neg_imag" in self.columns:
                sign = f"column {self.name('neg_imag')!r} holds -Z''; negated to Z''"
            else:
                sign = f"column {self.name('imag')!r} holds Z'' (negative for capacitive data), taken as stored"
            parts = ["real", "imag" if "imag" in self.columns else "neg_imag"]
        else:
            ph = "phase" if "phase" in self.columns else "neg_phase"
            sign = f"Z = |Z|·exp(j·phase) from {self.name('modulus')!r} and {self.name(ph)!r}" + ("; the file stores -phase" if ph == "neg_phase" else "")
            parts = ["modulus", ph]
        units = []
        for role in ["frequency", *parts]:
            index, scale = self.columns[role]
            if role == "frequency" and scale == ANGULAR_SCALE:
                units.append(f"{self.header[index]!r} as angular frequency ω in rad/s, converted to Hz: f = ω/2π")
                continue
            units.append(f"{self.header[index]!r}" + ("" if scale == 1 else f" ×{scale:g}"))
        return {"sign_convention": sign, "units": "columns used (scaled to Hz, Ω, degrees): " + ", ".join(units) + self._unnamed_units(parts),
                "columns": self.record(parts)}

    def _unnamed_units(self, parts: Sequence[str]) -> str:
        """``; no unit in the header of 'f' (read as Hz), "Z'" and "Z''" (read as Ω)``: the
        columns used whose header names no unit, grouped by the unit impedax read them in; ""
        when every header names its unit, or there is no header (its ``interpretation`` says what the columns were read as)."""
        if self.headerless:
            return ""
        groups: dict[str, list[str]] = {}
        for role in ["frequency", *parts]:
            index, scale = self.columns[role]
            if scale == 1 and not _unit_of(self.header[index]):
                unit = {"frequency": "Hz", "phase": "degrees", "neg_phase": "degrees"}.get(role, "Ω")
                groups.setdefault(unit, []).append(repr(self.header[index].strip()))
        if not groups:
            return ""
        said = [f"{', '.join(names[:-1])} and {names[-1]}" if len(names) > 1 else names[0] for names in groups.values()]
        return "; no unit in the header of " + ", ".join(f"{names} (read as {unit})" for names, unit in zip(said, groups))

    def record(self, parts: Sequence[str]) -> dict[str, dict]:
        """``attrs["columns"]``: each column used (frequency, ``parts``, sigma) by its role, with
        its name, unit, scale and sign (`_common.column_entry`)."""
        out = {}
        for role in ["frequency", *parts, *(["sigma"] if "sigma" in self.columns else [])]:
            index, scale = self.columns[role]
            cell = self.header[index]
            unit = ANGULAR_UNIT if role == "frequency" and scale == ANGULAR_SCALE else _unit_of(cell)
            out[_RECORDED_ROLE[role]] = column_entry(_RECORDED_ROLE[role], cell.strip(), unit, scale, negated=role in ("neg_imag", "neg_phase"))
        return out


#: The ``attrs["columns"]`` role of each layout role (a role and its negation record as one).
_RECORDED_ROLE = {"frequency": "frequency", "real": "z_real", "imag": "z_imag", "neg_imag": "z_imag", "modulus": "z_modulus",
                  "phase": "z_phase", "neg_phase": "z_phase", "sigma": "sigma"}


def _unit_of(cell: str) -> str:
    """The unit a header cell names (``'Frequency (kHz)'`` → ``'kHz'``, ``'ReZ_Ohm'`` → ``'Ω'``),
    or ``''`` when it names none."""
    try:
        found = role_of(cell) or fallback_role(cell)
    except DataError:
        return ""
    return found[2] if found else ""


class NoLayout(DataError):
    """The text is not a table with a spectrum header (so `load` goes on to list the formats tried)."""

    def __init__(self, message: str, *, path=None, line=None):
        self.reason = message
        super().__init__(message, path=path, line=line)


def detect_layout(header: Sequence[str], path: Path, line: int | None) -> Layout:
    """The `Layout` of a header row; `NoLayout` when it names no frequency/Z columns. Columns
    named as in `ROLES` first (of a column in Hz and one of ω in rad/s, the one in Hz); then
    each generic name of `FALLBACK_ROLES` fills a quantity none of them holds, when no other
    generic column asks for it."""
    columns: dict[str, tuple[int, float]] = {}
    ignored: dict[int, str] = {}
    generic: list[tuple[int, str, float]] = []
    for index, cell in enumerate(header):
        try:
            found = role_of(cell)
        except DataError as exc:
            raise DataError(str(exc), path=path, line=line) from None
        if found is None:
            weak = fallback_role(cell)
            if weak is not None:
                generic.append((index, weak[0], weak[1]))
            elif cell.strip():
                ignored[index] = cell.strip()
            continue
        role, scale, _ = found
        if role == "frequency" and role in columns and ANGULAR_SCALE in (scale, columns[role][1]) and scale != columns[role][1]:
            # a column in Hz beside one of ω in rad/s: the Hz one is read, ω is another column
            if scale == ANGULAR_SCALE:
                ignored[index] = cell.strip()
                continue
            ignored[columns[role][0]] = header[columns[role][0]].strip()
        elif role in columns:
            raise DataError(f"two columns for {role}: {header[columns[role][0]]!r} and {cell!r}", path=path, line=line)
        columns[role] = (index, scale)
    held = {_SLOT.get(role, role) for role in columns}
    asked = [_SLOT.get(role, role) for _, role, _ in generic]
    for index, role, scale in generic:
        if _SLOT.get(role, role) in held or asked.count(_SLOT.get(role, role)) > 1:
            ignored[index] = header[index].strip()
        else:
            columns[role] = (index, scale)
    cells = [c.strip() for c in header]
    side_by_side = _side_by_side(cells) if not ("frequency" in columns and (
        "real" in columns and ("imag" in columns or "neg_imag" in columns) or "modulus" in columns and ("phase" in columns or "neg_phase" in columns))) else None
    if side_by_side:
        raise NoLayout(
            f"the header holds spectra side by side ({', '.join(repr(c) for c in side_by_side)}), which impedax does not read: one table "
            "holds one spectrum. Give each spectrum a sheet of its own (sheets on one frequency grid become a sheet dimension), put them "
            "one below the other under one header (a sweep dimension when they share the frequencies), or save each to a file of its own "
            "(docs/io.md, 'Several sweeps in one table')",
            path=path, line=line,
        )
    if "frequency" not in columns:
        in_hz = [c for c in cells if _safe_unit(split_header_cell(c)[1], "frequency")]
        hint = ""
        if in_hz or columns:  # (a table of Z, or a column in Hz: a spectrum whose frequency column has another name)
            hint = (f"; {in_hz[0]!r} is in a frequency unit, but" if in_hz else "; ") + (
                f"{' a' if in_hz else 'a'} frequency column is named {', '.join(repr(n) for n in _FREQUENCY_NAMES)} (any case, with a unit such "
                "as 'Frequency (Hz)' or 'f / kHz'), or 'omega' for an angular frequency in rad/s: rename it so (docs/io.md, 'Column names of a table')")
        raise NoLayout(f"no frequency column in header {cells}{hint}", path=path, line=line)
    if "imag" in columns and "neg_imag" in columns:
        raise DataError("both Z'' and -Z'' columns given; keep one", path=path, line=line)
    if "phase" in columns and "neg_phase" in columns and not ("real" in columns and ("imag" in columns or "neg_imag" in columns)):
        raise DataError("both phase and -phase columns given; keep one", path=path, line=line)
    layout = Layout(columns, tuple(cells), tuple(ignored[i] for i in sorted(ignored)))
    if not layout.cartesian and not ("modulus" in columns and ("phase" in columns or "neg_phase" in columns)):
        raise NoLayout(
            f"cannot find impedance columns in header {cells}; expected Z' and Z'' (or -Z''), or |Z| and phase", path=path, line=line
        )
    return layout


# --- where a table's header is, and a units row under it ---------------------------------------

#: A cell holding one number, with a decimal point or comma (``1.5E+03``, ``0,1``).
NUMBER_CELL = re.compile(r"[-+]?(\d+([.,]\d*)?|[.,]\d+)([eE][-+]?\d+)?")

DELIMITER_NAMES = {"\t": "a tab", ";": "';'", ",": "','", None: "spaces"}
"""The delimiters of delimited text (`csv.find_delimiter`: None is runs of spaces), as messages name them."""


def delimiter_hint(cells: Sequence[str], delimiter: str | None, n_fields: int, *, first_row: bool = False) -> str:
    """What a refusal of a row of other fields than its header's (``cells``, split by the
    header's ``delimiter``) says when another delimiter splits the row into ``n_fields``
    numbers: the row was written with another delimiter than its header (a header typed with ';'
    over rows exported with ','); or, for the table's ``first_row``, when it reads as
    ``n_fields`` numbers written with decimal commas in a comma-separated file (a later row
    follows rows that read right: a cell too many, not the file's decimal mark); "" otherwise
    (a line of text under the table gets none)."""
    text = (delimiter or " ").join(cells)
    for other, name in DELIMITER_NAMES.items():
        split = text.split(other) if other else text.split()
        if other != delimiter and len(split) == n_fields and all(NUMBER_CELL.fullmatch(c.strip().strip('"')) for c in split):
            return f"this row is separated by {name} where the header is by {DELIMITER_NAMES[delimiter]}: save the file with one delimiter throughout"
    if first_row and delimiter == "," and len(cells) > n_fields and _decimal_comma_row(n_fields).fullmatch(text):
        return ("the numbers look written with decimal commas in a file whose cells are separated by ',' too, so each comma splits a number "
                f"({','.join(cells[:2])!r} read as {cells[0]!r} and {cells[1]!r}): save it with ';' between cells, or with decimal points")
    return ""


@functools.lru_cache(maxsize=16)
def _decimal_comma_row(n_fields: int) -> re.Pattern:
    """A row of ``n_fields`` numbers written with decimal commas and separated by ',' as well
    (``3,16,-4,95,2``: 3.16 and -4.95 and 2 in some split): `delimiter_hint`'s last case."""
    number = r"[-+]?\d+(?:,\d+)?(?:[eE][-+]?\d+)?"
    return re.compile(rf"{number}(?:,{number}){{{n_fields - 1}}}")

PREAMBLE_ROWS_MAX = 100
"""Not used: `find_header` looks through every row for a table's header when the first row is
not one (an instrument's or a user's notes above the table: ``Instrument: FooStat 3000``), so a
table below 120 lines of notes is read, not refused as "no frequency column in header ['note',
'1:', 'value']". Kept for code that imports it."""

#: Units of columns that hold no spectrum quantity (time, potential, current, point number ...),
#: which a units row may hold beside Hz, Ω and degrees (`with_units_row`).
OTHER_UNITS = {"s", "ms", "sec", "min", "h", "V", "mV", "A", "mA", "µA", "μA", "uA", "nA", "W", "°C", "K", "%", "#", "bits"}


def _unit_text(cell: str) -> str | None:
    """The unit a units-row cell holds (``Hz``, ``[kOhm]``, ``(°)`` → ``Hz``, ``kOhm``, ``°``),
    or None when the cell is no unit (a number, a name, a lost Ω shown as '?')."""
    text = unquoted(cell)
    if len(text) >= 2 and (text[0], text[-1]) in (("(", ")"), ("[", "]")):
        text = text[1:-1].strip()
    if not text or NUMBER_CELL.fullmatch(text):
        return None
    if text in OTHER_UNITS or re.sub(r"\s+", "", text).lower() in _RAD_PER_SECOND:
        return text
    for quantity in ("frequency", "resistance", "angle"):
        try:
            if unit_scale(text, quantity) is not None:
                return text
        except DataError:
            return text  # (an ambiguous unit, 'MHZ': a unit, which the header's reading refuses by name)
    return None


def with_units_row(header: Sequence[str], below: Sequence[str] | None) -> list[str] | None:
    """The header cells with the units of the row ``below`` written into them, ``Frequency`` over
    ``kHz`` → ``Frequency (kHz)``, when that row is a units row (as Gamry writes, and many
    spreadsheets): every non-empty cell a unit (`_unit_text`; no number, no other text), at least
    one, each under a named header cell that carries no unit or the same one. None otherwise."""
    if below is None:
        return None
    header, below = [c.strip() for c in header], [c.strip() for c in below]
    if len(below) > len(header) and any(below[len(header):]):
        return None
    units = [_unit_text(c) if c else "" for c in below[: len(header)]]
    if not any(units) or any(u is None for u in units):
        return None
    merged = list(header)
    for k, unit in enumerate(units):
        if not unit:
            continue
        own = split_header_cell(header[k])[1] if header[k] else None
        if own is None or (own and own != unit):
            return None  # (a unit under no name, or under a name that has another)
        if not own:
            merged[k] = f"{unquoted(header[k])} ({unit})"
    return merged


def header_layout(header: Sequence[str], below: Sequence[str] | None, path: Path, line: int | None) -> tuple[Layout, bool]:
    """(`detect_layout` of ``header``, whether the row ``below`` held its units): the units of a
    units row (`with_units_row`) are read as if they had been in the header."""
    merged = with_units_row(header, below)
    return detect_layout(merged if merged is not None else header, path, line), merged is not None


@dataclass(frozen=True)
class HeaderFound:
    """A table's header found below other rows (`find_header`): its position among the rows
    searched, its `Layout`, and whether a units row follows it (`with_units_row`)."""

    at: int
    layout: Layout
    units_row: bool


def find_header(count: int, cells: Callable[[int, int], Sequence[str]], line_of: Callable[[int], int], path: Path, *, first: int = 1,
                limit: int | None = None, maybe_numbers: Callable[[int], bool] | None = None) -> HeaderFound | None:
    """The first of ``count`` rows, from ``first`` to ``limit`` (None: every row), that reads as a spectrum header
    (`detect_layout`, through a units row under it) and is followed by a row of as many numbers;
    None when there is none. ``cells(at, k)`` are the cells of row ``k`` as row ``at`` splits
    them (a text file's delimiter is the header's); ``line_of(k)`` its line (or sheet row).
    ``maybe_numbers(k)``: a quick test that row ``k`` may be a row of numbers (False only when it
    cannot be), which spares splitting the rows of a long text that holds no table."""
    def numbers_below(at: int, k: int, n: int) -> bool:  # (row k, as row at splits it: n numbers)
        row = cells(at, k) if k < count else ()
        return len(row) == n and all(NUMBER_CELL.fullmatch(c.strip().strip('"')) for c in row if c.strip())

    for at in range(first, count - 1 if limit is None else min(count - 1, limit)):
        if maybe_numbers is not None and not (maybe_numbers(at + 1) or (at + 2 < count and maybe_numbers(at + 2))):
            continue
        header = cells(at, at)
        if len(header) < 2:
            continue
        if not (numbers_below(at, at + 1, len(header)) or numbers_below(at, at + 2, len(header))):
            continue  # (no row of numbers under it, nor under a units row: no header; cheap, before with_units_row)
        merged = with_units_row(header, cells(at, at + 1))
        data = at + 2 if merged is not None else at + 1
        if data >= count:
            continue
        following = cells(at, data)
        if len(following) != len(header) or not all(NUMBER_CELL.fullmatch(c.strip().strip('"')) for c in following if c.strip()):
            continue
        try:
            layout = detect_layout(merged if merged is not None else header, path, line_of(at))
        except DataError:
            continue
        return HeaderFound(at, layout, merged is not None)
    return None


def preamble_note(first: int, header: int, text: str, word: str = "lines") -> str:
    """``attrs["preamble"]``: the lines (or sheet rows) above a table's header, not read; ``text``
    the first of them, shown up to 60 characters, '…' when more was passed over (one line is
    "line 1: …", not "lines 1–1")."""
    one = word.rstrip("s")
    span = f"{word} {first}–{header - 1}" if header - 1 > first else f"{one} {first}"
    shown = text.strip()
    more = header - 1 > first or len(shown) > 60
    return f"{span}: text above the table's header ({one} {header}), not read: {shown[:60]!r}{' …' if more else ''}"


def units_row_note(line: int, units: Sequence[str], word: str = "line") -> str:
    """``attrs["units_row"]``: a units row under the header, read as the columns' units."""
    return f"{word} {line}: units under the header ({', '.join(u.strip() for u in units if u.strip())}), read as the columns' units"


#: The frequency names a refusal lists (`ROLES` holds them all, in the form `_key` gives them).
_FREQUENCY_NAMES = ("Frequency", "Freq", "Freq.", "f")
#: A label that numbers a spectrum in a header cell: ``Z' cell1``, ``Z'' 2``, ``f1``.
_LABEL = re.compile(r"^(?P<base>.*?\S)(?:\s+\S+|[\s_-]*\d+)$")


def _safe_unit(unit: str, quantity: str) -> bool:
    """Whether ``unit`` is one of ``quantity`` (an ambiguous 'MHZ' counts)."""
    try:
        return bool(unit) and unit_scale(unit, quantity) is not None
    except DataError:
        return True


def _side_by_side(cells: Sequence[str]) -> list[str]:
    """The header cells of spectra side by side (``Z' cell1 (Ohm)``, ``Z'' cell1 (Ohm)``, ``Z' cell2
    (Ohm)``…): named as a Z quantity (`ROLES`) once a label after the name is taken off, one such
    quantity twice or more; [] otherwise."""
    labelled: list[tuple[str, str]] = []
    for cell in cells:
        name, unit = split_header_cell(cell)
        m = _LABEL.match(name)
        if not m or not cell.strip():
            continue
        try:
            found = role_of(f"{m.group('base')} ({unit})" if unit else m.group("base"))
        except DataError:
            continue
        if found is not None and found[0] != "frequency" and found[0] != "sigma":
            labelled.append((_SLOT.get(found[0], found[0]), cell.strip()))
    roles = [role for role, _ in labelled]
    return [cell for role, cell in labelled if roles.count(role) > 1] if any(roles.count(r) > 1 for r in roles) else []


RADIANS_MODULUS_MARGIN = 3.0
"""A phase read in degrees that never leaves ±π/2° cannot carry a |Z| that changes by more than
this × what Bode's gain–phase relation lets such phases change it (`_radians_note`)."""


def _radians_note(layout: Layout, phase: np.ndarray, freq: np.ndarray, modulus: np.ndarray, path: Path, line: int | None) -> dict:
    """A ``phase_unit_note`` when a phase column without a unit, read as degrees, holds
    values that look like radians: all within ±π/2 and some beyond ±0.2 (as degrees, a spectrum
    that never leaves ±1.6° of a resistor's). A `DataError` instead when |Z| says they are
    radians: by Bode's gain–phase relation (d ln|Z|/d ln ω ≈ −(2/π) φ for a minimum-phase
    impedance) phases within ±max|φ|° change ln|Z| by at most (2/π)·max|φ|·(π/180)·ln(f_max/f_min)
    across the band; a |Z| that changes by over `RADIANS_MODULUS_MARGIN` × that (a capacitive arc's
    100× fall beside phases ≤ 1.57) cannot be read in degrees, and impedax does not guess."""
    name = layout.name("phase" if "phase" in layout.columns else "neg_phase")
    found = role_of(name) or fallback_role(name)
    magnitude = np.abs(phase[np.isfinite(phase)])
    if found is None or found[2] or magnitude.size == 0 or magnitude.max() > np.pi / 2 or magnitude.max() < 0.2:
        return {}
    finite = np.isfinite(freq) & (freq > 0) & np.isfinite(modulus) & (modulus > 0)
    if finite.sum() >= 2:
        span = float(np.log(freq[finite].max() / freq[finite].min()))
        allowed = (2 / np.pi) * np.deg2rad(float(magnitude.max())) * span
        change = float(np.log(modulus[finite].max() / modulus[finite].min()))
        if change > RADIANS_MODULUS_MARGIN * allowed:
            raise DataError(
                f"column {name!r} has no unit, and its values (all within ±π/2 = ±1.571) cannot be degrees: phases within "
                f"±{magnitude.max():.3g}° leave |Z| within about {np.exp(allowed):.3g}× across the band, but |Z| changes "
                f"{np.exp(change):.3g}×; they look like radians: name the column '{name} (rad)' (or '{name} (deg)' if they are degrees)",
                path=path, line=line,
            )
    note = (f"column {name!r} has no unit and was read in degrees, but its values all lie within ±π/2 (±1.571), as radians "
            f"would: if they are radians, name the column '{name} (rad)'; if they are degrees (a nearly resistive sample), "
            f"nothing is wrong")
    return {"phase_unit_note": note}


def _degrees_note(layout: Layout, phase: np.ndarray) -> dict:
    """A ``phase_unit_note`` when a phase column whose unit says radians holds values beyond
    ±2π (a full turn), where no impedance phase written in radians goes: they look like degrees
    (``Phase (rad)`` over values down to −60). Read as the unit says; impedax does not guess."""
    name = layout.name("phase" if "phase" in layout.columns else "neg_phase")
    found = role_of(name) or fallback_role(name)
    if found is None or not np.isclose(found[1], np.degrees(1.0)):  # (the unit's scale to degrees: radians)
        return {}
    base = split_header_cell(name)[0]
    return radians_beyond_turn_note(np.deg2rad(phase), f"column {name!r}", f"if they are degrees, name the column '{base} (deg)'")  # (scaled to degrees when read)


#: How `spectrum_from_rows` reports a row of delimiters only (``,,`` or ``;;``), skipped as a blank line.
EMPTY_ROW = "empty row (delimiters only)"


def _first_decimal_comma(rows: Sequence[tuple[int, Sequence[str]]], delimiter: str | None) -> int | None:
    """The line of the first row holding a number written with a decimal comma (`decimal_comma`),
    over the whole table; None when none does."""
    if isinstance(rows, RowBlock) and "," not in "".join(rows.cells):  # (a long table without a ',': no row to look at)
        return None
    for line, cells in rows:
        if "," in "".join(cells) and decimal_comma(cells, delimiter):  # (one join a row: rows without a ',' cost next to nothing)
            return line
    return None


class RowBlock:
    """Rows of a table that all have ``width`` cells, held as one flat list, row after row, with
    each row's line: a long table split at once, without a list per row (200,000 lists held at
    once cost Python's garbage collector several times what splitting them does). Iterates as
    the ``(line, cells)`` pairs `spectrum_from_rows` takes; `column` gives one column's cells."""

    __slots__ = ("lines", "cells", "width")

    def __init__(self, lines: Sequence[int], cells: Sequence[str], width: int):
        if width < 1 or len(cells) != len(lines) * width:
            raise ValueError(f"RowBlock: {len(cells)} cells are not {len(lines)} rows of {width}")
        self.lines, self.cells, self.width = lines, cells, width

    def __len__(self) -> int:
        return len(self.lines)

    def __getitem__(self, k: int) -> tuple[int, Sequence[str]]:
        k = range(len(self.lines))[k]
        return self.lines[k], self.cells[k * self.width:(k + 1) * self.width]

    def __iter__(self):
        width, cells = self.width, self.cells
        return ((line, cells[k * width:(k + 1) * width]) for k, line in enumerate(self.lines))

    def column(self, index: int) -> Sequence[str]:
        """The cells of column ``index`` (0-based), one per row."""
        return self.cells[index::self.width]

    @classmethod
    def split(cls, numbered: Sequence[tuple[int, str]], delimiter: str) -> "RowBlock | list[tuple[int, list[str]]]":
        """``(line, text.split(delimiter))`` of each row of ``numbered``: a `RowBlock`, split at
        once, when every row has as many cells as the first; else a list, row by row."""
        texts = [text for _, text in numbered]
        counts = [text.count(delimiter) for text in texts]
        if not texts or counts.count(counts[0]) != len(counts):
            return [(n, text.split(delimiter)) for n, text in numbered]
        return cls([n for n, _ in numbered], delimiter.join(texts).split(delimiter), counts[0] + 1)


#: A character no number cell of a column read at once (`_columns_at_once`) holds: a number in
#: the file's decimal mark, with spaces or tabs either side, one a line. Letters (nan, inf), '_'
#: (1_000, which float reads), quotes and the other decimal mark are left to the row-by-row loop.
_FOREIGN_TO_POINT = re.compile(r"[^0-9eE+\-. \t\n]")
_FOREIGN_TO_COMMA = re.compile(r"[^0-9eE+\-, \t\n]")


def _columns_at_once(rows: Sequence[tuple[int, Sequence[str]]], n_fields: int, wanted: dict[str, tuple[int, float]],
                     optional: dict[str, int], comma: bool) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]] | None:
    """The columns of ``rows`` read at once, a column at a time, when every row has ``n_fields``
    cells (a `RowBlock` may have more, empty on every row) and every cell of the ``wanted`` columns
    is a number in the file's decimal mark that
    reads finite: ``(values of each wanted role, unscaled; values of each ``optional`` column
    whose every cell reads as a number)``, the numbers `spectrum_from_rows`'s loop reads row by
    row (a 200,000-row table took seconds there). None for anything else (a repeated header, an
    empty row or cell, text, a '.' beside decimal commas, a field too many or too few, NaN), which
    the loop reads, or refuses naming the line and column."""
    if not rows:
        return None
    if isinstance(rows, RowBlock):
        # (cells beyond the header's, empty on every row: a trailing delimiter, which the loop drops)
        if rows.width < n_fields or any(any(c.strip() for c in rows.column(k)) for k in range(n_fields, rows.width)):
            return None
    elif any(len(cells) != n_fields for _, cells in rows):
        return None

    def cells_of(index: int) -> Sequence[str]:
        return rows.column(index) if isinstance(rows, RowBlock) else [cells[index] for _, cells in rows]

    foreign = _FOREIGN_TO_COMMA if comma else _FOREIGN_TO_POINT
    columns: dict[str, np.ndarray] = {}
    for role, (index, _) in wanted.items():
        text = "\n".join(cells_of(index))
        if foreign.search(text) is not None:
            return None
        try:  # (float, as `_common.number` reads a cell; what it refuses, the loop names: an empty cell, '1e', '1,2,3')
            column = np.array([float(c) for c in (text.replace(",", ".") if comma else text).split("\n")], dtype=np.float64)
        except ValueError:
            return None
        if column.size != len(rows) or not np.isfinite(column).all():  # (a line break inside a sheet's cell; 1e999: the loop names it)
            return None
        columns[role] = column
    extra: dict[str, np.ndarray] = {}
    for name, index in optional.items():  # (as the loop: a column of text or gaps is just another column)
        try:
            extra[name] = np.array([float(cell.replace(",", ".") if comma else cell) for cell in cells_of(index)], dtype=np.float64)
        except ValueError:
            continue
    return columns, extra


def _polar_note(layout: Layout, z: np.ndarray, lines: Sequence[int], rows, path: Path, comma: bool, position: str = "line") -> dict:
    """``polar_columns_note`` (and ``polar_columns_flipped_phase``) when the |Z| or phase column
    beside Z' and Z'' disagrees with Z (read from ``lines`` of ``rows``) beyond the rounding of
    its digits (`consistency.polar_columns_attrs`); ``{}`` otherwise, or when such a column holds text. A
    table of more than `consistency.CHECK_ALL_ROWS` rows is checked on `consistency.SAMPLE_ROWS`
    rows spread through it, and on every row when one of them disagrees: reading a long table
    costs no more than before."""
    from .consistency import CHECK_ALL_ROWS, SAMPLE_ROWS, polar_columns_attrs

    imag = "imag" if "imag" in layout.columns else "neg_imag"
    ph = next((role for role in ("phase", "neg_phase") if role in layout.columns), None)
    index = {"real": layout.columns["real"][0], "imag": layout.columns[imag][0]}
    index.update({role: layout.columns[key][0] for role, key in (("modulus", "modulus"), ("phase", ph)) if key in layout.columns})
    scales = {"real": layout.columns["real"][1], "imag": layout.columns[imag][1]}
    scales.update({role: layout.columns[key][1] for role, key in (("modulus", "modulus"), ("phase", ph)) if key in layout.columns})
    sign = {"modulus": 1.0, "phase": -1.0 if ph == "neg_phase" else 1.0}
    names = {role: layout.header[i].strip() for role, i in index.items()}
    if isinstance(rows, RowBlock) and list(rows.lines[:1]) == list(lines[:1]) and len(rows) == len(lines):
        def cells_at(at: np.ndarray) -> dict[str, list[str]]:  # (read at once: the rows are the lines)
            flat, width, at = rows.cells, rows.width, at.tolist()
            return {role: [flat[i * width + k] for i in at] for role, k in index.items()}
    else:
        by_line = {line: cells for line, cells in rows}

        def cells_at(at: np.ndarray) -> dict[str, list[str]]:
            at_lines = [by_line[lines[i]] for i in at.tolist()]
            return {role: [cells[k] for cells in at_lines] for role, k in index.items()}

    def check(at: np.ndarray) -> dict[str, str]:
        cells = cells_at(at)
        values = {}
        for role in ("modulus", "phase"):
            if role in index:
                try:
                    values[role] = np.array([float(c.replace(",", ".") if comma else c) for c in cells[role]]) * scales[role] * sign[role]
                except ValueError:  # (a column of text or gaps: nothing to compare)
                    continue
        if not values:
            return {}

        def printed(k: np.ndarray) -> dict[str, list[str]]:
            return {role: [column[i] for i in k] for role, column in cells.items()}

        return polar_columns_attrs(z[at], values.get("modulus"), values.get("phase"), [lines[i] for i in at], names, scales, printed, path.name, position=position)

    if len(lines) <= CHECK_ALL_ROWS:
        return check(np.arange(len(lines)))
    return check(np.unique(np.linspace(0, len(lines) - 1, SAMPLE_ROWS).round().astype(int))) and check(np.arange(len(lines)))


def spectrum_from_rows(
    path: Path,
    layout: Layout,
    rows: Sequence[tuple[int, Sequence[str]]],
    attrs: dict,
    *,
    comma: bool | None = None,
    delimiter: str | None = None,
    skipped: Skipped | None = None,
    where: str = "",
    header_line: int | None = None,
    split_sweeps: bool = False,
    cut_line: int | None = None,
    delimited: bool = False,
    position: str = "line",
) -> xr.Dataset:
    """One spectrum from ``rows`` (line number, cells; or a `RowBlock`) laid out as ``layout``, read
    a column at a time when every row is a row of numbers (`_columns_at_once`), else row by row. ``cut_line``: the
    file's last line when the file ends without a line end (`_common.cut_last_line`); a row
    there short of fields, or cut inside its last field (`check_last_field_digits`), is refused
    saying the file looks cut short (`check_field_count`). ``delimited``: the rows are
    delimited text split by ``delimiter`` (the header's), and a row of other fields than the
    header's that another delimiter would split right is refused naming both. With
    ``split_sweeps``, a table of several sweeps of one frequency list (the list restarts, or an
    EC-Lab ``cycle number`` column changes) becomes a ``sweep`` (``cycle``) dimension
    (`_sweep_blocks`). ``position``: what the line numbers are, in `_polar_note`'s words ('row'
    for a spreadsheet's rows)."""
    skipped = skipped if skipped is not None else Skipped()
    header = list(layout.header)
    while header and not header[-1]:
        header.pop()
    n_fields = len(header)
    comma_line = _first_decimal_comma(rows, delimiter) if comma is None or comma else None
    if comma is None:  # (every row: with the first 20 only, a comma first met below them would be 'not a number')
        comma = comma_line is not None
    if comma:  # (as delimited text says it; an instrument's table read here says it too)
        attrs["decimal_mark"] = "comma"
    polar = ("modulus", "phase", "neg_phase")
    wanted = {role: col for role, col in layout.columns.items() if not (layout.cartesian and role in polar)}
    values: dict[str, list[float]] = {role: [] for role in wanted}
    lines: list[int] = []
    time_col = next((i for i, h in enumerate(header) if _key(split_header_cell(h)[0]) in ("time", "elapsedtime", "time(sec)")), None)
    cycle_col = next((i for i, h in enumerate(header) if _key(h) in _CYCLE_NAMES), None) if split_sweeps else None
    # optional columns: read while every cell is a number; one of text or gaps is just another column
    optional = {name: index for name, index in (("time", time_col), ("cycle", cycle_col)) if index is not None}
    source_rows = rows  # (|Z| and the phase beside Z', Z'' are read from them: `_polar_note`)
    optional_values: dict[str, list[float]] = {name: [] for name in optional}
    last_fields: list[str] = []  # (the last cell of each data row, for `check_last_field_digits`)
    at_once = _columns_at_once(rows, n_fields, wanted, optional, comma)
    if at_once is not None:  # (every row a row of numbers: the loop below would read the same values, one by one)
        if rows[-1][0] == cut_line:  # (as the loop checks the file's last line, cut without a line end)
            last_column = rows.column(n_fields - 1) if isinstance(rows, RowBlock) else [cells[-1] for _, cells in rows]
            check_last_field_digits([cell.strip() for cell in last_column], path, cut_line, name=header[-1])
        values = {role: column * wanted[role][1] for role, column in at_once[0].items()}
        optional, optional_values = {name: optional[name] for name in at_once[1]}, at_once[1]
        lines = list(rows.lines) if isinstance(rows, RowBlock) else [line for line, _ in rows]
        rows = ()
    for line, cells in rows:
        cells = [c.strip() for c in cells]
        while len(cells) > n_fields and not cells[-1]:
            cells.pop()  # a trailing separator, as in the header
        if [c.strip('"').strip() for c in cells] == [h.strip('"').strip() for h in header]:
            skipped.add(line, "repeated header")
            continue
        if not any(c.strip('"').strip() for c in cells):
            skipped.add(line, EMPTY_ROW)  # (',,' or ';;' as a spreadsheet program leaves them: a blank line)
            continue
        hint = delimiter_hint(cells, delimiter, n_fields, first_row=not last_fields) if delimited and len(cells) != n_fields else ""
        check_field_count(cells, n_fields, path, line, where=where, last_of_cut_file=line == cut_line, hint=hint,
                          expected=layout.field_count_text(n_fields))
        last_fields.append(cells[-1])
        if line == cut_line:
            check_last_field_digits(last_fields, path, line, name=header[-1])
        for role, (index, scale) in wanted.items():
            values[role].append(number(cells[index], path, line, header[index], comma=comma, comma_line=comma_line) * scale)
        for name, index in list(optional.items()):
            try:
                optional_values[name].append(float(cells[index].replace(",", ".") if comma else cells[index]))
            except ValueError:
                del optional[name]
        lines.append(line)
    if not lines:
        raise DataError(f"{where}header but no data rows" + (f" (skipped: {'; '.join(skipped.report())})" if len(skipped) else ""), path=path, line=header_line)
    col = {role: np.array(v) for role, v in values.items()}
    if layout.cartesian:
        z = col["real"] + 1j * (col["imag"] if "imag" in col else -col["neg_imag"])
    else:
        phase = col["phase"] if "phase" in col else -col["neg_phase"]
        z = col["modulus"] * np.exp(1j * np.deg2rad(phase))
        attrs = {**attrs, **_radians_note(layout, phase, col["frequency"], col["modulus"], path, header_line), **_degrees_note(layout, phase)}
    if layout.cartesian and any(role in layout.columns for role in polar):
        attrs = {**attrs, **_polar_note(layout, z, lines, source_rows, path, comma, position)}
    attrs = {**attrs, **layout.notes()}
    if layout.other_columns():
        attrs.setdefault("other_columns", ", ".join(layout.other_columns()))
    extra = {}
    if "time" in optional:
        extra["time"] = (np.array(optional_values["time"]), "s", "time of the measurement")
    freq, sigma = col["frequency"], col.get("sigma")
    cycles = np.array(optional_values["cycle"]) if "cycle" in optional else None
    by_cycle = cycles if cycles is not None and np.isfinite(cycles).all() else None
    sweeps = _sweep_blocks(freq, by_cycle, lines, path) if split_sweeps else None
    if sweeps is None and split_sweeps and by_cycle is not None and np.unique(by_cycle).size == 1:
        attrs = {**attrs, "cycle": f"{by_cycle[0]:g}"}  # one cycle, numbered (a file's pieces are joined by it: `_common.stack`)
    if sweeps is None:
        return _spectrum(path, freq, z, lines, attrs, skipped=skipped, extra=extra, sigma=sigma, where=where)
    dim, labels, blocks, deviation = sweeps
    for i in np.flatnonzero(freq == 0):
        skipped.add(lines[i], "f = 0 (DC row, not an impedance point)")
    skipped.rows.sort()

    def one(b: np.ndarray) -> xr.Dataset:
        return _spectrum(path, freq[b], z[b], [lines[i] for i in b], attrs, skipped=Skipped(), extra={k: (v[b], u, d) for k, (v, u, d) in extra.items()},
                         sigma=None if sigma is None else sigma[b], where=where)

    ds = None if deviation is None else _sweeps_at_once(one, blocks, dim, labels, freq, z, sigma, extra)
    if ds is None:
        spectra = [one(b) for b in blocks]
        if deviation is None:
            raise _grids_differ(path, dim, labels, blocks, spectra, freq, lines, skipped, where)
        grid = spectra[0]["frequency"]
        ds = xr.concat([s.assign_coords(frequency=grid) for s in spectra], dim=dim, combine_attrs="override").assign_coords({dim: labels})
    grid = ds["frequency"]
    note = f"{len(blocks)} {dim}s of {grid.size} points ({_sweep_starts(dim, blocks, lines)})"
    if deviation > 0:
        note += f"; their frequencies differ from {dim} {labels[0]}'s by up to {deviation:.1e} relative, and the grid is {dim} {labels[0]}'s"
    ds.attrs["sweeps"] = note
    if len(skipped):
        ds.attrs["skipped_rows"] = skipped.report()
    return ds


def _sweeps_at_once(one: Callable[[np.ndarray], xr.Dataset], blocks: Sequence[np.ndarray], dim: str, labels: Sequence[str], freq: np.ndarray,
                    z: np.ndarray, sigma: np.ndarray | None, extra: dict) -> xr.Dataset | None:
    """Sweeps of one grid (``blocks`` of one size) stacked over ``dim`` as `xr.concat` of each
    one's spectrum (``one(block)``, on the first's grid) gives them, from the first's Dataset and
    the arrays of all: a Dataset per sweep cost ~1 ms in xarray (4,000 SYNTHETIC EC-Lab cycles
    took 7 s). None when a sweep would not pass `_spectrum`'s checks (a frequency not positive, a
    sigma not positive): the caller builds each, which names the line."""
    index = np.stack(blocks)
    if not np.all(freq[index] > 0) or (sigma is not None and not np.all(sigma[index] > 0)):
        return None
    first = one(blocks[0])
    arrays = {"Z": z, **({} if sigma is None else {"sigma": sigma}), **{k: v for k, (v, _, _) in extra.items()}}
    if set(first.data_vars) != set(arrays):
        return None
    variables = {name: ((dim, *first[name].dims), np.asarray(arrays[name], dtype=first[name].dtype)[index], first[name].attrs) for name in first.data_vars}
    return xr.Dataset(variables, coords=first.coords, attrs=dict(first.attrs)).assign_coords({dim: labels})


#: Header names (as `_key` gives them) of a column numbering the sweeps: EC-Lab's ``cycle number``.
_CYCLE_NAMES = ("cyclenumber", "cycle")


def _sweep_blocks(freq: np.ndarray, cycles: np.ndarray | None, lines: Sequence[int], path: Path):
    """``(dim, labels, blocks, deviation)`` of a table holding several sweeps one after another,
    each block the row indices of one sweep (rows at f = 0 left out); ``None`` for one spectrum.
    A sweep starts where the cycle number changes or, without one, where the first frequency
    comes back (within `SWEEP_RTOL`). The longest sweeps are the list; when every sweep follows
    it (within `SWEEP_RTOL`) they share one grid, and ``deviation`` is how far they strayed.
    With two or more complete sweeps, one cut short (the start of the list) is a `DataError`
    saying so; a single late point near the first frequency (a check at the end of a sweep) is
    no sweep. Sweeps that do not share a grid (`_restarts`: the list restarts near its first
    frequency but not on it; or cycles of other frequencies) come back with ``deviation`` None:
    the caller refuses them (`_grids_differ`) rather than merge them into one spectrum."""
    rows = np.flatnonzero(freq != 0)
    f = freq[rows]
    if cycles is not None and np.unique(cycles[rows]).size > 1:
        values = cycles[rows]
        starts = [0, *(np.flatnonzero(values[1:] != values[:-1]) + 1).tolist()]
        dim, labels = "cycle", [f"{v:g}" for v in values[starts]]
        if len(set(labels)) != len(labels):
            return None  # cycles interleaved: not sweeps one after another
    else:
        near_first = np.abs(f / f[0] - 1) <= SWEEP_RTOL if f.size else np.zeros(0, bool)
        starts = [0, *(np.flatnonzero(near_first[1:] & ~near_first[:-1]) + 1).tolist()]
        dim = "sweep"
        if len(starts) < 2:
            return _restarted_sweeps(rows, f)
        labels = [str(k) for k in range(len(starts))]
    blocks = np.split(rows, starts[1:])
    if any(np.unique(freq[b]).size < b.size for b in blocks):
        return None  # a frequency repeated within a sweep (a sweep down and back up): not repeated sweeps
    n = max(b.size for b in blocks)
    complete = [b for b in blocks if b.size == n]
    grid = freq[complete[0]]
    deviations = [float(np.max(np.abs(freq[b] / grid[: b.size] - 1))) for b in blocks]
    if len(complete) < 2 or max(deviations) > SWEEP_RTOL:
        if dim == "cycle" and min(b.size for b in blocks) >= MIN_SWEEP_POINTS:
            return dim, labels, blocks, None  # cycles one after another, on different grids
        return _restarted_sweeps(rows, f) if dim == "sweep" else None
    if len(complete) < len(blocks):
        sizes = ", ".join(str(b.size) for b in blocks)
        short = next(b for b in blocks if b.size != n)
        raise DataError(
            f"the table holds {len(blocks)} {dim}s of one frequency list ({_sweep_starts(dim, blocks, lines)}), of {sizes} points; "
            f"impedax holds one frequency grid per file: keep the complete {dim}s, or export each to a file of its own",
            path=path, line=lines[short[0]],
        )
    return dim, labels, blocks, max(deviations)


#: Fewest points of a sweep on a grid of its own: one or two points back near the start of the
#: range are a check at the end of a sweep, not a second sweep.
MIN_SWEEP_POINTS = 3
#: How near (a share of the log-frequency span the sweep has covered) a step back must land to the
#: sweep's first frequency to restart the list: a jump back to the start of the range, not a sweep
#: that turns round (down and back up) nor a second range beyond the first (pieces of one spectrum).
RESTART_SPAN_SHARE = 0.25


def _restarted_sweeps(rows: np.ndarray, f: np.ndarray):
    """`_sweep_blocks`'s answer for sweeps on grids of their own (`_restarts`), ``deviation``
    None (the caller refuses them), or None when the list does not restart."""
    restarts = _restarts(f)
    if restarts is None:
        return None
    blocks = np.split(rows, restarts[1:])
    return "sweep", [str(k) for k in range(len(blocks))], blocks, None


def _restarts(f: np.ndarray) -> list[int] | None:
    """Where the sweeps of a list of several start (position 0 first), or None when ``f`` is
    not sweeps one after another: each sweep monotonic in one direction, the next starting
    where the direction reverses with a jump back near the first one's start (within
    `RESTART_SPAN_SHARE` of the span covered), each of at least `MIN_SWEEP_POINTS` points."""
    if f.size < 2 * MIN_SWEEP_POINTS or not np.all(f > 0):
        return None
    log_f = np.log(f)
    steps = np.diff(log_f)
    direction = np.sign(steps[0])
    if direction == 0:
        return None
    starts = [0]
    for i in np.flatnonzero(steps * direction <= 0) + 1:
        first = starts[-1]
        covered = abs(log_f[i - 1] - log_f[first])
        if steps[i - 1] == 0 or abs(log_f[i] - log_f[first]) > RESTART_SPAN_SHARE * covered:
            return None  # a repeated frequency, or a turn that is no jump back to the start
        starts.append(int(i))
    sizes = np.diff([*starts, f.size])
    if len(starts) < 2 or sizes.min() < MIN_SWEEP_POINTS:
        return None
    return starts


def _grids_differ(path: Path, dim: str, labels: Sequence[str], blocks: Sequence[np.ndarray], spectra: Sequence[xr.Dataset],
                  freq: np.ndarray, lines: Sequence[int], skipped: Skipped, where: str) -> SweepGridsDiffer:
    """The error for sweeps one after another on different frequency grids: where the second
    starts, how many sweeps, each one's points, range and lines, how far the grids differ, and
    how to read one alone; it carries each sweep as a spectrum of its own (`SweepGridsDiffer`)."""
    def span(b: np.ndarray) -> str:
        f = freq[b]
        if b.size == 1:  # (a sweep cut short after its first point: not "1 points, 5–5 Hz, lines 9–9")
            return f"1 point, {f[0]:.6g} Hz, line {lines[b[0]]}"
        return f"{b.size} points, {f[0]:.6g}–{f[-1]:.6g} Hz, lines {lines[b[0]]}–{lines[b[-1]]}"

    described = "; ".join(f"{dim} {label}: {span(b)}" for label, b in zip(labels, blocks))
    first = freq[blocks[0]]
    same_size = [b for b in blocks[1:] if b.size == first.size]
    if len(same_size) == len(blocks) - 1:
        differ = max(float(np.max(np.abs(freq[b] / first - 1))) for b in same_size)
        how = f"their frequencies differ by up to {differ:.1e} relative, beyond the {SWEEP_RTOL:g} a repeat of one grid may stray"
    else:
        how = "of different numbers of points"
    others = ", ".join(f"{dim}={label}" for label in labels[1:3]) + (", …" if len(labels) > 3 else "")
    found = f"{where}the table holds {len(blocks)} {dim}s on different frequency grids ({_sweep_starts(dim, blocks, lines)}; {described}), {how}"
    message = (
        f"{found}; impedax will not merge them into one spectrum: read one alone with --select {dim}={labels[0]} "
        f"(or {others}; in Python impedax.io.load(path, sweep='{labels[0]}')), or export each to a file of its own"
    )
    alone = {}
    for label, b, ds in zip(labels, blocks, spectra):
        ds = ds.assign_coords({dim: label})
        ds.attrs["sweeps"] = f"{dim} {label} of {len(blocks)}, read alone (lines {lines[b[0]]}–{lines[b[-1]]}): the file's {dim}s are on different frequency grids"
        own = Skipped()  # (its DC rows and repeated headers: those among its lines)
        own.rows = [(n, why) for n, why in skipped.rows if lines[b[0]] <= n <= lines[b[-1]]]
        if len(own):
            ds.attrs["skipped_rows"] = own.report()
        alone[label] = ds
    return SweepGridsDiffer(message, path=path, line=lines[blocks[1][0]], dim=dim, spectra=alone, found=found)


def _sweep_starts(dim: str, blocks: Sequence[np.ndarray], lines: Sequence[int]) -> str:
    """Where the second and later sweeps start: 'the frequency list restarts on lines 22, 42'."""
    starts = ", ".join(str(lines[b[0]]) for b in blocks[1:])
    changes = "cycle number changes" if dim == "cycle" else "frequency list restarts"
    return f"the {changes} on line{'s' if len(blocks) > 2 else ''} {starts}"


def _spectrum(path, freq, z, lines, attrs, *, skipped: Skipped, extra: dict, sigma, where: str) -> xr.Dataset:
    """One spectrum from its columns (`finish`), with its ``sigma`` column checked."""
    ds = finish(path, freq, z, lines, attrs, skipped=skipped, extra=extra)
    if sigma is not None:
        keep = freq != 0
        sigma = sigma[keep]
        if not (np.all(np.isfinite(sigma)) and np.all(sigma > 0)):
            bad = int(np.flatnonzero(~(sigma > 0))[0])
            raise DataError(f"{where}sigma must be positive, got {sigma[bad]:g}", path=path, line=[n for n, k in zip(lines, keep) if k][bad])
        ds["sigma"] = ("frequency", sigma, {"units": "ohm", "long_name": "standard deviation of Z"})
    return ds


def read_headed_table(path: str | Path, attrs: dict, delimiter: str = "\t", *, row_end: tuple[str, str] | None = None) -> xr.Dataset:
    """A file that is one table: the first non-blank line its header (column roles by
    `detect_layout`), every further non-blank line a row. ``row_end``: (the line end the
    instrument writes after every row, the last included; its name), e.g. ``("\\r\\r\\n", "CR CR LF")``:
    a file whose every line ends so, but whose last row ends without one, was cut short, and is
    refused naming that row even when its last number shows no cut (`check_last_field_digits`
    cannot judge numbers written in their shortest form). A file an editor saved (other line
    ends) is not judged so."""
    path = Path(path)
    text = read_text(path)
    lines = text.splitlines()
    if row_end is not None and (cut := cut_last_line(text, lines)) is not None:
        end, name = row_end
        if end in text and text.count("\n") == text.count(end):
            raise DataError(f"the last row lacks the {name} that {attrs['format']} ends every row with, as the rows above it end; {CUT_SHORT}",
                            path=path, line=cut)
    k = first_line(lines, path)
    layout = detect_layout(lines[k].split(delimiter), path, k + 1)
    rows = [(j + 1, lines[j].split(delimiter)) for j in range(k + 1, len(lines)) if lines[j].strip()]
    return spectrum_from_rows(path, layout, rows, attrs, delimiter=delimiter, header_line=k + 1, cut_line=cut_last_line(text, lines))


def first_line_sniffer(is_header, expected: str):
    """A `Reader.sniff` that accepts a file whose first non-blank line passes ``is_header``;
    otherwise it answers ``first line is not <expected>``."""

    def sniff(path: Path, head: bytes) -> str | None:
        first = head_text(head).lstrip().split("\n", 1)[0]
        return None if is_header(first) else f"first line is not {expected}"

    return sniff
