"""The fit's figure keeps its legends off the data: on the pyimpspec-format file data.dfr (its
test circuit's spectrum as the instrument software wrote it), fitted with R0 + R1 || CPE1 +
R2 || CPE2, the residual panel's legend (Re, Im and the rounding-level entry) stood in the lower
left over the Re residuals from 10 to 14 Hz (2026-12-07). Oracle: the legend's box on the drawn
figure against the panel's own lines (their vertices through the axes' transform, with points
along each segment between them)."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import impedax as ix  # noqa: E402

REAL = Path(__file__).resolve().parent / "fixtures" / "real"


def _points_under(ax, box) -> int:
    """How many drawn points of ``ax``'s lines (vertices and 20 points along each segment, inside
    the frame) lie in ``box``."""
    frame = ax.get_window_extent()
    count = 0
    for line in ax.get_lines():
        xy = line.get_transform().transform(np.asarray(line.get_xydata(), float))
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if len(xy) > 1 and line.get_linestyle() not in ("None", "none", "", " "):
            t = np.linspace(0.0, 1.0, 21)[:, None, None]
            xy = (xy[:-1][None] * (1 - t) + xy[1:][None] * t).reshape(-1, 2)
        xy = xy[(xy[:, 0] >= frame.x0) & (xy[:, 0] <= frame.x1) & (xy[:, 1] >= frame.y0) & (xy[:, 1] <= frame.y1)]
        count += int(np.sum((xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1)))
    return count


def test_the_fit_figure_s_legends_lie_off_its_data():
    fit = ix.fit("R0 + R1 || CPE1 + R2 || CPE2", ix.load(REAL / "data.dfr"))
    fig = fit.plot()
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    ax_res = fig.axes[3]
    assert ax_res.get_ylabel().startswith("residual")
    texts = [t.get_text() for t in ax_res.get_legend().get_texts()]
    assert texts[:2] == ["Re", "Im"] and texts[2].startswith("rounding level")
    for ax in fig.axes:
        legend = ax.get_legend()
        if legend is not None:
            assert _points_under(ax, legend.get_window_extent(renderer)) == 0, ax.get_ylabel()
    plt.close(fig)


def test_the_zhit_figure_s_legends_lie_off_its_data_and_rule_levels():
    """REAL exampleData.csv, Z-HIT: the residual legend (the two rules' levels) sat in the upper
    right on the point rule's dashed line at +5.02 %, which it names."""
    fig = ix.zhit(ix.load(REAL / "exampleData.csv")).plot()
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    ax_res = fig.axes[2]
    assert [t.get_text() for t in ax_res.get_legend().get_texts()][0].startswith("point rule")
    for ax in fig.axes:
        legend = ax.get_legend()
        if legend is not None:
            assert _points_under(ax, legend.get_window_extent(renderer)) == 0, ax.get_ylabel()
    plt.close(fig)
