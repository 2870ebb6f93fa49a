"""Compile a circuit tree into pure JAX functions.

`compile_circuit` closes over the tree and gives ``fn(params, freq) -> Z`` for one circuit
(fastest evaluation; one XLA program per circuit), with an analytic Jacobian assembled from
the elements' own derivatives. The other compiled forms build on the node functions here:
`impedax.circuits.probes` (transfer functions inside the network) and
`impedax.circuits.program` (padded arrays: one evaluator for many topologies).
"""

from __future__ import annotations

import functools
import inspect
import traceback
from dataclasses import dataclass, field
from typing import Callable, Iterable, Mapping

import jax
import jax.numpy as jnp
import numpy as np

from ..arguments import MAX_MESSAGE, shown, unknown_parameter
from ..data import checked_frequencies
from ..errors import CircuitError, ParameterError
from .elements import DEFAULT_REGISTRY
from .parser import parse
from .spec import ElementSpec, Registry
from .tree import Circuit, Element, Parallel

__all__ = ["CompiledCircuit", "compile_circuit", "check_element_names", "check_user_elements", "checked_parameters", "node_function"]

# frequencies a user's element is traced at once (`check_user_elements`): a sweep's usual length
TRIAL_FREQUENCIES = 30
BUILT_IN_SPECS = frozenset(DEFAULT_REGISTRY.specs)


def check_element_names(circuit: Circuit, registry: Registry) -> None:
    """Raise `CircuitError` for an unknown symbol or a repeated element name in a built tree."""
    seen = set()
    for e in circuit.elements():
        registry[e.symbol]  # raises for an unknown symbol
        if e.name in seen:
            raise CircuitError(f"duplicate element name {e.name!r} in {circuit}")
        seen.add(e.name)


def check_user_elements(specs: Iterable[ElementSpec]) -> None:
    """Raise `CircuitError` naming the element when a user's formula (a spec not built in)
    cannot run as the solvers run it: traced by JAX with ω of shape (F,) and scalar
    parameters, returning an array that broadcasts to (F,). Each spec is traced once per
    session (cached): a formula written with NumPy, ``float()`` or a Python ``if`` on a
    parameter failed deep in a solver, and a wrong shape as an ``add`` of (30,) and (3,)."""
    for spec in specs:
        if spec not in BUILT_IN_SPECS:
            _check_user_element(spec)


def _formula_at(formula, exc: BaseException | None = None) -> str:
    """`` (FILE, line N)``: where a user's ``formula`` is — the line of its own file ``exc`` was
    raised on (its innermost such frame), else the line it is defined on; "" for a formula with
    no source file (a callable object, one typed at a prompt)."""
    code = getattr(inspect.unwrap(formula), "__code__", None)  # (a --plugin formula is wrapped to print to stderr)
    if code is None or code.co_filename.startswith("<"):
        return ""
    raised = [frame.lineno for frame in traceback.extract_tb(exc.__traceback__) if frame.filename == code.co_filename] if exc is not None else []
    return f" ({code.co_filename}, line {raised[-1] if raised else code.co_firstlineno})"


@functools.lru_cache(maxsize=None)
def _check_user_element(spec: ElementSpec) -> None:
    omega = jax.ShapeDtypeStruct((TRIAL_FREQUENCIES,), jnp.float64)
    scalars = [jax.ShapeDtypeStruct((), jnp.float64)] * len(spec.parameters)
    for form, formula in (("impedance", spec.impedance), ("admittance", spec.admittance)):
        if formula is None:
            continue
        try:
            out = jax.eval_shape(formula, omega, *scalars)
        except Exception as exc:  # (whatever a user's formula raises when traced)
            reason = (str(exc).strip().splitlines() or [""])[0][:MAX_MESSAGE // 2]
            raise CircuitError(
                f"element {spec.symbol}: its {form} function{_formula_at(formula, exc)} failed under JAX ({type(exc).__name__}: {reason}); "
                "write it with jax.numpy (jnp) rather than numpy or math, and with jnp.where rather than a Python if or float() on its arguments"
            ) from None
        shape = getattr(out, "shape", None)
        if not isinstance(out, jax.ShapeDtypeStruct) or not np.issubdtype(out.dtype, np.number):
            raise CircuitError(f"element {spec.symbol}: its {form} function{_formula_at(formula)} returns {type(out).__name__}, not an array of numbers")
        try:
            fits = np.broadcast_shapes(shape, omega.shape) == omega.shape
        except ValueError:
            fits = False
        if not fits:
            raise CircuitError(
                f"element {spec.symbol}: its {form} function{_formula_at(formula)} returns shape {shape} for {TRIAL_FREQUENCIES} frequencies; "
                f"it must return one value per frequency (shape ({TRIAL_FREQUENCIES},)) or a scalar"
            )


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


def node_function(node: Circuit, registry: Registry, form: str = "Z"):
    """Trace-time recursion: returns ``fn(params, omega)`` giving the node's impedance
    (``form="Z"``) or admittance (``"Y"``). A parallel node sums its children's admittances,
    taken from the elements' own admittance formulas where they have one."""
    if isinstance(node, Element):
        return _element_fn(node, registry, form)
    parallel = isinstance(node, Parallel)
    child_fns = [node_function(c, registry, "Y" if parallel else "Z") for c in node.children]

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


def checked_parameters(circuit: Circuit, names: tuple[str, ...], params, freq) -> dict:
    """The arguments of a compiled function of ``circuit`` (`CompiledCircuit`, the probes),
    checked: ``{name: value}`` for its parameters ``names``, a list or tuple as a JAX array.
    `ParameterError` for a ``params`` that is not a mapping, lacks a parameter (naming an
    unknown key, with the closest name, when one is there instead), holds a value that is not
    numbers, or one whose shape does not broadcast against ``freq`` and the values before it;
    `DataError` for concrete frequencies that are not finite and positive. Only what is static
    under ``jit`` is read (keys, dtypes, shapes): JAX tracers pass the value checks, and under
    ``jit`` this runs once, at trace time. Keys beyond the parameters are allowed when none is
    missing (a model's parameter draws hold more than one circuit's parameters). The values
    themselves (a negative R, an α of 2) are not checked: docs/circuits.md, "Compiled forms"."""
    if not isinstance(params, Mapping):
        raise ParameterError(f"params must be a mapping parameter name → value, got {shown(params)} ({type(params).__name__})")
    missing = [n for n in names if n not in params]
    if missing:
        unknown = [k for k in params if k not in names]
        if unknown:
            raise unknown_parameter("params", unknown[0], names, circuit)
        raise ParameterError(f"missing parameter(s) {', '.join(missing)} for circuit {circuit}")
    values = {}
    for n in names:
        value = params[n]
        if not _is_numbers(value):
            raise ParameterError(f"params[{n!r}] must be a number or an array of numbers, got {shown(value)} ({type(value).__name__})")
        values[n] = jnp.asarray(value) if isinstance(value, (list, tuple)) else value
    if not isinstance(freq, jax.core.Tracer):
        freq = checked_frequencies(freq, ndim_max=None)
    freq_shape = tuple(np.shape(freq))
    shape = freq_shape
    same_rank = jax.config.jax_numpy_rank_promotion == "raise"  # (JAX set to refuse (2, 1) against (31,))
    for n, value in values.items():
        own = tuple(np.shape(value))
        try:
            if same_rank and own and shape and len(own) != len(shape):
                raise ValueError("rank promotion")
            shape = np.broadcast_shapes(shape, own)
        except ValueError:
            others = "" if shape == freq_shape else f" and the parameters before it (together {shape})"
            raise ParameterError(
                f"params[{n!r}] has shape {own}, which does not broadcast against freq's shape {freq_shape}{others}: "
                "give a number, an array that broadcasts (a column (k, 1) for a row of frequencies), or use jax.vmap"
            ) from None
    return values


def _names_text(names: tuple[str, ...], limit: int = MAX_MESSAGE // 2) -> str:
    """The parameter names, comma-separated, cut to about ``limit`` characters."""
    text = ", ".join(names)
    return text if len(text) <= limit else text[: limit - 1].rsplit(", ", 1)[0] + ", …"


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
        values = checked_parameters(self.circuit, self.parameter_names, params, freq)
        omega = 2.0 * jnp.pi * jnp.asarray(freq)
        return self._fn(values, omega)

    def check_arguments(self, params, freq) -> None:
        """Raise for arguments ``compiled(params, freq)`` would refuse (`checked_parameters`:
        a missing or mistyped name, a value that is not numbers or whose shape does not
        broadcast against ``freq``, bad concrete frequencies)."""
        checked_parameters(self.circuit, self.parameter_names, params, freq)

    def vector(self, theta, freq) -> jnp.ndarray:
        """Evaluate with ``theta`` an array (..., P) in ``parameter_names`` order (a list or
        tuple too); its last axis must hold exactly the P parameters."""
        return self(self.unpack(theta), freq)

    def unpack(self, theta) -> dict:
        """``{name: theta[..., i]}`` for ``theta`` (..., P) in ``parameter_names`` order."""
        theta = self._checked_theta(theta)
        return {n: theta[..., i] for i, n in enumerate(self.parameter_names)}

    def _checked_theta(self, theta, *, vector: bool = False):
        """``theta`` as a JAX array whose last axis holds the P parameters (only that axis if
        ``vector``); `ParameterError` otherwise. Shapes are static: checked at trace time."""
        try:
            theta = jnp.asarray(theta)
        except (TypeError, ValueError):
            raise ParameterError(f"theta must be an array of the circuit's {len(self.parameter_names)} parameter values, got {shown(theta)}") from None
        if theta.dtype == bool or not np.issubdtype(theta.dtype, np.number):
            raise ParameterError(f"theta must be numbers, got dtype {theta.dtype}")
        n = len(self.parameter_names)
        names = _names_text(self.parameter_names)
        if theta.ndim == 0 or theta.shape[-1] != n:
            got = "a single number" if theta.ndim == 0 else f"{theta.shape[-1]} values (last axis)"
            raise ParameterError(f"theta has {got}, the circuit has {n} parameters ({names})")
        if vector and theta.ndim != 1:
            raise ParameterError(f"theta must be one vector of the {n} parameters ({names}), got shape {theta.shape}; use jax.vmap for several")
        return theta

    def value_and_jacobian(self, theta, freq):
        """``(Z, J)`` with Z (F,) and J = ∂Z/∂θ (F, P) complex, for ``theta`` (P,) in
        ``parameter_names`` order (a list or tuple too). J is assembled from the elements' own
        derivatives and the chain rule through the tree (`_node_derivatives_fn`), several times
        cheaper than forward mode through the whole circuit; it is what the least-squares
        solvers use."""
        theta = self._checked_theta(theta, vector=True)
        if not isinstance(freq, jax.core.Tracer):
            checked_frequencies(freq, ndim_max=None)
        z, columns = self.value_and_columns(theta, freq, range(len(self.parameter_names)))
        return z, jnp.stack(columns, axis=-1)

    def value_and_columns(self, theta, freq, wanted):
        """``(Z, [∂Z/∂θ_i for i in wanted])``, each (F,) complex; ``theta`` is anything
        indexable by parameter position (an array, or a tuple of scalars), ``wanted`` a static
        sequence of positions. Derivatives not wanted are never traced."""
        n = len(theta) if isinstance(theta, (tuple, list)) else (np.shape(theta) or (0,))[0]
        if n != len(self.parameter_names):  # (static: the length of a tuple, the shape of an array)
            raise ParameterError(f"theta has {n} values, the circuit has {len(self.parameter_names)} parameters ({_names_text(self.parameter_names)})")
        omega = 2.0 * jnp.pi * jnp.asarray(freq, jnp.float64)
        wanted = tuple(int(i) for i in wanted)
        z, rows = self._jacobian_fn(theta, omega, frozenset(wanted))
        full = lambda v: jnp.broadcast_to(v, omega.shape).astype(jnp.complex128)  # noqa: E731
        return full(z), [full(rows[i]) for i in wanted]


def _is_numbers(value) -> bool:
    """Whether a parameter value is numbers: a Python or NumPy number, an array of numbers or
    a JAX tracer (not a bool, a string or None)."""
    if isinstance(value, (float, int)) and not isinstance(value, bool):
        return True
    if isinstance(value, jax.core.Tracer):
        return True
    dtype = getattr(value, "dtype", None)
    if dtype is None:
        try:
            dtype = np.asarray(value).dtype
        except Exception:  # ragged lists and the like
            return False
    return np.dtype(dtype).kind in "iufc"


def compile_circuit(circuit: Circuit | str, registry: Registry = DEFAULT_REGISTRY) -> CompiledCircuit:
    """Compile ``circuit`` (a `Circuit` or its text) once into a pure ``fn(params, freq) -> Z``
    (`CompiledCircuit`; no string work when called): ``params`` maps each name of
    ``parameter_names`` to a value in SI units, ``freq`` is in Hz, Z in Ω. Each element gives
    its own impedance at ω = 2πf (its spec's formula, e.g. the CPE's Z = 1/(Q (jω)^α)); a
    series node sums impedances, Z = Σ Z_i, and a parallel node admittances, 1/Z = Σ 1/Z_i
    (docs/circuits.md). Unknown element types and repeated names raise `CircuitError` (in
    text: `CircuitSyntaxError` from `parse`, with a caret)."""
    circuit = parse(circuit, registry)
    check_element_names(circuit, registry)
    check_user_elements(dict.fromkeys(registry[e.symbol] for e in circuit.elements()))
    names = circuit.parameter_names(registry)
    index = {n: i for i, n in enumerate(names)}
    return CompiledCircuit(circuit, registry, names, node_function(circuit, registry), _node_derivatives_fn(circuit, registry, index))


def _compile_method(self: Circuit, registry: Registry = DEFAULT_REGISTRY) -> CompiledCircuit:
    """Compile into a pure ``fn(params, freq) -> Z``; see `compile_circuit`."""
    return compile_circuit(self, registry)


# `Circuit.compile` is public API; it is attached here, where the compiler lives, so that the
# tree module need not import the compiler (which imports the tree): no import cycle
Circuit.compile = _compile_method
