"""The diagnosis' noise model, data problems located point by point, identifiability and
plausibility of suggestions (docs/diagnosis.md, sections 1, 2 and 5). SYNTHETIC spectra from the
numpy formulas of tests/hidden_effects.py (independent of impedax's circuits)."""

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis.catalog import Proposal
from impedax.fitting.diagnosis.diagnosis import CORRELATED_ERROR_MAX, CORRELATION_MAX, NOISE_FRACTION_MIN, centred_covariance, format_quantity, undetermined_parameters
from impedax.fitting.diagnosis.effects import DEFAULT_EFFECTS

import evaluation_set as es
import hidden_effects as he


def uneven_spectrum(name, seed, sigma_top=0.002, sigma_bottom=0.03):
    """A correct model's spectrum whose relative noise grows log-linearly from ``sigma_top`` at
    the highest frequency to ``sigma_bottom`` at the lowest (as on skin and electrochemical
    cells), complex Gaussian per component."""
    circuit, formula, params, frange = he.ADEQUATE[name]
    rng = np.random.default_rng(seed)
    f = he.frequencies(*frange)
    x = np.linspace(1.0, 0.0, f.size)  # 1 at the lowest frequency
    sigma = sigma_top * (sigma_bottom / sigma_top) ** x
    z = formula(f, params)
    z = z + sigma * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    return circuit, f, z, sigma


@pytest.mark.parametrize("name,seed", [("r_cpe", 3)])
def test_noise_growing_toward_low_frequency_on_a_correct_model_is_adequate(name, seed):
    circuit, f, z, sigma = uneven_spectrum(name, seed)
    d = ix.diagnose(ix.make_spectrum(f, z), circuit)
    assert d.verdict == "adequate", d.report()
    assert d.suggestions == ()
    est = d.measurement_noise[np.argsort(d.baseline.frequency)]
    # the estimate follows the noise: the low-frequency decade is seen as several times noisier
    # (truth 15×; a median over 9 points scatters by ~±30 %, so a loose factor 3 and a factor-3 band)
    assert np.mean(est[:10]) > 3 * np.mean(est[-10:])
    assert 1 / 3 < np.mean(est[:10]) / np.mean(sigma[:10]) < 3
    per_f = d.summary()["noise"]["per_frequency"]
    assert len(per_f) == d.baseline.n_points and min(per_f) >= ix.fitting.diagnosis.noise.NOISE_FLOOR


def test_uniform_noise_gets_no_discrepancy_floor_and_the_right_level():
    circuit, formula, params, frange = he.ADEQUATE["randles"]
    rng = np.random.default_rng(11)
    f, z = he.spectrum(formula, params, frange, 0.01, rng)
    d = ix.diagnose(ix.make_spectrum(f, z), circuit)
    assert d.verdict == "adequate", d.report()
    # KK residuals of KK-consistent data are noise: the floor must not inflate σ by more than 30 %
    assert d.discrepancy < 0.01 * 0.8
    assert 0.6 < d.noise_level / 0.01 < 1.5


def test_a_few_erratic_points_are_masked_and_the_rest_diagnosed():
    circuit, effect, formula, params, frange = he.CASES["series_resistance/rc"]
    rng = np.random.default_rng(7)
    f, z = he.spectrum(formula, params, frange, 0.005, rng)
    z = z.copy()
    bad = [55, 56, 57]  # three erratic points near the top of the band
    z[bad] *= np.array([1.25 - 0.2j, 0.8 + 0.25j, 1.3 + 0.1j])
    d = ix.diagnose(ix.make_spectrum(f, z), circuit)
    assert d.verdict == "missing_effect", d.report()
    assert set(np.round(f[bad], 6)) <= set(np.round(d.masked_points, 6))
    assert len(d.masked_points) <= 8  # the mask is as narrow as the offending points (and a neighbour or two)
    assert d.suggestions[0].effect == effect
    assert d.baseline.n_points == f.size - len(d.masked_points)
    assert d.summary()["masked_points"] == list(d.masked_points)
    # (2026-12-02) the verdict says it was judged without them, and JSON says how many
    verdict = next(x for x in d.report().splitlines() if x.startswith("verdict:"))
    kept = np.setdiff1d(np.round(f, 6), np.round(d.masked_points, 6))
    assert verdict.startswith(
        f"verdict: MISSING_EFFECT on {ix.fitting.diagnosis.bands.format_frequency(kept.min())} – {ix.fitting.diagnosis.bands.format_frequency(kept.max())} "
        f"({kept.size} of {f.size} points; the other {len(d.masked_points)} left out as not Kramers–Kronig consistent) — "
    ), verdict
    assert (d.summary()["n_points_judged"], d.summary()["n_points_left_out"]) == (kept.size, len(d.masked_points))
    assert d.summary()["verdict_band_hz"] == [pytest.approx(kept.min()), pytest.approx(kept.max())]


def _with_non_passive_top(formula, params, frange, seed):
    """A spectrum whose two highest frequencies carry a phase error large enough to turn the
    real part negative (Re Z < 0: no passive circuit gives it), as a real instrument file does."""
    f, z = he.spectrum(formula, params, frange, 0.005, np.random.default_rng(seed))
    top = np.argsort(f)[-2:]
    z = z.copy()
    z[top] = np.abs(z[top]) * np.exp(1j * np.array([2.2, 1.9]))  # phase 126° and 109°: Re < 0
    assert np.all(z[top].real < 0)
    return f, z, top


def test_points_with_a_negative_real_part_are_left_out_of_a_correct_model():
    circuit, formula, params, frange = he.ADEQUATE["r_cpe"]
    f, z, top = _with_non_passive_top(formula, params, frange, 5)
    d = ix.diagnose(ix.make_spectrum(f, z), circuit)
    assert d.verdict == "adequate", d.report()
    assert set(np.round(f[top], 6)) <= set(np.round(d.masked_points, 6))
    assert d.baseline.n_points == f.size - len(d.masked_points)
    assert "Re Z < 0" in d.report()
    # (2026-12-02) the verdict names the points it was judged on and why the others were left out
    assert set(np.round(d.not_passive_points, 6)) == set(np.round(f[top], 6))
    verdict = next(x for x in d.report().splitlines() if x.startswith("verdict:"))
    assert f"({f.size - len(d.masked_points)} of {f.size} points; the other {len(d.masked_points)} left out" in verdict, verdict
    assert "for Re Z < 0, which no passive circuit gives)" in verdict and verdict.startswith("verdict: ADEQUATE on "), verdict
    # the fit of the rest finds the generating parameters (0.5 % noise: R1 within 3 %)
    assert d.baseline.values["R1"] == pytest.approx(params["R1"], rel=0.03)
    # each masked point keeps its measured Z, and the figure marks it (red crosses)
    by_f = dict(zip(np.round(f, 6), z))
    assert [by_f[round(fm, 6)] for fm in d.masked_points] == list(d.masked_impedance)
    fig = d.plot()
    nyquist, magnitude, phase = fig.axes[:3]
    (cross,) = [line for line in nyquist.get_lines() if line.get_marker() == "x"]
    np.testing.assert_allclose(cross.get_xydata(), np.column_stack([z[top].real, -z[top].imag])[np.argsort(f[top])])
    (cross,) = [line for line in magnitude.get_lines() if line.get_marker() == "x"]
    np.testing.assert_allclose(cross.get_xydata(), np.column_stack([f[top], np.abs(z[top])])[np.argsort(f[top])])
    (cross,) = [line for line in phase.get_lines() if line.get_marker() == "x"]
    np.testing.assert_allclose(cross.get_ydata(), np.degrees(np.angle(z[top]))[np.argsort(f[top])])
    assert any(t.get_text().startswith("masked (2") for t in nyquist.get_legend().get_texts())


def test_a_missing_effect_is_found_behind_non_passive_points():
    circuit, effect, formula, params, frange = he.CASES["series_resistance/rc"]
    f, z, top = _with_non_passive_top(formula, params, frange, 6)
    d = ix.diagnose(ix.make_spectrum(f, z), circuit)
    assert d.verdict == "missing_effect" and d.suggestions[0].effect == effect, d.report()
    assert set(np.round(f[top], 6)) <= set(np.round(d.masked_points, 6))


def test_a_spectrum_mostly_below_zero_is_not_masked_away():
    from impedax.fitting.diagnosis.diagnosis import non_passive_points

    f = np.geomspace(1, 1e5, 30)
    z = -(10 + 100 / (1 + 1j * f / 1e3))  # a sign error of the whole file: not a few artifacts
    assert not non_passive_points(ix.make_spectrum(f, z)).any()
    z = 10 + 100 / (1 + 1j * f / 1e3)
    z[-1] = -z[-1].real + 1j * z[-1].imag
    assert non_passive_points(ix.make_spectrum(f, z)).tolist() == [False] * 29 + [True]
    # a capacitive spectrum (Re Z ≈ 0) at 1 % noise: Re Z dips below zero by the noise only
    rng = np.random.default_rng(8)
    f = np.geomspace(1, 1e6, 60)
    z = 1.0 + 1 / (2j * np.pi * f * 4e-10)
    z = z + 0.01 * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    assert (z.real < 0).sum() > 10 and not non_passive_points(ix.make_spectrum(f, z)).any()
    # ... and a point below zero by less than 3σ of the data's own σ is noise too
    sigma = np.full(f.size, 1e3)
    z2 = 1e4 + 1 / (2j * np.pi * f * 4e-10)
    z2[-1] = -2.5e3 + 1j * z2[-1].imag  # −2.5σ, far beyond 5 % of |Z| at 1 MHz
    assert non_passive_points(ix.make_spectrum(f, z2)).tolist()[-1]
    assert not non_passive_points(ix.make_spectrum(f, z2, sigma=sigma)).any()


def test_undetermined_parameters_of_a_superfluous_arc():
    circuit, formula, params, frange = he.ADEQUATE["rc"]
    f, z = he.spectrum(formula, params, frange, 0.01, np.random.default_rng(2))
    right = ix.fit(circuit, ix.make_spectrum(f, z))
    assert undetermined_parameters(right) == frozenset()
    # a second arc where there is none: its R and C (or their correlation) are not determined
    over = ix.fit("R0 + R1 || C1 + R2 || C2", ix.make_spectrum(f, z), init={"R2": 1.0, "C2": 1e-3})
    assert undetermined_parameters(over) & {"R2", "C2", "R1", "C1"}


def test_a_resistor_a_candidate_adds_that_runs_open_is_undetermined_whatever_its_error():
    """A parallel R far above every |Z| of the data carries no current the data can see: a
    candidate that adds one is not determined by the data even with a tiny relative error (a
    flat linearisation gave PowerSuite's real spectrum R_relax = 1.2e275 ± 9e10 Ω). A baseline
    resistor running open is not the candidate's (refine takes such a fit at its bound)."""
    import dataclasses

    from impedax.fitting.diagnosis.diagnosis import _opened

    circuit, formula, params, frange = he.ADEQUATE["rc"]
    f, z = he.spectrum(formula, params, frange, 0.01, np.random.default_rng(2))
    data = ix.make_spectrum(f, z)
    base = ix.fit(circuit, data)
    candidate = ix.fit(circuit + " + R2 || C2", data, init={"R2": 1.0, "C2": 1e-3})
    z_max = float(np.max(np.abs(z)))

    def opened(values):
        return _opened(dataclasses.replace(candidate, values={**candidate.values, **values}, stderr={**candidate.stderr, "R2": 1e-3 * z_max}), base)

    assert opened({"R2": 1e3 * z_max}) == {"R2"}
    assert opened({"R2": 10 * z_max}) == frozenset()
    assert opened({"R2": 10 * z_max, "R1": 1e3 * z_max}) == frozenset()  # R1 is the baseline's


def test_a_cpe_far_from_one_radian_per_second_is_determined():
    # R + CPE measured at 10 kHz–10 MHz (ln ω ≈ 11–18): Q is the admittance at ω = 1 rad/s,
    # decades outside the band, so ln Q and α are almost collinear in the raw parameters
    rng = np.random.default_rng(5)
    f = np.geomspace(1e4, 1e7, 50)
    jw = 2j * np.pi * f
    z = 50.0 + 1.0 / (2e-7 * jw**0.8)
    z = z + 0.01 * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    fit = ix.fit("R0 + CPE1", ix.make_spectrum(f, z))
    names = list(fit.free_names)
    iq, ia = names.index("CPE1.Q"), names.index("CPE1.alpha")
    rho = fit.correlation[iq, ia]
    assert abs(rho) > 0.99  # the raw rule would call the CPE undetermined
    assert undetermined_parameters(fit) == frozenset()
    # closed form: at the decorrelating frequency the error of ln(Q ω_c^α) is the conditional
    # one, sd(ln Q) √(1 − ρ²), when that frequency lies inside the band
    rel_sd, corr = centred_covariance(fit)
    sd_log_q = fit.stderr["CPE1.Q"] / fit.values["CPE1.Q"]
    assert rel_sd[iq] == pytest.approx(sd_log_q * np.sqrt(1 - rho**2), rel=1e-6)
    assert abs(corr[iq, ia]) < 1e-8
    omega_c = np.exp(-fit.covariance[iq, ia] / fit.values["CPE1.Q"] / fit.covariance[ia, ia])
    assert 2 * np.pi * f[0] < omega_c < 2 * np.pi * f[-1]
    # the other parameters are untouched: R0's error against its value, α's against its range (0, 1]
    ir = names.index("R0")
    assert rel_sd[ir] == pytest.approx(fit.stderr["R0"] / fit.values["R0"])
    assert rel_sd[ia] == pytest.approx(fit.stderr["CPE1.alpha"] / 1.0)


def test_candidates_carry_their_undetermined_parameters_and_warnings():
    circuit, effect, formula, params, frange = he.CASES["extra_relaxation/r_rc"]
    f, z = he.spectrum(formula, params, frange, 0.01, np.random.default_rng(3))
    d = ix.diagnose(ix.make_spectrum(f, z), circuit)
    assert d.suggestions and d.suggestions[0].effect == effect
    for s in d.candidates:
        assert s.significant <= (s.warning is None and not s.undetermined)
    # every candidate with a warning ranks after every one without
    flags = [s.warning is not None for s in d.candidates]
    assert flags == sorted(flags)
    out = d.summary()
    assert all("undetermined" in c and "warning" in c for c in out["candidates"])
    assert "undetermined" in out["suggestions"][0]


@pytest.mark.parametrize(
    "effect,added,value,plausible",
    [("stray_capacitance", "C_stray", 20e-12, True), ("stray_capacitance", "C_stray", 84e-6, False), ("series_inductance", "L_lead", 1e-6, True), ("series_inductance", "L_lead", 2e-3, False)],
)
def test_plausibility_of_fitted_values(effect, added, value, plausible):
    p = Proposal(effect, ix.parse(f"R0 + {added}"), added, "", ())
    warning = DEFAULT_EFFECTS[effect].plausible({added: value}, p)
    assert (warning is None) == plausible
    if not plausible:
        assert added in warning and "not" in warning


@pytest.mark.parametrize("tau,band_top,plausible", [(1e-6, 1e5, False), (10e-6, 1e5, True), (1e-6, 1e6, True), (5.0, 1e5, True)])
def test_a_finite_warburg_is_diffusion_only_where_the_band_reaches_its_45_degree_region(tau, band_top, plausible):
    # its phase is within 1° of 45° from ωτ = 5 on (closed form: tanh(√(jx))/√(jx) at x = 5
    # has phase −45.1°, at x = 1 −18°); below, the data see an arc's start, not diffusion
    x = 5.0
    phase = np.degrees(np.angle(np.tanh(np.sqrt(1j * x)) / np.sqrt(1j * x)))
    assert abs(phase + 45) < 1
    p = Proposal("diffusion", ix.parse("R0 + R1 || C1 + Ws_d"), "Ws_d", "", (), band=(0.1, band_top))
    warning = DEFAULT_EFFECTS["diffusion"].plausible({"Ws_d.R": 300.0, "Ws_d.tau": tau}, p)
    assert (warning is None) == plausible, warning
    omega_tau_at_top = 2 * np.pi * band_top * tau
    assert (omega_tau_at_top >= x) == plausible


def test_an_arc_above_the_band_is_not_named_diffusion():
    # R0 + R1 ∥ C1 + R2 ∥ C2 with τ₂ ≈ 0.6 µs above a 100 kHz band (the evaluation set's
    # extra_relaxation/edge template, SYNTHETIC dev draw 17, a seed no split uses): a Ws_d with
    # τ = 1.6 µs fitted 5 in AIC better than R ∥ C and was named first, though its diffusion
    # region lies above the band; it is now not proposed
    t = next(t for t in es.TEMPLATES if t.name == "extra_relaxation/edge")
    case = es.make_case(t, t.variants[0], "dev", 17)
    d = ix.diagnose(ix.make_spectrum(case.frequency, case.z), case.circuit)
    assert d.suggestions[0].effect == "extra_relaxation", d.report()
    finite = [c for c in d.candidates if c.effect == "diffusion" and c.added.startswith(("Ws", "Wo")) and c.fit.values[f"{c.added}.tau"] * 2 * np.pi * 1e5 < 5]
    # (a candidate whose parameters are undetermined carries that warning instead)
    assert finite and all(c.warning and not c.significant for c in finite)
    assert any("diffusion region" in c.warning for c in finite)


@pytest.mark.slow  # (10-15 s; the suite's budget, 2026-11-30)
def test_a_finite_warburg_within_the_aic_margin_of_an_arc_comes_after_it():
    # a 9-element ladder missing a fast R ∥ C (the evaluation set's extra_relaxation/ladder9,
    # SYNTHETIC dev draw 11, a seed no split uses; 1 % noise): a Ws_d nested in the fast arc
    # fitted 4 in AIC better than R ∥ C with as many parameters and was named first. Within
    # DELTA_AIC_MIN the data do not show its 45° region decisively: the arc goes first
    t = next(t for t in es.TEMPLATES if t.name == "extra_relaxation/ladder9")
    case = es.make_case(t, t.variants[0], "dev", 11)
    d = ix.diagnose(ix.make_spectrum(case.frequency, case.z), case.circuit)
    first = d.suggestions[0]
    assert first.effect == "extra_relaxation", d.report()
    finite = [c for c in d.suggestions if c.effect == "diffusion" and c.added.startswith(("Ws", "Wo"))]
    assert finite and finite[0].fit.n_params == first.fit.n_params
    assert finite[0].delta_aic < first.delta_aic < finite[0].delta_aic + 10  # better by AIC, within the margin
    assert d.suggestions.index(finite[0]) > 0


@pytest.mark.parametrize("value,unit,text", [(84e-6, "F", "84 µF"), (2200.0, "ohm", "2.2 kΩ"), (0.81, "1", "0.81"), (1.5e-6, "H", "1.5 µH"),
                                              (5e14, "Ohm", "500 TΩ"), (1.19e282, "Ohm", "1.19e+282 Ω")])  # (beyond T: plain, not 1.19e+270 TΩ)
def test_values_are_given_with_si_prefixes(value, unit, text):
    assert format_quantity(value, unit) == text


def test_explanation_speaks_of_the_circuit_and_its_fitted_values():
    circuit, effect, formula, params, frange = he.CASES["constant_phase/r_rc"]
    f, z = he.spectrum(formula, params, frange, 0.01, np.random.default_rng(4))
    d = ix.diagnose(ix.make_spectrum(f, z), circuit)
    best = d.suggestions[0]
    assert best.effect == effect
    text = best.explanation.lower()
    assert "skin" not in text and "meyer" not in text
    assert "cpe1.alpha =" in text and "%" in text


def _step_and_outlier_spectra():
    """A sweep whose sample changes half-way (a step of 15 % in R1) and the same arc with three
    isolated erratic points (SYNTHETIC, numpy formulas)."""
    rng = np.random.default_rng(9)
    f = he.frequencies(0.1, 1e5)
    r1 = np.where(np.arange(f.size) < 30, 2000.0, 2300.0)  # swept from low f: the sample changes at point 30
    z_step = 50 + r1 / (1 + 2j * np.pi * f * r1 * 1e-6)
    z_step = z_step + 0.005 * np.abs(z_step) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    z_out = 50 + 2000 / (1 + 2j * np.pi * f * 2000 * 1e-6)
    z_out = z_out + 0.005 * np.abs(z_out) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    z_out[[12, 31, 47]] *= np.array([1.2, 0.85 - 0.1j, 1.1 + 0.2j])
    return f, z_step, z_out


def test_erratic_points_are_located_exactly_but_a_step_change_is_not_called_erratic():
    from impedax.fitting.diagnosis.noise import OUTLIER_MAX_FRACTION, kk_outliers

    f, z_step, z_out = _step_and_outlier_spectra()
    s_out = ix.make_spectrum(f, z_out)
    kk = ix.kk_test(s_out)
    assert not kk.valid
    mask, kept = kk_outliers(s_out, kk, max_fraction=OUTLIER_MAX_FRACTION)
    assert list(np.nonzero(mask)[0]) == [12, 31, 47] and kept.valid
    s_step = ix.make_spectrum(f, z_step)
    kk_step = ix.kk_test(s_step)
    assert not kk_step.valid
    assert kk_outliers(s_step, kk_step, max_fraction=OUTLIER_MAX_FRACTION) is None


def test_a_candidate_that_contains_another_reaches_at_least_its_fit():
    # a fingertip whose air gap leaks (R_EP ∥ CPE_EP ∥ C_gap) diagnosed without the leak: the
    # full electrode-polarization candidate contains R_EP ∥ C_gap, so at its optimum it fits at
    # least as well; started from its own guesses alone it stalled with the leak switched off
    # (R_EP → ∞), at the baseline's misfit, and a series arc was named instead
    rng = np.random.default_rng(11)
    f = np.geomspace(1.0, 1e6, 60)
    jw = 2j * np.pi * f
    skin = 3e5 / (1 + 3e5 * 2e-9 * jw**0.7)
    gap = 1 / (1 / 2e7 + 2e-9 * jw**0.3 + jw * 4e-10)
    z = 2e3 + skin + gap
    z = z + 0.01 * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)
    d = ix.diagnose(ix.make_spectrum(f, z), "R_f + R_sk || CPE_sk + C_gap")
    ep = {s.model: s.fit for s in d.candidates if s.effect == "electrode_polarization"}
    full = ep["R_f + R_sk || CPE_sk + R_EP || CPE_EP || C_gap"]
    assert full.chi2 <= ep["R_f + R_sk || CPE_sk + R_EP || C_gap"].chi2
    assert full.rms_rel < 0.02  # at the noise (1 %), not the baseline's tens of per cent
    assert d.suggestions[0].effect == "electrode_polarization", d.report()


@pytest.mark.slow  # (10-15 s; the suite's budget, 2026-11-30)
def test_each_effects_best_candidate_reaches_what_fit_of_its_model_reaches():
    # two R ∥ CPE arcs and a finite-length (transmissive) Warburg at the end, written here:
    # Ws = R tanh(√(jωτ))/√(jωτ), 1 % noise, diagnosed without the Warburg. The baseline bends
    # its arcs around the missing tail; from a few warm starts the Ws candidate stalled at
    # 3.9 % where `impedax fit` of its model string reaches 1.3 %, and a nested R ∥ CPE (1.5 %)
    # was named instead. The best candidate of each effect that stays poor is fitted again
    # from 32 starts (the starts `fit` climbs to)
    rng = np.random.default_rng(1009)
    f = np.logspace(-3, 6, 60)
    jw = 2j * np.pi * f
    x = np.sqrt(jw * 10.0)
    z = 10.0 + 400.0 / (1 + 400.0 * 1e-7 * jw**0.9) + 1e3 / (1 + 1e3 * 1e-5 * jw**0.8) + 800.0 * np.tanh(x) / x
    z = z + 0.01 * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)
    data = ix.make_spectrum(f, z)
    d = ix.diagnose(data, "R0 + R1 || CPE1 + R2 || CPE2")
    assert d.suggestions[0].effect == "diffusion" and "Ws_d" in d.suggestions[0].model, d.report()
    leader = d.suggestions[0]
    again = ix.fit(leader.model, data)
    assert leader.rms_rel <= again.rms_rel * 1.01
    assert leader.fit.values["Ws_d.R"] == pytest.approx(800.0, rel=0.1)


def _draw(template_name: str, index: int, variant: int = 0):
    """A SYNTHETIC spectrum of an evaluation-set template (numpy formula) outside its dev and
    held-out cases (dev seeds, draw ``index`` ≥ 10: parameters varied by 15 %), with the
    template's noise variant ``variant``."""
    template = next(t for t in es.TEMPLATES if t.name == template_name)
    case = es.make_case(template, template.variants[variant], "dev", index)
    return case, ix.make_spectrum(case.frequency, case.z)


def test_an_effects_best_candidate_left_undetermined_by_a_stalled_start_is_refitted():
    # a finger whose gap leaks through R_EP ∥ CPE_EP (α ≈ 0.3), diagnosed without it: the
    # baseline put the leak into R_sk, and from its warm starts the electrode-polarization
    # candidate stopped at 1.75 % with CPE_EP undetermined (so not proposed) where `impedax
    # fit` of its model string reaches 1.41 % with every parameter determined; a series
    # R ∥ CPE was named instead
    case, data = _draw("electrode_polarization/finger", 12)
    d = ix.diagnose(data, case.circuit)
    best = d.suggestions[0]
    assert best.effect == "electrode_polarization", d.report()
    assert not best.undetermined
    assert best.rms_rel <= ix.fit(best.model, data).rms_rel * 1.01


def test_a_candidate_that_contains_the_baseline_and_fits_worse_is_refitted():
    # a stray capacitance across a finger circuit: its candidate stopped at 1.78 %, behind the
    # baseline's 1.71 % (C_stray → 0 gives the baseline's fit), where 1.44 % is reachable; a
    # Warburg behind R_sk was named instead
    case, data = _draw("stray_capacitance/finger", 20)
    d = ix.diagnose(data, case.circuit)
    stray = [s for s in d.candidates if s.effect == "stray_capacitance"]
    assert min(s.fit.chi2 for s in stray) <= d.baseline.chi2
    assert d.suggestions[0].effect == "stray_capacitance", d.report()


def two_arcs_without_series_resistance(seed, rel_noise=0.005):
    """R1 ∥ CPE1 + R2 ∥ CPE2, no series resistance, measured up to 200 kHz: the small fast arc
    (τ ≈ 0.4 µs) is still rising at the top of the band, so the data never reach a plateau of
    Re Z (as test_data.txt of AutoEIS). Written here, complex Gaussian noise."""
    rng = np.random.default_rng(seed)
    f = np.geomspace(0.05, 2e5, 50)
    jw = 2j * np.pi * f
    z = 2e6 / (1 + 2e6 * 2e-6 * jw**0.95) + 150.0 / (1 + 150.0 * 4e-9 * jw**0.93)
    return ix.make_spectrum(f, z + rel_noise * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2))


def test_a_series_resistance_that_falls_to_zero_is_dropped_from_the_suggestion():
    # with R0 kept, the missing arc's candidate fits to the noise but R0 → 0 is undetermined,
    # so before nothing was proposed and R ∥ CPE (several % off) was called adequate
    d = ix.diagnose(two_arcs_without_series_resistance(5), "R0 + R1 || CPE1")
    assert d.verdict == "missing_effect", d.report()
    best = d.suggestions[0]
    assert "R0" not in best.fit.values and best.undetermined == () and best.warning is None, d.report()
    assert "R0 left out" in best.explanation
    assert best.rms_rel < 0.01 < d.baseline.rms_rel
    arcs = sorted(v for k, v in best.fit.values.items() if k.startswith("R"))
    assert arcs[0] == pytest.approx(150.0, rel=0.15) and arcs[1] == pytest.approx(2e6, rel=0.15)
    assert not undetermined_parameters(ix.fit(best.model, ix.make_spectrum(best.fit.frequency, best.fit.z_data)))


def test_a_series_resistance_the_data_resolve_is_kept():
    # the same arcs measured to 20 MHz with 100 Ω in series: the plateau is reached, R0 is
    # determined, and no suggestion leaves it out
    rng = np.random.default_rng(6)
    f = np.geomspace(0.05, 2e7, 60)
    jw = 2j * np.pi * f
    z = 100.0 + 2e6 / (1 + 2e6 * 2e-6 * jw**0.95) + 150.0 / (1 + 150.0 * 4e-9 * jw**0.93)
    z = z + 0.005 * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)
    d = ix.diagnose(ix.make_spectrum(f, z), "R0 + R1 || CPE1")
    assert d.suggestions and all("R0" in s.fit.values for s in d.candidates), d.report()
    assert d.suggestions[0].fit.values["R0"] == pytest.approx(100.0, rel=0.2)


def meyer_with_series_resistance_and_cpe(seed, rel_noise=0.005):
    """C_i + R_f + R_sc ∥ CPE_sc on 10 Hz–1 MHz (the evaluation set's two/meyer_rs_cpe shape:
    1 nF, 20 kΩ, 1 MΩ ∥ Q = 5 nF·s^(α−1), α = 0.72), by its own numpy formula."""
    rng = np.random.default_rng(seed)
    f = np.geomspace(10.0, 1e6, 60)
    jw = 2j * np.pi * f
    z = 1 / (jw * 1e-9) + 2e4 + 1e6 / (1 + 1e6 * 5e-9 * jw**0.72)
    return ix.make_spectrum(f, z + rel_noise * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2))


@pytest.mark.slow  # (55 s: the default suite keeps under 15 minutes on 2 cores)
def test_a_capacitor_that_carries_no_current_is_dropped_from_the_suggestion():
    # C_i + R_sc ∥ C_sc fits with C_sc → 0 (R_sc stands for R_f); R_relax ∥ CPE_relax added
    # then fits to the noise with C_sc undetermined: before, it was never proposed (on one dev
    # draw of the evaluation set the next step ended adequate at 22× the noise)
    data = meyer_with_series_resistance_and_cpe(2)
    d = ix.diagnose(data, "C_i + R_sc || C_sc")
    at = next(i for i, s in enumerate(d.suggestions) if s.removed)
    leaving = d.suggestions[at]
    assert leaving.removed == ("C_sc",) and leaving.undetermined == () and leaving.warning is None, d.report()
    assert "C_sc left out" in leaving.explanation and "plain resistance" in leaving.explanation
    assert leaving.rms_rel < 0.01 < 0.3 < d.baseline.rms_rel
    values = leaving.fit.values
    assert values["R_sc"] == pytest.approx(2e4, rel=0.1)  # the series resistance
    assert values["R_relax"] == pytest.approx(1e6, rel=0.3)  # the arc
    assert not undetermined_parameters(ix.fit(leaving.model, data))
    # it fits best, but the significant suggestions that keep every element go first (_rank) ...
    assert at > 0 and all(s.removed == () and s.delta_aic > leaving.delta_aic for s in d.suggestions[:at])
    # ... and refine's paths from them reach the generating structure
    r = ix.refine(data, "C_i + R_sc || C_sc")
    assert ix.parse(r.final_model) == ix.parse("C_i + R_sc || CPE_sc + R_s") and r.verdict == "adequate", r.report()
    assert r.final.rms_rel < 0.01 and r.final.values["CPE_sc.alpha"] == pytest.approx(0.72, abs=0.03)


def test_a_capacitor_the_data_resolve_is_kept():
    # the series resistance and the CPE are there: every R ∥ C of the candidates carries
    # current, nothing is left out
    d = ix.diagnose(meyer_with_series_resistance_and_cpe(7), "C_i + R_f + R_sc || CPE_sc")
    assert d.verdict == "adequate", d.report()
    assert all(c.removed == () for c in d.candidates)


def test_a_warm_started_candidate_reaches_at_least_what_fit_reaches_from_the_data():
    # a lithium-ion cell's shape (R0 + two R ∥ CPE + a Warburg, milliohms; the evaluation set's
    # dev case diffusion/battery#0, numpy formulas of tests/evaluation_set.py) diagnosed
    # without the Warburg: the baseline bends its second arc into a capacitor (α → 1) and the
    # Warburg candidate, warm-started from it, stayed at 2.6 % where `impedax fit` of its model
    # string reaches 1.3 % from the data-driven start alone; an extra R ∥ C was named instead.
    # Every warm-started candidate now also starts from that data-driven guess
    case = next(c for c in es.cases("dev") if c.name == "diffusion/battery#0")
    data = ix.make_spectrum(case.frequency, case.z)
    d = ix.diagnose(data, case.circuit)
    warburg = next(s for s in d.candidates if s.model == "R0 + R1 || CPE1 + R2 || CPE2 + W_d")
    alone = ix.fit(warburg.model, data, n_starts=1)
    assert warburg.rms_rel <= alone.rms_rel * 1.01
    assert d.suggestions[0].model == warburg.model, d.report()


def test_the_ranking_weighs_each_point_by_the_noise_there():
    # a Randles cell with a Warburg, noise growing toward low frequency (the evaluation set's
    # dev case diffusion/randles#2, numpy formulas of tests/evaluation_set.py), diagnosed
    # without the Warburg: with ΔAIC over the fits' own (modulus-weighted) residuals the noisy
    # low decade decided and a nested R ∥ CPE ranked first; over residuals divided by the
    # noise model's σ_k the Warburg does
    case = next(c for c in es.cases("dev") if c.name == "diffusion/randles#2")
    d = ix.diagnose(ix.make_spectrum(case.frequency, case.z), case.circuit)
    assert d.suggestions[0].effect == "diffusion", d.report()
    # the ΔAIC reported is over the noise-weighted residuals, written out here
    best = d.suggestions[0]

    def aic(fit):
        r = fit.residuals / d.noise
        n = 2 * r.size
        return n * np.log(np.sum(r.real**2 + r.imag**2) / n) + 2 * fit.n_params

    assert best.delta_aic == pytest.approx(aic(best.fit) - aic(d.baseline), rel=1e-9)


@pytest.mark.slow  # (12 s; the suite's budget)
def test_a_correlated_pair_each_determined_on_its_own_does_not_block_a_candidate():
    # a lead inductance missing from an 8-element ladder (0.3 % noise growing toward low
    # frequency): with L added the fit falls from 1.87 % to 0.47 %, every parameter within
    # 6 %, but R1 and R3 (arcs of nearby time constants trade resistance) correlate at −0.993.
    # The correlation rule alone called them undetermined and the diagnosis ended `adequate`
    case, data = _draw("series_inductance/ladder8", 31, variant=1)
    d = ix.diagnose(data, case.circuit)
    assert d.verdict == "missing_effect", d.report()
    best = d.suggestions[0]
    assert best.effect == "series_inductance" and not best.undetermined, d.report()
    names = list(best.fit.free_names)
    rel_sd, corr = centred_covariance(best.fit)
    i, j = names.index("R1"), names.index("R3")
    assert abs(corr[i, j]) > CORRELATION_MAX  # the pair the raw rule rejected ...
    assert max(rel_sd[i], rel_sd[j]) <= CORRELATED_ERROR_MAX  # ... each known to 10 % on its own


def test_in_a_correlated_pair_only_the_poorly_known_member_is_undetermined():
    # an arc whose top lies above the band (τ = 0.6 µs over 0.1 Hz–100 kHz): R0 and the arc's R
    # trade at |correlation| > 0.99, R0 known to ~50 %, the arc's R to ~2 % (its marginal error
    # already pays for the trade). Only R0 is undetermined
    from impedax.fitting.diagnosis.diagnosis import CORRELATION_SINGULAR

    case, data = _draw("extra_relaxation/edge", 14)
    fit = ix.fit("R0 + R1 || C1 + R2 || C2", data, n_starts=8)
    names = list(fit.free_names)
    rel_sd, corr = centred_covariance(fit)
    r0 = names.index("R0")
    partner = int(np.argmax(np.where(np.arange(len(names)) == r0, 0, np.abs(corr[r0]))))
    assert CORRELATION_MAX < abs(corr[r0, partner]) <= CORRELATION_SINGULAR
    assert rel_sd[r0] > CORRELATED_ERROR_MAX >= rel_sd[partner]
    assert undetermined_parameters(fit) == {"R0"}


def test_an_exponent_is_known_by_its_error_against_its_range():
    # electrode polarization across a bare gap, R_EP ∥ CPE_EP ∥ C_gap with α_EP ≈ 0.25
    # (the evaluation set's electrode_polarization/gap, weak, 0.3 % noise growing toward low
    # frequency; SYNTHETIC dev2 draw 1). α is fitted to ± 0.05, a twentieth of its range (0, 1],
    # but to more than 10 % of its small value while correlated above 0.99 with R_EP: judged
    # against its value it was undetermined, the generating circuit was not proposed and a
    # series arc was named
    t = next(t for t in es.TEMPLATES if t.name == "electrode_polarization/gap")
    case = es.make_case(t, t.variants[1], "dev2", 1)
    data = ix.make_spectrum(case.frequency, case.z)
    fit = ix.fit("R_EP || CPE_EP || C_gap", data)
    alpha, error = fit.values["CPE_EP.alpha"], fit.stderr["CPE_EP.alpha"]
    names = list(fit.free_names)
    corr = np.asarray(fit.correlation)[names.index("CPE_EP.alpha")]
    assert error / alpha > CORRELATED_ERROR_MAX and np.max(np.abs(np.delete(corr, names.index("CPE_EP.alpha")))) > CORRELATION_MAX
    assert error < 0.1  # (the range of α is 1)
    assert "CPE_EP.alpha" not in undetermined_parameters(fit)
    d = ix.diagnose(data, case.circuit)
    assert d.suggestions[0].effect == "electrode_polarization" and "CPE_EP" in d.suggestions[0].model, d.report()


def test_a_series_resistance_traded_against_an_arc_above_the_band_is_left_out():
    # the same arc above the band, the user's R0 + R1 ∥ C1: every candidate with the arc leaves
    # R0 undetermined (25 ± 8 Ω traded against R_relax, not fallen to zero); without R0 the arc
    # fits within 4 % in rms_rel and every parameter is determined. Only candidates whose R0
    # fell to zero were tried without it, and a Warburg was named
    case, data = _draw("extra_relaxation/edge", 14)
    d = ix.diagnose(data, case.circuit)
    best = d.suggestions[0]
    assert best.effect == "extra_relaxation" and best.removed == ("R0",) and not best.undetermined, d.report()
    assert "R0 left out" in best.where and "traded against" in best.where
    full = ix.fit("R0 + R1 || C1 + R2 || C2", data, n_starts=8)
    assert best.rms_rel <= 1.05 * full.rms_rel


def test_a_series_resistance_that_fell_to_zero_does_not_send_its_suggestion_down_the_list():
    # two R ∥ CPE arcs and no series resistance (SYNTHETIC, written here, 0.5 % noise) diagnosed
    # with R0 + R1 ∥ CPE1: the second arc fits to the noise with R0 at zero. Its suggestion
    # without R0 ranked after every significant candidate that keeps R0 (an arc of 2 % in
    # series was named first), as though leaving R0 out changed what R1 stands for; R0 at 0
    # is the same fit, so it ranks by AIC. A series resistance traded against the other
    # resistances (not at zero) still changes them and still ranks after
    rng = np.random.default_rng(5)
    f = np.geomspace(0.01, 1e5, 60)
    jw = 2j * np.pi * f
    z = 4000 / (1 + 4000 * 3e-9 * jw**0.87) + 15000 / (1 + 15000 * 2e-4 * jw**0.7)
    z = z + 0.005 * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)
    d = ix.diagnose(ix.make_spectrum(f, z), "R0 + R1 || CPE1")
    best = d.suggestions[0]
    assert best.removed == best.vanished == ("R0",) and "it fell to" in best.where, d.report()
    assert best.delta_aic == min(s.delta_aic for s in d.suggestions), d.report()
    assert best.rms_rel < 0.01, d.report()  # (at the noise: two arcs, as the data were made)
    traded = [s for s in d.suggestions if s.removed and not s.vanished]
    kept = [i for i, s in enumerate(d.suggestions) if not s.removed and s.significant]
    assert traded and kept and all(d.suggestions.index(s) > kept[0] for s in traded), d.report()


def test_noise_growing_toward_low_frequency_is_not_masked_as_the_datas_problem():
    # a battery whose Warburg tail shows in the lowest decades, 0.3 % noise growing ×6 toward
    # low frequency: the KK test's one global scale flags 14 of its 60 points, most at the
    # noisy end. Masked, they took the points that tell a Warburg from one more arc. Judged
    # against the local noise they are data. Since 2026-12-02 the test leaves its lone spikes out
    # of the Voigt chain's fit (docs/kk.md, "The validity rule", 5): it flags 4, and the one at
    # 25.5 mHz (7.5 s in the fit that followed it, 9.5 s in the one without it; its neighbours
    # 1.6 s and 0.8 s) stays masked against the local noise too
    case, data = _draw("diffusion/battery", 20, variant=1)
    assert int(ix.kk_test(data).flagged.sum()) >= 4
    d = ix.diagnose(data, case.circuit)
    assert len(d.masked_points) <= 1 and d.baseline.n_points >= data.sizes["frequency"] - 1
    assert any("within the noise where they are" in note for note in d.notes)
    assert d.suggestions[0].effect == "diffusion", d.report()


def _real_test_data():
    from pathlib import Path

    return ix.load(Path(__file__).parent / "fixtures" / "real" / "test_data.txt"), "R0 + R1 || CPE1"


def _battery_with_noise_growing_toward_low_frequency():
    case, data = _draw("diffusion/battery", 20, variant=1)
    return data, case.circuit


@pytest.mark.parametrize("spectrum", [
    pytest.param(_real_test_data, id="test_data.txt", marks=pytest.mark.slow),  # (17-20 s, the suite's budget)
    pytest.param(_battery_with_noise_growing_toward_low_frequency, id="battery", marks=pytest.mark.slow),  # (its later steps had the right noise before too)
])
def test_every_step_of_a_refinement_is_judged_against_the_first_steps_noise(spectrum):
    # refine passed its later steps the KK test after the first step's local judgement, whose
    # fewer flags let the points it cleared raise the discrepancy floor: on AutoEIS's real
    # test_data.txt the first step had σ ≈ 0.1 % (δ 0.074 %), every later one 0.34 % (δ 0.33 %),
    # and the last model of 14 parameters sat at 0.14× that noise. Every step is one model
    # against the same points, so every step has the first step's noise model
    data, circuit = spectrum()
    r = ix.refine(data, circuit, max_effects=1)
    first = r.steps[0].diagnosis
    assert int(ix.kk_test(data).flagged.sum()) > 0 and any("within the noise where they are" in n for n in first.notes)
    for step in r.steps[1:]:
        d = step.diagnosis
        assert np.array_equal(d.baseline.frequency, first.baseline.frequency)
        assert d.discrepancy == pytest.approx(first.discrepancy, rel=1e-9, abs=1e-12), (d.discrepancy, first.discrepancy)
        np.testing.assert_allclose(d.noise, first.noise, rtol=1e-9)
        assert d.noise_source == first.noise_source
    limited = [n for n in r.notes if n.startswith("refine stopped at its limit of 1 added effect")]
    assert len(limited) == (1 if r.verdict == "missing_effect" else 0), (r.verdict, r.notes)


def test_a_drift_hidden_by_a_few_left_out_points_is_not_called_erratic():
    # R2 of two arcs drifts by 50 % along the sweep (SYNTHETIC dev draw outside the splits):
    # leaving out six scattered points made the KK test pass, so they were masked as erratic
    # and a missing effect was sought in the rest. They stood at 1.8–2.6× the scatter of the
    # points kept; the erratic points of the evaluation set stand at 5–12×
    from impedax.fitting.diagnosis.noise import OUTLIER_MAX_FRACTION, kk_outliers

    case, data = _draw("invalid/drift_two_arcs", 20)
    kk = ix.kk_test(data)
    assert not kk.valid
    assert kk_outliers(data, kk, max_fraction=OUTLIER_MAX_FRACTION) is None
    assert ix.diagnose(data, case.circuit).verdict == "data_invalid"
    case, data = _draw("outliers/extra_relaxation", 20)  # three erratic points: still located
    mask, kept = kk_outliers(data, ix.kk_test(data), max_fraction=OUTLIER_MAX_FRACTION)
    assert int(mask.sum()) == 3 and kept.valid


def test_a_leak_resistor_that_runs_open_is_left_out_of_the_candidate():
    # a finger whose gap leaks through a nearly resistive CPE (3 % noise growing toward low
    # frequency, SYNTHETIC dev draw outside the splits): R_EP ∥ CPE_EP ∥ C_gap fits best with
    # R_EP → 89 GΩ, which left R_EP and CPE_EP undetermined, and a series arc was named. (Draw
    # 22 showed it while the KK test's global noise scale masked its noisiest points; judged
    # against the local noise they count, and its R_EP is finite.)
    from impedax.fitting.diagnosis.diagnosis import OPEN_RESISTANCE_FACTOR

    case, data = _draw("electrode_polarization/finger", 41, variant=2)
    d = ix.diagnose(data, case.circuit)
    best = d.suggestions[0]
    assert best.effect == "electrode_polarization" and not best.undetermined, d.report()
    assert "R_EP" not in best.fit.values and "CPE_EP.alpha" in best.fit.values
    assert "R_EP left out" in best.where and best.removed == ()
    full = next(s for s in d.candidates if s.model == "R_f + R_sk || CPE_sk + R_EP || CPE_EP || C_gap")
    assert full.fit.values["R_EP"] > OPEN_RESISTANCE_FACTOR * np.max(np.abs(data["Z"].values)) and full.undetermined
    assert best.rms_rel <= full.rms_rel * 1.001  # the same fit, one parameter fewer


def _battery_with_series_capacitor(capacitance_f, warburg_sigma=0.02, seed=2):
    """SYNTHETIC battery-like spectrum, 10 mHz–10 kHz, 0.5 % complex Gaussian noise (numpy, no
    impedax): 20 mΩ + 50 mΩ ∥ CPE (Q = 1, α = 0.85) + a Warburg σ(1 − j)/√ω, and, when
    ``capacitance_f`` is given, a capacitor 1/(jωC) in series (an intercalation capacitance;
    None: no capacitor; ``warburg_sigma`` None: no Warburg)."""
    f = np.logspace(-2, 4, 60)
    w = 2 * np.pi * f
    z = 0.02 + 0.05 / (1 + 0.05 * 1.0 * (1j * w) ** 0.85)
    if warburg_sigma is not None:
        z = z + warburg_sigma * (1 - 1j) / np.sqrt(w)
    if capacitance_f is not None:
        z = z + 1 / (1j * w * capacitance_f)
    rng = np.random.default_rng(seed)
    return ix.make_spectrum(f, z + 0.005 * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))


def test_an_open_resistor_beside_a_series_capacitor_is_left_out_where_the_circuit_blocks_dc():
    # a 100 F capacitor missing from R0 + R1 || CPE1 + W1 (SYNTHETIC): R_relax ∥ C_relax at the
    # end fits with R_relax → 12 MΩ, undetermined, so it was not proposed and a finite Warburg
    # (4.4 %) was named; C_relax alone in series is the generating circuit (as on AutoEIS's
    # battery cycle 22, REAL: 1.9 % → 0.875 %, C_relax = 15.2 F). Seeds 1 and 3 give the same
    # suggestion (R_relax at 31 Ω and 50 Ω there, just over 100× the largest |Z| of 0.28 Ω).
    from impedax.fitting.diagnosis.diagnosis import OPEN_RESISTANCE_FACTOR

    data = _battery_with_series_capacitor(100.0)
    d = ix.diagnose(data, "R0 + R1 || CPE1 + W1")
    best = d.suggestions[0]
    assert best.model == "R0 + R1 || CPE1 + W1 + C_relax" and not best.undetermined, d.report()
    assert best.fit.values["C_relax"] == pytest.approx(100.0, rel=0.05)  # (99.8 F; 0.5 % noise)
    assert best.rms_rel < 0.01  # the noise's rms is 0.5 % per component
    assert "R_relax left out: it ran open" in best.where and "already blocks DC (W1)" in best.where
    full = next(s for s in d.candidates if s.model == "R0 + R1 || CPE1 + W1 + R_relax || C_relax")
    assert full.fit.values["R_relax"] > OPEN_RESISTANCE_FACTOR * np.max(np.abs(data["Z"].values)) and full.undetermined
    assert best.rms_rel <= full.rms_rel * 1.001  # the same fit, one parameter fewer


@pytest.mark.slow  # (15-30 s; the suite's budget)
def test_nothing_missing_beside_a_warburg_is_still_adequate():
    # the same battery without the capacitor, diagnosed with its own circuit (SYNTHETIC)
    d = ix.diagnose(_battery_with_series_capacitor(None), "R0 + R1 || CPE1 + W1")
    assert d.verdict == "adequate" and d.suggestions == (), d.report()


@pytest.mark.slow  # (15-30 s; the suite's budget)
def test_an_open_resistor_beside_a_capacitor_is_left_out_where_the_circuit_conducts_too():
    # the capacitor missing from R0 + R1 || CPE1, which conducts at DC (SYNTHETIC, no Warburg):
    # R_relax ∥ C_relax runs open here too. Until 2026-12-04 no candidate left R_relax out (a
    # series C turns a conducting circuit into a blocking one) and R0 + CPE1 + Ws_d was named at
    # 5.1 %; the generating circuit, C_relax alone in series, fits to the noise, and its placement
    # says that the data show no DC path (a blocking capacitance, or an arc below the band)
    from impedax.fitting.diagnosis.diagnosis import OPEN_RESISTANCE_FACTOR

    data = _battery_with_series_capacitor(100.0, warburg_sigma=None)
    d = ix.diagnose(data, "R0 + R1 || CPE1")
    best = d.suggestions[0]
    assert best.model == "R0 + R1 || CPE1 + C_relax" and not best.undetermined, d.report()
    assert best.fit.values["C_relax"] == pytest.approx(100.0, rel=0.05)
    assert best.rms_rel < 0.01  # the noise's rms is 0.5 % per component
    assert "R_relax left out: it ran open" in best.where and "no DC path" in best.where
    full = next(s for s in d.candidates if s.model == "R0 + R1 || CPE1 + R_relax || C_relax")
    assert full.fit.values["R_relax"] > OPEN_RESISTANCE_FACTOR * np.max(np.abs(data["Z"].values)) and "R_relax" in full.undetermined


@pytest.mark.slow  # (15-30 s; the suite's budget)
def test_nothing_missing_from_a_conducting_circuit_is_still_adequate():
    # the same battery without capacitor and Warburg, diagnosed with its own circuit (SYNTHETIC)
    d = ix.diagnose(_battery_with_series_capacitor(None, warburg_sigma=None), "R0 + R1 || CPE1")
    assert d.verdict == "adequate" and d.suggestions == (), d.report()


def test_a_poor_leaders_rungs_get_the_steps_to_converge():
    # the same finger at 0.3 % noise: with the candidates' 100 steps in its rungs too, the
    # electrode-polarization candidate stopped unconverged at 0.93 % (0.45 % reachable,
    # `impedax fit`) and a series arc was named
    case, data = _draw("electrode_polarization/finger", 21, variant=1)
    d = ix.diagnose(data, case.circuit)
    best = d.suggestions[0]
    assert best.effect == "electrode_polarization" and best.fit.converged, d.report()
    assert best.rms_rel <= ix.fit(best.model, data).rms_rel * 1.01


def test_a_capacitance_across_the_finger_leaves_out_the_series_resistance_it_shunts():
    # a 20 pF stray capacitance across a finger circuit (R_f = 2 kΩ, 1.4 % noise; SYNTHETIC,
    # numpy formula of tests/evaluation_set.py), diagnosed without it: the baseline does not
    # determine R_f (its 2 kΩ beside the skin's ~9 kΩ at 1 MHz), and with C_stray across the
    # whole circuit R_f trades with C_stray (r = 0.998), so the candidate that keeps R_f was
    # undetermined and a Warburg in the skin branch was named. The candidate without R_f is
    # determined, fits as well, and leaving out an element the baseline did not determine does
    # not rank it behind those that keep every element
    case, data = _draw("stray_capacitance/finger", 40)
    d = ix.diagnose(data, case.circuit)
    assert "R_f" in {e.name for e in d.baseline.circuit.elements()}
    assert d.verdict == "missing_effect", d.report()
    best = d.suggestions[0]
    assert best.effect == "stray_capacitance" and not best.undetermined, d.report()
    assert ix.parse(best.model) == ix.parse("(R_sk || CPE_sk + R_EP || CPE_EP || C_gap) || C_stray") and best.removed == ("R_f",)
    assert 1e-11 < best.fit.values["C_stray"] < 4e-11  # generated: 20 pF, varied by 15 %
    kept = next(s for s in d.candidates if ix.parse(s.model) == ix.parse("(R_f + R_sk || CPE_sk + R_EP || CPE_EP || C_gap) || C_stray"))
    assert kept.undetermined and best.delta_aic <= kept.delta_aic + 1.0


def test_a_series_resistance_the_finger_baseline_determines_is_kept_under_a_stray_capacitance():
    # the same circuit with R_f determined by its baseline (SYNTHETIC, another draw): no
    # candidate leaves it out
    case, data = _draw("stray_capacitance/finger", 11, variant=1)
    d = ix.diagnose(data, case.circuit)
    assert "R_f" not in {n for n in d.baseline.free_names if not d.baseline.stderr[n] <= abs(d.baseline.values[n])}
    assert all("R_f" not in s.removed for s in d.candidates if s.effect == "stray_capacitance"), d.report()


def test_a_candidate_behind_a_refitted_leader_it_contains_is_restarted_from_it():
    # a finger whose gap leaks through R_EP ∥ CPE_EP (SYNTHETIC draw), diagnosed without it:
    # both electrode-polarization candidates first stopped at the baseline's 8.8 %; the leader
    # rung refitted R_EP ∥ C_gap to 3.9 %, but R_EP ∥ CPE_EP ∥ C_gap, which contains it, was
    # checked for such a stall only before the rungs, stayed at 8.8 %, and a series R ∥ CPE
    # (1.7 %) was named. Restarted from the refitted R_EP ∥ C_gap it reaches `impedax fit`'s
    # 1.2 %, every parameter determined
    case, data = _draw("electrode_polarization/finger", 50)
    d = ix.diagnose(data, case.circuit)
    best = d.suggestions[0]
    assert best.effect == "electrode_polarization" and not best.undetermined, d.report()
    assert ix.parse(best.model) == ix.parse("R_f + R_sk || CPE_sk + R_EP || CPE_EP || C_gap")
    assert best.rms_rel <= ix.fit(best.model, data).rms_rel * 1.01
    nested = next(s for s in d.candidates if ix.parse(s.model) == ix.parse("R_f + R_sk || CPE_sk + R_EP || C_gap"))
    assert best.fit.chi2 <= nested.fit.chi2


@pytest.mark.slow  # (22 s in the suite: make test-all runs it)
def test_a_baseline_stuck_short_of_its_optimum_is_refitted_before_an_effect_is_named():
    # the correct 9-element ladder (SYNTHETIC draw, 1 % noise growing toward low frequency):
    # the baseline's starts (24 copies then) stopped at 2.84 % where `impedax fit` of the same
    # circuit reaches 1.93 %, and "C3 → CPE3" reached 1.93 % with two arcs swapped, a false
    # alarm. Before a missing effect is named the baseline gets more starts; with its optimum,
    # nothing is missing. Its 32 copies now reach 1.95 % themselves; a user's own fit stuck at
    # 5.37 % (one start) is what gets refitted
    case, data = _draw("adequate/ladder9", 70)
    best = ix.fit(case.circuit, data)
    d = ix.diagnose(data, case.circuit)
    assert d.verdict == "adequate", d.report()
    assert d.baseline.rms_rel <= best.rms_rel * 1.02  # (1.95 %: R1 and R3 exchanged)
    stuck = ix.fit(case.circuit, data, n_starts=1)
    assert stuck.rms_rel > 2 * best.rms_rel
    d = ix.diagnose(stuck)
    assert d.verdict == "adequate", d.report()
    assert d.baseline.rms_rel <= best.rms_rel * 1.02
    assert any("and 32 random starts and reached a better optimum" in n for n in d.notes)


def _ladder9_case(template, index, variant=(0.003, "low_f", "weak", 0)):
    """A SYNTHETIC 9-element ladder of the evaluation set (numpy formulas of
    tests/evaluation_set.py) at 0.3 % noise growing 6× toward low frequency, drawn from a dev
    seed no split uses."""
    t = next(t for t in es.TEMPLATES if t.name == template)
    return es.make_case(t, variant, "dev", index)


@pytest.mark.slow  # (25 s, one 9-element diagnosis; the suite's budget)
def test_an_effect_at_the_quiet_top_of_the_band_counts_by_the_noise_there():
    # the fast arc's C is a CPE (α ≈ 0.9) near the top of the band, where the noise is 6× below
    # the low decade's. The generating circuit lowers BIC by 65; with the rule on the plain mean
    # |r|² against mean(2σ²) the noisy low decade set the bar (the CPE explained under 25 % of it)
    # and the diagnosis read `adequate`
    case = _ladder9_case("constant_phase/ladder9", 19)
    d = ix.diagnose(ix.make_spectrum(case.frequency, case.z), case.circuit)
    assert d.verdict == "missing_effect", d.report()
    best = d.suggestions[0]
    assert best.effect == "constant_phase", d.report()
    # the rule written out: the noise-weighted mean square falls by at least a quarter of 2
    # (its value for pure noise), each point divided by its own σ_k
    weighted = lambda fit: np.mean(np.abs(fit.residuals / d.noise) ** 2)  # noqa: E731
    assert (weighted(d.baseline) - weighted(best.fit)) / 2 >= NOISE_FRACTION_MIN


@pytest.mark.parametrize("index", [pytest.param(10, marks=pytest.mark.slow), pytest.param(11, marks=pytest.mark.slow)])  # (both draws with make test-all: the suite's budget; the r_cpe ladder of the test above stays)
def test_a_correct_ladder_with_noise_growing_toward_low_frequency_stays_adequate(index):
    # nothing is missing. Draw 11: the baseline's own and 32 random starts stop at 0.556 %,
    # "C3 → CPE3" reaches 0.511 % with the generating R1 ∥ CPE1 fitted by R3 ∥ CPE3 (ΔAIC −64,
    # a false alarm under the noise-weighted rule); the baseline started from the candidate's
    # arcs in the other order reaches the same 0.511 %, as `impedax fit` of the circuit does
    case = _ladder9_case("adequate/ladder9", index)
    data = ix.make_spectrum(case.frequency, case.z)
    d = ix.diagnose(data, case.circuit)
    assert d.verdict == "adequate", d.report()
    assert d.baseline.rms_rel <= ix.fit(case.circuit, data).rms_rel * 1.01


def test_a_cpe_at_alpha_one_is_judged_as_the_identical_r_parallel_c():
    # SYNTHETIC: an R ∥ C arc (numpy formula) with 0.3 % noise. Fitted with R1 ∥ CPE1 the CPE's
    # α sits at its bound 1: the same fit as R1 ∥ C1. Held at its bound, α no longer dilutes the
    # other parameters' correlations and errors, so the diagnosis' determinacy rule sees both
    # fits alike (a CPE at α = 1 had passed the rule where the identical R ∥ C failed it).
    from impedax.fitting.diagnosis.diagnosis import centred_covariance

    f = np.geomspace(1e-1, 1e5, 50)
    z = 20.0 + 500.0 / (1 + 2j * np.pi * f * 500.0 * 2e-6)
    rng = np.random.default_rng(0)  # (a draw where α ends at its bound; in others at 0.9996–0.9997)
    z = z * (1 + 0.003 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))
    data = ix.make_spectrum(f, z)
    with_cpe = ix.fit("R0 + R1 || CPE1", data)
    with_c = ix.fit("R0 + R1 || C1", data)
    assert "CPE1.alpha" in with_cpe.at_bound and with_cpe.chi2 == pytest.approx(with_c.chi2, rel=1e-4)
    rel_cpe, corr_cpe = centred_covariance(with_cpe)
    rel_c, corr_c = centred_covariance(with_c)
    i_cpe = [list(with_cpe.free_names).index(n) for n in ("R0", "R1")]
    i_c = [list(with_c.free_names).index(n) for n in ("R0", "R1")]
    # (the CPE fit stops a hair from its bound, α = 1 − 5e-10: its Jacobian differs by ~0.5 %;
    # with α's column in, R0's error was 7 % larger and the R0–R1 correlation −0.12 for −0.03)
    np.testing.assert_allclose(rel_cpe[i_cpe], rel_c[i_c], rtol=2e-2)
    assert corr_cpe[i_cpe[0], i_cpe[1]] == pytest.approx(corr_c[i_c[0], i_c[1]], abs=1e-2)
    # (the capacitor's error and Q's at ω_c: both the admittance coefficient of one element)
    assert rel_cpe[list(with_cpe.free_names).index("CPE1.Q")] == pytest.approx(rel_c[list(with_c.free_names).index("C1")], rel=1e-2)


def test_two_parameters_held_at_bounds_match_a_fit_with_both_fixed():
    # SYNTHETIC two arcs without a series R (numpy formula, 0.3 % noise): holding R0 and the
    # CPE's α (given in at_bound) must give the other parameters the errors and correlations of
    # a fit with those two fixed there (to the 2 % the degrees of freedom differ by), whatever
    # their units: R in Ω beside α, Q and C near 1e-6 and 1e-4
    import dataclasses

    from impedax.fitting.diagnosis.diagnosis import centred_covariance

    f = np.geomspace(1e-1, 1e5, 50)
    z = 500.0 / (1 + 2j * np.pi * f * 500.0 * 2e-6) + 300.0 / (1 + 2j * np.pi * f * 300.0 * 1e-4)
    rng = np.random.default_rng(0)
    data = ix.make_spectrum(f, z * (1 + 0.003 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))))
    free = ix.fit("R0 + R1 || CPE1 + R2 || C2", data)
    held = dataclasses.replace(free, at_bound=("R0", "CPE1.alpha"))
    fixed = ix.fit("R0 + R1 || CPE1 + R2 || C2", data, fixed={"R0": free.values["R0"], "CPE1.alpha": free.values["CPE1.alpha"]}, init=free)
    rel, corr = centred_covariance(held)
    names, fixed_names = list(free.free_names), list(fixed.free_names)
    for n in ("R1", "R2", "C2"):
        assert rel[names.index(n)] == pytest.approx(fixed.stderr[n] / fixed.values[n], rel=2e-2), n
    assert corr[names.index("R1"), names.index("R2")] == pytest.approx(fixed.correlation[fixed_names.index("R1"), fixed_names.index("R2")], abs=1e-3)
    assert np.isnan(corr[names.index("R0")]).all() and np.isnan(corr[:, names.index("CPE1.alpha")]).all()


def test_kk_flagged_and_non_passive_points_keep_their_own_measured_impedance():
    """Both kinds of masked point at once (SYNTHETIC, 0.5 % noise): the two highest frequencies
    with Re Z < 0, and one erratic point mid-band, 12 % off in magnitude and phase. Each masked
    point's Z is the one measured at its frequency, in the order of ``masked_points``."""
    circuit, formula, params, frange = he.ADEQUATE["r_cpe"]
    f, z, top = _with_non_passive_top(formula, params, frange, 5)
    mid = int(np.argsort(f)[f.size // 2])
    z[mid] *= 1 + 0.12 * np.exp(0.7j)
    d = ix.diagnose(ix.make_spectrum(f, z), circuit)
    masked = set(np.round(d.masked_points, 6))
    assert set(np.round(f[top], 6)) <= masked and round(f[mid], 6) in masked, d.report()
    by_f = dict(zip(np.round(f, 6), z))
    assert list(d.masked_impedance) == [by_f[round(fm, 6)] for fm in d.masked_points]
    assert list(d.masked_points) == sorted(d.masked_points)


@pytest.mark.slow
def test_a_series_resistance_within_its_error_of_zero_but_not_near_it_is_not_said_to_have_fallen():
    """REAL ZPlot file (impedance.py's example data, MIT): with the arc added in series, R0 ends
    at 72.1 ± 481 Ω: not told from 0, but not at 0 either ("it fell to 72.1 Ω" read oddly);
    nested behind R1 it runs to µΩ: there it fell (`FELL_SHARE_OF_ERROR`)."""
    import os

    path = os.path.join(os.path.dirname(__file__), "fixtures", "real", "exampleDataZPlot.z")
    d = ix.diagnose(ix.load(path), "R0 + R1 || C1 + L_lead")
    wheres = [s.where for s in d.suggestions if s.removed == ("R0",)]
    within = [w for w in wheres if "not told from 0" in w]
    assert within and all("fell to" not in w for w in within), wheres
    assert any("it fell to" in w and "µΩ" in w for w in wheres), wheres


def test_the_noise_line_says_how_its_local_sigma_differs_from_the_kk_tests_one_estimate():
    """The report's noise line beside impedax kk's "noise estimate": the local estimate says it is
    the scatter around each point, at least 0.7× the KK test's one estimate, and the points at the
    0.1 % minimum are counted (a walkthrough read REAL ZPlot's "σ ≈ 0.1 %" beside kk's 0.0705 % as
    a contradiction, 2026-12-06). Stand-in σ: 3 of 5 points at 0.001 by construction."""
    from impedax.fitting.diagnosis.diagnosis import noise_line

    sigma = np.array([0.001, 0.001, 0.0012, 0.001, 0.0024])
    line = noise_line(sigma, "Kramers–Kronig residuals, local (per frequency)", 8.706, 0.000705)
    assert line == ("noise: σ ≈ 0.1 % per component (median; 0.1–0.24 % over the band; Kramers–Kronig residuals, local (per frequency: the scatter of 9 frequencies "
                    "around each, at least 0.7× the KK test's single estimate, 0.0705 %); at its 0.1 % minimum at 3 of 5 points); the residuals are 8.71× the noise.")
    # with the discrepancy floor the source names, and masked points: the estimate of the points kept
    line = noise_line(np.array([0.004, 0.005, 0.006]), "Kramers–Kronig residuals, local (per frequency) + model-discrepancy floor 0.3 %", 1.2, 0.002, masked=True)
    assert "(per frequency: the scatter of 9 frequencies around each, at least 0.7× the KK test's single estimate without the masked points, 0.2 %) + model-discrepancy floor 0.3 %);" in line
    assert "minimum" not in line
    # a noise given or a sigma column is no KK estimate: only the minimum is said
    assert noise_line(np.full(4, 0.001), "given", 0.5, 0.000705) == "noise: σ ≈ 0.1 % per component (median; uniform; given; at its 0.1 % minimum at 4 of 4 points); the residuals are 0.5× the noise."


@pytest.mark.slow  # (~8 s: a diagnosis of a real file)
def test_the_noise_line_on_real_zplot_names_the_kk_estimate_and_the_minimum():
    """REAL impedance.py ZPlot file: impedax kk prints "noise estimate = 0.0705 %", diagnose σ ≈
    0.1 %, the 0.1 % minimum at most points. Oracles: the KK test run on its own (`ix.kk_test`) and
    the σ per point counted at the floor here."""
    from pathlib import Path

    data = ix.load(Path(__file__).parent / "fixtures" / "real" / "exampleDataZPlot.z")
    kk = ix.kk_test(data)
    d = ix.diagnose(data, "R0 + R1 || C1")
    line = next(x for x in d.report().splitlines() if x.startswith("noise:"))
    at_floor = int(np.sum(np.isclose(d.noise, 0.001, rtol=1e-9, atol=0)))
    assert at_floor > 0
    assert f"at least 0.7× the KK test's single estimate, {kk.noise_estimate * 100:.3g} %)" in line and f"{kk.noise_estimate * 100:.3g}" == "0.0705"
    assert f"; at its 0.1 % minimum at {at_floor} of {d.noise.size} points)" in line


def test_the_noise_ratio_is_the_per_point_rms_of_residual_over_noise_as_the_docs_define_it():
    """docs/diagnosis.md defined the noise ratio twice: mean(|Δ_k|²/2σ_k²) = ratio² (what
    `_noise_ratio` computes) and rms_rel/√(mean 2σ_k²), which differs wherever σ_k varies (REAL
    ZPlot: 8.71 printed, 7.19 by the second; 2026-12-06). Oracle: both computed here with numpy
    from the baseline's Z and σ_k; the docs keep only the first."""
    from pathlib import Path

    circuit, f, z, _ = uneven_spectrum("r_cpe", 3)
    d = ix.diagnose(ix.make_spectrum(f, z), circuit)
    b = d.baseline
    delta = np.abs((b.z_model - b.z_data) / np.abs(b.z_data))
    per_point = np.sqrt(np.mean(delta**2 / (2 * d.noise**2)))
    pooled = np.sqrt(np.mean(delta**2)) / np.sqrt(np.mean(2 * d.noise**2))
    assert d.noise.max() > 3 * d.noise.min() and abs(per_point / pooled - 1) > 0.01  # (σ varies ×10: the two differ, here by 1.5 %)
    assert d.noise_ratio == pytest.approx(per_point, rel=1e-9)
    text = (Path(__file__).resolve().parents[1] / "docs" / "diagnosis.md").read_text(encoding="utf-8")
    assert "rms_rel/√(mean 2σ_k²)" not in text and "The *noise ratio* √(mean(|Δ_k|²/2σ_k²))" in text
