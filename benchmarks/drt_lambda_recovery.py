"""Which λ recovers a SYNTHETIC DRT best: GCV's (the γ `drt` reports), the L-curve's, or the
Bayesian evidence's (the credible band's, `band_lambda`)? docs/drt.md, "Credible band and
calibration" (2026-12-07).

The cases of tests/test_drt.py::test_credible_band_is_calibrated (71 points, 10 mHz–100 kHz),
complex noise of relative σ 0.1, 0.3, 1 and 2 %, seeds 100–109. For each spectrum and each λ the
non-negative γ at that fixed λ is compared with the true γ (closed forms) over the measured τ
window: relative L2 error ‖γ − γ_true‖ / ‖γ_true‖. Not part of the test suite (≈ 2–3 min on two cores):

    PYTHONPATH=. python benchmarks/drt_lambda_recovery.py
"""

import math

import numpy as np

import impedax as ix
from drt_band_near_peak import CASES, F


def error(result, truth_fn):
    lo, hi = result.window
    inside = (result.tau >= lo) & (result.tau <= hi)
    truth = truth_fn(result.tau[inside])
    return float(np.linalg.norm(result.gamma[inside] - truth) / np.linalg.norm(truth))


def main():
    names = ("gcv", "lcurve", "evidence")
    totals, wins = {k: [] for k in names}, dict.fromkeys(names, 0)
    print(f"{'case':28s} {'noise':>6s} " + " ".join(f"{k:>9s}" for k in names) + "   (mean relative L2 error of γ; median log10 λ)")
    for name, (z, truth_fn, _) in CASES.items():
        for level in (0.001, 0.003, 0.01, 0.02):
            spectra = []
            for seed in range(100, 110):
                rng = np.random.default_rng(seed)
                spectra.append(z + level * np.abs(z) * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2))
            gcv = ix.drt((F, np.stack(spectra))).results
            lcurve = ix.drt((F, np.stack(spectra)), lam_method="lcurve").results
            lams = {"gcv": [r.lam for r in gcv], "lcurve": [r.lam for r in lcurve], "evidence": [r.band_lambda for r in gcv]}
            cell = {}
            for key in names:
                errors = [error(ix.drt((F, s), lam=lam), truth_fn) for s, lam in zip(spectra, lams[key])]
                cell[key] = (float(np.mean(errors)), float(np.median(np.log10(lams[key]))))
                totals[key].append(cell[key][0])
            wins[min(cell, key=lambda k: cell[k][0])] += 1
            print(f"{name:28s} {level * 100:5.1f}% " + " ".join(f"{cell[k][0]:9.3f}" for k in names) + "   " + " ".join(f"{cell[k][1]:+.1f}" for k in names), flush=True)
    print("mean over the cells:", {k: round(float(np.mean(v)), 3) for k, v in totals.items()}, "best in cells:", wins)


if __name__ == "__main__":
    main()
