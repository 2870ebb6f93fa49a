"""A corner panel's title for a log parameter whose interval spans many decades: REAL CH
Instruments with ``R0 + R1 || CPE1`` (R1 runs off to TΩ, the data do not bound it) read
"R1 = 43.1 [2.37e-05, 4.85e+07] TΩ", all three in the largest value's prefix. Each number now
has its own prefix there. Oracle: the numbers read back from the title with the SI prefix table
written here, against the draws' own quantiles."""

import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.plotting.bayes import interval_text

REAL = Path(__file__).parent / "fixtures" / "real"
PREFIX = {"T": 1e12, "G": 1e9, "M": 1e6, "k": 1e3, "": 1.0, "m": 1e-3, "µ": 1e-6, "n": 1e-9, "p": 1e-12}
NUMBER = re.compile(r"([-\d.]+(?:e[-+]\d+)?) ?([TGMkmµnp]?)Ω")


def _read(text: str) -> list[float]:
    return [float(m.group(1)) * PREFIX[m.group(2)] for m in NUMBER.finditer(text)]


def test_an_interval_over_decades_writes_each_number_in_its_own_prefix():
    text = interval_text(4.31e13, 2.37e7, 4.85e19, "Ω", significant=True)
    assert text == "43.1 TΩ [23.7 MΩ, 4.85e+19 Ω]"  # (beyond the largest prefix, T: as a plain number)
    assert interval_text(5.0e3, 1.2, 9.0e3, "Ω", significant=True) == "5 kΩ [1.2 Ω, 9 kΩ]"
    # within what one prefix writes readably (none below 0.01), one prefix as before
    assert interval_text(1.2e3, 13.0, 9.51e4, "Ω", significant=True) == "1.2 [0.013, 95.1] kΩ"


def test_the_real_corner_title_reads_each_number():
    post = ix.sample("R0 + R1 || CPE1", ix.load(REAL / "exampleDataCHInstruments.txt"), progress=False, seed=0, steps=400)
    fig = post.corner()
    title, = [ax.get_title() for ax in fig.axes if ax.get_title().startswith("R1 =")]
    draws = post.samples["R1"]
    expected = [np.median(draws), np.quantile(draws, 0.05), np.quantile(draws, 0.95)]
    assert expected[2] / expected[1] > 1e6  # (the case: an interval over many decades)
    assert "e-" not in title
    np.testing.assert_allclose(_read(title), expected, rtol=6e-3)
