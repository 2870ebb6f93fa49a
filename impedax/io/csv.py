"""Delimited text spectra (CSV, TSV, semicolon or whitespace separated).

Canonical header: ``frequency_hz,z_real_ohm,z_imag_ohm`` with Z = Z' + jZ'' (Z'' < 0 for
capacitive data). Common variants are recognised (``freq``, ``Zreal``, ``Zimag``, ``Z'``,
``-Z''`` or ``-Zimag`` with the sign handled, ``|Z|`` with ``phase`` in degrees, units in
brackets such as ``Frequency (kHz)``). Optional ``sigma_ohm`` column.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import xarray as xr

from .atomic import atomic_path
from ..data import make_spectrum
from ..errors import DataError

__all__ = ["read_csv", "write_csv", "CSV_HEADER"]


class UnrecognisedText(DataError):
    """The file is not delimited text with a spectrum header (so `load` lists the other formats)."""

    def __init__(self, message: str, *, path=None, line=None):
        self.reason = message
        super().__init__(message, path=path, line=line)

CSV_HEADER = ("frequency_hz", "z_real_ohm", "z_imag_ohm")

_ROLES = {
    "frequency": {"frequency", "freq", "f", "frequencyhz", "freqhz", "frequency_hz", "freq_hz", "fhz"},
    "real": {"z_real", "zreal", "z_re", "zre", "re_z", "rez", "re(z)", "z'", "real", "zr", "z_real_ohm", "realz", "zreal_ohm"},
    "imag": {"z_imag", "zimag", "z_im", "zim", "im_z", "imz", "im(z)", "z''", 'z"', "imag", "zi", "z_imag_ohm", "imagz", "zimag_ohm"},
    "neg_imag": {"-z_imag", "-zimag", "-z_im", "-zim", "-im_z", "-imz", "-im(z)", "-z''", '-z"', "-imag", "neg_z_imag", "minus_z_imag", "-z_imag_ohm", "-zimag_ohm"},
    "modulus": {"|z|", "zmod", "z_mod", "mod(z)", "modz", "magnitude", "z_mod_ohm", "abs(z)", "absz", "z_abs"},
    "phase": {"phase", "phase_deg", "z_phase", "zphase", "phase(z)", "z_phase_deg", "phi", "phasedeg", "theta"},
    "sigma": {"sigma", "sigma_ohm", "sigma_z", "sigma_z_ohm", "std", "sem"},
}
_SCALE = {"hz": 1.0, "khz": 1e3, "mhz": 1e6, "ohm": 1.0, "ω": 1.0, "kohm": 1e3, "kω": 1e3, "deg": 1.0, "°": 1.0, "": 1.0}


def _normalise(header_cell: str) -> tuple[str, float, str]:
    """'Frequency (kHz)' → ('frequency', 1e3, 'khz')."""
    cell = header_cell.strip().strip('"').strip()
    unit = ""
    m = re.match(r"^(.*?)\s*[\(\[/]\s*([^\)\]]*)\s*[\)\]]?\s*$", cell)
    if m and m.group(1) and not cell.lower().endswith(("(z)", "(z|")) and m.group(2).lower() in _SCALE:
        cell, unit = m.group(1), m.group(2).lower()
    key = re.sub(r"\s+", "", cell.lower()).replace("’", "'").replace("″", "''")
    return key, _SCALE.get(unit, 1.0), unit


def _split(line: str, delimiter: str | None) -> list[str]:
    return [c.strip() for c in (line.split(delimiter) if delimiter else line.split())]


def read_csv(path: str | Path) -> xr.Dataset:
    """Read one spectrum from delimited text. Errors name the file and line."""
    path = Path(path)
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise DataError("file not found", path=path) from None
    except OSError as exc:
        raise DataError(f"cannot read file: {exc.strerror}", path=path) from None
    if b"\x00" in raw[:4096]:
        raise UnrecognisedText("binary file, not delimited text", path=path)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    lines = [(i + 1, ln) for i, ln in enumerate(text.splitlines()) if ln.strip() and not ln.lstrip().startswith(("#", "%", "!"))]
    if not lines:
        raise UnrecognisedText("file is empty (no header, no data)", path=path)
    header_no, header = lines[0]
    delimiter = next((d for d in (",", "\t", ";") if d in header), None)
    cells = _split(header, delimiter)
    roles: dict[str, tuple[int, float]] = {}
    unknown = []
    for col, cell in enumerate(cells):
        key, scale, _unit = _normalise(cell)
        role = next((r for r, names in _ROLES.items() if key in names), None)
        if role is None:
            unknown.append(cell)
        elif role in roles:
            raise DataError(f"two columns for {role}: {cells[roles[role][0]]!r} and {cell!r}", path=path, line=header_no)
        else:
            roles[role] = (col, scale)
    if "frequency" not in roles:
        _no_header_check(cells, path, header_no)
        raise UnrecognisedText(f"no frequency column in header {cells}; expected e.g. {','.join(CSV_HEADER)}", path=path, line=header_no)
    has_cartesian = "real" in roles and ("imag" in roles or "neg_imag" in roles)
    has_polar = "modulus" in roles and "phase" in roles
    if "imag" in roles and "neg_imag" in roles:
        raise DataError("both Z'' and -Z'' columns given; keep one", path=path, line=header_no)
    if not (has_cartesian or has_polar):
        raise UnrecognisedText(
            f"cannot find impedance columns in header {cells}; expected z_real_ohm and z_imag_ohm "
            "(or -z_imag_ohm, or |Z| and phase in degrees)",
            path=path,
            line=header_no,
        )
    rows = []
    for line_no, line in lines[1:]:
        values = _split(line, delimiter)
        if len(values) != len(cells):
            raise DataError(f"{len(values)} fields, but the header has {len(cells)}", path=path, line=line_no)
        row = []
        for col, cell in enumerate(values):
            try:
                row.append(float(cell))
            except ValueError:
                if col in {c for c, _ in roles.values()}:
                    raise DataError(f"column {cells[col]!r}: {cell!r} is not a number", path=path, line=line_no) from None
                row.append(np.nan)
        for role, (col, _) in roles.items():
            if not np.isfinite(row[col]):
                raise DataError(f"column {cells[col]!r} is {values[col]!r} (NaN/Inf are not accepted)", path=path, line=line_no)
        rows.append((line_no, row))
    if not rows:
        raise DataError("header but no data rows", path=path, line=header_no)
    data = np.array([r for _, r in rows])
    line_numbers = [n for n, _ in rows]

    def col(role):
        c, scale = roles[role]
        return data[:, c] * scale

    freq = col("frequency")
    for i, f in enumerate(freq):
        if f <= 0:
            raise DataError(f"frequency must be positive, got {f:g}", path=path, line=line_numbers[i])
    seen: dict[float, int] = {}
    for i, f in enumerate(freq):
        if f in seen:
            raise DataError(f"duplicate frequency {f:g} Hz (also on line {seen[f]})", path=path, line=line_numbers[i])
        seen[f] = line_numbers[i]
    if has_cartesian:
        imag = col("imag") if "imag" in roles else -col("neg_imag")
        z = col("real") + 1j * imag
    else:
        z = col("modulus") * np.exp(1j * np.deg2rad(col("phase")))
    sigma = col("sigma") if "sigma" in roles else None
    attrs = {"format": "delimited text", "path": str(path)}
    if "neg_imag" in roles:
        attrs["sign_note"] = "file stores -Z''; converted to Z''"
    if unknown:
        attrs["ignored_columns"] = ", ".join(unknown)
        warnings.warn(f"{path}: ignored columns {unknown}", stacklevel=2)
    return make_spectrum(freq, z, sigma=sigma, attrs=attrs, source=str(path))


def _no_header_check(cells, path, line_no):
    try:
        [float(c) for c in cells]
    except ValueError:
        return
    raise UnrecognisedText(f"the first line is numbers, not a header; start the file with {','.join(CSV_HEADER)}", path=path, line=line_no)


def write_csv(ds: xr.Dataset, path: str | Path | None = None) -> str:
    """Write one spectrum as ``frequency_hz,z_real_ohm,z_imag_ohm`` (17 significant digits).

    Returns the text; writes it atomically to ``path`` when given.
    """
    z = ds["Z"]
    if z.ndim != 1:
        raise DataError(f"CSV holds one spectrum; this one has dimensions {z.dims} (save it as .nc)", path=path)
    f = ds["frequency"].values
    zv = z.values
    header = list(CSV_HEADER)
    columns = [f, zv.real, zv.imag]
    if "sigma" in ds:
        header.append("sigma_ohm")
        columns.append(ds["sigma"].values)
    lines = [",".join(header)]
    for row in zip(*columns):
        lines.append(",".join(f"{v:.17g}" for v in row))
    text = "\n".join(lines) + "\n"
    if path is not None:
        with atomic_path(path) as tmp:
            tmp.write_text(text)
    return text
