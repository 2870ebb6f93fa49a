"""Draws that run flat to a prior's edge are flagged as set by the prior there, even where their
density at the edge is below half their central interval's (the dense rule): on REAL Autolab
with R0 + CPE1 ∥ (R1 + W1) (seed 2), W1.sigma's draws ran flat in log from its prior's lower
end 2.75 µΩ s^-1/2 up two decades (2.9 % of them in the lowest 2 % of the range, 1.43 per unit
of the prior's coordinate, against the dense rule's 1.44), so its q05 = 5.8 µΩ s^-1/2 was the
prior's and the report gave it unmarked. Oracle: the shares computed here with numpy in the
prior's own coordinate (log-uniform: t = ln(x/a)/ln(b/a))."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.bayes.diagnostics import EDGE_BAND, EDGE_DENSITY, prior_edges
from impedax.fitting.bayes.priors import Prior

REAL = Path(__file__).parent / "fixtures" / "real"


def _t(x, a, b):
    return np.log(x / a) / np.log(b / a)


def test_a_flat_tail_to_the_prior_s_edge_is_flagged():
    """SYNTHETIC: a peak at 2 mΩ (sd 0.5 in ln) holding 86 % of the draws, and 14 % spread
    log-uniformly from the prior's lower end 1 µΩ up to 100 µΩ; a peak alone is not flagged."""
    rng = np.random.default_rng(0)
    a, b = 1e-6, 1e4
    n = 100_000
    plateau = np.exp(rng.uniform(np.log(a), np.log(1e-4), int(0.14 * n)))
    peak = np.exp(rng.normal(np.log(2e-3), 0.5, n - plateau.size))
    x = np.concatenate([peak, plateau])
    t = _t(x, a, b)
    central = np.subtract(*np.quantile(t, [0.95, 0.05]))
    share = np.mean(t <= EDGE_BAND)
    assert share / EDGE_BAND < EDGE_DENSITY * 0.9 / central  # (the case: the dense rule misses it)
    prior = {"W1.sigma": Prior("loguniform", a, b)}
    edges = prior_edges(("W1.sigma",), ("Ohm s^-1/2",), x[:, None], prior, (0.0,), (np.inf,))
    assert edges.piled_up == {"W1.sigma": "lower"}
    (text,) = edges.warnings
    assert f"({100 * share:.2g} % of the draws lie in the lowest 2 % of its prior's range (log scale), as densely as in the 8 % next to them: the draws run flat to the edge)" in text, text
    assert "the prior, not the data, sets the lower end of its 90 % interval" in text
    assert prior_edges(("W1.sigma",), ("Ohm s^-1/2",), peak[:, None], prior, (0.0,), (np.inf,)).piled_up == {}


def test_a_gaussian_tail_that_reaches_the_edge_thinly_is_not_flagged():
    """SYNTHETIC: a broad Gaussian in the prior's coordinate (centre 0.45, sd 0.15 of the range):
    its density falls off toward the edge, so the data, not the prior, set its q05."""
    rng = np.random.default_rng(1)
    t = rng.normal(0.45, 0.15, 100_000)
    t = t[(t > 0) & (t < 1)]
    x = 1e-6 * (1e10) ** t
    edges = prior_edges(("R1",), ("Ohm",), x[:, None], {"R1": Prior("loguniform", 1e-6, 1e4)}, (0.0,), (np.inf,))
    assert edges.piled_up == {}


@pytest.mark.slow
def test_real_autolab_w1_sigma_is_marked():
    """The user's run (steps='auto', seed 2; about a minute): the dense rule misses W1.sigma by
    a hair, the flat rule does not."""
    post = ix.sample("R0 + CPE1 || (R1 + W1)", ix.load(REAL / "exampleDataAutolab.txt"), seed=2, progress=False)
    prior = post.priors["W1.sigma"]
    t = _t(post.samples["W1.sigma"], prior.a, prior.b)
    share, central = np.mean(t <= EDGE_BAND), np.subtract(*np.quantile(t, [0.95, 0.05]))
    assert share / EDGE_BAND < EDGE_DENSITY * 0.9 / central  # (the case)
    assert share > 0.01 and share / EDGE_BAND > 0.8 * np.mean((t > EDGE_BAND) & (t <= 5 * EDGE_BAND)) / (4 * EDGE_BAND)
    assert post.piled_up.get("W1.sigma") == "lower"
    assert "W1.sigma" in post.set_by_prior_edge
    assert any(w.startswith("W1.sigma piles up against the lower end of its prior") and "run flat to the edge" in w for w in post.warnings)
