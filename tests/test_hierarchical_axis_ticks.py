"""The hierarchical population figure's value axes read as the corner plot's: on the REAL battery
cycles (benchmarks/data/autoeis_battery_130.nc, cycles 0–9, R0 + R1 ∥ CPE1 + R2 ∥ CPE2, R1 and R2
per trial) the R1 panel (1.5–2.9 Ω) was a log axis ticked "1.6 × 10⁰, 1.8 × 10⁰ …", and a capacitance
or a gap in µm would read "× 10⁻⁶". A panel spanning less than a factor of 10 is now a linear axis
counted in the SI prefix its label names; a wider one a log axis ticked in plain prefixed
numbers. SYNTHETIC posteriors built by hand (no sampling): C1 per trial about 10 µF."""

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.bayes.hierarchical import HierarchicalPosterior

FREQ = np.geomspace(1.0, 1e4, 9)
CHAINS, DRAWS, TRIALS = 2, 500, 6


def capacitances(spread: float) -> HierarchicalPosterior:
    """C1 of R0 + R1 ∥ C1 per trial, population median 10 µF, ``spread`` (sd of ln) between trials."""
    rng = np.random.default_rng(1)
    c1 = 1e-5 * np.exp(spread * rng.standard_normal(TRIALS))
    z = 10.0 + 100.0 / (1 + 2j * np.pi * FREQ[None, :] * 100.0 * c1[:, None])
    full = (CHAINS, DRAWS, 1)
    index = pd.MultiIndex.from_arrays([np.arange(TRIALS)], names=["trial"])
    jitter = np.exp(0.01 * rng.standard_normal((CHAINS, DRAWS, TRIALS, 1)))
    return HierarchicalPosterior(
        circuit=ix.parse("R0 + R1 || C1"), trial_names=("C1",), shared_names=("R0", "R1"),
        mu=np.full(full, math.log(1e-5)), spread=np.full(full, spread), spread_session=np.zeros(full),
        trial_values=c1[None, None, :, None] * jitter, shared=np.broadcast_to(np.array([10.0, 100.0]), (CHAINS, DRAWS, 2)).copy(), delta=np.zeros((CHAINS, DRAWS)),
        frequency=FREQ, z_data=z, nu=np.full(FREQ.size, 0.01), trial_index=xr.Coordinates.from_pandas_multiindex(index, "trial_index")["trial_index"],
        sessions=1, discrepancy=False, divergences=0, step_size=np.full(CHAINS, 0.1), mean_tree_steps=7.0, mean_acceptance=0.8, elapsed_s=1.0,
    )


def _axis(post):
    fig = post.plot()
    try:
        fig.canvas.draw()
        ax = fig.axes[0]
        labels = [t.get_text() for t in ax.get_yticklabels(which="both") if t.get_text()]
        return ax.get_yscale(), ax.get_ylabel(), labels, [line.get_ydata() for line in ax.get_lines() if line.get_marker() == "o"][0]
    finally:
        plt.close(fig)


def test_a_narrow_panel_is_linear_in_the_prefix_of_its_values():
    post = capacitances(0.1)  # (new trial's 90 %: ×/÷ e^0.16, within a factor of 10)
    scale, label, ticks, points = _axis(post)
    assert scale == "linear" and label == "C1 [µF]"
    values = [float(t.replace("−", "-")) for t in ticks]  # (plain numbers: no "× 10⁻⁶", no exponent)
    assert len(values) >= 3 and 5 <= min(values) and max(values) <= 20  # (µF of values about 10 µF)
    np.testing.assert_allclose(points, np.median(np.asarray(post.trial_values)[..., 0].reshape(-1, TRIALS), axis=0), rtol=1e-12)  # (data in F)


def test_a_wide_panel_stays_log_with_prefixed_ticks():
    post = capacitances(1.5)  # (new trial's 90 %: ×/÷ e^2.5 ≈ 12: over two decades)
    scale, label, ticks, _ = _axis(post)
    assert scale == "log" and label == "C1 [F]"
    assert ticks and all("10^" not in t and "times" not in t for t in ticks) and any(t.endswith("µ") for t in ticks), ticks


def test_a_narrow_dimensionless_panel_carries_its_values_without_an_offset():
    """`plot_population`'s panel of a dimensionless quantity (a CPE's α) whose trials and bands
    span 1e-5 about 0.85 (SYNTHETIC draws made here): its ticks read the values (0.84999, ...), no
    offset text "1e−5+8.499e−1" above the panel, where it ran into the legend. Oracle: the
    offset text and the tick labels read back as numbers near 0.85."""
    from impedax.plotting.hierarchical import plot_population

    rng = np.random.default_rng(6)
    draws = 0.85 * (1 + 1e-5 * rng.standard_normal((400, 4, 1)))
    band = {"value": 0.85, "q05": 0.85 * (1 - 2e-5), "q95": 0.85 * (1 + 2e-5)}
    fig = plot_population(["CPE1.alpha"], [""], draws, {"CPE1.alpha": band}, {"CPE1.alpha": band}, ["1", "2", "3", "4"], title="t")
    fig.canvas.draw()
    ax = fig.axes[0]
    assert ax.yaxis.get_offset_text().get_text() == ""
    lo, hi = ax.get_ylim()
    values = [float(t.get_text().replace("\N{MINUS SIGN}", "-")) for t in ax.get_yticklabels() if t.get_text() and lo <= t.get_position()[1] <= hi]
    assert values and all(abs(v - 0.85) < 1e-3 for v in values), values
    plt.close(fig)
