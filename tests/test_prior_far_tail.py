"""A normal or log-normal prior whose parameter bounds sit far out in one of its tails (a bound
narrowed from a previous measurement, a prior centred outside it): the truncated density is
proper and impedax must normalise it. The mass inside the bounds was a difference of two cdfs,
which is 0 in doubles once both lie near 1 (a lower bound 8.3 sd or more above the mean; above
an upper bound the two cdfs are small and were exact), so ln p was −∞ everywhere and `sample`
stopped with "the log-probability is −∞ at the least-squares fit ... check the priors and the
data" naming neither. Oracles: scipy's truncnorm (log-space tails) and SYNTHETIC data from the
R0 + R1 ∥ C1 formula."""

import math

import jax.numpy as jnp
import numpy as np
import pytest
from scipy import stats

import impedax as ix
from impedax.fitting.bayes.priors import prior_log_density

CASES = [  # (kind, a, b, lower, upper): the bounds z sd from the centre, in either tail
    ("normal", 1e4, 1e3, 19500.0, 1e5),  # 9.5 sd above the mean
    ("normal", 1e4, 1e3, 5e4, math.inf),  # 40 sd above, no upper bound
    ("normal", 1e4, 1e3, 0.0, 500.0),  # 9.5 sd below (was already exact)
    ("lognormal", 1e-6, 0.1, 1e-5, 1.0),  # ln: 23 sd above the median
]


def _oracle(kind, a, b, lower, upper):
    if kind == "normal":
        return stats.truncnorm((lower - a) / b, (upper - a) / b, loc=a, scale=b)
    lo = (math.log(lower) - math.log(a)) / b
    hi = (math.log(upper) - math.log(a)) / b if math.isfinite(upper) else math.inf
    return lo, hi


@pytest.mark.parametrize("kind, a, b, lower, upper", CASES)
def test_the_density_far_in_a_tail_is_the_truncated_one(kind, a, b, lower, upper):
    prior = ix.Prior(kind, a, b)
    if kind == "normal":
        oracle = _oracle(kind, a, b, lower, upper)
        x = oracle.ppf([0.01, 0.3, 0.5, 0.9])
        expected_logpdf, expected_cdf = oracle.logpdf(x), oracle.cdf(x)
    else:  # ln x ~ N(ln a, b²) truncated: p(x) = truncnorm(ln x)/x
        lo, hi = _oracle(kind, a, b, lower, upper)
        z = stats.truncnorm(lo, hi)
        u = z.ppf([0.01, 0.3, 0.5, 0.9])
        x = np.exp(math.log(a) + b * u)
        expected_logpdf, expected_cdf = z.logpdf(u) - math.log(b) - np.log(x), z.cdf(u)
    assert math.isfinite(prior.log_normaliser(lower, upper))
    args = [jnp.full(x.shape, v) for v in (prior.code, prior.a, prior.b, lower, upper, prior.log_normaliser(lower, upper))]
    ours = np.asarray(prior_log_density(jnp.asarray(x), *args))
    np.testing.assert_allclose(ours, expected_logpdf, rtol=1e-9)
    np.testing.assert_allclose(prior.cdf(x, lower, upper), expected_cdf, rtol=1e-8, atol=1e-12)


def test_sample_runs_with_a_bound_far_in_the_priors_upper_tail():
    """R1 = 20 kΩ (SYNTHETIC, 1 % noise); R1's prior normal(10 kΩ, 1 kΩ) cut to R1 ≥ 19.5 kΩ: the
    data hold R1 to ±0.3 %, the prior's slope there, −(R1 − 10 kΩ)/(1 kΩ)² ≈ −0.01/Ω, moves it a
    little below the data's value but not below the bound."""
    f = np.geomspace(0.1, 1e5, 41)
    rng = np.random.default_rng(0)
    z = 10 + 2e4 / (1 + 2j * np.pi * f * 2e4 * 1e-6)
    z = z * (1 + 0.01 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))
    post = ix.sample("R0 + R1 || C1", ix.make_spectrum(f, z), priors={"R1": "normal:1e4,1e3"}, bounds={"R1": (19500.0, 1e5)}, steps=400, seed=1, progress=False)
    r1 = post.samples["R1"]
    assert r1.min() > 19500.0 and 19500.0 < np.median(r1) < 2.02e4
