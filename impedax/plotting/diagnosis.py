"""Figures of a diagnosis and of a refinement (`impedax.fitting.diagnosis`, docs/diagnosis.md).

The results are taken duck-typed: a diagnosis has ``baseline`` (a fit with ``frequency``,
``z_data``, ``z_model``, ``residuals``, ``model``, ``rms_rel``), ``failing_bands`` (with
``f_min``/``f_max``), ``verdict`` and ``best`` (a suggestion with ``fit`` and ``effect``, or
None); a refinement has ``steps`` (each with ``fit``, ``effect``, ``added``, ``removed``,
``model`` and ``diagnosis``, the last one's with ``noise_ratio`` and ``baseline``),
``final_model`` and ``verdict``.
"""

from __future__ import annotations


import matplotlib.pyplot as plt
import numpy as np

from . import FLAT_NYQUIST, characters_across, font_size, frequency_axis, labelled_log_ticks, nyquist_view, model_curve, nyquist_panel_height, nyquist_shape, plot_spectrum, legends_off_data, refresh_legend, residual_axis, shade_bands, wrap_model

__all__ = ["plot_diagnosis", "plot_refinement", "noise_levels", "NOISE_LEVEL_LABEL"]


ADEQUATE_BANDS = "misfit no effect explains (adequate)"
"""The legend of an ``adequate`` diagnosis' failing bands: structured residuals that no candidate
explains significantly (docs/diagnosis.md, section 5), not a model that fails."""


def band_shading(diagnosis) -> tuple[str, str]:
    """Legend label and colour of ``diagnosis``' failing bands: "model fails" in red, or, when
    its verdict is ``adequate``, `ADEQUATE_BANDS` in grey, so that figure and verdict agree."""
    if getattr(diagnosis, "verdict", None) == "adequate":
        return ADEQUATE_BANDS, "tab:grey"
    return "model fails", "tab:red"


DATA_PROBLEM_BANDS = "data problem (KK flags the data)"
"""The legend of failing bands marked ``data_problem``: misfit where the KK test flags the data,
shaded apart from the model's (`DATA_PROBLEM_COLOR`), as the report tags them."""
DATA_PROBLEM_COLOR = "tab:orange"


def model_and_data_bands(diagnosis) -> tuple[list, list]:
    """``diagnosis``' failing bands as (f_min, f_max) pairs: (the model's, those marked
    ``data_problem``), for shading each kind apart."""
    bands = getattr(diagnosis, "failing_bands", ())
    return ([(b.f_min, b.f_max) for b in bands if not getattr(b, "data_problem", False)],
            [(b.f_min, b.f_max) for b in bands if getattr(b, "data_problem", False)])


def weighting_words(fit) -> str:
    """``, proportional weighting`` after a figure title's rms_rel: the weighting ``fit`` was made
    with ("" for an object that records none)."""
    weighting = getattr(fit, "weighting", None)
    return f", {weighting} weighting" if weighting else ""


def plot_diagnosis(diagnosis, *, title: str | None = None, figsize: tuple[float, float] | None = None):
    """Nyquist, Bode and residual panels of the baseline with the failing bands shaded (those
    where the KK test flags the data apart, `DATA_PROBLEM_BANDS`) and the best suggestion
    overlaid (matplotlib Figure; ``figsize`` (width, height) [in], `spectrum_layout`)."""
    b = diagnosis.baseline
    bands, data_bands = model_and_data_bands(diagnosis)
    best = diagnosis.best
    suggestion = model_curve(best.fit) if best is not None else None
    # the Nyquist panel follows the data and the masked points as the comparison's does, the
    # baseline's and the suggestion's curves widening it by at most `MODEL_OVERSHOOT` of the
    # data's span (`nyquist_view`; REAL ZPlot's ran to 900 Ω beside data that end at 615 Ω)
    fig = plot_spectrum(
        (b.frequency, b.z_data), model_curve(b), title=title or f"{b.model}: {diagnosis.verdict} (rms_rel {b.rms_rel * 100:.3g} %{weighting_words(b)})", bands=bands,
        model_label="baseline", residual_labels=("Re (baseline)", "Im (baseline)"), model_at_data=b.z_model,
        band_label=band_shading(diagnosis)[0], band_color=band_shading(diagnosis)[1], figsize=figsize,
        nyquist_curves=[] if suggestion is None else [suggestion[1]], nyquist_points=_masked_impedance(diagnosis),
    )
    if data_bands:  # (the frequency axes: |Z|, phase and the residuals)
        shade_bands(fig.axes[1:], data_bands, label=DATA_PROBLEM_BANDS, color=DATA_PROBLEM_COLOR)
    _mark_masked(fig.axes[0], diagnosis, fig.axes[1:3])
    if len(fig.axes) > 3 and mark_flagged_kept(fig.axes[3], b, diagnosis):  # (the residual panel)
        refresh_legend(fig.axes[3])
    if best is not None:
        axes = fig.axes
        f, z = suggestion
        axes[0].plot(z.real, -z.imag, "-", color="tab:green", lw=1.2, label=f"+ {best.effect}")
        # (plot, not loglog/semilogx: those set the scale again, and with it matplotlib's
        # tick labels in place of plain_log_ticks' and frequency_axis')
        axes[1].plot(f, np.abs(z), "-", color="tab:green", lw=1.2, label=f"+ {best.effect}")
        axes[2].plot(f, np.degrees(np.angle(z)), "-", color="tab:green", lw=1.2)
        if len(axes) > 3:
            r = best.fit.residuals * 100
            axes[3].plot(b.frequency, np.abs(r), "-", color="tab:green", lw=1.0, label=f"|res| with {best.effect}")
            axes[3].legend(fontsize=font_size("legend", 8), ncol=3)
        refresh_legend(axes[0])
        refresh_legend(axes[1])
    legends_off_data(fig)
    return fig


def _masked_impedance(diagnosis) -> np.ndarray:
    """Z [Ω] of the diagnosis' masked points (`_mark_masked` draws them), none when they do
    not match ``masked_points``."""
    f = np.asarray(getattr(diagnosis, "masked_points", ()), float)
    z = np.asarray(getattr(diagnosis, "masked_impedance", ()), complex).ravel()
    return z if z.size == f.size else np.zeros(0, complex)


MASKED_STYLE = dict(marker="x", ls="none", ms=6, mew=1.3, color="tab:red")

FLAGGED_KEPT_STYLE = dict(marker="o", ls="none", ms=8, mfc="none", mew=1.2, color=DATA_PROBLEM_COLOR)


def kk_flagged_kept(diagnosis) -> np.ndarray:
    """The frequencies [Hz] the diagnosis' KK test flags and every fit kept (not masked): the
    points its report names ("the KK test flags 4 point(s) inside the band (5.34 Hz, …): kept in
    every fit")."""
    kk = getattr(diagnosis, "kk", None)
    if kk is None or getattr(kk, "flagged", None) is None:
        return np.zeros(0)
    flagged = np.asarray(kk.frequency, float)[np.asarray(kk.flagged, bool)]
    masked = np.asarray(getattr(diagnosis, "masked_points", ()), float)
    return np.array([f for f in flagged if not np.any(np.isclose(masked, f, rtol=1e-9))])


def mark_flagged_kept(ax, fit, diagnosis, *, label: bool = True) -> bool:
    """Ring the residuals (Re and Im, [%]) of ``fit`` at the points the KK test flags and the fits
    kept (`kk_flagged_kept`), in the data-problem colour; True when there were any. Only the
    failing bands that the flags fall in were shaded: on the REAL BioLogic file the report named
    4 flagged points (5.34, 56.2, 123, 270 Hz) and the figure shaded 49–83 Hz alone."""
    kept = kk_flagged_kept(diagnosis)
    f = np.asarray(fit.frequency, float)
    at = [int(np.argmin(np.abs(np.log(f / k)))) for k in kept if k > 0]
    at = [i for i, k in zip(at, kept) if np.isclose(f[i], k, rtol=1e-6)]
    if not at:
        return False
    r = np.asarray(fit.residuals)[at] * 100
    ax.plot(f[at], r.real, label=f"KK-flagged, kept in the fit ({len(at)})" if label else None, **FLAGGED_KEPT_STYLE)
    ax.plot(f[at], r.imag, **FLAGGED_KEPT_STYLE)
    return True


def _mark_masked(nyquist, diagnosis, bode=()) -> None:
    """The diagnosis' masked points (left out of every fit: KK-flagged, or Re Z < 0) as red
    crosses on the Nyquist panel and, when given, the |Z| and phase panels."""
    f = np.asarray(getattr(diagnosis, "masked_points", ()), float)
    z = np.asarray(getattr(diagnosis, "masked_impedance", ()), complex)
    if f.size == 0 or z.size != f.size:
        return
    label = f"masked ({f.size}: left out of every fit)"
    nyquist.plot(z.real, -z.imag, label=label, **MASKED_STYLE)
    refresh_legend(nyquist)
    if bode:
        ax_mod, ax_ph = bode
        ax_mod.plot(f, np.abs(z), label=label, **MASKED_STYLE)
        ax_ph.plot(f, np.degrees(np.angle(z)), **MASKED_STYLE)
        refresh_legend(ax_mod)


NOISE_LEVEL_LABEL = "noise level each step is judged against (1×)"
"""The legend of the refinement figure's noise marks (`noise_levels`)."""


NOISE_MARK_POINTS = 18
"""The width of a step's noise mark in the refinement figure [points]; each step's label starts right of it."""


def noise_levels(steps) -> list[tuple[int, float]]:
    """(step, rms_rel [%]) at which each step's diagnosis calls the residuals 1× the noise: the
    step's plotted rms_rel divided by its noise ratio (√(mean |r|²/(2σ²)), docs/diagnosis.md,
    section 2). The ratio weighs σ by where the residuals lie, so the level moves from step to
    step: one line from the last step's ratio put a start judged 1.26× the noise (BioLogic)
    below it. A step's point lies above its mark exactly when its ratio exceeds 1. Steps
    without a diagnosis or a positive ratio have no mark."""
    out = []
    for i, s in enumerate(steps):
        ratio = getattr(s.diagnosis, "noise_ratio", None) if s.diagnosis is not None else None
        if ratio is not None and np.isfinite(ratio) and ratio > 0:
            out.append((i, s.fit.rms_rel / ratio * 100))
    return out


REFINEMENT_RESIDUAL_LABEL = "(Z_model − Z)/|Z| [%]"
"""The y label of the refinement figure's residual panels: model minus data, `FitResult.residuals`,
as the fit and diagnosis figures name it (not "res. [%]", which gives no sign)."""


def plot_refinement(refinement, *, title: str | None = None):
    """Error per step (rms_rel, log scale, with each step's noise level, `noise_levels`), the relative
    residuals of the last five steps vs frequency (of more steps, the first row's title says
    which are shown), each step's failing bands shaded, and a
    Nyquist panel of the data with the first and the last step's model (matplotlib Figure).
    The axes are: the error per step, the residual panels from the top, the Nyquist panel. A
    flat spectrum (`FLAT_NYQUIST`) has its Nyquist panel across the top, a steeper one above
    the error panel."""
    n = len(refinement.steps)
    rows = min(n, 5)
    width, ratios = 11.0, (1.0, 1.6)
    # the models (and the suptitle) are wrapped to the width of their panel (of the figure), never cut
    title_chars = characters_across(width * ratios[1] / sum(ratios) - 0.6, font_size("title", 8))
    first, last = refinement.steps[0].fit, refinement.steps[-1].fit
    shape = nyquist_shape((first.frequency, first.z_data), (last.frequency, last.z_model))  # (`_refinement_nyquist`: the start may run off)
    across = shape <= FLAT_NYQUIST
    top = nyquist_panel_height(shape, width) if across else 0.0
    fig = plt.figure(figsize=(width, 3.2 + 2.3 * rows + top), layout="constrained")
    below = 1 if across else 0  # (the first row of the error and residual panels)
    grid = fig.add_gridspec(rows + below, 2, width_ratios=list(ratios), height_ratios=[top] * below + [2.3] * rows)
    if across:
        ax = fig.add_subplot(grid[1:, 0])
    else:  # (the Nyquist panel takes the upper part of the left column)
        left = grid[:, 0].subgridspec(2, 1, height_ratios=[1.2, 1.0])
        ax = fig.add_subplot(left[1])
    rms = [s.fit.rms_rel * 100 for s in refinement.steps]
    ax.semilogy(range(n), rms, "o-", color="tab:blue")
    ax.margins(y=0.12)  # (room for the label above the highest step, which the frame cut)
    for i, s in enumerate(refinement.steps):
        label = s.effect or ("start" if not s.removed else "simplified")
        if s.removed:
            label += "\n" + (f"{', '.join(s.removed)} → {s.added}" if s.added and s.effect is None else "− " + ", ".join(s.removed))  # (as `RefinementStep.change`)
        # each step's label stands upright above its point and just right of it: no wider than a
        # step, so labels of steps of close rms_rel do not write over each other, and clear of the
        # line, which comes in from the upper left and leaves downwards (REAL exampleData.csv's 7
        # steps: level labels would run leftwards into each other, "extra_relaxation − W1"
        # across "diffusion"), and right of the step's noise mark, which reaches NOISE_MARK_POINTS/2
        # either side (the demo's "electrode_polarization" ran up through it); the start's reads across
        upright = i > 0
        ax.annotate(label, (i, rms[i]), textcoords="offset points", xytext=(NOISE_MARK_POINTS / 2 + 2, 8) if upright else (4, 6), ha="left",
                    va="bottom" if upright else "baseline", rotation=90 if upright else 0, fontsize=font_size("text", 8))
    judged = noise_levels(refinement.steps)
    if judged:  # (a mark per step: the rms_rel at which that step's verdict calls the residuals 1× the noise)
        at, levels = zip(*judged)
        ax.plot(at, levels, ls="none", marker="_", ms=NOISE_MARK_POINTS, mew=1.6, color="grey", label=NOISE_LEVEL_LABEL)  # (marks alone: a line between them crossed the steps' line)
        ax.legend(fontsize=font_size("legend", 8), loc="best")
    ax.set_xlabel("refinement step")
    ax.set_ylabel("rms_rel [%]")
    labelled_log_ticks(ax.yaxis)  # (REAL VersaStudio's steps, 20.5 % to 0.54 %, read against 1 and 10 alone; the demo's, 0.426 % to 15 %, against 1, 10, 100)
    ax.set_xticks(range(n))
    ax.set_xlim(-0.5, n - 0.5)
    ax.grid(alpha=0.3, which="both")
    shown = list(range(n))[-5:] if n > 5 else list(range(n))
    named: set[str] = set()  # (each kind of shading is named in the legend of the first row that shows it)
    for row, i in enumerate(shown):
        s = refinement.steps[i]
        a = fig.add_subplot(grid[row + below, 1])
        r = s.fit.residuals * 100
        a.semilogx(s.fit.frequency, r.real, "o-", ms=2.5, lw=0.7, label="Re")
        a.semilogx(s.fit.frequency, r.imag, "s-", ms=2.5, lw=0.7, label="Im")
        frequency_axis(a.xaxis)
        a.axhline(0, color="k", lw=0.5)
        if s.diagnosis is not None:
            # red where the step's diagnosis names a missing effect, grey where it is adequate (the verdict in the title)
            label, color = band_shading(s.diagnosis)
            bands, data_bands = model_and_data_bands(s.diagnosis)
            fresh = bool(bands) and label not in named
            shade_bands([a], bands, label=label if fresh else None, color=color)
            named.update([label] if fresh else [])
            fresh_data = bool(data_bands) and DATA_PROBLEM_BANDS not in named
            shade_bands([a], data_bands, label=DATA_PROBLEM_BANDS if fresh_data else None, color=DATA_PROBLEM_COLOR)
            named.update([DATA_PROBLEM_BANDS] if fresh_data else [])
            fresh = fresh or fresh_data
        else:
            fresh = False
        if s.diagnosis is not None:  # (the flagged points the report names, kept in the fit: named in the first row that shows them)
            ringed = mark_flagged_kept(a, s.fit, s.diagnosis, label="kk flagged kept" not in named)
            fresh = fresh or (ringed and "kk flagged kept" not in named)
            named.update(["kk flagged kept"] if ringed else [])
        change = "start" if s.change == "(start)" else s.change
        # (no break inside "(rms_rel 1.72 %)": REAL VersaStudio's step 2 wrapped as "(rms_rel / 1.72 %)")
        head = wrap_model(f"step {i}: {change}  (rms_rel\u00a0{s.fit.rms_rel * 100:.3g}\u00a0%)", title_chars)
        if row == 0 and shown[0] > 0:  # (steps left out: said above the first row shown, so 7 steps shown as 2–6 say so)
            head = wrap_model(f"residuals of the last {len(shown)} of {n} steps ({shown[0]}–{shown[-1]}; all {n} in the error panel)", title_chars) + "\n" + head
        a.set_title(head + "\n" + wrap_model(s.model, title_chars), fontsize=font_size("title", 8))
        a.set_ylabel(REFINEMENT_RESIDUAL_LABEL, fontsize=font_size("label", 8))
        a.grid(alpha=0.3)
        if residual_axis(a, s.fit.residuals) or row == 0 or fresh:
            a.legend(fontsize=font_size("legend", 7), ncol=3)
    fig.axes[-1].set_xlabel("frequency [Hz]")
    nyquist = fig.add_subplot(grid[0, :] if across else left[0])
    _refinement_nyquist(nyquist, refinement, characters_across((width if across else width * ratios[0] / sum(ratios)) - 1.0, font_size("legend", 8)))
    fig.suptitle(title or wrap_model(f"refinement: {refinement.steps[0].model} → {refinement.final_model} ({_verdict_where(refinement)}{weighting_words(refinement.steps[-1].fit)})", characters_across(width - 0.4, font_size("suptitle", 12))))
    legends_off_data(fig)
    room_for_step_labels(ax)
    return fig


def room_for_step_labels(ax, passes: int = 3) -> None:
    """Widen the error panel's step axis to the right until every step's label ends inside the
    panel: the last step's label stands right of its point, and on the REAL exampleData.csv's
    7 steps "simplified / CPE1 → C1" ran 37 points past the frame, over the residual panel's
    label. Measured after the layout, again after each widening (which narrows the steps)."""
    fig = ax.get_figure()
    for _ in range(passes):
        fig.draw_without_rendering()
        renderer = fig.canvas.get_renderer()
        frame = ax.get_window_extent(renderer)
        beyond = max((t.get_window_extent(renderer).x1 - frame.x1 for t in ax.texts), default=0.0)
        if beyond <= 0.5:
            return
        lo, hi = ax.get_xlim()
        ax.set_xlim(lo, hi + (beyond + 3.0) * (hi - lo) / frame.width)


def _verdict_where(refinement) -> str:
    """The verdict, and where it was judged when points were left out (the report's
    `Refinement.verdict_scope`, short): ``adequate on 2.53 kHz – 200 kHz, 20 of 72 points``."""
    if not refinement.masked_points:
        return str(refinement.verdict)
    from ..data import format_band

    lo, hi = refinement.verdict_band
    n = refinement.final.frequency.size
    return f"{refinement.verdict} on {format_band(lo, hi, ' – ')}, {n} of {n + len(refinement.masked_points)} points"


def _refinement_nyquist(ax, refinement, legend_chars: int) -> None:
    """The data with the model of the refinement's first step (dashed) and of its last (solid),
    at equal scales and scaled to the data and the last model: where the start missed the
    data, and that the end does not."""
    first, last = refinement.steps[0].fit, refinement.steps[-1].fit
    ax.plot(first.z_data.real, -first.z_data.imag, "o", ms=3.5, mfc="none", color="tab:blue", label="data")
    if refinement.steps[0].diagnosis is not None:
        _mark_masked(ax, refinement.steps[0].diagnosis)
    drawn = [(first, "--", "tab:grey", "start")] + ([(last, "-", "tab:green", "final")] if len(refinement.steps) > 1 else [])
    curves = []
    for fit, style, color, name in drawn:
        z = model_curve(fit)[1]
        curves.append(z)
        ax.plot(z.real, -z.imag, style, lw=1.4, color=color, label=wrap_model(f"{name}: {fit.model} ({fit.rms_rel * 100:.3g} %)", legend_chars))
    # the panel follows the data and the masked points (`nyquist_view`), the curves widening it
    # by at most `MODEL_OVERSHOOT` of the data's span: a start far off (the demo's pure
    # capacitor, a line to 165 MΩ beside an arc of 57 MΩ) runs off the panel, where it had
    # shrunk the data to a corner; and the panel's box narrows to that frame, where equal scales
    # over a panel capped in height (`TALLEST_PANEL`) had widened its range past the data
    masked = getattr(refinement.steps[0].diagnosis, "masked_impedance", ())
    ax.set_xlabel("Z' [Ω]")
    ax.set_ylabel("−Z'' [Ω]")
    nyquist_view(ax, first.z_data, *curves, frequency=first.frequency, points=np.asarray(masked, complex))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=font_size("legend", 8))
