"""The diagnosis' note on a KK result it cannot place point by point (``kk=`` tested on other
frequencies than the fit's) names the flagged range by its measured points, as the data line
beside it does: SYNTHETIC data read "data: … in 1 mHz–3.98 Hz" above "note: the KK test flags
1 mHz–5.01 Hz" (5.01 Hz is halfway between the measured 3.98 Hz and 6.31 Hz). Oracle: the grid
the data were written on, and the frequencies the KK result flags."""

import re

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


@pytest.mark.slow  # (a diagnosis: about 20 s)
def test_the_note_on_a_kk_result_of_other_frequencies_names_its_measured_points():
    f, z = _drifting_low_end()
    ds = ix.make_spectrum(f, z)
    kk = ix.kk_test(ds.isel(frequency=slice(0, 40)))  # (tested without the top point: kk= cannot be placed on the fit's points)
    assert not kk.valid
    d = ix.diagnose(ds, "R0 + R1 || C1", kk=kk, drt_evidence=False, n_starts=1, progress=None)
    note, = [n for n in d.notes if n.startswith("the KK test flags") and "misfits there" in n]
    named = re.findall(r"(\d+(?:\.\d+)?) (m|k)?Hz", note.split(":")[0])
    named = [float(v) * {"m": 1e-3, "k": 1e3, None: 1.0, "": 1.0}[p] for v, p in named]
    flagged = np.sort(kk.frequency[kk.flagged])
    grid = {format_frequency(float(x)) for x in f}
    for value in named:  # every frequency named is a measured one, not a band edge between two
        assert format_frequency(value) in grid, note
    assert format_frequency(named[0]) == format_frequency(flagged[0]) and format_frequency(named[-1]) in {format_frequency(x) for x in flagged}, note
    # the data line names the same range
    data_line, = [line for line in d.report().splitlines() if line.startswith("data:")]
    assert note.split(": misfits")[0].removeprefix("the KK test flags ") in data_line, (note, data_line)
