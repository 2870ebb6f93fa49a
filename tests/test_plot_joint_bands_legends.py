"""The joint posterior's band figure (`impedax sample --shared ... --plot`,
`plot_joint_posterior_bands`) keeps its legends off the data (walkthrough: on the demo's trial
remainders, R_EP || CPE_EP || C_gap over trials 1-3, the row-1 |Z| legend of five entries lay
over the points from 1 Hz to 2 kHz). Oracle: the legend's box and the points matplotlib draws
(`drawn_points`) on an Agg canvas; spectra and draws are SYNTHETIC, made here with numpy."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from impedax.plotting import drawn_points  # noqa: E402
from impedax.plotting.bayes import plot_joint_posterior_bands  # noqa: E402


def _finger(f, r_ep, q, alpha, c_gap):
    """R_EP ∥ CPE_EP ∥ C_gap [Ω] at ``f`` [Hz] (broadcast over the parameters)."""
    jw = 2j * np.pi * f
    return 1 / (1 / r_ep + q * jw**alpha + jw * c_gap)


def test_no_legend_of_the_joint_bands_lies_over_data():
    """SYNTHETIC: three trials of the demo's remainder shape (|Z| 70 MΩ at 1 Hz to 320 Ω at
    1 MHz, 1 % noise), 100 draws each about their values, with a predictive band."""
    rng = np.random.default_rng(4)
    freq = np.geomspace(1.0, 1e6, 61)
    f_model = np.geomspace(1.0, 1e6, 200)
    r_ep = np.array([7e7, 6e7, 6.5e7])
    z_data = np.array([_finger(freq, r, 2e-9, 0.3, 490e-12) for r in r_ep])
    z_data *= 1 + 0.01 * (rng.standard_normal(z_data.shape) + 1j * rng.standard_normal(z_data.shape))
    spread = 1 + 0.03 * rng.standard_normal((3, 100, 1))
    z_draws = _finger(f_model[None, None, :], r_ep[:, None, None] * spread, 2e-9, 0.3, 490e-12 * (1 + 0.005 * rng.standard_normal((1, 100, 1))))
    z_predictive = z_draws * (1 + 0.01 * rng.standard_normal(z_draws.shape))
    fig = plot_joint_posterior_bands(freq, z_data, ["trial=1", "trial=2", "trial=3"], f_model, z_draws, title="R_EP || CPE_EP || C_gap: joint posterior bands", z_predictive=z_predictive)
    fig.canvas.draw()
    axes = np.array(fig.axes).reshape(3, 3)
    for ax in axes[0, :2]:  # the Nyquist and |Z| panels of row 1 carry the legends
        legend = ax.get_legend()
        assert legend is not None
        box = legend.get_window_extent()
        xy = drawn_points(ax)
        inside = (xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1)
        assert not inside.any(), f"{int(inside.sum())} drawn points under the legend of {ax.get_ylabel()}"
        assert fig.bbox.contains(box.x0, box.y0) and fig.bbox.contains(box.x1, box.y1)
        for title in (ax.title, ax._left_title, ax._right_title):  # (moved above its frame: clear of the panel's title)
            if title.get_text():
                assert not box.overlaps(title.get_window_extent()), title.get_text()
    plt.close(fig)


def test_a_legend_moved_off_the_data_clears_a_title_on_the_left():
    """A panel titled on the left (the joint bands' "trial=1" over its Nyquist panel) whose
    legend covers data: moved below the panel as under a centred title, not above the frame
    over the title. SYNTHETIC: a line through the whole panel."""
    from impedax.plotting import legends_off_data

    fig, ax = plt.subplots(figsize=(4, 3), layout="constrained")
    x = np.linspace(0, 1, 200)
    for k in range(5):
        ax.plot(x, (x + 0.2 * k) % 1, ".", label=f"curve {k}")
    ax.set_title("trial=1", loc="left")
    ax.legend()
    legends_off_data(fig)
    fig.canvas.draw()
    box = ax.get_legend().get_window_extent()
    assert not box.overlaps(ax._left_title.get_window_extent())
    assert box.y1 <= ax.get_window_extent().y0  # (below the frame)
    plt.close(fig)
