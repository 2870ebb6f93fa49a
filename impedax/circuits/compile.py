"""Compile a circuit tree into pure JAX functions.

Two forms:

* `compile_circuit` closes over the tree and gives ``fn(params, freq) -> Z`` for one circuit
  (fastest evaluation; one XLA program per circuit).
* `CircuitProgram` describes a circuit as padded arrays (element kinds per slot, and the
  series/parallel nodes as child masks in topological order). One jitted evaluator,
  `evaluate_program`, serves every topology of the same padded size, so a fitter compiled
  once can fit many candidate circuits, even together under ``vmap``.

Probes (`voltage_across`, `current_through`) give transfer functions of a network driven by
a unit voltage source across its terminals.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Iterable, Mapping

import jax
import jax.numpy as jnp
import numpy as np

from ..errors import CircuitError, ParameterError
from .elements import DEFAULT_REGISTRY, MAX_ELEMENT_PARAMS, Registry
from .tree import Circuit, Element, Parallel, Series

__all__ = [
    "CompiledCircuit",
    "compile_circuit",
    "voltage_across",
    "current_through",
    "CircuitProgram",
    "evaluate_program",
    "ProgramLayout",
    "default_theta",
]


def _check_names(circuit: Circuit, registry: Registry) -> None:
    seen = set()
    for e in circuit.elements():
        registry[e.symbol]  # raises for an unknown symbol
        if e.name in seen:
            raise CircuitError(f"duplicate element name {e.name!r} in {circuit}")
        seen.add(e.name)


def _element_fn(e: Element, registry: Registry, form: str = "Z"):
    spec = registry[e.symbol]
    names = spec.parameter_names(e.name)
    own, invert = _element_formula(spec, form)

    def fn(params, omega):
        value = own(omega, *(params[n] for n in names))
        return 1.0 / value if invert else value

    return fn


def _element_formula(spec, form: str):
    """(formula, invert): the element's own formula for ``form`` ("Z" impedance, "Y"
    admittance), and whether its value must be inverted to get there."""
    if form == "Y" and spec.admittance is not None:
        return spec.admittance, False
    return spec.impedance, form == "Y"


def _node_fn(node: Circuit, registry: Registry, form: str = "Z"):
    """Trace-time recursion: returns ``fn(params, omega)`` giving the node's impedance
    (``form="Z"``) or admittance (``"Y"``). A parallel node sums its children's admittances,
    taken from the elements' own admittance formulas where they have one."""
    if isinstance(node, Element):
        return _element_fn(node, registry, form)
    parallel = isinstance(node, Parallel)
    child_fns = [_node_fn(c, registry, "Y" if parallel else "Z") for c in node.children]

    def fn(params, omega):
        total = child_fns[0](params, omega)
        for f in child_fns[1:]:
            total = total + f(params, omega)
        return total if (form == "Y") == parallel else 1.0 / total

    return fn


def _element_derivatives_fn(e: Element, registry: Registry, index: Mapping[str, int], form: str):
    """``fn(theta, omega, wanted) -> (value, {parameter index: ∂value/∂θ})`` for one element,
    value its impedance or admittance (``form``); its own derivatives by forward mode
    (elementwise over ω, one tangent per parameter in ``wanted``). Where only the other
    formula exists, Y = 1/Z and ∂Y = −Y²·∂Z."""
    spec = registry[e.symbol]
    columns = [index[n] for n in spec.parameter_names(e.name)]
    own, invert = _element_formula(spec, form)

    def fn(theta, omega, wanted):
        values = tuple(theta[i] for i in columns)
        formula = lambda *v: own(omega, *v)  # noqa: E731
        value = formula(*values)
        rows = {}
        for k, i in enumerate(columns):
            if i in wanted:
                tangent = tuple(jnp.ones_like(v) if j == k else jnp.zeros_like(v) for j, v in enumerate(values))
                rows[i] = jax.jvp(formula, values, tangent)[1]
        if invert:
            value = 1.0 / value
            factor = -value * value
            rows = {i: factor * d for i, d in rows.items()}
        return value, rows

    return fn


def _node_derivatives_fn(node: Circuit, registry: Registry, index: Mapping[str, int], form: str = "Z"):
    """Trace-time recursion for `CompiledCircuit.value_and_jacobian`: ``fn(theta, omega,
    wanted)`` gives the node's impedance or admittance (``form``) and its derivatives by the
    parameters in ``wanted``. Sums pass derivatives through (Z = Σ Z_i in series, Y = Σ Y_i in
    parallel); changing form uses ∂(1/v) = −(1/v)²·∂v, so every column costs one complex
    product per change of form on its way to the root."""
    if isinstance(node, Element):
        return _element_derivatives_fn(node, registry, index, form)
    parallel = isinstance(node, Parallel)
    child_fns = [_node_derivatives_fn(c, registry, index, "Y" if parallel else "Z") for c in node.children]

    def fn(theta, omega, wanted):
        total, rows = child_fns[0](theta, omega, wanted)
        for f in child_fns[1:]:
            value, more = f(theta, omega, wanted)
            total, rows = total + value, {**rows, **more}
        if (form == "Y") == parallel:
            return total, rows
        value = 1.0 / total
        factor = -value * value
        return value, {i: factor * d for i, d in rows.items()}

    return fn


@dataclass(frozen=True, eq=False)
class CompiledCircuit:
    """A circuit compiled to a pure function; call as ``compiled(params, freq)``.

    ``params`` maps parameter names to values (scalars or arrays that broadcast against
    ``freq``); ``freq`` is in Hz. Returns the complex impedance [Ω]. Works under
    ``jax.jit``, ``jax.vmap`` and ``jax.grad``.
    """

    circuit: Circuit
    registry: Registry
    parameter_names: tuple[str, ...]
    _fn: Callable = field(repr=False)
    _jacobian_fn: Callable = field(repr=False)

    def __call__(self, params: Mapping[str, object], freq) -> jnp.ndarray:
        missing = [n for n in self.parameter_names if n not in params]
        if missing:
            raise ParameterError(f"missing parameter(s) {', '.join(missing)} for circuit {self.circuit}")
        omega = 2.0 * jnp.pi * jnp.asarray(freq)
        return self._fn(params, omega)

    def vector(self, theta, freq) -> jnp.ndarray:
        """Evaluate with ``theta`` an array in ``parameter_names`` order."""
        return self(self.unpack(theta), freq)

    def unpack(self, theta) -> dict:
        return {n: theta[..., i] for i, n in enumerate(self.parameter_names)}

    def value_and_jacobian(self, theta, freq):
        """``(Z, J)`` with Z (F,) and J = ∂Z/∂θ (F, P) complex, for ``theta`` (P,) in
        ``parameter_names`` order. J is assembled from the elements' own derivatives and
        the chain rule through the tree (`_node_derivatives_fn`), several times cheaper
        than forward mode through the whole circuit; it is what the least-squares solvers use."""
        z, columns = self.value_and_columns(theta, freq, range(len(self.parameter_names)))
        return z, jnp.stack(columns, axis=-1)

    def value_and_columns(self, theta, freq, wanted):
        """``(Z, [∂Z/∂θ_i for i in wanted])``, each (F,) complex; ``theta`` is anything
        indexable by parameter position (an array, or a tuple of scalars), ``wanted`` a static
        sequence of positions. Derivatives not wanted are never traced."""
        omega = 2.0 * jnp.pi * jnp.asarray(freq, jnp.float64)
        wanted = tuple(int(i) for i in wanted)
        z, rows = self._jacobian_fn(theta, omega, frozenset(wanted))
        full = lambda v: jnp.broadcast_to(v, omega.shape).astype(jnp.complex128)  # noqa: E731
        return full(z), [full(rows[i]) for i in wanted]


def compile_circuit(circuit: Circuit | str, registry: Registry = DEFAULT_REGISTRY) -> CompiledCircuit:
    """Compile ``circuit`` once into a pure ``fn(params, freq) -> Z`` (no string work when called)."""
    from .parser import parse

    circuit = parse(circuit, registry)
    _check_names(circuit, registry)
    names = circuit.parameter_names(registry)
    index = {n: i for i, n in enumerate(names)}
    return CompiledCircuit(circuit, registry, names, _node_fn(circuit, registry), _node_derivatives_fn(circuit, registry, index))


# --- probes ---------------------------------------------------------------------------------


def _resolve_target(circuit: Circuit, names: frozenset[str]):
    """Path of (node, child index) steps from the root to the target, plus the selected
    children of the last node when the target is a group of series siblings."""
    unknown = names - set(circuit.element_names)
    if unknown:
        raise CircuitError(f"no element(s) {', '.join(sorted(unknown))} in {circuit}")
    path = []
    node = circuit
    while True:
        if set(node.element_names) == names:
            return path, None
        holder = [i for i, c in enumerate(node.children) if names <= set(c.element_names)]
        if holder:
            path.append((node, holder[0]))
            node = node.children[holder[0]]
            continue
        if isinstance(node, Series):
            chosen = [i for i, c in enumerate(node.children) if set(c.element_names) & names]
            if set().union(*(set(node.children[i].element_names) for i in chosen)) == names:
                return path, tuple(chosen)
        raise CircuitError(
            f"{', '.join(sorted(names))} do not form a two-terminal block of {circuit}: "
            "name one element, a whole parenthesised block, or series neighbours"
        )


def _probe(circuit, target, registry, quantity: str):
    from .parser import parse

    circuit = parse(circuit, registry)
    _check_names(circuit, registry)
    names = frozenset([target] if isinstance(target, str) else target)
    path, chosen = _resolve_target(circuit, names)
    root_fn = _node_fn(circuit, registry)
    step_fns = [[_node_fn(c, registry) for c in node.children] for node, _ in path]
    last = path[-1][0].children[path[-1][1]] if path else circuit
    chosen_fns = None if chosen is None else [_node_fn(last.children[i], registry) for i in chosen]

    def fn(params, freq):
        omega = 2.0 * jnp.pi * jnp.asarray(freq)
        z = root_fn(params, omega)
        voltage, current = jnp.ones_like(z), 1.0 / z  # unit source across the terminals
        for (node, index), fns in zip(path, step_fns):
            z_child = fns[index](params, omega)
            if isinstance(node, Series):
                voltage = current * z_child
            else:
                current = voltage / z_child
        if chosen_fns is not None:
            z_sel = sum(f(params, omega) for f in chosen_fns)
            voltage = current * z_sel
        return voltage if quantity == "voltage" else current

    return fn


def voltage_across(circuit: Circuit | str, target: str | Iterable[str], registry: Registry = DEFAULT_REGISTRY):
    """Transfer function V_target/V_source for a source across the circuit's terminals.

    ``target`` is an element name or a set of names forming a block (a parenthesised group, or
    neighbours in one series chain: Meyer's V_F is ``{"C_i", "R_sc", "C_sc"}``).
    Returns ``fn(params, freq) -> complex`` (dimensionless).
    """
    return _probe(circuit, target, registry, "voltage")


def current_through(circuit: Circuit | str, target: str | Iterable[str], registry: Registry = DEFAULT_REGISTRY):
    """Transfer function I_target/V_source [S]; e.g. Meyer's Q_f/V_A = I_Rsc/(jω V_A)."""
    return _probe(circuit, target, registry, "current")


# --- padded programs ------------------------------------------------------------------------


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
        """Layout ``scale`` (1, 2, 4): room for 6·scale R, 4·scale C and CPE, 2·scale of the rest."""
        base = {"R": 6, "C": 4, "CPE": 4}
        caps = tuple(base.get(spec.symbol, 2) * scale for spec in registry.specs)
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
        from .parser import parse

        circuit = parse(circuit, registry)
        _check_names(circuit, registry)
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
    ``layout`` static. Unused slots are evaluated at their defaults and never referenced.
    """
    omega = (2.0 * jnp.pi * jnp.asarray(freq))[None, :]
    parts = []
    for k, spec in enumerate(layout.registry.specs):
        rows = theta[layout.slots_of(k)]
        z_k = spec.impedance(omega, *(rows[:, i : i + 1] for i in range(len(spec.parameters))))
        parts.append(jnp.broadcast_to(z_k, (rows.shape[0], omega.shape[1])).astype(jnp.complex128))
    size, n = layout.n_slots, layout.n_nodes
    values = jnp.concatenate(parts + [jnp.ones((n, omega.shape[1]), jnp.complex128)], axis=0)
    children, is_parallel = program["children"], program["is_parallel"]
    for k in range(n):
        mask = children[k][:, None]
        z_sum = jnp.sum(mask * values, axis=0)
        # unused rows (padding nodes hold 0) must not enter 1/Z, not even masked out
        y_sum = jnp.sum(mask / jnp.where(mask > 0, values, 1.0), axis=0)
        z_par = 1.0 / jnp.where(y_sum == 0, 1.0, y_sum)
        values = values.at[size + k].set(jnp.where(is_parallel[k], z_par, z_sum))
    return values[program["root"]]
