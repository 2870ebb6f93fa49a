"""`impedax.io.load(path, sweep=LABEL)` picks a spectrum of a file's one dimension of spectra on
one grid, as it reads one alone when their grids differ (docs/io.md: ``sweep`` takes the label of
whichever dimension the file's spectra lie along). REAL files of tests/fixtures/real: the
spreadsheet's four sheets and IviumSoft's two measurements, one grid each, were refused with "the
file holds no sweeps to pick from (sheet, frequency)" until 2026-12-06."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix

REAL = Path(__file__).parent / "fixtures" / "real"


@pytest.mark.parametrize(("name", "dim", "label"), [("data.xlsx", "sheet", "header-variant-2"), ("data.ods", "sheet", "header-variant-4"), ("data.ids", "measurement", "1")])
def test_a_label_of_the_files_one_dimension_picks_that_spectrum(name, dim, label):
    whole = ix.load(REAL / name)
    assert whole["Z"].dims == (dim, "frequency")  # (the oracle's premise: one dimension of spectra on one grid)
    picked = ix.load(REAL / name, sweep=label)
    assert picked["Z"].dims == ("frequency",)
    np.testing.assert_array_equal(picked["Z"].values, whole["Z"].sel({dim: label}).values)
    assert str(picked[dim].values) == label


def test_an_unknown_label_lists_the_files_labels_and_one_spectrum_still_has_none():
    with pytest.raises(ix.DataError, match="sweep=Sheet9: no sheet Sheet9; its sheets: header-variant-1, header-variant-2, header-variant-3, header-variant-4"):
        ix.load(REAL / "data.xlsx", sweep="Sheet9")
    with pytest.raises(ix.DataError, match=r"sweep=0: the file holds no sweeps to pick from \(one spectrum\)"):
        ix.load(REAL / "exampleDataGamry.DTA", sweep="0")


def test_identify_names_a_path_that_is_no_path_as_load_does():
    """impedax.io.identify(123) raised Python's TypeError "expected str, bytes or os.PathLike
    object, not int" (until 2026-12-06); load's own message now, and a REAL file is still identified."""
    with pytest.raises(ix.DataError, match=r"a file path \(str or pathlib.Path\) is needed, got 123 \(int\)"):
        ix.io.identify(123)
    assert ix.io.identify(REAL / "data.dfr")[0].name == "Autolab FRA dfr"
