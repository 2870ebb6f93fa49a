"""Extending impedax (elements, readers, effects): a user's mistakes are refused where they are
made, naming the element, reader or effect and the field — not later, deep in a fit, as a raw
Python error. Expected values are written here by hand or with numpy; data are SYNTHETIC."""

import dataclasses
import math
import re
from pathlib import Path

import jax.numpy as jnp
import numpy as np
import pytest

import impedax as ix
from impedax.circuits import Element, ElementSpec, ParameterSpec
from impedax.circuits.compile import check_user_elements
from impedax.circuits.program import CircuitProgram
from impedax.errors import ArgumentNeeded
from impedax.io import Reader, register_reader

DOCS = Path(__file__).resolve().parent.parent / "docs"


def _arc(w, r, t):
    return r / (1 + 1j * w * t)


P2 = (ParameterSpec("R", "Ohm", 100.0), ParameterSpec("tau", "s", 1e-3))


def _spec(symbol="Kx", parameters=P2, impedance=_arc, **facts):
    return ElementSpec(symbol, "test arc", "Z = R/(1 + jωτ)", parameters, impedance, **facts)


# --- element specs, refused at declaration ----------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"lower": 1000.0, "upper": 1.0}, "parameter 'R': lower=1000 must be below upper=1"),
        ({"lower": 5.0, "upper": 5.0}, "parameter 'R': lower=5 must be below upper=5"),
        ({"lower": 0.0, "upper": 10.0}, "parameter 'R': default=100 is outside its bounds (0, 10)"),
        ({"default": 0.0}, "parameter 'R': default=0 is outside its bounds (0, inf)"),  # open at lower
        ({"default": math.nan}, "parameter 'R': default must be a finite number, got nan"),
        ({"default": math.inf}, "parameter 'R': default must be a finite number, got inf"),
        ({"lower": "0"}, "parameter 'R': lower must be a number, got str '0'"),
        ({"upper": None}, "parameter 'R': upper must be a number, got NoneType None"),
        ({"default": "100"}, "parameter 'R': default must be a number, got str '100'"),
        ({"lower": math.nan}, "parameter 'R': bounds must be numbers"),
        ({"unit": None}, "parameter 'R': unit must be text, got NoneType None"),
    ],
)
def test_a_bad_parameter_is_refused_naming_it_and_the_field(kwargs, message):
    arguments = {"suffix": "R", "unit": "Ohm", "default": 100.0, **kwargs}
    with pytest.raises(ix.CircuitError) as caught:
        ParameterSpec(**arguments)
    assert str(caught.value).startswith(message)


@pytest.mark.parametrize(
    "arguments, message",
    [
        # the unit left out: the default is taken for the unit, and the default is missing
        (("R", 1.0), "parameter 'R': no unit: ParameterSpec('R', 1.0) takes 1.0 for the unit and has no default; the unit comes second: "
                     "ParameterSpec('R', UNIT, 1.0), UNIT text such as 'Ohm', 'F', 's' or '1' (none)"),
        (("tau", 1e-3, 0.0), "parameter 'tau': unit must be text, got float 0.001; the unit comes second: ParameterSpec('tau', UNIT, 0.001), UNIT text "
                             "such as 'Ohm', 'F', 's' or '1' (none)"),
        (("R", "Ohm"), "parameter 'R': no default: its starting value comes third, ParameterSpec('R', 'Ohm', DEFAULT)"),
    ],
)
def test_a_parameter_declared_without_its_unit_says_so(arguments, message):
    with pytest.raises(ix.CircuitError) as caught:
        ParameterSpec(*arguments)
    assert str(caught.value) == message


def test_a_parameter_within_its_bounds_is_kept_and_its_numbers_become_floats():
    p = ParameterSpec("x", "1", 1, lower=-math.inf, upper=1, upper_inclusive=True)  # default at an inclusive upper
    assert (p.default, p.lower, p.upper) == (1.0, -math.inf, 1.0) and all(type(v) is float for v in (p.default, p.lower, p.upper))
    with pytest.raises(ix.CircuitError, match=r"default=1 is outside its bounds \(-inf, 1\)"):
        ParameterSpec("x", "1", 1, lower=-math.inf, upper=1)  # the same at an open upper


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"impedance": "notafunction"}, "element Kx: impedance must be a function f(omega, R, tau), got str 'notafunction'"),
        ({"admittance": 3.0}, "element Kx: admittance must be a function f(omega, R, tau), got float 3.0"),
        ({"impedance": lambda w, r: r + 0j}, "element Kx: its impedance function takes (w, r), but it is called as f(omega, R, tau): omega and one argument per parameter (2)"),
        ({"impedance": lambda w, r, t, extra: r + 0j}, "element Kx: its impedance function takes (w, r, t, extra)"),
        ({"admittance": lambda w: 1 + 0j}, "element Kx: its admittance function takes (w)"),
        ({"parameters": (("R", "Ohm", 1.0),)}, "element Kx: parameters[0] must be a ParameterSpec(suffix, unit, default, ...), got tuple ('R', 'Ohm', 1.0)"),
        ({"parameters": {"R": 1.0}}, "element Kx: parameters must be a tuple of ParameterSpec, got dict"),
        ({"aliases": "Kq"}, "element Kx: aliases must be a tuple of symbols, e.g. ('Kq',)"),
    ],
)
def test_a_bad_element_is_refused_naming_it_and_the_field(kwargs, message):
    with pytest.raises(ix.CircuitError) as caught:
        _spec(**kwargs)
    assert str(caught.value).startswith(message)


def test_formulas_of_any_fitting_signature_and_parameters_as_a_list_are_accepted():
    assert _spec(impedance=lambda w, *p: p[0] / (1 + 1j * w * p[1])).impedance is not None  # *args
    assert _spec(impedance=lambda w, r, t, k=1.0: k * r / (1 + 1j * w * t)).impedance is not None  # a default
    assert _spec(parameters=list(P2)) == _spec()  # a list is taken as the tuple (it was unhashable inside fit)
    one = ElementSpec("Ky", "resistor", "Z = R", ParameterSpec("R", "Ohm", 1.0), lambda w, r: r + 0j)
    assert one.parameters == (ParameterSpec("R", "Ohm", 1.0),)
    registry = ix.DEFAULT_REGISTRY.register(_spec(parameters=list(P2)))
    f = np.array([1.0, 159.15494309189535])  # ωτ = 1 at the second
    np.testing.assert_allclose(np.asarray(ix.compile_circuit("Kx1", registry)({"Kx1.R": 100.0, "Kx1.tau": 1e-3}, f)), [100 / (1 + 2j * np.pi * 1e-3), 50 - 50j], rtol=1e-12)


@pytest.mark.parametrize("spec", list(ix.DEFAULT_REGISTRY), ids=lambda s: s.symbol)
def test_every_built_in_spec_passes_its_own_checks(spec):
    again = dataclasses.replace(spec, parameters=tuple(dataclasses.replace(p) for p in spec.parameters))
    assert again == spec


def test_register_refuses_what_is_not_a_spec():
    with pytest.raises(ix.CircuitError, match=r"^Registry.register expects an ElementSpec\(symbol, name, equation, parameters, impedance\), got str 'Kx'$"):
        ix.DEFAULT_REGISTRY.register("Kx")


@pytest.mark.parametrize(
    "facts, message",
    [
        ({"symbol": "G"}, "element G: element symbol 'G' is already taken by the built-in Gerischer element (G: Z = R/√(1 + jωτ)); choose another symbol"),
        ({"aliases": ("Q",)}, "element Kx: element symbol 'Q' is already taken by the built-in constant phase element (CPE: Z = 1/(Q (jω)^α)); choose another symbol"),
        ({"cdc": "R"}, "element Kx: CDC letter 'R' is already taken by the built-in resistor element (R: Z = R); choose another CDC letter"),
    ],
)
def test_a_clash_with_a_built_in_says_it_is_the_built_in(facts, message):
    with pytest.raises(ix.CircuitError) as caught:
        ix.DEFAULT_REGISTRY.register(_spec(**facts))
    assert str(caught.value) == message


def test_a_clash_between_users_elements_names_the_first():
    registry = ix.DEFAULT_REGISTRY.register(_spec())
    with pytest.raises(ix.CircuitError, match=r"^element Kx: element symbol 'Kx' is already taken by this registry's test arc element \(Kx: Z = R/\(1 \+ jωτ\)\); choose another symbol$"):
        registry.register(_spec())


# --- user formulas, traced once when compiled -------------------------------------------------


@pytest.mark.parametrize(
    "formula, message",
    [
        (lambda w, r, t: np.asarray(r) / (1 + 1j * np.asarray(w) * t), "element Kb: its impedance function{at} failed under JAX (TracerArrayConversionError: "),
        (lambda w, r, t: r / (1 + 1j * w * t) if t > 0 else r, "element Kb: its impedance function{at} failed under JAX (TracerBoolConversionError: "),
        (lambda w, r, t: jnp.full(3, r + 0j), "element Kb: its impedance function{at} returns shape (3,) for 30 frequencies; it must return one value per frequency (shape (30,)) or a scalar"),
        (lambda w, r, t: (r, t), "element Kb: its impedance function{at} returns tuple, not an array of numbers"),
    ],
)
def test_a_formula_that_cannot_run_under_jax_is_refused_when_compiled(formula, message):
    """The message names the formula's file and line (each lambda above is on one line: the
    line it is written on, by Python's own record of it)."""
    registry = ix.DEFAULT_REGISTRY.register(_spec("Kb", impedance=formula))
    with pytest.raises(ix.CircuitError) as caught:
        ix.compile_circuit("R0 + Kb1", registry)
    assert str(caught.value).startswith(message.format(at=f" ({__file__}, line {formula.__code__.co_firstlineno})"))
    with pytest.raises(ix.CircuitError, match="element Kb: its impedance function"):  # the padded programs evaluate every kind
        CircuitProgram.build("R0 + R1", registry)


def test_the_trace_is_cached_per_spec_and_built_ins_are_not_traced():
    calls = []

    def counted(w, r, t):
        calls.append(1)
        return r / (1 + 1j * w * t)

    spec = _spec("Kc", impedance=counted)
    registry = ix.DEFAULT_REGISTRY.register(spec)
    ix.compile_circuit("R0 + Kc1", registry)
    assert len(calls) == 1
    ix.compile_circuit("Kc1 + R2", registry)
    check_user_elements([spec, *ix.DEFAULT_REGISTRY])
    assert len(calls) == 1


# --- readers ------------------------------------------------------------------------------------

LAB_TEXT = "LABEIS/1\n#DATA\n" + "".join(f"{f};{100 + 1 / f};0\n" for f in (1.0, 10.0, 100.0, 1000.0, 10000.0))


def _read_lab(path):
    rows = np.array([[float(x) for x in line.split(";")] for line in Path(path).read_text().splitlines()[2:]])
    return ix.make_spectrum(rows[:, 0], rows[:, 1] + 1j * rows[:, 2])


@pytest.fixture
def lab_file(tmp_path):
    path = tmp_path / "run1.lab"
    path.write_text(LAB_TEXT)
    return path


def test_one_extension_as_text_is_one_suffix():
    assert Reader("LABEIS", ".lab", lambda p, h: None, _read_lab).extensions == (".lab",)
    with pytest.raises(ValueError, match=r"Reader 'LABEIS': each extension is a suffix that starts with '\.', such as '\.lab', got 'lab'"):
        Reader("LABEIS", ("lab",), lambda p, h: None, _read_lab)
    with pytest.raises(TypeError, match="Reader 'LABEIS': sniff must be a function, got str"):
        Reader("LABEIS", (".lab",), "LABEIS/1", _read_lab)


@pytest.mark.parametrize(
    "sniff, says",
    [
        # (named by the file and line of the sniff that raised: the lambda's own)
        (lambda p, h: h[0:0] + 1, "reader 'LABEIS': its sniff{where} raised TypeError: can't concat int to bytes"),
        (lambda p, h: 1, "reader 'LABEIS': its sniff returned int 1"),
    ],
)
def test_a_sniff_that_breaks_its_contract_is_named_when_no_reader_claims_the_file(lab_file, sniff, says):
    readers = register_reader(Reader("LABEIS", (".lab",), sniff, _read_lab))
    with pytest.raises(ix.DataError) as caught:
        ix.load(lab_file, readers=readers)
    says = says.format(where=f" ({__file__}, line {sniff.__code__.co_firstlineno})")
    assert f"not a recognised spectrum file: {says} (a sniff returns None (or True) for a file in its format, else the reason it is not); as delimited text" in str(caught.value)


def test_a_sniff_may_answer_true_or_false(lab_file):
    mine = ix.load(lab_file, readers=register_reader(Reader("LABEIS", (".lab",), lambda p, h: h.startswith(b"LABEIS/1"), _read_lab)))
    np.testing.assert_allclose(mine["Z"].values, [101.0, 100.1, 100.01, 100.001, 100.0001])
    assert mine.attrs["format"] == "LABEIS"
    with pytest.raises(ix.DataError) as caught:
        ix.load(lab_file, readers=register_reader(Reader("LABEIS", (".lab",), lambda p, h: False, _read_lab)))
    assert "reader 'LABEIS'" not in str(caught.value)  # "not mine" is an answer, not a fault
    assert "LABEIS: sniff returned False" in ix.io.identify(lab_file, register_reader(Reader("LABEIS", (".lab",), lambda p, h: False, _read_lab)))[1]


def test_a_read_that_returns_no_dataset_is_named(lab_file):
    readers = register_reader(Reader("LABEIS", (".lab",), lambda p, h: None, lambda p: (1, 2)))
    with pytest.raises(ix.DataError, match=r"run1.lab: reader 'LABEIS' returned tuple, not a spectrum Dataset \(build it with impedax.make_spectrum\)"):
        ix.load(lab_file, readers=readers)


# --- a user's element read without its registry -------------------------------------------------


def test_the_hint_for_an_unknown_symbol_first_asks_for_the_users_registry():
    with pytest.raises(ix.CircuitSyntaxError) as caught:
        ix.parse("R0 + Gfl1")
    assert caught.value.unknown_symbol == "Gfl"
    assert caught.value.hint == "if Gfl is an element of your own, pass the registry that declares it (registry= in Python); else did you mean G_fl1?"


def test_a_saved_fit_of_a_users_element_read_without_its_registry_is_not_called_damaged(tmp_path):
    registry = ix.DEFAULT_REGISTRY.register(_spec())
    f = np.logspace(0, 5, 16)
    data = ix.make_spectrum(f, 10.0 + 100.0 / (1 + 2j * np.pi * f * 1e-3))  # SYNTHETIC, noise-free
    path = tmp_path / "fit_kx.nc"
    ix.write_result(ix.fit("R0 + Kx1", data, registry=registry, n_starts=1), path)
    saved = ix.load(path)
    with pytest.raises(ArgumentNeeded) as caught:
        ix.FitResult.from_xarray(saved)
    assert str(caught.value) == f"{path}: the saved least-squares fit uses element 'Kx', which is not in the registry: pass the registry that declares it (registry=)"
    assert ix.FitResult.from_xarray(saved, registry=registry).values["Kx1.R"] == pytest.approx(100.0, rel=1e-6)


# --- a user's effect --------------------------------------------------------------------------


def _doc_blocks() -> list[str]:
    """The python blocks of docs/diagnosis.md's "An effect of your own"."""
    text = (DOCS / "diagnosis.md").read_text(encoding="utf-8")
    section = text[text.index("### An effect of your own") : text.index("## 5. Ranking and verdict")]
    return re.findall(r"```python\n(.*?)```", section, flags=re.S)


def _context(circuit_text="R0 + R1 || C1", values=None):
    """A baseline that lacks a Gerischer (SYNTHETIC data: R0 = 10 Ω + G, R = 200 Ω, τ = 10 ms)."""
    from impedax.fitting.diagnosis import BaselineContext

    f = np.logspace(-2, 6, 50)
    circuit = ix.parse(circuit_text)
    values = values or {"R0": 10.0, "R1": 150.0, "C1": 1e-4}
    z_model = np.asarray(ix.compile_circuit(circuit)(values, f))
    return BaselineContext(circuit, values, f, 10.0 + 200.0 / np.sqrt(1.0 + 2j * np.pi * f * 0.01), z_model)


def test_the_documented_effect_proposes_its_element():
    from impedax.fitting.diagnosis import BaselineContext, Effect, EffectCatalog, Proposal  # the types a propose needs

    assert BaselineContext and Proposal and Effect and EffectCatalog
    scope: dict = {}
    exec(_doc_blocks()[0], scope)
    [(effect, proposal)] = ix.fitting.diagnosis.EffectCatalog((scope["GERISCHER"],)).proposals(_context())
    assert effect.id == proposal.effect == "gerischer" and scope["effects"].ids()[-1] == "gerischer"
    assert str(proposal.circuit) == "R0 + R1 || C1 + G_rd" and len(proposal.starts) == 3
    assert {k: v for k, v in proposal.starts[0].items() if not k.startswith("G_")} == {"R0": 10.0, "R1": 150.0, "C1": 1e-4}


@pytest.mark.slow
def test_the_documented_diagnosis_names_the_users_effect_first(capsys):
    scope: dict = {}
    for block in _doc_blocks():
        exec(block, scope)
    assert scope["diagnosis"].verdict == "missing_effect"
    assert "1. [gerischer]" in capsys.readouterr().out


def _propose(returns):
    from impedax.fitting.diagnosis import Effect

    return Effect("mine", "t", "p", "s", "c", lambda circuit, ctx: returns(circuit, ctx))


@pytest.mark.parametrize(
    "returns, error, message",
    [
        (lambda c, x: 1 / 0, ix.ParameterError, "effect 'mine': its propose raised ZeroDivisionError: division by zero"),
        (lambda c, x: None, ix.ParameterError, "effect 'mine': its propose returned NoneType, not a list of Proposal (an empty list when it has nothing to propose)"),
        (lambda c, x: ["R0 + L_x"], ix.ParameterError, "effect 'mine': its propose returned, as item 0, str, not a Proposal"),
        (
            lambda c, x: [_proposal("mine", str(c) + " + L_x", x.start(L_x=1e-6))],
            ix.ParameterError,
            "effect 'mine': its propose returned, as item 0, a circuit that is str, not a Circuit (parse it: impedax.parse('R0 + R1 || C1 + L_x', ctx.registry)",
        ),
        (lambda c, x: [_proposal("other", c + Element("L", "L_x"), x.start(L_x=1e-6))], ix.ParameterError, "effect 'mine': its propose returned, as item 0, a Proposal of effect 'other'"),
        (
            lambda c, x: [_proposal("mine", c + Element("L", "L_x"), x.start(L_y=1e-6))],
            ix.ParameterError,
            "effect 'mine': its propose returned, as item 0, starting values of 'L_y', which R0 + R1 || C1 + L_x does not have",
        ),
        (lambda c, x: [_proposal("mine", c + Element("Zz", "Zz_x"), x.start())], ix.CircuitError, "effect 'mine': its propose returned, as item 0, the circuit R0 + R1 || C1 + Zz_x: unknown element symbol 'Zz'"),
    ],
)
def test_a_users_effect_that_proposes_wrongly_is_named(returns, error, message):
    catalog = ix.fitting.diagnosis.EffectCatalog((_propose(returns),))
    with pytest.raises(error) as caught:
        catalog.proposals(_context())
    assert str(caught.value).startswith(message)


def _proposal(effect, circuit, start):
    from impedax.fitting.diagnosis import Proposal

    return Proposal(effect, circuit, "L_x", "in series", (start,))


@pytest.mark.parametrize(
    "element, start, message",
    [
        ("R", {"R_x": -5.0}, "effect 'mine': its propose returned, as item 0, a start R_x=-5.0, outside R_x's bounds (0, inf)"),
        ("CPE", {"CPE_x.Q": 1e-6, "CPE_x.alpha": 1.5}, "effect 'mine': its propose returned, as item 0, a start CPE_x.alpha=1.5, outside CPE_x.alpha's bounds (0, 1]"),
        ("R", {"R_x": 5.0, "R1": -150.0}, "effect 'mine': its propose returned, as item 0, a start R1=-150.0, outside R1's bounds (0, inf)"),
        ("R", {"R_x": "5"}, "effect 'mine': its propose returned, as item 0, a start R_x='5', outside R_x's bounds (0, inf)"),
    ],
)
def test_a_users_effect_starting_outside_the_bounds_is_named(element, start, message):
    catalog = ix.fitting.diagnosis.EffectCatalog((_propose(lambda c, x: [_proposal("mine", c + Element(element, f"{element}_x"), {**x.start(), **start})]),))
    with pytest.raises(ix.ParameterError) as caught:
        catalog.proposals(_context())
    assert str(caught.value).startswith(message), str(caught.value)


def test_a_users_effect_may_keep_a_baseline_value_on_its_bound_and_start_inside():
    # the baseline's own fitted values pass as they are (a fitted CPE alpha may sit at 1, on
    # its bound); the values the effect sets lie inside their bounds
    ctx = _context("R0 + R1 || CPE1", {"R0": 10.0, "R1": 150.0, "CPE1.Q": 1e-4, "CPE1.alpha": 1.0})
    ctx = dataclasses.replace(ctx, values={**ctx.values, "R0": 0.0})  # a series R fitted to zero, its lower bound
    catalog = ix.fitting.diagnosis.EffectCatalog((_propose(lambda c, x: [_proposal("mine", c + Element("L", "L_x"), x.start(L_x=1e-6))]),))
    [(_, proposal)] = catalog.proposals(ctx)
    assert proposal.starts[0] == {"R0": 0.0, "R1": 150.0, "CPE1.Q": 1e-4, "CPE1.alpha": 1.0, "L_x": 1e-6}
