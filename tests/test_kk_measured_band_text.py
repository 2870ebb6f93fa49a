"""`impedax kk` names a bad band by its flagged measured points, as `diagnose` and `refine` do:
on REAL Gamry it wrote "bad band: 15.9 mHz – 2.26 kHz" (the edge halfway to 2.53 kHz) where the
last flagged point is 2.02 kHz, and on REAL test_data.txt "1 mHz – 676 mHz" (last flagged point
585 mHz). The JSON's ``bad_bands_hz`` keep the halfway edges (the contract, and what the figure
shades); ``measured_bands_hz`` (added) gives the flagged points' range. Oracles: the file's
measured frequencies, the band edges read from the JSON."""

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

REAL = Path(__file__).parent / "fixtures" / "real"


@pytest.mark.parametrize("name, measured, halfway", [
    ("exampleDataGamry.DTA", "15.9 mHz – 2.02 kHz", "2.26 kHz"),
    ("test_data.txt", "1 mHz – 585 mHz", "676 mHz"),
])
def test_kk_text_names_the_flagged_points_range(name, measured, halfway, capsys):
    assert main(["kk", str(REAL / name)]) == 0
    out = capsys.readouterr().out
    band_line = next(line for line in out.splitlines() if line.startswith("  bad band:"))
    assert band_line.startswith(f"  bad band: {measured}:"), band_line
    assert halfway not in out
    assert main(["kk", str(REAL / name), "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    f = np.sort(ix.load(REAL / name).frequency)
    (lo, hi), = payload["bad_bands_hz"]
    assert hi not in f  # (the contract's edge still lies halfway to the next point)
    inside = f[(f >= lo) & (f <= hi)]
    flagged = payload["bad_band_frequencies_hz"][0]
    assert payload["measured_bands_hz"] == [[min(flagged), max(flagged)]]
    assert inside[0] == min(flagged)  # (both files' bands: flagged from their first to their last point)
    assert inside[-1] == max(flagged)


def test_kk_html_names_the_measured_range():
    kk = ix.kk_test(ix.load(REAL / "exampleDataGamry.DTA"))
    assert "15.9 mHz – 2.02 kHz" in kk._repr_html_() and "2.26 kHz" not in kk._repr_html_()
