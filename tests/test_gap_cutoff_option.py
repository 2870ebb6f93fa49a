"""`impedax gap --cutoff-hz HZ`: the paper method's cutoff, which the Python API took
(`gap_analysis(cutoff_hz=…)`) and the command line did not. The oracle is Sirin §2.3 by hand in
numpy: C_gap = mean over f ≥ cutoff of |Y_R|/ω = 1/(2πf |mean Z|), u = ε0 ε_gap A/C_gap, on
SYNTHETIC single-contact spectra (R_EP ∥ CPE_EP ∥ C_gap, 1 % noise) whose EP branch makes the
mean depend on the cutoff."""

import json

import numpy as np
import pytest

import impedax as ix
from cli_run import run
from impedax.models import gap_analysis

EPS_AIR = 1.00059
EPS0 = 8.8541878128e-12
AREA = 130e-6  # [m²], a fingertip
C_GAP = EPS0 * EPS_AIR * AREA / 20e-6
R_EP, ALPHA = 5e6, 0.6
Q_EP = 3 * C_GAP * (2 * np.pi * 30.0) ** (1 - ALPHA)
FREQ = np.geomspace(1.0, 1e5, 41)


@pytest.fixture(scope="module")
def contact(tmp_path_factory):
    rng = np.random.default_rng(11)
    w = 2 * np.pi * FREQ
    z = np.tile(1.0 / (1.0 / R_EP + Q_EP * (1j * w) ** ALPHA + 1j * w * C_GAP), (4, 1))
    z = z * (1 + 0.01 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    path = tmp_path_factory.mktemp("cutoff") / "contact.nc"
    ix.save(ix.make_spectrum(FREQ, z, dims=("trial",)), str(path))
    return path, z


def _paper_c_gap(z_trials, cutoff):
    z = np.asarray(z_trials).mean(axis=0)
    keep = FREQ >= cutoff
    return np.mean(1.0 / (2 * np.pi * FREQ[keep] * np.abs(z[keep])))


def test_cutoff_sets_the_paper_mean_and_the_json_and_report_say_it(contact, tmp_path, capsys):
    path, z = contact
    cutoff = 1000.0
    assert _paper_c_gap(z, cutoff) != pytest.approx(_paper_c_gap(z, 30.0), rel=1e-3)  # (the cutoff matters for these data)
    written = tmp_path / "gap.json"  # (--out FILE.json is the --json document, and the report goes to stdout)
    code, out, err = run(["gap", path, "--area", "130e-6", "--v0", "100", "--cutoff-hz", "1k", "--pooled", "--steps", "100", "--quiet", "--out", written], capsys)
    assert code == 0, err
    assert "(mean |Y_R|/ω at and above 1000 Hz, Sirin §2.3)" in out
    summary = json.loads(written.read_text())
    assert summary["paper_method"]["c_gap_f"] == pytest.approx(_paper_c_gap(z, cutoff), rel=1e-9)
    assert summary["paper_method"]["gap_um"] == pytest.approx(EPS0 * EPS_AIR * AREA / _paper_c_gap(z, cutoff) * 1e6, rel=1e-9)
    assert summary["paper_method"]["cutoff_hz"] == cutoff and summary["settings"]["cutoff_hz"] == cutoff
    assert summary["provenance"]["settings"]["cutoff_hz"] == cutoff


def test_the_default_cutoff_is_the_papers_30_hz(contact, capsys):
    path, z = contact
    code, out, err = run(["gap", path, "--area", "130e-6", "--v0", "100", "--pooled", "--steps", "100", "--quiet", "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    assert summary["paper_method"]["cutoff_hz"] == 30.0
    assert summary["paper_method"]["c_gap_f"] == pytest.approx(_paper_c_gap(z, 30.0), rel=1e-9)


@pytest.mark.parametrize("value, words", [
    ("0", "--cutoff-hz must be positive, got 0"), ("-5", "--cutoff-hz must be positive, got -5"), ("nan", "--cutoff-hz must be finite, got nan"),
    ("200k", "--cutoff-hz must be at most 100000 Hz, the highest frequency of the total spectra (1–100000 Hz), got 200000"),
])
def test_a_cutoff_not_positive_or_above_the_band_is_refused(contact, tmp_path, capsys, value, words):
    """The command line's message is gap_analysis's own, its cutoff_hz named as the option."""
    path, _ = contact
    out = tmp_path / "gap.json"
    code, stdout, err = run(["gap", path, "--area", "130e-6", "--cutoff-hz", value, "--pooled", "--out", out], capsys)
    assert code == 2, err
    assert words in err and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert not out.exists()


@pytest.mark.parametrize("value", [0.0, -5.0, float("nan"), 2e5])
def test_gap_analysis_refuses_the_same_cutoffs_naming_cutoff_hz(contact, value):
    path, _ = contact
    with pytest.raises(ix.ParameterError, match=r"^cutoff_hz must be (positive|finite|at most 100000 Hz, the highest frequency of the total spectra \(1–100000 Hz\)), got"):
        gap_analysis(ix.load(str(path)), area=130e-6, v0=100.0, cutoff_hz=value, method="pooled", steps=100, progress=False)


BELOW = "the paper method's cutoff 500 mHz lies below the band of the total spectra (1 Hz–100 kHz): its C_gap is the mean |Y_R|/ω over every measured frequency"


def test_a_cutoff_below_the_band_uses_every_point_and_says_so(contact, tmp_path, capsys):
    """A cutoff below the data's band cuts nothing: the command and gap_analysis both take it, read
    the paper's C_gap over every point (by hand: the mean over all 41) and say so in a warning of
    the report and of the JSON."""
    path, z = contact
    written = tmp_path / "gap.json"
    code, out, err = run(["gap", path, "--area", "130e-6", "--v0", "100", "--cutoff-hz", "0.5", "--pooled", "--steps", "100", "--quiet", "--out", written], capsys)
    assert code == 0, err
    summary = json.loads(written.read_text())
    assert summary["paper_method"]["c_gap_f"] == pytest.approx(_paper_c_gap(z, 0.0), rel=1e-9)
    assert summary["paper_method"]["cutoff_hz"] == 0.5
    assert sum(BELOW in w for w in summary["warnings"]) == 1, summary["warnings"]
    assert BELOW in " ".join(out.split())
    result = gap_analysis(ix.load(str(path)), area=130e-6, v0=100.0, cutoff_hz=0.5, method="pooled", steps=100, progress=False)
    assert result.paper.c_gap == pytest.approx(_paper_c_gap(z, 0.0), rel=1e-9)
    assert sum(BELOW in w for w in result.warnings) == 1


def test_a_cutoff_inside_the_band_gives_no_such_warning(contact, tmp_path, capsys):
    path, _ = contact
    code, out, err = run(["gap", path, "--area", "130e-6", "--v0", "100", "--cutoff-hz", "1", "--pooled", "--steps", "100", "--quiet", "--json"], capsys)
    assert code == 0, err
    assert not any("lies below the band" in w for w in json.loads(out)["warnings"])


def test_fmax_below_the_cutoff_names_both(contact, capsys):
    path, _ = contact
    code, stdout, err = run(["gap", path, "--area", "130e-6", "--cutoff-hz", "1k", "--fmax", "500", "--pooled"], capsys)
    assert code == 2 and "--fmax 500 Hz leaves no frequency above 1000 Hz (--cutoff-hz 1000)" in err


def test_data_below_the_default_cutoff_are_refused_naming_the_default(tmp_path, capsys):
    """Without --cutoff-hz, data that end below the paper's 30 Hz (SYNTHETIC, 1–20 Hz) are refused
    with a message that says 30 Hz is the default the user did not give, exit 2, no file written."""
    freq = np.geomspace(1.0, 20.0, 11)
    w = 2 * np.pi * freq
    z = np.tile(1.0 / (1.0 / R_EP + Q_EP * (1j * w) ** ALPHA + 1j * w * C_GAP), (4, 1))
    path = tmp_path / "low.nc"
    ix.save(ix.make_spectrum(freq, z, dims=("trial",)), str(path))
    out = tmp_path / "gap.json"
    code, _, err = run(["gap", path, "--area", "130e-6", "--pooled", "--out", out], capsys)
    assert code == 2, err
    assert "--cutoff-hz must be at most 20 Hz" in err and "--cutoff-hz not given: 30 Hz is the paper's default" in err, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1 and not out.exists()
