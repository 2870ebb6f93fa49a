"""Statistics of least-squares fits: information criteria, covariances and identifiability
from the Jacobian, and the whiteness test that decides whether a fit reached the noise."""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ..passivity import FIT_RESIDUAL_NOISE, KK_RESIDUAL_NOISE, NOISE_OF_SIGMA, NON_PASSIVE_CHANCE, NON_PASSIVE_MARGIN, chance_depth, non_passive, non_passive_words, top_of_band  # (the rule of Re Z < 0, below JAX: `impedax inspect` applies it too)

__all__ = ["difference_noise", "residual_noise", "information_criteria", "known_noise_criteria", "KNOWN_SIGMA", "UNKNOWN_VARIANCE", "covariances", "null_sets", "uncertainties", "at_noise_floor", "dominant_points", "non_passive", "fit_noise", "chance_depth", "non_passive_words", "top_of_band", "NOISE_OF_SIGMA", "FIT_RESIDUAL_NOISE", "KK_RESIDUAL_NOISE", "SINGULAR_RATIO_LIMIT", "DOMINANT_FRACTION", "NON_PASSIVE_MARGIN", "NON_PASSIVE_CHANCE"]

# a Jacobian direction whose singular value is below this fraction of the largest is not
# determined by the data (its parameters are reported together)
SINGULAR_RATIO_LIMIT = 1e-8
# Jacobians whose equilibrated JᵀJ has a condition number provably below this get its inverse
# directly (errors ~ cond · 1e-16: the same as the eigendecomposition's), the others its
# eigendecomposition or SVD; above this the two could differ by more than 1e-10
WELL_CONDITIONED = 1e6


def information_criteria(chi2: float, n_residuals: int, n_free: int) -> tuple[float, float]:
    """AIC = n ln(χ²/n) + 2k and BIC = n ln(χ²/n) + k ln n over the n = 2N real residuals
    (the convention of lmfit; differences between models on the same data are what matter).
    Broadcasts over arrays of chi² (batch fits)."""
    n = n_residuals
    if np.ndim(chi2):
        base = n * np.log(np.maximum(chi2, 1e-300) / n)
        return base + 2 * n_free, base + n_free * np.log(n)
    base = n * math.log(max(chi2, 1e-300) / n)
    return base + 2 * n_free, base + n_free * math.log(n)


KNOWN_SIGMA = "chi2 + 2k"
"""The AIC form of a fit weighted by the data's sigma taken as the noise: −2 ln L = χ² + const
(`known_noise_criteria`; ``impedax compare``'s under ``weighting="sigma"``)."""
UNKNOWN_VARIANCE = "n ln(chi2/n) + 2k"
"""The AIC form of `information_criteria`: the weights are relative and the noise scale is
estimated (σ̂² = χ²/n), −2 ln L = n ln(χ²/n) + const (lmfit's convention, `FitResult.aic`)."""


def known_noise_criteria(chi2: float, n_residuals: int, n_free: int) -> tuple[float, float]:
    """AIC = χ² + 2k and BIC = χ² + k ln n (`KNOWN_SIGMA`): the criteria of a fit whose weights
    are the data's σ, taken as the noise, so that χ² is −2 ln L up to a constant."""
    return chi2 + 2 * n_free, chi2 + n_free * math.log(n_residuals)


def covariances(jac: np.ndarray, chi2_red, weighting: str):
    """Covariance and correlation matrices from Jacobians (..., M, K) in parameter space,
    with the singular values and right singular vectors of the column-equilibrated Jacobian
    (equilibrated, proportional columns give an evenly weighted null vector). Tikhonov-
    regularised, so undetermined directions show as huge variances and ±1 correlations, not
    NaN (NaN only for a Jacobian with an inf or NaN entry); scaled by the reduced chi² unless
    the weights are the data's sigma (as lmfit).

    Jacobians proven well-conditioned (`WELL_CONDITIONED`) take the plain inverse of JᵀJ and
    have NaN singular values and vectors: they have no near-null direction to report."""
    batch, (m, k) = jac.shape[:-2], jac.shape[-2:]
    jac = jac.reshape(-1, m, k)
    # a Jacobian with an inf or NaN entry (a start far out on a parameter's range) has no
    # covariance: NaN, said so by the result, never an exception from LAPACK
    finite = np.all(np.isfinite(jac), axis=(-2, -1))
    dtype = np.result_type(jac.dtype, 0.0)  # (np.where's, without its copy when all are finite)
    jac = np.asarray(jac, dtype) if finite.all() else np.where(finite[:, None, None], jac, 0.0)
    # columns divided by their largest entry before squaring, so that sensitivities of 1e154
    # and more (JᵀJ would overflow) are equilibrated like any other
    peak = _column_peaks(np.abs(jac))
    peak = np.where(peak > 0, peak, 1.0)
    # (two quotients, not one: a matrix against its own transpose goes to another BLAS routine,
    # whose rounding moved ill-conditioned covariances by 1e-10)
    gram = np.swapaxes(jac / peak[:, None, :], -1, -2) @ (jac / peak[:, None, :])
    norms = np.sqrt(np.einsum("bkk->bk", gram))
    scale = np.where(norms > 0, 1.0 / np.where(norms > 0, norms, 1.0), 1.0)
    gram = gram * scale[:, :, None] * scale[:, None, :]  # of the column-equilibrated Jacobian
    with np.errstate(under="ignore"):
        scale = scale / peak
    inverse = np.full(gram.shape, np.nan)
    s, vt = np.full(norms.shape, np.nan), np.full(gram.shape, np.nan)
    regular = np.flatnonzero(np.all(norms > 0, axis=-1) & finite)
    try:
        inverse[regular] = np.linalg.inv(gram[regular])
    except np.linalg.LinAlgError:  # one of them exactly singular: all take the decomposition
        pass
    # cond(JᵀJ) = λ_max/λ_min ≤ trace(JᵀJ)·trace((JᵀJ)⁻¹) = bound; below the limit the inverse is
    # as accurate as the decomposition, and the regularisation below would change it by < 1e-20.
    # The inverse of a numerically singular JᵀJ has a trace of ±1e16 or more (the sign is
    # rounding's): the bound is then huge or negative
    with np.errstate(invalid="ignore"):
        bound = np.trace(gram, axis1=1, axis2=2) * np.trace(inverse, axis1=1, axis2=2)
        spectral = np.flatnonzero(~((bound > 0) & (bound < WELL_CONDITIONED)) & finite)
    if spectral.size:
        # singular values from the eigenvalues of JᵀJ (K×K, far cheaper than the SVD of J);
        # where they span more than 1e-4 (eigenvalues 1e-8), squaring the condition number
        # would cost accuracy, so those Jacobians get the SVD itself
        eigenvalues, vectors = np.linalg.eigh(gram[spectral])
        s[spectral] = np.sqrt(np.clip(eigenvalues[:, ::-1], 0, None))
        vt[spectral] = np.swapaxes(vectors[:, :, ::-1], -1, -2)
        ill = spectral[~(s[spectral, -1] > 1e-4 * s[spectral, 0])]
        if ill.size:
            _, s[ill], vt[ill] = np.linalg.svd(jac[ill] * scale[ill, None, :], full_matrices=False)
        s_max = np.where(s[spectral, :1] > 0, s[spectral, :1], 1.0)
        with np.errstate(over="ignore", invalid="ignore"):  # a column of zeros: infinite variance, said so
            inverse[spectral] = (np.swapaxes(vt[spectral], -1, -2) * (1.0 / (s[spectral] ** 2 + (1e-13 * s_max) ** 2))[:, None, :]) @ vt[spectral]
    with np.errstate(over="ignore", invalid="ignore"):
        cov = (inverse * scale[:, :, None] * scale[:, None, :]).reshape(*batch, k, k)
    s, vt = s.reshape(*batch, k), vt.reshape(*batch, k, k)
    if weighting != "sigma":
        chi2_red = np.asarray(chi2_red, float)
        with np.errstate(over="ignore", invalid="ignore"):  # (an infinite variance stays infinite: said so)
            cov = cov * np.where(np.isfinite(chi2_red), chi2_red, 1.0)[..., None, None]
    d = np.sqrt(np.clip(np.einsum("...ii->...i", cov), 0, None))
    with np.errstate(all="ignore"):
        corr = np.clip(np.nan_to_num(cov / (d[..., :, None] * d[..., None, :]), nan=0.0), -1, 1)
    k = jac.shape[-1]
    corr[..., np.arange(k), np.arange(k)] = 1.0
    return cov, corr, s, vt


def _column_peaks(magnitudes: np.ndarray) -> np.ndarray:
    """The largest entry of each column of a stack (B, M, K): ``np.max(magnitudes, axis=-2)``,
    the same numbers (a maximum has no rounding), by halving the rows, ~5× faster for a batch's
    (1000, 114, 8) stack, where NumPy reduces the short rows one element at a time."""
    if not magnitudes.shape[-2]:
        return np.max(magnitudes, axis=-2)  # (NumPy's error for an empty stack)
    while magnitudes.shape[-2] > 1:
        half = magnitudes.shape[-2] // 2
        top = np.maximum(magnitudes[:, :half], magnitudes[:, half : 2 * half])
        if magnitudes.shape[-2] % 2:  # (the odd row joins the last pair's)
            top[:, -1] = np.maximum(top[:, -1], magnitudes[:, -1])
        magnitudes = top
    return magnitudes[:, 0]


def null_sets(s: np.ndarray, vt: np.ndarray, names: Sequence[str]):
    """Groups of parameters along near-null directions of one equilibrated Jacobian, each group
    once (two directions over the same parameters, a Havriliak–Negami element's four on REAL
    CHInstruments data, give the group and its warning once), and the
    smallest-to-largest singular value ratio."""
    s_max = s[0] if s.size and s[0] > 0 else 1.0
    null: list[list[str]] = []
    for j in np.flatnonzero(s < SINGULAR_RATIO_LIMIT * s_max):
        add_null_group(null, [names[i] for i in np.flatnonzero(np.abs(vt[j]) > 0.2)])
    return null, float(s[-1] / s_max) if s.size else 1.0


def add_null_group(groups: list[list[str]], group: list[str]) -> None:
    """Add the parameters of one near-null direction to ``groups`` unless a direction over the
    same parameters gave it already: two such directions are one group and one warning
    (`null_sets`; `shared.joint_null_sets` alike)."""
    if group not in groups:
        groups.append(group)


def uncertainties(jac: np.ndarray, chi2_red: float, weighting: str, names: Sequence[str]):
    """(covariance, correlation, null sets, singular-value ratio) of one fit (`covariances`)."""
    if len(names) == 0:
        return np.zeros((0, 0)), np.zeros((0, 0)), [], 0.0
    cov, corr, s, vt = covariances(jac, chi2_red, weighting)
    return (cov, corr, *null_sets(s, vt, names))


# the guess's fit is accepted without a multistart when its weighted residuals look like noise:
# lag-1 autocorrelation along frequency below this (white noise: ≈ 0 ± 1/√(2N); a misfit
# that the multistart could improve leaves smooth, strongly correlated residuals)
WHITENESS_LIMIT = 0.5
MIN_POINTS_FOR_WHITENESS = 10


def at_noise_floor(freq, z, z_model, inv_re, inv_im, code) -> np.ndarray:
    """Whether fits (…, N) converged (``code == 0``) with residuals that look like white noise;
    broadcasts over leading batch dimensions."""
    order = np.argsort(freq)
    with np.errstate(all="ignore"):
        dz = (np.asarray(z_model) - z)[..., order]
        parts = [dz.real * np.asarray(inv_re)[..., order], dz.imag * np.asarray(inv_im)[..., order]]
        num = sum(np.sum(p[..., 1:] * p[..., :-1], axis=-1) for p in parts)
        den = sum(np.sum(p**2, axis=-1) for p in parts)
        rho = num / den
    ok = (np.asarray(code) == 0) & np.isfinite(den) & (den > 0) & (rho < WHITENESS_LIMIT)
    return ok & (len(order) >= MIN_POINTS_FOR_WHITENESS)


# a weighting leaves a fit dominated by a few points when at most this fraction of its 2N
# residuals (at least one) carry more than half of the weight, measured against modulus
# weighting (relative errors, every residual alike): (|Z_k| / w_k)² per residual
DOMINANT_FRACTION = 0.05


def dominant_points(z, inv_re, inv_im) -> tuple[np.ndarray, np.ndarray]:
    """Points (…, N) whose residuals carry most of the weight, and the share they carry (…).

    Residual k weighs (|Z_k|·(1/w_k))² relative to modulus weighting; the heaviest residuals
    are taken until they hold more than half of the total; when they number at most
    `DOMINANT_FRACTION` of all 2N (at least one), their points are returned, else none.
    Proportional weighting on a component crossing zero is the usual cause."""
    z = np.asarray(z)
    n = z.shape[-1]
    modulus = np.abs(z)
    with np.errstate(all="ignore"):
        weight = np.concatenate([(np.asarray(inv_re) * modulus) ** 2, (np.asarray(inv_im) * modulus) ** 2], axis=-1)
        weight = np.where(np.isfinite(weight), weight, 0.0)
        order = np.argsort(-weight, axis=-1, kind="stable")
        cumulative = np.cumsum(np.take_along_axis(weight, order, axis=-1), axis=-1)
        total = cumulative[..., -1:]
        needed = np.sum(cumulative <= 0.5 * total, axis=-1) + 1  # residuals until past half
    limit = max(1, int(math.floor(DOMINANT_FRACTION * 2 * n)))
    dominated = (needed <= limit) & (total[..., 0] > 0)
    heavy = np.zeros(weight.shape, bool)
    np.put_along_axis(heavy, order, np.arange(2 * n) < needed[..., None], axis=-1)
    heavy &= dominated[..., None]
    with np.errstate(all="ignore"):
        share = np.where(dominated, np.sum(np.where(heavy, weight, 0.0), axis=-1) / total[..., 0], 0.0)
    return heavy[..., :n] | heavy[..., n:], share


def fit_noise(freq, z, z_model, n_free: int) -> np.ndarray:
    """σ [Ω] of each component of each point of spectra z (…, N) estimated from a fit z_model:
    `residual_noise` of the relative residuals (first differences in frequency order, which a
    smooth misfit barely changes) × |Z|; 0 where it cannot be estimated (below 3 points)."""
    z, z_model = np.atleast_2d(z), np.atleast_2d(z_model)
    order = np.argsort(np.asarray(freq, float))
    with np.errstate(all="ignore"):
        rel = (z - z_model) / np.abs(z)
    levels = residual_noise(rel.real, rel.imag, order, n_free)
    levels = np.where(np.isfinite(levels), levels, 0.0)
    return levels[:, None] * np.abs(z)


_MAD_TO_SIGMA = 1.482602218505602  # 1/Φ⁻¹(3/4): median(|x|)·this = σ for Gaussian x


def difference_noise(differences: np.ndarray) -> float | np.ndarray:
    """Robust σ of white noise from its first differences in frequency order (a difference of
    two independent draws has σ√2): 1.4826·median|d|/√2. A smooth deviation barely changes it.
    Of the last axis: one σ per row of a stack of differences (B, M)."""
    sigma = _MAD_TO_SIGMA * np.median(np.abs(differences), axis=-1) / math.sqrt(2.0)
    return float(sigma) if np.ndim(sigma) == 0 else sigma


def residual_noise(residual_real: np.ndarray, residual_imag: np.ndarray, order: np.ndarray, n_params: float) -> float | np.ndarray:
    """Robust σ of the random part of relative residuals (the KK test's noise estimate):
    `difference_noise` of the first differences of Re and Im in frequency order (``order``),
    which a smooth (drift-like) deviation barely changes, inflated by √(2N/(2N − P)) for the P
    fitted (or effective) parameters; NaN below 3 points. Residuals of several spectra on one
    grid (B, N) give one σ per spectrum, in one pass (called spectrum by spectrum, a batch of
    1,000 fits of 57 points spent 26.5 ms in it, in one pass 4.6 ms)."""
    n = residual_real.shape[-1]
    if n < 3:
        return math.nan if residual_real.ndim < 2 else np.full(residual_real.shape[:-1], np.nan)
    d = np.concatenate([np.diff(residual_real[..., order], axis=-1), np.diff(residual_imag[..., order], axis=-1)], axis=-1)
    return difference_noise(d) * math.sqrt(2 * n / max(2 * n - n_params, 1))
