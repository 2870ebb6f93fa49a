"""Elements that contain others (`ElementSpec.limits`), circuits nested through them
(`impedax.circuits.nesting`), fits started from a nested model's optimum (``fit(init=)``) and
the comparisons that say when a model fits worse than one it contains."""

import json
import math

import numpy as np
import pytest

import impedax as ix
from impedax.circuits import DEFAULT_REGISTRY, ElementLimit, ElementSpec, ParameterSpec
from impedax.circuits.nesting import carried_values, embedding
from impedax.errors import CircuitError
from impedax.fitting import is_nested

# element impedances written here from their textbook formulas (docs/physics.md, "Element
# formulas"), not from impedax's element functions
NUMPY_Z = {
    "R": lambda w, r: r + 0 * w,
    "C": lambda w, c: 1 / (1j * w * c),
    "CPE": lambda w, q, a: 1 / (q * (1j * w) ** a),
    "W": lambda w, s: s * (1 - 1j) / np.sqrt(w),
    "Wo": lambda w, r, t: r / (np.sqrt(1j * w * t) * np.tanh(np.sqrt(1j * w * t))),
    "Ws": lambda w, r, t: r * np.tanh(np.sqrt(1j * w * t)) / np.sqrt(1j * w * t),
    "G": lambda w, r, t: r / np.sqrt(1 + 1j * w * t),
    "CC": lambda w, r, t, a: r / (1 + (1j * w * t) ** a),
    "HN": lambda w, r, t, a, b: r / (1 + (1j * w * t) ** a) ** b,
}
SMALL_PARAMETERS = {"R": (250.0,), "C": (3e-5,), "W": (40.0,), "CC": (80.0, 2e-3, 0.8)}


@pytest.mark.parametrize("large", [s.symbol for s in DEFAULT_REGISTRY if s.limits])
def test_each_limit_gives_the_simpler_elements_impedance_over_the_window(large):
    """A Wo at the carried (R, τ) is the W it stands for, and so on for every declared limit:
    within 1e-6 of the simpler element's impedance from 10 mHz to 1 MHz."""
    omega = 2 * np.pi * np.geomspace(1e-2, 1e6, 60)
    for limit in DEFAULT_REGISTRY[large].limits:
        small = SMALL_PARAMETERS[limit.symbol]
        carried = limit.values(small, float(omega.min()), float(omega.max()))
        assert len(carried) == len(DEFAULT_REGISTRY[large].parameters)
        z_small, z_large = NUMPY_Z[limit.symbol](omega, *small), NUMPY_Z[large](omega, *carried)
        assert np.max(np.abs(z_large / z_small - 1)) < 1e-6, (large, limit.where)


def test_limits_take_one_value_per_spectrum():
    """The carried values of a batch: arrays in, arrays out, each spectrum's own."""
    sigma = np.array([10.0, 40.0, 90.0])
    r, tau = DEFAULT_REGISTRY["Wo"].limits[0].values((sigma,), 0.05, 1e5)
    assert np.shape(r) == np.shape(tau) == (3,)
    np.testing.assert_allclose(r / np.sqrt(2 * tau), sigma)


def test_embedding_finds_which_element_stands_for_which():
    P = ix.parse
    pairs = embedding(P("R0 + R1 || C1 + W1"), P("R0 + R1 || CPE1 + Wo1"))
    assert [(a.name, b.name, None if lim is None else lim.symbol) for a, b, lim in pairs] == [("R0", "R0", None), ("R1", "R1", None), ("C1", "CPE1", "C"), ("W1", "Wo1", "W")]
    assert embedding(P("R0 + Wo1"), P("R0 + W1")) is None  # (a W does not contain a Wo)
    assert embedding(P("R0 + W1"), P("R0 + R1")) is None
    assert embedding(P("R1 || Q1"), P("CPE2 || (R2 + W2)")) is not None  # (an alias, another order, an element more)
    assert is_nested(P("CC1"), P("HN1")) and is_nested(P("R0 + R1"), P("R0 + Ws1")) and not is_nested(P("R0 + Ws1"), P("R0 + R1"))


def test_carried_values_reproduce_the_smaller_circuit_and_fall_back_to_names():
    """R0 + W1 carried into R0 + Wo1 over 0.1 Hz–10 kHz: the same impedance (a numpy formula of
    each); a circuit not nested keeps the parameters the two share by name."""
    f = np.geomspace(0.1, 1e4, 30)
    w = 2 * np.pi * f
    values = carried_values(ix.parse("R0 + W1"), {"R0": 12.0, "W1.sigma": 55.0}, ix.parse("R0 + Wo1"), float(w.min()), float(w.max()))
    np.testing.assert_allclose(12.0 + NUMPY_Z["Wo"](w, values["Wo1.R"], values["Wo1.tau"]), 12.0 + NUMPY_Z["W"](w, 55.0), rtol=1e-7)
    assert carried_values(ix.parse("R0 + W1"), {"R0": 12.0, "W1.sigma": 55.0}, ix.parse("R0 + R1"), 1.0, 10.0) == {"R0": 12.0}


def test_a_user_element_declares_its_limit_and_a_bad_one_is_refused():
    """A user's element joins nesting through its spec: a 'resistor with a series inductance'
    contains R at L = 0."""
    spec = ElementSpec(
        "RL", "resistor with inductance", "Z = R + jωL",
        (ParameterSpec("R", "Ohm", 10.0, lower=0.0), ParameterSpec("L", "H", 1e-6, lower=0.0)),
        lambda w, r, l: r + 1j * w * l,
        limits=(ElementLimit("R", "L -> 0", lambda p, lo, hi: (p[0], 1e-12 / hi)),),
    )
    registry = DEFAULT_REGISTRY.register(spec)
    assert is_nested(ix.parse("R0 + R1", registry), ix.parse("R0 + RL1", registry), registry)
    with pytest.raises(CircuitError, match="limits must be a tuple of ElementLimit"):
        ElementSpec("RX", "x", "Z = R", (ParameterSpec("R", "Ohm", 1.0, lower=0.0),), lambda w, r: r + 0 * w, limits=("R",))
    with pytest.raises(CircuitError, match="values must be a function"):
        ElementLimit("R", "x", 3.0)


def _two_arcs_and_warburg(f, r0, r1, q1, a1, r2, q2, a2, sigma):
    w = 2 * np.pi * f
    arc = lambda r, q, a: r / (1 + r * q * (1j * w) ** a)  # noqa: E731
    return r0 + arc(r1, q1, a1) + arc(r2, q2, a2) + sigma * (1 - 1j) / np.sqrt(w)


def test_a_single_fit_started_from_a_nested_fit_ends_no_higher():
    """SYNTHETIC: two R ∥ CPE arcs and a semi-infinite Warburg (a numpy formula), 0.5 % noise.
    The Wo model started from the W model's fit (``init=``) ends at or below its χ² (a Wo at
    τ → ∞ is that W), whatever its own search finds."""
    f = np.geomspace(0.02, 2e4, 50)
    rng = np.random.default_rng(11)
    z = _two_arcs_and_warburg(f, 0.05, 0.02, 2.0, 0.8, 0.03, 40.0, 0.7, 0.01)
    data = ix.make_spectrum(f, z * (1 + 0.005 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)))
    w_fit = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + W1", data)
    wo_fit = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + Wo1", data, init=w_fit)
    assert wo_fit.chi2 <= w_fit.chi2 * (1 + 1e-6)
    assert not [t for t in ix.compare([w_fit, wo_fit]).f_tests if t["reason"] == "not_at_optimum"]


@pytest.fixture(scope="module")
def cycles_40_to_59():
    """20 REAL cycles of AutoEIS's battery set (MIT; benchmarks/data/LICENSE-autoeis.txt), the
    run where the Wo model's default batch fits stopped above the W model's χ² on 12 before
    each spectrum was also solved from its W limit (2026-12-02)."""
    from pathlib import Path

    return ix.load(Path(__file__).parents[1] / "benchmarks" / "data" / "autoeis_battery_130.nc").isel(cycle=slice(40, 60))


def test_a_batch_reaches_the_optimum_of_the_model_its_circuit_contains(cycles_40_to_59):
    """By default (each spectrum also solved from its optimum moved to the Wo's W limit) and from
    the W batch (``init=``): no Wo fit ends above its W fit; one local fit each (``n_starts=1``)
    does, and the comparison counts those spectra as counted here."""
    data = cycles_40_to_59
    w_fits = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + W1", data, progress=False)
    default = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + Wo1", data, progress=False)
    started = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + Wo1", data, init=w_fits, progress=False)
    local = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + Wo1", data, n_starts=1, progress=False)
    chi2_w, chi2_default, chi2_started, chi2_local = (b.dataset["chi2"].values for b in (w_fits, default, started, local))
    assert np.all(chi2_default <= chi2_w * (1 + 1e-6)) and np.all(chi2_started <= chi2_w * (1 + 1e-6))
    assert np.all(chi2_started <= chi2_default * (1 + 1e-6))  # (each spectrum solved from both: no optimum lost)
    worse = chi2_local - chi2_w > 1e-6 * chi2_w
    assert worse.sum() >= 5  # (what the comparison is to find)
    pairs = ix.compare([w_fits, local]).not_at_optimum()
    assert [(p["complex"], p["simple"], p["spectra"]) for p in pairs] == [(local.model, w_fits.model, int(worse.sum()))]
    assert pairs[0]["worst_chi2_ratio"] == pytest.approx(float(np.max(chi2_local[worse] / chi2_w[worse])))
    assert ix.compare([w_fits, default]).not_at_optimum() == [] and pairs[0]["note"] in ix.compare([w_fits, local]).report()


def test_compare_command_fits_the_contained_model_first_and_starts_the_larger_there(tmp_path, capsys):
    """``impedax compare`` with the larger model given first: the W model is fitted first and the
    Wo model also started from its optimum (the JSON's ``started_from_contained``); no cycle's
    Wo χ² ends above its W χ² (3 REAL cycles of examples/data)."""
    from pathlib import Path

    from impedax.cli import main

    path = Path(__file__).parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc"
    wo, w = "R0 + R1 || CPE1 + R2 || CPE2 + Wo1", "R0 + R1 || CPE1 + R2 || CPE2 + W1"
    assert main(["compare", str(path), "--model", wo, "--model", w, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["started_from_contained"] == [{"model": wo, "from": w}]
    assert out["not_at_optimum"] == []
    for spectrum in out["spectra"]:
        chi2 = {m["model"]: m["chi2"] for m in spectrum["models"]}
        assert chi2[wo] <= chi2[w] * (1 + 1e-6)


def test_an_element_added_before_the_others_leaves_their_values_where_their_names_are():
    """A refit with an element inserted (a diagnosis's candidate) carries each value to the
    element of its name, not to the first element of its kind."""
    values = carried_values(ix.parse("R0 + R1 || C1"), {"R0": 5.0, "R1": 100.0, "C1": 1e-6}, ix.parse("R0 + R2 || C2 + R1 || C1"), 1.0, 1e5)
    assert values == {"R0": 5.0, "R1": 100.0, "C1": 1e-6}


def test_carried_values_past_the_larger_models_bounds_are_moved_inside_not_refused():
    """A W fit starting a Wo model whose τ the user bounded to 0.1–10 s: the carried
    τ = 200/ω_min lies past it and is moved inside (a user's own init there is refused)."""
    from impedax.errors import ParameterError
    from impedax.fitting.parameters import ParameterTable
    from types import SimpleNamespace

    w_fit = SimpleNamespace(circuit=ix.parse("R0 + W1"), values={"R0": 5.0, "W1.sigma": 20.0}, frequency=np.geomspace(0.01, 1e4, 20))
    table = ParameterTable.build(ix.parse("R0 + Wo1"), init=w_fit, bounds={"Wo1.tau": (0.1, 10.0)})
    tau = table.values[table.names.index("Wo1.tau")]
    assert 9.99 < tau < 10.0 and table.values[table.names.index("R0")] == 5.0
    with pytest.raises(ParameterError, match="outside its bounds"):
        ParameterTable.build(ix.parse("R0 + Wo1"), init={"Wo1.tau": 1e4}, bounds={"Wo1.tau": (0.1, 10.0)})


@pytest.mark.parametrize("large", ["Wo", "Ws", "G"])
def test_toward_moves_an_element_into_its_warburg_limit_keeping_its_high_frequency_coefficient(large):
    """A fitted (R, τ) = (30 Ω, 0.4 s) moved toward its W limit is the W of σ = R/√(2τ), the
    element's impedance R/√(jωτ) at ωτ ≫ 1 (numpy formulas)."""
    omega = 2 * np.pi * np.geomspace(0.01, 1e4, 40)
    limit = next(lim for lim in DEFAULT_REGISTRY[large].limits if lim.symbol == "W")
    r, tau = limit.toward((np.array([30.0]), np.array([0.4])), float(omega.min()), float(omega.max()))
    z = NUMPY_Z[large](omega, float(r[0]), float(tau[0]))
    assert np.max(np.abs(z / NUMPY_Z["W"](omega, 30.0 / np.sqrt(0.8)) - 1)) < 1e-6
    with pytest.raises(CircuitError, match="toward must be None or a function"):
        ElementLimit("W", "tau -> inf", limit.values, toward=1.0)
    # at the window's edge: the same coefficient, the knee at ω_min·τ = 3
    r_edge, tau_edge = limit.edge((np.array([30.0]), np.array([0.4])), float(omega.min()), float(omega.max()))
    assert tau_edge[0] == pytest.approx(3.0 / omega.min()) and r_edge[0] / np.sqrt(2 * tau_edge[0]) == pytest.approx(30.0 / np.sqrt(0.8))


def test_compare_of_one_spectrum_keeps_the_larger_models_own_search_where_it_ends_lower(capsys):
    """REAL battery cycle 69: the Wo model started from the W fit sits at its W limit, while its
    own search reaches a χ² 1 % lower; ``impedax compare`` keeps that lower fit (a walkthrough
    was told the Wo fit 'did not reach its optimum' and to do what compare had done)."""
    from pathlib import Path

    from impedax.cli import main

    path = Path(__file__).parents[1] / "benchmarks" / "data" / "autoeis_battery_130.nc"
    wo, w = "R0 + R1 || CPE1 + R2 || CPE2 + Wo1", "R0 + R1 || CPE1 + R2 || CPE2 + W1"
    assert main(["compare", str(path), "--select", "cycle=69", "--model", w, "--model", wo, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    chi2 = {m["model"]: m["chi2"] for m in out["models"]}
    own = ix.fit(wo, ix.load(path).sel(cycle=69), progress=False)
    assert chi2[wo] <= own.chi2 * (1 + 1e-6) and chi2[wo] < chi2[w]
    assert all(t["reason"] != "not_at_optimum" for t in out["f_tests"])


@pytest.mark.parametrize("value, lower, upper, moved", [
    (0.0, 0.0, math.inf, 1e-300),  # R0 of a smaller model at 0: (0, ∞) is fitted in log space
    (-3.0, 0.0, math.inf, 1e-300),
    (1.0, 0.0, 1.0, 1 - 1e-6),  # an exponent at 1 where the larger model's bound excludes it
    (2.0, 0.5, 1.0, 1 - 1e-6),
    (0.5, 0.5, 1.0, 0.5 * (1 + 1e-6)),
    (-1.0, -1.0, 1.0, -1 + 2e-6),  # 1e-6 of the span
    (-5.0, -1.0, math.inf, -1 + 1e-6),  # (NaN before: no move was defined)
    (0.0, -2.0, 0.0, -1e-6),
    (math.nan, 0.0, 1.0, math.nan),
])
def test_a_carried_value_on_or_past_a_bound_moves_just_inside(value, lower, upper, moved):
    """`parameters.nudged_inside`, the single-value form of the batch's `inner_edges`: a fitted
    value carried to a larger model lands 1e-6 inside the bound it sits on or beyond (hand-derived
    points)."""
    from impedax.fitting.parameters import nudged_inside

    got = nudged_inside(value, lower, upper)
    assert (math.isnan(got) and math.isnan(moved)) or got == pytest.approx(moved, rel=1e-12, abs=1e-310)
