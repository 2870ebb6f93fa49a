"""The refinement figure draws the residuals of the last five steps: of more steps, the first
residual row's title says which are shown and that the error panel has them all. Until
2026-12-06 a refinement of 7 steps (REAL exampleData.csv from R0 + R1 ∥ C1) showed steps 2–6
without a word. Oracle: the steps counted by hand; a stand-in refinement of 7 (and of 5)
steps, each the fit of a SYNTHETIC R0 + R1 ∥ C1 spectrum (no refine run)."""

from types import SimpleNamespace

import matplotlib
import numpy as np
import pytest

import impedax as ix
from impedax.plotting.diagnosis import plot_refinement

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def fit():
    f = np.geomspace(1.0, 1e5, 30)
    z = 20.0 + 500.0 / (1 + 2j * np.pi * f * 500.0 * 1e-6)  # SYNTHETIC R0 + R1 ∥ C1
    z = z * (1 + 0.005 * np.random.default_rng(4).standard_normal(f.size))
    return ix.fit("R0 + R1 || C1", ix.make_spectrum(f, z), progress=False)


def _refinement(fit, n):
    steps = [SimpleNamespace(fit=fit, effect=None if i == 0 else f"effect_{i}", removed=(), added=None, change="(start)" if i == 0 else f"+ effect_{i}",
                             model=fit.model, diagnosis=None) for i in range(n)]
    return SimpleNamespace(steps=steps, final_model=fit.model, verdict="adequate", masked_points=())


def _residual_titles(fig):
    return [ax.get_title() for ax in fig.axes if ax.get_ylabel() == "(Z_model − Z)/|Z| [%]"]


def test_seven_steps_say_which_five_are_drawn(fit):
    import matplotlib.pyplot as plt

    fig = plot_refinement(_refinement(fit, 7))
    try:
        titles = _residual_titles(fig)
        assert len(titles) == 5
        assert titles[0].replace("\n", " ").startswith("residuals of the last 5 of 7 steps (2–6; all 7 in the error panel)")
        assert [t.split("step ")[1].split(":")[0] for t in titles] == ["2", "3", "4", "5", "6"]
    finally:
        plt.close(fig)


def test_five_steps_need_no_word(fit):
    import matplotlib.pyplot as plt

    fig = plot_refinement(_refinement(fit, 5))
    try:
        titles = _residual_titles(fig)
        assert len(titles) == 5 and titles[0].startswith("step 0:") and not any("residuals of the last" in t for t in titles)
    finally:
        plt.close(fig)
