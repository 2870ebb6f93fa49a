"""`gap_analysis(..., edl_fit=...)` with a fit of another circuit than the one it samples (a
user's ``ix.fit('R1 || C1', remainder)``) ran the naive fit and then failed inside the sampling
with "init was fitted with R1 || C1 to 41 points; sample was given R_EP || CPE_EP || C_gap and
41 points": words of `impedax.sample`'s ``init=``, which the caller never passed (2026-12-07).
It is refused first, naming ``edl_fit``, both circuits and the call that makes the right fit.
SYNTHETIC spectra from formulas (`spectra.sirin_measurements`); the fit is a stub, and the
module's ``fit`` raises if reached, so the refusal is shown to come before any fit."""

from types import SimpleNamespace

import numpy as np
import pytest

import impedax as ix
import impedax.fitting
import impedax.models.gap as gap_module
from impedax.circuits import parse
from impedax.models.gap import gap_analysis
from spectra import sirin_measurements


@pytest.fixture
def spectra():
    f, *arrays = sirin_measurements(np.random.default_rng(4), 3)
    return [ix.make_spectrum(f, z, dims=("trial",)) for z in arrays]


def _no_fit(*args, **kwargs):
    raise AssertionError("a fit ran before edl_fit was checked")


@pytest.mark.parametrize("ep, other", [("CPE", "R1 || C1"), ("CPE", "R_EP || C_gap"), ("Q", "R_EP || C_gap || CPE_EP")])
def test_an_edl_fit_of_another_circuit_is_refused_before_any_fit(spectra, monkeypatch, ep, other):
    monkeypatch.setattr(impedax.fitting, "fit", _no_fit)
    stub = SimpleNamespace(circuit=parse(other), model=other, dims=())
    expected = str(gap_module.remainder_circuit("CPE"))  # (Q: the circuit language's alias of CPE)
    with pytest.raises(ix.ParameterError) as caught:
        gap_analysis(*spectra, area=130e-6, method="pooled", steps=100, progress=False, ep=ep, edl_fit=stub)
    message = str(caught.value)
    assert message.startswith(f"edl_fit is a fit of {other}; gap_analysis samples {expected}"), message
    assert f"ix.fit('{expected}', ix.models.remaining_impedance(total, skin, touchscreen), weighting='sigma')" in message
    assert "init" not in message


def test_an_edl_fit_of_the_sampled_circuit_passes_the_check(spectra, monkeypatch):
    """The same circuit passes this check (the naive fit then runs: here the patched one, which raises)."""
    monkeypatch.setattr(impedax.fitting, "fit", _no_fit)
    stub = SimpleNamespace(circuit=gap_module.remainder_circuit("CPE"), model="R_EP || CPE_EP || C_gap", dims=())
    with pytest.raises(AssertionError, match="a fit ran"):  # (the naive fit, after the check)
        gap_analysis(*spectra, area=130e-6, method="pooled", steps=100, progress=False, edl_fit=stub)
