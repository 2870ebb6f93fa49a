"""A refinement that ends on a model whose own diagnosis still names a missing effect, below
refine's limit, says why refine did not add it. REAL Autolab under proportional weighting ended
"verdict: MISSING_EFFECT — … adding extra_relaxation (R_relax2 || C_relax2) lowers AIC by 36.6"
with no word of why refine stopped there (2026-12-06): its last step simplified CPE3 to C3, and
refine added no effect after simplifying. It now goes on from a simplified model as from any
step; the note remains for a step taken from it and dropped, and for a limit."""

from pathlib import Path
from types import SimpleNamespace

import pytest

import impedax as ix
from impedax.fitting.diagnosis.refinement import unfollowed_effect_note

REAL = Path(__file__).parent / "fixtures" / "real"


def _step(effect, change, model):
    return SimpleNamespace(effect=effect, change=change, model=model)


def test_the_note_names_a_last_simplification_as_the_reason():
    steps = [_step(None, "(start)", "R0 + R1 || C1"), _step("extra_relaxation", "+ R_relax || CPE_relax [extra_relaxation]", "A"), _step(None, "CPE_relax → C_relax [simplified]", "B")]
    note = unfollowed_effect_note(steps, SimpleNamespace(effect="series_inductance", added="L_lead"))
    assert note.startswith("the final model still misses series_inductance (L_lead) by its own diagnosis, which refine did not add: ")
    assert "simplified the model in its last step (CPE_relax → C_relax)" in note and "a diagnosis of B shows it" in note


def test_the_note_names_a_dropped_step_otherwise():
    steps = [_step(None, "(start)", "R0 + R1 || C1"), _step("extra_relaxation", "+ R_relax || C_relax [extra_relaxation]", "A")]
    note = unfollowed_effect_note(steps, SimpleNamespace(effect="diffusion", added="W_d"))
    assert "the step refine took from it was dropped" in note and "a diagnosis of A shows it" in note


@pytest.mark.slow
def test_real_autolab_refine_goes_on_after_simplifying():
    """REAL Autolab under proportional weighting: the third path ends at CPE3 → C3 (CPE3.alpha at
    its bound 1) with 3 of its 4 effects used, and the simpler model's own diagnosis names
    extra_relaxation (ΔAIC −36.6). Refine goes on from it as from any step: the step it takes
    lowers rms_rel and AIC below the simplified step's, with every parameter determined, and the
    end names no effect within the limit (2026-12-06: it ended MISSING_EFFECT there)."""
    data = ix.load(REAL / "exampleDataAutolab.txt")
    result = ix.refine(data, "R0 + R1 || C1", weighting="proportional")
    simplified = [i for i, s in enumerate(result.steps) if i and s.effect is None]
    assert simplified and any(s.effect is not None for s in result.steps[simplified[0] + 1 :]), [s.change for s in result.steps]
    before, end = result.steps[simplified[0]], result.steps[-1]
    assert end.fit.rms_rel < before.fit.rms_rel and end.fit.aic < before.fit.aic - 2
    went_on = [n for n in result.notes if n.startswith("refine went on after simplifying (")]
    assert len(went_on) == 1, result.notes
    assert result.summary()["undetermined"] == []
    assert result.verdict != "missing_effect" and not any("still misses" in n for n in result.notes), result.notes


@pytest.mark.slow
def test_an_adequate_end_gets_no_such_note():
    """Nothing missing: SYNTHETIC R0 + R1 || C1 (numpy formula, 1 % noise) refined from itself."""
    import numpy as np

    rng = np.random.default_rng(3)
    f = np.logspace(-1, 5, 40)
    z = 10.0 + 100.0 / (1 + 2j * np.pi * f * 100.0 * 1e-5)
    z = z * (1 + 0.01 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    result = ix.refine(ix.make_spectrum(f, z), "R0 + R1 || C1")
    assert result.verdict == "adequate" and not any("still misses" in n for n in result.notes)


@pytest.mark.slow
def test_a_refinement_names_its_weighting_in_report_json_and_figure():
    """REAL Autolab refined under proportional weighting: every step's rms_rel and AIC are of that
    weighting, and neither the report, the JSON nor the figure said which (fit, diagnose and
    compare name it; 2026-12-06)."""
    import matplotlib

    matplotlib.use("Agg")
    data = ix.load(REAL / "exampleDataAutolab.txt")
    result = ix.refine(data, "R0 + R1 || C1", weighting="unit", max_effects=1)
    assert result.report().splitlines()[0] == "refinement of R0 + R1 || C1 under unit weighting (rms_rel and AIC of each step's fit)"
    assert result.summary()["weighting"] == "unit"
    fig = result.plot()
    assert "unit weighting" in fig._suptitle.get_text().replace("\n", " ")
