"""`impedax.models.gap_analysis` refuses inputs that are no spectrum Dataset with one `DataError`
naming the input, before any fit (until 2026-12-06 None or a file name raised an AttributeError,
a Dataset without Z a KeyError, from inside its checks)."""

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.models import gap_analysis
from impedax.models.gap import gap_remainder

FREQ = np.geomspace(1.0, 1e6, 31)


@pytest.fixture(scope="module")
def spectrum():
    return ix.make_spectrum(FREQ, 1e3 + 1.0 / (2j * np.pi * FREQ * 1e-9))


EXPECTED = "expected a spectrum Dataset with complex 'Z' over 'frequency' (impedax.load, impedax.make_spectrum), got"


@pytest.mark.parametrize(("which", "given", "message"), [
    ("total", None, f"total: {EXPECTED} None (NoneType)"),
    ("total", [1, 2], f"total: {EXPECTED} [1, 2] (list)"),
    ("total", "total.nc", f"total: {EXPECTED} 'total.nc' (str) (a file name: read it with impedax.load first)"),
    ("skin", "skin.nc", f"skin: {EXPECTED} 'skin.nc' (str) (a file name: read it with impedax.load first)"),
    ("touchscreen", 3.0, f"touchscreen: {EXPECTED} 3.0 (float)"),
])
def test_an_input_that_is_no_dataset_is_named(spectrum, which, given, message):
    inputs = {"total": spectrum, "skin": spectrum * 0.1, "touchscreen": spectrum * 0.2, which: given}
    with pytest.raises(ix.DataError) as caught:
        gap_analysis(inputs["total"], inputs["skin"], inputs["touchscreen"], method="pooled", steps=20, progress=False)
    assert str(caught.value) == message


def test_a_dataset_without_z_is_named_as_the_total(spectrum):
    other = xr.Dataset({"impedance": ("frequency", spectrum["Z"].values)}, coords={"frequency": FREQ})
    with pytest.raises(ix.DataError) as caught:
        gap_analysis(other, method="pooled", steps=20, progress=False)
    assert str(caught.value) == "total: dataset has no variable 'Z' (its data variables: 'impedance')"


def test_gap_remainder_names_them_alike(spectrum):
    """`impedax remaining`'s function: None raised an AttributeError, a file name a TypeError."""
    with pytest.raises(ix.DataError) as caught:
        gap_remainder(None, None, None)
    assert str(caught.value) == f"total: {EXPECTED} None (NoneType)"
    with pytest.raises(ix.DataError) as caught:
        gap_remainder(spectrum, "skin.nc", spectrum * 0.2)
    assert str(caught.value) == f"skin: {EXPECTED} 'skin.nc' (str) (a file name: read it with impedax.load first)"


def test_a_results_methods_name_a_bad_branch_or_true_gap():
    """`GapAnalysis.force_at_max("x")` raised xarray's KeyError "not all values found in index
    'branch'", `plot(true_gap="x")` a TypeError and `plot(true_gap=-1)` drew a negative gap; the
    arguments are checked before the result is read (so a stand-in for it serves here)."""
    from types import SimpleNamespace

    from impedax.models.gap import GapAnalysis

    for method in (GapAnalysis.force_at_max, GapAnalysis.gap_voltage_at_force_max):
        with pytest.raises(ix.ParameterError) as caught:
            method(SimpleNamespace(), "with EP")
        assert str(caught.value) == "unknown branch 'with EP'; did you mean 'with_ep'? (choose one of with_ep, without_ep)"
    with pytest.raises(ix.ParameterError, match=r"true_gap must be a number, got '2.8 um' \(str\)"):
        GapAnalysis.plot(SimpleNamespace(), true_gap="2.8 um")
    with pytest.raises(ix.ParameterError, match="true_gap must be positive, got -2.8e-06"):
        GapAnalysis.plot(SimpleNamespace(), true_gap=-2.8e-6)
