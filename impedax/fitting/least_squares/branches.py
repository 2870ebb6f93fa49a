"""Idle terms: why a parameter is undetermined when its element (or the sub-circuit holding it)
is one branch of a parallel block that carries next to none of the block's current over the
measured band (a resistor that ran open beside a CPE, a capacitance beside a resistor that
shorts it, a branch R1 + W1 whose R1 ran open), or one term of a series chain that takes next
to none of its voltage (a Warburg element whose R ran to 0). Single, batch and global fits add
the same note, and `diagnose` repeats its baseline's (docs/fitting.md, "Identifiability
warnings")."""

from __future__ import annotations

import collections
import math
from typing import Iterator, NamedTuple

import numpy as np

from ...circuits import Circuit, Element, Parallel, Registry, Series
from ...circuits.compile import node_function
from ..parameters import ParameterTable
from ..statistics import covariances

__all__ = [
    "IDLE_BRANCH_SHARE", "VANISHING_SHARE", "RELATIVE_ERROR_LIMIT", "IdleBranch", "undetermined", "undetermined_names", "left_to_priors", "undetermined_mask", "parallel_branches", "circuit_terms",
    "idle_branches", "idle_branch_notes", "is_idle_note", "vanishing_parameters", "VANISHED", "settle_vanishing", "vanishing_candidates", "unidentified_stderr",
    "vanishing_term_mask", "held_covariances",
]

RELATIVE_ERROR_LIMIT = 1.0
"""A free parameter whose standard error exceeds this × its value is not determined by the data."""
IDLE_BRANCH_SHARE = 1e-3
"""A branch of a parallel block is idle when its admittance stays below this fraction of the
block's at every frequency, and so is a term of a series chain whose impedance stays below this
fraction of the chain's: without it the block's or chain's impedance changes by at most about
as much."""
VANISHING_SHARE = 1e-6
"""A term whose share (as for `IDLE_BRANCH_SHARE`) stays below this at every frequency changes
the impedance by less than any instrument resolves (the best reach ~1e-4): its parameters are
undetermined whatever their standard error says. A fit to near-exact data (SYNTHETIC, or a
refit of a model's own output) has residuals of ~1e-14, which make every standard error small,
also that of a resistor run open to 1e20 Ω beside a CPE."""


def undetermined(value, stderr):
    """Elementwise: is a parameter at ``value`` with standard error ``stderr`` undetermined, i.e.
    nonzero with a relative standard error above `RELATIVE_ERROR_LIMIT` (or none finite)? The
    rule of every fit's warnings; a parameter at a bound is judged by its bound note instead."""
    v, e = np.asarray(value, float), np.asarray(stderr, float)
    with np.errstate(all="ignore"):
        return (v != 0) & (~np.isfinite(e) | (np.abs(e / v) > RELATIVE_ERROR_LIMIT))


def undetermined_names(fit) -> list[str]:
    """The free parameters of ``fit`` (a `FitResult`) the data do not determine: off their
    bounds, nonzero, with a relative standard error above `RELATIVE_ERROR_LIMIT` (`undetermined`),
    as its warnings say."""
    return [n for n in fit.free_names if n not in fit.at_bound and undetermined(fit.values[n], fit.stderr[n])]


def left_to_priors(value: float, stderr: float, at_bound: bool) -> bool:
    """Whether a posterior's least-squares start leaves one parameter to the priors: `undetermined`
    off a bound (the fits' rule), or at a bound with an infinite standard error — a vanishing
    term's parameter (`settle_vanishing`: `without_error` keeps its inf where another bound gives
    none), R2 run to ∞ beside a CPE, whose draws spread over the prior's tail (R2 of cycle 64 of
    AutoEIS's battery cycles in a global start fit: 90 % interval 5.9e3–1.3e86 Ω). Another
    parameter at a bound is judged by its bound note and the prior-edge warning."""
    return bool(undetermined(value, stderr)) and (not at_bound or float(stderr) == math.inf)


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


def idle_note_reduced(text: str) -> str | None:
    """The circuit without the idle term that idle note ``text`` names (`IdleBranch.reduced`),
    or None when ``text`` is no idle note."""
    if not is_idle_note(text):
        return None
    return text.partition(_IDLE_NOTE_WORDS)[0].rpartition("so the data cannot determine it: ")[2] or None


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
        share = _shares(node, registry, table, values[rows], omega)[i]
        idle = np.isfinite(share) & (share < IDLE_BRANCH_SHARE)
        if idle.any():
            reduced = circuit
            for name in elements:
                reduced = reduced.without(name)
            for row, s in zip(rows[idle].tolist(), share[idle].tolist()):
                named[row].update(elements)
                found.append(IdleBranch(row, str(term), str(node), s, str(reduced), series))
    return found


def _shares(node: Parallel | Series, registry: Registry, table: ParameterTable, values: np.ndarray, omega: np.ndarray) -> list[np.ndarray]:
    """Per child of ``node``, its largest share over ``omega`` (1, N) for fits with values (B, P):
    a parallel block's branches share its current by admittance, |Y_child / Σ Y|, a chain's
    terms its voltage by impedance, |Z_child / Σ Z|."""
    n_rows = values.shape[0]
    # (rows padded to a power of two, at least 8, and at least `_SHARE_ROWS` past 8: eager JAX
    # compiles each operation once per shape, and these shapes recur; one program per block
    # would compile for every candidate circuit of a diagnosis)
    n_padded = 1 << max(3, (n_rows - 1).bit_length())
    n_padded = n_padded if n_padded <= 8 else max(n_padded, _SHARE_ROWS)
    padded = np.concatenate([values, np.repeat(values[:1], n_padded - n_rows, axis=0)]) if n_rows else values
    params = {n: padded[:, j][:, None] for j, n in enumerate(table.names)}
    form = "Z" if isinstance(node, Series) else "Y"
    with np.errstate(all="ignore"):
        terms = [np.asarray(node_function(c, registry, form)(params, omega))[:n_rows] for c in node.children]
        total = sum(terms)
        return [np.max(np.abs(t / total), axis=1) for t in terms]


_SHARE_ROWS = 128
"""`_shares` pads the rows of more than 8 fits to at least this many, so a batch's calls of
different sizes (62 and 81 rows on AutoEIS's 130 battery cycles with ``Wo1``) share one shape and
one compilation of each eager operation (33 → 17 in a fresh process); a single fit's row keeps its
8 (benchmarks/README.md, "Where a batch call goes today, and the vanishing-term shares in one
shape")."""


VANISHING_COLUMN = 1e-4
"""`vanishing_parameters` looks only at fits with a candidate's Jacobian column below this × the
median column (a vanishing term's: below ~1e-5 of the impedance's scale; a determined
Warburg τ on AutoEIS's battery cycles: 3e-3 of the median)."""
VANISHED = 2
"""`vanishing_parameters`' code of a vanishing term's parameter that no natural bound explains."""


def vanishing_parameters(circuit: Circuit, registry: Registry, table: ParameterTable, values: np.ndarray, freq, candidates: np.ndarray, jacobian=None) -> np.ndarray:
    """(B, K) int8 over the free parameters of fits with values (B, P): nonzero for a parameter
    of a term (a branch of a parallel block or a term of a series chain, an element or a
    sub-circuit) whose share stays below `VANISHING_SHARE` at every frequency ``freq``. For a
    scale on (0, ∞): +1 where ten times the value shrinks the term's share further (at the upper
    bound ∞: a resistor run open beside a CPE), −1 where a tenth does (at 0: a capacitance run
    to 0 beside a resistor); `VANISHED` otherwise (a CPE's α beside its vanishing Q).

    Only fits with a ``candidates`` parameter (B, K: those the rule may change, `settle_vanishing`:
    determined and at no bound) are looked at; given the fits' ``jacobian`` (B, 2N, K) of the
    weighted residuals in the solver's variables, only those whose candidate's column is below
    `VANISHING_COLUMN` × their median, or whose column times |value| is below that × the median
    of those (a scale run to ~0 in a series chain, as a Warburg σ): a vanishing term's parameters move Z by at most ~10× its
    share (an exponent's log ω factor), while the scales of a circuit move it by Z itself (Z is
    homogeneous of degree 1 in its impedance scales). The median, not the largest: an L at 0
    has a column 1e4 times the others'. A parameter at a bound or undetermined is no candidate."""
    values = np.asarray(values, float)
    found = np.zeros((values.shape[0], len(table.free_names)), np.int8)
    freq = np.asarray(freq, float)
    if isinstance(circuit, Element) or freq.size == 0 or not found.size:
        return found
    small = np.asarray(candidates, bool)
    if jacobian is not None:
        with np.errstate(all="ignore"):
            norms = np.sqrt(np.sum(np.square(np.asarray(jacobian, float)), axis=-2))  # (x² = |x|², without |x| taken first)
            # ... or |x|·column, the change for a relative step: a series term's scale run to ~0 (a
            # Warburg σ = 1e-11 Ω s^-1/2: Z_W = σ(1−j)/√ω) keeps its column ∂Z/∂σ, only x∂Z/∂x = Z_W shrinks
            relative = norms * np.abs(values[:, table.free_index])
            small = small & (
                ~(norms >= VANISHING_COLUMN * np.median(norms, axis=-1, keepdims=True))
                | ~(relative >= VANISHING_COLUMN * np.median(relative, axis=-1, keepdims=True))
            )
    looked = np.flatnonzero(small.any(axis=-1))
    if looked.size < values.shape[0]:
        if looked.size:
            found[looked] = vanishing_parameters(circuit, registry, table, values[looked], freq, small[looked])
        return found
    # only the nodes that hold a candidate, and only the candidates' codes (a node's shares cost its JAX operations, compiled per shape)
    wanted = {n for n, any_row in zip(table.free_names, small.any(axis=0)) if any_row}
    column = {n: j for j, n in enumerate(table.free_names)}
    omega = 2 * np.pi * freq[None, :]
    nodes = [circuit]
    while nodes:
        node = nodes.pop()
        if not any(n in wanted for e in node.elements() for n in registry[e.symbol].parameter_names(e.name)):
            continue
        for c, (child, share) in enumerate(zip(node.children, _shares(node, registry, table, values, omega))):
            if not isinstance(child, Element):
                nodes.append(child)
            rows = np.flatnonzero(np.isfinite(share) & (share < VANISHING_SHARE))
            for name in (n for e in child.elements() for n in registry[e.symbol].parameter_names(e.name) if n in wanted):
                if not rows.size:
                    break
                k, i = column[name], table.names.index(name)
                code = np.full(rows.size, VANISHED, np.int8)
                for side, factor in ((1, 10.0), (-1, 0.1)):
                    if not (table.lower[i] == 0 and table.upper[i] == np.inf):  # a scale (R, C, Q ...), not an exponent
                        continue
                    moved = values[rows].copy()
                    with np.errstate(over="ignore"):  # (a value near float64's end moved to inf: its share is no smaller)
                        moved[:, i] *= factor
                    code[_shares(node, registry, table, moved, omega)[c] < 0.5 * share[rows]] = side
                found[rows, k] = np.where(found[rows, k] == 0, code, found[rows, k])
    return found


def vanishing_term_mask(circuit: Circuit, registry: Registry, table: ParameterTable, values: np.ndarray, freq, jacobian) -> np.ndarray:
    """(B, K) bool over the free parameters of fits with values (B, P) and Jacobians (B, 2N, K):
    the parameters of a term whose share stays below `VANISHING_SHARE` at every frequency
    (`vanishing_parameters` with every free parameter a candidate), determined or not, at a
    bound or not. Such a term changes Z by less than any instrument resolves: the data hold the
    reduced circuit, and its parameters are undetermined whatever their standard errors say."""
    values = np.asarray(values, float)
    everyone = np.ones((values.shape[0], len(table.free_names)), bool)
    return vanishing_parameters(circuit, registry, table, values, freq, everyone, jacobian) != 0


def held_covariances(jacobian: np.ndarray, chi2_red, weighting: str, cov: np.ndarray, corr: np.ndarray, held: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Covariances and correlations (B, K, K) of fits with Jacobians (B, 2N, K), reduced χ²
    (B,) and `covariances`' ``cov``, ``corr``, with the parameters ``held`` (B, K,
    `vanishing_term_mask`) held at their values for the others: the others' block from J
    without the held columns (JᵀJ without their rows and columns: the covariance conditional
    on them, the reduced circuit's), the held ones' block kept from the full linearisation,
    no cross terms. A vanishing term's columns are its linearisation at wherever along the flat
    valley the solver stopped (R1 + W1 open beside a CPE: a conductance where R1 dominates,
    a capacitance where W1.sigma does), and inflated the others' errors up to 15× at one point of
    it (CH Instruments' file, ``CPE1 || (R1 + W1) + R0``) but not at another."""
    cov, corr, held = np.array(cov, float), np.array(corr, float), np.asarray(held, bool)
    chi2_red = np.broadcast_to(np.asarray(chi2_red, float), held.shape[:1])
    patterns, which = np.unique(held, axis=0, return_inverse=True)
    for pattern, code in zip(patterns, range(len(patterns))):
        keep = ~pattern
        if not pattern.any() or not keep.any():
            continue
        rows = np.flatnonzero(np.ravel(which) == code)
        kept_cov, kept_corr, _, _ = covariances(np.asarray(jacobian, float)[rows][:, :, keep], chi2_red[rows], weighting)
        for full, kept in ((cov, kept_cov), (corr, kept_corr)):
            full[np.ix_(rows, keep, keep)] = kept
            full[np.ix_(rows, keep, pattern)] = 0.0
            full[np.ix_(rows, pattern, keep)] = 0.0
    return cov, corr


def vanishing_candidates(sides: np.ndarray, free_values: np.ndarray, free_stderr: np.ndarray) -> np.ndarray:
    """(B, K): the free parameters `settle_vanishing` may change: determined and at no bound."""
    return (np.asarray(sides) == 0) & ~undetermined(free_values, free_stderr)


def settle_vanishing(codes: np.ndarray, sides: np.ndarray, free_values: np.ndarray, free_stderr: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Bound sides and standard errors (B, K) of the free parameters with `vanishing_parameters`'
    ``codes`` applied where the fit called a parameter determined and at no bound (±1 become
    the side; the standard error is infinite, the data give none), and where that was (they get
    the idle note). The undetermined keep their note."""
    sides, codes = np.asarray(sides), np.asarray(codes)
    new = vanishing_candidates(sides, free_values, free_stderr) & (codes != 0)
    return np.where(new & (codes != VANISHED), codes, sides).astype(sides.dtype), np.where(new, np.inf, free_stderr), new


def unidentified_stderr(free_names, groups, sides: np.ndarray, free_stderr: np.ndarray) -> np.ndarray:
    """Standard errors (K,) of the free parameters ``free_names`` with those in a group of
    ``groups`` (the near-null directions, `statistics.null_sets`) made infinite where at no bound
    (``sides`` (K,) zero): the data do not determine them, whatever χ²_red scales the
    linearisation's variance by. On noise-free data χ²_red ≈ 1e-32 shrank the regularised
    variance of a near-null direction to a standard error of 0.01 % (the Meyer finger's C_s and
    C_i: 0.012 %), which read as determined; with 0.1 % noise it reads 1e11 %."""
    flagged = {n for g in groups for n in g}
    mask = np.array([n in flagged for n in free_names], bool) & (np.asarray(sides) == 0)
    return np.where(mask, np.inf, free_stderr)


def idle_branch_notes(circuit: Circuit, registry: Registry, table: ParameterTable, values: np.ndarray, mask: np.ndarray, freq) -> dict[int, tuple[str, ...]]:
    """{row: notes} of the `idle_branches` of fits with values (B, P) and ``mask`` (B, K)."""
    notes: dict[int, list[str]] = collections.defaultdict(list)
    for branch in idle_branches(circuit, registry, table, values, mask, freq):
        notes[branch.row].append(branch.text())
    return {row: tuple(n) for row, n in notes.items()}
