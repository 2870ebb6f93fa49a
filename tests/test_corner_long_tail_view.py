"""A corner column whose draws have a long tail shows their central 99 % (and says so in the
title), not every draw: on REAL exampleData.csv (R0 + R1 ∥ CPE1 + R2 ∥ CPE2, 1500 steps, seed 1)
72 000 draws of CPE2.Q, 90 % of them within 200–555 F s^(α-1), were drawn on an axis to 1950,
the histogram and its 5/50/95 % lines in its left quarter. A Gaussian column keeps every draw in
view. Oracle: numpy's quantiles of the SYNTHETIC draws made here, matplotlib's view limits."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np

from impedax.plotting.bayes import plot_corner


def test_a_long_tail_is_cut_from_the_view_and_a_gaussian_is_not():
    rng = np.random.default_rng(3)
    n = 72_000
    gaussian = rng.normal(0.0158, 0.0004, n)
    tailed = np.exp(rng.normal(np.log(320.0), 0.3, n))
    tailed[:40] = np.linspace(1200.0, 1950.0, 40)  # (a few far draws, as the REAL run's)
    fig = plot_corner(np.c_[gaussian, tailed], ["R0", "CPE2.Q"], [True, True], units=["Ohm", "F s^(alpha-1)"])
    try:
        fig.canvas.draw()
        axes = np.array(fig.axes).reshape(2, 2)
        low, high = axes[1, 1].get_xlim()
        q005, q05, q95, q995 = np.quantile(tailed, [0.005, 0.05, 0.95, 0.995])
        assert high < 0.5 * tailed.max() and high <= q995 + 0.1 * (q995 - q005) + 1e-9 and low >= q005 - 0.1 * (q995 - q005) - 1e-9
        assert (q95 - q05) / (high - low) > 0.4  # (the 90 % interval fills nearly half the axis: a fifth before)
        assert axes[1, 0].get_ylim() == (low, high)  # (its row follows)
        g_low, g_high = axes[0, 0].get_xlim()
        assert g_low <= gaussian.min() and g_high >= gaussian.max()  # (a Gaussian's extremes stay in view)
        assert fig._suptitle.get_text().endswith("; CPE2.Q: central 99 % shown)")
    finally:
        plt.close(fig)


def test_a_known_value_beyond_the_cut_stays_in_view():
    """A truth line (SYNTHETIC α = 1 at its bound, the draws' tail running down from it) is kept in
    the view the cut makes: set to the draws' central 99 %, α = 1 lay past it and was not drawn."""
    rng = np.random.default_rng(4)
    alpha = 1 - np.abs(rng.standard_cauchy(40_000)) * 2e-4
    alpha = alpha[alpha > 0.9]
    fig = plot_corner(np.c_[alpha], ["CPE1.alpha"], [True], units=["1"], truths={"CPE1.alpha": 1.0})
    try:
        fig.canvas.draw()
        low, high = fig.axes[0].get_xlim()
        assert "central 99 % shown" in fig._suptitle.get_text()  # (the case: a cut view)
        assert low < 1.0 < high
    finally:
        plt.close(fig)
