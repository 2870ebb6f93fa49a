"""impedax's least squares against another package's solver on the same problem.

optimistix's Levenberg–Marquardt (a test dependency; impedax's fits run impedax's own
iteration) minimises the modulus-weighted residual of each synthetic spectrum, written here
in jax.numpy apart from impedax's compiler and tests/spectra.py; impedax's optimum must be
that minimum: the same χ², the same values.
"""

import numpy as np
import pytest

import impedax as ix
from spectra import CASES, noisy

optx = pytest.importorskip("optimistix")
jax = pytest.importorskip("jax")
jnp = jax.numpy


def _cpe(s, q, alpha):
    return 1.0 / (q * s**alpha)


def _parallel(a, b):
    return a * b / (a + b)


FORMULAS = {  # Z(s = jω, parameters by name)
    "rc": lambda s, p: p["R0"] + _parallel(p["R1"], 1.0 / (s * p["C1"])),
    "r_cpe": lambda s, p: p["R0"] + _parallel(p["R1"], _cpe(s, p["CPE1.Q"], p["CPE1.alpha"])),
    "randles": lambda s, p: p["R0"] + _parallel(p["R1"] + p["W1.sigma"] * jnp.sqrt(2.0) / jnp.sqrt(s), 1.0 / (s * p["C1"])),
    "two_arcs": lambda s, p: p["R0"] + _parallel(p["R1"], _cpe(s, p["CPE1.Q"], p["CPE1.alpha"])) + _parallel(p["R2"], _cpe(s, p["CPE2.Q"], p["CPE2.alpha"])),
}


def optimistix_minimum(case, f, z, start):
    """optimistix's Levenberg–Marquardt on Σ |Z_model − Z|²/|Z|² (Re and Im apart), positive
    parameters in log, exponents as they are, from ``start``: (values, χ²)."""
    names = list(start)
    s = 2j * np.pi * jnp.asarray(f)
    z, modulus = jnp.asarray(z), jnp.asarray(np.abs(z))

    def values(y):
        return {n: (y[i] if n.endswith("alpha") else jnp.exp(y[i])) for i, n in enumerate(names)}

    def residual(y, _):
        r = (FORMULAS[case](s, values(y)) - z) / modulus
        return jnp.concatenate([r.real, r.imag])

    y0 = jnp.asarray([v if n.endswith("alpha") else np.log(v) for n, v in start.items()])
    solution = optx.least_squares(residual, optx.LevenbergMarquardt(rtol=1e-10, atol=1e-12), y0, max_steps=2000)
    found = {n: float(v) for n, v in values(solution.value).items()}
    return found, float(jnp.sum(residual(solution.value, None) ** 2))


@pytest.mark.parametrize("case", list(CASES))
def test_the_fit_reaches_optimistix_minimum_of_the_same_residual(case, rng):
    model, formula, truth, (f_lo, f_hi) = CASES[case]
    f = np.geomspace(f_lo, f_hi, 50)
    z = noisy(formula(f, truth), 0.01, rng)
    result = ix.fit(model, ix.make_spectrum(f, z))
    assert result.converged, result.message
    found, chi2 = optimistix_minimum(case, f, z, truth)
    # impedax's χ² is this residual's: the numpy formula at impedax's values gives it
    own = np.sum(np.abs((formula(f, result.values) - z) / np.abs(z)) ** 2)
    assert result.chi2 == pytest.approx(own, rel=1e-9)
    assert result.chi2 <= chi2 * (1 + 1e-8)  # not above the oracle's minimum
    assert result.chi2 == pytest.approx(chi2, rel=1e-6)
    for name, value in found.items():
        # the same optimum: within a thousandth of a standard error
        assert abs(result.values[name] - value) <= 1e-3 * result.stderr[name], name
