"""`impedax inspect` names the points whose real part is negative, which no passive cell gives
(an instrument's phase error near the top of its band, most often), before a fit meets them.
The oracle is the REAL file's bytes: the rows whose Zre is below −5 % of |Z|."""

import json
import math
from pathlib import Path

import pytest

from impedax.cli import main
from impedax.data import format_frequency

REAL = Path(__file__).parent / "fixtures" / "real"


def _negative_rows(path: Path) -> list[float]:
    """Frequencies [Hz] of the PowerSuite rows (Frequency, Zre, Zimg) with Zre < −0.05·|Z|."""
    rows = [line.split("\t") for line in path.read_text().splitlines()[1:] if line.strip()]
    return [float(f) for f, re_, im in rows if float(re_) < -0.05 * math.hypot(float(re_), float(im))]


def test_inspect_names_the_real_files_points_with_negative_real_part(capsys):
    path = REAL / "exampleDataPowersuite.txt"
    bad = _negative_rows(path)
    assert len(bad) == 2  # (1.12 MHz and 2 MHz, the top of the sweep)
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    line = next(line for line in out.splitlines() if line.startswith("  Re Z < 0:"))
    assert f"2 of 30 points have Re Z < 0 by more than 5 % of |Z| ({', '.join(format_frequency(f) for f in sorted(bad))})" in line, line
    assert "no passive circuit reaches" in line and "top of the instrument's band" in line
    assert main(["inspect", str(path), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["non_passive_frequencies_hz"] == sorted(bad)
    assert "2 of 30 points" in summary["non_passive_note"]


@pytest.mark.parametrize("name", ["exampleDataGamry.DTA", "exampleDataBioLogic.mpt", "data.xlsx"])
def test_inspect_says_nothing_of_files_without_such_points(capsys, name):
    assert main(["inspect", str(REAL / name), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["non_passive_frequencies_hz"] == [] and summary["non_passive_note"] is None
    assert main(["inspect", str(REAL / name)]) == 0
    assert "Re Z < 0" not in capsys.readouterr().out
