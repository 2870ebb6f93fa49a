"""diagnose names the band to keep that ``impedax kk`` names (`kk.retested_band`), with the same
--fmin/--fmax, and says why when it names a band kk does not; a KK result given for another
frequency grid than the fit's is refused (docs/diagnosis.md, "Is it the data or the model?")."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.errors import ParameterError
from impedax.fitting.diagnosis.effects import DEFAULT_EFFECTS

REAL = Path(__file__).parent / "fixtures" / "real"


def test_diagnose_names_the_band_and_trim_impedax_kk_names_on_real_ch_instruments():
    """REAL CH Instruments: the full test leaves 825 Hz–46.4 kHz unflagged in one run, and diagnose
    named it (--fmin 8e2 --fmax 5e4) where impedax kk names 4.64 Hz–82.5 kHz (--fmin 4.6 --fmax 8.3e4),
    a band that passes a KK test of its own: one spectrum, two trims."""
    data = ix.load(REAL / "exampleDataCHInstruments.txt")
    kk = ix.kk_test(data, find_passing_band=True)
    lo, hi = kk.passing_band
    f = data["frequency"].values
    assert ix.kk_test(data.isel(frequency=np.nonzero((f >= lo) & (f <= hi))[0])).valid  # (the oracle: the band passes by itself)
    trim = " ".join(kk.suggested_options)
    assert trim == "--fmin 4.6 --fmax 8.3e4"
    d = ix.diagnose(data, "R0 + R1 || CPE1 + CPE2")
    assert d.verdict.value == "data_invalid" and d.masked_points == ()  # (the decision is unchanged)
    assert "passes at 4.64 Hz–82.5 kHz" in d.reason and f"({trim})" in d.reason, d.reason
    assert "825 Hz–46.4 kHz (" not in d.reason and "--fmin 8e2" not in d.reason, d.reason
    assert d.summary()["kk_valid_band"] == [lo, hi]
    assert d.kk_run_band == (825.2, 46440.0)  # (refine still acts on the run the full test leaves unflagged)
    # the same with kk= impedax kk's own result (which holds its passing band already)
    assert ix.diagnose(data, "R0 + R1 || CPE1 + CPE2", kk=kk).reason == d.reason


def test_diagnose_says_why_impedax_kk_names_no_band_on_real_gamry():
    """REAL Gamry: the full test leaves 2.53 kHz–200 kHz unflagged (20 of 72 points) and diagnose
    advises it, while impedax kk names no trim (it keeps at least half of the points): the note says so."""
    data = ix.load(REAL / "exampleDataGamry.DTA")
    kk = ix.kk_test(data, find_passing_band=True)
    assert kk.passing_band is None and kk.suggested_options == []
    d = ix.diagnose(data, "R0 + R1 || CPE1")
    kept = d.kk_flagged_kept
    assert "2.53 kHz–200 kHz" in kept and "(--fmin 2.5e3)" in kept, kept
    assert "impedax kk names no trim" in kept and "half of the 72 points" in kept, kept


def test_a_kk_result_of_another_grid_is_refused_by_name_and_one_of_the_full_data_still_serves_a_trimmed_fit():
    """Before: a KK result of every other point of REAL CH Instruments was never placed on the fit's
    points: nothing masked, no word. The KK test of the full data with a fit over --fmin/--fmax
    is legitimate (its grid holds the fit's points)."""
    data = ix.load(REAL / "exampleDataCHInstruments.txt")
    other = ix.kk_test(data.isel(frequency=slice(None, None, 2)))
    with pytest.raises(ParameterError) as err:
        ix.diagnose(data, "R0 + R1 || CPE1", kk=other)
    message = str(err.value)
    assert "37 frequencies" in message and "73" in message and "100 mHz" in message, message
    full = ix.kk_test(data)
    d = ix.diagnose(data, "R0 + R1 || CPE1", kk=full, fmin=5, fmax=9e4, effects=DEFAULT_EFFECTS.select(()), drt_evidence=False)
    f = data["frequency"].values
    # (placed on the fit's 51 points: its flags at the trimmed band's ends are masked there)
    assert d.baseline.n_points + len(d.masked_points) == np.count_nonzero((f >= 5) & (f <= 9e4)) and len(d.masked_points) > 0


def test_the_points_kept_inside_the_band_are_named_with_the_exclude_impedax_kk_gives_on_real_biologic():
    """REAL BioLogic: impedax kk says --exclude 5.34,56.2,123,270; diagnose's note said
    --exclude 5.33641,56.2418,123.303,270.433 for the same four points."""
    data = ix.load(REAL / "exampleDataBioLogic.mpt")
    options = ix.kk_test(data, find_passing_band=True).suggested_options
    assert options[0] == "--exclude"
    d = ix.diagnose(data, "R0 + R1 || CPE1", effects=DEFAULT_EFFECTS.select(()), drt_evidence=False)
    assert f"--exclude {options[1]} leaves these out too" in d.kk_flagged_kept, d.kk_flagged_kept


def test_refine_s_note_names_the_band_impedax_kk_names_on_real_ch_instruments():
    """REAL CH Instruments, refine stopping at its start (max_effects=0): its note said "the KK test
    passes only 825 Hz–46.4 kHz (22 of 73 points) … it would leave out 70 %", beside a verdict and
    an impedax kk naming 4.64 Hz–82.5 kHz; refine still does not start again (both leave out more
    than the quarter it may)."""
    data = ix.load(REAL / "exampleDataCHInstruments.txt")
    lo, hi = ix.kk_test(data, find_passing_band=True).passing_band
    f = data["frequency"].values
    inside = int(np.count_nonzero((f >= lo) & (f <= hi)))
    r = ix.refine(data, "R0 + R1 || CPE1 + CPE2", max_effects=0)
    assert r.verdict.value == "data_invalid" and r.masked_points == ()
    note, = [n for n in r.notes if n.startswith("the KK test passes only")]
    assert f"passes only 4.64 Hz–82.5 kHz ({inside} of {f.size} points)" in note and f"leave out {(1 - inside / f.size) * 100:.0f} %" in note, note
