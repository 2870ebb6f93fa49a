"""The diagnosis figure's Nyquist panel is shaped to the data, as the comparison's is
(`nyquist_frame`): walkthrough 2026-12-06, `impedax diagnose exampleDataZPlot.z --model
'R0 + R1 || C1' --plot`, whose Z' axis ran to 900 Ω beside data (and curves) that end at 615 Ω:
the panel, at most `TALLEST_PANEL` high, was filled by widening the range, a third of it blank.
Oracles: the REAL ZPlot file and a SYNTHETIC arc written here with numpy; the axis limits and
window extents read back from matplotlib."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.plotting import MODEL_OVERSHOOT, NYQUIST_EDGE_MARGIN  # noqa: E402
from impedax.plotting.diagnosis import plot_diagnosis  # noqa: E402

REAL = Path(__file__).parent / "fixtures" / "real"


def check_shaped_to(fig, z) -> None:
    """The Nyquist panel's Z' and −Z'' ranges end within the margins of the data's span (a
    curve's overshoot, `MODEL_OVERSHOOT`, and matplotlib's 5 % margin, with room to spare), and
    the data take most of the panel's width on screen."""
    fig.canvas.draw()
    ax = fig.axes[0]
    x, y = z.real, -z.imag
    span = max(np.ptp(x), np.ptp(y))
    room = (MODEL_OVERSHOOT + 0.05 + NYQUIST_EDGE_MARGIN + 0.02) * span
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert x0 >= x.min() - room and x1 <= x.max() + room, (ax.get_xlim(), x.min(), x.max())
    assert y0 >= y.min() - room and y1 <= y.max() + room, (ax.get_ylim(), y.min(), y.max())
    frame = ax.get_window_extent()
    ends = ax.transData.transform(np.column_stack([[x.min(), x.max()], [y.min(), y.min()]]))
    assert (ends[1, 0] - ends[0, 0]) / frame.width > 0.75
    # equal scales kept: the box narrowed to the data's shape, the range did not widen
    assert abs(frame.width / (x1 - x0) - frame.height / (y1 - y0)) < 0.02 * frame.width / (x1 - x0)


@pytest.mark.slow  # (the diagnosis of a real file, ~20 s; the stand-in below checks the same in `make test`)
def test_real_zplot_diagnosis_nyquist_panel_follows_the_data():
    data = ix.load(REAL / "exampleDataZPlot.z")
    diagnosis = ix.diagnose(data, "R0 + R1 || C1")
    fig = plot_diagnosis(diagnosis)
    check_shaped_to(fig, diagnosis.baseline.z_data)
    plt.close(fig)


def fit_stand_in(model: str, f, z_model, z_data) -> SimpleNamespace:
    residuals = (z_model - z_data) / np.abs(z_data)
    return SimpleNamespace(model=model, frequency=f, z_data=z_data, z_model=z_model, residuals=residuals, rms_rel=float(np.sqrt(np.mean(np.abs(residuals) ** 2 / 2))))


def test_synthetic_arc_diagnosis_nyquist_panel_follows_the_data():
    """SYNTHETIC: R0 + R1‖C1 (150 Ω + 470 Ω at τ = 15 µs, as ZPlot's arc, 1:2 high to wide,
    whose panel the height cap widens) with 0.3 % noise; a stand-in diagnosis whose baseline is
    1 % off and whose suggestion fits."""
    f = np.geomspace(3e5, 3e3, 20)
    z = 150.0 + 470.0 / (1 + 2j * np.pi * f * 15e-6)
    data = z * (1 + 0.003 * np.random.default_rng(0).standard_normal(f.size))
    best = SimpleNamespace(effect="series_inductance", fit=fit_stand_in("R0 + R1 || C1 + L_lead", f, z, data))
    diagnosis = SimpleNamespace(baseline=fit_stand_in("R0 + R1 || C1", f, z * 1.01, data), failing_bands=[], verdict="missing_effect", best=best)
    fig = plot_diagnosis(diagnosis)
    check_shaped_to(fig, data)
    plt.close(fig)
