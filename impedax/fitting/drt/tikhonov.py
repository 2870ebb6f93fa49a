"""Tikhonov-regularised least squares for the DRT, in JAX, batched over spectra by `jax.lax.map`.

For one spectrum with weights w_n = 1/|Z_n| (relative residuals, docs/physics.md, "Goodness of fit"), the real design
A (2N × P: Re rows over Im rows, columns R_∞, L, 1/C, x_1..x_M) and data b:

    x̂(λ) = argmin ‖A x − b‖² + λ xᵀ Γ x     (subject to x_m ≥ 0 for the RBF weights when
                                               non-negative; R_∞ and L are free, 1/C ≥ 0)

Γ is the roughness penalty of `basis.penalty_matrix` on the RBF block plus η = 1e-10 on the
diagonal, so that Γ = RᵀR is positive definite (η is far below anything that moves R_∞ or L).

Choosing λ (Hansen, "Rank-deficient and discrete ill-posed problems", SIAM 1998, ch. 7): with the
SVD Ã = A R⁻¹ = U S Vᵀ and β = Uᵀb, for every λ on a log grid

    f_i = s_i²/(s_i² + λ),  ‖r‖² = ‖b‖² − ‖β‖² + Σ (1 − f_i)² β_i²,  ‖Rx‖² = Σ (s_i β_i/(s_i² + λ))²,
    GCV(λ) = 2N ‖r‖² / (2N − ρ Σ f_i)²   modified GCV (Golub, Heath, Wahba 1979; Cummins,
                                          Filloon, Nychka 2001), ρ = 1.3 for 2N < 100, else 2,
    L-curve: λ at the largest curvature of (log ‖r‖², log ‖Rx‖²)     (Hansen & O'Leary 1993),
             among the λ whose log ‖r‖² lies in the lower half of its range.

Both use the unconstrained solution, as pyDRTtools does; the minimum is refined by a parabola in
log λ. GCV is the default: it estimates the predictive error directly and has one minimum on
these spectra that tracks the noise level (λ grows about tenfold per threefold noise in
tests/test_drt.py); plain GCV (ρ = 1) is known to undersmooth now and then, which under
γ ≥ 0 splits a broad peak into several, hence ρ > 1. The L-curve corner is offered too; it
needs no noise model but its corner is shallow on short spectra and it oversmooths at 3 %
noise (peaks widen by half a decade).

The non-negative problem at the chosen λ is a bound-constrained QP, solved exactly by the
primal–dual active-set method (Hintermüller, Ito, Kunisch, SIAM J. Optim. 13 (2003) 865): each
iteration is one Cholesky solve on the free set and it usually stops after a few; when its
active set cycles (ill-conditioned H at small λ), Lawson–Hanson's NNLS takes over from its
point, which converges finitely (capped at ``max_iter`` added coefficients and reported).

Credible band (docs/drt.md, "Credible band and calibration"): the Bayesian reading of the same
problem, b ~ N(Ax, σ²I) with the smoothness prior x_γ ~ N(0, (σ²/λ) Γ⁻¹) on the RBF weights
(MacKay, "Bayesian interpolation", Neural Comput. 4 (1992) 415) and a flat prior on the n_s
series terms, with λ chosen by the evidence

    ln p(b | λ) = ½ Σ_i ln(λ/(s_i² + λ)) − (n_s/2) ln λ − ((2N − n_s)/2) ln(‖r_λ‖² + λ‖R x_λ‖²) + const

(σ² integrated out under a Jeffreys prior; the flat prior on the series terms is what Wahba's
GML/REML criterion gives the penalty's null space: the −(n_s/2) ln λ removes the ½ ln λ each
series column's s_i² ≈ ‖a_i‖²/η ≫ λ brings into the sum, which would otherwise treat η, a device
to factor Γ, as a λ-scaled prior and push λ up; tests/test_drt_evidence_lambda.py checks the
optimum against the Gaussian marginal likelihood written out), maximised on the same grid and refined by a
parabola. At λ_ev the posterior is Gaussian, x ~ N(H⁻¹Aᵀb, σ̂² H⁻¹) with H = AᵀA + λ_ev Γ and
σ̂² = (‖r‖² + λ_ev‖Rx‖²)/(2N − n_s); γ = Φx, and its 5 %/95 % quantiles are clipped at 0 when γ ≥ 0.
GCV's λ (above) oversmooths on purpose, so that γ ≥ 0 does not split broad peaks; the band
at that λ is dominated by the smoothing bias and covered the true γ at only 40–75 % of τ.
The evidence λ is smaller (less bias, more variance); its band covers 88 % on average
(80–100 % per case and noise level) on the calibration set of docs/drt.md. On a spectrum that
is not a DRT + R_∞ + L within its noise, σ̂ takes the misfit for noise and λ_ev grows large
(REAL Parstat: 12, σ̂ 17 % against 0.56 % first-difference noise; docs/drt.md).
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import jax.scipy.linalg as jsl
import numpy as np

__all__ = ["solve_batch", "LAMBDA_METHODS"]

LAMBDA_METHODS = ("gcv", "lcurve")
_Z90 = 1.6448536269514722  # Φ⁻¹(0.95)


def _criteria(s, beta, rss0, log_lam, n_rows):
    lam = jnp.exp(log_lam)[:, None]
    s2 = (s * s)[None, :]
    f = s2 / (s2 + lam)
    rss = rss0 + jnp.sum(((1.0 - f) * beta[None, :]) ** 2, axis=1)
    rss = jnp.maximum(rss, 1e-300)
    trace = jnp.sum(f, axis=1)
    penalty = jnp.maximum(jnp.sum((s[None, :] * beta[None, :] / (s2 + lam)) ** 2, axis=1), 1e-300)
    rho = 1.3 if n_rows < 100 else 2.0  # modified GCV (see the module docstring)
    gcv = n_rows * rss / jnp.maximum(n_rows - rho * trace, 1e-6) ** 2
    return gcv, rss, penalty


def _log_evidence(s, rss, penalty, log_lam, n_rows, n_series):
    """ln p(b | λ) over the grid, up to a constant (module docstring): the first sum runs over
    every column, the series ones included (their s_i² ≈ ‖a_i‖²/η ≫ λ, so each adds ½ ln λ
    whatever η is), and −(n_series/2) ln λ takes those terms back out."""
    lam = jnp.exp(log_lam)[:, None]
    s2 = (s * s)[None, :]
    occam = 0.5 * jnp.sum(jnp.log(lam / (s2 + lam)), axis=1) - 0.5 * n_series * log_lam
    return occam - 0.5 * (n_rows - n_series) * jnp.log(rss + lam[:, 0] * penalty)


def _parabola_min(log_lam, values, k):
    """Vertex of the parabola through grid points k−1, k, k+1 (k clipped inside the grid)."""
    k = jnp.clip(k, 1, log_lam.size - 2)
    x0, x1 = log_lam[k - 1], log_lam[k]
    y0, y1, y2 = values[k - 1], values[k], values[k + 1]
    denom = y0 - 2 * y1 + y2
    h = x1 - x0
    # a neighbour at ±inf (the L-curve's curvature is −inf at the grid's ends and outside the
    # lower half of the residual range) leaves no parabola: the grid point itself, not NaN
    usable = jnp.isfinite(y0) & jnp.isfinite(y1) & jnp.isfinite(y2) & (jnp.abs(denom) > 1e-300)
    shift = jnp.where(usable, 0.5 * h * (y0 - y2) / jnp.where(usable, denom, 1.0), 0.0)
    return x1 + jnp.clip(shift, -h, h)


def _choose_log_lambda(s, beta, rss0, log_grid, n_rows, method):
    """(ln λ of the criterion's optimum, refined by a parabola; the grid index of the optimum)."""
    gcv, rss, penalty = _criteria(s, beta, rss0, log_grid, n_rows)
    if method == "gcv":
        values = jnp.log(gcv)
        k = jnp.argmin(values)
        return _parabola_min(log_grid, values, k), k
    xi, eta = jnp.log(rss), jnp.log(penalty)
    d_xi, d_eta = jnp.gradient(xi, log_grid), jnp.gradient(eta, log_grid)
    dd_xi, dd_eta = jnp.gradient(d_xi, log_grid), jnp.gradient(d_eta, log_grid)
    kappa = (d_xi * dd_eta - dd_xi * d_eta) / jnp.maximum(d_xi**2 + d_eta**2, 1e-300) ** 1.5
    # only the lower half of the residual range: at very large λ the curve bends again where the
    # series terms alone are left (a second, spurious "corner")
    kappa = jnp.where(xi <= 0.5 * (jnp.min(xi) + jnp.max(xi)), kappa, -jnp.inf)
    kappa = kappa.at[0].set(-jnp.inf).at[-1].set(-jnp.inf)
    # exact or nearly exact data (noise ≤ 1e-4): ‖r‖² reaches its floor and the curvature is NaN
    # or −inf over much of the grid; the corner is then the grid's best finite point, and with
    # no finite point at all the bottom of the grid (raised to the floor by the caller)
    kappa = jnp.where(jnp.isfinite(kappa), kappa, -jnp.inf)
    k = jnp.where(jnp.any(jnp.isfinite(kappa)), jnp.argmax(kappa), 0)
    return _parabola_min(log_grid, -kappa, k), k


def _masked_cholesky(H, free):
    both = free[:, None] & free[None, :]
    Hm = jnp.where(both, H, 0.0) + jnp.diag(jnp.where(free, 0.0, 1.0))
    return jsl.cho_factor(Hm, lower=True)


def _solve_on(H, c, passive):
    x = jsl.cho_solve(_masked_cholesky(H, passive), jnp.where(passive, c, 0.0))
    return jnp.where(passive, x, 0.0)


def _pdas(H, c, constrained, max_iter):
    """min ½xᵀHx − cᵀx subject to x_i ≥ 0 where ``constrained``: primal–dual active set
    (Hintermüller et al. 2003). Returns (x, free set, converged)."""

    def body(state):
        active, _, it, _ = state
        x = _solve_on(H, c, ~active)
        grad = H @ x - c
        new_active = constrained & ((active & (grad > 0)) | (~active & (x < 0)))
        return new_active, x, it + 1, jnp.all(new_active == active)

    x0 = _solve_on(H, c, jnp.ones_like(constrained))
    active0 = constrained & (x0 < 0)
    state = (active0, x0, jnp.int32(0), jnp.all(~active0))
    active, x, _, done = jax.lax.while_loop(lambda st: (~st[3]) & (st[2] < max_iter), body, state)
    return x, ~active, done


def _lawson_hanson(H, c, constrained, x_start, max_iter):
    """The same QP by Lawson & Hanson's active-set NNLS ("Solving Least Squares Problems", 1974,
    ch. 23) in its normal-equation form (Bro & De Jong 1997), warm-started from a feasible
    ``x_start``: finite convergence without the cycling PDAS can show on ill-conditioned H.
    Returns (x, passive set, converged)."""
    scale = jnp.max(jnp.abs(c)) + 1e-300
    tol = 1e-11 * scale
    n = H.shape[0]

    def restore(x, passive):
        """Inner loop: step from feasible x towards the passive-set solution, dropping the
        coefficients that reach zero, until that solution is feasible."""

        def cond(st):
            x, passive, s, it = st
            return jnp.any(passive & constrained & (s <= 0)) & (it < n)

        def body(st):
            x, passive, s, it = st
            blocking = passive & constrained & (s <= 0)
            ratio = jnp.where(blocking, x / jnp.where(blocking, x - s, 1.0), jnp.inf)
            alpha = jnp.clip(jnp.min(ratio), 0.0, 1.0)
            x = x + alpha * (s - x)
            passive = passive & ~(constrained & (x <= 1e-14 * jnp.max(jnp.abs(x)) + 1e-300))
            x = jnp.where(passive, x, 0.0)
            return x, passive, _solve_on(H, c, passive), it + 1

        s = _solve_on(H, c, passive)
        x, passive, s, _ = jax.lax.while_loop(cond, body, (x, passive, s, jnp.int32(0)))
        return s, passive

    def outer_body(st):
        x, passive, it, _ = st
        w = c - H @ x
        candidates = constrained & ~passive & (w > tol)
        done = ~jnp.any(candidates)
        j = jnp.argmax(jnp.where(candidates, w, -jnp.inf))
        passive = jnp.where(done, passive, passive.at[j].set(True))
        x_new, passive = restore(x, passive)
        return jnp.where(done, x, x_new), passive, it + 1, done

    x0 = jnp.where(constrained, jnp.maximum(x_start, 0.0), x_start)
    passive0 = ~constrained | (x0 > 0)
    x0, passive0 = restore(x0, passive0)
    x, passive, _, done = jax.lax.while_loop(lambda st: (~st[3]) & (st[2] < max_iter), outer_body, (x0, passive0, jnp.int32(0), jnp.array(False)))
    return x, passive, done


@functools.partial(jax.jit, static_argnames=("method", "signed", "n_series", "max_iter"))
def solve_batch(design_re, design_im, weights, z_re, z_im, gamma_penalty, r_inv, constrained, phi, log_grid, fixed_log_lambda, log_floor, *, method, signed, n_series, max_iter=100):
    """Regularised DRT solve of B spectra on one frequency grid.

    design_re/design_im (N, P): unweighted Re/Im design; weights, z_re, z_im (B, N) in the
    caller's normalised units; gamma_penalty (P, P) = Γ + ηI and r_inv = R⁻¹ with Γ + ηI = RᵀR;
    constrained (P,) bool; the first ``n_series`` columns are the series terms (R_∞, L, 1/C),
    which the smoothness prior leaves free; phi (K, P) maps x to γ on the output grid; log_grid the ln λ grid;
    fixed_log_lambda: ln λ (B,) used when ``method == "fixed"``, and with "gcv"/"lcurve" for
    the spectra where it is finite (NaN: chosen by ``method``; so a fixed λ and an automatic
    one share one compilation); log_floor: the smallest ln λ an automatic choice may return.
    Returns a dict of (B, ...) arrays: x, log_lambda, log_lambda_choice (the criterion's own
    choice, before the floor), choice_index (its grid index: at the top or the bottom of the
    grid, the criterion's optimum may lie beyond), gamma,
    gamma_sd, sigma, converged, effective_parameters, and the GCV/L-curve criteria over the grid.
    """
    n_rows = 2 * design_re.shape[0]

    def one(w, zr, zi, fixed):
        A = jnp.concatenate([w[:, None] * design_re, w[:, None] * design_im], axis=0)
        b = jnp.concatenate([w * zr, w * zi])
        At = A @ r_inv
        U, s, _ = jnp.linalg.svd(At, full_matrices=False)
        beta = U.T @ b
        rss0 = jnp.maximum(b @ b - beta @ beta, 0.0)
        gcv, rss_curve, penalty_curve = _criteria(s, beta, rss0, log_grid, n_rows)
        if method == "fixed":
            log_lam, choice, index = fixed, fixed, jnp.array(-1)
        else:
            choice, index = _choose_log_lambda(s, beta, rss0, log_grid, n_rows, method)
            log_lam = jnp.where(jnp.isfinite(fixed), fixed, jnp.maximum(choice, log_floor))
        lam = jnp.exp(log_lam)
        AtA = A.T @ A
        H = AtA + lam * gamma_penalty
        c = A.T @ b
        if signed:
            free = jnp.ones(H.shape[0], bool)
            x = jsl.cho_solve(_masked_cholesky(H, free), c)
            converged = jnp.array(True)
        else:
            x_pdas, free, converged = _pdas(H, c, constrained, 30)
            x, free, converged = jax.lax.cond(
                converged,
                lambda: (x_pdas, free, converged),
                lambda: _lawson_hanson(H, c, constrained, x_pdas, max_iter),
            )
        factor = _masked_cholesky(H, free)
        both = free[:, None] & free[None, :]
        cov = jnp.where(both, jsl.cho_solve(factor, jnp.eye(H.shape[0])), 0.0)  # (H_FF)⁻¹, zero elsewhere
        r = A @ x - b
        rss = r @ r
        influence = jnp.sum(cov * AtA)
        sigma2 = rss / jnp.maximum(n_rows - influence, 1.0)
        gamma = phi @ x
        gamma_sd = jnp.sqrt(jnp.maximum(sigma2 * jnp.einsum("kp,pq,kq->k", phi, cov, phi), 0.0))
        # the credible band: Gaussian posterior at the evidence-chosen λ (module docstring)
        log_evidence = _log_evidence(s, rss_curve, penalty_curve, log_grid, n_rows, n_series)
        log_lam_band = _parabola_min(log_grid, -log_evidence, jnp.argmax(log_evidence))
        lam_band = jnp.exp(log_lam_band)
        factor_band = jsl.cho_factor(AtA + lam_band * gamma_penalty, lower=True)
        x_band = jsl.cho_solve(factor_band, c)
        r_band = A @ x_band - b
        sigma2_band = (r_band @ r_band + lam_band * x_band @ gamma_penalty @ x_band) / (n_rows - n_series)
        phi_l = jsl.solve_triangular(factor_band[0], phi.T, lower=True)  # L⁻¹Φᵀ: Φ H⁻¹ Φᵀ = ‖L⁻¹Φᵀ‖² per column
        band_mean = phi @ x_band
        band_sd = jnp.sqrt(jnp.maximum(sigma2_band * jnp.sum(phi_l * phi_l, axis=0), 0.0))
        return dict(
            x=x, log_lambda=log_lam, log_lambda_choice=choice, choice_index=index, gamma=gamma, gamma_sd=gamma_sd, sigma=jnp.sqrt(sigma2), covariance=sigma2 * cov,
            converged=converged, effective_parameters=influence, gcv=gcv, rss_curve=rss_curve, penalty_curve=penalty_curve,
            band_mean=band_mean, band_sd=band_sd, log_lambda_band=log_lam_band, log_evidence=log_evidence,
        )

    # One spectrum after another, not vmap: under vmap each factorisation becomes one batched
    # LAPACK call, which jaxlib splits over XLA's intra-op thread pool and then waits for; two
    # such calls at once (the solve's and the band's Cholesky are independent) can hold every
    # thread of a 2-core machine's pool waiting for work that none is left to run, and the call
    # never returns. A spectrum's own calls are not batched and run on the calling thread.
    return jax.lax.map(lambda spectrum: one(*spectrum), (weights, z_re, z_im, fixed_log_lambda))


def quantile_band(band_mean, band_sd, signed, gamma=None):
    """(5 %, 95 %) quantiles of the Gaussian posterior of γ; clipped at 0 when γ ≥ 0 is imposed.
    With ``gamma`` (the reported estimate, at GCV's λ) the band is widened to contain it, so a
    plot never shows γ outside its own band. NumPy, on the host (eager JAX operations would
    each be compiled in every process)."""
    band_mean, band_sd = np.asarray(band_mean), np.asarray(band_sd)
    lo, hi = band_mean - _Z90 * band_sd, band_mean + _Z90 * band_sd
    if not signed:
        lo, hi = np.maximum(lo, 0.0), np.maximum(hi, 0.0)
    if gamma is not None:
        lo, hi = np.minimum(lo, gamma), np.maximum(hi, gamma)
    return lo, hi
