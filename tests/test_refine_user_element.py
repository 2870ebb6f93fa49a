"""A series resistance of the starting circuit that refine left out early (it was undetermined
beside an ideal capacitor) comes back when the data support it, and an ``adequate`` verdict
says why a candidate past ΔAIC −10 is not significant (docs/diagnosis.md, sections 5 and 6)."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.plotting.diagnosis import ADEQUATE_BANDS, plot_refinement

F = 10 ** np.arange(-2, 5 + 1e-9, 1 / 7)  # 10 mHz – 100 kHz, 7 per decade [Hz]


def coated_metal(seed: int = 42, draw: int = 3) -> xr.Dataset:
    """SYNTHETIC coated metal, Z = R0 + 1/(Q_c (jω)^a_c + 1/(R_pore + 1/(Q_dl (jω)^a_dl + 1/R_ct))),
    R0 = 20 Ω, 0.75 % noise on |Z| (complex Gaussian); the ``draw``-th noise draw of ``seed``."""
    w = 2 * np.pi * F
    r0, q_c, a_c, r_pore, q_dl, a_dl, r_ct = 20.0, 5e-9, 0.92, 4.966e5, 3.2e-6, 0.75, 2.247e6
    z = r0 + 1 / (q_c * (1j * w) ** a_c + 1 / (r_pore + 1 / (q_dl * (1j * w) ** a_dl + 1 / r_ct)))
    rng = np.random.default_rng(seed)
    for _ in range(draw):
        noise = 0.0075 * np.abs(z) * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)) / np.sqrt(2)
    return xr.Dataset({"Z": ("frequency", z + noise)}, coords={"frequency": F})


def test_why_not_significant_names_the_noise_variance_explained():
    from types import SimpleNamespace

    from impedax.fitting.diagnosis import Diagnosis

    # hand numbers: σ_k = 1 %; baseline residuals (1 + 1j) %, |r/σ|² = 2; candidate's (0.9 + 0.9j) %,
    # 1.62: it explains (2 − 1.62)/2 = 19 % of the noise variance
    base = SimpleNamespace(frequency=F, residuals=np.full(F.size, 0.01 + 0.01j))
    candidate = SimpleNamespace(delta_aic=-12.0, warning=None, fit=SimpleNamespace(frequency=F, residuals=np.full(F.size, 0.009 + 0.009j)))
    diagnosis = SimpleNamespace(baseline=base, noise=np.full(F.size, 0.01))
    text = Diagnosis._why_not_significant(diagnosis, candidate)
    assert "explains 19 % of the noise variance, under the 25 %" in text and "NOISE_FRACTION_MIN" in text
    assert Diagnosis._why_not_significant(diagnosis, SimpleNamespace(**(candidate.__dict__ | {"delta_aic": -9.0}))) == ""


@pytest.mark.slow  # (about 20 s in a fresh process)
def test_adequate_names_the_noise_variance_rule_for_a_candidate_past_the_aic_threshold():
    d = ix.diagnose(coated_metal(), "R1 || CPE1 + R2 || CPE2")
    assert d.verdict == "adequate"
    top = d.candidates[0]
    assert top.effect == "series_resistance" and top.delta_aic < -10  # past DELTA_AIC_MIN, yet not significant
    assert top.fit.values["R_s"] == pytest.approx(20.0, rel=0.3)  # the candidate reached the true R0: no worse optimum
    text = d.report()
    line = next(t for t in text.splitlines() if t.startswith("no effect improves the fit significantly"))
    assert "NOISE_FRACTION_MIN" in line and "of the noise variance, under the 25 %" in line
    assert "where the model fails" not in text and "where the residuals are structured" in text


def test_adequate_shading_is_not_labelled_model_fails():
    from types import SimpleNamespace

    from impedax.plotting.diagnosis import band_shading

    assert band_shading(SimpleNamespace(verdict=ix.fitting.diagnosis.Verdict.ADEQUATE)) == (ADEQUATE_BANDS, "tab:grey")
    assert band_shading(SimpleNamespace(verdict=ix.fitting.diagnosis.Verdict.MISSING_EFFECT))[0] == "model fails"


@pytest.mark.slow  # (about 60 s)
def test_refine_keeps_the_series_resistance_the_data_support():
    data = coated_metal()
    r = ix.refine(data, "R0 + R1 || C1")
    assert "R0" in r.final.values and r.final.values["R0"] == pytest.approx(20.0, rel=0.5)
    # compare's ΔAIC between the fits' own AICs, as refine's paths are compared
    without = ix.fit("R1 || CPE1 + R2 || CPE2", data)
    assert without.aic - r.final.aic > 10
    fig = plot_refinement(r)
    legends = [t.get_text() for ax in fig.axes if ax.get_legend() is not None for t in ax.get_legend().get_texts()]
    assert r.verdict == "adequate"
    if r.steps[-1].diagnosis.failing_bands:  # the adequate last step's bands are not called failing
        assert ADEQUATE_BANDS in legends
    plt.close(fig)
