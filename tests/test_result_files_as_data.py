"""A DRT's or a KK test's written summary (write_result, ``--out``) given where a spectrum is
expected is named as what it is (io.export.written_result), as a fit's is
(tests/test_fit_roundtrip.py, a slow file). Spectra: SYNTHETIC closed forms."""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix
from impedax.errors import DataError


@pytest.mark.parametrize("suffix, what", [(".csv", "a DRT"), (".json", "a DRT")])
def test_a_drt_output_given_as_data_is_named(tmp_path, suffix, what):
    """`ix.drt(...)` written with write_result, then loaded where a spectrum is expected: it was
    told only that the table has no frequency column (a walkthrough's DRT CSV fed to fit)."""
    f = np.geomspace(0.1, 1e5, 41)
    z = 10 + 100 / (1 + 2j * np.pi * f * 1e-3)  # SYNTHETIC R‖C, closed form
    out = tmp_path / f"g{suffix}"
    ix.write_result(ix.drt((f, z)), out)
    with pytest.raises(DataError, match=f"summary of {what} .*impedax drt --out.*not a spectrum"):
        ix.load(out)


def test_a_kk_json_given_as_data_is_named(tmp_path):
    f = np.geomspace(0.1, 1e5, 41)
    z = 10 + 100 / (1 + 2j * np.pi * f * 1e-3)
    out = tmp_path / "kk.json"
    ix.write_result(ix.kk_test((f, z)), out)
    with pytest.raises(DataError, match="summary of a Kramers–Kronig test .*impedax kk --out.*not a spectrum"):
        ix.load(out)


@pytest.mark.parametrize("analysis, what, command", [(ix.drt, "a batch of DRTs", "drt"), (ix.kk_test_batch, "a batch of Kramers–Kronig tests", "kk")])
def test_a_batch_json_given_as_data_is_named(tmp_path, analysis, what, command):
    """A stack's DRT or KK summary holds each spectrum's under "spectra"; it was told "no
    frequency column" (2026-12-04). Two SYNTHETIC R‖C spectra, closed forms."""
    f = np.geomspace(0.1, 1e5, 41)
    z = np.array([10 + r / (1 + 2j * np.pi * f * r * 1e-5) for r in (100.0, 150.0)])
    out = tmp_path / "stack.json"
    ix.write_result(analysis(ix.make_spectrum(f, z, dims=("cell",))), out)
    with pytest.raises(DataError, match=f"JSON summary of {what} .*impedax {command} --out.*not a spectrum"):
        ix.load(out)


def test_a_drt_csv_with_carriage_returns_alone_is_named(tmp_path):
    """A result's CSV saved with bare carriage returns as line ends (an old Mac editor's) is
    named as a DRT's summary too: the csv module alone stops at a bare ``\\r``."""
    f = np.geomspace(0.1, 1e5, 41)
    z = 10 + 100 / (1 + 2j * np.pi * f * 1e-3)  # SYNTHETIC R‖C, closed form
    out = tmp_path / "g.csv"
    ix.write_result(ix.drt((f, z)), out)
    out.write_bytes(out.read_bytes().replace(b"\r\n", b"\n").replace(b"\n", b"\r"))
    with pytest.raises(DataError, match="summary of a DRT .*not a spectrum"):
        ix.load(out)


def test_a_bare_carriage_return_in_the_first_line_is_a_data_error(tmp_path):
    """``a\\rb`` as a file's first line ended in "_csv.Error: new-line character seen in
    unquoted field" from the result-file check, exit 1 (a KK/DRT walkthrough, 2026-12-05)."""
    path = tmp_path / "cr.txt"
    path.write_bytes(b"a\rb\n")
    with pytest.raises(DataError, match=r"cr\.txt, line 1: not a recognised spectrum file"):
        ix.load(path)



def _rc_spectra(n_spectra: int):
    """SYNTHETIC R0 + R1 ‖ C1 spectra, closed forms (R1 = 100, 150, ... Ω; τ = R1 · 10 µF)."""
    f = np.geomspace(0.1, 1e5, 41)
    z = np.array([10 + r / (1 + 2j * np.pi * f * r * 1e-5) for r in (100.0, 150.0)[:n_spectra]])
    return ix.make_spectrum(f, z[0]) if n_spectra == 1 else ix.make_spectrum(f, z, dims=("cell",))


@pytest.mark.parametrize("suffix", [".csv", ".json"])
@pytest.mark.parametrize("n_spectra, what", [(1, "a Z-HIT test"), (2, "a batch of Z-HIT tests")])
def test_a_zhit_output_given_as_data_is_named(tmp_path, suffix, n_spectra, what):
    """A Z-HIT test's CSV or JSON (impedax kk --method zhit --out) given as data: until 2026-12-06
    "no frequency column in header ['{']" (the JSON) or "cannot find impedance columns" (the CSV),
    where a linear KK test's was named; the command that writes the .nc is spelt whole, its file kk.nc."""
    data = _rc_spectra(n_spectra)
    out = tmp_path / f"zhit{suffix}"
    ix.write_result(ix.zhit(data) if n_spectra == 1 else ix.zhit_batch(data), out)
    with pytest.raises(DataError) as err:
        ix.load(out)
    assert str(err.value) == (f"{out}: this file is the {suffix[1:].upper()} summary of {what} (write_result, impedax kk --method zhit --out), not a spectrum: "
                              "it is to read, not to load back; the form that reads back is a .nc: write the result with ix.write_result(result, 'kk.nc') "
                              "(impedax kk --method zhit --out kk.nc), then ix.io.read_netcdf('kk.nc')")


@pytest.mark.slow  # (about 45 s: two fits of one spectrum and two batch fits of two)
@pytest.mark.parametrize("n_spectra, what, call", [
    (1, "a comparison of models on one spectrum", "ix.io.read_netcdf('compare.nc')"),
    (2, "a comparison of models over many spectra", "ix.BatchComparison.from_xarray(ix.load('compare.nc'))"),
])
def test_a_comparison_output_given_as_data_is_named(tmp_path, n_spectra, what, call):
    """A comparison's CSV or JSON (impedax compare --out) given as data: until 2026-12-06 "no
    frequency column in header ['model', 'label', ...]" or "... ['{']"."""
    data = _rc_spectra(n_spectra)
    comparison = ix.compare([ix.fit("R0 + R1 || C1", data), ix.fit("R0 + R1", data)])
    for suffix in (".csv", ".json"):
        out = tmp_path / f"c{suffix}"
        ix.write_result(comparison, out)
        with pytest.raises(DataError) as err:
            ix.load(out)
        assert str(err.value) == (f"{out}: this file is the {suffix[1:].upper()} summary of {what} (write_result, impedax compare --out), not a spectrum: "
                                  f"it is to read, not to load back; the form that reads back is a .nc: write the result with ix.write_result(result, 'compare.nc') "
                                  f"(impedax compare --out compare.nc), then {call}")
