"""The sampler names the noise model as WAIC's cause where the least-squares start's residuals
are uneven under one relative noise level (`sampler._start_misfit`). It looked for
`UNEVEN_NOISE_NOTE` in the start fit's warnings: a reworded note made WAIC blame the chain
instead. The fit carries it as a value set where the note is made (`FitResult.uneven_noise`),
stored in the .nc; a fit without it (a file written without it, one built by hand) is read by
the words.

Oracle: the notes as the fit wrote them, and the same fit with the phrase reworded (the
constant monkeypatched in `least_squares.result` before the fit; `sampler` keeps its own import
of the old words). SYNTHETIC data: R0 + R1 ∥ CPE1 (20 Ω, 1 kΩ, Q = 1e-4, α = 0.9) with complex
noise of 2.5 % below 1 Hz and 0.5 % above (seed 5), fitted with the same circuit: no misfit
note, residuals over 4× larger at 0.14–1.4 Hz; and the same circuit with 0.5 % everywhere."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.bayes.evidence import START_UNEVEN_NOISE
from impedax.fitting.bayes.logprob import NoiseModel
from impedax.fitting.bayes.sampler import _start_misfit
from impedax.fitting.least_squares import result as result_module
from impedax.fitting.least_squares.result import UNEVEN_NOISE_NOTE, FitResult, fit_uneven_noise
from impedax.io import read_netcdf

F = np.geomspace(0.01, 1e5, 50)
S = 2j * np.pi * F
TRUTH = 20 + 1000 / (1 + 1000 * 1e-4 * S**0.9)
MODEL = "R0 + R1 || CPE1"
REWORDED = "the standard errors take the weighted noise to be the same at every frequency"


def _data(uneven: bool):
    rng = np.random.default_rng(5)
    rel = np.where(F < 1, 0.025, 0.005) if uneven else 0.005
    return ix.make_spectrum(F, TRUTH * (1 + rel * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2)))


@pytest.fixture(scope="module")
def plain():
    return ix.fit(MODEL, _data(True))


@pytest.fixture(scope="module")
def reworded():
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(result_module, "UNEVEN_NOISE_NOTE", REWORDED)
        return ix.fit(MODEL, _data(True))


def test_a_reworded_uneven_noise_note_still_names_the_noise_model(plain, reworded):
    assert any(REWORDED in w for w in reworded.warnings) and not any(UNEVEN_NOISE_NOTE in w for w in reworded.warnings)
    old = SimpleNamespace(warnings=reworded.warnings, weighting=reworded.weighting, chi2_red=reworded.chi2_red)  # (no value: the words)
    assert _start_misfit(old, NoiseModel.PROPORTIONAL) is False  # (the old rule: the chain is blamed)
    assert reworded.uneven_noise is True
    assert _start_misfit(reworded, NoiseModel.PROPORTIONAL) == _start_misfit(plain, NoiseModel.PROPORTIONAL) == START_UNEVEN_NOISE
    assert _start_misfit(reworded, NoiseModel.SIGMA) is False  # (under the data's σ it is no cause)


def test_the_value_is_the_words_on_the_normal_path(plain):
    even = ix.fit(MODEL, _data(False))
    assert (plain.uneven_noise, plain.model_misfit) == (True, False) and any(UNEVEN_NOISE_NOTE in w for w in plain.warnings)
    assert even.uneven_noise is False and not any(UNEVEN_NOISE_NOTE in w for w in even.warnings)
    assert _start_misfit(even, NoiseModel.PROPORTIONAL) is False


def test_the_value_survives_the_nc_and_an_old_file_is_read_by_its_words(plain, reworded, tmp_path):
    path = tmp_path / "fit.nc"
    ix.write_result(reworded, path)
    back = FitResult.from_xarray(read_netcdf(path))
    assert back.uneven_noise is True and _start_misfit(back, NoiseModel.PROPORTIONAL) == START_UNEVEN_NOISE
    for fit, expected in ((reworded, False), (plain, True)):  # (without the attribute: the words)
        ds = fit.to_xarray()
        ds.attrs = {k: v for k, v in ds.attrs.items() if k not in ("warning_tags", "model_misfit", "data_limit_note", "data_limit_hint", "misfit_note", "uneven_noise", "sigma_residual_notes", "model_misfits")}  # (an older version's file: neither the tags nor the note values)
        ix.io.write_netcdf(ds, path)
        old = FitResult.from_xarray(read_netcdf(path))
        assert old.uneven_noise is None and fit_uneven_noise(old) is expected
