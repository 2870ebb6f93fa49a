"""What a pipeline asks of every command (walkthrough of 2026-12-01, lab automation): ``--quiet``
drops progress lines and nothing else; ``sample --json`` prints progress as the other commands
do; the reader's skipped rows in compare's (and diagnose's, refine's, sample's) JSON; a JSON
summary of stack, simulate and remaining; ``inspect`` of a saved fit with its parameter units and,
for an element of the user's own, the ``registry=`` / ``--plugin`` it is read with.

SYNTHETIC spectra are numpy formulas written here (R0 + R1 ∥ C1, 0.5 % noise, fixed seeds); the
REAL Parstat file of tests/fixtures is read for its 781 DC rows."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from impedax.cli import common, main

PARSTAT = Path(__file__).parent / "fixtures" / "real" / "exampleDataParstat.txt"  # REAL: 781 DC rows (f = 0) before 31 points
PARSTAT_SKIPPED = ["lines 2–782: f = 0 (DC row, not an impedance point)"]

R0, R1, C1 = 10.0, 100.0, 10e-6  # SYNTHETIC truth [Ω, Ω, F]
F21 = np.geomspace(1.0, 1e5, 21)  # Hz
MODEL = "R0 + R1 || C1"

# a line of `common.progress_printer`: "[  0.0 s] text"
PROGRESS_LINE = re.compile(r"^\[\s*\d+\.\d s\] ", re.MULTILINE)


def rc_impedance(f: np.ndarray) -> np.ndarray:
    """R0 + R1 ∥ C1 [Ω] at ``f`` [Hz]: R0 + R1 / (1 + jωR1C1)."""
    return R0 + R1 / (1 + 2j * np.pi * f * R1 * C1)


def write_rc(path: Path, f: np.ndarray = F21, seed: int = 5, noise: float = 0.005) -> Path:
    """SYNTHETIC: R0 + R1 ∥ C1 at ``f`` with ``noise`` × |Z| Gaussian noise per component."""
    rng = np.random.default_rng(seed)
    z = rc_impedance(f)
    z = z + noise * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{float(a)!r},{float(b.real)!r},{float(b.imag)!r}\n" for a, b in zip(f, z)))
    return path


def run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def without_times(doc: dict) -> dict:
    """A JSON document without what differs between two runs of one fit (the wall time, the
    provenance's clock and settings)."""
    doc = {k: v for k, v in doc.items() if k not in ("provenance", "elapsed_s")}
    return {k: without_times(v) if isinstance(v, dict) else v for k, v in doc.items()}


# --- 1. --quiet -----------------------------------------------------------------------------------


@pytest.mark.parametrize("command", [["fit", "--model", MODEL], ["diagnose", "--model", MODEL, "--effects", "series_inductance", "--noise", "1%"]], ids=["fit", "diagnose"])
def test_quiet_drops_the_progress_lines_and_keeps_the_json(command, tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(common, "PROGRESS_AFTER_S", 0.0)  # (every line printed at once: a short run says them too)
    name, *options = command
    # SYNTHETIC for fit; diagnose on the REAL Parstat file, whose JSON names its 781 DC rows
    data = write_rc(tmp_path / "rc.csv") if name == "fit" else PARSTAT
    code, loud, err = run(capsys, name, data, *options, "--json")
    assert code == 0, err
    assert PROGRESS_LINE.search(err), err  # (the printer speaks without --quiet: the check below can fail)
    code, quiet, quiet_err = run(capsys, name, data, *options, "--json", "--quiet")
    assert code == 0, quiet_err
    assert not PROGRESS_LINE.search(quiet_err), quiet_err
    assert without_times(json.loads(quiet)) == without_times(json.loads(loud))
    if name == "diagnose":
        assert json.loads(quiet)["skipped_rows"] == PARSTAT_SKIPPED


def test_every_command_that_prints_progress_takes_quiet(capsys):
    for command in ("fit", "compare", "drt", "diagnose", "refine", "sample", "gap", "kk"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        assert "--quiet" in capsys.readouterr().out, command


def test_every_command_takes_quiet(capsys):
    """Every subcommand, those without progress lines too (2026-12-03: `impedax simulate --quiet`
    was "unrecognized arguments", though it writes notes and "wrote FILE" on stderr), read from
    the parser's own list of subcommands."""
    import argparse

    from impedax.cli import build_parser

    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    assert {"simulate", "info", "stack", "fit"} <= set(sub.choices)
    for command, parser in sub.choices.items():
        options = {s for action in parser._actions for s in action.option_strings}
        assert "--quiet" in options and "-q" in options, command  # (-q for short: 2026-12-04)


def test_q_is_quiet_for_short(tmp_path, capsys, monkeypatch):
    """A walkthrough typed ``-q`` and got "unrecognized arguments": it is --quiet's short form."""
    monkeypatch.setattr(common, "PROGRESS_AFTER_S", 0.0)
    data = write_rc(tmp_path / "rc.csv")
    code, short, err = run(capsys, "fit", data, "--model", MODEL, "--json", "-q")
    assert code == 0, err
    assert not PROGRESS_LINE.search(err) and "unrecognized" not in err
    code, long, _ = run(capsys, "fit", data, "--model", MODEL, "--json", "--quiet")
    assert without_times(json.loads(short)) == without_times(json.loads(long))


def test_simulate_quiet_writes_the_same_and_keeps_its_notes(tmp_path, capsys):
    code, loud, loud_err = run(capsys, "simulate", MODEL, "--param", "R0=10", "--points", "5")
    assert code == 0
    code, quiet, quiet_err = run(capsys, "simulate", MODEL, "--param", "R0=10", "--points", "5", "--quiet")
    assert code == 0 and quiet == loud and quiet_err == loud_err
    assert quiet_err.strip() == "impedax simulate: defaults used for R1 = 100 Ω, C1 = 1 µF"


def test_kk_takes_quiet_as_the_other_analysis_commands(capsys):
    """`impedax kk --quiet` (a walkthrough, 2026-12-02: "unrecognized arguments: --quiet"): the same
    report and JSON as without, and the notes (the REAL Parstat file's skipped DC rows) kept."""
    with pytest.raises(SystemExit):
        main(["kk", "--help"])
    assert "--quiet" in capsys.readouterr().out
    code, loud, loud_err = run(capsys, "kk", PARSTAT)
    assert code == 0, loud_err
    code, quiet, quiet_err = run(capsys, "kk", PARSTAT, "--quiet")
    assert code == 0 and quiet == loud and quiet_err == loud_err and "rows skipped" in quiet_err
    code, quiet_json, _ = run(capsys, "kk", PARSTAT, "--json", "--quiet")
    assert code == 0 and json.loads(quiet_json)["skipped_rows"] == PARSTAT_SKIPPED


def test_quiet_keeps_the_notes(capsys):
    code, _, err = run(capsys, "fit", PARSTAT, "--model", MODEL, "--quiet")
    assert code == 0 and "impedax fit: note:" in err and "rows skipped" in err


# --- 2. sample --json prints its progress (stderr), as the others do, unless --quiet -------------


def test_sample_json_prints_progress_unless_quiet(tmp_path, capsys):
    data = write_rc(tmp_path / "rc.csv")
    argv = ["sample", data, "--model", MODEL, "--walkers", "16", "--steps", "30", "--burn", "10", "--json"]
    code, out, err = run(capsys, *argv)
    assert code == 0, err
    assert "sample: compiling" in err and json.loads(out)["model"] == MODEL
    code, out, err = run(capsys, *argv, "--quiet")
    assert code == 0 and "sample:" not in err.replace("impedax sample:", "") and json.loads(out)["model"] == MODEL


# --- 3. skipped rows in compare's JSON (REAL Parstat file) ---------------------------------------


def test_compare_json_and_note_name_the_skipped_dc_rows(capsys):
    models = ["--model", MODEL, "--model", "R0 + R1 || CPE1"]
    code, out, err = run(capsys, "compare", PARSTAT, *models, "--json", "--quiet")
    assert code == 0, err
    assert json.loads(out)["skipped_rows"] == PARSTAT_SKIPPED
    code, _, err = run(capsys, "compare", PARSTAT, *models, "--quiet")
    assert code == 0 and [line for line in err.splitlines() if "skipped" in line] == [f"impedax compare: note: {PARSTAT}: rows skipped as no impedance points: {PARSTAT_SKIPPED[0]}"]


def test_a_file_without_skipped_rows_gives_compare_an_empty_list(tmp_path, capsys):
    code, out, err = run(capsys, "compare", write_rc(tmp_path / "rc.csv"), "--model", MODEL, "--model", "R0 + R1 || CPE1", "--json", "--quiet")
    assert code == 0 and json.loads(out)["skipped_rows"] == [] and "skipped" not in err


# --- 4. --json of stack, simulate, remaining ------------------------------------------------------


def test_simulate_json_summarises_the_written_spectrum(tmp_path, capsys):
    out_csv = tmp_path / "sim.csv"
    code, out, err = run(capsys, "simulate", MODEL, "--param", "R0=10", "R1=100", "--fmin", "10", "--fmax", "1e4", "--points", "7", "--out", out_csv, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["written"] == [str(out_csv)] and doc["model"] == MODEL
    assert doc["parameters"]["R0"] == 10.0 and doc["parameters"]["R1"] == 100.0 and doc["defaulted"] == ["C1"]
    assert doc["parameter_units"] == {"R0": "Ohm", "R1": "Ohm", "C1": "F"}
    assert (doc["frequencies"], doc["frequency_min_hz"], doc["frequency_max_hz"], doc["dims"], doc["spectra"]) == (7, 10.0, 1e4, {"frequency": 7}, 1)
    rows = out_csv.read_text().splitlines()
    assert len([r for r in rows if r and r[0].isdigit()]) == 7  # (the file holds what the JSON says)


def test_simulate_json_without_out_is_refused(capsys):
    code, out, err = run(capsys, "simulate", MODEL, "--json")
    assert code == 2 and out == "" and "--out FILE" in err and "Traceback" not in err


def test_stack_json_lists_files_labels_and_shape(tmp_path, capsys):
    files = [write_rc(tmp_path / f"day{i}.csv", seed=i) for i in (1, 2, 3)]
    out_nc = tmp_path / "days.nc"
    code, out, err = run(capsys, "stack", *files, "--dim", "day", "--coords", "1", "2", "3", "--out", out_nc, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["written"] == [str(out_nc)] and doc["files"] == [str(f) for f in files]
    assert (doc["dim"], doc["labels"], doc["dims"], doc["spectra"], doc["frequencies"]) == ("day", [1, 2, 3], {"day": 3, "frequency": 21}, 3, 21)


def test_remaining_json_summarises_the_remainder(tmp_path, capsys):
    # SYNTHETIC: three spectra, total = skin + screen + 1 kΩ (a remainder of 1 kΩ at every frequency)
    f = np.geomspace(10.0, 1e4, 9)
    parts = {"skin": 200.0 - 50j * np.ones_like(f), "screen": 300.0 - 20j * np.ones_like(f)}
    parts["total"] = parts["skin"] + parts["screen"] + 1000.0
    paths = {}
    for name, z in parts.items():
        paths[name] = tmp_path / f"{name}.csv"
        paths[name].write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{float(a)!r},{float(b.real)!r},{float(b.imag)!r}\n" for a, b in zip(f, z)))
    out_csv = tmp_path / "rest.csv"
    code, out, err = run(capsys, "remaining", paths["total"], paths["skin"], paths["screen"], "--out", out_csv, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["written"] == [str(out_csv)] and doc["kind"] == "mean" and doc["n_trials"] == {"total": 1, "skin": 1, "touchscreen": 1}
    assert (doc["frequencies"], doc["spectra"], doc["dims"]) == (9, 1, {"frequency": 9})
    assert doc["source"] == {"total": str(paths["total"]), "skin": str(paths["skin"]), "touchscreen": str(paths["screen"])}
    code, _, err = run(capsys, "remaining", paths["total"], paths["skin"], paths["screen"], "--json")
    assert code == 2 and "--out FILE" in err


# --- 5. inspect of a saved fit --------------------------------------------------------------------


def test_inspect_gives_a_saved_fits_parameter_units(tmp_path, capsys):
    saved = tmp_path / "fit.nc"
    code, _, err = run(capsys, "fit", write_rc(tmp_path / "rc.csv"), "--model", MODEL, "--out", saved, "--quiet")
    assert code == 0, err
    code, out, err = run(capsys, "inspect", saved, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["parameter_units"] == {"R0": "Ohm", "R1": "Ohm", "C1": "F"}
    assert doc["read_with"] == "FitResult.from_xarray(impedax.io.read_netcdf(path))"


PLUGIN = '''\
import jax.numpy as jnp
import impedax as ix


def rx_impedance(omega, r):
    """A resistor of the user's own: Z = R."""
    return r + 0 * omega


RX = ix.ElementSpec("Rq", "my resistor", "Z = R", (ix.ParameterSpec("R", "Ohm", 100.0, description="resistance"),), rx_impedance)
'''


def test_inspect_of_a_fit_with_a_plugin_element_names_registry_and_plugin(tmp_path, capsys):
    plugin = tmp_path / "mine.py"
    plugin.write_text(PLUGIN)
    saved = tmp_path / "fit.nc"
    code, _, err = run(capsys, "--plugin", plugin, "fit", write_rc(tmp_path / "rc.csv"), "--model", "Rq0 + R1 || C1", "--out", saved, "--quiet")
    assert code == 0, err
    code, out, err = run(capsys, "inspect", saved)
    assert code == 0, err
    assert "FitResult.from_xarray(impedax.io.read_netcdf(path), registry=REGISTRY)" in out and "--plugin FILE.py" in out
    assert "Rq0.R [Ohm]" in out
