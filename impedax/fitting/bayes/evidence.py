"""Model-comparison numbers of a Bayesian run: the Laplace log evidence at the MAP and WAIC.

Both work in the sampled space (see `impedax.fitting.bayes.logprob`) with the run's jitted
functions; see docs/bayesian.md for how to read them.
"""

from __future__ import annotations

import enum
import math
from typing import NamedTuple, Sequence

import jax.numpy as jnp
import numpy as np

from ...arguments import CHAIN_TAU_MULTIPLE
from ...data import format_frequency
from .diagnostics import kept_draws_text, more_draws_advice
from .logprob import LogProbArgs, LogProbFunctions

__all__ = ["LaplaceEvidence", "WAIC", "waic_cause", "START_BEYOND_SIGMA", "START_UNEVEN_NOISE", "WAIC_FIT_DISTANCE", "WAIC_MAX_DRAWS", "WAIC_POINT_LIMIT", "WAIC_PARAMETER_FACTOR", "LAPLACE_WIDTH_RATIO", "laplace_evidence", "waic", "EVIDENCE_NOTE_LEAD", "WAIC_NOTE_LEAD", "MODEL_COMPARISON_NOTE_LEADS", "short_chain_waic_note", "WAIC_REMEDY", "evidence_note_beside_waic", "WaicDoubt", "waic_doubts", "SHORT_CHAIN_REMEDY", "DOUBTED_WAIC_REMEDY", "evidence_remedy", "EvidenceDoubt", "evidence_doubt_of_notes", "model_comparison_notes_of"]

LAPLACE_WIDTH_RATIO = 2.0
"""The Laplace log evidence is flagged unreliable when, for some parameter, the Gaussian at the
MAP (sd from −H⁻¹) is wider or narrower than the draws' sd by more than this factor. On a
Gaussian posterior the two agree to the chain's sampling error (a few %); a parameter the data
leave to its prior has a nearly flat log-posterior, so −H⁻¹ is many times the prior's range
while the draws fill only that range, and ln Z then swings with that curvature."""

WAIC_MAX_DRAWS = 4000
WAIC_POINT_LIMIT = 0.4
"""Vehtari, Gelman & Gabry (2017, Stat. Comput. 27:1413, sec. 2.2): WAIC is unreliable where a
point's p_waic (the variance of its log-likelihood over the draws) exceeds 0.4. Reported in the
warning, not used to raise it: on correctly specified synthetic spectra (40 points, 1 % noise)
some point exceeded it in 16 of 20 runs."""
WAIC_PARAMETER_FACTOR = 2.0
"""WAIC is flagged when p_waic exceeds this many times the number of sampled parameters P. A
regular posterior gives p_waic ≈ P; p_waic > P marks a badly misspecified model or posterior
(the loo package's glossary, after Vehtari, Gelman & Gabry 2017). The factor 2 leaves room for
the scatter of p_waic itself: p_waic/P was 0.74–1.25 on 20 correctly specified synthetic spectra."""

WAIC_FIT_DISTANCE = 2.0
"""A posterior whose median lies within this many of its standard deviations (sampled space)
of the least-squares value, for every parameter, sits on the data's best fit: the draws' 95 %
region holds it. Further off, the posterior has moved away from the fit (a prior excludes it,
or the chain is still moving)."""


class EvidenceDoubt(enum.StrEnum):
    """Why a posterior's Laplace log evidence is undefined or no score to compare models by, as a
    value, not words: `LaplaceEvidence.reason`, `Posterior.log_evidence_unreliable_reason`,
    ``impedax sample --json``'s and ``impedax compare --json``'s ``log_evidence_unreliable_reason``,
    and what `impedax.compare`'s ``log_evidence_reliable`` reads. Each has its note in words
    (`laplace_evidence`'s, beginning with `EVIDENCE_NOTE_LEAD`)."""

    HESSIAN_NOT_FINITE = "hessian_not_finite"
    """Undefined: the Hessian at the MAP is not finite."""
    NOT_PEAKED = "not_peaked"
    """Undefined: the log-posterior is not peaked at the MAP (−H not positive definite)."""
    NEARLY_FLAT = "nearly_flat"
    """Unreliable: −H's eigenvalues span over 12 decades (a nearly flat direction)."""
    NOT_GAUSSIAN = "not_gaussian"
    """Unreliable: some parameter's Gaussian width at the MAP and its draws' width differ by more
    than `LAPLACE_WIDTH_RATIO`."""


class LaplaceEvidence(NamedTuple):
    """ln Z (NaN when undefined), the MAP in the sampled space, a note ("" when none), and why the
    value is undefined or unreliable (`EvidenceDoubt`; None when it is sound), the note's cause as
    a value."""

    log_evidence: float
    map_y: np.ndarray
    note: str
    reason: EvidenceDoubt | None = None


class WAIC(NamedTuple):
    """WAIC on the deviance scale, its effective number of parameters p_waic, a note ("" when
    none), and how many points have a pointwise p_waic above `WAIC_POINT_LIMIT`."""

    waic: float
    p_waic: float
    note: str
    n_unreliable: int = 0


EVIDENCE_NOTE_LEAD = "Laplace log evidence "
"""How the notes of `laplace_evidence` begin, each saying the value is unreliable or undefined.
`impedax.compare` marks the log evidence of a posterior by its reason (`EvidenceDoubt`,
`Posterior.log_evidence_unreliable_reason`), not by these words; they give the reason only of a
posterior file written without it (`evidence_doubt_of_notes`)."""
WAIC_NOTE_LEAD = "WAIC "
"""How the notes of `waic` begin, each saying the value is unreliable or undefined (whether WAIC
is one to compare models by is `waic_doubts`'s value, not these words)."""
MODEL_COMPARISON_NOTE_LEADS = (EVIDENCE_NOTE_LEAD, WAIC_NOTE_LEAD)
"""The leads of the notes that speak only to comparing models (the Laplace evidence, WAIC). A
command that compares none (`impedax gap`) leaves those notes out of its warnings by
`Posterior.model_comparison_notes`, which holds them apart; the leads pick them out only of a
posterior file written without it (`model_comparison_notes_of`)."""


def _old_evidence_reason(note: str) -> EvidenceDoubt:
    """The `EvidenceDoubt` of a note of `laplace_evidence` as the notes have read since the lead
    was set (for a posterior file written without the reason: `evidence_doubt_of_notes`)."""
    rest = note[len(EVIDENCE_NOTE_LEAD):]
    if rest.startswith("undefined: the Hessian"):
        return EvidenceDoubt.HESSIAN_NOT_FINITE
    if rest.startswith("undefined"):
        return EvidenceDoubt.NOT_PEAKED
    if rest.startswith("is unreliable: the posterior is nearly flat"):
        return EvidenceDoubt.NEARLY_FLAT
    return EvidenceDoubt.NOT_GAUSSIAN


def evidence_doubt_of_notes(notes: Sequence[str]) -> EvidenceDoubt | None:
    """The `EvidenceDoubt` a posterior's ``notes`` hold in words (the first note beginning with
    `EVIDENCE_NOTE_LEAD`), None without one: only for a posterior file written without
    ``log_evidence_unreliable_reason`` (`Posterior.from_xarray`), whose notes are all there is;
    a posterior in memory carries the reason `laplace_evidence` gave."""
    note = next((n for n in notes if n.startswith(EVIDENCE_NOTE_LEAD)), None)
    return None if note is None else _old_evidence_reason(note)


def model_comparison_notes_of(notes: Sequence[str]) -> tuple[str, ...]:
    """The ``notes`` that begin with a lead of `MODEL_COMPARISON_NOTE_LEADS`: only for a posterior
    file written without ``model_comparison_notes`` (`Posterior.from_xarray`); a posterior in
    memory holds them apart as `sample` made them."""
    return tuple(n for n in notes if n.startswith(MODEL_COMPARISON_NOTE_LEADS))


class WaicDoubt(enum.StrEnum):
    """Why a posterior's WAIC is no score to compare models by (`waic_doubts`), as a value, not
    words: what `Posterior.waic_unreliable_reason` holds, ``impedax sample --json``'s and
    ``impedax compare --json``'s ``waic_unreliable_reason``, and what `impedax.compare`'s
    ``waic_reliable`` and the Laplace evidence's remedy (`laplace_evidence`) read. Each has its
    note in words: `waic`'s (undefined, p_waic) and `short_chain_waic_note`."""

    UNDEFINED = "undefined"
    """WAIC is not finite: the likelihood is not finite at (nearly) every draw."""
    SHORT_CHAIN = "short_chain"
    """The kept chain has fewer than `CHAIN_TAU_MULTIPLE` draws per walker, too few to estimate τ."""
    HIGH_P_WAIC = "high_p_waic"
    """p_waic exceeds `WAIC_PARAMETER_FACTOR` × the number of sampled parameters (WAIC's own
    variance warning)."""


def _too_short(n_draws: int) -> bool:
    """Whether ``n_draws`` kept draws per walker are too few to estimate τ (the chain-length
    warning's rule, `diagnostics.integrated_autocorr`'s)."""
    return n_draws < CHAIN_TAU_MULTIPLE


def waic_doubts(waic_value: float, p_waic: float, n_params: int, n_draws: int | None = None) -> tuple[WaicDoubt, ...]:
    """The reasons WAIC ``waic_value`` (p_waic ``p_waic``, of ``n_params`` sampled parameters,
    from a chain of ``n_draws`` kept draws per walker; None: its length not judged) is no score to
    compare models by, in the order `WaicDoubt` lists them (the first is the posterior's
    ``waic_unreliable_reason``); () when it is one. The one rule `waic`'s note, the note beside
    WAIC (`short_chain_waic_note`), the Laplace evidence's remedy and `impedax.compare`'s
    ``waic_reliable`` follow."""
    doubts = []
    if not math.isfinite(waic_value):
        doubts.append(WaicDoubt.UNDEFINED)
    if n_draws is not None and _too_short(n_draws):
        doubts.append(WaicDoubt.SHORT_CHAIN)
    if p_waic > WAIC_PARAMETER_FACTOR * n_params:
        doubts.append(WaicDoubt.HIGH_P_WAIC)
    return tuple(doubts)


def short_chain_waic_note(n_draws: int, thin: int = 1) -> str:
    """The note beside WAIC of a chain of ``n_draws`` kept draws per walker (after thinning by
    ``thin``) too few to estimate τ (fewer than `CHAIN_TAU_MULTIPLE`, the rule of the chain-length
    warning and `diagnostics.integrated_autocorr`), "" for more. Whether such draws have spread
    from the start over the posterior is unknown, and until they have p_waic is off: on SYNTHETIC
    R0 + R1 ∥ C1 (40 points, 1 % noise) it read 1.9 after 8 steps and 4.7 after 2000 (P = 4), so
    WAIC is no score to compare models by (said beside it, not printed bare)."""
    if not _too_short(n_draws):
        return ""
    return (f"{WAIC_NOTE_LEAD}and p_waic are from a chain too short to trust ({kept_draws_text(n_draws, thin)}, too few to estimate τ: emcee needs ≳ {CHAIN_TAU_MULTIPLE} τ): "
            "whether its draws have spread from the start over the posterior is unknown, and until they have p_waic is off the mark (low on the shortest chains), "
            f"so do not compare models by this WAIC; {more_draws_advice(thin)} (steps='auto', the default, runs until the chain is {CHAIN_TAU_MULTIPLE} τ long)")


def laplace_evidence(chain_y, log_prob, args: LogProbArgs, functions: LogProbFunctions, lo_y, hi_y, names: Sequence[str] | None = None, *, converged: bool | None = None,
                     waic_reasons: Sequence[WaicDoubt] | None = None) -> LaplaceEvidence:
    """ln Z ≈ ln p(y*) + ln π(y*) + (d/2) ln 2π − ½ ln det(−H) at the MAP y* (sampled space).

    The MAP starts from the best draw of ``chain_y`` (walker, draw, param) and is polished by
    L-BFGS-B within the prior support (``lo_y``, ``hi_y``); H is the Hessian by JAX there. The
    note names the parameters (``names``, in order) whose Gaussian width at the MAP and whose
    draws' width differ by more than `LAPLACE_WIDTH_RATIO`: there the approximation fails;
    ``converged`` (the chain's, `Posterior.chain_converged`; None: not known) leaves out of its
    causes a chain too short when true. ``waic_reasons`` (the run's WAIC's, `waic_doubts`; None:
    not known, judged by the length of ``chain_y`` alone) choose the note's remedy: WAIC only
    where it is a score to compare models by (`evidence_remedy`).
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
        return LaplaceEvidence(math.nan, y_map, f"{EVIDENCE_NOTE_LEAD}undefined: the Hessian at the MAP is not finite", EvidenceDoubt.HESSIAN_NOT_FINITE)
    eig = np.linalg.eigvalsh(-0.5 * (h + h.T))
    if eig.min() <= 0:
        return LaplaceEvidence(math.nan, y_map, f"{EVIDENCE_NOTE_LEAD}undefined: the log-posterior is not peaked at the MAP (a flat or unidentified direction)", EvidenceDoubt.NOT_PEAKED)
    if eig.min() / eig.max() < 1e-12:
        note, reason = f"{EVIDENCE_NOTE_LEAD}is unreliable: the posterior is nearly flat along some direction (unidentified parameters)", EvidenceDoubt.NEARLY_FLAT
    else:
        reasons = ((WaicDoubt.SHORT_CHAIN,) if _too_short(chain_y.shape[1]) else ()) if waic_reasons is None else tuple(waic_reasons)
        note = _width_note(np.linalg.inv(-0.5 * (h + h.T)), chain_y, names, converged, reasons)
        reason = EvidenceDoubt.NOT_GAUSSIAN if note else None
    return LaplaceEvidence(lp_map + 0.5 * d * math.log(2 * math.pi) - 0.5 * float(np.sum(np.log(eig))), y_map, note, reason)


WAIC_REMEDY = "Compare models by WAIC, or fix or bound that parameter"
"""How a note of `laplace_evidence` on a posterior far from Gaussian ends (`_width_note`): the way
out it names where WAIC is a score to compare models by (`evidence_remedy`)."""
SHORT_CHAIN_REMEDY = "WAIC, from a chain too short to estimate τ, is no score to compare models by either (see the note beside it): run a longer chain, or fix or bound that parameter"
"""`WAIC_REMEDY` where the chain is too short to estimate τ (`WaicDoubt.SHORT_CHAIN`): the note
does not send the user to a WAIC `short_chain_waic_note` says not to compare models by
in the same report (REAL exampleDataGamry.DTA with R0 + R1 || CPE1 and --steps 40)."""
DOUBTED_WAIC_REMEDY = "WAIC is no score to compare models by either (see its warning): fix or bound that parameter"
"""`WAIC_REMEDY` where WAIC has a warning of its own (`WaicDoubt.UNDEFINED`,
`WaicDoubt.HIGH_P_WAIC`): one posterior's warnings do not say both "Compare models by
WAIC" and "Do not compare models by this WAIC"."""


def evidence_remedy(waic_reasons: Sequence[WaicDoubt]) -> str:
    """The way out a note of `laplace_evidence` names, by why the run's WAIC is no score to
    compare models by (``waic_reasons``, `waic_doubts`; () when it is one): a chain too short
    first, as its remedy (a longer chain) may mend WAIC's other doubts too."""
    if WaicDoubt.SHORT_CHAIN in waic_reasons:
        return SHORT_CHAIN_REMEDY
    return DOUBTED_WAIC_REMEDY if waic_reasons else WAIC_REMEDY


def evidence_note_beside_waic(evidence_note: str, waic_note: str) -> str:
    """The Laplace evidence's note ``evidence_note`` as kept beside a WAIC note ``waic_note``
    (unreliable or undefined, `waic`; "" for none): where WAIC has one, not sending the user to
    compare models by it (`DOUBTED_WAIC_REMEDY`). `sample` does not use it: it gives
    `laplace_evidence` the reasons of its WAIC (``waic_reasons``), which choose the remedy."""
    if not waic_note or not evidence_note.endswith(WAIC_REMEDY):
        return evidence_note
    return evidence_note[: -len(WAIC_REMEDY)] + DOUBTED_WAIC_REMEDY


def _width_note(covariance: np.ndarray, chain_y: np.ndarray, names: Sequence[str] | None, converged: bool | None = None, waic_reasons: Sequence[WaicDoubt] = ()) -> str:
    """"" when every parameter's Laplace sd (from ``covariance``) is within
    `LAPLACE_WIDTH_RATIO` of its draws' sd in ``chain_y`` (walker, draw, param); else a note
    naming them with both widths. A Gaussian far wider than the draws is blamed on a parameter
    left to its prior or cut off by a prior's edge or a bound, and, unless the chain is known to
    have ``converged``, on draws not yet spread out (a converged REAL Gamry chain is not sent to "see
    its warning" of a chain too short, which it does not have). The remedy names WAIC
    only where ``waic_reasons`` (the run's WAIC's, `waic_doubts`) are none (`evidence_remedy`)."""
    laplace_sd = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
    draws_sd = chain_y.reshape(-1, chain_y.shape[-1]).std(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = laplace_sd / draws_sd
    off = [k for k, r in enumerate(ratio) if not 1 / LAPLACE_WIDTH_RATIO <= r <= LAPLACE_WIDTH_RATIO]
    if not off:
        return ""
    label = (lambda k: names[k]) if names is not None and len(names) == ratio.size else (lambda k: f"parameter {k}")
    detail = ", ".join(f"{label(k)} (Gaussian sd {laplace_sd[k]:.3g} against the draws' {draws_sd[k]:.3g}, sampled space)" for k in off)
    wide = any(ratio[k] > LAPLACE_WIDTH_RATIO for k in off)
    if not wide:
        why = ""
    elif converged:
        why = "; a Gaussian far wider than the draws marks a parameter left to its prior, or one whose draws a prior's edge or a bound cuts off (see its pile-up warning, if any)"
    else:
        why = "; a Gaussian far wider than the draws marks a parameter left to its prior, or draws that have not yet spread over the posterior (a chain too short: see its warning)"
    return f"{EVIDENCE_NOTE_LEAD}is unreliable: the posterior is not Gaussian at the MAP along {detail}{why}. {evidence_remedy(waic_reasons)}"


START_BEYOND_SIGMA = "beyond sigma"
"""``model_misfit`` of `waic_cause` when the start fit's only mark of a misfit is a χ²_red far
above 1 with the data's σ (no misfit note blames the model): a σ that understates the noise
does that as well as a model that misses structure."""


START_UNEVEN_NOISE = "uneven noise"
"""``model_misfit`` of `waic_cause` when the start fit's residuals, under a noise model of one
relative level (``proportional``), are several times larger in one band than elsewhere (its
`least_squares.result.UNEVEN_NOISE_NOTE`): the likelihood's σ is too small there. On the shipped
SYNTHETIC skin (noise ~4× larger at 1–5 Hz) p_waic was 13 for 5 parameters with the chain
converged: more steps do not mend it."""


def waic_cause(chain_y, names: Sequence[str], *, excluded: Sequence[str] = (), start_y=None, converged: bool = True, model_misfit: bool | str = False) -> str:
    """Why the draws of ``chain_y`` (walker, draw, param; sampled space; parameters ``names``)
    fit the data so differently from one another that p_waic is large, in words, from what
    applies: the priors exclude the least-squares values of ``excluded``; the chain has not
    converged (``converged`` false); the posterior median lies more than `WAIC_FIT_DISTANCE`
    standard deviations from the least-squares values ``start_y`` (sampled space; None: not
    known); or, with the posterior on that fit, the start fit misses structure the data hold
    (``model_misfit``: its misfit note, or χ²_red ≫ 1 with the data's σ), so that every draw
    fits some points well and others badly — a misspecified model, which more steps or another
    prior do not mend; ``model_misfit`` `START_BEYOND_SIGMA`: only χ²_red says so, and the
    cause named is a σ that understates the noise or a model that misses structure."""
    causes = []
    if excluded:
        causes.append(f"the posterior sits away from the data's best fit: the priors exclude where the data put {', '.join(excluded)} (the least-squares value lies outside)")
    away: list[str] = []
    if start_y is not None:
        flat = chain_y.reshape(-1, chain_y.shape[-1])
        sd = flat.std(axis=0)
        with np.errstate(divide="ignore", invalid="ignore"):
            distance = np.abs(np.median(flat, axis=0) - np.asarray(start_y, float)) / sd
        away = [n for n, d in zip(names, distance) if n not in excluded and np.isfinite(d) and d > WAIC_FIT_DISTANCE]
        if away:
            causes.append(f"the posterior sits away from the data's best fit: the median of {', '.join(away)} lies over {WAIC_FIT_DISTANCE:g} posterior standard deviations from the least-squares value (a prior that excludes it, or a chain still moving)")
    if model_misfit == START_UNEVEN_NOISE and not excluded and not away:
        causes.insert(
            0,
            "the noise model gives every point one relative σ, while the start fit's residuals are several times larger in one band (see its note): "
            "there σ is too small, and the draws' small moves change those points' log-likelihood by much more than one; give the data's σ "
            "(a sigma column of the file or make_spectrum(sigma=...), and noise='sigma') or leave that band out before comparing models by WAIC — more steps do not mend it"  # (impedax sample: "--noise sigma", `cli.common.command_line_words`; not in Python)
        )
    elif model_misfit == START_BEYOND_SIGMA and not excluded and not away:
        causes.insert(
            0,
            "the start fit's residuals are several times the data's sigma (see its note): either σ understates the noise, so that the likelihood is too narrow "
            "and the draws' small moves change each point's log-likelihood by much more than one (the intervals are then too narrow as well; check the sigma column), "
            "or the model misses structure the data hold, which a diagnosis (impedax diagnose) shows; more steps or other priors mend neither"
        )
    elif model_misfit and not excluded and not away:
        causes.insert(
            0,
            "the model misfits the data: the posterior sits on the least-squares fit, but that fit misses structure the data hold (see the start fit's misfit note), "
            "so its residuals are many noise widths at most points and the draws' small moves about it change each point's log-likelihood by much more than one — "
            "a misspecified model, which more steps or other priors do not mend; a diagnosis (impedax diagnose) shows which effect is missing"
        )
    if not converged:
        causes.append("the chain has not converged (see the chain-length warning): run more steps")
    if not causes:
        return "the posterior sits away from the data's best fit, or the model misfits the data — a prior that excludes where the data put a parameter, or a chain still moving from its start (run more steps)"
    return "; ".join(causes)


def _at_points(args: LogProbArgs, p_i: np.ndarray) -> str:
    """``", at 1 Hz, 1.26 Hz, …"``: the frequencies of the points whose pointwise p_waic exceeds
    `WAIC_POINT_LIMIT`, highest first (at most 4), or "" when the frequencies are not one per point."""
    freq = np.asarray(getattr(args, "freq", ()), float).ravel()
    if freq.size != p_i.size:
        return ""
    high = [k for k in np.argsort(-p_i) if p_i[k] > WAIC_POINT_LIMIT]
    return ", at " + ", ".join(format_frequency(float(freq[k])) for k in high[:4]) + (", …" if len(high) > 4 else "") if high else ""


def waic(chain_y, args: LogProbArgs, functions: LogProbFunctions, excluded: Sequence[str] = (), *, names: Sequence[str] | None = None, start_y=None, converged: bool = True, model_misfit: bool | str = False) -> WAIC:
    """WAIC = −2 (lppd − p_waic) over the frequency points (Watanabe 2010; Gelman et al. 2014),
    from at most `WAIC_MAX_DRAWS` evenly spaced draws of ``chain_y``. The note warns when
    p_waic exceeds `WAIC_PARAMETER_FACTOR` × the number of sampled parameters and names the
    cause that applies (`waic_cause`: ``excluded``, the parameters whose least-squares values
    lie outside their priors; the least-squares values ``start_y`` in the sampled space, of the
    parameters ``names``; the chain's convergence; the start fit's ``model_misfit``)."""
    from scipy.special import logsumexp

    flat = chain_y.reshape(-1, chain_y.shape[-1])
    if flat.shape[0] > WAIC_MAX_DRAWS:
        flat = flat[np.linspace(0, flat.shape[0] - 1, WAIC_MAX_DRAWS).astype(int)]
    ll = np.asarray(functions.pointwise(jnp.asarray(flat), args), float)  # (S, N)
    if not np.all(np.isfinite(ll)):
        ll = ll[np.all(np.isfinite(ll), axis=1)]
        if ll.shape[0] < 2:
            return WAIC(math.nan, math.nan, f"{WAIC_NOTE_LEAD}undefined: non-finite likelihood at the draws")
    lppd = logsumexp(ll, axis=0) - math.log(ll.shape[0])
    p_i = ll.var(axis=0, ddof=1)
    total, p_waic = float(-2.0 * np.sum(lppd - p_i)), float(np.sum(p_i))
    high = int(np.sum(p_i > WAIC_POINT_LIMIT))
    n_params = chain_y.shape[-1]
    if WaicDoubt.HIGH_P_WAIC not in waic_doubts(total, p_waic, n_params):
        return WAIC(total, p_waic, "", high)
    names = list(names) if names is not None and len(names) == n_params else [f"parameter {k}" for k in range(n_params)]
    cause = waic_cause(chain_y, names, excluded=excluded, start_y=start_y, converged=converged, model_misfit=model_misfit)
    note = (
        f"{WAIC_NOTE_LEAD}is unreliable: its effective number of parameters p_waic = {p_waic:.3g} is over {WAIC_PARAMETER_FACTOR:g} × the "
        f"{n_params} sampled parameters (near the data's best fit p_waic ≈ {n_params}; p_waic > {n_params} marks a badly misspecified "
        f"model or posterior, Vehtari, Gelman & Gabry 2017), and {high} of {p_i.size} points have a pointwise p_waic above {WAIC_POINT_LIMIT} "
        f"(largest {p_i.max():.3g}{_at_points(args, p_i)}): the draws fit the data very differently from one another, because {cause}. Do not compare models by this WAIC"
    )
    return WAIC(total, p_waic, note, high)
