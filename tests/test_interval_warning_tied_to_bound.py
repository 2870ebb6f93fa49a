"""The warning that the least-squares start's linearised standard errors differ from the
posterior's 68 % half-widths says why for a parameter tied to one at a bound: on REAL Gamry with
R0 + R1 ∥ CPE1 it read "R0 (10×; its fit is at a bound, …), R1 (3.9×)", R1 with no reason,
where R1's linearised error is wide because the linearisation lets R0 (at 0, r = −0.98 with R1
in the fit) pass its bound. Oracle: the correlation computed here with numpy from the fit's
covariance; the ratio from numpy's quantiles of the draws."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.bayes.diagnostics import interval_warnings, tied_to_bound

REAL = Path(__file__).parent / "fixtures" / "real"


def test_a_parameter_correlated_with_one_at_a_bound_is_named_with_it():
    sd = np.array([600.0, 650.0, 1e-8])
    corr = np.array([[1.0, -0.978, 0.3], [-0.978, 1.0, 0.5], [0.3, 0.5, 1.0]])  # (by hand: R1 tied to R0, Q not)
    tied = tied_to_bound(("R0", "R1", "Q"), corr * np.outer(sd, sd), ("R0",))
    assert set(tied) == {"R1"} and tied["R1"][0] == "R0" and tied["R1"][1] == pytest.approx(-0.978) and tied["R1"][2] == "whose fit is at a bound"
    (text,) = interval_warnings({"R0": 600.0, "R1": 650.0, "Q": 3e-8}, {"R0": 60.0, "R1": 165.0, "Q": 1e-8}, chain_converged=True, at_bound=("R0",), tied=tied)
    assert "R1 (3.9×; correlated with R0 (r = -0.98 in the least-squares fit), whose fit is at a bound)" in text, text
    assert "Q (3×)" in text  # (no reason known: none given)
    assert tied_to_bound(("R0", "R1"), np.eye(3), ("R0",)) == {}  # (a covariance of other parameters: nothing)


@pytest.mark.slow
def test_real_gamry_names_r1_with_r0_at_its_bound():
    data = ix.load(REAL / "exampleDataGamry.DTA")
    start = ix.fit("R0 + R1 || CPE1", data, weighting="modulus", progress=False)
    assert start.at_bound == ("R0",)
    names = list(start.free_names)
    cov = np.asarray(start.covariance, float)
    r = cov[names.index("R0"), names.index("R1")] / np.sqrt(cov[names.index("R0"), names.index("R0")] * cov[names.index("R1"), names.index("R1")])
    assert r < -0.9  # (the case: R1 tied to R0)
    post = ix.sample("R0 + R1 || CPE1", data, init=start, seed=1, steps=1200, progress=False)
    draws = post.samples["R1"]
    ratio = start.linearised_stderr["R1"] / (0.5 * (np.quantile(draws, 0.84) - np.quantile(draws, 0.16)))
    assert ratio > 2.0  # (numpy's quantiles: R1 is beyond the warning's 2×)
    (text,) = [w for w in post.warnings if "linearised standard errors differ" in w]
    assert f"R1 ({ix.data.format_factor(ratio)}×; correlated with R0 (r = {r:+.2f} in the least-squares fit), whose fit is at a bound)" in text, text


@pytest.mark.slow
def test_real_battery_joint_posterior_names_r2_with_cpe2_alpha_of_its_cycle():
    """REAL battery cycles, ``shared=["CPE1.alpha"]`` over cycle (800 steps): R2[cycle=64] was named
    "(2.2×)" bare beside CPE2.alpha[cycle=64] at 1; r read here from the global fit's covariance."""
    data = ix.load(Path(__file__).parent.parent / "examples" / "data" / "autoeis_battery_cycles.nc")
    post = ix.sample("R0 + R1 || CPE1 + R2 || CPE2 + W1", data, shared=["CPE1.alpha"], over="cycle", steps=800, seed=1, progress=False)
    cov = post.fit.dataset["covariance"].sel(cycle=64)
    r = float(cov.sel(free_param="R2", free_param_2="CPE2.alpha") / np.sqrt(cov.sel(free_param="R2", free_param_2="R2") * cov.sel(free_param="CPE2.alpha", free_param_2="CPE2.alpha")))
    assert r < -0.8
    (text,) = [w for w in post.warnings if "linearised standard errors differ" in w]
    assert f"R2[cycle=64] (" in text and f"correlated with CPE2.alpha[cycle=64] (r = {r:+.2f} in the least-squares fit), whose fit is at a bound)" in text, text


def test_a_parameter_correlated_with_an_undetermined_one_is_named_with_it():
    """REAL exampleData.csv, R0 + R1 ∥ CPE1 + R2 ∥ CPE2 (1500 steps): "CPE2.alpha (2.6×)" stood
    bare beside R2, whose relative standard error is 9.2e5 % (r = −0.93 in the fit); by hand here."""
    sd = np.array([5.3e6, 0.2, 170.0])
    corr = np.array([[1.0, -0.93, -0.84], [-0.93, 1.0, 0.97], [-0.84, 0.97, 1.0]])
    tied = tied_to_bound(("R2", "CPE2.alpha", "CPE2.Q"), corr * np.outer(sd, sd), (), ("R2",))
    assert tied == {"CPE2.alpha": ("R2", pytest.approx(-0.93), "which the data do not determine"), "CPE2.Q": ("R2", pytest.approx(-0.84), "which the data do not determine")}
    (text,) = interval_warnings({"R2": 5.3e6, "CPE2.alpha": 0.2}, {"R2": 2e4, "CPE2.alpha": 0.077}, chain_converged=True, piled_up=("R2",), tied=tied)
    assert "CPE2.alpha (2.6×; correlated with R2 (r = -0.93 in the least-squares fit), which the data do not determine)" in text, text


@pytest.mark.slow
def test_real_example_data_names_cpe2_alpha_with_the_undetermined_r2():
    data = ix.load(REAL / "exampleData.csv")
    post = ix.sample("R0 + R1 || CPE1 + R2 || CPE2", data, seed=1, steps=1500, progress=False)
    assert post.undetermined == ("R2",)
    names = list(post.fit.free_names)
    cov = np.asarray(post.fit.covariance, float)
    i, j = names.index("CPE2.alpha"), names.index("R2")
    r = cov[i, j] / np.sqrt(cov[i, i] * cov[j, j])
    (text,) = [w for w in post.warnings if "linearised standard errors differ" in w]
    assert f"CPE2.alpha (" in text and f"correlated with R2 (r = {r:+.2f} in the least-squares fit), which the data do not determine)" in text, text
