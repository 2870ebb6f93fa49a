"""What a `--select` leaves in the outputs: the file and the selection (`source`) in the JSON,
the .nc and the figures' titles; inspect's words and preview of a selection, and of a saved
result; the KK batch's count of inconclusive spectra; an honest time left of an auto run."""

import json

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main

F = np.geomspace(1e-1, 1e5, 41)
R1S = [100.0 * 1.3**k for k in range(12)]


@pytest.fixture(scope="module")
def stack(tmp_path_factory):
    """Twelve R0 + R1 ∥ C1 spectra (R1 from 100 Ω up, 0.1 % noise, seed 3) over cycle 0..11,
    with a title that counts them all."""
    rng = np.random.default_rng(3)
    z = np.stack([(10 + r / (1 + 2j * np.pi * F * r * 1e-6)) * (1 + 1e-3 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size))) for r in R1S])
    ds = ix.make_spectrum(F, z, dims=("cycle",)).assign_coords(cycle=np.arange(12))
    ds.attrs["title"] = "test cell, all 12 cycles"
    path = tmp_path_factory.mktemp("stack") / "cycles.nc"
    ix.save(ds, path)
    return str(path)


def run_json(capsys, *argv):
    assert main(list(argv)) == 0
    return json.loads(capsys.readouterr().out)


def test_fit_and_kk_json_and_nc_name_the_file_and_the_selection(stack, tmp_path, capsys):
    out = tmp_path / "fit3.nc"
    summary = run_json(capsys, "fit", stack, "--select", "cycle=3", "--model", "R0 + R1 || C1", "--json", "--out", str(out))
    assert summary["source"] == f"{stack} [cycle=3]"
    assert abs(summary["params"]["R1"]["value"] - R1S[3]) < 0.01 * R1S[3]  # (the pick was fitted)
    assert xr.open_dataset(out).attrs["source"] == f"{stack} [cycle=3]"
    again = ix.load(out)  # (the result's data, read back: errors name this file, the data's own stays)
    assert again.attrs["source"] == str(out) and again.attrs["saved_from"] == f"{stack} [cycle=3]"
    assert run_json(capsys, "kk", stack, "--select", "cycle=3", "--json")["source"] == f"{stack} [cycle=3]"
    assert run_json(capsys, "kk", stack, "--select", "cycle=3:4", "--json")["source"] == f"{stack} [cycle=3:4]"
    assert run_json(capsys, "fit", stack, "--model", "R0 + R1 || C1", "--json")["source"] == stack  # (no selection: the file)


def test_diagnose_json_and_nc_name_the_selection(stack, tmp_path, capsys):
    out = tmp_path / "diag5.nc"
    summary = run_json(capsys, "diagnose", stack, "--select", "cycle=5", "--model", "R0 + R1 || C1", "--json", "--out", str(out), "--noise", "0.1%")
    assert summary["source"] == f"{stack} [cycle=5]"
    assert xr.open_dataset(out).attrs["source"] == f"{stack} [cycle=5]"


def test_a_figure_title_gets_the_file_name_and_the_selection(tmp_path):
    import matplotlib.pyplot as plt

    from impedax.cli.common import figure_writer

    fig = plt.figure(figsize=(11, 5))
    fig.suptitle("R0 + R1 || C1   rms_rel = 1 %")
    figure_writer(lambda: fig, "/some/long/folder/cycles.nc [cycle=3]")(tmp_path / "f.png")
    assert fig._suptitle.get_text() == "R0 + R1 || C1   rms_rel = 1 %\ncycles.nc [cycle=3]"
    plt.close(fig)


def test_kk_batch_counts_inconclusive_spectra_apart(capsys):
    path = "tests/fixtures/dev3000_imps_0_sample_00000.csv"
    assert main(["kk", path]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == "linear KK test of 2 spectra over sweep: 0 KK-consistent, 0 not, 2 inconclusive (too few frequencies to tell)"
    summary = run_json(capsys, "kk", path, "--json")
    assert (summary["n_valid"], summary["n_conclusive"], summary["n_inconclusive"]) == (2, 0, 2)  # (n_valid as before: the contract)
    assert all(s["valid"] and not s["conclusive"] for s in summary["spectra"])


def test_inspect_preview_of_a_selection_draws_every_spectrum_under_a_short_title(stack):
    from impedax.cli.common import load_selected
    from impedax.cli.inspect import PREVIEW_SPECTRA, _preview

    few = _preview(load_selected(stack, ["cycle=2:6"]), "impedax netCDF", stack)
    assert len(few.axes[0].get_lines()) == 5
    assert [t.get_text() for t in few.axes[0].get_legend().get_texts()] == ["2", "3", "4", "5", "6"]
    title = few._suptitle.get_text()
    assert title.startswith("cycles.nc [cycle=2:6]: impedax netCDF") and "5 spectra" in title and stack not in title
    many = _preview(load_selected(stack, None), "impedax netCDF", stack)
    assert len(many.axes[0].get_lines()) == PREVIEW_SPECTRA == 10 and "10 of 12 spectra" in many._suptitle.get_text().replace("\n", " ")


def test_inspect_words_after_a_selection(stack, tmp_path, capsys):
    assert main(["inspect", stack, "--select", "cycle=3:3"]) == 0
    out = capsys.readouterr().out
    assert "  cycle: 1 spectrum (3), selected by --select cycle=3:3" in out and "pick one" not in out
    assert main(["inspect", stack, "--select", "cycle=3,5,9", "--out", str(tmp_path / "s.csv")]) == 2
    assert "the selection holds 3 over cycle: give --out a .nc name, or select one label, e.g. --select cycle=3" in capsys.readouterr().err
    assert main(["inspect", stack, "--select", "cycle=3,5,9", "--out", str(tmp_path / "s.nc")]) == 0
    attrs = xr.open_dataset(tmp_path / "s.nc").attrs
    assert attrs["title"] == "test cell, all 12 cycles [selection: cycle=3,5,9]" and attrs["selection"] == "cycle=3,5,9"


def test_inspect_of_a_saved_posterior_shows_the_data_units_and_says_what_it_is(tmp_path, capsys):
    out = tmp_path / "samp.nc"
    f = np.geomspace(1, 1e5, 30)
    rng = np.random.default_rng(0)
    z = (10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6)) * (1 + 0.01 * rng.normal(size=f.size))
    ix.save(ix.make_spectrum(f, z), tmp_path / "d.csv")
    assert main(["sample", str(tmp_path / "d.csv"), "--model", "R0 + R1 || C1", "--steps", "200", "--walkers", "16", "--quiet", "--out", str(out)]) == 0
    capsys.readouterr()
    assert main(["inspect", str(out)]) == 0
    text = capsys.readouterr().out
    assert "holding a saved single-spectrum posterior" in text and "  units: Hz, ohm\n" in text
    assert "parameter units: R0 [Ohm], R1 [Ohm], C1 [F], sigma_rel [1]" in text
    summary = run_json(capsys, "inspect", str(out), "--json")
    assert summary["units"] == "Hz, ohm" and summary["result_kind"] == "posterior" and summary["parameter_units"]["C1"] == "F"


def test_an_auto_runs_time_left_is_the_least_left_and_never_zero():
    """At step 990 of ≈1000 estimated after 4 s, "~0 s left" was shown while the run went on to
    12 s: under a second to the estimate no time is shown; further from it, the time to it (500
    steps at 4/500 s a step) as the least left."""
    from impedax.fitting.bayes.progress import ProgressLine

    bar = ProgressLine(20000, True, label="sampling", interactive=False, open_ended=True)
    bar.first = (0.0, 0)
    bar.set_target(1000, "50 τ")
    assert bar.text(990, 4.0) == "sampling: step 990 (≈1000 needed for 50 τ; at most 20000), 4 s"
    assert bar.text(500, 4.0) == "sampling: step 500 (≈1000 needed for 50 τ; at most 20000), 4 s, ≥ ~4 s left"
