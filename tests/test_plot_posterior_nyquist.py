"""The posterior band figure (`impedax sample --plot`, `plot_posterior_bands`) reads as the fit's
figure does: its Nyquist panel ends where the drawn curves end (REAL ZPlot's data end at 615 Ω,
and the panel ran to 920 Ω, a third of it empty), and its data and model wear the colours of
`plot_spectrum` (data blue open circles, model orange; the posterior figure drew the data black
and the model blue). Oracles: the extents of the drawn lines (`get_xydata`) and the colours of
`plot_spectrum`'s lines on an Agg canvas; the draws are SYNTHETIC, made here with numpy about the
REAL data's arc."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import to_rgba  # noqa: E402

from impedax.plotting import plot_spectrum  # noqa: E402
from impedax.plotting.bayes import plot_joint_posterior_bands, plot_posterior_bands  # noqa: E402


def _arc(f, r0, r1, tau):
    """R0 + R1 ∥ C with time constant ``tau`` [Ω] at ``f`` [Hz]."""
    return r0 + r1 / (1 + 2j * np.pi * f * tau)


def _posterior(seed=3):
    rng = np.random.default_rng(seed)
    freq = np.geomspace(3e3, 3e5, 25)
    z = _arc(freq, 150.0, 500.0, 1.6e-5) * (1 + 0.003 * rng.standard_normal(25))
    f_model = np.geomspace(3e3, 3e5, 200)
    draws = _arc(f_model[None, :], 150.0 * (1 + 0.01 * rng.standard_normal((60, 1))), 500.0 * (1 + 0.01 * rng.standard_normal((60, 1))), 1.6e-5)
    return freq, z, f_model, draws


def _drawn_extent(ax):
    xy = np.concatenate([line.get_xydata() for line in ax.get_lines() if len(line.get_xdata()) > 1])
    return xy[:, 0].min(), xy[:, 0].max(), xy[:, 1].min(), xy[:, 1].max()


def test_the_posterior_nyquist_panel_ends_where_its_curves_end():
    freq, z, f_model, draws = _posterior()
    fig = plot_posterior_bands(freq, z, f_model, draws, title="R0 + R1 || C1")
    fig.canvas.draw()
    ax = fig.axes[0]
    x0, x1, y0, y1 = _drawn_extent(ax)
    lo, hi = ax.get_xlim()
    bottom, top = ax.get_ylim()
    assert lo <= x0 and hi >= x1 and bottom <= y0 and top >= y1  # everything drawn is in view
    assert hi - x1 < 0.1 * (x1 - x0), f"the panel runs to {hi:.0f} Ω beside curves that end at {x1:.0f} Ω"
    assert top - y1 < 0.1 * (y1 - y0)
    width, height = ax.get_window_extent().width, ax.get_window_extent().height
    assert abs((hi - lo) / width - (top - bottom) / height) < 1e-6 * (hi - lo) / width  # equal scales
    plt.close(fig)


def _styles(fig_axes):
    """{label: (colour, marker)} of the labelled lines of ``fig_axes``."""
    return {line.get_label(): (to_rgba(line.get_color()), line.get_marker()) for ax in fig_axes for line in ax.get_lines() if not line.get_label().startswith("_")}


def test_posterior_data_and_model_wear_the_fit_figure_colours():
    freq, z, f_model, draws = _posterior()
    fit = plot_spectrum((freq, z), (f_model, np.median(draws.real, 0) + 1j * np.median(draws.imag, 0)))
    fit_styles = _styles(fit.axes[:1])
    data_style, model_colour = fit_styles["data"], fit_styles["model"][0]
    for fig in (plot_posterior_bands(freq, z, f_model, draws, title="t"), plot_joint_posterior_bands(freq, z[None], ["trial=1"], f_model, draws[None], title="t")):
        for ax in fig.axes[:3]:
            styles = _styles([ax])
            assert styles["data"] == data_style, ax.get_ylabel()
            medians = [style for label, style in styles.items() if "median" in label]
            assert medians and all(colour == model_colour for colour, _ in medians), ax.get_ylabel()
            bands = [c for c in ax.collections if c.get_label().endswith("band")]
            assert all(np.allclose(to_rgba(c.get_facecolor()[0])[:3], model_colour[:3]) for c in bands)
        plt.close(fig)
    plt.close(fit)


def test_a_comparison_draws_data_and_its_first_model_as_a_fit_figure_does():
    """`impedax compare --plot` (`Comparison.plot`): the data blue open circles and the first
    model orange, as `impedax fit --plot` draws data and model; the further models in further
    colours of the cycle, none in the data's (the data were black). SYNTHETIC arc fitted by
    R0 + R1 ∥ C1 and R0 + R1 ∥ CPE1."""
    import impedax as ix

    freq, z, f_model, draws = _posterior()
    data = ix.make_spectrum(freq, z)
    comparison = ix.compare([ix.fit("R0 + R1 || C1", data), ix.fit("R0 + R1 || CPE1", data)])
    fig = comparison.plot()
    fit = plot_spectrum((freq, z), (f_model, draws[0]))
    data_style, model_colour = _styles(fit.axes[:1])["data"], _styles(fit.axes[:1])["model"][0]
    for ax in fig.axes[:3]:
        styles = _styles([ax])
        assert styles["data"] == data_style, ax.get_ylabel()
        models = [colour for label, (colour, _) in styles.items() if label != "data"]
        assert len(models) == 2 and models[0] == model_colour and data_style[0] not in models and models[1] != models[0]
    plt.close(fig)
    plt.close(fit)
