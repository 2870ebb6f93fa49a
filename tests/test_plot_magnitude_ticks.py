"""Every log |Z| axis labels a tick at or below its lowest point and one at or above its highest,
two at least (`plotting.magnitude_axis`). |Z| from 150 to 450 Ω was labelled 200, 300, 400 (none
at or below 150), on a 6.3 × 5 in figure |Z| from 15 to 70 Ω only 20 and 50, and a gap
analysis' |Z_R| from 4.5 kΩ to 50 MΩ from 10k up (2026-12-07). Oracle: the tick labels of the
drawn figure read back as numbers (with the prefix of the label's brackets or their own) and
checked against their ticks' positions, and the |Z| of the arrays drawn; SYNTHETIC spectra of
R0 + R1 || C1 written here with numpy."""

import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from impedax.plotting import plot_bode, plot_spectrum  # noqa: E402

PREFIXES = {"": 1.0, "k": 1e3, "M": 1e6, "G": 1e9, "m": 1e-3, "µ": 1e-6}
F = np.geomspace(1.0, 1e5, 51)


def _rc(low: float, high: float):
    """|Z| from ``high`` (R0 + R1) at low frequency to ``low`` (R0) at high frequency."""
    return low + (high - low) / (1 + 2j * np.pi * F * (high - low) * 1e-6)


def _labels(ax):
    """The labelled ticks of ``ax``'s y axis in view, as values [Ω] read from their texts."""
    fig = ax.get_figure()
    fig.draw_without_rendering()
    axis = ax.yaxis
    unit = re.search(r"\[(.*?)Ω\]", ax.get_ylabel()).group(1)
    lo, hi = sorted(axis.get_view_interval())
    values = []
    for minor in (False, True):
        locs = axis.get_minorticklocs() if minor else axis.get_majorticklocs()
        ticks = (axis.get_minor_ticks if minor else axis.get_major_ticks)(len(locs))
        for loc, tick in zip(locs, ticks):
            text = tick.label1.get_text().replace("\N{MINUS SIGN}", "-")
            if not text or not lo * (1 - 1e-9) <= loc <= hi * (1 + 1e-9):
                continue
            own = text[-1] if text[-1] in PREFIXES else ""
            value = float(text[: len(text) - len(own)]) * PREFIXES[own] * PREFIXES[unit]
            assert value == pytest.approx(loc, rel=1e-6), (text, loc)  # (the label is its tick's value)
            values.append(value)
    return sorted(values)


# the farthest an axis reaches beyond its data: half a decade (the demo's naive fit read to
# 10000 MΩ above a highest point of 166 MΩ, 1.8 decades)
REACH = 10**0.5


def _assert_spans(ax, magnitudes):
    """Labelled ticks at or beyond the lowest and the highest of ``magnitudes``, two at least;
    on an axis labelled at decades (or every other decade) whose next label lies more than half a
    decade past the data, that end stays within half a decade of the data instead."""
    shown = _labels(ax)
    assert len(shown) >= 2, shown
    low, high = min(magnitudes), max(magnitudes)
    lo, hi = sorted(ax.get_ylim())
    assert lo >= low / REACH * (1 - 1e-9) and hi <= high * REACH * (1 + 1e-9), ((lo, hi), (low, high))
    stride = shown[-1] / shown[-2] if shown[-1] / shown[-2] >= 10 * (1 - 1e-9) else None  # (labels at decades: the next one lies a stride on)
    assert min(shown) <= low * (1 + 1e-9) or (stride and min(shown) / stride < low / REACH), (shown, low)
    assert max(shown) >= high * (1 - 1e-9) or (stride and max(shown) * stride > high * REACH), (shown, high)
    return shown


@pytest.mark.parametrize("low, high", [(150, 450), (160, 340), (101, 184), (15, 70), (1500, 9000), (20, 520), (1325, 1.14e6), (0.021, 0.035)])
@pytest.mark.parametrize("figsize", [None, (6.3, 5.0)])
def test_the_modulus_panel_labels_ticks_around_its_data(low, high, figsize):
    """`plot_spectrum` (the fit's, KK's, diagnosis' |Z| panel through `plot_bode`): a SYNTHETIC
    arc over a factor 1.7 to 860 in |Z|, in Ω, kΩ or mΩ, at the default size and at a thesis
    text width."""
    z = _rc(low, high)
    model = z * (1 + 1e-3)
    fig = plot_spectrum((F, z), (F, model), figsize=figsize)
    _assert_spans(fig.axes[1], np.abs(np.concatenate([z, model])))
    plt.close(fig)


def test_plot_bode_on_your_own_axes_spans_the_data():
    """docs/io.md's `plot_bode(ax_mod, ax_ph, data, model)` on axes of one's own (6.3 × 2.4 in)."""
    z = _rc(150, 450)
    fig, (ax_nyq, ax_mod, ax_ph) = plt.subplots(1, 3, figsize=(6.3, 2.4), layout="constrained")
    plot_bode(ax_mod, ax_ph, (F, z), (F, z))
    _assert_spans(ax_mod, np.abs(z))
    plt.close(fig)


def test_a_zoom_is_left_as_set():
    """A range set by hand after the figure is made (a zoom into 200 – 300 Ω) is not widened."""
    z = _rc(150, 450)
    fig = plot_spectrum((F, z), (F, z))
    ax = fig.axes[1]
    ax.set_ylim(200, 300)
    fig.draw_without_rendering()
    assert ax.get_ylim() == (200, 300)
    plt.close(fig)


def test_the_gap_figures_remaining_impedance_spans_its_data():
    """The gap analysis' |Z_R| panel (its range set from the data, a runaway model cut): a
    SYNTHETIC R_EP ∥ C_gap of 3 repeats, 4.5 kΩ to 50 MΩ (`test_gap_outputs`' stub, as the
    figure draws it): labelled up to at or above the highest point; at its bottom, where the
    decade below 4.5 kΩ lies 0.65 decades down, the axis ends within half a decade of it and
    10k is the lowest label."""
    from test_gap_outputs import _stub

    gap = _stub(rhat_max=1.001)
    fig = gap.plot()
    ax = fig.axes[0]
    assert ax.get_yscale() == "log" and "|Z_R|" in ax.get_ylabel()
    drawn = np.abs(gap.remaining["Z"].values)
    _assert_spans(ax, drawn)
    plt.close(fig)


def test_a_range_just_past_a_decade_ends_near_its_data():
    """|Z| from 57 to 112 Ω (the span of REAL exampleDataBioLogic.mpt, here a SYNTHETIC arc):
    the range ends at a labelled 120, not at the next minor tick, 200, which left the top 40 %
    of the panel empty; the bottom at 50."""
    z = _rc(57, 112)
    fig = plot_spectrum((F, z), (F, z))
    ax = fig.axes[1]
    shown = _assert_spans(ax, np.abs(z))
    assert ax.get_ylim()[1] <= 1.3 * 112 and 120 in shown
    assert 50 in shown and ax.get_ylim()[0] >= 50 * (1 - 1e-9)
    plt.close(fig)


def test_a_wide_axis_ends_at_a_decade_and_a_skipped_value_at_an_end_is_labelled():
    """|Z| over two and a half decades (SYNTHETIC R0 + R1 || C1: 1 kΩ + 500 kΩ ∥ 2 nF, 2.6 to
    501 kΩ; its labels are decades) ends at a decade, 1 MΩ, labelled, not at 1.2 or 2 MΩ beside
    decade labels; over 1.4 decades (20 to 520 Ω, labels 20, 50, 100, 200, 500) its top, 800,
    is labelled though the axis' minor labels skip 8. 1 kΩ + 1 MΩ ∥ 1 nF reaches 1.00098 MΩ, a
    decade below the next label, 10 MΩ: its top stays within half a decade of the data, the
    last label 1 MΩ (it read to 10 MΩ)."""
    wide = 1e3 + 0.5e6 / (1 + 2j * np.pi * F * 0.5e6 * 2e-9)
    for z, top in ((wide, 1e6), (_rc(20, 520), 800)):
        fig = plot_spectrum((F, z), (F, z))
        ax = fig.axes[1]
        shown = _assert_spans(ax, np.abs(z))
        assert ax.get_ylim()[1] == pytest.approx(top) and max(shown) == pytest.approx(top), shown
        plt.close(fig)
    over = 1e3 + 1e6 / (1 + 2j * np.pi * F * 1e6 * 1e-9)  # (1.00098 MΩ at 1 Hz: 1 MΩ just below it, 10 MΩ a decade above)
    fig = plot_spectrum((F, over), (F, over))
    ax = fig.axes[1]
    shown = _assert_spans(ax, np.abs(over))
    assert ax.get_ylim()[1] <= 1.00098e6 * REACH and max(shown) == pytest.approx(1e6), shown
    plt.close(fig)
