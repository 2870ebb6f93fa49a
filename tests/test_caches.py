"""`impedax.clear_caches` releases the compiled programs (their memory maps) of a process."""

import os

import numpy as np
import pytest

import impedax as ix

pytestmark = pytest.mark.skipif(not os.path.exists("/proc/self/maps"), reason="needs Linux's /proc/self/maps")


def _memory_maps() -> int:
    with open("/proc/self/maps") as maps:
        return sum(1 for _ in maps)


def test_clear_caches_releases_what_fits_compiled():
    freq = np.logspace(5, -1, 30)
    omega = 2 * np.pi * freq
    data = ix.make_spectrum(freq, 10 + 100 / (1 + 1j * omega * 100 * 1e-6))  # R0 + R1 ‖ C1
    ix.clear_caches()
    before = _memory_maps()
    for circuit in ("R0 + R1 || C1", "R0 + R1 || CPE1", "R0 + R1 || C1 + R2 || C2", "R0 + (R1 + W1) || C1", "L0 + R0 + R1 || CPE1"):
        ix.fit(circuit, data)
    grown = _memory_maps() - before
    ix.clear_caches()
    released = before + grown - _memory_maps()
    assert grown > 100  # five circuits compiled their solvers
    assert released > 0.8 * grown
