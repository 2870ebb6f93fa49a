"""A starting equivalent circuit from a DRT: DRT → circuit → fit in one step (docs/drt.md,
"From the DRT to a circuit").

R0 (R_∞) + one R_k‖CPE_k per peak the report counts (`peaks.counted_peaks`: resolved and inside
the measured τ window), started at R_k = the peak's R, α = 0.9, Q_k = τ_k^α / R_k (so that
(R_k Q_k)^{1/α} = τ_k), or R_k‖C_k, C_k = τ_k/R_k, when the peak is as narrow as one ideal R‖C's
at the same λ and noise (`NARROW_FACTOR`, `shape.reference_width`; non-negative DRT); a Warburg W1 in series when the data end in a diffusion tail, a CPE in
series when they end in a constant-phase tail of another slope (`shape.low_frequency_tail`; the
peaks at the tail's τ are its own, not arcs); else a series CPE for a resolved peak beyond the
slowest point (the data show only its arc's fast side,
R/(jωτ)^α); L1 when the DRT's L is a visible part of |Z| at the top frequency (5 %, or 4× the
noise); a series C when
the DRT fitted one; R0 alone for a flat spectrum (`DRTResult.flat`). Unresolved peaks and peaks faster than the top frequency are left out.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from ...data import format_quantity, format_time, format_uncertain
from .peaks import RESOLVED_SIGMAS, counted_peaks
from .shape import low_frequency_tail, reference_width

__all__ = ["SuggestedCircuit", "suggest_circuit", "most_common_suggestion", "most_common_suggestion_at", "START_ALPHA", "R0_FLOOR_SHARE", "INDUCTIVE_SHARE", "INDUCTIVE_NOISE_MULTIPLE", "INDUCTIVE_SHARE_MIN", "NARROW_FACTOR", "NARROW_SLACK", "NARROW_NOISE_MULTIPLE"]

START_ALPHA = 0.9
"""The CPE exponent each arc starts at (the registry's default for CPE.alpha)."""

NARROW_FACTOR = 1.1
NARROW_SLACK = 0.01
NARROW_NOISE_MULTIPLE = 1.5
"""A counted peak starts as R‖C, not R‖CPE, when its FWHM is at most 1 + `NARROW_SLACK` +
`NARROW_NOISE_MULTIPLE` × the DRT's first-difference noise (at most `NARROW_FACTOR`) times that
of the DRT of one ideal R‖C at its τ, solved at the same frequencies, weights and λ
(`shape.reference_width`): as narrow as an ideal R‖C's at that noise. SYNTHETIC 1.2 kΩ + 85 kΩ/(1 +
(jω·1.87 ms)^α), 71 points 0.1 Hz–1 MHz, relative noise on each part, 8 seeds: α = 1 (an ideal
R‖C) 0.999–1.006× at 0.3 % noise, 0.995–1.017× at 1 %, 0.983–1.011× at 3 %, 0.985–1.015× at 5 %;
α 0.97 1.23–1.25× at 0.3 %, 1.05–1.12× at 5 %; α 0.9 ≥ 1.31×, α 0.8 ≥ 1.51× (0.5–3 %). The REAL
ZPlot file's arc (a fit gives α = 0.992, rms_rel 0.35 % against 0.51 % with a C) is 1.026× at
first-difference noise 0.35 % (limit 1.015): an R‖CPE."""

R0_FLOOR_SHARE = 1e-6
"""R0 starts at R_∞, but at least this share of max|Z|: a fit starts a resistance above 0 (a
DRT's R_∞ can be 0 or slightly negative when the data stop before the high-frequency limit)."""

INDUCTIVE_SHARE = 0.05
"""An inductor L1 joins the circuit when ω_max·L is at least this share of |Z| at the top
frequency: the share at which `DRTResult.warnings` names a negative L (below it, L is noise
about 0 or a lead the fit does not need)."""
INDUCTIVE_NOISE_MULTIPLE = 4.0
"""Below `INDUCTIVE_SHARE`, L1 also joins when ω_max·L is at least this many times the DRT's
noise (the larger of its residual σ and the first-difference noise, both relative to |Z|) and at
least `INDUCTIVE_SHARE_MIN` of |Z|: a lead's inductance is then a clear part of the top points.
A REAL ZPlot file: ω_max·L = 4.9 % of |Z| against a residual σ of 0.89 %; R0 + R1 ∥ CPE1 fits it
at rms_rel 1.35 %, with L1 at 0.35 % (AIC −383 → −494), and the 5 % rule alone left L1 out."""
INDUCTIVE_SHARE_MIN = 0.005
"""The least share of |Z| at the top frequency an inductance's ω_max·L must have to join the
circuit, however low the noise (noise-free data: a DRT's L of rounding size is no lead)."""


def _inductance_shows(share: float, result) -> bool:
    """Whether an inductance whose ω_max·L is ``share`` of |Z| at the top frequency is a visible
    part of the data of the DRT ``result``: at least `INDUCTIVE_SHARE`, or at least
    `INDUCTIVE_NOISE_MULTIPLE` × the DRT's noise and `INDUCTIVE_SHARE_MIN`."""
    noises = [v for v in (result.noise_estimate, result.difference_noise) if math.isfinite(v)]
    noise = max(noises) if noises else math.inf
    return share >= INDUCTIVE_SHARE or share >= max(INDUCTIVE_NOISE_MULTIPLE * noise, INDUCTIVE_SHARE_MIN)


@dataclass(frozen=True)
class SuggestedCircuit:
    """A starting circuit read off a DRT: ``model`` (circuit text, e.g. ``"R0 + R1 || CPE1"``),
    ``init`` (parameter name → start, SI units) and ``reasons`` (one short text per part, and per
    peak left out)."""

    model: str
    init: Mapping[str, float] = field(default_factory=dict)
    reasons: tuple[str, ...] = ()

    @property
    def n_arcs(self) -> int:
        """The R‖CPE and R‖C arcs in ``model``."""
        return self.model.count("||")

    def fit_options(self) -> str:
        """The ``impedax fit`` options that fit ``model`` from ``init``: ``--model '…' --init …``."""
        starts = " ".join(f"{name}={value:.4g}" for name, value in self.init.items())
        return f"--model '{self.model}' --init {starts}"

    def fit_command(self, data: str = "FILE") -> str:
        """The ``impedax fit`` command line that fits ``model`` to ``data`` from ``init``."""
        return f"impedax fit {data} {self.fit_options()}"


def suggest_circuit(result) -> SuggestedCircuit:
    """The starting circuit of a `DRTResult` (module docstring): R0 + one R_k‖CPE_k per counted
    peak outside a diffusion tail (+ W1, + L1, + C). Without an arc (and no tail) R0 + C1: it fits
    a spectrum that stays resistive (C1 grows) or turns capacitive at its low end."""
    z_top = abs(result.impedance[int(np.argmax(result.frequency))])
    init = {"R0": max(float(result.r_inf_ohm), R0_FLOOR_SHARE * float(result.z_ref))}
    parts, reasons = ["R0"], [f"R0: the series resistance R_inf = {format_quantity(result.r_inf_ohm, 'Ω', 4)}"]
    omega_max = 2 * math.pi * float(result.frequency.max())
    if result.l_h > 0 and _inductance_shows(omega_max * result.l_h / z_top, result):
        parts.append("L1")
        init["L1"] = float(result.l_h)
        reasons.append(f"L1: the DRT's L = {format_quantity(result.l_h, 'H')}, ωL = {omega_max * result.l_h / z_top * 100:.2g} % of |Z| at the top frequency")
    tail = low_frequency_tail(result.frequency, result.impedance)
    tail_from = math.inf if tail is None else tail.tau_s
    tail_name = "W1" if tail is None or tail.warburg else "the tail's CPE"
    counted = {id(p) for p in counted_peaks(result.peaks)}
    slow_end = result.window[1]
    k, beyond = 0, None
    for p in result.peaks:
        at = f"the peak at τ = {format_time(p.tau_s)} ({format_uncertain(p.r_ohm, p.r_ohm_sd, 'Ω')})"
        if p.tau_s >= tail_from:
            reasons.append(f"{at} left out: it lies in the {'diffusion' if tail.warburg else 'constant-phase'} tail ({tail_name} holds it)")
        elif p.r_ohm <= 0:
            reasons.append(f"{at} left out: a negative R (signed DRT) is no R‖CPE arc")
        elif p.resolved and p.tau_s > slow_end and beyond is None:
            beyond = p
        elif id(p) not in counted:
            why = "outside the measured τ window" if not p.inside_window else f"its R is not told from zero ({RESOLVED_SIGMAS:g} sd)"
            reasons.append(f"{at} left out: {why}")
        elif (ideal := _ideal_width(result, p)) is not None:
            k += 1
            parts.append(f"R{k} || C{k}")
            init |= {f"R{k}": p.r_ohm, f"C{k}": p.tau_s / p.r_ohm}
            reasons.append(f"R{k} || C{k}: {at}, resolved and inside the measured τ window, {p.width_decades:.2f} decades wide, "
                           f"as narrow as one ideal R‖C's at this λ ({ideal:.2f}): no sign of a distributed arc (a CPE)")
        else:
            k += 1
            parts.append(f"R{k} || CPE{k}")
            init |= {f"R{k}": p.r_ohm, f"CPE{k}.Q": p.tau_s**START_ALPHA / p.r_ohm, f"CPE{k}.alpha": START_ALPHA}
            reasons.append(f"R{k} || CPE{k}: {at}, resolved and inside the measured τ window")
    if beyond is not None:
        # an arc whose τ lies beyond the slowest point shows only its fast side, R/(jωτ)^α for
        # ωτ ≫ 1: a series CPE, Q = τ^α/R (its R the data cannot tell)
        name = f"CPE{k + 1}"
        parts.append(name)
        init |= {f"{name}.Q": beyond.tau_s**START_ALPHA / beyond.r_ohm, f"{name}.alpha": START_ALPHA}
        reasons.append(f"{name} in series: the peak at τ = {format_time(beyond.tau_s)} lies beyond the slowest point (τ {format_time(slow_end)}); "
                       "the data show only its arc's start, R/(jωτ)^α")
    if tail is not None and tail.warburg:
        parts.append("W1")
        init["W1.sigma"] = _warburg_sigma(result)
        reasons.append(f"W1: {tail.words()}, a Warburg's ω^−0.5 (a diffusion tail)")
    elif tail is not None:
        # −Im Z = sin(απ/2)/(Q ω^α) of a CPE in series (its slope −α; a Warburg is α = 0.5)
        name = f"CPE{k + 1 + (beyond is not None)}"
        alpha = min(max(tail.alpha, 0.05), 1.0)
        parts.append(name)
        init |= {f"{name}.Q": _tail_cpe_q(result, alpha), f"{name}.alpha": alpha}
        reasons.append(f"{name} in series: {tail.words()}, not a Warburg's ω^−0.5: a constant-phase tail, α ≈ {alpha:.2f}")
    if not math.isinf(result.c_f):
        parts.append(f"C{k + 1}")
        init[f"C{k + 1}"] = float(result.c_f)
        reasons.append(f"C{k + 1}: the DRT's series C = {format_quantity(result.c_f, 'F')}")
    elif k == 0 and beyond is None and math.isinf(tail_from) and result.flat:
        reasons.append("R0 alone: the spectrum is flat (∫|γ| is round-off, docs/drt.md \"Peaks\"); it has no arc, tail or capacitive end to fit")
    elif k == 0 and beyond is None and math.isinf(tail_from):
        parts.append("C1")
        init["C1"] = _low_end_capacitance(result)
        reasons.append("C1: no arc is resolved inside the measured τ window; R0 + C1 fits a spectrum that stays resistive (C1 grows) "
                       "or turns capacitive at its low end; measure lower frequencies to see an arc")
    if result.sign_hint:  # (the parts stand, but they were read off data no passive cell gives)
        reasons.insert(0, "read off data whose sign looks flipped (the DRT's sign_hint): correct the sign first, then run the DRT again")
    if result.over_smoothed:  # (the parts stand, but they were read off a γ smoothed past the data)
        reasons.insert(0, f"read off a DRT whose λ = {result.lam:.3g} over-smooths the data (its warning): run the DRT again at a smaller λ or the automatic one")
    return SuggestedCircuit(" + ".join(parts), init, tuple(reasons))


def _ideal_width(result, peak) -> float | None:
    """The FWHM [decades] of one ideal R‖C's DRT at ``peak``'s τ (`shape.reference_width`) when
    ``peak`` is as narrow at the DRT's noise (`NARROW_FACTOR`); None when wider, or for a signed DRT
    (the reference is solved under γ ≥ 0)."""
    if result.signed or not peak.width_decades > 0:
        return None
    noise = result.difference_noise if math.isfinite(result.difference_noise) else 0.0
    limit = min(NARROW_FACTOR, 1.0 + NARROW_SLACK + NARROW_NOISE_MULTIPLE * noise)
    ideal = reference_width(result, peak.tau_s)
    return ideal if ideal > 0 and peak.width_decades <= limit * ideal else None


def _warburg_sigma(result) -> float:
    """σ [Ω s^−½] of σ(1 − j)/√ω from the lowest half decade: the median of −Im Z·√ω."""
    f = np.asarray(result.frequency, float)
    low = f <= f.min() * math.sqrt(10.0)
    values = -np.imag(result.impedance[low]) * np.sqrt(2 * math.pi * f[low])
    return float(np.median(values[values > 0])) if np.any(values > 0) else 1.0


def _tail_cpe_q(result, alpha: float) -> float:
    """Q [F s^(α−1)] of a series CPE 1/(Q (jω)^α) from the lowest half decade: −Im Z =
    sin(απ/2)/(Q ω^α), so Q = sin(απ/2)/(−Im Z·ω^α), the median over those points."""
    f = np.asarray(result.frequency, float)
    low = f <= f.min() * math.sqrt(10.0)
    values = -np.imag(result.impedance[low]) * (2 * math.pi * f[low]) ** alpha
    return math.sin(alpha * math.pi / 2) / float(np.median(values[values > 0])) if np.any(values > 0) else 1.0


def _low_end_capacitance(result) -> float:
    """C [F] with 1/(ω_min C) = −Im Z at the lowest frequency (at least 0.1 % of |Z| there)."""
    low = int(np.argmin(result.frequency))
    z = result.impedance[low]
    return 1.0 / (2 * math.pi * float(result.frequency[low]) * max(-float(np.imag(z)), 1e-3 * abs(z)))


def most_common_suggestion(results) -> tuple[SuggestedCircuit, int]:
    """(the suggestion whose model most spectra of ``results`` share — the first spectrum's of
    them, with its starts —, how many share it); ties go to the model met first. Spectra with a
    ``sign_hint`` (a sign stored flipped) or an over-smoothing fixed λ (`DRTResult.over_smoothed`)
    take part only when every spectrum has one."""
    _, suggestion, count = most_common_suggestion_at(results)
    return suggestion, count


def most_common_suggestion_at(results, suggestions=None) -> tuple[int, SuggestedCircuit, int]:
    """`most_common_suggestion` with, first, the index in ``results`` of the spectrum whose starts
    it gives (the batch JSON's ``suggested_from``); ``suggestions``: each
    result's `DRTResult.suggested_circuit` when already read (default: read here)."""
    taking = [i for i, r in enumerate(results) if not (r.sign_hint or r.over_smoothed)] or list(range(len(results)))
    suggestions = [(i, results[i].suggested_circuit() if suggestions is None else suggestions[i]) for i in taking]
    model, count = Counter(s.model for _, s in suggestions).most_common(1)[0]
    index, suggestion = next((i, s) for i, s in suggestions if s.model == model)
    return index, suggestion, count
