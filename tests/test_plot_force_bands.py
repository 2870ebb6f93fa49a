"""The demo's force figure (step5_force.png, `plot_force_bands`) labels its log force axis as
the other figures' log axes do (`plain_log_ticks`: 40, 60, 200, 400), not in matplotlib's
mathtext (walkthrough: "4×10², 6×10¹"). Oracle: the tick label texts on an Agg canvas; the
bands are SYNTHETIC, made here with numpy."""

from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from impedax.plotting.models import plot_force_bands  # noqa: E402
from tick_labels import labels_in_view  # noqa: E402


def test_the_log_force_axis_has_plain_tick_labels():
    """SYNTHETIC: a peak force of 0.45 N falling to 60 mN at the band's ends (a decade, where
    matplotlib labels minor ticks 6×10¹, 2×10², 4×10²), with a gap voltage on the twin axis."""
    freq = np.geomspace(10.0, 1e5, 41)
    bell = np.exp(-0.5 * ((np.log10(freq) - 3.0) / 0.8) ** 2)
    force = 0.06 + 0.39 * bell  # [N]: 57 mN (the lower band at 10 Hz) to 490 mN
    volts = 75.0 * np.sqrt(bell)
    data = {}
    for key, s in (("median", 1.0), ("q05", 0.93), ("q95", 1.08)):
        data[key] = (("branch", "frequency"), np.stack([force * s, 0.8 * force * s]))
    data["gap_voltage_median"] = (("branch", "frequency"), np.stack([volts, 0.9 * volts]))
    gap = SimpleNamespace(force=xr.Dataset(data, coords={"branch": ["with_ep", "without_ep"], "frequency": freq}), v0=75.0)
    fig = plot_force_bands(gap)
    fig.canvas.draw()
    ax = fig.axes[0]
    assert ax.get_yscale() == "log" and "[mN]" in ax.get_ylabel()
    texts = [t for t, _ in labels_in_view(ax.yaxis, fig.canvas.get_renderer())]
    assert len(texts) >= 3, texts
    assert all("10^" not in t and "×10" not in t and "$" not in t for t in texts), texts
    assert {"100", "200"} <= set(texts), texts  # (the numbers as printed, in mN)
    plt.close(fig)
