"""`impedax gap` / `impedax remaining` on files whose dimensions carry text (or date) labels, and
on files with condition dimensions (voltage, material) besides the trials.

The SYNTHETIC data model an electroadhesion gripper's pad on a target: material × voltage ×
trial × frequency, written here in numpy (skin/pad and target R_inf + R ∥ CPE, remainder
R_EP ∥ C_EP ∥ C_gap, 1 % complex noise), as a 2026-12-01 walkthrough built them. Before the fix
every text label stopped both commands with "AttributeError: 'str' object has no attribute
'item'" (`gap_inputs._label`), and voltages were averaged as replicates without a word."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main
from impedax.data import label_value
from impedax.errors import ParameterError
from impedax.models.gap import gap_analysis, gap_remainder
from impedax.models.gap_inputs import condition_notes, is_replicate_dim, spectra_used

EPS0 = 8.8541878128e-12
AREA = 4e-4  # a 4 cm² gripper pad [m²]
F = np.geomspace(1.0, 1e6, 21)
W = 2 * np.pi * F
MATERIALS = ["glass", "wood"]
VOLTS = np.array([50.0, 100.0, 150.0])
TRIALS = ["t1", "t2", "t3", "t4"]


def _r_cpe(r_inf, r, q, alpha):
    return r_inf + 1.0 / (1.0 / r + q * (1j * W) ** alpha)


@pytest.fixture(scope="module")
def gripper():
    """SYNTHETIC (material, voltage, trial, frequency) total, pad and target Datasets, text
    labels on material and trial; the gap shrinks with the voltage, u = u0/(1 + V/300 V)."""
    rng = np.random.default_rng(75)
    shape = (len(MATERIALS), VOLTS.size, len(TRIALS), F.size)
    pad = _r_cpe(200.0, 1e5, 5e-9, 0.85)
    target = _r_cpe(50.0, 2e6, 1e-10, 0.9)
    rem = np.empty(shape, complex)
    for i, u0 in enumerate((4e-6, 12e-6)):
        for j, v in enumerate(VOLTS):
            c_gap = EPS0 * 1.00059 * AREA / (u0 / (1 + v / 300.0))
            rem[i, j] = 1.0 / (1.0 / 2e8 + 1j * W * (1e-9 + c_gap))

    def noisy(z):
        z = np.broadcast_to(z, shape)
        return z * (1 + 0.01 * (rng.normal(size=shape) + 1j * rng.normal(size=shape)))

    coords = {"material": MATERIALS, "voltage": VOLTS, "trial": TRIALS}
    dims = ("material", "voltage", "trial")
    return tuple(ix.make_spectrum(F, noisy(z), dims=dims, coords=coords) for z in (pad + target + rem, pad, target))


def _saved(folder, parts):
    paths = []
    for name, ds in zip(("total", "pad", "target"), parts):
        paths.append(str(folder / f"{name}.nc"))
        ix.save(ds, paths[-1])
    return paths


def _mean(ds):
    z = ds["Z"].transpose(..., "frequency").values
    return z.reshape(-1, z.shape[-1]).mean(axis=0)


# --- 1. labels of every kind ------------------------------------------------------------------


@pytest.mark.parametrize("label, expected", [
    ("t1", "t1"), (np.str_("glass"), "glass"), (np.array(["t2"], dtype=object)[0], "t2"), (b"t3", "t3"),
    (np.int64(4), 4), (7, 7), (np.float64(100.0), 100.0), (np.bool_(True), True),
    (np.datetime64("2026-12-01T10:30:00.000000000"), "2026-12-01T10:30:00.000000000"),
])
def test_label_value_gives_plain_python_for_every_kind_of_label(label, expected):
    value = label_value(label)
    assert value == expected and type(value) is type(expected)
    json.dumps(value)  # (JSON holds it as it is)


def test_spectra_used_reads_text_and_date_labels(gripper):
    """Text labels (an object array from netCDF, a numpy str array) and dates: the labels as
    text, the dates as ISO text, not nanosecond counts."""
    total, pad, target = (ds.sel(material="glass", voltage=100.0) for ds in gripper)
    used = spectra_used(total, pad, target)
    assert used["total"]["labels"] == TRIALS and used["total"]["dims"] == ["trial"]
    as_object = total.assign_coords(trial=np.array(TRIALS, dtype=object))
    assert spectra_used(as_object, pad, target)["total"]["labels"] == TRIALS
    days = np.array(["2026-11-27", "2026-11-28", "2026-11-29", "2026-11-30"], dtype="datetime64[ns]")
    dated = total.assign_coords(trial=days)
    labels = spectra_used(dated, pad, target)["total"]["labels"]
    assert labels == [f"{d}T00:00:00.000000000" for d in ("2026-11-27", "2026-11-28", "2026-11-29", "2026-11-30")]
    mixed = spectra_used(*(ds.sel(material="glass") for ds in gripper))["skin"]["labels"]
    assert mixed[0] == [50.0, "t1"] and mixed[-1] == [150.0, "t4"]


def test_python_gap_remainder_on_text_labels_matches_numpy(gripper):
    total, pad, target = (ds.sel(material="glass", voltage=100.0) for ds in gripper)
    remaining, notes = gap_remainder(total, pad, target)
    np.testing.assert_allclose(remaining["Z"].values, _mean(total) - _mean(pad) - _mean(target), rtol=1e-12)
    assert notes == []


def test_cli_remaining_selects_by_text_label(gripper, tmp_path, capsys):
    """`impedax remaining ... --select material=glass --select voltage=100` on text-labelled
    files: exit 0, the remainder of numpy's subtraction, no condition warning."""
    paths = _saved(tmp_path, gripper)
    out = tmp_path / "rem.csv"
    assert main(["remaining", *paths, "--select", "material=glass", "--select", "voltage=100", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "averaged as replicates" not in err and "from 4 total, 4 skin, 4 touchscreen spectra" in err
    z = ix.load(str(out))["Z"].values
    picked = [ds.sel(material="glass", voltage=100.0) for ds in gripper]
    np.testing.assert_allclose(z, _mean(picked[0]) - _mean(picked[1]) - _mean(picked[2]), rtol=1e-6)


def test_cli_gap_reads_text_labels_up_to_the_sampling(gripper, tmp_path, capsys, monkeypatch):
    """`impedax gap ... --pooled --select material=glass --select voltage=100` passes the
    inputs' labels (where the AttributeError was) and the fits; the sampling is stopped by a
    stand-in that says it was reached (the whole run is the slow test below)."""
    import impedax.fitting as fitting
    from impedax.errors import DataError

    def reached(*args, **kwargs):
        raise DataError("stand-in: the sampling was reached")

    monkeypatch.setattr(fitting, "sample", reached)
    paths = _saved(tmp_path, gripper)
    assert main(["gap", *paths, "--area", "4e-4", "--v0", "100", "--pooled", "--select", "material=glass", "--select", "voltage=100", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "stand-in: the sampling was reached" in err and "Traceback" not in err and "AttributeError" not in err
    assert "averaged as replicates" not in err  # (one material, one voltage: nothing mixed)
    assert main(["gap", *paths, "--area", "4e-4", "--v0", "100", "--pooled", "--select", "material=glass", "--quiet"]) == 2
    early = [line for line in capsys.readouterr().err.splitlines() if line.startswith("impedax gap: warning: ")]
    assert len(early) == 1 and early[0].startswith("impedax gap: warning: voltage (3 labels: 50, 100, 150)")  # (on stderr before the sampling)


@pytest.mark.slow
def test_cli_gap_runs_on_text_labels_and_names_the_trials(gripper, tmp_path, capsys):
    """The walkthrough's command (`--pooled --select material=glass`), short chain: exit 0; the
    JSON's trials name t1…t4 and the voltage warning is among its warnings. (Slow: about 18 s,
    most of it compiling the pooled sampler.)"""
    paths = _saved(tmp_path, gripper)
    args = ["gap", *paths, "--area", "4e-4", "--v0", "100", "--pooled", "--steps", "20", "--select", "material=glass", "--json", "--quiet"]
    assert main(args) == 0
    captured = capsys.readouterr()
    out = json.loads(captured.out)
    assert out["trials"]["total"]["dims"] == ["voltage", "trial"]
    assert out["trials"]["total"]["labels"][:2] == [[50.0, "t1"], [50.0, "t2"]]
    voltage = [w for w in out["warnings"] if w.startswith("voltage (3 labels: 50, 100, 150) of total, skin and touchscreen is averaged as replicates")]
    assert len(voltage) == 1 and "--select voltage=LABEL" in voltage[0]
    assert not any(w.startswith(("material (", "trial (")) for w in out["warnings"])
    assert "warning(s), see the JSON 'warnings'" in captured.err and "Traceback" not in captured.err


# --- 3. condition dimensions averaged as replicates ---------------------------------------------


@pytest.mark.parametrize("dim, replicate", [
    ("trial", True), ("trials", True), ("trial_id", True), ("sweepIndex", True), ("Session", True), ("cycle", True),
    ("repeats", True), ("run", True), ("voltage", False), ("material", False), ("report", False), ("dim_0", False), ("temperature", False),
    ("location", True), ("locations", True), ("site", True), ("electrode", False),  # (Sirin: 5 screen locations averaged; hydrogel vs metal electrode a condition)
])
def test_replicate_dims_are_known_by_a_word_of_their_name(dim, replicate):
    assert is_replicate_dim(dim) is replicate


def test_condition_notes_name_each_condition_dim_once(gripper):
    notes = condition_notes(*gripper)
    assert [n.split(" (")[0] for n in notes] == ["material", "voltage"]
    assert notes[0].startswith("material (2 labels: glass, wood) of total, skin and touchscreen is averaged as replicates")
    assert "--select material=LABEL (Python: data.sel(material=LABEL)), e.g. --select material=glass" in notes[0]
    assert notes[1].startswith("voltage (3 labels: 50, 100, 150)") and notes[1].endswith("e.g. --select voltage=50")
    one_voltage = [ds.sel(material="glass", voltage=[100.0]) for ds in gripper]  # (a dimension of one spectrum mixes nothing)
    assert condition_notes(*one_voltage) == []
    sessions = [ds.sel(material="glass").rename(voltage="session") for ds in gripper]
    assert condition_notes(*sessions) == []
    unlabelled = [ds.sel(material="glass").drop_vars("voltage") for ds in gripper]
    assert condition_notes(*unlabelled)[0].startswith("voltage (3 positions: 0, 1, 2)")


def test_sirin_touchscreen_over_locations_is_no_condition():
    """Sirin et al. measured the touchscreen at 5 locations × 10 trials ("to cover the whole
    surface") and averaged them; a SYNTHETIC screen file of that layout drew "location (5
    labels: 1, 2, 3, 4, 5) of touchscreen is averaged as replicates ... if location is a
    condition ..., analyse one at a time with --select location=LABEL", advice against the
    paper's own method. A skin file over the paper's two electrode types still draws it."""
    freq = np.geomspace(1.0, 1e6, 7)
    z = 90.0 + 1.7e5 / (1 + 1.7e5 * 1.184e-9 * (2j * np.pi * freq) ** 0.92)
    screen = ix.make_spectrum(freq, np.broadcast_to(z, (5, 10, freq.size)) * (1 + 0.01 * np.arange(50).reshape(5, 10, 1)), dims=("location", "trial"),
                              coords={"location": [1, 2, 3, 4, 5], "trial": list(range(1, 11))})
    total = ix.make_spectrum(freq, np.stack([10 * z, 11 * z]), dims=("trial",))
    skin = ix.make_spectrum(freq, np.stack([z, 1.1 * z]), dims=("trial",))
    assert condition_notes(total, skin, screen) == []
    electrodes = ix.make_spectrum(freq, np.stack([z, 1.1 * z]), dims=("electrode",), coords={"electrode": ["hydrogel", "metal"]})
    notes = condition_notes(total, electrodes, screen)
    assert len(notes) == 1 and notes[0].startswith("electrode (2 labels: hydrogel, metal) of skin is averaged as replicates")


def test_cli_remaining_warns_of_the_voltages_it_averages(gripper, tmp_path, capsys):
    """The walkthrough's `impedax remaining ... --select material=glass`: 12 spectra of three
    voltages averaged as one remainder, silently; now a warning on stderr naming voltage."""
    paths = _saved(tmp_path, gripper)
    assert main(["remaining", *paths, "--select", "material=glass", "--out", str(tmp_path / "r.nc")]) == 0
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("impedax remaining: warning: ")]
    assert len(lines) == 1 and lines[0].removeprefix("impedax remaining: warning: ").startswith("voltage (3 labels: 50, 100, 150)")
    assert "--select voltage=" in lines[0] and "from 12 total, 12 skin, 12 touchscreen spectra" in err


# --- 4. a contact other than a fingertip --------------------------------------------------------


def test_gripper_pad_area_refusal_names_the_override(gripper, tmp_path, capsys):
    """A 0.04 m² (20 cm × 20 cm) gripper pad: refused as an implausible contact area (a fingertip's
    range named; since 2026-12-02 the pad is not called a fingertip), and the message names the
    way to analyse it, on the command line and in Python."""
    paths = _saved(tmp_path, gripper)
    assert main(["gap", *paths, "--area", "0.04", "--select", "material=glass", "--select", "voltage=100"]) == 2
    err = capsys.readouterr().err
    assert "0.04 m² (40000 mm²) is not a plausible contact area (a fingertip's is" in err and "--no-area-check" in err and "check_area=False" in err
    assert "Traceback" not in err
    with pytest.raises(ParameterError, match=r"--no-area-check \(Python: gap_analysis\(\.\.\., check_area=False\)\)"):
        gap_analysis(*gripper, area=0.04, method="pooled", progress=False)
