"""`impedax gap`'s sampling verdict (SAMPLING UNRELIABLE, the JSON's ``sampling``) read the R-hat
and ESS of the population medians and spreads only, while the warnings under it read every
sampled quantity: a run of the SYNTHETIC demo files with --steps 40 headed "R-hat up to 1.091,
ESS down to 22" above a warning "CPE_EP.alpha (1.13)", ESS 15 (2026-12-07), and a shared CPE_EP.alpha
whose chains disagreed raised no alarm at all, though u moves with it. The posterior here is
built by hand from numpy draws (no sampling): iid normal draws give split-R̂ ≈ 1 and ESS ≈ the
draw count; two chains held apart by 20 % give split-R̂ ≫ 1.05 by construction."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import xarray as xr

import impedax as ix
from impedax.fitting.bayes.hierarchical import HierarchicalPosterior
from impedax.models.gap import GapAnalysis
from impedax.models.sirin import paper_gap_estimate, remainder_circuit, remaining_impedance

EPS0 = 8.8541878128e-12  # vacuum permittivity [F/m], CODATA 2018
EPS_AIR = 1.00059
AREA = 130e-6  # [m²]
GAP = 2.8e-6  # [m]
CHAINS, DRAWS = 4, 400


def _posterior(alpha_apart: float) -> HierarchicalPosterior:
    """u, R_EP, CPE_EP.Q per trial (μ, spreads iid across chains), CPE_EP.alpha shared: iid about
    0.3 in every chain, each chain's draws scaled by 1 + ``alpha_apart`` × its index / 3."""
    rng = np.random.default_rng(7)
    f = np.geomspace(1.0, 1e6, 13)
    centre = np.log([GAP, 1e8, 4e-9])
    mu = centre + 0.01 * rng.standard_normal((CHAINS, DRAWS, 3))
    spread = np.exp(np.log(0.07) + 0.05 * rng.standard_normal((CHAINS, DRAWS, 3)))
    alpha = 0.3 * (1 + 0.01 * rng.standard_normal((CHAINS, DRAWS))) * (1 + alpha_apart * np.arange(CHAINS)[:, None] / 3)
    trials = 3
    trial_values = np.exp(mu[:, :, None, :] + np.zeros((1, 1, trials, 1)))
    z = np.ones((trials, f.size), complex)
    return HierarchicalPosterior(
        circuit=remainder_circuit("CPE"), trial_names=("u", "R_EP", "CPE_EP.Q"), shared_names=("CPE_EP.alpha",), mu=mu, spread=spread,
        spread_session=np.zeros_like(spread), trial_values=trial_values, shared=alpha[..., None], delta=np.zeros((CHAINS, DRAWS)), frequency=f, z_data=z,
        nu=np.full(f.size, 0.01), trial_index=xr.DataArray(np.arange(trials), dims="trial"), sessions=1, discrepancy=False, divergences=0,
        step_size=np.full(CHAINS, 0.1), mean_tree_steps=7.0, mean_acceptance=0.85, elapsed_s=1.0,
        reparametrization=ix.gap_thickness_reparametrization("C_gap", area=AREA, eps_r=EPS_AIR))


def _analysis(post) -> GapAnalysis:
    f = np.geomspace(1.0, 1e6, 13)
    c_gap = EPS0 * EPS_AIR * AREA / GAP
    z = 1.0 / (1.0 / 1e8 + 2j * np.pi * f * c_gap)
    spectra = [ix.make_spectrum(f, np.stack([zz, zz * 1.01]), dims=("trial",)) for zz in (z + 2e3, np.full(f.size, 1e3 + 0j), np.full(f.size, 1e3 + 0j))]
    names = {"R_EP": (1e8, "Ohm"), "CPE_EP.Q": (4e-9, "F s^(alpha-1)"), "CPE_EP.alpha": (0.3, "1"), "C_gap": (c_gap, "F")}
    fit = SimpleNamespace(frequency=f, z_model=z, rms_rel=0.02, chi2_red=0.1, weighting="sigma", model="R_EP || CPE_EP || C_gap",
                          values={n: v for n, (v, _) in names.items()}, stderr={n: 0.01 * v for n, (v, _) in names.items()},
                          to_table=lambda: [{"name": n, "unit": unit} for n, (_, unit) in names.items()])
    band = np.geomspace(1e-3, 1e-2, f.size)
    force = xr.Dataset({k: (("branch", "frequency"), np.stack([band * s, band * s])) for k, s in (("median", 1.0), ("q05", 0.9), ("q95", 1.1))},
                       coords={"branch": ["with_ep", "without_ep"], "frequency": f})
    return GapAnalysis(remaining_impedance(*spectra), paper_gap_estimate(*spectra, area=AREA), fit, fit, None, force, AREA, 75.0, "CPE",
                       method="hierarchical", hierarchical=post)


def test_a_shared_parameter_whose_chains_disagree_makes_the_sampling_unreliable():
    post = _posterior(alpha_apart=0.2)
    warned = [w for w in post.warnings if w.startswith("R-hat above 1.05 for")]
    assert warned and "CPE_EP.alpha" in warned[0]  # (the oracle's case: the warnings see it)
    (alarm,) = _analysis(post).alarms
    assert alarm.startswith("SAMPLING UNRELIABLE: 0 divergent transitions of 1600 draws, R-hat up to ")
    sampling = _analysis(post).summary()["sampling"]
    assert sampling["rhat_max"] > 1.5 and sampling["rhat"]["CPE_EP.alpha"] == sampling["rhat_max"]
    assert f"R-hat up to {sampling['rhat_max']:.3f}" in alarm
    # the keys the JSON had are kept
    assert {"mu[u]", "mu[R_EP]", "mu[CPE_EP.Q]", "spread[u]", "spread[R_EP]", "spread[CPE_EP.Q]"} <= set(sampling["rhat"])
    assert {"mu[u]", "spread[u]", "CPE_EP.alpha"} <= set(sampling["ess"])


def test_the_headline_s_r_hat_and_ess_are_the_report_s():
    """The figures the headline quotes are the largest R-hat and the smallest ESS of every sampled
    quantity, as the posterior's own report line ("sampler: … R-hat up to …, ESS down to …")."""
    post = _posterior(alpha_apart=0.2)
    sampling = _analysis(post).summary()["sampling"]
    line = post.report().splitlines()
    sampler = next(s for s in line if s.startswith("sampler:"))
    assert f"R-hat up to {sampling['rhat_max']:.3f}, ESS down to {sampling['ess_min']:.0f}," in sampler


def test_chains_that_agree_raise_no_alarm():
    post = _posterior(alpha_apart=0.0)
    assert not [w for w in post.warnings if "R-hat" in w]
    assert _analysis(post).alarms == ()
    assert _analysis(post).summary()["sampling"]["rhat_max"] < 1.05


def test_the_json_s_sampling_carries_the_mean_acceptance_the_report_line_shows():
    """The report's sampling line says "mean acceptance 0.85"; the JSON's ``sampling`` had the
    divergences, draws, R-hat and ESS but not it (a walkthrough, 2026-12-07). The posterior
    here has ``mean_acceptance=0.85`` by construction."""
    analysis = _analysis(_posterior(alpha_apart=0.0))
    assert analysis.summary()["sampling"]["acceptance"] == 0.85
    (line,) = [ln for ln in analysis.report().splitlines() if ln.startswith("sampling ")]
    assert f"mean acceptance {analysis.summary()['sampling']['acceptance']:.2f}" in line
