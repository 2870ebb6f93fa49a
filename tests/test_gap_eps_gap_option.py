"""`impedax gap --eps-gap`: the relative permittivity of the gap's medium, which the Python API
took (`gap_analysis(eps_gap=…)`) and the command line did not, and the report's line that says
which ε_gap u = ε0 ε_gap A/C_gap used. SYNTHETIC single-contact spectra from a numpy formula
written here (an electroadhesive pad whose gap holds a dielectric film, ε_r = 3.4)."""

import json

import numpy as np
import pytest

import impedax as ix
from cli_run import run

EPS0 = 8.8541878128e-12
EPS_FILM = 3.4  # a polyimide film in the gap
AREA = 4e-4  # [m²], a 2 cm × 2 cm pad
U_TRUE = 5e-6  # [m]
C_GAP = EPS0 * EPS_FILM * AREA / U_TRUE  # 2.41 nF
R_EP = 1e8
ALPHA = 0.6
Q_EP = C_GAP * (2 * np.pi * 30.0) ** (1 - ALPHA)
FREQ = np.geomspace(1.0, 1e6, 41)


def _pad(seed=3, n_trials=5, noise=0.01):
    """Trials of R_EP ∥ CPE_EP ∥ C_gap (admittances add) with 1 % complex noise."""
    rng = np.random.default_rng(seed)
    w = 2 * np.pi * FREQ
    z = 1.0 / (1.0 / R_EP + Q_EP * (1j * w) ** ALPHA + 1j * w * C_GAP)
    z = np.tile(z, (n_trials, 1))
    z = z * (1 + noise * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    return ix.make_spectrum(FREQ, z, dims=("trial",))


def _paper_gap(z_trials, eps):
    """Sirin §2.3 by hand: C = mean over f ≥ 30 Hz of 1/(2πf |mean Z|), u = ε0 ε A/C [m]."""
    z = np.asarray(z_trials).mean(axis=0)
    keep = FREQ >= 30.0
    c = np.mean(1.0 / (2 * np.pi * FREQ[keep] * np.abs(z[keep])))
    return EPS0 * eps * AREA / c


def test_eps_gap_sets_the_medium_of_u_and_the_report_says_it(tmp_path, capsys):
    pad = _pad()
    path = str(tmp_path / "pad.nc")
    ix.save(pad, path)
    code, stdout, err = run(["gap", path, "--area", "4e-4", "--no-area-check", "--v0", "200", "--eps-gap", "3.4",
                             "--pooled", "--steps", "100", "--quiet", "--json"], capsys)
    assert code == 0, err
    out = json.loads(stdout)
    assert out["settings"]["eps_gap"] == 3.4
    assert out["paper_method"]["gap_um"] == pytest.approx(_paper_gap(pad["Z"].values, EPS_FILM) * 1e6, rel=1e-9)
    g = out["gap_um"]
    assert g["q05"] <= U_TRUE * 1e6 <= g["q95"], g
    code, stdout, err = run(["gap", path, "--area", "4e-4", "--no-area-check", "--v0", "200", "--eps-gap", "3.4",
                             "--pooled", "--steps", "100", "--quiet"], capsys)
    assert code == 0, err
    (line,) = [ln for ln in stdout.splitlines() if ln.startswith("gap medium")]
    assert "ε_gap = 3.4 (given: --eps-gap; Python: eps_gap)" in line and "u = ε0 ε_gap A/C_gap" in line


def test_the_default_medium_is_named_air():
    report_line = ix.models.gap.medium_text(1.00059)
    assert report_line.startswith("ε_gap = 1.00059 (air, the default")
    assert "--eps-gap" in report_line


@pytest.mark.parametrize("value", ["0.5", "0", "-3", "nan"])
def test_an_eps_gap_below_one_is_refused_before_any_work(tmp_path, capsys, value):
    path = str(tmp_path / "pad.nc")
    ix.save(_pad(), path)
    out = tmp_path / "gap.json"
    code, stdout, err = run(["gap", path, "--area", "4e-4", "--no-area-check", "--eps-gap", value, "--pooled", "--out", out], capsys)
    assert code == 2
    assert "--eps-gap" in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1, err
    assert not out.exists()
