"""What `impedax kk`'s next step says of diagnose and refine is what they do with the flagged
points: they leave them out themselves where the test passes without them, or where they are a
short run at an end of the band, and otherwise keep them. On REAL BioLogic (4 lone points inside
the band; without them the test still fails) the line said "impedax refine leaves the
KK-flagged points out by itself", and refine then kept all four in every fit, saying so.
The oracle is `ix.diagnose` on the same data (which points it masks) and the KK test without the
points. The other spectrum is SYNTHETIC (numpy formulas written here, fixed seed)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from pathlib import Path

import impedax as ix
from cli_run import run

DIAGNOSE_WORDS = ("diagnose and refine leave KK-flagged points out by themselves only where the test passes without them (a few erratic points) "
                  "or where they are a short run at an end of the band, and say so; otherwise they keep them in every fit, as the data's problem")

# SYNTHETIC: 100 Ω + 1 kΩ ‖ 1 µF (τ = 1 ms), 41 points from 100 kHz to 1 Hz (8 a decade), 0.5 % noise
FREQ = np.geomspace(1e5, 1.0, 41)


def rc_spectrum(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    z = 100.0 + 1000.0 / (1.0 + 1j * 2 * np.pi * FREQ * 1e-3)
    return z * (1.0 + 0.005 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)) / math.sqrt(2))


def saved(tmp_path, z):
    path = tmp_path / "spectrum.csv"
    np.savetxt(path, np.column_stack([FREQ, z.real, z.imag]), delimiter=",", header="freq,zreal,zimag", comments="")
    return path


def next_lines(out: str) -> list[str]:
    lines = out.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("next:"))
    return lines[start:]


REAL = Path(__file__).parent / "fixtures" / "real"


def test_biologics_next_step_does_not_say_refine_leaves_its_points_out(capsys):
    """REAL BioLogic: without the 4 points the test still fails (15.2 Hz), the case where
    diagnose and refine keep them; the line says they keep them then."""
    path = REAL / "exampleDataBioLogic.mpt"
    code, out, err = run(["kk", path], capsys)
    assert code == 0, err
    lines = next_lines(out)
    assert lines[0].endswith("--exclude 5.34,56.2,123,270")
    assert "leaves the KK-flagged points out by itself" not in out
    assert lines[1] == f"  impedax fit, diagnose and refine take the same options; {DIAGNOSE_WORDS}"
    data = ix.load(path)
    result = ix.kk_test(data)
    assert not ix.kk_test(data.drop_sel(frequency=result.excludable_frequencies)).valid  # (the condition under which they are kept)


@pytest.mark.slow
def test_biologics_points_are_kept_by_diagnose():
    """The oracle of the words above on the same file: diagnose masks none of the 4 points, and says so."""
    diagnosis = ix.diagnose(REAL / "exampleDataBioLogic.mpt", "R0 + R1 || C1", progress=False)
    assert len(diagnosis.masked_points) == 0 and "5.34 Hz, 56.2 Hz, 123 Hz, 270 Hz" in diagnosis.kk_flagged_kept


def test_a_lone_spike_is_left_out_by_diagnose_as_the_words_say(tmp_path, capsys):
    """SYNTHETIC: one point 20 % off inside the band; the test passes without it, the case where
    diagnose leaves it out, as it does (the oracle)."""
    z = rc_spectrum(0)
    z[20] *= 1.2  # 316 Hz
    code, out, err = run(["kk", saved(tmp_path, z)], capsys)
    assert code == 0, err
    lines = next_lines(out)
    assert lines[0].endswith("--exclude 316") and DIAGNOSE_WORDS in lines[1]
    assert ix.kk_test((np.delete(FREQ, 20), np.delete(z, 20))).valid
    diagnosis = ix.diagnose((FREQ, z), "R0 + R1 || C1", progress=False)
    assert list(diagnosis.masked_points) == [FREQ[20]]
    text = ix.kk_test((FREQ, z)).report()  # (the Python report: the same words after its own)
    assert "refine leaves the KK-flagged points out by itself" not in text and f"fit, diagnose and refine take the data so trimmed; {DIAGNOSE_WORDS}" in text
