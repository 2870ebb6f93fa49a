"""``impedax inspect --json``: ``points`` counts the frequencies (of each spectrum), ``rows`` the
impedance points the file holds over every spectrum, which differ for a table of several sweeps
of one frequency list. The oracle is the file's own bytes: its lines of numbers."""

import json
from pathlib import Path

import numpy as np

from impedax.cli import main

ZPLOT = Path(__file__).parent / "fixtures" / "real" / "exampleDataZPlot.z"


def _inspect(capsys, *args) -> str:
    assert main(["inspect", *args]) == 0
    return capsys.readouterr().out


def _sweeps_file(tmp_path) -> Path:
    """SYNTHETIC: three sweeps of one RC over the same 5 frequencies, one after another."""
    f = np.logspace(4, 0, 5)
    lines = ["frequency_hz,z_real_ohm,z_imag_ohm"]
    for r in (100.0, 110.0, 120.0):
        z = r / (1 + 2j * np.pi * f * r * 1e-6)
        lines += [f"{a:.6g},{b.real:.6g},{b.imag:.6g}" for a, b in zip(f, z)]
    path = tmp_path / "sweeps.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_rows_count_every_sweeps_points_and_points_the_frequencies(tmp_path, capsys):
    path = _sweeps_file(tmp_path)
    rows = [line for line in path.read_text().splitlines() if line[:1].isdigit()]
    assert len(rows) == 15 and len({line.split(",")[0] for line in rows}) == 5
    summary = json.loads(_inspect(capsys, str(path), "--json"))
    assert summary["dims"] == {"sweep": 3, "frequency": 5}
    assert (summary["points"], summary["rows"]) == (5, 15)
    first = _inspect(capsys, str(path)).splitlines()[0]
    assert first.startswith(f"{path}: delimited text, 5 frequencies 1 Hz–10 kHz, ") and "15 rows (3 spectra of 5 frequencies)" in first, first


def test_rows_equal_points_for_one_spectrum(capsys):
    lines = ZPLOT.read_text(encoding="latin-1").splitlines()
    data = [line for line in lines[lines.index("End Comments") + 1 :] if line.strip()]
    summary = json.loads(_inspect(capsys, str(ZPLOT), "--json"))
    assert summary["points"] == summary["rows"] == len(data) == 21
    assert "rows" not in _inspect(capsys, str(ZPLOT)).splitlines()[0]
