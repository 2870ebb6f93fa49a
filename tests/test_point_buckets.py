"""Spectra are solved on a bucketed number of points (`solvers.padded_size`): zero-weight
copies of the last point pad a spectrum, so that spectra of nearby lengths share one
compiled solver. Padded fits must equal unpadded ones, and a new length in the same bucket
must compile nothing.

Oracles: the bucket sizes by hand (eight per octave), unpadded fits (the padding switched
off), and JAX's own count of compilations. The spectra are a numpy formula written here."""

import jax
import numpy as np
import pytest

import impedax as ix
from impedax.fitting.least_squares import solvers
from impedax.fitting.least_squares.solvers import padded_points, padded_size

MODEL = "R0 + R1 || CPE1 + W1"


def spectrum(f, rng, n_spectra=None):
    """Z = R0 + R1/(1 + R1 Q (jω)^α) + σ(1 − j)/√ω with 0.5 % complex noise."""
    s = 2j * np.pi * f
    z = 0.1 + 1.0 / (1 + 1.0 * 0.05 * s**0.8) + 0.2 * (1 - 1j) / np.sqrt(2 * np.pi * f)
    shape = (f.size,) if n_spectra is None else (n_spectra, f.size)
    return z * (1 + 0.005 * (rng.normal(size=shape) + 1j * rng.normal(size=shape)))


@pytest.mark.parametrize("n, size", [(1, 2), (5, 6), (10, 10), (16, 16), (17, 18), (57, 60), (60, 60), (64, 64), (65, 72), (100, 104), (1000, 1024), (1025, 1152)])
def test_bucket_sizes(n, size):
    assert padded_size(n) == size


def test_buckets_add_at_most_an_eighth():
    sizes = np.array([padded_size(n) for n in range(16, 5000)])
    n = np.arange(16, 5000)
    assert np.all(sizes >= n) and np.all(sizes <= 1.125 * n)
    assert np.all(np.diff(sizes) >= 0)


def test_padded_points_repeat_the_last_point_with_zero_weight():
    f = np.geomspace(1, 1e3, 57)
    z = np.arange(57) + 1j
    fp, zp, re, im = padded_points(f, z, np.ones(57), 2 * np.ones(57))
    assert fp.size == zp.size == re.size == im.size == 60
    np.testing.assert_array_equal(fp[57:], f[-1])
    np.testing.assert_array_equal(zp[57:], z[-1])
    np.testing.assert_array_equal(re[57:], 0.0)
    np.testing.assert_array_equal(im[57:], 0.0)
    np.testing.assert_array_equal(fp[:57], f)


def unpadded(monkeypatch):
    monkeypatch.setattr(solvers, "padded_size", lambda n: n)


def test_single_fit_equals_the_unpadded_fit(rng, monkeypatch):
    f = np.geomspace(0.02, 1e4, 57)
    data = ix.make_spectrum(f, spectrum(f, rng))
    padded = ix.fit(MODEL, data)
    unpadded(monkeypatch)
    plain = ix.fit(MODEL, data)
    for name in padded.values:
        assert padded.values[name] == pytest.approx(plain.values[name], rel=1e-10)
        assert padded.stderr[name] == pytest.approx(plain.stderr[name], rel=1e-9)
    assert padded.chi2 == pytest.approx(plain.chi2, rel=1e-10)
    assert padded.z_model.shape == (57,)
    np.testing.assert_allclose(padded.z_model, plain.z_model, rtol=1e-10)
    assert padded.warnings == plain.warnings and padded.at_bound == plain.at_bound
    # (not the step count: the stopping test at the last steps reacts to rounding)


@pytest.mark.slow  # (the suite's 15-minute budget, 2026-12-01: make test-all runs it)
def test_batch_fit_equals_the_unpadded_fit(rng, monkeypatch):
    f = np.geomspace(0.02, 1e4, 41)  # → 44 points
    data = ix.make_spectrum(f, spectrum(f, rng, 20), dims=("trial",))
    padded = ix.fit(MODEL, data).dataset
    unpadded(monkeypatch)
    plain = ix.fit(MODEL, data).dataset
    for name in ("value", "stderr", "chi2", "rms_rel", "Z_model"):
        np.testing.assert_allclose(padded[name].values, plain[name].values, rtol=1e-9, err_msg=name)
    np.testing.assert_array_equal(padded["n_evaluations"].values, plain["n_evaluations"].values)
    np.testing.assert_array_equal(padded["converged"].values, plain["converged"].values)
    assert padded.sizes["frequency"] == 41


def test_a_new_length_in_the_same_bucket_compiles_nothing(rng):
    compiles = []
    jax.monitoring.register_event_duration_secs_listener(lambda event, duration, **_: compiles.append(event) if event == "/jax/core/compile/backend_compile_duration" else None)
    # one start and at most 50 steps: the same programs every fit
    options = {"n_starts": 1, "max_steps": 50}
    f = np.geomspace(0.02, 1e4, 61)  # → 64 points
    ix.fit(MODEL, ix.make_spectrum(f, spectrum(f, rng)), **options)
    before = len(compiles)
    for n in (62, 64):  # the same bucket (61 to 64 points)
        g = np.geomspace(0.05, 2e3, n)
        result = ix.fit(MODEL, ix.make_spectrum(g, spectrum(g, rng)), **options)
        assert result.z_model.shape == (n,)
    assert len(compiles) == before
