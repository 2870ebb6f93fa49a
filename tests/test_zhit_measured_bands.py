"""``impedax kk --method zhit`` names a bad band by its flagged measured points, as the linear
test does (docs/kk.md): on REAL Gamry it read "bad band: 15.9 mHz – 449 mHz", 449 mHz lying
halfway between two measured frequencies. Oracles: the file's measured frequencies and the
points Z-HIT flags, read back from the text and the JSON."""

import json
import re
from pathlib import Path

import numpy as np

import impedax as ix
from impedax.cli import main
from impedax.data import format_frequency

REAL = Path(__file__).parent / "fixtures" / "real"
PREFIX = {"M": 1e6, "k": 1e3, "": 1.0, "m": 1e-3, "µ": 1e-6}


def _named(line: str) -> list[float]:
    return [float(v) * PREFIX[p or ""] for v, p in re.findall(r"(\d+(?:\.\d+)?) (M|k|m|µ)?Hz", line)]


def test_zhit_names_each_bad_band_by_its_flagged_measured_points(capsys):
    path = REAL / "exampleDataGamry.DTA"
    result = ix.zhit(ix.load(path))
    assert not result.valid
    measured = {format_frequency(float(f)) for f in result.frequency}
    flagged = np.sort(result.frequency[result.flagged])
    lines = [line for line in result.report().splitlines() if line.strip().startswith("bad band:")]
    assert len(lines) == len(result.bad_bands)
    for line in lines:  # the range named, before the rules' counts: measured frequencies the test flags
        named = _named(line.split(": ")[1])
        assert named and all(format_frequency(f) in measured for f in named), line
        assert all(format_frequency(f) in {format_frequency(float(x)) for x in flagged} for f in named), line
    # JSON: per band its flagged points and their range (the keys kk's linear test gives)
    assert main(["kk", str(path), "--method", "zhit", "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    points = payload["bad_band_frequencies_hz"]
    assert sorted(f for band in points for f in band) == flagged.tolist()
    assert payload["measured_bands_hz"] == [[band[0], band[-1]] for band in points]
    assert len(payload["measured_bands_hz"]) == len(payload["bad_bands_hz"])  # (the edges kept beside them)
    for (lo, hi), (m_lo, m_hi) in zip(payload["bad_bands_hz"], payload["measured_bands_hz"]):
        assert lo <= m_lo <= m_hi <= hi


def test_zhit_provenance_records_no_setting_of_the_linear_chain(capsys):
    """``kk --method zhit --json``'s provenance said ``"c": 0.85``, the linear test's µ cut-off,
    which Z-HIT has none of (it refuses --c): a record of a setting the run did not use."""
    assert main(["kk", str(REAL / "exampleDataGamry.DTA"), "--method", "zhit", "--json"]) == 0
    settings = json.loads(capsys.readouterr().out)["provenance"]["settings"]
    assert settings["method"] == "zhit" and settings["c"] is None
    assert main(["kk", str(REAL / "exampleDataGamry.DTA"), "--json"]) == 0  # (the linear test records the c it used)
    assert json.loads(capsys.readouterr().out)["provenance"]["settings"]["c"] == 0.85
