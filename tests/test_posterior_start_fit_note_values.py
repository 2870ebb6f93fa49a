"""A posterior's stored start fit (the ``fit`` attribute of its `.nc`) keeps the values a fit
sets where it makes its notes (`FitResult.model_misfit`, ``data_limit_note``, ``data_limit_hint``,
``uneven_noise``, ``misfit_note``, ``sigma_residual_notes``), as a fit's own `.nc` does; a file without them is read by the
warnings' words (`result.fit_data_limit`, `fit_uneven_noise`, `fit_blaming_note`).

Oracle: the values this test gives the start fit, worded so that the words alone say otherwise
(none holds `DATA_LIMIT_NOTE`, `UNEVEN_NOISE_NOTE` or one of `MODEL_MISFIT_MARKS`), and for the
old file the phrases as the fit words them. SYNTHETIC R0 + R1 ∥ C1 spectrum (numpy formula, 1 %
noise, seed 5), a short chain."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.bayes import Posterior
from impedax.fitting.least_squares import notes
from impedax.fitting.least_squares.result import DATA_LIMIT_NOTE, MODEL_MISSES_STRUCTURE, SIGN_HINT_LEAD, UNEVEN_NOISE_NOTE, fit_blaming_note, fit_data_limit, fit_uneven_noise
from impedax.io import read_netcdf, write_netcdf

F = np.geomspace(0.1, 1e5, 24)
HINT = f"; {SIGN_HINT_LEAD}the signs of Im Z look flipped (this test's words)"
LIMIT = "the data, not only the model, bound this fit (this test's words)" + HINT
UNEVEN = "the weighted residuals differ across the band (this test's words)"
MISFIT = "the model lacks an arc the data hold (this test's words)"
SIGMA = "the residuals lie well below the data's σ (this test's words)"


@pytest.fixture(scope="module")
def post():
    noise = np.array([1, 1j]) @ np.random.default_rng(5).normal(size=(2, F.size)) / np.sqrt(2)
    z = (20.0 + 1e3 / (1 + 2j * np.pi * F * 1e-3)) * (1 + 0.01 * noise)
    return ix.sample("R0 + R1 || C1", ix.make_spectrum(F, z), steps=30, walkers=8, seed=2, progress=False)


def _with_start(post, warnings, tags=None):
    return dataclasses.replace(post, fit=dataclasses.replace(post.fit, warnings=tuple(warnings), warning_tags=tags))


def test_the_start_fit_s_note_values_survive_the_posterior_s_nc(post, tmp_path):
    mine = _with_start(post, (MISFIT, LIMIT, UNEVEN, SIGMA), ((notes.MISFIT, notes.MODEL_MISFIT), (notes.DATA_LIMIT, notes.sign_hint_tag(HINT)), (notes.UNEVEN_NOISE,), (notes.SIGMA_RESIDUAL,)))
    untagged = dataclasses.replace(mine.fit, warning_tags=None)
    assert (fit_data_limit(untagged), fit_uneven_noise(untagged)) == (("", ""), False)  # (the words say otherwise)
    path = tmp_path / "post.nc"
    ix.write_result(mine, path)
    back = Posterior.from_xarray(read_netcdf(path)).fit
    assert (back.model_misfit, back.misfit_note, back.data_limit_note, back.data_limit_hint, back.uneven_noise) == (True, MISFIT, LIMIT, HINT, True)
    assert back.sigma_residual_notes == (SIGMA,)
    assert (fit_data_limit(back), fit_uneven_noise(back), fit_blaming_note(back)) == ((LIMIT, HINT), True, MISFIT)
    clean = _with_start(post, (), ())
    ix.write_result(clean, path)
    back = Posterior.from_xarray(read_netcdf(path)).fit
    assert (back.model_misfit, back.misfit_note, back.data_limit_note, back.data_limit_hint, back.uneven_noise) == (False, "", "", "", False)


def test_a_posterior_file_without_them_is_read_by_the_words(post, tmp_path):
    limit = f"{MODEL_MISSES_STRUCTURE} (test){DATA_LIMIT_NOTE}{HINT}"  # (a note as a fit words one: the phrases)
    uneven = f"{UNEVEN_NOISE_NOTE} (test)"
    ds = _with_start(post, (limit, uneven)).to_xarray()
    ds.attrs["fit"] = {k: v for k, v in ds.attrs["fit"].items() if k not in ("warning_tags", "model_misfit", "data_limit_note", "data_limit_hint", "uneven_noise", "misfit_note", "sigma_residual_notes")}
    path = tmp_path / "old.nc"
    write_netcdf(ds, path)
    back = Posterior.from_xarray(read_netcdf(path)).fit
    assert (back.model_misfit, back.misfit_note, back.data_limit_note, back.uneven_noise, back.sigma_residual_notes) == (None, None, None, None, None)
    assert (fit_data_limit(back), fit_uneven_noise(back), fit_blaming_note(back)) == ((limit, HINT), True, limit)
