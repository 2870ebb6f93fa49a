"""Bounds at which an element is a simpler one: a CPE whose α is at its upper bound 1 is an
ideal capacitor, Z = 1/(Q (jω)^α) = 1/(jωQ) (docs/physics.md, the CPE). The fits' bound notes,
the sampler's prior-edge warnings and `refine`'s swap of a CPE for a C name that simpler model
alike. Toward its lower bound 0 a CPE tends to a resistor, Z = 1/Q at α = 0: the fits' notes say
so below `RESISTOR_LIKE_ALPHA` (`resistor_like_exponents`)."""

from __future__ import annotations

from ..circuits import Circuit, Registry

__all__ = ["capacitor_name", "replacement_name", "reducing_bounds", "resistor_like_exponents", "RESISTOR_LIKE_ALPHA"]


def capacitor_name(name: str, taken) -> str:
    """A C's name for the CPE ``name`` it replaces: CPE1 → C1, CPE_relax → C_relax (C_relax2, ...
    when taken), as `effects` names a CPE for the C it replaces."""
    return replacement_name(name, "C", taken)


def replacement_name(name: str, symbol: str, taken) -> str:
    """The name of a ``symbol`` element (C, R) put in the place of the CPE ``name``: CPE1 → C1,
    CPE_relax → C_relax; the next number (C_relax2, ...; R3 for CPE2 beside R2) when taken."""
    label = name[4:] if name.startswith("CPE_") else name[3:] if name.startswith("CPE") else name[2:] if name.startswith("Q_") else name[1:] if name.startswith("Q") else name
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
