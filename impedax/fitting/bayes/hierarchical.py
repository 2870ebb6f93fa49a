"""Hierarchical Bayesian model of many spectra (trials, and sessions as a level), with model
discrepancy in the noise, sampled by NUTS (blackjax).

Model (docs/bayesian.md, "Hierarchical model across trials"), for trial t of session g(t):

    ln θ_tj = μ_j + τ_j ζ_g(t)j + s_j η_tj,  ζ, η ~ N(0, 1)      (per-trial parameters j; non-centred)
    shared parameters φ: one value for every trial
    Re, Im of r_tk = Z(θ_t, φ; f_k) + ε_k + e_tk − Z_tk ~ N(0, σ_tk²),  σ_tk = |Z_tk| √(ν_k² + δ²)
    ε: an error shared by every trial, Gaussian with the covariance the data's
       ``common_error_modes`` give (ε = Σ_j ξ_j d_j, ξ ~ N(0, 1)); marginalised; none without them
    e_t: each trial's own error, smooth in frequency, Gaussian with the covariance the data's
       ``trial_error_modes`` give (e_t = Σ_j ζ_tj m_j, ζ ~ N(0, 1) independent between trials);
       marginalised; none without them

μ_j is the population median (geometric mean) of parameter j, s_j its spread between trials
(sd of ln θ), τ_j between sessions (only with a session level). ν_k is the relative noise at
frequency k estimated from the trial scatter (the sd over trials of the per-trial least-squares
residuals about their mean, smoothed over neighbouring frequencies); δ is the sampled
discrepancy floor: a misfit common to all trials (structure the model lacks) cannot hide in ν_k
and raises δ, which widens every interval. ε is an error known to be common to all trials, e.g.
the error of the skin and screen means subtracted from every Sirin trial
(`impedax.models.sirin.trial_remainders`): independent noise would average it away over the
trials, so it is kept as one shared draw (docs/bayesian.md, "Errors shared by every trial").
e_t is each Sirin trial's own skin and screen deviating from those means: a whole spectrum,
correlated across frequencies, which independent noise would let the trial's parameters absorb.

Priors: μ_j ~ N(ln θ̂_j, 2²) about the median of the per-trial least-squares fits (95 % within
±3.9 in ln, a factor 50 either way: 3.4 decades in all; so those fits must be sound:
`impedax.models.gap` refits them weighted by each trial's noise where they stray from the trial
mean's fit); s_j, τ_j ~ half-normal(0.5) and half-normal(``session_spread_scale``); δ ~
half-normal(0.1); shared positive parameters ln φ ~ N(ln φ̂, 2²), bounded ones uniform within
their bounds (sampled through a logit).

Why NUTS: with 30 trials and 3 per-trial parameters the posterior has ~100 dimensions, where
emcee's affine-invariant moves are expected to mix poorly and NUTS follows the gradient.
`benchmarks/bench_coverage.py --ess` measures ESS/s of both on one log density; its first run
did not confirm a speed advantage (benchmarks/README.md).
"""

from __future__ import annotations

import functools
import math
import sys
import time
from dataclasses import dataclass, field
from typing import Mapping, NamedTuple, Sequence

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from ...arguments import MAX_SAMPLER_STEPS, checked_arguments, closest_name, count, progress_line_flag, real, refuse_unknown_keywords, sequence_of, seed as seed_rule
from ...circuits import DEFAULT_REGISTRY, Circuit, Registry, compile_circuit, parse
from ...data import column_width, concise_repr, make_spectrum, report_text, unit_text
from ...errors import DataError, FitError, ParameterError
from ...io.netcdf import result_dataset
from ...progress import quiet_beneath
from ..derived import draw_indices
from ..frozen import FrozenResult, KeyHintDict, freeze_fields
from ..least_squares.result import PARAMETER_UNIT_NAME
from .diagnostics import PiledUp, PriorEdges, prior_edges, reducing_bounds
from .priors import Prior, PriorKind
from .reparam import Reparametrization
from .progress import ProgressLine, announce

__all__ = ["HierarchicalPosterior", "sample_hierarchical", "hierarchical_log_density", "trial_scatter_noise", "HIERARCHICAL_PRIORS", "TARGET_ACCEPT"]

HIERARCHICAL_PRIORS = {
    "mu": "normal(ln of the median per-trial least-squares value, 2)",
    "spread_trial": "half-normal(0.5) on the sd of ln θ between trials",
    "spread_session": "half-normal(session_spread_scale) on the sd of ln θ between sessions",
    "delta": "half-normal(0.1) on the relative discrepancy floor",
    "shared": "normal(ln least-squares value, 2) in ln φ for positive φ; uniform within the bounds otherwise",
}

MU_PRIOR_SD = 2.0
"""sd (in ln) of the prior of each population median μ_j about ln θ̂_j (module docstring)."""
TARGET_ACCEPT = 0.85
"""NUTS's target acceptance rate in the warm-up's step-size adaptation (`sample_hierarchical`'s
default): higher targets take smaller steps, fewer divergent transitions, longer trajectories."""
DEFAULT_WARMUP = 400
"""`sample_hierarchical`'s warm-up steps per chain by default (the divergence warning names it)."""
CENTRED_RATIO = 3.0
"""``parameterisation="auto"`` samples a per-trial quantity centred when the median relative
standard error of its per-trial fits is below 1/CENTRED_RATIO of their spread (sd of ln)."""
_SPREAD_SCALE = 0.5
_DELTA_SCALE = 0.1


def trial_scatter_noise(z_data: np.ndarray, z_fit: np.ndarray, *, window: int = 3) -> np.ndarray:
    """Relative noise ν_k per frequency from the scatter of trials about their own fits.

    ``z_data``, ``z_fit``: complex (trials, frequencies). With ρ_tk = (Z_tk − Ẑ_tk)/|Z_tk|,
    ν_k² = Σ_t |ρ_tk − ρ̄_k|² / (2 (T − 1)) (Re and Im pooled; the mean over trials ρ̄_k, a
    misfit shared by the trials, is removed — it is the discrepancy's part), averaged over
    ``window`` neighbouring frequencies. Returns ν (frequencies,)."""
    rho = (np.asarray(z_data) - np.asarray(z_fit)) / np.abs(z_data)
    n = rho.shape[0]
    if n < 2:
        raise DataError("the noise from trial scatter needs at least 2 trials")
    dev = rho - rho.mean(axis=0)
    var = (np.abs(dev) ** 2).sum(axis=0) / (2.0 * (n - 1))
    if window > 1:
        pad = window // 2
        padded = np.pad(var, pad, mode="edge")
        var = np.convolve(padded, np.ones(window) / window, mode="valid")
    return np.sqrt(var)


class _Layout(NamedTuple):
    """Static description of one hierarchical model (hashable: one compilation per layout)."""

    circuit: Circuit
    registry: Registry
    trial_names: tuple[str, ...]  # per-trial quantities (circuit or reparametrization names)
    shared_names: tuple[str, ...]
    shared_bounded: tuple[bool, ...]  # logit (True) or log (False) for each shared parameter
    fixed_names: tuple[str, ...]
    reparametrization: Reparametrization | None
    n_sessions: int  # 1: no session level
    discrepancy: bool
    centred: tuple[bool, ...]  # per per-trial quantity: sample ln θ_tj itself (centred) or η_tj (non-centred)
    n_common: int  # leading components of the error shared by every trial (0: none)
    n_trial_modes: int = 0  # leading components of each trial's own smooth error (0: none)


class _Data(NamedTuple):
    """The arrays of one data set (a pytree argument: one compilation serves many data sets)."""

    freq: jax.Array  # (N,)
    z: jax.Array  # (T, N) complex
    nu: jax.Array  # (N,) relative noise from trial scatter
    session: jax.Array  # (T,) int index of each trial's session
    mu_center: jax.Array  # (K,) prior centre of μ
    shared_center: jax.Array  # (S,) prior centre (ln φ̂) of log-sampled shared parameters
    shared_lo: jax.Array  # (S,)
    shared_hi: jax.Array  # (S,)
    fixed: jax.Array  # (F,)
    common_basis: jax.Array  # (M, N) complex leading components of the error shared by every trial [Ω]
    common_var: jax.Array  # (2, N) variance of the rest of it, Re and Im [Ω²]
    trial_basis: jax.Array  # (P, N) complex leading components of each trial's own smooth error [Ω]
    trial_var: jax.Array  # (2, N) variance of the rest of it, Re and Im [Ω²]


def _trial_centre(pos, data: _Data, lay: _Layout):
    """Centre of each trial's ln θ (T, K): μ, plus its session's offset with a session level."""
    centre = jnp.broadcast_to(pos["mu"], (data.z.shape[0], pos["mu"].shape[0]))
    if lay.n_sessions > 1:
        centre = centre + (jnp.exp(pos["log_spread_session"])[None, :] * pos["zeta"])[data.session]
    return centre


def _split(lay: _Layout) -> tuple[list[int], list[int]]:
    """Columns (of the K per-trial quantities) sampled centred and non-centred."""
    return np.flatnonzero(np.asarray(lay.centred, dtype=bool)), np.flatnonzero(~np.asarray(lay.centred, dtype=bool))


def _trial_log_values(pos, data: _Data, lay: _Layout):
    """ln θ (T, K) from a position: a centred column is sampled itself (``log_theta``, its
    columns only), a non-centred one as centre + s η (``eta``, its columns only)."""
    cen, non = _split(lay)
    parts = []
    if cen.size:
        parts.append(pos["log_theta"])
    if non.size:
        centre = _trial_centre(pos, data, lay)[:, non]
        parts.append(centre + jnp.exp(pos["log_spread"])[None, non] * pos["eta"])
    out = jnp.concatenate(parts, axis=1) if len(parts) > 1 else parts[0]
    order = np.argsort(np.concatenate([cen, non]))
    return out if np.all(order == np.arange(order.size)) else out[:, order]


def _trial_values(pos, data: _Data, lay: _Layout):
    """Natural per-trial values θ (T, K) from a position."""
    return jnp.exp(_trial_log_values(pos, data, lay))


def _shared_values(pos, data: _Data, lay: _Layout):
    y = pos["shared"]
    bounded = jnp.asarray(lay.shared_bounded, dtype=bool)
    logistic = data.shared_lo + (data.shared_hi - data.shared_lo) * jax.nn.sigmoid(y)
    return jnp.where(bounded, logistic, jnp.exp(y))


def _circuit_params(theta_t, shared, data: _Data, lay: _Layout) -> dict:
    values = {n: theta_t[j] for j, n in enumerate(lay.trial_names)}
    values.update({n: shared[j] for j, n in enumerate(lay.shared_names)})
    values.update({n: data.fixed[j] for j, n in enumerate(lay.fixed_names)})
    rp = lay.reparametrization
    if rp is not None:
        values.update(rp.circuit_values({n: values.pop(n) for n in rp.names}))
    return values


def _model_z(pos, data: _Data, lay: _Layout):
    """Model impedance (T, N) of every trial."""
    fn = compile_circuit(lay.circuit, lay.registry)
    theta = _trial_values(pos, data, lay)
    shared = _shared_values(pos, data, lay)
    return jax.vmap(lambda th: fn(_circuit_params(th, shared, data, lay), data.freq))(theta)


def _half_normal_log(log_x, scale):
    x = jnp.exp(log_x)
    return -0.5 * (x / scale) ** 2 + log_x  # + ln|dx/d ln x|


def _log_density(pos, data: _Data, lay: _Layout, session_scale: float):
    lp = jnp.sum(-0.5 * ((pos["mu"] - data.mu_center) / MU_PRIOR_SD) ** 2)
    lp += jnp.sum(_half_normal_log(pos["log_spread"], _SPREAD_SCALE))
    cen, non = _split(lay)
    if cen.size:
        log_spread = pos["log_spread"][cen]
        lp += jnp.sum(-0.5 * ((pos["log_theta"] - _trial_centre(pos, data, lay)[:, cen]) / jnp.exp(log_spread)[None, :]) ** 2 - log_spread[None, :])
    if non.size:
        lp += jnp.sum(-0.5 * pos["eta"] ** 2)
    if lay.n_sessions > 1:
        lp += jnp.sum(_half_normal_log(pos["log_spread_session"], session_scale))
        lp += jnp.sum(-0.5 * pos["zeta"] ** 2)
    y = pos["shared"]
    bounded = jnp.asarray(lay.shared_bounded, dtype=bool)
    # uniform on (lo, hi) through a logistic: ln σ(y) + ln(1 − σ(y)) is the Jacobian
    lp += jnp.sum(jnp.where(bounded, jax.nn.log_sigmoid(y) + jax.nn.log_sigmoid(-y), -0.5 * ((y - data.shared_center) / MU_PRIOR_SD) ** 2))
    rel2 = data.nu**2
    if lay.discrepancy:
        lp += _half_normal_log(pos["log_delta"], _DELTA_SCALE)
        rel2 = rel2 + jnp.exp(2.0 * pos["log_delta"])
    var = (jnp.abs(data.z) ** 2) * rel2[None, :]  # σ_tk², each of Re and Im
    r = _model_z(pos, data, lay) - data.z
    if lay.n_trial_modes:
        total = lp + _structured_error_log_likelihood(r, var, data)
    else:
        ll = jnp.sum(-0.5 * (r.real**2 + r.imag**2) / var - jnp.log(var) - jnp.log(2.0 * jnp.pi))
        total = lp + ll + _shared_error_log_term(r, var, data.common_var, data.common_basis)
    return jnp.where(jnp.isfinite(total), total, -jnp.inf)


def _shared_error_log_term(r, var, common_var, basis):
    """What an error ε shared by every trial adds to the independent-noise log likelihood.

    Model: Z_tk = Z(θ_t, φ; f_k) + ε_k + e_tk, e independent (σ_tk² for Re and Im), ε Gaussian
    with covariance Bᵀ B + diag(c²) in the real-stacked (Re, Im) frequency space: B (M, 2N) its
    leading components, c² the rest. ε is marginalised exactly. Per frequency and part the
    residuals over trials have covariance diag(σ_tk²) + c_k² 11ᵀ (Sherman–Morrison: with
    a = Σ_t 1/σ_tk², b = Σ_t r_tk/σ_tk², s = 1 + c² a, the log density gains ½ c² b²/s − ½ ln s);
    the components add 1 ⊗ Bᵀ, a rank-M update (Woodbury: with h = a/s, g = B (b/s),
    A = I + B diag(h) Bᵀ, it gains ½ gᵀ A⁻¹ g − ½ ln det A). ``r``, ``var``: (T, N);
    ``common_var`` (2, N); ``basis`` (M, N) complex. Zero when there is no shared error."""
    a = jnp.sum(1.0 / var, axis=0)
    out, h, g = 0.0, [], []
    for part, c2 in ((r.real, common_var[0]), (r.imag, common_var[1])):
        b = jnp.sum(part / var, axis=0)
        s = 1.0 + c2 * a
        out = out + jnp.sum(0.5 * c2 * b**2 / s - 0.5 * jnp.log(s))
        h.append(a / s)
        g.append(b / s)
    if basis.shape[0]:
        stacked = jnp.concatenate([basis.real, basis.imag], axis=1)  # (M, 2N)
        h, g = jnp.concatenate(h), stacked @ jnp.concatenate(g)
        matrix = jnp.eye(basis.shape[0]) + (stacked * h[None, :]) @ stacked.T
        chol = _cholesky(matrix)
        y = _forward_substitution(chol, g[:, None])
        out = out + 0.5 * jnp.sum(y**2) - _log_diagonal_sum(chol)
    return out


def _structured_error_log_likelihood(r, var, data: _Data):
    """Log likelihood of the residuals ``r`` (T, N) when each trial also carries its own smooth
    error and every trial one shared error, both marginalised exactly.

    Model (Re and Im stacked, 2N per trial): r_t = ε + e_t + n_t with n_t independent (σ_tk²
    = ``var`` plus the rest variances of both errors), e_t = Pᵀ ζ_t (ζ_t ~ N(0, I), independent
    between trials: the trial's own skin and screen deviating from their means) and ε = Bᵀ ξ
    (ξ ~ N(0, I): the error of the subtracted means). The covariance D + U Uᵀ with U =
    [blockdiag_t(Pᵀ) | 1 ⊗ Bᵀ] gets Woodbury's identity; its capacitance matrix I + Uᵀ D⁻¹ U is
    block-arrowhead (per-trial blocks A_t = I + P D_t⁻¹ Pᵀ, border C_t = P D_t⁻¹ Bᵀ, corner
    A_c = I + Σ_t B D_t⁻¹ Bᵀ), factored block by block: L_t = chol(A_t), W_t = L_t⁻¹ C_t,
    L_s = chol(A_c − Σ_t W_tᵀ W_t). With y_t = P D_t⁻¹ r_t, y_c = B Σ_t D_t⁻¹ r_t,
    z_t = L_t⁻¹ y_t, z_c = L_s⁻¹ (y_c − Σ_t W_tᵀ z_t): ln N = ln N(r; 0, D) + ½ (Σ|z_t|² + |z_c|²)
    − Σ ln diag L_t − Σ ln diag L_s. The rests of both errors (beyond their leading components)
    enter D per frequency; the shared rest is thus counted as independent between trials."""
    rs = jnp.concatenate([r.real, r.imag], axis=1)  # (T, 2N)
    rest = jnp.concatenate([data.common_var[0] + data.trial_var[0], data.common_var[1] + data.trial_var[1]])
    v = jnp.concatenate([var, var], axis=1) + rest[None, :]
    w = 1.0 / v
    out = jnp.sum(-0.5 * rs**2 * w - 0.5 * jnp.log(2.0 * jnp.pi * v))
    p = jnp.concatenate([data.trial_basis.real, data.trial_basis.imag], axis=1)  # (P, 2N)
    a_t = jnp.eye(p.shape[0])[None] + jnp.einsum("mk,tk,nk->tmn", p, w, p)
    low_t = _cholesky(a_t)
    z_t = _forward_substitution(low_t, jnp.einsum("mk,tk->tm", p, rs * w)[..., None])[..., 0]  # (T, P)
    out = out + 0.5 * jnp.sum(z_t**2) - jnp.sum(_log_diagonal_sum(low_t))
    if data.common_basis.shape[0]:
        b = jnp.concatenate([data.common_basis.real, data.common_basis.imag], axis=1)  # (K, 2N)
        w_t = _forward_substitution(low_t, jnp.einsum("mk,tk,nk->tmn", p, w, b))  # (T, P, K)
        schur = jnp.eye(b.shape[0]) + jnp.einsum("mk,k,nk->mn", b, jnp.sum(w, axis=0), b) - jnp.einsum("tpm,tpn->mn", w_t, w_t)
        low_s = _cholesky(schur)
        y_c = b @ jnp.sum(rs * w, axis=0) - jnp.einsum("tpm,tp->m", w_t, z_t)
        z_c = _forward_substitution(low_s, y_c[:, None])[:, 0]
        out = out + 0.5 * jnp.sum(z_c**2) - _log_diagonal_sum(low_s)
    return out


def _cholesky(a):
    """Lower Cholesky factor (..., M, M) of small SPD matrices ``a`` (..., M, M), one column per
    step in whole-vector JAX operations: with c = a[:, j] − L L[j, :]ᵀ (the columns found so far),
    L[j, j] = √c_j and L[i, j] = c_i / √c_j below it. No LAPACK call (batched LAPACK under vmap
    can deadlock jaxlib 0.10's pool), and about M operations instead of the M³/6 scalar ones of an
    element-by-element factorisation."""
    m = a.shape[-1]
    rows = jnp.arange(m)
    low = jnp.zeros_like(a)
    for j in range(m):
        col = a[..., :, j] - jnp.einsum("...ik,...k->...i", low, low[..., j, :])
        diag = jnp.sqrt(col[..., j])[..., None]
        low = low.at[..., :, j].set(jnp.where(rows > j, col / diag, jnp.where(rows == j, diag, 0.0)))
    return low


def _forward_substitution(low, b):
    """Y (..., M, X) with L Y = ``b`` (..., M, X) for lower-triangular ``low`` (..., M, M), one
    row per step in whole-vector operations."""
    y = jnp.zeros(jnp.broadcast_shapes(low.shape[:-2], b.shape[:-2]) + b.shape[-2:], dtype=b.dtype)
    for i in range(low.shape[-1]):
        row = (b[..., i, :] - jnp.einsum("...k,...kx->...x", low[..., i, :], y)) / low[..., i, i][..., None]
        y = y.at[..., i, :].set(row)
    return y


def _log_diagonal_sum(low):
    """Σ ln diag L over the last two axes of ``low`` (½ ln det of the factored matrix)."""
    return jnp.sum(jnp.log(jnp.diagonal(low, axis1=-2, axis2=-1)), axis=-1)


COMMON_COMPONENTS = 12
"""Leading components of an error shared by every trial kept with their correlation across
frequencies (fixed, so one compilation serves every data set); the rest of its variance enters
per frequency."""


def _error_modes(data: xr.Dataset, name: str) -> np.ndarray | None:
    """The modes (mode, frequency) of the data variable ``name`` as a complex array, checked; None
    when the data have none."""
    if name not in data:
        return None
    modes = data[name]
    if modes.dims[-1:] != ("frequency",) or modes.ndim != 2:
        raise DataError(f"{name!r} must have dims (mode, frequency), got {modes.dims}")
    d = np.asarray(modes.values, dtype=np.complex128)
    if not np.all(np.isfinite(d)):
        raise DataError(f"{name!r} must be finite")
    return d


def _leading_components(d: np.ndarray | None, scale: np.ndarray, count: int, n_freq: int):
    """Split Σ_j d_j d_jᴴ (``d`` (modes, N) complex, Re and Im as separate real parts) into
    ``count`` leading components (``basis`` (count, N) complex, zero-padded) and the rest's
    variance per frequency (``var`` (2, N), Re and Im). Components are ranked after dividing each
    frequency by ``scale`` (the likelihood's units). ``d`` None: nothing (all zeros)."""
    basis, rest = np.zeros((count, n_freq), complex), np.zeros((2, n_freq))
    if d is None:
        return basis, rest
    stacked = np.concatenate([d.real / scale, d.imag / scale], axis=1)  # (modes, 2N), whitened
    _, sv, vt = np.linalg.svd(stacked, full_matrices=False)
    m = min(count, sv.size)
    lead = (sv[:m, None] * vt[:m]) * np.concatenate([scale, scale])[None, :]
    basis[:m] = lead[:, :n_freq] + 1j * lead[:, n_freq:]
    var = ((sv[m:, None] * vt[m:]) ** 2).sum(axis=0) * np.concatenate([scale, scale]) ** 2
    return basis, np.stack([var[:n_freq], var[n_freq:]])


def _shared_error_components(data: xr.Dataset, z: np.ndarray, nu: np.ndarray, n_freq: int):
    """Split the error shared by every trial (``common_error_modes`` of the data: ε = Σ_j ξ_j d_j,
    ξ ~ N(0, 1)) into `COMMON_COMPONENTS` leading components (``basis`` (M, N) complex) and the
    rest's variance per frequency (``var`` (2, N), Re and Im). Components
    are ranked in the likelihood's units (each frequency scaled by the noise of the trials' mean,
    |Z̄_k| ν_k/√T). No modes: nothing shared (M = 0)."""
    d = _error_modes(data, "common_error_modes")
    if d is None:
        return np.zeros((0, n_freq), complex), np.zeros((2, n_freq))
    scale = np.abs(z.mean(axis=0)) * np.maximum(nu, 1e-12) / np.sqrt(z.shape[0])
    return _leading_components(d, scale, COMMON_COMPONENTS, n_freq)


TRIAL_COMPONENTS = 6
"""Leading components of each trial's own smooth error (``trial_error_modes``) kept with their
correlation across frequencies; the rest of its variance enters per frequency."""


def _trial_error_components(data: xr.Dataset, z: np.ndarray, nu: np.ndarray, n_freq: int):
    """Leading components (``basis`` (P, N) complex) and rest variance (``var`` (2, N)) of each
    trial's own smooth error e_t = Σ_j ζ_tj m_j, ζ_tj ~ N(0, 1) independent between trials
    (``trial_error_modes`` of the data, e.g. written by `impedax.models.sirin.trial_remainders`:
    a total trial's own skin and screen deviate from the subtracted means by a whole spectrum,
    correlated across frequencies). Ranked with each frequency scaled by one trial's noise
    |Z̄_k| ν_k. No modes: P = 0."""
    d = _error_modes(data, "trial_error_modes")
    if d is None:
        return np.zeros((0, n_freq), complex), np.zeros((2, n_freq))
    scale = np.abs(z.mean(axis=0)) * np.maximum(nu, 1e-12)
    return _leading_components(d, scale, TRIAL_COMPONENTS, n_freq)


# the sampler calls the density from several places (blackjax's warm-up and its NUTS kernels);
# as one jitted function of (position, data) it is traced once, not at each (8.5 → 3.4 s of tracing
# and lowering for the remainders of tests/test_models_gap.py; the same draws)
_jitted_log_density = jax.jit(_log_density, static_argnums=(2, 3))


def _compile_time_words() -> str:
    """What the compilation of the sampler costs and what makes the next one fast, for its
    progress line: 30–70 s the first time on a quiet 2-core machine (the Sirin remainders),
    longer under load (156 s at a load of 6–9), then a few seconds from JAX's persistent cache,
    named where it is (``use_compilation_cache``; none set: how to set one)."""
    import os

    folder = jax.config.jax_compilation_cache_dir
    first = "the first time 30–70 s on a quiet 2-core machine, longer on a busy one"
    if not folder:
        return f"{first}, and again in every new process: impedax.use_compilation_cache() keeps it on disk, as the impedax command does"
    home = os.path.expanduser("~")
    shown = "~" + folder[len(home):] if home not in ("", "~", os.sep) and folder.startswith(home + os.sep) else folder
    return f"{first}; then a few seconds: JAX's persistent cache in {shown} keeps it for the next run"


class _Phases:
    """One line on stderr at each change of phase of a hierarchical run, around its progress
    line ``bar`` (steps are passed on to it): the compilation ends at the first step (tracing
    and XLA's compilation take 30–70 s on the Sirin remainders when JAX's persistent cache does
    not have the programs yet), the warm-up (step size and mass-matrix adaptation) at step
    ``warmup``, then the draws."""

    def __init__(self, bar: ProgressLine, warmup: int, draws: int):
        self.bar, self.warmup, self.draws, self.steps = bar, warmup, draws, 0

    def _phase(self, text: str) -> None:
        bar = self.bar
        if bar.enabled:
            if bar.shown and bar.interactive:
                sys.stderr.write("\n")
            announce(text, bar.callback or True)
            bar.shown = False

    def advance(self) -> None:
        now = time.perf_counter() - self.bar.t0
        if self.steps == 0:
            self._phase(f"hierarchical: compiled in {now:.0f} s; warm-up: {self.warmup} NUTS steps adapting the step size and the mass matrix …")
        elif self.steps == self.warmup:
            self._phase(f"hierarchical: warm-up done at {now:.0f} s; drawing {self.draws} draws per chain …")
        self.steps += 1
        self.bar.advance()

    def advance_to(self, steps: int) -> None:
        """Steps done so far, all chains (a block of steps run by one call)."""
        while self.steps < steps:
            self.advance()


_CHAIN_AXIS = "device"

BLOCK_SECONDS = 0.25
"""The sampler runs as calls of a block of NUTS steps each, the progress line advancing between
them (a callback from inside one compiled program would keep JAX's persistent cache from storing
it: every process compiled again, 30–70 s; docs/bayesian.md, "Compilation"). A block grows from one
step, doubling while a call takes less than this [s]: the line moves a few times a second, and
the ~1 ms a call costs stays below 1 % of the run."""

BLOCK_CAPACITY = 256
"""The most steps one call runs: a call's per-step inputs (keys, the warm-up schedule) and its
draws are arrays of this length, so the compiled program does not depend on the numbers of
warm-up steps and draws (a new ``--steps`` compiled the sampler again: ~30 s on the Sirin
remainders)."""


def _chain_devices(chains: int) -> int:
    """How many JAX devices (one per core) share the chains: the most that divide them evenly."""
    return max(d for d in range(1, min(chains, len(jax.devices())) + 1) if chains % d == 0)


class _Sampler(NamedTuple):
    """The compiled program of one hierarchical run over every chain (split evenly over the
    devices, vmapped on each; ``jit_hierarchical_nuts`` in JAX's cache): ``run(phase, state,
    init, warm_keys, run_keys, schedule, out, begin, end, data)`` → (state, out). Phase `START`: the NUTS and adaptation state at the
    initial positions ``init``; `WARM`: warm-up steps begin … end − 1; `DRAW`: draws begin …
    end − 1 into ``out`` (positions, divergent, integration steps, acceptance, step size). One
    program for the three: the log density's gradient and the NUTS kernel compile once (three
    programs of their own took 32 s of XLA against 21.5 s for one, Sirin remainders).
    The per-step arrays hold one block (`BLOCK_CAPACITY` steps): ``warm_keys``, ``run_keys``,
    ``schedule`` and ``out`` at step i are entry i − begin.
    ``state_of(init, data)``: the state's shapes (`jax.eval_shape`); ``over_chains``: the
    placement of per-chain arrays (given so to the first call too, or the second would compile
    again for the new placement)."""

    run: object
    state_of: object
    over_chains: jax.sharding.Sharding


START, WARM, DRAW = 0, 1, 2


def _warmup_engine(target_accept: float):
    """blackjax's window adaptation (``blackjax.window_adaptation``'s defaults: diagonal mass
    matrix, Stan's schedule, initial step size 1) as its (init, step, final) functions, so that
    the warm-up can run in blocks; the same arithmetic as its ``run``."""
    from blackjax.adaptation.metric_recipes import lookup_recipe
    from blackjax.adaptation.staged_adaptation import _make_engine, build_schedule
    from blackjax.adaptation.window_adaptation import _pick_recipe_name

    core = lookup_recipe(_pick_recipe_name(is_mass_matrix_diagonal=True)).build_core(imm_shrinkage_to_previous=0.0, initial_inverse_mass_matrix=None)
    init, step, final = _make_engine(core, target_acceptance_rate=target_accept, n_da_updates=1, metric_telemetry=False)
    return init, step, final, build_schedule


@functools.lru_cache(maxsize=16)
def _compiled_sampler(lay: _Layout, session_scale: float, target_accept: float, n_devices: int) -> _Sampler:
    """The program of `_Sampler`, jitted: it closes over nothing but the layout (static), so
    JAX's persistent cache finds it again in a new process. Same draws as blackjax's
    ``window_adaptation(...).run`` followed by ``nuts(...).step`` in a scan."""
    import blackjax
    from blackjax.mcmc.integrators import velocity_verlet

    adapt_init, adapt_step, adapt_final, _ = _warmup_engine(target_accept)
    kernel = blackjax.nuts.build_kernel(velocity_verlet)

    def start(init, logdensity):
        state = (blackjax.nuts.init(init, logdensity), adapt_init(init, 1.0))
        # weak types made strong (same dtype, same values): a block's output has them strong, and
        # a weak input would compile the program again for the second block
        return jax.tree_util.tree_map(lambda x: jax.lax.convert_element_type(x, jnp.result_type(x)), state)

    def hierarchical_nuts(phase, state, init, warm_keys, run_keys, schedule, out, begin, end, data):
        logdensity = functools.partial(_jitted_log_density, data=data, lay=lay, session_scale=session_scale)

        def warm_step(i, carry):
            chain, adaptation = carry
            chain, info = kernel(warm_keys[i - begin], chain, logdensity, adaptation.step_size, adaptation.inverse_mass_matrix)
            return chain, adapt_step(adaptation, schedule[i - begin], chain.position, chain.logdensity_grad, info.acceptance_rate, i)

        def draw_step(i, carry):
            (chain, adaptation), (positions, divergent, n_steps, accept, _) = carry
            step_size, inverse_mass_matrix = adapt_final(adaptation)
            chain, info = kernel(run_keys[i - begin], chain, logdensity, step_size, inverse_mass_matrix)
            put = lambda buf, x: jax.lax.dynamic_update_index_in_dim(buf, x, i - begin, 0)  # noqa: E731
            return (chain, adaptation), (jax.tree_util.tree_map(put, positions, chain.position), put(divergent, info.is_divergent), put(n_steps, info.num_integration_steps), put(accept, info.acceptance_rate), step_size)

        return jax.lax.switch(phase, [
            lambda: (start(init, logdensity), out),
            lambda: (jax.lax.fori_loop(begin, end, warm_step, state), out),
            lambda: jax.lax.fori_loop(begin, end, draw_step, (state, out)),
        ])

    mesh = jax.sharding.Mesh(np.array(jax.devices()[:n_devices]), (_CHAIN_AXIS,))
    spread, same = jax.sharding.PartitionSpec(_CHAIN_AXIS), jax.sharding.PartitionSpec()
    # per chain: state, init, warm_keys, run_keys, out; shared: phase, schedule, begin, end, data
    mapped = jax.vmap(hierarchical_nuts, in_axes=(None, 0, 0, 0, 0, None, 0, None, None, None))
    specs = (same, spread, spread, spread, spread, same, spread, same, same, same)
    program = jax.jit(jax.shard_map(mapped, mesh=mesh, in_specs=specs, out_specs=spread, check_vma=False))

    def state_of(init, data):
        return jax.vmap(lambda x: start(x, functools.partial(_jitted_log_density, data=data, lay=lay, session_scale=session_scale)))(init)

    return _Sampler(program, state_of, jax.sharding.NamedSharding(mesh, spread))


def _first_metric_step(warmup: int) -> int:
    """The warm-up steps done when the mass matrix is first adapted (the end of the first slow
    window of Stan's schedule, `blackjax`'s ``build_schedule``: 100 of 400 steps, 90 of 100); 0
    when ``warmup`` has no such window. Before it NUTS runs with the identity metric and takes long
    trajectories: the steps the progress line's time left leaves out (`ProgressLine` ``settle``)."""
    from blackjax.adaptation.staged_adaptation import build_schedule

    ends = np.flatnonzero(np.asarray(build_schedule(warmup))[:, 1]) if warmup > 0 else np.array([], int)
    return int(ends[0]) + 1 if ends.size else 0


def _run_blocks(block, total: int, phases: _Phases, offset: int) -> None:
    """Run ``total`` steps as calls ``block(begin, end)`` of growing blocks (`BLOCK_SECONDS`, at
    most `BLOCK_CAPACITY` steps), the progress line advancing to ``offset + end`` after each."""
    begin, size = 0, 1
    while begin < total:
        end = min(begin + size, total)
        t = time.perf_counter()
        jax.block_until_ready(block(begin, end))
        if time.perf_counter() - t < BLOCK_SECONDS:
            size = min(2 * size, BLOCK_CAPACITY)
        phases.advance_to(offset + end)
        begin = end


def _block_of(steps: np.ndarray, begin: int, end: int, axis: int) -> np.ndarray:
    """Entries begin … end − 1 of ``steps`` along ``axis`` (the step axis), zero-padded to
    `BLOCK_CAPACITY` entries."""
    piece = np.zeros(steps.shape[:axis] + (BLOCK_CAPACITY,) + steps.shape[axis + 1:], steps.dtype)
    index = (slice(None),) * axis
    piece[index + (slice(0, end - begin),)] = steps[index + (slice(begin, end),)]
    return piece


def _sample(lay: _Layout, dat: _Data, init_pos, keys, session_scale: float, warmup: int, draws: int, target_accept: float, n_devices: int, phases):
    """(positions, divergent, integration steps, acceptance, step size) of every chain: the
    program of `_compiled_sampler`, compiled (or read from JAX's persistent cache) before the
    first step, run in blocks; each block's keys and schedule go in, and its draws come out, as
    arrays of `BLOCK_CAPACITY` steps, so that every number of steps runs the one program."""
    sampler = _compiled_sampler(lay, session_scale, target_accept, n_devices)
    schedule = np.asarray(_warmup_engine(target_accept)[3](warmup)).reshape(warmup, 2)
    split = jax.vmap(jax.random.split)(keys)  # each chain's (warm-up key, draws key)
    warm_keys = np.asarray(jax.vmap(lambda k: jax.random.split(k, warmup))(split[:, 0]))
    run_keys = np.asarray(jax.vmap(lambda k: jax.random.split(k, draws))(split[:, 1]))
    chains = keys.shape[0]
    block_out = (
        jax.tree_util.tree_map(lambda x: jnp.zeros((chains, BLOCK_CAPACITY) + x.shape[1:], x.dtype), init_pos),
        jnp.zeros((chains, BLOCK_CAPACITY), bool), jnp.zeros((chains, BLOCK_CAPACITY), int), jnp.zeros((chains, BLOCK_CAPACITY)), jnp.zeros(chains),
    )
    # the run's arrays on the host, every draw (the step size, one per chain, as it is)
    out = jax.tree_util.tree_map(lambda x: np.zeros((chains, draws) + x.shape[2:], x.dtype) if x.ndim > 1 else np.zeros(x.shape, x.dtype), block_out)
    state = jax.tree_util.tree_map(lambda s: jnp.zeros(s.shape, s.dtype), jax.eval_shape(sampler.state_of, init_pos, dat))
    no_keys = _block_of(warm_keys[:, :0], 0, 0, 1)
    state, init_pos, no_keys, block_out = jax.device_put((state, init_pos, no_keys, block_out), sampler.over_chains)
    no_schedule = _block_of(schedule[:0], 0, 0, 0)
    carry = list(sampler.run(START, state, init_pos, no_keys, no_keys, no_schedule, block_out, 0, 0, dat))
    jax.block_until_ready(carry)

    def warm(begin, end):
        keys_now = jax.device_put(_block_of(warm_keys, begin, end, 1), sampler.over_chains)
        carry[:] = sampler.run(WARM, carry[0], init_pos, keys_now, no_keys, _block_of(schedule, begin, end, 0), carry[1], begin, end, dat)
        return carry

    def draw(begin, end):
        keys_now = jax.device_put(_block_of(run_keys, begin, end, 1), sampler.over_chains)
        carry[:] = sampler.run(DRAW, carry[0], init_pos, no_keys, keys_now, no_schedule, carry[1], begin, end, dat)
        leaves, got = jax.tree_util.tree_leaves(out), jax.tree_util.tree_leaves(carry[1])
        for kept, block in zip(leaves, got):
            if kept.ndim > 1:
                kept[:, begin:end] = np.asarray(block)[:, : end - begin]
            else:
                kept[...] = np.asarray(block)
        return carry

    _run_blocks(warm, warmup, phases, 0)
    _run_blocks(draw, draws, phases, warmup)
    return out


def _ess(x: np.ndarray) -> np.ndarray:
    """Effective sample size of draws (chains, draws, ...) (Geyer's initial monotone sequence
    on the chain-averaged autocorrelation, Stan's estimator; Vehtari et al. 2021, without ranks)."""
    c, n = x.shape[:2]
    flat = x.reshape(c, n, -1)
    centred = flat - flat.mean(axis=1, keepdims=True)
    spec = np.fft.rfft(centred, n=2 * n, axis=1)
    acov = np.fft.irfft(spec * np.conj(spec), axis=1)[:, :n] / n
    chain_var = acov[:, 0] * n / max(n - 1, 1)
    w = chain_var.mean(axis=0)
    b = n * flat.mean(axis=1).var(axis=0, ddof=1) if c > 1 else np.zeros(flat.shape[2])
    var_plus = (n - 1) / n * w + b / n
    rho = 1.0 - (w - acov.mean(axis=0)) / np.where(var_plus > 0, var_plus, 1.0)
    out = np.empty(flat.shape[2])
    for i in range(flat.shape[2]):
        tau, prev = -1.0, np.inf
        for t in range(0, n - 1, 2):
            pair = rho[t, i] + rho[t + 1, i]
            if pair < 0:
                break
            pair = min(pair, prev)
            prev = pair
            tau += 2.0 * pair
        out[i] = c * n / max(tau, 1.0 / math.log10(max(c * n, 10)))
    return out.reshape(x.shape[2:])


def _bounds_and_unit(name: str, specs, rp: Reparametrization | None) -> tuple[float, float, str]:
    """(lower, upper, unit) of parameter ``name``: the reparametrization's where it is one of its
    own, else the circuit's spec (``specs``: `Circuit.parameter_specs`)."""
    if rp is not None and name in rp.names:
        i = rp.names.index(name)
        return float(rp.lower[i]), float(rp.upper[i]), rp.units[i]
    return float(specs[name].lower), float(specs[name].upper), specs[name].unit


def _rhat(x: np.ndarray) -> np.ndarray:
    """Split-R̂ of draws (chains, draws, ...) (Gelman et al., BDA3 §11.4)."""
    c, n = x.shape[:2]
    half = n // 2
    split = np.concatenate([x[:, :half], x[:, half : 2 * half]], axis=0)
    m, k = split.shape[:2]
    w = split.var(axis=1, ddof=1).mean(axis=0)
    b = k * split.mean(axis=1).var(axis=0, ddof=1)
    return np.sqrt(((k - 1) / k * w + b / k) / np.where(w > 0, w, np.inf))


def mixing_name(key: str) -> str:
    """A key of `HierarchicalPosterior.rhat`/``ess`` as its report and prior-edge warnings word
    it: ``mu[R1]`` → ``R1 (population median)``, ``spread[R1]`` → ``R1 (spread)``, ``delta`` →
    ``discrepancy δ``; a shared parameter's name is its own (the warnings name these, not the keys,
    which the report never shows)."""
    for prefix, words in (("mu[", "population median"), ("spread[", "spread")):
        if key.startswith(prefix) and key.endswith("]"):
            return f"{key[len(prefix):-1]} ({words})"
    return "discrepancy δ" if key == "delta" else key


@dataclass(frozen=True, eq=False)
class HierarchicalPosterior(PiledUp, FrozenResult):
    """Draws of the hierarchical model (module docstring). Natural units (SI) throughout.

    ``mu`` (chains, draws, K): ln of the population median of each per-trial quantity;
    ``spread`` (chains, draws, K): its sd of ln between trials; ``spread_session`` likewise
    between sessions (zeros without a session level); ``trial_values`` (chains, draws, T, K);
    ``shared`` (chains, draws, S); ``delta`` (chains, draws) the discrepancy floor (zeros when off).
    ``mu_prior_centre`` (K,) and ``shared_prior_centre`` (S,): the centres (ln) of the normal
    priors of μ and of the log-sampled shared parameters (None: not recorded, a file written
    by an older version), which the prior-edge check (`piled_up`) needs for those.
    """

    __repr__ = concise_repr  # (the generated one printed every array and Dataset)
    __str__ = report_text  # (print(result): its report)

    circuit: Circuit
    trial_names: tuple[str, ...]
    shared_names: tuple[str, ...]
    mu: np.ndarray
    spread: np.ndarray
    spread_session: np.ndarray
    trial_values: np.ndarray
    shared: np.ndarray
    delta: np.ndarray
    frequency: np.ndarray
    z_data: np.ndarray  # (T, N)
    nu: np.ndarray  # (N,)
    trial_index: xr.DataArray  # the trials' coordinates, stacked
    sessions: int
    discrepancy: bool
    divergences: int
    step_size: np.ndarray
    mean_tree_steps: float
    mean_acceptance: float
    elapsed_s: float
    fixed: Mapping[str, float] = field(default_factory=dict)
    common_sd: np.ndarray | None = None  # (2, N) sd of the Re and Im error shared by every trial [Ω]
    trial_sd: np.ndarray | None = None  # (2, N) sd of the Re and Im smooth error of each trial's own [Ω]
    reparametrization: Reparametrization | None = None
    registry: Registry = field(default=DEFAULT_REGISTRY, repr=False)
    mu_prior_centre: np.ndarray | None = None  # (K,) ln of the median of μ's prior
    shared_prior_centre: np.ndarray | None = None  # (S,) ln φ̂, the centre of a log-sampled shared parameter's prior

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def model(self) -> str:
        return str(self.circuit)

    def _bounds_and_unit(self, name: str) -> tuple[float, float, str]:
        """(lower, upper, unit) of a circuit or reparametrization parameter."""
        return _bounds_and_unit(name, self.circuit.parameter_specs(self.registry), self.reparametrization)

    @functools.cached_property
    def _prior_edges(self) -> PriorEdges:
        """`prior_edges` of the quantities that have a prior of their own (the module
        docstring's): each population median exp(μ_j) against its log-normal prior (median
        exp of ``mu_prior_centre``, S = 2), each shared parameter against its uniform prior
        within its bounds, or its log-normal one about φ̂. A per-trial value's prior is the
        population itself, which moves with the data: not checked. In the warnings a
        population median is "NAME (population median)", in ``piled_up`` it is NAME (the
        per-trial and shared names are distinct)."""
        shown, keys, units, priors, lower, upper, draws = [], [], [], {}, [], [], []

        def add(key: str, label: str, unit: str, prior: Prior, lo: float, hi: float, x: np.ndarray) -> None:
            shown.append(label)
            keys.append(key)
            units.append(unit)
            priors[label] = prior
            lower.append(lo)
            upper.append(hi)
            draws.append(np.asarray(x, float).ravel())

        for j, n in enumerate(self.trial_names):
            if self.mu_prior_centre is not None:
                add(n, f"{n} (population median)", self._bounds_and_unit(n)[2], Prior(PriorKind.LOGNORMAL, math.exp(float(self.mu_prior_centre[j])), MU_PRIOR_SD), 0.0, math.inf, np.exp(self.mu[..., j]))
        for j, n in enumerate(self.shared_names):
            lo, hi, unit = self._bounds_and_unit(n)
            if math.isfinite(hi):  # (sampled through a logit: uniform within the bounds, as `_setup`)
                add(n, n, unit, Prior(PriorKind.UNIFORM, lo, hi), lo, hi, self.shared[..., j])
            elif self.shared_prior_centre is not None:
                add(n, n, unit, Prior(PriorKind.LOGNORMAL, math.exp(float(self.shared_prior_centre[j])), MU_PRIOR_SD), 0.0, math.inf, self.shared[..., j])
        if not shown:
            return PriorEdges([], {})
        edges = prior_edges(shown, units, np.stack(draws, axis=1), priors, lower, upper, reducing_bounds(self.circuit, self.registry))
        return PriorEdges(edges.warnings, {keys[shown.index(label)]: side for label, side in edges.piled_up.items()})

    @property
    def n_draws(self) -> int:
        return int(self.mu.shape[0] * self.mu.shape[1])

    def _index(self, name: str) -> int:
        if name not in self.trial_names:
            close = closest_name(name, self.trial_names) if isinstance(name, str) else None
            hint = f"; did you mean {close}?" if close else ""
            raise ParameterError(f"{name!r} is not a per-trial parameter{hint}; per-trial: {', '.join(self.trial_names)}")
        return self.trial_names.index(name)

    def population(self, name: str, *, level: float = 0.90) -> KeyHintDict:
        """Population median exp(μ) of ``name`` [its unit]: posterior ``value`` (median) and the
        central ``level`` interval (``q05``/``q95`` for 90 %; ``low``/``high`` always), in a new
        dict whose missing key names the keys there are (`MissingKey`; as `spread_between_trials`
        and `new_trial`)."""
        draws = np.exp(self.mu[..., self._index(name)]).ravel()
        return _interval(draws, level)

    def spread_between_trials(self, name: str, *, level: float = 0.90) -> KeyHintDict:
        """Spread of ``name`` between trials: sd of ln θ (≈ relative sd), median and interval."""
        return _interval(self.spread[..., self._index(name)].ravel(), level)

    def new_trial(self, name: str, *, level: float = 0.90, seed: int = 0) -> KeyHintDict:
        """Posterior predictive interval of ``name`` for a new trial (of a new session when
        there is a session level): exp(μ + s η [+ τ ζ]) with fresh η, ζ ~ N(0, 1)."""
        j = self._index(name)
        rng = np.random.default_rng(seed)
        mu, s, tau = (a[..., j].ravel() for a in (self.mu, self.spread, self.spread_session))
        draws = np.exp(mu + s * rng.standard_normal(mu.shape) + tau * rng.standard_normal(mu.shape))
        return _interval(draws, level)

    def population_parameters(self) -> KeyHintDict:
        """Draws of a typical trial's circuit parameters: every per-trial quantity at its
        population median exp(μ), the shared and fixed ones as sampled/fixed; a
        reparametrization's circuit values added (e.g. C_gap from u). Flat (draws,) arrays, in a
        new dict whose missing key names the keys there are (`MissingKey`)."""
        values = KeyHintDict((n, np.exp(self.mu[..., j]).ravel()) for j, n in enumerate(self.trial_names))
        values.update({n: self.shared[..., j].ravel() for j, n in enumerate(self.shared_names)})
        values.update({n: np.full(self.n_draws, v) for n, v in self.fixed.items()})
        rp = self.reparametrization
        if rp is not None:
            values.update({k: np.asarray(v) for k, v in rp.circuit_values({n: jnp.asarray(values[n]) for n in rp.names}).items()})
        return values

    def ess(self) -> KeyHintDict:
        """Effective sample sizes of μ and the spreads (and δ) across chains, keyed ``mu[NAME]``,
        ``spread[NAME]``, ``delta``: a new dict whose missing key names the keys there are
        (`MissingKey`: ``ess()["R1"]`` suggests ``mu[R1]``)."""
        out = KeyHintDict((f"mu[{n}]", float(e)) for n, e in zip(self.trial_names, _ess(self.mu)))
        out.update({f"spread[{n}]": float(e) for n, e in zip(self.trial_names, _ess(np.log(self.spread)))})
        if self.discrepancy:
            out["delta"] = float(_ess(np.log(self.delta)))
        return out

    def rhat(self) -> KeyHintDict:
        """R-hat of μ and the spreads across chains, keyed as `ess` (``mu[NAME]``, ``spread[NAME]``;
        a missing key: `MissingKey`)."""
        out = KeyHintDict((f"mu[{n}]", float(r)) for n, r in zip(self.trial_names, _rhat(self.mu)))
        out.update({f"spread[{n}]": float(r) for n, r in zip(self.trial_names, _rhat(np.log(self.spread)))})
        return out

    def _other_mixing(self) -> tuple[dict[str, float], dict[str, float]]:
        """(R-hat, ESS) of what `rhat` and `ess` leave out: each shared parameter (in the space it
        is sampled in: ln φ, or the logit within its bounds, where R-hat is the same up to the
        monotone map) and R-hat of δ (`mixing` adds them to `rhat` and `ess`, which keep their
        keys)."""
        rhat, ess = {}, {}
        for j, n in enumerate(self.shared_names):
            x = self.shared[..., j]
            lo, hi, _ = self._bounds_and_unit(n)
            y = np.log(np.clip((x - lo) / (hi - x), 1e-300, None)) if math.isfinite(hi) else np.log(np.clip(x, 1e-300, None))
            rhat[n], ess[n] = float(_rhat(y)), float(_ess(y))
        if self.discrepancy:
            rhat["delta"] = float(_rhat(np.log(self.delta)))
        return rhat, ess

    def mixing(self) -> tuple[KeyHintDict, KeyHintDict]:
        """(R-hat, ESS) of every sampled quantity: `rhat` and `ess` (μ and the spreads, keys
        ``mu[NAME]``, ``spread[NAME]``; δ's ESS) with each shared parameter's (key NAME) and δ's
        R-hat (``delta``) added (new dicts; a missing key: `MissingKey`). The warnings, the
        report's sampler line and ``impedax gap``'s SAMPLING UNRELIABLE read these."""
        other_rhat, other_ess = self._other_mixing()
        return KeyHintDict({**self.rhat(), **other_rhat}), KeyHintDict({**self.ess(), **other_ess})

    @property
    def warnings(self) -> tuple[str, ...]:
        """The sampling's health and the prior edges, their remedies in the keywords of
        `sample_hierarchical` (``target_accept=``, ``warmup=``, ``draws=``, ``chains=``); the gap
        analysis puts them in its own words (`models.gap.hierarchical_advice_of_gap`) and
        ``impedax gap`` in its options (Python's text never reads "impedax gap: --steps")."""
        notes = []
        if self.divergences:
            notes.append(f"{self.divergences} divergent NUTS transitions of {self.n_draws} draws: the intervals may be biased; sample with a higher "
                         f"target_accept= (smaller steps: 0.95 or 0.99, the default {TARGET_ACCEPT}) or a longer warmup= (the default {DEFAULT_WARMUP})")
        all_rhat, all_ess = self.mixing()
        chains, per_chain = self.mu.shape[:2]
        more = f"run more draws per chain ({per_chain} now): draws={2 * per_chain}, or more chains ({chains} now): chains={2 * chains}"
        bad = {k: r for k, r in all_rhat.items() if not r < 1.05}
        if bad:
            notes.append(f"R-hat above 1.05 for {', '.join(f'{mixing_name(k)} ({r:.3g})' for k, r in bad.items())}: the chains disagree, so the intervals are not yet the posterior's; {more}")
        low = {k: e for k, e in all_ess.items() if e < 100}
        if low:
            whose = "their medians are uncertain and their 90 % intervals' ends" if len(low) > 1 else "its median is uncertain and its 90 % interval's ends"  # (one quantity: singular)
            notes.append(f"effective sample size below 100 for {', '.join(f'{mixing_name(k)} ({e:.0f})' for k, e in low.items())} of {self.n_draws} draws: "
                         f"{whose} more so; {more}")
        notes.extend(self._prior_edges.warnings)
        return tuple(notes)

    def predict(self, *, noise: bool = True, max_draws: int = 200, seed: int = 0) -> np.ndarray:
        """Posterior predictive impedance [Ω] (draws, trials, frequency) at the data's
        frequencies; with ``noise`` it includes the likelihood's noise σ_tk (ν_k and δ), each
        trial's own smooth error (``trial_sd``) and the error shared by every trial (``common_sd``), so its
        bands are where new measurements fall, not only where the model curve lies."""
        fn = compile_circuit(self.circuit, self.registry)
        c, d = self.mu.shape[:2]
        pick = draw_indices(c * d, max_draws)
        theta = self.trial_values.reshape(c * d, *self.trial_values.shape[2:])[pick]
        shared = self.shared.reshape(c * d, -1)[pick]
        rp = self.reparametrization

        def one(th, sh):
            values = {n: th[j] for j, n in enumerate(self.trial_names)}
            values.update({n: sh[j] for j, n in enumerate(self.shared_names)})
            values.update({n: jnp.asarray(v) for n, v in self.fixed.items()})
            if rp is not None:
                values.update(rp.circuit_values({n: values.pop(n) for n in rp.names}))
            return fn(values, jnp.asarray(self.frequency))

        z = np.asarray(jax.jit(jax.vmap(jax.vmap(one, in_axes=(0, None)), in_axes=(0, 0)))(jnp.asarray(theta), jnp.asarray(shared)))
        if noise:
            rng = np.random.default_rng(seed)
            delta = self.delta.ravel()[pick][:, None, None]
            sigma = np.abs(self.z_data)[None] * np.sqrt(self.nu[None, None] ** 2 + delta**2)
            z = z + sigma * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape))
            if self.trial_sd is not None:  # each trial's own error, drawn per point (its marginal sd)
                z = z + self.trial_sd[0] * rng.standard_normal(z.shape) + 1j * self.trial_sd[1] * rng.standard_normal(z.shape)
            if self.common_sd is not None:  # one shared error per draw, the same in every trial
                shape = (z.shape[0], 1, z.shape[2])
                z = z + self.common_sd[0] * rng.standard_normal(shape) + 1j * self.common_sd[1] * rng.standard_normal(shape)
        return z

    def summary(self) -> dict:
        return {
            "model": self.model,
            "method": "hierarchical NUTS (blackjax)",
            "population": {n: self.population(n) for n in self.trial_names},
            "spread": {n: self.spread_between_trials(n) for n in self.trial_names},
            "new_trial": {n: self.new_trial(n) for n in self.trial_names},
            "shared": {n: _interval(self.shared[..., j].ravel(), 0.90) for j, n in enumerate(self.shared_names)},
            "discrepancy": _interval(self.delta.ravel(), 0.90) if self.discrepancy else None,
            "sessions": self.sessions,
            "trials": int(self.z_data.shape[0]),
            "ess": self.ess(),
            "rhat": self.rhat(),
            "divergences": self.divergences,
            "warnings": list(self.warnings),
            "piled_up": self.piled_up,
            "fixed": {n: float(v) for n, v in self.fixed.items()},
            # (the units of the values above, and the run's size)
            "units": {n: self._bounds_and_unit(n)[2] for n in (*self.trial_names, *self.shared_names)},
            "chains": int(self.mu.shape[0]),
            "draws": int(self.mu.shape[1]),
            "mean_acceptance": float(self.mean_acceptance),
        }

    def to_table(self) -> list[dict[str, object]]:
        """The report's rows as a tidy table (`impedax.write_result` .csv): per
        quantity ``name``, ``level`` (``population`` for a per-trial one,
        ``shared``, or ``discrepancy`` for δ), ``median`` and ``q05``/``q95`` (of the population
        median exp(μ), of a shared value, of δ), ``spread`` (sd of ln between trials),
        ``new_trial_q05``/``new_trial_q95`` (`new_trial`: of a new session too when there is a
        session level), ``unit`` as the element spells it (``Ohm``); empty where it does not apply."""
        empty = {"spread": None, "new_trial_q05": None, "new_trial_q95": None}
        rows = []
        for n in self.trial_names:
            p, t = self.population(n), self.new_trial(n)
            rows.append({"name": n, "level": "population", "median": p["value"], "q05": p["q05"], "q95": p["q95"], "spread": self.spread_between_trials(n)["value"],
                         "new_trial_q05": t["q05"], "new_trial_q95": t["q95"], "unit": self._bounds_and_unit(n)[2]})
        for j, n in enumerate(self.shared_names):
            q = _interval(self.shared[..., j].ravel(), 0.9)
            rows.append({"name": n, "level": "shared", "median": q["value"], "q05": q["q05"], "q95": q["q95"], **empty, "unit": self._bounds_and_unit(n)[2]})
        if self.discrepancy:
            q = _interval(self.delta.ravel(), 0.9)
            rows.append({"name": "delta", "level": "discrepancy", "median": q["value"], "q05": q["q05"], "q95": q["q95"], **empty, "unit": "1"})
        return rows

    def _sampler_line(self) -> str:
        """The sampling's health in one line (the report's second, the notebook's first)."""
        rhat, ess = self.mixing()
        return (f"sampler: {self.divergences} divergent transitions of {self.n_draws} draws, R-hat up to {max(rhat.values()):.3f}, ESS down to {min(ess.values()):.0f}, "
                f"mean acceptance {self.mean_acceptance:.2f}")

    def _repr_html_(self) -> str:
        """The report in a notebook: the sampler's line, a row per quantity (population median
        and its 90 % interval, spread between trials, a new trial's 90 % interval, unit; shared
        ones marked), δ, the warnings."""
        from ...plotting.html import result_html

        rows = []
        for n in self.trial_names:
            p, s, t = self.population(n), self.spread_between_trials(n), self.new_trial(n)
            rows.append({"parameter": n, "population": p["value"], "q05": p["q05"], "q95": p["q95"], "spread (sd of ln)": s["value"],
                         "new trial q05": t["q05"], "new trial q95": t["q95"], "unit": unit_text(self._bounds_and_unit(n)[2])})
        for j, n in enumerate(self.shared_names):
            q = _interval(self.shared[..., j].ravel(), 0.9)
            rows.append({"parameter": n, "population": q["value"], "q05": q["q05"], "q95": q["q95"], "spread (sd of ln)": "shared", "unit": unit_text(self._bounds_and_unit(n)[2])})
        if self.discrepancy:
            q = _interval(self.delta.ravel(), 0.9)
            rows.append({"parameter": "discrepancy δ (relative)", "population": q["value"], "q05": q["q05"], "q95": q["q95"]})
        sessions = f" in {self.sessions} sessions" if self.sessions > 1 else ""
        title = f"{self.model}: hierarchical posterior over {self.z_data.shape[0]} trials{sessions}, NUTS {self.mu.shape[0]} chains × {self.mu.shape[1]} draws"
        words = ["new trial: one in a new session (its spread between sessions drawn too)"] if self.sessions > 1 else []
        return result_html(title, rows, lines=[self._sampler_line(), *words, *self.warnings])

    def plot(self, *, title: str | None = None, figsize: tuple[float, float] | None = None):
        """The population (matplotlib Figure): a panel per per-trial quantity, log axis in its
        unit, each trial's posterior median and 90 % interval, the population median with its
        90 % interval and a new trial's 90 % interval (of a new session, with a session level) as bands; the title names the noise model
        (ν_k from the trials' scatter, δ floor). ``figsize`` (width, height) [in]."""
        from ...plotting.hierarchical import plot_population

        names = self.trial_names
        index = self.trial_index.to_index()
        keys = [key if isinstance(key, tuple) else (key,) for key in index]
        labels = [str(key[0]) if len(key) == 1 else ", ".join(f"{n}={v}" for n, v in zip(index.names, key)) for key in keys]
        draws = self.trial_values.reshape(-1, *self.trial_values.shape[2:])
        noise = "noise ν_k from the trials' scatter" + (" + discrepancy floor δ" if self.discrepancy else "")
        return plot_population(
            names, [self._bounds_and_unit(n)[2] for n in names], draws, {n: self.population(n) for n in names}, {n: self.new_trial(n) for n in names}, labels, xlabel=", ".join(str(n) for n in index.names),
            title=title or f"{self.model}: {self.z_data.shape[0]} trials, NUTS {self.mu.shape[0]} chains × {self.mu.shape[1]} draws\n{noise}", figsize=figsize,
            new_trial_label=self._new_trial_words() + ", 90 %",
        )

    def _new_trial_words(self) -> str:
        """What `new_trial` predicts: with a session level, a new trial of a new session (the
        spread between sessions τ drawn too), not one more trial of the sessions measured."""
        return "new trial in a new session" if self.sessions > 1 else "new trial"

    def report(self) -> str:
        lines = [f"{self.model}: hierarchical model over {self.z_data.shape[0]} trials" + (f" in {self.sessions} sessions" if self.sessions > 1 else "") + f", NUTS {self.mu.shape[0]} chains × {self.mu.shape[1]} draws ({self.elapsed_s:.1f} s)"]
        lines.append(self._sampler_line())
        width = column_width((*self.trial_names, *self.shared_names), 14)
        lines.append(f"{'parameter':<{width}} {'population':>11} {'q05':>11} {'q95':>11} {'spread':>8} {'new trial q05–q95':>25}  unit")
        for n in self.trial_names:
            p, s, t = self.population(n), self.spread_between_trials(n), self.new_trial(n)
            lines.append(f"{n:<{width}} {p['value']:>11.5g} {p['q05']:>11.5g} {p['q95']:>11.5g} {s['value']:>8.3f} {t['q05']:>12.5g}–{t['q95']:<12.5g}  {unit_text(self._bounds_and_unit(n)[2])}".rstrip())
        for j, n in enumerate(self.shared_names):
            q = _interval(self.shared[..., j].ravel(), 0.9)
            lines.append(f"{n:<{width}} {q['value']:>11.5g} {q['q05']:>11.5g} {q['q95']:>11.5g} {'shared':>8} {'':>25}  {unit_text(self._bounds_and_unit(n)[2])}".rstrip())
        if self.discrepancy:
            q = _interval(self.delta.ravel(), 0.9)
            lines.append(f"{'discrepancy δ':<{width}} {q['value']:>11.3g} {q['q05']:>11.3g} {q['q95']:>11.3g}   (relative floor; noise from trial scatter ν median {np.median(self.nu):.3g})")
        lines.append("population: the median over trials (geometric mean), q05–q95 its 90 % interval; spread: sd of ln between trials (≈ relative sd)"
                     + ("; new trial: one in a new session (its spread between sessions drawn too)" if self.sessions > 1 else ""))
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines)

    def _unit_coordinates(self) -> dict[str, tuple]:
        """The units of the per-trial and shared parameters as coordinates: ``unit`` along
        ``param`` (as a fit's and a posterior's Dataset; the unit of ``trial_values`` and of the
        population median exp(``mu``)) and ``shared_unit`` along ``shared_param``: the
        reparametrization's or the element specs' (`_bounds_and_unit`)."""
        def units(names):
            return [self._bounds_and_unit(n)[2] for n in names]

        return {"unit": ("param", units(self.trial_names), {"long_name": PARAMETER_UNIT_NAME}),
                "shared_unit": ("shared_param", units(self.shared_names), {"long_name": PARAMETER_UNIT_NAME})}

    def to_xarray(self) -> xr.Dataset:
        """The draws, the data (``Z`` over trial_index and frequency; the trials' coordinates
        as one coordinate per stacked level), ν, the error sds and the run's settings; the
        parameters' units as ``unit`` (param) and ``shared_unit`` (shared_param);
        `HierarchicalPosterior.from_xarray` rebuilds the posterior from it."""
        k, s = list(self.trial_names), list(self.shared_names)
        index = self.trial_index.to_index()
        levels = [str(n) for n in index.names]
        clash = sorted(set(levels) & {"chain", "draw", "param", "shared_param", "frequency", "part", "trial_index"})
        if clash:
            raise ParameterError(f"cannot store a hierarchical posterior over a dimension named {clash[0]!r}: the draws use that name; rename it in the data")
        ds = xr.Dataset(
            {
                "mu": (("chain", "draw", "param"), self.mu, {"long_name": "ln of the population median"}),
                "spread": (("chain", "draw", "param"), self.spread, {"long_name": "sd of ln between trials"}),
                "spread_session": (("chain", "draw", "param"), self.spread_session, {"long_name": "sd of ln between sessions"}),
                "trial_values": (("chain", "draw", "trial_index", "param"), self.trial_values),
                "shared": (("chain", "draw", "shared_param"), self.shared),
                "delta": (("chain", "draw"), self.delta, {"long_name": "relative discrepancy floor"}),
                "nu": ("frequency", self.nu, {"long_name": "relative noise from trial scatter"}),
                "Z": (("trial_index", "frequency"), self.z_data, {"units": "ohm"}),
                "step_size": ("chain", np.asarray(self.step_size)),
                **({"common_sd": (("part", "frequency"), self.common_sd, {"units": "ohm", "long_name": "sd of the Re and Im error shared by every trial"})} if self.common_sd is not None else {}),
                **({"trial_sd": (("part", "frequency"), self.trial_sd, {"units": "ohm", "long_name": "sd of the Re and Im smooth error of each trial's own"})} if self.trial_sd is not None else {}),
                **({"mu_prior_centre": ("param", np.asarray(self.mu_prior_centre, float), {"long_name": "ln of the median of mu's log-normal prior (sd 2 in ln)"})} if self.mu_prior_centre is not None else {}),
                **({"shared_prior_centre": ("shared_param", np.asarray(self.shared_prior_centre, float), {"long_name": "ln of the median of a log-sampled shared parameter's prior (sd 2 in ln)"})} if self.shared_prior_centre is not None else {}),
            },
            coords={
                "param": k, "shared_param": s, "frequency": ("frequency", self.frequency, {"units": "Hz"}), "part": ["real", "imag"],
                **{name: value for name, value in self._unit_coordinates().items() if name not in levels},  # (a trial level of that name keeps it, as before)
                **{n: ("trial_index", index.get_level_values(n).values) for n in levels},
            },
            attrs={
                "impedax_kind": "hierarchical_posterior", "model": self.model, "sampler": "blackjax NUTS with window adaptation", "sessions": self.sessions,
                "divergences": self.divergences, "discrepancy": int(self.discrepancy), "trial_levels": levels, "fixed": {n: float(v) for n, v in self.fixed.items()},
                "mean_tree_steps": self.mean_tree_steps, "mean_acceptance": self.mean_acceptance, "elapsed_s": self.elapsed_s,
                "reparametrization": self.reparametrization.describe() if self.reparametrization is not None else None,
            },
        )
        return result_dataset(ds.copy(deep=True))

    @classmethod
    def from_xarray(cls, ds: xr.Dataset, *, reparametrization: Reparametrization | None = None, registry: Registry | None = None) -> "HierarchicalPosterior":
        """Rebuild a posterior from `HierarchicalPosterior.to_xarray` output (`impedax.load`,
        `impedax.io.read_netcdf`, or ``xr.open_dataset`` as stored). A custom reparametrization
        must be passed again; a file that is not a complete saved one raises one `DataError`."""
        import pandas as pd  # (xarray's own dependency)

        from ...io.netcdf import damaged_result, saved_result  # (io is imported only here: rarely needed)
        from .reparam import rebuild

        registry = DEFAULT_REGISTRY if registry is None else registry

        ds = saved_result(
            ds, "hierarchical_posterior", variables=("mu", "spread", "spread_session", "trial_values", "shared", "delta", "nu", "Z", "step_size", "param", "shared_param", "frequency"),
            attrs=("model", "sessions", "divergences", "discrepancy", "trial_levels", "fixed", "mean_tree_steps", "mean_acceptance", "elapsed_s", "reparametrization"),
        )
        with damaged_result("hierarchical_posterior", ds):
            levels = [str(n) for n in ds.attrs["trial_levels"]]
            index = pd.MultiIndex.from_arrays([ds[n].values for n in levels], names=levels)
            stacked = xr.Dataset(coords=xr.Coordinates.from_pandas_multiindex(index, "trial_index"))
            rp = reparametrization
            if rp is None and ds.attrs["reparametrization"]:
                rp = rebuild(ds.attrs["reparametrization"])

            def values(name, *dims):
                return np.asarray(ds[name].transpose(*dims).values)

            return cls(
                circuit=parse(ds.attrs["model"], registry), trial_names=tuple(str(n) for n in ds["param"].values), shared_names=tuple(str(n) for n in ds["shared_param"].values),
                mu=values("mu", "chain", "draw", "param"), spread=values("spread", "chain", "draw", "param"), spread_session=values("spread_session", "chain", "draw", "param"),
                trial_values=values("trial_values", "chain", "draw", "trial_index", "param"), shared=values("shared", "chain", "draw", "shared_param"),
                delta=values("delta", "chain", "draw"), frequency=values("frequency", "frequency"), z_data=np.asarray(ds["Z"].transpose("trial_index", "frequency").values, complex),
                nu=values("nu", "frequency"), trial_index=stacked["trial_index"], sessions=int(ds.attrs["sessions"]), discrepancy=bool(ds.attrs["discrepancy"]),
                divergences=int(ds.attrs["divergences"]), step_size=values("step_size", "chain"), mean_tree_steps=float(ds.attrs["mean_tree_steps"]),
                mean_acceptance=float(ds.attrs["mean_acceptance"]), elapsed_s=float(ds.attrs["elapsed_s"]), fixed={str(n): float(v) for n, v in ds.attrs["fixed"].items()},
                common_sd=values("common_sd", "part", "frequency") if "common_sd" in ds else None, trial_sd=values("trial_sd", "part", "frequency") if "trial_sd" in ds else None,
                reparametrization=rp, registry=registry,
                mu_prior_centre=values("mu_prior_centre", "param") if "mu_prior_centre" in ds else None,
                shared_prior_centre=values("shared_prior_centre", "shared_param") if "shared_prior_centre" in ds else None,
            )


def _interval(draws: np.ndarray, level: float) -> KeyHintDict:
    lo, hi = (1.0 - level) / 2.0, 1.0 - (1.0 - level) / 2.0
    q_lo, q50, q_hi = np.quantile(draws, [lo, 0.5, hi])
    out = KeyHintDict(value=float(q50), low=float(q_lo), high=float(q_hi))
    if abs(level - 0.9) < 1e-12:
        out.update(q05=float(q_lo), q95=float(q_hi))
    return out


def _check_batch_init(init, circuit, order, freq, z) -> None:
    """``init`` a batch of fits of ``circuit`` to these trials (``z`` (T, N) stacked along
    ``order``): its per-trial fits give the start, the prior centres and the noise ν_k, so a
    batch of other spectra (or of the same frequencies, other impedances) is refused."""
    from ..least_squares.result import data_difference

    ds = getattr(init, "dataset", None)
    if not callable(getattr(init, "fit_of", None)) or not isinstance(ds, xr.Dataset) or "Z" not in ds:
        raise ParameterError(f"init must be a BatchFitResult of fit({circuit}, data) over the trials, got {type(init).__name__}")
    if str(init.model) != str(circuit) or sorted(init.dims) != sorted(order):
        raise ParameterError(f"init was fitted with {init.model} over {' × '.join(init.dims)}; hierarchical sampling was given {circuit} over {' × '.join(order)}")
    fit_freq = np.asarray(ds["frequency"].values, float)
    z_fit = np.asarray(ds["Z"].transpose(*order, "frequency").values).reshape(-1, fit_freq.size)
    if z_fit.shape != z.shape:
        raise ParameterError(f"init was fitted to {z_fit.shape[0]} spectra of {fit_freq.size} points; the data have {z.shape[0]} of {freq.size}: pass init=fit(circuit, data) of the trials sampled")
    for trial in range(z.shape[0]):
        difference = data_difference(freq, z[trial], fit_freq, z_fit[trial])
        if difference is not None:
            raise ParameterError(f"init was fitted to different data: trial {trial} ({', '.join(order)} stacked): {difference}; pass init=fit(circuit, data) of the trials sampled")


def _setup(circuit, data, *, per_trial, session_dim, reparametrization, fixed, discrepancy, session_spread_scale, chains, parameterisation, seed, registry, init, progress=None):
    """Checks, per-trial least-squares fits, noise ν_k, priors and the chains' starts."""
    from ..least_squares import fit

    if parameterisation not in ("auto", "centred", "non-centred"):
        raise ParameterError(f"parameterisation must be 'auto', 'centred' or 'non-centred', got {parameterisation!r}")
    circuit = parse(circuit, registry) if isinstance(circuit, str) else circuit
    if "Z" not in data or "frequency" not in data["Z"].dims:
        raise DataError("hierarchical sampling needs a spectrum Dataset with complex 'Z' over 'frequency'")
    rep_dims = [d for d in data["Z"].dims if d != "frequency"]
    if not rep_dims:
        raise DataError("hierarchical sampling needs replicate spectra: Z has no dimension besides 'frequency'")
    if session_dim is not None and session_dim not in rep_dims:
        raise DataError(f"session_dim {session_dim!r} is not a dimension of Z ({', '.join(data['Z'].dims)})")
    fixed = dict(fixed or {})
    specs = circuit.parameter_specs(registry)
    rp = reparametrization
    replaced = set(rp.replaces) if rp is not None else set()
    free = [n for n in circuit.parameter_names(registry) if n not in fixed and n not in replaced]
    known = free + (list(rp.names) if rp is not None else [])
    if isinstance(per_trial, str):  # ('R1' was read letter by letter: "per-trial parameter 'R'")
        raise ParameterError(f"per_trial must be a list of parameter names, e.g. per_trial=({per_trial!r},); got the string {per_trial!r}")
    if not per_trial:
        raise ParameterError(f"per_trial is empty: name at least one parameter drawn per trial, of {', '.join(known)}")
    repeated = sorted({n for n in per_trial if list(per_trial).count(n) > 1})
    if repeated:
        raise ParameterError(f"per_trial names {', '.join(repeated)} more than once")
    for name in per_trial:
        if name not in known:
            raise ParameterError(f"per-trial parameter {name!r} is not a free parameter of {circuit}; free: {', '.join(known)}")
    for name in fixed:
        if name not in specs:
            raise ParameterError(f"fixed parameter {name!r} is not a parameter of {circuit}")
    shared_names = tuple(n for n in known if n not in per_trial)

    order = ([session_dim] if session_dim else []) + [d for d in rep_dims if d != session_dim]
    z_da = data["Z"].transpose(*order, "frequency")
    stacked = z_da.stack(trial_index=order)
    z = np.asarray(stacked.transpose("trial_index", "frequency").values)
    freq = np.asarray(data["frequency"].values, dtype=np.float64)
    n_trials = z.shape[0]
    if n_trials < 3:
        raise DataError(f"a population needs at least 3 trials, got {n_trials}")
    if session_dim:
        session_codes = np.repeat(np.arange(data.sizes[session_dim]), n_trials // data.sizes[session_dim])
        n_sessions = int(data.sizes[session_dim])
    else:
        session_codes, n_sessions = np.zeros(n_trials, dtype=int), 1

    if init is None:
        # each trial's fit starts from the fit of the trials' mean: single noisy trials fitted
        # from the data-driven guess alone can land far off (R_EP → 1e47 Ω, α → 0.12 on Sirin seed 12)
        mean = make_spectrum(data["frequency"].values, data["Z"].mean(rep_dims).values, source="trial mean")
        announce(f"hierarchical: fitting the {n_trials} trials by least squares (the start, the priors' centres and the noise) …", progress)
        init = fit(circuit, data, init=fit(circuit, mean, fixed=fixed or None, weighting="modulus", registry=registry), fixed=fixed or None, weighting="modulus", registry=registry)
    else:
        _check_batch_init(init, circuit, order, freq, z)
    batch = init
    vals = batch.dataset["value"].transpose("param", *order).values.reshape(len(batch.dataset["param"]), n_trials)
    pnames = [str(p) for p in batch.dataset["param"].values]
    per_fit = {n: vals[pnames.index(n)] for n in pnames}
    z_fit = batch.dataset["Z_model"].transpose(*order, "frequency").values.reshape(n_trials, -1)
    if rp is not None:
        inv = rp.inverse if rp.inverse is not None else None
        if inv is None:
            raise ParameterError("hierarchical sampling with a reparametrization needs its inverse (to start the chains)")
        per_fit.update({k: np.asarray(v, float) for k, v in inv({n: per_fit[n] for n in rp.replaces}, rp.constant_values).items()})
    nu = trial_scatter_noise(z, z_fit)
    common_basis, common_var = _shared_error_components(data, z, nu, freq.size)
    trial_basis, trial_var = _trial_error_components(data, z, nu, freq.size)

    theta0 = np.stack([np.asarray(per_fit[n], float) for n in per_trial], axis=1)  # (T, K)
    errs = batch.dataset["linearised_stderr" if "linearised_stderr" in batch.dataset else "stderr"].transpose("param", *order).values.reshape(len(pnames), n_trials)
    # relative standard error of each per-trial quantity (a reparametrized one: of what it replaces, 1 : 1 maps)
    source = {n: (rp.replaces[rp.names.index(n)] if rp is not None and n in rp.names else n) for n in per_trial}
    rel_stderr = np.stack([np.abs(errs[pnames.index(source[n])] / vals[pnames.index(source[n])]) for n in per_trial], axis=1)
    rel_stderr = np.where(np.isfinite(rel_stderr), rel_stderr, np.inf)
    if not np.all(theta0 > 0):
        raise FitError(f"the per-trial least-squares fits gave non-positive values of {', '.join(per_trial)}; a log-normal population needs positive values")
    log0 = np.log(theta0)
    mu0 = np.median(log0, axis=0)
    # robust: single-trial fits of a weakly identified model can land in another mode (e.g. a CPE
    # with α → 1 taking C_gap's place); the median and the MAD ignore those trials, and the
    # chains start with every trial within 2 spreads of the median
    spread0 = np.clip(1.4826 * np.median(np.abs(log0 - mu0), axis=0), 1e-3, 1.0)
    offset0 = np.clip(log0 - mu0, -2.0 * spread0, 2.0 * spread0)
    bounded, lo, hi, centre, sh0 = [], [], [], [], []
    for n in shared_names:
        b_lo, b_hi, _ = _bounds_and_unit(n, specs, rp)
        value = float(np.median(per_fit[n]))
        is_bounded = math.isfinite(b_hi)
        bounded.append(is_bounded)
        lo.append(b_lo if is_bounded else 0.0)
        hi.append(b_hi if is_bounded else 1.0)
        centre.append(math.log(value) if value > 0 else 0.0)
        if is_bounded:
            frac = min(max((value - b_lo) / (b_hi - b_lo), 1e-4), 1 - 1e-4)
            sh0.append(math.log(frac / (1 - frac)))
        else:
            sh0.append(math.log(value))

    if parameterisation == "auto":
        # per quantity: centred when each trial pins its own value well (relative standard error
        # of the per-trial fits below 1/CENTRED_RATIO of their spread), non-centred otherwise
        # (Betancourt & Girolami 2015: a centred funnel appears when the data say little about
        # each trial compared with the spread). The fits' spread holds their own noise too
        # (spread0² ≈ s² + stderr²): a quantity the same in every trial (s = 0) has spread0 ≈
        # stderr and would pass a plain "stderr < spread0" half the time — then its s runs into
        # the funnel's neck (user data, R_EP and CPE_EP.Q equal in all trials: 686 divergent
        # transitions of 2000, R-hat 1.3; docs/bayesian.md "Parameterisation")
        use_centred = tuple(bool(c) for c in np.median(rel_stderr, axis=0) * CENTRED_RATIO < spread0)
    else:
        use_centred = (parameterisation == "centred",) * len(per_trial)
    cen_cols, non_cols = [j for j, c in enumerate(use_centred) if c], [j for j, c in enumerate(use_centred) if not c]
    lay = _Layout(circuit, registry, tuple(per_trial), shared_names, tuple(bounded), tuple(fixed), rp, n_sessions, bool(discrepancy), use_centred, common_basis.shape[0], trial_basis.shape[0])
    dat = _Data(
        jnp.asarray(freq), jnp.asarray(z), jnp.asarray(nu), jnp.asarray(session_codes, dtype=jnp.int32), jnp.asarray(mu0),
        jnp.asarray(centre, dtype=jnp.float64), jnp.asarray(lo, dtype=jnp.float64), jnp.asarray(hi, dtype=jnp.float64), jnp.asarray([fixed[n] for n in fixed], dtype=jnp.float64),
        jnp.asarray(common_basis), jnp.asarray(common_var), jnp.asarray(trial_basis), jnp.asarray(trial_var),
    )
    rng = np.random.default_rng(seed)
    k = len(per_trial)

    def start():
        pos = {
            "mu": mu0 + 0.01 * rng.standard_normal(k),
            "log_spread": np.log(spread0) + 0.05 * rng.standard_normal(k),
            "shared": np.asarray(sh0) + 0.01 * rng.standard_normal(len(sh0)),
        }
        if cen_cols:
            pos["log_theta"] = (mu0 + offset0 + 0.002 * rng.standard_normal(log0.shape))[:, cen_cols]
        if non_cols:
            pos["eta"] = (offset0 / spread0 + 0.05 * rng.standard_normal(log0.shape))[:, non_cols]
        if n_sessions > 1:
            pos["log_spread_session"] = np.log(np.full(k, 0.5 * session_spread_scale))
            pos["zeta"] = 0.1 * rng.standard_normal((n_sessions, k))
        if discrepancy:
            pos["log_delta"] = np.log(0.01) + 0.1 * rng.standard_normal()
        return pos

    inits = [start() for _ in range(chains)]
    init_pos = {key: jnp.asarray(np.stack([p[key] for p in inits])) for key in inits[0]}
    return lay, dat, init_pos, stacked["trial_index"]


def _total_sd(basis, rest) -> np.ndarray:
    """sd (2, N) of the Re and Im parts of an error given as leading components ``basis`` (M, N)
    complex and the ``rest``'s variance (2, N)."""
    b = np.asarray(basis)
    return np.sqrt(np.stack([(b.real**2).sum(axis=0), (b.imag**2).sum(axis=0)]) + np.asarray(rest))


def _acceptance_rate(value, name):
    """NUTS's target acceptance rate: a number strictly between 0 and 1."""
    value = real()(value, name)
    if not 0.0 < value < 1.0:
        raise ParameterError(f"{name} is NUTS's target acceptance rate, strictly between 0 and 1 (default {TARGET_ACCEPT}; 0.95 for fewer divergent transitions), got {value:g}")
    return value


@quiet_beneath  # (its start fits say nothing of their own: with progress=False they wrote "[0.0 s] fitting …" to stderr)
@checked_arguments(
    per_trial=sequence_of(str, what="parameter name, e.g. per_trial=('R1',)"), chains=count(1, 1024), warmup=count(1, MAX_SAMPLER_STEPS), draws=count(1, MAX_SAMPLER_STEPS),
    target_accept=_acceptance_rate, session_spread_scale=real(positive=True), seed=seed_rule, progress=progress_line_flag,
)
def sample_hierarchical(
    circuit: Circuit | str,
    data: xr.Dataset,
    *,
    per_trial: Sequence[str],
    session_dim: str | None = None,
    reparametrization: Reparametrization | None = None,
    fixed: Mapping[str, float] | None = None,
    discrepancy: bool = True,
    session_spread_scale: float = 0.1,
    chains: int = 4,
    warmup: int = DEFAULT_WARMUP,
    draws: int = 400,
    target_accept: float = TARGET_ACCEPT,
    parameterisation: str = "auto",
    seed: int = 0,
    registry: Registry = DEFAULT_REGISTRY,
    init=None,
    progress=None,
) -> HierarchicalPosterior:
    """Sample the hierarchical model (module docstring) of the spectra in ``data``.

    ``data``: a spectrum Dataset with complex ``Z`` over (..., ``frequency``); every other dim
    is a replicate (trials); an optional complex ``common_error_modes`` (mode, frequency) is an
    error shared by every trial, ε = Σ_j ξ_j d_j with ξ ~ N(0, 1), and an optional complex
    ``trial_error_modes`` (mode, frequency) each trial's own smooth error, e_t = Σ_j ζ_tj m_j
    with ζ_tj ~ N(0, 1) independent between trials; both are marginalised in the likelihood
    (`impedax.models.sirin.trial_remainders` writes them). ``per_trial`` names the quantities drawn per trial from a
    log-normal population (circuit parameter names, or names of ``reparametrization``, e.g.
    ``u``); every other free parameter is shared by all trials. ``session_dim`` adds a session
    level (trials nested in the sessions along that dim). ``discrepancy`` samples the relative
    floor δ (otherwise δ = 0). ``parameterisation``: ``"centred"`` samples each trial's ln θ,
    ``"non-centred"`` its standardised offset η; ``"auto"`` picks centred when the per-trial
    least-squares fits determine each trial better than the trials differ. ``init``: a `BatchFitResult` of the circuit on ``data`` (else
    one is run, each trial started from the fit of the trials' mean) — the per-trial fits give
    the start, the prior centres and the noise ν_k. ``progress``: a line at each phase (compiling,
    warm-up, draws) and a progress line once the run has taken a second, on stderr when None
    (the default) or True, none when False, handed one line of text at a time to a function
    (``progress=print``), as `fit` and `sample` take it.
    Returns a `HierarchicalPosterior`.
    """
    progress = progress_line_flag(progress, "progress")  # (the default None is not checked by the decorator: lines on stderr)
    t0 = time.perf_counter()
    lay, dat, init_pos, trial_index = _setup(
        circuit, data, per_trial=per_trial, session_dim=session_dim, reparametrization=reparametrization, fixed=fixed, discrepancy=discrepancy,
        session_spread_scale=session_spread_scale, chains=chains, parameterisation=parameterisation, seed=seed, registry=registry, init=init, progress=progress,
    )
    keys = jax.random.split(jax.random.PRNGKey(seed), chains)
    announce(f"hierarchical: tracing and compiling the sampler ({chains} chains; {_compile_time_words()}) …", progress)
    bar = ProgressLine(int(warmup) + int(draws), progress, label=f"impedax hierarchical ({chains} chains, warm-up {warmup} + draws {draws})", settle=_first_metric_step(int(warmup)))
    phases = _Phases(bar, int(warmup), int(draws))
    try:
        positions, divergent, n_steps, accept, step_size = _sample(lay, dat, init_pos, keys, float(session_spread_scale), int(warmup), int(draws), float(target_accept), _chain_devices(int(chains)), phases)
    finally:
        bar.close()
    positions = jax.tree_util.tree_map(np.asarray, positions)

    theta = np.asarray(jax.vmap(jax.vmap(lambda p: _trial_values(p, dat, lay)))(positions))
    shared = np.asarray(jax.vmap(jax.vmap(lambda p: _shared_values(p, dat, lay)))(positions))
    n_sessions = lay.n_sessions
    if n_sessions > 1:
        spread_session = np.exp(positions["log_spread_session"])
    else:
        spread_session = np.zeros_like(positions["mu"])
    delta = np.exp(positions["log_delta"]) if discrepancy else np.zeros(positions["mu"].shape[:2])
    return HierarchicalPosterior(
        circuit=lay.circuit, trial_names=lay.trial_names, shared_names=lay.shared_names, mu=positions["mu"], spread=np.exp(positions["log_spread"]),
        spread_session=spread_session, trial_values=theta, shared=shared, delta=delta, frequency=np.asarray(dat.freq), z_data=np.asarray(dat.z), nu=np.asarray(dat.nu),
        trial_index=trial_index, sessions=n_sessions, discrepancy=bool(discrepancy), divergences=int(np.sum(divergent)),
        step_size=np.asarray(step_size), mean_tree_steps=float(np.mean(n_steps)), mean_acceptance=float(np.mean(accept)),
        elapsed_s=time.perf_counter() - t0, fixed=dict(zip(lay.fixed_names, np.asarray(dat.fixed).tolist())), common_sd=_total_sd(dat.common_basis, dat.common_var) if lay.n_common else None,
        trial_sd=_total_sd(dat.trial_basis, dat.trial_var) if lay.n_trial_modes else None, reparametrization=lay.reparametrization, registry=registry,
        mu_prior_centre=np.asarray(dat.mu_center), shared_prior_centre=np.asarray(dat.shared_center),
    )


def hierarchical_log_density(circuit: Circuit | str, data: xr.Dataset, *, per_trial: Sequence[str], seed: int = 0, **options):
    """The model's log posterior density and a starting position, for other samplers (e.g. the
    emcee comparison in benchmarks/bench_coverage.py): returns ``(log_density(position),
    position)``, a position being a dict of arrays (one chain). ``options`` as for
    `sample_hierarchical` (``session_dim``, ``reparametrization``, ``fixed``, ``discrepancy``,
    ``session_spread_scale``, ``parameterisation``, ``registry``, ``init``)."""
    opts = dict(session_dim=None, reparametrization=None, fixed=None, discrepancy=True, session_spread_scale=0.1, parameterisation="auto", registry=DEFAULT_REGISTRY, init=None)
    refuse_unknown_keywords("hierarchical_log_density()", options, list(opts))
    opts.update(options)
    circuit = parse(circuit, opts["registry"]) if isinstance(circuit, str) else circuit
    lay, dat, init_pos, _ = _setup(circuit, data, per_trial=per_trial, chains=1, seed=seed, **opts)
    density = functools.partial(_log_density, data=dat, lay=lay, session_scale=float(opts["session_spread_scale"]))
    return density, {k: v[0] for k, v in init_pos.items()}
