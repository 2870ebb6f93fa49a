"""Where an emcee run's walkers start, the length of the run and the run itself, for single and
joint posteriors alike (`start_walkers`; `run_emcee`): a fixed number of steps, or
``steps="auto"``, which stops when the kept chain is `CHAIN_TAU_MULTIPLE` autocorrelation times
long and τ has settled (emcee's recipe, "Saving & monitoring progress"; docs/bayesian.md,
"Chain length"); straggler walkers are left out of the kept chain (`find_stragglers`)."""

from __future__ import annotations

import math
import time
from typing import Callable, Mapping, NamedTuple, Sequence

import numpy as np

from ...arguments import AUTO_MAX_STEPS as AUTO_MAX_STEPS, MAX_CHAIN_VALUES, MAX_SAMPLER_STEPS, count, shown
from ...errors import FitError, ParameterError
from .diagnostics import CHAIN_TAU_MULTIPLE, NO_STRAGGLERS, Stragglers, find_stragglers, integrated_autocorr
from .priors import UNDETERMINED_STDERRS, Prior, undetermined
from .progress import ProgressLine

__all__ = [
    "AUTO_STEPS", "AUTO_MAX_STEPS", "AUTO_CHECK_STEPS", "AUTO_TAU_CHANGE", "Chain", "ChainLength", "AUTO_MAX_CHAIN_NUMBERS", "steps_rule", "auto_step_cap", "run_emcee", "without_stragglers", "length_settings", "length_text", "capped_at",
    "START_MARGIN", "support_in_sampled_space", "inside_support", "ball_scales", "undetermined_span", "start_walkers",
]

AUTO_STEPS = "auto"

AUTO_CHECK_STEPS = 250
"""Steps between two estimates of τ in a ``steps="auto"`` run (emcee's recipe checks every 100;
each estimate costs an FFT of the whole kept chain, so the next one is also put off to the
steps the last estimate says are needed)."""

AUTO_TAU_CHANGE = 0.01
"""A ``steps="auto"`` run stops only when every parameter's τ changed by less than this
fraction since the previous estimate (emcee's recipe): τ estimated on a chain of ~50 τ is low
by 10–15 % on the examples, and with 2 % the runs stopped at 42–64 τ of the τ a 20 000-step chain
gives, with 1 % at 52–116 τ (docs/bayesian.md, "Chain length")."""


def steps_rule(value, name):
    """A run's ``steps`` (a `checked_arguments` rule): a count of steps, or ``"auto"``."""
    if isinstance(value, str):
        if value == AUTO_STEPS:
            return value
        raise ParameterError(f"{name} must be an integer, got {shown(value)} (str); or {AUTO_STEPS!r} to run until the chain is {CHAIN_TAU_MULTIPLE} τ long")
    return count(1, MAX_SAMPLER_STEPS, why="the chain is kept in memory")(value, name)


class Chain(NamedTuple):
    """What an emcee run leaves, after burn and thin, without its straggler walkers
    (``stragglers``, `find_stragglers`: the walkers left out, in the run's numbering)."""

    chain_y: np.ndarray  # (walker, draw, param), sampled space
    log_prob: np.ndarray  # (walker, draw)
    acceptance: np.ndarray  # (walker,)
    elapsed_s: float
    steps: int  # the steps run
    burn: int
    stopped: str | None  # steps="auto": "converged" or "cap"; None for a fixed length
    stragglers: Stragglers = NO_STRAGGLERS


AUTO_MAX_CHAIN_NUMBERS = 30_000_000
"""The most numbers (steps × walkers × (parameters + 1), float64: 240 MB) emcee keeps for a
``steps="auto"`` run: the battery circuit's 20 000 steps × 64 walkers × 10 are 12.8 M; a joint
posterior of 60 parameters and 240 walkers reaches it at 2 049 steps (20 000 would be 2.3 GB)."""


def auto_step_cap(walkers: int, n_params: int = 0) -> int:
    """The most steps a ``steps="auto"`` run of ``walkers`` over ``n_params`` sampled parameters
    takes: `AUTO_MAX_STEPS`, fewer where steps × walkers would pass `MAX_CHAIN_VALUES` or the
    chain `AUTO_MAX_CHAIN_NUMBERS` (a joint posterior of many parameters)."""
    walkers = max(int(walkers), 1)
    cap = min(AUTO_MAX_STEPS, MAX_CHAIN_VALUES // walkers, AUTO_MAX_CHAIN_NUMBERS // (walkers * (max(int(n_params), 0) + 1)))
    return max(1, cap)


class ChainLength:
    """When a ``steps="auto"`` run stops (emcee's recipe): every `AUTO_CHECK_STEPS` steps, τ of
    each parameter is estimated on the chain the run would keep (after ``burn``, default a
    quarter of the steps so far, and ``thin``; without the straggler walkers of that chain,
    `find_stragglers`) exactly as the `Posterior` will; the run stops
    when that chain is at least `CHAIN_TAU_MULTIPLE` τ long for every parameter and τ changed
    by less than `AUTO_TAU_CHANGE` since the previous estimate. While the chain is too short,
    the next estimate waits for the steps the last one says are needed."""

    def __init__(self, burn: int | None, thin: int):
        self.burn, self.thin = burn, thin
        self.next_check = AUTO_CHECK_STEPS
        self.previous: np.ndarray | None = None  # τ [steps] at the previous estimate
        self.needed: int | None = None  # the steps the last estimate says the run needs
        self.long = False  # the last estimate found the chain `CHAIN_TAU_MULTIPLE` τ long
        self.tau_change: float | None = None  # the largest relative change of τ at the last estimate (None: the first)

    def burn_of(self, steps: int) -> int:
        return steps // 4 if self.burn is None else self.burn

    def steps_needed(self, tau_steps: float) -> int:
        """The fewest steps whose kept chain (after `burn_of`) is `CHAIN_TAU_MULTIPLE` · τ long."""
        kept = CHAIN_TAU_MULTIPLE * max(tau_steps, self.thin)
        return int(math.ceil(kept * 4 / 3)) if self.burn is None else int(math.ceil(self.burn + kept))

    def long_enough(self, sampler, steps: int, *, last: bool = False) -> bool:
        """Whether the run may stop after ``steps`` (estimating τ when a check is due, or at
        the ``last`` step)."""
        if steps < self.next_check and not last:
            return False
        burn = self.burn_of(steps)
        if steps <= burn:
            self.next_check = burn + AUTO_CHECK_STEPS
            return False
        kept = np.transpose(sampler.get_chain(discard=burn, thin=self.thin), (1, 0, 2))
        # the walkers the posterior will keep (`without_stragglers`): a straggler stuck since its
        # start made every τ unknown, and one in a second mode lengthened it, so the run went on
        # to its cap, or far past the 50 τ of the chain it reports
        stragglers = find_stragglers(np.transpose(sampler.get_log_prob(discard=burn, thin=self.thin)), sampler.acceptance_fraction)
        if stragglers.walkers:
            kept = np.delete(kept, stragglers.walkers, axis=0)
        tau_draws = integrated_autocorr(kept)
        tau = tau_draws * self.thin
        known = bool(np.all(np.isfinite(tau)))
        long_enough = known and kept.shape[1] >= CHAIN_TAU_MULTIPLE * max(float(np.max(tau_draws)), 1.0)
        change = np.abs(tau - self.previous) / tau if known and self.previous is not None else None
        stable = change is not None and bool(np.all(change < AUTO_TAU_CHANGE))
        self.long, self.tau_change = long_enough, float(np.max(change)) if change is not None else None
        self.previous = tau
        self.next_check = steps + AUTO_CHECK_STEPS
        if known:
            self.needed = self.steps_needed(float(np.max(tau)))
            if not long_enough:
                self.next_check = max(self.next_check, -(-self.needed // AUTO_CHECK_STEPS) * AUTO_CHECK_STEPS)
        return long_enough and stable


def run_emcee(p0: np.ndarray, log_prob: Callable[[np.ndarray], np.ndarray], *, steps: int | str, burn: int | None, thin: int, seed: int, progress) -> Chain:
    """emcee's stretch move from ``p0`` (walkers, parameters) with ``log_prob`` (all walkers'
    coordinates → their log-probabilities, one vectorised call) over ``steps`` (or, ``"auto"``,
    until `ChainLength` says the chain is long enough, `auto_step_cap` steps at most); the chain
    after ``burn`` (None: a quarter of the steps run) and ``thin``, its straggler walkers left out
    (`without_stragglers`). Single and joint posteriors (`sample`, `sample_shared`) run through
    here."""
    import emcee

    walkers, n_params = p0.shape
    sampler = emcee.EnsembleSampler(walkers, n_params, log_prob, vectorize=True)
    sampler.random_state = np.random.RandomState(seed).get_state()
    auto = steps == AUTO_STEPS
    most = auto_step_cap(walkers, n_params) if auto else steps
    length = ChainLength(burn, thin) if auto else None
    bar = ProgressLine(most, progress, label=f"sampling (emcee, {walkers} walkers)", open_ended=auto)
    t0 = time.perf_counter()
    ran, converged = 0, False
    try:
        for ran, _ in enumerate(sampler.sample(p0, iterations=most, skip_initial_state_check=True), start=1):
            bar.update(ran)
            if length is not None and length.long_enough(sampler, ran, last=ran == most):
                converged = True
                bar.set_target(None, f"{CHAIN_TAU_MULTIPLE} τ reached, τ settled: done")
                break
            if length is not None and length.needed is not None:
                bar.set_target(*_length_goal(length, ran))
    finally:
        bar.close()
    elapsed = time.perf_counter() - t0
    burn = (ran // 4 if burn is None else burn) if auto else burn
    chain_y = np.transpose(sampler.get_chain(discard=burn, thin=thin), (1, 0, 2))  # (W, D, P)
    log_prob_kept = np.transpose(sampler.get_log_prob(discard=burn, thin=thin))
    stopped = ("converged" if converged else "cap") if auto else None
    return without_stragglers(Chain(chain_y, log_prob_kept, np.asarray(sampler.acceptance_fraction, float), elapsed, ran, burn, stopped))


def without_stragglers(chain: Chain) -> Chain:
    """``chain`` without its straggler walkers (`find_stragglers` on its kept log-probabilities),
    which it names in ``stragglers``; the very same chain when there are none."""
    stragglers = find_stragglers(chain.log_prob, chain.acceptance)
    if not stragglers.walkers:
        return chain
    kept = np.setdiff1d(np.arange(chain.log_prob.shape[0]), stragglers.walkers)
    return chain._replace(chain_y=chain.chain_y[kept], log_prob=chain.log_prob[kept], acceptance=chain.acceptance[kept], stragglers=stragglers)


def _length_goal(length: ChainLength, ran: int) -> tuple[int | None, str]:
    """What an auto run waits for, for its progress line: the steps its chain needs to be
    `CHAIN_TAU_MULTIPLE` τ long, or, once it is, τ to settle (`AUTO_TAU_CHANGE`)."""
    if not (length.long and ran >= length.needed):
        return length.needed, f"{CHAIN_TAU_MULTIPLE} τ"
    known = length.tau_change is not None and math.isfinite(length.tau_change)
    changed = f"changed {length.tau_change * 100:.1f} % at the last check" if known else "no earlier estimate yet"
    return None, f"{CHAIN_TAU_MULTIPLE} τ reached; waiting for τ to settle ({changed}, < {AUTO_TAU_CHANGE * 100:.0f} % stops)"


def length_settings(chain: Chain, walkers: int) -> dict:
    """How a run's length was chosen, for a posterior's ``settings``: ``steps_mode``
    (``"auto"``/``"fixed"``), and for ``"auto"`` ``step_cap`` and ``stopped``."""
    if chain.stopped is None:
        return {"steps_mode": "fixed"}
    return {"steps_mode": "auto", "step_cap": auto_step_cap(walkers, chain.chain_y.shape[-1]), "stopped": chain.stopped}


def length_text(settings: Mapping) -> str:
    """How the run's length was chosen, for a report's sampler line ("" for a fixed one)."""
    if settings.get("steps_mode") != "auto":
        return ""
    if settings.get("stopped") == "cap":
        return f"automatic: stopped at its cap of {settings.get('step_cap')} steps; "
    return f"automatic: stopped at {CHAIN_TAU_MULTIPLE} τ; "


def capped_at(settings: Mapping) -> int | None:
    """The cap an automatic run stopped at (for the chain-length warning), else None."""
    return settings.get("step_cap") if settings.get("stopped") == "cap" else None


# --- where the walkers start -------------------------------------------------------------------

START_MARGIN = 1e-9
"""How far inside a finite end of its support (relative, in the sampled space; at least this
much absolute) a walker starts: ln x rounds, and exp(ln b) can land just past b."""


def support_in_sampled_space(support: Sequence[tuple[float, float]], log_scale: Sequence[bool]) -> tuple[np.ndarray, np.ndarray]:
    """The prior supports (lo, hi] in the sampled space (ln x where ``log_scale``)."""
    lo_y = np.array([math.log(s[0]) if ls and s[0] > 0 else (-np.inf if ls else s[0]) for s, ls in zip(support, log_scale)])
    hi_y = np.array([math.log(s[1]) if ls else s[1] for s, ls in zip(support, log_scale)])
    return lo_y, hi_y


def inside_support(y: np.ndarray, lo_y: np.ndarray, hi_y: np.ndarray) -> np.ndarray:
    """Sampled coordinates ``y`` (…, P) strictly inside the supports (lo_y, hi_y): a coordinate
    past a finite end is reflected about it (walkers around a start at a bound stay spread on
    its inner side, not piled on the bound nor outside it, where the log-probability is −∞),
    then kept `START_MARGIN` inside both ends."""
    with np.errstate(invalid="ignore"):  # (the reflection about an infinite end, never taken)
        y = np.where(y < lo_y, 2 * lo_y - y, y)
        y = np.where(y > hi_y, 2 * hi_y - y, y)
    lo_in = lo_y + START_MARGIN * np.maximum(1.0, np.abs(np.where(np.isfinite(lo_y), lo_y, 0.0)))
    hi_in = hi_y - START_MARGIN * np.maximum(1.0, np.abs(np.where(np.isfinite(hi_y), hi_y, 0.0)))
    return np.clip(y, lo_in, np.maximum(hi_in, lo_in))


def ball_scales(start: Sequence[float], stderr: Sequence[float], log_scale: Sequence[bool]) -> np.ndarray:
    """The radius per parameter of the walkers' starting ball in the sampled space: 10 % of its
    relative standard error (its standard error when sampled linearly), within 1e-7…0.01; 0.001
    where the error is unknown."""
    rel = [e / abs(v) if ls else e for v, e, ls in zip(start, stderr, log_scale)]
    return np.array([0.1 * float(np.clip(r if math.isfinite(r) else 1e-2, 1e-6, 0.1)) for r in rel])


def undetermined_span(prior: Prior, lower: float, upper: float, start: float, stderr: float | None, at_bound: bool) -> tuple[float, float] | None:
    """The natural range over which the walkers of a log-sampled parameter (``lower`` ≥ 0) with a
    default prior start when the least-squares fit leaves it `undetermined`: from the bottom of
    the prior's support to the fit's value + `UNDETERMINED_STDERRS` standard errors (the top of
    the support when the error is not finite); None for a determined parameter (a small ball)."""
    if not (lower >= 0 and undetermined(lower, start, stderr, at_bound)):
        return None
    lo, hi = prior.support(lower, upper)
    top = min(hi, start + UNDETERMINED_STDERRS * stderr) if stderr is not None and math.isfinite(stderr) else hi
    return (lo, top) if 0 < lo < top else None


def _followers(covariance: np.ndarray, spread_over) -> dict[int, tuple[float, list[tuple[int, float]]]]:
    """For each widely spread parameter i: how far the linearisation reaches (`UNDETERMINED_STDERRS`
    standard errors √Σ_ii), and the other parameters j (not spread themselves) with their
    regression coefficient Σ_ji/Σ_ii in ``covariance`` (natural values; NaN: unknown)."""
    out: dict[int, tuple[float, list[tuple[int, float]]]] = {}
    for i in spread_over:
        var = covariance[i, i]
        if not (np.isfinite(var) and var > 0):
            continue
        rows = []
        for j in range(covariance.shape[0]):
            if j == i or j in spread_over:
                continue
            beta = covariance[j, i] / var
            if np.isfinite(beta) and beta != 0:
                rows.append((j, float(beta)))
        out[i] = (UNDETERMINED_STDERRS * math.sqrt(var), rows)
    return out


def start_walkers(
    start: Sequence[float], log_scale: Sequence[bool], ball: np.ndarray, *, walkers: int, seed: int, lo_y: np.ndarray, hi_y: np.ndarray,
    log_prob_one: Callable[[np.ndarray], float], log_prob_all: Callable[[np.ndarray], np.ndarray], where: str,
    wide: Sequence[tuple[float, float] | None] = (), covariance: np.ndarray | None = None,
) -> np.ndarray:
    """The walkers' start (walkers, P) in the sampled space, for single and joint posteriors: a
    small ball around the least-squares ``start`` (natural values; radii ``ball``, `ball_scales`),
    every walker strictly inside the supports (lo_y, hi_y) (`inside_support`).

    A parameter with a range in ``wide`` (natural values, log-sampled: an undetermined one,
    `undetermined_span`) is spread log-uniformly over it instead, and the other parameters follow
    it along the fit's ``covariance`` (P × P over the sampled parameters, natural values, NaN
    where unknown: their regression on it, x_j += Σ_ji/Σ_ii · Δx_i, with Δx_i within
    ±`UNDETERMINED_STDERRS`·√Σ_ii, where the linearisation describes the fit), so that walkers
    spread along a ridge such as R0 + R1 = const and not off it. Walkers whose log-probability is −∞, or (with
    a ``wide`` spread) below the start's by more than the 99.9 % quantile of χ²_P/2 (outside the
    typical set of a P-dimensional posterior peaked there), are moved halfway back towards the
    start (up to 30 times; then onto it). ``log_prob_one``/``log_prob_all``: the log-probability
    of one point / of all walkers; ``where`` names the start in the error raised when its
    log-probability is −∞. Deterministic for a ``seed``."""
    from scipy import stats

    log_scale = np.asarray(log_scale, bool)
    start = np.asarray(start, float)
    p = start.size
    y0 = np.where(log_scale, np.log(np.where(log_scale, start, 1.0)), start)
    rng = np.random.default_rng(seed)
    offsets = np.asarray(ball, float) * rng.normal(size=(walkers, p))
    spread_over = {i: span for i, span in enumerate(wide) if span is not None}
    target = {i: rng.uniform(math.log(span[0]), math.log(span[1]), size=walkers) for i, span in spread_over.items()}
    follow = _followers(np.full((p, p), np.nan) if covariance is None else np.asarray(covariance, float), spread_over)
    lo_in = np.where(np.isfinite(lo_y), inside_support(np.where(np.isfinite(lo_y), lo_y, 0.0), lo_y, hi_y), lo_y)  # (x_j ≤ 0: the lowest start inside)

    def place(frac: np.ndarray) -> np.ndarray:
        """The walkers a fraction ``frac`` (walkers,) of the way from the start to their draw."""
        y = y0 + offsets * frac[:, None]
        for i, u in target.items():
            y[:, i] = y0[i] + frac * (u - y0[i])
            reach, rows = follow.get(i, (0.0, ()))
            moved = np.clip(np.exp(y[:, i]) - start[i], -reach, reach)
            for j, beta in rows:
                x_j = (np.exp(y[:, j]) if log_scale[j] else y[:, j]) + beta * moved
                y[:, j] = np.where(x_j > 0, np.log(np.where(x_j > 0, x_j, 1.0)), lo_in[j]) if log_scale[j] else x_j
        return inside_support(y, lo_y, hi_y)

    lp_start = float(log_prob_one(y0))
    if not np.isfinite(lp_start):
        raise FitError(f"the log-probability is −∞ at {where} (model not finite there, or outside the priors); check the priors and the data")
    floor = lp_start - 0.5 * float(stats.chi2.ppf(0.999, p)) if spread_over else -np.inf
    frac = np.ones(walkers)
    p0 = place(frac)
    lp0 = np.asarray(log_prob_all(p0))
    for _ in range(30):
        bad = ~(np.isfinite(lp0) & (lp0 >= floor))
        if not bad.any():
            break
        frac[bad] *= 0.5
        p0 = place(frac)
        lp0 = np.asarray(log_prob_all(p0))
    else:
        bad = ~(np.isfinite(lp0) & (lp0 >= floor))
        at_start = place(np.zeros(walkers))[0]  # the start, moved inside the supports
        p0[bad] = at_start if np.isfinite(float(log_prob_one(at_start))) else y0
    return p0
