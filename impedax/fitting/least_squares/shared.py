"""Global fits: parameters shared across spectra (`fit(..., shared=[...], over="trial")`).

Spectra i = 1…M along the ``over`` dimensions share the values s of the shared parameters;
every spectrum keeps its own values a_i of the others. The joint least-squares problem
min Σ_i ‖r_i(a_i, s)‖² has a block-arrow normal matrix: with J_i = ∂r_i/∂a_i and
S_i = ∂r_i/∂s,

    [ J_iᵀJ_i (block-diagonal)   J_iᵀS_i  ] [δa_i]     [ J_iᵀr_i  ]
    [ S_iᵀJ_i                  Σ S_iᵀS_i  ] [δs  ] = − [ Σ S_iᵀr_i ],

solved by the Schur complement (Triggs et al. 2000, bundle adjustment §6.1):
(Σ S_iᵀS_i − Σ S_iᵀJ_i (J_iᵀJ_i)⁻¹ J_iᵀS_i) δs = −Σ S_iᵀr_i + Σ S_iᵀJ_i (J_iᵀJ_i)⁻¹ J_iᵀr_i,
then δa_i = −(J_iᵀJ_i)⁻¹ (J_iᵀr_i + J_iᵀS_i δs), each diagonal block damped (Levenberg–
Marquardt with Marquardt's scaling and Nielsen's update, as `lm.lm_iteration`). No dense
Jacobian over all spectra is formed: the per-spectrum blocks come from the circuit's analytic
Jacobian (`solvers.tree_residuals`), ``vmap``-ed over spectra, all inside one ``jit``.

The covariance is the inverse of the same matrix, by the block-inverse formula:
Cov(s) = S⁻¹ (S the Schur complement), Cov(a_i, s) = −A_i⁻¹B_i S⁻¹,
Cov(a_i) = A_i⁻¹ + A_i⁻¹B_i S⁻¹B_iᵀA_i⁻¹ (A_i = J_iᵀJ_i, B_i = J_iᵀS_i), scaled by
χ²/(2NM − (M·K_own + K_shared)) unless the weights are the data's sigma.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import math
import time
from dataclasses import dataclass
from typing import NamedTuple, Sequence

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from ...circuits import Circuit, DEFAULT_REGISTRY, Registry, compile_circuit
from ...arguments import closest_name, shown
from ...data import column_width, concise_repr, counted, report_text, coordinate_labels, format_relative_error, unit_text
from ...errors import DataError, FitError, ParameterError
from ...progress import say, silenced
from ...warning_groups import scope_key
from ..parameters import ParameterTable, to_internal
from ..problem import residual_scale, weights
from ..statistics import SINGULAR_RATIO_LIMIT, add_null_group, information_criteria
from .batch import BatchFitResult, batch_with_warnings, data_notes, fit_batch
from .order import exchangeable_blocks
from .branches import idle_branch_notes, idle_branches, settle_vanishing, undetermined, undetermined_mask, unidentified_stderr, vanishing_candidates, vanishing_parameters
from .result import value_shown_at_bound, near_bound_notes, BOUND_CHI2_FRACTION, LINEARISED_STDERR_NAME, STDERR_NOTE, at_rounding, bound_note, bound_sides, is_remainder, NUMERICALLY_ON_FRACTION, on_bound, shown_stderr, stack_notes, unidentified_group_note, vanishing_term_sides, without_error
from .solvers import SolverArgs, tree_residuals

__all__ = ["SharedFitResult", "SharedLayout", "shared_layout", "fit_shared", "JointSolution", "joint_solver", "joint_covariance", "joint_null_sets", "JointNullSets", "SHARING_P_LIMIT"]

# sharing is reported as contradicted by the data when the F-test of shared against
# independent fits rejects it at this level
SHARING_P_LIMIT = 0.01

POOR_SPECTRUM_CHI2_RATIO = 2.0
"""A spectrum whose χ² in the global fit is above this multiple of its independent fit's is
refitted alone under the shared values and the global fit solved again from there (kept when
the joint χ² falls): on the REAL battery cycles 40–59 (R0 + R1 ∥ CPE1 + R2 ∥ CPE2, both α
shared) the global fit from the independent fits left cycle 49 at 46 % rms_rel."""


@dataclass(frozen=True)
class SharedLayout:
    """Which free parameters are shared (``shared``, positions ``shared_slots`` in the free
    order) and which are each spectrum's own (``own_slots``), the dimensions they are shared
    over (``over``) and the other extra dimensions (``keep``: one global fit per index)."""

    shared: tuple[str, ...]
    over: tuple[str, ...]
    keep: tuple[str, ...]
    shared_slots: tuple[int, ...]
    own_slots: tuple[int, ...]


def _as_names(value, what: str) -> tuple[str, ...]:
    if isinstance(value, str):
        names = tuple(n.strip() for n in value.split(",") if n.strip())
    else:
        try:
            names = tuple(value)
        except TypeError:
            raise ParameterError(f"{what}: expected a name or a list of names, got {type(value).__name__}") from None
    if not names or not all(isinstance(n, str) and n for n in names):
        raise ParameterError(f"{what}: expected one or more names, got {shown(value)}")
    if len(set(names)) != len(names):
        raise ParameterError(f"{what}: a name is given twice ({', '.join(names)})")
    return names


def shared_layout(table: ParameterTable, extra_dims: Sequence[str], shared, over, *, source: str = "data") -> SharedLayout:
    """Check ``shared`` (parameter names) and ``over`` (extra dimensions of the data; None when
    the data have exactly one) and lay them out. `ParameterError` names what is wrong."""
    extra_dims = tuple(extra_dims)
    if shared is None:
        raise ParameterError("over= was given without shared=: name the parameters to share (shared=['R0', ...])")
    names = _as_names(shared, "shared")
    if not extra_dims:
        raise DataError("shared parameters need data with extra dimensions (trial, session, ...) to share them over; these data hold one spectrum", path=source)
    if over is None:
        if len(extra_dims) != 1:
            raise ParameterError(f"over: the data have several extra dimensions ({', '.join(extra_dims)}); say which the parameters are shared over (over='{extra_dims[0]}', or several: over={list(map(str, extra_dims))})")
        over_dims = extra_dims
    else:
        over_dims = _as_names(over, "over")
        for d in over_dims:
            if d not in extra_dims:
                raise ParameterError(f"over: {d!r} is not a dimension of the data (extra dimensions: {', '.join(extra_dims)})")
    for n in names:
        if n not in table.names:
            close = closest_name(n, table.names)
            hint = f"; did you mean {close}?" if close else ""
            raise ParameterError(f"shared: unknown parameter {n!r}{hint} (parameters: {', '.join(table.names)})")
        if n not in table.free_names:
            raise ParameterError(f"shared: {n} is fixed; a fixed value is already the same in every spectrum (free parameters: {', '.join(table.free_names)})")
    free = table.free_names
    shared_slots = tuple(sorted(free.index(n) for n in names))
    own_slots = tuple(i for i in range(len(free)) if i not in shared_slots)
    keep = tuple(d for d in extra_dims if d not in over_dims)
    return SharedLayout(tuple(free[i] for i in shared_slots), tuple(over_dims), keep, shared_slots, own_slots)


class JointSolution(NamedTuple):
    """One global fit: own points ``u_own`` (M, K_own) and the shared point ``u_shared``
    (K_shared,) in the solver's unconstrained space, the weighted ``chi2`` Σ‖r_i‖², whether it
    converged (``done``) and the ``steps`` taken."""

    u_own: jax.Array
    u_shared: jax.Array
    chi2: jax.Array
    done: jax.Array
    steps: jax.Array


class _JointState(NamedTuple):
    """The damped iteration's state (as `lm.LMState`, with the blocks of every spectrum)."""

    u_own: jax.Array  # (M, Ko)
    u_shared: jax.Array  # (Ks,)
    a: jax.Array  # (M, K, K) per-spectrum JᵀJ at the accepted point (free order)
    g: jax.Array  # (M, K) per-spectrum Jᵀr
    cost: jax.Array  # ½ Σ ‖r_i‖²
    try_own: jax.Array
    try_shared: jax.Array
    pred: jax.Array
    lam: jax.Array
    nu: jax.Array
    i: jax.Array
    done: jax.Array
    dmax_own: jax.Array  # (M, Ko) running maximum of diag(A_i) (Marquardt's scaling)
    dmax_shared: jax.Array  # (Ks,) running maximum of diag(Σ C_i)


_SPECTRUM_AXES = SolverArgs(freq=None, z=0, inv_w_re=0, inv_w_im=0, x_fixed=None, lower=None, upper=None)


def _solve_blocks(a, b):
    """Batched a⁻¹b for (…, k, k) systems; empty systems give empty answers."""
    if a.shape[-1] == 0:
        return jnp.zeros(b.shape, b.dtype)
    return jnp.linalg.solve(a, b)


@functools.lru_cache(maxsize=16)
def joint_solver(circuit: Circuit, registry: Registry, free: tuple[int, ...], kinds: tuple[int, ...], shared_slots: tuple[int, ...], rtol: float = 1e-8, xtol: float = 1e-10):
    """(solve, finish, chi2_x) for the global fit of ``circuit`` with the free parameters at
    positions ``free`` (transforms ``kinds``) and those at ``shared_slots`` of the free order
    shared (module docstring).

    ``solve(u_own (M, Ko), u_shared (Ks,), args, max_steps) -> JointSolution``; ``args`` is a
    `SolverArgs` whose z, inv_w_re, inv_w_im have a leading spectrum axis (M, N).
    ``finish(u_own, u_shared, args) -> (x_free (M, K), x (M, P), J (M, 2N, K), r (M, 2N))``:
    every spectrum's free and all parameters, and its Jacobian and residual in parameter space;
    ``chi2_x(x_free (M, K), args) -> (M,)``: every spectrum's weighted χ² at free values x_free."""
    compiled = compile_circuit(circuit, registry)
    residuals = tree_residuals(compiled, free, kinds)
    k = len(free)
    s_idx = np.asarray(shared_slots, int)
    o_idx = np.asarray([i for i in range(k) if i not in shared_slots], int)
    normal = jax.vmap(residuals.normal_u, in_axes=(0, _SPECTRUM_AXES))
    order = np.argsort(np.concatenate([o_idx, s_idx]))

    def joined(u_own, u_shared):
        m = u_own.shape[0]
        return jnp.concatenate([u_own, jnp.broadcast_to(u_shared[None, :], (m, s_idx.size))], axis=1)[:, order]

    def evaluate(u_own, u_shared, args):
        a, g, cost, _ = normal(joined(u_own, u_shared), args)
        cost = jnp.sum(cost)
        ok = jnp.isfinite(cost) & jnp.all(jnp.isfinite(a)) & jnp.all(jnp.isfinite(g))
        return a, g, jnp.where(ok, cost, jnp.inf)

    def step(s: _JointState, args) -> _JointState:
        a_try, g_try, c_try = evaluate(s.try_own, s.try_shared, args)
        first = s.i == 0
        gain = s.cost - c_try
        ok = first | ((gain > 0) & jnp.isfinite(c_try))
        rho = gain / jnp.where(s.pred > 0, s.pred, 1.0)
        lam = jnp.where(first, s.lam, jnp.where(ok, s.lam * jnp.maximum(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3), s.lam * s.nu))
        nu = jnp.where(ok, 2.0, s.nu * 2.0)
        keep = lambda new, old: jnp.where(ok, new, old)  # noqa: E731
        u_own, u_shared, cost = keep(s.try_own, s.u_own), keep(s.try_shared, s.u_shared), keep(c_try, s.cost)
        a, g = keep(a_try, s.a), keep(g_try, s.g)
        # the blocks: A_i (own × own), B_i (own × shared), C = Σ C_i (shared × shared)
        a_own = a[:, o_idx][:, :, o_idx]
        b = a[:, o_idx][:, :, s_idx]
        c = jnp.sum(a[:, s_idx][:, :, s_idx], axis=0)
        g_own, g_shared = g[:, o_idx], jnp.sum(g[:, s_idx], axis=0)
        dmax_own = jnp.maximum(jnp.diagonal(a_own, axis1=1, axis2=2), s.dmax_own)
        dmax_shared = jnp.maximum(jnp.diagonal(c), s.dmax_shared)
        d_own = jnp.where(dmax_own > 0, dmax_own, 1.0)
        d_shared = jnp.where(dmax_shared > 0, dmax_shared, 1.0)
        damped_own = a_own + lam * (d_own[:, :, None] * jnp.eye(o_idx.size)[None])
        # A_i⁻¹ [B_i, g_i] for every spectrum at once, then the Schur complement
        x = _solve_blocks(damped_own, jnp.concatenate([b, g_own[:, :, None]], axis=2))
        x_b, x_g = x[:, :, :-1], x[:, :, -1]
        schur = c + lam * jnp.diag(d_shared) - jnp.einsum("mks,mkt->st", b, x_b)
        rhs = g_shared - jnp.einsum("mks,mk->s", b, x_g)
        delta_shared = -jnp.linalg.solve(schur, rhs)
        delta_own = -(x_g + jnp.einsum("mks,s->mk", x_b, delta_shared))
        solved = jnp.all(jnp.isfinite(delta_shared)) & jnp.all(jnp.isfinite(delta_own))
        delta_shared = jnp.where(solved, delta_shared, 0.0)
        delta_own = jnp.where(solved, delta_own, 0.0)
        pred = 0.5 * (jnp.sum(delta_own * (lam * d_own * delta_own - g_own)) + jnp.dot(delta_shared, lam * d_shared * delta_shared - g_shared))
        flat = ~first & ok & (gain <= rtol * s.cost)
        size = jnp.sqrt(jnp.sum(delta_own**2) + jnp.sum(delta_shared**2))
        norm = jnp.sqrt(jnp.sum(u_own**2) + jnp.sum(u_shared**2))
        tiny = solved & (size <= xtol * (norm + xtol))
        done = flat | tiny | (lam > 1e15) | ~jnp.isfinite(cost)
        return _JointState(u_own, u_shared, a, g, cost, u_own + delta_own, u_shared + delta_shared, pred, lam, nu, s.i + 1, done, dmax_own, dmax_shared)

    @jax.jit
    def solve(u_own, u_shared, args, max_steps):
        m = u_own.shape[0]
        init = _JointState(
            u_own=u_own, u_shared=u_shared, a=jnp.zeros((m, k, k)), g=jnp.zeros((m, k)), cost=jnp.asarray(jnp.inf),
            try_own=u_own, try_shared=u_shared, pred=jnp.asarray(1.0), lam=jnp.asarray(1e-3), nu=jnp.asarray(2.0),
            i=jnp.asarray(0), done=jnp.asarray(False), dmax_own=jnp.zeros((m, o_idx.size)), dmax_shared=jnp.zeros(s_idx.size),
        )
        s = jax.lax.while_loop(lambda s: (s.i < max_steps) & ~s.done, lambda s: step(s, args), init)
        return JointSolution(s.u_own, s.u_shared, 2.0 * s.cost, s.done, s.i)

    def finish_one(u, args):
        x_free, x = residuals.to_x(u, args)
        jac, r = residuals.linearise_x(x_free, args)
        return x_free, x, jac, r

    @jax.jit
    def finish(u_own, u_shared, args):
        return jax.vmap(finish_one, in_axes=(0, _SPECTRUM_AXES))(joined(u_own, u_shared), args)

    chi2_x = jax.jit(jax.vmap(residuals.chi2_x, in_axes=(0, _SPECTRUM_AXES)))
    return solve, finish, chi2_x


def _regularized_inverse(a: np.ndarray) -> np.ndarray:
    """Inverses of symmetric positive semi-definite matrices (…, k, k), column-equilibrated and
    Tikhonov-regularised as `statistics.covariances` (undetermined directions give huge
    variances, not NaN)."""
    if a.shape[-1] == 0:
        return np.zeros(a.shape)
    d = np.sqrt(np.clip(np.einsum("...ii->...i", a), 0, None))
    scale = np.where(d > 0, 1.0 / np.where(d > 0, d, 1.0), 1.0)
    eq = a * scale[..., :, None] * scale[..., None, :]
    w, v = np.linalg.eigh(eq)
    # a matrix without a positive eigenvalue (a block of zeros, or rounding's negative Schur
    # complement: parameters without effect on Z) is regularised against 1, as
    # `statistics.covariances` does: variances of 1e26, where a floor of 1e-300 made 1e-26 × it
    # underflow to 0 and divided by zero (inf and NaN, and a RuntimeWarning)
    w_max = np.where(w[..., -1:] > 0, w[..., -1:], 1.0)
    inv = (v / (np.clip(w, 0, None) + 1e-26 * w_max)[..., None, :]) @ np.swapaxes(v, -1, -2)
    with np.errstate(over="ignore"):  # (columns below ~1e-140: a variance beyond the float range is inf, as there)
        return inv * scale[..., :, None] * scale[..., None, :]


def joint_covariance(jac: np.ndarray, own: Sequence[int], shared: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
    """Unscaled covariance of a global fit from the per-spectrum Jacobians ``jac`` (M, 2N, K)
    by the block inverse (module docstring): the shared block (Ks, Ks) and every spectrum's
    marginal covariance over all its free parameters (M, K, K), free order."""
    own, shared = np.asarray(own, int), np.asarray(shared, int)
    m, k = jac.shape[0], jac.shape[2]
    if not np.all(np.isfinite(jac)):  # an overflowed model: nothing is determined, and says so
        return np.full((shared.size, shared.size), np.inf), np.full((m, k, k), np.inf)
    j_own, j_shared = jac[:, :, own], jac[:, :, shared]
    a = np.swapaxes(j_own, 1, 2) @ j_own
    b = np.swapaxes(j_own, 1, 2) @ j_shared
    c = np.einsum("mns,mnt->st", j_shared, j_shared)
    a_inv = _regularized_inverse(a)
    a_inv_b = a_inv @ b
    schur_inv = _regularized_inverse(c - np.einsum("mks,mkt->st", b, a_inv_b))
    cov_os = -a_inv_b @ schur_inv
    cov_oo = a_inv + a_inv_b @ schur_inv @ np.swapaxes(a_inv_b, 1, 2)
    full = np.zeros((m, k, k))
    full[:, own[:, None], own[None, :]] = cov_oo
    full[:, own[:, None], shared[None, :]] = cov_os
    full[:, shared[:, None], own[None, :]] = np.swapaxes(cov_os, 1, 2)
    full[:, shared[:, None], shared[None, :]] = schur_inv
    return schur_inv, full


class JointNullSets(NamedTuple):
    """The near-null directions of one global fit (`joint_null_sets`): ``groups``, per spectrum,
    the groups of its free parameters (own and shared) along each direction, as
    `FitResult.unidentified_groups` (those of ``shared_groups`` included); ``ratios`` (M,), per
    spectrum, the smallest of its directions' singular values over the largest (1 without
    any); ``shared_groups``, the directions of shared parameters alone (said once per global
    fit), with ``shared_ratio``."""

    groups: list[list[list[str]]]
    ratios: np.ndarray
    shared_groups: list[list[str]]
    shared_ratio: float


# a direction's parameters are those with a component above this share of it (`statistics.null_sets`' rule)
_NULL_COMPONENT = 0.2


def _unit_columns(jac: np.ndarray, axes: tuple[int, ...]) -> np.ndarray:
    """``jac`` with each column scaled to unit norm over ``axes`` (divided by its largest entry
    first, as `statistics.covariances`, so that no square overflows); a zero column stays zero."""
    peak = np.max(np.abs(jac), axis=axes, keepdims=True) if jac.size else np.ones((1,) * jac.ndim)
    scaled = jac / np.where(peak > 0, peak, 1.0)
    norm = np.sqrt(np.sum(scaled**2, axis=axes, keepdims=True))
    return scaled / np.where(norm > 0, norm, 1.0)


def _joint_product(e_own: np.ndarray, e_shared: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """J̃v of the joint equilibrated Jacobian (blocks ``e_own`` (M, 2N, Ko), ``e_shared``
    (M, 2N, Ks)) and v = (x (M, Ko), y (Ks,)): (M, 2N)."""
    return np.einsum("mnk,mk->mn", e_own, x) + e_shared @ y


def _largest_singular_value(e_own: np.ndarray, e_shared: np.ndarray, steps: int = 200) -> float:
    """The largest singular value of the joint equilibrated Jacobian (`_joint_product`), by power
    iteration on J̃ᵀJ̃ (to 1e-3: it sets a threshold of 1e-8 of it); at least 1, the
    norm of each nonzero unit column."""
    x, y = np.ones(e_own.shape[::2]), np.ones(e_shared.shape[-1])
    estimate = 0.0
    for _ in range(steps):
        norm = math.sqrt(float(np.sum(x**2) + np.sum(y**2)))
        if norm == 0:
            break
        x, y = x / norm, y / norm
        r = _joint_product(e_own, e_shared, x, y)
        x, y = np.einsum("mnk,mn->mk", e_own, r), np.einsum("mns,mn->s", e_shared, r)
        previous, estimate = estimate, math.sqrt(math.sqrt(float(np.sum(x**2) + np.sum(y**2))))
        if abs(estimate - previous) <= 1e-3 * estimate:
            break
    return max(estimate, 1.0)


def joint_null_sets(jac: np.ndarray, own: Sequence[int], shared: Sequence[int], names: Sequence[str]) -> JointNullSets:
    """The near-null directions of a global fit's joint Jacobian, from the per-spectrum
    Jacobians ``jac`` (M, 2N, K) over the free parameters ``names`` (positions ``own`` and
    ``shared``), by the rule of single fits (`statistics.null_sets`): a singular value of the
    column-equilibrated joint Jacobian below `SINGULAR_RATIO_LIMIT` × its largest, its
    parameters those with a component above 0.2, here of the direction as each spectrum's own
    fit sees it (its shared components scaled by the spectrum's share of the shared column:
    R0 shared against R1 of each spectrum is (−1/√M, 1/√M) jointly, ±0.71 in each spectrum).

    The joint Jacobian is never formed. A direction either moves only a spectrum's own
    parameters (a near-null singular value of its own equilibrated block, by SVD) or moves the
    shared ones by y: then each spectrum's own parameters follow it by the least-squares
    x_i = −J̃_i⁺ S̃_i y, and the direction is near-null when y is a near-null right singular
    vector of the shared columns with what each spectrum's own columns explain projected out,
    ((I − U_iU_iᵀ) S̃_i)_i stacked (the square root of the Schur complement, without squaring the
    condition number as JᵀJ does). Its singular value is ‖J̃v‖/‖v‖ of v = (x, y). An
    overflowed Jacobian (an inf or NaN entry) has none, as a single fit's. Two directions over
    the same parameters are one group (`statistics.add_null_group`, as `null_sets`: a
    Havriliak–Negami element's four parameters are listed and warned once)."""
    jac = np.asarray(jac, float)
    own, shared = np.asarray(own, int), np.asarray(shared, int)
    m = jac.shape[0]
    groups: list[list[list[str]]] = [[] for _ in range(m)]
    ratios = np.ones(m)
    shared_groups: list[list[str]] = []
    shared_ratio = 1.0
    if not jac.size or not np.all(np.isfinite(jac)):
        return JointNullSets(groups, ratios, shared_groups, shared_ratio)
    e_own = _unit_columns(jac[:, :, own], (1,))
    e_shared = _unit_columns(jac[:, :, shared], (0, 1))
    s_max = _largest_singular_value(e_own, e_shared)
    limit = SINGULAR_RATIO_LIMIT * s_max
    own_names, shared_names = [names[i] for i in own], [names[i] for i in shared]
    # directions of one spectrum's own parameters alone
    if own.size:
        u, s, vt = np.linalg.svd(e_own, full_matrices=False)
    else:
        u, s, vt = np.zeros((m, jac.shape[1], 0)), np.zeros((m, 0)), np.zeros((m, 0, 0))
    kept = s >= limit
    for i, j in np.argwhere(~kept).tolist():
        add_null_group(groups[i], [own_names[c] for c in np.flatnonzero(np.abs(vt[i, j]) > _NULL_COMPONENT)])
        ratios[i] = min(ratios[i], float(s[i, j]) / s_max)
    # directions that move the shared parameters
    if not shared.size:
        return JointNullSets(groups, ratios, shared_groups, shared_ratio)
    u_kept = u * kept[:, None, :]
    remainder = e_shared - u_kept @ (np.swapaxes(u_kept, 1, 2) @ e_shared)
    _, t, yt = np.linalg.svd(remainder.reshape(-1, shared.size), full_matrices=False)
    column_share = np.sqrt(np.sum(e_shared**2, axis=1))  # (M, Ks): each spectrum's share of a shared unit column
    for y in yt[t < limit]:
        along = np.einsum("mnk,mn->mk", u_kept, e_shared @ y)
        x = -np.einsum("mjk,mj->mk", vt, np.where(kept, along / np.where(kept, s, 1.0), 0.0))
        size = float(np.linalg.norm(_joint_product(e_own, e_shared, x, y))) / math.sqrt(float(np.sum(x**2) + np.sum(y**2))) / s_max
        members = [shared_names[c] for c in np.flatnonzero(np.abs(y) > _NULL_COMPONENT)]
        seen = np.zeros((m, len(names)))  # each spectrum's view: own components x_i, shared ones y scaled by its share
        seen[:, own], seen[:, shared] = x, y[None, :] * column_share
        norms = np.linalg.norm(seen, axis=1, keepdims=True)
        spectrum_members = np.abs(seen) > _NULL_COMPONENT * np.where(norms > 0, norms, np.inf)
        if not spectrum_members[:, own].any():  # shared parameters alone: one group for the global fit
            add_null_group(shared_groups, members)
            shared_ratio = min(shared_ratio, size)
            for i in range(m):
                add_null_group(groups[i], members)
                ratios[i] = min(ratios[i], size)
            continue
        for i in np.flatnonzero(spectrum_members.any(axis=1)).tolist():
            add_null_group(groups[i], [names[c] for c in np.flatnonzero(spectrum_members[i])])
            ratios[i] = min(ratios[i], size)
    return JointNullSets(groups, ratios, shared_groups, shared_ratio)


def _correlation(cov: np.ndarray) -> np.ndarray:
    d = np.sqrt(np.clip(np.einsum("...ii->...i", cov), 0, None))
    with np.errstate(all="ignore"):
        corr = np.clip(np.nan_to_num(cov / (d[..., :, None] * d[..., None, :]), nan=0.0), -1, 1)
    k = cov.shape[-1]
    corr[..., np.arange(k), np.arange(k)] = 1.0
    return corr


@dataclass(frozen=True, eq=False)
class SharedFitResult(BatchFitResult):
    """A global fit: one value of each ``shared`` parameter across the ``over`` dimensions, per-
    spectrum values of the others. Immutable; answers every call of `BatchFitResult`.

    ``dataset`` holds, beside the variables of a batch fit (``value``/``stderr`` over (param,
    *dims), the shared ones repeated along ``over``): ``shared_value``/``shared_stderr`` over
    (shared_param, *keep) (keep: the extra dimensions not shared over), ``shared_correlation``,
    each spectrum's ``covariance``/``correlation`` over all its free parameters, the joint
    ``joint_chi2``, ``joint_chi2_red``, ``joint_dof``, ``joint_aic``, ``joint_bic`` and the test of
    sharing against independent fits: ``independent_chi2``, ``independent_aic``, ``delta_aic``
    (shared − independent; negative favours sharing), ``f_statistic``, ``f_pvalue``."""

    __repr__ = concise_repr  # (the generated one printed every array)
    __str__ = report_text  # (print(result): its report)

    def fit_of(self, *positional, **labels):
        """Not for a global fit: one spectrum refitted alone would move the shared parameters
        (`BatchFitResult.fit_of`); `ParameterError` saying so, however it is called (a position
        too, not Python's TypeError)."""
        raise ParameterError(
            "fit_of refits one spectrum alone, which would move the shared parameters of this global fit; "
            "fix them instead: ix.fit(model, one_spectrum, fixed={shared name: its value}, init=the spectrum's values)"
        )

    shared: tuple[str, ...] = ()
    over: tuple[str, ...] = ()
    _KIND = "shared_fit"

    @classmethod
    def from_xarray(cls, ds: xr.Dataset, *, registry: Registry | None = None) -> "SharedFitResult":
        """Rebuild a global fit from `SharedFitResult.to_xarray` output (as `BatchFitResult.from_xarray`
        does a batch): the shared parameters and the dimensions shared over from its variables."""
        return cls._rebuilt(ds, "shared_fit", registry, shared=lambda d: tuple(str(n) for n in d["shared_param"].values),
                            over=lambda d: tuple(str(n) for n in d["rms_rel"].dims if n not in d["shared_value"].dims))

    @property
    def keep(self) -> tuple[str, ...]:
        return tuple(d for d in self.dims if d not in self.over)

    def values(self, name: str) -> xr.DataArray:
        """Fitted values of ``name``: over the dimensions not shared over for a shared parameter,
        over all extra dimensions for the others."""
        if name in self.shared:
            return self.dataset["shared_value"].sel(shared_param=name)
        return super().values(name)

    def stderr(self, name: str) -> xr.DataArray:
        """Standard errors of ``name``, the shape of `values`: over the dimensions not shared over
        for a shared parameter (``shared_stderr``), over all extra dimensions for the others."""
        if name in self.shared:
            return self.dataset["shared_stderr"].sel(shared_param=name)
        return super().stderr(name)

    def to_table(self) -> list[dict[str, object]]:
        """`BatchFitResult.to_table` with a ``shared`` column after ``fixed``:
        True on the rows of a shared parameter (the JSON's ``shared``), whose value and stderr
        each row of its group repeats (one estimate, not one per spectrum: average the rows with
        ``shared`` False only, or take one row per group). Its ``warnings`` are the spectrum's
        and then its global fit's ("shared CPE2.alpha is at its upper bound 1", "the spectra
        disagree with sharing ...")."""
        out = []
        for row in super().to_table():
            at = list(row).index("fixed") + 1
            group = self.warnings.get(scope_key(self.over, ", ".join(f"{d}={row[d]}" for d in self.keep)), ())
            items = list({**row, "warnings": "; ".join(([row["warnings"]] if row["warnings"] else []) + list(group))}.items())
            out.append(dict(items[:at] + [("shared", row["name"] in self.shared)] + items[at:]))
        return out

    def _scalar_or_list(self, da: xr.DataArray):
        return float(da) if da.ndim == 0 else da.transpose(*self.keep).values.tolist()

    def group_labels(self) -> list[dict]:
        """The labels of each group of spectra that shares one value (one per combination of the
        dimensions not shared over, in C order over `keep`: the order of the lists in
        ``summary()["shared"]``); [{}] when every spectrum shares one value."""
        import itertools

        ds = self.dataset
        axes = [[(d, v) for v in coordinate_labels(ds, d)] for d in self.keep]
        return [dict(combo) for combo in itertools.product(*axes)]

    def _notes_of(self, row: dict) -> list[str]:
        """A spectrum's warnings and those of the global fit of its group (a shared parameter's
        bound note is filed there, `scope_key`)."""
        group = ", ".join(f"{d}={row['labels'][d]}" for d in self.keep)
        return [*row["warnings"], *self.warnings.get(scope_key(self.over, group), ())]

    def _group_texts(self) -> list[str]:
        return [", ".join(f"{d}={v}" for d, v in labels.items()) for labels in self.group_labels()]

    def summary(self) -> dict:
        """The batch summary plus ``over``, ``shared`` (per shared parameter: value, stderr,
        fixed = False, as the parameters of a single fit's JSON; lists over the dimensions not
        shared over, if any) and ``sharing`` (joint χ², the F-test and ΔAIC against
        independent fits)."""
        out = super().summary()
        ds = self.dataset
        specs = self.circuit.parameter_specs(self.registry)  # (each shared parameter's unit, as a single fit's)
        out["over"] = list(self.over)
        groups = {"labels": self.group_labels()} if self.keep else {}  # (which group each list entry is)
        out["shared"] = {
            n: {"value": self._scalar_or_list(ds["shared_value"].sel(shared_param=n)), "stderr": _shown(self._scalar_or_list(ds["shared_stderr"].sel(shared_param=n))), "fixed": False, "unit": specs[n].unit, **groups}
            for n in self.shared
        }
        keys = ("joint_chi2", "joint_chi2_red", "joint_dof", "joint_aic", "joint_bic", "independent_chi2", "independent_aic", "delta_aic", "f_statistic", "f_pvalue")
        out["sharing"] = {**{k.removeprefix("joint_"): self._scalar_or_list(ds[k]) for k in keys}, **groups}
        return out

    def report(self, *, misfit_hints=None) -> str:
        """The batch's table, the shared parameters' (one row per global fit), the test of
        sharing, the warnings and, given ``misfit_hints`` (`BatchFitResult.misfit_hints`, which
        ``impedax fit`` computes once), its hint line, which says why the command line prints
        the diagnose command of the worst such spectrum."""
        lines = [*self._parameter_lines(), "", f"shared over {', '.join(self.over)} (one global fit{'' if not self.keep else ' per ' + ', '.join(self.keep)}):"]
        ds = self.dataset
        specs = self.circuit.parameter_specs(self.registry)
        width = column_width(self.shared, 16)
        # one value per group of the dimensions not shared over: each row and F-test says whose
        groups = self._group_texts() if self.keep else [""]
        lead_width = column_width(groups, 5) if self.keep else 0
        lead = (lambda g: f"{g:<{lead_width}} ") if self.keep else (lambda g: "")
        lines.append(f"{lead('group')}{'parameter':<{width}} {'value':>12} {'stderr':>10} {'rel':>9}  unit")
        ordered = lambda da: (da.transpose(*self.keep) if self.keep else da).values.ravel()  # noqa: E731
        for n in self.shared:
            v = ordered(ds["shared_value"].sel(shared_param=n))
            e = ordered(ds["shared_stderr"].sel(shared_param=n))
            at = ds["at_bound"].sel(param=n).isel({d: 0 for d in self.over}).transpose(*self.keep).values.ravel()
            for g, vi, ei, bound in zip(groups, v.tolist(), e.tolist(), at.tolist()):
                rel = "at bound" if bound else format_relative_error(ei / vi) if vi and math.isfinite(ei) else "—"
                shown = f"{ei:>10.3g}" if math.isfinite(ei) else f"{'—':>10}"  # (at a bound: no standard error)
                value = value_shown_at_bound(n, vi, self.warnings.get(scope_key(self.over, g), ())) if bound else f"{vi:.5g}"  # (on a bound 0: "0", as its note says)
                lines.append(f"{lead(g)}{n:<{width}} {value:>12} {shown} {rel:>9}  {unit_text(specs[n].unit)}".rstrip())
        for g, f, p, d, c in zip(groups, *(ordered(ds[k]).tolist() for k in ("f_statistic", "f_pvalue", "delta_aic", "joint_chi2_red"))):
            whose = f" ({g})" if g else ""
            lines.append(f"sharing vs independent fits{whose}: F = {f:.3g}, p = {p:.3g}, ΔAIC = {d:+.1f} (negative favours sharing); joint chi2_red {c:.4g}")
        return "\n".join(lines + self._warning_lines() + ([] if misfit_hints is None else ["", f"hint: {misfit_hints['note']}"]))


def _shown(stderr):
    """A shared standard error (a number or a list over the kept dimensions) as the JSON gives
    it: None where there is none (at a bound; `result.shown_stderr`)."""
    return [_shown(e) for e in stderr] if isinstance(stderr, list) else shown_stderr(stderr, False)


def _group_arrays(data: xr.Dataset, layout: SharedLayout, extra: tuple[str, ...]):
    """Z (G, M, N) and sigma (or None) with the global fits' spectra in rows, and the shape of
    the keep and over dimensions."""
    order = (*layout.keep, *layout.over, "frequency")
    z = data["Z"].transpose(*order).values
    sigma = data["sigma"].transpose(*order).values if "sigma" in data else None
    keep_shape = tuple(data.sizes[d] for d in layout.keep)
    over_shape = tuple(data.sizes[d] for d in layout.over)
    g, m, n = int(np.prod(keep_shape)), int(np.prod(over_shape)), data.sizes["frequency"]
    return z.reshape(g, m, n), None if sigma is None else sigma.reshape(g, m, n), keep_shape, over_shape


def fit_shared(
    circuit: Circuit, data: xr.Dataset, table: ParameterTable, *, shared, over, weighting: str, n_starts: int, max_steps: int, seed: int,
    registry: Registry = DEFAULT_REGISTRY, source: str = "data", t0: float | None = None,
) -> SharedFitResult:
    """The global fit of ``circuit`` to ``data`` with the parameters ``shared`` shared over the
    dimensions ``over`` (module docstring). Starts from independent fits of every spectrum
    (`batch.fit_batch`), the shared parameters at the median of their independent values;
    those fits are also the alternative of the F-test of sharing."""
    t0 = time.perf_counter() if t0 is None else t0
    if not isinstance(max_steps, (int, np.integer)) or isinstance(max_steps, bool) or max_steps < 1:
        raise ParameterError(f"max_steps must be a positive integer, got {max_steps!r}")
    extra = tuple(d for d in data["Z"].dims if d != "frequency")
    layout = shared_layout(table, extra, shared, over, source=source)
    if hasattr(data["Z"].data, "compute"):  # dask-backed: a global fit needs all of it at once
        data = data.compute()
    freq = np.asarray(data["frequency"].values, float)
    independent = fit_batch(circuit, data, table, weighting=weighting, n_starts=n_starts, max_steps=max_steps, seed=seed, registry=registry, source=source)
    z, sigma, keep_shape, over_shape = _group_arrays(data, layout, extra)
    n_groups, m, n_freq = z.shape
    inv_re, inv_im = weights(z, sigma, weighting, source, freq)
    free = table.free_index
    k, k_shared = free.size, len(layout.shared_slots)
    own, sh = np.asarray(layout.own_slots, int), np.asarray(layout.shared_slots, int)
    order = (*layout.keep, *layout.over, "param")
    x_ind = independent.dataset["value"].transpose(*order).values.reshape(n_groups, m, -1)[:, :, free]
    chi2_ind = independent.dataset["chi2"].transpose(*layout.keep, *layout.over).values.reshape(n_groups, m)
    solver = joint_solver(circuit, registry, *table.free_structure, layout.shared_slots)
    exchangeable = exchangeable_free_columns(circuit, registry, table, layout)
    refits = [functools.partial(_own_refits, circuit, registry, table, layout, freq, z[gi], None if sigma is None else sigma[gi], weighting=weighting, n_starts=n_starts, max_steps=max_steps, seed=seed, source=source)
              for gi in range(n_groups)]
    fits = [_solve_group(solver, table, layout, freq, z[gi], inv_re[gi], inv_im[gi], x_ind[gi], chi2_ind[gi], weighting=weighting, max_steps=int(max_steps), exchangeable=exchangeable, refit=refits[gi])
            for gi in range(n_groups)]
    values, x_free, chi2, z_model, cov_shared, cov_full = (np.stack([getattr(f, name) for f in fits]) for name in ("values", "x_free", "chi2", "z_model", "cov_shared", "cov_full"))
    joint = {"chi2": np.array([f.chi2.sum() for f in fits]), "converged": np.array([f.converged for f in fits]), "steps": np.array([f.steps for f in fits])}

    n_res = 2 * n_freq * m
    k_joint = m * own.size + k_shared
    dof = n_res - k_joint
    noise = joint["chi2"] / dof if dof > 0 else np.full(n_groups, math.nan)
    if weighting != "sigma":
        factor = np.where(np.isfinite(noise), noise, 1.0)
        cov_shared = cov_shared * factor[:, None, None]
        cov_full = cov_full * factor[:, None, None, None]
    stderr_free = np.sqrt(np.clip(np.einsum("gmii->gmi", cov_full), 0, None))
    stderr = np.full(values.shape, np.nan)
    stderr[:, :, free] = stderr_free
    shared_value = x_free[:, 0, sh]
    shared_stderr = np.sqrt(np.clip(np.einsum("gii->gi", cov_shared), 0, None))
    corr_full, corr_shared = _correlation(cov_full), _correlation(cov_shared)

    # sharing against independent fits: nested models on the same residuals
    k_ind = m * k
    chi2_indep = np.sum(np.where(np.isfinite(chi2_ind), chi2_ind, np.inf), axis=1)
    aic_joint, bic_joint = information_criteria(joint["chi2"], n_res, k_joint)
    aic_ind, _ = information_criteria(chi2_indep, n_res, k_ind)
    f_stat, f_p = _f_test(joint["chi2"], chi2_indep, k_joint, k_ind, n_res)

    # warnings: per spectrum the single-fit rules on its marginal covariance; per global fit
    # the shared parameters' determination and the test of sharing
    flat_values, flat_stderr = values.reshape(-1, values.shape[-1]), stderr.reshape(-1, values.shape[-1])
    sides = bound_sides(table, flat_values, flat_stderr).reshape(n_groups, m, k)
    for gi in range(n_groups):
        sides[gi] = _confirm_sides(sides[gi], x_free[gi], table, sh, solver[2], fits[gi].args, noise[gi] * fits[gi].scale**2, 2 * n_freq)
    sides = sides.reshape(-1, k)
    # an own parameter of a term that vanishes at any value is undetermined, not at a bound (as `fit_result`)
    own_sides = vanishing_term_sides(circuit, registry, table, flat_values, sides, freq, z.reshape(-1, n_freq)) if k else sides
    sides = np.where(np.isin(np.arange(k), sh), sides, own_sides).astype(sides.dtype)  # (a shared one's bound: said per global fit)
    # a spectrum's own parameters of a term that changes Z by < 1e-6: at the natural bound that explains it, or undetermined (as `fit_result`)
    candidates = vanishing_candidates(sides, flat_values[:, free], flat_stderr[:, free])
    candidates[:, sh] = False
    vanishing = vanishing_parameters(circuit, registry, table, flat_values, freq, candidates)
    vanishing[:, sh] = 0
    sides, flat_stderr[:, free], vanished = settle_vanishing(vanishing, sides, flat_values[:, free], flat_stderr[:, free])
    # the parameters of the joint Jacobian's near-null directions (`joint_null_sets`) have no
    # standard error, whatever χ²_red scales the linearisation by (as `fit_result`): a shared
    # one in every spectrum of its global fit
    shared_columns = table.free_index[sh]
    null_groups = [found for f in fits for found in f.null.groups]  # (per spectrum, flat order)
    null_ratios = np.concatenate([f.null.ratios for f in fits])
    for row, found in enumerate(null_groups):
        if found:
            flat_stderr[row, free] = unidentified_stderr(table.free_names, found, sides[row], flat_stderr[row, free])
    shared_flagged = np.zeros((n_groups, k_shared), bool)
    for gi, f in enumerate(fits):
        shared_flagged[gi] = np.isinf(unidentified_stderr(layout.shared, [g for found in f.null.groups for g in found], sides[gi * m, sh], np.zeros(k_shared)))
        shared_stderr[gi] = np.where(shared_flagged[gi], np.inf, shared_stderr[gi])
        flat_stderr[gi * m : (gi + 1) * m, shared_columns] = np.where(shared_flagged[gi], np.inf, flat_stderr[gi * m : (gi + 1) * m, shared_columns])
    stderr = flat_stderr.reshape(values.shape)
    # (a shared parameter's bound and determination are said once per global fit, below)
    quiet_stderr = flat_stderr.copy()
    quiet_stderr[:, shared_columns] = 0.0
    quiet_sides = sides.copy()
    quiet_sides[:, sh] = 0
    # (the correlation of two shared parameters of one near-null direction is that direction's,
    # whose note is said per global fit, below: none of its own in each spectrum)
    quiet_corr = corr_full.reshape(-1, k, k).copy()
    for gi, f in enumerate(fits):
        for group in f.null.shared_groups:
            columns = np.array([table.free_names.index(n) for n in group], int)
            quiet_corr[gi * m : (gi + 1) * m, columns[:, None], columns[None, :]] = np.eye(columns.size)
    # a spectrum with a near-null direction through its own parameters: a single fit's warnings
    # with that group's (`fit_notes`, as a batch's); one of shared parameters alone is said per global fit
    alone = [[sorted(g) for g in f.null.shared_groups] for f in fits]
    told = [[g for g in found if sorted(g) not in alone[row // m]] for row, found in enumerate(null_groups)]
    spectrum_notes = stack_notes(table, flat_values, quiet_stderr, quiet_corr, quiet_sides, freq=freq, z=z.reshape(-1, n_freq), null_sets=told, ratios=null_ratios)
    for row, note in idle_branch_notes(circuit, registry, table, flat_values, undetermined_mask(table, flat_values, quiet_stderr, quiet_sides) | vanished, freq).items():
        spectrum_notes[row] = spectrum_notes.get(row, ()) + note
    # what concerns each spectrum's data in the global fit, the rules and texts of single and
    # batch fits (`batch.data_notes`: a weighting dominated by a few points, Re Z < 0, the misfit
    # against its own Kramers–Kronig misfit, whose KK test runs only for the spectra at rms_rel
    # ≥ MISFIT_CHECKED_FROM), under the spectrum's key as in a batch
    flat_sigma = None if sigma is None else sigma.reshape(-1, n_freq)
    # (`notes.Note`s: their tags are each spectrum's `BatchFitResult.warning_tags`, set where the notes are made)
    for row, note in enumerate(data_notes(freq, z.reshape(-1, n_freq), z_model.reshape(-1, n_freq), flat_sigma, weighting, source, remainder=is_remainder(data.attrs), attrs=data.attrs)):
        if note:
            spectrum_notes[row] = spectrum_notes.get(row, ()) + note
    group_notes = [
        _sharing_notes(layout, shared_value[gi], shared_stderr[gi], sides.reshape(n_groups, m, k)[gi, 0, sh], table, f_stat[gi], f_p[gi], aic_joint[gi] - aic_ind[gi], bool(joint["converged"][gi]), int(joint["steps"][gi]),
                       null=fits[gi].null, flagged=shared_flagged[gi], exact=bool(np.all(at_rounding(z[gi], z_model[gi]))), on=on_bound(table, values[gi, :1], sides.reshape(n_groups, m, k)[gi, :1], np.tile(freq, m), z[gi].reshape(1, -1))[0, sh],
                       exactly=on_bound(table, values[gi, :1], sides.reshape(n_groups, m, k)[gi, :1], np.tile(freq, m), z[gi].reshape(1, -1), NUMERICALLY_ON_FRACTION)[0, sh])
        for gi in range(n_groups)
    ]
    for gi in range(n_groups):  # a shared parameter within 2 standard errors of its bound: said once per global fit (each spectrum's notes have it quiet)
        first = sides.reshape(-1, k)[gi * m : gi * m + 1]
        own_quiet = np.ones_like(first)  # (the spectra's own parameters: their notes are each spectrum's)
        own_quiet[:, sh] = first[:, sh]
        group_notes[gi] += tuple("shared " + note for _, note in near_bound_notes(table, flat_values[gi * m : gi * m + 1], flat_stderr[gi * m : gi * m + 1], own_quiet))
    for gi in range(n_groups):  # a shared parameter's idle branch: said once per global fit, when idle in every spectrum
        group_notes[gi] += _shared_idle_notes(circuit, registry, table, layout, values[gi], shared_value[gi], shared_stderr[gi], sides.reshape(n_groups, m, k)[gi, 0, sh], freq)
    # the result gives no standard error, nor correlations, to a parameter at a bound or a
    # vanishing term's (as `fit_result`); the notes above speak of the linearisation
    linearised_stderr = stderr
    shown, shown_corr = without_error(sides, vanished, flat_stderr[:, free], corr_full.reshape(-1, k, k))
    stderr = flat_stderr.copy()
    stderr[:, free] = shown
    stderr, corr_full = stderr.reshape(values.shape), shown_corr.reshape(corr_full.shape)
    shared_sides = sides.reshape(n_groups, m, k)[:, 0, sh]
    shared_linearised_stderr = shared_stderr
    shared_stderr, corr_shared = without_error(shared_sides, np.zeros(shared_sides.shape, bool), shared_stderr, corr_shared)
    dataset, warnings = _result_dataset(
        circuit, data, table, layout, extra, keep_shape, over_shape, values=values, stderr=stderr, linearised_stderr=linearised_stderr, chi2=chi2, z_model=z_model, sides=sides,
        cov_full=cov_full, corr_full=corr_full, shared_value=shared_value, shared_stderr=shared_stderr, shared_linearised_stderr=shared_linearised_stderr, corr_shared=corr_shared, joint=joint,
        stats={"joint_chi2": joint["chi2"], "joint_chi2_red": noise, "joint_dof": np.full(n_groups, float(dof)), "joint_aic": aic_joint, "joint_bic": bic_joint,
               "independent_chi2": chi2_indep, "independent_aic": aic_ind, "delta_aic": aic_joint - aic_ind, "f_statistic": f_stat, "f_pvalue": f_p},
        spectrum_notes=spectrum_notes, group_notes=group_notes, weighting=weighting, null_groups=null_groups,
    )
    return batch_with_warnings(SharedFitResult(circuit, dataset, weighting, {}, time.perf_counter() - t0, registry, shared=layout.shared, over=layout.over, warning_tags={}), warnings)


class _GroupFit(NamedTuple):
    """One global fit: all parameters ``values`` (M, P) and the free ones ``x_free`` (M, K), each
    spectrum's weighted ``chi2`` (M,) and ``z_model`` (M, N), the unscaled covariances (shared
    block, and each spectrum's over its free parameters), convergence, steps, the solver's
    ``args`` with their residual ``scale`` (for χ² at other points) and the near-null
    directions (`joint_null_sets`)."""

    values: np.ndarray
    x_free: np.ndarray
    chi2: np.ndarray
    z_model: np.ndarray
    cov_shared: np.ndarray
    cov_full: np.ndarray
    converged: bool
    steps: int
    args: SolverArgs
    scale: float
    null: JointNullSets


def _solve_group(solver, table: ParameterTable, layout: SharedLayout, freq, z, inv_re, inv_im, x_independent, chi2_independent, *, weighting: str, max_steps: int, exchangeable=(), refit=None) -> _GroupFit:
    """The global fit of spectra z (M, N) from their independent fits ``x_independent`` (M, K):
    own parameters start there, shared ones at the median over the spectra; ``exchangeable``:
    `exchangeable_free_columns`; ``refit(rows, shared free values) -> x (rows, K) | None``: the
    free values of those spectra fitted alone with the shared parameters held (`_own_refits`),
    for the spectra whose χ² the global fit leaves above `POOR_SPECTRUM_CHI2_RATIO` × their
    independent fit's."""
    solve, finish, _ = solver
    free = table.free_index
    lower, upper, kind = table.lower[free], table.upper[free], table.kind[free]
    own, shared = np.asarray(layout.own_slots, int), np.asarray(layout.shared_slots, int)
    # one scale for the whole global fit: a per-spectrum scale would reweight the spectra
    scale = float(np.median(residual_scale(z, inv_re, inv_im, weighting)))
    args = SolverArgs(freq, z, inv_re * scale, inv_im * scale, np.where(np.isnan(table.values), 1.0, table.values), lower, upper)
    u_start = to_internal(x_independent, lower, upper, kind)
    finite = np.all(np.isfinite(u_start), axis=1) & np.isfinite(chi2_independent)
    fallback = np.median(u_start[finite], axis=0) if finite.any() else to_internal(np.ones(free.size), lower, upper, kind)
    u_start = np.where(finite[:, None], u_start, fallback[None, :])
    # the independent fits list exchangeable blocks by peak frequency (`order`): where two arcs'
    # peaks cross between spectra, a shared CPE1.alpha starts from one arc in some spectra and the
    # other arc in the rest; the start with each spectrum's blocks aligned to the shared median is
    # solved too, and the lower χ² kept (`blocks_aligned_to_shared`)
    starts = [u_start]
    aligned = blocks_aligned_to_shared(u_start, exchangeable, shared)
    if not np.array_equal(aligned, u_start):
        starts.append(aligned)
    best = None
    for start in starts:
        u_shared = np.median(start[:, shared], axis=0)  # (the median commutes with the monotone transforms)
        sol = jax.device_get(solve(start[:, own], u_shared, args, max_steps))
        out = tuple(np.asarray(a) for a in jax.device_get(finish(sol.u_own, sol.u_shared, args)))
        total = float(np.sum(out[3] ** 2))
        if best is None or total < best[0]:
            best = (total, sol, out)
    # spectra the global fit leaves far above their own fits: each refitted alone under the shared
    # values, then solved again; with every free parameter shared there is nothing of a spectrum's
    # own to refit (the refit's solver, with no own columns, would end in JAX's "Need at least one
    # array to stack" on spectra that differ)
    if refit is not None and len(own):
        chi2_rows = np.sum(best[2][3] ** 2, axis=1) / scale**2
        poor = np.flatnonzero(np.isfinite(chi2_independent) & (chi2_rows > POOR_SPECTRUM_CHI2_RATIO * chi2_independent))
        if poor.size:
            say(f"{counted(poor.size, 'spectrum', 'spectra')} of the global fit above {POOR_SPECTRUM_CHI2_RATIO:g}× the χ² of {'its own fit' if poor.size == 1 else 'their own fits'}: "
                f"{'it' if poor.size == 1 else 'each'} refitted alone under the shared values, then the global fit solved again")
            with silenced():  # (the refits' own stages: one line above says them)
                x_refit = refit(poor, best[2][0][0, shared])
            if x_refit is not None:
                u_own = np.array(best[1].u_own, float)
                u_own[poor] = to_internal(x_refit, lower, upper, kind)[:, own]
                sol = jax.device_get(solve(u_own, np.asarray(best[1].u_shared, float), args, max_steps))
                out = tuple(np.asarray(a) for a in jax.device_get(finish(sol.u_own, sol.u_shared, args)))
                total = float(np.sum(out[3] ** 2))
                if total < best[0]:
                    best = (total, sol, out)
    _, sol, (x_free, values, jac, r) = best
    jac, r = jac / scale, r / scale
    n = z.shape[1]
    cov_shared, cov_full = joint_covariance(jac, own, shared)
    z_model = z + r[:, :n] / inv_re + 1j * r[:, n:] / inv_im
    null = joint_null_sets(jac, own, shared, table.free_names)
    return _GroupFit(values, x_free, np.sum(r**2, axis=1), z_model, cov_shared, cov_full, bool(sol.done), int(sol.steps), args, scale, null)


def _own_refits(circuit: Circuit, registry: Registry, table: ParameterTable, layout: SharedLayout, freq, z, sigma, rows, shared_free, *, weighting: str, n_starts: int, max_steps: int, seed: int, source: str):
    """The free values (len(rows), K) of spectra ``z[rows]`` each fitted alone (`fit_batch`, its
    ladder of starts) with the shared parameters held at ``shared_free``, or None when a fit fails."""
    free = table.free_index
    columns = free[np.asarray(layout.shared_slots, int)]
    held = np.zeros(len(table.names), bool)
    held[columns] = True
    values = np.array(table.values, float)
    values[columns] = shared_free
    held_table = dataclasses.replace(table, fixed=table.fixed | held, values=values)
    variables = {"Z": (("spectrum", "frequency"), z[rows])}
    if sigma is not None:
        variables["sigma"] = (("spectrum", "frequency"), sigma[rows])
    data = xr.Dataset(variables, coords={"spectrum": np.arange(len(rows)), "frequency": freq})
    try:
        alone = fit_batch(circuit, data, held_table, weighting=weighting, n_starts=n_starts, max_steps=max_steps, seed=seed, registry=registry, source=source)
    except (FitError, DataError, ParameterError):  # (the first solution stands)
        return None
    x = alone.dataset["value"].transpose("spectrum", "param").values[:, free]
    return x if np.all(np.isfinite(x)) else None


def exchangeable_free_columns(circuit: Circuit, registry: Registry, table: ParameterTable, layout: SharedLayout) -> list[np.ndarray]:
    """Per group of exchangeable blocks (`order.exchangeable_blocks`) holding a shared
    parameter: its columns in the free order, (members, parameters per block)."""
    groups = exchangeable_blocks(circuit, table.names, np.asarray(table.fixed, bool), table.lower, table.upper, registry)
    position = {int(c): j for j, c in enumerate(table.free_index)}
    out = []
    for blocks in groups:
        columns = np.array([[position[c] for c in idx] for _, idx in blocks])
        if np.isin(columns, layout.shared_slots).any():
            out.append(columns)
    return out


def blocks_aligned_to_shared(u: np.ndarray, groups: list[np.ndarray], shared) -> np.ndarray:
    """Start values ``u`` (M, K, internal coordinates) with each spectrum's exchangeable blocks
    reordered so that its shared parameters lie closest (squared distance) to their median over
    the spectra, the median recomputed after each pass (three at most): the spectra then start
    from one assignment of the arcs, whatever their peaks' order."""
    if not groups or u.shape[0] < 2:
        return u
    shared = np.asarray(shared, int)
    u = np.array(u, float)
    for _ in range(3):
        moved = False
        for columns in groups:
            orders = [list(p) for p in itertools.permutations(range(columns.shape[0]))]
            for i in range(u.shape[0]):
                target = np.median(u[:, shared], axis=0)
                costs = []
                for order in orders:
                    trial = u[i].copy()
                    trial[columns.ravel()] = u[i][columns[order].ravel()]
                    costs.append(float(np.sum((trial[shared] - target) ** 2)))
                best = int(np.argmin(costs))
                if costs[best] < costs[0] - 1e-12:
                    u[i, columns.ravel()] = u[i][columns[orders[best]].ravel()].copy()
                    moved = True
        if not moved:
            break
    return u


def _confirm_sides(sides, x_free, table: ParameterTable, shared_slots, chi2_x, args, chi2_red: float, n_residuals: int) -> np.ndarray:
    """`bound_sides` candidates (M, K) of one global fit, kept where setting the parameter
    exactly to its bound raises χ² by at most `BOUND_CHI2_FRACTION` of the reduced χ² (the
    rule of single fits, docs/fitting.md "Convergence and bounds"): an own parameter on its
    spectrum's χ², a shared one on the sum over the spectra. χ² and ``chi2_red`` in the solver's
    scaled units."""
    if not sides.any():
        return sides
    free = table.free_index
    lower, upper = table.lower[free], table.upper[free]
    base = np.asarray(chi2_x(x_free, args))
    allowed = BOUND_CHI2_FRACTION * (chi2_red if math.isfinite(chi2_red) else 0.0) + n_residuals * 1e-28
    out = sides.copy()
    for j in np.flatnonzero(sides.any(axis=0)).tolist():
        rows = np.flatnonzero(sides[:, j])
        moved = x_free.copy()
        moved[rows, j] = np.where(sides[rows, j] > 0, upper[j], lower[j])
        if j in shared_slots:
            moved[:, j] = moved[rows[0], j]
            rise = float(np.sum(np.asarray(chi2_x(moved, args))) - np.sum(base))
            keep = np.full(rows.size, math.isfinite(rise) and rise <= allowed)
        else:
            with np.errstate(invalid="ignore"):
                rise_rows = np.asarray(chi2_x(moved, args))[rows] - base[rows]
            keep = np.isfinite(rise_rows) & (rise_rows <= allowed)
        out[rows[~keep], j] = 0
    return out


def _f_test(chi2_shared, chi2_independent, k_shared_model: int, k_independent: int, n_res: int):
    """F = ((χ²_shared − χ²_ind)/(k_ind − k_shared)) / (χ²_ind/(n − k_ind)) and its p-value
    (as `comparison.compare`); NaN where undefined."""
    from scipy import stats

    d1, d2 = k_independent - k_shared_model, n_res - k_independent
    with np.errstate(all="ignore"):
        f = np.maximum(chi2_shared - chi2_independent, 0.0) / d1 / (chi2_independent / d2) if d1 > 0 and d2 > 0 else np.full(np.shape(chi2_shared), np.nan)
        f = np.where(np.isfinite(f), f, np.nan)
        p = np.where(np.isfinite(f), stats.f.sf(np.nan_to_num(f), d1, max(d2, 1)), np.nan)
    return f, p


def _shared_idle_notes(circuit, registry, table: ParameterTable, layout: SharedLayout, values, value, stderr, sides, freq) -> tuple[str, ...]:
    """The idle-branch note (`branches.idle_branches`) of the shared parameters the global fit
    leaves undetermined (the rule of `_sharing_notes`), for an element idle in every spectrum
    of the group (values (M, P)), with the largest share among them."""
    shared_columns = [table.free_names.index(n) for n in layout.shared]
    flagged = (np.asarray(sides) == 0) & undetermined(value, stderr)
    mask = np.zeros((values.shape[0], len(table.free_names)), bool)
    mask[:, np.asarray(shared_columns, int)[flagged]] = True
    by_element: dict[str, list] = {}
    for branch in idle_branches(circuit, registry, table, values, mask, freq):
        by_element.setdefault(branch.element, []).append(branch)
    return tuple("shared " + max(found, key=lambda b: b.share).text() for found in by_element.values() if len(found) == values.shape[0])


def _sharing_notes(layout: SharedLayout, value, stderr, sides, table: ParameterTable, f, p, delta_aic, converged: bool, steps: int, *, on, exactly=None,
                   null: JointNullSets | None = None, flagged=None, exact: bool = False) -> tuple[str, ...]:
    """The notes of one global fit: convergence, the near-null directions of shared parameters
    alone (``null``, `joint_null_sets`, in a single fit's words), the shared parameters' bounds
    (``on``: on the bound, `result.on_bound`, else off it but not told from it; ``exactly``: on
    it within `result.NUMERICALLY_ON_FRACTION`, its value not given) and determination (not of
    one in a near-null direction, ``flagged``: that direction's note speaks for it), the F-test
    (none where the global fit matches every spectrum to rounding, ``exact``, `result.at_rounding`:
    residuals of rounding size make any F large, SYNTHETIC noise-free spectra F ≈ 400)."""
    exactly = on if exactly is None else exactly
    flagged = np.zeros(len(layout.shared), bool) if flagged is None else np.asarray(flagged, bool)
    notes = []
    if not converged:
        notes.append(f"the global fit did not converge in {steps} steps; raise max_steps or check the model")
    for group in () if null is None else null.shared_groups:
        notes.append("shared " + unidentified_group_note(group, null.shared_ratio))
    for n, v, e, side, at, at_exactly, in_group in zip(layout.shared, value.tolist(), stderr.tolist(), np.asarray(sides).tolist(), np.asarray(on).tolist(), np.asarray(exactly).tolist(), flagged.tolist()):
        if side:
            i = table.names.index(n)
            bound, where = float((table.upper if side > 0 else table.lower)[i]), "upper" if side > 0 else "lower"
            notes.append("shared " + (bound_note(n, bound, where, unit=table.units[i]) if at_exactly else bound_note(n, bound, where, value=v, stderr=e, unit=table.units[i], on=bool(at))))
        elif undetermined(v, e) and not in_group:
            relative = abs(e / v) if math.isfinite(e) else math.inf
            notes.append(f"shared {n} has " + (f"a relative standard error of {format_relative_error(relative)}" if math.isfinite(relative) else "no finite standard error") + ": the data do not determine it")
    if math.isfinite(p) and p < SHARING_P_LIMIT and not exact:
        notes.append(
            f"the spectra disagree with sharing {', '.join(layout.shared)} over {', '.join(layout.over)}: independent fits are better "
            f"(F = {f:.3g}, p = {p:.2g}, ΔAIC = {delta_aic:+.1f}); the shared values are a compromise"
        )
    return tuple(notes)


def _result_dataset(circuit, data, table, layout: SharedLayout, extra, keep_shape, over_shape, *, values, stderr, linearised_stderr, chi2, z_model, sides, cov_full, corr_full,
                    shared_value, shared_stderr, shared_linearised_stderr, corr_shared, joint, stats, spectrum_notes, group_notes, weighting, null_groups=None):
    """The result's Dataset (the variables of `BatchFitResult` plus the shared ones, and as its
    attribute ``unidentified_groups`` each spectrum's ``null_groups`` (flat order) that has any,
    keyed as a batch's), and its warnings keyed as a batch fit's (`notes.Note`s, as made, with
    their tags: `batch.batch_with_warnings`)."""
    names = table.names
    n_freq = data.sizes["frequency"]
    grouped = (*layout.keep, *layout.over)
    shape = (*keep_shape, *over_shape)
    n_groups, m = values.shape[:2]

    def spectra(a, tail=()):
        """(G, M, *tail) → an array over the data's extra dims (in their order) and tail."""
        da = xr.DataArray(np.asarray(a).reshape((*shape, *np.shape(a)[2:])), dims=(*grouped, *tail))
        return da.transpose(*extra, *tail)

    def groups(a, tail=()):
        return (*layout.keep, *tail), np.asarray(a).reshape((*keep_shape, *np.shape(a)[1:]))

    free_names = list(table.free_names)
    at_bound = np.zeros(values.shape, bool)
    at_bound[..., table.free_index] = sides.reshape(n_groups, m, -1) != 0
    z_data = data["Z"].transpose(*grouped, "frequency").values.reshape(n_groups, m, n_freq)
    with np.errstate(all="ignore"):
        rms_rel = np.sqrt(np.mean(np.abs((z_model - z_data) / np.abs(z_data)) ** 2, axis=-1))
    k = len(free_names)
    aic, bic = information_criteria(chi2, 2 * n_freq, k)
    converged = np.repeat(joint["converged"][:, None], m, axis=1).astype(bool)
    steps = np.repeat(joint["steps"][:, None], m, axis=1).astype(np.int64)
    variables = {
        "value": spectra(values, ("param",)).transpose("param", *extra),
        "stderr": spectra(stderr, ("param",)).transpose("param", *extra).assign_attrs(note=STDERR_NOTE),
        "linearised_stderr": spectra(linearised_stderr, ("param",)).transpose("param", *extra).assign_attrs(long_name=LINEARISED_STDERR_NAME),
        "fixed": ("param", table.fixed),
        "lower": ("param", table.lower, {"long_name": "the fit's lower bound of each parameter (natural, or the user's bounds=)"}),
        "upper": ("param", table.upper, {"long_name": "the fit's upper bound of each parameter (natural, or the user's bounds=)"}),
        "at_bound": spectra(at_bound, ("param",)).transpose("param", *extra),
        "chi2": spectra(chi2),
        "chi2_red": spectra(chi2 / (2 * n_freq - k) if 2 * n_freq > k else np.full(chi2.shape, math.nan)),
        "aic": spectra(aic),
        "bic": spectra(bic),
        "rms_rel": spectra(rms_rel),
        "converged": spectra(converged),
        "n_evaluations": spectra(steps),
        "Z": spectra(z_data, ("frequency",)).assign_attrs(units="ohm"),
        "Z_model": spectra(z_model, ("frequency",)).assign_attrs(units="ohm"),
        "is_shared": ("param", np.array([n in layout.shared for n in names])),
        "covariance": spectra(cov_full, ("free_param", "free_param_2")),
        "correlation": spectra(corr_full, ("free_param", "free_param_2")),
        "shared_value": groups(shared_value, ("shared_param",)),
        "shared_stderr": groups(shared_stderr, ("shared_param",)),
        "shared_linearised_stderr": groups(shared_linearised_stderr, ("shared_param",)),
        "shared_correlation": groups(corr_shared, ("shared_param", "shared_param_2")),
        **{key: groups(v) for key, v in stats.items()},
    }
    variables = {key: (v.variable if isinstance(v, xr.DataArray) else v) for key, v in variables.items()}
    coords = {d: data[d].values for d in extra if d in data.coords}
    ds = xr.Dataset(
        variables,
        coords={"param": list(names), "free_param": free_names, "free_param_2": free_names, "shared_param": list(layout.shared), "shared_param_2": list(layout.shared),
                "frequency": ("frequency", np.asarray(data["frequency"].values, float), {"units": "Hz"}), **coords},
        attrs={"model": str(circuit), "weighting": weighting, "n_free": k, "shared": ",".join(layout.shared), "over": ",".join(layout.over)},
    )
    labels = {d: [f"{d}={c}" for c in (data[d].values if d in data.coords else range(data.sizes[d]))] for d in extra}
    warnings: dict[str, tuple[str, ...]] = {}
    unidentified: dict[str, list[list[str]]] = {}  # (as a batch's: only the spectra that have any)
    for flat, index in enumerate(np.ndindex(*shape)):
        where = dict(zip(grouped, index))
        key = ", ".join(labels[d][where[d]] for d in extra)
        note = spectrum_notes.get(flat, ())
        if note:
            warnings[key] = tuple(note)
        if null_groups is not None and null_groups[flat]:
            unidentified[key] = [list(g) for g in null_groups[flat]]
    if null_groups is not None:  # (a global fit saved by an older version has none)
        ds.attrs["unidentified_groups"] = unidentified
    for gi, index in enumerate(np.ndindex(*keep_shape)):
        if group_notes[gi]:
            label = ", ".join(labels[d][i] for d, i in zip(layout.keep, index))
            warnings[scope_key(layout.over, label)] = group_notes[gi]
    return ds, warnings
