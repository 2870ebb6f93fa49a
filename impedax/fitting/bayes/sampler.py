"""Bayesian fitting with emcee: `sample` returns a frozen `Posterior`.

The log-probability is built from parts and evaluated for all walkers in one jitted, vmapped
call (emcee's ``vectorize=True``):

    ln p(y | data) = ln π(y) + Σ_k ln N(Re r_k; 0, σ_k²) + ln N(Im r_k; 0, σ_k²) + const,
    r_k = Z_model(f_k) − Z_data,k.

Sampled space: every parameter with a positive domain (resistances, capacitances, CPE Q and α,
σ, τ, the physical quantities of a reparametrization, ``sigma_rel``) is sampled as y = ln x;
others as x itself. Priors are defined on the natural parameter x, so the prior density in
the sampled space carries the Jacobian |dx/dy| = x: ln π_y(y) = ln π_x(e^y) + y.

Noise models (`NOISE_MODELS`): ``proportional`` — Re and Im of point k each carry Gaussian noise
σ_k = sigma_rel·|Z_data,k|, with ``sigma_rel`` a sampled parameter (log-uniform on [1e-5, 1]
by default); ``sigma`` — a known per-point σ_k from the data's ``sigma`` variable (e.g. the
standard error of the mean of repeated trials), nothing extra sampled.
"""

from __future__ import annotations

import difflib
import functools
import math
import sys
import time
from dataclasses import dataclass, field
from typing import Callable, Mapping

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from ...circuits import Circuit, DEFAULT_REGISTRY, Registry, compile_circuit, parse
from ...errors import DataError, FitError, ParameterError
from ..derived import QUANTILES, _call, _check_real, band_dataset, needs_freq
from ..least_squares.single import FitResult, fit
from ..problem import open_spectrum
from .priors import Prior, parse_prior, prior_log_density
from .reparam import Reparametrization, rebuild

__all__ = ["sample", "Posterior", "NOISE_MODELS", "SIGMA_REL_PRIOR", "DEFAULT_SPAN_DECADES"]

NOISE_MODELS = {
    "proportional": "Re and Im of each point carry Gaussian noise σ_k = sigma_rel·|Z_data,k|; sigma_rel is sampled",
    "sigma": "Re and Im of each point carry Gaussian noise with the known σ_k of the data's 'sigma' variable (e.g. SEM of repeated trials)",
}
SIGMA_REL_PRIOR = Prior("loguniform", 1e-5, 1.0)
DEFAULT_SPAN_DECADES = 3.0  # default log-uniform prior for unbounded parameters: LSQ value ×/÷ 10³
CHAIN_TAU_MULTIPLE = 50
ACCEPTANCE_RANGE = (0.15, 0.6)
CORRELATION_WARNING = 0.9
WAIC_MAX_DRAWS = 4000


# --- the log-probability ------------------------------------------------------------------


@dataclass(frozen=True)
class _Structure:
    """Everything static about a log-probability (hashable: one compilation per structure)."""

    circuit: Circuit
    registry: Registry
    circuit_names: tuple[str, ...]
    direct_index: tuple[int, ...]  # per circuit name: index in the sampled vector, −1 if fixed/replaced
    reparametrization: Reparametrization | None
    reparam_index: tuple[int, ...]
    sigma_index: int  # −1 when the noise scale is known
    log_scale: tuple[bool, ...]


def _natural(y, st: _Structure):
    return jnp.where(jnp.asarray(st.log_scale), jnp.exp(y), y)


def _circuit_params(x, args, st: _Structure) -> dict:
    params = {}
    for i, name in enumerate(st.circuit_names):
        j = st.direct_index[i]
        params[name] = x[j] if j >= 0 else args["fixed"][i]
    if st.reparametrization is not None:
        rp = st.reparametrization
        params.update(rp.circuit_values({n: x[j] for n, j in zip(rp.names, st.reparam_index)}))
    return params


def _all_params(x, args, st: _Structure, names) -> dict:
    params = _circuit_params(x, args, st)
    params.update({n: x[j] for j, n in enumerate(names)})
    return params


def _pointwise_loglik(x, args, st: _Structure):
    """ln-likelihood of each frequency point (Re and Im together), shape (N,)."""
    z = compile_circuit(st.circuit, st.registry)(_circuit_params(x, args, st), args["freq"])
    r = z - args["z"]
    sigma = args["scale"] * (x[st.sigma_index] if st.sigma_index >= 0 else 1.0)
    ll = -0.5 * (r.real**2 + r.imag**2) / sigma**2 - 2.0 * jnp.log(sigma) - jnp.log(2.0 * jnp.pi)
    return jnp.where(jnp.isfinite(ll), ll, -jnp.inf)


def _log_prior(y, args, st: _Structure):
    x = _natural(y, st)
    lp = prior_log_density(x, args["code"], args["a"], args["b"], args["lo"], args["hi"], args["log_norm"])
    return jnp.sum(lp + jnp.where(jnp.asarray(st.log_scale), y, 0.0))


def _log_prob(y, args, st: _Structure):
    lp = _log_prior(y, args, st)
    ll = jnp.sum(_pointwise_loglik(_natural(y, st), args, st))
    ok = jnp.isfinite(lp) & jnp.isfinite(ll)
    return jnp.where(ok, lp + jnp.where(ok, ll, 0.0), -jnp.inf)


@functools.lru_cache(maxsize=64)
def _functions(st: _Structure):
    """Jitted (batched log-prob, single log-prob, its value-and-grad, Hessian, pointwise ll)."""
    single = functools.partial(_log_prob, st=st)
    batched = jax.jit(jax.vmap(single, in_axes=(0, None)))
    value_and_grad = jax.jit(jax.value_and_grad(single))
    hessian = jax.jit(jax.hessian(single))
    pointwise = jax.jit(jax.vmap(lambda y, args: _pointwise_loglik(_natural(y, st), args, st), in_axes=(0, None)))
    return batched, jax.jit(single), value_and_grad, hessian, pointwise


# --- setting up a run ------------------------------------------------------------------------


def _coerce_priors(priors) -> dict[str, Prior]:
    out = {}
    for name, prior in (priors or {}).items():
        if isinstance(prior, str):
            _, prior = parse_prior(f"{name}={prior}")
        elif isinstance(prior, tuple) and len(prior) == 3:
            prior = Prior(*prior)
        elif not isinstance(prior, Prior):
            raise ParameterError(f"prior for {name}: expected a Prior, a (kind, a, b) tuple or 'kind:a,b' text, got {prior!r}")
        out[name] = prior
    return out


def _default_prior(lower, upper, unit, start) -> Prior:
    if math.isfinite(upper) and lower > 0:
        return Prior("loguniform", lower, upper)
    if math.isfinite(upper) and math.isfinite(lower):
        return Prior("uniform", lower, upper)
    span = 10.0**DEFAULT_SPAN_DECADES
    if lower >= 0 and start > 0:
        return Prior("loguniform", max(start / span, lower * (1 + 1e-12)) if lower > 0 else start / span, start * span)
    centre = start if math.isfinite(start) else 0.0
    half = span * max(abs(centre), 1.0)
    return Prior("uniform", max(centre - half, lower), min(centre + half, upper))


def _check_prior_inside(name, prior: Prior, lower, upper, inclusive):
    if prior.kind in ("uniform", "loguniform"):
        too_high = prior.b > upper or (prior.b == upper and not inclusive and math.isfinite(upper))
        if prior.a < lower or too_high:
            right = "]" if inclusive else ")"
            raise ParameterError(f"prior for {name}: {prior} reaches outside the parameter's bounds ({lower:g}, {upper:g}{right})")


class _Progress:
    """A one-line progress indication on stderr, shown only once a run has taken a second."""

    def __init__(self, total: int, enabled: bool):
        self.total, self.enabled = total, enabled
        self.t0 = time.perf_counter()
        self.last = 0.0
        self.shown = False

    def update(self, done: int) -> None:
        if not self.enabled:
            return
        now = time.perf_counter() - self.t0
        if now < 1.0 or (now - self.last < 0.5 and done < self.total):
            return
        self.last = now
        rate = done / now if now > 0 else 0.0
        eta = (self.total - done) / rate if rate > 0 else math.inf
        sys.stderr.write(f"\rimpedax sample: step {done}/{self.total} ({100 * done / self.total:.0f}%), {now:.0f} s, ~{eta:.0f} s left ")
        sys.stderr.flush()
        self.shown = True

    def close(self) -> None:
        if self.shown:
            sys.stderr.write("\n")
            sys.stderr.flush()


def sample(
    circuit: Circuit | str,
    data: xr.Dataset | str,
    *,
    priors: Mapping[str, Prior | str] | None = None,
    noise: str = "proportional",
    walkers: int | None = None,
    steps: int = 2000,
    burn: int | None = None,
    thin: int = 1,
    seed: int = 0,
    init: FitResult | None = None,
    fixed: Mapping[str, float] | None = None,
    reparametrization: Reparametrization | None = None,
    fmin: float | None = None,
    fmax: float | None = None,
    progress: bool = True,
    registry: Registry = DEFAULT_REGISTRY,
) -> "Posterior":
    """Sample the posterior of ``circuit``'s parameters given ``data`` with emcee.

    emcee's affine-invariant ensemble sampler (``vectorize=True``) drives a jitted, vmapped
    log-probability: log-prior + Gaussian log-likelihood of the real-stacked residual
    [Re, Im](Z_model − Z_data) under the noise model ``noise`` (`NOISE_MODELS`). Parameters with a
    positive domain are sampled as ln x (prior Jacobian included). ``priors`` maps parameter
    names to `Prior` (or ``"kind:a,b"`` text); the default is log-uniform within the bounds,
    LSQ value ×/÷ 10³ for parameters unbounded above, uniform for exponents (α in (0, 1]), and
    log-uniform on [1e-5, 1] for ``sigma_rel``. ``reparametrization`` samples physical
    quantities behind some circuit parameters (`gap_thickness_reparametrization`).
    ``walkers`` (default max(64, 4·P)) start in a small ball around the least-squares fit
    ``init`` (run by `fit` when not given); ``burn`` (default steps // 4) steps are discarded and
    every ``thin``-th kept. Returns a `Posterior` with diagnostics, Laplace log evidence and WAIC.
    """
    import emcee

    if noise not in NOISE_MODELS:
        raise ParameterError(f"unknown noise model {noise!r}; choose one of {', '.join(NOISE_MODELS)}")
    for what, value, least in (("steps", steps, 1), ("thin", thin, 1)):
        if not isinstance(value, (int, np.integer)) or value < least:
            raise ParameterError(f"{what} must be an integer of at least {least} (got {value!r})")
    burn = steps // 4 if burn is None else burn
    if not isinstance(burn, (int, np.integer)) or burn < 0 or burn >= steps:
        raise ParameterError(f"burn must be an integer from 0 to steps − 1 = {steps - 1} (got {burn!r})")
    if (steps - burn) // thin < 1:
        raise ParameterError("no draws left after burn and thin; use more steps")
    circuit = parse(circuit, registry)
    spectrum = open_spectrum(data, fmin=fmin, fmax=fmax, single="sample")
    ds, source = spectrum.data, spectrum.source
    freq = np.asarray(ds["frequency"].values, float)
    z = np.asarray(ds["Z"].values, complex)
    sigma = np.asarray(ds["sigma"].values, float) if "sigma" in ds else None
    if noise == "sigma" and sigma is None:
        raise DataError("noise='sigma' needs a 'sigma' variable in the data (e.g. the SEM of repeated trials); use noise='proportional' otherwise", path=source)
    scale = np.abs(z) if noise == "proportional" else sigma
    if np.any(~np.isfinite(scale) | (scale <= 0)):
        raise DataError(f"noise model {noise!r}: zero or non-finite noise scale (|Z| or sigma is 0 somewhere)", path=source)

    specs = circuit.parameter_specs(registry)
    circuit_names = tuple(specs)
    fixed = {k: float(v) for k, v in (fixed or {}).items()}
    for n in fixed:
        if n not in specs:
            raise ParameterError(f"fixed: unknown parameter {n!r} for {circuit} (parameters: {', '.join(circuit_names)})")
    if init is not None:
        if not isinstance(init, FitResult):
            raise ParameterError("init must be a FitResult from impedax.fit for this circuit and data")
        if str(init.circuit) != str(circuit) or init.n_points != freq.size or not np.allclose(init.frequency, freq):
            raise ParameterError(f"init was fitted with {init.model} to {init.n_points} points; sample was given {circuit} and {freq.size} points")
        fixed.update({n: init.values[n] for n, f in init.fixed.items() if f and n not in fixed})

    rp = reparametrization
    replaced = set(rp.replaces) if rp is not None else set()
    if rp is not None:
        for n in rp.replaces:
            if n not in specs:
                raise ParameterError(f"reparametrization replaces {n!r}, which is not a parameter of {circuit} (parameters: {', '.join(circuit_names)})")
            if n in fixed:
                raise ParameterError(f"{n} is both fixed and replaced by the reparametrization")
        for n in rp.names:
            if n in specs or n == "sigma_rel":
                raise ParameterError(f"reparametrization parameter {n!r} clashes with a circuit parameter name")

    # the sampled parameters: free circuit parameters, then physical ones, then sigma_rel
    names, units, lower, upper, inclusive = [], [], [], [], []
    for n in circuit_names:
        if n in fixed or n in replaced:
            continue
        s = specs[n]
        names.append(n), units.append(s.unit), lower.append(s.lower), upper.append(s.upper), inclusive.append(s.upper_inclusive)
    if rp is not None:
        for n, u, lo, hi in zip(rp.names, rp.units, rp.lower, rp.upper):
            names.append(n), units.append(u), lower.append(lo), upper.append(hi), inclusive.append(False)
    if noise == "proportional":
        names.append("sigma_rel"), units.append("1"), lower.append(0.0), upper.append(math.inf), inclusive.append(False)
    if not names:
        raise FitError("every parameter is fixed; nothing to sample")

    priors = _coerce_priors(priors)
    for n in priors:
        if n not in names:
            if n in replaced:
                raise ParameterError(f"prior for {n}: it is replaced by the reparametrization; put priors on {', '.join(rp.names)}")
            if n in fixed:
                raise ParameterError(f"prior for {n}: the parameter is fixed")
            close = difflib.get_close_matches(n, names, n=1)
            hint = f"; did you mean {close[0]}?" if close else ""
            raise ParameterError(f"prior for unknown parameter {n!r}{hint} (sampled parameters: {', '.join(names)})")
    for i, n in enumerate(names):
        if n in priors:
            _check_prior_inside(n, priors[n], lower[i], upper[i], inclusive[i])
    n_params = len(names)
    walkers = max(64, 4 * n_params) if walkers is None else walkers
    if not isinstance(walkers, (int, np.integer)) or walkers < 2 * n_params or walkers % 2:
        raise ParameterError(f"walkers must be an even number of at least 2 × {n_params} parameters = {2 * n_params} (got {walkers!r})")

    # the least-squares start
    if init is None:
        init = fit(circuit, ds, fixed=fixed or None, weighting="modulus" if noise == "proportional" else "sigma", registry=registry)
    start = [init.values[n] for n in names if n in specs]
    if rp is not None:
        rp_start = rp.start({n: init.values[n] for n in rp.replaces})
        for n, lo, hi in zip(rp.names, rp.lower, rp.upper):
            start.append(float(np.clip(rp_start[n], lo * (1 + 1e-9) if lo > 0 else lo + 1e-12, hi * (1 - 1e-9))))
    if noise == "proportional":
        start.append(max(init.rms_rel / math.sqrt(2.0), 1e-4))

    chosen: dict[str, Prior] = {}
    notes: list[str] = []
    for i, n in enumerate(names):
        if n in priors:
            chosen[n] = priors[n]
        elif n == "sigma_rel":
            chosen[n] = SIGMA_REL_PRIOR
        else:
            chosen[n] = _default_prior(lower[i], upper[i], units[i], start[i])
    log_scale = tuple(bool(lo >= 0) for lo in lower)
    support = [chosen[n].support(lower[i], upper[i]) for i, n in enumerate(names)]
    for i, n in enumerate(names):
        lo, hi = support[i]
        if not lo < start[i] <= hi:
            inside = math.sqrt(lo * hi) if lo > 0 and math.isfinite(hi) else (0.5 * (lo + hi) if math.isfinite(hi) else lo * 2 + 1)
            notes.append(f"the least-squares value of {n} ({start[i]:.4g}) is outside its prior {chosen[n]}; walkers start inside the prior")
            start[i] = inside
    args = {
        "freq": jnp.asarray(freq),
        "z": jnp.asarray(z),
        "scale": jnp.asarray(scale),
        "fixed": jnp.asarray([fixed.get(n, 1.0) for n in circuit_names]),
        "code": jnp.asarray([chosen[n].code for n in names], jnp.int32),
        "a": jnp.asarray([chosen[n].a for n in names]),
        "b": jnp.asarray([chosen[n].b for n in names]),
        "lo": jnp.asarray([s[0] for s in support]),
        "hi": jnp.asarray([s[1] for s in support]),
        "log_norm": jnp.asarray([chosen[n].log_normaliser(lower[i], upper[i]) for i, n in enumerate(names)]),
    }
    index = {n: j for j, n in enumerate(names)}
    st = _Structure(
        circuit=circuit,
        registry=registry,
        circuit_names=circuit_names,
        direct_index=tuple(index.get(n, -1) for n in circuit_names),
        reparametrization=rp,
        reparam_index=tuple(index[n] for n in rp.names) if rp is not None else (),
        sigma_index=index.get("sigma_rel", -1),
        log_scale=log_scale,
    )
    batched, single, value_and_grad, hessian, pointwise = _functions(st)

    # a small ball around the least-squares fit, in the sampled space
    y0 = np.array([math.log(v) if ls else v for v, ls in zip(start, log_scale)])
    spread = []
    for i, n in enumerate(names):
        se = init.stderr.get(n, math.nan) if n in init.stderr else math.nan
        rel = se / abs(start[i]) if log_scale[i] else se
        if n == "sigma_rel":
            rel = 1.0 / math.sqrt(2 * freq.size)
        spread.append(0.1 * float(np.clip(rel if math.isfinite(rel) else 1e-2, 1e-6, 0.1)))
    rng = np.random.default_rng(seed)
    lo_y = np.array([math.log(s[0]) if ls and s[0] > 0 else (-np.inf if ls else s[0]) for s, ls in zip(support, log_scale)])
    hi_y = np.array([math.log(s[1]) if ls else s[1] for s, ls in zip(support, log_scale)])
    p0 = y0 + np.asarray(spread) * rng.normal(size=(walkers, n_params))
    p0 = np.clip(p0, np.where(np.isfinite(lo_y), lo_y + 1e-9, -np.inf), hi_y)
    if not np.isfinite(float(single(jnp.asarray(y0), args))):
        raise FitError(f"the log-probability is −∞ at the least-squares fit of {circuit} (model not finite there, or outside the priors); check the priors and the data")
    lp0 = np.asarray(batched(jnp.asarray(p0), args))
    for _ in range(30):
        bad = ~np.isfinite(lp0)
        if not bad.any():
            break
        p0[bad] = y0 + 0.5 * (p0[bad] - y0)
        lp0 = np.asarray(batched(jnp.asarray(p0), args))
    else:
        p0[~np.isfinite(lp0)] = y0

    def log_prob_fn(coords):
        return np.asarray(batched(jnp.asarray(coords), args))

    sampler = emcee.EnsembleSampler(walkers, n_params, log_prob_fn, vectorize=True)
    sampler.random_state = np.random.RandomState(seed).get_state()
    bar = _Progress(steps, progress)
    t0 = time.perf_counter()
    try:
        for i, _ in enumerate(sampler.sample(p0, iterations=steps, skip_initial_state_check=True)):
            bar.update(i + 1)
    finally:
        bar.close()
    elapsed = time.perf_counter() - t0
    chain_y = np.transpose(sampler.get_chain(discard=burn, thin=thin), (1, 0, 2))  # (W, D, P)
    log_prob = np.transpose(sampler.get_log_prob(discard=burn, thin=thin))
    draws = np.where(np.asarray(log_scale), np.exp(chain_y), chain_y)
    acceptance = np.asarray(sampler.acceptance_fraction, float)

    # MAP (from the best draw) and the Laplace approximation of the evidence
    log_evidence, map_y, evidence_note = _laplace(chain_y, log_prob, args, value_and_grad, hessian, lo_y, hi_y)
    if evidence_note:
        notes.append(evidence_note)
    waic, p_waic, waic_note = _waic(chain_y, args, pointwise)
    if waic_note:
        notes.append(waic_note)
    map_x = np.where(np.asarray(log_scale), np.exp(map_y), map_y)

    return Posterior(
        circuit=circuit,
        names=tuple(names),
        units=tuple(units),
        log_scale=log_scale,
        draws=draws,
        log_prob=log_prob,
        acceptance=acceptance,
        priors=chosen,
        noise=noise,
        fit=init,
        fixed=dict(fixed),
        frequency=freq,
        z_data=z,
        sigma=sigma,
        log_evidence=float(log_evidence),
        waic=float(waic),
        p_waic=float(p_waic),
        map_values={n: float(v) for n, v in zip(names, map_x)},
        notes=tuple(notes),
        settings={"walkers": int(walkers), "steps": int(steps), "burn": int(burn), "thin": int(thin), "seed": int(seed), "elapsed_s": float(elapsed)},
        reparametrization=rp,
        registry=registry,
    )


def _laplace(chain_y, log_prob, args, value_and_grad, hessian, lo_y, hi_y):
    """ln Z ≈ ln p(y*) + ln π(y*) + (d/2) ln 2π − ½ ln det(−H) at the MAP y* (sampled space)."""
    from scipy.optimize import minimize

    flat_lp = log_prob.reshape(-1)
    best = np.unravel_index(int(np.argmax(flat_lp)), log_prob.shape)
    y_best = chain_y[best]

    def objective(y):
        v, g = value_and_grad(jnp.asarray(y), args)
        v, g = float(v), np.asarray(g, float)
        if not np.isfinite(v) or not np.all(np.isfinite(g)):
            return 1e300, np.zeros_like(g)
        return -v, -g

    bounds = [(None if not np.isfinite(lo) else lo, None if not np.isfinite(hi) else hi) for lo, hi in zip(lo_y, hi_y)]
    try:
        sol = minimize(objective, y_best, jac=True, method="L-BFGS-B", bounds=bounds, options={"maxiter": 500})
        y_map = sol.x if -sol.fun >= flat_lp.max() else y_best
    except (ValueError, FloatingPointError):
        y_map = y_best
    lp_map = float(-objective(y_map)[0])
    h = np.asarray(hessian(jnp.asarray(y_map), args), float)
    d = len(y_map)
    if not np.all(np.isfinite(h)):
        return math.nan, y_map, "Laplace log evidence undefined: the Hessian at the MAP is not finite"
    eig = np.linalg.eigvalsh(-0.5 * (h + h.T))
    if eig.min() <= 0:
        return math.nan, y_map, "Laplace log evidence undefined: the log-posterior is not peaked at the MAP (a flat or unidentified direction)"
    note = ""
    if eig.min() / eig.max() < 1e-12:
        note = "Laplace log evidence is unreliable: the posterior is nearly flat along some direction (unidentified parameters)"
    return lp_map + 0.5 * d * math.log(2 * math.pi) - 0.5 * float(np.sum(np.log(eig))), y_map, note


def _waic(chain_y, args, pointwise):
    """WAIC = −2 (lppd − p_waic) over the frequency points (Watanabe 2010; Gelman et al. 2014)."""
    from scipy.special import logsumexp

    flat = chain_y.reshape(-1, chain_y.shape[-1])
    if flat.shape[0] > WAIC_MAX_DRAWS:
        flat = flat[np.linspace(0, flat.shape[0] - 1, WAIC_MAX_DRAWS).astype(int)]
    ll = np.asarray(pointwise(jnp.asarray(flat), args), float)  # (S, N)
    if not np.all(np.isfinite(ll)):
        ll = ll[np.all(np.isfinite(ll), axis=1)]
        if ll.shape[0] < 2:
            return math.nan, math.nan, "WAIC undefined: non-finite likelihood at the draws"
    lppd = logsumexp(ll, axis=0) - math.log(ll.shape[0])
    p_i = ll.var(axis=0, ddof=1)
    return float(-2.0 * np.sum(lppd - p_i)), float(np.sum(p_i)), ""


# --- diagnostics ------------------------------------------------------------------------------


def _autocorr(chain_y: np.ndarray) -> np.ndarray:
    """Integrated autocorrelation time per parameter in stored draws (emcee, tol=0)."""
    import emcee

    if chain_y.shape[1] < 2:
        return np.full(chain_y.shape[-1], np.nan)
    tau = emcee.autocorr.integrated_time(np.transpose(chain_y, (1, 0, 2)), c=5, tol=0, quiet=True)
    return np.asarray(tau, float)


def _hdi(x: np.ndarray, mass: float = 0.9) -> tuple[float, float]:
    """Shortest interval holding ``mass`` of the draws."""
    x = np.sort(x)
    n = x.size
    k = max(int(math.ceil(mass * n)), 1)
    if k >= n:
        return float(x[0]), float(x[-1])
    widths = x[k - 1:] - x[: n - k + 1]
    i = int(np.argmin(widths))
    return float(x[i]), float(x[i + k - 1])


# --- the result -------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Posterior:
    """Draws from the posterior of a circuit's parameters given one spectrum. Immutable.

    ``draws`` (walker, draw, param) are natural values of the sampled parameters ``names``
    (free circuit parameters, the physical ones of a reparametrization, ``sigma_rel``);
    ``log_prob`` their log-posterior in the sampled space; ``fit`` the least-squares start.
    Diagnostics: ``acceptance`` per walker, ``autocorr`` (integrated autocorrelation time in
    sampler steps), ``ess`` (effective sample size), ``warnings``. Model comparison:
    ``log_evidence`` (Laplace, at the MAP) and ``waic`` (deviance scale: lower is better).
    """

    circuit: Circuit
    names: tuple[str, ...]
    units: tuple[str, ...]
    log_scale: tuple[bool, ...]
    draws: np.ndarray
    log_prob: np.ndarray
    acceptance: np.ndarray
    priors: dict[str, Prior]
    noise: str
    fit: FitResult
    fixed: dict[str, float]
    frequency: np.ndarray
    z_data: np.ndarray
    sigma: np.ndarray | None
    log_evidence: float
    waic: float
    p_waic: float
    map_values: dict[str, float]
    notes: tuple[str, ...] = ()
    settings: dict = field(default_factory=dict)
    reparametrization: Reparametrization | None = None
    registry: Registry = field(default=DEFAULT_REGISTRY, repr=False)

    # -- basic views ----------------------------------------------------------------------
    @property
    def model(self) -> str:
        return str(self.circuit)

    @property
    def n_walkers(self) -> int:
        return int(self.draws.shape[0])

    @property
    def n_draws(self) -> int:
        return int(self.draws.shape[1])

    @property
    def samples(self) -> dict[str, np.ndarray]:
        """Flat draws (after burn and thin) by sampled-parameter name."""
        flat = self.draws.reshape(-1, len(self.names))
        return {n: flat[:, i] for i, n in enumerate(self.names)}

    @property
    def mean_acceptance(self) -> float:
        return float(np.mean(self.acceptance))

    @functools.cached_property
    def _sampled_space(self) -> np.ndarray:
        return np.where(np.asarray(self.log_scale), np.log(np.where(np.asarray(self.log_scale), self.draws, 1.0)), self.draws)

    @functools.cached_property
    def autocorr(self) -> dict[str, float]:
        """Integrated autocorrelation time per parameter [sampler steps] (emcee, tol=0)."""
        tau = _autocorr(self._sampled_space) * self.settings.get("thin", 1)
        return {n: float(t) for n, t in zip(self.names, tau)}

    @functools.cached_property
    def ess(self) -> dict[str, float]:
        """Effective sample size per parameter: walkers × draws / τ (τ in stored draws, ≥ 1)."""
        tau = np.maximum(_autocorr(self._sampled_space), 1.0)
        return {n: float(self.n_walkers * self.n_draws / t) for n, t in zip(self.names, tau)}

    @functools.cached_property
    def warnings(self) -> tuple[str, ...]:
        """Diagnostics that need attention (chain length, acceptance, correlations, fit notes)."""
        out = []
        thin = self.settings.get("thin", 1)
        taus = {n: t / thin for n, t in self.autocorr.items()}
        finite = {n: t for n, t in taus.items() if np.isfinite(t)}
        if finite:
            worst = max(finite, key=finite.get)
            if self.n_draws < CHAIN_TAU_MULTIPLE * finite[worst]:
                out.append(
                    f"the chain ({self.n_draws} draws per walker after burn-in) is shorter than {CHAIN_TAU_MULTIPLE} autocorrelation times "
                    f"(τ = {finite[worst] * thin:.3g} steps for {worst}): run more steps before trusting the intervals"
                )
        acc = self.mean_acceptance
        if not ACCEPTANCE_RANGE[0] <= acc <= ACCEPTANCE_RANGE[1]:
            out.append(f"mean acceptance fraction {acc:.3f} is outside {ACCEPTANCE_RANGE[0]}–{ACCEPTANCE_RANGE[1]}: the sampler is {'stuck' if acc < ACCEPTANCE_RANGE[0] else 'taking tiny steps'}")
        ys = self._sampled_space.reshape(-1, len(self.names))
        if ys.shape[0] > 2 and len(self.names) > 1:
            with np.errstate(all="ignore"):
                corr = np.corrcoef(ys, rowvar=False)
            for i in range(len(self.names)):
                for j in range(i + 1, len(self.names)):
                    same_element = self.names[i].split(".")[0] == self.names[j].split(".")[0]  # a CPE's Q and α: correlated yet well determined
                    if np.isfinite(corr[i, j]) and abs(corr[i, j]) > CORRELATION_WARNING and not same_element:
                        space = "log " if self.log_scale[i] and self.log_scale[j] else ""
                        out.append(
                            f"{self.names[i]} and {self.names[j]} are strongly correlated in the posterior (r = {corr[i, j]:+.3f} in {space}space): "
                            "the data constrain a combination of them; fix one or give it an informative prior"
                        )
        out.extend(self.notes)
        out.extend(f"least-squares start: {w}" for w in self.fit.warnings)
        return tuple(out)

    # -- parameter draws ------------------------------------------------------------------
    def parameter_draws(self) -> dict[str, np.ndarray]:
        """Flat draws of every parameter: sampled, fixed (repeated) and circuit parameters
        derived through the reparametrization."""
        flat = self.samples
        n = self.n_walkers * self.n_draws
        out = {name: np.full(n, value) for name, value in self.fixed.items()}
        out.update(flat)
        if self.reparametrization is not None:
            rp = self.reparametrization
            derived = rp.circuit_values({k: flat[k] for k in rp.names})
            out.update({k: np.asarray(v, float) for k, v in derived.items()})
        return out

    def circuit_samples(self) -> dict[str, np.ndarray]:
        """Flat draws of the circuit's parameters (derived ones included)."""
        everything = self.parameter_draws()
        return {n: everything[n] for n in self.circuit.parameter_names(self.registry)}

    def quantiles(self, *, circuit: bool = False) -> xr.Dataset:
        """median, q05, q16, q84, q95, mean, sd and the 90% HDI per parameter (``circuit=True``:
        the circuit's parameters, derived through the reparametrization)."""
        draws = self.circuit_samples() if circuit else self.samples
        names = list(draws)
        table = {k: [] for k in (*QUANTILES, "mean", "sd", "hdi90_low", "hdi90_high")}
        for n in names:
            x = np.asarray(draws[n], float)
            for k, q in QUANTILES.items():
                table[k].append(float(np.quantile(x, q)))
            table["mean"].append(float(x.mean()))
            table["sd"].append(float(x.std(ddof=1)) if x.size > 1 else 0.0)
            lo, hi = _hdi(x)
            table["hdi90_low"].append(lo)
            table["hdi90_high"].append(hi)
        return xr.Dataset({k: ("param", v) for k, v in table.items()}, coords={"param": names})

    def summary(self) -> dict:
        """The JSON summary used by ``impedax sample --json``."""
        q = self.quantiles()
        params = {n: {k: float(q[k].sel(param=n)) for k in ("median", "q05", "q16", "q84", "q95")} for n in self.names}
        for n in self.names:
            params[n].update(hdi90=[float(q["hdi90_low"].sel(param=n)), float(q["hdi90_high"].sel(param=n))], unit=self.units[self.names.index(n)], prior=str(self.priors[n]))
        out = {
            "model": self.model,
            "params": params,
            "acceptance": self.mean_acceptance,
            "autocorr": dict(self.autocorr),
            "ess": dict(self.ess),
            "warnings": list(self.warnings),
            "log_evidence": self.log_evidence,
            "waic": self.waic,
            "noise": self.noise,
            "walkers": self.n_walkers,
            "draws": self.n_draws,
            "steps": self.settings.get("steps"),
            "burn": self.settings.get("burn"),
            "thin": self.settings.get("thin"),
            "seed": self.settings.get("seed"),
            "map": dict(self.map_values),
        }
        if self.reparametrization is not None:
            cq = self.quantiles(circuit=True)
            out["circuit_params"] = {n: {k: float(cq[k].sel(param=n)) for k in ("median", "q05", "q16", "q84", "q95")} for n in self.reparametrization.replaces}
        return out

    def report(self) -> str:
        """A readable table of the posterior."""
        q = self.quantiles()
        width = max(len(n) for n in self.names)
        lines = [
            f"model      {self.model}",
            f"noise      {self.noise}: {NOISE_MODELS[self.noise]}",
            f"sampler    emcee, {self.n_walkers} walkers, {self.settings.get('steps')} steps (burn {self.settings.get('burn')}, thin {self.settings.get('thin')}), {self.n_walkers * self.n_draws} draws, acceptance {self.mean_acceptance:.3f}",
            f"evidence   Laplace ln Z = {self.log_evidence:.2f}    WAIC = {self.waic:.2f}",
            "",
            f"{'parameter':<{width}}  {'median':>11}  {'q05':>11}  {'q95':>11}  {'τ [steps]':>9}  {'ESS':>7}  unit   prior",
        ]
        for i, n in enumerate(self.names):
            lines.append(
                f"{n:<{width}}  {float(q['median'][i]):>11.5g}  {float(q['q05'][i]):>11.5g}  {float(q['q95'][i]):>11.5g}  {self.autocorr[n]:>9.3g}  {self.ess[n]:>7.0f}  {self.units[i]:<5}  {self.priors[n]}"
            )
        for w in self.warnings:
            lines.append(f"warning: {w}")
        return "\n".join(lines)

    # -- propagation ----------------------------------------------------------------------
    def derive(self, fn: Callable, freq=None, *, draws: bool = False, max_draws: int | None = None) -> xr.Dataset:
        """Evaluate ``fn(params[, freq])`` (a JAX function of the parameters dict, with every
        parameter by name: circuit, physical and ``sigma_rel``) over all draws in one vmapped
        call. Returns a Dataset with ``median``, ``q05``, ``q16``, ``q84``, ``q95``, ``mean``,
        ``sd`` (and ``draws`` over ``sample`` when ``draws=True``); ``freq`` defaults to the data's
        frequencies when ``fn`` takes one. ``max_draws`` evaluates an
        evenly spaced subset instead of every draw."""
        if freq is None and needs_freq(fn):
            freq = self.frequency
        g = _call(fn, freq)
        params = self.parameter_draws()
        if max_draws is not None and max_draws < self.n_walkers * self.n_draws:
            pick = np.linspace(0, self.n_walkers * self.n_draws - 1, max_draws).astype(int)
            params = {k: v[pick] for k, v in params.items()}
        out = jax.jit(jax.vmap(g))({k: jnp.asarray(v) for k, v in params.items()})
        _check_real(out)
        return band_dataset(np.asarray(out, float), freq, keep_draws=draws, attrs={"method": "posterior draws", "model": self.model})

    def predict(self, freq=None, *, max_draws: int = 400) -> np.ndarray:
        """Model impedance [Ω] (draws, frequency) over an evenly spaced subset of the draws."""
        freq = self.frequency if freq is None else np.asarray(freq, float)
        params = self.circuit_samples()
        total = self.n_walkers * self.n_draws
        pick = np.linspace(0, total - 1, min(max_draws, total)).astype(int)
        compiled = compile_circuit(self.circuit, self.registry)
        fn = jax.jit(jax.vmap(lambda p, f: compiled(p, f), in_axes=(0, None)))
        return np.asarray(fn({k: jnp.asarray(v[pick]) for k, v in params.items()}, jnp.asarray(freq)))

    # -- plots ----------------------------------------------------------------------------
    def plot(self, *, title: str | None = None, n_lines: int = 40):
        """Data with posterior bands: Nyquist (draws as thin lines) and Bode |Z| and phase with
        the 68% and 90% credible bands of the model (matplotlib Figure)."""
        import matplotlib.pyplot as plt

        f = np.geomspace(self.frequency.min(), self.frequency.max(), 200)
        zs = self.predict(f)
        fig = plt.figure(figsize=(11, 5.5), layout="constrained")
        grid = fig.add_gridspec(2, 2, width_ratios=[1, 1.2])
        ax_nyq, ax_mod = fig.add_subplot(grid[:, 0]), fig.add_subplot(grid[0, 1])
        ax_ph = fig.add_subplot(grid[1, 1], sharex=ax_mod)
        z = self.z_data
        for k in np.linspace(0, zs.shape[0] - 1, min(n_lines, zs.shape[0])).astype(int):
            ax_nyq.plot(zs[k].real, -zs[k].imag, "-", color="tab:blue", alpha=0.08, lw=0.8)
        med = np.median(zs.real, axis=0) + 1j * np.median(zs.imag, axis=0)
        ax_nyq.plot(med.real, -med.imag, "-", color="tab:blue", lw=1.5, label="posterior median")
        ax_nyq.plot(z.real, -z.imag, "o", ms=3.5, mfc="none", color="k", label="data")
        ax_nyq.set(xlabel="Z' [Ω]", ylabel="−Z'' [Ω]", title="Nyquist")
        ax_nyq.set_aspect("equal", adjustable="datalim")
        for ax, values, data_values in ((ax_mod, np.abs(zs), np.abs(z)), (ax_ph, np.degrees(np.angle(zs)), np.degrees(np.angle(z)))):
            q = np.quantile(values, [0.05, 0.16, 0.5, 0.84, 0.95], axis=0)
            ax.fill_between(f, q[0], q[4], color="tab:blue", alpha=0.18, lw=0, label="90% band")
            ax.fill_between(f, q[1], q[3], color="tab:blue", alpha=0.35, lw=0, label="68% band")
            ax.plot(f, q[2], "-", color="tab:blue", lw=1.2, label="median")
            ax.plot(self.frequency, data_values, "o", ms=3.5, mfc="none", color="k", label="data")
            ax.set_xscale("log")
        ax_mod.set(yscale="log", ylabel="|Z| [Ω]")
        ax_ph.set(ylabel="phase [deg]", xlabel="frequency [Hz]")
        for ax in (ax_nyq, ax_mod, ax_ph):
            ax.grid(alpha=0.3, which="both")
        ax_nyq.legend(fontsize=8)
        ax_mod.legend(fontsize=8)
        fig.suptitle(title or f"{self.model}: posterior bands ({self.n_walkers * self.n_draws} draws)")
        return fig

    def corner(self, *, truths: Mapping[str, float] | None = None, bins: int = 30, max_points: int = 4000):
        """Corner plot: marginal histograms on the diagonal and pairwise scatter below it
        (log10 axes for log-sampled parameters). ``truths`` draws reference lines."""
        import matplotlib.pyplot as plt

        k = len(self.names)
        flat = self.draws.reshape(-1, k)
        if flat.shape[0] > max_points:
            flat = flat[np.linspace(0, flat.shape[0] - 1, max_points).astype(int)]
        shown = np.where(np.asarray(self.log_scale), np.log10(np.where(np.asarray(self.log_scale), flat, 1.0)), flat)
        labels = [f"log10 {n}" if ls else n for n, ls in zip(self.names, self.log_scale)]
        truth = None
        if truths:
            truth = [(math.log10(truths[n]) if ls else truths[n]) if n in truths else None for n, ls in zip(self.names, self.log_scale)]
        size = min(2.0 * k + 1, 16)
        fig, axes = plt.subplots(k, k, figsize=(size, size), squeeze=False, layout="constrained")
        for i in range(k):
            for j in range(k):
                ax = axes[i, j]
                if j > i:
                    ax.set_visible(False)
                    continue
                if i == j:
                    ax.hist(shown[:, i], bins=bins, color="tab:blue", histtype="stepfilled", alpha=0.6)
                    for qv in np.quantile(shown[:, i], [0.05, 0.5, 0.95]):
                        ax.axvline(qv, color="k", lw=0.8, ls="--" if qv != np.median(shown[:, i]) else "-")
                    ax.set_yticks([])
                else:
                    ax.plot(shown[:, j], shown[:, i], ".", ms=1.5, alpha=0.25, color="tab:blue")
                    if truth is not None and truth[i] is not None:
                        ax.axhline(truth[i], color="tab:red", lw=0.8)
                if truth is not None and truth[j] is not None:
                    ax.axvline(truth[j], color="tab:red", lw=0.8)
                if i == k - 1:
                    ax.set_xlabel(labels[j], fontsize=8)
                else:
                    ax.set_xticklabels([])
                if j == 0 and i > 0:
                    ax.set_ylabel(labels[i], fontsize=8)
                elif j > 0:
                    ax.set_yticklabels([])
                ax.tick_params(labelsize=7)
        fig.suptitle(f"{self.model}: posterior ({flat.shape[0]} draws shown)", fontsize=9)
        return fig

    # -- storage --------------------------------------------------------------------------
    def to_xarray(self) -> xr.Dataset:
        """Draws (walker, draw, param), log_prob, diagnostics, summaries, the least-squares
        start and the data; `Posterior.from_xarray` rebuilds the posterior from it."""
        q = self.quantiles()
        fr = self.fit
        names = list(fr.values)
        free = list(fr.free_names)
        data = {
            "draws": (("walker", "draw", "param"), self.draws),
            "log_prob": (("walker", "draw"), self.log_prob),
            "acceptance": ("walker", self.acceptance),
            "autocorr": ("param", [self.autocorr[n] for n in self.names], {"units": "steps"}),
            "ess": ("param", [self.ess[n] for n in self.names]),
            "log_scale": ("param", np.asarray(self.log_scale, bool)),
            "map": ("param", [self.map_values[n] for n in self.names]),
            "Z": ("frequency", self.z_data, {"units": "ohm"}),
            "fit_value": ("circuit_param", [fr.values[n] for n in names]),
            "fit_stderr": ("circuit_param", [fr.stderr[n] for n in names]),
            "fit_fixed": ("circuit_param", [fr.fixed[n] for n in names]),
            "fit_covariance": (("free_param", "free_param_2"), fr.covariance),
            "fit_correlation": (("free_param", "free_param_2"), fr.correlation),
            "Z_fit": ("frequency", fr.z_model, {"units": "ohm"}),
        }
        data.update({k: ("param", q[k].values) for k in q.data_vars})
        if self.sigma is not None:
            data["sigma"] = ("frequency", self.sigma, {"units": "ohm"})
        attrs = {
            "impedax_kind": "posterior",
            "model": self.model,
            "noise": self.noise,
            "units": list(self.units),
            "priors": {n: [p.kind, p.a, p.b] for n, p in self.priors.items()},
            "fixed": dict(self.fixed),
            "settings": dict(self.settings),
            "log_evidence": self.log_evidence,
            "waic": self.waic,
            "p_waic": self.p_waic,
            "notes": list(self.notes),
            "warnings": list(self.warnings),
            "reparametrization": self.reparametrization.describe() if self.reparametrization is not None else None,
            "fit": {"weighting": fr.weighting, "chi2": fr.chi2, "converged": fr.converged, "message": fr.message, "n_evaluations": fr.n_evaluations, "warnings": list(fr.warnings), "n_starts": fr.n_starts, "elapsed_s": fr.elapsed_s},
        }
        coords = {
            "walker": np.arange(self.n_walkers),
            "draw": np.arange(self.n_draws),
            "param": list(self.names),
            "circuit_param": names,
            "free_param": free,
            "free_param_2": free,
            "frequency": ("frequency", self.frequency, {"units": "Hz"}),
        }
        return xr.Dataset(data, coords=coords, attrs=attrs)

    @classmethod
    def from_xarray(cls, ds: xr.Dataset, *, reparametrization: Reparametrization | None = None, registry: Registry = DEFAULT_REGISTRY) -> "Posterior":
        """Rebuild a posterior from `Posterior.to_xarray` output (e.g. read back from netCDF).
        A custom reparametrization must be passed again (its functions are not stored)."""
        if ds.attrs.get("impedax_kind") != "posterior" or "draws" not in ds:
            raise DataError("not a saved impedax posterior (no 'draws' variable / impedax_kind attribute)")
        circuit = parse(ds.attrs["model"], registry)
        rp = reparametrization
        if rp is None and ds.attrs.get("reparametrization"):
            rp = rebuild(ds.attrs["reparametrization"])
        fa = ds.attrs["fit"]
        names = [str(n) for n in ds["circuit_param"].values]
        fr = FitResult(
            circuit=circuit,
            values={n: float(v) for n, v in zip(names, ds["fit_value"].values)},
            stderr={n: float(v) for n, v in zip(names, ds["fit_stderr"].values)},
            fixed={n: bool(v) for n, v in zip(names, ds["fit_fixed"].values)},
            free_names=tuple(str(n) for n in ds["free_param"].values),
            covariance=np.asarray(ds["fit_covariance"].values, float),
            correlation=np.asarray(ds["fit_correlation"].values, float),
            frequency=np.asarray(ds["frequency"].values, float),
            z_data=np.asarray(ds["Z"].values, complex),
            z_model=np.asarray(ds["Z_fit"].values, complex),
            weighting=fa["weighting"],
            chi2=float(fa["chi2"]),
            converged=bool(fa["converged"]),
            message=fa["message"],
            n_evaluations=int(fa["n_evaluations"]),
            warnings=tuple(fa["warnings"]),
            n_starts=int(fa["n_starts"]),
            elapsed_s=float(fa["elapsed_s"]),
            registry=registry,
        )
        sampled = [str(n) for n in ds["param"].values]
        return cls(
            circuit=circuit,
            names=tuple(sampled),
            units=tuple(ds.attrs["units"]),
            log_scale=tuple(bool(v) for v in ds["log_scale"].values),
            draws=np.asarray(ds["draws"].values, float),
            log_prob=np.asarray(ds["log_prob"].values, float),
            acceptance=np.asarray(ds["acceptance"].values, float),
            priors={n: Prior(*v) for n, v in ds.attrs["priors"].items()},
            noise=ds.attrs["noise"],
            fit=fr,
            fixed={k: float(v) for k, v in ds.attrs["fixed"].items()},
            frequency=np.asarray(ds["frequency"].values, float),
            z_data=np.asarray(ds["Z"].values, complex),
            sigma=np.asarray(ds["sigma"].values, float) if "sigma" in ds else None,
            log_evidence=float(ds.attrs["log_evidence"]) if ds.attrs["log_evidence"] is not None else math.nan,
            waic=float(ds.attrs["waic"]) if ds.attrs["waic"] is not None else math.nan,
            p_waic=float(ds.attrs["p_waic"]) if ds.attrs["p_waic"] is not None else math.nan,
            map_values={n: float(v) for n, v in zip(sampled, ds["map"].values)},
            notes=tuple(ds.attrs.get("notes", ())),
            settings=dict(ds.attrs["settings"]),
            reparametrization=rp,
            registry=registry,
        )
