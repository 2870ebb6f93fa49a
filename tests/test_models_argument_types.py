"""The models' remaining public functions refuse text where numbers go with one `ParameterError`
naming the argument (until 2026-12-06 NumPy's ValueError "could not convert string to float" or a
JAX TypeError), as their other functions do (`arguments.numeric_array`)."""

import warnings

import pytest

import impedax as ix
from impedax.models import meyer, vezzoli


@pytest.mark.parametrize(("call", "says"), [
    (lambda: meyer.static_force_f1("x", area=1e-4, d_sc=1e-5, eps_sc=10), "v_f must be numbers, got 'x'"),
    (lambda: meyer.static_force_f2("x", area=1e-4, d_sc=1e-5, eps_sc=10), "v_f must be numbers, got 'x'"),
    (lambda: meyer.static_force_series("x", area=1e-4, d_i=1e-6, eps_i=3, d_sc=1e-5, eps_sc=10), "v_f must be numbers, got 'x'"),
    (lambda: vezzoli.stratum_corneum_sweep([100.0], "x"), "h_s must be numbers, got 'x'"),
    (lambda: vezzoli.stratum_corneum_sweep([-100.0], [1e-5]), "freq must be positive"),
    (lambda: vezzoli.insulator_sweep("x", 3.0), "h_i must be numbers, got 'x'"),
    (lambda: vezzoli.voltage_sweep("x"), "eps_i must be numbers, got 'x'"),
])
def test_text_for_numbers_is_named(call, says):
    with pytest.raises(ix.ParameterError, match=says):
        call()


@pytest.mark.parametrize(("call", "says"), [
    (lambda: meyer.friction_coefficient("a", "b"), r"normal_force must be numbers \[N\], got 'a'"),
    (lambda: meyer.friction_coefficient([0.1, 0.2, 0.3], [0.05, "x", 0.14]), r"friction_force must be numbers \[N\]"),
    (lambda: meyer.force_from_friction("x", 0.5), r"delta_friction must be numbers \[N\], got 'x'"),
])
def test_measured_forces_that_are_no_numbers_are_a_data_error(call, says):
    """Measured forces are data: a DataError, as friction_coefficient's other faults (NaN: "finite")."""
    with pytest.raises(ix.DataError, match=says):
        call()


def test_the_sweeps_still_compute_and_warn_at_their_caller():
    """Numbers pass as before: F1 = ε0 A V²/(2 (d/ε)²) by hand for 100 V, 1 cm², d = 10 µm, ε = 10
    is 8.8541878e-12 · 1e-4 · 1e4/(2 · 1e-12) = 4.4271 N; the sweeps' Eq8 warning still points at
    the line that called them (one frame more since they check their arguments)."""
    assert float(meyer.static_force_f1(100.0, area=1e-4, d_sc=1e-5, eps_sc=10.0)) == pytest.approx(4.4270939, rel=1e-6)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sweep = vezzoli.insulator_sweep([1e-6, 2e-6], [3.0, 40.0])
    assert sweep.shape == (2, 2)
    eq8 = [w for w in caught if issubclass(w.category, vezzoli.Eq8ValidityWarning)]
    assert len(eq8) == 1 and eq8[0].filename == __file__


def test_meyer_parameters_and_sirins_ratios_name_what_they_were_given():
    """meyer_parameters('x') raised AttributeError "'str' object has no attribute 'c_s'", and
    Sirin eq 3's magnitude_ratio of text NumPy's UFuncTypeError (until 2026-12-06). Numbers pass:
    |1+1j|/|2| = √2/2 by hand."""
    from impedax.models import meyer_parameters, sirin

    with pytest.raises(ix.ParameterError, match=r"physical must be a MeyerPhysical .* got 'x' \(str\)"):
        meyer_parameters("x")
    with pytest.raises(ix.ParameterError, match=r"z_i must be impedances \(complex numbers\), got 'a'"):
        sirin.magnitude_ratio("a", [1.0])
    with pytest.raises(ix.ParameterError, match=r"z_total must be impedances \(complex numbers\), got 'b'"):
        sirin.phase_synchronization([1j], "b")
    assert float(sirin.magnitude_ratio([1 + 1j], [2.0])[0]) == pytest.approx(2 ** 0.5 / 2, rel=1e-12)
