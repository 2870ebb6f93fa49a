"""Coverage of the DRT's 90 % credible band over the whole measured window and near the peaks,
and the bias of the peak height (docs/drt.md, "Credible band and calibration"; 2026-12-07).

SYNTHETIC spectra from numpy formulas: 71 points, 10 mHz–100 kHz, the cases of
tests/test_drt.py::test_credible_band_is_calibrated, complex noise of relative σ `level`,
seeds 100–109. Not part of the test suite (≈ 1 min on two cores):

    PYTHONPATH=. python benchmarks/drt_band_near_peak.py
"""

import math

import numpy as np

import impedax as ix

F = np.logspace(-2, 5, 71)
W = 2 * np.pi * F
NEAR_DECADES = 0.5  # "near a peak": within this many decades of a true peak's τ


def zarc(r, tau0, alpha):
    return r / (1 + (1j * W * tau0) ** alpha)


def hn(r, tau0, alpha, beta):
    return r / (1 + (1j * W * tau0) ** alpha) ** beta


def zarc_gamma(tau, r, tau0, alpha):
    """Fuoss–Kirkwood: γ = R/(2π) sin((1−α)π)/(cosh(α ln(τ/τ₀)) − cos((1−α)π))."""
    return r / (2 * math.pi) * math.sin((1 - alpha) * math.pi) / (np.cosh(alpha * np.log(tau / tau0)) - math.cos((1 - alpha) * math.pi))


def hn_gamma(tau, r, tau0, alpha, beta):
    """Stieltjes inversion of R/(1 + (sτ₀)^α)^β at s = e^{jπ}/τ."""
    s_tau0 = (tau0 / tau) ** alpha * np.exp(1j * math.pi * alpha)
    return np.abs(np.imag(r / (1 + s_tau0) ** beta)) / math.pi


CASES = {  # name: (Z, true γ, τ of the true peaks)
    "ZARC 1 kΩ, 10 ms, α 0.8": (10 + zarc(1000, 1e-2, 0.8), lambda t: zarc_gamma(t, 1000, 1e-2, 0.8), [1e-2]),
    "ZARC α 0.6": (10 + zarc(1000, 1e-2, 0.6), lambda t: zarc_gamma(t, 1000, 1e-2, 0.6), [1e-2]),
    "two ZARCs": (10 + zarc(500, 1e-4, 0.85) + zarc(1000, 1e-1, 0.75), lambda t: zarc_gamma(t, 500, 1e-4, 0.85) + zarc_gamma(t, 1000, 1e-1, 0.75), [1e-4, 1e-1]),
    "HN α 0.9 β 0.85": (10 + hn(1000, 1e-2, 0.9, 0.85), lambda t: hn_gamma(t, 1000, 1e-2, 0.9, 0.85), None),
}


def measure(result, truth_fn, peak_taus):
    tau = result.tau
    lo, hi = result.window
    inside = (tau >= lo) & (tau <= hi)
    truth = truth_fn(tau)
    covered = (result.gamma_q05 <= truth) & (truth <= result.gamma_q95)
    if peak_taus is None:  # the true maximum on the grid
        peak_taus = [float(tau[inside][np.argmax(truth[inside])])]
    near = np.zeros_like(inside)
    heights = []
    for t0 in peak_taus:
        around = np.abs(np.log10(tau / t0)) <= NEAR_DECADES
        near |= around
        heights.append(result.gamma[around].max() / truth[around].max())
    return covered[inside].mean(), covered[near & inside].mean(), float(np.mean(heights))


def main():
    print(f"{'case':28s} {'noise':>6s} {'window':>7s} {'±0.5 dec':>9s} {'height/true':>12s}")
    for name, (z, truth_fn, peak_taus) in CASES.items():
        for level in (0.0, 0.003, 0.01, 0.03, 0.05):
            seeds = range(100, 110) if level else [0]
            spectra = []
            for seed in seeds:
                rng = np.random.default_rng(seed)
                spectra.append(z + level * np.abs(z) * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2))
            batch = ix.drt((F, np.stack(spectra)))
            rows = np.array([measure(r, truth_fn, peak_taus) for r in batch.results])
            window, near, height = rows.mean(axis=0)
            print(f"{name:28s} {level * 100:5.1f}% {window:7.2f} {near:9.2f} {height:12.2f}")


if __name__ == "__main__":
    main()
