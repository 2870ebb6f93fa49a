"""One diagnosis solves each candidate fit once: a solve given the same circuits, starts and
options as one before it gives the same fits again, which change nothing (REAL
tests/fixtures/real/exampleData.csv, impedance.py 1.7, MIT)."""

from __future__ import annotations

import collections
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis import diagnosis as diagnosis_module

EXAMPLE = Path(__file__).resolve().parent / "fixtures" / "real" / "exampleData.csv"


def _counted(monkeypatch, module, name):
    """``module.name`` replaced by a wrapper that counts its calls by their exact inputs."""
    calls = collections.Counter()
    original = getattr(module, name)

    def counted(circuits, data, **options):
        key = (repr(circuits), np.asarray(data["frequency"].values).tobytes(), np.asarray(data["Z"].values).tobytes(), repr(sorted(options.items())))
        calls[key] += 1
        return original(circuits, data, **options)

    monkeypatch.setattr(module, name, counted)
    return calls


@pytest.mark.slow
def test_a_stalled_candidate_is_not_refitted_again_from_the_same_start(monkeypatch):
    """From ``R0 + (R1 + W_d) || C1`` on REAL exampleData.csv a candidate stalls short of one
    nested in it and is refitted from that one's optimum; the leaders' further starts leave it
    stalled, and the same refit from the same start was solved a second time (its fits can
    only tie the first's, kept or beaten already)."""
    calls = _counted(monkeypatch, diagnosis_module, "fit_candidates")
    ix.diagnose(ix.load(EXAMPLE), "R0 + (R1 + W_d) || C1")
    assert calls and max(calls.values()) == 1, [n for n in calls.values()]
