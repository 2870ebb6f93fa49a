"""`laplace_evidence` on log-densities whose evidence is known in closed form: a Gaussian (no
note, ln Z exact) and one parameter left to a bounded flat prior (flagged, named)."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from impedax.fitting.bayes.evidence import EVIDENCE_NOTE_LEAD, laplace_evidence
from impedax.fitting.bayes.logprob import LogProbFunctions

jax.config.update("jax_enable_x64", True)


def _functions(log_density):
    single = jax.jit(lambda y, args: log_density(y))
    return LogProbFunctions(
        batched=jax.jit(jax.vmap(single, in_axes=(0, None))), single=single,
        value_and_grad=jax.jit(jax.value_and_grad(single)), hessian=jax.jit(jax.hessian(single)), pointwise=None,
    )


def _chain(draws, log_density):
    chain_y = draws.reshape(8, -1, draws.shape[-1])  # (walker, draw, param)
    log_prob = np.asarray(jax.vmap(log_density)(jnp.asarray(chain_y.reshape(-1, draws.shape[-1])))).reshape(chain_y.shape[:2])
    return chain_y, log_prob


def test_a_gaussian_gets_its_exact_evidence_and_no_note():
    a = np.array([[4.0, 1.0], [1.0, 2.0]])  # precision
    c = -3.0

    def log_density(y):
        return c - 0.5 * y @ jnp.asarray(a) @ y

    draws = np.random.default_rng(0).multivariate_normal([0.0, 0.0], np.linalg.inv(a), size=8000)
    chain_y, log_prob = _chain(draws, log_density)
    out = laplace_evidence(chain_y, log_prob, None, _functions(log_density), [-np.inf] * 2, [np.inf] * 2, names=["x", "y"])
    assert out.log_evidence == pytest.approx(c + math.log(2 * math.pi) - 0.5 * math.log(np.linalg.det(a)), abs=1e-9)
    assert out.note == "" and out.reason is None


def test_a_parameter_left_to_its_flat_prior_is_named():
    """y1's likelihood is nearly flat (sd 10) over a prior of width 1: −H⁻¹ gives sd 10, the
    draws (uniform on [0, 1]) sd 0.29, far beyond the factor 2."""

    def log_density(y):
        return -0.5 * (y[0] / 0.1) ** 2 - 0.5 * ((y[1] - 0.5) / 10.0) ** 2

    rng = np.random.default_rng(1)
    draws = np.column_stack([rng.normal(0.0, 0.1, 8000), rng.uniform(0.0, 1.0, 8000)])
    chain_y, log_prob = _chain(draws, log_density)
    out = laplace_evidence(chain_y, log_prob, None, _functions(log_density), [-np.inf, 0.0], [np.inf, 1.0], names=["R0", "W1.tau"])
    assert "unreliable" in out.note and "W1.tau" in out.note and "R0" not in out.note
    assert "left to its prior" in out.note
    assert out.note.startswith(EVIDENCE_NOTE_LEAD) and out.reason == "not_gaussian"  # (`impedax.compare` reads the reason, not the words)


def test_a_converged_chain_is_not_sent_to_a_chain_length_warning():
    """The width note named "a chain too short: see its warning" as a cause even where the chain
    had converged and no such warning was given (REAL exampleDataGamry.DTA, R0 at its prior's
    edge after 13000 steps, 2026-12-06): with ``converged`` true it names the prior or a bound
    only; with it false, or unknown (None), both as before."""

    def log_density(y):
        return -0.5 * (y[0] / 0.1) ** 2 - 0.5 * ((y[1] - 0.5) / 10.0) ** 2

    rng = np.random.default_rng(1)
    draws = np.column_stack([rng.normal(0.0, 0.1, 8000), rng.uniform(0.0, 1.0, 8000)])
    chain_y, log_prob = _chain(draws, log_density)
    notes = {c: laplace_evidence(chain_y, log_prob, None, _functions(log_density), [-np.inf, 0.0], [np.inf, 1.0], names=["R0", "W1.tau"], converged=c).note for c in (True, False, None)}
    assert "left to its prior" in notes[True] and "a bound cuts off" in notes[True] and "chain too short" not in notes[True]
    assert "chain too short: see its warning" in notes[False] and notes[None] == notes[False]
