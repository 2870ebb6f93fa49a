"""`impedax sample --json` says whether the kept chain is long enough, as a boolean
(``chain_converged``): the warning "the chain … is shorter than 50 autocorrelation times" was
text only, and ``stopped`` is null for a fixed --steps, so a program had to read the warnings'
words to tell a 40-step run's intervals from a converged one's. Oracle: the JSON's own figures,
draws per walker ≥ 50 × the largest τ (in kept draws, τ / thin), and a chain too short to
estimate τ (autocorr null) is not converged. SYNTHETIC R0 + R1 ∥ C1 (R0 = 10 Ω, R1 = 100 Ω,
C1 = 1 µF, 1 % noise) written here."""

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

F = np.geomspace(1.0, 1e5, 30)


@pytest.fixture(scope="module")
def spectrum(tmp_path_factory):
    rng = np.random.default_rng(3)
    z = 10.0 + 100.0 / (1 + 2j * np.pi * F * 100.0 * 1e-6)
    z = z * (1 + 0.01 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2))
    path = tmp_path_factory.mktemp("sample") / "rc.csv"
    ix.save(ix.make_spectrum(F, z), path)
    return path


def _json(capsys, spectrum, steps):
    assert main(["sample", str(spectrum), "--model", "R0 + R1 || C1", "--json", "--quiet", "--steps", str(steps), "--walkers", "16", "--seed", "1"]) == 0
    return json.loads(capsys.readouterr().out)


def _long_enough(doc):
    tau = list(doc["autocorr"].values())
    return all(t is not None for t in tau) and doc["draws"] >= 50 * max(max(t / doc["thin"] for t in tau), 1.0)


@pytest.mark.parametrize("steps, expected", [(20, False), (60, False), (8000, True)])
def test_the_json_says_whether_the_chain_is_long_enough(capsys, spectrum, steps, expected):
    doc = _json(capsys, spectrum, steps)
    assert _long_enough(doc) is expected  # (the oracle's case)
    assert doc["chain_converged"] is expected
    assert any("autocorrelation times" in w or "too short to estimate" in w for w in doc["warnings"]) is not expected
