"""Calibration of the hierarchical model, measured: how often do its 90 % and 68 % intervals of a
population median contain the generating value? And ESS/s of NUTS against emcee on the same
hierarchical posterior.

Two studies over fresh synthetic data sets (seeds 1..N):

* ``sirin``: `generate_sirin_synthetic` (u log-normal, 1 % between sessions and 7 % between
  trials, R_EP and CPE_EP.Q varying too, noise larger at low frequency); per-trial remainders;
  per-trial u, R_EP, CPE_EP.Q, shared α; the target is the population median of u,
  ε0 ε_gap A / 413 pF = 2.789 µm.
* ``two_arc``: `generate_two_arc_trials` (R0 + R1 ∥ CPE1 + R2 ∥ CPE2, 20 trials; R0 and the
  exponents shared, R1, Q1, R2, Q2 per trial); targets: population medians of R1 and R2, and R0.
* ``single``: one spectrum of R0 + R1 ∥ CPE1 + R2 ∥ CPE2 (`two_arcs`, a numpy formula here; 50
  points, 10 mHz–100 kHz, Re and Im each with Gaussian noise 1 % of |Z|), sampled by `ix.sample`
  with its defaults (emcee, proportional noise, chain length ``auto``); targets: every one of the
  seven parameters, by the equal-tailed intervals of the posterior and by the least-squares
  fit's linearised ± (value ± 1.645 σ and ± σ, default weighting).

Usage: ``python benchmarks/bench_coverage.py [--sets 50] [--study sirin|two_arc|single|all] [--ess]``
(``all``: the two hierarchical studies).
Results are appended as JSON lines to ``--out`` (default benchmarks/coverage_results.jsonl) as
they come, so an interrupted run keeps the sets it finished; the table prints the coverage with
its 95 % binomial (Wilson) interval.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from pathlib import Path

import numpy as np

import impedax as ix
from impedax.constants import EPSILON_0, EPSILON_AIR
from impedax.fitting.bayes.hierarchical import sample_hierarchical
from impedax.models import synthetic

HERE = Path(__file__).resolve().parent
AREA = 130e-6
U_TRUE = EPSILON_0 * EPSILON_AIR * AREA / synthetic.SIRIN_SYNTHETIC_TRUTH["remainder_sliding"]["C_gap"]


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """95 % Wilson score interval of a binomial proportion k/n."""
    if n == 0:
        return (0.0, 1.0)
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return centre - half, centre + half


def _covers(post, name, truth, shared=False):
    out = {}
    for level in (0.90, 0.68):
        if shared:
            j = post.shared_names.index(name)
            draws = post.shared[..., j].ravel()
            lo, hi = np.quantile(draws, [(1 - level) / 2, 1 - (1 - level) / 2])
        else:
            q = post.population(name, level=level)
            lo, hi = q["low"], q["high"]
        out[f"{int(level * 100)}"] = bool(lo <= truth <= hi)
        out[f"width{int(level * 100)}"] = float(hi - lo)
    return out


def sirin_set(seed: int, *, chains: int, warmup: int, draws: int) -> dict:
    ds = synthetic.generate_sirin_synthetic(seed)
    data = synthetic.sirin_trial_remainders(ds)
    gap = ix.gap_thickness_reparametrization("C_gap", area=AREA, eps_r=EPSILON_AIR)
    post = sample_hierarchical("R_EP || CPE_EP || C_gap", data, per_trial=("u", "R_EP", "CPE_EP.Q"), reparametrization=gap, chains=chains, warmup=warmup, draws=draws, seed=seed)
    realized = float(np.exp(np.log(ds["trial_u"].sel(contact="sliding").values).mean()))  # geometric mean of the 30 trials' true u
    return {"study": "sirin", "seed": seed, "u": _covers(post, "u", U_TRUE), "u_median": post.population("u")["value"], "u_trials_geomean": realized, "divergences": post.divergences, "seconds": post.elapsed_s, "load_1min": os.getloadavg()[0], "ess_mu_u": post.ess()["mu[u]"], "rhat_mu_u": post.rhat()["mu[u]"]}


def two_arc_set(seed: int, *, chains: int, warmup: int, draws: int) -> dict:
    data = synthetic.generate_two_arc_trials(seed)
    post = sample_hierarchical("R0 + R1 || CPE1 + R2 || CPE2", data, per_trial=("R1", "CPE1.Q", "R2", "CPE2.Q"), chains=chains, warmup=warmup, draws=draws, seed=seed)
    t = synthetic.TWO_ARC_TRUTH
    return {"study": "two_arc", "seed": seed, "R1": _covers(post, "R1", t["R1"]), "R2": _covers(post, "R2", t["R2"]), "R0": _covers(post, "R0", t["R0"], shared=True), "divergences": post.divergences, "seconds": post.elapsed_s, "load_1min": os.getloadavg()[0], "ess": post.ess()}


SINGLE_TRUTH = {"R0": 20.0, "R1": 100.0, "CPE1.Q": 1e-5, "CPE1.alpha": 0.85, "R2": 200.0, "CPE2.Q": 1e-3, "CPE2.alpha": 0.8}
SINGLE_NOISE = 0.01  # of |Z|, on Re and Im each


def two_arcs(f: np.ndarray, p: dict) -> np.ndarray:
    """R0 + R1/(1 + R1 Q1 (jω)^α1) + R2/(1 + R2 Q2 (jω)^α2), written apart from impedax's compiler."""
    jw = 2j * np.pi * f
    return p["R0"] + p["R1"] / (1 + p["R1"] * p["CPE1.Q"] * jw ** p["CPE1.alpha"]) + p["R2"] / (1 + p["R2"] * p["CPE2.Q"] * jw ** p["CPE2.alpha"])


def single_set(seed: int, **_) -> dict:
    rng = np.random.default_rng(seed)
    f = np.logspace(-2, 5, 50)
    z = two_arcs(f, SINGLE_TRUTH)
    ds = ix.make_spectrum(f, z + SINGLE_NOISE * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))
    t = time.perf_counter()
    post = ix.sample("R0 + R1 || CPE1 + R2 || CPE2", ds, seed=seed, progress=False)
    seconds = time.perf_counter() - t
    q = post.quantiles(circuit=True)
    fit = ix.fit("R0 + R1 || CPE1 + R2 || CPE2", ds)
    row = {"study": "single", "seed": seed, "seconds": seconds, "load_1min": os.getloadavg()[0], "steps": post.settings.get("steps"), "warnings": len(post.warnings)}
    for name, truth in SINGLE_TRUTH.items():
        s = q.sel(param=name)
        value, sd = fit.values[name], fit.stderr.get(name, float("nan"))
        row[name] = {
            "90": bool(float(s["q05"]) <= truth <= float(s["q95"])), "68": bool(float(s["q16"]) <= truth <= float(s["q84"])),
            "lsq90": bool(abs(value - truth) <= 1.645 * sd), "lsq68": bool(abs(value - truth) <= sd),
        }
    return row


def table(rows: list[dict]) -> str:
    lines = ["| study | target | sets | 90 % covers | (95 % binomial) | 68 % covers | (95 % binomial) |", "|---|---|---|---|---|---|---|"]
    for study, targets in (("sirin", ("u",)), ("two_arc", ("R1", "R2", "R0")), ("single", tuple(SINGLE_TRUTH))):
        sub = [r for r in rows if r["study"] == study]
        if not sub:
            continue
        for target in targets:
            for kind, (k90_key, k68_key) in (("", ("90", "68")), (" (least squares ±)", ("lsq90", "lsq68"))):
                if k90_key not in sub[0][target]:
                    continue
                n = len(sub)
                k90 = sum(r[target][k90_key] for r in sub)
                k68 = sum(r[target][k68_key] for r in sub)
                a, b = wilson(k90, n)
                c, d = wilson(k68, n)
                lines.append(f"| {study}{kind} | {target} | {n} | {k90 / n:.0%} | {a:.0%}–{b:.0%} | {k68 / n:.0%} | {c:.0%}–{d:.0%} |")
    return "\n".join(lines)


def ess_per_second(seed: int = 1) -> dict:
    """NUTS vs emcee on the Sirin hierarchical posterior (the same log density, jitted and
    vectorised over walkers for emcee): ESS/s of μ_u, wall time including sampling only."""
    import emcee
    import jax
    import jax.numpy as jnp
    from jax.flatten_util import ravel_pytree

    from impedax.fitting.bayes import hierarchical as h

    ds = synthetic.generate_sirin_synthetic(seed)
    data = synthetic.sirin_trial_remainders(ds)
    gap = ix.gap_thickness_reparametrization("C_gap", area=AREA, eps_r=EPSILON_AIR)
    kw = dict(per_trial=("u", "R_EP", "CPE_EP.Q"), reparametrization=gap, seed=seed)
    sample_hierarchical("R_EP || CPE_EP || C_gap", data, chains=4, warmup=300, draws=300, **kw)  # compile
    t0 = time.perf_counter()
    post = sample_hierarchical("R_EP || CPE_EP || C_gap", data, chains=4, warmup=300, draws=300, **kw)
    nuts_s = time.perf_counter() - t0
    nuts_ess = post.ess()["mu[u]"]
    # emcee on the same density, flattened, vectorised over walkers, started at the least-squares fits
    logdensity, example = h.hierarchical_log_density("R_EP || CPE_EP || C_gap", data, **kw)
    flat0, unravel = ravel_pytree(example)
    dim = flat0.size
    marker = jax.tree_util.tree_map(jnp.zeros_like, example)
    marker["mu"] = marker["mu"].at[0].set(1.0)
    mu_u_index = int(np.argmax(np.asarray(ravel_pytree(marker)[0])))
    walkers = 2 * dim + 2
    batched = jax.jit(jax.vmap(lambda v: logdensity(unravel(v))))
    rng = np.random.default_rng(seed)
    p0 = np.asarray(flat0)[None] + 1e-4 * rng.standard_normal((walkers, dim))
    sampler = emcee.EnsembleSampler(walkers, dim, lambda x: np.asarray(batched(jnp.asarray(x))), vectorize=True)
    steps = 4000
    batched(jnp.asarray(p0))  # compile outside the timing
    t0 = time.perf_counter()
    sampler.run_mcmc(p0, steps, progress=False)
    emcee_s = time.perf_counter() - t0
    mu_u = sampler.get_chain(discard=steps // 2)[:, :, mu_u_index]  # (steps, walkers)
    tau = emcee.autocorr.integrated_time(mu_u, tol=0)[0]
    emcee_ess = mu_u.shape[0] * walkers / tau
    return {"dim": int(dim), "nuts_seconds": nuts_s, "nuts_ess_mu_u": nuts_ess, "nuts_ess_per_s": nuts_ess / nuts_s, "emcee_walkers": walkers, "emcee_steps": steps, "emcee_seconds": emcee_s, "emcee_tau_steps": float(tau), "emcee_ess_mu_u": float(emcee_ess), "emcee_ess_per_s": float(emcee_ess / emcee_s)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", type=int, default=50)
    ap.add_argument("--first", type=int, default=1)
    ap.add_argument("--study", choices=("sirin", "two_arc", "single", "all"), default="all")
    ap.add_argument("--chains", type=int, default=2)
    ap.add_argument("--warmup", type=int, default=250)
    ap.add_argument("--draws", type=int, default=250)
    ap.add_argument("--ess", action="store_true", help="also measure ESS/s of NUTS and emcee")
    ap.add_argument("--out", default=str(HERE / "coverage_results.jsonl"))
    args = ap.parse_args()
    out = Path(args.out)
    studies = {"sirin": sirin_set, "two_arc": two_arc_set, "single": single_set}
    chosen = ["sirin", "two_arc"] if args.study == "all" else [args.study]
    rows = []
    for seed in range(args.first, args.first + args.sets):
        for study in chosen:
            row = studies[study](seed, chains=args.chains, warmup=args.warmup, draws=args.draws)
            rows.append(row)
            with out.open("a") as fh:
                fh.write(json.dumps(row) + "\n")
            print(json.dumps(row), flush=True)
    print(table(rows))
    if args.ess:
        print(json.dumps(ess_per_second(), indent=1))


if __name__ == "__main__":
    main()
