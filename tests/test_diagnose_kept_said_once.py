"""`impedax diagnose` says once why it kept the points the Kramers–Kronig test flags: on the
data line. The same sentence came again as the report's last note (with ": diagnosed with every
point"), some 400 characters twice on REAL BioLogic (4 lone points inside the band) and 600 on
REAL Gamry. The JSON keeps both keys (``kk_flagged_kept`` and ``notes``) as they were."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from cli_run import run

REAL = Path(__file__).parent / "fixtures" / "real"


@pytest.mark.slow
def test_biologics_kept_points_are_said_once(capsys):
    path = REAL / "exampleDataBioLogic.mpt"
    code, out, err = run(["diagnose", path, "--model", "R0 + R1 || C1", "--json", "-q"], capsys)
    assert code == 0, err
    payload = json.loads(out)
    kept = payload["kk_flagged_kept"]
    assert kept.startswith("the KK test flags 4 points inside the band (5.34 Hz, 56.2 Hz, 123 Hz, 270 Hz): kept in every fit")
    assert f"{kept}: diagnosed with every point" in payload["notes"]  # (the JSON as it was)
    code, out, err = run(["diagnose", path, "--model", "R0 + R1 || C1", "-q"], capsys)
    assert code == 0, err
    assert out.count(kept) == 1
    (data_line,) = [line for line in out.splitlines() if line.startswith("data:")]
    assert kept in data_line
    assert not any(line.startswith("note: the KK test flags 4 point(s)") for line in out.splitlines())
