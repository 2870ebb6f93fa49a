"""The rms_rel panel of the batch DRT figure has two labelled ticks or more in view, whatever
its range, and their labels do not overlap. matplotlib's log ticks (thinned to fit the short
panel) labelled one value alone on SYNTHETIC spectra of small rms_rel: a panel from 0.068 to
0.195 % read "0.1" and nothing else, one from 0.042 to 0.094 % "0.06", one from 0.60 to 1.74 %
"1" (measured on this figure, 2026-12-07). Oracles: the tick labels as drawn (text, position in
view, window extent), and the value each label names read back as a number against its tick."""

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from impedax.fitting.drt import drt  # noqa: E402

F = np.geomspace(0.01, 1e5, 41)
W = 2 * np.pi * F


@pytest.fixture(scope="module")
def figure():
    z = 10 + 1000 / (1 + (1j * W * 1e-2) ** 0.8)
    rng = np.random.default_rng(0)
    spectra = np.stack([z * (1 + 0.0008 * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2)) for _ in range(4)])
    fig = drt((F, spectra)).plot()
    yield fig
    plt.close(fig)


def _labels(ax):
    fig = ax.get_figure()
    fig.canvas.draw()
    lo, hi = ax.get_ylim()
    ticks = [t for t in ax.yaxis.get_major_ticks() + ax.yaxis.get_minor_ticks() if lo * (1 - 1e-9) <= t.get_loc() <= hi * (1 + 1e-9)]
    return [(t.get_loc(), t.label1) for t in ticks if t.label1.get_visible() and t.label1.get_text()]


@pytest.mark.parametrize(
    "limits",
    [(0.0677, 0.195), (0.0424, 0.0943), (0.0076, 0.0131), (0.602, 1.74), (6.26, 18.1), (0.131, 0.135), (0.011, 0.19), (1e-4, 100.0), (1e-9, 1e6)],
)
def test_the_rms_panel_has_two_readable_labels_at_any_range(figure, limits):
    ax = figure.axes[1]
    assert ax.get_ylabel() == "DRT fit rms_rel [%]"
    ax.set_ylim(*limits)
    labels = _labels(ax)
    assert len(labels) >= 2, (limits, [text.get_text() for _, text in labels])
    for loc, text in labels:  # each label names its tick's value, to its 3 significant digits
        assert float(text.get_text()) == pytest.approx(loc, rel=5e-3), (loc, text.get_text())
    renderer = figure.canvas.get_renderer()
    boxes = [text.get_window_extent(renderer) for _, text in labels]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :]), (limits, [text.get_text() for _, text in labels])


def test_the_panel_as_drawn_has_two_labels(figure):
    """The figure's own range (the points' rms_rel, about 0.05–0.1 %), as `plot` framed it."""
    assert len(_labels(figure.axes[1])) >= 2
