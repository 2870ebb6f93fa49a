"""Batch fits: every spectrum of a Dataset with extra dimensions in one compiled call.

Dask-backed data are fitted chunk by chunk through ``xarray.apply_ufunc(...,
dask="parallelized")``, so the same call scales out on a ``dask.distributed`` cluster.
"""

from __future__ import annotations

import datetime
import functools
import math
import time
import warnings as python_warnings
from dataclasses import dataclass, field, replace
from typing import Callable, Mapping

import jax
import numpy as np
import xarray as xr

from ...arguments import unknown_parameter
from ...circuits import Circuit, DEFAULT_REGISTRY, Registry
from ...circuits.nesting import carried_values
from ...data import column_width, concise_repr, exact_number, report_text, coordinate_labels, counted, format_band, format_percent_column, format_relative_error, label_text, label_value, unit_text
from ...errors import DataError, ParameterError
from ...io.netcdf import result_dataset
from ...progress import say, silenced
from ...warning_groups import LABELS_SHOWN, grouped_warnings, labels_text, warning_kinds
from ..frozen import FrozenResult, KeyHintDict, freeze_fields
from ..grid import refuse_result_names
from ..kk import KKChains
from ..parameters import ParameterTable
from ..problem import residual_scale, weights
from ..statistics import SINGULAR_RATIO_LIMIT, UNKNOWN_VARIANCE, at_noise_floor, covariances, fit_noise, information_criteria, non_passive, null_sets
from .order import canonical_order
from .branches import RELATIVE_ERROR_LIMIT, held_covariances, idle_branch_notes, settle_vanishing, vanishing_term_mask, undetermined, unidentified_stderr, undetermined_mask, vanishing_candidates, vanishing_parameters
from .constraints import constraint_misfit_notes, with_constraint_notes
from .notes import MISFIT, MODEL_MISFIT, carried_over, has_tag, notes_tags, stored_tags, tagged, tags_attr, tags_of, with_tag
from .result import value_shown_at_bound, sign_notes_first, settled_codes, stored_notes, warnings_blame_model, misfit_hint_spectra, MISFIT_CHECKED_FROM, MISFIT_RATIO_MAX, COVARIANCE_NOTE, BOUND_RESTARTS, FIT_STATISTICS, bounds_attr, is_remainder, parameter_groups, LINEARISED_STDERR_NAME, PARAMETER_UNIT_NAME, STDERR_NOTE, bound_sides, confirm_bounds, falling_inward, fit_result, gross_misfits, misfit_notes, non_passive_notes, warning_tags_by_words, sigma_misstated, sigma_scale_notes, trial_means_of_sigma, uneven_residual_notes, shown_stderr, stack_notes, vanishing_term_sides, dominated_notes, without_error
from .solvers import SCREEN_STEPS, SharedArgs, SolverOutput, SolverStatus, SpectrumRows, TreeSolvers, better, over_devices, padded_points, tree_solver, unscale
from .starts import SpectrumFeatures, climb_target, draw_size, batch_outliers, escalation_rungs, guess_start, inward_start, limit_starts, rms_rel_of, rung_seed, rung_starts, to_solver_space, values_inside

__all__ = ["BatchFitResult", "fit_batch", "labels_by_keyword"]

_STATS = ("chi2", "converged", "n_evaluations")

LONG_TABLE_ROWS = 40
"""The most spectra `BatchFitResult.to_latex` writes as a ``tabular``, which a page of A4 or
letter at 10–12 pt holds (about 45 rows below a caption); more become a ``longtable``, which
breaks across pages."""


_spectrum_fit: Callable | None = None
"""`single.fit`, registered by that module (`register_spectrum_fit`) for `BatchFitResult.fit_of`:
batch.py may not import it, since single.py imports batch.py."""


def register_spectrum_fit(fit: Callable) -> None:
    """Let `BatchFitResult.fit_of` refit one spectrum with ``fit`` (`single.fit`)."""
    global _spectrum_fit
    _spectrum_fit = fit


_COMPUTED_HERE = object()  # (`BatchFitResult.report`'s misfit_hints not given: it computes them)


def labels_by_keyword(method: Callable) -> Callable:
    """A method that picks one spectrum by its labels, one keyword per batch dimension
    (``fit_of(cycle=64)``), made to refuse a positional argument with a `ParameterError` that
    says how to call it (the batch's dimensions, an example with a real label) instead of
    Python's bare TypeError (README: impedax's functions raise its own errors, naming the
    argument). A position is refused even along one dimension: there a label and a position
    differ as soon as the labels do not count from 0 (cycles 1, 2, …), and a spectrum picked by
    the wrong one would go unnoticed. ``self`` has ``dims`` and ``dataset`` (the labels)."""

    @functools.wraps(method)
    def by_labels(self, *positional, **labels):
        if positional:
            raise ParameterError(positional_labels_message(method.__name__, positional, self.dims, self.dataset))
        return method(self, **labels)

    return by_labels


def positional_labels_message(what: str, positional: tuple, dims: tuple[str, ...], ds: xr.Dataset) -> str:
    """The message of `labels_by_keyword`: ``what`` (the method) called with ``positional``
    on a batch over ``dims`` (labels from ``ds``, a dimension without coordinates by position)."""
    labels = {d: coordinate_labels(ds, d) for d in dims}
    example = {d: (labels[d][0] if labels[d] else 0) for d in dims}
    given = positional[0]
    note = ""
    if len(dims) == 1 and len(positional) == 1:
        (dim,) = dims
        if given in labels[dim]:  # (a label: the keyword was left out)
            example[dim] = given
        elif isinstance(given, (int, np.integer)) and not isinstance(given, bool) and -len(labels[dim]) <= given < len(labels[dim]):
            example[dim] = labels[dim][int(given)]
            note = f"; {given!r} is not among the labels along {dim}: the spectrum at position {int(given)} is the one with {dim}={example[dim]!r}"
        shown = ", ".join(map(repr, labels[dim][:6])) + (", …" if len(labels[dim]) > 6 else "")
        note += f" (the labels along {dim}: {shown})"
    call = f"{what}(" + ", ".join(f"{d}={v!r}" for d, v in example.items()) + ")"
    return (f"{what} takes the spectrum by its labels, one keyword per batch dimension ({', '.join(dims)}), not by position: {call}{note}")


@dataclass(frozen=True, eq=False)
class BatchFitResult(FrozenResult):
    """Fits of one circuit to every spectrum of a Dataset with extra dimensions. Immutable.

    ``dataset`` holds ``value``/``stderr`` over (param, *dims) (stderr NaN at a bound, inf for a
    vanishing term's parameter, as `FitResult`; ``linearised_stderr`` gives one at a bound as
    `FitResult.linearised_stderr`), ``rms_rel``, ``chi2``,
    ``chi2_red``, ``aic``, ``bic``, ``converged`` over dims, ``at_bound`` (whether a parameter
    is at a natural or user bound) over (param, *dims), the bounds themselves (``lower``,
    ``upper`` over param), the data ``Z`` and ``Z_model`` over (*dims, frequency) and each
    spectrum's ``covariance`` of its free parameters over (*dims, free_param, free_param_2), as
    `FitResult.covariance` (what `derive` propagates; absent from files of older versions). ``warnings`` maps a spectrum's index (a dict of coordinates, as text)
    to its warnings; ``dataset.attrs["unidentified_groups"]`` the same index to its
    unidentified groups (`FitResult.unidentified_groups`, only spectra that have any;
    `unidentified_groups_of`).
    """

    __repr__ = concise_repr  # (the generated one printed every array)
    __str__ = report_text  # (print(result): its report)

    circuit: Circuit
    dataset: xr.Dataset
    weighting: str
    warnings: dict[str, tuple[str, ...]]
    elapsed_s: float = 0.0
    registry: Registry = field(default=DEFAULT_REGISTRY, repr=False)
    source: str | None = field(default=None, repr=False)  # where the data came from (their ``attrs["source"]``), None if unknown: `impedax.write_result` records it
    notes: tuple[str, ...] = ()  # advice for every spectrum that is not a warning, as `FitResult.notes`
    warning_tags: dict[str, tuple[tuple[str, ...], ...]] | None = field(default=None, repr=False)  # each spectrum's (key of ``warnings``) tags of its warnings, in their order, as `FitResult.warning_tags`; None: not known, read from the words
    _tags_given_with: tuple | None = field(default=None, repr=False)  # (the warnings and tags ``warning_tags`` were set with, as `FitResult`'s: `notes.carried_over`)

    @property
    def model_misfits(self) -> tuple[str, ...] | None:
        """The spectra (keys of ``warnings``) whose warnings blame the model (`notes.MODEL_MISFIT`,
        as `FitResult.model_misfit`); None: not known (`misses_structure` then reads the words)."""
        if self.warning_tags is None:
            return None
        return tuple(k for k, tags in self.warning_tags.items() if any(has_tag(t, MODEL_MISFIT) for t in tags))

    def tagged_warnings(self, key: str) -> tuple[str, ...]:
        """Spectrum ``key``'s warnings as `notes.Note`s carrying their tags (plain texts where not
        known), as `FitResult.tagged_warnings`."""
        return tagged(self.warnings.get(key, ()), None if self.warning_tags is None else self.warning_tags.get(key, ((),) * len(self.warnings.get(key, ()))))

    def spectrum_warning_tags(self, key: str) -> tuple[tuple[str, ...], ...]:
        """Spectrum ``key``'s warnings' tags, in their order (`warning_tags`), or, where they are
        not known, those the words say (`result.warning_tags_by_words`), as
        `result.fit_warning_tags` gives a single fit's: a JSON row's ``warning_tags``."""
        warnings = self.warnings.get(key, ())
        if self.warning_tags is None:
            return warning_tags_by_words(warnings)
        return tuple(tuple(t) for t in self.warning_tags.get(key, ((),) * len(warnings)))

    def __post_init__(self):
        warnings, tags = {k: tuple(v) for k, v in self.warnings.items()}, self.warning_tags
        if tags is not None and (set(tags) != set(warnings) or any(len(tags[k]) != len(w) for k, w in warnings.items()) or carried_over(warnings, tags, self._tags_given_with)):  # (``warnings`` replaced alone, not by `batch_with_warnings`: the tags are not theirs; `notes.Note`s bring their own)
            tags = {k: notes_tags(v) for k, v in warnings.items()} if any(tags_of(n) for v in warnings.values() for n in v) else None
            object.__setattr__(self, "warnings", {k: tuple(str(n) for n in v) for k, v in warnings.items()})
        object.__setattr__(self, "warning_tags", tags)
        object.__setattr__(self, "_tags_given_with", None)
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`); to_xarray hands out a copy
        if tags is not None:  # (the frozen mappings themselves: a copy of the result walks them no more, `frozen.read_only`)
            object.__setattr__(self, "_tags_given_with", (self.warnings, self.warning_tags))

    @property
    def model(self) -> str:
        return str(self.circuit)

    @property
    def dims(self) -> tuple[str, ...]:
        return tuple(d for d in self.dataset["rms_rel"].dims)

    @property
    def n_spectra(self) -> int:
        return int(self.dataset["rms_rel"].size)

    @property
    def n_points(self) -> int | None:
        """The frequencies each spectrum's fit used: the data's after ``fmin``/``fmax`` (and the
        command line's ``--exclude``), the same for every spectrum (a batch's Z is finite
        everywhere); None for a result stored without its spectra."""
        return int(self.dataset.sizes["frequency"]) if "frequency" in self.dataset.dims else None

    _KIND = "batch_fit"  # (`impedax_kind` of the saved result; a joint fit's is its own)

    def to_xarray(self) -> xr.Dataset:
        """``dataset`` with what `from_xarray` needs besides in its attrs: the warnings (spectrum
        → its warnings, as ``warnings``) and the time taken; and ``unit`` along ``param``, each
        parameter's unit (the element specs', as the CSV's ``unit``). Its attrs
        are Python objects (dicts of warnings and unidentified groups) that ``.to_netcdf`` refuses, its
        error saying so: a file is written with ``impedax.write_result(batch, "fits.nc")``, which
        encodes them (`impedax.io.netcdf.result_dataset`)."""
        specs = self.circuit.parameter_specs(self.registry)
        units = [specs[str(p)].unit if str(p) in specs else "" for p in self.dataset["param"].values]
        ds = self.dataset.copy(deep=True).assign_coords(unit=("param", units, {"long_name": PARAMETER_UNIT_NAME})).assign_attrs(impedax_kind=self._KIND, warnings={k: list(v) for k, v in self.warnings.items()}, elapsed_s=float(self.elapsed_s), notes=list(self.notes),
                                                                                                                           model_misfits=[k for k, _ in self.spectrum_keys() if self._blames_model(k)],
                                                                                                                           warning_tags=None if self.warning_tags is None else {k: tags_attr(v) for k, v in self.warning_tags.items()})
        return result_dataset(ds)  # (ds.to_netcdf's error then names impedax.write_result)

    @classmethod
    def from_xarray(cls, ds: xr.Dataset, *, registry: Registry | None = None) -> "BatchFitResult":
        """Rebuild a batch of fits from `BatchFitResult.to_xarray` output: as returned, read back
        by `impedax.load`, or opened as stored (``xr.open_dataset`` of a file `impedax.write_result`
        or ``impedax fit --out FILE.nc`` wrote). ``registry``: the one the circuit's elements are
        in (None: the default one). A file written by older versions may lack the warnings: none.
        ``source``: the data's file the saved result names (`impedax.io.netcdf.saved_source`)."""
        return cls._rebuilt(ds, "batch_fit", registry)

    @classmethod
    def _rebuilt(cls, ds: xr.Dataset, kind: str, registry: Registry | None, **fields):
        """``from_xarray`` of a saved result of ``kind`` (``fields``: a subclass's own, from the
        dataset)."""
        from ...circuits import parse
        from ...io.netcdf import damaged_result, saved_result, saved_source  # (io is imported only here: rarely needed)

        registry = DEFAULT_REGISTRY if registry is None else registry
        if isinstance(ds, xr.Dataset) and "impedax_kind" not in ds.attrs and _looks_like(ds) == kind:  # (written before the kind was stored)
            ds = ds.assign_attrs(impedax_kind=kind)
        ds = saved_result(ds, kind, variables=("value", "stderr", "fixed", "at_bound", "rms_rel", "converged", "Z", "Z_model"), attrs=("model", "weighting"))
        with damaged_result(kind, ds):
            warnings = {str(k): (v,) if isinstance(v, str) else tuple(str(w) for w in v) for k, v in dict(ds.attrs.get("warnings", {})).items()}
            elapsed = float(ds.attrs.get("elapsed_s", 0.0))
            dataset = ds.drop_vars("unit", errors="ignore")  # (to_xarray's, from the specs; a file of older versions has none)
            dataset.attrs = {k: v for k, v in ds.attrs.items() if k not in ("impedax_kind", "warnings", "elapsed_s", "format", "notes", "model_misfits", "warning_tags")}
            return cls(circuit=parse(ds.attrs["model"], registry), dataset=dataset, weighting=str(ds.attrs["weighting"]), warnings=warnings, elapsed_s=elapsed, registry=registry, source=saved_source(ds),
                       notes=stored_notes(ds.attrs.get("notes", ())), warning_tags=stored_batch_tags(ds.attrs, warnings), **{k: f(ds) for k, f in fields.items()})  # (notes: none in a file of older versions)

    def values(self, name: str) -> xr.DataArray:
        """Fitted values of parameter ``name`` over the batch dimensions."""
        return self.dataset["value"].sel(param=self._parameter(name, "values"))

    def stderr(self, name: str) -> xr.DataArray:
        """Standard errors of parameter ``name`` over the batch dimensions, the shape of
        `values` (NaN where fixed, inf where undetermined; as ``stderr`` in `to_xarray`):
        ``b.values(n).plot.line(x="voltage")`` with these as error bars."""
        return self.dataset["stderr"].sel(param=self._parameter(name, "stderr"))

    def per_spectrum_starts(self, data: xr.Dataset | None = None, names=None, circuit: Circuit | None = None) -> np.ndarray:
        """This batch's values as the starts of a new batch fit of ``data`` (``fit(..., init=batch)``):
        shape (*the data's extra dimensions, len(names)), each spectrum's own fitted values of the
        parameters ``names`` holds (NaN for the others: their data-driven guess); without ``data``
        this batch's own spectra, without ``names`` this batch's parameters in its order (a bare
        call is not Python's TypeError); with the new
        fit's ``circuit`` when this batch's circuit is nested in it (a W where it has a Wo), each
        spectrum's optimum carried into it (`nesting.carried_values`). The data must be
        over the same dimensions with the same sizes and labels (coordinates), in any order (a
        spectrum takes the fit with its labels); otherwise a `ParameterError` says what differs."""
        ds = self.dataset
        if data is None:
            data = ds
        elif not isinstance(data, xr.Dataset) or "Z" not in data:
            raise ParameterError(f"per_spectrum_starts: data= takes the spectra to start (an xarray Dataset with Z, as impedax.load gives), not {type(data).__name__}; "
                                 "leave it out for this batch's own spectra")
        if names is None:
            names = [str(p) for p in ds["param"].values]
        elif isinstance(names, str) or not all(isinstance(n, str) for n in names):
            raise ParameterError(f"per_spectrum_starts: names= takes a list of parameter names (e.g. {[str(p) for p in ds['param'].values[:2]]}), not {names!r}; "
                                 "leave it out for this batch's parameters")
        extra = tuple(d for d in data["Z"].dims if d != "frequency")
        if set(extra) != set(self.dims):
            raise ParameterError(
                f"init: the batch of fits is over {' × '.join(self.dims)} but the data's spectra are over {' × '.join(extra) or 'nothing (one spectrum)'}; "
                "init=batch starts each spectrum from its own optimum and needs the same dimensions"
                + ("; for one spectrum use one of its fits, e.g. init=batch.fit_of(" + ", ".join(f"{d}=…" for d in self.dims) + ")" if not extra else "")
            )
        value = ds["value"].transpose("param", *extra)
        for d in extra:
            if d in data.coords and d in ds.coords:
                # labels matched by value (pandas' index: dates in ns and in µs alike, as a file
                # read back holds them), the data's a subset of the batch's or all of them
                ours, theirs = ds.get_index(d), data.get_index(d)
                missing = theirs[~theirs.isin(ours)]
                if len(missing) or ours.has_duplicates:
                    shown = ", ".join(map(str, missing[:5])) + (", …" if len(missing) > 5 else "")
                    raise ParameterError(f"init: the data's labels along {d} are not the batch of fits' ({'not in it: ' + shown if len(missing) else 'its labels repeat'}); "
                                         "init=batch starts each spectrum from the fit with the same label: fit the spectra it has no fit for without init=")
                value = value.isel({d: ours.get_indexer(theirs)})  # each spectrum takes the fit with its label
            elif data.sizes[d] != ds.sizes[d]:
                raise ParameterError(f"init: the batch of fits has {ds.sizes[d]} spectra along {d}, the data {data.sizes[d]}, and without labels along {d} they are matched by position: "
                                     f"init=batch needs as many (label {d} in both, e.g. data.assign_coords({d}=...), to match a part of the batch by label)")
        own = {str(p): value.sel(param=p).values for p in ds["param"].values}
        if circuit is not None:
            omega = 2 * np.pi * np.asarray(ds["frequency"].values, float)
            own = carried_values(self.circuit, own, circuit, float(omega.min()), float(omega.max()), self.registry)
        out = np.full((*(data.sizes[d] for d in extra), len(names)), np.nan)
        for j, name in enumerate(names):
            if name in own:
                out[..., j] = own[name]
        return out

    def _parameter(self, name, what: str) -> str:
        """``name`` if the circuit has that parameter; else a `ParameterError` from ``what``
        (the method) naming the parameters and the closest one."""
        names = [str(p) for p in self.dataset["param"].values]
        if not isinstance(name, str) or name not in names:
            raise unknown_parameter(f"{what}()", name, names, self.model)
        return name

    @labels_by_keyword
    def fit_of(self, **labels):
        """The whole `FitResult` of one spectrum — standard errors, correlations, warnings,
        ``predict``, ``plot`` — picked by its label along every batch dimension (``cycle=64``;
        the 0-based position along a dimension without coordinates): the spectrum refitted from
        this batch's values with one start, the fixed parameters and bounds kept (a value on a bound
        nudged inside, as ``fit(..., init=batch)`` starts it), so it returns to the batch's optimum.
        Labels only, by keyword: ``fit_of(0)`` is a `ParameterError` naming the call to make, even
        for a batch of one dimension (`labels_by_keyword`; a position is the label at it,
        ``fit_of(cycle=batch.dataset.cycle.values[0])``)."""
        from ...data import make_spectrum

        if _spectrum_fit is None:  # (not reached: a BatchFitResult comes from fit, whose module registers it)
            raise ParameterError("fit_of needs impedax.fitting.least_squares.single imported")
        fit = _spectrum_fit
        ds = self.dataset
        one = ds.isel(self._spectrum_position(labels, "fit_of"))
        spectrum = make_spectrum(ds["frequency"].values, one["Z"].values, sigma=one["sigma"].values if "sigma" in one else None, source=f"{self.model} batch, {labels}")
        names = [str(p) for p in ds["param"].values]
        value = {n: float(one["value"].sel(param=n)) for n in names}
        fixed = {n: value[n] for n in names if bool(ds["fixed"].sel(param=n))}
        bounds = self.user_bounds() or None  # (the user's, not the natural ones)
        # a value on a user bound (the batch's optimum there) is nudged inside, as init=batch does
        table = ParameterTable.build(self.circuit, registry=self.registry, fixed=fixed, bounds=bounds)
        init = values_inside({n: v for n, v in value.items() if n not in fixed}, table)
        return fit(self.circuit, spectrum, init=init, fixed=fixed, bounds=bounds, weighting=self.weighting, n_starts=1, registry=self.registry)

    def _spectrum_position(self, labels: dict, what: str) -> dict[str, int]:
        """The position along every batch dimension of the spectrum with ``labels`` (its label
        along each, the 0-based position along one without coordinates); a `ParameterError`
        from ``what`` (the method) when a dimension is missing, unknown or has no such label."""
        ds = self.dataset
        unknown = sorted(set(labels) - set(self.dims))
        missing = [d for d in self.dims if d not in labels]
        if unknown or missing:
            raise ParameterError(
                f"{what} needs one label for each batch dimension ({', '.join(self.dims)})"
                + (f"; unknown: {', '.join(unknown)}" if unknown else "") + (f"; missing: {', '.join(missing)}" if missing else "")
            )
        position = {}
        for dim, label in labels.items():
            if dim in ds.coords:
                position[dim] = self._label_position(dim, label)
            else:
                if not (isinstance(label, (int, np.integer)) and 0 <= label < ds.sizes[dim]):
                    raise ParameterError(f"{dim}={label!r}: {dim} has no coordinates; give a position from 0 to {ds.sizes[dim] - 1}")
                position[dim] = int(label)
        return position

    def _label_position(self, dim: str, label) -> int:
        """The position of ``label`` along ``dim`` (a dimension with coordinates), labels compared
        by value: along dates any form of the date (an ISO text "2024-01-02T10:00", a
        ``numpy.datetime64`` in any unit, a ``datetime.datetime``, a ``pandas.Timestamp``: all
        read by ``pandas.Timestamp``, not only a ``Timestamp``); a
        `ParameterError` naming the labels nearest to it (in time or value; else the first ones)."""
        import pandas as pd

        index = self.dataset.get_index(dim)
        wanted = label
        if isinstance(index, pd.DatetimeIndex):
            try:
                wanted = pd.Timestamp(label) if isinstance(label, (str, datetime.date, np.datetime64)) else None
            except (TypeError, ValueError):
                wanted = None
        found = [] if wanted is None else np.flatnonzero(index == wanted)
        if len(found):
            return int(found[0])
        labels = list(index)
        shown = lambda v: v.isoformat() if isinstance(v, pd.Timestamp) else str(label_value(v))  # noqa: E731
        numeric = index.dtype.kind in "iuf" and isinstance(label, (int, float, np.integer, np.floating)) and not isinstance(label, (bool, np.bool_))
        if wanted is not None and (isinstance(index, pd.DatetimeIndex) or numeric):
            labels = sorted(labels, key=lambda v: abs(v - wanted))
            nearby = "nearest labels: " + ", ".join(map(shown, labels[:5]))
        else:
            nearby = "its labels: " + ", ".join(map(shown, labels[:10])) + (", …" if len(labels) > 10 else "")
        what = "an ISO date ('2024-01-02T10:00'), a numpy.datetime64, datetime or pandas.Timestamp" if isinstance(index, pd.DatetimeIndex) else None
        raise ParameterError(f"{dim}={label!r} is not among the batch's labels ({nearby})" + (f"; a {dim} label is {what}" if what and wanted is None else ""))

    @labels_by_keyword
    def unidentified_groups_of(self, **labels) -> tuple[tuple[str, ...], ...]:
        """The unidentified groups of one spectrum's fit (`FitResult.unidentified_groups`: the
        free parameters along each near-null direction of its Jacobian, `statistics.null_sets`),
        picked by its labels as `fit_of`; () when the data determine every parameter. Kept in
        ``dataset.attrs["unidentified_groups"]`` (spectrum → groups, keyed as `warnings`; a
        global fit's over each spectrum's own and shared parameters, `shared.joint_null_sets`);
        a result without them (a batch or a global fit written by older
        versions) raises a `ParameterError`."""
        position = self._spectrum_position(labels, "unidentified_groups_of")
        stored = self._stored_groups()
        if stored is None:
            raise ParameterError(f"unidentified_groups_of: this {'global fit' if self._KIND != 'batch_fit' else 'batch of fits'} saved by an older impedax does not record each spectrum's unidentified groups; "
                                 + ("fit_of(...) refits one spectrum and gives them" if self._KIND == "batch_fit" else "fit the data again with this impedax to get them"))
        ds = self.dataset
        key = ", ".join(f"{d}={(ds[d].values[position[d]] if d in ds.coords else position[d])}" for d in self.dims)  # (as `fit_batch` keys them)
        return parameter_groups(stored.get(key, ()))

    @labels_by_keyword
    def at_bound_of(self, **labels) -> tuple[str, ...]:
        """The free parameters at a natural or user bound in one spectrum's fit, picked by its
        labels as `fit_of` (``at_bound_of(cycle=64)``): a tuple of names, the form of
        `FitResult.at_bound` and of each row's ``at_bound`` in `summary`'s ``spectra``; ()
        when none is. ``summary()["at_bound"]`` counts, per name, the spectra where it is; the
        ``at_bound`` variable of `dataset` holds the same flags over (param, *dims)."""
        one = self.dataset["at_bound"].isel(self._spectrum_position(labels, "at_bound_of"))
        return tuple(str(n) for n, flag in zip(self.dataset["param"].values, one.transpose("param").values) if flag)

    def _stored_groups(self) -> dict | None:
        """``dataset.attrs["unidentified_groups"]`` (spectrum → groups), None if not recorded."""
        stored = self.dataset.attrs.get("unidentified_groups")
        return None if stored is None else dict(stored)

    UNDETERMINED_RULE = f"relative error > {RELATIVE_ERROR_LIMIT * 100:.0f} % or none"  # (`undetermined`, as figures name it)

    def undetermined(self, name: str) -> xr.DataArray:
        """Where the data do not determine parameter ``name`` (bool over the batch dimensions):
        the fits' rule (`branches.undetermined`: relative standard error above 100 %, or none
        finite), a fixed parameter or one at a bound never (its bound note speaks for it)."""
        ds = self.dataset.sel(param=self._parameter(name, "undetermined"))
        flagged = undetermined(ds["value"].values, ds["stderr"].values) & ~ds["at_bound"].values & (not bool(ds["fixed"]))
        return xr.DataArray(flagged, dims=ds["value"].dims, coords=ds["value"].coords).drop_vars("param")

    def to_table(self) -> list[dict[str, object]]:
        """The tidy table: one row per spectrum and parameter, the extra dimensions' coordinates
        (their index where they have none) as the first columns, then name, value, stderr (None
        when fixed or there is none, as `FitResult.to_table`), unit and fixed, then the
        spectrum's `SPECTRUM_STATISTICS` (rms_rel, chi2, chi2_red, aic, bic: the keys of a single
        fit's JSON), repeated on each of its rows (`impedax.io.write_result` .csv),
        then the flags (as `FitResult.to_table`): ``converged`` (the spectrum's),
        ``at_bound`` and ``undetermined`` (this parameter's; the rule of `undetermined`), and
        ``warnings``: the spectrum's warnings joined by "; " ("" if none; as a comparison's
        table), ``weighting`` (as `FitResult.to_table`) and
        ``misses_structure`` (the spectrum's, `misses_structure`: its warnings or the misfit hint
        say its model misses structure the data hold: on the REAL 130 battery
        cycles, the 49 spectra the hint counts)."""
        ds = self.dataset
        specs = self.circuit.parameter_specs(self.registry)
        names = [str(p) for p in ds["param"].values]
        value = ds["value"].transpose(*self.dims, "param").values
        stderr = ds["stderr"].transpose(*self.dims, "param").values
        at_bound = ds["at_bound"].transpose(*self.dims, "param").values.astype(bool)
        converged = ds["converged"].transpose(*self.dims).values.astype(bool)
        fixed = ds["fixed"].values.tolist()
        # (`undetermined`'s rule for every parameter at once: never fixed, never at a bound)
        flagged = undetermined(value, stderr) & ~at_bound & ~np.asarray(fixed, bool)
        statistics = self._spectrum_statistics()
        labels = [coordinate_labels(ds, d) for d in self.dims]
        keys = [key for key, _ in self.spectrum_keys()]  # (C order, as np.ndindex)
        misses = self.misses_structure.transpose(*self.dims).values.reshape(-1)
        rows = []
        for position, index in enumerate(np.ndindex(*value.shape[:-1])):
            where = {d: labels[i][j] for i, (d, j) in enumerate(zip(self.dims, index))}
            own = {k: float(a[index]) for k, a in statistics.items()}
            warned = "; ".join(self.warnings.get(keys[position], ()))
            for p, n in enumerate(names):
                rows.append({
                    **where, "name": n, "value": float(value[index + (p,)]), "stderr": shown_stderr(float(stderr[index + (p,)]), fixed[p]), "unit": specs[n].unit, "fixed": fixed[p], **own,
                    "converged": bool(converged[index]), "at_bound": bool(at_bound[index + (p,)]), "undetermined": bool(flagged[index + (p,)]), "warnings": warned, "weighting": self.weighting,
                    "misses_structure": bool(misses[position]),
                })
        return rows

    def to_latex(self) -> str:
        """The fits as a plain LaTeX ``tabular`` (no package needed), or of more than
        `LONG_TABLE_ROWS` spectra a ``longtable`` (``\\usepackage{longtable}``, said in a comment
        line; it breaks across pages, the heading repeated), one row per spectrum: its
        labels under the heading of its dimensions (``0.3``, not ``0.30000000000000004``:
        `label_text`), each parameter's value ± standard error as `FitResult.to_latex` writes one
        (the error to two significant digits, the value to its last digit; "(fixed)", "(at
        bound)" and "(undetermined)" marked alike), rms_rel [%] last; the heading names each
        parameter and its unit (and "(shared)" for a global fit's shared one, whose estimate every
        row repeats). A comment line names the model, the spectra, what is shared and the
        weighting (``impedax fit FILE --out FILE.tex`` of several spectra, not refused with
        "a LaTeX table holds the fit of one spectrum")."""
        from ...data import latex_text, latex_unit, latex_value_error

        ds = self.dataset
        specs = self.circuit.parameter_specs(self.registry)
        names = [str(p) for p in ds["param"].values]
        fixed = [bool(f) for f in ds["fixed"].values]
        # (a global fit's shared parameters: one estimate each row repeats, said in the heading and the comment)
        shared, over = tuple(getattr(self, "shared", ())), tuple(getattr(self, "over", ()))
        heads = [latex_text(", ".join(self.dims))] + [latex_text(n) + (f" [{latex_unit(specs[n].unit)}]" if latex_unit(specs[n].unit) else "") + (" (shared)" if n in shared else "") for n in names] + [r"rms\_rel [\%]"]
        sharing = f", {', '.join(shared)} shared over {', '.join(over)}" if shared else ""
        lines = [f"% impedax fit: {self.model}, {self.n_spectra} spectr{'um' if self.n_spectra == 1 else 'a'} over {_dims_text({d: ds.sizes[d] for d in self.dims})}{sharing}, weighting {self.weighting}; value ± standard error"]
        long = self.n_spectra > LONG_TABLE_ROWS
        if long:  # (a tabular does not break across pages: the REAL 130 battery cycles' ran off the first)
            lines += [f"% {self.n_spectra} rows: a longtable, which breaks across pages with the heading on each; needs \\usepackage{{longtable}} in the preamble, and no table float around it",
                      r"\begin{longtable}{" + "l" * len(heads) + "}", r"\hline", " & ".join(heads) + r" \\", r"\hline", r"\endhead", r"\hline", r"\endfoot"]
        else:
            lines += [r"\begin{tabular}{" + "l" * len(heads) + "}", r"\hline", " & ".join(heads) + r" \\", r"\hline"]
        for row in self.summary()["spectra"]:
            cells = []
            for p, n in enumerate(names):
                value, error = row["values"][n], row["stderr"][n]
                error = math.nan if error is None else error
                if fixed[p]:
                    note = " (fixed)"
                elif n in row["at_bound"]:
                    note = " (at bound)"
                else:  # (the fits' rule, `branches.undetermined`, as a single fit's table)
                    note = " (undetermined)" if undetermined(value, error) else ""
                cells.append(latex_value_error(value, error, exact=fixed[p]) + note)
            lines.append(" & ".join([latex_text(", ".join(label_text(v) for v in row["labels"].values()))] + cells + [f"{row['rms_rel'] * 100:.3g}"]) + r" \\")
        lines += [r"\end{longtable}"] if long else [r"\hline", r"\end{tabular}"]
        return "\n".join(lines) + "\n"

    def _spectrum_statistics(self) -> dict[str, np.ndarray]:
        """Each spectrum's `SPECTRUM_STATISTICS` over the batch dimensions (C order), as the
        dataset holds them; NaN for one a file written by an older impedax lacks."""
        ds = self.dataset
        return {k: ds[k].transpose(*self.dims).values.astype(float) if k in ds else np.full(ds["rms_rel"].shape, np.nan) for k in SPECTRUM_STATISTICS}

    def _repr_html_(self) -> str:
        from ...plotting.html import result_html

        s = self.summary()
        rows = [{"parameter": p, "median": v["median"], "q16": v["q16"], "q84": v["q84"]} for p, v in s["params"].items()]
        chi2_median = f", median chi2_red {np.nanmedian([r['chi2_red'] for r in s['spectra']]):.3g}" if self._against_sigma() else ""  # (as the report)
        lines = [f"{self.n_spectra} {'spectrum' if self.n_spectra == 1 else 'spectra'} over {_dims_text(s['dims'])}: converged {s['converged_fraction'] * 100:.1f} %, median rms_rel {s['rms_rel_median'] * 100:.3g} %{chi2_median}, weighting {self.weighting}", *(f"note: {n}" for n in self.notes)]
        return result_html(self.model, rows, lines=lines)

    def plot(self, *, title: str | None = None, figsize: tuple[float, float] | None = None, params=None, x: str | None = None, spectra: str = "auto"):
        """Each free parameter (± stderr) and rms_rel across the spectra (matplotlib Figure;
        `plotting.fit.plot_batch`); ``figsize`` (width, height) [in] in place of the size that
        follows the number of panels; ``params`` (a list of names) draws those parameters only,
        in that order (an unknown name: a `ParameterError` naming the circuit's parameters);
        ``x`` (a batch dimension with a numeric coordinate, e.g. ``"voltage"``) draws them
        against that coordinate, one series per label of the other dimensions (else
        the spectra are categories in the batch's order); ``spectra`` "nyquist", "phase" or
        "auto" (the phase against frequency where a capacitive tail would draw the Nyquist
        panel as a vertical line, as a finger's)."""
        from ...plotting.fit import plot_batch

        return plot_batch(self, title=title, figsize=figsize, params=params, x=x, spectra=spectra)

    def plot_residual_map(self, *, title: str | None = None, excluded=None):
        """Where the model fails across the spectra: each fit's residuals, real and imaginary,
        as maps over the spectra and frequency (relative to |Z| in %, or in units of the data's
        σ where the fits were weighted by it), and rms_rel below (matplotlib Figure;
        `plotting.fit.plot_residual_map`; ``impedax fit FILE --residual-map FIG.png``).
        ``excluded``: frequencies [Hz] left out of the fits, drawn as hatched grey
        rows (the command line's ``--exclude`` passes its own). A missing effect leaves one sign
        pattern at the same frequencies in every spectrum; noise leaves speckle."""
        from ...plotting.fit import plot_residual_map

        return plot_residual_map(self, title=title, excluded=excluded)

    def summary(self) -> dict:
        """The JSON of ``impedax fit --json`` for several spectra (docs/fitting.md, "Batch fits")."""
        ds = self.dataset
        specs = self.circuit.parameter_specs(self.registry)
        fixed = {str(p): bool(ds["fixed"].sel(param=p).all()) for p in ds["param"].values}
        return {
            "model": self.model,
            "dims": {d: int(ds.sizes[d]) for d in self.dims},
            "sizes": {d: int(ds.sizes[d]) for d in self.dims},  # (the key kk and drt give too; "dims" here is the same mapping)
            "n_spectra": self.n_spectra,
            "n_points": self.n_points,  # (a single fit's key: the frequencies each fit used, after the band)
            "n_params": sum(not f for f in fixed.values()),  # (a single fit's key: the free parameters of each spectrum's fit)
            "params": {  # (the spread across the spectra, and each one's unit and fixed, as a single fit's)
                str(p): {"median": float(ds["value"].sel(param=p).median()), "q16": float(ds["value"].sel(param=p).quantile(0.16)), "q84": float(ds["value"].sel(param=p).quantile(0.84)), "unit": specs[str(p)].unit,
                         "fixed": fixed[str(p)], "stderr_median": _median_stderr(ds["stderr"].sel(param=p).values, fixed[str(p)])}
                for p in ds["param"].values
            },
            "rms_rel_median": float(ds["rms_rel"].median()),
            "converged_fraction": float(ds["converged"].mean()),
            "converged": bool(ds["converged"].all()),  # (a single fit's key: every spectrum's fit converged)
            "aic_form": UNKNOWN_VARIANCE,  # (a single fit's key: the form of each spectrum's aic and bic)
            "at_bound": {str(p): int(n) for p, n in zip(ds["param"].values, ds["at_bound"].values.reshape(ds.sizes["param"], -1).sum(axis=1)) if n},
            "warnings": sorted({w for ws in self.warnings.values() for w in ws}),
            "warning_kinds": self._warning_kinds(),  # (each kind with its spectra, as report() groups them)
            "spectra": self._spectrum_rows(),
            "weighting": self.weighting,  # (as a single fit's JSON)
            "user_bounds": bounds_attr(self.user_bounds()),  # (as a single fit's JSON)
            "notes": list(self.notes),  # (as a single fit's JSON)
        }

    def user_bounds(self) -> KeyHintDict:
        """The bounds the user set (``bounds=``, ``--bound``) on free parameters, as
        `FitResult.bounds`: the dataset's ``lower``/``upper`` that differ from the element's own
        (`ParameterSpec.narrowed_sides`; none in a batch saved before they were stored). A new
        dict whose missing key names the keys there are (`MissingKey`, as ``FitResult.bounds``')."""
        ds = self.dataset
        if "lower" not in ds:
            return KeyHintDict()
        specs = self.circuit.parameter_specs(self.registry)
        out = KeyHintDict()
        for p in ds["param"].values:
            n = str(p)
            lo, hi = float(ds["lower"].sel(param=n)), float(ds["upper"].sel(param=n))
            if not bool(ds["fixed"].sel(param=n).all()) and specs[n].narrowed_sides(lo, hi):
                out[n] = (lo, hi)
        return out

    def _warning_kinds(self) -> list[dict]:
        """`warning_kinds` of the spectra's warnings, each kind also with ``labels``: its spectra's
        labels as dicts ({dimension: label}, as ``spectra[].labels``; same order as its
        ``spectra``, the texts "cycle=64")."""
        label_of = dict(self.spectrum_keys())
        return [{**kind, "labels": [label_of.get(place, {}) for place in kind["spectra"]]} for kind in warning_kinds(self.warnings)]

    @property
    def misses_structure(self) -> xr.DataArray:
        """Per spectrum (bool over `dims`), whether its model misses structure the data hold, by
        `FitResult.misses_structure`'s rule: a warning says so (`result.MODEL_MISFIT_MARKS`; its
        misfit checked from 2 % rms_rel), or `misfit_hints` names it (below 2 %, over 5× what the
        Kramers–Kronig chain reaches). Not the warnings alone: on the REAL 130 battery
        cycles they name none while the hints name 49. The warning's blame is its
        `notes.MODEL_MISFIT` tag (`warning_tags`), set where the notes are made, not read from
        their words (a batch without tags: their words)."""
        ds = self.dataset
        hinted = set(self._hinted[0].tolist())
        flags = [self._blames_model(key) or i in hinted for i, (key, _) in enumerate(self.spectrum_keys())]
        shape = tuple(ds.sizes[d] for d in self.dims)
        return xr.DataArray(np.array(flags, bool).reshape(shape), dims=self.dims, coords={d: ds[d] for d in self.dims if d in ds.coords})

    def _blames_model(self, key: str) -> bool:
        """Whether spectrum ``key``'s warnings blame the model: their `notes.MODEL_MISFIT` tags (set
        where the notes are made), or where they are not known, their words (`warnings_blame_model`)."""
        if self.warning_tags is None:
            return warnings_blame_model(self.warnings.get(key, ()))
        return any(has_tag(t, MODEL_MISFIT) for t in self.warning_tags.get(key, ()))

    def spectrum_keys(self):
        """(key, labels) of each spectrum in C order: the text `fit_batch` files its warnings
        under ("cycle=64, cell=a") and its labels as JSON gives them ({dimension: label})."""
        for where in self._spectrum_labels():
            yield labels_key(where), {d: label_value(c) for d, c in where.items()}

    def _spectrum_labels(self):
        """Each spectrum's labels as stored ({dimension: label}, the position along a dimension
        without coordinates), in C order over `dims`."""
        ds = self.dataset
        labels = [ds[d].values if d in ds.coords else np.arange(ds.sizes[d]) for d in self.dims]
        for index in np.ndindex(*(ds.sizes[d] for d in self.dims)):
            yield {d: labels[i][j] for i, (d, j) in enumerate(zip(self.dims, index))}

    def transpose(self, *dims: str) -> "BatchFitResult":
        """The same fits with the batch dimensions in the order ``dims`` (as
        ``xarray.Dataset.transpose``; a batch of a transposed stack lined up with another, as
        `compare` does): each variable's batch dimensions in that order, its other dimensions
        where they were, and the warnings and unidentified groups filed under that order's keys
        (`labels_key`: "cell=a, cycle=1" for "cycle=1, cell=a"). A `ParameterError` unless
        ``dims`` are the batch's dimensions, each once."""
        if sorted(dims) != sorted(self.dims):
            raise ParameterError(f"transpose takes the batch's dimensions ({', '.join(self.dims)}), each once, in a new order; got {', '.join(map(str, dims)) or 'none'}")
        if tuple(dims) == self.dims:
            return self
        ds = self.dataset.copy()
        for name in self.dataset.data_vars:
            own = ds[name].dims
            ordered = iter(d for d in dims if d in own)
            ds[name] = ds[name].transpose(*(next(ordered) if d in dims else d for d in own))
        keys = {labels_key(where): labels_key({d: where[d] for d in dims}) for where in self._spectrum_labels()}
        stored = self._stored_groups()
        if stored is not None:
            ds.attrs["unidentified_groups"] = {keys.get(k, k): v for k, v in stored.items()}
        return batch_with_warnings(replace(self, dataset=ds), {keys.get(k, k): self.tagged_warnings(k) for k in self.warnings})

    def _spectrum_rows(self) -> list[dict]:
        """Each spectrum's fit (the JSON's ``spectra``): its label along every batch dimension
        (the position where a dimension has no coordinates), then ``labels`` (dimension → label,
        every dimension, as a KK or DRT batch's rows), ``values``, ``stderr`` (None when fixed or
        there is none, as `to_table`), ``linearised_stderr`` (the linearisation's, bounds ignored,
        as a single fit's JSON: at a bound, the number its note quotes), ``rms_rel``, ``chi2``, ``chi2_red``, ``aic``, ``bic`` (as a
        single fit's JSON), ``converged``, ``at_bound`` (names, as a
        single fit's JSON), its ``warnings`` and ``unidentified_groups`` (lists of names, as a
        single fit's JSON; only where the result records them, `unidentified_groups_of`) and
        ``misses_structure`` (`misses_structure`). A dimension named as one of these keys (a batch
        over ``values``) is only under ``labels``: its label would clobber the fit's key."""
        ds = self.dataset
        names = [str(p) for p in ds["param"].values]
        value, stderr, at_bound = (ds[v].transpose(*self.dims, "param").values for v in ("value", "stderr", "at_bound"))
        linearised = ds["linearised_stderr"].transpose(*self.dims, "param").values if "linearised_stderr" in ds else None
        statistics = self._spectrum_statistics()
        converged = ds["converged"].transpose(*self.dims).values
        fixed = ds["fixed"].values.tolist()
        stored_groups = self._stored_groups()
        misses = self.misses_structure.transpose(*self.dims).values.reshape(-1)
        evaluations = ds["n_evaluations"].transpose(*self.dims).values if "n_evaluations" in ds else None
        units = [self.circuit.parameter_specs(self.registry)[n].unit for n in names]
        rows = []
        for position, (index, (key, label)) in enumerate(zip(np.ndindex(*converged.shape), self.spectrum_keys())):  # (key: as `fit_batch` names the spectra its warnings are about)
            own = {
                "values": {n: float(value[index + (p,)]) for p, n in enumerate(names)},
                "stderr": {n: shown_stderr(float(stderr[index + (p,)]), fixed[p]) for p, n in enumerate(names)},
                # (the linearisation's, bounds ignored, as a single fit's params[NAME]["linearised_stderr"]: the number a bound note quotes)
                **({} if linearised is None else {"linearised_stderr": {n: shown_stderr(float(linearised[index + (p,)]), fixed[p]) for p, n in enumerate(names)}}),
                # (the same numbers in a single fit's shape, so code that reads a single fit's params reads each row's)
                "params": {n: {"value": float(value[index + (p,)]), "stderr": shown_stderr(float(stderr[index + (p,)]), fixed[p]), "fixed": bool(fixed[p]), "unit": units[p],
                               **({} if linearised is None else {"linearised_stderr": shown_stderr(float(linearised[index + (p,)]), fixed[p])})} for p, n in enumerate(names)},
                **({} if evaluations is None else {"n_evaluations": int(evaluations[index])}),
                **{k: float(a[index]) for k, a in statistics.items()},
                "converged": bool(converged[index]),
                "at_bound": [n for p, n in enumerate(names) if at_bound[index + (p,)]],
                "warnings": list(self.warnings.get(key, ())),
                "warning_tags": [list(t) for t in self.spectrum_warning_tags(key)],  # (each warning's tags, in their order, as a single fit's JSON)
                **({} if stored_groups is None else {"unidentified_groups": [list(g) for g in parameter_groups(stored_groups.get(key, ()))]}),
                "misses_structure": bool(misses[position]),  # (`misses_structure`)
            }
            rows.append({**{d: c for d, c in label.items() if d not in own and d != "labels"}, "labels": label, **own})
        return rows

    def report(self, *, misfit_hints=_COMPUTED_HERE) -> str:
        """The parameter table (`_parameter_lines`), the warnings and notes, and the hint of the
        fits that miss structure small as their misfits look (`misfit_hints`; ``misfit_hints=``
        what that method returned already, dict or None, so that a caller that has them does not
        run the Kramers–Kronig chains again, as ``impedax fit`` would)."""
        hints = self.misfit_hints() if misfit_hints is _COMPUTED_HERE else misfit_hints
        return "\n".join(self._parameter_lines() + self._warning_lines() + ([] if hints is None else ["", f"hint: {hints['note']}"]))

    def misfit_hints(self) -> dict | None:
        """The fits that miss structure the data hold, small as their misfits look, as a single
        fit's `misfit_hint` says it (weighted by |Z|, rms_rel from 0.2 % to 2 % and over 5× what
        the Kramers–Kronig test's Voigt chain reaches on that spectrum; `misfit_hint_spectra`,
        ~0.5 ms of chain per spectrum in that range, computed when asked): ``spectra`` (how
        many), ``worst`` (``labels``, ``rms_rel``, ``chain_rms_rel``, ``ratio``: the largest
        ratio's spectrum), ``note`` and ``labels``: every such spectrum's labels (dicts, in the
        batch's order: on the REAL 130 battery cycles 49 fits are counted, and the worst one
        named alone would leave the others unfound), which the note names too; None when there is none (a batch's warnings begin at
        2 %, so these fits are told nothing else)."""
        rows, ratio, chain = self._hinted
        if not rows.size:
            return None
        rms = self.dataset["rms_rel"].transpose(*self.dims).values.reshape(-1)
        worst = int(np.argmax(ratio))
        keys = list(self.spectrum_keys())
        labels = keys[rows[worst]][1]
        key = labels_shown(labels)  # (as text writes it: soc=0.3, not soc=0.30000000000000004)
        hinted = [keys[i][1] for i in sorted(rows.tolist())]
        rule = f"rms_rel below {MISFIT_CHECKED_FROM * 100:g} % and over {MISFIT_RATIO_MAX:g}× what a Kramers–Kronig-consistent model reaches on that spectrum"
        figures = f"{rms[rows[worst]] * 100:.3g} %, {ratio[worst]:.3g}× the chain's {chain[worst] * 100:.3g} % (a diagnosis of that spectrum shows where and what)"
        if rows.size == 1:  # (one: named once, not "1 of the 1 fits ... their misfits ...; the worst, cycle=0")
            of = "the only one" if self.n_spectra == 1 else f"1 of the {self.n_spectra}"
            note = f"the fit of {key} ({of}) misses structure the data hold, small as its misfit looks ({rule}): {figures}"
        else:
            note = f"{rows.size} of the {self.n_spectra} fits ({spectra_named(hinted)}) miss structure the data hold, small as their misfits look ({rule}); the worst, {key}: {figures}"
        return {"spectra": int(rows.size), "worst": {"labels": labels, "rms_rel": float(rms[rows[worst]]), "chain_rms_rel": float(chain[worst]), "ratio": float(ratio[worst])}, "note": note,
                "labels": hinted}

    @functools.cached_property
    def _hinted(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """`misfit_hint_spectra` of the batch (the flat indices of the spectra `misfit_hints`
        names, their ratios and chains' rms_rel); none unless weighted by |Z| with its spectra.
        Computed once per result (its fields are read-only): the report, the JSON and the CSV
        each ask for it."""
        if self.weighting != "modulus" or "Z" not in self.dataset:
            return np.empty(0, int), np.empty(0), np.empty(0)
        z = self.dataset["Z"].transpose(*self.dims, "frequency").values.reshape(self.n_spectra, -1)
        rms = self.dataset["rms_rel"].transpose(*self.dims).values.reshape(-1)
        return misfit_hint_spectra(self.dataset["frequency"].values, z, rms)

    def _parameter_lines(self) -> list[str]:
        """The header and the parameter table: one column per spectrum (value and relative
        standard error, as a single fit's table) up to `SPECTRA_AS_COLUMNS` spectra, else the
        median and 16/84 % quantiles across them, said to be a spread across the spectra (not
        an uncertainty), then one row per spectrum up to `SPECTRA_AS_ROWS` (`_spectrum_lines`),
        beyond that where to find each spectrum's fit."""
        s = self.summary()
        width = column_width(s["params"], 16)
        noun = "spectrum" if self.n_spectra == 1 else "spectra"
        against_sigma = self._against_sigma()
        chi2_median = f"   median chi2_red {np.nanmedian([r['chi2_red'] for r in s['spectra']]):.3g}" if against_sigma else ""
        lines = [f"model {self.model}: {self.n_spectra} {noun} over {_dims_text(s['dims'])}", f"converged: {s['converged_fraction'] * 100:.1f} %   median rms_rel {s['rms_rel_median'] * 100:.3g} %{chi2_median}   weighting {self.weighting}{self._points_text()}", ""]
        specs = self.circuit.parameter_specs(self.registry)
        if self.n_spectra <= SPECTRA_AS_COLUMNS:
            rows = s["spectra"]
            heads = [labels_shown(r["labels"]) for r in rows]
            fixed = {str(p): bool(f) for p, f in zip(self.dataset["param"].values, self.dataset["fixed"].values)}
            cells = [[_cell(r["values"][p], r["stderr"][p], fixed[p], p in r["at_bound"], p, self._notes_of(r)) for r in rows] for p in s["params"]]
            col = max(22, *(len(h) for h in heads), *(len(c) for row in cells for c in row))
            lines.append(f"{'parameter':<{width}} " + " ".join(f"{h:>{col}}" for h in heads) + "  unit")
            for p, row in zip(s["params"], cells):
                lines.append(f"{p:<{width}} " + " ".join(f"{c:>{col}}" for c in row) + f"  {unit_text(specs[p].unit)}".rstrip())
            lines.append(f"{'rms_rel':<{width}} " + " ".join(f"{r['rms_rel'] * 100:>{col - 2}.3g} %" for r in rows))
            if against_sigma:  # (the misfit against the data's σ: about 1 at the noise)
                lines.append(f"{'chi2_red':<{width}} " + " ".join(f"{r['chi2_red']:>{col}.3g}" for r in rows))
            return lines
        # (the quantiles read like a confidence interval: say what they are)
        lines.append(f"across the {self.n_spectra} spectra (not uncertainties): median, 16th and 84th percentiles of each parameter's values")
        lines.append(f"{'parameter':<{width}} {'median':>12} {'16 %':>12} {'84 %':>12}  unit")
        for p, v in s["params"].items():
            lines.append(f"{p:<{width}} {v['median']:>12.5g} {v['q16']:>12.5g} {v['q84']:>12.5g}  {unit_text(specs[p].unit)}".rstrip())
        if self.n_spectra <= SPECTRA_AS_ROWS:
            return lines + ["", *self._spectrum_lines(s)]
        return lines + ["", f"each spectrum's values, standard errors and rms_rel: {EACH_SPECTRUM_WHERE}"]

    def _against_sigma(self) -> bool:
        """Whether the fits were weighted by the data's σ, where the report gives each one's
        χ²_red beside rms_rel (about 1 at the noise σ states: rms_rel alone, in a SYNTHETIC
        σ-weighted batch's report, is the number σ-weighted fits are not judged by)."""
        return self.weighting == "sigma" and "chi2_red" in self.dataset

    def _points_text(self) -> str:
        """The points each fit used and their band, for the report's second line
        ("   29 points each (588 mHz–17 kHz)"; "" for a result stored without its spectra): what
        ``fmin``/``fmax`` and ``--exclude`` left."""
        if self.n_points is None:
            return ""
        f = self.dataset["frequency"].values
        return f"   {counted(self.n_points, 'point')} each ({format_band(float(f.min()), float(f.max()))})"

    def _spectrum_lines(self, s: dict) -> list[str]:
        """Each spectrum's fit, one row per spectrum (its labels, then each parameter as the
        columns of a small batch give it: value ± relative standard error, `_cell`; then
        rms_rel), ``s`` the `summary`."""
        rows = s["spectra"]
        heads = [labels_shown(r["labels"]) for r in rows]
        fixed = {str(p): bool(f) for p, f in zip(self.dataset["param"].values, self.dataset["fixed"].values)}
        names = list(s["params"])
        against_sigma = self._against_sigma()
        rms = format_percent_column([r["rms_rel"] for r in rows])  # (3 significant digits, the decimal points lined up)
        cells = [[_cell(r["values"][p], r["stderr"][p], fixed[p], p in r["at_bound"], p, self._notes_of(r)) for p in names] + [f"{percent} %"] + ([f"{r['chi2_red']:.3g}"] if against_sigma else []) for r, percent in zip(rows, rms)]
        columns = names + ["rms_rel"] + (["chi2_red"] if against_sigma else [])
        widths = [max(len(c), *(len(row[j]) for row in cells)) for j, c in enumerate(columns)]
        lead = column_width(heads, "spectrum")
        lines = ["each spectrum's fit (value ± relative standard error):", f"{'spectrum':<{lead}}  " + "  ".join(f"{c:>{w}}" for c, w in zip(columns, widths))]
        for head, row in zip(heads, cells):
            lines.append(f"{head:<{lead}}  " + "  ".join(f"{c:>{w}}" for c, w in zip(row, widths)))
        return lines

    def _notes_of(self, row: dict) -> list[str]:
        """The warnings that speak for one spectrum's parameters (a `_spectrum_rows` row): its
        own (a global fit adds its group's, `SharedFitResult`)."""
        return row["warnings"]

    def _warning_lines(self) -> list[str]:
        """The warnings, one line per kind with the spectra it applies to (`grouped_warnings`),
        where the rest are when a line names only the first of its spectra (`WARNED_SPECTRA_WHERE`),
        then the notes (`notes`), after an empty line; none when there are none."""
        warned = ["", *grouped_warnings(self.warnings, self.n_spectra, spectra=[key for key, _ in self.spectrum_keys()])] if any(self.warnings.values()) else []
        if any(" in all)" in line for line in warned):  # (`labels_text` cut a kind's spectra short)
            warned.append(f"every spectrum of each kind: {WARNED_SPECTRA_WHERE}")
        return warned + ([""] if self.notes and not warned else []) + [f"note: {n}" for n in self.notes]


def spectra_named(labels: list[dict]) -> str:
    """Spectra by their labels ({dimension: label}) for a line of text, as the grouped warnings
    name them: ``cycle 0, 3, 7, ... (49 in all)`` along one dimension, else ``cell=a, cycle=1;
    ...``, the first `LABELS_SHOWN`."""
    dims = list(labels[0]) if labels else []
    if len(dims) == 1:
        return f"{dims[0]} {labels_text([one[dims[0]] for one in labels])}"
    shown = "; ".join(labels_shown(one) for one in labels[:LABELS_SHOWN])
    return shown + (f"; ... ({len(labels)} in all)" if len(labels) > LABELS_SHOWN else "")


SPECTRA_AS_COLUMNS = 6
"""`BatchFitResult.report` gives each spectrum its own column up to this many spectra (6
columns of 23 characters fit a 160-character line with the names; the 16/84 % quantiles of so
few values are interpolations between two of them), the median and quantiles beyond."""


def labels_key(labels) -> str:
    """A spectrum's labels ({dimension: label}) as `fit_batch` files its warnings under them and
    the report heads its rows: "cycle=64, cell=a"."""
    return ", ".join(f"{d}={c}" for d, c in labels.items())


def labels_shown(labels) -> str:
    """A spectrum's labels ({dimension: label}) as text writes them, each as `label_text`
    ("soc=0.3, cell=a"; `labels_key` keeps "soc=0.30000000000000004", under which warnings are
    filed): the report's headings and the hint's names."""
    return ", ".join(f"{d}={label_text(c)}" for d, c in labels.items())


SPECTRA_AS_ROWS = 20
"""Beyond `SPECTRA_AS_COLUMNS` and up to this many spectra, `BatchFitResult.report` follows the
quantiles with one row per spectrum (20 rows stay on one screen); beyond, it says where each
spectrum's fit is (`EACH_SPECTRUM_WHERE`)."""

EACH_SPECTRUM_WHERE = "batch.to_table() or ix.write_result(batch, 'FILE.csv') (a row per spectrum and parameter), batch.summary()['spectra']"
"""Where a large batch's report sends the reader for each spectrum's fit (the command line
gives its own options: `impedax.cli.common.command_line_words`)."""

WARNED_SPECTRA_WHERE = "batch.summary()['warning_kinds'] (each spectrum's own: batch.warnings, or the warnings column of ix.write_result(batch, 'FILE.csv'))"
"""Where a batch's report sends the reader for the spectra a warning line names only the first
of ("cycle 0, 3, 4, ... (56 in all)" on the REAL 130 battery cycles, with no word where the
other 48 were; the command line gives its own options: `impedax.cli.common.command_line_words`)."""

SPECTRUM_STATISTICS = FIT_STATISTICS
"""Each spectrum's goodness of fit in a batch's JSON rows and CSV rows, under the keys of a
single fit's JSON (`FitResult.summary`), so models can be compared spectrum by spectrum."""


def _cell(value: float, stderr, fixed: bool, at_bound: bool, name: str = "", notes=()) -> str:
    """One spectrum's parameter ``name`` as the single fit's table gives it: ``0.11946 ± 1.2 %``
    (value and relative standard error), ``… (fixed)``, ``… at bound`` (``0 at bound`` where
    its ``notes`` say it is on its bound 0, `value_shown_at_bound`), ``… ± —`` (no finite error)."""
    if fixed:
        return f"{exact_number(value)} (fixed)"  # (as given: no error to round to)
    if at_bound:
        return f"{value_shown_at_bound(name, value, notes)} at bound"
    rel = format_relative_error(stderr / value) if stderr is not None and value else "—"
    return f"{value:.5g} ± {rel}"


def _looks_like(ds: xr.Dataset) -> str | None:
    """The kind of fit result a dataset without ``impedax_kind`` (written by older versions)
    holds, by its variables: a joint fit's ``shared_value``, a batch's values over extra
    dimensions; None for anything else (a KK batch, a spectrum)."""
    if "value" not in ds.variables or "rms_rel" not in ds.variables or not ds["rms_rel"].dims or len(ds["value"].dims) < 2:
        return None
    return "shared_fit" if "shared_value" in ds.variables else "batch_fit"


def _dims_text(dims: dict[str, int]) -> str:
    """``cycle (3)`` or ``session (2) × trial (5)``: a batch's dimensions and their sizes."""
    return " × ".join(f"{d} ({n})" for d, n in dims.items())


def _solve_stack(circuit, table: ParameterTable, freq, z, sigma, *, weighting, n_starts, max_steps, seed, registry, source, starts=None, screened: list | None = None) -> tuple[SolverOutput, np.ndarray, "_LaneRunner", np.ndarray]:
    """`_started_stack`, then every converged fit left at a bound while chi² falls inward
    restarted from inside (`restarted_inward`); the last item flags the fits still so."""
    out, used, solver = _started_stack(circuit, table, freq, z, sigma, weighting=weighting, n_starts=n_starts, max_steps=max_steps, seed=seed, registry=registry, source=source, starts=starts, screened=screened)
    inv_re, inv_im = weights(z, sigma, weighting, source, freq)
    out, inward = restarted_inward(out, solver, table, z, inv_re, inv_im, weighting, residual_scale(z, inv_re, inv_im, weighting), max_steps)
    return out, used, solver, inward


def restarted_inward(out: SolverOutput, solver: "_LaneRunner", table: ParameterTable, z, inv_re, inv_im, weighting: str, scale, max_steps: int) -> tuple[SolverOutput, np.ndarray]:
    """The batch's form of `single.restarted_inward`: converged fits with a parameter at a bound
    while chi² falls inward (`result.falling_inward`) solved again from inside their bounds
    (`starts.inward_start`), kept where chi² is lower, at most `BOUND_RESTARTS` times. Returns
    the outputs and which fits (B,) are still converged at a bound while chi² falls inward:
    the rule's verdict on the outputs returned, which `canonical_order` keeps (it exchanges
    only blocks of equal bounds)."""
    inward = np.zeros(np.shape(out.code), bool)
    for attempt in range(BOUND_RESTARTS + 1):
        inward[:] = False
        converged = np.flatnonzero(np.asarray(out.code) == SolverStatus.CONVERGED)
        if not converged.size or not len(table.free_names):
            break
        sides, step = falling_inward(table, np.asarray(out.x)[converged], np.asarray(out.jacobian)[converged], z[converged], np.asarray(out.z_model)[converged], inv_re[converged], inv_im[converged], weighting, lambda p, s: solver.chi2_at_x(p, converged[s]))
        stuck = np.flatnonzero(sides.any(axis=1))
        inward[converged[stuck]] = True
        if not stuck.size or attempt == BOUND_RESTARTS:
            break
        redo = converged[stuck]
        start = to_solver_space(table, inward_start(table, np.asarray(out.x)[redo], sides[stuck], step[stuck]))
        u_r, _, done_r, steps_r = solver.solve(start, redo, np.full(redo.size, max_steps))
        steps_before = np.asarray(out.steps_total)[redo]
        candidate = unscale(solver.outputs(u_r, redo, done_r, steps_r, steps_before + steps_r), np.asarray(scale)[redo])
        if not np.any(np.asarray(candidate.chi2) < np.asarray(out.chi2)[redo]):
            break
        out = _merged(out, redo, candidate)
    return out, inward


def _started_stack(circuit, table: ParameterTable, freq, z, sigma, *, weighting, n_starts, max_steps, seed, registry, source, starts=None, screened: list | None = None) -> tuple[SolverOutput, np.ndarray, "_LaneRunner"]:
    """Solver outputs (arrays over B) for a stack of spectra z (B, N), the starts used, and
    the lane runner (for chi² at other points).

    Every spectrum from the better of its data-driven guess and (batches of at least
    `REFERENCE_MIN_SPECTRA`, ``n_starts`` ≥ 2) the reference spectrum's optimum; with
    ``n_starts`` = 1 from its guess (or the user's start) alone, one local fit each, as
    impedance.py's loop fits; ``starts`` (B, P), where finite, replace the guess (each spectrum
    from its own earlier optimum, ``init=batch``). Then (large batches) the reference's other
    minima (`_tried_runner_up`), its neighbours' optima where they are better, then more
    starts for the fits that are still poor (below; each rung's starts screened for
    `SCREEN_STEPS` steps, the best continued to convergence; ``screened``, a list, collects
    each rung's screened points and their chi²). All solves go through the lane
    solver (`lm.work_queue`)."""
    b = z.shape[0]
    inv_re, inv_im = weights(z, sigma, weighting, source, freq)
    features = SpectrumFeatures(freq, z)
    solvers = tree_solver(circuit, registry, max_steps, *table.free_structure)
    scale = residual_scale(z, inv_re, inv_im, weighting)
    free = table.free_index
    # solved on `padded_size` points (zero-weight copies of the last): nearby lengths share a compilation
    freq_p, z_p, inv_re_p, inv_im_p = padded_points(freq, z, inv_re * scale[:, None], inv_im * scale[:, None])
    shared = SharedArgs(freq_p, table.lower[free], table.upper[free])
    x_fixed = np.where(np.isnan(table.values), 1.0, table.values)
    rows = SpectrumRows(z_p, inv_re_p, inv_im_p, np.broadcast_to(x_fixed, (b, x_fixed.size)))
    solver = _LaneRunner(solvers, rows, shared, np.size(freq))

    guesses = guess_start(circuit, table, features, registry, starts=starts)
    large = b >= REFERENCE_MIN_SPECTRA
    own_starts, runner_ups = None, ()
    if starts is not None and n_starts > 1:  # (solved apart below: each spectrum's own start and the default)
        own_starts, guesses = guesses, guess_start(circuit, table, features, registry)
    if large and n_starts > 1:
        say("the start search on a reference spectrum, whose optimum every spectrum is offered")
        with silenced():  # (it fits the reference as a stack of one: its stages are this one)
            guesses, runner_ups = _with_reference_start(guesses, solver, circuit, table, freq, z, sigma, weighting=weighting, n_starts=n_starts, max_steps=max_steps, seed=seed, registry=registry, source=source)
    say(f"local fits of the {counted(b, 'spectrum', 'spectra')}")
    spectra = np.arange(b)
    u, chi2, done, steps = solver.solve(guesses, spectra, np.full(b, max_steps))
    out = unscale(solver.outputs(u, spectra, done, steps, steps), scale)
    used = np.ones(b, int)
    if own_starts is not None:  # (the optimum of a nested fit, init=: `ParameterTable` carries it)
        out, u, _ = _also_solved_from(out, u, own_starts, solver, scale, max_steps)
        used += 1
    if n_starts < 2:
        return out, used, solver
    for limit_start in limit_starts(circuit, table, np.asarray(out.x), freq, registry):
        out, u, _ = _also_solved_from(out, u, guess_start(circuit, table, features, registry, starts=limit_start), solver, scale, max_steps)
        used += 1
    for u_other in runner_ups:
        out, u, tried = _tried_runner_up(out, u, u_other, solver, z, scale, max_steps)
        used[tried] += 1
    if large:
        return _outliers_restarted(out, u, used, solver, circuit, table, features, freq, z, n_starts, seed, scale, max_steps, registry), used, solver
    # more starts for the fits that are poor relative to what the data allow, as `fit`: the
    # multistart when the residuals are not white, the next rungs (`starts.escalation_rungs`)
    # while above `starts.climb_target`
    poor = np.flatnonzero(~at_noise_floor(freq, z, out.z_model, inv_re, inv_im, out.code))
    target = None
    for rung, multiple in enumerate(escalation_rungs(len(table.free_names))):
        if rung and poor.size:
            target = climb_target(freq, z[poor], solver.kk_chains.misfits(freq, z, poor)) if target is None else target
            still = rms_rel_of(out.z_model[poor], z[poor]) > target
            poor, target = poor[still], target[still]
        if not poor.size:
            break
        say(f"{poor.size} of the fits {'not at the noise' if not rung else 'still poor'}: {multiple * draw_size(table, n_starts)} more starts each")
        out = _multistart_rung(out, solver, circuit, table, features, poor, n_starts, multiple, rung, seed, scale, max_steps, registry, screened=screened)
        used[poor] = np.where(used[poor] > 1, used[poor], 0) + multiple * draw_size(table, n_starts)
    return out, used, solver


def _also_solved_from(out: SolverOutput, u: np.ndarray, starts: np.ndarray, solver: "_LaneRunner", scale, max_steps: int, spectra: np.ndarray | None = None, budget: int | None = None) -> tuple[SolverOutput, np.ndarray, np.ndarray]:
    """``out`` (and its solver points ``u``) with each spectrum (or those of ``spectra``) also
    solved from ``starts`` (one row per spectrum solved; the solver's space), kept where that
    fit ends lower: each spectrum's own start (``init=``, a batch of fits of this circuit or
    of one nested in it), its optimum moved into an element's limit (`limit_starts`) or another
    minimum of the reference spectrum (`_tried_runner_up`). Both are solved: picking one start
    by its χ² kept the own start on all of the 130 REAL battery cycles when a W fit started a
    Wo fit (each start at the W optimum), and lost the finite-τ optima of the default search on
    61 of them (χ² up to 2.1×). ``budget``: at most that many steps each, and only the fits
    that converged within them kept. Also returns the new fits' χ² divided by the old, per
    spectrum solved (inf where not kept for want of convergence)."""
    spectra = np.arange(len(u)) if spectra is None else spectra
    u_own, _, done_own, steps_own = solver.solve(starts, spectra, np.full(spectra.size, max_steps if budget is None else min(budget, max_steps)))
    candidate = unscale(solver.outputs(u_own, spectra, done_own, steps_own, np.asarray(out.steps_total)[spectra] + steps_own), np.asarray(scale)[spectra])
    if budget is not None:
        candidate = candidate._replace(chi2=np.where(done_own, candidate.chi2, np.inf))
    with np.errstate(divide="ignore", invalid="ignore"):  # (a fit at χ² = 0: exact data)
        ratio = np.asarray(candidate.chi2) / np.asarray(out.chi2)[spectra]
    take = np.asarray(candidate.chi2) < np.asarray(out.chi2)[spectra]
    u = np.array(u)
    u[spectra[take]] = u_own[take]
    return _merged(out, spectra, candidate), u, ratio


# the reference spectrum's other minima (`_runner_ups`): at most this many, each within this
# factor of its best chi² and apart from it and each other by this fraction of chi², found by
# continuing this many of its ladder's screened points, the best from distinct basins
RUNNER_UPS = 2
RUNNER_UP_FACTOR = 10.0
RUNNER_UP_DISTINCT_CHI2 = 0.01
RUNNER_UP_CANDIDATES = 16
# screened points closer than this in the solver's space (the largest coordinate difference;
# a factor 1.35 in a parameter of logarithmic transform) count as one basin
DISTINCT_BASIN = 0.3
# a runner-up is first solved on this many spectra spread over the batch and this many of the
# worst fits, and on the others only if it lowered one of those ...
RUNNER_UP_SAMPLE = 16
# ... by at least this fraction of chi² (1 % of rms_rel)
RUNNER_UP_GAIN = 0.02
# steps a spectrum's solve from a runner-up may take (a fit converges in 10–50; a lane from
# another basin that runs on is in a valley, and held the whole solve to the step limit)
RUNNER_UP_STEPS = 100


def _runner_ups(u_best: np.ndarray, screened: list, solver: "_LaneRunner", max_steps: int) -> np.ndarray:
    """Other minima (R, K; the solver's space) of a spectrum fitted alone with optimum
    ``u_best``: the best screened points of its start ladder (``screened``: (points, chi²) of
    each rung) from basins apart from the optimum and each other (`DISTINCT_BASIN`), continued
    to convergence; the lowest ones within `RUNNER_UP_FACTOR` of the optimum's chi².

    A batch's reference spectrum is the yardstick for all: where the batch holds two kinds of
    spectra, the other kind's optimum is often the reference's second minimum. On AutoEIS's 130
    REAL battery cycles with `R0 + R1 || CPE1 + R2 || CPE2 + Ws1` the reference (cycle 106) has
    its optimum at Ws τ = 0.21 s and a second minimum 3.6× above it at τ = 46 s, the optimum of
    27 later cycles (their χ² 0.34–0.99× that of the reference's basin); with `G1` in place of
    `Ws1` the second minimum is the optimum of 46 cycles (χ² down to 0.11×)."""
    k = u_best.size
    if not screened:
        return np.empty((0, k))
    points = np.concatenate([p.reshape(-1, k) for p, _ in screened])
    chi2 = np.concatenate([np.ravel(c) for _, c in screened])
    order = np.argsort(np.where(np.isfinite(chi2), chi2, np.inf))
    # (apart from the optimum and from each point picked: the same maxima of |difference| as
    # point by point, against all the picked ones at once)
    apart = np.max(np.abs(points - u_best), axis=-1) > DISTINCT_BASIN
    picked = np.empty((RUNNER_UP_CANDIDATES + 1, k))
    picked[0], n_picked = u_best, 1
    for i, finite, far in zip(order.tolist(), np.isfinite(chi2[order]).tolist(), apart[order].tolist()):
        if not finite or n_picked > RUNNER_UP_CANDIDATES:
            break
        if far and (n_picked == 1 or np.all(np.max(np.abs(points[i] - picked[1:n_picked]), axis=-1) > DISTINCT_BASIN)):
            picked[n_picked], n_picked = points[i], n_picked + 1
    picked = list(picked[:n_picked])
    if len(picked) == 1:
        return np.empty((0, k))
    # (the optimum solved with them: its chi² on the same scale, after a step or two)
    u_end, chi2_end, _, _ = solver.solve(np.array(picked), np.zeros(len(picked), int), np.full(len(picked), max_steps))
    chi2_end = np.where(np.isfinite(chi2_end), chi2_end, np.inf)
    chi2_best, u_end, chi2_end = chi2_end[0], u_end[1:], chi2_end[1:]
    kept, kept_chi2 = [], [chi2_best]
    for i in np.argsort(chi2_end):
        if len(kept) == RUNNER_UPS or not chi2_end[i] <= RUNNER_UP_FACTOR * chi2_best:
            break
        if all(abs(chi2_end[i] / c - 1) > RUNNER_UP_DISTINCT_CHI2 for c in kept_chi2):
            kept.append(u_end[i])
            kept_chi2.append(chi2_end[i])
    return np.array(kept).reshape(-1, k)


def _tried_runner_up(out: SolverOutput, u: np.ndarray, u_other: np.ndarray, solver: "_LaneRunner", z, scale, max_steps: int) -> tuple[SolverOutput, np.ndarray, np.ndarray]:
    """``out`` with spectra also solved from ``u_other``, a second minimum of the reference
    spectrum (`_runner_ups`), kept where lower: first on a sample (`RUNNER_UP_SAMPLE` spread
    over the batch and as many of the worst fits by rms_rel), then on all the others if it
    lowered a fit of the sample by `RUNNER_UP_GAIN`; each solve at most `RUNNER_UP_STEPS`
    steps. Returns the outputs, solver points and the spectra solved. On 1,000 noisy copies of
    one spectrum no copy prefers another minimum, and the sample spares the batch that solve."""
    b = len(u)
    spread = np.unique(np.linspace(0, b - 1, min(b, RUNNER_UP_SAMPLE)).round().astype(int))
    worst = np.argsort(rms_rel_of(out.z_model, z))[-RUNNER_UP_SAMPLE:]
    sample = np.union1d(spread, worst)
    out, u, ratio = _also_solved_from(out, u, np.broadcast_to(u_other, (sample.size, u_other.size)), solver, scale, max_steps, sample, RUNNER_UP_STEPS)
    gained = int(np.sum(ratio < 1 - RUNNER_UP_GAIN))
    if not gained:
        say(f"another minimum of the reference spectrum tried on {sample.size} of the spectra: none lowered by {RUNNER_UP_GAIN * 100:.0f} % of χ² or more")
        return out, u, sample
    rest = np.setdiff1d(np.arange(b), sample)
    if not rest.size:  # (a batch no larger than the sample)
        say(f"another minimum of the reference spectrum lowered {gained} of the {b} fits")
        return out, u, sample
    say(f"another minimum of the reference spectrum lowered {gained} of {sample.size} fits: tried on the other {rest.size}")
    out, u, _ = _also_solved_from(out, u, np.broadcast_to(u_other, (rest.size, u_other.size)), solver, scale, max_steps, rest, RUNNER_UP_STEPS)
    return out, u, np.arange(b)


# rounds of `_outliers_restarted`: each offers the optima the last one found to the neighbours
# and gives the spectra that became outliers their rung
OUTLIER_ROUNDS = 3


def _outliers_restarted(out, u, used, solver, circuit, table, features, freq, z, n_starts, seed, scale, max_steps, registry) -> SolverOutput:
    """A large batch's fits improved where they are poor relative to what the data allow:
    first from their neighbours' optima (`_from_neighbours`); then one rung (``n_starts``
    starts) for each fit poor relative to the other spectra (`starts.batch_outliers`) or
    grossly against its KK misfit (`result.gross_misfits`, the misfit warning's rule, where
    the other spectra are no yardstick) — the reference spectrum, fitted alone, climbed the
    whole ladder, and every spectrum was offered that optimum. The yardstick moves as the
    rung improves fits: on AutoEIS's 130 REAL battery cycles with
    `L0 + R0 + R1 || CPE1 + R2 || CPE2 + Ws1` the first pass left the median at 6 % rms_rel,
    its rung brought most to 0.65 %, and cycles at 2–4 % (0.5–0.9 % fitted alone) became the
    outliers only then. So up to `OUTLIER_ROUNDS` rounds: the improved optima offered to the
    neighbours again, and the spectra that became outliers (not given starts before) their rung.
    ``used`` (starts per spectrum) is updated in place."""
    tried = np.zeros(len(z), bool)
    out, u = _from_neighbours(out, u, solver, scale, max_steps)
    for _ in range(OUTLIER_ROUNDS):
        poor = np.union1d(_poor_in_batch(out, z), gross_misfits(freq, z, out.z_model, solver.kk_chains))
        poor = poor[~tried[poor]]
        if not poor.size:
            break
        before = np.array(out.chi2[poor])
        say(f"{poor.size} of the fits poor beside the others or against their KK misfit: {draw_size(table, n_starts)} more starts each")
        out = _multistart_rung(out, solver, circuit, table, features, poor, n_starts, 1, 0, seed, scale, max_steps, registry)
        used[poor] = draw_size(table, n_starts)
        tried[poor] = True
        if not np.any(out.chi2[poor] < before):  # nothing moved: the yardstick and the neighbours' optima are as they were
            break
        out, u = _from_neighbours(out, to_solver_space(table, np.asarray(out.x)), solver, scale, max_steps)
    return out


def _poor_in_batch(out: SolverOutput, z) -> np.ndarray:
    return batch_outliers(rms_rel_of(out.z_model, z), np.asarray(out.code) == SolverStatus.CONVERGED)


def _multistart_rung(out, solver, circuit, table, features, poor, n_starts, multiple, rung, seed, scale, max_steps, registry, screened: list | None = None) -> SolverOutput:
    """``out`` with spectra ``poor`` improved by one rung of the start ladder: ``multiple``
    draws of ``n_starts`` starts each (as `fit` draws them), screened for `SCREEN_STEPS`
    steps (at most ``max_steps``), the best of each spectrum continued to convergence and kept
    where it is better. ``screened`` (a list): the screened points (len(poor), starts, K) and
    their chi² (len(poor), starts) are appended to it."""
    per = multiple * draw_size(table, n_starts)  # (each draw's starts: the given start once where nothing is jittered)
    starts = rung_starts(circuit, table, features[poor], n_starts, [rung_seed(seed, rung, call) for call in range(multiple)], registry).reshape(poor.size * per, -1)
    owner = np.repeat(poor, per)
    u_s, chi2_s, _, steps_s = solver.solve(starts, owner, np.full(owner.size, min(SCREEN_STEPS, max_steps)), cold=True)
    chi2_s = np.where(np.isfinite(chi2_s), chi2_s, np.inf).reshape(poor.size, per)
    if screened is not None:
        screened.append((u_s.reshape(poor.size, per, -1), chi2_s))
    best = np.argmin(chi2_s, axis=1)
    u_best = u_s.reshape(poor.size, per, -1)[np.arange(poor.size), best]
    u_m, _, done_m, steps_m = solver.solve(u_best, poor, np.full(poor.size, max_steps))
    screened = steps_s.reshape(poor.size, per).sum(axis=1)
    multi = unscale(solver.outputs(u_m, poor, done_m, steps_m, screened + steps_m), scale[poor])
    return _merged(out, poor, multi)


_JACOBIAN = SolverOutput._fields.index("jacobian")


def _rows_joined(jacobians: list[np.ndarray], n_padded: int, n: int) -> np.ndarray:
    """The chunks' Jacobians (…, 2·n_padded, K) of a solve on points padded by `padded_points`
    joined along the first axis, with the rows `trimmed` keeps (the first ``n`` points' Re, then
    their Im) copied once into a C-ordered stack: concatenating, then trimming with a fancy
    index copied twice and left the stack laid out (2N, B, K) in memory."""
    if n_padded == n:
        return np.concatenate(jacobians)
    out = np.empty((sum(len(j) for j in jacobians), 2 * n, *np.shape(jacobians[0])[2:]), np.result_type(*jacobians))
    start = 0
    for j in jacobians:
        out[start : start + len(j), :n] = j[:, :n]
        out[start : start + len(j), n:] = j[:, n_padded : n_padded + n]
        start += len(j)
    return out


def _merged(out: SolverOutput, rows, candidate: SolverOutput) -> SolverOutput:
    """``out`` with rows ``rows`` replaced by ``candidate`` where its chi² is lower."""
    for mine, theirs in zip(out, better(out.row(rows), candidate)):
        if theirs is not None:
            mine[rows] = theirs  # (`outputs` gives arrays of our own)
    return out


# a neighbour's optimum replaces a spectrum's own when its chi² there is lower by this fraction
NEIGHBOUR_GAIN = 1e-3
NEIGHBOUR_PASSES = 3


def _from_neighbours(out, u, solver, scale, max_steps):
    """Neighbouring spectra of a batch (consecutive cycles, trials) have neighbouring optima:
    where the optimum of spectrum i ± 1 gives spectrum i a lower chi² than its own solution,
    spectrum i landed in a local minimum; it is solved again from there (kept if better).
    Up to `NEIGHBOUR_PASSES` passes, so an optimum travels along a run of trapped spectra.
    Returns the outputs and the solver points."""
    b = len(u)
    spectra = np.arange(b)
    u = np.array(u)
    for _ in range(NEIGHBOUR_PASSES):
        own = np.asarray(out.chi2) * np.asarray(scale) ** 2  # (the solver's scaled chi²)
        left, right = np.r_[0, spectra[:-1]], np.r_[spectra[1:], b - 1]
        chi2_left, chi2_right = solver.chi2_at([u[left], u[right]], spectra)
        from_right = chi2_right < chi2_left
        start = np.where(from_right[:, None], u[right], u[left])
        trial = np.where(from_right, chi2_right, chi2_left)
        redo = np.flatnonzero(trial < (1 - NEIGHBOUR_GAIN) * own)
        if not redo.size:
            break
        u_r, _, done_r, steps_r = solver.solve(start[redo], redo, np.full(redo.size, max_steps))
        steps_before = np.asarray(out.steps_total)[redo]
        candidate = unscale(solver.outputs(u_r, redo, done_r, steps_r, steps_before + steps_r), scale[redo])
        take = redo[np.asarray(candidate.chi2) < np.asarray(out.chi2)[redo]]
        out = _merged(out, redo, candidate)
        u[take] = u_r[np.isin(redo, take)]
    return out, u


# batches of at least this many spectra also try the solution of a reference spectrum as start
REFERENCE_MIN_SPECTRA = 16


def _with_reference_start(guesses, solver, circuit, table, freq, z, sigma, **options) -> tuple[np.ndarray, np.ndarray]:
    """Spectra of one batch (trials, subjects, conditions) usually resemble each other: the fit
    of the most typical spectrum (closest to the median log|Z|) is a better start for most of
    them than their own data-driven guess. Each spectrum starts from whichever of the two has
    the lower chi² on its data. Also returns the reference's other minima (`_runner_ups`)."""
    log_mag = np.log(np.abs(z))
    typical = int(np.argmin(np.sum((log_mag - np.median(log_mag, axis=0)) ** 2, axis=1)))
    screened: list = []
    reference, _, reference_solver, _ = _solve_stack(circuit, table, freq, z[typical : typical + 1], None if sigma is None else sigma[typical : typical + 1], screened=screened, **options)
    if not np.isfinite(reference.chi2[0]):
        return guesses, np.empty((0, guesses.shape[1]))
    u_best = to_solver_space(table, reference.x[0])
    runner_ups = _runner_ups(u_best, screened, reference_solver, options["max_steps"])
    u_ref = np.broadcast_to(u_best, guesses.shape)
    spectra = np.arange(len(z))
    chi2_ref, chi2_guess = solver.chi2_at([u_ref, guesses], spectra)
    take = chi2_ref < chi2_guess
    return np.where(take[:, None], u_ref, guesses), runner_ups


class _LaneRunner:
    """Host side of the lane solver: splits problems into fixed-size chunks (one compilation
    serves any batch size; at least one chunk per core), runs each group of one chunk per
    device as one program on all devices at once (`solvers.over_devices`: one compilation
    for every device), then continues problems left open by the many-lane pass on a few
    lanes."""

    def __init__(self, solvers: TreeSolvers, rows: SpectrumRows, shared: SharedArgs, n_points: int):
        self.lanes, self.finish, self.chi2, self.key = solvers.lanes, solvers.finish, solvers.chi2, solvers.key
        self.rows, self.shared = rows, shared
        self.n_points = n_points  # (before padding: `outputs` are cut back to them)
        self._placed: dict = {}
        self._shared_placed = None
        self.kk_chains = KKChains()  # spectrum → its KK test's chain, fitted once per call (`result.known_kk_misfits`, `result.misfit_notes`)

    def _groups(self, n: int, capacity: int, n_lanes: int) -> list[list[np.ndarray]]:
        """Problems 0..n-1 in chunks of at most ``capacity``, grouped one chunk per device: a
        chunk per device where there are at least two problems per lane for each, and whole
        groups (more, smaller chunks) rather than a last group with idle devices."""
        n_devices = len(jax.devices())
        n_chunks = max(-(-n // capacity), min(n_devices, -(-n // (2 * n_lanes))))
        if n_chunks > n_devices:
            n_chunks = -(-n_chunks // n_devices) * n_devices
        chunks = np.array_split(np.arange(n), n_chunks)
        return [chunks[i : i + n_devices] for i in range(0, n_chunks, n_devices)]

    def _local(self, spectra: list[np.ndarray], capacity: int, sharding):
        """The rows each chunk of a group uses, padded to ``capacity``, stacked over the
        devices (a device without a chunk gets spectrum 0's row and no problem) and placed,
        and the problems' indices into them (kept: successive passes reuse the same
        chunks); the shared arguments, placed on every device."""
        key = (tuple(s.tobytes() for s in spectra), capacity)
        if key not in self._placed:
            picks, locals_ = [], []
            for spectrum in spectra + [np.zeros(1, int)] * (len(jax.devices()) - len(spectra)):
                used, local = np.unique(spectrum, return_inverse=True)
                picks.append(np.concatenate([used, np.full(capacity - used.size, used[0])]))
                locals_.append(np.concatenate([local, np.zeros(capacity - spectrum.size, int)]))
            pick = np.stack(picks)
            rows = jax.device_put(SpectrumRows(*(np.ascontiguousarray(v[pick]) for v in self.rows)), sharding)
            self._placed[key] = rows, np.stack(locals_).astype(np.int32)
        if self._shared_placed is None:
            self._shared_placed = jax.device_put(self.shared, jax.sharding.NamedSharding(sharding.mesh, jax.sharding.PartitionSpec()))
        return (*self._placed[key], self._shared_placed)

    @staticmethod
    def _stacked(values: np.ndarray, parts: list[np.ndarray], capacity: int, fill) -> np.ndarray:
        """``values[part]`` of each chunk padded to ``capacity`` (with ``fill``: a row
        of values, or a scalar), stacked over the devices."""
        out = np.empty((len(jax.devices()), capacity) + values.shape[1:], values.dtype)
        out[...] = fill
        for j, part in enumerate(parts):
            out[j, : part.size] = values[part]
        return out

    def _run(self, u0, spectrum, budget, scaled, *, many: bool):
        n_lanes, capacity = (_LANES, _CAPACITY) if many else (_FEW_LANES, _FEW_CAPACITY)
        solve, sharding = over_devices(self.lanes(n_lanes), 6, drain=not many, stored=("batch-lanes", (self.key, n_lanes)))
        groups = self._groups(len(u0), capacity, n_lanes)
        pending = []
        for parts in groups:
            rows, local, shared = self._local([spectrum[p] for p in parts], capacity, sharding)
            counts = np.zeros(len(jax.devices()), np.int64)
            counts[: len(parts)] = [p.size for p in parts]
            pending.append(solve(self._stacked(u0, parts, capacity, u0[0]), local, self._stacked(budget, parts, capacity, 0), counts, rows, self._stacked(scaled, parts, capacity, True), shared))
        results = jax.device_get(pending)
        return [np.concatenate([r[i][j, : p.size] for r, parts in zip(results, groups) for j, p in enumerate(parts)]) for i in range(4)]

    def solve(self, u0, spectrum, budget, *, cold: bool = False):
        """(u, chi², done, steps) of every problem, each run to convergence or its budget.
        ``cold`` (random starts): damped with λI by the trust-region rule, as a single fit's
        first steps; else with Marquardt's scaling (docs/fitting.md, "Damping")."""
        many = len(u0) >= _MANY_LANES_FROM * len(jax.devices())
        scaled = np.full(len(u0), not cold)
        u, chi2, done, steps = self._run(np.asarray(u0, float), spectrum, budget, scaled, many=many)
        open_ = np.flatnonzero(~done & (steps < budget))
        if many and open_.size:  # left open by the early stop: continue on a few lanes
            u2, chi2_2, done2, steps2 = self._run(u[open_], spectrum[open_], budget[open_] - steps[open_], scaled[open_], many=False)
            u[open_], chi2[open_], done[open_], steps[open_] = u2, chi2_2, done2, steps[open_] + steps2
        return u, chi2, done, steps

    def _per_spectrum(self, name: str, points, spectrum, *same) -> list:
        """``fn(*points, local, rows, shared, *same)`` (``fn``: the solvers' ``name``, "chi2"
        or "finish") at ``points`` (arrays (n, K)) of spectra ``spectrum``, in chunks of one
        of two fixed sizes run on all devices at once; each chunk's results, trimmed. Calls of
        at least `_CAPACITY` points take chunks of that size (a second compilation, for large
        batches only): 1,000 spectra in chunks of 64 made 8 calls, each costing ~0.6 ms to
        place, launch and fetch on top of its arithmetic."""
        capacity, n_lanes = (_CAPACITY, _LANES) if len(spectrum) >= _CAPACITY else (_FEW_CAPACITY, _FEW_LANES)
        run, sharding = over_devices(getattr(self, name), len(points) + 2, stored=(f"batch-{name}", self.key))
        groups = self._groups(len(spectrum), capacity, n_lanes)
        pending = []
        for parts in groups:
            rows, local, shared = self._local([spectrum[p] for p in parts], capacity, sharding)
            pending.append(run(*(self._stacked(u, parts, capacity, u[0]) for u in points), local, rows, shared, *same))
        return [jax.tree_util.tree_map(lambda a, j=j, n=p.size: a[j, :n], r) for r, parts in zip(jax.device_get(pending), groups) for j, p in enumerate(parts)]

    def chi2_at(self, points, spectrum) -> list[np.ndarray]:
        """Weighted chi² of spectra ``spectrum`` at each array of solver points u (+inf where
        not finite)."""
        return [np.nan_to_num(np.concatenate(self._per_spectrum("chi2", [np.asarray(u, float)], spectrum, True)), nan=np.inf) for u in points]

    def chi2_at_x(self, points, spectrum) -> np.ndarray:
        """Weighted chi² of spectra ``spectrum`` at free parameter values ``points`` (C, K)."""
        return np.concatenate(self._per_spectrum("chi2", [np.asarray(points, float)], spectrum, False))

    def outputs(self, u, spectrum, done, steps, steps_total) -> SolverOutput:
        """Solver outputs at solutions ``u`` of spectra ``spectrum`` (as `solvers._finish`), each
        a new array (not a view of another or of an argument: callers may update them)."""
        parts = self._per_spectrum("finish", [u], spectrum)
        n_padded = np.shape(parts[0].z_model)[-1]
        out = SolverOutput(*(None if first is None else _rows_joined([p[i] for p in parts], n_padded, self.n_points) if i == _JACOBIAN else np.concatenate([p[i] for p in parts])
                             for i, first in enumerate(parts[0])))
        out = out._replace(z_model=out.z_model[..., : self.n_points])  # (`trimmed`'s cut; the Jacobian's rows were cut as they were joined)
        code = np.where(done, int(SolverStatus.CONVERGED), int(SolverStatus.MAX_STEPS))
        return out._replace(code=code, steps=np.array(steps), steps_total=np.array(steps_total), chi2_starts=out.chi2[:, None].copy())


def _packed_stack(circuit, table: ParameterTable, freq, z, sigma, *, weighting, n_starts, max_steps, seed, registry, source, starts=None, remainder: bool = False, attrs=None) -> tuple[np.ndarray, list[tuple[str, ...]], list[list[list[str]]]]:
    """One row per spectrum (values, stderr, linearised stderr, at-bound flags, chi2, converged,
    evaluations, Re/Im of Z_model, the covariance of the free parameters as a `FitResult`'s), its warnings (`notes.Note`s with their tags,
    as a `FitResult`'s `tagged_warnings`) and its unidentified groups (`null_sets`, as
    `FitResult.unidentified_groups`), without a FitResult per spectrum: the uncertainties of all
    spectra in one stacked computation (`covariances`), their warnings too (`stack_notes`); only
    spectra that overflowed or did not converge go through `fit_result`."""
    out, used, solver, inward = _solve_stack(circuit, table, freq, z, sigma, weighting=weighting, n_starts=n_starts, max_steps=max_steps, seed=seed, registry=registry, source=source, starts=starts)
    say(f"standard errors, bounds and warnings of the {counted(len(z), 'fit')}")
    out = canonical_order(circuit, table, freq, out, registry)
    b, k, n_res = z.shape[0], len(table.free_names), 2 * len(freq)
    chi2 = np.array(out.chi2, float)  # copies: device_get's arrays are read-only
    finite = np.isfinite(chi2) & np.all(np.isfinite(out.z_model), axis=-1)
    converged = finite & (settled_codes(out.code, out.z_model, z) == SolverStatus.CONVERGED)
    values = np.array(out.x, float)
    stderr = np.full(values.shape, np.nan)
    inv_re, inv_im = weights(z, sigma, weighting, source, freq)
    converged &= ~inward  # a fit left at a bound while chi² falls inward is not converged (`fit_result` says why)
    odd = ~converged  # these get `fit_result`'s handling of overflow and non-convergence
    notes: list[tuple[str, ...]] = [()] * b
    groups: list[list[list[str]]] = [[] for _ in range(b)]
    cov, corr, singular = np.zeros((b, k, k)), np.zeros((b, k, k)), np.zeros(b, bool)
    if k:
        jac = out.jacobian if finite.all() else np.where(finite[:, None, None], out.jacobian, 0.0)
        chi2_red = chi2 / (n_res - k) if n_res > k else np.full(b, np.nan)
        cov, corr, sv, vt = covariances(jac, chi2_red, weighting)
        stderr[:, table.free_index] = np.sqrt(np.clip(np.einsum("bii->bi", cov), 0, None))
        s_max = np.where(sv[:, :1] > 0, sv[:, :1], 1.0)  # (as `null_sets`)
        singular = np.any(sv < SINGULAR_RATIO_LIMIT * s_max, axis=1)
    # parameters at a bound: as `fit_result`, the candidates of all regular fits confirmed at once
    sides = np.zeros((b, k), np.int8)
    regular = np.flatnonzero(~odd)
    jac_regular = jac[regular] if k else None  # (one copy for the four rules below that read it)
    sides[regular] = confirm_bounds(table, values[regular], bound_sides(table, values[regular], stderr[regular]), lambda p, s: solver.chi2_at_x(p, regular[s]), n_res)
    if k and regular.size:  # (a parameter of a term that vanishes at any value is undetermined, not at a bound: as `fit_result`)
        sides[regular] = vanishing_term_sides(circuit, registry, table, values[regular], sides[regular], freq, z[regular], jac_regular)
    # parameters of a term that changes Z by < 1e-6: at the natural bound that explains it, or undetermined (as `fit_result`)
    free_values, free_stderr = values[regular][:, table.free_index], stderr[regular][:, table.free_index]
    vanishing = np.zeros((len(regular), k), np.int8)
    if k:
        candidates = vanishing_candidates(sides[regular], free_values, free_stderr)
        vanishing = vanishing_parameters(circuit, registry, table, values[regular], freq, candidates, jac_regular)
    sides[regular], free_stderr, vanished = settle_vanishing(vanishing, sides[regular], free_values, free_stderr)
    if k and regular.size:  # the others' errors hold a vanishing term's parameters at no bound at their values (as `fit_result`)
        held = vanishing_term_mask(circuit, registry, table, values[regular], freq, jac_regular) & (sides[regular] == 0)
        if held.any():
            cov[regular], corr[regular] = held_covariances(jac_regular, chi2_red[regular], weighting, cov[regular], corr[regular], held)
            free_stderr = np.where(held | vanished, free_stderr, np.sqrt(np.clip(np.einsum("bii->bi", cov[regular]), 0, None)))
    # the parameters of near-null directions are undetermined whatever χ²_red is (as `fit_result`)
    ratios = {}
    for row, i in enumerate(regular.tolist()):
        if singular[i]:
            groups[i], ratios[i] = null_sets(sv[i], vt[i], table.free_names)
            free_stderr[row] = unidentified_stderr(table.free_names, groups[i], sides[i], free_stderr[row])
    stderr[np.ix_(regular, table.free_index)] = free_stderr
    # the exact warning text of a single fit (`fit_notes`), built for the stack at once, near-null groups included
    for row, note in stack_notes(table, values[regular], stderr[regular], corr[regular], sides[regular], freq=freq, z=z[regular],
                                 null_sets=[groups[i] for i in regular.tolist()], ratios=[ratios.get(i) for i in regular.tolist()]).items():
        notes[regular[row]] = note
    names = table.names
    # idle branches (the fits that did not converge get the note from `fit_result`)
    idle = idle_branch_notes(circuit, registry, table, values[regular], undetermined_mask(table, values[regular], stderr[regular], sides[regular]) | vanished, freq)
    for row, note in idle.items():
        notes[regular[row]] = notes[regular[row]] + note
    # the warnings above speak of the linearisation; the result gives no standard error to a
    # parameter at a bound (as `fit_result`; the odd fits below get it from there)
    linearised = stderr.copy()
    stderr[np.ix_(regular, table.free_index)] = without_error(sides[regular], vanished, free_stderr)[0]
    z_model = np.array(out.z_model)
    weighting_extra = data_notes(freq, z, z_model, sigma, weighting, source, solver.kk_chains, remainder=remainder, attrs=attrs, n_free=int(table.free_index.size))
    misfit = [with_tag(notes_i, MISFIT) for notes_i in weighting_extra]  # (each spectrum's misfit notes alone, the last of its notes)
    for i in np.flatnonzero(odd):
        r = fit_result(circuit, table, freq, z[i], out.row(i), weighting, int(used[i]), 0.0, registry, chi2_at_x=lambda p, s, i=i: solver.chi2_at_x(p, s + i), extra_notes=weighting_extra[i], weights=(inv_re[i], inv_im[i]))
        values[i] = [r.values[n] for n in names]
        stderr[i] = [r.stderr[n] for n in names]
        linearised[i] = [r.linearised_stderr[n] for n in names]
        chi2[i], converged[i], z_model[i], notes[i] = r.chi2, r.converged, r.z_model, r.tagged_warnings
        groups[i] = [list(g) for g in r.unidentified_groups]
        sides[i] = [n in r.at_bound for n in table.free_names]
        cov[i] = r.covariance
    for i in np.flatnonzero(~odd):
        notes[i] = notes[i] + weighting_extra[i]
    # a misfit the user's fixed value or bound explains is told so, not blamed on the model (as a single fit's)
    for i in [i for i in range(b) if misfit[i]]:
        at = tuple(n for n, side in zip(table.free_names, sides[i].tolist()) if side)
        checked = constraint_misfit_notes(circuit, table, registry, freq, z[i], z_model[i], None if sigma is None else sigma[i], dict(zip(names, values[i].tolist())), at, misfit[i], solver.kk_chains.misfit(i), weighting=weighting, fit=_spectrum_fit, attrs=attrs)
        notes[i] = with_constraint_notes(notes[i], misfit[i], checked)  # (the constraint's note, untagged, blames no model)
    notes = [sign_notes_first(n) for n in notes]  # (`notes.Note`s: their tags go with them)
    at_bound = np.zeros(values.shape)
    at_bound[:, table.free_index] = sides != 0
    stats = np.stack([chi2, converged.astype(float), np.asarray(out.steps_total, float)], axis=-1)
    return np.concatenate([values, stderr, linearised, at_bound, stats, z_model.real, z_model.imag, cov.reshape(b, k * k)], axis=-1), notes, groups


# lane solver shapes: many lanes for large batches, few for the rest and stragglers (each pair
# is one compilation per circuit)
_LANES, _CAPACITY = 64, 512
_FEW_LANES, _FEW_CAPACITY = 8, 64
# many lanes take a call of at least this many problems per device (four per lane): below,
# 64 lanes mostly wait for their slowest problems, and a first call on a few hundred spectra
# (the 130 battery cycles; a rung of 256 starts) compiles the few-lane program alone
_MANY_LANES_FROM = 4 * _LANES


def data_notes(freq, z, z_model, sigma, weighting: str, source: str, kk_chains: KKChains | None = None, *, remainder: bool = False, attrs=None, n_free: int | None = None) -> list[tuple[str, ...]]:
    """The warnings of fits to spectra z (B, N) with models z_model (B, N) that concern the data
    rather than the parameters, one tuple per spectrum, as a single fit gives them: a weighting
    dominated by a few points (`weighting_notes`), points with Re Z < 0 (`non_passive_notes`)
    residuals uneven across the band (`uneven_residual_notes`), residuals beyond or below the
    stated σ (`sigma_scale_notes`)
    and a gross misfit (`misfit_notes`; ``kk_chains``: the fit call's Kramers–Kronig chains, `kk.KKChains`);
    ``remainder``: the spectra are a subtraction's remainder (`is_remainder`), Re Z < 0 its cause;
    ``attrs``: the data's, for how to fix a flipped sign (`misfit_notes`); ``n_free``: each
    fit's number of free parameters (`misfit_notes`; None for a shared fit's spectra). The notes
    of `misfit_notes`, `uneven_residual_notes` and `sigma_scale_notes` are `notes.Note`s that carry
    their tags (`notes.WARNING_TAGS`; the misfit notes, the last of a spectrum's, tagged
    `notes.MISFIT`: `notes.with_tag`), the others plain texts."""
    b = len(z)
    inverse_weights = weights(z, sigma, weighting, source, freq)
    weighted = dominated_notes(weighting, freq, z, *inverse_weights)
    # (σ-weighted fits beyond σ: whether a KK-consistent chain under the same σ is too, σ then misstating the noise)
    misstated, chain_chi2_red = sigma_misstated(freq, z, z_model, sigma, weighting, n_free)
    misfit = misfit_notes(freq, z, z_model, kk_chains, sigma, attrs, weighting=weighting, n_free=n_free, misstated=misstated)
    trial_means = trial_means_of_sigma(attrs)  # (σ the standard error of trial means: what the notes of residuals below or uneven against it say)
    uneven = uneven_residual_notes(freq, z, z_model, *inverse_weights, weighting, misfit, has_sigma=sigma is not None, trial_means=trial_means)
    scale = sigma_scale_notes(z, z_model, *inverse_weights, weighting, n_free, misfit, chain_chi2_red, trial_means)  # (the blame: the misfit notes' tags)
    noise = None if sigma is not None else fit_noise(freq, z, z_model, n_free or 0)  # (Re Z < 0 is judged against the noise the residuals show)
    passive = ~np.any(non_passive(z, sigma, noise), axis=-1)  # (the spectra `non_passive_notes` has nothing to say of)
    return [tuple(weighted[i]) + (() if passive[i] else non_passive_notes(freq, z[i], None if sigma is None else sigma[i], remainder=remainder, noise=None if noise is None else noise[i]))
            + uneven[i] + scale[i] + misfit[i] for i in range(b)]


def _median_stderr(stderr: np.ndarray, fixed: bool) -> float | None:
    """The median over the spectra of one parameter's standard errors that the JSON shows
    (`shown_stderr`: finite, not fixed; not at a bound), None where no spectrum has one."""
    shown = np.asarray(stderr, float).reshape(-1)
    shown = shown[np.isfinite(shown)]
    return None if fixed or shown.size == 0 else float(np.median(shown))


RESULT_NAMES = frozenset({
    "param", "fit_output", "value", "stderr", "linearised_stderr", "fixed", "lower", "upper", "at_bound", "chi2", "chi2_red", "aic", "bic", "rms_rel", "converged", "n_evaluations", "Z_model", "sigma", "unit",  # ("unit": to_xarray's coordinate along param)
    "covariance", "free_param", "free_param_2",  # (each spectrum's covariance)
})
"""The names of a batch result's dimensions and variables (`fit_batch`'s Dataset, and the core
dimension of the chunked path's ``apply_ufunc``): a batch dimension of one of these names is
refused (`grid.refuse_result_names`), where xarray had failed deep inside the fit (or, for
``param``, built a Dataset with that dimension twice)."""


def fit_batch(circuit: Circuit, data: xr.Dataset, table: ParameterTable, *, weighting: str, n_starts: int, max_steps: int, seed: int, registry: Registry = DEFAULT_REGISTRY, source: str = "data", t0: float | None = None, starts: np.ndarray | None = None) -> BatchFitResult:
    """Fits of ``circuit`` to every spectrum of ``data``; ``starts`` (*extra dims, P): each
    spectrum's own starting values (NaN: its data-driven guess), `BatchFitResult.per_spectrum_starts`."""
    t0 = time.perf_counter() if t0 is None else t0
    extra = tuple(d for d in data["Z"].dims if d != "frequency")
    refuse_result_names(extra, RESULT_NAMES, "a fit result", source=source)
    freq = np.asarray(data["frequency"].values, float)
    names = table.names
    n_par, n_freq = len(names), freq.size
    z_da = data["Z"].transpose(*extra, "frequency")
    sigma_da = data["sigma"].transpose(*extra, "frequency") if "sigma" in data else None
    warnings: dict[str, tuple[str, ...]] = {}

    def fit_block(z_block, *rest):
        """(z, [sigma], [starts]) of a block of spectra, as `inputs` below lists them."""
        rest = list(rest)
        sigma_block = rest.pop(0) if sigma_da is not None else None
        starts_block = rest.pop(0) if starts is not None else None
        shape = z_block.shape[:-1]
        z2 = np.asarray(z_block).reshape(-1, n_freq)
        s2 = None if sigma_block is None else np.asarray(sigma_block).reshape(-1, n_freq)
        x0 = None if starts_block is None else np.asarray(starts_block).reshape(-1, n_par)
        packed, notes, groups = _packed_stack(circuit, table, freq, z2, s2, weighting=weighting, n_starts=n_starts, max_steps=max_steps, seed=seed, registry=registry, source=source, starts=x0, remainder=is_remainder(data.attrs), attrs=data.attrs)
        note_array, group_array = np.empty(len(notes), object), np.empty(len(groups), object)  # (tuples and lists as elements, not as a further axis)
        note_array[:], group_array[:] = notes, groups
        return packed.reshape(*shape, -1), note_array.reshape(shape), group_array.reshape(shape)

    free_names = list(table.free_names)
    n_free = len(free_names)
    width = 4 * n_par + len(_STATS) + 2 * n_freq + n_free * n_free
    if z_da.chunks is not None:
        inputs = [z_da] + ([sigma_da] if sigma_da is not None else [])
        core = [["frequency"]] * len(inputs)
        if starts is not None:  # chunked as the spectra, so that each block gets its own starts
            inputs.append(xr.DataArray(starts, dims=(*extra, "start_param"), coords={d: z_da[d] for d in extra if d in z_da.coords}).chunk({d: z_da.chunksizes[d] for d in extra}))
            core.append(["start_param"])
        with python_warnings.catch_warnings():
            # dask builds its empty "meta" output by casting the complex input's meta to float
            python_warnings.simplefilter("ignore", np.exceptions.ComplexWarning)
            packed_da, notes_da, groups_da = xr.apply_ufunc(
                fit_block,
                *inputs,
                input_core_dims=core,
                output_core_dims=[["fit_output"], [], []],
                dask="parallelized",
                output_dtypes=[np.float64, object, object],
                dask_gufunc_kwargs={"output_sizes": {"fit_output": width}, "allow_rechunk": True},
            )
            computed = xr.Dataset({"packed": packed_da, "notes": notes_da, "groups": groups_da}).compute()  # one pass over the graph
        packed = computed["packed"].transpose(*extra, "fit_output").values
        notes = computed["notes"].transpose(*extra).values.ravel().tolist()
        groups = computed["groups"].transpose(*extra).values.ravel().tolist()
    else:
        packed, notes, groups = fit_block(z_da.values, *([] if sigma_da is None else [sigma_da.values]), *([] if starts is None else [starts]))
        notes, groups = notes.ravel().tolist(), groups.ravel().tolist()
    labels = [[f"{d}={c}" for c in (data[d].values if d in data.coords else range(n))] for d, n in zip(extra, z_da.shape)]
    unidentified: dict[str, list[list[str]]] = {}  # (as the warnings: only the spectra that have any)
    tags: dict[str, tuple[tuple[str, ...], ...]] = {}  # (each spectrum's warnings' tags: `BatchFitResult.warning_tags`)
    for idx, note, group in zip(np.ndindex(*z_da.shape[:-1]), notes, groups):
        key = ", ".join(label[i] for label, i in zip(labels, idx))
        if note:
            warnings[key], tags[key] = tuple(str(n) for n in note), notes_tags(note)
        if group:
            unidentified[key] = [list(g) for g in group]
    coords = {d: data[d].values for d in extra if d in data.coords}
    values = packed[..., :n_par]
    stderr = packed[..., n_par : 2 * n_par]
    linearised = packed[..., 2 * n_par : 3 * n_par]
    at_bound = packed[..., 3 * n_par : 4 * n_par] != 0
    chi2, converged, n_eval = (packed[..., 4 * n_par + i] for i in range(3))
    off = 4 * n_par + 3
    z_model = packed[..., off : off + n_freq] + 1j * packed[..., off + n_freq : off + 2 * n_freq]
    covariance = packed[..., off + 2 * n_freq :].reshape(*packed.shape[:-1], n_free, n_free)
    z_data = z_da.values if z_da.chunks is None else z_da.compute().values
    with np.errstate(all="ignore"):  # overflowed fits carry +inf
        rel = (z_model - z_data) / np.abs(z_data)
        rms_rel = np.sqrt(np.mean(np.abs(rel) ** 2, axis=-1))
    k = int((~table.fixed).sum())
    n_res = 2 * n_freq
    aic, bic = information_criteria(chi2, n_res, k)
    param_first = lambda a: np.moveaxis(a, -1, 0)  # noqa: E731
    ds = xr.Dataset(
        {
            "value": (("param", *extra), param_first(values)),
            "stderr": (("param", *extra), param_first(stderr), {"note": STDERR_NOTE}),
            "linearised_stderr": (("param", *extra), param_first(linearised), {"long_name": LINEARISED_STDERR_NAME}),
            "fixed": ("param", table.fixed),
            "lower": ("param", table.lower, {"long_name": "the fit's lower bound of each parameter (natural, or the user's bounds=)"}),
            "upper": ("param", table.upper, {"long_name": "the fit's upper bound of each parameter (natural, or the user's bounds=)"}),
            "at_bound": (("param", *extra), param_first(at_bound)),
            "chi2": (extra, chi2),
            "chi2_red": (extra, chi2 / (n_res - k) if n_res > k else np.full(chi2.shape, math.nan)),
            "aic": (extra, aic),
            "bic": (extra, bic),
            "rms_rel": (extra, rms_rel),
            "converged": (extra, converged.astype(bool)),
            "n_evaluations": (extra, n_eval.astype(np.int64)),
            "Z": ((*extra, "frequency"), z_data, {"units": "ohm"}),
            "Z_model": ((*extra, "frequency"), z_model, {"units": "ohm"}),
            "covariance": ((*extra, "free_param", "free_param_2"), covariance, {"note": COVARIANCE_NOTE}),
        },
        coords={"param": list(names), "free_param": free_names, "free_param_2": free_names, "frequency": ("frequency", freq, {"units": "Hz"}), **coords},
        attrs={"model": str(circuit), "weighting": weighting, "n_free": k, "unidentified_groups": unidentified},
    )
    if sigma_da is not None:  # (the data's own σ, which weighted the fits: `fit_of` refits with it)
        ds["sigma"] = ((*extra, "frequency"), sigma_da.values if sigma_da.chunks is None else sigma_da.compute().values, {"units": "ohm"})
    return BatchFitResult(circuit, ds, weighting, warnings, time.perf_counter() - t0, registry, warning_tags=tags)


def batch_with_warnings(batch: BatchFitResult, warnings) -> BatchFitResult:
    """``batch`` with ``warnings`` (spectrum key → its warnings) in place of its own: `notes.Note`s
    (its `BatchFitResult.tagged_warnings`, renamed, merged or filtered) keep their tags; a batch
    whose tags are not known and that gets no tagged note keeps none (as `result.with_warnings`)."""
    warnings = {k: tuple(v) for k, v in warnings.items()}
    known = batch.warning_tags is not None or any(tags_of(n) for v in warnings.values() for n in v)
    return replace(batch, warnings={k: tuple(str(n) for n in v) for k, v in warnings.items()}, warning_tags={k: notes_tags(v) for k, v in warnings.items()} if known else None, _tags_given_with=None)  # (the tags given with these warnings: theirs)


def stored_batch_tags(attrs, warnings) -> dict[str, tuple[tuple[str, ...], ...]] | None:
    """`BatchFitResult.warning_tags` from a saved batch's attributes, for its ``warnings``: as
    stored (``warning_tags``); in a file written before they were, built from its
    ``model_misfits`` (the spectra whose warnings blame the model: the warning that says so, by
    `MODEL_MISFIT_MARKS`, or else the spectrum's last, its misfit note, tagged `notes.MISFIT` and
    `notes.MODEL_MISFIT`); None in a file without either (its words then decide)."""
    stored = attrs.get("warning_tags")
    if isinstance(stored, Mapping):
        tags = {str(k): stored_tags(v, len(warnings.get(str(k), ()))) for k, v in stored.items()}
        if set(tags) == set(warnings) and all(t is not None for t in tags.values()):
            return tags
    misfits = attrs.get("model_misfits")
    if misfits is None:
        return None
    misfits = set(stored_notes(misfits))
    out = {}
    for key, ws in warnings.items():
        rows = [() for _ in ws]
        if key in misfits and ws:
            at = next((i for i, w in enumerate(ws) if warnings_blame_model((w,))), len(ws) - 1)
            rows[at] = (MISFIT, MODEL_MISFIT)
        out[key] = tuple(rows)
    return out
