"""`impedax kk` of a spectrum that passes ends with what to run next, `impedax drt` on the same
points, as `impedax inspect` names it ("then impedax drt … (how many arcs; it ends with a starting
circuit to fit)"): a walkthrough of REAL ZPlot and Autolab found the valid verdict the only step
that said nothing of the next. A failing test keeps its own next step (leave points out), with no
drt line. The command runs (the oracle: `impedax drt` exits 0 and ends with its starting circuit)."""

from __future__ import annotations

import shlex
from pathlib import Path

from cli_run import run

REAL = Path(__file__).parent / "fixtures" / "real"


def next_lines(out: str) -> list[str]:
    return [line for line in out.splitlines() if line.startswith("next:")]


def test_a_valid_spectrum_is_told_to_run_drt_on_the_same_points(capsys):
    path = REAL / "exampleDataZPlot.z"
    code, out, err = run(["kk", path, "--fmax", "2e5"], capsys)
    assert code == 0, err
    assert "verdict: valid" in out
    (line,) = next_lines(out)
    assert line.endswith(" (how many arcs; it ends with a starting circuit to fit)")
    words = shlex.split(line.removeprefix("next: ").split(" (how many", 1)[0])
    assert words[:3] == ["impedax", "drt", str(path)] and words[3] == "--fmax" and float(words[4]) == 2e5 and len(words) == 5
    code, out, err = run(words[1:], capsys)
    assert code == 0, err
    assert out.splitlines()[-1].startswith("starting circuit from the DRT")


def test_a_failing_spectrum_keeps_its_own_next_step(capsys):
    code, out, err = run(["kk", REAL / "exampleDataBioLogic.mpt"], capsys)
    assert code == 0, err
    lines = next_lines(out)
    assert lines and all("impedax drt" not in line for line in lines)
