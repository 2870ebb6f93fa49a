"""What a lab-automation run reads from the outputs (walkthrough of 2026-12-01, `--json` only):
standard input named ``<stdin>`` everywhere, parameter units in every fit's JSON, a single fit's
CSV with the batch's fit-quality columns, the reader's skipped rows and the KK test's notes in
the analysis JSON, ``warnings`` and ``converged`` where they were missing, messages that name
the band and the command, singular counts, and ``kk --out``.

SYNTHETIC spectra are numpy formulas written here (R0 + R1 ∥ C1, 0.5 % noise, fixed seeds);
the REAL Parstat file of tests/fixtures is read for its 781 DC rows."""

from __future__ import annotations

import csv
import io
import json
import sys
from pathlib import Path

import numpy as np
import pytest

from impedax.cli import main

FIXTURES = Path(__file__).parent / "fixtures" / "real"
PARSTAT = FIXTURES / "exampleDataParstat.txt"  # REAL: 781 DC rows (f = 0) before 31 points

R0, R1, C1 = 10.0, 100.0, 10e-6  # SYNTHETIC truth [Ω, Ω, F]


def rc_impedance(f: np.ndarray) -> np.ndarray:
    """R0 + R1 ∥ C1 [Ω] at ``f`` [Hz]: R0 + R1 / (1 + jωR1C1)."""
    return R0 + R1 / (1 + 2j * np.pi * f * R1 * C1)


def csv_text(f: np.ndarray, seed: int = 7, noise: float = 0.005) -> str:
    """SYNTHETIC: the R0 + R1 ∥ C1 spectrum at ``f`` with ``noise`` × |Z| Gaussian noise per
    component (seed ``seed``), as impedax's canonical CSV."""
    rng = np.random.default_rng(seed)
    z = rc_impedance(f)
    z = z + noise * np.abs(z) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
    return "frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{float(a)!r},{float(b.real)!r},{float(b.imag)!r}\n" for a, b in zip(f, z))


F31 = np.geomspace(0.1, 1e5, 31)


@pytest.fixture
def good(tmp_path) -> Path:
    path = tmp_path / "good.csv"
    path.write_text(csv_text(F31))
    return path


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def run_json(capsys, *argv: str) -> dict:
    code, out, err = run(capsys, *argv)
    assert code == 0, err
    return json.loads(out)


def stdin_holds(monkeypatch, text: str) -> None:
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(text.encode())))


def rows_of(path: Path) -> list[dict]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


# --- 1. standard input ------------------------------------------------------------------------


def test_standard_input_is_named_stdin_in_every_output(tmp_path, capsys, monkeypatch):
    stdin_holds(monkeypatch, csv_text(F31))
    out = tmp_path / "fit.csv"
    summary = run_json(capsys, "fit", "-", "--model", "R0 + R1 || C1", "--json", "--out", out)
    assert summary["source"] == "<stdin>" and summary["provenance"]["source"] == "<stdin>"
    assert summary["provenance"]["data_files"] == ["<stdin>"]  # (was [])
    rows = rows_of(out)
    assert {r["source"] for r in rows} == {"<stdin>"} and {r["data_files"] for r in rows} == {"<stdin>"}
    assert ".impedax-stdin" not in json.dumps(summary) + out.read_text()
    assert summary["params"]["R1"]["value"] == pytest.approx(R1, rel=0.02)  # (the spectrum on stdin was fitted)

    stdin_holds(monkeypatch, csv_text(F31))
    kk = run_json(capsys, "kk", "-", "--json")
    assert kk["source"] == "<stdin>" and kk["provenance"]["data_files"] == ["<stdin>"]


def test_a_sweep_of_standard_input_is_selected_and_named(capsys, monkeypatch):
    """SYNTHETIC: two sweeps of 21 and 25 points on different grids, one after the other."""
    first, second = np.geomspace(0.1, 1e5, 21), np.geomspace(0.1, 1e5, 25)
    text = csv_text(first) + csv_text(second, seed=8).split("\n", 1)[1]
    stdin_holds(monkeypatch, text)
    summary = run_json(capsys, "fit", "-", "--select", "sweep=1", "--model", "R0 + R1 || C1", "--json")
    assert summary["n_points"] == second.size and summary["source"] == "<stdin> [sweep=1]"  # (was refused: stdin is read once)
    stdin_holds(monkeypatch, text)
    code, _, err = run(capsys, "fit", "-", "--select", "sweep=7", "--model", "R0 + R1 || C1")
    assert code == 2 and "--select sweep=7: <stdin> holds 2 sweeps" in err


# --- 2. units, 3. the single fit's CSV -----------------------------------------------------------


EXPECTED_UNITS = {"R0": "Ohm", "R1": "Ohm", "CPE1.Q": "F s^(alpha-1)", "CPE1.alpha": "1"}  # (the element specs', by hand)


def test_every_fit_json_gives_each_parameter_its_unit(good, tmp_path, capsys):
    out = tmp_path / "f.csv"
    summary = run_json(capsys, "fit", good, "--model", "R0 + R1 || CPE1", "--json", "--out", out)
    assert {n: p["unit"] for n, p in summary["params"].items()} == EXPECTED_UNITS
    assert {r["name"]: r["unit"] for r in rows_of(out)} == EXPECTED_UNITS  # (the CSV's, the same)
    assert set(summary["params"]["R0"]) == {"value", "stderr", "fixed", "unit", "linearised_stderr"}  # (keys only added; linearised_stderr 2026-12-02)
    compared = run_json(capsys, "compare", good, "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "--json")
    units = [{n: p["unit"] for n, p in m["params"].items()} for m in compared["models"]]
    assert units == [{"R0": "Ohm", "R1": "Ohm", "C1": "F"}, EXPECTED_UNITS]


def test_a_single_fit_csv_has_the_batch_fit_quality_columns(good, tmp_path, capsys):
    out = tmp_path / "f.csv"
    summary = run_json(capsys, "fit", good, "--model", "R0 + R1 || C1", "--json", "--out", out)
    rows = rows_of(out)
    assert list(rows[0])[:13] == ["name", "value", "stderr", "unit", "fixed", "rms_rel", "chi2", "chi2_red", "aic", "bic", "converged", "at_bound", "undetermined"]
    for key in ("rms_rel", "chi2", "chi2_red", "aic", "bic"):
        assert {float(r[key]) for r in rows} == {summary[key]}  # (the same on every row, the JSON's)
    # oracle: rms_rel = sqrt(mean |Z_model − Z|² / |Z|²) from the fitted values and the data (numpy)
    data = np.loadtxt(good, delimiter=",", skiprows=1)
    f, z = data[:, 0], data[:, 1] + 1j * data[:, 2]
    v = {r["name"]: float(r["value"]) for r in rows}
    model = v["R0"] + v["R1"] / (1 + 2j * np.pi * f * v["R1"] * v["C1"])
    assert float(rows[0]["rms_rel"]) == pytest.approx(np.sqrt(np.mean(np.abs(model - z) ** 2 / np.abs(z) ** 2)), rel=1e-9)
    assert 0.003 < float(rows[0]["rms_rel"]) < 0.01  # (the 0.5 % per component noise: ~0.7 % rms of |ΔZ|/|Z|)


# --- 4. the reader's skipped rows, the KK test's notes --------------------------------------------


def test_skipped_rows_reach_kk_fit_and_drt_json_as_inspect_gives_them(capsys):
    inspected = run_json(capsys, "inspect", PARSTAT, "--json")["skipped_rows"]
    assert inspected == ["lines 2–782: f = 0 (DC row, not an impedance point)"]  # REAL: 781 DC rows
    assert run_json(capsys, "kk", PARSTAT, "--json")["skipped_rows"] == inspected
    assert run_json(capsys, "drt", PARSTAT, "--json")["skipped_rows"] == inspected
    assert run_json(capsys, "fit", PARSTAT, "--model", "R0 + R1 || C1", "--json")["skipped_rows"] == inspected
    code, out, err = run(capsys, "kk", PARSTAT)  # text: one line on stderr, none in the report
    assert code == 0 and "lines 2–782" not in out
    assert [line for line in err.splitlines() if "skipped" in line] == [f"impedax kk: note: {PARSTAT}: rows skipped as no impedance points: lines 2–782: f = 0 (DC row, not an impedance point)"]


def test_a_file_without_skipped_rows_says_so_with_an_empty_list(good, capsys):
    assert run_json(capsys, "kk", good, "--json")["skipped_rows"] == []
    code, _, err = run(capsys, "kk", good)
    assert code == 0 and "skipped" not in err


def test_the_sparse_data_note_is_in_the_kk_json(tmp_path, capsys):
    """SYNTHETIC: 15 points over 7 decades (about 2 a decade, 0.5 % noise): the Voigt chain's own
    misfit is above the noise, which the text says; the JSON now too."""
    path = tmp_path / "sparse.csv"
    path.write_text(csv_text(np.geomspace(1e-2, 1e5, 15), seed=11))
    summary = run_json(capsys, "kk", path, "--json")
    _, text, _ = run(capsys, "kk", path)
    sparse = [n for n in summary["notes"] if n.startswith("sparse data:")]
    assert len(sparse) == 1 and sparse[0] in text and "judged against that, not the noise" in sparse[0]
    assert summary["warnings"] == summary["notes"] + ([summary["sign_hint"]] if summary["sign_hint"] else [])
    assert summary["chain_error"] > max(summary["noise_estimate"], 0.0)  # (why the note is there)
    dense = run_json(capsys, "kk", _dense(tmp_path), "--json")
    assert dense["notes"] == [] and dense["warnings"] == []


def _dense(tmp_path) -> Path:
    path = tmp_path / "dense.csv"
    path.write_text(csv_text(F31))
    return path


# --- 5. warnings and converged of diagnose and refine ---------------------------------------------


@pytest.mark.slow
def test_diagnose_and_refine_json_give_warnings_and_converged(good, capsys):
    diagnosis = run_json(capsys, "diagnose", good, "--model", "R0 + R1 || C1", "--bound", "R1=50:500", "--json")
    assert diagnosis["baseline"]["converged"] is True
    assert any(n.startswith("your bounds (") for n in diagnosis["notes"])  # (information only: no warning)
    assert diagnosis["warnings"] == [n for n in diagnosis["notes"] if not n.startswith("your bounds (")]
    assert {n: p["unit"] for n, p in diagnosis["baseline"]["params"].items()} == {"R0": "Ohm", "R1": "Ohm", "C1": "F"}
    refined = run_json(capsys, "refine", good, "--model", "R0 + R1 || C1", "--json")
    assert refined["final_converged"] is True and refined["warnings"] == refined["notes"]
    assert {n: p["unit"] for n, p in refined["final_params"].items()} == {"R0": "Ohm", "R1": "Ohm", "C1": "F"}


# --- 6. messages ----------------------------------------------------------------------------------


def test_too_few_points_names_the_band(good, capsys):
    code, _, err = run(capsys, "fit", good, "--model", "R0 + R1 || C1", "--fmin", "99999")
    assert code == 2
    assert f"{good}: 3 free parameters but only 2 real data values (1 frequency at or above --fmin = 99999 Hz); fix parameters or use more data (a wider band)" in err
    code, _, err = run(capsys, "fit", good, "--model", "R0 + R1 || C1", "--fmin", "5e4", "--fmax", "99999")
    assert code == 2 and "(1 frequency from --fmin = 50 kHz to --fmax = 99999 Hz)" in err


def test_too_few_points_for_sample_is_its_one_line_with_the_band(good, capsys):
    """A hostile walkthrough (2026-12-08): sample printed "sample: fitting the least-squares
    start …" before this error, and left the band out of it ("(1 frequency)", of a file of more)."""
    code, out, err = run(capsys, "sample", good, "--model", "R0 + R1 || C1", "--fmin", "99999")
    assert code == 2 and out == ""
    assert err == (f"impedax sample: error: {good}: 3 free parameters but only 2 real data values (1 frequency at or above --fmin = 99999 Hz); "
                   "fix parameters or use more data (a wider band)\n")


def test_too_few_points_for_refine_names_refine_and_counts_in_the_singular(tmp_path, capsys):
    path = tmp_path / "two.csv"
    path.write_text(csv_text(np.array([1.0, 10.0])))  # SYNTHETIC: two points
    code, _, err = run(capsys, "refine", path, "--model", "R0 + R1 || C1")
    assert code == 2 and f"impedax refine: error: {path}: refine needs at least 4 frequencies for 3 free parameters" in err
    code, _, err = run(capsys, "diagnose", path, "--model", "R1")
    assert code == 2 and "diagnose needs at least 4 frequencies for 1 free parameter and" in err


def test_too_few_points_for_diagnose_names_the_file_and_the_band(capsys):
    # REAL exampleDataZPlot.z (21 points, 3 kHz–300 kHz): 10–12 kHz keeps one (11.94 kHz), below
    # 3.5 kHz one (3 kHz); the message said "got 1", naming neither the file nor the band
    path = "tests/fixtures/real/exampleDataZPlot.z"
    code, _, err = run(capsys, "diagnose", path, "--model", "R0 + R1 || CPE1", "--fmin", "1e4", "--fmax", "1.2e4")
    assert code == 2
    assert f"impedax diagnose: error: {path}: diagnose needs at least 4 frequencies for 4 free parameters and the Kramers–Kronig test, got 1 from --fmin = 10 kHz to --fmax = 12 kHz" in err
    code, _, err = run(capsys, "refine", path, "--model", "R0 + R1 || CPE1", "--fmax", "3.5e3")
    assert code == 2 and f"{path}: refine needs at least 4 frequencies for 4 free parameters and the Kramers–Kronig test, got 1 at or below --fmax = 3.5 kHz" in err
    assert "Traceback" not in err


def test_a_kk_batch_of_one_spectrum_is_one_spectrum(tmp_path, capsys):
    """SYNTHETIC: two spectra along cycle; a range that picks one keeps the dimension."""
    import impedax as ix

    rng = np.random.default_rng(5)
    z = np.stack([rc_impedance(F31) * (1 + 0.005 * (rng.normal(size=F31.size) + 1j * rng.normal(size=F31.size))) for _ in range(2)])
    path = tmp_path / "cycles.nc"
    ix.save(ix.make_spectrum(F31, z, dims=("cycle",)).assign_coords(cycle=[1, 2]), path)
    code, out, err = run(capsys, "kk", path, "--select", "cycle=1:1")
    assert code == 0, err
    assert out.startswith("linear KK test of 1 spectrum over cycle:")


# --- 7. kk --out ----------------------------------------------------------------------------------


def test_kk_out_writes_the_csv_and_json_of_the_test(good, tmp_path, capsys):
    table, document = tmp_path / "kk.csv", tmp_path / "kk.json"
    printed = run_json(capsys, "kk", good, "--json", "--out", document)
    saved = json.loads(document.read_text())
    for d in (printed, saved):
        d["provenance"].pop("written_utc")
    assert saved == printed  # (--out x.json is the --json document)
    assert run(capsys, "kk", good, "--out", table)[0] == 0
    rows = rows_of(table)
    assert list(rows[0])[:8] == ["frequency_hz", "z_real_ohm", "z_imag_ohm", "z_kk_real_ohm", "z_kk_imag_ohm", "residual_real", "residual_imag", "flagged"]
    data = np.loadtxt(good, delimiter=",", skiprows=1)
    np.testing.assert_array_equal([float(r["frequency_hz"]) for r in rows], data[:, 0])
    # oracle: Δ' = (Z' − Z'_kk)/|Z| from the table's own columns (numpy), and the JSON's residuals
    z = np.array([float(r["z_real_ohm"]) + 1j * float(r["z_imag_ohm"]) for r in rows])
    z_kk = np.array([float(r["z_kk_real_ohm"]) + 1j * float(r["z_kk_imag_ohm"]) for r in rows])
    np.testing.assert_allclose([float(r["residual_real"]) for r in rows], (z - z_kk).real / np.abs(z), rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose([float(r["residual_imag"]) for r in rows], printed["residuals_imag"], rtol=1e-12)
    assert {r["source"] for r in rows} == {str(good)}  # (the provenance columns follow)


def test_kk_out_is_checked_before_any_work(good, tmp_path, capsys):
    code, out, err = run(capsys, "kk", good, "--out", tmp_path / "kk.xlsx")
    assert code == 2 and "--out: unknown result extension '.xlsx'" in err and not out
    code, _, err = run(capsys, "kk", good, "--json", "--out", "-")
    assert code == 2 and "--out - and --json both write to standard output" in err
    assert not list(tmp_path.iterdir()) or [p.name for p in tmp_path.iterdir()] == ["good.csv"]
