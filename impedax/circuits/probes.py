"""Probes: transfer functions inside a network driven by a unit voltage source across its
terminals — the voltage across, or the current through, one element or block.

Each probe is a pure ``fn(params, freq) -> complex`` (jittable, differentiable), built from the
node functions of `impedax.circuits.compile`: walking from the root to the target, a series
node passes the current on (V_child = I Z_child) and a parallel node the voltage
(I_child = V / Z_child).
"""

from __future__ import annotations

from typing import Iterable, Mapping

import jax.numpy as jnp

from ..arguments import closest_name, shown
from ..errors import CircuitError, ParameterError
from .compile import check_element_names, checked_parameters, node_function
from .elements import DEFAULT_REGISTRY
from .parser import parse
from .spec import Registry
from .tree import Circuit, Series

__all__ = ["voltage_across", "current_through"]


def _resolve_target(circuit: Circuit, names: frozenset[str]):
    """Path of (node, child index) steps from the root to the target, plus the selected
    children of the last node when the target is a group of series siblings."""
    unknown = sorted(names - set(circuit.element_names))
    if unknown:
        close = closest_name(unknown[0], circuit.element_names)
        hint = f"; did you mean {close!r}?" if close else ""
        raise CircuitError(f"no element(s) {', '.join(map(repr, unknown))} in {circuit}{hint}")
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


def _target_names(target) -> frozenset[str]:
    """The element names of a probe's ``target`` (one name, or an iterable of names), each
    stripped of surrounding whitespace (no element name holds any); `ParameterError` for
    anything else or for no name at all."""
    if isinstance(target, str):
        items = [target]
    elif isinstance(target, (bytes, Mapping)) or not hasattr(target, "__iter__"):
        raise ParameterError(f"target must be an element name or a set of element names (e.g. {{'C_i', 'R_sc'}}), got {shown(target)} ({type(target).__name__})")
    else:
        items = list(target)
    for item in items:
        if not isinstance(item, str):
            raise ParameterError(f"target: element names are text, got {shown(item)} ({type(item).__name__})")
    names = frozenset(item.strip() for item in items)
    if not names or names == {""}:
        raise ParameterError(f"target names no element, got {shown(target)}: name one element or a block of them")
    return names


def _probe(circuit, target, registry, quantity: str):
    circuit = parse(circuit, registry)
    check_element_names(circuit, registry)
    names = _target_names(target)
    path, chosen = _resolve_target(circuit, names)
    parameter_names = circuit.parameter_names(registry)
    root_fn = node_function(circuit, registry)
    step_fns = [[node_function(c, registry) for c in node.children] for node, _ in path]
    last = path[-1][0].children[path[-1][1]] if path else circuit
    chosen_fns = None if chosen is None else [node_function(last.children[i], registry) for i in chosen]

    def fn(params, freq):
        params = checked_parameters(circuit, parameter_names, params, freq)  # (the compiled circuit's checks)
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
    Returns ``fn(params, freq) -> complex`` (dimensionless), which checks its arguments as a
    compiled circuit does (`compile.checked_parameters`: every parameter of ``circuit``, numbers
    that broadcast against ``freq``, positive frequencies) and stays jittable.
    """
    return _probe(circuit, target, registry, "voltage")


def current_through(circuit: Circuit | str, target: str | Iterable[str], registry: Registry = DEFAULT_REGISTRY):
    """Transfer function I_target/V_source [S]; e.g. Meyer's Q_f/V_A = I_Rsc/(jω V_A)."""
    return _probe(circuit, target, registry, "current")
