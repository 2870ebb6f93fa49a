"""The log-probability of a Bayesian fit, jitted once per structure.

    ln p(y | data) = ln π(y) + Σ_k ln N(Re r_k; 0, σ_k²) + ln N(Im r_k; 0, σ_k²) + const,
    r_k = Z_model(f_k) − Z_data,k.

Sampled space: every parameter with a positive domain is sampled as y = ln x, others as x
itself (``LogProbStructure.log_scale``). Priors are defined on the natural parameter x, so the
prior density in the sampled space carries the Jacobian |dx/dy| = x: ln π_y(y) = ln π_x(e^y) + y.

Noise models (`NoiseModel`, described in `NOISE_MODELS`): ``proportional`` — Re and Im of point
k each carry Gaussian noise σ_k = sigma_rel·|Z_data,k|, with ``sigma_rel`` a sampled parameter;
``sigma`` — a known per-point σ_k from the data's ``sigma`` variable (e.g. the standard error of
the mean of repeated trials), nothing extra sampled.

What is static (the circuit, which vector entry feeds which circuit parameter) is a hashable
`LogProbStructure`; what varies between runs of one structure (data, fixed values, prior
numbers) is a `LogProbArgs` pytree, so one compilation serves them all.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ...arguments import NOISE_MODELS as NOISE_MODELS, NoiseModel as NoiseModel
from ...circuits import Circuit, Registry, compile_circuit
from ..stored import StoredProgram
from .priors import prior_log_density
from .reparam import Reparametrization

__all__ = ["NoiseModel", "NOISE_MODELS", "LogProbStructure", "LogProbArgs", "LogProbFunctions", "log_prob_functions", "walkers_log_prob", "natural", "start_weighting"]


def start_weighting(noise: str) -> str:
    """The weighting of the least-squares fit a sampling starts from: ``modulus`` for
    proportional noise, the data's ``sigma`` for known noise."""
    return "modulus" if NoiseModel(noise) is NoiseModel.PROPORTIONAL else "sigma"


NOISE_TITLES = {NoiseModel.PROPORTIONAL: "noise σ ∝ |Z|", NoiseModel.SIGMA: "noise σ: the data's sigma"}
"""`NOISE_MODELS` in a few words, for a posterior's figure titles (`Posterior.plot`, `corner`)."""


@dataclass(frozen=True)
class LogProbStructure:
    """Everything static about a log-probability (hashable: one compilation per structure)."""

    circuit: Circuit
    registry: Registry
    circuit_names: tuple[str, ...]
    direct_index: tuple[int, ...]  # per circuit name: index in the sampled vector, −1 if fixed/replaced
    reparametrization: Reparametrization | None
    reparam_index: tuple[int, ...]
    sigma_index: int  # −1 when the noise scale is known
    log_scale: tuple[bool, ...]


class LogProbArgs(NamedTuple):
    """The arrays a log-probability of one structure reads (a pytree passed to the jitted
    functions): the data, the fixed circuit values and the priors of the sampled parameters."""

    freq: jax.Array  # (N,) Hz
    z: jax.Array  # (N,) complex Ω, the data
    scale: jax.Array  # (N,) Ω: σ_k = scale_k · sigma_rel (proportional) or scale_k (known σ)
    fixed: jax.Array  # per circuit name: its value when fixed (ignored otherwise)
    code: jax.Array  # per sampled parameter: `Prior.code`
    a: jax.Array  # per sampled parameter: the prior's first number
    b: jax.Array  # per sampled parameter: the prior's second number
    lo: jax.Array  # per sampled parameter: lower end of the prior's support (natural value)
    hi: jax.Array  # per sampled parameter: upper end of the prior's support (natural value)
    log_norm: jax.Array  # per sampled parameter: `Prior.log_normaliser` of the truncation


class LogProbFunctions(NamedTuple):
    """The jitted functions of one structure, each taking ``(y, args)``."""

    batched: Callable  # (W, P) → (W,) log-posterior, what emcee calls (vectorize=True)
    single: Callable  # (P,) → () log-posterior
    value_and_grad: Callable  # (P,) → (value, gradient)
    hessian: Callable  # (P,) → (P, P)
    pointwise: Callable  # (S, P) → (S, N) ln-likelihood of each frequency point


def natural(y, st: LogProbStructure):
    """Natural parameter values x from sampled values y (exp where log-sampled)."""
    return jnp.where(jnp.asarray(st.log_scale), jnp.exp(y), y)


def _circuit_params(x, args: LogProbArgs, st: LogProbStructure) -> dict:
    params = {}
    for i, name in enumerate(st.circuit_names):
        j = st.direct_index[i]
        params[name] = x[j] if j >= 0 else args.fixed[i]
    if st.reparametrization is not None:
        rp = st.reparametrization
        params.update(rp.circuit_values({n: x[j] for n, j in zip(rp.names, st.reparam_index)}))
    return params


def _pointwise_loglik(x, args: LogProbArgs, st: LogProbStructure):
    """ln-likelihood of each frequency point (Re and Im together), shape (N,)."""
    z = compile_circuit(st.circuit, st.registry)(_circuit_params(x, args, st), args.freq)
    r = z - args.z
    sigma = args.scale * (x[st.sigma_index] if st.sigma_index >= 0 else 1.0)
    ll = -0.5 * (r.real**2 + r.imag**2) / sigma**2 - 2.0 * jnp.log(sigma) - jnp.log(2.0 * jnp.pi)
    return jnp.where(jnp.isfinite(ll), ll, -jnp.inf)


def _log_prior(y, args: LogProbArgs, st: LogProbStructure):
    x = natural(y, st)
    lp = prior_log_density(x, args.code, args.a, args.b, args.lo, args.hi, args.log_norm)
    return jnp.sum(lp + jnp.where(jnp.asarray(st.log_scale), y, 0.0))


def _log_prob(y, args: LogProbArgs, st: LogProbStructure):
    lp = _log_prior(y, args, st)
    ll = jnp.sum(_pointwise_loglik(natural(y, st), args, st))
    ok = jnp.isfinite(lp) & jnp.isfinite(ll)
    return jnp.where(ok, lp + jnp.where(ok, ll, 0.0), -jnp.inf)


@functools.lru_cache(maxsize=64)
def log_prob_functions(st: LogProbStructure) -> LogProbFunctions:
    """The jitted log-probability functions of ``st`` (cached: one compilation per structure),
    each kept across processes (`stored.StoredProgram`, named ``bayes-…``, keyed by ``st``): a
    fresh `impedax sample` of a circuit sampled before traces none of them, the Laplace
    evidence's Hessian included (benchmarks/README.md, "Stored Bayesian programs")."""
    single = functools.partial(_log_prob, st=st)

    def stored(name: str, fn: Callable) -> StoredProgram:
        return StoredProgram(f"bayes-{name}", st, jax.jit(fn))

    return LogProbFunctions(
        batched=stored("batched", jax.vmap(single, in_axes=(0, None))),
        single=stored("single", single),
        value_and_grad=stored("value-and-grad", jax.value_and_grad(single)),
        hessian=stored("hessian", jax.hessian(single)),
        pointwise=stored("pointwise", jax.vmap(lambda y, args: _pointwise_loglik(natural(y, st), args, st), in_axes=(0, None))),
    )


def walkers_log_prob(batched: Callable, args) -> Callable[[np.ndarray], np.ndarray]:
    """``coords`` (W, P) → their log-posteriors (W,) as numpy by ``batched(coords, args)`` (a
    `LogProbFunctions.batched`, or a joint posterior's), what emcee calls thousands of times: a
    stored program is found once per walker count (`StoredProgram.for_arguments`), not on every
    call."""
    by_shape: dict = {}

    def log_prob(coords):
        coords = jnp.asarray(coords)
        run = by_shape.get(coords.shape)
        if run is None:
            run = by_shape[coords.shape] = batched.for_arguments(coords, args) if isinstance(batched, StoredProgram) else batched
        return np.asarray(run(coords, args))

    return log_prob
