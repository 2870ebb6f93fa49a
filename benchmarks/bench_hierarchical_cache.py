"""Fresh-process wall time of the gap analysis (`impedax.models.gap.gap_analysis`, the
hierarchical NUTS sampler of `impedax gap`) on the embedded SYNTHETIC Sirin data, cold (a new,
empty IMPEDAX_CACHE_DIR) and then warm (the cache the cold run filled), with the persistent
cache set up as the command line does. A short run (``--steps`` draws and warm-up steps per
chain, default 20) so the compilation dominates. Prints per run: the load average at its start,
the wall time, the sampler's time, the median of u (the same draws cold and warm), the cache's
files, and how many programs JAX refused to store for their host callbacks.

    python benchmarks/bench_hierarchical_cache.py [--steps 20] [--repeat 1]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

CHILD = """
import sys, time, logging
import jax
jax.config.update("jax_explain_cache_misses", True)
logging.basicConfig(level=logging.WARNING)
import numpy as np
from impedax.cli import _configure_jax_cache
_configure_jax_cache()
from impedax.models import example_spectra
from impedax.models.gap import gap_analysis
s = example_spectra()
r = gap_analysis(s["total_sliding"], s["skin"], s["touchscreen"], area=130e-6, v0=75.0, steps=int(sys.argv[1]), progress=False)
print(f"{r.hierarchical.elapsed_s:.1f} {np.median(r.draws('u')):.10e}")
"""


def run(cache: str, steps: int) -> str:
    env = dict(os.environ, IMPEDAX_CACHE_DIR=cache, PYTHONPATH=str(ROOT))
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", CHILD, str(steps)], env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if out.returncode != 0:
        raise SystemExit(out.stderr[-2000:])
    sampler, u = out.stdout.split()
    files = sum(len(f) for _, _, f in os.walk(cache))
    refused = out.stderr.count("because it uses host callbacks")
    return f"load {load:.1f}  wall {wall:.1f} s  sampler {float(sampler):.1f} s  u {float(u) * 1e6:.6f} µm  cache files {files}  refused (host callbacks) {refused}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory(prefix="impedax-bench-cache-") as cache:
            print("cold ", run(cache, args.steps), flush=True)
            print("warm ", run(cache, args.steps), flush=True)


if __name__ == "__main__":
    main()
