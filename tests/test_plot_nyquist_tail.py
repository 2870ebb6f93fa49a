"""Nyquist panels of a spectrum with a capacitive tail (walkthrough 2026-12-02, a haptics
modeler's SYNTHETIC finger spectra): with C_s + C_i in series −Z'' reaches 1.2 GΩ at 1 Hz beside
Z' ≤ 130 kΩ, and the equal scales drew the data as a vertical line at Z' ≈ 0 on a GΩ axis (the
comparison's panel a sliver under a legend that covered its axis). The panel is now zoomed on
the structure (`tail_frame`) and says where the tail leaves it (`mark_tail`); a spectrum of
ordinary shape keeps the limits it had (numbers from the code before the change)."""

from __future__ import annotations

from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from impedax.plotting import TAIL_RATIO, nyquist_frame, plot_spectrum, tail_frame  # noqa: E402
from impedax.plotting.comparison import plot_comparison  # noqa: E402

FINGER_F = np.geomspace(1.0, 1e5, 40)


def finger(f: np.ndarray) -> np.ndarray:
    """SYNTHETIC Meyer finger, C_s + C_i + R_sc || C_sc + R_f [Ω] (the walkthrough's values)."""
    jw = 2j * np.pi * f
    c_s, c_i, r_sc, c_sc, r_f = 140e-12, 1.7e-9, 130e3, 2.2e-9, 500.0
    return 1 / (jw * c_s) + 1 / (jw * c_i) + r_sc / (1 + jw * r_sc * c_sc) + r_f


def noisy(z: np.ndarray, seed: int, level: float = 0.01) -> np.ndarray:
    """SYNTHETIC noise: ``level`` of |Z| on each part, fixed seed."""
    rng = np.random.default_rng(seed)
    return z + level * np.abs(z) * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size))


def stand_in_fit(model, f, z_data, z_model):
    residuals = (z_model - z_data) / np.abs(z_data)
    return SimpleNamespace(model=model, frequency=f, z_data=z_data, z_model=z_model, residuals=residuals, weighting="modulus",
                           rms_rel=float(np.sqrt(np.mean(np.abs(residuals) ** 2 / 2))))


def assert_equal_scales(ax):
    (x0, x1), (y0, y1), box = ax.get_xlim(), ax.get_ylim(), ax.get_window_extent()
    assert abs((x1 - x0) / box.width - (y1 - y0) / box.height) < 0.006 * (x1 - x0) / box.width


def test_a_finger_spectrum_s_nyquist_panel_shows_the_skin_not_the_tail():
    z_true = finger(FINGER_F)
    z = noisy(z_true, seed=78)
    skin = np.ptp(z_true.real)  # ≈ R_sc: 130 kΩ
    assert np.ptp(-z.imag) > 5000 * skin  # (the premise: 1.2 GΩ of −Z'')
    fig = plot_spectrum((FINGER_F, z), (FINGER_F, z_true))
    fig.canvas.draw()
    ax = fig.axes[0]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    # before: y up to 1.3e9, x to 1.05e9; now the panel is a few skin spans high, in kΩ
    assert y1 - y0 < 5 * skin and y1 < 1e6, (x0, x1, y0, y1)
    assert x0 <= z_true.real.min() and x1 >= z_true.real.max()  # the skin's whole Z' (R_f to R_f + R_sc) in view
    inside = (-z.imag >= y0) & (-z.imag <= y1)
    assert inside.sum() >= 8  # the high-frequency points, readable
    assert_equal_scales(ax)
    text = " ".join(t.get_text() for t in ax.texts)
    assert "runs off the top" in text and "1 Hz" in text and "GΩ" in text, text
    # the frequency named is the highest one whose point lies above the panel
    leaving = FINGER_F[-z.imag > y1].max()
    assert f"below {leaving / 1e3:.3g} kHz" in text, (text, leaving)
    plt.close(fig)


def test_tail_frame_follows_the_model_not_the_noise_in_z_real():
    # SYNTHETIC: at 1 Hz the noise on Z' (1 % of 1.2 GΩ) dwarfs the skin; the model's Z' sets the span
    z_true = finger(FINGER_F)
    z = noisy(z_true, seed=3)
    x0, x1, y0, y1 = tail_frame(z, z_true)
    assert y1 - y0 == pytest.approx(3 * np.ptp(z_true.real), rel=0.05)
    assert x1 - x0 < 1.2 * np.ptp(z_true.real)
    # an ordinary arc, a CPE line of α = 0.95 (−Z''/Z' = tan(85.5°) = 12.7): no zoom
    f = np.geomspace(1e-2, 1e5, 60)
    jw = 2j * np.pi * f
    assert tail_frame(10 + 100 / (1 + jw * 1e-3)) is None
    line = 10.0 + 1 / (1e-5 * jw**0.95)
    assert np.ptp(-line.imag) / np.ptp(line.real) < TAIL_RATIO and tail_frame(line, line) is None


# SYNTHETIC two arcs (20 Ω + 100 Ω ∥ 10 µF + 40 Ω ∥ CPE), 0.5 % noise, seed 7
ARC_F = np.geomspace(0.1, 1e5, 50)


def two_arcs() -> tuple[np.ndarray, np.ndarray]:
    jw = 2j * np.pi * ARC_F
    z = 20.0 + 100.0 / (1 + jw * 100.0 * 1e-5) + 40.0 / (1 + (jw * 40.0 * 2e-4) ** 0.8)
    rng = np.random.default_rng(7)
    return z, z + 0.005 * np.abs(z) * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size))


def test_an_ordinary_spectrum_keeps_the_limits_it_had():
    z, zn = two_arcs()
    fig = plot_spectrum((ARC_F, zn), (ARC_F, z))
    fig.canvas.draw()
    ax = fig.axes[0]
    # no zoom: the panel follows the data (`nyquist_frame`) with matplotlib's 5 % margins
    # (2026-12-06; before, the code gave the limits it had before the tail zoom, Z' widened to
    # 188.8 Ω beside data that end at 160 Ω, which the height-capped panel's equal scales asked)
    x0, x1, y0, y1 = nyquist_frame(zn, z)
    assert ax.get_xlim() == pytest.approx((x0 - 0.05 * (x1 - x0), x1 + 0.05 * (x1 - x0)), rel=1e-9)
    assert ax.get_ylim() == pytest.approx((y0 - 0.05 * (y1 - y0), y1 + 0.05 * (y1 - y0)), rel=1e-9)
    assert not ax.texts
    plt.close(fig)
    fits = [stand_in_fit("R0 + R1 || C1 + R2 || CPE2", ARC_F, zn, z), stand_in_fit("R0 + R1 || C1", ARC_F, zn, z * 0.98)]
    fig = plot_comparison(SimpleNamespace(fits=fits, best=fits[0].model))
    fig.canvas.draw()
    ax = fig.axes[0]
    assert ax.get_xlim() == pytest.approx((12.591880078600376, 167.06833814708125), rel=1e-9)
    assert ax.get_ylim() == pytest.approx((-2.8270314037210653, 59.36520593045138), rel=1e-9)
    plt.close(fig)


def test_a_finger_comparison_s_legend_covers_no_axis_or_tick_label():
    # the walkthrough's compare figure: the Nyquist legend of two long model names was wider than
    # the sliver of a panel and covered its axis and its top tick label
    z_true = finger(FINGER_F)
    z = noisy(z_true, seed=78)
    names = ("C_s + C_i + R_sc || C_sc + R_f [C_i=1.7e-09]", "C_s + C_i + R_sc || CPE_sc + R_f [C_i=1.7e-09]")
    fits = [stand_in_fit(names[0], FINGER_F, z, z_true * (1 + 0.01j)), stand_in_fit(names[1], FINGER_F, z, z_true)]
    fig = plot_comparison(SimpleNamespace(fits=fits, best=names[1]))
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    nyquist = fig.axes[0]
    assert nyquist.get_window_extent().width > 0.25 * fig.bbox.width  # no sliver
    labels = [t.get_window_extent(renderer) for ax in fig.axes for axis in (ax.xaxis, ax.yaxis)
              for t in axis.get_ticklabels() + [axis.label] if t.get_visible() and t.get_text()]
    for ax in fig.axes:
        legend = ax.get_legend()
        if legend is None:
            continue
        box = legend.get_window_extent(renderer)
        assert not any(box.overlaps(label) for label in labels), ax.get_title()
        frame = ax.get_window_extent()
        inside = box.x0 >= frame.x0 - 0.5 and box.x1 <= frame.x1 + 0.5 and box.y0 >= frame.y0 - 0.5 and box.y1 <= frame.y1 + 0.5
        # inside its frame, or outside it altogether (moved above or below the panel)
        assert inside or not box.overlaps(frame), ax.get_title()
    plt.close(fig)


def test_a_legend_wider_than_its_panel_is_moved_off_the_axis():
    # `legends_off_data` moved only a legend over drawn points; one wider than a narrow panel
    # (long model names) spread over the axis and its tick labels beside it, and is moved too
    from impedax.plotting import legends_off_data

    fig = plt.figure(figsize=(8, 4), layout="constrained")
    grid = fig.add_gridspec(1, 2, width_ratios=[1, 6])
    narrow, wide = fig.add_subplot(grid[0]), fig.add_subplot(grid[1])
    narrow.plot([0.0, 0.1], [1.0, 0.9], label="C_s + C_i + R_sc || CPE_sc + R_f [C_i=1.7e-09] (rms_rel 1.19 %)")
    narrow.set(xlim=(0, 1), ylim=(0, 1))
    narrow.legend(loc="lower right")  # (over no point: the line lies at the top left)
    wide.plot([0, 1], [1, 0])
    legends_off_data(fig)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    box = narrow.get_legend().get_window_extent(renderer)
    labels = [t.get_window_extent(renderer) for ax in (narrow, wide) for t in ax.get_yticklabels() + ax.get_xticklabels() if t.get_text()]
    assert not any(box.overlaps(label) for label in labels)
    assert not box.overlaps(wide.get_window_extent())
    assert not box.overlaps(narrow.get_window_extent())  # (before: across the panel and its axis, 500 px wide on a panel of 5)
    plt.close(fig)


# SYNTHETIC R0 + R1 || CPE1 + Wo1 + G1 from 10 mHz to 1 MHz (review 2026-12-06): the open Warburg is
# a capacitor below ~1 Hz, −Z'' reaches 8 kΩ beside a structure 137 Ω wide (58×, under TAIL_RATIO)
WO_F = np.geomspace(1e-2, 1e6, 71)


def arcs_with_a_tail(f: np.ndarray) -> np.ndarray:
    jw = 2j * np.pi * f
    cpe = 1 / (1e-6 * jw**0.8)
    s = np.sqrt(jw * 0.1)
    return 10 + 100 * cpe / (100 + cpe) + 50 / (np.tanh(s) * s) + 20 / np.sqrt(1 + jw * 1e-3)


@pytest.mark.parametrize("with_data", [True, False], ids=["fit", "model_alone"])
def test_arcs_below_a_58x_tail_are_not_drawn_as_a_strip(with_data):
    z_true = arcs_with_a_tail(WO_F)
    span = np.ptp(z_true.real)
    assert 20 * span < np.ptp(-z_true.imag) < TAIL_RATIO * span  # (the premise: between the two ratios)
    z = noisy(z_true, seed=5, level=0.002)
    fig = plot_spectrum((WO_F, z), (WO_F, z_true)) if with_data else plot_spectrum(model=(WO_F, z_true))
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    box = ax.get_window_extent()
    assert box.width > 0.25 * box.height, (box.width, box.height)  # before: 8-11 px wide beside 440-590 px high
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert x0 <= z_true.real.min() and x1 >= z_true.real.max()
    arcs = -z_true.imag < 2 * span  # the two arcs and the Warburg's start, above 1 Hz
    assert ((-z.imag[arcs] >= y0) & (-z.imag[arcs] <= y1)).all()
    assert_equal_scales(ax)
    assert "runs off the top" in " ".join(t.get_text() for t in ax.texts)
    legend = ax.get_legend().get_window_extent(renderer)
    inside = legend.x0 >= box.x0 - 0.5 and legend.x1 <= box.x1 + 0.5 and legend.y0 >= box.y0 - 0.5 and legend.y1 <= box.y1 + 0.5
    assert inside or not legend.overlaps(box)
    plt.close(fig)


def test_meyer_s_finger_simulated_alone_is_zoomed_on_the_skin():
    # `impedax simulate --plot` draws the model alone: it drew a vertical line on a GΩ axis
    z_true = finger(FINGER_F)
    fig = plot_spectrum(model=(FINGER_F, z_true))
    fig.canvas.draw()
    ax = fig.axes[0]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    skin = np.ptp(z_true.real)
    assert y1 - y0 < 5 * skin and x1 - x0 < 5 * skin, (x0, x1, y0, y1)
    assert "runs off the top" in " ".join(t.get_text() for t in ax.texts)
    plt.close(fig)


def test_a_steep_cpe_line_is_not_taken_for_a_tail():
    # a blocking electrode's line keeps its whole extent at any slope under TAIL_RATIO: α = 0.99,
    # −Z''/Z' = tan(89.1°) = 64, points spread evenly up the line
    jw = 2j * np.pi * np.geomspace(1e-2, 1e5, 60)
    line = 1 / (1e-5 * jw**0.99)
    assert 20 < np.ptp(-line.imag) / np.ptp(line.real) < TAIL_RATIO
    assert tail_frame(line, line) is None


def test_a_capacitor_alone_beside_an_arc_frames_the_arc_not_its_round_off():
    # SYNTHETIC: the demo's air gap, R_EP || CPE_EP || C_gap (113 MΩ, 4.19 nF s^(α-1), α 0.296,
    # 410 pF) over 1 Hz–1 MHz with 0.5 % noise, −Z'' from 387 Ω to 26 MΩ, beside the naive model C_gap alone as
    # impedax compiles it (its Z' round-off, nΩ, not 0): the panel took that round-off for the
    # structure's Z' span and showed 6 nΩ of −Z'' around the 1 MHz point (the demo's step 2)
    import impedax as ix

    f = np.geomspace(1.0, 1e6, 61)
    jw = 2j * np.pi * f
    z = noisy(1 / (1 / 113e6 + 4.19e-9 * jw**0.296 + jw * 410e-12), 0, level=0.005)  # (noise puts Z' below 0 at the top, as the demo's)
    assert z.real.min() < 0
    z_model = np.asarray(ix.compile_circuit(ix.parse("C_gap"))({"C_gap": 959e-12}, f), complex)
    z_model = z_model + 1e-18 * np.abs(z_model) * np.sin(np.arange(f.size))  # a fit's round-off in Z' (±4 nΩ in the demo)
    assert tail_frame(z, z_model) is None  # an ordinary arc: the data's Z' span, 57 MΩ, is 0.4 × its −Z'' span
    fig = plot_spectrum((f, z), (f, z_model))
    try:
        fig.canvas.draw()
        ax = fig.axes[0]
        low, high = ax.get_ylim()
        # the panel shows the whole arc: −Z'' from its lowest to its highest point (the formula's)
        assert low <= float((-z.imag).min()) and high >= float((-z.imag).max())
        assert ax.get_xlim()[1] >= float(z.real.max())
    finally:
        plt.close(fig)
