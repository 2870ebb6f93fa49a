"""Figure of a model comparison (`impedax.fitting.comparison.Comparison.plot`)."""

from __future__ import annotations

import numpy as np

from . import font_size


def plot_comparison(comparison, *, figsize: tuple[float, float] | None = None):
    """Data with every model's fit (Nyquist, |Z|, phase), and each model's relative residuals,
    for a `Comparison`, in the layout of a single spectrum (`spectrum_layout`, which
    ``figsize`` (width, height) [in] sizes). Figure."""
    from . import equal_aspect, model_curve, nyquist_frame, nyquist_shape, plain_log_ticks, spectrum_layout

    ref = comparison.fits[0]
    f, z = ref.frequency, ref.z_data
    # the layout and the Nyquist limits follow the data: a poor model's curve may run past them
    fig, (ax_nyq, ax_mod, ax_ph, ax_res) = spectrum_layout(nyquist_shape((f, z)), True, figsize=figsize)
    ax_nyq.plot(z.real, -z.imag, "o", mfc="none", ms=3.5, color="k", label="data")
    ax_mod.loglog(f, np.abs(z), "o", mfc="none", ms=3.5, color="k", label="data")
    ax_ph.semilogx(f, np.degrees(np.angle(z)), "o", mfc="none", ms=3.5, color="k", label="data")
    # a line style of its own for each model, so that two fits of the same curve (a CPE at α = 1
    # and a capacitor) are both seen, one drawn over the other
    styles = ("-", "--", "-.", ":")
    curves = []
    rows = getattr(comparison, "rows", None) or [{}] * len(comparison.fits)
    for k, (r, row) in enumerate(zip(comparison.fits, rows)):
        label = f"{row.get('label', r.model)} (rms_rel {r.rms_rel * 100:.3g} %)"  # (a fit with fixed values named by them)
        ls = styles[k % len(styles)]
        f_model, z_model = model_curve(r)
        curves.append(z_model)
        ax_nyq.plot(z_model.real, -z_model.imag, ls=ls, label=label)
        ax_mod.loglog(f_model, np.abs(z_model), ls=ls, label=label)
        ax_ph.semilogx(f_model, np.degrees(np.angle(z_model)), ls=ls, label=label)
        ax_res.semilogx(f, np.abs(r.residuals) * 100, ".", ls=ls, label=label)
    ax_nyq.set(xlabel="Z' [Ω]", ylabel="−Z'' [Ω]", title="Nyquist")
    equal_aspect(ax_nyq, frame=nyquist_frame(z, *curves))
    ax_nyq.legend(fontsize=font_size("legend", 7), loc="best")  # (data and every model; the Bode panels draw them alike)
    ax_mod.set(xlabel="frequency [Hz]", ylabel="|Z| [Ω]")
    plain_log_ticks(ax_mod.yaxis)
    ax_ph.set(xlabel="frequency [Hz]", ylabel="phase [deg]")
    ax_res.set(xlabel="frequency [Hz]", ylabel="|relative residual| [%]", yscale="log")
    plain_log_ticks(ax_res.yaxis)
    for ax in (ax_nyq, ax_mod, ax_ph, ax_res):
        ax.grid(alpha=0.3, which="both")
    ax_res.legend(fontsize=font_size("legend", 7))
    fig.suptitle(f"model comparison — best by AIC: {comparison.best}")
    return fig
