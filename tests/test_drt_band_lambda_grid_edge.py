"""The credible band's λ (the evidence's optimum on the λ grid) at an end of that grid is no
optimum: the report, `DRTResult.notes` and the JSON say so, naming λ and the grid's end, as
impedax says of a parameter at its bound. On the REAL data.dfr (29 points) the evidence's best
grid point is its first, 10⁻⁸; on a SYNTHETIC two-arc spectrum (1 % noise) it lies inside."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix

REAL = Path(__file__).parent / "fixtures" / "real" / "data.dfr"
WORDS = "the credible band's λ = 10⁻⁸ (the evidence's) is at the bottom of its search grid, 10⁻⁸–100"


@pytest.fixture(scope="module")
def real():
    return ix.drt(ix.load(str(REAL)))


def test_band_lambda_at_the_bottom_of_the_grid_is_said(real):
    grid = np.asarray(real.lambda_grid)
    assert grid[0] == pytest.approx(1e-8, rel=1e-9) and grid[-1] == pytest.approx(100.0, rel=1e-9)  # (the grid's ends, as docs/drt.md gives them)
    assert real.band_lambda == pytest.approx(grid[0], rel=1e-9)
    said = [n for n in real.notes if WORDS in n]
    assert len(said) == 1 and "not an optimum" in said[0], real.notes
    assert f"note: {said[0]}" in real.report()
    summary = real.summary()
    assert summary["band_lambda_at_grid_edge"] == "bottom" and said[0] in summary["notes"]


def test_band_lambda_inside_the_grid_gives_no_note():
    f = np.geomspace(0.1, 1e5, 50)
    w = 2 * np.pi * f
    z = 10 + 100 / (1 + 1j * w * 1e-3) + 200 / (1 + 1j * w * 1e-1)
    rng = np.random.default_rng(3)
    z = z * (1 + 0.01 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    result = ix.drt(ix.make_spectrum(f, z))
    grid = np.asarray(result.lambda_grid)
    assert grid[0] * 1.01 < result.band_lambda < grid[-1] / 1.01
    assert not any("search grid" in n for n in result.notes)
    assert result.summary()["band_lambda_at_grid_edge"] is None


def test_a_batch_report_counts_the_spectra_whose_band_lambda_is_at_an_end():
    """The REAL data.ods holds the same spectrum on 4 sheets: its batch report says, once, on how
    many of them the band's λ is at the grid's bottom; the JSON's rows each keep the note."""
    batch = ix.drt(ix.load(str(REAL.with_suffix(".ods"))))
    lines = [ln for ln in batch.report().splitlines() if "search grid" in ln]
    assert lines == ["note: the credible band's λ (the evidence's) is at the bottom of its search grid, 10⁻⁸–100, on 4 of 4 spectra: "
                     "not an optimum, the evidence's maximum is there or below (γ, its λ and the peaks do not depend on it)"], lines
    assert [row["band_lambda_at_grid_edge"] for row in batch.summary()["spectra"]] == ["bottom"] * 4
