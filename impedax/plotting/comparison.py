"""Figure of a model comparison (`impedax.fitting.comparison.Comparison.plot`)."""

from __future__ import annotations

import numpy as np


def plot_comparison(comparison):
    """Data with every model's fit, and each model's relative residuals, for a `Comparison` (Figure)."""
    import matplotlib.pyplot as plt

    from . import equal_aspect, plain_log_ticks, settle_nyquist

    fig, axes = plt.subplots(2, 2, figsize=(11, 7), layout="constrained")
    ref = comparison.fits[0]
    f, z = ref.frequency, ref.z_data
    axes[0, 0].plot(z.real, -z.imag, "o", mfc="none", ms=3.5, color="k", label="data")
    axes[0, 1].loglog(f, np.abs(z), "o", mfc="none", ms=3.5, color="k", label="data")
    axes[1, 0].semilogx(f, np.degrees(np.angle(z)), "o", mfc="none", ms=3.5, color="k", label="data")
    # a line style of its own for each model, so that two fits of the same curve (a CPE at α = 1
    # and a capacitor) are both seen, one drawn over the other
    styles = ("-", "--", "-.", ":")
    for k, r in enumerate(comparison.fits):
        label = f"{r.model} (rms_rel {r.rms_rel * 100:.3g} %)"
        ls = styles[k % len(styles)]
        axes[0, 0].plot(r.z_model.real, -r.z_model.imag, ls=ls, label=label)
        axes[0, 1].loglog(f, np.abs(r.z_model), ls=ls, label=label)
        axes[1, 0].semilogx(f, np.degrees(np.angle(r.z_model)), ls=ls, label=label)
        axes[1, 1].semilogx(f, np.abs(r.residuals) * 100, ".", ls=ls, label=label)
    axes[0, 0].set(xlabel="Z' [Ω]", ylabel="−Z'' [Ω]", title="Nyquist")
    equal_aspect(axes[0, 0])
    axes[0, 1].set(xlabel="frequency [Hz]", ylabel="|Z| [Ω]")
    axes[1, 0].set(xlabel="frequency [Hz]", ylabel="phase [deg]")
    axes[1, 1].set(xlabel="frequency [Hz]", ylabel="|relative residual| [%]", yscale="log")
    plain_log_ticks(axes[1, 1].yaxis)
    for ax in axes.flat:
        ax.grid(alpha=0.3, which="both")
    axes[1, 1].legend(fontsize=7)
    fig.suptitle(f"model comparison — best by AIC: {comparison.best}")
    settle_nyquist(fig, axes[0, 0])
    return fig
