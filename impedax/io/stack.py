"""`stack_files`: one spectrum per file (a corrosion test's day01.csv … day10.csv), or files of
spectra over the same dimensions (per-material files over voltage), as one Dataset over a new
dimension, which `impedax.fit` then fits as a batch (docs/io.md, "Several files as one series")."""

from __future__ import annotations

import keyword
import math
import os
import re
from pathlib import Path
from typing import Sequence

import numpy as np
import xarray as xr

from ..arguments import checked_arguments, shown
from ..data import make_spectrum
from ..errors import DataError, ParameterError
from ._common import merged_attrs
from .provenance import PROVENANCE_ATTRS
from .loader import STDIN, STDIN_NAME, load
from .table import SWEEP_RTOL

__all__ = ["stack_files", "stack_labels", "check_dimension_name", "DIMENSION_NAME"]


STDIN_LABEL = "stdin"
"""The label of standard input (``-``) along the new dimension when no ``coords`` are given."""


@checked_arguments()
def stack_files(paths: Sequence[str | os.PathLike], dim: str = "file", coords: Sequence | None = None, *, readers: Sequence | None = None,
                common_frequencies: bool = False) -> xr.Dataset:
    """The spectra of ``paths`` (each read by `impedax.load`) as one spectrum Dataset with Z over
    (``dim``, frequency), in the order given; files that each hold spectra over the same extra
    dimensions (per-material files over voltage) give Z over (``dim``, *those dimensions*,
    frequency), each file's spectra lined up by their labels (in any order).

    ``coords``: one label per file (`stack_labels`: text that reads as numbers becomes numbers);
    default the file names without extension (``day01``). The files must share one frequency
    grid: the same frequencies in any order, each within `SWEEP_RTOL` (0.1 %, the tolerance the
    readers merge sweeps with) of the first file's, whose values and order the result keeps.
    ``sigma`` is kept when every file has it. ``attrs["sources"]`` lists the files, and attributes
    that differ between them are kept labelled (``day01: ...; day02: ...``); the readers' records
    of the columns they read (``attrs["columns"]``) are kept as one when the files agree, else
    each file's in ``attrs["columns_by_file"]`` (file path → record).
    ``dim``: a name `check_dimension_name` takes (``day``, ``cell_2``).
    Raises `ParameterError` for bad ``dim``/``coords`` and `DataError` naming the file that cannot
    join (missing, unreadable, other dimensions or labels than the first file's, already over
    ``dim``, another grid, sigma in some files only, the same spectrum as another file's).
    ``readers``: as `impedax.load`'s (None: the built-in ones).

    ``common_frequencies``: files whose grids differ keep the frequencies every
    file has (each within `SWEEP_RTOL` of the first file's) and leave out the rest, measured
    points only (nothing is interpolated); ``attrs["frequencies_left_out"]`` maps each file that
    lost points to their frequencies [Hz]. A file that would keep fewer than half its points
    (`COMMON_SHARE_MIN`) is a `DataError` naming it: those files were not measured on one plan.
    """
    if isinstance(paths, (str, bytes, os.PathLike)):
        raise ParameterError(f"paths must be a list of files, got the single {shown(str(paths))}: give [path] for one file")
    try:
        paths = list(paths)
    except TypeError:
        raise ParameterError(f"paths must be a list of files, got {shown(paths)} ({type(paths).__name__})") from None
    if not paths:
        raise ParameterError("paths is empty: give at least one spectrum file")
    for i, path in enumerate(paths):  # (a number: this message, not os.fspath's TypeError)
        if not isinstance(path, (str, os.PathLike)):
            raise ParameterError(f"paths: item {i + 1} of {len(paths)} is not a file name: {shown(path)} ({type(path).__name__})")
    if not isinstance(dim, str) or not dim.strip():
        raise ParameterError(f"dim must be the name of the new dimension (text, e.g. 'day'), got {shown(dim)}")
    check_dimension_name(dim)
    if dim == "frequency":
        raise ParameterError("dim: 'frequency' is every spectrum's own dimension; name the new one otherwise, e.g. 'day'")
    if dim in ("Z", "sigma"):  # (Z ended in xarray's ValueError, sigma in make_spectrum's words on sigma's shape)
        raise ParameterError(f"dim: {dim!r} is the name of a variable of every spectrum; name the new dimension otherwise, e.g. 'day'")
    labels = None if coords is None else stack_labels(coords, len(paths))  # (the labels given are checked first, as any argument)
    _refuse_repeated(paths)
    spectra = [_spectra_of(path, dim, readers) for path in paths]
    if labels is None:  # (after the reading: a file's fault is named before its name's, nan.csv's NaN before 'nan'; standard input, "-", is labelled "stdin")
        labels = stack_labels([STDIN_LABEL if str(p) == STDIN else Path(str(p)).stem for p in paths], len(paths), given=False)
    paths = [STDIN_NAME if str(p) == STDIN else p for p in paths]
    first, first_path = spectra[0], str(paths[0])
    extra = tuple(d for d in first["Z"].dims if d != "frequency")
    spectra = [_aligned(ds, path, first, first_path, extra) for ds, path in zip(spectra, paths)]
    if common_frequencies:
        spectra, left_out = _on_common_frequencies(spectra, paths, first_path)
        first = spectra[0]
    f0 = first["frequency"].values
    order0 = np.argsort(f0)
    z = np.empty((len(paths), *(first.sizes[d] for d in extra), f0.size), complex)
    with_sigma = ["sigma" in ds for ds in spectra]
    if any(with_sigma) and not all(with_sigma):
        having, lacking = with_sigma.index(True), with_sigma.index(False)
        raise DataError(f"has no sigma but {paths[having]} has one: stack files that all have sigma, or none (a fit weights by sigma only where every spectrum has it)", path=paths[lacking])
    sigma = np.empty(z.shape) if all(with_sigma) else None
    for i, (path, ds) in enumerate(zip(paths, spectra)):
        f = ds["frequency"].values
        order = np.argsort(f)
        _check_grid(f[order], f0[order0], path, first_path)
        z[i][..., order0] = ds["Z"].transpose(*extra, "frequency").values[..., order]
        if sigma is not None:
            sigma[i][..., order0] = ds["sigma"].transpose(*extra, "frequency").values[..., order]
    _refuse_copies(z, paths)
    attrs = merged_attrs([(str(label), ds.attrs) for label, ds in zip(labels, spectra)], dim)
    # each file's own (the list below names them all); and what says a file is a saved result or
    # what wrote it: the stack holds their spectra alone (else two KK tests' files stacked
    # would be shown by impedax inspect as "a saved Kramers-Kronig test", with the first test's provenance)
    for key in ("path", "saved_from", "impedax_kind", *PROVENANCE_ATTRS):
        attrs.pop(key, None)
    attrs["sources"] = [str(p) for p in paths]
    attrs["stacked_along"] = dim
    if common_frequencies and left_out:
        attrs["frequencies_left_out"] = left_out
    records = [ds.attrs.get("columns") for ds in spectra]
    if "columns" not in attrs and any(isinstance(r, dict) for r in records):
        # the files' readers recorded different columns (Hz here, kHz there): each file's record,
        # by its path as in "sources" ({} for a file whose reader recorded none)
        attrs["columns_by_file"] = {str(p): dict(r) if isinstance(r, dict) else {} for p, r in zip(paths, records)}
    source = first_path if len(paths) == 1 else f"{first_path} … {paths[-1]} ({len(paths)} files)"
    stacked = make_spectrum(f0, z, sigma=sigma, dims=(dim, *extra), coords={dim: labels, **{d: first[d].values for d in extra if d in first.coords}}, attrs=attrs, source=source)
    for d in extra:  # (the files' labels keep their attributes: a voltage's units)
        if d in first.coords:
            stacked[d].attrs = dict(first[d].attrs)
    return stacked


DIMENSION_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_.-]*")
"""The names `stack_files` gives a new dimension: an ASCII letter, then ASCII letters, digits,
``_``, ``-`` and ``.``, which ``--select NAME=LABEL`` (split at the first ``=``), ``--over`` and
``--plot-x`` read whole, and netCDF stores as they are. Left out: blanks, ``=``, ``,``, ``/``
and the like (``--select`` would split the name, netCDF refuses ``/``); a leading ``-`` (an
option to argparse), digit (``0``, ``1e3``: a number, which ``ds.sel(0=...)`` cannot take) or
``_`` (netCDF keeps names led by ``_`` for its own); any other character (``é``, ``½``, ``Ω``):
netCDF names are UTF-8, and the netCDF3 writer impedax uses (scipy's) stores each character of
a name as one byte, ``é`` as a byte that is no UTF-8 text and ``Ω`` not at all."""

NAME_CHARACTERS_MAX = 256
"""The longest name netCDF's library reads (its ``NC_MAX_NAME``)."""


def check_dimension_name(dim: str) -> None:
    """`ParameterError` (a ValueError) naming ``dim`` and what in it a dimension's name may not
    hold, unless it matches `DIMENSION_NAME`, is no Python keyword (``class``, ``None``:
    ``ds.sel(class=...)`` is a syntax error) nor a word that reads as a number (``nan``, ``inf``,
    ``infinity`` in any case), and has at most `NAME_CHARACTERS_MAX` characters. An empty or
    non-text ``dim`` is `stack_files`' to refuse; ``frequency``, ``Z`` and ``sigma`` too."""
    if not isinstance(dim, str) or not dim or DIMENSION_NAME.fullmatch(dim) and not _reserved_word(dim) and len(dim) <= NAME_CHARACTERS_MAX:
        return
    bad = sorted({c for c in dim if not re.fullmatch(r"[A-Za-z0-9_.-]", c)}, key=dim.index)
    if bad:
        listed = ", ".join(_character(c) for c in bad[:3]) + (f", … ({len(bad)} characters)" if len(bad) > 3 else "")
        said = f"{listed} cannot stand in it" + (" (netCDF reads names as UTF-8, which impedax's netCDF3 writer writes for ASCII only)" if any(not c.isascii() for c in bad) else "")
    elif not re.fullmatch(r"[A-Za-z]", dim[0]):
        said = f"{dim[0]!r} cannot lead it" + (" (netCDF keeps names led by '_' for its own)" if dim[0] == "_" else "")
    elif len(dim) > NAME_CHARACTERS_MAX:
        said = f"its {len(dim)} characters are more than netCDF's {NAME_CHARACTERS_MAX}"
    else:
        said = _reserved_word(dim)
    raise ParameterError(f"dim: {_name(dim)} cannot name a dimension: {said}; name it with an ASCII letter, then letters, digits, '_', '-' or '.' "
                         "(e.g. day, cell_2), no Python keyword, nan or inf")


def _reserved_word(name: str) -> str:
    """What ``name`` means to Python or to a reader of numbers (``float``), or "" if nothing."""
    if keyword.iskeyword(name):
        return f"it is a Python keyword (ds.sel({name}=...) is a syntax error)"
    if _number(name) is not None or name.lower() in ("nan", "inf", "infinity"):
        return f"it reads as a number (float({name!r}) is {float(name)!r})"
    return ""


def _character(c: str) -> str:
    """One character of a name as the message shows it: quoted, escaped when invisible, with
    its code point when it is not ASCII."""
    return repr(c) if c.isascii() else f"{c!r} (U+{ord(c):04X})"


def _name(name: str, limit: int = 60) -> str:
    """``name`` quoted (invisible characters escaped), cut to ``limit`` characters."""
    text = repr(name)
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _refuse_repeated(paths: Sequence) -> None:
    """`DataError` when one file is given twice (the same file by any path to it): its spectrum
    would stand in the series twice as two measurements. A message on the repeated label
    alone would send the user to --coords, which would write the two copies without a word."""
    seen: dict[str, int] = {}
    for i, path in enumerate(paths):
        if str(path) == STDIN:
            continue
        key = os.path.normcase(os.path.realpath(os.fspath(path)))
        if key in seen:
            raise DataError(f"is given twice (files {seen[key] + 1} and {i + 1} of {len(paths)}): each file is one measurement of the series; give each once", path=str(path))
        seen[key] = i


def _refuse_copies(z: np.ndarray, paths: Sequence) -> None:
    """`DataError` when two files hold the same spectrum, every Z equal (a file copied under a
    second name, ``day02.csv`` a copy of ``day01.csv``): it would stand in the series twice as two
    measurements, as a file given twice would (`_refuse_repeated`; ``impedax gap`` refuses such
    inputs alike)."""
    seen: dict[bytes, int] = {}
    for i in range(z.shape[0]):
        key = np.ascontiguousarray(z[i]).tobytes()
        if key in seen:
            raise DataError(f"holds the same spectrum as {paths[seen[key]]} (every Z equal: a copy of that file?): each file is one measurement of the series; give each once", path=str(paths[i]))
        seen[key] = i


def stack_labels(values: Sequence, count: int, *, given: bool = True) -> np.ndarray:
    """One label per file: ``values`` as numbers when every one reads as a number (whole numbers
    as integers: ``1 2 3``, ``0.5 1.5``), else as text; `ParameterError` naming ``coords`` when
    their count is not ``count``, a label repeats, or one is no label ``--select DIM=LABEL`` can
    name (`_check_label`: empty, blanks around it, NaN or inf) (``given``: the user gave them;
    otherwise they are the file names, and the message says to give coords)."""
    if isinstance(values, (str, bytes)):
        raise ParameterError(f"coords must be one label per file, got the single {shown(values)}")
    try:
        values = list(values)
    except TypeError:
        raise ParameterError(f"coords must be one label per file, got {shown(values)} ({type(values).__name__})") from None
    if len(values) != count:
        raise ParameterError(f"coords: {len(values)} label{'s' if len(values) != 1 else ''} for {count} file{'s' if count != 1 else ''}; give one per file, in the files' order")
    for i, value in enumerate(values):
        _check_label(value, i, count, given)
    numbers = [_number(v) for v in values]
    if all(n is not None for n in numbers):
        labels = np.array([int(n) for n in numbers]) if all(float(n).is_integer() and abs(n) < 2**31 for n in numbers) else np.array(numbers, float)
    else:
        labels = np.array([str(v) for v in values])
    seen: dict = {}
    for i, label in enumerate(labels.tolist()):
        if label in seen and given:
            raise ParameterError(f"coords: the label {label!r} is given twice (files {seen[label] + 1} and {i + 1}); give each file its own label")
        if label in seen:
            raise ParameterError(f"files {seen[label] + 1} and {i + 1} are both named {label!r}: label the files with coords (impedax stack --coords), one label per file")
        seen[label] = i
    return labels


def _check_label(value, i: int, count: int, given: bool) -> None:
    """`ParameterError` naming label ``i`` (0-based) of ``count`` when ``--select DIM=LABEL`` could
    not name it: empty or only blanks, blanks around it (--select strips them), or a number that
    is not finite (NaN, inf: a stack of "nan" and 1 has text labels, and NaN equals no label)."""
    where = f"coords: label {i + 1} of {count}" if given else f"the label of file {i + 1} of {count} (its name without extension)"
    fix = "give each file a label --select can name (a number, or text without blanks around it)" if given else \
        "label the files with coords (impedax stack --coords), one label per file"
    if isinstance(value, (float, np.floating)) and not math.isfinite(value):
        raise ParameterError(f"{where}, {shown(str(value))}, is not a finite number; {fix}")
    if not isinstance(value, str):
        return
    if not value.strip():
        raise ParameterError(f"{where} is empty{'' if not value else ' (blanks only)'}; {fix}")
    if value != value.strip():
        raise ParameterError(f"{where}, {shown(value)}, has blanks around it, which --select DIM=LABEL strips; {fix}")
    try:
        number = float(value)
    except ValueError:
        return
    if not math.isfinite(number):
        raise ParameterError(f"{where}, {shown(value)}, is not a finite number; {fix}")


def _number(value) -> float | None:
    """``value`` as a finite float (a number, or text that reads as one), else None."""
    if isinstance(value, bool):
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


def _spectra_of(path, dim: str, readers=None) -> xr.Dataset:
    """The spectra of file ``path`` (one, or several over extra dimensions) read by ``readers``
    (as `impedax.load`'s); a file already over ``dim`` is a `DataError` naming it."""
    ds = load(path, readers)
    extra = [d for d in ds["Z"].dims if d != "frequency"]
    if dim in extra:
        raise DataError(
            f"holds spectra over {', '.join(extra)} already, {dim} among them; the stack adds a new dimension: name it otherwise (--dim), "
            f"e.g. the quantity that tells the files apart (material, cell)",
            path=path,
        )
    if dim in ds.coords:  # (a scalar coordinate the reader set, e.g. a cycle number)
        ds = ds.drop_vars(dim)
    return ds


def _aligned(ds: xr.Dataset, path, first: xr.Dataset, first_path: str, extra: tuple[str, ...]) -> xr.Dataset:
    """``ds`` (the spectra of ``path``) over the extra dimensions ``extra`` of the first file,
    each spectrum lined up with the first file's of the same labels (its labels in any order); a
    `DataError` naming ``path`` when its dimensions, sizes or labels differ from the first file's
    (a stack of files over voltage along a new material needs every file over the same voltages)."""
    own = tuple(d for d in ds["Z"].dims if d != "frequency")
    if set(own) != set(extra):
        def over(spectra, dims):
            return f"{math.prod(spectra.sizes[d] for d in dims)} spectra (over {', '.join(dims)})" if dims else "one spectrum"

        raise DataError(
            f"holds {over(ds, own)} but {first_path} holds {over(first, extra)}; a stack joins files of the same dimensions along a new one "
            + (f"(a file of one spectrum each: export one, impedax inspect FILE --select {own[0]}=LABEL --out ONE.csv)" if own and not extra else "(stack files of one kind at a time)"),
            path=path,
        )
    for d in extra:
        if ds.sizes[d] != first.sizes[d]:
            raise DataError(f"has {ds.sizes[d]} spectra along {d}, {first_path} {first.sizes[d]}; a stack needs the same labels along {d} in every file", path=path)
        if (d in ds.coords) != (d in first.coords):
            raise DataError(f"{d} {'has' if d in ds.coords else 'has no'} labels (coordinates) here but {'has' if d in first.coords else 'none'} in {first_path}; label both or neither", path=path)
        if d not in first.coords:
            continue  # (positions: the same size is all there is to match)
        ours, theirs = first[d].values.tolist(), ds[d].values.tolist()
        if ours == theirs:
            continue
        missing = [v for v in ours if v not in theirs]
        unknown = [v for v in theirs if v not in ours]
        if missing or unknown or len(set(theirs)) != len(theirs):
            said = "; ".join(part for part in (
                f"not in {first_path}: {_labels(unknown)}" if unknown else "",
                f"missing here: {_labels(missing)}" if missing else "",
                "its labels repeat" if not (missing or unknown) else "",
            ) if part)
            raise DataError(f"its labels along {d} ({_labels(theirs)}) are not {first_path}'s ({_labels(ours)}): {said}; a stack lines spectra up by their labels", path=path)
        ds = ds.sel({d: ours})  # the same labels in another order: each spectrum goes under its label
    return ds


def _labels(values: list) -> str:
    """At most six labels as text, then how many there are."""
    return ", ".join(map(str, values[:6])) + (f", … ({len(values)} in all)" if len(values) > 6 else "")


def _check_grid(f: np.ndarray, f0: np.ndarray, path, first_path: str) -> None:
    """`DataError` naming ``path`` unless its sorted frequencies ``f`` [Hz] are the first file's
    ``f0`` within `SWEEP_RTOL`: each grid's points and range, how many frequencies match, and
    those one file has and the other lacks (a point skipped in one sweep is named as such)."""
    if f.shape == f0.shape and np.all(np.abs(f / f0 - 1) <= SWEEP_RTOL):
        return
    from ..data import format_band, format_frequency

    name0 = Path(first_path).name
    lacking = f0[_nearest_match(f, f0) < 0]  # (the first file's frequencies this one lacks)
    extra = f[_nearest_match(f0, f) < 0]

    def listed(values: np.ndarray) -> str:
        shown = ", ".join(format_frequency(v) for v in values[:4])
        return shown + (", …" if values.size > 4 else "")

    shared = f0.size - lacking.size
    told = [f"{shared} frequenc{'y matches' if shared == 1 else 'ies match'} within {SWEEP_RTOL * 100:.1f} %"]
    if lacking.size:
        told.append(f"{name0} has {lacking.size} this file lacks ({listed(lacking)})")
    if extra.size:
        told.append(f"this file has {extra.size} {name0} lacks ({listed(extra)})")
    if not (lacking.size or extra.size):  # (every point near one of the other's, but not one for one: points within 0.1 % of each other)
        told = [f"each frequency is near one of {name0}'s, but not one for one"]
    remedy = ("keep the frequencies every file has (impedax stack --common-frequencies; common_frequencies=True), or fit the files one by one"
              if shared >= COMMON_SHARE_MIN * max(f.size, f0.size) else
              "they share under half their points, too few to keep only the shared ones (--common-frequencies): fit the files one by one")
    raise DataError(
        f"its frequency grid differs from {first_path}'s ({f.size} vs {f0.size} points: {format_band(f.min(), f.max())} vs "
        f"{format_band(f0.min(), f0.max())}; {'; '.join(told)}); "
        f"spectra stack only on one grid (within {SWEEP_RTOL * 100:.1f} %): measure them so, {remedy}",
        path=path,
    )


def _nearest_match(f: np.ndarray, f0: np.ndarray) -> np.ndarray:
    """For each of ``f0``'s frequencies [Hz], the index of the nearest of ``f``'s on a log scale
    when it is within `SWEEP_RTOL`, else -1."""
    order = np.argsort(f)
    log_f, target = np.log(f[order]), np.log(f0)
    above = np.clip(np.searchsorted(log_f, target), 0, f.size - 1)  # (the neighbours of each target in the sorted grid)
    below = np.clip(above - 1, 0, f.size - 1)
    index = order[np.where(np.abs(log_f[below] - target) <= np.abs(log_f[above] - target), below, above)]
    return np.where(np.abs(f[index] / f0 - 1) <= SWEEP_RTOL, index, -1)


COMMON_SHARE_MIN = 0.5
"""`stack_files` with ``common_frequencies`` refuses a file that would keep less than this share
of its points: a sweep plan of 10 points per decade stacked with one of 5 shares half the
first's points, and files that share fewer were not measured on one plan."""


def _on_common_frequencies(spectra: list[xr.Dataset], paths: Sequence, first_path: str) -> tuple[list[xr.Dataset], dict[str, list[float]]]:
    """``spectra`` each cut to the frequencies every one has, each matched to the first file's
    within `SWEEP_RTOL` (the nearest on a log scale); and, by file path, the frequencies [Hz] of
    each file that were left out (files that lost none are absent). `DataError` naming a file
    that keeps fewer than `COMMON_SHARE_MIN` of its points, or whose points match one of the first
    file's twice."""
    f0 = spectra[0]["frequency"].values
    matches = []  # per file: for each of the first file's points, the index of its match here (-1: none)
    for ds, path in zip(spectra, paths):
        match = _nearest_match(ds["frequency"].values, f0)
        matched = match >= 0
        if np.unique(match[matched]).size != np.count_nonzero(matched):
            raise DataError(f"two of {first_path}'s frequencies match one of this file's within {SWEEP_RTOL * 100:.1f} %: the grids cannot be lined up point by point", path=path)
        matches.append(match)
    kept = np.all(np.array(matches) >= 0, axis=0)
    left_out: dict[str, list[float]] = {}
    cut = []
    for ds, path, match in zip(spectra, paths, matches):
        n = ds.sizes["frequency"]
        if np.count_nonzero(kept) < COMMON_SHARE_MIN * n:
            raise DataError(
                f"shares only {np.count_nonzero(kept)} of its {n} frequencies with the other files (within {SWEEP_RTOL * 100:.1f} %): under half, so the files were not "
                f"measured on one sweep plan; fit them one by one",
                path=path,
            )
        index = match[kept]
        dropped = np.setdiff1d(np.arange(n), index)
        if dropped.size:
            left_out[str(path)] = sorted(float(v) for v in ds["frequency"].values[dropped])
        cut.append(ds.isel(frequency=index))
    return cut, left_out
