"""Sirin et al.: subtraction with SEM propagation (against a Monte Carlo), the paper's C_gap
method, gap thickness, gap voltage against the node equations, force with and without EP."""

import jax
import numpy as np
import pytest

import impedax as ix
from impedax.errors import DataError, ParameterError
from impedax.models import sirin

E0 = 8.8541878128e-12
F61 = np.geomspace(1.0, 1e6, 61)


def rcpe(f, r_inf, r, q, a):
    return r_inf + r / (1 + r * q * (2j * np.pi * f) ** a)


def edl(f, R_EP, C_EP, C_gap):  # noqa: N803 - circuit parameter names
    r_ep, c_ep, c_gap = R_EP, C_EP, C_gap
    w = 2 * np.pi * f
    return 1 / (1 / r_ep + 1j * w * c_ep + 1j * w * c_gap)


# the synthetic example's skin and screen (phase maxima at 250 Hz and 100 kHz)
SKIN = rcpe(F61, 800.0, 2.0e7, 1.049e-8, 0.90)
TS = rcpe(F61, 90.0, 1.7e5, 1.184e-9, 0.92)
EDL = {"R_EP": 2e7, "C_EP": 50e-12, "C_gap": 413e-12}


def test_gap_thickness_reference():
    u = sirin.gap_thickness(413e-12, area=130e-6)
    assert u == pytest.approx(2.79e-6, rel=0.003)
    assert u == pytest.approx(E0 * 1.00059 * 130e-6 / 413e-12, rel=1e-12)
    draws = np.array([400e-12, 413e-12, 430e-12])
    np.testing.assert_allclose(np.asarray(sirin.gap_thickness(jax.numpy.asarray(draws))), E0 * 1.00059 * 130e-6 / draws)


def _spectra(rng, z, n, rel_sd, freq):
    noise = rng.normal(0, 1, (n, freq.size)) + 1j * rng.normal(0, 0.5, (n, freq.size))
    return ix.make_spectrum(freq, z[None, :] + rel_sd * np.abs(z)[None, :] * noise, dims=("trial",))


def test_subtraction_is_exact_without_noise():
    zr = EDL_Z = edl(F61, **EDL)
    one = lambda z: ix.make_spectrum(F61, np.stack([z, z]), dims=("trial",))  # noqa: E731
    out = sirin.remaining_impedance(one(SKIN + TS + zr), one(SKIN), one(TS))
    np.testing.assert_allclose(out["Z"].values, EDL_Z, rtol=1e-9)


def test_sem_propagation_matches_monte_carlo():
    rng = np.random.default_rng(11)
    freq = np.geomspace(10, 1e5, 5)
    z_tot, z_s, z_t = edl(freq, **EDL) + 1e5, rcpe(freq, 1e3, 1e5, 1e-8, 0.8), rcpe(freq, 100, 1e4, 1e-9, 0.9)
    sizes = {"total": 30, "skin": 20, "ts": 12}
    rel = {"total": 0.05, "skin": 0.2, "ts": 0.1}
    predicted_re, predicted_im, means = [], [], []
    for _ in range(400):
        t = _spectra(rng, z_tot, sizes["total"], rel["total"], freq)
        s = _spectra(rng, z_s, sizes["skin"], rel["skin"], freq)
        m = _spectra(rng, z_t, sizes["ts"], rel["ts"], freq)
        out = sirin.remaining_impedance(t, s, m)
        predicted_re.append(out["sigma_real"].values)
        predicted_im.append(out["sigma_imag"].values)
        means.append(out["Z"].values)
    means = np.array(means)
    # the Monte Carlo spread of the mean Z_R against the mean predicted SEM (400 reps: ~4 % noise)
    np.testing.assert_allclose(np.mean(predicted_re, axis=0), means.real.std(axis=0, ddof=1), rtol=0.12)
    np.testing.assert_allclose(np.mean(predicted_im, axis=0), means.imag.std(axis=0, ddof=1), rtol=0.12)
    # and against the closed form: sqrt(sum rel^2 |z|^2 var_part / n)
    expected_re = np.sqrt(sum((rel[k] * np.abs(z)) ** 2 / sizes[k] for k, z in zip(sizes, (z_tot, z_s, z_t))))
    np.testing.assert_allclose(np.mean(predicted_re, axis=0), expected_re, rtol=0.05)
    assert np.all(out["sigma"].values == pytest.approx(np.sqrt((out["sigma_real"] ** 2 + out["sigma_imag"] ** 2) / 2).values))


def test_trial_remainders_carry_the_error_of_the_subtracted_means_and_of_each_trial():
    """Skin and screen trials scaled by (1 + s g_t) with known g_t: the means' error is
    (s mean_t g_t) Z, so the covariance the modes describe, Σ_j d_j d_jᵀ of the real-stacked
    modes, must equal var(g, ddof 1) s²/n · vvᵀ summed over skin and screen (v = [Re Z; Im Z]);
    the remainders themselves are total − mean skin − mean screen."""
    rng = np.random.default_rng(2)
    n, s = 10, 0.05
    g = {"skin": rng.standard_normal(n), "ts": rng.standard_normal(n)}
    skin = ix.make_spectrum(F61, SKIN[None, :] * (1 + s * g["skin"][:, None]), dims=("trial",))
    ts = ix.make_spectrum(F61, TS[None, :] * (1 + s * g["ts"][:, None]), dims=("trial",))
    total = ix.make_spectrum(F61, np.tile(SKIN + TS + edl(F61, **EDL), (4, 1)), dims=("trial",))
    out = sirin.trial_remainders(total, skin, ts)
    expected_z = SKIN + TS + edl(F61, **EDL) - skin["Z"].values.mean(0) - ts["Z"].values.mean(0)
    np.testing.assert_allclose(out["Z"].values, np.tile(expected_z, (4, 1)), rtol=1e-12)
    d = out["common_error_modes"].values
    assert out["common_error_modes"].dims == ("common_mode", "frequency") and d.shape == (2 * n, F61.size)
    stacked = lambda a: np.concatenate([a.real, a.imag], axis=-1)  # noqa: E731
    expected = sum(np.var(g[k], ddof=1) * s**2 / n * np.outer(stacked(z), stacked(z)) for k, z in (("skin", SKIN), ("ts", TS)))
    np.testing.assert_allclose(stacked(d).T @ stacked(d), expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())
    # each trial's own error: the sample covariance of one skin and one screen trial, n times that of the mean
    m = out["trial_error_modes"].values
    assert out["trial_error_modes"].dims == ("trial_mode", "frequency") and m.shape == (2 * n, F61.size)
    np.testing.assert_allclose(stacked(m).T @ stacked(m), n * expected, rtol=1e-9, atol=1e-12 * n * np.abs(expected).max())


def test_subtraction_bad_input():
    a = ix.make_spectrum(F61, np.stack([SKIN, SKIN]), dims=("trial",))
    b = ix.make_spectrum(F61[:-1], np.stack([SKIN[:-1], SKIN[:-1]]), dims=("trial",))
    with pytest.raises(DataError, match="skin: its frequencies differ from the total spectrum's"):
        sirin.remaining_impedance(a, b, a)
    with pytest.raises(DataError, match="expected a spectrum Dataset"):
        sirin.remaining_impedance(a, SKIN, a)
    single = ix.make_spectrum(F61, SKIN)
    out = sirin.remaining_impedance(single, a, a)
    assert "sigma" not in out and "not available" in out.attrs["sigma_method"]


def test_python_api_takes_the_grids_impedax_gap_takes():
    """SYNTHETIC: a descending skin sweep and a touchscreen whose frequencies were exported to 4
    significant digits (≤ 1.3e-4 off) are the total's grid, as `impedax gap` and `impedax remaining`
    read them (within 1e-3, the readers' sweep tolerance). The Python functions refused both with
    "frequencies differ from the total spectrum's (61 vs 61 points)". Oracle: eq 5 and the paper's
    C_gap = mean over f ≥ 30 Hz of 1/(2πf|Z_R|) written out with numpy on the ascending arrays."""
    zr = edl(F61, **EDL)
    total = ix.make_spectrum(F61, np.stack([SKIN + TS + zr, 1.01 * (SKIN + TS + zr)]), dims=("trial",))
    skin_z, ts_z = np.stack([SKIN, 0.99 * SKIN]), np.stack([TS, 1.02 * TS])
    skin = ix.make_spectrum(F61, skin_z, dims=("trial",)).isel(frequency=slice(None, None, -1))
    rounded = np.array([float(f"{f:.4g}") for f in F61])
    assert 0 < np.max(np.abs(rounded / F61 - 1)) < 1e-3
    ts = ix.make_spectrum(rounded, ts_z, dims=("trial",))
    expected = (total["Z"].values.mean(0) - skin_z.mean(0) - ts_z.mean(0))
    out = sirin.remaining_impedance(total, skin, ts)
    np.testing.assert_allclose(out["Z"].values, expected, rtol=1e-12)
    np.testing.assert_array_equal(out["frequency"].values, F61)
    np.testing.assert_allclose(sirin.trial_remainders(total, skin, ts)["Z"].values, total["Z"].values - skin_z.mean(0) - ts_z.mean(0), rtol=1e-12)
    keep = F61 >= 30.0
    c_gap = np.mean(1.0 / (2 * np.pi * F61[keep] * np.abs(expected[keep])))
    assert sirin.paper_gap_estimate(total, skin, ts).c_gap == pytest.approx(c_gap, rel=1e-12)
    mr = sirin.impedance_contributions(total, skin, ts)["magnitude_ratio"].sel(component="skin").values
    np.testing.assert_allclose(mr, np.abs(skin_z.mean(0)) / np.abs(total["Z"].values.mean(0)), rtol=1e-12)
    with pytest.raises(ParameterError, match="give both skin and touchscreen spectra"):  # (MR and PPS need the parts)
        sirin.impedance_contributions(total, None, None)
    # a grid that does differ names the first point, not "61 vs 61 points"
    shifted = ix.make_spectrum(F61 * 1.01, skin_z, dims=("trial",))
    with pytest.raises(DataError, match=r"skin: its frequencies differ .*first differing at point 1: 1\.01 Hz where the total has 1 Hz"):
        sirin.remaining_impedance(total, shifted, ts)


def test_skin_and_screen_dataarrays_pair_with_freq_by_frequency_not_by_position():
    """ix.load keeps a descending sweep descending, and `gap_force_peak(p, f, trial_mean(skin)["Z"],
    …)` took the DataArray's values by position: on SYNTHETIC skin and screen models, a skin
    saved high-to-low put its 1 MHz value at 1 Hz, and the force came out 0.9999 off at some
    frequency without a word. Oracle: eq 1 with the node voltages in numpy (the remainder parallel,
    so ΔV_gap = V0 Z_R/(Z_TS + Z_R + Z_skin))."""
    zr = edl(F61, **EDL)
    skin_desc = ix.make_spectrum(F61, np.stack([SKIN, SKIN]), dims=("trial",)).isel(frequency=slice(None, None, -1))
    ts = ix.make_spectrum(F61, np.stack([TS, TS]), dims=("trial",))
    z_skin, z_ts = sirin.trial_mean(skin_desc)["Z"], sirin.trial_mean(ts)["Z"]
    assert z_skin["frequency"].values[0] == 1e6  # (as read: high to low)
    u = E0 * 1.00059 * 130e-6 / EDL["C_gap"]
    expected = 0.5 * E0 * 1.00059 * 130e-6 * np.abs(75.0 * zr / (TS + zr + SKIN)) ** 2 / u**2
    np.testing.assert_allclose(np.asarray(sirin.gap_force_peak(EDL, F61, z_skin, z_ts, area=130e-6, v0=75.0)), expected, rtol=1e-9)
    np.testing.assert_allclose(np.asarray(sirin.gap_voltage(EDL, F61[::-1], z_skin, z_ts, v0=75.0)), (75.0 * zr / (TS + zr + SKIN))[::-1], rtol=1e-9)
    assert float(sirin.gap_force_peak(EDL, F61[20], z_skin, z_ts, area=130e-6)) == pytest.approx(expected[20], rel=1e-9)
    with pytest.raises(ParameterError, match=r"z_skin is over frequencies that do not hold every frequency of freq .*first missing 1\.01 Hz"):
        sirin.gap_force_peak(EDL, F61 * 1.01, z_skin, z_ts)
    # REAL: the Gamry DTA of tests/fixtures/real is recorded from 200 kHz down to 15.9 mHz, and read so
    from pathlib import Path

    gamry = ix.load(Path(__file__).parent / "fixtures" / "real" / "exampleDataGamry.DTA")
    f_file, z_file = gamry["frequency"].values, gamry["Z"].values
    assert f_file[0] > f_file[-1]
    order = np.argsort(f_file)
    f_up, z_up = f_file[order], z_file[order]
    z_gap = 1 / (2j * np.pi * f_up * EDL["C_gap"])
    np.testing.assert_allclose(np.asarray(sirin.gap_voltage({"C_gap": EDL["C_gap"]}, f_up, gamry["Z"], 0.0, v0=75.0)), 75.0 * z_gap / (z_gap + z_up), rtol=1e-9)


def test_a_negative_drive_amplitude_is_refused_in_every_force_function():
    """impedax gap --v0 -75, impedax force --param v_a=-140 / v_m=-2000 and gap_analysis(v0=-75)
    are refused, but the Python force functions squared the sign slip away and returned the force
    of +V without a word (and gap_voltage a phasor of the opposite sign). 0 V stays allowed: no
    drive, no force (eq 1, eq 3.6 and eq 10 are squares of the drive)."""
    from impedax.models import meyer, vezzoli

    f = np.array([100.0, 1e3])
    calls = {
        "v0": [lambda v: sirin.gap_voltage(EDL, f, 1e3, 1e3, v0=v), lambda v: sirin.gap_force_peak(EDL, f, 1e3, 1e3, v0=v),
               lambda v: sirin.gap_force_time_average(EDL, f, 1e3, 1e3, v0=v)],
        "v_a": [lambda v: meyer.force_time_average(meyer.THESIS_PARAMS, f, v_a=v), lambda v: meyer.force_peak(meyer.THESIS_PARAMS, f, v_a=v)],
        "v_m": [lambda v: vezzoli.electrovibration_force(f, v_m=v), lambda v: vezzoli.electrovibration_force_peak(f, v_m=v)],
    }
    for name, functions in calls.items():
        for call in functions:
            with pytest.raises(ParameterError, match=rf"{name} is the drive's amplitude \[V\] and must be ≥ 0, got -75"):
                call(-75.0)
            with pytest.raises(ParameterError, match=rf"{name} is the drive's amplitude"):
                call(np.array([75.0, -75.0]))
            assert np.all(np.asarray(call(0.0)) == 0.0)


def _conditions_data(seed=5):
    """SYNTHETIC: total over material x voltage x trial (C_gap per material, R_EP per voltage),
    skin over voltage x trial (its Re scales with the voltage), screen over trial; 2 % noise."""
    rng = np.random.default_rng(seed)
    freq = np.geomspace(10.0, 1e5, 8)
    c_gap = {"glass": 413e-12, "pet": 250e-12}
    r_ep = {50: 2e7, 100: 1e7, 150: 5e6}
    noisy = lambda z, shape: z * (1 + 0.02 * (rng.standard_normal(shape + z.shape[-1:]) + 1j * rng.standard_normal(shape + z.shape[-1:])))  # noqa: E731
    skin = np.stack([noisy(rcpe(freq, 800.0 * (1 + v / 500), 2e7, 1e-8, 0.9), (5,)) for v in r_ep])  # (voltage, trial, f)
    screen = noisy(rcpe(freq, 90.0, 1.7e5, 1.2e-9, 0.92), (6,))  # (trial, f)
    total = np.stack([[noisy(edl(freq, r, 50e-12, c) + rcpe(freq, 800.0 * (1 + v / 500), 2e7, 1e-8, 0.9) + rcpe(freq, 90.0, 1.7e5, 1.2e-9, 0.92), (4,)) for v, r in r_ep.items()] for c in c_gap.values()])
    coords = {"material": list(c_gap), "voltage": list(r_ep)}
    return (
        freq,
        (total, skin, screen),
        (
            ix.make_spectrum(freq, total, dims=("material", "voltage", "trial"), coords=coords),
            ix.make_spectrum(freq, skin, dims=("voltage", "trial"), coords={"voltage": list(r_ep)}),
            ix.make_spectrum(freq, screen, dims=("trial",)),
        ),
    )


def test_conditions_not_in_over_are_kept_and_subtracted_per_condition():
    freq, (total, skin, screen), datasets = _conditions_data()
    out = sirin.remaining_impedance(*datasets, over=["trial"])
    # oracle (numpy): trial means and SEMs (ddof 1) of each, the skin paired voltage by voltage
    sem2 = lambda z, axes: (z.real.var(axis=axes, ddof=1) / np.prod([z.shape[a] for a in axes]), z.imag.var(axis=axes, ddof=1) / np.prod([z.shape[a] for a in axes]))  # noqa: E731
    expected = total.mean(axis=2) - skin.mean(axis=1)[None] - screen.mean(axis=0)[None, None]
    (t_re, t_im), (s_re, s_im), (m_re, m_im) = sem2(total, (2,)), sem2(skin, (1,)), sem2(screen, (0,))
    assert out["Z"].dims == ("material", "voltage", "frequency") and list(out["material"].values) == ["glass", "pet"]
    assert list(out["voltage"].values) == [50, 100, 150] and out.attrs["condition_dims"] == "material, voltage"
    np.testing.assert_allclose(out["Z"].values, expected, rtol=1e-12)
    np.testing.assert_allclose(out["sigma_real"].values, np.sqrt(t_re + s_re[None] + m_re[None, None]), rtol=1e-12)
    np.testing.assert_allclose(out["sigma_imag"].values, np.sqrt(t_im + s_im[None] + m_im[None, None]), rtol=1e-12)
    assert out.attrs["n_trials_total"] == 4 and out.attrs["n_trials_skin"] == 5 and out.attrs["n_trials_touchscreen"] == 6
    # one condition of it is the remainder of that condition's spectra alone
    one = sirin.remaining_impedance(*(d.sel(voltage=100) for d in datasets[:2]), datasets[2], over=["trial"])
    np.testing.assert_allclose(out["Z"].sel(voltage=100).values, one["Z"].values, rtol=1e-12)
    # averaging the voltages too leaves material only; the default (every dim) a single spectrum
    assert sirin.remaining_impedance(*datasets, over=["voltage", "trial"])["Z"].dims == ("material", "frequency")
    assert sirin.remaining_impedance(*datasets)["Z"].dims == ("frequency",)


def test_kept_conditions_are_refused_where_one_spectrum_is_needed():
    freq, _, (total, skin, screen) = _conditions_data()
    with pytest.raises(DataError, match=r"skin: its voltage \(\[50, 100, 200\]\) differs from the total's \(\[50, 100, 150\]\)"):
        sirin.remaining_impedance(total, skin.assign_coords(voltage=[50, 100, 200]), screen, over=["trial"])
    z_r = sirin.remaining_impedance(total, skin, screen, over=["trial"])
    with pytest.raises(DataError, match=r"condition dims material, voltage .*z_r\.sel\(material='glass', voltage=50\)"):
        sirin.gap_capacitance_paper(z_r)
    assert sirin.gap_capacitance_paper(z_r.sel(material="glass", voltage=50)) > 0
    batch = type("Batch", (), {"dims": ("material",)})()  # what a fit of z_r is: a batch over its conditions
    with pytest.raises(ParameterError, match=r"edl_fit is a batch of fits over material .*--select material=LABEL"):
        ix.models.gap_analysis(total, skin, screen, area=130e-6, edl_fit=batch, progress=False)


def test_paper_capacitance_method():
    pure = 1 / (2j * np.pi * F61 * 413e-12)
    assert sirin.gap_capacitance_paper(pure, F61) == pytest.approx(413e-12, rel=1e-12)
    z = edl(F61, 2e7, 0.0, 413e-12)
    c = sirin.gap_capacitance_paper(z, F61)
    # by hand: mean over f >= 30 Hz of sqrt(C^2 + (1/(w R))^2)
    keep = F61 >= 30
    w = 2 * np.pi * F61[keep]
    assert c == pytest.approx(np.mean(np.sqrt(413e-12**2 + (1 / (w * 2e7)) ** 2)), rel=1e-12)
    assert sirin.gap_capacitance_paper(z, F61, cutoff_hz=1e3, fmax_hz=1e4) == pytest.approx(413e-12, rel=1e-3)
    with pytest.raises(DataError, match="no measured frequency at or above the cutoff 2e\\+06 Hz"):
        sirin.gap_capacitance_paper(z, F61, cutoff_hz=2e6)
    spec = sirin.admittance_spectrum(z, F61)
    np.testing.assert_allclose(spec["capacitance"].values, np.full(61, 413e-12), rtol=1e-12)


def test_paper_bounds_use_extreme_trials():
    low, mid, high = 400e-12, 413e-12, 430e-12
    trials = lambda zs: ix.make_spectrum(F61, np.stack(zs), dims=("trial",))  # noqa: E731
    gap = lambda c: 1 / (2j * np.pi * F61 * c)  # noqa: E731
    total = trials([SKIN + TS + gap(c) for c in (low, mid, high)])
    est = sirin.paper_gap_estimate(total, trials([SKIN] * 3), trials([TS] * 3), area=130e-6)
    # lowest total impedance = largest capacitance → smallest gap
    assert est.gap_lower == pytest.approx(sirin.gap_thickness(high), rel=1e-9)
    assert est.gap_upper == pytest.approx(sirin.gap_thickness(low), rel=1e-9)
    assert est.gap_lower < est.gap < est.gap_upper
    assert float(est.to_xarray()["gap"]) == est.gap


def _node_voltage_gap(z_r, v0=75.0):
    z_total = TS + z_r + SKIN
    i = v0 / z_total
    v1, v2 = v0 - TS * i, SKIN * i
    return v1 - v2


def test_gap_voltage_matches_node_equations():
    v = np.asarray(sirin.gap_voltage(EDL, F61, SKIN, TS, ep="C"))
    np.testing.assert_allclose(v, _node_voltage_gap(edl(F61, **EDL)), rtol=1e-10)
    v_noep = np.asarray(sirin.gap_voltage(EDL, F61, SKIN, TS, ep=None))
    np.testing.assert_allclose(v_noep, _node_voltage_gap(1 / (2j * np.pi * F61 * 413e-12)), rtol=1e-10)
    # a remainder with a series element: the gap sees only its share of the remainder voltage
    params = {**EDL, "R_s": 1e4}
    z_par = edl(F61, **EDL)
    v_series = np.asarray(sirin.gap_voltage(params, F61, SKIN, TS, remainder="R_s + R_EP || C_EP || C_gap"))
    np.testing.assert_allclose(v_series, _node_voltage_gap(z_par + 1e4) * z_par / (z_par + 1e4), rtol=1e-10)


def test_force_with_and_without_ep():
    params = {"R_EP": 1e8, "CPE_EP.Q": 4e-9, "CPE_EP.alpha": 0.30, "C_gap": 413e-12}
    with_ep = np.asarray(sirin.gap_force_peak(params, F61, SKIN, TS, ep="CPE"))
    without = np.asarray(sirin.gap_force_peak(params, F61, SKIN, TS, ep=None))
    low = F61 < 30
    assert np.all(with_ep[low] < without[low])
    assert np.all(with_ep[F61 <= 3] < 0.85 * without[F61 <= 3])
    flat = F61 <= 250
    assert without[flat].min() > 0.75 * without.max()
    assert without.max() == pytest.approx(without[0], rel=1e-2)
    above = F61 >= 250
    assert np.all(np.diff(without[above]) < 0) and without[F61 >= 1e4][0] < 0.5 * without.max()
    # eq 1 by hand, no EP: 1/2 eps0 eps_gap A |dV|^2 / u^2 = 1/2 C_gap |dV|^2 / u, u from C_gap
    u = E0 * 1.00059 * 130e-6 / 413e-12
    dv = _node_voltage_gap(1 / (2j * np.pi * F61 * 413e-12))
    np.testing.assert_allclose(without, 0.5 * 413e-12 * np.abs(dv) ** 2 / u, rtol=1e-10)
    # another gap medium (eps_gap 3): the same C_gap gives a 3x thicker gap and, by 1/2 C V^2/u, a third of the force
    third = np.asarray(sirin.gap_force_peak(params, F61, SKIN, TS, ep=None, eps_gap=3.0))
    np.testing.assert_allclose(third, 0.5 * 413e-12 * np.abs(dv) ** 2 / (E0 * 3.0 * 130e-6 / 413e-12), rtol=1e-10)
    np.testing.assert_allclose(np.asarray(sirin.gap_force_time_average(params, F61, SKIN, TS, ep=None)), without / 2, rtol=1e-12)


def test_fig2d_circuit_puts_the_force_peak_below_100_hz():
    """docs/models.md, Fig 2f: with the paper's C_gap, its EP range (corner at 30 Hz) and the
    example's skin and screen, Fig 2d's circuit peaks near 48 Hz, not at the paper's 250 Hz;
    250 Hz needs the EP corner near 420 Hz. Oracle: F = ½ ε0 ε_gap A |V0 Z_R/Z_total|²/u²."""
    freq = np.geomspace(1.0, 1e6, 1201)
    skin, ts = rcpe(freq, 800.0, 2.0e7, 1.049e-8, 0.90), rcpe(freq, 90.0, 1.7e5, 1.184e-9, 0.92)
    c_gap, u = 413e-12, E0 * 1.00059 * 130e-6 / 413e-12

    def peak_hz(corner_hz, c_ep):
        params = {"R_EP": 1 / (2 * np.pi * corner_hz * (c_ep + c_gap)), "C_EP": c_ep, "C_gap": c_gap}
        force = np.asarray(sirin.gap_force_peak(params, freq, skin, ts))
        z_r = edl(freq, **params)
        np.testing.assert_allclose(force, 0.5 * E0 * 1.00059 * 130e-6 * np.abs(75.0 * z_r / (z_r + skin + ts)) ** 2 / u**2, rtol=1e-10)
        return freq[np.argmax(force)]

    for c_ep in (0.01 * c_gap, 0.5 * c_gap, 2.0 * c_gap):
        assert 44.0 <= peak_hz(30.0, c_ep) <= 52.0
    assert peak_hz(420.0, 0.01 * c_gap) == pytest.approx(250.0, rel=0.05)


def test_auto_reads_c_gap_alone_as_no_ep_branch():
    # ep="auto" on {"C_gap": …}: the gap alone, eq 1 by hand with the node equations (numpy)
    force = np.asarray(sirin.gap_force_peak({"C_gap": 4.13e-10}, F61, SKIN, TS))
    u = E0 * 1.00059 * 130e-6 / 4.13e-10
    dv = _node_voltage_gap(1 / (2j * np.pi * F61 * 4.13e-10))
    np.testing.assert_allclose(force, 0.5 * E0 * 1.00059 * 130e-6 * np.abs(dv) ** 2 / u**2, rtol=1e-10)
    # R_EP without C_EP or CPE_EP.*: which branch is ambiguous, so it still asks
    with pytest.raises(ParameterError, match="C_EP or CPE_EP"):
        sirin.gap_force_peak({"R_EP": 1e8, "C_gap": 4.13e-10}, F61, SKIN, TS)


def test_force_vmaps_over_posterior_draws():
    rng = np.random.default_rng(5)
    draws = {k: v * np.exp(rng.normal(0, 0.05, 16)) for k, v in EDL.items()}
    batched = jax.vmap(lambda p: sirin.gap_force_peak(p, F61, SKIN, TS))(draws)
    assert batched.shape == (16, 61)
    one = sirin.gap_force_peak({k: v[3] for k, v in draws.items()}, F61, SKIN, TS)
    np.testing.assert_allclose(np.asarray(batched[3]), np.asarray(one), rtol=1e-12)
    with pytest.raises(ParameterError, match="electrode-polarization"):
        sirin.remainder_circuit("L")


def test_magnitude_ratio_phase_sync_and_friction():
    z_t = np.array([100 * np.exp(-1j * np.pi / 3)])
    assert sirin.magnitude_ratio(z_t / 4, z_t)[0] == pytest.approx(0.25)
    assert sirin.phase_synchronization(z_t, z_t)[0] == pytest.approx(100.0)
    assert sirin.phase_synchronization(np.array([np.exp(-1j * np.pi / 6)]), z_t)[0] == pytest.approx(50.0)
    assert sirin.force_from_friction_coefficients(0.5, 0.625) == pytest.approx(0.2)
    with pytest.raises(ParameterError):
        sirin.force_from_friction_coefficients(0.5, 0.0)
    # eq 6 with F_n = -1 N gave -0.2 N, a repulsion, without a word; F_n = 0 a force of 0
    for bad in (-1.0, 0.0, [1.0, -1.0]):
        with pytest.raises(ParameterError, match=r"normal_force is the finger's normal force F_n \[N\] .* must be positive"):
            sirin.force_from_friction_coefficients(0.5, 0.625, normal_force=bad)


def test_contributions_dataset():
    trials = lambda z: ix.make_spectrum(F61, np.stack([z, z]), dims=("trial",))  # noqa: E731
    zr = edl(F61, **EDL)
    ds = sirin.impedance_contributions(trials(SKIN + TS + zr), trials(SKIN), trials(TS))
    np.testing.assert_allclose(ds["magnitude_ratio"].sel(component="remaining").values, np.abs(zr) / np.abs(SKIN + TS + zr), rtol=1e-9)
