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
    command = line.split("from the command line, ", 1)[1].removesuffix(")")
    words = shlex.split(command)
    assert words[:3] == ["impedax", "fit", str(path)] and words[-2:] == ["--model", "R0 + R1 || CPE1"]
    assert float(words[words.index("--fmin") + 1]) == 2.0  # (the run's band kept)
    assert main(words[1:] + ["-q"]) == 0
    assert any(line.startswith("warning (") and "CPE1.alpha" in line for line in capsys.readouterr().out.splitlines())  # (its α at or near 1)
