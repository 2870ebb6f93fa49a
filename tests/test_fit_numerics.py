"""Numerical edge cases of fitting: extreme frequency and impedance ranges, overflow reported.

Spectra come from the numpy formulas of tests/spectra.py, not from impedax's compiler.
"""

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from spectra import noisy, rc

NOISE = 0.01
WIDE_BAND = np.geomspace(1e-3, 1e7, 61)  # ten decades

# R0 + R1 || C1 at the corners of what instruments see. A passive RC network changes |Z| by at
# most one decade per decade of frequency, so one spectrum over 1e-3–1e7 Hz cannot span
# 1e-3–1e12 Ω with every parameter visible; these spectra cover the corners between them.
EXTREMES = {
    # an insulator: 1 TΩ with 1 pF (corner 0.16 Hz); |Z| from ≈2e4 Ω to 1e12 Ω
    "teraohm": {"R0": 1e4, "R1": 1e12, "C1": 1e-12},
    # a large battery: milliohm resistances, a 50 F double layer (corner 1.6 Hz); |Z| 1e-3–3e-3 Ω
    "milliohm": {"R0": 1e-3, "R1": 2e-3, "C1": 50.0},
    # 1 MΩ with 10 µF (corner 16 mHz) behind a 1 mΩ contact: |Z| from ≈1.9e-3 Ω to 1e6 Ω
    "nine-decades": {"R0": 1e-3, "R1": 1e6, "C1": 1e-5},
}


@pytest.mark.parametrize("case", list(EXTREMES))
def test_extreme_spectra_recover_parameters_to_the_noise_level(case, rng):
    truth = EXTREMES[case]
    z = rc(WIDE_BAND, truth)
    data = ix.make_spectrum(WIDE_BAND, noisy(z, NOISE, rng))
    result = ix.fit("R0 + R1 || C1", data)
    assert result.converged, result.message
    assert result.rms_rel < 2 * NOISE * np.sqrt(2)
    for name, value in truth.items():
        err = result.stderr[name]
        assert np.isfinite(result.values[name]) and 0 < err < abs(value)
        assert abs(result.values[name] - value) < 4 * err, (name, result.values[name], value, err)


def test_nine_decades_in_one_spectrum_keep_milliohm_precision(rng):
    """|Z| spans 1.9e-3 Ω to 1e6 Ω: the milliohm series resistance, seen only in the top
    decade, comes back to that decade's noise level (relative weighting keeps it visible)."""
    truth = EXTREMES["nine-decades"]
    z = rc(WIDE_BAND, truth)
    assert np.abs(z).min() < 2e-3 and np.abs(z).max() > 0.9e6
    result = ix.fit("R0 + R1 || C1", ix.make_spectrum(WIDE_BAND, noisy(z, NOISE, rng)))
    # the top points see R0 in series with the capacitor: rel. error a few % (not 1e-7 Ω absolute)
    assert result.values["R0"] == pytest.approx(1e-3, rel=0.1)
    assert result.stderr["R0"] / 1e-3 < 0.05


def test_unit_weighting_on_teraohm_data_stays_finite(rng):
    """Absolute residuals of 1e10 Ω square to 1e20: no overflow. The 10 kΩ series resistance is
    invisible next to 1 TΩ under unit weighting, and the fit says so instead of inventing it."""
    truth = EXTREMES["teraohm"]
    data = ix.make_spectrum(WIDE_BAND, noisy(rc(WIDE_BAND, truth), NOISE, rng))
    result = ix.fit("R0 + R1 || C1", data, weighting="unit", init={"R1": 1e11, "C1": 1e-11})
    assert result.converged and np.isfinite(result.chi2)
    assert result.values["R1"] == pytest.approx(1e12, rel=0.01)
    assert result.values["C1"] == pytest.approx(1e-12, rel=0.01)
    assert all(np.isfinite(result.stderr[n]) for n in ("R1", "C1"))
    # (R0 is either undetermined or indistinguishable from its lower bound 0: near 10 kΩ, not on 0)
    assert any(w.startswith("R0 ") and ("not determined" in w or "cannot be told from its lower bound 0" in w) for w in result.warnings), result.warnings


def test_user_start_below_one_microfarad_is_kept(rng):
    """A start of 1 pF reaches the solver as 1 pF (it was once lifted to 1 µF by the clip that
    keeps starts inside their bounds)."""
    from impedax.fitting.parameters import ParameterTable
    from impedax.fitting.least_squares.starts import SpectrumFeatures, data_driven_guess

    circuit = ix.parse("R0 + R1 || C1")
    table = ParameterTable.build(circuit, init={"C1": 1e-12})
    z = rc(WIDE_BAND, EXTREMES["teraohm"])
    guess = data_driven_guess(circuit, table, SpectrumFeatures(WIDE_BAND, z))
    assert guess[2] == pytest.approx(1e-12, rel=1e-5)


OVERFLOW = {
    # ωL = 2π·1e7·1e308 overflows to inf: the model is non-finite at every point of the band
    "fixed value overflows": {"fixed": {"L1": 1e308}},
    # finite model (≈1e307 Ω) but its squared weighted residuals overflow
    "bounds force overflow": {"bounds": {"L1": (1e300, 1e305)}},
}


@pytest.mark.parametrize("case", list(OVERFLOW))
def test_non_finite_model_is_reported_not_returned_as_nan(case):
    f = np.geomspace(1.0, 1e7, 40)
    data = ix.make_spectrum(f, 100.0 + 2j * np.pi * f * 1e-6)  # R1 + L1 with L1 = 1 µH
    result = ix.fit("R1 + L1", data, **OVERFLOW[case])
    assert not result.converged
    assert "not finite (overflow)" in result.message and "check bounds, fixed values" in result.message
    assert any("did not converge" in w for w in result.warnings)
    assert all(np.isfinite(v) for v in result.values.values())
    free = [n for n in result.values if not result.fixed[n]]
    assert all(result.stderr[n] == np.inf for n in free)  # undetermined, not NaN
    assert not np.isnan(result.z_model).any() and not np.isnan(result.chi2) and not np.isnan(result.rms_rel)
    ds = result.to_xarray()
    assert not np.isnan(ds["value"].values).any()


def test_non_finite_model_cli_json_says_so(tmp_path, capsys):
    f = np.geomspace(1.0, 1e7, 40)
    path = tmp_path / "rl.csv"
    ix.save(ix.make_spectrum(f, 100.0 + 2j * np.pi * f * 1e-6), path)
    assert main(["fit", str(path), "--model", "R1 + L1", "--fix", "L1=1e308", "--json"]) == 0
    captured = capsys.readouterr()
    out = json.loads(captured.out)  # strict JSON: infinities become null
    assert out["converged"] is False and "overflow" in out["message"]
    assert out["params"]["R1"]["stderr"] is None and np.isfinite(out["params"]["R1"]["value"])
    assert "did not converge" in captured.err and "Traceback" not in captured.err


def test_batch_with_overflowing_fixed_value_reports_each_spectrum():
    f = np.geomspace(1.0, 1e7, 40)
    z = np.stack([r + 2j * np.pi * f * 1e-6 for r in (50.0, 100.0, 200.0)])
    data = ix.make_spectrum(f, z, dims=("trial",))
    ds = ix.fit("R1 + L1", data, fixed={"L1": 1e308}).to_xarray()
    assert not ds["converged"].values.any()
    assert not np.isnan(ds["value"].values).any()
    assert np.isinf(ds["stderr"].sel(param="R1").values).all()


def test_vectorised_batch_statistics_equal_single_fits_warnings_included(rng):
    """The batch computes uncertainties for all spectra in one stacked SVD and builds warning
    text only for flagged spectra: values, stderr and warnings must match one-by-one fits.
    Meyer's C_s/C_i pair is flagged; the fixed-C_i fits are not. Two capacitors in series
    are determined only as C_s·C_i/(C_s + C_i): batch and single fits (different solvers)
    may stop at different points of that valley, so for them the combination is compared."""
    from spectra import meyer

    f = np.geomspace(10, 1e6, 50)
    truth = {"C_s": 140e-12, "C_i": 1.7e-9, "R_sc": 130e3, "C_sc": 2.2e-9, "R_f": 500.0}
    z = np.stack([noisy(meyer(f, truth), NOISE, rng) for _ in range(3)])
    data = ix.make_spectrum(f, z, dims=("trial",), coords={"trial": [0, 1, 2]})
    text = "C_s + C_i + R_sc || C_sc + R_f"
    for fixed in (None, {"C_i": 1.7e-9}):
        batch = ix.fit(text, data, fixed=fixed)
        ds = batch.to_xarray()
        for i in range(3):
            single = ix.fit(text, data.isel(trial=i), fixed=fixed)
            values = {name: float(ds["value"].sel(param=name, trial=i)) for name in single.values}
            valley = {"C_s", "C_i"} if fixed is None else set()
            series = lambda v: v["C_s"] * v["C_i"] / (v["C_s"] + v["C_i"])  # noqa: E731
            assert series(values) == pytest.approx(series(single.values), rel=1e-5)
            for name in set(single.values) - valley:
                # beside the valley the others move with the point where it stopped: by 1e-5
                # relative here, a thousandth of their standard error
                assert abs(values[name] - single.values[name]) <= (1e-2 * single.stderr[name] if valley else 1e-5 * abs(single.values[name]))
                # in the valley the Jacobian (so the covariance) depends a little on the point
                assert float(ds["stderr"].sel(param=name, trial=i)) == pytest.approx(single.stderr[name], rel=1e-2 if valley else 1e-4, nan_ok=True)
            if valley:
                assert any("C_s, C_i are not separately determined" in w for w in batch.warnings[f"trial={i}"])
                assert any("C_s, C_i are not separately determined" in w for w in single.warnings)
            else:
                assert batch.warnings.get(f"trial={i}", ()) == single.warnings
        assert bool(batch.warnings) == (fixed is None)


@pytest.mark.parametrize(
    "kind, lower, upper, formula",
    [
        (0, 0.0, np.inf, lambda u, a, b: np.exp(u)),
        (1, 1e-9, 1e-3, lambda u, a, b: np.exp(np.log(a) + (np.log(b) - np.log(a)) / (1 + np.exp(-u)))),
        (2, 0.0, 1.0, lambda u, a, b: a + (b - a) / (1 + np.exp(-u))),
        (3, 5.0, np.inf, lambda u, a, b: a + np.exp(u)),
        (4, -np.inf, np.inf, lambda u, a, b: u),
    ],
)
def test_parameter_transform_of_each_kind(kind, lower, upper, formula):
    """The unconstrained → bounded maps of `_parameters`' docstring, one kind traced alone
    (what compiled solvers use) and selected from a kind array, against numpy formulas;
    `to_internal` inverts them."""
    from impedax.fitting.parameters import external_of_kind, to_external, to_internal

    u = np.linspace(-6.0, 6.0, 13)
    expected = formula(u, lower, upper)
    np.testing.assert_allclose(np.asarray(external_of_kind(u, lower, upper, kind)), expected, rtol=1e-14)
    np.testing.assert_allclose(np.asarray(to_external(u, np.full(u.size, lower), np.full(u.size, upper), np.full(u.size, kind))), expected, rtol=1e-14)
    np.testing.assert_allclose(to_internal(expected, lower, upper, kind), u, rtol=1e-7, atol=1e-7)


def test_a_start_far_out_on_a_warburg_time_constant_gives_a_result_not_a_linalg_error():
    # ZPlot's real spectrum (impedance.py 1.7's example file) with a Ws whose τ starts at 67 ns:
    # the fit ends with a Jacobian column of ~1e154, whose square overflowed JᵀJ into NaN and
    # NumPy's eigh raised LinAlgError from inside `fit`. Now: a result, the undetermined
    # parameters named
    data = ix.load(Path(__file__).parent / "fixtures" / "real" / "exampleDataZPlot.z")
    init = {"R0": 2.99, "CPE1.Q": 1.21e-4, "CPE1.alpha": 0.417, "R1": 1519.2, "Ws1.R": 65.75, "Ws1.tau": 6.725e-8}
    r = ix.fit("R0 + CPE1 || (R1 + Ws1)", data, init=init, n_starts=1, max_steps=2000)
    assert np.isfinite(r.rms_rel) and r.rms_rel < 0.02
    assert any("Ws1.tau" in w and "not determined" in w for w in r.warnings), r.warnings


def test_a_variance_beyond_float_range_is_inf_without_a_numpy_warning():
    """A parameter the data barely touch (its Jacobian column 1e-152 of the others: variance
    ~1e304) times a large reduced χ² (1e10, a fit that misses the data by far) overflows: the
    variance is inf, the result says so, and numpy's RuntimeWarning does not reach the user's
    terminal (a walkthrough's `impedax fit` printed one, 2026-12-02)."""
    import warnings

    from impedax.fitting.statistics import covariances

    jac = np.random.default_rng(0).standard_normal((1, 20, 3))
    jac[..., 2] *= 1e-152
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        cov, corr, _, _ = covariances(jac, np.array([1e10]), "modulus")
    assert np.isinf(cov[0, 2, 2]) and np.all(np.isfinite(np.diag(cov[0])[:2]))


def test_fit_noise_of_a_stack_is_each_spectrum_s_own():
    """`statistics.fit_noise` of many spectra in one pass: per spectrum, 1.4826·median|d|/√2 of the
    first differences d of Re and Im of the relative residuals in frequency order, × √(2N/(2N − P)),
    × |Z| (written here per row, apart from the code); a row that cannot be estimated gives 0."""
    from impedax.fitting.statistics import fit_noise

    rng = np.random.default_rng(5)
    f = np.geomspace(1e5, 0.1, 40)  # (high to low, as files list them)
    z = (10 + rng.normal(size=(6, f.size))) * np.exp(-1j * rng.uniform(0, 1, (6, f.size)))
    z_model = z * (1 + 0.01 * rng.normal(size=z.shape) + 0.01j * rng.normal(size=z.shape))
    z_model[4, 7] = np.nan
    out = fit_noise(f, z, z_model, 5)
    order = np.argsort(f)
    for i in range(6):
        rel = ((z[i] - z_model[i]) / np.abs(z[i]))[order]
        d = np.concatenate([np.diff(rel.real), np.diff(rel.imag)])
        sigma = 1.482602218505602 * np.median(np.abs(d)) / np.sqrt(2) * np.sqrt(80 / 75)
        expected = 0.0 if not np.isfinite(sigma) else sigma
        np.testing.assert_allclose(out[i], expected * np.abs(z[i]), rtol=1e-12)
    assert np.all(out[4] == 0) and np.all(out[[0, 1, 2, 3, 5]] > 0)
