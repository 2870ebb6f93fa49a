"""`impedax gap`'s text report gave the force maximum as a bare median ("with EP: max 352 mN at
31.6 Hz") while the gap, C_gap and the gap voltage each had their 90 % interval beside them; the
force's band was only in the CSV and JSON (the demo files with --steps 40, 2026-12-07). The
report has a line with the 90 % band of the PEAK force at each maximum. Results are hand-built
(`test_gap_outputs._stub`): SYNTHETIC bands from numpy, eq 1 with a bell-shaped gap voltage."""

from __future__ import annotations

import numpy as np

from test_gap_outputs import _force_bands, _stub


def _band_at_max(branch):
    """The oracle: the band of the largest median, from the bands' own arrays (numpy argmax)."""
    bands = _force_bands().sel(branch=branch)
    i = int(np.argmax(bands["median"].values))
    return float(bands["q05"].values[i]), float(bands["q95"].values[i]), float(bands["frequency"].values[i])


def test_the_report_gives_the_force_s_90_percent_band_at_each_maximum():
    lines = _stub(rhat_max=1.01, warnings=()).report().splitlines()
    force = next(k for k, line in enumerate(lines) if line.startswith("force (peak"))
    interval = lines[force + 1]
    lo, hi, f = _band_at_max("with_ep")
    lo2, hi2, f2 = _band_at_max("without_ep")
    # FREQ's 1 kHz is the bell's top: median ½ ε0 ε A V0²/u² = ½ · 8.859e-12 · 2e-4 · 500² / (5e-6)²
    # = 8.859 N, × 0.93 and × 1.08 (with EP), × 0.8 of those without EP
    assert (round(lo, 2), round(hi, 2), f, f2) == (8.24, 9.57, 1000.0, 1000.0)
    assert (round(lo2, 2), round(hi2, 2)) == (6.59, 7.65)
    assert interval == (f"force 90 %      credible band of the peak force at each maximum: with EP {lo:.3g}–{hi:.3g} N at 1 kHz; "
                        f"without EP {lo2:.3g}–{hi2:.3g} N at 1 kHz"), interval


def test_a_force_of_an_undetermined_gap_is_no_credible_band():
    """u not determined (a lower bound only): the draws' band is no estimate, and the line says so."""
    from dataclasses import replace

    lines = replace(_stub(rhat_max=1.01, warnings=()), gap_lower_bound=4e-6).report().splitlines()
    (line,) = [x for x in lines if x.startswith("force 90 %")]
    assert line.startswith("force 90 %      interval of the draws' peak force (no estimate: see the force line) at each maximum: with EP ")
    assert "credible" not in line
