"""Residual panels read plainly: no offset or multiplier text beside a residual axis, and
residuals at the round-off of float64 (a fit to noise-free SYNTHETIC data) named as such. A fit
of R0 + R1 || C1 to its own noise-free spectrum drew ticks −4 … 4 under a detached "1e−14",
read as residuals of a few percent (2026-12-07). Oracle: the drawn figure's offset text and
tick labels (each read back as a number equals its tick's position), and the legend's texts;
the spectra are written here with numpy."""

import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from impedax.plotting import ROUNDING_RESIDUAL, plot_residuals, plot_spectrum  # noqa: E402


def _rc(f):
    return 20.0 + 500.0 / (1 + 2j * np.pi * f * 500.0 * 1e-6)


F = np.geomspace(0.1, 1e5, 61)


def _shown_ticks(axis):
    """(position, text) of the major tick labels ``axis`` draws in view."""
    lo, hi = sorted(axis.get_view_interval())
    locs = axis.get_majorticklocs()
    ticks = axis.get_major_ticks(len(locs))
    return [(float(loc), t.label1.get_text()) for loc, t in zip(locs, ticks) if lo <= loc <= hi and t.label1.get_text()]


def _read(text: str) -> float:
    return float(text.replace("\N{MINUS SIGN}", "-"))


def _assert_plain(ax):
    """No offset text, and every tick label is its tick's own value."""
    ax.figure.draw_without_rendering()
    assert ax.yaxis.get_offset_text().get_text() == ""
    shown = _shown_ticks(ax.yaxis)
    assert len(shown) >= 2
    spacing = np.min(np.diff([loc for loc, _ in shown]))
    for loc, text in shown:
        assert _read(text) == pytest.approx(loc, abs=1e-6 * spacing), (loc, text)
    return [text for _, text in shown]


def _legend_texts(ax):
    legend = ax.get_legend()
    return [t.get_text() for t in legend.get_texts()] if legend is not None else []


def test_a_fit_at_rounding_level_has_plain_residual_ticks_and_says_so():
    """Model and data equal but for round-off, 1e-16 … 5e-16 of |Z| (the level of a fit to
    noise-free SYNTHETIC data): the ticks read as e-notation percentages, the legend names the
    rounding level with the largest |residual| (5e-14 %)."""
    z = _rc(F)
    rng = np.random.default_rng(1)
    bump = 1 + rng.uniform(1e-16, 5e-16, F.size) * np.exp(1j * rng.uniform(0, 2 * np.pi, F.size))
    fig = plot_spectrum((F, z), (F, z * bump))
    ax_res = fig.axes[3]
    texts = _assert_plain(ax_res)
    assert any("e" in t for t in texts)  # (e-notation: values about 1e-14 %)
    notes = [t for t in _legend_texts(ax_res) if t.startswith("rounding level")]
    assert len(notes) == 1
    largest = float(re.search(r"≤ (\S+) %", notes[0]).group(1))
    r = (z * bump - z) / np.abs(z) * 100
    assert largest == pytest.approx(max(np.abs(r.real).max(), np.abs(r.imag).max()), rel=0.05)
    plt.close(fig)


def test_an_ordinary_misfit_keeps_plain_ticks_and_no_rounding_note():
    """A model 1 % off (R1 = 505 Ω against 500 Ω): ticks in plain decimals, no note."""
    z = _rc(F)
    model = 20.0 + 505.0 / (1 + 2j * np.pi * F * 505.0 * 1e-6)
    fig = plot_spectrum((F, z), (F, model))
    ax_res = fig.axes[3]
    texts = _assert_plain(ax_res)
    assert not any("e" in t for t in texts)
    assert not any(t.startswith("rounding level") for t in _legend_texts(ax_res))
    plt.close(fig)


def test_the_kk_residual_panel_at_rounding_level_reads_plainly():
    """`plot_residuals` (the KK test's panel): offsets of 2e-15 and −3e-15 of |Z|."""
    fig, ax = plt.subplots()
    real, imag = np.full(F.size, 2e-15), np.full(F.size, -3e-15)
    real[::2] = 1e-15
    plot_residuals(ax, F, real, imag)
    _assert_plain(ax)
    assert any(t.startswith("rounding level") and "3e-13 %" in t for t in _legend_texts(ax))
    plt.close(fig)


def test_the_rounding_threshold_separates_round_off_from_six_digit_files():
    """A residual just above `ROUNDING_RESIDUAL` (a file written to 6 digits leaves 1e-7 of |Z|
    or more) is no rounding: no note."""
    fig, ax = plt.subplots()
    plot_residuals(ax, F, np.full(F.size, 3 * ROUNDING_RESIDUAL), np.zeros(F.size))
    assert not any(t.startswith("rounding level") for t in _legend_texts(ax))
    plt.close(fig)


@pytest.mark.parametrize("which", ["fit", "compare"])
def test_a_noise_free_synthetic_fit_and_comparison_read_plainly(which):
    """End to end: `ix.fit` of R0 + R1 || C1 to its own noise-free SYNTHETIC spectrum, and
    `ix.compare` of it beside R0 + R1 || CPE1 (whose α goes to 1): the residual panel carries
    the rounding note and, on its linear axis (the fit's), no offset text."""
    import impedax as ix

    data = ix.data.make_spectrum(F, _rc(F))
    fit = ix.fit("R0 + R1 || C1", data)
    assert fit.rms_rel < ROUNDING_RESIDUAL  # (the case)
    if which == "fit":
        fig = fit.plot()
        ax_res = fig.axes[3]
        _assert_plain(ax_res)
    else:
        fig = ix.compare([fit, ix.fit("R0 + R1 || CPE1", data)]).plot()
        ax_res = fig.axes[3]
        assert ax_res.get_yscale() == "log"
    assert any(t.startswith("rounding level") for t in _legend_texts(ax_res))
    plt.close(fig)


def test_a_batchs_residual_map_colour_bar_reads_plainly():
    """`BatchFitResult.plot_residual_map` of three noise-free SYNTHETIC spectra (R1 480, 500,
    520 Ω): the colour bar's ticks are its values in e-notation, with no "1e−14" beside them."""
    import impedax as ix

    zs = np.stack([20.0 + r / (1 + 2j * np.pi * F * r * 1e-6) for r in (480.0, 500.0, 520.0)])
    batch = ix.fit("R0 + R1 || C1", ix.make_spectrum(F, zs, dims=("cell",)))
    fig = batch.plot_residual_map()
    bar = next(ax for ax in fig.axes if ax.get_label() == "<colorbar>")
    texts = _assert_plain(bar)
    assert any("e" in t for t in texts)
    plt.close(fig)
