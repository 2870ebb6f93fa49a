"""Log axes of values a reader reads off a figure label ticks between the decades when the axis
spans about two decades or less. REAL VersaStudio refined from R0 + R1 || C1 (2026-12-07
walkthrough): the error panel's steps at 20.5, 3.59, 1.72 and 0.54 % and their noise marks near
0.3 % stood against the labels 1 and 10 alone. Oracle: the tick labels matplotlib draws
(`labels_in_view`) on an Agg canvas, read back as numbers; the spectra are SYNTHETIC."""

from __future__ import annotations

from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.plotting.diagnosis import plot_refinement  # noqa: E402
from test_refinement_figure_steps_shown import fit  # noqa: E402,F401  (the fixture: a SYNTHETIC R0 + R1 ∥ C1 fit)
from tick_labels import labels_in_view  # noqa: E402


class _FitAt:
    """``fit`` as it would read with an rms_rel of ``rms_rel`` (a refinement step's stand-in)."""

    def __init__(self, fit, rms_rel):
        self._fit, self.rms_rel = fit, rms_rel

    def __getattr__(self, name):
        return getattr(self._fit, name)


def _values(axis, renderer) -> list[float]:
    return sorted(float(text.replace("−", "-")) for text, _ in labels_in_view(axis, renderer))


def test_the_refinement_error_panel_labels_values_between_its_decades(fit):
    """Four steps at VersaStudio's rms_rel (20.5, 3.59, 1.72, 0.54 %): the error panel's labels
    are never a decade apart and one lies at or below the lowest step."""
    rms = (0.205, 0.0359, 0.0172, 0.0054)
    steps = [SimpleNamespace(fit=_FitAt(fit, r), effect=None if i == 0 else "extra_relaxation", removed=(), added=None,
                             change="(start)" if i == 0 else "+ R_relax || CPE_relax", model=fit.model, diagnosis=None) for i, r in enumerate(rms)]
    fig = plot_refinement(SimpleNamespace(steps=steps, final_model=fit.model, verdict="adequate", masked_points=()))
    try:
        fig.canvas.draw()
        ax = next(a for a in fig.axes if a.get_ylabel() == "rms_rel [%]")
        values = _values(ax.yaxis, fig.canvas.get_renderer())
        assert len(values) >= 4, values
        assert max(b / a for a, b in zip(values, values[1:])) < 10, values
        assert values[0] <= 100 * min(rms) and values[-1] >= 10, values
    finally:
        plt.close(fig)


def test_a_batch_parameter_panel_on_a_log_axis_labels_values_between_its_decades():
    """SYNTHETIC batch of R0 + R1 ∥ C1 with R1 from 30 Ω to 1.2 kΩ (40×: its panel goes log):
    the R1 panel's labels are never a decade apart (they were 100 and 1000 alone)."""
    f = np.geomspace(1.0, 1e5, 25)
    r1 = np.array([30.0, 90.0, 400.0, 1200.0])
    z = 10.0 + r1[:, None] / (1 + 2j * np.pi * f * r1[:, None] * 1e-6)
    batch = ix.fit("R0 + R1 || C1", ix.make_spectrum(f, z * (1 + 0.002 * np.random.default_rng(8).standard_normal(z.shape)), dims=("cell",)), progress=False)
    fig = batch.plot()
    try:
        fig.canvas.draw()
        ax = next(a for a in fig.axes if a.get_title().startswith("R1 "))
        assert ax.get_yscale() == "log"
        values = _values(ax.yaxis, fig.canvas.get_renderer())
        assert len(values) >= 3 and max(b / a for a, b in zip(values, values[1:])) < 10, values
    finally:
        plt.close(fig)
