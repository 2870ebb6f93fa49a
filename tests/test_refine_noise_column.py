"""Refine's table and JSON give each step's residuals against the noise its verdict was judged
on (``×noise``, `RefinementStep.noise_ratio`), so that users can see whether a step's gain is
beyond the noise. On REAL exampleData.csv from R0 + R1 || C1 the table gave rms_rel and AIC of
13-parameter steps (0.805 %, 0.693 %, 0.608 %) with no word of where the noise lies; only the
figure marked it (2026-12-06)."""

import numpy as np
import pytest

import impedax as ix

NOISE = 0.01  # σ per component, relative to |Z|: given, so the diagnosis uses it as it is


def _two_arcs():
    """SYNTHETIC R0 + R1 ∥ C1 + R2 ∥ C2 (numpy formula), 1 % complex noise, 40 points."""
    rng = np.random.default_rng(7)
    f = np.logspace(-1, 5, 40)
    w = 2 * np.pi * f
    z = 10.0 + 100.0 / (1 + 1j * w * 100.0 * 1e-5) + 50.0 / (1 + 1j * w * 50.0 * 2e-3)
    z = z + NOISE * np.abs(z) * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
    return f, z


@pytest.fixture(scope="module")
def refined():
    f, z = _two_arcs()
    return f, z, ix.refine(ix.make_spectrum(f, z), "R0 + R1 || C1", noise=NOISE, max_effects=1, progress=False)


def _ratio_by_hand(f, z, values, model):
    """√(mean |Z_model − Z|²/|Z|² / 2σ²) with Z_model from the fitted values by hand, for the
    start and for the two circuits of two arcs refine reaches (in series, or nested)."""
    w = 2 * np.pi * f
    v = values

    def arc(r, c):
        return r / (1 + 1j * w * r * c)

    zm = {
        "R0 + R1 || C1": lambda: v["R0"] + arc(v["R1"], v["C1"]),
        "R0 + R1 || C1 + R_relax || C_relax": lambda: v["R0"] + arc(v["R1"], v["C1"]) + arc(v["R_relax"], v["C_relax"]),
        "R0 + (R1 + R_relax || C_relax) || C1": lambda: v["R0"] + 1 / (1 / (v["R1"] + arc(v["R_relax"], v["C_relax"])) + 1j * w * v["C1"]),
    }[model]()
    return float(np.sqrt(np.mean(np.abs(zm - z) ** 2 / np.abs(z) ** 2) / (2 * NOISE**2)))


@pytest.mark.slow
def test_each_step_gives_its_residuals_against_the_noise(refined):
    f, z, result = refined
    assert [s.model for s in result.steps][0] == "R0 + R1 || C1" and result.steps[1].effect == "extra_relaxation"
    by_hand = [_ratio_by_hand(f, z, s.fit.values, s.model) for s in result.steps]
    assert by_hand[0] > 5 and 0.7 < by_hand[1] < 1.3  # (the start misses the second arc; the end is at the noise)
    for step, expected in zip(result.steps, by_hand):
        assert step.noise_ratio == pytest.approx(expected, rel=1e-3)
    json_steps = result.summary()["steps"]
    assert [s["noise_ratio"] for s in json_steps] == pytest.approx(by_hand, rel=1e-3)
    table = result.table().splitlines()
    assert table[0].split() == ["step", "rms_rel", "AIC", "×noise", "change", "/", "model"]
    for i, expected in enumerate(by_hand):
        assert table[1 + 2 * i].split()[4] == f"{expected:.3g}×"  # (index, rms_rel, %, AIC, ×noise)


def test_the_notebook_table_rounds_it_and_a_step_without_diagnosis_has_none():
    """The HTML rows give the ratio as the text table does (3 significant digits); a step with no
    diagnosis (a refinement rebuilt from stand-ins or a saved file) shows "–" and JSON null."""
    from types import SimpleNamespace

    from impedax.fitting.diagnosis.refinement import Refinement, RefinementStep

    f, z = _two_arcs()
    fit = ix.fit("R0 + R1 || C1", (f, z))
    judged = SimpleNamespace(verdict="adequate", verdict_heading="ADEQUATE", reason="the residuals are noise", beyond_catalog=False, noise_ratio=0.91234,
                             not_passive_points=(), sign_hint=None, effects_left_out=())
    html = Refinement((RefinementStep(fit, None, None, judged),), "adequate")._repr_html_()
    assert "×noise" in html and "0.912" in html and "0.91234" not in html
    bare = Refinement((RefinementStep(fit, None, None, None),), "adequate")
    assert bare.table().splitlines()[1].split()[4] == "–" and bare.summary()["steps"][0]["noise_ratio"] is None
