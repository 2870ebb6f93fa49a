"""Time and peak memory of impedax commands against the number of points (issue 15).

Each row of `CASES` runs in its own process, started by a small launcher process, so that
``resource.getrusage(RUSAGE_CHILDREN).ru_maxrss`` in the launcher is the peak resident memory
of that one case. Times are wall-clock of the whole process: start-up and JIT compilation
included, as a user sees them.

A row is one entry in `CASES`: a command name, a point count and the command line to run on the
data file. To add a command, append its rows (e.g. ``*(Case("kk", n, kk_argv) for n in SIZES)``).

    python benchmarks/bench_scale.py               # every row
    python benchmarks/bench_scale.py --max 100000  # up to 100k points
    python benchmarks/bench_scale.py --only fit
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

SIZES = (1_000, 10_000, 100_000, 1_000_000)
MODEL = "R0 + R1 || C1 + R2 || C2"


@dataclass(frozen=True)
class Case:
    """One row: ``command`` on a spectrum of ``points`` frequencies, run as ``argv(data file)``."""

    command: str
    points: int
    argv: Callable[[Path], list[str]]


def load_argv(path: Path) -> list[str]:
    return [sys.executable, "-c", f"import impedax as ix; ix.load({str(path)!r})"]


def fit_argv(path: Path) -> list[str]:
    return [sys.executable, "-m", "impedax", "fit", str(path), "--model", MODEL, "--json"]


CASES = [
    *(Case("load", n, load_argv) for n in SIZES),
    *(Case("fit", n, fit_argv) for n in SIZES),
]

# the launcher: run the case, then report its wall time and its peak RSS (kB on Linux)
LAUNCHER = """
import json, resource, subprocess, sys, time
t = time.perf_counter()
done = subprocess.run(json.loads(sys.argv[1]), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
wall = time.perf_counter() - t
print(json.dumps({"code": done.returncode, "wall_s": wall, "peak_rss_kb": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss,
                  "stderr": done.stderr[-300:]}))
"""


def write_spectrum(points: int, folder: Path) -> Path:
    """``MODEL`` (10 Ω + 100 Ω ‖ 1 µF + 1 kΩ ‖ 100 µF) with 1 % noise, 10 mHz–1 MHz, as impedax CSV."""
    import impedax as ix

    rng = np.random.default_rng(15)
    f = np.geomspace(1e-2, 1e6, points)
    w = 2 * np.pi * f
    z = 10.0 + 100.0 / (1 + 1j * w * 100.0 * 1e-6) + 1000.0 / (1 + 1j * w * 1000.0 * 1e-4)
    z = z * (1 + 0.01 * (rng.standard_normal(points) + 1j * rng.standard_normal(points)))
    path = folder / f"spectrum_{points}.csv"
    ix.save(ix.make_spectrum(f, z), path)
    return path


def run_case(case: Case, data: Path) -> dict:
    done = subprocess.run([sys.executable, "-c", LAUNCHER, json.dumps(case.argv(data))], capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max", type=int, default=max(SIZES), help="largest point count to run")
    parser.add_argument("--only", action="append", help="only these commands (repeatable)")
    args = parser.parse_args()
    cases = [c for c in CASES if c.points <= args.max and (not args.only or c.command in args.only)]
    load = os.getloadavg()[0]
    print(f"# bench_scale: {len(cases)} cases, load average {load:.1f} at the start")
    print(f"{'command':<8} {'points':>9} {'file MB':>8} {'wall s':>8} {'peak RSS MB':>12}  note")
    with tempfile.TemporaryDirectory() as tmp:
        files: dict[int, Path] = {}
        for case in cases:
            if case.points not in files:
                files[case.points] = write_spectrum(case.points, Path(tmp))
            data = files[case.points]
            row = run_case(case, data)
            note = "" if row["code"] == 0 else f"exit {row['code']}: {row['stderr'].strip().splitlines()[-1] if row['stderr'].strip() else ''}"
            print(f"{case.command:<8} {case.points:>9,} {data.stat().st_size / 2**20:>8.1f} {row['wall_s']:>8.2f} {row['peak_rss_kb'] / 1024:>12.0f}  {note}", flush=True)
    print(f"# load average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
