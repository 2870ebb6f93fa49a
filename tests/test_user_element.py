"""A user's element, declared once in a registry of its own, works everywhere without edits
elsewhere: compiling, padded programs, starting guesses and fitting, diagnosis, drawing and
conversion (refused by name where the notation has no symbol for it).

The element is a leaky capacitor, Z = R/(1 + jωRC) (R ∥ C in one element): it conducts DC,
which nothing declares — the spec infers it from the formula. Expected values are the closed
forms of the formulas, written here with numpy.
"""

import dataclasses

import numpy as np
import pytest

import impedax as ix
from impedax.circuits import DCPath, ElementSpec, ParameterSpec, ProgramLayout, StartRole
from impedax.fitting.diagnosis.effects import BaselineContext
from impedax.fitting.least_squares.starts import SpectrumFeatures, data_driven_guess
from impedax.fitting.parameters import ParameterTable


def _leaky_capacitor(w, r, c):
    return r / (1.0 + 1j * w * r * c)


LEAKY = ElementSpec(
    "Lk",
    "leaky capacitor",
    "Z = R/(1 + jωRC)",
    (ParameterSpec("R", "Ohm", 100.0, description="leak resistance"), ParameterSpec("C", "F", 1e-6, description="capacitance", role="arc_capacitance")),
    _leaky_capacitor,
    program_capacity=3,
)
# for contrast: a series R–C (blocks DC) and a lossy inductor R ∥ L (shorts DC), facts undeclared
SERIES_RC = ElementSpec("Sc", "series RC", "Z = R + 1/(jωC)", (ParameterSpec("R", "Ohm", 10.0), ParameterSpec("C", "F", 1e-6)), lambda w, r, c: r + 1.0 / (1j * w * c))
LOSSY_L = ElementSpec("Ll", "lossy inductor", "Z = jωLR/(R + jωL)", (ParameterSpec("R", "Ohm", 10.0), ParameterSpec("L", "H", 1e-6)), lambda w, r, l: 1j * w * l * r / (r + 1j * w * l))
REGISTRY = ix.DEFAULT_REGISTRY.register(LEAKY).register(SERIES_RC).register(LOSSY_L)

F = np.logspace(-1, 5, 31)
TRUE = {"R0": 10.0, "Lk1.R": 100.0, "Lk1.C": 1e-5}


def _z_true(f):
    w = 2 * np.pi * f
    return 10.0 + 100.0 / (1 + 1j * w * 100.0 * 1e-5)


def test_dc_path_is_inferred_from_the_formula_and_can_be_declared():
    assert LEAKY.dc is None and LEAKY.dc_path is DCPath.CONDUCTS
    assert SERIES_RC.dc_path is DCPath.BLOCKS
    assert LOSSY_L.dc_path is DCPath.SHORTS
    assert dataclasses.replace(LEAKY, dc="blocks").dc_path is DCPath.BLOCKS
    with pytest.raises(ix.CircuitError, match="dc must be one of 'conducts', 'blocks', 'shorts'"):
        dataclasses.replace(LEAKY, dc="leaks")


@pytest.mark.parametrize("spec", list(ix.DEFAULT_REGISTRY), ids=lambda s: s.symbol)
def test_inference_agrees_with_every_built_in_declaration(spec):
    assert dataclasses.replace(spec, dc=None).dc_path is spec.dc_path


def test_start_roles_are_declared_or_inferred_from_the_unit():
    assert LEAKY.start_roles == (StartRole.ARC_RESISTANCE, StartRole.ARC_CAPACITANCE)
    assert ParameterSpec("tau", "s", 1.0).start_role is StartRole.TIME_CONSTANT
    assert ParameterSpec("k", "m", 1.0).start_role is StartRole.DEFAULT
    with pytest.raises(ix.CircuitError, match="start role must be one of"):
        ParameterSpec("k", "m", 1.0, role="guess")


def test_compiles_and_runs_in_a_padded_program():
    circuit = ix.parse("R0 + Lk1", REGISTRY)
    z = np.asarray(ix.compile_circuit(circuit, REGISTRY)(TRUE, F))
    np.testing.assert_allclose(z, _z_true(F), rtol=1e-12)
    layout = ProgramLayout.sized(1, REGISTRY)
    assert layout.capacities[REGISTRY.kind_index("Lk")] == 3 and layout.capacities[REGISTRY.kind_index("Sc")] == 2
    program = ix.CircuitProgram.build(circuit, REGISTRY)
    np.testing.assert_allclose(np.asarray(program(TRUE, F)), _z_true(F), rtol=1e-12)


def test_starting_guess_follows_the_roles_and_the_fit_recovers_the_values():
    circuit = ix.parse("R0 + Lk1", REGISTRY)
    table = ParameterTable.build(circuit, registry=REGISTRY)
    guess = dict(zip(table.names, data_driven_guess(circuit, table, SpectrumFeatures(F, _z_true(F)), REGISTRY)))
    # the arc's own resistance ≈ Z'(f_min) − Z'(f_max), its capacitance ≈ τ/R with τ from the
    # −Z'' peak (the grid has 5 points per decade: within a factor 10^0.1 of 1/(2πRC))
    assert guess["Lk1.R"] == pytest.approx(100.0, rel=0.02)
    assert 1e-5 / 1.3 < guess["Lk1.C"] < 1e-5 * 1.3
    assert guess["R0"] == pytest.approx(10.0, rel=0.02)
    result = ix.fit(circuit, ix.make_spectrum(F, _z_true(F)), registry=REGISTRY)
    for name, value in TRUE.items():
        assert result.values[name] == pytest.approx(value, rel=1e-6)


def _context(circuit):
    z = np.asarray(ix.compile_circuit(circuit, REGISTRY)(circuit.defaults(REGISTRY), F))
    return BaselineContext(circuit, circuit.defaults(REGISTRY), F, z * 1.05, z, REGISTRY)


def test_diagnosis_treats_the_conducting_user_element_as_conducting():
    # a capacitor with a DC-conducting sibling already has a leak: no electrode-polarization
    # branch is proposed across it; with a DC-blocking sibling it is
    effect = ix.DEFAULT_EFFECTS["electrode_polarization"]
    leaky = ix.parse("R0 + Lk1 || C1", REGISTRY)
    assert effect.propose(leaky, _context(leaky)) == []
    blocking = ix.parse("R0 + Sc1 || C1", REGISTRY)
    texts = {str(p.circuit) for p in effect.propose(blocking, _context(blocking))}
    assert texts == {"R0 + Sc1 || R_EP || C1", "R0 + Sc1 || R_EP || CPE_EP || C1"}


def test_draws_as_a_labelled_box_or_as_the_part_it_names(tmp_path):
    pytest.importorskip("schemdraw")
    path = tmp_path / "leaky.svg"
    ix.save_circuit_diagram(ix.parse("R0 + Lk1 || C1", REGISTRY), path, registry=REGISTRY)
    assert "Lk1" in path.read_text()
    drawn = REGISTRY.register(dataclasses.replace(LEAKY, symbol="Lc", draw="Capacitor"))
    ix.draw_circuit(ix.parse("Lc1", drawn), registry=drawn)
    bad = REGISTRY.register(dataclasses.replace(LEAKY, symbol="Lb", draw="NoSuchPart"))
    with pytest.raises(ix.ImpedaxError, match=r"Lb \(leaky capacitor\) is drawn as 'NoSuchPart'"):
        ix.draw_circuit(ix.parse("Lb1", bad), registry=bad)


def test_conversion_refuses_it_by_name_unless_it_declares_a_symbol():
    circuit = ix.parse("R0 + Lk1 || C1", REGISTRY)
    with pytest.raises(ix.CircuitError, match=r"Lk1 \(leaky capacitor\) has no CDC equivalent"):
        circuit.to_cdc(REGISTRY)
    with pytest.raises(ix.CircuitError, match=r"Lk1 \(leaky capacitor\) has no impedance.py equivalent"):
        circuit.to_impedance_py(REGISTRY)
    with pytest.raises(ix.CircuitSyntaxError, match="unknown CDC element 'K'"):
        ix.from_cdc("R(KC)", REGISTRY)
    # declared symbols make it convertible both ways
    named = ix.DEFAULT_REGISTRY.register(dataclasses.replace(LEAKY, cdc="K", impedance_py="Lk"))
    circuit = ix.parse("R1 + Lk1 || C1", named)
    assert circuit.to_cdc(named) == "R(KC)" and ix.from_cdc("R(KC)", named) == circuit
    assert circuit.to_impedance_py(named) == "R1-p(Lk1,C1)" and ix.from_impedance_py("R1-p(Lk1,C1)", named) == circuit
    with pytest.raises(ix.CircuitError, match="element Lk: CDC letter 'R' is already taken by the built-in resistor element \\(R: Z = R\\); choose another CDC letter"):
        ix.DEFAULT_REGISTRY.register(dataclasses.replace(LEAKY, cdc="R"))


@pytest.mark.parametrize(
    "field, value",
    [("cdc", "KK"), ("cdc", "k"), ("impedance_py", "L-k"), ("draw", "a b"), ("program_capacity", 0)],
)
def test_bad_facts_are_refused_at_declaration(field, value):
    with pytest.raises(ix.CircuitError, match="element Lk"):
        dataclasses.replace(LEAKY, **{field: value})



def test_a_changed_formula_under_the_same_symbol_is_compiled_anew():
    """Two registries whose `Kx` differ only in the formula (R/(1 + jωτ) and 2R/(1 + jωτ), the
    declared equation text left the same) are
    two registries: the compiled solvers cached by registry once served the first formula to
    the second, so its fit gave Kx1.R = 100 where the data say 50, with no message."""
    spec = ElementSpec("Kx", "test arc", "Z = R/(1 + jωτ)", (ParameterSpec("R", "Ohm", 100.0), ParameterSpec("tau", "s", 1e-3)), lambda w, r, t: r / (1 + 1j * w * t))
    doubled = dataclasses.replace(spec, impedance=lambda w, r, t: 2 * r / (1 + 1j * w * t))
    assert spec != doubled
    one, two = ix.DEFAULT_REGISTRY.register(spec), ix.DEFAULT_REGISTRY.register(doubled)
    assert one != two and hash(one) != hash(two)
    w = 2 * np.pi * F
    data = ix.make_spectrum(F, 10.0 + 100.0 / (1 + 1j * w * 1e-3))
    assert ix.fit("R0 + Kx1", data, registry=one).values["Kx1.R"] == pytest.approx(100.0, rel=1e-6)
    assert ix.fit("R0 + Kx1", data, registry=two).values["Kx1.R"] == pytest.approx(50.0, rel=1e-6)
    batch = ix.fit("R0 + Kx1", ix.make_spectrum(F, np.stack([data["Z"].values] * 2), dims=("trial",)), registry=two)
    np.testing.assert_allclose(batch.values("Kx1.R").values, 50.0, rtol=1e-6)
