"""`impedax sample --json` says whether the kept chain is long enough, as a boolean
(``chain_converged``): the warning "the chain … is shorter than 50 autocorrelation times" was
text only, and ``stopped`` is null for a fixed --steps, so a program had to read the warnings'
words to tell a 40-step run's intervals from a converged one's. Oracle: the JSON's own figures,
draws per walker ≥ 50 × the largest τ (in kept draws, τ / thin), and a chain too short to
estimate τ (autocorr null) is not converged. SYNTHETIC R0 + R1 ∥ C1 (R0 = 10 Ω, R1 = 100 Ω,
C1 = 1 µF, 1 % noise) of test_cli_sample_options."""

import json

import pytest

from impedax.cli import main
from test_cli_sample_options import spectrum  # noqa: F401 (the module fixture: its SYNTHETIC R0 + R1 ∥ C1 file)


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
