"""Figures of the physical models: the gap analysis (`impedax.models.gap.GapAnalysis.plot`),
its force bands, and a force spectrum (`impedax force --plot`)."""

from __future__ import annotations

import numpy as np

from ..arguments import figure_size
from ..data import format_frequency, format_quantity
from . import font_size

MODEL_MARGIN = 10.0
"""How far [×] a model curve may extend the |Z_R| axis of `plot_gap_analysis` beyond the data."""


# the size [in] of `plot_gap_analysis`'s figure of three panels side by side
GAP_FIGSIZE = (15.0, 4.6)


def plot_gap_analysis(gap, *, true_gap: float | None = None, figsize: tuple[float, float] | None = None):
    """Remaining impedance with both fits, the posterior of u against the paper's bounds
    (and ``true_gap`` [m] when known, e.g. for synthetic data), and the force bands with and
    without the EP branch (matplotlib Figure). The states that void the result (``gap.alarms``:
    "MODEL DOES NOT FIT", "SAMPLING UNRELIABLE") head the figure in red."""
    import matplotlib.pyplot as plt

    from ..data import format_percent
    from . import frequency_axis, legends_off_data, magnitude_axis, model_curve

    fig, axes = plt.subplots(1, 3, figsize=figure_size(figsize, "figsize") or GAP_FIGSIZE, layout="constrained")
    f = gap.remaining["frequency"].values
    z = gap.remaining["Z"].values
    ax = axes[0]
    averaged = " (mean of trials)" if getattr(gap, "averages_trials", True) else " (one spectrum each)" if not getattr(gap, "single_contact", False) else " (one spectrum)"
    # (the data blue, the fitted model orange, the naive start grey dashed: the colours of every spectrum figure, `refine --plot`'s start)
    ax.loglog(f, np.abs(z), "o", mfc="none", ms=3.5, color="C0", label=("Z" if getattr(gap, "single_contact", False) else "Z_R") + averaged)
    if "sigma" in gap.remaining:
        s = gap.remaining["sigma"].values
        ax.fill_between(f, np.maximum(np.abs(z) - s, np.abs(z) * 0.05), np.abs(z) + s, color="0.8", label="± SEM")
    # the y-range follows the data: a model curve may widen it by at most MODEL_MARGIN on either
    # side, so a fit that ran away (C_gap = 1e125 F) is cut off instead of stretching the axis
    # over a hundred decades
    shown = np.abs(z)
    if "sigma" in gap.remaining:
        shown = np.concatenate([shown, np.maximum(np.abs(z) - s, np.abs(z) * 0.05), np.abs(z) + s])
    shown = shown[np.isfinite(shown) & (shown > 0)]
    data_low, data_high = (float(shown.min()), float(shown.max())) if shown.size else (None, None)
    low, high = data_low, data_high
    for fit, style, colour, label in ((gap.naive_fit, "--", "0.5", "C_gap only"), (gap.edl_fit, "-", "C1", gap.edl_fit.model)):
        f_model, z_model = model_curve(fit)
        mag = np.abs(z_model)
        within = mag[(mag >= data_low / MODEL_MARGIN) & (mag <= data_high * MODEL_MARGIN)] if data_low is not None else mag
        ax.loglog(f_model, mag, style, color=colour, label=f"{label} (rms_rel {format_percent(fit.rms_rel)})" + ("" if within.size else ", off the axis"))
        if data_low is not None and within.size:
            low, high = min(low, float(within.min())), max(high, float(within.max()))
    if data_low is not None:
        ax.set_ylim(low / 1.5, high * 1.5)
    single = getattr(gap, "single_contact", False)  # (nothing subtracted: the total is the contact's impedance)
    ax.set(xlabel="frequency [Hz]", ylabel="|Z| [Ω]" if single else "|Z_R| [Ω]", title="single contact: total, nothing subtracted" if single else "remaining impedance (Sirin eq 5)")
    magnitude_axis(ax.yaxis)  # (a labelled tick at or below the lowest |Z_R| and at or above the highest)
    frequency_axis(ax.xaxis)  # (1, 10, 100, 1000, 10k beside |Z_R|'s 1000, 10k, as every frequency axis; not 10⁰ … 10⁶)
    ax.legend(fontsize=font_size("legend", 7))
    ax = axes[1]
    u = gap.draws("u") * 1e6
    shown = np.concatenate([u, [gap.paper.gap * 1e6]])
    # (draws and the paper's estimate decades apart — a poor fit, a prior bound — on a log axis,
    # where a linear one squeezed the histogram into one bar at its edge)
    wide = bool(np.all(shown > 0) and shown.max() > 10 * shown.min())
    bins = np.geomspace(u.min(), u.max(), 61) if wide and u.max() > u.min() else 60
    ax.hist(u, bins=bins, density=not wide, color="tab:blue", alpha=0.7, label="posterior of u" + (" (population median)" if gap.method == "hierarchical" else ""))
    if wide:
        ax.set_xscale("log")
    g = gap.gap
    ax.axvspan(g["q05"] * 1e6, g["q95"] * 1e6, color="tab:blue", alpha=0.15, label="90 % credible interval")
    # (the lengths in the SI prefix of their size, as the report gives them: a paper method's 504 pm read "0.00 µm")
    ax.axvline(gap.paper.gap * 1e6, color="k", label=f"paper method {format_quantity(gap.paper.gap, 'm', 4)}")
    if gap.paper_has_bounds:  # (one trial of each: no interval)
        ax.axvspan(gap.paper.gap_lower * 1e6, gap.paper.gap_upper * 1e6, color="tab:orange", alpha=0.15, label="paper bounds (extreme impedances)" + ("; NO interval for u: see the warning" if getattr(gap, "paper_bounds_no_interval", False) else ""))
    if true_gap is not None:
        ax.axvline(true_gap * 1e6, color="tab:green", ls="--", label=f"truth (synthetic) {format_quantity(true_gap, 'm', 4)}")
    identified = getattr(gap, "gap_identified", True)
    bounded = getattr(gap, "gap_lower_bound", None) is not None
    if bounded:  # only C_EP + C_gap is determined: u ≥ the bound, the histogram is the priors'
        bound = gap.gap_lower_bound * 1e6
        ax.axvline(bound, color="tab:red", lw=2, label=f"lower bound u ≥ {bound:.3g} µm (all that the data give)")
        ax.axvspan(bound, ax.get_xlim()[1], color="tab:red", alpha=0.06)
    title = ("air-gap thickness" if identified else "air-gap thickness: NOT determined (lower bound only)" if bounded
             else "air-gap thickness: NOT determined (no bound: the model misfits)" if getattr(gap, "gap_bound_withheld", None) is not None
             else "air-gap thickness: NO AIR GAP (see the heading)")
    # (the density of u in µm: its bars' areas sum to 1 over the axis in µm; not "density" alone)
    ax.set(xlabel="gap thickness u [µm]", ylabel="draws" if wide else "probability density [1/µm]", title=title)
    ax.legend(fontsize=font_size("legend", 7))
    ax = axes[2]
    unit = _force_axis(ax, gap.force, ep_label="with EP branch", alpha=0.2, suffix="median, 90 % band")
    ax.set(xlabel="frequency [Hz]", ylabel=f"peak force F_e [{unit}]", title=f"electrostatic force, V0 = {gap.v0:.4g} V (Sirin eq 1, peak)" + _force_title_note(gap))
    _legend(ax, _gap_voltage_axis(ax, gap.force), font_size("legend", 7))
    for a in axes:
        a.grid(alpha=0.3, which="both")
    alarms = getattr(gap, "alarms", ())
    if alarms:  # (the report's first lines: the whole figure rests on them, as on the text)
        import textwrap

        fig.suptitle("\n".join(line for alarm in alarms for line in textwrap.wrap(alarm, 150)), color="tab:red", fontweight="bold", fontsize=font_size("title", 10))
    legends_off_data(fig)  # (u's legend lay over its posterior's bars on REAL data.dfr, whose draws fill the panel)
    return fig


def _force_title_note(gap) -> str:
    """The force panel's second title line when u is not determined: the bands then come from
    u set by the priors (``--ep C``: from the summed capacitance's gap), and the data bound the
    force only from above, at u's lower bound (`GapAnalysis.force_upper_bound`), or not at all."""
    if getattr(gap, "gap_identified", True):
        return ""
    bound = getattr(gap, "force_upper_bound", None)
    limit = f"F ≤ {format_quantity(float(bound.max()), 'N')} at u's lower bound" if bound is not None else "no bound"
    return f"\nNOT determined (u is not): {limit}"


def force_unit(force_n) -> tuple[float, str]:
    """(scale [N], unit) to draw forces [N] in: the SI prefix of their largest finite value
    (`impedax.data.si_prefix`: 6.7 N in N, 0.35 N in mN); mN when there is none."""
    from ..data import si_prefix

    values = np.abs(np.asarray(force_n, dtype=np.float64))
    values = values[np.isfinite(values) & (values > 0)]
    if not values.size:
        return 1e-3, "mN"
    scale, prefix = si_prefix(float(values.max()))
    return scale, f"{prefix}N"


FORCE_LOG_SPAN = 100.0
"""The force axes of the gap analysis' figures (`_force_axis`: the gap figure's force panel, the
demo's force figure) count in N, their ticks SI-prefixed (1p … 1), when the force's 90 % band and
median span more than this factor (`force_span`); else in the SI prefix of the largest force (mN).
On REAL data.dfr (no air gap) the band reaches from pN to 6.6 N: in mN its ticks would read
"1n" of a mN."""


def force_span(force) -> float:
    """The largest over the smallest positive, finite value of the force bands' ``q05``,
    ``median`` and ``q95`` [N] (1 when there are none)."""
    values = np.concatenate([np.ravel(force[k].values) for k in ("q05", "median", "q95")]).astype(float)
    values = values[np.isfinite(values) & (values > 0)]
    return float(values.max() / values.min()) if values.size else 1.0


def _force_bands(ax, force, *, ep_label: str, scale: str, alpha: float, suffix: str, in_newtons: bool = False) -> str:
    """Median and 90 % band of the force [N] with and without the EP branch, drawn in the unit
    of `force_unit` (``in_newtons``: in N, for a log axis whose ticks carry their own prefixes;
    returned, for the axis label)."""
    ff = force["frequency"].values
    unit_scale, unit = (1.0, "N") if in_newtons else force_unit(force["q95"].values)
    for branch, color, label in (("with_ep", "tab:blue", ep_label), ("without_ep", "tab:red", "without EP (C_gap only)")):
        band = force.sel(branch=branch)
        ax.fill_between(ff, band["q05"] / unit_scale, band["q95"] / unit_scale, color=color, alpha=alpha)
        getattr(ax, scale)(ff, band["median"] / unit_scale, color=color, label=f"{label}: {suffix}")
    return unit


def _force_axis(ax, force, *, ep_label: str, alpha: float, suffix: str) -> str:
    """The force bands (`_force_bands`) on ``ax`` over log frequency (`frequency_axis`: 1, 10,
    100, 1000, 10k), on a log force axis with
    plain tick labels (`plain_log_ticks`: 40, 60, 100, 200 in mN), in N beyond `FORCE_LOG_SPAN`;
    linear when no force is positive. The gap figure's force panel and the demo's force figure
    (`plot_force_bands`) draw the force alike: the force falls by a decade or more over the band
    (Sirin's finger: 395 mN at 1 Hz to 35 mN at 1 MHz), which a linear axis drew as a curve
    pressed to its floor above 10 kHz beside the other figure's log axis. Returns the unit."""
    from . import frequency_axis, plain_log_ticks

    values = np.concatenate([np.ravel(force[k].values) for k in ("q05", "median", "q95")]).astype(float)
    positive = bool(np.any(np.isfinite(values) & (values > 0)))
    wide = force_span(force) > FORCE_LOG_SPAN
    unit = _force_bands(ax, force, ep_label=ep_label, scale="loglog" if positive else "semilogx", alpha=alpha, suffix=suffix, in_newtons=wide)
    if positive:
        plain_log_ticks(ax.yaxis)
    frequency_axis(ax.xaxis)  # (1, 10, 100, 1000, 10k, as the force axis and every frequency axis read)
    return unit


def _gap_voltage_axis(ax, force):
    """The gap voltage's amplitude |ΔV_gap| [V] (medians, dotted, with and without the EP branch)
    on a twin axis at the right of the force axis ``ax``; None when ``force`` has no gap voltage."""
    if "gap_voltage_median" not in force:
        return None
    twin = ax.twinx()
    ff = force["frequency"].values
    for branch, color, label in (("with_ep", "tab:blue", "with EP"), ("without_ep", "tab:red", "without EP")):
        twin.plot(ff, force.sel(branch=branch)["gap_voltage_median"].values, ":", color=color, lw=1.5, label=f"gap voltage |ΔV_gap| {label} (median, right axis)")
    twin.set_ylabel("gap voltage |ΔV_gap| [V] (amplitude, dotted)")
    twin.set_ylim(bottom=0)
    return twin


def _legend(ax, twin, size) -> None:
    """One legend on ``ax`` for its curves and those of its twin axis (if any)."""
    handles, labels = ax.get_legend_handles_labels()
    if twin is not None:
        more = twin.get_legend_handles_labels()
        handles, labels = handles + more[0], labels + more[1]
    ax.legend(handles, labels, fontsize=size)


def plot_force_bands(gap):
    """The force on the finger with and without the EP branch, median and 90 % bands, for a
    `GapAnalysis` (the demo's last figure)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.8), layout="constrained")
    # (60, 200, 400 as the other log axes read, where matplotlib wrote 6×10¹, 2×10², 4×10²; the gap figure's force panel alike)
    unit = _force_axis(ax, gap.force, ep_label="with electrode polarization (refined model)", alpha=0.25, suffix="median and 90 % band")
    ax.set(xlabel="frequency [Hz]", ylabel=f"electrostatic force [{unit}] (peak, Sirin eq 1)", title=f"Force on the finger for V0 = {gap.v0:g} V (Sirin Fig 2f story; SYNTHETIC data)")
    ax.grid(alpha=0.3, which="both")
    _legend(ax, _gap_voltage_axis(ax, gap.force), font_size("legend", 8))
    return fig


def plot_force_spectrum(freq, force, *, title: str, convention: str = "time-average", peak=None, subtitle: str = "", notes=()):
    """Force [N] against frequency [Hz], drawn in the SI prefix of its largest value (`force_unit`); ``convention`` ("time-average" or
    "peak") labels the axis. ``peak``: a mapping with ``frequency_hz``, ``force_n``,
    ``at_band_edge`` and, optionally, ``band_edge`` (`impedax force`'s JSON ``peak``), marked on
    the curve. ``subtitle``
    (e.g. the drive and the parameters changed from the paper's) goes under the title, and
    ``notes`` (warnings) under the axes, in red. A force ≥ 0 everywhere is drawn from zero."""
    import textwrap

    import matplotlib.pyplot as plt

    from . import characters_across, frequency_axis

    fig, ax = plt.subplots(figsize=(6, 4))
    # in the SI prefix of the largest force (`force_unit`): Vezzoli's model with a thin layer
    # would otherwise draw 14,000 mN in mN
    unit_scale, unit = force_unit(force)
    ax.semilogx(freq, np.asarray(force) / unit_scale, marker="o" if np.size(freq) < 3 else None)
    frequency_axis(ax.xaxis)
    # a force of one sign is drawn from zero, so that the axis shows its size: over a narrow band
    # (Vezzoli's eq 10 at 10–50 kHz, 74.44–74.49 mN) an autoscaled axis would draw a change of
    # 0.07 % as a steep rise across the whole panel
    largest = float(np.max(np.asarray(force))) / unit_scale if np.size(force) else 0.0
    if np.all(np.asarray(force) >= 0) and np.isfinite(largest):
        ax.set_ylim(bottom=0.0, top=max(ax.get_ylim()[1], 1.05 * largest) if largest > 0 else 1.0)
    if peak is not None:
        value, where = format_quantity(float(peak["force_n"]), "N", 4), format_frequency(float(peak["frequency_hz"]))
        # (as `impedax force` says it: one frequency and a flat force have no peak, nor a band's end it rises past)
        label = {"fmin=fmax": f"one frequency (no peak located): {value} at {where}", "flat": f"no peak: {value} at every frequency"}.get(
            peak.get("band_edge"), ("largest at the band's end" if peak["at_band_edge"] else "peak") + f": {value} at {where}")
        ax.plot([peak["frequency_hz"]], [peak["force_n"] / unit_scale], "v", color="C3", label=label)
        ax.legend(fontsize=font_size("legend", 8))
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel(("peak" if convention == "peak" else "time-averaged") + f" force [{unit}]")
    ax.grid(True, which="both", alpha=0.3)
    # title and notes wrapped to the figure's width, 6.5 in with notes (at 95 characters Meyer's
    # CPE subtitle ran off the right edge, "...(C_sc of eq 3.13 at 1 kH")
    width = 6.5 if notes else 6.0
    wrapped = lambda text, size: textwrap.wrap(text, characters_across(width - 0.4, size), break_on_hyphens=False)  # noqa: E731
    if not subtitle and not notes:
        ax.set_title("\n".join(wrapped(title, font_size("title", 12))))
        fig.tight_layout()
        return fig
    size = font_size("title", 8.5)
    ax.set_title("\n".join(wrapped(title, size) + wrapped(subtitle, size)), fontsize=size)
    lines = [line for note in notes for line in wrapped(f"warning: {note}", font_size("text", 6.5))]
    if lines:
        fig.set_size_inches(6.5, 4.4 + 0.16 * len(lines))
        fig.text(0.01, 0.01, "\n".join(lines), fontsize=font_size("text", 6.5), color="C3", ha="left", va="bottom")
    fig.tight_layout(rect=(0, 0.14 * len(lines) / fig.get_size_inches()[1] + (0.03 if lines else 0), 1, 1))
    return fig
