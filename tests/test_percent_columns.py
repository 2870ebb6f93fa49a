"""The percent columns of impedax's text tables line up (`impedax.data.format_percent_column`):
each value to 3 significant digits, padded so that the decimal points sit at one character
position (a common number of decimals, tried first, wrote "77.500" over "0.426": digits the value
does not have).
`format_percent`'s 3 significant digits dropped trailing zeros and changed decimals with the
magnitude: refine's table on the REAL Gamry file read "30.1 %" above "6.64 %", the KK batch
table on REAL battery cycles "0.11 %" below "0.0927 %" (2026-12-07). Free text keeps `format_percent`.

The oracle is each result's own number (rms_rel, the KK noise estimate), not the report's text:
each printed value is that number to 3 significant digits, ``{:#.3g}`` (the old writing,
``{:.3g}``, with its trailing zeros)."""

import math
import re
from pathlib import Path

import pytest

import impedax as ix
from impedax.data import format_percent_column

ROOT = Path(__file__).resolve().parents[1]
GAMRY = ROOT / "tests" / "fixtures" / "real" / "exampleDataGamry.DTA"
BATTERY = ROOT / "benchmarks" / "data" / "autoeis_battery_130.nc"
CYCLES = list(range(10, 18))  # (8 REAL cycles: more than SPECTRA_AS_COLUMNS, so the batch report has a row per spectrum)
BATTERY_MODELS = ("R0 + R1 || CPE1 + W1", "R0 + R1 || C1 + W1")
GAMRY_MODELS = ("R0 + R1 || C1", "R0 + R1 || CPE1", "R0 + (R1 + R2 || CPE2) || C1")


def _cells(lines: list[str], nth: int) -> list[tuple[int, str]]:
    """Per line, the ``nth`` number written before " %": the character position of its decimal
    point (of its end, without one) and the number's text."""
    cells = []
    for line in lines:
        m = list(re.finditer(r"(\S+) +%", line))[nth]
        text = m.group(1)
        cells.append((m.start(1) + (text.index(".") if "." in text else len(text)), text))
    return cells


def _assert_column(cells: list[tuple[int, str]], ratios: list[float]):
    """One decimal-point position; each value the ratio in % to 3 significant digits, as
    ``{:#.3g}`` writes it (``{:.3g}``'s old writing with its trailing zeros)."""
    assert len(cells) == len(ratios) >= 2
    assert len({position for position, _ in cells}) == 1, cells
    for (_, text), ratio in zip(cells, ratios):
        percent = abs(ratio) * 100
        expected = f"{percent:#.3g}"
        assert "e" not in expected
        assert text == expected.rstrip("."), (text, percent)
        assert abs(float(text) - float(f"{percent:.3g}")) == 0, (text, percent)


# --- the helper, against hand-written columns ---------------------------------------------------

@pytest.mark.parametrize("ratios, column", [
    ([0.0312, 0.028], ["3.12", "2.80"]),  # (2.8 had one decimal fewer)
    ([0.00426, 0.775], [" 0.426", "77.5  "]),  # (not 77.500: the points line up, each value keeps its 3 digits)
    ([1.234, 0.5], ["123  ", " 50.0"]),
    ([0.301, 0.0664, 0.0047], ["30.1  ", " 6.64 ", " 0.470"]),
    ([1e-12, 0.05], ["0   ", "5.00"]),  # (an exact fit's 1e-10 % reads 0)
    ([3e-6, 0.05], ["0.000300", "5.00    "]),
    ([float("nan"), 0.5, 12.34], ["   —  ", "  50.0", "1234  "]),
    ([-0.0312], ["3.12"]),
    ([], []),
])
def test_a_column_lines_up_its_decimal_points(ratios, column):
    assert format_percent_column(ratios) == column


# --- the tables, on REAL data -------------------------------------------------------------------

@pytest.fixture(scope="module")
def cycles():
    return ix.load(BATTERY).isel(cycle=CYCLES)


@pytest.fixture(scope="module")
def gamry():
    return ix.load(GAMRY)


@pytest.fixture(scope="module")
def refinement(gamry):
    return ix.refine(gamry, "R0 + R1 || C1")


@pytest.mark.slow  # (a refinement of the REAL file: 29 s on 2 cores at load 7)
def test_refine_steps(refinement):
    """REAL Gamry from R0 + R1 || C1: "30.1 %" above "6.64 %" before."""
    lines = [ln for ln in refinement.table().splitlines()[1:] if re.match(r"\s+\d+\s", ln)]
    _assert_column(_cells(lines, 0), [s.fit.rms_rel for s in refinement.steps])


def test_compare_models(gamry):
    comparison = ix.compare([ix.fit(m, gamry) for m in GAMRY_MODELS])
    lines = comparison.table().splitlines()[1 : 1 + len(GAMRY_MODELS)]
    _assert_column(_cells(lines, 0), [r["rms_rel"] for r in comparison.rows])


def test_kk_batch_rms_rel_and_noise(cycles):
    """REAL battery cycles: the noise column read "0.11 %" below "0.0927 %" before."""
    result = ix.kk_test_batch(cycles)
    lines = result.report().splitlines()
    rows = [ln for ln in lines if ln.startswith("cycle=")]
    _assert_column(_cells(rows, 0), [r.rms_rel for r in result.results])
    _assert_column(_cells(rows, 1), [r.noise_estimate for r in result.results])


def test_batch_fit_rows(cycles):
    batch = ix.fit(BATTERY_MODELS[0], cycles)
    lines = batch.report().splitlines()
    start = lines.index("each spectrum's fit (value ± relative standard error):")
    rows = lines[start + 2 : start + 2 + len(CYCLES)]
    assert all(r.startswith("cycle=") for r in rows)
    _assert_column(_cells(rows, -1), [float(v) for v in batch.dataset["rms_rel"].transpose("cycle").values])


def test_batch_compare_models(cycles):
    """REAL battery cycles: median rms_rel "3.85 %" above "24.8 %" before."""
    comparison = ix.compare([ix.fit(m, cycles) for m in BATTERY_MODELS])
    lines = comparison.report().splitlines()
    head = next(i for i, ln in enumerate(lines) if ln.startswith("model ") and ln.endswith("median rms_rel"))
    rows = lines[head + 1 : head + 1 + len(BATTERY_MODELS)]
    _assert_column(_cells(rows, 1), [m["rms_rel_median"] for m in comparison.models()])
    assert all(re.search(r" 100 % ", r) for r in rows)  # (the converged column before it, as it was)


@pytest.mark.slow  # (the refinement above)
def test_free_text_keeps_its_writing(refinement):
    """Free text is not a column: the refinement's summary line still says rms_rel as
    `format_percent` writes it."""
    first, last = refinement.steps[0].fit.rms_rel, refinement.final.rms_rel
    assert f"fell from {first * 100:.3g} % to {last * 100:.3g} %" in refinement.report()
