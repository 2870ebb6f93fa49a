"""Plausibility ranges of physical inputs, shared by ``impedax gap`` (the contact area) and
``impedax force`` (the area and Meyer's circuit values): a value far outside them is most
likely a unit slip (2.2 for 2.2n F, 50 for 50e-6 m²), so the commands refuse it with a message
saying the unit likely intended (docs/models.md, "Plausible values"). The drive amplitude (gap's
V0, warned about by `gap_analysis`; force's v_a and v_m, `DRIVE_PARAMETERS`) and Vezzoli's thicknesses and resistivity
(`VEZZOLI_RANGES`) outside their ranges are warned about instead (`WARNED_ONLY`): a rig or a
skin may differ from the papers', and a user may explore.

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
from .meyer import CPE_REFERENCE_HZ, THESIS_DRIVE_V, THESIS_PARAMS
from .vezzoli import TABLE2

__all__ = ["FINGERTIP_AREA_M2", "DRIVE_VOLTAGE_V", "AIR_BREAKDOWN_V", "MEYER_FACTOR", "VEZZOLI_RANGES", "DRIVE_PARAMETERS", "WARNED_ONLY", "PARAMETER_UNITS", "plausible_range", "implausible_message", "cpe_capacitance", "implausible_cpe_message"]

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
"""Air's Paschen minimum [V] at 1 atm (about 327 V, near a 7.5–10 µm gap; a textbook value, not in
the papers: docs/physics.md, "impedax's own choices and derived values"): no air gap holds more
without breaking down, and below ~5 µm field emission lowers the breakdown further. A gap
voltage above it makes eq 1's force (no breakdown in it) unreachable."""
MEYER_FACTOR = 1e3
"""Meyer's circuit values are plausible within this factor either way of the thesis's."""
VEZZOLI_RANGES = {"h_i": (1e-7, 9e-4), "h_s": (1e-5, 5e-3), "rho_s": (3e2, 3e6), "eps_i": (1.0, 3.6e3), "eps_s": (1.0, 2.34e5)}
"""Plausible values of Vezzoli et al.'s insulator thickness h_i [m], stratum corneum thickness
h_s [m] and its resistivity ρ_s [Ω m] (docs/physics.md, "Vezzoli" and, for Fig 8's h_s, which the
paper does not print, "impedax's own choices and derived values"; the paper's Table 2 and Figs 8–10):
h_i a factor 10 beyond the paper's insulators either way, from under 1 µm (SiO₂ for 0.03 N,
Fig 9; the 1 µm of Figs 8 and 10) to Table 2's 90 µm film: 100 nm–900 µm; h_s a factor 10 beyond
Fig 8's 100–500 µm (the fingertip's range, after Fruhstorfer 2000): 10 µm–5 mm; ρ_s 100× either
way of Table 2's 3.0e4 Ω m, the paper's one value (at 440 Hz; it varies between subjects and with
frequency, Yamamoto 1976), which moves eq 8's corner 1/(2π ε0 ε_s ρ_s) (256 Hz with Table 2)
over 2.6 Hz–26 kHz, past the paper's 100 Hz–10 kHz. A dropped µ (90 for 90 µm, ×10⁶) or k (30 for
30 kΩ m, ×10³) falls outside each. The relative permittivities (below 1 they
are refused, `arguments.relative_permittivity`): ε_i up to 100× the paper's largest insulator,
ε_i = 36 (Fig 9), 3600; ε_s up to 100× Table 2's 2340 (as ρ_s), 2.34e5."""
DRIVE_PARAMETERS = {"meyer": "v_a", "vezzoli": "v_m"}
"""The drive amplitude's name in each model: plausible within `DRIVE_VOLTAGE_V`."""
WARNED_ONLY = frozenset({*DRIVE_PARAMETERS.values(), *VEZZOLI_RANGES})
"""Parameters whose implausible value is a warning, not an error (a rig may drive other voltages,
a film and a skin may be thinner or thicker than the papers'); the others are refused."""
PARAMETER_UNITS = {"C_s": "F", "C_i": "F", "C_sc": "F", "R_sc": "Ω", "R_f": "Ω", "area": "m²", "CPE_sc.Q": "F s^(α−1)", "CPE_sc.alpha": "", "v_a": "V", "v_m": "V", "h_i": "m", "h_s": "m", "rho_s": "Ω m", "eps_i": "", "eps_s": ""}


def plausible_range(model: str, name: str) -> tuple[float, float] | None:
    """The plausible (low, high) of parameter ``name`` of ``model`` (``"meyer"``, ``"vezzoli"``,
    ``"gap"``), or None when it has none: ``area`` in `FINGERTIP_AREA_M2` for every model; the
    drive amplitude (`DRIVE_PARAMETERS`) in `DRIVE_VOLTAGE_V`; Meyer's C_s, C_i, C_sc, R_sc, R_f
    within `MEYER_FACTOR` of `THESIS_PARAMS`; Vezzoli's h_i, h_s, rho_s in `VEZZOLI_RANGES`."""
    if name == "area":
        return FINGERTIP_AREA_M2
    if name == DRIVE_PARAMETERS.get(model):
        return DRIVE_VOLTAGE_V
    if model == "vezzoli" and name in VEZZOLI_RANGES:
        return VEZZOLI_RANGES[name]
    if model == "meyer" and name in THESIS_PARAMS:
        reference = THESIS_PARAMS[name]
        return reference / MEYER_FACTOR, reference * MEYER_FACTOR
    return None


# the reading an SI prefix most likely meant for a drive: nearest the paper's own (v_m=2M: 2 kV, not 2 V)
_REFERENCES = {"v_a": THESIS_DRIVE_V, "v_m": TABLE2["v_m"]}
_DRIVES = "the drives of the papers: Sirin et al. 75 V, Meyer 140 V, Vezzoli et al. 2 kV"
_RANGE_REASONS = {
    "v_a": _DRIVES,
    "v_m": _DRIVES,
    "h_i": "10× beyond the paper's insulators, 1 µm (Figs 8–10) to Table 2's 90 µm film",
    "h_s": "10× beyond Fig 8's stratum corneum, 100–500 µm",
    "rho_s": "100× either way of Table 2's 30 kΩ m at 440 Hz",
    "eps_i": "up to 100× the paper's largest insulator permittivity, ε_i = 36 (Fig 9)",
    "eps_s": "up to 100× Table 2's ε_s = 2340 (the stratum corneum at 440 Hz)",
}


def _shown(value: float, unit: str) -> str:
    """``value`` with an SI prefix (2.2e-09 F → '2.2 nF'); m² as it is."""
    if unit == "m²" or not 1e-15 <= abs(value) < 1e15:  # (beyond the prefixes: 1e+300 Ω, not 1e+288 TΩ)
        return f"{value:g} {unit}"
    scale, prefix = next(((s, p) for s, p in SI_PREFIXES if abs(value) >= s), SI_PREFIXES[-1])
    return f"{value / scale:.4g} {prefix}{unit}"


DRIVE_SLIP_FACTOR = 10.0
"""A drive voltage above `DRIVE_VOLTAGE_V` by up to this factor (2–20 kV) is warned about as a
high-voltage drive, not as a unit slip (`implausible_message`)."""


def _intended(value: float, low: float, high: float, unit: str, centre: float | None = None) -> str:
    """What a value outside ``low``–``high`` likely meant: the SI prefix that brings it inside
    (nearest ``centre``, by default the range's middle, in log), or for an area the mm² or cm²
    reading."""
    if unit == "m²":
        for factor, said in ((1e-6, "mm²"), (1e-4, "cm²")):
            if low <= value * factor <= high:
                return f"; the area is in m²: {value:g} {said} is {value * factor:g}"
        return "; the area is in m² (130 mm² is 130e-6)"
    middle = math.sqrt(low * high) if centre is None else centre
    fits = [(abs(math.log(value * s / middle)), p, value * s) for s, p in SI_PREFIXES if p and low <= value * s <= high]
    if not fits:
        return f"; the value is in {unit}"
    meant = min(fits)[2]
    scale, prefix = next(((s, p) for s, p in SI_PREFIXES if abs(meant) >= s), SI_PREFIXES[-1])
    written = "u" if prefix == "µ" else prefix
    return f"; the value is in {unit} (an SI prefix scales it, e.g. 2.2n is 2.2e-9): {meant / scale:.4g}{written} ({_shown(meant, unit)}) was likely meant"


def implausible_message(model: str, name: str, value: float) -> str | None:
    """Why ``value`` of parameter ``name`` is implausible (outside `plausible_range`), with the
    unit likely intended, or None when it is plausible or has no range. A parameter of
    `WARNED_ONLY` is said to be most likely a unit slip (the caller warns rather than refuses)."""
    bounds = plausible_range(model, name)
    if bounds is None:
        return None
    low, high = bounds
    if low <= value <= high:
        return None
    unit = PARAMETER_UNITS.get(name, "")
    if name == "area":
        where = f"a fingertip's apparent contact is {low:g}–{high:g} m² ({low * 1e6:g}–{high * 1e6:g} mm²)"
    elif name in WARNED_ONLY and not unit:  # (a relative permittivity: no unit, so no unit slip)
        return f"{name} = {value:g} is implausible (plausible {low:g}–{high:g}, {_RANGE_REASONS[name]})"
    elif name in WARNED_ONLY and unit == "V" and high < value <= DRIVE_SLIP_FACTOR * high:
        # (a drive of a few kV is a high-voltage drive as grippers use, not a unit slip: 5000 read
        # as "5 (5 V) was likely meant" would mean millivolts, which nobody writes for a drive)
        return (f"{name} = {_shown(value, unit)} is above the plausible {_shown(low, unit)}–{_shown(high, unit)} ({_RANGE_REASONS[name]}): "
                "a high-voltage drive, as some electroadhesive grippers use, not a unit slip; the value is in V")
    elif name in WARNED_ONLY:
        where = f"plausible {_shown(low, unit)}–{_shown(high, unit)}, {_RANGE_REASONS[name]}"
        return f"{name} = {_shown(value, unit)} is implausible ({where}), most likely a unit slip{_intended(value, low, high, unit, _REFERENCES.get(name))}"
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
