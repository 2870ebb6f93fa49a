"""SYNTHETIC multi-arc spectra for the DRT-evidence study of the diagnosis, from numpy formulas
written independently of impedax: Z = R0 + Σ R_k/(1 + (jωτ_k)^α_k) with proportional complex
Gaussian noise. A case is a user's circuit that lacks one arc of the truth (the diagnosis should
name ``extra_relaxation`` and place the new arc near the missing τ) or one that lacks nothing
(the diagnosis should find it adequate). `cases(split)` draws the development or the held-out
set from fixed seeds that do not overlap."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

F_MIN, F_MAX, N_POINTS = 1e-2, 1e5, 50
NOISES = (0.003, 0.01, 0.03)


@dataclass(frozen=True)
class Case:
    name: str
    circuit: str  # the user's circuit (impedax text)
    frequency: np.ndarray
    z: np.ndarray
    missing_tau: float | None  # τ of the arc the user's circuit lacks [s]; None: nothing missing
    noise: float


def arcs_impedance(f, r0, arcs):
    """R0 + Σ R/(1 + (jωτ)^α) over ``arcs`` = [(R, τ, α), ...] (α = 1: an ideal R ∥ C)."""
    jw = 2j * np.pi * np.asarray(f, float)
    return r0 + sum(r / (1.0 + (jw * tau) ** a) for r, tau, a in arcs)


def _noisy(z, level, rng):
    return z * (1.0 + level * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)))


def _window():
    """τ range of the measured band: 1/(2π f_max) .. 1/(2π f_min)."""
    return np.log10(1 / (2 * np.pi * F_MAX)), np.log10(1 / (2 * np.pi * F_MIN))


def draw_case(seed: int) -> Case:
    """One case from ``seed``: 2 or 3 true arcs at least 1.2 decades apart; in 3 of 4 cases one
    arc (its position drawn: lowest, middle, highest τ, or within 0.5 decade of the band edge)
    is left out of the user's circuit; ideal R ∥ C arcs, or ZARCs (α 0.75–0.9) with R ∥ CPE in
    the user's circuit."""
    rng = np.random.default_rng(seed)
    f = np.logspace(np.log10(F_MIN), np.log10(F_MAX), N_POINTS)
    lo, hi = _window()
    n_arcs = int(rng.choice([2, 3]))
    edge = rng.random() < 0.3
    for _ in range(1000):  # log τ drawn inside the window, ≥ 1.2 decades apart
        if edge:
            inner = np.sort(rng.uniform(lo + 1.0, hi - 1.0, n_arcs - 1))
            at_edge = rng.choice([lo + rng.uniform(0.1, 0.5), hi - rng.uniform(0.1, 0.5)])
            log_tau = np.sort(np.append(inner, at_edge))
        else:
            log_tau = np.sort(rng.uniform(lo + 0.6, hi - 0.6, n_arcs))
        if np.all(np.diff(log_tau) >= 1.2):
            break
    distributed = rng.random() < 0.35
    alphas = rng.uniform(0.75, 0.9, n_arcs) if distributed else np.ones(n_arcs)
    r0 = float(10 ** rng.uniform(0, 1.5))
    rs = 10 ** rng.uniform(1, 2.5, n_arcs)
    arcs = [(float(r), float(10**t), float(a)) for r, t, a in zip(rs, log_tau, alphas)]
    noise = float(rng.choice(NOISES))
    z = _noisy(arcs_impedance(f, r0, arcs), noise, rng)
    missing = rng.random() < 0.75
    if missing:
        if edge:
            k = int(np.argmin([min(abs(np.log10(t) - lo), abs(np.log10(t) - hi)) for _, t, _ in arcs]))
        else:
            k = int(rng.integers(n_arcs))
        kept = [i for i in range(n_arcs) if i != k]
    else:
        kept = list(range(n_arcs))
    block = "CPE" if distributed else "C"
    circuit = "R0 + " + " + ".join(f"R{j + 1} || {block}{j + 1}" for j in range(len(kept)))
    where = ("edge" if edge else ["low-tau", "mid-tau", "high-tau"][min(k, 2) if n_arcs == 3 else (0 if k == 0 else 2)]) if missing else "none"
    name = f"s{seed}:{n_arcs}{'zarc' if distributed else 'rc'}-{where}"
    return Case(name, circuit, f, z, arcs[k][1] if missing else None, noise)


def cases(split: str, n: int) -> list[Case]:
    """``n`` cases of the development (seeds 0..) or held-out (seeds 10000..) set."""
    first = {"dev": 0, "heldout": 10000}[split]
    return [draw_case(first + i) for i in range(n)]
