"""`impedax gap` on REAL single spectra that hold no air gap (2026-12-06 walkthrough).

- exampleData.csv, Parstat and Autolab (a battery and electrochemical cells, not a contact): the EDL
  fit ends with C_gap at its lower bound 0, and u = ε0·ε_gap·A/C_gap raised ZeroDivisionError (a
  traceback, exit 1). Now u = ∞ there, the walkers start on u's upper bound, and the report
  says what it is.
- BioLogic: u was sampled flat over 0.058 µm–460 mm; the sampling warned "u piles up against its
  upper bound", and yet `gap_identified` was true. Now the sampling's own pile-up marks u as no
  air gap, as the gap's `_piled_bounds` rule does."""

import json
import math
from pathlib import Path
from types import SimpleNamespace

import pytest

from impedax.cli import main
from impedax.constants import C_GAP_BOUNDS_F, EPSILON_0, EPSILON_AIR
from impedax.fitting.bayes.reparam import gap_thickness_reparametrization
from impedax.models.gap import NO_AIR_GAP, GapAnalysis

REAL = Path(__file__).parent / "fixtures" / "real"
AREA = 130e-6  # Sirin et al.'s 130 mm² [m²]


def test_the_gap_of_a_c_gap_at_zero_is_infinite_and_of_84_pf_the_parallel_plate_value():
    rp = gap_thickness_reparametrization(area=AREA)
    assert rp.start({"C_gap": 0.0})["u"] == math.inf
    # u = ε0 ε_gap A / C by hand: 8.8541878128e-12 × 1.00059 × 130e-6 / 84e-12 = 13.711 µm
    assert rp.start({"C_gap": 84e-12})["u"] == pytest.approx(8.8541878128e-12 * 1.00059 * 130e-6 / 84e-12, rel=1e-9)
    assert EPSILON_0 == pytest.approx(8.8541878128e-12, rel=1e-9) and EPSILON_AIR == pytest.approx(1.00059)


def stand_in(piled_up: dict, median: float = 181e-6) -> SimpleNamespace:
    """The fields `GapAnalysis.gap_implausible` reads, with no draw at a bound by `_piled_bounds`."""
    out = SimpleNamespace(hierarchical=None, posterior=SimpleNamespace(piled_up=piled_up), gap={"value": median}, _u_piled_bounds=[])
    out._u_piled_by_sampling = GapAnalysis._u_piled_by_sampling.fget(out)
    return out


@pytest.mark.parametrize(
    ("piled_up", "sides"),
    [({"u": "upper"}, ["upper"]), ({"u": "both"}, ["lower", "upper"]), ({"R_EP": "upper"}, []), ({}, [])],
)
def test_the_samplings_pile_up_of_u_makes_it_no_air_gap(piled_up, sides):
    why = GapAnalysis.gap_implausible.fget(stand_in(piled_up))
    if not sides:  # (u at 181 µm, inside 1 nm–1 mm, and nothing piled up: a gap)
        assert why is None
        return
    assert C_GAP_BOUNDS_F == (1e-15, 1e-4)
    for side in sides:  # (u's upper bound is C_gap's lower one, 1 fF)
        assert f"piles up at the {side} bound of its prior (C_gap = {'1 fF' if side == 'upper' else '100 µF'}:" in why, why


@pytest.mark.slow
@pytest.mark.parametrize("name", ["exampleData.csv", "exampleDataParstat.txt"])
def test_gap_of_a_spectrum_whose_edl_fit_puts_c_gap_at_zero_reports_instead_of_crashing(name, capsys):
    assert main(["gap", str(REAL / name), "--area", str(AREA), "--pooled", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["gap_identified"] is False and doc["force_determined"] is False
    assert any(alarm.startswith(NO_AIR_GAP) or alarm.startswith("MODEL DOES NOT FIT") for alarm in doc["alarms"]), doc["alarms"]
    assert any("C_gap is at its lower bound 0" in w for w in doc["warnings"])


@pytest.mark.slow
def test_gap_of_biologic_sampled_flat_to_the_bound_is_no_air_gap(capsys):
    assert main(["gap", str(REAL / "exampleDataBioLogic.mpt"), "--area", str(AREA), "--pooled", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert any(w.startswith("sampling: u piles up against its upper bound") for w in doc["warnings"])
    assert doc["gap_identified"] is False and "piles up at the upper bound" in doc["gap_implausible"]
    assert any(alarm.startswith(NO_AIR_GAP) for alarm in doc["alarms"])
