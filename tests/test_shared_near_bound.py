"""A shared parameter near its bound is said once, by its global fit, with its standard error;
each spectrum's notes say nothing of it (REAL 130 battery cycles with --shared
CPE1.alpha,CPE2.alpha printed "CPE2.alpha = 1 ± 0 lies within 2 standard errors of its upper
bound 1" for all 130 spectra: the ± 0 of a shared column quieted in each spectrum's notes)."""

import numpy as np
import pytest
import xarray as xr

import impedax as ix


@pytest.mark.slow  # (~9 s: a global fit of two spectra and its independent fits)
def test_a_shared_alpha_near_1_is_noted_once_with_its_error_and_never_with_a_zero_one():
    """SYNTHETIC: two cells of R0 + R1 || C1 (an ideal capacitor, α = 1; numpy formula, 0.1 %
    noise) fitted with R0 + R1 || CPE1, α shared: it lands just below 1."""
    f = np.logspace(-1, 5, 40)
    rng = np.random.default_rng(3)
    r1 = np.array([100.0, 250.0])
    z = 10 + r1[:, None] / (1 + 2j * np.pi * f[None, :] * r1[:, None] * 1e-5)
    z = z * (1 + 0.001 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    data = xr.Dataset({"Z": (("cell", "frequency"), z)}, coords={"cell": ["a", "b"], "frequency": f})
    fit = ix.fit("R0 + R1 || CPE1", data, shared="CPE1.alpha", progress=False)
    alpha, error = float(fit.values("CPE1.alpha")), float(fit.stderr("CPE1.alpha"))
    assert 1 - alpha < 2 * error and error > 0  # (within 2 standard errors of 1: the note's case)
    spectra = [w for key, texts in fit.warnings.items() if key.startswith("cell=") for w in texts]
    assert not any("CPE1.alpha" in w for w in spectra) and not any("± 0 " in w for w in spectra)
    (note,) = [w for w in fit.warnings["shared over cell"] if "CPE1.alpha" in w]
    assert note.startswith("shared CPE1.alpha = ") and "lies within 2 standard errors of its upper bound 1" in note
    assert f"± {error:.2g}" in note  # (its error to two significant digits, as the report rounds it)
