"""What a fit says about the data's σ beyond its warnings: σ carried but not used by the
weighting is a note of the Python result (`result.unused_sigma_notes`, `FitResult.notes`), as
the command line said on stderr alone before 2026-12-02; and a σ that looks given in the wrong
unit (a fraction of |Z| read as ohms) is said to be one (`result.sigma_unit_slip`), where a
walkthrough's σ = 0.03 on 2 kΩ–5 MΩ data was told "residuals 2.6e6–3e6× the data's sigma: σ
understates the noise or the model misses something"."""

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.least_squares.result import sigma_unit_slip

FREQ = np.logspace(0, 5, 40)  # 1 Hz – 100 kHz
MODEL = "R0 + R1 || C1"
UNUSED = "the data carry sigma (σ per point), which this fit's modulus weighting does not use"
SLIP = "σ looks given in the wrong unit"


def z_rc(f, r0=2e3, r1=5e5, c1=2e-9):
    """R0 + R1 ∥ C1 [Ω], written here as the oracle."""
    return r0 + r1 / (1.0 + 2j * np.pi * f * r1 * c1)


def noisy(seed, relative):
    """SYNTHETIC: complex Gaussian noise of σ = relative·|Z| on Re and on Im; (Z, σ)."""
    rng = np.random.default_rng(seed)
    z = z_rc(FREQ)
    sigma = relative * np.abs(z)
    return z + sigma * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)), sigma


def uneven(seed):
    """SYNTHETIC: the walkthrough's noise, 3 % of |Z| below 10 Hz and 0.3 % above."""
    return noisy(seed, np.where(FREQ < 10, 0.03, 0.003))


def test_unused_sigma_is_a_note_of_single_and_batch_fits_alike(tmp_path):
    (z1, s1), (z2, s2) = uneven(1), uneven(2)
    single = ix.fit(MODEL, ix.make_spectrum(FREQ, z1, sigma=s1))
    assert single.weighting == "modulus"  # (the default stays)
    (note,) = single.notes
    assert note.startswith(UNUSED) and "weighting='sigma' weighs each point by it" in note
    assert not any("does not use: weighting='sigma'" in w for w in single.warnings)  # (a note, not a warning)
    assert f"note: {note}" in single.report().splitlines() and single.summary()["notes"] == [note]
    assert "note: the data carry sigma" in single._repr_html_()  # (the notebook display, as the report)
    batch = ix.fit(MODEL, ix.make_spectrum(FREQ, np.stack([z1, z2]), sigma=np.stack([s1, s2]), dims="trial"))
    assert batch.notes == single.notes and batch.summary()["notes"] == [note]
    assert batch.report().splitlines().count(f"note: {note}") == 1  # (once for the batch, not per spectrum)
    assert batch.fit_of(trial=0).notes == single.notes
    # kept by a saved result (a file before 2026-12-02 has none: ())
    ix.write_result(single, tmp_path / "single.nc")
    ix.write_result(batch, tmp_path / "batch.nc")
    with xr.open_dataset(tmp_path / "single.nc") as ds:
        assert ix.FitResult.from_xarray(ds).notes == single.notes
    with xr.open_dataset(tmp_path / "batch.nc") as ds:
        assert ix.BatchFitResult.from_xarray(ds).notes == batch.notes
    older = single.to_xarray()
    older.attrs = {k: v for k, v in older.attrs.items() if k != "notes"}
    assert ix.FitResult.from_xarray(older).notes == ()


def test_no_note_when_sigma_is_used_or_absent():
    z, s = uneven(3)
    assert ix.fit(MODEL, ix.make_spectrum(FREQ, z, sigma=s), weighting="sigma").notes == ()
    plain = ix.fit(MODEL, ix.make_spectrum(FREQ, z))
    assert plain.notes == () and "notes" in plain.summary() and not any(line.startswith("note:") for line in plain.report().splitlines())


@pytest.mark.parametrize(
    "factor, sigma, modulus, expected",
    [
        (50.0, 0.03, 1e4, None),  # residuals 50× σ: a model's miss may reach it
        (1e3, 0.03, 1e4, "a fraction of |Z| read as ohms"),  # every σ below 1 Ω, |Z| 10 kΩ
        (1e3, 0.03, 20.0, None),  # |Z| 20 Ω: 0.03 Ω is 0.15 % of it, plausible ohms
        (1e3, 5.0, 1e6, "σ is in median 5e-06 of |Z|"),  # 5 Ω on 1 MΩ: 5e-6, no analyser resolves it
        (1e3, 5.0, 1e3, None),  # 5 Ω on 1 kΩ: 0.5 %, a noise real data have
    ],
)
def test_sigma_unit_slip_by_hand_numbers(factor, sigma, modulus, expected):
    z = np.full(10, modulus * (0.6 + 0.8j))  # |Z| = modulus
    found = sigma_unit_slip(z, np.full(10, sigma), factor)
    assert found is None if expected is None else expected in found


def test_a_relative_sigma_read_as_ohms_is_called_a_unit_slip_in_single_and_batch():
    """σ = 0.03 meant as 3 %, on 2 kΩ–0.5 MΩ: the residuals are ~1e5–1e6× σ; the note says σ is
    in Ω and how a relative σ is given, single and batch alike."""
    (z1, _), (z2, _) = noisy(4, 0.01), noisy(5, 0.01)
    # (one start each: the note does not depend on the start ladder, which such a weighting climbs for 15 s)
    single = ix.fit(MODEL, ix.make_spectrum(FREQ, z1, sigma=0.03), weighting="sigma", n_starts=1)
    (note,) = [w for w in single.warnings if SLIP in w]
    assert "sigma = rel·|Z|" in note and "make_spectrum(f, Z, sigma=0.03 * abs(Z))" in note and "σ is 0.03 Ω, all below 1 Ω" in note
    factor = float(note.split("× the data's sigma")[0].split()[-1])
    # oracle: the residuals in rms over σ, from numpy: √(Σ|ΔZ|²/(0.03²·dof))
    expected = np.sqrt(np.sum(np.abs(single.z_model - z1) ** 2) / 0.03**2 / single.dof)
    assert factor == pytest.approx(expected, rel=0.05) and factor > 1e4
    batch = ix.fit(MODEL, ix.make_spectrum(FREQ, np.stack([z1, z2]), sigma=0.03, dims="trial"), weighting="sigma", n_starts=1)
    first = [w for w in batch.summary()["spectra"][0]["warnings"] if SLIP in w]
    assert first == [note]  # (the batch's first spectrum: the single fit's text)
    assert all(any(SLIP in w for w in row["warnings"]) for row in batch.summary()["spectra"])


def test_sigma_three_times_too_small_is_no_unit_slip():
    z, s = noisy(6, 0.01)
    result = ix.fit(MODEL, ix.make_spectrum(FREQ, z, sigma=s / 3), weighting="sigma")
    # (a KK chain weighted by the same σ misses by as much, so the note says σ misstates the noise: it understates it)
    assert any("× the data's sigma in rms" in w and "understates" in w for w in result.warnings)
    assert not any(SLIP in w for w in result.warnings)
