"""`BatchFitResult.to_latex` (``impedax fit FILE --out FILE.tex`` of several spectra; refused
until 2026-12-06): a LaTeX tabular with a row per spectrum, each parameter's value ± standard
error rounded as a single fit's table rounds it. Oracle: hand-rounded numbers (533.3168 ±
13.0249 → 533 ± 13) of values written by hand (no fit)."""

import numpy as np
import pytest
import xarray as xr

from impedax.fitting.least_squares import BatchFitResult

F = np.geomspace(1, 1e5, 8)
Z = 10 + 100 / (1 + 2j * np.pi * F * 1e-4)


def test_a_row_per_spectrum_with_each_pair_rounded_to_its_error():
    value = np.array([[533.3168, 12.3456, 12.3456], [0.012345, 2.18e7, 100.0], [1.0002e-6, 1e-6, 1e-6]])
    stderr = np.array([[13.0249, 0.5, 0.5], [0.00067, 2.8e15, np.nan], [2.82e-9, 1e-8, 1e-8]])
    ds = xr.Dataset(
        {
            "value": (("param", "soc"), value), "stderr": (("param", "soc"), stderr),
            "fixed": ("param", np.zeros(3, bool)), "at_bound": (("param", "soc"), np.array([[False] * 3, [False, False, True], [False] * 3])),
            "rms_rel": ("soc", [0.0123, 0.5, 0.02]), "converged": ("soc", np.ones(3, bool)),
            "Z": (("soc", "frequency"), np.tile(Z, (3, 1))), "Z_model": (("soc", "frequency"), np.tile(Z, (3, 1))),
        },
        coords={"param": ["R0", "R_sc", "C1"], "soc": [0.0, 0.1, 0.30000000000000004], "frequency": F},
        attrs={"model": "R0 + R_sc || C1", "weighting": "modulus", "impedax_kind": "batch_fit", "warnings": {}},
    )
    lines = BatchFitResult.from_xarray(ds).to_latex().splitlines()
    assert lines[0] == "% impedax fit: R0 + R_sc || C1, 3 spectra over soc (3), weighting modulus; value ± standard error"
    assert lines[1:3] == [r"\begin{tabular}{lllll}", r"\hline"]
    assert lines[3] == r"soc & R0 [$\Omega$] & R\_sc [$\Omega$] & C1 [$\mathrm{F}$] & rms\_rel [\%] \\"
    assert lines[5] == r"0.0 & $533 \pm 13$ & $0.01235 \pm 0.00067$ & $(1.0002 \pm 0.0028) \times 10^{-6}$ & 1.23 \\"
    assert lines[6] == r"0.1 & $12.35 \pm 0.50$ & $2.2 \times 10^{7} \pm 2.8 \times 10^{15}$ (undetermined) & $(1.000 \pm 0.010) \times 10^{-6}$ & 50 \\"
    assert lines[7] == r"0.3 & $12.35 \pm 0.50$ & $100$ (at bound) & $(1.000 \pm 0.010) \times 10^{-6}$ & 2 \\"
    assert lines[-2:] == [r"\hline", r"\end{tabular}"]


@pytest.mark.slow  # (~12 s: a global fit, compilation included)
def test_a_global_fit_s_table_marks_its_shared_parameter():
    """SYNTHETIC: three spectra of R0 + R1 ∥ CPE1 (numpy formula, α = 0.85, R1 growing; 0.3 %
    noise) fitted with CPE1.alpha shared over trial: its column is headed "(shared)" and the
    comment says what is shared (before, equal values in every row with no word why)."""
    import impedax as ix

    f = np.geomspace(0.1, 1e5, 30)
    rng = np.random.default_rng(2)
    z = np.stack([10 + r1 / (1 + r1 * 1e-4 * (2j * np.pi * f) ** 0.85) for r1 in (100.0, 120.0, 140.0)])
    z = z * (1 + 0.003 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)) / np.sqrt(2))
    fits = ix.fit("R0 + R1 || CPE1", ix.make_spectrum(f, z, dims="trial"), shared=["CPE1.alpha"], over="trial", progress=False)
    lines = fits.to_latex().splitlines()
    assert lines[0].startswith("% impedax fit: R0 + R1 || CPE1, 3 spectra over trial (3), CPE1.alpha shared over trial, weighting modulus")
    assert lines[3].split(" & ")[4] == "CPE1.alpha (shared)" and lines[3].split(" & ")[1] == r"R0 [$\Omega$]"
    assert len({line.split(" & ")[4] for line in lines[5:8]}) == 1  # (one estimate, repeated)


def _batch_of(n):
    """A batch of ``n`` SYNTHETIC fits written by hand (no fit): R0 = 10 ± 0.5 Ω, R1 from 90 to
    110 Ω ± 0.5 Ω, rms_rel 1 %, over ``cycle``."""
    ds = xr.Dataset(
        {
            "value": (("param", "cycle"), np.vstack([np.full(n, 10.0), np.linspace(90.0, 110.0, n)])), "stderr": (("param", "cycle"), np.full((2, n), 0.5)),
            "fixed": ("param", np.zeros(2, bool)), "at_bound": (("param", "cycle"), np.zeros((2, n), bool)),
            "rms_rel": ("cycle", np.full(n, 0.01)), "converged": ("cycle", np.ones(n, bool)),
            "Z": (("cycle", "frequency"), np.tile(Z, (n, 1))), "Z_model": (("cycle", "frequency"), np.tile(Z, (n, 1))),
        },
        coords={"param": ["R0", "R1"], "cycle": np.arange(n), "frequency": F},
        attrs={"model": "R0 + R1", "weighting": "modulus", "impedax_kind": "batch_fit", "warnings": {}},
    )
    return BatchFitResult.from_xarray(ds)


def test_130_spectra_make_a_longtable_that_breaks_across_pages():
    """The REAL battery set's 130 cycles gave a tabular of 130 rows, which LaTeX does not break:
    it ran off the page. More than 40 rows are a longtable: its heading before \\endhead (repeated on
    every page), a rule in \\endfoot, every row of 4 cells, and a comment naming the package.
    No LaTeX is installed to compile it: the structure is checked line by line."""
    lines = _batch_of(130).to_latex().splitlines()
    assert lines[0].startswith("% impedax fit: R0 + R1, 130 spectra over cycle (130)")
    assert lines[1].startswith("%") and r"\usepackage{longtable}" in lines[1]
    assert lines[2:9] == [r"\begin{longtable}{llll}", r"\hline", r"cycle & R0 [$\Omega$] & R1 [$\Omega$] & rms\_rel [\%] \\", r"\hline", r"\endhead", r"\hline", r"\endfoot"]
    rows = lines[9:-1]
    assert len(rows) == 130 and all(r.endswith(r" \\") and len(r[:-3].split(" & ")) == 4 for r in rows)
    assert rows[0] == r"0 & $10.00 \pm 0.50$ & $90.00 \pm 0.50$ & 1 \\" and rows[-1] == r"129 & $10.00 \pm 0.50$ & $110.00 \pm 0.50$ & 1 \\"
    assert lines[-1] == r"\end{longtable}" and "tabular" not in "\n".join(lines)
    body = "\n".join(lines)
    assert body.count(r"\begin{") == body.count(r"\end{") == 1


def test_40_spectra_stay_a_plain_tabular():
    lines = _batch_of(40).to_latex().splitlines()
    assert lines[1] == r"\begin{tabular}{llll}" and lines[-2:] == [r"\hline", r"\end{tabular}"] and "longtable" not in "\n".join(lines)
    assert len(lines) == 1 + 4 + 40 + 2
