"""`impedax.clear_caches` releases the compiled programs (their memory maps) of a process;
`impedax.use_compilation_cache` keeps them on disk for the next one."""

import os

import numpy as np
import pytest

import impedax as ix

pytestmark = pytest.mark.skipif(not os.path.exists("/proc/self/maps"), reason="needs Linux's /proc/self/maps")


def _memory_maps() -> int:
    with open("/proc/self/maps") as maps:
        return sum(1 for _ in maps)


@pytest.mark.slow  # (an end-to-end run of ~10 s: make test-all; the fast suite's 15-minute budget)
def test_clear_caches_releases_what_fits_compiled():
    """The first fit of a process also maps what no cache holds and nothing should release: the
    shared libraries it imports (scipy.special, OpenBLAS, numpy.fft: ~160 maps) and the stacks of
    the threads it starts (~100). A warm-up fit of a sixth circuit maps them before the count, so
    that the count is of compiled programs alone (without it 805 of 1,069 maps were released, 75 %,
    all of them the five circuits' programs; with it 805 of 814)."""
    freq = np.logspace(5, -1, 30)
    omega = 2 * np.pi * freq
    data = ix.make_spectrum(freq, 10 + 100 / (1 + 1j * omega * 100 * 1e-6))  # R0 + R1 ‖ C1
    ix.fit("R0 + R1 || G1", data)  # the warm-up: libraries and threads, then released below
    ix.clear_caches()
    before = _memory_maps()
    for circuit in ("R0 + R1 || C1", "R0 + R1 || CPE1", "R0 + R1 || C1 + R2 || C2", "R0 + (R1 + W1) || C1", "L0 + R0 + R1 || CPE1"):
        ix.fit(circuit, data)
    grown = _memory_maps() - before
    ix.clear_caches()
    released = before + grown - _memory_maps()
    assert grown > 100  # five circuits compiled their solvers
    assert released > 0.8 * grown


def test_use_compilation_cache_keeps_compiled_programs_on_disk(tmp_path):
    """`impedax.use_compilation_cache` (run in a child process: it sets JAX's configuration for
    the whole process) points JAX's persistent cache at the folder, whose entries a fit then
    writes (the compiled program and impedax's stored program beside it); a folder that cannot
    be created leaves JAX's setting alone and returns None."""
    import subprocess
    import sys

    blocker = tmp_path / "a_file"
    blocker.write_text("")
    folder = tmp_path / "cache"
    script = f"""
import jax, numpy as np, impedax as ix
assert ix.use_compilation_cache({str(blocker / 'sub')!r}) is None
assert jax.config.jax_compilation_cache_dir is None
assert ix.use_compilation_cache({str(folder)!r}) == {str(folder)!r}
assert jax.config.jax_compilation_cache_dir == {str(folder)!r}
f = np.logspace(5, -1, 30)
ix.fit("R0 + R1 || C1", ix.make_spectrum(f, 10 + 100 / (1 + 2j * np.pi * f * 1e-4)))
"""
    env = {k: v for k, v in os.environ.items() if k not in ("IMPEDAX_CACHE_DIR", "JAX_COMPILATION_CACHE_DIR")}
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr
    written = [p.name for p in folder.iterdir()]
    assert any(name.endswith("-cache") for name in written), written  # JAX's compiled program
    assert "impedax-exported" in written, written
