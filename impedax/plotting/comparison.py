"""Figure of a model comparison (`impedax.fitting.comparison.Comparison.plot`)."""

from __future__ import annotations

import numpy as np

from ..arguments import figure_size
from ..data import counted
from . import drawn_label, font_size, label_spectra_axis


def plot_comparison(comparison, *, figsize: tuple[float, float] | None = None):
    """Data with every model's fit (Nyquist, |Z|, phase), and each model's relative residuals,
    each named with its rms_rel and ΔAIC, for a `Comparison`, in the layout of a single spectrum (`spectrum_layout`, which
    ``figsize`` (width, height) [in] sizes). Figure."""
    from . import frequency_axis, labelled_log_ticks, legends_off_data, magnitude_axis, model_curve, nyquist_frame, nyquist_shape, nyquist_view, residual_axis, spectrum_layout

    ref = comparison.fits[0]
    f, z = ref.frequency, ref.z_data
    # the layout and the Nyquist limits follow the data: a poor model's curve may run past them
    fig, (ax_nyq, ax_mod, ax_ph, ax_res) = spectrum_layout(nyquist_shape((f, z)), True, figsize=figsize)
    # (the data blue and the models from orange on, as `impedax fit --plot` draws data and model)
    ax_nyq.plot(z.real, -z.imag, "o", mfc="none", ms=3.5, color="C0", label="data")
    ax_mod.loglog(f, np.abs(z), "o", mfc="none", ms=3.5, color="C0", label="data")
    ax_ph.semilogx(f, np.degrees(np.angle(z)), "o", mfc="none", ms=3.5, color="C0", label="data")
    # a line style of its own for each model, so that two fits of the same curve (a CPE at α = 1
    # and a capacitor) are both seen, one drawn over the other
    styles = ("-", "--", "-.", ":")
    curves = []
    rows = getattr(comparison, "rows", None) or [{}] * len(comparison.fits)
    for k, (r, row) in enumerate(zip(comparison.fits, rows)):
        # (a fit with fixed values named by them; its ΔAIC to the table's 2 decimals: the figure
        # says by how much the best leads, where the title named it alone)
        delta = row.get("delta_aic")
        lead = f", ΔAIC {delta:.2f}" if delta is not None and np.isfinite(delta) else ""
        label = f"{row.get('label', r.model)} (rms_rel {r.rms_rel * 100:.3g} %{lead})"
        ls, colour = styles[k % len(styles)], f"C{k % 9 + 1}"
        f_model, z_model = model_curve(r)
        curves.append(z_model)
        ax_nyq.plot(z_model.real, -z_model.imag, ls=ls, color=colour, label=label)
        ax_mod.loglog(f_model, np.abs(z_model), ls=ls, color=colour, label=label)
        ax_ph.semilogx(f_model, np.degrees(np.angle(z_model)), ls=ls, color=colour, label=label)
        ax_res.semilogx(f, np.abs(r.residuals) * 100, ".", ls=ls, color=colour)  # (named in the Nyquist legend, below)
    ax_nyq.set(xlabel="Z' [Ω]", ylabel="−Z'' [Ω]", title="Nyquist")
    nyquist_view(ax_nyq, z, *curves, frequency=f, frame=nyquist_frame(z, *curves))
    ax_nyq.legend(fontsize=font_size("legend", 7), loc="best")  # (data and every model; the Bode panels draw them alike)
    ax_mod.set(xlabel="frequency [Hz]", ylabel="|Z| [Ω]")
    magnitude_axis(ax_mod.yaxis, nyquist=ax_nyq)  # (in the Nyquist panel's prefix: one unit across the figure)
    ax_ph.set(xlabel="frequency [Hz]", ylabel="phase [deg]")
    ax_res.set(xlabel="frequency [Hz]", ylabel="|relative residual| [%]", yscale="log")
    # (two labels or more at any range, `labelled_log_ticks`, as every rms_rel panel: matplotlib's
    # log ticks read residuals of 0.068–0.195 % as "0.1" alone, 0.3–300 % as 1, 10, 100)
    labelled_log_ticks(ax_res.yaxis)
    for ax in (ax_mod, ax_ph, ax_res):  # (shared)
        frequency_axis(ax.xaxis)
    if residual_axis(ax_res, np.concatenate([np.ravel(r.residuals) for r in comparison.fits])):
        ax_res.legend(fontsize=font_size("legend", 7))  # (the rounding-level note alone)
    for ax in (ax_nyq, ax_mod, ax_ph, ax_res):
        ax.grid(alpha=0.3, which="both")
    # (the residual panel has no legend of the models, only the rounding-level note when there is one:
    # the Nyquist panel's names each model in the colour and line style of its residuals; the same
    # legend again, moved above the panel for four models on REAL exampleData.csv, took a third of
    # the height of the |Z|, phase and residual panels)
    title = f"model comparison — best by AIC: {getattr(comparison, 'best_label_with_ties', comparison.best)} ({comparison.fits[0].weighting} weighting)"  # ("X (tied with Y)": `Comparison.best_label_with_ties`)
    undetermined = comparison.undetermined_best() if hasattr(comparison, "undetermined_best") else None
    if undetermined:  # (as the report says it: REAL exampleData.csv's best, R0 + R1 || CPE1, leaves R1 undetermined, the data hold R0 + CPE1)
        title += f"\n{', '.join(undetermined['undetermined'])} undetermined in it: " + (
            f"the data hold {' or '.join(undetermined['reduced'])}" if undetermined["reduced"] else "its warnings say which term to drop")
        if undetermined["best_determined"] is not None and not undetermined["far_worse"]:
            title += f"; with every parameter determined: {undetermined['best_determined']} (ΔAIC {undetermined['delta_aic']:.2f})"
    fig.suptitle(title)
    legends_off_data(fig)  # (a legend of long model names wider than its panel spread over the axis and its tick labels)
    return fig


def plot_batch_comparison(comparison, *, figsize: tuple[float, float] | None = None):
    """Each model's ΔAIC (to the spectrum's best) against the spectrum, one line per model, for
    a `BatchComparison`; the lowest summed AIC in the title; ``figsize`` (width, height) [in],
    default 11 × 4.5. Figure."""
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    figsize = figure_size(figsize, "figsize")
    rows = comparison.spectra()
    index = np.arange(len(rows))
    fig, ax = plt.subplots(figsize=figsize or (11, 4.5))
    markers = ("o", "s", "^", "D", "v")
    summed = {m["label"]: m for m in comparison.models()}
    any_reduced = False
    for k, label in enumerate(comparison.labels):
        delta = np.array([r["models"][k]["delta_aic"] for r in rows], float)
        # (where the model reduces to the spectrum's best, its ΔAIC is AIC's charge for idle
        # parameters, no rival's lead, as the table's lead column takes it: drawn hollow, so that
        # the figure does not show a weak win where the table counts a decisive one)
        reduced = np.array([label in r["reduces_to_best"] for r in rows], bool)
        any_reduced |= bool(reduced.any())
        m = summed[label]
        # (markers alone: the spectra are independent, a line between them would suggest a trend)
        (line,) = ax.plot(index[~reduced], delta[~reduced], marker=markers[k % len(markers)], ms=5, ls="none", label=f"{label} (best on {m['wins']} of {len(rows)}, ΔΣAIC {m['delta_aic_sum']:.1f})")
        if reduced.any():
            ax.plot(index[reduced], delta[reduced], marker=markers[k % len(markers)], ms=5, ls="none", mfc="none", color=line.get_color())
    if any_reduced:
        ax.plot([], [], marker="o", ms=5, ls="none", mfc="none", color="0.3", label="hollow: reduces to the spectrum's best (its ΔAIC is the charge for idle parameters, no rival's)")
    # (4: `fitting.comparison.WEAK_DELTA_AIC`, which this lower layer may not import)
    ax.axhline(4.0, color="0.5", ls=":", lw=1, label="ΔAIC 4 (weaker support beyond, Burnham & Anderson 2002)")
    ax.set_yscale("symlog", linthresh=10.0, linscale=2.0)
    ax.set_ylim(bottom=-0.5)  # (ΔAIC ≥ 0: no room below the winners' line)
    # ticks in the linear part too (2: the charge of one parameter that does nothing; 4: weak)
    top = max(10.0, float(np.nanmax([r["models"][k]["delta_aic"] for r in rows for k in range(len(comparison.labels))] or [10.0])))
    ax.set_yticks([t for t in (0, 2, 4, 6, 8, 10, 100, 1_000, 10_000, 100_000) if t <= 10 * top])
    ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    # each spectrum's labels on the x axis (every k-th where they do not all fit), the batch's
    # dimensions named: the axis read "spectrum index (0 = cycle=0, …)" beyond 30 spectra
    label_spectra_axis(ax, [", ".join(drawn_label(v) for v in r["labels"].values()) for r in rows], list(comparison.dims))
    ax.set_ylabel("ΔAIC to the spectrum's best")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=font_size("legend", 7), loc="best")
    fig.suptitle(f"model comparison over {counted(len(rows), 'spectrum', 'spectra')} — lowest summed AIC: {comparison.labels[comparison.best_index]} ({comparison.dataset.attrs['weighting']} weighting)")
    fig.tight_layout()
    return fig
