"""Gaussian radial basis over ln τ for the distribution of relaxation times, and its exact-to-
rounding impedance integrals.

The DRT model (Schmidt & Ivers-Tiffée 2011; Wan, Saccoccio, Chen, Ciucci, Electrochim. Acta 184
(2015) 483, eqs 4–12):

    Z(ω) = R_∞ + jωL [+ 1/(jωC)] + ∫ γ(ln τ) / (1 + jωτ) d ln τ,
    γ(y) = Σ_m x_m φ_m(y),   φ_m(y) = exp(−(ε (y − y_m))²),   y = ln τ.

γ has units of Ω (resistance per unit of ln τ); ∫ γ d ln τ is the polarisation resistance.
Each basis function contributes A'_{nm} + j A''_{nm} to Z(ω_n), with s = ln(ω_n τ_m):

    A'(s)  =  ∫ exp(−(ε u)²) / (1 + e^{2(u+s)}) du,
    A''(s) = −∫ exp(−(ε u)²) / (2 cosh(u + s)) du.

How they are computed: both integrands are analytic in the strip |Im u| < π/2 (the kernels'
poles sit at u + s = ±jπ/2) and decay like a Gaussian, so the trapezoidal rule on a uniform grid
converges geometrically, with error ≈ exp(−π²/h) from the poles plus the Gaussian tail beyond the
truncation (Trefethen & Weideman, SIAM Review 56 (2014) 385, §5). With step h = min(0.05, 0.1/ε)
and the tails cut at |u| = 9/ε (exp(−81)), both terms are far below float64 rounding;
tests/test_drt.py checks the values against scipy.integrate.quad to 1e-12.

The roughness penalty ∫ (d^k γ/dy^k)² dy = xᵀ Γ_k x has a closed form for Gaussians of equal
width: with d = y_i − y_j, a = ε²/2 and c = √(π/2)/ε,
    k = 1:  Γ_ij = c e^{−a d²} (2a − 4a² d²),
    k = 2:  Γ_ij = c e^{−a d²} (12a² − 48a³ d² + 16a⁴ d⁴).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["RBFBasis", "rbf_basis", "impedance_integrals", "penalty_matrix"]


@dataclass(frozen=True, eq=False)
class RBFBasis:
    """Centres ``ln_tau`` (M,) [ln s], spacing ``step`` (in ln τ) and shape ``epsilon`` of the
    Gaussian RBFs φ_m(y) = exp(−(ε (y − y_m))²); FWHM = 2√(ln 2)/ε."""

    ln_tau: np.ndarray
    step: float
    epsilon: float

    @property
    def tau(self) -> np.ndarray:
        return np.exp(self.ln_tau)

    @property
    def fwhm_decades(self) -> float:
        return 2.0 * math.sqrt(math.log(2.0)) / self.epsilon / math.log(10.0)

    def evaluate(self, ln_tau: np.ndarray) -> np.ndarray:
        """Φ (len(ln_tau), M): γ(ln_tau) = Φ @ x."""
        d = np.asarray(ln_tau, float)[:, None] - self.ln_tau[None, :]
        return np.exp(-((self.epsilon * d) ** 2))

    def integral(self) -> np.ndarray:
        """∫ φ_m d ln τ = √π/ε for every m (M,)."""
        return np.full(self.ln_tau.size, math.sqrt(math.pi) / self.epsilon)


def rbf_basis(frequency: np.ndarray, *, points_per_decade: float = 8.0, extend_short: float = 1.0, extend_long: float = 1.0, fwhm_steps: float = 2.0) -> RBFBasis:
    """Centres log-spaced from 1/(2π f_max) to 1/(2π f_min), extended by ``extend_short``
    decades below and ``extend_long`` above (γ just outside the measured window still shapes the
    edges of the spectrum), ``points_per_decade`` per decade, each Gaussian ``fwhm_steps``
    spacings wide."""
    f = np.asarray(frequency, float)
    lo = math.log(1.0 / (2 * math.pi * f.max())) - extend_short * math.log(10.0)
    hi = math.log(1.0 / (2 * math.pi * f.min())) + extend_long * math.log(10.0)
    count = max(int(round((hi - lo) / math.log(10.0) * points_per_decade)) + 1, 2)
    ln_tau = np.linspace(lo, hi, count)
    step = float(ln_tau[1] - ln_tau[0])
    epsilon = 2.0 * math.sqrt(math.log(2.0)) / (fwhm_steps * step)
    return RBFBasis(ln_tau=ln_tau, step=step, epsilon=epsilon)


def impedance_integrals(omega: np.ndarray, basis: RBFBasis) -> tuple[np.ndarray, np.ndarray]:
    """(A', A'') of shape (N, M): the real and imaginary parts of ∫ φ_m(y)/(1 + jω_n e^y) dy,
    by the trapezoidal rule described in the module docstring."""
    eps = basis.epsilon
    h = min(0.05, 0.1 / eps)
    half = 9.0 / eps
    u = np.arange(-math.ceil(half / h), math.ceil(half / h) + 1) * h
    weight = np.exp(-((eps * u) ** 2)) * h  # (K,)
    s = np.log(np.asarray(omega, float))[:, None] + basis.ln_tau[None, :]  # (N, M)
    x = s[:, :, None] + u[None, None, :]
    real_kernel = 0.5 * (1.0 - np.tanh(x))  # 1/(1 + e^{2x}) without overflow
    e = np.exp(-np.abs(x))
    imag_kernel = e / (1.0 + e * e)  # 1/(2 cosh x) without overflow
    return real_kernel @ weight, -(imag_kernel @ weight)


def penalty_matrix(basis: RBFBasis, derivative: int = 1) -> np.ndarray:
    """Γ (M, M) with xᵀΓx = ∫ (d^k γ / d(ln τ)^k)² d ln τ for k = ``derivative`` (1 or 2)."""
    a = basis.epsilon**2 / 2.0
    c = math.sqrt(math.pi / 2.0) / basis.epsilon
    d2 = (basis.ln_tau[:, None] - basis.ln_tau[None, :]) ** 2
    g = c * np.exp(-a * d2)
    if derivative == 1:
        return g * (2 * a - 4 * a**2 * d2)
    if derivative == 2:
        return g * (12 * a**2 - 48 * a**3 * d2 + 16 * a**4 * d2**2)
    raise ValueError(derivative)
