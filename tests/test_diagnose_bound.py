"""``impedax diagnose/refine --bound`` and ``bounds=``: the user's bounds kept in the baseline fit
and in every later fit that has the parameter, as a FitResult's bounds are; a bound the optimum
presses against gives the ``constraint`` verdict, a loose one changes nothing.

SYNTHETIC spectra from numpy formulas written here: R0 + R1 ∥ C1 (R0 = 10 Ω, R1 = 100 Ω,
C1 = 10 µF) and, for refine, R0 + R1 ∥ CPE1 (Q = 10 µF s^(α−1), α = 0.85), each with 0.5 %
relative complex noise. Only a few effects are tried, without the DRT evidence where the API
allows, to keep the runs short."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.cli.refine import reproduce_line

MODEL = "R0 + R1 || C1"
R0, R1, C1, ALPHA = 10.0, 100.0, 1e-5, 0.85
F = np.geomspace(0.1, 1e5, 25)
NOISE = 0.005
EFFECT_IDS = ["series_inductance", "constant_phase"]
EFFECTS = ix.DEFAULT_EFFECTS.select(EFFECT_IDS)


def noisy(z: np.ndarray, seed: int) -> np.ndarray:
    """``z`` with NOISE relative complex Gaussian noise (SYNTHETIC)."""
    rng = np.random.default_rng(seed)
    return z * (1 + NOISE * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)))


def rc(f: np.ndarray, r1: float = R1) -> np.ndarray:
    """Z = R0 + 1/(1/R1 + jωC1) [Ω]."""
    return R0 + 1 / (1 / r1 + 1j * 2 * np.pi * f * C1)


def rms_rel(z_model: np.ndarray, z: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.abs((z_model - z) / np.abs(z)) ** 2)))


@pytest.fixture(scope="module")
def arc():
    return ix.make_spectrum(F, noisy(rc(F), 7))


@pytest.fixture(scope="module")
def arc_file(arc, tmp_path_factory):
    path = tmp_path_factory.mktemp("bound") / "arc.csv"
    ix.save(arc, path)
    return str(path)


def test_a_bound_below_the_optimum_is_the_constraint(arc):
    z = arc["Z"].values
    # the oracle: the formula is at the noise; with R1 held at 80 Ω (C1 refitted by hand on a
    # grid) no R0 ∥ C1 choice comes near it
    assert rms_rel(rc(F), z) < 2 * NOISE
    held = min(rms_rel(R0 + 1 / (1 / 80.0 + 1j * 2 * np.pi * F * c), z) for c in np.geomspace(5e-6, 2e-5, 200))
    assert held > 10 * NOISE
    d = ix.diagnose(arc, MODEL, bounds={"R1": (10.0, 80.0)}, effects=EFFECTS, drt_evidence=False)
    assert d.verdict == "constraint"
    assert d.baseline.bounds == {"R1": (10.0, 80.0)} and "R1" in d.baseline.at_bound
    assert d.baseline.values["R1"] == pytest.approx(80.0, rel=1e-6)
    assert d.baseline.rms_rel > 10 * NOISE
    assert "R1 on your upper bound 80 Ω" in d.reason and "not a missing effect" in d.reason
    assert any("your bounds (R1 within 10 Ω..80 Ω)" in n for n in d.notes)
    # every candidate that still has R1 kept the bound
    kept = [s.fit for s in d.candidates if "R1" in s.fit.values]
    assert kept and all(fit.bounds.get("R1") == (10.0, 80.0) and fit.values["R1"] <= 80.0 for fit in kept)
    assert d.summary()["baseline"]["user_bounds"] == {"R1": [10.0, 80.0]}


def test_a_loose_bound_leaves_the_verdict_as_without_it(arc):
    free = ix.diagnose(arc, MODEL, effects=EFFECTS, drt_evidence=False)
    loose = ix.diagnose(arc, MODEL, bounds={"R1": (50.0, 200.0)}, effects=EFFECTS, drt_evidence=False)
    assert free.verdict == loose.verdict == "adequate"
    assert loose.baseline.bounds == {"R1": (50.0, 200.0)} and loose.baseline.at_bound == ()
    assert loose.baseline.values["R1"] == pytest.approx(R1, rel=0.03)
    assert loose.baseline.values["R1"] == pytest.approx(free.baseline.values["R1"], rel=1e-4)
    assert free.summary()["baseline"]["user_bounds"] == {}


def test_cli_bound_gives_the_constraint_verdict_in_json(arc_file, capsys):
    args = ["diagnose", arc_file, "--model", MODEL, "--effects", ",".join(EFFECT_IDS), "--bound", "R1=10:80", "--json"]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["verdict"] == "constraint"
    assert out["baseline"]["user_bounds"] == {"R1": [10.0, 80.0]} and "R1" in out["baseline"]["at_bound"]
    assert out["baseline"]["params"]["R1"]["value"] == pytest.approx(80.0, rel=1e-6)


@pytest.mark.parametrize("command", ["diagnose", "refine"])
@pytest.mark.parametrize("items, says", [
    (["--bound", "R2=1:2"], "unknown parameter 'R2'"),
    (["--bound", "r1=1:2"], "did you mean R1?"),
    (["--bound", "R1=80:10"], "R1=80:10: the lower end 80 must be below the upper end 10"),
    (["--bound", "R1"], "expected NAME=LO:HI"),
    (["--bound", "R1=-1:10"], "outside R1's own range"),
    (["--fix", "R1=100", "--bound", "R1=10:80"], "a fixed parameter is not fitted"),
])
def test_a_bad_bound_exits_2_naming_the_option_and_parameter(arc_file, command, items, says, capsys):
    assert main([command, arc_file, "--model", MODEL, *items]) == 2
    err = capsys.readouterr().err
    named = items[-1].partition("=")[0]  # (the parameter the bad --bound gives)
    assert "--bound" in err and named in err and says in err, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize("options, says", [
    ({"bounds": {"R2": (1.0, 2.0)}}, "unknown parameter 'R2'"),
    ({"bounds": {"R1": (80.0, 10.0)}}, "bounds for R1: lower 80 must be below upper 10"),
    ({"bounds": {"R1": (-1.0, 10.0)}}, "bounds for R1: (-1, 10) reach outside"),
    ({"fixed": {"R1": 100.0}, "bounds": {"R1": (10.0, 80.0)}}, "fixed: R1=100 is outside its bounds (10, 80)"),
])
def test_python_bounds_are_refused_in_fits_words(arc, options, says):
    with pytest.raises(ix.ParameterError) as by_fit:
        ix.fit(MODEL, arc, **options)
    assert says in str(by_fit.value)
    for run in (ix.diagnose, ix.refine):
        with pytest.raises(ix.ParameterError) as error:
            run(arc, MODEL, **options)
        assert str(error.value) == str(by_fit.value)


def test_a_fit_result_is_diagnosed_with_its_own_bounds_not_new_ones(arc):
    fitted = ix.fit(MODEL, arc, n_starts=1)
    with pytest.raises(ix.ParameterError, match="a FitResult keeps the bounds it was fitted with"):
        ix.diagnose(fitted, bounds={"R1": (10.0, 80.0)})


def test_refine_keeps_the_bound_in_every_step_and_the_final_fit():
    """A CPE arc (α = 0.85) fitted from R0 + R1 ∥ C1 with R1 bounded loosely around its true
    value: refine replaces C1 by a CPE and keeps R1's bound in every model, the final refit
    included, and the command that reproduces the final fit carries it."""
    z = noisy(R0 + 1 / (1 / R1 + C1 * (1j * 2 * np.pi * F) ** ALPHA), 11)
    result = ix.refine(ix.make_spectrum(F, z), MODEL, bounds={"R1": (60.0, 150.0)}, effects=EFFECTS, max_effects=1, drt_evidence=False)
    assert len(result.steps) >= 2 and "CPE" in result.final_model, [s.model for s in result.steps]
    assert all(step.fit.bounds == {"R1": (60.0, 150.0)} for step in result.steps)
    final = result.final
    assert final.values["R1"] == pytest.approx(R1, rel=0.05) and final.values["CPE1.alpha"] == pytest.approx(ALPHA, abs=0.03)
    assert result.summary()["final_user_bounds"] == {"R1": [60.0, 150.0]}
    line = reproduce_line(result)
    assert line is not None and "within your bounds" in line and line.endswith("--bound R1=60:150"), line
