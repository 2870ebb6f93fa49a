"""Convergence diagnostics of an emcee chain: autocorrelation time, highest-density interval and
the warnings a `Posterior` raises (chain length, acceptance, strong correlations, draws piled up
against a prior's edge)."""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import numpy as np

from ...data import unit_text

__all__ = [
    "CHAIN_TAU_MULTIPLE", "ACCEPTANCE_RANGE", "CORRELATION_WARNING", "EDGE_BAND", "EDGE_DENSITY", "EDGE_MIN_DRAWS",
    "integrated_autocorr", "hdi", "chain_warnings", "prior_edge_warnings", "figure",
]

CHAIN_TAU_MULTIPLE = 50
ACCEPTANCE_RANGE = (0.15, 0.6)
CORRELATION_WARNING = 0.9
EDGE_BAND = 0.02  # the outer 2 % of a prior's range (in its own coordinate) ...
EDGE_DENSITY = 0.5  # ... holding draws at least half as dense as over their central 90 %: piled up
EDGE_MIN_DRAWS = 20  # fewer draws in the band than this say nothing


def integrated_autocorr(chain_y: np.ndarray) -> np.ndarray:
    """Integrated autocorrelation time per parameter in stored draws of ``chain_y`` (walker,
    draw, param) (emcee, tol=0). NaN (unknown) for a chain of fewer than `CHAIN_TAU_MULTIPLE`
    draws per walker — emcee's estimate needs a chain of ≳ 50 τ, and τ ≥ 1, so a shorter chain
    cannot support it (its estimate collapses towards 0: 2 draws give τ = 0) — and for a
    parameter in which some walker never moved over the kept draws (its autocorrelation is 0/0,
    or a rounding error of its mean)."""
    import emcee

    n_walkers, n_draws, n_params = chain_y.shape
    if n_draws < CHAIN_TAU_MULTIPLE:
        return np.full(n_params, np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = np.asarray(emcee.autocorr.integrated_time(np.transpose(chain_y, (1, 0, 2)), c=5, tol=0, quiet=True), float)
    stuck = np.any(np.all(chain_y == chain_y[:, :1], axis=1), axis=0)  # per parameter: a walker that never moved
    return np.where(stuck, np.nan, tau)


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


def chain_warnings(
    names: Sequence[str],
    log_scale: Sequence[bool],
    chain_y: np.ndarray,
    autocorr_steps: Mapping[str, float],
    thin: int,
    mean_acceptance: float,
) -> list[str]:
    """Warnings about a chain ``chain_y`` (walker, draw, param; sampled space): shorter than
    `CHAIN_TAU_MULTIPLE` autocorrelation times (``autocorr_steps`` in sampler steps), mean
    acceptance outside `ACCEPTANCE_RANGE`, pairs of parameters of different elements correlated
    beyond `CORRELATION_WARNING`."""
    out = []
    n_draws = chain_y.shape[1]
    taus = {n: t / thin for n, t in autocorr_steps.items()}
    finite = {n: t for n, t in taus.items() if np.isfinite(t)}
    if n_draws < CHAIN_TAU_MULTIPLE:
        out.append(
            f"the chain is too short to estimate τ ({n_draws} draw{'s' if n_draws != 1 else ''} per walker after burn-in; emcee needs ≳ {CHAIN_TAU_MULTIPLE} τ, "
            f"and τ is at least one draw): τ and ESS are unknown and the intervals are not to be trusted; run more steps"
        )
    elif len(finite) < len(taus):
        stuck = int(np.sum(np.all(chain_y == chain_y[:, :1], axis=(1, 2))))
        unknown = [n for n in taus if n not in finite]
        out.append(
            f"τ of {', '.join(unknown)} could not be estimated"
            + (f": {stuck} of {chain_y.shape[0]} walkers never moved over the {n_draws} kept draws (stuck walkers)" if stuck else "")
            + "; τ and ESS are unknown there: run more steps or check the start"
        )
    if finite:
        worst = max(finite, key=finite.get)
        if n_draws < CHAIN_TAU_MULTIPLE * finite[worst]:
            out.append(
                f"the chain ({n_draws} draws per walker after burn-in) is shorter than {CHAIN_TAU_MULTIPLE} autocorrelation times "
                f"(τ = {finite[worst] * thin:.3g} steps for {worst}): run more steps before trusting the intervals"
            )
    acc = mean_acceptance
    if not ACCEPTANCE_RANGE[0] <= acc <= ACCEPTANCE_RANGE[1]:
        out.append(f"mean acceptance fraction {acc:.3f} is outside {ACCEPTANCE_RANGE[0]}–{ACCEPTANCE_RANGE[1]}: the sampler is {'stuck' if acc < ACCEPTANCE_RANGE[0] else 'taking tiny steps'}")
    ys = chain_y.reshape(-1, len(names))
    if ys.shape[0] > 2 and len(names) > 1:
        with np.errstate(all="ignore"):
            corr = np.corrcoef(ys, rowvar=False)
        for i in range(len(names)):
            for j in range(i + 1, len(names)):
                same_element = names[i].split(".")[0] == names[j].split(".")[0]  # a CPE's Q and α: correlated yet well determined
                if np.isfinite(corr[i, j]) and abs(corr[i, j]) > CORRELATION_WARNING and not same_element:
                    space = "log " if log_scale[i] and log_scale[j] else ""
                    out.append(
                        f"{names[i]} and {names[j]} are strongly correlated in the posterior (r = {corr[i, j]:+.3f} in {space}space): "
                        "the data constrain a combination of them; fix one or give it an informative prior"
                    )
    return out


def prior_edge_warnings(
    names: Sequence[str],
    units: Sequence[str],
    draws: np.ndarray,
    priors: Mapping,
    lower: Sequence[float],
    upper: Sequence[float],
) -> list[str]:
    """A warning for each parameter whose posterior piles up against an edge of its prior.

    In the prior's own coordinate t = F(x) (its cumulative probability: linear for a uniform
    prior, log for a log-uniform one), the prior is flat on [0, 1] and the posterior's density is
    proportional to the likelihood. Draws are piled up against an edge when the band of
    `EDGE_BAND` of t next to it (or a tenth of the draws' central 90 % interval in t, when that
    is narrower) holds them at least `EDGE_DENSITY` times as densely as that central interval
    does: the likelihood has not fallen off by the edge, so the prior (or, where the edge is the
    parameter's own bound, the bound) and not the data sets that side of the interval.
    ``draws`` are flat natural values (sample, param); ``lower``/``upper`` the parameters' bounds.
    """
    out = []
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
        for side, share, end, bound, q, beyond in (
            ("lower", np.mean(t <= band), lo, lower[i], np.quantile(x, 0.05), "smaller"),
            ("upper", np.mean(t >= 1 - band), hi, upper[i], np.quantile(x, 0.95), "larger"),
        ):
            if share * t.size < EDGE_MIN_DRAWS or (share / band) < EDGE_DENSITY * (0.9 / central):
                continue
            where = f"{100 * share:.0f} % of the draws lie in the {'lowest' if side == 'lower' else 'highest'} {100 * band:.2g} % of its prior's range" + (" (log scale)" if prior.kind == "loguniform" else "" if prior.bounded else " (by prior mass)")
            unit = f" {unit_text(units[i])}".rstrip()
            interval = f"the {side} end of its 90 % interval ({'q05' if side == 'lower' else 'q95'} = {q:.3g}{unit})"
            if not prior.bounded:
                out.append(f"{n} piles up against the {side} tail of its prior {prior} ({where}): the prior, not the data, sets {interval}")
            elif end == bound:
                out.append(f"{n} piles up against its {side} bound {end:g} ({where}): the bound, not the data, sets {interval}; the data would take {beyond} values (is the model missing something?)")
            else:
                out.append(
                    f"{n} piles up against the {side} end of its prior {prior} ({where}): the prior, not the data, sets {interval}; "
                    f"the data allow {beyond} values — give {n} a prior that says how {'small' if side == 'lower' else 'large'} it can be"
                )
    return out
