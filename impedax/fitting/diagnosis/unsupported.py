"""Terms of a fitted circuit the data do not support, though the fit did not make them vanish:
an arc whose relaxation lies outside the band (the data see one flank of it, so one of its
elements is an extrapolation, `arcs.ArcBeyondBand`) and a term holding a parameter the data do
not determine (`diagnosis.undetermined_parameters`). `refinement._pruned` fits the model
without each and keeps it when its AIC is not higher: the data then say nothing for the term.
(A term the fit ran to a natural bound, a resistor open or a series R at 0, is `vanishing`'s.)"""

from __future__ import annotations

from dataclasses import dataclass

from ...circuits import Circuit, Element, Parallel
from ...errors import CircuitError
from ..arcs import arcs_beyond_band
from ..least_squares import FitResult
from .diagnosis import undetermined_parameters

__all__ = ["UnsupportedTerm", "unsupported_terms"]


@dataclass(frozen=True)
class UnsupportedTerm:
    """A simpler circuit than a fit's: ``reduced``, without the elements ``removed``, and
    ``why`` the data do not support them (words that a note goes on from with ": …")."""

    removed: tuple[str, ...]
    reduced: Circuit
    why: str


def _enclosing_block(node: Circuit, name: str) -> Parallel | None:
    """The innermost parallel block of ``node`` that holds element ``name`` (None if none does)."""
    if isinstance(node, Element):
        return None
    for child in node.children:
        if name in child.element_names:
            inner = _enclosing_block(child, name)
            return inner if inner is not None else (node if isinstance(node, Parallel) else None)
    return None


def _without_all(circuit: Circuit, names) -> Circuit:
    """``circuit`` without each of the elements ``names`` (`Circuit.without`: out of a parallel
    block the branch opens, out of a series chain it is shorted); CircuitError when nothing
    would be left."""
    for name in names:
        circuit = circuit.without(name)
    return circuit


def unsupported_terms(fit: FitResult) -> list[UnsupportedTerm]:
    """The simpler circuits `refinement._pruned` tries in place of ``fit``'s, one per term the
    data do not support, each once:

    - an arc (R ∥ C or R ∥ CPE) relaxing outside the band by more than
      `arcs.BEYOND_BAND_FACTOR`: the circuit without its extrapolated element (below the
      band the resistor opens and the arc is its capacitance; above it the capacitance opens
      and the arc is its resistor). On exampleData.csv (REAL) refine ended with R_relax ∥
      CPE_relax relaxing at 8.75 µHz, 360× below the band, R_relax = 806 mΩ ± 89 %; with CPE_relax
      alone the AIC is lower by 0.7, with one parameter fewer;
    - an element holding a parameter the data do not determine, free in the fit: the circuit
      without the element, and without the whole parallel block around it (a redundant arc:
      R0 + R1 ∥ C1 + R2 ∥ C2 on one arc's data leaves R1 undetermined, and only without both
      R1 and C1 is it R0 + R2 ∥ C2)."""
    registry = fit.registry
    out: list[UnsupportedTerm] = []
    seen: set[str] = set()

    def add(removed: tuple[str, ...], why: str) -> None:
        try:
            reduced = _without_all(fit.circuit, removed)
        except CircuitError:  # (the term is the whole circuit)
            return
        if str(reduced) not in seen:
            seen.add(str(reduced))
            out.append(UnsupportedTerm(removed, reduced, why))

    for arc in arcs_beyond_band(fit.circuit, fit.values, registry, fit.frequency):
        if all(fit.fixed.get(n, False) for n in fit.circuit.element(arc.extrapolated).parameter_names(registry)):
            continue
        add((arc.extrapolated,), f"{arc.elements} relaxes outside the band ({arc.sentence()})")
    undetermined = undetermined_parameters(fit)
    for element in fit.circuit.elements():
        held = [n for n in element.parameter_names(registry) if n in undetermined]
        if not held:
            continue
        words = f"the data do not determine {', '.join(held)}"
        add((element.name,), words)
        block = _enclosing_block(fit.circuit, element.name)
        if block is not None and len(block.element_names) < len(fit.circuit.element_names):
            add(block.element_names, f"{words} (in {block})")
    return out
