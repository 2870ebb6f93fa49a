"""A spectrum that is 0 at every point (a lead not connected, a failed sweep: the instrument wrote
0,0 on every row) is refused by every fit, under every weighting, with one line that says so.
Before, modulus weighting advised ``--weighting unit``, and unit weighting then "fitted" the zeros
(R0 = 1e-300 Ω, rms_rel inf %, RuntimeWarnings from the start guesses)."""

import subprocess
import sys

import numpy as np
import pytest

import impedax as ix
from impedax.errors import DataError

FREQ = np.geomspace(1.0, 1e5, 20)
SAID = "Z = 0 at every one of the 20 points"


@pytest.fixture()
def zero_file(tmp_path):
    path = tmp_path / "zero.csv"
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{float(f)!r},0,0\n" for f in FREQ))
    return path


@pytest.mark.parametrize("weighting", ["modulus", "unit", "proportional"])
def test_the_command_line_refuses_a_spectrum_of_zeros_under_every_weighting(zero_file, weighting):
    run = subprocess.run([sys.executable, "-m", "impedax", "fit", str(zero_file), "--model", "R0 + R1 || C1", "--weighting", weighting, "--json"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 2
    assert run.stdout == ""
    assert SAID in run.stderr and "nothing to fit" in run.stderr and "zero.csv" in run.stderr
    assert "--weighting unit" not in run.stderr  # (the advice that led to a fit of zeros)
    assert "Traceback" not in run.stderr and "RuntimeWarning" not in run.stderr


def test_a_batch_names_its_spectrum_of_zeros():
    z = np.stack([100.0 + 1e3 / (1 + 2j * np.pi * FREQ * 1e-4), np.zeros(FREQ.size)])  # SYNTHETIC R0 + R1 ∥ C1, then zeros
    with pytest.raises(DataError, match=r"Z = 0 at every one of the 20 points of spectrum 1: .*nothing to fit"):
        ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, z, dims=("trial",)), weighting="unit")


def test_a_spectrum_with_some_zero_points_still_names_them():
    z = 100.0 + 1e3 / (1 + 2j * np.pi * FREQ * 1e-4)  # SYNTHETIC R0 + R1 ∥ C1
    z[3] = 0
    with pytest.raises(DataError, match=r"zero or non-finite weight at f=.* \(point 3\), where \|Z\| = 0 Ω; drop the point"):
        ix.fit("R0 + R1 || C1", (FREQ, z))
