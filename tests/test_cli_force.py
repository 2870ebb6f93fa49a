"""`impedax force meyer|vezzoli`: reference values, JSON contract, bad input → exit 2."""

import json

import numpy as np
import pytest

from impedax.cli import main


def _json(capsys, *args):
    assert main(["force", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_vezzoli_table2_point(capsys):
    out = _json(capsys, "vezzoli", "--fmin", "440", "--fmax", "440", "--points", "1")
    assert set(out) >= {"frequency_hz", "force_n", "peak", "params", "convention"}
    assert out["frequency_hz"] == [440.0] and out["force_n"][0] == pytest.approx(0.0556, rel=0.002)
    assert out["peak"] == {"frequency_hz": 440.0, "force_n": out["force_n"][0]}
    assert out["convention"] == "time-average" and out["params"]["v_m"] == 2000.0


def test_meyer_defaults_reproduce_fig_3_4(capsys):
    out = _json(capsys, "meyer", "--fmin", "1e3", "--fmax", "1e6", "--points", "301")
    assert out["peak"]["force_n"] == pytest.approx(0.164, rel=0.02)
    assert out["peak"]["frequency_hz"] == pytest.approx(37e3, rel=0.05)
    assert out["params"]["v_a"] == 140.0 and out["params"]["R_sc"] == 130e3


def test_param_override_scales_with_voltage_squared(capsys):
    base = _json(capsys, "vezzoli", "--fmin", "100", "--fmax", "1000", "--points", "3")
    double = _json(capsys, "vezzoli", "--fmin", "100", "--fmax", "1000", "--points", "3", "--param", "v_m=4000")
    np.testing.assert_allclose(double["force_n"], 4 * np.array(base["force_n"]), rtol=1e-12)


def test_csv_output_and_plot(capsys, tmp_path):
    png = tmp_path / "f.png"
    assert main(["force", "meyer", "--points", "5", "--plot", str(png)]) == 0
    captured = capsys.readouterr()
    lines = captured.out.strip().splitlines()
    assert lines[0] == "frequency_hz,force_n" and len(lines) == 6
    assert "peak" in captured.err and png.stat().st_size > 1000


@pytest.mark.parametrize(
    "args, match",
    [
        (["meyer", "--param", "Rsc=1"], "R_sc"),
        (["vezzoli", "--param", "h_i=-1"], "h_s"),
        (["vezzoli", "--param", "h_i=abc"], "eps_i"),
        (["vezzoli", "--param", "h_i"], "rho_s"),
        (["vezzoli", "--fmin", "0"], "positive"),
    ],
)
def test_bad_input_exits_2_with_one_message(capsys, args, match):
    assert main(["force", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and match in err[0]
