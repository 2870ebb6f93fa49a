"""The credible band's λ (`DRTResult.band_lambda`) maximises the Bayesian evidence of the model
docs/drt.md states: b ~ N(Ax, σ²I), a smoothness prior x_γ ~ N(0, (σ²/λ) Γ⁻¹) on the RBF
weights only, R_∞, L (and 1/C) under a flat prior, σ² under Jeffreys' prior dσ²/σ².

Oracle, independent of the SVD formula in tikhonov.py: the Gaussian marginal likelihood written
out with numpy on SYNTHETIC spectra of 16 frequencies. Given σ² and λ, b ~ N(A_s x_s, σ²K) with
K = I + A_γ (λΓ)⁻¹ A_γᵀ; the flat x_s integrates in closed form to
(2πσ²)^{-(n−n_s)/2} det K^{-1/2} det(A_sᵀK⁻¹A_s)^{-1/2} exp(−bᵀPb/2σ²),
P = K⁻¹ − K⁻¹A_s(A_sᵀK⁻¹A_s)⁻¹A_sᵀK⁻¹, and σ² is integrated numerically (scipy quad over ln σ²).
The design is built here from `basis` (impedance integrals checked against quad in
tests/test_drt.py), weights 1/|Z| and Z over max|Z| (docs/drt.md, "Choosing λ"). The series
columns are scaled as the test likes: under a flat prior their scale does not move λ.
The evidence that gave the series terms the prior's λ-scaled variance (σ²/λη, η = 1e-10) put
the band's λ 0.10 decade above this optimum on the first spectrum.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate
from scipy.optimize import minimize_scalar

from impedax.fitting.drt import drt
from impedax.fitting.drt.basis import impedance_integrals, penalty_matrix, rbf_basis

F = np.geomspace(0.1, 1e4, 16)
W = 2 * np.pi * F


def _noisy(z, seed):
    rng = np.random.default_rng(seed)
    return z * (1 + 0.01 * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2))


CASES = {
    "R + ZARC + L": (_noisy(10 + 100 / (1 + (1j * W * 1e-2) ** 0.8) + 1j * W * 1e-6, 1), False),
    "R + ZARC + series C": (_noisy(10 + 100 / (1 + (1j * W * 1e-3) ** 0.8) + 1 / (1j * W * 1e-3), 2), True),
}


def _oracle_log_evidence(z, capacitance, log10_lam):
    basis = rbf_basis(F, points_per_decade=4.0, extend_short=0.0, extend_long=0.0 if capacitance else 1.0, fwhm_steps=1.5)
    a_re, a_im = impedance_integrals(W, basis)
    zn = z / np.abs(z).max()
    w = 1 / np.abs(zn)
    series = [(np.ones_like(W), np.zeros_like(W)), (np.zeros_like(W), W)] + ([(np.zeros_like(W), -1 / W)] if capacitance else [])
    a_s = np.vstack([np.column_stack([w * re for re, _ in series]), np.column_stack([w * im for _, im in series])])
    a_g = np.vstack([w[:, None] * a_re, w[:, None] * a_im])
    b = np.concatenate([w * zn.real, w * zn.imag])
    n, n_s = b.size, a_s.shape[1]
    chol = np.linalg.cholesky(penalty_matrix(basis, 2) + 1e-10 * np.eye(a_g.shape[1]))
    g = np.linalg.solve(chol, a_g.T).T  # A_γ L⁻ᵀ: A_γ Γ⁻¹ A_γᵀ = g gᵀ
    k = np.eye(n) + g @ g.T / 10.0**log10_lam
    logdet_k = 2 * np.sum(np.log(np.diag(np.linalg.cholesky(k))))
    k_as, k_b = np.linalg.solve(k, a_s), np.linalg.solve(k, b)
    m = a_s.T @ k_as
    q = b @ k_b - k_b @ a_s @ np.linalg.solve(m, a_s.T @ k_b)
    dof = n - n_s

    def log_integrand(t):  # ln σ² = t; dσ²/σ² = dt
        return -0.5 * dof * (math.log(2 * math.pi) + t) - q / (2 * math.exp(t))

    t0 = math.log(q / dof)
    peak = log_integrand(t0)
    value = integrate.quad(lambda t: math.exp(log_integrand(t) - peak), t0 - 30, t0 + 30, limit=200)[0]
    return -0.5 * logdet_k - 0.5 * np.linalg.slogdet(m)[1] + peak + math.log(value)


@pytest.mark.parametrize("case", list(CASES))
def test_band_lambda_maximises_the_brute_force_evidence(case):
    z, capacitance = CASES[case]
    result = drt((F, z), points_per_decade=4.0, capacitance=capacitance)
    grid = np.arange(-7.0, 2.0001, 0.25)
    values = [_oracle_log_evidence(z, capacitance, x) for x in grid]
    k = int(np.argmax(values))
    assert 0 < k < grid.size - 1  # an interior optimum, so the comparison means something
    best = minimize_scalar(lambda x: -_oracle_log_evidence(z, capacitance, x), bounds=(grid[k - 1], grid[k + 1]), method="bounded", options={"xatol": 1e-4}).x
    assert abs(math.log10(result.band_lambda) - best) < 0.02, (result.band_lambda, 10**best)
