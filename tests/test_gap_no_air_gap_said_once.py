"""`impedax gap` said that its Bayesian u is no air gap once in the alarm NO AIR GAP and again in
warnings: the posterior of u piling up at its prior's bound (the alarm's own rule), the pooled
sampling's "u = … (posterior median) is no air gap", and the warning that the Bayesian u and the
paper method's u disagree ("… check that the spectrum is of an air-gap contact and that the model
fits it", beside NO AIR GAP and MODEL DOES NOT FIT on the REAL exampleData.csv as a single
contact; all three beside the alarm on a SYNTHETIC R_EP ∥ CPE_EP contact without any gap,
2026-12-06). They are left out where the alarm holds; the comparison stays where only the paper's u
is no air gap (it then questions the Bayesian u, which no alarm does) or no alarm holds (the REAL
Gamry file: tests/test_gap_methods_disagree.py). The JSON keeps its keys."""

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting import gap_thickness_reparametrization
from impedax.models.gap import METHODS_DISAGREE, NO_AIR_GAP, _no_air_gap_said_once, _sampling_notes, gap_analysis, gap_bounds

REAL = Path(__file__).parent / "fixtures" / "real"
COMPARISON = f"the Bayesian gap thickness 10.4 µm and the paper method's u = 19.2 fm differ 5.38e+08× (…): {METHODS_DISAGREE} — …"
PILED = "the posterior of u piles up at the upper bound of its prior, u = 886 mm (…)"


@dataclass(frozen=True)
class _Result:
    """What `_no_air_gap_said_once` reads of a `GapAnalysis`: its warnings and the alarm's reason."""

    warnings: tuple
    gap_implausible: str | None = None


def test_the_restated_warnings_are_left_out_under_no_air_gap_only():
    warnings = ("EDL fit: C_gap is at its lower bound 0", PILED, COMPARISON)
    alarm = "u = 10.4 µm (posterior median) piles up at the upper bound of its prior"
    assert _no_air_gap_said_once(_Result(warnings, alarm), (PILED, COMPARISON)).warnings == warnings[:1]
    assert _no_air_gap_said_once(_Result(warnings), (PILED, COMPARISON)).warnings == warnings  # (no alarm of the Bayesian u: kept)


def test_the_samplings_no_air_gap_note_is_the_alarms():
    """The pooled sampling's own note on u outside 1 nm–1 mm (`implausible_gap_notes`, at the median
    of the draws) is left out: the alarm NO AIR GAP holds by the same median and range."""
    area = 1e-4
    rp = gap_thickness_reparametrization("C_gap", area=area, lower=gap_bounds(area)[0], upper=gap_bounds(area)[1])
    note = "u = 0.807 m (posterior median) is no air gap (1e-09–0.001 m is): check the area's unit first, A = 0.0001 m² (100 mm²; 200 mm² is 200e-6 m²), then the data"
    assert _sampling_notes([note, "other"], rp, np.full(9, 0.807)) == ["other"]
    assert _sampling_notes([note, "other"]) == [note, "other"]  # (without the sampling's parametrization: as before)


@pytest.mark.slow
def test_a_synthetic_contact_without_a_gap_says_it_once():
    """R_EP ∥ CPE_EP written in numpy (no C_gap): u runs to its prior's upper bound."""
    f = np.geomspace(1, 1e5, 41)
    z = 1 / (1 / 1e6 + 2e-9 * (2j * np.pi * f) ** 0.8)
    rng = np.random.default_rng(0)
    z = z * (1 + 0.005 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    result = gap_analysis(ix.make_spectrum(f, z), area=1e-4, method="pooled", steps=300, progress=False, check_area=False)
    assert result.gap_implausible is not None and any(a.startswith(NO_AIR_GAP) for a in result.alarms)
    assert result.gap["value"] > 1e-3  # (metres: beyond every air gap)
    for restated in ("the posterior of u piles up", "(posterior median) is no air gap", METHODS_DISAGREE):
        assert not [w for w in result.warnings if restated in w], (restated, result.warnings)
    assert "piles up at the upper bound of its prior" in result.gap_implausible and "lies outside the air gaps" in result.gap_implausible  # (the alarm says both)


@pytest.mark.slow
def test_real_csv_as_a_single_contact_says_no_air_gap_once(capsys):
    assert main(["gap", str(REAL / "exampleData.csv"), "--area", "1e-4", "--no-area-check", "--pooled", "--json", "--quiet"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert any(a.startswith("NO AIR GAP: u = ") for a in doc["alarms"]) and doc["gap_implausible"] is not None
    assert not [w for w in doc["warnings"] if METHODS_DISAGREE in w], doc["warnings"]
    # (the numbers the warning set side by side stay in the JSON)
    assert doc["gap_um"]["value"] > 0 and doc["paper_method"]["gap_um"] < 1e-3
