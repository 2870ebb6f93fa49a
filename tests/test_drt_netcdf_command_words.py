"""``impedax drt --out FILE.nc`` writes the DRT's warnings in the words the command printed
(``leave the top points out (--fmax)``), as its CSV and JSON do; until 2026-12-07 the .nc held
Python's (``data.where(data.frequency <= f, drop=True)``), which the command line never says.
Oracles: the ``warning:`` lines the command printed, and its ``--json`` document; Python's own
.nc (`ix.write_result`) keeps Python's words."""

import json

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from cli_run import run

REAL_POWERSUITE = "tests/fixtures/real/exampleDataPowersuite.txt"


def _negative_r0(tmp_path):
    """SYNTHETIC R0 + R1 ∥ C1 with R0 = −5 Ω (no passive cell has it), 100 Ω, 1 µF, 41 points
    100 kHz … 10 mHz: the DRT's R_inf comes out negative and it warns, naming how to leave the
    top points out."""
    f = np.logspace(5, -2, 41)
    z = -5 + 100 / (1 + 1j * 2 * np.pi * f * 1e-4)
    path = tmp_path / "negative_r0.csv"
    np.savetxt(path, np.c_[f, z.real, z.imag], delimiter=",", header="frequency,Z',Z''", comments="")
    return path


def _warning_lines(text: str) -> list[str]:
    return [line.removeprefix("warning: ") for line in text.splitlines() if line.startswith("warning: ")]


def test_the_netcdf_holds_the_warnings_the_command_printed(tmp_path, capsys):
    path = _negative_r0(tmp_path)
    code, out, err = run(["drt", path, "-q"], capsys)
    assert code == 0, err
    printed = _warning_lines(out + err)
    assert any("leave the top points out (--fmax)" in w for w in printed), out
    code, _, err = run(["drt", path, "-q", "--out", tmp_path / "drt.nc"], capsys)
    assert code == 0, err
    with xr.open_dataset(tmp_path / "drt.nc") as ds:
        written = str(ds["warnings"].item())
    assert "drop=True" not in written and "data.where" not in written, written
    for warning in printed:  # (the report's numbers may be shorter than the warnings': compare the words after the first ':')
        assert warning.partition(": ")[2] in written, (warning, written)
    python = ix.drt(ix.load(path))
    ix.write_result(python, tmp_path / "python.nc")
    with xr.open_dataset(tmp_path / "python.nc") as ds:
        assert "data.where(data.frequency <= f, drop=True)" in str(ds["warnings"].item())  # (the Python API keeps Python's words)


@pytest.mark.slow
def test_the_real_powersuite_netcdf_says_what_the_json_says(tmp_path, capsys):
    """REAL PowerSuite (R_inf < 0 and a misfit: '(--fmax)', '(--signed)'): the .nc's warnings are
    the --json document's, joined by '; '."""
    code, out, err = run(["drt", REAL_POWERSUITE, "-q", "--json", "--out", tmp_path / "drt.nc"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    with xr.open_dataset(tmp_path / "drt.nc") as ds:
        written = str(ds["warnings"].item())
    assert written == "; ".join(summary["warnings"]) and "(--fmax)" in written and "(--signed)" in written, written
