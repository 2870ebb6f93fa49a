"""The catalog of physical effects a diagnosis can propose: the one file to add an effect.

Each effect is a proposal function plus an `Effect` entry in `DEFAULT_EFFECTS` (a stable ``id``,
used in JSON; the physics in words; the residual signature it leaves when a model lacks it; the
circuit change in words). ``propose(circuit, context)`` returns one `Proposal` per sensible
placement in the given circuit: the augmented circuit (a valid impedax circuit) plus warm
starts — the baseline fit's values and data-driven guesses for the new element (from the misfit
ΔZ = Z_data − Z_model or ΔY = 1/Z_data − 1/Z_model where the effect acts). The types live in
`impedax.fitting.diagnosis.catalog`; docs/diagnosis.md, section 4, describes the eight effects.
"""

from __future__ import annotations

import re
from typing import Mapping

import numpy as np

from ...circuits import Circuit, DCPath, Element, Parallel, Registry, Series

from ...data import format_band, format_frequency, format_quantity
from ..arcs import arcs_beyond_band
from ..drt import PeakEvidence, r_cpe_tau
from .catalog import BaselineContext, Effect, EffectCatalog, Proposal

__all__ = ["DEFAULT_EFFECTS", "FINITE_WARBURGS", "IN_PLACE_OF_WARBURG", "added_resistors", "cited_where", "drt_citation", "element_parents", "placement"]


# --- tree helpers ---------------------------------------------------------------------------


def element_parents(circuit: Circuit) -> dict[str, Circuit | None]:
    """element name → the node that holds it directly (None for a one-element circuit)."""
    out: dict[str, Circuit | None] = {}

    def walk(node, parent):
        if isinstance(node, Element):
            out[node.name] = parent
            return
        for child in node.children:
            walk(child, node)

    walk(circuit, None)
    return out


def _holder(circuit: Circuit, node: Circuit) -> Circuit | None:
    """The series or parallel node that holds ``node`` (the very object) as a child, or None."""
    if isinstance(circuit, Element):
        return None
    for child in circuit.children:
        if child is node:
            return circuit
        found = _holder(child, node)
        if found is not None:
            return found
    return None


def _resistive(node: Circuit, registry: Registry) -> bool:
    """Does this branch conduct DC through a finite resistance (an element whose spec says
    `DCPath.CONDUCTS`, or a series/parallel chain that does)?"""
    if isinstance(node, Element):
        return registry[node.symbol].dc_path is DCPath.CONDUCTS
    if isinstance(node, Series):
        return all(_resistive(c, registry) for c in node.children)
    return any(_resistive(c, registry) for c in node.children)


def _top_series(circuit: Circuit) -> tuple[Circuit, ...]:
    return circuit.children if isinstance(circuit, Series) else (circuit,)


def _symbol(registry: Registry, e: Element) -> str:
    return registry[e.symbol].symbol


def _leaky_sibling(circuit: Circuit, name: str, registry: Registry) -> bool:
    """True when element ``name`` sits in a parallel block with a DC-conducting branch."""
    parent = element_parents(circuit)[name]
    if not isinstance(parent, Parallel):
        return False
    def conducts(node):  # a branch with a resistive element in it carries the low-frequency current
        return _resistive(node, registry) or any(_resistive(x, registry) for x in node.elements())

    return any(conducts(c) for c in parent.children if not (isinstance(c, Element) and c.name == name))


def _edl_leak_of(circuit: Circuit, name: str, registry: Registry) -> str | None:
    """The leak resistor of an electric double layer found before: the name of R_EP when
    capacitor ``name`` sits in a block R_EP ∥ ``name`` of two branches (R_EP: the name the
    electrode-polarization effect and the EDL model give it), else None."""
    parent = element_parents(circuit)[name]
    if not isinstance(parent, Parallel) or len(parent.children) != 2:
        return None
    other = next(c for c in parent.children if not (isinstance(c, Element) and c.name == name))
    leak = isinstance(other, Element) and _symbol(registry, other) == "R" and other.name.startswith("R_EP")
    return other.name if leak else None


def _arc_resistors(circuit: Circuit, registry: Registry) -> list[str]:
    """Resistors that are one branch of a parallel block (or in series inside such a branch)."""
    parents = element_parents(circuit)
    out = []
    for e in circuit.elements():
        if _symbol(registry, e) != "R":
            continue
        p = parents[e.name]
        if isinstance(p, Parallel) or (isinstance(p, Series) and p is not circuit):
            out.append(e.name)
    return out


def _positive(x: float, floor: float) -> float:
    return float(x) if np.isfinite(x) and x > floor else float(floor)


# --- proposal functions ---------------------------------------------------------------------


def _series_resistance(circuit: Circuit, ctx: BaselineContext) -> list[Proposal]:
    if any(isinstance(c, Element) and _symbol(ctx.registry, c) == "R" for c in _top_series(circuit)):
        return []
    _, hi = ctx.ends()
    name = ctx.fresh("R", "s")
    dz = ctx.z_data[hi] - ctx.z_model[hi]
    r0 = _positive(np.mean(dz.real), 1e-3 * np.abs(ctx.z_data).min())
    starts = tuple(ctx.start(**{name: r0 * s}) for s in (1.0, 0.2, 5.0))
    return [Proposal("series_resistance", circuit + Element("R", name), name, "in series with the whole circuit", starts)]


def _series_inductance(circuit: Circuit, ctx: BaselineContext) -> list[Proposal]:
    if any(isinstance(c, Element) and _symbol(ctx.registry, c) == "L" for c in _top_series(circuit)):
        return []
    _, hi = ctx.ends()
    name = ctx.fresh("L", "lead")
    w_top = ctx.omega[-1]
    dz = ctx.z_data[hi] - ctx.z_model[hi]
    l0 = _positive(np.max(dz.imag / ctx.omega[hi]), 1e-3 * np.abs(ctx.z_data[-1]) / w_top)
    starts = tuple(ctx.start(**{name: l0 * s}) for s in (1.0, 0.1, 10.0))
    return [Proposal("series_inductance", circuit + Element("L", name), name, "in series with the whole circuit (leads)", starts)]


def _stray_capacitance(circuit: Circuit, ctx: BaselineContext) -> list[Proposal]:
    if isinstance(circuit, Element) or (isinstance(circuit, Parallel) and any(isinstance(c, Element) and _symbol(ctx.registry, c) == "C" for c in circuit.children)):
        return []  # a capacitance across a capacitance adds nothing
    _, hi = ctx.ends()
    name = ctx.fresh("C", "stray")
    dy = 1 / ctx.z_data[hi] - 1 / ctx.z_model[hi]
    c0 = _positive(np.max(dy.imag / ctx.omega[hi]), 1e-2 / (ctx.omega[-1] * np.abs(ctx.z_data[-1])))
    starts = tuple(ctx.start(**{name: c0 * s}) for s in (1.0, 0.1, 10.0))
    out = [Proposal("stray_capacitance", Parallel((circuit, Element("C", name))), name, "across the whole circuit (fixture)", starts)]
    # a series resistance the baseline does not determine (standard error above its value) is
    # shunted by C_stray at the top of the band: the candidate without it as well (a finger's
    # R_f of 2 kΩ beside 8 kΩ of C_stray at 1 MHz; docs/diagnosis.md, section 5)
    loose = [c for c in _top_series(circuit) if isinstance(c, Element) and _symbol(ctx.registry, c) == "R" and c.name in ctx.undetermined]
    if loose and isinstance(circuit, Series):
        r = loose[0]
        inner = circuit.without(r.name)
        out.append(Proposal(
            "stray_capacitance", Parallel((inner, Element("C", name))), name,
            f"across the whole circuit (fixture), and {r.name} left out (the baseline does not determine it; C_stray shunts it at the top of the band)",
            tuple({k: v for k, v in s.items() if k != r.name} for s in starts), removed=(r.name,),
        ))
    return out


def _zarc_alpha(width_decades: float) -> float:
    """α of a ZARC R/(1 + (jωτ)^α) whose DRT has the full width at half maximum ``width_decades``:
    γ ∝ sin(απ)/(cosh(α ln(τ/τ0)) + cos(απ)) falls to half at α|ln(τ/τ0)| = arccosh(2 + cos απ),
    so FWHM = 2 arccosh(2 + cos απ)/(α ln 10), decreasing in α (solved by bisection)."""
    def fwhm(a):
        return 2 * np.arccosh(2 + np.cos(a * np.pi)) / (a * np.log(10))

    lo, hi = 0.3, 0.99
    if not np.isfinite(width_decades) or width_decades <= fwhm(hi):
        return hi
    if width_decades >= fwhm(lo):
        return lo
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if fwhm(mid) > width_decades else (lo, mid)
    return float(0.5 * (lo + hi))


def _distributed_alpha(ctx: BaselineContext, tau: float, tolerance_decades: float = 0.5) -> tuple[float, float] | None:
    """(τ of the peak, α guess) when the data's DRT has a distributed peak within
    ``tolerance_decades`` of ``tau``; α from the peak's width less the regularisation's own
    broadening (the matching model peak's width, an ideal R‖C under the same λ), added in
    quadrature."""
    ev = ctx.drt_evidence
    if ev is None or not ev.distributed or not (np.isfinite(tau) and tau > 0):
        return None
    near = [p for p in ev.distributed if abs(np.log10(p.tau_s / tau)) <= tolerance_decades]
    if not near:
        return None
    p = min(near, key=lambda q: abs(np.log10(q.tau_s / tau)))
    partner = [m for d, m in ev.explained if d is p]
    ideal = partner[0].width_decades if partner else min((m.width_decades for m in ev.model_peaks), default=0.0)
    return float(p.tau_s), _zarc_alpha(float(np.sqrt(max(p.width_decades**2 - ideal**2, 0.0))))


def _constant_phase(circuit: Circuit, ctx: BaselineContext) -> list[Proposal]:
    out = []
    parents = element_parents(circuit)
    for e in circuit.elements():
        if _symbol(ctx.registry, e) != "C":
            continue
        label = e.name[2:] if e.name.startswith("C_") else e.name[1:]
        name = f"CPE{label}" if label.isdigit() and f"CPE{label}" not in circuit.element_names else ctx.fresh("CPE", label)
        c = ctx.values.get(e.name, 1e-6)
        # the CPE matches the capacitor near the arc's corner frequency 1/(2π R C), if it has one
        parent = parents[e.name]
        r_sib = [ctx.values[x.name] for x in (parent.children if isinstance(parent, Parallel) else ()) if isinstance(x, Element) and _symbol(ctx.registry, x) == "R"]
        w_c = 1.0 / (r_sib[0] * c) if r_sib and r_sib[0] * c > 0 else np.sqrt(ctx.omega[0] * ctx.omega[-1])
        w_c = float(np.clip(w_c, ctx.omega[0], ctx.omega[-1]))
        alphas, where = (0.85, 0.7, 0.55), f"in place of the ideal capacitor {e.name}"
        # a distributed DRT peak at this arc's τ: start first at the α its width implies
        drt_peak = _distributed_alpha(ctx, 1.0 / w_c) if r_sib else None
        expected, evidence = {}, ""
        if drt_peak is not None:
            tau_peak, alpha_drt = drt_peak
            alphas = (alpha_drt,) + tuple(a for a in alphas if abs(a - alpha_drt) > 0.05)[:2]
            expected = {f"{name}.alpha": alpha_drt}
            evidence = f"the data's DRT peak at τ ≈ {format_quantity(tau_peak, 's')} is wider than an R‖C's: α ≈ {alpha_drt:.2f}"
        starts = []
        for alpha in alphas:
            start = {k: v for k, v in ctx.start().items() if k != e.name}
            start[f"{name}.Q"] = c * w_c ** (1 - alpha)
            start[f"{name}.alpha"] = alpha
            starts.append(start)
        out.append(Proposal("constant_phase", circuit.replace(e.name, Element("CPE", name)), name, where, tuple(starts), expected=expected, evidence=evidence))
    return out


def _arc_scan(ctx: BaselineContext, alpha: float, k: int = 3) -> list[tuple[float, float]]:
    """The k best (R, τ) of one arc R/(1 + (jωτ)^α) matched to the misfit ΔZ = Z_data − Z_model
    (for each τ on a log grid, R by weighted linear least squares; local minima of the rest)."""
    dz = ctx.z_data - ctx.z_model
    w2 = 1.0 / np.abs(ctx.z_data) ** 2
    f_grid = np.logspace(np.log10(ctx.frequency[0] / 3), np.log10(ctx.frequency[-1] * 3), 48)
    tau = 1.0 / (2 * np.pi * f_grid)
    b = 1.0 / (1.0 + (1j * ctx.omega[None, :] * tau[:, None]) ** alpha)
    r = np.maximum(np.sum(w2 * (np.conj(b) * dz).real, axis=1) / np.sum(w2 * np.abs(b) ** 2, axis=1), 0.0)
    cost = np.sum(w2 * np.abs(dz[None, :] - r[:, None] * b) ** 2, axis=1)
    cost = np.where(r > 0, cost, np.inf)
    minima = [i for i in range(cost.size) if np.isfinite(cost[i]) and (i == 0 or cost[i] <= cost[i - 1]) and (i == cost.size - 1 or cost[i] <= cost[i + 1])]
    minima.sort(key=lambda i: cost[i])
    return [(float(r[i]), float(tau[i])) for i in minima[:k]]


def _drt_arcs(ctx: BaselineContext, k: int = 2) -> list[tuple[float, float, float]]:
    """(R, τ, α) of up to ``k`` arcs the data's DRT shows and the baseline lacks (its unexplained
    peaks, largest first; α < 1 for a distributed peak, from its width)."""
    ev = ctx.drt_evidence
    if ev is None:
        return []
    out = []
    for p in sorted(ev.unexplained, key=lambda q: -q.r_ohm)[:k]:
        if not (p.r_ohm > 0 and np.isfinite(p.tau_s) and p.tau_s > 0):
            continue
        alpha = _zarc_alpha(p.width_decades) if any(p is d for d in ev.distributed) else 1.0
        out.append((float(p.r_ohm), float(p.tau_s), alpha))
    return out


def _relaxation_starts(ctx: BaselineContext, r_name: str, c_name: str, cpe: bool) -> tuple[dict, ...]:
    """Warm starts for a new R ∥ C (or R ∥ CPE): the data's unexplained DRT peaks first (R and τ
    read off the peak), then the arcs matched to the misfit ΔZ (`_arc_scan`) and guesses around
    the misfit's peak frequency."""
    alpha = 0.8 if cpe else 1.0
    f_x = ctx.misfit_frequency()
    i = int(np.argmin(np.abs(ctx.frequency - f_x)))
    dz = np.abs(ctx.z_data - ctx.z_model)
    r0 = _positive(2 * dz[: i + 1].max(), 0.02 * np.abs(ctx.z_data[i]))
    drt = [(r, tau, min(a, 0.9) if cpe else 1.0) for r, tau, a in _drt_arcs(ctx)]
    misfit = [(r, tau, alpha) for r, tau in _arc_scan(ctx, alpha)] + [(r0, t / (2 * np.pi * f_x), alpha) for t in (1.0, 0.2, 5.0)]
    starts = []
    for r, tau, a in (drt + misfit)[:4]:
        r = _positive(r, 1e-3 * np.abs(ctx.z_data).min())
        new = {r_name: r}
        if cpe:
            new[f"{c_name}.Q"] = tau**a / r
            new[f"{c_name}.alpha"] = a
        else:
            new[c_name] = tau / r
        starts.append(ctx.start(**new))
    return tuple(starts)


def _arc_tau(circuit: Circuit, values: Mapping[str, float], registry: Registry, r_name: str) -> float:
    """The time constant of the arc whose resistor is ``r_name``: R·C, or (R·Q)^(1/α) for a CPE
    beside it in the same parallel block (nan when it has neither; inf when a CPE's α near 0
    puts it beyond floating point)."""
    parent = element_parents(circuit)[r_name]
    r = values.get(r_name, np.nan)
    for x in parent.children if isinstance(parent, Parallel) else ():
        if isinstance(x, Element) and _symbol(registry, x) == "C":
            return float(r * values.get(x.name, np.nan))
        if isinstance(x, Element) and _symbol(registry, x) == "CPE":
            return r_cpe_tau(r, values.get(f"{x.name}.Q", np.nan), values.get(f"{x.name}.alpha", np.nan))
    return float("nan")


DRT_CITE_DECADES = 0.5
"""A fitted arc's τ within this many decades of a DRT peak the baseline does not explain (inside
the measured window) is named as that peak (`drt_citation`)."""

# the placements `_extra_relaxation` gives; the DRT citation follows them in the words
_RELAX_PLACEMENT = re.compile(r"in series with the whole circuit|nested in series with \S+ \(a layer behind that arc\)")
# `drt_citation`'s words (left out before they are given again: `cited_where` is idempotent)
_CITATION = re.compile(r" \(fitted τ = [^()]*, within half a decade of the data's DRT peak at [^()]* that the model does not explain\)")
# `arcs.ArcBeyondBand.words` (left out before they are given again, as `_CITATION`)
_BEYOND = re.compile(r" \(fitted τ = [^()]*: it relaxes at [^()]*: not a relaxation the data resolve\)")


def _unexplained_in_window(evidence: PeakEvidence | None):
    """The data's DRT peaks the baseline does not explain, largest R first, with a positive R and
    τ and inside the measured window (``Peak.inside_window``: a peak beyond it is the DRT's
    extrapolation, not a relaxation the data show)."""
    if evidence is None:
        return []
    peaks = sorted(evidence.unexplained, key=lambda q: -q.r_ohm)
    return [p for p in peaks if p.r_ohm > 0 and np.isfinite(p.tau_s) and p.tau_s > 0 and p.inside_window]


def _extra_relaxation(circuit: Circuit, ctx: BaselineContext) -> list[Proposal]:
    """A further arc R_relax ∥ C_relax (or ∥ CPE_relax) in series with the whole circuit or
    nested behind each arc resistor, started from the data's unexplained DRT peaks and the
    misfit. Which DRT peak a fitted arc stands for is said after the fit (`cited_where`)."""
    out = []
    names = ctx.fresh_group("relax", "R", "C", "CPE")  # (one number for the arc's elements: they pair)
    r_name = names["R"]
    resistors = _arc_resistors(circuit, ctx.registry)
    for sym in ("C", "CPE"):
        c_name = names[sym]
        arc = Parallel((Element("R", r_name), Element(sym, c_name)))
        starts = _relaxation_starts(ctx, r_name, c_name, sym == "CPE")
        out.append(Proposal("extra_relaxation", circuit + arc, str(arc), "in series with the whole circuit", starts))
        for r in resistors:
            nested = circuit.replace(r, Series((Element("R", r), arc)))
            out.append(Proposal("extra_relaxation", nested, str(arc), f"nested in series with {r} (a layer behind that arc)", starts))
    return out


def drt_citation(effect_id: str, proposal: Proposal, values: Mapping[str, float], registry: Registry, evidence: PeakEvidence | None) -> str:
    """The words naming the data's DRT peak a fitted ``extra_relaxation`` candidate stands for:
    `` (fitted τ = 20 ms, within half a decade of the data's DRT peak at 32.2 ms that the model
    does not explain)``, or "" (other effects, pairs of effects, no DRT evidence, no such peak).

    The peak must be one the baseline does not explain, whose R the DRT tells from zero (not
    in ``evidence.unresolved``: REAL PowerSuite's 4.8 ms peak, 99 ± 55 kΩ, which the DRT line
    calls a ripple, was cited in support two lines below it), lie inside the measured window
    (``Peak.inside_window``) and lie within `DRT_CITE_DECADES` of the fitted arc's τ (R·C, or
    (R·Q)^(1/α) for R ∥ CPE): the peak the warm start came from (the largest unexplained one)
    when it qualifies, else the qualifying peak nearest the fitted τ. Named before the fit,
    the warm start's peak was cited whatever the fit ended at: AutoEIS's battery cycle 64 with
    ``R0 + R1 || CPE1`` cited a 25 s peak outside the band for an arc fitted at 43.6 ms."""
    if effect_id != "extra_relaxation" or evidence is None:
        return ""
    names = set(re.findall(r"[A-Za-z_]\w*", proposal.added))
    r_names = [e.name for e in proposal.circuit.elements() if e.name in names and _symbol(registry, e) == "R"]
    if len(r_names) != 1:
        return ""
    tau = _arc_tau(proposal.circuit, values, registry, r_names[0])
    if not (np.isfinite(tau) and tau > 0):
        return ""
    largest = sorted(evidence.unexplained, key=lambda q: -q.r_ohm)[:1]  # the warm start's first peak
    ripples = {id(p) for p in evidence.unresolved}  # (the DRT line calls them not told from zero: no evidence to cite)
    near = [p for p in _unexplained_in_window(evidence) if abs(np.log10(tau / p.tau_s)) <= DRT_CITE_DECADES and id(p) not in ripples]
    if not near:
        return ""
    peak = largest[0] if any(p is largest[0] for p in near) else min(near, key=lambda p: abs(np.log10(tau / p.tau_s)))
    return f" (fitted τ = {format_quantity(tau, 's')}, within half a decade of the data's DRT peak at {format_quantity(peak.tau_s, 's')} that the model does not explain)"


def added_resistors(effect_id: str, added: str, circuit: Circuit, registry: Registry) -> tuple[str, ...]:
    """The resistors of the arcs an ``extra_relaxation`` candidate (alone or in a pair) adds, named
    in its ``added`` text; () for other effects, whose R ∥ C (a stray capacitance across a
    resistance) is meant to lie beyond the band."""
    if "extra_relaxation" not in effect_id.split("+"):
        return ()
    names = set(re.findall(r"[A-Za-z_]\w*", added))
    return tuple(e.name for e in circuit.elements() if e.name in names and _symbol(registry, e) == "R")


def placement(where: str) -> str:
    """A suggestion's ``where`` without `drt_citation`'s and `arcs.ArcBeyondBand.words`' words: the
    placement alone, the same for every candidate placed there whatever its fit (an R ∥ C and an
    R ∥ CPE in one place)."""
    return _BEYOND.sub("", _CITATION.sub("", where))


def cited_where(effect_id: str, proposal: Proposal, values: Mapping[str, float], registry: Registry, evidence: PeakEvidence | None, frequency=()) -> str:
    """``proposal.where`` for the fitted candidate: `drt_citation` after the placement's words
    (before what a derived candidate appends: ", and R0 left out (…)"), then the words of each
    added arc that relaxes outside the band of ``frequency`` [Hz] (`arcs.arcs_beyond_band`); words
    already there are replaced, so that this is idempotent."""
    where = proposal.where
    if "extra_relaxation" in effect_id.split("+"):
        where = placement(where)
    beyond = arcs_beyond_band(proposal.circuit, values, registry, frequency, added_resistors(effect_id, proposal.added, proposal.circuit, registry))
    note = drt_citation(effect_id, proposal, values, registry, evidence) + "".join(a.words() for a in beyond)
    if not note:
        return where
    m = _RELAX_PLACEMENT.match(where)
    k = m.end() if m else len(where)
    return where[:k] + note + where[k:]


# finite Warburgs: their low-frequency part is an arc (Ws) or R + C in series (Wo); diffusion
# shows only in their 45° region
FINITE_WARBURGS = ("Wo", "Ws")
# how a diffusion candidate's ``where`` begins when its finite Warburg replaces the circuit's W
IN_PLACE_OF_WARBURG = "in place of the semi-infinite Warburg"


def _beside_diffusion(circuit: Circuit, target: str | None, registry: Registry) -> bool:
    """Would an element added in series with ``target`` (None: at the end of the circuit) sit
    in a series chain that already holds a diffusion element (W, Wo, Ws)?"""
    if target is None:
        chain = _top_series(circuit)
    else:
        parent = element_parents(circuit)[target]
        chain = parent.children if isinstance(parent, Series) else ()
    return any(isinstance(c, Element) and _symbol(registry, c) in ("W",) + FINITE_WARBURGS for c in chain)


def _diffusion(circuit: Circuit, ctx: BaselineContext) -> list[Proposal]:
    out = []
    lo, _ = ctx.ends()
    dz = ctx.z_data[lo] - ctx.z_model[lo]
    w_lo = ctx.omega[lo]
    z_floor = 0.02 * np.abs(ctx.z_data[0])
    sigma0 = _positive(np.mean(np.abs(dz) * np.sqrt(w_lo) / np.sqrt(2)), z_floor * np.sqrt(ctx.omega[0]))
    r0 = _positive(np.max(np.abs(dz)), z_floor)
    tau0 = 1.0 / ctx.omega[0]
    band = (float(ctx.frequency[0]), float(ctx.frequency[-1]))
    placements = [(None, "in series at the end of the circuit")] + [(r, f"in series with {r} (Randles-type, behind the charge transfer)") for r in _arc_resistors(circuit, ctx.registry)]
    # a second diffusion element in series with one already there only splits its tail: W + W is
    # one W (σ₁ + σ₂), and W + Wo or W + Ws share the f^−½ branch above 1/τ
    placements = [(target, where) for target, where in placements if not _beside_diffusion(circuit, target, ctx.registry)]
    # modify before add: a semi-infinite Warburg already in the circuit may be finite (Wo, Ws)
    for e in circuit.elements():
        if _symbol(ctx.registry, e) != "W":
            continue
        sigma_w = ctx.values.get(f"{e.name}.sigma", sigma0)
        for sym in FINITE_WARBURGS:
            name = ctx.fresh(sym, e.name.split("_", 1)[1] if "_" in e.name else "d")
            # a finite layer behaves as W (R = σ√(2τ)) above 1/τ: start τ at and beyond the band's bottom
            starts = tuple(
                {**{k: v for k, v in ctx.start().items() if not k.startswith(f"{e.name}.")}, f"{name}.R": sigma_w * np.sqrt(2 * tau), f"{name}.tau": tau}
                for tau in (tau0, 0.1 * tau0, 10 * tau0)
            )
            out.append(Proposal("diffusion", circuit.replace(e.name, Element(sym, name)), name, f"{IN_PLACE_OF_WARBURG} {e.name} (a finite diffusion layer)", starts, band=band))
    for sym in ("W",) + FINITE_WARBURGS:
        name = ctx.fresh(sym, "d")
        if sym == "W":
            starts = tuple(ctx.start(**{f"{name}.sigma": sigma0 * s}) for s in (1.0, 0.2, 5.0))
        else:
            starts = tuple(ctx.start(**{f"{name}.R": r0 * sr, f"{name}.tau": tau0 * st}) for sr, st in ((1.0, 1.0), (1.0, 0.05), (3.0, 10.0)))
        for target, where in placements:
            new = circuit + Element(sym, name) if target is None else circuit.replace(target, Series((Element("R", target), Element(sym, name))))
            out.append(Proposal("diffusion", new, name, where, starts, band=band))
    return out


def _electrode_polarization(circuit: Circuit, ctx: BaselineContext) -> list[Proposal]:
    out = []
    lo, _ = ctx.ends()
    dy = 1 / ctx.z_data[lo] - 1 / ctx.z_model[lo]
    y_lo = np.abs(1 / ctx.z_data[0])
    g0 = _positive(np.mean(dy.real), 1e-3 * y_lo)
    b0 = _positive(np.mean(np.abs(dy)), 1e-2 * y_lo)
    w0 = ctx.omega[0]
    for e in circuit.elements():
        sym = _symbol(ctx.registry, e)
        leak = _edl_leak_of(circuit, e.name, ctx.registry) if sym == "C" else None
        if leak:  # the leak R_EP ∥ C_gap found before, completed with its capacitive part
            b_name = ctx.fresh("CPE", "EP")
            starts = tuple(ctx.start(**{f"{b_name}.Q": b0 / w0**alpha, f"{b_name}.alpha": alpha}) for alpha in (0.5, 0.25, 0.75))
            completed = circuit.replace(e.name, Parallel((Element("CPE", b_name), Element(e.symbol, e.name))))
            out.append(Proposal("electrode_polarization", completed, b_name, f"across {e.name} beside {leak} (the double layer's capacitive part)", starts))
        if sym not in ("C", "CPE") or _leaky_sibling(circuit, e.name, ctx.registry):
            continue
        ep_names = ctx.fresh_group("EP", "R", "C", "CPE")  # (R_EP pairs with its C_EP or CPE_EP)
        r_name = ep_names["R"]
        where = f"across {e.name} (electric double layer, Sirin et al.)"
        starts = tuple(ctx.start(**{r_name: s / g0}) for s in (1.0, 0.2, 5.0))
        out.append(Proposal("electrode_polarization", circuit.replace(e.name, Parallel((Element("R", r_name), Element(e.symbol, e.name)))), r_name, where, starts))
        b_sym = "CPE" if sym == "C" else "C"
        b_name = ep_names[b_sym]
        branch = Parallel((Element("R", r_name), Element(b_sym, b_name)))
        starts = []
        for s_r, alpha in ((1.0, 0.5), (5.0, 0.25), (0.2, 0.75), (1.0, 0.25)):
            new = {r_name: s_r / g0}
            if b_sym == "CPE":
                new[f"{b_name}.Q"] = b0 / w0**alpha
                new[f"{b_name}.alpha"] = alpha
            else:
                new[b_name] = b0 / w0 * s_r
            starts.append(ctx.start(**new))
        out.append(Proposal("electrode_polarization", circuit.replace(e.name, Parallel((Element("R", r_name), Element(b_sym, b_name), Element(e.symbol, e.name)))), str(branch), where, tuple(starts)))
    return out


def _inductive_loop(circuit: Circuit, ctx: BaselineContext) -> list[Proposal]:
    """A low-frequency inductive loop (adsorbed intermediates, corrosion): a branch
    R_loop + L_loop across an arc's resistor, R → R ∥ (R_loop + L_loop), docs/physics.md
    "Inductive loop": Z = R(R_loop + jωL)/(R + R_loop + jωL), a zero at R_loop/L and a pole at
    (R + R_loop)/L, between which Z'' is positive and the impedance falls from R to
    R·R_loop/(R + R_loop). Proposed only when the data lie on the loop's side of the model: below
    its real part at the band's low end, and above its imaginary part there or, on average, over
    the low-end run where Z'_data < Z'_model (a loop above the lowest points: the baseline's R
    settles between R and R ∥ R_loop, and its Z'' misfit is positive only near the loop). Warm
    starts: R_loop from that drop in Z'; L_loop = √(R_loop(R + R_loop))/ω at the peak of
    Z''_data − Z''_model over that run (the loop's Z'' peaks near the geometric mean of its zero
    and pole), and a decade either side."""
    lo, _ = ctx.ends()
    dz = ctx.z_data - ctx.z_model
    below = dz.real < 0
    # (the low-end run below the model's Z': from the lowest point on, or on past it when noise
    # lifts the lowest alone above the model; that point's Z'' still counts in the run's mean)
    first = 1 if below.size > 1 and not below[0] else 0
    run = first + (int(np.argmin(below[first:])) if not below[first:].all() else below.size - first)
    if not (np.mean(dz[lo].real) < 0 and (np.mean(dz[lo].imag) > 0 or np.mean(dz.imag[:max(run, lo.size)]) > 0)):
        return []
    drop = -float(np.mean(dz[lo].real))
    w_peak = float(ctx.omega[int(np.argmax(dz.imag[:max(run, 1)]))])
    band = (float(ctx.frequency[0]), float(ctx.frequency[-1]))
    out = []
    for r in _arc_resistors(circuit, ctx.registry):
        r_value = float(ctx.values.get(r, np.nan))
        if not (np.isfinite(r_value) and r_value > 0):
            continue
        excess = max(min(drop, 0.95 * r_value), 1e-6 * r_value)  # R − R ∥ R_loop at DC (a resistor run open: next to none of it)
        r_loop = _positive(r_value * (r_value / excess - 1.0), 1e-3 * r_value)
        l_loop = float(np.sqrt(r_loop) * np.sqrt(r_value + r_loop)) / w_peak
        loop_names = ctx.fresh_group("loop", "R", "L")
        r_name, l_name = loop_names["R"], loop_names["L"]
        starts = tuple(ctx.start(**{r_name: r_loop, l_name: l_loop * s}) for s in (1.0, 0.1, 10.0))
        new = circuit.replace(r, Parallel((Element("R", r), Series((Element("R", r_name), Element("L", l_name))))))
        out.append(Proposal("inductive_loop", new, f"{r_name} + {l_name}", f"across {r} (a low-frequency inductive loop)", starts, band=band))
    return out


# --- plausibility of fitted values ------------------------------------------------------------

STRAY_CAPACITANCE_MAX = 1e-9
"""F. Fixture and cable capacitance is pF to about a nF; microfarads across a sample are a
capacitive process of the sample (a double layer), not the fixture."""
LEAD_INDUCTANCE_MAX = 1e-4
"""H. Leads and cables have ~0.1–1 µH per metre; henries in series are not a lead."""


def _stray_plausible(values, p: Proposal) -> str | None:
    c = values.get(p.added, np.nan)
    if np.isfinite(c) and c > STRAY_CAPACITANCE_MAX:
        return f"{p.added} = {format_quantity(c, 'F')} is not fixture capacitance (pF–nF, at most {format_quantity(STRAY_CAPACITANCE_MAX, 'F')}): a capacitive path of the sample itself, which another effect should model"
    return None


def _lead_plausible(values, p: Proposal) -> str | None:
    inductance = values.get(p.added, np.nan)
    if np.isfinite(inductance) and inductance > LEAD_INDUCTANCE_MAX:
        return f"{p.added} = {format_quantity(inductance, 'H')} is not the inductance of leads (about a µH per metre, at most {format_quantity(LEAD_INDUCTANCE_MAX, 'H')}): an inductive process of the sample, not the wiring"
    return None


def _loop_plausible(values, p: Proposal) -> str | None:
    """The loop spans its zero R_loop/(2πL) to its pole (R + R_loop)/(2πL) (docs/physics.md,
    "Inductive loop"); that span must overlap the band: a loop above the band leaves the branch
    a plain resistor R_loop across R at every measured frequency, a loop below it an open
    branch; the data see no loop either way. R is the resistor the branch sits across (the
    other resistor of its parallel block)."""
    r_name, l_name = p.added.split(" + ")
    r_loop, inductance = values.get(r_name, np.nan), values.get(l_name, np.nan)
    block = _holder(p.circuit, element_parents(p.circuit)[r_name])
    across = next((c.name for c in (block.children if block is not None else ()) if isinstance(c, Element) and c.symbol == "R"), None)
    r_arc = values.get(across, np.nan) if across else np.nan
    if not (np.isfinite(r_loop) and np.isfinite(inductance) and np.isfinite(r_arc) and r_loop > 0 and inductance > 0 and r_arc > 0):
        return None
    f_zero, f_pole = r_loop / (2 * np.pi * inductance), (r_arc + r_loop) / (2 * np.pi * inductance)
    lo, hi = p.band
    if f_pole < lo or f_zero > hi:
        return (f"{l_name}, {r_name} and {across} put the loop at {format_band(f_zero, f_pole)}, outside the band ({format_band(lo, hi)}): "
                "the data see a resistance or an open branch there, not an inductive loop")
    return None


DIFFUSION_REGION_OMEGA_TAU = 5.0
"""A finite Warburg's phase is within 1° of 45° (diffusion, Z ∝ (jω)^−½) from ωτ = 5 on."""


def _diffusion_plausible(values, p: Proposal) -> str | None:
    """A finite Warburg (Wo, Ws; Z = R·coth or R·tanh of √(jωτ), over √(jωτ)) shows diffusion
    only where ωτ ≥ `DIFFUSION_REGION_OMEGA_TAU`; below, it acts as a resistance with a
    capacitive part (Ws: Z ≈ R(1 − jωτ/3), the start of an arc; phase −18° at ωτ = 1) or a
    resistance and a capacitor in series (Wo: −72° at ωτ = 1). With the band's top below that
    region the data see no diffusion, and an arc fits as well (SYNTHETIC R0 + R1 ∥ C1 + R2 ∥ C2
    with τ₂ = 0.6 µs above a 100 kHz band: Ws_d at τ = 1.1–1.6 µs, ΔAIC within 6 of R ∥ C)."""
    tau = values.get(f"{p.added}.tau", np.nan)
    if not (np.isfinite(tau) and tau > 0):
        return None
    f_diffusion = DIFFUSION_REGION_OMEGA_TAU / (2 * np.pi * tau)
    if f_diffusion > p.band[1]:
        return (f"{p.added}.tau = {format_quantity(tau, 's')}: its diffusion region (45°, from {format_frequency(f_diffusion)}) lies above the band's top ({format_frequency(p.band[1])}); "
                "the data see only its low-frequency part, which an arc or a capacitor makes as well, not diffusion")
    return None


DEFAULT_EFFECTS = EffectCatalog(
    (
        Effect(
            "series_resistance",
            "series resistance",
            "an ohmic resistance in series with everything: electrolyte, bulk tissue, electrodes, leads",
            "Z' offset at high frequency: the data's real part levels off above the model's",
            "add R_s in series with the whole circuit",
            _series_resistance,
        ),
        Effect(
            "series_inductance",
            "series inductance",
            "inductance of leads and cables (and of the instrument's wiring) in series with the sample",
            "positive Z'' (inductive) at the top of the band, growing with f, that the model cannot make",
            "add L_lead in series with the whole circuit",
            _series_inductance,
            _lead_plausible,
        ),
        Effect(
            "stray_capacitance",
            "stray capacitance",
            "a capacitance of the fixture or cables across the whole sample",
            "|Z| falls and the phase turns capacitive again at the top of the band",
            "put C_stray in parallel with the whole circuit (also without a series resistance the baseline does not determine)",
            _stray_capacitance,
            _stray_plausible,
        ),
        Effect(
            "constant_phase",
            "constant-phase behaviour",
            "a distribution of time constants (rough or inhomogeneous interfaces, fractional skin; Meyer) makes an ideal capacitor a CPE",
            "a depressed, too-symmetric arc: the data's −Z'' peak is lower and wider than the model's, slopes shallower than −1",
            "replace an ideal C by a CPE (α < 1)",
            _constant_phase,
        ),
        Effect(
            "extra_relaxation",
            "further relaxation",
            "a further process with its own time constant (a second layer, interface or dispersion)",
            "a run of same-sign residuals around one frequency decade: an arc or shoulder the model lacks",
            "add R_relax ∥ C_relax (or ∥ CPE_relax) in series, or nested behind an arc's resistor",
            _extra_relaxation,
        ),
        Effect(
            "diffusion",
            "diffusion (Warburg)",
            "mass transport by diffusion: semi-infinite (W), through a blocking (Wo) or transmissive (Ws) finite layer",
            "a 45° tail at low frequency: Z' and −Z'' rise together as f^−½, where the model flattens or turns vertical",
            "add W_d, Wo_d or Ws_d in series with an arc's resistor (Randles) or at the end",
            _diffusion,
            _diffusion_plausible,
        ),
        Effect(
            "electrode_polarization",
            "electrode polarization",
            "an electric double layer leaks charge across a capacitive element at low frequency (the EDL across the finger's air gap, Sirin et al.)",
            "below a crossover frequency the data are resistive (and |Z| lower) while the model stays capacitive",
            "put a leakage branch R_EP, R_EP ∥ CPE_EP (or ∥ C_EP) in parallel across a capacitive element, or a CPE_EP beside a leak R_EP ∥ C found before",
            _electrode_polarization,
        ),
        Effect(
            "inductive_loop",
            "low-frequency inductive loop",
            "a slow process that follows the potential with a lag (adsorbed intermediates, corrosion, a fuel cell's or battery's side reaction) makes the current lead: an inductive loop below the arcs",
            "at the low end the data fall below the model's Z' while Z'' turns positive (the Nyquist plot loops below the real axis)",
            "put R_loop + L_loop in parallel across an arc's resistor: R → R ∥ (R_loop + L_loop)",
            _inductive_loop,
            _loop_plausible,
        ),
    )
)
"""The default effect catalog (ids are stable: they appear in JSON)."""

