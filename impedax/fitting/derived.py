"""Uncertainty propagation to any quantity computed from a circuit's parameters.

``fn(params)`` or ``fn(params, freq)`` is a JAX function of the parameters dict (names → values)
and optionally of frequency [Hz]; it returns a real scalar or array. For a posterior it is
evaluated over every draw in one vmapped call; for a least-squares fit the delta method
propagates the covariance: Cov[g] = J Σ Jᵀ with J = ∂g/∂θ from JAX at the fitted values.
Both return an xarray Dataset with ``median``, ``q05``, ``q16``, ``q84``, ``q95``; for a batch of
fits (`BatchFitResult`) the delta method runs per spectrum, with each spectrum's covariance, and
every variable gains the batch's dimensions (`derive_batch`).
"""

from __future__ import annotations

import inspect
from collections.abc import Mapping

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from ..data import checked_frequencies
from ..arguments import closest_name, count, shown, unknown_parameter
from ..errors import ParameterError
from .least_squares.branches import RELATIVE_ERROR_LIMIT, undetermined

__all__ = ["derive", "derive_fit", "derive_batch", "batch_constants", "QUANTILES", "MISSES_STRUCTURE_WARNING", "UNDETERMINED_WARNING", "band_dataset", "bind_frequency", "check_real", "needs_freq", "draws_band", "called"]

QUANTILES = {"q05": 0.05, "q16": 0.16, "median": 0.5, "q84": 0.84, "q95": 0.95}

# what a band propagated from a fit whose model misses structure the data hold says (`derive_fit`,
# `derive_batch`): a walkthrough's SYNTHETIC finger with a constant-phase skin, fitted with an RC
# skin (χ²_red 12-13 weighted by σ), derived a force of 0.594 ± 0.036 mN at 1 kHz where the truth
# was 120.5 mN, with no word
MISSES_STRUCTURE_WARNING = ("the fit's model misses structure the data hold (its warnings or its misfit hint say so): the band is that model's uncertainty, "
                            "not the quantity's, and can lie far from it; find what is missing first (impedax diagnose)")
UNDETERMINED_WARNING = (f"its standard error exceeds {RELATIVE_ERROR_LIMIT * 100:.0f} % of its value: the data do not determine it (it rests on parameters "
                        "the fit's warnings call undetermined or not separately determined); fix one of them at a value you know, or use impedax sample")


def _undetermined(value: np.ndarray, stderr: np.ndarray) -> np.ndarray:
    """Whether a derived quantity is undetermined by the rule a fit applies to its parameters
    (`branches.undetermined`: relative standard error above `RELATIVE_ERROR_LIMIT`, or none
    finite), per spectrum (the leading axis of ``value``, (spectra, *output)): for an output over
    frequency, at more than half its points, so that a quantity crossing zero at a few
    frequencies is not flagged there."""
    loose = undetermined(value, stderr)
    return loose.reshape(len(loose), -1).mean(axis=1) > 0.5


def _takes_freq(fn) -> bool:
    try:
        return len(inspect.signature(fn).parameters) >= 2
    except (TypeError, ValueError):
        return False


def needs_freq(fn) -> bool:
    """Whether ``fn`` takes a second (frequency) argument without a default."""
    return _takes_freq(fn) and not _has_default_second(fn)


def bind_frequency(fn, freq):
    """``params -> fn(params[, freq])`` as a JAX array (``freq`` bound when given)."""
    if not callable(fn):
        raise ParameterError(f"derive: fn must be a function of the parameters, fn(params) or fn(params, freq), got {shown(fn)} ({type(fn).__name__})")
    if freq is None:
        if needs_freq(fn):
            raise ParameterError("derive: the function takes a frequency argument; pass freq=...")
        arguments = ()
    else:
        arguments = (jnp.asarray(checked_frequencies(freq)),)

    def g(params):
        value = fn(params, *arguments)
        try:
            return jnp.asarray(value)
        except TypeError:  # (JAX's own words name neither fn nor what it gave: "Value 'x' with dtype <U1 is not a valid JAX array type")
            name = getattr(fn, "__name__", None) or type(fn).__name__
            raise ParameterError(f"derive: fn ({name}) must return a number or an array of numbers, got {shown(value)} ({type(value).__name__})") from None

    return g


TRACED_VALUE_CONVERSIONS = (jax.errors.ConcretizationTypeError, jax.errors.TracerArrayConversionError, jax.errors.TracerIntegerConversionError, jax.errors.TracerBoolConversionError)
"""What JAX raises when a function it traces turns a traced value into a Python or NumPy value
(``float(p["C1"])``, ``np.asarray(...)``, ``if p["R1"] > 0``): `derive` calls ``fn`` under
`jax.vmap` (draws) and `jax.jacfwd` (the delta method), where the values are tracers."""


def traced_conversion_message(fn) -> str:
    """The message for a ``fn`` that converted a traced value (`TRACED_VALUE_CONVERSIONS`),
    naming it: the JAX error came from deep inside JAX and named neither fn nor the fix."""
    name = getattr(fn, "__name__", None) or type(fn).__name__
    return (f"derive: fn ({name}) must be written with jax.numpy operations on its arguments (params[, freq]) and must not convert them "
            "to Python floats or NumPy arrays (float(), int(), np.asarray(), an if on a value): JAX traces it over the draws and for its "
            "derivatives; write jnp.where(...) for a choice")


def _has_default_second(fn) -> bool:
    params = list(inspect.signature(fn).parameters.values())
    return len(params) >= 2 and params[1].default is not inspect.Parameter.empty


def check_real(out) -> None:
    """Raise `ParameterError` when a derived quantity is complex."""
    if jnp.iscomplexobj(out):
        raise ParameterError("derive: the function returned complex values; derive a real quantity (e.g. jnp.abs(...) or jnp.angle(...))")


def _dims(shape, freq) -> tuple[tuple[str, ...], dict]:
    if freq is not None:
        f = np.atleast_1d(np.asarray(freq, float))
        if len(shape) >= 1 and shape[-1] == f.size:
            dims = tuple(f"dim_{i}" for i in range(len(shape) - 1)) + ("frequency",)
            return dims, {"frequency": ("frequency", f, {"units": "Hz"})}
    return tuple(f"dim_{i}" for i in range(len(shape))), {}


def mean_and_sd(draws: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mean and standard deviation (ddof = 1; 0 for one draw) of ``draws`` (S, ...) over the
    draws, each column scaled by its largest |draw| first: the draws of a parameter the data do
    not determine reach 1e220 (an open branch's R), whose squares lie beyond float64, and
    ``np.std`` overflowed to inf with a RuntimeWarning there."""
    draws = np.asarray(draws, float)
    with np.errstate(invalid="ignore"):  # (a column of NaN or inf is left to itself)
        scale = np.max(np.abs(draws), axis=0) if draws.shape[0] else np.ones(draws.shape[1:])
    scale = np.where(np.isfinite(scale) & (scale > 0), scale, 1.0)
    scaled = draws / scale
    sd = scaled.std(axis=0, ddof=1) * scale if draws.shape[0] > 1 else np.zeros(draws.shape[1:])
    return scaled.mean(axis=0) * scale, sd


def band_dataset(draws: np.ndarray, freq=None, *, keep_draws: bool = False, attrs=None) -> xr.Dataset:
    """Quantile bands (and optionally the draws, dim ``sample``) of ``draws`` (S, ...)."""
    dims, coords = _dims(draws.shape[1:], freq)
    qs = np.quantile(draws, list(QUANTILES.values()), axis=0)
    data = {k: (dims, q) for k, q in zip(QUANTILES, qs)}
    mean, sd = mean_and_sd(draws)
    data["mean"] = (dims, mean)
    data["sd"] = (dims, sd)
    if keep_draws:
        data["draws"] = (("sample",) + dims, draws)
    return xr.Dataset(data, coords=coords, attrs=dict(attrs or {}))


def derive_fit(result, fn, freq=None, constants=None) -> xr.Dataset:
    """Delta-method propagation of a least-squares fit to ``fn(params[, freq])`` (``freq``
    defaults to the fitted frequencies when ``fn`` takes one); ``constants`` (name → number) are
    in ``params`` beside the fitted values, held exactly (`batch_constants` for a batch's).

    Var[g] = J Σ Jᵀ (J = ∂g/∂θ_free by JAX at the fitted values, Σ = ``result.covariance``);
    the bands are the normal quantiles value ± z·stderr (q05/q95: z = 1.645, q16/q84: 0.994).
    Returns a Dataset with ``value``, ``stderr``, ``median`` (= value), ``q05``, ``q16``,
    ``q84``, ``q95`` and, for outputs of at most one dimension, ``covariance``; attrs
    ``misses_structure`` and ``warning`` when the fit's model misses structure the data hold;
    ``undetermined`` and ``warning`` when the quantity's standard error exceeds its value (the
    fit's rule for its parameters; at more than half the frequencies for an output over them).
    """
    if freq is None and needs_freq(fn):
        freq = result.frequency
    g = bind_frequency(fn, freq)
    free = list(result.free_names)
    base = {n: jnp.asarray(v) for n, v in result.values.items()}
    base.update({n: jnp.asarray(v[()]) for n, v in batch_constants(constants, list(base), result.model, None).items()})

    def of_free(x):
        params = dict(base)
        params.update({n: x[i] for i, n in enumerate(free)})
        return g(params)

    x0 = jnp.asarray([result.values[n] for n in free])
    value = called(of_free, x0, list(base), result.model, fn)
    check_real(value)
    value = np.asarray(value, float)
    jac = np.asarray(called(jax.jacfwd(of_free), x0, list(base), result.model, fn), float).reshape(value.size, len(free))
    cov = jac @ np.asarray(result.covariance, float) @ jac.T
    stderr = np.sqrt(np.clip(np.diag(cov), 0, None)).reshape(value.shape)
    from scipy import stats

    dims, coords = _dims(value.shape, freq)
    data = {"value": (dims, value), "stderr": (dims, stderr), "median": (dims, value)}
    for k, q in QUANTILES.items():
        if k != "median":
            data[k] = (dims, value + stats.norm.ppf(q) * stderr)
    if value.ndim <= 1:
        d = dims[0] if dims else "dim_0"
        data["covariance"] = ((d, d + "_2"), cov) if value.ndim == 1 else ((), cov.reshape(()))
    data["jacobian"] = (dims + ("free_param",), jac.reshape(value.shape + (len(free),)))
    coords["free_param"] = free
    attrs = {"method": "delta method: Var = J Σ Jᵀ", "model": result.model}
    # a parameter at a bound that the quantity depends on: the band is the linearisation's, which ignores the bound
    bounded = [n for j, n in enumerate(free) if n in getattr(result, "at_bound", ()) and np.any(jac[:, j] != 0)]
    if bounded:
        attrs["at_bound"] = ", ".join(bounded)
        attrs["note"] = (f"depends on {', '.join(bounded)} at {'its' if len(bounded) == 1 else 'their'} bound: the band is the linearisation's, "
                         "which ignores the bound (impedax sample gives an interval that respects it)")
    if getattr(result, "misses_structure", False):
        attrs["misses_structure"] = 1
        attrs["warning"] = MISSES_STRUCTURE_WARNING
    if _undetermined(value[None], stderr[None])[0]:
        attrs["undetermined"] = 1
        attrs["warning"] = "; ".join(filter(None, [attrs.get("warning"), UNDETERMINED_WARNING]))
    return xr.Dataset(data, coords=coords, attrs=attrs)


def derive_batch(batch, fn, freq=None, constants=None) -> xr.Dataset:
    """`derive_fit` of every spectrum of a batch of fits (`BatchFitResult`, `SharedFitResult`) in
    one vmapped call: Var[g] = J Σ Jᵀ per spectrum, J = ∂g/∂θ_free at its fitted values (its fixed
    ones too, which may differ between spectra) and Σ its ``covariance`` (a batch saved before
    2026-12-01 has none: each spectrum's is its `BatchFitResult.fit_of`'s). Returns the Dataset of
    `derive_fit` (``value``, ``stderr``, ``median``, ``q05``, ``q16``, ``q84``, ``q95``,
    ``covariance`` for outputs of at most one dimension, ``jacobian``) with the batch's dimensions
    (and their labels) first in every variable, and ``at_bound`` (bool over those dimensions):
    whether the quantity depends on a parameter at its bound in that spectrum, where the band is
    the linearisation's (attrs ``at_bound`` name the parameters, ``note`` says so), and
    ``misses_structure`` (bool, `BatchFitResult.misses_structure`; attrs ``warning`` counts them)
    and ``undetermined`` (bool: the quantity's standard error exceeds its value, as `derive_fit`).
    ``constants`` (name → a number, or a DataArray of one value per spectrum over some of the
    batch's dimensions: a drive voltage per ``voltage`` label) are in ``params`` beside each
    spectrum's fitted values, held exactly (`batch_constants`)."""
    ds = batch.dataset
    dims = tuple(batch.dims)
    if freq is None and needs_freq(fn):
        freq = np.asarray(ds["frequency"].values, float)
    g = bind_frequency(fn, freq)
    names = [str(p) for p in ds["param"].values]
    fixed = np.asarray(ds["fixed"].values, bool).reshape(-1)
    free = [n for n, f in zip(names, fixed) if not f]
    shape = tuple(ds.sizes[d] for d in dims)
    values = ds["value"].transpose(*dims, "param").values.reshape(-1, len(names)).astype(float)
    covariance = _spectrum_covariances(batch, free).reshape(-1, len(free), len(free))
    free_index = np.array([names.index(n) for n in free], int)
    held = batch_constants(constants, names, batch.model, batch)
    known = names + list(held)

    def of_free(x, base, extra):
        params = {n: base[i] for i, n in enumerate(names)}
        params.update({n: x[j] for j, n in enumerate(free)})
        params.update(extra)
        return g(params)

    x0 = jnp.asarray(values[:, free_index])
    base = jnp.asarray(values)
    extra = {n: jnp.asarray(v.reshape(-1)) for n, v in held.items()}
    value = called(lambda x: jax.vmap(of_free)(x, base, extra), x0, known, batch.model, fn)
    check_real(value)
    value = np.asarray(value, float)
    out_shape = value.shape[1:]
    m = int(np.prod(out_shape))
    jac = np.asarray(called(lambda x: jax.vmap(jax.jacfwd(of_free))(x, base, extra), x0, known, batch.model, fn), float).reshape(len(values), m, len(free))
    cov = jac @ covariance @ np.swapaxes(jac, -1, -2)
    stderr = np.sqrt(np.clip(np.einsum("bii->bi", cov), 0, None)).reshape(value.shape)
    from scipy import stats

    own_dims, coords = _dims(out_shape, freq)
    full = dims + own_dims
    lead = lambda a: a.reshape(shape + a.shape[1:])  # noqa: E731
    data = {"value": (full, lead(value)), "stderr": (full, lead(stderr)), "median": (full, lead(value))}
    for k, q in QUANTILES.items():
        if k != "median":
            data[k] = (full, lead(value + stats.norm.ppf(q) * stderr))
    if len(out_shape) <= 1:
        d = own_dims[0] if own_dims else "dim_0"
        data["covariance"] = (dims + (d, d + "_2"), lead(cov)) if len(out_shape) == 1 else (dims, lead(cov.reshape(-1)))
    data["jacobian"] = (full + ("free_param",), lead(jac.reshape(len(values), *out_shape, len(free))))
    coords["free_param"] = free
    coords.update({d: ds[d].values for d in dims if d in ds.coords})
    # a parameter at a bound that the quantity depends on, spectrum by spectrum (as `derive_fit`)
    at_bound = ds["at_bound"].transpose(*dims, "param").values.reshape(len(values), len(names))[:, free_index].astype(bool)
    depends = np.any(jac != 0, axis=1)
    bounded_here = at_bound & depends
    data["at_bound"] = (dims, lead(bounded_here.any(axis=1)))
    attrs = {"method": "delta method per spectrum: Var = J Σ Jᵀ", "model": batch.model}
    if held:
        data.update({f"constant_{n}": (dims, v) for n, v in held.items()})
    bounded = [n for j, n in enumerate(free) if bounded_here[:, j].any()]
    if bounded:
        attrs["at_bound"] = ", ".join(bounded)
        attrs["note"] = (f"in {int(bounded_here.any(axis=1).sum())} of {len(values)} spectra (at_bound) it depends on {', '.join(bounded)} at "
                         f"{'its' if len(bounded) == 1 else 'their'} bound: the band there is the linearisation's, which ignores the bound "
                         "(impedax sample gives an interval that respects it)")
    misses = getattr(batch, "misses_structure", None)
    if misses is not None:
        flags = np.asarray(misses.transpose(*dims).values, bool)
        data["misses_structure"] = (dims, flags)
        if flags.any():
            attrs["warning"] = f"in {int(flags.sum())} of {flags.size} spectra (misses_structure): {MISSES_STRUCTURE_WARNING}"
    loose = _undetermined(value, stderr)
    data["undetermined"] = (dims, lead(loose))
    if loose.any():
        attrs["warning"] = "; ".join(filter(None, [attrs.get("warning"), f"in {int(loose.sum())} of {loose.size} spectra (undetermined): {UNDETERMINED_WARNING}"]))
    return xr.Dataset(data, coords=coords, attrs=attrs)


def batch_constants(constants, names: list[str], model: str, batch) -> dict[str, np.ndarray]:
    """The ``constants=`` of `derive`: name → value held in ``params`` beside the fitted ones,
    each as an array over the batch's dimensions (shape () for a single fit, ``batch`` None). A
    number is the same for every spectrum; a DataArray over some of the batch's dimensions gives
    one value per spectrum, matched by label (`grid.aligned_values`, as ``fixed=``). A
    name of a parameter, a value that is not a finite real number, or a DataArray for a single
    fit is a `ParameterError` naming it."""
    from .grid import aligned_values

    if constants is None:
        return {}
    if not isinstance(constants, Mapping):
        raise ParameterError(f"derive: constants must be a mapping of name → value (constants={{'V0': 200.0}}), got {type(constants).__name__}")
    dims = () if batch is None else tuple(batch.dims)
    shape = () if batch is None else tuple(batch.dataset.sizes[d] for d in dims)
    out = {}
    for name, value in constants.items():
        label = f"constants[{name!r}]"
        if name in names:
            raise ParameterError(f"derive: {label} has the name of a parameter of {model}, which fn already gets fitted: give the constant another name")
        if isinstance(value, xr.DataArray) and value.ndim:
            if batch is None:
                raise ParameterError(f"derive: {label} is a DataArray over {', '.join(map(str, value.dims))}; a single fit has one spectrum: give a number")
            value = aligned_values(value, batch.dataset, dims, label, str(batch.dataset.attrs.get("source", "")))
        if isinstance(value, xr.DataArray):
            value = value.expand_dims({d: batch.dataset.sizes[d] for d in dims if d not in value.dims}).transpose(*dims).values
        try:
            array = np.broadcast_to(np.asarray(value, dtype=float), shape)
        except (TypeError, ValueError):
            raise ParameterError(f"derive: {label} must be a real number or a DataArray of one number per spectrum over the batch's dimensions ({', '.join(dims) or 'none'}), got {shown(value)}") from None
        if not np.all(np.isfinite(array)):
            raise ParameterError(f"derive: {label} must be finite, got {shown(value)}")
        out[name] = np.array(array)
    return out


def _spectrum_covariances(batch, free: list[str]) -> np.ndarray:
    """Each spectrum's covariance of the ``free`` parameters, (*batch dims, K, K): the batch's
    own (``dataset["covariance"]``), or for a batch saved before it was stored each spectrum's
    `BatchFitResult.fit_of` (a refit from its values)."""
    ds = batch.dataset
    dims = tuple(batch.dims)
    k = len(free)
    if "covariance" in ds:
        return ds["covariance"].sel(free_param=free, free_param_2=free).transpose(*dims, "free_param", "free_param_2").values.astype(float)
    out = np.empty((*(ds.sizes[d] for d in dims), k, k))
    for index in np.ndindex(*(ds.sizes[d] for d in dims)):
        one = batch.fit_of(**{d: ds[d].values[i] if d in ds.coords else i for d, i in zip(dims, index)})
        order = [list(one.free_names).index(n) for n in free]
        out[index] = np.asarray(one.covariance, float)[np.ix_(order, order)]
    return out


def called(g, x, known, model, fn):
    """``g(x)``, a call of the user's ``fn`` under JAX (vmap over draws, jacfwd), with what fn
    got wrong there as one `ParameterError`: a parameter name the model has not (a KeyError from
    inside JAX's trace), named with the closest known name; a traced value turned into a Python
    or NumPy one (`TRACED_VALUE_CONVERSIONS`), naming fn and how to write it
    (`traced_conversion_message`). Raised here, outside JAX, so that JAX adds nothing to them."""

    try:
        return g(x)
    except KeyError as exc:
        raise unknown_parameter("derive: fn asked for", exc.args[0] if exc.args else "?", known, model) from None
    except TRACED_VALUE_CONVERSIONS:
        raise ParameterError(traced_conversion_message(fn)) from None


def draw_indices(total: int, max_draws: int | None) -> np.ndarray:
    """Indices of at most ``max_draws`` evenly spaced draws out of ``total`` (all for None);
    ``max_draws`` below 1 or not an integer is a `ParameterError`."""
    limit = count(1, optional=True)(max_draws, "max_draws")
    return np.linspace(0, total - 1, total if limit is None else min(limit, total)).astype(int)


def draws_band(fn, freq, params: dict, model: str, *, draws: bool, max_draws: int | None, method: str) -> xr.Dataset:
    """``fn(params[, freq])`` over posterior draws ``params`` (name → array over draws) in one
    vmapped call, at most ``max_draws`` evenly spaced ones, summarised by `band_dataset`
    (``method`` in its attrs): what `Posterior.derive` and `SharedPosterior.derive` return."""
    g = bind_frequency(fn, freq)
    pick = draw_indices(len(next(iter(params.values()))), max_draws)
    params = {k: v[pick] for k, v in params.items()}
    out = called(jax.jit(jax.vmap(g)), {k: jnp.asarray(v) for k, v in params.items()}, list(params), model, fn)
    check_real(out)
    out = np.asarray(out, float)
    attrs = {"method": method, "model": model}
    bad = int(np.count_nonzero(~np.all(np.isfinite(out.reshape(out.shape[0], -1)), axis=1)))
    if bad:  # (2026-12-03: fn undefined at some draws gave NaN quantiles without a word)
        attrs["non_finite_draws"] = bad
        attrs["warning"] = (f"fn gives a value that is not finite (NaN or ±inf) at {bad} of {out.shape[0]} draws, so the quantiles are NaN where it does: "
                            "fn is undefined there (a log or square root of a negative number, a division by zero); check it over the parameters' ranges")
    return band_dataset(out, freq, keep_draws=draws, attrs=attrs)


def _keywords_of(method) -> tuple[str, ...]:
    """The keyword-only arguments of a bound ``derive`` method (a posterior's: draws, max_draws)."""
    try:
        return tuple(n for n, p in inspect.signature(method).parameters.items() if p.kind is p.KEYWORD_ONLY)
    except (TypeError, ValueError):
        return ()


def _refuse_keywords(kwargs, taken: tuple[str, ...], path: str) -> None:
    """A `ParameterError` for the first keyword of ``kwargs`` not in ``taken``: ``derive`` of
    ``path`` would otherwise ignore it (a least-squares fit took ``draws=True`` silently)."""
    unknown = [k for k in kwargs if k not in taken]
    if not unknown:
        return
    close = closest_name(str(unknown[0]), taken) if taken else None
    hint = f"; did you mean {close}?" if close else ""
    takes = f"the keyword{'s' if len(taken) > 1 else ''} {', '.join(taken)} besides freq"
    also = "" if "draws" in taken else "; draws and max_draws are a posterior's"
    raise ParameterError(f"derive: {'keywords' if len(unknown) > 1 else 'keyword'} {', '.join(shown(k) for k in unknown)} {'are' if len(unknown) > 1 else 'is'} not taken for {path}: it takes {takes}{also}{hint}")


def derive(result, fn, freq=None, **kwargs) -> xr.Dataset:
    """Propagate a fit or a posterior to ``fn(params[, freq])``: `Posterior.derive` for a
    posterior (all draws, one vmapped call), `derive_fit` (delta method) for a `FitResult`,
    `derive_batch` (the delta method per spectrum, over the batch's dimensions) for a
    `BatchFitResult` or `SharedFitResult`. Keywords beyond ``freq`` are the posterior's
    (``draws``, ``max_draws``) or the fits' (``constants``: values held in ``params``, one per
    spectrum of a batch, `batch_constants`); one the chosen path does not take is a `ParameterError` naming
    it and the keywords that path takes (a fit's delta method has no draws to keep or thin)."""
    if hasattr(result, "draws") and hasattr(result, "derive"):
        _refuse_keywords(kwargs, _keywords_of(result.derive), f"a {type(result).__name__} (posterior draws)")
        return result.derive(fn, freq, **kwargs)
    if hasattr(result, "covariance") and hasattr(result, "free_names"):
        _refuse_keywords(kwargs, ("constants",), "a least-squares fit (delta method)")
        return derive_fit(result, fn, freq, **kwargs)
    if callable(getattr(result, "spectrum_keys", None)) and isinstance(getattr(result, "dataset", None), xr.Dataset):
        _refuse_keywords(kwargs, ("constants",), "a batch of fits (delta method per spectrum)")
        return derive_batch(result, fn, freq, **kwargs)
    raise ParameterError(f"derive: expected a FitResult, a BatchFitResult or a Posterior, got {type(result).__name__}")
