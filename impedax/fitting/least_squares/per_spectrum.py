"""Fixed and starting values that differ between the spectra of a batch: ``fit(...,
fixed={"C_EP": DataArray over material})``, one value per spectrum (docs/fitting.md, "Batch
fits"). The spectra are fitted in groups that share every such value (one group per label along
the DataArray's dimensions), each group with plain numbers, and the groups' results joined along
those dimensions into one `BatchFitResult`, as if the batch solver had taken a value per spectrum.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Callable, Mapping

import numpy as np
import xarray as xr

from ...arguments import shown
from ...errors import IN_MEMORY, ParameterError
from .batch import BatchFitResult

__all__ = ["has_per_spectrum_values", "split_fits"]


def has_per_spectrum_values(*mappings) -> bool:
    """Whether any of ``mappings`` (``fixed``, ``init``; None or not a mapping: no) holds an
    xarray.DataArray with a dimension."""
    return any(isinstance(m, Mapping) and any(isinstance(v, xr.DataArray) and v.ndim for v in m.values()) for m in mappings)


def split_fits(fit: Callable, circuit, data: xr.Dataset, source: str, *, fixed, init, **options) -> BatchFitResult:
    """``fit(circuit, group, fixed=numbers, init=numbers, **options)`` of each group of the
    spectra of ``data`` that share every per-spectrum value of ``fixed`` and ``init`` (DataArrays
    over some of the data's extra dimensions, `aligned_values`), joined into one
    `BatchFitResult` over the data's dimensions (`joined`)."""
    extra = tuple(d for d in data["Z"].dims if d != "frequency")
    fixed = {n: aligned_values(v, data, extra, f"fixed[{n!r}]", source) for n, v in (fixed or {}).items()}
    init = None if init is None else {n: aligned_values(v, data, extra, f"init[{n!r}]", source) for n, v in init.items()}
    over = tuple(d for d in extra if any(isinstance(v, xr.DataArray) and d in v.dims for v in (*fixed.values(), *(init or {}).values())))
    sizes = [data.sizes[d] for d in over]
    parts = []
    for index in np.ndindex(*sizes):
        where = dict(zip(over, index))

        def number(value):
            return float(value.isel({d: i for d, i in where.items() if d in value.dims})) if isinstance(value, xr.DataArray) else value

        group = data.isel({d: [i] for d, i in where.items()})  # (each dimension kept, of length 1: the group is a batch)
        parts.append(fit(circuit, group, fixed={n: number(v) for n, v in fixed.items()} or None, init=None if init is None else {n: number(v) for n, v in init.items()}, **options))
    return joined(parts, over, sizes)


def aligned_values(value, data: xr.Dataset, extra: tuple[str, ...], label: str, source: str):
    """``value`` as it is when a number; a DataArray over some of the data's extra dimensions
    ``extra`` with the data's labels along each (in any order; reordered as the data's), or over
    a dimension without labels of the same size and none of its own. Else a `ParameterError`
    naming ``label`` (``fixed['C_EP']``) and what differs."""
    if not isinstance(value, xr.DataArray):
        return value
    if not value.ndim:
        return float(value)
    where = f" of {source}" if source not in (None, "", "dataset", IN_MEMORY) else ""  # (the file, when the data came from one)
    unknown = [d for d in value.dims if d not in extra]
    if unknown:
        have = ", ".join(extra) if extra else "none: the data hold one spectrum"
        raise ParameterError(
            f"{label} is a DataArray over {', '.join(map(str, value.dims))}; one value per spectrum is over the data's extra dimensions "
            f"({have}){where}, and {', '.join(map(str, unknown))} is not one of them" + ("; one value per frequency is not a fit parameter" if "frequency" in unknown else "")
        )
    for d in value.dims:
        ours = data[d].values.tolist() if d in data.coords else None
        theirs = value[d].values.tolist() if d in value.coords else None
        if ours is None:
            if value.sizes[d] != data.sizes[d] or theirs is not None:
                raise ParameterError(f"{label}: the data{where} have {data.sizes[d]} spectra along {d} without labels; give {data.sizes[d]} values along {d} without coordinates, in the data's order")
            continue
        if theirs is None:
            raise ParameterError(f"{label} has no labels along {d}; the data's are {_text(ours)}: label it, e.g. xr.DataArray(values, dims={d!r}, coords={{{d!r}: data[{d!r}].values}})")
        missing = [v for v in ours if v not in theirs]
        alien = [v for v in theirs if v not in ours]
        if missing or alien or len(set(map(_key, theirs))) != len(theirs):
            said = "; ".join(part for part in (f"not in the data: {_text(alien)}" if alien else "", f"missing: {_text(missing)}" if missing else "") if part) or "its labels repeat"
            raise ParameterError(f"{label}: its labels along {d} ({_text(theirs)}) are not the data's ({_text(ours)}){where}: {said}; give one value for each spectrum, labelled as the data")
        value = value.sel({d: data[d].values})  # (the data's order)
    return value


def joined(parts: list[BatchFitResult], dims: tuple[str, ...], sizes: list[int]) -> BatchFitResult:
    """One `BatchFitResult` of ``parts`` (C order over ``dims`` of ``sizes``, each a batch with
    those dimensions of length 1): the datasets concatenated along each dimension (the variables
    without it, the parameters' flags and bounds, are the same in every part), the warnings and
    unidentified groups (keyed by each spectrum's labels) merged, the times added."""
    if not dims:
        return parts[0]
    step = math.prod(sizes[1:])
    rows = [joined(parts[i * step : (i + 1) * step], dims[1:], sizes[1:]) for i in range(sizes[0])]
    first = rows[0]
    dataset = xr.concat([r.dataset for r in rows], dim=dims[0], data_vars="minimal", coords="minimal", compat="override", combine_attrs="override")
    groups: dict = {}
    for r in rows:
        groups.update(dict(r.dataset.attrs.get("unidentified_groups", {})))
    if "unidentified_groups" in first.dataset.attrs:
        dataset.attrs["unidentified_groups"] = groups
    warnings: dict = {}
    for r in rows:
        warnings.update(r.warnings)
    return dataclasses.replace(first, dataset=dataset, warnings=warnings, elapsed_s=sum(r.elapsed_s for r in rows))


def _key(label):
    return label if isinstance(label, (str, int, float)) else shown(label)


def _text(labels: list) -> str:
    return ", ".join(map(str, labels[:6])) + (f", … ({len(labels)} in all)" if len(labels) > 6 else "")
