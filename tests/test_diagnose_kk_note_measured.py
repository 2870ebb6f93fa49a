"""A KK result of other frequencies than the fit's (``kk=``) is refused, both grids named by their
measured points. Until 2026-12-06 it was never placed on the fit's points and a note named its
flagged range (SYNTHETIC: "note: the KK test flags 1 mHz–5.01 Hz", then by its measured points,
1 mHz–3.98 Hz), nothing masked. Oracle: the grid the data were written on."""

import numpy as np
import pytest

import impedax as ix
from impedax.data import format_frequency


def _drifting_low_end():
    """R0 + R1 ∥ C1 (10 Ω, 100 Ω, 1 mF; SYNTHETIC) at 41 frequencies 1 mHz–100 kHz,
    0.2 % noise, times 1 + 0.1·cos(π x/2)·(1 + j)/√2, x = log(f/1 mHz)/log(30) clipped to [0, 1]:
    a sample drifting over the first decade and a half of the sweep."""
    f = np.logspace(-3, 5, 41)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-3)
    rng = np.random.default_rng(7)
    z = z * (1 + 0.002 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    x = np.clip(np.log(f / 1e-3) / np.log(30), 0, 1)
    return f, z * (1 + 0.1 * np.cos(np.pi * x / 2) * (1 + 1j) / np.sqrt(2))


@pytest.mark.slow  # (the baseline fit before the check: about 9 s)
def test_a_kk_result_of_other_frequencies_is_refused_naming_both_grids_by_their_measured_points():
    """Until 2026-12-06 such a result was never placed on the fit's points (a note named its flagged
    range, nothing was masked); now it is refused, both grids named by their measured ends."""
    f, z = _drifting_low_end()
    ds = ix.make_spectrum(f, z)
    kk = ix.kk_test(ds.isel(frequency=slice(0, 40)))  # (tested without the top point)
    assert not kk.valid
    with pytest.raises(ix.ParameterError) as err:
        ix.diagnose(ds, "R0 + R1 || C1", kk=kk, drt_evidence=False, n_starts=1, progress=None)
    message = str(err.value)
    assert f"40 frequencies, {format_frequency(f[0])}–{format_frequency(f[39])}" in message, message
    assert f"41 frequencies, {format_frequency(f[0])}–{format_frequency(f[40])}" in message, message
