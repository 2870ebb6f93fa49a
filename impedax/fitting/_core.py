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
"""

from __future__ import annotations

import functools
from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx

from ..circuits import Circuit, ProgramLayout, Registry, compile_circuit, evaluate_program
from ._parameters import to_external

__all__ = ["tree_solver", "program_solver", "solver_messages", "SCREEN_STEPS"]

SCREEN_STEPS = 40  # Levenberg–Marquardt steps every start gets before the best is refined


def _expand(u, args):
    """Unconstrained free vector (K,) → full parameter vector (P,)."""
    x_free = to_external(u, args["lower"], args["upper"], args["kind"])
    x_ext = jnp.concatenate([args["x_fixed"], jnp.ones((1,))])
    return x_ext.at[args["free_index"]].set(x_free)[:-1]


def _make(model: Callable, max_steps: int):
    solver = optx.LevenbergMarquardt(rtol=1e-9, atol=1e-12)

    def residual_x(x_free, args):
        x_ext = jnp.concatenate([args["x_fixed"], jnp.ones((1,))])
        x = x_ext.at[args["free_index"]].set(x_free)[:-1]
        r = model(x, args["freq"], args["model_args"]) - args["z"]
        return jnp.concatenate([r.real * args["inv_w_re"], r.imag * args["inv_w_im"]])

    def residual_u(u, args):
        return residual_x(to_external(u, args["lower"], args["upper"], args["kind"]), args)

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


@functools.lru_cache(maxsize=16)
def program_solver(layout: ProgramLayout, max_steps: int):
    """(single, batched) jitted solvers for any circuit of ``layout``; the program's arrays
    are passed in ``args["model_args"]`` and its (S, 4) parameters flattened to P = 4S."""

    def model(x, freq, program):
        return evaluate_program(program, x.reshape(layout.n_slots, -1), freq, layout=layout)

    solve = _make(model, max_steps)
    # candidates differ in program and in everything else: vmap over all of args
    return jax.jit(solve), jax.jit(jax.vmap(solve))


def solver_messages(code: int) -> str:
    """Human text for an optimistix result code."""
    if code == 0:
        return ""
    text = optx.RESULTS._index_to_message[int(code)]
    return " ".join(text.split("\n\n")[0].split())
