"""The ``quantity`` attr of the remainder that ``impedax gap --remaining`` writes, on the REAL
Autolab data.dfr (one sweep, 29 frequencies, no trial dimension: a single contact, nothing
subtracted), 2026-12-06 walkthrough: the attr said "trial means" of a file holding one spectrum."""

from pathlib import Path

import numpy as np

import impedax as ix
from cli_run import run
from impedax.models.sirin import remaining_impedance

DFR = Path(__file__).parent / "fixtures" / "real" / "data.dfr"


def test_gap_remaining_of_one_spectrum_is_not_called_trial_means(tmp_path, capsys):
    """The file holds 29 rows and no trial dim: the written remainder is that spectrum itself
    (its numbers equal the file's, in rising frequency), so its quantity says one spectrum, not trial means."""
    data = ix.load(DFR)
    assert data["Z"].dims == ("frequency",) and data.sizes["frequency"] == 29
    rem_path = tmp_path / "rem.nc"
    code, _, err = run(["gap", DFR, "--area", "130e-6", "--pooled", "--steps", "100", "--quiet", "--remaining", rem_path], capsys)
    assert code == 0, err
    rem = ix.load(rem_path)
    by_frequency = data.sortby("frequency")  # (the file sweeps 10 kHz down to 1 Hz)
    np.testing.assert_allclose(rem["frequency"].values, by_frequency["frequency"].values, rtol=1e-12)
    np.testing.assert_allclose(rem["Z"].values, by_frequency["Z"].values, rtol=1e-12)
    quantity = rem.attrs["quantity"]
    assert "trial means" not in quantity and quantity.endswith("one spectrum"), quantity
    assert "no skin or touchscreen subtracted" in quantity


def test_three_single_spectra_are_one_spectrum_each_and_trials_stay_trial_means():
    """Total, skin and screen one spectrum each: no mean over trials either; a total with two
    trials (the file's sweep and 1.1× it) is averaged, and the attr still says trial means."""
    data = ix.load(DFR)
    assert remaining_impedance(data, data, data).attrs["quantity"].endswith("one spectrum each")
    two = ix.make_spectrum(data["frequency"].values, np.stack([data["Z"].values, 1.1 * data["Z"].values]), dims=("trial",))
    assert remaining_impedance(two, None, None).attrs["quantity"].endswith("trial means")
