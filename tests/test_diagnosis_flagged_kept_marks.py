"""The diagnosis and refinement figures ring the points the KK test flags and the fits kept, the
points the report names: on the REAL exampleDataBioLogic.mpt (impedance.py, MIT) diagnosed with
R0 + R1 || C1 the report says "the KK test flags 4 points inside the band (5.34 Hz, 56.2 Hz,
123 Hz, 270 Hz): kept in every fit", and the figures shaded 49–83 Hz alone (the one failing band
the flags fall in). Oracle: the frequencies written in the report's own sentence. Also: the
refinement figure's step labels end inside their panel (measured on the drawn figure)."""

from __future__ import annotations

import re

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax as ix  # noqa: E402

BIOLOGIC = "tests/fixtures/real/exampleDataBioLogic.mpt"
FREQUENCY_UNITS = {"Hz": 1.0, "kHz": 1e3, "MHz": 1e6, "mHz": 1e-3}


def named_in_report(sentence: str) -> list[float]:
    """The frequencies [Hz] in "flags 4 points inside the band (5.34 Hz, 56.2 Hz, …)"."""
    inside = re.search(r"flags \d+ points? inside the band \(([^)]*)\)", sentence).group(1)
    return sorted(float(v) * FREQUENCY_UNITS[u] for v, u in re.findall(r"([\d.]+) (\w*Hz)", inside))


def ringed(fig) -> list[np.ndarray]:
    """The x data of each ringed-residual line (its legend name, or its twin's) of ``fig``."""
    return [np.sort(np.asarray(line.get_xdata(), float)) for ax in fig.axes for line in ax.get_lines()
            if line.get_label().startswith("KK-flagged, kept in the fit")]


@pytest.mark.slow
def test_the_diagnosis_figure_rings_the_flagged_points_the_report_names():
    diagnosis = ix.diagnose(ix.load(BIOLOGIC), "R0 + R1 || C1")
    named = named_in_report(diagnosis.kk_flagged_kept)
    assert len(named) == 4
    fig = diagnosis.plot()
    try:
        lines = ringed(fig)
        assert len(lines) == 1
        assert lines[0] == pytest.approx(named, rel=0.01)  # (the report rounds to 3 digits)
    finally:
        plt.close(fig)


@pytest.mark.slow
def test_the_refinement_figure_rings_them_on_every_step_shown():
    refinement = ix.refine(ix.load(BIOLOGIC), "R0 + R1 || C1")
    named = named_in_report(refinement.steps[0].diagnosis.kk_flagged_kept)
    fig = refinement.plot()
    try:
        lines = ringed(fig)
        assert len(lines) == 1  # named once, in the first row's legend
        assert lines[0] == pytest.approx(named, rel=0.01)
        # every row's residual panel rings them (the named line and its unnamed twins)
        rows = [ax for ax in fig.axes if ax.get_ylabel() == "(Z_model − Z)/|Z| [%]"]
        assert len(rows) == len(refinement.steps)
        for ax in rows:
            rings = [np.sort(np.asarray(line.get_xdata(), float)) for line in ax.get_lines() if line.get_marker() == "o" and line.get_markerfacecolor() == "none"]
            assert rings and all(r == pytest.approx(named, rel=0.01) for r in rings)
    finally:
        plt.close(fig)


@pytest.mark.slow
def test_every_step_label_of_the_refinement_figure_ends_inside_its_panel():
    # REAL exampleData.csv (impedance.py, MIT) refined from R0 + R1 || C1 takes 7 steps, the last
    # "simplified / CPE1 → C1", whose label stands right of its point and ran 37 points past the
    # error panel's frame, over the residual panel's "res. [%]"
    refinement = ix.refine(ix.load("tests/fixtures/real/exampleData.csv"), "R0 + R1 || C1")
    assert len(refinement.steps) >= 6
    fig = refinement.plot()
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        panel = fig.axes[0]  # the error per step
        assert panel.get_xlabel() == "refinement step"
        frame = panel.get_window_extent(renderer)
        ends = [t.get_window_extent(renderer).x1 - frame.x1 for t in panel.texts]
        assert len(ends) == len(refinement.steps) and max(ends) <= 1.0  # (points; a pixel of slack)
    finally:
        plt.close(fig)
