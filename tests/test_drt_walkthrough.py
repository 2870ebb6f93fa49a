"""The DRT after a user walkthrough on REAL battery spectra (benchmarks/data/autoeis_battery_130.nc,
130 cycles): R_pol is the integral of the whole fitted expansion, the exported τ grid shows γ
fall at both ends, the files written from Python and from the command line are the same, and a
batch's report has a line per spectrum. Oracles: the DRT model's own impedance at f → 0
(`DRTResult.predict`, computed by quadrature of the basis kernels, independently of the
closed-form areas √π/ε), the data's labels, and the values in memory.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.data import format_quantity, format_time
from impedax.io.export import to_jsonable
from impedax.io.netcdf import read_netcdf

BATTERY = Path(__file__).resolve().parents[1] / "benchmarks" / "data" / "autoeis_battery_130.nc"


@pytest.fixture(scope="module")
def battery():
    return ix.load(BATTERY)


@pytest.fixture(scope="module")
def cycle64(battery):
    return ix.drt(battery.sel(cycle=64))


def test_r_pol_is_the_whole_expansion_so_r_inf_plus_r_pol_is_the_model_at_dc(cycle64):
    """Cycle 64 has a 25 s peak at the last basis centre: the old R_pol, the trapezoid over the
    centres' range, was 3.5625 Ω, 0.9 % below the model's own Z(0) − R_∞ = 3.5932 Ω."""
    r = cycle64
    assert np.isinf(r.c_f)  # no series C: Z(f → 0) = R_∞ + R_pol exactly
    z_dc = r.predict(np.array([1e-12]))[0]
    assert r.r_inf_ohm + r.polarization_resistance == pytest.approx(z_dc.real, rel=1e-9)
    assert r.summary()["r_pol_ohm"] == pytest.approx(z_dc.real - r.r_inf_ohm, rel=1e-9)


def test_the_exported_grid_shows_gamma_fall_and_holds_the_whole_area(cycle64):
    r = cycle64
    # the grid reaches past the outermost centres on both sides, and γ has fallen there
    assert r.tau[0] < r.basis_tau[0] and r.tau[-1] > r.basis_tau[-1]
    assert max(r.gamma[0], r.gamma[-1]) < 1e-4 * r.gamma.max()
    # so the area on the grid, and the peaks' areas (nothing is dropped on this cycle), are R_pol
    assert np.trapezoid(r.gamma, np.log(r.tau)) == pytest.approx(r.polarization_resistance, rel=1e-6)
    assert sum(p.r_ohm for p in r.peaks + r.dropped_peaks) == pytest.approx(r.polarization_resistance, rel=1e-6)
    # the inner points are those of the unextended grid: the basis centres' ends are on it
    assert np.isclose(r.tau, r.basis_tau[0], rtol=1e-12).sum() == 1 and np.isclose(r.tau, r.basis_tau[-1], rtol=1e-12).sum() == 1


def test_a_batch_keeps_the_identity_for_every_spectrum(battery):
    batch = ix.drt(battery.isel(cycle=[0, 64, 129]))
    for one in batch.results:
        assert one.r_inf_ohm + one.polarization_resistance == pytest.approx(one.predict(np.array([1e-12]))[0].real, rel=1e-9)


def test_the_report_says_gamma_is_in_ohms(cycle64):
    text = cycle64.report()
    assert "γ in units of max|Z|" not in text and "γ is reported in Ω" in text


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _same_table(python_csv, cli_csv) -> bool:
    """The command line's CSV is the Python one's, cell for cell, with provenance columns after its
    own but before its last, warnings (since 2026-12-06: tests/test_drt_csv_warnings.py)."""
    py, cli = _rows(python_csv), _rows(cli_csv)
    return len(py) == len(cli) and all(a == {k: b[k] for k in a} for a, b in zip(py, cli)) and [k for k in cli[0] if k in py[0]] == list(py[0])


def test_python_and_the_command_line_write_the_same_drt_files(tmp_path, battery, capsys):
    """.csv (γ over τ, lossless), .json (the summary) and .nc from `write_result` and from
    ``impedax drt --out``: both accept all three and write the same bytes / values."""
    data = battery.sel(cycle=64)
    source = tmp_path / "c64.nc"
    ix.save(data, source)
    r = ix.drt(ix.load(source))
    for ext in ("csv", "json", "nc"):
        ix.write_result(r, tmp_path / f"py.{ext}")
        assert main(["drt", str(source), "--out", str(tmp_path / f"cli.{ext}")]) == 0
    capsys.readouterr()
    # the same table; the command line's has the provenance columns after it (docs/io.md, "Provenance")
    assert _same_table(tmp_path / "py.csv", tmp_path / "cli.csv")
    rows = _rows(tmp_path / "cli.csv")
    assert list(rows[0])[:5] == ["tau_s", "gamma_ohm", "gamma_q05_ohm", "gamma_q95_ohm", "impedax_version"]
    # lossless: every float reads back to the same double (10 significant digits did not)
    assert np.array_equal([float(row["tau_s"]) for row in rows], r.tau)
    assert np.array_equal([float(row["gamma_ohm"]) for row in rows], r.gamma)
    assert np.array_equal([float(row["gamma_q95_ohm"]) for row in rows], r.gamma_q95)
    expected = json.loads(json.dumps(to_jsonable(r.summary())))
    written = json.loads((tmp_path / "cli.json").read_text())
    assert written.pop("source") == str(source)  # (the command line names the file it read, as kk and fit: 2026-12-01)
    from_python = json.loads((tmp_path / "py.json").read_text())
    assert from_python.pop("source") == str(source)  # (write_result names the result's own source by default: 2026-12-01)
    assert written.pop("provenance")["command"] == "impedax drt" and "provenance" not in from_python  # (docs/io.md, "Provenance")
    assert written.pop("skipped_rows") == [] and "skipped_rows" not in from_python  # (the reader's, from the command line: 2026-12-01)
    assert "kk_note" in written and "kk_note" not in from_python  # (the command line's KK test: 2026-12-05)
    written.pop("kk_note")
    assert written.pop("suggestion_withheld") is None and "suggestion_withheld" not in from_python  # (the command line's reading of the warnings: 2026-12-06)
    assert written == expected == from_python
    for name in ("py.nc", "cli.nc"):
        saved = read_netcdf(tmp_path / name)
        assert np.array_equal(saved["Z"].values, r.impedance) and np.array_equal(saved["gamma"].values, r.gamma)


def test_a_batch_writes_label_columns_and_its_json_is_the_commands(tmp_path, battery, capsys):
    data = battery.isel(cycle=[3, 7])
    source = tmp_path / "two.nc"
    ix.save(data, source)
    batch = ix.drt(ix.load(source))
    ix.write_result(batch, tmp_path / "py.csv")
    assert main(["drt", str(source), "--out", str(tmp_path / "cli.csv")]) == 0
    capsys.readouterr()
    assert main(["drt", str(source), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed.pop("source") == str(source)  # (the command line names the file it read, as kk and fit: 2026-12-01)
    assert printed.pop("provenance")["command"] == "impedax drt"
    assert printed.pop("skipped_rows") == []  # (the reader's, from the command line: 2026-12-01)
    assert "kk_note" in printed  # (the command line's KK test: 2026-12-05)
    printed.pop("kk_note")
    assert printed.pop("suggestion_withheld") is None  # (the command line's reading of the warnings: 2026-12-06)
    assert printed == json.loads(json.dumps(to_jsonable(batch.summary())))
    assert printed["dims"] == ["cycle"] and printed["sizes"] == {"cycle": 2} and [s["labels"] for s in printed["spectra"]] == [{"cycle": 3}, {"cycle": 7}]
    assert _same_table(tmp_path / "py.csv", tmp_path / "cli.csv")
    rows = _rows(tmp_path / "py.csv")
    n_tau = batch.results[0].tau.size
    assert list(rows[0])[0] == "cycle" and len(rows) == 2 * n_tau
    assert [row["cycle"] for row in rows[::n_tau]] == ["3", "7"]
    assert np.array_equal([float(row["gamma_ohm"]) for row in rows[n_tau:]], batch.results[1].gamma)


def test_a_batch_report_has_a_line_per_spectrum_as_the_command_prints(tmp_path, battery, capsys):
    data = battery.isel(cycle=[0, 64, 129])
    source = tmp_path / "three.nc"
    ix.save(data, source)
    batch = ix.drt(ix.load(source))
    text = batch.report()
    lines = text.splitlines()
    assert len(lines) == 4 and lines[0].startswith("DRT of 3 spectra over cycle")
    for line, label, one in zip(lines[1:], (0, 64, 129), batch.results):
        assert line.startswith(f"  cycle={label}: rms_rel") and f"R_inf {format_quantity(one.r_inf_ohm, 'Ω', 4)}," in line and f"R_pol {format_quantity(one.polarization_resistance, 'Ω', 4)}," in line
        # τ as the single report prints it ("167 µs", not "0.000167 s"; 2026-12-01)
        assert all(f"{format_time(p.tau_s)} ({format_quantity(p.r_ohm, 'Ω')}" in line for p in one.peaks)  # (R with its SI prefix, as the single report)
    assert main(["drt", str(source)]) == 0
    # the report, then (2026-12-02) the starting circuit most spectra suggest
    out, suggestion = capsys.readouterr().out, batch.results[0].suggested_circuit()
    report, last = out.removesuffix("\n").rsplit("\n", 1)
    assert report == text
    assert last.startswith(f"starting circuit from the DRT (the one 3 of 3 spectra suggest, starts from the first of them): {suggestion.model} — fit it with: impedax fit ")


def test_an_overlay_delta_off_the_tau_axis_is_named_in_the_legend_not_drawn(cycle64):
    """A fitted R‖C far from the data (R2 = 2 MΩ, C2 = 25 F: τ = R·C = 5·10⁷ s) has no line on
    the γ axes; the legend used to say "R‖C deltas" over nothing. The in-range delta is drawn."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    from impedax.fitting.drt import circuit_drt

    overlay = circuit_drt("R0 + R1 || C1 + R2 || C2", {"R0": 0.16, "R1": 1.0, "C1": 0.07, "R2": 2e6, "C2": 25.0})
    assert sorted(tau for tau, _ in overlay.deltas) == pytest.approx([0.07, 5e7])
    fig = cycle64.plot(overlay=overlay)
    try:
        ax = fig.axes[0]
        texts = [t.get_text() for t in ax.get_legend().get_texts()]
        (note,) = [t for t in texts if "outside the plotted τ range" in t]
        assert "2 MΩ" in note and "5e+07 s" in note
        assert "R‖C deltas (R in labels)" in texts  # the one at 70 ms is drawn
        drawn = [seg for c in ax.collections if isinstance(c, LineCollection) for seg in c.get_segments()]
        assert len(drawn) == 1 and drawn[0][0][0] == pytest.approx(0.07)
    finally:
        plt.close(fig)


def test_a_batch_json_gives_the_starting_circuit_the_text_ends_with(tmp_path, battery, capsys):
    """The batch JSON had each spectrum's suggestion but not the one the text's last line gives
    (the circuit most spectra suggest, from the first of them), nor top-level ``warnings`` as
    ``impedax kk --json`` has (2026-12-06). Cycle 3 suggests a third arc, cycles 64, 89 and 100 do
    not: 3 of 4, started from cycle 64. Oracle: the printed line, read back."""
    source = tmp_path / "four.nc"
    ix.save(battery.sel(cycle=[3, 64, 89, 100]), source)
    assert main(["drt", str(source)]) == 0
    last = capsys.readouterr().out.removesuffix("\n").rsplit("\n", 1)[1]
    head, command = last.split(" — fit it with: ")
    assert head.startswith("starting circuit from the DRT (the one 3 of 4 spectra suggest, starts from the first of them): ")
    model = head.split("): ", 1)[1]
    starts = dict(item.split("=") for item in command.split(" --init ")[1].split())
    assert f"--model '{model}'" in command
    assert main(["drt", str(source), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["suggested_model"] == model and printed["n_suggesting"] == 3 and printed["suggested_from"] == {"cycle": 64}
    assert {name: f"{value:.4g}" for name, value in printed["suggested_init"].items()} == starts
    assert printed["suggestion_reasons"] == printed["spectra"][1]["suggestion_reasons"]
    assert printed["spectra"][0]["suggested_model"] != model
    # the spectra's warnings, each once (cycle 89's: γ does not reproduce it)
    assert printed["warnings"] and printed["warnings"] == sorted({w for s in printed["spectra"] for w in s["warnings"]})
