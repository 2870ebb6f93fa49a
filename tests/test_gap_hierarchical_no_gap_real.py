"""`impedax gap` (hierarchical, the default) on the REAL battery cycles 0, 64 and 129
(examples/data/autoeis_battery_cycles.nc: a battery, not a contact; 2026-12-06 walkthrough): the
EDL fit of every cycle puts C_gap at its lower bound 0 (u = ∞). The NUTS sampling ran for about a
minute and then failed with "prior lognormal:inf,2: both numbers must be finite"."""

from pathlib import Path

import pytest

from impedax.cli import main

CYCLES = Path(__file__).parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc"


def test_trials_without_a_gap_are_named_before_the_hierarchical_sampling(capsys, monkeypatch):
    import impedax.fitting.bayes.hierarchical as hierarchical

    def sampled(*args, **kwargs):
        raise AssertionError("the hierarchical sampling ran")

    monkeypatch.setattr(hierarchical, "sample_hierarchical", sampled)
    assert main(["gap", str(CYCLES), "--area", "130e-6", "--steps", "20", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "3 of the 3 total trials (cycle=0; cycle=64; cycle=129) put C_gap at its lower bound 0" in err, err
    assert "--pooled" in err and "autoeis_battery_cycles.nc" in err and "Traceback" not in err and "lognormal:inf" not in err
