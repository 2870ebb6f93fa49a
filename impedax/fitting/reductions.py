"""Bounds at which an element is a simpler one: a CPE whose α is at its upper bound 1 is an
ideal capacitor, Z = 1/(Q (jω)^α) = 1/(jωQ) (docs/physics.md, the CPE). The fits' bound notes,
the sampler's prior-edge warnings and `refine`'s swap of a CPE for a C name that simpler model
alike."""

from __future__ import annotations

from ..circuits import Circuit, Registry

__all__ = ["capacitor_name", "reducing_bounds"]


def capacitor_name(name: str, taken) -> str:
    """A C's name for the CPE ``name`` it replaces: CPE1 → C1, CPE_relax → C_relax (C_relax2, ...
    when taken), as `effects` names a CPE for the C it replaces."""
    label = name[4:] if name.startswith("CPE_") else name[3:] if name.startswith("CPE") else name[2:] if name.startswith("Q_") else name[1:] if name.startswith("Q") else name
    if label.isdigit() or not label:
        k = int(label) if label else 1
        while f"C{k}" in taken:
            k += 1
        return f"C{k}"
    candidate, k = f"C_{label}", 2
    while candidate in taken:
        candidate, k = f"C_{label}{k}", k + 1
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
