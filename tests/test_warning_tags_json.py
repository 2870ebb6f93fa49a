"""A fit's warning tags (`notes.WARNING_TAGS`) in the JSON of the commands that give a fit's own
warnings (``warning_tags``, parallel to ``warnings``: `impedax fit` single and per spectrum of a
batch, `compare`'s models, `sample`'s start fit), so that a program asks "does a warning blame
the model" without reading words; and tags that cannot go stale: `dataclasses.replace` of
``warnings`` with other words keeps no tags of the old ones (the words decide), `notes.Note`s
bring their own.

Oracles: the phrases the notes are built from (`MODEL_MISFIT_MARKS`, `UNEVEN_NOISE_NOTE`), which
on the normal path say what the tags say, and the Python API's `FitResult.warning_tags`.
SYNTHETIC spectra (numpy formulas written here, seeded complex noise), 50 points 0.1 Hz – 100 kHz,
fitted with R0 + R1 ∥ C1: two arcs (0.5 % noise; the model misses one: a warning that blames the
model) and one arc with 2.5 % noise below 1 Hz and 0.5 % above (uneven residuals)."""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.least_squares import notes
from impedax.fitting.least_squares.batch import batch_with_warnings
from impedax.fitting.least_squares.result import MODEL_MISFIT_MARKS, UNEVEN_NOISE_NOTE, fit_blames_model, with_warnings

F = np.geomspace(0.1, 1e5, 50)
S = 2j * np.pi * F
ONE = 20 + 1000 / (1 + S * 1e-3)  # R0 = 20 Ω, R1 = 1 kΩ, τ = 1 ms
MODEL = "R0 + R1 || C1"


def _noisy(z, rel, seed):
    rng = np.random.default_rng(seed)
    return z * (1 + rel * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2))


CASES = {"two": _noisy(ONE + 1000 / (1 + S * 1.0), 0.005, 11), "uneven": _noisy(ONE, np.where(F < 1, 0.025, 0.005), 5)}


def _said(warning: str) -> set[str]:
    """What a warning's words say, as tag names (the oracle; on the normal path the tags agree)."""
    return {tag for tag, holds in ((notes.MODEL_MISFIT, any(m in warning for m in MODEL_MISFIT_MARKS)), (notes.UNEVEN_NOISE, UNEVEN_NOISE_NOTE in warning)) if holds}


def _named(tags) -> set[str]:
    return {t.split("=", 1)[0] for t in tags} & {notes.MODEL_MISFIT, notes.UNEVEN_NOISE}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    where = tmp_path_factory.mktemp("tags")
    paths = {}
    for case, z in CASES.items():
        paths[case] = where / f"{case}.csv"
        ix.save(ix.make_spectrum(F, z), paths[case])
    stack = xr.concat([ix.make_spectrum(F, z) for z in CASES.values()], dim="case").assign_coords(case=list(CASES))
    paths["stack"] = where / "cases.nc"
    ix.save(stack, paths["stack"])
    return paths


@pytest.fixture(scope="module")
def fits():
    return {case: ix.fit(MODEL, ix.make_spectrum(F, z), progress=False) for case, z in CASES.items()}


# --- tags that cannot go stale ------------------------------------------------------------------


def test_replacing_a_fit_s_warnings_by_other_words_keeps_no_old_tags(fits):
    two = fits["two"]
    assert two.model_misfit is True
    other = dataclasses.replace(two, warnings=("a caller's note",))  # (as many warnings as before, other words)
    assert other.warning_tags is None and other.model_misfit is None and fit_blames_model(other) is False
    again = dataclasses.replace(pickle.loads(pickle.dumps(two)), warnings=("a caller's note",))  # (a pickled fit alike)
    assert again.warning_tags is None


def test_replaced_notes_bring_their_tags_and_unchanged_warnings_keep_theirs(fits):
    two, uneven = fits["two"], fits["uneven"]
    both = with_warnings(two, two.tagged_warnings + uneven.tagged_warnings)
    swapped = dataclasses.replace(both, warnings=both.tagged_warnings[::-1])  # (`notes.Note`s, reordered)
    assert swapped.warnings == both.warnings[::-1] and swapped.warning_tags == both.warning_tags[::-1]
    assert dataclasses.replace(both, warnings=both.warnings[::-1]).warning_tags is None  # (plain texts reordered: the words)
    assert dataclasses.replace(both, chi2=1.0).warning_tags == both.warning_tags  # (warnings unchanged)
    assert dataclasses.replace(both, warnings=tuple(both.warnings)).warning_tags == both.warning_tags
    given = ((notes.UNEVEN_NOISE,), (notes.MISFIT, notes.MODEL_MISFIT))
    assert dataclasses.replace(both, warnings=both.warnings[::-1], warning_tags=given).warning_tags == given  # (new tags given with the new warnings)
    reworded = with_warnings(two, (notes.Note("the model misses structure, in other words", two.warning_tags[0]),))  # (same tags, other words: with_warnings sets them)
    assert reworded.warning_tags == two.warning_tags and reworded.model_misfit is True


def test_a_batch_s_replaced_warnings_keep_no_old_tags(fits):
    batch = ix.fit(MODEL, xr.concat([ix.make_spectrum(F, z) for z in CASES.values()], dim="case").assign_coords(case=list(CASES)), progress=False)
    assert batch.model_misfits == ("case=two",)
    reworded = {k: tuple(f"a caller's note {i}" for i, _ in enumerate(v)) for k, v in batch.warnings.items()}  # (as many per spectrum, other words)
    other = dataclasses.replace(batch, warnings=reworded)
    assert other.warning_tags is None and other.model_misfits is None and other.misses_structure.values.tolist() == [False, False]
    notes_swapped = {k: tuple(batch.tagged_warnings(k))[::-1] for k in batch.warnings}
    swapped = dataclasses.replace(batch, warnings=notes_swapped)
    assert dict(swapped.warning_tags) == {k: tuple(v)[::-1] for k, v in batch.warning_tags.items()}
    assert dict(dataclasses.replace(batch, elapsed_s=0.0).warning_tags) == dict(batch.warning_tags)
    kept = batch_with_warnings(batch, {k: (notes.Note("reworded", tags),) for k, (tags,) in batch.warning_tags.items()})  # (same tags, other words)
    assert kept.model_misfits == ("case=two",)
