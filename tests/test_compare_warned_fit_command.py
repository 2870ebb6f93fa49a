"""`impedax compare` over several spectra ends its "fits with warnings" line with the command
that lists them, this run's file and options and the first warned model, where it printed
"impedax fit FILE --model MODEL"; the command runs as printed."""

import shlex

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main


@pytest.mark.slow  # (~7 s: a comparison of two models over two spectra, then the fit it names)
def test_the_fits_with_warnings_line_gives_a_command_that_runs(tmp_path, capsys):
    """SYNTHETIC: two cells of R0 + R1 || C1 (an ideal capacitor; numpy formula, 0.2 % noise):
    R0 + R1 || CPE1 puts α at or near its bound 1, a warning R0 + R1 || C1 has not."""
    f = np.geomspace(1.0, 1e5, 30)
    rng = np.random.default_rng(2)
    r1 = np.array([[100.0], [300.0]])
    z = (10 + r1 / (1 + 2j * np.pi * f * r1 * 1e-6)) * (1 + 0.002 * (rng.standard_normal((2, f.size)) + 1j * rng.standard_normal((2, f.size))) / np.sqrt(2))
    path = tmp_path / "cells.nc"
    ix.save(ix.make_spectrum(f, z, dims=("cell",), coords={"cell": ["a", "b"]}), path)
    assert main(["compare", str(path), "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "--fmin", "2", "-q"]) == 0
    line = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("fits with warnings: "))
    assert "FILE" not in line and "MODEL" not in line
    command = line.split("(impedax fit lists them: ", 1)[1].removesuffix(")")
    assert "report()" not in line  # (the Python API's words: the command line has no batch to call it on)
    words = shlex.split(command)
    assert words[:3] == ["impedax", "fit", str(path)] and words[-2:] == ["--model", "R0 + R1 || CPE1"]
    assert float(words[words.index("--fmin") + 1]) == 2.0  # (the run's band kept)
    assert main(words[1:] + ["-q"]) == 0
    assert any(line.startswith("warning (") and "CPE1.alpha" in line for line in capsys.readouterr().out.splitlines())  # (its α at or near 1)


@pytest.mark.slow  # (~10 s: a comparison of two models over two spectra)
def test_each_model_with_warnings_gets_its_command():
    """SYNTHETIC: two cells of R0 + R1 ∥ C1 + R2 ∥ C2 (numpy formula, 0.2 % noise, arcs at 1.6 kHz
    and 3.2 Hz) compared as R0 + R1 ∥ CPE1 (one arc: misses the second, warned) and R0 + R1 ∥ CPE1
    + R2 ∥ CPE2 (its CPEs' α at their bound 1 on ideal capacitors, warned): the line gave the first
    model's command alone until 2026-12-06; now one per warned model, in the table's order."""
    import contextlib
    import io

    f = np.geomspace(0.1, 1e5, 40)
    rng = np.random.default_rng(3)
    r1 = np.array([[100.0], [300.0]])
    z = 10 + r1 / (1 + 2j * np.pi * f * r1 * 1e-6) + 200 / (1 + 2j * np.pi * f * 200 * 2.5e-4)
    z = z * (1 + 0.002 * (rng.standard_normal((2, f.size)) + 1j * rng.standard_normal((2, f.size))) / np.sqrt(2))
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        path = f"{folder}/cells.nc"
        ix.save(ix.make_spectrum(f, z, dims=("cell",), coords={"cell": ["a", "b"]}), path)
        text = io.StringIO()
        with contextlib.redirect_stdout(text):
            assert main(["compare", path, "--model", "R0 + R1 || CPE1", "--model", "R0 + R1 || CPE1 + R2 || CPE2", "-q"]) == 0
    line = next(line for line in text.getvalue().splitlines() if line.startswith("fits with warnings: "))
    named = [m for m in ("R0 + R1 || CPE1 on", "R0 + R1 || CPE1 + R2 || CPE2 on") if m in line]
    commands = [shlex.split(c) for c in line.split("(impedax fit lists them: ", 1)[1].removesuffix(")").split("; ")]
    assert len(commands) == len(named) == 2  # (both warned: the one-arc model misses an arc, the two-arc model has its α at 1)
    assert [c[-1] for c in commands] == [m.removesuffix(" on") for m in named] and all(c[:3] == ["impedax", "fit", path] for c in commands)
