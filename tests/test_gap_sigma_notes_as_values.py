"""`impedax gap` leaves out the EDL fit's notes that read residuals below σ, or uneven against
it, as what σ is or a σ misstating the noise, where σ is the standard error of varying trials
(`_edl_fit_warnings`). It found them by their words (`SIGMA_OVERSTATES_WORDS`,
`SIGMA_OF_TRIAL_MEANS_WORDS`, `SIGMA_BAND_WORDS`): a reworded note was kept. They are a value set
where the notes are made (`FitResult.sigma_residual_notes`), stored in the .nc; a file without it
is read by the words.

Oracle: the notes as the fit words them, and the same fit with `SIGMA_OF_TRIAL_MEANS_WORDS`
reworded (monkeypatched before the fit); the old rule is written out here. SYNTHETIC Sirin
example of seed 1 (numpy formulas), its trial-mean remainder, the EDL fit weighted by its SEM
(as tests/test_gap_sem_weighting.py)."""

from __future__ import annotations

import pytest

import impedax as ix
from impedax.fitting.least_squares import result as result_module
from impedax.fitting.least_squares.result import SIGMA_BAND_WORDS, SIGMA_OF_TRIAL_MEANS_WORDS, SIGMA_OVERSTATES_WORDS, FitResult, fit_sigma_residual_notes
from impedax.io import read_netcdf, write_netcdf
from impedax.models.gap import _edl_fit_warnings
from impedax.models.sirin import remaining_impedance
from impedax.models.synthetic import example_spectra, generate_sirin_synthetic

EDL = "R_EP || CPE_EP || C_gap"
REWORDED = "σ is the SEM over the trials (this test's words)"
OLD_WORDS = (SIGMA_OVERSTATES_WORDS, SIGMA_OF_TRIAL_MEANS_WORDS, SIGMA_BAND_WORDS)  # (the words the old rule read)


@pytest.fixture(scope="module")
def remaining():
    parts = example_spectra(generate_sirin_synthetic(seed=1))
    return remaining_impedance(parts["total_sliding"], parts["skin"], parts["touchscreen"])


@pytest.fixture(scope="module")
def reworded(remaining):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(result_module, "SIGMA_OF_TRIAL_MEANS_WORDS", REWORDED)
        return ix.fit(EDL, remaining, weighting="sigma")


def _old_rule(edl) -> list[str]:
    return [f"EDL fit: {w}" for w in edl.warnings if not any(words in w for words in OLD_WORDS)]


def test_a_reworded_sigma_note_is_left_out_all_the_same(remaining, reworded):
    note = next(w for w in reworded.warnings if REWORDED in w)  # (the case: the fit says what its σ is, reworded)
    assert f"EDL fit: {note}" in _old_rule(reworded)  # (the old rule keeps it)
    assert reworded.sigma_residual_notes == (note,)
    kept = _edl_fit_warnings(reworded, remaining)
    assert f"EDL fit: {note}" not in kept and len(kept) == len(reworded.warnings) - 1


def test_the_value_survives_the_nc_and_an_old_file_is_read_by_its_words(remaining, reworded, tmp_path):
    path = tmp_path / "edl.nc"
    ix.write_result(reworded, path)
    back = FitResult.from_xarray(read_netcdf(path))
    assert back.sigma_residual_notes == reworded.sigma_residual_notes and fit_sigma_residual_notes(back) == reworded.sigma_residual_notes
    ds = reworded.to_xarray()
    ds.attrs = {k: v for k, v in ds.attrs.items() if k not in ("warning_tags", "model_misfit", "data_limit_note", "data_limit_hint", "misfit_note", "uneven_noise", "sigma_residual_notes", "model_misfits")}  # (an older version's file: neither the tags nor the note values)
    write_netcdf(ds, path)
    old = FitResult.from_xarray(read_netcdf(path))
    assert old.sigma_residual_notes is None and fit_sigma_residual_notes(old) == ()  # (the words: the reworded note is not found)
