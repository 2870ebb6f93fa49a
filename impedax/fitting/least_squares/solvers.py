"""The compiled least-squares core shared by `fit`, batch fits and candidate fits.

The residual is the real-stacked weighted residual ``[Re(Z_m − Z_d)/w_re, Im(Z_m − Z_d)/w_im]``,
squared once by the solver. Two solvers:

* one spectrum of a circuit compiled by `compile_circuit` (``tree_solver(...).single``):
  impedax's Levenberg–Marquardt iteration (`lm.lm_iteration`) from one or many starts, the
  starts screened side by side (``vmap``) and the best continued, in one loop. Each
  linearisation is one evaluation of the circuit's analytic Jacobian
  (`CompiledCircuit.value_and_columns`) instead of forward mode through the circuit. Tree
  solvers are compiled per circuit and free set (which parameters are free, and their
  transforms): fixed values are constants of the trace;
* many spectra of one circuit (``tree_solver(...).lanes``, `lm.work_queue`): a work queue of
  independent Levenberg–Marquardt problems over a fixed number of ``vmap`` lanes, with the
  same iteration and Jacobian.

Candidate circuits of one padded program layout (the diagnosis) have their own solver,
`candidates.candidate_solver`, on the same `lm.work_queue` and `SolverArgs`.

Arguments and outputs are typed: `SolverArgs` in, `SolverOutput` out, `SolverStatus` codes.
"""

from __future__ import annotations

import enum
import functools
from typing import Any, Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ...circuits import Circuit, Registry, compile_circuit
from ..parameters import external_of_kind
from ..stored import QUICK_COMPILE, StoredProgram
from .lm import lm_iteration, select_lanes, work_queue
from .order import structural_peaks

__all__ = [
    "tree_solver", "TreeSolvers", "SolverArgs", "SpectrumRows", "SharedArgs", "SolverOutput", "SolverStatus",
    "one_transfer", "PendingOutputs", "tree_residuals", "solver_args", "unscale", "better", "over_devices", "SCREEN_STEPS",
    "padded_size", "padded_points", "trimmed", "IDENTITY_DAMPING_STEPS",
]

SCREEN_STEPS = 40  # Levenberg–Marquardt steps every start gets before the best is refined
# single fits damp with λI (classical trust-region update) for this many steps, then as the
# batch lanes (Marquardt's scaling, Nielsen's update; `_make`)
IDENTITY_DAMPING_STEPS = 50


class SolverStatus(enum.IntEnum):
    """How a solve ended (`SolverOutput.code`); `message` is the text a user reads."""

    CONVERGED = 0
    MAX_STEPS = 1
    FAILED = 2

    @property
    def message(self) -> str:
        return _STATUS_MESSAGES[self]


_STATUS_MESSAGES = {
    SolverStatus.CONVERGED: "",
    SolverStatus.MAX_STEPS: "the solver reached its step limit before converging; raise max_steps or give better starting values",
    SolverStatus.FAILED: "the solver stopped without converging (a singular or diverging linear system)",
}


class SolverArgs(NamedTuple):
    """The arrays a solver takes for one spectrum (a pytree: batched by ``vmap``).

    ``freq`` [Hz], data ``z`` [Ω], the inverse weights of its real and imaginary parts,
    ``x_fixed`` (all parameters; fixed values where fixed, placeholders elsewhere), and the
    bounds of the free parameters. The candidate solver (`candidates.candidate_solver`), whose
    free set is data rather than part of the trace, also takes each free parameter's transform
    ``kind`` and position ``free_index`` and the circuit program's arrays ``model_args``."""

    freq: Any
    z: Any
    inv_w_re: Any
    inv_w_im: Any
    x_fixed: Any
    lower: Any
    upper: Any
    kind: Any = None
    free_index: Any = None
    model_args: Any = None


class SpectrumRows(NamedTuple):
    """What differs between the spectra of a batch (arrays over spectra)."""

    z: Any
    inv_w_re: Any
    inv_w_im: Any
    x_fixed: Any


class SharedArgs(NamedTuple):
    """What the spectra of a batch share: frequencies, free set and bounds."""

    freq: Any
    lower: Any
    upper: Any


def combine(shared: SharedArgs, row: SpectrumRows) -> SolverArgs:
    """The solver arguments of one spectrum of a batch."""
    return SolverArgs(shared.freq, row.z, row.inv_w_re, row.inv_w_im, row.x_fixed, shared.lower, shared.upper)


class SolverOutput(NamedTuple):
    """What a solve returns, per spectrum (leading batch axes where solved in batches):
    all parameters ``x``, weighted ``chi2``, the Jacobian of the weighted residuals in
    parameter space (2N, K) for the covariance, the model's impedance ``z_model``, the
    `SolverStatus` ``code``, ``steps`` of the final solve (single fits: with its start's
    screen), the chi² of every screened start
    ``chi2_starts``, all steps ``steps_total``, (tree solvers) the peak frequencies of
    exchangeable blocks ``peaks`` (`order.canonical_order`), and (single fits) the chi² with
    each free parameter moved to either bound (``bound_points``, ``bound_chi2``), which
    `result.confirm_bounds` asks for."""

    x: Any
    chi2: Any
    jacobian: Any
    z_model: Any
    code: Any = None
    steps: Any = None
    chi2_starts: Any = None
    steps_total: Any = None
    peaks: Any = None
    bound_points: Any = None  # (single fits) free values at the solution, then each moved to its lower, then its upper bound
    bound_chi2: Any = None  # chi² at those points, weights scaled as the solver's (`result.confirm_bounds`)

    def row(self, i) -> "SolverOutput":
        """The outputs of spectrum ``i`` (or rows ``i``) of a batch."""
        return SolverOutput(*(None if v is None else v[i] for v in self))


def solver_args(table, freq, z, inv_re, inv_im) -> SolverArgs:
    """The arrays a tree solver takes (`tree_residuals`; which parameters are free and their
    transforms are compiled into it) for one spectrum and a `ParameterTable`."""
    # numpy arrays: jit transfers them on its fast path (jnp.asarray per array costs more)
    free = table.free_index
    return SolverArgs(
        freq=np.asarray(freq, float),
        z=np.asarray(z, complex),
        inv_w_re=np.asarray(inv_re, float),
        inv_w_im=np.asarray(inv_im, float),
        x_fixed=np.where(np.isnan(table.values), 1.0, table.values),
        lower=table.lower[free],
        upper=table.upper[free],
    )



def padded_size(n: int) -> int:
    """The number of points a spectrum of ``n`` points is solved with: ``n`` rounded up to a
    multiple of 2^(⌊log₂ n⌋ − 3) (at least 2), eight sizes per octave, at most 12.5 % more
    points. Compiled solvers are specialised on the number of points, so spectra of nearby
    lengths share one compilation."""
    step = max(2, 2 ** (max(int(n).bit_length() - 1, 0) - 3))
    return -(-int(n) // step) * step


def padded_points(freq, z, inv_re, inv_im, size: int | None = None):
    """Frequencies (N,), data and inverse weights (…, N) padded to ``size`` points (default
    `padded_size` (N)): the added points repeat the last frequency and datum with zero weight,
    so their residuals and Jacobian rows are zero and chi², steps and solutions are those of
    the N points (to rounding in the order of sums)."""
    n = np.shape(freq)[-1]
    extra = (padded_size(n) if size is None else size) - n
    if not extra:
        return np.asarray(freq, float), z, inv_re, inv_im

    def pad(a, value=None):
        a = np.asarray(a)
        tail = np.repeat(a[..., -1:], extra, axis=-1) if value is None else np.full(a.shape[:-1] + (extra,), value, a.dtype)
        return np.concatenate([a, tail], axis=-1)

    return pad(np.asarray(freq, float)), pad(z), pad(inv_re, 0.0), pad(inv_im, 0.0)


def trimmed(out: SolverOutput, n: int) -> SolverOutput:
    """Outputs of a solve on points padded by `padded_points`, cut back to the first ``n``
    points: the model's impedance (…, N) and the Jacobian's rows (…, 2N, K), Re and Im."""
    n_padded = np.shape(out.z_model)[-1]
    if n_padded == n:
        return out
    rows = np.r_[0:n, n_padded : n_padded + n]
    return out._replace(z_model=np.asarray(out.z_model)[..., :n], jacobian=np.asarray(out.jacobian)[..., rows, :])


def unscale(out: SolverOutput, scale) -> SolverOutput:
    """Outputs of a solve on residuals scaled by `problem.residual_scale`, scaled back."""
    scale = np.asarray(scale)
    if np.all(scale == 1.0):  # modulus weighting: nothing to undo
        return out
    chi2_starts = out.chi2_starts / scale.reshape(scale.shape + (1,) * (np.ndim(out.chi2_starts) - scale.ndim)) ** 2
    return out._replace(chi2=out.chi2 / scale**2, chi2_starts=chi2_starts, jacobian=out.jacobian / scale.reshape(scale.shape + (1, 1)))


def better(a: SolverOutput, b: SolverOutput) -> SolverOutput:
    """The solver output with the lower chi² (a on ties), elementwise over a batch axis
    (the per-start chi² of the screen, which differ in shape, are dropped)."""
    take_b = np.asarray(b.chi2) < np.asarray(a.chi2)

    def pick(x, y):
        return None if x is None else np.where(take_b.reshape(take_b.shape + (1,) * (np.ndim(x) - take_b.ndim)), y, x)

    return SolverOutput(*(pick(x, y) for x, y in zip(a, b)))._replace(chi2_starts=None)


class Residuals(NamedTuple):
    """The functions a solver needs, of (point, args): ``chi2_x``, the weighted chi² at
    parameters x_free (the Re and Im halves squared apart: under vmap, joining them costs
    several times the circuit); ``linearise_x`` → (J, r) in parameter space;
    ``normal_u`` → the normal equations (JᵀJ, Jᵀr, ½‖r‖², extra) at u; ``to_x`` → (x_free,
    all parameters) at u."""

    chi2_x: Callable
    linearise_x: Callable
    normal_u: Callable
    to_x: Callable


def tree_residuals(compiled, free: tuple[int, ...], kinds: tuple[int, ...]):
    """The `Residuals` of a compiled circuit whose free parameters (positions ``free``, with
    transform ``kinds``, see `parameters.Transform`) are known when tracing, with the circuit's
    analytic Jacobian (`CompiledCircuit.value_and_columns`) in ``normal_u`` and
    ``linearise_x``: one evaluation of it per linearisation rather than forward mode through
    the circuit. Also ``to_x``, the parameters of the solver's point u.

    Knowing the free set when tracing, fixed parameters are constants of the trace: no
    gather or scatter by index, no derivative columns for them, one transform formula per
    kind present.
    Re and Im parts are weighted apart and, in what runs under ``vmap`` (``normal_u``), never
    concatenated: XLA's concatenation of the halves costs several times
    the circuit."""
    slot = {i: j for j, i in enumerate(free)}
    n_params = len(compiled.parameter_names)

    def theta(x_free, args):
        """All parameters, by position: the free ones from x_free, the rest from x_fixed."""
        return tuple(x_free[slot[i]] if i in slot else args.x_fixed[i] for i in range(n_params))

    # one vector formula per transform kind present, each over the whole vector and kept where
    # that kind applies: under vmap a select costs less than gathering and rejoining the groups
    # (measured: ~20 % of a battery circuit's solver step; benchmarks/README.md)
    present = sorted(set(kinds))
    masks = [np.asarray(kinds) == k for k in present]

    def external(u, args):
        lower, upper = args.lower, args.upper
        out = external_of_kind(u, lower, upper, present[0]) if present else u
        for k, mask in zip(present[1:], masks[1:]):
            out = jnp.where(mask, external_of_kind(u, lower, upper, k), out)
        return out

    def u_to_x(u, args):
        return jax.jvp(lambda v: external(v, args), (u,), (jnp.ones_like(u),))

    def impedance(x_free, args):
        return compiled(dict(zip(compiled.parameter_names, theta(x_free, args))), args.freq)

    def parts_x(x_free, args, dx_du=None):
        """(J_re, J_im) (K, N), parameters first, and (r_re, r_im) (N,), weighted (and by
        u, given dx/du)."""
        z, columns = compiled.value_and_columns(theta(x_free, args), args.freq, free)
        w_re, w_im = args.inv_w_re, args.inv_w_im
        jac = jnp.stack(columns) if dx_du is None else jnp.stack(columns) * dx_du[:, None]
        r = z - args.z
        return jac.real * w_re[None, :], jac.imag * w_im[None, :], r.real * w_re, r.imag * w_im

    def linearise_x(x_free, args):
        j_re, j_im, r_re, r_im = parts_x(x_free, args)
        return jnp.concatenate([j_re, j_im], axis=1).T, jnp.concatenate([r_re, r_im])

    def normal_u(u, args):
        x, dx_du = u_to_x(u, args)
        j_re, j_im, r_re, r_im = parts_x(x, args, dx_du)
        # parameters-first halves and two products: under vmap, XLA runs this JᵀJ faster than
        # any layout with Re and Im joined (measured, benchmarks/README.md)
        a = j_re @ j_re.T + j_im @ j_im.T
        return a, j_re @ r_re + j_im @ r_im, 0.5 * (jnp.sum(r_re**2) + jnp.sum(r_im**2)), ()

    def chi2_x(x_free, args):
        r = impedance(x_free, args) - args.z
        return jnp.sum((r.real * args.inv_w_re) ** 2) + jnp.sum((r.imag * args.inv_w_im) ** 2)

    def to_x(u, args):
        x_free = external(u, args)
        return x_free, jnp.stack(theta(x_free, args))

    return Residuals(chi2_x, linearise_x, normal_u, to_x)


def _finish(u, args: SolverArgs, residuals: Residuals, peaks=None) -> SolverOutput:
    """Solver outputs at the solution u: parameters, the Jacobian in parameter space (for
    the covariance), chi², the model's impedance and, given ``peaks``
    (`order.structural_peaks`), the peak frequencies that order exchangeable blocks."""
    x_free, x = residuals.to_x(u, args)
    jac, r = residuals.linearise_x(x_free, args)
    n = args.z.shape[0]
    chi2 = jnp.sum(r**2)
    return SolverOutput(
        x=x,
        chi2=jnp.where(jnp.isfinite(chi2), chi2, jnp.inf),
        jacobian=jac,
        z_model=args.z + r[:n] / args.inv_w_re + 1j * (r[n:] / args.inv_w_im),
        peaks=None if peaks is None else peaks(x, args.freq),
    )


def _normal_only(residuals: Residuals):
    """``normal_u`` keeping no ``extra`` with the accepted point."""
    return lambda u, args: (*residuals.normal_u(u, args)[:3], ())


def _make(residuals, max_steps: int, peaks=None):
    """``solve(u0s (S, K), screen_steps, args, continue_best)``: one spectrum fitted by impedax's
    Levenberg–Marquardt iteration (`lm.lm_iteration`, the batch lanes' cost rule): a solve's
    first `IDENTITY_DAMPING_STEPS` steps damped with λI, λ by the classical trust-region rule,
    the rest as the batch lanes' iteration (Marquardt's scaling, Nielsen's update;
    docs/fitting.md, "Damping"). Every start runs for
    ``screen_steps`` steps side by side (``vmap``), then the best of them to convergence for
    at most ``max_steps`` steps in lane 0, the other lanes idle; ``screen_steps`` 0: the first
    start alone; negative: no step at all (a device with no draw of its own, `single.fit`).
    ``continue_best`` false: the screen alone, the outputs at its best point (a
    rung of many screens continues their best points side by side afterwards, `single.escalated`).
    Both phases are one loop over one vmapped step, so a first fit compiles the
    circuit's step once (the loop runs no faster for it)."""
    init, step = lm_iteration(_normal_only(residuals), scaling=False, trust_region=True)
    lane_init = jax.vmap(lambda u0, args: init(u0, args)._replace(lam=jnp.asarray(1.0)), in_axes=(0, None))

    def lane_step(s, args):
        # at `IDENTITY_DAMPING_STEPS`, a solve not yet done continues as a fresh Nielsen
        # iteration with Marquardt's scaling (the batch lanes' iteration)
        switch = s.i == IDENTITY_DAMPING_STEPS
        s = s._replace(scaled=s.scaled | switch, lam=jnp.where(switch, 1e-3, s.lam), nu=jnp.where(switch, 2.0, s.nu), dmax=jnp.where(switch[:, None], 0.0, s.dmax))
        return jax.vmap(step, in_axes=(0, None))(s, args)

    def solve(u0s, screen_steps, args, continue_best):
        n_starts = u0s.shape[0]
        idle = jnp.arange(n_starts) > 0

        def final_from(u):
            s = lane_init(jnp.broadcast_to(u, u0s.shape), args)
            return s._replace(done=idle | ~continue_best)

        screening = screen_steps > 0
        # one vmapped start for both cases: every start screened, or the first alone in lane 0
        # (`final_from`): the program holds one copy of the start's Jacobian fewer
        started = lane_init(jnp.where(screening, u0s, jnp.broadcast_to(u0s[0], u0s.shape)), args)
        s0 = select_lanes(screening, started, started._replace(done=idle | (screen_steps < 0)))

        def running(carry):
            s, in_screen, _, _ = carry
            return in_screen | (~s.done[0] & (s.i[0] < max_steps))

        def body(carry):
            s, in_screen, chi2s, steps1 = carry
            limit = jnp.where(in_screen, screen_steps, max_steps)
            active = ~s.done & (s.i < limit)
            s = select_lanes(active, lane_step(s, args), s)
            screened = in_screen & ~jnp.any(~s.done & (s.i < limit))
            chi2 = jnp.where(jnp.isfinite(s.cost), 2.0 * s.cost, jnp.inf)
            chi2s, steps1 = jnp.where(screened, chi2, chi2s), jnp.where(screened, s.i, steps1)
            # the final solve's start only when the screen ends (a branch, not a select: the
            # start's Jacobian is not computed at every step)
            s = jax.lax.cond(screened, lambda s: final_from(s.u[jnp.argmin(chi2)]), lambda s: s, s)
            return s, in_screen & ~screened, chi2s, steps1

        carry = (s0, screening, jnp.full(n_starts, jnp.inf), jnp.zeros(n_starts, s0.i.dtype))
        s, _, chi2s, steps1 = jax.lax.while_loop(running, body, carry)
        # the steps of the solution's path: its start's screen, then the final solve
        u, steps = s.u[0], jnp.where(screening, steps1[jnp.argmin(chi2s)], 0) + s.i[0]
        code = jnp.where(s.done[0], int(SolverStatus.CONVERGED), int(SolverStatus.MAX_STEPS))
        # the at-bound check's chi² (`result.confirm_bounds`) here, not in a program of its own:
        # a fresh process then compiles one program per fit
        x_free = residuals.to_x(u, args)[0]
        one = jnp.eye(x_free.size, dtype=bool)
        points = jnp.concatenate([x_free[None], jnp.where(one, args.lower, x_free), jnp.where(one, args.upper, x_free)])
        bound_chi2 = jax.vmap(lambda x: residuals.chi2_x(x, args))(points)
        return _finish(u, args, residuals, peaks)._replace(code=code, steps=steps, chi2_starts=chi2s, steps_total=jnp.sum(steps1) + s.i[0], bound_points=points, bound_chi2=bound_chi2)

    return solve


class TreeSolvers(NamedTuple):
    """The compiled solvers of one circuit and free set (`tree_solver`); ``key``: what names
    them across processes (`stored.StoredProgram`)."""

    single: Callable
    lanes: Callable
    finish: Callable
    chi2: Callable
    chi2_x: Callable
    key: tuple


@functools.lru_cache(maxsize=128)
def tree_solver(circuit: Circuit, registry: Registry, max_steps: int, free: tuple[int, ...], kinds: tuple[int, ...]):
    """Jitted solvers for one circuit and free set (positions ``free`` with transform
    ``kinds``, `ParameterTable.free_structure`; cached): ``single(u0s, screen_steps, args, continue_best)``
    fits one spectrum from one or many starts (`_make`) on every device, each its own draw of
    starts u0s (D, S, K) and screen length (D,) (`one_transfer`'s ``per_device`` outputs); ``lanes(n_lanes)`` gives the `lm.work_queue` solver
    for batches, ``finish(u, spectrum, rows, shared)`` the outputs at solutions,
    ``chi2(points, spectrum, rows, shared, in_u)`` the weighted chi² at points u (``in_u``)
    or at free parameter values x, and ``chi2_x(...)`` the latter (all vmapped over points)."""
    compiled = compile_circuit(circuit, registry)
    residuals = tree_residuals(compiled, free, kinds)
    peaks = structural_peaks(compiled.circuit, compiled.parameter_names, registry)

    def per_spectrum(fn):
        """``fn(u, args)`` vmapped over points u (C, K) of the spectra rows[spectrum]."""

        def mapped(u, spectrum, rows, shared):
            return jax.vmap(lambda u_i, s: fn(u_i, combine(shared, jax.tree_util.tree_map(lambda a: a[s], rows))))(u, spectrum)

        return jax.jit(mapped)

    finish = per_spectrum(lambda u, args: _finish(u, args, residuals, peaks))

    def chi2_function(points, spectrum, rows, shared, in_u):
        """Weighted chi² at ``points`` (C, K) of the spectra rows[spectrum]: free parameter
        values, or the solver's points u where ``in_u`` (one program for both)."""

        def one(p, s):
            args = combine(shared, jax.tree_util.tree_map(lambda a: a[s], rows))
            return residuals.chi2_x(jnp.where(in_u, residuals.to_x(p, args)[0], p), args)

        return jax.vmap(one)(points, spectrum)

    chi2 = jax.jit(chi2_function)
    static = (circuit, registry, max_steps, free, kinds)
    chi2_stored = StoredProgram("fit-chi2", static, chi2_function, compiler_options=QUICK_COMPILE)

    def chi2_x(points, spectrum, rows, shared):
        return chi2_stored(points, spectrum, rows, shared, False)

    lanes = functools.lru_cache(maxsize=4)(lambda n_lanes: jax.jit(_with_damping_sharded(work_queue(residuals.normal_u, n_lanes, combine, trust_region=True)), static_argnames="drain"))

    # every device runs a draw of starts of its own, with its own screen length (the draws
    # of a rung side by side: a 2-core machine screens two at the time of one)
    single = one_transfer(_make(residuals, max_steps, peaks), "fit-single", static, n_sharded=2)
    return TreeSolvers(single, lanes, finish, chi2, chi2_x, static)


def _with_damping_sharded(queue: Callable) -> Callable:
    """`lm.work_queue`'s ``solve`` with the per-problem damping flag ``scaled`` before the
    arguments every device shares: ``solve(u0, spectrum, budget, n_problems, rows, scaled,
    shared, drain=)``, so that `over_devices` gives each device its own flags (six sharded
    arguments)."""

    def solve(u0, spectrum, budget, n_problems, rows, scaled, shared, *, drain):
        return queue(u0, spectrum, budget, n_problems, rows, shared, scaled, drain=drain)

    return solve


@functools.lru_cache(maxsize=64)
def over_devices(fn: Callable, n_sharded: int, drain: bool | None = None, stored: tuple[str, Any] | None = None):
    """``fn`` run on every JAX device at once as one compiled program (``jax.shard_map``):
    the first ``n_sharded`` arguments carry a leading axis of one entry per device (each
    device computes ``fn`` on its own entry, e.g. a chunk of a batch), the rest are the same
    on every device; outputs get the same leading axis. One compilation serves all devices,
    where a program placed on each device apart is compiled once per device. ``drain`` is
    passed on as a keyword when given (`lm.work_queue`). ``stored``: (name, key), to keep the
    program across processes (`stored.StoredProgram`). Returns (the jitted function, the
    sharding of its per-device arguments)."""
    run, shardings, spread = _on_every_device(fn if drain is None else functools.partial(fn, drain=drain), n_sharded)
    jitted = jax.jit(run)
    if stored is not None:
        name, key = stored
        jitted = StoredProgram(name, (key, n_sharded, drain), jitted, shardings)
    return jitted, spread


def _on_every_device(fn: Callable, n_sharded: int):
    """(``run``, ``shardings``, the sharding of a per-device argument): ``run(*args)``
    computes ``fn`` on every device at once (``jax.shard_map``, not jitted), each on its own
    entry of the first ``n_sharded`` arguments' leading axis, the rest the same everywhere;
    outputs get that leading axis. ``shardings(args)`` gives the sharding of each argument
    (`stored.StoredProgram`)."""
    mesh = jax.sharding.Mesh(np.array(jax.devices()), ("device",))
    spread, same = jax.sharding.PartitionSpec("device"), jax.sharding.PartitionSpec()

    def per_device(*args):
        local = jax.tree_util.tree_map(lambda a: a[0], args[:n_sharded])
        out = fn(*local, *args[n_sharded:])
        return jax.tree_util.tree_map(lambda a: a[None], out)

    def run(*args):
        specs = tuple(spread if i < n_sharded else same for i in range(len(args)))
        return jax.shard_map(per_device, mesh=mesh, in_specs=specs, out_specs=spread, check_vma=False)(*args)

    spread_sharding, same_sharding = jax.sharding.NamedSharding(mesh, spread), jax.sharding.NamedSharding(mesh, same)
    return run, lambda args: [spread_sharding] * n_sharded + [same_sharding] * (len(args) - n_sharded), spread_sharding


def one_transfer(solve: Callable, name: str, static, n_sharded: int = 0):
    """``solve(...) -> SolverOutput``, jitted to return its arrays packed in one float64
    array, and unpacked on the host: one device-to-host copy per fit instead of one per output
    (each costs tens of µs, as much as several solver steps); kept across processes as
    `stored.StoredProgram` ``name`` with key ``static``. Returns ``run(...)`` giving a
    `PendingOutputs`; its ``fetch()`` waits and returns the `SolverOutput` in numpy.
    ``n_sharded`` > 0: ``solve`` runs on every device at once (`over_devices`), each on its own
    entry of the first ``n_sharded`` arguments' leading axis; every output then has that
    leading axis (`PendingOutputs.per_device` splits them). Each device packs its own
    outputs, so the program holds no collective: packing them together after the devices'
    work gathered them across devices, where a device that finished early waits on one of
    XLA's CPU worker threads for the other (with the other stuck in a batched LAPACK solve,
    `lm.solve_by_elimination`, XLA aborted the process after 40 s of that wait)."""
    if not n_sharded:
        return StoredProgram(name, (static, n_sharded), lambda *args: PendingOutputs(*_packed(solve(*args))), compiler_options=QUICK_COMPILE)

    def packed(*args):
        recorded = []  # (kind, layout), known once this trace has run `solve` on a device

        def packed_here(*local):
            flat, kind, layout = _packed(solve(*local))
            recorded.append((kind, layout))
            return flat

        flat = _on_every_device(packed_here, n_sharded)[0](*args)  # (devices, size)
        return PendingOutputs(flat, *recorded[-1])

    shardings = _on_every_device(solve, n_sharded)[1]  # (the same for any function)
    return StoredProgram(name, (static, n_sharded), packed, shardings, compiler_options=QUICK_COMPILE)


def _packed(out) -> tuple:
    """(one float64 array of every output of ``out``, its NamedTuple type, the layout: (name,
    start, stop, shape, dtype) per output)."""
    fields = {k: v for k, v in out._asdict().items() if v is not None}
    layout, at = [], 0
    for field, v in fields.items():
        size = v.size * (2 if jnp.iscomplexobj(v) else 1)
        layout.append((field, at, at + size, v.shape, np.dtype(v.dtype)))
        at += size
    parts = [jnp.stack([v.real, v.imag], axis=-1) if jnp.iscomplexobj(v) else v for v in fields.values()]
    return jnp.concatenate([p.astype(jnp.float64).ravel() for p in parts]), type(out), tuple(layout)


@jax.tree_util.register_pytree_node_class
class PendingOutputs:
    """Solver outputs still on the device, packed by `one_transfer`: the array ``flat``, and as
    the pytree's static part the NamedTuple ``kind`` the solver returned and the ``layout``
    ((name, start, stop, shape, dtype) per output) to unpack it with."""

    def __init__(self, flat, kind: type, layout: tuple):
        self.flat, self.kind, self.layout = flat, kind, layout

    def tree_flatten(self):
        return (self.flat,), (self.kind, self.layout)

    @classmethod
    def tree_unflatten(cls, static, children):
        return cls(children[0], *static)

    def fetch(self):
        """The outputs in numpy; a program run on every device (`one_transfer` with
        ``n_sharded``) packed one row per device, and each output then leads with that axis."""
        flat = np.asarray(self.flat)
        lead = flat.shape[:-1]
        out = {}
        for name, start, stop, shape, dtype in self.layout:
            part = np.ascontiguousarray(flat[..., start:stop])
            out[name] = part.view(np.complex128).reshape(lead + shape) if dtype.kind == "c" else part.reshape(lead + shape).astype(dtype, copy=False)
        return self.kind(**out)

    def per_device(self) -> list:
        """`fetch` of a program run on every device (`one_transfer` with ``n_sharded``): one
        output per device."""
        out = self.fetch()
        return [out._replace(**{k: v[j] for k, v in out._asdict().items() if v is not None}) for j in range(len(out.chi2))]
