"""With a session level a hierarchical posterior's "new trial" is a trial of a new session
(`HierarchicalPosterior.new_trial`: exp(μ + s η + τ ζ)), wider than one more trial of the
sessions measured; the figure's legend, the report and the notebook said only "new trial".
The posterior is built by hand (SYNTHETIC draws, no sampling): μ = ln 100, s = 0.1 between
trials, τ = 0.2 between sessions in every draw, so a new trial of a new session is log-normal
with sd √(0.1² + 0.2²) of ln, a closed form for its 90 % interval."""

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
CHAINS, DRAWS, SESSIONS, TRIALS = 2, 4000, 2, 3


def by_hand(sessions: int) -> HierarchicalPosterior:
    t = SESSIONS * TRIALS
    rng = np.random.default_rng(1)
    index = pd.MultiIndex.from_product([range(SESSIONS), range(TRIALS)], names=["session", "trial"])
    r1 = 100.0 * np.exp(0.1 * rng.standard_normal(t))
    z = 10.0 + r1[:, None] / (1 + 2j * np.pi * FREQ * r1[:, None] * 1e-5)  # R0 + R1 || C1
    full = (CHAINS, DRAWS, 1)
    return HierarchicalPosterior(
        circuit=ix.parse("R0 + R1 || C1"), trial_names=("R1",), shared_names=("R0", "C1"),
        mu=np.full(full, math.log(100.0)), spread=np.full(full, 0.1), spread_session=np.full(full, 0.2 if sessions > 1 else 0.0),
        trial_values=np.broadcast_to(r1[None, None, :, None], (CHAINS, DRAWS, t, 1)).copy(),
        shared=np.broadcast_to(np.array([10.0, 1e-5]), (CHAINS, DRAWS, 2)).copy(), delta=np.zeros((CHAINS, DRAWS)),
        frequency=FREQ, z_data=z, nu=np.full(FREQ.size, 0.01), trial_index=xr.Coordinates.from_pandas_multiindex(index, "trial_index")["trial_index"],
        sessions=sessions, discrepancy=False, divergences=0, step_size=np.full(CHAINS, 0.1), mean_tree_steps=7.0, mean_acceptance=0.8, elapsed_s=1.0,
    )


def light_band(fig):
    """The legend's name and the (low, high) extent of the light band of the first panel."""
    ax = fig.axes[0]
    handles, labels = ax.get_legend_handles_labels()
    (band,) = [p for p in ax.patches if math.isclose(p.get_alpha(), 0.12)]
    y = band.get_path().transformed(band.get_patch_transform()).vertices[:, 1] if hasattr(band, "get_patch_transform") else band.get_xy()[:, 1]
    return [lab for lab in labels if lab.startswith("new trial")], (float(np.min(y)), float(np.max(y)))


def test_a_new_trial_with_a_session_level_is_said_to_be_of_a_new_session():
    post = by_hand(SESSIONS)
    z90 = 1.6448536269514722
    sd = math.hypot(0.1, 0.2)
    expected = (100.0 * math.exp(-z90 * sd), 100.0 * math.exp(z90 * sd))
    fig = post.plot()
    try:
        labels, (lo, hi) = light_band(fig)
    finally:
        plt.close(fig)
    assert labels == ["new trial in a new session, 90 %"]
    # 8,000 draws: the sample quantiles of a log-normal within 3 % (their sd is ≈ 1 %)
    assert lo == pytest.approx(expected[0], rel=0.03) and hi == pytest.approx(expected[1], rel=0.03)
    assert "new trial: one in a new session (its spread between sessions drawn too)" in post.report()
    assert "new trial: one in a new session" in post._repr_html_()


def test_without_a_session_level_it_stays_a_new_trial():
    post = by_hand(1)
    fig = post.plot()
    try:
        labels, _ = light_band(fig)
    finally:
        plt.close(fig)
    assert labels == ["new trial, 90 %"]
    assert "new session" not in post.report() and "new session" not in post._repr_html_()
