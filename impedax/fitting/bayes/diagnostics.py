"""Convergence diagnostics of an emcee chain: autocorrelation time, highest-density interval,
straggler walkers and the warnings a `Posterior` raises (straggler walkers left out, chain
length, acceptance, strong correlations, draws piled up against a prior's edge, a linearised
standard error far from the posterior's width)."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Mapping, NamedTuple, Sequence

import numpy as np
import xarray as xr

from ...arguments import CHAIN_TAU_MULTIPLE as CHAIN_TAU_MULTIPLE
from ...circuits import Circuit, Registry
from ...data import format_bound, format_factor, format_quantity, value_span
from ..derived import QUANTILES, mean_and_sd
from ..frozen import KeyHintDict, ReadOnlyDict
from ..reductions import reducing_bounds, series_shorts

__all__ = [
    "CHAIN_TAU_MULTIPLE", "ACCEPTANCE_STUCK", "GAUSSIAN_ACCEPTANCE", "CORRELATION_WARNING", "EDGE_BAND", "EDGE_DENSITY", "EDGE_MIN_DRAWS",
    "INTERVAL_RATIO_WARNING", "CORRELATION_ADVICE", "StrongCorrelation", "strong_correlations", "integrated_autocorr", "flat_acceptance", "acceptance_ceiling", "hdi", "chain_warnings", "PriorEdges", "prior_edges", "short_advice", "reducing_bounds", "user_bound_sides", "circuit_name", "WalkerDraws", "PiledUp",
    "acceptance_warnings", "interval_warnings", "tied_to_bound", "figure", "STRAGGLER_LOG_PROB_GAP", "Stragglers", "NO_STRAGGLERS", "find_stragglers", "straggler_warnings", "walkers_text", "kept_walkers",
]

ACCEPTANCE_STUCK = 0.15  # below: the walkers rarely move
GAUSSIAN_ACCEPTANCE = (0.807, 0.716, 0.647, 0.594, 0.551, 0.516, 0.486, 0.460, 0.438, 0.418, 0.399, 0.384, 0.368, 0.356, 0.344)
"""Mean acceptance of emcee's stretch move (a = 2, 64 walkers) on a d-dimensional Gaussian,
d = 1…15, measured with emcee (docs/bayesian.md, "Acceptance"): the same for correlated and
uncorrelated Gaussians (the move is affine-invariant) and for 2d + 2 walkers."""
CORRELATION_WARNING = 0.9
CORRELATION_ADVICE = "fix one or give it an informative prior"
"""The end of the correlation warning of `chain_warnings`: what `impedax sample` (``--fix``,
``--prior``) can do; a caller without those options (`impedax gap`) says its own after the
`StrongCorrelation.finding`, knowing the warning as `StrongCorrelation.warning`."""
EDGE_BAND = 0.02  # the outer 2 % of a prior's range (in its own coordinate) ...
EDGE_DENSITY = 0.5  # ... holding draws at least half as dense as over their central 90 %: piled up
EDGE_MIN_DRAWS = 20  # fewer draws in the band than this say nothing
EDGE_FLAT = 0.8  # ... or at least 0.8 times as dense as over the next 4 bands inward: the draws run flat to the edge ...
EDGE_FLAT_SHARE = 0.005  # ... with at least 0.5 % of the draws in the band, so that a wider prior would move the 5 % quantile
INTERVAL_RATIO_WARNING = 2.0
"""A linearised standard error more than this factor from the posterior's 68 % half-width (or
less than its inverse): the two disagree beyond what a well-sampled, locally Gaussian posterior
shows (0.97–1.05 on the BioLogic example; docs/bayesian.md, "Which interval to trust")."""
TIED_TO_BOUND_CORRELATION = 0.8
"""|r| in the least-squares fit's covariance from which a parameter counts as tied to one whose
fit is at a bound (`tied_to_bound`): the linearisation lets that one pass its bound and drags
this one's standard error along (REAL Gamry, R0 + R1 ∥ CPE1: R1 at r = −0.98 with R0 at 0;
REAL battery cycle 0: R1 at 0.90, R2 at −0.94 with CPE2.alpha at 1)."""

STRAGGLER_LOG_PROB_GAP = 20.0
"""A walker whose median log-probability over the kept draws lies more than this many nats below
the median of all walkers' medians is a straggler (`find_stragglers`): where it sits, the
posterior density is below e^-20 ≈ 2e-9 of where the others sit. A walker that mixes cannot lag
so far: a Gaussian posterior's log-probability lies χ²_d/2 below its peak, and even a single
draw's lies more than (χ²_d quantile 0.9999 − median)/2 below the median with probability
1e-4 — 7.3 nats for d = 1, 10.7 for 5, 16.5 for 20 (scipy.stats.chi2.ppf) — while a walker's
median over its draws is far tighter still (its spread falls as 1/√(draws/τ): at d = 60,
`MAX_JOINT_PARAMETERS`, a single draw's 99.99 % gap is 25 nats, but the median of just 5
independent draws has a standard deviation of 3.1). On the
BioLogic example (R0 + R1 ∥ CPE1, α ≥ 0.5, seed 2) the 61 healthy walkers' medians lie within
0.7 nats of one another and the 3 stragglers 56.5–58.0 nats below (docs/bayesian.md,
"Diagnostics")."""


class Stragglers(NamedTuple):
    """The straggler walkers of a run (`find_stragglers`), for its warning and its results:
    ``walkers`` their indices among the run's walkers, ``log_prob_gap`` how far [nats] each one's
    median log-probability lies below the median of all walkers' medians, ``acceptance`` their
    acceptance fractions, ``others_acceptance`` the median acceptance of the other walkers and
    ``draws`` the kept draws per walker (each straggler's left out of the posterior)."""

    walkers: tuple[int, ...] = ()
    log_prob_gap: tuple[float, ...] = ()
    acceptance: tuple[float, ...] = ()
    others_acceptance: float = math.nan
    draws: int = 0

    def to_attr(self) -> dict:
        """A netCDF/JSON attribute of plain numbers (`from_attr` reads it back)."""
        return {"walkers": list(self.walkers), "log_prob_gap": list(self.log_prob_gap), "acceptance": list(self.acceptance), "others_acceptance": self.others_acceptance if math.isfinite(self.others_acceptance) else None, "draws": self.draws}

    @classmethod
    def from_attr(cls, attr) -> "Stragglers":
        """`to_attr`'s dict back (None, from a file written by an older version: none)."""
        if not attr or not attr.get("walkers"):
            return NO_STRAGGLERS
        others = attr.get("others_acceptance")
        return cls(
            tuple(int(w) for w in attr["walkers"]), tuple(float(g) for g in attr["log_prob_gap"]), tuple(float(a) for a in attr["acceptance"]),
            math.nan if others is None else float(others), int(attr.get("draws", 0)),
        )


NO_STRAGGLERS = Stragglers()


def find_stragglers(log_prob: np.ndarray, acceptance: np.ndarray) -> Stragglers:
    """The walkers of ``log_prob`` (walker, draw: the kept chain's log-probabilities) whose median
    log-probability lies more than `STRAGGLER_LOG_PROB_GAP` below the median of all walkers'
    medians — walkers in a region of negligible posterior weight: a second mode, or stuck since
    their start — with their gaps and acceptance (``acceptance``: per walker), and the others'
    median acceptance (`Stragglers`). A walker at −∞ is one; fewer than half the walkers can be."""
    log_prob = np.asarray(log_prob, float)
    if log_prob.ndim != 2 or log_prob.shape[1] == 0:
        return NO_STRAGGLERS
    medians = np.median(log_prob, axis=1)
    with np.errstate(invalid="ignore"):
        gap = np.median(medians) - medians
        straggling = gap > STRAGGLER_LOG_PROB_GAP
    if not np.any(straggling):
        return NO_STRAGGLERS
    acceptance = np.asarray(acceptance, float)
    walkers = np.flatnonzero(straggling)
    return Stragglers(
        tuple(int(w) for w in walkers), tuple(float(g) for g in gap[walkers]), tuple(float(a) for a in acceptance[walkers]),
        float(np.median(acceptance[~straggling])), int(log_prob.shape[1]),
    )


def straggler_warnings(stragglers: Stragglers, n_walkers: int) -> list[str]:
    """The warning for a run's ``stragglers`` (`find_stragglers`) among its ``n_walkers``
    walkers: how many, how far below the others their log-probability lies, their acceptance
    against the others', that they sat where the posterior has no weight, and that their draws
    were left out."""
    if not stragglers.walkers:
        return []
    k = len(stragglers.walkers)
    gaps = [g for g in stragglers.log_prob_gap if math.isfinite(g)]
    gap_text = f"{value_span(gaps, '.1f')} nats" if gaps else "infinitely far"
    if len(gaps) < k and gaps:
        gap_text += " (or infinitely far)"
    weight = f"a relative posterior density of e^-{min(gaps):.0f} or less" if gaps else "zero posterior density"
    accepted = [a for a in stragglers.acceptance if math.isfinite(a)]
    acceptance = f"acceptance {value_span(accepted, '.3f')} against a median {stragglers.others_acceptance:.3f} for the others" if accepted and math.isfinite(stragglers.others_acceptance) else ""
    indices = ", ".join(str(w) for w in stragglers.walkers)
    return [
        f"{k} of {n_walkers} walkers (walker{'s' if k != 1 else ''} {indices}) {'are stragglers' if k != 1 else 'is a straggler'}: {'their' if k != 1 else 'its'} median log-probability lies {gap_text} below "
        f"the median of all walkers' (more than {STRAGGLER_LOG_PROB_GAP:g} nats)" + (f", {acceptance}" if acceptance else "")
        + f": {'they' if k != 1 else 'it'} sat in a region of negligible posterior weight ({weight}: a second mode, or walkers stuck since the start), "
        f"so {'their' if k != 1 else 'its'} {k * stragglers.draws} draws are left out of the posterior: every summary, interval, plot and saved draw is of the other {n_walkers - k} walkers"
    ]


def walkers_text(n_walkers: int, stragglers: Stragglers) -> str:
    """A report's count of walkers: the ``n_walkers`` whose draws make the posterior, or the run's
    with the ``stragglers`` left out ("64 walkers (3 stragglers left out)")."""
    k = len(stragglers.walkers)
    return f"{n_walkers} walkers" if not k else f"{n_walkers + k} walkers ({k} straggler{'s' if k != 1 else ''} left out)"


def kept_walkers(n_walkers: int, stragglers: Stragglers) -> np.ndarray:
    """The run's indices of the ``n_walkers`` walkers whose draws make the posterior (those not
    among ``stragglers``): 0 … n_walkers − 1 when there are none."""
    return np.setdiff1d(np.arange(n_walkers + len(stragglers.walkers)), np.asarray(stragglers.walkers, int))


def integrated_autocorr(chain_y: np.ndarray) -> np.ndarray:
    """Integrated autocorrelation time per parameter in stored draws of ``chain_y`` (walker,
    draw, param): emcee's estimator (``emcee.autocorr.integrated_time`` with c = 5, tol = 0:
    the walkers' mean normalised autocorrelation function, summed up to Sokal's window), one
    real FFT per parameter for all walkers at once, zero-padded to scipy's next fast length of
    2n − 1 (no wrap-around: the same function as emcee's power-of-two padding, to rounding).
    NaN (unknown) for a chain of fewer than
    `CHAIN_TAU_MULTIPLE` draws per walker — emcee's estimate needs a chain of ≳ 50 τ, and
    τ ≥ 1, so a shorter chain cannot support it (its estimate collapses towards 0: 2 draws give
    τ = 0) — and for a parameter in which some walker never moved over the kept draws (its
    autocorrelation is 0/0, or a rounding error of its mean)."""
    from scipy import fft

    n_walkers, n_draws, n_params = chain_y.shape
    if n_draws < CHAIN_TAU_MULTIPLE:
        return np.full(n_params, np.nan)
    n_fft = fft.next_fast_len(2 * n_draws - 1, real=True)
    window_factor = 5.0
    tau = np.empty(n_params)
    for p in range(n_params):
        x = np.ascontiguousarray(chain_y[:, :, p], dtype=float)  # (the same sums, to the last bit, whatever the layout)
        x = x - np.mean(x, axis=1, keepdims=True)
        spectrum = fft.rfft(x, n=n_fft, axis=1)
        acf = fft.irfft(spectrum.real**2 + spectrum.imag**2, n=n_fft, axis=1)[:, :n_draws]
        with np.errstate(divide="ignore", invalid="ignore"):
            rho = np.mean(acf / acf[:, :1], axis=0)
        taus = 2.0 * np.cumsum(rho) - 1.0
        inside = np.arange(n_draws) < window_factor * taus
        tau[p] = taus[int(np.argmin(inside)) if inside.any() else n_draws - 1]
    stuck = np.any(np.all(chain_y == chain_y[:, :1], axis=1), axis=0)  # per parameter: a walker that never moved
    return np.where(stuck, np.nan, tau)


def flat_acceptance(n_params: int) -> float:
    """Mean acceptance of the stretch move (a = 2) where the log-probability is flat over the
    walkers' moves: E[min(1, z^(d−1))] with z drawn from g(z) ∝ 1/√z on [1/2, 2], which is
    2 − √2 + (1 − 2^−(d − ½)) / ((d − ½)√2) (1 for d = 1, → 0.586 for large d)."""
    d = n_params
    return 2.0 - math.sqrt(2.0) + (1.0 - 2.0 ** -(d - 0.5)) / ((d - 0.5) * math.sqrt(2.0))


def acceptance_ceiling(n_params: int) -> float:
    """The mean acceptance above which a run of ``n_params`` parameters is closer to a flat
    log-probability (`flat_acceptance`) than to a Gaussian posterior (`GAUSSIAN_ACCEPTANCE`;
    beyond 15 parameters, the value measured at 15): the midpoint of the two."""
    gaussian = GAUSSIAN_ACCEPTANCE[min(max(n_params, 1), len(GAUSSIAN_ACCEPTANCE)) - 1]
    return 0.5 * (gaussian + flat_acceptance(max(n_params, 1)))


def figure(value: float, spec: str) -> str:
    """A number of a report formatted by ``spec``, or "—" when it is unknown (NaN)."""
    return format(value, spec) if math.isfinite(value) else "—"


def hdi(x: np.ndarray, mass: float = 0.9) -> tuple[float, float]:
    """Shortest interval holding ``mass`` of the draws."""
    x = np.sort(x)
    n = x.size
    k = max(int(math.ceil(mass * n)), 1)
    if k >= n:
        return float(x[0]), float(x[-1])
    widths = x[k - 1:] - x[: n - k + 1]
    i = int(np.argmin(widths))
    return float(x[i]), float(x[i + k - 1])


def draws_table(draws: Mapping[str, np.ndarray]) -> xr.Dataset:
    """median, q05, q16, q84, q95, mean, sd and the 90 % HDI (`hdi90_low`, `hdi90_high`) of
    each named parameter's draws, over dim ``param``."""
    table = {k: [] for k in (*QUANTILES, "mean", "sd", "hdi90_low", "hdi90_high")}
    for x in draws.values():
        x = np.asarray(x, float)
        for k, q in QUANTILES.items():
            table[k].append(float(np.quantile(x, q)))
        mean, sd = mean_and_sd(x)
        table["mean"].append(float(mean))
        table["sd"].append(float(sd))
        lo, hi = hdi(x)
        table["hdi90_low"].append(lo)
        table["hdi90_high"].append(hi)
    return xr.Dataset({k: ("param", v) for k, v in table.items()}, coords={"param": list(draws)})


def acceptance_warnings(mean_acceptance: float, n_params: int) -> list[str]:
    """A warning when the mean acceptance of the stretch move says the walkers rarely move
    (below `ACCEPTANCE_STUCK`) or that the log-probability barely changes across their moves
    (above `acceptance_ceiling` for ``n_params``). A healthy run accepts what a Gaussian
    posterior of its dimension does (`GAUSSIAN_ACCEPTANCE`: 0.81 for one parameter, 0.55 for
    five), and an affine-invariant move takes no "tiny steps"; near `flat_acceptance` the walkers
    stand much closer together than the posterior is wide: still spreading out from their start,
    or over a posterior the data leave flat (prior-dominated, unidentified)."""
    acc = mean_acceptance
    if acc < ACCEPTANCE_STUCK:
        return [f"mean acceptance fraction {acc:.3f} is below {ACCEPTANCE_STUCK}: the sampler is stuck (walkers rarely move: several modes, a narrow curved ridge, walkers left in a region of low probability, or many parameters the data leave flat within their priors)"]
    ceiling = acceptance_ceiling(n_params)
    if acc > ceiling:
        gaussian = GAUSSIAN_ACCEPTANCE[min(n_params, len(GAUSSIAN_ACCEPTANCE)) - 1]
        return [
            f"mean acceptance fraction {acc:.3f} is above {ceiling:.2f} (with {n_params} parameter{'s' if n_params != 1 else ''}, a Gaussian posterior gives {gaussian:.2f}, "
            f"a flat log-probability {flat_acceptance(n_params):.2f}): the log-probability barely changes across the walkers' moves — they are still spreading out from "
            "their start, or the data leave the posterior flat (prior-dominated): run more steps; see the prior-edge warnings"
        ]
    return []


@dataclass(frozen=True)
class StrongCorrelation:
    """Two sampled parameters of different elements whose draws correlate beyond
    `CORRELATION_WARNING` (`strong_correlations`): ``first`` and ``second`` their names, in the
    order they are sampled, ``r`` Pearson's correlation coefficient of their draws over all
    walkers in the sampled space — of their logarithms where ``log_space`` (both sampled in log)."""

    first: str
    second: str
    r: float
    log_space: bool

    @property
    def finding(self) -> str:
        """The warning without its advice: "R_EP and CPE_EP.Q are strongly correlated in the
        posterior (r = +0.972 in log space): the data constrain a combination of them"."""
        space = "log " if self.log_space else ""
        return f"{self.first} and {self.second} are strongly correlated in the posterior (r = {self.r:+.3f} in {space}space): the data constrain a combination of them"

    @property
    def warning(self) -> str:
        """The warning `chain_warnings` gives of it: the finding, then `CORRELATION_ADVICE`
        (a caller with advice of its own, `impedax gap`, knows the warning by this text)."""
        return f"{self.finding}; {CORRELATION_ADVICE}"

    def to_attr(self) -> dict:
        """A JSON object of plain values (``impedax sample --json``'s ``strong_correlations``)."""
        return {"first": self.first, "second": self.second, "r": self.r, "log_space": self.log_space}


def strong_correlations(names: Sequence[str], log_scale: Sequence[bool], chain_y: np.ndarray) -> tuple[StrongCorrelation, ...]:
    """The pairs of parameters of different elements whose draws ``chain_y`` (walker, draw,
    param; sampled space) correlate beyond `CORRELATION_WARNING` (|r|, Pearson over all walkers'
    draws), in the order of ``names``. Parameters of one element (a CPE's Q and α: correlated
    yet well determined) are left out; none from 2 draws or fewer, or one parameter."""
    ys = chain_y.reshape(-1, len(names))
    if ys.shape[0] <= 2 or len(names) < 2:
        return ()
    with np.errstate(all="ignore"):
        corr = np.corrcoef(ys, rowvar=False)
    out = []
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            same_element = names[i].split(".")[0] == names[j].split(".")[0]
            if np.isfinite(corr[i, j]) and abs(corr[i, j]) > CORRELATION_WARNING and not same_element:
                out.append(StrongCorrelation(names[i], names[j], float(corr[i, j]), bool(log_scale[i] and log_scale[j])))
    return tuple(out)


def chain_warnings(
    names: Sequence[str],
    log_scale: Sequence[bool],
    chain_y: np.ndarray,
    autocorr_steps: Mapping[str, float],
    thin: int,
    mean_acceptance: float,
    *,
    step_cap: int | None = None,
    steps: int | None = None,
) -> list[str]:
    """Warnings about a chain ``chain_y`` (walker, draw, param; sampled space): shorter than
    `CHAIN_TAU_MULTIPLE` autocorrelation times (``autocorr_steps`` in sampler steps; with
    ``step_cap``, the cap at which the automatic chain length stopped, the warning says so;
    with ``steps``, the steps the run took, it says about how many would do: `steps_needed`),
    mean acceptance below `ACCEPTANCE_STUCK` or above `acceptance_ceiling`, pairs of
    parameters of different elements correlated beyond `CORRELATION_WARNING`
    (`strong_correlations`, each `StrongCorrelation.warning`)."""
    out = []
    n_draws = chain_y.shape[1]
    taus = {n: t / thin for n, t in autocorr_steps.items()}
    finite = {n: t for n, t in taus.items() if np.isfinite(t)}
    capped = f" (the automatic chain length stopped at its cap of {step_cap} steps)" if step_cap else ""
    if n_draws < CHAIN_TAU_MULTIPLE:
        out.append(
            f"the chain is too short to estimate τ ({kept_draws_text(n_draws, thin)}; emcee needs ≳ {CHAIN_TAU_MULTIPLE} τ, "
            f"and τ is at least one draw){capped}: τ and ESS are unknown and the intervals are not to be trusted; {more_draws_advice(thin)}"
        )
    elif len(finite) < len(taus):
        stuck = int(np.sum(np.all(chain_y == chain_y[:, :1], axis=(1, 2))))
        unknown = [n for n in taus if n not in finite]
        out.append(
            f"τ of {', '.join(unknown)} could not be estimated"
            + (f": {stuck} of {chain_y.shape[0]} walkers never moved over the {n_draws} kept draws (stuck walkers)" if stuck else "")
            + f"{capped}; τ and ESS are unknown there: run more steps or check the start"
        )
    if finite:
        worst = max(finite, key=finite.get)
        if n_draws < CHAIN_TAU_MULTIPLE * finite[worst]:
            out.append(
                f"the chain ({n_draws} draws per walker after burn-in) is shorter than {CHAIN_TAU_MULTIPLE} autocorrelation times "
                f"(τ = {finite[worst] * thin:.3g} steps for {worst}){capped}: run more steps before trusting the intervals"
                + (steps_advice(steps_needed(steps, n_draws, finite[worst]), capped=bool(step_cap)) if steps else "")
            )
    out.extend(acceptance_warnings(mean_acceptance, len(names)))
    out.extend(c.warning for c in strong_correlations(names, log_scale, chain_y))
    return out


def kept_draws_text(n_draws: int, thin: int) -> str:
    """"37 draws per walker after burn-in and thinning by 40" (", and thinning" only when ``thin`` > 1)."""
    return f"{n_draws} draw{'s' if n_draws != 1 else ''} per walker after burn-in" + (f" and thinning by {thin}" if thin > 1 else "")


def more_draws_advice(thin: int) -> str:
    """What to run for more kept draws: more steps, or (``thin`` > 1) a smaller thin, which keeps
    more of the steps already run (a thinned chain long in steps has few draws: REAL-sized
    SYNTHETIC R0 + R1 ∥ C1, 2000 steps thinned by 40, kept 37 per walker, 2026-12-06)."""
    return "run more steps" if thin <= 1 else "thin less (thin=) or run more steps"


def steps_needed(steps: int, n_draws: int, tau_draws: float) -> int:
    """About the steps a run like this one (``steps`` steps, ``n_draws`` kept per walker) needs
    for a kept chain of `CHAIN_TAU_MULTIPLE` τ (``tau_draws``, in kept draws): its steps scaled by
    50 τ over the draws kept, burn-in and thinning in proportion (exact for the default burn of a
    quarter; a fixed burn needs fewer), rounded up to 500. τ estimated on a short chain runs low
    (docs/bayesian.md, "Why 1 %"), so this is a least."""
    return int(math.ceil(steps * CHAIN_TAU_MULTIPLE * tau_draws / max(n_draws, 1) / 500.0) * 500)


def steps_advice(needed: int, *, capped: bool) -> str:
    """The chain-length warning's advice, a number of steps to run: a fixed length (beyond the
    automatic one's cap, when it stopped there), or the automatic length, which stops at 50 τ; in
    Python's words, which the command line says as --steps (`cli.common._phrased`)."""
    if capped:
        return f" — a fixed length beyond the automatic cap, at least about {needed} (steps={needed}; τ estimated on a short chain runs low)"
    return (f" — steps='auto' (the default), which runs until the chain is {CHAIN_TAU_MULTIPLE} τ long, or a fixed length of at least about {needed} "
            f"(steps={needed}; τ estimated on a short chain runs low)")


class PriorEdges(NamedTuple):
    """The parameters whose draws pile up against an edge of their prior (`prior_edges`):
    ``piled_up`` maps each to its side ("lower", "upper" or "both"), ``warnings`` says it in
    words, one warning per side; ``at_reduction`` names those piled up only at the bound where
    their element is a simpler one (a CPE's alpha at 1: the data are consistent with that element)."""

    warnings: list[str]
    piled_up: dict[str, str]
    at_reduction: frozenset[str] = frozenset()


def user_bound_sides(user_bounds: Mapping[str, tuple[float, float]], circuit: Circuit, registry: Registry) -> dict[str, frozenset[str]]:
    """{parameter: sides} of the bounds the user narrowed (``bounds=``, ``--bound``) that are
    not the element's own: ``R1=:10M`` narrows only R1's "upper" side (its lower is the
    element's 0), ``CPE1.alpha=0.5:1`` only the "lower" (1 is the CPE's own):
    `ParameterSpec.narrowed_sides`."""
    specs = circuit.parameter_specs(registry)
    out = {}
    for n, (lo, hi) in user_bounds.items():
        if n not in specs:
            continue
        sides = specs[n].narrowed_sides(lo, hi)
        if sides:
            out[n] = sides
    return out


def prior_edges(
    names: Sequence[str],
    units: Sequence[str],
    draws: np.ndarray,
    priors: Mapping,
    lower: Sequence[float],
    upper: Sequence[float],
    reductions: Mapping[str, tuple[str, str]] | None = None,
    bound_causes: Mapping[str, str] | None = None,
    user_sides: Mapping[str, frozenset[str]] | None = None,
    shorts: Mapping[str, tuple[str, str]] | None = None,
) -> PriorEdges:
    """The parameters whose posterior piles up against an edge of their prior, as data and as
    a warning for each (`PriorEdges`).

    In the prior's own coordinate t = F(x) (its cumulative probability: linear for a uniform
    prior, log for a log-uniform one), the prior is flat on [0, 1] and the posterior's density is
    proportional to the likelihood. Draws are piled up against an edge when the band of
    `EDGE_BAND` of t next to it (or a tenth of the draws' central 90 % interval in t, when that
    is narrower) holds them at least `EDGE_DENSITY` times as densely as that central interval
    does, or (a flat tail) holds at least `EDGE_FLAT_SHARE` of them at least `EDGE_FLAT` times as
    densely as the four bands next to it: the likelihood has not fallen off by the edge, so the
    prior (or, where the edge is the parameter's own bound, the bound) and not the data sets that
    side of the interval.
    ``draws`` are flat natural values (sample, param); ``lower``/``upper`` the parameters' bounds.
    ``reductions`` (`reducing_bounds`): parameters whose bound makes their element a simpler
    one; piled up there, the data are consistent with that simpler element (a CPE's alpha at 1
    is a capacitor, and alpha > 1 is not physical), not asking for values beyond the bound.
    ``bound_causes``: {parameter: words} for parameters whose bounds follow an input (a gap
    thickness's follow the area, `Reparametrization.bound_causes`); piled up at such a bound,
    the warning points at that input, not at the model.
    ``user_sides`` (`user_bound_sides`): the sides of parameters' bounds the user set; piled up
    there, the warning names the user's bound as what sets that end (the data want values beyond
    it), never a reduction, which holds only at the element's own bound (a CPE's α piled up at a
    user's 0.78 is no capacitor).
    ``shorts`` (`short_advice`): {parameter: (side, words)} of parameters whose element, a term
    of a series chain, is a short beyond that side (a W's σ → 0); piled up there at the prior's
    end or the element's own bound, the warning names the circuit without that element.
    """
    reductions, bound_causes, user_sides, shorts = reductions or {}, bound_causes or {}, user_sides or {}, shorts or {}
    out, piled_up, at_reduction = [], {}, set()
    for i, n in enumerate(names):
        prior = priors[n]
        x = np.asarray(draws[:, i], float)
        t = prior.cdf(x, lower[i], upper[i])
        t = t[np.isfinite(t)]
        if t.size < EDGE_MIN_DRAWS:
            continue
        t05, t95 = np.quantile(t, [0.05, 0.95])
        central = t95 - t05
        if not central > 0:
            continue
        band = min(EDGE_BAND, central / 10)
        lo, hi = prior.support(lower[i], upper[i])
        for side, share, inward, end, bound, q, beyond in (
            ("lower", np.mean(t <= band), np.mean((t > band) & (t <= 5 * band)), lo, lower[i], np.quantile(x, 0.05), "smaller"),
            ("upper", np.mean(t >= 1 - band), np.mean((t < 1 - band) & (t >= 1 - 5 * band)), hi, upper[i], np.quantile(x, 0.95), "larger"),
        ):
            if share * t.size < EDGE_MIN_DRAWS:
                continue
            dense = (share / band) >= EDGE_DENSITY * (0.9 / central)
            # (a flat tail to the edge: REAL Autolab's W1.sigma of R0 + CPE1 ∥ (R1 + W1), 2.9 % of its draws in the lowest 2 % of its
            # log-uniform prior as densely as in the next 8 %, just below the dense rule, its q05 = 5.8 µΩ s^-1/2 the prior's)
            flat = share >= EDGE_FLAT_SHARE and inward > 0 and (share / band) >= EDGE_FLAT * (inward / (4 * band))
            if not (dense or flat):
                continue
            piled_up[n] = "both" if n in piled_up else side
            where = f"{100 * share:{'.0f' if dense else '.2g'}} % of the draws lie in the {'lowest' if side == 'lower' else 'highest'} {100 * band:.2g} % of its prior's range" + (" (log scale)" if prior.kind == "loguniform" else "" if prior.bounded else " (by prior mass)")
            if not dense:
                where += f", as densely as in the {100 * 4 * band:.2g} % next to them: the draws run flat to the edge"
            at = format_bound(end, units[i])  # (the bound and q as the report writes quantities: 10 kΩ, not 10000 Ω)
            interval = f"the {side} end of its 90 % interval ({'q05' if side == 'lower' else 'q95'} = {format_quantity(q, units[i])})"
            if not prior.bounded:
                out.append(f"{n} follows its prior {prior} into the {side} tail ({where}): the data do not cut that tail off, so the prior, not the data, sets {interval}")
            elif end == bound and side in user_sides.get(n, ()):
                out.append(
                    f"{n} piles up against its {side} bound {at}, the bound you set (bounds=) ({where}): your bound, not the data, sets {interval}; "  # (impedax sample: "(--bound)", `cli.common.command_line_words`)
                    f"the data want {beyond} values — widen {n}'s bound if they are plausible"
                )
            elif end == bound and reductions.get(n, ("",))[0] == side:
                at_reduction.add(n)
                out.append(f"{n} piles up against its {side} bound {at} ({where}): the bound, not the data, sets {interval}; the data are consistent with {n} = {at}, and {reductions[n][1]}")
            elif end == bound and n in bound_causes:
                out.append(f"{n} piles up against its {side} bound {at} ({where}): the bound, not the data, sets {interval}; the data would take {beyond} values. {bound_causes[n]}")
            elif end == bound:
                shorted = shorts.get(n, ("",))[0] == side
                out.append(f"{n} piles up against its {side} bound {at} ({where}): the bound, not the data, sets {interval}; the data would take {beyond} values"
                           + (f"; {shorts[n][1]}" if shorted else " (is the model missing something?)"))
            else:
                out.append(
                    f"{n} piles up against the {side} end of its prior {prior} ({where}): the prior, not the data, sets {interval}; "
                    f"the data allow {beyond} values — give {n} a prior that says how {'small' if side == 'lower' else 'large'} it can be"
                    + (f"; {shorts[n][1]}" if shorts.get(n, ("",))[0] == side else "")
                )
    return PriorEdges(out, piled_up, frozenset(n for n in at_reduction if piled_up[n] != "both"))



def short_advice(circuit: Circuit, registry: Registry, values: Mapping[str, float], freq) -> dict[str, tuple[str, str]]:
    """{parameter: (side, words)} for `prior_edges`'s ``shorts``: the parameters whose element,
    a term of a series chain, is a short beyond that side (`reductions.series_shorts`, the
    element's other parameters at ``values``, at the frequencies ``freq``), with the circuit
    without it, as a user would type it. On REAL exampleDataBioLogic.mpt with
    R0 + R1 || CPE1 + W1, W1.sigma piles up at its prior's lower end, where a warning without it would ask only
    for a prior that says how small it can be."""
    specs = circuit.parameter_specs(registry)
    out = {}
    for n, (side, element, reduced) in series_shorts(circuit, registry, values, freq).items():
        bound = specs[n].lower if side == "lower" else specs[n].upper
        limit = "∞" if bound == math.inf else format_quantity(bound, specs[n].unit) if bound else "0"
        out[n] = (side, f"{element} tends to a short as {n} → {limit} (its impedance vanishes), so the data may need no {element}: try the model without it, {reduced}")
    return out


def circuit_name(name: str) -> str:
    """The circuit parameter of a sampled name: a joint posterior's per-spectrum ``R2[cycle=64]``
    → ``R2``; any other name (``R2``, ``u``, ``sigma_rel``) is its own."""
    return name.split("[")[0]


class WalkerDraws:
    """The views of an emcee run's draws shared by `Posterior` and `SharedPosterior` (they hold
    ``circuit``, ``names``, ``log_scale``, ``draws`` (walker, draw, param), ``acceptance`` and
    ``settings``): sizes, flat samples, the acceptance, τ, the effective sample size, whether the
    chain is long enough, and the strongly correlated pairs."""

    @property
    def model(self) -> str:
        return str(self.circuit)

    @property
    def n_walkers(self) -> int:
        return int(self.draws.shape[0])

    @property
    def n_draws(self) -> int:
        return int(self.draws.shape[1])

    @property
    def samples(self) -> KeyHintDict:
        """Flat draws (after burn and thin) by sampled-parameter name: a new dict at each call,
        whose missing key names the keys there are (`MissingKey`, as ``fit.values``')."""
        flat = self.draws.reshape(-1, len(self.names))
        return KeyHintDict((n, flat[:, i]) for i, n in enumerate(self.names))

    @property
    def mean_acceptance(self) -> float:
        return float(np.mean(self.acceptance))

    @functools.cached_property
    def _sampled_space(self) -> np.ndarray:
        return np.where(np.asarray(self.log_scale), np.log(np.where(np.asarray(self.log_scale), self.draws, 1.0)), self.draws)

    @functools.cached_property
    def autocorr(self) -> ReadOnlyDict:
        """Integrated autocorrelation time per parameter [sampler steps] (emcee, tol=0); NaN when
        the chain is too short to estimate it (`integrated_autocorr`). Kept by the result, so
        read-only as its other mappings (``post.autocorr["R1"] = 0`` changed its Dataset)."""
        tau = integrated_autocorr(self._sampled_space) * self.settings.get("thin", 1)
        return ReadOnlyDict((n, float(t)) for n, t in zip(self.names, tau))

    @functools.cached_property
    def ess(self) -> ReadOnlyDict:
        """Effective sample size per parameter: walkers × draws / τ (τ in stored draws, ≥ 1);
        read-only, as `autocorr`."""
        tau = np.maximum(integrated_autocorr(self._sampled_space), 1.0)
        return ReadOnlyDict((n, float(self.n_walkers * self.n_draws / t)) for n, t in zip(self.names, tau))

    @property
    def chain_converged(self) -> bool:
        """Whether the kept chain is at least `CHAIN_TAU_MULTIPLE` autocorrelation times long for
        every parameter (τ known for all)."""
        tau = np.asarray([self.autocorr[n] for n in self.names], float) / self.settings.get("thin", 1)
        return bool(np.all(np.isfinite(tau)) and self.n_draws >= CHAIN_TAU_MULTIPLE * max(float(np.max(tau)), 1.0))

    @functools.cached_property
    def strong_correlations(self) -> tuple[StrongCorrelation, ...]:
        """The pairs of sampled parameters the correlation warnings name, as data: names and
        Pearson's r in the sampled space (`diagnostics.strong_correlations` of the draws the
        warnings read; each warning is the pair's `StrongCorrelation.warning`)."""
        return strong_correlations(self.names, self.log_scale, self._sampled_space)


class PiledUp:
    """The prior-edge check of a posterior (`Posterior`, `SharedPosterior`: they hold ``names``,
    ``units``, ``draws``, ``priors`` and ``bounds``), computed once for its warnings and its
    ``piled_up`` data. `HierarchicalPosterior` gives its own ``_prior_edges`` (its priors are
    per quantity: population medians, shared parameters)."""

    @functools.cached_property
    def _prior_edges(self) -> PriorEdges:
        rp = getattr(self, "reparametrization", None)
        causes = dict(rp.bound_causes) if rp is not None else {}
        sides = user_bound_sides(getattr(self, "user_bounds", None) or {}, self.circuit, self.registry)
        reductions = reducing_bounds(self.circuit, self.registry)
        # (keyed by circuit parameter; a joint posterior's per-spectrum CPE2.alpha[cycle=64] is CPE2.alpha's)
        by_name = lambda keyed: {n: keyed[circuit_name(n)] for n in self.names if circuit_name(n) in keyed}  # noqa: E731
        flat = self.draws.reshape(-1, len(self.names))
        medians = {**{circuit_name(n): float(np.median(flat[:, i])) for i, n in enumerate(self.names)}, **self.fixed}
        shorts = short_advice(self.circuit, self.registry, medians, self.frequency)
        return prior_edges(self.names, self.units, flat, self.priors, *self.bounds, by_name(reductions), causes, by_name(sides), by_name(shorts))

    @property
    def piled_up(self) -> KeyHintDict:
        """The sampled parameters whose draws pile up against an edge of their prior or bound,
        each with its side: "lower", "upper" or "both" (`prior_edges`; the warnings say it in
        words). A new dict whose missing key names the keys there are (`MissingKey`)."""
        return KeyHintDict(self._prior_edges.piled_up)

    @property
    def at_prior_edge(self) -> list[str]:
        """The rows the reports mark AT PRIOR EDGE: `set_by_prior_edge` less those the start fit's
        rule leaves undetermined (``undetermined``, marked NOT DETERMINED)."""
        loose = set(getattr(self, "undetermined", ()))
        return [n for n in self.set_by_prior_edge if n not in loose]

    @property
    def set_by_prior_edge(self) -> tuple[str, ...]:
        """The piled-up parameters (`piled_up`) whose table rows the reports mark (AT PRIOR EDGE,
        or NOT DETERMINED when the start fit's rule leaves them undetermined too):
        a prior's or a bound's edge, not the data, sets one end of their interval. Left out: those
        piled up only at the bound where their element is a simpler one (a CPE's alpha at 1),
        which their warning names instead, as the start fit's bound note does."""
        edges = self._prior_edges
        return tuple(n for n in self.names if n in edges.piled_up and n not in edges.at_reduction)

AT_BOUND = "whose fit is at a bound"
NOT_DETERMINED = "which the data do not determine"
"""`tied_to_bound`'s reasons for a parameter another is tied to."""


def tied_to_bound(names: Sequence[str], covariance, at_bound: Sequence[str], undetermined: Sequence[str] = ()) -> dict[str, tuple[str, float, str]]:
    """{parameter: (the parameter it is most correlated with among those at a bound or left
    undetermined by the fit, r, why that one: `AT_BOUND` or `NOT_DETERMINED`)} for each of
    ``names`` (the fit's free parameters, the order of ``covariance``) not itself among them
    whose correlation with one reaches `TIED_TO_BOUND_CORRELATION` in magnitude: the
    linearisation lets that one pass its bound or run over decades, and drags this one's error
    along (REAL exampleData.csv, R0 + R1 ∥ CPE1 + R2 ∥ CPE2: CPE2.alpha at r = −0.93 with R2,
    whose relative standard error is 9.2e5 %)."""
    cov = np.asarray(covariance, float)
    if cov.shape != (len(names), len(names)):
        return {}
    anchors = {n: AT_BOUND for n in at_bound}
    anchors.update({n: NOT_DETERMINED for n in undetermined if n not in anchors})
    sd = np.sqrt(np.diag(cov))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(sd, sd)
    out = {}
    for i, n in enumerate(names):
        if n in anchors:
            continue
        candidates = [(abs(corr[i, j]), names[j], float(corr[i, j])) for j, b in enumerate(names) if b in anchors and np.isfinite(corr[i, j])]
        if candidates:
            strength, other, r = max(candidates)
            if strength >= TIED_TO_BOUND_CORRELATION:
                out[n] = (other, r, anchors[other])
    return out


def interval_warnings(
    linearised: Mapping[str, float],
    half_widths: Mapping[str, float],
    *,
    chain_converged: bool,
    at_bound: Sequence[str] = (),
    piled_up: Sequence[str] = (),
    tied: Mapping[str, tuple[str, float, str]] | None = None,
) -> list[str]:
    """One warning naming the parameters whose least-squares ``linearised`` standard error and
    posterior 68 % half-width ((q84 − q16)/2, ``half_widths``) differ by more than
    `INTERVAL_RATIO_WARNING`, and saying which to use: the posterior's, which follows the
    model's non-linearity, the parameters' bounds (``at_bound``: the fit sits at one) and the
    priors (``piled_up``: the draws pile up against a prior's or a bound's edge), where the linearised
    error is a local approximation at the fit — unless the chain has not converged
    (``chain_converged`` false), when neither is to be trusted yet. ``tied`` (`tied_to_bound`):
    a parameter with no reason of its own is named with the one at a bound it is correlated with,
    whose linearised error, passing the bound, widens its own (REAL Gamry's R1 at 3.9× would otherwise be named
    with no reason)."""
    tied = tied or {}
    flagged = []
    for n, lin in linearised.items():
        half = half_widths.get(n, math.nan)
        if not (math.isfinite(lin) and lin > 0 and math.isfinite(half) and half > 0):
            continue
        ratio = lin / half
        if ratio > INTERVAL_RATIO_WARNING or ratio < 1 / INTERVAL_RATIO_WARNING:
            why = [w for w, where in (("its fit is at a bound", at_bound), ("its draws pile up against an edge", piled_up)) if n in where]
            if not why and n in tied:
                other, r, because = tied[n]
                why = [f"correlated with {other} (r = {r:+.2f} in the least-squares fit), {because}"]
            flagged.append(f"{n} ({format_factor(ratio)}×{'; ' + ', '.join(why) if why else ''})")
    if not flagged:
        return []
    head = (
        f"the least-squares start's linearised standard errors differ from the posterior's 68 % half-widths by more than {INTERVAL_RATIO_WARNING:g}× "
        f"for {', '.join(flagged)} (linearised ÷ posterior)"
    )
    if not chain_converged:
        return [head + ": the chain is too short to tell which is right (see the chain-length warning); run more steps before using either"]
    return [head + ": use the posterior's intervals — they follow the model's non-linearity, the parameters' bounds and the priors; the linearised errors are a local approximation at the fit"]
