"""Every frequency axis of impedax's figures reads one way (`plotting.frequency_axis`, 2026-12-07):
plain numbers, an SI prefix from 10⁴ up and below 10⁻³ (0.001, 0.01 … 1000, 10k, 100k, 1M).
The gap and force figures and the batch maps read so; the Bode, residual, KK, Z-HIT, DRT,
diagnosis, refinement, comparison and posterior-band figures read matplotlib's 10⁰ … 10⁵ until then.
Oracles: the tick labels as drawn on an Agg canvas, each read back as a number (SI prefixes by
their powers of ten) against its tick's position, the decades' texts against a table written
here by hand, and the labels' boxes apart. Data: REAL exampleData.csv (impedance.py's, 3.2 mHz –
10 kHz, between 7 and 8 decades) for the KK, Z-HIT and DRT figures; SYNTHETIC numpy spectra and duck-typed
results (no fit) elsewhere, and one small SYNTHETIC batch fitted for the batch figures."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
import warnings

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.plotting import frequency_axis, legends_off_data, plot_bode, plot_spectra, plot_spectrum  # noqa: E402
from impedax.plotting.bayes import plot_joint_posterior_bands, plot_posterior_bands  # noqa: E402
from impedax.plotting.comparison import plot_comparison  # noqa: E402
from impedax.plotting.diagnosis import plot_diagnosis, plot_refinement  # noqa: E402
from impedax.plotting.models import plot_force_bands, plot_force_spectrum  # noqa: E402
from test_gap_figure_frequency_ticks import _bands, _number  # noqa: E402  (force bands over a grid, numpy; a label read back as a number)
from test_gap_outputs import _stub  # noqa: E402  (a GapAnalysis built by hand)
from test_presentation_review import F, diagnosis_stand_in, fit, rc, refinement_stand_in  # noqa: E402

REAL = Path(__file__).parent / "fixtures" / "real"

# how a decade reads on every frequency axis (written by hand, not by the code under test)
DECADE_TEXT = {1e-3: "0.001", 1e-2: "0.01", 1e-1: "0.1", 1.0: "1", 1e1: "10", 1e2: "100", 1e3: "1000", 1e4: "10k", 1e5: "100k", 1e6: "1M"}
def decade(loc: float) -> float:
    """A tick's position as the tables' keys write it: matplotlib places 10⁻⁵ at 9.999999999999999e-06."""
    return float(f"{loc:.9g}")


def _labels(fig, axis):
    """(tick position, text, box) of the visible tick labels of ``axis`` (major and minor) in view."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    lo, hi = sorted(axis.get_view_interval())
    ticks = [t for t in axis.get_major_ticks() + axis.get_minor_ticks() if lo * (1 - 1e-9) <= t.get_loc() <= hi * (1 + 1e-9)]
    return [(t.get_loc(), t.label1.get_text(), t.label1.get_window_extent(renderer)) for t in ticks if t.label1.get_visible() and t.label1.get_text()]


def assert_plain_labels(fig, axis, what, decades=None) -> None:
    """The visible labels of ``axis``: two or more, none in 10ⁿ or exponent form, each read back
    as its tick's value, those of ``decades`` (value → text) as written there, none over another."""
    labels = _labels(fig, axis)
    texts = [text for _, text, _ in labels]
    assert len(labels) >= 2, (what, texts)
    for loc, text, _ in labels:
        assert "$" not in text and "^" not in text and "e+" not in text and "e-" not in text, (what, texts)  # (no 10ⁿ, no 1e+05)
        assert _number(text) == pytest.approx(loc, rel=1e-6), (what, loc, text)
        if decades is not None and decade(loc) in decades:
            assert text == decades[decade(loc)], (what, loc, text)
    boxes = [box for _, _, box in labels]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :]), (what, texts)


def _real():
    return ix.load(REAL / "exampleData.csv")


def _data():
    return rc(1.0) + rc(0.5, 1e-1, 0.0)


def _draws():
    return _data()[None, :] * (1 + 0.01 * np.random.default_rng(3).standard_normal((50, 1)))


def _fit_figure():
    fig = plot_spectrum((F, _data()), (F, _data() * 1.01))
    return fig, [ax.xaxis for ax in fig.axes[1:4]]


def _own_axes():
    fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3), layout="constrained")
    plot_bode(a, b, (F, _data()))
    return fig, [a.xaxis, b.xaxis]


def _spectra():
    fig = plot_spectra([(F, _data()), (F, 1.2 * _data())], ["a", "b"])
    return fig, [fig.axes[1].xaxis, fig.axes[2].xaxis]


def _kk():
    fig = ix.kk_test(_real()).plot()
    return fig, [ax.xaxis for ax in fig.axes[1:4]]


def _zhit():
    fig = ix.zhit(_real()).plot()
    return fig, [fig.axes[2].xaxis]  # (the panels above share it and show no labels)


def _drt():
    fig = ix.drt(_real()).plot()
    return fig, [fig.axes[i].xaxis for i in (1, 3, 4)]  # (residuals, |Z|, phase; τ by its own rule: tests/test_time_axis_ticks.py)


def _diagnosis():
    fig = plot_diagnosis(diagnosis_stand_in())
    return fig, [ax.xaxis for ax in fig.axes[1:4]]


def _refinement():
    fig = plot_refinement(refinement_stand_in())
    return fig, [ax.xaxis for ax in fig.axes if ax.get_xscale() == "log"]


def _comparison():
    data = _data()
    comparison = SimpleNamespace(fits=[fit("R0 + R1 || C1", rc(1.4), data, weighting="modulus"), fit("R0 + R1 || C1 + R2 || C2", data * 1.001, data, weighting="modulus")], best="R0 + R1 || C1 + R2 || C2")
    fig = plot_comparison(comparison)
    return fig, [ax.xaxis for ax in fig.axes[1:4]]


def _bands_figure():
    fig = plot_posterior_bands(F, _data(), F, _draws(), title="SYNTHETIC")
    return fig, [fig.axes[1].xaxis, fig.axes[2].xaxis]


def _joint_bands():
    fig = plot_joint_posterior_bands(F, np.stack([_data(), _data()]), ["trial=0", "trial=1"], F, np.stack([_draws(), _draws()]), title="SYNTHETIC")
    return fig, [fig.axes[i].xaxis for i in (1, 2, 4, 5)]


def _gap():
    fig = _stub(rhat_max=1.001).plot()
    return fig, [fig.axes[0].xaxis, fig.axes[2].xaxis]


def _force_bands():
    fig = plot_force_bands(SimpleNamespace(force=_bands(np.geomspace(1.0, 1e6, 61)), v0=75.0))
    return fig, [fig.axes[0].xaxis]


def _force_spectrum():
    f = np.geomspace(10.0, 1e6, 50)
    fig = plot_force_spectrum(f, 0.1 / (1 + (f / 1e4) ** 2), title="SYNTHETIC force")
    return fig, [fig.axes[0].xaxis]


@pytest.fixture(scope="module")
def batch():
    """4 SYNTHETIC spectra R0 + R1 ∥ C1 (R1 growing), 0.1 Hz – 100 kHz, 0.3 % noise (seed 11), fitted."""
    f = np.geomspace(0.1, 1e5, 31)
    rng = np.random.default_rng(11)
    z = np.stack([20.0 + r1 / (1 + 2j * np.pi * f * r1 * 1e-5) for r1 in (800.0, 900.0, 1000.0, 1100.0)])
    z = z * (1 + 0.003 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)) / np.sqrt(2))
    data = ix.make_spectrum(f, z, dims=("cycle",), coords={"cycle": np.arange(4)})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return data, ix.fit("R0 + R1 || C1", data, progress=False)


def _batch_phase(batch):
    fig = batch[1].plot(spectra="phase")
    return fig, [fig.axes[-1].xaxis]


def _residual_map(batch):
    fig = batch[1].plot_residual_map()
    return fig, [fig.axes[0].yaxis, fig.axes[1].yaxis]


def _kk_batch(batch):
    fig = ix.kk_test_batch(batch[0]).plot()
    return fig, [fig.axes[0].yaxis]


# {kind: (builder of (figure, its frequency axes), whether it takes the fitted batch)}
FIGURES = {
    "fit (plot_spectrum)": (_fit_figure, False), "plot_bode on your own axes": (_own_axes, False), "plot_spectra": (_spectra, False),
    "KK (REAL)": (_kk, False), "Z-HIT (REAL)": (_zhit, False), "DRT (REAL)": (_drt, False), "diagnosis": (_diagnosis, False),
    "refinement": (_refinement, False), "comparison": (_comparison, False), "posterior bands": (_bands_figure, False),
    "joint posterior bands": (_joint_bands, False), "gap analysis": (_gap, False), "force bands": (_force_bands, False),
    "force spectrum (impedax force --plot)": (_force_spectrum, False), "batch fit, phase panel": (_batch_phase, True),
    "residual map": (_residual_map, True), "KK batch map": (_kk_batch, True),
}
KINDS = list(FIGURES)


@pytest.fixture
def figure(request):
    """The figure of the test's ``kind`` and its frequency axes (the batch fitted once)."""
    build, with_batch = FIGURES[request.param]
    drawn = build(request.getfixturevalue("batch")) if with_batch else build()
    yield drawn
    plt.close(drawn[0])


@pytest.mark.parametrize("figure", KINDS, indirect=True)
def test_every_frequency_axis_reads_plain_numbers_of_its_ticks(figure, request):
    kind = request.node.callspec.id
    fig, axes = figure
    assert axes, kind
    for axis in axes:
        assert axis.get_scale() == "log", kind
        assert_plain_labels(fig, axis, kind, DECADE_TEXT)  # (one way for every figure: 1000, 10k; not 1k nor 10000)


def test_the_real_spectrum_reads_its_decades_as_the_gap_figure_reads_its_six():
    """REAL exampleData.csv runs from 3.2 mHz to 10 kHz: the KK figure's residual axis reads each
    decade, 0.01 to 10k, as the force figure reads 1 to 1M."""
    fig, axes = _kk()
    decades = [text for loc, text, _ in sorted(_labels(fig, axes[-1])) if loc in DECADE_TEXT]
    assert decades == ["0.01", "0.1", "1", "10", "100", "1000", "10k"]
    plt.close(fig)
    fig, axes = _force_bands()
    assert [text for _, text, _ in sorted(_labels(fig, axes[0]))] == ["1", "10", "100", "1000", "10k", "100k", "1M"]
    plt.close(fig)


@pytest.mark.parametrize("width", [1.5, 2.0, 3.0])
@pytest.mark.parametrize("band", [(1e-3, 1e5), (1e-2, 1e6), (20.0, 60.0), (0.5, 8.0)])
def test_a_narrow_panel_keeps_its_labels_apart_and_readable(width, band):
    """8 decades on a panel 1.5 in wide (labelled every few decades, "0.001" the widest label),
    and a band within a decade (its minor ticks labelled: 20, 30, 40, 60): two labels or more,
    none over another. matplotlib's 2×10¹, 3×10¹ … ran into each other on such panels (by 32 px
    at 1.5 in, 20 – 60 Hz)."""
    fig, ax = plt.subplots(figsize=(width, 2.0), layout="constrained")
    f = np.geomspace(*band, 40)
    ax.semilogx(f, np.log(f))
    frequency_axis(ax.xaxis)
    labels = _labels(fig, ax.xaxis)
    texts = [text for _, text, _ in labels]
    assert len(labels) >= 2, texts
    for loc, text, _ in labels:
        assert _number(text) == pytest.approx(loc, rel=1e-6), (loc, text)
    boxes = sorted((box for _, _, box in labels), key=lambda b: b.x0)
    assert all(right.x0 > left.x1 for left, right in zip(boxes, boxes[1:])), texts
    plt.close(fig)


def test_frequency_axis_makes_a_linear_axis_log_and_ticks_a_y_axis():
    fig, ax = plt.subplots(figsize=(4, 4), layout="constrained")
    ax.plot([1, 2], [10.0, 1e5])
    frequency_axis(ax.yaxis)
    assert ax.get_yscale() == "log" and ax.get_xscale() == "linear"
    assert [text for loc, text, _ in sorted(_labels(fig, ax.yaxis)) if loc in DECADE_TEXT] == ["10", "100", "1000", "10k", "100k"]
    plt.close(fig)


def test_a_legend_on_curves_of_its_twin_axis_goes_off_them():
    """The gap figure's force legend lies on the force axis, the gap voltage's curves on its twin
    (the right axis): `legends_off_data` counted the force axis' own curves alone and left the
    legend over the twin's. Here the host's curve runs along the bottom, the twin's across the
    upper right, where the legend stands; the twin's points (from its own data transform)
    must end up outside the legend's box, and without the twin's curve the legend stays put."""

    def figure(with_twin_curve: bool):
        fig, ax = plt.subplots(figsize=(5, 3.5), layout="constrained")
        x = np.linspace(0.0, 1.0, 50)
        ax.plot(x, 0.05 + 0.02 * x, label="force (host)")
        ax.set_ylim(0.0, 1.0)
        twin = ax.twinx()
        twin.set_ylim(0.0, 1.0)
        if with_twin_curve:
            twin.plot(x, np.full(x.size, 0.93), ":", label="gap voltage (twin)")
        ax.legend(loc="upper right")
        return fig, ax, twin

    fig, ax, twin = figure(True)
    fig.draw_without_rendering()
    inside = ax.get_legend().get_window_extent()
    (line,) = twin.get_lines()
    xy = twin.transData.transform(line.get_xydata())
    covered = (xy[:, 0] >= inside.x0) & (xy[:, 0] <= inside.x1) & (xy[:, 1] >= inside.y0) & (xy[:, 1] <= inside.y1)
    assert covered.any()  # (the case can fail: the legend starts on the twin's curve)
    legends_off_data(fig)
    fig.draw_without_rendering()
    box = ax.get_legend().get_window_extent()
    xy = twin.transData.transform(line.get_xydata())
    assert not np.any((xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1))
    assert box.y0 >= ax.get_window_extent().y1 - 0.5  # (above the frame)
    plt.close(fig)

    fig, ax, _ = figure(False)
    fig.draw_without_rendering()
    before = ax.get_legend().get_window_extent().bounds
    legends_off_data(fig)
    fig.draw_without_rendering()
    assert np.allclose(ax.get_legend().get_window_extent().bounds, before)  # (nothing under it: it stays)
    plt.close(fig)
