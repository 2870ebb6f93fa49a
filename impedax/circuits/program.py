"""A circuit as padded arrays, so one compiled evaluator serves many topologies.

`CircuitProgram` describes a circuit by element kinds per slot and its series/parallel nodes
as child masks in topological order. One jitted evaluator, `evaluate_program`, serves every
topology of the same `ProgramLayout`, so a fitter compiled once can fit many candidate
circuits, even together under ``vmap``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import jax.numpy as jnp
import numpy as np

from ..errors import CircuitError, ParameterError
from .compile import check_element_names
from .elements import DEFAULT_REGISTRY
from .parser import parse
from .spec import MAX_ELEMENT_PARAMS, Registry
from .tree import Circuit, Element, Parallel

__all__ = ["ProgramLayout", "CircuitProgram", "PROGRAM_SCALES", "default_theta", "evaluate_program"]


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

    def arrays(self) -> dict[str, jnp.ndarray]:
        """The program's data (a pytree that can be stacked and vmapped across circuits)."""
        return {
            "is_parallel": jnp.asarray(self.is_parallel),
            "children": jnp.asarray(self.children),
            "root": jnp.asarray(self.root, jnp.int32),
        }

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


def evaluate_program(program: Mapping[str, jnp.ndarray], theta, freq, *, layout: ProgramLayout):
    """Impedance of a padded circuit program (see `CircuitProgram`); pure, jittable, vmappable.

    ``program`` is `CircuitProgram.arrays()`, ``theta`` the (S, 4) parameters, ``freq`` in Hz,
    ``layout`` static. Unused slots are evaluated at their defaults and never referenced. Every
    slot's impedance and admittance is computed once, and each node sums its children's
    impedances (series) or admittances (parallel) as real mask-vector products on Re and Im:
    (S + 2N)·F complex divisions for S slots, N nodes and F frequencies.
    """
    omega = (2.0 * jnp.pi * jnp.asarray(freq))[None, :]
    parts = []
    for k, spec in enumerate(layout.registry.specs):
        rows = theta[layout.slots_of(k)]
        if rows.shape[0] == 0:
            continue
        z_k = spec.impedance(omega, *(rows[:, i : i + 1] for i in range(len(spec.parameters))))
        parts.append(jnp.broadcast_to(z_k, (rows.shape[0], omega.shape[1])).astype(jnp.complex128))
    size, n = layout.n_slots, layout.n_nodes
    ones = jnp.ones((n, omega.shape[1]), jnp.complex128)
    z = jnp.concatenate(parts + [ones], axis=0)
    y = jnp.concatenate([1.0 / zp for zp in parts] + [ones], axis=0)
    children, is_parallel = program["children"], program["is_parallel"]
    for k in range(n):
        mask = children[k]
        z_sum = (mask @ z.real) + 1j * (mask @ z.imag)
        y_sum = (mask @ y.real) + 1j * (mask @ y.imag)
        z_node = jnp.where(is_parallel[k], 1.0 / jnp.where(y_sum == 0, 1.0, y_sum), z_sum)
        y_node = jnp.where(is_parallel[k], y_sum, 1.0 / jnp.where(z_sum == 0, 1.0, z_sum))
        z = z.at[size + k].set(z_node)
        y = y.at[size + k].set(y_node)
    return z[program["root"]]
