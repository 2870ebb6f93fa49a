"""The distribution of relaxation times against closed forms written here in numpy.

Oracles: spectra of R‖C, ZARC and Havriliak–Negami blocks from their impedance formulas; the
true DRT peak from the Stieltjes inversion γ(τ) = (1/π)|Im Z(s = e^{jπ}/τ)|; basis integrals
from scipy.integrate.quad. Noise 0.3–3 % (complex Gaussian, relative to |Z|, fixed seeds).
Bounds (from the issue): peak τ within 0.1 decade, peak R within 10 %, the right number of peaks.
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest
from scipy.integrate import quad

import impedax as ix
from impedax.errors import CircuitError, DataError, ParameterError
from impedax.fitting.drt import DRTBatchResult, DRTResult, circuit_drt, drt, havriliak_negami_drt, r_cpe_drt, r_cpe_tau, unexplained_peaks, zarc_drt
from impedax.fitting.drt.basis import impedance_integrals, penalty_matrix, rbf_basis

F = np.geomspace(0.01, 1e5, 71)
W = 2 * np.pi * F


def rc(r, tau):
    return r / (1 + 1j * W * tau)


def zarc(r, tau, alpha):
    return r / (1 + (1j * W * tau) ** alpha)


def hn(r, tau, alpha, beta):
    return r / (1 + (1j * W * tau) ** alpha) ** beta


def noisy(z, level, seed):
    rng = np.random.default_rng(seed)
    return z + level * np.abs(z) * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2)


def hn_true_gamma(tau, r, tau0, alpha, beta):
    """Stieltjes inversion of Z(s) = R/(1 + (sτ₀)^α)^β at s = e^{jπ}/τ (independent of analytic.py)."""
    s_tau0 = (tau0 / tau) ** alpha * np.exp(1j * math.pi * alpha)
    return np.abs(np.imag(r / (1 + s_tau0) ** beta)) / math.pi


def zarc_mass(r, tau0, alpha, tau_lo, tau_hi):
    """∫ γ d ln τ of a ZARC between tau_lo and tau_hi, from the inversion of R/(1 + (sτ₀)^α)."""
    tau = np.geomspace(tau_lo, tau_hi, 20001)
    g = np.abs(np.imag(r / (1 + (tau0 / tau) ** alpha * np.exp(1j * math.pi * alpha)))) / math.pi
    return float(np.trapezoid(g, np.log(tau)))


def assert_peaks(result, truth, *, tau_decades=0.1, r_rel=0.10):
    """``truth``: [(τ, R)] sorted by τ; the DRT must have exactly these peaks."""
    found = [(p.tau_s, p.r_ohm) for p in result.peaks]
    assert len(found) == len(truth), f"peaks {found}, expected {truth}"
    for (tau, r), (tau_true, r_true) in zip(found, truth):
        assert abs(math.log10(tau / tau_true)) <= tau_decades, (found, truth)
        assert abs(r - r_true) <= r_rel * r_true, (found, truth)


# ---------------------------------------------------------------- basis and closed forms

@pytest.mark.parametrize("omega", [0.07, 2 * math.pi * 5.0, 3e4])
@pytest.mark.parametrize("index", [0, 35, 70])
def test_basis_integrals_match_adaptive_quadrature(omega, index):
    basis = rbf_basis(F)
    a_re, a_im = impedance_integrals(np.array([omega]), basis)
    y0, eps = basis.ln_tau[index], basis.epsilon
    phi = lambda y: math.exp(-((eps * (y - y0)) ** 2))
    lo, hi = y0 - 12 / eps, y0 + 12 / eps
    re = quad(lambda y: phi(y) / (1 + (omega * math.exp(y)) ** 2), lo, hi, epsabs=1e-15, epsrel=1e-13, limit=200)[0]
    im = quad(lambda y: -phi(y) * omega * math.exp(y) / (1 + (omega * math.exp(y)) ** 2), lo, hi, epsabs=1e-15, epsrel=1e-13, limit=200)[0]
    assert a_re[0, index] == pytest.approx(re, abs=1e-12)
    assert a_im[0, index] == pytest.approx(im, abs=1e-12)


@pytest.mark.parametrize("order", [1, 2])
def test_penalty_matrix_is_the_integral_of_the_squared_derivative(order):
    basis = rbf_basis(F)
    x = np.random.default_rng(3).random(basis.ln_tau.size)
    y = np.linspace(basis.ln_tau[0] - 4, basis.ln_tau[-1] + 4, 100001)
    g = basis.evaluate(y) @ x
    for _ in range(order):
        g = np.gradient(g, y)
    assert x @ penalty_matrix(basis, order) @ x == pytest.approx(np.trapezoid(g**2, y), rel=1e-4)


@pytest.mark.parametrize(
    "gamma_fn, z_fn",
    [
        (lambda t: zarc_drt(t, 2.0, 0.5, 0.8), lambda w: 2.0 / (1 + (1j * w * 0.5) ** 0.8)),
        (lambda t: r_cpe_drt(t, 3.0, 1e-2, 0.7), lambda w: 1 / (1 / 3.0 + 1e-2 * (1j * w) ** 0.7)),
        (lambda t: havriliak_negami_drt(t, 2.0, 1.0, 0.7, 0.6), lambda w: 2.0 / (1 + (1j * w) ** 0.7) ** 0.6),
    ],
)
def test_closed_form_drts_reproduce_their_impedance(gamma_fn, z_fn):
    y = np.linspace(-45, 45, 600001)
    tau = np.exp(y)
    g = gamma_fn(tau)
    for w in (1e-2, 0.7, 30.0):
        z = np.trapezoid(g / (1 + 1j * w * tau), y)
        assert z == pytest.approx(z_fn(w), abs=2e-6)


def test_r_cpe_time_constant_and_an_alpha_near_zero():
    assert r_cpe_tau(3.0, 1e-2, 0.7) == pytest.approx(0.03 ** (1 / 0.7), rel=1e-12)
    assert math.isnan(r_cpe_tau(-3.0, 1e-2, 0.7)) and math.isnan(r_cpe_tau(3.0, 1e-2, 0.0))
    # (R·Q)^(1/α) = 1e4^200 overflows a float (Python raised OverflowError): τ₀ = inf, and the
    # block, whose impedance R/(1 + (jωτ₀)^α) is 0 at every finite ω, has a zero DRT
    assert r_cpe_tau(1e3, 10.0, 0.005) == math.inf
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tau = np.logspace(-6, 6, 13)
        assert np.all(r_cpe_drt(tau, 1e3, 10.0, 0.005) == 0.0)
        result = circuit_drt("R0 + R1 || CPE1", {"R0": 1.0, "R1": 1e3, "CPE1.Q": 10.0, "CPE1.alpha": 0.005}, tau=tau)
    assert np.all(result.gamma == 0.0)


def test_havriliak_negami_closed_form_equals_the_stieltjes_inversion():
    tau = np.logspace(-4, 3, 50)
    assert havriliak_negami_drt(tau, 5.0, 0.1, 0.8, 0.6) == pytest.approx(hn_true_gamma(tau, 5.0, 0.1, 0.8, 0.6), rel=1e-10)


def test_circuit_drt_of_series_blocks():
    values = {"R0": 10.0, "R1": 100.0, "C1": 1e-5, "R2": 300.0, "CPE2.Q": 1e-3, "CPE2.alpha": 0.8}
    result = circuit_drt("R0 + R1 || C1 + R2 || CPE2", values)
    assert result.r_inf_ohm == 10.0
    assert result.deltas == ((pytest.approx(1e-3), 100.0),)
    tau0 = (300.0 * 1e-3) ** (1 / 0.8)
    x = np.log(result.tau / tau0)
    expected = 300.0 / (2 * math.pi) * math.sin(0.2 * math.pi) / (np.cosh(0.8 * x) - math.cos(0.2 * math.pi))
    assert result.gamma == pytest.approx(expected, rel=1e-12)
    assert [t for t, _ in result.relaxations] == [pytest.approx(1e-3), pytest.approx(tau0, rel=0.06)]
    with pytest.raises(CircuitError, match="W1"):
        circuit_drt("R0 + W1", {"R0": 1.0, "W1": 1.0})
    with pytest.raises(ParameterError, match="C1"):
        circuit_drt("R0 + R1 || C1", {"R0": 1.0, "R1": 1.0})


# ---------------------------------------------------------------- recovery of known DRTs

SINGLE = {
    "R||C": (10 + rc(1000, 1e-2), [(1e-2, 1000)]),
    "ZARC a=0.8": (10 + zarc(1000, 1e-2, 0.8), [(1e-2, 1000)]),
    "R||CPE a=0.7": (5 + 1 / (1 / 800 + 2e-4 * (1j * W) ** 0.7), [((800 * 2e-4) ** (1 / 0.7), 800)]),
}


@pytest.mark.parametrize("level", [0.003, 0.01, 0.03])
@pytest.mark.parametrize("case", list(SINGLE))
def test_single_relaxation_peak(case, level):
    z, truth = SINGLE[case]
    result = drt((F, noisy(z, level, 1)))
    assert_peaks(result, truth)
    assert result.r_inf_ohm == pytest.approx(z[-1].real, rel=0.1, abs=1.0)
    assert result.converged
    # an ideal R‖C is a delta: the smoothness penalty at λ's floor leaves ≈ 1 % misfit at low noise
    assert result.rms_rel < max(2.5 * level, 0.02)


@pytest.mark.parametrize("level", [0.003, 0.01, 0.03])
def test_havriliak_negami_peak_at_the_true_maximum(level):
    r, tau0, alpha, beta = 1000.0, 1e-2, 0.9, 0.85
    tau = np.logspace(-6, 2, 20001)
    tau_peak = tau[np.argmax(hn_true_gamma(tau, r, tau0, alpha, beta))]
    result = drt((F, noisy(10 + hn(r, tau0, alpha, beta), level, 2)))
    assert_peaks(result, [(tau_peak, r)])


MULTI = {
    "two R||C, 1 decade": (10 + rc(500, 1e-3) + rc(1000, 1e-2), [(1e-3, 500), (1e-2, 1000)]),
    "two ZARC, 2 decades": (10 + zarc(500, 1e-4, 0.85) + zarc(1000, 1e-2, 0.85), [(1e-4, 500), (1e-2, 1000)]),
    "three R||C, 2 decades": (10 + rc(500, 1e-4) + rc(1000, 1e-2) + rc(700, 1.0), [(1e-4, 500), (1e-2, 1000), (1.0, 700)]),
    "three R||C, 1.5 decades": (5 + rc(300, 3e-4) + rc(600, 1e-2) + rc(400, 0.3), [(3e-4, 300), (1e-2, 600), (0.3, 400)]),
    # a ZARC's tails reach its neighbours' share of the τ axis (split halfway in log τ): the true
    # resistance under each peak includes them
    "R||C + ZARC + R||C": (
        10 + rc(500, 1e-3) + zarc(1000, 0.03, 0.9) + rc(400, 3.0),
        [(1e-3, 500 + zarc_mass(1000, 0.03, 0.9, 1e-9, math.sqrt(3e-5))), (0.03, zarc_mass(1000, 0.03, 0.9, math.sqrt(3e-5), 0.3)), (3.0, 400 + zarc_mass(1000, 0.03, 0.9, 0.3, 1e6))],
    ),
}


@pytest.mark.parametrize("level", [0.003, 0.01])
@pytest.mark.parametrize("case", list(MULTI))
def test_multi_arc_peaks(case, level):
    z, truth = MULTI[case]
    assert_peaks(drt((F, noisy(z, level, 3))), truth)


def test_multi_arc_peaks_at_3_percent_noise_two_decades_apart():
    z, truth = MULTI["three R||C, 2 decades"]
    assert_peaks(drt((F, noisy(z, 0.03, 4))), truth)


def test_lambda_grows_with_the_noise_and_the_peaks_do_not_oscillate():
    z, truth = MULTI["R||C + ZARC + R||C"]
    lams = []
    for level in (0.003, 0.01, 0.03):
        result = drt((F, noisy(z, level, 5)))
        assert_peaks(result, truth)
        lams.append(result.lam)
    assert lams[0] <= lams[1] < lams[2] and lams[2] > 10 * lams[0]
    # the L-curve corner is offered but smooths more than GCV (docs/drt.md): it may merge the
    # ZARC with its neighbour; it must still fit the data to about the noise
    lcurve = drt((F, noisy(z, 0.01, 5)), lam_method="lcurve")
    assert lcurve.lambda_method == "lcurve" and lcurve.lam > lams[1] and lcurve.rms_rel < 0.03


def test_fixed_lambda_is_used_and_reported():
    result = drt((F, noisy(10 + rc(1000, 1e-2), 0.01, 1)), lam=0.05)
    assert result.lam == pytest.approx(0.05) and result.lambda_method == "fixed"


def test_inductive_loop_needs_signed():
    # a low-frequency inductive loop: a negative-resistance relaxation, plus a lead inductance
    z = 10 + 1j * W * 2e-6 + rc(200, 1e-3) + rc(-60, 0.3)
    data = (F, noisy(z, 0.005, 6))
    signed = drt(data, signed=True)
    assert signed.l_h == pytest.approx(2e-6, rel=0.2)
    assert signed.rms_rel < 0.01
    positive = [p for p in signed.peaks if p.r_ohm > 0]
    negative = [p for p in signed.peaks if p.r_ohm < 0]
    assert len(positive) == 1 and len(negative) == 1
    assert abs(math.log10(positive[0].tau_s / 1e-3)) < 0.1 and positive[0].r_ohm == pytest.approx(200, rel=0.1)
    # the loop shares its ringing with the positive arc: 15 %
    assert abs(math.log10(negative[0].tau_s / 0.3)) < 0.1 and negative[0].r_ohm == pytest.approx(-60, rel=0.15)
    assert np.min(signed.gamma) < 0
    non_negative = drt(data)
    assert np.min(non_negative.gamma) >= 0
    assert non_negative.rms_rel > 3 * signed.rms_rel  # γ ≥ 0 cannot fit the loop


def test_blocking_electrode_gets_a_series_capacitor():
    z = 20 + rc(1000, 1e-3) + 1 / (1j * W * 1e-3)
    result = drt((F, noisy(z, 0.005, 7)))
    assert result.c_f == pytest.approx(1e-3, rel=0.05)
    assert_peaks(result, [(1e-3, 1000)])


def test_batch_over_extra_dimensions_equals_one_by_one():
    spectra = np.stack([noisy(MULTI["two R||C, 1 decade"][0], 0.01, s) for s in range(6)]).reshape(2, 3, -1)
    data = ix.make_spectrum(F, spectra, dims=("session", "trial"), coords={"session": [1, 2], "trial": [10, 20, 30]})
    batch = drt(data)
    assert isinstance(batch, DRTBatchResult) and batch.shape == (2, 3) and len(batch) == 6
    single = drt((F, spectra[1, 2]))
    assert batch[1, 2].gamma == pytest.approx(single.gamma, rel=1e-7, abs=1e-9 * single.gamma.max())
    assert batch[1, 2].lam == pytest.approx(single.lam, rel=1e-9)
    assert [p.tau_s for p in batch[1, 2].peaks] == pytest.approx([p.tau_s for p in single.peaks])
    ds = batch.to_xarray()
    assert ds["gamma"].dims == ("session", "trial", "tau")
    assert list(ds["trial"].values) == [10, 20, 30]
    assert (batch.n_peaks == 2).all()
    assert batch.report().startswith("DRT of 6 spectra over session × trial: 6 with 2 peak(s)")


def test_credible_band_brackets_the_estimate_and_peaks_have_uncertainty():
    result = drt((F, noisy(10 + zarc(1000, 1e-2, 0.8), 0.01, 8)))
    assert np.all(result.gamma_q05 <= result.gamma + 1e-9) and np.all(result.gamma + 1e-9 >= result.gamma_q05)
    assert np.all(result.gamma_q95 >= result.gamma - 1e-9) and np.all(result.gamma_q05 >= 0)
    assert np.max(result.gamma_q95 - result.gamma_q05) > 0
    (peak,) = result.peaks
    assert 0 < peak.r_ohm_sd < 0.1 * peak.r_ohm and 0 <= peak.log10_tau_sd < 0.2


CALIBRATION_CASES = {
    "ZARC α=0.8": (10 + zarc(1000, 1e-2, 0.8), lambda t: zarc_drt(t, 1000, 1e-2, 0.8)),
    "ZARC α=0.6": (10 + zarc(1000, 1e-2, 0.6), lambda t: zarc_drt(t, 1000, 1e-2, 0.6)),
    "two ZARCs": (10 + zarc(500, 1e-4, 0.85) + zarc(1000, 1e-1, 0.75), lambda t: zarc_drt(t, 500, 1e-4, 0.85) + zarc_drt(t, 1000, 1e-1, 0.75)),
    "HN α=0.9 β=0.85": (10 + hn(1000, 1e-2, 0.9, 0.85), lambda t: hn_true_gamma(t, 1000, 1e-2, 0.9, 0.85)),
}


def band_coverage(result, truth_fn):
    """Fraction of the output τ inside the measured range 1/ω_max..1/ω_min where the true γ lies
    in [gamma_q05, gamma_q95]."""
    lo, hi = result.window
    inside = (result.tau >= lo) & (result.tau <= hi)
    truth = truth_fn(result.tau[inside])
    return float(np.mean((result.gamma_q05[inside] <= truth) & (truth <= result.gamma_q95[inside])))


@pytest.mark.slow
def test_credible_band_is_calibrated():
    """Pointwise coverage of the true γ by the 90 % band, averaged over τ in the measured range,
    12 noise seeds per case at 0.3, 1 and 3 % noise (one batched call each). Target (issue 16):
    80–97 % on average. Bounds: the grand mean over the 12 (case, noise) cells within 0.80–0.97;
    each cell within 0.65–1.0 (a cell is 12 spectra whose coverages are strongly correlated over
    τ, so one cell scatters by ±0.08 between seed sets; measured cells in docs/drt.md)."""
    cells = {}
    for name, (z, truth_fn) in CALIBRATION_CASES.items():
        for level in (0.003, 0.01, 0.03):
            batch = drt((F, np.stack([noisy(z, level, 500 + seed) for seed in range(12)])))
            cells[name, level] = float(np.mean([band_coverage(r, truth_fn) for r in batch.results]))
    grand = float(np.mean(list(cells.values())))
    assert 0.80 <= grand <= 0.97, cells
    assert all(0.65 <= c <= 1.0 for c in cells.values()), cells


def test_result_to_xarray_and_report():
    result = drt((F, noisy(MULTI["two R||C, 1 decade"][0], 0.01, 9)))
    assert isinstance(result, DRTResult)
    ds = result.to_xarray()
    assert ds["gamma"].attrs["units"] == "ohm" and ds["tau"].size == result.tau.size
    assert ds["peak_tau"].size == 2 and ds.attrs["lambda_method"] == "gcv"
    text = result.report()
    assert "2 peak(s)" in text and "λ =" in text
    assert result.gamma_at(result.peaks[0].tau_s) == pytest.approx(result.peaks[0].gamma_max_ohm, rel=0.05)


def test_plot_returns_a_figure_with_the_overlay():
    import matplotlib.pyplot as plt

    data = noisy(10 + rc(500, 2e-3) + zarc(1000, 0.3, 0.8), 0.01, 10)
    result = drt((F, data))
    overlay = circuit_drt("R0 + R1 || C1 + R2 || CPE2", {"R0": 10, "R1": 500, "C1": 4e-6, "R2": 1000, "CPE2.Q": 0.3**0.8 / 1000, "CPE2.alpha": 0.8})
    fig = result.plot(overlay=overlay)
    assert len(fig.axes) == 5
    plt.close(fig)


# ---------------------------------------------------------------- evidence for the diagnosis

def test_unexplained_peaks_names_the_missing_arc():
    data = noisy(10 + rc(500, 1e-3) + zarc(1000, 0.1, 0.9) + rc(400, 10.0), 0.005, 11)
    result = drt((F, data))
    model = (F, 10 + rc(500, 1e-3) + zarc(1000, 0.1, 0.9))
    evidence = unexplained_peaks(result, model)
    assert evidence.n_explained == 2 and len(evidence.unexplained) == 1
    (missing,) = evidence.unexplained
    assert abs(math.log10(missing.tau_s / 10.0)) < 0.15 and missing.r_ohm == pytest.approx(400, rel=0.15)
    assert evidence.text.startswith("the data's DRT has 3 peaks (at 1 ms, 100 ms, 10 s); the model explains 2; unexplained: 10 s")
    full = unexplained_peaks(result, (F, 10 + rc(500, 1e-3) + zarc(1000, 0.1, 0.9) + rc(400, 10.0)))
    assert full.unexplained == () and full.n_explained == 3


def test_an_unexplained_peak_the_band_cannot_tell_from_zero_is_said_so():
    """Two unexplained peaks put by hand beside a real DRT's: one of R 40 ± 5 Ω (resolved, 8σ)
    and one of R 0.3 ± 0.5 Ω (under `RESOLVED_SIGMAS` = 2σ: a ripple). The text names the first
    as unexplained and the second as not told from zero, with its ± (an ADEQUATE diagnosis
    listed such a ripple as an unexplained relaxation); both stay τ guesses for proposals."""
    import dataclasses

    from impedax.fitting.drt import Peak, RESOLVED_SIGMAS, is_resolved

    result = drt((F, noisy(10 + rc(500, 1e-3), 0.005, 11)))
    firm = Peak(tau_s=10.0, r_ohm=40.0, width_decades=0.8, gamma_max_ohm=30.0, r_ohm_sd=5.0)
    ripple = Peak(tau_s=1e-5, r_ohm=0.3, width_decades=0.8, gamma_max_ohm=0.2, r_ohm_sd=0.5)
    data = dataclasses.replace(result, peaks=tuple(sorted(result.peaks + (firm, ripple), key=lambda p: p.tau_s)))
    evidence = unexplained_peaks(data, result)  # the model: the one-arc DRT itself
    assert RESOLVED_SIGMAS == 2.0 and is_resolved(firm) and not is_resolved(ripple)
    assert is_resolved(dataclasses.replace(ripple, r_ohm_sd=math.nan))  # no band: nothing says otherwise
    assert set(evidence.unexplained) == {firm, ripple} and evidence.unresolved == (ripple,)
    assert "; unexplained: 10 s (R ≈ 40 Ω)" in evidence.text, evidence.text
    assert "not told from zero by the DRT's uncertainty" in evidence.text and "(R ≈ 300 ± 500 mΩ)" in evidence.text
    only_ripple = unexplained_peaks(dataclasses.replace(result, peaks=tuple(sorted(result.peaks + (ripple,), key=lambda p: p.tau_s))), result)
    assert "unexplained:" not in only_ripple.text and only_ripple.unresolved == (ripple,)


def test_unexplained_peaks_flags_a_distributed_peak_as_cpe_like():
    result = drt((F, noisy(10 + zarc(1000, 1e-2, 0.65), 0.005, 12)))
    evidence = unexplained_peaks(result, (F, 10 + rc(1000, 1e-2)))
    assert evidence.unexplained == () and len(evidence.distributed) == 1
    assert "CPE-like" in evidence.text
    sharp = unexplained_peaks(drt((F, noisy(10 + rc(1000, 1e-2), 0.005, 12))), (F, 10 + rc(1000, 1e-2)))
    assert sharp.distributed == ()


def test_unexplained_peaks_accepts_a_fit_result():
    data = ix.make_spectrum(F, noisy(10 + rc(500, 1e-3) + rc(1000, 0.1), 0.005, 13))
    fit = ix.fit("R0 + R1 || C1", data, init={"R0": 10, "R1": 1500, "C1": 1e-4})
    evidence = unexplained_peaks(drt(data), fit)
    assert len(evidence.data_peaks) == 2 and len(evidence.unexplained) >= 1
    with pytest.raises(DataError):
        unexplained_peaks(drt(data), 42)


# ---------------------------------------------------------------- bad input

GOOD = (F, 10 + rc(100, 1e-3))


@pytest.mark.parametrize(
    "data, kwargs, error, match",
    [
        (GOOD, {"lam": -1.0}, ParameterError, "positive"),
        (GOOD, {"lam": "big"}, ParameterError, "auto"),
        (GOOD, {"lam_method": "aic"}, ParameterError, "gcv"),
        (GOOD, {"method": "bayes"}, ParameterError, "tikhonov"),
        (GOOD, {"basis": "pwl"}, ParameterError, "rbf"),
        (GOOD, {"derivative": 3}, ParameterError, "derivative"),
        (GOOD, {"signed": "yes"}, ParameterError, "signed"),
        (GOOD, {"capacitance": "maybe"}, ParameterError, "capacitance"),
        ((F, np.where(F > 1e3, np.nan, 1.0 + 0j)), {}, DataError, "non-finite"),
        ((F, np.zeros(F.size, complex)), {}, DataError, "zero"),
        ((F[:3], np.ones(3, complex)), {}, DataError, "at least 5"),
        ((F, np.ones(5, complex)), {}, DataError, "Z has 5 values along frequency but there are 71 frequencies"),
        ("no_such_file.csv", {}, DataError, "not found"),
        (42, {}, DataError, "expected"),
    ],
)
def test_bad_input_raises_impedax_errors(data, kwargs, error, match):
    with pytest.raises(error, match=match):
        drt(data, **kwargs)


# ---------------------------------------------------------------- command line

def test_cli_json_keys_and_outputs(tmp_path, capsys):
    from impedax.cli import main

    path = tmp_path / "s.csv"
    ix.save(ix.make_spectrum(F, noisy(10 + rc(500, 1e-3) + rc(1000, 0.1), 0.005, 14)), path)
    assert main(["drt", str(path), "--json", "--plot", str(tmp_path / "d.png"), "--out", str(tmp_path / "d.nc")]) == 0
    payload = json.loads(capsys.readouterr().out)
    # the public contract: these keys stay (more are added: tests/test_drt_review.py)
    assert {"tau_s", "gamma_ohm", "gamma_q05", "gamma_q95", "r_inf_ohm", "l_h", "lambda", "lambda_method", "peaks", "rms_rel", "warnings"} <= set(payload)
    assert len(payload["peaks"]) == 2 and all({"tau_s", "r_ohm", "width_decades"} <= set(p) for p in payload["peaks"])
    assert payload["lambda_method"] == "gcv" and len(payload["tau_s"]) == len(payload["gamma_q95"])
    assert (tmp_path / "d.png").read_bytes()[:4] == b"\x89PNG"
    import xarray as xr

    with xr.open_dataset(tmp_path / "d.nc") as ds:
        assert ds["gamma"].size == len(payload["tau_s"])
    assert main(["drt", str(path), "--lam", "0.01", "--signed", "--out", str(tmp_path / "g.csv")]) == 0
    text = capsys.readouterr().out
    assert "λ = 0.01 as given" in text and "signed" in text
    assert (tmp_path / "g.csv").read_text().startswith("tau_s,gamma_ohm")
    assert main(["drt", str(path), "--lam", "lots"]) == 2
    assert "--lam" in capsys.readouterr().err


@pytest.mark.slow
def test_evidence_names_the_missing_arc_on_random_multi_arc_spectra():
    """40 random spectra with 2–3 arcs (R‖C or ZARC α 0.75–0.95, 1–2 decades apart, 0.3–3 %
    noise); the model is the true spectrum without one arc. The missing arc must be the one
    unexplained peak (τ within 0.3 decade) in ≥ 90 % of them (measured: 39/40)."""
    rng = np.random.default_rng(42)
    hits = 0
    for _ in range(40):
        n_arcs = int(rng.choice([2, 3]))
        start = rng.uniform(-4.5, -3.0)
        taus = 10 ** np.concatenate([[start], start + np.cumsum(rng.uniform(1.0, 2.0, size=n_arcs - 1))])
        rs = rng.uniform(300, 1000, size=n_arcs)
        alphas = np.where(rng.random(n_arcs) < 0.5, 1.0, rng.uniform(0.75, 0.95, size=n_arcs))
        arcs = [r / (1 + (1j * W * t) ** a) for r, t, a in zip(rs, taus, alphas)]
        level = float(rng.choice([0.003, 0.01, 0.03]))
        z = (10 + sum(arcs)) * (1 + level * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)) / math.sqrt(2))
        k = int(rng.integers(n_arcs))
        evidence = unexplained_peaks(drt((F, z)), (F, 10 + sum(a for i, a in enumerate(arcs) if i != k)))
        hits += len(evidence.unexplained) == 1 and abs(math.log10(evidence.unexplained[0].tau_s / taus[k])) < 0.3
    assert hits >= 36, hits


def test_warnings_name_what_no_passive_cell_has():
    """A closed-form arc with R_∞ = −5 Ω (non-passive), with a negative series L, and the
    same arc with R_∞ = 10 Ω and nothing else (no warning)."""
    arc = rc(1000, 1e-3)
    passive = drt((F, noisy(10 + arc, 0.005, 1)))
    assert passive.warnings == () and passive.summary()["warnings"] == []
    negative_r = drt((F, noisy(-5 + arc, 0.005, 1)))
    assert negative_r.r_inf_ohm < -4 and any(w.startswith("R_inf = ") and "negative" in w for w in negative_r.warnings)
    negative_l = drt((F, noisy(10 + arc - 1j * W * 1e-5, 0.005, 1)))
    assert negative_l.l_h == pytest.approx(-1e-5, rel=0.1)
    assert any(w.startswith("L = ") for w in negative_l.warnings) and "warning: L = " in negative_l.report()


def test_the_report_writes_its_values_with_si_prefixes():
    # SYNTHETIC: 20 Ω + a ZARC of 2.2 kΩ at τ = 2 ms, and a series inductance of 3 µH. The
    # report read "R = 2201 ± 1.2e+02 Ω", "L = 3e-06 H", "f = 79.6 Hz" before; now each in
    # the prefix of its value, the standard error in the value's prefix
    z = 20.0 + zarc(2200.0, 2e-3, 0.9) + 1j * W * 3e-6
    result = ix.drt(ix.make_spectrum(F, noisy(z, 0.003, 7)))
    text = result.report()
    assert "e+" not in text and "e-" not in text, text
    assert " µH" in text and "R_pol = 2." in text and " kΩ" in text, text
    (peak,) = result.peaks
    line = next(ln for ln in text.splitlines() if ln.lstrip().startswith("τ = "))
    value, _, rest = line.split("R = ")[1].partition(" ± ")
    assert float(value) * 1e3 == pytest.approx(peak.r_ohm, rel=5e-3) and rest.split()[1] == "kΩ"
    assert float(rest.split()[0]) * 1e3 == pytest.approx(peak.r_ohm_sd, rel=0.05)


def test_format_uncertain_reads_as_written_by_hand():
    # the value to the last digit of its error, the error to two significant digits (GUM §7.2.6),
    # in the SI prefix of the value as rounded (rule of 2026-12-01; it had 3 digits whatever the error)
    from impedax.data import format_uncertain

    assert format_uncertain(730.8, 120.0, "Ohm") == "730 ± 120 Ω"
    assert format_uncertain(3939.0, 190.0, "Ohm") == "3.94 ± 0.19 kΩ"
    assert format_uncertain(2.78e-6, 1e-7, "H") == "2.78 ± 0.10 µH"
    assert format_uncertain(1.15, 0.0056, "Ohm") == "1.1500 ± 0.0056 Ω"  # the user's line, was "1.15 ± 0.0056 Ω"
    assert format_uncertain(0.7732, 0.0051, "Ohm") == "773.2 ± 5.1 mΩ"  # beside it, was "773 ± 5.1 mΩ"
    assert format_uncertain(999.6, 5.0, "Ohm") == "999.6 ± 5.0 Ω"  # the prefix of the value as rounded to its error
    assert format_uncertain(999.96, 5.0, "Ohm") == "1.0000 ± 0.0050 kΩ"  # (999.96 at the 0.1 digit is 1000.0)
    assert format_uncertain(0.5, 0.1, "1") == "0.50 ± 0.10"
    assert format_uncertain(0.0, 1.0, "Ohm") == "0.0 ± 1.0 Ω"
    assert format_uncertain(0.3, 0.5, "Ohm") == "300 ± 500 mΩ"  # below its error: each to 2 digits
    assert format_uncertain(2e-5, 3e-6, "F s^(alpha-1)") == "20.0 ± 3.0 µF s^(α-1)"  # (a compound unit in the prefix of its leading unit; was "(2.00 ± 0.30)e-05 F s^(α-1)")
    assert format_uncertain(3939.0, float("nan"), "Ohm") == "3.94 ± nan kΩ"  # the value keeps its prefix
    assert format_uncertain(999.6, -5.0, "Ohm") == "999.6 ± 5.0 Ω"  # an error is a size


def _decimals(number: str) -> int:
    """Digits after the decimal point of a number as printed ("773.2" → 1, "120" → 0)."""
    return len(number.partition(".")[2])


def test_cli_drt_peak_values_have_the_decimals_of_their_errors_on_real_data(capsys):
    # REAL data (AutoEIS battery cycle 64): the user saw "1.15 ± 0.0056 Ω" beside "773 ± 5.1 mΩ"
    import re
    from pathlib import Path

    from impedax.cli import main

    path = Path(__file__).parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc"
    assert main(["drt", str(path), "--select", "cycle=64"]) == 0
    text = capsys.readouterr().out
    pairs = re.findall(r"R = (-?\d+(?:\.\d+)?) ± (\d+(?:\.\d+)?) (mΩ|Ω|kΩ)", text)
    assert len(pairs) == 3, text  # three peaks, each "R = value ± error unit"
    for value, error, _ in pairs:
        assert _decimals(value) == _decimals(error), (value, error)
        assert len(error.replace(".", "").lstrip("0")) == 2, error  # two significant digits
    assert any(unit == "Ω" and _decimals(value) == 4 for value, _, unit in pairs), pairs  # the 73 ms peak: ± 0.0056 Ω


def test_the_drt_model_predicts_between_the_data_and_is_drawn_as_a_curve():
    # SYNTHETIC 20 Ω + a ZARC: predict() is z_fit at the data's frequencies, follows the formula
    # between them (the DRT's misfit is well below 1 % here) and the figure draws it densely
    z = 20.0 + zarc(2200.0, 2e-3, 0.9)
    result = ix.drt(ix.make_spectrum(F, z))
    np.testing.assert_allclose(result.predict(F), result.z_fit, rtol=1e-12)
    between = np.sqrt(F[:-1] * F[1:])
    w_between = 2 * np.pi * between
    z_between = 20.0 + 2200.0 / (1 + (1j * w_between * 2e-3) ** 0.9)
    assert np.max(np.abs(result.predict(between) - z_between) / np.abs(z_between)) < 1e-2
    fig = result.plot()
    nyquist = [ax for ax in fig.axes if ax.get_xlabel().startswith("Z'")][0]
    (line,) = [ln for ln in nyquist.get_lines() if ln.get_label() == "DRT fit"]
    assert line.get_xydata().shape[0] >= 200


def test_the_drt_model_predicts_with_a_series_capacitance_and_for_a_scalar():
    # SYNTHETIC blocking electrode: 20 Ω + a ZARC in series with 50 µF, fitted with the series
    # capacitance: predict() is z_fit at the data's frequencies (the 1/(jωC) term included),
    # follows the formula between them, and takes a scalar frequency
    z = 20.0 + zarc(2200.0, 2e-3, 0.9) + 1 / (1j * W * 50e-6)
    result = ix.drt(ix.make_spectrum(F, z), capacitance=True)
    assert np.isfinite(result.c_f)
    np.testing.assert_allclose(result.predict(F), result.z_fit, rtol=1e-12)
    between = np.sqrt(F[:-1] * F[1:])
    w = 2 * np.pi * between
    z_between = 20.0 + 2200.0 / (1 + (1j * w * 2e-3) ** 0.9) + 1 / (1j * w * 50e-6)
    assert np.max(np.abs(result.predict(between) - z_between) / np.abs(z_between)) < 1e-2
    assert np.shape(result.predict(10.0)) == () and result.predict(10.0) == pytest.approx(result.predict(np.array([10.0]))[0], rel=1e-14)


def test_a_signed_drt_of_one_arc_gives_it_the_whole_area():
    """A signed DRT of one exact arc, 10 Ω + 100 Ω ∥ 100 µF (τ = 10 ms): its one peak's R is the
    whole axis' area, lobes of the other sign included, so it equals R_pol and the true 100 Ω
    (it kept its positive lobe alone, 128.4 Ω, and suggested R1 = 128.4; walkthrough 2026-12-05)."""
    f = np.logspace(-2, 5, 71)
    z = 10.0 + 100.0 / (1.0 + 2j * np.pi * f * 100.0 * 100e-6)
    result = drt((f, z), signed=True)
    from impedax.fitting.drt.peaks import counted_peaks

    (peak,) = counted_peaks(result.peaks)
    assert peak.r_ohm == pytest.approx(100.0, rel=0.02) and peak.r_ohm == pytest.approx(result.polarization_resistance, rel=0.005)
    assert abs(math.log10(peak.tau_s / 1e-2)) < 0.05
