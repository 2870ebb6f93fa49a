"""A corner plot's log axis of a dimensionless parameter (a CPE's α, sigma_rel) writes no SI
prefix on its ticks: α with draws over five decades (a CPE the data do not see, its α spread over
its uniform prior) was ticked "1µ, 10µ, 100µ, 0.001", as if α had a unit. Oracle: each label
read back as a plain float equals its tick's location; Ω keeps its prefixes (10k)."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np

from impedax.plotting.bayes import plot_corner


def _labels(ax, axis="x"):
    ax.figure.canvas.draw()
    ticks = ax.xaxis if axis == "x" else ax.yaxis
    lo, hi = sorted(ax.get_xlim() if axis == "x" else ax.get_ylim())
    return [(t.get_position()[0 if axis == "x" else 1], t.get_text()) for t in ticks.get_ticklabels(which="both") if t.get_text() and lo <= t.get_position()[0 if axis == "x" else 1] <= hi]


def test_log_axes_of_dimensionless_parameters_have_no_si_prefix():
    rng = np.random.default_rng(0)
    n = 20000
    alpha = np.exp(rng.uniform(np.log(1e-5), 0.0, n))  # (SYNTHETIC draws over five decades)
    sigma_rel = np.exp(rng.uniform(np.log(1e-4), np.log(0.05), n))
    r1 = np.exp(rng.normal(np.log(1e3), 1.5, n))
    fig = plot_corner(np.stack([r1, alpha, sigma_rel], -1), ["R1", "CPE1.alpha", "sigma_rel"], [True, True, True], units=["Ohm", "1", "1"])
    try:
        bottom = {ax.get_xlabel(): ax for ax in fig.axes if ax.get_xlabel()}
        for name in ("CPE1.alpha", "sigma_rel"):
            labels = _labels(bottom[name])
            assert len(labels) >= 3
            for where, text in labels:
                assert not any(p in text for p in "µmkMnp"), (name, text)
                assert np.isclose(float(text.replace("−", "-")), where, rtol=1e-6), (name, text, where)
        rows = {ax.get_ylabel(): ax for ax in fig.axes if ax.get_ylabel()}
        assert all(not any(p in text for p in "µmkMnp") for _, text in _labels(rows["CPE1.alpha"], "y"))
        assert any(text.endswith("k") for _, text in _labels(bottom["R1 [Ω]"]))  # (a resistance keeps its prefix: 10k)
    finally:
        plt.close(fig)
