"""`impedax diagnose` and `refine` say "drawing FILE" before drawing their figure, as `impedax drt`
does: refine's figure (a residual panel per step, each model's curve) took 39 s on a 2-core
machine at load 8 after the last progress line on REAL CH Instruments, with no word. The
spectrum is SYNTHETIC (100 Ω + 1 kΩ ‖ 1 µF written here, 0.5 % noise, fixed seed)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from impedax.cli import common
from cli_run import run

PROGRESS_LINE = re.compile(r"^\[\s*\d+\.\d s\] (.*)$", re.MULTILINE)


@pytest.fixture()
def spectrum(tmp_path):
    rng = np.random.default_rng(3)
    f = np.geomspace(1e5, 1.0, 31)
    z = (100.0 + 1000.0 / (1 + 2j * np.pi * f * 1e-3)) * (1 + 0.005 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2))
    path = tmp_path / "rc.csv"
    np.savetxt(path, np.column_stack([f, z.real, z.imag]), delimiter=",", header="freq,zreal,zimag", comments="")
    return path


@pytest.mark.parametrize("command", ["diagnose", "refine"])
def test_the_figure_is_announced_before_it_is_drawn(command, spectrum, tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(common, "PROGRESS_AFTER_S", 0.0)  # (every line printed at once)
    figure = tmp_path / "figure.png"
    options = ["--effects", "series_inductance", "--noise", "1%"] + (["--max-effects", "1"] if command == "refine" else [])
    code, _, err = run([command, spectrum, "--model", "R0 + R1 || C1", *options, "--plot", figure], capsys)
    assert code == 0, err
    said = PROGRESS_LINE.findall(err)
    assert said[-1] == f"drawing {figure}", err  # (the last progress line, after the analysis's own)
    lines = err.splitlines()
    assert lines.index(f"wrote {figure}") > max(i for i, line in enumerate(lines) if line.endswith(f"drawing {figure}"))
    assert figure.stat().st_size > 0
    code, _, err = run([command, spectrum, "--model", "R0 + R1 || C1", *options, "--plot", figure, "-q"], capsys)
    assert code == 0 and "drawing" not in err, err
