"""`impedax gap`'s text report said nothing of its sampling when it passed its checks: no R-hat,
ESS or acceptance of the hierarchical NUTS run, no chain length, τ or acceptance of the pooled
emcee run; the figures were only in the JSON (hierarchical) or nowhere (pooled), so a reader could
not tell a checked run from an unchecked one (2026-12-07). The report has a ``sampling`` line
with them. Hierarchical: the hand-built posterior of test_gap_sampling_verdict_shared (numpy
draws: 4 chains × 400, iid). Pooled: a stub with the figures given here."""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np

from test_gap_sampling_verdict_shared import _analysis, _posterior


def _line(result):
    (line,) = [x for x in result.report().splitlines() if x.startswith("sampling  ")]
    return line


def test_a_hierarchical_run_that_passed_says_its_figures():
    post = _posterior(alpha_apart=0.0)
    result = _analysis(post)
    rhat, ess = post.mixing()
    assert max(rhat.values()) < 1.05 and min(ess.values()) > 100  # (the case: it passes the checks)
    assert _line(result) == (f"sampling        hierarchical NUTS, 1600 draws: 0 divergent, R-hat up to {max(rhat.values()):.3f}, "
                             f"ESS down to {min(ess.values()):.0f} (of every sampled quantity), mean acceptance 0.85: passed its checks "
                             "(R-hat < 1.05, at most 1 % divergent)")


def test_an_unreliable_hierarchical_run_s_line_says_so():
    line = _line(_analysis(_posterior(alpha_apart=0.2)))
    assert line.endswith(": FAILED its checks (R-hat < 1.05, at most 1 % divergent): see SAMPLING UNRELIABLE above")


def _pooled(base, *, tau, steps, burn, converged, stopped):
    draws = base.hierarchical.population_parameters()
    post = SimpleNamespace(parameter_draws=lambda: draws, mean_acceptance=0.412, autocorr={"u": tau, "R_EP": tau / 2}, ess={"u": 64 * (steps - burn) / tau, "R_EP": 2e4},
                           n_walkers=64, settings={"steps": steps, "burn": burn, "thin": 1, "stopped": stopped}, chain_converged=converged, piled_up={})
    return replace(base, method="pooled", hierarchical=None, posterior=post)


def test_a_pooled_run_says_its_chain_length_in_autocorrelation_times():
    base = _analysis(_posterior(alpha_apart=0.0))
    # 4000 steps, burn 1000: 3000 kept = 37.5 τ of τ = 80 steps; ESS 64 × 3000/80 = 2400
    short = _line(_pooled(base, tau=80.0, steps=4000, burn=1000, converged=False, stopped=None))
    assert short == ("sampling        emcee, 64 walkers × 4000 steps (burn 1000), acceptance 0.41, τ up to 80 steps, ESS down to 2400: "
                     "the kept chain is 37.5 τ long, under the 50 τ it needs (see the warning)")
    done = _line(_pooled(base, tau=50.0, steps=4000, burn=1000, converged=True, stopped="converged"))
    assert done.endswith("τ up to 50 steps, ESS down to 3840: the kept chain is 60 τ long (≥ 50 τ)")
    assert "(burn 1000, automatic: stopped at 50 τ)" in done


def test_the_pooled_json_gives_the_chain_s_figures():
    """`--pooled --json` had `sampling: null` and no chain figure at all: `pooled_sampling` holds
    the line's numbers (null when hierarchical, whose figures are `sampling`'s)."""
    base = _analysis(_posterior(alpha_apart=0.0))
    assert base.summary()["pooled_sampling"] is None
    doc = _pooled(base, tau=80.0, steps=4000, burn=1000, converged=False, stopped=None).summary()
    assert doc["sampling"] is None
    assert doc["pooled_sampling"] == {"walkers": 64, "steps": 4000, "burn": 1000, "stopped": None, "acceptance": 0.412, "autocorr_max_steps": 80.0,
                                      "ess_min": 2400.0, "chain_tau": 37.5, "chain_converged": False}
