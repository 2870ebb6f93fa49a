"""A corner plot's diagonal histogram is on its column's x range, so its median and 5/95 % lines
read right against the column's labelled bottom axis (walkthrough: REAL BioLogic's R0
histogram spanned 62.10–64.96 Ω over scatter panels of 62.24–64.65 Ω, its q95 line at 64.03
read 63.87 on the bottom axis). Oracle: matplotlib's view limits and display transforms on an
Agg canvas; the draws are SYNTHETIC, made here with numpy."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from impedax.plotting.bayes import plot_corner  # noqa: E402


def test_each_histogram_shares_its_columns_range_and_reads_right_on_its_axis():
    """SYNTHETIC: 40 000 draws, 4 000 of them in the scatter, so the histograms (every draw,
    their extremes) would span wider than the scatter; one log-spread parameter."""
    rng = np.random.default_rng(1)
    n = 40_000
    draws = np.c_[rng.normal(63.56, 0.28, n), rng.normal(48.2, 0.95, n), np.exp(rng.normal(np.log(1e-3), 1.5, n)), rng.normal(0.915, 0.02, n)]
    names = ["R0", "R1", "C1", "alpha"]
    fig = plot_corner(draws, names, [True, True, True, False], units=["Ohm", "Ohm", "F", ""])
    fig.canvas.draw()
    k = len(names)
    axes = np.array(fig.axes).reshape(k, k)
    assert axes[2, 2].get_xscale() == "log"  # (the case: a log column too)
    for i in range(k):
        diagonal = axes[i, i]
        for below in axes[i + 1 :, i]:
            assert below.get_xlim() == diagonal.get_xlim(), names[i]
        for beside in axes[i, :i]:  # (the row's y axes: the same parameter, the same range)
            assert beside.get_ylim() == diagonal.get_xlim(), names[i]
        # the 5/50/95 % lines, read against the column's bottom axis, where the panel's x labels are
        bottom = axes[k - 1, i]
        expected = np.quantile(draws[:, i], [0.05, 0.5, 0.95])
        drawn = sorted(line.get_xdata()[0] for line in diagonal.get_lines())
        read = [bottom.transData.inverted().transform(diagonal.transData.transform((x, 0.5)))[0] for x in drawn]
        np.testing.assert_allclose(read, expected, rtol=1e-6)
    plt.close(fig)


def test_a_narrow_dimensionless_column_has_no_offset_text_over_its_label():
    """Corner columns of α about 0.85 and sigma_rel about 1e-5, each spanning 1e-5 of its value
    (SYNTHETIC noise-free data): the offset "1e−5+8.499e−1" under the α column ran over its label
    "CPE1.alpha" and the next column's. Their ticks carry the values (`PlainTicks`), no offset
    text is drawn, and no two tick labels of a column overlap (matplotlib's text boxes)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from impedax.plotting.bayes import plot_corner

    rng = np.random.default_rng(8)
    centres = np.array([20.0, 0.8499, 1.02e-5])
    flat = centres * (1 + 1e-5 * rng.standard_normal((3000, 3)))
    fig = plot_corner(flat, ["R0", "CPE1.alpha", "sigma_rel"], [True, False, False], units=["Ω", "", ""])
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            assert axis.get_offset_text().get_text() == "" or not axis.get_offset_text().get_visible(), (ax.get_xlabel(), ax.get_ylabel())
            boxes = [t.get_window_extent(renderer) for t in axis.get_ticklabels() if t.get_visible() and t.get_text()]
            boxes = [b for b in boxes if ax.get_window_extent(renderer).expanded(1.2, 1.2).overlaps(b)]
            assert not any(a.overlaps(b) for n, a in enumerate(boxes) for b in boxes[n + 1 :]), (ax.get_xlabel(), [t.get_text() for t in axis.get_ticklabels()])
    plt.close(fig)
