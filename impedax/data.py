"""The spectrum data model: an `xarray.Dataset` with complex ``Z`` over ``frequency``.

* ``Z`` — complex impedance [Ω], Z = Z' + jZ'' (Z'' < 0 for capacitive data), dimension
  ``frequency`` plus any extra dimensions (trial, session, condition, ...);
* ``frequency`` — coordinate in Hz, strictly positive, no duplicates;
* ``sigma`` — optional per-point standard deviation [Ω] of Z (applies to Re and Im), e.g. the
  standard error of the mean of repeated trials;
* units in attrs; ``attrs["source"]`` names where the data came from.
"""

from __future__ import annotations

import keyword
import math
import re
from typing import Mapping, Sequence

import numpy as np
import xarray as xr

from .arguments import MAX_POINTS, checked_arguments, count, format_frequency, real, reversed_band_message, shown  # (format_frequency: written there for the argument checks' messages, impedax.data.format_frequency to its callers)
from .errors import IN_MEMORY, DataError, ParameterError

__all__ = ["make_spectrum", "validate_spectrum", "log_frequencies", "checked_frequencies", "label_value", "coordinate_labels"]


@checked_arguments(fmin=real(), fmax=real(), points=count(1, MAX_POINTS, why="80 MB of frequencies"))
def log_frequencies(fmin: float, fmax: float, points: int) -> np.ndarray:
    """``points`` log-spaced frequencies [Hz] from ``fmin`` to ``fmax``, both ends included."""
    if not (np.isfinite(fmin) and np.isfinite(fmax)) or fmin <= 0 or fmax <= 0:
        raise DataError(f"frequencies must be positive and finite, got fmin={fmin}, fmax={fmax}")
    if fmax < fmin:
        raise DataError(reversed_band_message(fmin, fmax))
    if points < 1 or (points == 1 and fmin != fmax):
        raise DataError(f"need at least 2 points for a range (got {points}); use fmin == fmax for one point")
    return np.geomspace(fmin, fmax, points) if points > 1 else np.array([float(fmin)])


@checked_arguments()
def make_spectrum(
    frequency: Sequence[float],
    Z,
    *,
    sigma=None,
    dims: Sequence[str] | str = (),
    coords: Mapping[str, Sequence] | None = None,
    attrs: Mapping[str, object] | None = None,
    source: str = IN_MEMORY,
) -> xr.Dataset:
    """Build and validate a spectrum Dataset.

    ``Z`` has shape ``(*extra, n_frequency)`` with the extra dimensions named by ``dims`` (one
    name may be given as a string); ``coords`` labels those extra dimensions (the frequencies
    are ``frequency``); ``sigma`` is one value or an array that broadcasts to Z's shape.
    """
    dims = _extra_dims(dims)
    coords = _extra_coords(coords, dims)
    if attrs is not None and not isinstance(attrs, Mapping):
        raise ParameterError(f"attrs must be a mapping (dict), got {shown(attrs)} ({type(attrs).__name__})")
    frequency = _numbers(frequency, np.float64, "frequency", source, real="frequencies in Hz")
    Z = _numbers(Z, np.complex128, "Z", source, complex_only=True)
    all_dims = (*dims, "frequency")
    if frequency.ndim != 1:
        raise DataError(f"frequency must be one-dimensional, got shape {frequency.shape}", path=source)
    if Z.ndim != len(all_dims):
        if Z.ndim == 0:
            raise DataError("Z must be an array over frequency, got a single number", path=source)
        if not dims:
            names = ("trial", "session", "condition") if Z.ndim <= 4 else tuple(f"dim_{i}" for i in range(Z.ndim - 1))
            example = names[: Z.ndim - 1]
            raise DataError(f"Z has {Z.ndim} dimensions; name the ones before frequency, e.g. dims={example!r} for Z over {(*example, 'frequency')!r}", path=source)
        # (quoting the dims the caller gave: 'frequency', which impedax adds, is in neither)
        raise DataError(f"Z has {Z.ndim} dimensions but dims={dims!r} were given (Z's dimensions before frequency: {Z.ndim - 1})", path=source)
    if Z.shape[-1] != frequency.size:
        turned = f" (Z's shape {Z.shape}: frequency must be its last axis; Z.T if the frequencies run down its rows)" if frequency.size in Z.shape[:-1] else ""
        raise DataError(f"Z has {Z.shape[-1]} values along frequency but there are {frequency.size} frequencies{turned}", path=source)
    data_vars = {"Z": (all_dims, Z, {"units": "ohm", "long_name": "complex impedance Z' + jZ''"})}
    if sigma is not None:
        sigma = _numbers(sigma, np.float64, "sigma", source, real="a standard deviation [Ω] per point, for Re and Im alike")
        try:
            sigma = np.broadcast_to(sigma, Z.shape)
        except ValueError:
            raise DataError(f"sigma has shape {sigma.shape}, which does not broadcast to Z's {Z.shape}", path=source) from None
        data_vars["sigma"] = (all_dims, np.array(sigma), {"units": "ohm", "long_name": "standard deviation of Z"})
    all_coords = {"frequency": ("frequency", frequency, {"units": "Hz"})}
    for name, values in coords.items():
        try:
            labels = np.asarray(values)
        except (TypeError, ValueError):  # (a ragged list)
            raise DataError(f"coords[{name!r}] must be one label per entry along {name!r}, got {shown(values)}", path=source) from None
        n = Z.shape[dims.index(name)]
        if labels.ndim != 1:
            raise DataError(f"coords[{name!r}] must be one label per entry along {name!r}, got shape {labels.shape}", path=source)
        if labels.size != n:
            raise DataError(f"coords[{name!r}] has {labels.size} labels but Z has {n} entries along {name!r}", path=source)
        all_coords[name] = (name, labels)
    ds = xr.Dataset(data_vars, coords=all_coords, attrs={"source": source, **dict(attrs or {})})
    return _checked(ds, source, arrays=True)


def _extra_dims(dims) -> tuple[str, ...]:
    """``dims`` of `make_spectrum` as a tuple of names: one string is one name; 'frequency',
    repeated names and names that are not strings are a `ParameterError`."""
    if isinstance(dims, str):
        dims = (dims,)
    try:
        dims = tuple(dims)
    except TypeError:
        raise ParameterError(f"dims must be names of Z's dimensions before frequency, e.g. ('trial',), got {shown(dims)}") from None
    for name in dims:
        if not isinstance(name, str) or not name:
            raise ParameterError(f"dims must be names (strings), got {shown(name)} in {shown(dims)}")
    if "frequency" in dims:
        raise ParameterError(f"dims names the dimensions before frequency, which is always Z's last; leave 'frequency' out of dims={dims!r}")
    repeated = sorted({name for name in dims if dims.count(name) > 1})
    if repeated:
        raise ParameterError(f"dims names {repeated[0]!r} twice: {dims!r}")
    return dims


def _extra_coords(coords, dims: tuple[str, ...]) -> dict:
    """``coords`` of `make_spectrum`: labels of the dimensions in ``dims`` only; the
    frequencies are the ``frequency`` argument, so a 'frequency' key is a `ParameterError`."""
    if coords is None:
        return {}
    if not isinstance(coords, Mapping):
        raise ParameterError(f"coords must be a mapping of dimension name to labels, got {shown(coords)} ({type(coords).__name__})")
    for name in coords:
        if name == "frequency":
            raise ParameterError("frequency given twice: as the first argument and in coords; leave 'frequency' out of coords")
        if name not in dims:
            known = f"the dimensions in dims {dims!r}" if dims else "none: dims is empty, so Z has no dimension but frequency"
            raise ParameterError(f"coords names {shown(name)}, which is not a dimension of Z; coords may label {known}")
    return dict(coords)


def _numbers(values, dtype, name: str, source: str, *, complex_only: bool = False, real: str = "") -> np.ndarray:
    """``values`` as an array of ``dtype``; `DataError` for text, None, ragged lists, bools,
    real numbers where ``complex_only``, complex ones where ``real`` says what they are."""
    try:
        array = np.asarray(values)
        if array.dtype == bool or not (np.issubdtype(array.dtype, np.number)):
            raise TypeError
    except (TypeError, ValueError):
        raise DataError(f"{name} must be numbers, got {shown(values)}", path=source) from None
    if array.size == 0:
        raise DataError(f"{name} is empty: no data" + (f" (shape {array.shape})" if array.ndim > 1 else ""), path=source)
    if complex_only and not np.iscomplexobj(array):
        raise DataError(f"{name} must be complex, e.g. Z' + 1j*Z'' (got dtype {array.dtype}); a magnitude or Z' alone is not an impedance spectrum", path=source)
    if real and np.iscomplexobj(array):
        raise DataError(f"{name} must be real ({real}), got dtype {array.dtype}", path=source)
    return np.asarray(array, dtype=dtype)


def checked_frequencies(freq, name: str = "freq", *, ndim_max: int | None = 1, source: str | None = None) -> np.ndarray:
    """``freq`` [Hz] as a float64 array (a scalar or up to ``ndim_max`` dimensions; None: any),
    every value finite and positive; otherwise one `DataError` naming ``name`` and the first bad
    value and its position."""
    try:
        array = np.asarray(freq)
        if array.dtype == bool or not np.issubdtype(array.dtype, np.number):
            raise TypeError
    except (TypeError, ValueError):
        raise DataError(f"{name} must be frequencies in Hz (numbers), got {shown(freq)}", path=source) from None
    if np.iscomplexobj(array):
        raise DataError(f"{name} must be real frequencies in Hz, got dtype {array.dtype}", path=source)
    if ndim_max is not None and array.ndim > ndim_max:
        raise DataError(f"{name} must be one-dimensional (or one number), got shape {array.shape}", path=source)
    if array.size == 0:
        raise DataError(f"{name} is empty", path=source)
    array = np.asarray(array, dtype=np.float64)
    bad = np.argwhere(~np.isfinite(np.atleast_1d(array)) | (np.atleast_1d(array) <= 0))
    if bad.size:
        index = tuple(int(i) for i in bad[0])
        where = "got " if array.ndim == 0 else f"point {index[0]} is " if array.ndim == 1 else f"the value at {index} is "
        raise DataError(f"{name} must be positive and finite; {where}{np.atleast_1d(array)[index]:g}", path=source)
    return array


# the Dataset.encoding key `impedax.load` sets to the file whose data passed `validate_spectrum`
CHECKED_FILE = "impedax_checked_file"

# what to do about a non-finite Z, one spectrum (False) or a batch (True): every check runs as the
# data are read, before --select or --exclude could act
NON_FINITE_ADVICE = {
    False: "; leave that point out of the file (Python: out of the arrays given to make_spectrum)",
    True: "; every spectrum needs a value at every frequency: leave that point or spectrum out of the file (Python: out of the arrays given to "
          "make_spectrum); spectra measured on different sweeps are analysed apart, not padded with NaN to one grid",
}
# the same for arrays (given to `make_spectrum`, or a (frequency, Z) pair given as data): no file,
# the Python that leaves the point out (an array sigma needs the same [keep])
NON_FINITE_ARRAYS_ADVICE = {
    False: "; leave that point out of the arrays: keep = np.isfinite(Z); frequency, Z = frequency[keep], Z[keep]",
    True: "; every spectrum needs a value at every frequency: leave that frequency out of every spectrum, keep = np.isfinite(Z).all(axis=tuple(range(Z.ndim - 1))); "
          "frequency, Z = frequency[keep], Z[..., keep], or that spectrum out of Z; spectra measured on different sweeps are analysed apart, not padded with NaN to one grid",
}


def validate_spectrum(ds: xr.Dataset, *, source: str | None = None) -> xr.Dataset:
    """Check the data model; raise `DataError` naming the problem. Returns ``ds`` unchanged.
    Data `impedax.load` read from ``source`` passed these checks then: a failure now says that
    they were changed in memory since, so that no one looks for the fault in the file. A
    non-finite Z of a Dataset built in Python (no reader's ``attrs["format"]``) is answered with
    the ``ds.dropna('frequency')`` that leaves it out (`_checked`)."""
    if not isinstance(ds, xr.Dataset):  # (before ds.attrs: a list would end in AttributeError)
        raise DataError(f"expected an xarray.Dataset, got {type(ds).__name__}", path=source or "dataset")
    return _checked(ds, source or str(ds.attrs.get("source", "dataset")), arrays=False)


def _checked(ds: xr.Dataset, source: str, *, arrays: bool) -> xr.Dataset:
    """`validate_spectrum`'s checks, a non-finite Z's advice fitted to where the data came from: a
    file (a reader's Dataset, its ``attrs["format"]``) keeps `NON_FINITE_ADVICE`; data built in
    Python get Python's remedy, for the ``arrays`` given to `make_spectrum`
    `NON_FINITE_ARRAYS_ADVICE`, for a Dataset xarray's dropna (`_dropna_advice`), which is also
    the remedy for a file's data changed in memory after `impedax.load` checked them."""
    try:
        return _validated(ds, source)
    except DataError as exc:
        loaded = ds.encoding.get(CHECKED_FILE) == source
        if not loaded and "format" in ds.attrs:
            raise
        detail = exc.detail
        for batch, advice in NON_FINITE_ADVICE.items():
            if advice in detail:
                remedy = NON_FINITE_ARRAYS_ADVICE[batch] if arrays and source == IN_MEMORY else advice if arrays else _dropna_advice(ds)
                detail = detail.replace(advice, "") + remedy
        if not loaded:
            if detail == exc.detail:
                raise
            raise DataError(detail, path=source) from None
        raise DataError(f"{detail} (changed in memory after impedax.load read the file, which passed this check)", path=source) from None


# spellings of a frequency dimension other than impedax's ``frequency`` (lower case), named in the
# advice to rename it; otherwise the advice names Z's last dimension, where impedax keeps frequency
_FREQUENCY_ALIASES = ("freq", "f", "freqs", "frequencies", "frequency_hz", "freq_hz")


def frequency_dimension_problem(dims: tuple[str, ...], has_dimension: bool = False) -> str:
    """What is wrong with a ``Z`` over ``dims`` that lacks the ``frequency`` dimension (or, with
    ``has_dimension``, its coordinate), and how to fix it: the one message of `impedax.save`
    and `impedax.load` (more than "dataset has no variable 'Z'")."""
    if has_dimension:
        return "'Z' has a 'frequency' dimension but no coordinate on it: give it the frequencies in Hz, e.g. ds = ds.assign_coords(frequency=f_hz)"
    if not dims:
        return "'Z' has no 'frequency' dimension (it is a single number): a spectrum is Z over a 'frequency' dimension with a coordinate in Hz"
    guess = str(next((d for d in dims if str(d).lower() in _FREQUENCY_ALIASES), dims[-1]))
    rename = f"ds.rename({guess}=\"frequency\")" if guess.isidentifier() and not keyword.iskeyword(guess) else f"ds.rename({{{guess!r}: \"frequency\"}})"
    found = ", ".join(repr(str(d)) for d in dims)
    return f"'Z' has no 'frequency' dimension (its dimensions: {found}): name the frequency dimension 'frequency', with a coordinate in Hz, e.g. ds = {rename}"


def _validated(ds: xr.Dataset, source: str) -> xr.Dataset:
    variables = ds.variables  # Variables, not DataArrays: this runs before every fit
    if "Z" not in variables:
        names = ", ".join(repr(str(n)) for n in ds.data_vars) or "none"
        raise DataError(f"dataset has no variable 'Z' (its data variables: {names})", path=source)
    z_var = variables["Z"]
    if "frequency" not in z_var.dims or "frequency" not in ds.coords:
        raise DataError(frequency_dimension_problem(z_var.dims, "frequency" in z_var.dims), path=source)
    z = z_var.values
    if not np.iscomplexobj(z):
        raise DataError("'Z' must be complex (Z' + jZ'')", path=source)
    f = variables["frequency"].values
    if f.dtype == bool or not np.issubdtype(f.dtype, np.number) or np.iscomplexobj(f):
        raise DataError(f"the frequency coordinate must be real numbers in Hz, got dtype {f.dtype}", path=source)
    f = np.asarray(f, dtype=np.float64)
    if f.size == 0:
        raise DataError("the spectrum has no frequencies", path=source)
    bad = np.flatnonzero(~np.isfinite(f) | (f <= 0))
    if bad.size:
        raise DataError(f"frequency must be positive and finite; point {bad[0]} is {f[bad[0]]:g}", path=source)
    ordered = np.sort(f)
    repeated = ordered[1:][ordered[1:] == ordered[:-1]]
    if repeated.size:
        dup = repeated[0]
        where = np.flatnonzero(f == dup)
        points = ", ".join(map(str, where[:5])) + (f", … ({where.size} points)" if where.size > 5 else "")
        raise DataError(f"duplicate frequency {dup:g} Hz at points {points}", path=source)
    empty = [dim for dim, n in zip(z_var.dims, z_var.shape) if n == 0 and dim != "frequency"]
    if empty:
        raise DataError(f"dimension {empty[0]!r} of Z has length 0: the data hold no spectrum", path=source)
    _check_units(variables["frequency"], "frequency", HERTZ, "Hz", FREQUENCY_SCALES, source)
    _check_units(z_var, "Z", OHMS, "ohm", RESISTANCE_SCALES, source)
    if not np.all(np.isfinite(z)):
        idx = np.argwhere(~np.isfinite(z))[0]
        remedy = NON_FINITE_ADVICE[any(d != "frequency" for d in z_var.dims)]
        raise DataError(f"Z has a non-finite value at {point_text(ds, z_var.dims, idx)}: {z[tuple(idx)]}{remedy}", path=source)
    if "sigma" in variables:
        _check_sigma(ds, variables["sigma"], z_var, source)
    return ds


# spellings of the units impedax works in (compared in lower case, spaces removed), and the
# factors that bring prefixed units to them (named in the message that refuses them)
HERTZ = ("hz", "1/s", "s-1", "s^-1", "s⁻¹")
OHMS = ("ω", "ohm", "ohms")
FREQUENCY_SCALES = {"mhz": 1e-3, "khz": 1e3, "ghz": 1e9, "rad/s": 1 / (2 * np.pi)}
RESISTANCE_SCALES = {"mω": 1e-3, "mohm": 1e-3, "kω": 1e3, "kohm": 1e3, "kohms": 1e3, "gω": 1e9, "gohm": 1e9}
_CASE_SENSITIVE_SCALES = {"MHz": 1e6, "MΩ": 1e6, "MOhm": 1e6, "Mohm": 1e6, "MOhms": 1e6}


def _check_units(variable: xr.Variable, name: str, accepted: tuple[str, ...], unit: str, scales: dict, source: str) -> None:
    """`DataError` when ``variable`` has a ``units`` attribute other than ``unit`` (in one of
    its ``accepted`` spellings): impedax reads the values as Hz and Ω, whatever the attribute."""
    units = variable.attrs.get("units")
    if units is None:
        return
    text = str(units).strip()
    if text.lower().replace(" ", "") in accepted:
        return
    factor = _CASE_SENSITIVE_SCALES.get(text.replace(" ", ""), scales.get(text.lower().replace(" ", "")))
    how = f"multiply the values by {factor:.6g}" if factor is not None else f"convert the values to {unit}"
    raise DataError(f"{name} has units {text[:40]!r}, but impedax works in {unit}: {how} and set its units attribute to {unit!r}", path=source)


def _check_sigma(ds: xr.Dataset, sigma: xr.Variable, z_var: xr.Variable, source: str) -> None:
    """`DataError` unless ``sigma`` is real, positive and finite, over Z's dimensions (any
    order) with Z's sizes: the fits and samplers take it point by point."""
    what = f"a standard deviation [Ω] per point of Z, over Z's dimensions {z_var.dims}"
    if set(sigma.dims) != set(z_var.dims) or any(ds.sizes[d] != n for d, n in zip(sigma.dims, sigma.shape)):
        got = "a single value" if not sigma.dims else f"dims {sigma.dims} with shape {sigma.shape}"
        hint = "; make_spectrum(..., sigma=value) spreads one value over every point" if not sigma.dims or set(sigma.dims) < set(z_var.dims) else ""
        raise DataError(f"sigma must be {what}; got {got}{hint}", path=source)
    values = sigma.values
    if values.dtype == bool or not np.issubdtype(values.dtype, np.number) or np.iscomplexobj(values):
        raise DataError(f"sigma must be real numbers ({what}), got dtype {values.dtype}", path=source)
    bad = np.argwhere(~np.isfinite(values) | (values <= 0))
    if bad.size:
        idx = bad[0]
        raise DataError(f"sigma must be positive and finite; at {point_text(ds, sigma.dims, idx)} it is {values[tuple(idx)]:g}", path=source)


def label_value(label):
    """A coordinate label as plain Python, as JSON and text hold it: a bool, integer or float
    (numpy's too) as itself; a date or time (numpy ``datetime64``/``timedelta64``) as its ISO
    text (as ``str`` of it gives), not the count of nanoseconds that ``.item()`` and
    ``.tolist()`` give; text (``str``, ``numpy.str_``,
    bytes decoded as UTF-8) and anything else as its ``str``. A label read from netCDF is often
    a ``str`` in an object array, which has no ``.item()``."""
    if isinstance(label, (bool, np.bool_)):
        return bool(label)
    if isinstance(label, np.datetime64):
        return str(np.datetime_as_string(label))
    if isinstance(label, np.timedelta64):
        return str(label)
    if isinstance(label, (int, np.integer)):
        return int(label)
    if isinstance(label, (float, np.floating)):
        return float(label)
    if isinstance(label, bytes):
        return label.decode("utf-8", errors="replace")
    return str(label)


def label_text(label) -> str:
    """A coordinate label as a report or figure writes it (`label_value`'s, as ``str``), but a
    float that ``str`` writes with binary noise to 12 significant digits: np.arange(11) * 0.1
    labelled a spectrum "soc=0.30000000000000004", now "soc=0.3" (0.5 and 0.0 stay as they were)."""
    from .warning_groups import label_shown  # (the one rule, which text outputs share: `label_shown`)

    return label_shown(label_value(label))


def coordinate_labels(ds, dim: str) -> list:
    """The labels of ``ds``'s spectra along ``dim``, each as `label_value` gives it (a date as
    its ISO text), or the positions 0..n-1 where ``dim`` has no coordinate."""
    if dim not in ds.coords:
        return list(range(ds.sizes[dim]))
    return [label_value(v) for v in ds[dim].values]


def _dropna_advice(ds: xr.Dataset) -> str:
    """How xarray leaves out the first non-finite point of Z in a Dataset changed in memory (a
    point masked as NaN by hand): ``ds.dropna('frequency')``, which for a stack leaves that
    frequency out of every spectrum, or the spectrum alone without it
    (``ds.sel(cycle=64).dropna('frequency')``; by position where a dimension has no labels)."""
    z = ds.variables["Z"]
    idx = np.argwhere(~np.isfinite(z.values))[0]
    others = [(dim, int(i)) for dim, i in zip(z.dims, idx) if dim != "frequency"]
    if not others:
        return "; ds.dropna('frequency') leaves it out"
    labelled = all(dim in ds.coords and isinstance(ds[dim].values[i].item(), int | float | str) for dim, i in others)  # (else by position)
    chosen = ", ".join(f"{dim}={ds[dim].values[i].item()!r}" if labelled else f"{dim}={i}" for dim, i in others)
    return f"; ds.dropna('frequency') leaves that frequency out of every spectrum, ds.{'sel' if labelled else 'isel'}({chosen}).dropna('frequency') out of that spectrum alone"


def point_text(ds: xr.Dataset, dims, idx) -> str:
    """A point of a variable over ``dims`` at positions ``idx``, named by its coordinates:
    ``cycle=64, f=1.5 kHz`` (a dimension without coordinates by its position, ``trial #3``;
    the frequency as `format_frequency` writes it, with its point number)."""
    parts = []
    for dim, i in zip(dims, (int(i) for i in idx)):
        if dim == "frequency":
            parts.append(f"f={format_frequency(float(ds['frequency'].values[i]))} (point {i})")
        elif dim in ds.coords:
            parts.append(f"{dim}={label_value(ds[dim].values[i])}")
        else:
            parts.append(f"{dim} #{i}")
    return ", ".join(parts)


def format_band(lo: float, hi: float, dash: str = "–") -> str:
    """A band of frequencies [Hz] for text: ``4.68 Hz–6.08 Hz``; one frequency where the two
    read the same (a run of one point: ``56.2 Hz``, not ``56.2 Hz–56.2 Hz``)."""
    low, high = format_frequency(lo), format_frequency(hi)
    return low if low == high else f"{low}{dash}{high}"


def unit_text(unit: str) -> str:
    """A parameter's unit (its element spec's spelling) for text: ``Ohm`` as ``Ω``, also inside
    compound units (``Ω s^-1/2``), a CPE's ``alpha`` as ``α`` (``F s^(α-1)``); a dimensionless
    ``1`` as nothing."""
    return "" if unit == "1" else re.sub(r"\balpha\b", "α", re.sub(r"\b[Oo]hm\b", "Ω", unit))


def counted(n: int, singular: str, plural: str | None = None) -> str:
    """``n`` and the noun in its number: ``1 spectrum``, ``3 spectra``, ``1 free parameter``
    (``plural`` default: ``singular`` + "s"). The CLI's counts read so (never
    "1 free parameters", "1 spectra")."""
    return f"{n} {singular if n == 1 else plural or singular + 's'}"


def column_width(entries, header: str | int) -> int:
    """The width of a text table's first column: its longest entry, and at least its
    ``header`` (or that many characters), so that the columns after it stay under theirs."""
    return max([header if isinstance(header, int) else len(header), *(len(e) for e in entries)])


# SI prefixes of a value's scale, largest first (`format_quantity`, the plots' tick labels)
SI_PREFIXES = ((1e12, "T"), (1e9, "G"), (1e6, "M"), (1e3, "k"), (1.0, ""), (1e-3, "m"), (1e-6, "µ"), (1e-9, "n"), (1e-12, "p"), (1e-15, "f"))


def si_prefix(magnitude: float) -> tuple[float, str]:
    """The (scale, prefix) of `SI_PREFIXES` for a value of this magnitude: the largest scale at
    or below it; femto below that."""
    return next(((scale, prefix) for scale, prefix in SI_PREFIXES if magnitude >= scale), SI_PREFIXES[-1])


def _quantity_parts(value: float, unit: str, digits: int) -> tuple[str, float, str]:
    """(number text, scale, unit text with its prefix) of `format_quantity`: ``("2.2", 1e3, "kΩ")``;
    a compound unit takes the prefix on its leading unit, as the figures' axes count it
    (``("2.87", 1e-3, "mΩ s^-1/2")``, a Warburg σ; ``µF s^(α-1)``, a CPE's Q); scale 1 and the
    plain unit where no prefix applies (a unit led by a power or a quotient: ``m^2``, ``1/s``)."""
    label = unit_text(unit) if unit else ""
    lead = label.split(" ")[0]
    if not label or not np.isfinite(value) or value == 0 or "^" in lead or "/" in lead:
        return f"{value:.{digits}g}", 1.0, label
    shown = float(f"{value:.{digits}g}")  # (the prefix of the value as printed: 999.6 Ω is 1 kΩ)
    if not SI_PREFIXES[-1][0] <= abs(shown) < 1e3 * SI_PREFIXES[0][0]:  # (beyond the prefixes: 1.19e+282 Ω, not 1.19e+270 TΩ)
        return f"{value:.{digits}g}", 1.0, label
    scale, prefix = si_prefix(abs(shown))
    number = f"{shown / scale:.{digits}g}"
    if "e" in number:  # (fewer digits than the number has before its point: 130 GΩ to 2 digits is "130", not "1.3e+02")
        number = f"{float(number):.0f}"
    return number, scale, f"{prefix}{label}"


def value_span(values, spec: str = ".3g") -> str:
    """``values`` as "a" when they agree in format ``spec`` (one value, or equal ones) and "a–b"
    (their smallest and largest) when not: a report's figure of several walkers or points."""
    lo, hi = format(float(np.min(values)), spec), format(float(np.max(values)), spec)
    return lo if lo == hi else f"{lo}–{hi}"


def format_quantity(value: float, unit: str, digits: int = 3) -> str:
    """``84 µF``, ``2.2 kΩ``, ``0.81`` (a value with an SI prefix, ``digits`` significant;
    dimensionless as it is)."""
    number, _, label = _quantity_parts(value, unit, digits)
    return f"{number} {label}" if label else number


def format_bound(value: float, unit: str) -> str:
    """A parameter's bound (the element's, or one the user gave: ``--bound R1=1m:10m``) for text:
    as `format_quantity` writes it where that text is the same number (``10 kΩ``, ``10 mΩ``,
    ``10 µF s^(α-1)``, ``0.9``), else with up to 6 significant digits, as many as keep it that
    number (``99.999 kΩ``, not ``100 kΩ``; 6 as ``:g`` writes them, but with
    their unit, not "its upper bound 10000"); 0 as ``0`` and an infinite bound as ``∞``, in any unit."""
    if value == 0 or not math.isfinite(value):
        return "0" if value == 0 else "∞" if value > 0 else "-∞" if value < 0 else str(value)
    for digits in range(3, 7):
        number, scale, label = _quantity_parts(value, unit, digits)
        if math.isclose(float(number) * scale, value, rel_tol=1e-12, abs_tol=0.0):
            break
    return f"{number} {label}" if label else number


def format_uncertain(value: float, stderr: float, unit: str) -> str:
    """``730 ± 120 Ω``, ``3.94 ± 0.19 kΩ``, ``1.1500 ± 0.0056 Ω``: `format_value_error`'s rule
    (the error to two significant digits, the value to the error's last digit, GUM JCGM
    100:2008 §7.2.6, `round_to_error`) in the SI prefix of the value as so rounded (a compound
    unit in that of its leading unit: ``20.0 ± 3.0 µF s^(α-1)``); without a prefix where
    `format_quantity` gives none (zero, not finite, a unit led by a power: then
    ``(2.00 ± 0.30)e-05 m^2``). An error that is not finite or not positive leaves the
    value to 3 significant digits (``3.94 ± nan kΩ``). (A value with 3 digits whatever its error
    would read ``1.15 ± 0.0056 Ω`` beside ``773 ± 5.1 mΩ``.)"""
    stderr = abs(stderr)  # (an error is a size)
    if not (math.isfinite(value) and math.isfinite(stderr) and stderr > 0):
        number, scale, label = _quantity_parts(value, unit, 3)
        error = stderr / scale
        shown = f"{float(f'{error:.2g}'):g}" if np.isfinite(error) else f"{error}"
        return f"{number} ± {shown}" + (f" {label}" if label else "")
    number, _, exponent = round_to_error(value, stderr)
    rounded = float(f"{number}e{exponent}") if exponent else float(number)  # (the prefix of the value as printed: 999.96 ± 5 Ω is 1.0000 ± 0.0050 kΩ)
    _, scale, label = _quantity_parts(rounded, unit, 15)  # (15 digits: a float's, so the rounded value keeps its magnitude)
    number, error, exponent = round_to_error(value / scale, stderr / scale)
    text = f"({number} ± {error})e{exponent:+03d}" if exponent else f"{number} ± {error}"
    return f"{text} {label}" if label else text


# significant digits a standard error is given to, and its value rounded to the same last
# digit (GUM, JCGM 100:2008 §7.2.6: "at most two significant digits")
ERROR_DIGITS = 2
# one rule for every row: a value whose power of ten (after rounding) is from −2 to 3, 0.01 ≤
# |value| < 10⁴, is written out (0.01235, 533, 1234.5); any other value and its error share
# the value's power of ten, (1.0002 ± 0.0028)e-06, (1.2346 ± 0.0012)e+04
PLAIN_EXPONENTS = range(-2, 4)


def _round_half_up(number, place: int):
    """``number`` (a Decimal) rounded half up to the digit of 10^``place``."""
    import decimal

    return number.quantize(decimal.Decimal(1).scaleb(place), rounding=decimal.ROUND_HALF_UP)


def _significant(number, digits: int) -> str:
    """``number`` (a nonzero Decimal) to ``digits`` significant digits, half up, written out
    where its power of ten is in `PLAIN_EXPONENTS` ("5.0", "120"), else as "2.2e+07"; a
    rounding that carries (9.96 → 10) moves the power of ten."""
    rounded = _round_half_up(number, number.adjusted() - (digits - 1))
    rounded = _round_half_up(rounded, rounded.adjusted() - (digits - 1))  # (10.0 → 10)
    size = rounded.adjusted()
    if size in PLAIN_EXPONENTS:
        return format(rounded, "f")
    return f"{format(rounded.scaleb(-size), 'f')}e{size:+03d}"


def round_to_error(value: float, error: float, digits: int = ERROR_DIGITS) -> tuple[str, str, int]:
    """(value, error, exponent) as written for ``value ± error``: the error to ``digits``
    significant digits, the value to the error's last digit, both by decimal rounding half up
    of the numbers as Python prints them (533.3168 ± 13.0249 → "533", "13"; 0.012345 ± 0.00067
    → "0.01235", "0.00067"). ``exponent`` is 0, or the value's power of ten after rounding
    where that is outside `PLAIN_EXPONENTS` (0.01 ≤ |value| < 10⁴ is written out), both numbers
    then scaled by it: 1.0002e-06 ± 2.82e-09 → "1.0002", "0.0028", −6; 9.996e-4 ± 9.96e-6 →
    "1.000", "0.010", −3 (the carry moves the exponent). A value below its error (0 < |value|
    < error, relative error above 100 %: the data do not determine it) would round to "0.0"
    at the error's digit; it is given instead to ``digits`` significant digits, as is the
    error, each with its own power of ten (2.18e7 ± 2.8e15 → "2.2e+07", "2.8e+15", 0; 5 ± 120
    → "5.0", "120", 0). An error that is not finite or not positive gives "" and the value to
    5 significant digits."""
    import decimal

    if not (math.isfinite(value) and math.isfinite(error) and error > 0):
        return (f"{value:.5g}" if math.isfinite(value) else str(value)), "", 0
    exact_value, exact_error = decimal.Decimal(repr(float(value))), decimal.Decimal(repr(float(error)))
    if 0 < abs(value) < error:
        return _significant(exact_value, digits), _significant(exact_error, digits), 0
    place = exact_error.adjusted() - (digits - 1)  # (the power of ten of the error's last digit)
    rounded_error = _round_half_up(exact_error, place)
    if rounded_error.adjusted() > exact_error.adjusted():  # (9.96 → 10: still two digits, "10" not "10.0")
        place += 1
    rounded_value = _round_half_up(exact_value, place)
    size = rounded_value.adjusted() if rounded_value != 0 else rounded_error.adjusted()
    exponent = 0 if size in PLAIN_EXPONENTS else size

    def written(number: decimal.Decimal) -> str:
        shown = _round_half_up(number.scaleb(-exponent), place - exponent)
        return format(abs(shown) if shown == 0 else shown, "f")  # (no "-0.0")

    return written(exact_value), written(exact_error), exponent


def exact_number(value: float) -> str:
    """``value`` as given: the shortest decimal that reads back as the same float (``repr``),
    without a trailing ".0" (12.3456 → "12.3456", 2000.0 → "2000", 1e-06 → "1e-06"); for a
    fixed parameter, which has no error to round to."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def format_value_error(value: float, error: float, unit: str = "") -> str:
    """``533 ± 13 Ω``, ``0.01235 ± 0.00067``, ``(1.0002 ± 0.0028)e-06 F``, ``2.2e+07 ±
    2.8e+15 Ω`` (a value below its error): `round_to_error` as text (the value alone where
    there is no error)."""
    number, err, exponent = round_to_error(value, error)
    label = unit_text(unit) if unit else ""
    if not err:
        text = number
    elif exponent:
        text = f"({number} ± {err})e{exponent:+03d}"
    else:
        text = f"{number} ± {err}"
    return f"{text} {label}" if label else text


def latex_unit(unit: str) -> str:
    """A parameter's unit (its element spec's spelling) in plain LaTeX math, no package needed:
    ``Ohm`` → ``$\\Omega$``, ``Ohm s^-1/2`` → ``$\\Omega\\,\\mathrm{s}^{-1/2}$``, ``F s^(alpha-1)``
    → ``$\\mathrm{F}\\,\\mathrm{s}^{\\alpha-1}$``; a dimensionless ``1`` as nothing."""
    if not unit or unit == "1":
        return ""
    parts = []
    for token in unit.split():
        base, _, power = token.partition("^")
        base = r"\Omega" if base.lower() == "ohm" else rf"\mathrm{{{base}}}"
        power = re.sub(r"\balpha\b", r"\\alpha", power[1:-1] if power.startswith("(") and power.endswith(")") else power)
        parts.append(f"{base}^{{{power}}}" if power else base)
    return "$" + r"\,".join(parts) + "$"


def latex_number(text: str) -> str:
    """A number as Python writes it in LaTeX math, without the ``$``: "2.2e+07" → ``2.2
    \\times 10^{7}``, "533" as it is."""
    mantissa, e, power = text.partition("e")
    return f"{mantissa} \\times 10^{{{int(power)}}}" if e and power.lstrip("+-").isdigit() else text


def latex_value_error(value: float, error: float, *, exact: bool = False) -> str:
    """`round_to_error` in LaTeX math: ``$533 \\pm 13$``, ``$(1.0002 \\pm 0.0028) \\times
    10^{-6}$``, ``$2.2 \\times 10^{7} \\pm 2.8 \\times 10^{15}$`` (a value below its error,
    each with its own power of ten); the value alone where there is no error, to 5 significant
    digits or, ``exact``, as given (`exact_number`: a fixed value)."""
    number, err, exponent = round_to_error(value, error)
    if not err:
        return f"${latex_number(exact_number(value) if exact and math.isfinite(value) else number)}$"
    pair = f"{latex_number(number)} \\pm {latex_number(err)}"
    return f"$({pair}) \\times 10^{{{exponent}}}$" if exponent else f"${pair}$"


def latex_text(text: str) -> str:
    """``text`` with LaTeX's special characters escaped (``R_sc`` → ``R\\_sc``)."""
    special = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_", "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}
    return "".join(special.get(c, c) for c in text)


def concise_repr(result) -> str:
    """``Name(field=value, ...)`` of a result dataclass in one or a few lines: arrays and
    Datasets by their shape, long sequences by their length, long texts cut. The generated
    repr printed every array, hundreds of lines for one fit; ``report()`` says what it means."""
    import dataclasses

    parts = []
    for f in dataclasses.fields(result):
        if not f.repr:
            continue
        value = getattr(result, f.name)
        if isinstance(value, (xr.Dataset, xr.DataArray)):
            text = f"<{type(value).__name__} {dict(value.sizes)}>"
        elif hasattr(value, "shape") and hasattr(value, "dtype") and getattr(value, "ndim", 0) > 0:
            text = f"<{value.dtype} array {tuple(value.shape)}>"
        elif isinstance(value, (tuple, list, dict)) and len(value) > 6:
            text = f"<{len(value)} {'entries' if isinstance(value, dict) else 'items'}>"
        else:
            text = " ".join(repr(value).split())  # (one line: a nested result's repr may hold a NumPy array's lines)
            text = text if len(text) <= 100 else text[:97] + "…"
        parts.append(f"{f.name}={text}")
    return f"{type(result).__name__}({', '.join(parts)})"


def report_text(result) -> str:
    """``str(result)``, what ``print(result)`` shows: its ``report()``, the text the command line
    prints (the repr stays `concise_repr`; ``print(fit)``, the first thing a user types,
    gives the report, not the fields)."""
    return result.report()


def format_relative_error(ratio: float) -> str:
    """A relative standard error for a table: ``3.8 %``, ``0.52 %``, ``126 %`` (whole percent from
    10 %, where ``1.3e+02 %`` read badly), ``1.2e+12 %`` from 10⁴ % up; ``—`` when not finite."""
    percent = abs(ratio) * 100
    if not np.isfinite(percent):
        return "—"
    return f"{percent:.0f} %" if 9.95 <= percent < 9999.5 else f"{percent:.2g} %"


def format_percent(ratio: float) -> str:
    """A relative misfit as a percentage, 3 significant digits and no exponent: ``77.5 %``,
    ``0.426 %``, ``100 %`` (``{:.2g}`` had written ``1e+02 %``); ``—`` when not finite."""
    percent = abs(ratio) * 100
    if not np.isfinite(percent):
        return "—"
    text = f"{percent:.3g}"
    return (f"{percent:.0f}" if "e" in text else text) + " %"


def format_percent_column(ratios: Sequence[float], digits: int = 3) -> list[str]:
    """Ratios as one text-table column of percentages (no ``%``), their decimal points in one
    place: each value to ``digits`` significant digits, trailing zeros kept (``2.80`` under
    ``3.12``), padded on the left to the widest integer part and on the right to the widest
    fraction (``77.5  `` over `` 0.426``, not ``77.500``: a common number of decimals would
    write digits the value does not have); ``0`` for a value ``{:.3g}`` writes with an exponent
    below 1 (an exact fit's 1e-10 %), whole numbers from 1000 on, ``—`` where not finite. Each
    value reads as `format_percent` writes it (which drops the trailing zeros); free text keeps
    `format_percent`."""
    texts = []
    for ratio in ratios:
        percent = abs(float(ratio)) * 100
        text = f"{percent:#.{digits}g}" if math.isfinite(percent) else "—"
        texts.append(f"{percent:.0f}" if "e" in text else text.rstrip("."))  # ("123." of the alternate form: "123")
    whole = [t.split(".")[0] for t in texts]
    fraction = [t[len(w):] for t, w in zip(texts, whole)]
    width_whole, width_fraction = max(map(len, whole), default=0), max(map(len, fraction), default=0)
    return [w.rjust(width_whole) + f.ljust(width_fraction) for w, f in zip(whole, fraction)]


def format_factor(ratio: float, digits: int = 2) -> str:
    """A factor for text, before its ``×``: ``digits`` significant, written out from 1 to 10⁶
    (``180``, not ``:.2g``'s ``1.8e+02``), as Python writes it otherwise (``2.5``, ``0.0042``,
    ``2.5e+07``)."""
    text = f"{ratio:.{digits}g}"
    return f"{float(text):.0f}" if "e" in text and 1 <= abs(ratio) < 1e6 else text


_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def format_lambda(value: float, digits: int = 3) -> str:
    """A dimensionless λ as written by hand: ``0.0125``, ``2.6×10⁻⁵``, ``10⁻⁸`` (no e-notation;
    the DRT's report and its figure's legend alike)."""
    text = f"{value:.{digits}g}"
    if "e" not in text:
        return text
    mantissa, exponent = text.split("e")
    power = f"10{str(int(exponent)).translate(_SUPERSCRIPT)}"
    return power if mantissa == "1" else f"{mantissa}×{power}"


def format_time(tau: float, digits: int = 3) -> str:
    """A time constant [s] for text: ``2 ms``, ``0.3 s``, ``40 µs`` (``digits`` significant)."""
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 1e-9)):
        if tau >= scale or unit == "ns":
            return f"{float(f'{tau / scale:.{digits}g}'):g} {unit}"
    return f"{tau:.{digits}g} s"
