"""A joint posterior's JSON (`SharedPosterior.summary`, `impedax sample --shared --json`) gives the
global least-squares start the walkers began at, ``start_fit``, as a single spectrum's does
(added there 2026-12-01: its ± beside the intervals); the joint one had none, so users saw the
two compared only in the warning when they differ 2×. Oracle: scipy's least squares of the
same joint model (R0 shared, R1 and C1 per spectrum; residuals relative to |Z_data|, the
``modulus`` weighting of proportional noise) on SYNTHETIC RC spectra."""

import json

import numpy as np
from scipy.optimize import least_squares

from test_shared_posterior_roundtrip import FREQ, proportional, rc_impedance  # noqa: F401  (proportional: a fixture)


def test_the_json_gives_the_global_start_fit(proportional):  # noqa: F811
    post = proportional
    z = post.z_data  # (2, N): trials 3 and 7

    def residuals(log_x):
        r0, r1a, c1a, r1b, c1b = np.exp(log_x)
        res = [(rc_impedance(FREQ, r0, r1, c1) - zi) / np.abs(zi) for zi, r1, c1 in ((z[0], r1a, c1a), (z[1], r1b, c1b))]
        return np.concatenate([np.concatenate([r.real, r.imag]) for r in res])

    best = least_squares(residuals, np.log([50.0, 1000.0, 5e-7, 1000.0, 5e-7]), xtol=1e-14, ftol=1e-14, gtol=1e-14)
    expected = dict(zip(["R0", "R1[trial=3]", "C1[trial=3]", "R1[trial=7]", "C1[trial=7]"], np.exp(best.x)))
    start = json.loads(json.dumps(post.summary()))["start_fit"]  # (JSON as written)
    assert start["model"] == "R0 + R1 || C1" and start["weighting"] == "modulus" and start["at_bound"] == []
    assert set(start["values"]) == set(expected) == set(start["stderr"])  # (every sampled circuit parameter; sigma_rel has no start fit)
    for name, value in expected.items():
        assert abs(start["values"][name] / value - 1) < 1e-5, (name, start["values"][name], value)
        assert 0 < start["stderr"][name] < 0.1 * start["values"][name]  # (1 % noise on 30 points: well determined)
