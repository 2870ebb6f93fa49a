"""Terms of a fitted circuit that vanished: a resistor run open beside a capacitor, a series
resistor run to 0 — the fit's own flags say the term is not there, and the model without it is
the same fit within what any instrument resolves. `refinement._pruned` takes them out of
its final model; the diagnosis report names the simpler model beside its "to apply" line."""

from __future__ import annotations

import numpy as np

from ...circuits import Circuit, parse
from ...errors import CircuitError, ParameterError
from ..least_squares import FitResult
from ..least_squares.branches import VANISHING_SHARE, IdleBranch, idle_branches
from ..parameters import ParameterTable

__all__ = ["flagged_parameters", "idle_elements", "vanished_terms", "vanished_parameters", "share_words"]


def flagged_parameters(fit: FitResult) -> set[str]:
    """The free parameters of ``fit`` its own flags put at a bound (``at_bound``) or give an
    infinite standard error (a vanishing term's, `branches.settle_vanishing`)."""
    return set(fit.at_bound) | {n for n in fit.free_names if fit.stderr.get(n) == np.inf}


def vanished_terms(fit: FitResult) -> list[tuple[IdleBranch, Circuit, tuple[str, ...]]]:
    """The terms of ``fit``'s circuit that vanished: a branch of a parallel block or a term of a
    series chain holding a parameter its flags hold (`flagged_parameters`: at a bound, as a
    resistor run open beside a C or a series R run to 0; or a vanishing term's) whose share of the block's current (the chain's
    voltage) stays below `branches.VANISHING_SHARE` at every frequency (`branches.idle_branches`,
    as the fit's idle note names it). Each as (the `IdleBranch`, the circuit without the term,
    the flagged parameters in it); the fit's model without the term differs from it by less
    than any instrument resolves."""
    flagged = flagged_parameters(fit)
    if not flagged or not np.isfinite(fit.chi2) or len(fit.circuit.element_names) < 2:
        return []
    try:
        table = ParameterTable.build(fit.circuit, registry=fit.registry, fixed={k: v for k, v in fit.values.items() if fit.fixed[k]} or None)
    except (ParameterError, CircuitError):
        return []
    values = np.array([[fit.values[n] for n in table.names]], float)
    mask = np.array([[n in flagged for n in table.free_names]])
    out = []
    for branch in idle_branches(fit.circuit, fit.registry, table, values, mask, fit.frequency):
        if not branch.share < VANISHING_SHARE:
            continue
        try:
            reduced = parse(branch.reduced, fit.registry)
        except CircuitError:
            continue
        gone = set(fit.circuit.parameter_names(fit.registry)) - set(reduced.parameter_names(fit.registry))
        out.append((branch, reduced, tuple(n for n in fit.free_names if n in gone and n in flagged)))
    return out


def idle_elements(fit: FitResult, undetermined: frozenset[str]) -> frozenset[str]:
    """The elements of ``fit``'s circuit in an idle term (`branches.idle_branches`: a branch
    carrying below `branches.IDLE_BRANCH_SHARE` of its block's current, or a series term below
    that share of its chain's voltage) holding one of the ``undetermined`` parameters — the
    elements its idle note names. The fit gave them no role, so the diagnosis prefers changing
    them among candidates the data cannot tell apart (`diagnosis._rank`)."""
    if not undetermined or not np.isfinite(fit.chi2) or len(fit.circuit.element_names) < 2:
        return frozenset()
    try:
        table = ParameterTable.build(fit.circuit, registry=fit.registry, fixed={k: v for k, v in fit.values.items() if fit.fixed[k]} or None)
    except (ParameterError, CircuitError):
        return frozenset()
    values = np.array([[fit.values[n] for n in table.names]], float)
    mask = np.array([[n in undetermined for n in table.free_names]])
    out: set[str] = set()
    for branch in idle_branches(fit.circuit, fit.registry, table, values, mask, fit.frequency):
        try:
            kept = parse(branch.reduced, fit.registry).element_names
        except CircuitError:
            continue
        out |= set(fit.circuit.element_names) - set(kept)
    return frozenset(out)


def vanished_parameters(fit: FitResult) -> frozenset[str]:
    """The parameters of ``fit``'s vanished terms (`vanished_terms`) that its flags hold (at a
    bound or a vanishing term's): `undetermined_parameters` counts a parameter at the natural
    bound that makes its term vanish as determined, but the data tell only that the term is
    not there (R1 = 1.8e255 Ω beside C1 on CHInstruments' spectrum). ``Refinement.summary``
    lists them as undetermined, should the final model keep one (`_pruned` takes them out)."""
    return frozenset(n for _, _, names in vanished_terms(fit) for n in names)


def share_words(branch: IdleBranch) -> str:
    """How little of its block a vanished term carries, as the notes say it: ``takes at most
    1e-05× the voltage across`` (a term of a series chain) or ``carries at most 1e-05× the current
    through`` (a branch of a parallel block); the block's text follows."""
    return f"takes at most {branch.share:.2g}× the voltage across" if branch.series else f"carries at most {branch.share:.2g}× the current through"
