"""Convergence diagnostics of an emcee chain: autocorrelation time, highest-density interval and
the warnings a `Posterior` raises (chain length, acceptance, strong correlations)."""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import numpy as np

__all__ = ["CHAIN_TAU_MULTIPLE", "ACCEPTANCE_RANGE", "CORRELATION_WARNING", "integrated_autocorr", "hdi", "chain_warnings"]

CHAIN_TAU_MULTIPLE = 50
ACCEPTANCE_RANGE = (0.15, 0.6)
CORRELATION_WARNING = 0.9


def integrated_autocorr(chain_y: np.ndarray) -> np.ndarray:
    """Integrated autocorrelation time per parameter in stored draws of ``chain_y`` (walker,
    draw, param) (emcee, tol=0); NaN for a chain of fewer than two draws."""
    import emcee

    if chain_y.shape[1] < 2:
        return np.full(chain_y.shape[-1], np.nan)
    tau = emcee.autocorr.integrated_time(np.transpose(chain_y, (1, 0, 2)), c=5, tol=0, quiet=True)
    return np.asarray(tau, float)


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
