"""Bounds at which an element is a simpler one: a CPE whose α is at its upper bound 1 is an
ideal capacitor, Z = 1/(Q (jω)^α) = 1/(jωQ) (docs/physics.md, the CPE). The fits' bound notes,
the sampler's prior-edge warnings and `refine`'s swap of a CPE for a C name that simpler model
alike. Toward its lower bound 0 a CPE tends to a resistor, Z = 1/Q at α = 0: the fits' notes say
so below `RESISTOR_LIKE_ALPHA` (`resistor_like_exponents`)."""

from __future__ import annotations

import math
from typing import Mapping

import numpy as np

from ..circuits import Circuit, Element, Registry, Series, compile_circuit, parse
from ..errors import CircuitError

__all__ = ["capacitor_name", "replacement_name", "reducing_bounds", "resistor_like_exponents", "RESISTOR_LIKE_ALPHA", "warburg_deviation", "warburg_like_elements", "WARBURG_LIKE_DEVIATION", "series_shorts", "SHORT_STEP", "SHORT_SHARE"]


def capacitor_name(name: str, taken) -> str:
    """A C's name for the CPE ``name`` it replaces: CPE1 → C1, CPE_relax → C_relax (C_relax2, ...
    when taken), as `effects` names a CPE for the C it replaces."""
    return replacement_name(name, "C", taken)


def replacement_name(name: str, symbol: str, taken, own: str = "CPE") -> str:
    """The name of a ``symbol`` element (C, R, W) put in the place of the ``own`` element ``name``
    (a CPE by default): CPE1 → C1, CPE_relax → C_relax, G1 → W1, Wo_d → W_d; the next number
    (C_relax2, ...; R3 for CPE2 beside R2) when taken."""
    if own == "CPE":
        label = name[4:] if name.startswith("CPE_") else name[3:] if name.startswith("CPE") else name[2:] if name.startswith("Q_") else name[1:] if name.startswith("Q") else name
    else:
        label = name[len(own) + 1:] if name.startswith(own + "_") else name[len(own):] if name.startswith(own) else name
    if label.isdigit() or not label:
        k = int(label) if label else 1
        while f"{symbol}{k}" in taken:
            k += 1
        return f"{symbol}{k}"
    candidate, k = f"{symbol}_{label}", 2
    while candidate in taken:
        candidate, k = f"{symbol}_{label}{k}", k + 1
    return candidate


def reducing_bounds(circuit: Circuit, registry: Registry) -> dict[str, tuple[str, str]]:
    """{parameter: (side, words)} of ``circuit``'s parameters whose bound on that side is the
    value at which their element is a simpler one: a CPE's alpha at its upper bound 1 is an
    ideal capacitor C = Q, named as `refine` names the C it puts in the CPE's place
    (`capacitor_name`)."""
    out = {}
    for e in circuit.elements():
        if registry[e.symbol].symbol != "CPE":
            continue
        _, alpha = registry[e.symbol].parameter_names(e.name)
        out[alpha] = ("upper", f"{e.name} with alpha = 1 is a capacitor: the model with {capacitor_name(e.name, circuit.element_names)} in its place may be enough")
    return out


RESISTOR_LIKE_ALPHA = 0.2
"""A CPE acts nearly as a resistor when its exponent is below this: Z = (jω)^−α/Q has the phase
−απ/2, within 18° of a resistor's 0 at α = 0.2, and a modulus 1/(Q ω^α) that changes by only
10^α = 1.58× per decade of frequency (at α = 0 it is the resistor 1/Q). The values a CPE's
physics gives lie well above: 0.5 for semi-infinite diffusion (the Warburg element), 0.7–1 for
rough or porous double layers (Orazem & Tribollet 2008, Electrochemical Impedance Spectroscopy,
§13.2). On AutoEIS's real battery cycle 64, ``R0 + R1 || CPE1 + CPE2 || (R2 + Wo1)`` ends at
CPE2.alpha = 0.031 with R2 → 0, and impedance.py's real example data with ``R0 + R1 || CPE1`` at
α = 0.15 with R1 = 2.4 kΩ on a spectrum of |Z| ≈ 0.05 Ω; ``R0 + R1 || CPE1`` and ``R0 + R1 ||
CPE1 + W1`` on the other real files in tests/fixtures/real fit at α = 0.42–1."""


def resistor_like_exponents(circuit: Circuit, registry: Registry) -> dict[str, tuple[str, str, str | None]]:
    """{alpha: (CPE name, Q parameter, name of the R that would take its place)} of ``circuit``'s
    CPEs, the R's name as `replacement_name` gives it (R3 for CPE2 beside R2), None when
    ``registry`` has no resistor R: what a fit's note says when α ends below
    `RESISTOR_LIKE_ALPHA` (`least_squares.result.resistor_like_notes`)."""
    has_resistor = "R" in registry and registry["R"].symbol == "R"
    out = {}
    for e in circuit.elements():
        if registry[e.symbol].symbol != "CPE":
            continue
        q, alpha = registry[e.symbol].parameter_names(e.name)
        out[alpha] = (e.name, q, replacement_name(e.name, "R", circuit.element_names) if has_resistor else None)
    return out


WARBURG_LIKE_DEVIATION = 1e-3
"""The largest relative difference over the band between a finite Warburg (Wo, Ws) or a Gerischer
and the semi-infinite Warburg R/√(jωτ) = σ(1 − j)/√ω (σ = R/√(2τ)) it tends to as τ → ∞, under
which it is said to act as that W (`warburg_deviation`): 0.1 %, below the noise of most
measurements. On AutoEIS's REAL battery cycle 64 the G model's optimum has G1.tau = 8.6e8 s,
4e-9 off (2026-12-04)."""


def warburg_deviation(symbol: str, omega_tau):
    """|Z/Z_W − 1| of a Wo, Ws or G at ω·τ = ``omega_tau`` (largest at the band's lowest ω):
    G: (1 + 1/(jωτ))^(−1/2) − 1; Wo: coth(x) − 1; Ws: tanh(x) − 1, x = √(jωτ). NaN for other
    symbols (an element of the user's with a W limit: no closed form here)."""
    y = np.asarray(omega_tau, float)
    x = np.sqrt(1j * y)
    with np.errstate(all="ignore"):
        if symbol == "G":
            return np.abs((1 + 1 / (1j * y)) ** -0.5 - 1)
        if symbol == "Wo":
            return np.abs(1 / np.tanh(x) - 1)
        if symbol == "Ws":
            return np.abs(np.tanh(x) - 1)
    return np.full(y.shape, np.nan)


def warburg_like_elements(circuit: Circuit, registry: Registry) -> dict[str, tuple[str, str, str, str, str]]:
    """{tau: (element, R parameter, name of the W that would take its place, σ's unit, element
    symbol)} of ``circuit``'s Wo, Ws and G, which reduce to a semi-infinite Warburg W as τ → ∞,
    the W named as `replacement_name` names it (G1 → W1); {} when ``registry`` has no W: what a
    fit's note says when the element is within `WARBURG_LIKE_DEVIATION` of that W over the band
    (`least_squares.result.warburg_like_notes`)."""
    if "W" not in registry or registry["W"].symbol != "W":
        return {}
    sigma_unit = registry["W"].parameters[0].unit
    out = {}
    for e in circuit.elements():
        spec = registry[e.symbol]
        names = spec.parameter_names(e.name)
        if spec.symbol in ("Wo", "Ws", "G") and len(names) == 2:
            out[names[1]] = (e.name, names[0], replacement_name(e.name, "W", circuit.element_names, own=spec.symbol), sigma_unit, spec.symbol)
    return out


SHORT_STEP = 1e12
SHORT_SHARE = 1e-6
"""`series_shorts` takes a parameter whose bound is 0 (∞) to its value ÷ (×) `SHORT_STEP`, and
calls the element a short there when its |Z| falls below `SHORT_SHARE` of its |Z| at the value
at every frequency: an impedance proportional to the parameter (a W's σ, an R, an L) or to its
inverse (a C, a CPE's Q) falls by 1e12, one that tends to a finite value (a CPE's α → 0: the
resistor 1/Q) or grows does not."""


def _in_series(node: Circuit, name: str) -> bool:
    """Whether element ``name`` of ``node`` is one term of a series chain (its parent a `Series`),
    not a branch of a parallel block, nor the whole circuit."""
    if isinstance(node, Element):
        return False
    for child in node.children:
        if isinstance(child, Element) and child.name == name:
            return isinstance(node, Series)
        if not isinstance(child, Element) and name in child.element_names:
            return _in_series(child, name)
    return False


def _toward(value: float, bound: float) -> float | None:
    """The parameter's value taken toward its ``bound`` (`SHORT_STEP`), the bound itself when finite
    and not 0; None where no such value is defined (a value not positive beside a bound 0 or ∞)."""
    if bound == 0 or math.isinf(bound):
        if not value > 0 or not math.isfinite(value) or bound < 0:
            return None
        return value / SHORT_STEP if bound == 0 else value * SHORT_STEP
    return bound


def series_shorts(circuit: Circuit, registry: Registry, values: Mapping[str, float], freq) -> dict[str, tuple[str, str, Circuit]]:
    """{parameter: (side, element, circuit without it)} of ``circuit``'s parameters whose element
    is one term of a series chain and becomes a short (Z → 0) as the parameter runs to its bound
    on ``side`` ("lower", "upper"), the element's other parameters at ``values`` (a W's σ → 0, an
    R or an L → 0, a C or a CPE's Q → ∞; `SHORT_SHARE` at every frequency ``freq`` [Hz]): there
    the circuit is the one without that element (`Circuit.without`, which shorts a series term).
    An element that is a branch of a parallel block is left out (shorted, it shorts the whole
    block, which is no removal), as are elements whose parameters lack a value, and a circuit
    without the element that does not read back and compile (`parse`, `compile_circuit`)."""
    omega = 2 * np.pi * np.asarray(freq, float).ravel()
    specs = circuit.parameter_specs(registry)
    out: dict[str, tuple[str, str, Circuit]] = {}
    if omega.size == 0:
        return out
    for e in circuit.elements():
        spec = registry[e.symbol]
        names = spec.parameter_names(e.name)
        if not _in_series(circuit, e.name) or not all(n in values and math.isfinite(values[n]) for n in names):
            continue
        point = [float(values[n]) for n in names]
        with np.errstate(all="ignore"):
            z = np.abs(np.asarray(spec.impedance(omega, *point), complex))
        if not np.all(np.isfinite(z) & (z > 0)):
            continue
        for k, n in enumerate(names):
            for side, bound in (("lower", specs[n].lower), ("upper", specs[n].upper)):
                limit = _toward(point[k], float(bound))
                if limit is None:
                    continue
                with np.errstate(all="ignore"):
                    z_limit = np.abs(np.asarray(spec.impedance(omega, *point[:k], limit, *point[k + 1:]), complex))
                if not np.all(z_limit <= SHORT_SHARE * z):  # (NaN: not a short)
                    continue
                try:
                    reduced = circuit.without(e.name)
                    if parse(str(reduced), registry) != reduced:
                        continue
                    compile_circuit(reduced, registry)
                except CircuitError:
                    continue
                out[n] = (side, e.name, reduced)
    return out
