"""`Posterior.report()` of a sampling with a physical reparametrization says what the sampled
quantity stands for and with which constants: ``ix.sample(..., reparametrization=
gap_thickness_reparametrization("C_gap", area=…))`` reported a row ``u … m`` and nothing of the
area and permittivity that turn it into C_gap. SYNTHETIC R ∥ C_gap spectrum from numpy."""

import numpy as np
import pytest

import impedax as ix

EPS0 = 8.8541878128e-12
AREA = 130e-6
EPS_R = 1.00059
U_TRUE = 2.79e-6
C_GAP = EPS0 * EPS_R * AREA / U_TRUE  # 412.6 pF
R = 1e8


def test_the_report_names_the_reparametrization_and_its_constants():
    rng = np.random.default_rng(5)
    f = np.geomspace(1.0, 1e5, 31)
    z = 1.0 / (1.0 / R + 2j * np.pi * f * C_GAP)
    z = z * (1 + 0.005 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    data = ix.make_spectrum(f, z)
    post = ix.sample("R_EP || C_gap", data, reparametrization=ix.gap_thickness_reparametrization("C_gap", area=AREA), steps=60, seed=0, progress=False)
    lines = post.report().splitlines()
    (line,) = [ln for ln in lines if ln.startswith("reparam")]
    assert line == "reparam    u in place of C_gap: C_gap = ε0·ε_r·A/u (A = 0.00013 m², ε_r = 1.00059)", line
    # the constants stated are those the draws used: ε0 ε_r A/u at the median u is the generating C_gap
    u = float(np.median(post.parameter_draws()["u"]))
    assert EPS0 * EPS_R * AREA / u == pytest.approx(C_GAP, rel=0.01)


def test_without_a_reparametrization_there_is_no_such_line():
    rng = np.random.default_rng(6)
    f = np.geomspace(1.0, 1e5, 31)
    z = (1.0 / (1.0 / R + 2j * np.pi * f * C_GAP)) * (1 + 0.005 * rng.standard_normal(f.size))
    post = ix.sample("R_EP || C_gap", ix.make_spectrum(f, z), steps=40, seed=0, progress=False)
    assert not any(ln.startswith("reparam") for ln in post.report().splitlines())
