"""A further path kept with a higher AIC says which rule kept it (a walkthrough, 2026-12-05: on
the REAL Gamry file above 2.5 kHz, "the fourth path is kept in place of the third path's end"
named AIC −441.0 against −448.7 and no reason). Oracle: the two AICs and parameter counts read
off the note itself, and the rule (within ΔAIC 10, fewer parameters) applied by hand."""

from __future__ import annotations

import re
from pathlib import Path

import impedax as ix

REAL = Path(__file__).parent / "fixtures" / "real"


def test_a_path_kept_for_fewer_parameters_names_the_rule():
    data = ix.load(REAL / "exampleDataGamry.DTA")
    result = ix.refine(data, "R0 + R1 || C1", fmin=2.5e3, progress=False)
    kept = [n for n in result.notes if " is kept in place of " in n]
    assert kept
    for note in kept:
        (kept_aic, kept_size), (other_aic, other_size) = [(float(a), int(k)) for a, k in re.findall(r"\(AIC (-?[\d.]+), (\d+) parameters", note)[:2]]
        counted = [int(x) for x in re.findall(r"(\d+) counting", note)]  # (a vanished resistor counts as kept)
        if kept_aic > other_aic:  # by hand: kept for parsimony, within ΔAIC 10 and with fewer parameters
            assert kept_aic - other_aic <= 10
            assert (counted[0] if counted else kept_size) < other_size
            assert f"Its AIC is {kept_aic - other_aic:.1f} higher, within 10" in note and "the simpler is kept" in note
        else:
            assert "the simpler is kept" not in note
