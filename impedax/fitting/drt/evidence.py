"""DRT evidence for the diagnosis: the peaks of the data's DRT that a fitted circuit does not
explain, and the peaks broader than the circuit's (a CPE where the circuit has a capacitor)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...data import format_quantity, format_time, format_uncertain
from ...errors import DataError
from ..frozen import FrozenResult, freeze_fields
from .peaks import RESOLVED_SIGMAS, Peak
from .result import DRTResult

__all__ = ["PeakEvidence", "unexplained_peaks", "is_resolved", "RESOLVED_SIGMAS"]

def is_resolved(peak: Peak) -> bool:
    """Whether ``peak``'s |R| is at least `RESOLVED_SIGMAS` × its standard deviation (True when
    the DRT has no credible band to say otherwise: ``r_ohm_sd`` nan); the rule `Peak.resolved`
    holds (peaks.py), here for a peak built or edited by hand too."""
    return not abs(peak.r_ohm) < RESOLVED_SIGMAS * peak.r_ohm_sd


@dataclass(frozen=True, eq=False)
class PeakEvidence(FrozenResult):
    """What the data's DRT says about a fitted circuit.

    ``data_peaks``/``model_peaks``: peaks of the data's DRT and of the DRT of the circuit's
    spectrum (same frequencies, basis and λ, so both are broadened alike);
    ``explained``: (data peak, model peak) pairs within ``tolerance_decades`` in τ;
    ``unexplained``: data peaks with no model peak — each is a τ guess (``tau_s``) and a
    resistance (``r_ohm``) for a missing relaxation; ``nearest_model_tau``: for each of those, the
    τ of the closest model peak (the block the new arc sits beside; nan if the model has none);
    ``distributed``: data peaks wider than ``distributed_ratio`` × the matching model peak (or ×
    an ideal R‖C's peak under the same regularisation, when unexplained) — a CPE/ZARC where the
    circuit has (or lacks) a capacitor; ``unresolved``: the unexplained peaks whose R the DRT's
    credible band does not tell from zero (`is_resolved`; still τ and R guesses for a proposal,
    which the fit then judges); ``text``: one line for the diagnosis report.
    """

    data_peaks: tuple[Peak, ...]
    model_peaks: tuple[Peak, ...]
    explained: tuple[tuple[Peak, Peak], ...]
    unexplained: tuple[Peak, ...]
    nearest_model_tau: tuple[float, ...]
    distributed: tuple[Peak, ...]
    text: str
    unresolved: tuple[Peak, ...] = ()

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def n_explained(self) -> int:
        return len(self.explained)


def _model_spectrum(model):
    if hasattr(model, "z_model") and hasattr(model, "frequency"):
        return np.asarray(model.frequency, float), np.asarray(model.z_model, complex)
    try:
        f, z = model
        return np.asarray(f, float), np.asarray(z, complex)
    except (TypeError, ValueError):
        raise DataError(f"model must be a FitResult, a (frequency, Z_model) pair or a DRTResult, got {type(model).__name__}") from None


def unexplained_peaks(data_drt: DRTResult, model, *, tolerance_decades: float = 0.5, distributed_ratio: float = 1.6, solve=None) -> PeakEvidence:
    """The peaks of ``data_drt`` that the fitted ``model`` does not explain.

    Contract (for `diagnose` and other callers):
    - ``data_drt``: `impedax.drt(data)` of one spectrum (a `DRTResult`).
    - ``model``: a `FitResult` (its ``frequency`` and ``z_model`` are used), a
      (frequency, Z_model) pair, or a `DRTResult` the caller computed; in the first two cases
      the model's DRT is computed here with the data's λ and basis (``data_drt.lam``,
      ``data_drt.options``), so a circuit that reproduces the data reproduces its peaks.
    - A data peak is explained when a model peak lies within ``tolerance_decades`` of it in
      log10 τ (greedy, largest data peaks first, each model peak used once).
    - Returns a frozen `PeakEvidence`; ``unexplained`` peaks give the τ and R guesses for an
      ``extra_relaxation`` (an R‖C or R‖CPE with τ = tau_s, R = r_ohm); ``distributed`` peaks
      suggest ``constant_phase``; ``text`` reads e.g. "the data's DRT has 3 peaks (at 2 ms,
      0.3 s, 40 s); the model explains 2; unexplained: 40 s (R ≈ 12 Ω)".
    - ``solve``: what computes the model's and the reference DRTs, called as `drt` is
      (default `drt`; `diagnose` passes its `DRTMemo`, so a spectrum met again is not solved again).
    Never raises for a model without peaks (all data peaks are then unexplained); raises
    `DataError` for a model that is none of the accepted kinds.
    """
    from ._drt import drt

    solve = drt if solve is None else solve

    if not isinstance(data_drt, DRTResult):
        raise DataError(f"data_drt must be the DRTResult of one spectrum, got {type(data_drt).__name__}")
    options = dict(data_drt.options)
    if isinstance(model, DRTResult):
        model_drt = model
    else:
        f, z = _model_spectrum(model)
        model_drt = solve((f, z), lam=data_drt.lam, **options)
    data_peaks, model_peaks = data_drt.peaks, model_drt.peaks
    used: set[int] = set()
    explained, unexplained = [], []
    for p in sorted(data_peaks, key=lambda p: -abs(p.r_ohm)):
        distances = [abs(math.log10(p.tau_s / m.tau_s)) if i not in used else math.inf for i, m in enumerate(model_peaks)]
        k = int(np.argmin(distances)) if distances else -1
        if k >= 0 and distances[k] <= tolerance_decades:
            used.add(k)
            explained.append((p, model_peaks[k]))
        else:
            unexplained.append(p)
    explained.sort(key=lambda pair: pair[0].tau_s)
    unexplained.sort(key=lambda p: p.tau_s)
    nearest = tuple(
        float(min(model_peaks, key=lambda m: abs(math.log10(p.tau_s / m.tau_s))).tau_s) if model_peaks else float("nan") for p in unexplained
    )
    distributed = [p for p, m in explained if p.width_decades > distributed_ratio * m.width_decades]
    if unexplained:
        # the width an ideal R‖C at the same τ would get under the same basis and λ
        f = data_drt.frequency
        w = 2 * np.pi * f
        # one spectrum per call: the same compiled solve as the data's and the model's
        reference = [solve((f, data_drt.r_inf_ohm + p.r_ohm / (1 + 1j * w * p.tau_s)), lam=data_drt.lam, **options) for p in unexplained]
        for p, ref in zip(unexplained, reference):
            near = [q for q in ref.peaks if abs(math.log10(q.tau_s / p.tau_s)) < tolerance_decades]
            if near and p.width_decades > distributed_ratio * near[0].width_decades:
                distributed.append(p)
    distributed.sort(key=lambda p: p.tau_s)
    unresolved = tuple(p for p in unexplained if not is_resolved(p))
    text = f"the data's DRT has {len(data_peaks)} peak{'s' if len(data_peaks) != 1 else ''}"
    if data_peaks:
        text += f" (at {', '.join(format_time(p.tau_s, 2) for p in data_peaks)})"
    text += f"; the model explains {len(explained)}"
    if len(unresolved) < len(unexplained):
        text += "; unexplained: " + ", ".join(f"{format_time(p.tau_s, 2)} (R ≈ {format_quantity(p.r_ohm, 'Ω')})" for p in unexplained if is_resolved(p))
    if unresolved:
        text += (
            "; not told from zero by the DRT's uncertainty (a ripple, not a missing relaxation): "
            + ", ".join(f"{format_time(p.tau_s, 2)} (R ≈ {format_uncertain(p.r_ohm, p.r_ohm_sd, 'Ω')})" for p in unresolved)
        )
    if distributed:
        text += "; distributed (CPE-like): " + ", ".join(format_time(p.tau_s, 2) for p in distributed)
    return PeakEvidence(
        data_peaks=data_peaks, model_peaks=model_peaks, explained=tuple(explained), unexplained=tuple(unexplained),
        nearest_model_tau=nearest, distributed=tuple(distributed), text=text, unresolved=unresolved,
    )
