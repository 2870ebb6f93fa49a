"""`ResultGrid`: one method's results for every spectrum of a Dataset with extra dimensions
(trial, session, ...), held in C order over those dimensions; the batch results of the KK test
and the DRT are grids. `refuse_result_names`: the check, shared by every batch analysis, that
no batch dimension has the name of its result's own variables and dimensions."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Collection, Mapping, Sequence

import numpy as np

from ..data import label_value
from ..errors import DataError
from .frozen import freeze_fields

__all__ = ["ResultGrid", "refuse_result_names"]


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
class ResultGrid:
    """``results`` in C order over ``dims`` (sizes ``shape``, coordinates ``coords``);
    ``grid[i, j]`` (integer positions) gives one result."""

    dims: tuple[str, ...]
    shape: tuple[int, ...]
    coords: Mapping[str, np.ndarray]
    results: tuple

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    def __getitem__(self, index):
        index = index if isinstance(index, tuple) else (index,)
        if not self.shape:
            return self.results[0]
        return self.results[int(np.ravel_multi_index(index, self.shape))]

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
