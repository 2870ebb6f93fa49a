"""`impedax stack` of files on different frequency grids: the refusal says what differs as a
researcher checks it, each grid's points and range and which frequencies one file has and the
other lacks, not "first differing at" the point after a skipped one. REAL files: Gamry's
exampleDataGamry.DTA, the same with one point left out (the oracle: the frequency taken out),
and EC-Lab's exampleDataBioLogic.mpt on a grid of its own."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.data import format_band, format_frequency
from impedax.errors import DataError

REAL = Path(__file__).parent / "fixtures" / "real"
GAMRY = REAL / "exampleDataGamry.DTA"
SKIPPED = 40  # (0-based: the point left out, 19.9 Hz in the REAL sweep)


def _without_point(tmp_path: Path) -> tuple[Path, float]:
    ds = ix.load(GAMRY)
    out = tmp_path / "skipped.csv"
    ix.save(ds.drop_isel(frequency=SKIPPED), out)
    return out, float(ds["frequency"].values[SKIPPED])


def test_a_skipped_point_is_named_not_the_point_after_it(tmp_path):
    cut, skipped_hz = _without_point(tmp_path)
    f = ix.load(GAMRY)["frequency"].values
    with pytest.raises(DataError) as err:
        ix.stack_files([GAMRY, cut])
    text = str(err.value)
    assert f"its frequency grid differs from {GAMRY}'s (71 vs 72 points" in text, text
    assert f"71 frequencies match within 0.1 %; exampleDataGamry.DTA has 1 this file lacks ({format_frequency(skipped_hz)})" in text, text
    assert "first differing" not in text and "--common-frequencies" in text
    # and the other way round: the file that has it first
    with pytest.raises(DataError) as err:
        ix.stack_files([cut, GAMRY])
    assert f"this file has 1 skipped.csv lacks ({format_frequency(skipped_hz)})" in str(err.value), str(err.value)
    assert format_band(f.min(), f.max()) in str(err.value)


def test_grids_of_two_instruments_are_told_by_their_ranges(tmp_path, capsys):
    mpt = REAL / "exampleDataBioLogic.mpt"
    f0, f = ix.load(GAMRY)["frequency"].values, ix.load(mpt)["frequency"].values
    assert main(["stack", str(GAMRY), str(mpt), "--out", str(tmp_path / "s.nc")]) == 2
    err = capsys.readouterr().err
    assert f"(43 vs 72 points: {format_band(f.min(), f.max())} vs {format_band(f0.min(), f0.max())};" in err, err
    # the oracle for what matches: each of the mpt's frequencies against the Gamry grid, within 0.1 %
    matched = sum(bool(np.any(np.abs(fi / f0 - 1) <= 1e-3)) for fi in f)
    assert matched == 1 and "1 frequency matches within 0.1 %" in err and f"exampleDataGamry.DTA has {72 - matched} this file lacks" in err
    assert f"this file has {43 - matched} exampleDataGamry.DTA lacks" in err
    # --common-frequencies would refuse them (under half shared): not offered
    assert "too few to keep only the shared ones (--common-frequencies): fit the files one by one" in err
    assert "impedax stack --common-frequencies;" not in err
    assert not (tmp_path / "s.nc").exists() and len(err.strip().splitlines()) == 1
