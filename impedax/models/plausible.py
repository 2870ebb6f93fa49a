"""Plausibility ranges of physical inputs, shared by ``impedax gap`` (the contact area) and
``impedax force`` (the area and Meyer's circuit values): a value far outside them is most
likely a unit slip (2.2 for 2.2n F, 50 for 50e-6 m²), so the commands refuse it with a message
saying the unit likely intended (docs/models.md, "Plausible values").

The area range is a fingertip's apparent contact, 1 mm² to 100 cm² (`FINGERTIP_AREA_M2`).
Meyer's capacitances and resistances may lie a factor `MEYER_FACTOR` (1000) either way of the
thesis values (docs/physics.md, thesis eq 3.13: C_s 140 pF, C_i 1.7 nF, C_sc 2.2 nF, R_sc 130 kΩ,
R_f 500 Ω): generous for other screens, skins and insulators, yet a missing SI prefix (a
factor of 10⁹ for n, 10¹² for p) always falls outside. The CPE variant's CPE_sc.Q [F s^(α−1)]
has no fixed range, since its unit moves with α: it is plausible when the capacitance it gives at
1 kHz, C_sc(1 kHz) = Q (2π·1 kHz)^(α−1) (where the thesis quotes ε_sc; `meyer_parameters`), lies
in C_sc's range (`implausible_cpe_message`).
"""

from __future__ import annotations

import math

from ..data import SI_PREFIXES
from .meyer import CPE_REFERENCE_HZ, THESIS_PARAMS

__all__ = ["FINGERTIP_AREA_M2", "DRIVE_VOLTAGE_V", "AIR_BREAKDOWN_V", "MEYER_FACTOR", "PARAMETER_UNITS", "plausible_range", "implausible_message", "cpe_capacitance", "implausible_cpe_message"]

FINGERTIP_AREA_M2 = (1e-6, 1e-2)  # plausible apparent contact of a fingertip: 1 mm² to 100 cm²
DRIVE_VOLTAGE_V = (1.0, 2e3)
"""Plausible drive amplitude V0 [V] of a finger's electroadhesion: up to the largest drive of the
three papers (docs/physics.md), Vezzoli et al.'s 2 kV across a 90 µm insulator (Sirin et al.
75 V, Meyer 140 V). The air gap carries part of V0 (V_gap = u √(2F/(ε0 A)) from eq 1: about
87 % at the force's peak on a SYNTHETIC 200 mm², 5 µm contact: 65 kV of a 75 kV drive), and a
µm air gap breaks down at a few hundred volts (air's Paschen minimum is about 330 V, near 10 µm
at 1 atm), which eq 1's force does not model. Below 1 V: no drive of the papers,
and a likely unit slip (75m is 0.075 V). Outside the range: a warning, not an error (the force
is only ∝ V0², and a test rig may drive other voltages)."""
AIR_BREAKDOWN_V = 330.0
"""Air's Paschen minimum [V] at 1 atm (about 327 V, near a 7.5–10 µm gap): no air gap holds more
without breaking down, and below ~5 µm field emission lowers the breakdown further. A gap
voltage above it makes eq 1's force (no breakdown in it) unreachable."""
MEYER_FACTOR = 1e3
"""Meyer's circuit values are plausible within this factor either way of the thesis's."""
PARAMETER_UNITS = {"C_s": "F", "C_i": "F", "C_sc": "F", "R_sc": "Ω", "R_f": "Ω", "area": "m²", "CPE_sc.Q": "F s^(α−1)", "CPE_sc.alpha": ""}


def plausible_range(model: str, name: str) -> tuple[float, float] | None:
    """The plausible (low, high) of parameter ``name`` of ``model`` (``"meyer"``, ``"vezzoli"``,
    ``"gap"``), or None when it has none: ``area`` in `FINGERTIP_AREA_M2` for every model; Meyer's
    C_s, C_i, C_sc, R_sc, R_f within `MEYER_FACTOR` of `THESIS_PARAMS`."""
    if name == "area":
        return FINGERTIP_AREA_M2
    if model == "meyer" and name in THESIS_PARAMS:
        reference = THESIS_PARAMS[name]
        return reference / MEYER_FACTOR, reference * MEYER_FACTOR
    return None


def _shown(value: float, unit: str) -> str:
    """``value`` with an SI prefix (2.2e-09 F → '2.2 nF'); m² as it is."""
    if unit == "m²" or not 1e-15 <= abs(value) < 1e15:  # (beyond the prefixes: 1e+300 Ω, not 1e+288 TΩ)
        return f"{value:g} {unit}"
    scale, prefix = next(((s, p) for s, p in SI_PREFIXES if abs(value) >= s), SI_PREFIXES[-1])
    return f"{value / scale:.4g} {prefix}{unit}"


def _intended(value: float, low: float, high: float, unit: str) -> str:
    """What a value outside ``low``–``high`` likely meant: the SI prefix that brings it inside
    (nearest the range's middle, in log), or for an area the mm² or cm² reading."""
    if unit == "m²":
        for factor, said in ((1e-6, "mm²"), (1e-4, "cm²")):
            if low <= value * factor <= high:
                return f"; the area is in m²: {value:g} {said} is {value * factor:g}"
        return "; the area is in m² (130 mm² is 130e-6)"
    middle = math.sqrt(low * high)
    fits = [(abs(math.log(value * s / middle)), p, value * s) for s, p in SI_PREFIXES if p and low <= value * s <= high]
    if not fits:
        return f"; the value is in {unit}"
    meant = min(fits)[2]
    scale, prefix = next(((s, p) for s, p in SI_PREFIXES if abs(meant) >= s), SI_PREFIXES[-1])
    written = "u" if prefix == "µ" else prefix
    return f"; the value is in {unit} (an SI prefix scales it, e.g. 2.2n is 2.2e-9): {meant / scale:.4g}{written} ({_shown(meant, unit)}) was likely meant"


def implausible_message(model: str, name: str, value: float) -> str | None:
    """Why ``value`` of parameter ``name`` is implausible (outside `plausible_range`), with the
    unit likely intended, or None when it is plausible or has no range."""
    bounds = plausible_range(model, name)
    if bounds is None:
        return None
    low, high = bounds
    if low <= value <= high:
        return None
    unit = PARAMETER_UNITS.get(name, "")
    if name == "area":
        where = f"a fingertip's apparent contact is {low:g}–{high:g} m² ({low * 1e6:g}–{high * 1e6:g} mm²)"
    else:
        where = f"plausible {_shown(low, unit)}–{_shown(high, unit)}, {MEYER_FACTOR:g}× either way of the thesis's {_shown(THESIS_PARAMS[name], unit)}"
    return f"{name} = {_shown(value, unit)} is implausible ({where}){_intended(value, low, high, unit)}"


def cpe_capacitance(q: float, alpha: float, frequency_hz: float = CPE_REFERENCE_HZ) -> float:
    """The capacitance [F] with the CPE's impedance magnitude at ``frequency_hz``:
    C(ω) = Q ω^(α−1) (|Z_CPE| = 1/(Q ω^α) = 1/(ω C)); α = 1 gives Q."""
    return q * (2.0 * math.pi * frequency_hz) ** (alpha - 1.0)


def implausible_cpe_message(q: float, alpha: float) -> str | None:
    """Why Meyer's ``CPE_sc.Q`` = ``q`` with exponent ``alpha`` is implausible, or None: its
    capacitance at 1 kHz (`cpe_capacitance`) must lie in C_sc's `plausible_range`; the message
    gives that capacitance and the Q an SI prefix likely meant."""
    low, high = plausible_range("meyer", "C_sc")
    capacitance = cpe_capacitance(q, alpha)
    if low <= capacitance <= high:
        return None
    scale = capacitance / q
    unit = PARAMETER_UNITS["CPE_sc.Q"]
    return (
        f"CPE_sc.Q = {q:g} {unit} with CPE_sc.alpha = {alpha:g} is implausible: its capacitance at 1 kHz, Q (2π·1 kHz)^(α−1) = "
        f"{_shown(capacitance, 'F')}, lies outside {_shown(low, 'F')}–{_shown(high, 'F')} ({MEYER_FACTOR:g}× either way of the thesis's "
        f"C_sc {_shown(THESIS_PARAMS['C_sc'], 'F')}){_intended(q, low / scale, high / scale, unit)}"
    )
