"""The γ panel of the DRT figure (`plot_gamma`) is scaled to what a reader can read: the curves
and band inside the measured τ window and every peak marked, not the band outside the window,
which the grey of the unmeasured range shows behind it. Oracles: a SYNTHETIC γ written here
with numpy (Gaussians in log τ of known height); REAL exampleData.csv, whose band reaches 172 mΩ
at τ ≈ 300 s (outside its window, 16 µs – 50 s) beside curves and peaks of at most 51 mΩ.
Geometry read back from matplotlib: the axis limits and the peak labels' window extents."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.plotting.drt import plot_drt, plot_gamma  # noqa: E402

REAL = Path(__file__).parent / "fixtures" / "real"


def bump(tau, at, height, width=0.2):
    return height * np.exp(-0.5 * (np.log10(tau / at) / width) ** 2)


def check_readable(ax, peaks_top: float, fig) -> None:
    """The panel's top above the highest peak but not far (≤ 2×), every peak label inside the
    frame, and the grey of the unmeasured range behind the band and translucent."""
    fig.canvas.draw()
    low, high = ax.get_ylim()
    assert peaks_top < high <= 2.0 * peaks_top, (high, peaks_top)
    frame = ax.get_window_extent()
    for text in ax.texts:
        box = text.get_window_extent()
        assert frame.y0 <= box.y0 and box.y1 <= frame.y1, (text.get_text(), box, frame)
    band = next(c for c in ax.collections if c.get_label().startswith("90 % band"))
    shading = [p for p in ax.patches]
    assert shading and all(p.get_zorder() < band.get_zorder() and p.get_alpha() is not None and p.get_alpha() < 1 for p in shading)


def test_band_outside_the_window_does_not_set_the_gamma_range():
    """SYNTHETIC: a peak of 1 Ω inside the window (1 ms – 10 s), one of 1.5 Ω at 30 s outside
    it (listed, its label must show), and a band reaching 10 Ω at 300 s, outside: the range
    ran to 13 Ω (1.3 × the band), the peaks in its lowest eighth."""
    tau = np.geomspace(1e-5, 1e3, 300)
    gamma = bump(tau, 0.1, 1.0) + bump(tau, 30.0, 1.5)
    q95 = 1.2 * gamma + bump(tau, 300.0, 10.0, 0.3)
    peaks = [SimpleNamespace(tau_s=0.1, gamma_max_ohm=1.0, r_ohm=1.2, inside_window=True), SimpleNamespace(tau_s=30.0, gamma_max_ohm=1.5, r_ohm=1.8, inside_window=False)]
    result = SimpleNamespace(tau=tau, gamma=gamma, gamma_q05=0.8 * gamma, gamma_q95=q95, peaks=peaks, window=(1e-3, 10.0))
    fig, ax = plt.subplots(figsize=(6, 3.5))
    plot_gamma(ax, result)
    check_readable(ax, 1.5, fig)
    assert "band cut at the top" in " ".join(t.get_text() for t in ax.get_legend().get_texts())
    plt.close(fig)


def test_curves_drawn_before_keep_their_range():
    """SYNTHETIC: another spectrum's γ drawn on the axes first (as examples/drt_guides_the_circuit.py
    draws the cycles) is not cut by the range `plot_gamma` sets."""
    tau = np.geomspace(1e-5, 1e3, 300)
    gamma = bump(tau, 0.1, 1.0)
    result = SimpleNamespace(tau=tau, gamma=gamma, gamma_q05=0.8 * gamma, gamma_q95=1.2 * gamma, peaks=[], window=(1e-3, 10.0))
    fig, ax = plt.subplots()
    ax.semilogx(tau, bump(tau, 1.0, 5.0))
    plot_gamma(ax, result)
    assert ax.get_ylim()[1] >= 5.0
    plt.close(fig)


def test_real_drt_figure_gamma_range_follows_curves_and_peaks():
    """REAL exampleData.csv: the γ axis ran to 230 mΩ (1.3 × the band's 172 mΩ at τ ≈ 300 s,
    under the grey); the highest curve and peak (listed, outside the window, at 203 s) is 51 mΩ."""
    result = ix.drt(ix.load(REAL / "exampleData.csv"))
    assert np.max(result.gamma_q95) > 3 * max(p.gamma_max_ohm for p in result.peaks)  # (the case: a band far above the peaks, outside the window)
    fig = plot_drt(result)
    check_readable(fig.axes[0], max(p.gamma_max_ohm for p in result.peaks), fig)
    plt.close(fig)
