"""The mask of a diagnosis leaves no few kept points beyond a masked run at an end of the band
(`end_islands_masked`, docs/diagnosis.md "Masked points")."""

from types import SimpleNamespace

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis.diagnosis import END_ISLAND_MAX, _data_problem, end_islands_masked
from impedax.fitting.diagnosis.noise import kk_judged_locally, noise_model
from impedax.fitting.kk import kk_test


def _mask(text: str) -> np.ndarray:
    return np.array([c == "x" for c in text])


@pytest.mark.parametrize("before, after", [
    ("..xxxxx.........", "xxxxxxx........."),  # two kept below a run of five: masked
    ("...xxxxx........", "...xxxxx........"),  # three kept: they constrain the end, kept
    (".x..............", ".x.............."),  # a lone flagged point next to the end point is no run
    (".xx.............", "xxx............."),  # one kept below a run of two
    ("..xx............", "..xx............"),  # two kept below a run of two: not more than them
    ("..........xxxx..", "..........xxxxxx"),  # the top end alike
    (".xxx........xxx.", "xxxx........xxxx"),  # both ends
    ("................", "................"),
])
def test_kept_points_beyond_a_masked_run_at_an_end_are_masked(before, after):
    assert END_ISLAND_MAX == 2
    f = np.logspace(-3, 3, len(before))
    np.testing.assert_array_equal(end_islands_masked(_mask(before), f), _mask(after))
    # the points' order does not matter: the rule reads them by frequency
    shuffled = np.random.default_rng(3).permutation(f.size)
    np.testing.assert_array_equal(end_islands_masked(_mask(before)[shuffled], f[shuffled]), _mask(after)[shuffled])


def _drifting_low_end(amplitude: float, start_hz: float, top_hz: float):
    """R0 + R1 ∥ C1 (10 Ω, 100 Ω, 1 mF; SYNTHETIC) at 41 frequencies 1 mHz–100 kHz, 0.2 % noise,
    times a drift 1 + a·sin(π x)·(1 + j)/√2 over x = log(f/start)/log(top/start) in [0, 1]: the
    sample drifts over the low end of the sweep (as in AutoEIS's test_data.txt, up to 0.6 Hz)."""
    f = np.logspace(-3, 5, 41)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-3)
    rng = np.random.default_rng(7)
    z = z * (1 + 0.002 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    x = np.clip(np.log(f / start_hz) / np.log(top_hz / start_hz), 0, 1)
    return f, z * (1 + amplitude * np.sin(np.pi * x) * (1 + 1j) / np.sqrt(2))


@pytest.mark.parametrize("amplitude, start_hz, top_hz, island", [(0.015, 6e-4, 0.1, 1), (0.01, 3e-4, 0.25, 2)])
def test_the_drifting_low_end_of_a_sweep_is_masked_to_the_end(amplitude, start_hz, top_hz, island):
    f, z = _drifting_low_end(amplitude, start_hz, top_hz)
    kk = kk_test(ix.make_spectrum(f, z))
    local = kk_judged_locally(kk) if not kk.valid else kk
    flagged = np.asarray(local.flagged, bool)
    # the situation: the lowest `island` points are kept (cleared by the local judgement, or never
    # flagged) below a flagged run, though the drift reaches them
    assert not flagged[:island].any() and flagged[island:island + 10].all()
    if island == 1:
        assert kk.flagged[0]  # flagged against the global noise, cleared against the local one
    fit = SimpleNamespace(frequency=f, residuals=np.full(f.size, 0.1), n_params=4, n_points=f.size)  # (a model far off everywhere: no point is the data's alone)
    nm = noise_model(f, z, noise=None, sigma=None, kk=local, fallback_rms=0.1)
    problem = _data_problem(fit, local, nm)
    assert problem.invalid is None
    np.testing.assert_array_equal(problem.masked, flagged | (np.arange(f.size) < island))
    assert f"{island} point(s) at the end of the band" in problem.note
