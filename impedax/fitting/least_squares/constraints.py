"""The user's constraints (``fixed=`` values, ``bounds=`` a fit sits on) as a cause of a misfit:
a fit held by a wrong fixed value or bound misses the data, and the misfit note
(`result.misfit_notes`) would blame the model and send the user to a diagnosis for a missing
effect. `constraint_misfit_notes` checks that cheaply (one local fit from the fit's own values
with the binding constraints released, and one from the data-driven guess where that fails) and, where freeing them explains the misfit, says so
instead. docs/fitting.md, "Misfit notes"."""

from __future__ import annotations

import math
from typing import Callable, Mapping

import numpy as np

from ...circuits import Circuit, Registry
from ...data import format_bound
from ...errors import ImpedaxError
from ...progress import silenced
from ..parameters import ParameterTable
from .result import MISFIT_CHECKED_FROM, MODEL_MISFIT_OVER_CONSISTENT, SIGN_HINT_LEAD, misfit_beyond_noise, user_bounds

__all__ = ["binding_constraints", "constraint_words", "released_fit", "constraint_explains", "explaining_constraints", "constraint_misfit_notes", "with_constraint_notes", "CONSTRAINT_MISFIT_GAIN"]

# a constraint explains a fit's misfit when one local fit with it released (`released_fit`) at
# least halves the rms_rel ... (a factor the data's noise cannot make: on the user's spectrum,
# R0 fixed at 0.04 Ω where it is 0.05 Ω, 15.2 % → 0.387 %; a right fixed value changes nothing)
CONSTRAINT_MISFIT_GAIN = 0.5


def binding_constraints(values: Mapping[str, float], fixed: Mapping[str, bool], at_bound, bounds: Mapping[str, tuple[float, float]]) -> list[tuple[str, str, float]]:
    """The constraints of the user's that hold a fit: (name, "fixed" | "lower" | "upper", value)
    for every fixed parameter and every free one at a bound the user set (``at_bound`` names
    it and its value is nearer that bound of ``bounds`` than the other; a natural bound, e.g.
    R at 0, is the model's, not the user's)."""
    out = [(n, "fixed", float(v)) for n, v in values.items() if fixed.get(n, False)]
    for n in at_bound:
        if n in bounds:
            lo, hi = bounds[n]
            v = float(values[n])
            side = "lower" if abs(v - lo) <= abs(hi - v) else "upper"
            out.append((n, side, lo if side == "lower" else hi))
    return out


def constraint_words(constraints, units: Mapping[str, str] | None = None) -> str:
    """``R0 fixed at 40 mΩ (your fixed=, --fix)`` / ``R0 on your upper bound 48 mΩ (bounds=)``,
    joined: each value in its parameter's unit of ``units`` ({name: unit}; none for a name not
    in it), as bounds are written (`data.format_bound`)."""
    units = units or {}
    parts = [
        f"{n} fixed at {format_bound(v, units.get(n, ''))} (your fixed=, --fix)" if kind == "fixed" else f"{n} on your {kind} bound {format_bound(v, units.get(n, ''))} (bounds=)"
        for n, kind, v in constraints
    ]
    return " and ".join(parts)


def released_fit(circuit: Circuit, data, values: Mapping[str, float], fixed: Mapping[str, bool], bounds: Mapping[str, tuple[float, float]], constraints, *, weighting: str, registry: Registry, fit: Callable, from_guess: bool = False):
    """One local fit (``n_starts=1``) of ``data`` from ``values`` with ``constraints``
    (`binding_constraints`) released: their fixed values freed, their bounds back to the
    element's; every other fixed value and bound kept. A start on a bound it may not start on
    is left to the data-driven guess; ``from_guess``: every free parameter from the guess (the
    constrained fit's values may be far off: a wrong fixed capacitance drove the others of a
    finger circuit to 10²¹ F, from where no local fit comes back). None where the fit cannot be
    made (an `ImpedaxError`). ``fit``: `single.fit`, passed in (single.py imports this module)."""
    released = {n for n, _, _ in constraints}
    keep_fixed = {n: float(v) for n, v in values.items() if fixed.get(n, False) and n not in released}
    keep_bounds = {n: b for n, b in bounds.items() if n not in released}
    specs = circuit.parameter_specs(registry)
    init = {}
    for n, v in values.items():
        if from_guess or n in keep_fixed or not math.isfinite(v):
            continue
        lo, hi = keep_bounds.get(n, (specs[n].lower, specs[n].upper))
        if lo < v < hi or (v == hi and n not in keep_bounds and specs[n].upper_inclusive):
            init[n] = float(v)
    try:
        return fit(circuit, data, init=init or None, fixed=keep_fixed or None, bounds=keep_bounds or None, weighting=weighting, n_starts=1, registry=registry)
    except ImpedaxError:
        return None


def constraint_explains(rms_constrained: float, rms_released: float, kk: float, n_points: int | None = None, n_released: int | None = None) -> bool:
    """Whether releasing the constraints explains a misfit: the released fit is within what the
    misfit rules accept of a model (below `result.MISFIT_CHECKED_FROM`, or within
    `result.MODEL_MISFIT_OVER_CONSISTENT` × the KK test's Voigt chain's rms_rel ``kk``) and its
    rms_rel is at most `CONSTRAINT_MISFIT_GAIN` × the constrained one's, or, with the ``n_points``
    and the ``n_released`` constraints known, below it by more than the noise by the rule that
    blames a model against the KK chain (`result.misfit_beyond_noise`: χ² ratio and ΔAIC, the
    released constraints counted as parameters)."""
    accepted = max(MISFIT_CHECKED_FROM, MODEL_MISFIT_OVER_CONSISTENT * kk) if np.isfinite(kk) else MISFIT_CHECKED_FROM
    if not (np.isfinite(rms_released) and rms_released <= accepted):
        return False
    if rms_released <= CONSTRAINT_MISFIT_GAIN * rms_constrained:
        return True
    return n_points is not None and n_released is not None and misfit_beyond_noise(rms_constrained, rms_released, n_points, n_released)


def explaining_constraints(circuit: Circuit, data, values: Mapping[str, float], fixed: Mapping[str, bool], bounds: Mapping[str, tuple[float, float]], constraints, rms_constrained: float, kk: float, *, weighting: str, registry: Registry, fit: Callable):
    """(the constraints that explain the misfit, the fit with them released) or None: every
    binding constraint released at once (`released_fit`) must explain it (`constraint_explains`
    on ``data``'s points); of several, those whose release alone explains it are named (a
    harmless ``--fix C_i`` beside the bound that holds the fit is not), all of them when none
    alone does. One local fit per constraint more, only where the first explains; a second
    from the data-driven guess where the one from the fit's values does not explain (those
    values may be far off, `released_fit`'s ``from_guess``; 2026-12-02: a finger spectrum with
    ``--fix C_i=1.7n`` on data in kHz read as Hz (C_i 1000× larger) missed them by 7,300 % and was told a
    missing effect, though C_i freed from the guess reaches 1.48 %)."""
    n_points = int(np.asarray(data["frequency"]).size)

    def explained(subset):
        n_released = len({n for n, _, _ in subset})
        for from_guess in (False, True):
            released = released_fit(circuit, data, values, fixed, bounds, subset, weighting=weighting, registry=registry, fit=fit, from_guess=from_guess)
            if released is not None and constraint_explains(rms_constrained, released.rms_rel, kk, n_points, n_released):
                return released
        return None

    released = explained(constraints)
    if released is None:
        return None
    if len(constraints) == 1:
        return list(constraints), released
    alone = [(c, r) for c in constraints if (r := explained([c])) is not None]
    if not alone:
        return list(constraints), released
    if len(alone) == 1:
        return [alone[0][0]], alone[0][1]
    return [c for c, _ in alone], released


def constraint_note(constraints, kk: float, units: Mapping[str, str] | None = None) -> str:
    """The misfit note of a fit whose misfit its user's ``constraints`` explain; it holds the
    constraints and the data's figure ``kk``, not the fits' (single and batch fits in other
    local minima give the same text, as `result.misfit_notes`); ``units``: `constraint_words`'."""
    names = ", ".join(dict.fromkeys(n for n, _, _ in constraints))
    return (
        f"the misfit is a constraint you set, not the model's: with {constraint_words(constraints, units)} the fit misses the data, and one local fit "
        f"with {names} free reaches what the data allow (a Kramers–Kronig-consistent model reaches {kk * 100:.2g} % rms_rel) and at least halves the misfit; "
        f"fit with {names} free, or check the value you set (no effect is missing for this misfit)"
    )


def constraint_misfit_notes(circuit: Circuit, table: ParameterTable, registry: Registry, freq, z, z_model, sigma, values: Mapping[str, float], at_bound, misfit: tuple[str, ...], kk: float | None, *, weighting: str, fit: Callable, attrs=None) -> tuple[str, ...]:
    """``misfit`` (one fit's `result.misfit_notes`) with its note replaced by `constraint_note`
    where the user's binding constraints (`binding_constraints`) explain it, naming those that do
    (`explaining_constraints` on the spectrum z (N,) at ``freq``, σ ``sigma``
    (N,) or None, against the fit's model ``z_model``; ``kk``: the KK test's misfit that
    `misfit_notes` used). Unchanged otherwise: no note, no binding constraint, or freeing them
    does not explain the misfit, or the note holds the KK test's sign hint (`result.SIGN_HINT_LEAD`:
    freeing a constraint does not mend a stored sign). ``fit``: `single.fit` (`released_fit`)."""
    if not misfit or kk is None or not kk > 0 or any(f"; {SIGN_HINT_LEAD}" in note for note in misfit):
        return misfit
    fixed = {n: bool(f) for n, f in zip(table.names, table.fixed)}
    bounds = user_bounds(table, circuit, registry)
    constraints = binding_constraints(values, fixed, at_bound, bounds)
    if not constraints:
        return misfit
    from ...data import make_spectrum
    from .starts import rms_rel_of

    data = make_spectrum(np.asarray(freq, float), np.asarray(z, complex), sigma=None if sigma is None else np.asarray(sigma, float), attrs=dict(attrs or {}))
    rms_constrained = float(rms_rel_of(np.asarray(z_model)[None], np.asarray(z)[None])[0])
    with silenced():  # (its refits are part of the fit said already: their own lines repeated "fitting …", 2026-12-02)
        found = explaining_constraints(circuit, data, values, fixed, bounds, constraints, rms_constrained, kk, weighting=weighting, registry=registry, fit=fit)
    if found is None:
        return misfit
    return (constraint_note(found[0], kk, dict(zip(table.names, table.units))),)


def with_constraint_notes(notes: tuple[str, ...], misfit: tuple[str, ...], checked: tuple[str, ...]) -> tuple[str, ...]:
    """A fit's ``notes``, which end with its ``misfit`` notes, ending with ``checked``
    (`constraint_misfit_notes`) instead."""
    if checked == misfit or not misfit or tuple(notes[-len(misfit):]) != tuple(misfit):
        return tuple(notes)
    return tuple(notes[: -len(misfit)]) + tuple(checked)
