"""`derive` says when the data do not determine a derived quantity: a gap thickness from C_gap
of `R_EP || C_EP || C_gap`, where two ideal capacitors in parallel show only their sum (SYNTHETIC
spectra from the numpy formula Z = 1/(1/R_EP + jω(C_EP + C_gap)), 1 % noise)."""

import numpy as np
import xarray as xr

import impedax as ix

EPS0, AREA = 8.8541878128e-12, 4e-4
F = np.geomspace(10, 1e6, 40)


def _pad(c_gap, rng):
    z = 1 / (1 / 50e6 + 2j * np.pi * F * (2e-9 + c_gap))
    return z * (1 + 0.01 * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)) / np.sqrt(2))


def _thickness(p):
    return EPS0 * AREA / p["C_gap"]


def test_a_thickness_from_a_capacitor_the_data_cannot_separate_is_flagged_and_a_fixed_partner_clears_it():
    rng = np.random.default_rng(3)
    data = ix.make_spectrum(F, _pad(120e-12, rng))
    loose = ix.derive(ix.fit("R_EP || C_EP || C_gap", data, progress=False), _thickness)
    assert loose.attrs["undetermined"] == 1 and "the data do not determine it" in loose.attrs["warning"]
    assert float(loose["stderr"]) > float(loose["value"])  # (the rule: relative error above 100 %)
    fixed = ix.derive(ix.fit("R_EP || C_EP || C_gap", data, fixed={"C_EP": 2e-9}, progress=False), _thickness)
    assert "undetermined" not in fixed.attrs and "warning" not in fixed.attrs
    assert abs(float(fixed["value"]) / (EPS0 * AREA / 120e-12) - 1) < 0.1  # u = ε0 A / C_gap within the noise's reach


def test_a_batch_flags_each_spectrum_whose_quantity_is_undetermined():
    rng = np.random.default_rng(4)
    spectra = [ix.make_spectrum(F, _pad(c, rng)) for c in (115e-12, 125e-12)]
    stack = xr.concat(spectra, dim="repeat")
    derived = ix.derive(ix.fit("R_EP || C_EP || C_gap", stack, progress=False), _thickness)
    assert derived["undetermined"].dims == ("repeat",) and derived["undetermined"].values.tolist() == [True, True]
    assert "in 2 of 2 spectra (undetermined)" in derived.attrs["warning"]
    sure = ix.derive(ix.fit("R_EP || C_EP || C_gap", stack, fixed={"C_EP": 2e-9}, progress=False), _thickness)
    assert sure["undetermined"].values.tolist() == [False, False] and "warning" not in sure.attrs
