"""Tick labels do not run into each other on narrow panels: a Nyquist panel a few millimetres
wide (`FittingLocator`) and a corner plot's log axis over about a decade (its minor labels,
SI-prefixed and thinned: `plain_log_ticks`). Oracle: the labels' own boxes on an Agg canvas
(matplotlib's `get_window_extent`); the spectra are SYNTHETIC, written here with numpy."""

import re

import pytest

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from impedax.plotting import equal_aspect, nyquist_frame  # noqa: E402
from impedax.plotting.bayes import plot_corner  # noqa: E402
from tick_labels import labels_in_view  # noqa: E402


def assert_no_overlap(axis, renderer):
    labels = labels_in_view(axis, renderer)
    for i, (a, box_a) in enumerate(labels):
        for b, box_b in labels[i + 1 :]:
            assert not box_a.overlaps(box_b), f"tick labels {a!r} and {b!r} overlap"
    return [t for t, _ in labels]


def test_a_narrow_nyquist_panel_keeps_its_labels_apart():
    """Meyer's finger (SYNTHETIC, noise-free): −Z'' to 1.2 GΩ over Z' of 130 kΩ, so the equal
    scales leave the panel a sliver; before, its x labels ran together ("0.0.001")."""
    f = np.logspace(0, 6, 61)
    jw = 2j * np.pi * f
    z = 1 / (jw * 140e-12) + 1 / (jw * 1.7e-9) + 130e3 / (1 + jw * 130e3 * 2.2e-9) + 500
    fig, ax = plt.subplots(figsize=(6, 6))
    ax.plot(z.real, -z.imag, "o")
    ax.set(xlabel="Z' [Ω]", ylabel="−Z'' [Ω]")
    equal_aspect(ax, frame=nyquist_frame(z))
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    assert ax.get_window_extent(renderer).width < 0.1 * fig.bbox.width  # (the case: a sliver)
    assert len(assert_no_overlap(ax.xaxis, renderer)) >= 1
    assert len(assert_no_overlap(ax.yaxis, renderer)) >= 3
    assert ax.get_xlabel() == "Z' [GΩ]"
    plt.close(fig)


def test_a_corner_log_axis_over_a_decade_has_prefixed_labels_apart():
    """R1 log-normal about 8 kΩ (draws over a factor above 10: a log axis about 1.5 decades
    wide, where matplotlib labels minor ticks); before, "2000 3000 4000 6000" ran together
    beside "20k 30k", in a larger font than the major labels."""
    rng = np.random.default_rng(5)
    draws = np.c_[rng.normal(20, 0.2, 4000), np.exp(rng.normal(np.log(8000), 0.5, 4000)), np.exp(rng.normal(np.log(1e-6), 0.05, 4000))]
    fig = plot_corner(draws, ["R0", "R1", "C1"], [True, True, True], units=["Ohm", "Ohm", "F"])
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    axes = np.array(fig.axes).reshape(3, 3)
    for axis in (axes[2, 1].xaxis, axes[1, 0].yaxis):  # R1's log axes
        assert axis.get_scale() == "log"
        texts = assert_no_overlap(axis, renderer)
        assert len(texts) >= 3 and "10k" in texts
        assert all(re.fullmatch(r"\d+(\.\d+)?k", t) for t in texts), texts  # (SI-prefixed: 2k, not 2000)
    for ax in fig.axes:
        if ax.get_visible():
            assert_no_overlap(ax.xaxis, renderer)
            assert_no_overlap(ax.yaxis, renderer)
    plt.close(fig)


def test_a_corner_of_twenty_parameters_keeps_its_labels_and_titles_apart():
    """The walkthrough's joint posterior (2026-12-03): 20 parameters named as a shared fit names
    them (``CPE1.Q[cycle=129]``) on one 16 in figure ran its y labels over each other, its x
    labels together and its last title off the right edge. Now each panel keeps 1.5 in (31 in
    in all) and a label longer than its panel puts the unit on a line of its own."""
    rng = np.random.default_rng(3)
    names = ["CPE1.alpha"] + [f"{p}[cycle={c}]" for c in (0, 64, 129) for p in ("R0", "R1", "CPE1.Q", "R2", "CPE2.Q", "CPE2.alpha")] + ["sigma_rel"]
    units = [""] + ["Ohm", "Ohm", "F s^(alpha-1)", "Ohm", "F s^(alpha-1)", ""] * 3 + [""]
    scale = [0.46] + [0.11, 1.7, 0.075, 2.7, 23.0, 0.95] * 3 + [0.034]
    draws = np.array(scale) * (1 + 0.02 * rng.normal(size=(3000, 20)))
    fig = plot_corner(draws, names, [False] * 20, units=units)
    assert tuple(fig.get_size_inches()) == (31.0, 31.0)  # 1.5 in × 20 + 1 in
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    axes = np.array(fig.axes).reshape(20, 20)
    ylabels = [axes[i, 0].yaxis.label.get_window_extent(renderer) for i in range(1, 20)]
    xlabels = [axes[19, j].xaxis.label.get_window_extent(renderer) for j in range(20)]
    for boxes in (ylabels, xlabels):
        for a, b in zip(boxes, boxes[1:]):
            assert not a.overlaps(b)
    assert axes[19, 3].get_xlabel() == "CPE1.Q[cycle=0]\n[mF s^(α-1)]"  # (too long for its panel on one line; 75 mF)
    figure = fig.bbox
    for i in range(20):
        title = axes[i, i].title.get_window_extent(renderer)
        assert figure.x0 <= title.x0 and title.x1 <= figure.x1, names[i]
    plt.close(fig)


def test_a_log_axis_in_percent_has_no_si_prefixes():
    """(walkthrough 2026-12-03: the comparison's "|relative residual| [%]" read 100, 0.01, 1µ,
    100p, 10f — a micro-percent.) A % axis writes e-notation below 0.001; one in Ω keeps 10k."""
    from impedax.plotting import plain_log_ticks

    fig, (ax, ax_ohm) = plt.subplots(2, 1, figsize=(6, 6))
    ax.semilogy(np.arange(5), [100, 1, 1e-6, 1e-10, 1e-14])
    ax.set_ylabel("|relative residual| [%]")
    plain_log_ticks(ax.yaxis)
    ax_ohm.semilogy(np.arange(3), [10, 1e3, 1e5])
    ax_ohm.set_ylabel("|Z| [Ω]")
    plain_log_ticks(ax_ohm.yaxis)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    texts = [t for t, _ in labels_in_view(ax.yaxis, renderer)]
    assert texts and all(re.fullmatch(r"\d+(\.\d+)?|\d(\.\d+)?e-?\d+", t) for t in texts), texts
    assert any("e-" in t and float(t) < 1e-8 for t in texts) and any(float(t) >= 1 and "e" not in t for t in texts)  # (1e-13 … 1e-5, 0.001 … 10)
    assert "10k" in [t for t, _ in labels_in_view(ax_ohm.yaxis, renderer)]
    plt.close(fig)


def test_a_corner_axis_in_metres_counts_in_a_prefix():
    """An air gap u of 2.8 µm (a `gap_thickness_reparametrization`'s unit, m): its axis reads
    ``u [µm]`` with ticks 2.7 … 2.9 and no detached 1e−6, its title ``… µm`` (walkthrough
    2026-12-03: ``u [m]`` under matplotlib's offset, titled ``2.8055 [2.8030, 2.8078] ×10⁻⁶ m``)."""
    rng = np.random.default_rng(2)
    u = rng.normal(2.8e-6, 0.01e-6, 4000)
    fig = plot_corner(np.c_[rng.normal(5e7, 1e6, 4000), u], ["R_EP", "u"], [True, True], units=["Ohm", "m"])
    fig.canvas.draw()
    axes = np.array(fig.axes).reshape(2, 2)
    assert axes[1, 1].get_xlabel() == "u [µm]" and axes[1, 0].get_ylabel() == "u [µm]"
    assert axes[1, 1].xaxis.get_offset_text().get_text() == "" and axes[1, 0].yaxis.get_offset_text().get_text() == ""
    ticks = [float(t.replace("\N{MINUS SIGN}", "-")) for t, _ in labels_in_view(axes[1, 1].xaxis, fig.canvas.get_renderer())]
    assert ticks and all(2.7 <= t <= 2.9 for t in ticks), ticks
    median = float(np.median(u)) * 1e6
    assert axes[1, 1].get_title().startswith(f"u = {median:.3f}") and axes[1, 1].get_title().endswith(" µm")
    plt.close(fig)


def test_a_bode_modulus_under_a_decade_labels_its_top():
    """A |Z| axis over less than a decade (SYNTHETIC: impedax simulate's long walkthrough
    circuit at its defaults, |Z| from 101 to 484 Ω, axis 94–523 Ω) was labelled 100, 200, 300,
    400 only: the curve's top, the low-frequency |Z|, sat above the last label. A mantissa that
    fits is now labelled at the axis' end too (500 here), apart from its neighbours."""
    from impedax import make_spectrum, parse
    from impedax.circuits import compile_circuit
    from impedax.plotting import plot_spectrum

    circuit = parse("R0 + L1 + (R1 || (C1 + R2 || CPE2)) + R3 || (W3 + C3) || (R4 + Wo4) + Ws5 || CC5 + HN6 + G7")
    f = np.geomspace(1, 1e6, 61)
    z = np.asarray(compile_circuit(circuit)(circuit.defaults(), f))
    fig = plot_spectrum(model=make_spectrum(f, z))
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    axis = fig.axes[1].yaxis
    texts = assert_no_overlap(axis, renderer)
    top = max(float(t) for t in texts)
    assert abs(z).max() == pytest.approx(483.5, abs=1)  # (the case)
    assert top >= 0.9 * abs(z).max(), texts
    plt.close(fig)
