"""Start-up time of ``impedax --version`` and ``impedax --help`` (fresh processes; the median
of 11 runs after one warm-up). Neither should import JAX (issue 14: ≤ 0.3 s)."""

import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def median_seconds(args, runs=11):
    env = dict(os.environ, PYTHONPATH=ROOT)
    subprocess.run([sys.executable, "-m", "impedax", *args], env=env, capture_output=True, check=True)
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "impedax", *args], env=env, capture_output=True, check=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


if __name__ == "__main__":
    for args in (["--version"], ["--help"], ["fit", "--help"]):
        print(f"impedax {' '.join(args):<12} {median_seconds(args) * 1000:7.0f} ms")
