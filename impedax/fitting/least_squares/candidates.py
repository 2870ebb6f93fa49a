"""Fit many candidate circuits to one spectrum together, with one compilation.

Each candidate becomes a padded `CircuitProgram` of a shared `ProgramLayout`; programs,
parameter maps, bounds and starts travel as data, and the candidates are solved together
under ``vmap``. Candidate counts, free-parameter counts and layouts are padded to a few
bucket sizes, so a diagnosis pays one compilation (kept by JAX's persistent cache) whatever
circuits it proposes.
"""

from __future__ import annotations

import time
from typing import Mapping, NamedTuple, Sequence

import jax.numpy as jnp
import numpy as np
import xarray as xr

from ...circuits import Circuit, CircuitProgram, DEFAULT_REGISTRY, ProgramLayout, Registry, default_theta, parse
from ...errors import FitError
from ..parameters import Transform, to_internal
from ..problem import FitProblem, prepare_fit, weights
from .result import FitResult, fit_result
from .solvers import SolverArgs, SolverOutput, program_solver
from .starts import SpectrumFeatures, data_driven_guess, random_starts

__all__ = ["fit_candidates", "SolverShape", "solver_shape"]

_K_BUCKETS = (4, 8, 12, 16, 24, 32, 48)  # the Jacobian costs one model pass per column
_C_BUCKET = 8


def _bucket(n: int, buckets) -> int:
    """The smallest of ``buckets`` (ascending) that holds ``n``."""
    for b in buckets:
        if n <= b:
            return b
    raise FitError(f"too many free parameters ({n}) for a candidate fit")


class SolverShape(NamedTuple):
    """The padded shape of one compiled candidate solver: the program layout, the candidate
    count and the free-parameter count. Calls of `fit_candidates` with one shape share one
    compilation (the diagnosis keeps one for all its steps)."""

    layout: ProgramLayout
    n_candidates: int
    n_free: int

    def holds(self, circuits: Sequence[Circuit], registry: Registry) -> bool:
        """Whether every circuit fits in this shape's layout (so no new compilation is needed)."""
        need = ProgramLayout.covering(circuits, registry)
        return need.n_nodes <= self.layout.n_nodes and all(a <= b for a, b in zip(need.capacities, self.layout.capacities))


def solver_shape(circuits: Sequence[Circuit], registry: Registry = DEFAULT_REGISTRY) -> SolverShape:
    """The tightest shape that holds ``circuits`` (evaluation cost grows with the slot count),
    its counts rounded up to the buckets, so a diagnosis's candidate sets share it."""
    layout = ProgramLayout.covering(circuits, registry)
    n = -(-len(circuits) // _C_BUCKET) * _C_BUCKET
    k = _bucket(max(len(c.parameter_names(registry)) for c in circuits), _K_BUCKETS)
    return SolverShape(layout, n, k)


def fit_candidates(
    circuits: Sequence[Circuit | str],
    data: xr.Dataset,
    *,
    init: Sequence[Mapping[str, float] | Sequence[Mapping[str, float]] | None] | None = None,
    fixed: Mapping[str, float] | None = None,
    weighting: str = "modulus",
    n_starts: int = 8,
    max_steps: int = 400,
    seed: int = 0,
    seeds: Sequence[int] | None = None,
    registry: Registry = DEFAULT_REGISTRY,
    single_phase: bool = False,
    shape: SolverShape | None = None,
    step_limit: int | None = None,
) -> list[FitResult]:
    """Fit every circuit in ``circuits`` to the one spectrum ``data`` in a single vmapped call.

    ``init[i]`` (optional) holds starting values for candidate i, e.g. a baseline fit's values
    plus a guess for an added element (warm start); remaining parameters are guessed from the
    data. ``init[i]`` may also be a list of such mappings: several warm starts (they replace the
    first random starts). ``fixed`` values apply to candidates that have those parameters.
    ``single_phase`` runs every start to convergence with one compact Levenberg–Marquardt loop
    (no screening phase; compiles several times faster; meant for warm starts). ``seeds``: one
    random-start seed per candidate (default ``seed`` for all). ``shape`` (a `SolverShape`:
    layout, candidate count, free-parameter count) fixes the compiled shapes, so calls with
    different circuits can share one compilation; with ``single_phase``, ``step_limit``
    (≤ ``max_steps``) stops this call earlier without a new compilation. Returns one
    `FitResult` per circuit, in order, exactly as `impedax.fit` would report them.
    """
    t0 = time.perf_counter()
    circuits = [parse(c, registry) for c in circuits]
    if not circuits:
        return []
    prepared, warm = _prepare(circuits, data, init, fixed, registry=registry)
    spectrum = prepared[0].data
    freq = np.asarray(spectrum["frequency"].values, float)
    z = np.asarray(spectrum["Z"].values, complex)
    sigma = np.asarray(spectrum["sigma"].values, float) if "sigma" in spectrum else None
    inv_re, inv_im = weights(z, sigma, weighting, prepared[0].source)
    layout = shape.layout if shape is not None else ProgramLayout.covering(circuits, registry)
    k_pad = max(shape.n_free if shape is not None else 0, _bucket(max(int((~p.table.fixed).sum()) for p in prepared), _K_BUCKETS))
    seeds = list(seeds) if seeds is not None else [seed] * len(circuits)
    if len(seeds) != len(circuits):
        raise FitError("seeds must give one seed per circuit")
    features = SpectrumFeatures(freq, z)
    rows = [
        _candidate_row(problem, CircuitProgram.build(problem.circuit, registry, layout), extra, seed_i, features, n_starts=n_starts, k_pad=k_pad, registry=registry)
        for problem, extra, seed_i in zip(prepared, warm, seeds)
    ]
    n_real = len(rows)
    n_total = max(shape.n_candidates if shape is not None else 0, -(-n_real // _C_BUCKET) * _C_BUCKET)
    rows += [rows[-1]] * (n_total - n_real)  # pad the candidate count (results discarded)
    steps = min(step_limit or max_steps, max_steps) if single_phase else None
    starts, args = _stacked(rows, freq, z, inv_re, inv_im, steps)
    _, many = program_solver(layout, max_steps, bool(single_phase))
    out = SolverOutput(*(None if v is None else np.asarray(v) for v in many(starts, args)))
    elapsed = (time.perf_counter() - t0) / n_real
    results = []
    for i, (problem, row) in enumerate(zip(prepared, rows[:n_real])):
        one = out.row(i)
        one = one._replace(x=one.x[row.flat], jacobian=one.jacobian[:, : row.n_free])
        results.append(fit_result(problem.circuit, problem.table, freq, z, one, weighting, n_starts, elapsed, registry))
    return results


def _prepare(circuits, data, init, fixed, *, registry) -> tuple[list[FitProblem], list[list[dict]]]:
    """Each candidate's `FitProblem` (its first start as ``init``) and its further warm starts."""
    init = list(init) if init is not None else [None] * len(circuits)
    if len(init) != len(circuits):
        raise FitError("init must give one mapping (or None) per circuit")
    prepared, warm = [], []
    for circuit, start in zip(circuits, init):
        names = circuit.parameter_names(registry)
        mine = {k: v for k, v in (fixed or {}).items() if k in names}
        starts = [start] if start is None or isinstance(start, Mapping) else list(start)
        starts = [{k: v for k, v in (one or {}).items() if k in names and k not in mine} for one in starts] or [{}]
        warm.append([_inside(circuit, one, registry) for one in starts[1:]])
        prepared.append(prepare_fit(circuit, data, init=_inside(circuit, starts[0], registry), fixed=mine, bounds=None, fmin=None, fmax=None, registry=registry))
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


def _candidate_row(problem: FitProblem, program: CircuitProgram, warm: list[dict], seed: int, features: SpectrumFeatures, *, n_starts: int, k_pad: int, registry: Registry) -> CandidateRow:
    """The data-driven guess, the warm starts and random starts of one candidate, padded."""
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
    starts_x = starts_x[:, free]
    starts_u = np.zeros((n_starts, k_pad))
    starts_u[:, :k] = to_internal(starts_x, table.lower[free], table.upper[free], table.kind[free])

    def pad(a, fill):
        return np.concatenate([a, np.full(k_pad - k, fill, dtype=np.asarray(a).dtype)])

    return CandidateRow(
        starts=starts_u, free_index=pad(flat[free].astype(np.int32), layout.n_slots * 4), lower=pad(table.lower[free], -np.inf),
        upper=pad(table.upper[free], np.inf), kind=pad(table.kind[free], Transform.IDENTITY), x_fixed=x_fixed,
        program=program.arrays(), flat=flat, n_free=k,
    )


def _stacked(rows: list[CandidateRow], freq, z, inv_re, inv_im, max_steps: int | None) -> tuple[jnp.ndarray, SolverArgs]:
    """The candidates' starts and solver arguments stacked along a leading candidate axis;
    ``max_steps`` (single-phase solver) their step limit."""
    n = len(rows)

    def stack(field):
        return jnp.asarray(np.stack([getattr(r, field) for r in rows]))

    def spread(a):
        return jnp.broadcast_to(jnp.asarray(a), (n, np.size(a)))

    args = SolverArgs(
        freq=spread(freq), z=spread(z), inv_w_re=spread(inv_re), inv_w_im=spread(inv_im), x_fixed=stack("x_fixed"),
        free_index=stack("free_index"), lower=stack("lower"), upper=stack("upper"), kind=stack("kind"),
        model_args={key: jnp.stack([r.program[key] for r in rows]) for key in rows[0].program},
        max_steps=None if max_steps is None else jnp.full((n,), max_steps, jnp.int64),
    )
    return stack("starts"), args


def _inside(circuit: Circuit, values: Mapping[str, float], registry: Registry) -> dict[str, float]:
    """Warm starts nudged strictly inside their bounds (a fitted α may sit at exactly 1)."""
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
    return out
