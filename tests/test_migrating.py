"""Coming from impedance.py (docs/migrating.md): its elements, names, keywords and results map
onto impedax's as the page says.

Oracles: impedance.py's own functions and fits (installed with the bench extras; those tests
are skipped without it), and formulas written out here. Data: impedance.py's REAL example
spectrum (tests/fixtures/real/exampleData.csv), and SYNTHETIC spectra from numpy formulas.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.circuits import ElementSpec, ParameterSpec
from impedax.cli import main

EXAMPLE = Path(__file__).parent / "fixtures" / "real" / "exampleData.csv"  # REAL: impedance.py's example
FREQ = np.logspace(-2, 5, 36)  # Hz


def synthetic_rc() -> "ix.xarray.Dataset":
    """SYNTHETIC: R0 + R1 || C1 (10 Ω, 100 Ω, 1 µF) with 0.5 % proportional noise, seed 3."""
    rng = np.random.default_rng(3)
    z = 10 + 100 / (1 + 1j * 2 * np.pi * FREQ * 100 * 1e-6)
    z = z * (1 + 0.005 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)))
    return ix.make_spectrum(FREQ, z)


# --- elements -------------------------------------------------------------------------------

# impedance.py symbol → parameter values in impedance.py's order (p[0], p[1], ...)
ELEMENT_VALUES = {
    "R": [47.0], "C": [3e-6], "L": [2e-7], "CPE": [4e-5, 0.83], "W": [35.0],
    "Wo": [80.0, 0.4], "Ws": [60.0, 2.5], "G": [30.0, 4e-3], "Zarc": [25.0, 1.5e-3, 0.72],
}


@pytest.mark.parametrize("symbol", sorted(ELEMENT_VALUES))
def test_every_mapped_element_is_impedance_pys_formula_in_its_parameter_order(symbol):
    """impedax's element with ``impedance_py=symbol``, its parameters in declaration order,
    against impedance.py's own element function with the same list."""
    elements = pytest.importorskip("impedance.models.circuits.elements")
    spec = ix.DEFAULT_REGISTRY.by_impedance_py[symbol]
    values = ELEMENT_VALUES[symbol]
    z_impedance_py = np.asarray(getattr(elements, symbol)(values, FREQ))
    z_impedax = np.asarray(spec.impedance(2 * np.pi * FREQ, *values))
    np.testing.assert_allclose(z_impedax, z_impedance_py, rtol=1e-13)


def test_zarc_is_cole_cole_both_ways():
    circuit = ix.from_impedance_py("R0-p(R1,CPE1)-Zarc1")
    assert str(circuit) == "R0 + R1 || CPE1 + CC1"
    assert circuit.parameter_names()[-3:] == ("CC1.R", "CC1.tau", "CC1.alpha")
    assert ix.to_impedance_py("R0 + R1 || CPE1 + CC1") == "R0-p(R1,CPE1)-Zarc1"  # CC1 keeps its number
    assert ix.to_impedance_py("R0 + Q1") == "R0-CPE0"  # an alias's number is not kept (test_convert)


def test_an_element_without_equivalent_names_the_way_out():
    with pytest.raises(ix.CircuitSyntaxError) as caught:
        ix.from_impedance_py("R0-K1")
    text = str(caught.value)
    assert "'K' has no impedax equivalent" in text and "Zarc" in text
    assert "impedance_py='K'" in text and '"Adding an element"' in text


def test_the_pages_user_k_element_is_impedance_pys_k():
    """docs/migrating.md, "Elements": K registered with ``impedance_py="K"``."""
    elements = pytest.importorskip("impedance.models.circuits.elements")

    def k_element(omega, r, tau):
        return r / (1.0 + 1j * omega * tau)

    k_spec = ElementSpec(
        "K", "RC relaxation (impedance.py's K)", "Z = R/(1 + jωτ)",
        (ParameterSpec("R", "Ohm", 100.0), ParameterSpec("tau", "s", 1e-3)), k_element, impedance_py="K",
    )
    registry = ix.DEFAULT_REGISTRY.register(k_spec)
    circuit = ix.from_impedance_py("R0-K1", registry)
    assert circuit.parameter_names(registry) == ("R0", "K1.R", "K1.tau")
    assert circuit.to_impedance_py(registry) == "R0-K1"
    # (the page says the circuit holds no registry: each look-up takes it again)
    with pytest.raises(ix.CircuitError, match="unknown element symbol 'K'"):
        circuit.parameter_names()
    z = np.asarray(ix.compile_circuit(circuit, registry)({"R0": 5.0, "K1.R": 40.0, "K1.tau": 2e-3}, FREQ))
    np.testing.assert_allclose(z, 5.0 + np.asarray(elements.K([40.0, 2e-3], FREQ)), rtol=1e-13)


# --- names and keywords ---------------------------------------------------------------------

NAME_HINTS = [
    ("fixed", "CPE1_1", "CPE1.alpha"),  # was "CPE1.Q", the closer spelling
    ("fixed", "CPE1_0", "CPE1.Q"),
    ("init", "Wo1_0", "Wo1.R"),
    ("init", "Wo1_1", "Wo1.tau"),
    ("fixed", "W1", "W1.sigma"),  # a bare element name: its one parameter
    ("fixed", "Zarc1_2", "CC1.alpha"),  # impedance.py's symbol, read through the registry
    ("bounds", "R_0", "R0"),
]


AUTOEIS_NAME_HINTS = [
    ("fixed", "P3n", "CPE3.alpha"),  # AutoEIS's CPE exponent n
    ("init", "P3w", "CPE3.Q"),  # its magnitude w
    ("fixed", "P3", "CPE3.Q or CPE3.alpha"),  # a bare element: both
    ("bounds", "P3n", "CPE3.alpha"),
]
# AutoEIS's documentation: "the corresponding CPE is parameterized by P4w and P4n", Q and α
OTHER_TOOLS_CIRCUITS = {"impedance.py": lambda: ix.from_impedance_py("R0-p(R1,CPE1)-Wo1-W1-Zarc1"), "AutoEIS": lambda: ix.from_autoeis("R1-[R2,P3]")}


@pytest.mark.parametrize(("tool", "keyword", "name", "meant"), [("impedance.py", *row) for row in NAME_HINTS] + [("AutoEIS", *row) for row in AUTOEIS_NAME_HINTS])
def test_another_tools_parameter_name_is_answered_with_impedaxs(tool, keyword, name, meant):
    circuit = OTHER_TOOLS_CIRCUITS[tool]()
    value = (0.5, 1.0) if keyword == "bounds" else 0.5
    with pytest.raises(ix.ParameterError, match=rf"unknown parameter '{name}'.*; did you mean {meant}\?"):
        ix.fit(circuit, synthetic_rc(), **{keyword: {name: value}})


def test_a_bare_name_of_an_element_with_several_parameters_gives_them_all():
    from impedax.arguments import closest_name

    assert closest_name("CPE1", ["R0", "CPE1.Q", "CPE1.alpha"]) == "CPE1.Q or CPE1.alpha"
    assert closest_name("CPE1_2", ["R0", "CPE1.Q", "CPE1.alpha"]) != "CPE1.alpha"  # no third parameter
    assert closest_name("CPE1.a", ["CPE1.Q", "CPE1.alpha"]) == "CPE1.alpha"  # the earlier rules stand


@pytest.mark.parametrize(
    ("keywords", "expected"),
    [
        ({"constants": {"R0": 10.0}}, "for impedance.py's constants= write fixed={name: value}"),
        ({"initial_guess": [10.0, 100.0, 1e-6]}, "for impedance.py's initial_guess= write init={name: value}, here init={'R0': 10.0, 'R1': 100.0, 'C1': 1e-06}"),
        ({"initial_guess": [10.0, 100.0]}, "init=dict(zip(circuit.parameter_names(), initial_guess))"),  # (2 values for 3 parameters: the recipe)
        ({"weight_by_modulus": True}, 'write weighting="modulus"'),
    ],
)
def test_impedance_py_keywords_are_answered_with_impedaxs(keywords, expected):
    with pytest.raises(ix.ParameterError) as caught:
        ix.fit("R0 + R1 || C1", synthetic_rc(), **keywords)
    assert expected in str(caught.value) and "n_starts" not in str(caught.value)


def test_the_constants_hint_shows_the_users_own_values_as_fixed():
    with pytest.raises(ix.ParameterError) as caught:
        ix.fit("R0 + R1 || C1", synthetic_rc(), constants={"R0": 10.0})
    assert str(caught.value) == "fit() has no argument 'constants': for impedance.py's constants= write fixed={name: value}, here fixed={'R0': 10.0} (docs/migrating.md)"


@pytest.mark.parametrize("circuit", ["R0-p(R1,CPE1)", "R0 + R1 || CPE1", "from_impedance_py"])
def test_the_constants_and_initial_guess_hints_write_impedance_py_names_as_impedaxs(circuit):
    circuit = ix.from_impedance_py("R0-p(R1,CPE1)") if circuit == "from_impedance_py" else circuit
    with pytest.raises(ix.ParameterError) as caught:
        ix.fit(circuit, synthetic_rc(), constants={"R0": 10.0, "CPE1_1": 0.9})
    assert "here fixed={'R0': 10.0, 'CPE1.alpha': 0.9} (docs/migrating.md)" in str(caught.value)
    with pytest.raises(ix.ParameterError) as caught:
        ix.diagnose(synthetic_rc(), circuit, constants={"CPE1_0": 1e-6})
    assert "here fixed={'CPE1.Q': 1e-06}" in str(caught.value)
    with pytest.raises(ix.ParameterError) as caught:
        ix.fit(circuit, synthetic_rc(), initial_guess=[10, 100, 1e-6, 0.9])
    assert "here init={'R0': 10, 'R1': 100, 'CPE1.Q': 1e-06, 'CPE1.alpha': 0.9}" in str(caught.value)


def test_an_impedance_py_string_in_python_is_answered_with_from_impedance_py():
    with pytest.raises(ix.CircuitSyntaxError) as caught:
        ix.fit("R0-p(R1,CPE1)", synthetic_rc())
    assert caught.value.hint == "series is written '+'; in Python an impedance.py string is passed as ix.from_impedance_py('R0-p(R1,CPE1)') (the command line reads it by itself)"


@pytest.mark.parametrize(("model", "shown"), [("R0-p(R1,CPE1)", "CPE1.alpha=0.5:1"), ("R0 + R1 || CPE1", "CPE1.alpha=0.5:1"), ("R0 + R1 || C1", "CPE1_1=0.5:1")])
def test_cli_misspelt_bound_option_shows_the_option_it_names_and_impedaxs_name(model, shown, capsys):
    with pytest.raises(SystemExit) as caught:
        main(["fit", "data.csv", "--model", model, "--bounds", "CPE1_1=0.5:1"])
    assert caught.value.code == 2
    err = capsys.readouterr().err
    assert f"unrecognized arguments: --bounds CPE1_1=0.5:1; did you mean --bound?; a NAME=VALUE follows its option (--init, --fix, --bound): e.g. --bound {shown}\n" in err


def test_init_as_a_list_shows_the_translation():
    with pytest.raises(ix.ParameterError, match=r"got a list; from impedance.py's initial_guess list: init=dict\(zip"):
        ix.fit("R0 + R1 || C1", synthetic_rc(), init=[10.0, 100.0, 1e-6])


def test_bounds_as_two_lists_shows_the_translation_and_a_pair_example():
    with pytest.raises(ix.ParameterError) as caught:
        ix.fit("R0 + R1 || C1", synthetic_rc(), bounds=([0, 0, 0], [1e3, 1e3, 1]))
    text = str(caught.value)
    assert "impedance.py's (lower list, upper list)" in text and "{'R1': (10.0, 1e3)}" in text
    assert "zip(circuit.parameter_names(), lower, upper)" in text
    with pytest.raises(ix.ParameterError, match=r"e\.g\. \{'R1': \(10\.0, 1e3\)\}; got list"):
        ix.fit("R0 + R1 || C1", synthetic_rc(), bounds=[1.0, 2.0])


def test_the_pages_init_from_a_list_follows_impedance_pys_order():
    circuits = pytest.importorskip("impedance.models.circuits")
    text = "R0-p(R1,CPE1)-p(R2-Wo1,CPE2)-Zarc1"
    circuit = ix.from_impedance_py(text)
    names, _ = circuits.CustomCircuit(text, initial_guess=[1.0] * len(circuit.parameter_names())).get_param_names()
    by_hint = [ix.arguments.closest_name(n, circuit.parameter_names(), impedance_py_symbols=ix.DEFAULT_REGISTRY.impedance_py_symbols) for n in names]
    assert by_hint == list(circuit.parameter_names())  # the hints map impedance.py's names one to one, in order


# --- data and results -----------------------------------------------------------------------


def test_ignore_below_x_one_liner_keeps_impedance_pys_points():
    preprocessing = pytest.importorskip("impedance.preprocessing")
    f, z = preprocessing.ignoreBelowX(*preprocessing.readCSV(str(EXAMPLE)))
    data = ix.load(EXAMPLE)
    data = data.isel(frequency=np.flatnonzero(data.Z.values.imag < 0))
    order = np.argsort(f)
    np.testing.assert_array_equal(data.frequency.values, f[order])
    np.testing.assert_array_equal(data.Z.values, z[order])


def test_kk_test_is_linkk_complex_with_capacitor(monkeypatch):
    validation = pytest.importorskip("impedance.validation")
    preprocessing = pytest.importorskip("impedance.preprocessing")
    # (numpy 2 writes np.float64(...) into the string linKK evaluates: it needs np there)
    monkeypatch.setitem(validation.circuit_elements, "np", np)
    f, z = preprocessing.ignoreBelowX(*preprocessing.readCSV(str(EXAMPLE)))
    m, mu, _, res_real, res_imag = validation.linKK(f, z, c=0.85, fit_type="complex", add_cap=True)
    data = ix.load(EXAMPLE)
    kk = ix.kk_test(data.isel(frequency=np.flatnonzero(data.Z.values.imag < 0)), c=0.85)
    assert kk.n_rc == m and kk.mu == pytest.approx(mu, rel=1e-6)
    order = np.argsort(f)
    np.testing.assert_allclose(kk.residuals_real, res_real[order], atol=1e-7)
    np.testing.assert_allclose(kk.residuals_imag, res_imag[order], atol=1e-7)


def test_kk_test_with_linkks_m_is_linkk_where_the_ms_differ(monkeypatch):
    """docs/migrating.md, "Validity test": on the REAL ZPlot file linKK stops at M = 6, impedax's
    rule at 9; with ``n_rc`` = linKK's M the chain, µ and residuals are linKK's."""
    validation = pytest.importorskip("impedance.validation")
    preprocessing = pytest.importorskip("impedance.preprocessing")
    monkeypatch.setitem(validation.circuit_elements, "np", np)  # (impedance.py 1.7.1 under numpy 2)
    path = EXAMPLE.parent / "exampleDataZPlot.z"
    f, z = preprocessing.readFile(str(path), instrument="zplot")
    m, mu, _, res_real, res_imag = validation.linKK(f, z, c=0.85, fit_type="complex", add_cap=True)
    data = ix.load(path)
    assert m == 6 and ix.kk_test(data, c=0.85).n_rc != m  # (9 when written: impedax chooses M its own way)
    kk = ix.kk_test(data, n_rc=m)
    at = [int(np.argmin(np.abs(data.frequency.values - fi))) for fi in f]
    assert kk.mu == pytest.approx(mu, rel=1e-9)
    np.testing.assert_allclose(kk.residuals_real[at], res_real, atol=1e-10)
    np.testing.assert_allclose(kk.residuals_imag[at], res_imag, atol=1e-10)


def test_linkk_under_numpy_2_needs_np_where_it_evaluates():
    """docs/migrating.md, "Validity test": impedance.py 1.7.1's linKK evaluates a string that
    numpy 2 writes as np.float64(...); without the page's one line it raises NameError."""
    validation = pytest.importorskip("impedance.validation")
    if int(np.__version__.split(".")[0]) < 2 or "np" in validation.circuit_elements:
        pytest.skip("numpy 1, or impedance.py already fixed")
    f = np.logspace(-1, 4, 20)
    with pytest.raises(NameError, match="'np'"):
        validation.linKK(f, 10 + 100 / (1 + 1j * 2 * np.pi * f * 1e-3), c=None, max_M=3, fit_type="complex", add_cap=True)


@pytest.mark.slow  # (three fits, ~18 s with their compilation)
def test_the_same_start_need_not_reach_impedance_pys_optimum():
    """docs/migrating.md, "The same start need not end at the same optimum" (REAL exampleData.csv):
    R0-p(R1,CPE1)-Wo1 from impedance.py's guess, by modulus: impedance.py reaches cost 0.0357,
    impedax's n_starts=1 a local minimum at 0.1295, its default several starts 0.0357."""
    circuits = pytest.importorskip("impedance.models.circuits")
    preprocessing = pytest.importorskip("impedance.preprocessing")
    f, z = preprocessing.ignoreBelowX(*preprocessing.readCSV(str(EXAMPLE)))
    data = ix.load(EXAMPLE)
    data = data.isel(frequency=np.flatnonzero(data.Z.values.imag < 0))
    text, guess = "R0-p(R1,CPE1)-Wo1", [0.01, 0.01, 10, 0.9, 0.01, 1]
    theirs = circuits.CustomCircuit(text, initial_guess=guess)
    theirs.fit(f, z, weight_by_modulus=True)
    circuit = ix.from_impedance_py(text)
    init = dict(zip(circuit.parameter_names(), guess))

    def cost(z_model):  # Σ |(Z_model − Z)/|Z||², the modulus weighting's cost
        return float(np.sum(np.abs((np.asarray(z_model) - z) / np.abs(z)) ** 2))

    one_start = ix.fit(circuit, data, init=init, n_starts=1)
    several = ix.fit(circuit, data, init=init)
    assert cost(theirs.predict(f)) == pytest.approx(0.0357, abs=5e-4)
    assert cost(one_start.predict(f)) == pytest.approx(0.1295, abs=5e-4) and one_start.values["CPE1.alpha"] == pytest.approx(0.234, abs=1e-3)
    assert cost(several.predict(f)) == pytest.approx(cost(theirs.predict(f)), rel=1e-3)


@pytest.mark.slow  # (two fits from impedance.py's start, ~7 s with their compilation)
def test_the_same_weighting_gives_impedance_pys_fit():
    """docs/migrating.md, "The same fit, the same numbers": unit ≡ impedance.py's default,
    modulus ≡ weight_by_modulus=True; arcs listed highest-frequency first."""
    circuits = pytest.importorskip("impedance.models.circuits")
    preprocessing = pytest.importorskip("impedance.preprocessing")
    f, z = preprocessing.ignoreBelowX(*preprocessing.readCSV(str(EXAMPLE)))
    data = ix.load(EXAMPLE)
    data = data.isel(frequency=np.flatnonzero(data.Z.values.imag < 0))
    text, guess = "R0-p(R1,CPE1)-p(R2,CPE2)", [0.01, 0.01, 10, 0.9, 0.01, 1, 0.9]
    circuit = ix.from_impedance_py(text)
    init = dict(zip(circuit.parameter_names(), guess))
    for weighting, by_modulus in (("unit", False), ("modulus", True)):
        theirs = circuits.CustomCircuit(text, initial_guess=guess)
        theirs.fit(f, z, weight_by_modulus=by_modulus)
        p = dict(zip(theirs.get_param_names()[0], theirs.parameters_))
        conf = dict(zip(theirs.get_param_names()[0], theirs.conf_))
        ours = ix.fit(circuit, data, init=init, weighting=weighting, n_starts=1)
        # arcs by time constant τ = (R Q)^(1/α), shortest (highest frequency) first
        arcs = sorted((1, 2), key=lambda k: (p[f"R{k}"] * p[f"CPE{k}_0"]) ** (1 / p[f"CPE{k}_1"]))
        for mine, k in zip((1, 2), arcs):
            for ours_name, theirs_name in ((f"R{mine}", f"R{k}"), (f"CPE{mine}.Q", f"CPE{k}_0"), (f"CPE{mine}.alpha", f"CPE{k}_1")):
                assert ours.values[ours_name] == pytest.approx(p[theirs_name], rel=2e-3), (weighting, ours_name)
                assert ours.stderr[ours_name] == pytest.approx(conf[theirs_name], rel=2e-2), (weighting, ours_name)
        assert ours.values["R0"] == pytest.approx(p["R0"], rel=1e-3)
        np.testing.assert_allclose(ours.predict(f), theirs.predict(f), rtol=1e-3)


# --- plotting -------------------------------------------------------------------------------


def test_plot_nyquist_takes_a_complex_array():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from impedax.plotting import plot_bode, plot_nyquist

    z = 10 + 100 / (1 + 1j * FREQ / 100)  # SYNTHETIC
    fig, ax = plt.subplots()
    plot_nyquist(ax, z, list(z * 1.01))
    (x, y), (xm, _) = ax.lines[0].get_data(), ax.lines[1].get_data()
    np.testing.assert_array_equal(x, z.real)
    np.testing.assert_array_equal(y, -z.imag)
    np.testing.assert_allclose(xm, 1.01 * z.real)
    with pytest.raises(ix.ParameterError, match="plot_bode: data is a complex array of Z without frequencies"):
        plot_bode(ax, ax, z)
    with pytest.raises(ix.ParameterError, match=r"plot_nyquist: data must be a spectrum Dataset .* or a complex array of Z; got array of shape"):
        plot_nyquist(ax, FREQ)  # real numbers: no Z
    with pytest.raises(ix.ParameterError, match=r"frequency and Z differ in shape"):
        plot_nyquist(ax, (FREQ, z[:3]))
    plt.close(fig)


# --- command line ---------------------------------------------------------------------------


def test_cli_reads_an_impedance_py_model_and_says_so(capsys):
    assert main(["info", "R0-p(R1,CPE1)-Zarc1", "--json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["model"] == "R0 + R1 || CPE1 + CC1"
    assert captured.err.strip() == "impedax info: read as impedance.py notation: R0 + R1 || CPE1 + CC1"
    assert main(["info", "R0 + R1 || C1"]) == 0
    assert "impedance.py" not in capsys.readouterr().err  # impedax text: no note


def test_cli_refuses_an_impedance_py_model_it_cannot_read_with_the_readers_message(capsys):
    assert main(["info", "R0-K1"]) == 2
    err = capsys.readouterr().err
    assert "impedance.py element 'K' has no impedax equivalent" in err and "Traceback" not in err


def test_cli_keeps_impedaxs_message_for_impedax_text_with_a_stray_minus(capsys):
    assert main(["info", "R0 + R1 - C1"]) == 2
    err = capsys.readouterr().err
    assert "series is written '+'" in err and "read as impedance.py" not in err


def test_cli_fix_hints_an_impedance_py_parameter_name(capsys):
    assert main(["fit", str(EXAMPLE), "--model", "R0-p(R1,CPE1)", "--fix", "CPE1_1=0.9"]) == 2
    err = capsys.readouterr().err
    assert "read as impedance.py notation: R0 + R1 || CPE1" in err
    assert "unknown parameter 'CPE1_1'" in err and "did you mean CPE1.alpha?" in err


def test_an_autoeis_name_of_an_element_the_circuit_lacks_gets_no_cpe_hint():
    from impedax.arguments import closest_name

    assert closest_name("P4n", ["R1", "R2", "CPE3.Q", "CPE3.alpha"]) is None  # no CPE4
    assert closest_name("P3x", ["R1", "CPE3.Q", "CPE3.alpha"]) is None  # AutoEIS has no suffix x


def test_cli_fix_hints_an_autoeis_parameter_name(capsys):
    assert main(["fit", str(EXAMPLE), "--model", "R1-[R2,P3]", "--fix", "P3n=0.9"]) == 2
    err = capsys.readouterr().err
    assert "read as AutoEIS notation: R1 + R2 || CPE3" in err
    assert "unknown parameter 'P3n'" in err and "did you mean CPE3.alpha?" in err


WEIGHTING_NOTE = ("note: impedax weights the residuals by 1/|Z| by default (--weighting modulus, impedance.py's weight_by_modulus=True); "
                  "impedance.py's default is unweighted, here --weighting unit")


@pytest.mark.parametrize("command", ["fit", "diagnose", "refine"])
def test_cli_says_once_that_the_default_weighting_is_not_impedance_pys(capsys, command):
    """A walkthrough (2026-12-02): "read as impedance.py notation" said nothing of the weighting.
    (The --fix error stops each run before any fit: the notes come first.)"""
    assert main([command, str(EXAMPLE), "--model", "R0-p(R1,CPE1)", "--fix", "CPE1_1=0.9"]) == 2
    assert capsys.readouterr().err.count(f"impedax {command}: {WEIGHTING_NOTE}") == 1
    assert main([command, str(EXAMPLE), "--model", "R0-p(R1,CPE1)", "--weighting", "unit", "--fix", "CPE1_1=0.9"]) == 2  # (the note's option, as spelt)
    err = capsys.readouterr().err
    assert "read as impedance.py notation" in err and "weight_by_modulus" not in err and "unrecognized" not in err
    assert main([command, str(EXAMPLE), "--model", "R0 + R1 || CPE1", "--fix", "CPE1_1=0.9"]) == 2  # impedax text: no note
    assert "weight_by_modulus" not in capsys.readouterr().err


def test_cli_weighting_note_once_for_several_models_and_not_where_nothing_is_weighted(capsys):
    assert main(["compare", str(EXAMPLE), "--model", "R0-p(R1,C1)", "--model", "R0-p(R1,CPE1)", "--fix", "CPE1_1=0.9"]) == 2
    assert capsys.readouterr().err.count(WEIGHTING_NOTE) == 1
    assert main(["sample", str(EXAMPLE), "--model", "R0-p(R1,CPE1)", "--fix", "CPE1_1=0.9"]) == 2  # (sample's --noise is its own: no --weighting)
    assert "weight_by_modulus" not in capsys.readouterr().err


def test_cli_compare_reads_impedance_py_models(capsys):
    """compare's --model is a list: each impedance.py string read and named once."""
    assert main(["compare", str(EXAMPLE), "--model", "R0-p(R1,C1)", "--model", "R0 + R1 || CPE1", "--json"]) == 0
    captured = capsys.readouterr()
    assert [row["model"] for row in json.loads(captured.out)["models"]] == ["R0 + R1 || C1", "R0 + R1 || CPE1"]
    assert captured.err.count("read as impedance.py notation") == 1
    assert "impedax compare: read as impedance.py notation: R0 + R1 || C1" in captured.err
