"""WAIC of a chain too short to estimate τ (fewer than 50 kept draws per walker, the chain-length
warning's rule) was printed with nothing beside it, though such draws have not yet spread over the
posterior and p_waic is off (2026-12-06). The report's evidence line, the JSON (key ``waic_note``,
added) and the notebook view now say so beside it, and what to run. Oracle: a SYNTHETIC
R0 + R1 ∥ C1 spectrum (numpy formula) and the run's own lengths: 40 steps keep 40 − 10 = 30 draws
per walker (burn a quarter), below 50; 100 steps keep 75, enough to estimate τ."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

F = np.geomspace(0.1, 1e5, 30)
pytestmark = pytest.mark.slow  # (the first run compiles the sampler: ~10 s on the shared 2-core machine)


@pytest.fixture(scope="module")
def spectrum(tmp_path_factory):
    rng = np.random.default_rng(7)
    z = 20.0 + 1e3 / (1 + 2j * np.pi * F * 1e3 * 1e-6)
    z = z * (1 + 0.01 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2))
    path = tmp_path_factory.mktemp("waic") / "rc.csv"
    ix.save(ix.make_spectrum(F, z), path)
    return path


def _run(capsys, path, steps, *extra):
    assert main(["sample", str(path), "--model", "R0 + R1 || C1", "--steps", str(steps), "--walkers", "16", "--quiet", *extra]) == 0
    return capsys.readouterr().out


def test_waic_of_a_chain_too_short_for_tau_says_so_beside_it(spectrum):
    data = ix.load(spectrum)
    post = ix.sample("R0 + R1 || C1", data, steps=40, walkers=16, progress=False)
    assert post.n_draws == 30
    lines = post.report().splitlines()
    evidence = next(i for i, line in enumerate(lines) if line.startswith("evidence"))
    assert "WAIC = " in lines[evidence]
    assert lines[evidence + 1] == f"           {post.waic_note}"
    assert post.waic_note.startswith("WAIC and p_waic are from a chain too short to trust (30 draws per walker after burn-in") and "steps='auto'" in post.waic_note
    assert post.summary()["waic_note"] == post.waic_note and "too short to trust" in post._repr_html_()
    # 100 steps keep 75 draws per walker: τ can be estimated, no note
    long = ix.sample("R0 + R1 || C1", data, steps=100, walkers=16, progress=False)
    assert long.n_draws == 75 and long.waic_note == "" and long.summary()["waic_note"] is None
    assert "too short to trust" not in long.report() and not any("too short to estimate τ" in w for w in long.warnings)  # (the chain-length warning's rule agrees)


def test_the_command_line_says_it_in_its_words(capsys, spectrum):
    text = _run(capsys, spectrum, 40).splitlines()
    evidence = next(i for i, line in enumerate(text) if line.startswith("evidence"))
    assert text[evidence + 1].startswith("           WAIC and p_waic are from a chain too short to trust") and "(--steps auto, the default" in text[evidence + 1]
    doc = json.loads(_run(capsys, spectrum, 40, "--json"))
    assert doc["draws"] == 30 and doc["waic_note"].startswith("WAIC and p_waic are from a chain too short to trust") and "(--steps auto, the default" in doc["waic_note"]
    assert {"waic", "p_waic"} <= set(doc)  # (keys only added)


def test_a_thinned_chain_too_short_for_tau_says_to_thin_less(capsys, spectrum):
    """2000 steps thinned by 40 kept 37 draws per walker: too few to estimate τ, though long in
    steps; the chain-length warning and the WAIC note said only "run more steps" and blamed draws
    not yet spread (2026-12-06). Both now name the thinning and say to thin less. Here 400 steps,
    burn 100, thin 10: (400 − 100) / 10 = 30 draws per walker."""
    post = ix.sample("R0 + R1 || C1", ix.load(spectrum), steps=400, thin=10, walkers=16, progress=False)
    assert post.n_draws == 30
    warning = next(w for w in post.warnings if "too short to estimate τ" in w)
    assert "(30 draws per walker after burn-in and thinning by 10;" in warning and warning.endswith("thin less (thin=) or run more steps")
    assert "30 draws per walker after burn-in and thinning by 10, too few to estimate τ" in post.waic_note and "thin less (thin=) or run more steps" in post.waic_note
    text = _run(capsys, spectrum, 400, "--thin", "10")
    assert "thin less (--thin) or run more steps" in text and "thin=" not in text


def test_compare_says_which_waic_is_one_to_compare_models_by(spectrum):
    """`impedax.compare` of posteriors reported ``log_evidence_reliable`` but nothing of WAIC, and
    its table sent a model with an unreliable log evidence to "compare these models by WAIC" even
    when that WAIC came from a chain too short to trust (2026-12-06). Each row now has
    ``waic_reliable`` (added, also in the JSON): false for the 40-step chain (30 draws per walker,
    below 50, the rule of the note beside WAIC), true for the 100-step one (75)."""
    from impedax.io.export import to_jsonable

    data = ix.load(spectrum)
    short = ix.sample("R0 + R1 || C1", data, steps=40, walkers=16, progress=False)
    long = ix.sample("R0 + R1 || C1", data, steps=100, walkers=16, progress=False)
    assert (short.n_draws, long.n_draws) == (30, 75) and short.waic_note and not long.waic_note
    assert not any(w.startswith("WAIC ") for w in long.warnings)  # (nor is the long one's flagged otherwise)
    c = ix.compare([short, long])
    assert [r["waic_reliable"] for r in c.rows] == [False, True]
    doc = json.loads(json.dumps(to_jsonable(c.summary()), allow_nan=False))
    assert [m["waic_reliable"] for m in doc["models"]] == [False, True] and "log_evidence_reliable" in doc["models"][0]  # (keys only added)
    table = c.table().splitlines()
    short_row = next(line for line in table if line.startswith(c.rows[0]["label"] + " "))
    long_row = next(line for line in table if line.startswith(c.rows[1]["label"] + " "))
    assert f"{short.waic:.2f}*" in short_row.split() and f"{long.waic:.2f}" in long_row.split()
    assert any(line.startswith("* WAIC undefined, from a chain too short to estimate τ") and line.endswith(f"{c.rows[0]['label']}; do not compare models by it") for line in table)


def test_the_evidence_note_does_not_send_a_short_chain_to_its_waic():
    """REAL exampleDataGamry.DTA with R0 + R1 || CPE1 and 40 steps (30 draws per walker): the
    report said "do not compare models by this WAIC" beside WAIC and, in the Laplace evidence's
    warning, "Compare models by WAIC" (2026-12-06). The note now sends a chain that short to a
    longer chain; 300 steps (225 draws per walker) keep the WAIC remedy."""
    from pathlib import Path

    data = ix.load(Path(__file__).parent / "fixtures" / "real" / "exampleDataGamry.DTA")
    short = ix.sample("R0 + R1 || CPE1", data, steps=40, seed=1, progress=False)
    (note,) = [w for w in short.warnings if w.startswith("Laplace log evidence is unreliable")]
    assert short.waic_note and "Compare models by WAIC" not in note
    assert note.endswith("WAIC, from a chain too short to estimate τ, is no score to compare models by either (see the note beside it): run a longer chain, or fix or bound that parameter")
    longer = ix.sample("R0 + R1 || CPE1", data, steps=300, seed=1, progress=False)
    (note,) = [w for w in longer.warnings if w.startswith("Laplace log evidence is unreliable")]
    assert not longer.waic_note and note.endswith("Compare models by WAIC, or fix or bound that parameter")


def test_the_evidence_note_does_not_send_users_to_a_waic_its_own_warning_calls_unreliable(spectrum, monkeypatch):
    """A posterior whose Laplace evidence is unreliable and whose WAIC is too carried both
    "Compare models by WAIC" and "Do not compare models by this WAIC" (2026-12-06). Both are
    forced here on a real run of SYNTHETIC data (the pair is rare on real files: REAL Gamry and
    BioLogic runs gave one or the other): every width counts as off (`LAPLACE_WIDTH_RATIO` 1) and
    WAIC's p_waic is over 2 × the 4 sampled parameters, its warning in words of the test's own
    (the remedy reads `waic_doubts` of the numbers, not the words, since 2026-12-07); the posterior
    keeps the evidence's note without the WAIC remedy."""
    from impedax.fitting.bayes import evidence, sampler
    from impedax.fitting.bayes.evidence import EVIDENCE_NOTE_LEAD

    waic_note = "p_waic over 2 × the sampled parameters (reworded). Do not compare models by this WAIC"
    real_waic = sampler.waic
    monkeypatch.setattr(evidence, "LAPLACE_WIDTH_RATIO", 1.0)
    monkeypatch.setattr(sampler, "waic", lambda *a, **k: real_waic(*a, **k)._replace(p_waic=9.0, note=waic_note))
    post = ix.sample("R0 + R1 || C1", ix.load(spectrum), steps=100, walkers=16, progress=False)
    (note,) = [w for w in post.warnings if w.startswith(EVIDENCE_NOTE_LEAD)]
    assert "Compare models by WAIC" not in note and note.endswith("WAIC is no score to compare models by either (see its warning): fix or bound that parameter")
    assert waic_note in post.warnings and post.waic_unreliable_reason == "high_p_waic"
