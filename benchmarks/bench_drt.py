"""DRT: impedax (Tikhonov on Gaussian RBFs, JAX) vs pyimpspec's TR-RBF, same spectra, same run.

Run: `.venv/bin/python benchmarks/bench_drt.py` (pyimpspec optional: it needs kvxopt or cvxopt;
missing peers are reported and skipped). pyDRTtools 0.2 installs but does not import without
cvxopt, which it does not declare; it is skipped. Spectra: three synthetic cases on the
battery set's 57 frequencies (9.9 kHz–0.021 Hz, 0.5 % noise) with known peaks, and a real
battery spectrum (examples/data, AutoEIS, MIT). Wall-clock medians after one warm-up call;
figures go to benchmarks/README.md.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

import impedax as ix
from _timing import median_time

ROOT = Path(__file__).resolve().parent.parent
BATTERY = ix.load(ROOT / "examples" / "data" / "autoeis_battery_cycles.nc")
F = np.asarray(BATTERY["frequency"].values)
W = 2 * np.pi * F


def _rc(r, tau):
    return r / (1 + 1j * W * tau)


def _zarc(r, tau, alpha):
    return r / (1 + (1j * W * tau) ** alpha)


def _noisy(z, seed, level=0.005):
    rng = np.random.default_rng(seed)
    return z * (1 + level * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2))


CASES = {
    # name: (Z, true peaks τ [s])
    "two R||C": (_noisy(0.1 + _rc(0.5, 1e-3) + _rc(1.0, 0.1), 1), [1e-3, 0.1]),
    "R||C+ZARC+R||C": (_noisy(0.1 + _rc(0.5, 1e-3) + _zarc(1.0, 0.03, 0.9) + _rc(0.4, 3.0), 2), [1e-3, 0.03, 3.0]),
    "two ZARC": (_noisy(0.1 + _zarc(0.7, 3e-3, 0.85) + _zarc(1.2, 0.3, 0.8), 3), [3e-3, 0.3]),
}


def _peak_error(found, truth) -> tuple[int, float]:
    """(number of peaks found, worst |log10 τ error| over the true peaks, nearest found peak)."""
    if len(found) == 0:
        return 0, float("inf")
    worst = max(min(abs(math.log10(f / t)) for f in found) for t in truth)
    return len(found), worst


def main() -> None:
    tools = {"impedax drt": lambda f, z: [p.tau_s for p in ix.drt((f, z)).peaks]}
    try:
        import pyimpspec
        from pyimpspec.analysis.drt import calculate_drt_tr_rbf

        def run_pyimpspec(f, z):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                result = calculate_drt_tr_rbf(pyimpspec.DataSet(f, z), num_procs=1)
            tau, gamma = result.get_peaks()
            keep = gamma > 0.1 * np.max(result.get_gammas())  # its peak list includes tiny ripples
            return list(np.asarray(tau)[keep])

        tools["pyimpspec TR-RBF (defaults)"] = run_pyimpspec
    except ImportError as exc:
        print(f"pyimpspec not usable ({exc}): skipped")

    spectra = {**{k: v for k, v in CASES.items()}, "battery cycle 0": (np.asarray(BATTERY["Z"].values[0]), None)}
    print(f"{'tool':30s}" + "".join(f"{name:>22s}" for name in spectra) + f"{'median ratio':>14s}")
    times = {}
    for tool, fn in tools.items():
        row, cells = {}, []
        for name, (z, truth) in spectra.items():
            row[name] = median_time(lambda: fn(F, z), 7, warmup=True)
            peaks = fn(F, z)
            if truth is None:
                cells.append(f"{row[name] * 1e3:8.1f} ms, {len(peaks)} pk")
            else:
                n, err = _peak_error(peaks, truth)
                cells.append(f"{row[name] * 1e3:7.1f} ms {n}/{len(truth)} {err:4.2f}d")
        times[tool] = row
        ratio = np.median([row[c] / times["impedax drt"][c] for c in spectra])
        print(f"{tool:30s}" + "".join(f"{c:>22s}" for c in cells) + f"{ratio:13.1f}×")
    print("cells: time per spectrum, peaks found / true, worst peak-τ error in decades")

    # 130 spectra in one call (the size of the AutoEIS battery set): synthetic arcs that drift
    rng = np.random.default_rng(7)
    stack = np.stack([
        _noisy(0.1 + _rc(0.5 * (1 + 0.3 * rng.random()), 1e-3 * 10 ** rng.uniform(-0.3, 0.3)) + _zarc(1.0 + rng.random(), 0.03 * 10 ** rng.uniform(-0.3, 0.3), 0.9) + _rc(0.4, 3.0), 100 + i)
        for i in range(130)
    ])
    batch = median_time(lambda: ix.drt((F, stack)), 5, warmup=True)
    print(f"impedax drt, 130 spectra in one call (vmapped): {batch:.2f} s warm ({batch / 130 * 1e3:.1f} ms per spectrum)")
    n_right = sum(len(r.peaks) == 3 for r in ix.drt((F, stack)).results)
    print(f"  spectra with the 3 true peaks found: {n_right}/130")


if __name__ == "__main__":
    main()
