"""`ResultGrid`: one method's results for every spectrum of a Dataset with extra dimensions
(trial, session, ...), held in C order over those dimensions; the batch results of the KK test,
Z-HIT and the DRT are grids. `refuse_result_names`: the check, shared by every batch analysis, that
no batch dimension has the name of its result's own variables and dimensions. `aligned_values`:
a value given per spectrum (a DataArray over the data's extra dimensions) matched to the data's
labels, as `fit`'s ``fixed=``/``init=`` and `derive`'s ``constants=`` take them."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Collection, Mapping, Sequence

import numpy as np
import xarray as xr

from ..arguments import shown
from ..data import label_value
from ..errors import IN_MEMORY, DataError, ParameterError
from .frozen import FrozenResult, freeze_fields

__all__ = ["ResultGrid", "refuse_result_names", "aligned_values"]


def refuse_result_names(batch_dims: Sequence[str], result_names: Collection[str], result: str, *, source: object = None) -> None:
    """`DataError` when a batch dimension has one of ``result_names``, the names of the
    variables and dimensions of the batch result's Dataset (``result``: what it is, e.g. "a fit
    result"): xarray had otherwise failed deep inside the analysis or in ``to_xarray`` (a
    dimension ``tau`` of 4 spectra beside the DRT's ``tau`` of 155 points: "conflicting sizes"),
    after the work was done. Called before any work, with the data's ``source`` for the message."""
    clashing = [str(d) for d in batch_dims if d in result_names]
    if clashing:
        raise DataError(
            f"the batch dimension(s) {', '.join(repr(d) for d in clashing)} have the name of {result}'s variable or dimension ({', '.join(sorted(result_names))}); "
            f"rename them first, e.g. data.rename({clashing[0]}='{clashing[0]}_label')",
            path=source,
        )


@dataclass(frozen=True, eq=False)
class ResultGrid(FrozenResult):
    """``results`` in C order over ``dims`` (sizes ``shape``, coordinates ``coords``);
    ``grid[i, j]`` (integer positions) gives one result."""

    dims: tuple[str, ...]
    shape: tuple[int, ...]
    coords: Mapping[str, np.ndarray]
    results: tuple

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    def __getitem__(self, index):
        """One result by its integer positions, one per dimension (negative from the end, as a
        list's); an `IndexError` naming the dimensions and their sizes otherwise: numpy's
        "invalid entry in coordinates array" ended ``for r in batch`` on the REAL battery cycles."""
        index = index if isinstance(index, tuple) else (index,)
        if not self.shape:
            return self.results[0]
        sizes = " × ".join(f"{d} {n}" for d, n in zip(self.dims, self.shape))
        if len(index) != len(self.shape) or not all(isinstance(i, (int, np.integer)) and not isinstance(i, bool) for i in index):
            raise IndexError(f"{type(self).__name__}[...] takes one integer position per dimension ({sizes}), e.g. [{', '.join(['0'] * len(self.shape))}]"
                             f"{'' if len(self.shape) == 1 else '; .results[k] holds them in order (the last dimension fastest), .labels() their places'}; got {index!r}")
        if not all(-n <= i < n for i, n in zip(index, self.shape)):
            raise IndexError(f"{type(self).__name__}{list(index)} is beyond its spectra ({sizes})")
        return self.results[int(np.ravel_multi_index(tuple(int(i) % n for i, n in zip(index, self.shape)), self.shape))]

    def __iter__(self):
        """The results in the order of ``results`` (C order over ``dims``)."""
        return iter(self.results)

    def __len__(self) -> int:
        return len(self.results)

    def labels(self) -> list[dict]:
        """Each result's place, in the order of ``results``: {dimension: its coordinate's value
        there, or the position where the dimension has no coordinate}."""
        axes = [[label_value(v) for v in np.asarray(self.coords[d])] if d in self.coords else list(range(n)) for d, n in zip(self.dims, self.shape)]
        return [{d: axes[k][i] for k, (d, i) in enumerate(zip(self.dims, index))} for index in np.ndindex(*self.shape)]

    def per_spectrum(self, name: str, dtype=float) -> np.ndarray:
        """Attribute ``name`` of every result as an array over ``dims``."""
        return np.array([getattr(r, name) for r in self.results], dtype=dtype).reshape(self.shape)


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
            raise ParameterError(f"{label} has no labels along {d}; the data's are {_labels_text(ours)}: label it, e.g. xr.DataArray(values, dims={d!r}, coords={{{d!r}: data[{d!r}].values}})")
        missing = [v for v in ours if v not in theirs]
        alien = [v for v in theirs if v not in ours]
        if missing or alien or len(set(map(_label_key, theirs))) != len(theirs):
            said = "; ".join(part for part in (f"not in the data: {_labels_text(alien)}" if alien else "", f"missing: {_labels_text(missing)}" if missing else "") if part) or "its labels repeat"
            raise ParameterError(f"{label}: its labels along {d} ({_labels_text(theirs)}) are not the data's ({_labels_text(ours)}){where}: {said}; give one value for each spectrum, labelled as the data")
        value = value.sel({d: data[d].values})  # (the data's order)
    return value


def _label_key(label):
    return label if isinstance(label, (str, int, float)) else shown(label)


def _labels_text(labels: list) -> str:
    return ", ".join(map(str, labels[:6])) + (f", … ({len(labels)} in all)" if len(labels) > 6 else "")
