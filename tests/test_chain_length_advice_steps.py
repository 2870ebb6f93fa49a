"""The chain-length warning says about how many steps would do: "run more steps" alone left a
user of `--steps 1500` on REAL exampleData.csv (R0 + R1 ∥ CPE1 + R2 ∥ CPE2; τ = 61 steps,
1125 kept draws) to guess. Oracle: τ from emcee's own estimator (``emcee.autocorr``) on the
posterior's draws, and the steps by hand: 50 τ of kept draws, with a quarter burnt, rounded up
to 500."""

import math

import emcee
import numpy as np
import pytest

import impedax as ix
from impedax.fitting.bayes.diagnostics import steps_needed


def _spectrum():
    """SYNTHETIC R0 + R1 ∥ C1 (20 Ω, 500 Ω, 10 µF), 1 % noise, 30 points 10 kHz–0.1 Hz."""
    f = np.logspace(4, -1, 30)
    z = 20.0 + 1.0 / (1.0 / 500.0 + 1j * 2 * np.pi * f * 1e-5)
    return ix.make_spectrum(f, z * (1 + 0.01 * np.random.default_rng(0).standard_normal(f.size)))


def test_steps_needed_by_hand():
    assert steps_needed(1500, 1125, 61.1) == 4500  # (1500 × 50 × 61.1 / 1125 = 4073 → 4500)
    assert steps_needed(600, 450, 28.0) == 2000  # (600 × 1400 / 450 = 1867 → 2000)


@pytest.mark.slow
def test_a_short_chain_warning_names_the_steps_to_run():
    post = ix.sample("R0 + R1 || C1", _spectrum(), steps=600, seed=1, progress=False)
    (text,) = [w for w in post.warnings if "shorter than 50 autocorrelation times" in w]
    tau = max(emcee.autocorr.integrated_time(np.transpose(np.log(post.draws[..., i])), quiet=True)[0] for i in range(len(post.names)))  # (draws, walkers)
    kept = post.n_draws
    assert kept == 450
    by_hand = int(math.ceil(600 * 50 * tau / kept / 500) * 500)
    assert f"or a fixed length of at least about {by_hand} (steps={by_hand};" in text, (text, tau)
    assert "steps='auto' (the default)" in text


def test_the_command_line_says_the_advice_as_steps_options():
    """The command line says Python's steps='auto' and steps=4500 as --steps auto, --steps 4500
    (it read "--steps auto (the default, --steps auto)" and kept "steps=4500")."""
    from impedax.cli.common import command_line_words as _phrased
    from impedax.fitting.bayes.diagnostics import steps_advice

    said = _phrased(steps_advice(4500, capped=False), "sample")
    assert said == " — --steps auto (the default), which runs until the chain is 50 τ long, or a fixed length of at least about 4500 (--steps 4500; τ estimated on a short chain runs low)"
    assert "(--steps 31000;" in _phrased(steps_advice(31000, capped=True), "sample")
    assert _phrased("raise max_steps=400", "sample") == "raise --max-steps=400"  # (another keyword's number is left to its own rule)
