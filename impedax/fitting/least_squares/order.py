"""Exchangeable blocks reported in one order.

Sibling subcircuits with the same structure (the two ``R || CPE`` arcs of
``R0 + R1 || CPE1 + R2 || CPE2``) can trade their parameter values without changing Z, so a
solver may end either way round. Fits list them as written with the block whose −Z'' peaks at
the highest frequency first (as the data-driven guess assigns arcs), so ``R1`` means the same
arc in every spectrum of a batch and in every refit.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np

from ...circuits import Circuit, Element, Registry, Series, compile_circuit

__all__ = ["canonical_order", "exchangeable_blocks", "peak_frequencies"]


def _shape(node: Circuit, registry: Registry) -> str:
    """A subcircuit's structure without its element names: ``P(R,CPE)`` for ``R1 || CPE1``."""
    if isinstance(node, Element):
        return registry[node.symbol].symbol
    kind = "S" if isinstance(node, Series) else "P"
    return f"{kind}({','.join(_shape(c, registry) for c in node.children)})"


def exchangeable_blocks(circuit: Circuit, names, fixed, lower, upper, registry: Registry) -> list[list[tuple[Circuit, list[int]]]]:
    """Groups of sibling subcircuits with the same structure, outer groups first: each member
    with its parameters' indices in ``names``, position by position. Only groups whose
    parameters are all free (``fixed``) with equal bounds can be reordered."""
    index = {n: i for i, n in enumerate(names)}
    groups = []

    def walk(node):
        if isinstance(node, Element):
            return
        by_shape: dict[str, list] = {}
        for child in node.children:
            if not isinstance(child, Element):
                by_shape.setdefault(_shape(child, registry), []).append(child)
        for members in by_shape.values():
            blocks = [(m, [index[n] for n in m.parameter_names(registry)]) for m in members]
            columns = np.array([idx for _, idx in blocks])
            same_bounds = all((lower[c] == lower[c[0]]).all() and (upper[c] == upper[c[0]]).all() for c in columns.T)
            if len(blocks) > 1 and not fixed[columns].any() and same_bounds:
                groups.append(blocks)
        for child in node.children:
            walk(child)

    walk(circuit)
    return groups


def peak_frequencies(blocks, names, registry: Registry):
    """``fn(x (P,), freq) -> (members,)``: the frequency at which each block's −Z'' peaks
    (−inf where it is never positive), from a full parameter vector x (pure JAX)."""
    compiled = [compile_circuit(block, registry) for block in blocks]
    columns = [np.array([list(names).index(n) for n in c.parameter_names]) for c in compiled]

    def peaks(x, freq):
        out = []
        for c, idx in zip(compiled, columns):
            neg_im = -c.vector(x[idx], freq).imag
            out.append(jnp.where(jnp.any(neg_im > 0), freq[jnp.argmax(neg_im)], -jnp.inf))
        return jnp.stack(out)

    return peaks


def structural_peaks(circuit: Circuit, names: tuple[str, ...], registry: Registry):
    """``fn(x, freq) -> (M,)`` peak frequencies of the members of every exchangeable group
    (fixed values and bounds aside), concatenated in group order — for solvers to return with
    their solution, so that ordering a fit needs no extra call; None when there are none."""
    p = len(names)
    groups = exchangeable_blocks(circuit, names, np.zeros(p, bool), np.zeros(p), np.zeros(p), registry)
    if not groups:
        return None
    parts = [peak_frequencies([b for b, _ in blocks], names, registry) for blocks in groups]
    return lambda x, freq: jnp.concatenate([f(x, freq) for f in parts])


@functools.lru_cache(maxsize=64)
def _plan(circuit: Circuit, names: tuple[str, ...], fixed: bytes, lower: bytes, upper: bytes, registry: Registry):
    """Per reorderable group: its parameter columns (members, params per block), the offset of
    its members in `structural_peaks`' output, and a jitted peak function over a batch of the
    group's parameters (`_batched_peaks`: used when the solver returned no peaks, or when a
    group sits inside a member of another, whose reordering moves it)."""
    p = len(names)
    every = exchangeable_blocks(circuit, names, np.zeros(p, bool), np.zeros(p), np.zeros(p), registry)
    offsets, at = {}, 0
    for blocks in every:
        offsets[tuple(str(b) for b, _ in blocks)] = at
        at += len(blocks)
    groups = exchangeable_blocks(circuit, names, np.frombuffer(fixed, bool), np.frombuffer(lower), np.frombuffer(upper), registry)
    elements = [[set(b.element_names) for b, _ in blocks] for blocks in groups]
    nested = any(set().union(*inner) <= member for a, outer in enumerate(elements) for b, inner in enumerate(elements) if a != b for member in outer)
    plan = []
    for blocks in groups:
        batched = _batched_peaks(_shape(blocks[0][0], registry), len(blocks), blocks[0][0], registry)
        plan.append((np.array([idx for _, idx in blocks]), offsets[tuple(str(b) for b, _ in blocks)], batched))
    return plan, nested


_PEAK_PROGRAMS: dict[tuple[str, int, Registry], object] = {}
"""`_batched_peaks`' jitted functions, one per block structure (`_shape`) and member count."""


def _batched_peaks(structure: str, members: int, block: Circuit, registry: Registry):
    """Jitted ``fn(xb (B, members, p), freq) -> (B, members)``: the frequency at which −Z'' of
    each of ``members`` blocks of one ``structure`` (``block`` is one of them) peaks, −inf where
    it is never positive, ``xb`` each member's p parameters in its own order (``x[:, columns]``
    of `_plan`'s columns). One function per structure, not per circuit: the blocks' names are
    not in it, so the candidates of a diagnosis and the steps of a refine that share
    ``R ∥ CPE`` arcs trace and load it once (a jit per circuit traced 124 times in one
    ``refine`` of a REAL battery cycle, 4.5 s of its 46 s; benchmarks/README.md)."""
    key = (structure, members, registry)
    if key not in _PEAK_PROGRAMS:
        compiled = compile_circuit(block, registry)

        def peaks(xb, freq):
            out = []
            for m in range(members):
                neg_im = -compiled.vector(xb[m], freq).imag
                out.append(jnp.where(jnp.any(neg_im > 0), freq[jnp.argmax(neg_im)], -jnp.inf))
            return jnp.stack(out)

        _PEAK_PROGRAMS[key] = jax.jit(jax.vmap(peaks, in_axes=(0, None)))
    return _PEAK_PROGRAMS[key]


def canonical_order(circuit: Circuit, table, freq, out, registry: Registry):
    """Solver outputs with exchangeable blocks in order (see the module docstring): permutes
    ``x`` (…, P) and the Jacobian's columns (…, M, K); everything else is unchanged. Uses the
    peak frequencies the solver returned (``out.peaks``, a `solvers.SolverOutput`) when it did."""
    plan, nested = _plan(circuit, table.names, table.fixed.tobytes(), table.lower.tobytes(), table.upper.tobytes(), registry)
    if not plan:
        return out
    x = np.array(out.x, float)
    batch_shape, n_par = x.shape[:-1], x.shape[-1]
    x = x.reshape(-1, n_par)
    given = None if nested or out.peaks is None else np.asarray(out.peaks).reshape(x.shape[0], -1)
    order = np.tile(np.arange(n_par), (x.shape[0], 1))
    rows = np.arange(x.shape[0])[:, None]
    for columns, offset, batched in plan:  # outer groups first: an inner group is sorted where it has moved to
        peaks = given[:, offset : offset + len(columns)] if given is not None else np.asarray(batched(x[:, columns], np.asarray(freq, float)))
        rank = np.argsort(-peaks, axis=1, kind="stable")  # (B, members)
        permutation = np.tile(np.arange(n_par), (x.shape[0], 1))
        for slot in range(len(columns)):
            permutation[:, columns[slot]] = columns[rank[:, slot]]
        x, order = x[rows, permutation], order[rows, permutation]
    moved = np.flatnonzero(np.any(order != np.arange(n_par), axis=1))
    if not moved.size:
        return out  # already in order (the usual case)
    free = table.free_index
    position = np.full(n_par, -1)
    position[free] = np.arange(free.size)
    jac = np.array(out.jacobian).reshape(-1, *np.shape(out.jacobian)[-2:])
    columns = position[order[moved][:, free]][:, None, :]
    jac[moved] = np.take_along_axis(jac[moved], np.broadcast_to(columns, (moved.size, *jac.shape[1:])), axis=-1)
    return out._replace(x=x.reshape(*batch_shape, n_par), jacobian=jac.reshape(np.shape(out.jacobian)))
