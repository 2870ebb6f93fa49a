"""Results out in the formats people share: a tidy CSV table, JSON and netCDF (docs/io.md,
"Exporting results").

A result (`FitResult`, `BatchFitResult`, `Posterior`, `Diagnosis`, ...) offers its own
``to_table()`` (tidy rows: one parameter per row, one row per spectrum and parameter for
batches), ``summary()`` (the CLI's JSON) and ``to_xarray()`` (lossless); this module only writes
them, atomically, in the format the file's extension names. It does not import the results'
types (io sits below fitting): any object with these methods can be written.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from .atomic import atomic_path, check_file_name, check_writable
from ..arguments import checked_arguments, shown
from ..errors import IN_MEMORY, DataError, ParameterError

__all__ = ["RESULT_FORMATS", "written_result", "result_format", "result_table", "result_source", "write_result", "write_table", "write_json", "to_jsonable"]

# extension → format of `write_result` (what each writes: docs/io.md)
RESULT_FORMATS = {".csv": "csv", ".json": "json", ".nc": "netcdf"}


# the results whose .csv or .json `written_result` recognises: (what the file holds, the call that
# reads its .nc back), by the columns of the CSV (`result_table`) and the keys of the JSON
# (``summary()``) their writers give them (docs/io.md, "Exporting results")
_FIT = ("a least-squares fit", "fit", "ix.FitResult.from_xarray(ix.load({nc}))")
_BATCH = ("a batch of least-squares fits", "fit", "ix.BatchFitResult.from_xarray(ix.load({nc}))")
_POSTERIOR = ("a posterior", "sample", "ix.Posterior.from_xarray(ix.load({nc}))")
_DIAGNOSIS = ("a diagnosis", "diagnose", "ix.Diagnosis.baseline_of(ix.load({nc})) (its baseline fit)")
_REFINEMENT = ("a refinement", "refine", "ix.Refinement.final_fit_of(ix.load({nc})) (its final fit)")
_DRT = ("a DRT (γ over τ)", "drt", "xarray.open_dataset({nc})")
_KK = ("a Kramers–Kronig test", "kk", "xarray.open_dataset({nc})")
_DRT_BATCH = ("a batch of DRTs (γ over τ)", "drt", "xarray.open_dataset({nc})")
_KK_BATCH = ("a batch of Kramers–Kronig tests", "kk", "xarray.open_dataset({nc})")
# (unrecognised, these would be told "no frequency column in header ['{']")
_ZHIT = ("a Z-HIT test", "kk --method zhit", "ix.io.read_netcdf({nc})")
_ZHIT_BATCH = ("a batch of Z-HIT tests", "kk --method zhit", "ix.io.read_netcdf({nc})")
_COMPARISON = ("a comparison of models on one spectrum", "compare", "ix.io.read_netcdf({nc})")
_BATCH_COMPARISON = ("a comparison of models over many spectra", "compare", "ix.BatchComparison.from_xarray(ix.load({nc}))")


def _table_kind(header: Sequence[str], command: str | None) -> tuple[str, str, str] | None:
    """What a result CSV with these columns holds (``command``: its provenance column's value)."""
    if {"tau_s", "gamma_ohm"} <= set(header):
        return _DRT
    if {"frequency_hz", "modulus_zhit_ohm", "residual_modulus"} <= set(header):
        return _ZHIT if header[0] == "frequency_hz" else _ZHIT_BATCH  # (a batch's: a column per dimension first)
    if {"model", "label", "n_params", "aic", "delta_aic"} <= set(header):
        return _COMPARISON
    if {"model", "circuit", "best", "aic", "delta_aic"} <= set(header):  # (a row per spectrum and model, its labels first)
        return _BATCH_COMPARISON
    if {"section", "name", "value"} <= set(header):  # (candidate columns only when there are candidates)
        return _DIAGNOSIS
    if {"name", "median", "q05", "q95"} <= set(header):
        return _POSTERIOR
    if {"name", "value", "stderr", "unit", "fixed"} <= set(header):
        if header[0] != "name":  # (a batch's table: a column per extra dimension first)
            return _BATCH
        return _REFINEMENT if command == "impedax refine" else _FIT
    return None


def _summary_kind(summary: Mapping) -> tuple[str, str, str] | None:
    """What a result JSON with these top-level keys holds."""
    keys = set(summary)
    spectra = summary.get("spectra")
    if {"n_spectra", "spectra"} <= keys and isinstance(spectra, list) and spectra and isinstance(spectra[0], dict):
        # a batch of DRTs or KK tests: each spectrum's summary as a single one's (a batch of fits has its params at the top)
        if _summary_kind(spectra[0]) is _DRT:
            return _DRT_BATCH
        if _summary_kind(spectra[0]) is _KK:
            return _KK_BATCH
        if _summary_kind(spectra[0]) is _ZHIT:
            return _ZHIT_BATCH
    if {"models", "ranked_by", "n_spectra"} <= keys:
        return _BATCH_COMPARISON
    if {"models", "best", "ranked_by"} <= keys:
        return _COMPARISON
    if summary.get("method") == "zhit" and {"modulus_zhit_ohm", "residuals_modulus"} <= keys:
        return _ZHIT
    if {"tau_s", "gamma_ohm", "peaks"} <= keys:
        return _DRT
    if {"mu", "n_rc", "bad_bands"} <= keys:
        return _KK
    if {"final_model", "steps", "verdict"} <= keys:
        return _REFINEMENT
    if {"baseline", "kk"} <= keys:
        return _DIAGNOSIS
    if {"model", "params", "acceptance"} <= keys:
        return _POSTERIOR
    if {"model", "params", "n_spectra"} <= keys:
        return _BATCH
    if {"model", "params", "n_points", "rms_rel"} <= keys:
        return _FIT
    return None


def written_result(path: str | Path, head: str) -> str | None:
    """For a result's ``.csv`` or ``.json`` (`write_result`, ``--out``) read where a spectrum is
    expected (`impedax.load`): what it holds and that its ``.nc`` is the form that reads back,
    with the call; None for any other file. ``head``: the file's first bytes as text (a JSON file
    is read whole, up to `_common.max_file_bytes`). A walkthrough's ``ix.load("fit.csv")`` was told
    "not a recognised spectrum file … no frequency column"."""
    from ._common import max_file_bytes

    path = Path(path)
    kind = None
    if head.lstrip().startswith("{"):
        try:
            if path.stat().st_size <= max_file_bytes():
                summary = json.loads(path.read_text(encoding="utf-8"))
                kind = _summary_kind(summary) if isinstance(summary, dict) else None
        except (OSError, ValueError):
            return None
    else:
        # (lines split as Python splits them: a bare carriage return ends a line here as in the
        # readers, where the csv module would stop at it with "new-line character seen")
        rows = list(csv.reader(head.splitlines()))
        if len(rows) >= 2:  # (the header and a whole first row, for the provenance column)
            header, first = [cell.strip() for cell in rows[0]], rows[1]
            command = first[header.index("command")] if "command" in header and header.index("command") < len(first) else None
            kind = _table_kind(header, command)
    if kind is None:
        return None
    what, command, call = kind
    nc = path.with_suffix(".nc")
    if nc.is_file():
        reload = f"the form that reads back is the .nc beside it: {call.format(nc=repr(str(nc)))}"
    else:
        name = f"{command.split()[0]}.nc"  # ("kk --method zhit": kk.nc)
        reload = (f"the form that reads back is a .nc: write the result with ix.write_result(result, {name!r}) "
                  f"(impedax {command} --out {name}), then {call.format(nc=repr(name))}")
    return f"this file is the {path.suffix.lstrip('.').upper()} summary of {what} (write_result, impedax {command} --out), not a spectrum: it is to read, not to load back; {reload}"


def result_format(path: str | Path, formats: Mapping[str, str] = RESULT_FORMATS) -> str:
    """The format named by ``path``'s extension (case-insensitive); `DataError` naming the
    known extensions otherwise (checked before any work is done); a name that names a folder
    (``out/``, `check_file_name`) is refused first."""
    check_file_name(path, f"result{next(iter(formats), '.json')}")
    suffix = Path(path).suffix.lower()
    if suffix not in formats:
        known = ", ".join(formats)
        raise DataError(f"unknown output extension {suffix or '(none)'!r}: use one of {known}", path=path)
    return formats[suffix]


def result_table(result) -> list[dict[str, object]]:
    """The tidy rows of ``result`` (its ``to_table()``): one dict per row, same keys in every row."""
    to_table = getattr(result, "to_table", None)
    if to_table is None:
        raise DataError(f"{type(result).__name__} has no table of parameters; write it as .json or .nc")
    return to_table()


def to_jsonable(obj):
    """``obj`` with numpy scalars and arrays as Python values and NaN/±Inf as None (strict JSON)."""
    if isinstance(obj, Mapping):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind in "fiub" and (obj.dtype.kind != "f" or np.isfinite(obj).all()):
            return obj.tolist()  # (already JSON values: no walk element by element)
        return [to_jsonable(v) for v in obj.tolist()]
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, (np.floating, float)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


def table_cell(value) -> str:
    """One CSV cell: floats in their shortest exact form (``repr``), booleans as true/false,
    None and NaN as an empty cell."""
    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (float, np.floating)):
        return "" if math.isnan(value) else repr(float(value))
    if isinstance(value, np.integer):
        return str(int(value))
    return str(value)


def write_table(rows: Sequence[Mapping[str, object]], path: str | Path) -> None:
    """Write ``rows`` as CSV (a header line of the keys in order of first appearance, then one
    line per row; a key missing from a row is an empty cell), atomically."""
    columns: dict[str, None] = {}
    for row in rows:
        columns.update(dict.fromkeys(row))
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for row in rows:
        writer.writerow([table_cell(row.get(c)) for c in columns])
    with atomic_path(path) as tmp:
        tmp.write_text(buffer.getvalue(), encoding="utf-8")


def write_json(obj, path: str | Path) -> None:
    """Write ``obj`` as strict JSON (`to_jsonable`), atomically."""
    text = json.dumps(to_jsonable(obj), indent=2, allow_nan=False) + "\n"
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def is_result(obj) -> bool:
    """Whether ``obj`` is something `write_result` writes (a result with a summary or a dataset)."""
    return callable(getattr(obj, "summary", None)) or callable(getattr(obj, "to_xarray", None))


def _required_arguments(method) -> list[str]:
    """The arguments ``method`` cannot be called without (none for anything not callable)."""
    import inspect

    if not callable(method):
        return []
    try:
        signature = inspect.signature(method)
    except (TypeError, ValueError):
        return []
    return [p.name for p in signature.parameters.values() if p.default is p.empty and p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]


def result_source(result) -> str | None:
    """Where a result's data came from, as the result knows it (its ``source``: `FitResult`,
    `BatchFitResult`, a comparison of fits of one data, ...), or None (data built in memory,
    `IN_MEMORY`, or a result that keeps no source)."""
    source = getattr(result, "source", None)
    return source if isinstance(source, str) and source not in ("", IN_MEMORY) else None


@checked_arguments()
def write_result(result, path: str | Path, *, source: str | None = None, provenance: Mapping[str, object] | None = None) -> None:
    """Write ``result`` in the format of ``path``'s extension: ``.csv`` the tidy table
    (`result_table`), ``.json`` its ``summary()``, ``.nc`` its ``to_xarray()`` (lossless
    netCDF, `write_netcdf`). Atomic: the file is whole or not there. Anything but a result
    (a dict, None, a spectrum Dataset) is a `ParameterError` saying what to pass; a result's
    ``to_xarray`` Dataset (as its ``ds.to_netcdf`` error advises: its ``impedax_kind`` or
    `netcdf.NETCDF_ADVICE` attribute marks it) is written as the result would be, to ``.nc`` only; a path that
    cannot be written is a `DataError` naming it, raised before the result is converted
    (`check_writable`). A model whose ``to_xarray`` needs arguments (`MeyerModel`: the
    frequencies) is a `ParameterError` saying to write ``impedax.io.write_netcdf(m.to_xarray(freq), path)``.
    ``source`` (where the data came from: ``path [cycle=3]``; by default the result's own
    ``source``, its data's ``attrs["source"]``, as `impedax.load` sets it: `result_source`) is
    added to the JSON as the key ``source`` and to the netCDF as the attribute ``source``, unless
    the result's summary or dataset has its own, and is the provenance record's ``source``.
    ``provenance`` (`impedax.io.provenance.provenance`: version, command, settings, data, time)
    is the netCDF attributes of `provenance_attrs` (by default a record naming this version,
    ``source`` and now), and, only when given (the command line gives it), the JSON key
    ``provenance`` and the CSV columns of `provenance_columns` on every row (a JSON or CSV
    without it stays the result's own ``summary()``/table: docs/io.md, "Provenance")."""
    if isinstance(result, (str, os.PathLike)) and is_result(path):
        raise ParameterError(f"write_result takes (result, path); the arguments look swapped: got the path {shown(str(result))} first and a {type(path).__name__} second")
    if not isinstance(path, (str, os.PathLike)):
        raise ParameterError(f"write_result: path must be a file path (str or pathlib.Path), got {shown(path)} ({type(path).__name__})")
    kind = result_format(path)
    if _is_result_dataset(result):  # (a result's ``to_xarray``, perhaps edited: ds.to_netcdf's error names this call)
        if kind != "netcdf":
            raise ParameterError(f"a result's Dataset is written as .nc (lossless); for {Path(path).suffix.lower()} pass the result itself: impedax.write_result(result, {shown(str(path))})")
        check_writable(path)
        from .provenance import provenance as made

        if source is None:  # (the Dataset's own, as a result's `result_source`)
            saved = result.attrs.get("source")
            source = saved if isinstance(saved, str) and saved not in ("", IN_MEMORY) else None
        _write_dataset(result, path, source, dict(provenance) if provenance is not None else made(source=source))
        return
    if not is_result(result):
        got = "None" if result is None else type(result).__name__
        spectrum = "; a spectrum Dataset is written with impedax.save(data, path)" if hasattr(result, "data_vars") else ""
        raise ParameterError(f"write_result takes a result (FitResult, BatchFitResult, Comparison, Diagnosis, Refinement, Posterior, ...), got {got}{spectrum}")
    needs = _required_arguments(getattr(result, "to_xarray", None))
    if needs and not callable(getattr(result, "summary", None)):  # (a model, e.g. MeyerModel: its dataset is over frequencies the caller picks)
        name, given = type(result).__name__, ", ".join(needs)
        raise ParameterError(f"a {name} has a dataset only at a given {given}: save m.to_xarray({given}) with impedax.io.write_netcdf(m.to_xarray({given}), path)")
    check_writable(path)
    from .provenance import PROVENANCE_KEY, provenance_attrs, provenance_columns
    from .provenance import provenance as made

    source = result_source(result) if source is None else source
    record = dict(provenance) if provenance is not None else made(source=source)
    if kind == "csv":
        rows = result_table(result)
        if provenance is not None:
            columns = provenance_columns(record)
            rows = [{**row, **{k: v for k, v in columns.items() if k not in row}} for row in rows]
        write_table(rows, path)
    elif kind == "json":
        if not callable(getattr(result, "summary", None)):
            raise DataError(f"{type(result).__name__} has no summary; write it as .nc")
        summary = result.summary()
        if source is not None and "source" not in summary:
            summary = {**summary, "source": source}
        write_json({**summary, PROVENANCE_KEY: record} if provenance is not None else summary, path)
    else:
        if not callable(getattr(result, "to_xarray", None)):
            raise DataError(f"{type(result).__name__} has no dataset; write it as .json")
        _write_dataset(result.to_xarray(), path, source, record)


def _is_result_dataset(obj) -> bool:
    """Whether ``obj`` is a result's ``to_xarray`` Dataset (its ``impedax_kind`` a saved result's,
    or the attribute `netcdf.result_dataset` gives a Dataset ``to_netcdf`` cannot write)."""
    from .netcdf import NETCDF_ADVICE, RESULT_KINDS

    attrs = getattr(obj, "attrs", None)
    return hasattr(obj, "data_vars") and isinstance(attrs, Mapping) and (attrs.get("impedax_kind") in RESULT_KINDS or NETCDF_ADVICE in attrs)


def _write_dataset(ds, path, source: str | None, record: Mapping[str, object]) -> None:
    """A result's Dataset to ``path`` (`write_netcdf`) with ``source`` (unless it has its own)
    and the provenance ``record`` as attributes (`write_result`); the Dataset given is not changed."""
    from .netcdf import write_netcdf
    from .provenance import provenance_attrs

    ds = ds.assign_attrs({"source": source} if source is not None and "source" not in ds.attrs else {})
    write_netcdf(ds.assign_attrs(provenance_attrs(record)), path)
