"""Lossless netCDF files (scipy's netCDF3 engine; no HDF5 library needed).

netCDF3 has no complex type: each complex variable V is stored as ``V__real`` and
``V__imag`` and joined again on reading; non-scalar attrs are stored as JSON text; int64
arrays are stored as int32 or float64 with their dtype restored on reading. A variable of no
values whose zero-length dimension netCDF3 cannot hold (it has one such dimension, the record
dimension, and only first in each variable) is stored as a scalar marked ``impedax_empty`` (its
dimensions and their lengths) and made again on reading.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

from .atomic import atomic_path
from ..errors import IN_MEMORY, ArgumentNeeded, DataError

__all__ = ["read_netcdf", "write_netcdf", "result_dataset", "NETCDF_ADVICE", "encode_dataset", "decode_dataset", "saved_result", "saved_source", "damaged_result", "result_kind", "not_a_spectrum", "NETCDF_FORMAT"]

_JSON = "json:"
# magic (4 bytes), record count (4), then the dimension, attribute and variable lists (8 each)
_NETCDF3_HEADER_BYTES = 32


def _encode_attrs(attrs, owner: str = "the dataset") -> dict:
    """``attrs`` as netCDF3 stores them; a value it cannot hold (an arbitrary object, a
    complex number) is a `DataError` naming the attribute and ``owner``."""
    out = {}
    for k, v in attrs.items():
        v = bool(v) if isinstance(v, np.bool_) else v
        if isinstance(v, bool) or v is None or isinstance(v, (dict, list, tuple)):
            try:
                out[k] = _JSON + json.dumps(v)
            except (TypeError, ValueError, RecursionError):
                raise DataError(_unstorable(k, v, owner)) from None
        elif isinstance(v, (np.integer, int)) and not np.iinfo(np.int32).min <= int(v) <= np.iinfo(np.int32).max:
            out[k] = float(v)
        elif isinstance(v, (str, bytes, int, float, np.integer, np.floating)) or (isinstance(v, np.ndarray) and v.dtype.kind not in "cOV"):
            out[k] = v
        else:  # (xarray's TypeError, or scipy's, would name neither the file nor what to do)
            raise DataError(_unstorable(k, v, owner))
    return out


def _unstorable(key, value, owner: str) -> str:
    from ..arguments import shown

    return (f"attribute {shown(key)} of {owner} is {shown(value)} ({type(value).__name__}), which a netCDF file cannot hold; "
            "make it text, a number or a list of them (or drop it) before saving")


def _decode_attrs(attrs) -> dict:
    out = {}
    for k, v in attrs.items():
        if isinstance(v, str) and v.startswith(_JSON):
            try:
                v = json.loads(v[len(_JSON):])
            except RecursionError:
                raise DataError(f"attribute {k!r}: its JSON text is nested too deeply to be impedax's") from None
            except ValueError as exc:
                raise DataError(f"attribute {k!r}: its 'json:' text is not valid JSON ({exc.msg} at character {exc.pos})") from None
        out[k] = v
    return out


def _encode_array(da: xr.DataArray, name: str = "") -> dict[str, xr.DataArray]:
    attrs = _encode_attrs(da.attrs, f"variable {name!r}")
    if np.iscomplexobj(da.values):
        return {
            "__real": da.real.assign_attrs({**attrs, "impedax_part": "real"}),
            "__imag": da.imag.assign_attrs({**attrs, "impedax_part": "imag"}),
        }
    if da.dtype == np.int64 or da.dtype == np.uint64 or da.dtype == bool:
        fits = da.size == 0 or (da.min() >= np.iinfo(np.int32).min and da.max() <= np.iinfo(np.int32).max)
        kind = "bool" if da.dtype == bool else str(da.dtype)
        return {"": da.astype(np.int32 if fits else np.float64).assign_attrs({**attrs, "impedax_dtype": kind})}
    return {"": da.assign_attrs(attrs)}


_EMPTY = "impedax_empty"  # (a variable of no values stored as a scalar: its [[dimension, length], ...])


def _empty_placeholder(da: xr.DataArray, name) -> dict[str, xr.DataArray]:
    """A variable of no values as a scalar that netCDF3 can hold, marked with its dimensions and
    lengths (`_EMPTY`) and dtype. Written as it is, a KK batch's bad bands, (cell, band) with no
    band in any cell, would make a file no reader opens: band is taken as the record dimension,
    second in the variable."""
    attrs = _encode_attrs({**da.attrs, _EMPTY: [[str(d), int(n)] for d, n in zip(da.dims, da.shape)]}, f"variable {name!r}")
    return {"": xr.DataArray(np.float64(0.0), attrs={**attrs, "impedax_dtype": str(da.dtype)})}


def encode_dataset(ds: xr.Dataset) -> xr.Dataset:
    """A netCDF3-storable copy of ``ds`` (see module docstring)."""
    empty_dims = [d for d, n in ds.sizes.items() if n == 0]

    def encoded(da: xr.DataArray, name) -> dict[str, xr.DataArray]:
        record = len(empty_dims) == 1 and da.dims[:1] == (empty_dims[0],)  # (netCDF3's one record dimension, first)
        if da.size == 0 and not record:
            return _empty_placeholder(da, name)
        return _encode_array(da, name)

    data_vars, coords = {}, {}
    for name, da in ds.coords.items():
        for suffix, part in encoded(xr.DataArray(da.variable), name).items():
            coords[name + suffix] = part.variable
    for name, da in ds.data_vars.items():
        for suffix, part in encoded(da, name).items():
            data_vars[name + suffix] = part.variable
    return xr.Dataset(data_vars, coords=coords, attrs=_encode_attrs(ds.attrs))


def _unmarked_part(ds: xr.Dataset, name) -> str | None:
    """``"real"`` or ``"imag"`` for a variable ``V__real`` or ``V__imag`` that another program
    wrote without impedax's ``impedax_part`` mark, when its partner is there and ``V`` is not
    (plain xarray following the layout above); else None, the variable kept as it is. Without it
    such a file would say "dataset has no variable 'Z'" whatever else is wrong."""
    name = str(name)
    for part, other in (("real", "imag"), ("imag", "real")):
        if name.endswith(f"__{part}"):
            base = name[: -len(part) - 2]
            partner = ds.variables.get(f"{base}__{other}")
            if base and base not in ds.variables and partner is not None and "impedax_part" not in partner.attrs:
                return part
    return None


def decode_dataset(ds: xr.Dataset) -> xr.Dataset:
    """Inverse of `encode_dataset` (the file it was read from kept in ``encoding["source"]``)."""
    out = xr.Dataset(attrs=_decode_attrs(ds.attrs))
    coords = {}
    for name in list(ds.coords) + list(ds.data_vars):
        var = ds[name].variable
        attrs = dict(var.attrs)
        part = attrs.pop("impedax_part", None) or _unmarked_part(ds, name)
        dtype = attrs.pop("impedax_dtype", None)
        attrs = _decode_attrs(attrs)
        empty = attrs.pop(_EMPTY, None)
        if empty is not None:  # (`_empty_placeholder`)
            try:
                dims, shape = zip(*[(str(d), int(n)) for d, n in empty]) if empty else ((), ())
                values = np.empty(shape, dtype=np.dtype(dtype or "float64"))
            except (TypeError, ValueError):
                raise DataError(f"variable {name!r}: its {_EMPTY} attribute {empty!r} is not a list of [dimension, length] pairs with a dtype") from None
            if values.size:
                raise DataError(f"variable {name!r}: its {_EMPTY} attribute gives {values.size} values where it marks a variable of none")
            new = xr.Variable(dims, values, attrs)
            if name in ds.coords:
                coords[name] = new
            else:
                out[name] = new
            continue
        if part == "imag":
            continue
        if part == "real":
            base = name[: -len("__real")]
            if base + "__imag" not in ds.variables:
                raise DataError(f"{base}__real has no {base}__imag partner")
            imag = ds[base + "__imag"].variable
            if imag.dims != var.dims or imag.shape != var.shape:
                # never broadcast: a one-element imaginary part is a damaged file, not Z'' everywhere
                raise DataError(f"{base}__real has shape {dict(zip(var.dims, var.shape))} but {base}__imag has {dict(zip(imag.dims, imag.shape))}")
            values = var.values + 1j * imag.values
            new = xr.Variable(var.dims, values, attrs)
            name = base
        else:
            values = var.values
            if dtype is not None:
                values = values.astype(bool if dtype == "bool" else dtype)
            new = xr.Variable(var.dims, values, attrs)
        if name in ds.coords or (part == "real" and name + "__real" in ds.coords):
            coords[name] = new
        else:
            out[name] = new
    out = out.assign_coords(coords)
    if ds.encoding.get("source"):  # (results' from_xarray name the file in their errors)
        out.encoding["source"] = ds.encoding["source"]
    return out


# a saved result's ``impedax_kind`` → what it is and the call that reads it (`saved_result`)
RESULT_KINDS = {
    "fit": ("least-squares fit", "FitResult.from_xarray"),
    "batch_fit": ("batch of least-squares fits", "BatchFitResult.from_xarray"),
    "shared_fit": ("joint (shared-parameter) fit", "SharedFitResult.from_xarray"),
    "posterior": ("single-spectrum posterior", "Posterior.from_xarray"),
    "shared_posterior": ("joint (shared-parameter) posterior", "SharedPosterior.from_xarray"),
    "hierarchical_posterior": ("hierarchical posterior", "HierarchicalPosterior.from_xarray"),
    "gap_analysis": ("gap analysis result (impedax gap)", "impedax.io.read_netcdf"),
    # (their spectrum is the kept points' data; the fit inside them is read with the call named)
    "refinement": ("refinement (impedax refine) with its final fit", "Refinement.final_fit_of"),
    "diagnosis": ("diagnosis (impedax diagnose) with its baseline fit", "Diagnosis.baseline_of"),
    "comparison": ("comparison of models on one spectrum (impedax compare)", "impedax.io.read_netcdf"),
    "batch_comparison": ("comparison of models over many spectra (impedax compare)", "BatchComparison.from_xarray"),
    # (these hold Z and would be shown as plain spectra; their data are the spectra tested)
    "kk": ("Kramers-Kronig test (impedax kk)", "impedax.io.read_netcdf"),
    "zhit": ("Z-HIT test (impedax kk --method zhit)", "impedax.io.read_netcdf"),
    "drt": ("distribution of relaxation times (impedax drt)", "impedax.io.read_netcdf"),
}


NETCDF_ADVICE = "netcdf"
"""The attribute of a result's ``to_xarray`` Dataset that names the calls writing and reading it
(`result_dataset`): ``ds.to_netcdf(path)``'s error quotes it."""


class _WrittenByImpedax(dict):
    """A dict attribute of a result's ``to_xarray`` Dataset: equal to the dict and printed as it
    (``str``, the Dataset's display), but its repr, which xarray quotes when ``ds.to_netcdf``
    refuses the first attribute netCDF cannot hold, says how such a Dataset is written."""

    def __repr__(self) -> str:
        return (f"{dict.__repr__(self)} (impedax: netCDF holds neither complex values nor dict attributes; "
                "write this Dataset with impedax.write_result(ds, path) or impedax.io.write_netcdf(ds, path))")

    __str__ = dict.__repr__


def _call(kind: str | None, name: str) -> str:
    """The call that reads back a saved result of ``kind`` from the file ``name``, as typed in a session."""
    if kind not in RESULT_KINDS:
        return f"impedax.io.read_netcdf({name!r})"
    call = reader_call(kind).replace("(path)", f"({name!r})")
    return call if call.startswith("impedax.") else "impedax." + call


def _refused_by_to_netcdf(ds: xr.Dataset) -> bool:
    """Whether xarray's ``to_netcdf`` (netCDF3 or netCDF4: no complex type, attributes numbers,
    text or lists of numbers) refuses ``ds``: a complex variable, or an attribute that is a dict,
    None or a list holding anything but numbers (a list of texts fails deep in the engine)."""
    def refused(value) -> bool:
        if isinstance(value, (list, tuple)):
            return not all(isinstance(v, (int, float, np.number)) and not isinstance(v, complex) for v in value)
        return value is None or isinstance(value, (dict, complex, np.complexfloating))

    return any(v.dtype.kind == "c" for v in ds.variables.values()) or any(
        refused(v) for attrs in (ds.attrs, *(var.attrs for var in ds.variables.values())) for v in attrs.values())


def result_dataset(ds: xr.Dataset) -> xr.Dataset:
    """A result's ``to_xarray`` Dataset as handed out (every result's, so all alike): when
    ``ds.to_netcdf`` cannot write it (`_refused_by_to_netcdf`: complex spectra, dict or text-list
    attributes), its first attribute is `NETCDF_ADVICE`, a dict naming the calls that write
    and read it (``impedax.write_result(result, 'kk.nc')``, ``impedax.io.read_netcdf('kk.nc')``), and
    each dict attribute (it included) is one whose repr says why (`_WrittenByImpedax`): xarray
    checks attributes before values and quotes the first it refuses, so its TypeError names
    impedax.write_result whichever engine is used. A Dataset it can write (a comparison's
    criteria) is left as it is. The attribute is written to the file, where it names the
    reading call; the results' ``from_xarray`` leave it out (`saved_result`)."""
    attrs = {k: v for k, v in ds.attrs.items() if k != NETCDF_ADVICE}
    if _refused_by_to_netcdf(ds):
        kind = attrs.get("impedax_kind")
        name = f"{kind if kind in RESULT_KINDS else 'result'}.nc"
        write = f"impedax.write_result(result, {name!r}) or impedax.write_result(ds, {name!r})" if kind in RESULT_KINDS else f"impedax.write_result(ds, {name!r})"
        attrs = {NETCDF_ADVICE: {"write": write, "read": _call(kind, name)}, **attrs}
    out = ds.copy(deep=False)
    out.attrs = {k: _WrittenByImpedax(v) if isinstance(v, dict) else v for k, v in attrs.items()}
    return out


NETCDF_FORMAT = "impedax netCDF"
"""The ``format`` of data read from an impedax netCDF file (`formats.netcdf.READER`); the format
its data were first read from, if another, is kept as ``data_format`` (`loader.load`)."""


def result_kind(ds: xr.Dataset) -> str | None:
    """The `RESULT_KINDS` key of a saved result that holds no spectrum, or None: its
    ``impedax_kind``, or for a gap analysis written before it carried one, its attrs."""
    kind = ds.attrs.get("impedax_kind")
    if kind in RESULT_KINDS:
        return kind
    if "paper_gap_um" in ds.attrs and "median" in ds.variables and "branch" in ds.dims:
        return "gap_analysis"
    return None


def not_a_spectrum(ds: xr.Dataset) -> str | None:
    """For a saved result read where a spectrum is expected (``impedax.load``): what the file
    holds and the call that reads it; None for anything else."""
    kind = result_kind(ds) if "Z" not in ds.variables else None
    if kind is None:
        return None
    return f"this file holds a {RESULT_KINDS[kind][0]}, not a spectrum; read it with {reader_call(kind)}"


def reader_call(kind: str) -> str:
    """The call that reads a saved result of ``kind`` (a `RESULT_KINDS` key) from ``path``."""
    call = RESULT_KINDS[kind][1]
    return call + "(path)" if call == "impedax.io.read_netcdf" else f"{call}(impedax.io.read_netcdf(path))"


def saved_result(ds, kind: str, *, variables=(), attrs=()) -> xr.Dataset:
    """``ds`` (a result's ``to_xarray``, as read or as stored) decoded, once it is a saved result
    of ``kind`` with every one of ``variables`` (or those ``variables(attrs)`` names) and
    ``attrs``; otherwise one `DataError` naming the file (``encoding["source"]``) and what is
    missing or which reader it needs."""
    what = RESULT_KINDS[kind][0]
    if not isinstance(ds, xr.Dataset):
        raise DataError(f"from_xarray takes an xarray.Dataset, got {type(ds).__name__}")
    source = ds.encoding.get("source")
    try:
        ds = decode_dataset(ds)
    except DataError as exc:
        raise DataError(str(exc), path=source if exc.path is None else exc.path) from None
    found = ds.attrs.get("impedax_kind")
    if found != kind:
        if found in RESULT_KINDS:
            raise DataError(f"a saved {RESULT_KINDS[found][0]}, not a {what}: read it with {RESULT_KINDS[found][1]}", path=source)
        raise DataError(f"not a saved impedax {what} (impedax_kind {found!r}, expected {kind!r})", path=source)
    missing = [repr(k) for k in (variables(ds.attrs) if callable(variables) else variables) if k not in ds.variables]
    missing_attrs = [repr(k) for k in attrs if k not in ds.attrs]
    if missing or missing_attrs:
        parts = ([f"variable(s) {', '.join(missing)}"] if missing else []) + ([f"attribute(s) {', '.join(missing_attrs)}"] if missing_attrs else [])
        raise DataError(f"incomplete saved {what}: missing {' and '.join(parts)}", path=source)
    from .provenance import PROVENANCE_ATTRS

    if any(k in ds.attrs for k in (*PROVENANCE_ATTRS, NETCDF_ADVICE)):  # (what made the file and how to write it, not part of the result: a result written again records its own)
        ds = ds.copy(deep=False)
        ds.attrs = {k: v for k, v in ds.attrs.items() if k not in (*PROVENANCE_ATTRS, NETCDF_ADVICE)}
    return ds


def saved_source(ds: xr.Dataset) -> str | None:
    """Where a saved result's data came from, as `impedax.write_result` recorded it (the
    attribute ``source``), so that a result read back has the ``source`` it had: ``saved_from``
    when `impedax.load` read the file (it names the file read as ``source`` and keeps the one
    saved as ``saved_from``), else ``source``; None when neither is there or the data were
    built in memory (`IN_MEMORY`)."""
    source = ds.attrs.get("saved_from", ds.attrs.get("source"))
    return str(source) if source not in (None, "", IN_MEMORY) else None


class damaged_result:
    """``with damaged_result(kind, ds):`` turns what rebuilding a checked saved result raises on
    inconsistent content (KeyError, ValueError, ...) into one `DataError` naming the file."""

    def __init__(self, kind: str, ds: xr.Dataset):
        self.what, self.source = RESULT_KINDS[kind][0], ds.encoding.get("source")

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if isinstance(exc, DataError) and exc.path is not None or isinstance(exc, ArgumentNeeded):  # (an argument the call lacks: not damage)
            return False
        symbol = getattr(exc, "unknown_symbol", None)
        if symbol is not None:  # (a user's element, read without its registry: not damage either)
            where = f"{self.source}: " if self.source else ""
            raise ArgumentNeeded(
                f"{where}the saved {self.what} uses element {symbol!r}, which is not in the registry: "
                "pass the registry that declares it (registry=)"
            ) from None
        if isinstance(exc, (KeyError, ValueError, TypeError, IndexError, AttributeError)):  # (impedax's own errors are ValueErrors)
            detail = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
            raise DataError(f"damaged saved {self.what}: {detail}", path=self.source) from None
        return False


def write_netcdf(ds: xr.Dataset, path: str | Path) -> None:
    """Write ``ds`` to ``path`` atomically, complex values and attrs preserved."""
    try:
        encoded = encode_dataset(ds)
    except DataError as exc:
        raise DataError(exc.detail, path=path) from None
    with atomic_path(path) as tmp:
        encoded.to_netcdf(tmp, engine="scipy", format="NETCDF3_64BIT")


def read_netcdf(path: str | Path) -> xr.Dataset:
    """Read a netCDF file written by `write_netcdf` (complex variables joined, shapes checked)."""
    from ._common import check_file

    path = Path(path)
    size = check_file(path)
    if size < _NETCDF3_HEADER_BYTES:
        with open(path, "rb") as fh:
            signed = fh.read(3) == b"CDF"
        what = "truncated netCDF file" if signed else "not a readable netCDF file"
        raise DataError(f"{what}: {size} bytes, less than a netCDF header", path=path)
    try:
        with xr.open_dataset(path, engine="scipy", mmap=False) as raw:  # read, not mapped: closed cleanly when decoding fails
            ds = decode_dataset(raw.load())
        ds.encoding["source"] = str(path)
        if "Z" in ds.variables and "impedax_kind" not in ds.attrs:  # (a spectrum, not a saved result)
            # a spectrum's errors name the file it is read from, not where it came from before
            # it was saved ("memory" for one built in a session); that stays as ``saved_from``
            saved = ds.attrs.get("source")
            if saved is not None and str(saved) != str(path):
                ds.attrs["saved_from"] = saved
            ds.attrs["source"] = str(path)
    except DataError as exc:
        raise DataError(str(exc), path=path) from None
    except (OSError, ValueError, TypeError, IndexError, KeyError, AttributeError, OverflowError, MemoryError, RecursionError) as exc:
        # the engine's own text spans several lines and suggests libraries impedax does not use
        detail = (str(exc).strip().splitlines() or [type(exc).__name__])[0].replace(str(path), "the file")[:120]
        raise DataError(f"not a readable netCDF file, damaged or truncated ({detail}); impedax reads the netCDF3 files that impedax save writes", path=path) from None
    # (a spectrum's dimensions only: a saved KK test with no bad band has a band dimension of length 0)
    empty = [f"{name!r}" for name in (ds["Z"].dims if "Z" in ds.variables else ()) if ds.sizes[name] == 0]
    if empty:
        raise DataError(f"dimension {', '.join(empty)} has length 0: the file holds no spectrum", path=path)
    return ds
