"""The public API's argument checks: make_spectrum's Z and sigma, the frequencies of every
``predict(freq)``, the compiled circuit's parameters (values, vectors, probes), any real number
for kk_test's c and for starting values, (frequency, Z) pairs as fit data,
Posterior.from_xarray of a netCDF file as stored, and the Python priors' messages.
Oracles: closed-form RC impedances written here, the numbers put in, and the exact messages."""

import re
import warnings
from decimal import Decimal
from fractions import Fraction

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import xarray as xr

import impedax as ix

RC = "R0 + R1 || C1"
VALUES = {"R0": 10.0, "R1": 1e3, "C1": 1e-6}
FREQ = np.geomspace(1.0, 1e5, 31)


def rc_impedance(freq, r0=10.0, r1=1e3, c1=1e-6):
    """R0 + R1/(1 + jωR1C1), written out by hand."""
    omega = 2 * np.pi * np.asarray(freq, float)
    return r0 + r1 / (1 + 1j * omega * r1 * c1)


def noisy_rc(seed=0, relative=0.005):
    rng = np.random.default_rng(seed)
    z = rc_impedance(FREQ)
    return z * (1 + relative * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)))


# --- 1. make_spectrum -------------------------------------------------------------------------


def test_make_spectrum_refuses_real_z_like_a_dataset_does():
    with pytest.raises(ix.DataError, match=r"Z must be complex, e\.g\. Z' \+ 1j\*Z''.*a magnitude or Z' alone is not an impedance spectrum"):
        ix.make_spectrum([1, 10, 100, 1000], [100.0, 90.0, 50.0, 10.0])
    with pytest.raises(ix.DataError, match="Z must be complex"):
        ix.make_spectrum([1, 10, 100, 1000], np.array([100, 90, 50, 10]))  # integers too
    ds = ix.make_spectrum([1, 10, 100, 1000], np.array([100.0, 90.0, 50.0, 10.0]) + 0j)  # complex with Z'' = 0: fine
    assert ds["Z"].dtype == np.complex128 and np.all(ds["Z"].values.imag == 0)


def test_make_spectrum_refuses_complex_sigma_without_a_numpy_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ix.DataError, match=r"sigma must be real \(a standard deviation"):
            ix.make_spectrum(FREQ, rc_impedance(FREQ), sigma=1.0 + 1.0j)
        with pytest.raises(ix.DataError, match="frequency must be real"):
            ix.make_spectrum(FREQ + 0j, rc_impedance(FREQ))
    with pytest.raises(ix.DataError, match=r"sigma has shape \(2,\), which does not broadcast to Z's \(31,\)"):
        ix.make_spectrum(FREQ, rc_impedance(FREQ), sigma=[1.0, 2.0])
    ds = ix.make_spectrum(FREQ, rc_impedance(FREQ), sigma=2.0)
    assert np.all(ds["sigma"].values == 2.0)


def test_make_spectrum_names_the_dimensions_to_give():
    z = np.stack([rc_impedance(FREQ)] * 3)
    with pytest.raises(ix.DataError) as info:
        ix.make_spectrum(FREQ, z)
    assert str(info.value) == "in-memory data: Z has 2 dimensions; name the ones before frequency, e.g. dims=('trial',) for Z over ('trial', 'frequency')"
    assert "were given" not in str(info.value)
    with pytest.raises(ix.DataError, match=r"Z has 3 dimensions; .*dims=\('trial', 'session'\)"):
        ix.make_spectrum(FREQ, z[None])
    with pytest.raises(ix.DataError, match=r"Z has 2 dimensions but dims=\('a', 'b'\) were given \(Z's dimensions before frequency: 1\)"):
        ix.make_spectrum(FREQ, z, dims=("a", "b"))
    # the dims quoted are those given, without the 'frequency' impedax adds
    with pytest.raises(ix.DataError) as info:
        ix.make_spectrum(FREQ, np.stack([z] * 2), dims=("temperature",))
    assert "dims=('temperature',) were given" in str(info.value) and "frequency')" not in str(info.value)
    assert ix.make_spectrum(FREQ, z, dims=("trial",)).sizes == {"trial": 3, "frequency": 31}


def test_make_spectrum_takes_one_dimension_name_as_a_string():
    """``dims="trial"`` had been split into letters (dims ('t', 'r', 'i', 'a', 'l', ...));
    it is one name, the same Dataset as ``dims=("trial",)``."""
    z = np.stack([rc_impedance(FREQ), rc_impedance(FREQ, r1=2e3)])
    as_text = ix.make_spectrum(FREQ, z, dims="trial", coords={"trial": [7, 8]})
    assert as_text["Z"].dims == ("trial", "frequency")
    assert as_text.identical(ix.make_spectrum(FREQ, z, dims=("trial",), coords={"trial": [7, 8]}))
    assert as_text["Z"].sel(trial=8).values == pytest.approx(rc_impedance(FREQ, r1=2e3))


def test_sigma_as_make_spectrum_promises_it_still_passes():
    """One value spreads over every point; a sigma over Z's dimensions in another order is
    the same data (the fits transpose it), so validate_spectrum accepts both."""
    z = np.stack([rc_impedance(FREQ), rc_impedance(FREQ, r1=2e3)])
    data = ix.make_spectrum(FREQ, z, sigma=0.5, dims=("trial",))
    assert data["sigma"].dims == ("trial", "frequency") and np.all(data["sigma"].values == 0.5)
    assert ix.validate_spectrum(data.assign(sigma=data["sigma"].transpose("frequency", "trial"))) is not None


@pytest.mark.parametrize("f_units, z_units", [("Hz", "ohm"), ("hz", "Ohm"), ("1/s", "ohms"), ("s-1", "Ω"), ("S^-1", "\u2126"), (" HZ ", "OHM")])
def test_units_that_mean_hertz_and_ohms_are_accepted(f_units, z_units):
    data = xr.Dataset({"Z": ("frequency", rc_impedance(FREQ), {"units": z_units})}, coords={"frequency": ("frequency", FREQ, {"units": f_units})})
    assert ix.validate_spectrum(data) is data


@pytest.mark.parametrize("variable, units, factor", [("frequency", "MHz", "1e+06"), ("frequency", "mHz", "0.001"), ("frequency", "rad/s", "0.159155"), ("Z", "MOhm", "1e+06"), ("Z", "mΩ", "0.001"), ("frequency", "s", None), ("Z", "S", None)])
def test_other_units_are_refused_with_the_factor_to_convert(variable, units, factor):
    """impedax reads frequency as Hz and Z as Ω whatever the attribute says: a frequency in
    MHz would be read a million times too low, so it is refused with the factor (and mHz,
    milli, is not MHz, mega)."""
    data = ix.make_spectrum(FREQ, rc_impedance(FREQ))
    data[variable].attrs["units"] = units
    unit = "Hz" if variable == "frequency" else "ohm"
    how = f"multiply the values by {factor}" if factor else f"convert the values to {unit}"
    with pytest.raises(ix.DataError, match=re.escape(f"{variable} has units '{units}', but impedax works in {unit}: {how} and set")):
        ix.validate_spectrum(data)


def test_a_loaded_file_changed_in_memory_is_not_blamed(tmp_path):
    """A NaN put into a loaded Dataset had been reported as a fault of the (clean) file."""
    path = tmp_path / "clean.nc"
    ix.save(ix.make_spectrum(FREQ, rc_impedance(FREQ)), path)
    data = ix.load(path)
    assert ix.fit(RC, data).converged  # (as read: accepted)
    data["Z"].values[3] = np.nan
    with pytest.raises(ix.DataError) as info:
        ix.fit(RC, data)
    assert str(info.value).startswith(f"{path}: Z has a non-finite value at f={FREQ[3]:.3g} Hz (point 3)")
    assert "changed in memory after impedax.load read the file" in str(info.value)
    with pytest.raises(ix.DataError) as built:  # (data built in a session: no such note)
        ix.fit(RC, ix.make_spectrum(FREQ, rc_impedance(FREQ)).assign(Z=("frequency", np.where(FREQ == FREQ[3], np.nan, rc_impedance(FREQ)))))
    assert "changed in memory" not in str(built.value)
    assert str(built.value).endswith("(point 3): (nan+0j); ds.dropna('frequency') leaves it out")  # (no file: Python's remedy, tests/test_api_nan_in_memory.py)
    assert "leave that point out" not in str(info.value)  # (the file passed: no advice to edit it)
    z = np.stack([rc_impedance(FREQ), rc_impedance(FREQ)])
    z[1, 3] = np.nan  # (a stack padded with NaN: what to do, 2026-12-03)
    with pytest.raises(ix.DataError, match=r"spectrum #1, f=.* \(point 3\): \(nan\+0j\); every spectrum needs a value at every frequency: .*not padded with NaN to one grid$"):
        ix.make_spectrum(FREQ, z, dims=("spectrum",))

def test_a_point_masked_in_memory_is_answered_with_the_dropna_that_leaves_it_out(tmp_path):
    """A NaN set by hand in a loaded stack (a point masked as bad) names xarray's remedy; the
    remedy, followed, fits, and recovers the RC's values (closed form, 30 of its 31 points)."""
    path = tmp_path / "stack.nc"
    z = np.stack([rc_impedance(FREQ), rc_impedance(FREQ, r1=2e3)])
    ix.save(xr.Dataset({"Z": (("cycle", "frequency"), z)}, coords={"cycle": [12, 64], "frequency": FREQ}), path)
    data = ix.load(path)
    data["Z"].values[1, 3] = np.nan
    with pytest.raises(ix.DataError) as info:
        ix.fit(RC, data)
    assert ("(point 3): (nan+0j); ds.dropna('frequency') leaves that frequency out of every spectrum, "
            "ds.sel(cycle=64).dropna('frequency') out of that spectrum alone (changed in memory") in str(info.value)
    alone = ix.fit(RC, data.sel(cycle=64).dropna("frequency"))
    assert alone.params["R1"] == pytest.approx(2e3, rel=1e-6)
    both = ix.fit(RC, data.dropna("frequency"))
    assert data.dropna("frequency").sizes["frequency"] == 30
    np.testing.assert_allclose(both.to_xarray()["value"].sel(param="R1").values, [1e3, 2e3], rtol=1e-6)
    data = ix.load(path).sel(cycle=12)
    data["Z"].values[5] = np.nan
    with pytest.raises(ix.DataError, match=re.escape("(point 5): (nan+0j); ds.dropna('frequency') leaves it out (changed in memory")):
        ix.fit(RC, data)


def test_zero_modulus_in_a_batch_names_the_spectrum_and_the_point():
    z = np.stack([rc_impedance(FREQ), rc_impedance(FREQ)])
    z[1, 7] = 0
    with pytest.raises(ix.DataError, match=re.escape(f"weighting 'modulus': zero or non-finite weight at f={FREQ[7]:.3g} Hz (point 7) of spectrum 1, where |Z| = 0 Ω; drop the point or use weighting='unit'")):
        ix.fit(RC, ix.make_spectrum(FREQ, z, dims="trial"))


def test_duplicate_frequency_message_stays_short_for_many_points():
    with pytest.raises(ix.DataError) as info:
        ix.make_spectrum(np.ones(100_000), np.ones(100_000) * (1 - 1j))
    assert str(info.value) == "in-memory data: duplicate frequency 1 Hz at points 0, 1, 2, 3, 4, … (100000 points)"


# --- 2. predict(freq) -------------------------------------------------------------------------


@pytest.fixture(scope="module")
def results():
    data = ix.make_spectrum(FREQ, noisy_rc())
    return {"fit": ix.fit(RC, data, n_starts=1), "kk": ix.kk_test(data), "drt": ix.drt(data)}


BAD_FREQUENCIES = [
    ([10.0, -1.0, 100.0], "freq must be positive and finite; point 1 is -1"),
    ([0.0, 10.0], "freq must be positive and finite; point 0 is 0"),
    ([10.0, 20.0, np.nan], "freq must be positive and finite; point 2 is nan"),
    ([10.0, np.inf], "freq must be positive and finite; point 1 is inf"),
    (-5.0, "freq must be positive and finite; got -5"),
]


@pytest.mark.parametrize("kind", ["kk", "drt"])
@pytest.mark.parametrize("freq, message", BAD_FREQUENCIES)
def test_predict_refuses_bad_frequencies_before_any_work(results, kind, freq, message):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy RuntimeWarning on the way
        with pytest.raises(ix.DataError) as info:
            results[kind].predict(freq)
    assert str(info.value) == message


@pytest.mark.parametrize("kind", ["kk", "drt"])
@pytest.mark.parametrize(
    "freq, message",
    [
        (np.ones((2, 3)) * 10.0, r"freq must be one-dimensional \(or one number\), got shape \(2, 3\)"),
        (["a", "b"], "freq must be frequencies in Hz"),
        ([10.0 + 1j], "freq must be real frequencies"),
        ([], "freq is empty"),
    ],
)
def test_predict_refuses_frequencies_of_the_wrong_kind(results, kind, freq, message):
    with pytest.raises(ix.DataError, match=message):
        results[kind].predict(freq)


@pytest.mark.parametrize("freq, message", BAD_FREQUENCIES[:4])
def test_fit_predict_refuses_bad_frequencies(results, freq, message):
    """FitResult.predict evaluates the compiled circuit, which checks concrete frequencies."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ix.DataError) as info:
            results["fit"].predict(freq)
    assert str(info.value) == message


def test_good_frequencies_still_predict(results):
    fit = results["fit"]
    z = fit.predict([10.0, 100.0])
    np.testing.assert_allclose(z, rc_impedance([10.0, 100.0], fit.values["R0"], fit.values["R1"], fit.values["C1"]), rtol=1e-10)
    assert np.shape(results["drt"].predict(10.0)) == ()
    np.testing.assert_allclose(results["kk"].predict(FREQ), results["kk"].kk_impedance, rtol=1e-12)


def test_derive_checks_its_frequencies(results):
    with pytest.raises(ix.DataError, match="freq must be positive and finite; point 0 is -2"):
        results["fit"].derive(lambda p, f: jnp.abs(ix.compile_circuit(RC)(p, f)), freq=[-2.0, 3.0])


@pytest.mark.parametrize("returned", ["x", {"tau": 1.0}])
def test_derive_names_fn_that_returns_no_numbers(results, returned):
    """JAX's words ("Value 'x' with dtype <U1 is not a valid JAX array type") named neither fn nor derive."""
    def tau(p):
        return returned

    with pytest.raises(ix.ParameterError) as info:
        results["fit"].derive(tau)
    assert str(info.value).startswith("derive: fn (tau) must return a number or an array of numbers, got ") and type(returned).__name__ in str(info.value)


@pytest.mark.parametrize("bands, said", [
    ([(1.0, 2.0, 3.0)], "bands[0] must be a band (f_min, f_max) in Hz with 0 < f_min < f_max, e.g. [(10.0, 100.0)]; got (1.0, 2.0, 3.0)"),
    ([(100.0, 10.0)], "bands[0] must be a band (f_min, f_max) in Hz with 0 < f_min < f_max, e.g. [(10.0, 100.0)]; got (100.0, 10.0)"),
    ("10-100", "bands must be a list of (f_min, f_max) bands in Hz, e.g. [(10.0, 100.0)]; got '10-100' (str)"),
])
def test_fit_plot_names_a_wrong_band(results, bands, said):
    """A band of three numbers raised ValueError "too many values to unpack" from the figure code."""
    with pytest.raises(ix.ParameterError) as info:
        results["fit"].plot(bands=bands)
    assert str(info.value) == said


def test_fit_plot_shades_the_bands_given(results):
    import matplotlib.pyplot as plt

    fig = results["fit"].plot(bands=[(10, 100.0)])
    spans = [(p.get_x(), p.get_x() + p.get_width()) for ax in fig.axes for p in ax.patches if hasattr(p, "get_width")]
    plt.close(fig)
    assert (10.0, 100.0) in spans, spans


def test_drt_plot_names_a_fit_given_as_overlay(results):
    """A FitResult as overlay raised AttributeError "'FitResult' object has no attribute 'tau'"."""
    with pytest.raises(ix.ParameterError) as info:
        results["drt"].plot(overlay=results["fit"])
    assert str(info.value) == "overlay must be a DRT, an AnalyticDRT or a DRTResult (a fit's DRT is impedax.fitting.drt.circuit_drt(fit)); got FitResult"


def test_validate_spectrum_formats_numbers_plainly():
    ds = ix.make_spectrum(FREQ, rc_impedance(FREQ)).assign_coords(frequency=np.r_[-1.0, FREQ[1:]])
    with pytest.raises(ix.DataError) as info:
        ix.validate_spectrum(ds)
    assert str(info.value).endswith("frequency must be positive and finite; point 0 is -1")
    assert "np.float64" not in str(info.value)


# --- 3. the compiled circuit ------------------------------------------------------------------


def test_compiled_circuit_names_an_unknown_key_with_a_hint():
    fn = ix.compile_circuit(RC)
    with pytest.raises(ix.ParameterError) as info:
        fn({"R0": 10.0, "R1": 1e3, "C_1": 1e-6}, FREQ)
    assert str(info.value) == "params: unknown parameter 'C_1' for R0 + R1 || C1; did you mean C1? (parameters: R0, R1, C1)"
    # the same message as ix.fit(init=...) gives for the same typo
    with pytest.raises(ix.ParameterError) as fit_info:
        ix.fit(RC, ix.make_spectrum(FREQ, noisy_rc()), init={"C_1": 1e-6})
    assert str(fit_info.value) == "init" + str(info.value)[len("params") :]


def test_compiled_circuit_missing_parameter_without_unknown_key():
    with pytest.raises(ix.ParameterError, match=r"missing parameter\(s\) C1 for circuit R0 \+ R1 \|\| C1"):
        ix.compile_circuit(RC)({"R0": 10.0, "R1": 1e3}, FREQ)


@pytest.mark.parametrize("value", ["1e-6", None, True, [1, "a"], {"x": 1}])
def test_compiled_circuit_refuses_values_that_are_not_numbers(value):
    with pytest.raises(ix.ParameterError, match=r"params\['C1'\] must be a number or an array of numbers"):
        ix.compile_circuit(RC)({**VALUES, "C1": value}, FREQ)


def test_compiled_circuit_refuses_a_non_mapping_and_bad_frequencies():
    fn = ix.compile_circuit(RC)
    with pytest.raises(ix.ParameterError, match="params must be a mapping"):
        fn([10.0, 1e3, 1e-6], FREQ)
    with pytest.raises(ix.DataError, match="freq must be positive and finite; point 0 is 0"):
        fn(VALUES, np.r_[0.0, FREQ])
    # any shape that broadcasts (a column of frequencies against rows of values) is still taken
    z = fn({**VALUES, "R0": np.array([[10.0, 20.0]])}, FREQ[:, None])
    np.testing.assert_allclose(np.asarray(z)[:, 1], rc_impedance(FREQ, r0=20.0), rtol=1e-12)
    with pytest.raises(ix.DataError, match=r"freq must be positive and finite; the value at \(1, 0\) is -1"):
        fn(VALUES, np.array([[1.0], [-1.0]]))


def test_compiled_circuit_stays_jittable_vmappable_and_differentiable():
    fn = ix.compile_circuit(RC)
    np.testing.assert_allclose(np.asarray(jax.jit(fn)(VALUES, FREQ)), rc_impedance(FREQ), rtol=1e-12)
    batch = {"R0": jnp.array([10.0, 20.0]), "R1": jnp.array([1e3, 2e3]), "C1": jnp.array([1e-6, 1e-6])}
    z = np.asarray(jax.vmap(fn, in_axes=(0, None))(batch, FREQ))
    np.testing.assert_allclose(z[1], rc_impedance(FREQ, 20.0, 2e3, 1e-6), rtol=1e-12)
    # d|Z|/dR0 at high frequency, where Z → R0 (C1 shorts R1): 1 within the R1 part's share
    grad = jax.grad(lambda r0: jnp.abs(fn({**VALUES, "R0": r0}, jnp.array([1e7])))[0])(10.0)
    assert float(grad) == pytest.approx(1.0, abs=1e-3)
    # frequencies traced under jit pass unchecked (no tracer is turned into a number)
    np.testing.assert_allclose(np.asarray(jax.jit(lambda f: fn(VALUES, f))(FREQ)), rc_impedance(FREQ), rtol=1e-12)


def test_compiled_circuit_keeps_taking_extra_keys_when_none_is_missing():
    """A model's parameter draws hold more than one circuit's parameters (impedax.models.sirin
    relies on it: 'extra entries in params are ignored')."""
    z = ix.compile_circuit(RC)({**VALUES, "sigma_rel": 0.01}, FREQ)
    np.testing.assert_allclose(np.asarray(z), rc_impedance(FREQ), rtol=1e-12)


RCPE = "R0 + R1 || CPE1"
RCPE_VALUES = {"R0": 10.0, "R1": 1e3, "CPE1.Q": 1e-6, "CPE1.alpha": 0.9}


def rcpe_impedance(freq, r0=10.0, r1=1e3, q=1e-6, alpha=0.9):
    """R0 + R1/(1 + R1 Q (jω)^α), written out by hand."""
    omega = 2 * np.pi * np.asarray(freq, float)
    return r0 + r1 / (1 + r1 * q * (1j * omega) ** alpha)


def test_compiled_vector_takes_a_list_or_tuple_of_exactly_the_parameters():
    """A list raised a raw TypeError; 3 values were read with a clamped index and 6 with two
    ignored: now a list or tuple is an array, and a wrong length is named with the parameters."""
    fn = ix.compile_circuit(RCPE)
    theta = [10.0, 1e3, 1e-6, 0.9]
    for given in (theta, tuple(theta), np.array(theta)):
        np.testing.assert_allclose(np.asarray(fn.vector(given, FREQ)), rcpe_impedance(FREQ), rtol=1e-12)
        z, jac = fn.value_and_jacobian(given, FREQ)
        np.testing.assert_allclose(np.asarray(z), rcpe_impedance(FREQ), rtol=1e-12)
        np.testing.assert_allclose(np.asarray(jac[:, 0]), 1.0)  # ∂Z/∂R0 = 1
    for wrong in (theta[:3], theta + [1.0, 2.0]):
        with pytest.raises(ix.ParameterError) as info:
            fn.vector(wrong, FREQ)
        assert str(info.value) == f"theta has {len(wrong)} values (last axis), the circuit has 4 parameters (R0, R1, CPE1.Q, CPE1.alpha)"
        with pytest.raises(ix.ParameterError, match=f"theta has {len(wrong)} values"):
            fn.value_and_jacobian(wrong, FREQ)


def test_theta_checks_keep_vector_and_jacobian_jittable_vmappable_differentiable():
    fn = ix.compile_circuit(RCPE)
    theta = jnp.array([10.0, 1e3, 1e-6, 0.9])
    np.testing.assert_allclose(np.asarray(jax.jit(fn.vector)(theta, FREQ)), rcpe_impedance(FREQ), rtol=1e-12)
    batch = jnp.stack([theta, theta.at[0].set(20.0)])
    z = np.asarray(jax.vmap(fn.vector, in_axes=(0, None))(batch, FREQ))
    np.testing.assert_allclose(z[1], rcpe_impedance(FREQ, r0=20.0), rtol=1e-12)
    z, jac = jax.jit(jax.vmap(lambda t: fn.value_and_jacobian(t, FREQ)))(batch)
    assert jac.shape == (2, FREQ.size, 4)
    np.testing.assert_allclose(np.asarray(z[1]), rcpe_impedance(FREQ, r0=20.0), rtol=1e-12)
    grad = jax.grad(lambda t: jnp.sum(jnp.real(fn.vector(t, FREQ))))(theta)
    assert float(grad[0]) == pytest.approx(FREQ.size)  # ∂Re Z/∂R0 = 1 at every frequency
    # shapes are static: a wrong length is refused when tracing, under jit and vmap too
    with pytest.raises(ix.ParameterError, match=r"theta has 3 values \(last axis\)"):
        jax.jit(fn.vector)(theta[:3], FREQ)
    with pytest.raises(ix.ParameterError, match="theta has 5 values"):
        jax.vmap(lambda t: fn.value_and_jacobian(t, FREQ))(jnp.ones((2, 5)))


def test_compiled_parameter_values_broadcast_against_freq_or_are_named():
    """docs/circuits.md: a value is a number or an array that broadcasts against freq. A list
    raised "unsupported operand list + ArrayImpl" and a (3,) array JAX's broadcasting error."""
    fn = ix.compile_circuit(RCPE)
    z = np.asarray(fn({**RCPE_VALUES, "R0": [[10.0], [20.0]]}, FREQ[None, :]))  # a list: a column of two R0
    assert z.shape == (2, FREQ.size)  # (the tests run JAX with rank promotion refused: equal ranks)
    np.testing.assert_allclose(z[1], rcpe_impedance(FREQ, r0=20.0), rtol=1e-12)
    with pytest.raises(ix.ParameterError) as info:
        fn({**RCPE_VALUES, "R0": [1.0, 2.0]}, FREQ)
    assert str(info.value).startswith("params['R0'] has shape (2,), which does not broadcast against freq's shape (31,): ")
    with pytest.raises(ix.ParameterError, match=r"params\['R1'\] has shape \(1, 3\), which does not broadcast against freq's shape \(1, 31\) and the parameters before it \(together \(2, 31\)\)"):
        fn({**RCPE_VALUES, "R0": np.ones((2, 1)), "R1": np.ones((1, 3))}, FREQ[None, :])
    with pytest.raises(ix.ParameterError, match=r"params\['R0'\] has shape \(2, 1\), which does not broadcast against freq's shape \(31,\)"):
        fn({**RCPE_VALUES, "R0": np.ones((2, 1))}, FREQ)  # (JAX set to refuse rank promotion, as here: named too)
    with pytest.raises(ix.ParameterError, match=r"params\['R0'\] has shape \(3,\)"):
        jax.jit(fn)({**RCPE_VALUES, "R0": jnp.ones(3)}, FREQ)  # (refused when tracing)
    # a batch of values through vmap, and a gradient, still work
    z = np.asarray(jax.vmap(lambda r0: fn({**RCPE_VALUES, "R0": r0}, FREQ))(jnp.array([10.0, 20.0])))
    np.testing.assert_allclose(z[1], rcpe_impedance(FREQ, r0=20.0), rtol=1e-12)
    grad = jax.grad(lambda r0: jnp.sum(jnp.real(fn({**RCPE_VALUES, "R0": r0}, FREQ))))(10.0)
    assert float(grad) == pytest.approx(FREQ.size)


def test_probes_check_their_arguments_as_the_compiled_circuit_does_and_stay_jittable():
    """A probe's function raised KeyError for a missing parameter and took negative frequencies;
    its target "C1 " was "no element(s) C1  in …". Now the compiled circuit's check (one
    function, the same messages), and the target's names stripped."""
    values = {"R1": 1e3, "C1": 1e-6}
    omega = 2 * np.pi * FREQ
    expected = 1 / (1 + 1j * omega * 1e3 * 1e-6)  # V_C/V = Z_C/(R + Z_C)
    v = ix.voltage_across("R1 + C1", "C1 ")
    np.testing.assert_allclose(np.asarray(v(values, FREQ)), expected, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(jax.jit(v)(values, FREQ)), expected, rtol=1e-12)
    batch = np.asarray(jax.vmap(lambda r: v({**values, "R1": r}, FREQ))(jnp.array([1e3, 2e3])))
    np.testing.assert_allclose(batch[1], 1 / (1 + 1j * omega * 2e3 * 1e-6), rtol=1e-12)
    grad = jax.grad(lambda c: jnp.abs(v({**values, "C1": c}, jnp.array([1e9])))[0])(1e-6)
    assert float(grad) < 0  # a larger C1 takes less of the voltage
    with pytest.raises(ix.ParameterError) as probe_error:
        v({"R1": 1.0}, FREQ)
    with pytest.raises(ix.ParameterError) as circuit_error:
        ix.compile_circuit("R1 + C1")({"R1": 1.0}, FREQ)
    assert str(probe_error.value) == str(circuit_error.value) == "missing parameter(s) C1 for circuit R1 + C1"
    with pytest.raises(ix.DataError, match="freq must be positive and finite; point 0 is -1"):
        v(values, -FREQ)
    with pytest.raises(ix.ParameterError, match=r"params\['C1'\] has shape \(3,\)"):
        ix.current_through("R1 + C1", {"R1"})({**values, "C1": np.ones(3)}, FREQ)


# --- 4. Posterior.from_xarray of a stored file -------------------------------------------------


def test_posterior_from_xarray_reads_a_file_opened_as_stored(tmp_path):
    post = ix.sample(RC, ix.make_spectrum(FREQ, noisy_rc()), steps=40, walkers=16, seed=2)
    path = tmp_path / "post.nc"
    ix.write_result(post, path)
    with xr.open_dataset(path) as raw:
        assert isinstance(raw.attrs["priors"], str) and raw.attrs["priors"].startswith("json:")  # stored encoded
        back = ix.Posterior.from_xarray(raw.load())
    np.testing.assert_array_equal(back.draws, post.draws)
    np.testing.assert_array_equal(back.z_data, post.z_data)
    assert back.priors == post.priors and back.names == post.names and back.fit.values == post.fit.values
    loaded = ix.Posterior.from_xarray(ix.load(path))  # the decoded way still works
    np.testing.assert_array_equal(loaded.draws, post.draws)
    with pytest.raises(ix.DataError, match="from_xarray takes an xarray.Dataset, got str"):
        ix.Posterior.from_xarray(str(path))


# --- 5. (frequency, Z) pairs as fit data ------------------------------------------------------


def test_fit_takes_a_frequency_z_pair_like_kk_test():
    z = noisy_rc()
    from_pair = ix.fit(RC, (FREQ, z), n_starts=1)
    from_dataset = ix.fit(RC, ix.make_spectrum(FREQ, z), n_starts=1)
    assert from_pair.values == pytest.approx(from_dataset.values, rel=1e-9)
    assert from_pair.values["R1"] == pytest.approx(1e3, rel=0.02)  # the generating value, 0.5 % noise
    assert ix.kk_test((FREQ, z)).valid == ix.kk_test(ix.make_spectrum(FREQ, z)).valid


@pytest.mark.parametrize(
    "pair, message",
    [
        ((np.r_[np.nan, FREQ[1:]], noisy_rc()), "frequency must be positive and finite; point 0 is nan"),
        ((-FREQ, noisy_rc()), "frequency must be positive and finite; point 0 is -1"),
        ((np.r_[FREQ[:-1], FREQ[0]], noisy_rc()), "duplicate frequency 1 Hz at points 0, 30"),
        ((FREQ, np.abs(noisy_rc())), "Z must be complex"),
        ((FREQ, noisy_rc()[:-1]), "Z has 30 values along frequency but there are 31 frequencies"),
        ((FREQ, np.stack([noisy_rc()] * 2, axis=-1)), "Z has 2 values along frequency but there are 31 frequencies (Z's shape (31, 2): frequency must be its last axis; Z.T"),
    ],
)
@pytest.mark.parametrize("method", ["fit", "kk_test", "drt", "diagnose", "sample"])
def test_bad_pairs_get_make_spectrums_messages(pair, message, method):
    call = {
        "fit": lambda: ix.fit(RC, pair),
        "kk_test": lambda: ix.kk_test(pair),
        "drt": lambda: ix.drt(pair),
        "diagnose": lambda: ix.diagnose(pair, RC),
        "sample": lambda: ix.sample(RC, pair, steps=10),
    }[method]
    with pytest.raises(ix.DataError) as info:
        call()
    assert message in str(info.value)


def test_numbers_are_not_a_pair():
    with pytest.raises(ix.DataError, match="data must be a spectrum Dataset"):
        ix.fit(RC, [1.0, 2.0])


# --- 7. priors given from Python ---------------------------------------------------------------


@pytest.mark.parametrize(
    "prior, message",
    [
        ("gauss:0,1", "priors['R1']='gauss:0,1': unknown prior kind 'gauss'"),
        (("gauss", 0, 1), "priors['R1']=('gauss', 0, 1): unknown prior kind 'gauss'"),
        ("uniform:1", "priors['R1']='uniform:1': uniform takes two numbers"),
    ],
)
def test_python_prior_errors_quote_the_python_argument(prior, message):
    with pytest.raises(ix.ParameterError) as info:
        ix.sample(RC, ix.make_spectrum(FREQ, noisy_rc()), priors={"R1": prior}, steps=10)
    assert str(info.value).startswith(message)
    assert "--prior" not in str(info.value)


def test_prior_outside_bounds_message_closes_its_bracket_once():
    with pytest.raises(ix.ParameterError) as info:
        ix.sample(RC, ix.make_spectrum(FREQ, noisy_rc()), priors={"R1": "uniform:-5,10"}, steps=10)
    assert str(info.value) == "prior for R1: uniform:-5,10 reaches outside the parameter's bounds (0, inf)"


def test_command_line_prior_errors_keep_the_option():
    with pytest.raises(ix.ParameterError, match=r"^--prior 'R1=gauss:0,1': unknown prior kind 'gauss'"):
        ix.fitting.parse_prior("R1=gauss:0,1")


# --- 8. any real number where a number is asked ----------------------------------------------


@pytest.mark.parametrize("c", [np.float32(0.85), jnp.asarray(0.85), Fraction(17, 20), Decimal("0.85")], ids=["float32", "jax", "fraction", "decimal"])
def test_kk_c_takes_any_real_number(c):
    """``c=np.float32(0.85)`` was refused: "c must be between 0 and 1 (exclusive), got
    np.float32(0.85)" (only int and float were numbers)."""
    data = ix.make_spectrum(FREQ, noisy_rc())
    reference, got = ix.kk_test(data, c=0.85), ix.kk_test(data, c=c)
    assert got.c == pytest.approx(0.85, rel=1e-6) and got.n_rc == reference.n_rc
    np.testing.assert_allclose(got.residuals_real, reference.residuals_real, rtol=1e-12)
    batch = ix.kk_test_batch(data.expand_dims(trial=[0, 1]), c=c)
    assert batch.n_rc.tolist() == [reference.n_rc] * 2


def test_fit_takes_a_decimal_start():
    """``init={"R1": Decimal("800")}`` said "must be a number"; a Decimal is one (and a
    quiet-NaN Decimal is refused as not finite)."""
    data = ix.make_spectrum(FREQ, noisy_rc())
    reference = ix.fit(RC, data, init={"R1": 800.0}, n_starts=1)
    for start in (Decimal("800"), Fraction(800)):
        assert ix.fit(RC, data, init={"R1": start}, n_starts=1).values == pytest.approx(reference.values, rel=1e-9)
    with pytest.raises(ix.ParameterError, match=r"init\['R1'\] must be finite"):
        ix.fit(RC, data, init={"R1": Decimal("NaN")})


def test_kk_thresholds_take_any_real_number_but_not_a_bool():
    """A threshold given as a NumPy scalar was "must be a positive number"; True passed as 1."""
    data = ix.make_spectrum(FREQ, noisy_rc())
    reference = ix.kk_test(data, thresholds={"point": 6.0})
    assert ix.kk_test(data, thresholds={"point": np.float32(6.0)}).thresholds == reference.thresholds
    with pytest.raises(ix.ParameterError, match="threshold point must be a positive number, got True"):
        ix.kk_test(data, thresholds={"point": True})
