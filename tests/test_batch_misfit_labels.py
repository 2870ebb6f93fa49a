"""A batch's hint of fits that miss structure, small as their misfits look, names every such
spectrum (`misfit_hints()["labels"]` and the note), not only how many and the worst: on the
REAL 130 battery cycles 49 were counted and one named."""

import numpy as np
import pytest
from test_batch_misses_structure import two_arcs_and_one

import impedax as ix


@pytest.mark.slow  # (~11 s: a batch fit of 4 spectra and their KK chains)
def test_the_hint_names_each_spectrum_it_counts():
    """SYNTHETIC: four noisy copies (0.05 %) of R0 + R1 ∥ C1 (numpy formula), trials 0 and 2
    with a second arc of 50 Ω at 11 Hz, fitted with R0 + R1 ∥ C1: the oracle is the hint's rule
    with `ix.kk_test`'s chain, rms_rel below 2 % and over 5× the chain's."""
    data = two_arcs_and_one()
    fits = ix.fit("R0 + R1 || C1", data, progress=False)
    rms = fits.dataset["rms_rel"].values
    chain = np.array([ix.kk_test(data.isel(trial=k)).rms_rel for k in range(4)])
    expected = [{"trial": k} for k in range(4) if 0.002 <= rms[k] < 0.02 and rms[k] > 5 * chain[k]]
    assert expected == [{"trial": 0}, {"trial": 2}]
    hints = fits.misfit_hints()
    assert hints["spectra"] == 2 and hints["labels"] == expected
    assert hints["note"].startswith("2 of the 4 fits (trial 0, 2) miss structure")
    assert f"hint: {hints['note']}" in fits.report()
    # a comparison over the stack names the same spectra, where its winner (R0 + R1 ∥ C1 on every
    # trial: R0 + C1 has no arc) misses the second arc
    comparison = ix.compare([fits, ix.fit("R0 + C1", data, progress=False)])
    best = comparison.best_misfit_hints()
    assert best["labels"] == expected and "on 2 of 4 spectra (trial 0, 2)" in best["note"]
    # one such fit is named once, in the singular (was "1 of the 2 fits ... their misfits ...; the worst, trial=0")
    pair = ix.fit("R0 + R1 || C1", data.isel(trial=[0, 1]), progress=False).misfit_hints()
    assert pair["labels"] == [{"trial": 0}]
    assert pair["note"].startswith("the fit of trial=0 (1 of the 2) misses structure the data hold, small as its misfit looks (")
