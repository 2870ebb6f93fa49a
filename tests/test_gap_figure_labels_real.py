"""`impedax gap` on the REAL Autolab data.dfr (one spectrum, 29 frequencies 1 Hz–10 kHz, a single
contact: nothing subtracted), 2026-12-06 walkthrough: the figure's legends against the geometry
drawn and the file's own shape, and the sampling's words against a hand computation."""

import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import impedax as ix
from impedax.models.gap import gap_analysis

matplotlib.use("Agg")
pytestmark = pytest.mark.slow  # (the module's gap analysis: about 25 s)

DFR = Path(__file__).parent / "fixtures" / "real" / "data.dfr"
AREA = 130e-6  # [m²]
PREFIX = {"p": 1e-12, "n": 1e-9, "µ": 1e-6, "m": 1e-3, "": 1.0}


@pytest.fixture(scope="module")
def gap():
    # (1500 steps: the draws of u spread from 0.7 µm to the prior's bound, as with steps="auto")
    return gap_analysis(ix.load(DFR), area=AREA, method="pooled", steps=1500, progress=False)


@pytest.fixture(scope="module")
def figure(gap):
    import matplotlib.pyplot as plt

    fig = gap.plot()
    yield fig
    plt.close(fig)


def test_the_paper_methods_line_is_labelled_with_its_own_position(figure):
    """The paper method's u here is 504 pm (C_gap = 2.29 µF): its line sat at 5.04e-4 µm, its
    legend read "paper method 0.00 µm". The label's number, read back with its SI prefix, is the
    line's x (the axis is in µm)."""
    (line,) = [l for l in figure.axes[1].get_lines() if l.get_label().startswith("paper method")]
    x_m = float(line.get_xdata()[0]) * 1e-6
    number, prefix = re.fullmatch(r"paper method ([0-9.]+) ([pnµm]?)m", line.get_label()).groups()
    assert float(number) * PREFIX[prefix] == pytest.approx(x_m, rel=5e-3), line.get_label()
    assert 1e-10 < x_m < 1e-9  # (504 pm: no air gap, as the report says)


def test_one_spectrum_is_not_called_a_mean_of_trials(figure):
    """data.dfr holds one sweep (29 rows, no trial dimension): the data's legend read "Z (mean of
    trials)" although no trial was averaged ("spectra used  total 1" in the report)."""
    assert ix.load(DFR)["Z"].dims == ("frequency",)
    labels = figure.axes[0].get_legend_handles_labels()[1]
    assert labels[0].startswith("Z") and "trials" not in labels[0], labels


def test_the_pile_up_warning_gives_the_bound_of_u_in_metres(gap):
    """u's upper bound is u at C_gap = 1 fF: ε0 ε_air A / 1 fF = 8.8541878128e-12 × 1.00059 × 130e-6
    / 1e-15 = 1.15172 m by hand. The warning read "u piles up against its upper bound 1.15172 (…)"
    beside a report in µm; now it gives the unit, as its q95 did."""
    bound = 8.8541878128e-12 * 1.00059 * AREA / 1e-15
    assert f"{bound:g}" == "1.15172"
    (warning,) = [w for w in gap.warnings if w.startswith("sampling: u piles up against its upper bound")]
    assert warning.startswith("sampling: u piles up against its upper bound 1.15172 m ("), warning


def test_a_force_band_over_decades_is_drawn_on_a_log_axis_where_the_median_shows(figure):
    """No air gap here: u's draws reach from 0.7 µm to the prior's 1.15 m, so the force's 90 % band
    spans pN to N, while its median is µN. A linear axis up to 6.6 N drew that median on the zero
    line (0.0001 % of the axis' height); now it stands clear of both ends of a log axis."""
    ax = figure.axes[2]
    (median,) = [l for l in ax.get_lines() if l.get_label().startswith("with EP branch")]
    y = np.asarray(median.get_ydata(), float)
    assert ax.get_yscale() == "log" and "[N]" in ax.get_ylabel()
    low, high = ax.get_ylim()
    share = (np.log10(y) - np.log10(low)) / (np.log10(high) - np.log10(low))  # (height in the axis, 0–1)
    assert np.all((share > 0.05) & (share < 0.95)), share


def test_a_single_contacts_force_is_flat_in_the_json_as_in_the_report(gap):
    """A single contact: C_gap carries the whole V0 at every frequency, so F = ½ ε0 ε_gap A V0²/u²
    does not depend on frequency; the JSON's force_max_n.band_edge said "fmin" (rising past 1 Hz)."""
    assert gap.force_at_max()["band_edge"] == "flat" and gap.force_at_max("without_ep")["band_edge"] == "flat"
    assert "at every frequency" in gap.report()


def test_the_remaining_impedance_panel_wears_the_fit_figure_colours(figure):
    """The remaining-impedance panel draws the data as every spectrum figure does (blue open
    circles, `plot_spectrum`), the fitted EDL model orange and the naive C_gap-only start grey
    dashed, as `refine --plot` draws a start (the data were black and the naive fit blue, the
    data's colour elsewhere). Oracle: the colours of `plot_spectrum`'s data and model lines."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import to_rgba

    from impedax.plotting import plot_spectrum

    fit_fig = plot_spectrum(ix.load(DFR), ix.load(DFR))
    (data_line,) = [l for l in fit_fig.axes[0].get_lines() if l.get_label() == "data"]
    (model_line,) = [l for l in fit_fig.axes[0].get_lines() if l.get_label() == "model"]
    lines = {l.get_label(): l for l in figure.axes[0].get_lines()}
    data = next(l for label, l in lines.items() if label.startswith("Z"))
    naive = next(l for label, l in lines.items() if label.startswith("C_gap only"))
    edl = next(l for label, l in lines.items() if label.startswith("R_EP"))
    assert to_rgba(data.get_color()) == to_rgba(data_line.get_color()) and data.get_marker() == "o" and data.get_markerfacecolor() == "none"
    assert to_rgba(edl.get_color()) == to_rgba(model_line.get_color())
    assert to_rgba(naive.get_color())[:3] == to_rgba("0.5")[:3] and naive.get_linestyle() == "--"
    plt.close(fit_fig)


def test_no_legend_lies_over_the_posteriors_bars_or_the_points(figure):
    """u's draws here fill the histogram panel from 0.7 µm to the prior's bound: its legend of
    three entries lay over the bars at 0.8–5 µm (2026-12-07 walkthrough). Oracle: a 5 × 5 grid over
    every bar with a height, and the lines' points, against each legend's box after the layout."""
    from matplotlib.container import BarContainer

    figure.canvas.draw()
    bars = [b for ax in figure.axes for c in ax.containers if isinstance(c, BarContainer) for b in c.patches if b.get_height() > 0]
    assert len(bars) > 20  # (the histogram of u)
    t = np.linspace(0.0, 1.0, 5)
    for ax in figure.axes:
        legend = ax.get_legend()
        if legend is None:
            continue
        box = legend.get_window_extent()
        points = [line.get_transform().transform(line.get_xydata()) for line in ax.get_lines() if line.get_marker() not in ("None", "", " ", None)]
        for b in (b for b in bars if b.axes is ax):
            x, y = np.meshgrid(b.get_x() + b.get_width() * t, b.get_y() + b.get_height() * t)
            points.append(b.get_transform().transform(np.column_stack([x.ravel(), y.ravel()])))
        xy = np.concatenate(points) if points else np.empty((0, 2))
        frame = ax.get_window_extent()
        xy = xy[(xy[:, 0] >= frame.x0) & (xy[:, 0] <= frame.x1) & (xy[:, 1] >= frame.y0) & (xy[:, 1] <= frame.y1)]
        under = (xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1)
        assert not under.any(), f"{int(under.sum())} points under the legend of {ax.get_title()!r}"
