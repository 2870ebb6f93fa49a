"""A circuit as padded arrays, so one compiled evaluator serves many topologies.

`CircuitProgram` describes a circuit by element kinds per slot and its series/parallel nodes
as child masks in topological order. One jitted evaluator, `evaluate_program`, serves every
topology of the same `ProgramLayout`, so a fitter compiled once can fit many candidate
circuits, even together under ``vmap``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import jax
import jax.numpy as jnp
import numpy as np

from ..errors import CircuitError, ParameterError
from .compile import check_element_names, check_user_elements
from .elements import DEFAULT_REGISTRY
from .parser import parse
from .spec import MAX_ELEMENT_PARAMS, Registry
from .tree import Circuit, Element, Parallel

__all__ = ["ProgramLayout", "CircuitProgram", "PROGRAM_SCALES", "default_theta", "evaluate_program", "program_value_and_columns"]


@dataclass(frozen=True)
class ProgramLayout:
    """Static shape of a padded program: slot capacity per element kind and node count.

    Slots are grouped by kind (kind k owns ``slots_of(k)``), so evaluating a program runs each
    element formula only on its own slots. Everything that differs between circuits of one
    layout is data, so one compiled function serves them all.
    """

    registry: Registry
    capacities: tuple[int, ...]  # per kind, in registry.specs order
    n_nodes: int

    @property
    def n_slots(self) -> int:
        return sum(self.capacities)

    def slots_of(self, kind: int) -> slice:
        start = sum(self.capacities[:kind])
        return slice(start, start + self.capacities[kind])

    @classmethod
    def sized(cls, scale: int, registry: Registry = DEFAULT_REGISTRY) -> "ProgramLayout":
        """Layout ``scale`` (1, 2, 4): room for ``program_capacity``·scale elements of each
        kind (built-ins: 6 R, 4 C, 4 CPE, 2 of the rest) and 8·scale nodes."""
        caps = tuple(spec.program_capacity * scale for spec in registry.specs)
        return cls(registry, caps, 8 * scale)

    @classmethod
    def covering(cls, circuits, registry: Registry = DEFAULT_REGISTRY) -> "ProgramLayout":
        """The smallest layout that holds every circuit in ``circuits`` (kind counts and nodes)."""
        caps = [0] * len(registry.specs)
        nodes = 1
        for c in circuits:
            counts = [0] * len(registry.specs)
            for e in c.elements():
                counts[registry.kind_index(e.symbol)] += 1
            caps = [max(a, b) for a, b in zip(caps, counts)]
            nodes = max(nodes, _count_nodes(c) + 1)
        return cls(registry, tuple(caps), nodes)


PROGRAM_SCALES = (1, 2, 4)


@dataclass(frozen=True, eq=False)
class CircuitProgram:
    """A circuit as padded arrays, for one compiled evaluator across topologies.

    * ``layout``: the static `ProgramLayout` (slots grouped by element kind, node count N);
    * ``is_parallel`` (N,), ``children`` (N, S+N): node k combines the values whose mask
      entries are 1, by impedance sum (series) or admittance sum (parallel); nodes are in
      topological order and node k's value has index S+k;
    * ``root``: index of the circuit's value;
    * parameters live in an (S, 4) array ``theta``: row s holds slot s's parameters in
      declaration order (`parameter_slots` maps names to (s, i)); unused entries hold the
      kind's defaults.
    """

    circuit: Circuit
    layout: ProgramLayout
    is_parallel: np.ndarray
    children: np.ndarray
    root: int
    parameter_slots: dict[str, tuple[int, int]]
    element_slots: dict[str, int]

    @classmethod
    def build(cls, circuit: Circuit | str, registry: Registry = DEFAULT_REGISTRY, layout: ProgramLayout | None = None) -> "CircuitProgram":
        circuit = parse(circuit, registry)
        check_element_names(circuit, registry)
        check_user_elements(registry.specs)  # (every kind's slots are evaluated)
        elements = list(circuit.elements())
        counts = [0] * len(registry.specs)
        for e in elements:
            counts[registry.kind_index(e.symbol)] += 1
        n_nodes = _count_nodes(circuit) + 1
        candidates = [layout] if layout is not None else [ProgramLayout.sized(s, registry) for s in PROGRAM_SCALES]
        layout = next((lay for lay in candidates if lay.n_nodes >= n_nodes and all(c <= cap for c, cap in zip(counts, lay.capacities))), None)
        if layout is None:
            raise CircuitError(f"circuit {circuit} is too large for a padded program ({len(elements)} elements, {n_nodes - 1} nodes)")
        size, n = layout.n_slots, layout.n_nodes
        used = [0] * len(registry.specs)
        element_slots: dict[str, int] = {}
        slots: dict[str, tuple[int, int]] = {}
        for e in elements:
            k = registry.kind_index(e.symbol)
            s = layout.slots_of(k).start + used[k]
            used[k] += 1
            element_slots[e.name] = s
            for i, name in enumerate(registry[e.symbol].parameter_names(e.name)):
                slots[name] = (s, i)
        is_parallel = np.zeros(n, bool)
        children = np.zeros((n, size + n), np.float64)
        counter = [0]

        def emit(node) -> int:
            if isinstance(node, Element):
                return element_slots[node.name]
            idx = [emit(c) for c in node.children]
            k = counter[0]
            counter[0] += 1
            children[k, idx] = 1.0
            is_parallel[k] = isinstance(node, Parallel)
            return size + k

        root = emit(circuit)
        if isinstance(circuit, Element):  # wrap so the root is always a node
            children[0, root] = 1.0
            root = size
        return cls(circuit, layout, is_parallel, children, root, slots, element_slots)

    def arrays(self) -> dict[str, np.ndarray]:
        """The program's data as NumPy arrays (a pytree that can be stacked, passed to jitted
        functions and vmapped across circuits)."""
        return {"is_parallel": self.is_parallel, "children": self.children, "root": np.asarray(self.root, np.int32)}

    def pack(self, params: Mapping[str, float]) -> np.ndarray:
        """Parameter mapping → (S, 4) ``theta`` array (unused entries: the kind's defaults)."""
        theta = default_theta(self.layout)
        for name, (s, i) in self.parameter_slots.items():
            if name not in params:
                raise ParameterError(f"missing parameter {name!r} for circuit {self.circuit}")
            theta[s, i] = params[name]
        return theta

    def unpack(self, theta) -> dict[str, object]:
        return {name: theta[..., s, i] for name, (s, i) in self.parameter_slots.items()}

    def __call__(self, params: Mapping[str, float], freq):
        """Evaluate at ``params`` (a mapping) — mainly for checks; fitters call `evaluate_program`."""
        return evaluate_program(self.arrays(), jnp.asarray(self.pack(params)), freq, layout=self.layout)


def _count_nodes(node: Circuit) -> int:
    if isinstance(node, Element):
        return 0
    return 1 + sum(_count_nodes(c) for c in node.children)


def default_theta(layout: ProgramLayout) -> np.ndarray:
    """(S, 4) array holding each slot's kind defaults (1.0 beyond a kind's parameters)."""
    theta = np.ones((layout.n_slots, MAX_ELEMENT_PARAMS))
    for k, spec in enumerate(layout.registry.specs):
        for i, p in enumerate(spec.parameters):
            theta[layout.slots_of(k), i] = p.default
    return theta


def _slot_impedances(theta, omega, layout: ProgramLayout, *, derivatives: bool = False):
    """Every slot's impedance (S, F), kinds in layout order, and with ``derivatives`` also
    ∂z_s/∂θ_(s,i) (S, 4, F; zero beyond a kind's parameters) by one batched JVP per kind."""
    n_freq, width = omega.shape[1], theta.shape[1]
    values, columns = [], []
    for k, spec in enumerate(layout.registry.specs):
        rows = theta[layout.slots_of(k)]
        n_k, n_par = rows.shape[0], len(spec.parameters)
        if n_k == 0:
            continue

        def formula(r, spec=spec, n_k=n_k, n_par=n_par):
            z = spec.impedance(omega, *(r[:, i : i + 1] for i in range(n_par)))
            return jnp.broadcast_to(z, (n_k, n_freq)).astype(jnp.complex128)

        if not derivatives:
            values.append(formula(rows))
            continue
        tangents = jnp.broadcast_to(jnp.eye(width)[:n_par, None, :], (n_par, n_k, width))
        z_k, d_k = jax.vmap(lambda t: jax.jvp(formula, (rows,), (t,)), out_axes=(None, 0))(tangents)  # d_k: (n_par, n_k, F)
        values.append(z_k)
        columns.append(jnp.concatenate([jnp.moveaxis(d_k, 0, 1), jnp.zeros((n_k, width - n_par, n_freq), jnp.complex128)], axis=1))
    z_slots = jnp.concatenate(values, axis=0)
    return (z_slots, jnp.concatenate(columns, axis=0)) if derivatives else z_slots


def _masked(mask, v):
    """mask @ v for a real mask and complex v, as two real products."""
    return (mask @ v.real) + 1j * (mask @ v.imag)


def _node_values(program, z_slots, y_slots, layout: ProgramLayout):
    """Impedance and admittance of every node (N, F), in topological order (one `lax.scan`
    step per node): node k sums its children's impedances (series) or admittances (parallel)
    as real mask-vector products."""
    size, n = layout.n_slots, layout.n_nodes
    children, is_parallel = jnp.asarray(program["children"]), jnp.asarray(program["is_parallel"])

    def node(carry, k):
        z_nodes, y_nodes = carry
        slot_mask, node_mask = children[k, :size], children[k, size:]
        z_sum = _masked(slot_mask, z_slots) + _masked(node_mask, z_nodes)
        y_sum = _masked(slot_mask, y_slots) + _masked(node_mask, y_nodes)
        z_k = jnp.where(is_parallel[k], 1.0 / jnp.where(y_sum == 0, 1.0, y_sum), z_sum)
        y_k = jnp.where(is_parallel[k], y_sum, 1.0 / jnp.where(z_sum == 0, 1.0, z_sum))
        return (z_nodes.at[k].set(z_k), y_nodes.at[k].set(y_k)), None

    empty = jnp.zeros((n, z_slots.shape[1]), jnp.complex128)
    (z_nodes, y_nodes), _ = jax.lax.scan(node, (empty, empty), jnp.arange(n))
    return z_nodes, y_nodes


def evaluate_program(program: Mapping[str, jnp.ndarray], theta, freq, *, layout: ProgramLayout):
    """Impedance of a padded circuit program (see `CircuitProgram`); pure, jittable, vmappable.

    ``program`` is `CircuitProgram.arrays()`, ``theta`` the (S, 4) parameters, ``freq`` in Hz,
    ``layout`` static. Unused slots are evaluated at their defaults and never referenced. Every
    slot's impedance and admittance is computed once, and each node sums its children's
    impedances (series) or admittances (parallel) as real mask-vector products on Re and Im:
    (S + 2N)·F complex divisions for S slots, N nodes and F frequencies.
    """
    omega = (2.0 * jnp.pi * jnp.asarray(freq))[None, :]
    z_slots = _slot_impedances(theta, omega, layout)
    z_nodes, _ = _node_values(program, z_slots, 1.0 / z_slots, layout)
    return z_nodes[program["root"] - layout.n_slots]


def program_value_and_columns(program: Mapping[str, jnp.ndarray], theta, freq, wanted, *, layout: ProgramLayout):
    """(Z, ∂Z/∂θ) of a padded program: the impedance (F,) and the derivative columns (K, F)
    for the flattened parameter positions ``wanted`` (K,) into ``theta.ravel()`` (position
    4·S gives a zero column: padding). Pure, jittable, vmappable; the analytic counterpart of
    forward-mode differentiation through `evaluate_program`, at the cost of about two
    evaluations whatever K is.

    Each slot's own derivatives ∂z_s/∂θ_(s,i) come from its element formula (a JVP on that
    kind's slots only); the root's sensitivity to every value v, ∂Z/∂z_v, is carried down
    from the root in reverse topological order by the chain rule: 1 through a series node,
    (z_node/z_v)² = z_node²·y_v² through a parallel one (its impedance is 1/Σ 1/z_c). Then
    ∂Z/∂θ_(s,i) = ∂Z/∂z_s · ∂z_s/∂θ_(s,i).
    """
    omega = (2.0 * jnp.pi * jnp.asarray(freq))[None, :]
    n_freq = omega.shape[1]
    size, n = layout.n_slots, layout.n_nodes
    z_slots, slot_columns = _slot_impedances(theta, omega, layout, derivatives=True)
    y_slots = 1.0 / z_slots
    z_nodes, y_nodes = _node_values(program, z_slots, y_slots, layout)
    children, is_parallel = jnp.asarray(program["children"]), jnp.asarray(program["is_parallel"])
    root = program["root"] - size

    def node(carry, k):
        """Pass node k's sensitivity on to its children (nodes come before their parents)."""
        node_sense, slot_sense = carry
        sense = node_sense[k]
        through_parallel = z_nodes[k] ** 2 * sense
        slot_sense = slot_sense + children[k, :size, None] * jnp.where(is_parallel[k], through_parallel[None, :] * y_slots**2, sense[None, :])
        node_sense = node_sense + children[k, size:, None] * jnp.where(is_parallel[k], through_parallel[None, :] * y_nodes**2, sense[None, :])
        return (node_sense, slot_sense), None

    at_root = (jnp.arange(n) == root)[:, None] * jnp.ones((1, n_freq), jnp.complex128)
    (_, slot_sense), _ = jax.lax.scan(node, (at_root, jnp.zeros((size, n_freq), jnp.complex128)), jnp.arange(n), reverse=True)
    columns = slot_columns * slot_sense[:, None, :]  # (S, 4, F)
    flat = jnp.concatenate([columns.reshape(size * theta.shape[1], n_freq), jnp.zeros((1, n_freq), jnp.complex128)])
    return z_nodes[root], flat[wanted]
