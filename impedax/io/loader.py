"""`load` and `save`: a spectrum file in, the impedax data model out (and back).

A file is recognised by its content: each reader's ``sniff`` looks at the first 64 kB (and the
name) and the first that claims the file reads it; plain delimited text is the fallback. A file
no reader claims raises one `DataError`: first why it is not delimited text (the column names
it found), then how many other formats were tried (`identify` gives each one's reason). Files that are not regular
files (``/dev/zero``, pipes) or are larger than `MAX_FILE_BYTES` are refused before anything is
read.
"""

from __future__ import annotations

import inspect
import os
import re
import traceback
from pathlib import Path
from typing import Mapping, Sequence

import xarray as xr

from ..arguments import checked_arguments, shown
from ..data import CHECKED_FILE, validate_spectrum
from ..errors import IN_MEMORY, DataError, ParameterError, SweepGridsDiffer
from .atomic import check_file_name
from ._common import MAX_FILE_BYTES, check_file, check_zero_tail, head_text
from .csv import read_csv, write_csv
from .export import written_result
from .netcdf import NETCDF_FORMAT, not_a_spectrum, write_netcdf
from .provenance import STDIN_NAME as PROVENANCE_STDIN_NAME
from .registry import Reader
from .table import NoLayout

__all__ = ["load", "save", "identify", "MAX_FILE_BYTES", "SPECTRUM_SUFFIXES", "STDIN"]

SNIFF_BYTES = 65536

#: What `save` writes, by extension: netCDF (lossless) or canonical CSV ("" is CSV).
NETCDF_SUFFIXES = (".nc", ".nc4", ".cdf")
CSV_SUFFIXES = (".csv", ".txt", ".tsv", "")
SPECTRUM_SUFFIXES = NETCDF_SUFFIXES + CSV_SUFFIXES

#: The path that means standard input (``impedax fit - --model ...``); named so in messages.
STDIN = "-"
STDIN_NAME = PROVENANCE_STDIN_NAME  # ("<stdin>": the provenance's data_files name it so too)


def _head(path: Path) -> bytes:
    check_file(path)
    try:
        with open(path, "rb") as fh:
            return fh.read(SNIFF_BYTES)
    except OSError as exc:
        raise DataError(f"cannot read file: {exc.strerror}", path=path) from None


def _raised_at(function, exc: BaseException, origin: str = "") -> tuple[str, str]:
    """Where a reader's ``function`` raised ``exc``: ("" or `` of --plugin lab.py``, the reader's
    ``origin``, `Reader.origin`), then `` (FILE, line N)``, the innermost frame in the function's
    own file, FILE left out when it is the one ``origin`` names; "" when unknown. A user's read or
    sniff is so named by its file and line, a plugin's by the plugin too, here rather than by a
    wrapper on the command line (which would find no line outside the plugin file)."""
    code = getattr(inspect.unwrap(function), "__code__", None)  # (a --plugin sniff is wrapped to print to stderr)
    lines = [frame.lineno for frame in traceback.extract_tb(exc.__traceback__) if code is not None and frame.filename == code.co_filename]
    of = f" of {origin}" if origin else ""
    if not lines:
        return of, ""
    named = {os.path.realpath(text) for text in (origin, origin.partition(" ")[2]) if text}
    own = os.path.realpath(code.co_filename) in named
    return of, f" ({'' if own else code.co_filename + ', '}line {lines[-1]})"


def _named(reader: Reader) -> str:
    """``reader 'LAB'``, with where it was declared when known (`Reader.origin`): ``reader 'LAB' of
    --plugin lab.py``, as the messages of its read and sniff name it."""
    return f"reader {reader.name!r}" + (f" of {reader.origin}" if reader.origin else "")


def identify(path: str | os.PathLike, readers: Sequence[Reader] | None = None) -> tuple[Reader | None, list[str]]:
    """The reader that claims ``path`` (``None`` for plain text) and the reasons of those that did
    not; a path that is no str or os.PathLike is one `DataError`, as `load`'s.
    ``-``, `load`'s standard input, is one `DataError` saying so (not "-: file not found")."""
    _check_path(path)
    if str(path) == STDIN:
        raise DataError("identify looks at a file, and '-' is standard input, which only impedax.load reads (once): its attrs['format'] "
                        "names the reader that read it (attrs['stdin_note'] when none of your own readers claimed it); "
                        "to identify piped data, save them to a file first", path=STDIN_NAME)
    reader, tried, _faults = _identify(path, readers)
    return reader, tried


def _identify(path: str | os.PathLike, readers: Sequence[Reader] | None) -> tuple[Reader | None, list[str], list[str]]:
    """`identify`, and what the sniffs that broke their contract did (raised, or returned
    neither None, a reason text nor a bool): named first when no reader claims the file."""
    readers = _checked_readers(readers)
    path = Path(path)
    head = _head(path)
    check_zero_tail(path, head)  # (before any reader: text cut by zeros reads as fewer points, or as 'binary')
    tried, faults = [], []
    for reader in readers:
        try:
            answer = reader.sniff(path, head)
        except Exception as exc:  # a user's sniff must not hide the other formats
            reason = f"sniff failed ({type(exc).__name__})"
            detail = (str(exc).strip().splitlines() or [""])[0][:200]
            of, at = _raised_at(reader.sniff, exc, reader.origin)
            faults.append(f"reader {reader.name!r}{of}: its sniff{at} raised {type(exc).__name__}{': ' + detail if detail else ''}")
        else:
            if answer is None or answer is True:
                return reader, tried, faults
            if answer is False:
                reason = "sniff returned False"
            elif isinstance(answer, str):
                reason = answer
            else:
                reason = f"sniff returned {type(answer).__name__}"
                faults.append(f"{_named(reader)}: its sniff returned {type(answer).__name__} {shown(answer)}")
        tried.append(f"{reader.name}: {reason}")
    return None, tried, faults


def _checked_readers(readers) -> Sequence[Reader]:
    """``readers`` as `load` and `identify` take them (None: `impedax.io.READERS`), else one
    `ParameterError` saying what was given (a single Reader, a function, text: not a TypeError
    or AttributeError from inside the loop that tries them)."""
    if readers is None:
        from .formats import READERS

        return READERS
    if isinstance(readers, Reader):
        raise ParameterError(f"readers must be a sequence of impedax.io.Reader, got the single Reader {readers.name!r}: "
                             "give impedax.io.register_reader(reader), which tries it before the built-in readers")
    if isinstance(readers, (str, bytes)) or not isinstance(readers, Sequence):
        raise ParameterError(f"readers must be a sequence of impedax.io.Reader (impedax.io.register_reader(...)), got {shown(readers)} ({type(readers).__name__})")
    for i, reader in enumerate(readers):
        if not isinstance(reader, Reader):
            given = f"the function {reader.__name__!r}" if callable(reader) and hasattr(reader, "__name__") else f"{shown(reader)} ({type(reader).__name__})"
            raise ParameterError(f"readers[{i}] is {given}, not an impedax.io.Reader: "
                                 "build one with impedax.io.Reader(name, extensions, sniff, read)")
    return readers


@checked_arguments()
def load(path: str | os.PathLike, readers: Sequence[Reader] | None = None, *, sweep: str | None = None) -> xr.Dataset:
    """Load a spectrum file into the impedax data model (see `impedax.data`).

    ``readers`` is the registry to try, in order (default `impedax.io.READERS`; extend it with
    `impedax.io.register_reader`). Recognised by content: netCDF written by `save`, every
    instrument export in the registry (see docs/io.md) and delimited text with or without a
    header. Rows that are not impedance points (DC rows at f = 0, repeated headers) are skipped
    and listed in ``attrs["skipped_rows"]``; ``attrs["sign_convention"]`` and ``attrs["units"]``
    say how Z was read. Raises `DataError` naming the file (and line).

    A table of several sweeps one after another on different frequency grids is never merged
    into one spectrum: it raises `SweepGridsDiffer` (where the second starts, each sweep's
    points), unless ``sweep`` names one of them (its label: '0', '1', … or the cycle number),
    which is then read alone; so are a file's sheets, curves or measurements on different
    grids (``sweep``: a sheet's name, a curve's label). On a file whose sweeps share a grid (a ``sweep`` or ``cycle``
    dimension) ``sweep`` picks that one; on a file of one spectrum it is an error.
    """
    if isinstance(path, xr.Dataset):
        return validate_spectrum(path)
    _check_path(path)
    _checked_readers(readers)  # (before standard input is read)
    if str(path) == STDIN:
        return _load_stdin(readers, sweep)
    return _load_file(Path(path), readers, sweep)


def _load_file(path: Path, readers: Sequence[Reader] | None, sweep: str | None,
               identified: tuple[Reader | None, list[str], list[str]] | None = None) -> xr.Dataset:
    """`load` of a file; ``identified``: `_identify`'s answer when the caller has it already
    (standard input, whose readers are asked once, not again here)."""
    if sweep is not None:
        return _one_sweep(path, readers, str(sweep), identified)
    reader, tried, faults = identified if identified is not None else _identify(path, readers)
    if reader is not None:
        ds = _read_with(reader, path)
        if not isinstance(ds, xr.Dataset):
            raise DataError(f"{_named(reader)} returned {type(ds).__name__}, not a spectrum Dataset (build it with impedax.make_spectrum)", path=path)
        held = not_a_spectrum(ds) if isinstance(ds, xr.Dataset) else None
        if held:  # (a saved result, e.g. of impedax gap: say how to read it, not that it lacks Z)
            raise DataError(held, path=path)
        if reader.name == NETCDF_FORMAT and "Z" not in ds.variables:
            # (a netCDF file of the user's own layout is told more than "dataset has no variable 'Z'")
            names = ", ".join(repr(str(v)) for v in ds.data_vars) or "none"
            raise DataError(f"a netCDF file that holds no spectrum (no variable 'Z'; its data variables: {names}): impedax loads the spectra "
                            "impedax.save writes (a saved result is read with its class's from_xarray); for data of your own layout, build the "
                            "spectrum in Python, impedax.make_spectrum(frequency_hz, Z) with Z complex, and save it with impedax.save(data, 'run.nc')", path=path)
        if reader.name == NETCDF_FORMAT and ds.attrs.get("format", reader.name) != reader.name:
            # data saved from another format (an instrument file, stacked CSVs): this file is netCDF,
            # the format its data were first read from stays as ``data_format``
            ds.attrs["data_format"] = ds.attrs["format"]
            ds.attrs["format"] = reader.name
        ds.attrs.setdefault("format", reader.name)
        if ds.attrs.get("source") == IN_MEMORY:  # (a reader of the user's built it with make_spectrum: later errors name the file)
            ds.attrs["source"] = str(path)
        elif "impedax_kind" in ds.attrs and ds.attrs.get("source") not in (None, str(path)):
            # a saved result's data: errors name this file; the data's own file stays as ``saved_from``
            ds.attrs["saved_from"] = ds.attrs["source"]
            ds.attrs["source"] = str(path)
        from .formats import READERS as built_in

        if any(reader is r for r in built_in):
            return _checked(ds, path)
        _recorded_conventions(ds, reader)
        try:  # a user's reader: its Dataset's fault is named as the reader's (not "dataset has no variable 'Z'" alone)
            return _checked(ds, path)
        except DataError as exc:
            raise DataError(f"{_named(reader)} returned a Dataset that is not a spectrum: {exc.detail} (build it with impedax.make_spectrum(frequency_hz, Z))",
                            path=path, line=exc.line) from None
    head = _head(path)
    if not head_text(head).strip():  # binary or blank: decided from the first 64 kB, before reading the whole file
        if head.strip(b" \t\r\n"):
            kind = _unread_kind(head)
            if kind and not faults:  # (a .csv.gz, an .xls: named, not "a binary file that no reader claims")
                raise DataError(f"not a recognised spectrum file: {kind} ({len(tried)} formats tried)", path=path)
            raise DataError(_unrecognised(None, tried, faults, _by_extension(path, readers, tried)), path=path)
        raise DataError("file is empty", path=path)
    try:
        ds = read_csv(path)
    except NoLayout as exc:
        result = written_result(path, head_text(head))  # (a result's .csv or .json: say which and what reads back)
        if result:
            raise DataError(result, path=path) from None
        if not faults and _looks_like_json(head_text(head)):
            # (a JSON file was told "as delimited text, no frequency column in header ['{"frequency": [1', '10', ...]")
            raise DataError(_unrecognised_json(len(tried)), path=path) from None
        if not faults and _HTML_OPENING.match(head_text(head)):
            # (a web page saved in place of the file gets this, not "no frequency column in header ['<!DOCTYPE', 'html>']")
            raise DataError("not a recognised spectrum file: an HTML web page, not the data (a page that shows the file, saved in its place?): "
                            f"download the file itself (on GitHub, its Raw button); {len(tried)} formats tried", path=path) from None
        raise DataError(_unrecognised(exc.reason, tried, faults, _by_extension(path, readers, tried)), path=exc.path, line=exc.line) from None
    return _checked(ds, path)


def _recorded_conventions(ds: xr.Dataset, reader: Reader) -> None:
    """A user's reader that recorded no ``sign_convention`` or ``units`` (`make_spectrum` alone)
    gets its `Reader.conventions` there, or a word that it recorded none: otherwise ``impedax
    inspect`` would say "impedax data model: Z = Z' + jZ''" and "Hz, ohm", as if the file held
    them (a SYNTHETIC kHz/kΩ lab file)."""
    said = f"{reader.conventions} (as {_named(reader)} declares its conventions)" if reader.conventions.strip() else ""
    for key, what in (("sign_convention", "sign convention"), ("units", "units")):
        if key not in ds.attrs:
            ds.attrs[key] = said or f"{_named(reader)} recorded no {what} (Reader.conventions is empty)"


def _read_with(reader: Reader, path: Path) -> xr.Dataset:
    """``reader.read(path)``; an exception other than impedax's own (a bug or an unchecked
    input in a user's reader) becomes one `DataError` naming the file, the reader, where it was
    declared (`Reader.origin`: a ``--plugin`` file) and the line of its code that raised, the
    original kept as ``__cause__`` (in Python too: a user's ``float('oops')`` is no bare
    traceback). A `DataError` raised without ``path=`` is given the file, so that its ``line=``
    is shown too (not "impedax inspect: error: no header line", naming neither)."""
    from ..errors import ImpedaxError

    try:
        return reader.read(path)
    except DataError as exc:
        if exc.path is None and type(exc) is DataError:  # (raised without path=: the file and its line were named nowhere)
            raise DataError(exc.detail, path=path, line=exc.line) from exc
        raise
    except ImpedaxError:
        raise
    except Exception as exc:
        reason = (str(exc).strip().splitlines() or [""])[0][:300]
        raise DataError(f"the reader {reader.name!r}{''.join(_raised_at(reader.read, exc, reader.origin))} raised {type(exc).__name__}{': ' + reason if reason else ''}", path=path) from exc


def _one_sweep(path: Path, readers: Sequence[Reader] | None, label: str,
               identified: tuple[Reader | None, list[str], list[str]] | None = None) -> xr.Dataset:
    """Sweep ``label`` of file ``path`` (`load`'s ``sweep``): alone when the file's sweeps are on
    different grids (`SweepGridsDiffer.spectrum`), else picked from its sweep or cycle dimension,
    or from the one dimension its spectra lie along (a workbook's sheets, Ivium's measurements on
    one grid: not "the file holds no sweeps to pick from", as the same label reads the sheet
    alone when the sheets' grids differ)."""
    try:
        ds = _load_file(path, readers, None, identified)
    except SweepGridsDiffer as exc:
        return _sweep_of(exc, label, path)
    dims = [d for d in ("sweep", "cycle") if d in ds["Z"].dims]
    others = [d for d in ds["Z"].dims if d != "frequency"]
    if not dims and len(others) == 1:  # (a file's sheets, curves or measurements on one grid, as on different grids)
        dims = others
    if not dims:
        held = "one spectrum" if ds["Z"].ndim == 1 else f"spectra along {', '.join(others)}: pick one with data.sel({others[0]}=LABEL) (on the command line --select {others[0]}=LABEL)"
        raise DataError(f"sweep={label}: the file holds no sweeps to pick from ({held})", path=path)
    if dims[0] not in ds.coords:
        ds = ds.assign_coords({dims[0]: range(ds.sizes[dims[0]])})
    labels = [str(v) for v in ds[dims[0]].values]
    if label not in labels:
        raise DataError(f"sweep={label}: no {dims[0]} {label}; its {dims[0]}s: {', '.join(labels)}", path=path)
    return ds.isel({dims[0]: labels.index(label)})


def _sweep_of(exc: SweepGridsDiffer, label: str, path: Path) -> xr.Dataset:
    """Sweep ``label`` of file ``path`` whose sweeps lie on different grids (``exc``), as `load`
    gives a spectrum: its format and source named, validated."""
    ds = exc.spectrum(label)
    ds.attrs.setdefault("format", "delimited text")
    ds.attrs.setdefault("source", str(path))
    return _checked(ds, path)


def _checked(ds: xr.Dataset, path: Path) -> xr.Dataset:
    """``ds`` read from ``path``, validated and marked so (`data.CHECKED_FILE`): a later
    failure of `validate_spectrum` says the data changed in memory, not in the file."""
    validate_spectrum(ds, source=str(path))
    ds.encoding[CHECKED_FILE] = str(path)
    return ds


def _by_extension(path: Path, readers: Sequence[Reader] | None, tried: Sequence[str]) -> str:
    """The reason of the one reader whose `Reader.extensions` alone hold ``path``'s suffix (any
    case: ``.DTA``), when it did not claim the file: the format the file's name promises (a
    ``.mpt`` without its first line is told more than why it is no delimited text); ""
    for a suffix several readers list (``.txt``, ``.csv``) or none, and for a sniff that gave no
    reason (False) or broke its contract (named apart, `_unrecognised`'s ``faults``)."""
    suffix = path.suffix.lower()
    owners = [r for r in _checked_readers(readers) if suffix and suffix in (e.lower() for e in r.extensions)]
    if len(owners) != 1:
        return ""
    reason = next((entry.removeprefix(f"{owners[0].name}: ") for entry in tried if entry.startswith(f"{owners[0].name}: ")), None)
    if reason is None or reason.startswith(("sniff failed", "sniff returned")):  # (a fault is named apart; a False gives no reason)
        return ""
    return f"named {path.suffix}, the extension of {_named(owners[0])}, which does not recognise it: {reason}"


def _unrecognised(as_text: str | None, tried: Sequence[str], faults: Sequence[str] = (), expected: str = "") -> str:
    """The message for a file no reader claims: why it is not delimited text first (the reason
    a user of a text table needs; ``None``: the file is binary), then how many other formats
    were tried, not each one's reason (twenty reasons buried the one sentence that matters:
    ~2,000 characters); `identify` gives them, docs/io.md lists the formats. A sniff that broke
    its contract (``faults``) comes before all that: most likely a user's reader meant the file;
    then the reason of the format the file's extension names (``expected``, `_by_extension`)."""
    if faults:
        contract = "a sniff returns None (or True) for a file in its format, else the reason it is not"
        return f"not a recognised spectrum file: {'; '.join(faults)} ({contract}); " + _unrecognised(as_text, tried, (), expected).removeprefix("not a recognised spectrum file: ")
    if expected:
        return f"not a recognised spectrum file: {expected}; " + _unrecognised(as_text, tried).removeprefix("not a recognised spectrum file: ")
    other = "" if as_text is None else " other"  # (a binary file was not tried as text)
    count = f"{len(tried)}{other} format{'s' if len(tried) != 1 else ''}"
    listed = f"; {count} tried (each one's reason: impedax.io.identify; the formats: docs/io.md)" if tried else f"; no{other} format is registered"
    if as_text is None:
        return f"not a recognised spectrum file: a binary file that no reader claims{listed}"
    return f"not a recognised spectrum file: as delimited text, {as_text}{listed}"


#: Signatures of files impedax does not open, compressed files and archives first: (bytes, what
#: it is, what to do).
UNREAD_SIGNATURES = (
    (b"\x1f\x8b", "a gzip-compressed file", "decompress it first (gunzip -k FILE), or pipe it in with '-' for the file (gunzip -c FILE | impedax COMMAND -)"),
    (b"BZh", "a bzip2-compressed file", "decompress it first (bunzip2 -k FILE), or pipe it in with '-' for the file (bunzip2 -c FILE | impedax COMMAND -)"),
    (b"\xfd7zXZ\x00", "an xz-compressed file", "decompress it first (unxz -k FILE), or pipe it in with '-' for the file (unxz -c FILE | impedax COMMAND -)"),
    (b"\x28\xb5\x2f\xfd", "a zstd-compressed file", "decompress it first (unzstd FILE), or pipe it in with '-' for the file (unzstd -c FILE | impedax COMMAND -)"),
    (b"PK\x03\x04", "a zip archive (and no .xlsx or .ods workbook)", "extract the spectrum file from it first (unzip FILE)"),
    (b"7z\xbc\xaf\x27\x1c", "a 7-Zip archive", "extract the spectrum file from it first"),
    (b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1", "an Excel 97-2003 workbook (.xls) or another OLE2 file",
     "save the workbook as .xlsx (Excel: File > Save As) or each sheet as CSV"),
    (b"%PDF-", "a PDF document", "give the file of the spectrum's numbers that the figure or report was made from"),
    (b"\x89PNG\r\n\x1a\n", "a PNG image", "give the file of the spectrum's numbers that the plot was made from"),
    (b"\xff\xd8\xff", "a JPEG image", "give the file of the spectrum's numbers that the plot was made from"),
)


def _unread_kind(head: bytes) -> str:
    """What a file impedax does not open is (`UNREAD_SIGNATURES`) and what to do; "" for others."""
    return next((f"{what}, which impedax does not open: {advice}" for magic, what, advice in UNREAD_SIGNATURES if head.startswith(magic)), "")


_HTML_OPENING = re.compile(r"\ufeff?\s*(<!doctype\s+html|<html[\s>])", re.IGNORECASE)
_JSON_OPENING = re.compile(r'\ufeff?\s*(\{\s*["}]|\[\s*[-{\["\d\]])')


def _looks_like_json(text: str) -> bool:
    """Whether ``text`` opens as JSON does: an object's ``{"`` or ``{}``, or an array of
    objects, arrays, strings or numbers; not an instrument's ``[Header]`` section line."""
    return _JSON_OPENING.match(text) is not None


def _unrecognised_json(tried: int) -> str:
    """The message for a JSON file that no reader claims and that is no result impedax wrote
    (`written_result`): it is JSON, not a table, and the way to give impedax its spectrum."""
    return ("not a recognised spectrum file: a JSON file (it opens with '{' or '['), which impedax reads only as a PalmSens .pssession "
            f"({tried} formats tried); write the spectrum as a table, frequency_hz,z_real_ohm,z_imag_ohm (impedax.save(impedax.make_spectrum(f, Z), 'run.csv'))")


def _load_stdin(readers: Sequence[Reader] | None, sweep: str | None = None) -> xr.Dataset:
    """A spectrum from standard input: read (at most `max_file_bytes`), kept in a temporary
    file while a reader recognises it by content, and named ``<stdin>`` in messages and in the
    data's attrs (`_named_stdin`). ``sweep`` as `load`'s; a table of sweeps on different grids
    raises `SweepGridsDiffer` holding each sweep read (standard input is read once: the
    command line's ``--select sweep=LABEL`` takes its sweep from there)."""
    import sys
    import tempfile

    from ._common import max_file_bytes
    from .atomic import staging_directory

    limit = max_file_bytes()
    stream = getattr(sys.stdin, "buffer", None)
    if stream is None:
        raise DataError("no standard input to read from", path=STDIN_NAME)
    try:
        terminal = stream.isatty()
    except (OSError, ValueError):  # (a closed or detached stream: read below says so)
        terminal = False
    if terminal:  # (impedax kk - typed with nothing piped in would wait silently for the keyboard)
        raise DataError("standard input is a terminal, not a file: '-' reads a spectrum piped in (impedax kk - < run.csv, or another "
                        "command's output through |); give the file's path otherwise", path=STDIN_NAME)
    try:
        raw = stream.read(limit + 1)
    except OSError as exc:
        raise DataError(f"cannot read standard input: {exc.strerror}", path=STDIN_NAME) from None
    if len(raw) > limit:
        raise DataError(f"more than {limit // 2**20} MB on standard input (the limit; see docs/robustness.md to raise it)", path=STDIN_NAME)
    if not raw.strip(b" \t\r\n"):  # (not "file is empty": there is no file to look for)
        raise DataError("standard input is empty: nothing was piped in (did the command before '|' write nothing, or fail?)", path=STDIN_NAME)
    with staging_directory(tempfile.gettempdir(), prefix=".impedax-stdin-") as folder:
        path = folder / "stdin"
        path.write_bytes(raw)
        try:
            identified = _identify(path, readers)  # (each sniff runs once, not here and again in load)
            note = _stdin_declined(readers, identified)
            ds = _load_file(path, readers, sweep, identified)
        except DataError as exc:
            text = str(exc)
            placed = text.startswith(f"{path} [")  # (a place inside the file, 'FILE [sheet S], cell B10: …': said once, as it is)
            for prefix in (f"{path}, line {exc.line}: ", f"{path}: "):
                if text.startswith(prefix):
                    text = text[len(prefix):]
                    break
            text = text.replace(str(path), STDIN_NAME)
            where = {"path": None, "line": None} if placed else {"path": STDIN_NAME, "line": exc.line}
            if isinstance(exc, SweepGridsDiffer):
                spectra = {label: _named_stdin(_sweep_of(exc, label, path), str(path)) for label in exc.labels}
                out: DataError = SweepGridsDiffer(text, **where, dim=exc.dim, spectra=spectra, found=exc.found.replace(str(path), STDIN_NAME))
            else:
                out = DataError(text, **where)
            out.path, out.line = STDIN_NAME, exc.line
            raise out from None
        if note:
            ds.attrs["stdin_note"] = f"standard input read as {ds.attrs.get('format', 'delimited text')}: {note}"
    return _named_stdin(ds, str(path))


def _stdin_declined(readers: Sequence[Reader] | None, identified: tuple[Reader | None, list[str], list[str]]) -> str:
    """Why standard input (kept in a file with no suffix, whose `_identify` answer is
    ``identified``) may be read by the wrong reader: the user's readers (not built in, a
    ``--plugin``'s) that did not claim it, with their reasons, when none of them did; "" otherwise. A reader that goes by the file's extension never
    claims standard input, which is then read as delimited text (a kHz/kΩ table 1000× off
    without this word). Stored as ``attrs["stdin_note"]``."""
    from .formats import READERS as built_in

    own = [r for r in (readers or ()) if not any(r is b for b in built_in)]
    if not own:
        return ""
    claimed, tried, _ = identified
    if claimed is not None and any(claimed is r for r in own):
        return ""
    reasons = [entry for r in own for entry in tried if entry.startswith(f"{r.name}: ")]
    named = ", ".join(_named(r) for r in own)
    return (f"it has no file name, and your {'readers' if len(own) > 1 else 'reader'} ({named}) did not claim it "
            f"({'; '.join(reasons) or 'no reason given'}); a reader that goes by the file's extension never claims standard input: "
            "give the file's path in place of '-' to have it read so")


def _named_stdin(ds: xr.Dataset, copy: str) -> xr.Dataset:
    """``ds`` read from ``copy``, the temporary file that held standard input, with every mention
    of that file (attrs ``path`` and ``source``, as every reader sets them, and any text attribute
    holding it) as `STDIN_NAME`: the JSON ``source``, the provenance and the ``--out`` columns name
    ``<stdin>``, never a deleted temporary path (``/tmp/.impedax-stdin-XXXX/stdin``)."""
    def named(value):
        if isinstance(value, str):
            return value.replace(copy, STDIN_NAME)
        if isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value):
            return type(value)(v.replace(copy, STDIN_NAME) for v in value)
        return value

    ds.attrs = {key: named(value) for key, value in ds.attrs.items()}
    ds.attrs["path"] = ds.attrs["source"] = STDIN_NAME
    for key in ("source", CHECKED_FILE):
        if ds.encoding.get(key) == copy:
            ds.encoding[key] = STDIN_NAME
    return ds


def spectrum_format(path: str | os.PathLike) -> str:
    """``"netcdf"`` or ``"csv"``: what `save` writes to ``path`` (by extension); `DataError`
    naming the known extensions otherwise (checked before any work is done)."""
    suffix = Path(path).suffix.lower()
    if suffix in NETCDF_SUFFIXES:
        return "netcdf"
    if suffix in CSV_SUFFIXES:
        return "csv"
    raise DataError(f"unknown output format {suffix!r}; use {', '.join(NETCDF_SUFFIXES)} (netCDF), {', '.join(s for s in CSV_SUFFIXES if s)} (CSV; .tsv tab-separated) or no extension (CSV)", path=path)


def _check_path(path) -> None:
    """A file path as `load` and `save` take it (str or os.PathLike), else one `DataError`."""
    if not isinstance(path, (str, os.PathLike)):
        raise DataError(f"a file path (str or pathlib.Path) is needed, got {shown(path)} ({type(path).__name__})")
    if isinstance(path, str) and not path:  # (Path('') is '.': "'.': is a directory, not a spectrum file" would not say what is wrong)
        raise DataError("empty file name: no spectrum file was named (an unset shell variable, \"$DATA\" with nothing in it?)")
    if "\x00" in str(path):
        raise DataError(f"a file name cannot contain a NUL character: {shown(str(path))}")


@checked_arguments()
def save(ds: xr.Dataset, path: str | os.PathLike, *, provenance: Mapping[str, object] | None = None) -> None:
    """Save a spectrum: ``.nc`` → lossless netCDF, ``.csv``/``.txt`` (or no extension) →
    canonical CSV, ``.tsv`` → the same columns separated by tabs. Atomic. ``provenance``
    (`impedax.io.provenance.provenance`; the command line gives it) is recorded as a written
    result records it (docs/io.md, "Provenance"): the netCDF attributes of `provenance_attrs`,
    the CSV columns of `provenance_columns` after the spectrum's own."""
    if not isinstance(ds, xr.Dataset):
        from .export import is_result  # (what write_result takes: a summary or a to_xarray)

        if is_result(ds):
            where = str(path) if isinstance(path, (str, os.PathLike)) else "result.nc"
            raise DataError(f"save takes a spectrum Dataset, got a {type(ds).__name__}: a result is written with impedax.write_result(result, {where!r}) (.nc, .csv or .json)")
        raise DataError(f"save takes a spectrum Dataset (impedax.make_spectrum, impedax.load), got {shown(ds)} ({type(ds).__name__})")
    _check_path(path)
    check_file_name(path, "spectrum.csv")  # (before Path(), which reads "out/" as a file "out")
    path = Path(path)
    kind = spectrum_format(path)
    validate_spectrum(ds)
    from .provenance import provenance_attrs, provenance_columns

    if kind == "netcdf":
        write_netcdf(ds if provenance is None else ds.assign_attrs(provenance_attrs(provenance)), path)
    else:
        columns = None if provenance is None else provenance_columns(provenance)
        write_csv(ds, path, delimiter="\t" if path.suffix.lower() == ".tsv" else ",", columns=columns)
