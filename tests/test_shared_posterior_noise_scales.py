"""A joint posterior with proportional noise samples one sigma_rel for every spectrum; where the
spectra's own residual scales differ (a worse fit, a noisier measurement) the common scale is
too wide for some and too narrow for others, and their intervals with it, and nothing said so.
(On the REAL battery cycles, examples/data/autoeis_battery_cycles.nc with R0 + R1 ∥ CPE1 + R2 ∥
CPE2 + L0 and both α shared, the spectra's scales at the most probable draw are 2.4 %, 3.3 % and
4.1 %: 1.7×, below `NOISE_SCALE_RATIO`, no warning.) SYNTHETIC data: RC spectra by formula, one
with 0.3 % noise and one with 3 %; the rms at the most probable draw by numpy from the formula."""

import numpy as np
import pytest

import impedax as ix
from test_shared_posterior_roundtrip import FREQ, MODEL, rc_impedance


def _joint(noise_a: float, noise_b: float):
    rng = np.random.default_rng(5)
    z = np.stack([rc_impedance(FREQ, 50.0, 1000.0, 3e-7), rc_impedance(FREQ, 50.0, 1500.0, 5e-7)])
    z = z * (1 + np.array([[noise_a], [noise_b]]) * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape)))
    data = ix.make_spectrum(FREQ, z, dims=("trial",), coords={"trial": [1, 2]})
    return ix.sample(MODEL, data, shared=["R0"], over="trial", steps=300, walkers=16, seed=2, progress=False), z


def _rms_at_best_draw(post, z):
    best = post.draws.reshape(-1, len(post.names))[int(np.argmax(post.log_prob))]
    value = dict(zip(post.names, best))
    out = []
    for row, label in enumerate(post.spectra):
        model = rc_impedance(FREQ, value["R0"], value[f"R1[{label}]"], value[f"C1[{label}]"])
        rel = (model - z[row]) / np.abs(z[row])
        out.append(np.sqrt(np.mean(np.concatenate([rel.real, rel.imag]) ** 2)))
    return np.array(out)


def test_spectra_of_different_noise_are_warned_about():
    post, z = _joint(0.003, 0.03)
    expected = _rms_at_best_draw(post, z)
    np.testing.assert_allclose(post.spectrum_noise_scales(), expected, rtol=1e-6)
    assert expected[1] > 5 * expected[0]  # (the case: 10× the noise)
    (text,) = [w for w in post.warnings if w.startswith("one sigma_rel is sampled for all 2 spectra")]
    assert f"trial=1 misses its data by {expected[0]:.3g} rms (relative), trial=2 by {expected[1]:.3g}" in text
    assert f"against sigma_rel {np.median(post.samples['sigma_rel']):.3g}" in text
    assert "noise='sigma'" in text


def test_spectra_of_equal_noise_are_not():
    post, z = _joint(0.01, 0.01)
    scales = post.spectrum_noise_scales()
    assert scales.max() < 1.5 * scales.min()
    assert not any(w.startswith("one sigma_rel") for w in post.warnings)
