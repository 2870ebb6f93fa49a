"""The checks of `impedax gap`'s three inputs and of `impedax force`'s parameters (the review
of the gap inputs): sign-flipped files, frequency grids (sorted, compared within SWEEP_RTOL, the
odd file named), the same file twice, the spectra used per file, plausible force parameters
and negative numbers as option values. All data are SYNTHETIC (numpy formulas,
`spectra.sirin_measurements`); expectations are written here with numpy."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.models.gap import gap_analysis
from spectra import sirin_measurements
from gap_files import saved_gap_files

AREA = 130e-6


def _measurements(seed=3, n_trials=4, points=31):
    """SYNTHETIC total, skin and screen, ``n_trials`` trials each (dims ``trial``, labelled 1..n)."""
    f, *spectra = sirin_measurements(np.random.default_rng(seed), n_trials, noise=0.005, trial_scatter=None, points=points)
    labels = np.arange(1, n_trials + 1)
    return tuple(ix.make_spectrum(f, z, dims=("trial",), coords={"trial": labels}) for z in spectra)


def _flat(ds):
    return ds["Z"].transpose(..., "frequency").values.reshape(-1, ds.sizes["frequency"])


def _with(ds, *, freq=None, z=None):
    """``ds`` with other frequencies or spectra (trials × frequency)."""
    f = ds["frequency"].values if freq is None else freq
    z = _flat(ds) if z is None else z
    return ix.make_spectrum(f, z, dims=("trial",), coords={"trial": ds["trial"].values})


def _run(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:  # (argparse's own errors)
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


class _Stop(Exception):
    pass


@pytest.fixture
def captured_remainder(monkeypatch):
    """Stops the pooled gap analysis at its sampler, keeping the remainder it was given."""
    import impedax.fitting

    seen = {}

    def fake_sample(circuit, data, **kwargs):
        seen["remaining"] = data
        raise _Stop

    monkeypatch.setattr(impedax.fitting, "sample", fake_sample)
    return seen


# --- 1. a sign-flipped input is refused, naming the file ----------------------------------------


@pytest.mark.parametrize("which, name", [(0, "total"), (1, "skin"), (2, "touchscreen")])
def test_conjugated_input_is_refused_naming_the_file(tmp_path, capsys, which, name):
    parts = list(_measurements())
    parts[which] = _with(parts[which], z=np.conj(_flat(parts[which])))
    paths = saved_gap_files(tmp_path, parts)
    out = tmp_path / "result.json"
    code, _, err = _run(["gap", *paths, "--area", "130e-6", "--pooled", "--out", str(out)], capsys)
    assert code == 2
    assert f"{name} ({paths[which]})" in err and "opposite sign" in err and "Z'' > 0 at" in err
    assert not out.exists()  # nothing half-written


def test_conjugated_csv_names_the_column_to_rename(tmp_path, capsys):
    total, skin, ts = (_flat(d).mean(0) for d in _measurements())
    f = np.geomspace(1.0, 1e6, 31)
    paths = []
    for name, z in (("total", total), ("skin", skin), ("ts", np.conj(ts))):
        path = tmp_path / f"{name}.csv"
        path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{a:.10g},{b.real:.10g},{b.imag:.10g}\n" for a, b in zip(f, z)))
        paths.append(str(path))
    code, _, err = _run(["gap", *paths, "--area", "130e-6", "--pooled"], capsys)
    assert code == 2
    assert "touchscreen" in err and "rename the column 'z_imag_ohm' to '-z_imag_ohm'" in err


def test_negated_real_part_is_refused():
    total, skin, ts = _measurements()
    with pytest.raises(ix.DataError, match=r"skin: .*real part may be stored with the opposite sign"):
        gap_analysis(total, _with(skin, z=-np.conj(_flat(skin))), ts, area=AREA, method="pooled", progress=False)


def test_a_few_positive_points_pass(captured_remainder):
    """Noise may lift Z'' above 0 at a few points (a resistive screen at low frequency): under half passes."""
    total, skin, ts = _measurements()
    z = _flat(ts).copy()
    z[:, :5] = z[:, :5].real + 1j * np.abs(z[:, :5].imag)  # 5 of 31 points
    with pytest.raises(_Stop):
        gap_analysis(total, skin, _with(ts, z=z), area=AREA, method="pooled", progress=False)


# --- 2. frequency grids --------------------------------------------------------------------------


def test_descending_and_rounded_grids_give_the_sorted_remainder(captured_remainder):
    total, skin, ts = _measurements()
    f = total["frequency"].values
    desc = _with(ts, freq=f[::-1], z=_flat(ts)[:, ::-1])
    rounded = _with(skin, freq=np.array([float(f"{v:.6g}") for v in f]))
    assert np.max(np.abs(rounded["frequency"].values / f - 1)) > 1e-9  # (refused before: rtol 1e-9)
    with pytest.raises(_Stop):
        gap_analysis(total, rounded, desc, area=AREA, method="pooled", progress=False)
    remaining = captured_remainder["remaining"]
    expected = _flat(total).mean(0) - _flat(skin).mean(0) - _flat(ts).mean(0)
    np.testing.assert_allclose(remaining["frequency"].values, f)
    np.testing.assert_allclose(remaining["Z"].values, expected, rtol=1e-12)


def test_grid_beyond_the_sweep_tolerance_is_refused():
    total, skin, ts = _measurements()
    f = total["frequency"].values
    shifted = f.copy()
    shifted[7] *= 1.002  # beyond 1e-3
    with pytest.raises(ix.DataError, match=re.escape(f"first differing at point 8: {shifted[7]:.6g} Hz where total and skin have {f[7]:.6g} Hz")):
        gap_analysis(total, skin, _with(ts, freq=shifted), area=AREA, method="pooled", progress=False)


def test_rad_per_second_total_is_named_with_the_ratio(tmp_path, capsys):
    total, skin, ts = _measurements()
    f = total["frequency"].values
    paths = saved_gap_files(tmp_path, [_with(total, freq=2 * np.pi * f), skin, ts])
    code, _, err = _run(["gap", *paths, "--area", "130e-6", "--pooled"], capsys)
    assert code == 2
    assert err.count("total (") == 1 and "differ from those of skin and touchscreen" in err
    assert f"{2 * np.pi * f[0]:.6g} Hz where skin and touchscreen have {f[0]:.6g} Hz" in err
    assert "2π" in err and "rad/s" in err


def test_khz_screen_is_named_with_the_ratio():
    """A grid 1/1000 of the others is the one read in kHz: the message said "the other two look
    like kHz" of it; one 1000× the others leaves the other two as the kHz ones; with all three
    differing each slip is said of the file it fits."""
    total, skin, ts = _measurements()
    f = total["frequency"].values
    with pytest.raises(ix.DataError, match=r"touchscreen: its frequencies differ from those of total and skin.*they are the other two's divided by 1000 at every point: its frequencies look like kHz") as caught:
        gap_analysis(total, skin, _with(ts, freq=f / 1e3), area=AREA, method="pooled", progress=False)
    assert "the other two's frequencies look like" not in str(caught.value)
    with pytest.raises(ix.DataError, match=r"touchscreen: its frequencies differ.*they are the other two's times 1000 at every point: the other two's frequencies look like kHz"):
        gap_analysis(total, skin, _with(ts, freq=f * 1e3), area=AREA, method="pooled", progress=False)
    with pytest.raises(ix.DataError, match=r"the frequencies of all three files differ") as caught:
        gap_analysis(_with(total, freq=f / 1e3), _with(skin, freq=2 * np.pi * f), ts, area=AREA, method="pooled", progress=False)
    said = str(caught.value)
    assert "they are touchscreen's divided by 1000 at every point: total's frequencies look like kHz" in said
    assert "they are touchscreen's times 2π at every point: skin's frequencies look like angular frequency" in said


def test_shorter_grid_names_its_file_and_sizes():
    total, skin, ts = _measurements()
    short = _measurements(points=21)[1]
    with pytest.raises(ix.DataError, match=r"skin: its frequencies differ from those of total and touchscreen.*skin: 21 points.*total and touchscreen: 31 points"):
        gap_analysis(total, short, ts, area=AREA, method="pooled", progress=False)


def test_a_file_of_one_frequency_is_one_point_at_one_frequency(tmp_path, capsys):
    """A hostile walkthrough (2026-12-08): a touchscreen file of one point was listed as
    "1 points, 0.031623–0.031623 Hz" among three grids that all differ."""
    total, skin, ts = _measurements()
    one = ix.make_spectrum(ts["frequency"].values[3:4], _flat(ts)[:, 3:4], dims=("trial",), coords={"trial": ts["trial"].values})
    skin = _with(skin, freq=skin["frequency"].values * 1.5)
    with pytest.raises(ix.DataError, match=r"the frequencies of all three files differ") as info:
        gap_analysis(total, skin, one, area=AREA, method="pooled", progress=False)
    f = float(ts["frequency"].values[3])
    assert f"touchscreen: 1 point, {f:.6g} Hz;" in str(info.value) and not re.search(r"\b1 points", str(info.value)), str(info.value)


# --- 3. the same input twice ---------------------------------------------------------------------


def test_same_file_twice_is_refused(tmp_path, capsys):
    paths = saved_gap_files(tmp_path, _measurements())
    code, _, err = _run(["gap", paths[0], paths[1], paths[1], "--area", "130e-6", "--pooled"], capsys)
    assert code == 2
    assert f"skin and touchscreen are the same file, {paths[1]}" in err


def test_identical_spectra_in_two_files_are_refused(tmp_path, capsys):
    total, skin, ts = _measurements()
    paths = saved_gap_files(tmp_path, [total, skin, skin])
    code, _, err = _run(["gap", *paths, "--area", "130e-6", "--pooled"], capsys)
    assert code == 2
    assert f"skin ({paths[1]}) and touchscreen ({paths[2]}) hold identical spectra" in err


# --- 4. the spectra used, per file ---------------------------------------------------------------


@pytest.mark.slow  # (an end-to-end run of ~10 s: make test-all; the fast suite's 15-minute budget)
def test_select_reports_the_spectra_used_per_file(tmp_path, capsys):
    total, skin, ts = _measurements(n_trials=5)
    paths = saved_gap_files(tmp_path, [total, skin.isel(trial=[0, 1, 2]), ts])
    out = tmp_path / "result.json"
    code, text, _ = _run(["gap", *paths, "--area", "130e-6", "--pooled", "--steps", "20", "--quiet", "--select", "trial=2:4", "--out", str(out)], capsys)
    assert code == 0
    trials = json.loads(out.read_text())["trials"]
    assert trials["total"]["count"] == 3 and trials["total"]["labels"] == [2, 3, 4] and trials["total"]["dims"] == ["trial"]
    assert trials["skin"]["count"] == 2 and trials["skin"]["labels"] == [2, 3]  # (the skin file holds trials 1-3)
    assert trials["touchscreen"]["labels"] == [2, 3, 4] and trials["touchscreen"]["by_position"] == []
    assert "spectra used    total 3 (trial 2, 3, 4) [selected trial=2:4]; skin 2 (trial 2, 3) [selected trial=2:4]; touchscreen 3 (trial 2, 3, 4) [selected trial=2:4]" in text  # (the selection named since 2026-12-02)
    assert "positions" not in text


def test_select_by_position_in_one_file_is_reported(tmp_path, capsys):
    """A skin file without trial labels: trial=1:2 picks positions 1, 2 there (its 2nd and 3rd
    spectra) but the trials labelled 1 and 2 in the others; the report says so."""
    total, skin, ts = _measurements(n_trials=4)
    unlabelled = ix.make_spectrum(skin["frequency"].values, _flat(skin), dims=("trial",))
    paths = saved_gap_files(tmp_path, [total, unlabelled, ts])
    code, text, _ = _run(["gap", *paths, "--area", "130e-6", "--pooled", "--steps", "20", "--quiet", "--select", "trial=1:2", "--json"], capsys)
    assert code == 0
    document = json.JSONDecoder().raw_decode(text)[0]
    assert document["trials"]["skin"]["by_position"] == ["trial"] and document["trials"]["skin"]["labels"] == [1, 2]
    assert document["trials"]["total"]["labels"] == [1, 2] and document["trials"]["total"]["by_position"] == []
    assert any("skin has no labels along trial" in w and "labels in total and touchscreen" in w for w in document["warnings"])


def test_trials_over_two_dimensions_list_each_spectrum():
    from impedax.models.gap_inputs import spectra_used

    total, skin, ts = _measurements(n_trials=4)
    z = _flat(total).reshape(2, 2, -1)
    two = ix.make_spectrum(total["frequency"].values, z, dims=("session", "trial"), coords={"session": ["a", "b"], "trial": [1, 2]})
    used = spectra_used(two, skin, ts)
    assert used["total"] == {"count": 4, "dims": ["session", "trial"], "labels": [["a", 1], ["a", 2], ["b", 1], ["b", 2]], "by_position": [], "source": two.attrs.get("source")}
    assert used["skin"]["count"] == 4 and used["skin"]["labels"] == [1, 2, 3, 4]


# --- 5. force: plausible parameters --------------------------------------------------------------


def test_force_ranges_are_1000x_the_thesis_values_and_gaps_area():
    from impedax.models import gap, plausible

    thesis = {"C_s": 140e-12, "C_i": 1.7e-9, "R_sc": 130e3, "C_sc": 2.2e-9, "R_f": 500.0}  # PHYSICS.md, thesis eq 3.13
    for name, value in thesis.items():
        np.testing.assert_allclose(plausible.plausible_range("meyer", name), (value / 1e3, value * 1e3))
    assert plausible.plausible_range("meyer", "area") == gap.FINGERTIP_AREA_M2 == (1e-6, 1e-2)


@pytest.mark.parametrize("param, fragment", [
    ("C_sc=2.2", "C_sc = 2.2 F is implausible"),
    ("C_sc=2.2", "2.2n (2.2 nF) was likely meant"),
    ("area=50", "50 mm² is 5e-05"),
    ("R_sc=0.13", "plausible 130 Ω–130 MΩ"),
    ("C_i=1.7m", "C_i = 1.7 mF is implausible"),
    ("C_i=1.7m", "1.7n (1.7 nF) was likely meant"),
])
def test_force_refuses_implausible_parameters(tmp_path, capsys, param, fragment):
    out = tmp_path / "force.csv"
    code, _, err = _run(["force", "meyer", "--param", param, "--points", "3", "--out", str(out)], capsys)
    assert code == 2
    assert f"--param {param.split('=')[0]}=" in err and "implausible" in err and fragment in err
    assert not out.exists()


def test_force_plausible_values_and_no_param_check(capsys):
    code, _, _ = _run(["force", "meyer", "--param", "C_sc=2.2n", "--param", "area=50e-6", "--points", "3"], capsys)
    assert code == 0
    code, _, err = _run(["force", "meyer", "--param", "C_sc=2.2", "--points", "3", "--no-param-check"], capsys)
    assert code == 0 and "warning: --param C_sc=2.2" in err


def test_force_drive_and_vezzoli_ranges_come_from_the_papers():
    """Oracle: the papers' numbers (docs/physics.md). Drives: gap's 1 V–2 kV. Vezzoli: h_i 10×
    beyond 1 µm (Figs 8–10) and 90 µm (Table 2), h_s 10× beyond Fig 8's 100–500 µm, rho_s 100×
    either way of Table 2's 3.0e4 Ω m, whose eq 8 corners 1/(2π ε0 ε_s ρ_s) then span the paper's
    100 Hz–10 kHz."""
    from impedax.models import gap, plausible

    assert plausible.plausible_range("meyer", "v_a") == plausible.plausible_range("vezzoli", "v_m") == gap.DRIVE_VOLTAGE_V == (1.0, 2e3)
    np.testing.assert_allclose(plausible.plausible_range("vezzoli", "h_i"), (1e-6 / 10, 90e-6 * 10))
    np.testing.assert_allclose(plausible.plausible_range("vezzoli", "h_s"), (100e-6 / 10, 500e-6 * 10))
    np.testing.assert_allclose(plausible.plausible_range("vezzoli", "rho_s"), (3.0e4 / 100, 3.0e4 * 100))
    corners = [1 / (2 * np.pi * 8.8541878128e-12 * 2340 * rho) for rho in plausible.plausible_range("vezzoli", "rho_s")]
    assert corners[1] < 100 and corners[0] > 10e3
    assert plausible.plausible_range("vezzoli", "v_a") is None and plausible.plausible_range("meyer", "h_i") is None


def _eq10(freq, *, h_i=90e-6, h_s=350e-6, area=1e-4, eps_i=3.35, eps_s=2340.0, rho_s=3.0e4, v_m=2000.0):
    """Vezzoli eq 10 by hand (docs/physics.md), Table 2 defaults."""
    wt = 2 * np.pi * freq * 8.8541878128e-12 * eps_s * rho_s
    return 8.8541878128e-12 * area * v_m**2 / (4 * (h_i + h_s) * (h_i / eps_i + h_s / eps_s)) * wt**2 / (1 + wt**2)


@pytest.mark.parametrize("model, param, fragments", [
    ("meyer", "v_a=140k", ["v_a = 140 kV is implausible", "plausible 1 V–2 kV", "140 (140 V) was likely meant"]),
    ("meyer", "v_a=0.14", ["v_a = 140 mV is implausible", "plausible 1 V–2 kV", "140 (140 V) was likely meant"]),
    ("vezzoli", "v_m=2M", ["v_m = 2 MV is implausible", "plausible 1 V–2 kV", "2k (2 kV) was likely meant"]),
    ("vezzoli", "h_i=90", ["h_i = 90 m is implausible", "plausible 100 nm–900 µm", "90u (90 µm) was likely meant"]),
    ("vezzoli", "h_s=350", ["h_s = 350 m is implausible", "plausible 10 µm–5 mm", "350u (350 µm) was likely meant"]),
    ("vezzoli", "rho_s=30", ["rho_s = 30 Ω m is implausible", "plausible 300 Ω m–3 MΩ m", "30k (30 kΩ m) was likely meant"]),
])
def test_force_warns_of_an_implausible_drive_thickness_or_resistivity_and_computes(capsys, model, param, fragments):
    """A unit slip in the drive, a thickness or the resistivity is warned about (stderr and the
    JSON's warnings, naming the --param, its value with unit and the range), not refused."""
    code, out, err = _run(["force", model, "--param", param, "--fmin", "440", "--fmax", "440", "--points", "1", "--json"], capsys)
    assert code == 0
    document = json.loads(out)
    [warning] = [w for w in document["warnings"] if "implausible" in w]
    assert warning.startswith(f"--param {param.split('=')[0]}=") and "most likely a unit slip" in warning
    assert all(f in warning for f in fragments), warning
    assert f"warning: {warning}" in err
    if model == "vezzoli":  # computed as given: eq 10 with the slipped value
        name, value = param.split("=")
        given = {"v_m": 2e6, "h_i": 90.0, "h_s": 350.0, "rho_s": 30.0}[name]
        assert document["force_n"][0] == pytest.approx(_eq10(440.0, **{name: given}), rel=1e-9)


@pytest.mark.parametrize("param", ["eps_i=0.5", "eps_s=0.9", "eps_i=8.85e-12"])
def test_force_refuses_a_relative_permittivity_below_1(tmp_path, capsys, param):
    """No material's relative permittivity is below vacuum's 1 (2026-12-03: eps_i=0.5 computed
    without a word); 8.85e-12 is ε0, an absolute permittivity in F/m given for a relative one."""
    out = tmp_path / "force.csv"
    code, _, err = _run(["force", "vezzoli", "--param", param, "--points", "3", "--out", str(out)], capsys)
    name, value = param.split("=")
    assert code == 2 and f"--param {name} = {float(value):g} is below 1" in err and "relative permittivity" in err
    assert not out.exists()


@pytest.mark.parametrize("param, high", [("eps_s=1e9", 100 * 2340.0), ("eps_i=5000", 100 * 36.0)])
def test_force_warns_of_a_very_large_relative_permittivity_and_computes(capsys, param, high):
    """ε_s 1e9 or ε_i 5000 is warned about as h_i, h_s, rho_s are (stderr and the JSON's warnings),
    and computed as given (eq 10 by hand); the range's top is 100× the paper's value (Table 2's
    ε_s 2340, Fig 9's largest ε_i 36), and no unit slip is suggested (ε_r has no unit)."""
    code, out, err = _run(["force", "vezzoli", "--param", param, "--fmin", "440", "--fmax", "440", "--points", "1", "--json"], capsys)
    assert code == 0
    document = json.loads(out)
    [warning] = [w for w in document["warnings"] if "implausible" in w]
    name, value = param.split("=")
    assert warning.startswith(f"--param {name}=") and f"{name} = {float(value):g} is implausible (plausible 1–{high:g}" in warning and "unit slip" not in warning
    assert f"warning: {warning}" in err
    assert document["force_n"][0] == pytest.approx(_eq10(440.0, **{name: float(value)}), rel=1e-9)


@pytest.mark.filterwarnings("ignore:Vezzoli eq 8 assumes")  # (eps_s = 1 puts C_i/C_s above eq 8's 0.1: warned, not the point here)
def test_the_force_models_refuse_a_relative_permittivity_below_1_in_python():
    """The same rule in Python for every permittivity of the force models: Vezzoli's eps_i, eps_s,
    Meyer's MeyerPhysical and static forces (eps_i, eps_sc) and Sirin's eps_gap; 1 itself (vacuum)
    is accepted."""
    from impedax.errors import ParameterError
    from impedax.models import meyer, sirin, vezzoli

    calls = {
        "eps_i": lambda e: vezzoli.electrovibration_force(440.0, eps_i=e),
        "eps_s": lambda e: vezzoli.voltage_for_force(0.01, 440.0, eps_s=e),
        "MeyerPhysical.eps_sc": lambda e: meyer.MeyerPhysical(eps_sc=e),
        "eps_sc": lambda e: meyer.static_force_f2(10.0, area=1e-4, d_sc=2e-4, eps_sc=e),
        "eps_gap": lambda e: sirin.gap_thickness(413e-12, eps_gap=e),
    }
    for name, call in calls.items():
        with pytest.raises(ParameterError, match=rf"^{re.escape(name)} = 0\.5 is below 1: a relative permittivity"):
            call(0.5)
        call(1.0)
    with pytest.raises(ParameterError, match="eps_gap = 0.5 is below 1"):
        f, *spectra = sirin_measurements(np.random.default_rng(0), 2)
        gap_analysis(*(ix.make_spectrum(f, z, dims=("trial",)) for z in spectra), area=130e-6, eps_gap=0.5, progress=False)


def test_force_paper_values_give_no_plausibility_warning_and_eq8_warning_stays(capsys):
    """Fig 8's 1 µm insulator is plausible (no unit-slip warning) yet outside eq 8's C_i ≪ C_s:
    C_i/C_s = 3.35·350/(2340·1) = 0.501, still warned about; Table 2 and 140 V warn of nothing."""
    code, out, _ = _run(["force", "vezzoli", "--param", "h_i=1u", "--fmin", "440", "--fmax", "440", "--points", "1", "--json"], capsys)
    assert code == 0
    [warning] = json.loads(out)["warnings"]
    assert "C_i/C_s = ε_i h_s/(ε_s h_i) = 0.501" in warning and "implausible" not in warning
    code, out, _ = _run(["force", "meyer", "--param", "v_a=140", "--fmin", "37k", "--fmax", "37k", "--points", "1", "--json"], capsys)
    assert code == 0 and json.loads(out)["warnings"] == []
    code, out, _ = _run(["force", "vezzoli", "--param", "h_s=350", "--param", "h_i=90u", "--fmin", "440", "--fmax", "440", "--points", "1", "--json"], capsys)
    warnings = json.loads(out)["warnings"]
    assert len(warnings) == 2 and "implausible" in warnings[0] and "Vezzoli eq 8 assumes C_i ≪ C_s" in warnings[1]


# --- 6. negative numbers as option values --------------------------------------------------------


@pytest.mark.parametrize("argv, fragment", [
    (["--area", "-1e-4"], "--area must be positive (m²), got -0.0001"),
    (["--v0", "-75"], "--v0 must be positive (V), got -75"),
    (["--area", "-130u"], "--area must be positive (m²), got -0.00013"),
])
def test_gap_negative_values_reach_the_check(tmp_path, capsys, argv, fragment):
    paths = saved_gap_files(tmp_path, _measurements())
    base = ["--area", "130e-6"] if argv[0] != "--area" else []
    code, _, err = _run(["gap", *paths, *base, *argv, "--pooled"], capsys)
    assert code == 2
    assert fragment in err and "expected one argument" not in err


def test_force_negative_frequency_reaches_the_check(capsys):
    code, _, err = _run(["force", "meyer", "--fmin", "-1e1", "--points", "3"], capsys)
    assert code == 2
    assert "--fmin must be positive, got -10" in err and "expected one argument" not in err  # (the option named, as fit's: 2026-12-06)


@pytest.mark.parametrize("model, param", [("vezzoli", "v_m=5000"), ("meyer", "v_a=5k"), ("meyer", "v_a=20k")])
def test_a_drive_of_a_few_kilovolts_is_a_high_voltage_drive_not_a_unit_slip(capsys, model, param):
    """2–20 kV (up to 10× the papers' largest drive) is warned about as a high-voltage drive; the
    force is computed as given (eq 10 ∝ V², checked by hand for vezzoli); no "5 V was likely meant"."""
    code, out, err = _run(["force", model, "--param", param, "--fmin", "440", "--fmax", "440", "--points", "1", "--json"], capsys)
    assert code == 0
    document = json.loads(out)
    [warning] = [w for w in document["warnings"] if param.split("=")[0] in w]
    assert "is above the plausible 1 V–2 kV" in warning and "high-voltage drive" in warning
    assert "likely meant" not in warning and "most likely a unit slip" not in warning
    if model == "vezzoli":
        assert document["force_n"][0] == pytest.approx(_eq10(np.array([440.0]), v_m=5000.0)[0], rel=1e-9)


def test_exchanged_columns_are_named_as_such():
    """A skin file with Z' and Z'' in each other's columns (Z' ↔ Z'' of the SYNTHETIC skin) is told
    the columns look exchanged, as inspect, kk and diagnose say, not given the real-part hint,
    whose fix (−conj Z) turns it into conj of the other reading."""
    total, skin, ts = _measurements()
    z = _flat(skin)
    with pytest.raises(ix.DataError, match=r"skin: Z' and Z'' may be stored in each other's columns"):
        gap_analysis(total, _with(skin, z=z.imag + 1j * z.real), ts, area=AREA, method="pooled", progress=False)
