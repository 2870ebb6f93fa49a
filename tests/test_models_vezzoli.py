"""Vezzoli et al.: eq 10 (Table 2 → 0.0556 N), eq 10 as the time average of eqs 7 + 9, the peak
force as their maximum, eq 8's validity (C_i ≪ C_s) warning, the Fig 8–10 sweeps, eq 11, and the
squeeze-film lift (order of magnitude at 2 µm, 0.2 N)."""

import warnings

import jax
import numpy as np
import pytest

from impedax.errors import ParameterError
from impedax.models import vezzoli

E0 = 8.8541878128e-12


def test_table2_force():
    assert float(vezzoli.electrovibration_force(440.0)) == pytest.approx(0.0556, rel=0.002)
    # by hand from Table 2
    tau = E0 * 2340 * 3e4
    wt = 2 * np.pi * 440 * tau
    hand = E0 * 1e-4 * 2000**2 / (4 * (90e-6 + 350e-6) * (90e-6 / 3.35 + 350e-6 / 2340)) * wt**2 / (1 + wt**2)
    assert float(vezzoli.electrovibration_force(440.0)) == pytest.approx(hand, rel=1e-12)


@pytest.mark.parametrize("f0", [10.0, 440.0, 5000.0])
def test_eq10_is_time_average_of_eq7_with_eq9_voltage(f0):
    tau = float(vezzoli.skin_time_constant())
    wt = 2 * np.pi * f0 * tau
    t = np.linspace(0, 1 / f0, 2001)[:-1]
    v_e = 2000.0 * wt / np.sqrt(1 + wt**2) * np.cos(2 * np.pi * f0 * t + np.pi / 2 - np.arctan(wt))  # eq 9
    inst = np.asarray(vezzoli.instantaneous_force(v_e))
    assert inst.mean() == pytest.approx(float(vezzoli.electrovibration_force(f0)), rel=1e-9)
    # eq 8 transfer has the eq 9 amplitude and phase
    h = complex(vezzoli.effective_voltage(f0))
    assert abs(h) == pytest.approx(wt / np.sqrt(1 + wt**2)) and np.angle(h) == pytest.approx(np.pi / 2 - np.arctan(wt))


def test_voltage_inversion_and_fig10():
    eps = np.array([1.0, 3.9, 10.0, 36.0])
    with pytest.warns(vezzoli.Eq8ValidityWarning, match="5.38"):  # 1 µm insulators: C_i/C_s up to 36·350/2340
        volts = vezzoli.voltage_sweep(eps)
    assert np.all(np.diff(volts.values) < 0)
    with pytest.warns(vezzoli.Eq8ValidityWarning):
        back = vezzoli.electrovibration_force(500.0, h_i=1e-6, eps_i=eps, v_m=volts.values)
    np.testing.assert_allclose(np.asarray(back), 0.01, rtol=1e-12)


def test_a_negative_force_target_is_refused_not_nan():
    """Eq 10 is V_m² times a positive factor, so no voltage gives a negative time-averaged force:
    voltage_for_force(-0.01, 500) returned NaN without a word (√ of a negative). Zero needs 0 V;
    0.01 N is eq 10 solved by hand (Table 2 values)."""
    with pytest.raises(ParameterError, match=r"force must be ≥ 0 N .* got -0\.01"):
        vezzoli.voltage_for_force(-0.01, 500.0)
    with pytest.raises(ParameterError, match="force must be ≥ 0 N"):
        vezzoli.voltage_sweep([3.4], force=-0.01)
    assert float(vezzoli.voltage_for_force(0.0, 500.0)) == 0.0
    tau = 8.8541878128e-12 * 2340 * 3.0e4
    wt = 2 * np.pi * 500.0 * tau
    expected = np.sqrt(4 * 0.01 * (90e-6 + 350e-6) * (90e-6 / 3.35 + 350e-6 / 2340) * (1 + wt**2) / (8.8541878128e-12 * 1e-4 * wt**2))
    assert float(vezzoli.voltage_for_force(0.01, 500.0)) == pytest.approx(expected, rel=1e-12)


def test_fig9_and_fig8_sweeps():
    h_i = np.geomspace(0.5e-6, 100e-6, 20)
    with pytest.warns(vezzoli.Eq8ValidityWarning):
        fig9 = vezzoli.insulator_sweep(h_i, np.arange(1, 37))
    assert fig9.dims == ("eps_i", "h_i") and fig9.attrs["convention"] == "time-average"
    assert np.all(np.diff(fig9.values, axis=1) < 0)  # thinner insulator, more force
    assert np.all(np.diff(fig9.values, axis=0) > 0)  # higher permittivity, more force
    freq = np.geomspace(100, 1e4, 21)
    with pytest.warns(vezzoli.Eq8ValidityWarning, match="0.581"):  # Meyer's 1 µm, ε_i 3.4: 3.4·400/2340
        fig8 = vezzoli.stratum_corneum_sweep(freq, [100e-6, 200e-6, 400e-6])
    assert np.all(np.diff(fig8.values, axis=1) > 0)  # high-pass in frequency
    # a thin insulator: the force falls with stratum corneum thickness
    assert np.all(np.diff(fig8.values, axis=0) < 0)
    # Meyer's conditions give forces of the order of the measured tens of mN
    assert 1e-3 < float(fig8.sel(h_s=200e-6).values[-1]) < 1.0


@pytest.mark.parametrize("f0", [10.0, 256.0, 5000.0])
def test_peak_force_is_the_maximum_of_eq7_over_a_period(f0):
    """Eq 7 with eq 9: DC + 2ω of equal amplitude, so the peak is twice eq 10 and the minimum 0."""
    tau = E0 * 2340 * 3e4
    wt = 2 * np.pi * f0 * tau
    t = np.linspace(0, 1 / f0, 20001)[:-1]
    v_e = 2000.0 * wt / np.sqrt(1 + wt**2) * np.cos(2 * np.pi * f0 * t + np.pi / 2 - np.arctan(wt))
    inst = E0 * 1e-4 * v_e**2 / (2 * (90e-6 + 350e-6) * (90e-6 / 3.35 + 350e-6 / 2340))
    peak = float(vezzoli.electrovibration_force_peak(f0))
    assert peak == pytest.approx(inst.max(), rel=1e-6)
    assert peak == pytest.approx(2 * float(vezzoli.electrovibration_force(f0)), rel=1e-12)
    assert inst.min() == pytest.approx(0.0, abs=1e-6 * peak)


def test_table2_satisfies_eq8_condition_and_does_not_warn():
    ratio = 3.35 * 350e-6 / (2340 * 90e-6)  # C_i/C_s = (ε_i/h_i)/(ε_s/h_s)
    assert ratio < 0.01
    assert float(vezzoli.insulator_capacitance_ratio()) == pytest.approx(ratio, rel=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        vezzoli.electrovibration_force(440.0)
        vezzoli.electrovibration_force_peak(440.0)
        vezzoli.voltage_for_force(0.01, 440.0)
    assert vezzoli.eq8_validity_message() is None


@pytest.mark.parametrize("ratio, warns", [(0.09, False), (0.11, True), (0.509, True)])
def test_eq8_warning_names_the_ratio_above_the_limit(ratio, warns):
    h_i = 3.35 * 350e-6 / (2340 * ratio)  # the insulator thickness giving this C_i/C_s
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        vezzoli.electrovibration_force(np.geomspace(10, 1e4, 7), h_i=h_i)
    ours = [w for w in caught if issubclass(w.category, vezzoli.Eq8ValidityWarning)]
    assert len(ours) == (1 if warns else 0)  # once per call, not once per frequency
    if warns:
        assert f"C_i/C_s = ε_i h_s/(ε_s h_i) = {ratio:.3g}" in str(ours[0].message)
        assert ours[0].filename == __file__  # points at the caller


def test_eq8_warning_names_the_largest_ratio_of_an_array_and_stays_quiet_under_jit():
    eps = np.array([1.0, 3.35, 36.0])
    with pytest.warns(vezzoli.Eq8ValidityWarning, match=r"= 0\.538 \(the largest of the values given\)"):
        vezzoli.electrovibration_force(440.0, h_i=10e-6, eps_i=eps)  # 36·350/(2340·10) = 0.538
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # traced values are unknown: nothing is said, nothing fails
        force = jax.jit(lambda h: vezzoli.electrovibration_force(440.0, h_i=h))(1e-6)
    assert float(force) > 0


def test_friction_coupling_eq11():
    assert vezzoli.friction_coupling(0.8, 0.3, 0.2, 0.05) == pytest.approx(0.5 * 0.25)


def test_squeeze_film_levitates_02N_near_2um():
    two = vezzoli.squeeze_film_lift(2e-6, normal_force=0.2)
    assert 0.1 < two.force < 0.4  # order of magnitude claimed by the paper, assumptions in the docstring
    assert two.squeeze_number > 10  # the sigma -> inf limit holds
    assert vezzoli.squeeze_film_lift(3e-6, normal_force=0.2).friction_reduction == 1.0
    amps = [0.5e-6, 1e-6, 2e-6, 3e-6]
    lifts = [vezzoli.squeeze_film_lift(a).force for a in amps]
    assert np.all(np.diff(lifts) > 0)
    assert vezzoli.squeeze_film_lift(0.0).force == pytest.approx(0.0, abs=1e-12)


def test_squeeze_film_flat_plate_closed_form():
    # no fingerprints (h_e = 0): P = sqrt(1 + 1.5 eps^2)/(1 + eps cos wt), time mean sqrt((1+1.5e^2)/(1-e^2))
    hv, hr = 1e-6, 2e-6
    e = hv / (hr + hv)
    lift = vezzoli.squeeze_film_lift(hv, h_r=hr, h_e=0.0).force
    assert lift == pytest.approx(1e5 * 1e-4 * (np.sqrt((1 + 1.5 * e**2) / (1 - e**2)) - 1), rel=1e-9)


def test_squeeze_film_bad_input():
    with pytest.raises(ParameterError, match="amplitude"):
        vezzoli.squeeze_film_lift(-1e-6)
    with pytest.raises(ParameterError, match="normal force"):
        vezzoli.squeeze_film_lift(1e-6, normal_force=0.0)


@pytest.mark.parametrize("keyword, value, said", [
    ("area", 0.0, r"area must be positive \[m²\], got 0\.0"),  # said "lift must be finite, got nan"
    ("area", -1e-4, r"area must be positive \[m²\]"),  # "math domain error"
    ("l_e", 0.0, r"l_e must be positive \[m\]"),  # ZeroDivisionError
    ("freq", -38220.0, r"freq must be positive \[Hz\]"),  # a negative squeeze number without a word
    ("p0", -1e5, r"p0 must be positive \[Pa\]"),  # a negative lift without a word
    ("h_r", 0.0, r"h_r must be positive \[m\], got 0\.0: at h_r = 0 the film closes"),  # "lift must be finite, got nan"
    ("h_e", -50e-6, r"h_e must be ≥ 0 \[m\]"),
    ("points", 1, r"points must be an integer ≥ 2"),  # a lift of 0 N without a word
])
def test_squeeze_film_geometry_and_air_refused_by_name(keyword, value, said):
    """Each geometric and air input of eqs 2–6 must be positive (h_e ≥ 0: a flat finger), said by
    its name and unit, not by an internal quantity or a Python error."""
    with pytest.raises(ParameterError, match="squeeze_film_lift: " + said):
        vezzoli.squeeze_film_lift(2e-6, **{keyword: value})


def test_squeeze_film_warns_where_the_sigma_to_infinity_limit_is_not_justified():
    """The paper justifies eq 6's σ → ∞ limit "if σ > 10". σ = 12 η ω l0²/(p0 h0²) by hand:
    Table 1 at 2 µm with A = 1 cm² gives 18.4 (no warning); a 50 mm² fingertip (l0 = 7.07 mm)
    gives 9.2, and a 20 kHz mode 9.6: the lift is then the limit's, and said to overstate it.
    Before, both returned that lift without a word."""
    def sigma(area, freq, h_v=2e-6):
        return 12 * 1.85e-5 * 2 * np.pi * freq * area / (1e5 * (1.8e-6 + h_v + 50e-6) ** 2)

    with warnings.catch_warnings():
        warnings.simplefilter("error", vezzoli.SqueezeNumberWarning)
        table = vezzoli.squeeze_film_lift(2e-6)
    assert table.squeeze_number == pytest.approx(sigma(1e-4, 38220.0), rel=1e-12) and table.squeeze_number > 10
    for kwargs, expected in ((dict(area=50e-6), sigma(50e-6, 38220.0)), (dict(freq=20e3), sigma(1e-4, 20e3))):
        assert expected < 10
        with pytest.warns(vezzoli.SqueezeNumberWarning, match=rf"squeeze number σ = {expected:.3g} \(eq 5\) is not above 10"):
            film = vezzoli.squeeze_film_lift(2e-6, **kwargs)
        assert film.squeeze_number == pytest.approx(expected, rel=1e-12)


def test_a_sweep_outside_eq8_warns_once_at_its_caller():
    """Fig 9's sweep (1 µm insulator, ε_i 3.4 and 36: C_i/C_s = 0.5 and 5.4) warns once, and the
    warning points at this file, not inside impedax."""
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        vezzoli.insulator_sweep(np.array([1e-6]), np.array([3.4, 36.0]))
    eq8 = [w for w in caught if issubclass(w.category, vezzoli.Eq8ValidityWarning)]
    assert len(eq8) == 1 and eq8[0].filename == __file__


@pytest.mark.parametrize(
    "args, name",
    [((0.5, 0.7, 1.0, 0.1), "delta_mu"), ((0.5, -0.1, 1.0, 0.1), "delta_mu"), ((0.0, 0.0, 1.0, 0.1), "mu"),
     ((0.5, 0.2, -1.0, 0.1), "normal_force"), ((0.5, 0.2, 1.0, -0.1), "electrostatic_force")],
)
def test_friction_coupling_refuses_what_gives_no_friction_of_eq11(args, name):
    """(0.5 − 0.7)(1 + 0.1) = −0.22 N was returned without a word (2026-12-06): a friction
    coefficient below zero, a negative normal or electrostatic force."""
    with pytest.raises(ParameterError, match=name):
        vezzoli.friction_coupling(*args)
    assert vezzoli.friction_coupling(0.5, 0.5, 1.0, 0.1) == 0.0  # (Δµ = µ: no friction, at the edge)


@pytest.mark.parametrize(
    "amplitude, kwargs, name",
    [(-1e-6, {}, "amplitude"), (1e-6, {"area": -1e-4}, "area"), (1e-6, {"freq": -38220.0}, "freq"), (1e-6, {"eta": 0.0}, "eta"), (1e-6, {"h_r": 0.0}, "h_r")],
)
def test_squeeze_number_refuses_what_squeeze_film_lift_refuses(amplitude, kwargs, name):
    """`squeeze_number` took a negative amplitude (σ = 20.7 for −1 µm), a negative frequency (σ < 0)
    and a negative area ("math domain error") without impedax's word until 2026-12-06."""
    with pytest.raises(ParameterError, match=f"squeeze_number: {name}"):
        vezzoli.squeeze_number(amplitude, **kwargs)
    # eq 5 by hand at Table 1 and A = 1 cm²: 12 η ω A / (p0 (h_r + h_v + h_e)²)
    h0 = 1.8e-6 + 2e-6 + 50e-6
    assert vezzoli.squeeze_number(2e-6) == pytest.approx(12 * 1.85e-5 * 2 * np.pi * 38220.0 * 1e-4 / (1e5 * h0**2), rel=1e-12)


@pytest.mark.parametrize(
    "call, name",
    [(lambda: vezzoli.skin_time_constant(rho_s=-1.0), "rho_s"), (lambda: vezzoli.effective_voltage(-100.0), "freq"),
     (lambda: vezzoli.effective_voltage(100.0, eps_s=0.5), "eps_s"), (lambda: vezzoli.instantaneous_force(100.0, area=-1e-4), "area"),
     (lambda: vezzoli.insulator_capacitance_ratio(h_i=-1e-6), "h_i")],
)
def test_the_eq_7_8_helpers_refuse_what_electrovibration_force_refuses(call, name):
    """τ < 0, a negative force and a ratio of −0.5 came back without a word (2026-12-06)."""
    with pytest.raises(ParameterError, match=name):
        call()


def test_the_eq_7_8_helpers_keep_their_values():
    """By hand, Table 2: τ = ε0 ε_s ρ_s, v_e/v = jωτ/(1 + jωτ), eq 7 at 100 V (a negative v_e is
    allowed: eq 7 squares it), C_i/C_s = ε_i h_s/(ε_s h_i)."""
    e0 = 8.8541878128e-12
    tau = e0 * 2340.0 * 3.0e4
    assert vezzoli.skin_time_constant() == pytest.approx(tau, rel=1e-12)
    jwt = 2j * np.pi * 440.0 * tau
    assert complex(vezzoli.effective_voltage(440.0)) == pytest.approx(jwt / (1 + jwt), rel=1e-12)
    force = e0 * 1e-4 * 100.0**2 / (2 * (90e-6 + 350e-6) * (90e-6 / 3.35 + 350e-6 / 2340.0))
    assert float(vezzoli.instantaneous_force(-100.0)) == pytest.approx(force, rel=1e-12)
    assert vezzoli.insulator_capacitance_ratio() == pytest.approx(3.35 * 350e-6 / (2340.0 * 90e-6), rel=1e-12)
