"""The axes of the validity and DRT figures, as a reader meets them: the Z-HIT figure counts |Z|
in the prefix the KK and fit figures of the same spectrum count it in (mΩ for a battery's tens
of mΩ, where it read 0.02, 0.03 Ω beside 20, 30 mΩ); a |Z| axis ends no more than about half a
decade past its data and model curves (the demo's naive C_gap fit of |Z| 166 Ω – 166 MΩ read to
10000 MΩ, 1.8 decades above its highest point); the KK figure's title gives µ to the digits of
the report (0.847 read "µ 0.85", equal to the cut-off c = 0.85 the report said it lies below).
Oracles: SYNTHETIC spectra written here with numpy (R0 + R1 || C1, closed form) and the tick
labels of the drawn figure read back as numbers."""

import math
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.plotting import plot_spectrum  # noqa: E402

PREFIXES = {"": 1.0, "k": 1e3, "M": 1e6, "G": 1e9, "m": 1e-3, "µ": 1e-6}
F = np.geomspace(0.01, 1e4, 61)
HALF_DECADE = 10**0.5


def _rc(r0: float, r1: float, c1: float, f=F):
    return r0 + r1 / (1 + 2j * np.pi * f * r1 * c1)


def _noisy(z, level=0.002, seed=3):
    rng = np.random.default_rng(seed)
    return z + level * np.abs(z) * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size))


def _magnitude_panel(fig):
    return next(ax for ax in fig.axes if ax.get_yscale() == "log" and "|Z|" in ax.get_ylabel() and "%" not in ax.get_ylabel())


def _tick_values(ax):
    """The labelled ticks of ``ax``'s y axis in view, read from their texts in the label's unit
    and checked against their positions; [Ω]."""
    fig = ax.get_figure()
    fig.draw_without_rendering()
    unit = re.search(r"\[(.?)Ω\]", ax.get_ylabel()).group(1)
    lo, hi = sorted(ax.get_ylim())
    values = []
    for locs, ticks in ((ax.yaxis.get_majorticklocs(), ax.yaxis.get_major_ticks), (ax.yaxis.get_minorticklocs(), ax.yaxis.get_minor_ticks)):
        for loc, tick in zip(locs, ticks(len(locs))):
            text = tick.label1.get_text().replace("\N{MINUS SIGN}", "-")
            if not text or not lo * (1 - 1e-9) <= loc <= hi * (1 + 1e-9):
                continue
            own = text[-1] if text[-1] in PREFIXES else ""
            value = float(text[: len(text) - len(own)]) * PREFIXES[own] * PREFIXES[unit]
            assert value == pytest.approx(loc, rel=1e-6), (text, loc, ax.get_ylabel())
            values.append(value)
    return sorted(values)


def test_the_zhit_figure_counts_the_modulus_in_the_prefix_of_the_kk_figure():
    """A SYNTHETIC battery-like spectrum, 15 mΩ + 30 mΩ ∥ 1 F (|Z| 15 – 45 mΩ): the KK figure's
    |Z| panel reads mΩ (its Nyquist panel's prefix); the Z-HIT figure's reads mΩ as well, its
    tick labels the values in mΩ (20, 30, 40), not 0.02, 0.03, 0.04 Ω."""
    z = _noisy(_rc(0.015, 0.030, 1.0), level=0.001)
    kk_fig = ix.kk_test((F, z)).plot()
    zhit_fig = ix.zhit((F, z)).plot()
    kk_panel, zhit_panel = _magnitude_panel(kk_fig), _magnitude_panel(zhit_fig)
    kk_fig.draw_without_rendering()
    zhit_fig.draw_without_rendering()
    assert kk_panel.get_ylabel() == "|Z| [mΩ]"
    assert zhit_panel.get_ylabel() == "|Z| [mΩ]"
    shown = _tick_values(zhit_panel)
    assert len(shown) >= 2 and all(0.01 <= v <= 0.06 for v in shown), shown
    plt.close(kk_fig)
    plt.close(zhit_fig)


def test_the_zhit_figure_counts_kiloohm_and_ohm_spectra_in_their_prefix():
    """|Z| of 1.2 – 86 kΩ (a SYNTHETIC skin-like R ∥ C) reads kΩ on the Z-HIT figure; 12 – 42 Ω
    reads Ω, with no prefix."""
    for (r0, r1, c1), label in (((1.2e3, 85e3, 22e-9), "|Z| [kΩ]"), ((12.0, 30.0, 1e-3), "|Z| [Ω]")):
        fig = ix.zhit((F, _noisy(_rc(r0, r1, c1)))).plot()
        panel = _magnitude_panel(fig)
        fig.draw_without_rendering()
        assert panel.get_ylabel() == label
        assert len(_tick_values(panel)) >= 2
        plt.close(fig)


def _drawn_range(ax):
    """The smallest and largest |Z| of the lines drawn on ``ax`` [Ω]."""
    values = np.concatenate([np.asarray(line.get_ydata(), float) for line in ax.get_lines()])
    values = values[np.isfinite(values) & (values > 0)]
    return float(values.min()), float(values.max())


@pytest.mark.parametrize("scale", [166.0, 1.0e3, 2.6e3])
def test_a_modulus_axis_ends_within_half_a_decade_of_its_curves(scale):
    """A capacitor's |Z| = 1/(ωC) over six decades of frequency and a model a factor 2 above it,
    as the demo's naive fit draws them (SYNTHETIC; from ``scale`` Ω up six decades): the axis
    reaches no further than half a decade beyond the lowest and the highest curve (it read to
    10000 MΩ above a highest point of 166 MΩ), and its labelled ticks lie in view, at least two,
    at every decade or every other one."""
    f = np.geomspace(1.0, 1e6, 61)
    data = scale * 1e6 / f * (1 - 1j) / math.sqrt(2)
    model = -2j * scale * 1e6 / f
    fig = plot_spectrum((f, data), (f, model))
    ax = _magnitude_panel(fig)
    shown = _tick_values(ax)
    lo, hi = sorted(ax.get_ylim())
    low, high = _drawn_range(ax)
    assert hi <= high * HALF_DECADE * (1 + 1e-9), (hi, high)
    assert lo >= low / HALF_DECADE * (1 - 1e-9), (lo, low)
    assert len(shown) >= 2
    ratios = np.diff(np.log10(shown))
    assert np.allclose(ratios, np.round(ratios)) and set(np.round(ratios)) <= {1.0, 2.0}, shown
    plt.close(fig)


def test_the_kk_title_gives_mu_to_the_digits_of_the_report():
    """The KK figure's title writes µ as the report does, to 3 decimals (µ = 0.847 read "µ 0.85"
    in the title of REAL exampleData.csv, equal to the cut-off c = 0.85 the report says it lies
    below). Oracle: the result's own µ formatted to 3 decimals, and the report's line."""
    from pathlib import Path

    result = ix.kk_test(Path(__file__).parent / "fixtures" / "real" / "exampleData.csv")
    fig = result.plot()
    title = fig._suptitle.get_text()
    assert f"µ = {result.mu:.3f}" in result.report()
    assert f"µ {result.mu:.3f}" in title, title
    assert result.mu < 0.85 and "µ 0.85," not in title
    plt.close(fig)


def test_the_drt_legend_above_the_gamma_panel_stays_within_its_width():
    """REAL exampleData.csv (impedance.py, MIT) has a Nyquist shape that puts its DRT figure's
    Nyquist panel in the middle column: the γ panel's legend above it, two columns of 5.6 in,
    was wider than the panel's column (4.8 in), so the layout shrank the γ panel to 3 in and
    left 2.6 in of blank figure beside it. The legend lies within the γ panel's width, and the
    panel keeps most of its column (12 in × 1.4/3.5, less its labels)."""
    from pathlib import Path

    result = ix.drt(ix.load(Path(__file__).parent / "fixtures" / "real" / "exampleData.csv"))
    fig = result.plot()
    ax = next(a for a in fig.axes if a.get_xlabel() == "τ [s]")
    assert len(ax.get_subplotspec().colspan) == 1 and ax.get_subplotspec().get_gridspec().ncols == 3  # (the case: the middle-column layout)
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    legend, panel = ax.get_legend().get_window_extent(renderer), ax.get_window_extent(renderer)
    assert legend.y0 >= panel.y1 - 1  # (above the panel)
    assert legend.x0 >= panel.x0 - 1 and legend.x1 <= panel.x1 + 1, (legend, panel)
    assert panel.width / fig.dpi >= 3.8, panel.width / fig.dpi
    plt.close(fig)


def test_the_comparison_legend_says_by_how_much_each_model_trails():
    """`impedax compare --plot`: each model's legend entry gives its ΔAIC as the table prints it
    (2 decimals), so the figure says by how much the best leads, not only which one it is.
    SYNTHETIC R ∥ C skin (1.2 kΩ + 85 kΩ ∥ 22 nF) with 0.5 % noise; the oracle is the table's
    own ΔAIC column, read from the report's text."""
    f = np.geomspace(1e5, 0.1, 41)
    z = _noisy(_rc(1.2e3, 85e3, 22e-9, f), level=0.005 / math.sqrt(2), seed=7)
    comparison = ix.compare([ix.fit("R0 + R1 || C1", (f, z)), ix.fit("R0 + R1 || CPE1", (f, z))])
    table = {}
    for line in str(comparison.report()).splitlines():
        parts = line.split("←")[0].split()  # (the best's row ends "← best")
        if line.startswith("R0 + R1 ||") and len(parts) >= 13 and parts[5].isdigit():  # (a table row: k after the model)
            table[" ".join(parts[:5])] = parts[-2]  # (model, k, rms_rel %, chi2_red, AIC, AICc, BIC, ΔAIC, weight)
    fig = comparison.plot()
    texts = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
    assert len(table) == 2, table
    for model, delta in table.items():
        assert any(t.startswith(f"{model} (rms_rel") and f"ΔAIC {delta}" in t for t in texts), (model, delta, texts)
    plt.close(fig)


def _labelled_in_view(ax):
    ax.get_figure().draw_without_rendering()
    lo, hi = sorted(ax.get_ylim())
    texts = ax.get_yticklabels(minor=False) + ax.get_yticklabels(minor=True)
    return sorted(float(t.get_position()[1]) for t in texts if t.get_text() and lo * (1 - 1e-9) <= t.get_position()[1] <= hi * (1 + 1e-9))


def test_a_short_rms_panel_of_a_validity_batch_is_labelled_through_its_range():
    """The rms_rel and noise panel of the KK batch figure of the REAL battery cycles (0, 64,
    129: rms_rel 0.25–0.31 %, noise 0.117–0.176 %) spans under half a decade: it
    read 0.2 and 0.3 alone, no label below the noise curve from 0.11 to 0.2. Ticked at evenly
    spaced round values there, each labelled: at least three labels, one below the lowest
    point's level of a tenth of the range's log span above it."""
    from pathlib import Path

    data = ix.load(Path(__file__).parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc")
    batch = ix.kk_test_batch(data)
    fig = batch.plot()
    ax = next(a for a in fig.axes if a.get_ylabel().startswith("rms_rel"))
    values = [float(v) * 100 for r in batch.results for v in (r.rms_rel, r.noise_estimate)]
    shown = _labelled_in_view(ax)
    lo, hi = sorted(ax.get_ylim())
    assert math.log10(hi / lo) < 0.7  # (the case: a short log axis)
    assert len(shown) >= 3, shown
    assert min(shown) <= min(values) * (max(values) / min(values)) ** 0.35, (shown, min(values))
    plt.close(fig)


def test_the_comparison_title_says_when_the_best_leaves_a_parameter_undetermined():
    """REAL exampleData.csv compared as R0 + R1 || C1 against R0 + R1 || CPE1: the report says
    the best by AIC, R0 + R1 || CPE1, "leaves R1 undetermined: the data hold R0 + CPE1"; the
    figure's title crowned it with no word of that. Its title names the undetermined parameter
    and the reduced model the report names. Oracle: the report's own sentence."""
    from pathlib import Path

    data = ix.load(Path(__file__).parent / "fixtures" / "real" / "exampleData.csv")
    comparison = ix.compare([ix.fit("R0 + R1 || C1", data), ix.fit("R0 + R1 || CPE1", data)])
    assert "R0 + R1 || CPE1 leaves R1 undetermined: the data hold R0 + CPE1" in str(comparison.report())  # (the case)
    fig = comparison.plot()
    title = fig._suptitle.get_text()
    assert "best by AIC: R0 + R1 || CPE1" in title
    assert "R1 undetermined" in title and "the data hold R0 + CPE1" in title, title
    plt.close(fig)
