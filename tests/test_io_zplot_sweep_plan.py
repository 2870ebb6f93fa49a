"""ZPlot's header plans the sweep (``vs Freq-Initial``, ``vs Freq-Final``): the REAL
exampleDataZPlot.z plans 300 kHz to 1 Hz, and its rows stop at 3 kHz (21 of the 56 points its
``Data Points`` line announces), which inspect tells as the other instruments' sweeps stopped
short; the SYNTHETIC tests/fixtures/zplot_sweep.z covers its plan and is told nothing. The
oracle is the file's bytes: its header lines and its data rows."""

import math
import re
from pathlib import Path

import impedax as ix
from impedax.cli import main
from impedax.data import format_frequency

FIXTURES = Path(__file__).parent / "fixtures"
ZPLOT = FIXTURES / "real" / "exampleDataZPlot.z"


def _header(path: Path) -> dict[str, str]:
    lines = path.read_text(encoding="latin-1").splitlines()
    end = lines.index("End Comments")
    return {key.strip(): value.strip() for key, sep, value in (line.partition(":") for line in lines[:end]) if sep}


def _rows(path: Path) -> list[float]:
    lines = path.read_text(encoding="latin-1").splitlines()
    return [float(re.split(r"[\t,]", line)[0]) for line in lines[lines.index("End Comments") + 1 :] if line.strip()]


def test_the_header_numbers_are_a_consistent_plan():
    """The header's own numbers agree: 10 points a decade (``Log Interval``) from 300 kHz to 1 Hz
    are the 56 points ``Data Points`` announces, and the rows step by a tenth of a decade."""
    header = _header(ZPLOT)
    initial, final, per_decade = float(header["vs Freq-Initial"]), float(header["vs Freq-Final"]), float(header["vs Freq-Log Interval"])
    assert (initial, final, per_decade) == (3e5, 1.0, 10.0)
    assert math.ceil(math.log10(initial / final) * per_decade) + 1 == int(header["Data Points"]) == 56
    rows = _rows(ZPLOT)
    assert len(rows) == 21 and rows[0] == 3e5 and rows[-1] == 3e3
    assert all(abs(math.log10(a / b) - 0.1) < 1e-5 for a, b in zip(rows, rows[1:]))


def test_the_plan_is_kept_and_points_short_of_it_are_told(capsys):
    header = _header(ZPLOT)
    attrs = ix.load(ZPLOT).attrs
    assert attrs["initial_frequency_hz"] == float(header["vs Freq-Initial"])
    assert attrs["final_frequency_hz"] == float(header["vs Freq-Final"])
    low = format_frequency(min(_rows(ZPLOT)))
    note = f"the settings plan a sweep from 300 kHz to 1 Hz; the file's points span 300 kHz–{low} (none below {low})"
    assert attrs["frequency_plan_note"] == note
    assert main(["inspect", str(ZPLOT)]) == 0
    out = capsys.readouterr().out
    assert f"  frequency plan note: {note}\n" in out
    assert "  point count note: header says 'Data Points: 56'; the file holds 21 rows (sweep stopped early?)\n" in out


def test_a_sweep_that_covers_its_plan_is_not_told():
    synthetic = FIXTURES / "zplot_sweep.z"
    header = _header(synthetic)
    assert (float(header["vs Freq-Initial"]), float(header["vs Freq-Final"])) == (max(_rows(synthetic)), min(_rows(synthetic)))
    attrs = ix.load(synthetic).attrs
    assert (attrs["initial_frequency_hz"], attrs["final_frequency_hz"]) == (1e5, 1.0)
    assert "frequency_plan_note" not in attrs and "point_count_note" not in attrs
