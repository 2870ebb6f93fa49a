"""The reports of ``impedax diagnose`` and ``impedax refine`` read by a researcher who does not
know impedax's internals (docs/diagnosis.md): counts in their number, each fact said once, the
verdict's count of bands agreeing with the bands listed, and a plain word when nothing is
missing. Each test states the words a reading of the REAL example files or of a SYNTHETIC
spectrum found wanting."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

import impedax as ix
from impedax.fitting.diagnosis.diagnosis import _verdict

REAL = Path(__file__).parent / "fixtures" / "real"


def _band(data_problem: bool) -> SimpleNamespace:
    return SimpleNamespace(data_problem=data_problem)


def _suggestion(delta_aic: float) -> SimpleNamespace:
    return SimpleNamespace(significant=True, effect="series_inductance", added="L_lead", delta_aic=delta_aic, beyond_band=())


def test_the_verdict_counts_its_bands_in_their_number():
    """REAL ZPlot from R0 + R1 || C1: "structured in 1 band(s)" for the one band listed."""
    verdict, reason = _verdict([_suggestion(-83.1)], [_band(False)], 8.71)
    assert verdict == "missing_effect"
    assert reason == "the residuals are 8.71× the noise and structured in 1 band; adding series_inductance (L_lead) lowers AIC by 83.1."
    _, reason = _verdict([_suggestion(-20.0)], [_band(False), _band(False)], 3.0)
    assert "structured in 2 bands;" in reason and "(s)" not in reason


def test_the_verdict_names_the_bands_of_the_data_s_problem_it_does_not_count():
    """REAL BioLogic from R0 + R1 || C1 lists two bands under "where the model fails", one tagged
    "[data problem: …]", beside "structured in 1 band(s)": the verdict says what the other is."""
    _, reason = _verdict([_suggestion(-54.1)], [_band(False), _band(True)], 1.72)
    assert reason.startswith("the residuals are 1.72× the noise and structured in 1 band (and 1 where the KK test flags the data); adding"), reason
    # adequate beyond the catalog says the same
    cand = SimpleNamespace(significant=False, effect="diffusion", added="W_d", delta_aic=-3.0, beyond_band=())
    verdict, reason = _verdict([cand], [_band(False), _band(False), _band(True)], 4.0)
    assert verdict == "adequate" and "structured in 2 bands (and 1 where the KK test flags the data), but no effect" in reason, reason


@pytest.fixture(scope="module")
def biologic():
    """REAL BioLogic (impedance.py's example file, MIT) diagnosed from R0 + R1 || C1: 4 lone
    points inside the band flagged by the KK test and kept in every fit."""
    return ix.diagnose(ix.load(REAL / "exampleDataBioLogic.mpt"), "R0 + R1 || C1", progress=False)


@pytest.mark.slow
def test_the_report_counts_in_the_number_of_its_counts(biologic):
    """"the KK test flags 4 point(s) inside the band", "structured in 1 band(s)" on REAL BioLogic."""
    report = biologic.report()
    assert "(s)" not in report, [line for line in report.splitlines() if "(s)" in line]
    assert "the KK test flags 4 points inside the band (5.34 Hz, 56.2 Hz, 123 Hz, 270 Hz): kept in every fit" in report
    (verdict,) = [line for line in report.splitlines() if line.startswith("verdict:")]
    assert "structured in 1 band (and 1 where the KK test flags the data);" in verdict, verdict
    assert sum(line.startswith("  ") and "[data problem" in line for line in report.splitlines()) == 1


@pytest.mark.slow
def test_the_data_line_names_the_flagged_points_once(biologic):
    """The data line said "NOT Kramers–Kronig consistent in 5.34 Hz, 56.2 Hz, 123 Hz, 270 Hz (…);
    the KK test flags 4 points inside the band (5.34 Hz, 56.2 Hz, 123 Hz, 270 Hz): …"."""
    (data_line,) = [line for line in biologic.report().splitlines() if line.startswith("data:")]
    listed = "5.34 Hz, 56.2 Hz, 123 Hz, 270 Hz"
    assert data_line.count(listed) == 1, data_line
    assert data_line.startswith("data: the data are NOT Kramers–Kronig consistent (KK rms_rel 2.81 %); "
                                f"the KK test flags 4 points inside the band ({listed}): kept in every fit"), data_line
