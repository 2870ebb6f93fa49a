"""``impedax sample --steps N`` and ``impedax gap --steps N`` refuse the same chains: fewer than
`MIN_SAMPLER_STEPS` (20) steps, with one message that names --steps, the least and why, exit 2,
before any file is read. ``sample`` took any N ≥ 1 (2 steps: 2 draws per walker, quantiles of a
start ball) while ``gap`` refused fewer than 20."""

from __future__ import annotations

import pytest

from impedax.arguments import GAP_MIN_STEPS, MIN_SAMPLER_STEPS
from impedax.cli import main


def test_one_minimum_for_both_commands():
    assert MIN_SAMPLER_STEPS == GAP_MIN_STEPS == 20


@pytest.mark.parametrize("command", [["sample", "{missing}", "--model", "R0 + R1 || C1"], ["gap", "{missing}", "{missing}", "{missing}", "--area", "1e-4", "--pooled"]])
@pytest.mark.parametrize("steps", ["0", "1", "2", "19"])
def test_fewer_steps_than_the_minimum_are_refused_alike(tmp_path, capsys, command, steps):
    missing = str(tmp_path / "not_read.csv")  # (refused before any file is read: this one does not exist)
    argv = [missing if a == "{missing}" else a for a in command] + ["--steps", steps]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert f"--steps must be at least 20 (got {steps})" in err, err
    assert "τ" in err and "--steps auto" in err and "not_read.csv" not in err, err
    assert len(err.strip().splitlines()) == 1, err


def test_the_minimum_itself_passes_the_check(monkeypatch):
    """20 steps pass `check_steps` (what runs after it is the sampler's business)."""
    from impedax.cli.sample import check_steps

    for steps in (20, 21, 500, "auto"):
        check_steps(steps)
