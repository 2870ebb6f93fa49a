"""The one set-up every fitting method shares: a spectrum from a path or a Dataset, checked,
with its frequency band selected (``fmin``/``fmax``) and, for methods that take one spectrum,
extra dimensions refused with a message that says what to do; the parameter table; the
weighting of the residuals."""

from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..arguments import format_given_frequency, shown
from ..circuits import DEFAULT_REGISTRY, Circuit, from_impedance_py, parse
from ..circuits.parser import ARGUMENT_ORDERS
from ..data import format_band, format_frequency, make_spectrum, validate_spectrum
from ..errors import IN_MEMORY, ArgumentsSwapped, DataError, FitError, ImpedaxError, ParameterError
from ..io.table import ROLES
from .parameters import ParameterTable

WEIGHTINGS = {
    "unit": "no weighting: absolute residuals Z_model − Z_data [Ω]",
    "modulus": "both parts divided by |Z_data| (relative error; the default)",
    "proportional": "Re divided by |Re Z_data| and Im by |Im Z_data| separately",
    "sigma": "divided by the per-point standard deviation `sigma` of the data (true chi²)",
}

WEIGHTING_SCALES = {"modulus": "|Z|", "proportional": "|Re Z| and |Im Z|", "unit": "1 Ω"}
"""What each weighting of `WEIGHTINGS` but sigma divides the residuals by: the scale a chi2_red
is measured against when it is not the noise (`FitResult.report`, `Diagnosis.report`)."""


@dataclass(frozen=True, eq=False)
class Spectrum:
    """A checked spectrum Dataset and where it came from (a path, or the Dataset's ``source``);
    ``band``: the limits that left out some of its points (`band_text`: "at or above fmin = 10
    Hz"), None when fmin and fmax left out none."""

    data: xr.Dataset
    source: str
    band: str | None = None

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
        raise DataError(f"no frequencies {band_text(fmin, fmax)} (the data span {format_band(f.min(), f.max())})", path=source)
    return ds.isel(frequency=np.flatnonzero(keep)) if not keep.all() else ds


def band_text(fmin: float | None, fmax: float | None) -> str:
    """The band ``fmin``..``fmax`` [Hz] in the words of messages: ``at or above fmin = 1 MHz``,
    ``at or below fmax = …``, ``from fmin = … to fmax = …``, each frequency as
    `format_given_frequency` writes it (``1 MHz``; ``99999 Hz`` as given) (the command line names its --fmin and --fmax
    there: `impedax.cli.common.option_words`)."""
    if fmax is None:
        return f"at or above fmin = {format_given_frequency(fmin)}"
    if fmin is None:
        return f"at or below fmax = {format_given_frequency(fmax)}"
    return f"from fmin = {format_given_frequency(fmin)} to fmax = {format_given_frequency(fmax)}"


def open_spectrum(data: xr.Dataset | str | os.PathLike, *, fmin: float | None = None, fmax: float | None = None, single: str | None = None) -> Spectrum:
    """Load (a path) or check (a Dataset) a spectrum and select its band.

    ``single``: the name of a method that takes one spectrum (``"diagnose"``, ...); data with
    extra dimensions (trial, session, ...) then raise `DataError` naming it.
    """
    data = spectrum_argument(data)
    if isinstance(data, str) and circuit_text(data):
        order = ARGUMENT_ORDERS if single not in ARGUMENT_ORDER else f"{single} takes {ARGUMENT_ORDER[single]}"
        raise DataError(f"data {shown(data)} is circuit text, not a spectrum or a file: the arguments look swapped ({order})")
    if isinstance(data, xr.Dataset):
        source = str(data.attrs.get("source", "dataset"))
        validate_spectrum(data, source=source)
    else:
        from ..io import load

        source = str(data)
        data = load(data)
    selected = select_band(data, fmin, fmax, source)
    spectrum = Spectrum(selected, source, band_text(fmin, fmax) if selected.sizes["frequency"] < data.sizes["frequency"] else None)
    check_magnitudes(spectrum.data["frequency"], abs(spectrum.data["Z"]), source)
    if single is not None and spectrum.extra_dims:
        raise DataError(
            f"{single} takes one spectrum; these data hold several (extra dimensions {', '.join(spectrum.extra_dims)}): "
            f"select one first (data.isel({spectrum.extra_dims[0]}=0), data.sel({spectrum.extra_dims[0]}=label); "
            f"the command line's --select {spectrum.extra_dims[0]}=LABEL) or average them",
            path=source,
        )
    return spectrum




def circuit_parameters(arguments) -> tuple[tuple[str, ...], dict[str, str]]:
    """The parameter names of a call's ``circuit`` (impedax text, else impedance.py text, or a
    `Circuit`) and its ``registry``'s impedance.py symbols: `impedax.arguments.CircuitParameters`,
    for the messages answering impedance.py's keywords (``constants=``, ``initial_guess=``)."""
    registry = arguments.get("registry", DEFAULT_REGISTRY)
    circuit = arguments["circuit"]
    if isinstance(circuit, str):
        try:
            circuit = parse(circuit, registry)
        except ImpedaxError:
            circuit = from_impedance_py(circuit, registry)
    return circuit.parameter_names(registry), dict(registry.impedance_py_symbols)


def circuit_text(text: str) -> bool:
    """Whether a data argument ``text`` is circuit text rather than a path: no such file, and
    it parses as a circuit of the default elements, in impedax's notation or impedance.py's
    (``R0-p(R1,CPE1)``, which a walkthrough passed as data and was told "file not found")."""
    if os.path.exists(text) or text.strip() in ("", "-"):
        return False
    for reader in (parse, from_impedance_py):
        try:
            reader(text)
        except ImpedaxError:
            continue
        return True
    return False


def looks_like_circuit(value) -> bool:
    """Whether an argument is a circuit: a `Circuit`, or text that names no file and parses
    as one (`circuit_text`)."""
    return isinstance(value, Circuit) or (isinstance(value, str) and circuit_text(value))


def looks_like_spectrum(value) -> bool:
    """Whether an argument is a spectrum: a Dataset or DataArray, a path object, text naming an
    existing file, or a (frequency, Z) pair of arrays."""
    if isinstance(value, (xr.Dataset, xr.DataArray)) or hasattr(value, "__fspath__"):
        return True
    if isinstance(value, str):
        return "\x00" not in value and os.path.isfile(value)
    return is_pair(value)


def _described(value) -> str:
    """An argument named in a few words: a circuit by its text, a spectrum by its type or path."""
    if isinstance(value, Circuit):
        return shown(str(value))
    if isinstance(value, str):
        return shown(value)
    return f"a {type(value).__name__}"


# the public functions that take a circuit and a spectrum, in this order (named when the two look
# swapped: `check_argument_order`, and `open_spectrum` for the functions that pass their name as
# ``single``; fit, which passes none there, gets `parser.ARGUMENT_ORDERS`)
ARGUMENT_ORDER = {"fit": "(circuit, data)", "sample": "(circuit, data)", "diagnose": "(data, circuit)", "refine": "(data, circuit)"}


def check_argument_order(function: str, first, second) -> None:
    """`ArgumentsSwapped` when ``function``'s two positional arguments (``first``, ``second`` in
    its order, `ARGUMENT_ORDER`) hold a circuit and a spectrum in each other's places: the data
    slot a circuit (a `Circuit` or circuit text) and the circuit slot a spectrum (a Dataset, a
    path, a (frequency, Z) pair). A walkthrough's ``ix.diagnose(circuit, data)`` was told only
    "data must be a spectrum Dataset … got Series([Element('R0')…"."""
    order = ARGUMENT_ORDER[function]
    circuit, data = (first, second) if order == "(circuit, data)" else (second, first)
    if not (looks_like_circuit(data) and looks_like_spectrum(circuit)):
        return
    first_kind, second_kind = ("data", "a circuit") if order == "(circuit, data)" else ("a circuit", "data")
    raise ArgumentsSwapped(
        f"the arguments look swapped ({function} takes {order}): the first argument looks like {first_kind} ({_described(first)}) "
        f"and the second like {second_kind} ({_described(second)}); call impedax.{function}{order}"
    )


MAX_MAGNITUDE = 1e100  # |Z| [Ω] and f [Hz] whose squares and products stay finite in float64


def check_magnitudes(frequency, magnitude, source: str) -> None:
    """`DataError` when |Z| or f lies outside [1/`MAX_MAGNITUDE`, `MAX_MAGNITUDE`]: the
    methods square and multiply them (|Z|², ωτ), which would overflow or underflow float64.
    Such values are read unchanged (`impedax.load`) but not analysed."""
    for name, values, unit in (("|Z|", magnitude, "Ω"), ("frequency", frequency, "Hz")):
        # NumPy arrays or DataArrays: dask-backed ones reduce chunk by chunk, the others in
        # NumPy (xarray's `where` costs milliseconds, as much as a fit that stops at its guess)
        if getattr(values, "chunks", None) is None:
            values = np.asarray(values)
        positive = values.where(values > 0) if hasattr(values, "where") else np.where(values > 0, values, np.nan)
        with warnings.catch_warnings():  # (all zero: nothing to check here; the weighting says so)
            warnings.simplefilter("ignore", RuntimeWarning)
            high, low = float(np.nanmax(positive)), float(np.nanmin(positive))
        if math.isfinite(high) and (high > MAX_MAGNITUDE or low < 1.0 / MAX_MAGNITUDE):
            raise DataError(
                f"{name} spans {low:.3g}–{high:.3g} {unit}, outside the range impedax analyses "
                f"({1.0 / MAX_MAGNITUDE:g}–{MAX_MAGNITUDE:g}); rescale the data (e.g. to kΩ or MHz)",
                path=source,
            )


def spectrum_argument(data):
    """``data`` as a public function takes it: a spectrum Dataset or a path, returned as it is;
    a DataArray of complex Z over ``frequency`` or a (frequency, Z) pair of arrays becomes a
    Dataset (`spectrum_of_pair`); anything else (None, a NumPy array, a list of numbers) is a
    `DataError` that says what to pass."""
    if isinstance(data, str) and "\x00" in data:
        raise DataError(f"a file name cannot contain a NUL character: {shown(data)}")
    if isinstance(data, xr.Dataset) or isinstance(data, str) or hasattr(data, "__fspath__"):
        return data
    if is_pair(data):
        return spectrum_of_pair(data)
    if isinstance(data, xr.DataArray):
        if "frequency" not in data.dims or not np.issubdtype(data.dtype, np.complexfloating):
            raise DataError(
                f"a DataArray of complex Z over a 'frequency' dimension can be used as data; this one has dims {data.dims} and dtype {data.dtype}",
                path=str(data.attrs.get("source", "DataArray")),
            )
        return data.to_dataset(name="Z")
    if isinstance(data, Circuit):  # (a circuit alone, e.g. refine(circuit) with its default circuit)
        raise DataError(f"data must be a spectrum Dataset, a file path or a (frequency, Z) pair of arrays, got a circuit ({shown(str(data))}): "
                        f"the circuit goes in the other argument ({ARGUMENT_ORDERS})")
    raise DataError(
        f"data must be a spectrum Dataset (impedax.make_spectrum, impedax.load), a file path or a (frequency, Z) pair of arrays, got {shown(data)} ({type(data).__name__})"
    )


def is_pair(data) -> bool:
    """Whether ``data`` is a (frequency, Z) pair: a tuple or list of two arrays (or lists), not
    of two numbers, strings or Datasets."""
    if not isinstance(data, (tuple, list)) or len(data) != 2:
        return False
    return all(not isinstance(item, (str, bytes, xr.Dataset)) and (isinstance(item, (list, tuple)) or np.ndim(item) >= 1) for item in data)


def spectrum_of_pair(pair) -> xr.Dataset:
    """A (frequency [Hz], complex Z [Ω]) pair as a spectrum Dataset, checked by `make_spectrum`;
    Z's dimensions before frequency are named ``dim_0``, ``dim_1``, ...."""
    frequency, z = pair
    try:
        extra = max(np.ndim(z) - 1, 0)
    except ValueError:  # a ragged list: make_spectrum names it
        extra = 0
    return make_spectrum(frequency, z, dims=tuple(f"dim_{i}" for i in range(extra)))


@dataclass(frozen=True, eq=False)
class FitProblem:
    """A circuit, the spectrum it is fitted to (band selected), its parameter table and the
    data's source (for messages)."""

    circuit: Circuit
    data: xr.Dataset
    table: ParameterTable
    source: str


def prepare_fit(circuit, data, *, init, fixed, bounds, fmin, fmax, registry) -> FitProblem:
    """The set-up of every least-squares method: the circuit parsed, the spectrum loaded and
    band-selected, the parameter table built, and enough data for the free parameters."""
    return fit_problem(circuit, open_spectrum(data, fmin=fmin, fmax=fmax), init=init, fixed=fixed, bounds=bounds, registry=registry)


def fit_problem(circuit, spectrum: Spectrum, *, init, fixed, bounds, registry) -> FitProblem:
    """`prepare_fit` on a spectrum already opened (`open_spectrum`): for many circuits on one spectrum."""
    circuit = parse(circuit, registry)
    data, source = spectrum.data, spectrum.source
    _refuse_repeated_labels(data, source)
    table = ParameterTable.build(circuit, registry=registry, init=init, fixed=fixed, bounds=bounds)
    n_points = data.sizes["frequency"]
    k = int((~table.fixed).sum())
    if k >= 2 * n_points:
        # (the band the user's limits left, when they left out points: "1 frequency" alone would send
        # the user to the file, which holds 31)
        frequencies = f"{n_points} frequenc{'y' if n_points == 1 else 'ies'}" + (f" {spectrum.band}" if spectrum.band else "")
        where = "" if source in (None, "", "dataset", IN_MEMORY) else f"{source}: "  # (the file, when the data came from one)
        raise FitError(f"{where}{k} free parameters but only {2 * n_points} real data values ({frequencies}); fix parameters or use more data" + (" (a wider band)" if spectrum.band else ""))
    return FitProblem(circuit, data, table, source)


def _refuse_repeated_labels(data: xr.Dataset, source) -> None:
    """`DataError` when a dimension of a batch repeats a label: its fits are kept and found by
    label (warnings by spectrum, `fit_of`, ``init=batch``), and ten spectra labelled cycle=1 would be
    fitted, their warnings folded into one entry and `fit_of(cycle=1)` give one of them without a
    word."""
    for d in data["Z"].dims:
        if d == "frequency" or d not in data.coords:
            continue
        index = data.get_index(d)
        if index.has_duplicates:
            repeated = ", ".join(str(v) for v in index[index.duplicated()].unique()[:5])
            raise DataError(f"the labels along {d} repeat ({repeated}): each spectrum of a batch is found by its label; give each its own "
                            f"(Python: data.assign_coords({d}=range({data.sizes[d]}))) or fit them apart (impedax fit --select {d}=LABEL picks one label's)", path=source)


SIGMA_SOURCES = (
    f"a column headed {', '.join(sorted(ROLES['sigma'])[:-1])} or {sorted(ROLES['sigma'])[-1]} (σ in Ω, one for Re and for Im: separate σ of Re and of Im are not read), "
    "or make_spectrum(sigma=...)"
)
"""Where a 'sigma' variable comes from, for the errors that ask for one (a walkthrough's file with
``sigma_re``, ``sigma_im`` columns was told only that a 'sigma' variable was missing)."""


def weights(z: np.ndarray, sigma: np.ndarray | None, weighting: str, source: str, frequency=None):
    """Inverse weights (1/w_re, 1/w_im) of the real and imaginary residuals for `WEIGHTINGS`;
    ``frequency`` [Hz] (Z's last axis) names the points whose weight is zero."""
    empty = np.all(np.asarray(z) == 0, axis=-1)  # (a spectrum of zeros: no weighting makes it fittable; unit weighting "fitted" it)
    if np.any(empty):
        first = tuple(int(i) for i in np.argwhere(empty)[0]) if np.ndim(empty) else ()
        which = f" of spectrum {first if len(first) > 1 else first[0]}" if first else ""
        raise DataError(f"Z = 0 at every one of the {np.shape(z)[-1]} points{which}: no impedance was recorded (a lead not connected, a failed sweep?); nothing to fit", path=source)
    if weighting not in WEIGHTINGS:
        raise ParameterError(f"unknown weighting {weighting!r}; choose one of {', '.join(WEIGHTINGS)}")
    if weighting == "unit":
        w_re = w_im = np.ones(z.shape)
    elif weighting == "modulus":
        w_re = w_im = np.abs(z)
    elif weighting == "proportional":
        floor = 1e-9 * np.abs(z)
        w_re, w_im = np.maximum(np.abs(z.real), floor), np.maximum(np.abs(z.imag), floor)
    else:
        if sigma is None:
            raise DataError(f"weighting='sigma' needs a 'sigma' variable in the data (e.g. the SEM of repeated trials): {SIGMA_SOURCES}", path=source)
        w_re = w_im = sigma
    bad = ~np.isfinite(w_re) | (w_re <= 0) | ~np.isfinite(w_im) | (w_im <= 0)
    if np.any(bad):
        raise DataError(f"weighting {weighting!r}: {_zero_weight_text(z, bad, frequency)}", path=source)
    return 1.0 / w_re, 1.0 / w_im


def _zero_weight_text(z: np.ndarray, bad: np.ndarray, frequency) -> str:
    """Where the weights are zero or not finite, and what to do: the first such point (its
    frequency and number, its spectrum in a batch) and how many there are."""
    where = np.argwhere(np.broadcast_to(bad, np.shape(z)))
    first = tuple(int(i) for i in where[0])
    k = first[-1]
    point = f"f={format_frequency(float(np.asarray(frequency)[k]))} (point {k})" if frequency is not None else f"point {k}"
    if len(first) > 1:
        point += f" of spectrum {first[:-1] if len(first) > 2 else first[0]}"
    more = f" and {len(where) - 1} more point{'s' * (len(where) > 2)}" if len(where) > 1 else ""
    return f"zero or non-finite weight at {point}{more}, where |Z| = {abs(z[first]):g} Ω; drop the point or use weighting='unit'"


def residual_scale(z, inv_re, inv_im, weighting: str) -> np.ndarray:
    """A constant per spectrum that brings the weighted residuals to the size of relative
    ones (exactly 1 for modulus weighting). Levenberg–Marquardt's damping is absolute, so
    with residuals of 1e10 Ω (unit weighting of teraohm data) it would take undamped
    Gauss–Newton jumps; the minimiser is unchanged and chi² and the Jacobian are scaled back."""
    if weighting == "modulus":
        return np.ones(np.shape(z)[:-1])
    typical = np.median(np.abs(z) * np.sqrt(0.5 * (np.asarray(inv_re) ** 2 + np.asarray(inv_im) ** 2)), axis=-1)
    return 1.0 / np.where(np.isfinite(typical) & (typical > 0), typical, 1.0)


def frequency_and_z(data):
    """The preamble of the array-based tests (KK, DRT, Z-HIT): (frequency (N,), Z (*extra, N),
    extra dims, extra coords, source) from a spectrum Dataset, a file path or a (frequency, Z)
    pair (`spectrum_of_pair`, as `fit` takes it), checked; `DataError` on anything else."""
    return frequency_z_and_sigma(data)[:5]


def frequency_z_and_sigma(data):
    """`frequency_and_z`'s five, then the data's stated σ [Ω] (of Re and of Im) broadcast to Z's
    shape (*extra, N), or None when the data carry no ``sigma`` variable (the
    KK test weighs and judges by it)."""
    if is_pair(data):
        data = spectrum_of_pair(data)
    if isinstance(data, (str, bytes)) or hasattr(data, "__fspath__") or isinstance(data, (xr.Dataset, xr.DataArray)):
        spectrum = open_spectrum(data)
        ds, dims = spectrum.data, spectrum.extra_dims
        z = ds["Z"].transpose(*dims, "frequency")
        coords = {d: np.asarray(ds[d].values) for d in dims if d in ds.coords}
        sigma = None
        if "sigma" in ds.data_vars:
            sigma = np.asarray(xr.broadcast(ds["sigma"], ds["Z"])[0].transpose(*dims, "frequency").values, float)
        return np.asarray(ds["frequency"].values, float), np.asarray(z.values, complex), dims, coords, spectrum.source, sigma
    raise DataError(f"expected a spectrum Dataset, a file path or a (frequency, Z) pair of arrays, got {type(data).__name__}")
