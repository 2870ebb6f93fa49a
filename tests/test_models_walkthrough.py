"""A user's walkthrough of the surface-haptics models (`impedax.models`): the gap functions read
their remainder from the parameter names, take the DataArrays `trial_mean` returns, check
lengths; Meyer's functions read their variant; variants and branches in any case; a saved gap
analysis is named by `impedax.load`; a MeyerModel is refused by `write_result` with what to do;
the gap report and figure scale their force unit. Oracles: the node equations and eq 1 written
with numpy (docs/physics.md), the thesis circuit solved with numpy."""

from __future__ import annotations

import re

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.errors import DataError, ParameterError
from impedax.data import format_frequency, format_quantity
from impedax.models import meyer, sirin

E0 = 8.8541878128e-12
EPS_AIR = 1.00059
AREA = 130e-6
F61 = np.geomspace(1.0, 1e6, 61)
CPE_PARAMS = {"R_EP": 1e8, "CPE_EP.Q": 4e-9, "CPE_EP.alpha": 0.3, "C_gap": 413e-12}
C_PARAMS = {"R_EP": 2e7, "C_EP": 50e-12, "C_gap": 413e-12}


def rcpe(f, r_inf, r, q, a):
    return r_inf + r / (1 + r * q * (2j * np.pi * f) ** a)


SKIN = rcpe(F61, 800.0, 2.0e7, 1.049e-8, 0.90)
TS = rcpe(F61, 90.0, 1.7e5, 1.184e-9, 0.92)


def remainder_numpy(params, f=F61):
    """Z_R of R_EP || (C_EP or CPE_EP) || C_gap written out."""
    w = 2 * np.pi * f
    y_ep = 1j * w * params["C_EP"] if "C_EP" in params else params["CPE_EP.Q"] * (1j * w) ** params["CPE_EP.alpha"]
    return 1 / (1 / params["R_EP"] + y_ep + 1j * w * params["C_gap"])


def force_numpy(params, skin=SKIN, ts=TS, f=F61, v0=75.0):
    """Sirin eq 1 at the amplitude with the gap's permittivity, F = ½ ε0 ε_gap A |ΔV|²/u², with
    the node equations (the voltage across the parallel remainder is ΔV = V0 Z_R/(Z_TS + Z_R + Z_skin))."""
    z_r = remainder_numpy(params, f)
    dv = v0 * z_r / (ts + z_r + skin)
    u = E0 * EPS_AIR * AREA / params["C_gap"]
    return 0.5 * E0 * EPS_AIR * AREA * np.abs(dv) ** 2 / u**2


# --- 1. the remainder is read from the parameter names -----------------------------------------


@pytest.mark.parametrize("params", [CPE_PARAMS, C_PARAMS], ids=["CPE", "C"])
def test_gap_force_reads_the_branch_from_the_names(params):
    got = np.asarray(sirin.gap_force_peak(params, F61, SKIN, TS))
    np.testing.assert_allclose(got, force_numpy(params), rtol=1e-10)
    np.testing.assert_allclose(np.asarray(sirin.gap_force_time_average(params, F61, SKIN, TS)), force_numpy(params) / 2, rtol=1e-10)
    np.testing.assert_allclose(np.asarray(sirin.remainder_impedance(params, F61)), remainder_numpy(params), rtol=1e-10)


def test_docs_vmap_recipe_runs_on_cpe_draws():
    """docs/models.md: `jax.vmap(lambda p: gap_force_peak(p, freq, z_skin, z_ts))(draws)` on
    draws of the default (CPE) analysis, under jit."""
    rng = np.random.default_rng(3)
    draws = {k: jnp.asarray(v * np.exp(rng.normal(0, 0.05, 8))) for k, v in CPE_PARAMS.items()}
    batched = np.asarray(jax.jit(jax.vmap(lambda p: sirin.gap_force_peak(p, F61, SKIN, TS)))(draws))
    assert batched.shape == (8, 61)
    np.testing.assert_allclose(batched[5], force_numpy({k: float(v[5]) for k, v in draws.items()}), rtol=1e-9)


def test_explicit_branch_still_works_in_any_case():
    for ep in ("CPE", "cpe", "Cpe"):
        np.testing.assert_allclose(np.asarray(sirin.gap_force_peak(CPE_PARAMS, F61, SKIN, TS, ep=ep)), force_numpy(CPE_PARAMS), rtol=1e-10)
    assert str(sirin.remainder_circuit("c")) == "R_EP || C_EP || C_gap"
    assert str(sirin.remainder_circuit()) == "R_EP || CPE_EP || C_gap"  # the default of gap_analysis and impedax gap
    assert str(sirin.remainder_circuit("none")) == str(sirin.remainder_circuit(None)) == "C_gap"
    no_ep = np.asarray(sirin.gap_force_peak(CPE_PARAMS, F61, SKIN, TS, ep=None))
    np.testing.assert_allclose(no_ep, force_numpy({"R_EP": 1e300, "C_EP": 0.0, "C_gap": 413e-12}), rtol=1e-9)


def test_names_without_a_branch_list_both_variants():
    with pytest.raises(ParameterError) as info:
        sirin.gap_force_peak({"R_EP": 1e8, "C_gap": 4e-10}, F61, SKIN, TS)
    message = str(info.value)
    assert "R_EP, CPE_EP.Q, CPE_EP.alpha, C_gap (ep='CPE')" in message and "R_EP, C_EP, C_gap (ep='C')" in message
    with pytest.raises(ParameterError, match="both C_EP and CPE_EP"):
        sirin.gap_voltage({**CPE_PARAMS, "C_EP": 1e-12}, F61, SKIN, TS)


@pytest.mark.parametrize("params", [{"R_EP": 1e8, "CPE_EP.Q": 4e-9, "CPE_EP.alpha": 0.3, "u": 2.8e-6}, {"R_EP": 1e8, "u": 2.8e-6}], ids=["branch", "no-branch"])
def test_u_instead_of_c_gap_points_to_circuit_samples(params):
    with pytest.raises(ParameterError, match=re.escape("pass post.circuit_samples(), which holds C_gap")):
        sirin.gap_force_peak(params, F61, SKIN, TS)


# --- 2. DataArrays at the boundary ----------------------------------------------------------------


def test_dataarrays_from_trial_mean_are_taken_as_arrays():
    skin = ix.make_spectrum(F61, np.stack([SKIN * 0.99, SKIN * 1.01]), dims=("trial",))
    ts = ix.make_spectrum(F61, np.stack([TS * 0.98, TS * 1.02]), dims=("trial",))
    z_skin, z_ts = sirin.trial_mean(skin)["Z"], sirin.trial_mean(ts)["Z"]
    assert isinstance(z_skin, xr.DataArray)
    v = sirin.gap_voltage(CPE_PARAMS, z_skin["frequency"], z_skin, z_ts)
    assert not isinstance(v, xr.DataArray)
    z_r = remainder_numpy(CPE_PARAMS)
    np.testing.assert_allclose(np.asarray(v), 75.0 * z_r / (TS + z_r + SKIN), rtol=1e-10)
    np.testing.assert_allclose(np.asarray(sirin.gap_force_peak(CPE_PARAMS, z_skin["frequency"], z_skin, z_ts)), force_numpy(CPE_PARAMS), rtol=1e-10)
    with pytest.raises(ParameterError, match=re.escape("z_skin is a Dataset; pass its complex impedance")):
        sirin.gap_voltage(CPE_PARAMS, F61, sirin.trial_mean(skin), z_ts)


# --- 3. lengths are checked ------------------------------------------------------------------------


def test_mismatched_lengths_are_named():
    with pytest.raises(ParameterError, match="z_skin has 10 values, freq has 61"):
        sirin.gap_force_peak(CPE_PARAMS, F61, np.ones(10) * 1e3, np.ones(61) * 1e3, ep="CPE")
    with pytest.raises(ParameterError, match="z_ts has 60 values, freq has 61"):
        sirin.gap_voltage(CPE_PARAMS, F61, SKIN, TS[:60])
    # one value for every frequency broadcasts, as before
    np.testing.assert_allclose(np.asarray(sirin.gap_force_peak(CPE_PARAMS, F61, 1e3, 1e3)), force_numpy(CPE_PARAMS, skin=1e3, ts=1e3), rtol=1e-10)


# --- 6, 7. Meyer: the variant from the names, in any case ------------------------------------------


def meyer_force_numpy(params, f, v_a=140.0, area=np.pi * 4e-3**2):
    """Time-averaged force of thesis eq 3.6 with the circuit solved in numpy (V_F across C_i and
    the SC block, Q_f = I_Rsc/(jω)); C_sc of the prefactor Q ω^(α−1) for the CPE."""
    w = 2 * np.pi * f
    if "C_sc" in params:
        y_c, c_sc = 1j * w * params["C_sc"], params["C_sc"]
    else:
        y_c, c_sc = params["CPE_sc.Q"] * (1j * w) ** params["CPE_sc.alpha"], params["CPE_sc.Q"] * w ** (params["CPE_sc.alpha"] - 1)
    z_sc = 1 / (1 / params["R_sc"] + y_c)
    z_ci = 1 / (1j * w * params["C_i"])
    i = v_a / (1 / (1j * w * params["C_s"]) + z_ci + z_sc + params["R_f"])
    v_f = i * (z_ci + z_sc)
    q_f = (i * z_sc / params["R_sc"]) / (1j * w)
    series = params["C_i"] * c_sc / (params["C_i"] + c_sc)
    return series**2 / (2 * area * E0) * 0.5 * (np.abs(v_f) ** 2 - np.abs(q_f) ** 2 / params["C_i"] ** 2)


def test_meyer_reads_the_variant_from_the_names():
    f = np.array([100.0, 1e3, 37e3])
    for variant in ("rc", "cpe"):
        params = meyer.meyer_model(variant).params
        np.testing.assert_allclose(np.asarray(meyer.force_time_average(params, f)), meyer_force_numpy(params, f), rtol=1e-9)
    with pytest.raises(ParameterError, match=re.escape("pass variant='cpe'")):
        meyer.force_time_average(meyer.meyer_model("cpe").params, f, variant="rc")


def test_variant_and_branch_in_any_case_keep_the_canonical_spelling():
    model = meyer.meyer_model("CPE")
    assert model.variant == "cpe" and "CPE_sc.Q" in model.params
    assert meyer.meyer_model("RC").params == meyer.meyer_model("rc").params
    np.testing.assert_allclose(np.asarray(meyer.finger_voltage(model.params, [1e3], variant="Cpe")), np.asarray(meyer.finger_voltage(model.params, [1e3])), rtol=1e-14)


# --- 5. a MeyerModel is no result to write ---------------------------------------------------------


def test_write_result_of_a_meyer_model_says_what_to_save(tmp_path):
    with pytest.raises(ParameterError, match=re.escape("save m.to_xarray(freq) with impedax.io.write_netcdf")):
        ix.write_result(meyer.meyer_model("cpe"), tmp_path / "m.nc")
    assert list(tmp_path.iterdir()) == []


# --- 4, 8, 9, 10. the gap analysis ------------------------------------------------------------------


@pytest.fixture(scope="module")
def stationary():
    """The shipped SYNTHETIC example's stationary total, pooled, a short run (forces of N)."""
    from impedax.models import example_spectra, gap_analysis  # (10: exported from impedax.models)

    s = example_spectra()
    parts = s["total_stationary"], s["skin"], s["touchscreen"]
    return gap_analysis(*parts, method="pooled", steps=40, progress=False, ep="cpe"), parts


def test_gap_analysis_is_exported_and_normalises_the_branch(stationary):
    from impedax.models import gap_analysis
    from impedax.models.gap import gap_analysis as direct

    assert gap_analysis is direct
    result, _ = stationary
    assert result.ep == "CPE" and result.edl_fit.model == "R_EP || CPE_EP || C_gap"


def test_steps_lower_limit_is_one_constant(capsys):
    from impedax.arguments import GAP_MIN_STEPS
    from impedax.cli import main
    from impedax.models import example_spectra, gap_analysis

    s = example_spectra()
    with pytest.raises(ParameterError, match=f"steps must be at least {GAP_MIN_STEPS}, got {GAP_MIN_STEPS - 1}"):
        gap_analysis(s["total_sliding"], s["skin"], s["touchscreen"], method="pooled", steps=GAP_MIN_STEPS - 1, progress=False)
    with pytest.raises(SystemExit):
        main(["gap", "--help"])
    assert f"at least {GAP_MIN_STEPS} (default auto)" in " ".join(capsys.readouterr().out.split())


def test_saved_gap_analysis_is_named_by_load(stationary, tmp_path):
    result, _ = stationary
    path = tmp_path / "gap.nc"
    ix.write_result(result, path)
    with pytest.raises(DataError, match=re.escape("this file holds a gap analysis result (impedax gap), not a spectrum; read it with impedax.io.read_netcdf")):
        ix.load(path)
    back = ix.io.read_netcdf(path)
    np.testing.assert_allclose(back["median"].values, result.force["median"].values, rtol=1e-12)
    # every force band has its unit in memory too, not only the median (2026-12-02)
    assert {k: result.force[k].attrs.get("units") for k in ("median", "q05", "q95", "gap_voltage_q05")} == {"median": "N", "q05": "N", "q95": "N", "gap_voltage_q05": "V"}
    # a file written before the kind was stored is recognised by its attrs
    old = result.to_xarray()
    del old.attrs["impedax_kind"]
    ix.io.write_netcdf(old, tmp_path / "old.nc")
    with pytest.raises(DataError, match="holds a gap analysis result"):
        ix.load(tmp_path / "old.nc")


def test_gap_help_says_one_thing_about_nc(capsys):
    from impedax.cli import main

    with pytest.raises(SystemExit):
        main(["gap", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    # what --out's help says a .nc holds (".nc attribute)", naming where single_contact is kept, is no description of the file)
    described = re.findall(r"\.nc(?! attribute)[ :][^;.]*", text.split("--out FILE.csv|.json|.nc", 2)[-1])
    assert described == [".nc the force bands with the gap summary as attributes, the EDL parameters and the draws of u (netCDF"], described


def test_gap_json_gives_the_frequency_of_the_force_without_ep(stationary):
    """``force_without_ep_n`` carries its own ``frequency_hz``, as ``force_n`` does: the
    remainder's frequencies (the total's, from the example files), and the report's "without EP:
    max … at F" is read off it."""
    import json

    from impedax.io.export import to_jsonable

    result, (total, _, _) = stationary
    s = json.loads(json.dumps(to_jsonable(result.summary()), allow_nan=False))  # (as `impedax gap --json` prints it)
    bare, with_ep = s["force_without_ep_n"], s["force_n"]
    np.testing.assert_array_equal(bare["frequency_hz"], total["frequency"].values)
    assert bare["frequency_hz"] == with_ep["frequency_hz"] and len(bare["median"]) == len(bare["frequency_hz"])
    j = int(np.argmax(bare["median"]))
    line = next(x for x in result.report().splitlines() if x.startswith("force (peak"))
    # (its largest at 1 Hz, the band's end: 2026-12-05; what the grid's first step shows, d ln F/d ln f, since 2026-12-06)
    slope = np.log(bare["median"][0] / bare["median"][1]) / np.log(bare["frequency_hz"][0] / bare["frequency_hz"][1])
    assert slope < -0.1  # (the oracle's premise: still rising toward 1 Hz, not levelled off)
    assert line.endswith(f"without EP: max {format_quantity(bare['median'][j], 'N')} at {format_frequency(bare['frequency_hz'][j])}, the band's lower end, and still rises below it (∝ f^{slope:.2g} there)")
    assert s["force_max_without_ep_n"]["edge_slope"] == pytest.approx(slope, rel=1e-9) and s["force_max_n"]["edge_slope"] is None
    assert j == 0 and s["force_max_without_ep_n"]["band_edge"] == "fmin" and s["force_max_n"]["band_edge"] is None


def test_report_and_figure_scale_the_force_unit(stationary):
    result, _ = stationary
    peak = result.force.sel(branch="with_ep")["median"].values
    assert 1.0 < peak.max() < 1e3  # the oracle's premise: the stationary example's force is of newtons
    line = next(x for x in result.report().splitlines() if x.startswith("force (peak"))
    assert f"max {float(f'{peak.max():.3g}'):g} N at" in line and "mN" not in line
    # the maximum without EP on the same line (the JSON's force_without_ep_n)
    bare = result.force.sel(branch="without_ep")["median"]
    j = int(np.argmax(bare.values))
    slope = float(np.log(bare[0] / bare[1]) / np.log(bare["frequency"][0] / bare["frequency"][1]))
    assert line.split("; ")[-1] == f"without EP: max {format_quantity(float(bare[j]), 'N')} at {format_frequency(float(bare['frequency'][j]))}, the band's lower end, and still rises below it (∝ f^{slope:.2g} there)"
    assert not np.isclose(bare.values.max(), peak.max())  # (two branches, two maxima: the line can tell them apart)
    fig = result.plot()
    ax = fig.axes[2]
    assert ax.get_ylabel() == "peak force F_e [N]"
    assert ax.get_ylim()[1] < 2 * result.force["q95"].values.max()
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    naive = next(t for t in labels if t.startswith("C_gap only"))
    percent = result.naive_fit.rms_rel * 100  # (near 100 %: 3 digits, no exponent, where .2g wrote 1e+02)
    assert f"rms_rel {float(f'{percent:.3g}'):g} %" in naive and "e+" not in naive


def _voltage_oracle(draws, f, z_skin, z_ts, v0, with_ep):
    """|ΔV_gap| [V] per draw (draw, frequency) by the node equations of docs/physics.md, written
    with numpy: I = V0/(Z_TS + Z_R + Z_skin), ΔV = V0 − Z_TS I − Z_skin I, all of it across C_gap
    (the elements of the remainder are in parallel)."""
    w = 2 * np.pi * f[None, :]
    y = 1j * w * draws["C_gap"][:, None]
    if with_ep:
        y = y + 1 / draws["R_EP"][:, None] + draws["CPE_EP.Q"][:, None] * (1j * w) ** draws["CPE_EP.alpha"][:, None]
    z_r = 1 / y
    current = v0 / (z_ts + z_r + z_skin)
    return np.abs(v0 - z_ts * current - z_skin * current)


def test_gap_voltage_is_output_beside_the_force_from_the_same_draws(stationary, tmp_path):
    """The gap voltage promised by `impedax gap --help` (2026-12-01: it was only in Python's
    `sirin.gap_voltage`): JSON ``gap_voltage_v`` / ``gap_voltage_without_ep_v`` on the force's
    frequencies, equal to the numpy node equations over the posterior draws; eq 1 over those
    draws gives back the force band (so both come from the same draws); the report's line, the
    CSV's bayes row and the .nc's variables give it too. SYNTHETIC data (the shipped example)."""
    import csv

    result, (total, skin, ts) = stationary
    draws = {k: np.asarray(v, float) for k, v in result.posterior.parameter_draws().items()}
    f = total["frequency"].values

    def mean_z(ds):
        z = ds["Z"].transpose(..., "frequency").values
        return z.reshape(-1, z.shape[-1]).mean(axis=0)

    z_skin, z_ts = mean_z(skin), mean_z(ts)
    s = result.summary()
    u = E0 * EPS_AIR * AREA / draws["C_gap"]  # (the gap of each draw's C_gap)
    for key, force_key, with_ep in (("gap_voltage_v", "force_n", True), ("gap_voltage_without_ep_v", "force_without_ep_n", False)):
        volts = _voltage_oracle(draws, f, z_skin, z_ts, result.v0, with_ep)
        q05, q50, q95 = np.quantile(volts, [0.05, 0.5, 0.95], axis=0)
        np.testing.assert_array_equal(s[key]["frequency_hz"], s[force_key]["frequency_hz"])
        np.testing.assert_allclose(s[key]["median"], q50, rtol=1e-9)
        np.testing.assert_allclose(s[key]["q05"], q05, rtol=1e-9)
        np.testing.assert_allclose(s[key]["q95"], q95, rtol=1e-9)
        force = 0.5 * E0 * EPS_AIR * AREA * volts**2 / u[:, None] ** 2  # eq 1 on the same draws
        np.testing.assert_allclose(s[force_key]["median"], np.median(force, axis=0), rtol=1e-9)
    # the voltage at the force maximum with EP, in the report, the CSV and the .nc
    i = int(np.argmax(s["force_n"]["median"]))
    at_max = result.gap_voltage_at_force_max()
    assert at_max["frequency_hz"] == f[i] and at_max["value"] == s["gap_voltage_v"]["median"][i] and at_max["q05"] < at_max["value"] < at_max["q95"]
    line = next(x for x in result.report().splitlines() if x.startswith("gap voltage"))
    printed = re.search(r"with EP: ([\d.]+) V \(90 %: ([\d.]+)–([\d.]+) V\) at (\S+ \S+);", line)
    assert printed and printed[4] == format_frequency(f[i]) and printed[2] != printed[3], line  # (the ends told apart)
    for text, key in zip(printed.groups()[:3], ("value", "q05", "q95")):
        decimals = len(text.partition(".")[2])  # (3 or 4 significant digits since 2026-12-02: "71 V" has none)
        assert float(text) == pytest.approx(at_max[key], abs=0.51 * 10**-decimals)  # (rounded to the printed decimals)
    assert "without EP: " in line
    path = tmp_path / "gap.csv"
    ix.io.write_result(result, path)
    with open(path, newline="") as handle:
        bayes = next(csv.DictReader(handle))
    assert float(bayes["gap_voltage_v"]) == pytest.approx(at_max["value"], rel=1e-12) and float(bayes["force_max_frequency_hz"]) == pytest.approx(f[i], rel=1e-12)
    assert float(bayes["gap_voltage_low_v"]) == pytest.approx(at_max["q05"], rel=1e-12) and float(bayes["gap_voltage_high_v"]) == pytest.approx(at_max["q95"], rel=1e-12)
    nc = result.to_xarray()
    assert nc["gap_voltage_median"].attrs["units"] == "V"
    np.testing.assert_array_equal(nc["gap_voltage_q95"].sel(branch="without_ep").values, s["gap_voltage_without_ep_v"]["q95"])
    fig = result.plot()
    assert fig.axes[3].get_ylabel().startswith("gap voltage |ΔV_gap| [V]")
    assert np.allclose(fig.axes[3].lines[0].get_ydata(), s["gap_voltage_v"]["median"])


def test_gap_correlation_warning_says_what_a_gap_user_can_do():
    """The sampler's correlation warning ends "fix one or give it an informative prior", options
    `impedax gap` does not have (2026-12-01: `--fix R_EP=1e8` was refused): in the gap analysis
    it says instead how much the pair matters to u — u's correlation r with each (log space) and
    the narrowing 1 − √(1 − r²) knowing one would give (the Gaussian conditional sd, numpy
    here) — and the Python call that fixes one. SYNTHETIC draws, r(u, R_EP) = −0.42 as on the
    walkthrough's set; a pair that reaches u (r = 0.9) is said to widen it."""
    from impedax.fitting.bayes.diagnostics import chain_warnings, strong_correlations
    from impedax.models.gap import _correlation_advice

    rng = np.random.default_rng(3)
    n = 4000
    for r_u, verdict in ((-0.42, "this matters little to u"), (0.9, "this widens u's interval")):
        z_u, z_r = rng.standard_normal((2, n))
        ln_r = 17.7 + 0.01 * (r_u * z_u + np.sqrt(1 - r_u**2) * z_r)  # (ln R_EP: correlation r_u with ln u)
        ln_q = -19.6 + 0.98 * (ln_r - 17.7) + 0.002 * rng.standard_normal(n)  # (ln Q tied to ln R_EP, r ≈ 0.98)
        ln_u = np.log(4.02e-6) + 0.0015 * z_u
        chain = np.stack([ln_r, ln_q, ln_u], axis=-1).reshape(40, 100, 3)
        raw = [w for w in chain_warnings(["R_EP", "CPE_EP.Q", "u"], [True] * 3, chain, {"R_EP": 1.0, "CPE_EP.Q": 1.0, "u": 1.0}, 1, 0.3) if "strongly correlated" in w]
        assert len(raw) == 1 and raw[0].endswith("fix one or give it an informative prior")  # (the generic text, as `impedax sample` says it)
        draws = {"R_EP": np.exp(ln_r), "CPE_EP.Q": np.exp(ln_q), "u": np.exp(ln_u), "C_gap": E0 * EPS_AIR * 100e-6 / np.exp(ln_u)}
        (said,) = _correlation_advice(raw, strong_correlations(["R_EP", "CPE_EP.Q", "u"], [True] * 3, chain), draws, "R_EP || CPE_EP || C_gap")
        r = [np.corrcoef(ln_u, x)[0, 1] for x in (ln_r, ln_q)]
        narrowing = 1 - np.sqrt(1 - max(v * v for v in r))
        assert said.startswith(raw[0][: raw[0].index("; fix one")]) and "fix one or give it an informative prior" not in said
        assert f"; {verdict}: " in said and f"{r[0]:+.2f} with R_EP and {r[1]:+.2f} with CPE_EP.Q" in said and f"by at most {narrowing * 100:.0f} %" in said
        # u's interval as the report's headline gives it, to 1 nm (it said "4.01–4.03 µm" to 3
        # significant digits, and "2.8–2.81 µm" beside the demo files' headline 2.797–2.814 µm)
        u05, u95 = np.exp(np.quantile(ln_u, [0.05, 0.95])) * 1e6
        assert f"u's interval {u05:.3f}–{u95:.3f} µm (±" in said, said
        assert "impedax gap has no --fix or --prior" in said and "fixed={'R_EP': …}" in said and "edl_fit=ix.fit('R_EP || CPE_EP || C_gap', ix.models.remaining_impedance(total, skin, touchscreen)" in said
        assert all(callable(getattr(ix.models, name)) for name in re.findall(r"ix\.models\.(\w+)\(", said))  # (the call it gives exists)
    other = ["the chain (225 draws per walker after burn-in) is shorter than 50 autocorrelation times"]
    assert _correlation_advice(other, strong_correlations(["R_EP", "CPE_EP.Q", "u"], [True] * 3, chain), draws, "R_EP || CPE_EP || C_gap") == other  # (other warnings as they are)


def test_gap_correlation_advice_keys_on_the_finding_not_the_warning_s_words(monkeypatch):
    """Up to 2026-12-01 the gap advice found the sampler's correlation warning by a regular
    expression over its words: with the sampler's advice reworded, the warning passed through
    ending in advice `impedax gap` cannot follow. It now knows the warning as the
    `StrongCorrelation.warning` of the posterior's pairs: reworded, it is still replaced, after
    the finding with numpy's r; the same words with no such pair among the findings are left as they are. SYNTHETIC draws: ln R_EP and
    ln CPE_EP.Q at r ≈ 0.98, u independent of both."""
    from impedax.fitting.bayes import diagnostics
    from impedax.models.gap import _correlation_advice

    monkeypatch.setattr(diagnostics, "CORRELATION_ADVICE", "reconsider the model")
    z = np.random.default_rng(5).standard_normal((3, 4000))
    ln_r = 17.7 + 0.01 * z[0]
    ln_q = -19.6 + 0.98 * (ln_r - 17.7) + 0.002 * z[1]
    ln_u = np.log(4.02e-6) + 0.0015 * z[2]
    chain = np.stack([ln_r, ln_q, ln_u], axis=-1).reshape(40, 100, 3)
    (raw,) = [w for w in diagnostics.chain_warnings(["R_EP", "CPE_EP.Q", "u"], [True] * 3, chain, {"R_EP": 1.0, "CPE_EP.Q": 1.0, "u": 1.0}, 1, 0.3) if "strongly correlated" in w]
    finding = f"R_EP and CPE_EP.Q are strongly correlated in the posterior (r = {np.corrcoef(ln_r, ln_q)[0, 1]:+.3f} in log space): the data constrain a combination of them"
    assert raw == f"{finding}; reconsider the model"  # (the sampler's warning, reworded)
    draws = {"R_EP": np.exp(ln_r), "CPE_EP.Q": np.exp(ln_q), "u": np.exp(ln_u), "C_gap": E0 * EPS_AIR * 100e-6 / np.exp(ln_u)}
    found = diagnostics.strong_correlations(["R_EP", "CPE_EP.Q", "u"], [True] * 3, chain)
    (said,) = _correlation_advice([raw], found, draws, "R_EP || CPE_EP || C_gap")
    r = [np.corrcoef(ln_u, x)[0, 1] for x in (ln_r, ln_q)]
    assert said.startswith(f"{finding}; this matters little to u: ") and "reconsider the model" not in said
    assert f"{r[0]:+.2f} with R_EP and {r[1]:+.2f} with CPE_EP.Q" in said and "impedax gap has no --fix or --prior" in said and "fixed={'R_EP': …}" in said
    assert _correlation_advice([raw], (), draws, "R_EP || CPE_EP || C_gap") == [raw]


@pytest.mark.parametrize(("words", "hint"), [(["--fix", "R_EP=1e8"], None), (["--prior", "R_EP=x"], None), (["--stps", "30"], "--steps"), (["--quite"], "--quiet")])
def test_gap_names_no_far_fetched_option(capsys, words, hint):
    """`impedax gap --fix R_EP=1e8` named "--dpi" (difflib ratio 0.6, two of its five characters
    the shared "--"); an unknown option is now named only from a ratio of 0.7 on, so --fix and
    --prior get no hint while a slip (--stps, --quite) still does."""
    from impedax.cli import main

    with pytest.raises(SystemExit) as stop:
        main(["gap", "t.nc", "s.nc", "ts.nc", "--area", "100e-6", *words])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and f"unrecognized arguments: {' '.join(words)}" in err
    assert ("did you mean" not in err) if hint is None else (f"did you mean {hint}?" in err)


def test_undetermined_gap_line_does_not_read_as_the_gap_range(stationary):
    """On the stationary example (u not determined: the priors set it) the report read "(90%
    interval of the draws, not of the gap 0.161–0.168 µm, …", as if that range were the gap's
    (2026-12-01). Now the range follows "interval of the draws:" and what it is not comes after
    it; the numbers are the draws' 5 and 95 % quantiles (numpy)."""
    result, _ = stationary
    assert not result.gap_identified  # (the premise: the stationary total does not determine u)
    u = result.posterior.parameter_draws()["u"] * 1e6
    low, high = np.quantile(u, [0.05, 0.95])
    first = next(x for x in result.report().splitlines() if x.startswith("sampled u (prior-set)"))
    assert f"(90 % interval of the draws: {low:.3f}–{high:.3f} µm, set by the priors, not a range of the gap, " in first, first
    assert "not of the gap" not in first
