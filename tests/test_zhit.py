"""Z-HIT against exact moduli of closed-form spectra, noise, drift, the CLI and bad input."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import impedax as ix
from impedax.errors import DataError, ParameterError

F = np.geomspace(0.01, 1e5, 71)
W = 2 * np.pi * F

EXACT = {
    "R||C": 10 + 1000 / (1 + 1j * W * 1e-2),
    "R-CPE": 10 + 1 / (1 / 1000 + 1e-4 * (1j * W) ** 0.8),
    "Randles + Warburg": 10 + 1 / (1j * W * 2e-5 + 1 / (100 + 50 * (1 - 1j) / np.sqrt(W))),
    "Havriliak-Negami": 10 + 1000 / (1 + (1j * W * 1e-2) ** 0.8) ** 0.6,
    "two R||C": 10 + 500 / (1 + 1j * W * 1e-4) + 2000 / (1 + 1j * W * 1e-1),
}


def noisy(z, level, seed):
    rng = np.random.default_rng(seed)
    return z * (1 + level * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2))


@pytest.mark.parametrize("case", list(EXACT))
def test_modulus_from_the_phase_matches_the_exact_modulus(case):
    z = EXACT[case]
    result = ix.zhit((F, z))
    # first-order Z-HIT on exact data: within 1.5 % everywhere (docs/drt.md)
    assert np.max(np.abs(result.modulus / np.abs(z) - 1)) < 0.015
    assert result.valid


@pytest.mark.parametrize("case", list(EXACT))
def test_noisy_valid_spectra_are_not_flagged(case):
    assert all(ix.zhit((F, noisy(EXACT[case], 0.01, seed))).valid for seed in range(5))


@pytest.mark.parametrize("case", ["R||C", "R-CPE", "two R||C"])
def test_modulus_drift_at_low_frequency_is_flagged(case):
    z = noisy(EXACT[case], 0.01, 1)
    low = F < 0.1
    z[low] *= 1 + 0.1 * np.log10(0.1 / F[low])  # |Z| drifts up to 10 % at the slow end, the phase does not
    result = ix.zhit((F, z))
    assert not result.valid
    assert result.bad_bands[0][0] == pytest.approx(0.01) and result.bad_bands[0][1] < 0.1
    assert result.flagged[0]


def test_result_xarray_and_summary():
    result = ix.zhit((F, EXACT["R-CPE"]))
    ds = result.to_xarray()
    assert set(["Z", "modulus_zhit", "residuals", "flagged"]) <= set(ds.data_vars)
    assert "valid" in result.report() and result.summary()["valid"] == result.valid


@pytest.mark.parametrize(
    "data, kwargs, error, match",
    [
        ((F[:4], np.ones(4, complex)), {}, DataError, "at least 6"),
        ((F, np.zeros(F.size, complex)), {}, DataError, "zero"),
        ((F, np.ones((2, F.size), complex)), {}, DataError, "extra dimensions"),
        ((F, EXACT["R||C"]), {"noise_floor": -1}, ParameterError, "noise_floor"),
        ((F, EXACT["R||C"]), {"run_length": 0}, ParameterError, "run_length"),
    ],
)
def test_bad_input(data, kwargs, error, match):
    with pytest.raises(error, match=match):
        ix.zhit(data, **kwargs)


def test_cli_kk_method_zhit(tmp_path, capsys):
    from impedax.cli import main

    path = tmp_path / "s.csv"
    ix.save(ix.make_spectrum(F, noisy(EXACT["R-CPE"], 0.005, 2)), path)
    assert main(["kk", str(path), "--method", "zhit", "--json", "--plot", str(tmp_path / "z.png")]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["method"] == "zhit" and payload["valid"] is True
    # the keys of before stay (the JSON is a public contract); the keys added since are listed
    assert {"method", "valid", "rms_rel", "bad_bands", "noise_estimate", "frequency_hz", "modulus_zhit_ohm", "residuals_modulus"} <= set(payload)
    assert {"conclusive", "bad_bands_hz", "bad_band_rules", "noise_estimate_rel", "point_threshold_rel", "run_threshold_rel", "run_length", "end_slope_local_hz", "sign_hint"} <= set(payload)
    assert payload["conclusive"] is True and payload["sign_hint"] is None
    assert (tmp_path / "z.png").read_bytes()[:4] == b"\x89PNG"
