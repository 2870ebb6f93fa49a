"""Figures of the Kramers–Kronig test (`impedax.fitting.kk.KKResult.plot`)."""

from __future__ import annotations

from . import plot_bode, plot_nyquist, plot_residuals, settle_nyquist, shade_bands


def plot_kk(result, *, title: str | None = None):
    """Nyquist and Bode of data vs KK fit, and the residuals Δ [%] vs frequency with the
    point threshold and the bad bands shaded, for a `KKResult`. Returns a matplotlib Figure."""
    import matplotlib.pyplot as plt

    data, model = (result.frequency, result.impedance), (result.frequency, result.kk_impedance)
    fig = plt.figure(figsize=(11, 6.5), layout="constrained")
    grid = fig.add_gridspec(3, 2, width_ratios=[1, 1.2])
    ax_nyq = fig.add_subplot(grid[:, 0])
    ax_mod = fig.add_subplot(grid[0, 1])
    ax_ph = fig.add_subplot(grid[1, 1], sharex=ax_mod)
    ax_res = fig.add_subplot(grid[2, 1], sharex=ax_mod)
    plot_nyquist(ax_nyq, data, model, model_label=f"KK fit (M={result.n_rc})")
    plot_bode(ax_mod, ax_ph, data, model, model_label=f"KK fit (M={result.n_rc})")
    plot_residuals(ax_res, result.frequency, result.residuals_real, result.residuals_imag, labels=("Δ re", "Δ im"), ylabel="KK residual [%]", limit=result.thresholds["point"] * result.threshold_scale)
    ax_ph.set_xlabel("")
    if result.bad_bands:
        shade_bands([ax_mod, ax_ph, ax_res], result.bad_bands, label="not KK-consistent")
    verdict = "valid" if result.valid else "not valid"
    fig.suptitle(title or f"linear KK test: {verdict}, rms_rel {result.rms_rel * 100:.2g} %, µ {result.mu:.2f}")
    settle_nyquist(fig, ax_nyq)
    return fig
