"""A parameter on its bound 0 reads "0" in the tables of a fit, a batch and a global fit, as
its note "R0 is at its lower bound 0" says, not the digits where the solver stopped (REAL
exampleDataGamry.DTA with R0 + R1 || CPE1 + R2 || CPE2 printed "R0 1.2675e-05 at bound"
beside that note)."""

import re

import numpy as np
import pytest
import xarray as xr

import impedax as ix

ON_ZERO = "R0 is at its lower bound 0"


@pytest.fixture(scope="module")
def two_cells():
    """SYNTHETIC: R1 || C1 with no series resistance, Z = R1 / (1 + jωR1C1), from the formula."""
    f = np.logspace(-1, 5, 40)
    w = 2 * np.pi * f
    r1 = np.array([100.0, 250.0])
    z = r1[:, None] / (1 + 1j * w[None, :] * r1[:, None] * 1e-5)
    return xr.Dataset({"Z": (("cell", "frequency"), z)}, coords={"cell": ["a", "b"], "frequency": f})


def row(report: str, name: str) -> str:
    return next(line for line in report.splitlines() if line.startswith(name + " "))


def test_a_batch_and_a_single_fit_show_a_parameter_on_its_bound_0_as_0(two_cells):
    batch = ix.fit("R0 + R1 || C1", two_cells, progress=False)
    assert all(ON_ZERO in batch.warnings[k] for k in ("cell=a", "cell=b"))
    values = batch.values("R0").values
    assert np.all(values > 0) and np.all(values < 1e-9)  # (fitted in log space: not exactly 0)
    assert row(batch.report(), "R0").split()[1:] == ["0", "at", "bound", "0", "at", "bound", "Ω"]
    single = ix.fit("R0 + R1 || C1", two_cells.isel(cell=0), progress=False)
    assert ON_ZERO in single.warnings and single.values["R0"] > 0
    assert re.fullmatch(r"R0\s+0\s+—\s+at bound\s+Ω", row(single.report(), "R0"))
    # the JSON keeps the value as fitted
    assert batch.summary()["spectra"][0]["values"]["R0"] == values[0]


def test_a_shared_parameter_on_its_bound_0_reads_0_in_both_tables(two_cells):
    shared = ix.fit("R0 + R1 || C1", two_cells, shared="R0", progress=False)
    notes = shared.warnings.get("shared over cell", ())
    assert f"shared {ON_ZERO}" in notes and float(shared.values("R0")) > 0
    report = shared.report()
    assert row(report, "R0").split()[1:] == ["0", "at", "bound", "0", "at", "bound", "Ω"]
    shared_row = report.split("shared over cell (one global fit):")[1]
    assert re.search(r"\nR0\s+0\s+—\s+at bound\s+Ω", shared_row)
