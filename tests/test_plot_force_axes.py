"""The gap analysis' two force figures draw the force alike: `impedax gap --plot`'s force panel
(the demo's step4_gap_and_force.png) on a log axis, as the demo's force figure
(step5_force.png, `plot_force_bands`) does. The demo's force falls from 395 mN at 1 Hz to 35 mN
at 1 MHz; the gap figure drew it on a linear axis (log only beyond a 100× span) beside the force
figure's log axis (2026-12-07). Oracle: each figure's axis scale, unit and tick labels read back
from the drawn figure; the bands are SYNTHETIC, made here with numpy (eq 1's V² over a bell)."""

from dataclasses import replace
from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402

from impedax.plotting.models import FORCE_LOG_SPAN, plot_force_bands  # noqa: E402
from test_gap_outputs import _stub  # noqa: E402  (a GapAnalysis built by hand: no fit, no sampling)
from tick_labels import labels_in_view  # noqa: E402

FREQ = np.geomspace(1.0, 1e6, 61)


def _bands(low: float, high: float) -> xr.Dataset:
    """Force bands [N] falling from ``high`` at 1 Hz to ``low`` at 1 MHz (a logistic step in log
    f), ±7 % about the median, without EP 0.8 × with; a gap voltage beside them."""
    step = 1.0 / (1.0 + np.exp(2.0 * (np.log10(FREQ) - 3.0)))
    force = low * (high / low) ** step
    volts = 75.0 * np.sqrt(step)
    data = {}
    for key, s in (("median", 1.0), ("q05", 0.93), ("q95", 1.07)):
        data[key] = (("branch", "frequency"), np.stack([force * s, 0.8 * force * s]))
        data[f"gap_voltage_{key}"] = (("branch", "frequency"), np.stack([volts, 0.9 * volts]))
    return xr.Dataset(data, coords={"branch": ["with_ep", "without_ep"], "frequency": FREQ})


def _force_panels(force):
    """The force axes of the gap figure and of the force figure, drawn."""
    gap_fig = replace(_stub(rhat_max=1.001), force=force).plot()
    force_fig = plot_force_bands(SimpleNamespace(force=force, v0=75.0))
    for fig in (gap_fig, force_fig):
        fig.canvas.draw()
    return (gap_fig, gap_fig.axes[2]), (force_fig, force_fig.axes[0])


@pytest.mark.parametrize("low, high, unit", [(0.035, 0.395, "mN"), (2e-12, 6.6, "N")])
def test_both_force_figures_draw_the_force_on_one_kind_of_axis(low, high, unit):
    """The demo's span, 11× (under `FORCE_LOG_SPAN`), in mN; REAL data.dfr's, pN to 6.6 N, in N.
    Both figures: a log force axis in the same unit, tick labels plain numbers that read back as
    their ticks' values, the median's whole range inside the view."""
    force = _bands(low, high)
    assert (high * 1.07 / (0.8 * low * 0.93) > FORCE_LOG_SPAN) == (unit == "N")  # (the cases)
    drawn = _force_panels(force)
    scale = {"mN": 1e-3, "N": 1.0}[unit]
    prefixes = {"p": 1e-12, "n": 1e-9, "µ": 1e-6, "m": 1e-3, "": 1.0, "k": 1e3}
    for fig, ax in drawn:
        assert ax.get_yscale() == "log", fig
        assert f"[{unit}]" in ax.get_ylabel()
        lo, hi = ax.get_ylim()
        assert lo <= 0.8 * low / scale and hi >= high / scale
        texts = [t for t, _ in labels_in_view(ax.yaxis, fig.canvas.get_renderer())]
        assert len(texts) >= 2, texts
        for text in texts:
            prefix = text[-1] if text[-1] in "pnµmk" else ""
            value = float(text[: len(text) - len(prefix)].replace("\N{MINUS SIGN}", "-")) * prefixes[prefix]
            assert lo <= value <= hi, (text, lo, hi)
            assert "$" not in text and "×" not in text
        plt.close(fig)
    (_, gap_ax), (_, force_ax) = drawn
    assert gap_ax.get_ylabel().split("[")[1].split("]")[0] == force_ax.get_ylabel().split("[")[1].split("]")[0] == unit
