"""WAIC's warning names the noise model when the start fit's residuals are uneven under one
relative noise level, and the points whose pointwise p_waic is high: on the shipped SYNTHETIC
skin (noise ~4× larger at 1–5 Hz) p_waic was 13 for 5 parameters with the chain converged, and
the warning said to run more steps (a walkthrough, 2026-12-04)."""

from types import SimpleNamespace

import numpy as np
import pytest

from impedax.fitting.bayes.evidence import START_UNEVEN_NOISE, WAIC_POINT_LIMIT, _at_points, waic_cause
from impedax.fitting.bayes.logprob import NoiseModel
from impedax.fitting.bayes.sampler import _start_misfit
from impedax.fitting.least_squares.result import UNEVEN_NOISE_NOTE


def test_the_cause_is_the_noise_model_not_the_chain():
    chain = np.random.default_rng(0).normal(size=(8, 200, 3))
    text = waic_cause(chain, ["a", "b", "c"], start_y=np.zeros(3), model_misfit=START_UNEVEN_NOISE)
    assert text.startswith("the noise model gives every point one relative σ") and "run more steps" not in text
    assert "(a sigma column of the file or make_spectrum(sigma=...), and noise='sigma')" in text and "--" not in text  # (Python's words; both until 2026-12-06)
    # the start's note decides it, under proportional noise only
    start = SimpleNamespace(warnings=(f"the weighted residuals are over 4× larger (rms) at 1 Hz – 5.01 Hz ...: {UNEVEN_NOISE_NOTE} (modulus weighting), so ...",),
                            weighting="modulus", chi2_red=1.0)
    assert _start_misfit(start, NoiseModel.PROPORTIONAL) == START_UNEVEN_NOISE
    assert _start_misfit(SimpleNamespace(warnings=(), weighting="modulus", chi2_red=1.0), NoiseModel.PROPORTIONAL) is False


def test_the_points_of_high_pointwise_p_waic_are_named_highest_first():
    f = np.array([1.0, 2.0, 5.0, 10.0, 100.0, 1000.0])
    p_i = np.array([0.5, 5.4, 0.1, 0.9, 0.0, 0.41])
    assert p_i[p_i > WAIC_POINT_LIMIT].size == 4
    assert _at_points(SimpleNamespace(freq=f), p_i) == ", at 2 Hz, 10 Hz, 1 Hz, 1 kHz"
    assert _at_points(SimpleNamespace(freq=f), np.zeros(6)) == ""
    assert _at_points(SimpleNamespace(freq=f[:3]), p_i) == ""  # (not one frequency per point)


@pytest.mark.slow  # (8–20 s: a sampling of the shipped skin spectrum)
def test_the_shipped_skin_with_proportional_noise_names_the_noise_model():
    import impedax as ix
    from impedax.models.synthetic import example_spectra

    skin = example_spectra()["skin"].isel(session=1, trial=1)
    post = ix.sample("R_inf + R_sk || CPE_sk", skin, seed=0, progress=False)
    [note] = [w for w in post.warnings if w.startswith("WAIC is unreliable")]
    assert "because the noise model gives every point one relative σ" in note and "run more steps" not in note
    assert ", at 1" in note or ", at 2" in note  # (the high points lie in 1–5 Hz, where the noise is larger)
