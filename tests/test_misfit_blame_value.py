"""Whether a fit's warnings blame its model (`FitResult.misses_structure`, a batch's per spectrum,
the sampler's start misfit, the σ-scale note it withholds) was read from the words of the misfit
note (`MODEL_MISFIT_MARKS`): a reworded note flipped it. It is a value set where the note is made
(`FitResult.model_misfit`, `BatchFitResult.model_misfits`), stored in the .nc; a file without it
is read by the words.

Oracle: the notes as the fit wrote them, and the same fit with the phrase reworded (the constant
`MODEL_MISSES_STRUCTURE` monkeypatched before the fit). SYNTHETIC data: two arcs,
R0 + R1 ∥ C1 + R2 ∥ C2 (20 Ω, 1 kΩ at τ 1 ms, 1 kΩ at τ 1 s; numpy formula, 0.5 % complex noise,
seed 11) fitted with one arc, R0 + R1 ∥ C1, which misses the second: its rms_rel is far above 5×
what a Kramers–Kronig-consistent model reaches; and one arc's data fitted with one arc (no note)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.least_squares import result as result_module
from impedax.fitting.least_squares.result import FitResult, MODEL_MISSES_STRUCTURE, warnings_blame_model
from impedax.io import read_netcdf

F = np.geomspace(0.01, 1e5, 36)
W = 2 * np.pi * F
ONE_ARC = "R0 + R1 || C1"
REWORDED = "the data hold structure this model lacks"


def _arcs(second: bool, seed: int = 11) -> np.ndarray:
    z = 20.0 + 1e3 / (1 + 1j * W * 1e-3) + (1e3 / (1 + 1j * W * 1.0) if second else 0.0)
    rng = np.random.default_rng(seed)
    return z * (1 + 0.005 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2))


@pytest.fixture(scope="module")
def two_arcs():
    return ix.make_spectrum(F, _arcs(True))


@pytest.fixture(scope="module")
def plain(two_arcs):
    return ix.fit(ONE_ARC, two_arcs)


@pytest.fixture(scope="module")
def reworded(two_arcs):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(result_module, "MODEL_MISSES_STRUCTURE", REWORDED)
        return ix.fit(ONE_ARC, two_arcs)


def test_a_reworded_misfit_note_still_marks_the_model(plain, reworded):
    assert any(w.startswith(MODEL_MISSES_STRUCTURE) for w in plain.warnings)  # (the case, as the fit words it)
    assert any(w.startswith(REWORDED) for w in reworded.warnings) and not warnings_blame_model(reworded.warnings)  # (the old rule flips)
    assert reworded.model_misfit is True and reworded.misses_structure is True
    assert reworded.summary()["misses_structure"] is True


def test_the_value_is_the_words_on_the_normal_path(plain):
    """As the fit words its notes, the value is what the words said: true for the one arc that
    misses the second, false for the right model (no misfit note)."""
    good = ix.fit(ONE_ARC, ix.make_spectrum(F, _arcs(False)))
    assert (plain.model_misfit, plain.misses_structure) == (warnings_blame_model(plain.warnings), True) == (True, True)
    assert good.model_misfit is False and good.model_misfit == warnings_blame_model(good.warnings) and not good.misses_structure


def test_the_sampler_reads_the_start_fit_s_value(reworded):
    from impedax.fitting.bayes.logprob import NoiseModel
    from impedax.fitting.bayes.sampler import _start_misfit

    assert _start_misfit(reworded, NoiseModel.PROPORTIONAL) is True


def test_the_value_survives_the_nc_and_an_old_file_is_read_by_its_words(plain, reworded, tmp_path):
    path = tmp_path / "fit.nc"
    ix.write_result(reworded, path)
    back = FitResult.from_xarray(read_netcdf(path))
    assert back.model_misfit is True and back.misses_structure and back.warnings == reworded.warnings
    for fit, expected in ((reworded, False), (plain, True)):  # (without the attribute: the words, as before)
        ds = fit.to_xarray()
        ds.attrs = {k: v for k, v in ds.attrs.items() if k not in ("warning_tags", "model_misfit", "data_limit_note", "data_limit_hint", "misfit_note", "uneven_noise", "sigma_residual_notes", "model_misfits")}  # (an older version's file: neither the tags nor the note values)
        ix.io.write_netcdf(ds, path)
        old = FitResult.from_xarray(read_netcdf(path))
        assert old.model_misfit is None and old.misses_structure is expected


def test_the_sigma_note_withheld_for_a_blamed_model_is_withheld_however_worded():
    """With the data's σ, a fit whose misfit note blames the model gets no note that σ may
    understate the noise (the model explains the excess): the reworded fit's warnings are the
    plain fit's, the phrase apart."""
    z = _arcs(True)
    data = ix.make_spectrum(F, z, sigma=0.005 * np.abs(z) / np.sqrt(2))
    plain = ix.fit(ONE_ARC, data, weighting="sigma")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(result_module, "MODEL_MISSES_STRUCTURE", REWORDED)
        reworded = ix.fit(ONE_ARC, data, weighting="sigma")
    assert any(w.startswith(MODEL_MISSES_STRUCTURE) for w in plain.warnings) and not any("either σ understates the noise" in w for w in plain.warnings)
    assert [w.replace(REWORDED, MODEL_MISSES_STRUCTURE) for w in reworded.warnings] == list(plain.warnings)


def test_a_batch_marks_its_reworded_spectra(tmp_path):
    """A stack of one arc and two arcs: the second spectrum's model misses structure, by the
    batch's value whatever the words; stored in the .nc; a file without it read by its words."""
    stack = xr.concat([ix.make_spectrum(F, _arcs(False)), ix.make_spectrum(F, _arcs(True))], dim="cell").assign_coords(cell=["one", "two"])
    plain = ix.fit(ONE_ARC, stack)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(result_module, "MODEL_MISSES_STRUCTURE", REWORDED)
        batch = ix.fit(ONE_ARC, stack)
    assert [warnings_blame_model(batch.warnings.get(k, ())) for k in ("cell=one", "cell=two")] == [False, False]  # (the old rule flips)
    assert batch.misses_structure.values.tolist() == plain.misses_structure.values.tolist() == [False, True]
    assert batch.model_misfits == plain.model_misfits == ("cell=two",)
    path = tmp_path / "batch.nc"
    ix.write_result(batch, path)
    back = type(batch).from_xarray(read_netcdf(path))
    assert back.model_misfits == ("cell=two",) and back.misses_structure.values.tolist() == [False, True]
    ds = plain.to_xarray()
    ds.attrs = {k: v for k, v in ds.attrs.items() if k not in ("warning_tags", "model_misfit", "data_limit_note", "data_limit_hint", "misfit_note", "uneven_noise", "sigma_residual_notes", "model_misfits")}
    ix.io.write_netcdf(ds, path)
    old = type(plain).from_xarray(read_netcdf(path))
    assert old.model_misfits is None and old.misses_structure.values.tolist() == [False, True]
