"""The paper examples' log axes read as impedax's figures read theirs (2026-12-07): frequency
axes by `plotting.frequency_axis` (1, 10, 100, 1000, 10k … 1G), |Z| by `magnitude_axis`, other
log values (admittance, capacitance, voltage, force, thickness) by `plain_log_ticks`; until then
sirin_remaining_impedance.py (Figs 3d, 4a/4b), sirin_mr_pps.py (Figs 4c/4d),
meyer_force_spectrum.py (Fig 3.4) and vezzoli_electrovibration.py (Figs 8, 9) read matplotlib's
10ⁿ on both axes, beside the plain numbers of the other gallery figures. Oracle: the figures as
each script saves them (--fast), drawn on an Agg canvas; every label read back as a number (SI
prefixes by their powers of ten) against its tick's position, the frequency decades' texts
against the hand-written table of tests/test_frequency_axis_ticks.py, and the labels' boxes
apart. Data: SYNTHETIC (the shipped Sirin-style example) and model curves of the papers."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from test_example_legends import _saved_figures  # noqa: E402  (the script run with --fast, its figures kept)
from test_frequency_axis_ticks import DECADE_TEXT, _labels, assert_plain_labels  # noqa: E402  (labels as drawn; plain, read back, apart)

# the frequency decades beyond the table's 1M (Meyer's Fig 3.4 runs to 1 GHz), written by hand
FREQUENCY_DECADES = {**DECADE_TEXT, 1e7: "10M", 1e8: "100M", 1e9: "1G"}

# {script: {figure: the labels of its log axes that show tick labels, in the order of the axes (x, then y)}}
LOG_AXES = {
    "sirin_remaining_impedance": {
        "sirin_fig3d_remaining_impedance.png": ["|Z_R| [Ω]", "frequency [Hz]"],  # (the |Z| panel's own frequency labels hidden by sharex)
        "sirin_fig4ab_admittance_capacitance.png": ["frequency [Hz]", "|Y_R| [S]", "frequency [Hz]", "capacitance [pF]"],
    },
    "sirin_mr_pps": {"sirin_fig4cd_mr_pps.png": ["frequency [Hz]", "frequency [Hz]"]},
    "meyer_force_spectrum": {"meyer_fig3_4_force_spectrum.png": ["frequency [Hz]", "amplitude [V]"]},
    "vezzoli_electrovibration": {"vezzoli_fig8_9_10_electrovibration.png": ["frequency [Hz]", "insulator thickness h_i [µm]", "time-averaged force F_e [mN]"]},
}


@pytest.fixture(scope="module", params=list(LOG_AXES))
def script_figures(request, tmp_path_factory):
    figures = _saved_figures(request.param, tmp_path_factory.mktemp(request.param))
    yield request.param, figures
    for fig in figures.values():
        plt.close(fig)


def _log_axes(fig):
    """The log-scaled axes of ``fig`` that show tick labels, x before y in each panel."""
    return [axis for ax in fig.axes for axis in (ax.xaxis, ax.yaxis) if axis.get_scale() == "log" and _labels(fig, axis)]


def test_every_log_axis_reads_plain_numbers_and_frequencies_as_every_figure(script_figures):
    script, figures = script_figures
    assert set(figures) == set(LOG_AXES[script])
    for name, fig in figures.items():
        axes = _log_axes(fig)
        assert [axis.get_label().get_text() for axis in axes] == LOG_AXES[script][name], name
        for axis in axes:
            label = axis.get_label().get_text()
            assert_plain_labels(fig, axis, (name, label), FREQUENCY_DECADES if label.startswith("frequency") else None)
