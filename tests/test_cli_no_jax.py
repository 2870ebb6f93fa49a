"""Commands that compute nothing do not import JAX (its import is most of a fresh process's
1–2 s): each runs in a fresh Python process, which then reports whether ``jax`` is in
``sys.modules``. benchmarks/README.md, "Start-up of the command line", has the wall times."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
REAL = ROOT / "tests" / "fixtures" / "real"


def fresh_process(code: str, env: dict | None = None) -> dict:
    """Run ``code`` in a new interpreter; it ends by printing a JSON object, returned."""
    environment = {**os.environ, "PYTHONPATH": str(ROOT), **(env or {})}
    for name in ("JAX_COMPILATION_CACHE_DIR", "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS", "IMPEDAX_PLUGINS"):
        if env is None or name not in env:
            environment.pop(name, None)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=environment, cwd=ROOT, timeout=300)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_the_compilation_cache_is_set_without_importing_jax(tmp_path):
    """`impedax.use_compilation_cache` (which every command calls first) leaves JAX unimported
    and hands it the folder and the 0.05 s threshold that JAX reads when it is imported; until
    2026-12-06 it imported JAX itself, so `impedax inspect` of a REAL file spent ~1.5 s on it."""
    folder = tmp_path / "cache"
    result = fresh_process(f"""
import json, sys
import impedax as ix
given = ix.use_compilation_cache({str(folder)!r})
before = "jax" in sys.modules
import jax
print(json.dumps({{"given": given, "jax_before": before, "dir": jax.config.jax_compilation_cache_dir,
                  "min_s": jax.config.jax_persistent_cache_min_compile_time_secs}}))
""")
    assert result == {"given": str(folder), "jax_before": False, "dir": str(folder), "min_s": 0.05}
    assert folder.is_dir()
