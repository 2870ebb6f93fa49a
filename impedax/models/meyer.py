"""Meyer (2012 thesis): electrostatic force on a fingertip touching a 3M MicroTouch screen.

Series chain from the source V_A to ground (thesis Fig 3.3 / A.1)::

    C_s + C_i + R_sc || C_sc + R_f          (RC variant)
    C_s + C_i + R_sc || CPE_sc + R_f        (fractional variant, thesis Fig 5.3 / ch. 6)

C_s is the cable capacitor, C_i the SiO2 insulator, R_sc ∥ C_sc the stratum corneum and R_f the
body. The finger voltage V_F (ITO to conductive tissue) is the voltage across {C_i, SC block};
the leaked charge Q_f is the charge that went through R_sc, Q_f = I_Rsc/(jω).

Force conventions: `force_time_average` is the time average over one period of eq 3.6/A.3 for a
sinusoidal drive of amplitude V_A (½ of the expression with the phasor magnitudes |V_F|², |Q_f|²);
`force_peak` the largest instantaneous force over a period (≥ twice the average: V_F and Q_f
are not in phase); the static forces (eqs 3.7–3.9) are instantaneous forces for a voltage V_F.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace
from typing import Mapping

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from ..circuits import Circuit, current_through, parse, voltage_across
from ..arguments import checked_arguments, drive_amplitude, numeric_array, relative_permittivity, require_parameters, shown, variants_named
from ..errors import DataError, ParameterError
from ..io.netcdf import result_dataset
from ..constants import EPSILON_0

__all__ = [
    "CPE_REFERENCE_HZ",
    "MeyerPhysical",
    "MeyerModel",
    "THESIS_PHYSICAL",
    "THESIS_PARAMS",
    "THESIS_DRIVE_V",
    "VARIANT_AUTO",
    "meyer_circuit",
    "meyer_parameters",
    "meyer_model",
    "finger_voltage",
    "leaked_charge",
    "force_time_average",
    "force_peak",
    "force_from_charge",
    "static_force_series",
    "static_force_f1",
    "static_force_f2",
    "FrictionLine",
    "friction_coefficient",
    "force_from_friction",
]

THESIS_DRIVE_V = 140.0
"""Drive amplitude V_A [V] of thesis Fig 3.4."""

CPE_REFERENCE_HZ = 1e3  # the thesis quotes ρ_sc, ε_sc "at 1 kHz" (eq 3.13 text): CPE_sc.Q gives C_sc there (impedax's choice: docs/physics.md)

_CIRCUITS = {
    "rc": "C_s + C_i + R_sc || C_sc + R_f",
    "cpe": "C_s + C_i + R_sc || CPE_sc + R_f",
}
_SC_BLOCK = {"rc": ("C_i", "R_sc", "C_sc"), "cpe": ("C_i", "R_sc", "CPE_sc")}


_PHYSICAL_UNITS = {"rho_sc": "Ω·m", "d_sc": "m", "d_i": "m", "area": "m²", "r_f": "Ω", "c_s": "F"}


@dataclass(frozen=True)
class MeyerPhysical:
    """Physical description of finger and screen (thesis eq 3.13), SI units.

    ``rho_sc`` [Ω·m] and ``eps_sc`` of the stratum corneum at 1 kHz, ``d_sc`` [m] its thickness;
    ``eps_i``, ``d_i`` [m] of the SiO2 insulator; ``area`` [m²] the contact area (a 4 mm radius
    disc); ``r_f`` [Ω] body resistance; ``c_s`` [F] cable capacitor. Every value finite and
    positive, the permittivities at least 1 (`ParameterError` naming the field otherwise).
    """

    rho_sc: float = 33e3
    eps_sc: float = 1000.0
    d_sc: float = 200e-6
    eps_i: float = 3.9
    d_i: float = 1e-6
    area: float = math.pi * (4e-3) ** 2
    r_f: float = 500.0
    c_s: float = 140e-12

    def __post_init__(self):
        for name in ("rho_sc", "d_sc", "d_i", "area", "r_f", "c_s"):  # (area=0 would raise ZeroDivisionError in r_sc)
            numeric_array(positive=True)(getattr(self, name), f"MeyerPhysical.{name} [{_PHYSICAL_UNITS[name]}]")
        for name in ("eps_sc", "eps_i"):  # (below vacuum's 1: unphysical)
            relative_permittivity(getattr(self, name), f"MeyerPhysical.{name}")

    @property
    def r_sc(self) -> float:
        """R_sc = ρ_sc d_sc / A [Ω] (eq 3.13)."""
        return self.rho_sc * self.d_sc / self.area

    @property
    def c_sc(self) -> float:
        """C_sc = ε0 ε_sc A / d_sc [F] (eqs 3.5, 3.13)."""
        return EPSILON_0 * self.eps_sc * self.area / self.d_sc

    @property
    def c_i(self) -> float:
        """C_i = ε0 ε_i A / d_i [F] (eqs 3.5, 3.13)."""
        return EPSILON_0 * self.eps_i * self.area / self.d_i


THESIS_PHYSICAL = MeyerPhysical()
"""The thesis's physical values (eq 3.13)."""

THESIS_PARAMS: Mapping[str, float] = {"C_s": 140e-12, "C_i": 1.7e-9, "R_sc": 130e3, "C_sc": 2.2e-9, "R_f": 500.0}
"""Circuit values as rounded in thesis eq 3.13 (these give Fig 3.4: 164 mN peak near 37 kHz)."""


def meyer_circuit(variant: str = "rc") -> Circuit:
    """The thesis circuit: ``"rc"`` → C_s + C_i + R_sc || C_sc + R_f (Fig 3.3); ``"cpe"`` →
    the fractional variant with CPE_sc in place of C_sc."""
    return parse(_CIRCUITS[_check_variant(variant)])


VARIANT_AUTO = "auto"
"""``variant`` of the functions of parameters read from the names: ``C_sc`` → ``"rc"``,
``CPE_sc.*`` → ``"cpe"`` (their default)."""


def _check_variant(variant: str, *, auto: bool = False) -> str:
    """``variant`` in its canonical spelling (``"rc"``, ``"cpe"``: case does not matter; with
    ``auto`` also ``"auto"``)."""
    folded = variant.casefold() if isinstance(variant, str) else None
    if folded in _CIRCUITS or (auto and folded == VARIANT_AUTO):
        return folded
    raise ParameterError(f"unknown Meyer variant {shown(variant)}; use one of {', '.join(_CIRCUITS)}{' or auto' if auto else ''}")


def _variant_of(params, variant) -> str:
    """The canonical variant for ``params``: ``"auto"`` reads it from the names (static dict
    keys, so jittable); a ParameterError names what is missing and, when ``params`` are the
    other variant's, says which ``variant`` to pass."""
    variant = _check_variant(variant, auto=True)
    if not isinstance(params, Mapping):
        require_parameters(params, ())
    has = variants_named(params, {"rc": "C_sc", "cpe": "CPE_sc."}, "variant", exclusive=variant == VARIANT_AUTO)
    if variant == VARIANT_AUTO:
        if not (has["rc"] or has["cpe"]):
            names = {v: meyer_circuit(v).parameter_names() for v in _CIRCUITS}
            missing = [n for n in names["rc"] if n not in params and n != "C_sc"]
            raise ParameterError(
                f"params lacks {', '.join(missing + ['C_sc or CPE_sc.Q, CPE_sc.alpha'])}; the model's parameters are "
                f"{', '.join(names['rc'])} (variant='rc') or {', '.join(names['cpe'])} (variant='cpe')"
            )
        return "rc" if has["rc"] else "cpe"
    other = "cpe" if variant == "rc" else "rc"
    names = meyer_circuit(variant).parameter_names()
    missing = [n for n in names if n not in params]
    if missing and has[other] and not has[variant]:
        marker = "C_sc" if other == "rc" else "CPE_sc.*"
        raise ParameterError(f"params lacks {', '.join(missing)} (variant {variant!r}) but hold {marker} of variant {other!r}: pass variant={other!r}, or leave variant out (it is read from the names)")
    return variant


def _check_alpha(alpha) -> None:
    """The CPE exponent α must be a number in (0, 1] (a CPE between a resistor and a capacitor)."""
    try:  # a Python, NumPy or 0-d JAX number; not a bool, a string or an array
        value = None if isinstance(alpha, (bool, np.bool_, str, bytes)) or np.ndim(alpha) != 0 else float(alpha)
    except (TypeError, ValueError):
        value = None
    if value is None or not 0.0 < value <= 1.0:
        raise ParameterError(f"CPE_sc.alpha must be in (0, 1], got {shown(alpha)}")


def meyer_parameters(physical: MeyerPhysical = THESIS_PHYSICAL, *, variant: str = "rc", alpha: float = 0.8) -> dict[str, float]:
    """Circuit parameters from a physical description (thesis eq 3.13).

    RC: R_sc = ρ_sc d_sc/A, C_sc = ε0 ε_sc A/d_sc, C_i = ε0 ε_i A/d_i, plus R_f and C_s.
    CPE: ``CPE_sc.alpha = alpha`` and ``CPE_sc.Q = C_sc ω_ref^(1−α)`` with ω_ref = 2π·1 kHz, so
    the CPE has the capacitor's impedance magnitude at 1 kHz, where ρ_sc and ε_sc were quoted.
    """
    if not isinstance(physical, MeyerPhysical):  # (not an AttributeError "'str' object has no attribute 'c_s'")
        raise ParameterError(f"physical must be a MeyerPhysical (impedax.models.MeyerPhysical(rho_sc=…, d_sc=…, …)), got {shown(physical)} ({type(physical).__name__})")
    variant = _check_variant(variant)
    params = {"C_s": physical.c_s, "C_i": physical.c_i, "R_sc": physical.r_sc, "R_f": physical.r_f}
    if variant == "rc":
        params["C_sc"] = physical.c_sc
    else:
        _check_alpha(alpha)
        params["CPE_sc.Q"] = physical.c_sc * (2.0 * math.pi * CPE_REFERENCE_HZ) ** (1.0 - alpha)
        params["CPE_sc.alpha"] = float(alpha)
    return params


@dataclass(frozen=True)
class MeyerModel:
    """A Meyer finger–screen model: ``circuit``, its ``params`` and the contact ``area`` [m²]."""

    variant: str
    circuit: Circuit
    params: Mapping[str, float]
    area: float
    physical: MeyerPhysical | None = field(default=None)

    def with_params(self, **values: float) -> "MeyerModel":
        """A copy with some circuit parameters replaced (names as in ``circuit``)."""
        unknown = set(values) - set(self.params)
        if unknown:
            raise ParameterError(f"unknown parameter(s) {', '.join(sorted(unknown))}; parameters: {', '.join(self.params)}")
        return replace(self, params={**self.params, **values})

    def force(self, freq, *, v_a: float = THESIS_DRIVE_V):
        """Time-averaged force [N] at ``freq`` [Hz] (see `force_time_average`)."""
        return force_time_average(self.params, freq, area=self.area, v_a=v_a, variant=self.variant)

    def to_xarray(self, freq, *, v_a: float = THESIS_DRIVE_V) -> xr.Dataset:
        """Force, V_F/V_A and Q_f/V_A over ``freq`` as a Dataset."""
        freq = np.asarray(freq, dtype=np.float64)
        return result_dataset(xr.Dataset(
            {
                "force": ("frequency", np.asarray(self.force(freq, v_a=v_a)), {"units": "N", "convention": "time-average", "long_name": "electrostatic force, eq 3.6"}),
                # (what each complex ratio is, as the force says its unit)
                "finger_voltage_ratio": ("frequency", np.asarray(finger_voltage(self.params, freq, variant=self.variant)), {"units": "1", "long_name": "V_F/V_A: voltage across C_i and the stratum corneum per drive volt"}),
                "leaked_charge_ratio": ("frequency", np.asarray(leaked_charge(self.params, freq, variant=self.variant)), {"units": "C/V", "long_name": "Q_f/V_A: charge leaked through R_sc per drive volt"}),
            },
            coords={"frequency": ("frequency", freq, {"units": "Hz"})},
            attrs={"model": str(self.circuit), "area_m2": self.area, "drive_amplitude_v": v_a, "source": "Meyer (2012) thesis model"},
        ))


def meyer_model(variant: str = "rc", *, physical: MeyerPhysical | None = None, alpha: float = 0.8) -> MeyerModel:
    """Meyer's model with the thesis parameters as defaults.

    Without ``physical`` the circuit values are the rounded ones of eq 3.13 (`THESIS_PARAMS`;
    for ``"cpe"``, Q from C_sc = 2.2 nF as in `meyer_parameters`) and A = π(4 mm)². With
    ``physical`` (a `MeyerPhysical`) they are computed from ρ_sc, ε_sc, d_sc, ε_i, d_i, A.
    """
    variant = _check_variant(variant)
    if physical is None:
        params = dict(THESIS_PARAMS)
        if variant == "cpe":
            _check_alpha(alpha)
            c_sc = params.pop("C_sc")
            params["CPE_sc.Q"] = c_sc * (2.0 * math.pi * CPE_REFERENCE_HZ) ** (1.0 - alpha)
            params["CPE_sc.alpha"] = float(alpha)
        area = THESIS_PHYSICAL.area
    else:
        params = meyer_parameters(physical, variant=variant, alpha=alpha)
        area = physical.area
    return MeyerModel(variant, meyer_circuit(variant), params, area, physical)


@functools.lru_cache(maxsize=None)
def _probes(variant: str):
    """Per volt of drive: V_F (across C_i and the SC block), I_Rsc, V_sc (across the SC block)
    and the current through C_sc (or CPE_sc)."""
    text = _CIRCUITS[variant]
    c_i, r_sc, c_sc = _SC_BLOCK[variant]
    return voltage_across(text, {c_i, r_sc, c_sc}), current_through(text, r_sc), voltage_across(text, {r_sc, c_sc}), current_through(text, c_sc)


@checked_arguments(freq=numeric_array(positive=True))
def finger_voltage(params: Mapping[str, object], freq, *, variant: str = VARIANT_AUTO):
    """V_F/V_A: voltage from the ITO to the finger tissue (across C_i and the stratum corneum)
    per volt of drive, from the solved circuit (thesis eq 3.12 derived from A.1; the printed
    numerator of eq 3.12/A.2 is wrong, see docs/physics.md, "Meyer"). ``variant``: ``"auto"``
    (default) reads it from the parameter names (C_sc → ``"rc"``, CPE_sc.* → ``"cpe"``), or
    ``"rc"``/``"cpe"`` (any case). Pure JAX, vmappable over draws."""
    variant = _variant_of(params, variant)
    require_parameters(params, meyer_circuit(variant).parameter_names())
    return _probes(variant)[0](params, freq)


@checked_arguments(freq=numeric_array(positive=True))
def leaked_charge(params: Mapping[str, object], freq, *, variant: str = VARIANT_AUTO):
    """Q_f/V_A [C/V]: charge leaked through R_sc onto the glass, I_Rsc/(jω V_A) (eq 3.12);
    ``variant`` as `finger_voltage`."""
    variant = _variant_of(params, variant)
    require_parameters(params, meyer_circuit(variant).parameter_names())
    omega = 2.0 * jnp.pi * jnp.asarray(freq)
    return _probes(variant)[1](params, freq) / (1j * omega)


def _effective_c_sc(params: Mapping[str, object], variant: str, omega):
    """C_sc of the eq 3.6 prefactor [F]: C_sc (RC); for the CPE, C_sc(ω) = Q ω^(α−1), the
    capacitance with the CPE's impedance magnitude at ω (equal to C_sc at 1 kHz by
    `meyer_parameters`). With it |V_CPE| = |Q_CPE|/C_sc(ω) ≤ |Q_i|/C_sc(ω), so C(ω)|V_F| ≤ |Q_i|
    (Q_i = I/(jω), the charge on C_i; C = C_i C_sc/(C_i + C_sc)) and the force keeps the RC
    model's limit Q_i²/(2ε0A) (eq 3.6 with Q_f → 0)."""
    if variant == "rc":
        return params["C_sc"]
    return params["CPE_sc.Q"] * omega ** (params["CPE_sc.alpha"] - 1.0)


def force_from_charge(v_f, q_f, *, c_i, c_sc, area):
    """Instantaneous force [N] of thesis eq 3.6/A.3:
    F = (C_i C_sc/(C_i + C_sc))² / (2 A ε0) · (V_F² − Q_f²/C_i²), for real V_F [V], Q_f [C]."""
    series = c_i * c_sc / (c_i + c_sc)
    return series**2 / (2.0 * area * EPSILON_0) * (v_f**2 - q_f**2 / c_i**2)


@checked_arguments(freq=numeric_array(positive=True), area=numeric_array(positive=True), v_a=drive_amplitude)
def force_time_average(params: Mapping[str, object], freq, *, area: float = THESIS_PHYSICAL.area, v_a: float = THESIS_DRIVE_V, variant: str = VARIANT_AUTO):
    """Time-averaged electrostatic force [N] for a sinusoidal drive of amplitude ``v_a`` [V]
    (thesis eq 3.6/A.3 averaged over a period, Fig 3.4):
    F̄ = (C_i C_sc/(C_i + C_sc))²/(2Aε0) · ½ (|V_F|² − |Q_f|²/C_i²) with phasor amplitudes.

    ``variant``: ``"auto"`` (default) reads it from the parameter names (C_sc → ``"rc"``,
    CPE_sc.* → ``"cpe"``), or ``"rc"``/``"cpe"`` (any case).
    Convention: time-average (the peak of the oscillating force is larger). For the CPE
    variant C_sc in the prefactor is C_sc(ω) = Q ω^(α−1), the capacitance with the CPE's
    impedance magnitude at each ω (α = 1 is the RC model); the force then obeys the RC model's
    charge bound F̄ ≤ |Q_i|²/(4Aε0). Pure JAX in ``params`` (vmap over posterior draws).
    Evaluated as Re[(V̂_F − Q̂_f/C_i)·conj(V̂_F + Q̂_f/C_i)] (equal to the difference of squares,
    without its cancellation at very low frequency; see `_force_phasors`). Circuit values must be
    positive and CPE_sc.alpha in (0, 1] (`ParameterError` otherwise).
    """
    prefactor, minus, plus = _force_phasors(params, freq, area, v_a, variant)
    return prefactor * 0.5 * jnp.real(minus * jnp.conj(plus))


@checked_arguments(freq=numeric_array(positive=True), area=numeric_array(positive=True), v_a=drive_amplitude)
def force_peak(params: Mapping[str, object], freq, *, area: float = THESIS_PHYSICAL.area, v_a: float = THESIS_DRIVE_V, variant: str = VARIANT_AUTO):
    """Peak electrostatic force [N]: the largest instantaneous force of thesis eq 3.6/A.3 over a
    period of the drive V_A cos ωt (arguments as `force_time_average`).

    With phasors V_F(t) = Re(V̂_F e^{jωt}), Q_f(t) = Re(Q̂_f e^{jωt}) and Re(z e^{jωt})² =
    ½|z|² + ½ Re(z² e^{2jωt}), eq 3.6 is F(t) = F̄ + (K/2) Re[(V̂_F² − Q̂_f²/C_i²) e^{2jωt}]:
    the time average F̄ (`force_time_average`) plus a 2ω oscillation, K = (C_i C_sc/(C_i +
    C_sc))²/(2Aε0). Its maximum is

        F_peak = F̄ + (K/2) |V̂_F² − Q̂_f²/C_i²|  ≥  2 F̄,

    equal to 2 F̄ only where V_F and Q_f are in phase. Thesis values: 2.0001 F̄ at 37 kHz, 2.18 F̄
    at 1 kHz, 7.4 F̄ at 100 Hz, 64 F̄ at 10 Hz, where the leaked charge cancels V_F's term on
    average but not at every instant (F(t) then swings below zero, to F̄ − (K/2)|…|). Pure JAX.
    |V̂_F² − Q̂_f²/C_i²| is evaluated as |V̂_F − Q̂_f/C_i|·|V̂_F + Q̂_f/C_i| (see `_force_phasors`).
    """
    prefactor, minus, plus = _force_phasors(params, freq, area, v_a, variant)
    return prefactor * 0.5 * (jnp.real(minus * jnp.conj(plus)) + jnp.abs(minus * plus))


def _check_element_values(params: Mapping[str, object], variant: str) -> None:
    """Every circuit value of ``params`` present, finite and positive (as ``impedax force
    --param`` requires), and CPE_sc.alpha ≤ 1; JAX tracers pass (vmap over draws)."""
    names = meyer_circuit(variant).parameter_names()
    require_parameters(params, names)
    positive = numeric_array(positive=True)
    for name in names:
        positive(params[name], f"params[{name!r}] (a Meyer circuit value)")
    alpha = params.get("CPE_sc.alpha") if variant == "cpe" else None
    if alpha is not None and not isinstance(alpha, jax.core.Tracer) and not np.all(np.asarray(alpha) <= 1.0):
        raise ParameterError(f"params['CPE_sc.alpha'] must be in (0, 1], got {alpha!r}")


def _force_phasors(params, freq, area, v_a, variant):
    """(K, V̂_F − Q̂_f/C_i, V̂_F + Q̂_f/C_i) of eq 3.6 at ``freq`` for the drive amplitude ``v_a`` [V].

    |V̂_F|² − |Q̂_f/C_i|² = Re[(V̂_F − Q̂_f/C_i)·conj(V̂_F + Q̂_f/C_i)] (the cross terms
    −Q̂ V̂* + V̂ Q̂* = 2j Im(V̂ Q̂*) are imaginary). The difference is formed without subtraction:
    V_F = V_Ci + V_sc and C_i V_Ci = Q_i = Q_f + Q_sc (Q_sc = I_Csc/(jω), the charge of C_sc or
    CPE_sc), so V̂_F − Q̂_f/C_i = V̂_sc + Î_Csc/(jω C_i). Below ~1e-4 Hz (thesis values) V_F and
    Q_f/C_i agree to (ωτ)², τ = R_sc(C_sc + C_i), and |V_F|² − |Q_f/C_i|² cancels to rounding noise."""
    variant = _variant_of(params, variant)
    _check_element_values(params, variant)
    v_f = finger_voltage(params, freq, variant=variant) * v_a
    q_c = leaked_charge(params, freq, variant=variant) * v_a / params["C_i"]
    _, _, v_sc_probe, i_cap_probe = _probes(variant)
    omega = 2.0 * jnp.pi * jnp.asarray(freq)
    minus = (v_sc_probe(params, freq) + i_cap_probe(params, freq) / (1j * omega * params["C_i"])) * v_a
    c_i = params["C_i"]
    c_sc = _effective_c_sc(params, variant, omega)
    series = c_i * c_sc / (c_i + c_sc)
    return series**2 / (2.0 * area * EPSILON_0), minus, v_f + q_c


def _thickness(value, name):
    """A layer thickness [m]: numbers ≥ 0 (0: no such layer; a negative one, a sign slip, would give a
    force of any size without a word)."""
    value = numeric_array()(value, name)
    if not isinstance(value, jax.core.Tracer) and not (np.isrealobj(np.asarray(value)) and np.all(np.asarray(value) >= 0)):
        raise ParameterError(f"{name} is a layer thickness [m] and must be ≥ 0, got {shown(value)}")
    return value


def _some_layer(arguments) -> None:
    """Eq 3.7 needs a layer between the plates: d_i and d_sc not both 0 (the force is infinite)."""
    d_i, d_sc = arguments["d_i"], arguments["d_sc"]
    if not any(isinstance(v, jax.core.Tracer) for v in (d_i, d_sc)) and np.any((np.asarray(d_i) == 0) & (np.asarray(d_sc) == 0)):
        raise ParameterError("d_i and d_sc are both 0: eq 3.7 needs a dielectric between the plates (the force is infinite without one)")


@checked_arguments(_some_layer, v_f=numeric_array(), area=numeric_array(positive=True), d_i=_thickness, d_sc=_thickness, eps_i=relative_permittivity, eps_sc=relative_permittivity)
def static_force_series(v_f, *, area: float, d_i: float, eps_i: float, d_sc: float, eps_sc: float):
    """Thesis eq 3.7: force [N] of two dielectrics in series with no leaked charge,
    F = ε0 A V_F² / (2 (d_i/ε_i + d_sc/ε_sc)²)."""
    return EPSILON_0 * area * jnp.asarray(v_f) ** 2 / (2.0 * (d_i / eps_i + d_sc / eps_sc) ** 2)


@checked_arguments(v_f=numeric_array(), area=numeric_array(positive=True), d_sc=numeric_array(positive=True), eps_sc=relative_permittivity)
def static_force_f1(v_f, *, area: float, d_sc: float, eps_sc: float):
    """Thesis eq 3.8 (zero insulator thickness; the form Meyer argues is right for a solid
    dielectric slab): F1 = ε0 A V_F² / (2 (d_sc/ε_sc)²) = Q²/(2 ε0 A)."""
    return EPSILON_0 * area * jnp.asarray(v_f) ** 2 / (2.0 * (d_sc / eps_sc) ** 2)


@checked_arguments(v_f=numeric_array(), area=numeric_array(positive=True), d_sc=numeric_array(positive=True), eps_sc=relative_permittivity)
def static_force_f2(v_f, *, area: float, d_sc: float, eps_sc: float):
    """Thesis eq 3.9 (the textbook parallel-plate form, correct only for a dielectric fluid):
    F2 = ε0 ε_sc A V_F² / (2 d_sc²) = Q²/(2 ε0 ε_sc A) = F1/ε_sc."""
    return EPSILON_0 * eps_sc * area * jnp.asarray(v_f) ** 2 / (2.0 * d_sc**2)


@dataclass(frozen=True)
class FrictionLine:
    """Least-squares line friction = µ · normal + offset from no-voltage data (thesis §4.4)."""

    mu: float
    offset: float
    mu_stderr: float
    n_points: int

    def to_xarray(self) -> xr.Dataset:
        return result_dataset(xr.Dataset({"mu": self.mu, "offset": self.offset, "mu_stderr": self.mu_stderr}, attrs={"n_points": self.n_points, "offset_units": "N"}))


def _measured(values, name: str, *, flat: bool = True) -> np.ndarray:
    """Measured forces [N] as a float array (flattened unless ``flat`` is False), else one
    `DataError` naming ``name`` (text where numbers go: not NumPy's ValueError)."""
    try:
        array = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise DataError(f"{name} must be numbers [N], got {shown(values)}") from None
    return array.ravel() if flat else array


def friction_coefficient(normal_force, friction_force, *, through_origin: bool = False) -> FrictionLine:
    """µ from a linear regression of friction force on normal force [N] measured without
    voltage (thesis §4.4, Fig 4.8); ``through_origin`` forces the offset to zero."""
    fn, ft = _measured(normal_force, "normal_force"), _measured(friction_force, "friction_force")
    if fn.shape != ft.shape:
        raise DataError(f"normal_force has {fn.size} values but friction_force has {ft.size}")
    need = 2 if through_origin else 3
    if fn.size < need:
        raise DataError(f"need at least {need} (normal, friction) pairs for a line with an error estimate, got {fn.size}")
    if not (np.all(np.isfinite(fn)) and np.all(np.isfinite(ft))):
        raise DataError("normal and friction forces must be finite")
    design = fn[:, None] if through_origin else np.stack([fn, np.ones_like(fn)], axis=1)
    if np.ptp(fn) == 0 and not through_origin:
        raise DataError("all normal forces are equal: the friction slope is undetermined")
    coef, *_ = np.linalg.lstsq(design, ft, rcond=None)
    resid = ft - design @ coef
    dof = fn.size - design.shape[1]
    cov = np.linalg.inv(design.T @ design) * (resid @ resid / dof)
    return FrictionLine(float(coef[0]), 0.0 if through_origin else float(coef[1]), float(np.sqrt(cov[0, 0])), int(fn.size))


def force_from_friction(delta_friction, mu):
    """Thesis eq 4.1: electrostatic force F_e = ΔF/µ [N] from the friction increase ΔF [N]
    under voltage at the same normal force; ``mu`` a float or a `FrictionLine`."""
    mu = mu.mu if isinstance(mu, FrictionLine) else mu
    if not np.all(np.asarray(mu) > 0):
        raise ParameterError(f"friction coefficient must be positive, got {mu}")
    return _measured(delta_friction, "delta_friction", flat=False) / mu
