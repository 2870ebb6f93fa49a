"""Z-HIT names the points with Re Z < 0, as the linear test does (its note and JSON
``non_passive_hz``): on REAL PowerSuite its rms_rel is 119 %, nearly all from the two top points
(1.12 MHz, 2 MHz) whose real part is negative (phase beyond −90°), and it said nothing of them.
Oracle: the file's own Z, Re Z against 5 % of |Z| (numpy)."""

import json
from pathlib import Path

import numpy as np

import impedax as ix
from impedax.cli import main
from impedax.data import format_frequency

REAL = Path(__file__).parent / "fixtures" / "real"


def test_zhit_notes_the_points_no_passive_circuit_reaches(capsys):
    path = REAL / "exampleDataPowersuite.txt"
    data = ix.load(path)
    f, z = data["frequency"].values, data["Z"].values
    negative = np.sort(f[z.real < -0.05 * np.abs(z)])
    assert negative.tolist() == [1120134.9, 2e6]
    result = ix.zhit(data)
    (note,) = [line for line in result.report().splitlines() if line.startswith("note:")]
    assert "Re Z < 0" in note and all(format_frequency(x) in note for x in negative), note
    assert main(["kk", str(path), "--method", "zhit", "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["non_passive_hz"] == negative.tolist()
    assert any("Re Z < 0" in w for w in payload["warnings"])


def test_a_passive_spectrum_gets_no_such_note():
    result = ix.zhit(ix.load(REAL / "exampleDataGamry.DTA"))
    assert result.non_passive_frequencies.size == 0 and not any("Re Z < 0" in n for n in result.notes)
