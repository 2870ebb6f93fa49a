"""F-tests of a pair nested only at a limit that leaves a parameter of the larger model not
identified (a block R2 || C2 removed: R2 -> 0 leaves C2 free; a Cole–Cole at τ -> 0 leaves α
free). The plain F distribution is then not p's reference (Davies 1977, Biometrika 64, 247;
1987, Biometrika 74, 33): p stays the plain F-test's, ``valid`` stays true, and the note says so.
SYNTHETIC spectra, from closed forms written here."""

import json

import numpy as np
import pytest

import impedax as ix
from impedax.circuits import parse
from impedax.fitting.comparison import unidentified_limits


@pytest.mark.parametrize(
    "simple, larger, expected",
    [
        ("R0 + R1 || C1", "R0 + R1 || C1 + R2 || C2", ["R2 || C2 removed: C2 is not identified when R2 -> 0"]),
        ("R0 + R1 || C1", "R0 + (R1 + R2 || C2) || C1", ["R2 || C2 removed: C2 is not identified when R2 -> 0"]),
        ("R0 + R1 || C1", "R0 + R1 || C1 + R2 || CPE2", ["R2 || CPE2 removed: CPE2.Q and CPE2.alpha are not identified when R2 -> 0"]),
        ("R0 + R1 || C1", "R0 + R1 || C1 || (R2 + C2)", ["R2 + C2 removed: C2 is not identified when R2 -> inf"]),
        ("R0 + R1 || C1", "R0 + R1 || C1 + Wo2", ["Wo2 removed: Wo2.tau is not identified when Wo2.R -> 0"]),
        ("R0 + R1 || C1", "R0 + R1 || CPE1 || CPE2", ["CPE2 removed: CPE2.alpha is not identified when CPE2.Q -> 0"]),
        ("R0 + R1 || C1", "R0 + R1 || CPE1 + Wo2", ["Wo2 removed: Wo2.tau is not identified when Wo2.R -> 0"]),  # (beside CPE1 at α = 1)
        ("R0 + R1", "R0 + CC1", ["CC1 reduced to R1: CC1.alpha is not identified when CC1.tau -> 0"]),
        ("R0 + R1", "R0 + HN1", ["HN1 reduced to R1: HN1.alpha and HN1.beta are not identified when HN1.tau -> 0"]),
        # limits that take one parameter away: on the edge of the space, nothing left free
        ("R0 + R1 || C1", "R0 + R1 || CPE1", []),
        ("R0 + R1 || C1 + W1", "R0 + R1 || C1 + Wo1", []),
        ("R0 + R1 || C1", "R0 + R1 || C1 + W1", []),
        ("R0 + R1 || CPE1", "R0 + CPE1 || (R1 + W1)", []),
        ("R0 + R1", "R0 + Ws1", []),
        ("R0 + CC1", "R0 + HN1", []),
        ("R0 + R1 || C1", "R0 + R1 || C1", []),
        ("R0 + R1 || C1", "R0 + W1", []),  # (not nested)
    ],
)
def test_unidentified_limits_name_the_parameters_a_limit_leaves_free(simple, larger, expected):
    assert unidentified_limits(parse(simple), parse(larger)) == expected


def _two_arcs():
    """SYNTHETIC: R0 = 10 Ω, 100 Ω ∥ 1 µF and 50 Ω ∥ 1 mF, 0.5 % complex noise (seed 5)."""
    f = np.geomspace(0.01, 1e5, 50)
    s = 2j * np.pi * f
    rng = np.random.default_rng(5)
    z = 10 + 100 / (1 + s * 100e-6) + 50 / (1 + s * 50e-3)
    return ix.make_spectrum(f, z * (1 + 0.005 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)))


DAVIES_LIMIT = "R2 || C2 removed: C2 is not identified when R2 -> 0"


def test_a_removed_block_gets_the_davies_note_with_the_plain_p_and_its_decisions_unchanged(tmp_path, capsys):
    from scipy import stats

    from impedax.cli import main

    data = _two_arcs()
    one = ix.fit("R0 + R1 || C1", data)
    two = ix.fit("R0 + R1 || C1 + R2 || C2", data, init=one)
    comparison = ix.compare([one, two])
    (test,) = comparison.f_tests
    assert test["valid"] and test["reason"] is None and test["boundary_limits"] == []
    assert test["unidentified_limits"] == [DAVIES_LIMIT]
    n = 2 * data.sizes["frequency"]
    f_value = (one.chi2 - two.chi2) / 2 / (two.chi2 / (n - 5))
    assert test["f"] == pytest.approx(f_value, rel=1e-9)
    assert test["p_value"] == pytest.approx(stats.f.sf(f_value, 2, n - 5), rel=1e-9)  # (the plain F distribution's p, unchanged)
    assert DAVIES_LIMIT in test["note"] and "Davies 1977" in test["note"] and "too small" in test["note"], test["note"]
    assert comparison.best == two.model  # (the second arc is real: the decision stands)
    assert f"p = {test['p_value']:.3g} ({test['note']})" in comparison.report()
    assert list(comparison.to_xarray()["f_test_note"].values) == [test["note"]]
    # the command: its text report and its JSON
    path = tmp_path / "two_arcs.csv"
    ix.save(data, path)
    argv = ["compare", str(path), "--model", "R0 + R1 || C1", "--model", "R0 + R1 || C1 + R2 || C2"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert DAVIES_LIMIT in out and "Davies 1977" in out, out
    assert main([*argv, "--json"]) == 0
    (entry,) = json.loads(capsys.readouterr().out)["f_tests"]
    assert entry["valid"] is True and DAVIES_LIMIT in entry["note"] and entry["unidentified_limits"] == [DAVIES_LIMIT]


def test_a_one_parameter_limit_keeps_its_mixture_note_alone():
    """CPE1 at α = 1 takes one parameter away: the chi-bar-squared note, word for word, and no
    Davies note. SYNTHETIC arc with α = 0.93 and 1 % noise (seed 11)."""
    f = np.geomspace(0.05, 1e5, 60)
    s = 2j * np.pi * f
    rng = np.random.default_rng(11)
    z = 10 + 100 / (1 + (s * 1e-3) ** 0.93)
    data = ix.make_spectrum(f, z * (1 + 0.01 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)))
    rc = ix.fit("R0 + R1 || C1", data)
    cpe = ix.fit("R0 + R1 || CPE1", data, init=rc)
    (test,) = ix.compare([rc, cpe]).f_tests
    assert test["valid"] and test["unidentified_limits"] == []
    assert test["note"] == ("R0 + R1 || C1 is R0 + R1 || CPE1 at the edge of its parameter space (CPE1: alpha = 1): "
                            "p is from the 50:50 chi-bar-squared mixture (Self & Liang 1987), not the plain F distribution")
    assert "Davies" not in test["note"] and "not identified" not in test["note"]
