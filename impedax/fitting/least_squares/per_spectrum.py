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

from ..grid import aligned_values
from .batch import BatchFitResult, batch_with_warnings

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
    for r in rows:  # (`notes.Note`s: each spectrum's tags with its warnings)
        warnings.update({k: r.tagged_warnings(k) for k in r.warnings})
    return batch_with_warnings(dataclasses.replace(first, dataset=dataset, elapsed_s=sum(r.elapsed_s for r in rows)), warnings)
