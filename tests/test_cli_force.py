"""`impedax force meyer|vezzoli`: reference values, JSON contract, bad input → exit 2; the
refined peak against dense grids of formulas written here, the peak convention against the
time-domain maximum of eq 3.6 / eq 7, --out files, and eq 8's validity warning."""

import json
import math
import re

import numpy as np
import pytest

from impedax.cli import main
from impedax.models import force_maximum

E0 = 8.8541878128e-12
THESIS = {"C_s": 140e-12, "C_i": 1.7e-9, "R_sc": 130e3, "C_sc": 2.2e-9, "R_f": 500.0}
AREA = math.pi * 0.004**2


def _json(capsys, *args):
    assert main(["force", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_vezzoli_table2_point(capsys):
    out = _json(capsys, "vezzoli", "--fmin", "440", "--fmax", "440", "--points", "1")
    assert set(out) >= {"frequency_hz", "force_n", "peak", "params", "convention"}
    assert out["frequency_hz"] == [440.0] and out["force_n"][0] == pytest.approx(0.0556, rel=0.002)
    assert {k: out["peak"][k] for k in ("frequency_hz", "force_n")} == {"frequency_hz": 440.0, "force_n": out["force_n"][0]}
    assert out["peak"]["at_band_edge"] is True and out["peak"]["band_edge"] == "fmin=fmax"  # one frequency: no peak located
    assert out["convention"] == "time-average" and out["params"]["v_m"] == 2000.0
    assert out["warnings"] == []  # Table 2 satisfies eq 8's C_i << C_s


def test_meyer_defaults_reproduce_fig_3_4(capsys):
    out = _json(capsys, "meyer", "--fmin", "1e3", "--fmax", "1e6", "--points", "301")
    assert out["peak"]["force_n"] == pytest.approx(0.164, rel=0.02)
    assert out["peak"]["frequency_hz"] == pytest.approx(37e3, rel=0.05)
    assert out["params"]["v_a"] == 140.0 and out["params"]["R_sc"] == 130e3


def test_param_override_scales_with_voltage_squared(capsys):
    base = _json(capsys, "vezzoli", "--fmin", "100", "--fmax", "1000", "--points", "3")
    double = _json(capsys, "vezzoli", "--fmin", "100", "--fmax", "1000", "--points", "3", "--param", "v_m=4000")
    np.testing.assert_allclose(double["force_n"], 4 * np.array(base["force_n"]), rtol=1e-12)


def test_csv_output_and_plot(capsys, tmp_path):
    png = tmp_path / "f.png"
    assert main(["force", "meyer", "--points", "5", "--plot", str(png)]) == 0
    captured = capsys.readouterr()
    lines = captured.out.strip().splitlines()
    assert lines[0].startswith("frequency_hz,force_n,convention,") and len(lines) == 6  # (then model, parameters, provenance: 2026-12-01)
    assert "peak" in captured.err and png.stat().st_size > 1000


@pytest.mark.parametrize(
    "args, match",
    [
        (["meyer", "--param", "Rsc=1"], "R_sc"),
        (["vezzoli", "--param", "h_i=-1"], "h_s"),
        (["vezzoli", "--param", "h_i=abc"], "eps_i"),
        (["vezzoli", "--param", "h_i"], "rho_s"),
        (["vezzoli", "--fmin", "0"], "positive"),
        # overflow: no maximum to find (inf − inf, inf/inf, a Python float squared past 1e308)
        (["meyer", "--param", "v_a=1e200"], "not finite (overflow) at 10 Hz and 160 other frequencies; check the --param values (v_a=1e+200)"),
        (["vezzoli", "--param", "rho_s=1e300"], "--param values (rho_s=1e+300)"),
        (["vezzoli", "--param", "v_m=1e200"], "--param values (v_m=1e+200)"),
        (["meyer", "--out", "f.txt"], "--out: unknown extension '.txt'"),
    ],
)
def test_bad_input_exits_2_with_one_message(capsys, args, match):
    assert main(["force", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and match in err[0]


# --- oracles written here (numpy), independent of impedax's circuit probes ----------------------


def _meyer_phasors(f, v_a=140.0, p=THESIS):
    """RC chain by hand: I = V_A/Z_total, V_F = I (1/(jωC_i) + Z_sc), Q_f = I_Rsc/(jω) = I Z_sc/(R_sc jω);
    returns K = (C_i C_sc/(C_i + C_sc))²/(2Aε0), V_F and Q_f/C_i."""
    jw = 2j * np.pi * np.asarray(f, float)
    z_sc = p["R_sc"] / (1 + jw * p["R_sc"] * p["C_sc"])
    current = v_a / (1 / (jw * p["C_s"]) + 1 / (jw * p["C_i"]) + z_sc + p["R_f"])
    k = (p["C_i"] * p["C_sc"] / (p["C_i"] + p["C_sc"])) ** 2 / (2 * AREA * E0)
    return k, current * (1 / (jw * p["C_i"]) + z_sc), current * z_sc / (p["R_sc"] * jw) / p["C_i"]


def _meyer_mean(f):
    k, a, b = _meyer_phasors(f)
    return k * 0.5 * (np.abs(a) ** 2 - np.abs(b) ** 2)


def _meyer_time_domain(f0, samples=20000):
    """Eq 3.6 over one period, F(t) = K (V_F(t)² − (Q_f(t)/C_i)²), sampled."""
    k, a, b = _meyer_phasors(f0)
    phase = np.exp(2j * np.pi * np.arange(samples) / samples)
    return k * (np.real(a * phase) ** 2 - np.real(b * phase) ** 2)


def _vezzoli_time_domain(f0, samples=20000, h_i=90e-6, h_s=350e-6, area=1e-4, eps_i=3.35, eps_s=2340.0, rho_s=3e4, v_m=2000.0):
    """Eq 7 with eq 9's v_e(t) = V_m ωτ/√(1+(ωτ)²) cos(ωt + π/2 − arctan ωτ), sampled over a period."""
    wt = 2 * np.pi * f0 * E0 * eps_s * rho_s
    t = np.arange(samples) / samples / f0
    v_e = v_m * wt / np.sqrt(1 + wt**2) * np.cos(2 * np.pi * f0 * t + np.pi / 2 - np.arctan(wt))
    return E0 * area * v_e**2 / (2 * (h_i + h_s) * (h_i / eps_i + h_s / eps_s))


# --- 1. the peak: refined between grid points, or the band's end ------------------------------------


def test_meyer_peak_is_refined_to_the_dense_grid_maximum(capsys):
    out = _json(capsys, "meyer")  # the default 161 points over 10 Hz–1 GHz
    peak = out["peak"]
    # the grid's best point is 35.5 kHz; the maximum lies between its neighbours
    assert peak["grid_frequency_hz"] == pytest.approx(35481.3, rel=1e-5) and peak["at_band_edge"] is False and peak["band_edge"] is None
    f = np.geomspace(30e3, 45e3, 200_001)  # spacing 2e-6 in ln f
    dense = _meyer_mean(f)
    k = int(np.argmax(dense))
    assert 0 < k < f.size - 1
    assert peak["frequency_hz"] == pytest.approx(f[k], rel=1e-5)
    assert peak["force_n"] == pytest.approx(dense[k], rel=1e-9)
    assert peak["force_n"] >= peak["grid_force_n"]
    # thesis Fig 3.4: 164 mN near 37 kHz
    assert peak["force_n"] == pytest.approx(0.164, rel=0.01) and peak["frequency_hz"] == pytest.approx(37e3, rel=0.01)
    # the stderr line in SI prefixes, as the figure's legend and impedax elsewhere (it said
    # "peak 0.1642 N at 37006 Hz (…; grid maximum 0.1641 N at 3.548e+04 Hz)" until 2026-12-06)
    grid = _meyer_mean(np.array([peak["grid_frequency_hz"]]))[0]
    says = f"peak {dense[k] * 1e3:.4g} mN at {f[k] / 1e3:.3g} kHz (refined between grid points; grid maximum {grid * 1e3:.4g} mN at 35.5 kHz)"
    assert says == "peak 164.2 mN at 37 kHz (refined between grid points; grid maximum 164.2 mN at 35.5 kHz)"
    assert says in _stderr_line(capsys, "meyer")
    # vezzoli, a high-pass: largest at --fmax, eq 10's plateau ε0 A V_m²/(4 (h_i + h_s)(h_i/ε_i + h_s/ε_s)) = 74.49 mN at 1 MHz
    plateau = 8.8541878128e-12 * 1e-4 * 2000.0**2 / (4 * (90e-6 + 350e-6) * (90e-6 / 3.35 + 350e-6 / 2340))
    # ... within 1 % of it from (ωτ)² /(1 + (ωτ)²) = 0.99, ωτ = √99, τ = ε0 ε_s ρ_s: 2.548 kHz, the grid's 2.59 kHz (until
    # 2026-12-06 the line said only "and still rises above it", read as a force still growing past 1 MHz)
    knee = np.sqrt(99.0) / (2 * np.pi * 8.8541878128e-12 * 2340.0 * 3.0e4)
    grid = np.geomspace(1.0, 1e6, 161)
    low = grid[grid >= knee][0]
    out_v = _json(capsys, "vezzoli")
    assert out_v["peak"]["plateau_hz"] == [pytest.approx(low, rel=1e-12), 1e6]
    assert (f"the force is largest at --fmax, {plateau * 1e3:.4g} mN at 1 MHz, on a plateau: within 1 % of it over {low / 1e3:.3g} kHz–1 MHz, "
            "where it levels off (it may still rise above --fmax)") in _stderr_line(capsys, "vezzoli")
    assert out["peak"]["plateau_hz"] is not None  # (meyer's flat top: within 1 % over 5.6–251 kHz; its refined peak is said as before)


def _stderr_line(capsys, *args):
    assert main(["force", *args]) == 0
    return capsys.readouterr().err


def test_peak_convention_maximum_against_a_dense_grid(capsys):
    out = _json(capsys, "meyer", "--convention", "peak")
    assert out["convention"] == "peak"
    f = np.geomspace(25e3, 45e3, 200_001)
    k, a, b = _meyer_phasors(f)
    # max over t of F̄ + (K/2) Re[(a² − b²) e^{2jωt}]: mean plus the 2ω amplitude (the time-domain test checks it)
    dense = k * 0.5 * (np.abs(a) ** 2 - np.abs(b) ** 2 + np.abs(a**2 - b**2))
    j = int(np.argmax(dense))
    assert 0 < j < f.size - 1
    assert out["peak"]["frequency_hz"] == pytest.approx(f[j], rel=1e-5)
    assert out["peak"]["force_n"] == pytest.approx(dense[j], rel=1e-9)


def test_grid_maximum_at_fmin_with_the_maximum_inside_the_first_interval(capsys):
    # grid 30 kHz, 5.5 MHz, 1 GHz: the best point is fmin, yet the force rises past it to 37 kHz
    out = _json(capsys, "meyer", "--fmin", "30e3", "--points", "3")
    assert out["peak"]["grid_frequency_hz"] == 30e3
    assert out["peak"]["at_band_edge"] is False
    assert out["peak"]["frequency_hz"] == pytest.approx(37006, rel=1e-4)


@pytest.mark.parametrize(
    "args, edge, says",
    [
        (["vezzoli"], "fmax", "largest at --fmax"),  # a high-pass: no maximum below infinity
        (["meyer", "--fmin", "1e5"], "fmin", "largest at --fmin"),
        (["meyer", "--fmax", "1e4"], "fmax", "still rises above it"),
    ],
)
def test_largest_force_at_a_band_edge_is_not_called_a_peak(capsys, args, edge, says):
    out = _json(capsys, *args)
    peak = out["peak"]
    end = 0 if edge == "fmin" else -1
    assert peak["at_band_edge"] is True and peak["band_edge"] == edge
    assert peak["frequency_hz"] == out["frequency_hz"][end] and peak["force_n"] == out["force_n"][end]
    err = _stderr_line(capsys, *args)
    assert "no peak in the band" in err and says in err


def test_force_maximum_of_a_closed_form():
    """A Gaussian in ln f with its top at 1234.5 Hz between the points of a coarse grid."""
    top = 1234.5

    def bump(f):
        return 3.0 * np.exp(-((np.log(f) - np.log(top)) ** 2) / 2.0)

    freq = np.geomspace(10.0, 1e5, 9)
    peak = force_maximum(lambda f: float(bump(f)), freq, bump(freq))
    assert peak.frequency_hz == pytest.approx(top, rel=1e-6) and peak.force_n == pytest.approx(3.0, rel=1e-12) and peak.is_peak
    rising = force_maximum(lambda f: float(np.log(f)), freq, np.log(freq))
    assert rising.at_band_edge and rising.band_edge == "fmax" and rising.frequency_hz == 1e5 and not rising.is_peak


# --- 3. conventions -----------------------------------------------------------------------------


def test_vezzoli_peak_is_twice_the_mean_and_the_time_domain_maximum(capsys):
    band = ["vezzoli", "--fmin", "10", "--fmax", "1e4", "--points", "4"]
    mean = _json(capsys, *band)
    peak = _json(capsys, *band, "--convention", "peak")
    assert mean["convention"] == "time-average" and peak["convention"] == "peak"
    np.testing.assert_allclose(peak["force_n"], 2 * np.array(mean["force_n"]), rtol=1e-12)
    for f0, m, p in zip(mean["frequency_hz"], mean["force_n"], peak["force_n"]):
        inst = _vezzoli_time_domain(f0)
        assert m == pytest.approx(inst.mean(), rel=1e-9)
        assert p == pytest.approx(inst.max(), rel=1e-6)
        assert inst.min() == pytest.approx(0.0, abs=1e-6 * p)  # DC + 2ω of equal amplitude


def test_meyer_peak_is_the_time_domain_maximum_of_eq_3_6(capsys):
    band = ["meyer", "--fmin", "10", "--fmax", "1e6", "--points", "6"]
    mean = _json(capsys, *band)
    peak = _json(capsys, *band, "--convention", "peak")
    ratio = np.array(peak["force_n"]) / np.array(mean["force_n"])
    for f0, m, p in zip(mean["frequency_hz"], mean["force_n"], peak["force_n"]):
        inst = _meyer_time_domain(f0)
        assert m == pytest.approx(inst.mean(), rel=1e-9)
        assert p == pytest.approx(inst.max(), rel=1e-6)
    # not simply 2x: V_F and Q_f are out of phase; the gap closes where Q_f vanishes
    assert np.all(ratio >= 2 * (1 - 1e-12))
    assert ratio[0] == pytest.approx(64, rel=0.02) and ratio[2] == pytest.approx(2.18, rel=0.01)  # 10 Hz, 1 kHz
    assert ratio[-1] == pytest.approx(2.0, rel=1e-4)  # 1 MHz


# --- 2. --out -------------------------------------------------------------------------------------


@pytest.mark.parametrize("suffix", [".csv", ".json", ".CSV"])
def test_out_writes_what_stdout_would_show(capsys, tmp_path, suffix):
    args = ["force", "meyer", "--points", "7", "--convention", "peak"]
    assert main(args + (["--json"] if suffix == ".json" else [])) == 0
    expected = capsys.readouterr().out
    path = tmp_path / f"force{suffix}"
    assert main(args + ["--out", str(path)]) == 0
    captured = capsys.readouterr()
    stamp = re.compile(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ")  # (written_utc: the runs may fall in different seconds)
    assert stamp.sub("T", path.read_text(encoding="utf-8")) == stamp.sub("T", expected)
    assert captured.out == ""  # the spectrum went to the file
    assert f"wrote {path}" in captured.err.splitlines()
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]  # no temporary left behind


def test_out_with_json_and_plot(capsys, tmp_path):
    csv, png = tmp_path / "f.csv", tmp_path / "f.png"
    assert main(["force", "vezzoli", "--points", "5", "--json", "--out", str(csv), "--plot", str(png)]) == 0
    captured = capsys.readouterr()
    out = json.loads(captured.out)  # --json still prints the JSON
    lines = csv.read_text().splitlines()
    assert lines[0].startswith("frequency_hz,force_n,convention,model,") and len(lines) == 6
    # the shortest exact form: the same numbers as the JSON, bit for bit
    assert [[float(x) for x in line.split(",")[:2]] for line in lines[1:]] == [list(p) for p in zip(out["frequency_hz"], out["force_n"])]
    assert [line.split(",")[0] for line in lines[1:]] == [repr(f).removesuffix(".0") for f in out["frequency_hz"]]
    assert f"wrote {csv}" in captured.err and f"wrote {png}" in captured.err and png.stat().st_size > 1000


@pytest.mark.parametrize("name", ["f.txt", "f.nc", "f", "f.png"])
def test_out_unknown_extension_is_refused_before_any_work(capsys, tmp_path, name):
    path = tmp_path / name
    assert main(["force", "meyer", "--out", str(path)]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and "--out" in err[0] and ".csv" in err[0] and ".json" in err[0]
    assert captured.out == "" and list(tmp_path.iterdir()) == []


# --- 4. Vezzoli eq 8 validity --------------------------------------------------------------------


def test_vezzoli_warns_once_when_c_i_is_not_small_against_c_s(capsys):
    args = ["vezzoli", "--param", "h_i=1e-6", "--param", "eps_i=3.4", "--param", "v_m=140"]  # Fig 8's conditions
    ratio = 3.4 * 350e-6 / (2340 * 1e-6)  # C_i/C_s = (ε_i/h_i)/(ε_s/h_s) = 0.509
    assert main(["force", *args]) == 0
    warned = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(warned) == 1 and "C_i/C_s" in warned[0] and f"{ratio:.3g}" in warned[0]
    out = _json(capsys, *args)
    assert len(out["warnings"]) == 1 and f"{ratio:.3g}" in out["warnings"][0]


def test_vezzoli_table2_defaults_do_not_warn(capsys):
    assert 3.35 * 350e-6 / (2340 * 90e-6) < 0.01  # Table 2: C_i/C_s = 0.0056
    assert main(["force", "vezzoli"]) == 0
    assert "warning" not in capsys.readouterr().err
    assert _json(capsys, "vezzoli")["warnings"] == []


def test_a_flat_force_is_not_said_to_rise(capsys):
    """R_f = 1e300 Ω: no current, the force is 0 N at every frequency (eq 3.6 with V_F = 0); an
    implausible R_f, computed with --no-param-check."""
    out = _json(capsys, "meyer", "--param", "R_f=1e300", "--points", "9", "--no-param-check")
    assert max(out["force_n"]) == 0.0 == min(out["force_n"])
    assert out["peak"]["band_edge"] == "flat" and out["peak"]["at_band_edge"] is False
    err = _stderr_line(capsys, "meyer", "--param", "R_f=1e300", "--points", "9", "--no-param-check")
    assert "0 N at every frequency" in err and "rises" not in err


# --- Meyer's CPE variant (R_sc ∥ CPE_sc, thesis Fig 5.3) ------------------------------------------


CPE_BAND = ("--fmin", "10", "--fmax", "1e7", "--points", "13")  # (one grid: the CPE variant compiles once)


def _meyer_cpe_force(f, q, alpha, convention, v_a=140.0, p=THESIS):
    """Eq 3.6 by hand with Z_sc = R_sc ∥ CPE (1/Z_sc = 1/R_sc + Q (jω)^α) and the prefactor's
    C_sc(ω) = Q ω^(α−1): time average K/2 (|V_F|² − |Q_f|²/C_i²); peak that plus K/2 |V_F² − Q_f²/C_i²|."""
    w = 2 * np.pi * np.asarray(f, float)
    jw = 1j * w
    z_sc = 1 / (1 / p["R_sc"] + q * jw**alpha)
    current = v_a / (1 / (jw * p["C_s"]) + 1 / (jw * p["C_i"]) + z_sc + p["R_f"])
    v_f = current * (1 / (jw * p["C_i"]) + z_sc)
    q_f_over_c_i = current * z_sc / (p["R_sc"] * jw) / p["C_i"]
    c_sc = q * w ** (alpha - 1)
    k = (p["C_i"] * c_sc / (p["C_i"] + c_sc)) ** 2 / (2 * AREA * E0)
    mean = k / 2 * (np.abs(v_f) ** 2 - np.abs(q_f_over_c_i) ** 2)
    return mean if convention == "time-average" else mean + k / 2 * np.abs(v_f**2 - q_f_over_c_i**2)


@pytest.mark.parametrize("convention", ["time-average", "peak"])
def test_meyer_cpe_force_against_eq_3_6_by_hand(capsys, convention):
    out = _json(capsys, "meyer", "--param", "CPE_sc.Q=5n", "--param", "CPE_sc.alpha=0.85", *CPE_BAND, "--convention", convention)
    assert out["variant"] == "cpe" and out["params"]["CPE_sc.Q"] == 5e-9 and out["params"]["CPE_sc.alpha"] == 0.85 and "C_sc" not in out["params"]
    np.testing.assert_allclose(out["force_n"], _meyer_cpe_force(out["frequency_hz"], 5e-9, 0.85, convention), rtol=1e-9)


def test_meyer_cpe_with_alpha_1_is_the_rc_variant_with_c_sc_q(capsys):
    band = CPE_BAND
    cpe = _json(capsys, "meyer", "--variant", "cpe", "--param", "CPE_sc.Q=3.3n", "--param", "CPE_sc.alpha=1", *band)
    rc = _json(capsys, "meyer", "--param", "C_sc=3.3n", *band)
    assert rc["variant"] == "rc" and cpe["variant"] == "cpe"
    np.testing.assert_allclose(cpe["force_n"], rc["force_n"], rtol=1e-12)
    np.testing.assert_allclose(rc["force_n"], _meyer_cpe_force(rc["frequency_hz"], 3.3e-9, 1.0, "time-average"), rtol=1e-9)


def test_meyer_cpe_defaults_give_the_thesis_c_sc_at_1_khz(capsys):
    out = _json(capsys, "meyer", "--variant", "cpe", "--param", "CPE_sc.alpha=0.7", *CPE_BAND)
    q = out["params"]["CPE_sc.Q"]
    assert q * (2 * np.pi * 1e3) ** (0.7 - 1) == pytest.approx(2.2e-9, rel=1e-12)
    np.testing.assert_allclose(out["force_n"], _meyer_cpe_force(out["frequency_hz"], q, 0.7, "time-average"), rtol=1e-9)


@pytest.mark.parametrize(
    "args, match",
    [
        (["--param", "CPE_sc.Q=5.9"], "capacitance at 1 kHz, Q (2π·1 kHz)^(α−1) = 1.026 F"),
        (["--param", "CPE_sc.Q=5.9"], "5.9n (5.9 nF s^(α−1)) was likely meant"),
        (["--param", "CPE_sc.Q=5n", "--param", "CPE_sc.alpha=1.2"], "--param CPE_sc.alpha=1.2: must be in (0, 1]"),
        (["--variant", "cpe", "--param", "C_sc=2n"], "--param C_sc belongs to the rc variant"),
        (["--variant", "rc", "--param", "CPE_sc.Q=2n"], "--param CPE_sc.Q belongs to the cpe variant"),
        (["--param", "C_sc=2n", "--param", "CPE_sc.alpha=0.9"], "belong to different Meyer variants"),
    ],
)
def test_meyer_cpe_bad_input_exits_2(capsys, args, match):
    assert main(["force", "meyer", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and match in err[0]


def test_meyer_cpe_implausible_q_computes_with_no_param_check(capsys):
    out = _json(capsys, "meyer", "--param", "CPE_sc.Q=5.9", "--no-param-check", *CPE_BAND)
    assert len(out["warnings"]) == 1 and "CPE_sc.Q = 5.9" in out["warnings"][0]
    np.testing.assert_allclose(out["force_n"], _meyer_cpe_force(out["frequency_hz"], 5.9, 0.8, "time-average"), rtol=1e-9)


def test_vezzoli_has_no_variant(capsys):
    assert main(["force", "vezzoli", "--variant", "cpe"]) == 2
    assert "only meyer has variants" in capsys.readouterr().err


def test_meyer_area_alone_scales_the_force_as_one_over_area_and_says_so(capsys):
    """eq 3.6's prefactor is 1/(2 A ε0): with C_i, C_sc, R_sc held, halving A doubles F at every
    frequency; the warning says so and gives the elements of eq 3.13 scaled to the area."""
    base = _json(capsys, "meyer", "--fmin", "1e3", "--fmax", "1e6", "--points", "31")
    assert base["warnings"] == []
    half = _json(capsys, "meyer", "--fmin", "1e3", "--fmax", "1e6", "--points", "31", "--param", f"area={AREA / 2!r}")
    np.testing.assert_allclose(half["force_n"], 2.0 * np.asarray(base["force_n"]), rtol=1e-12)
    (note,) = half["warnings"]
    assert "changes only eq 3.6's 1/A" in note and "× 2" in note
    scaled = dict(re.findall(r"(C_i|C_sc|R_sc)=([0-9.e+-]+)", note))
    assert float(scaled["C_i"]) == pytest.approx(THESIS["C_i"] / 2, rel=1e-3) and float(scaled["C_sc"]) == pytest.approx(THESIS["C_sc"] / 2, rel=1e-3)
    assert float(scaled["R_sc"]) == pytest.approx(THESIS["R_sc"] * 2, rel=1e-3)
    given = _json(capsys, "meyer", "--points", "11", "--param", f"area={AREA / 2!r}", f"C_i={THESIS['C_i'] / 2!r}")
    assert given["warnings"] == []  # (an element of the area given: the user chose the values)


@pytest.mark.parametrize(
    "args, says, not_says",
    [
        (["--fmin", "1000", "--fmax", "1000"], "one frequency (no peak located): 128.7 mN at 1 kHz", "band's end"),
        (["--param", "R_f=1e300", "--points", "9", "--no-param-check"], "no peak: 0 N at every frequency", "at 10 Hz"),
    ],
)
def test_the_figures_marker_says_what_the_text_says(capsys, monkeypatch, tmp_path, args, says, not_says):
    """One frequency (the text: "(one frequency: no peak located)") was marked "largest at the
    band's end", and a force the same everywhere (the text: "no peak in the band: … 0 N at every
    frequency") "peak: 0 N"; 128.7 mN is eq 3.6 at 1 kHz (the JSON's force_n, 0.12875 N)."""
    import impedax.plotting.models as plots

    drawn = []
    draw = plots.plot_force_spectrum
    monkeypatch.setattr(plots, "plot_force_spectrum", lambda *a, **k: drawn.append(draw(*a, **k)) or drawn[-1])
    assert main(["force", "meyer", *args, "--plot", str(tmp_path / "f.png")]) == 0
    (label,) = drawn[0].axes[0].get_legend_handles_labels()[1]
    assert says in label and not_says not in label, label


def _eq10_log_slope(f):
    """d ln F/d ln f of Vezzoli's eq 10, (ωτ)²/(1 + (ωτ)²) × const: 2/(1 + (ωτ)²), τ = ε0 ε_s ρ_s
    with Table 2's ε_s = 2340, ρ_s = 3.0e4 Ω m (by hand)."""
    wt = 2 * np.pi * f * E0 * 2340.0 * 3.0e4
    return 2.0 / (1.0 + wt**2)


@pytest.mark.parametrize(
    "band, levelled",
    [(("--fmin", "10k", "--fmax", "50k"), True), (("--fmin", "3k", "--fmax", "8k"), True), (("--fmin", "1", "--fmax", "5"), False),
     (("--fmin", "100", "--fmax", "500"), False), (("--fmin", "1", "--fmax", "1M", "--points", "2"), True)],
)
def test_a_band_shorter_than_a_decade_says_what_its_end_shows(capsys, band, levelled):
    """Vezzoli's eq 10 over less than a decade (no plateau is judged there): at 10–50 kHz it changes
    by 0.012 % per decade at --fmax and was said to "still rise above it" until 2026-12-06; at 1–5 Hz
    it rises as f². The line follows the slope at the band's end, checked against eq 10's own there
    (also on a grid of two points, whose one step spans the band: no plateau is judged on it)."""
    out = _json(capsys, "vezzoli", *band)
    f = np.asarray(out["frequency_hz"])
    slope = out["peak"]["edge_slope"]
    assert out["peak"]["band_edge"] == "fmax" and out["peak"]["plateau_hz"] is None
    # d ln F/d ln f at --fmax: eq 10's own there (a step of 1e-3 in ln f inward: within 0.2 %)
    assert slope == pytest.approx(_eq10_log_slope(f[-1]), rel=2e-3)
    err = _stderr_line(capsys, "vezzoli", *band)
    if levelled:  # below 1 % per decade: 10^slope − 1 < 0.01
        assert 10 ** _eq10_log_slope(f[-1]) - 1 < 0.01
        assert "where it has levelled off: it changes by" in err and "per decade there" in err and "still rises above it" not in err
        if 10 ** _eq10_log_slope(f[-1]) - 1 < 1e-6:  # (1 MHz: 3e-7 of the force per decade)
            assert "changes by less than 0.001 % per decade" in err
    else:
        assert f"and still rises above it (∝ f^{slope:.2g} there)" in err and "levelled" not in err
        assert 10 ** _eq10_log_slope(f[-1]) - 1 > 0.01


def test_the_figure_draws_a_force_from_zero(monkeypatch, tmp_path):
    """Vezzoli's eq 10 over 10–50 kHz changes by 0.07 % (74.44–74.49 mN); its autoscaled axis drew
    that as a steep rise across the panel until 2026-12-06. The axis now starts at 0 and holds the
    curve: eq 10's limit ε0 A V_m²/(4 (h_i + h_s)(h_i/ε_i + h_s/ε_s)) by hand, Table 2."""
    import impedax.plotting.models as plots

    drawn = []
    draw = plots.plot_force_spectrum
    monkeypatch.setattr(plots, "plot_force_spectrum", lambda *a, **k: drawn.append(draw(*a, **k)) or drawn[-1])
    assert main(["force", "vezzoli", "--fmin", "10k", "--fmax", "50k", "--plot", str(tmp_path / "f.png"), "-q"]) == 0
    limit_mn = E0 * 1e-4 * 2000.0**2 / (4 * (90e-6 + 350e-6) * (90e-6 / 3.35 + 350e-6 / 2340)) * 1e3
    bottom, top = drawn[0].axes[0].get_ylim()
    assert bottom == 0.0 and limit_mn < top < 1.2 * limit_mn


def test_a_band_reaching_1_ghz_is_written_in_ghz(capsys):
    """Meyer's default band ends at 1 GHz; a frequency there was written "1e+03 MHz" (2026-12-06).
    Vezzoli's eq 10 is within 1 % of its limit over the whole 1 MHz–1 GHz (ωτ ≥ 3900 there)."""
    err = _stderr_line(capsys, "vezzoli", "--fmin", "1M", "--fmax", "1G")
    assert "at 1 GHz, on a plateau: within 1 % of it over 1 MHz–1 GHz" in err and "e+03" not in err
    from impedax.data import format_band, format_frequency

    assert [format_frequency(f) for f in (1e9, 2.5e9, 999e6)] == ["1 GHz", "2.5 GHz", "999 MHz"] and format_band(10.0, 1e9) == "10 Hz–1 GHz"
