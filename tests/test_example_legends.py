"""The example scripts' legends lie over none of the points and curves their panels draw:
meyer_rc_vs_cpe.py's residual legend stood on the fractional model's residuals (docs/gallery),
and its force legend reaches the RC curve's fall above 100 kHz. Oracle: the figures as the
script saves them, laid out on an Agg canvas; each legend's box (`get_window_extent`) against
every vertex of the panel's lines, points put along each segment, and each marker's radius
(matplotlib's display transforms); every spectrum is SYNTHETIC."""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

EXAMPLES_DIR = Path(__file__).resolve().parent.parent / "examples"


def _saved_figures(script: str, tmp_path, monkeypatch) -> dict:
    """{file name: Figure} of ``script`` run with --fast, each kept open where the script saves it."""
    monkeypatch.syspath_prepend(str(EXAMPLES_DIR))
    import _example

    figures = {}

    def keep(fig, args, name):
        fig.canvas.draw()
        figures[name] = fig
        return args.out / name

    monkeypatch.setattr(_example, "save", keep)
    module = __import__(script)
    module.main([str(tmp_path), "--fast"])
    return figures


def _covered(ax) -> list[tuple[float, float]]:
    """The data points [display px] of ``ax``'s lines that its legend's box covers, each marker
    counted with its radius and each segment by 16 points along it."""
    box = ax.get_legend().get_window_extent()
    frame = ax.get_window_extent()
    dpi = ax.get_figure().dpi
    hits = []
    for line in ax.get_lines():
        if not line.get_visible():
            continue
        xy = line.get_transform().transform(np.asarray(line.get_xydata(), float))
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        radius = 0.0
        if line.get_marker() not in (None, "None", "none", "", " "):
            radius = line.get_markersize() / 2 * dpi / 72
        if len(xy) > 1 and line.get_linestyle() not in ("None", "none", "", " "):
            t = np.linspace(0.0, 1.0, 17)[:-1, None]
            xy = np.concatenate([np.concatenate([a + (b - a) * t for a, b in zip(xy[:-1], xy[1:])]), xy[-1:]])
        inside = (xy[:, 0] >= frame.x0) & (xy[:, 0] <= frame.x1) & (xy[:, 1] >= frame.y0) & (xy[:, 1] <= frame.y1)
        for x, y in xy[inside]:
            if box.x0 - radius <= x <= box.x1 + radius and box.y0 - radius <= y <= box.y1 + radius:
                hits.append((line.get_label(), float(x), float(y)))
    return hits


@pytest.mark.slow  # (the script's fits and sampling, 15 s)
def test_meyer_rc_vs_cpe_legends_cover_no_point_or_curve(tmp_path, monkeypatch):
    figures = _saved_figures("meyer_rc_vs_cpe", tmp_path, monkeypatch)
    try:
        assert set(figures) == {"meyer_fig5_3_rc_vs_cpe_impedance.png", "meyer_fig5_1b_force_rc_vs_cpe.png"}
        legends = 0
        for name, fig in figures.items():
            for ax in fig.axes:
                if ax.get_legend() is None:
                    continue
                legends += 1
                hits = _covered(ax)
                assert not hits, (name, ax.get_title(), hits[:5])
                # and inside the figure (a legend moved out of its panel stays on the canvas)
                box, canvas = ax.get_legend().get_window_extent(), fig.bbox
                assert canvas.x0 <= box.x0 and box.x1 <= canvas.x1 and canvas.y0 <= box.y0 and box.y1 <= canvas.y1, (name, ax.get_title())
        assert legends == 4  # |Z|, phase, residuals; force
    finally:
        for fig in figures.values():
            plt.close(fig)
