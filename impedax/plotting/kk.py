"""Figures of the Kramers–Kronig test (`impedax.fitting.kk.KKResult.plot`) and the rule levels
drawn on Z-HIT's residuals (`impedax.fitting.zhit.ZHITResult.plot`)."""

from __future__ import annotations

import numpy as np
from matplotlib.transforms import blended_transform_factory

from ..data import format_percent
from . import dense_model, drawn_label, drawn_points, font_size, label_bode_above_residuals, legends_off_data, nyquist_shape, plot_bode, plot_nyquist, plot_residuals, refresh_legend, shade_bands, spectrum_layout


def plot_kk(result, *, title: str | None = None):
    """Nyquist and Bode of data vs KK fit, and the residuals Δ', Δ'' and |Δ| [%] vs frequency
    with the levels of the point and run rules (both test |Δ|) and the bad bands shaded, each
    named by the rules that flagged it, for a `KKResult`. Returns a matplotlib Figure."""
    data, model = (result.frequency, result.impedance), dense_model(result.frequency, result.kk_impedance, getattr(result, "predict", None))
    shape = nyquist_shape(data, model)
    fig, (ax_nyq, ax_mod, ax_ph, ax_res) = spectrum_layout(shape, True)
    plot_nyquist(ax_nyq, data, model, model_label=f"KK fit (M={result.n_rc})")
    plot_bode(ax_mod, ax_ph, data, model, model_label=f"KK fit (M={result.n_rc})", nyquist=ax_nyq)
    plot_residuals(ax_res, result.frequency, result.residuals_real, result.residuals_imag, labels=("Δ re", "Δ im"), ylabel="KK residual (Z − Z_kk)/|Z| [%]")
    order = np.argsort(result.frequency)
    magnitude = np.hypot(result.residuals_real, result.residuals_imag)[order]
    # (plot, not semilogx, on the log axis plot_residuals made: semilogx sets the scale again,
    # and with it matplotlib's 10ⁿ labels in place of `frequency_axis`')
    ax_res.plot(result.frequency[order], magnitude * 100, "-", color="0.25", lw=1.0, label="|Δ| (the rules test it)")
    label_bode_above_residuals(shape, ax_mod, ax_ph)
    if result.bad_bands:
        shade_bands([ax_mod, ax_ph, ax_res], result.bad_bands, label="not KK-consistent")
    levels = result.rule_levels
    t = result.thresholds
    # (judged by the data's σ: each point's own levels, t·σ/|Z|)
    per_point = None if getattr(result, "point_scale", None) is None else (result.frequency[order], result.point_scale[order] * t["point"], result.point_scale[order] * t["run"])
    verdict = "valid" if result.valid else "not valid"
    fig.suptitle(title or f"linear KK test: {verdict}, rms_rel {format_percent(result.rms_rel)}, µ {result.mu:.3f}")  # (µ to the report's 3 decimals: 0.847 read "0.85", the cut-off c it lies below; before the legend is placed off the labels on the final layout)
    # (last: it places the figure's legends off the data, `legends_off_data`)
    add_rule_levels(ax_res, point=levels["point"], run=levels["run"], run_length=int(t["run_length"]), bands=result.bad_bands, band_rules=result.band_rules, per_point=per_point)
    return fig


# where a band's rule label hangs from [axes fraction], and the room kept under it
# (`room_for_band_labels`) [× its font size]: a label of 7 pt with its box and a gap
BAND_LABEL_TOP = 0.97
BAND_LABEL_ROOM_EM = 2.0


def room_for_band_labels(ax, fontsize: float) -> None:
    """Raise the top of ``ax``'s y range so that every curve stays below the bands' rule labels
    hung from its top (`BAND_LABEL_TOP`, `BAND_LABEL_ROOM_EM` of ``fontsize`` [pt] under
    them): the KK test's |Δ| at 3.9 % ran behind "point + run + window rule" on a range to 4.66 %.
    The panel's height is taken before the layout shrinks it, so the room is a little larger
    than needed, never smaller. Nothing is clipped: the range already holds every curve."""
    low, high = ax.get_ylim()
    top = ax.dataLim.y1
    height_pt = ax.get_position().height * ax.get_figure().get_figheight() * 72.0
    if not (np.isfinite(top) and high > low and height_pt > 0):
        return
    free = BAND_LABEL_TOP - BAND_LABEL_ROOM_EM * fontsize / height_pt  # (the highest axes fraction a curve may reach)
    if free <= 0.5:  # (a panel too small for the labels: as it was)
        return
    needed = low + (top - low) / free
    if needed > high:
        ax.set_ylim(low, needed)


def add_rule_levels(ax, *, point: float, run: float, run_length: int, bands=(), band_rules=(), signed: bool = False, per_point=None) -> None:
    """Draw the level of the point rule and of the run rule (fractions, drawn in %) on a residual
    axis — at ± when the residual drawn is itself the signed quantity the rules test (``signed``,
    Z-HIT), above zero only when they test a magnitude (|Δ| of the KK test) — and write over each
    of ``bands`` the rules (``band_rules``) that flagged it. ``per_point``: (frequencies, point
    levels, run levels), each point's own levels (a KK test judged by the data's σ), drawn as
    curves in place of ``point`` and ``run``. Last, every legend of the figure that covers data
    goes above its panel (`legends_off_data`), the KK and the Z-HIT figure alike: the residual
    legend's least covering place lay over REAL Parstat's Δ at 60 Hz – 10 kHz (its −40 % at
    10 kHz) and Gamry's residuals and rule levels at 1 – 200 kHz, and on the Z-HIT figure of REAL
    exampleData.csv over the point rule's line at +5.02 %."""
    signs = (-1, 1) if signed else (1,)
    what = "|residual|" if signed else "|Δ|"
    if per_point is not None:
        f, point_levels, run_levels = (np.asarray(a, float) for a in per_point)
        # (plot on the log frequency axis of the panel: semilogx would reset its `frequency_axis` labels)
        ax.plot(f, point_levels * 100, color="tab:red", lw=0.7, ls="--", label=f"point rule: {what} > its level (from σ)")
        ax.plot(f, run_levels * 100, color="tab:orange", lw=0.8, ls=":", label=f"run rule: ≥ {run_length} in a row > their level (from σ)")
        point, run, signs = np.nan, np.nan, ()
    for sign in signs:
        ax.axhline(sign * point * 100, color="tab:red", lw=0.7, ls="--", label=f"point rule: {what} > {point * 100:.3g} %" if sign > 0 else None)
    if np.isfinite(run):
        for sign in signs:
            ax.axhline(sign * run * 100, color="tab:orange", lw=0.8, ls=":", label=f"run rule: ≥ {run_length} in a row > {run * 100:.3g} %" if sign > 0 else None)
    on_top = blended_transform_factory(ax.transData, ax.transAxes)
    named = [(lo, hi, rules) for (lo, hi), rules in zip(bands, band_rules) if rules]
    labels = []
    for lo, hi, rules in named:
        labels.append(ax.text(float(np.sqrt(lo * hi)), BAND_LABEL_TOP, " + ".join(rules) + " rule", transform=on_top, ha="center", va="top", fontsize=font_size("text", 7), color="tab:red",
                bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": "none", "alpha": 0.8}))
    if named:
        room_for_band_labels(ax, font_size("text", 7))
    if ax.get_legend() is None:
        ax.legend(fontsize=font_size("legend", 8), ncol=2)
    else:
        refresh_legend(ax)
    if labels:
        legend_clear_of(ax, labels)
    legends_off_data(ax.get_figure())


# the places `legend_clear_of` tries, in turn
LEGEND_PLACES = ("lower right", "lower left", "lower center", "center right", "center left", "upper right", "upper left", "center")


def legend_clear_of(ax, texts) -> None:
    """Move ``ax``'s legend off ``texts`` (the bands' rule labels): matplotlib's "best" spot
    avoids lines, not texts, and the KK legend sat on "point + run + window rule" once the range
    made room for it (`room_for_band_labels`). The first of `LEGEND_PLACES` that overlaps none
    and covers the fewest drawn points (`drawn_points`), fixed (a "best" spot chosen anew at the
    next draw could land on them again)."""
    legend = ax.get_legend()
    if legend is None:
        return
    fig = ax.get_figure()
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer).expanded(1.1, 1.5) for t in texts]  # (a margin: the layout may still move them a little)
    points = drawn_points(ax)
    best = None
    for place in LEGEND_PLACES:
        legend.set_loc(place)
        box = legend.get_window_extent(renderer)
        if any(box.overlaps(b) for b in boxes):
            continue
        covered = int(np.sum((points[:, 0] >= box.x0) & (points[:, 0] <= box.x1) & (points[:, 1] >= box.y0) & (points[:, 1] <= box.y1)))
        if best is None or covered < best[0]:
            best = (covered, place)
    legend.set_loc(best[1] if best else "best")


def plot_validity_batch(batch, magnitudes, *, residual: str, title: str):
    """A validity test of every spectrum of a batch (`KKBatchResult`, `ZHITBatchResult`): its
    residual magnitude ``magnitudes`` (spectra × frequency, fractions of |Z|) as a map over the
    spectra (x, in batch order, marked with their labels) and frequency (y, log), each flagged
    point circled, and each spectrum's rms_rel and noise estimate below, the spectra not valid in
    red; ``residual``: what the magnitudes are, for the colour bar. Where a measurement went
    wrong across a series (a spike at one frequency in many cycles, a drifting end) shows at a
    glance, where the text gives a line per spectrum."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    from . import frame_points, frame_spectra, frequency_axis, frequency_cell_edges, label_spectra_axis, labelled_log_ticks, plain_log_ticks
    from .fit import MAP_VECTOR_CELLS

    results = batch.results
    n = len(results)
    freq = np.asarray(results[0].frequency, float)
    order = np.argsort(freq)
    f = freq[order]
    values = np.asarray(magnitudes, float)[:, order] * 100
    f_edges = frequency_cell_edges(f)
    x_edges = np.arange(n + 1) - 0.5
    fig, (ax_map, ax_rms) = plt.subplots(2, 1, figsize=(8, 6.5), height_ratios=[3, 1.3], sharex=True, layout="constrained")
    positive = values[np.isfinite(values) & (values > 0)]
    low = max(float(positive.min()), 1e-3) if positive.size else 1e-3
    high = max(float(positive.max()), low * 10) if positive.size else 1.0
    mesh = ax_map.pcolormesh(x_edges, f_edges, np.clip(values, low, high).T, norm=LogNorm(low, high), cmap="magma_r", shading="flat", rasterized=values.size > MAP_VECTOR_CELLS)
    bar = fig.colorbar(mesh, ax=ax_map)
    bar.set_label(f"{residual} [%]")
    plain_log_ticks(bar.ax.yaxis)
    flagged = np.array([np.asarray(r.flagged, bool)[order] for r in results])
    spectra, points = np.nonzero(flagged)
    if spectra.size:
        ax_map.scatter(spectra, f[points], s=18, facecolors="none", edgecolors="tab:cyan", linewidths=1.0, label=f"flagged ({spectra.size} point{'' if spectra.size == 1 else 's'})")
        ax_map.legend(loc="upper right", fontsize=font_size("legend", 8), framealpha=0.85)
    ax_map.set_yscale("log")
    ax_map.set_ylim(f_edges[0], f_edges[-1])
    ax_map.set_ylabel("frequency [Hz]")
    frequency_axis(ax_map.yaxis)
    rms = np.array([r.rms_rel for r in results]) * 100
    noise = np.array([r.noise_estimate for r in results]) * 100
    bad = np.array([r.conclusive and not r.valid for r in results])
    x = np.arange(n)
    ax_rms.plot(x, rms, "-", color="0.5", lw=0.8)
    ax_rms.plot(x[~bad], rms[~bad], "o", ms=3, color="tab:blue", label="rms_rel, valid")
    if bad.any():
        ax_rms.plot(x[bad], rms[bad], "o", ms=4, color="tab:red", label="rms_rel, not valid")
    # (one spectrum: a dash as marker, where a dashed line through one point draws nothing: the
    # noise estimate of a SYNTHETIC batch of one had a legend entry and no mark)
    ax_rms.plot(x, noise, "--", color="0.3", lw=0.9, label="noise estimate", **({"marker": "_", "ms": 14, "mew": 1.2} if n == 1 else {}))
    ax_rms.set_yscale("log")
    ax_rms.set_ylabel("rms_rel, noise [%]")
    # (two labels or more at any range, `labelled_log_ticks`: matplotlib's ticks read the REAL
    # battery cycles' 0.11–0.32 % as 0.2 and 0.3 alone, none by the noise curve; with the noise
    # curve in the frame, 0.07–0.6 %, the panel reads 0.1, 0.2, 0.5)
    labelled_log_ticks(ax_rms.yaxis)
    ax_rms.grid(alpha=0.3, which="both")
    ax_rms.legend(fontsize=font_size("legend", 7), ncols=3, loc="best")
    label_spectra_axis(ax_rms, [", ".join(drawn_label(v) for v in where.values()) for where in batch.labels()], batch.dims)
    fig.suptitle(title)
    # (a legend over a flagged circle goes above its panel: "flagged (280 points)" in the upper
    # right hid the REAL battery cycles' 6.2–9.9 kHz flags of cycles 92, 112 and 116)
    legends_off_data(fig)
    frame_points(ax_rms, np.concatenate([rms, noise]))  # (as the DRT batch figure's rms_rel panel)
    frame_spectra(ax_rms, n, maps=(ax_map,))
    return fig
