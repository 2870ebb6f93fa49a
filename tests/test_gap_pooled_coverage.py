"""Coverage of the pooled gap analysis (`gap_analysis(method="pooled")`, ``impedax gap --pooled``):
over fresh SYNTHETIC Sirin-style sets written from formulas (`spectra.sirin_measurements`: skin
and screen R_inf + R ∥ CPE, remainder R_EP ∥ CPE_EP ∥ C_gap, 0.5 % complex noise per point, 8
trials, no scatter between trials, so the pooled model, one remainder with the trial means' SEM,
is the true one), the 90 % interval of u holds the generating u = ε0 ε_air A / C_gap in most sets.

Bound: with n = 10 sets and a true coverage of 0.90, P(k ≤ 6) = 1.3 %, so k ≥ 7 is required
(loose: it passes a coverage down to about 0.75 half the time, and fails only an interval that
misses far more often than it should). A miss may not be far: none by more than 1 % of u, ten
times the interval's half-width (≈ 0.09 % here). Measured (2026-12-07, seeds 1000–1009, steps
2000; the same sets with the automatic chain length, 3250–6000 steps, alike): 8 of 10 covered, the
two misses 0.014 % and 0.036 % of u above the interval's upper end. The identification rule
(`gap_identified`) is not asserted here (tests/test_gap_ep_supported_by_aic.py tests it on seed
1002; docs/models.md, "A single contact" and "The force when u is not determined")."""

import numpy as np
import pytest

import impedax as ix
from impedax.models.gap import gap_analysis
from spectra import sirin_measurements

EPS0 = 8.8541878128e-12  # vacuum permittivity [F/m], CODATA 2018
EPS_AIR = 1.00059  # air's relative permittivity (Sirin et al.)
AREA = 130e-6  # [m²]
C_GAP = 413e-12  # the generating C_gap [F], `sirin_measurements`' default
U_TRUE = EPS0 * EPS_AIR * AREA / C_GAP  # 2.789 µm
SEEDS = range(1000, 1010)


@pytest.mark.slow
def test_pooled_gap_interval_covers_the_generating_gap_in_most_sets():
    covered, misses = [], []
    for seed in SEEDS:
        f, *spectra = sirin_measurements(np.random.default_rng(seed), 8, noise=0.005)
        total, skin, ts = (ix.make_spectrum(f, z, dims=("trial",)) for z in spectra)
        g = gap_analysis(total, skin, ts, area=AREA, method="pooled", steps=2000, seed=seed - 1000, progress=False).gap
        inside = g["q05"] <= U_TRUE <= g["q95"]
        covered.append(inside)
        if not inside:
            misses.append(min(abs(U_TRUE - g["q05"]), abs(U_TRUE - g["q95"])) / U_TRUE)
    assert sum(covered) >= 7, (covered, misses)
    assert all(m < 0.01 for m in misses), misses
