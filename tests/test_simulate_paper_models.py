"""`impedax simulate meyer` / `meyer-cpe`: Meyer's finger-on-screen circuit with the thesis's
eq 3.13 values as its defaults. Typed as a circuit, `C_s + C_i + R_sc || C_sc + R_f` took the
elements' generic defaults (1 µF, 100 Ω), a spectrum of no finger. The oracle is the thesis's
series impedance written here in numpy (docs/physics.md, "Meyer"):
Z = 1/(jωC_s) + 1/(jωC_i) + R_sc/(1 + jωR_sc C_sc) + R_f, the CPE variant with
R_sc/(1 + R_sc Q (jω)^α)."""

import json
from pathlib import Path

import numpy as np
import pytest

from cli_run import run

REAL_SPECTRUM = Path(__file__).parent / "fixtures" / "real" / "exampleData.csv"  # (REAL; refused before it is read)
C_S, C_I, R_SC, C_SC, R_F = 140e-12, 1.7e-9, 130e3, 2.2e-9, 500.0  # thesis eq 3.13, rounded


def _spectrum(stdout):
    rows = np.array([[float(x) for x in line.split(",")] for line in stdout.splitlines()[1:]])
    return rows[:, 0], rows[:, 1] + 1j * rows[:, 2]


def test_meyer_is_the_thesis_circuit_with_its_values(capsys):
    code, out, err = run(["simulate", "meyer", "--fmin", "10", "--fmax", "1M", "--points", "9"], capsys)
    assert code == 0, err
    f, z = _spectrum(out)
    s = 2j * np.pi * f
    expected = 1 / (s * C_S) + 1 / (s * C_I) + R_SC / (1 + s * R_SC * C_SC) + R_F
    np.testing.assert_allclose(z, expected, rtol=1e-12)
    assert err == ("impedax simulate: meyer is C_s + C_i + R_sc || C_sc + R_f with the thesis's eq 3.13 values: "
                   "C_s = 140 pF, C_i = 1.7 nF, R_sc = 130 kΩ, C_sc = 2.2 nF, R_f = 500 Ω\n")


def test_meyer_cpe_takes_q_from_c_sc_at_1_khz_and_a_param_overrides(capsys):
    code, out, err = run(["simulate", "meyer-cpe", "--param", "C_s=100p", "--fmin", "10", "--fmax", "1M", "--points", "9"], capsys)
    assert code == 0, err
    f, z = _spectrum(out)
    alpha = 0.8
    q = C_SC * (2 * np.pi * 1e3) ** (1 - alpha)  # the CPE's |Z| equals C_sc's at 1 kHz
    jw = 2j * np.pi * f
    expected = 1 / (jw * 100e-12) + 1 / (jw * C_I) + R_SC / (1 + R_SC * q * jw**alpha) + R_F
    np.testing.assert_allclose(z, expected, rtol=1e-12)
    assert "C_s = 140 pF" not in err and "C_i = 1.7 nF" in err and "CPE_sc.alpha = 0.8" in err


def test_the_json_says_which_paper_model_ran(tmp_path, capsys):
    code, out, err = run(["simulate", "MEYER", "--points", "3", "--out", tmp_path / "m.csv", "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    assert summary["model"] == "C_s + C_i + R_sc || C_sc + R_f" and summary["paper_model"] == "meyer"
    assert summary["parameters"] == pytest.approx({"C_s": C_S, "C_i": C_I, "R_sc": R_SC, "C_sc": C_SC, "R_f": R_F}, rel=1e-15)


def test_a_circuit_is_no_paper_model(capsys):
    code, out, err = run(["simulate", "R0 + C1", "--points", "2"], capsys)
    assert code == 0 and "thesis" not in err


@pytest.mark.parametrize(("argv", "expected"), [
    (["simulate", "meyer", "--param", "CPE_sc.alpha=0.8"],
     "--param: CPE_sc.alpha is a parameter of meyer-cpe (C_s + C_i + R_sc || CPE_sc + R_f), not of meyer (C_s + C_i + R_sc || C_sc + R_f): "
     "name the model meyer-cpe to set it (parameters of meyer: C_s, C_i, R_sc, C_sc, R_f)"),
    (["simulate", "meyer-cpe", "--param", "C_sc=1n"],
     "--param: C_sc is a parameter of meyer (C_s + C_i + R_sc || C_sc + R_f), not of meyer-cpe (C_s + C_i + R_sc || CPE_sc + R_f): name the model meyer to set it"),
    (["fit", REAL_SPECTRUM, "--model", "meyer-rc", "--fix", "CPE_sc.Q=1n"],
     "--fix: CPE_sc.Q is a parameter of meyer-cpe (C_s + C_i + R_sc || CPE_sc + R_f), not of meyer-rc"),
    (["fit", REAL_SPECTRUM, "--model", "meyer", "--plot", "never-written.png", "--plot-params", "CPE_sc.alpha"],
     "--plot-params: CPE_sc.alpha is a parameter of meyer-cpe"),
    (["sample", REAL_SPECTRUM, "--model", "meyer", "--prior", "CPE_sc.alpha=uniform:0.5,1"],
     "--prior: CPE_sc.alpha is a parameter of meyer-cpe (C_s + C_i + R_sc || CPE_sc + R_f), not of meyer"),
    (["sample", REAL_SPECTRUM, "--model", "meyer-cpe", "--fix", "C_sc=1n"],
     "--fix: C_sc is a parameter of meyer (C_s + C_i + R_sc || C_sc + R_f), not of meyer-cpe"),
    (["diagnose", REAL_SPECTRUM, "--model", "meyer-cpe", "--fix", "C_sc=1n"],
     "--fix: C_sc is a parameter of meyer (C_s + C_i + R_sc || C_sc + R_f), not of meyer-cpe"),
    (["diagnose", REAL_SPECTRUM, "--model", "meyer", "--bound", "CPE_sc.alpha=0.5:1"],
     "--bound: CPE_sc.alpha is a parameter of meyer-cpe"),
    (["refine", REAL_SPECTRUM, "--model", "meyer", "--fix", "CPE_sc.alpha=0.8"],
     "--fix: CPE_sc.alpha is a parameter of meyer-cpe"),
])
def test_a_parameter_of_the_other_meyer_variant_names_that_variant(argv, expected, capsys):
    """A CPE parameter on the RC model (and C_sc on the CPE one) was "unknown parameter
    'CPE_sc.alpha' for model 'C_s + C_i + R_sc || C_sc + R_f'": the error now names the paper
    model that has it, before any data are read (exit code 2, no traceback)."""
    code, out, err = run(argv, capsys)
    assert code == 2 and out == ""
    assert expected in err and "Traceback" not in err and "unknown parameter" not in err


def test_a_name_of_no_meyer_variant_keeps_the_nearest_name_hint(capsys):
    code, _, err = run(["simulate", "meyer", "--param", "C_x=1"], capsys)
    assert code == 2 and "unknown parameter 'C_x'" in err and "did you mean C_s?" in err and "meyer-cpe" not in err
