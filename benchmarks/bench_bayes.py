"""Bayesian sampling speed: impedax's vectorized log-probability against emcee driving
impedance.py's prediction one walker at a time, on the same synthetic data and posterior.

Run: `.venv/bin/python benchmarks/bench_bayes.py`. Prints a table; figures go to
benchmarks/README.md. Both sides use emcee's stretch move with the same walkers, priors
(log-uniform, sampled in log space), proportional noise model and data (R0 + R1 || CPE1,
50 frequencies, synthetic 1% noise). Wall-clock times on this machine, after compilation.
"""

from __future__ import annotations

import math
import time
import warnings

import emcee
import numpy as np

import impedax as ix

FREQ = np.geomspace(0.1, 1e5, 50)
TRUTH = {"R0": 20.0, "R1": 5000.0, "CPE1.Q": 3e-6, "CPE1.alpha": 0.8}


def synthetic_data(rng):
    w = 2 * np.pi * FREQ
    z_cpe = 1 / (TRUTH["CPE1.Q"] * (1j * w) ** TRUTH["CPE1.alpha"])
    z = TRUTH["R0"] + 1 / (1 / TRUTH["R1"] + 1 / z_cpe)
    return z + 0.01 * np.abs(z) * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape))


def capture_log_prob(circuit, data, init, walkers):
    """The exact vectorized function impedax hands to emcee (captured from one short run)."""
    captured = {}
    original = emcee.EnsembleSampler.__init__

    def spy(self, nwalkers, ndim, log_prob_fn, **kw):
        captured["fn"] = log_prob_fn
        original(self, nwalkers, ndim, log_prob_fn, **kw)

    emcee.EnsembleSampler.__init__ = spy
    try:
        post = ix.sample(circuit, data, init=init, walkers=walkers, steps=20, burn=5, progress=False)
    finally:
        emcee.EnsembleSampler.__init__ = original
    return captured["fn"], post


def impedance_py_log_prob(z_data, bounds):
    """Same posterior, evaluated with impedance.py's CustomCircuit.predict per walker."""
    from impedance.models.circuits import CustomCircuit

    circuit = CustomCircuit("R0-p(R1,CPE1)", initial_guess=[10.0, 1000.0, 1e-6, 0.8])
    scale = np.abs(z_data)
    kinds, lo, hi = [k for k, _, _ in bounds], np.array([a for _, a, _ in bounds]), np.array([b for _, _, b in bounds])

    def log_prior(y):  # in y = ln x: log-uniform is flat, uniform carries the Jacobian x
        return sum(y[i] - math.log(hi[i] - lo[i]) if k == "uniform" else -math.log(math.log(hi[i] / lo[i])) for i, k in enumerate(kinds))

    def log_prob(y):
        x = np.exp(y)
        if np.any(x <= lo) or np.any(x > hi):
            return -np.inf
        circuit.parameters_ = list(x[:4])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            z = circuit.predict(FREQ)
        sigma = x[4] * scale
        r = z - z_data
        ll = np.sum(-0.5 * (r.real**2 + r.imag**2) / sigma**2 - 2 * np.log(sigma) - math.log(2 * math.pi))
        return float(ll + log_prior(y))

    return log_prob


def evals_per_second(fn, coords, seconds=2.0):
    fn(coords)
    n, t0 = 0, time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        fn(coords)
        n += coords.shape[0]
    return n / (time.perf_counter() - t0)


def ess_per_second(log_prob, p0, steps, vectorize, seed=0):
    sampler = emcee.EnsembleSampler(p0.shape[0], p0.shape[1], log_prob, vectorize=vectorize)
    sampler.random_state = np.random.RandomState(seed).get_state()
    t0 = time.perf_counter()
    sampler.run_mcmc(p0, steps, skip_initial_state_check=True)
    elapsed = time.perf_counter() - t0
    chain = sampler.get_chain(discard=steps // 4)
    tau = emcee.autocorr.integrated_time(chain, tol=0, quiet=True)
    ess = chain.shape[0] * chain.shape[1] / np.max(tau)  # the worst-mixing parameter
    return ess / elapsed, ess, elapsed, float(np.max(tau))


def main():
    rng = np.random.default_rng(0)
    data = ix.make_spectrum(FREQ, synthetic_data(rng))
    circuit = "R0 + R1 || CPE1"
    init = ix.fit(circuit, data)
    rows = []
    ours = {}
    for walkers in (64, 256):
        fn, post = capture_log_prob(circuit, data, init, walkers)
        coords = np.log(post.draws[:, -1, :])  # all parameters are sampled in log space here
        ours[walkers] = (fn, coords, post)
        rows.append((f"impedax vectorized log-prob, {walkers} walkers", evals_per_second(fn, coords), "evals/s"))
    _, coords64, post64 = ours[64]
    bounds = [(post64.priors[n].kind, post64.priors[n].a, post64.priors[n].b) for n in post64.names]
    baseline = impedance_py_log_prob(data["Z"].values, bounds)
    ours_lp, base_lp = ours[64][0](coords64[:4]), np.array([baseline(y) for y in coords64[:4]])
    np.testing.assert_allclose(base_lp, ours_lp, rtol=1e-9)  # the same posterior on both sides
    rate_base = evals_per_second(lambda c: [baseline(y) for y in c], coords64[:16], seconds=3.0)
    rows.append(("impedance.py predict per walker (emcee baseline)", rate_base, "evals/s"))

    ess_rows = []
    for walkers, steps in ((32, 4000), (256, 1000)):
        p0 = np.tile(coords64, (walkers // 64 + 1, 1))[:walkers] + 1e-6 * rng.normal(size=(walkers, coords64.shape[1]))
        rate, ess, elapsed, tau = ess_per_second(ours[64 if walkers <= 64 else 256][0], p0, steps, True)
        ess_rows.append((walkers, steps, rate, ess, elapsed, tau))
        rows.append((f"impedax ESS/s ({walkers} walkers, {steps} steps: τ_max {tau:.0f}, ESS {ess:.0f} in {elapsed:.1f} s)", rate, "ESS/s"))
    ess_per_eval = ess_rows[0][3] / (32 * 4000 * 0.75)
    rate_b, ess_b, t_b, tau_b = ess_per_second(baseline, coords64[:32], 600, False)
    rows.append((f"impedance.py ESS/s (32 walkers, 600 steps: τ_max {tau_b:.0f}, ESS {ess_b:.0f} in {t_b:.1f} s)", rate_b, "ESS/s"))
    implied = rate_base * ess_per_eval
    rows.append(("impedance.py ESS/s implied (its evals/s × ESS per evaluation of the same sampler)", implied, "ESS/s"))
    width = max(len(r[0]) for r in rows)
    for name, value, unit in rows:
        print(f"{name:<{width}}  {value:>12,.0f} {unit}")
    print(f"log-prob evaluations: {rows[0][1] / rate_base:.0f}× (64 walkers), {rows[1][1] / rate_base:.0f}× (256 walkers) the impedance.py baseline")
    for walkers, steps, rate, *_ in ess_rows:
        print(f"effective samples per second, impedax with {walkers} walkers: {rate / rate_b:.0f}× measured, {rate / implied:.0f}× implied impedance.py baseline")
    return rows


if __name__ == "__main__":
    main()
