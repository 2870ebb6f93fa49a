"""Figures of a Bayesian fit: data with posterior predictive bands, and the corner plot.

The functions take arrays (what `Posterior.plot` and `Posterior.corner` hand over), never a
sampler, and return a matplotlib `Figure`; nothing is shown or saved implicitly.
"""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np

from . import equal_aspect, nyquist_shape, spectrum_layout

__all__ = ["plot_posterior_bands", "plot_corner"]

BAND_QUANTILES = (0.05, 0.16, 0.5, 0.84, 0.95)


def plot_posterior_bands(frequency, z_data, model_frequency, z_draws, *, title: str, n_lines: int = 40, z_predictive=None):
    """Data (``frequency`` [Hz], ``z_data`` [Ω]) with the model's draws ``z_draws`` (draws,
    ``model_frequency``): Nyquist with ``n_lines`` draws as thin lines and the median, and Bode
    |Z| and phase with the 68% and 90% credible bands; ``z_predictive`` (draws with the noise
    added, same shape) adds the 90% posterior predictive band as dashed lines."""
    f, zs, z = np.asarray(model_frequency, float), np.asarray(z_draws, complex), np.asarray(z_data, complex)
    med = np.median(zs.real, axis=0) + 1j * np.median(zs.imag, axis=0)
    fig, (ax_nyq, ax_mod, ax_ph, _) = spectrum_layout(nyquist_shape((frequency, z), (f, med)), False)
    for k in np.linspace(0, zs.shape[0] - 1, min(n_lines, zs.shape[0])).astype(int):
        ax_nyq.plot(zs[k].real, -zs[k].imag, "-", color="tab:blue", alpha=0.08, lw=0.8)
    ax_nyq.plot(med.real, -med.imag, "-", color="tab:blue", lw=1.5, label="posterior median")
    ax_nyq.plot(z.real, -z.imag, "o", ms=3.5, mfc="none", color="k", label="data")
    ax_nyq.set(xlabel="Z' [Ω]", ylabel="−Z'' [Ω]", title="Nyquist")
    equal_aspect(ax_nyq)
    zp = None if z_predictive is None else np.asarray(z_predictive, complex)
    for ax, values, data_values, transform in ((ax_mod, np.abs(zs), np.abs(z), np.abs), (ax_ph, np.degrees(np.angle(zs)), np.degrees(np.angle(z)), lambda v: np.degrees(np.angle(v)))):
        if zp is not None:
            qp = np.quantile(transform(zp), [0.05, 0.95], axis=0)
            ax.plot(f, qp[0], "--", color="tab:orange", lw=1.0, label="90% predictive (model + noise)")
            ax.plot(f, qp[1], "--", color="tab:orange", lw=1.0)
        q = np.quantile(values, BAND_QUANTILES, axis=0)
        ax.fill_between(f, q[0], q[4], color="tab:blue", alpha=0.18, lw=0, label="90% band")
        ax.fill_between(f, q[1], q[3], color="tab:blue", alpha=0.35, lw=0, label="68% band")
        ax.plot(f, q[2], "-", color="tab:blue", lw=1.2, label="median")
        ax.plot(frequency, data_values, "o", ms=3.5, mfc="none", color="k", label="data")
        ax.set_xscale("log")
    ax_mod.set(yscale="log", ylabel="|Z| [Ω]")
    ax_ph.set(ylabel="phase [deg]", xlabel="frequency [Hz]")
    for ax in (ax_nyq, ax_mod, ax_ph):
        ax.grid(alpha=0.3, which="both")
    ax_nyq.legend(fontsize=8)
    ax_mod.legend(fontsize=8)
    fig.suptitle(title)
    return fig


def plot_corner(
    draws,
    names: Sequence[str],
    log_scale: Sequence[bool],
    *,
    truths: Mapping[str, float] | None = None,
    bins: int = 30,
    max_points: int = 4000,
    title: str = "posterior",
):
    """Corner plot of ``draws`` (…, param) named ``names``: marginal histograms (5/50/95%
    lines) on the diagonal and pairwise scatter below it, log10 axes where ``log_scale``;
    ``truths`` by name draws reference lines; at most ``max_points`` evenly spaced draws."""
    k = len(names)
    flat = np.asarray(draws, float).reshape(-1, k)
    if flat.shape[0] > max_points:
        flat = flat[np.linspace(0, flat.shape[0] - 1, max_points).astype(int)]
    shown = np.where(np.asarray(log_scale), np.log10(np.where(np.asarray(log_scale), flat, 1.0)), flat)
    labels = [f"log10 {n}" if ls else n for n, ls in zip(names, log_scale)]
    truth = None
    if truths:
        truth = [(math.log10(truths[n]) if ls else truths[n]) if n in truths else None for n, ls in zip(names, log_scale)]
    size = min(2.0 * k + 1, 16)
    fig, axes = plt.subplots(k, k, figsize=(size, size), squeeze=False, layout="constrained")
    for i in range(k):
        for j in range(k):
            ax = axes[i, j]
            if j > i:
                ax.set_visible(False)
                continue
            if i == j:
                ax.hist(shown[:, i], bins=bins, color="tab:blue", histtype="stepfilled", alpha=0.6)
                for qv in np.quantile(shown[:, i], [0.05, 0.5, 0.95]):
                    ax.axvline(qv, color="k", lw=0.8, ls="--" if qv != np.median(shown[:, i]) else "-")
                ax.set_yticks([])
            else:
                ax.plot(shown[:, j], shown[:, i], ".", ms=1.5, alpha=0.25, color="tab:blue")
                if truth is not None and truth[i] is not None:
                    ax.axhline(truth[i], color="tab:red", lw=0.8)
            if truth is not None and truth[j] is not None:
                ax.axvline(truth[j], color="tab:red", lw=0.8)
            if i == k - 1:
                ax.set_xlabel(labels[j], fontsize=8)
            else:
                ax.set_xticklabels([])
            if j == 0 and i > 0:
                ax.set_ylabel(labels[i], fontsize=8)
            elif j > 0:
                ax.set_yticklabels([])
            ax.tick_params(labelsize=7)
    fig.suptitle(f"{title} ({flat.shape[0]} draws shown)", fontsize=9)
    return fig
