"""A pile-up toward a short names the circuit without that element (2026-12-07).

On REAL exampleDataBioLogic.mpt with R0 + R1 || CPE1 + W1, W1.sigma's draws piled up at the
lower end of its prior and the warning asked only for a prior that says how small it can be:
as σ → 0 the series W1 is a short, and the model without it, R0 + R1 || CPE1, is the one to try.
Where shorting the element is a removal (a term of a series chain: `Circuit.without`) the warning
now names that circuit, read back and compiled; where the element is a branch of a parallel
block (shorting it shorts the block) it says nothing new.

Oracles: the elements' closed forms (Z_W = σ(1 − j)/√ω → 0 as σ → 0, Z_C = 1/(jωC) → 0 as
C → ∞, the CPE at α = 0 the resistor 1/Q), the tree's shape, and a SYNTHETIC spectrum made with
numpy from R0 + R1/(1 + R1 Q (jω)^α), which has no W.
"""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix
from impedax.circuits import DEFAULT_REGISTRY, compile_circuit
from impedax.fitting.bayes.diagnostics import prior_edges, short_advice
from impedax.fitting.bayes.priors import Prior
from impedax.fitting.reductions import series_shorts

F = np.geomspace(0.01, 1e5, 40)


def _shorts(model: str) -> dict[str, tuple[str, str, str]]:
    circuit = ix.parse(model)
    return {n: (side, element, str(reduced)) for n, (side, element, reduced) in series_shorts(circuit, DEFAULT_REGISTRY, circuit.defaults(DEFAULT_REGISTRY), F).items()}


def test_a_series_term_shorts_at_the_bound_its_closed_form_says():
    shorts = _shorts("R0 + R1 || CPE1 + W1")
    assert shorts == {"R0": ("lower", "R0", "R1 || CPE1 + W1"), "W1.sigma": ("lower", "W1", "R0 + R1 || CPE1")}  # (R1, CPE1: parallel branches)
    shorts = _shorts("R0 + C1 + CPE2")
    assert shorts["C1"] == ("upper", "C1", "R0 + CPE2") and shorts["CPE2.Q"] == ("upper", "CPE2", "R0 + C1")
    assert "CPE2.alpha" not in shorts  # (α → 0 leaves the resistor 1/Q, α → 1 a capacitor: no short)
    # a term of a series chain inside a parallel branch: shorting it removes it from that chain
    assert _shorts("R0 + R1 || (CPE1 + W1)")["W1.sigma"] == ("lower", "W1", "R0 + R1 || CPE1")


def test_a_parallel_branch_is_no_removal():
    assert "W1.sigma" not in _shorts("R0 + R1 || W1") and _shorts("W1") == {}


def test_the_circuit_named_reads_back_and_compiles():
    (_, words), = [v for n, v in short_advice(ix.parse("R0 + R1 || CPE1 + W1"), DEFAULT_REGISTRY, {"R0": 60.0, "R1": 50.0, "CPE1.Q": 0.01, "CPE1.alpha": 0.9, "W1.sigma": 1e-3}, F).items() if n == "W1.sigma"]
    text = words.rsplit("try the model without it, ", 1)[1]
    assert text == "R0 + R1 || CPE1" and str(ix.parse(text)) == text and compile_circuit(text).parameter_names == ("R0", "R1", "CPE1.Q", "CPE1.alpha")


def _piled_low(n: int = 4000) -> np.ndarray:
    """Draws of a log-uniform prior on [1e-4, 1e2] piled up against 1e-4: in its coordinate
    t = log(x/1e-4)/log(1e6), half a normal of sd 0.15 from t = 0 (densest at the edge, none near 1)."""
    t = np.abs(np.random.default_rng(0).normal(0.0, 0.15, n))
    return (1e-4 * 1e6 ** t[t < 1])[:, None]


def test_the_pile_up_warning_appends_the_advice_only_on_its_side():
    prior = {"W1.sigma": Prior("loguniform", 1e-4, 1e2)}
    plain = prior_edges(("W1.sigma",), ("Ohm s^-1/2",), _piled_low(), prior, (0.0,), (np.inf,)).warnings
    advice = "W1 tends to a short as W1.sigma → 0 (its impedance vanishes), so the data may need no W1: try the model without it, R0 + R1 || CPE1"
    (warning,) = prior_edges(("W1.sigma",), ("Ohm s^-1/2",), _piled_low(), prior, (0.0,), (np.inf,), shorts={"W1.sigma": ("lower", advice)}).warnings
    assert warning == f"{plain[0]}; {advice}"
    (other_side,) = prior_edges(("W1.sigma",), ("Ohm s^-1/2",), _piled_low(), prior, (0.0,), (np.inf,), shorts={"W1.sigma": ("upper", advice)}).warnings
    assert other_side == plain[0]


@pytest.mark.slow  # (a sampler run: ~30 s on the shared 2-core machine)
def test_a_series_warburg_the_data_lack_is_named_as_removable():
    """SYNTHETIC R0 + R1 ∥ CPE1 (60 Ω, 50 Ω, Q = 0.01, α = 0.9; 1 % noise) sampled with
    R0 + R1 ∥ CPE1 + W1: W1.sigma piles up at its prior's lower end, and the warning names
    R0 + R1 || CPE1, the circuit the data were made from."""
    rng = np.random.default_rng(3)
    omega = 2 * np.pi * F
    z = 60.0 + 50.0 / (1 + 50.0 * 0.01 * (1j * omega) ** 0.9)
    z = z * (1 + 0.01 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2))
    post = ix.sample("R0 + R1 || CPE1 + W1", ix.make_spectrum(F, z), steps=800, walkers=24, seed=0, progress=False)
    assert post.piled_up == {"W1.sigma": "lower"}
    (warning,) = [w for w in post.warnings if w.startswith("W1.sigma piles up")]
    assert warning.endswith("; W1 tends to a short as W1.sigma → 0 (its impedance vanishes), so the data may need no W1: try the model without it, R0 + R1 || CPE1")
    assert "the data allow smaller values — give W1.sigma a prior that says how small it can be" in warning  # (the prior's advice kept)


def test_at_the_elements_own_bound_the_advice_takes_the_place_of_a_missing_something():
    """A uniform prior down to W1.sigma's own bound 0, the draws piled up against it: the warning
    asked "is the model missing something?", where the data say W1 may be a short."""
    x = np.abs(np.random.default_rng(1).normal(0.0, 15.0, 4000))
    draws, prior = x[x < 100][:, None], {"W1.sigma": Prior("uniform", 0.0, 100.0)}
    (plain,) = prior_edges(("W1.sigma",), ("Ohm s^-1/2",), draws, prior, (0.0,), (np.inf,)).warnings
    assert plain.endswith("the data would take smaller values (is the model missing something?)")
    (warning,) = prior_edges(("W1.sigma",), ("Ohm s^-1/2",), draws, prior, (0.0,), (np.inf,), shorts={"W1.sigma": ("lower", "ADVICE")}).warnings
    assert warning == plain.replace(" (is the model missing something?)", "; ADVICE")
