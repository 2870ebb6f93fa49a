"""`impedax gap` on one spectrum: the Bayesian u and the paper method's u are set against each
other. The REAL Gamry file (exampleDataGamry.DTA, a cell, no air gap) read as a single contact
at A = 1 cm² gave u = 2.19 µm (Bayesian) and 0.006 µm (paper), 360× apart, without a word: the
rule that compares them held the Bayesian u against the paper's bounds, which one spectrum has
not. A SYNTHETIC single pad where the two agree stays without the warning."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from impedax.cli import main
from impedax.models.gap import _estimate_bound_notes, gap_analysis
from impedax.models.sirin import PaperGapEstimate

sys.path.insert(0, str(Path(__file__).parent))
from test_gap_single_contact import AREA, U_TRUE, _pad_trials  # noqa: E402

REAL = Path(__file__).parent / "fixtures" / "real"
EPS0, EPS_AIR = 8.8541878128e-12, 1.00059
SINGLE = xr.Dataset(attrs={"single_contact": 1, "n_trials_total": 1})
ONE_EACH = xr.Dataset(attrs={"n_trials_total": 1, "n_trials_skin": 1, "n_trials_touchscreen": 1})


def _one_spectrum_estimate(u):
    """The paper's estimate of one spectrum: its bounds, of the one trial, are u itself."""
    c = EPS0 * EPS_AIR * AREA / u
    return PaperGapEstimate(c_gap=c, gap=u, c_gap_low_impedance=c, c_gap_high_impedance=c, gap_lower=u, gap_upper=u, cutoff_hz=30.0, area=AREA, eps_gap=EPS_AIR)


def test_one_spectrum_whose_two_estimates_are_orders_apart_is_warned():
    """The Gamry run's numbers: 2.19 µm against 0.00594 µm, 2.19/0.00594 = 368.7 by hand."""
    (note,) = _estimate_bound_notes("Bayesian gap thickness", 2.19e-6, _one_spectrum_estimate(5.94e-9), SINGLE, "; draws span 1.4–3.9 µm")
    assert note.startswith("the Bayesian gap thickness 2.19 µm and the paper method's u = 0.00594 µm differ 369×"), note
    assert "one spectrum, so the paper method has no bounds; draws span 1.4–3.9 µm" in note and "the two methods disagree" in note
    # either way round, and for one spectrum per file of the three-file mode
    (other,) = _estimate_bound_notes("Bayesian gap thickness", 5.94e-9, _one_spectrum_estimate(2.19e-6), ONE_EACH)
    assert "differ 369×" in other and "one spectrum per file" in other


def test_one_spectrum_whose_estimates_agree_within_the_ratio_is_not_warned():
    """The SYNTHETIC pad's paper u is 0.82× the truth (its EP admittance counted as C_gap's):
    far within the 10× of `GAP_METHODS_RATIO_MAX`; 9× apart is within it too, 11× is not."""
    for paper_u, warned in ((0.82 * U_TRUE, False), (U_TRUE / 9, False), (U_TRUE * 9, False), (U_TRUE / 11, True), (U_TRUE * 11, True)):
        assert len(_estimate_bound_notes("Bayesian gap thickness", U_TRUE, _one_spectrum_estimate(paper_u), SINGLE)) == warned, paper_u


def _gamry_paper_gap(area):
    """Sirin §2.3 by numpy from the file's own ZCURVE columns (Freq, Zreal, Zimag): C_gap = mean
    |1/Z|/ω over 30 Hz and above, u = ε0 ε_air A / C_gap [m]."""
    lines = (REAL / "exampleDataGamry.DTA").read_text(encoding="latin-1").splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith("ZCURVE")) + 3
    rows = []
    for line in lines[start:]:
        cells = line.split("\t")
        if len(cells) < 6:
            break
        rows.append([float(x) for x in cells[3:6]])
    f, zr, zi = np.array(rows).T
    keep = f >= 30.0
    c_gap = np.mean(np.abs(1 / (zr + 1j * zi))[keep] / (2 * np.pi * f[keep]))
    return EPS0 * EPS_AIR * area / c_gap


@pytest.mark.slow
def test_real_gamry_single_contact_says_the_two_estimates_disagree(capsys):
    assert main(["gap", str(REAL / "exampleDataGamry.DTA"), "--area", "1e-4", "--pooled", "--json", "--quiet"]) == 0
    doc = json.loads(capsys.readouterr().out)
    u_paper = _gamry_paper_gap(1e-4)
    assert doc["paper_method"]["gap_um"] == pytest.approx(u_paper * 1e6, rel=1e-6)  # 0.00594 µm
    u_bayes = doc["gap_um"]["value"] * 1e-6  # (2.19 µm, the EDL model's C_gap over the whole band)
    assert u_bayes / u_paper > 100
    (note,) = [w for w in doc["warnings"] if "the two methods disagree" in w]
    assert f"the Bayesian gap thickness {u_bayes * 1e6:.3g} µm and the paper method's u = {u_paper * 1e6:.3g} µm" in note, note
    assert "one spectrum, so the paper method has no bounds" in note
    assert doc["gap_identified"] == (doc["gap_implausible"] is None)  # (the verdicts are left as they were)


@pytest.mark.slow
def test_synthetic_single_spectrum_where_the_methods_agree_has_no_warning():
    result = gap_analysis(_pad_trials(7, n_trials=1), area=AREA, method="pooled", steps=100, progress=False)
    assert result.gap["q05"] <= U_TRUE <= result.gap["q95"], result.gap
    assert 0.5 < result.paper.gap / U_TRUE < 1.0  # (0.82: the EP branch counted as C_gap's)
    assert not [w for w in result.warnings if "the two methods disagree" in w]


def test_a_paper_u_below_a_tenth_of_a_micrometre_keeps_three_significant_digits():
    """The Gamry run's report read "paper method    u = 0.006 µm" (one digit) beside C_gap 149.1 nF
    and the warning's 0.00594 µm: 5.943 nm is 0.00594 µm to 3 significant digits; 3 decimals
    stay from 0.1 µm up."""
    from impedax.models.gap import _gap_length, _gap_range

    assert _gap_length(5.943115904e-9) == "0.00594 µm"
    assert _gap_length(4.33e-8) == "0.0433 µm"
    assert _gap_length(2.1875731685e-6) == "2.188 µm" and _gap_length(0.126e-6) == "0.126 µm"
    assert _gap_range(5.943e-9, 6.61e-9) == "0.00594–0.00661 µm"
    assert _gap_range(2.797e-6, 2.814e-6) == "2.797–2.814 µm"
