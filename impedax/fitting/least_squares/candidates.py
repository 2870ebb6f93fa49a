"""Fit many candidate circuits to one spectrum together, with one compilation.

Each candidate becomes a padded `CircuitProgram` of a shared `ProgramLayout`; programs,
parameter maps, bounds and starts travel as data. Every (candidate, start) pair is one
Levenberg–Marquardt problem of a work queue over a fixed number of ``vmap`` lanes
(`lm.work_queue`) on every JAX device at once (`solvers.over_devices`), with the program's
analytic Jacobian (`program_value_and_columns`). The compiled solver depends only on the
layout, the padded free-parameter count K and the padded number of frequencies, never on how
many candidates or starts there are: layouts, K and the frequency count are rounded up to
buckets, so a diagnosis and every step of a refinement share one compilation (kept by JAX's
persistent cache) whatever circuits they propose.
"""

from __future__ import annotations

import dataclasses
import functools
import time
from typing import Mapping, NamedTuple, Sequence

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from ...circuits import Circuit, CircuitProgram, DEFAULT_REGISTRY, ProgramLayout, Registry, default_theta, parse, program_value_and_columns
from ...errors import FitError
from ..parameters import ParameterTable, Transform, to_external, to_internal
from ..problem import FitProblem, fit_problem, open_spectrum, weights
from ..stored import QUICK_COMPILE, StoredProgram
from .lm import solve_by_elimination, work_queue
from .order import canonical_order
from .result import FitResult, dominated_notes, fit_result
from .solvers import SolverArgs, SolverOutput, SolverStatus, over_devices, padded_points, trimmed
from .starts import SpectrumFeatures, data_driven_guess, random_starts, values_inside

__all__ = ["fit_candidates", "SolverShape", "solver_shape", "candidate_solver"]

_K_BUCKETS = (12, 24, 48)
_SLOT_BUCKETS = (0, 2, 4, 6, 8, 12, 16, 24, 32, 48, 64)  # slots per element kind
_NODE_BUCKETS = (4, 8, 12, 16, 24, 32, 48, 64)
_FREQ_STEP = 16  # frequencies are padded (with zero weight) to a multiple of this
_LANES = 8
"""Problems iterated side by side. A queue call holds at most `_CAPACITY` problems whose step
counts run from ~20 to the step limit, and it drains: once the queue is empty, every lane
computes until the slowest problem ends. Few lanes keep that idle tail short. Time in the
queue over a warm ``refine`` of exampleDataVersaStudio.par (5,400 problems): 9.9 s with 4
lanes, 9.5 s with 8, 11.1 s with 16, 12.6 s with 32, 18.9 s with 64."""
DAMPINGS = ("marquardt", "identity")
"""`fit_candidates`' Levenberg–Marquardt dampings: D = the running maximum of diag(JᵀJ), or D = I."""
_CAPACITY = 256  # problems (candidate × start) per call of the queue; more are run in several calls
_FINISH = 32  # candidates per call of the finishing pass


def _bucket(n: int, buckets) -> int:
    """The smallest of ``buckets`` (ascending) that holds ``n``."""
    for b in buckets:
        if n <= b:
            return b
    raise FitError(f"a candidate fit needs {n} of something the solver holds at most {buckets[-1]} of (free parameters, slots of one element kind or nodes)")


class SolverShape(NamedTuple):
    """The padded shape of one compiled candidate solver: the program layout, the
    free-parameter count K and the frequency count. Calls of `fit_candidates` with one shape
    share one compilation; a refinement carries its shape from step to step (`grown_to`)."""

    layout: ProgramLayout
    n_free: int
    n_freq: int = 0

    def holds(self, circuits: Sequence[Circuit], registry: Registry, n_freq: int = 0) -> bool:
        """Whether every circuit (and ``n_freq`` frequencies) fits in this shape (so no new compilation is needed)."""
        need = ProgramLayout.covering(circuits, registry)
        k = max(len(c.parameter_names(registry)) for c in circuits)
        fits = need.n_nodes <= self.layout.n_nodes and all(a <= b for a, b in zip(need.capacities, self.layout.capacities))
        return fits and k <= self.n_free and n_freq <= self.n_freq and registry == self.layout.registry

    def grown_to(self, circuits: Sequence[Circuit], registry: Registry, n_freq: int = 0) -> "SolverShape":
        """This shape if it holds ``circuits`` and ``n_freq`` frequencies, else the bucketed
        shape that holds them and everything this one held."""
        if self.holds(circuits, registry, n_freq):
            return self
        new = solver_shape(circuits, registry, n_freq)
        if registry != self.layout.registry:
            return new
        layout = ProgramLayout(registry, tuple(max(a, b) for a, b in zip(new.layout.capacities, self.layout.capacities)), max(new.layout.n_nodes, self.layout.n_nodes))
        return SolverShape(layout, max(new.n_free, self.n_free), max(new.n_freq, self.n_freq))


def solver_shape(circuits: Sequence[Circuit], registry: Registry = DEFAULT_REGISTRY, n_freq: int = 0) -> SolverShape:
    """A shape that holds ``circuits`` and ``n_freq`` frequencies: the covering layout with
    each kind's slot count and the node count rounded up to buckets, K and the frequency count
    rounded up too (so the candidate sets of successive refinement steps mostly share it;
    evaluation cost grows with the slot and node counts)."""
    need = ProgramLayout.covering(circuits, registry)
    layout = ProgramLayout(registry, tuple(_bucket(c, _SLOT_BUCKETS) for c in need.capacities), _bucket(need.n_nodes, _NODE_BUCKETS))
    k = _bucket(max(len(c.parameter_names(registry)) for c in circuits), _K_BUCKETS)
    return SolverShape(layout, k, -(-n_freq // _FREQ_STEP) * _FREQ_STEP)


class CandidateRows(NamedTuple):
    """What differs between the candidates of one queue (arrays over candidates): every
    parameter of the flattened program ``x_fixed`` (fixed values; the free ones are
    overwritten), the free parameters' positions in it ``free_index`` (4·S: padding), their
    bounds and `Transform` ``kind``, and the program's arrays."""

    x_fixed: jax.Array
    free_index: jax.Array
    lower: jax.Array
    upper: jax.Array
    kind: jax.Array
    program: dict


class SpectrumArgs(NamedTuple):
    """What every candidate shares: the frequencies, the data and the inverse weights (padded
    frequencies have zero weight)."""

    freq: jax.Array
    z: jax.Array
    inv_w_re: jax.Array
    inv_w_im: jax.Array


def _combine(shared: SpectrumArgs, row: CandidateRows) -> SolverArgs:
    return SolverArgs(shared.freq, shared.z, shared.inv_w_re, shared.inv_w_im, row.x_fixed, row.lower, row.upper, row.kind, row.free_index, row.program)


def _program_parts(layout: ProgramLayout):
    """(to_x, parts): the free parameters and the full (S, 4) parameters at the solver's
    point u, and the weighted Jacobian halves (K, F) and residual halves (F,) at u, in
    parameter space or (``in_u``) in the solver's space."""

    def to_x(u, args: SolverArgs):
        x_free, dx_du = jax.jvp(lambda v: to_external(v, args.lower, args.upper, args.kind), (u,), (jnp.ones_like(u),))
        theta = jnp.concatenate([args.x_fixed, jnp.ones(1)]).at[args.free_index].set(x_free)[:-1]
        return theta, dx_du

    def parts(u, args: SolverArgs, in_u: bool):
        theta, dx_du = to_x(u, args)
        z, columns = program_value_and_columns(args.model_args, theta.reshape(layout.n_slots, -1), args.freq, args.free_index, layout=layout)
        if in_u:
            columns = columns * dx_du[:, None]
        r = z - args.z
        w_re, w_im = args.inv_w_re, args.inv_w_im
        return theta, z, columns.real * w_re[None, :], columns.imag * w_im[None, :], r.real * w_re, r.imag * w_im

    return parts


LAPACK_LANE_UNKNOWNS_MAX = 32
"""The candidate queue solves its lanes' damped systems by LAPACK up to this many unknowns,
by `lm.solve_by_elimination` beyond (`_lane_solve`)."""


def _lane_solve(a, b):
    """The damped system of one lane (vmapped over the queue's lanes): LAPACK for at most
    `LAPACK_LANE_UNKNOWNS_MAX` unknowns, whose program compiles faster than the elimination's
    (a diagnosis' first call 0.3–1 s sooner). jaxlib 0.10 splits a large batch of LAPACK
    solves over XLA's CPU worker threads and waits for them on one, which can hang a program
    running on every device at once (`lm.solve_by_elimination`); the queue's batches are its
    `_LANES` lanes, and 8 systems of 48 unknowns on both devices at once were measured to
    finish (256 of 12 hang). Beyond the bound, the elimination."""
    return jnp.linalg.solve(a, b) if a.shape[-1] <= LAPACK_LANE_UNKNOWNS_MAX else solve_by_elimination(a, b)


@functools.lru_cache(maxsize=16)
def candidate_solver(layout: ProgramLayout, n_free: int, n_lanes: int = _LANES):
    """Jitted ``(queue, finish)`` for candidates of ``layout`` with ``n_free`` (padded) free
    parameters, both kept across processes (`stored.StoredProgram`): ``queue`` is
    `lm.work_queue` over ``n_lanes`` lanes of (candidate, start) problems (`CandidateRows` per
    candidate, `SpectrumArgs` shared) with the normal equations from the program's analytic
    Jacobian, run on every device at once (`solvers.over_devices`: ``queue(u0, which, budget,
    n_problems, scaled, rows, shared)``, the first five with a leading axis of one entry per
    device, each device draining its own problems); ``finish(u, rows, shared)`` gives, vmapped
    over candidates, the full parameters, chi², the weighted Jacobian in parameter space
    (2F, K) and the model's impedance at points u."""
    parts = _program_parts(layout)

    def normal_u(u, args):
        _, _, j_re, j_im, r_re, r_im = parts(u, args, True)
        # parameters-first halves and two products (as `solvers.tree_residuals`)
        return j_re @ j_re.T + j_im @ j_im.T, j_re @ r_re + j_im @ r_im, 0.5 * (jnp.sum(r_re**2) + jnp.sum(r_im**2)), ()

    # the damped systems by `_lane_solve`: the unrolled factorisation of `lm.solve_damped`
    # would double the compile time of the whole solver. The damping (`DAMPINGS`) is
    # chosen per problem at run time, so both share this compilation
    lanes = work_queue(normal_u, n_lanes, _combine, linear_solve=_lane_solve)

    def per_device(u0, which, budget, n_problems, scaled, rows, shared, *, drain):
        return lanes(u0, which, budget, n_problems, rows, shared, scaled, drain=drain)

    # one queue per JAX device (one per core, `impedax._use_every_core`), one program for all
    static = (layout, n_free, n_lanes)
    queue, _ = over_devices(per_device, 5, drain=True, stored=("candidate-queue", static))

    def finish_one(u, row, shared):
        theta, z, j_re, j_im, r_re, r_im = parts(u, _combine(shared, row), False)
        chi2 = jnp.sum(r_re**2) + jnp.sum(r_im**2)
        return theta, jnp.where(jnp.isfinite(chi2), chi2, jnp.inf), jnp.concatenate([j_re, j_im], axis=1).T, z

    finish = StoredProgram("candidate-finish", static, jax.vmap(finish_one, in_axes=(0, 0, None)), compiler_options=QUICK_COMPILE)
    return queue, finish


def fit_candidates(
    circuits: Sequence[Circuit | str],
    data: xr.Dataset,
    *,
    init: Sequence[Mapping[str, float] | Sequence[Mapping[str, float]] | None] | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    weighting: str = "modulus",
    n_starts: int = 8,
    max_steps: int = 400,
    seed: int = 0,
    seeds: Sequence[int] | None = None,
    registry: Registry = DEFAULT_REGISTRY,
    shape: SolverShape | None = None,
    step_limit: int | None = None,
    damping: str | Sequence[str] = "marquardt",
) -> list[FitResult]:
    """Fit every circuit in ``circuits`` to the one spectrum ``data`` with one compiled solver.

    ``init[i]`` (optional) holds starting values for candidate i, e.g. a baseline fit's values
    plus a guess for an added element (warm start); remaining parameters are guessed from the
    data. ``init[i]`` may also be a list of such mappings: several warm starts (they replace the
    first random starts); when any candidate has starting values, every candidate also starts
    from the data-driven guess of its whole circuit (one start more: where `impedax.fit` of
    its model string begins). ``fixed`` values and ``bounds`` (name → (lower, upper), as
    `impedax.fit`'s) apply to candidates that have those parameters; every start (warm, from the
    data, random) lies strictly inside the bounds (`_inside`). The bounds are data of the compiled
    solver (`CandidateRow.lower`/``upper``), never part of its shape.
    Every start of every candidate runs Levenberg–Marquardt to convergence or ``max_steps``
    steps (``step_limit``, when given, lowers it) and each candidate keeps its best start.
    ``seeds``: one random-start seed per candidate (default ``seed`` for all). ``shape`` (a
    `SolverShape`: layout and K) fixes the compiled shapes, so calls with different circuits
    share one compilation. ``damping``: "marquardt" (Marquardt's scaling, the batch lanes'
    iteration) or "identity" (λI, as optimistix; docs/fitting.md, "Damping"), for every
    circuit or one per circuit; both run in the same compiled solver.
    Returns one `FitResult` per circuit, in order, exactly as `impedax.fit` would report them.
    """
    t0 = time.perf_counter()
    circuits = [parse(c, registry) for c in circuits]
    if not circuits:
        return []
    prepared, warm = _prepare(circuits, data, init, fixed, bounds, registry=registry)
    spectrum = prepared[0].data
    freq = np.asarray(spectrum["frequency"].values, float)
    z = np.asarray(spectrum["Z"].values, complex)
    sigma = np.asarray(spectrum["sigma"].values, float) if "sigma" in spectrum else None
    inv_re, inv_im = weights(z, sigma, weighting, prepared[0].source, freq)
    shape = (shape or solver_shape(circuits, registry, freq.size)).grown_to(circuits, registry, freq.size)
    layout = shape.layout
    k_pad = shape.n_free
    seeds = list(seeds) if seeds is not None else [seed] * len(circuits)
    if len(seeds) != len(circuits):
        raise FitError("seeds must give one seed per circuit")
    features = SpectrumFeatures(freq, z)
    # warm-started candidates also start from the data alone (one more start each, so every
    # row has the same number of starts)
    data_start = any((~np.isnan(problem.table.values) & ~problem.table.fixed).any() for problem in prepared)
    rows = [
        _candidate_row(problem, CircuitProgram.build(problem.circuit, registry, layout), extra, seed_i, features, n_starts=n_starts, k_pad=k_pad, registry=registry, data_start=data_start)
        for problem, extra, seed_i in zip(prepared, warm, seeds)
    ]
    dampings = [damping] * len(circuits) if isinstance(damping, str) else list(damping)
    if len(dampings) != len(circuits) or any(d not in DAMPINGS for d in dampings):
        raise FitError(f"damping must be one of {', '.join(DAMPINGS)}, or a list of them with one per circuit; got {damping!r}")
    budget = min(step_limit or max_steps, max_steps)
    scaled = np.array([d == "marquardt" for d in dampings])
    outputs = _solve(rows, _spectrum_args(freq, z, inv_re, inv_im, shape.n_freq), freq.size, layout, k_pad, budget, scaled)
    elapsed = (time.perf_counter() - t0) / len(rows)
    results = []
    (dominated,) = dominated_notes(weighting, freq, z, inv_re, inv_im)  # (the data's and the weighting's, every candidate alike, as impedax.fit warns)
    for problem, row, one in zip(prepared, rows, outputs):
        one = one._replace(x=one.x[row.flat], jacobian=one.jacobian[:, : row.n_free])
        # exchangeable blocks in the order every fit reports (docs/fitting.md), so a
        # candidate's R1 is the arc `impedax.fit` of its model from these values calls R1
        one = canonical_order(problem.circuit, problem.table, freq, one, registry)
        results.append(fit_result(problem.circuit, problem.table, freq, z, one, weighting, n_starts + data_start, elapsed, registry, extra_notes=dominated))  # (no misfit note: the data's and the weighting's alone, untagged; `FitResult.warning_tags` known)
    return results


def _spectrum_args(freq, z, inv_re, inv_im, n_padded: int) -> SpectrumArgs:
    """The shared arrays, padded to ``n_padded`` frequencies with zero weight (copies of the
    last point, `solvers.padded_points`), so spectra of similar length share one compilation."""
    return SpectrumArgs(*padded_points(freq, z, np.asarray(inv_re, float), np.asarray(inv_im, float), size=n_padded))


def _solve(rows: list["CandidateRow"], shared: SpectrumArgs, n_freq: int, layout: ProgramLayout, k_pad: int, budget: int, scaled: np.ndarray) -> list[SolverOutput]:
    """Every start of every candidate through the work queue (in calls of at most `_CAPACITY`
    problems), then each candidate's best start through the finishing pass (in calls of
    `_FINISH` candidates); ``scaled``: per candidate, Marquardt's scaling (else λI). Returns
    one `SolverOutput` per candidate (frequency padding removed)."""
    queue, finish = candidate_solver(layout, k_pad)
    n_starts = rows[0].starts.shape[0]
    n_devices = len(jax.devices())
    per_call = max(1, min(_CAPACITY, n_devices * _CAPACITY // n_starts))  # candidates per queue call
    u = np.zeros((len(rows), n_starts, k_pad))
    chi2 = np.full((len(rows), n_starts), np.inf)
    done = np.zeros((len(rows), n_starts), bool)
    steps = np.zeros((len(rows), n_starts), int)
    for lo in range(0, len(rows), per_call):
        part = rows[lo : lo + per_call]
        m = len(part) * n_starts
        starts = np.concatenate([r.starts for r in part])
        which_all = np.repeat(np.arange(len(part)), n_starts).astype(np.int32)
        scaled_all = np.repeat(scaled[lo : lo + len(part)], n_starts)
        # problem p on device p mod D: each device gets every candidate's starts alike
        mine = [np.arange(d, m, n_devices) for d in range(n_devices)]
        u0 = np.zeros((n_devices, _CAPACITY, k_pad))
        which = np.zeros((n_devices, _CAPACITY), np.int32)
        marquardt = np.ones((n_devices, _CAPACITY), bool)
        for d, idx in enumerate(mine):
            u0[d, : idx.size], which[d, : idx.size], marquardt[d, : idx.size] = starts[idx], which_all[idx], scaled_all[idx]
        counts = np.array([idx.size for idx in mine], np.int64)
        out = jax.device_get(queue(u0, which, np.full((n_devices, _CAPACITY), budget), counts, marquardt, _stack_rows(part, _CAPACITY), shared))
        got = []
        for a in out:
            flat = np.empty((m,) + a.shape[2:], a.dtype)
            for d, idx in enumerate(mine):
                flat[idx] = a[d, : idx.size]
            got.append(flat.reshape((len(part), n_starts) + a.shape[2:]))
        u[lo : lo + len(part)], chi2[lo : lo + len(part)], done[lo : lo + len(part)], steps[lo : lo + len(part)] = got
    chi2 = np.where(np.isfinite(chi2), chi2, np.inf)
    best = np.argmin(chi2, axis=1)
    u_best = u[np.arange(len(rows)), best]
    outputs = []
    for lo in range(0, len(rows), _FINISH):
        part = rows[lo : lo + _FINISH]
        at = np.zeros((_FINISH, k_pad))
        at[: len(part)] = u_best[lo : lo + len(part)]
        theta, chi2_best, jac, z_model = (np.asarray(a) for a in finish(at, _stack_rows(part, _FINISH), shared))
        for i in range(len(part)):
            c = lo + i
            b = best[c]
            outputs.append(trimmed(SolverOutput(
                x=theta[i], chi2=chi2_best[i], jacobian=jac[i], z_model=z_model[i],
                code=int(SolverStatus.CONVERGED if done[c, b] else SolverStatus.MAX_STEPS), steps=steps[c, b], chi2_starts=chi2[c], steps_total=int(steps[c].sum()),
            ), n_freq))
    return outputs


def _prepare(circuits, data, init, fixed, bounds, *, registry) -> tuple[list[FitProblem], list[list[dict]]]:
    """Each candidate's `FitProblem` (its first start as ``init``; the ``fixed`` values and
    ``bounds`` of its parameters) and its further warm starts, all inside its bounds."""
    init = list(init) if init is not None else [None] * len(circuits)
    if len(init) != len(circuits):
        raise FitError("init must give one mapping (or None) per circuit")
    prepared, warm = [], []
    spectrum = open_spectrum(data)
    for circuit, start in zip(circuits, init):
        names = circuit.parameter_names(registry)
        mine = {k: v for k, v in (fixed or {}).items() if k in names}
        limits = {k: v for k, v in (bounds or {}).items() if k in names}
        # (a table of the bounds alone checks them and places the warm starts inside them)
        bounded = ParameterTable.build(circuit, registry=registry, bounds=limits) if limits else None
        starts = [start] if start is None or isinstance(start, Mapping) else list(start)
        starts = [{k: v for k, v in (one or {}).items() if k in names and k not in mine} for one in starts] or [{}]
        warm.append([_inside(circuit, one, registry, bounded) for one in starts[1:]])
        prepared.append(fit_problem(circuit, spectrum, init=_inside(circuit, starts[0], registry, bounded), fixed=mine, bounds=limits or None, registry=registry))
    if prepared[0].data["Z"].ndim != 1:
        raise FitError("fit_candidates fits one spectrum; select or average the extra dimensions first")
    return prepared, warm


class CandidateRow(NamedTuple):
    """One candidate's arrays for the program solver: ``starts`` (S, K_pad) in the solver's
    space, the free parameters' positions in the flattened program ``free_index``, bounds and
    `Transform` kinds (padded to K_pad), all parameters ``x_fixed``, the program's arrays, and
    ``flat``: where the circuit's parameters sit in the flattened program."""

    starts: np.ndarray
    free_index: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    kind: np.ndarray
    x_fixed: np.ndarray
    program: dict
    flat: np.ndarray
    n_free: int


def _candidate_row(problem: FitProblem, program: CircuitProgram, warm: list[dict], seed: int, features: SpectrumFeatures, *, n_starts: int, k_pad: int, registry: Registry, data_start: bool = False) -> CandidateRow:
    """The data-driven guess, the warm starts and random starts of one candidate (``n_starts``
    in all), and with ``data_start`` one more: the data-driven guess of the whole circuit, the
    given starts left out; padded."""
    circuit, table = problem.circuit, problem.table
    layout = program.layout
    flat = np.array([s * 4 + i for s, i in (program.parameter_slots[n] for n in table.names)])
    x_fixed = default_theta(layout).ravel()
    guess = data_driven_guess(circuit, table, features, registry)
    x_fixed[flat] = guess
    x_fixed[flat[table.fixed]] = table.values[table.fixed]
    free = table.free_index
    k = free.size
    starts_x = random_starts(table, features, guess, n_starts, seed)
    for j, values in enumerate(warm[: n_starts - 1], start=1):
        starts_x[j] = guess
        for name, value in values.items():
            starts_x[j, table.names.index(name)] = value
    if data_start:
        # warm-started: one more start, the data-driven guess of the whole circuit (where
        # `impedax.fit` of the model string begins), so a candidate stalled behind its warm
        # starts still gets at least that (a Warburg added to a baseline that bent its arcs
        # around it: 2.6 % warm, 1.3 % from the data alone)
        blank = dataclasses.replace(table, values=np.where(table.fixed, table.values, np.nan))
        starts_x = np.concatenate([starts_x, random_starts(blank, features, data_driven_guess(circuit, blank, features, registry), 1, seed)])
    starts_x = starts_x[:, free]
    starts_u = np.zeros((starts_x.shape[0], k_pad))
    starts_u[:, :k] = to_internal(starts_x, table.lower[free], table.upper[free], table.kind[free])

    def pad(a, fill):
        return np.concatenate([a, np.full(k_pad - k, fill, dtype=np.asarray(a).dtype)])

    return CandidateRow(
        starts=starts_u, free_index=pad(flat[free].astype(np.int32), layout.n_slots * 4), lower=pad(table.lower[free], -np.inf),
        upper=pad(table.upper[free], np.inf), kind=pad(table.kind[free], Transform.IDENTITY), x_fixed=x_fixed,
        program=program.arrays(), flat=flat, n_free=k,
    )


def _stack_rows(rows: list[CandidateRow], capacity: int) -> CandidateRows:
    """The candidates' arrays stacked along a leading axis of ``capacity`` (padding repeats
    the first candidate; its results are never read)."""
    padded = rows + [rows[0]] * (capacity - len(rows))

    def stack(field):
        return np.stack([getattr(r, field) for r in padded])

    return CandidateRows(
        x_fixed=stack("x_fixed"), free_index=stack("free_index"), lower=stack("lower"), upper=stack("upper"), kind=stack("kind"),
        program={key: np.stack([r.program[key] for r in padded]) for key in rows[0].program},
    )


def _inside(circuit: Circuit, values: Mapping[str, float], registry: Registry, bounded: ParameterTable | None = None) -> dict[str, float]:
    """Warm starts nudged strictly inside their bounds (a fitted α may sit at exactly 1). With
    ``bounded`` (a table of the user's bounds), a start of a parameter bounded there is moved
    inside them as `impedax.fit` moves a batch's starts (`starts.values_inside`): one on a
    bound 1e-6 inside, one outside `starts.INSIDE_FRACTION` of the span inside (a start just
    inside sits where the logistic is flat, and the solver stops there)."""
    specs = circuit.parameter_specs(registry)
    out = {}
    for name, value in values.items():
        spec = specs[name]
        value = float(value)
        if not np.isfinite(value):
            continue
        if value <= spec.lower:
            value = spec.lower + max(abs(spec.lower) * 1e-6, 1e-12)
        if value >= spec.upper:
            value = spec.upper * (1 - 1e-6) if spec.upper > 0 else spec.upper - 1e-6
        out[name] = value
    if bounded is not None:
        narrowed = {n for n, lo, hi in zip(bounded.names, bounded.lower, bounded.upper) if lo != specs[n].lower or hi != specs[n].upper}
        out.update(values_inside({n: v for n, v in out.items() if n in narrowed}, bounded))
    return out
