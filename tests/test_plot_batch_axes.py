"""A batch fit's figure (`plot_batch`) over 10 days: every day labelled on the batch axes (before,
an even spread of 8 ticks left out days 3 and 8, the two the Nyquist panel does not draw), the
log panel's minor labels SI-prefixed and apart (before, "4×10⁶" ran into "3×10⁶"), and the
Nyquist panel's Z' range ending near the data (before, equal scales on a wide panel ran it to
8 MΩ beside data ending at 3.1 MΩ). Oracle: the labels' own boxes on an Agg canvas
(`get_window_extent`) and the data's extent from numpy; the spectra are SYNTHETIC."""

import dataclasses
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.plotting import label_spectra_axis  # noqa: E402
from tick_labels import labels_in_view  # noqa: E402

DAYS = np.arange(1, 11)


def assert_apart(axis, renderer) -> list[str]:
    labels = labels_in_view(axis, renderer)
    for i, (a, box_a) in enumerate(labels):
        for b, box_b in labels[i + 1 :]:
            assert not box_a.overlaps(box_b), f"tick labels {a!r} and {b!r} overlap"
    return [text for text, _ in labels]


@pytest.fixture(scope="module")
def days_figure():
    """SYNTHETIC coated metal drying over 10 days: R0 20 Ω, R1 from 5 MΩ down by 0.68 a day (1.5
    decades: a log panel with minor labels), C1 2 nF, 0.5 % complex Gaussian noise (seed 3)."""
    rng = np.random.default_rng(3)
    f = np.logspace(-2, 5, 36)
    r1 = 5e6 * 0.68 ** (DAYS - 1)
    jw = 2j * np.pi * f
    z = 20 + r1[:, None] / (1 + jw * r1[:, None] * 2e-9)
    z = z * (1 + 0.005 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    data = xr.Dataset({"Z": (("day", "frequency"), z)}, coords={"day": DAYS, "frequency": f})
    fig = ix.fit("R0 + R1 || C1", data).plot()
    fig.canvas.draw()
    yield fig, z
    plt.close(fig)


def parameter_panels(fig):
    return [ax for ax in fig.axes if not ax.get_title().startswith("data (○) and fits")]


def test_every_day_is_labelled_on_the_batch_axes(days_figure):
    fig, _ = days_figure
    renderer = fig.canvas.get_renderer()
    panels = parameter_panels(fig)
    assert len(panels) == 4
    for ax in panels:
        assert assert_apart(ax.xaxis, renderer) == [str(d) for d in DAYS], ax.get_title()
    nyquist = [ax for ax in fig.axes if ax not in panels][0]
    drawn = [line.get_label() for line in nyquist.lines if line.get_marker() == "o"]
    assert len(drawn) == 8 and "3" not in drawn  # (the case: days left out of the Nyquist panel)


def test_the_log_panel_labels_its_minor_ticks_with_si_prefixes_apart(days_figure):
    fig, _ = days_figure
    renderer = fig.canvas.get_renderer()
    (r1,) = [ax for ax in fig.axes if ax.get_title().startswith("R1")]
    assert r1.get_yscale() == "log"
    texts = assert_apart(r1.yaxis, renderer)
    assert "1M" in texts and len(texts) >= 3, texts
    assert all(re.fullmatch(r"\d+(\.\d+)?[kM]", t) for t in texts), texts  # (2M, 500k: not 2×10⁶)
    for ax in fig.axes:
        assert_apart(ax.yaxis, renderer)


def test_the_nyquist_panel_ends_near_the_data_at_equal_scales(days_figure):
    fig, z = days_figure
    (nyquist,) = [ax for ax in fig.axes if ax not in parameter_panels(fig)]
    x0, x1 = nyquist.get_xlim()
    y0, y1 = nyquist.get_ylim()
    top = z.real.max()  # (day 1's arc ends at R0 + R1 ≈ 5 MΩ)
    assert top < x1 <= 1.3 * top and x0 < z.real.min()
    assert y1 >= (-z.imag).max()
    box = nyquist.get_window_extent(fig.canvas.get_renderer())
    scale_x, scale_y = box.width / (x1 - x0), box.height / (y1 - y0)
    assert scale_x == pytest.approx(scale_y, rel=0.02)  # (equal scales kept: pixels per Ω)


@pytest.mark.parametrize("n, names", [(10, None), (130, None), (24, "cycle {}, T {}")])
def test_a_batch_axis_labels_a_regular_subset_apart(n, names):
    """Labels of n spectra on a panel 3.2 inches wide: all of 10; of 130 every k-th from the first,
    k one of 1, 2, 5 × 10ⁿ; long (tilted) labels apart too."""
    labels = [str(i) if names is None else names.format(i, 25 + 5 * (i % 3)) for i in range(n)]
    fig, ax = plt.subplots(figsize=(3.2, 2.6), layout="constrained")
    ax.plot(np.arange(n), np.ones(n), "o")
    label_spectra_axis(ax, labels, ["cycle"])
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    if names is None:
        texts = assert_apart(ax.xaxis, renderer)
    else:  # (tilted, parallel labels: their upright boxes overlap, the slanted texts must not)
        shown = [(tick.label1, tick.get_loc()) for tick in ax.xaxis.get_major_ticks() if tick.label1.get_text() and -0.5 <= tick.get_loc() <= n - 0.5]
        texts = [label.get_text() for label, _ in shown]
        tilt = np.radians(shown[0][0].get_rotation())
        assert tilt > 0
        anchors = np.array([ax.transData.transform((x, 0))[0] for _, x in shown])
        height = shown[0][0].get_fontsize() * fig.dpi / 72  # (the font's size in pixels)
        assert np.min(np.diff(anchors)) * np.sin(tilt) >= height  # (distance across the slant)
    at = [labels.index(t) for t in texts]
    steps = set(np.diff(at).tolist())
    assert at[0] == 0 and len(steps) == 1
    (step,) = steps
    assert step in (1, 2, 5, 10, 20, 50)
    if n == 10:
        assert step == 1
    assert len(texts) >= 3
    plt.close(fig)


def test_plot_draws_the_parameters_asked_for_in_their_order_and_names_the_valid_ones():
    """``batch.plot(params=[...])`` (added 2026-12-01): those panels in that order, then rms_rel;
    an unknown name is refused naming the circuit's parameters. SYNTHETIC: 4 cells of
    R0 + R1 || C1 (R1 1–4 kΩ, C1 1 µF), 1 % noise (seed 5)."""
    rng = np.random.default_rng(5)
    f = np.logspace(-1, 5, 30)
    r1 = np.array([1e3, 2e3, 3e3, 4e3])
    z = 10 + r1[:, None] / (1 + 2j * np.pi * f * r1[:, None] * 1e-6)
    z = z * (1 + 0.01 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    batch = ix.fit("R0 + R1 || C1", xr.Dataset({"Z": (("cell", "frequency"), z)}, coords={"cell": np.arange(4), "frequency": f}))
    fig = batch.plot(params=["C1", "R1"])
    titles = [ax.get_title() for ax in parameter_panels(fig)]
    plt.close(fig)
    assert [t.split(" ")[0] for t in titles] == ["C1", "R1", "rms_rel"], titles
    whole = batch.plot()
    assert [ax.get_title().split(" ")[0] for ax in parameter_panels(whole)] == ["R0", "R1", "C1", "rms_rel"]
    plt.close(whole)
    open_figures = plt.get_fignums()
    with pytest.raises(ix.ParameterError) as info:
        batch.plot(params=["R1", "C2"])
    assert str(info.value) == "plot(params=...): unknown parameter 'C2' for R0 + R1 || C1 (parameters: R0, R1, C1)"
    with pytest.raises(ix.ParameterError, match="did you mean R1"):
        batch.plot(params=["r1"])
    with pytest.raises(ix.ParameterError, match="no parameter named"):
        batch.plot(params=[])
    assert plt.get_fignums() == open_figures  # (refused before a figure is made)


def test_a_flat_panel_on_a_bound_does_not_reach_past_it():
    # every value at α = 1 (the CPE's natural upper bound): the ±1 % window (0.99–1.01) showed
    # room above 1, where α cannot go; it now ends 5 % of its height above the bound
    from impedax.plotting.fit import _window_flat

    fig, ax = plt.subplots()
    ax.plot([0, 1, 2], [1.0, 1.0, 1.0], "s")
    _window_flat(ax, np.array([1.0, 1.0, 1.0]), None, (0.0, 1.0))
    low, high = ax.get_ylim()
    assert high == pytest.approx(1.0 + 0.05 * 0.02) and low == pytest.approx(1.0 + 0.001 - 0.02)
    _window_flat(ax, np.array([0.0, 0.0]) + 5.0, None, (5.0, np.inf))  # (on a lower bound: mirrored)
    assert ax.get_ylim() == pytest.approx((5.0 - 0.005, 5.0 - 0.005 + 0.1))
    _window_flat(ax, np.array([0.5, 0.5]), None, (0.0, 1.0))  # (inside: centred as before)
    assert ax.get_ylim() == pytest.approx((0.495, 0.505))
    plt.close(fig)


def finger_batch():
    """SYNTHETIC fingertips (numpy): C_s 140 pF + C_i 1.7 nF + R_sc ∥ C_sc + R_f 500 Ω for three
    skins (R_sc 80, 130, 200 kΩ; C_sc 2 nF), 41 points 1 Hz–1 MHz, 1 % noise (seed 5): −Z''
    reaches ~1 GΩ beside Z' ≤ 200 kΩ, a capacitive tail."""
    rng = np.random.default_rng(5)
    f = np.logspace(0, 6, 41)
    jw = 2j * np.pi * f
    z = np.stack([1 / (jw * 140e-12) + 1 / (jw * 1.7e-9) + 1 / (1 / r + jw * 2e-9) + 500.0 for r in (80e3, 130e3, 200e3)])
    z = z * (1 + 0.01 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)) / np.sqrt(2))
    data = ix.make_spectrum(f, z, dims=("skin",), coords={"skin": ["dry", "mid", "moist"]})
    return ix.fit("C_s + C_i + R_sc || C_sc + R_f", data, fixed={"C_i": 1.7e-9}), f, z


def test_a_batch_with_a_capacitive_tail_draws_the_phase_not_a_vertical_nyquist_line():
    """A walkthrough's finger batch: even zoomed, the Nyquist panel drew every spectrum as one
    vertical line at Z' ≈ 0 beside an axis to 1.9 MΩ; "auto" now draws the phase against
    frequency (the data's circles at numpy's angle of Z), "nyquist" keeps the Nyquist panel."""
    batch, f, z = finger_batch()
    fig = batch.plot()
    panel = fig.axes[-1]
    assert panel.get_xscale() == "log" and panel.get_ylabel() == "phase [deg]" and "capacitive" not in panel.get_title() and "Nyquist panel shows a line" in panel.get_title()
    circles = [ln for ln in panel.get_lines() if ln.get_marker() == "o"]
    np.testing.assert_allclose(circles[0].get_xdata(), f)
    np.testing.assert_allclose(circles[0].get_ydata(), np.degrees(np.angle(z[0])))
    nyquist = batch.plot(spectra="nyquist").axes[-1]
    assert nyquist.get_ylabel().startswith("−Z'' [")
    plt.close("all")


def test_an_ordinary_batch_keeps_its_nyquist_panel_and_a_wrong_choice_is_named(days_figure):
    assert days_figure[0].axes[-1].get_ylabel().startswith("−Z'' [")
    batch, _, _ = finger_batch()
    with pytest.raises(ix.ParameterError, match=r"^spectra must be one of auto, nyquist, phase, got 'bode'"):
        batch.plot(spectra="bode")


def test_every_figure_taking_figsize_checks_it():
    """(walkthrough 2026-12-03: figsize=(0, 0) returned a 0 × 0 figure without a word.) One
    check (`impedax.arguments.figure_size`) for the batch figure, the single spectrum's layout
    and the batch comparison: two positive finite numbers."""
    from impedax.plotting import plot_spectrum
    from impedax.plotting.comparison import plot_batch_comparison
    from impedax.plotting.fit import plot_batch

    f = np.logspace(0, 4, 12)
    z = 20 + 1000 / (1 + 2j * np.pi * f * 1000 * 1e-6)
    data = xr.Dataset({"Z": (("day", "frequency"), np.stack([z, 1.1 * z]))}, coords={"day": [1, 2], "frequency": f})
    batch = ix.fit("R0 + R1 || C1", data)
    for bad in [(0, 0), (8, -1), (8, float("nan")), (8,), "8x6", (True, 6)]:
        for draw in (lambda: batch.plot(figsize=bad), lambda: plot_spectrum((f, z), figsize=bad), lambda: plot_batch_comparison(None, figsize=bad)):
            with pytest.raises(ix.ParameterError, match=r"figsize must be \(width, height\) in inches"):
                draw()
    fig = plot_batch(batch, figsize=(9, 5))
    assert tuple(fig.get_size_inches()) == (9.0, 5.0)
    plt.close("all")


def test_values_beyond_the_axis_have_their_triangles_in_the_legend():
    """Undetermined values far off the determined ones are drawn as ▲ / ▼ at the panel's edge; the
    legend named the open circles only. SYNTHETIC R0 + R1 ∥ C1 over 4 cells, R1 of cell b set by
    hand to 1e30 ± 1e52 Ω (above the axis) and of cell c to 1e-30 ± 1 Ω (below): the R1 panel's
    legend has an entry drawn with each triangle marker the panel draws, in the grey they are
    drawn in (the legend read back from matplotlib)."""
    f = np.logspace(-1, 5, 30)
    r1 = np.array([1e3, 1.2e3, 1.4e3, 1.1e3])
    z = 10 + r1[:, None] / (1 + 2j * np.pi * f * r1[:, None] * 1e-6)
    data = xr.Dataset({"Z": (("cell", "frequency"), z)}, coords={"cell": list("abcd"), "frequency": f})
    batch = ix.fit("R0 + R1 || C1", data)
    ds = batch.dataset.copy(deep=True)
    ds["value"].loc[dict(param="R1", cell="b")], ds["stderr"].loc[dict(param="R1", cell="b")] = 1e30, 1e52
    ds["value"].loc[dict(param="R1", cell="c")], ds["stderr"].loc[dict(param="R1", cell="c")] = 1e-30, 1.0
    edited = dataclasses.replace(batch, dataset=ds)
    assert edited.undetermined("R1").values.tolist() == [False, True, True, False]
    fig = edited.plot()
    try:
        (ax,) = [a for a in fig.axes if a.get_title().startswith("R1")]
        drawn = {line.get_marker() for line in ax.get_lines() if line.get_marker() in ("^", "v") and len(line.get_xdata())}
        assert drawn == {"^", "v"}
        legend = ax.get_legend()
        entries = {handle.get_marker(): text.get_text() for handle, text in zip(legend.legend_handles, legend.get_texts()) if hasattr(handle, "get_marker")}
        assert {"^", "v"} <= set(entries), entries
        assert "above" in entries["^"] and "below" in entries["v"]
    finally:
        plt.close(fig)


@pytest.mark.parametrize("cycles, integral", [([1, 2, 3], True), ([0.0, 50.0, 100.0], True), ([0.1, 0.2, 0.4], False)])
def test_plot_x_of_a_whole_number_coordinate_has_whole_number_ticks(cycles, integral):
    """``batch.plot(x="cycle")`` (`impedax fit --plot-x cycle`) over cycles 1, 2, 3: ticks at 1,
    2, 3 only, where matplotlib put 1.0, 1.5, 2.0, 2.5, 3.0 (half a cycle). A coordinate of
    whole numbers stored as floats (0, 50, 100 V) is ticked in whole numbers too; one with
    fractions keeps matplotlib's ticks. SYNTHETIC R0 + R1 ∥ C1, R1 growing with the cycle, 0.3 %
    noise. Oracle: the tick positions inside the view and their labels' text."""
    rng = np.random.default_rng(2)
    f = np.geomspace(1.0, 1e5, 25)
    r1 = 500.0 * (1 + 0.1 * np.arange(3))[:, None]
    z = (20.0 + r1 / (1 + 2j * np.pi * f * r1 * 1e-6)) * (1 + 0.003 * rng.standard_normal((3, f.size)))
    batch = ix.fit("R0 + R1 || C1", xr.Dataset({"Z": (("cycle", "frequency"), z)}, coords={"cycle": cycles, "frequency": f}))
    fig = batch.plot(x="cycle")
    fig.canvas.draw()
    for ax in fig.axes[:3]:  # (R0, R1, C1)
        lo, hi = ax.get_xlim()
        ticks = [t for t in ax.get_xticks() if lo <= t <= hi]
        texts = [t.get_text() for t in ax.get_xticklabels() if lo <= t.get_position()[0] <= hi]
        if integral:
            assert all(float(t).is_integer() for t in ticks), ticks
            assert all("." not in text for text in texts), texts
        else:
            assert any(not float(t).is_integer() for t in ticks), ticks
    plt.close(fig)
