"""A |Z| axis counted in its Nyquist panel's prefix writes no prefix of its own on a tick, and
then writes every value from 10⁴ up in one exponent form: Meyer's finger circuit (`impedax
simulate meyer --plot`, 1.4 kΩ–1.23 GΩ, its Nyquist panel zoomed to kΩ) read "1, 100, 10000,
1e6" [kΩ] (walkthrough 2026-12-07). Oracle: the drawn tick labels against their ticks' positions;
the SYNTHETIC spectrum is eq 3.13's circuit written here with numpy."""

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from impedax.plotting import _plain_number, plot_spectrum  # noqa: E402


def test_meyers_magnitude_axis_reads_one_form_from_ten_thousand_up():
    f = np.geomspace(1.0, 1e6, 61)
    s = 2j * np.pi * f
    z = 1 / (s * 140e-12) + 1 / (s * 1.7e-9) + 130e3 / (1 + s * 130e3 * 2.2e-9) + 500.0
    fig = plot_spectrum((f, z))
    fig.draw_without_rendering()
    ax = next(a for a in fig.axes if a.get_ylabel().startswith("|Z|"))
    assert ax.get_ylabel() == "|Z| [kΩ]"
    lo, hi = sorted(ax.get_ylim())
    shown = [(loc, t.get_text()) for loc, t in zip(ax.yaxis.get_majorticklocs(), ax.yaxis.get_ticklabels()) if t.get_text() and lo <= loc <= hi]
    assert len(shown) >= 3, shown
    for loc, text in shown:
        assert float(text) == pytest.approx(loc / 1e3)  # (kΩ: the label is the value in the axis' prefix, no prefix of its own)
        assert ("e" in text) == bool(loc / 1e3 >= 1e4), shown


@pytest.mark.parametrize("value, text", [(1e4, "1e4"), (1e5, "1e5"), (2.5e4, "2.5e4"), (1e6, "1e6"), (123456.0, "1.23456e5"), (-3e7, "-3e7"), (1.5e-5, "1.5e-5"), (40.0, "40")])
def test_a_tick_without_prefixes_in_exponent_form(value, text):
    assert _plain_number(value, prefixes=False) == text
