"""`ResultGrid`: one method's results for every spectrum of a Dataset with extra dimensions
(trial, session, ...), held in C order over those dimensions; the batch results of the KK test
and the DRT are grids."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

__all__ = ["ResultGrid"]


@dataclass(frozen=True, eq=False)
class ResultGrid:
    """``results`` in C order over ``dims`` (sizes ``shape``, coordinates ``coords``);
    ``grid[i, j]`` (integer positions) gives one result."""

    dims: tuple[str, ...]
    shape: tuple[int, ...]
    coords: Mapping[str, np.ndarray]
    results: tuple

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
        axes = [np.asarray(self.coords[d]).tolist() if d in self.coords else list(range(n)) for d, n in zip(self.dims, self.shape)]
        return [{d: axes[k][i] for k, (d, i) in enumerate(zip(self.dims, index))} for index in np.ndindex(*self.shape)]

    def per_spectrum(self, name: str, dtype=float) -> np.ndarray:
        """Attribute ``name`` of every result as an array over ``dims``."""
        return np.array([getattr(r, name) for r in self.results], dtype=dtype).reshape(self.shape)
