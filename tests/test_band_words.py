"""Frequencies in words: a band of one point reads as that frequency (`data.format_band`), on
the KK test's, the diagnosis's and the failing bands' lines. REAL BioLogic data (impedance.py's
example file): its KK test flags four single points."""

from pathlib import Path

import numpy as np

import impedax as ix
from impedax.data import format_band

BIOLOGIC = Path(__file__).parent / "fixtures" / "real" / "exampleDataBioLogic.mpt"


def test_a_band_reads_as_its_ends_or_as_one_frequency():
    assert format_band(4.68, 6.08) == "4.68 Hz–6.08 Hz"
    assert format_band(2530.0, 2e5, " – ") == "2.53 kHz – 200 kHz"
    assert format_band(56.2, 56.2) == "56.2 Hz"
    assert format_band(56.21, 56.24) == "56.2 Hz"  # (the same in three digits: one frequency said once)
    assert format_band(0.0159, 2020.0) == "15.9 mHz–2.02 kHz"


def test_single_points_of_real_data_are_named_once():
    kk = ix.kk_test(BIOLOGIC)
    assert len(kk.bad_bands) == 4
    d = ix.diagnose(BIOLOGIC, "R0 + R1 || CPE1")
    text = d.report()
    flagged = np.sort(kk.frequency[kk.flagged])
    words = ", ".join(f"{f:.3g} Hz" for f in flagged)  # (the four points, all between 1 Hz and 1 kHz)
    assert f"the KK test flags 4 points inside the band ({words})" in text
    for f in flagged:
        assert f"{f:.3g} Hz–{f:.3g} Hz" not in text and f"between {f:.3g} Hz and {f:.3g} Hz" not in text
    assert "at 56.2 Hz the data and the model differ" in text  # (the failing band 49.3–64.1 Hz holds one point of the model's misfit)


def test_the_force_plots_peak_reads_with_an_si_prefix():
    """The force spectrum's peak label: 33.1 kHz, as the text elsewhere (it read 3.314e+04 Hz)."""
    from impedax.plotting.models import plot_force_spectrum

    f = np.geomspace(10.0, 1e6, 5)
    fig = plot_force_spectrum(f, np.ones(5) * 0.1, title="t", peak={"frequency_hz": 33140.0, "force_n": 0.1649, "at_band_edge": False})
    (text,) = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert text == "peak: 164.9 mN at 33.1 kHz"
