"""What every reader shares: bounded file reading, numbers, units, skipped-row reports and the
final checks that turn columns into the impedax data model (`impedax.data`).

Rules every reader follows: never reorder, never broadcast, never drop a point silently. A row
that is not an impedance point (a DC row at f = 0, a repeated header, an all-empty padding
cell) is skipped *and* named in ``attrs["skipped_rows"]``; a point whose frequency or Z is
missing is an error naming its line.
"""

from __future__ import annotations

import errno
import math
import os
import re
import shlex
import stat
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np
import xarray as xr

from ..data import format_frequency, make_spectrum
from ..errors import DataError, SweepGridsDiffer
from .consistency import FLIPPED_PHASE_KEY

__all__ = [
    "UNIT_CELL", "MAX_FILE_BYTES", "MAX_FILE_BYTES_ENV", "max_file_bytes", "check_file", "read_bytes", "read_text", "decode_text", "head_text", "lf_line_ends", "number",
    "Skipped", "finish", "first_line", "stack", "merged_attrs", "unit_scale", "split_header_cell", "decimal_comma",
    "check_field_count", "check_zero_tail", "CUT_AS", "CUT_BEFORE_END", "CUT_SHORT", "cut_short_note", "cut_last_line", "column_entry", "COLUMN_ROLES", "SI_UNITS",
    "significant_digits", "check_last_field_digits", "frequency_plan_note", "PLAN_SHORT_FACTOR", "LAST_FIELD_SAMPLE", "LAST_FIELD_MIN_ROWS", "radians_beyond_turn_note",
]

#: Largest file a reader reads whole (checked before reading). Instrument exports are
#: kilobytes; a million points as impedax writes them is ~55 MB. Text in other layouts than
#: impedax's own CSV takes up to ~20 times the file's size in memory while it is read
#: (benchmarks/README.md, "Scale"), so 64 MB stays near 1 GB.
MAX_FILE_BYTES = 64 * 2**20
#: A netCDF file's limit is this many times `max_file_bytes` (256 MB by default): it is read
#: into ~1–3× its size in memory (no text to parse), and impedax writes larger ones itself (a
#: joint posterior of 960,000 draws is 88 MB, which the text files' limit would refuse to read back).
NETCDF_LIMIT_FACTOR = 4
#: Environment variable that raises (or lowers) `MAX_FILE_BYTES`: bytes, or with k/M/G: ``512M``.
MAX_FILE_BYTES_ENV = "IMPEDAX_MAX_FILE_BYTES"
_SIZE_UNITS = {"": 1, "k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}


def max_file_bytes() -> int:
    """The largest file a reader reads whole: ``IMPEDAX_MAX_FILE_BYTES`` if set, else `MAX_FILE_BYTES`."""
    text = os.environ.get(MAX_FILE_BYTES_ENV, "").strip()
    if not text:
        return MAX_FILE_BYTES
    number, unit = text.rstrip("bB"), ""
    if number and number[-1].lower() in _SIZE_UNITS:
        number, unit = number[:-1], number[-1].lower()
    try:
        value = float(number) * _SIZE_UNITS[unit]
    except ValueError:
        value = float("nan")
    if not (value >= 1 and value < 2**62):
        raise DataError(f"{MAX_FILE_BYTES_ENV}={text!r}: expected a size such as 512M, 2G or 1e9 (bytes)")
    return int(value)


def _size_text(n: int) -> str:
    return f"{n / 2**30:.3g} GB" if n >= 2**30 else f"{n / 2**20:.3g} MB" if n >= 2**20 else f"{n} bytes"

_UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")


def optional_module(name: str, path: Path, needed_for: str):
    """``import name`` for a reader that needs an optional package, after checking the file;
    without the package, `DataError` naming the file and saying how to get it (``needed_for``)."""
    import importlib

    check_file(path)
    try:
        return importlib.import_module(name)
    except ImportError:
        raise DataError(needed_for, path=path) from None


def check_file(path: Path) -> int:
    """Size of ``path`` in bytes after checking it is a regular, readable file of bounded size."""
    try:
        info = path.stat()
    except FileNotFoundError:
        if path.is_symlink():
            raise DataError(f"broken symbolic link (to {os.readlink(path)!r}, which does not exist)", path=path) from None
        raise DataError("file not found" + missing_file_hint(path), path=path) from None
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise DataError("symlink loop (the symbolic links point at each other, never at a file)", path=path) from None
        raise DataError(f"cannot read file: {exc.strerror}", path=path) from None
    if stat.S_ISDIR(info.st_mode):
        raise DataError("is a directory, not a spectrum file (its files of one spectrum each join into one series with impedax stack DIR/*.csv --out SERIES.nc, or impedax.stack_files)", path=path)
    if not stat.S_ISREG(info.st_mode):
        raise DataError("not a regular file (a device, pipe or socket); save the spectrum to a file first", path=path)
    limit = max_file_bytes()
    netcdf = info.st_size > limit and _netcdf_signed(path)
    limit *= NETCDF_LIMIT_FACTOR if netcdf else 1
    if info.st_size > limit:
        what = "netCDF files" if netcdf else "spectrum files"
        raise DataError(f"file is {_size_text(info.st_size)}; impedax reads {what} up to {_size_text(limit)} (set {MAX_FILE_BYTES_ENV}=SIZE to raise it)", path=path)
    if not os.access(path, os.R_OK):
        raise DataError("cannot read file: permission denied", path=path)
    return info.st_size


def _netcdf_signed(path: Path) -> bool:
    """Whether ``path`` starts with a netCDF signature (classic "CDF", or HDF5's for netCDF-4)."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(8)
    except OSError:
        return False
    return head.startswith(b"CDF") or head.startswith(b"\x89HDF")


#: Folders with more entries than this are not searched for a name like a missing file's.
NEAR_NAMES_MAX_ENTRIES = 10_000


def missing_file_hint(path: Path) -> str:
    """What may be wrong with the name of a file that does not exist (after "file not found"):
    a file of that name in another case or a close one in its folder (``; did you mean
    'run.Z'?``), a name that ends or starts with a space, a ``~`` Python does not expand, or a
    folder that does not exist; "" when none applies (``exampleDataZPlot.Z`` for the REAL
    ``exampleDataZPlot.z`` is told more than "file not found")."""
    import difflib

    name, folder = path.name, path.parent
    if re.match(r"(?i)(https?|ftp|s3|file):/", str(path)):  # (pathlib makes 'https://' 'https:/')
        return ("; it is a web address, and impedax reads files on this computer: download it first (curl -O URL), "
                "or pipe it in with '-' for the file (curl -s URL | impedax COMMAND -)")
    if any(c in name for c in "*?"):  # (a quoted 'data/*.csv', or one that matches nothing)
        import glob

        matches = sorted(glob.glob(str(path)))
        if matches:
            shown_matches = ", ".join(matches[:3]) + (", …" if len(matches) > 3 else "")
            return (f"; {name!r} is a pattern of file names that the shell did not expand (was it quoted?): it matches {len(matches)} "
                    f"file{'s' if len(matches) > 1 else ''} here ({shown_matches}); leave out the quotes")
        return f"; {name!r} is a pattern of file names, and no file matches it"
    if str(path).startswith("~"):
        return "; '~' is not expanded here (a shell expands it when not quoted; in Python, give pathlib.Path(path).expanduser())"
    if name != name.strip():
        return f"; the name {name!r} starts or ends with a space"
    if not folder.is_dir():
        return f"; there is no folder {str(folder)!r}" if str(folder) not in ("", ".") else ""
    try:
        with os.scandir(folder) as entries:
            names = []
            for entry in entries:
                names.append(entry.name)
                if len(names) > NEAR_NAMES_MAX_ENTRIES:
                    return ""
    except OSError:
        return ""
    same = [n for n in names if n.lower() == name.lower()]
    near = same or difflib.get_close_matches(name, names, n=3, cutoff=0.8)
    return f"; did you mean {' or '.join(repr(n) for n in near)}?" if near else ""


_NOT_TEXT = re.compile(rb"[\x00-\x08\x0e-\x1f\x7f]")
"""A byte no text export holds (a control character other than tab, line feed, vertical tab,
form feed and carriage return): a binary file's, or UTF-16 text's zero bytes."""


ZERO_RUN_MIN = 16
"""The fewest zero bytes in a row that `check_zero_tail` takes for a block never written (a
file system writes blocks of 512 bytes and more); one zero byte may be a string terminator."""


def check_zero_tail(path: Path, head: bytes) -> None:
    """One `DataError` when ``path`` (whose first bytes are ``head``) is text with zero bytes in
    it: a tail of them, as a copy or save that was interrupted leaves a file (its full size, its
    last blocks never written), or a block of them inside (a damaged block), naming the line
    where the first run of `ZERO_RUN_MIN` zero bytes starts; or zero bytes only. Judged when ``head`` holds a zero byte or
    the file ends in one; a file with other control bytes than tab and line ends (a binary
    format's signature or data) or UTF-16 text (a zero byte beside each character) is not."""
    if head.startswith(_UTF16_BOMS) or utf16_without_bom(head) is not None or _NOT_TEXT.search(head.replace(b"\x00", b"")):
        return
    try:
        with open(path, "rb") as fh:
            if b"\x00" not in head:
                fh.seek(-1, os.SEEK_END)
                if fh.read(1) != b"\x00":
                    return
            fh.seek(0)
            raw = fh.read()  # (bounded: `check_file` refused a file above the size limit)
    except OSError:
        return  # (the read that follows says why)
    cause = "as a copy or save that was interrupted (a drive removed, a crash) leaves a file: copy it again"
    body = raw.rstrip(b"\x00")
    if not body:
        raise DataError(f"the file holds only zero bytes ({len(raw)}), {cause}", path=path)
    if _NOT_TEXT.search(raw.replace(b"\x00", b"")):
        return
    first = raw.find(b"\x00" * ZERO_RUN_MIN)
    if first < 0:
        return  # (a stray zero byte, a string terminator: the readers judge it)
    line = len(raw[:first].splitlines()) + (1 if raw[:first].endswith((b"\n", b"\r")) or not first else 0)
    if first == len(body):
        raise DataError(f"the file's last {len(raw) - len(body)} bytes (from byte {len(body)} on) are zero bytes after text that stops there, {cause}",
                        path=path, line=line)
    run = len(raw[first:]) - len(raw[first:].lstrip(b"\x00"))
    raise DataError(f"{run} zero bytes (from byte {first} on) inside the text, where a file's block was damaged or never written "
                    "(an interrupted copy, a failing drive): copy it again from the instrument's computer", path=path, line=line)


def read_bytes(path: Path) -> bytes:
    """The whole file, refused before reading when it is not a regular file or is too large."""
    check_file(path)
    limit = max_file_bytes()
    try:
        with open(path, "rb") as fh:
            raw = fh.read(limit + 1)
    except OSError as exc:
        raise DataError(f"cannot read file: {exc.strerror}", path=path) from None
    if len(raw) > limit:  # grew while we looked
        raise DataError(f"file is larger than {_size_text(limit)} (set {MAX_FILE_BYTES_ENV}=SIZE to raise it)", path=path)
    return raw


def utf16_without_bom(raw: bytes) -> str | None:
    """``"utf-16-le"`` or ``"utf-16-be"`` when ``raw`` looks like UTF-16 text written without a
    byte-order mark (ASCII characters with a NUL byte beside each), else None."""
    sample = raw[:4096]
    sample = sample[: len(sample) // 2 * 2]
    if len(sample) < 4:
        return None
    even, odd = sample[0::2], sample[1::2]
    half = len(sample) // 2
    if odd.count(0) >= 0.9 * half and even.count(0) <= 0.05 * half:
        return "utf-16-le"
    if even.count(0) >= 0.9 * half and odd.count(0) <= 0.05 * half:
        return "utf-16-be"
    return None


def decode_text(raw: bytes, path: Path | None = None) -> str:
    """Text of an export: UTF-16 with a byte-order mark, UTF-8 (BOM optional) or, failing that,
    Windows' Latin-1 (µ, °, Ω as single bytes). A NUL byte in other files means binary."""
    if raw.startswith(_UTF16_BOMS):
        try:
            return raw.decode("utf-16").replace("\ufeff", "")
        except UnicodeDecodeError:
            odd = f"; its {len(raw)} bytes are an odd count, which UTF-16 text never has, {CUT_AS}" if len(raw) % 2 else ""
            raise DataError("starts with a UTF-16 byte-order mark but is not UTF-16 text" + odd, path=path) from None
    utf16 = utf16_without_bom(raw)
    if utf16 is not None:
        try:
            return raw[: len(raw) // 2 * 2].decode(utf16)
        except UnicodeDecodeError:
            raise DataError(f"looks like UTF-16 text without a byte-order mark ({utf16}) but does not decode as it; save it as UTF-8", path=path) from None
    if b"\x00" in raw[:4096]:
        raise DataError("binary file, not text", path=path)
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def read_text(path: Path) -> str:
    return decode_text(read_bytes(path), path)


def head_text(head: bytes) -> str:
    """Best-effort text of a file's first bytes for sniffing ('' for binary), every line end
    (CR LF, LF, or CR alone as classic Mac OS wrote them) as LF, so that a sniffer's
    ``split("\\n")`` and ``re.M`` see the file's lines."""
    if head.startswith(_UTF16_BOMS):
        text = head[: len(head) // 2 * 2].decode("utf-16", errors="replace").replace("\ufeff", "")
    elif (utf16 := utf16_without_bom(head)) is not None:
        text = head[: len(head) // 2 * 2].decode(utf16, errors="replace")
    elif b"\x00" in head[:4096]:
        return ""
    else:
        text = head.decode("utf-8-sig", errors="replace")
    return text.replace("\r\n", "\n").replace("\r", "\n")


def lf_line_ends(raw: bytes) -> bytes:
    """``raw`` with CR LF as LF, and in a file without any LF (classic Mac OS ends each line
    with CR alone) each CR as LF: for a reader that splits bytes at LF. A lone CR in a file with
    LFs (a binary frame's byte) is kept, so the line numbers stay the file's."""
    raw = raw.replace(b"\r\n", b"\n")
    return raw if b"\n" in raw else raw.replace(b"\r", b"\n")


def first_line(lines: Sequence[str], path: Path) -> int:
    """Index of the first non-blank line; `DataError` for a blank file."""
    k = next((i for i, ln in enumerate(lines) if ln.strip()), None)
    if k is None:
        raise DataError("file is empty", path=path)
    return k


def number(cell: str, path: Path, line: int | None, column: str, *, comma: bool = False, comma_line: int | None = None) -> float:
    """``cell`` as a finite float; an empty cell is a missing value, named as such. With
    ``comma`` (the file's decimal mark, `decimal_comma`) a cell holding a '.' is refused: in
    "1.259;108,080" the dot is a thousands separator (1259 Hz) that would be read as a decimal.
    ``comma_line``: the line of the file's first decimal comma, named in that message."""
    text = cell.strip().strip('"').strip()
    if not text:
        raise DataError(f"column {column!r} is empty (missing value)", path=path, line=line)
    if comma:
        if "." in text:  # (1.259 beside 108,080: a thousands separator, or two locales in one file; never guessed)
            raise DataError(
                f"column {column!r}: {cell.strip()!r} has a '.', and other numbers of this file a ','"
                f"{f' (the first on line {comma_line})' if comma_line is not None and comma_line != line else ''}: one of the two is a thousands "
                "separator (1,000 or 1.000 for a thousand), or the file mixes two locales; impedax does not guess which: export the "
                "numbers without thousands separators, with one decimal mark",
                path=path, line=line,
            )
        text = text.replace(",", ".")
    try:
        value = float(text)
    except ValueError:
        raise DataError(f"column {column!r}: {cell.strip()!r} is not a number", path=path, line=line) from None
    if not np.isfinite(value):
        raise DataError(f"column {column!r} is {cell.strip()!r} (NaN/Inf are not accepted)", path=path, line=line)
    return value


def decimal_comma(cells: Sequence[str], delimiter: str | None) -> bool:
    """Locale exports write ``1,5E+003`` when the field separator is not a comma."""
    if delimiter == ",":
        return False
    return any(re.fullmatch(r"\s*[-+]?\d*,\d+(?:[eE][-+]?\d+)?\s*", c) for c in cells)


#: The roles of the columns a reader records in ``attrs["columns"]`` (`column_entry`), each with
#: the quantity its values are scaled to.
COLUMN_ROLES = {"frequency": "frequency", "z_real": "resistance", "z_imag": "resistance", "z_modulus": "resistance",
                "z_phase": "angle", "sigma": "resistance"}
#: The unit impedax holds each quantity in, and assumes for a column that names none.
SI_UNITS = {"frequency": "Hz", "resistance": "ohm", "angle": "deg"}


def radians_beyond_turn_note(phase_rad, field: str, remedy: str) -> dict:
    """A ``phase_unit_note`` when ``phase_rad``, a phase read in radians because ``field`` says so
    (a ``Phase (rad)`` column, LabOne's ``phasez``), reaches beyond ±2π (a full turn), where no
    impedance phase in radians goes: they look like degrees (values down to −60). They are read as
    radians all the same (impedax does not guess); ``remedy`` says what to do if they are degrees.
    {} otherwise."""
    radians = np.asarray(phase_rad, dtype=float)
    radians = radians[np.isfinite(radians)]
    if radians.size == 0 or np.abs(radians).max() <= 2 * np.pi:
        return {}
    extreme = float(radians[np.argmax(np.abs(radians))])
    return {"phase_unit_note": f"{field} says radians, but its values reach {extreme:.3g}, beyond ±2π (a full turn), where no impedance "
                               f"phase in radians goes; read as radians: {remedy}"}


def column_entry(role: str, column: str, unit: str = "", scale: float = 1.0, *, negated: bool = False) -> dict:
    """What a reader records in ``attrs["columns"][role]`` of the column it read ``role`` from
    (a key of `COLUMN_ROLES`): ``{"column": its name in the file, "unit": the unit its values
    were read in (the SI one of `SI_UNITS` when the file names none), "scale": the factor to
    Hz, Ω or degrees, "negated": whether the file holds the negated quantity (-Z'', -phase)}``."""
    return {"column": column, "unit": unit or SI_UNITS[COLUMN_ROLES[role]], "scale": float(scale), "negated": bool(negated)}


CUT_AS = "as a file cut short does (copied before it was complete?): copy it again"
"""How a refusal names a cut as the likely cause, after the sign of it it found."""

CUT_BEFORE_END = f"the file ends without a line end, {CUT_AS}"
"""What a refusal of a part the file lacks (a table, the end of a header, the points a header
announces) adds when the file ends without a line end (`cut_short_note`)."""

CUT_SHORT = f"{CUT_BEFORE_END}, or delete the line"
"""What a refusal of a last row adds when the file ends without a line end."""


def cut_short_note(content: str | bytes) -> str:
    """``"; "`` and `CUT_BEFORE_END` when a file's ``content`` ends without a line end, as a file
    cut short while copied does; ``""`` otherwise. A reader that finds a part missing (no table,
    fewer points than its header announces) adds it to its refusal: the cut is the likely cause."""
    return f"; {CUT_BEFORE_END}" if content and content[-1:] not in ("\n", "\r", b"\n", b"\r") else ""


def cut_last_line(text: str, lines: Sequence[str]) -> int | None:
    """The line number (1-based) of the last of ``lines`` (``text.splitlines()``) when ``text``
    ends without a line end, as a file cut short while copied does; None when it ends with one."""
    return len(lines) if lines and text and not text.endswith(("\n", "\r")) else None


def check_field_count(cells: Sequence[str], n_fields: int, path: Path, line: int | None, *, where: str = "", last_of_cut_file: bool = False,
                      hint: str = "", expected: str = "") -> None:
    """A table row must have as many fields as its header ("Rules every reader follows": a
    missing or extra cell would shift values onto other columns, and a row cut short would be
    read as other numbers); `DataError` naming the line otherwise, saying the file looks cut
    short when ``last_of_cut_file`` (its last row, with no line end after it), then ``hint``
    (the reader's word on the cause, e.g. `table.delimiter_hint`). ``expected``: what sets the
    count, when not a header (`table.Layout.field_count_text`); default ``the header has N``."""
    if len(cells) != n_fields:
        cause = f"; {CUT_SHORT}" if last_of_cut_file and len(cells) < n_fields else ""
        cause += f"; {hint}" if hint else ""
        fields = "1 field" if len(cells) == 1 else f"{len(cells)} fields"
        expected = expected or f"the header has {n_fields}"
        raise DataError(f"{where}{fields}, but {expected} (a missing or extra cell would shift values){cause}", path=path, line=line)


_NUMBER_DIGITS = re.compile(r"[-+]?(\d*)(?:[.,](\d*))?(?:[eE][-+]?(\d*))?")


def significant_digits(cell: str) -> int | None:
    """The digits of a number cell from its first non-zero digit on, those of the exponent
    included (``-8.440604`` → 7, ``0.00120`` → 3, ``1.5E+03`` → 4); a zero's are all it is
    written with (``0.0000000E+00`` → 10, ``0`` → 1: the precision of its format); None for a
    cell that is no number. A number cut short anywhere after its first non-zero digit has fewer."""
    m = _NUMBER_DIGITS.fullmatch(cell.strip().strip('"').strip())
    if m is None or not (m.group(1) or m.group(2)):
        return None
    mantissa = (m.group(1) or "") + (m.group(2) or "")
    return len(mantissa.lstrip("0") or mantissa) + len(m.group(3) or "")


#: Rows above the last that `check_last_field_digits` compares with (a long file's nearest, to
#: keep reading it fast), and how many it needs: with fewer, one value written short (0.5 in a
#: column of 0.5123) is as likely as a cut.
LAST_FIELD_SAMPLE = 1000
LAST_FIELD_MIN_ROWS = 3


def check_last_field_digits(column: Sequence[str], path: Path, line: int | None, *, name: str = "") -> None:
    """``column``: the last field of every data row, in file order, of a file that ends without
    a line end (`cut_last_line`). A row cut inside its last field keeps its field count, so
    `check_field_count` passes it; it is refused here, naming ``line``, when that field has
    fewer `significant_digits` than the column has on every other row (the least of up to
    `LAST_FIELD_SAMPLE` rows above it, at least `LAST_FIELD_MIN_ROWS`): ``-8.44`` under rows
    of ``-8.440604``. A column holding any cell that is no number is not judged. A last field
    that is empty where every other row has one (the cut fell just after a delimiter) is refused
    the same way; a column with gaps on other rows (notes) is not judged."""
    if len(column) <= LAST_FIELD_MIN_ROWS:
        return
    what = f"column {name!r}: " if name else ""
    if not column[-1].strip():
        if all(cell.strip() for cell in column[-1 - LAST_FIELD_SAMPLE:-1]):
            raise DataError(f"{what}empty on the last row, where every other row has a value; {CUT_SHORT}", path=path, line=line)
        return
    last = significant_digits(column[-1])
    others = [significant_digits(cell) for cell in column[-1 - LAST_FIELD_SAMPLE:-1]]
    if last is None or None in others:
        return
    fewest = min(others)
    if last < fewest:
        raise DataError(
            f"{what}{column[-1].strip()!r} on the last row has {last} significant digits, every other row at least {fewest}; {CUT_SHORT}",
            path=path, line=line,
        )


class Skipped:
    """Rows a reader skipped, with the reason; reported as consecutive ranges."""

    def __init__(self) -> None:
        self.rows: list[tuple[int, str]] = []

    def add(self, line: int, reason: str) -> None:
        self.rows.append((line, reason))

    def __len__(self) -> int:
        return len(self.rows)

    def report(self) -> list[str]:
        """``["lines 2–389: f = 0 (DC row)", "line 400: repeated header"]``."""
        out: list[str] = []
        start = prev = None
        reason = None
        for line, why in self.rows + [(None, None)]:
            if reason is not None and (why != reason or line != prev + 1):
                out.append(f"line {start}: {reason}" if start == prev else f"lines {start}–{prev}: {reason}")
                start = None
            if line is None:
                break
            if start is None:
                start, reason = line, why
            prev, reason = line, why
        return out


def finish(
    path: Path,
    freq,
    z,
    lines: Sequence[int],
    attrs: dict,
    *,
    skipped: Skipped | None = None,
    extra: dict | None = None,
) -> xr.Dataset:
    """One spectrum from columns read on ``lines``: DC rows (f = 0) are skipped and reported;
    negative or repeated frequencies are errors naming the line."""
    freq = np.asarray(freq, dtype=np.float64)
    z = np.asarray(z, dtype=np.complex128)
    skipped = skipped if skipped is not None else Skipped()
    keep = freq != 0
    if not keep.all():
        for i in np.flatnonzero(~keep):
            skipped.add(int(lines[i]), "f = 0 (DC row, not an impedance point)")
        skipped.rows.sort()
        freq, z = freq[keep], z[keep]
        lines = [n for n, k in zip(lines, keep) if k]
        extra = {k: (v[keep], u, d) for k, (v, u, d) in (extra or {}).items()}
    if freq.size == 0:
        raise DataError("the impedance table has no data rows" + (f" (skipped: {'; '.join(skipped.report())})" if len(skipped) else ""), path=path)
    # checked on arrays (a million points make no Python object each); the first offender in
    # file order is the one named
    bad = np.flatnonzero(~(freq > 0))
    if bad.size:
        raise DataError(f"frequency must be positive, got {freq[bad[0]]:g}", path=path, line=lines[bad[0]])
    order = np.argsort(freq, kind="stable")
    repeats = np.flatnonzero(freq[order][1:] == freq[order][:-1])
    if repeats.size:
        second = int(order[repeats + 1].min())
        first = int(np.flatnonzero(freq == freq[second])[0])
        raise DataError(f"duplicate frequency {freq[second]:g} Hz (also on line {lines[first]}){_duplicate_remedy(freq, lines, second)}", path=path, line=lines[second])
    attrs = {"path": str(path), **{k: v for k, v in attrs.items() if v not in (None, "")}}
    if len(skipped):
        attrs["skipped_rows"] = skipped.report()
    ds = make_spectrum(freq, z, attrs=attrs, source=str(path))
    for name, (values, units, long_name) in (extra or {}).items():
        ds[name] = ("frequency", np.asarray(values, dtype=np.float64), {"units": units, "long_name": long_name})
    return ds


#: How far (relative) the frequencies of a repeated sweep may stray from the first sweep's: an
#: instrument's measured frequencies vary in their last digits from sweep to sweep.
SWEEP_RTOL = 1e-3


def _duplicate_remedy(freq: np.ndarray, lines: Sequence[int], second: int) -> str:
    """What to do about a repeated frequency first met at ``freq[second]``: when the list turns
    there (each part monotonic, the part from ``second`` on the earlier part's frequencies,
    within `SWEEP_RTOL`, 3 points or more), a second sweep starts there; otherwise a point was
    measured twice."""
    head, tail = freq[:second], freq[second:]

    def monotonic(f: np.ndarray) -> bool:
        steps = np.diff(f)
        return bool(np.all(steps > 0) or np.all(steps < 0))

    grid = np.sort(head)
    near = np.clip(np.searchsorted(grid, tail), 1, grid.size - 1) if grid.size > 1 else np.zeros(tail.size, int)
    on_grid = np.minimum(np.abs(tail / grid[near] - 1), np.abs(tail / grid[near - 1] - 1)) <= SWEEP_RTOL if grid.size > 1 else tail == grid[0]
    if tail.size >= 3 and head.size >= 3 and monotonic(head) and monotonic(tail) and np.all(on_grid):
        return (
            f": a second sweep starts on line {lines[second]} (the frequencies turn back: {head[0]:g} → {head[-1]:g} Hz, then {tail[0]:g} → "
            f"{tail[-1]:g} Hz, on the same frequencies); impedax holds one frequency grid per spectrum, in the file's order: save each sweep "
            f"to a file of its own (lines {lines[0]}–{lines[second - 1]} and {lines[second]}–{lines[-1]}), or write the second in the first "
            "one's order, so that the sweeps read as a sweep dimension (--select sweep=0 picks one; docs/io.md, 'Several sweeps in one table')"
        )
    return ": a point measured twice? delete one of the two lines, or average them into one point"


def stack(path: Path, spectra: Sequence[tuple[str, xr.Dataset]], dim: str) -> xr.Dataset:
    """Several spectra of one file on one frequency grid as a ``dim`` dimension, ahead of the
    dimensions each already has (a sheet's sweeps); different grids or shapes are an error
    (impedax holds one grid per Dataset)."""
    if len(spectra) == 1:
        return spectra[0][1]
    label0, first = spectra[0]
    f0 = first["frequency"].values
    inner = tuple(d for d in first["Z"].dims if d != "frequency")
    if _numbering_carries_on(spectra, inner):
        return _continued(path, spectra, dim, inner[0] if inner else _NUMBERED[0])
    for label, ds in spectra[1:]:
        f = ds["frequency"].values
        if f.shape != f0.shape or not np.array_equal(f, f0):
            raise _grids_differ(path, spectra, dim, f"{dim} {label!r} ({f.size} points) has a different frequency grid from {dim} {label0!r} ({f0.size} points)")
        same_labels = all((d in ds.coords) == (d in first.coords) and (d not in first.coords or np.array_equal(ds[d].values, first[d].values)) for d in inner)
        if tuple(d for d in ds["Z"].dims if d != "frequency") != inner or any(ds.sizes[d] != first.sizes[d] for d in inner) or not same_labels:
            raise DataError(
                f"{dim} {label!r} holds {_spectra_text(ds)} where {dim} {label0!r} holds {_spectra_text(first)}; "
                f"impedax stacks {dim}s that hold the same spectra: export the {dim}s to separate files",
                path=path,
            )
    coords = {dim: [label for label, _ in spectra], **{d: first[d].values for d in inner if d in first.coords}}
    return make_spectrum(
        f0, np.stack([ds["Z"].transpose(*inner, "frequency").values for _, ds in spectra]), dims=(dim, *inner), coords=coords,
        attrs=merged_attrs([(label, ds.attrs) for label, ds in spectra], dim), source=str(path),
    )


def _grids_differ(path: Path, spectra: Sequence[tuple[str, xr.Dataset]], dim: str, found: str) -> SweepGridsDiffer:
    """The error for a file's spectra (sheets, curves, measurements) on different frequency
    grids, which impedax will not stack: ``found`` (which two differ) and how to read one alone;
    it carries each as a spectrum of its own (`SweepGridsDiffer`), so that ``--select DIM=LABEL``
    and ``impedax.io.load(path, sweep=LABEL)`` read it."""
    labels = [str(label) for label, _ in spectra]
    message = f"{found}: read one alone, --select {shlex.quote(f'{dim}={labels[0]}')} (Python: impedax.io.load(path, sweep={labels[0]!r})), or export each to a file"
    alone = {}
    for label, ds in zip(labels, (ds for _, ds in spectra)):
        ds = ds.assign_coords({dim: label})
        ds.attrs = {**ds.attrs, "sweeps": f"{dim} {label} of {len(labels)}, read alone: the file's {dim}s are on different frequency grids"}
        alone[label] = ds
    return SweepGridsDiffer(message, path=path, line=None, dim=dim, spectra=alone, found=found)


#: Attributes whose value is a name, not prose (`consistency.FLIPPED_PHASE_KEY`: a column's):
#: `merged_attrs` keeps one only when every spectrum has the same, since a labelled join
#: ("sheet 1: Phase") names no column; the labelled note beside it says which spectra.
NAME_ATTRS = frozenset({FLIPPED_PHASE_KEY})


def merged_attrs(parts: Sequence[tuple[str, Mapping]], dim: str) -> dict:
    """The attributes ``parts`` (label, attrs) of spectra read from one file: those they share,
    each one's own text labelled with its ``dim`` (a sheet's sign convention, a note; a
    `NAME_ATTRS` one only when they share it), every skipped row's report."""
    attrs = {}
    keys = list(dict.fromkeys(key for _, own in parts for key in own))  # every spectrum's, in order
    for key in keys:
        values = [own.get(key) for _, own in parts]
        if all(v == values[0] for v in values):
            attrs[key] = values[0]
        elif key in NAME_ATTRS:
            continue
        elif all(isinstance(v, str) or v is None for v in values):
            attrs[key] = "; ".join(f"{dim} {label}: {v}" for (label, _), v in zip(parts, values) if v is not None)
    reports = [f"{dim} {label}: {r}" for label, own in parts for r in own.get("skipped_rows", [])]
    attrs.pop("skipped_rows", None)
    attrs.pop("source", None)  # (the file: each part's "FILE [sheet S]" joined would name it once per part in every message)
    if reports:
        attrs["skipped_rows"] = reports
    return attrs


#: Inner dimensions whose labels number the spectra across a file (EC-Lab's ``cycle number``):
#: sheets that carry the numbering on (1, 2 / 3, 4) hold parts of one series.
_NUMBERED = ("cycle",)


def _numbered_cycles(ds: xr.Dataset, numbered: str) -> list[str] | None:
    """The cycle numbers a spectrum holds: its ``numbered`` labels, or the one its attrs name
    (a table of one numbered cycle); None when it numbers none."""
    inner = tuple(d for d in ds["Z"].dims if d != "frequency")
    if inner == (numbered,) and numbered in ds.coords:
        return [str(v) for v in ds[numbered].values]
    if not inner and numbered in ds.attrs:
        return [str(ds.attrs[numbered])]
    return None


def _numbering_carries_on(spectra: Sequence[tuple[str, xr.Dataset]], inner: tuple[str, ...]) -> bool:
    """Every spectrum numbers its cycles (`_NUMBERED`; one cycle or several), on one frequency
    grid, each one's numbers above the last of the one before: parts of one series."""
    numbered = inner[0] if len(inner) == 1 else _NUMBERED[0] if not inner else None
    if numbered not in _NUMBERED:
        return False
    f0 = spectra[0][1]["frequency"].values
    last = -math.inf
    for _, ds in spectra:
        labels = _numbered_cycles(ds, numbered)
        if labels is None or not np.array_equal(ds["frequency"].values, f0):
            return False
        try:
            numbers = [float(v) for v in labels]
        except ValueError:
            return False
        if numbers[0] <= last:
            return False
        last = numbers[-1]
    return len(spectra) > 1


def _continued(path: Path, spectra: Sequence[tuple[str, xr.Dataset]], dim: str, numbered: str) -> xr.Dataset:
    """Spectra whose ``numbered`` labels carry on from one to the next, as one ``numbered``
    dimension in the order read, with a ``dim`` coordinate naming where each came from."""
    labels = [_numbered_cycles(ds, numbered) for _, ds in spectra]
    sources = [label for (label, _), mine in zip(spectra, labels) for _ in mine]
    z = [ds["Z"].transpose(numbered, "frequency").values if numbered in ds.dims else ds["Z"].values[None] for _, ds in spectra]
    attrs = merged_attrs([(label, {k: v for k, v in ds.attrs.items() if k not in ("sweeps", dim, numbered)}) for label, ds in spectra], dim)
    attrs[f"{dim}s"] = f"{numbered}s " + ", ".join(f"{mine[0]}–{mine[-1]} from {dim} {label}" if len(mine) > 1 else f"{mine[0]} from {dim} {label}" for (label, _), mine in zip(spectra, labels))
    ds = make_spectrum(
        spectra[0][1]["frequency"].values, np.concatenate(z), dims=(numbered,), coords={numbered: [v for mine in labels for v in mine]}, attrs=attrs, source=str(path),
    )
    return ds.assign_coords({dim: (numbered, sources)})


def _spectra_text(ds: xr.Dataset) -> str:
    """'one spectrum', or the sizes of its dimensions besides frequency ('3 sweeps')."""
    inner = [d for d in ds["Z"].dims if d != "frequency"]
    if not inner:
        return "one spectrum"
    labels = (f"{ds.sizes[d]} {d}s" + (f" ({', '.join(str(v) for v in ds[d].values)})" if d in ds.coords else "") for d in inner)
    return " × ".join(labels)


# --- units ----------------------------------------------------------------------------------

# Prefixes are case-sensitive: m = milli, M = mega (a 'Frequency (mHz)' column is 1e-3 Hz).
_PREFIX = {"": 1.0, "m": 1e-3, "µ": 1e-6, "μ": 1e-6, "u": 1e-6, "k": 1e3, "K": 1e3, "M": 1e6, "G": 1e9}
_BASES = {
    "frequency": ("Hz", "hz", "HZ"),
    "resistance": ("Ω", "Ohm", "ohm", "Ohms", "ohms", "OHM", "OHMS"),
}
_ANGLE = {"deg": 1.0, "°": 1.0, "degree": 1.0, "degrees": 1.0, "Deg": 1.0, "rad": 180 / np.pi}


def unit_scale(unit: str, quantity: str) -> float | None:
    """Factor turning values in ``unit`` into Hz, Ω or degrees (``quantity`` is 'frequency',
    'resistance' or 'angle'); ``None`` when ``unit`` is not such a unit. Raises `DataError`
    for an all-capitals unit with an M prefix ('MHZ': milli or mega?)."""
    unit = unit.strip()
    if quantity == "angle":
        return _ANGLE.get(unit)
    for base in sorted(_BASES[quantity], key=len, reverse=True):
        if unit.endswith(base):
            prefix = unit[: -len(base)]
            if prefix == "M" and base in ("HZ", "OHM", "OHMS"):
                raise DataError(f"unit {unit!r} is ambiguous (mHz or MHz? mΩ or MΩ?); write the prefix in its SI case")
            return _PREFIX.get(prefix)
    return None


UNIT_CELL = re.compile(r"^(?P<name>.*?\S)\s*(?:[\(\[]\s*(?P<u1>[^()\[\]]*?)\s*[\)\]]|/\s*(?P<u2>[^/()]+?))\s*$")
_ANY_UNIT = ("frequency", "resistance", "angle")


def unquoted(cell: str) -> str:
    """``cell`` stripped, without the double quotes around it when it is quoted (``'"Z' (Ω)"'``);
    a quote that is part of the name stays (``'Z"'``, a double prime: Z'')."""
    text = cell.strip()
    return text[1:-1].strip() if len(text) >= 2 and text[0] == text[-1] == '"' else text


def split_header_cell(cell: str) -> tuple[str, str]:
    """``'Frequency (kHz)'`` → ``('Frequency', 'kHz')``; ``'Re(Z)/Ohm'`` → ``('Re(Z)', 'Ohm')``;
    ``'Re(Z)'`` → ``('Re(Z)', '')`` (a bracket that holds no unit is part of the name)."""
    text = unquoted(cell)
    m = UNIT_CELL.match(text)
    if m:
        unit = (m.group("u1") if m.group("u1") is not None else m.group("u2")) or ""
        if any(_safe_scale(unit, q) is not None for q in _ANY_UNIT) or unit.lower() in ("s", "sec"):
            return m.group("name").strip(), unit.strip()
    return text, ""


def _safe_scale(unit: str, quantity: str):
    try:
        return unit_scale(unit, quantity)
    except DataError:
        return 1.0  # recognisably a unit, if an ambiguous one: the caller reports it


#: How far (a factor) the points may stop inside the planned band before the file is told short of it.
PLAN_SHORT_FACTOR = 1.5


def frequency_plan_note(freq, initial, final) -> str | None:
    """An instrument's ``frequency_plan_note``: ``the settings plan a sweep from 2 MHz to 100 mHz;
    the file's points span 99.6 kHz–100 mHz (none above 99.6 kHz)`` when the points ``freq`` [Hz]
    stop short of the band the settings plan (``initial`` to ``final`` [Hz], numbers) at its top
    or bottom by more than `PLAN_SHORT_FACTOR` (a sweep stopped early, an export cut); None
    otherwise, or without a plan."""
    if not isinstance(initial, float) or not isinstance(final, float) or min(initial, final) <= 0:
        return None
    low, high = float(freq.min()), float(freq.max())
    short = [f"none above {format_frequency(high)}" if high * PLAN_SHORT_FACTOR < max(initial, final) else "",
             f"none below {format_frequency(low)}" if low > PLAN_SHORT_FACTOR * min(initial, final) else ""]
    if not any(short):
        return None
    span = (high, low) if initial > final else (low, high)
    return (f"the settings plan a sweep from {format_frequency(initial)} to {format_frequency(final)}; the file's points span "
            f"{format_frequency(span[0])}–{format_frequency(span[1])} ({'; '.join(s for s in short if s)})")

