"""refine's verdict quotes the ranking's ΔAIC (over the residuals divided by the noise), its table
each fit's own AIC under the run's weighting: the report now says which is which and gives the
same candidate's ΔAIC between the fits' own AICs (REAL Autolab under --weighting proportional
said "lowers AIC by 36.6" where the table's AICs of that step differ by about 10)."""

import re

import numpy as np
import pytest

import impedax as ix


@pytest.mark.slow  # (~13 s: a diagnosis with its candidate fits)
def test_the_verdicts_delta_aic_is_named_beside_the_fits_own():
    """SYNTHETIC two arcs (numpy formula: 10 Ω + 100 Ω ∥ 1 µF + 200 Ω ∥ 250 µF, 0.3 % noise,
    seed 5) refined from R0 + R1 ∥ C1 under proportional weighting with no effect added: the
    verdict names a missing effect; the line under it gives the verdict's own figure and the
    fits' own ΔAIC, n ln(χ²/n) + 2k of the two fits by numpy (n = 2N), from the table's AIC."""
    f = np.geomspace(0.1, 1e5, 40)
    rng = np.random.default_rng(5)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6) + 200 / (1 + 2j * np.pi * f * 200 * 2.5e-4)
    z = z * (1 + 0.003 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2))
    refinement = ix.refine(ix.make_spectrum(f, z), "R0 + R1 || C1", max_effects=0, weighting="proportional", progress=False)
    report = refinement.report()
    lines = report.splitlines()
    verdict = next(i for i, line in enumerate(lines) if line.startswith("verdict: MISSING_EFFECT"))
    quoted = float(re.search(r"lowers AIC by (\d+(?:\.\d+)?)", lines[verdict]).group(1))
    note = lines[verdict + 1]
    said = re.search(r"that ΔAIC, (-[\d.]+), is the ranking's.*under proportional weighting, as in the table, adding (\w+) is ΔAIC (-[\d.]+): (-[\d.]+) → (-[\d.]+)\)", note)
    assert said, note
    assert float(said.group(1)) == -quoted
    diagnosis = refinement.steps[-1].diagnosis
    best, baseline = diagnosis.best, diagnosis.baseline
    n = 2 * f.size

    def aic(fit):  # (the unknown-variance form, n ln(χ²/n) + 2k)
        return n * np.log(fit.chi2 / n) + 2 * fit.n_params

    assert said.group(2) == best.effect
    assert float(said.group(3)) == pytest.approx(aic(best.fit) - aic(baseline), abs=0.06)
    table_aic = float(lines[2].split()[3])  # (step 0's row: the table's AIC, after rms_rel and its %)
    assert float(said.group(4)) == pytest.approx(table_aic, abs=0.051)
    assert abs(float(said.group(3))) < quoted  # (here too the two differ: proportional weights are not the noise's)
    assert refinement.summary()["verdict_aic_note"] == note
