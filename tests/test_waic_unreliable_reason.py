"""Why WAIC is no score to compare models by, as a value (`evidence.WaicDoubt`), not as words.

Until 2026-12-07 three places judged it from prose: `impedax.compare`'s ``waic_reliable`` looked
for warnings beginning "WAIC ", the Laplace evidence's remedy was rewritten where WAIC had a note,
and `_width_note` applied the short-chain rule of its own. A WAIC warning in other words left
compare calling that WAIC reliable. Now `evidence.waic_doubts` is the one rule, of WAIC's
numbers: `Posterior.waic_unreliable_reason` (JSON ``waic_unreliable_reason``), compare's
``waic_reliable`` (and its row's ``waic_unreliable_reason``) and the evidence note's remedy read it.

Oracles: pointwise log-likelihoods made by hand, whose variances give p_waic by hand
(±a at every point over S draws: S a² / (S − 1) each), a Gaussian log-posterior whose Hessian
is −1/s², the chain-length rule (fewer than 50 kept draws per walker), and a SYNTHETIC
R0 + R1 ∥ C1 spectrum (numpy formula).
"""

from __future__ import annotations

import dataclasses
import json
import math
from types import SimpleNamespace

import jax.numpy as jnp
import numpy as np
import pytest

import impedax as ix
from impedax.fitting.bayes.evidence import (
    DOUBTED_WAIC_REMEDY, SHORT_CHAIN_REMEDY, WAIC_REMEDY, WaicDoubt, laplace_evidence, waic, waic_doubts,
)

S_WALKERS, N_POINTS = 8, 10


def _pointwise(ll: np.ndarray):
    """Functions whose pointwise log-likelihood at the draws is ``ll`` (draws, points), whatever the draws."""
    return SimpleNamespace(pointwise=lambda y, args: jnp.asarray(ll))


def _alternating(n_draws_total: int, amplitude: float) -> np.ndarray:
    """ll = −1 ± ``amplitude`` alternating over the draws at every point: variance amplitude² S/(S − 1)."""
    sign = np.where(np.arange(n_draws_total) % 2 == 0, 1.0, -1.0)
    return -1.0 + amplitude * sign[:, None] * np.ones((1, N_POINTS))


def test_waics_own_variance_warning_is_a_reason():
    chain = np.zeros((S_WALKERS, 50, 2))  # 2 sampled parameters, 50 draws per walker: long enough
    s = chain.shape[0] * chain.shape[1]
    args = SimpleNamespace(freq=np.geomspace(1, 1e3, N_POINTS))
    high = waic(chain, args, _pointwise(_alternating(s, 1.0)))
    assert high.p_waic == pytest.approx(N_POINTS * s / (s - 1))  # 10.03 > 2 × 2
    assert waic_doubts(high.waic, high.p_waic, 2, 50) == (WaicDoubt.HIGH_P_WAIC,) and high.note  # (the note follows the same rule)
    low = waic(chain, args, _pointwise(_alternating(s, 0.5)))
    assert low.p_waic == pytest.approx(0.25 * N_POINTS * s / (s - 1))  # 2.51 ≤ 4
    assert waic_doubts(low.waic, low.p_waic, 2, 50) == () and low.note == ""


def test_a_non_finite_waic_is_a_reason():
    chain = np.zeros((S_WALKERS, 50, 2))
    ll = np.full((S_WALKERS * 50, N_POINTS), np.nan)
    ll[0] = -1.0  # one finite draw: fewer than 2, no WAIC
    out = waic(chain, SimpleNamespace(freq=np.ones(N_POINTS)), _pointwise(ll))
    assert math.isnan(out.waic) and waic_doubts(out.waic, out.p_waic, 2, 50) == (WaicDoubt.UNDEFINED,)


def test_a_chain_too_short_to_estimate_tau_is_a_reason():
    assert waic_doubts(100.0, 1.0, 2, 49) == (WaicDoubt.SHORT_CHAIN,)
    assert waic_doubts(100.0, 1.0, 2, 50) == ()
    assert waic_doubts(100.0, 1.0, 2) == ()  # (length not judged)
    # in the order WaicDoubt lists them: the first is the posterior's reason
    assert waic_doubts(math.nan, math.nan, 2, 10) == (WaicDoubt.UNDEFINED, WaicDoubt.SHORT_CHAIN)
    assert waic_doubts(100.0, 5.0, 2, 10) == (WaicDoubt.SHORT_CHAIN, WaicDoubt.HIGH_P_WAIC)


def test_the_evidence_remedy_follows_the_reasons():
    """A Gaussian log-posterior of width s = 10 (Hessian −1/s²) with draws of sd 1: the Laplace
    width is 10× the draws', so the note is raised; its remedy names WAIC only where no reason
    says WAIC is no score to compare models by."""
    s = 10.0
    functions = SimpleNamespace(value_and_grad=lambda y, args: (-0.5 * jnp.sum(y**2) / s**2, -y / s**2), hessian=lambda y, args: -jnp.eye(1) / s**2)
    chain = np.random.default_rng(0).standard_normal((S_WALKERS, 60, 1))
    log_prob = -0.5 * chain[..., 0] ** 2 / s**2

    def note(reasons):
        return laplace_evidence(chain, log_prob, None, functions, np.array([-np.inf]), np.array([np.inf]), ["x"], converged=True, waic_reasons=reasons).note

    assert note(()).endswith(WAIC_REMEDY)
    assert note((WaicDoubt.SHORT_CHAIN,)).endswith(SHORT_CHAIN_REMEDY)
    assert note((WaicDoubt.SHORT_CHAIN, WaicDoubt.HIGH_P_WAIC)).endswith(SHORT_CHAIN_REMEDY)
    assert note((WaicDoubt.HIGH_P_WAIC,)).endswith(DOUBTED_WAIC_REMEDY) and note((WaicDoubt.UNDEFINED,)).endswith(DOUBTED_WAIC_REMEDY)
    # not given: judged by the chain's length (60 draws per walker: long enough; 30: too short)
    assert note(None).endswith(WAIC_REMEDY)
    short = laplace_evidence(chain[:, :30], log_prob[:, :30], None, functions, np.array([-np.inf]), np.array([np.inf]), ["x"], converged=True).note
    assert short.endswith(SHORT_CHAIN_REMEDY)


@pytest.fixture(scope="module")
def posterior():
    rng = np.random.default_rng(7)
    f = np.geomspace(0.1, 1e5, 30)
    z = 20.0 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6)
    z = z * (1 + 0.01 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2))
    return ix.sample("R0 + R1 || C1", ix.make_spectrum(f, z), steps=100, walkers=16, progress=False)


def _compared(*posteriors):
    from impedax.io.export import to_jsonable

    c = ix.compare(list(posteriors))
    doc = json.loads(json.dumps(to_jsonable(c.summary()), allow_nan=False))
    return c.rows, doc["models"]


def test_a_reworded_waic_warning_still_marks_waic_unreliable(posterior):
    """p_waic over 2 × the 4 sampled parameters, its warning in other words (not beginning
    "WAIC "): compare called that WAIC reliable until 2026-12-07."""
    assert posterior.n_draws == 75 and posterior.waic_unreliable_reason is None and posterior.summary()["waic_unreliable_reason"] is None
    p = len(posterior.names)
    reworded = dataclasses.replace(posterior, p_waic=2.0 * p + 1.0, notes=(*posterior.notes, f"The effective parameter count exceeds twice the {p} sampled ones: do not rank models by it"))
    assert reworded.waic_unreliable_reason == WaicDoubt.HIGH_P_WAIC == "high_p_waic" and reworded.summary()["waic_unreliable_reason"] == "high_p_waic"
    rows, models = _compared(reworded, posterior)
    assert [r["waic_reliable"] for r in rows] == [False, True] and [r["waic_unreliable_reason"] for r in rows] == ["high_p_waic", None]
    assert [m["waic_reliable"] for m in models] == [False, True] and [m["waic_unreliable_reason"] for m in models] == ["high_p_waic", None]
    # the warning's words alone (p_waic regular) do not make it unreliable: the rule is of the numbers
    worded = dataclasses.replace(posterior, notes=(*posterior.notes, "WAIC is unreliable: (words only)"))
    assert worded.waic_unreliable_reason is None


def test_each_reason_reaches_compare(posterior):
    undefined = dataclasses.replace(posterior, waic=math.nan, p_waic=math.nan)
    short = dataclasses.replace(posterior, draws=posterior.draws[:, :30], log_prob=posterior.log_prob[:, :30])
    assert (undefined.waic_unreliable_reason, short.waic_unreliable_reason) == ("undefined", "short_chain") and short.waic_note
    rows, models = _compared(undefined, short, posterior)
    assert [r["waic_unreliable_reason"] for r in rows] == ["undefined", "short_chain", None] and [r["waic_reliable"] for r in rows] == [False, False, True]
    assert [m["waic_unreliable_reason"] for m in models] == ["undefined", "short_chain", None]
    # a least-squares fit's row has no WAIC, nor these keys
    rows, _ = _compared(posterior, posterior.fit)
    assert "waic_unreliable_reason" not in rows[1] and "waic_reliable" not in rows[1]
