"""The one set-up every fitting method shares: a spectrum from a path or a Dataset, checked,
with its frequency band selected (``fmin``/``fmax``) and, for methods that take one spectrum,
extra dimensions refused with a message that says what to do."""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..data import validate_spectrum
from ..errors import DataError


@dataclass(frozen=True, eq=False)
class Spectrum:
    """A checked spectrum Dataset and where it came from (a path, or the Dataset's ``source``)."""

    data: xr.Dataset
    source: str

    @property
    def extra_dims(self) -> tuple[str, ...]:
        return tuple(d for d in self.data["Z"].dims if d != "frequency")


def select_band(ds: xr.Dataset, fmin: float | None, fmax: float | None, source: str) -> xr.Dataset:
    """The points with fmin ≤ f ≤ fmax (either bound may be None); `DataError` if none remain."""
    f = ds["frequency"].values
    keep = np.ones(f.shape, bool)
    if fmin is not None:
        keep &= f >= fmin
    if fmax is not None:
        keep &= f <= fmax
    if not keep.any():
        raise DataError(f"no frequencies between fmin={fmin} and fmax={fmax}", path=source)
    return ds.isel(frequency=np.flatnonzero(keep)) if not keep.all() else ds


def open_spectrum(data: xr.Dataset | str | os.PathLike, *, fmin: float | None = None, fmax: float | None = None, single: str | None = None) -> Spectrum:
    """Load (a path) or check (a Dataset) a spectrum and select its band.

    ``single``: the name of a method that takes one spectrum (``"diagnose"``, ...); data with
    extra dimensions (trial, session, ...) then raise `DataError` naming it.
    """
    if isinstance(data, xr.Dataset):
        source = str(data.attrs.get("source", "dataset"))
        validate_spectrum(data, source=source)
    else:
        from ..io import load

        source = str(data)
        data = load(data)
    spectrum = Spectrum(select_band(data, fmin, fmax, source), source)
    if single is not None and spectrum.extra_dims:
        raise DataError(
            f"{single} takes one spectrum; these data hold several (extra dimensions {', '.join(spectrum.extra_dims)}): "
            "select one or average them first",
            path=source,
        )
    return spectrum
