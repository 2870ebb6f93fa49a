"""kk and drt refuse a band with too few frequencies naming the band, as fit does: "the KK test
needs at least 4 frequencies, got 1" alone sent the user to a file of 21 (REAL ZPlot, `impedax kk
FILE --fmin 250k`, walkthrough 2026-12-07). Oracle: the file's frequencies as `ix.load` reads them."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

ZPLOT = Path(__file__).resolve().parent / "fixtures" / "real" / "exampleDataZPlot.z"


@pytest.mark.parametrize("argv, needs, fmin, fmax, words", [
    (["kk", "--fmin", "250k"], "the KK test needs at least 4 frequencies", 250e3, None, "at or above --fmin = 250 kHz"),
    (["drt", "--fmax", "4k"], "the DRT needs at least 5 frequencies", None, 4e3, "at or below --fmax = 4 kHz"),
    (["kk", "--method", "zhit", "--fmin", "100k", "--fmax", "200k"], "Z-HIT needs at least 6 frequencies", 100e3, 200e3, "from --fmin = 100 kHz to --fmax = 200 kHz"),
])
def test_too_few_frequencies_in_the_band_names_the_band(capsys, argv, needs, fmin, fmax, words):
    f = ix.load(ZPLOT)["frequency"].values
    kept = int(np.sum((f >= (fmin or 0)) & (f <= (fmax or np.inf))))
    assert main([argv[0], str(ZPLOT), *argv[1:]]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert f"{needs}, got {kept} ({kept} of the data's {f.size} {words}); use a wider band" in err


def test_too_few_frequencies_without_a_band_says_no_band(tmp_path, capsys):
    path = tmp_path / "three.csv"
    path.write_text("frequency,z_real_ohm,z_imag_ohm\n1000,100,-10\n100,110,-50\n10,150,-40\n")
    assert main(["kk", str(path)]) == 2
    err = capsys.readouterr().err
    assert "the KK test needs at least 4 frequencies, got 3" in err and "of the data's" not in err
