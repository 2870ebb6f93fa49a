"""``--bound NAME=LO:HI`` of `impedax fit`, `sample` and `compare` (the API's ``bounds=``).
Oracle: a SYNTHETIC R0 + R1 ∥ C1 spectrum written here with numpy (R0 = 10 Ω, R1 = 100 Ω,
C1 = 1 µF, 1 % noise, seed 3): a bound below the true R1 binds (R1 on it, the other parameters
those of the fit with R1 held there), one around it changes nothing."""

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

F = np.geomspace(1.0, 1e5, 30)
MODEL = "R0 + R1 || C1"
R0, R1, C1 = 10.0, 100.0, 1e-6


@pytest.fixture(scope="module")
def spectrum(tmp_path_factory):
    rng = np.random.default_rng(3)
    z = R0 + R1 / (1 + 2j * np.pi * F * R1 * C1)
    z = z * (1 + 0.01 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2))
    path = tmp_path_factory.mktemp("bound") / "rc.csv"
    ix.save(ix.make_spectrum(F, z), path)
    return path


def _fit_json(capsys, *argv):
    assert main(["fit", *map(str, argv), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _held_fit(path, r1):
    """R0 and C1 fitted with R1 held at ``r1`` by scipy (the oracle): residuals (Z_model − Z)/|Z|
    in both parts, the weighting modulus the fit uses by default."""
    from scipy.optimize import least_squares

    data = ix.load(path)
    f, z = np.asarray(data["frequency"].values), np.asarray(data["Z"].values)

    def residual(log_p):
        r0, c1 = np.exp(log_p)
        model = r0 + r1 / (1 + 2j * np.pi * f * r1 * c1)
        rel = (model - z) / np.abs(z)
        return np.concatenate([rel.real, rel.imag])

    return np.exp(least_squares(residual, np.log([R0, C1]), xtol=1e-15, ftol=1e-15, gtol=1e-15).x)


def test_a_bound_below_the_true_value_binds(capsys, spectrum, tmp_path):
    summary = tmp_path / "fit.json"
    assert main(["fit", str(spectrum), "--model", MODEL, "--bound", "R1=10:50", "--out", str(summary)]) == 0
    out = json.loads(summary.read_text())
    assert out["params"]["R1"]["value"] == pytest.approx(50.0, rel=1e-9)
    assert out["at_bound"] == ["R1"] and out["user_bounds"] == {"R1": [10.0, 50.0]}
    # the other parameters are those of the fit with R1 held on the bound
    r0, c1 = _held_fit(spectrum, 50.0)
    assert out["params"]["R0"]["value"] == pytest.approx(r0, rel=1e-6) and out["params"]["C1"]["value"] == pytest.approx(c1, rel=1e-6)
    # the text report: "at bound" in R1's row, the warning, and the note in the command line's words
    text = capsys.readouterr().out
    row = next(line for line in text.splitlines() if line.startswith("R1 "))
    assert "at bound" in row
    assert "R1 is at its upper bound 50" in text and "(--bound)" in text and "(bounds=)" not in text


def test_a_bound_that_does_not_bind_changes_nothing(capsys, spectrum):
    free = _fit_json(capsys, spectrum, "--model", MODEL)
    assert free["user_bounds"] == {}  # (a fit without --bound: the key, empty)
    # each form: both ends, an empty lower side (the element's own 0), an empty upper side (inf, null in strict JSON)
    bounded = _fit_json(capsys, spectrum, "--model", MODEL, "--bound", "R1=10:1k", "--bound", "C1=:10u", "--bound", "R0=1m:")
    assert bounded["user_bounds"] == {"R0": [0.001, None], "R1": [10.0, 1000.0], "C1": [0.0, 1e-5]}
    assert bounded["at_bound"] == [] and free["at_bound"] == []
    for name in ("R0", "R1", "C1"):
        assert bounded["params"][name]["value"] == pytest.approx(free["params"][name]["value"], rel=1e-6)
    assert free["params"]["R1"]["value"] == pytest.approx(R1, rel=0.05)  # (the data's R1, inside the bound)


def test_sample_samples_within_the_bound(capsys, spectrum):
    assert main(["sample", str(spectrum), "--model", MODEL, "--bound", "R1=10:50", "--json", "--steps", "200", "--walkers", "16"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["user_bounds"] == {"R1": [10.0, 50.0]}
    assert 10.0 <= out["params"]["R1"]["q05"] and out["params"]["R1"]["q95"] <= 50.0


BAD = [
    (["fit", "--model", MODEL, "--bound", "r1=10:50"], ["--bound", "'r1'", "did you mean R1?"]),
    (["fit", "--model", MODEL, "--bound", "R1=50:10"], ["--bound R1=50:10", "lower end 50 must be below the upper end 10"]),
    (["fit", "--model", MODEL, "--bound", "R1=1k:1k"], ["--bound R1=1k:1k", "lower end 1000 must be below"]),
    (["fit", "--model", MODEL, "--bound", "R1=-5:10"], ["--bound R1=-5:10", "outside R1's own range (0, inf)"]),
    (["fit", "--model", "R0 + R1 || CPE1", "--bound", "CPE1.alpha=0.5:1.5"], ["--bound CPE1.alpha=0.5:1.5", "outside CPE1.alpha's own range (0, 1]"]),
    (["fit", "--model", "R0 + R1 || CPE1", "--bound", "CPE1.alpha=0:"], ["--bound CPE1.alpha=0:", "narrows nothing"]),
    (["fit", "--model", MODEL, "--bound", "R1=10:50", "--fix", "R1=20"], ["--bound R1=10:50 and --fix R1=20"]),
    (["fit", "--model", MODEL, "--bound", "R1=10:50", "--init", "R1=100"], ["--init: R1=100 is outside its bounds (10, 50)", "(--bound R1=10:50)"]),
    (["fit", "--model", MODEL, "--bound", "R1=10:50", "--init", "R1=50"], ["--init: R1=50 is on its upper bound", "(--bound R1=10:50)"]),
    (["fit", "--model", MODEL, "--bound", "R1=10"], ["--bound 'R1=10': expected NAME=LO:HI"]),
    (["fit", "--model", MODEL, "--bound", "R1=:"], ["--bound 'R1=:': give at least one end"]),
    (["fit", "--model", MODEL, "--bound", "R1=1:5", "--bound", "R1=2:3"], ["--bound: R1 given twice"]),
    (["sample", "--model", MODEL, "--bound", "R9=10:50"], ["--bound: unknown parameter 'R9'"]),
    (["sample", "--model", MODEL, "--bound", "R1=10:50", "--fix", "R1=20"], ["--bound R1=10:50 and --fix R1=20"]),
    (["sample", "--model", MODEL, "--bound", "R1=10:50", "--shared", "R0"], ["--bound", "not available with --shared"]),
    (["compare", "--model", MODEL, "--model", "R0 + R1 || CPE1", "--bound", "CPE1.alfa=0.5:1"], ["--bound: no model has a parameter 'CPE1.alfa'", "did you mean CPE1.alpha?"]),
    (["compare", "--model", MODEL, "--model", "R0 + R1 || CPE1", "--bound", "CPE1.alpha=0.5:2"], ["--bound CPE1.alpha=0.5:2", "own range (0, 1]"]),
]


@pytest.mark.parametrize("argv, words", BAD, ids=[" ".join(a[a.index("--bound"):]) + f" ({a[0]})" for a, _ in BAD])
def test_bad_bounds_are_refused_with_one_message(capsys, spectrum, argv, words):
    assert main([argv[0], str(spectrum), *argv[1:]]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for word in words:
        assert word in err, err
