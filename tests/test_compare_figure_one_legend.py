"""The comparison figure (`impedax compare --plot`, `Comparison.plot`) names the models once, in
the Nyquist panel's legend, whose colours and line styles the residual curves share. Four models
on REAL exampleData.csv (2026-12-07 walkthrough): the residual panel repeated that legend, which
went above the panel (`legends_off_data`) and took a third of the height of the |Z|, phase and
residual panels (108 px each of a 740 px figure; 149 px without it). Oracle: the legends and the
panels' boxes on an Agg canvas; the spectrum is SYNTHETIC (numpy)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax as ix  # noqa: E402
from matplotlib.colors import to_rgba  # noqa: E402

MODELS = ("R0 + R1 || C1", "R0 + R1 || CPE1", "R0 + L0 + R1 || CPE1", "R0 + L0 + R1 || CPE1 + R2 || CPE2")


@pytest.fixture(scope="module")
def figure():
    """SYNTHETIC R0 + R1 ∥ CPE1 + R2 ∥ CPE2 (0.1 Ω, 0.3 Ω α 0.8, 0.5 Ω α 0.6), 10 mHz–10 kHz, 1 % noise."""
    f = np.geomspace(0.01, 1e4, 49)
    jw = 2j * np.pi * f
    z = 0.1 + 0.3 / (1 + 0.3 * 0.05 * jw**0.8) + 0.5 / (1 + 0.5 * 2.0 * jw**0.6)
    rng = np.random.default_rng(11)
    data = ix.make_spectrum(f, z * (1 + 0.01 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))))
    fig = ix.compare([ix.fit(m, data, progress=False) for m in MODELS]).plot()
    fig.canvas.draw()
    yield fig
    plt.close(fig)


def _panel(fig, ylabel):
    """The panel whose y label starts with ``ylabel`` (the Ω axes count in an SI prefix: [mΩ])."""
    return next(ax for ax in fig.axes if ax.get_ylabel().startswith(ylabel))


def test_the_residual_panel_has_no_legend_of_its_own(figure):
    assert _panel(figure, "|relative residual| [%]").get_legend() is None
    assert [ax for ax in figure.axes if ax.get_legend() is not None] == [_panel(figure, "−Z''")]


def test_each_residual_curve_is_named_by_a_nyquist_legend_entry_of_its_colour_and_style(figure):
    legend = _panel(figure, "−Z''").get_legend()
    entries = {(to_rgba(h.get_color()), h.get_linestyle()): t.get_text() for h, t in zip(legend.legend_handles, legend.get_texts()) if t.get_text() != "data"}
    curves = _panel(figure, "|relative residual| [%]").get_lines()
    named = [entries.get((to_rgba(line.get_color()), line.get_linestyle())) for line in curves]
    assert len(curves) == len(MODELS) and all(named), named
    assert [n.split(" (rms_rel")[0] for n in named] == list(MODELS)


def test_the_bode_and_residual_panels_keep_their_height(figure):
    """Each at least a third of the Nyquist panel's height (on REAL exampleData.csv the repeated
    legend left them 0.29 of it)."""
    nyquist = _panel(figure, "−Z''").get_window_extent().height
    for label in ("|Z| [", "phase [deg]", "|relative residual| [%]"):
        assert _panel(figure, label).get_window_extent().height >= nyquist / 3, label
