"""`impedax force`'s line on stderr says what the force was computed for: the drive amplitude and
the contact area, in SI prefixes, and whether they are the paper's values or changed. It gave the
convention and the peak only, so a run read from the terminal did not say at which V_A and A
its millinewtons hold (the CSV's columns and the JSON's params did)."""

import math

import pytest

from cli_run import run

THESIS_AREA_MM2 = math.pi * 4.0**2  # thesis eq 3.13: A = π (4 mm)², 50.27 mm²


def _line(capsys, *args):
    code, _, err = run(["force", *args], capsys)
    assert code == 0, err
    (line,) = [ln for ln in err.splitlines() if ln.startswith("impedax force") and "warning" not in ln]
    return line


def test_meyer_line_names_the_thesis_drive_and_area(capsys):
    line = _line(capsys, "meyer")
    assert line.startswith(f"impedax force meyer: time-averaged force at V_A = 140 V, A = {THESIS_AREA_MM2:.4g} mm² (thesis eq 3.13 values); peak 164.2 mN at 37 kHz")


def test_meyer_line_says_a_changed_drive_and_its_thesis_value(capsys):
    line = _line(capsys, "meyer", "--param", "v_a=100")
    assert f"at V_A = 100 V, A = {THESIS_AREA_MM2:.4g} mm² (thesis eq 3.13 values except V_A: 140 V in the thesis)" in line


@pytest.mark.parametrize("convention, what", [("time-average", "time-averaged force"), ("peak", "peak force (largest over a period)")])
def test_vezzoli_line_names_table_2_drive_and_area(capsys, convention, what):
    line = _line(capsys, "vezzoli", "--fmin", "440", "--fmax", "440", "--convention", convention)
    # Table 2: V_m = 2000 V, A = 1 cm² = 100 mm²; eq 10 at 440 Hz: 0.0556 N (×2 for the peak)
    expected = 8.8541878128e-12 * 1e-4 * 2000.0**2 / (4 * (90e-6 + 350e-6) * (90e-6 / 3.35 + 350e-6 / 2340))
    tau = 8.8541878128e-12 * 2340 * 3.0e4
    wt = 2 * math.pi * 440 * tau
    expected *= wt**2 / (1 + wt**2) * (2 if convention == "peak" else 1)
    assert line.startswith(f"impedax force vezzoli: {what} at V_m = 2 kV, A = 100 mm² (Table 2 values); {expected * 1e3:.4g} mN at 440 Hz")


def test_a_changed_area_is_said_as_changed(capsys):
    line = _line(capsys, "vezzoli", "--param", "area=2e-4", "--fmin", "440", "--fmax", "440")
    assert "at V_m = 2 kV, A = 200 mm² (Table 2 values except A: 100 mm² in Table 2)" in line
