"""The gap report's C_gap line says how the paper's method read its C_gap: the mean of
|Y_R|/ω over the frequencies at and above the cutoff (Sirin §2.3, 30 Hz by default), an
assumption the number rests on that the report did not name. The analysis is built by hand
(as tests/test_gap_sampling_verdict_shared.py), its paper estimate from numpy spectra; the
oracle is the mean written here in numpy."""

import numpy as np

import impedax as ix
from impedax.data import format_quantity
from test_gap_sampling_verdict_shared import _analysis, _posterior


def test_the_c_gap_line_names_the_paper_s_cutoff():
    analysis = _analysis(_posterior(alpha_apart=0.0))
    f = analysis.remaining["frequency"].values
    z = analysis.remaining["Z"].values
    keep = f >= 30.0
    c_paper = np.mean(1.0 / (2 * np.pi * f[keep] * np.abs(z[keep])))
    (line,) = [ln for ln in analysis.report().splitlines() if ln.startswith("C_gap")]
    assert line.endswith(f"paper method {format_quantity(c_paper, 'F', 4)} (mean |Y_R|/ω at and above 30 Hz, Sirin §2.3)"), line
