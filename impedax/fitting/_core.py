"""The compiled least-squares core shared by `fit`, batch fits and candidate fits.

One jitted function per model form runs a Levenberg–Marquardt solve (optimistix) from many
starts at once (``vmap``) and returns the best. The residual is the real-stacked weighted
residual ``[Re(Z_m − Z_d)/w_re, Im(Z_m − Z_d)/w_im]``; optimistix squares it once.

Free parameters are gathered into a vector of length K (padded entries point at a dummy slot
and have zero Jacobian columns), so fits with the same K, start count and frequency count
share one compilation. Two model forms:

* ``tree``: a circuit compiled by `compile_circuit` (parameters in ``parameter_names`` order);
* ``program``: a `CircuitProgram` whose arrays travel as data, so one compilation serves every
  topology of a `ProgramLayout` (used by the diagnosis to fit many candidates).

Warm-started candidate fits (the diagnosis) use ``program_solver(..., single_phase=True)``:
every start runs one compact Levenberg–Marquardt loop (`levenberg_marquardt`, one
linearisation per iteration, traced once) and the best is kept. Without the screening phase
and with a single trace of the model's Jacobian it compiles several times faster.
"""

from __future__ import annotations

import functools
from typing import Callable

import jax
import jax.numpy as jnp
import optimistix as optx

from ..circuits import Circuit, ProgramLayout, Registry, compile_circuit
from ._parameters import to_external

__all__ = ["tree_solver", "program_solver", "levenberg_marquardt", "solver_messages", "SCREEN_STEPS"]

SCREEN_STEPS = 40  # Levenberg–Marquardt steps every start gets before the best is refined


def _expand(u, args):
    """Unconstrained free vector (K,) → full parameter vector (P,)."""
    x_free = to_external(u, args["lower"], args["upper"], args["kind"])
    x_ext = jnp.concatenate([args["x_fixed"], jnp.ones((1,))])
    return x_ext.at[args["free_index"]].set(x_free)[:-1]


def _residuals(model: Callable):
    def residual_x(x_free, args):
        x_ext = jnp.concatenate([args["x_fixed"], jnp.ones((1,))])
        x = x_ext.at[args["free_index"]].set(x_free)[:-1]
        r = model(x, args["freq"], args["model_args"]) - args["z"]
        return jnp.concatenate([r.real * args["inv_w_re"], r.imag * args["inv_w_im"]])

    def residual_u(u, args):
        return residual_x(to_external(u, args["lower"], args["upper"], args["kind"]), args)

    return residual_x, residual_u


def _lm_parts(residual: Callable, rtol: float = 1e-8, xtol: float = 1e-10):
    """(init, step) of a dense Levenberg–Marquardt iteration for ½‖residual(u, args)‖² with
    Marquardt scaling and Nielsen's damping update (Madsen, Nielsen & Tingleff 2004, alg. 3.16).

    Each step linearises once at the trial point (``jacfwd``) and keeps it only when the cost
    falls, so the model's Jacobian is traced once. A start is done when an accepted step lowers
    the cost by less than ``rtol`` relatively, or the step is below ``xtol``.
    """

    def with_aux(u, args):
        r = residual(u, args)
        return r, r

    def init(u0, args):
        m = jax.eval_shape(residual, u0, args).shape[0]
        k = u0.shape[0]
        return {
            "u": u0, "jac": jnp.zeros((m, k)), "r": jnp.zeros(m), "cost": jnp.asarray(jnp.inf), "u_try": u0, "pred": jnp.asarray(1.0),
            "lam": jnp.asarray(1e-3), "nu": jnp.asarray(2.0), "i": jnp.asarray(0), "done": jnp.asarray(False), "dmax": jnp.zeros(k),
        }

    def step(s, args):
        j_try, r_try = jax.jacfwd(with_aux, has_aux=True)(s["u_try"], args)
        c_try = 0.5 * jnp.sum(r_try**2)
        c_try = jnp.where(jnp.isfinite(c_try) & jnp.all(jnp.isfinite(j_try)), c_try, jnp.inf)
        first = s["i"] == 0
        gain = s["cost"] - c_try
        ok = first | ((gain > 0) & jnp.isfinite(c_try))
        rho = gain / jnp.where(s["pred"] > 0, s["pred"], 1.0)
        lam = jnp.where(first, s["lam"], jnp.where(ok, s["lam"] * jnp.maximum(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3), s["lam"] * s["nu"]))
        nu = jnp.where(ok, 2.0, s["nu"] * 2.0)
        keep = lambda new, old: jnp.where(ok, new, old)  # noqa: E731
        u, jac, r, cost = keep(s["u_try"], s["u"]), keep(j_try, s["jac"]), keep(r_try, s["r"]), keep(c_try, s["cost"])
        a = jac.T @ jac
        g = jac.T @ r
        dmax = jnp.maximum(jnp.diag(a), s["dmax"])
        d = jnp.where(dmax > 0, dmax, 1.0)  # padded parameters have zero columns
        delta = -jnp.linalg.solve(a + lam * jnp.diag(d), g)
        delta = jnp.where(jnp.isfinite(delta), delta, 0.0)
        pred = 0.5 * jnp.dot(delta, lam * d * delta - g)
        flat = ~first & ok & (gain <= rtol * s["cost"])
        tiny = jnp.sqrt(jnp.sum(delta**2)) <= xtol * (jnp.sqrt(jnp.sum(u**2)) + xtol)
        done = s["done"] | flat | tiny | (lam > 1e15) | ~jnp.isfinite(cost)
        new = {"u": u, "jac": jac, "r": r, "cost": cost, "u_try": u + delta, "pred": pred, "lam": lam, "nu": nu, "i": s["i"] + 1, "done": done, "dmax": dmax}
        return jax.tree_util.tree_map(lambda a_, b_: jnp.where(s["done"], b_, a_), new, s)  # a finished start stays put

    return init, step


def levenberg_marquardt(residual: Callable, u0, args, max_steps, *, rtol: float = 1e-8, xtol: float = 1e-10):
    """Minimise ½‖residual(u, args)‖² from ``u0`` (see `_lm_parts`); ``max_steps`` may be
    traced. Returns (u, chi² = ‖r‖², converged, iterations, J(u), r(u))."""
    init, step = _lm_parts(residual, rtol, xtol)
    s = jax.lax.while_loop(lambda s: (s["i"] < max_steps) & ~s["done"], lambda s: step(s, args), init(u0, args))
    return s["u"], 2.0 * s["cost"], s["done"], s["i"], s["jac"], s["r"]


_MAX_STEPS_CODE = int(optx.RESULTS.max_steps_reached._value)
MIN_STEPS = 8


def _make_single_phase_batch(model: Callable, max_steps: int):
    """A solver for C candidates × S starts at once. All starts iterate in one loop that ends
    when, for every candidate, its best start so far has converged and no unfinished start is
    better (or at the step limit): stragglers in slow valleys do not hold the batch up."""
    _, residual_u = _residuals(model)
    init, step = _lm_parts(residual_u)
    per_start = jax.vmap(step, in_axes=(0, None))
    batch_step = jax.vmap(per_start, in_axes=(0, 0))

    def settled(s):
        cost = jnp.where(jnp.isfinite(s["cost"]), s["cost"], jnp.inf)
        best_done = jnp.min(jnp.where(s["done"], cost, jnp.inf), axis=1)
        best_open = jnp.min(jnp.where(s["done"], jnp.inf, cost), axis=1)
        return jnp.all(s["done"].all(axis=1) | (best_done <= best_open))

    def solve_batch(u0s, args):
        limit = jnp.minimum(args["max_steps"][0], max_steps)
        s0 = jax.vmap(jax.vmap(init, in_axes=(0, None)), in_axes=(0, 0))(u0s, args)
        s = jax.lax.while_loop(lambda s: (s["i"].max() < limit) & ((s["i"].max() < MIN_STEPS) | ~settled(s)), lambda s: batch_step(s, args), s0)
        return jax.vmap(_finish)(s, args)

    def _finish(s, args):
        chi2s = 2.0 * s["cost"]
        best = jnp.argmin(jnp.where(jnp.isfinite(chi2s), chi2s, jnp.inf))
        u, r = s["u"][best], s["r"][best]
        x_free = to_external(u, args["lower"], args["upper"], args["kind"])
        # chain rule back to parameter space: dr/dx = dr/du / (dx/du) (elementwise transform)
        dx_du = jax.jvp(lambda v: to_external(v, args["lower"], args["upper"], args["kind"]), (u,), (jnp.ones_like(u),))[1]
        jac = jnp.where(dx_du[None, :] != 0, s["jac"][best] / jnp.where(dx_du == 0, 1.0, dx_du)[None, :], 0.0)
        n = args["z"].shape[0]
        return {
            "x": _expand(u, args),
            "x_free": x_free,
            "chi2": chi2s[best],
            "code": jnp.where(s["done"][best], 0, _MAX_STEPS_CODE),
            "steps": s["i"][best],
            "chi2_starts": chi2s,
            "steps_total": jnp.sum(s["i"]),
            "jacobian": jac,
            "z_model": args["z"] + r[:n] / args["inv_w_re"] + 1j * (r[n:] / args["inv_w_im"]),
        }

    return solve_batch


def _make(model: Callable, max_steps: int):
    solver = optx.LevenbergMarquardt(rtol=1e-9, atol=1e-12)
    residual_x, residual_u = _residuals(model)

    def solve_one(u0, args, steps):
        sol = optx.least_squares(residual_u, solver, u0, args, max_steps=steps, throw=False)
        r = residual_u(sol.value, args)
        chi2 = jnp.sum(r**2)
        chi2 = jnp.where(jnp.isfinite(chi2), chi2, jnp.inf)
        return sol.value, chi2, sol.result._value, sol.stats["num_steps"]

    def solve(u0s, args):
        # phase 1: every start for a few steps together (a vmapped loop runs as long as its
        # slowest member, so this is kept short); phase 2: the best one to convergence
        if u0s.shape[0] > 1:
            us, chi2s, _, steps1 = jax.vmap(solve_one, in_axes=(0, None, None))(u0s, args, SCREEN_STEPS)
            u_best = us[jnp.argmin(chi2s)]
        else:
            chi2s, steps1, u_best = jnp.zeros(1), jnp.zeros(1, jnp.int64), u0s[0]
        u, chi2, code, steps = solve_one(u_best, args, max_steps)
        x_free = to_external(u, args["lower"], args["upper"], args["kind"])
        jac = jax.jacfwd(residual_x)(x_free, args)
        x = _expand(u, args)
        return {
            "x": x,
            "x_free": x_free,
            "chi2": chi2,
            "code": code,
            "steps": steps,
            "chi2_starts": chi2s,
            "steps_total": jnp.sum(steps1) + steps,
            "jacobian": jac,
            "z_model": model(x, args["freq"], args["model_args"]),
        }

    return solve


# spectra of one batch share frequencies, free set and bounds; data and fixed values vary
_BATCH_AXES = {"freq": None, "z": 0, "inv_w_re": 0, "inv_w_im": 0, "x_fixed": 0, "free_index": None, "lower": None, "upper": None, "kind": None, "model_args": None}


@functools.lru_cache(maxsize=128)
def tree_solver(circuit: Circuit, registry: Registry, max_steps: int):
    """(single, batched) jitted solvers for one circuit (cached per circuit)."""
    compiled = compile_circuit(circuit, registry)

    def model(x, freq, _model_args):
        return compiled.vector(x, freq)

    solve = _make(model, max_steps)
    return jax.jit(solve), jax.jit(_map_spectra(solve))


def _map_spectra(solve):
    """Batched ``solve`` as a sequential loop inside one compiled program (``lax.map``), not a
    ``vmap``: a vmapped solver loop runs every spectrum for as many steps as the slowest one
    needs and evaluates both branches of each accept/reject, so per spectrum it costs several
    times a lone solve."""

    def batched(u0s, args):
        mapped = {k: v for k, v in args.items() if _BATCH_AXES[k] == 0}
        shared = {k: v for k, v in args.items() if _BATCH_AXES[k] is None}
        return jax.lax.map(lambda item: solve(item[0], {**shared, **item[1]}), (u0s, mapped))

    return batched


def evaluate_program_fast(program, theta, freq, *, layout: ProgramLayout):
    """Same value as `impedax.circuits.evaluate_program`, cheaper inside a solver: every slot's
    admittance is computed once (not once per node), and the node sums are real mask-vector
    products on Re and Im. Complex divisions fall from N·(S+N)·F to (S+2N)·F."""
    omega = (2.0 * jnp.pi * jnp.asarray(freq))[None, :]
    parts = []
    for k, spec in enumerate(layout.registry.specs):
        rows = theta[layout.slots_of(k)]
        if rows.shape[0] == 0:
            continue
        z_k = spec.impedance(omega, *(rows[:, i : i + 1] for i in range(len(spec.parameters))))
        parts.append(jnp.broadcast_to(z_k, (rows.shape[0], omega.shape[1])).astype(jnp.complex128))
    size, n = layout.n_slots, layout.n_nodes
    ones = jnp.ones((n, omega.shape[1]), jnp.complex128)
    z = jnp.concatenate(parts + [ones], axis=0)
    y = jnp.concatenate([1.0 / zp for zp in parts] + [ones], axis=0)
    children, is_parallel = program["children"], program["is_parallel"]
    for k in range(n):
        mask = children[k]
        z_sum = (mask @ z.real) + 1j * (mask @ z.imag)
        y_sum = (mask @ y.real) + 1j * (mask @ y.imag)
        z_node = jnp.where(is_parallel[k], 1.0 / jnp.where(y_sum == 0, 1.0, y_sum), z_sum)
        y_node = jnp.where(is_parallel[k], y_sum, 1.0 / jnp.where(z_sum == 0, 1.0, z_sum))
        z = z.at[size + k].set(z_node)
        y = y.at[size + k].set(y_node)
    return z[program["root"]]


@functools.lru_cache(maxsize=16)
def program_solver(layout: ProgramLayout, max_steps: int, single_phase: bool = False):
    """(single, batched) jitted solvers for any circuit of ``layout``; the program's arrays
    are passed in ``args["model_args"]`` and its (S, 4) parameters flattened to P = 4S.
    ``single_phase``: every start runs `levenberg_marquardt` to the end (for warm starts)."""

    def model(x, freq, program):
        return evaluate_program_fast(program, x.reshape(layout.n_slots, -1), freq, layout=layout)

    if single_phase:
        batch = jax.jit(_make_single_phase_batch(model, max_steps))
        return None, batch
    solve = _make(model, max_steps)
    # candidates differ in program and in everything else: vmap over all of args
    return jax.jit(solve), jax.jit(jax.vmap(solve))


def solver_messages(code: int) -> str:
    """Human text for an optimistix result code."""
    if code == 0:
        return ""
    text = optx.RESULTS._index_to_message[int(code)]
    return " ".join(text.split("\n\n")[0].split())
