"""``impedax fit --out FILE.nc`` writes the fit's warnings and message in the words the command
printed (``raise --max-steps``), as its ``--json`` and ``--out FILE.json`` do; until 2026-12-07
the .nc held Python's (``raise max_steps``), an option the command line does not have, while
``impedax drt --out FILE.nc`` had its own copy of the translation. Oracles: the command's
``--json`` document of the same run; Python's own .nc (`ix.write_result`) keeps Python's words.
SYNTHETIC R0 + R1 ∥ C1 spectrum (numpy formula, 1 % noise, seed 1) fitted with two arcs and
--max-steps 3, so that the fit stops at its step limit and says how to raise it."""

import json

import numpy as np

import impedax as ix
from cli_run import run
from impedax.fitting.least_squares.result import FitResult
from impedax.io import read_netcdf

F = np.geomspace(0.1, 1e5, 30)
MODEL = "R0 + R1 || C1 + R2 || C2"


def _spectrum(tmp_path):
    z = 20 + 1e3 / (1 + 2j * np.pi * F * 1e-3)
    path = tmp_path / "rc.csv"
    ix.save(ix.make_spectrum(F, z * (1 + 0.01 * np.random.default_rng(1).normal(size=F.size))), path)
    return path


def test_the_fit_netcdf_says_what_the_json_says(tmp_path, capsys):
    path = _spectrum(tmp_path)
    code, out, err = run(["fit", path, "--model", MODEL, "--max-steps", "3", "-q", "--json", "--out", tmp_path / "fit.nc"], capsys)
    assert code == 0, err
    printed = json.loads(out)
    assert any("raise --max-steps" in w for w in printed["warnings"]), printed["warnings"]  # (the case)
    ds = read_netcdf(tmp_path / "fit.nc")
    assert list(ds.attrs["warnings"]) == printed["warnings"]
    assert "--max-steps" in ds.attrs["message"] and "max_steps" not in ds.attrs["message"]
    back = FitResult.from_xarray(ds)  # (read back as any fit file)
    assert back.warnings == tuple(printed["warnings"]) and back.converged is False
    python = ix.fit(MODEL, ix.load(path), max_steps=3)
    ix.write_result(python, tmp_path / "python.nc")
    assert any("raise max_steps" in w for w in read_netcdf(tmp_path / "python.nc").attrs["warnings"])  # (the Python API keeps Python's words)
