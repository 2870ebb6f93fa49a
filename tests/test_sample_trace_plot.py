"""`Posterior.trace()` and ``impedax sample --trace FILE``: each parameter's kept draws of every
walker against the sampler's step, with the walkers' median. There was no trace plot: a user
checking convergence by eye (drift, a stuck walker) had to rebuild one from ``to_xarray()``.
Oracle: the posterior's own draws array, its settings (burn, thin) and emcee's step counting
(kept steps burn + thin, burn + 2·thin, …), matplotlib's line data; the data are SYNTHETIC."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

import impedax as ix
from cli_run import run as run_cli


@pytest.fixture(scope="module")
def posterior():
    """SYNTHETIC R0 + R1 ∥ C1 (20 Ω, 500 Ω, 10 µF), 1 % noise, 30 points 10 kHz–0.1 Hz, 400 steps, thin 2."""
    f = np.logspace(4, -1, 30)
    z = 20.0 + 1.0 / (1.0 / 500.0 + 1j * 2 * np.pi * f * 1e-5)
    data = ix.make_spectrum(f, z * (1 + 0.01 * np.random.default_rng(0).standard_normal(f.size)))
    return ix.sample("R0 + R1 || C1", data, steps=400, thin=2, seed=1, progress=False)


def test_each_row_holds_every_walker_s_draws_against_the_step(posterior):
    fig = posterior.trace()
    try:
        axes = fig.axes
        assert len(axes) == len(posterior.names)
        walkers, draws = posterior.draws.shape[:2]
        burn, thin = posterior.settings["burn"], posterior.settings["thin"]
        for i, (ax, name) in enumerate(zip(axes, posterior.names)):
            lines = ax.get_lines()
            assert len(lines) == walkers + 1  # (every walker and their median)
            np.testing.assert_array_equal(lines[0].get_xdata(), burn + thin * np.arange(1, draws + 1))
            np.testing.assert_array_equal(np.array([line.get_ydata() for line in lines[:walkers]]), posterior.draws[:, :, i])
            np.testing.assert_allclose(lines[-1].get_ydata(), np.median(posterior.draws[:, :, i], axis=0))
            assert ax.get_ylabel().startswith(name)
        assert [ax.get_ylabel() for ax in axes][:2] == ["R0 [Ω]", "R1 [Ω]"]
    finally:
        plt.close(fig)
    fig = posterior.trace(params=["C1"])
    try:
        assert len(fig.axes) == 1 and fig.axes[0].get_ylabel().startswith("C1 [")
    finally:
        plt.close(fig)
    with pytest.raises(ix.ParameterError, match="R7"):
        posterior.trace(params=["R7"])


def test_cli_trace_writes_the_figure(tmp_path, capsys):
    f = np.logspace(4, -1, 30)
    z = 20.0 + 1.0 / (1.0 / 500.0 + 1j * 2 * np.pi * f * 1e-5)
    path = tmp_path / "rc.csv"
    np.savetxt(path, np.c_[f, z.real, z.imag], delimiter=",")
    code, out, err = run_cli(["sample", str(path), "--model", "R0 + R1 || C1", "--steps", "200", "--quiet", "--trace", str(tmp_path / "trace.png")], capsys)
    assert code == 0, err
    assert (tmp_path / "trace.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
def test_a_joint_posterior_draws_its_trace_named_per_spectrum():
    """SYNTHETIC R0 + R1 ∥ C1 at two trials (R1 500 and 800 Ω), R0 shared, 150 steps: a row per
    sampled parameter, named as the joint posterior names them (R1[trial=1])."""
    f = np.logspace(4, -1, 25)
    z = np.array([20.0 + 1.0 / (1.0 / r1 + 1j * 2 * np.pi * f * 1e-5) for r1 in (500.0, 800.0)])
    z = z * (1 + 0.01 * np.random.default_rng(2).standard_normal(z.shape))
    data = ix.make_spectrum(f, z, dims="trial")
    post = ix.sample("R0 + R1 || C1", data, shared=["R0"], over="trial", steps=150, seed=1, progress=False)
    fig = post.trace()
    try:
        labels = [ax.get_ylabel() for ax in fig.axes]
        assert len(labels) == len(post.names) and labels[0].startswith("R0 [") and any(label.startswith("R1[trial=1] [") for label in labels), labels
        i = list(post.names).index("R1[trial=1]")
        np.testing.assert_array_equal(fig.axes[i].get_lines()[0].get_ydata(), post.draws[0, :, i])
    finally:
        plt.close(fig)


def test_a_narrow_dimensionless_trace_has_no_offset_beside_its_axis():
    """A trace row of a dimensionless parameter whose draws span 1e-5 about 0.85 (a CPE's α on
    SYNTHETIC noise-free data) reads its values on the ticks (0.84990, 0.84991, ...), not
    9.0, 9.5, 10 under matplotlib's "1e−5+8.499e−1", which ran over the row above; the same
    for sigma_rel about 1e-5 and for a resistance in Ω. Oracle: the offset text and the tick
    labels read back as numbers inside the draws' range."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from impedax.plotting.bayes import plot_trace

    rng = np.random.default_rng(5)
    centres = np.array([0.8499, 1.02e-5, 20.0])
    draws = centres * (1 + 1e-5 * rng.standard_normal((16, 50, 3)))
    fig = plot_trace(draws, ["CPE1.alpha", "sigma_rel", "R0"], [False, False, True], units=["", "", "Ω"])
    fig.canvas.draw()
    for ax, centre in zip(fig.axes, centres):
        assert ax.yaxis.get_offset_text().get_text() == "", ax.get_ylabel()
        lo, hi = ax.get_ylim()
        values = [float(t.get_text().replace("\N{MINUS SIGN}", "-")) for t in ax.get_yticklabels() if t.get_text() and lo <= t.get_position()[1] <= hi]
        assert values and all(abs(v - centre) < 1e-3 * centre for v in values), (ax.get_ylabel(), values)
    plt.close(fig)
