"""`impedax drt` says where the data fail the Kramers–Kronig test, beside the DRT (JSON
``kk_note``): γ fitted to a drift holds it as peaks. The oracle of the band is `ix.kk_test` run
on the same data; the spectra are SYNTHETIC closed forms with a drift written here, and a
spectrum with nothing wrong gets no note."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

FREQ = np.geomspace(0.01, 1e5, 71)
OMEGA = 2 * np.pi * FREQ
# SYNTHETIC 10 Ω + 100 Ω (τ 1 ms) + 300 Ω (τ 3 s), 0.3 % noise
_RNG = np.random.default_rng(1)
CLEAN = (10 + 100 / (1 + 1j * OMEGA * 1e-3) + 300 / (1 + 1j * OMEGA * 3.0)) * (1 + 0.003 * (_RNG.standard_normal(71) + 1j * _RNG.standard_normal(71)) / np.sqrt(2))
DRIFT = np.zeros(71)
DRIFT[:15] = 0.08 * np.linspace(1, 0, 15)  # +8 % at 10 mHz, falling to 0 over the 15 lowest points
DRIFTED = CLEAN * (1 + DRIFT)


@pytest.fixture()
def files(tmp_path):
    paths = {}
    for name, z in (("clean", CLEAN), ("drifted", DRIFTED)):
        paths[name] = tmp_path / f"{name}.csv"
        ix.save(ix.make_spectrum(FREQ, z), paths[name])
    paths["cells"] = tmp_path / "cells.nc"
    ix.save(ix.make_spectrum(FREQ, np.stack([CLEAN, DRIFTED]), dims=("cell",)), paths["cells"])
    return paths


def test_a_drifting_spectrum_gets_the_kk_band_and_the_peak_inside_it(files, capsys):
    kk = ix.kk_test((FREQ, DRIFTED))
    assert not kk.valid
    bands = kk.measured_bands_text()  # (until 2026-12-06 the bands' edges, halfway to the neighbouring points: impedax kk names the flagged points)
    assert main(["drt", str(files["drifted"])]) == 0
    lines = capsys.readouterr().out.splitlines()
    (note,) = [line for line in lines if line.startswith("note: the data fail")]
    assert note.startswith(f"note: the data fail the Kramers–Kronig test at {bands} (impedax kk {files['drifted']} says which points and what to do)")
    slow = max(ix.drt((FREQ, DRIFTED)).peaks, key=lambda p: p.tau_s)  # (the 3 s arc's peak, at 49 mHz, inside the band)
    assert f"the peak at τ = {ix.data.format_time(slow.tau_s)}" in note and note.endswith("lies there")
    assert lines[-1].startswith("starting circuit from the DRT")  # (the note comes before it)
    assert main(["drt", str(files["drifted"]), "--json"]) == 0
    assert f"note: {json.loads(capsys.readouterr().out)['kk_note']}" == note


def test_a_sound_spectrum_gets_no_note(files, capsys):
    assert ix.kk_test((FREQ, CLEAN)).valid
    assert main(["drt", str(files["clean"])]) == 0
    assert "Kramers–Kronig test at" not in capsys.readouterr().out
    assert main(["drt", str(files["clean"]), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["kk_note"] is None


def test_a_batch_names_the_spectra_that_fail(files, capsys):
    assert main(["drt", str(files["cells"])]) == 0
    out = capsys.readouterr().out
    assert f"note: 1 of 2 spectra fail the Kramers–Kronig test (cell=1; impedax kk {files['cells']} lists their bands)" in out


def test_a_flipped_sign_gets_its_hint_not_the_note(tmp_path, capsys):
    path = tmp_path / "flipped.csv"
    ix.save(ix.make_spectrum(FREQ, np.conj(CLEAN)), path)
    assert main(["drt", str(path)]) == 0
    out = capsys.readouterr().out
    assert "opposite sign" in out and "fail the Kramers–Kronig test" not in out


def test_the_note_names_the_flagged_measured_points_as_impedax_kk_does(capsys):
    """REAL Gamry: the note read "at 15.9 mHz–2.26 kHz" (the band's edge halfway to the measured
    2.53 kHz) where ``impedax kk`` names "15.9 mHz – 2.02 kHz", its highest flagged point. Oracle:
    the file's measured frequencies and the points the KK test flags."""
    from pathlib import Path

    path = Path(__file__).parent / "fixtures" / "real" / "exampleDataGamry.DTA"
    kk = ix.kk_test(ix.load(path))
    flagged = np.sort(kk.frequency[kk.flagged])
    assert main(["drt", str(path)]) == 0
    (note,) = [line for line in capsys.readouterr().out.splitlines() if line.startswith("note: the data fail")]
    named = f"{ix.data.format_frequency(float(flagged[0]))}–{ix.data.format_frequency(float(flagged[-1]))}"
    assert note.startswith(f"note: the data fail the Kramers–Kronig test at {named} ("), note


def test_the_kk_command_carries_the_runs_band_and_exclusions(files, capsys):
    """`impedax drt FILE --exclude ...` tests the points it took, and its note named `impedax kk
    FILE` alone, which tests every point and flags others (REAL BioLogic with --exclude
    5.34,56.2,123,270: the note said 15.2 Hz, the command it named flags 5.34, 56.2, 123 and
    270 Hz). The command carries the run's --fmin, --fmax and --exclude, and names the same
    points as the note (the oracle: `ix.kk_test` of the data without them, run here)."""
    import shlex

    from impedax.cli.common import exclude_points

    path = files["drifted"]
    left_out = f"{FREQ[40]:.6g}"  # (a measured point inside the band, as --exclude takes it)
    argv = ["drt", str(path), "--fmax", "3e4", "--exclude", left_out]
    assert main(argv) == 0
    (note,) = [line for line in capsys.readouterr().out.splitlines() if line.startswith("note: the data fail")]
    command = note.split("(", 1)[1].split(" says which points", 1)[0]
    words = shlex.split(command)
    assert words[:4] == ["impedax", "kk", str(path), "--fmax"] and float(words[4]) == 3e4 and words[5:] == ["--exclude", left_out]
    data = exclude_points(ix.load(path), left_out)
    kk = ix.kk_test(data.sel(frequency=data.frequency[data.frequency <= 3e4]))
    assert f"the Kramers–Kronig test at {kk.measured_bands_text()} (" in note
    assert main(shlex.split(command)[1:]) == 0
    assert "NOT valid" in capsys.readouterr().out
