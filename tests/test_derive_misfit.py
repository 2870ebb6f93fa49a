"""`derive` says when the fit it propagates misses structure the data hold (a Python-API
walkthrough, 2026-12-02: an RC skin fitted to a SYNTHETIC finger whose skin is a constant-phase
element gave a force band 200× below the truth, ± 6 %, with no word)."""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix

MODEL = "C_s + C_i + R_sc || C_sc + R_f"
FREQ = np.logspace(0, 6, 61)


def finger(alpha: float, seed: int) -> np.ndarray:
    """Meyer's finger chain C_s + C_i + R_sc ∥ (constant-phase skin Q (jω)^α) + R_f, written here
    with numpy (α = 1: the RC skin of MODEL), with 1 % complex noise of |Z| (SYNTHETIC)."""
    w = 2 * np.pi * FREQ
    z = 1 / (1j * w * 140e-12) + 1 / (1j * w * 1.7e-9) + 1 / (1 / 130e3 + 2e-9 * (1j * w) ** alpha) + 500.0
    rng = np.random.default_rng(seed)
    return z * (1 + 0.01 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)) / np.sqrt(2))


@pytest.fixture(scope="module")
def rc_and_cpe_batch():
    data = ix.make_spectrum(FREQ, np.stack([finger(1.0, 0), finger(0.75, 1)]), dims=("subject",), coords={"subject": ["rc", "cpe"]})
    return ix.fit(MODEL, data, fixed={"C_i": 1.7e-9})


def test_a_batch_derive_flags_the_spectra_whose_model_misses_structure(rc_and_cpe_batch):
    out = ix.derive(rc_and_cpe_batch, lambda p: p["C_sc"])
    assert out["misses_structure"].sel(subject=["rc", "cpe"]).values.tolist() == [False, True]
    assert out.attrs["warning"].startswith("in 1 of 2 spectra (misses_structure): the fit's model misses structure the data hold")
    assert "impedax diagnose" in out.attrs["warning"]


def test_a_single_derive_flags_a_model_that_misses_structure_and_not_one_that_fits():
    cpe_skin = ix.fit(MODEL, ix.make_spectrum(FREQ, finger(0.75, 1)), fixed={"C_i": 1.7e-9})
    rc_skin = ix.fit(MODEL, ix.make_spectrum(FREQ, finger(1.0, 0)), fixed={"C_i": 1.7e-9})
    assert cpe_skin.misses_structure and not rc_skin.misses_structure
    flagged = ix.derive(cpe_skin, lambda p: p["R_sc"])
    assert flagged.attrs["misses_structure"] == 1 and "not the quantity's" in flagged.attrs["warning"]
    assert "misses_structure" not in ix.derive(rc_skin, lambda p: p["R_sc"]).attrs
