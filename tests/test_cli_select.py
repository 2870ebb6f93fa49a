"""`--select DIM=LABEL`: one spectrum of a file that holds several, for every command that takes
one (diagnose, refine, compare, kk --plot, kk --method zhit) and for fit, kk, drt, sample and
inspect; kk and drt without it: every spectrum of the file. The spectra are
written here from a closed form (R0 + R1 ∥ C1 with a different R1 each), so a wrong pick
shows in the fitted values."""

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main

F = np.geomspace(1e-1, 1e5, 41)
R0, C1 = 10.0, 1e-6
R1_OF = {"a": 100.0, "b": 400.0, "c": 1600.0}


def rc(r1, rng):
    """R0 + R1 ∥ C1 from its transfer function, with 0.1 % complex noise."""
    z = R0 + r1 / (1 + 1j * 2 * np.pi * F * r1 * C1)
    return z * (1 + 1e-3 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)))


@pytest.fixture(scope="module")
def stacks(tmp_path_factory):
    """Three files of the same three spectra: labels as text, labels as numbers, no labels."""
    rng = np.random.default_rng(7)
    z = np.stack([rc(r1, rng) for r1 in R1_OF.values()])
    folder = tmp_path_factory.mktemp("stacks")
    paths = {}
    for name, coords in (("text", list(R1_OF)), ("numbers", [0.5, 1.0, 2.0]), ("none", None)):
        ds = ix.make_spectrum(F, z, dims=("trial",))
        ds = ds.drop_vars("trial", errors="ignore")
        if coords is not None:
            ds = ds.assign_coords(trial=coords)
        paths[name] = str(folder / f"{name}.nc")
        ix.save(ds, paths[name])
    return paths


def json_out(args, capsys):
    assert main(args) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("kind, label, expected", [("text", "b", "b"), ("numbers", "1", "b"), ("numbers", "2.0", "c"), ("none", "0", "a"), ("none", "2", "c")])
def test_fit_of_the_selected_spectrum_finds_its_own_resistance(stacks, kind, label, expected, capsys):
    out = json_out(["fit", stacks[kind], "--model", "R0 + R1 || C1", "--select", f"trial={label}", "--json"], capsys)
    assert out["params"]["R1"]["value"] == pytest.approx(R1_OF[expected], rel=0.01)
    assert out["params"]["R0"]["value"] == pytest.approx(R0, rel=0.02)


def test_kk_of_the_selected_spectrum_equals_the_api_on_that_spectrum(stacks, capsys):
    out = json_out(["kk", stacks["text"], "--select", "trial=c", "--json"], capsys)
    expected = ix.kk_test(ix.load(stacks["text"]).isel(trial=2))
    assert out["rms_rel"] == pytest.approx(expected.rms_rel, rel=1e-12)
    assert out["n_rc"] == expected.n_rc


def test_without_select_a_fit_is_a_batch_and_the_rest_ask_for_a_pick(stacks, tmp_path, capsys):
    out = json_out(["fit", stacks["text"], "--model", "R0 + R1 || C1", "--json"], capsys)
    assert out["n_spectra"] == 3
    one_spectrum = {
        "impedax diagnose": ["diagnose", "--model", "R0 + R1 || C1"], "impedax refine": ["refine", "--model", "R0 + R1 || C1"],
    }
    for name, args in one_spectrum.items():
        assert main([args[0], stacks["text"], *args[1:]]) == 2
        err = capsys.readouterr().err
        assert err.count("error:") == 1 and f"{name} takes one spectrum" in err
        assert "3 over trial (trial: a, b, c)" in err and "--select trial=LABEL, e.g. --select trial=a" in err
    assert not (tmp_path / "kk.png").exists()


def test_drt_without_select_solves_every_spectrum_of_the_file(stacks, tmp_path, capsys):
    """The DRT of R0 + R1 ∥ C1 is one peak of area R1 at τ = R1·C1."""
    out = json_out(["drt", stacks["text"], "--json"], capsys)
    assert out["dims"] == ["trial"] and out["n_spectra"] == 3
    for spectrum, (label, r1) in zip(out["spectra"], R1_OF.items()):
        assert spectrum["labels"] == {"trial": label} and len(spectrum["peaks"]) == 1
        peak = spectrum["peaks"][0]
        assert peak["r_ohm"] == pytest.approx(r1, rel=0.1) and peak["tau_s"] == pytest.approx(r1 * C1, rel=0.3)
        assert spectrum["r_inf_ohm"] == pytest.approx(R0, rel=0.05)
    csv, png, nc = tmp_path / "drt.csv", tmp_path / "drt.png", tmp_path / "drt.nc"
    assert main(["drt", stacks["text"], "--out", str(csv), "--plot", str(png)]) == 0
    text = capsys.readouterr().out
    assert text.startswith("DRT of 3 spectra") and "trial=b: rms_rel" in text
    lines = csv.read_text().splitlines()
    n_tau = len(out["spectra"][0]["tau_s"])
    assert lines[0].startswith("trial,tau_s,gamma_ohm,gamma_q05_ohm,gamma_q95_ohm,impedax_version,") and len(lines) == 1 + 3 * n_tau  # (then the provenance: docs/io.md)
    assert [ln.split(",")[0] for ln in lines[1 :: n_tau]] == ["a", "b", "c"] and png.stat().st_size > 10_000
    assert main(["drt", stacks["text"], "--out", str(nc)]) == 0
    saved = ix.io.read_netcdf(nc)  # written as write_result writes it: complex Z restored
    assert saved.sizes["trial"] == 3 and np.iscomplexobj(saved["Z"].values) and np.allclose(saved["rms_rel"].values, [s["rms_rel"] for s in out["spectra"]])


def test_kk_without_select_tests_every_spectrum_of_the_file(stacks, capsys):
    out = json_out(["kk", stacks["numbers"], "--json"], capsys)
    data = ix.load(stacks["numbers"])
    assert out["dims"] == ["trial"] and out["n_spectra"] == 3
    assert [s["labels"] for s in out["spectra"]] == [{"trial": 0.5}, {"trial": 1.0}, {"trial": 2.0}]
    for i, spectrum in enumerate(out["spectra"]):
        one = ix.kk_test(data.isel(trial=i))
        assert spectrum["rms_rel"] == pytest.approx(one.rms_rel, rel=1e-9) and spectrum["valid"] == bool(one.valid)
    assert out["n_valid"] == sum(s["valid"] for s in out["spectra"])
    out = json_out(["kk", stacks["none"], "--json"], capsys)  # no coordinate: positions
    assert [s["labels"] for s in out["spectra"]] == [{"trial": 0}, {"trial": 1}, {"trial": 2}]
    assert main(["kk", stacks["text"]]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("linear KK test of 3 spectra over trial: ") and [ln.split()[0] for ln in lines[2:]] == ["trial=a", "trial=b", "trial=c"]


@pytest.mark.parametrize(
    "select, fragment",
    [
        ("trial=d", "no spectrum of"),
        ("trial", "expected DIM=LABEL"),
        ("=b", "expected DIM=LABEL"),
        ("cycle=1", "has no dimension 'cycle' to select from; its dimensions besides frequency: trial"),
        ("frequency=1", "has no dimension 'frequency'"),
    ],
)
def test_a_bad_selection_is_one_message_and_exit_2(stacks, select, fragment, capsys):
    assert main(["kk", stacks["text"], "--select", select]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and fragment in err and "Traceback" not in err
    if select == "trial=d":
        assert "its trial labels: a, b, c" in err


def test_positions_where_a_dimension_has_no_labels(stacks, capsys):
    for label in ("3", "-1", "x"):
        assert main(["kk", stacks["none"], "--select", f"trial={label}"]) == 2
        assert "has no labels along trial; give a position 0..2" in capsys.readouterr().err


def test_the_same_dimension_twice_and_a_single_spectrum_file(stacks, tmp_path, capsys):
    assert main(["kk", stacks["text"], "--select", "trial=a", "--select", "trial=b"]) == 2
    assert "trial given twice" in capsys.readouterr().err
    one = tmp_path / "one.csv"
    ix.save(ix.make_spectrum(F, rc(100.0, np.random.default_rng(1))), one)
    assert main(["kk", str(one), "--select", "trial=a"]) == 2
    assert "it holds one spectrum" in capsys.readouterr().err


def test_diagnose_and_drt_run_on_the_pick(stacks, capsys):
    # (one effect: the pick, not the catalog, is under test; all eight took 3 s more)
    out = json_out(["diagnose", stacks["text"], "--model", "R0 + R1 || C1", "--select", "trial=b", "--effects", "series_resistance", "--json"], capsys)
    assert out["verdict"] == "adequate"
    # each spectrum has noise of its own, so each fit's misfit tells the spectra apart
    misfit = [ix.fit("R0 + R1 || C1", ix.load(stacks["text"]).isel(trial=i)).rms_rel for i in range(3)]
    assert out["baseline"]["rms_rel"] == pytest.approx(misfit[1], rel=1e-6)
    assert min(abs(misfit[1] - misfit[0]), abs(misfit[1] - misfit[2])) > 1e-3 * misfit[1]
    out = json_out(["drt", stacks["text"], "--select", "trial=c", "--json"], capsys)
    assert out["r_inf_ohm"] == pytest.approx(R0, rel=0.05)


def test_inspect_lists_the_labels_and_shows_the_pick(stacks, capsys):
    out = json_out(["inspect", stacks["numbers"], "--json"], capsys)
    assert out["labels"] == {"trial": [0.5, 1.0, 2.0]} and out["dims"]["trial"] == 3
    assert main(["inspect", stacks["text"]]) == 0
    assert "trial: 3 spectra (a, b, c); pick one with --select trial=LABEL" in capsys.readouterr().out
    out = json_out(["inspect", stacks["text"], "--select", "trial=c", "--json"], capsys)
    assert out["labels"] == {} and "trial" not in out["dims"]
    z = R0 + R1_OF["c"] / (1 + 1j * 2 * np.pi * F * R1_OF["c"] * C1)
    assert out["z_abs_max_ohm"] == pytest.approx(np.abs(z).max(), rel=0.01)


@pytest.fixture(scope="module")
def gap_files(tmp_path_factory):
    """Three gap inputs: total and touchscreen over (session, trial), skin over trial only; each
    spectrum an R0 + R1 ∥ C1 of its own R1, so a pick shows in the values."""
    rng = np.random.default_rng(21)
    folder = tmp_path_factory.mktemp("gap")
    trials = [0, 1, 2]
    paths = {}
    for name, sessions in (("total", ["s1", "s2"]), ("skin", None), ("ts", ["s1", "s2"])):
        if sessions is None:
            ds = ix.make_spectrum(F, np.stack([rc(100.0 * (t + 1), rng) for t in trials]), dims=("trial",), coords={"trial": trials})
        else:
            z = np.stack([[rc(100.0 * (t + 1) * (s + 1), rng) for t in trials] for s in range(len(sessions))])
            ds = ix.make_spectrum(F, z, dims=("session", "trial"), coords={"session": sessions, "trial": trials})
        paths[name] = str(folder / f"{name}.nc")
        ix.save(ds, paths[name])
    return paths


class _GapStub:
    warnings = ()
    plot = None  # (no --plot given)

    def summary(self):
        return {"method": "stub"}

    def report(self):
        return "stub"


@pytest.fixture
def gap_inputs(monkeypatch):
    """`impedax gap` with the analysis replaced by a stub that records the three Datasets it
    is given (the analysis itself is tested in test_models_gap.py)."""
    import impedax.models.gap as gap_module

    seen = []
    monkeypatch.setattr(gap_module, "gap_analysis", lambda total, skin, touchscreen, **options: seen.append((total, skin, touchscreen)) or _GapStub())
    return seen


def test_gap_select_narrows_each_file_that_has_the_dimension(gap_files, gap_inputs, capsys):
    files = [gap_files[k] for k in ("total", "skin", "ts")]
    assert json_out(["gap", *files, "--area", "130e-6", "--select", "session=s2", "--json"], capsys) | {"provenance": None} == {"method": "stub", "provenance": None}  # (provenance: docs/io.md)
    (total, skin, ts), = gap_inputs
    assert total["Z"].dims == ("trial", "frequency") and ts["Z"].dims == ("trial", "frequency")
    np.testing.assert_array_equal(total["Z"].values, ix.load(files[0]).sel(session="s2")["Z"].values)
    np.testing.assert_array_equal(ts["Z"].values, ix.load(files[2]).sel(session="s2")["Z"].values)
    np.testing.assert_array_equal(skin["Z"].values, ix.load(files[1])["Z"].values)  # no session: all of it
    assert total.attrs["source"] == f"{files[0]} [session=s2]"
    # without --select every session is a replicate, as before
    assert json_out(["gap", *files, "--area", "130e-6", "--json"], capsys) | {"provenance": None} == {"method": "stub", "provenance": None}
    assert gap_inputs[1][0]["Z"].dims == ("session", "trial", "frequency")


@pytest.mark.parametrize(
    "select, fragment",
    [
        ("session=s9", "--select session=s9: no spectrum of"),
        ("cycle=1", "--select cycle=1: none of"),
        ("session", "expected DIM=LABEL"),
    ],
)
def test_gap_bad_selection_is_one_message_and_exit_2(gap_files, gap_inputs, select, fragment, capsys):
    files = [gap_files[k] for k in ("total", "skin", "ts")]
    assert main(["gap", *files, "--area", "130e-6", "--select", select]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and fragment in err and "Traceback" not in err
    if select == "session=s9":
        assert "its session labels: s1, s2" in err
    if select == "cycle=1":
        assert "has a dimension 'cycle' to select from; their dimensions besides frequency: session, trial" in err
    assert gap_inputs == []  # refused before the analysis


BIOLOGIC = str(Path(__file__).resolve().parents[1] / "tests" / "fixtures" / "real" / "exampleDataBioLogic.mpt")  # (REAL: one spectrum, its attrs say cycle 1)


@pytest.mark.parametrize("label", ["1", "1.0", "0:3", "1:"])
def test_a_label_the_single_spectrum_carries_selects_it(label):
    from impedax.cli.common import load_selected

    data = ix.load(BIOLOGIC)
    assert data.attrs["cycle"] == "1" and "cycle" not in data["Z"].dims  # (as `impedax inspect` shows it)
    picked = load_selected(BIOLOGIC, [f"cycle={label}"])
    assert picked.identical(data)  # a no-op


def test_a_label_the_single_spectrum_does_not_carry_is_refused_with_its_value(capsys):
    assert main(["kk", BIOLOGIC, "--select", "cycle=2"]) == 2
    err = capsys.readouterr().err
    assert "--select cycle=2: the file holds cycle 1 only" in err and BIOLOGIC in err
    assert main(["kk", BIOLOGIC, "--select", "cycle=1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["valid"] is not None
    # a name it carries neither way is refused as before
    assert main(["kk", BIOLOGIC, "--select", "trial=1"]) == 2
    assert "has no dimension 'trial' to select from; it holds one spectrum" in capsys.readouterr().err


def test_a_scalar_coordinate_is_a_carried_label():
    from impedax.cli.common import select_spectra

    z = R0 + 100.0 / (1 + 1j * 2 * np.pi * F * 100.0 * C1)  # R0 + R1 ∥ C1, noise-free
    data = ix.make_spectrum(F, z).assign_coords(cycle=10)  # (a saved selection keeps its label so)
    assert select_spectra(data, "one.nc", ["cycle=10"]).identical(data)
    with pytest.raises(ix.errors.ParameterError, match="the file holds cycle 10 only"):
        select_spectra(data, "one.nc", ["cycle=3"])


def test_a_command_of_several_files_selects_a_label_one_of_them_carries(tmp_path):
    """``impedax gap``'s inputs (`load_selected_files`): a label that one file carries as its
    single spectrum's value (BioLogic's cycle 1) is a no-op there, as with one file, and the
    same message names the value it holds otherwise."""
    from impedax.cli.common import load_selected_files

    z = R0 + 100.0 / (1 + 1j * 2 * np.pi * F * 100.0 * C1)
    other = str(tmp_path / "other.nc")
    ix.save(ix.make_spectrum(F, z), other)
    picked = load_selected_files([BIOLOGIC, other, other], ["cycle=1"])
    assert picked[0].identical(ix.load(BIOLOGIC)) and picked[1].identical(ix.load(other))
    with pytest.raises(ix.errors.ParameterError, match="--select cycle=2: the file holds cycle 1 only"):
        load_selected_files([BIOLOGIC, other, other], ["cycle=2"])
    with pytest.raises(ix.errors.ParameterError, match="none of .* has a dimension 'trial' to select from; each holds one spectrum"):
        load_selected_files([BIOLOGIC, other, other], ["trial=1"])
