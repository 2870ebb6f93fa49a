"""Wall time of ``impedax diagnose`` on a 60-point SYNTHETIC spectrum (≈ 20 candidates),
compilation included: cold (empty JAX persistent cache, fresh process) and warm (cache filled).

Each measurement runs the CLI in a fresh Python process, as a user would; IMPEDAX_CACHE_DIR
points at a temporary directory that is empty for the cold runs. Prints a table.

    python benchmarks/bench_diagnose.py [--repeat 2]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

CASES = {
    # name: (user circuit, numpy formula of the SYNTHETIC truth, frequency range)
    "meyer-like, CPE skin hidden (19 candidates)": (
        "C_i + R_sc || C_sc + R_f",
        lambda f: 1 / (1j * 2 * np.pi * f * 1e-9) + 1e6 / (1 + 1e6 * 5e-9 * (1j * 2 * np.pi * f) ** 0.7) + 1e4,
        (10.0, 1e6),
    ),
    "two arcs, Warburg hidden (18 candidates)": (
        "R0 + R1 || CPE1 + R2 || CPE2",
        lambda f: 10 + 400 / (1 + 400 * 1e-7 * (1j * 2 * np.pi * f) ** 0.9) + 1 / (1 / (3000 + 150 * (1 - 1j) / np.sqrt(2 * np.pi * f)) + 5e-5 * (1j * 2 * np.pi * f) ** 0.75),
        (0.01, 1e6),
    ),
}


def _spectrum(tmp: Path, name: str, formula, frange) -> Path:
    rng = np.random.default_rng(0)
    f = np.logspace(np.log10(frange[0]), np.log10(frange[1]), 60)
    z = formula(f)
    z = z + 0.01 * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    path = tmp / f"{abs(hash(name))}.csv"
    with open(path, "w") as fh:
        fh.write("frequency_hz,z_real_ohm,z_imag_ohm\n")
        for fi, zi in zip(f, z):
            fh.write(f"{float(fi)!r},{float(zi.real)!r},{float(zi.imag)!r}\n")
    return path


def _run(path: Path, model: str, cache: str) -> tuple[float, str]:
    env = dict(os.environ, IMPEDAX_CACHE_DIR=cache, PYTHONPATH=str(ROOT))
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "impedax", "diagnose", str(path), "--model", model], env=env, capture_output=True, text=True)
    elapsed = time.perf_counter() - t0
    if out.returncode != 0:
        raise SystemExit(out.stderr)
    verdict = next((line for line in out.stdout.splitlines() if line.startswith("verdict")), "")
    return elapsed, verdict


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.2f} (2-core machine; other work inflates times)")
    print(f"{'case':45s} {'cold [s]':>9s} {'warm [s]':>9s}  verdict")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for name, (model, formula, frange) in CASES.items():
            path = _spectrum(tmp, name, formula, frange)
            colds, warms = [], []
            for r in range(args.repeat):
                cache = tempfile.mkdtemp(dir=tmp)  # empty: cold
                colds.append(_run(path, model, cache)[0])
                t, verdict = _run(path, model, cache)  # same cache, now filled: warm
                warms.append(t)
            print(f"{name:45s} {min(colds):9.1f} {min(warms):9.1f}  {verdict[:60]}")


if __name__ == "__main__":
    main()
