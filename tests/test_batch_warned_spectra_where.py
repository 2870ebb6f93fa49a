"""A batch report whose warning line names only the first of its spectra ("cycle 0, 1, ...
(12 in all)") says where every one of them is (REAL 130 battery cycles: "56 of 130 spectra:
cycle 0, 3, 4, 5, 6, 7, 8, 9, ... (56 in all)" and no word where the other 48 were)."""

import numpy as np
import xarray as xr

import impedax as ix
from impedax.cli.common import command_line_words
from impedax.fitting.least_squares import BatchFitResult

N = 20
NOTE = "R1 has a relative standard error of 150 %: it is not determined by the data"


def batch(warned: int) -> BatchFitResult:
    """20 cycles of R0 + R1 || C1 written by hand (values, no fit), the first ``warned`` of them
    with NOTE."""
    f = np.geomspace(1, 1e5, 5)
    z = 10 + 100 / (1 + 2j * np.pi * f * 1e-4)
    params = ["R0", "R1", "C1"]
    ds = xr.Dataset(
        {
            "value": (("param", "cycle"), np.tile([[10.0], [100.0], [1e-6]], N)), "stderr": (("param", "cycle"), np.tile([[0.1], [150.0], [1e-8]], N)),
            "fixed": ("param", np.zeros(3, bool)), "at_bound": (("param", "cycle"), np.zeros((3, N), bool)),
            "rms_rel": ("cycle", np.full(N, 0.01)), "converged": ("cycle", np.ones(N, bool)),
            "Z": (("cycle", "frequency"), np.tile(z, (N, 1))), "Z_model": (("cycle", "frequency"), np.tile(z, (N, 1))),
        },
        coords={"param": params, "cycle": np.arange(N), "frequency": f},
        attrs={"model": "R0 + R1 || C1", "weighting": "unit", "impedax_kind": "batch_fit", "warnings": {f"cycle={k}": [NOTE] for k in range(warned)}},
    )
    return BatchFitResult.from_xarray(ds)


def test_a_warning_line_cut_short_says_where_every_spectrum_is():
    cut = batch(12).report()
    assert f"warning (12 of 20 spectra: all but cycle 12, 13, 14, 15, 16, 17, 18, 19): {NOTE}" in cut  # (the others, 8: named in full)
    assert "every spectrum of each kind" not in cut
    cut = batch(10).report()
    assert f"warning (10 of 20 spectra: cycle 0, 1, 2, 3, 4, 5, 6, 7, ... (10 in all)): {NOTE}" in cut
    line = next(line for line in cut.splitlines() if line.startswith("every spectrum of each kind: "))
    assert "summary()['warning_kinds']" in line and "batch.warnings" in line
    assert [k["spectra"] for k in batch(10).summary()["warning_kinds"]] == [[f"cycle={k}" for k in range(10)]]  # (what the line points at)
    # the command line's words for it
    cli = command_line_words(cut, "fit")
    assert 'every spectrum of each kind: --json ("warning_kinds"; each spectrum\'s own: its row of "spectra", or the warnings column of --out FILE.csv)' in cli
    # every spectrum named: no such line
    assert "every spectrum of each kind" not in batch(8).report()
