"""Every log axis of values read off impedax's figures (the rms_rel panels of the refinement, the
batch fit's residual map, the KK and DRT batch figures; a batch's parameter panels; the
comparison figure's |relative residual| panel) has two
labelled ticks or more in view at any range, labels that do not overlap, and each label reads
back as its tick's value (`plotting.labelled_log_ticks`). matplotlib's log ticks labelled one
value alone on short ranges (0.068–0.195 % read "0.1") and the decades alone over three or more
(a refinement's step at 0.426 % stood against 1, 10 and 100). Oracles: the tick labels as drawn
on an Agg canvas (text, position in view, window extent), each text read back as a number (SI
prefixes by their powers of ten); every spectrum is SYNTHETIC."""

from __future__ import annotations

import math
from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.plotting.diagnosis import plot_refinement  # noqa: E402
from test_figure_log_axes_labelled import _FitAt  # noqa: E402
from test_refinement_figure_steps_shown import fit  # noqa: E402,F401  (the fixture: a SYNTHETIC R0 + R1 ∥ C1 fit)

F = np.geomspace(1.0, 1e5, 25)
PREFIX_POWERS = {"f": -15, "p": -12, "n": -9, "µ": -6, "m": -3, "k": 3, "M": 6, "G": 9, "T": 12}
RANGES = [(0.0677, 0.195), (0.0424, 0.0943), (0.0076, 0.0131), (0.602, 1.74), (6.26, 18.1), (0.131, 0.135), (0.011, 0.19), (0.3, 30.0), (0.1, 200.0), (1e-4, 100.0), (1e-9, 1e6)]


def _number(text: str) -> float:
    """A tick label as the number it names: ``0.2``, ``1e-9``, ``500µ``, ``20k``."""
    text = text.replace("−", "-")
    return float(text[:-1]) * 10.0 ** PREFIX_POWERS[text[-1]] if text[-1] in PREFIX_POWERS else float(text)


def _synthetic_batch():
    r1 = np.array([30.0, 90.0, 400.0, 1200.0])
    z = 10.0 + r1[:, None] / (1 + 2j * np.pi * F * r1[:, None] * 1e-6)
    return ix.make_spectrum(F, z * (1 + np.array([0.0005, 0.002, 0.01, 0.04])[:, None] * np.random.default_rng(8).standard_normal(z.shape)), dims=("cell",))


def _synthetic_comparison():
    """Two models compared on the batch's third spectrum (1 % noise): the comparison figure's
    |relative residual| panel (matplotlib's log ticks read 0.068–0.195 % as "0.1" alone)."""
    data = _synthetic_batch().isel(cell=2)
    return ix.compare([ix.fit(model, data, progress=False) for model in ("R0 + R1 || C1", "R0 + R1 || CPE1")])


@pytest.fixture(scope="module")
def batch_fit():
    return ix.fit("R0 + R1 || C1", _synthetic_batch(), progress=False)


@pytest.fixture(scope="module")
def panels(fit, batch_fit):  # noqa: F811
    """(figure, the log axes) of each panel kind."""
    rms = (0.205, 0.0359, 0.0172, 0.0054)
    steps = [SimpleNamespace(fit=_FitAt(fit, r), effect=None if i == 0 else "extra_relaxation", removed=(), added=None,
                             change="(start)" if i == 0 else "+ R_relax || CPE_relax", model=fit.model, diagnosis=None) for i, r in enumerate(rms)]
    refinement = plot_refinement(SimpleNamespace(steps=steps, final_model=fit.model, verdict="adequate", masked_points=()))
    spectra = _synthetic_batch()
    figures = {
        "refinement rms_rel": (refinement, lambda fig: next(a for a in fig.axes if a.get_ylabel() == "rms_rel [%]")),
        "batch parameter R1": (batch_fit.plot(), lambda fig: next(a for a in fig.axes if a.get_title().startswith("R1 "))),
        "residual map rms_rel": (batch_fit.plot_residual_map(), lambda fig: fig.axes[2]),
        "KK batch rms_rel": (ix.kk_test_batch(spectra).plot(), lambda fig: next(a for a in fig.axes if a.get_ylabel() == "rms_rel, noise [%]")),
        "DRT batch rms_rel": (ix.drt(spectra).plot(), lambda fig: next(a for a in fig.axes if a.get_ylabel() == "DRT fit rms_rel [%]")),
        "comparison |residual|": (_synthetic_comparison().plot(), lambda fig: next(a for a in fig.axes if a.get_ylabel() == "|relative residual| [%]")),
    }
    yield {kind: (fig, pick(fig)) for kind, (fig, pick) in figures.items()}
    for fig, _ in figures.values():
        plt.close(fig)


def _labels(ax):
    fig = ax.get_figure()
    fig.canvas.draw()
    lo, hi = sorted(ax.get_ylim())
    ticks = [t for t in ax.yaxis.get_major_ticks() + ax.yaxis.get_minor_ticks() if lo * (1 - 1e-9) <= t.get_loc() <= hi * (1 + 1e-9)]
    return [(t.get_loc(), t.label1) for t in ticks if t.label1.get_visible() and t.label1.get_text()]


KINDS = ["refinement rms_rel", "batch parameter R1", "residual map rms_rel", "KK batch rms_rel", "comparison |residual|", "DRT batch rms_rel"]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("limits", RANGES)
def test_each_log_panel_has_two_readable_labels_at_any_range(panels, kind, limits):
    fig, ax = panels[kind]
    assert ax.get_yscale() == "log", kind  # (the spectra's noise, 0.05 % to 4 %, spreads each rms_rel over 20×)
    ax.set_ylim(*limits)
    labels = _labels(ax)
    texts = [text.get_text() for _, text in labels]
    assert len(labels) >= 2, (kind, limits, texts)
    for loc, text in labels:  # each label names its tick's value
        assert _number(text.get_text()) == pytest.approx(loc, rel=5e-3), (kind, loc, text.get_text())
    renderer = fig.canvas.get_renderer()
    boxes = [text.get_window_extent(renderer) for _, text in labels]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :]), (kind, limits, texts)


@pytest.mark.parametrize("kind", KINDS[:-1])  # (the DRT batch figure's rms panel is too short for labels half a decade apart over three decades)
def test_a_range_over_three_decades_labels_between_the_decades(panels, kind):
    """0.3–300 on these panels: a label between each two neighbouring decades (1, 2, 3, 4, 6, 1, 2, 5
    or 1, 3 × 10ⁿ, as the panel's height holds), where matplotlib read 1, 10 and 100 alone."""
    fig, ax = panels[kind]
    ax.set_ylim(0.3, 300.0)
    values = sorted(_number(text.get_text()) for _, text in _labels(ax))
    assert max(b / a for a, b in zip(values, values[1:])) < 10 - 1e-9, (kind, values)
