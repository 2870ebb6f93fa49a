"""Every element against an independent numpy/cmath formula, its limits, and jit/vmap/grad."""

import cmath
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import impedax as ix
from impedax.circuits import DEFAULT_REGISTRY, ElementSpec, ParameterSpec

FREQS = np.array([1e-3, 0.1, 1.0, 37.0, 1e3, 1e5, 1e7])


def coth(x):
    return cmath.cosh(x) / cmath.sinh(x)


# independent oracles written with cmath, one frequency at a time
ORACLES = {
    "R1": ({"R1": 47.0}, lambda w, p: p["R1"]),
    "C1": ({"C1": 2.2e-9}, lambda w, p: 1 / (1j * w * p["C1"])),
    "L1": ({"L1": 3e-6}, lambda w, p: 1j * w * p["L1"]),
    "CPE1": ({"CPE1.Q": 1e-6, "CPE1.alpha": 0.8}, lambda w, p: 1 / (p["CPE1.Q"] * (1j * w) ** p["CPE1.alpha"])),
    "Q1": ({"Q1.Q": 3e-7, "Q1.alpha": 0.55}, lambda w, p: 1 / (p["Q1.Q"] * (1j * w) ** p["Q1.alpha"])),
    "W1": ({"W1.sigma": 150.0}, lambda w, p: p["W1.sigma"] / math.sqrt(w) - 1j * p["W1.sigma"] / math.sqrt(w)),
    "Wo1": ({"Wo1.R": 80.0, "Wo1.tau": 0.3}, lambda w, p: p["Wo1.R"] * coth(cmath.sqrt(1j * w * p["Wo1.tau"])) / cmath.sqrt(1j * w * p["Wo1.tau"])),
    "Ws1": ({"Ws1.R": 80.0, "Ws1.tau": 0.3}, lambda w, p: p["Ws1.R"] * cmath.tanh(cmath.sqrt(1j * w * p["Ws1.tau"])) / cmath.sqrt(1j * w * p["Ws1.tau"])),
    "G1": ({"G1.R": 60.0, "G1.tau": 2e-3}, lambda w, p: p["G1.R"] / cmath.sqrt(1 + 1j * w * p["G1.tau"])),
    "CC1": ({"CC1.R": 500.0, "CC1.tau": 1e-4, "CC1.alpha": 0.7}, lambda w, p: p["CC1.R"] / (1 + (1j * w * p["CC1.tau"]) ** p["CC1.alpha"])),
    "HN1": ({"HN1.R": 500.0, "HN1.tau": 1e-4, "HN1.alpha": 0.7, "HN1.beta": 0.6}, lambda w, p: p["HN1.R"] / (1 + (1j * w * p["HN1.tau"]) ** p["HN1.alpha"]) ** p["HN1.beta"]),
}


@pytest.mark.parametrize("name", ORACLES)
def test_element_matches_independent_formula(name):
    params, oracle = ORACLES[name]
    z = np.asarray(ix.compile_circuit(name)(params, FREQS))
    for f, zi in zip(FREQS, z):
        w = 2 * math.pi * f
        if name in ("Wo1", "Ws1") and abs(cmath.sqrt(1j * w * params[f"{name}.tau"])) > 300:
            continue  # cmath cosh/sinh overflow there; checked by the limit tests instead
        expected = complex(oracle(w, params))
        assert zi == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("spec", [s for s in DEFAULT_REGISTRY if s.admittance is not None], ids=lambda s: s.symbol)
def test_declared_admittance_is_the_inverse_impedance(spec):
    """Elements that declare an admittance formula (summed directly by parallel nodes) give
    exactly 1/Z, against the cmath oracle of the impedance."""
    params, oracle = ORACLES[f"{spec.symbol}1"]
    values = [params[n] for n in spec.parameter_names(f"{spec.symbol}1")]
    w = 2 * np.pi * FREQS
    y = np.broadcast_to(np.asarray(spec.admittance(jnp.asarray(w), *values)), w.shape)
    expected = np.array([1 / complex(oracle(wi, params)) for wi in w])
    np.testing.assert_allclose(y, expected, rtol=1e-13)


def test_cpe_alpha_one_is_capacitor_and_half_is_warburg_like():
    f = np.geomspace(1, 1e5, 9)
    z_cpe = ix.compile_circuit("CPE1")({"CPE1.Q": 1e-6, "CPE1.alpha": 1.0}, f)
    z_c = ix.compile_circuit("C1")({"C1": 1e-6}, f)
    np.testing.assert_allclose(z_cpe, z_c, rtol=1e-12)
    z_half = np.asarray(ix.compile_circuit("CPE1")({"CPE1.Q": 1e-3, "CPE1.alpha": 0.5}, f))
    np.testing.assert_allclose(np.degrees(np.angle(z_half)), -45.0, atol=1e-9)


def test_finite_warburgs_limits_and_no_overflow():
    wo, ws = ix.compile_circuit("Wo1"), ix.compile_circuit("Ws1")
    p_o, p_s = {"Wo1.R": 10.0, "Wo1.tau": 1.0}, {"Ws1.R": 10.0, "Ws1.tau": 1.0}
    # low frequency: short → R (resistive), open → capacitive with C = tau/R: Z ≈ R/3 + 1/(jω τ/R)
    f_low = np.array([1e-7])
    assert complex(ws(p_s, f_low)[0]) == pytest.approx(10.0, rel=1e-6)
    w = 2 * math.pi * 1e-7
    assert complex(wo(p_o, f_low)[0]) == pytest.approx(10.0 / 3 + 1 / (1j * w * 0.1), rel=1e-6)
    # high frequency: both tend to the semi-infinite Warburg R/sqrt(jωτ); huge arguments stay finite
    f_high = np.array([1e12, 1e30])
    for fn, p in ((wo, p_o), (ws, p_s)):
        z = np.asarray(fn(p, f_high))
        assert np.all(np.isfinite(z))
        expected = 10.0 / np.sqrt(1j * 2 * np.pi * f_high)
        np.testing.assert_allclose(z, expected, rtol=1e-9)


def test_relaxations_limits():
    cc, hn = ix.compile_circuit("CC1"), ix.compile_circuit("HN1")
    p = {"CC1.R": 100.0, "CC1.tau": 1e-3, "CC1.alpha": 0.6}
    q = {"HN1.R": 100.0, "HN1.tau": 1e-3, "HN1.alpha": 0.6, "HN1.beta": 1.0}
    f = np.array([1e-9, 1e12])
    z = np.asarray(cc(p, f))
    assert z[0] == pytest.approx(100.0, rel=1e-4) and abs(z[1]) < 1e-3
    # HN with beta = 1 is Cole–Cole; Gerischer is HN-like with alpha = 1, beta = 1/2
    np.testing.assert_allclose(hn(q, FREQS), cc(p, FREQS), rtol=1e-12)
    g = ix.compile_circuit("G1")({"G1.R": 100.0, "G1.tau": 1e-3}, FREQS)
    h = hn({"HN1.R": 100.0, "HN1.tau": 1e-3, "HN1.alpha": 1.0, "HN1.beta": 0.5}, FREQS)
    np.testing.assert_allclose(g, h, rtol=1e-12)


@pytest.mark.parametrize("name", ORACLES)
def test_extreme_parameters_stay_finite(name):
    params, _ = ORACLES[name]
    fn = ix.compile_circuit(name)
    for scale in (1e-12, 1e12):
        p = {k: (v * scale if not k.endswith(("alpha", "beta")) else v) for k, v in params.items()}
        z = np.asarray(fn(p, np.geomspace(1e-3, 1e7, 21)))
        assert np.all(np.isfinite(z)), (name, scale)


def test_jit_vmap_grad_of_elements_and_circuits():
    c = ix.compile_circuit("R0 + R1 || CPE1 + Wo1")
    f = jnp.geomspace(1.0, 1e5, 30)
    p = {"R0": 10.0, "R1": 100.0, "CPE1.Q": 1e-5, "CPE1.alpha": 0.85, "Wo1.R": 50.0, "Wo1.tau": 0.1}
    z = c(p, f)
    np.testing.assert_allclose(jax.jit(c)(p, f), z, rtol=1e-13)
    batch = {k: jnp.full((5,), v) for k, v in p.items()}
    zb = jax.vmap(c, in_axes=(0, None))(batch, f)
    assert zb.shape == (5, 30)
    np.testing.assert_allclose(zb[3], z, rtol=1e-13)

    # d|Z|²/dR0 at high frequency compared with a central finite difference
    def loss(r0):
        return jnp.sum(jnp.abs(c({**p, "R0": r0}, f)) ** 2)

    g = jax.grad(loss)(10.0)
    h = 1e-4
    fd = (loss(10.0 + h) - loss(10.0 - h)) / (2 * h)
    assert float(g) == pytest.approx(float(fd), rel=1e-6)
    grads = jax.grad(lambda q: jnp.sum(jnp.abs(c(q, f))))(p)
    assert all(np.isfinite(float(v)) for v in grads.values())


def test_registry_is_a_value_and_user_elements_work():
    def transmission(w, r, c):  # a user element: Z = sqrt(r/(jωc))
        return jnp.sqrt(r / (1j * w * c))

    spec = ElementSpec("Tl", "user transmission line", "Z = √(r/(jωc))", (ParameterSpec("r", "Ohm", 1.0), ParameterSpec("c", "F", 1e-6)), transmission)
    reg = DEFAULT_REGISTRY.register(spec)
    assert "Tl" in reg and "Tl" not in DEFAULT_REGISTRY
    # a value: equal contents, equal registries and hashes (compiled solvers are cached by it)
    same = type(DEFAULT_REGISTRY)(DEFAULT_REGISTRY.specs + (spec,))
    assert same == reg and hash(same) == hash(reg) and reg != DEFAULT_REGISTRY
    c = ix.parse("R0 + Tl_1", reg)
    z = ix.compile_circuit(c, reg)({"R0": 5.0, "Tl_1.r": 4.0, "Tl_1.c": 1e-6}, np.array([100.0]))
    assert complex(z[0]) == pytest.approx(5 + cmath.sqrt(4.0 / (1j * 2 * math.pi * 100 * 1e-6)), rel=1e-12)
    with pytest.raises(ix.CircuitSyntaxError):
        ix.parse("R0 + Tl_1")
    with pytest.raises(ix.CircuitError):
        DEFAULT_REGISTRY.register(ElementSpec("R", "again", "", (ParameterSpec(None, "Ohm", 1.0),), transmission))
    with pytest.raises(ix.CircuitError):
        ElementSpec("r2", "bad symbol", "", (ParameterSpec(None, "Ohm", 1.0),), transmission)


def test_parameter_specs_follow_the_table():
    c = ix.parse("R_sc + C_gap + L1 + CPE_skin + W1 + Wo1 + Ws1 + G1 + CC1 + HN1")
    assert c.parameter_names() == (
        "R_sc", "C_gap", "L1", "CPE_skin.Q", "CPE_skin.alpha", "W1.sigma", "Wo1.R", "Wo1.tau",
        "Ws1.R", "Ws1.tau", "G1.R", "G1.tau", "CC1.R", "CC1.tau", "CC1.alpha",
        "HN1.R", "HN1.tau", "HN1.alpha", "HN1.beta",
    )
    specs = c.parameter_specs()
    assert specs["CPE_skin.alpha"].contains(1.0) and not specs["CPE_skin.alpha"].contains(1.01)
    assert not specs["R_sc"].contains(0.0) and specs["R_sc"].contains(1e12)
    assert specs["C_gap"].unit == "F"
