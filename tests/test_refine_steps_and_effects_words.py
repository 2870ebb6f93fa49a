"""refine's summary line counts its steps and, where a step added a pair of effects, the effects:
`max_effects` counts effects, so "in 3 step(s)" beside "its limit of 4 added effect(s)" read as a
contradiction on REAL VersaStudio (a step of `extra_relaxation+series_inductance`)."""

import dataclasses

import numpy as np
import pytest

import impedax as ix


@pytest.fixture(scope="module")
def refined():
    """SYNTHETIC R0 + R1 ‖ CPE1 (α = 0.8), written in numpy, 0.3 % noise; refine from R0 + R1 ‖ C1."""
    f = np.geomspace(1e5, 0.1, 40)
    s = 2j * np.pi * f
    z = 20 + 1000 / (1 + 1000 * 1e-5 * s**0.8)
    rng = np.random.default_rng(3)
    z = z + 0.003 * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    return ix.refine(ix.make_spectrum(f, z), "R0 + R1 || C1", max_effects=1, progress=False)


def _summary(refinement):
    return next(line for line in refinement.report().splitlines() if line.startswith("rms_rel ") and " in " in line)


def test_one_step_of_one_effect_says_one_step(refined):
    assert len(refined.steps) == 2 and refined.steps[1].effect and "+" not in refined.steps[1].effect
    line = _summary(refined)
    assert " in 1 step;" in line and "effect" not in line and "step(s)" not in line, line


def test_a_step_of_a_pair_says_how_many_effects(refined):
    step = dataclasses.replace(refined.steps[1], effect="extra_relaxation+series_inductance")
    paired = dataclasses.replace(refined, steps=(refined.steps[0], step))
    line = _summary(paired)
    assert " in 1 step (2 effects added);" in line, line
