"""Every relaxation-time axis τ [s] reads as the frequency axes do (`plotting.time_axis`, the
rule of `plotting.frequency_axis` with times below 0.1 s in their SI prefix, 2026-12-08): 1µ,
10µ, 100µ, 1m, 10m, 0.1, 1, 10 … 1000, 10k, on an axis labelled in seconds. The DRT's γ(τ)
panel, a DRT batch's curves and its map over the spectra read matplotlib's 10⁻⁶ … 10³ until
then, beside frequency axes reading 0.01 … 10k. Oracles, as tests/test_frequency_axis_ticks.py's:
the tick labels as drawn on an Agg canvas, each read back as a number (SI prefixes by their
powers of ten) against its tick's position, the decades' texts against a table written here by
hand, and the labels' boxes apart. Data: REAL exampleData.csv (impedance.py's, 3.2 mHz – 10 kHz)
for the single DRT figure; SYNTHETIC R ∥ C arcs (closed form, 0.2 % noise, fixed seeds) for the
batch figure."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.plotting import time_axis  # noqa: E402
from test_frequency_axis_ticks import _labels, assert_plain_labels, decade  # noqa: E402  (labels as drawn; plain, read back, apart; a tick's decade)

REAL = Path(__file__).parent / "fixtures" / "real"

# how a decade of τ reads on every time axis (written by hand, not by the code under test)
TIME_DECADE_TEXT = {1e-7: "100n", 1e-6: "1µ", 1e-5: "10µ", 1e-4: "100µ", 1e-3: "1m", 1e-2: "10m", 1e-1: "0.1", 1.0: "1", 1e1: "10", 1e2: "100", 1e3: "1000", 1e4: "10k"}


def _tau_axes(fig):
    """The axes of ``fig`` whose label is τ [s], as (Axes' axis, ...): x or y."""
    return [axis for ax in fig.axes for axis in (ax.xaxis, ax.yaxis) if axis.get_label().get_text() == "τ [s]"]


def test_the_real_drt_figure_reads_its_tau_decades_in_seconds():
    """REAL exampleData.csv: γ over τ from 7 µs to 1100 s reads each decade, 10µ to 1000."""
    fig = ix.drt(ix.load(REAL / "exampleData.csv")).plot()
    try:
        (axis,) = _tau_axes(fig)
        assert axis is axis.axes.xaxis and axis.get_scale() == "log"
        assert_plain_labels(fig, axis, "DRT γ(τ)", TIME_DECADE_TEXT)
        decades = [text for loc, text, _ in sorted(_labels(fig, axis)) if decade(loc) in TIME_DECADE_TEXT]
        assert decades == ["10µ", "100µ", "1m", "10m", "0.1", "1", "10", "100", "1000"]
    finally:
        plt.close(fig)


def test_a_drt_batchs_curves_and_map_read_tau_in_seconds():
    """Three SYNTHETIC spectra, 10 Ω + 50 Ω ∥ (τ = 0.1 ms) + 100 Ω ∥ (τ = 10, 30, 100 ms): the
    curves' τ axis (x) and the map's (y) read plainly, each decade as the table writes it."""
    f = np.geomspace(1e5, 0.1, 61)
    w = 2 * np.pi * f
    rng = np.random.default_rng(60)
    z = np.stack([10.0 + 50.0 / (1 + 1j * w * 1e-4) + 100.0 / (1 + 1j * w * tau) for tau in (0.01, 0.03, 0.1)])
    z = z * (1 + 0.002 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    fig = ix.drt(ix.make_spectrum(f, z, dims=("cycle",), coords={"cycle": [5, 6, 7]})).plot()
    try:
        axes = _tau_axes(fig)
        assert [axis is axis.axes.xaxis for axis in axes] == [True, False]  # (the curves' x, the map's y)
        for axis in axes:
            assert axis.get_scale() == "log"
            assert_plain_labels(fig, axis, "DRT batch", TIME_DECADE_TEXT)
            assert {"1m", "0.1", "1"} <= {text for _, text, _ in _labels(fig, axis)}
    finally:
        plt.close(fig)


@pytest.mark.parametrize("width", [1.5, 2.0, 3.0])
@pytest.mark.parametrize("band", [(1e-7, 1e4), (1e-6, 10.0), (2e-3, 3e-2), (0.02, 0.3)])
def test_a_narrow_time_panel_keeps_its_labels_apart_and_readable(width, band):
    """11 decades on a panel 1.5 in wide (every few decades labelled), and ranges within a decade
    or two, where the minor ticks are labelled (2m, 3m … 20m; 20m, 30m … 0.2, 0.3 across the
    0.1 s at which the prefix ends): two labels or more, each its tick's value, none over another."""
    fig, ax = plt.subplots(figsize=(width, 2.0), layout="constrained")
    tau = np.geomspace(*band, 40)
    ax.semilogx(tau, np.log(tau))
    ax.set_xlabel("τ [s]")
    time_axis(ax.xaxis)
    assert_plain_labels(fig, ax.xaxis, (width, band), TIME_DECADE_TEXT)
    for loc, text, _ in _labels(fig, ax.xaxis):
        assert not (loc < 0.1 * (1 - 1e-9) and text[-1].isdigit()), (loc, text)  # (below 0.1 s in its prefix: 20m, not 0.02)
    plt.close(fig)


def test_time_axis_makes_a_linear_y_axis_log():
    fig, ax = plt.subplots(figsize=(4, 4), layout="constrained")
    ax.plot([1, 2], [1e-6, 10.0])
    time_axis(ax.yaxis)
    assert ax.get_yscale() == "log" and ax.get_xscale() == "linear"
    assert [text for loc, text, _ in sorted(_labels(fig, ax.yaxis)) if decade(loc) in TIME_DECADE_TEXT] == ["1µ", "10µ", "100µ", "1m", "10m", "0.1", "1", "10"]
    plt.close(fig)


@pytest.mark.slow  # (the script's DRT of three cycles and a fit: ~13 s)
def test_the_gallery_drt_figures_read_tau_in_seconds(tmp_path):
    """examples/drt_guides_the_circuit.py (REAL battery cycles): the γ(τ) panel of
    drt_guides_the_circuit.png and the ageing overlay drt_battery_ageing.png, as the gallery shows them."""
    from test_example_legends import _saved_figures

    figures = _saved_figures("drt_guides_the_circuit", tmp_path)
    try:
        assert set(figures) == {"drt_guides_the_circuit.png", "drt_battery_ageing.png"}
        for name, fig in figures.items():
            (axis,) = _tau_axes(fig)
            assert_plain_labels(fig, axis, name, TIME_DECADE_TEXT)
    finally:
        for fig in figures.values():
            plt.close(fig)
