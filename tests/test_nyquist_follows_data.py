"""Every single-spectrum Nyquist panel follows the data as the comparison's and the diagnosis'
do (`nyquist_view` frames it with `nyquist_frame`): before 2026-12-06 the fit figure
(`plot_spectrum`, `FitResult.plot`), the KK, DRT and refinement figures set equal scales over a
panel capped in height (`TALLEST_PANEL`), which widened the Z' range past the data: REAL
exampleDataZPlot.z's fit to 900 Ω beside data and curve that end at 615 Ω, exampleDataGamry.DTA's
KK test to 23 kΩ beside 18 kΩ, exampleDataBioLogic.mpt's DRT to ~150 Ω beside 111 Ω.
Oracles: SYNTHETIC spectra written here with numpy and the REAL files; the axis limits read back
from matplotlib after a draw."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.plotting import MODEL_OVERSHOOT, TAIL_VIEW, model_curve, plot_spectrum, tail_frame  # noqa: E402

REAL = Path(__file__).parent / "fixtures" / "real"

# matplotlib's 5 % margin on either side of the frame, and some room to spare; the model's
# overshoot (`MODEL_OVERSHOOT`) is inside the curves' span the tests measure
MARGIN = 2 * 0.05 + 0.03


def check_follows(ax, z_data, *curves) -> None:
    """The panel's Z' and −Z'' ranges exceed the span of the data and the curves (each curve
    counted as far as `nyquist_frame` lets it widen the frame) by no more than `MARGIN` of the
    larger span, every data point lies inside the axes, and the scales are equal."""
    ax.get_figure().canvas.draw()
    z = np.asarray(z_data, complex).ravel()
    x, y = z.real, -z.imag
    reach = MODEL_OVERSHOOT * max(np.ptp(x), np.ptp(y))
    xs, ys = [x], [y]
    for c in curves:
        c = np.asarray(c, complex).ravel()
        xs.append(np.clip(c.real, x.min() - reach, x.max() + reach))
        ys.append(np.clip(-c.imag, y.min() - reach, y.max() + reach))
    xs, ys = np.concatenate(xs), np.concatenate(ys)
    span = max(np.ptp(xs), np.ptp(ys))
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert x1 - x0 <= np.ptp(xs) + MARGIN * span, f"Z' range {x0:.4g}..{x1:.4g} beside data and curves over {xs.min():.4g}..{xs.max():.4g}"
    assert y1 - y0 <= np.ptp(ys) + MARGIN * span, f"-Z'' range {y0:.4g}..{y1:.4g} beside data and curves over {ys.min():.4g}..{ys.max():.4g}"
    assert x0 <= x.min() and x.max() <= x1 and y0 <= y.min() and y.max() <= y1, "a data point outside the axes"
    frame = ax.get_window_extent()
    assert frame.width / (x1 - x0) == pytest.approx(frame.height / (y1 - y0), rel=0.02), "scales not equal"


def synthetic_arc():
    """SYNTHETIC R0 + R1‖C1, 150 Ω + 470 Ω at τ = 15 µs (ZPlot's arc, 1:2 high to wide, whose
    panel the height cap widened), with 0.3 % noise."""
    f = np.geomspace(3e5, 3e3, 20)
    z = 150.0 + 470.0 / (1 + 2j * np.pi * f * 15e-6)
    return f, z, z * (1 + 0.003 * np.random.default_rng(0).standard_normal(f.size))


def test_fit_figure_of_a_synthetic_arc_follows_the_data():
    f, z, data = synthetic_arc()
    fig = plot_spectrum((f, data), (f, z))
    check_follows(fig.axes[0], data, z)
    plt.close(fig)


def test_fit_figure_holds_a_curve_and_points_the_caller_adds():
    """`plot_spectrum`'s ``nyquist_curves`` widen the frame by at most `MODEL_OVERSHOOT` (a
    curve 30 % longer runs off), ``nyquist_points`` (masked points) are held inside."""
    f, z, data = synthetic_arc()
    far = 150.0 + 700.0 / (1 + 2j * np.pi * f * 15e-6)
    masked = np.array([700.0 - 20j])
    fig = plot_spectrum((f, data), (f, z), nyquist_curves=[far], nyquist_points=masked)
    ax = fig.axes[0]
    check_follows(ax, np.concatenate([data, masked]), z, far)
    fig.canvas.draw()
    assert ax.get_xlim()[1] < far.real.max()  # (the far curve runs off the panel)
    plt.close(fig)


def test_steep_synthetic_spectrum_keeps_every_point_at_equal_scales():
    """SYNTHETIC R0 + CPE (α = 0.9, −Z'' about 6× Z'): the steep layout, its panel narrowed to
    the data's shape, every point inside."""
    f = np.geomspace(1e5, 1e-1, 50)
    z = 20.0 + 1.0 / ((2j * np.pi * f) ** 0.9 * 1e-4)
    data = z * (1 + 0.003 * np.random.default_rng(2).standard_normal(f.size))
    fig = plot_spectrum((f, data), (f, z))
    check_follows(fig.axes[0], data, z)
    plt.close(fig)


def test_capacitive_tail_keeps_its_zoom():
    """SYNTHETIC R0 + R1‖C1 + C_s (a capacitive tail to 1.6 MΩ beside Z' ≤ 120 Ω): the panel
    stays zoomed on the structure (`tail_frame`), as before."""
    f = np.geomspace(1e5, 1e-1, 50)
    w = 2 * np.pi * f
    z = 20.0 + 100.0 / (1 + 1j * w * 1e-4) + 1.0 / (1j * w * 1e-6)
    fig = plot_spectrum((f, z), (f, z))
    ax = fig.axes[0]
    fig.canvas.draw()
    zoom = tail_frame(z, z)
    assert zoom is not None
    assert ax.get_ylim()[1] == pytest.approx(zoom[3] + 0.05 * (zoom[3] - zoom[2]), rel=0.01)
    assert ax.get_ylim()[1] < 0.01 * (-z.imag).max()
    plt.close(fig)


@pytest.mark.slow  # (a fit of a real file; the synthetic arc above checks the same in `make test`)
def test_real_zplot_fit_figure_follows_the_data():
    result = ix.fit("R0 + R1 || C1", ix.load(REAL / "exampleDataZPlot.z"))
    fig = result.plot()
    check_follows(fig.axes[0], result.z_data, model_curve(result)[1])
    plt.close(fig)


def test_real_gamry_kk_figure_follows_the_data():
    result = ix.kk_test(ix.load(REAL / "exampleDataGamry.DTA"))
    fig = result.plot()
    check_follows(fig.axes[0], result.impedance, result.kk_impedance)
    plt.close(fig)


def test_real_biologic_drt_figure_follows_the_data():
    result = ix.drt(ix.load(REAL / "exampleDataBioLogic.mpt"))
    fig = result.plot()
    nyquist = next(ax for ax in fig.axes if ax.get_xlabel().startswith("Z'"))
    check_follows(nyquist, result.impedance, result.z_fit)
    plt.close(fig)


def stand_in_fit(model: str, f, z_model, z_data, rms_rel: float) -> SimpleNamespace:
    return SimpleNamespace(model=model, frequency=f, z_data=z_data, z_model=z_model, residuals=(z_model - z_data) / np.abs(z_data), rms_rel=rms_rel)


def test_refinement_figure_of_a_synthetic_arc_follows_the_data():
    """A stand-in refinement of the SYNTHETIC arc: a start 1 % off, a final fit."""
    from impedax.plotting.diagnosis import plot_refinement

    f, z, data = synthetic_arc()
    steps = [
        SimpleNamespace(fit=stand_in_fit("R0 + R1 || C1", f, z * 1.01, data, 0.01), effect=None, added=None, removed=(), model="R0 + R1 || C1", diagnosis=None, change="(start)"),
        SimpleNamespace(fit=stand_in_fit("R0 + R1 || C1 + L_lead", f, z, data, 0.003), effect="series_inductance", added="L_lead", removed=(), model="R0 + R1 || C1 + L_lead", diagnosis=None, change="+ L_lead"),
    ]
    refinement = SimpleNamespace(steps=steps, final_model=steps[-1].model, verdict="adequate", masked_points=[])
    fig = plot_refinement(refinement)
    nyquist = next(ax for ax in fig.axes if ax.get_xlabel().startswith("Z'"))
    check_follows(nyquist, data, z * 1.01, z)
    plt.close(fig)
