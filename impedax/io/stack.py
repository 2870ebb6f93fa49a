"""`stack_files`: one spectrum per file (a corrosion test's day01.csv … day10.csv) as one
Dataset over a new dimension, which `impedax.fit` then fits as a batch (docs/io.md, "Several
files as one series")."""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Sequence

import numpy as np
import xarray as xr

from ..arguments import shown
from ..data import make_spectrum
from ..errors import DataError, ParameterError
from ._common import merged_attrs
from .loader import STDIN, STDIN_NAME, load
from .table import SWEEP_RTOL

__all__ = ["stack_files", "stack_labels"]


STDIN_LABEL = "stdin"
"""The label of standard input (``-``) along the new dimension when no ``coords`` are given."""


def stack_files(paths: Sequence[str | os.PathLike], dim: str = "file", coords: Sequence | None = None) -> xr.Dataset:
    """The spectra of ``paths`` (each read by `impedax.load`, each holding one spectrum) as one
    spectrum Dataset with Z over (``dim``, frequency), in the order given.

    ``coords``: one label per file (`stack_labels`: text that reads as numbers becomes numbers);
    default the file names without extension (``day01``). The files must share one frequency
    grid: the same frequencies in any order, each within `SWEEP_RTOL` (0.1 %, the tolerance the
    readers merge sweeps with) of the first file's, whose values and order the result keeps.
    ``sigma`` is kept when every file has it. ``attrs["sources"]`` lists the files, and attributes
    that differ between them are kept labelled (``day01: ...; day02: ...``); the readers' records
    of the columns they read (``attrs["columns"]``) are kept as one when the files agree, else
    each file's in ``attrs["columns_by_file"]`` (file path → record).
    Raises `ParameterError` for bad ``dim``/``coords`` and `DataError` naming the file that cannot
    join (missing, unreadable, several spectra, another grid, sigma in some files only).
    """
    if isinstance(paths, (str, bytes, os.PathLike)):
        raise ParameterError(f"paths must be a list of files, got the single {shown(str(paths))}: give [path] for one file")
    try:
        paths = list(paths)
    except TypeError:
        raise ParameterError(f"paths must be a list of files, got {shown(paths)} ({type(paths).__name__})") from None
    if not paths:
        raise ParameterError("paths is empty: give at least one spectrum file")
    if not isinstance(dim, str) or not dim.strip():
        raise ParameterError(f"dim must be the name of the new dimension (text, e.g. 'day'), got {shown(dim)}")
    if dim == "frequency":
        raise ParameterError("dim: 'frequency' is every spectrum's own dimension; name the new one otherwise, e.g. 'day'")
    # (standard input, "-", is named as load names it, <stdin>, and labelled "stdin"; added 2026-12-01)
    labels = stack_labels([STDIN_LABEL if str(p) == STDIN else Path(str(p)).stem for p in paths] if coords is None else coords, len(paths), given=coords is not None)
    spectra = [_one_spectrum(path, dim) for path in paths]
    paths = [STDIN_NAME if str(p) == STDIN else p for p in paths]
    first, first_path = spectra[0], str(paths[0])
    f0 = first["frequency"].values
    order0 = np.argsort(f0)
    z = np.empty((len(paths), f0.size), complex)
    with_sigma = ["sigma" in ds for ds in spectra]
    if any(with_sigma) and not all(with_sigma):
        having, lacking = with_sigma.index(True), with_sigma.index(False)
        raise DataError(f"has no sigma but {paths[having]} has one: stack files that all have sigma, or none (a fit weights by sigma only where every spectrum has it)", path=paths[lacking])
    sigma = np.empty(z.shape) if all(with_sigma) else None
    for i, (path, ds) in enumerate(zip(paths, spectra)):
        f = ds["frequency"].values
        order = np.argsort(f)
        _check_grid(f[order], f0[order0], path, first_path)
        z[i, order0] = ds["Z"].values[order]
        if sigma is not None:
            sigma[i, order0] = ds["sigma"].values[order]
    attrs = merged_attrs([(str(label), ds.attrs) for label, ds in zip(labels, spectra)], dim)
    for key in ("path", "saved_from"):  # (each file's own: the list below names them all)
        attrs.pop(key, None)
    attrs["sources"] = [str(p) for p in paths]
    attrs["stacked_along"] = dim
    records = [ds.attrs.get("columns") for ds in spectra]
    if "columns" not in attrs and any(isinstance(r, dict) for r in records):
        # the files' readers recorded different columns (Hz here, kHz there): each file's record,
        # by its path as in "sources" ({} for a file whose reader recorded none)
        attrs["columns_by_file"] = {str(p): dict(r) if isinstance(r, dict) else {} for p, r in zip(paths, records)}
    source = first_path if len(paths) == 1 else f"{first_path} … {paths[-1]} ({len(paths)} files)"
    return make_spectrum(f0, z, sigma=sigma, dims=(dim,), coords={dim: labels}, attrs=attrs, source=source)


def stack_labels(values: Sequence, count: int, *, given: bool = True) -> np.ndarray:
    """One label per file: ``values`` as numbers when every one reads as a number (whole numbers
    as integers: ``1 2 3``, ``0.5 1.5``), else as text; `ParameterError` naming ``coords`` when
    their count is not ``count`` or a label repeats (``given``: the user gave them; otherwise they
    are the file names, and the message says to give coords)."""
    if isinstance(values, (str, bytes)):
        raise ParameterError(f"coords must be one label per file, got the single {shown(values)}")
    try:
        values = list(values)
    except TypeError:
        raise ParameterError(f"coords must be one label per file, got {shown(values)} ({type(values).__name__})") from None
    if len(values) != count:
        raise ParameterError(f"coords: {len(values)} label{'s' if len(values) != 1 else ''} for {count} file{'s' if count != 1 else ''}; give one per file, in the files' order")
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


def _number(value) -> float | None:
    """``value`` as a finite float (a number, or text that reads as one), else None."""
    if isinstance(value, bool):
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


def _one_spectrum(path, dim: str) -> xr.Dataset:
    """The one spectrum of file ``path``; a file of several is a `DataError` naming it."""
    ds = load(path)
    extra = [d for d in ds["Z"].dims if d != "frequency"]
    if extra:
        held = " × ".join(str(ds.sizes[d]) for d in extra)
        raise DataError(
            f"holds {held} spectra (over {', '.join(extra)}); a stack takes one spectrum per file: export each to a file of its own "
            f"(impedax inspect FILE --select {extra[0]}=LABEL --out ONE.csv), or fit this file as it is",
            path=path,
        )
    if dim in ds.coords:  # (a scalar coordinate the reader set, e.g. a cycle number)
        ds = ds.drop_vars(dim)
    return ds


def _check_grid(f: np.ndarray, f0: np.ndarray, path, first_path: str) -> None:
    """`DataError` naming ``path`` unless its sorted frequencies ``f`` [Hz] are the first file's
    ``f0`` within `SWEEP_RTOL`."""
    if f.shape == f0.shape and np.all(np.abs(f / f0 - 1) <= SWEEP_RTOL):
        return
    n = min(f.size, f0.size)
    bad = np.flatnonzero(np.abs(f[:n] / f0[:n] - 1) > SWEEP_RTOL)
    if bad.size:
        where = f"first differing at {f[bad[0]]:.6g} Hz where {Path(first_path).name} has {f0[bad[0]]:.6g} Hz"
    else:
        where = f"the first {n} frequencies agree, then {'this file' if f.size > f0.size else Path(first_path).name} goes on"
    raise DataError(
        f"its frequency grid differs from {first_path}'s ({f.size} vs {f0.size} points, {where}); "
        f"spectra stack only on one grid (within {SWEEP_RTOL:.1%}): measure them so, or fit the files one by one",
        path=path,
    )
