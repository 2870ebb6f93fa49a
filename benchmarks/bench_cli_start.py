"""Start-up and compile wait of fresh processes.

1. ``impedax --version``, ``impedax --help``, ``fit --help``, ``inspect`` of a REAL file and
   ``info`` (the median of 11 runs after one warm-up). None imports JAX (issue 14: ≤ 0.3 s).
   Then ``import jax`` alone, which every computing command pays, with the versions of JAX and
   ml_dtypes (whose NumPy loops are registered at import: 0.7.0 took 1–2 s, 0.6.0 ~0.1 s).
2. ``--compile``: the wait of a first fit, each in a fresh process, with an empty JAX
   persistent cache (``IMPEDAX_CACHE_DIR`` pointing at a new directory: everything compiles)
   and again with that cache filled (issue 14: ``impedax fit`` on an empty cache ≤ 3 s for
   circuits up to 10 elements; the first batch call on the 130 battery cycles ≤ 10 s):

   - ``impedax fit`` CLI, whole process, on cycle 0 of AutoEIS's battery set (57 points) with
     the 8-parameter battery circuit, and on a 10-element circuit's spectrum (numpy formula
     below, 0.5 % noise, 61 points);
   - a Python process: ``import impedax`` then ``ix.fit`` of the 130 battery cycles (the batch
     solvers compile), timed from the import to the result.

Run: ``.venv/bin/python benchmarks/bench_cli_start.py [--compile] [--repeat 3]``. The load
average is printed with every figure (the 2-core machine is shared with other jobs).
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
from _timing import write_bytecode

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REAL_DATA = os.path.join(ROOT, "benchmarks", "data", "autoeis_battery_130.nc")
BATTERY_CIRCUIT = "R0 + R1 || CPE1 + R2 || CPE2 + W1"
TEN_ELEMENTS = "R0 + R1 || CPE1 + R2 || C2 + (R3 + W3) || CPE3 + L4 + Wo5"


def ten_element_spectrum(f, rng):
    """Z of TEN_ELEMENTS written apart from impedax, with 0.5 % complex noise."""
    w = 2 * np.pi * f
    s = 1j * w
    x = np.sqrt(s * 0.5)  # Wo5: R coth(√(jωτ))/√(jωτ), τ = 0.5 s, R = 40 Ω
    z = (2.0 + 1 / (1 / 30.0 + 2e-6 * s**0.85) + 1 / (1 / 50.0 + 1e-4 * s)
         + 1 / (1 / (80.0 + 15.0 * (1 - 1j) / np.sqrt(w)) + 3e-3 * s**0.8) + 1e-7 * s + 40.0 / (np.tanh(x) * x))
    return z * (1 + 0.005 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))


def median_seconds(args, runs=11):
    env = dict(os.environ, PYTHONPATH=ROOT)
    subprocess.run([sys.executable, "-m", "impedax", *args], env=env, cwd=ROOT, capture_output=True, check=True)
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "impedax", *args], env=env, cwd=ROOT, capture_output=True, check=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def import_jax_seconds(runs=5) -> tuple[float, str]:
    """Median seconds of ``import jax`` in a fresh process, and the versions imported."""
    code = "import time; t0 = time.perf_counter(); import jax, ml_dtypes; print(time.perf_counter() - t0, jax.__version__, ml_dtypes.__version__)"
    times, versions = [], ""
    for _ in range(runs):
        seconds, jax_version, dtypes_version = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
        times.append(float(seconds))
        versions = f"jax {jax_version}, ml_dtypes {dtypes_version}"
    return statistics.median(times), versions


def cli_fit_seconds(csv: str, model: str, cache: str) -> float:
    env = dict(os.environ, PYTHONPATH=ROOT, IMPEDAX_CACHE_DIR=cache)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "impedax", "fit", csv, "--model", model, "--json"], env=env, cwd=ROOT, capture_output=True, check=True)
    return time.perf_counter() - t0


def first_batch_seconds(cache: str) -> dict:
    """A fresh Python process: import impedax, the CLI's persistent cache, one batch fit of
    the 130 cycles; seconds from the import to the result."""
    code = (
        "import time, json; t0 = time.perf_counter()\n"
        "import impedax as ix\nfrom impedax.cli import _configure_jax_cache\n_configure_jax_cache()\n"
        f"data = ix.load({REAL_DATA!r}); t1 = time.perf_counter()\n"
        f"r = ix.fit({BATTERY_CIRCUIT!r}, data); t2 = time.perf_counter()\n"
        "print(json.dumps({'import_and_load_s': t1 - t0, 'first_batch_s': t2 - t1, 'total_s': t2 - t0}))\n"
    )
    env = dict(os.environ, PYTHONPATH=ROOT, IMPEDAX_CACHE_DIR=cache)
    out = subprocess.run([sys.executable, "-c", code], env=env, cwd=ROOT, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def compile_rows(repeat: int) -> None:
    sys.path.insert(0, ROOT)
    import impedax as ix

    with tempfile.TemporaryDirectory() as tmp:
        battery = os.path.join(tmp, "battery_cycle0.csv")
        ix.save(ix.load(REAL_DATA).isel(cycle=0), battery)
        ten = os.path.join(tmp, "ten_elements.csv")
        f = np.geomspace(1e-2, 1e5, 61)
        ix.save(ix.make_spectrum(f, ten_element_spectrum(f, np.random.default_rng(3))), ten)
        cases = [("impedax fit, battery cycle 0, 8 parameters (5 elements)", lambda cache: cli_fit_seconds(battery, BATTERY_CIRCUIT, cache)),
                 ("impedax fit, 10 elements, 13 parameters", lambda cache: cli_fit_seconds(ten, TEN_ELEMENTS, cache)),
                 ("import + first batch fit, 130 battery cycles", lambda cache: first_batch_seconds(cache)["total_s"])]
        print(f"{'fresh process':<48} {'empty cache [s]':>16} {'warm cache [s]':>15}   load average")
        for label, run in cases:
            cold, warm = [], []
            for i in range(repeat):
                cache = os.path.join(tmp, f"cache-{len(label)}-{i}")
                cold.append(run(cache))
                warm.append(run(cache))
            print(f"{label:<48} {statistics.median(cold):>16.2f} {statistics.median(warm):>15.2f}   {os.getloadavg()[0]:.1f}"
                  f"   (runs: {', '.join(f'{c:.1f}/{w:.1f}' for c, w in zip(cold, warm))})", flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--compile", action="store_true", help="the compile wait of first fits (empty and warm persistent cache)")
    parser.add_argument("--repeat", type=int, default=3, help="fresh processes per compile figure (median)")
    options = parser.parse_args()
    write_bytecode()  # as after a user's first run (PYTHONDONTWRITEBYTECODE would make every process compile impedax)
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    # commands that compute nothing: none imports JAX (tests/test_cli_no_jax.py)
    for args in (["--version"], ["--help"], ["fit", "--help"], ["inspect", "tests/fixtures/real/exampleDataZPlot.z"], ["info", "R0 + R1 || CPE1"]):
        print(f"impedax {' '.join(args):<45} {median_seconds(args) * 1000:7.0f} ms")
    seconds, versions = import_jax_seconds()
    print(f"{'import jax (' + versions + ')':<53} {seconds * 1000:7.0f} ms")
    if options.compile:
        compile_rows(options.repeat)
