"""Wall-clock timing shared by the benchmark scripts."""

from __future__ import annotations

import time

import numpy as np


def median_time(fn, repeat: int, *, number: int = 1, warmup: bool = False, block=lambda out: out) -> float:
    """Median over ``repeat`` runs of the time of one call of ``fn()`` (averaged over ``number``
    calls per run). ``warmup`` calls it once first; ``block`` waits for the last result (e.g.
    ``jax.block_until_ready``) before the clock stops."""
    if warmup:
        block(fn())
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        for _ in range(number):
            out = fn()
        block(out)
        times.append((time.perf_counter() - t) / number)
    return float(np.median(times))


def write_bytecode() -> None:
    """Write impedax's bytecode (``impedax/**/__pycache__``) before fresh processes are timed,
    as Python does at a user's first run. Where PYTHONDONTWRITEBYTECODE is set (it is on the
    benchmark machine) no process writes it, and every one would compile impedax's modules from
    source: 0.2–0.4 s of each fresh process (benchmarks/README.md, "Bytecode")."""
    import compileall
    from pathlib import Path

    compileall.compile_dir(str(Path(__file__).resolve().parent.parent / "impedax"), quiet=1)
