"""Time per spectrum of the linear Kramers–Kronig test: impedax vs impedance.py linKK vs pyimpspec.

Run: `.venv/bin/python benchmarks/bench_kk.py` (pyimpspec and impedance are optional; missing
peers are reported and skipped). All tools run in this process on identical synthetic spectra
(61 points, 1 % noise), wall-clock medians; figures go to benchmarks/README.md.

`bench_kk.py --scale [N ...]`: time and peak resident memory of one `kk_test` (and of
`impedax kk --json` on a CSV file) at 1k, 10k, 100k and 1M points, each in a fresh subprocess
(peak RSS of that process, so imports are included: about 0.2 GB of it is Python + JAX + numpy).

`bench_kk.py --scale-zhit [N ...]`: the same for one `zhit` of `10 Ω + 1 kΩ‖10 µF` over
1 mHz–1 MHz with 1 % complex Gaussian noise (σ = 1 % of |Z| split over Re and Im), 3 seeds a size.
"""

from __future__ import annotations

import contextlib
import io
import warnings

import numpy as np

import impedax as ix
from _timing import median_time

F_EIS = np.geomspace(0.1, 1e5, 61)
F_FINGER = np.geomspace(1.0, 1e6, 61)


def _spectra():
    """Synthetic spectra from numpy formulas (RC, R-CPE, Randles+Warburg, two arcs, finger EDL)."""
    w, wf = 2 * np.pi * F_EIS, 2 * np.pi * F_FINGER
    cases = {
        "RC": (F_EIS, 10 + 1000 / (1 + 1j * w * 1e-3)),
        "R-CPE": (F_EIS, 10 + 1 / (1 / 1000 + 1e-5 * (1j * w) ** 0.8)),
        "Randles+W": (F_EIS, 10 + 1 / (1j * w * 2e-5 + 1 / (100 + 50 * (1 - 1j) / np.sqrt(w)))),
        "two arcs": (F_EIS, 10 + 500 / (1 + 1j * w * 1e-4) + 2000 / (1 + 1j * w * 1e-1)),
        "finger EDL": (F_FINGER, 1 / (1 / 2e6 + 1j * wf * 2e-9 + 1j * wf * 413e-12)),
    }
    rng = np.random.default_rng(0)
    return {k: (f, z + 0.01 * np.abs(z) * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size))) for k, (f, z) in cases.items()}


def main() -> None:
    spectra = _spectra()
    tools = {"impedax kk_test": (lambda f, z: ix.kk_test((f, z)), 30)}
    try:
        from impedance import validation

        # impedance.py eval()s model text built from repr() of numpy scalars ("np.float64(...)")
        validation.circuit_elements.setdefault("np", np)
        def run_linkk(f, z):
            with contextlib.redirect_stdout(io.StringIO()):  # linKK prints progress every 10 M
                return validation.linKK(f, z, c=0.85, max_M=50, fit_type="complex")

        tools["impedance.py linKK (complex)"] = (run_linkk, 10)
    except ImportError:
        print("impedance.py not installed: skipped")
    try:
        import pyimpspec

        def run_pyimpspec(f, z, **kw):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                return pyimpspec.perform_kramers_kronig_test(pyimpspec.DataSet(f, z), num_procs=1, **kw)

        tools["pyimpspec (defaults)"] = (run_pyimpspec, 3)
    except ImportError:
        print("pyimpspec not installed: skipped")

    batch = np.stack([z for f, z in spectra.values() if f is F_EIS] * 50)
    t_batch = median_time(lambda: ix.kk_test_batch((F_EIS, batch)), 5, warmup=True) / batch.shape[0]

    times = {name: {case: median_time(lambda: fn(f, z), repeat, warmup=True) for case, (f, z) in spectra.items()} for name, (fn, repeat) in tools.items()}
    base = times["impedax kk_test"]
    print(f"{'tool':40s}" + "".join(f"{c:>12s}" for c in spectra) + f"{'median ratio':>14s}")
    for name, row in times.items():
        ratio = np.median([row[c] / base[c] for c in spectra])
        print(f"{name:40s}" + "".join(f"{row[c] * 1e3:10.2f}ms" for c in spectra) + f"{ratio:13.1f}×")
    print(f"impedax kk_test_batch, {batch.shape[0]} EIS spectra at once: {t_batch * 1e3:.2f} ms per spectrum")


_SCALE_CHILD = """
import resource, sys, time
import numpy as np
import impedax as ix
n = int(sys.argv[1])
f = np.geomspace(0.1, 1e5, n)
w = 2 * np.pi * f
z = 100 + 1000 / (1 + 1j * w * 1e-3)
rng = np.random.default_rng(0)
z = z + 0.01 * np.abs(z) * (rng.standard_normal(n) + 1j * rng.standard_normal(n))
start = time.perf_counter()
result = ix.kk_test((f, z))
elapsed = time.perf_counter() - start
print(elapsed, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024, result.valid, result.n_rc)
"""


_SCALE_ZHIT_CHILD = """
import math, resource, sys, time
import numpy as np
import impedax as ix
n, seed = int(sys.argv[1]), int(sys.argv[2])
f = np.geomspace(1e-3, 1e6, n)
w = 2 * np.pi * f
z = 10 + 1000 / (1 + 1j * w * 1e-2)
rng = np.random.default_rng(seed)
z = z + 0.01 * np.abs(z) * (rng.standard_normal(n) + 1j * rng.standard_normal(n)) / math.sqrt(2)
start = time.perf_counter()
result = ix.zhit((f, z))
elapsed = time.perf_counter() - start
print(elapsed, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024, result.valid, int(result.flagged.sum()))
"""


def scale_zhit(sizes, seeds=3) -> None:
    """Each size and seed in its own process: zhit time [s], peak RSS [GB], verdict, flagged points."""
    import subprocess
    import sys

    print(f"{'points':>9s} {'seed':>4s} {'zhit [s]':>9s} {'peak RSS [GB]':>14s} {'valid':>6s} {'flagged':>8s}")
    for n in sizes:
        for seed in range(seeds):
            out = subprocess.run([sys.executable, "-c", _SCALE_ZHIT_CHILD, str(n), str(seed)], capture_output=True, text=True)
            if out.returncode != 0:
                print(f"{n:9d} {seed:4d}  failed: {out.stderr.strip().splitlines()[-1] if out.stderr.strip() else out.returncode}")
                continue
            elapsed, rss, valid, flagged = out.stdout.split()
            print(f"{n:9d} {seed:4d} {float(elapsed):9.2f} {int(rss) / 1e9:14.2f} {valid:>6s} {flagged:>8s}", flush=True)


def scale(sizes) -> None:
    """Each size in its own process: kk_test time [s], peak RSS [GB], verdict and M."""
    import subprocess
    import sys

    print(f"{'points':>9s} {'kk_test [s]':>12s} {'peak RSS [GB]':>14s} {'valid':>6s} {'M':>4s}")
    for n in sizes:
        out = subprocess.run([sys.executable, "-c", _SCALE_CHILD, str(n)], capture_output=True, text=True)
        if out.returncode != 0:
            print(f"{n:9d}  failed: {out.stderr.strip().splitlines()[-1] if out.stderr.strip() else out.returncode}")
            continue
        elapsed, rss, valid, m = out.stdout.split()
        print(f"{n:9d} {float(elapsed):12.2f} {int(rss) / 1e9:14.2f} {valid:>6s} {m:>4s}", flush=True)


if __name__ == "__main__":
    import sys

    if "--scale-zhit" in sys.argv:
        sizes = [int(a) for a in sys.argv[sys.argv.index("--scale-zhit") + 1 :]] or [1_000, 10_000, 100_000, 1_000_000]
        scale_zhit(sizes)
    elif "--scale" in sys.argv:
        sizes = [int(a) for a in sys.argv[sys.argv.index("--scale") + 1 :]] or [1_000, 10_000, 100_000, 1_000_000]
        scale(sizes)
    else:
        main()
