"""When the pooled sampling of `impedax gap` piled u up at a bound of its prior, its warning ended
"check the area's unit first (m²; 200 mm² is 200e-6), then the bounds (lower=, upper=) and the
data" (REAL exampleData.csv and exampleDataBioLogic.mpt as single contacts, 2026-12-06): keywords
of `gap_thickness_reparametrization` that neither `gap_analysis` nor `impedax gap` takes, since
the gap analysis bounds u so that C_gap lies within 1 fF–100 µF at any area. The gap analysis now
says so and names the area as each surface sets it: ``area=`` in Python, ``--area`` on the
command line."""

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.cli.common import command_line_words
from impedax.fitting import gap_thickness_reparametrization
from impedax.models.gap import _sampling_notes, gap_analysis, gap_bounds

REAL = Path(__file__).parent / "fixtures" / "real"
AREA = 1e-4


def _piled_warning():
    """The sampler's warning of u at its upper bound, its cause as the sampling's parametrization gives it."""
    low, high = gap_bounds(AREA)
    rp = gap_thickness_reparametrization("C_gap", area=AREA, lower=low, upper=high)
    cause = dict(rp.bound_causes)["u"]
    assert "then the bounds (lower=, upper=) and the data" in cause  # (the generic words, right for sample(..., reparametrization=...))
    return rp, f"u piles up against its upper bound 885.941 mm (3 % of the draws …): the bound, not the data, sets the upper end of its 90 % interval; the data would take larger values. {cause}"


def test_the_python_words_name_area_and_no_bound_keyword():
    rp, warning = _piled_warning()
    (said,) = _sampling_notes([warning], rp, np.full(9, 2e-6))
    assert "lower=" not in said and "upper=" not in said
    assert said.endswith("u at a bound means C_gap at 100 µF or 1 fF, the ends of the range the gap analysis allows C_gap at any area (no option widens it); "
                         "check the area's unit first (area= in m²; 200 mm² is 200e-6), then the data"), said


def test_the_command_line_words_name_the_area_option():
    rp, warning = _piled_warning()
    (said,) = _sampling_notes([warning], rp, np.full(9, 2e-6))
    shown = command_line_words(said, "gap")
    assert "check the area's unit first (--area in m²; 200 mm² is 200e-6), then the data" in shown and "area=" not in shown


@pytest.mark.slow
@pytest.mark.parametrize("surface", ["python", "cli"])
def test_real_csv_as_a_single_contact_names_the_area_as_its_surface_sets_it(surface, capsys):
    path = REAL / "exampleData.csv"
    if surface == "python":
        warnings = gap_analysis(ix.load(path), area=AREA, method="pooled", progress=False, check_area=False).warnings
        words = "(area= in m²;"
    else:
        assert main(["gap", str(path), "--area", str(AREA), "--no-area-check", "--pooled", "--json", "--quiet"]) == 0
        warnings = json.loads(capsys.readouterr().out)["warnings"]
        words = "(--area in m²;"
    (piled,) = [w for w in warnings if w.startswith("sampling: u piles up against its upper bound")]
    assert words in piled and "lower=" not in piled and "upper=" not in piled, piled
