"""The frequency axes of the gap analysis' figures (`GapAnalysis.plot`: the |Z_R| and force
panels; the demo's force figure, `plot_force_bands`) read plain numbers, 1, 10, 100, 1000, 10k,
100k, 1M, as their |Z_R| and force axes and the batch maps' frequency axes do
(`plotting.plain_log_ticks`); they read 10⁰ … 10⁶ beside a |Z_R| axis of 1000, 10k
(examples/sirin_gap_and_force.py, docs/gallery). Oracle: the tick labels as drawn on an Agg
canvas (text, window extent), each read back as a number (SI prefixes by their powers of ten)
against its tick's position; the spectra and bands are SYNTHETIC (numpy)."""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from impedax.plotting.models import plot_force_bands  # noqa: E402
from test_gap_outputs import _stub  # noqa: E402  (a GapAnalysis built by hand: no fit, no sampling)

PREFIX_POWERS = {"n": -9, "µ": -6, "m": -3, "k": 3, "M": 6, "G": 9}


def _number(text: str) -> float:
    text = text.replace("\N{MINUS SIGN}", "-")
    return float(text[:-1]) * 10.0 ** PREFIX_POWERS[text[-1]] if text[-1] in PREFIX_POWERS else float(text)


def _frequency_labels(fig, ax):
    """(tick position, text, box) of the visible frequency tick labels of ``ax`` in view."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    lo, hi = sorted(ax.get_xlim())
    ticks = [t for t in ax.xaxis.get_major_ticks() + ax.xaxis.get_minor_ticks() if lo * (1 - 1e-9) <= t.get_loc() <= hi * (1 + 1e-9)]
    return [(t.get_loc(), t.label1.get_text(), t.label1.get_window_extent(renderer)) for t in ticks if t.label1.get_visible() and t.label1.get_text()]


def _bands(freq):
    """Force bands [N] over ``freq``: 0.3 N falling to 0.04 N, ±7 %; without EP 0.8 × with."""
    import xarray as xr

    step = 1.0 / (1.0 + np.exp(2.0 * (np.log10(freq) - np.log10(np.sqrt(freq[0] * freq[-1])))))
    force = 0.04 * (0.3 / 0.04) ** step
    data = {key: (("branch", "frequency"), np.stack([force * s, 0.8 * force * s])) for key, s in (("median", 1.0), ("q05", 0.93), ("q95", 1.07))}
    return xr.Dataset(data, coords={"branch": ["with_ep", "without_ep"], "frequency": freq})


def _figures():
    gap = _stub(rhat_max=1.001)
    gap_fig = gap.plot()
    wide = plot_force_bands(SimpleNamespace(force=_bands(np.geomspace(1.0, 1e6, 61)), v0=75.0))
    short = plot_force_bands(SimpleNamespace(force=_bands(np.geomspace(200.0, 3e3, 21)), v0=75.0))  # (a band of about a decade)
    return {"gap |Z_R|": (gap_fig, gap_fig.axes[0]), "gap force": (gap_fig, gap_fig.axes[2]), "force figure": (wide, wide.axes[0]), "force figure, short band": (short, short.axes[0])}


@pytest.fixture(scope="module")
def figures():
    drawn = _figures()
    yield drawn
    for fig in {id(f): f for f, _ in drawn.values()}.values():
        plt.close(fig)


@pytest.mark.parametrize("panel", ["gap |Z_R|", "gap force", "force figure", "force figure, short band"])
def test_frequency_ticks_read_as_plain_numbers_of_their_values(figures, panel):
    fig, ax = figures[panel]
    assert ax.get_xscale() == "log" and ax.get_xlabel() == "frequency [Hz]", panel
    labels = _frequency_labels(fig, ax)
    texts = [text for _, text, _ in labels]
    assert len(labels) >= 2, (panel, texts)
    for loc, text, _ in labels:
        assert "$" not in text and "^" not in text, (panel, texts)  # (no mathtext 10ⁿ)
        assert _number(text) == pytest.approx(loc, rel=1e-6), (panel, loc, text)
    boxes = [box for _, _, box in labels]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :]), (panel, texts)


def test_the_decades_of_1_hz_to_1_mhz_read_1_to_1m(figures):
    """The demo's band, 1 Hz–1 MHz: each decade labelled as the batch maps write it."""
    fig, ax = figures["force figure"]
    assert [text for _, text, _ in sorted(_frequency_labels(fig, ax), key=lambda label: label[0])] == ["1", "10", "100", "1000", "10k", "100k", "1M"]
