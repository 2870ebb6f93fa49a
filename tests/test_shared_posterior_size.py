"""A joint posterior beyond emcee's `MAX_JOINT_PARAMETERS`, and a prior for a parameter it does
not sample, are refused before its global fit: until 2026-12-06 the refusals came after it (12 s
on the REAL battery cycles 120–129 with two of 8 parameters shared: 2 + 10 × 6 + sigma_rel = 63)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import impedax as ix
import impedax.fitting.bayes.shared_posterior as shared_posterior


def rc_trials(count: int) -> xr.Dataset:
    """SYNTHETIC R0 + R1 ∥ C1 spectra (numpy), R1 varying by trial."""
    f = np.logspace(0, 5, 21)
    z = np.stack([50.0 + r1 / (1 + 2j * np.pi * f * r1 * 1e-7) for r1 in np.linspace(1e3, 2e3, count)])
    return xr.Dataset({"Z": (("trial", "frequency"), z)}, coords={"trial": np.arange(count), "frequency": f})


def test_too_many_joint_parameters_are_refused_before_the_global_fit(monkeypatch):
    def no_fit(*args, **kwargs):
        raise AssertionError("the global fit ran before the refusal")

    monkeypatch.setattr(shared_posterior, "fit", no_fit)
    # 1 shared + 30 trials × 2 own (R1, C1) + sigma_rel = 62 > 60
    with pytest.raises(ix.ParameterError, match=r"^the joint posterior of 30 spectra has 62 sampled parameters \(1 shared \+ 30 × 2 own \+ sigma_rel\); emcee mixes up to 60"):
        ix.sample("R0 + R1 || C1", rc_trials(30), shared=["R0"], over="trial", steps=10, progress=False)
    # fixing C1 leaves 1 + 30 × 1 + 1 = 32: the global fit is reached
    with pytest.raises(AssertionError, match="global fit ran"):
        ix.sample("R0 + R1 || C1", rc_trials(30), shared="R0", fixed={"C1": 1e-7}, steps=10, progress=False)


def test_a_prior_for_an_unknown_or_fixed_parameter_is_refused_before_the_global_fit(monkeypatch):
    """`impedax sample --shared R0 --prior R7=...` on the REAL battery cycles was refused after the
    global fit (4.9–9.4 s against 2.7 s for one spectrum); now before it, with the same words."""
    def no_fit(*args, **kwargs):
        raise AssertionError("the global fit ran before the refusal")

    monkeypatch.setattr(shared_posterior, "fit", no_fit)
    with pytest.raises(ix.ParameterError, match=r"^prior for unknown parameter 'R7' \(parameters: R0, R1, C1\)"):
        ix.sample("R0 + R1 || C1", rc_trials(3), shared="R0", priors={"R7": "uniform:0,1"}, steps=10, progress=False)
    with pytest.raises(ix.ParameterError, match=r"^prior for C1: the parameter is fixed"):
        ix.sample("R0 + R1 || C1", rc_trials(3), shared="R0", fixed={"C1": 1e-7}, priors={"C1": "loguniform:1e-9,1e-6"}, steps=10, progress=False)
