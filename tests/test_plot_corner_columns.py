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
