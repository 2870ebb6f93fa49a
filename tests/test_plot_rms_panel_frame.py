"""The rms_rel panel of a batch's DRT figure frames its points: on the REAL 130-cycle battery set
(benchmarks/data/autoeis_battery_130.nc) the panel is about 75 pt high, matplotlib's 5 % margin
3.4 pt, and cycle 22's point (rms_rel 0.92 %) stood at the top of the frame (2026-12-07). Oracle:
each marker's centre on the drawn figure (its data through the axes' transform) against the
panel's box, in points: at least the marker's radius plus `GAP_PT` inside."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from impedax.plotting import frame_points  # noqa: E402

BATTERY = Path(__file__).resolve().parents[1] / "benchmarks" / "data" / "autoeis_battery_130.nc"
GAP_PT = 3.0  # the free space [pt] a framed marker keeps from the frame


def _room(ax, *, across: bool = False):
    """The smallest distance [pt] between a marker's edge (a line's points, its markersize / 2
    from the centre) and the top or bottom of ``ax``'s frame; lines without markers count with
    radius 0. ``across``: the left or right of the frame, over the lines with markers (a line
    without, an axhline, spans the frame)."""
    fig = ax.get_figure()
    fig.draw_without_rendering()
    box = ax.get_window_extent()
    to_pt = 72.0 / fig.dpi
    room = np.inf
    for line in ax.get_lines():
        marked = line.get_marker() not in ("None", None, "", " ")
        if across and not (marked and line.get_visible()):
            continue
        xy = np.asarray(line.get_xydata(), float)
        keep = np.all(np.isfinite(xy), axis=1) & (xy[:, 1] > 0 if ax.get_yscale() == "log" else True)
        if not keep.any():
            continue
        shown = ax.transData.transform(xy[keep])[:, 0 if across else 1]
        low, high = (box.x0, box.x1) if across else (box.y0, box.y1)
        radius = line.get_markersize() / 2 if marked else 0.0
        room = min(room, float(np.min(high - shown)) * to_pt - radius, float(np.min(shown - low)) * to_pt - radius)
    return room


def test_the_drt_batch_rms_panel_frames_its_points():
    """REAL battery cycles: every rms_rel point (and the noise line) ends `GAP_PT` inside the
    panel's top and bottom; cycle 22's point is the highest."""
    import impedax as ix

    batch = ix.drt(ix.load(BATTERY))
    fig = batch.plot()
    ax_rms = fig.axes[1]
    assert ax_rms.get_ylabel() == "DRT fit rms_rel [%]" and ax_rms.get_yscale() == "log"
    rms = np.array([one.rms_rel for one in batch.results]) * 100
    assert int(np.argmax(rms)) == 22  # (the case)
    assert _room(ax_rms) >= GAP_PT
    plt.close(fig)


@pytest.mark.parametrize("scale", ["log", "linear"])
def test_frame_points_keeps_the_room_on_a_short_panel(scale):
    """SYNTHETIC: 40 points from 0.2 to 0.9 on a panel 1 inch high (matplotlib's margin: 5 %
    of the range, about 2.5 pt beside the frame's width); framed, the markers (radius 2 pt)
    keep `GAP_PT` from it, and the range holds what it held."""
    fig, ax = plt.subplots(figsize=(6, 1.3))
    y = np.linspace(0.2, 0.9, 40)[np.random.default_rng(3).permutation(40)]
    ax.plot(np.arange(40), y, "o", ms=4)
    ax.set_yscale(scale)
    before = ax.get_ylim()
    assert _room(ax) < GAP_PT  # (the case)
    frame_points(ax, y)
    assert _room(ax) >= GAP_PT
    after = ax.get_ylim()
    assert after[0] <= before[0] and after[1] >= before[1]
    plt.close(fig)
