"""The catalog of physical effects a diagnosis can propose: the one file to add an effect.

Each effect is a proposal function plus an `Effect` entry in `DEFAULT_EFFECTS` (a stable ``id``,
used in JSON; the physics in words; the residual signature it leaves when a model lacks it; the
circuit change in words). ``propose(circuit, context)`` returns one `Proposal` per sensible
placement in the given circuit: the augmented circuit (a valid impedax circuit) plus warm
starts — the baseline fit's values and data-driven guesses for the new element (from the misfit
ΔZ = Z_data − Z_model or ΔY = 1/Z_data − 1/Z_model where the effect acts). The types live in
`impedax.fitting.diagnosis.catalog`; docs/diagnosis.md, section 4, describes the seven effects.
"""

from __future__ import annotations

import numpy as np

from ...circuits import Circuit, DCPath, Element, Parallel, Registry, Series

from .catalog import BaselineContext, Effect, EffectCatalog, Proposal

__all__ = ["DEFAULT_EFFECTS"]


# --- tree helpers ---------------------------------------------------------------------------


def _parents(circuit: Circuit) -> dict[str, Circuit | None]:
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
    parent = _parents(circuit)[name]
    if not isinstance(parent, Parallel):
        return False
    def conducts(node):  # a branch with a resistive element in it carries the low-frequency current
        return _resistive(node, registry) or any(_resistive(x, registry) for x in node.elements())

    return any(conducts(c) for c in parent.children if not (isinstance(c, Element) and c.name == name))


def _arc_resistors(circuit: Circuit, registry: Registry) -> list[str]:
    """Resistors that are one branch of a parallel block (or in series inside such a branch)."""
    parents = _parents(circuit)
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
    return [Proposal("stray_capacitance", Parallel((circuit, Element("C", name))), name, "across the whole circuit (fixture)", starts)]


def _constant_phase(circuit: Circuit, ctx: BaselineContext) -> list[Proposal]:
    out = []
    parents = _parents(circuit)
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
        starts = []
        for alpha in (0.85, 0.7, 0.55):
            start = {k: v for k, v in ctx.start().items() if k != e.name}
            start[f"{name}.Q"] = c * w_c ** (1 - alpha)
            start[f"{name}.alpha"] = alpha
            starts.append(start)
        out.append(Proposal("constant_phase", circuit.replace(e.name, Element("CPE", name)), name, f"in place of the ideal capacitor {e.name}", tuple(starts)))
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


def _relaxation_starts(ctx: BaselineContext, r_name: str, c_name: str, cpe: bool) -> tuple[dict, ...]:
    alpha = 0.8 if cpe else 1.0
    f_x = ctx.misfit_frequency()
    i = int(np.argmin(np.abs(ctx.frequency - f_x)))
    dz = np.abs(ctx.z_data - ctx.z_model)
    r0 = _positive(2 * dz[: i + 1].max(), 0.02 * np.abs(ctx.z_data[i]))
    arcs = _arc_scan(ctx, alpha) + [(r0, 1.0 / (2 * np.pi * f_x)), (r0, 0.2 / (2 * np.pi * f_x)), (r0, 5.0 / (2 * np.pi * f_x))]
    starts = []
    for r, tau in arcs[:4]:
        r = _positive(r, 1e-3 * np.abs(ctx.z_data).min())
        new = {r_name: r}
        if cpe:
            new[f"{c_name}.Q"] = tau**alpha / r
            new[f"{c_name}.alpha"] = alpha
        else:
            new[c_name] = tau / r
        starts.append(ctx.start(**new))
    return tuple(starts)


def _extra_relaxation(circuit: Circuit, ctx: BaselineContext) -> list[Proposal]:
    out = []
    r_name = ctx.fresh("R", "relax")
    for sym in ("C", "CPE"):
        c_name = ctx.fresh(sym, "relax")
        arc = Parallel((Element("R", r_name), Element(sym, c_name)))
        starts = _relaxation_starts(ctx, r_name, c_name, sym == "CPE")
        out.append(Proposal("extra_relaxation", circuit + arc, str(arc), "in series with the whole circuit", starts))
        for r in _arc_resistors(circuit, ctx.registry):
            nested = circuit.replace(r, Series((Element("R", r), arc)))
            out.append(Proposal("extra_relaxation", nested, str(arc), f"nested in series with {r} (a layer behind that arc)", starts))
    return out


def _diffusion(circuit: Circuit, ctx: BaselineContext) -> list[Proposal]:
    out = []
    lo, _ = ctx.ends()
    dz = ctx.z_data[lo] - ctx.z_model[lo]
    w_lo = ctx.omega[lo]
    z_floor = 0.02 * np.abs(ctx.z_data[0])
    sigma0 = _positive(np.mean(np.abs(dz) * np.sqrt(w_lo) / np.sqrt(2)), z_floor * np.sqrt(ctx.omega[0]))
    r0 = _positive(np.max(np.abs(dz)), z_floor)
    tau0 = 1.0 / ctx.omega[0]
    placements = [(None, "in series at the end of the circuit")] + [(r, f"in series with {r} (Randles-type, behind the charge transfer)") for r in _arc_resistors(circuit, ctx.registry)]
    for sym in ("W", "Wo", "Ws"):
        name = ctx.fresh(sym, "d")
        if sym == "W":
            starts = tuple(ctx.start(**{f"{name}.sigma": sigma0 * s}) for s in (1.0, 0.2, 5.0))
        else:
            starts = tuple(ctx.start(**{f"{name}.R": r0 * sr, f"{name}.tau": tau0 * st}) for sr, st in ((1.0, 1.0), (1.0, 0.05), (3.0, 10.0)))
        for target, where in placements:
            new = circuit + Element(sym, name) if target is None else circuit.replace(target, Series((Element("R", target), Element(sym, name))))
            out.append(Proposal("diffusion", new, name, where, starts))
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
        if sym not in ("C", "CPE") or _leaky_sibling(circuit, e.name, ctx.registry):
            continue
        r_name = ctx.fresh("R", "EP")
        where = f"across {e.name} (electric double layer, Sirin et al.)"
        starts = tuple(ctx.start(**{r_name: s / g0}) for s in (1.0, 0.2, 5.0))
        out.append(Proposal("electrode_polarization", circuit.replace(e.name, Parallel((Element("R", r_name), Element(e.symbol, e.name)))), r_name, where, starts))
        b_sym = "CPE" if sym == "C" else "C"
        b_name = ctx.fresh(b_sym, "EP")
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
        ),
        Effect(
            "stray_capacitance",
            "stray capacitance",
            "a capacitance of the fixture or cables across the whole sample",
            "|Z| falls and the phase turns capacitive again at the top of the band",
            "put C_stray in parallel with the whole circuit",
            _stray_capacitance,
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
        ),
        Effect(
            "electrode_polarization",
            "electrode polarization",
            "an electric double layer leaks charge across a capacitive element at low frequency (the EDL across the finger's air gap, Sirin et al.)",
            "below a crossover frequency the data are resistive (and |Z| lower) while the model stays capacitive",
            "put a leakage branch R_EP, R_EP ∥ CPE_EP (or ∥ C_EP) in parallel across a capacitive element",
            _electrode_polarization,
        ),
    )
)
"""The default effect catalog (ids are stable: they appear in JSON)."""

