"""`make demo` in fast mode: every step runs, the files appear together, the story names the
missing effect and the error falls, and the gap thickness is near the synthetic truth."""

import re

import pytest

from impedax.cli import main

U_TRUE_UM = 2.787  # C_gap = 413 pF, A = 130 mm² (docs/physics.md: ≈ 2.79 µm)


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    import contextlib
    import io

    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        code = main(["demo", "--out", str(out), "--fast"])
    return code, buffer.getvalue(), out


def test_demo_writes_everything(demo):
    code, text, out = demo
    assert code == 0
    names = {p.name for p in out.iterdir()}
    assert names == {"report.html", "remaining_impedance.nc", "force_bands.nc", "step2_naive_fit.png", "step3_refinement.png", "refined_circuit.png", "step4_gap_and_force.png", "step5_force.png"}
    report = (out / "report.html").read_text()
    for name in names - {"report.html", "remaining_impedance.nc", "force_bands.nc"}:
        assert name in report
    assert text.strip().splitlines()[-1] == f"Report: {(out / 'report.html').resolve()}"


def test_demo_story(demo):
    _, text, _ = demo
    for step in range(1, 7):
        assert f"[{step}/6]" in text
    assert "SYNTHETIC" in text
    assert "Verdict on C_gap: missing_effect" in text
    assert re.search(r"^\s+electrode_polarization\s+ΔAIC", text, flags=re.M)  # top suggestion
    assert "Final model: R_EP || CPE_EP || C_gap   verdict: adequate" in text
    naive = float(re.search(r"Model C_gap: rms_rel = ([\d.e-]+)", text).group(1))
    final = [float(x) for x in re.findall(r"^\s+\d+\s+([\d.]+)%", text, flags=re.M)]
    assert naive > 0.3 and final[-1] / 100 < naive / 20  # the error falls


def test_demo_gap_thickness(demo):
    _, text, _ = demo
    u, lo, hi = (float(x) for x in re.search(r"u = ([\d.]+) µm, 90% credible interval ([\d.]+)–([\d.]+) µm", text).groups())
    assert lo <= u <= hi
    assert lo <= U_TRUE_UM <= hi  # the interval of the population median contains the generating u
    spread = float(re.search(r"spread between trials: ([\d.]+)%", text).group(1))
    assert 3.0 < spread < 14.0  # generated with 7 % between trials (and 1 % between sessions)
    new_lo, new_hi = (float(x) for x in re.search(r"a new trial: u in ([\d.]+)–([\d.]+) µm", text).groups())
    assert new_lo < lo and new_hi > hi
    assert u == pytest.approx(U_TRUE_UM, rel=0.03)
    paper = float(re.search(r"paper's method: u = ([\d.]+) µm", text).group(1))
    assert paper == pytest.approx(U_TRUE_UM, rel=0.05)
