"""Arcs (R ∥ C and R ∥ CPE blocks) against the measured band: where each relaxes, and those the
data see only one flank of.

An arc R/(1 + (jωτ)^α) (R ∥ C: α = 1, τ = RC; R ∥ CPE: τ = (RQ)^(1/α); docs/physics.md, the
ZARC) peaks in −Z'' at its relaxation frequency 1/(2πτ). Far above the band the data see its
low-frequency flank, where it acts as its resistor, so its capacitance (C or Q) only bends the
band's top: an extrapolation of the model. Far below, they see its high-frequency flank, where it
acts as its capacitance, and its resistance is the extrapolation. Fits (`least_squares.result.
arc_beyond_band_notes`), diagnoses and refinements (`diagnosis.effects`) say so.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from ..circuits import Circuit, Element, Parallel, Registry
from ..data import format_quantity

__all__ = ["ArcBeyondBand", "BEYOND_BAND_FACTOR", "FAR_BEYOND_FACTOR", "arc_taus", "arcs_beyond_band", "circuit_arcs"]

BEYOND_BAND_FACTOR = 2.0
"""How far outside the band (a ratio of frequencies) an arc's relaxation frequency 1/(2πτ) must
lie to be flagged (`arcs_beyond_band`): nearer, the data reach its flank up to 80 % of its peak
−Z'' (an R ∥ C's −Z''/max = 2ωτ/(1 + (ωτ)²) = 0.8 at ωτ = 1/2), close enough to place it."""

FAR_BEYOND_FACTOR = 1e3
"""Beyond this ratio of frequencies outside the band an arc's τ is no number the data tell: it
acts as its resistor (above) or its capacitance (below) alone, and `ArcBeyondBand` says that
instead of the figures (refine on REAL CH Instruments data printed "τ = 8.02e+33 s: it relaxes
at 1.98e-35 Hz, 5e+33× below the band's bottom"; a walkthrough, 2026-12-04)."""


@dataclass(frozen=True)
class ArcBeyondBand:
    """An arc (R ∥ C or R ∥ CPE) whose relaxation frequency 1/(2πτ) lies outside the band
    ``band_hz`` its fit saw by more than `BEYOND_BAND_FACTOR`: ``side`` "above" its top or
    "below" its bottom (the module's docstring says what the data see of it then)."""

    resistor: str
    capacitance: str
    tau_s: float
    band_hz: tuple[float, float]

    @property
    def frequency_hz(self) -> float:
        return 1.0 / (2 * np.pi * self.tau_s)

    @property
    def side(self) -> str:
        return "above" if self.frequency_hz > self.band_hz[1] else "below"

    @property
    def factor(self) -> float:
        """How far outside, as a ratio of frequencies (> 1)."""
        return self.frequency_hz / self.band_hz[1] if self.side == "above" else self.band_hz[0] / self.frequency_hz

    @property
    def elements(self) -> str:
        return f"{self.resistor} || {self.capacitance}"

    @property
    def acts_as(self) -> str:
        """The element the arc acts as over the band when far from it (`FAR_BEYOND_FACTOR`): its
        resistor above the band, its capacitance below."""
        return self.resistor if self.side == "above" else self.capacitance

    @property
    def extrapolated(self) -> str:
        """The element whose value only the flank the data miss would fix."""
        return self.capacitance if self.side == "above" else self.resistor

    def sentence(self) -> str:
        """``fitted τ = 71 ns: it relaxes at 2.24 MHz, 7.5× above the band's top, 300 kHz, so the
        data see only the low-frequency flank of its arc, where it acts as a resistance, and
        C_relax is an extrapolation: not a relaxation the data resolve``."""
        edge, flank, acts = ("top", "low", "a resistance") if self.side == "above" else ("bottom", "high", "its capacitance")
        if self.factor > FAR_BEYOND_FACTOR:
            return (
                f"it relaxes more than {FAR_BEYOND_FACTOR:.0f}× {self.side} the band's {edge}, {format_quantity(self.band_hz[1] if self.side == 'above' else self.band_hz[0], 'Hz')} "
                f"(fitted τ = {format_quantity(self.tau_s, 's')}), so over the whole band it acts as {self.acts_as} alone and {self.extrapolated} does not show in the data: "
                "not a relaxation the data resolve"
            )
        return (
            f"fitted τ = {format_quantity(self.tau_s, 's')}: it relaxes at {format_quantity(self.frequency_hz, 'Hz')}, {self.factor:.2g}× {self.side} the band's {edge}, "
            f"{format_quantity(self.band_hz[1] if self.side == 'above' else self.band_hz[0], 'Hz')}, so the data see only the {flank}-frequency flank of its arc, where it acts as "
            f"{acts}, and {self.extrapolated} is an extrapolation: not a relaxation the data resolve"
        )

    def words(self) -> str:
        """`sentence` in parentheses, as a suggestion's placement carries it."""
        return f" ({self.sentence()})"

    def remedy(self) -> str:
        """What would resolve the arc: ``a band reaching past 2.24 MHz would show its peak``; for
        an arc beyond `FAR_BEYOND_FACTOR`, the element it acts as alone."""
        if self.factor > FAR_BEYOND_FACTOR:
            return f"the model with {self.acts_as} alone in place of {self.elements} may be enough"
        return f"a band reaching {'past' if self.side == 'above' else 'below'} {format_quantity(self.frequency_hz, 'Hz')} would show its peak"

    def as_json(self) -> dict:
        return {"elements": [self.resistor, self.capacitance], "tau_s": self.tau_s, "frequency_hz": self.frequency_hz, "side": self.side, "band_hz": list(self.band_hz), "extrapolated": self.extrapolated}


def circuit_arcs(circuit: Circuit, registry: Registry) -> tuple[tuple[str, str, str], ...]:
    """(resistor, capacitance, its symbol "C" or "CPE") of each parallel block of exactly a
    resistor and a capacitor or CPE in ``circuit``, in the circuit's order."""
    out = []

    def walk(node):
        if isinstance(node, Element):
            return
        if isinstance(node, Parallel) and len(node.children) == 2 and all(isinstance(c, Element) for c in node.children):
            symbols = {registry[c.symbol].symbol: c.name for c in node.children}
            capacitance = next((s for s in ("C", "CPE") if s in symbols), None)
            if "R" in symbols and capacitance is not None:
                out.append((symbols["R"], symbols[capacitance], capacitance))
                return
        for child in node.children:
            walk(child)

    walk(circuit)
    return tuple(out)


def arc_taus(symbol: str, r, c_or_q, alpha=None) -> np.ndarray:
    """τ [s] of R ∥ C (RC) or of R ∥ CPE ((RQ)^(1/α)) for arrays of values; NaN where RQ ≤ 0 or
    α ≤ 0, inf where a small α puts it beyond floating point."""
    r, c = np.asarray(r, float), np.asarray(c_or_q, float)
    with np.errstate(all="ignore"):  # (a resistor run open times its C overflows to inf: no arc to speak of)
        rc = r * c
        if symbol == "C":
            return np.where(rc > 0, rc, np.nan)
        a = np.asarray(alpha, float)
        ok = (rc > 0) & (a > 0)
        return np.where(ok, np.exp(np.log(np.where(ok, rc, 1.0)) / np.where(ok, a, 1.0)), np.nan)


def _parameter_names(capacitance: str, symbol: str, registry: Registry) -> tuple[str, ...]:
    """The parameter names of the capacitance of an arc: (C,) or (Q, α)."""
    return registry[symbol].parameter_names(capacitance) if symbol == "CPE" else (capacitance,)


def arcs_beyond_band(circuit: Circuit, values: Mapping[str, float], registry: Registry, frequency, resistors=None) -> tuple[ArcBeyondBand, ...]:
    """The arcs of ``circuit`` (`circuit_arcs`; only those whose resistor is one of
    ``resistors`` when given) whose relaxation frequency 1/(2πτ) lies outside the band of
    ``frequency`` [Hz] by more than `BEYOND_BAND_FACTOR`."""
    f = np.asarray(frequency, float)
    if f.size == 0:
        return ()
    band = (float(np.min(f)), float(np.max(f)))
    out = []
    for r_name, c_name, symbol in circuit_arcs(circuit, registry):
        if resistors is not None and r_name not in resistors:
            continue
        params = [values.get(n, np.nan) for n in _parameter_names(c_name, symbol, registry)]
        tau = float(arc_taus(symbol, values.get(r_name, np.nan), *params))
        if not (np.isfinite(tau) and tau > 0):
            continue
        arc = ArcBeyondBand(r_name, c_name, tau, band)
        if not band[0] / BEYOND_BAND_FACTOR <= arc.frequency_hz <= band[1] * BEYOND_BAND_FACTOR:
            out.append(arc)
    return tuple(out)
