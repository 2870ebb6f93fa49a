"""What a fit reports for a parameter at a bound or of a vanishing term (docs/fitting.md,
"Standard errors at a bound"): no standard error (NaN at a bound, inf for a vanishing term's;
null in the JSON, an empty cell in the CSV, "—" in the text table), NaN rows and columns in the
correlation matrix, the other parameters' errors and ``covariance`` those of the linearisation
with every free parameter free (not held at the bound), alike in single and batch fits.

SYNTHETIC spectra written here as formulas; the oracles are the Jacobian of
Z = R0 + 1/(1/R1 + Q (jω)^α) written out below, and a profile of χ² by scipy."""

import json
import math

import numpy as np
import pytest
import xarray as xr
from scipy.optimize import least_squares

import impedax as ix
from impedax.io.export import to_jsonable, write_result

MODEL = "R0 + R1 || CPE1"
F = np.geomspace(0.1, 1e5, 40)
JW = 2j * np.pi * F


def noisy(z, seed=7, rel=0.005):
    rng = np.random.default_rng(seed)
    return z * (1 + rel * (rng.normal(size=z.size) + 1j * rng.normal(size=z.size)) / np.sqrt(2))


def series_r_at_zero():
    """R1 ∥ CPE(α = 0.9) with a series resistance of −0.5 Ω, 0.5 % noise: R0 ends at its bound 0."""
    return ix.make_spectrum(F, noisy(1000.0 / (1 + 1000.0 * 2e-6 * JW**0.9) - 0.5))


def interior():
    """R0 = 50 Ω + R1 ∥ CPE: every parameter off its bounds."""
    return ix.make_spectrum(F, noisy(50.0 + 1000.0 / (1 + 1000.0 * 2e-6 * JW**0.9), seed=8))


def open_branch_exact():
    """A blocking electrode without noise, R0 + CPE: fitted with R0 + R1 ∥ CPE1, R1 runs open
    and its branch vanishes (`branches.VANISHING_SHARE`)."""
    return ix.make_spectrum(F, 50.0 + 1 / (2e-5 * JW**0.85))


def model_z(v):
    y = v["CPE1.Q"] * JW ** v["CPE1.alpha"]
    return v["R0"] + 1 / (1 / v["R1"] + y)


def jacobian(v, z_data):
    """The modulus-weighted Jacobian (2N, 4) of Re and Im of Z over (R0, R1, Q, α), by hand."""
    y = v["CPE1.Q"] * JW ** v["CPE1.alpha"]
    d = -1 / (1 / v["R1"] + y) ** 2  # dZ/dY of the parallel block
    columns = [np.ones_like(JW), d * (-1 / v["R1"] ** 2), d * JW ** v["CPE1.alpha"], d * y * np.log(JW)]
    w = 1 / np.abs(z_data)
    return np.stack([np.concatenate([(c * w).real, (c * w).imag]) for c in columns], axis=1)


def linearised_covariance(result):
    """χ²_red (JᵀJ)⁻¹ over (R0, R1, Q, α) with every parameter free: numpy alone."""
    v, z = result.values, result.z_data
    chi2 = np.sum(np.abs(model_z(v) - z) ** 2 / np.abs(z) ** 2)
    j = jacobian(v, z)
    return chi2 / (2 * F.size - 4) * np.linalg.inv(j.T @ j)


def table_row(report, name):
    return next(line for line in report.splitlines() if line.startswith(name + " "))


def test_a_parameter_at_its_bound_has_no_standard_error_anywhere(tmp_path):
    r = ix.fit(MODEL, series_r_at_zero())
    assert r.at_bound == ("R0",) and "R0 is at its lower bound 0" in r.warnings
    assert list(r.free_names) == ["R0", "R1", "CPE1.Q", "CPE1.alpha"]
    cov = linearised_covariance(r)
    sd = np.sqrt(np.diag(cov))
    # the covariance is the linearisation with every parameter free (R0's row too) ...
    np.testing.assert_allclose(r.covariance, cov, rtol=1e-6, atol=0)
    # ... R0 has no standard error; the others have the linearisation's, not held at R0 = 0
    assert math.isnan(r.stderr["R0"])
    np.testing.assert_allclose([r.stderr[n] for n in r.free_names[1:]], sd[1:], rtol=1e-6)
    assert r.linearised_stderr["R0"] == pytest.approx(sd[0], rel=1e-6)
    # correlations: none for R0 (its row and column, the diagonal too), the linearisation's for the others
    corr = r.correlation
    assert np.isnan(corr[0]).all() and np.isnan(corr[:, 0]).all()
    expected = cov / np.outer(sd, sd)
    np.testing.assert_allclose(corr[1:, 1:], expected[1:, 1:], rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(r.linearised_correlation, expected, rtol=1e-6, atol=1e-9)
    # JSON (strict: null), the CSV (an empty cell), to_xarray (NaN), the text and notebook tables
    summary = json.loads(json.dumps(to_jsonable(r.summary()), allow_nan=False))
    assert summary["params"]["R0"]["stderr"] is None and summary["at_bound"] == ["R0"]
    assert summary["params"]["R1"]["stderr"] == pytest.approx(sd[1], rel=1e-6)
    # (the linearisation's at the bound too, as curve_fit and impedance.py's conf_ give it: added 2026-12-02)
    assert summary["params"]["R0"]["linearised_stderr"] == pytest.approx(sd[0], rel=1e-6)
    rows = {row["name"]: row for row in r.to_table()}
    assert rows["R0"]["stderr"] is None and rows["R1"]["stderr"] == pytest.approx(sd[1], rel=1e-6)
    write_result(r, tmp_path / "fit.csv")
    lines = (tmp_path / "fit.csv").read_text().splitlines()
    header, r0_line = lines[0].split(","), next(line for line in lines if line.startswith("R0,")).split(",")
    assert r0_line[header.index("stderr")] == ""
    ds = r.to_xarray()
    assert math.isnan(float(ds["stderr"].sel(param="R0"))) and bool(ds["at_bound"].sel(param="R0"))
    assert float(ds["linearised_stderr"].sel(param="R0")) == pytest.approx(sd[0], rel=1e-6)
    assert np.isnan(ds["correlation"].sel(free_param="R0").values).all()
    report = r.report()
    assert table_row(report, "R0").split()[2:4] == ["—", "at"] and "at bound" in table_row(report, "R0")
    assert "nan" not in report.lower()
    assert "%" in table_row(report, "R1")
    # a derived quantity propagates the covariance: R1 alone, its linearised error
    derived = r.derive(lambda p: p["R1"])
    assert float(derived["stderr"]) == pytest.approx(sd[1], rel=1e-6)


def test_a_user_bound_gives_no_standard_error_either():
    r = ix.fit(MODEL, series_r_at_zero(), bounds={"CPE1.alpha": (0.5, 0.85)})
    assert set(r.at_bound) == {"R0", "CPE1.alpha"} and "CPE1.alpha is at its upper bound 0.85" in r.warnings
    assert math.isnan(r.stderr["CPE1.alpha"]) and r.summary()["params"]["CPE1.alpha"]["stderr"] is None
    cov = linearised_covariance(r)
    assert r.linearised_stderr["CPE1.alpha"] == pytest.approx(math.sqrt(cov[3, 3]), rel=1e-6)
    np.testing.assert_allclose([r.stderr["R1"], r.stderr["CPE1.Q"]], np.sqrt(np.diag(cov))[1:3], rtol=1e-6)
    assert np.isnan(r.correlation[3]).all() and np.isnan(r.correlation[:, 0]).all()
    assert np.isfinite(r.correlation[1:3, 1:3]).all()
    assert "at bound" in table_row(r.report(), "CPE1.alpha")


def test_a_vanishing_term_s_parameter_has_an_infinite_error_and_no_correlations():
    r = ix.fit(MODEL, open_branch_exact())
    assert r.at_bound == ("R1",) and "R1 is at its upper bound ∞" in r.warnings
    assert r.stderr["R1"] == math.inf and r.linearised_stderr["R1"] == math.inf
    assert r.summary()["params"]["R1"]["stderr"] is None and {row["name"]: row for row in r.to_table()}["R1"]["stderr"] is None
    i = list(r.free_names).index("R1")
    assert np.isnan(r.correlation[i]).all() and np.isnan(r.correlation[:, i]).all()
    others = [j for j in range(4) if j != i]
    assert np.isfinite(r.correlation[np.ix_(others, others)]).all()
    # the others' correlations are the linearisation's (R1's column is next to nothing: its
    # branch carries < 1e-6 of the current; correlations do not depend on χ², rounding here)
    cov = linearised_covariance(r)
    sd = np.sqrt(np.diag(cov))
    np.testing.assert_allclose(r.correlation[np.ix_(others, others)], (cov / np.outer(sd, sd))[np.ix_(others, others)], atol=1e-4)


def test_batch_fits_report_as_single_fits():
    data = [series_r_at_zero(), interior(), open_branch_exact()]
    batch = ix.fit(MODEL, xr.concat(data, dim="trial"))
    ds = batch.dataset
    names = [str(p) for p in ds["param"].values]
    table = batch.to_table()
    for i, d in enumerate(data):
        single = ix.fit(MODEL, d)
        at_bound = tuple(n for n in single.free_names if bool(ds["at_bound"].sel(param=n)[i]))
        assert at_bound == single.at_bound, i
        for var, source in (("stderr", single.stderr), ("linearised_stderr", single.linearised_stderr)):
            got = ds[var].isel(trial=i).values
            want = np.array([source[n] for n in names])
            np.testing.assert_array_equal(np.isnan(got), np.isnan(want), err_msg=f"{var} {i}")
            np.testing.assert_array_equal(np.isinf(got), np.isinf(want), err_msg=f"{var} {i}")
            if i < 2:  # (exact data: errors of rounding's χ², which differs between the two)
                np.testing.assert_allclose(got[np.isfinite(want)], want[np.isfinite(want)], rtol=1e-4, err_msg=f"{var} {i}")
        rows = {row["name"]: row for row in table if row["trial"] == i}
        for n in names:
            assert (rows[n]["stderr"] is None) == (single.to_table()[names.index(n)]["stderr"] is None), (i, n)
    assert math.isnan(float(ds["stderr"].sel(param="R0")[0])) and np.isfinite(ds["stderr"].isel(trial=1)).all()
    assert float(ds["stderr"].sel(param="R1")[2]) == math.inf


def test_the_others_are_not_held_at_the_bound():
    """R0 + R1 ∥ C1 measured only below 30 Hz, where the arc has not closed: R0 (truly 20 Ω)
    trades against R1, and the fit stops at R0 = 0 with R1 = 1019 Ω. Held at R0 = 0, R1 would get
    the error of a fit with R0 fixed there, 1.7 Ω; the data allow R1 down to 854 Ω within one
    standard deviation (χ² profiled by scipy with R0 ≥ 0 free: Δχ² = χ²_red). The others keep
    the linearisation's errors (R1: 222 Ω), which reach past that."""
    f = np.geomspace(0.1, 30, 30)
    jw = 2j * np.pi * f
    z = 20.0 + 1000.0 / (1 + jw * 1000.0 * 1e-6)
    rng = np.random.default_rng(0)
    z = z + 0.01 * np.abs(z) * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape))
    r = ix.fit("R0 + R1 || C1", ix.make_spectrum(f, z))
    assert r.at_bound == ("R0",) and math.isnan(r.stderr["R0"])
    v = r.values

    def residual(p, r1):
        d = (p[0] + r1 / (1 + jw * r1 * p[1]) - z) / np.abs(z)
        return np.concatenate([d.real, d.imag])

    def rise(r1):  # χ² at R1 with R0 ≥ 0 and C1 refitted, above the fit's, in units of χ²_red
        chi2 = 2 * least_squares(residual, [1.0, v["C1"]], args=(r1,), bounds=([0, 0], [np.inf, np.inf]), x_scale=[1.0, v["C1"]]).cost
        return (chi2 - r.chi2) / r.chi2_red

    # R1's error as a fit held at R0 = 0 would give it (modulus weighting; numpy alone)
    columns = [1 / (1 + jw * v["R1"] * v["C1"]) ** 2, -jw * v["R1"] ** 2 / (1 + jw * v["R1"] * v["C1"]) ** 2]
    j = np.stack([np.concatenate([(c / np.abs(z)).real, (c / np.abs(z)).imag]) for c in columns], axis=1)
    held = math.sqrt((r.chi2 / (2 * f.size - 3) * np.linalg.inv(j.T @ j))[0, 0])
    # five of those down, the data are still within one standard deviation: holding understates R1's error
    assert rise(v["R1"] - 5 * held) < 1.0
    # ... the reported one reaches past the profile's one standard deviation
    assert rise(v["R1"] - r.stderr["R1"]) > 1.0 and r.stderr["R1"] > 20 * held


def test_global_fits_report_as_single_fits():
    """A shared series resistance at its bound 0 (three spectra of R1 ∥ CPE with −0.5 Ω in
    series): no standard error for it, shared or per spectrum, NaN correlations, the
    linearisation's kept in ``linearised_stderr``, "at bound" in the report."""
    z = np.stack([noisy(1000.0 / (1 + 1000.0 * 2e-6 * JW**0.9) - 0.5, seed=s) for s in (11, 12, 13)])
    result = ix.fit(MODEL, ix.make_spectrum(F, z, dims=("trial",)), shared=["R0"], over="trial")
    ds = result.dataset
    assert math.isnan(float(ds["shared_stderr"].sel(shared_param="R0")))
    assert result.summary()["shared"]["R0"]["stderr"] is None
    assert json.loads(json.dumps(to_jsonable(result.summary())))["shared"]["R0"]["stderr"] is None
    assert np.isnan(ds["stderr"].sel(param="R0").values).all()
    assert np.isfinite(ds["linearised_stderr"].sel(param="R0").values).all()
    assert np.isfinite(ds["stderr"].sel(param="R1").values).all()
    corr = ds["correlation"].values  # (trial, free, free); R0 is the first free parameter
    assert np.isnan(corr[:, 0, :]).all() and np.isnan(corr[:, :, 0]).all() and np.isfinite(corr[:, 1:, 1:]).all()
    line = next(l for l in result.report().splitlines() if l.startswith("R0 ") and "at bound" in l)
    assert "nan" not in line


def test_a_derived_quantity_says_when_it_rests_on_a_parameter_at_its_bound():
    """R0 at its bound 0: R0 + R1 depends on it (the note says so), R1 alone does not."""
    fit = ix.fit(MODEL, series_r_at_zero())
    assert "R0" in fit.at_bound
    total = fit.derive(lambda p: p["R0"] + p["R1"])
    assert total.attrs["at_bound"] == "R0" and "ignores the bound" in total.attrs["note"]
    assert "at_bound" not in fit.derive(lambda p: p["R1"]).attrs


def test_derive_names_a_parameter_the_model_has_not():
    fit = ix.fit(MODEL, interior())
    with pytest.raises(ix.ParameterError, match=r"derive: fn asked for: unknown parameter 'R_1'.*did you mean R1"):
        fit.derive(lambda p: p["R_1"] * 2)


GAMRY = __import__("pathlib").Path(__file__).parent / "fixtures" / "real" / "exampleDataGamry.DTA"


def test_no_correlation_warning_names_a_parameter_at_its_bound():
    # Gamry's real example with R0 + L0 + R1 ∥ CPE1: R0 ends at its bound 0, where the
    # linearisation correlates it with R1 (r ≈ -0.995); the result gives R0 no standard error
    # and no correlations, so no warning may speak of one
    r = ix.fit("R0 + L0 + R1 || CPE1", ix.load(GAMRY))
    assert {"R0", "L0"} <= set(r.at_bound), r.report()
    k = r.free_names.index("R0")
    assert np.all(np.isnan(r.correlation[k]))
    at = set(r.at_bound)
    assert not [w for w in r.warnings if "strongly correlated" in w and any(f"{n} and " in w or f"and {n} are" in w for n in at)], r.warnings


def test_a_cpe_at_its_bound_is_not_called_well_determined():
    # the same file, R0 fixed at 1.6 kΩ, R0 + R1 ∥ CPE1 + W1: CPE1.alpha at its bound 1 and
    # CPE1.Q at 73 % relative error; no note may call them well determined
    r = ix.fit("R0 + R1 || CPE1 + W1", ix.load(GAMRY), fixed={"R0": 1600.0})
    assert "CPE1.alpha" in r.at_bound, r.report()
    assert not [w for w in r.warnings if "well determined" in w or "CPE1.Q and CPE1.alpha" in w], r.warnings


def test_the_cpe_correlation_note_calls_q_and_alpha_well_determined_only_when_they_are():
    from impedax.fitting.least_squares.result import WELL_DETERMINED, correlated_note

    well = correlated_note("CPE1.Q", "CPE1.alpha", -0.995, (0.02, 0.004))
    assert well.endswith("both are still well determined (relative errors 2 % and 0.4 %))"), well
    loose = correlated_note("CPE1.Q", "CPE1.alpha", -0.992, (0.73, 0.05))
    assert "well determined" not in loose and "(73 % and 5 %)" in loose, loose
    assert "well determined" not in correlated_note("CPE1.Q", "CPE1.alpha", -0.99, (WELL_DETERMINED * 1.01, 0.01))
    assert "well determined" not in correlated_note("CPE1.Q", "CPE1.alpha", -0.99, (math.nan, 0.01))


def test_the_batch_plot_draws_no_error_bar_for_a_value_at_its_bound():
    # R0 at its bound 0 in trial 0, off it in trial 1: text and JSON give trial 0's R0 no
    # standard error, so the plot draws it without a bar, as an "at bound" marker; trial 1's
    # bar is its stderr, on both sides
    import matplotlib

    matplotlib.use("Agg")
    batch = ix.fit(MODEL, xr.concat([series_r_at_zero(), interior()], dim="trial"))
    ds = batch.dataset
    assert ds["at_bound"].sel(param="R0").values.tolist() == [True, False]
    assert float(ds["linearised_stderr"].sel(param="R0")[0]) > 0  # (the bar drawn before)
    fig = batch.plot()
    (panel,) = [ax for ax in fig.axes if ax.get_title().startswith("R0")]
    segments = [s for c in panel.collections for s in c.get_segments()]
    assert [s[0][0] for s in segments] == [1.0], segments
    r0, err = batch.values("R0").values[1], float(ds["stderr"].sel(param="R0")[1])
    np.testing.assert_allclose([segments[0][0][1], segments[0][1][1]], [r0 - err, r0 + err], rtol=1e-9)
    (marked,) = [line for line in panel.get_lines() if line.get_label() == "at bound (no stderr)"]
    assert marked.get_xdata().tolist() == [0]
    plt = __import__("matplotlib.pyplot").pyplot
    plt.close(fig)


def test_a_value_within_two_standard_errors_of_its_bound_says_its_interval_is_not_symmetric():
    """SYNTHETIC R0 + R1 ∥ CPE1 with R0 = 1 mΩ beside 1 kΩ (Q 1e-5, α 0.85), 0.1 % complex noise,
    seed 3: R0 = 0.0016 ± 0.00094 Ω, off its bound 0 but within 2σ of it, so R0 ± 2σ reaches
    below 0 where no resistance lies; the note says so (single and batch alike) and names the
    posterior. With R0 = 50 Ω, far from 0, no such note."""
    f = np.logspace(-2, 5, 50)
    w = 2 * np.pi * f

    def spectrum(r0, seed):
        rng = np.random.default_rng(seed)
        z = r0 + 1000 / (1 + 1000 * 1e-5 * (1j * w) ** 0.85)
        return z * (1 + 0.001 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))

    z = spectrum(1e-3, 3)
    single = ix.fit("R0 + R1 || CPE1", ix.make_spectrum(f, z))
    value, error = single.values["R0"], single.stderr["R0"]
    assert 0 < value < 2 * error and 1e-4 < error < 1e-3  # (off 0, within 2σ of it; the error's 2 digits are 0.1 and 0.01 mΩ)
    (note,) = [w for w in single.warnings if "not symmetric" in w]
    assert note.startswith(f"R0 = {value * 1e3:.2f} ± {error * 1e3:.2f} mΩ lies within 2 standard errors of its lower bound 0") and "impedax sample" in note
    batch = ix.fit("R0 + R1 || CPE1", ix.make_spectrum(f, np.stack([z, spectrum(50.0, 3)]), dims=("copy",)))
    assert note in batch.warnings["copy=0"] and not any("not symmetric" in w for w in batch.warnings.get("copy=1", ()))


def test_a_narrow_valley_between_two_elements_points_to_the_posterior():
    """The note of a correlation (|r| > 0.99) between parameters of different elements adds that
    the linearised ± may understate their spread (SYNTHETIC two-arc fits, R1 and R2 at r =
    −0.999, covered the truth at 2σ in 70 % of copies); one element's pair keeps its own reason."""
    from impedax.fitting.least_squares.result import correlated_note

    assert correlated_note("R1", "R2", -0.999).endswith("the data barely tell them apart; in so narrow a valley the linearised ± may understate their spread: impedax sample gives the posterior's")
    assert "narrow a valley" not in correlated_note("CPE1.Q", "CPE1.alpha", -0.995, (0.01, 0.02))


def test_a_value_within_1e4_of_its_upper_bound_is_said_to_be_near_that_bound():
    """`near_bound_notes` names the side `bound_sides` found: α = 1 − 8.4e-15 ± 1.5e-15 is within
    1e-4 of its upper bound 1, but more than 2 standard errors away from it, and was said to lie
    "within 2 standard errors of its lower bound 0" (REAL data.ods, 2026-12-03). Values by hand."""
    from impedax.fitting.least_squares.result import near_bound_notes
    from impedax.fitting.parameters import ParameterTable

    table = ParameterTable.build(ix.parse("R0 + R1 || CPE1"))
    assert list(table.names) == ["R0", "R1", "CPE1.Q", "CPE1.alpha"]
    values = np.array([[10.0, 100.0, 1e-5, 1 - 8.4e-15]])
    stderr = np.array([[0.1, 1.0, 1e-7, 1.5e-15]])
    (note,) = [n for _, n in near_bound_notes(table, values, stderr, np.zeros((1, 4), np.int8))]
    # (said as its distance from the bound, rounded to its error: until 2026-12-06 "CPE1.alpha =
    # 0.9999999999999916 ± 0.0000000000000015 lies 8.4e-15 from its upper bound 1: the ± is not
    # symmetric there", digits no one reads and an asymmetry the ± never reaches)
    assert note == "CPE1.alpha lies (8.4 ± 1.5)e-15 below its upper bound 1, on it to 1 part in 10⁴ or better (CPE1 with alpha = 1 is a capacitor: the model with C1 in its place may be enough)", note
    stderr[0, 3] = 1e-14  # (now within 2 standard errors: the words of before)
    (note,) = [n for _, n in near_bound_notes(table, values, stderr, np.zeros((1, 4), np.int8))]
    assert note.startswith("CPE1.alpha = 0.999999999999992 ± 0.000000000000010 lies within 2 standard errors of its upper bound 1:"), note


def test_a_near_bound_note_writes_its_value_with_the_reports_si_prefix():
    """REAL Autolab spectrum (tests/fixtures/real/exampleDataAutolab.txt) fitted with
    R0 + (R1 + W1) ∥ CPE1: W1.sigma = 0.002751 ± 0.00139 Ω s^-1/2 lies within 2 standard errors
    of 0. The note wrote "W1.sigma = 0.00275 ± 0.0014 Ω s^-1/2" where the rest of impedax writes
    mΩ s^-1/2; by hand (GUM: the error to 2 digits, the value to its last digit, in mΩ):
    1.39 → 1.4, 2.751 → 2.8."""
    from pathlib import Path

    data = ix.load(Path(__file__).resolve().parent / "fixtures" / "real" / "exampleDataAutolab.txt")
    fit = ix.fit("R0 + (R1 + W1) || CPE1", data)
    assert math.isclose(fit.values["W1.sigma"], 0.002751, rel_tol=0.01) and math.isclose(fit.stderr["W1.sigma"], 0.00139, rel_tol=0.02)
    (note,) = [w for w in fit.warnings if "not symmetric" in w]
    assert note.startswith("W1.sigma = 2.8 ± 1.4 mΩ s^-1/2 lies within 2 standard errors of its lower bound 0:"), note


@pytest.mark.parametrize("kwargs, expected", [
    (dict(value=6.77e-4, stderr=1e-3, unit="Ohm s^-1/2", on=True), "W1.sigma = 677 µΩ s^-1/2 runs to its lower bound 0"),
    (dict(value=6.61e7, stderr=2.3e27, unit="Ohm s^-1/2"), "W1.sigma = 66.1 MΩ s^-1/2 cannot be told from its lower bound 0 (linearised standard error 2.3e+27 Ω s^-1/2, bounds ignored)"),
    (dict(value=7.96e7, stderr=1.3e11, unit="Ohm"), "R1 = 79.6 MΩ cannot be told from its lower bound 0 (linearised standard error 130 GΩ, bounds ignored)"),
])
def test_a_bound_note_writes_value_and_error_with_si_prefixes(kwargs, expected):
    """`bound_note` writes its numbers as the fit report does (SI prefix on the leading unit;
    2.3e27 is beyond the prefixes and stays as it is). Prefixes by hand: 6.77e-4 = 677e-6,
    6.61e7 = 66.1e6, 1.3e11 = 130e9."""
    from impedax.fitting.least_squares.result import bound_note

    assert bound_note(expected.split(" = ")[0], 0.0, "lower", **kwargs).startswith(expected)


def test_a_bound_note_writes_the_bound_as_the_quantity_the_user_typed():
    """REAL Autolab spectrum (tests/fixtures/real/exampleDataAutolab.txt) fitted with R0 + R1 ∥ C1
    and ``--bound R1=1m:10m``: R1 runs to the 10 mΩ the user typed, and the note said "R1 is at its
    upper bound 0.01" (``:g``, no unit) where the value beside it is written in mΩ. Oracle: the
    text the user typed, 10m, in Ω with its prefix."""
    from pathlib import Path

    data = ix.load(Path(__file__).resolve().parent / "fixtures" / "real" / "exampleDataAutolab.txt")
    fit = ix.fit("R0 + R1 || C1", data, bounds={"R1": (1e-3, 1e-2)})
    assert fit.values["R1"] == pytest.approx(1e-2, rel=1e-6) and fit.at_bound == ("R1",)
    assert "R1 is at its upper bound 10 mΩ" in fit.warnings, fit.warnings


def test_every_bound_note_writes_its_bound_with_unit_and_si_prefix():
    """The least-squares notes on a bound (on it, off it, chi² falling inward, a user's
    constraint), by hand: a bound 1e-5 F s^(α-1) is 10 µF s^(α-1), 99999 Ω stays 99.999 kΩ (not
    the 100 kΩ of three digits, a bound the user did not give), 0 and 1 of a CPE's α as they are."""
    from impedax.data import format_bound
    from impedax.fitting.least_squares.constraints import constraint_words
    from impedax.fitting.least_squares.result import bound_note, inward_message, near_bound_notes
    from impedax.fitting.parameters import ParameterTable

    assert [format_bound(v, u) for v, u in ((1e4, "Ohm"), (99999.0, "Ohm"), (1e-5, "F s^(alpha-1)"), (0.0, "Ohm"), (1.0, "1"), (math.inf, "Ohm"))] == ["10 kΩ", "99.999 kΩ", "10 µF s^(α-1)", "0", "1", "∞"]
    assert bound_note("CPE1.Q", 1e-5, "upper", unit="F s^(alpha-1)") == "CPE1.Q is at its upper bound 10 µF s^(α-1)"
    assert bound_note("R1", 1e4, "upper", value=9.9e3, stderr=50.0, unit="Ohm").startswith("R1 = 9.9 kΩ cannot be told from its upper bound 10 kΩ ")
    table = ParameterTable.build(ix.parse("R0 + R1 || CPE1"), bounds={"R1": (10.0, 99999.0)})
    assert inward_message(table, np.array([0, 1, 0, 0])).startswith("stopped with R1 at its upper bound 99.999 kΩ while")
    values = np.array([[10.0, 99998.0, 1e-5, 0.8]])
    stderr = np.array([[0.1, 1000.0, 1e-7, 0.01]])
    (note,) = [n for _, n in near_bound_notes(table, values, stderr, np.zeros((1, 4), np.int8))]
    assert note.startswith("R1 = 100.0 ± 1.0 kΩ lies within 2 standard errors of its upper bound 99.999 kΩ:"), note
    assert constraint_words([("R0", "fixed", 0.04), ("R1", "upper", 1e4)], {"R0": "Ohm", "R1": "Ohm"}) == "R0 fixed at 40 mΩ (your fixed=, --fix) and R1 on your upper bound 10 kΩ (bounds=)"


def test_an_exponent_a_rounding_below_1_reads_as_at_its_bound():
    """REAL file tests/fixtures/real/data.ods (sheet 1: an exact spectrum of R0 = 100 Ω, R1 ∥
    CPE1 with α = 1, R2 ∥ CPE2; impedance.py's test data) fitted with R0 + R1 ∥ CPE1 + R2 ∥ CPE2
    + W1 ends at rms_rel 1e-13 % with CPE1.alpha = 1 − 8.4e-15 ± 1.6e-15. The note wrote
    "0.9999999999999916 ± 0.0000000000000016 lies 8.4e-15 from its upper bound 1: the ± is not
    symmetric there": it is the bound to 1 part in 10¹⁴, which the file's own α = 1 says. Oracle:
    the distance 1 − α of the fit's own numbers, rounded by hand to its error's two digits."""
    from pathlib import Path

    data = ix.load(Path(__file__).resolve().parent / "fixtures" / "real" / "data.ods").isel(sheet=0)
    fit = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + W1", data)
    distance, error = 1 - fit.values["CPE1.alpha"], fit.stderr["CPE1.alpha"]
    assert 0 < distance < 1e-13 and 0 < error < distance / 2
    (note,) = [w for w in fit.warnings if w.startswith("CPE1.alpha")]
    assert note.startswith(f"CPE1.alpha lies ({distance * 1e15:.1f} ± {error * 1e15:.1f})e-15 below its upper bound 1, on it to 1 part in 10⁴ or better (CPE1 with alpha = 1 is a capacitor"), note


def test_a_fixed_value_reads_in_the_tables_as_the_user_gave_it():
    """SYNTHETIC R0 + R1 ∥ C1 with R0 fixed at 10.123456 Ω (``--fix R0=10.123456``): the fit's,
    a batch's and the sampler's tables wrote it to 5 digits, "10.123 (fixed)", a value the user
    never gave beside the mark that it was not fitted. A fixed value has no error to round to:
    it is written as given (`data.exact_number`, as the LaTeX table has it). Oracle: the text
    typed."""
    f = np.geomspace(1, 1e5, 20)
    z = 10.123456 + 2000 / (1 + 1j * 2 * np.pi * f * 2000 * 1e-7)
    z = z * (1 + 0.01 * np.random.default_rng(0).normal(size=f.size))
    single = ix.fit("R0 + R1 || C1", ix.make_spectrum(f, z), fixed={"R0": 10.123456})
    (row,) = [line for line in single.report().splitlines() if line.startswith("R0 ")]
    assert row.split() == ["R0", "10.123456", "(fixed)", "Ω"], row
    batch = ix.fit("R0 + R1 || C1", ix.make_spectrum(f, np.stack([z, z]), dims=("copy",)), fixed={"R0": 10.123456})
    (row,) = [line for line in batch.report().splitlines() if line.startswith("R0 ")]
    assert row.split()[1:3] == ["10.123456", "(fixed)"], row
    post = ix.sample("R0 + R1 || C1", ix.make_spectrum(f, z), fixed={"R0": 10.123456}, steps=40, progress=False)
    (row,) = [line for line in post.report().splitlines() if line.startswith("R0 ")]
    assert row.split() == ["R0", "10.123456", "(fixed)", "Ω"], row
