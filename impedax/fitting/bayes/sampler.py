"""Bayesian fitting with emcee: `sample` returns a frozen `Posterior`.

`sample` runs in named steps: check the settings, load the spectrum, lay out the sampled
parameters, choose their priors, start from a least-squares fit, place the walkers, run emcee
(with a progress line; ``steps="auto"`` until the chain is long enough, `AUTO_MAX_STEPS` at
most), then compute MAP, Laplace evidence and WAIC (`evidence`) and wrap it all in a
`Posterior`. The log-probability emcee drives (one jitted, vmapped call for all
walkers, ``vectorize=True``) and the noise models are defined in `logprob`; priors in `priors`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, NamedTuple, Sequence

import jax.numpy as jnp
import numpy as np
import xarray as xr

from ...arguments import MAX_CHAIN_VALUES, MAX_WALKERS, checked_arguments, choice, closest_name, count, frequency, instance_of, number_text, parameter_bounds, parameter_values, progress_line_flag, seed as seed_rule, unknown_parameter
from ...circuits import Circuit, DEFAULT_REGISTRY, Registry, parse
from ...errors import DataError, FitError, ParameterError
from ..kk import zero_impedance_text
from ..least_squares import FitResult, fit
from ..least_squares.result import data_difference, fit_blames_model, fit_uneven_noise
from ..parameters import checked_bounds, outside_bounds_message
from ..problem import SIGMA_SOURCES, Spectrum, check_argument_order, fit_problem, open_spectrum
from .chain import (
    AUTO_CHECK_STEPS, AUTO_MAX_STEPS, AUTO_STEPS, AUTO_TAU_CHANGE, auto_step_cap, ball_scales, length_settings, run_emcee, start_walkers, steps_rule,
    support_in_sampled_space, undetermined_span,
)
from .diagnostics import CHAIN_TAU_MULTIPLE, integrated_autocorr
from .evidence import START_BEYOND_SIGMA, START_UNEVEN_NOISE, laplace_evidence, waic, waic_doubts
from .logprob import NOISE_MODELS, LogProbArgs, LogProbFunctions, LogProbStructure, NoiseModel, log_prob_functions, start_weighting, walkers_log_prob
from .posterior import Posterior
from ...progress import quiet_beneath
from .progress import announce
from .priors import DEFAULT_SPAN_DECADES, SIGMA_REL_PRIOR, Prior, check_prior_inside, coerce_priors, data_scale_range, default_prior
from .reparam import Reparametrization
from .shared_posterior import MAX_JOINT_PARAMETERS, SharedPosterior, sample_shared

__all__ = [
    "sample", "Posterior", "SharedPosterior", "MAX_JOINT_PARAMETERS", "NOISE_MODELS", "SIGMA_REL_PRIOR", "DEFAULT_SPAN_DECADES", "SampledParameters",
    "AUTO_MAX_STEPS", "AUTO_CHECK_STEPS", "AUTO_TAU_CHANGE", "auto_step_cap",
]


# --- the steps' typed hand-overs ---------------------------------------------------------------


class _Observations(NamedTuple):
    """The spectrum a run samples against, with the noise scale of its noise model."""

    freq: np.ndarray  # Hz
    z: np.ndarray  # Ω
    sigma: np.ndarray | None  # the data's known σ [Ω], if any
    scale: np.ndarray  # |Z| (proportional) or σ (known noise)
    data: xr.Dataset
    source: str | None
    spectrum: Spectrum  # (as opened: its band names --fmin/--fmax in a too-few-points message)


@dataclass(frozen=True)
class SampledParameters:
    """The sampled parameters in order (free circuit parameters, then the physical ones of a
    reparametrization, then ``sigma_rel``) with their units and open bounds (``inclusive``:
    the upper bound belongs to the domain)."""

    names: tuple[str, ...]
    units: tuple[str, ...]
    lower: tuple[float, ...]
    upper: tuple[float, ...]
    inclusive: tuple[bool, ...]

    @property
    def log_scale(self) -> tuple[bool, ...]:
        """Sampled as ln x: every parameter with a non-negative domain."""
        return tuple(bool(lo >= 0) for lo in self.lower)


# --- step 1: settings and data ---------------------------------------------------------------


def _sigma_origin(data: xr.Dataset) -> str:
    """What the data's σ is, in `diagnosis.noise.sigma_origin`'s words (a remainder's standard
    error of trial means, a stated sigma, or a sigma column), for a run with known noise."""
    from ..diagnosis.noise import sigma_origin  # (here: the diagnosis package is not imported by every sample)

    return sigma_origin(data.attrs)


def _check_settings(noise, steps, burn, thin) -> tuple[NoiseModel, int | None]:
    """The noise model and burn (default steps // 4; None for ``steps="auto"`` without a
    burn: a quarter of the steps it runs) after checking the run's settings."""
    if noise not in NOISE_MODELS:
        raise ParameterError(f"unknown noise model {noise!r}; choose one of {', '.join(NOISE_MODELS)}")
    for what, value, least in (("steps", steps, 1), ("thin", thin, 1)):
        if value == AUTO_STEPS and what == "steps":
            continue
        if not isinstance(value, (int, np.integer)) or value < least:
            raise ParameterError(f"{what} must be an integer of at least {least} (got {value!r})")
    if steps == AUTO_STEPS:
        if burn is not None and (not isinstance(burn, (int, np.integer)) or burn < 0):
            raise ParameterError(f"burn must be a non-negative integer (got {burn!r})")
        return NoiseModel(noise), burn
    burn = steps // 4 if burn is None else burn
    if not isinstance(burn, (int, np.integer)) or burn < 0 or burn >= steps:
        raise ParameterError(f"burn must be an integer from 0 to steps − 1 = {steps - 1} (got {burn!r})")
    if (steps - burn) // thin < 1:
        raise ParameterError("no draws left after burn and thin; use more steps")
    return NoiseModel(noise), burn


def _observations(data, noise: NoiseModel, fmin, fmax) -> _Observations:
    spectrum = open_spectrum(data, fmin=fmin, fmax=fmax, single="sample")
    ds, source = spectrum.data, spectrum.source
    freq = np.asarray(ds["frequency"].values, float)
    z = np.asarray(ds["Z"].values, complex)
    sigma = np.asarray(ds["sigma"].values, float) if "sigma" in ds else None
    if noise is NoiseModel.SIGMA and sigma is None:
        raise DataError(f"noise='sigma' needs a 'sigma' variable in the data (e.g. the SEM of repeated trials): {SIGMA_SOURCES}; use noise='proportional' otherwise", path=source)
    scale = np.abs(z) if noise is NoiseModel.PROPORTIONAL else sigma
    if noise is NoiseModel.PROPORTIONAL and np.any(scale == 0):  # (where, as the KK test and the DRT say it)
        raise DataError(f"{zero_impedance_text(freq, z)}; noise='proportional' (σ = sigma_rel·|Z|) needs |Z| > 0: drop those points", path=source)
    if np.any(~np.isfinite(scale) | (scale <= 0)):
        raise DataError(f"noise model {noise.value!r}: zero or non-finite noise scale (|Z| or sigma is 0 somewhere)", path=source)
    return _Observations(freq, z, sigma, scale, ds, source, spectrum)


# --- step 2: which parameters are sampled ------------------------------------------------------


def _fixed_values(circuit: Circuit, specs, fixed, init: FitResult | None, freq, z) -> dict[str, float]:
    """The user's fixed values, plus those fixed in ``init`` (checked against circuit and data:
    a fit of another spectrum would centre the priors and place the walkers on other data)."""
    fixed = {k: float(v) for k, v in (fixed or {}).items()}
    for n in fixed:
        if n not in specs:
            raise ParameterError(f"fixed: unknown parameter {n!r} for {circuit} (parameters: {', '.join(specs)})")
    if init is not None:
        if not isinstance(init, FitResult):
            raise ParameterError("init must be a FitResult from impedax.fit for this circuit and data")
        if str(init.circuit) != str(circuit) or init.n_points != freq.size or not np.allclose(init.frequency, freq):
            raise ParameterError(f"init was fitted with {init.model} to {init.n_points} points; sample was given {circuit} and {freq.size} points")
        difference = data_difference(freq, z, init.frequency, init.z_data)
        if difference is not None:
            raise ParameterError(f"init was fitted to different data: {difference} (fmin/fmax or another spectrum?); pass init=fit(circuit, data) of the spectrum sampled")
        fixed.update({n: init.values[n] for n, f in init.fixed.items() if f and n not in fixed})
    return fixed


def _check_reparametrization(rp: Reparametrization | None, circuit: Circuit, specs, fixed) -> None:
    if rp is None:
        return
    for n in rp.replaces:
        if n not in specs:
            raise ParameterError(f"reparametrization replaces {n!r}, which is not a parameter of {circuit} (parameters: {', '.join(specs)})")
        if n in fixed:
            raise ParameterError(f"{n} is both fixed and replaced by the reparametrization")
    for n in rp.names:
        if n in specs or n == "sigma_rel":
            raise ParameterError(f"reparametrization parameter {n!r} clashes with a circuit parameter name")


def _narrowed_bounds(circuit: Circuit, specs, bounds, init: FitResult | None, fixed, rp: Reparametrization | None) -> tuple[dict[str, tuple[float, float]], list[str]]:
    """The bounds the user narrowed for sampled circuit parameters, the support of their priors
    and the space sampled: those of ``init``'s fit (`FitResult.bounds`), then ``bounds`` (checked
    as `fit` checks them: `checked_bounds`; a fixed value must lie strictly inside), which win.
    A parameter the reparametrization replaces is not sampled: ``bounds`` for it are refused,
    init's dropped with a note. Returns (name → (lower, upper), notes)."""
    narrowed = {n: b for n, b in (init.bounds if init is not None else {}).items() if n not in fixed}
    replaced = set(rp.replaces) if rp is not None else set()
    for name, (lo, hi) in (bounds or {}).items():
        if name not in specs:
            raise unknown_parameter("bounds", name, tuple(specs), circuit)
        lo, hi = checked_bounds(name, lo, hi, specs[name])
        if name in replaced:
            raise ParameterError(f"bounds for {name}: it is replaced by the reparametrization, whose parameters ({', '.join(rp.names)}) are sampled within their own bounds")
        if name in fixed:
            if not lo < fixed[name] < hi:
                raise ParameterError(outside_bounds_message("fixed", name, fixed[name], lo, hi, False))
            continue
        narrowed[name] = (lo, hi)
    notes = [f"init's bounds for {n} {number_text(narrowed[n][0])}–{number_text(narrowed[n][1])} are not applied: the reparametrization replaces {n}" for n in narrowed if n in replaced]
    return {n: b for n, b in narrowed.items() if n not in replaced}, notes


# how far (a fraction of the bounds' span) an init value may lie past a bound and still count
# as on it: a fit stopped at a bound reaches it through exp/log transforms, a few ulps either side
BOUND_SLACK = 1e-9


def _within_bounds(start: list[float], space: SampledParameters, narrowed: Mapping[str, tuple[float, float]]) -> list[float]:
    """The start values with each parameter of the user's bounds ``narrowed`` clipped onto
    them (a fit's value rounded a few ulps past its bound, `BOUND_SLACK`)."""
    return [min(max(x, narrowed[n][0]), narrowed[n][1]) if n in narrowed else x for n, x in zip(space.names, start)]


def _check_init_inside(init: FitResult, narrowed: Mapping[str, tuple[float, float]]) -> None:
    """A `ParameterError` when ``init``'s value of a parameter lies outside the bounds it is
    sampled within (``bounds=`` narrower than init's fit): its walkers would start outside the
    prior. A value on a bound (a fit stopped there; rounding past it by `BOUND_SLACK` of the
    span) is a start, moved onto the bound (`_within_bounds`)."""
    for n, (lo, hi) in narrowed.items():
        value, slack = init.values[n], BOUND_SLACK * ((hi - lo) if math.isfinite(hi - lo) else max(abs(lo), 1.0))
        if not lo - slack <= value <= hi + slack:
            raise ParameterError(f"init: {n}={number_text(value)} is outside its bounds ({number_text(lo)}, {number_text(hi)}) given to sample; start from a fit with these bounds: init=fit(circuit, data, bounds=...)")


def _sampled_parameters(specs, fixed, rp: Reparametrization | None, noise: NoiseModel, narrowed: Mapping[str, tuple[float, float]]) -> SampledParameters:
    """The sampled parameters; a circuit parameter within the user's bounds ``narrowed`` where
    given (upper end excluded, as `fit` excludes it, but where it is the element's own upper end
    and the element includes it: ``--bound CPE1.alpha=0.4:1`` keeps a prior up to α = 1, as
    the element's bounds alone do), else its element's."""
    replaced = set(rp.replaces) if rp is not None else set()
    rows = [(n, s.unit, *narrowed[n], narrowed[n][1] == s.upper and s.upper_inclusive) if n in narrowed else (n, s.unit, s.lower, s.upper, s.upper_inclusive) for n, s in specs.items() if n not in fixed and n not in replaced]
    if rp is not None:
        rows += [(n, u, lo, hi, False) for n, u, lo, hi in zip(rp.names, rp.units, rp.lower, rp.upper)]
    if noise is NoiseModel.PROPORTIONAL:
        rows.append(("sigma_rel", "1", 0.0, math.inf, False))
    if not rows:
        raise FitError("every parameter is fixed; nothing to sample")
    names, units, lower, upper, inclusive = (tuple(column) for column in zip(*rows))
    return SampledParameters(names, units, lower, upper, inclusive)


def _check_user_priors(priors: Mapping[str, Prior], space: SampledParameters, fixed, rp: Reparametrization | None) -> None:
    replaced = set(rp.replaces) if rp is not None else set()
    for n in priors:
        if n not in space.names:
            if n in replaced:
                raise ParameterError(f"prior for {n}: it is replaced by the reparametrization; put priors on {', '.join(rp.names)}")
            if n in fixed:
                raise ParameterError(f"prior for {n}: the parameter is fixed")
            close = closest_name(n, space.names)
            hint = f"; did you mean {close}?" if close else ""
            raise ParameterError(f"prior for unknown parameter {n!r}{hint} (sampled parameters: {', '.join(space.names)})")
    for i, n in enumerate(space.names):
        if n in priors:
            check_prior_inside(n, priors[n], space.lower[i], space.upper[i], space.inclusive[i])


def _walker_count(walkers, n_params: int) -> int:
    walkers = max(64, 4 * n_params) if walkers is None else walkers
    if not isinstance(walkers, (int, np.integer)) or walkers < 2 * n_params or walkers % 2:
        raise ParameterError(f"walkers must be an even number of at least 2 × {n_params} parameters = {2 * n_params} (got {walkers!r})")
    return walkers


# --- step 3: start and priors ----------------------------------------------------------------


def _init_weighting_note(init: FitResult, noise: NoiseModel) -> str | None:
    """A note when the user's start fit ``init`` minimised another χ² than the sampler's
    likelihood: its optimum places the walkers and its covariance spreads them and widens the
    priors of undetermined parameters (`_choose_priors`), so a start of another weighting costs
    burn-in and may widen the wrong priors; ``None`` when it matches (`start_weighting`)."""
    matching = start_weighting(noise)
    if init.weighting == matching:
        return None
    return (
        f"init was fitted with weighting {init.weighting!r}, but the {noise.value} noise model's likelihood is the χ² of weighting {matching!r}: "
        f"the walkers start around that fit and its standard errors set their spread; for a start that matches, pass init=fit(..., weighting={matching!r})"
    )


def _least_squares_start(init: FitResult, space: SampledParameters, specs, rp: Reparametrization | None, noise: NoiseModel) -> list[float]:
    """Natural start values of the sampled parameters from the least-squares fit."""
    start = [init.values[n] for n in space.names if n in specs]
    if rp is not None:
        rp_start = rp.start({n: init.values[n] for n in rp.replaces})
        for n, lo, hi in zip(rp.names, rp.lower, rp.upper):
            start.append(float(np.clip(rp_start[n], lo * (1 + 1e-9) if lo > 0 else lo + 1e-12, hi * (1 - 1e-9))))
    if noise is NoiseModel.PROPORTIONAL:
        start.append(max(init.rms_rel / math.sqrt(2.0), 1e-4))
    return start


class _Priors(NamedTuple):
    """The priors a run chose, and where its walkers start."""

    chosen: dict[str, Prior]  # by sampled-parameter name
    support: list[tuple[float, float]]  # each prior's support within the bounds
    start: list[float]  # natural start values inside the supports
    spread: list[tuple[float, float] | None]  # natural range to spread a parameter's walkers over, None: a small ball
    notes: list[str]


def _choose_priors(priors: Mapping[str, Prior], space: SampledParameters, start: list[float], init: FitResult, obs: _Observations, own_bounds: Mapping[str, tuple[float, float]] | None = None) -> _Priors:
    """Each sampled parameter's prior (the user's, or `default_prior`: widened to the data's
    impedance scale where the least-squares fit ``init`` leaves the parameter `undetermined`),
    its support within the bounds, and the start moved inside the support where the fit lies
    outside it (with a note when the prior is the user's). The walkers of an undetermined
    parameter with a default prior start spread over the fit's approximate 95 % interval
    (value ± 2·stderr) within the prior, log-uniformly, not in a ball around a value the data
    do not fix (`undetermined_span`). ``own_bounds``: the element's own bounds of the parameters
    the user narrowed, whose default prior is the one without that narrowing cut to it
    (`default_prior`'s ``own``)."""
    own_bounds = own_bounds or {}
    chosen: dict[str, Prior] = {}
    spread: list[tuple[float, float] | None] = []
    z_abs = np.abs(obs.z)
    init_stderr = init.linearised_stderr  # (at a bound: the linearisation's scale)
    for i, n in enumerate(space.names):
        wide = None
        if n in priors:
            chosen[n] = priors[n]
        elif n == "sigma_rel":
            chosen[n] = SIGMA_REL_PRIOR
        else:
            stderr = float(init_stderr[n]) if n in init.stderr and not init.fixed.get(n, False) else None
            at_bound = n in init.at_bound
            chosen[n] = default_prior(space.lower[i], space.upper[i], start[i], stderr=stderr, at_bound=at_bound, scale=data_scale_range(space.units[i], obs.freq, z_abs), own=own_bounds.get(n))
            wide = undetermined_span(chosen[n], space.lower[i], space.upper[i], start[i], stderr, at_bound)
        spread.append(wide)
    support = [chosen[n].support(space.lower[i], space.upper[i]) for i, n in enumerate(space.names)]
    start, notes = list(start), []
    for i, n in enumerate(space.names):
        lo, hi = support[i]
        if not lo < start[i] <= hi:
            if n not in priors:  # a default prior above a fit stopped at its bound
                start[i] = min(lo * (1 + 1e-6) if lo > 0 else lo + 1e-12, hi)
                continue
            inside = math.sqrt(lo * hi) if lo > 0 and math.isfinite(hi) else (0.5 * (lo + hi) if math.isfinite(hi) else lo * 2 + 1)
            notes.append(f"the least-squares value of {n} ({start[i]:.4g}) is outside its prior {chosen[n]}; walkers start inside the prior")
            start[i] = inside
    return _Priors(chosen, support, start, spread, notes)


CHI2_RED_MISFIT = 3.0
"""With the data's σ (noise='sigma'), a start fit's χ²_red above this is a misfit beyond the
noise: χ²_red of a model that fits has mean 1 and sd √(2/(2N − k)), 0.14 for 50 points."""


def _start_misfit(init: FitResult, noise: NoiseModel) -> bool | str:
    """Whether the least-squares start misses the data: True where its misfit note blames the
    model (its tag `model_misfit`, `fit_blames_model`: set where the note is made, not the note's words); `evidence.START_UNEVEN_NOISE` where, under one relative noise
    level, its residuals are uneven (its tag `uneven_noise`, `fit_uneven_noise`: not its
    `UNEVEN_NOISE_NOTE`'s words); `evidence.START_BEYOND_SIGMA` where only its χ²_red, with the
    data's σ, exceeds `CHI2_RED_MISFIT` (an understated σ or a missing effect); else False."""
    if fit_blames_model(init):
        return True
    if noise is NoiseModel.PROPORTIONAL and fit_uneven_noise(init):
        return START_UNEVEN_NOISE
    beyond = noise is NoiseModel.SIGMA and init.weighting == "sigma" and math.isfinite(init.chi2_red) and init.chi2_red > CHI2_RED_MISFIT
    return START_BEYOND_SIGMA if beyond else False


def _converged(chain_y: np.ndarray) -> bool:
    """`Posterior.chain_converged` of the kept chain ``chain_y`` (walker, draw, param): at least
    `CHAIN_TAU_MULTIPLE` autocorrelation times long for every parameter, τ known for all."""
    tau = integrated_autocorr(chain_y)
    return bool(np.all(np.isfinite(tau)) and chain_y.shape[1] >= CHAIN_TAU_MULTIPLE * max(float(np.max(tau)), 1.0))


def _log_prob_setup(circuit, registry, specs, fixed, rp, obs: _Observations, space: SampledParameters, chosen, support):
    """The arrays and the static structure of the run's log-probability."""
    circuit_names = tuple(specs)
    args = LogProbArgs(
        freq=jnp.asarray(obs.freq),
        z=jnp.asarray(obs.z),
        scale=jnp.asarray(obs.scale),
        fixed=jnp.asarray([fixed.get(n, 1.0) for n in circuit_names]),
        code=jnp.asarray([chosen[n].code for n in space.names], jnp.int32),
        a=jnp.asarray([chosen[n].a for n in space.names]),
        b=jnp.asarray([chosen[n].b for n in space.names]),
        lo=jnp.asarray([s[0] for s in support]),
        hi=jnp.asarray([s[1] for s in support]),
        log_norm=jnp.asarray([chosen[n].log_normaliser(space.lower[i], space.upper[i]) for i, n in enumerate(space.names)]),
    )
    index = {n: j for j, n in enumerate(space.names)}
    structure = LogProbStructure(
        circuit=circuit,
        registry=registry,
        circuit_names=circuit_names,
        direct_index=tuple(index.get(n, -1) for n in circuit_names),
        reparametrization=rp,
        reparam_index=tuple(index[n] for n in rp.names) if rp is not None else (),
        sigma_index=index.get("sigma_rel", -1),
        log_scale=space.log_scale,
    )
    return args, structure


# --- step 4: the walkers' start ----------------------------------------------------------------


def _initial_walkers(
    start, space: SampledParameters, init: FitResult, *, walkers: int, seed: int, n_points: int,
    lo_y, hi_y, args: LogProbArgs, functions: LogProbFunctions, circuit: Circuit, wide: Sequence[tuple[float, float] | None] = (),
) -> np.ndarray:
    """The walkers' start (walkers, P) in the sampled space (`start_walkers`): a small ball around
    the least-squares start, its radius from the fit's linearised standard errors (``sigma_rel``'s
    from the number of points), each parameter with a range in ``wide`` spread over it, the other
    free circuit parameters following it along the fit's covariance."""
    init_stderr = init.linearised_stderr
    stderr = [start[i] / math.sqrt(2 * n_points) if n == "sigma_rel" else (init_stderr.get(n, math.nan) if n in init.stderr else math.nan) for i, n in enumerate(space.names)]
    free = list(init.free_names)
    cov = np.asarray(init.covariance, float)
    covariance = np.full((len(space.names),) * 2, np.nan)
    if cov.shape == (len(free), len(free)):
        rows = [free.index(n) if n in free else -1 for n in space.names]
        known = np.asarray(rows) >= 0
        covariance[np.ix_(known, known)] = cov[np.ix_(np.asarray(rows)[known], np.asarray(rows)[known])]
    return start_walkers(
        start, space.log_scale, ball_scales(start, stderr, space.log_scale), walkers=walkers, seed=seed, lo_y=lo_y, hi_y=hi_y,
        log_prob_one=lambda y: functions.single(jnp.asarray(y), args), log_prob_all=lambda y: functions.batched(jnp.asarray(y), args),
        where=f"the least-squares fit of {circuit}", wide=wide, covariance=covariance,
    )


# --- step 5: the emcee run ---------------------------------------------------------------------


# --- the entry point ---------------------------------------------------------------------------


def _chain_fits_in_memory(arguments) -> None:
    """steps × walkers within `MAX_CHAIN_VALUES` (emcee keeps every step of every walker);
    ``steps="auto"`` keeps within it by its cap (`auto_step_cap`)."""
    steps, walkers = arguments.get("steps", AUTO_STEPS), arguments.get("walkers")
    if walkers is not None and steps != AUTO_STEPS and steps * walkers > MAX_CHAIN_VALUES:
        raise ParameterError(f"steps × walkers = {steps * walkers:,} is above the limit {MAX_CHAIN_VALUES:,} (the chain is kept in memory); use fewer steps or walkers")


@quiet_beneath
@checked_arguments(
    _chain_fits_in_memory,
    priors=instance_of(Mapping, optional=True, what="a mapping name → Prior or 'kind:a,b'"), noise=choice(NOISE_MODELS, label="noise model", if_number="a number is a noise level, which diagnose and refine take; the proportional model samples it as sigma_rel"),
    walkers=count(2, MAX_WALKERS, optional=True), steps=steps_rule,
    burn=count(0, optional=True), thin=count(1), seed=seed_rule, fixed=parameter_values(), bounds=parameter_bounds,
    reparametrization=instance_of(Reparametrization, optional=True), fmin=frequency, fmax=frequency, progress=progress_line_flag,
    registry=instance_of(Registry, optional=True),
)
def sample(
    circuit: Circuit | str,
    data: xr.Dataset | str,
    *,
    priors: Mapping[str, Prior | str] | None = None,
    noise: str = "proportional",
    walkers: int | None = None,
    steps: int | str = AUTO_STEPS,
    burn: int | None = None,
    thin: int = 1,
    seed: int = 0,
    init: FitResult | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    reparametrization: Reparametrization | None = None,
    fmin: float | None = None,
    fmax: float | None = None,
    progress=None,
    registry: Registry | None = None,
    shared: Sequence[str] | str | None = None,
    over: Sequence[str] | str | None = None,
) -> Posterior | SharedPosterior:
    """Sample the posterior of ``circuit``'s parameters given ``data`` with emcee.

    emcee's affine-invariant ensemble sampler (``vectorize=True``) drives a jitted, vmapped
    log-probability: log-prior + Gaussian log-likelihood of the real-stacked residual
    [Re, Im](Z_model − Z_data) under the noise model ``noise`` (`NOISE_MODELS`). Parameters with a
    positive domain are sampled as ln x (prior Jacobian included). ``priors`` maps parameter
    names to `Prior` (or ``"kind:a,b"`` text); the default is log-uniform within the bounds,
    LSQ value ×/÷ 10³ for parameters unbounded above (reaching over the data's impedance scale
    where the fit leaves a parameter undetermined: at its bound or within 2 standard errors of
    it; `default_prior`), uniform for exponents (α in (0, 1]), and log-uniform on [1e-5, 1] for
    ``sigma_rel``. ``reparametrization`` samples physical
    quantities behind some circuit parameters (`gap_thickness_reparametrization`).
    ``bounds`` (name → (lower, upper), checked as `fit`'s) narrow circuit parameters: the
    support of their priors (a default prior is the default without them, cut to them:
    `default_prior`'s ``own``) and the space sampled;
    an ``init`` fit's own bounds (`FitResult.bounds`) apply as its fixed parameters do, ``bounds``
    taking precedence, and the start fit run without ``init`` is fitted within them.
    ``walkers`` (default max(64, 4·P)) start in a small ball around the least-squares fit
    ``init`` (run by `fit` when not given) and take ``steps`` steps each: a number, or
    ``"auto"`` (the default), which runs until the kept chain is `CHAIN_TAU_MULTIPLE` (50)
    autocorrelation times long for every parameter and τ has settled, `AUTO_MAX_STEPS` at most
    (then the chain-length warning says the cap was reached; docs/bayesian.md, "Chain length").
    ``burn`` (default a quarter of the steps run) steps are discarded and every ``thin``-th kept;
    ``settings`` records the steps that ran. Returns a `Posterior` with diagnostics, Laplace log
    evidence and WAIC. ``progress``: lines for the start fit, the compilation and the
    sampling, on stderr (None, the default, or True), none (False), or each handed to a function
    of one line of text (``progress=print``), as `fit` takes it. ``registry`` None: the default one.
    ``shared`` with ``over`` (as `fit`) samples the joint posterior of a global fit instead:
    shared parameters once, the others per spectrum, started from the global least-squares fit
    (`shared_posterior`; at most `MAX_JOINT_PARAMETERS` sampled parameters; the same chain-length
    rule), and returns a `SharedPosterior`.
    """
    check_argument_order("sample", circuit, data)
    progress = progress_line_flag(progress, "progress")  # (the default None is not checked by the decorator: lines on stderr)
    registry = DEFAULT_REGISTRY if registry is None else registry
    noise, burn = _check_settings(noise, steps, burn, thin)
    circuit = parse(circuit, registry)
    if shared is not None or over is not None:
        if init is not None or reparametrization is not None or bounds is not None:
            raise ParameterError("sample with shared parameters starts from its own global fit and takes no init, bounds or reparametrization")
        return sample_shared(
            circuit, data, shared=shared, over=over, priors=priors, noise=noise, walkers=walkers, steps=steps, burn=burn, thin=thin, seed=seed,
            fixed=fixed, fmin=fmin, fmax=fmax, progress=progress, registry=registry,
        )
    obs = _observations(data, noise, fmin, fmax)
    specs = circuit.parameter_specs(registry)
    fixed = _fixed_values(circuit, specs, fixed, init, obs.freq, obs.z)
    rp = reparametrization
    _check_reparametrization(rp, circuit, specs, fixed)
    narrowed, bound_notes = _narrowed_bounds(circuit, specs, bounds, init, fixed, rp)
    if init is not None:
        _check_init_inside(init, narrowed)
    space = _sampled_parameters(specs, fixed, rp, noise, narrowed)
    priors = coerce_priors(priors)
    _check_user_priors(priors, space, fixed, rp)
    walkers = _walker_count(walkers, len(space.names))
    if steps == AUTO_STEPS and burn is not None and burn >= auto_step_cap(walkers, len(space.names)):
        raise ParameterError(f"burn must be below the {auto_step_cap(walkers, len(space.names))} steps steps='auto' runs at most (got {burn})")

    if init is None:
        # (too few points for the free parameters said before the progress line, not after it)
        fit_problem(circuit, obs.spectrum, init=None, fixed=fixed or None, bounds=narrowed or None, registry=registry)
        announce("sample: fitting the least-squares start …", progress)
        init = fit(circuit, obs.data, fixed=fixed or None, bounds=narrowed or None, weighting=start_weighting(noise), registry=registry)
    weighting_note = _init_weighting_note(init, noise)
    fitted = _within_bounds(_least_squares_start(init, space, specs, rp, noise), space, narrowed)
    chosen_priors = _choose_priors(priors, space, fitted, init, obs, {n: (specs[n].lower, specs[n].upper) for n in narrowed})
    chosen, support, notes = chosen_priors.chosen, chosen_priors.support, chosen_priors.notes
    notes = ([weighting_note] if weighting_note else []) + bound_notes + notes
    excluded = [n for i, n in enumerate(space.names) if n in priors and not support[i][0] < fitted[i] <= support[i][1]]
    announce(f"sample: compiling the log-probability (once per circuit and data size) and placing {walkers} walkers …", progress)
    args, structure = _log_prob_setup(circuit, registry, specs, fixed, rp, obs, space, chosen, support)
    functions = log_prob_functions(structure)
    lo_y, hi_y = support_in_sampled_space(support, space.log_scale)
    p0 = _initial_walkers(
        chosen_priors.start, space, init, walkers=walkers, seed=seed, n_points=obs.freq.size, lo_y=lo_y, hi_y=hi_y, args=args, functions=functions, circuit=circuit,
        wide=chosen_priors.spread,
    )

    chain = run_emcee(p0, walkers_log_prob(functions.batched, args), steps=steps, burn=burn, thin=thin, seed=seed, progress=progress)
    length = length_settings(chain, walkers)

    converged = _converged(chain.chain_y)
    start_y = np.where(np.asarray(space.log_scale), np.log(np.maximum(np.asarray(fitted, float), np.finfo(float).tiny)), np.asarray(fitted, float))
    information = waic(chain.chain_y, args, functions, excluded, names=space.names, start_y=start_y, converged=converged, model_misfit=_start_misfit(init, noise))
    # (the reasons the posterior's `waic_unreliable_reason` gives, from the same numbers: the evidence's remedy names WAIC only where it is sound)
    reasons = waic_doubts(information.waic, information.p_waic, len(space.names), chain.chain_y.shape[1])
    evidence = laplace_evidence(chain.chain_y, chain.log_prob, args, functions, lo_y, hi_y, names=space.names, converged=converged, waic_reasons=reasons)
    notes += [note for note in (evidence.note, information.note) if note]
    log_scale = np.asarray(space.log_scale)
    map_x = np.where(log_scale, np.exp(evidence.map_y), evidence.map_y)
    return Posterior(
        circuit=circuit,
        names=space.names,
        units=space.units,
        log_scale=space.log_scale,
        draws=np.where(log_scale, np.exp(chain.chain_y), chain.chain_y),
        log_prob=chain.log_prob,
        acceptance=chain.acceptance,
        priors=chosen,
        noise=noise,
        fit=init,
        fixed=dict(fixed),
        frequency=obs.freq,
        z_data=obs.z,
        sigma=obs.sigma,
        log_evidence=float(evidence.log_evidence),
        waic=float(information.waic),
        p_waic=float(information.p_waic),
        map_values={n: float(v) for n, v in zip(space.names, map_x)},
        notes=tuple(notes),
        settings={"walkers": int(walkers), "steps": int(chain.steps), "burn": int(chain.burn), "thin": int(thin), "seed": int(seed), "elapsed_s": float(chain.elapsed_s), **length,
                  **({"sigma_origin": _sigma_origin(obs.data)} if noise is NoiseModel.SIGMA else {})},
        reparametrization=rp,
        registry=registry,
        user_bounds=dict(narrowed),
        stragglers=chain.stragglers,
        log_evidence_unreliable_reason=evidence.reason,
        model_comparison_notes=tuple(note for note in (evidence.note, information.note) if note),
    )
