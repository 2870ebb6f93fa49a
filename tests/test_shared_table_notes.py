"""A global fit's tidy table (`to_table`, `impedax fit --shared ... --out FILE.csv`) carries its
global fit's notes in each row's ``warnings`` after the spectrum's own: until 2026-12-06 the CSV
had no word that a shared parameter sat at its bound or that the spectra disagreed with sharing."""

import numpy as np
import pytest
import xarray as xr

import impedax as ix


@pytest.mark.slow  # (~10 s: a global fit of two spectra, its solvers compiled)
def test_each_row_holds_its_spectrum_s_warnings_then_its_global_fit_s():
    """SYNTHETIC: two cells of R1 || C1 with no series resistance (numpy formula), R0 shared:
    it lands on its bound 0, which the global fit notes under "shared over cell"."""
    f = np.logspace(-1, 5, 40)
    r1 = np.array([100.0, 250.0])
    z = r1[:, None] / (1 + 2j * np.pi * f[None, :] * r1[:, None] * 1e-5)
    data = xr.Dataset({"Z": (("cell", "frequency"), z)}, coords={"cell": ["a", "b"], "frequency": f})
    fit = ix.fit("R0 + R1 || C1", data, shared="R0", progress=False)
    group = fit.warnings["shared over cell"]
    assert "shared R0 is at its lower bound 0" in group
    for row in fit.to_table():
        own = fit.warnings.get(f"cell={row['cell']}", ())
        assert row["warnings"] == "; ".join([*own, *group])
