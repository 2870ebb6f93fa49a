"""A batch dimension named as a variable or dimension of the batch result's Dataset (``rc``,
``band`` for the KK test; ``tau``, ``peak`` for the DRT) is refused before any work with one
message naming it (exit 2 in the CLI), where ``to_xarray`` had failed with xarray's
"conflicting sizes for dimension 'tau'"; and the KK test's residuals are data minus KK fit,
by hand and in their long_names. Spectra: numpy formulas (R0 + R‖CPE), synthetic."""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting.drt.result import BATCH_RESULT_NAMES as DRT_NAMES
from impedax.fitting.kk import BATCH_RESULT_NAMES as KK_NAMES

F = np.geomspace(0.1, 1e5, 41)
W = 2 * np.pi * F


def arcs(n: int) -> np.ndarray:
    """n spectra R0 + R‖CPE with R = 0.1, 0.2, ... Ω (α = 0.85)."""
    return np.array([0.05 + 1 / (1 / (0.1 * k) + 2 * (1j * W) ** 0.85) for k in range(1, n + 1)])


def batch(dim: str, n: int = 4):
    return ix.make_spectrum(F, arcs(n), dims=dim, coords={dim: np.arange(1.0, n + 1)})


@pytest.mark.parametrize(("analysis", "command", "dim"), [
    (ix.kk_test_batch, "kk", "rc"), (ix.kk_test_batch, "kk", "band"), (ix.kk_test_batch, "kk", "mu"),
    (ix.drt, "drt", "tau"), (ix.drt, "drt", "peak"), (ix.drt, "drt", "lam"),
])
def test_a_dimension_named_like_the_results_is_refused_before_the_analysis(analysis, command, dim, tmp_path, capsys):
    data = batch(dim)
    with pytest.raises(ix.DataError, match=f"batch dimension\\(s\\) '{dim}' have the name of a (KK|DRT) batch result's variable or dimension.*rename them first"):
        analysis(data)
    path = tmp_path / "clash.nc"
    ix.save(data, path)
    capsys.readouterr()
    assert main([command, str(path), "--json"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and str(path) in err and f"'{dim}'" in err and "Traceback" not in err and "conflicting sizes" not in err


def test_the_kk_names_are_exactly_those_of_its_batch_dataset():
    """`kk.BATCH_RESULT_NAMES` lists every variable and dimension of `KKBatchResult.to_xarray`
    (a name added there and not here would let a clash through again). The DRT's list is
    checked against its Dataset in test_drt_batch_outputs.py, where a batch DRT is computed."""
    ds = ix.kk_test_batch(batch("cycle", 2)).to_xarray()
    assert (set(ds.variables) | set(ds.dims)) - {"cycle"} == KK_NAMES
    assert "tau" not in KK_NAMES and "rc" not in DRT_NAMES  # each refuses only its own names
    assert ix.kk_test_batch(batch("tau", 2)).to_xarray().sizes["tau"] == 2


def test_kk_residuals_are_data_minus_the_chain_as_their_long_names_say():
    """Δ = (Z_data − Z_kk)/|Z_data| (docs/kk.md, Boukamp's sign), Z_kk summed here from the
    result's R_k, τ_k and series terms: R0 + Σ R_k/(1 + jωτ_k) + jωL + (1/C)/(jω)."""
    rng = np.random.default_rng(3)
    z = arcs(1)[0]
    z = z + 0.01 * np.abs(z) * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size))
    result = ix.kk_test((F, z), capacitance=True, inductance=True)
    z_kk = (result.series_resistance + (result.resistances / (1 + 1j * W[:, None] * result.time_constants)).sum(axis=1)
            + 1j * W * result.series_inductance + result.inverse_series_capacitance / (1j * W))
    by_hand = (z - z_kk) / np.abs(z)
    assert np.abs(by_hand).max() > 5e-3  # 1 % noise: the sign is measurable
    np.testing.assert_allclose(result.residuals_real, by_hand.real, atol=1e-9)
    np.testing.assert_allclose(result.residuals_imag, by_hand.imag, atol=1e-9)
    for ds in (result.to_xarray(), ix.kk_test_batch(batch("cycle", 2)).to_xarray()):
        assert ds["residuals_real"].attrs["long_name"] == "(Z'_data - Z'_kk)/|Z_data|"
        assert ds["residuals_imag"].attrs["long_name"] == "(Z''_data - Z''_kk)/|Z_data|"
