"""Sweeps one after another in one table on different frequency grids: refused with one message
(file, line, counts), read one alone with ``--select sweep=K`` / ``load(path, sweep=K)``; sweeps
on one grid still stack. All data SYNTHETIC (an R0 + R1||C1 formula with 0.3 % noise)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

R0, R1, C1 = 100.0, 1e4, 1e-5  # Ω, Ω, F: one arc, relaxation at 1/(2π R1 C1) ≈ 1.6 Hz
F_DAY1 = np.logspace(5, -2, 50)  # Hz, 100 kHz → 10 mHz (descending, as an analyser sweeps)
LINE_OF_DAY2 = 2 + F_DAY1.size  # header on line 1, day 1 on lines 2–51


def rc_arc(f, seed):
    """SYNTHETIC Z = R0 + R1/(1 + jωR1C1) with 0.3 % proportional complex noise."""
    z = R0 + R1 / (1 + 1j * 2 * np.pi * f * R1 * C1)
    rng = np.random.default_rng(seed)
    return z * (1 + 0.003 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))


def write_days(path, grids, *, header="frequency_hz,z_real_ohm,z_imag_ohm", cycles=None):
    """SYNTHETIC table: sweep k on ``grids[k]`` (seed k), one after another."""
    rows = [header]
    for k, f in enumerate(grids):
        z = rc_arc(f, seed=k)
        rows += [f"{fi!r},{zi.real!r},{zi.imag!r}" + ("" if cycles is None else f",{cycles[k]}") for fi, zi in zip(f.tolist(), z.tolist())]
    path.write_text("\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("header", ["frequency_hz,z_real_ohm,z_imag_ohm", "freq/Hz,Re(Z)/Ohm,Im(Z)/Ohm"])
def test_sweeps_on_grids_shifted_1_percent_are_refused_naming_file_line_and_counts(tmp_path, capsys, header):
    path = write_days(tmp_path / "two_days.csv", [F_DAY1, F_DAY1 * 1.01], header=header)
    for command in (["inspect", str(path)], ["kk", str(path)], ["fit", str(path), "--model", "R0 + R1 || C1"]):
        assert main(command) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err
        assert f"{path}, line {LINE_OF_DAY2}: the table holds 2 sweeps on different frequency grids" in err
        assert f"sweep 0: 50 points, 100000–0.01 Hz, lines 2–51; sweep 1: 50 points, 101000–0.0101 Hz, lines 52–101" in err
        assert "differ by up to 1.0e-02 relative" in err and "--select sweep=0 (or sweep=1;" in err
    with pytest.raises(ix.SweepGridsDiffer) as caught:
        ix.load(path)
    assert caught.value.line == LINE_OF_DAY2 and caught.value.labels == ["0", "1"] and isinstance(caught.value, ix.DataError)


def test_select_reads_one_sweep_of_its_own_grid(tmp_path, capsys):
    path = write_days(tmp_path / "two_days.csv", [F_DAY1, F_DAY1 * 1.01])
    for k, grid in enumerate([F_DAY1, F_DAY1 * 1.01]):
        ds = ix.load(path, sweep=str(k))
        assert ds["Z"].dims == ("frequency",)
        order = np.argsort(grid)  # (the data model may sort the grid: compare point by point)
        np.testing.assert_allclose(np.sort(ds["frequency"].values), grid[order], rtol=1e-15)
        z = ds["Z"].sortby("frequency").values
        np.testing.assert_allclose(z, rc_arc(grid, seed=k)[order], rtol=1e-14)
    assert main(["kk", str(path), "--select", "sweep=1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["rms_rel"] < 0.01  # one sweep, 0.3 % noise: KK-consistent (the two merged gave 11.8 %)
    assert main(["inspect", str(path), "--select", "sweep=1"]) == 0
    shown = capsys.readouterr().out
    assert "50 frequencies" in shown and "selection: sweep=1" in shown and "sweep 1 of 2, read alone (lines 52–101)" in shown
    # a list or range cannot stack two grids; an unknown label names the labels
    for label in ("0:1", "0,1", "2"):
        assert main(["kk", str(path), "--select", f"sweep={label}"]) == 2
        assert f"--select sweep={label}: {path} holds 2 sweeps on different frequency grids" in capsys.readouterr().err


def test_sweeps_of_different_lengths_and_cycles_on_different_grids_are_refused(tmp_path, capsys):
    shorter = np.logspace(5, -2, 40)
    path = write_days(tmp_path / "lengths.csv", [F_DAY1, shorter])
    with pytest.raises(ix.DataError, match=rf"line {LINE_OF_DAY2}: the table holds 2 sweeps .*sweep 1: 40 points.* of different numbers of points"):
        ix.load(path)
    path = write_days(tmp_path / "cycles.csv", [F_DAY1, F_DAY1 * 1.01], header="freq/Hz,Re(Z)/Ohm,Im(Z)/Ohm,cycle number", cycles=[3, 4])
    with pytest.raises(ix.DataError, match=rf"line {LINE_OF_DAY2}: the table holds 2 cycles on different frequency grids \(the cycle number changes on line {LINE_OF_DAY2}"):
        ix.load(path)
    assert main(["inspect", str(path), "--select", "cycle=4"]) == 0
    assert "selection: cycle=4" in capsys.readouterr().out


def test_sweeps_on_one_grid_still_stack_and_one_spectrum_stays_one(tmp_path):
    # SYNTHETIC: day 2's frequencies off by 2e-4 (an instrument's last digits): one grid, stacked
    path = write_days(tmp_path / "same.csv", [F_DAY1, F_DAY1 * (1 + 2e-4)])
    ds = ix.load(path)
    assert ds["Z"].dims == ("sweep", "frequency") and ds.sizes["sweep"] == 2
    assert ds.attrs["sweeps"].startswith(f"2 sweeps of 50 points (the frequency list restarts on line {LINE_OF_DAY2})")
    np.testing.assert_allclose(ix.load(path, sweep="1")["Z"].values, ds["Z"].isel(sweep=1).values)
    # two ranges of one spectrum, low then high (no jump back to the start): one spectrum
    path = write_days(tmp_path / "pieces.csv", [np.logspace(1, -2, 20), np.logspace(5, 1.2, 20)])
    assert ix.load(path)["Z"].dims == ("frequency",) and ix.load(path).sizes["frequency"] == 40
    with pytest.raises(ix.DataError, match="holds no sweeps to pick from"):
        ix.load(path, sweep="0")


def test_workbook_sheet_of_sweeps_on_different_grids(tmp_path, capsys):
    """SYNTHETIC workbook: a sheet of two days on shifted grids is refused; alone in its
    workbook, --select picks a sweep; beside another sheet, picking it would drop that sheet,
    so the message says to save each sweep on its own."""
    openpyxl = pytest.importorskip("openpyxl")

    def book(path, n_sheets):
        workbook = openpyxl.Workbook()
        workbook.remove(workbook.active)
        for s in range(n_sheets):
            table = workbook.create_sheet(f"S{s}")
            table.append(["Frequency (Hz)", "Z' (Ohm)", "Z'' (Ohm)"])
            for k, f in enumerate([F_DAY1, F_DAY1 * 1.01]):
                for fi, zi in zip(f.tolist(), rc_arc(f, seed=k).tolist()):
                    table.append([fi, zi.real, zi.imag])
        workbook.save(path)
        return path

    one = book(tmp_path / "one.xlsx", 1)
    with pytest.raises(ix.SweepGridsDiffer, match=rf"sheet S0\], row {LINE_OF_DAY2}: the table holds 2 sweeps on different frequency grids"):
        ix.load(one)
    alone = ix.load(one, sweep="1")
    np.testing.assert_allclose(np.sort(alone["frequency"].values), np.sort(F_DAY1 * 1.01), rtol=1e-15)
    assert f"read alone (rows {LINE_OF_DAY2}–" in alone.attrs["sweeps"], alone.attrs["sweeps"]  # (a sheet's rows, as its errors say)
    two = book(tmp_path / "two.xlsx", 2)
    assert main(["inspect", str(two), "--select", "sweep=1"]) == 2
    err = capsys.readouterr().err
    assert f"row {LINE_OF_DAY2}: the table holds 2 sweeps on different frequency grids" in err and "save each sweep to a sheet or file of its own" in err


def test_workbook_sheets_on_different_grids_are_read_one_alone(tmp_path, capsys):
    """SYNTHETIC workbook of two sheets, one arc each, on grids of 50 and 30 points (two sessions
    of one cell): refused as a stack, with the offer; --select sheet=LABEL and
    load(path, sweep=LABEL) read one, on its own grid, and a fit of it recovers its arc."""
    openpyxl = pytest.importorskip("openpyxl")
    grids = {"monday": F_DAY1, "tuesday": np.logspace(5, -2, 30)}
    workbook = openpyxl.Workbook()
    workbook.remove(workbook.active)
    for k, (name, f) in enumerate(grids.items()):
        table = workbook.create_sheet(name)
        table.append(["Frequency (Hz)", "Z' (Ohm)", "Z'' (Ohm)"])
        for fi, zi in zip(f.tolist(), rc_arc(f, seed=k).tolist()):
            table.append([fi, zi.real, zi.imag])
    path = tmp_path / "sessions.xlsx"
    workbook.save(path)

    with pytest.raises(ix.SweepGridsDiffer) as caught:
        ix.load(path)
    assert str(caught.value) == (
        f"{path}: sheet 'tuesday' (30 points) has a different frequency grid from sheet 'monday' (50 points): read one alone, "
        "--select sheet=monday (Python: impedax.io.load(path, sweep='monday')), or export each to a file"
    )
    assert caught.value.labels == ["monday", "tuesday"]
    tuesday = ix.load(path, sweep="tuesday")
    np.testing.assert_allclose(tuesday["frequency"].values, grids["tuesday"], rtol=1e-15)
    np.testing.assert_allclose(tuesday["Z"].values, rc_arc(grids["tuesday"], seed=1), rtol=1e-12)
    assert tuesday.attrs["sweeps"] == "sheet tuesday of 2, read alone: the file's sheets are on different frequency grids"
    assert tuesday.attrs["format"] == "spreadsheet"

    assert main(["fit", str(path), "--model", "R0 + R1 || C1", "--select", "sheet=tuesday", "--json"]) == 0
    params = json.loads(capsys.readouterr().out)["params"]
    for name, true in (("R0", R0), ("R1", R1), ("C1", C1)):
        assert params[name]["value"] == pytest.approx(true, rel=0.02)  # 0.3 % noise on 30 points
    assert main(["inspect", str(path)]) == 2
    assert "read one alone, --select sheet=monday" in capsys.readouterr().err
    assert main(["inspect", str(path), "--select", "sheet=monday,tuesday"]) == 2  # one grid at a time
    assert "give one label (sheet: monday, tuesday)" in capsys.readouterr().err


def test_labone_sweeps_on_different_grids_are_read_one_alone_with_their_format(tmp_path):
    """SYNTHETIC LabOne CSV (the layout of tests/test_robustness.py's labone case): two sweeps of
    one flat 1 − 1j Ω on the grids 1, 2, 3 Hz and 1, 3, 5 Hz."""
    path = tmp_path / "dev1_imps.csv"
    path.write_text(
        "chunk;timestamp;size;fieldname\n0;1;3;frequency;1;2;3\n0;1;3;realz;1;1;1\n0;1;3;imagz;-1;-1;-1\n"
        "1;1;3;frequency;1;3;5\n1;1;3;realz;1;1;1\n1;1;3;imagz;-1;-1;-1\n"
    )
    with pytest.raises(ix.SweepGridsDiffer, match=r"sweep '1' \(3 points\) has a different frequency grid from sweep '0' \(3 points\): read one alone, --select sweep=0"):
        ix.load(path)
    second = ix.load(path, sweep="1")
    np.testing.assert_array_equal(np.sort(second["frequency"].values), [1.0, 3.0, 5.0])
    np.testing.assert_array_equal(second["Z"].values, np.full(3, 1 - 1j))
    assert second.attrs["format"] == "Zurich Instruments LabOne CSV"
