"""Idle terms: why a parameter is undetermined when its element (or the sub-circuit holding it)
is one branch of a parallel block that carries next to none of the block's current over the
measured band (a resistor that ran open beside a CPE, a capacitance beside a resistor that
shorts it, a branch R1 + W1 whose R1 ran open), or one term of a series chain that takes next
to none of its voltage (a Warburg element whose R ran to 0). Single, batch and global fits add
the same note, and `diagnose` repeats its baseline's (docs/fitting.md, "Identifiability
warnings")."""

from __future__ import annotations

import collections
from typing import Iterator, NamedTuple

import numpy as np

from ...circuits import Circuit, Element, Parallel, Registry, Series
from ...circuits.compile import node_function
from ..parameters import ParameterTable

__all__ = [
    "IDLE_BRANCH_SHARE", "RELATIVE_ERROR_LIMIT", "IdleBranch", "undetermined", "undetermined_mask", "parallel_branches", "circuit_terms", "idle_branches",
    "idle_branch_notes", "is_idle_note",
]

RELATIVE_ERROR_LIMIT = 1.0
"""A free parameter whose standard error exceeds this × its value is not determined by the data."""
IDLE_BRANCH_SHARE = 1e-3
"""A branch of a parallel block is idle when its admittance stays below this fraction of the
block's at every frequency, and so is a term of a series chain whose impedance stays below this
fraction of the chain's: without it the block's or chain's impedance changes by at most about
as much."""


def undetermined(value, stderr):
    """Elementwise: is a parameter at ``value`` with standard error ``stderr`` undetermined, i.e.
    nonzero with a relative standard error above `RELATIVE_ERROR_LIMIT` (or none finite)? The
    rule of every fit's warnings; a parameter at a bound is judged by its bound note instead."""
    v, e = np.asarray(value, float), np.asarray(stderr, float)
    with np.errstate(all="ignore"):
        return (v != 0) & (~np.isfinite(e) | (np.abs(e / v) > RELATIVE_ERROR_LIMIT))


def undetermined_mask(table: ParameterTable, values: np.ndarray, stderr: np.ndarray, sides: np.ndarray) -> np.ndarray:
    """(B, K) over the free parameters of fits with values and stderr (B, P) and bound sides
    (B, K): `undetermined` and not at a bound."""
    free = table.free_index
    return undetermined(np.asarray(values, float)[:, free], np.asarray(stderr, float)[:, free]) & (np.asarray(sides) == 0)


def parallel_branches(circuit: Circuit) -> Iterator[tuple[Parallel, int]]:
    """(parallel node, index of a child that is an element) in the order of the circuit text."""
    if isinstance(circuit, Element):
        return
    for i, child in enumerate(circuit.children):
        if isinstance(circuit, Parallel) and isinstance(child, Element):
            yield circuit, i
        yield from parallel_branches(child)


def circuit_terms(circuit: Circuit) -> Iterator[tuple[Parallel | Series, int]]:
    """(series or parallel node, index of a child) for every child of every node, a node's
    children before their own: the branches of parallel blocks and the terms of series chains,
    elements or not."""
    if isinstance(circuit, Element):
        return
    yield from ((circuit, i) for i in range(len(circuit.children)))
    for child in circuit.children:
        yield from circuit_terms(child)


# the words every idle note holds (`IdleBranch.text`), by which `is_idle_note` knows one among a fit's warnings
_IDLE_NOTE_WORDS = ", the model without it, differs from this fit by about that fraction of the "


def is_idle_note(text: str) -> bool:
    """Whether a fit's warning ``text`` is an idle note (`IdleBranch.text`)."""
    return _IDLE_NOTE_WORDS in text


class IdleBranch(NamedTuple):
    """An ``element`` (or a sub-circuit, by its text) of fit ``row`` that carries at most
    ``share`` of the current through its parallel ``block`` at every frequency or, ``series``
    true, takes at most ``share`` of the voltage across its series ``block``; ``reduced``: the
    circuit without it."""

    row: int
    element: str
    block: str
    share: float
    reduced: str
    series: bool = False

    def text(self) -> str:
        share = f"takes at most {self.share:.2g}× the voltage across" if self.series else f"carries at most {self.share:.2g}× the current through"
        block = "chain" if self.series else "block"
        return (
            f"{self.element} {share} {self.block} over the band, so the data cannot determine it: "
            f"{self.reduced}{_IDLE_NOTE_WORDS}{block}'s impedance"
        )


def idle_branches(circuit: Circuit, registry: Registry, table: ParameterTable, values: np.ndarray, mask: np.ndarray, freq) -> list[IdleBranch]:
    """The idle terms of fits with values (B, P) among those holding a parameter in ``mask``
    (B, K, `undetermined_mask`): a branch of a parallel block (an element or a sub-circuit) that
    carries below `IDLE_BRANCH_SHARE` of the block's current at every frequency ``freq``,
    |Y_branch / Σ Y| over the block's children at the fitted values, or a term of a series
    chain that takes below that share of its voltage, |Z_term / Σ Z|. A term inside an idle
    one is not named again."""
    mask = np.asarray(mask, bool)
    freq = np.asarray(freq, float)
    if not mask.any() or freq.size == 0:
        return []
    omega = 2 * np.pi * freq[None, :]
    column = {n: j for j, n in enumerate(table.free_names)}
    values = np.asarray(values, float)
    found = []
    named: dict[int, set[str]] = collections.defaultdict(set)  # per row, the elements inside a term named idle
    for node, i in circuit_terms(circuit):
        term = node.children[i]
        series = isinstance(node, Series)
        elements = term.element_names
        own = [column[n] for e in term.elements() for n in registry[e.symbol].parameter_names(e.name) if n in column]
        rows = np.flatnonzero(mask[:, own].any(axis=1)) if own else np.zeros(0, int)
        rows = np.array([r for r in rows.tolist() if not named[r] & set(elements)], int)
        if not rows.size:
            continue
        params = {n: values[rows, j][:, None] for j, n in enumerate(table.names)}
        with np.errstate(all="ignore"):
            # a parallel block's branches share its current by admittance, a chain's terms its voltage by impedance
            terms = [np.asarray(node_function(c, registry, "Z" if series else "Y")(params, omega)) for c in node.children]
            share = np.max(np.abs(terms[i] / sum(terms)), axis=1)
        idle = np.isfinite(share) & (share < IDLE_BRANCH_SHARE)
        if idle.any():
            reduced = circuit
            for name in elements:
                reduced = reduced.without(name)
            for row, s in zip(rows[idle].tolist(), share[idle].tolist()):
                named[row].update(elements)
                found.append(IdleBranch(row, str(term), str(node), s, str(reduced), series))
    return found


def idle_branch_notes(circuit: Circuit, registry: Registry, table: ParameterTable, values: np.ndarray, mask: np.ndarray, freq) -> dict[int, tuple[str, ...]]:
    """{row: notes} of the `idle_branches` of fits with values (B, P) and ``mask`` (B, K)."""
    notes: dict[int, list[str]] = collections.defaultdict(list)
    for branch in idle_branches(circuit, registry, table, values, mask, freq):
        notes[branch.row].append(branch.text())
    return {row: tuple(n) for row, n in notes.items()}
