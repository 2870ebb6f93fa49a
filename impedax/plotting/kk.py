"""Figures of the Kramers–Kronig test (`impedax.fitting.kk.KKResult.plot`)."""

from __future__ import annotations

from . import dense_model, nyquist_shape, plot_bode, plot_nyquist, plot_residuals, shade_bands, spectrum_layout


def plot_kk(result, *, title: str | None = None):
    """Nyquist and Bode of data vs KK fit, and the residuals Δ [%] vs frequency with the
    point threshold and the bad bands shaded, for a `KKResult`. Returns a matplotlib Figure."""
    data, model = (result.frequency, result.impedance), dense_model(result.frequency, result.kk_impedance, getattr(result, "predict", None))
    fig, (ax_nyq, ax_mod, ax_ph, ax_res) = spectrum_layout(nyquist_shape(data, model), True)
    plot_nyquist(ax_nyq, data, model, model_label=f"KK fit (M={result.n_rc})")
    plot_bode(ax_mod, ax_ph, data, model, model_label=f"KK fit (M={result.n_rc})")
    plot_residuals(ax_res, result.frequency, result.residuals_real, result.residuals_imag, labels=("Δ re", "Δ im"), ylabel="KK residual [%]", limit=result.thresholds["point"] * result.threshold_scale)
    ax_ph.set_xlabel("")
    if result.bad_bands:
        shade_bands([ax_mod, ax_ph, ax_res], result.bad_bands, label="not KK-consistent")
    verdict = "valid" if result.valid else "not valid"
    fig.suptitle(title or f"linear KK test: {verdict}, rms_rel {result.rms_rel * 100:.2g} %, µ {result.mu:.2f}")
    return fig
