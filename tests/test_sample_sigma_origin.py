"""`impedax sample --noise sigma` (``ix.sample(noise="sigma")``) said only "the data's 'sigma'
variable (e.g. SEM of repeated trials)", whatever that σ was: a remainder's standard error of trial
means, which holds the contact's variation between trials, read like a sigma column (2026-12-06).
The noise line, the JSON (key ``sigma_origin``, added) and a saved posterior now name it as the
diagnosis does. SYNTHETIC remainder of trials built here, counts known by construction."""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.bayes.posterior import Posterior
from impedax.models.sirin import remaining_impedance

F = np.geomspace(1.0, 1e5, 25)
W = 2 * np.pi * F


def _trials(z, n, rng, spread=0.0):
    """``n`` trials of ``z`` with 0.2 % noise, each scaled by a factor of log-sd ``spread``."""
    scale = np.exp(spread * rng.standard_normal((n, 1)))
    noisy = z * scale * (1 + 0.002 * (rng.standard_normal((n, F.size)) + 1j * rng.standard_normal((n, F.size))))
    return ix.make_spectrum(F, noisy, dims=("trial",))


@pytest.mark.slow
def test_the_noise_line_json_and_file_name_what_sigma_is(tmp_path):
    rng = np.random.default_rng(1)
    skin, screen = 1e4 / (1 + 1j * W * 1e-4), np.full(F.size, 2e3 + 0j)
    gap = 1 / (1 / 1e7 + 1j * W * 4e-10)
    remainder = remaining_impedance(_trials(gap + skin + screen, 6, rng, 0.02), _trials(skin, 5, rng), _trials(screen, 4, rng))
    words = "the standard error of trial means of 6 total, 5 skin, 4 touchscreen spectra"
    post = ix.sample("R_EP || C_gap", remainder, noise="sigma", steps=200, progress=False)
    assert post.report().splitlines()[1].endswith(f"(e.g. SEM of repeated trials); here {words}")
    assert post.summary()["sigma_origin"] == words
    ix.write_result(post, tmp_path / "post.nc")
    assert Posterior.from_xarray(ix.load(tmp_path / "post.nc")).summary()["sigma_origin"] == words
    # a sigma column: named so; proportional noise: none
    column = ix.make_spectrum(F, remainder["Z"].values, sigma=remainder["sigma"].values)
    assert ix.sample("R_EP || C_gap", column, noise="sigma", steps=200, progress=False).summary()["sigma_origin"] == "sigma column"
    assert ix.sample("R_EP || C_gap", remainder, steps=200, progress=False).summary()["sigma_origin"] is None
