"""`compare` replaces a fit's note that the data limit it (`DATA_LIMIT_NOTE`) where another model
fits the same data significantly better, keeping the note's KK sign hint. It found that note by
the phrase in the words and the hint by "; hint: " (`SIGN_HINT_LEAD`): a reworded note was left
in place, a reworded hint lead dropped the hint. The fit carries both as values set where the
note is made (`FitResult.data_limit_note`, `FitResult.data_limit_hint`), stored in the .nc; a
file without them is read by the words.

Oracle: the notes as the fit wrote them, and the same fit with the phrases reworded (the
constants monkeypatched in `least_squares.result` before the fit; `comparison` keeps its own
import of the old words, as any reader of the words would). SYNTHETIC data: R0 + R1 ∥ CPE1
(20 Ω, 1 kΩ, Q = 1e-5, α = 0.97) with 1 % complex noise (seed 0), fitted with R0 + R1 ∥ C1 and
R0 + R1 ∥ CPE1, the KK rule that would blame the simple model set out of reach (as
test_compare_misfit_note.py's fixture); and R0 + R1 ∥ C1 (20 Ω, 1 kΩ ∥ 10 µF, 0.5 % noise,
seed 3) stored conjugated, whose note ends with the KK test's sign hint."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.comparison import _model_not_data, _sign_hint_of
from impedax.fitting.least_squares import result as result_module
from impedax.fitting.least_squares.result import DATA_LIMIT_NOTE, SIGN_HINT_LEAD, FitResult, fit_data_limit
from impedax.io import read_netcdf

FREQ = np.geomspace(0.1, 1e5, 50)
S = 2j * np.pi * FREQ
TRUTH = 20 + 1000 / (1 + 1000 * 1e-5 * S**0.97)
_RNG = np.random.default_rng(0)
Z = TRUTH * (1 + 0.01 * (_RNG.normal(size=FREQ.size) + 1j * _RNG.normal(size=FREQ.size)))
MODELS = ("R0 + R1 || C1", "R0 + R1 || CPE1")
REWORDED = "what limits this fit is the data's noise or drift as much as the model (see impedax kk)"
REWORDED_LEAD = "a way out: "


def _fits(**words):
    data = ix.make_spectrum(FREQ, Z)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(result_module, "MODEL_MISFIT_OVER_CONSISTENT", np.inf)
        mp.setattr(result_module, "MODEL_MISFIT_NOISE_SHARE", np.inf)
        for name, text in words.items():
            mp.setattr(result_module, name, text)
        return [ix.fit(m, data) for m in MODELS]


@pytest.fixture(scope="module")
def plain():
    return _fits()


@pytest.fixture(scope="module")
def reworded():
    return _fits(DATA_LIMIT_NOTE=REWORDED)


def test_compare_replaces_a_reworded_data_limit_note(plain, reworded):
    simple = reworded[0]
    assert any(REWORDED in w for w in simple.warnings) and not any(DATA_LIMIT_NOTE in w for w in simple.warnings)  # (the old rule finds no note)
    assert simple.data_limit_note in simple.warnings and REWORDED in simple.data_limit_note
    c = ix.compare(reworded)
    assert not any(REWORDED in w for w in c.fits[0].warnings)
    (note,) = [w for w in c.fits[0].warnings if "fits these data significantly better" in w]
    assert "the misfit is this model's, not the data's noise" in note
    assert c.fits[0].model_misfit is True and c.fits[0].data_limit_note == ""
    # the plain fits decide the same: the same note, whatever the words of the one it replaced
    assert [w for w in ix.compare(plain).fits[0].warnings if "significantly better" in w] == [note]


def test_the_value_is_the_words_on_the_normal_path(plain):
    simple, right = plain
    (by_words,) = [w for w in simple.warnings if DATA_LIMIT_NOTE in w]
    assert fit_data_limit(simple) == (by_words, "") and simple.data_limit_note == by_words
    assert right.data_limit_note == "" and not any(DATA_LIMIT_NOTE in w for w in right.warnings)


def test_the_sign_hint_is_kept_however_its_lead_is_worded():
    """Conjugated data: the note that the data limit the fit ends with the KK test's sign hint;
    with its lead reworded, the old rule (`_sign_hint_of`) loses it, the value keeps it."""
    omega = 2 * np.pi * np.geomspace(0.1, 1e5, 60)
    rng = np.random.default_rng(3)
    truth = 20 + 1000 / (1 + 1j * omega * 1000 * 1e-5)
    flipped = np.conj(truth * (1 + 0.005 * (rng.standard_normal(omega.size) + 1j * rng.standard_normal(omega.size)) / math.sqrt(2)))
    data = ix.make_spectrum(omega / (2 * np.pi), flipped)
    hint = ix.kk_test(data).sign_hint
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(result_module, "SIGN_HINT_LEAD", REWORDED_LEAD)
        fit = ix.fit("R0 + R1 || C1", data)
    assert fit.data_limit_note.endswith(f"; {REWORDED_LEAD}{hint}") and fit.data_limit_hint == f"; {REWORDED_LEAD}{hint}"
    assert _sign_hint_of(fit.data_limit_note) == ""  # (the old rule loses the hint)
    better = replace(fit, z_model=flipped + (fit.z_model - flipped) / 2)  # (half the rms_rel, a lower AIC: `CLEARLY_LOWER_RMS`)
    replaced = _model_not_data(fit, 0, [fit, better], ["a", "b"], [], [0.0, -61.0])
    (note,) = [w for w in replaced.warnings if "fits these data significantly better" in w]
    assert note.endswith(f"; {REWORDED_LEAD}{hint}") and fit.data_limit_note not in replaced.warnings


def test_the_values_survive_the_nc_and_an_old_file_is_read_by_its_words(plain, reworded, tmp_path):
    path = tmp_path / "fit.nc"
    ix.write_result(reworded[0], path)
    back = FitResult.from_xarray(read_netcdf(path))
    assert (back.data_limit_note, back.data_limit_hint) == (reworded[0].data_limit_note, "")
    assert _model_not_data(back, 0, [back, reworded[1]], list(MODELS), [], [reworded[0].aic, reworded[1].aic]).model_misfit is True
    for fit, found in ((reworded[0], ""), (plain[0], plain[0].data_limit_note)):  # (without the attributes: the words)
        ds = fit.to_xarray()
        ds.attrs = {k: v for k, v in ds.attrs.items() if k not in ("warning_tags", "model_misfit", "data_limit_note", "data_limit_hint", "misfit_note", "uneven_noise", "sigma_residual_notes", "model_misfits")}  # (an older version's file: neither the tags nor the note values)
        ix.io.write_netcdf(ds, path)
        old = FitResult.from_xarray(read_netcdf(path))
        assert old.data_limit_note is None and fit_data_limit(old) == (found, "")
