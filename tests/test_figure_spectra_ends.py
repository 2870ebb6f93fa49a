"""The first and last spectrum of a batch's panels drawn inside the frame: on the REAL 130-cycle
battery set (benchmarks/data/autoeis_battery_130.nc) the x range −0.5 … 129.5 left half a
spectrum's width, 0.75 pt on a panel 195 pt wide, and the markers of cycles 0 and 129 (radius
1.5 pt) stood cut in half by the left and right frame of every parameter panel of the batch
fit's figure and of the rms_rel panels under the residual, KK and DRT maps (2026-12-07). Oracle:
each marker's centre on the drawn figure (its data through the axes' transform) against the
panel's box, in points; the maps' cells from their mesh's own coordinates."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import QuadMesh  # noqa: E402
from matplotlib.colors import to_rgb  # noqa: E402

import impedax as ix  # noqa: E402
from test_plot_rms_panel_frame import _room  # noqa: E402

BATTERY = Path(__file__).resolve().parents[1] / "benchmarks" / "data" / "autoeis_battery_130.nc"
GAP_PT = 3.0  # the free space [pt] a marker keeps from the frame


def _side_room(ax) -> float:
    """The smallest distance [pt] between a marker's edge (its centre ± markersize / 2) and the
    left or right of ``ax``'s frame, over its lines with markers."""
    return _room(ax, across=True)


@pytest.fixture(scope="module")
def battery():
    return ix.load(BATTERY)


@pytest.fixture(scope="module")
def battery_fit(battery):
    """REAL: R0 + R1 || CPE1 on the 130 cycles."""
    return ix.fit("R0 + R1 || CPE1", battery)


def test_the_batch_fit_panels_keep_their_end_markers_inside(battery_fit):
    """Every parameter panel and the rms_rel panel: cycles 0 and 129 `GAP_PT` inside the frame,
    their labels still on the axis."""
    fig = battery_fit.plot()
    panels = [ax for ax in fig.axes if ax.get_xlabel() == "cycle"]
    assert len(panels) == 5  # R0, R1, CPE1.Q, CPE1.alpha, rms_rel
    for ax in panels:
        assert _side_room(ax) >= GAP_PT, ax.get_title()
        lo, hi = ax.get_xlim()
        assert lo < 0 and hi > 129
    plt.close(fig)


def _map_cells(ax) -> tuple[float, float]:
    """The x extent of ``ax``'s colour map, from its mesh's coordinates."""
    (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
    x = np.asarray(mesh.get_coordinates())[..., 0]
    return float(x.min()), float(x.max())


def _grey_beyond(ax, lo: float, hi: float) -> bool:
    """Whether a patch that is not white covers x from ``lo`` to ``hi`` of ``ax`` (data units)."""
    for patch in ax.patches:
        xs = patch.get_transform().transform(patch.get_path().vertices)[:, 0]
        left, right = ax.transData.transform([(lo, 0.0), (hi, 0.0)])[:, 0]
        if xs.min() <= left + 0.5 and xs.max() >= right - 0.5 and to_rgb(patch.get_facecolor()) != (1.0, 1.0, 1.0):
            return True
    return False


def _check_map_ends(ax_rms, maps, n):
    assert _side_room(ax_rms) >= GAP_PT
    lo, hi = ax_rms.get_xlim()
    for ax in maps:
        assert ax.get_xlim() == (lo, hi)  # (shared: the map's cell k over point k)
        assert _map_cells(ax) == (-0.5, n - 0.5)
        # (the margin beyond the cells grey, not the white of a residual of 0)
        assert _grey_beyond(ax, lo, -0.5) and _grey_beyond(ax, n - 0.5, hi)


def test_the_residual_map_keeps_the_rms_panels_end_markers_inside(battery_fit):
    """The rms_rel panel under the residual maps: cycles 0 and 129 `GAP_PT` inside; the maps'
    cells still −0.5 … 129.5 on the shared x axis, the margin beside them grey."""
    fig = battery_fit.plot_residual_map()
    ax_re, ax_im, ax_rms = fig.axes[:3]
    assert ax_rms.get_xlabel() == "cycle"
    _check_map_ends(ax_rms, (ax_re, ax_im), 130)
    plt.close(fig)


def test_the_kk_batch_map_keeps_the_rms_panels_end_markers_inside(battery):
    """The KK test of the 130 cycles: its rms_rel panel and map, as the residual map's."""
    fig = ix.kk_test_batch(battery).plot()
    ax_map, ax_rms = fig.axes[:2]
    assert ax_rms.get_xlabel() == "cycle"
    _check_map_ends(ax_rms, (ax_map,), 130)
    plt.close(fig)


def test_the_drt_batch_map_keeps_the_rms_panels_end_markers_inside(battery):
    """The DRT of the 130 cycles: its rms_rel panel (fig.axes[1]) and γ map (fig.axes[2])."""
    fig = ix.drt(battery).plot()
    ax_rms, ax_map = fig.axes[1], fig.axes[2]
    assert ax_rms.get_ylabel() == "DRT fit rms_rel [%]"
    _check_map_ends(ax_rms, (ax_map,), 130)
    plt.close(fig)
