"""``impedax drt --out FILE.csv`` and ``ix.write_result(drt, FILE.csv)`` carry the DRT's warnings
in a last column, ``warnings`` (joined by "; ", as a fit's CSV; docs/drt.md, "Files"). Until
2026-12-06 the CSV held none: on the REAL PowerSuite file the report warns that R_inf < 0, and
the file written beside it did not say so. The columns before it stay where they were: the
table's own, then the provenance."""

import csv
import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix

from cli_run import run

POWERSUITE = Path(__file__).parent / "fixtures" / "real" / "exampleDataPowersuite.txt"
# the command line's columns before 2026-12-06, in order: the table's own, then the provenance
COLUMNS_BEFORE = ["tau_s", "gamma_ohm", "gamma_q05_ohm", "gamma_q95_ohm", "impedax_version", "written_utc", "command", "source", "data_files",
                  "setting_select", "setting_lam", "setting_lam_method", "setting_method", "setting_signed", "setting_min_peak_fraction",
                  "setting_fmin", "setting_fmax", "setting_exclude"]


def _rows(path: Path) -> list[dict]:
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


@pytest.mark.slow
def test_the_real_powersuite_warnings_are_in_the_command_line_csv(tmp_path, capsys):
    out = tmp_path / "drt.csv"
    top = ix.load(POWERSUITE).sortby("frequency").isel(frequency=-1)
    assert float(top["frequency"]) == 2e6 and float(top["Z"].real) < 0  # (the file's own top point: Z' = −470.5 Ω at 2 MHz)
    code, text, err = run(["drt", POWERSUITE, "--json"], capsys)
    assert code == 0, err
    summary = json.loads(text)
    assert summary["r_inf_ohm"] < 0 and any(w.startswith("R_inf = ") and "is negative" in w for w in summary["warnings"])
    code, _, err = run(["drt", POWERSUITE, "--out", out, "-q"], capsys)
    assert code == 0, err
    rows = _rows(out)
    assert list(rows[0]) == [*COLUMNS_BEFORE, "warnings"]
    assert {row["warnings"] for row in rows} == {"; ".join(summary["warnings"])}
    assert "leave the top points out (--fmax)" in rows[0]["warnings"]  # (the command's words, as its text and --json say them)


def test_python_writes_the_warnings_last_and_none_as_an_empty_cell(tmp_path):
    # SYNTHETIC: R0 + R1 || C1 (10 Ω, 100 Ω, 1 µF), 41 points 100 kHz … 10 mHz, exact: no warning
    f = np.logspace(5, -2, 41)
    clean = ix.make_spectrum(f, 10 + 100 / (1 + 1j * 2 * np.pi * f * 1e-4))
    result = ix.drt(clean)
    assert result.warnings == ()
    ix.write_result(result, tmp_path / "clean.csv")
    rows = _rows(tmp_path / "clean.csv")
    assert list(rows[0]) == ["tau_s", "gamma_ohm", "gamma_q05_ohm", "gamma_q95_ohm", "warnings"]
    assert {row["warnings"] for row in rows} == {""}
    real = ix.drt(ix.load(POWERSUITE))
    ix.write_result(real, tmp_path / "real.csv")
    assert {row["warnings"] for row in _rows(tmp_path / "real.csv")} == {"; ".join(real.warnings)} and real.r_inf_ohm < 0


def test_the_netcdf_holds_each_spectrums_warnings(tmp_path):
    """The .nc (`to_xarray`) had none either: now the variable ``warnings`` per spectrum. SYNTHETIC
    batch: an exact R0 + R1 || C1 (10 Ω, 100 Ω, 1 µF; no warning) and the same with R0 = −5 Ω,
    which no passive cell has (the DRT's R_inf comes out at R0, below −1 % of |Z| at the top)."""
    import xarray as xr

    f = np.logspace(5, -2, 41)
    arc = 100 / (1 + 1j * 2 * np.pi * f * 1e-4)
    both = xr.concat([ix.make_spectrum(f, 10 + arc), ix.make_spectrum(f, -5 + arc)], dim="trial").assign_coords(trial=["clean", "negative"])
    result = ix.drt(both)
    ix.write_result(result, tmp_path / "batch.nc")
    ds = ix.io.read_netcdf(tmp_path / "batch.nc")
    assert ds["warnings"].dims == ("trial",) and ds["warnings"].sel(trial="clean").item() == ""
    assert ds["warnings"].sel(trial="negative").item().startswith("R_inf = -5") and float(ds["r_inf"].sel(trial="negative")) < 0
    one = result.results[1]
    ix.write_result(one, tmp_path / "one.nc")
    assert ix.io.read_netcdf(tmp_path / "one.nc")["warnings"].item() == "; ".join(one.warnings) != ""
