"""What a fit's warnings say is one structure, the tags each warning carries from where it is
made (`notes.Note`, `FitResult.warning_tags`, `BatchFitResult.warning_tags` per spectrum), in
place of seven value fields and output-list parameters; batch and joint fits know per spectrum
what a single fit knows (the data limit the fit, uneven noise, σ notes), and the .nc keeps the
tags, while files written with the values alone, or with none, read back with the same answers.

Oracles: the phrases the notes are built from (`MODEL_MISFIT_MARKS`, `DATA_LIMIT_NOTE`,
`UNEVEN_NOISE_NOTE`, the σ words, the KK test's own sign hint), which on the normal path say the
same as the tags; each spectrum fitted alone against the batch; the file's attributes as written.
SYNTHETIC spectra (numpy formulas, seeded complex noise), 50 points 0.1 Hz – 100 kHz, fitted with
R0 + R1 ∥ C1: a CPE arc (α 0.97, 1 % noise) with the rule that blames the model switched off (as
tests/test_data_limit_value.py: the data limit the fit), two arcs (the model misses one), one arc
with 2.5 % noise below 1 Hz and 0.5 % above (uneven), one arc stored as conj(Z) (the data limit
the fit, with the KK test's sign hint); under σ weighting, σ stated 4× the noise, uneven noise
against a flat σ, and σ as the noise."""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli.common import command_line_words, dataset_in_command_words
from impedax.fitting.least_squares import notes
from impedax.fitting.least_squares import result as result_module
from impedax.fitting.least_squares.result import (DATA_LIMIT_NOTE, MODEL_MISFIT_MARKS, SIGMA_BAND_WORDS, SIGMA_OVERSTATES_WORDS, SIGN_HINT_LEAD, UNEVEN_NOISE_NOTE, FitResult,
                                                  fit_blames_model, fit_blaming_note, fit_data_limit, fit_sigma_residual_notes, fit_uneven_noise, sign_notes_first, with_warnings)
from impedax.io import read_netcdf, write_netcdf

F = np.geomspace(0.1, 1e5, 50)
S = 2j * np.pi * F
ONE = 20 + 1000 / (1 + S * 1e-3)
MODEL = "R0 + R1 || C1"
VALUE_ATTRS = ("model_misfit", "data_limit_note", "data_limit_hint", "misfit_note", "uneven_noise", "sigma_residual_notes")


def _noisy(z, rel, seed):
    rng = np.random.default_rng(seed)
    return z * (1 + rel * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2))


MODULUS = {
    "cpe": _noisy(20 + 1000 / (1 + 1000 * 1e-5 * S**0.97), 0.01 * np.sqrt(2), 0),
    "two": _noisy(ONE + 1000 / (1 + S * 1.0), 0.005, 11),
    "uneven": _noisy(ONE, np.where(F < 1, 0.025, 0.005), 5),
    "flipped": np.conj(_noisy(ONE, 0.005, 3)),
}
EXPECTED = {  # (each case's warnings' tags, by hand from the cases above)
    "cpe": [{notes.MISFIT, notes.DATA_LIMIT}],
    "two": [{notes.MISFIT, notes.MODEL_MISFIT}],
    "uneven": [{notes.UNEVEN_NOISE}],
    "flipped": [{notes.MISFIT, notes.DATA_LIMIT, notes.SIGN_HINT}, {notes.UNEVEN_NOISE}],
}
SIGMA = {"overstated": (_noisy(ONE, 0.005, 2), 0.02), "uneven": (_noisy(ONE, np.where(F < 1, 0.025, 0.005), 5), 0.005), "right": (_noisy(ONE, 0.005, 4), 0.005)}


def _stack(datasets: dict) -> xr.Dataset:
    return xr.concat(list(datasets.values()), dim="case").assign_coords(case=list(datasets))


@pytest.fixture(scope="module")
def modulus():
    data = {k: ix.make_spectrum(F, z) for k, z in MODULUS.items()}
    with pytest.MonkeyPatch.context() as mp:  # (the data limit the CPE arc's fit: the rule that blames the model off)
        mp.setattr(result_module, "MODEL_MISFIT_OVER_CONSISTENT", np.inf)
        mp.setattr(result_module, "MODEL_MISFIT_NOISE_SHARE", np.inf)
        singles = {k: ix.fit(MODEL, d, progress=False) for k, d in data.items()}
        batch = ix.fit(MODEL, _stack(data), progress=False)
    return data, singles, batch


@pytest.fixture(scope="module")
def sigma():
    data = {k: ix.make_spectrum(F, z, sigma=rel * np.abs(z) / np.sqrt(2)) for k, (z, rel) in SIGMA.items()}
    singles = {k: ix.fit(MODEL, d, weighting="sigma", progress=False) for k, d in data.items()}
    return singles, ix.fit(MODEL, _stack(data), weighting="sigma", progress=False), ix.fit(MODEL, _stack(data), weighting="sigma", shared=["R0"], over="case", progress=False)


def _by_words(warning: str) -> set[str]:
    """A warning's tags as its words say them on the normal path (the oracle)."""
    said = {notes.MODEL_MISFIT: any(m in warning for m in MODEL_MISFIT_MARKS), notes.DATA_LIMIT: DATA_LIMIT_NOTE in warning, notes.UNEVEN_NOISE: UNEVEN_NOISE_NOTE in warning,
            notes.SIGMA_RESIDUAL: SIGMA_OVERSTATES_WORDS in warning or SIGMA_BAND_WORDS in warning, notes.SIGN_HINT: f"; {SIGN_HINT_LEAD}" in warning}
    return {tag for tag, holds in said.items() if holds}


def _names(tags) -> set[str]:
    return {t.split("=", 1)[0] for t in tags} - {notes.MISFIT}


def test_a_single_fit_tags_each_warning_with_what_it_says(modulus):
    data, singles, _ = modulus
    for case, fit in singles.items():
        assert [set(t.split("=", 1)[0] for t in tags) for tags in fit.warning_tags] == EXPECTED[case], case
        assert [_names(tags) for tags in fit.warning_tags] == [_by_words(w) for w in fit.warnings], case
    flipped = singles["flipped"]
    hint = f"; {SIGN_HINT_LEAD}{ix.kk_test(data['flipped']).sign_hint}"
    assert flipped.data_limit_note == flipped.warnings[0] and flipped.data_limit_note.endswith(hint) and flipped.data_limit_hint == hint
    assert (flipped.model_misfit, flipped.uneven_noise, flipped.sigma_residual_notes, flipped.misfit_note) == (False, True, (), flipped.warnings[0])
    two = singles["two"]
    assert (two.model_misfit, two.data_limit_note, two.uneven_noise, fit_blaming_note(two)) == (True, "", False, two.warnings[0])
    assert singles["cpe"].data_limit_hint == "" and singles["uneven"].misfit_note == ""


def test_a_batch_knows_per_spectrum_what_each_fit_alone_knows(modulus, sigma):
    _, singles, batch = modulus
    sigma_singles, sigma_batch, _ = sigma
    for fits, stack in ((singles, batch), (sigma_singles, sigma_batch)):
        for case, fit in fits.items():
            key = f"case={case}"
            assert batch_view(stack, key) == (fit.warnings, fit.warning_tags), case
    assert batch.model_misfits == ("case=two",) and batch.misses_structure.values.tolist() == [False, True, False, False]
    assert [_names(t) for t in sigma_batch.warning_tags["case=overstated"]] == [{notes.SIGMA_RESIDUAL}]
    assert [_names(t) for t in sigma_batch.warning_tags["case=uneven"]][0] == {notes.UNEVEN_NOISE, notes.SIGMA_RESIDUAL}


def batch_view(batch, key):
    return batch.warnings.get(key, ()), batch.warning_tags.get(key, ())


def test_a_joint_fit_tags_its_spectra_as_their_words_say(sigma):
    joint = sigma[2]
    assert isinstance(joint, ix.SharedFitResult)
    seen = set()
    for key, warnings in joint.warnings.items():
        assert [_names(t) for t in joint.warning_tags[key]] == [_by_words(w) for w in warnings], key
        seen |= {n for t in joint.warning_tags[key] for n in _names(t)}
    assert {notes.UNEVEN_NOISE, notes.SIGMA_RESIDUAL} <= seen  # (not only a single fit knows them)


def test_tags_survive_the_nc_of_a_fit_a_batch_and_a_joint_fit(modulus, sigma, tmp_path):
    _, singles, batch = modulus
    path = tmp_path / "r.nc"
    for fit in singles.values():
        ix.write_result(fit, path)
        back = FitResult.from_xarray(read_netcdf(path))
        assert back.warning_tags == fit.warning_tags
        assert _answers(back) == _answers(fit)
    for result in (batch, sigma[1], sigma[2]):
        ix.write_result(result, path)
        back = type(result).from_xarray(read_netcdf(path))
        assert dict(back.warning_tags) == dict(result.warning_tags) and back.model_misfits == result.model_misfits
        assert back.misses_structure.values.tolist() == result.misses_structure.values.tolist()


def _answers(fit):
    return (fit.model_misfit, fit.data_limit_note, fit.data_limit_hint, fit.misfit_note, fit.uneven_noise, fit.sigma_residual_notes,
            fit_blames_model(fit), fit_data_limit(fit), fit_uneven_noise(fit), fit_blaming_note(fit), fit_sigma_residual_notes(fit))


def test_an_older_file_reads_back_with_the_same_answers(modulus, sigma, tmp_path):
    """Attributes as the version before the tags wrote them (the values, no ``warning_tags``):
    the same answers and tags; without any of them: None, and the words give the same answers."""
    path = tmp_path / "old.nc"
    for fit in (*modulus[1].values(), *sigma[0].values()):
        ds = fit.to_xarray()
        assert all(k in ds.attrs for k in VALUE_ATTRS)  # (still written, for readers of the older versions)
        ds.attrs = {k: v for k, v in ds.attrs.items() if k != "warning_tags"}
        write_netcdf(ds, path)
        back = FitResult.from_xarray(read_netcdf(path))
        assert _answers(back) == _answers(fit)
        assert [set(t) for t in back.warning_tags] == [set(t) for t in fit.warning_tags]
        ds.attrs = {k: v for k, v in ds.attrs.items() if k not in VALUE_ATTRS}
        write_netcdf(ds, path)
        bare = FitResult.from_xarray(read_netcdf(path))
        assert bare.warning_tags is None and (bare.model_misfit, bare.data_limit_note, bare.uneven_noise, bare.sigma_residual_notes) == (None,) * 4
        assert _answers(bare)[6:] == _answers(fit)[6:]  # (the words, on the normal path)
    for fit in (modulus[1]["flipped"], modulus[1]["two"], sigma[0]["overstated"]):  # (a version that stored some of the values: the words for the others)
        for key in (k for k in VALUE_ATTRS if k != "data_limit_hint"):  # (stored with data_limit_note from the first)
            ds = fit.to_xarray()
            ds.attrs = {k: v for k, v in ds.attrs.items() if k not in ("warning_tags", key, *(("data_limit_hint",) if key == "data_limit_note" else ()))}
            write_netcdf(ds, path)
            assert _answers(FitResult.from_xarray(read_netcdf(path))) == _answers(fit), key
    batch = modulus[2]
    ds = batch.to_xarray()
    ds.attrs = {k: v for k, v in ds.attrs.items() if k != "warning_tags"}  # (a batch's file before the tags: model_misfits alone)
    write_netcdf(ds, path)
    back = type(batch).from_xarray(read_netcdf(path))
    assert back.model_misfits == batch.model_misfits == ("case=two",) and back.misses_structure.values.tolist() == [False, True, False, False]


def test_a_sign_hint_tag_is_worded_as_its_warning_in_a_command_s_file():
    note = "the data limit the fit; hint: raise max_steps"
    ds = xr.Dataset(attrs={"warnings": [note], "warning_tags": [[notes.MISFIT, notes.DATA_LIMIT, notes.sign_hint_tag("; hint: raise max_steps")]]})
    out = dataset_in_command_words(ds, "fit").attrs
    (worded,) = out["warnings"]
    assert worded == command_line_words(note, "fit") != note
    assert out["warning_tags"][0][:2] == [notes.MISFIT, notes.DATA_LIMIT]  # (the tags' names are no Python words)
    assert worded.endswith(notes.tag_detail(out["warning_tags"][0], notes.SIGN_HINT))


def test_tags_go_with_their_warnings(modulus):
    flipped = modulus[1]["flipped"]
    note = flipped.tagged_warnings[0]
    again = pickle.loads(pickle.dumps(note))  # (a batch's blocks under dask)
    assert (again, again.tags) == (note, note.tags) and type(again) is notes.Note
    swapped = with_warnings(flipped, flipped.tagged_warnings[::-1])
    assert swapped.warnings == flipped.warnings[::-1] and swapped.warning_tags == flipped.warning_tags[::-1]
    assert with_warnings(swapped, sign_notes_first(swapped.tagged_warnings)).warning_tags == flipped.warning_tags
    assert _answers(swapped) == _answers(flipped)
    dropped = with_warnings(flipped, flipped.tagged_warnings[1:] + ("a note of the caller",))
    assert (dropped.data_limit_note, dropped.uneven_noise, dropped.warning_tags[-1]) == ("", True, ())
    alone = dataclasses.replace(flipped, warnings=flipped.warnings[:1])  # (the warnings replaced alone: the tags are not theirs)
    assert alone.warning_tags is None and _answers(alone)[6:] == _answers(with_warnings(flipped, flipped.tagged_warnings[:1]))[6:]  # (the words say the same)
