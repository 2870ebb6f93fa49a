"""A failed KK test with no point to leave out by its bands' rules is tested again without points
at the ends (`kk_test(find_passing_band=True)`, `kk.passing_band`): the band that passes, the
options that keep it, and the diagnosis's ``data_invalid`` reason naming it (docs/kk.md, "What to
do"). REAL files: impedance.py's examples (MIT; tests/fixtures/real/LICENSE-impedance-py)."""

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.errors import ParameterError
from impedax.fitting.kk import kk_test, kk_test_batch
from cli_run import run as run_cli

REAL = Path(__file__).parent / "fixtures" / "real"


@pytest.fixture(scope="module")
def parstat():
    """REAL exampleDataParstat.txt: 31 points 10 Hz–10 kHz; above 2.5 kHz the points scatter into
    the inductive half-plane (Z' from −0.5 to 31 mΩ) and the chain's misfit spreads over the
    whole band: the test fails at 44.7 Hz–10 kHz, 24 of 31 points, too many to leave out."""
    return ix.load(REAL / "exampleDataParstat.txt")


def _passes(data, low: int, high: int) -> bool:
    """The test of ``data`` without its ``low`` lowest and ``high`` highest points (by hand: a
    sorted selection, the default test)."""
    f = np.sort(data["frequency"].values)
    return bool(kk_test(data.sel(frequency=f[low:f.size - high])).valid)


def test_the_band_that_passes_is_found_by_leaving_out_the_fewest_points_at_the_ends(parstat):
    plain = kk_test(parstat)
    assert not plain.valid and plain.excludable_frequencies.size == 0 and plain.passing_band is None
    assert any("measure again" in line for line in plain.next_step())
    found = kk_test(parstat, find_passing_band=True)
    f = np.sort(parstat["frequency"].values)
    assert found.passing_band == (pytest.approx(10.0), pytest.approx(f[-7]))  # (2.51 kHz: the 6 highest left out)
    # the oracle: that band passes the test on its own, and no split of 5 points or fewer does
    assert _passes(parstat, 0, 6)
    assert not any(_passes(parstat, low, total - low) for total in range(1, 6) for low in range(total + 1))
    assert found.passing_rms_rel == pytest.approx(kk_test(parstat.sel(frequency=f[:-6])).rms_rel)
    np.testing.assert_allclose(found.excludable_frequencies, f[-6:])
    assert found.suggested_options[0] == "--fmax" and f[-7] < float(found.suggested_options[1]) < f[-6]
    lines = found.next_step()
    assert lines[0].startswith("next: the test passes on 10 Hz–2.51 kHz (KK rms_rel 0.31 %), leaving out the 6 points above it: trim the measurement to it: kk_test(data.drop_sel(frequency=result.excludable_frequencies))")
    # the whole band's flags reach into the band that passes: the report says why those points pass there
    inside = np.asarray(found.flagged, bool) & (found.frequency <= f[-7])
    assert 10 < np.count_nonzero(inside) < np.count_nonzero(found.flagged)
    assert lines[1].startswith(f"  the {np.count_nonzero(inside)} points flagged within it (") and lines[1].endswith("pass there: fitted to every point, the chain was pulled off them by the 6 points above it")
    assert not any("measure again" in line for line in lines)
    # the verdict itself is the whole band's
    assert not found.valid and found.bad_bands == plain.bad_bands and found.rms_rel == plain.rms_rel


def test_no_band_is_searched_where_the_test_passes_or_the_rules_leave_points_out():
    """SYNTHETIC R0 + R1 ∥ C1 (100 Ω, 1 kΩ, 1 µF; a formula here), 0.5 % noise: valid, nothing
    searched. REAL BioLogic: the rules leave 4 points out (--exclude): that remedy stands."""
    f = np.logspace(-1, 5, 40)
    rng = np.random.default_rng(3)
    z = 100 + 1e3 / (1 + 2j * np.pi * f * 1e-3)
    z = z * (1 + 0.005 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2))
    sound = kk_test(ix.make_spectrum(f, z), find_passing_band=True)
    assert sound.valid and sound.passing_band is None and sound.next_step() == []
    biologic = kk_test(ix.load(REAL / "exampleDataBioLogic.mpt"), find_passing_band=True)
    assert not biologic.valid and biologic.passing_band is None and biologic.suggested_options[0] == "--exclude"


def test_where_no_band_passes_the_advice_stays():
    """REAL exampleDataGamry.DTA: the test fails at 15.9 mHz–2.26 kHz, 52 of 72 points; no band of at
    least half of the points passes: nothing is proposed, the advice to measure again stands."""
    gamry = kk_test(ix.load(REAL / "exampleDataGamry.DTA"), find_passing_band=True)
    assert not gamry.valid and gamry.passing_band is None and gamry.suggested_options == []
    assert any("measure again" in line for line in gamry.next_step())


def test_a_batch_refuses_the_search(parstat):
    with pytest.raises(ParameterError, match="find_passing_band searches one spectrum at a time"):
        kk_test_batch(parstat.expand_dims(cycle=[0, 1]), find_passing_band=True)


def test_impedax_kk_prints_and_writes_the_band_and_its_options(parstat, capsys, tmp_path):
    path = REAL / "exampleDataParstat.txt"
    code, out, _ = run_cli(["kk", path, "--json"], capsys)
    summary = json.loads(out)
    f = np.sort(parstat["frequency"].values)
    assert code == 0 and summary["passing_band_hz"] == [pytest.approx(10.0), pytest.approx(f[-7])]
    assert summary["passing_rms_rel"] == pytest.approx(0.0031, abs=5e-4) and summary["suggested_options"][0] == "--fmax"
    code, out, _ = run_cli(["kk", path], capsys)
    line = next(x for x in out.splitlines() if x.startswith("next: the test passes on 10 Hz–2.51 kHz"))
    assert line.endswith(f"impedax kk {path} --fmax {summary['suggested_options'][1]}")
    # the command it prints passes
    code, out, _ = run_cli(["kk", path, *summary["suggested_options"]], capsys)
    assert code == 0 and "verdict: valid" in out


def test_a_data_invalid_diagnosis_names_the_band_found_by_testing_again(parstat):
    """REAL Parstat with R0 + R1 ∥ C1: no run of points the whole test passes (its flags cover 44.7
    Hz–10 kHz), so the reason named no band and refine gave up at 33 %; now it names the band the
    test passes without the 6 highest points, and that the model misses it clearly."""
    d = ix.diagnose(parstat, "R0 + R1 || C1")
    f = np.sort(parstat["frequency"].values)
    assert d.verdict == "data_invalid" and d.kk_valid_band == (pytest.approx(10.0), pytest.approx(f[-7])), d.reason
    assert "passes at 10 Hz–2.51 kHz (25 points, KK rms_rel 0.31 %, tested again without the points outside)" in d.reason
    assert d.misses_valid_band and "--fmax" in d.reason


@pytest.mark.slow  # (12 s alone: a whole refine)
def test_refine_of_the_real_parstat_file_goes_on_on_the_band_that_passes(parstat):
    """Before: ``data_invalid`` at step 0 (33 %), "Repeat or trim the measurement". Now refine
    starts again on 10 Hz–2.51 kHz (6 of 31 points left out, under a quarter) and ends adequate
    there, below 1 % rms_rel."""
    r = ix.refine(parstat, "R0 + R1 || C1")
    assert r.verdict == "adequate" and len(r.masked_points) == 6, r.report()
    assert r.final.rms_rel < 0.01 and "ADEQUATE on 10 Hz – 2.51 kHz (25 of 31 points" in r.report()
