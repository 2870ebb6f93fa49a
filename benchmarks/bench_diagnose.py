"""Wall time of ``impedax diagnose`` on 60-point SYNTHETIC spectra (14–25 candidates; user
circuits of 3 to 8 elements), compilation included: cold (empty JAX persistent cache, fresh
process) and warm (cache filled).

Each measurement runs the CLI in a fresh Python process, as a user would; IMPEDAX_CACHE_DIR
points at a temporary directory that is empty for the cold runs. Prints a table with the
fastest of ``--repeat`` runs and the load averages seen at their starts.

    python benchmarks/bench_diagnose.py [--repeat 2] [--only PREFIX]
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
from _timing import write_bytecode

ROOT = Path(__file__).resolve().parent.parent

def _zarc(f, r, q, alpha):
    """R ∥ CPE: R/(1 + R·Q·(jω)^α)."""
    return r / (1 + r * q * (1j * 2 * np.pi * f) ** alpha)


CASES = {
    # name: (user circuit, numpy formula of the SYNTHETIC truth, frequency range)
    "3 elements, CPE hidden (14 candidates)": (
        "R0 + R1 || C1",
        lambda f: 50 + _zarc(f, 3e3, 2e-6, 0.75),
        (0.1, 1e5),
    ),
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
    "8-element finger, stray C hidden (25 candidates)": (
        "R_f + R_sk || CPE_sk + R_EP || CPE_EP || C_gap + R_ts || C_ts",
        lambda f: 1 / (1 / (2e3 + _zarc(f, 3e5, 2e-9, 0.7) + 1 / (1 / 2e7 + 2e-9 * (1j * 2 * np.pi * f) ** 0.3 + 4e-10 * 1j * 2 * np.pi * f)
                            + _zarc(f, 5e3, 1e-8, 1.0)) + 5e-12 * 1j * 2 * np.pi * f),
        (1.0, 1e6),
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


def _run(path: Path, model: str, cache: str) -> tuple[float, float, str]:
    """(wall time [s], load average at the start, verdict line) of one fresh CLI process."""
    env = dict(os.environ, IMPEDAX_CACHE_DIR=cache, PYTHONPATH=str(ROOT))
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "impedax", "diagnose", str(path), "--model", model], env=env, cwd=str(ROOT), capture_output=True, text=True)
    elapsed = time.perf_counter() - t0
    if out.returncode != 0:
        raise SystemExit(out.stderr)
    verdict = next((line for line in out.stdout.splitlines() if line.startswith("verdict")), "")
    return elapsed, load, verdict


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--only", default="", help="run only the cases whose name starts with this")
    args = ap.parse_args()
    write_bytecode()  # as after a user's first run
    print(f"load average before: {os.getloadavg()[0]:.2f} (2-core machine; other work inflates times)")
    print(f"{'case':50s} {'cold [s]':>9s} {'warm [s]':>9s} {'load':>10s}  verdict")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for name, (model, formula, frange) in CASES.items():
            if not name.startswith(args.only):
                continue
            path = _spectrum(tmp, name, formula, frange)
            colds, warms, loads = [], [], []
            for r in range(args.repeat):
                cache = tempfile.mkdtemp(dir=tmp)  # empty: cold
                t, load, _ = _run(path, model, cache)
                colds.append(t)
                t, load_warm, verdict = _run(path, model, cache)  # same cache, now filled: warm
                warms.append(t)
                loads += [load, load_warm]
            print(f"{name:50s} {min(colds):9.1f} {min(warms):9.1f} {min(loads):4.1f}–{max(loads):4.1f}  {verdict[:60]}", flush=True)


if __name__ == "__main__":
    main()
