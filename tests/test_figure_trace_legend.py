"""The trace plot's legend ("median of the walkers") off the draws: inside the first row's upper
left it lay over the walkers' lines, which fill a converged chain's panel from edge to edge (the
REAL exampleDataZPlot.z sample, 64 walkers, 2026-12-07). Oracle: the legend's box on the drawn
figure against the walkers' own points (their data through the axes' transform) and against the
row's τ title; the draws are SYNTHETIC (a stationary chain, fixed seed)."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from impedax.plotting.bayes import plot_trace  # noqa: E402


def test_the_trace_legend_lies_off_the_walkers():
    rng = np.random.default_rng(4)
    draws = np.stack([20.0 + 0.2 * rng.standard_normal((32, 150)), 500.0 + 5.0 * rng.standard_normal((32, 150))], axis=-1)
    fig = plot_trace(draws, ["R0", "R1"], [False, False], units=["Ohm", "Ohm"], first_step=50, autocorr={"R0": 1.0, "R1": 1.0})
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    legend = ax.get_legend()
    assert [t.get_text() for t in legend.get_texts()] == ["median of the walkers"]
    box = legend.get_window_extent(renderer)
    points = np.concatenate([ax.transData.transform(np.column_stack([line.get_xdata(), line.get_ydata()])) for line in ax.get_lines()])
    inside = (points[:, 0] >= box.x0) & (points[:, 0] <= box.x1) & (points[:, 1] >= box.y0) & (points[:, 1] <= box.y1)
    assert not inside.any(), f"{inside.sum()} walker points under the legend"
    assert ax._right_title.get_text() == "τ = 1 steps"
    assert not box.overlaps(ax._right_title.get_window_extent(renderer))
    assert fig.bbox.contains(box.x0, box.y0) and fig.bbox.contains(box.x1, box.y1)
    plt.close(fig)
