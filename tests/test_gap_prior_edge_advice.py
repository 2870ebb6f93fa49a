"""`impedax gap --pooled` passed on the sampler's advice for an EDL parameter piled up at an end of
its prior, "— give R_EP a prior that says how large it can be" (REAL exampleDataGamry.DTA and
exampleDataBioLogic.mpt as single contacts, 2026-12-06), which neither `impedax gap` nor
`gap_analysis` can follow: they take no prior. The gap analysis now says what the pile-up means for
u, by u's correlation with the parameter in the draws (numpy's, computed here on draws we make)."""

import math

import numpy as np

from impedax.models.gap import _prior_edge_advice

LEAD = "R_EP piles up against the upper end of its prior loguniform:1.6,5.1e+15 (3 % of the draws …): the prior, not the data, sets the upper end of its 90 % interval (q95 = 1.48e+15 Ω); the data allow larger values"


def _draws(r_target, seed=0, n=4000):
    """u and R_EP draws, log-normal, whose logs correlate by about ``r_target``."""
    rng = np.random.default_rng(seed)
    a, b = rng.standard_normal((2, n))
    return {"u": np.exp(np.log(2e-6) + 0.1 * a), "R_EP": np.exp(30 + 3 * (r_target * a + math.sqrt(1 - r_target**2) * b)), "C_gap": np.ones(n)}


def test_the_advice_becomes_what_the_pile_up_means_for_u():
    draws = _draws(0.6)
    r = float(np.corrcoef(np.log(draws["u"]), np.log(draws["R_EP"]))[0, 1])
    (said,) = _prior_edge_advice([LEAD + " — give R_EP a prior that says how large it can be"], {"R_EP": "upper"}, draws)
    assert "give R_EP a prior" not in said and said.startswith(LEAD + "; the gap analysis takes no prior: "), said
    assert f"u's correlation with R_EP in the draws (log space) is {r:+.2f}, so bounding R_EP would narrow u's interval by at most {(1 - math.sqrt(1 - r * r)) * 100:.0f} %" in said, said


def test_other_warnings_and_a_parameter_not_piled_up_are_left_as_they_are():
    draws = _draws(0.1)
    other = "the chain is too short to estimate τ"
    warning = LEAD + " — give R_EP a prior that says how large it can be"
    assert _prior_edge_advice([other, warning], {}, draws) == [other, warning]
    (both,) = _prior_edge_advice([LEAD.replace("upper end", "lower end") + " — give R_EP a prior that says how small it can be"], {"R_EP": "both"}, draws)
    assert "the gap analysis takes no prior" in both


def test_the_ep_cpe_vanishing_points_to_u_not_determined():
    """CPE_EP.Q at its prior's lower end is the gap analysis's reason that u is not determined
    (SYNTHETIC shipped example, stationary total, --pooled): no correlation is offered as comfort."""
    draws = {**_draws(0.0), "CPE_EP.Q": np.exp(np.random.default_rng(1).standard_normal(4000))}
    lead = "CPE_EP.Q piles up against the lower end of its prior loguniform:5.8e-12,36.6 (12 % …): the prior, not the data, sets the lower end of its 90 % interval; the data allow smaller values"
    (said,) = _prior_edge_advice([lead + " — give CPE_EP.Q a prior that says how small it can be"], {"CPE_EP.Q": "lower"}, draws)
    assert said == lead + "; the gap analysis takes no prior: the EP CPE vanishing leaves C_gap and the EP branch not told apart (the warning 'u is NOT determined')"
