"""Diagnosis of a fit: where the model fails, which physical effect is missing, and the verdict
(docs/diagnosis.md). `diagnose` runs these steps:

1. Noise model σ_k (relative, per frequency and component; `impedax.fitting.diagnosis.noise`):
   the data's ``sigma`` (a sigma column or the trial scatter, `noise.sigma_origin`) when present, else a local estimate from the
   Kramers–Kronig residuals (`kk_test`), plus a model-discrepancy floor from the KK residuals'
   structured part, floored at `NOISE_FLOOR`.
2. Is it the data? ``data_invalid`` only when the KK misfit is comparable to the model's
   (`KK_COMPARABLE`) over at least `KK_INVALID_FRACTION` of the points; otherwise the run of
   points the KK test flags at an end of the band is masked (`Diagnosis.masked_points`, at most
   `KK_MASK_MAX_FRACTION`: the data's judgement, whatever the model) and the rest is diagnosed;
   flagged points inside the band, or more, stay in and are reported beside the verdict
   (`Diagnosis.kk_flagged_kept`). A
   ``data_invalid`` reason names the run the KK test passes (`kk_valid_run`), the trim that keeps
   it and whether the model misses it clearly (`Diagnosis.misses_valid_band`: refine then
   starts again on it when that leaves out at most `KK_MASK_MAX_FRACTION` of the points).
3. Failing bands (`impedax.fitting.diagnosis.bands`): runs of one sign in Re or Im of the
   relative residual that are structured beyond the noise, each described in words.
4. Candidates: every effect of the catalog (`impedax.fitting.diagnosis.effects`) proposes augmented
   circuits, fitted together warm-started through `fit_candidates` (one compilation) and
   ranked by ΔAIC; a candidate with more parameters outranks a simpler one only when it
   lowers AIC by more than `DELTA_AIC_MIN` (the same rule as the verdict; a series resistance
   that fell to zero and was left out counts as kept, `_ranked_size`).
   With ``drt_evidence`` (default), the data's DRT (`impedax.fitting.drt.drt`) and the baseline's
   are compared first (`unexplained_peaks`): a peak the baseline does not explain gives
   ``extra_relaxation`` its τ and R, a distributed peak gives ``constant_phase`` its α (the
   `BaselineContext.drt_evidence` the proposal functions read); when the DRT cannot be
   computed the diagnosis runs without it and says so in a note.
5. Verdict: ``missing_effect`` when a candidate is significant (ΔAIC < −`DELTA_AIC_MIN`, it
   explains at least `NOISE_FRACTION_MIN` of the noise variance (each point by its own σ_k),
   its parameters are determined
   — relative error ≤ `RELATIVE_ERROR_MAX`, |correlation| ≤ `CORRELATION_MAX` unless both of
   the pair are within `CORRELATED_ERROR_MAX` (and |correlation| ≤ `CORRELATION_SINGULAR`) —
   and its fitted values are plausible for the effect), ``adequate`` otherwise: no effect of
   the catalog explains what is left. Only significant candidates are listed as suggestions.
   When no single effect is significant but the residuals stay structured beyond the noise,
   pairs of effects are tried first (`_effect_pairs`; their ``effect`` is ``"a+b"``).
6. A fit held by the user's constraints (fixed values; free parameters on a bound the user set,
   not the element's own) is refitted once from its values with them released
   (`_constraint_verdict`): when that meets the fit's own rule (`constraints.constraint_explains`),
   the verdict is ``constraint`` and no effect is named missing. Every candidate fit keeps the
   user's fixed values and bounds of the parameters it has (the baseline's refit included; a
   bound on a parameter a candidate replaced does not apply), and a command the report prints
   keeps them too (``--fix``, ``--bound``).
"""

from __future__ import annotations

import dataclasses
import enum
import itertools
import math
from dataclasses import dataclass, field
from typing import Callable, Mapping, NamedTuple, Sequence

import numpy as np
import xarray as xr

from ...progress import reports_progress
from ...arguments import MAX_SOLVER_STEPS, MAX_STARTS, checked_arguments, choice, count, flag, frequency, instance_of, noise_fraction, parameter_bounds, parameter_values, seed as seed_rule
from ...circuits import Circuit, DCPath, DEFAULT_REGISTRY, Element, Parallel, Registry, Series, parse
from ...data import concise_repr, report_text, counted, format_frequency, format_quantity, make_spectrum, unit_text
from ...errors import DataError, FitError, ImpedaxError, ParameterError
from ...io.netcdf import result_dataset
from ..drt import PeakEvidence, drt, is_resolved, r_cpe_tau, unexplained_peaks
from ..kk import CONCLUSIVE_POINTS_MIN, KKResult, frequency_text, kk_test, left_out_options, passing_band, retested_band, zero_impedance_text  # (frequency_text, left_out_options: kept importable from here)
from ..least_squares import BatchFitResult, FitResult, fit
from ..least_squares.result import RESIDUAL_LONG_NAME, is_dominated_note
from ..least_squares.branches import is_idle_note, parallel_branches
from ..least_squares.order import exchangeable_blocks
from ..least_squares.candidates import SolverShape, fit_candidates, solver_shape
from ..least_squares.constraints import binding_constraints, constraint_words, explaining_constraints
from ..least_squares.result import bounds_attr, embedded_fit, fit_from_embedded, user_bounds_text
from ..least_squares.starts import climb_target
from ..parameters import ParameterTable
from ..problem import WEIGHTING_SCALES, WEIGHTINGS, check_argument_order, circuit_parameters, open_spectrum
from ..statistics import KK_RESIDUAL_NOISE, NOISE_OF_SIGMA, information_criteria, non_passive, non_passive_words, top_of_band
from ..arcs import FAR_BEYOND_FACTOR, ArcBeyondBand, arcs_beyond_band
from ..frozen import FrozenResult, freeze_fields
from ...data import format_band
from .bands import FailingBand, failing_bands, format_frequency, RUN_P
from .catalog import BaselineContext, Effect, EffectCatalog, Proposal
from .effects import DEFAULT_EFFECTS, FINITE_WARBURGS, IN_PLACE_OF_WARBURG, added_resistors, cited_where, element_parents
from .noise import GLOBAL_SHARE, LOCAL_SOURCE, LOCAL_WINDOW, NOISE_FLOOR, OUTLIER_MAX_FRACTION, NoiseModel, kk_indices, kk_judged_locally, kk_outliers, noise_model, sigma_origin
from .vanishing import idle_elements, share_words, vanished_parameters, vanished_terms

__all__ = [
    "Diagnosis", "DRTCircuit", "Suggestion", "Verdict", "diagnose", "noise_variance_explained", "ranked_size",
    "DELTA_AIC_MIN", "NOISE_FRACTION_MIN", "NOISE_RATIO_MAX", "NOISE_FLOOR", "KK_INVALID_FRACTION", "KK_INVALID_RMS", "BASELINE_STEPS",
    "KK_COMPARABLE", "MASK_MAX_FRACTION", "KK_MASK_MAX_FRACTION", "OPEN_RESISTANCE_FACTOR", "ARC_ORDERS_MAX", "RELATIVE_ERROR_MAX", "CORRELATION_MAX", "CORRELATED_ERROR_MAX", "CORRELATION_SINGULAR",
]

BASELINE_FIT_PREFIX = "baseline_fit_"
"""The names of the baseline fit's variables, dimensions and attributes in `Diagnosis.to_xarray`
(``baseline_fit_value``, ``baseline_fit_covariance``, ...): apart from the diagnosis' own."""

# --- documented thresholds (docs/diagnosis.md) ---
DELTA_AIC_MIN = 10.0
"""A candidate must lower AIC by more than this (Burnham & Anderson: ΔAIC > 10 ⇒ essentially no
support for the worse model)."""
NOISE_FRACTION_MIN = 0.25
"""... and lower the noise-weighted mean squared residual mean(|r_k|²/σ_k²) by at least this
fraction of its value for pure noise, 2 (so a large N cannot make a negligible improvement
'significant'); each point counts by its own σ_k, as in the ranking."""
NOISE_RATIO_MAX = 1.5
"""rms_rel/(√2 σ) above this with failing bands ⇒ the residuals are not noise."""
NOISE_RATIO_LOW = 0.5
"""rms_rel/(√2 σ) below this for an adequate model ⇒ the σ estimated is over 2× too high (a
model of k parameters fitted to N points at its true noise leaves √(1 − k/2N) ≈ 0.9 of it; the
REAL fixtures' final adequate models leave 0.54–3.4, the noise-free pyimpspec spectrum at most 0.001, a
SYNTHETIC 21-point arc at 0.1 % noise 0.42): the verdict's note says it is lenient
(`low_ratio_words`)."""
BAND_LOWERED_FRACTION = 0.5
"""A suggestion's explanation names a failing band it does not clear when it brings the rms
relative residual there to this fraction of the baseline's or below ("lowers it at ...")."""
SAME_FIT_NOISE = 1.0
"""Two suggestions are listed as one fit when their model spectra differ by less than this × the
noise σ_k at every point and their χ² by less than 2 in AIC's units (`_same_fit`): the data
cannot tell them apart. Two placements of one R ∥ C are often the same function of frequency
(R1 ∥ C1 + R ∥ C and (R1 + R ∥ C) ∥ C1); on CH Instruments' real file they differ by 0.002 σ at
most. So are a suggestion with R0 left out and the same one with R0 kept at its bound 0 (their
AIC differs by 2, the one parameter; on Gamry's real file they took two of the five places)."""
KK_COMPARABLE = 0.5
"""A point's misfit is the data's own when the KK test flags it and its KK residual |Δ_kk| is at
least this fraction of the model's |r| there."""
KK_INVALID_FRACTION = 0.25
"""``data_invalid`` when the KK misfit is comparable to the model's (`KK_COMPARABLE`) at at
least this fraction of the points (a quarter of the band: a drift or a step change spoils that
much of a sweep; a few erratic points do not)."""
KK_INVALID_RMS = 0.02
"""Not used by the rule since the data problems are located point by point (a public name)."""
MASK_MAX_FRACTION = 0.5
"""The points with Re Z < 0 are left out (`non_passive_points`) when they are at most this
fraction of the points; more, and the diagnosis keeps them. (The share of KK-flagged points left out is
`KK_MASK_MAX_FRACTION`.)"""
KK_MASK_MAX_FRACTION = 0.25
"""The points the KK test flags in a run that reaches an end of the band (with `END_ISLAND_MAX`)
are left out of every fit when they are at most this fraction of the points; more, or flagged
points inside the band, are kept and reported as the data's problem beside the verdict
(`Diagnosis.kk_flagged_kept`). A quarter is the share `KK_INVALID_FRACTION` calls the data
invalid: a diagnosis leaves out less than what would make it call the data invalid. Measured
(2026-12-02): on Gamry's REAL example file the KK test flags 52 of 72 points (15.9 mHz–2.26 kHz,
72 %), where Z-HIT flags 15.9–449 mHz and the test passes at 0.654 % rms above 0.5 Hz: the
flags spread from the drifting low end through the chain's fit; AutoEIS's REAL test_data.txt
34 % (23 of 67, 1 mHz–0.6 Hz at 0.4–1.2 %), whose model, refined without them, missed them by
32 %; a SYNTHETIC drifting low end of 41 points, 15 and 16 of them (37 % and 39 %,
`tests/test_diagnose_mask_ends.py`), the same situation.
A left-out set of the flagged points whose KK misfit is at least `KK_COMPARABLE` × the model's
there would follow the model: on Gamry's file 14 points from R0 + R1 ∥ CPE1 + W1, none from
R0 + R1 ∥ CPE1."""
MIN_KEPT_POINTS = 8
"""... and when at least this many points (and 3 per free parameter) are left to fit."""
END_ISLAND_MAX = 2
"""Kept points at an end of the band, at most this many, beyond a masked run of more points than
them are masked too (`end_islands_masked`). Each point gives two numbers (Z', Z''); the circuit's
element that acts only beyond the run (its lowest- or highest-frequency branch: a CPE's Q and α, an
R and a C) has at least two parameters of its own, so one or two points are matched exactly and
test nothing, while three (six numbers) over-determine such a branch. And they carry the drift of
the run next to them: the KK test's local judgement (`kk_judged_locally`) cleared them with a noise
scale whose window reaches into the run (AutoEIS's test_data.txt: 1 mHz and 1.34 mHz kept below 21
masked points up to 585 mHz, fitted to 0.01 % while the model missed the masked band by 2.8 %)."""
RELATIVE_ERROR_MAX = 1.0
"""A parameter is undetermined when its standard error exceeds this × |value| (or is not finite) ..."""
CORRELATION_MAX = 0.99
"""... or its |correlation| with another free parameter exceeds this (a near-singular Jacobian),
unless both of the pair are determined to `CORRELATED_ERROR_MAX` on their own ..."""
CORRELATED_ERROR_MAX = 0.1
"""A correlated pair whose standard errors are both within this × |value| is determined: the
marginal standard error already includes what the correlation costs (two arcs of nearby time
constants trade resistance, R1 and R3 at r = −0.993, yet each is known to 5 %) ..."""
CORRELATION_SINGULAR = 0.999
"""... unless their |correlation| exceeds this: the data then fix one combination of the two
(the error ellipse's axes differ more than 44-fold) and a small error of each is the
linearisation's, not the data's (a series R trading with an added arc's R at r = −0.9992 took
41 Ω where the spectrum has none)."""
LEADER_STARTS = (32, 80)
"""Starts of the further fits of each effect's best candidate while it stays poor (`_poor_leaders`):
a ladder like `impedax.fit`'s (its default climbs to 80 starts), each rung with new draws."""
BRANCH_NEGLIGIBLE = 0.1
"""In a block R ∥ C or R ∥ CPE, a branch whose admittance stays below this fraction of the
other's over the whole band carries no current the data resolve (`_negligible_branch_dropped`)."""
BASELINE_CHECK_STARTS = 32
"""Random starts of the baseline's refit before a missing effect is named (`_baseline_checked`)."""
BASELINE_STEPS = 300
"""Levenberg–Marquardt step limit of the baseline's cold starts (warm candidates: ``max_steps``)."""
BASELINE_COPIES = ((4, 16), (8, 24), (None, 32))
"""(at most K parameters, copies): the baseline is fitted as this many copies of the circuit,
each with its own ``n_starts`` random draws and damped both ways (`_fit_baseline`). The count
follows the circuit's parameter count alone, so the baseline fit is the same whatever effects
the catalog holds (a user's own effect, a subset given as ``effects``) and whatever solver
shape is passed in."""
CANDIDATE_STEPS = 100
"""Default step limit of the candidate fits (``max_steps``)."""
PAIR_SEEDS = 3
"""When no single effect is significant but the residuals stay structured beyond the noise, the
candidates (at most this many, best ΔAIC first) that lower AIC by more than `DELTA_AIC_MIN` yet
leave parameters undetermined are each given every effect of the catalog on top
(`_effect_pairs`)."""
INDUCTIVE_TOP_SIGMA = 3.0
INDUCTIVE_TOP_POINTS = 2
"""The data's top is inductive when at least this many points, counted down from the highest
frequency, have Z'' > `INDUCTIVE_TOP_SIGMA` σ_k |Z| and above the model's Z'' by as much: a sign
no circuit of R, C, CPE and Warburgs makes (`_inductive_top`, `_lead_behind`)."""


class Verdict(enum.StrEnum):
    """The outcome of a diagnosis; the values are the strings of the JSON and the reports."""

    ADEQUATE = "adequate"
    MISSING_EFFECT = "missing_effect"
    DATA_INVALID = "data_invalid"
    CONSTRAINT = "constraint"  # the user's fixed value or bound, not the model, explains the misfit (`_constraint_verdict`)


@dataclass(frozen=True, eq=False)
class Suggestion(FrozenResult):
    """A candidate circuit (one effect at one placement) and its fit."""

    __repr__ = concise_repr  # (the generated one printed every array)

    effect: str
    added: str
    where: str
    fit: FitResult
    delta_aic: float
    delta_bic: float
    significant: bool
    explanation: str
    fixed_bands: tuple[tuple[float, float], ...] = ()
    undetermined: tuple[str, ...] = ()  # parameters the data do not determine (new to the baseline)
    warning: str | None = None  # why the candidate is not proposed (undetermined, implausible, not converged)
    removed: tuple[str, ...] = ()  # baseline elements left out (a series resistance that fell to zero)
    vanished: tuple[str, ...] = ()  # those of them that fell to zero where the candidate kept them (`Proposal.vanished`)

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def model(self) -> str:
        return self.fit.model

    @property
    def rms_rel(self) -> float:
        return self.fit.rms_rel

    @property
    def aic(self) -> float:
        return self.fit.aic

    @property
    def beyond_band(self) -> tuple[ArcBeyondBand, ...]:
        """The arcs this ``extra_relaxation`` candidate adds that relax outside the band its fit
        saw (`arcs.arcs_beyond_band`): the data see one flank of each, not the arc."""
        circuit, registry = self.fit.circuit, self.fit.registry
        return arcs_beyond_band(circuit, self.fit.values, registry, self.fit.frequency, added_resistors(self.effect, self.added, circuit, registry))

    def as_json(self, same_fit: Sequence[Suggestion] = ()) -> dict:
        """The JSON of a suggestion; ``same_fit``: the other suggestions that are the same fit
        within the noise (`Diagnosis.same_fits`), given by their models as refine's steps[].same_fit."""
        return {
            "effect": self.effect, "model": self.model, "rms_rel": self.rms_rel, "aic": self.aic, "delta_aic": self.delta_aic,
            "delta_bic": self.delta_bic, "explanation": self.explanation, "added": self.added, "where": self.where,
            "significant": self.significant, "bic": self.fit.bic, "chi2_red": self.fit.chi2_red,
            "fixed_bands": [list(b) for b in self.fixed_bands], "undetermined": list(self.undetermined), "warning": self.warning,
            "values": {k: float(v) for k, v in self.fit.values.items()}, "removed": list(self.removed),
            "vanished": list(self.vanished), "same_fit": [t.model for t in same_fit],
            "units": {k: spec.unit for k, spec in self.fit.circuit.parameter_specs(self.fit.registry).items()},  # (of "values", as fit --json's params give them)
            "beyond_band": [a.as_json() for a in self.beyond_band],  # (added arcs that relax outside the band)
        }


@dataclass(frozen=True, eq=False)
class DRTCircuit:
    """The data's DRT's starting circuit fitted on a diagnosis' points (`_drt_circuit_fit`):
    ``fit``, and ``compared``, the best suggestion fitted to convergence from its values;
    ``delta_aic`` and ``compared_delta_aic`` against the baseline over the noise-weighted
    residuals, as the suggestions' ΔAIC (`noise_weighted_criteria`); ``better_fit``: better by
    more than `DELTA_AIC_MIN` and a `NOISE_FRACTION_MIN` share of the noise variance (else it is
    as good by AIC with fewer parameters)."""

    __repr__ = concise_repr

    fit: FitResult
    compared: FitResult
    delta_aic: float
    compared_delta_aic: float
    better_fit: bool

    def as_json(self) -> dict:
        f, c = self.fit, self.compared
        return {"model": f.model, "rms_rel": f.rms_rel, "aic": f.aic, "delta_aic": self.delta_aic, "n_params": f.n_params, "values": {k: float(v) for k, v in f.values.items()},
                "better_fit": self.better_fit, "compared_model": c.model, "compared_rms_rel": c.rms_rel, "compared_delta_aic": self.compared_delta_aic, "compared_n_params": c.n_params}


@dataclass(frozen=True, eq=False)
class Diagnosis(FrozenResult):
    """Outcome of `diagnose`: the baseline fit, KK test, noise, failing bands, ranked
    candidates (``suggestions``: the significant ones, best first; ``candidates``: all) and the
    `Verdict` with its ``reason``; ``drt``: the data's DRT peaks against the baseline's
    (`PeakEvidence`), or None when the DRT was off or could not be computed; ``drt_circuit``:
    the circuit that DRT reads, fitted, when it is better than the best suggestion
    (`DRTCircuit`), else None."""

    __repr__ = concise_repr  # (the generated one printed every array)
    __str__ = report_text  # (print(result): its report)

    baseline: FitResult
    kk: KKResult | None
    noise: np.ndarray
    noise_source: str
    failing_bands: tuple[FailingBand, ...]
    candidates: tuple[Suggestion, ...]
    verdict: Verdict
    reason: str
    notes: tuple[str, ...] = ()
    thresholds: Mapping[str, float] = field(default_factory=dict)
    drt: PeakEvidence | None = None
    measurement_noise: np.ndarray | None = None  # σ_meas per point (without the discrepancy floor)
    discrepancy: float = 0.0  # the model-discrepancy floor δ (relative, per component)
    masked_points: tuple[float, ...] = ()  # frequencies [Hz] left out as the data's problem: KK-flagged, or Re Z < 0
    kk_of_kept: KKResult | None = None  # the KK test of the points kept, when a few erratic points were masked
    kk_as_tested: KKResult | None = None  # the KK test before its local judgement (``kk`` is after it); the discrepancy floor δ takes its flags (refine passes it on, or kk_of_kept when points were masked)
    solver_shape: SolverShape | None = None  # the compiled candidate solver's shape (refine passes it on: one compilation for all steps)
    masked_impedance: tuple[complex, ...] = ()  # the measured Z [Ω] at each of ``masked_points`` (drawn, marked, in the figure)
    sign_hint: str | None = None  # the KK test's (`io.sign_check.sign_hint`): Z'' (or Z) may be stored with the opposite sign
    kk_valid_band: tuple[float, float] | None = None  # data_invalid: the band [Hz, lowest and highest measured] the KK test passes, which --fmin/--fmax keep: impedax kk's (`kk.retested_band`) when it names one, else the run it leaves unflagged (`kk_valid_run`)
    misses_valid_band: bool = False  # data_invalid: the model misses ``kk_valid_band`` clearly (an effect is missing there)
    not_passive_points: tuple[float, ...] = ()  # those of ``masked_points`` [Hz] left out for Re Z < 0 beyond the noise (the rest: the KK test's)
    kk_flagged_kept: str | None = None  # why points the KK test flags were kept in every fit (inside the band, more than `KK_MASK_MAX_FRACTION`, or mask=False): the data's problem, reported beside the verdict
    effects_left_out: tuple[str, ...] = ()  # the ids of `DEFAULT_EFFECTS` the candidates did not try (``effects=``, --effects, gave a subset)
    drt_circuit: "DRTCircuit | None" = None  # the data's DRT's starting circuit, fitted, when it is better than the best suggestion (`_drt_circuit_fit`)
    kk_run_band: tuple[float, float] | None = None  # data_invalid: the band refine starts again on when the model misses it clearly (`kk_valid_run`, or tested again keeping 3 points per free parameter); ``kk_valid_band`` unless impedax kk names another
    misses_run_band: bool = False  # data_invalid: the model misses ``kk_run_band`` clearly

    @property
    def source(self) -> str | None:
        """Where the data came from (the baseline fit's `FitResult.source`): what `impedax.write_result` records."""
        return self.baseline.source

    def __post_init__(self):
        object.__setattr__(self, "verdict", Verdict(self.verdict))
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def suggestions(self) -> tuple[Suggestion, ...]:
        return tuple(s for s in self.candidates if s.significant) if self.verdict == Verdict.MISSING_EFFECT else ()

    @property
    def best(self) -> Suggestion | None:
        return self.suggestions[0] if self.suggestions else None

    def same_fits(self, suggestion: Suggestion) -> tuple[Suggestion, ...]:
        """The other significant suggestions that are the same fit as ``suggestion`` within the
        noise (`_same_fit`: the data cannot tell them apart), in their order."""
        return tuple(t for t in self.suggestions if t is not suggestion and _same_fit(suggestion.fit, t.fit, self.noise))

    @property
    def noise_level(self) -> float:
        """Median relative noise σ per component."""
        return float(np.median(self.noise))

    @property
    def noise_ratio(self) -> float:
        """rms_rel / (√2 σ): ≈ 1 when the residuals are noise."""
        return _noise_ratio(self.baseline, self.noise)

    @property
    def beyond_catalog(self) -> bool:
        """An ``adequate`` verdict whose residuals are still structured and above
        `NOISE_RATIO_MAX` × the noise: no effect of the catalog (nor a pair) explains what is
        left, but the model does not describe the data to their noise either."""
        return self.verdict == Verdict.ADEQUATE and _beyond_single_effects(self.failing_bands, self.noise_ratio)

    @property
    def warnings(self) -> list[str]:
        """What to heed before trusting the verdict (JSON ``warnings``, the key fit, compare and
        sample give): every one of ``notes`` (masked points, refits, KK flags,
        what the data do not determine) but the one saying the user's bounds were kept, the
        sign hint (``sign_hint``), and an adequate verdict `beyond_catalog` (`beyond_catalog_words`:
        else the JSON's bare "adequate" at 16× the noise has no warning)."""
        beyond = [beyond_catalog_words(self.noise_ratio, self.effects_left_out)] if self.beyond_catalog else []
        return [n for n in self.notes if not n.startswith(BOUNDS_KEPT_LEAD)] + ([self.sign_hint] if self.sign_hint else []) + beyond

    @property
    def nothing_missing(self) -> bool:
        """An ``adequate`` verdict with the residuals within `NOISE_RATIO_MAX` × the noise: the
        model follows the data to their noise and no effect improves it, which the report says
        in plain words ("nothing is missing: …"), beside the verdict's thresholds."""
        return self.verdict == Verdict.ADEQUATE and not self.beyond_catalog and self.noise_ratio <= NOISE_RATIO_MAX

    @property
    def verdict_heading(self) -> str:
        """The verdict as the report heads it: ``ADEQUATE WITHIN THE CATALOG`` for an adequate
        verdict `beyond_catalog` (a bare "adequate" read as "fits the data" at 10× the noise),
        ``ADEQUATE WITHIN THE EFFECTS TRIED`` when ``effects=`` left some of the catalog out."""
        return self.verdict.upper() + ((" WITHIN THE EFFECTS TRIED" if self.effects_left_out else " WITHIN THE CATALOG") if self.beyond_catalog else "")

    @property
    def verdict_band(self) -> tuple[float, float]:
        """The lowest and highest frequency [Hz] of the points the verdict was judged on (the
        baseline fit's, without ``masked_points``)."""
        f = self.baseline.frequency
        return float(np.min(f)), float(np.max(f))

    @property
    def verdict_scope(self) -> str:
        """`verdict_scope_words` of this diagnosis: the band and the number of points its verdict
        was judged on, when points were left out; empty when none were."""
        return verdict_scope_words(self.baseline.frequency, self.masked_points, self.not_passive_points)

    def summary(self) -> dict:
        """The JSON of ``impedax diagnose --json`` (keys fixed by the issue; extra keys added)."""
        b = self.baseline
        kk = self.kk
        return {
            "model": b.model,
            "baseline": {"rms_rel": b.rms_rel, "chi2_red": b.chi2_red, "aic": b.aic, "bic": b.bic, "n_points": b.n_points, "n_params": b.n_params,
                         "params": b.summary()["params"], "at_bound": list(b.at_bound),
                         "user_bounds": bounds_attr(b.bounds),  # (the bounds=, --bound, as fit --json's user_bounds)
                         "converged": bool(b.converged),  # (as fit --json's)
                         "weighting": b.weighting},  # (what chi2_red and aic are against, as fit --json's weighting)
            "kk": {
                "valid": bool(kk.valid) if kk is not None else None,
                "rms_rel": float(kk.rms_rel) if kk is not None else None,
                "bad_bands": [[float(lo), float(hi)] for lo, hi in kk.bad_bands] if kk is not None else [],
                # per band, the lowest and highest flagged measured frequency [Hz]: the
                # range the text names, as impedax kk --json's (``bad_bands`` keep the edges halfway to the neighbours)
                "measured_bands_hz": [[float(lo), float(hi)] for lo, hi in kk.measured_bands] if kk is not None else [],
                "noise_estimate": float(kk.noise_estimate) if kk is not None else None,
                "conclusive": bool(kk.conclusive) if kk is not None else None,
                "sign_hint": kk.sign_hint if kk is not None else None,
            },
            "noise": {
                "level": self.noise_level, "source": self.noise_source, "ratio": self.noise_ratio, "discrepancy_floor": self.discrepancy,
                "frequency": [float(f) for f in self.baseline.frequency], "per_frequency": [float(x) for x in self.noise],
                "measurement": [float(x) for x in self.measurement_noise] if self.measurement_noise is not None else None,
            },
            "masked_points": [float(f) for f in self.masked_points],
            "failing_bands": [band.as_json() for band in self.failing_bands],
            "verdict": self.verdict,
            "reason": self.reason,
            "beyond_catalog": self.beyond_catalog,
            "nothing_missing": self.nothing_missing,  # (the report's "nothing is missing: …" line)
            "suggestions": [s.as_json(self.same_fits(s)) for s in self.suggestions],
            "candidates": [
                {"effect": s.effect, "model": s.model, "rms_rel": s.rms_rel, "aic": s.aic, "delta_aic": s.delta_aic, "delta_bic": s.delta_bic, "significant": s.significant, "undetermined": list(s.undetermined), "warning": s.warning}
                for s in self.candidates
            ],
            # what a suggestion's or candidate's delta_aic and delta_bic weigh the residuals by: each point's noise
            # (the "noise" entry's per_frequency), not the fit's own weighting that its "aic" uses, so they are no differences of "aic"
            "delta_aic_weighting": "noise",
            "thresholds": dict(self.thresholds),
            "notes": list(self.notes),
            "warnings": self.warnings,
            "drt_peaks": self._drt_peaks_json(),
            "drt_summary": self.drt.text if self.drt is not None else None,
            "sign_hint": self.sign_hint,
            "kk_valid_band": list(self.kk_valid_band) if self.kk_valid_band is not None else None,
            "misses_valid_band": self.misses_valid_band,
            "kk_flagged_kept": self.kk_flagged_kept,  # why KK-flagged points stayed in every fit, or null
            # what the verdict was judged on: the band [Hz] of the points kept, their number and how many were left out
            "verdict_band_hz": list(self.verdict_band), "n_points_judged": int(self.baseline.n_points), "n_points_left_out": len(self.masked_points),
            "effects_left_out": list(self.effects_left_out),  # the catalog's effects effects= (--effects) left out, not tried
            "drt_circuit": self._drt_circuit_json(),  # the DRT's circuit when it fits better than the best suggestion, or null
        }

    def _drt_circuit_json(self) -> dict | None:
        """``drt_circuit`` of the JSON (`DRTCircuit.as_json`), or None."""
        return self.drt_circuit.as_json() if self.drt_circuit is not None else None

    def _drt_circuit_lines(self, fit_command: str) -> list[str]:
        """The report's lines on ``drt_circuit`` (`_drt_circuit_fit`), under the suggestions."""
        d = self.drt_circuit
        if d is None or not self.suggestions:
            return []
        f, best = d.fit, d.compared
        how = "fits better than 1." if d.better_fit else "is as good as 1. by AIC with fewer parameters"
        refitted = " (1. fitted to convergence from its values)" if abs(d.compared_delta_aic - self.suggestions[0].delta_aic) > 0.05 else ""
        return [
            f"  the data's DRT reads another circuit (impedax drt), {f.model}, which {how}: rms_rel {f.rms_rel * 100:.3g} % against {best.rms_rel * 100:.3g} %, "
            f"ΔAIC {d.delta_aic:+.1f} against {d.compared_delta_aic:+.1f}{refitted}, {f.n_params} parameters against {best.n_params}; it is no one change to {self.baseline.model}, so no suggestion above",
            f"  to apply it: {fit_command} --model '{f.model}' {_start_words(f)}",
        ]

    def _drt_peaks_json(self) -> list[dict] | None:
        """The data's DRT peaks, each with whether the baseline explains it (None without a DRT)."""
        if self.drt is None:
            return None
        explained = {id(p) for p, _ in self.drt.explained}
        distributed = {id(p) for p in self.drt.distributed}
        return [
            {"tau_s": p.tau_s, "r_ohm": p.r_ohm, "width_decades": p.width_decades, "explained": id(p) in explained, "distributed": id(p) in distributed}
            for p in self.drt.data_peaks
        ]

    def _chi2_red_basis(self) -> str:
        """What the baseline's chi2_red is measured against, when that is not the noise the
        report's next lines judge by: `` (modulus weighting: residuals relative to |Z|, not to
        the noise; against the noise σ given below, chi2_red ≈ 216, as the residuals are 14.7×
        that noise)``. Without it "chi2_red 0.0218" beside "the residuals are 14.7× the
        noise" reads as a contradiction; a fit weighted by the data's sigma (χ² against it) needs no
        note. ("against the noise σ below ≈ 216" would read as "σ is below 216".) Under sigma weighting it names the weighting, and sets the figure
        against the noise below beside it where they differ by over 25 % (that noise adds a
        model-discrepancy floor to the sigma: REAL exampleData.csv with a sigma column, not
        "chi2_red 9.56" bare beside "the residuals are 1.81× the noise")."""
        ratio = self.noise_ratio
        if self.baseline.weighting == "sigma":
            chi2_red = self.baseline.chi2_red
            differs = not 0.8 < ratio**2 / chi2_red < 1.25 if chi2_red > 0 else False
            return " (sigma weighting: residuals relative to the data's sigma" + (f"; against the noise σ given below, chi2_red ≈ {ratio**2:.3g}, as the residuals are {ratio:.3g}× that noise)" if differs else ")")
        scale = WEIGHTING_SCALES.get(self.baseline.weighting, f"its {self.baseline.weighting} weights")
        return f" ({self.baseline.weighting} weighting: residuals relative to {scale}, not to the noise; against the noise σ given below, chi2_red ≈ {ratio**2:.3g}, as the residuals are {ratio:.3g}× that noise)"

    def report(self, *, fit_command: str | None = None) -> str:
        """The diagnosis as a short story (the default text of ``impedax diagnose``).
        ``fit_command``: how the command that applies the best suggestion starts (``impedax
        diagnose`` gives its file, --select, --weighting and the --fmin, --fmax and --exclude
        that leave out the masked points, `left_out_options`); default ``impedax fit DATA``
        with those options. It ends with --model and the suggestion's values."""
        b = self.baseline
        left_out = left_out_options(b.frequency, self.masked_points)
        if fit_command is None:
            fit_command = " ".join(["impedax fit DATA", left_out_words(left_out)]).strip()
        lines = [f"model {b.model}: rms_rel {b.rms_rel * 100:.3g} %, chi2_red {b.chi2_red:.3g}{self._chi2_red_basis()}, AIC {b.aic:.1f} ({b.n_points} points, {counted(b.n_params, 'free parameter')})"]
        if self.kk is not None:
            # (the band once: the note on the points kept names it where it names the same range,
            # "flags 51 of 73 points (100 mHz–684 Hz, …)" or "flags 4 points inside the band (5.34 Hz, …)")
            named = self.kk_flagged_kept and f"({self.kk.measured_bands_text()})" in self.kk_flagged_kept
            kk_text = "the data are Kramers–Kronig consistent" if self.kk.valid else "the data are NOT Kramers–Kronig consistent" + ("" if named else f" in {self.kk.measured_bands_text()}")
            if not self.kk.conclusive:
                kk_text = f"{b.n_points} frequencies are too few for the Kramers–Kronig test, and for the noise it estimates"
            kept = f"; without the {counted(len(self.masked_points), 'masked point')} they are (KK rms_rel {self.kk_of_kept.rms_rel * 100:.3g} %)" if self.kk_of_kept is not None else ""
            lines.append(f"data: {kk_text} (KK rms_rel {self.kk.rms_rel * 100:.3g} %){kept}" + (f"; {self.kk_flagged_kept}." if self.kk_flagged_kept else "."))
        tested = self.kk_of_kept if self.kk_of_kept is not None else self.kk
        lines.append(noise_line(self.noise, self.noise_source, self.noise_ratio, tested.noise_estimate if tested is not None else None, masked=self.kk_of_kept is not None))
        if self.masked_points:
            lines.append(f"masked: {counted(len(self.masked_points), 'point')} left out of every fit as the data's own problem ({', '.join(format_frequency(f) for f in self.masked_points[:6])}{', …' if len(self.masked_points) > 6 else ''}; the notes say why).")
        if self.failing_bands:
            # (adequate: structure no effect of the catalog explains significantly, not a failing model)
            lines.append("where the model fails:" if self.verdict != Verdict.ADEQUATE else "where the residuals are structured (below what an effect of the catalog explains significantly):")
            for band in self.failing_bands:
                tag = " [data problem: the KK test flags the data behind this misfit]" if band.data_problem else ""
                lines.append(f"  {format_frequency(band.f_min)} – {format_frequency(band.f_max)}: {band.pattern}{tag}")
        else:
            lines.append("no band of the residuals is structured beyond the noise on its own" + (" (the verdict below weighs all points together)." if self.verdict == Verdict.MISSING_EFFECT else "."))
        if self.drt is not None:
            lines.append(f"DRT: {self.drt.text}.")
        lines.append(f"verdict: {self.verdict_heading}{self.verdict_scope} — {self.reason}")
        if self.suggestions:
            lines.append("what is missing (best first; ΔAIC and ΔBIC here weigh each point by its noise, so they differ from the fits' own AIC that impedax fit and compare print):")
            shown = _folded(self.suggestions, self.noise)[:5]
            for i, (s, same) in enumerate(shown, 1):
                lines.append(f"  {i}. [{s.effect}] {s.explanation}")
                lines.append(f"     model {s.model}   rms_rel {s.rms_rel * 100:.3g} %   ΔAIC {s.delta_aic:+.1f}   ΔBIC {s.delta_bic:+.1f}")
                lines += [f"     ranked before {j}. (ΔAIC {t.delta_aic:+.1f}): {_ranked_before(s, t)}" for j, (t, _) in enumerate(shown, 1) if j > i and t.delta_aic < s.delta_aic]
                for t in same:
                    lines.append(f"     the same fit within the noise (the data cannot tell them apart): {t.model} [{t.effect}]   ΔAIC {t.delta_aic:+.1f}")
            best = self.suggestions[0].fit
            starts = _start_words(best) + _fixed_words(best) + bound_words(best)
            lines.append(f"  to apply 1. from its fitted values (a fit from scratch may stop in another minimum): {fit_command} --model '{best.model}' {starts}")
            lines += _without_vanished_lines(best, fit_command)
            lines += _at_bound_lines(best)
            lines += self._drt_circuit_lines(fit_command)
            if self.masked_points:  # (impedax fit takes every point the file holds unless told)
                lines.append(
                    f"     note: this diagnosis left out {counted(len(self.masked_points), 'point')} ({', '.join(format_frequency(f) for f in self.masked_points[:6])}{', …' if len(self.masked_points) > 6 else ''}); "
                    f"the command leaves them out too ({left_out_words(left_out)}); a fit of every point reaches other values (in Python: ix.fit(model, data, init=diagnosis.best.fit) on the data without them)"
                )
        elif self.candidates and self.verdict == Verdict.ADEQUATE:
            top = self.candidates[0]
            # (a best candidate that raises AIC is not "best" at anything the line is about: said so)
            best_words = f"best: {top.effect}, ΔAIC {top.delta_aic:+.1f}" if top.delta_aic < 0 else f"none lowers AIC; the closest, {top.effect}, raises it by {top.delta_aic:.1f}"
            lines.append(f"no effect improves the fit significantly ({best_words}, rms_rel {top.rms_rel * 100:.3g} %{self._why_not_significant(top)}).")
        if self.nothing_missing:
            tried = "no effect tried" if self.effects_left_out else "no effect of the catalog"
            kept = f" on the {b.n_points} points kept" if self.masked_points else ""  # (the verdict line names them)
            lines.append(f"nothing is missing: {b.model} follows the data to their noise{kept} (the residuals are {self.noise_ratio:.3g}× the noise), and {tried} improves it "
                         f"significantly; its parameters with their errors: {fit_command} --model '{b.model}'" + _fixed_words(b) + bound_words(b))
        rejected = [s for s in self.candidates if s.warning and s.delta_aic < -DELTA_AIC_MIN][:3]
        said_rule = False
        for s in rejected:
            warning = s.warning
            if UNDETERMINED_RULE in warning:  # (the rule once, on the first line that needs it: three times on REAL BioLogic)
                if said_rule:
                    warning = warning.replace(f" ({UNDETERMINED_RULE})", "").replace(f"({UNDETERMINED_RULE}; ", "(")
                said_rule = True
            lines.append(f"  not proposed: {s.model} (rms_rel {s.rms_rel * 100:.3g} %): {warning}")
        # (why KK-flagged points were kept is said on the data line; its note, for the JSON's
        # ``notes``, is not said again as the last line: 600 characters twice on REAL Gamry)
        said = {self.kk_flagged_kept, f"{self.kk_flagged_kept}: diagnosed with every point"} if self.kk is not None and self.kk_flagged_kept else set()
        for n in self.notes:
            if n not in said:
                lines.append(f"note: {n}")
        return "\n".join(lines)

    def _why_not_significant(self, candidate: Suggestion) -> str:
        """Why ``candidate``, whose ΔAIC is beyond `DELTA_AIC_MIN`, is not significant when the
        second rule (`NOISE_FRACTION_MIN`) holds it back:
        ``"; it explains 12 % of the noise variance, under the 25 % …"``; empty otherwise."""
        if candidate.delta_aic >= -DELTA_AIC_MIN:
            return ""
        explained = noise_variance_explained(self.baseline, candidate.fit, self)
        if explained < NOISE_FRACTION_MIN:
            return (f"; past ΔAIC {-DELTA_AIC_MIN:g}, but it explains {explained * 100:.0f} % of the noise variance, under the {NOISE_FRACTION_MIN * 100:.0f} % "
                    f"a significant effect must explain (NOISE_FRACTION_MIN: the fall of mean(|r_k|²/σ_k²) over 2, σ_k the noise above; "
                    f"ΔAIC is taken over the residuals divided by σ_k too, so it differs from the fits' own AICs that impedax compare gives)")
        return ""  # (held back by its parameters: the "not proposed" line below says why)

    def plot(self, *, title: str | None = None, figsize: tuple[float, float] | None = None):
        """Nyquist, Bode and residual panels of the baseline with the failing bands shaded and
        the best suggestion overlaid (matplotlib Figure; `impedax.plotting.diagnosis`);
        ``figsize`` (width, height) [in] in place of the size that follows the spectrum's shape."""
        from ...plotting.diagnosis import plot_diagnosis

        return plot_diagnosis(self, title=title, figsize=figsize)

    def to_xarray(self) -> xr.Dataset:
        """Baseline spectra, residuals (``residual_rel`` = (Z_model − Z)/|Z|, model minus data,
        as a fit's), noise and band mask over frequency; candidates over
        ``candidate``; verdict and thresholds in attrs; the baseline fit in full (values,
        stderr, covariance, ...: `FitResult.to_xarray` with its names prefixed
        ``baseline_fit_``, read back by `Diagnosis.baseline_of`); the masked points in
        ``masked_points_hz``; ``impedax_kind`` "diagnosis"."""
        b = self.baseline
        mask = np.zeros(b.frequency.size, bool)
        for band in self.failing_bands:
            mask |= (b.frequency >= band.f_min) & (b.frequency <= band.f_max)
        ds = xr.Dataset(
            {
                "Z": ("frequency", b.z_data, {"units": "ohm"}),
                "Z_model": ("frequency", b.z_model, {"units": "ohm"}),
                "residual_rel": ("frequency", b.residuals, {"units": "1", "long_name": RESIDUAL_LONG_NAME}),
                "noise_rel": ("frequency", self.noise, {"long_name": "relative noise per component (measurement and discrepancy floor)"}),
                "failing": ("frequency", mask),
                "candidate_model": ("candidate", [s.model for s in self.candidates]),
                "candidate_effect": ("candidate", [s.effect for s in self.candidates]),
                "rms_rel": ("candidate", [s.rms_rel for s in self.candidates]),
                "delta_aic": ("candidate", [s.delta_aic for s in self.candidates]),
                "delta_bic": ("candidate", [s.delta_bic for s in self.candidates]),
                "significant": ("candidate", [s.significant for s in self.candidates]),
                # why a candidate is not proposed: the parameters the data do not
                # determine (";"-joined, as a comparison's ``undetermined``) and the report's words ("" for none)
                "candidate_undetermined": ("candidate", np.array([";".join(s.undetermined) for s in self.candidates], str)),
                "candidate_warning": ("candidate", np.array([s.warning or "" for s in self.candidates], str)),
            },
            coords={"frequency": ("frequency", b.frequency, {"units": "Hz"}), "candidate": np.arange(len(self.candidates))},
            attrs={"model": b.model, "verdict": str(self.verdict), "reason": self.reason, "noise_source": self.noise_source, "baseline_rms_rel": b.rms_rel, "baseline_aic": b.aic, **{f"threshold_{k}": v for k, v in self.thresholds.items()}},
        )
        ds = xr.merge([ds, embedded_fit(b, BASELINE_FIT_PREFIX, b.frequency, b.z_data)], combine_attrs="no_conflicts")
        return result_dataset(ds.assign_attrs(impedax_kind="diagnosis", masked_points_hz=[float(f) for f in self.masked_points],
            masked_impedance_real_ohm=[float(np.real(z)) for z in self.masked_impedance], masked_impedance_imag_ohm=[float(np.imag(z)) for z in self.masked_impedance],
            notes=list(self.notes),
        ).copy(deep=True))

    @staticmethod
    def baseline_of(ds: xr.Dataset, *, registry: Registry | None = None) -> FitResult:
        """The baseline fit stored by `Diagnosis.to_xarray` (as returned or read back with
        `impedax.io.read_netcdf`), as a `FitResult`."""
        return fit_from_embedded(ds, BASELINE_FIT_PREFIX, registry=registry)

    def to_table(self) -> list[dict[str, object]]:
        """The tidy table in clearly named rows: ``section`` "baseline" rows are the baseline
        fit's parameters (`FitResult.to_table`), then one "candidate" row per augmented model
        (best first) with its effect, model, rms_rel, ΔAIC, ΔBIC and significance."""
        rows: list[dict[str, object]] = [{"section": "baseline", **row} for row in self.baseline.to_table()]
        rows += [
            {"section": "candidate", "effect": s.effect, "model": s.model, "rms_rel": s.rms_rel, "delta_aic": s.delta_aic, "delta_bic": s.delta_bic, "significant": s.significant}
            for s in self.candidates
        ]
        return rows

    def _repr_html_(self) -> str:
        from ...plotting.html import result_html

        rows = [{"effect": s.effect, "model": s.model, "rms_rel [%]": f"{s.rms_rel * 100:.3g}", "ΔAIC": s.delta_aic, "significant": s.significant,
                 "undetermined": ", ".join(s.undetermined)} for s in self.candidates[:8]]
        lines = [f"verdict: {self.verdict}{self.verdict_scope} — {self.reason}", f"baseline rms_rel {self.baseline.rms_rel * 100:.3g} %, AIC {self.baseline.aic:.2f}"]
        return result_html(f"diagnosis of {self.baseline.model}", rows, lines=lines)


# --- the steps of a diagnosis ----------------------------------------------------------------


# when the data do not determine a parameter of a candidate (`undetermined_parameters`): its words in a
# candidate's warning, which the report says once
UNDETERMINED_RULE = (f"relative error > {RELATIVE_ERROR_MAX * 100:.0f} %, |correlation| > {CORRELATION_SINGULAR:g}, "
                     f"or > {CORRELATION_MAX:g} with a relative error above {CORRELATED_ERROR_MAX * 100:.0f} %")


def _thresholds() -> dict[str, float]:
    return {
        "delta_aic_min": DELTA_AIC_MIN, "noise_fraction_min": NOISE_FRACTION_MIN, "noise_ratio_max": NOISE_RATIO_MAX, "same_fit_noise": SAME_FIT_NOISE, "run_p": RUN_P, "noise_floor": NOISE_FLOOR,
        "kk_invalid_fraction": KK_INVALID_FRACTION, "kk_comparable": KK_COMPARABLE, "mask_max_fraction": MASK_MAX_FRACTION, "kk_mask_max_fraction": KK_MASK_MAX_FRACTION,
        "relative_error_max": RELATIVE_ERROR_MAX, "correlation_max": CORRELATION_MAX, "correlated_error_max": CORRELATED_ERROR_MAX, "correlation_singular": CORRELATION_SINGULAR,
    }


def _same_fit(a: FitResult, b: FitResult, noise: np.ndarray) -> bool:
    """Do fits ``a`` and ``b`` of the same points give the same spectrum within
    `SAME_FIT_NOISE` × the noise σ_k (relative) at every point, and AIC less its parameters'
    term (n ln(χ²/n), the misfit) within 2?"""
    misfit_a, misfit_b = a.aic - 2 * a.n_params, b.aic - 2 * b.n_params
    if a.frequency.shape != b.frequency.shape or not np.array_equal(a.frequency, b.frequency) or abs(misfit_a - misfit_b) >= 2:
        return False
    return bool(np.all(np.abs(a.z_model - b.z_model) < SAME_FIT_NOISE * noise * np.abs(a.z_data)))


def _folded(suggestions: Sequence[Suggestion], noise: np.ndarray) -> list[tuple[Suggestion, list[Suggestion]]]:
    """The suggestions in their order, each later one that is the same fit as one before it
    (`_same_fit`) folded into that one: [(suggestion, [the same fits]), ...]."""
    out: list[tuple[Suggestion, list[Suggestion]]] = []
    for s in suggestions:
        home = next((same for t, same in out if _same_fit(t.fit, s.fit, noise)), None)
        if home is None:
            out.append((s, []))
        else:
            home.append(s)
    return out


def noise_line(sigma: np.ndarray, source: str, ratio: float, kk_estimate: float | None, *, masked: bool = False) -> str:
    """The report's noise line: σ's median and range over the points (``sigma``, relative per
    component), its ``source`` and the residuals' ``ratio`` to it. A local KK estimate says how
    it differs from the KK test's one estimate for the band (``kk_estimate``, which impedax kk
    prints: of the points kept when ``masked``): the scatter of `LOCAL_WINDOW` frequencies around
    each point, at least `GLOBAL_SHARE` × it; and the points at the `NOISE_FLOOR` minimum are
    counted (else REAL ZPlot's "σ ≈ 0.1 %" beside impedax kk's "noise estimate =
    0.0705 %" reads as a contradiction)."""
    words = source
    if source.startswith(LOCAL_SOURCE) and kk_estimate is not None and math.isfinite(kk_estimate):
        kept = " without the masked points" if masked else ""
        words = source.replace("(per frequency)", f"(per frequency: the scatter of {LOCAL_WINDOW} frequencies around each, at least {GLOBAL_SHARE:g}× "
                                                  f"the KK test's single estimate{kept}, {kk_estimate * 100:.3g} %)", 1)
    at_floor = int(np.sum(np.asarray(sigma) <= NOISE_FLOOR * (1 + 1e-9)))
    if at_floor:
        words += f"; at its {NOISE_FLOOR * 100:.2g} % minimum at {at_floor} of {np.size(sigma)} points"
    return f"noise: σ ≈ {float(np.median(sigma)) * 100:.3g} % per component (median; {format_range(sigma)}; {words}); the residuals are {ratio:.3g}× the noise."


def format_range(sigma: np.ndarray) -> str:
    """``0.3–2.1 %`` (the range of a relative noise per point), or ``uniform`` when it is one value."""
    lo, hi = float(np.min(sigma)), float(np.max(sigma))
    return "uniform" if hi <= lo * 1.05 else f"{lo * 100:.2g}–{hi * 100:.2g} % over the band"


def undetermined_parameters(fit: FitResult) -> frozenset[str]:
    """Free parameters the data do not determine: standard error not finite or above
    `RELATIVE_ERROR_MAX` × |value| (an exponent: × the width of its range, `_error_scales`),
    or |correlation| with another above `CORRELATION_MAX` while that member's standard error
    is above `CORRELATED_ERROR_MAX` × the same, or above `CORRELATION_SINGULAR`.

    A constant-phase coefficient is judged where the data measure it: Q of
    Z = 1/(Q (jω)^α) is the admittance at ω = 1 rad/s, often decades outside the band, so its
    raw error and its correlation with α grow with that distance although the element is well
    determined (`centred_covariance`)."""
    names = fit.free_names
    rel_sd, corr = centred_covariance(fit)
    out = {n for n, e in zip(names, rel_sd) if not (np.isfinite(e) and e <= RELATIVE_ERROR_MAX)}
    # a vanishing term's (`branches.VANISHING_SHARE`): undetermined, or at the natural bound that explains it
    stderr = fit.linearised_stderr  # (at a bound: the linearisation's, by which these rules judge it)
    held = {n for n in fit.at_bound if not np.isfinite(stderr[n])} if np.isfinite(fit.chi2) else set()  # (an overflowed fit's are undetermined)
    out = (out | {n for n in names if not np.isfinite(stderr[n])}) - held
    if corr.shape == (len(names), len(names)) and len(names) > 1:
        a, b = np.nonzero(np.triu(np.abs(np.nan_to_num(corr)) > CORRELATION_MAX, 1))
        for i, j in zip(a.tolist(), b.tolist()):
            if abs(corr[i, j]) > CORRELATION_SINGULAR:
                out |= {names[i], names[j]}
            else:
                out |= {names[k] for k in (i, j) if not rel_sd[k] <= CORRELATED_ERROR_MAX}
    return frozenset(out)


def _opened(fit: FitResult, base: FitResult) -> frozenset[str]:
    """The resistors ``fit`` adds to ``base``'s circuit that ran open (above
    `OPEN_RESISTANCE_FACTOR` × the data's largest |Z|): the effect's branch carries no current
    the data can see, so the data do not determine it, whatever its standard error says (on
    PowerSuite's REAL spectrum a nested R_relax went to 1.2e275 Ω "± 9e10 Ω", the error of a
    linearisation at so flat a point). A baseline resistor running open is the baseline's
    business (refine takes such a fit at the bound)."""
    z_max = float(np.max(np.abs(fit.z_data)))
    baseline = set(base.circuit.element_names)
    return frozenset(e.name for e in fit.circuit.elements() if e.symbol == "R" and e.name not in baseline and e.name in fit.free_names and fit.values[e.name] > OPEN_RESISTANCE_FACTOR * z_max)


def _undetermined_elements(fit: FitResult) -> frozenset[str]:
    """Elements of ``fit``'s circuit whose free parameters are all undetermined
    (`undetermined_parameters`)."""
    undetermined = undetermined_parameters(fit)
    out = set()
    for e in fit.circuit.elements():
        names = [n for n in fit.registry[e.symbol].parameter_names(e.name) if n in fit.free_names]
        if names and set(names) <= undetermined:
            out.add(e.name)
    return frozenset(out)


def _error_scales(fit: FitResult, names: Sequence[str], values: np.ndarray) -> np.ndarray:
    """What each parameter's standard error is measured against: its value, or for an exponent
    on a finite range (a CPE's α in (0, 1]) the width of that range. An exponent's error is
    absolute: α = 0.17 ± 0.05 is known to a twentieth of its range, though 29 % of its value."""
    specs = fit.circuit.parameter_specs(fit.registry)
    width = np.array([specs[n].upper - specs[n].lower if specs[n].unit == "1" else np.nan for n in names], float)
    return np.where(np.isfinite(width) & (width > 0), width, values)


def centred_covariance(fit: FitResult) -> tuple[np.ndarray, np.ndarray]:
    """Relative standard errors (`_error_scales`: an exponent's against its range) and
    correlations of ``fit``'s free parameters, each CPE's Q taken at the angular frequency ω_c
    of the band where it is least correlated with α.

    With y = ln Q + α ln ω_c (ln of the CPE's admittance coefficient at ω_c):
    cov(y, α) = cov(ln Q, α) + ln ω_c var(α) = 0 at ln ω_c = −cov(ln Q, α)/var(α), clipped
    to the data's band; y's standard error is relative (a log). A linear change of variables:
    the fit is the same, only the coefficient it reports moves. Parameters at a bound are held
    there (`_held_at_bounds`): the others' errors and correlations are those given them, and
    theirs stay as the fit reports them. Without a finite covariance the raw relative errors and
    correlation are returned."""
    names = list(fit.free_names)
    values = np.array([fit.values[n] for n in names], float)
    linearised = fit.linearised_stderr  # (at a bound: the linearisation's)
    stderr = np.array([linearised[n] for n in names], float)
    scale = _error_scales(fit, names, values)
    with np.errstate(all="ignore"):
        rel_sd = np.abs(stderr / scale)
    corr = fit.linearised_correlation
    cov = np.asarray(fit.covariance, float)
    bound = [names.index(n) for n in fit.at_bound if n in names]
    if cov.shape != (len(names), len(names)) or not np.all(np.isfinite(cov)):
        return rel_sd, corr
    held = np.isin(np.arange(len(names)), bound)
    if bound:
        cov = _held_at_bounds(cov, bound)
        with np.errstate(all="ignore"):
            # (a variance that rounding took to ≤ 0 says nothing: undetermined, not exact)
            sd = np.where(held | (np.diag(cov) > 0), np.sqrt(np.clip(np.diag(cov), 0, None)), np.nan)
            corr = cov / np.outer(sd, sd)
            rel_sd = np.where(held, rel_sd, np.abs(sd / scale))
        corr[held, :] = corr[:, held] = np.nan
    # (a Q held at its bound is not moved to ω_c: its row is zero, and the move would give it α's)
    pairs = [(names.index(n), names.index(n[:-2] + ".alpha")) for n in names if n.endswith(".Q") and n[:-2] + ".alpha" in names and not held[names.index(n)]]
    if not pairs:
        return rel_sd, corr
    # d(new) = T d(old): ln Q's row is (1/Q) dQ + ln ω_c dα
    transform = np.eye(len(names))
    log_omega = np.log(2 * np.pi * np.asarray(fit.frequency, float))
    for iq, ia in pairs:
        transform[iq, iq] = 1 / values[iq]
        var_alpha = cov[ia, ia]
        centre = -cov[iq, ia] / values[iq] / var_alpha if var_alpha > 0 else np.mean(log_omega)
        transform[iq, ia] = float(np.clip(centre, log_omega.min(), log_omega.max()))
    with np.errstate(all="ignore"):  # (a Q near zero overflows: its error is then infinite, undetermined)
        cov_c = transform @ cov @ transform.T
        sd = np.sqrt(np.clip(np.diag(cov_c), 0, None))
        if bound:  # (as above: a free variance rounded to ≤ 0 is undetermined)
            sd = np.where(held | (np.diag(cov_c) > 0), sd, np.nan)
        corr_c = cov_c / np.outer(sd, sd)
        rel_c = np.abs(sd / scale)
    for iq, _ in pairs:
        rel_c[iq] = sd[iq]
    rel_c[held] = rel_sd[held]
    corr_c[held, :] = corr_c[:, held] = np.nan
    return rel_c, corr_c


def _held_at_bounds(cov: np.ndarray, bound: Sequence[int]) -> np.ndarray:
    """``cov`` of the parameters given those at a bound (indices ``bound``) held there: the
    Schur complement Σ_ff − Σ_fb Σ_bb⁺ Σ_bf, with the bound parameters' rows and columns zero.
    At its bound a parameter is not free to move, and its linearised column had diluted the
    others' correlations: a CPE at α = 1 passed the correlation rule where the identical R ∥ C
    failed it (R_relax against Wo1.R −0.91, −0.99 as R ∥ C, on AutoEIS's battery cycle 0)."""
    free = np.setdiff1d(np.arange(cov.shape[0]), bound)
    # on the correlation scale: units decades apart (Q near 1e-11 beside α) would otherwise
    # fall under pinv's cutoff, and those parameters would not be held
    sd = np.sqrt(np.clip(np.diag(cov), 0, None))
    sd = np.where(sd > 0, sd, 1.0)
    corr = cov / np.outer(sd, sd)
    c_fb = corr[np.ix_(free, bound)]
    held_corr = corr[np.ix_(free, free)] - c_fb @ np.linalg.pinv(corr[np.ix_(bound, bound)], hermitian=True) @ c_fb.T
    held = np.zeros_like(cov)
    held[np.ix_(free, free)] = held_corr * np.outer(sd[free], sd[free])
    return held


def _noise_ratio(fit: FitResult, noise: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.abs(fit.residuals) ** 2 / (2 * noise**2))))


def _context(fit: FitResult, evidence: PeakEvidence | None = None) -> BaselineContext:
    """What the effects' proposal functions see of the baseline fit (sorted by frequency)."""
    order = np.argsort(fit.frequency)
    stderr = fit.linearised_stderr
    undetermined = frozenset(k for k in fit.free_names if not (np.isfinite(stderr[k]) and abs(stderr[k]) <= abs(fit.values[k])))
    return BaselineContext(fit.circuit, fit.values, fit.frequency[order], fit.z_data[order], fit.z_model[order], fit.registry, undetermined, evidence)


DRT_FAILURES = (ImpedaxError, ValueError, ArithmeticError, np.linalg.LinAlgError)
"""What a DRT of a spectrum raises when it cannot be computed (too few points, a failed solve)."""


class DRTMemo:
    """`drt` of each spectrum solved once: the DRTs one diagnosis or one `refine` run has
    computed, by their exact input (frequency and Z bit for bit, and the keywords), failures
    (`DRT_FAILURES`) included. The data's DRT depends on the data alone, yet each step of a
    refine solved it again, with every pair and lead it fitted (13 solves of one spectrum in a
    refine of exampleData.csv), and a step's baseline is often the fit whose DRT the step before
    solved; the same input gives the same result, so one run's results are bit-identical with
    it. Keep one per run (`refine` makes one per call): it holds every result it returns, and
    the fit of the circuit the data's DRT reads (`circuit_fit`), the same at every step."""

    def __init__(self) -> None:
        self._results: dict[tuple, object] = {}

    def _once(self, data, detail: tuple, compute: Callable[[], object]):
        """``compute()`` for the spectrum ``data`` ((frequency, Z), bit for bit) and ``detail``,
        done once; a failure (`DRT_FAILURES`) is kept and raised again each time."""
        frequency, z = data
        key = (np.asarray(frequency, float).tobytes(), np.asarray(z, complex).tobytes()) + detail
        if key not in self._results:
            try:
                self._results[key] = compute()
            except DRT_FAILURES as err:
                self._results[key] = err
        out = self._results[key]
        if isinstance(out, BaseException):
            raise out
        return out

    def __call__(self, data, **options):
        return self._once(data, ("drt",) + tuple(sorted(options.items())), lambda: drt(data, **options))

    def circuit_fit(self, data, model: str, weighting: str, compute: Callable[[], FitResult]) -> FitResult:
        """The fit of the DRT's circuit ``model`` to ``data`` ((frequency, Z)) with ``weighting``,
        ``compute``d once (`_drt_circuit_fit`: each step of a refine diagnoses the same data)."""
        return self._once(data, ("circuit", model, weighting), compute)


def _drt_evidence(fit: FitResult, notes: list[str], solved: DRTMemo) -> PeakEvidence | None:
    """The data's DRT peaks against the baseline's (`unexplained_peaks`, each DRT through
    ``solved``), or None with a note when the DRT cannot be computed (too few points, a failed
    solve): the diagnosis then runs on the misfit alone."""
    try:
        data_drt = solved((fit.frequency, fit.z_data))  # one 1-D spectrum: a DRTResult
        evidence = unexplained_peaks(data_drt, fit, solve=solved)
    except DRT_FAILURES as err:
        notes.append(f"DRT evidence not used: {getattr(err, 'detail', err)}")  # (the DRT ran on the fit's arrays: no file to name)
        return None
    return evidence


def _spectrum_of(fit: FitResult, data: xr.Dataset | None):
    """A spectrum Dataset on the fit's frequencies, with ``sigma`` from ``data`` if it has one."""
    sigma = None
    if data is not None and "sigma" in data:
        f_data = np.asarray(data["frequency"].values, float)
        idx = [int(np.argmin(np.abs(f_data - f))) for f in fit.frequency]
        if not np.allclose(f_data[idx], fit.frequency, rtol=1e-9):
            raise DataError("the data's frequencies do not contain the fit's; pass the data the fit was made on", path=str(data.attrs.get("source", "data")))
        sigma = np.asarray(data["sigma"].values, float)[idx]
    return make_spectrum(fit.frequency, fit.z_data, sigma=sigma, source="diagnosis"), sigma


def _new_values(base: FitResult, cand: FitResult) -> str:
    """The fitted values of the parameters the candidate adds or changes, with units."""
    specs = cand.circuit.parameter_specs(cand.registry)
    new = [n for n in cand.free_names if n not in base.values]
    return ", ".join(f"{n} = {format_quantity(cand.values[n], specs[n].unit)}" for n in new)


def _band_rms(fit: FitResult, lo: float, hi: float) -> float:
    """rms_rel of ``fit`` at the points with lo ≤ f ≤ hi, √mean|r_k|² as the fit's own (NaN
    without any)."""
    inside = (fit.frequency >= lo) & (fit.frequency <= hi)
    return float(np.sqrt(np.mean(np.abs(fit.residuals[inside]) ** 2))) if inside.any() else math.nan


def _lowered_bands(base: FitResult, cand: FitResult, bands: Sequence[FailingBand], fixed) -> list[tuple[tuple[float, float], float, float]]:
    """The failing bands of ``base`` that ``cand`` does not clear (not in ``fixed``) but where it
    at least halves the rms relative residual, except a band of most points (the overall
    rms_rel says it): [((f_min, f_max), rms before, rms after)]."""
    out = []
    for b in bands:
        inside = (base.frequency >= b.f_min) & (base.frequency <= b.f_max)
        if (b.f_min, b.f_max) in fixed or inside.mean() > 0.8:
            continue
        before, after = _band_rms(base, b.f_min, b.f_max), _band_rms(cand, b.f_min, b.f_max)
        if after <= BAND_LOWERED_FRACTION * before:
            out.append(((b.f_min, b.f_max), before, after))
    return out


EVIDENCE_ALPHA_AGREEMENT = 0.15
"""A fitted exponent within this of the one a DRT peak's width implies agrees with it
(`_evidence_words`)."""


def _evidence_words(p: Proposal, cand: FitResult) -> str:
    """`Proposal.evidence` in brackets when the fit ``cand`` agrees with what it expects (each
    value of `Proposal.expected` within `EVIDENCE_ALPHA_AGREEMENT`), else what the fit did
    instead: REAL Autolab file, R0 + R1 ∥ C1 → CPE: "the DRT peak … α ≈ 0.80" would stand beside a
    fitted α = 0.404, a CPE spanning several processes; "" without
    evidence."""
    if not p.evidence:
        return ""
    off = {k: (v, float(cand.values[k])) for k, v in p.expected.items() if k in cand.values and abs(float(cand.values[k]) - v) > EVIDENCE_ALPHA_AGREEMENT}
    if not off:
        return f" ({p.evidence})"
    name, (want, got) = next(iter(off.items()))
    return (f" (the data's DRT peak there implies {name} ≈ {want:.2f}, but the fit took {got:.2f}: the CPE spans more than that one peak, "
            "several processes or a tail, not the peak's width alone)")


def _explain(effect, p: Proposal, base: FitResult, cand: FitResult, fixed, lowered=()) -> str:
    """The suggestion in the terms of the user's circuit and data: what is added where, its
    fitted values with units, the error it removes, the bands it fixes and those where it at
    least halves the misfit (`_lowered_bands`). Its ΔAIC and ΔBIC are the report's model line's
    (`Diagnosis.report`), given once."""
    band_text = ""
    if fixed:
        band_text = "; it removes the misfit at " + ", ".join(format_band(lo, hi) for lo, hi in fixed)
    if lowered:
        band_text += ("; it lowers the misfit at " if not fixed else " and lowers it at ") + ", ".join(f"{format_band(lo, hi)} (rms_rel there {before * 100:.2g} % → {after * 100:.2g} %)" for (lo, hi), before, after in lowered)
    values = _new_values(base, cand)
    what = p.where if "+" in effect.id else f"{p.added} {p.where}"  # (a pair's placement names each addition, `_paired`)
    what += _evidence_words(p, cand)
    return (
        f"{effect.title}: adding {what}" + (f" ({values})" if values else "")
        + f" lowers rms_rel from {base.rms_rel * 100:.3g} % to {cand.rms_rel * 100:.3g} %{band_text}."
    )


def _drt_supports(s: Suggestion, evidence: PeakEvidence | None) -> bool:
    """Does the data's DRT back this candidate: an ``extra_relaxation`` whose new arc's τ (R·C
    of an added R ∥ C) lies within half a decade of a narrow (R ∥ C-like) peak the baseline
    does not explain, one the DRT's uncertainty tells from zero (`is_resolved`)?"""
    if evidence is None or s.effect != "extra_relaxation":
        return False
    v = s.fit.values
    r = next((k for k in v if k.startswith("R_relax")), None)
    c = next((k for k in v if k.startswith("C_relax")), None)
    if r is None or c is None:
        return False
    # the fit lists exchangeable blocks in one order (`canonical_order`): the new arc's values may
    # sit under the name of a baseline arc of the same structure, so every such arc's τ counts
    pairs = [(r, c)]
    names = list(v)
    for group in exchangeable_blocks(s.fit.circuit, names, np.zeros(len(names), bool), np.zeros(len(names)), np.zeros(len(names)), s.fit.registry):
        members = [[names[i] for i in idx] for _, idx in group]
        if [r, c] in members:  # (the group of R_relax ∥ C_relax itself: R ∥ C blocks, R's then C's parameter)
            pairs += [(a, b) for a, b in members]
    narrow = [p for p in evidence.unexplained if is_resolved(p) and not any(p is d for d in evidence.distributed)]
    return any(v[a] * v[b] > 0 and abs(math.log10(v[a] * v[b] / p.tau_s)) <= 0.5 for a, b in pairs for p in narrow)


def _ranked_before(s: Suggestion, t: Suggestion) -> str:
    """Why ``s`` ranks before ``t`` although ``t`` lowers AIC more (`_rank`'s rules, the first
    that tells them apart), in words for the report: a heading that spelled out every rule on every run (60 words) would
    not tell a reader of BioLogic's REAL spectrum which one put CPE1 (ΔAIC −78.2) before a
    Warburg (−85.7): the simpler."""
    margin = f"within ΔAIC {DELTA_AIC_MIN:g} of each other the data barely tell them apart, and"
    if set(t.removed) - set(t.vanished) and not set(s.removed) - set(s.vanished):
        return f"it keeps every element of yours ({t.model} leaves {', '.join(sorted(set(t.removed) - set(t.vanished)))} out, which changes what your elements stand for)"
    if t.delta_aic < s.delta_aic - DELTA_AIC_MIN:
        return "see the ranking rules, docs/diagnosis.md"
    if _ranked_size(s) < _ranked_size(t):
        fell = "".join(f", counting {', '.join(u.vanished)}, which fell to zero in {u.model} and was left out, as kept" for u in (s, t) if u.vanished)
        return f"{margin} the simpler goes first ({counted(_ranked_size(s), 'free parameter')} against {_ranked_size(t)}{fell})"
    if t.removed and not s.removed:
        return f"{margin} the one that leaves no element out goes first"
    if _claims_finite_diffusion(t) and not _claims_finite_diffusion(s):
        return f"{margin} a finite Warburg's 45° region is not shown decisively"
    if s.effect == "extra_relaxation" and t.effect != "extra_relaxation":
        return f"{margin} the data's DRT backs the added arc"
    return f"{margin} of candidates that are the same fit within the noise, one that changes an idle element goes first"


def _ranked_size(s: Suggestion) -> int:
    """The free parameters `_rank`'s parsimony counts for candidate ``s``: its fit's, plus one for
    each series resistance of the baseline that fell to zero in it and was left out
    (`Suggestion.vanished`; `_series_resistance_dropped` drops free resistors only). The candidate
    that kept it is the same fit with it at 0, and the ranking already counts ``s`` as keeping it
    (it is not "left out"); leaving it out so that the other parameters are determined does not
    make ``s`` the simpler explanation of the data: else, on a SYNTHETIC Meyer
    finger with CPE skin (α = 0.8, 1 % noise), W_d in series, R_f fallen to zero (4 parameters,
    ΔAIC −68.4), would be named before CPE_sc in place of C_sc (5, ΔAIC −72.1), the truth."""
    return ranked_size(s.fit, s.vanished)


def ranked_size(fit: FitResult, vanished: Sequence[str] = ()) -> int:
    """The size the parsimony rules compare (`_rank`'s and `refine`'s choice between its paths'
    ends): ``fit``'s free parameters plus one for each of ``vanished``, the free series
    resistances of the circuit it came from that fell to zero and were left out on the way
    (`Suggestion.vanished`): each is counted as kept, as its one free parameter (`_ranked_size`)."""
    return fit.n_params + len(vanished)


def _claims_finite_diffusion(s: Suggestion) -> bool:
    """Does the candidate add a finite Warburg (Wo, Ws) as diffusion (not in place of a
    semi-infinite W the circuit had)?"""
    if s.effect != "diffusion" or s.added not in s.fit.circuit.element_names:
        return False
    return s.fit.registry[s.fit.circuit.element(s.added).symbol].symbol in FINITE_WARBURGS and not s.where.startswith(IN_PLACE_OF_WARBURG)


def _changes_idle(s: Suggestion, idle: frozenset[str], base: Circuit | None) -> bool:
    """Does candidate ``s`` change an ``idle`` element of the baseline circuit ``base``: replace
    or leave it out (it is not in the candidate's circuit), or extend it (the candidate puts it
    in a node of another kind: in series with a new element where it was a parallel branch, or
    the reverse)?"""
    if not idle or base is None:
        return False
    before, after = element_parents(base), element_parents(s.fit.circuit)
    return any(e not in after or type(after[e]) is not type(before.get(e)) for e in idle)


def _idle_first(order: list[Suggestion], idle: frozenset[str], base: Circuit | None, noise: np.ndarray | None) -> list[Suggestion]:
    """``order`` with each candidate that changes an idle element of the baseline (`_changes_idle`)
    moved ahead of the first one before it that is the same fit within the noise (`_same_fit`) and
    changes none, when it is no larger and in the same class (with or without a warning). The two
    fit the data alike, but changing an element the baseline left idle keeps every working
    element's value and role, where the other reassigns them (R ∥ C_EP ∥ C_gap with C_EP idle:
    C_gap → CPE_gap fits as well as C_EP → CPE_EP, but moves the gap's capacitance into C_EP).
    Without idle elements or ties, ``order`` is returned unchanged."""
    if noise is None or not idle or base is None:
        return order
    out = list(order)
    for t in [s for s in order if _changes_idle(s, idle, base)]:
        i = out.index(t)
        tied = next((j for j, s in enumerate(out[:i]) if not _changes_idle(s, idle, base) and (s.warning is None) == (t.warning is None)
                     and t.fit.n_params <= s.fit.n_params and _same_fit(s.fit, t.fit, noise)), None)
        if tied is not None:
            out.insert(tied, out.pop(i))
    return out


def _rank(cands: list[Suggestion], evidence: PeakEvidence | None = None, loose: frozenset[str] = frozenset(), idle: frozenset[str] = frozenset(), base: Circuit | None = None, noise: np.ndarray | None = None) -> list[Suggestion]:
    """Best first by AIC, with the same parsimony rule as the verdict: a candidate with more
    free parameters outranks a simpler one only if it lowers AIC by more than `DELTA_AIC_MIN`.
    A candidate "leaves an element out" when it drops a baseline element that is not in
    ``loose`` (the elements the baseline does not determine: it gave them no value to stand
    for) and did not fall to zero where the candidate kept it (`Suggestion.vanished`: the kept
    candidate is the same fit with that element at 0, so no element stands for anything
    else). Among candidates the data cannot tell apart (within `DELTA_AIC_MIN`), one that keeps
    every element goes first (R ∥ C + R ∥ C is the same function of frequency as
    (R0 + R ∥ C) ∥ C), then the smaller (`_ranked_size`: a series resistance that fell to zero
    and was left out counts as kept), then one that drops no element at all, then one that
    does not add a finite Warburg as diffusion (`_claims_finite_diffusion`: its 45° region is
    what tells it from an arc of as many parameters, and within `DELTA_AIC_MIN` the data do
    not show it decisively), then one the DRT backs (`_drt_supports`). When a candidate that
    keeps every element is significant, every candidate that leaves one out comes after it:
    leaving an element out changes what the user's elements stand for (R_sc of an arc becomes
    the series resistance), so it is the answer only when nothing that keeps them explains the
    data. Candidates with a warning
    (undetermined or implausible parameters, no convergence) come after all the others. Last,
    of candidates that are the same fit within ``noise``, one that changes an ``idle`` element
    of the ``base`` circuit goes first (`_idle_first`)."""
    def left_out(s: Suggestion) -> bool:
        return not set(s.removed) <= loose | set(s.vanished)

    def ranked(group):
        rest = sorted(group, key=lambda s: s.delta_aic)
        out = []
        while rest:
            best_aic = rest[0].delta_aic
            close = [s for s in rest if s.delta_aic <= best_aic + DELTA_AIC_MIN]
            pick = min(close, key=lambda s: (left_out(s), _ranked_size(s), bool(s.removed), _claims_finite_diffusion(s), not _drt_supports(s, evidence), s.delta_aic))
            out.append(pick)
            rest.remove(pick)
        return out

    clean = [s for s in cands if s.warning is None]
    keeping = ranked([s for s in clean if not left_out(s)])
    first = keeping + ranked([s for s in clean if left_out(s)]) if any(s.significant for s in keeping) else ranked(clean)
    return _idle_first(first + ranked([s for s in cands if s.warning is not None]), idle, base, noise)


def non_passive_points(ds: xr.Dataset) -> np.ndarray:
    """Points (bool per frequency) the diagnosis leaves out as not passive: Re Z < 0 beyond
    the noise (`statistics.non_passive`: below −5 % of |Z|, and below −k σ, σ the data's own or
    else the KK test's noise estimate (`non_passive_noise`), k = `statistics.chance_depth`: 3.6 at
    61 points).

    Every element of the catalog is passive, so no circuit built from them has a negative
    real part (Re Z(jω) ≥ 0 for a passive one-port); such points are measurement artifacts
    (a phase error of the instrument near the top of its band is the usual cause). They are
    left out only while they are at most `MASK_MAX_FRACTION` of the points and leave
    `MIN_KEPT_POINTS`: a spectrum mostly below zero has a sign or reader problem to fix."""
    bad = non_passive(ds["Z"].values, ds["sigma"].values if "sigma" in ds else None, non_passive_noise(ds))
    if bad.mean() > MASK_MAX_FRACTION or (~bad).sum() < MIN_KEPT_POINTS:
        return np.zeros(bad.size, bool)
    return bad


def non_passive_noise(ds: xr.Dataset) -> np.ndarray | None:
    """σ [Ω] per point that `non_passive_points` judges Re Z < 0 against where the data state no
    σ: the noise the Kramers–Kronig test's residuals show (`KKResult.non_passive_noise`, as
    `impedax kk` judges them), so that noise alone is not left out as an artifact (a
    SYNTHETIC finger spectrum with ~2 % noise, Re Z 0.01–0.3 % of |Z| below 1 kHz, had a point
    beyond −5 % of |Z| in 1 of 12 spectra); None with σ, or where the test cannot run."""
    if "sigma" in ds:
        return None
    try:
        kk = kk_test(ds[["Z"]])
    except ImpedaxError:
        return None
    return None if kk.non_passive_noise is None else np.abs(ds["Z"].values) * kk.noise_estimate


def _fit_baseline(data, circuit: Circuit | str, effects: EffectCatalog, *, registry: Registry, fmin, fmax, weighting: str, n_starts: int, seed: int, shape: SolverShape | None, noise_given: bool, fixed: Mapping[str, float] | None = None,
                  bounds: Mapping[str, tuple[float, float]] | None = None):
    """Fit the user's circuit with the same compiled solver the candidates will use
    (`BASELINE_COPIES` copies of the circuit, each with its own random starts): one compilation
    in all.
    Every start runs twice, damped with λI (as `impedax.fit`'s optimistix) and with Marquardt's
    scaling (as the candidates), and the best fit is kept (docs/fitting.md, "Damping"): from
    the same cold starts the two reach different optima, and neither is always the better (a
    9-element ladder: 2.9 % with the scaling alone where λI reaches 1.8 %).
    Points with Re Z < 0 (`non_passive_points`) are left out. ``noise_given``: whether a noise
    level or a KK result was given (without one, too few points are refused before the fit,
    `_require_noise_without_kk`). ``fixed``: the user's fixed values (name → value), held in
    the baseline fit and so, through its `FitResult.fixed`, in every candidate fit that has the
    parameter (`_fit_proposals`); ``bounds`` (name → (lower, upper)), the user's bounds, kept the
    same way through `FitResult.bounds`. Returns (fit, spectrum Dataset of the points fitted, solver
    shape, the points left out as not passive: frequency → Z)."""
    ds = open_spectrum(data, fmin=fmin, fmax=fmax, single="diagnose").data
    not_passive = non_passive_points(ds)
    left_out = {float(f): complex(z) for f, z in zip(ds["frequency"].values[not_passive], ds["Z"].values[not_passive])}
    if left_out:
        ds = ds.isel(frequency=np.nonzero(~not_passive)[0])
    circuit = parse(circuit, registry)  # (a circuit's errors before the data's, and both before the fit)
    if fixed or bounds:  # (an unknown name, a value or bound out of range, lower ≥ upper, every parameter fixed: fit's own errors, before the fit)
        ParameterTable.build(circuit, registry=registry, fixed=fixed, bounds=bounds)
    require_points_for_diagnosis(ds.sizes["frequency"], len(circuit.parameter_names(registry)), source=ds.attrs.get("source"), fmin=fmin, fmax=fmax)
    if not noise_given:
        _require_noise_without_kk(ds.sizes["frequency"], None, ds["sigma"] if "sigma" in ds else None, source=ds.attrs.get("source"))
    _require_nonzero_impedance(ds["frequency"].values, ds["Z"].values, source=ds.attrs.get("source"))
    # the candidates depend on the circuit's structure: propose them around a stand-in fit, so
    # that one compiled solver holds the baseline and its candidates. The stand-in model is the
    # data scaled by 0.999, on no data-gated effect's side (an inductive loop is proposed only
    # where the data fall below the model's Z' and above its Z''); `_fit_proposals` grows the
    # shape when the data do call for one. The baseline's starts do not depend on it
    order = np.argsort(ds["frequency"].values)
    freq = np.asarray(ds["frequency"].values, float)[order]
    z = np.asarray(ds["Z"].values, complex)[order]
    stand_in = BaselineContext(circuit, circuit.defaults(registry), freq, z, z * (1 - 1e-3), registry)
    proposed = [p.circuit for _, p in effects.proposals(stand_in)]
    shape = (shape or solver_shape([circuit] + proposed, registry, freq.size)).grown_to([circuit] + proposed, registry, freq.size)
    copies = _baseline_copies(circuit, registry)
    fits = fit_candidates(
        [circuit] * (2 * copies), ds, fixed=dict(fixed) if fixed else None, bounds=dict(bounds) if bounds else None, weighting=weighting, n_starts=n_starts, max_steps=BASELINE_STEPS, seeds=[seed + i for i in range(copies)] * 2,
        registry=registry, shape=shape, damping=["identity"] * copies + ["marquardt"] * copies,
    )
    best = min(fits, key=lambda r: r.chi2 if np.isfinite(r.chi2) else np.inf)
    return best, ds, shape, left_out


def _baseline_copies(circuit: Circuit, registry: Registry) -> int:
    """How many copies of ``circuit`` the baseline fit runs (`BASELINE_COPIES`)."""
    k = len(circuit.parameter_names(registry))
    return next(copies for most, copies in BASELINE_COPIES if most is None or k <= most)


def _baseline(fit_or_data, circuit, *, data, effects, registry, fmin, fmax, weighting, n_starts, seed, shape, noise_given, fixed=None, bounds=None):
    """The fit to diagnose, the data it was made on (or None), the solver shape (or None) and
    the points left out as not passive, frequency → Z (data given with a circuit, fitted with
    ``fixed`` held and within ``bounds``; a `FitResult` is diagnosed on the points it was fitted
    to, with its own fixed values and bounds)."""
    if isinstance(fit_or_data, FitResult):
        if circuit is not None:
            raise ParameterError("give either a FitResult or data with a circuit, not both")
        if fixed:
            raise ParameterError("fixed= goes with data and a circuit; a FitResult keeps the fixed values it was fitted with (fit(..., fixed=...) first)")
        if bounds:
            raise ParameterError("bounds= goes with data and a circuit; a FitResult keeps the bounds it was fitted with (fit(..., bounds=...) first)")
        if fmin is not None or fmax is not None:
            raise ParameterError("fmin/fmax select the band of data to fit; a FitResult keeps the band it was fitted on")
        _require_nonzero_impedance(fit_or_data.frequency, fit_or_data.z_data, source=fit_or_data.source)
        return fit_or_data, data, shape, {}
    if isinstance(fit_or_data, BatchFitResult):
        raise ParameterError("diagnose takes the fit of one spectrum; fit a trial mean or select one spectrum of the batch")
    if circuit is None:
        raise ParameterError("diagnose(data, circuit): the circuit to diagnose is missing")
    if data is not None:
        raise ParameterError("give the data once")
    return _fit_baseline(fit_or_data, circuit, effects, registry=registry, fmin=fmin, fmax=fmax, weighting=weighting, n_starts=n_starts, seed=seed, shape=shape, noise_given=noise_given, fixed=fixed, bounds=bounds)


BOUNDS_KEPT_LEAD = "your bounds ("
"""The start of the note that the user's bounds were kept in every candidate fit: information,
not a caveat, so it is no one of `Diagnosis.warnings`."""

MIN_DIAGNOSIS_POINTS = 4  # what the KK test needs (R_0, one RC element, L, C)


def require_points_for_diagnosis(n_points: int, n_free: int, command: str = "diagnose", *, source: str | None = None, fmin: float | None = None, fmax: float | None = None) -> None:
    """`DataError` when the spectrum is too short to judge a model (before, one point was
    judged "adequate"): the KK test needs `MIN_DIAGNOSIS_POINTS` frequencies, and the real
    values must outnumber the free parameters by as many (a model with as many parameters as
    data values fits anything). ``command``: who needs them (refine checks before its first
    diagnosis, whose words "diagnose needs" had answered ``impedax refine``). ``source``: the
    file, named first; ``fmin``/``fmax``: the band that kept them, named after (REAL
    exampleDataZPlot.z with --fmin 1e4 --fmax 1.2e4 said "got 1" and neither the file nor why)."""
    needed = max(MIN_DIAGNOSIS_POINTS, -(-(n_free + MIN_DIAGNOSIS_POINTS) // 2))
    if n_points < needed:
        if fmin is not None and fmax is not None:
            band = f" from fmin = {format_frequency(fmin)} to fmax = {format_frequency(fmax)}"
        elif fmin is not None or fmax is not None:  # (fit's words for its own count)
            band = f" at or above fmin = {format_frequency(fmin)}" if fmin is not None else f" at or below fmax = {format_frequency(fmax)}"
        else:
            band = ""
        raise DataError(f"{command} needs at least {needed} frequencies for {counted(n_free, 'free parameter')} and the Kramers–Kronig test, got {n_points}{band}", path=source)


def _require_nonzero_impedance(frequency, z, *, source: str | None) -> None:
    """`DataError` when Z is exactly zero at some frequency: a diagnosis judges misfits against
    noise relative to |Z| and starts its candidates from the data's |Z|, so such a point has no
    noise scale (`impedax diagnose` of an all-zero table, with weighting 'unit', a value the fuzz
    matrix (tests/cli_fuzz_matrix.py) gives, gets this message, not a ZeroDivisionError)."""
    if np.any(np.asarray(z) == 0):
        raise DataError(f"{zero_impedance_text(np.asarray(frequency, float), np.asarray(z))}; a diagnosis judges misfits against noise relative to |Z|, "
                        "which needs |Z| > 0: drop those points", path=source)


def _require_noise_without_kk(n_points: int, noise: float | None, sigma, *, source: str | None) -> None:
    """`DataError` when the KK test is inconclusive (``n_points`` below `CONCLUSIVE_POINTS_MIN`
    frequencies) and neither a noise level nor the data's sigma is given: nothing then tells the
    model's misfit from noise (the KK chain's own misfit read as 3.9 % noise against a 2 % misfit
    on BioLogic's REAL file above 300 Hz, 5 points; a 26 % misfit of a hand-written 4-point table
    was called adequate)."""
    if n_points < CONCLUSIVE_POINTS_MIN and noise is None and sigma is None:
        raise DataError(
            f"{n_points} frequencies are too few to tell the model's misfit from noise (the KK test that estimates it needs {CONCLUSIVE_POINTS_MIN}): "
            "give the noise level, e.g. --noise 1% (noise=0.01), or data with a sigma column",
            path=source,
        )


def _kk_of(spectrum: xr.Dataset, notes: list[str], attrs: Mapping | None = None) -> KKResult | None:
    """The Kramers–Kronig test of the spectrum, or None (with a note) when it cannot run;
    ``attrs``: the data's, under the spectrum's own, for how its sign hint says to fix the file
    (`io.sign_check.opposite_sign_hint`: which column to rename)."""
    try:
        return kk_test(spectrum[["Z"]].assign_attrs({**(attrs or {}), **spectrum.attrs}))
    except ImpedaxError as err:
        notes.append(f"Kramers–Kronig test not run: {err}")
        return None


def _require_kk_on_the_fit(kk: KKResult, frequency: np.ndarray) -> None:
    """`ParameterError` when the KK result given (``kk=``) lacks some of the fit's frequencies
    [Hz]: its flags and residuals are placed on the fit's points by frequency (`kk_indices`), and
    before, a test of another grid was silently never placed (nothing masked, "adequate"). A test
    of the full data with a fit over a part of it (--fmin/--fmax) holds them all."""
    f_kk = np.asarray(kk.frequency, float)
    if kk_indices(kk, frequency) is None:
        grid = lambda f: f"{f.size} frequencies, {format_band(float(f.min()), float(f.max()))}"  # noqa: E731
        raise ParameterError(
            f"the KK result given (kk=) is of another frequency grid ({grid(f_kk)}) than the fit's ({grid(np.asarray(frequency, float))}): "
            "it must hold every frequency of the fit; run the KK test on the data diagnosed (impedax.kk_test(data)), or leave kk out"
        )


class DataProblem(NamedTuple):
    """The data's own problems at the fit's points: why they are invalid (or None) and which
    points to mask (bool per point of the fit); when invalid, the band the KK test passes that a
    trim keeps (`kk_valid_run`, or None) and whether the model misses it clearly there."""

    invalid: str | None
    masked: np.ndarray
    note: str | None
    valid_band: tuple[float, float] | None = None
    misses_valid_band: bool = False
    kept: str | None = None  # why KK-flagged points were kept in every fit (inside the band, or too many), or None
    kept_passing_band: tuple[float, float] | None = None  # too many kept: the run the KK test passes [Hz], which ``kept`` names with its trim
    run_band: tuple[float, float] | None = None  # invalid: the band refine starts again on (`kk_valid_run`, or tested again), ``valid_band`` unless impedax kk names another
    misses_run_band: bool = False  # invalid: the model misses ``run_band`` clearly


def kk_valid_run(frequency: np.ndarray, flagged: np.ndarray, n_params: int) -> np.ndarray | None:
    """The longest run of adjacent points (in frequency order) the KK test does not flag, as a
    bool per point of ``frequency`` (any order): what ``--fmin``/``--fmax`` keep of the band.
    None when it holds fewer than `MIN_KEPT_POINTS` or 3 per free parameter (each point gives two
    numbers; the rule by which flagged points are masked), or every point."""
    order = np.argsort(frequency)
    ok = ~np.asarray(flagged, bool)[order]
    best, start = (0, 0), None
    for i, good in enumerate(np.append(ok, False)):
        if good and start is None:
            start = i
        elif not good and start is not None:
            best, start = max(best, (i - start, start)), None
    length, first = best
    if length < max(MIN_KEPT_POINTS, 3 * n_params) or length == ok.size:
        return None
    run = np.zeros(ok.size, bool)
    run[order[first:first + length]] = True
    return run


def _band_misses(fit: FitResult, run: np.ndarray, dkk: np.ndarray, noise: NoiseModel) -> tuple[bool, float, float, float]:
    """Whether the model misses the points ``run`` clearly — its rms_rel there at least
    1/`KK_COMPARABLE`× the KK misfit ``dkk`` there (the rule that keeps a flagged point as the
    model's problem) and above `NOISE_RATIO_MAX` × the noise (a missing effect, not the data's) —
    with the model's rms_rel, the KK rms_rel and the noise ratio there."""
    model_rms = float(np.sqrt(np.mean(np.abs(fit.residuals[run]) ** 2)))
    kk_rms = float(np.sqrt(np.mean(dkk[run] ** 2)))
    ratio = float(np.sqrt(np.mean(np.abs(fit.residuals[run]) ** 2 / (2 * noise.sigma_rel[run] ** 2))))
    return model_rms >= kk_rms / KK_COMPARABLE and ratio > NOISE_RATIO_MAX, model_rms, kk_rms, ratio


def _valid_band_words(fit: FitResult, kk: KKResult, run: np.ndarray, dkk: np.ndarray, noise: NoiseModel, *, retested: bool = False,
                      refine_run: np.ndarray | None = None, refine_misses: bool = False, unnamed_by_kk: str = "") -> tuple[str, bool]:
    """What a ``data_invalid`` reason adds when part of the band passes the KK test (``run``:
    `kk_valid_run`, or with ``retested`` the band found by testing again without points at the
    ends, `impedax kk`'s (`retested_band`) first, ``dkk`` then that test's): where it fails, where
    it passes, the exact ``--fmin``/``--fmax`` that keep the passing run, and whether the model
    misses clearly there (`_band_misses`). ``refine_run``: the points refine starts again on
    (`DataProblem.run_band`) when they are another band, ``refine_misses`` whether the model misses
    them clearly; ``unnamed_by_kk``: why impedax kk names no band (`_unnamed_by_kk`), or "".
    Returns the words and that flag."""
    f = fit.frequency
    trim = left_out_words(left_out_options(f[run], f[~run]))
    misses, model_rms, kk_rms, ratio = _band_misses(fit, run, dkk, noise)
    failing = kk.measured_bands_text()
    other = refine_run is not None and not np.array_equal(refine_run, run)
    narrower = (f", as impedax kk does; the full test leaves only {format_band(float(f[refine_run].min()), float(f[refine_run].max()))} unflagged in one run: its chain, fitted to every point, "
                "is pulled off the rest of this band by the points outside it") if other else ""
    words = (
        f" The KK test fails at {failing} and passes at {format_frequency(float(f[run].min()))}–{format_frequency(float(f[run].max()))} "
        f"({int(run.sum())} points, KK rms_rel {kk_rms * 100:.2g} %{', tested again without the points outside' if retested else ''}{narrower}{unnamed_by_kk}): "
        f"trim the measurement to that band ({trim})"
    )
    if misses:
        outside = float(np.mean(~run))
        by_refine = "refine does so on its own" if outside <= KK_MASK_MAX_FRACTION else (
            f"refine does not: the trim leaves out {outside * 100:.0f} % of the points, more than the {KK_MASK_MAX_FRACTION * 100:.0f} % it leaves out on its own"
        )
        if other and (outside <= KK_MASK_MAX_FRACTION or (refine_misses and np.mean(~refine_run) <= KK_MASK_MAX_FRACTION)):
            # (refine acts on its own band: say which, whatever this one's share)
            band = format_band(float(f[refine_run].min()), float(f[refine_run].max()))
            starts = refine_misses and np.mean(~refine_run) <= KK_MASK_MAX_FRACTION
            by_refine = (f"refine starts again on its own on {band}, the run the full test leaves unflagged ({left_out_words(left_out_options(f[refine_run], f[~refine_run]))})" if starts else
                         f"refine does not: it starts again only on {band}, the run the full test leaves unflagged, " + (
                             "where the model does not miss clearly" if not refine_misses else
                             f"which leaves out {np.mean(~refine_run) * 100:.0f} % of the points, more than the {KK_MASK_MAX_FRACTION * 100:.0f} % it leaves out on its own"))
        words += (
            f"; the model misses those points by {model_rms * 100:.3g} % rms, {model_rms / max(kk_rms, 1e-300):.2g}× the data's own misfit there "
            f"and {ratio:.2g}× the noise: diagnose that band ({trim}) to find what is missing ({by_refine})"
        )
    return words + ".", misses


_KK_NAMED: dict[tuple[bytes, bytes], tuple[float, float, KKResult] | None] = {}
"""`retested_band` by the fit's (frequency, Z), the last few (its search depends on them alone, with
the default options diagnose's test has): refine diagnoses one spectrum many times."""


def _kk_named_band(fit: FitResult, kk: KKResult | None) -> tuple[np.ndarray, np.ndarray] | None:
    """The band ``impedax kk`` names for the fit's points (`retested_band` of their test ``kk``,
    as tested: before `kk_judged_locally`), as a bool per point of the fit and that band's test's
    |Δ| per point (0 outside); None when it names none, when ``kk`` is of another grid than the
    fit's (the fit over a part of the data), or for a stand-in without the data."""
    z = getattr(fit, "z_data", None)
    if z is None or not isinstance(kk, KKResult) or np.size(kk.frequency) != fit.n_points or kk_indices(kk, fit.frequency) is None or not kk.searches_passing_band:
        return None
    key = (np.asarray(fit.frequency, float).tobytes(), np.asarray(z, complex).tobytes())
    if key not in _KK_NAMED:
        if len(_KK_NAMED) >= 8:
            _KK_NAMED.pop(next(iter(_KK_NAMED)))
        _KK_NAMED[key] = retested_band(kk, fit.frequency, z)
    found = _KK_NAMED[key]
    if found is None:
        return None
    lo, hi, passing = found
    run = (fit.frequency >= lo) & (fit.frequency <= hi)
    dkk = np.zeros(fit.n_points)
    dkk[run] = np.hypot(passing.residuals_real, passing.residuals_imag)[np.searchsorted(passing.frequency, fit.frequency[run])]
    return run, dkk


def _unnamed_by_kk(kk: KKResult | None, n_points: int) -> str:
    """Why ``impedax kk`` names no trim where diagnose names the run the full test leaves
    unflagged: it keeps at least half of the points (`retested_band`); "" when kk's test is not
    the fit's or it does name one."""
    if not isinstance(kk, KKResult) or np.size(kk.frequency) != n_points or not kk.searches_passing_band:
        return ""
    return f"; the run the full test leaves unflagged: impedax kk names no trim, as no band keeping at least half of the {n_points} points passes"


def _data_problem(fit: FitResult, kk: KKResult | None, noise: NoiseModel, sign_hint: str | None = None, kk_as_tested: KKResult | None = None) -> DataProblem:
    """``data_invalid`` when the KK misfit is comparable to the model's (|Δ_kk| ≥ `KK_COMPARABLE`·|r|
    at a point the KK test flags) at at least `KK_INVALID_FRACTION` of the points; otherwise the
    flagged run at either end of the band (`end_runs`, with `end_islands_masked`) is masked when
    it is at most `KK_MASK_MAX_FRACTION` of the points and leaves enough to fit (≥ 3 per free
    parameter and ≥ 8): which points, the data alone decide. Flagged points inside the band, or
    a run beyond that share, are kept, and ``kept`` says why. ``sign_hint``: the KK test's
    (`io.sign_check.sign_hint`: it fails almost everywhere but passes on conj(Z)); the data are
    then invalid whatever the share, and the reason blames the sign convention and gives the fix,
    not the measurement (a good cell whose file stores −Z'' under Z'' was sent to be measured
    again; a model of the right kind misses conj(Z) by far more than the KK chain does, so the
    share was below `KK_INVALID_FRACTION` and conjugated SYNTHETIC finger data got "adequate").
    The band the words name with its trim is the one ``impedax kk`` names (`_kk_named_band` of
    ``kk_as_tested``, the test before `kk_judged_locally`; default ``kk``) when it names one:
    on REAL CH Instruments 4.64 Hz–82.5 kHz, where the longest run the full test leaves
    unflagged is 825 Hz–46.4 kHz; refine still acts on the latter (`DataProblem.run_band`)."""
    none = np.zeros(fit.n_points, bool)
    tested = kk if kk_as_tested is None else kk_as_tested
    if kk is None or kk.valid:
        return DataProblem(None, none, None)
    idx = kk_indices(kk, fit.frequency)
    if idx is None:
        return DataProblem(None, none, None)
    flagged = np.asarray(kk.flagged, bool)[idx]
    dkk = np.hypot(kk.residuals_real[idx], kk.residuals_imag[idx])
    comparable = flagged & (dkk >= KK_COMPARABLE * np.abs(fit.residuals))
    share = float(np.mean(comparable))
    if sign_hint:  # (whatever the share: a model of the right kind misses conj(Z) by far more than the KK chain does)
        where = (f"where the model fails (at {share * 100:.0f} % of the points the KK misfit is at least {KK_COMPARABLE * 100:.0f} % of the model's; "
                 if share >= KK_INVALID_FRACTION else "(")
        return DataProblem(
            f"the data themselves are not Kramers–Kronig consistent {where}KK rms_rel {kk.rms_rel * 100:.2g} %, model {fit.rms_rel * 100:.2g} %), most likely because of how the file "
            f"stores the sign, not the measurement: {sign_hint}; then diagnose again.",
            none, None,
        )
    if share >= KK_INVALID_FRACTION:
        # the band the KK test passes, named with the trim that keeps it: a model that misses it
        # clearly lacks an effect there (Gamry's real file: KK fails below 2.3 kHz, passes above at
        # 0.46 %, where R0 + (R1 + R_relax ∥ CPE_relax) ∥ C1 misses by 6.45 %: C1 wants a CPE)
        run = kk_valid_run(fit.frequency, flagged, fit.n_params)
        retested = run is None  # (no run the test passes: tested again without points at the ends, `kk.passing_band`; REAL Parstat: 10 Hz–2.51 kHz)
        if retested:
            found = passing_band(fit.frequency, fit.z_data, min_points=max(MIN_KEPT_POINTS, 3 * fit.n_params, math.ceil(fit.n_points / 2)))
            if found is not None:
                lo, hi, passing = found
                run = (fit.frequency >= lo) & (fit.frequency <= hi)
                dkk = np.zeros(fit.n_points)
                dkk[run] = np.hypot(passing.residuals_real, passing.residuals_imag)[np.searchsorted(passing.frequency, fit.frequency[run])]
        # (refine acts on ``run``; the words name the band impedax kk names, when it names one)
        run_misses = run is not None and _band_misses(fit, run, dkk, noise)[0]
        run_band = None if run is None else (float(fit.frequency[run].min()), float(fit.frequency[run].max()))
        named = _kk_named_band(fit, tested)
        if named is not None:
            band_words, misses = _valid_band_words(fit, kk, named[0], named[1], noise, retested=True, refine_run=run, refine_misses=run_misses)
            band = (float(fit.frequency[named[0]].min()), float(fit.frequency[named[0]].max()))
        elif run is not None:
            band_words, misses = _valid_band_words(fit, kk, run, dkk, noise, retested=retested, unnamed_by_kk="" if retested else _unnamed_by_kk(tested, fit.n_points))
            band = run_band
        else:
            band_words, misses, band = "", False, None
        return DataProblem(
            f"the data themselves are not Kramers–Kronig consistent where the model fails: at {share * 100:.0f} % of the points the KK misfit is at least "
            f"{KK_COMPARABLE * 100:.0f} % of the model's (KK rms_rel {kk.rms_rel * 100:.2g} %, model {fit.rms_rel * 100:.2g} %): drift, movement or a non-stationary "
            "sample during the sweep; no circuit should be asked to fit them. Repeat or trim the measurement." + band_words,
            none, None, band, misses, run_band=run_band, misses_run_band=run_misses,
        )
    # what is left out is the data's judgement, not the model's: the flagged run at an end of the
    # band (an instrument's limit, a drifting start or end of the sweep), at most
    # `KK_MASK_MAX_FRACTION` of the points; flagged points inside the band, or more, are kept
    ends = end_runs(end_islands_masked(flagged, fit.frequency), fit.frequency)
    inside = flagged & ~ends
    n_left = int((~ends).sum())
    share_ends = float(np.mean(ends))
    inside_words = None if not inside.any() else (
        f"the KK test flags {counted(int(inside.sum()), 'point')} inside the band ({runs_words(inside, fit.frequency)}): kept in every fit, as the data's problem there, not left out "
        f"(a diagnosis leaves out only a flagged run at an end of the band, where an instrument's limit or a drifting start or end of the sweep puts it; "
        f"{left_out_words(left_out_options(fit.frequency[~inside], fit.frequency[inside]))} leaves these out too)"  # (impedax kk's words: REAL BioLogic --exclude 5.34,56.2,123,270)
    )
    if ends.any() and share_ends <= KK_MASK_MAX_FRACTION and n_left >= max(MIN_KEPT_POINTS, 3 * fit.n_params):
        island = ends & ~flagged
        island_words = None if not island.any() else (
            f"{counted(int(island.sum()), 'point')} at the end of the band ({', '.join(format_frequency(f) for f in np.sort(fit.frequency[island]))}) "
            f"{'lies' if island.sum() == 1 else 'lie'} beyond the masked run and {'is' if island.sum() == 1 else 'are'} masked with it: the KK test does not flag "
            f"{'it' if island.sum() == 1 else 'them'}, but {END_ISLAND_MAX} or fewer points beyond a masked run carry its drift and a model "
            "fits them exactly, whatever it does over the run"
        )
        words = [w for w in (island_words, inside_words) if w]
        return DataProblem(None, ends, "; ".join(words) if words else None, kept=inside_words)
    if not ends.any():
        return DataProblem(None, none, inside_words and f"{inside_words}: diagnosed with every point", kept=inside_words)
    # the run named once: by the flagged points' range where it is theirs, with the points beyond
    # it it takes along listed (REAL test_data.txt: "21 of 67 points (1.78 mHz–585 mHz) … the
    # flagged run at the end of the band (1 mHz–585 mHz)", two ranges for one run)
    runs = f"run{'s' if len(runs_hz(ends, fit.frequency)) > 1 else ''}"
    beyond = np.sort(fit.frequency[ends & ~flagged])
    named = (f"the flagged {runs} at the end of the band" if not inside.any() else f"the flagged {runs} at the end of the band ({runs_words(ends & flagged, fit.frequency)})") + (
        f", with the {counted(beyond.size, 'point')} beyond {'it' if runs == 'run' else 'them'} ({', '.join(format_frequency(f) for f in beyond)})," if beyond.size else "")
    why = (
        f"leaving out {named} would discard "
        f"{share_ends * 100:.0f} % of the points, more than the {KK_MASK_MAX_FRACTION * 100:.0f} % a diagnosis leaves out"
        if share_ends > KK_MASK_MAX_FRACTION else
        f"leaving them out would leave {counted(n_left, 'point')} for {counted(fit.n_params, 'free parameter')}"
    )
    kept = f"the KK test flags {int(flagged.sum())} of {flagged.size} points ({runs_words(flagged, fit.frequency)}): kept in every fit, as the data's problem there, not left out: {why}"
    run = kk_valid_run(fit.frequency, flagged, fit.n_params) if share_ends > KK_MASK_MAX_FRACTION else None
    named = _kk_named_band(fit, tested) if run is not None else None  # (the band impedax kk names first: one trim for one spectrum)
    why = "" if named is None else ", tested again without the points outside, as impedax kk does"
    if named is not None:
        run, dkk = named
    elif run is not None:
        why = _unnamed_by_kk(tested, fit.n_points)
    passing = None if run is None else (float(fit.frequency[run].min()), float(fit.frequency[run].max()))
    if run is not None:  # (REAL Gamry: 72 % flagged; a missing effect named over the whole band, refine's next step then found the data invalid)
        kept += (f"{KEPT_PASSING_LEAD}{format_band(*passing)} ({int(run.sum())} points, KK rms_rel {np.sqrt(np.mean(dkk[run] ** 2)) * 100:.2g} %{why}): "
                 f"diagnose that band alone ({left_out_words(left_out_options(fit.frequency[run], fit.frequency[~run]))}) to see what the model lacks where the data are sound")
    return DataProblem(None, none, f"{kept}: diagnosed with every point", kept=kept, kept_passing_band=passing)


KEPT_PASSING_LEAD = "; the KK test passes at "
"""How `DataProblem.kept` (`Diagnosis.kk_flagged_kept`) goes on to name the run the KK test passes
when the flagged run kept is too long to leave out."""


def _kk_floor_words(best: FitResult, kk: KKResult, passing_band: tuple[float, float] | None) -> str:
    """What a ``missing_effect`` reason adds when the data fail the KK test at points every fit
    keeps and the best candidate's misfit comes within 1/`KK_COMPARABLE`× the KK misfit (the
    rule by which a point's misfit is the data's): past it the misfit is the data's, and the
    effect may stand in for their drift. On REAL Gamry the baseline misses by 29.4 %, the KK test
    by 5.21 % (52 of 72 points flagged): the candidate reaches 5.6 %, and refine's next step
    found the data invalid where diagnose had named the effect with no word of it.
    ``passing_band``: the run the test passes, named with its trim on the data line."""
    if best.rms_rel * KK_COMPARABLE > kk.rms_rel:
        return ""
    failing = kk.measured_bands_text()
    return (f" With it the fit ({best.rms_rel * 100:.3g} %) is as close as the data allow (the KK test's own misfit is {kk.rms_rel * 100:.3g} %): "
            f"past that the misfit is the data's, and the effect may stand in for their drift at {failing}"
            + (f"; diagnose {format_band(*passing_band)}, where the test passes, alone (the data line gives the trim)." if passing_band else "."))


def runs_words(selected: np.ndarray, frequency: np.ndarray) -> str:
    """The runs of `runs_hz` in words: ``"15.9 mHz–2.02 kHz, 5 kHz–8 kHz"``."""
    return ", ".join(format_band(lo, hi) for lo, hi in runs_hz(selected, frequency))


def runs_hz(selected: np.ndarray, frequency: np.ndarray) -> list[tuple[float, float]]:
    """The runs of adjacent ``selected`` points (bool per point of ``frequency``, any order) in
    frequency order, each as its (lowest, highest) frequency [Hz], low to high."""
    order = np.argsort(frequency)
    sel, f = np.asarray(selected, bool)[order], np.asarray(frequency, float)[order]
    edges = np.flatnonzero(np.diff(np.concatenate(([0], sel.astype(int), [0]))))
    return [(float(f[a]), float(f[b - 1])) for a, b in zip(edges[::2], edges[1::2])]


def end_runs(selected: np.ndarray, frequency: np.ndarray) -> np.ndarray:
    """``selected`` (bool per point of ``frequency``, any order) without its runs that reach
    neither end of the band: the run from the lowest frequency up and the one from the highest
    down, the bands an instrument's limit or a drifting start or end of the sweep spoils."""
    order = np.argsort(frequency)
    by_f = np.asarray(selected, bool)[order]
    out_by_f = np.zeros_like(by_f)
    for end, out in ((by_f, out_by_f), (by_f[::-1], out_by_f[::-1])):
        n = int(np.argmin(end)) if not end.all() else end.size
        out[:n] = True
    out = np.empty_like(out_by_f)
    out[order] = out_by_f
    return out


def end_islands_masked(masked: np.ndarray, frequency: np.ndarray) -> np.ndarray:
    """``masked`` (bool per point of ``frequency``, any order) with the kept points at either end of
    the band masked too when they are at most `END_ISLAND_MAX` and the masked run next to them
    holds more points than they do (a lone flagged point next to a kept end point is no run)."""
    order = np.argsort(frequency)
    by_f = np.asarray(masked, bool)[order]  # (copied by the fancy index)
    for end in (by_f, by_f[::-1]):  # the low end, then the high end (a view: writes reach by_f)
        if not end.any():
            break
        island = int(np.argmax(end))  # kept points before the first masked one
        run = int(np.argmin(end[island:])) if not end[island:].all() else end.size - island
        if 0 < island <= END_ISLAND_MAX and run > island:
            end[:island] = True
    out = np.empty_like(by_f)
    out[order] = by_f
    return out


def _fit_proposals(base: FitResult, spectrum: xr.Dataset, ctx: BaselineContext, proposals: list[tuple[Effect, Proposal]], shape: SolverShape | None, *, n_starts: int, max_steps: int, seed: int, say=None) -> tuple[list[tuple[Effect, Proposal]], list[FitResult], SolverShape]:
    """The baseline (refitted from its own values) and every proposal, fitted together; the
    proposals with those `_series_resistance_dropped` adds, and their fits after the
    baseline's; and the solver shape used (``shape`` when it holds them). ``say``: told as each
    further solve begins (stalled candidates, each rung of further starts for the poor leaders,
    the pruned circuits; `diagnose`'s progress: a step was silent 30 s on a loaded machine).
    Every fit keeps ``base``'s fixed values and the user's bounds (`FitResult.bounds`) of the
    parameters it has."""
    fixed = {k: v for k, v in base.values.items() if base.fixed[k]}
    circuits = [base.circuit] + [p.circuit for _, p in proposals]
    inits = [[dict(base.values), ctx.start()]] + [list(p.starts) for _, p in proposals]
    n_freq = spectrum.sizes["frequency"]
    shape = (shape or solver_shape(circuits, base.registry, n_freq)).grown_to(circuits, base.registry, n_freq)
    options = dict(fixed=fixed or None, bounds=dict(base.bounds) or None, weighting=base.weighting, n_starts=n_starts, seed=seed, registry=base.registry, shape=shape, max_steps=BASELINE_STEPS, step_limit=max_steps)
    try:
        fits = fit_candidates(circuits, spectrum, init=inits, **options)
        restarted = []  # (the stalled candidates and starts refitted: the same again would tie their fits, kept or beaten since)

        def restart_stalled():
            stalled = _stalled_behind_nested(proposals, fits[1:])
            if stalled and stalled != restarted:
                restarted[:] = stalled
                if say is not None:
                    say(f"refitting {counted(len(stalled), 'candidate')} stalled short of a candidate nested in them, from that one's optimum")
                redo = fit_candidates([proposals[i][1].circuit for i, _ in stalled], spectrum, init=[[start] for _, start in stalled], **options)
                for (i, _), again in zip(stalled, redo):
                    if again.chi2 < fits[1 + i].chi2:
                        fits[1 + i] = again

        restart_stalled()
        freq, z = np.asarray(spectrum["frequency"].values, float), np.asarray(spectrum["Z"].values, complex)
        target = float(climb_target(freq, z[None])[0])
        for rung, starts in enumerate(LEADER_STARTS):
            poor = _poor_leaders(proposals, fits[1:], target, fits[0])
            if not poor:
                break
            if say is not None:
                say(f"refitting {counted(len(poor), 'leading candidate')} whose {'fit is' if len(poor) == 1 else 'fits are'} still poor, from {starts} further starts each")
            redo = fit_candidates([proposals[i][1].circuit for i in poor], spectrum, init=[[dict(fits[1 + i].values)] for i in poor], **{**options, "n_starts": starts, "seed": seed + 7919 * rung, "step_limit": None})
            for i, again in zip(poor, redo):
                if again.chi2 < fits[1 + i].chi2:
                    fits[1 + i] = again
        restart_stalled()  # a leader refitted past a candidate that contains it
        pruned = (_series_resistance_dropped(base, proposals, fits[1:]) + _series_element_vanished(base, proposals, fits[1:])
                  + _negligible_branch_dropped(base, proposals, fits[1:]) + _open_resistor_dropped(base, proposals, fits[1:]))
        added = []
        if pruned:  # a pruned circuit already among the proposals keeps the better of its two fits
            if say is not None:
                say(f"fitting {counted(len(pruned), 'candidate')} without what {'its fit' if len(pruned) == 1 else 'their fits'} made negligible (a resistance at zero, an idle branch, a resistor run open)")
            index = {str(p.circuit): i for i, (_, p) in enumerate(proposals)}
            for (effect, p), cf in zip(pruned, fit_candidates([p.circuit for _, p in pruned], spectrum, init=[list(p.starts) for _, p in pruned], **options)):
                i = index.get(str(p.circuit))
                if i is None:
                    added.append((effect, p))
                    fits.append(cf)
                elif cf.chi2 < fits[1 + i].chi2:
                    fits[1 + i] = cf
        return proposals + added, fits, shape
    except FitError as err:
        raise FitError(f"diagnosis: the candidate fits failed: {err}") from None


def _drt_circuit_fit(base: FitResult, spectrum: xr.Dataset, sigma_rel: np.ndarray, suggestions: Sequence[Suggestion], drts: DRTMemo, *, seed: int) -> DRTCircuit | None:
    """The data's DRT's starting circuit (`DRTResult.suggested_circuit`, the one ``impedax drt``
    prints), fitted from the DRT's values on the diagnosis' points with the baseline's
    weighting, when it is better than the best suggestion (``suggestions[0]``, fitted to
    convergence from its values: a candidate's fit stops at `CANDIDATE_STEPS`) by the rules
    that make a suggestion significant, over the noise-weighted residuals (`DRTCircuit`): ΔAIC
    lower by more than `DELTA_AIC_MIN` and `NOISE_FRACTION_MIN` of the noise variance
    explained, or a lower AIC with fewer parameters; with every parameter determined, and a
    circuit of its own (not the baseline's nor a suggestion's, `Circuit.structure_key`). Else
    None, as when the DRT cannot be computed, says its fixed λ over-smooths or doubts the data's
    sign.

    A suggestion is one change to the user's circuit (an effect, or a pair); the DRT reads a
    circuit off the data at once. On REAL exampleData.csv, from R0 + R1 ∥ C1, the best
    suggestion adds R_relax ∥ CPE_relax and L_lead (rms_rel 2.65 %, 7 parameters) where
    `impedax drt` read R0 + L1 + R1 ∥ CPE1 + W1 (2.57 %, 6): C1 → CPE1, a Warburg and the lead
    at once, no one change."""
    try:
        data_drt = drts((base.frequency, base.z_data))
        if data_drt.over_smoothed or data_drt.sign_hint:
            return None
        start = data_drt.suggested_circuit()
        circuit = parse(start.model, base.registry)
        own = {f.circuit.structure_key(base.registry) for f in [base] + [s.fit for s in suggestions]}
        if circuit.structure_key(base.registry) in own or len(circuit.parameter_names(base.registry)) >= base.n_points:
            return None
        found = drts.circuit_fit((base.frequency, base.z_data), start.model, base.weighting,
                                 lambda: fit(circuit, spectrum, init=dict(start.init), weighting=base.weighting, registry=base.registry, n_starts=1, seed=seed, progress=False))
    except DRT_FAILURES:  # (no DRT, no circuit from it, or a fit that failed: nothing to compare)
        return None
    base_aic = noise_weighted_criteria(base, sigma_rel)[0]

    def against(other: FitResult) -> tuple[float, float, bool, bool]:  # (ΔAIC of each, better by fit, better by parameters)
        aic, other_aic = noise_weighted_criteria(found, sigma_rel)[0], noise_weighted_criteria(other, sigma_rel)[0]
        drop = (_noise_weighted_mean_square(other, sigma_rel) - _noise_weighted_mean_square(found, sigma_rel)) / 2
        by_fit = bool(aic < other_aic - DELTA_AIC_MIN and drop >= NOISE_FRACTION_MIN)
        return aic - base_aic, other_aic - base_aic, by_fit, bool(aic < other_aic and found.n_params < other.n_params)

    best = suggestions[0].fit
    if not np.isfinite(found.chi2) or not any(against(best)[2:]) or undetermined_parameters(found):
        return None
    fixed = {k: v for k, v in best.values.items() if best.fixed[k]} or None
    try:
        polished = fit(best.circuit, spectrum, init=best, fixed=fixed, bounds=dict(best.bounds) or None, weighting=best.weighting, registry=best.registry, n_starts=1, seed=seed, progress=False)
    except ImpedaxError:
        return None
    compared = polished if polished.chi2 < best.chi2 else best
    delta, compared_delta, by_fit, by_parameters = against(compared)
    return DRTCircuit(found, compared, delta, compared_delta, by_fit) if by_fit or by_parameters else None


def _baseline_checked(base: FitResult, spectrum: xr.Dataset, shape: SolverShape, named: FitResult, *, seed: int) -> FitResult | None:
    """The baseline refitted from its optimum, from the values of the candidate about to be
    named (``named``: its parameters the baseline has, the baseline's for the rest) and from
    `BASELINE_CHECK_STARTS` random starts (the candidates' compiled solver), when that finds
    a better optimum; else None.

    The baseline's own starts can all miss its global optimum while a candidate that contains
    it, from other starts, finds it under other names: on a SYNTHETIC 9-element ladder (the
    correct model, 1 % noise growing toward low frequency) the baseline stopped at 2.84 %,
    `impedax fit` of the same circuit reaches 1.93 %, and "C3 → CPE3" reached 1.93 % with its
    two arcs swapped — a false alarm. The named candidate's values start it too: the random
    starts can miss the basin the candidate found (a SYNTHETIC correct 9-element ladder at
    0.3 % noise: the baseline at 0.556 % after the random starts, "C3 → CPE3" at 0.511 %,
    the baseline from the candidate's values 0.511 %). Run only when a missing effect would
    be named."""
    fixed = {k: v for k, v in base.values.items() if base.fixed[k]}
    again = fit_candidates([base.circuit], spectrum, init=[[dict(base.values)] + _starts_from(base, named)], fixed=fixed or None, bounds=dict(base.bounds) or None, weighting=base.weighting, n_starts=BASELINE_CHECK_STARTS, seed=seed, registry=base.registry, shape=shape, max_steps=BASELINE_STEPS)[0]
    return again if np.isfinite(again.chi2) and again.chi2 < base.chi2 * (1 - 1e-6) else None


ARC_ORDERS_MAX = 24
"""At most this many assignments of a candidate's arcs to the baseline's (`_starts_from`)."""


def _arcs(fit: FitResult) -> list[tuple[str, str, str | None]]:
    """The arcs R ∥ C and R ∥ CPE in the top series chain of ``fit``'s circuit: per arc the
    names of its resistance, its capacitance (C, or CPE Q) and its CPE exponent (None for C)."""
    out = []
    for block in fit.circuit.children if isinstance(fit.circuit, Series) else (fit.circuit,):
        if not (isinstance(block, Parallel) and len(block.children) == 2 and all(isinstance(c, Element) for c in block.children)):
            continue
        by_symbol = {fit.registry[c.symbol].symbol: c.name for c in block.children}
        if set(by_symbol) == {"R", "C"}:
            out.append((by_symbol["R"], by_symbol["C"], None))
        elif set(by_symbol) == {"R", "CPE"}:
            out.append((by_symbol["R"], f"{by_symbol['CPE']}.Q", f"{by_symbol['CPE']}.alpha"))
    return out


def _starts_from(base: FitResult, named: FitResult) -> list[dict[str, float]]:
    """Starts for the baseline from the named candidate: its values where the baseline has the
    parameter (the baseline's for the rest), then the same with the candidate's arcs given to
    the baseline's arcs in every other order (up to `ARC_ORDERS_MAX`), each arc keeping its
    resistance R and time constant τ (τ = R·C, or τ^α = R·Q for R ∥ CPE, Z = R/(1 + R·Q·(jω)^α);
    `r_cpe_tau`). A candidate that turns C3 into CPE3 can fit as the baseline would with its
    arcs in another order (the generating R1 ∥ CPE1 fitted by R3 ∥ CPE3): the baseline reaches
    that optimum only with its arcs exchanged."""
    shared = {k: float(named.values.get(k, v)) for k, v in base.values.items()}
    mine, theirs = _arcs(base), _arcs(named)
    if len(mine) < 2 or len(mine) != len(theirs):
        return [shared]
    arcs = []
    for r, c, a in theirs:
        r_value, alpha = float(named.values[r]), 1.0 if a is None else float(named.values[a])
        arcs.append((r_value, r_cpe_tau(r_value, float(named.values[c]), alpha), alpha))
    out = [shared]
    for order in itertools.islice(itertools.permutations(range(len(arcs))), 1, ARC_ORDERS_MAX + 1):
        start = dict(shared)
        for (r, c, a), j in zip(mine, order):
            r_value, tau, alpha = arcs[j]
            alpha = alpha if a is not None else 1.0
            start[r], start[c] = r_value, tau**alpha / r_value
            if a is not None:
                start[a] = alpha
        if all(math.isfinite(v) for v in start.values()):
            out.append(start)
    return out


def _series_resistance_dropped(base: FitResult, proposals: list[tuple[Effect, Proposal]], fits: Sequence[FitResult]) -> list[tuple[Effect, Proposal]]:
    """For each candidate that lowers AIC by more than `DELTA_AIC_MIN` but leaves its series
    resistance (a resistor in series with the whole circuit) undetermined — fallen to zero
    (at its bound 0, or below its own standard error), or traded against the resistance of
    an arc whose top lies beyond the band (`undetermined_parameters`) — the same candidate
    without that resistor, warm-started from the candidate's optimum.

    When the spectrum's high-frequency end does not reach the series-resistance plateau, an
    added arc or diffusion element can take over the little resistance left there; the series
    R is then below what the data resolve and leaves every otherwise good candidate
    undetermined, so none is proposed (test_data.txt: R ∥ CPE stays at 6.1 % while
    R ∥ CPE + R ∥ CPE without R0 reaches 0.58 % with every parameter determined). An arc
    above the band leaves only R0 + R_relax determined (SYNTHETIC R0 + R1 ∥ C1 + R2 ∥ C2
    with τ₂ = 0.6 µs over 0.1 Hz–100 kHz: R0 = 13.9 ± 6.4 Ω at |correlation| > 0.99 with
    R_relax; without R0, 0.736 % against 0.723 %, every parameter determined). Dropping
    it is the parsimonious model the data support; the suggestion says so. Under a
    capacitance across the whole circuit (two parallel branches) the resistors in series
    with the other branch count as well: C_stray shunts them at the top of the band
    (`_series_with_all`). The pruned circuit may already be a proposal (the stray capacitance
    proposes one); `_fit_proposals` then keeps the better of the two fits."""
    out, seen = [], {str(base.circuit)}
    for effect, p, cf, top, undetermined in _significant_with_series(base, proposals, fits):
        for node in top:
            name = node.name if isinstance(node, Element) else None
            if name is None or cf.registry[node.symbol].symbol != "R" or name not in undetermined or cf.fixed.get(name, False):
                continue
            value, error = float(cf.values[name]), float(cf.linearised_stderr[name])
            why = "the data do not reach a series-resistance plateau" if isinstance(p.circuit, Series) else "the capacitance across the circuit shunts it at the top of the band"
            fell = name in cf.at_bound or (math.isfinite(error) and value <= error)  # (at 0, or within its standard error of it)
            if name in cf.at_bound or (math.isfinite(error) and value <= FELL_SHARE_OF_ERROR * error):
                how = f"it fell to {format_quantity(value, 'Ω')}"
            elif fell:  # (within its error of 0 but not near it: "fell to 72.1 Ω" (± 481 Ω) read oddly on a real ZPlot file)
                how = f"it is {format_quantity(value, 'Ω')} ± {format_quantity(error, 'Ω')}, not told from 0"
            elif math.isfinite(error):
                how = f"it is {format_quantity(value, 'Ω')} ± {format_quantity(error, 'Ω')}, traded against the other resistances"
            else:
                how = f"it is {format_quantity(value, 'Ω')} with no finite standard error, traded against the other resistances"
            left = _left_out(effect, p, cf, node, f"{how}: {why}", fell)
            if str(left[1].circuit) not in seen:
                seen.add(str(left[1].circuit))
                out.append(left)
            break
    return out


def _significant_with_series(base: FitResult, proposals: list[tuple[Effect, Proposal]], fits: Sequence[FitResult]):
    """(effect, proposal, its fit, the elements in series with the whole circuit
    (`_series_with_all`), the fit's undetermined parameters) of each candidate with at least two
    such elements that lowers AIC by more than `DELTA_AIC_MIN`: the candidates whose series
    elements `_series_resistance_dropped` and `_series_element_vanished` look at."""
    for (effect, p), cf in zip(proposals, fits):
        top = _series_with_all(p.circuit)
        if len(top) >= 2 and np.isfinite(cf.chi2) and cf.aic < base.aic - DELTA_AIC_MIN:
            yield effect, p, cf, top, undetermined_parameters(cf)


VANISHING_SYMBOLS = ("W", "L")
"""Elements of one parameter whose impedance goes to 0 with it (a Warburg's σ, an inductance):
in series with the whole circuit, such an element of the user's that falls to 0 in a candidate
is no longer needed there (`_series_element_vanished`)."""


def _series_element_vanished(base: FitResult, proposals: list[tuple[Effect, Proposal]], fits: Sequence[FitResult]) -> list[tuple[Effect, Proposal]]:
    """For each candidate that lowers AIC by more than `DELTA_AIC_MIN` but leaves undetermined
    the one parameter of a baseline element of `VANISHING_SYMBOLS` in series with the whole
    circuit, fallen to zero (at its bound, or within its standard error of 0), the same
    candidate without that element, warm-started from the candidate's optimum: the added
    element took over what it stood for. A SYNTHETIC Randles spectrum (R0 + (R1 + W) ∥ C1,
    σ = 30 Ω s^-½, 0.5 % noise) fitted as R0 + R1 ∥ C1 + W1: the candidate with a Warburg in
    R1's branch lowers AIC by 70 while W1.sigma falls to 0.09 ± 3.87; set aside as "the
    data do not determine W1.sigma", it would leave the verdict ADEQUATE."""
    out, seen = [], {str(base.circuit)}
    baseline = set(base.circuit.element_names)
    for effect, p, cf, top, undetermined in _significant_with_series(base, proposals, fits):
        for node in top:
            if not isinstance(node, Element) or cf.registry[node.symbol].symbol not in VANISHING_SYMBOLS or node.name not in baseline:
                continue
            (name,) = cf.registry[node.symbol].parameter_names(node.name)
            if name not in undetermined or cf.fixed.get(name, False):
                continue
            value, error = float(cf.values[name]), float(cf.linearised_stderr[name])
            if not (name in cf.at_bound or (math.isfinite(error) and value <= error)):
                continue
            unit = cf.circuit.parameter_specs(cf.registry)[name].unit
            how = f"it fell to {format_quantity(value, unit_text(unit))}" + (f" ± {format_quantity(error, unit_text(unit))}" if math.isfinite(error) else "")
            left = _left_out(effect, p, cf, node, f"{how}: {p.added} took over what it stood for", fell=True)
            if str(left[1].circuit) not in seen:
                seen.add(str(left[1].circuit))
                out.append(left)
    return out


FELL_SHARE_OF_ERROR = 0.1
"""A series resistance left out of a candidate "fell to" its value when at its bound 0 or below
this share of its standard error (251 µΩ ± 19.6 Ω: the log transform approaching 0); within its
error but above that share (72.1 Ω ± 481 Ω) it is "not told from 0"."""


def _series_with_all(circuit: Circuit) -> tuple[Circuit, ...]:
    """The elements in series with the whole circuit (the top series), or, for a circuit of
    two parallel branches (a capacitance across a circuit), those of its series branch."""
    if isinstance(circuit, Series):
        return circuit.children
    if isinstance(circuit, Parallel) and len(circuit.children) == 2:
        branches = [c for c in circuit.children if isinstance(c, Series)]
        if len(branches) == 1:
            return branches[0].children
    return ()


def _left_out(effect: Effect, p: Proposal, cf: FitResult, element: Element, why: str, fell: bool = False) -> tuple[Effect, Proposal]:
    """Proposal ``p`` without ``element``, warm-started from its fit ``cf`` less that element's
    parameters, saying why it was left out; ``fell``: it fell to zero in ``cf`` (a series
    resistance; not a branch that carries no current: without it, the block's other element
    stands for something else, R_sc ∥ C_sc's R_sc for the series R_f)."""
    gone = set(cf.registry[element.symbol].parameter_names(element.name))
    starts = ({k: float(x) for k, x in cf.values.items() if k not in gone},)
    vanished = p.vanished + ((element.name,) if fell else ())
    return effect, Proposal(p.effect, p.circuit.without(element.name), p.added, f"{p.where}, and {element.name} left out ({why})", starts, removed=p.removed + (element.name,), band=p.band, vanished=vanished,
                            expected=p.expected, evidence=p.evidence)


def _resistor_capacitor_blocks(circuit: Circuit, registry: Registry):
    """(resistor, capacitive element) of every parallel block of exactly a resistor and a C or CPE."""
    if isinstance(circuit, Element):
        return
    if isinstance(circuit, Parallel) and len(circuit.children) == 2 and all(isinstance(c, Element) for c in circuit.children):
        kinds = {registry[c.symbol].symbol: c for c in circuit.children}
        cap = kinds.get("C") or kinds.get("CPE")
        if "R" in kinds and cap is not None:
            yield kinds["R"], cap
        return
    for child in circuit.children:
        yield from _resistor_capacitor_blocks(child, registry)


def _significant_but_undetermined(base: FitResult, proposals: list[tuple[Effect, Proposal]], fits: Sequence[FitResult]):
    """(effect, proposal, fit, undetermined parameters) of each candidate that lowers AIC by
    more than `DELTA_AIC_MIN` against ``base`` but leaves parameters undetermined."""
    for (effect, p), cf in zip(proposals, fits):
        if np.isfinite(cf.chi2) and cf.aic < base.aic - DELTA_AIC_MIN:
            undetermined = undetermined_parameters(cf)
            if undetermined:
                yield effect, p, cf, undetermined


def _negligible_branch_dropped(base: FitResult, proposals: list[tuple[Effect, Proposal]], fits: Sequence[FitResult]) -> list[tuple[Effect, Proposal]]:
    """For each candidate that lowers AIC by more than `DELTA_AIC_MIN` but leaves a parameter
    of a baseline block R ∥ C (or R ∥ CPE) undetermined because one branch carries next to no
    current — |Y_C|/|Y_R| = ω·R·C (R·Q·ω^α) below `BRANCH_NEGLIGIBLE` over the whole band (the
    block is a plain resistance) or above its inverse (a plain capacitance) — the same
    candidate without that branch, warm-started from the candidate's optimum.

    A baseline can turn an arc into a resistance: on a spectrum of C_i + R_f + R_sc ∥ CPE_sc,
    C_i + R_sc ∥ C_sc fits with C_sc → 0 and R_sc ≈ R_f. An added R ∥ CPE then fits to the
    noise, but with C_sc undetermined it is never proposed, and the diagnosis ended `adequate`
    at 22× the noise; without C_sc every parameter is determined."""
    out, seen = [], {str(p.circuit) for _, p in proposals} | {str(base.circuit)}
    baseline = set(base.circuit.element_names)
    for effect, p, cf, undetermined in _significant_but_undetermined(base, proposals, fits):
        omega = 2 * np.pi * np.asarray(cf.frequency, float)
        for r, cap in _resistor_capacitor_blocks(p.circuit, cf.registry):
            names = {r.name, *cf.registry[cap.symbol].parameter_names(cap.name)}
            if not ({r.name, cap.name} <= baseline and names & undetermined) or any(cf.fixed.get(n, False) for n in names):
                continue
            v = cf.values
            with np.errstate(over="ignore"):  # (an open resistor of 1e255 Ω: an infinite ratio, no plain resistance)
                ratio = omega * v[r.name] * v[cap.name] if cap.name in v else v[r.name] * v[f"{cap.name}.Q"] * omega ** v[f"{cap.name}.alpha"]
            if float(np.max(ratio)) < BRANCH_NEGLIGIBLE:
                drop, why = cap, f"{r.name} ∥ {cap.name} acts as a plain resistance: the capacitive branch carries at most {float(np.max(ratio)):.2g}× the resistor's current over the band"
            elif float(np.min(ratio)) > 1 / BRANCH_NEGLIGIBLE:
                drop, why = r, f"{r.name} ∥ {cap.name} acts as a plain {cap.symbol}: the resistor carries at most {1 / float(np.min(ratio)):.2g}× the capacitive current over the band"
            else:
                continue
            left = _left_out(effect, p, cf, drop, why)
            if str(left[1].circuit) not in seen:
                seen.add(str(left[1].circuit))
                out.append(left)
    return out


OPEN_RESISTANCE_FACTOR = 100.0
"""A resistor a candidate adds in parallel with other branches is open when its value exceeds
this × the largest |Z| of the data: it carries under 1 % of its group's current anywhere in the
band (for R and C branches, |Z| of a group in series with others is at most the total's)."""


def _parallel_resistors(circuit: Circuit, registry: Registry):
    """(resistor, what is left without it) for every resistor that is one of three or more
    branches of a parallel node (without it the node stays a parallel group: R ∥ CPE ∥ C →
    CPE ∥ C; ``""``), or one of the two branches of a node in series with the whole circuit
    beside a C or CPE, when the rest of the circuit already blocks DC (`_blocks_dc`): R_relax ∥
    C_relax → C_relax in series (the words say so), or beside a C when it conducts (the
    open resistor is the data's word that no DC current passes; the words name
    a blocking capacitance).

    A two-branch node is reduced only there. Elsewhere leaving its resistor out takes away a DC
    path the model has: behind an arc's resistor, (R1 + C_relax) ∥ CPE1 no longer closes on
    R1; on a circuit that conducts, a series CPE, of any α, takes up other effects' misfit at
    the low end under this one's name (SYNTHETIC dev2 two/rc_cpe_w, a CPE and a Warburg
    missing from R0 + R1 ∥ C1: R0 + R1 ∥ C1 + CPE_relax, α = 0.36, was named before the
    Warburg)."""
    top = circuit.children if isinstance(circuit, Series) else ()
    for node, i in parallel_branches(circuit):
        resistor = node.children[i]
        if registry[resistor.symbol].symbol != "R":
            continue
        if len(node.children) >= 3:
            yield resistor, ""
            continue
        other = node.children[1 - i]
        blockers = [str(t) for t in top if t is not node and _blocks_dc(t, registry)]
        if not (any(t is node for t in top) and isinstance(other, Element) and registry[other.symbol].symbol in ("C", "CPE")):
            continue
        if blockers:
            yield resistor, f"; {other.name} stands alone in series, where the circuit already blocks DC ({blockers[0]})"
        elif registry[other.symbol].symbol == "C":  # (the open resistor is the data's, which show no DC path through the node)
            yield resistor, (f"; {other.name} stands alone in series: the data show no DC path through {resistor.name} ∥ {other.name} over the band, so its arc "
                             f"closes below the lowest frequency, or never (a blocking capacitance: an insulating layer, a coating, a blocking electrode)")


def _blocks_dc(circuit: Circuit, registry: Registry) -> bool:
    """Does no DC current pass (|Z| → ∞ as ω → 0): an element whose spec says `DCPath.BLOCKS`
    (C, CPE, W, Wo), a series chain with one, a parallel node all of whose branches block?"""
    if isinstance(circuit, Element):
        return registry[circuit.symbol].dc_path is DCPath.BLOCKS
    if isinstance(circuit, Series):
        return any(_blocks_dc(c, registry) for c in circuit.children)
    return all(_blocks_dc(c, registry) for c in circuit.children)


def _open_resistor_dropped(base: FitResult, proposals: list[tuple[Effect, Proposal]], fits: Sequence[FitResult]) -> list[tuple[Effect, Proposal]]:
    """For each candidate that lowers AIC by more than `DELTA_AIC_MIN` but leaves parameters
    undetermined because a resistor it adds in parallel with other branches
    (`_parallel_resistors`: two or more others, or a C or CPE in series with a circuit that
    blocks DC) ran open (above `OPEN_RESISTANCE_FACTOR` × the data's largest |Z|), the same
    candidate without that resistor, warm-started from the candidate's optimum.

    On a finger whose gap leaks through a nearly resistive CPE (α ≈ 0.05–0.3), the electrode
    polarization R_EP ∥ CPE_EP ∥ C_gap fits best with R_EP → 3·10¹¹ Ω, which leaves R_EP and
    CPE_EP undetermined, so it was not proposed and a series arc was named; without R_EP,
    CPE_EP ∥ C_gap fits as well with every parameter determined (SYNTHETIC dev draw). On
    AutoEIS's battery cycle 22 (REAL) with ``R0 + R1 || CPE1 + R2 || CPE2 + W1``, R_relax ∥
    C_relax at the end fits at 0.875 % with R_relax → 22 MΩ; the series C_relax it leaves
    fits as well with every parameter determined."""
    out, seen = [], {str(p.circuit) for _, p in proposals} | {str(base.circuit)}
    baseline = set(base.circuit.element_names)
    for effect, p, cf, undetermined in _significant_but_undetermined(base, proposals, fits):
        z_max = float(np.max(np.abs(cf.z_data)))
        for r, left in _parallel_resistors(p.circuit, cf.registry):
            if r.name in baseline or r.name not in undetermined or cf.fixed.get(r.name, False) or not cf.values[r.name] > OPEN_RESISTANCE_FACTOR * z_max:
                continue
            circuit = p.circuit.without(r.name)
            if str(circuit) in seen:
                continue
            seen.add(str(circuit))
            added = " + ".join(n for n in circuit.element_names if n not in baseline)
            why = f"{r.name} left out: it ran open ({format_quantity(float(cf.values[r.name]), 'Ω')}, over {OPEN_RESISTANCE_FACTOR:g}× the data's largest |Z|){left}"
            starts = ({k: float(v) for k, v in cf.values.items() if k != r.name},)
            out.append((effect, Proposal(p.effect, circuit, added, f"{p.where}, {why}", starts, removed=p.removed, band=p.band, vanished=p.vanished,
                                                 expected=p.expected, evidence=p.evidence)))
    return out


def _poor_leaders(proposals: list[tuple[Effect, Proposal]], fits: Sequence[FitResult], target: float, base: FitResult) -> list[int]:
    """Per effect (and apart, among the candidates that leave a baseline element out), the
    candidate that fits best, when its rms_rel is above ``target`` (what
    `impedax.fit` climbs its start ladder for: 1.5× the misfit of the KK test's Voigt chain,
    `starts.climb_target`), when it lowers AIC by more than `DELTA_AIC_MIN` against the
    baseline ``base`` but leaves parameters undetermined, or when it has every parameter of the
    baseline and more and still fits worse (the added element made inert gives the baseline's
    fit, so its starts stalled): it is fitted again from its optimum and random starts, first
    32 in all, then, if the effect's best is still poor, 80 (`LEADER_STARTS`, new draws each
    rung; `impedax.fit` climbs to 80), each for up to `BASELINE_STEPS` steps (a leak R_EP ∥
    CPE_EP converges slowly along its valley). A few warm starts from a baseline that absorbed the
    missing effect can stall short of where `impedax.fit` of the same model string gets (a Ws
    at the end of two R ∥ CPE arcs: 3.9 % where 1.3 % is reachable, at 1 % noise), and a more
    flexible wrong effect then wins the ranking. A stalled start often switches a branch off,
    which leaves it undetermined and the candidate not proposed at all (electrode polarization
    on a finger: 1.75 % with CPE_EP undetermined, where `impedax.fit` reaches 1.41 % with every
    parameter determined; a stray capacitance across a finger circuit: 1.78 % against the
    baseline's 1.71 %, where 1.44 % is reachable)."""
    best: dict[tuple[str, bool], int] = {}
    for i, (effect, p) in enumerate(proposals):
        key = (effect.id, bool(p.removed))
        if np.isfinite(fits[i].chi2) and (key not in best or fits[i].chi2 < fits[best[key]].chi2):
            best[key] = i

    def poor(fit: FitResult) -> bool:
        if fit.rms_rel > target:
            return True
        if fit.aic < base.aic - DELTA_AIC_MIN:
            return bool(undetermined_parameters(fit))
        return set(fit.free_names) > set(base.free_names) and fit.chi2 > base.chi2 * (1 + 1e-6)

    return [i for i in best.values() if poor(fits[i])]


def _stalled_behind_nested(proposals: list[tuple[Effect, Proposal]], fits: Sequence[FitResult]) -> list[tuple[int, dict[str, float]]]:
    """Candidates that fit worse than a candidate of the same effect whose free parameters are
    a strict subset of theirs, each with a start at that candidate's optimum (plus its own
    first start for the parameters it adds).

    A model that contains another reaches at least the other's fit at its optimum (the added
    branch can be made inert), so fitting worse means its starts stalled, usually with the
    added branch switched off (R_EP → ∞ beside a CPE). R_EP ∥ CPE_EP ∥ C_gap stalled at the
    baseline's 30 % while R_EP ∥ C_gap reached 2.6 % on a finger spectrum."""
    names = [frozenset(f.free_names) for f in fits]
    out = []
    for i, (effect, proposal) in enumerate(proposals):
        if not np.isfinite(fits[i].chi2):
            continue
        nested = [j for j, (other, _) in enumerate(proposals) if j != i and other.id == effect.id and names[j] < names[i] and fits[j].chi2 < fits[i].chi2 * (1 - 1e-6)]
        if nested:
            j = min(nested, key=lambda j: fits[j].chi2)
            own = dict(proposal.starts[0]) if proposal.starts else {}
            out.append((i, {**own, **{k: float(fits[j].values[k]) for k in fits[j].free_names}}))
    return out


def noise_weighted_criteria(fit: FitResult, sigma_rel: np.ndarray) -> tuple[float, float]:
    """AIC and BIC (`statistics.information_criteria`) of ``fit`` over its relative residuals
    divided by the noise model's σ_k (per frequency and component): every point counts by what
    the data allow there, whatever weighting the fit used."""
    r = fit.residuals / sigma_rel
    return information_criteria(float(np.sum(r.real**2 + r.imag**2)), 2 * r.size, fit.n_params)


def _noise_weighted_mean_square(fit: FitResult, sigma_rel: np.ndarray) -> float:
    """mean |r_k|²/σ_k² of ``fit``'s relative residuals over the noise model's σ_k: 2 (two
    components) where the residuals are noise, so a fall of 2 is one noise variance. Points
    whose σ_k is NaN (not covered by the noise model) are left out."""
    return float(np.nanmean(np.abs(fit.residuals / sigma_rel) ** 2))


def noise_variance_explained(before: FitResult, after: FitResult, diagnosis: "Diagnosis") -> float:
    """How much of the noise variance ``after`` explains beyond ``before``: the fall of
    mean |r_k|²/σ_k² over 2 (`_noise_weighted_mean_square`), σ_k the noise model of
    ``diagnosis`` taken at each fit's frequencies (fits of the same data, possibly with points
    masked). The second significance rule (`NOISE_FRACTION_MIN`) holds it against 0.25."""
    sigma_of = dict(zip(np.asarray(diagnosis.baseline.frequency, float).tolist(), np.asarray(diagnosis.noise, float)))

    def mean_square(fit):
        return _noise_weighted_mean_square(fit, np.array([sigma_of.get(f, np.nan) for f in np.asarray(fit.frequency, float).tolist()]))

    return (mean_square(before) - mean_square(after)) / 2


def _suggestions(base: FitResult, proposals: list[tuple[Effect, Proposal]], fits: Sequence[FitResult], sigma_rel: np.ndarray, bands: Sequence[FailingBand], evidence: PeakEvidence | None = None) -> list[Suggestion]:
    """A `Suggestion` per candidate with a finite fit: ΔAIC and ΔBIC over the noise-weighted
    residuals (`noise_weighted_criteria`), the bands it fixes, its new undetermined parameters,
    a plausibility warning (`Effect.plausible`) and significance (the thresholds, determined,
    plausible, converged). A candidate's placement names the data's DRT peak (``evidence``: the
    baseline's `PeakEvidence`) its fitted arc stands for, if any (`effects.cited_where`)."""
    base_ms = _noise_weighted_mean_square(base, sigma_rel)
    base_undetermined = undetermined_parameters(base)
    base_aic, base_bic = noise_weighted_criteria(base, sigma_rel)
    out = []
    for (effect, p), cf in zip(proposals, fits):
        if not np.isfinite(cf.chi2):
            continue
        aic, bic = noise_weighted_criteria(cf, sigma_rel)
        d_aic, d_bic = aic - base_aic, bic - base_bic
        drop = (base_ms - _noise_weighted_mean_square(cf, sigma_rel)) / 2
        opened = _opened(cf, base)
        undetermined = tuple(sorted((undetermined_parameters(cf) | opened) - base_undetermined))
        warning = None
        if undetermined:
            warning = "the data do not determine " + ", ".join(undetermined) + f" ({UNDETERMINED_RULE}"
            warning += "".join(f"; {n} ran open, {format_quantity(float(cf.values[n]), 'Ω')}" for n in sorted(opened)) + ")"
        elif effect.plausible is not None:
            warning = effect.plausible(cf.values, p)
        significant = bool(d_aic < -DELTA_AIC_MIN and drop >= NOISE_FRACTION_MIN and warning is None)
        after = failing_bands(cf, sigma_rel)
        fixed_bands = tuple((b.f_min, b.f_max) for b in bands if not any(a.f_min < b.f_max and a.f_max > b.f_min for a in after))
        lowered = _lowered_bands(base, cf, bands, fixed_bands)
        p = dataclasses.replace(p, where=cited_where(effect.id, p, cf.values, cf.registry, evidence, cf.frequency))
        out.append(Suggestion(effect.id, p.added, p.where, cf, d_aic, d_bic, significant, _explain(effect, p, base, cf, fixed_bands, lowered), fixed_bands, undetermined, warning, p.removed, p.vanished))
    return out


def _beyond_single_effects(bands: Sequence[FailingBand], ratio: float) -> bool:
    """Residuals structured in a band the data do not explain and above `NOISE_RATIO_MAX` × the
    noise: what an ``adequate`` verdict calls "beyond the catalog"."""
    return any(not b.data_problem for b in bands) and ratio > NOISE_RATIO_MAX


def _paired(first: Effect, p1: Proposal, second: Effect, p2: Proposal) -> tuple[Effect, Proposal]:
    """The effect ``second`` proposed (as ``p2``) on top of the candidate ``p1`` of ``first``, as
    one candidate of both: id ``first+second``, plausible when both effects find their own
    added elements plausible."""

    def plausible(values, _):
        for effect, p in ((first, p1), (second, p2)):
            why = effect.plausible(values, p) if effect.plausible is not None else None
            if why is not None:
                return why
        return None

    effect = Effect(
        f"{first.id}+{second.id}", f"{first.title} and {second.title}", f"{first.physics}; and {second.physics}",
        f"{first.signature}; and {second.signature}", f"{first.change}, and {second.change}", lambda circuit, ctx: [], plausible,
    )
    where = f"{p1.added} {p1.where}, and {p2.added} {p2.where}"
    band = (min(p1.band[0], p2.band[0]), max(p1.band[1], p2.band[1]))
    return effect, Proposal(effect.id, p2.circuit, f"{p1.added} and {p2.added}", where, p2.starts, p1.removed + p2.removed, band, p1.vanished + p2.vanished,
                            expected={**p1.expected, **p2.expected}, evidence=p1.evidence or p2.evidence)


def _effect_pairs(base: FitResult, cands: Sequence[Suggestion], proposals: list[tuple[Effect, Proposal]], spectrum: xr.Dataset, effects: EffectCatalog, shape: SolverShape, *, with_drt: bool, drts: DRTMemo, max_params: int, n_starts: int, max_steps: int, seed: int, say=None) -> tuple[list[tuple[Effect, Proposal]], list[FitResult], SolverShape]:
    """Candidates of two effects: each of the best `PAIR_SEEDS` candidates that lower AIC by
    more than `DELTA_AIC_MIN` but leave parameters undetermined, with every effect of the
    catalog proposed on top of its fit (its own context: values, misfit and DRT evidence),
    fitted as `_fit_proposals` fits the first ones (``say``: told as each seed's pairs begin).
    Returns the new proposals (`_paired`), their fits and the solver shape.

    A single effect can be undetermined because a second one is missing as well: on AutoEIS's
    battery cycle 0 with ``R0 + R1 || CPE1`` (23.6× the noise), a second arc leaves its R
    undetermined because the low-frequency arc does not close within the band, and a Warburg
    alone cannot make the second arc; every single candidate was undetermined and the
    verdict was ``adequate``."""
    by_circuit = {str(p.circuit): (e, p) for e, p in proposals}
    seen = set(by_circuit) | {str(base.circuit)}
    seeds = sorted((s for s in cands if s.undetermined and s.delta_aic < -DELTA_AIC_MIN and str(s.fit.circuit) in by_circuit), key=lambda s: s.delta_aic)[:PAIR_SEEDS]
    out: list[tuple[Effect, Proposal]] = []
    fits: list[FitResult] = []
    for k, s in enumerate(seeds, 1):
        first, p1 = by_circuit[str(s.fit.circuit)]
        if say is not None:
            say(f"pairs on top of {s.fit.model} ({first.id}; {k} of {len(seeds)})")
        ctx = _context(s.fit, _drt_evidence(s.fit, [], drts) if with_drt else None)
        pairs = []
        for second, p2 in effects.proposals(ctx):
            key = str(p2.circuit)
            if key not in seen and len(p2.circuit.parameter_names(base.registry)) <= max_params:
                seen.add(key)
                pairs.append(_paired(first, p1, second, p2))
        if pairs:
            if say is not None:
                say(f"fitting {len(pairs)} pairs on {s.fit.model}")
            pairs, pair_fits, shape = _fit_proposals(s.fit, spectrum, ctx, pairs, shape, n_starts=n_starts, max_steps=max_steps, seed=seed, say=say)
            out += pairs
            fits += pair_fits[1:]
    return out, fits, shape


def _inductive_top(base: FitResult, sigma_rel: np.ndarray) -> int:
    """How many points, counted down from the highest frequency, are inductive beyond the noise
    and beyond the model: Z''_data > `INDUCTIVE_TOP_SIGMA` σ_k |Z| and Z''_data − Z''_model too."""
    order = np.argsort(base.frequency)[::-1]
    zd, zm = base.z_data[order], base.z_model[order]
    margin = INDUCTIVE_TOP_SIGMA * np.broadcast_to(np.asarray(sigma_rel, float), base.frequency.shape)[order] * np.abs(zd)
    up = (zd.imag > margin) & (zd.imag - zm.imag > margin)
    return up.size if up.all() else int(np.argmin(up))


def _lead_behind(base: FitResult, cands: Sequence[Suggestion], proposals: list[tuple[Effect, Proposal]], spectrum: xr.Dataset, effects: EffectCatalog, shape: SolverShape, sigma_rel: np.ndarray, bands: Sequence[FailingBand], *, with_drt: bool, drts: DRTMemo, max_params: int, n_starts: int, max_steps: int, seed: int, say=lambda text: None) -> tuple[list[tuple[Effect, Proposal]], list[FitResult], SolverShape]:
    """A lead inductance hidden behind the effect named first: when the data's top is inductive
    (`_inductive_top`) and the best significant suggestion holds no ``series_inductance``,
    ``series_inductance`` on top of it (a pair, `_paired`), kept when it is significant
    against that suggestion by the usual rules (ΔAIC, noise variance explained, determined,
    plausible). A lone L cannot help while the model also lacks a high-frequency arc: on
    VersaStudio's REAL spectrum with ``R0 + R1 || CPE1`` (+4.7° at 100 kHz, a ~10 Ω arc at
    20–50 kHz the baseline does not make) L_lead alone lowers rms_rel 6.65 → 6.64 % and is
    undetermined; behind the nested R ∥ CPE it is 14 µH, determined, and lowers AIC by 75. Where
    it helps alone but far less than the effect named first, the pair says both are missing: on
    exampleData.csv (REAL) from ``R0 + R1 || C1``, L_lead alone −25.8 in AIC (8th), the arc
    −159.8 at 12.6 %, both −528.0 at 2.65 % (docs/diagnosis.md, section 5)."""
    best = next((s for s in cands if s.significant), None)
    if "series_inductance" not in effects.ids() or best is None or "series_inductance" in best.effect.split("+"):
        return [], [], shape
    by_circuit = {str(p.circuit): (e, p) for e, p in proposals}
    if str(best.fit.circuit) not in by_circuit or _inductive_top(base, sigma_rel) < INDUCTIVE_TOP_POINTS:
        return [], [], shape
    first, p1 = by_circuit[str(best.fit.circuit)]
    ctx = _context(best.fit, _drt_evidence(best.fit, [], drts) if with_drt else None)
    seen = set(by_circuit) | {str(base.circuit)}
    pairs = [_paired(first, p1, second, p2) for second, p2 in effects.select(["series_inductance"]).proposals(ctx)
             if str(p2.circuit) not in seen and len(p2.circuit.parameter_names(base.registry)) <= max_params]
    if not pairs:
        return [], [], shape
    say(f"fitting a series inductance on top of {best.effect} (the data's top is inductive)")
    pairs, fits, shape = _fit_proposals(best.fit, spectrum, ctx, pairs, shape, n_starts=n_starts, max_steps=max_steps, seed=seed)
    against_best = _suggestions(best.fit, pairs, fits[1:], sigma_rel, bands)
    kept = [(p, f) for p, f, s in zip(pairs, fits[1:], against_best) if s.significant]
    return [p for p, _ in kept], [f for _, f in kept], shape


def verdict_scope_words(judged, left_out, not_passive=()) -> str:
    """Where a verdict was judged, when points were left out of it: `` on 2.53 kHz – 200 kHz (20
    of 72 points; the other 52 left out as not Kramers–Kronig consistent)``; empty when none
    were. ``judged``: the frequencies [Hz] the verdict rests on; ``left_out``: those left out,
    of which ``not_passive`` for Re Z < 0 (the others: the KK test's). A bare "verdict:
    ADEQUATE" after refine left out Gamry's 52 lowest points would read as a model of the whole
    spectrum, where it describes 2.53–200 kHz only."""
    judged = np.asarray(judged, float)
    if not len(left_out) or not judged.size:
        return ""
    negative = len(set(map(float, not_passive)) & set(map(float, left_out)))
    inconsistent = len(left_out) - negative
    given = [(why, n) for why, n in (("as not Kramers–Kronig consistent", inconsistent), ("for Re Z < 0, which no passive circuit gives", negative)) if n]
    why_text = f"left out {given[0][0]}" if len(given) == 1 else "left out: " + ", ".join(f"{n} {why}" for why, n in given)
    return (f" on {format_frequency(float(judged.min()))} – {format_frequency(float(judged.max()))} ({judged.size} of {judged.size + len(left_out)} points; "
            f"the other {len(left_out)} {why_text})")


def left_out_words(options) -> str:
    """``options`` (`left_out_options`) as command-line text: ``--fmax 1e6 --exclude 5.34``."""
    return " ".join(f"{flag} {value}" for flag, value in options)


def unidentified_note(fit: FitResult) -> str:
    """The note of diagnose and refine on the groups of ``fit``'s parameters the data do not
    determine separately (`FitResult.unidentified_groups`; fit's warning says the same): each
    suggestion's fit inherits the ambiguity, so the remedy, a value fixed from elsewhere (an
    insulator's datasheet capacitance: docs/physics.md), is named with the keyword that sets it
    (``fixed={'C_i': VALUE}``; the command line says ``--fix C_i=VALUE``, `cli.common._phrased`)."""
    parts = []
    for group in fit.unidentified_groups:
        remedy = " or ".join(f"fixed={{'{name}': VALUE}}" for name in group)
        if len(group) == 1:
            parts.append(f"{group[0]} is not determined by the data (Z hardly changes with it): fix it to a value known from elsewhere ({remedy})")
        else:
            parts.append(f"{', '.join(group)} are not separately determined by the data (only a combination of them changes Z): fix one of them to a value known from elsewhere, e.g. a datasheet's ({remedy})")
    return "the baseline fit: " + "; ".join(parts) + "; every candidate that keeps them inherits this"


def _fixed_words(fit: FitResult, kept=None) -> str:
    """`` --fix NAME=VALUE`` for each fixed parameter of ``fit`` (in ``kept``, when given): a
    command that applies a suggestion keeps the user's fixed values, which its fit kept."""
    return "".join(f" --fix {k}={v:.6g}" for k, v in fit.values.items() if fit.fixed[k] and (kept is None or k in kept))


def _bound_ends(fit: FitResult, kept=None) -> dict[str, tuple[str, str]]:
    """The user's bounds of ``fit``'s parameters (`FitResult.bounds`; in ``kept``, when given)
    as ``--bound`` writes them: each end as --init prints numbers (.6g), an end that is the
    element's own left empty (`cli.common.parse_bounds` puts it back); all digits where .6g
    would make the two ends meet."""
    if not fit.bounds:
        return {}
    specs = fit.circuit.parameter_specs(fit.registry)
    out = {}
    for name, (lo, hi) in fit.bounds.items():
        if kept is not None and name not in kept:
            continue
        digits = 6 if float(f"{lo:.6g}") < float(f"{hi:.6g}") else 17
        out[name] = tuple("" if end == own else f"{end:.{digits}g}" for end, own in ((lo, float(specs[name].lower)), (hi, float(specs[name].upper))))
    return out


def bound_words(fit: FitResult, kept=None) -> str:
    """`` --bound NAME=LO:HI`` for each bound of the user's on ``fit``'s parameters (in
    ``kept``, when given): a command that applies a suggestion keeps the user's bounds, which
    its fit kept (`_bound_ends`)."""
    return "".join(f" --bound {name}={lo}:{hi}" for name, (lo, hi) in _bound_ends(fit, kept).items())


def restart_words(fit: FitResult) -> str:
    """``--init``, ``--fix`` and ``--bound`` words that restart ``fit`` from its values under the
    user's constraints (`_start_words`, `_fixed_words`, `bound_words`): each start strictly inside
    its bounds, as `impedax fit` requires (refine's reproduce line, `cli.refine.reproduce_line`)."""
    return _start_words(fit) + _fixed_words(fit) + bound_words(fit)


def _start_words(fit: FitResult, kept=None) -> str:
    """``--init NAME=VALUE`` for each free parameter of ``fit`` (in ``kept``, when given), .6g.
    A value of a bounded parameter is written strictly inside the bounds `bound_words` prints
    (`impedax fit` refuses a start on a bound: `_inside_text`)."""
    specs = fit.circuit.parameter_specs(fit.registry)
    ends = _bound_ends(fit, kept)
    words = []
    for name, value in fit.values.items():
        if fit.fixed[name] or (kept is not None and name not in kept):
            continue
        text = f"{value:.6g}"
        if name in ends:
            lo, hi = (float(t) if t else float(own) for t, own in zip(ends[name], (specs[name].lower, specs[name].upper)))
            text = _inside_text(value, lo, hi)
        words.append(f"--init {name}={text}")
    return " ".join(words)


def _inside_text(value: float, lo: float, hi: float) -> str:
    """``value`` written strictly inside (lo, hi): .6g when that is inside; else (a fitted value
    on its bound, or rounded onto it) moved 1e-6 of its bound inside (of the span, for a bound 0
    or below) as `starts.values_inside` moves a start, with the fewest digits that keep it there."""
    text = f"{value:.6g}"
    if lo < float(text) < hi:
        return text
    span = hi - lo if math.isfinite(hi - lo) else 1.0
    x = min(max(value, lo), hi)
    if not x > lo:
        x = lo * (1 + 1e-6) if lo > 0 else lo + 1e-6 * span
    if not x < hi:
        x = hi * (1 - 1e-6) if hi > 0 else hi - 1e-6 * span
    for digits in (6, 9, 12):
        text = f"{x:.{digits}g}"
        if lo < float(text) < hi:
            return text
    return repr(x)


def _constraint_verdict(user_fit: FitResult, spectrum: xr.Dataset, kk: KKResult | None, ratio: float) -> tuple[Verdict, str] | None:
    """`Verdict.CONSTRAINT` and its reason when the user's binding constraints on ``user_fit``
    (fixed values, a bounds= it sits on: `constraints.binding_constraints`) explain its misfit:
    one local fit with them released, from its values or else from the data-driven guess
    (`constraints.explaining_constraints`, on
    the diagnosis' ``spectrum``, which also names only those whose release alone explains it)
    meets the fit's own rule (`constraints.constraint_explains` against the KK test's rms_rel),
    so no effect is named missing. None otherwise."""
    constraints = binding_constraints(user_fit.values, user_fit.fixed, user_fit.at_bound, user_fit.bounds)
    if not constraints:
        return None
    found = explaining_constraints(
        user_fit.circuit, spectrum, user_fit.values, user_fit.fixed, user_fit.bounds, constraints, user_fit.rms_rel, kk.rms_rel if kk is not None else math.nan,
        weighting=user_fit.weighting, registry=user_fit.registry, fit=fit,
    )
    if found is None:
        return None
    constraints, released = found
    names = ", ".join(dict.fromkeys(n for n, _, _ in constraints))
    units = {n: spec.unit for n, spec in user_fit.circuit.parameter_specs(user_fit.registry).items()}
    return Verdict.CONSTRAINT, (
        f"the residuals are {ratio:.3g}× the noise, but the misfit is a constraint you set, not a missing effect: with {constraint_words(constraints, units)} "
        f"the fit reaches rms_rel {user_fit.rms_rel * 100:.3g} %, and one local fit with {names} free reaches {released.rms_rel * 100:.3g} %; "
        f"fit with {names} free, or check the value you set."
    )


def _at_bound_lines(fit: FitResult) -> list[str]:
    """Under the "to apply" line: the suggestion's fit's own warnings on parameters at a bound
    (`FitResult.at_bound`), which its command prints when run (a suggested model's
    ``--init CPE2.alpha=1`` gets a word here as `impedax fit` warns "CPE2.alpha is at its upper
    bound 1 …"). Those of a term that vanished are said above."""
    vanished = {n for _, _, names in vanished_terms(fit) for n in names}
    names = [n for n in fit.at_bound if n not in vanished]
    return [f"     note: in this fit {w}" for w in fit.warnings if any(w.startswith(f"{n} ") for n in names)]


def _without_vanished_lines(fit: FitResult, fit_command: str) -> list[str]:
    """Under the "to apply" line: each term of the suggestion's fit that vanished (`vanishing`:
    a resistor run open, R1 = 1.19e282 Ω beside CPE1 on exampleData.csv) named, with the model
    without it, which is the same fit within what an instrument resolves, and its command from
    the same values. Nothing when no term vanished."""
    lines = []
    for branch, reduced, names in vanished_terms(fit):
        kept = set(reduced.parameter_names(fit.registry))
        starts = _start_words(fit, kept) + _fixed_words(fit, kept) + bound_words(fit, kept)
        specs = fit.circuit.parameter_specs(fit.registry)
        held = ", ".join(f"{n} = {format_quantity(fit.values[n], specs[n].unit)}{', at its bound' if n in fit.at_bound else ''}" for n in names)
        what = share_words(branch)
        lines.append(
            f"     note: {branch.element} {what} {branch.block} in this fit ({held}): its term vanished, and {reduced}, without it, "
            f"is the same fit within what an instrument resolves, with fewer parameters: {fit_command} --model '{reduced}' {starts}"
        )
    return lines


def low_ratio_words(ratio: float, sigma_rel: np.ndarray, n_points: int) -> str:
    """The note of an adequate verdict whose residuals are under `NOISE_RATIO_LOW` × the noise
    estimated: the estimate is too high (or the data are noise-free and it is the floor
    `NOISE_FLOOR`), so a misfit below it goes unjudged."""
    level = float(np.median(sigma_rel))
    if level <= NOISE_FLOOR * 1.01:
        return (f"the residuals are {ratio:.2g}× the noise floor σ = {NOISE_FLOOR * 100:g} % (the data are nearly noise-free, or the estimate found less): "
                f"the verdict does not judge misfits below it; give a lower noise level (--noise REL, noise=) for a finer judgement")
    return (f"the residuals are {ratio:.2g}× the noise estimated (σ ≈ {level * 100:.2g} %): the estimate is likely too high (on {n_points} points the Kramers–Kronig "
            f"chain it comes from adds misfit of its own where it misses the shape between points), so the verdict is lenient: a misfit below σ goes unseen; "
            f"give the instrument's noise if you know it (--noise REL, noise=)")


def untried_words(left_out: Sequence[str]) -> str:
    """How a verdict names the effects of the catalog that ``effects=`` (--effects) left out."""
    return f"{', '.join(left_out)} {'was' if len(left_out) == 1 else 'were'} not tried (effects=, --effects, left {'it' if len(left_out) == 1 else 'them'} out)"


def beyond_catalog_words(ratio: float, left_out: Sequence[str] = ()) -> str:
    """The warning of an adequate verdict `Diagnosis.beyond_catalog`: the model does not follow
    the data to their noise, and (``left_out``) which effects were not tried."""
    tried = "no effect tried" if left_out else "no effect of the catalog"
    return (f"adequate only within {'the effects tried' if left_out else 'the catalog'}: the residuals are {ratio:.3g}× the noise and structured, and {tried} explains them; "
            "the model does not describe the data to their noise, and its values carry that misfit" + (f"; {untried_words(left_out)}" if left_out else ""))


def undetermined_words(fit: FitResult, names: Sequence[str]) -> str:
    """The note on the baseline's parameters ``names`` that the data do not determine
    (`undetermined_parameters`, `vanished_parameters`), with their relative standard errors."""
    rel = [fit.stderr.get(n, math.nan) / abs(fit.values[n]) if fit.values[n] else math.nan for n in names]
    errors = ", ".join(f"{n} ± {r * 100:.3g} %" if math.isfinite(r) else f"{n} with no finite error" for n, r in zip(names, rel))
    return (f"the baseline fit: the data do not determine {', '.join(names)} ({errors}; impedax fit of the model says why): "
            f"the verdict judges the fit, not {'this value' if len(names) == 1 else 'these values'}, and the data may not need {'its element' if len(names) == 1 else 'their elements'} "
            f"(impedax compare DATA --model '{fit.model}' --model '<the model without {'it' if len(names) == 1 else 'them'}>' weighs both)")


def structured_bands_words(bands: Sequence[FailingBand]) -> str:
    """How a verdict counts the bands of the model's misfit: ``1 band``, ``2 bands`` (not "1
    band(s)"), and beside them those the report lists as the data's problem: ``1 band (and 1
    where the KK test flags the data)``. REAL BioLogic from ``R0 + R1 || C1`` listed two bands
    under "where the model fails", one tagged as the data's problem, beside a verdict
    "structured in 1 band"."""
    model = sum(not b.data_problem for b in bands)
    data = len(bands) - model
    return counted(model, "band") + (f" (and {data} where the KK test flags the data)" if data else "")


def _verdict(cands: Sequence[Suggestion], bands: Sequence[FailingBand], ratio: float, left_out: Sequence[str] = ()) -> tuple[Verdict, str]:
    """The verdict and its reason from the ranked candidates, the bands and the noise ratio:
    ``missing_effect`` when a candidate is significant, else ``adequate`` (what is left, if
    anything, no effect of the catalog explains with determined, plausible values; ``left_out``:
    the catalog's effects not tried, which the reason then names)."""
    model_bands = [b for b in bands if not b.data_problem]
    counted_bands = structured_bands_words(bands)
    if any(s.significant for s in cands):
        best = next(s for s in cands if s.significant)
        # (at or under the noise overall, the misfit is systematic, not large: "0.844× the noise;
        # adding …" would read as a contradiction)
        within = ratio <= 1
        reason = f"the residuals are {ratio:.3g}× the noise" + (
            (f" overall, yet structured in {counted_bands}" if within else f" and structured in {counted_bands}") if model_bands
            else (" overall, yet not noise alone" if within else ""))
        if "+" in best.effect and any("+" not in s.effect for s in cands if s.significant):
            reason += f"; adding {best.effect.replace('+', ' and ')} together ({best.added}) lowers AIC by {-best.delta_aic:.1f}."
        elif "+" in best.effect:
            reason += f"; no single effect explains them with determined parameters, but adding {best.effect.replace('+', ' and ')} together ({best.added}) lowers AIC by {-best.delta_aic:.1f}."
        else:
            reason += f"; adding {best.effect} ({best.added}) lowers AIC by {-best.delta_aic:.1f}."
        for arc in best.beyond_band:  # (the first line a user reads: an arc the data see one flank of is no resolved relaxation)
            reason = reason[:-1] + (f", though {arc.elements} relaxes far {arc.side} the band: it acts as {arc.acts_as} alone there."
                                    if arc.factor > FAR_BEYOND_FACTOR else
                                    f", though {arc.elements} relaxes at {format_quantity(arc.frequency_hz, 'Hz')}, {arc.side} the band: the data see one flank of it.")
        return Verdict.MISSING_EFFECT, reason
    if _beyond_single_effects(bands, ratio):
        return Verdict.ADEQUATE, (
            f"the residuals are {ratio:.3g}× the noise and structured in {counted_bands}, but no effect {'tried' if left_out else 'of the catalog'} explains them "
            "with determined, plausible parameters" + (f"; {untried_words(left_out)}: diagnose again with them." if left_out else
                                                        ": what is left is beyond the catalog (or the model discrepancy floor); to go further, impedax drt FILE reads "
                                                        "a circuit off the data's DRT, and an effect of your own joins the catalog (docs/diagnosis.md, \"An effect of your own\").")
        )
    reason = (
        f"the residuals are {ratio:.3g}× the noise" + ((" with no structured band but where the KK test flags the data" if bands else " with no structured band") if not model_bands else " (small structure only)")
        + f", and no effect lowers AIC by more than {DELTA_AIC_MIN:g} while explaining at least {NOISE_FRACTION_MIN * 100:.0f} % of the noise variance."
    )
    return Verdict.ADEQUATE, reason


@reports_progress
@checked_arguments(circuit_parameters=circuit_parameters,
    effects=instance_of(EffectCatalog, what="an EffectCatalog (e.g. impedax.DEFAULT_EFFECTS)"), kk=instance_of(KKResult, optional=True),
    noise=noise_fraction, weighting=choice(WEIGHTINGS), registry=instance_of(Registry), fmin=frequency, fmax=frequency,
    n_starts=count(1, MAX_STARTS), max_steps=count(1, MAX_SOLVER_STEPS), seed=seed_rule, drt_evidence=flag,
    solver_shape=instance_of(SolverShape, optional=True, what="a SolverShape (e.g. an earlier Diagnosis.solver_shape)"), mask=flag,
    drt_memo=instance_of(DRTMemo, optional=True, what="a DRTMemo (one per data, e.g. refine's)"), fixed=parameter_values(),
    bounds=parameter_bounds,
)
def diagnose(
    fit_or_data,
    circuit: Circuit | str | None = None,
    *,
    data: xr.Dataset | None = None,
    effects: EffectCatalog = DEFAULT_EFFECTS,
    kk: KKResult | None = None,
    noise: float | None = None,
    weighting: str = "modulus",
    registry: Registry = DEFAULT_REGISTRY,
    fmin: float | None = None,
    fmax: float | None = None,
    n_starts: int = 4,
    max_steps: int = CANDIDATE_STEPS,
    seed: int = 0,
    drt_evidence: bool = True,
    solver_shape: SolverShape | None = None,
    mask: bool = True,
    progress: Callable[[str], None] | None = None,
    drt_memo: DRTMemo | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
) -> Diagnosis:
    """Diagnose a fit: where the model fails, which effect of ``effects`` is missing, verdict.

    ``fit_or_data``: a `FitResult` (then ``data`` may give the Dataset it was fitted to, for its
    ``sigma``; the fit's own registry and band are used, and its fixed values and bounds are
    kept in every candidate fit that has the parameter), or a spectrum Dataset/path together
    with ``circuit`` (parsed with ``registry`` and fitted first with ``weighting`` to the points
    with ``fmin`` ≤ f ≤ ``fmax``; ``fixed``, name → value, is held in that fit and in every
    candidate fit that has the parameter, as a FitResult's fixed values are, and ``bounds``,
    name → (lower, upper) as `fit`'s, are kept the same way, as a FitResult's bounds are: a
    bound the optimum presses against can make the verdict ``constraint``). ``kk``: a `KKResult` to reuse (default: `kk_test` of the
    fitted spectrum); ``noise``: a relative noise level to use instead of the estimate (needed,
    or a sigma in the data, on fewer than `CONCLUSIVE_POINTS_MIN` frequencies: `DataError` without).
    Candidates are fitted warm-started together (``n_starts`` starts each, ``max_steps``
    Levenberg–Marquardt steps). ``drt_evidence``: compare the data's DRT with the baseline's
    and let the unexplained peaks guide ``extra_relaxation`` and ``constant_phase`` (False: the
    misfit alone). ``solver_shape``: the compiled candidate solver's shape to reuse
    when it holds the candidates (an earlier `Diagnosis.solver_shape`; `refine` passes each
    step's on, so its steps share one compilation). ``mask``: leave out the points the KK test
    blames (False: judge every point given; `refine` passes False after its first step, so
    that every step is judged on the same points). ``progress``: called with a line of text as
    each stage begins (the CLI prints them once a run has taken a few seconds). ``drt_memo``: a
    `DRTMemo` the diagnoses of one spectrum share (`refine` passes one, so the data's DRT is
    solved once per run; default: one of this diagnosis' own). Thresholds and
    rules: module docstring and docs/diagnosis.md. Returns a `Diagnosis`.
    """
    check_argument_order("diagnose", fit_or_data, circuit)
    if n_starts < 1 or max_steps < 1:
        raise ParameterError("n_starts and max_steps must be at least 1")
    if not isinstance(drt_evidence, bool):
        raise ParameterError(f"drt_evidence must be True or False, got {drt_evidence!r}")
    say = progress if progress is not None else (lambda text: None)
    say("fitting the baseline" + (f" {circuit}" if circuit is not None and not isinstance(fit_or_data, FitResult) else ""))
    base, data, shape, left_out = _baseline(
        fit_or_data, circuit, data=data, effects=effects, registry=registry, fmin=fmin, fmax=fmax, weighting=weighting, n_starts=n_starts, seed=seed, shape=solver_shape,
        noise_given=noise is not None or kk is not None, fixed=fixed, bounds=bounds,
    )
    require_points_for_diagnosis(base.n_points, base.n_params)
    user_fit = base  # (the user's fit, whose fixed values and bounds `_constraint_verdict` checks)
    spectrum, sigma = _spectrum_of(base, data)
    not_passive = tuple(left_out)
    masked_z = dict(left_out)  # (each masked point's measured Z, for the figure)
    notes: list[str] = [unidentified_note(base)] if base.unidentified_groups else []
    if not_passive:
        kk_noise_used = sigma is None and data is not None and non_passive_noise(data) is not None
        every_f = np.concatenate([np.asarray(base.frequency, float), np.asarray(not_passive, float)])
        cause = ("an instrument artifact, often a phase error at the top of its band" if top_of_band(every_f, np.arange(every_f.size) >= base.frequency.size)
                 else "a measurement artifact below the top decade of the band, where an instrument's phase error seldom lies: check those points")
        notes.append(
            f"{counted(len(not_passive), 'point')} with {non_passive_words(NOISE_OF_SIGMA if sigma is not None else KK_RESIDUAL_NOISE if kk_noise_used else None, every_f.size)} "
            f"({', '.join(format_frequency(f) for f in not_passive[:6])}{', …' if len(not_passive) > 6 else ''}) "
            f"{'is' if len(not_passive) == 1 else 'are'} left out of every fit and test: no passive circuit has a negative real part ({cause})"
        )
    if kk is None:
        say("the Kramers–Kronig test of the data")
        kk = _kk_of(spectrum, notes, data.attrs if data is not None else None)
    else:
        _require_kk_on_the_fit(kk, base.frequency)
    inconclusive = None  # (reported as the test; its flags and noise estimate would read the Voigt chain's misfit as noise)
    if kk is not None and not kk.conclusive:
        _require_noise_without_kk(kk.frequency.size, noise, sigma, source=data.attrs.get("source") if data is not None else None)
        notes.append(f"the Kramers–Kronig test is inconclusive on {kk.frequency.size} frequencies (it needs {CONCLUSIVE_POINTS_MIN}): its flags and noise estimate are not used")
        inconclusive, kk = kk, None
    kk_as_tested = kk  # (the noise model's floor δ takes the test's own flags)
    sign_hint = kk_as_tested.sign_hint if kk_as_tested is not None else None  # (before `kk_judged_locally`, which may clear flags)
    if kk is not None and not kk.valid:
        local = kk_judged_locally(kk)
        cleared = int(np.sum(kk.flagged)) - int(np.sum(local.flagged))
        if cleared:
            notes.append(
                f"the KK test flags {counted(int(np.sum(kk.flagged)), 'point')} against its one global noise estimate; {cleared} of them {'is' if cleared == 1 else 'are'} within the noise "
                "where they are (the noise varies along the band) and count as data"
            )
            kk = local
    kk_bands = kk.bad_bands if kk is not None else ()
    located = kk_outliers(spectrum, kk, max_fraction=OUTLIER_MAX_FRACTION) if mask and kk is not None and not kk.valid else None
    kk_kept = located[1] if located is not None else None
    nm = noise_model(base.frequency, base.z_data, noise=noise, sigma=sigma, kk=kk_kept or kk, fallback_rms=base.rms_rel, floor_kk=kk_kept or kk_as_tested,
                     sigma_kind=sigma_origin(data.attrs if data is not None else None))
    if located is not None:  # a few erratic points: mask exactly them, the rest is KK consistent
        problem = DataProblem(None, located[0], None)
        kk_bands = ()
    else:
        problem = _data_problem(base, kk, nm, sign_hint, kk_as_tested)
        if not mask and problem.masked.any():
            kept = f"the KK test flags {int(np.sum(np.asarray(kk.flagged, bool)))} of {base.n_points} points: kept in every fit (mask=False; --keep-all-points)"
            problem = problem._replace(masked=np.zeros_like(problem.masked), note=None, kept=kept)
    if problem.invalid is not None:
        bands = failing_bands(base, nm.sigma_rel, kk_bad_bands=kk_bands)
        return Diagnosis(base, kk if kk is not None else inconclusive, nm.sigma_rel, nm.source, bands, (), Verdict.DATA_INVALID, problem.invalid, tuple(notes), _thresholds(), None, nm.measurement, nm.discrepancy, not_passive, kk_as_tested=kk_as_tested, solver_shape=shape, masked_impedance=tuple(left_out.values()), sign_hint=sign_hint,
                         kk_valid_band=problem.valid_band, misses_valid_band=problem.misses_valid_band, not_passive_points=not_passive,
                         kk_run_band=problem.run_band, misses_run_band=problem.misses_run_band)
    if problem.note:
        notes.append(problem.note)
    kk_flagged_kept = problem.kept
    keep = ~problem.masked
    masked = tuple(float(f) for f in base.frequency[problem.masked])
    masked_z.update(zip(masked, (complex(z) for z in base.z_data[problem.masked])))
    if masked:
        spectrum = spectrum.isel(frequency=np.nonzero(keep)[0])
        one = len(masked) == 1
        notes.append(f"{counted(len(masked), 'point')} " + (f"behind the failed KK test (without {'it' if one else 'them'} it passes)" if located is not None else "the KK test flags as the data's own problem")
                     + f" {'is' if one else 'are'} masked: every fit of this diagnosis leaves {'it' if one else 'them'} out")
    elif kk is not None and not kk.valid and problem.kept is None:
        notes.append(f"the KK test flags {kk.measured_bands_text()}: misfits there may be data problems")  # (its flagged points, as the data line names them)
    sigma_rel, measurement = nm.sigma_rel[keep], nm.measurement[keep]

    if drt_evidence:
        say("the DRT of the data and of the baseline")
    drts = DRTMemo() if drt_memo is None else drt_memo
    evidence = _drt_evidence(base, notes, drts) if drt_evidence else None
    ctx = _context(base, evidence)
    n_points = int(keep.sum())
    proposals = [(e, p) for e, p in effects.proposals(ctx) if len(p.circuit.parameter_names(base.registry)) < 2 * n_points]
    left_out = tuple(i for i in DEFAULT_EFFECTS.ids() if i not in effects.ids())
    say(f"fitting {len(proposals)} candidate circuits of {len({e.id for e, _ in proposals})} effects")
    if base.bounds:
        notes.append(
            BOUNDS_KEPT_LEAD + user_bounds_text(base) + ") are kept in every candidate fit that has the parameter, "
            "the baseline's refit included, and in the commands printed (--bound); a candidate that replaces the element drops its bound"
        )
    proposals, fits, shape = _fit_proposals(base, spectrum, ctx, proposals, shape, n_starts=n_starts, max_steps=max_steps, seed=seed, say=say)
    if masked:
        base = fits[0]
    elif fits[0].chi2 < base.chi2 * (1 - 1e-6):
        notes.append(f"the baseline refit found a better optimum (rms_rel {base.rms_rel * 100:.3g} % → {fits[0].rms_rel * 100:.3g} %); it is used as the baseline")
        base = fits[0]

    def judged(base):
        bands = failing_bands(base, sigma_rel, kk_bad_bands=kk_bands)
        loose = _undetermined_elements(base)
        idle = idle_elements(base, undetermined_parameters(base))
        cands = _rank(_suggestions(base, proposals, fits[1:], sigma_rel, bands, evidence), evidence, loose, idle, base.circuit, sigma_rel)
        return (bands, cands) + _verdict(cands, bands, _noise_ratio(base, sigma_rel), left_out)

    bands, cands, verdict, reason = judged(base)
    # before naming a missing effect (or none): does a fixed value or bound of the user's explain the misfit?
    constrained = None
    if binding_constraints(user_fit.values, user_fit.fixed, user_fit.at_bound, user_fit.bounds):
        say("checking the misfit with your fixed values and bounds released")
        constrained = _constraint_verdict(user_fit, spectrum, kk_as_tested, _noise_ratio(user_fit if user_fit.n_points == sigma_rel.size else base, sigma_rel))
    if constrained is not None:  # (no pairs, lead or baseline check: no effect is to be named)
        verdict, reason = constrained
    elif verdict == Verdict.ADEQUATE and _beyond_single_effects(bands, _noise_ratio(base, sigma_rel)):  # two effects missing at once?
        say("fitting pairs of effects (no single one is enough)")
        pairs, pair_fits, shape = _effect_pairs(base, cands, proposals, spectrum, effects, shape, with_drt=evidence is not None, drts=drts, max_params=2 * n_points - 1, n_starts=n_starts, max_steps=max_steps, seed=seed, say=say)
        if pairs:
            proposals, fits = proposals + pairs, fits + pair_fits
            bands, cands, verdict, reason = judged(base)
    if verdict == Verdict.MISSING_EFFECT and constrained is None:  # a lead inductance hidden behind the effect named first?
        leads, lead_fits, shape = _lead_behind(base, cands, proposals, spectrum, effects, shape, sigma_rel, bands, with_drt=evidence is not None, drts=drts, max_params=2 * n_points - 1, n_starts=n_starts, max_steps=max_steps, seed=seed, say=say)
        if leads:
            proposals, fits = proposals + leads, fits + lead_fits
            bands, cands, verdict, reason = judged(base)
    if verdict == Verdict.MISSING_EFFECT and constrained is None:  # before naming a missing effect: is the baseline at its own optimum?
        say("checking the baseline's own optimum before naming a missing effect")
        better = _baseline_checked(base, spectrum, shape, next(s.fit for s in cands if s.significant), seed=seed)
        if better is not None:
            notes.append(f"before naming a missing effect the baseline was refitted from the candidate's values (its arcs in every order) and {BASELINE_CHECK_STARTS} random starts and reached a better optimum (rms_rel {base.rms_rel * 100:.3g} % → {better.rms_rel * 100:.3g} %); it is used as the baseline")
            base = better
            bands, cands, verdict, reason = judged(base)
    drt_circuit = None
    if verdict == Verdict.MISSING_EFFECT and constrained is None and evidence is not None and not base.bounds and not any(base.fixed.values()):
        say("fitting the circuit the data's DRT reads")
        drt_circuit = _drt_circuit_fit(base, spectrum, sigma_rel, [s for s in cands if s.significant], drts, seed=seed)
    if verdict == Verdict.MISSING_EFFECT and kk_flagged_kept and kk is not None and not kk.valid:
        reason += _kk_floor_words(next(s.fit for s in cands if s.significant), kk, problem.kept_passing_band)
    ratio = _noise_ratio(base, sigma_rel)
    if verdict == Verdict.ADEQUATE and noise is None and sigma is None and ratio < NOISE_RATIO_LOW:
        notes.append(low_ratio_words(ratio, sigma_rel, base.n_points))
    # an element of the user's circuit that the data do not need (its fit's idle note: Wo1 with R at 0)
    idle = [f"the baseline fit: {w}" for w in base.warnings if is_idle_note(w)]
    notes += idle
    # a weighting that leaves the baseline (and every candidate, weighted alike) to a few points:
    # impedax fit warns, and so does diagnose --weighting proportional (REAL exampleData.csv)
    notes += [f"the baseline fit: {w}" for w in base.warnings if is_dominated_note(w)]
    # parameters of the user's model the data do not fix (C2 at ± 235 % beside a second arc the
    # data lack: impedax fit warns, and so does diagnose); an idle note says it already
    loose = sorted((undetermined_parameters(base) | vanished_parameters(base)) & set(base.free_names))
    if loose and not idle:
        notes.append(undetermined_words(base, loose))
    masked = tuple(sorted(masked + not_passive))
    return Diagnosis(
        base, kk if kk is not None else inconclusive, sigma_rel, nm.source, bands, tuple(cands), verdict, reason, tuple(notes), _thresholds(), evidence, measurement, nm.discrepancy, masked, kk_kept, kk_as_tested, shape,
        tuple(masked_z[f] for f in masked), sign_hint, not_passive_points=not_passive, kk_flagged_kept=kk_flagged_kept, effects_left_out=left_out, drt_circuit=drt_circuit,
    )
