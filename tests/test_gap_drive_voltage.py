"""The gap analysis's drive V0 follows the data (2026-12-02): `impedax gap … --select voltage=500`
analysed at the default 75 V without a word (force 0.196 N instead of ~8.7 N, JSON "v0": 75.0).
Now total spectra that carry one voltage set V0 (``v0_from`` "data"), a given --v0 that differs
is warned of, and several voltages keep the default with a warning that says so.

SYNTHETIC data: an electroadhesive gripper's pad, total = Z_TS + (R_EP ∥ CPE_EP ∥ C_gap) + Z_skin
over voltage (100, 500 V) × repeat (3), written here in numpy with 1 % complex noise, seed 78."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.cli.common import select_spectra
from impedax.errors import DataError, ParameterError
from impedax.models.gap import _gap_sampling_warnings, _sampling_notes, _volts_with_interval, check_fingertip_area
from impedax.models.gap_inputs import condition_notes, drive_voltage, is_voltage_name

EPS0 = 8.8541878128e-12  # F/m, CODATA 2018
EPS_AIR = 1.00059  # relative permittivity of air at 1 atm (impedax's EPSILON_AIR)
AREA = 2e-4  # a 2 cm² gripper pad [m²]
GAP = 5e-6  # true air gap [m]
F = np.geomspace(1.0, 1e5, 21)
W = 2 * np.pi * F
VOLTS = np.array([100.0, 500.0])


def _r_cpe(r, q, alpha):
    return 1.0 / (1.0 / r + q * (1j * W) ** alpha)


Z_SKIN = _r_cpe(1e5, 2e-8, 0.8)
Z_TS = _r_cpe(2e3, 5e-9, 0.9)
Z_REM = 1.0 / (1.0 / 15e6 + 2e-9 * (1j * W) ** 0.7 + 1j * W * EPS0 * EPS_AIR * AREA / GAP)


@pytest.fixture(scope="module")
def gripper():
    """SYNTHETIC total (voltage × repeat), skin and screen (repeat) Datasets."""
    rng = np.random.default_rng(78)

    def noisy(z, shape):
        return z * (1 + 0.01 * (rng.normal(size=shape + z.shape) + 1j * rng.normal(size=shape + z.shape)))

    total = ix.make_spectrum(F, noisy(Z_SKIN + Z_TS + Z_REM, (2, 3)), dims=("voltage", "repeat"), coords={"voltage": VOLTS, "repeat": [0, 1, 2]})
    skin = ix.make_spectrum(F, noisy(Z_SKIN, (3,)), dims="repeat", coords={"repeat": [0, 1, 2]})
    screen = ix.make_spectrum(F, noisy(Z_TS, (3,)), dims="repeat", coords={"repeat": [0, 1, 2]})
    return total, skin, screen


def _saved(folder, parts, names=("total", "skin", "ts")):
    paths = []
    for name, ds in zip(names, parts):
        paths.append(str(folder / f"{name}.nc"))
        ix.save(ds, paths[-1])
    return paths


# --- the resolution of V0 ------------------------------------------------------------------------


def test_v0_follows_the_selected_voltage(gripper):
    selected = select_spectra(gripper[0], "total.nc", ["voltage=500"])
    drive = drive_voltage(selected)
    assert (drive.value, drive.source, drive.warnings) == (500.0, "data", ())
    assert drive.note == "V0 = 500 V, the voltage the selected total spectra carry (voltage = 500), taken as the drive's peak amplitude; give --v0 to override"
    assert drive.summary() == {"v0_from": "data", "v0_carried": {"name": "voltage", "label": 500.0, "value_v": 500.0}}
    assert "taken as the drive's peak amplitude" in drive.description
    # Python's data.sel leaves the same scalar coordinate (no --select: not "selected")
    python = drive_voltage(gripper[0].sel(voltage=100.0))
    assert (python.value, python.source) == (100.0, "data") and "the total spectra carry (voltage = 100)" in python.note


def test_a_given_v0_wins_and_a_different_one_is_warned_of(gripper):
    selected = gripper[0].sel(voltage=500.0)
    same = drive_voltage(selected, 500.0)
    assert (same.value, same.source, same.warnings, same.note) == (500.0, "given", (), None)
    other = drive_voltage(selected, 300.0)
    assert (other.value, other.source) == (300.0, "given") and len(other.warnings) == 1
    assert other.warnings[0].startswith("v0 = 300 V (--v0; Python: v0) differs from the voltage the total spectra carry (voltage = 500)")
    assert "leave --v0 out to analyse at the data's 500 V" in other.warnings[0]


def test_no_voltage_keeps_the_default(gripper):
    bare = gripper[0].sel(voltage=500.0).drop_vars("voltage")
    drive = drive_voltage(bare)
    assert (drive.value, drive.source, drive.carried, drive.warnings, drive.note) == (75.0, "default", None, (), None)
    assert drive.summary() == {"v0_from": "default", "v0_carried": None}


def test_several_voltages_keep_the_default_and_the_warning_says_so(gripper):
    drive = drive_voltage(gripper[0])
    assert (drive.value, drive.source) == (75.0, "default")
    note = condition_notes(*gripper, default_v0=drive.value)[0]
    assert note.startswith("voltage (2 labels: 100, 500) of total is averaged as replicates")
    assert "the force is computed at the default V0 = 75 V, not at any of these voltages" in note
    assert "default V0" not in condition_notes(*gripper)[0]  # (impedax remaining: no V0)
    material = [ds.expand_dims(material=["glass", "wood"]) for ds in (gripper[0].sel(voltage=500.0).drop_vars("voltage"), *gripper[1:])]
    assert "default V0" not in condition_notes(*material, default_v0=75.0)[0]  # (a material is no voltage)


@pytest.mark.parametrize("name, says", [
    ("voltage", True), ("Voltage", True), ("V0", True), ("v0", True), ("drive_voltage", True), ("v_drive", True), ("volts", True),
    ("dc_voltage_v", False), ("ac_voltage_mv_rms", False), ("bias_voltage", False), ("V_pp", False), ("version", False),
    ("material", False), ("repeat", False), ("frequency", False),
])
def test_names_that_say_a_drive_voltage(name, says):
    assert is_voltage_name(name) is says


def test_units_attributes_and_labels_that_cannot_serve(gripper):
    one = gripper[0].sel(voltage=500.0)
    in_kv = one.assign_coords(voltage=one["voltage"].assign_attrs(units="kV") * 1e-3)
    in_kv["voltage"].attrs["units"] = "kV"
    drive = drive_voltage(in_kv)
    assert drive.value == pytest.approx(500.0) and drive.source == "data" and "(voltage = 0.5, 500 V)" in drive.note
    attribute = one.drop_vars("voltage").assign_attrs(V0="0.5 kV")
    assert (drive_voltage(attribute).value, drive_voltage(attribute).source) == (500.0, "data")
    gamry = one.drop_vars("voltage").assign_attrs(dc_voltage_v=0.2, ac_voltage_mv_rms=10.0)  # (a potentiostat's bias and small signal: no drive)
    assert drive_voltage(gamry).source == "default" and drive_voltage(gamry).warnings == ()
    negative = one.assign_coords(voltage=-500.0)
    refused = drive_voltage(negative)
    assert (refused.value, refused.source) == (75.0, "default") and "voltage = -500, which is no positive drive amplitude in volts" in refused.warnings[0]
    percent = one.assign_coords(voltage=one["voltage"].assign_attrs(units="%"))
    assert drive_voltage(percent).source == "default" and len(drive_voltage(percent).warnings) == 1
    disagree = one.assign_attrs(V0=300.0)
    assert drive_voltage(disagree).source == "default" and "voltages that disagree (voltage = 500, V0 = 300)" in drive_voltage(disagree).warnings[0]
    assert drive_voltage(one.assign_attrs(V0=500.0)).source == "data"  # (two names, one voltage)


# --- wording ---------------------------------------------------------------------------------------


def test_gap_voltages_have_no_false_precision():
    """The walkthrough's report line "without EP: 99.999927 V (90 %: 99.999925–99.999928 V)"."""
    assert _volts_with_interval({"value": 99.999927, "q05": 99.999925, "q95": 99.999928}) == "100.0 V (90 %: ≈ 100.0 V)"
    assert _volts_with_interval({"value": 99.300, "q05": 99.294, "q95": 99.334}) == "99.30 V (90 %: 99.29–99.33 V)"
    assert _volts_with_interval({"value": 71.0, "q05": 50.2, "q95": 90.4}) == "71 V (90 %: 50.2–90.4 V)"


def test_the_area_error_speaks_of_a_contact_not_a_fingertip():
    with pytest.raises(ParameterError) as info:
        check_fingertip_area(0.04)
    message = str(info.value)
    assert "is not a plausible contact area (a fingertip's is 1e-06–0.01 m², i.e. 1–10000 mm²)" in message and "fingertip contact" not in message


def test_model_comparison_notes_are_not_the_gaps():
    """The walkthrough's `impedax gap --pooled` passed on `impedax sample`'s WAIC and Laplace notes.
    They are told apart as the posterior holds them (`Posterior.model_comparison_notes`,
    `Posterior.own_warnings`), not by their words: a stand-in posterior whose notes begin otherwise."""
    from types import SimpleNamespace

    kept = "the chain is too short to estimate τ (15 draws per walker after burn-in)"
    comparing = ("p_waic = 8.69 is over 2 × the 4 sampled parameters … Do not compare models by this WAIC", "ln Z is unreliable: the posterior is not Gaussian at the MAP along R_EP")
    posterior = SimpleNamespace(own_warnings=(comparing[0], kept, comparing[1]), model_comparison_notes=comparing, warnings=(comparing[0], kept, comparing[1], "least-squares start: a note of the EDL fit"))
    assert _sampling_notes(_gap_sampling_warnings(posterior)) == [kept]


# --- the command line ------------------------------------------------------------------------------


@pytest.fixture
def stopped(monkeypatch):
    """`gap_analysis` replaced by a stand-in that records its keywords and stops the run."""
    import impedax.models.gap as gap_module

    asked = {}

    def reached(total, skin, touchscreen, **options):
        asked.update(options)
        raise DataError("stand-in: the analysis was reached")

    monkeypatch.setattr(gap_module, "gap_analysis", reached)
    return asked


def test_cli_says_once_that_v0_follows_the_selection(gripper, tmp_path, capsys, stopped):
    paths = _saved(tmp_path, gripper)
    assert main(["gap", *paths, "--area", "2e-4", "--select", "voltage=500", "--pooled", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert stopped["v0"] is None  # (gap_analysis finds the data's voltage itself)
    note = "impedax gap: note: V0 = 500 V, the voltage the selected total spectra carry (voltage = 500), taken as the drive's peak amplitude; give --v0 to override"
    assert err.count(note) == 1 and "warning" not in err


def test_cli_warns_of_a_v0_other_than_the_selected_voltage(gripper, tmp_path, capsys, stopped):
    paths = _saved(tmp_path, gripper)
    assert main(["gap", *paths, "--area", "2e-4", "--select", "voltage=500", "--v0", "300", "--pooled", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert stopped["v0"] == 300.0 and "V0 = 500 V, the voltage" not in err
    assert "impedax gap: warning: v0 = 300 V (--v0; Python: v0) differs from the voltage the total spectra carry (voltage = 500)" in err


def test_cli_several_voltages_warn_of_the_default_v0(gripper, tmp_path, capsys, stopped):
    paths = _saved(tmp_path, gripper)
    assert main(["gap", *paths, "--area", "2e-4", "--pooled", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert stopped["v0"] is None and "the force is computed at the default V0 = 75 V, not at any of these voltages" in err
    assert main(["gap", *paths, "--area", "2e-4", "--v0", "300", "--pooled", "--quiet"]) == 2
    assert "default V0" not in capsys.readouterr().err


def test_cli_figure_title_names_the_total_file_and_selection(gripper, tmp_path, capsys, monkeypatch):
    """The gap figure's default title (the `--title` help says it names the data file)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import impedax.models.gap as gap_module
    import impedax.plotting as plotting

    class Drawn:  # (a stand-in result: what the command writes and prints)
        warnings, settings, v0 = (), None, 500.0

        def plot(self):
            fig = plt.figure()
            fig.suptitle("gap analysis")
            return fig

        def summary(self):
            return {"v0": self.v0}

    titles = []
    monkeypatch.setattr(gap_module, "gap_analysis", lambda *a, **k: Drawn())
    monkeypatch.setattr(plotting, "save_figure", lambda fig, path, **k: titles.append(fig._suptitle.get_text()) or open(path, "wb").close())
    paths = _saved(tmp_path, gripper)
    assert main(["gap", *paths, "--area", "2e-4", "--select", "voltage=500", "--json", "--quiet", "--plot", str(tmp_path / "g.png")]) == 0
    capsys.readouterr()
    assert titles == ["gap analysis\ntotal.nc [voltage=500]"]


# --- end to end: the JSON and the force ∝ V0² --------------------------------------------------


@pytest.mark.slow
def test_cli_json_v0_and_the_force_scale_with_v0_squared(gripper, tmp_path, capsys):
    """Four short pooled runs on one set (the first compiles the sampler, ~17 s; the others ~1 s
    each): the selected voltage, --v0 equal to it, --v0 100 and a total without a voltage. The
    same seed gives the same draws, so every force band scales exactly as V0²; the maximum at
    500 V agrees with eq 1 from the true parameters (numpy: F = ½ ε0 ε A |V0 Z_R/Z_total|²/u²)."""
    paths = _saved(tmp_path, gripper)
    bare = _saved(tmp_path, [gripper[0].sel(voltage=500.0).drop_vars("voltage")], names=("bare",))[0]
    common = ["--area", "2e-4", "--pooled", "--steps", "20", "--json", "--quiet"]

    def run(*args, files=paths):
        assert main(["gap", *files, *args, *common]) == 0
        captured = capsys.readouterr()
        return json.loads(captured.out), captured.err

    data, err = run("--select", "voltage=500", "--plot", str(tmp_path / "g.png"))
    assert (data["v0"], data["v0_from"], data["v0_carried"]["name"]) == (500.0, "data", "voltage")
    assert err.count("V0 = 500 V, the voltage the selected total spectra carry") == 1
    assert not any(w.startswith(("sampling: WAIC", "sampling: Laplace")) for w in data["warnings"])
    same, _ = run("--select", "voltage=500", "--v0", "500")
    assert (same["v0"], same["v0_from"]) == (500.0, "given") and not any("differs from the voltage" in w for w in same["warnings"])
    low, _ = run("--select", "voltage=500", "--v0", "100")
    assert (low["v0"], low["v0_from"]) == (100.0, "given") and sum("differs from the voltage the total spectra carry (voltage = 500)" in w for w in low["warnings"]) == 1
    default, _ = run(files=[bare, *paths[1:]])
    assert (default["v0"], default["v0_from"], default["v0_carried"]) == (75.0, "default", None)
    for other, v0 in ((same, 500.0), (low, 100.0), (default, 75.0)):
        for key in ("median", "q05", "q95"):
            np.testing.assert_allclose(np.asarray(other["force_n"][key]), np.asarray(data["force_n"][key]) * (v0 / 500.0) ** 2, rtol=1e-9)
    hand = 0.5 * EPS0 * EPS_AIR * AREA * np.abs(500.0 * Z_REM / (Z_SKIN + Z_TS + Z_REM)) ** 2 / GAP**2
    assert max(data["force_n"]["median"]) == pytest.approx(hand.max(), rel=0.05)  # (8.8 N; the walkthrough's 75 V gave 0.196 N)
