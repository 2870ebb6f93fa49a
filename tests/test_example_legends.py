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


def _saved_figures(script: str, tmp_path) -> dict:
    """{file name: Figure} of ``script`` run with --fast, each kept open where the script saves it."""
    figures = {}
    with pytest.MonkeyPatch.context() as monkeypatch:
        monkeypatch.syspath_prepend(str(EXAMPLES_DIR))
        import _example

        def keep(fig, args, name):
            fig.canvas.draw()
            figures[name] = fig
            return args.out / name

        monkeypatch.setattr(_example, "save", keep)
        module = __import__(script)
        module.main([str(tmp_path), "--fast"])
    return figures


@pytest.fixture(scope="module")
def meyer_figures(tmp_path_factory):
    figures = _saved_figures("meyer_rc_vs_cpe", tmp_path_factory.mktemp("meyer"))
    yield figures
    for fig in figures.values():
        plt.close(fig)


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
def test_meyer_rc_vs_cpe_legends_cover_no_point_or_curve(meyer_figures):
    figures = meyer_figures
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


@pytest.mark.slow  # (the same run)
def test_meyer_rc_vs_cpe_magnitude_axis_reads_plain_labels_at_both_ends(meyer_figures):
    """|Z| of 2 kΩ to 130 kΩ read 10⁴ and 10⁵ alone (mathtext, no label below the lowest point):
    impedax's |Z| rule (`plotting.magnitude_axis`) labels a tick at or below the lowest point and
    one at or above the highest, as plain numbers (2k … 200k)."""
    fig = meyer_figures["meyer_fig5_3_rc_vs_cpe_impedance.png"]
    ax = next(a for a in fig.axes if a.get_ylabel() == "|Z| [Ω]")
    renderer = fig.canvas.get_renderer()
    lo, hi = sorted(ax.get_ylim())
    ticks = [t for t in ax.yaxis.get_major_ticks() + ax.yaxis.get_minor_ticks() if lo * (1 - 1e-9) <= t.get_loc() <= hi * (1 + 1e-9) and t.label1.get_visible() and t.label1.get_text()]
    texts = [t.label1.get_text() for t in ticks]
    assert len(ticks) >= 2 and not any("$" in text for text in texts), texts
    for tick in ticks:  # each reads back as its value (k: 10³)
        text = tick.label1.get_text()
        assert (float(text[:-1]) * 1e3 if text.endswith("k") else float(text)) == pytest.approx(tick.get_loc(), rel=1e-6), text
    points = np.concatenate([np.abs(line.get_ydata()) for line in ax.get_lines() if line.get_marker() not in (None, "None", "none", "")])
    locs = [t.get_loc() for t in ticks]
    assert min(locs) <= points.min() and max(locs) >= points.max(), (texts, points.min(), points.max())
    boxes = [t.label1.get_window_extent(renderer) for t in ticks]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :]), texts
