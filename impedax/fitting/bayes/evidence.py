"""Model-comparison numbers of a Bayesian run: the Laplace log evidence at the MAP and WAIC.

Both work in the sampled space (see `impedax.fitting.bayes.logprob`) with the run's jitted
functions; see docs/bayesian.md for how to read them.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from .logprob import LogProbArgs, LogProbFunctions

__all__ = ["LaplaceEvidence", "WAIC", "WAIC_MAX_DRAWS", "laplace_evidence", "waic"]

WAIC_MAX_DRAWS = 4000


class LaplaceEvidence(NamedTuple):
    """ln Z (NaN when undefined), the MAP in the sampled space, and a note ("" when none)."""

    log_evidence: float
    map_y: np.ndarray
    note: str


class WAIC(NamedTuple):
    """WAIC on the deviance scale, its effective number of parameters p_waic, and a note."""

    waic: float
    p_waic: float
    note: str


def laplace_evidence(chain_y, log_prob, args: LogProbArgs, functions: LogProbFunctions, lo_y, hi_y) -> LaplaceEvidence:
    """ln Z ≈ ln p(y*) + ln π(y*) + (d/2) ln 2π − ½ ln det(−H) at the MAP y* (sampled space).

    The MAP starts from the best draw of ``chain_y`` (walker, draw, param) and is polished by
    L-BFGS-B within the prior support (``lo_y``, ``hi_y``); H is the Hessian by JAX there.
    """
    from scipy.optimize import minimize

    flat_lp = log_prob.reshape(-1)
    best = np.unravel_index(int(np.argmax(flat_lp)), log_prob.shape)
    y_best = chain_y[best]

    def objective(y):
        v, g = functions.value_and_grad(jnp.asarray(y), args)
        v, g = float(v), np.asarray(g, float)
        if not np.isfinite(v) or not np.all(np.isfinite(g)):
            return 1e300, np.zeros_like(g)
        return -v, -g

    bounds = [(None if not np.isfinite(lo) else lo, None if not np.isfinite(hi) else hi) for lo, hi in zip(lo_y, hi_y)]
    try:
        sol = minimize(objective, y_best, jac=True, method="L-BFGS-B", bounds=bounds, options={"maxiter": 500})
        y_map = sol.x if -sol.fun >= flat_lp.max() else y_best
    except (ValueError, FloatingPointError):
        y_map = y_best
    lp_map = float(-objective(y_map)[0])
    h = np.asarray(functions.hessian(jnp.asarray(y_map), args), float)
    d = len(y_map)
    if not np.all(np.isfinite(h)):
        return LaplaceEvidence(math.nan, y_map, "Laplace log evidence undefined: the Hessian at the MAP is not finite")
    eig = np.linalg.eigvalsh(-0.5 * (h + h.T))
    if eig.min() <= 0:
        return LaplaceEvidence(math.nan, y_map, "Laplace log evidence undefined: the log-posterior is not peaked at the MAP (a flat or unidentified direction)")
    note = ""
    if eig.min() / eig.max() < 1e-12:
        note = "Laplace log evidence is unreliable: the posterior is nearly flat along some direction (unidentified parameters)"
    return LaplaceEvidence(lp_map + 0.5 * d * math.log(2 * math.pi) - 0.5 * float(np.sum(np.log(eig))), y_map, note)


def waic(chain_y, args: LogProbArgs, functions: LogProbFunctions) -> WAIC:
    """WAIC = −2 (lppd − p_waic) over the frequency points (Watanabe 2010; Gelman et al. 2014),
    from at most `WAIC_MAX_DRAWS` evenly spaced draws of ``chain_y``."""
    from scipy.special import logsumexp

    flat = chain_y.reshape(-1, chain_y.shape[-1])
    if flat.shape[0] > WAIC_MAX_DRAWS:
        flat = flat[np.linspace(0, flat.shape[0] - 1, WAIC_MAX_DRAWS).astype(int)]
    ll = np.asarray(functions.pointwise(jnp.asarray(flat), args), float)  # (S, N)
    if not np.all(np.isfinite(ll)):
        ll = ll[np.all(np.isfinite(ll), axis=1)]
        if ll.shape[0] < 2:
            return WAIC(math.nan, math.nan, "WAIC undefined: non-finite likelihood at the draws")
    lppd = logsumexp(ll, axis=0) - math.log(ll.shape[0])
    p_i = ll.var(axis=0, ddof=1)
    return WAIC(float(-2.0 * np.sum(lppd - p_i)), float(np.sum(p_i)), "")
