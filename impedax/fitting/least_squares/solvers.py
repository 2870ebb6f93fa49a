"""The compiled least-squares core shared by `fit`, batch fits and candidate fits.

The residual is the real-stacked weighted residual ``[Re(Z_m − Z_d)/w_re, Im(Z_m − Z_d)/w_im]``,
squared once by the solver. Three solvers:

* one spectrum of a circuit compiled by `compile_circuit` (``tree_solver(...)[0]``): optimistix
  Levenberg–Marquardt from one or many starts (``vmap``), the best kept. The circuit's analytic
  Jacobian (`CompiledCircuit.value_and_columns`) is attached to the residual as a custom JVP,
  so each linearisation costs one evaluation of it instead of forward mode through the circuit.
  Tree solvers are compiled per circuit and free set (which parameters are free, and their
  transforms): fixed values are constants of the trace;
* many spectra of one circuit (``tree_solver(...)[1]``, `_make_lanes`): a work queue of
  independent Levenberg–Marquardt problems over a fixed number of ``vmap`` lanes, with the
  same analytic Jacobian. optimistix's solver state holds closures that cannot be swapped
  lane by lane, so this loop runs the compact iteration of `_lm_parts`;
* candidate circuits of one `ProgramLayout` (``program_solver``): the program's arrays travel
  as data, and free parameters are gathered into a vector of length K (padded entries point at
  a dummy slot and have zero Jacobian columns), so one compilation serves every topology and
  free set of the layout (the diagnosis). Warm-started candidate
  fits use ``single_phase=True``: every start runs the `_lm_parts` loop and the best is kept.
"""

from __future__ import annotations

import functools
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import lineax as lx
import numpy as np
import optimistix as optx

from ...circuits import Circuit, ProgramLayout, Registry, compile_circuit
from .order import structural_peaks
from ..parameters import external_of_kind, to_external

__all__ = ["tree_solver", "program_solver", "levenberg_marquardt", "solver_messages", "SCREEN_STEPS"]

SCREEN_STEPS = 40  # Levenberg–Marquardt steps every start gets before the best is refined


def _free_to_full(x_free, args):
    x_ext = jnp.concatenate([args["x_fixed"], jnp.ones((1,))])
    return x_ext.at[args["free_index"]].set(x_free)[:-1]


def _weighted(r, args):
    """Complex residuals (N, ...) → the real-stacked weighted residual (2N, ...)."""
    w_re, w_im = args["inv_w_re"], args["inv_w_im"]
    if r.ndim == 2:
        w_re, w_im = w_re[:, None], w_im[:, None]
    return jnp.concatenate([r.real * w_re, r.imag * w_im])


def _u_to_x(u, args):
    """(x, dx/du) of the elementwise transform to parameter space."""
    return jax.jvp(lambda v: to_external(v, args["lower"], args["upper"], args["kind"]), (u,), (jnp.ones_like(u),))


class Residuals(NamedTuple):
    """The functions a solver needs, of (point, args): the weighted residual at parameters
    x_free or at the unconstrained point u; ``linearize_x`` → (J, r) in parameter space;
    ``normal_u`` → the normal equations (JᵀJ, Jᵀr, ½‖r‖², extra) at u; ``chi2_u`` → ‖r‖²
    (tree circuits only); ``to_x`` → (x_free, all parameters) at u."""

    residual_x: Callable
    residual_u: Callable
    linearize_x: Callable
    normal_u: Callable
    chi2_u: Callable | None
    to_x: Callable


def _residuals(model: Callable):
    """Residual functions of a model by forward-mode differentiation (`Residuals`)."""

    def residual_x(x_free, args):
        return _weighted(model(_free_to_full(x_free, args), args["freq"], args["model_args"]) - args["z"], args)

    def residual_u(u, args):
        return residual_x(to_external(u, args["lower"], args["upper"], args["kind"]), args)

    def forward(residual):
        def linearize(v, args):
            r = residual(v, args)
            return r, r

        return lambda v, args: jax.jacfwd(linearize, has_aux=True)(v, args)

    def normal_u(u, args):
        jac, r = forward(residual_u)(u, args)
        return jac.T @ jac, jac.T @ r, 0.5 * jnp.sum(r**2), (jac, r)  # (J, r) kept: see `_lm_parts`

    def to_x(u, args):
        x_free = to_external(u, args["lower"], args["upper"], args["kind"])
        return x_free, _free_to_full(x_free, args)

    return Residuals(residual_x, residual_u, forward(residual_x), normal_u, None, to_x)


def _tree_residuals(compiled, free: tuple[int, ...], kinds: tuple[int, ...]):
    """As `_residuals` for a compiled circuit whose free parameters (positions ``free``, with
    transform ``kinds``, see `_parameters`) are known when tracing, with the circuit's
    analytic Jacobian (`CompiledCircuit.value_and_columns`); ``residual_u`` carries it as a
    custom JVP, so optimistix's linearisation costs one evaluation of it rather than forward
    mode through the circuit. Also ``chi2_u``, the sum of squares alone, and ``to_x``, the
    parameters of the solver's point u.

    Knowing the free set when tracing, fixed parameters are constants of the trace: no
    gather or scatter by index, no derivative columns for them, one transform formula per
    kind present.
    Re and Im parts are weighted apart and, in what runs under ``vmap`` (``normal_u``,
    ``chi2_u``), never concatenated: XLA's concatenation of the halves costs several times
    the circuit."""
    slot = {i: j for j, i in enumerate(free)}
    n_params = len(compiled.parameter_names)

    def theta(x_free, args):
        """All parameters, by position: the free ones from x_free, the rest from x_fixed."""
        return tuple(x_free[slot[i]] if i in slot else args["x_fixed"][i] for i in range(n_params))

    # free parameters grouped by transform kind: one vector formula per kind present
    groups = [(k, np.flatnonzero(np.asarray(kinds) == k)) for k in sorted(set(kinds))]
    order = np.argsort(np.concatenate([g for _, g in groups])) if kinds else np.zeros(0, int)

    def external(u, args):
        lower, upper = args["lower"], args["upper"]
        if len(groups) == 1:
            return external_of_kind(u, lower, upper, groups[0][0])
        return jnp.concatenate([external_of_kind(u[g], lower[g], upper[g], k) for k, g in groups])[order]

    def u_to_x(u, args):
        return jax.jvp(lambda v: external(v, args), (u,), (jnp.ones_like(u),))

    def impedance(x_free, args):
        return compiled(dict(zip(compiled.parameter_names, theta(x_free, args))), args["freq"])

    def parts_x(x_free, args, dx_du=None):
        """(J_re, J_im) (K, N), parameters first, and (r_re, r_im) (N,), weighted (and by
        u, given dx/du)."""
        z, columns = compiled.value_and_columns(theta(x_free, args), args["freq"], free)
        w_re, w_im = args["inv_w_re"], args["inv_w_im"]
        jac = jnp.stack(columns) if dx_du is None else jnp.stack(columns) * dx_du[:, None]
        r = z - args["z"]
        return jac.real * w_re[None, :], jac.imag * w_im[None, :], r.real * w_re, r.imag * w_im

    def linearize_x(x_free, args):
        j_re, j_im, r_re, r_im = parts_x(x_free, args)
        return jnp.concatenate([j_re, j_im], axis=1).T, jnp.concatenate([r_re, r_im])

    def normal_u(u, args):
        x, dx_du = u_to_x(u, args)
        j_re, j_im, r_re, r_im = parts_x(x, args, dx_du)
        # parameters-first halves and two products: under vmap, XLA runs this JᵀJ faster than
        # any layout with Re and Im joined (measured, benchmarks/README.md)
        a = j_re @ j_re.T + j_im @ j_im.T
        return a, j_re @ r_re + j_im @ r_im, 0.5 * (jnp.sum(r_re**2) + jnp.sum(r_im**2)), ()

    def residual_x(x_free, args):
        return _weighted(impedance(x_free, args) - args["z"], args)

    def chi2_u(u, args):
        r = impedance(external(u, args), args) - args["z"]
        return jnp.sum((r.real * args["inv_w_re"]) ** 2) + jnp.sum((r.imag * args["inv_w_im"]) ** 2)

    @jax.custom_jvp
    def residual_u(u, args):
        return residual_x(external(u, args), args)

    @residual_u.defjvp
    def _residual_u_jvp(primals, tangents):
        u, args = primals
        x, dx_du = u_to_x(u, args)
        j_re, j_im, r_re, r_im = parts_x(x, args, dx_du)
        # J·t from the (K, N) halves: no (2N, K) copy of J (XLA would fuse the circuit into it
        # and evaluate every element twice, once for each half)
        return jnp.concatenate([r_re, r_im]), jnp.concatenate([tangents[0] @ j_re, tangents[0] @ j_im])

    def to_x(u, args):
        x_free = external(u, args)
        return x_free, jnp.stack(theta(x_free, args))

    return Residuals(residual_x, residual_u, linearize_x, normal_u, chi2_u, to_x)


UNROLLED_SOLVE_MAX = 12  # up to this many free parameters the damped system is solved inline


def _solve_damped(a, b):
    """x with a·x = b for the damped normal matrix a = JᵀJ + λD (symmetric positive definite).
    Small systems by a Cholesky factorisation written out in scalar operations: under
    ``vmap`` over solver lanes they fuse into a few vector loops, where a LAPACK call per
    matrix costs more than the whole factorisation. A factorisation that breaks down (rounding
    in a near-singular system) gives non-finite x, which the caller treats as a failed step."""
    k = a.shape[-1]
    if k > UNROLLED_SOLVE_MAX:
        return jnp.linalg.solve(a, b)
    low = [[None] * k for _ in range(k)]
    for j in range(k):
        low[j][j] = jnp.sqrt(a[j, j] - sum(low[j][m] ** 2 for m in range(j)))
        for i in range(j + 1, k):
            low[i][j] = (a[i, j] - sum(low[i][m] * low[j][m] for m in range(j))) / low[j][j]
    y = [None] * k
    for i in range(k):
        y[i] = (b[i] - sum(low[i][m] * y[m] for m in range(i))) / low[i][i]
    x = [None] * k
    for i in reversed(range(k)):
        x[i] = (y[i] - sum(low[m][i] * x[m] for m in range(i + 1, k))) / low[i][i]
    return jnp.stack(x)


def _lm_parts(normal: Callable, rtol: float = 1e-8, xtol: float = 1e-10, extra_init: Callable | None = None, inline_solve: bool = False):
    """(init, step) of a dense Levenberg–Marquardt iteration for ½‖r(u)‖² with Marquardt
    scaling and Nielsen's damping update (Madsen, Nielsen & Tingleff 2004, alg. 3.16);
    ``normal(u, args) -> (JᵀJ, Jᵀr, ½‖r‖², extra)``; ``extra`` (``()`` or arrays whose shapes
    ``extra_init(u0, args)`` gives) is kept with the accepted point, e.g. (J, r) for a model
    whose Jacobian is expensive to trace again at the end. ``inline_solve``: the damped
    system by `_solve_damped` (faster per step under ``vmap``, slower to compile).

    Each step linearises once at the trial point and keeps it only when the cost falls (the
    state holds JᵀJ and Jᵀr, not J), so the model's Jacobian is traced once. A start is done
    when an accepted step lowers the cost by less than ``rtol`` relatively, or the step is
    below ``xtol``.
    """

    def init(u0, args):
        k = u0.shape[0]
        return {
            "u": u0, "a": jnp.zeros((k, k)), "g": jnp.zeros(k), "cost": jnp.asarray(jnp.inf), "u_try": u0, "pred": jnp.asarray(1.0),
            "lam": jnp.asarray(1e-3), "nu": jnp.asarray(2.0), "i": jnp.asarray(0), "done": jnp.asarray(False), "dmax": jnp.zeros(k),
            "extra": () if extra_init is None else extra_init(u0, args),
        }

    def step(s, args):
        a_try, g_try, c_try, extra_try = normal(s["u_try"], args)
        c_try = jnp.where(jnp.isfinite(c_try) & jnp.all(jnp.isfinite(a_try)), c_try, jnp.inf)
        first = s["i"] == 0
        gain = s["cost"] - c_try
        ok = first | ((gain > 0) & jnp.isfinite(c_try))
        rho = gain / jnp.where(s["pred"] > 0, s["pred"], 1.0)
        lam = jnp.where(first, s["lam"], jnp.where(ok, s["lam"] * jnp.maximum(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3), s["lam"] * s["nu"]))
        nu = jnp.where(ok, 2.0, s["nu"] * 2.0)
        keep = lambda new, old: jnp.where(ok, new, old)  # noqa: E731
        u, cost = keep(s["u_try"], s["u"]), keep(c_try, s["cost"])
        a, g = keep(a_try, s["a"]), keep(g_try, s["g"])
        extra = jax.tree_util.tree_map(keep, extra_try, s["extra"])
        dmax = jnp.maximum(jnp.diag(a), s["dmax"])
        d = jnp.where(dmax > 0, dmax, 1.0)  # padded parameters have zero columns
        damped = a + lam * jnp.diag(d)
        delta = -(_solve_damped(damped, g) if inline_solve else jnp.linalg.solve(damped, g))
        solved = jnp.all(jnp.isfinite(delta))  # if not, the next trial is u itself: rejected, more damping
        delta = jnp.where(solved, delta, 0.0)
        pred = 0.5 * jnp.dot(delta, lam * d * delta - g)
        flat = ~first & ok & (gain <= rtol * s["cost"])
        tiny = solved & (jnp.sqrt(jnp.sum(delta**2)) <= xtol * (jnp.sqrt(jnp.sum(u**2)) + xtol))
        done = s["done"] | flat | tiny | (lam > 1e15) | ~jnp.isfinite(cost)
        new = {"u": u, "a": a, "g": g, "cost": cost, "u_try": u + delta, "pred": pred, "lam": lam, "nu": nu, "i": s["i"] + 1, "done": done, "dmax": dmax, "extra": extra}
        return jax.tree_util.tree_map(lambda a_, b_: jnp.where(s["done"], b_, a_), new, s)  # a finished start stays put

    return init, step


def levenberg_marquardt(normal: Callable, u0, args, max_steps, *, rtol: float = 1e-8, xtol: float = 1e-10, inline_solve: bool = True):
    """Minimise ½‖r(u)‖² from ``u0`` (see `_lm_parts`; by default the iteration of one lane
    of `_make_lanes`); ``max_steps`` may be traced. Returns (u, chi² = ‖r‖², converged,
    iterations)."""
    init, step = _lm_parts(normal, rtol, xtol, inline_solve=inline_solve)
    s = jax.lax.while_loop(lambda s: (s["i"] < max_steps) & ~s["done"], lambda s: step(s, args), init(u0, args))
    return s["u"], 2.0 * s["cost"], s["done"], s["i"]


_MAX_STEPS_CODE = int(optx.RESULTS.max_steps_reached._value)
MIN_STEPS = 8


def _finish(u, args, residuals: Residuals, peaks=None):
    """Solver outputs at the solution u: parameters, the Jacobian in parameter space (for
    the covariance), chi², the model's impedance and, given ``peaks``
    (`_order.structural_peaks`), the peak frequencies that order exchangeable blocks."""
    x_free, x = residuals.to_x(u, args)
    jac, r = residuals.linearize_x(x_free, args)
    n = args["z"].shape[0]
    chi2 = jnp.sum(r**2)
    out = {
        "x": x,
        "x_free": x_free,
        "chi2": jnp.where(jnp.isfinite(chi2), chi2, jnp.inf),
        "jacobian": jac,
        "z_model": args["z"] + r[:n] / args["inv_w_re"] + 1j * (r[n:] / args["inv_w_im"]),
    }
    if peaks is not None:
        out["peaks"] = peaks(x, args["freq"])
    return out


def _make_single_phase_batch(residuals, max_steps: int):
    """A solver for C candidates × S starts at once. All starts iterate in one loop that ends
    when, for every candidate, its best start so far has converged and no unfinished start is
    better (or at the step limit): stragglers in slow valleys do not hold the batch up."""
    normal_u = residuals.normal_u

    def extra_init(u0, args):
        m = args["z"].shape[0] * 2
        return jnp.zeros((m, u0.shape[0])), jnp.zeros(m)

    init, step = _lm_parts(normal_u, extra_init=extra_init)
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
        return jax.vmap(_best)(s, args)

    def _best(s, args):
        chi2s = 2.0 * s["cost"]
        best = jnp.argmin(jnp.where(jnp.isfinite(chi2s), chi2s, jnp.inf))
        u = s["u"][best]
        jac_u, r = (e[best] for e in s["extra"])
        x_free, dx_du = _u_to_x(u, args)
        # chain rule back to parameter space, dr/dx = (dr/du)/(dx/du): no second trace of the
        # model's Jacobian, which would double this solver's compile time
        jac = jnp.where(dx_du[None, :] != 0, jac_u / jnp.where(dx_du == 0, 1.0, dx_du)[None, :], 0.0)
        n = args["z"].shape[0]
        return {
            "x": _free_to_full(x_free, args),
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


def _make(residuals, max_steps: int, peaks=None):
    """optimistix Levenberg–Marquardt from one or many starts: every start for
    `SCREEN_STEPS` steps together, then the best to convergence."""
    # steps below 1e-6 relative (1e-9 absolute), far inside any stderr: on the benchmark's
    # spectra the values agree with a 1e-7 stop to 2e-10 relative, with 8 % fewer steps (the
    # last ones only wander at that level). The damped step (JᵀJ + λI)δ = −Jᵀr is solved by
    # Cholesky on the normal equations (K×K): positive definite for λ > 0 and cheaper than the
    # default QR of the stacked (2N + K)×K system
    solver = optx.LevenbergMarquardt(rtol=1e-6, atol=1e-9, linear_solver=lx.Normal(lx.Cholesky()))
    residual_u = residuals.residual_u

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
        u, _, code, steps = solve_one(u_best, args, max_steps)
        out = _finish(u, args, residuals, peaks)
        out.update(code=code, steps=steps, chi2_starts=chi2s, steps_total=jnp.sum(steps1) + steps)
        return out

    return solve


# spectra of one batch share frequencies, free set and bounds; data and fixed values vary
SPECTRUM_KEYS = ("z", "inv_w_re", "inv_w_im", "x_fixed")


@functools.lru_cache(maxsize=128)
def tree_solver(circuit: Circuit, registry: Registry, max_steps: int, free: tuple[int, ...], kinds: tuple[int, ...]):
    """Jitted solvers for one circuit and free set (positions ``free`` with transform
    ``kinds``, `ParameterTable.free_structure`; cached): ``single(u0s, args)`` runs optimistix
    from one or many starts (`_make`); ``lanes(n_lanes)`` gives the lane solver of
    `_make_lanes` for batches, ``finish(u, spectrum, rows, shared)`` the outputs at solutions
    and ``chi2(...)`` the weighted chi² at points u (both vmapped over points)."""
    compiled = compile_circuit(circuit, registry)
    residuals = _tree_residuals(compiled, free, kinds)
    peaks = structural_peaks(compiled.circuit, compiled.parameter_names, registry)

    def per_spectrum(fn):
        """``fn(u, args)`` vmapped over points u (C, K) of the spectra rows[spectrum]."""

        def mapped(u, spectrum, rows, shared):
            return jax.vmap(lambda u_i, s: fn(u_i, {**shared, **jax.tree_util.tree_map(lambda a: a[s], rows)}))(u, spectrum)

        return jax.jit(mapped)

    finish = per_spectrum(lambda u, args: _finish(u, args, residuals, peaks))
    chi2 = per_spectrum(residuals.chi2_u)

    lanes = functools.lru_cache(maxsize=4)(lambda n_lanes: jax.jit(_make_lanes(residuals.normal_u, n_lanes), static_argnames="drain"))
    return _one_transfer(_make(residuals, max_steps, peaks)), lanes, finish, chi2


def _one_transfer(solve: Callable):
    """``solve(u0s, args) -> dict of arrays``, jitted to return them packed in one float64
    array, and unpacked on the host: one device-to-host copy per fit instead of one per output
    (each costs tens of µs, as much as several solver steps). Returns ``run(u0s, args)``
    giving a `PendingOutputs`; its ``fetch()`` waits and returns the dict in numpy."""
    layouts: dict = {}

    def packed(u0s, args):
        out = {k: v for k, v in solve(u0s, args).items() if k != "x_free"}
        layout, at = [], 0
        for name, v in out.items():
            size = v.size * (2 if jnp.iscomplexobj(v) else 1)
            layout.append((name, at, at + size, v.shape, np.dtype(v.dtype)))
            at += size
        layouts[(u0s.shape, args["z"].shape)] = tuple(layout)
        parts = [jnp.stack([v.real, v.imag], axis=-1) if jnp.iscomplexobj(v) else v for v in out.values()]
        return jnp.concatenate([p.astype(jnp.float64).ravel() for p in parts])

    jitted = jax.jit(packed)

    def run(u0s, args):
        flat = jitted(u0s, args)  # traced before it returns: the layout of these shapes is known
        return PendingOutputs(flat, layouts[(u0s.shape, args["z"].shape)])

    return run


class PendingOutputs(NamedTuple):
    """Solver outputs still on the device, packed by `_one_transfer`."""

    flat: jax.Array
    layout: tuple  # (name, start, stop, shape, dtype) per output

    def fetch(self) -> dict:
        flat = np.asarray(self.flat)
        out = {}
        for name, start, stop, shape, dtype in self.layout:
            part = flat[start:stop]
            out[name] = part.view(np.complex128).reshape(shape) if dtype.kind == "c" else part.reshape(shape).astype(dtype, copy=False)
        return out


def _make_lanes(normal_u: Callable, n_lanes: int):
    """A work-queue Levenberg–Marquardt solver for many independent problems (spectra, or
    spectrum × start pairs). ``n_lanes`` problems iterate side by side (``vmap`` of one
    `_lm_parts` step); when a lane's problem converges or spends its step budget, the result
    is written out and the lane takes the next problem from the queue. Every lane does useful
    work at every step, so a batch costs about its total number of steps, not its size times
    the slowest problem's count (what a plain ``vmap`` of a solver loop costs).

    ``solve(u0 (C, K), spectrum (C,), budget (C,), n_problems, rows, shared, drain)``: problem
    p starts at ``u0[p]`` on the data of row ``spectrum[p]`` of ``rows`` (dict of arrays over
    spectra; ``shared`` holds what all have in common) and may take ``budget[p]`` steps; only
    the first ``n_problems`` are solved (the rest is padding, so one compilation serves any
    count). With ``drain=False`` the loop stops once the queue is empty and at most
    ``n_lanes // 8`` lanes still run: their problems come back unfinished (``done`` False),
    to be continued on fewer lanes, so a few slow problems do not keep every lane busy.
    Returns (u, chi², done, steps) over the C problems.
    """
    init, step = _lm_parts(normal_u, inline_solve=True)
    lane_init = jax.vmap(init, in_axes=(0, None))

    def solve(u0, spectrum, budget, n_problems, rows, shared, *, drain):
        capacity = u0.shape[0]
        lane_step = jax.vmap(lambda s, row: step(s, {**shared, **row}))

        def load(pid):
            clipped = jnp.minimum(pid, capacity - 1)
            row = jax.tree_util.tree_map(lambda a: a[spectrum[clipped]], rows)
            return lane_init(u0[clipped], None), row, budget[clipped]

        def select(mask, new, old):
            return jax.tree_util.tree_map(lambda a, b: jnp.where(mask.reshape(mask.shape + (1,) * (a.ndim - 1)), a, b), new, old)

        def write(out, pid, s, done):
            sink = jnp.where(pid < n_problems, pid, capacity)  # row `capacity` absorbs idle lanes
            return {
                "u": out["u"].at[sink].set(s["u"]),
                "chi2": out["chi2"].at[sink].set(2.0 * s["cost"]),
                "done": out["done"].at[sink].set(done),
                "steps": out["steps"].at[sink].set(s["i"]),
            }

        def running(carry):
            _, pid, _, _, next_pid, _ = carry
            active = pid < n_problems
            few = jnp.sum(active) <= n_lanes // 8
            return jnp.any(active) & (drain | (next_pid < n_problems) | ~few)

        def body(carry):
            s, pid, row, limit, next_pid, out = carry
            s = lane_step(s, row)
            finished = (pid < n_problems) & (s["done"] | (s["i"] >= limit))
            out = write(out, jnp.where(finished, pid, capacity), s, s["done"])
            new_pid = next_pid + jnp.cumsum(finished) - 1
            take = finished & (new_pid < n_problems)
            pid = jnp.where(finished, jnp.where(take, new_pid, capacity), pid)
            fresh, fresh_row, fresh_limit = load(pid)
            s = select(take, fresh, s)
            s["done"] = s["done"] | (finished & ~take)  # an idle lane stays put
            return s, pid, select(take, fresh_row, row), jnp.where(take, fresh_limit, limit), next_pid + jnp.sum(take), out

        pid = jnp.where(jnp.arange(n_lanes) < n_problems, jnp.arange(n_lanes), capacity)
        s, row, limit = load(pid)
        s["done"] = pid >= n_problems
        out = {
            "u": jnp.concatenate([u0, u0[:1]]),
            "chi2": jnp.full(capacity + 1, jnp.inf),
            "done": jnp.zeros(capacity + 1, bool),
            "steps": jnp.zeros(capacity + 1, jnp.int64),
        }
        carry = (s, pid, row, limit, jnp.minimum(n_lanes, n_problems), out)
        s, pid, _, _, _, out = jax.lax.while_loop(running, body, carry)
        out = write(out, pid, s, jnp.zeros(n_lanes, bool))  # problems still open when stopped early
        return tuple(out[k][:capacity] for k in ("u", "chi2", "done", "steps"))

    return solve


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

    residuals = _residuals(model)
    if single_phase:
        batch = jax.jit(_make_single_phase_batch(residuals, max_steps))
        return None, batch
    solve = _make(residuals, max_steps)
    # candidates differ in program and in everything else: vmap over all of args
    return jax.jit(solve), jax.jit(jax.vmap(solve))


def solver_messages(code: int) -> str:
    """Human text for an optimistix result code."""
    if code == 0:
        return ""
    text = optx.RESULTS._index_to_message[int(code)]
    return " ".join(text.split("\n\n")[0].split())
