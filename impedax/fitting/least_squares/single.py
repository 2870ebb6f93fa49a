"""Least-squares fitting of a circuit to a spectrum (or to many at once): `fit`.

`fit` returns a frozen `FitResult` for a one-dimensional spectrum and a `BatchFitResult` when
the data have extra dimensions (trial, subject, ...), which are fitted in one vmapped call.
"""

from __future__ import annotations

import dataclasses
import time
from typing import Callable, Mapping, Sequence

import jax
import xarray as xr
import numpy as np

from ...arguments import MAX_SOLVER_STEPS, MAX_STARTS, checked_arguments, choice, count, frequency, init_not_fixed, instance_of, parameter_bounds, parameter_values, seed as seed_rule
from ...circuits import Circuit, DEFAULT_REGISTRY, Registry
from ...data import counted
from ...errors import IN_MEMORY, ParameterError
from ...progress import PROGRESS_AFTER_S, progress_to, reports_progress, say
from ..kk import KKChains
from ..problem import WEIGHTINGS, check_argument_order, circuit_parameters, open_spectrum, prepare_fit, residual_scale, weights
from ..statistics import at_noise_floor, information_criteria
from .batch import BatchFitResult, data_notes, fit_batch, register_spectrum_fit
from .constraints import constraint_misfit_notes, with_constraint_notes
from .order import canonical_order
from .per_spectrum import has_per_spectrum_values, split_fits
from .notes import MISFIT, with_tag
from .result import BOUND_RESTARTS, FitResult, is_remainder, falling_inward, fit_result, sign_notes_first, unused_sigma_notes, with_warnings
from .shared import SharedFitResult, fit_shared, shared_layout
from .solvers import IDENTITY_DAMPING_STEPS, SCREEN_STEPS, SharedArgs, SolverStatus, SpectrumRows, better, padded_points, solver_args, tree_solver, trimmed, unscale
from .starts import KK_MISFIT_FACTOR, SpectrumFeatures, draw_size, draw_words, escalation_rungs, climb_target, guess_start, inward_start, limit_draw_count, limit_starts, rms_rel_of, rung_draws, rung_seed, to_solver_space

__all__ = ["fit", "FitResult", "BatchFitResult", "SharedFitResult", "WEIGHTINGS", "information_criteria"]


class FittedCircuits(set):
    """The (circuit, batch) pairs fitted in this process: the first fit's progress line says it
    compiles its solvers, the later ones not (a walkthrough read "compiles" on every warm run).
    ``impedax.clear_caches`` empties it with the compiled programs (`cache_clear`)."""

    def cache_clear(self) -> None:
        self.clear()


FITTED_CIRCUITS = FittedCircuits()


@reports_progress
@checked_arguments(
    circuit_parameters=circuit_parameters, init=parameter_values(results=True, per_spectrum=True), fixed=parameter_values(per_spectrum=True), bounds=parameter_bounds, weighting=choice(WEIGHTINGS),
    fmin=frequency, fmax=frequency, n_starts=count(1, MAX_STARTS, why="starts are solved together in memory"),
    max_steps=count(1, MAX_SOLVER_STEPS), seed=seed_rule, registry=instance_of(Registry),
)
def fit(
    circuit: Circuit | str,
    data: xr.Dataset | str,
    *,
    init: Mapping[str, float] | FitResult | BatchFitResult | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    weighting: str = "modulus",
    fmin: float | None = None,
    fmax: float | None = None,
    n_starts: int = 16,
    max_steps: int = 400,
    seed: int = 0,
    registry: Registry = DEFAULT_REGISTRY,
    shared: Sequence[str] | str | None = None,
    over: Sequence[str] | str | None = None,
    progress: Callable[[str], None] | None = None,
) -> FitResult | BatchFitResult:
    """Fit ``circuit`` to ``data`` by weighted least squares (Levenberg–Marquardt).

    Parameters are fitted in an unconstrained space (log for positive quantities, logistic
    for bounded ranges), float64. The data-driven guess (with any ``init`` values) is fitted
    first, alone. ``n_starts`` is the size of one draw of starts, a rung of the start ladder:
    the guess, (``n_starts`` − 1)//2 jittered copies of it and the rest drawn log-uniformly
    over ranges scaled to the data, screened side by side and the best continued to
    convergence. When the guess's fit is not at the noise (residuals not white, or no
    convergence) or took more than 50 steps, one draw is solved; while the best fit's rms_rel
    stays above `starts.KK_MISFIT_FACTOR` (1.2) × the misfit of a Kramers–Kronig-consistent
    model, 4 and then 16 new draws follow (and 64 more for circuits of 12 or more free
    parameters): up to 21 × ``n_starts`` starts (85 × for the large circuits), 336 by
    default, 42 for ``n_starts=2``; after a ladder, two starts more per element with a limit no
    step reaches (a Wo at τ → ∞ and at the limit's edge: `starts.limit_starts`). The best fit is kept; ``FitResult.n_starts`` says how many
    starts were used (1: the guess alone). ``n_starts=1`` fits the guess alone (in a batch:
    one local fit per spectrum). docs/fitting.md, "Starts".
    ``init`` gives starting values by name, or is a `FitResult` whose values start the
    parameters this circuit shares with it (e.g. refitting with one element added; a fit of a
    circuit nested in this one, a W where it has a Wo, starts the elements that stand for its
    own at its optimum, `nesting.carried_values`, so this fit ends no higher), or a
    `BatchFitResult` over the same dimensions and labels as ``data``: each spectrum starts from
    its own fitted values, carried alike (with ``n_starts=1``, one local fit each; in a batch of
    several spectra each is also solved from the default start and the lower fit kept;
    `BatchFitResult.per_spectrum_starts`).
    ``fixed`` pins parameters; ``bounds`` narrows them; a value of ``fixed`` or ``init`` may be an
    xarray.DataArray over some of the data's extra dimensions, labelled as the data, one value per
    spectrum (`per_spectrum.split_fits`: the spectra fitted in groups that share the values); ``weighting`` is one of `WEIGHTINGS`.
    ``data`` is a spectrum Dataset, a path or a (frequency, Z) pair of arrays. Extra dimensions
    (trial, subject, ...) are fitted together and give a `BatchFitResult`; dask-backed data are
    fitted chunk by chunk.
    ``shared`` (parameter names) with ``over`` (extra dimensions; may be left out when the data
    have one) fits one value of each shared parameter across ``over`` and per-spectrum values
    of the others in one global solve (`shared.fit_shared`), giving a `SharedFitResult`.
    Returns a `FitResult` for a single spectrum. Both results answer the same calls:
    ``summary()``, ``report()``, ``to_xarray()``, ``to_table()``, ``plot()`` and the notebook display.
    ``progress`` (e.g. ``print``) is called with a line of text as each stage begins: the fit,
    more starts, a batch's start search, its local fits, its outliers' starts and its statistics
    (a circuit's first batch in a process compiles its solvers: 10–15 s on the 130 REAL battery
    cycles); None (default): the lines go to stderr once the fit has
    run `progress.PROGRESS_AFTER_S` (2 s), as on the command line (`progress.reported`, in
    Python too); False: no lines.
    """
    check_argument_order("fit", circuit, data)
    if progress is not None:
        if not callable(progress):
            raise ParameterError(f"progress must be a function of one line of text (e.g. print), False (no lines) or None (lines on stderr once the fit has run {PROGRESS_AFTER_S:g} s), got {type(progress).__name__}")
        with progress_to(progress):
            return fit(circuit, data, init=init, fixed=fixed, bounds=bounds, weighting=weighting, fmin=fmin, fmax=fmax, n_starts=n_starts, max_steps=max_steps, seed=seed, registry=registry, shared=shared, over=over)
    t0 = time.perf_counter()
    init_not_fixed(init, fixed)
    if has_per_spectrum_values(fixed, init):  # one value per spectrum: the batch fitted in groups that share them
        if shared is not None or over is not None:
            raise ParameterError("fixed=/init=: one value per spectrum (a DataArray) is for a batch fit; a shared fit (shared=) takes one number per parameter: fit each group with data.sel(...) and its own value")
        spectrum = open_spectrum(data, fmin=fmin, fmax=fmax)
        return split_fits(fit, circuit, spectrum.data, spectrum.source, fixed=fixed, init=init, bounds=bounds, weighting=weighting, n_starts=n_starts, max_steps=max_steps, seed=seed, registry=registry)
    # a batch of fits (`BatchFitResult`): each spectrum of this batch starts from its own optimum
    batch_init, init = (init, None) if callable(getattr(init, "per_spectrum_starts", None)) else (None, init)
    problem = prepare_fit(circuit, data, init=init, fixed=fixed, bounds=bounds, fmin=fmin, fmax=fmax, registry=registry)
    circuit, data, table, source = problem.circuit, problem.data, problem.table, problem.source
    if n_starts < 1:
        raise ParameterError("n_starts must be at least 1")
    extra = [d for d in data["Z"].dims if d != "frequency"]
    starts = None
    if batch_init is not None:
        if shared is not None or over is not None:
            raise ParameterError("init: a BatchFitResult starts each spectrum of a batch fit from its own optimum; a shared fit (shared=) takes a mapping name → value or a FitResult")
        starts = batch_init.per_spectrum_starts(data, table.names, circuit)
    n_spectra = int(np.prod([data.sizes[d] for d in extra])) if extra else 1
    if shared is not None or over is not None:  # (checked before the first progress line, as every argument)
        shared_layout(table, extra, shared, over, source=source)
    first = (str(circuit), bool(extra)) not in FITTED_CIRCUITS
    FITTED_CIRCUITS.add((str(circuit), bool(extra)))
    say(f"fitting {circuit} to {counted(n_spectra, 'spectrum', 'spectra')} together" + (" (a circuit's first batch compiles its solvers)" if first else "") if extra
        else f"fitting {circuit}" + (" (a circuit's first fit compiles its solvers)" if first else ""))
    # σ the weighting does not use is said in the result (`unused_sigma_notes`), a batch's as a single fit's
    sigma_notes = unused_sigma_notes("sigma" in data, weighting)
    if shared is not None or over is not None:
        return dataclasses.replace(fit_shared(circuit, data, table, shared=shared, over=over, weighting=weighting, n_starts=n_starts, max_steps=max_steps, seed=seed, registry=registry, source=source, t0=t0), notes=sigma_notes)
    known_source = data_source(data)
    if extra:
        batch = fit_batch(circuit, data, table, weighting=weighting, n_starts=n_starts, max_steps=max_steps, seed=seed, registry=registry, source=source, t0=t0, starts=starts)
        return dataclasses.replace(batch, source=known_source, notes=sigma_notes)
    freq = np.asarray(data["frequency"].values, float)
    z = np.asarray(data["Z"].values, complex)
    sigma = np.asarray(data["sigma"].values, float) if "sigma" in data else None
    inv_re, inv_im = weights(z, sigma, weighting, source, freq)
    if not isinstance(max_steps, (int, np.integer)) or isinstance(max_steps, bool) or max_steps < 1:
        raise ParameterError(f"max_steps must be a positive integer, got {max_steps!r}")
    solvers = tree_solver(circuit, registry, int(max_steps), *table.free_structure)
    single = solvers.single
    scale = residual_scale(z, inv_re, inv_im, weighting)
    # solved on `padded_size` points (zero-weight copies of the last): nearby lengths share a compilation
    args = solver_args(table, *padded_points(freq, z, inv_re * scale, inv_im * scale))
    # the data-driven guess alone first; the multistart only when its fit is not at the noise,
    # and more starts while the fit stays poor relative to what the data allow
    features = SpectrumFeatures(freq, z)

    n_devices = len(jax.devices())
    # a start's screen is part of its fit: no longer than the step limit
    screen = min(SCREEN_STEPS, int(max_steps))

    # a draw's starts (`draw_size`: fewer than n_starts where every free parameter is given),
    # and the lanes a single start is repeated to, so that one compiled program serves both
    lanes = draw_size(table, n_starts)

    def solve(*draws, screen_steps=screen, continue_best=True):
        """One output per draw of starts (one start: the fit from it): the draw's starts
        screened for ``screen_steps`` steps and the best continued (``continue_best``; else
        the screen's best point). Each call of the solver runs one draw on every device (a
        device left without one takes no step), all calls dispatched before the first is
        awaited."""
        pending = []
        for first in range(0, len(draws), n_devices):
            group = [s if len(s) > 1 else np.repeat(s, lanes, axis=0) for s in draws[first : first + n_devices]]
            steps = [screen_steps if len(s) > 1 else 0 for s in draws[first : first + n_devices]]
            idle = n_devices - len(group)
            starts, steps = np.stack(group + group[:1] * idle), np.array(steps + [-1] * idle, np.int64)
            pending.append((draws[first : first + n_devices], single(starts, steps, args, np.bool_(continue_best))))
        outs = []
        for group, call in pending:
            for starts, out in zip(group, call.per_device()):
                if len(starts) == 1:  # the start repeated to the multistart's shape: one program serves both
                    out = out._replace(chi2_starts=np.zeros(1), steps_total=out.steps)
                outs.append(trimmed(unscale(out, scale), freq.size))
        return outs

    given = np.isfinite(table.values[table.free_index])
    start = "the given start" if given.all() and given.size else "the given start, the other parameters' from the data" if given.any() else "the data-driven start"
    guess_words = "the given start (the other parameters' from the data)" if given.any() and not given.all() else start  # (in a list of starts)
    (out,) = solve(guess_start(circuit, table, features, registry))
    used, at_limits = 1, 0  # (starts in all, and of them those at an element's limit)
    kk_chains = KKChains()  # (the KK test's chain, fitted once for the start ladder's target and the misfit notes)
    # the multistart also when the guess's fit took many steps: the guess was far from the
    # optimum it reached, which may be a local one (docs/fitting.md, "Starts")
    far = int(out.steps) > IDENTITY_DAMPING_STEPS
    if n_starts > 1 and (far or not at_noise_floor(freq, z, out.z_model, inv_re, inv_im, out.code)[()]):
        say(f"the fit from {start} is " + ("far from its start" if far else "not at the noise") + f": {lanes} starts (the start ladder's first draw: {draw_words(table, n_starts, guess_words, limit_draw_count(circuit, table, registry, n_starts))})")
        out, used = escalated(out, solve, circuit, table, features, freq, z, n_starts, seed, registry, int(max_steps), kk_chains)
        for limit_start in limit_starts(circuit, table, np.asarray(out.x)[None], freq, registry):  # (an element's limit no step reaches, as a batch's)
            (again,) = solve(guess_start(circuit, table, features, registry, starts=limit_start))
            out, used, at_limits = better(out, again), used + 1, at_limits + 1
    out = restarted_inward(out, lambda u: solve(u[None])[0], table, z, inv_re, inv_im, weighting, lambda o: one_spectrum_chi2(solvers.chi2_x, args, o))
    out = canonical_order(circuit, table, freq, out, registry)
    chi2_at_x = one_spectrum_chi2(solvers.chi2_x, args, out)
    # the data's notes as a batch gives them (`batch.data_notes`: one assembly for both paths),
    # `notes.Note`s whose tags are the fit's `FitResult.warning_tags`
    (notes,) = data_notes(freq, z[None], np.asarray(out.z_model)[None], None if sigma is None else sigma[None], weighting, source, kk_chains,
                          remainder=is_remainder(data.attrs), attrs=data.attrs, n_free=int(table.free_index.size))
    misfit = with_tag(notes, MISFIT)
    result = fit_result(circuit, table, freq, z, out, weighting, used, time.perf_counter() - t0, registry, chi2_at_x=chi2_at_x, extra_notes=notes, start=start, weights=(inv_re, inv_im),
                        starts_words=starts_words(table, n_starts, used, guess_words, at_limits, limit_draw_count(circuit, table, registry, n_starts)))
    # a misfit the user's fixed value or bound explains is told so, not blamed on the model (as a batch's)
    checked = constraint_misfit_notes(circuit, table, registry, freq, z, result.z_model, sigma, result.values, result.at_bound, misfit, kk_chains.misfit(0), weighting=weighting, fit=fit, attrs=data.attrs)
    if checked != misfit:  # (the constraint's note in its place, untagged: no misfit note, none that blames the model)
        result = with_warnings(dataclasses.replace(result, elapsed_s=time.perf_counter() - t0), with_constraint_notes(result.tagged_warnings, misfit, checked))
    return with_warnings(dataclasses.replace(result, source=known_source, notes=sigma_notes), sign_notes_first(result.tagged_warnings))


def data_source(data: xr.Dataset) -> str | None:
    """Where ``data`` came from, as its ``attrs["source"]`` says (`impedax.load`'s path, with any
    selection), or None for data built in memory (`make_spectrum`'s `IN_MEMORY`)."""
    source = data.attrs.get("source")
    return None if not isinstance(source, str) or source in ("", IN_MEMORY) else source


register_spectrum_fit(fit)  # (BatchFitResult.fit_of refits one spectrum with it)


def starts_words(table, n_starts: int, used: int, start: str, at_limits: int = 0, at_limit_in_draw: int = 0) -> str:
    """What the ``used`` starts of a fit were, after "best of {used} starts: " in its message:
    one draw of ``n_starts`` (`starts.draw_words`, ``start`` among them), and, where the start
    ladder climbed, that it escalated and why (the rule of `escalated`); the last
    ``at_limits`` of them are the best fit with an element moved to its limit
    (`starts.limit_starts`), said apart; ``at_limit_in_draw`` of each draw's random starts hold
    an element at its limit (`starts.limit_draw_count`).
    ``start``: the guess in a list ("the given start"). The message says that the given start
    is among them, and does not say "best of 336 starts" after a progress line of "draws of 16
    starts", nor "escalated to 338 (21 draws)" where the ladder's 21 draws of 16 are 336 and two
    more started at a G or Wo element's limit (REAL CHInstruments data, `R0 + G1`)."""
    draw = draw_words(table, n_starts, start, at_limit_in_draw)
    ladder = used - at_limits
    size = draw_size(table, n_starts)  # (the starts a draw runs: the given start once where nothing is jittered)
    limits = f"; and {at_limits} from the best fit with an element moved to its limit" if at_limits else ""
    if ladder <= size:
        return draw + limits
    return (f"the start ladder's first draw of {size}, escalated to {ladder} ({ladder // size} draws) as the best fit stayed above "
            f"{KK_MISFIT_FACTOR:g} × the misfit of a Kramers–Kronig-consistent model; each draw {draw}{limits}")


def escalated(out, solve, circuit, table, features, freq, z, n_starts: int, seed: int, registry, max_steps: int, kk_chains: KKChains | None = None):
    """The fit ``out`` improved by the start ladder (`starts.escalation_rungs`): ``n_starts``
    starts, then, while its rms_rel exceeds `starts.climb_target` (`KK_MISFIT_FACTOR` × the
    misfit of a Kramers–Kronig-consistent model), 4× and 16× as many (new draws each rung;
    64× more for circuits of `starts.LARGE_CIRCUIT_FREE` free parameters or more).
    ``solve(*draws, screen_steps, continue_best)`` runs the compiled multistart once per draw
    of starts (n_starts, K): a rung runs as several calls of that one shape, so climbing
    compiles nothing new. A rung of several draws screens each and continues the best point
    of every draw to convergence side by side, ``n_starts`` of them per call (one lane each:
    the lanes a draw's own continuation would leave idle); the best is kept. ``kk_chains``: the
    fit call's `kk.KKChains`, whose chain the target is read from. Returns (the best output, the
    number of starts used)."""
    calls, target = 0, None
    size = draw_size(table, n_starts)  # (the starts of one draw: the given start once where nothing is jittered)
    for rung, multiple in enumerate(escalation_rungs(len(table.free_names))):
        if rung:
            if target is None:
                target = climb_target(freq, z, None if kk_chains is None else kk_chains.misfits(freq, z[None], [0]))[0]
            rms_rel = float(rms_rel_of(out.z_model, z))
            if rms_rel <= target:
                break
            say(f"the best of {calls * size} starts misses the data by {rms_rel * 100:.3g} % rms_rel, above {target * 100:.2g} % "
                f"({KK_MISFIT_FACTOR:g} × the misfit of a Kramers–Kronig-consistent model): escalated to {(calls + multiple) * size} starts ({multiple} new draws of {size})")
        seeds = [rung_seed(seed, rung, call) for call in range(multiple)]
        draws = [to_solver_space(table, x) for x in rung_draws(circuit, table, features, n_starts, seeds, registry)]
        calls += multiple
        if multiple == 1:
            out = better(out, *solve(draws[0]))
            continue
        screened = to_solver_space(table, np.stack([s.x for s in solve(*draws, continue_best=False)]))
        groups = [screened[first : first + n_starts] for first in range(0, multiple, n_starts)]
        # (a group of at most `size` points runs on the draws' program, a larger one on n_starts lanes:
        # the groups, and so the point each continues, are those of a draw of n_starts either way)
        width = size if len(groups[0]) <= size else n_starts
        for continued in solve(*(np.resize(g, (width, g.shape[1])) for g in groups), screen_steps=max_steps):
            out = better(out, continued)
    return out, calls * size



def restarted_inward(out, solve_from, table, z, inv_re, inv_im, weighting: str, chi2_of):
    """``out`` (one spectrum's converged `SolverOutput`) restarted from inside its bounds while
    a parameter sits at a bound with chi² falling inward (`result.falling_inward`: the solver
    stopped where its bounded coordinate is flat, e.g. from a start clipped to the bound): the
    parameter moved by its Newton step along it alone, at least `starts.INSIDE_FRACTION` of
    its span inside (`starts.inward_start`), the others kept, solved again
    (``solve_from(u (K,))``, one start); kept where chi² is lower, at most `BOUND_RESTARTS`
    times (``chi2_of(out)``: the `one_spectrum_chi2` of an output, which measures the fall).
    The same rule as the batch's (`batch.restarted_inward`)."""
    for _ in range(BOUND_RESTARTS):
        if int(out.code) != SolverStatus.CONVERGED:
            break
        sides, step = falling_inward(table, np.asarray(out.x)[None], np.asarray(out.jacobian)[None], np.asarray(z)[None], np.asarray(out.z_model)[None], np.asarray(inv_re)[None], np.asarray(inv_im)[None], weighting, chi2_of(out))
        if not sides.any():
            break
        again = solve_from(to_solver_space(table, inward_start(table, np.asarray(out.x), sides[0], step[0])))
        if not float(again.chi2) < float(out.chi2):
            break
        out = better(out, again)._replace(steps_total=np.asarray(out.steps_total) + np.asarray(again.steps_total))
    return out


def one_spectrum_chi2(chi2_x, args, out):
    """``chi2_at_x(points (C, K), spectrum (C,))`` of one spectrum's solver ``args`` (for
    `result.confirm_bounds`): the solve's own ``bound_chi2`` where every point is among its
    ``bound_points`` (the solution, one free parameter moved to a bound: what the check asks
    for), else the compiled χ² program, points padded to a multiple of K + 1 rows (one
    compilation serves every call; needed only where `order.canonical_order` moved blocks)."""
    rows = SpectrumRows(args.z[None], args.inv_w_re[None], args.inv_w_im[None], args.x_fixed[None])
    shared = SharedArgs(args.freq, args.lower, args.upper)
    size = args.lower.size + 1
    known = {} if out.bound_points is None else {tuple(p): c for p, c in zip(np.asarray(out.bound_points).tolist(), np.asarray(out.bound_chi2).tolist())}

    def chi2_at_x(points, spectrum):
        found = [known.get(tuple(p)) for p in np.asarray(points, float).tolist()]
        if all(c is not None for c in found):
            return np.asarray(found, float)
        c = len(points)
        padded = -(-c // size) * size
        at = np.concatenate([points, np.repeat(points[:1], padded - c, axis=0)])
        return np.asarray(chi2_x(at, np.zeros(padded, np.int32), rows, shared))[:c]

    return chi2_at_x
