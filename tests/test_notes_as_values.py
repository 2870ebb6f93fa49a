"""Decisions and JSON fields that read impedax's own notes back by their words: a reworded note
changed them without a word. `impedax.compare`'s ``log_evidence_reliable`` looked for notes that
began "Laplace log evidence "; `impedax gap` dropped the sampling's model-comparison notes by
their leads. Each now reads a value carried beside the words (`LaplaceEvidence.reason`,
`Posterior.log_evidence_unreliable_reason`, `Posterior.model_comparison_notes`).

Oracle: the notes as the run wrote them. A run whose notes are reworded (the leads monkeypatched,
WAIC's note replaced by words of this test's own) is told apart as an unchanged run is; the old
rules (the leads as they were, written out here) flip on it. SYNTHETIC R0 + R1 ∥ C1 spectrum
(numpy formula, 1 % noise, seed 7); `LAPLACE_WIDTH_RATIO` 1 makes every width count as off, so
the Laplace evidence always gets its note."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.bayes import Posterior
from impedax.io import read_netcdf

pytestmark = pytest.mark.slow  # (two sampler runs: ~20 s on the shared 2-core machine)

F = np.geomspace(0.1, 1e5, 30)
OLD_EVIDENCE_LEAD = "Laplace log evidence "  # (the leads as the old rules read them)
OLD_COMPARISON_LEADS = (OLD_EVIDENCE_LEAD, "WAIC ")
REWORDED_LEAD = "The Laplace approximation of ln Z "
REWORDED_WAIC = "p_waic is over 2 × the sampled parameters (reworded by the test): do not compare models by this WAIC"


@pytest.fixture(scope="module")
def data():
    rng = np.random.default_rng(7)
    z = 20.0 + 1e3 / (1 + 2j * np.pi * F * 1e3 * 1e-6)
    return ix.make_spectrum(F, z * (1 + 0.01 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2)))


@pytest.fixture(scope="module")
def plain(data):
    return ix.sample("R0 + R1 || C1", data, steps=100, walkers=16, seed=3, progress=False)


@pytest.fixture(scope="module")
def reworded(data):
    """A run whose Laplace note begins `REWORDED_LEAD` and whose WAIC note is `REWORDED_WAIC`."""
    from impedax.fitting.bayes import evidence, sampler

    real_waic = sampler.waic
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(evidence, "LAPLACE_WIDTH_RATIO", 1.0)
        mp.setattr(evidence, "EVIDENCE_NOTE_LEAD", REWORDED_LEAD)
        mp.setattr(sampler, "waic", lambda *a, **k: real_waic(*a, **k)._replace(note=REWORDED_WAIC))
        return ix.sample("R0 + R1 || C1", data, steps=100, walkers=16, seed=3, progress=False)


def _old_reliable(post) -> bool:
    """`compare`'s old ``log_evidence_reliable``: no own warning begins with the old lead."""
    own = [w for w in post.warnings if not w.startswith("least-squares start: ")]
    return bool(np.isfinite(post.log_evidence)) and not any(w.startswith(OLD_EVIDENCE_LEAD) for w in own)


def test_compare_marks_a_reworded_laplace_note_unreliable(plain, reworded):
    (note,) = [w for w in reworded.warnings if w.startswith(REWORDED_LEAD)]
    assert "is unreliable: the posterior is not Gaussian at the MAP" in note  # (the case: the note, in other words)
    assert _old_reliable(reworded) is True  # (the old rule flips: it missed the note)
    rows = ix.compare([plain, reworded]).rows
    assert rows[1]["log_evidence_reliable"] is False and rows[1]["log_evidence_unreliable_reason"] == "not_gaussian"
    assert reworded.log_evidence_unreliable_reason == "not_gaussian" and reworded.summary()["log_evidence_unreliable_reason"] == "not_gaussian"


def test_compare_s_reliability_is_the_notes_on_an_unchanged_run(plain):
    """The normal path: reliable where the run wrote no Laplace note (its reason None), and,
    for the same run told its evidence is not Gaussian in the old words, unreliable as before."""
    assert plain.log_evidence_unreliable_reason is None and not any(w.startswith(OLD_EVIDENCE_LEAD) for w in plain.warnings)
    note = f"{OLD_EVIDENCE_LEAD}is unreliable: the posterior is not Gaussian at the MAP along R1"
    noted = dataclasses.replace(plain, notes=plain.notes + (note,), log_evidence_unreliable_reason="not_gaussian", model_comparison_notes=(note,))
    rows = ix.compare([plain, noted]).rows
    assert [r["log_evidence_reliable"] for r in rows] == [_old_reliable(plain), _old_reliable(noted)] == [True, False]
    assert [r["log_evidence_unreliable_reason"] for r in rows] == [None, "not_gaussian"]


def test_the_reason_and_the_comparison_notes_survive_the_nc(reworded, tmp_path):
    path = tmp_path / "post.nc"
    ix.write_result(reworded, path)
    back = Posterior.from_xarray(read_netcdf(path))
    assert back.log_evidence_unreliable_reason == "not_gaussian"
    assert back.model_comparison_notes == reworded.model_comparison_notes and REWORDED_WAIC in back.model_comparison_notes
    assert ix.compare([back]).rows[0]["log_evidence_reliable"] is False


def test_a_file_without_the_reason_is_read_by_the_notes_leads(plain, tmp_path):
    """A posterior file written before the reason was stored holds it only in the notes' words:
    those (in the words `laplace_evidence` wrote) give it; a file without such a note, none."""
    note = f"{OLD_EVIDENCE_LEAD}undefined: the log-posterior is not peaked at the MAP (a flat or unidentified direction)"
    waic_note = "WAIC is unreliable: p_waic = 9 is over 2 × the 3 sampled parameters"
    cases = ((dataclasses.replace(plain, notes=(note, "another note", waic_note)), "not_peaked", (note, waic_note)), (plain, plain.log_evidence_unreliable_reason, plain.model_comparison_notes))
    for post, reason, comparing in cases:
        ds = post.to_xarray()
        ds.attrs = {k: v for k, v in ds.attrs.items() if k not in ("log_evidence_unreliable_reason", "model_comparison_notes")}
        path = tmp_path / "old.nc"
        ix.io.write_netcdf(ds, path)
        back = Posterior.from_xarray(read_netcdf(path))
        assert back.log_evidence_unreliable_reason == reason and back.model_comparison_notes == comparing


def test_the_gap_analysis_leaves_out_reworded_comparison_notes(plain, reworded):
    """`impedax gap`'s pooled sampling passes on the posterior's own warnings less its
    model-comparison notes, however worded; on an unchanged run, what the leads left."""
    from impedax.models.gap import _gap_sampling_warnings

    old = lambda post: [w for w in post.warnings if not w.startswith(("least-squares start", *OLD_COMPARISON_LEADS))]  # noqa: E731
    assert REWORDED_WAIC in old(reworded) and any(w.startswith(REWORDED_LEAD) for w in old(reworded))  # (the old rule flips)
    kept = _gap_sampling_warnings(reworded)
    assert REWORDED_WAIC not in kept and not any(w.startswith(REWORDED_LEAD) for w in kept)
    assert kept == [w for w in reworded.own_warnings if w not in reworded.model_comparison_notes] and len(reworded.model_comparison_notes) == 2
    assert _gap_sampling_warnings(plain) == old(plain)
