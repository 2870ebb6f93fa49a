"""Every frequency axis of `plot_spectrum` that stands apart from the residual panel names its
quantity and unit: with the Nyquist panel across the top (a flat spectrum, REAL ZPlot), the
|Z| and phase panels side by side carried no axis label, their ticks differing in pixels from
the residual panel's below them, which alone read "frequency [Hz]" (`impedax fit`, `kk`,
`diagnose --plot`; `compare --plot` labelled them). Stacked in one column (a steep spectrum,
REAL CH Instruments), the panels share the residual panel's axis, which names it once.
Oracle: the axis label texts of the Figure, and the axes' columns."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.plotting import plot_spectrum  # noqa: E402

REAL = Path(__file__).parent / "fixtures" / "real"


def _figure(name):
    data = ix.load(REAL / name)
    z = data["Z"].values
    return plot_spectrum(data, (data["frequency"].values, z * 1.01))


def test_side_by_side_bode_panels_name_the_frequency_axis():
    fig = _figure("exampleDataZPlot.z")
    fig.canvas.draw()
    _, ax_mod, ax_ph, ax_res = fig.axes
    assert ax_mod.get_position().x1 < ax_ph.get_position().x0  # (side by side)
    for ax in (ax_mod, ax_ph, ax_res):
        assert ax.get_xlabel() == "frequency [Hz]", ax.get_ylabel()
        renderer = fig.canvas.get_renderer()
        label = ax.xaxis.label.get_window_extent(renderer)
        for other in fig.axes:  # (the label inside the figure and off every other panel)
            if other is not ax:
                assert not label.overlaps(other.get_window_extent(renderer)), (ax.get_ylabel(), other.get_ylabel())
    plt.close(fig)


def test_stacked_bode_panels_leave_the_axis_name_to_the_residual_panel():
    fig = _figure("exampleDataCHInstruments.txt")
    _, ax_mod, ax_ph, ax_res = fig.axes
    assert np.isclose(ax_mod.get_position().x0, ax_res.get_position().x0)  # (one column)
    assert ax_res.get_xlabel() == "frequency [Hz]" and ax_ph.get_xlabel() == "" and ax_mod.get_xlabel() == ""
    plt.close(fig)


def test_the_kk_figure_names_its_side_by_side_frequency_axes():
    """`impedax kk --plot` on REAL ZPlot: the |Z| and phase panels side by side read
    "frequency [Hz]", as the fit's do."""
    from impedax.fitting.kk import kk_test

    fig = kk_test(ix.load(REAL / "exampleDataZPlot.z")).plot()
    _, ax_mod, ax_ph, ax_res = fig.axes[:4]
    assert [ax.get_xlabel() for ax in (ax_mod, ax_ph, ax_res)] == ["frequency [Hz]"] * 3
    plt.close(fig)
