"""Figures of the distribution of relaxation times: γ vs τ with its credible band and peaks,
the DRT fit on Nyquist and Bode, and Z-HIT's reconstruction. Every function returns a Figure."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..data import counted, format_lambda, format_percent, format_quantity, format_time
from . import FLAT_NYQUIST, LabelledLogLocator, dense_model, drawn_label, font_size, frame_points, frequency_axis, frame_spectra, label_spectra_axis, labelled_log_ticks, legends_off_data, magnitude_axis, nyquist_panel_height, nyquist_shape, plot_bode, plot_nyquist, prefixed_axis, residual_axis, shade_bands, time_axis

__all__ = ["plot_drt", "plot_drt_batch", "plot_gamma", "plot_zhit"]


def counted_peaks(peaks) -> list:
    """The peaks a title counts: resolved (R told from zero) and inside the measured τ window,
    the rule of `fitting.drt.peaks.counted_peaks` (which this lower layer may not import)."""
    return [p for p in peaks if getattr(p, "resolved", True) and p.inside_window]


def band_label(result) -> str:
    """The credible band's legend entry: "90 % band", and where the band's λ is not γ's (the
    evidence's, `DRTResult.band_lambda`) that λ and "noise only", as the report says: on the REAL
    exampleDataZPlot.z the band at λ = 1.8×10⁻⁷ beside γ at 10⁻⁴ rose to 0.4 kΩ where γ is 0,
    under a legend that called it the band of the curve drawn."""
    lam, band_lam = float(getattr(result, "lam", np.nan)), float(getattr(result, "band_lambda", np.nan))
    if not (np.isfinite(lam) and np.isfinite(band_lam)) or abs(band_lam - lam) <= 0.01 * lam:
        return "90 % band"
    return f"90 % band (noise only, at λ = {format_lambda(band_lam, 2)}; γ at {format_lambda(lam, 2)})"


def plot_gamma(ax, result, *, overlay=None, label="data DRT", overlay_label=None, legend_above=False) -> None:
    """γ(τ) [Ω] on log τ with the 90 % band, peaks marked (τ and R), the measured τ range
    outside shaded, and ``overlay`` (an `AnalyticDRT` or a `DRTResult`) on top; the legend
    inside, or above the panel with ``legend_above`` (where no title is; in two columns where
    they fit the panel's width, else one: REAL exampleData.csv's two columns, 5.6 in, stood over
    a γ panel of a 4.8 in column, which the layout shrank to 3 in beside blank figure). The γ range is
    `gamma_top`'s: the band outside the measured window may run off the top."""
    before = ax.dataLim.frozen()  # (what was drawn on ``ax`` before keeps its range)
    ax.fill_between(result.tau, result.gamma_q05, result.gamma_q95, color="tab:blue", alpha=0.2, lw=0, label=band_label(result))
    ax.semilogx(result.tau, result.gamma, color="tab:blue", lw=1.6, label=label)
    for p in result.peaks:
        ax.plot(p.tau_s, p.gamma_max_ohm, "v", color="tab:red", ms=7)
        ax.annotate(f"{format_time(p.tau_s)}\n{format_quantity(p.r_ohm, 'Ω')}", (p.tau_s, p.gamma_max_ohm), textcoords="offset points", xytext=(0, 8), ha="center", fontsize=font_size("text", 7))
    for i, p in enumerate(getattr(result, "dropped_peaks", ())):  # below the cut-off: marked, not counted
        ax.plot(p.tau_s, p.gamma_max_ohm, "v", mfc="none", color="0.45", ms=6, label="peak below the cut-off (dropped)" if i == 0 else None)
    if overlay is not None:
        name = overlay_label or (f"circuit {overlay.circuit}" if hasattr(overlay, "circuit") else "model DRT")
        ax.semilogx(overlay.tau, overlay.gamma, "--", color="tab:orange", lw=1.4, label=name)
        deltas = getattr(overlay, "deltas", ())
        top = max(float(np.max(result.gamma)), 1e-300)
        shown = [(tau, r) for tau, r in deltas if result.tau.min() <= tau <= result.tau.max()]
        for i, (tau, r) in enumerate(shown):
            ax.vlines(tau, 0, top, color="tab:orange", lw=1.2, ls=":", label="R‖C deltas (R in labels)" if i == 0 else None)
            # (along the line from its foot: at its top the label lay under the peak's marker)
            ax.annotate(f"δ {format_quantity(r, 'Ω')}", (tau, 0.0), textcoords="offset points", xytext=(2, 3), rotation=90, ha="left", va="bottom", fontsize=font_size("text", 7), color="tab:orange")
        outside = [(tau, r) for tau, r in deltas if (tau, r) not in shown]
        if outside:  # no line to draw: the legend says where they are (a fitted block far off the data)
            where = ", ".join(f"δ {format_quantity(r, 'Ω')} at τ = {format_time(tau, 2)}" for tau, r in outside[:3]) + (", …" if len(outside) > 3 else "")
            ax.plot([], [], color="tab:orange", lw=1.2, ls=":", label=f"outside the plotted τ range, not drawn: {where}")
    lo, hi = result.window
    ceiling = gamma_top(result, overlay)
    clipped = bool(np.nanmax(result.gamma_q95, initial=-np.inf) > ceiling)
    # behind the band and translucent: the band beyond the window is seen, greyed, not hidden
    shading = dict(color="0.5", alpha=0.2, lw=0, zorder=0.5)
    ax.axvspan(result.tau.min(), lo, **shading)
    ax.axvspan(hi, result.tau.max(), **shading, label="outside measured range" + (" (band cut at the top)" if clipped else ""))
    ax.set_xlim(result.tau.min(), result.tau.max())
    ax.set_xlabel("τ [s]")
    time_axis(ax.xaxis)  # (1µ … 10m, 0.1, 1, 10: as the frequency axes read, not 10⁻⁶ … 10¹)
    ax.set_ylabel("γ [Ω]")
    prefixed_axis(ax.yaxis)
    ax.grid(alpha=0.3, which="both")
    # the γ range is what the reader can read (`gamma_top`), not all that is drawn: the band
    # drawn over all τ no longer sets it (curves drawn before or after, as other spectra's γ,
    # still do)
    low = min(0.0, float(np.nanmin(result.gamma_q05[gamma_window(result.tau, result.window)], initial=0.0)))
    ax.dataLim.intervaly = (min(before.y0, low), max(before.y1, ceiling))
    ax.autoscale_view()
    if legend_above:  # (inside, the legend covered the labels of the peaks it stood over)
        above = dict(fontsize=font_size("legend", 7), loc="lower left", bbox_to_anchor=(0.0, 1.01), borderaxespad=0.0, frameon=False)
        legend = ax.legend(ncol=2, **above)
        if _legend_width_in(legend) > _panel_width_in(ax):
            ax.legend(ncol=1, **above)
    else:
        ax.legend(fontsize=font_size("legend", 7))


# the room a panel's y label and tick labels take of its column's width [in] (`_panel_width_in`)
Y_LABELS_IN = 0.9


def _panel_width_in(ax) -> float:
    """The width [in] ``ax`` will have: its column's share of the figure (its grid's width
    ratios) less `Y_LABELS_IN`; its present width on axes not of a grid."""
    fig = ax.get_figure()
    spec = ax.get_subplotspec() if hasattr(ax, "get_subplotspec") else None
    if spec is None:
        return ax.get_position().width * fig.get_figwidth()
    grid = spec.get_gridspec()
    ratios = grid.get_width_ratios() or [1.0] * grid.ncols
    return fig.get_figwidth() * sum(ratios[c] for c in spec.colspan) / sum(ratios) - Y_LABELS_IN


def _legend_width_in(legend) -> float:
    """The width [in] of ``legend`` as drawn (its text measured by the figure's renderer)."""
    fig = legend.get_figure()
    return legend.get_window_extent(fig.canvas.get_renderer()).width / fig.dpi


# the γ panel's range above its highest curve, as a multiple of it (the peak labels' room)
GAMMA_HEADROOM = 1.3


def gamma_window(tau, window) -> np.ndarray:
    """Where ``tau`` lies in the measured τ ``window`` (all of it when none of it does)."""
    inside = (tau >= window[0]) & (tau <= window[1])
    return inside if inside.any() else np.ones_like(inside)


def gamma_top(result, overlay=None) -> float:
    """The top of the γ panel's range [Ω]: `GAMMA_HEADROOM` × the highest of the curves and the
    band inside the measured τ window and of every peak marked (a peak outside the window keeps
    its marker and label). Outside the window the data do not pin γ down, and the band there
    grows as wide as the regularisation lets it: REAL exampleData.csv's reaches 172 mΩ at
    τ ≈ 300 s beside curves and peaks of at most 51 mΩ, and scaling to it left the panel four
    fifths empty. That band, and a curve rising there without a peak, may run off the top,
    under the grey of the unmeasured range (whose legend then says the band is cut): its
    height there reads no measurement, while the curves inside the window are what a reader reads."""
    inside = gamma_window(result.tau, result.window)
    seen = [result.gamma[inside], result.gamma_q95[inside]]
    if overlay is not None:
        seen.append(overlay.gamma[gamma_window(overlay.tau, result.window)])
    marks = [p.gamma_max_ohm for p in (*result.peaks, *getattr(result, "dropped_peaks", ()))]
    highest = max([float(np.nanmax(g, initial=-np.inf)) for g in seen] + [float(m) for m in marks])
    return GAMMA_HEADROOM * highest if np.isfinite(highest) and highest > 0 else GAMMA_HEADROOM * max(float(np.nanmax(result.gamma_q95)), 1e-300)


def plot_drt(result, *, overlay=None, title: str | None = None):
    """γ vs τ (band, peaks, optional overlay) on the left; Nyquist and Bode of data vs the DRT
    fit on the right; relative residuals below."""
    data, model = (result.frequency, result.impedance), dense_model(result.frequency, result.z_fit, getattr(result, "predict", None))
    shape = nyquist_shape(data, model)
    if shape <= FLAT_NYQUIST:  # the Nyquist panel across the top, as high as the spectrum's shape asks
        heights = [nyquist_panel_height(shape, 12.0), 2.6, 2.2]
        fig = plt.figure(figsize=(12, sum(heights) + 0.6), layout="constrained")
        grid = fig.add_gridspec(3, 2, width_ratios=[1.4, 1], height_ratios=heights)
        slots = grid[1, 0], grid[2, 0], grid[0, :], grid[1, 1], grid[2, 1]
    else:
        fig = plt.figure(figsize=(12, 6.5), layout="constrained")
        grid = fig.add_gridspec(3, 3, width_ratios=[1.4, 1, 1.1])
        slots = grid[:2, 0], grid[2, 0], grid[:, 1], grid[0, 2], grid[1, 2]
    ax_g, ax_res, ax_nyq, ax_mod = (fig.add_subplot(slot) for slot in slots[:4])
    ax_ph = fig.add_subplot(slots[4], sharex=ax_mod)
    plot_gamma(ax_g, result, overlay=overlay, legend_above=True)
    plot_nyquist(ax_nyq, data, model, model_label="DRT fit")
    plot_bode(ax_mod, ax_ph, data, model, model_label="DRT fit", nyquist=ax_nyq)
    order = np.argsort(result.frequency)
    f = result.frequency[order]
    ax_res.semilogx(f, result.residuals.real[order] * 100, "o-", ms=3, lw=0.8, label="Re")
    ax_res.semilogx(f, result.residuals.imag[order] * 100, "s-", ms=3, lw=0.8, label="Im")
    ax_res.axhline(0, color="k", lw=0.6)
    ax_res.set_xlabel("frequency [Hz]")
    frequency_axis(ax_res.xaxis)
    ax_res.set_ylabel("DRT residual (Z − Z_fit)/|Z| [%]")
    ax_res.grid(alpha=0.3, which="both")
    residual_axis(ax_res, result.residuals)
    ax_res.legend(fontsize=font_size("legend", 8), ncol=2)
    dropped = len(getattr(result, "dropped_peaks", ()))
    n_counted = len(counted_peaks(result.peaks))  # resolved, inside the measured range (docs/drt.md, "Peaks")
    fig.suptitle(title or f"DRT: {n_counted} peak(s){f' (+{dropped} below the cut-off)' if dropped else ''}, λ = {result.lam:.2g} ({result.lambda_method}), rms_rel {format_percent(result.rms_rel)}")
    return fig


LEGEND_MAX = 10  # batches of up to this many spectra get a legend of their labels, larger ones a colour bar


def label_colour_bar(bar, labels, dims) -> None:
    """Mark a colour bar over the positions 0 … n−1 of a batch's spectra with the spectra's
    labels (``cycle`` 100 … 129), at most 8 integer ticks, named by the dimensions: its ticks
    were the positions, so after ``--select cycle=100:129`` the colour of cycle 125 read "25"."""
    from matplotlib.ticker import FuncFormatter, MaxNLocator

    n = len(labels)
    bar.locator = MaxNLocator(nbins=8, integer=True, min_n_ticks=1)
    bar.formatter = FuncFormatter(lambda x, pos=None: labels[int(round(x))] if 0 <= round(x) < n and abs(x - round(x)) < 1e-6 else "")
    bar.update_ticks()
    bar.set_label(", ".join(dims))


def gamma_map(ax, batch, window: tuple[float, float]):
    """γ(τ) of every spectrum of a batch as a map over the spectra (x, positions 0 … n−1) and τ
    (y, log), each spectrum's peaks on it (filled: counted, resolved inside the measured τ window;
    hollow: the others; area ∝ |R|), the window's ends dashed. The colour scale ends at the
    largest |γ| inside the window (beyond it the colour saturates: the arcs below f_min, up to
    3 Ω on the REAL battery cycles, would pale the peaks that were measured); a signed DRT's
    is diverging about 0. Returns the mesh and whether γ goes beyond the scale (above, below)."""
    from . import frequency_cell_edges

    results = batch.results
    tau = np.asarray(results[0].tau, float)
    same = all(one.tau.shape == tau.shape and np.allclose(one.tau, tau, rtol=1e-12) for one in results)
    if not same:  # (spectra on different grids: each γ read on the first one's τ, zero beyond its own)
        tau = np.geomspace(min(float(one.tau.min()) for one in results), max(float(one.tau.max()) for one in results), tau.size)
    order = np.argsort(tau)
    tau = tau[order]
    gamma = np.array([one.gamma[np.argsort(one.tau)] if same else np.interp(np.log(tau), np.log(np.sort(one.tau)), one.gamma[np.argsort(one.tau)], left=0.0, right=0.0) for one in results])
    inside = (tau >= window[0]) & (tau <= window[1])
    finite = gamma[:, inside][np.isfinite(gamma[:, inside])] if inside.any() else gamma[np.isfinite(gamma)]
    signed = bool(np.nanmin(gamma) < 0)
    scale = float(np.max(np.abs(finite))) if finite.size and np.max(np.abs(finite)) > 0 else 1.0
    low = -scale if signed else 0.0
    cells = frequency_cell_edges(tau)
    x_edges = np.arange(len(results) + 1) - 0.5
    mesh = ax.pcolormesh(x_edges, cells, gamma.T, vmin=low, vmax=scale, cmap="RdBu_r" if signed else "magma_r", shading="flat", rasterized=gamma.size > 5000)
    ax.set_yscale("log")
    ax.set_ylim(cells[0], cells[-1])
    ends = [end for end in window if cells[0] < end < cells[-1]]
    for k, end in enumerate(ends):
        ax.axhline(end, color="tab:cyan", lw=0.9, ls="--", label="measured τ range" if k == 0 else None)
    peaks = [(i, p) for i, one in enumerate(results) for p in one.peaks]
    r_top = max((abs(p.r_ohm) for _, p in peaks), default=0.0) or 1.0
    for kept, style in ((True, {"facecolors": "white", "edgecolors": "black", "label": "peaks (resolved, measured τ range)"}),
                        (False, {"facecolors": "none", "edgecolors": "tab:cyan", "label": "other peaks"})):
        chosen = [(i, p) for i, p in peaks if (p in counted_peaks([p])) == kept]
        if chosen:
            ax.scatter([i for i, _ in chosen], [p.tau_s for _, p in chosen], s=[8 + 40 * abs(p.r_ohm) / r_top for _, p in chosen], linewidths=0.8, zorder=3, **style)
    ax.set_ylabel("τ [s]")
    time_axis(ax.yaxis)
    return mesh, (bool(np.nanmax(gamma) > scale), bool(np.nanmin(gamma) < low))


# the batch figure's rms_rel axis is ticked as every log axis of values read off a figure
# (`labelled_log_ticks`); these names stay for code that ticked an axis with them
RmsRelLocator = LabelledLogLocator


def rms_rel_ticks(axis) -> None:
    """The log rms_rel [%] ``axis`` of the batch figure: `labelled_log_ticks`."""
    labelled_log_ticks(axis)


def plot_drt_batch(batch, *, title: str | None = None):
    """γ(τ) of every spectrum of a `DRTBatchResult` on one axes, coloured in batch order
    (viridis); below, the same γ as a map over the spectra and τ with each spectrum's peaks
    (`gamma_map`: how the peaks move and grow along the series, as the KK test's map of a batch
    shows its residuals), and each DRT fit's rms_rel beside the rms_rel the noise alone gives,
    √2 × ``difference_noise``, red where it warns (marked with the spectra's labels)."""
    labels = [", ".join(f"{d}={drawn_label(v)}" for d, v in where.items()) for where in batch.labels()]
    n = len(batch.results)
    # (axes made in the order overlay, rms_rel, map: fig.axes[1] stays the rms_rel panel it was)
    fig = plt.figure(figsize=(8, 9), layout="constrained")
    grid = fig.add_gridspec(3, 1, height_ratios=[3, 2.2, 1])
    ax = fig.add_subplot(grid[0])
    ax_rms = fig.add_subplot(grid[2])
    ax_map = fig.add_subplot(grid[1], sharex=ax_rms)
    colours = plt.get_cmap("viridis")(np.linspace(0, 1, max(n, 2)))
    if n <= LEGEND_MAX:
        for i, (one, label) in enumerate(zip(batch.results, labels)):
            ax.semilogx(one.tau, one.gamma, color=colours[i], lw=1.2, label=f"{label}: {len(counted_peaks(one.peaks))} peak(s)")
        ax.legend(fontsize=font_size("legend", 8))
    else:  # one LineCollection, not a Line2D per spectrum (130 of them took most of the figure's time)
        from matplotlib.collections import LineCollection

        ax.set_xscale("log")
        ax.add_collection(LineCollection([np.column_stack([one.tau, one.gamma]) for one in batch.results], colors=colours[:n], linewidths=1.2))
        ax.autoscale_view()
        bar = fig.colorbar(plt.cm.ScalarMappable(norm=plt.Normalize(0, n - 1), cmap="viridis"), ax=ax)
        label_colour_bar(bar, [", ".join(drawn_label(v) for v in where.values()) for where in batch.labels()], batch.dims)
    # the measured τ window, shaded outside as `plot_drt` does (the union of the spectra's windows)
    lo = min(one.window[0] for one in batch.results)
    hi = max(one.window[1] for one in batch.results)
    tau_min = min(float(one.tau.min()) for one in batch.results)
    tau_max = max(float(one.tau.max()) for one in batch.results)
    ax.axvspan(tau_min, lo, color="0.9", lw=0, zorder=0)
    ax.axvspan(hi, tau_max, color="0.9", lw=0, zorder=0, label="outside measured range")
    ax.set_xlim(tau_min, tau_max)
    ax.set_xlabel("τ [s]")
    time_axis(ax.xaxis)
    ax.set_ylabel("γ [Ω]")
    prefixed_axis(ax.yaxis)
    ax.grid(alpha=0.3, which="both")
    mesh, (above, below) = gamma_map(ax_map, batch, (lo, hi))
    bar = fig.colorbar(mesh, ax=ax_map, extend={(True, True): "both", (True, False): "max", (False, True): "min"}.get((above, below), "neither"))
    bar.set_label("γ [Ω]" + ("\n(scale: the largest γ inside\nthe measured τ range)" if above or below else ""))
    prefixed_axis(bar.ax.yaxis)  # (in the overlay's prefix, γ [kΩ] up to 7.6: the bar read γ [Ω] up to 7000 beside it)
    # (above the map: inside, it covered the peaks below f_min, at the map's top)
    ax_map.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), fontsize=font_size("legend", 7), frameon=False, ncols=3)
    ax_map.tick_params(axis="x", labelbottom=False)
    # each fit's rms_rel beside what the noise alone gives, √2 × the first-difference noise (σ per
    # part; `DRTResult.misfits`), the spectra whose γ does not reproduce them in red, as the KK
    # batch figure sets rms_rel beside its noise estimate and marks the spectra not valid
    x = np.arange(n)
    rms = np.array([one.rms_rel for one in batch.results]) * 100
    noise = np.array([np.sqrt(2.0) * one.difference_noise for one in batch.results]) * 100
    bad = np.array([bool(one.misfits) for one in batch.results])
    ax_rms.plot(x, rms, "-", color="0.5", lw=0.8)
    ax_rms.plot(x[~bad], rms[~bad], "o", ms=3, color="tab:blue", label="rms_rel")
    if bad.any():
        ax_rms.plot(x[bad], rms[bad], "o", ms=4, color="tab:red", label="rms_rel beyond the noise (a warning)")
    if np.isfinite(noise).any():
        ax_rms.plot(x, noise, "--", color="0.3", lw=0.9, label="rms_rel of the noise alone (√2 × first-difference noise)", **({"marker": "_", "ms": 14, "mew": 1.2} if n == 1 else {}))
    ax_rms.set_yscale("log")
    rms_rel_ticks(ax_rms.yaxis)
    label_spectra_axis(ax_rms, [", ".join(drawn_label(v) for v in where.values()) for where in batch.labels()], batch.dims)
    ax_rms.set_ylabel("DRT fit rms_rel [%]")
    ax_rms.grid(alpha=0.3, which="both")
    ax_rms.legend(fontsize=font_size("legend", 7), ncols=3, loc="best")
    counts = [len(counted_peaks(one.peaks)) for one in batch.results]  # resolved, inside the measured τ window
    low, high = min(counts), max(counts)
    peaks = f"{low} peak{'' if low == 1 else 's'}" if low == high else f"{low}–{high} peaks"
    fig.suptitle(title or f"DRT of {counted(n, 'spectrum', 'spectra')} over {', '.join(batch.dims)}: {peaks} in the measured τ range (shaded: outside)")
    legends_off_data(fig)
    frame_points(ax_rms, np.concatenate([rms, noise]))  # (on the final layout: the short panel's 5 % margin left cycle 22's point at the frame)
    frame_spectra(ax_rms, n, maps=(ax_map,))
    return fig


def plot_zhit(result, *, title: str | None = None):
    """|Z| measured vs reconstructed from the phase, phase, and the |Z| residual with bad bands."""
    fig, (ax_mod, ax_ph, ax_res) = plt.subplots(3, 1, figsize=(7, 7), sharex=True, layout="constrained")
    order = np.argsort(result.frequency)
    f = result.frequency[order]
    ax_mod.loglog(f, np.abs(result.impedance[order]), "o", ms=3.5, mfc="none", label="|Z| data")
    ax_mod.loglog(f, result.modulus[order], "-", lw=1.5, label="|Z| from the phase (Z-HIT)")
    ax_mod.set_ylabel("|Z| [Ω]")
    magnitude_axis(ax_mod.yaxis, own_prefix=True)  # (in an SI prefix, as the fit and KK figures of the spectrum: mΩ for a battery)
    ax_ph.semilogx(f, np.degrees(np.angle(result.impedance[order])), "o", ms=3.5, mfc="none")
    ax_ph.set_ylabel("phase [deg]")
    ax_res.semilogx(f, result.residuals[order] * 100, "o-", ms=3, lw=0.8)
    ax_res.axhline(0, color="k", lw=0.6)
    for sign in (-1, 1):
        ax_res.axhline(sign * result.threshold * 100, color="tab:red", lw=0.7, ls="--")
    ax_res.set_ylabel("(|Z| − |Z|_ZHIT)/|Z| [%]")
    ax_res.set_xlabel("frequency [Hz]")
    frequency_axis(ax_res.xaxis)  # (shared: the |Z| and phase panels read so too)
    if residual_axis(ax_res, result.residuals):
        ax_res.legend(fontsize=font_size("legend", 8))
    for ax in (ax_mod, ax_ph, ax_res):
        ax.grid(alpha=0.3, which="both")
    ax_mod.legend(fontsize=font_size("legend", 8))
    if result.bad_bands:
        shade_bands([ax_mod, ax_ph, ax_res], result.bad_bands, label="inconsistent |Z| and phase")
    fig.suptitle(title or f"Z-HIT: {'valid' if result.valid else 'not valid'}, rms_rel {format_percent(result.rms_rel)}")  # (as the report: 119 %, not 1.2e+02 %)
    return fig
