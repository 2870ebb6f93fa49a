"""Physical reparametrizations: sample physical quantities instead of circuit parameters.

A `Reparametrization` names new parameters (with units and bounds) and a pure JAX map from
them to the circuit parameters they replace. `impedax.sample` then places priors on, samples
and reports the physical quantities; the circuit parameters become derived quantities.

Ready-made: `gap_thickness_reparametrization` (C_gap = ε0 ε_r A / u, Sirin et al.;
docs/physics.md, "Sirin et al.") and `stratum_corneum_reparametrization` (R_sc = ρ_sc d_sc / A,
C_sc = ε0 ε_sc A / d_sc, Meyer 2012 eq 3.13; docs/physics.md, "Meyer (2012 thesis)"). They live
here rather than in `impedax.models` because `Posterior.from_xarray` rebuilds them from a saved
file and `impedax.fitting` exports them, and fitting does not import models.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np

from ...arguments import number_text, relative_permittivity
from ...errors import ArgumentNeeded, ParameterError
from ...constants import C_GAP_BOUNDS_F, EPSILON_0, EPSILON_AIR

__all__ = [
    "Reparametrization",
    "ReparametrizationKind",
    "rebuild",
    "gap_thickness_reparametrization",
    "gap_thickness_bounds",
    "implausible_gap_notes",
    "PLAUSIBLE_GAP_M",
    "AREA_UNIT_ADVICE",
    "stratum_corneum_reparametrization",
    "EPSILON_0",
]



class ReparametrizationKind(enum.StrEnum):
    """Which constructor built a reparametrization (stored with a saved posterior)."""

    CUSTOM = "custom"
    GAP_THICKNESS = "gap_thickness"
    STRATUM_CORNEUM = "stratum_corneum"


@dataclass(frozen=True)
class Reparametrization:
    """New parameters ``names`` (``units``, open ``lower`` / ``upper`` bounds) that replace the
    circuit parameters ``replaces`` through ``forward(new, constants) -> {replaced: value}``
    (pure JAX; ``new`` and ``constants`` are dicts by name). ``inverse(circuit_values,
    constants) -> {new: value}`` (numpy) places the walkers' start; without it the start is
    found numerically. ``kind`` names a built-in constructor so saved posteriors rebuild it.
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    lower: tuple[float, ...]
    upper: tuple[float, ...]
    replaces: tuple[str, ...]
    forward: Callable
    constants: tuple[tuple[str, float], ...] = ()
    # the inverse and the description only place the start and label the result: two maps equal in
    # everything else compile into one sampler (the built-in inverses are new bound methods per call)
    inverse: Callable | None = field(default=None, compare=False)
    kind: ReparametrizationKind = ReparametrizationKind.CUSTOM
    description: str = field(default="", compare=False)
    # (name, words) for a new parameter whose bound is set by an input, not by physics: its
    # pile-up warning names that input instead of asking whether the model lacks something
    bound_causes: tuple[tuple[str, str], ...] = field(default=(), compare=False)

    def __post_init__(self):
        if self.kind not in set(ReparametrizationKind):
            raise ParameterError(f"Reparametrization: unknown kind {self.kind!r}; choose one of {', '.join(ReparametrizationKind)}")
        object.__setattr__(self, "kind", ReparametrizationKind(self.kind))
        n = len(self.names)
        if not n or len(self.units) != n or len(self.lower) != n or len(self.upper) != n:
            raise ParameterError("Reparametrization: names, units, lower and upper need the same (non-zero) length")
        if not self.replaces:
            raise ParameterError("Reparametrization: replaces must name at least one circuit parameter")
        for name, lo, hi in zip(self.names, self.lower, self.upper):
            if not lo < hi:
                raise ParameterError(f"Reparametrization: bounds of {name}: lower {number_text(lo)} must be below upper {number_text(hi)}")

    @property
    def constant_values(self) -> dict[str, float]:
        return dict(self.constants)

    def circuit_values(self, new: Mapping[str, object]) -> dict:
        """The replaced circuit parameters for new-parameter values (JAX or numpy)."""
        return dict(self.forward(dict(new), self.constant_values))

    def start(self, circuit_values: Mapping[str, float]) -> dict[str, float]:
        """New-parameter values reproducing ``circuit_values`` (for the walkers' start)."""
        if self.inverse is not None:
            return {k: float(v) for k, v in self.inverse(dict(circuit_values), self.constant_values).items()}
        from scipy.optimize import least_squares

        target = np.array([math.log(circuit_values[n]) for n in self.replaces])
        lo = np.array([math.log(max(v, 1e-300)) if v > 0 else -50.0 for v in self.lower])
        hi = np.array([math.log(v) if math.isfinite(v) else 50.0 for v in self.upper])

        def residual(y):
            values = self.circuit_values({n: float(math.exp(v)) for n, v in zip(self.names, y)})
            return np.log(np.maximum([float(values[n]) for n in self.replaces], 1e-300)) - target

        sol = least_squares(residual, 0.5 * (lo + hi), bounds=(lo, hi))
        return {n: float(math.exp(v)) for n, v in zip(self.names, sol.x)}

    def describe(self) -> dict:
        """JSON-able description (stored with a saved posterior)."""
        return {
            "kind": self.kind.value, "names": list(self.names), "replaces": list(self.replaces), "constants": self.constant_values, "description": self.description,
            "lower": [float(v) for v in self.lower], "upper": [float(v) for v in self.upper],
        }


# --- the air gap (Sirin et al.) --------------------------------------------------------------


LEGACY_GAP_BOUNDS_M = (1e-9, 1e-3)
"""The bounds of u [m] every area had in older versions (1 nm–1 mm): a posterior they saved
without its bounds is rebuilt with them (`rebuild`)."""


PLAUSIBLE_GAP_M = LEGACY_GAP_BOUNDS_M
"""The air gaps a contact can hold (1 nm–1 mm: the papers' 0.1–10 µm with wide margins), far
inside `gap_thickness_bounds`, which follow the area and bound C_gap, not u: a posterior median
of u outside them is told to check the area's unit (`implausible_gap_notes`)."""


AREA_UNIT_ADVICE = "check the area's unit first"
"""The words that end a note on u at a bound of its range or outside `PLAUSIBLE_GAP_M` and start
its advice (`implausible_gap_notes`, `gap_thickness_reparametrization`'s bound cause): the gap
analysis replaces that advice where the area's unit cannot be the cause (`impedax.models.gap`)."""


def implausible_gap_notes(rp: Reparametrization | None, medians: Mapping[str, float]) -> list[str]:
    """A note for a gap thickness (``rp`` of kind `GAP_THICKNESS`) whose posterior median
    (``medians``: name → value) lies outside `PLAUSIBLE_GAP_M`: with ``area=200.0`` (m² for mm²)
    the sampler found u = 5.14 m, inside its area-following bounds, and said nothing."""
    if rp is None or rp.kind != ReparametrizationKind.GAP_THICKNESS:
        return []
    name, area = rp.names[0], dict(rp.constants).get("area", math.nan)
    u = float(medians.get(name, math.nan))
    low, high = PLAUSIBLE_GAP_M
    if not math.isfinite(u) or low <= u <= high:
        return []
    return [
        f"{name} = {u:.3g} m (posterior median) is no air gap ({low:g}–{high:g} m is): {AREA_UNIT_ADVICE}, A = {area:g} m² ({area * 1e6:g} mm²; "
        "200 mm² is 200e-6 m²), then the data"
    ]


def gap_thickness_bounds(area: float, eps_r: float = EPSILON_AIR) -> tuple[float, float]:
    """Bounds (lower, upper) of the gap thickness u [m] for ``area`` A [m²]: u = ε0 ε_r A/C at
    the upper and lower ends of `C_GAP_BOUNDS_F` (1 fF–100 µF), so every area bounds C_gap alike
    and the same data give the same C_gap whatever the area (11.5 pm–1.15 m at 130 mm²)."""
    _check_positive(area=area, eps_r=eps_r)
    relative_permittivity(eps_r, "eps_r")
    c_low, c_high = C_GAP_BOUNDS_F
    return EPSILON_0 * eps_r * area / c_high, EPSILON_0 * eps_r * area / c_low


def gap_thickness_reparametrization(element: str = "C_gap", *, area: float, eps_r: float = EPSILON_AIR, name: str = "u", lower: float | None = None, upper: float | None = None) -> Reparametrization:
    """Sample the air-gap thickness u [m] behind the capacitor ``element``:
    C_gap = ε0 ε_r A / u (parallel plates; Sirin et al., with ε_gap = 1.00059 for air).
    ``area`` A in m² (Sirin: 130 mm² = 1.3e-4 m²); u is bounded to (``lower``, ``upper``),
    by default `gap_thickness_bounds` (C_gap within 1 fF–100 µF: the bounds follow the area, as
    ``impedax gap``'s). u piled up at a bound means C_gap at 1 fF or 100 µF, or an ``area`` in
    the wrong unit: the warning says so (`bound_causes`).
    """
    _check_positive(area=area, eps_r=eps_r)
    relative_permittivity(eps_r, "eps_r")
    default_lower, default_upper = gap_thickness_bounds(area, eps_r)
    lower = default_lower if lower is None else lower
    upper = default_upper if upper is None else upper
    cause = (
        f"{element} = ε0·ε_r·A/{name} with A = {area:g} m² ({area * 1e6:g} mm²) and ε_r = {eps_r:g}: a {name} at a bound of its range means {element} at "
        f"{EPSILON_0 * eps_r * area / lower:.3g} F or {EPSILON_0 * eps_r * area / upper:.3g} F; {AREA_UNIT_ADVICE} (m²; "
        "200 mm² is 200e-6), then the bounds (lower=, upper=) and the data"
    )
    return Reparametrization(
        names=(name,), units=("m",), lower=(float(lower),), upper=(float(upper),), replaces=(element,),
        forward=_GapMap(element, name), constants=(("area", float(area)), ("eps_r", float(eps_r))),
        inverse=_GapMap(element, name).inverse, kind=ReparametrizationKind.GAP_THICKNESS,
        description=f"{element} = ε0·ε_r·A/{name} (A = {area:g} m², ε_r = {eps_r:g})", bound_causes=((name, cause),),
    )


@dataclass(frozen=True)
class _GapMap:
    element: str
    name: str

    def __call__(self, new, constants):
        return {self.element: EPSILON_0 * constants["eps_r"] * constants["area"] / new[self.name]}

    def inverse(self, circuit, constants):
        # (C_gap = 0, a fit at its lower bound: u = ∞, which a start clips onto u's upper bound;
        # REAL exampleData.csv's EDL fit ended there and `impedax gap` raised ZeroDivisionError)
        with np.errstate(divide="ignore"):
            return {self.name: EPSILON_0 * constants["eps_r"] * constants["area"] / np.asarray(circuit[self.element], float)}


# --- Meyer's stratum corneum --------------------------------------------------------------


@dataclass(frozen=True)
class _LayerMap:
    resistor: str
    capacitor: str
    names: tuple[str, str, str]  # resistivity, permittivity, thickness

    def __call__(self, new, constants):
        rho, eps, d = (new[n] for n in self.names)
        area = constants["area"]
        return {self.resistor: rho * d / area, self.capacitor: EPSILON_0 * eps * area / d}

    def inverse(self, circuit, constants):
        area, d = constants["area"], constants["d_start"]
        rho = circuit[self.resistor] * area / d
        eps = circuit[self.capacitor] * d / (EPSILON_0 * area)
        return dict(zip(self.names, (rho, eps, d)))


def stratum_corneum_reparametrization(resistor: str = "R_sc", capacitor: str = "C_sc", *, area: float = math.pi * 4e-3**2, d_start: float = 200e-6, names: tuple[str, str, str] = ("rho_sc", "eps_sc", "d_sc")) -> Reparametrization:
    """Sample the stratum corneum's resistivity ρ_sc [Ω·m], relative permittivity ε_sc and
    thickness d_sc [m] behind ``resistor`` and ``capacitor``: R_sc = ρ_sc d_sc / A,
    C_sc = ε0 ε_sc A / d_sc (Meyer 2012, eq 3.13; A = π(4 mm)² by default).

    Impedance fixes only R_sc and C_sc, so one combination of the three is set by the priors
    alone: give d_sc (or ε_sc) an informative prior. Walkers start at d_sc = ``d_start``.
    Bounds: ρ_sc in (1, 1e9) Ω·m, ε_sc in (1, 1e6), d_sc in (1e-7, 1e-2) m.
    """
    _check_positive(area=area, d_start=d_start)
    mapping = _LayerMap(resistor, capacitor, tuple(names))
    return Reparametrization(
        names=tuple(names), units=("ohm m", "1", "m"), lower=(1.0, 1.0, 1e-7), upper=(1e9, 1e6, 1e-2),
        replaces=(resistor, capacitor), forward=mapping, constants=(("area", float(area)), ("d_start", float(d_start))),
        inverse=mapping.inverse, kind=ReparametrizationKind.STRATUM_CORNEUM,
        description=f"{resistor} = {names[0]}·{names[2]}/A, {capacitor} = ε0·{names[1]}·A/{names[2]} (A = {area:g} m²)",
    )


def rebuild(description: Mapping) -> Reparametrization:
    """A built-in reparametrization from its `Reparametrization.describe` form."""
    kind, constants, replaces, names = description["kind"], dict(description["constants"]), list(description["replaces"]), list(description["names"])
    if kind == ReparametrizationKind.GAP_THICKNESS:
        bounds = dict(zip(("lower", "upper"), LEGACY_GAP_BOUNDS_M))  # (saved by older versions without them: those versions' default bounds)
        bounds.update({k: description[k][0] for k in ("lower", "upper") if k in description})
        return gap_thickness_reparametrization(replaces[0], area=constants["area"], eps_r=constants["eps_r"], name=names[0], **bounds)
    if kind == ReparametrizationKind.STRATUM_CORNEUM:
        return stratum_corneum_reparametrization(replaces[0], replaces[1], area=constants["area"], d_start=constants["d_start"], names=tuple(names))
    what = description.get("description") or f"{', '.join(names)} in place of {', '.join(replaces)}"
    raise ArgumentNeeded(f"the saved posterior used a custom reparametrization ({what}); pass it as reparametrization=")


def _check_positive(**values):
    for k, v in values.items():
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ParameterError(f"{k} must be a positive finite number (got {v!r})")
