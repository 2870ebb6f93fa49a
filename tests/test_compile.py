"""Compiled circuits and padded programs against hand-derived formulas; probes against the
divider formulas of docs/physics.md (Meyer's circuit, with the corrected V_F numerator)."""

import math
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import impedax as ix
from impedax.circuits import CircuitProgram, evaluate_program

F = np.geomspace(1.0, 1e7, 40)
W = 2 * np.pi * F
S = 1j * W

MEYER = "C_s + C_i + R_sc || C_sc + R_f"
MEYER_PARAMS = {"C_s": 140e-12, "C_i": 1.7e-9, "R_sc": 130e3, "C_sc": 2.2e-9, "R_f": 500.0}


def test_series_parallel_hand_formula():
    p = {"R0": 10.0, "R1": 1e3, "C1": 1e-6, "L1": 1e-6}
    z = np.asarray(ix.compile_circuit("L1 + R0 + R1 || C1")(p, F))
    expected = S * 1e-6 + 10.0 + 1e3 / (1 + S * 1e3 * 1e-6)
    np.testing.assert_allclose(z, expected, rtol=1e-12)


def test_program_matches_tree_for_many_topologies():
    texts = [
        "R1",
        "C1",
        "R0 + R1 || C1",
        MEYER,
        "R0 + (R1 + W1) || CPE1 + L1",
        "(R1 || C1) + (R2 || (C2 + R3) || CPE2) + Wo1 || Ws1 + G1 + CC1 + HN1",
        "R_EP || C_EP || C_gap",
    ]
    rng = np.random.default_rng(3)
    for text in texts:
        c = ix.parse(text)
        params = {n: (rng.uniform(0.5, 0.95) if n.endswith(("alpha", "beta")) else 10 ** rng.uniform(-9, 5)) for n in c.parameter_names()}
        z_tree = np.asarray(ix.compile_circuit(c)(params, F))
        prog = CircuitProgram.build(c)
        z_prog = np.asarray(evaluate_program(prog.arrays(), jnp.asarray(prog.pack(params)), F, layout=prog.layout))
        np.testing.assert_allclose(np.asarray(prog(params, F)), z_prog)
        np.testing.assert_allclose(z_prog, z_tree, rtol=1e-10, err_msg=text)


def test_one_compiled_program_serves_many_topologies_under_vmap():
    a, b = CircuitProgram.build("R0 + R1 || C1"), CircuitProgram.build("R0 || C0 + W1")
    assert a.layout == b.layout
    pa = a.pack({"R0": 5.0, "R1": 100.0, "C1": 1e-6})
    pb = b.pack({"R0": 50.0, "C0": 1e-7, "W1.sigma": 30.0})
    stacked = jax.tree.map(lambda x, y: jnp.stack([x, y]), a.arrays(), b.arrays())
    evaluate = partial(evaluate_program, layout=a.layout)
    z = jax.jit(jax.vmap(evaluate, in_axes=(0, 0, None)))(stacked, jnp.stack([pa, pb]), F)
    np.testing.assert_allclose(z[0], 5 + 100 / (1 + S * 1e-4), rtol=1e-12)
    np.testing.assert_allclose(z[1], 1 / (1 / 50 + S * 1e-7) + 30 * (1 - 1j) / np.sqrt(W), rtol=1e-12)
    g = jax.grad(lambda t: jnp.sum(jnp.abs(evaluate(a.arrays(), t, F))))(jnp.asarray(pa))
    assert np.all(np.isfinite(np.asarray(g)))


def _meyer_closed_forms(p):
    cs, ci, r, csc, rf = p["C_s"], p["C_i"], p["R_sc"], p["C_sc"], p["R_f"]
    den = ci * (1 + S * r * csc) + cs * (1 + S * r * csc) + S * r * cs * ci + S * rf * cs * ci * (1 + S * r * csc)
    vf = (cs + S * r * cs * (csc + ci)) / den  # corrected numerator (docs/physics.md)
    qf = cs * ci / den  # Q_f/V_A = I_Rsc/(s V_A)
    return vf, qf, den


def test_meyer_probes_match_hand_derivation():
    vf_fn = ix.voltage_across(MEYER, {"C_i", "R_sc", "C_sc"})
    i_fn = ix.current_through(MEYER, "R_sc")
    vf, qf, den = _meyer_closed_forms(MEYER_PARAMS)
    np.testing.assert_allclose(vf_fn(MEYER_PARAMS, F), vf, rtol=1e-10)
    np.testing.assert_allclose(np.asarray(i_fn(MEYER_PARAMS, F)) / S, qf, rtol=1e-10)
    # the printed eq 3.12 numerator C_s + C_sc R_sc (C_i + C_s) s differs from the circuit
    p = MEYER_PARAMS
    printed = (p["C_s"] + S * p["C_sc"] * p["R_sc"] * (p["C_i"] + p["C_s"])) / den
    assert np.max(np.abs(printed - vf) / np.abs(vf)) > 0.05
    # DC limit: Q_f → C_i V_F
    low = np.array([1e-6])
    ratio = complex((i_fn(p, low) / (1j * 2 * math.pi * low))[0] / vf_fn(p, low)[0])
    assert ratio == pytest.approx(p["C_i"], rel=1e-6)


def test_probe_voltages_add_up_and_currents_divide():
    c = "R0 + R1 || C1 + R2"
    p = {"R0": 10.0, "R1": 1e3, "C1": 1e-6, "R2": 50.0}
    parts = [ix.voltage_across(c, n)(p, F) for n in ("R0", "R1", "R2")]
    np.testing.assert_allclose(sum(parts), 1.0, rtol=1e-12)
    np.testing.assert_allclose(ix.voltage_across(c, "C1")(p, F), parts[1], rtol=1e-12)
    i_tot = 1 / np.asarray(ix.compile_circuit(c)(p, F))
    i_r1, i_c1 = ix.current_through(c, "R1")(p, F), ix.current_through(c, "C1")(p, F)
    np.testing.assert_allclose(i_r1 + i_c1, i_tot, rtol=1e-12)
    np.testing.assert_allclose(ix.voltage_across(c, {"R0", "R1", "C1", "R2"})(p, F), 1.0)
    with pytest.raises(ix.CircuitError, match="two-terminal"):
        ix.voltage_across(c, {"R0", "C1"})
    with pytest.raises(ix.CircuitError, match="no element"):
        ix.voltage_across(c, "C9")


def test_probes_are_jittable_and_differentiable():
    fn = jax.jit(ix.voltage_across(MEYER, "C_i"))
    v = fn(MEYER_PARAMS, F)
    assert v.shape == F.shape
    g = jax.grad(lambda ci: jnp.abs(ix.voltage_across(MEYER, "C_i")({**MEYER_PARAMS, "C_i": ci}, F)[10]))(1.7e-9)
    assert np.isfinite(float(g))


def test_duplicate_names_are_errors_in_built_trees():
    c = ix.Series([ix.Element("R", "R1"), ix.Element("C", "R1")])
    with pytest.raises(ix.CircuitError, match="duplicate"):
        ix.compile_circuit(c)


def test_analytic_jacobian_matches_hand_derivatives_of_an_arc():
    """∂Z/∂θ of R0 + R1 || CPE1 by hand: with D = 1 + R1 Q (jω)^α,
    ∂Z/∂R0 = 1, ∂Z/∂R1 = 1/D², ∂Z/∂Q = −R1² (jω)^α / D², ∂Z/∂α = −R1² Q (jω)^α ln(jω) / D²."""
    r0, r1, q, a = 10.0, 400.0, 1e-7, 0.8
    compiled = ix.compile_circuit("R0 + R1 || CPE1")
    theta = jnp.array([r0, r1, q, a])  # parameter_names order
    assert compiled.parameter_names == ("R0", "R1", "CPE1.Q", "CPE1.alpha")
    z, jac = compiled.value_and_jacobian(theta, F)
    s_a = W**a * np.exp(1j * np.pi / 2 * a)
    d = 1 + r1 * q * s_a
    log_s = np.log(W) + 1j * np.pi / 2
    expected = np.stack([np.ones_like(S), 1 / d**2, -(r1**2) * s_a / d**2, -(r1**2) * q * s_a * log_s / d**2], axis=-1)
    np.testing.assert_allclose(np.asarray(z), r0 + r1 / d, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(jac), expected, rtol=1e-10, atol=1e-14 * np.abs(expected).max())


@pytest.mark.parametrize(
    "text",
    ["R1", "CPE1", MEYER, "R0 + (R1 + W1) || CPE1 + L1", "(R1 || C1) + (R2 || (C2 + R3) || CPE2) + Wo1 || Ws1 + G1 + CC1 + HN1"],
)
def test_analytic_jacobian_matches_forward_mode(text):
    compiled = ix.compile_circuit(text)
    specs = ix.parse(text).parameter_specs()
    rng = np.random.default_rng(0)
    theta = jnp.array([specs[n].default * (1 if specs[n].unit == "1" else 10 ** rng.uniform(-1, 1)) for n in compiled.parameter_names])
    z, jac = jax.jit(compiled.value_and_jacobian)(theta, F)
    # forward mode through the whole circuit, one tangent per parameter
    expected = np.stack([np.asarray(jax.jvp(lambda t: compiled.vector(t, F), (theta,), (jnp.eye(theta.size)[i],))[1]) for i in range(theta.size)], axis=-1)
    np.testing.assert_allclose(np.asarray(z), np.asarray(compiled.vector(theta, F)), rtol=1e-13)
    np.testing.assert_allclose(np.asarray(jac), expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())


def test_jacobian_columns_of_a_subset_by_positions():
    """`value_and_columns` traces only the wanted derivatives, from a tuple of scalars as
    from an array; each column equals forward mode through the whole circuit."""
    compiled = ix.compile_circuit("R0 + R1 || (C1 + R2) || CPE1 + Wo1")
    theta = jnp.array([10.0, 400.0, 2e-7, 50.0, 1e-6, 0.8, 30.0, 0.2])
    wanted = (5, 1, 6)
    z, columns = compiled.value_and_columns(tuple(theta[i] for i in range(theta.size)), F, wanted)
    np.testing.assert_allclose(np.asarray(z), np.asarray(compiled.vector(theta, F)), rtol=1e-13)
    assert len(columns) == len(wanted) and all(c.shape == F.shape and c.dtype == jnp.complex128 for c in columns)
    for i, column in zip(wanted, columns):
        expected = np.asarray(jax.jvp(lambda t: compiled.vector(t, F), (theta,), (jnp.eye(theta.size)[i],))[1])
        np.testing.assert_allclose(np.asarray(column), expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())


def test_circuit_compile_method_equals_compile_circuit():
    """`Circuit.compile()` (public) gives the same function as `compile_circuit`."""
    circuit = ix.parse("R0 + R1 || C1")
    f = np.geomspace(1, 1e5, 7)
    params = {"R0": 10.0, "R1": 1e3, "C1": 1e-6}
    z = 10.0 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6)
    np.testing.assert_allclose(np.asarray(circuit.compile()(params, f)), z, rtol=1e-12)


def _nested_by_hand(p):
    """R0 + (R1 + R2 || CPE2) || C1 + Wo1 || C3 written out with numpy (an independent oracle)."""
    cpe2 = 1 / (p["CPE2.Q"] * W ** p["CPE2.alpha"] * np.exp(1j * np.pi / 2 * p["CPE2.alpha"]))
    inner = p["R1"] + 1 / (1 / p["R2"] + 1 / cpe2)
    arc = 1 / (1 / inner + S * p["C1"])
    x = np.sqrt(S * p["Wo1.tau"])
    wo = p["Wo1.R"] / (x * np.tanh(x))
    return p["R0"] + arc + 1 / (1 / wo + S * p["C3"])


def test_program_jacobian_matches_finite_differences_of_a_hand_formula():
    """`program_value_and_columns` (the candidate solver's Jacobian: slot derivatives and the
    root's sensitivities through series and parallel nodes) against central differences of
    a numpy formula; padded positions give zero columns."""
    from impedax.circuits import program_value_and_columns

    text = "R0 + (R1 + R2 || CPE2) || C1 + Wo1 || C3"
    p = {"R0": 10.0, "R1": 300.0, "R2": 2e3, "CPE2.Q": 3e-6, "CPE2.alpha": 0.8, "C1": 1e-7, "Wo1.R": 500.0, "Wo1.tau": 0.3, "C3": 2e-6}
    prog = CircuitProgram.build(text, layout=ix.circuits.ProgramLayout.sized(1))
    names = list(p)
    dummy = prog.layout.n_slots * 4
    wanted = np.array([prog.parameter_slots[n][0] * 4 + prog.parameter_slots[n][1] for n in names] + [dummy, dummy])
    z, columns = jax.jit(lambda t: program_value_and_columns(prog.arrays(), t, F, wanted, layout=prog.layout))(jnp.asarray(prog.pack(p)))
    np.testing.assert_allclose(np.asarray(z), _nested_by_hand(p), rtol=1e-12)
    for name, column in zip(names, np.asarray(columns)):
        h = 1e-6 * p[name]
        up, down = _nested_by_hand({**p, name: p[name] + h}), _nested_by_hand({**p, name: p[name] - h})
        expected = (up - down) / (2 * h)
        np.testing.assert_allclose(column, expected, rtol=1e-6, atol=1e-8 * np.abs(expected).max(), err_msg=name)
    assert np.all(np.asarray(columns)[len(names):] == 0)
