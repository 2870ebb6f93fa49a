"""Wall time of ``impedax refine DATA --model "R0 + R1 || C1"`` on the 12 real spectra of
tests/fixtures/real/ (impedance.py 1.7 and AutoEIS 0.0.44 example files, MIT), as a user runs
it: each measurement is a fresh CLI process, compilation included; cold with an empty JAX
persistent cache (IMPEDAX_CACHE_DIR a new temporary directory), warm with the cache that the
cold run of the same spectrum filled. Issue 18's target is refine ≤ 20 s warm on each.

Prints one row per spectrum: the fastest cold and warm time of ``--repeat`` runs, the load
averages seen at their starts, and the final model and rms_rel of the warm run's ``--json``
(the same as bench_real_spectra.py's table in docs/diagnosis.md, which times all 12 in one
process instead).

    python benchmarks/bench_refine_cli.py [--repeat 1] [--only PREFIX] [--warm-only]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
from _timing import write_bytecode  # noqa: E402
from bench_real_spectra import REAL, SPECTRA, START  # noqa: E402


def _run(path: Path, cache: str) -> tuple[float, float, dict]:
    """(wall time [s], load average at the start, the --json summary) of one fresh CLI process."""
    env = dict(os.environ, IMPEDAX_CACHE_DIR=cache, PYTHONPATH=str(ROOT))
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "impedax", "refine", str(path), "--model", START, "--json"],
                         env=env, cwd=str(ROOT), capture_output=True, text=True)
    elapsed = time.perf_counter() - t0
    if out.returncode != 0:
        raise SystemExit(f"{path.name}: exit {out.returncode}\n{out.stderr}")
    return elapsed, load, json.loads(out.stdout)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--only", default="", help="run only spectra whose file name starts with this")
    ap.add_argument("--warm-only", action="store_true", help="fill the cache without timing it, then time the warm runs")
    args = ap.parse_args(argv)
    write_bytecode()  # as after a user's first run
    print(f"load average before: {os.getloadavg()[0]:.2f} (2-core machine; other work inflates times)")
    print("| data | cold [s] | warm [s] | load | final model | rms_rel | k |")
    print("|---|---|---|---|---|---|---|")
    warm_times = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in SPECTRA:
            if not name.startswith(args.only):
                continue
            colds, warms, loads = [], [], []
            for _ in range(args.repeat):
                cache = tempfile.mkdtemp(dir=tmp)  # empty: cold
                t, load, _ = _run(REAL / name, cache)
                colds.append(t)
                loads.append(load)
                t, load, summary = _run(REAL / name, cache)  # the same cache, now filled: warm
                warms.append(t)
                loads.append(load)
            warm_times.append(min(warms))
            cold = "—" if args.warm_only else f"{min(colds):.1f}"
            print(f"| {name} | {cold} | {min(warms):.1f} | {min(loads):.1f}–{max(loads):.1f} | `{summary['final_model']}` "
                  f"| {100 * summary['final_rms_rel']:.3g} % | {summary['n_params']} |", flush=True)
    if warm_times:
        print(f"warm: {sum(t <= 20 for t in warm_times)} of {len(warm_times)} within 20 s; slowest {max(warm_times):.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
