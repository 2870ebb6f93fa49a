"""`impedax fit` ends with the `impedax diagnose` command to run next when its warning says the
model misses structure the data hold (rms_rel over 5× what a Kramers–Kronig-consistent model
reaches), as it does for a misfit that looks small (the hint): on REAL Gamry, `R0 + R1 || C1`
ends at 30.1 % against the chain's 4.8 %, and the warning said "a diagnosis (impedax diagnose)
shows where it fails" with no command, where the README says each step says what to run next.
A fit with no such warning (SYNTHETIC, the model that made the data) gets no next line."""

from __future__ import annotations

import shlex
from pathlib import Path

import numpy as np

from cli_run import run

REAL = Path(__file__).parent / "fixtures" / "real"


def next_line(out: str) -> str | None:
    return next((line for line in out.splitlines() if line.startswith("next: ")), None)


def test_gamrys_large_misfit_ends_with_the_diagnose_command(capsys):
    path = REAL / "exampleDataGamry.DTA"
    code, out, err = run(["fit", path, "--model", "R0 + R1 || C1", "-q"], capsys)
    assert code == 0, err
    assert "warning: the model misses structure the data hold: its rms_rel is over 5×" in out
    line = next_line(out)
    assert line is not None, out
    command = line[len("next: "):].split(" (", 1)[0]
    assert shlex.split(command) == ["impedax", "diagnose", str(path), "--model", "R0 + R1 || C1"]
    assert line.endswith("(where the model fails and what it misses; the warning above)")


def test_a_fit_at_the_noise_gets_no_next_line(tmp_path, capsys):
    rng = np.random.default_rng(2)
    f = np.geomspace(1e5, 1.0, 31)
    z = (100.0 + 1000.0 / (1 + 2j * np.pi * f * 1e-3)) * (1 + 0.002 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2))
    path = tmp_path / "rc.csv"
    np.savetxt(path, np.column_stack([f, z.real, z.imag]), delimiter=",", header="freq,zreal,zimag", comments="")
    code, out, err = run(["fit", path, "--model", "R0 + R1 || C1", "-q"], capsys)
    assert code == 0, err
    assert next_line(out) is None and "warning" not in out, out


def _stack(tmp_path, alphas):
    """SYNTHETIC spectra R0 + R1 ‖ CPE1 (one α each, numpy), 0.2 % noise, stacked over `cycle`
    labelled 1, 2, …; fitted with R0 + R1 ‖ C1, each misses the CPE's depression."""
    import impedax as ix

    rng = np.random.default_rng(5)
    f = np.geomspace(1e5, 0.1, 41)
    s = 2j * np.pi * f
    zs = []
    for alpha in alphas:
        z = 20 + 1000 / (1 + 1000 * 1e-5 * s**alpha)
        zs.append(z * (1 + 0.002 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2)))
    import xarray as xr

    data = xr.Dataset({"Z": (("cycle", "frequency"), np.array(zs))}, coords={"cycle": np.arange(1, len(alphas) + 1), "frequency": f})
    path = tmp_path / "cycles.nc"
    ix.save(data, path)
    return path


def test_a_batch_whose_warnings_say_the_model_misses_structure_names_its_worst_spectrum(tmp_path, capsys):
    """A batch of several spectra whose fits are over 2 % and over 5× the KK chain's misfit (no
    misfit hint, which begins below 2 %) ends with the diagnose command of its worst spectrum:
    the one with the largest rms_rel among those `misses_structure` flags (from the JSON)."""
    import json

    path = _stack(tmp_path, [0.85, 0.6, 0.75])  # (α furthest from 1: the largest misfit, cycle 2)
    code, out, err = run(["fit", path, "--model", "R0 + R1 || C1", "--json", "-q"], capsys)
    assert code == 0, err
    rows = json.loads(out)["spectra"]
    flagged = [r for r in rows if r["misses_structure"]]
    assert len(flagged) >= 2 and all(r["rms_rel"] >= 0.02 for r in flagged)
    worst = max(flagged, key=lambda r: r["rms_rel"])
    code, out, err = run(["fit", path, "--model", "R0 + R1 || C1", "-q"], capsys)
    assert code == 0, err
    line = next_line(out)
    assert line is not None, out
    command = shlex.split(line[len("next: "):].split(" (", 1)[0])
    assert command == ["impedax", "diagnose", str(path), "--select", f"cycle={worst['labels']['cycle']}", "--model", "R0 + R1 || C1"], line
    assert worst["labels"]["cycle"] == 2
