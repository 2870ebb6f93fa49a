"""When refine's report names diagnose's verdict (`refinement._diagnose_verdict_words`): where the
two read as contradictory, not where refine did what diagnose proposed. Stand-in results carry
only what the sentence reads (verdicts, the start's model, the steps, the final fit)."""

from types import SimpleNamespace

import pytest

from impedax.fitting.diagnosis.diagnosis import Verdict
from impedax.fitting.diagnosis.refinement import _diagnose_verdict_words


def _first(verdict):
    return SimpleNamespace(verdict=verdict, baseline=SimpleNamespace(model="R0 + R1 || C1"), best=SimpleNamespace(effect="extra_relaxation"))


def _refinement(verdict, n_steps=2):
    final = SimpleNamespace(model="R0 + (R1 + R_relax || CPE_relax) || C1", rms_rel=0.05)
    return SimpleNamespace(verdict=verdict, steps=[None] * (n_steps + 1), final=final)


def test_an_effect_added_and_judged_adequate_needs_no_sentence():
    assert _diagnose_verdict_words(_refinement(Verdict.ADEQUATE), _first(Verdict.MISSING_EFFECT), 31, restarted=False) is None


@pytest.mark.parametrize("final", [Verdict.DATA_INVALID, Verdict.CONSTRAINT])
def test_an_added_effect_that_ends_elsewhere_names_diagnose_s_proposal(final):
    note = _diagnose_verdict_words(_refinement(final, n_steps=1), _first(Verdict.MISSING_EFFECT), 31, restarted=False)
    assert note.startswith("diagnose of R0 + R1 || C1 (impedax diagnose, with the same options) says MISSING_EFFECT (adding extra_relaxation)")
    assert "after the 1 step that followed" in note


def test_the_same_verdict_needs_no_sentence():
    assert _diagnose_verdict_words(_refinement(Verdict.DATA_INVALID), _first(Verdict.DATA_INVALID), 31, restarted=False) is None


def test_a_refinement_netcdf_holds_diagnose_s_verdict():
    """SYNTHETIC R0 + R1 ∥ C1 (10 Ω, 100 Ω, 1 µF; numpy, 21 points 100 kHz–1 Hz, 0.2 % noise,
    seed 5), refined from its own model: both verdicts adequate, no sentence; the .nc says so."""
    import numpy as np

    import impedax as ix

    f = np.logspace(5, 0, 21)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6)
    rng = np.random.default_rng(5)
    z = z * (1 + 0.002 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    r = ix.refine(ix.make_spectrum(f, z), "R0 + R1 || C1")
    attrs = r.to_xarray().attrs
    assert attrs["diagnose_verdict"] == r.summary()["diagnose_verdict"] == "adequate"
    assert attrs["diagnose_verdict_note"] == "" and r.summary()["diagnose_verdict_note"] is None
