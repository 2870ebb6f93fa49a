"""One KK finding reads as one frequency range. REAL Gamry's refine report named it as
"15.9 mHz–2.26 kHz" (the bad band, whose edges lie halfway to the neighbouring points) beside
"52 of 72 points (15.9 mHz–2.02 kHz)" and "the flagged run at the end of the band (15.9
mHz–2.02 kHz)"; REAL test_data.txt as 1.54 mHz–676 mHz, 1.78 mHz–585 mHz and 1 mHz–585 mHz.
Oracles: the file's measured frequencies, and the ranges read back from the report's text."""

import itertools
import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix

REAL = Path(__file__).parent / "fixtures" / "real"
PREFIX = {"M": 1e6, "k": 1e3, "": 1.0, "m": 1e-3, "µ": 1e-6}
RANGE = re.compile(r"(\d+(?:\.\d+)?) (M|k|m|µ)?Hz–(\d+(?:\.\d+)?) (M|k|m|µ)?Hz")


def test_a_bad_band_is_named_by_its_measured_points():
    """`KKResult.measured_bands`: the lowest and highest flagged frequency of each bad band,
    both measured frequencies of the file (the band's own edges are not)."""
    kk = ix.kk_test(ix.load(REAL / "exampleDataGamry.DTA"))
    f = np.sort(kk.frequency)
    (lo, hi), = kk.bad_bands
    assert hi not in f  # (halfway to the next point: why the report named 2.26 kHz)
    assert kk.measured_bands == ((f[f >= lo].min(), f[f <= hi].max()),)
    assert kk.measured_bands_text() == "15.9 mHz–2.02 kHz"


def test_a_frequency_just_below_1_mhz_is_written_in_mhz():
    """REAL test_data.txt's lowest frequency, 0.99990517 mHz, read "0.001 Hz" beside "1.34 mHz"
    (`bands.format_frequency` had its own copy of the formatter)."""
    from impedax.fitting.diagnosis.bands import format_frequency

    assert format_frequency(0.00099990517) == "1 mHz"


def _ranges(text: str) -> list[tuple[str, float, float]]:
    return [(m.group(0), float(m.group(1)) * PREFIX[m.group(2) or ""], float(m.group(3)) * PREFIX[m.group(4) or ""]) for m in RANGE.finditer(text)]


@pytest.mark.slow  # (a diagnosis of each file: 20-40 s)
@pytest.mark.parametrize("name, finding", [("exampleDataGamry.DTA", "15.9 mHz–2.02 kHz"), ("test_data.txt", "1.78 mHz–585 mHz")])
def test_the_report_names_one_range_for_the_kk_finding(name, finding):
    """The diagnosis' data line (the line refine's report starts from) and verdict: ranges that
    overlap or touch are one and the same text; the finding is the flagged points' range."""
    d = ix.diagnose(ix.load(REAL / name), "R0 + R1 || C1", progress=None)
    lines = [line for line in d.report().splitlines() if line.startswith(("data:", "verdict"))]
    ranges = _ranges(" ".join(lines))
    assert finding in [text for text, _, _ in ranges], lines
    for (a, a_lo, a_hi), (b, b_lo, b_hi) in itertools.combinations(ranges, 2):
        if a_lo <= b_hi * 1.0001 and b_lo <= a_hi * 1.0001:  # (overlapping)
            assert a == b, lines


@pytest.mark.slow  # (a diagnosis: 20-40 s)
def test_diagnose_json_gives_the_range_its_text_names(capsys):
    """``impedax diagnose --json``'s ``kk`` held the bad bands' edges alone (REAL Gamry: up to
    2257 Hz, halfway to the measured 2.53 kHz) beside a text naming 15.9 mHz–2.02 kHz:
    ``measured_bands_hz`` (added, as ``impedax kk --json``'s) gives the flagged points' range."""
    import json

    from impedax.cli import main

    path = REAL / "exampleDataGamry.DTA"
    f = ix.load(path)["frequency"].values
    assert main(["diagnose", str(path), "--model", "R0 + R1 || C1", "--json"]) == 0
    kk = json.loads(capsys.readouterr().out)["kk"]
    (lo, hi), = kk["measured_bands_hz"]
    assert lo in f and hi in f and [lo, hi] == [0.0158898, 2015.625]  # (the file's own frequencies)
    (edge_lo, edge_hi), = kk["bad_bands"]  # (kept: the JSON is a contract)
    assert edge_lo <= lo < hi < edge_hi
