"""impedax's own Levenberg–Marquardt iteration, and the work queue that runs many of them.

Every least-squares fit runs it: single fits (`solvers.tree_solver`), batch fits and
candidate fits (`candidates.candidate_solver`), whose lanes swap problems mid-loop. One
iteration and one stopping rule for all, so single and batch fits agree on every flag.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp

__all__ = ["LMState", "lm_iteration", "work_queue", "select_lanes", "solve_damped", "solve_by_elimination", "UNROLLED_SOLVE_MAX"]

UNROLLED_SOLVE_MAX = 12  # up to this many free parameters `solve_damped` factorises in scalar operations


class LMState(NamedTuple):
    """One Levenberg–Marquardt start: the accepted point ``u`` with its normal equations
    (``a`` = JᵀJ, ``g`` = Jᵀr, ``cost`` = ½‖r‖²), the trial point ``u_try`` and the cost
    decrease ``pred`` the linear model predicts for it, the damping ``lam`` and its growth
    factor ``nu``, the step count ``i``, ``done``, the running maximum ``dmax`` of diag(JᵀJ)
    (Marquardt's scaling), ``extra`` kept with the accepted point, and ``scaled``: whether the
    damping uses Marquardt's scaling or the identity (see `lm_iteration`)."""

    u: jax.Array
    a: jax.Array
    g: jax.Array
    cost: jax.Array
    u_try: jax.Array
    pred: jax.Array
    lam: jax.Array
    nu: jax.Array
    i: jax.Array
    done: jax.Array
    dmax: jax.Array
    extra: tuple
    scaled: jax.Array


def solve_damped(a, b):
    """x with a·x = b for the damped normal matrix a = JᵀJ + λD (symmetric positive definite).
    Small systems by a Cholesky factorisation written out in scalar operations: under
    ``vmap`` over solver lanes they fuse into a few vector loops, where a LAPACK call per
    matrix costs more than the whole factorisation. A factorisation that breaks down (rounding
    in a near-singular system) gives non-finite x, which the caller treats as a failed step."""
    k = a.shape[-1]
    if k > UNROLLED_SOLVE_MAX:
        return solve_by_elimination(a, b)
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


def solve_by_elimination(a, b):
    """x with a·x = b for the damped normal matrix a (symmetric positive definite) by
    Gauss–Jordan elimination without pivoting (such matrices need none; Golub & Van Loan
    2013, §4.2): one row operation on the whole system [a | b] per unknown, so the program
    grows with k, not k³ as `solve_damped`'s scalar factorisation. Not LAPACK: a LAPACK call on
    a batch of systems splits the batch over XLA's CPU worker threads and waits for them on a
    worker thread; two devices doing so at once each hold one of a 2-core machine's two
    workers, and the process hangs (a 12-parameter fit with 120 starts, issue 14). A zero
    pivot gives non-finite x, which the caller treats as a failed step."""
    k = a.shape[-1]
    m = jnp.concatenate([a, b[:, None]], axis=1)
    for j in range(k):
        row = m[j] / m[j, j]
        m = (m - m[:, j : j + 1] * row[None, :]).at[j].set(row)
    return m[:, k]


def lm_iteration(normal: Callable, rtol: float = 1e-8, xtol: float = 1e-10, extra_init: Callable | None = None, linear_solve: Callable = solve_by_elimination, scaling: bool = True, trust_region: bool = False, scaled_stop: bool = False):
    """(init, step) of a dense Levenberg–Marquardt iteration for ½‖r(u)‖² with Nielsen's
    damping update (Madsen, Nielsen & Tingleff 2004, alg. 3.16): the damped system is
    (JᵀJ + λD)δ = −Jᵀr with Marquardt's scaling D = the running maximum of diag(JᵀJ)
    (``scaling``), else D = I; ``normal(u, args) -> (JᵀJ, Jᵀr, ½‖r‖², extra)``; ``extra``
    (``()`` or arrays whose shapes ``extra_init(u0, args)`` gives) is kept with the accepted
    point, e.g. (J, r) for a model whose Jacobian is expensive to trace again at the end.
    ``linear_solve(a, b)`` solves the damped system: `solve_by_elimination` (the default),
    or `solve_damped` (faster per step under ``vmap``, slower to compile).

    The two dampings reach different optima from the same starts. D = I suits cold starts far
    from the data: there Marquardt's D keeps the huge curvature of the start (an inductance or
    a diffusion resistance 10⁸ times too large) for the whole solve, λ grows and the start
    stalls where it began. Marquardt's D suits the long valley of a finite Warburg element
    whose τ runs to infinity (R/√τ fixed): D = I creeps along it (docs/fitting.md, "Damping").

    ``trust_region``: where D = I, λ follows the classical trust-region rule instead
    (Nocedal & Wright 2006, alg. 4.1, with λ for the inverse radius; optimistix's
    Levenberg–Marquardt): a trial is kept when the cost falls by at least 1 % of the predicted
    decrease ρ ≥ 0.01, λ is divided by 3.5 when ρ > 0.99 and multiplied by 4 on a rejection.
    From random starts it keeps larger steps for longer than Nielsen's update, and lands in
    the global basin more often (docs/fitting.md, "Damping"). With it, a start is done after
    an accepted step below ``xtol``, rather than before a proposed one: on exact data the
    last, small Gauss–Newton step takes the residual from ~1e-13 to rounding level.
    ``scaled_stop``: with ``trust_region``, the starts with Marquardt's scaling stop by
    Nielsen's rule (before a small proposed step) as without it, so that a work queue mixing
    both dampings leaves its scaled problems as they were (`work_queue`).

    Each step linearises once at the trial point and keeps it only when the cost falls (the
    state holds JᵀJ and Jᵀr, not J), so the model's Jacobian is traced once. A start is done
    when an accepted step lowers the cost by less than ``rtol`` relatively, or the step is
    below ``xtol``.
    """

    def init(u0, args) -> LMState:
        k = u0.shape[0]
        return LMState(
            u=u0, a=jnp.zeros((k, k)), g=jnp.zeros(k), cost=jnp.asarray(jnp.inf), u_try=u0, pred=jnp.asarray(1.0),
            lam=jnp.asarray(1e-3), nu=jnp.asarray(2.0), i=jnp.asarray(0), done=jnp.asarray(False), dmax=jnp.zeros(k),
            extra=() if extra_init is None else extra_init(u0, args), scaled=jnp.asarray(scaling),
        )

    def step(s: LMState, args) -> LMState:
        a_try, g_try, c_try, extra_try = normal(s.u_try, args)
        c_try = jnp.where(jnp.isfinite(c_try) & jnp.all(jnp.isfinite(a_try)), c_try, jnp.inf)
        first = s.i == 0
        gain = s.cost - c_try
        rho = gain / jnp.where(s.pred > 0, s.pred, 1.0)
        ok = first | ((gain > 0) & jnp.isfinite(c_try))
        lam = jnp.where(first, s.lam, jnp.where(ok, s.lam * jnp.maximum(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3), s.lam * s.nu))
        if trust_region:
            classical = ~s.scaled
            ok_tr = first | ((gain >= 0.01 * s.pred) & (gain > 0) & jnp.isfinite(c_try))
            good = ~first & (s.pred > 0) & (gain > 0.99 * s.pred)
            lam_tr = jnp.where(first, s.lam, jnp.where(ok_tr, jnp.where(good, s.lam / 3.5, s.lam), s.lam * 4.0))
            ok, lam = jnp.where(classical, ok_tr, ok), jnp.where(classical, lam_tr, lam)
        nu = jnp.where(ok, 2.0, s.nu * 2.0)
        keep = lambda new, old: jnp.where(ok, new, old)  # noqa: E731
        u, cost = keep(s.u_try, s.u), keep(c_try, s.cost)
        a, g = keep(a_try, s.a), keep(g_try, s.g)
        extra = jax.tree_util.tree_map(keep, extra_try, s.extra)
        dmax = jnp.maximum(jnp.diag(a), s.dmax)
        d = jnp.where(s.scaled & (dmax > 0), dmax, 1.0)  # padded parameters have zero columns
        damped = a + lam * jnp.diag(d)
        delta = -linear_solve(damped, g)
        solved = jnp.all(jnp.isfinite(delta))  # if not, the next trial is u itself: rejected, more damping
        delta = jnp.where(solved, delta, 0.0)
        pred = 0.5 * jnp.dot(delta, lam * d * delta - g)
        flat = ~first & ok & (gain <= rtol * s.cost)
        small = lambda step: jnp.sqrt(jnp.sum(step**2)) <= xtol * (jnp.sqrt(jnp.sum(u**2)) + xtol)  # noqa: E731
        # trust_region: done after taking a small step (as optimistix's test on the last step),
        # not before it: on exact data that last Gauss–Newton step reaches rounding level
        tiny = solved & small(delta)
        if trust_region:
            tiny_tr = ~first & ok & small(s.u_try - s.u)
            tiny = jnp.where(s.scaled, tiny, tiny_tr) if scaled_stop else tiny_tr
        done = s.done | flat | tiny | (lam > 1e15) | ~jnp.isfinite(cost)
        new = LMState(u=u, a=a, g=g, cost=cost, u_try=u + delta, pred=pred, lam=lam, nu=nu, i=s.i + 1, done=done, dmax=dmax, extra=extra, scaled=s.scaled)
        return jax.tree_util.tree_map(lambda a_, b_: jnp.where(s.done, b_, a_), new, s)  # a finished start stays put

    return init, step


def select_lanes(mask, new, old):
    """Pytrees ``new`` where ``mask`` (a scalar, or one flag per lane along the leading axis),
    else ``old``."""
    return jax.tree_util.tree_map(lambda a, b: jnp.where(jnp.reshape(mask, jnp.shape(mask) + (1,) * (a.ndim - jnp.ndim(mask))), a, b), new, old)


class QueueOutput(NamedTuple):
    """Per problem: the solution ``u``, its ``chi2``, whether it converged (``done``) and the
    number of ``steps`` taken."""

    u: jax.Array
    chi2: jax.Array
    done: jax.Array
    steps: jax.Array


def work_queue(normal_u: Callable, n_lanes: int, combine: Callable, *, linear_solve: Callable = solve_damped, trust_region: bool = False):
    """A work-queue Levenberg–Marquardt solver for many independent problems (spectra, or
    spectrum × start pairs). ``n_lanes`` problems iterate side by side (``vmap`` of one
    `lm_iteration` step); when a lane's problem converges or spends its step budget, the result
    is written out and the lane takes the next problem from the queue. Every lane does useful
    work at every step, so a batch costs about its total number of steps, not its size times
    the slowest problem's count (what a plain ``vmap`` of a solver loop costs).

    ``solve(u0 (C, K), spectrum (C,), budget (C,), n_problems, rows, shared, drain)``: problem
    p starts at ``u0[p]`` on the data of row ``spectrum[p]`` of ``rows`` (a pytree of arrays
    over spectra; ``shared`` holds what all have in common, ``combine(shared, row)`` makes the
    solver arguments of one problem) and may take ``budget[p]`` steps; only the first
    ``n_problems`` are solved (the rest is padding, so one compilation serves any count). With
    ``drain=False`` the loop stops once the queue is empty and at most ``n_lanes // 8`` lanes
    still run: their problems come back unfinished (``done`` False), to be continued on fewer
    lanes, so a few slow problems do not keep every lane busy. Returns a `QueueOutput` over
    the C problems. ``linear_solve``: as in `lm_iteration` (default `solve_damped`; the
    elimination compiles much faster). ``scaled`` (C,) bool, optional: per problem, Marquardt's
    scaling (True, the default) or D = I (`lm_iteration`); one compilation serves both.
    ``trust_region``: the problems with D = I update λ by the classical trust-region rule from
    λ = 1, as the first steps of a single fit (`lm_iteration`'s ``trust_region``); those with
    Marquardt's scaling keep Nielsen's update and stopping rule (``scaled_stop``).
    """
    init, step = lm_iteration(normal_u, linear_solve=linear_solve, trust_region=trust_region, scaled_stop=True)
    lane_init = jax.vmap(init, in_axes=(0, None))

    def solve(u0, spectrum, budget, n_problems, rows, shared, scaled=None, *, drain):
        capacity = u0.shape[0]
        lane_step = jax.vmap(lambda s, row: step(s, combine(shared, row)))

        def load(pid):
            clipped = jnp.minimum(pid, capacity - 1)
            row = jax.tree_util.tree_map(lambda a: a[spectrum[clipped]], rows)
            s = lane_init(u0[clipped], None)
            if scaled is not None:
                s = s._replace(scaled=scaled[clipped])
                if trust_region:
                    s = s._replace(lam=jnp.where(s.scaled, s.lam, 1.0))
            return s, row, budget[clipped]

        def write(out: QueueOutput, pid, s: LMState, done) -> QueueOutput:
            sink = jnp.where(pid < n_problems, pid, capacity)  # row `capacity` absorbs idle lanes
            return QueueOutput(out.u.at[sink].set(s.u), out.chi2.at[sink].set(2.0 * s.cost), out.done.at[sink].set(done), out.steps.at[sink].set(s.i))

        def running(carry):
            _, pid, _, _, next_pid, _ = carry
            active = pid < n_problems
            few = jnp.sum(active) <= n_lanes // 8
            return jnp.any(active) & (drain | (next_pid < n_problems) | ~few)

        def body(carry):
            s, pid, row, limit, next_pid, out = carry
            s = lane_step(s, row)
            finished = (pid < n_problems) & (s.done | (s.i >= limit))
            out = write(out, jnp.where(finished, pid, capacity), s, s.done)
            new_pid = next_pid + jnp.cumsum(finished) - 1
            take = finished & (new_pid < n_problems)
            pid = jnp.where(finished, jnp.where(take, new_pid, capacity), pid)
            fresh, fresh_row, fresh_limit = load(pid)
            s = select_lanes(take, fresh, s)
            s = s._replace(done=s.done | (finished & ~take))  # an idle lane stays put
            return s, pid, select_lanes(take, fresh_row, row), jnp.where(take, fresh_limit, limit), next_pid + jnp.sum(take), out

        pid = jnp.where(jnp.arange(n_lanes) < n_problems, jnp.arange(n_lanes), capacity)
        s, row, limit = load(pid)
        s = s._replace(done=pid >= n_problems)
        out = QueueOutput(
            u=jnp.concatenate([u0, u0[:1]]),
            chi2=jnp.full(capacity + 1, jnp.inf),
            done=jnp.zeros(capacity + 1, bool),
            steps=jnp.zeros(capacity + 1, jnp.int64),
        )
        carry = (s, pid, row, limit, jnp.minimum(n_lanes, n_problems), out)
        s, pid, _, _, _, out = jax.lax.while_loop(running, body, carry)
        out = write(out, pid, s, jnp.zeros(n_lanes, bool))  # problems still open when stopped early
        return QueueOutput(*(a[:capacity] for a in out))

    return solve
