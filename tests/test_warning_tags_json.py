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
import json
import pickle

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main
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


def _json(capsys, *argv) -> dict:
    code = main([str(a) for a in argv] + ["--json", "-q"])
    out, err = capsys.readouterr()
    assert code == 0, err
    return json.loads(out)


def test_cases_warn_as_intended(fits):
    """The cases hold what the tests below read: the two-arc fit blames the model, the uneven one
    says uneven residuals, each in one warning (by the words alone)."""
    assert [_said(w) for w in fits["two"].warnings] == [{notes.MODEL_MISFIT}]
    assert [_said(w) for w in fits["uneven"].warnings] == [{notes.UNEVEN_NOISE}]


def test_a_single_fit_s_json_gives_each_warning_s_tags(files, fits, capsys, tmp_path):
    for case in CASES:
        out = tmp_path / f"{case}.json"
        printed = _json(capsys, "fit", files[case], "--model", MODEL, "--out", out)
        assert len(printed["warning_tags"]) == len(printed["warnings"]) >= 1
        assert [_named(t) for t in printed["warning_tags"]] == [_said(w) for w in printed["warnings"]], case
        assert printed["warning_tags"] == [list(t) for t in fits[case].warning_tags]  # (the Python API's, as lists)
        assert json.loads(out.read_text(encoding="utf-8"))["warning_tags"] == printed["warning_tags"]  # (--out FILE.json is the --json document)
    blamed = _json(capsys, "fit", files["two"], "--model", MODEL)
    assert any(notes.MODEL_MISFIT in t for t in blamed["warning_tags"]) and blamed["misses_structure"] is True


def test_a_batch_s_json_gives_each_spectrum_s_tags_beside_its_warnings(files, fits, capsys):
    printed = _json(capsys, "fit", files["stack"], "--model", MODEL)
    rows = {row["case"]: row for row in printed["spectra"]}
    assert set(rows) == set(CASES)
    for case, row in rows.items():
        assert len(row["warning_tags"]) == len(row["warnings"])
        assert [_named(t) for t in row["warning_tags"]] == [_said(w) for w in row["warnings"]], case
        assert [_named(t) for t in row["warning_tags"]] == [_named(t) for t in fits[case].warning_tags], case  # (as the spectrum fitted alone)
    assert [any(notes.MODEL_MISFIT in t for t in rows[c]["warning_tags"]) for c in CASES] == [True, False]
    assert "warning_tags" not in printed  # (per spectrum only, as the batch gives its warnings per spectrum; the top level's are their distinct union)


@pytest.mark.slow  # (~10–20 s: two models on one spectrum, then on two)
def test_compare_s_json_gives_each_model_s_tags(files, capsys):
    printed = _json(capsys, "compare", files["two"], "--model", MODEL, "--model", "R0 + R1 || C1 + R2 || C2")
    by_label = {m["label"]: m for m in printed["models"]}
    for model in by_label.values():
        assert len(model["warning_tags"]) == len(model["warnings"])
        assert [_named(t) for t in model["warning_tags"]] == [_said(w) for w in model["warnings"]]
    assert any(notes.MODEL_MISFIT in t for t in by_label[MODEL]["warning_tags"])
    batch = _json(capsys, "compare", files["stack"], "--model", MODEL, "--model", "R0 + R1 || C1 + R2 || C2")
    for spectrum in batch["spectra"]:
        for model in spectrum["models"]:
            assert len(model["warning_tags"]) == len(model["warnings"])
            assert [_named(t) for t in model["warning_tags"]] == [_said(w) for w in model["warnings"]]
    two = next(s for s in batch["spectra"] if s["case"] == "two")
    assert any(notes.MODEL_MISFIT in t for m in two["models"] if m["label"] == MODEL for t in m["warning_tags"])


@pytest.mark.slow  # (~5–8 s: the start fit and a short chain)
def test_sample_s_json_tags_its_start_fit_s_warnings(files, fits, capsys):
    printed = _json(capsys, "sample", files["two"], "--model", MODEL, "--steps", "200", "--walkers", "16")
    assert len(printed["warning_tags"]) == len(printed["warnings"])
    start = [(w, t) for w, t in zip(printed["warnings"], printed["warning_tags"]) if w.startswith("least-squares start: ")]
    assert [t for _, t in start] == [list(t) for t in fits["two"].warning_tags]
    assert all(t == [] for w, t in zip(printed["warnings"], printed["warning_tags"]) if not w.startswith("least-squares start: "))  # (the sampler's own: none)


def test_a_fit_without_known_tags_gives_those_its_words_say(fits):
    """A fit read from a file written without tags (tags None): the JSON's tags are its words'."""
    for fit in fits.values():
        bare = dataclasses.replace(fit, warning_tags=None)
        assert bare.warning_tags is None
        assert [_named(t) for t in bare.summary()["warning_tags"]] == [_said(w) for w in fit.warnings]


# --- tags that cannot go stale ------------------------------------------------------------------


def test_replacing_a_fit_s_warnings_by_other_words_keeps_no_old_tags(fits):
    two = fits["two"]
    assert two.model_misfit is True
    other = dataclasses.replace(two, warnings=("a caller's note",))  # (as many warnings as before, other words)
    assert other.warning_tags is None and other.model_misfit is None and fit_blames_model(other) is False
    assert [_named(t) for t in other.summary()["warning_tags"]] == [set()]
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
    assert [row["warning_tags"] for row in other.summary()["spectra"]] == [[[]] * len(v) for v in reworded.values()]
    notes_swapped = {k: tuple(batch.tagged_warnings(k))[::-1] for k in batch.warnings}
    swapped = dataclasses.replace(batch, warnings=notes_swapped)
    assert dict(swapped.warning_tags) == {k: tuple(v)[::-1] for k, v in batch.warning_tags.items()}
    assert dict(dataclasses.replace(batch, elapsed_s=0.0).warning_tags) == dict(batch.warning_tags)
    kept = batch_with_warnings(batch, {k: (notes.Note("reworded", tags),) for k, (tags,) in batch.warning_tags.items()})  # (same tags, other words)
    assert kept.model_misfits == ("case=two",)


@pytest.mark.slow
def test_a_posterior_s_summary_tags_its_start_fit_s_warnings_in_python(files, fits):
    """`Posterior.summary()` (what `sample --json` prints) holds ``warning_tags`` parallel to its
    ``warnings``: none for the sampling's own, the start fit's for its "least-squares start: …"."""
    posterior = ix.sample(MODEL, ix.load(files["two"]), steps=200, walkers=16, seed=0)
    summary = posterior.summary()
    assert len(summary["warning_tags"]) == len(summary["warnings"])
    start = [t for w, t in zip(summary["warnings"], summary["warning_tags"]) if w.startswith("least-squares start: ")]
    assert start == [list(t) for t in posterior.fit.warning_tags]
    assert all(t == [] for w, t in zip(summary["warnings"], summary["warning_tags"]) if not w.startswith("least-squares start: "))
