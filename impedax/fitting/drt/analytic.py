"""Closed-form DRTs of circuit blocks, so a fitted circuit's DRT can be laid over the data's.

With Z(ω) = R_∞ + ∫ γ(ln τ)/(1 + jωτ) d ln τ and x = ln(τ/τ₀):
- R‖C: a delta of weight R at τ₀ = RC;
- ZARC / Cole–Cole R/(1 + (jωτ₀)^α) (and R‖CPE with τ₀ = (RQ)^{1/α}):
      γ = (R/2π) sin((1 − α)π) / (cosh(αx) − cos((1 − α)π))          (Fuoss & Kirkwood 1941);
- Havriliak–Negami R/(1 + (jωτ₀)^α)^β, with y = (τ/τ₀)^α:
      γ = (R/π) y^β sin(βθ) / (y² + 2y cos(απ) + 1)^{β/2},  θ = atan2(sin(απ), y + cos(απ))
      (Havriliak & Negami, Polymer 8 (1967) 161; Zorn, J. Polym. Sci. B 37 (1999) 1043).
R_∞, series L and series C are reported apart; ZARC/CPE blocks with α ≥ 0.99 are reported as
deltas (their peak is narrower than 0.03 decade). Warburg, Gerischer and other blocks have no
delta/closed form here and raise `CircuitError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...circuits.tree import Element, Parallel, Series
from ...data import concise_repr
from ...errors import CircuitError, ParameterError
from ...io.netcdf import result_dataset
from ..arcs import arc_taus
from ..frozen import FrozenResult, freeze_fields

# a ZARC with α ≥ 0.99 has a FWHM below 0.03 decade, finer than any τ grid it is drawn on:
# it is reported as a delta (an R‖C) at its τ₀
_DELTA_ALPHA = 0.99

__all__ = ["AnalyticDRT", "zarc_drt", "r_cpe_drt", "r_cpe_tau", "havriliak_negami_drt", "circuit_drt"]


def zarc_drt(tau, r: float, tau0: float, alpha: float) -> np.ndarray:
    """γ(τ) [Ω] of R/(1 + (jωτ₀)^α), 0 < α < 1 (α = 1 is a delta: use `circuit_drt`); zero
    for τ₀ = inf (the block shorts every finite frequency)."""
    if math.isinf(tau0):
        return np.zeros(np.shape(tau))
    x = np.log(np.asarray(tau, float) / tau0)
    phase = (1.0 - alpha) * math.pi
    return r / (2 * math.pi) * math.sin(phase) / (np.cosh(alpha * x) - math.cos(phase))


def r_cpe_tau(r: float, q: float, alpha: float) -> float:
    """τ₀ = (RQ)^{1/α} [s] of R in parallel with a CPE 1/(Q (jω)^α) (`arcs.arc_taus`); inf when α near 0 puts it
    beyond floating point, nan unless RQ > 0 and α > 0."""
    return float(arc_taus("CPE", r, q, alpha))


def r_cpe_drt(tau, r: float, q: float, alpha: float) -> np.ndarray:
    """γ(τ) [Ω] of R in parallel with a CPE 1/(Q (jω)^α): a ZARC with τ₀ = (RQ)^{1/α} (`r_cpe_tau`)."""
    return zarc_drt(tau, r, r_cpe_tau(r, q, alpha), alpha)


def havriliak_negami_drt(tau, r: float, tau0: float, alpha: float, beta: float) -> np.ndarray:
    """γ(τ) [Ω] of R/(1 + (jωτ₀)^α)^β, 0 < α ≤ 1, 0 < β ≤ 1 (not both 1)."""
    y = (np.asarray(tau, float) / tau0) ** alpha
    theta = np.arctan2(math.sin(alpha * math.pi), y + math.cos(alpha * math.pi))
    return r / math.pi * y**beta * np.sin(beta * theta) / (y * y + 2 * y * math.cos(alpha * math.pi) + 1) ** (beta / 2)


@dataclass(frozen=True, eq=False)
class AnalyticDRT(FrozenResult):
    """The DRT of a circuit: ``gamma`` [Ω] on ``tau`` [s] (continuous part), ``deltas``
    ((τ [s], R [Ω]) of ideal R‖C blocks), ``r_inf_ohm``, ``l_h``, ``c_f`` (inf: none) and the
    circuit text."""

    __repr__ = concise_repr  # (the generated one printed every array)

    tau: np.ndarray
    gamma: np.ndarray
    deltas: tuple[tuple[float, float], ...]
    r_inf_ohm: float
    l_h: float
    c_f: float
    circuit: str
    relaxations: tuple[tuple[float, float], ...] = ()  # (τ, R) per block: deltas and each continuous block's maximum

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    def to_xarray(self):
        import xarray as xr

        return result_dataset(xr.Dataset(
            {
                "gamma": ("tau", self.gamma, {"units": "ohm"}),
                "delta_tau": ("delta", np.array([d[0] for d in self.deltas], float), {"units": "s"}),
                "delta_r": ("delta", np.array([d[1] for d in self.deltas], float), {"units": "ohm"}),
                "r_inf": ((), self.r_inf_ohm, {"units": "ohm"}),
                "inductance": ((), self.l_h, {"units": "H"}),
                "capacitance": ((), self.c_f, {"units": "F"}),
            },
            coords={"tau": ("tau", self.tau, {"units": "s"})},
            attrs={"circuit": self.circuit, "method": "closed-form DRT of the circuit's blocks"},
        ).copy(deep=True))


def _value(values, name):
    try:
        return float(values[name])
    except KeyError:
        raise ParameterError(f"no value for parameter {name!r}") from None


def _block(node, values, tau, registry):
    """(γ on tau, deltas, r, l, inverse c) of one series block."""
    zero = np.zeros_like(tau)
    if isinstance(node, Element):
        symbol = registry[node.symbol].symbol
        if symbol == "R":
            return zero, [], _value(values, node.name), 0.0, 0.0
        if symbol == "L":
            return zero, [], 0.0, _value(values, node.name), 0.0
        if symbol == "C":
            return zero, [], 0.0, 0.0, 1.0 / _value(values, node.name)
        if symbol in ("CC", "HN"):
            r, t0, a = (_value(values, f"{node.name}.{p}") for p in ("R", "tau", "alpha"))
            b = _value(values, f"{node.name}.beta") if symbol == "HN" else 1.0
            if a >= _DELTA_ALPHA and b >= 1.0 - 1e-12:
                return zero, [(t0, r)], 0.0, 0.0, 0.0
            if symbol == "CC" or b >= 1.0 - 1e-12:
                return zarc_drt(tau, r, t0, a), [], 0.0, 0.0, 0.0
            return havriliak_negami_drt(tau, r, t0, a, b), [], 0.0, 0.0, 0.0
        raise CircuitError(f"element {node.name} ({symbol}) has no closed-form DRT in impedax; compute the DRT of the fitted spectrum instead (impedax.drt((f, Z_model)))")
    if isinstance(node, Parallel) and len(node.children) == 2 and all(isinstance(c, Element) for c in node.children):
        kinds = {registry[c.symbol].symbol: c for c in node.children}
        if "R" in kinds and "C" in kinds:
            r, c = _value(values, kinds["R"].name), _value(values, kinds["C"].name)
            return zero, [(r * c, r)], 0.0, 0.0, 0.0
        if "R" in kinds and "CPE" in kinds:
            r = _value(values, kinds["R"].name)
            q, a = _value(values, f"{kinds['CPE'].name}.Q"), _value(values, f"{kinds['CPE'].name}.alpha")
            if a >= _DELTA_ALPHA:
                return zero, [(r_cpe_tau(r, q, a), r)], 0.0, 0.0, 0.0
            return r_cpe_drt(tau, r, q, a), [], 0.0, 0.0, 0.0
    raise CircuitError(f"block {node} has no closed-form DRT in impedax (R‖C, R‖CPE, CC, HN, R, L, C in series do); compute the DRT of the fitted spectrum instead")


def circuit_drt(circuit, values=None, *, tau=None, registry=None) -> AnalyticDRT:
    """The closed-form DRT of a circuit of series blocks: R, L, C, R‖C, R‖CPE, CC and HN.

    ``circuit``: a circuit (tree or text) with ``values`` (name → value), or a `FitResult`
    (its circuit and fitted values). ``tau``: grid [s] (default: 10⁻⁸–10⁴ s, 20 per decade).
    Raises `CircuitError` for blocks without a closed form (Warburg, Gerischer, nested ladders).
    """
    from ...circuits import DEFAULT_REGISTRY, parse

    if hasattr(circuit, "circuit") and hasattr(circuit, "values") and values is None:
        registry = registry or getattr(circuit, "registry", None)
        circuit, values = circuit.circuit, circuit.values
    if isinstance(circuit, str):
        circuit = parse(circuit)
    registry = registry or DEFAULT_REGISTRY
    if values is None:
        raise ParameterError("circuit_drt needs parameter values (a mapping name → value) or a FitResult")
    tau = np.logspace(-8, 4, 241) if tau is None else np.asarray(tau, float)
    blocks = circuit.children if isinstance(circuit, Series) else (circuit,)
    gamma = np.zeros_like(tau)
    deltas, r_inf, l_h, inv_c = [], 0.0, 0.0, 0.0
    relax = []
    for node in blocks:
        g, d, r, l, ic = _block(node, values, tau, registry)
        gamma += g
        deltas += d
        r_inf, l_h, inv_c = r_inf + r, l_h + l, inv_c + ic
        relax += d
        if np.any(g > 0):
            relax.append((float(tau[int(np.argmax(g))]), float(np.trapezoid(g, np.log(tau)))))
    return AnalyticDRT(
        tau=tau, gamma=gamma, deltas=tuple(deltas), r_inf_ohm=r_inf, l_h=l_h, c_f=math.inf if inv_c == 0 else 1.0 / inv_c, circuit=str(circuit), relaxations=tuple(sorted(relax))
    )
