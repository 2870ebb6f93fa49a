"""Figures of a Bayesian fit: data with posterior predictive bands, and the corner plot.

The functions take arrays (what `Posterior.plot` and `Posterior.corner` hand over), never a
sampler, and return a matplotlib `Figure`; nothing is shown or saved implicitly.
"""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np

from ..arguments import count, figure_size, literal_text, real, shown, unknown_parameter
from ..data import format_quantity, si_prefix, unit_text
from ..errors import ParameterError
from . import characters_across, font_size, frequency_axis, legends_off_data, magnitude_axis, nyquist_view, nyquist_shape, plain_linear_ticks, plain_log_ticks, prefixable_unit, prefixed_axis, spectrum_layout

__all__ = ["plot_posterior_bands", "plot_joint_posterior_bands", "plot_corner", "plot_trace"]

BAND_QUANTILES = (0.05, 0.16, 0.5, 0.84, 0.95)

# the data and the model wear the colours of every other figure of a spectrum (`plot_spectrum`:
# data blue open circles, model orange), so that `impedax sample --plot` beside `impedax fit
# --plot` of one file reads the same; the predictive band, noise added, is dashed grey
DATA_COLOUR, MODEL_COLOUR, PREDICTIVE_COLOUR = "C0", "C1", "0.35"


def plot_posterior_bands(frequency, z_data, model_frequency, z_draws, *, title: str, n_lines: int = 40, z_predictive=None, figsize=None):
    """Data (``frequency`` [Hz], ``z_data`` [Ω]) with the model's draws ``z_draws`` (draws,
    ``model_frequency``): Nyquist with ``n_lines`` draws as thin lines and the median, and Bode
    |Z| and phase with the 68 % and 90 % credible bands; ``z_predictive`` (draws with the noise
    added, same shape) adds the 90 % posterior predictive band as dashed lines. ``figsize``
    (width, height) [in]: the figure's size (`spectrum_layout`)."""
    n_lines = count(0)(n_lines, "n_lines")
    f, zs, z = np.asarray(model_frequency, float), np.asarray(z_draws, complex), np.asarray(z_data, complex)
    fig, (ax_nyq, ax_mod, ax_ph, _) = spectrum_layout(nyquist_shape((frequency, z), (f, _median(zs))), False, figsize=figsize)
    _draw_bands((ax_nyq, ax_mod, ax_ph), frequency, z, f, zs, z_predictive, n_lines)
    ax_nyq.set_title("Nyquist")
    ax_ph.set_xlabel("frequency [Hz]")
    ax_nyq.legend(fontsize=font_size("legend", 8))
    ax_mod.legend(fontsize=font_size("legend", 8))
    fig.suptitle(title)
    return fig


def plot_joint_posterior_bands(frequency, z_data, labels: Sequence[str], model_frequency, z_draws, *, title: str, n_lines: int = 40, z_predictive=None, figsize=None):
    """`plot_posterior_bands` for several spectra of one joint posterior: one row per spectrum
    (``labels``, e.g. "trial=3"), Nyquist, |Z| and phase side by side, the frequency axes shared
    down each column. ``z_data`` (spectrum, frequency); ``z_draws`` and ``z_predictive``
    (spectrum, draws, ``model_frequency``). A legend that covers data goes out of its panel
    (`legends_off_data`)."""
    n_lines, figsize = count(0)(n_lines, "n_lines"), figure_size(figsize, "figsize")
    f, zs, z = np.asarray(model_frequency, float), np.asarray(z_draws, complex), np.asarray(z_data, complex)
    zp = None if z_predictive is None else np.asarray(z_predictive, complex)
    rows = len(labels)
    fig, axes = plt.subplots(rows, 3, figsize=figsize or (12.0, 0.6 + 2.5 * rows), layout="constrained", squeeze=False, gridspec_kw={"width_ratios": [1, 1.2, 1.2]})
    for i, label in enumerate(labels):
        ax_nyq, ax_mod, ax_ph = axes[i]
        if i:
            ax_mod.sharex(axes[0, 1])
            ax_ph.sharex(axes[0, 2])
        _draw_bands((ax_nyq, ax_mod, ax_ph), frequency, z[i], f, zs[i], None if zp is None else zp[i], n_lines)
        ax_nyq.set_title(literal_text(label), loc="left", fontsize=font_size("title", 10))
    for ax in axes[-1, 1:]:
        ax.set_xlabel("frequency [Hz]")
    axes[0, 0].legend(fontsize=font_size("legend", 8))
    axes[0, 1].legend(fontsize=font_size("legend", 8))
    fig.suptitle(title)
    legends_off_data(fig)  # (a |Z| panel 2.5 in tall has no free corner for five entries: the demo's trials lay under them from 1 Hz to 2 kHz)
    return fig


def _median(zs: np.ndarray) -> np.ndarray:
    """The median curve of complex draws (draws, frequency): Re and Im apart."""
    return np.median(zs.real, axis=0) + 1j * np.median(zs.imag, axis=0)


def _draw_bands(axes, frequency, z, f, zs, z_predictive, n_lines: int) -> None:
    """One spectrum's data ``z`` at ``frequency`` and its posterior draws ``zs`` (draws, ``f``)
    on (Nyquist, |Z|, phase) ``axes``: ``n_lines`` draws and the median on the Nyquist panel,
    the 68 % and 90 % credible bands and the median on the Bode panels, and the 90 % posterior
    predictive band of ``z_predictive`` (None: none) as dashed lines."""
    ax_nyq, ax_mod, ax_ph = axes
    med = _median(zs)
    for k in np.linspace(0, zs.shape[0] - 1, min(n_lines, zs.shape[0])).astype(int):
        ax_nyq.plot(zs[k].real, -zs[k].imag, "-", color=MODEL_COLOUR, alpha=0.08, lw=0.8)
    ax_nyq.plot(med.real, -med.imag, "-", color=MODEL_COLOUR, lw=1.5, label="posterior median")
    ax_nyq.plot(z.real, -z.imag, "o", ms=3.5, mfc="none", color=DATA_COLOUR, label="data")
    ax_nyq.set(xlabel="Z' [Ω]", ylabel="−Z'' [Ω]")
    nyquist_view(ax_nyq, z, med, frequency=frequency, frame="drawn")  # (over every draw: a frame that follows the data would cut the posterior's spread)
    zp = None if z_predictive is None else np.asarray(z_predictive, complex)
    for ax, values, data_values, transform in ((ax_mod, np.abs(zs), np.abs(z), np.abs), (ax_ph, np.degrees(np.angle(zs)), np.degrees(np.angle(z)), lambda v: np.degrees(np.angle(v)))):
        if zp is not None:
            qp = np.quantile(transform(zp), [0.05, 0.95], axis=0)
            ax.plot(f, qp[0], "--", color=PREDICTIVE_COLOUR, lw=1.0, label="90 % predictive (model + noise)")
            ax.plot(f, qp[1], "--", color=PREDICTIVE_COLOUR, lw=1.0)
        q = np.quantile(values, BAND_QUANTILES, axis=0)
        ax.fill_between(f, q[0], q[4], color=MODEL_COLOUR, alpha=0.18, lw=0, label="90 % band")
        ax.fill_between(f, q[1], q[3], color=MODEL_COLOUR, alpha=0.35, lw=0, label="68 % band")
        ax.plot(f, q[2], "-", color=MODEL_COLOUR, lw=1.2, label="median")
        ax.plot(frequency, data_values, "o", ms=3.5, mfc="none", color=DATA_COLOUR, label="data")
        frequency_axis(ax.xaxis)
    ax_mod.set(yscale="log", ylabel="|Z| [Ω]")
    magnitude_axis(ax_mod.yaxis, nyquist=ax_nyq)
    ax_ph.set(ylabel="phase [deg]")
    for ax in axes:
        ax.grid(alpha=0.3, which="both")


# a log-sampled parameter whose draws span more than this factor (1st to 99th percentile) is
# drawn on a log axis; a narrower one on a linear axis in its own unit, where log10 R0 from
# 1.7975 to 1.81 hid 63.6 Ω
LOG_AXIS_SPAN = 10.0

# a column's view: the central `TAIL_VIEW_MASS` of its draws (in log where its axis is log),
# widened by `TAIL_VIEW_MARGIN` of that span each side, where every draw would span more than
# `TAIL_VIEW_FACTOR` times it: a few far draws squeezed REAL exampleData.csv's CPE2.Q (R0 + R1 ∥ CPE1
# + R2 ∥ CPE2, 72 000 draws, 90 % within 0.20–0.55 kF s^(α-1)) into the quarter of an axis to 1.95;
# a Gaussian's extremes (±4.4 sd in 72 000 draws) span 1.7× its central 99 % (±2.58 sd): not cut
TAIL_VIEW_MASS = 0.99
TAIL_VIEW_FACTOR = 2.0
TAIL_VIEW_MARGIN = 0.1

# the units of a dimensionless parameter (a CPE's α, sigma_rel), whose log axis writes no SI
# prefix on a tick: α over decades was ticked "1µ, 10µ, 100µ, 0.001"
DIMENSIONLESS = ("", "1")

# a corner plot's panel side [in] (`corner_figure_size`): 2 in up to 7 parameters; more share
# 16 in down to 1.5 in each, and beyond 10 the figure grows, 1.5 in a panel (20 parameters on
# 16 in left 0.8 in a panel, their labels overprinted and run together)
CORNER_PANEL_IN = 2.0
CORNER_MIN_PANEL_IN = 1.5
CORNER_SHARED_IN = 16.0

# the most parameters a corner plot draws by default (`SharedPosterior.corner`: beyond it, the
# shared parameters, the first spectrum's and the noise's)
CORNER_MAX_PARAMS = 10


def plot_corner(
    draws,
    names: Sequence[str],
    log_scale: Sequence[bool],
    *,
    units: Sequence[str] | None = None,
    truths: Mapping[str, float] | None = None,
    bins: int = 30,
    max_points: int = 4000,
    title: str = "posterior",
    params: Sequence[str] | None = None,
):
    """Corner plot of ``draws`` (…, param) named ``names``: marginal histograms on the diagonal,
    titled with the median and the 90 % interval (5/50/95 % lines), and pairwise scatter
    below it, all in the parameters' own units (``units``, the element specs' spelling). A
    parameter sampled in log space (``log_scale``) whose draws span decades (`LOG_AXIS_SPAN`)
    gets log axes; Ω, F, H and m axes count in an SI prefix. ``truths`` by name draws reference
    lines. ``params``: the names to draw, in that order (None: every one; the title says "k of
    n parameters" for fewer). The figure grows with the panels (`corner_figure_size`), and a
    label longer than its panel puts the unit on a line of its own. Histograms and titles use
    every draw; the scatter at most ``max_points`` evenly spaced ones; a parameter has one range,
    its column's x axes (the histogram's among them) and its row's y axes. ``bins`` ≥ 1,
    ``max_points`` ≥ 1, a name of ``params`` or ``truths`` not among ``names`` and a truth that
    is not a finite number are a `ParameterError`."""
    bins, max_points = count(1)(bins, "bins"), count(1)(max_points, "max_points")
    names = list(names)
    picked = corner_params(params, names)
    truths = _checked_truths(truths, names)
    every = np.asarray(draws, float).reshape(-1, len(names))[:, picked]
    log_scale = [log_scale[i] for i in picked]
    units = None if units is None else [units[i] for i in picked]
    subset = f"{len(picked)} of {len(names)} parameters; " if len(picked) < len(names) else ""
    names = [names[i] for i in picked]
    k = len(names)
    flat = every[np.linspace(0, every.shape[0] - 1, max_points).astype(int)] if every.shape[0] > max_points else every
    units = [unit_text(u) for u in units] if units is not None else [""] * k
    lo, hi = np.nanquantile(every, [0.01, 0.99], axis=0)
    logs = [bool(ls) and low > 0 and high > LOG_AXIS_SPAN * low for ls, low, high in zip(log_scale, lo, hi)]
    views = [_column_view(every[:, i], logs[i], truths.get(n)) for i, n in enumerate(names)]
    size = corner_figure_size(k)
    label_chars = characters_across(0.95 * (size - 1) / k, font_size("label", 8))  # (a label along its panel: its length, the margins aside)
    labels = [(f"{n} [{u}]" if len(f"{n} [{u}]") <= label_chars else f"{n}\n[{u}]") if u else n for n, u in zip(names, units)]
    # a column shares one x range, the histogram's (every draw) with the scatter's (a subset):
    # apart, REAL BioLogic's R0 histogram spanned 62.10–64.96 Ω over panels of 62.24–64.65 Ω,
    # and its lines, read against the bottom axis, were off (q95 = 64.03 read 63.87)
    fig, axes = plt.subplots(k, k, figsize=(size, size), squeeze=False, sharex="col", layout="constrained")
    quantiles: dict[int, tuple[float, float, float]] = {}  # (the diagonal's median, q05, q95: titled once every panel is drawn)
    title_chars = int(0.85 * size / k * 72 / (font_size("title", 7) * 0.6))  # characters of the titles' 7 pt (≈ 0.6 em wide) a panel holds
    for i in range(k):
        for j in range(k):
            ax = axes[i, j]
            if j > i:
                ax.set_visible(False)
                continue
            if logs[j]:
                ax.set_xscale("log")
            if i == j:
                column = every[np.isfinite(every[:, i]), i]  # (a draw that overflowed is left out)
                view, tail = views[i]
                edges = (np.geomspace if logs[i] else np.linspace)(*view, bins + 1) if tail or (logs[i] and column.size) else bins
                ax.hist(column, bins=edges, color="tab:blue", histtype="stepfilled", alpha=0.6)
                if tail:
                    ax.set_xlim(*view)  # (the column's scatter would widen it to its own far draws)
                q05, q50, q95 = np.nanquantile(every[:, i], [0.05, 0.5, 0.95])
                for qv, style in ((q05, "--"), (q50, "-"), (q95, "--")):
                    ax.axvline(qv, color="k", lw=0.8, ls=style)
                quantiles[i] = (q50, q05, q95)
                ax.set_yticks([])
            else:
                if logs[i]:
                    ax.set_yscale("log")
                ax.plot(flat[:, j], flat[:, i], ".", ms=1.5, alpha=0.25, color="tab:blue")
                if truths and names[i] in truths:
                    ax.axhline(truths[names[i]], color="tab:red", lw=0.8)
            if truths and names[j] in truths:
                ax.axvline(truths[names[j]], color="tab:red", lw=0.8)
            for axis, is_log, n in ((ax.xaxis, logs[j], j), (ax.yaxis, logs[i], i)):
                if is_log:
                    plain_log_ticks(axis, prefixes=units[n] not in DIMENSIONLESS)  # (α's ticks read "10µ")
                elif axis is ax.xaxis or i != j:
                    axis.set_label_text(labels[n])  # (the formatter's prefix goes into the label)
                    prefixed_axis(axis, max_bins=4)  # (five-digit ticks of a narrow panel ran together: at most 4 intervals, fewer where they do not fit)
                    if not prefixable_unit(labels[n]):  # (α's values on its ticks: the offset "1e−5+8.499e−1" ran over the column's label)
                        plain_linear_ticks(axis)
            if i == k - 1:
                ax.set_xlabel(labels[j], fontsize=font_size("label", 8))
            else:
                ax.set_xlabel("")
                ax.tick_params(which="both", labelbottom=False)  # (the minor labels of a log axis too)
            if j == 0 and i > 0:
                ax.set_ylabel(labels[i], fontsize=font_size("label", 8))
            else:
                ax.set_ylabel("")
                ax.tick_params(which="both", labelleft=False)
            ax.tick_params(which="both", labelsize=font_size("tick", 7))  # (the minor labels of a log axis too: they were larger than the major ones)
    for i in range(k):
        for ax in axes[i, :i]:
            ax.set_ylim(axes[i, i].get_xlim())  # (a row's y axes: its parameter on the range of its column)
    for i, (q50, q05, q95) in quantiles.items():
        # (a linear axis counts in the prefix of the largest value it shows, `prefixed_axis`: the title in that
        # of the labelled axis of its parameter, the bottom panel of its column, whose view the row's y axes share)
        shown_top = None if logs[i] else max(abs(v) for v in axes[k - 1, i].get_xlim())
        text = f"{names[i]} = {interval_text(q50, q05, q95, units[i], significant=logs[i], top=shown_top)}"
        axes[i, i].set_title(text if len(text) <= title_chars else text.replace(" = ", " =\n", 1), fontsize=font_size("title", 7))  # (a long one on two lines, within its panel)
    cut = [n for n, (_, tail) in zip(names, views) if tail]
    shown = f"{subset}{every.shape[0]} draws" + (f"; {flat.shape[0]} in the scatter" if flat.shape[0] < every.shape[0] else "")
    shown += f"; {', '.join(cut)}: central {100 * TAIL_VIEW_MASS:g} % shown" if cut else ""
    fig.suptitle(f"{title} ({shown})", fontsize=font_size("suptitle", 9))
    return fig


def _column_view(values: np.ndarray, log: bool, truth: float | None = None) -> tuple[tuple[float, float], bool]:
    """The x range of a corner column of draws ``values`` (on a log axis where ``log``) and
    whether it cuts a long tail: every finite draw, or the central `TAIL_VIEW_MASS` widened by
    `TAIL_VIEW_MARGIN` where every draw would span more than `TAIL_VIEW_FACTOR` times that,
    reaching a known value ``truth`` (a truth line past the view was not drawn)."""
    column = values[np.isfinite(values) & ((values > 0) if log else True)]
    if column.size < 2:
        return (float(column.min()), float(column.max())) if column.size else (0.0, 1.0), False
    t = np.log(column) if log else column
    low, high = float(t.min()), float(t.max())
    q_low, q_high = (float(q) for q in np.quantile(t, [(1 - TAIL_VIEW_MASS) / 2, (1 + TAIL_VIEW_MASS) / 2]))
    tail = q_high > q_low and high - low > TAIL_VIEW_FACTOR * (q_high - q_low)
    if tail:
        margin = TAIL_VIEW_MARGIN * (q_high - q_low)
        low, high = max(low, q_low - margin), min(high, q_high + margin)
        if truth is not None and (truth > 0 or not log):
            at = math.log(truth) if log else truth
            low, high = min(low, at - margin), max(high, at + margin)
    return ((math.exp(low), math.exp(high)) if log else (low, high)), bool(tail)


TRACE_ROW_IN = 1.4  # a trace plot's row height [in]


def plot_trace(
    draws,
    names: Sequence[str],
    log_scale: Sequence[bool],
    *,
    units: Sequence[str] | None = None,
    first_step: int = 0,
    thin: int = 1,
    autocorr: Mapping[str, float] | None = None,
    title: str = "posterior",
    params: Sequence[str] | None = None,
):
    """Trace plot of the kept draws ``draws`` (walker, draw, param) named ``names``: one row per
    parameter, every walker's draws against the sampler's step (``first_step`` + d·``thin``, d
    from 1: ``first_step`` is the burn-in, left out) as thin lines, and the walkers' median at each step, in the parameter's unit
    (Ω, F, H and m in an SI prefix; a log axis for a log-sampled parameter over decades, as the
    corner plot's, `LOG_AXIS_SPAN`). A walker stuck apart, a drift or a median still moving say
    the chain has not converged, which τ and ESS alone may not show. ``autocorr`` (name → τ in
    steps) is written beside each row's label. ``params``: the names to draw, in that order."""
    draws = np.asarray(draws, float)
    names = list(names)
    picked = corner_params(params, names)
    k = len(picked)
    units = [unit_text(units[i]) for i in picked] if units is not None else [""] * k
    steps = first_step + thin * np.arange(1, draws.shape[1] + 1)  # (emcee's kept steps, counted from 1: burn + thin, burn + 2·thin, …)
    fig, axes = plt.subplots(k, 1, figsize=(8.0, 0.8 + TRACE_ROW_IN * k), sharex=True, squeeze=False, layout="constrained")
    for row, i in enumerate(picked):
        ax, values = axes[row, 0], draws[:, :, i]
        finite = values[np.isfinite(values)]
        low, high = (np.quantile(finite, [0.01, 0.99]) if finite.size else (np.nan, np.nan))
        log = bool(log_scale[i]) and low > 0 and high > LOG_AXIS_SPAN * low
        ax.plot(steps, values.T, "-", color="tab:blue", lw=0.4, alpha=max(0.03, min(0.3, 8.0 / values.shape[0])))
        ax.plot(steps, np.nanmedian(values, axis=0), "-", color="k", lw=1.0, label="median of the walkers")
        label = f"{names[i]} [{units[row]}]" if units[row] else names[i]
        ax.set_ylabel(label, fontsize=font_size("label", 8))
        if log:
            ax.set_yscale("log")
            plain_log_ticks(ax.yaxis, prefixes=units[row] not in DIMENSIONLESS)
        else:
            prefixed_axis(ax.yaxis, max_bins=4)
            if not prefixable_unit(label):  # (sigma_rel 1.02e-5 on its ticks, not 0 to 5 under "1e−10+1.02e−5", which ran over the row above)
                plain_linear_ticks(ax.yaxis)
        tau = (autocorr or {}).get(names[i])
        if tau is not None and np.isfinite(tau):
            ax.set_title(f"τ = {tau:.3g} steps", loc="right", fontsize=font_size("title", 7))
        ax.tick_params(labelsize=font_size("tick", 7))
        ax.grid(alpha=0.3)
    # (above the first row, on the line of its τ: inside, it lay over the walkers, which fill a
    # converged chain's panel from edge to edge)
    axes[0, 0].legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), borderaxespad=0.1, frameon=False, fontsize=font_size("legend", 7))
    axes[-1, 0].set_xlabel(f"step (burn-in of {first_step} left out)" if first_step else "step", fontsize=font_size("label", 8))
    fig.suptitle(f"{title} ({draws.shape[0]} walkers × {draws.shape[1]} draws)", fontsize=font_size("suptitle", 9))
    return fig


def corner_figure_size(k: int) -> float:
    """The side [in] of a corner plot of ``k`` parameters: `CORNER_PANEL_IN` a panel and an
    inch of margins, at most `CORNER_SHARED_IN` while that leaves `CORNER_MIN_PANEL_IN` a panel,
    then `CORNER_MIN_PANEL_IN` a panel."""
    return min(CORNER_PANEL_IN * k + 1, max(CORNER_SHARED_IN, CORNER_MIN_PANEL_IN * k + 1))


def corner_params(params, names: Sequence[str], what: str = "params") -> list[int]:
    """The positions in ``names`` of the corner plot's ``params`` (names, or one name; None:
    all). An unknown name (with the closest known one), a name twice or none at all is a
    `ParameterError` naming ``what`` (the keyword, or ``--corner-params``)."""
    if params is None:
        return list(range(len(names)))
    chosen = [params] if isinstance(params, str) else params
    if not isinstance(chosen, Sequence) or not all(isinstance(n, str) for n in chosen):
        raise ParameterError(f"{what} must be a list of parameter names, e.g. {list(names[:2])}; got {shown(params)}")
    if not chosen:
        raise ParameterError(f"{what}: no parameter names given (parameters: {', '.join(names)})")
    for n in chosen:
        if n not in names:
            raise unknown_parameter(what, n, names)
        if list(chosen).count(n) > 1:
            raise ParameterError(f"{what}: {n} is named twice; name each parameter once")
    return [names.index(n) for n in chosen]


def _checked_truths(truths, names: Sequence[str]) -> dict[str, float]:
    """``truths`` (name → value) of a corner plot, checked: a mapping of ``names`` to finite
    numbers, else a `ParameterError` naming the unknown name (with the posterior's names) or the
    value that is not a number (a truth of "a" was drawn at 0; one of an unknown name not at all)."""
    if truths is None:
        return {}
    if not isinstance(truths, Mapping):
        raise ParameterError(f"truths must be a mapping of parameter names to values, e.g. {{{names[0]!r}: 1.0}}; got {shown(truths)}")
    checked = {}
    for name, value in truths.items():
        if name not in names:
            raise unknown_parameter("truths", name, names)
        checked[name] = real()(value, f"truths[{name!r}]")
    return checked


def interval_text(median: float, low: float, high: float, unit: str = "", *, significant: bool = False, top: float | None = None) -> str:
    """``63.57 [63.10, 64.04] Ω``, ``4.80 [4.70, 4.90] MΩ``: a median and its interval in one
    SI prefix (Ω, F, H, m, or a compound unit led by one, as `prefixed_axis` counts an axis:
    ``86.0 [79.8, 92.4] µF s^(α-1)``; chosen by the largest of the three, so 999 [984, 1017] Ω
    reads 0.999 [0.984, 1.017] kΩ, or by ``top``, the largest value the panel's axis shows, so
    title and axis use one prefix), or with a shared power of ten for another unit far from 1
    (``1.000 [0.968, 1.034] ×10⁻⁵ V``), with the decimals that give the interval's
    half-width two significant digits; ``significant``: three significant digits each, for an
    interval over decades (``1.2 [0.013, 95.1] kΩ``), each in its own prefix where the shared one
    would write a number below 0.01 (``43.1 TΩ [23.7 MΩ, 4.85e+19 Ω]``, not ``43.1 [2.37e-05,
    4.85e+07] TΩ``; `format_quantity`, plain beyond the prefixes)."""
    if top is None or not np.isfinite(top):
        top = max((abs(v) for v in (median, low, high) if np.isfinite(v)), default=0.0)
    scale, prefix = 1.0, ""
    if top > 0 and prefixable_unit(f"[{unit}]"):
        scale, prefix = si_prefix(top)
        if significant and any(0 < abs(v) / scale < 0.01 for v in (median, low, high) if np.isfinite(v)):
            return f"{format_quantity(median, unit)} [{format_quantity(low, unit)}, {format_quantity(high, unit)}]"
    elif top > 0 and not (1e-3 <= top < 1e4):
        exponent = math.floor(math.log10(top))
        scale, prefix = 10.0**exponent, "×10" + str(exponent).translate(_SUPERSCRIPTS) + (" " if unit else "")
    m, a, b = median / scale, low / scale, high / scale
    if significant:
        text = f"{m:.3g} [{a:.3g}, {b:.3g}]"
    else:
        half = (b - a) / 2
        decimals = min(max(0, 1 - math.floor(math.log10(half))), 12) if np.isfinite(half) and half > 0 else 3
        text = f"{m:.{decimals}f} [{a:.{decimals}f}, {b:.{decimals}f}]"
    return f"{text} {prefix}{unit}".rstrip()


_SUPERSCRIPTS = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
