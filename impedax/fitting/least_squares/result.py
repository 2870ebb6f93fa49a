"""The result of a least-squares fit of one spectrum (`FitResult`), built from the solver's
outputs with its uncertainties and warnings; the warning rules are shared with batch fits
(`stack_notes` builds the same text for a stack of fits at once)."""

from __future__ import annotations

import collections
import functools
import itertools
import math
import re
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import xarray as xr

from ...arguments import frequency_bands
from ...circuits import Circuit, DEFAULT_REGISTRY, Registry, compile_circuit, parse
from ...data import checked_frequencies, column_width, concise_repr, exact_number, report_text, format_bound, format_factor, format_frequency, format_quantity, format_relative_error, format_uncertain, unit_text, value_span
from ...errors import DataError
from ...io.netcdf import NETCDF_ADVICE, result_dataset
from ..arcs import BEYOND_BAND_FACTOR, ArcBeyondBand, arc_taus
from ..frozen import FrozenResult, KeyHintDict, freeze_fields
from ..kk import KKChains, kk_sigma_misfits
from ..parameters import ParameterTable, data_scales
from ..problem import WEIGHTING_SCALES
from ..reductions import RESISTOR_LIKE_ALPHA, WARBURG_LIKE_DEVIATION, warburg_deviation
from ...passivity import SUBTRACTION_CAUSE, listed_frequencies, non_passive_notes
from ..statistics import FIT_RESIDUAL_NOISE, KNOWN_SIGMA, NOISE_OF_SIGMA, UNKNOWN_VARIANCE, covariances, dominant_points, information_criteria, known_noise_criteria, non_passive, non_passive_words, top_of_band, uncertainties
from .branches import RELATIVE_ERROR_LIMIT, held_covariances, idle_branch_notes, settle_vanishing, vanishing_term_mask, undetermined, unidentified_stderr, undetermined_mask, vanishing_candidates, vanishing_parameters
from .notes import DATA_LIMIT, MISFIT, MODEL_MISFIT, SIGMA_RESIDUAL, SIGN_HINT, UNEVEN_NOISE, Note, carried_over, has_tag, notes_tags, sign_hint_tag, stored_tags, tag_detail, tagged, tags_attr, tags_of
from .solvers import SolverOutput, SolverStatus
from .starts import attainable_misfit, inward_start, rms_rel_of, well_inside

__all__ = [
    "FitResult", "fit_result", "fit_notes", "parameter_groups", "BOUND_RESTARTS", "stack_notes", "bound_sides", "confirm_bounds", "falling_inward", "inward_message", "vanishing_term_sides", "at_bound_names", "weighting_notes", "dominated_notes", "is_dominated_note",
    "misfit_notes", "uneven_residual_notes", "sigma_scale_notes", "sigma_misstated", "SIGMA_CHAIN_CHI2_RATIO", "sigma_unit_slip", "SIGMA_UNIT_SLIP_FACTOR", "SIGMA_UNIT_SLIP_FRACTION", "SIGMA_RELATIVE_Z", "unused_sigma_notes", "SIGMA_OF_TRIAL_MEANS_WORDS", "trial_means_of_sigma", "SIGMA_SOURCES_ATTR", "SIGMA_FROM_TRIALS", "SIGMA_FROM_OWN", "SIGMA_FROM_NONE", "sigma_sources", "names_in_words", "stored_notes", "chi2_red_range", "SIGMA_SCALE_FACTOR", "residual_band_rms", "UNEVEN_BAND_POINTS", "UNEVEN_RESIDUAL_RATIO", "UNEVEN_NOISE_NOTE", "REMAINDER_ATTRS", "SUBTRACTION_CAUSE", "is_remainder", "listed_frequencies", "DATA_LIMIT_NOTE", "MODEL_MISFIT_MARKS", "warnings_blame_model", "fit_blames_model", "fit_blaming_note", "fit_data_limit", "fit_sigma_residual_notes", "note_value_attrs", "stored_note_values", "tags_from_values", "warning_tags_by_words", "fit_warning_tags", "with_warnings", "fit_uneven_noise", "MODEL_MISSES_STRUCTURE", "MISFIT_IS_MODELS", "SIGN_HINT_LEAD", "SIGN_CAUSE_NOTE", "sign_notes_first", "SIGNS_IN_DOUBT_SHARE", "signs_in_doubt", "MODEL_MISFIT_OVER_CONSISTENT", "MODEL_MISFIT_NOISE_SHARE", "MODEL_MISFIT_DELTA_AIC", "misfit_beyond_chain", "misfit_beyond_noise", "SIGMA_EXCEEDED", "gross_misfits", "within_stated_noise", "misfit_hint", "misfit_hint_spectra", "MISFIT_HINT_FROM", "known_kk_misfits", "on_bound", "bound_note", "CORRELATION_LIMIT", "RELATIVE_ERROR_LIMIT", "BOUND_STDERR_FRACTION",
    "BOUND_CHI2_FRACTION", "ON_BOUND_FRACTION", "NUMERICALLY_ON_FRACTION", "shown_stderr", "value_shown_at_bound", "without_error", "near_bound_notes", "resistor_like_notes", "warburg_like_notes", "arc_beyond_band_notes", "STDERR_NOTE", "LINEARISED_STDERR_NAME", "data_difference", "stored_bounds", "user_bounds", "user_bounds_text",
    "embedded_fit", "fit_from_embedded", "bounds_attr", "unidentified_group_note", "FIT_STATISTICS",
]

FIT_STATISTICS = ("rms_rel", "chi2", "chi2_red", "aic", "bic")
"""A fit's goodness of fit under the keys of its JSON (`FitResult.summary`), the columns of its
CSV table (`FitResult.to_table`) and of a batch's (`batch.SPECTRUM_STATISTICS`)."""


def bounds_attr(bounds) -> dict[str, list[float]]:
    """User bounds (name → (lower, upper)) as a JSON- and netCDF-attribute value (name →
    [lower, upper]); `stored_bounds` reads it back."""
    return {n: [float(lo), float(hi)] for n, (lo, hi) in bounds.items()}


def stored_bounds(stored) -> dict[str, tuple[float, float]]:
    """A fit's user bounds as stored in an attribute (`bounds_attr`); none in a file written
    by older versions."""
    return {str(n): (float(lo), float(hi)) for n, (lo, hi) in dict(stored or {}).items()}


def data_difference(freq, z, ref_freq, ref_z) -> str | None:
    """How a spectrum (``freq`` [Hz], ``z`` [Ω]) differs from a reference one, for the errors
    of calls given fits of different data (`compare`, `sample`'s ``init``): point counts and
    frequency ranges, else where the impedances first differ; None when they are the same (to
    `np.isclose`'s tolerance: a fit stores the spectrum it was given)."""
    freq, z, ref_freq, ref_z = (np.asarray(a) for a in (freq, z, ref_freq, ref_z))

    def span(f) -> str:
        return f"{f.size} points, {format_quantity(float(np.min(f)), 'Hz')}–{format_quantity(float(np.max(f)), 'Hz')}"

    if freq.size != ref_freq.size or not np.allclose(freq, ref_freq):
        return f"{span(ref_freq)} against {span(freq)}"
    differ = np.flatnonzero(~np.isclose(z, ref_z))
    if not differ.size:
        return None
    return f"the same {freq.size} frequencies, but Z differs (first at {format_quantity(float(ref_freq[differ[0]]), 'Hz')})"


# identifiability thresholds (documented in the README; RELATIVE_ERROR_LIMIT in `branches`)
CORRELATION_LIMIT = 0.99
# a free parameter is at a bound (docs/fitting.md, "Convergence and bounds") when the bound lies
# within this many standard errors (or within 1e-4 relative of a nonzero bound) ... (a filter of
# candidates: rule 2 decides. Two, not one: on exact data a series R creeping to 0 stops at
# rounding level, e.g. 1.2e-15 ± 1.2e-15 Ω, either side of one standard error by chance)
BOUND_STDERR_FRACTION = 2.0
# ... and setting it exactly to the bound changes chi² by less than this fraction of the
# reduced chi² (a hundredth of one residual's share): the data cannot tell the fit from the bound
BOUND_CHI2_FRACTION = 1e-2
# a parameter at a bound is *on* it (the note "R0 is at its lower bound 0") when it lies within
# this fraction of the bound or, for a bound 0, of the data's scale for its unit (the value at
# which its element alone has the measured |Z|: `parameters.data_scales`; 1 for a dimensionless
# parameter); else the data only cannot tell it from the bound (R1 = 8e7 ± 1e18 Ω in a fit whose
# misfit swamps it), and the note says so with its value and standard error
ON_BOUND_FRACTION = 1e-4
# ... and its note gives its value ("W1.sigma = 0.000677 Ω s^-1/2 runs to its lower bound 0")
# unless it lies within this fraction of that scale: it then moves the model by less than the
# solver's relative stopping tolerance (`lm.lm_iteration`'s rtol 1e-8), so its digits are where
# the solver stopped, not what the data say (a single fit's R0 = 4.75e-204 Ω or 5.9e-16 Ω, a
# batch's exact 0: one note, "R0 is at its lower bound 0")
NUMERICALLY_ON_FRACTION = 1e-8


SAMPLE_ADVICE = "; for an honest interval, sample the posterior (impedax sample)"
"""The end of a fit's warning that its ± is not to be trusted near a bound; a posterior's report,
which is that sample, repeats the warning without it (`without_sample_advice`)."""


def without_sample_advice(text: str) -> str:
    """A start fit's warning as a posterior's report repeats it: `SAMPLE_ADVICE` left out."""
    return text.replace(SAMPLE_ADVICE, "")


@dataclass(frozen=True, eq=False)
class FitResult(FrozenResult):
    """A least-squares fit of ``circuit`` to one spectrum. Immutable.

    ``values``/``stderr`` are keyed by parameter name (stderr NaN for fixed parameters);
    ``bounds`` the free parameters' bounds the user narrowed (``fit(bounds=...)``; name →
    (lower, upper)), which a sampler started from this fit keeps (``sample(init=fit)``);
    ``covariance``/``correlation`` are over ``free_names``. ``covariance`` is the linearisation at
    the optimum with every free parameter free and the bounds ignored, except that the others'
    block holds a vanishing term's parameters at no bound (`branches.held_covariances`). A free parameter at a
    bound (``at_bound``) has no standard error (NaN: a symmetric one says nothing there; its
    linearised one is in `linearised_stderr`), nor has a vanishing term's (inf,
    `branches.settle_vanishing`); the row and column of either in ``correlation`` are NaN, the
    diagonal too (docs/fitting.md, "Standard errors at a bound"). ``unidentified_groups``: the
    groups of free parameters along the Jacobian's near-null directions, which the data do not
    determine separately (one name: not at all); the identifiability warnings name the same
    groups (`diagnose_identifiability`). ``residuals`` are the complex
    relative residuals r_k = (Z_model,k − Z_data,k)/|Z_data,k| and
    ``rms_rel = sqrt(mean |r_k|²)`` (docs/physics.md, "Goodness of fit"). ``chi2`` is the sum of the squared
    weighted residuals, ``chi2_red = chi2/(2N − k)``; AIC/BIC see `information_criteria`.
    ``warnings`` say what may be wrong with the fit; ``notes`` give advice that is not a warning
    (σ the weighting does not use: `unused_sigma_notes`), shown after them by `report`.
    """

    __repr__ = concise_repr  # (the generated one printed every array)
    __str__ = report_text  # (print(result): its report)

    circuit: Circuit
    values: dict[str, float]
    stderr: dict[str, float]
    fixed: dict[str, bool]
    free_names: tuple[str, ...]
    covariance: np.ndarray
    correlation: np.ndarray
    frequency: np.ndarray
    z_data: np.ndarray
    z_model: np.ndarray
    weighting: str
    chi2: float
    converged: bool
    message: str
    n_evaluations: int
    warnings: tuple[str, ...] = ()
    n_starts: int = 1
    elapsed_s: float = 0.0
    at_bound: tuple[str, ...] = ()  # free parameters at a natural or user bound
    unidentified_groups: tuple[tuple[str, ...], ...] = ()  # near-null directions' parameters (`statistics.null_sets`)
    registry: Registry = field(default=DEFAULT_REGISTRY, repr=False)
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict, repr=False)  # the user's bounds of free parameters (`fit(bounds=...)`), those narrower than the element's (`constraints.user_bounds`)
    source: str | None = field(default=None, repr=False)  # where the data came from (their ``attrs["source"]``, `impedax.load`'s path), None if unknown: `impedax.write_result` records it
    notes: tuple[str, ...] = ()  # advice that is not a warning (`unused_sigma_notes`)
    warning_tags: tuple[tuple[str, ...], ...] | None = field(default=None, repr=False)  # each warning's tags (`notes.WARNING_TAGS`: what it says as values, set where it is made), in the order of ``warnings``; None: not known (a fit built by hand, a file written without them, ``warnings`` replaced alone by other ones: `with_warnings` keeps them), read from the words
    _tags_given_with: tuple | None = field(default=None, repr=False)  # (the warnings and tags ``warning_tags`` were set with: `dataclasses.replace` copies them, so that tags carried over onto other warnings are known as not theirs, `notes.carried_over`)

    def __post_init__(self):
        warnings, tags = tuple(self.warnings), self.warning_tags
        if tags is not None and (len(tags) != len(warnings) or carried_over(warnings, tags, self._tags_given_with)):  # (``warnings`` replaced alone, not by `with_warnings`: the tags are not theirs; `notes.Note`s bring their own)
            tags = notes_tags(warnings) if any(tags_of(w) for w in warnings) else None
            object.__setattr__(self, "warnings", tuple(str(w) for w in warnings))
        object.__setattr__(self, "warning_tags", tags)
        object.__setattr__(self, "_tags_given_with", None if tags is None else (self.warnings, tags))
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def tagged_warnings(self) -> tuple[str, ...]:
        """``warnings`` as `notes.Note`s carrying their tags (plain texts where not known):
        filtered, reordered or extended, they keep them (`with_warnings`)."""
        return tagged(self.warnings, self.warning_tags)

    @property
    def model_misfit(self) -> bool | None:
        """Whether a warning blames the model (`notes.MODEL_MISFIT`); None: not known
        (`fit_blames_model` then reads the words)."""
        return None if self.warning_tags is None else fit_blames_model(self)

    @property
    def data_limit_note(self) -> str | None:
        """The warning that the data limit the fit (`notes.DATA_LIMIT`), "" where it has none;
        None: not known (`fit_data_limit` then reads the words)."""
        return None if self.warning_tags is None else fit_data_limit(self)[0]

    @property
    def data_limit_hint(self) -> str:
        """That warning's end holding the KK test's sign hint ("; hint: …", `notes.SIGN_HINT`), ""
        without one or where not known."""
        return "" if self.warning_tags is None else fit_data_limit(self)[1]

    @property
    def misfit_note(self) -> str | None:
        """The fit's misfit warning (`misfit_notes`; compare's in its place, `notes.MISFIT`), ""
        where it has none; None: not known (`fit_blaming_note`)."""
        return None if self.warning_tags is None else _first_tagged(self.warnings, self.warning_tags, MISFIT)

    @property
    def uneven_noise(self) -> bool | None:
        """Whether a warning says the weighted residuals are uneven across the band
        (`notes.UNEVEN_NOISE`); None: not known (`fit_uneven_noise` then reads the words)."""
        return None if self.warning_tags is None else fit_uneven_noise(self)

    @property
    def sigma_residual_notes(self) -> tuple[str, ...] | None:
        """The warnings that read residuals below the data's σ, or uneven against it, as what σ is
        or a σ misstating the noise (`notes.SIGMA_RESIDUAL`); None: not known
        (`fit_sigma_residual_notes` then reads the words)."""
        return None if self.warning_tags is None else fit_sigma_residual_notes(self)

    @property
    def linearised_stderr(self) -> KeyHintDict:
        """``stderr`` with each free parameter at a bound given the linearisation's, √ of its
        ``covariance`` diagonal (the bounds ignored, as scipy's curve_fit reports). Not a ± error
        at a bound: the scale of χ²'s curvature there, what a one-sided limit or a sampler's
        start is built from. A vanishing term's parameter stays inf, a fixed one NaN. A new
        dict at each call, whose missing key names the keys there are (`MissingKey`)."""
        out = KeyHintDict(self.stderr)
        cov = np.asarray(self.covariance, float)
        if cov.shape == (self.n_params, self.n_params):
            for j, n in enumerate(self.free_names):
                if n in self.at_bound and math.isnan(out[n]):
                    out[n] = float(np.sqrt(max(cov[j, j], 0.0)))
        return out

    @property
    def linearised_correlation(self) -> np.ndarray:
        """``correlation`` with the NaN rows and columns of parameters without a standard error
        (at a bound, a vanishing term's) filled from ``covariance`` as `statistics.covariances`
        computes them: the linearisation's, bounds ignored (`linearised_stderr`)."""
        corr = np.array(self.correlation, float)
        cov = np.asarray(self.covariance, float)
        missing = np.isnan(corr)
        if missing.any() and cov.shape == corr.shape:
            d = np.sqrt(np.clip(np.diag(cov), 0, None))
            with np.errstate(all="ignore"):
                full = np.clip(np.nan_to_num(cov / (d[:, None] * d[None, :]), nan=0.0), -1, 1)
            np.fill_diagonal(full, 1.0)
            corr[missing] = full[missing]
        return corr

    @property
    def model(self) -> str:
        return str(self.circuit)

    @property
    def n_points(self) -> int:
        return int(self.frequency.size)

    @property
    def n_params(self) -> int:
        """Number of free parameters k."""
        return len(self.free_names)

    @property
    def dof(self) -> int:
        return 2 * self.n_points - self.n_params

    @property
    def chi2_red(self) -> float:
        return self.chi2 / self.dof if self.dof > 0 else math.nan

    @property
    def aic(self) -> float:
        return information_criteria(self.chi2, 2 * self.n_points, self.n_params)[0]

    @property
    def bic(self) -> float:
        return information_criteria(self.chi2, 2 * self.n_points, self.n_params)[1]

    @property
    def known_noise_criteria(self) -> tuple[float, float] | None:
        """AIC = χ² + 2k and BIC = χ² + k ln n (`statistics.KNOWN_SIGMA`) of a fit weighted by the
        data's sigma, the σ taken as the noise: what ``impedax compare`` ranks such fits by.
        None under the other weightings, where `aic` and `bic` (n ln(χ²/n) + 2k) are the only
        form (a walkthrough saw fit print AIC −24.13 and compare 80.52 for one fit, unexplained)."""
        return known_noise_criteria(self.chi2, 2 * self.n_points, self.n_params) if self.weighting == "sigma" else None

    def _criteria_text(self) -> str:
        """The report's AIC and BIC, with their form under sigma weighting, where compare's differs."""
        text = f"AIC {self.aic:.2f}    BIC {self.bic:.2f}"
        known = self.known_noise_criteria
        if known is None:
            return text
        return text + f" (n ln(χ²/n) + 2k; σ as the known noise, as impedax compare ranks: AIC {known[0]:.2f}, BIC {known[1]:.2f})"

    @property
    def misses_structure(self) -> bool:
        """Whether the model misses structure the data hold: a warning says so
        (`MODEL_MISFIT_MARKS`), or `misfit_hint` gives its hint (rms_rel below 2 % and over 5×
        what the Kramers–Kronig chain reaches; as `BatchFitResult.misses_structure`):
        its values and standard errors are then this model's best, not the system's. The warning's
        blame is its `notes.MODEL_MISFIT` tag, set where the note is made, not read from its words
        (`fit_blames_model`; a fit without tags: its words)."""
        return fit_blames_model(self) or misfit_hint(self) is not None

    @property
    def residuals(self) -> np.ndarray:
        with np.errstate(all="ignore"):  # an overflowed model is +inf: its residuals are too
            return (self.z_model - self.z_data) / np.abs(self.z_data)

    @property
    def rms_rel(self) -> float:
        with np.errstate(over="ignore"):
            return float(np.sqrt(np.mean(np.abs(self.residuals) ** 2)))

    @property
    def params(self) -> KeyHintDict:
        """``values`` as a new dict, yours to edit, whose missing key names the keys there are
        (`MissingKey`, as ``values``')."""
        return KeyHintDict(self.values)

    def predict(self, freq) -> np.ndarray:
        """Model impedance [Ω] at ``freq`` [Hz] with the fitted parameters."""
        return np.asarray(compile_circuit(self.circuit, self.registry)(self.values, checked_frequencies(freq)))

    def summary(self) -> dict:
        """The JSON summary used by ``impedax fit --json``: each of ``params`` with its value,
        stderr, fixed and ``unit`` (the element spec's, as `to_table` and ``sample --json`` give
        it) and ``linearised_stderr`` (`linearised_stderr`: at a bound, the
        linearisation's, what scipy's curve_fit and impedance.py's ``conf_`` give);
        ``misses_structure`` (`misses_structure`, the key of a batch's rows)."""
        specs = self.circuit.parameter_specs(self.registry)
        linearised = self.linearised_stderr
        return {
            "model": self.model,
            "n_points": self.n_points,
            "n_params": self.n_params,
            "params": {n: {"value": self.values[n], "stderr": shown_stderr(self.stderr[n], self.fixed[n]), "fixed": self.fixed[n], "unit": specs[n].unit,
                           "linearised_stderr": shown_stderr(linearised[n], self.fixed[n])} for n in self.values},
            "rms_rel": self.rms_rel,
            "chi2": self.chi2,
            "chi2_red": self.chi2_red,
            "aic": self.aic,
            "bic": self.bic,
            "aic_form": UNKNOWN_VARIANCE,  # (the form of aic and bic; under weighting sigma, compare's are the *_known_noise keys)
            **({"aic_known_noise": known[0], "bic_known_noise": known[1], "known_noise_form": KNOWN_SIGMA} if (known := self.known_noise_criteria) else {}),
            "converged": self.converged,
            "message": self.message,
            "at_bound": list(self.at_bound),
            "warnings": list(self.warnings),
            "warning_tags": [list(t) for t in fit_warning_tags(self)],  # (each warning's tags, in the order of warnings: docs/fitting.md, "What a warning says")
            "unidentified_groups": [list(g) for g in self.unidentified_groups],
            "weighting": self.weighting,
            "n_evaluations": self.n_evaluations,
            "n_starts": self.n_starts,  # (the starts the fit used, the start ladder's rungs included; the message words them)
            "user_bounds": bounds_attr(self.bounds),  # (the bounds=, --bound, of free parameters; an open end inf, null in JSON)
            "notes": list(self.notes),  # (advice that is not a warning, e.g. σ the weighting does not use)
            "misses_structure": bool(self.misses_structure),  # (as each row of a batch's "spectra" has it)
        }

    def _chi2_red_basis(self) -> str:
        """`` (relative to |Z|, not to the noise)`` after a chi2_red that is not weighted by the
        data's sigma: ≈ 1 means a fit to the noise only with sigma weighting (a walkthrough read
        modulus weighting's 1e-4 as a fit far below the noise). Empty with sigma weighting."""
        scale = WEIGHTING_SCALES.get(self.weighting)
        return f" (relative to {scale}, not to the noise)" if scale else ""

    def report(self) -> str:
        """A readable table of the fit, its warnings and notes, and the hint that a misfit
        which looks small misses structure the data hold (`misfit_hint`)."""
        specs = self.circuit.parameter_specs(self.registry)
        width = column_width(self.values, "parameter")
        lines = [
            f"model      {self.model}",
            f"weighting  {self.weighting}    points {self.n_points}    free parameters {self.n_params}",
            f"rms_rel    {self.rms_rel * 100:.3g} %    chi2 {self.chi2:.4g}    chi2_red {self.chi2_red:.4g}{self._chi2_red_basis()}    {self._criteria_text()}",
            f"status     {'converged' if self.converged else 'NOT converged'}: {self.message}",
            "",
            f"{'parameter':<{width}}  {'value':>12}  {'stderr':>10}  {'rel':>9}  unit",
        ]
        for n, v in self.values.items():
            if self.fixed[n]:
                lines.append(f"{n:<{width}}  {exact_number(v):>12}  {'(fixed)':>10}  {'':>9}  {unit_text(specs[n].unit)}".rstrip())  # (as given: no error to round to)
            else:
                e = self.stderr[n]
                # at a bound the linearised error says nothing (a log transform's scale at 0:
                # Wo1.R = 6.8e-07 ± 1.3e+07 Ω); a bound note gives it where it is off the bound
                at = n in self.at_bound
                rel = "at bound" if at else format_relative_error(e / v) if v and np.isfinite(e) else "—"
                shown = f"{'—':>10}" if at else f"{e:>10.3g}"
                value = value_shown_at_bound(n, v, self.warnings) if at else f"{v:.5g}"  # (on a bound 0: "0", as its note says)
                lines.append(f"{n:<{width}}  {value:>12}  {shown}  {rel:>9}  {unit_text(specs[n].unit)}".rstrip())
        for w in self.warnings:
            if not w.startswith("fit did not converge"):  # the status line says it once
                lines.append(f"warning: {w}")
        lines += [f"note: {n}" for n in self.notes]
        hint = misfit_hint(self)  # (as the command line prints it)
        if hint is not None:
            lines.append(f"hint: {hint}")
        return "\n".join(lines)

    def to_table(self) -> list[dict[str, object]]:
        """The tidy table of parameters: one row per parameter with name, value, stderr (None
        when fixed or there is none: at a bound, a vanishing term's, an overflowed fit's), unit
        (from the element specs) and fixed, then the fit's `FIT_STATISTICS` (rms_rel, chi2,
        chi2_red, aic, bic), repeated on each row as a batch's table has them, then
        the flags (as `BatchFitResult.to_table`):
        ``converged`` (the fit's), ``at_bound`` and ``undetermined`` (the fits' rule,
        `branches.undetermined`: relative standard error above 100 % or none, never for a fixed
        parameter or one at a bound), then ``warnings``: the fit's warnings joined by "; " ("" if
        none), on every row, as a batch's table has them, and ``weighting`` (what chi2, chi2_red and aic
        are against, also in a CSV written from Python) and ``misses_structure``
        (`misses_structure`, as a batch's table) (`impedax.io.write_result` .csv)."""
        specs = self.circuit.parameter_specs(self.registry)
        statistics = {k: float(getattr(self, k)) for k in FIT_STATISTICS}
        warned = "; ".join(self.warnings)
        misses = bool(self.misses_structure)
        return [
            {
                "name": n, "value": v, "stderr": shown_stderr(self.stderr[n], self.fixed[n]), "unit": specs[n].unit, "fixed": self.fixed[n], **statistics,
                "converged": bool(self.converged), "at_bound": n in self.at_bound,
                "undetermined": bool(undetermined(v, self.stderr[n])) and not self.fixed[n] and n not in self.at_bound, "warnings": warned, "weighting": self.weighting,
                "misses_structure": misses,
            }
            for n, v in self.values.items()
        ]

    def to_latex(self) -> str:
        """The parameters as a plain LaTeX ``tabular`` (no package needed): name, value ± standard
        error with the error to two significant digits and the value to its last digit
        (`impedax.data.round_to_error`: 533.3168 ± 13.0249 → $533 \\pm 13$), unit (Ω as
        ``\\Omega``); a fixed parameter (its value as given, `impedax.data.exact_number`) or one
        at a bound (no standard error, `to_table`) is marked so, and one the data do not
        determine (relative standard error above 100 %, the value and error then each to two
        significant digits with its own power of ten) is marked "(undetermined)". A comment
        line names the model and rms_rel (``impedax fit --out FILE.tex``)."""
        from ...data import latex_text, latex_unit, latex_value_error

        lines = [
            f"% impedax fit: {self.model}, weighting {self.weighting}, rms_rel {self.rms_rel * 100:.3g} %; value ± standard error",
            r"\begin{tabular}{lll}",
            r"\hline",
            r"parameter & value & unit \\",
            r"\hline",
        ]
        for row in self.to_table():
            error = math.nan if row["stderr"] is None else row["stderr"]
            if row["fixed"]:
                note = " (fixed)"
            elif row["name"] in self.at_bound:
                note = " (at bound)"
            else:  # (the fits' rule, `branches.undetermined`: relative standard error above 100 %, or none)
                note = " (undetermined)" if undetermined(row["value"], error) else ""
            cell = latex_value_error(row["value"], error, exact=row["fixed"]) + note
            lines.append(f"{latex_text(row['name'])} & {cell} & {latex_unit(row['unit'])} \\\\")
        lines += [r"\hline", r"\end{tabular}"]
        return "\n".join(lines) + "\n"

    def _repr_html_(self) -> str:
        from ...plotting.html import result_html

        status = "converged" if self.converged else "NOT converged"
        lines = [f"weighting {self.weighting}: rms_rel {self.rms_rel * 100:.3g} %, chi2_red {self.chi2_red:.4g}{self._chi2_red_basis()}, AIC {self.aic:.2f} ({self.n_points} points, {status})", *self.warnings, *(f"note: {n}" for n in self.notes)]
        # as the text table: a parameter at a bound has no meaningful linearised error to show
        # (and the status line above says whether the fit converged)
        rows = [{k: v for k, v in ({**row, "stderr": "at bound"} if row["name"] in self.at_bound else row).items() if k not in ("converged", "warnings", "weighting", "misses_structure", *FIT_STATISTICS)} for row in self.to_table()]
        return result_html(self.model, rows, lines=lines, figure=self.plot)

    def derive(self, fn, freq=None, *, constants=None):
        """Propagate the fit to ``fn(params[, freq])`` by the delta method (`derive_fit`;
        ``constants``: numbers held in ``params`` beside the fitted values)."""
        from ..derived import derive_fit

        return derive_fit(self, fn, freq, constants)

    def plot(self, *, title: str | None = None, bands=None, figsize: tuple[float, float] | None = None):
        """Data vs model: Nyquist, Bode and relative residuals (matplotlib Figure); ``bands``
        [(f_min, f_max), ...] in Hz shaded on the frequency axes (a diagnosis' failing bands);
        ``figsize`` (width, height) [in] in place of the size that follows the spectrum's shape."""
        from ...plotting import model_curve, plot_spectrum

        bands = frequency_bands(bands, "bands")
        return plot_spectrum(
            (self.frequency, self.z_data),
            model_curve(self),
            title=title or f"{self.model}   rms_rel = {self.rms_rel * 100:.3g} %   {self.weighting} weighting",  # (the weighting named, as the report does)
            bands=bands,
            model_label="fit",
            model_at_data=self.z_model,
            figsize=figsize,
        )

    def to_xarray(self) -> xr.Dataset:
        """Parameters (with stderr), covariance and the spectra as a Dataset, the residual
        ``residual_rel`` = (Z_model − Z)/|Z| (model minus data; docs/io.md, "Names and signs in a
        result's Dataset"); ``unit`` along
        ``param`` gives each parameter's unit (the element specs', as the CSV's ``unit``). Its attrs are Python
        objects (lists of warnings and groups, a dict of bounds) that ``.to_netcdf`` refuses, its
        error saying so: a file is written with ``impedax.write_result(result, "fit.nc")``, which
        encodes them (`impedax.io.netcdf.result_dataset`)."""
        names = list(self.values)
        free = list(self.free_names)
        specs = self.circuit.parameter_specs(self.registry)
        return result_dataset(xr.Dataset(
            {
                "value": ("param", [self.values[n] for n in names]),
                "stderr": ("param", [self.stderr[n] for n in names], {"note": STDERR_NOTE}),
                "linearised_stderr": ("param", [self.linearised_stderr[n] for n in names], {"long_name": LINEARISED_STDERR_NAME}),
                "fixed": ("param", [self.fixed[n] for n in names]),
                "at_bound": ("param", [n in self.at_bound for n in names]),
                "covariance": (("free_param", "free_param_2"), self.covariance, {"note": COVARIANCE_NOTE}),
                "correlation": (("free_param", "free_param_2"), self.correlation, {"note": CORRELATION_NOTE}),
                "Z": ("frequency", self.z_data, {"units": "ohm"}),
                "Z_model": ("frequency", self.z_model, {"units": "ohm"}),
                "residual_rel": ("frequency", self.residuals, {"units": "1", "long_name": RESIDUAL_LONG_NAME}),
            },
            coords={"param": names, "unit": ("param", [specs[n].unit for n in names], {"long_name": PARAMETER_UNIT_NAME}), "free_param": free, "free_param_2": free, "frequency": ("frequency", self.frequency, {"units": "Hz"})},
            attrs={
                "impedax_kind": "fit", "model": self.model, "weighting": self.weighting, "rms_rel": self.rms_rel, "chi2": self.chi2,
                "chi2_red": self.chi2_red, "aic": self.aic, "bic": self.bic, "converged": int(self.converged),
                "message": self.message, "warnings": list(self.warnings), "unidentified_groups": [list(g) for g in self.unidentified_groups],
                "n_evaluations": int(self.n_evaluations), "n_starts": int(self.n_starts), "elapsed_s": float(self.elapsed_s),
                "bounds": bounds_attr(self.bounds), "notes": list(self.notes), **note_value_attrs(self, flag=int),
            },
        ).copy(deep=True))  # (the user's to edit: the result's own arrays are read-only)

    @classmethod
    def from_xarray(cls, ds: xr.Dataset, *, registry: Registry | None = None) -> "FitResult":
        """Rebuild a fit from `FitResult.to_xarray` output: as returned, read back by
        `impedax.load`, or opened as stored (``xr.open_dataset`` of a file `impedax.write_result`
        or ``impedax fit --out FILE.nc`` wrote). ``registry``: the one the circuit's elements are
        in (None: the default one). A file written by older versions may lack the evaluation count,
        starts and time: 0, 1 and 0 s; or the unidentified groups: none.
        ``source`` is the data's file the saved result names (`impedax.io.netcdf.saved_source`;
        None in a file of older versions, which did not keep it)."""
        from ...io.netcdf import damaged_result, saved_result, saved_source  # (io is imported only here: rarely needed)

        registry = DEFAULT_REGISTRY if registry is None else registry
        if isinstance(ds, xr.Dataset) and "impedax_kind" not in ds.attrs and "value" in ds.variables and ds["value"].dims == ("param",) and "covariance" in ds.variables:  # (written before the kind was stored)
            ds = ds.assign_attrs(impedax_kind="fit")
        ds = saved_result(ds, "fit", variables=_FIT_VARIABLES, attrs=_FIT_ATTRS)
        with damaged_result("fit", ds):
            names = [str(n) for n in ds["param"].values]
            warnings = ds.attrs["warnings"]
            return cls(
                circuit=parse(ds.attrs["model"], registry),
                values={n: float(v) for n, v in zip(names, ds["value"].values)},
                stderr={n: float(v) for n, v in zip(names, ds["stderr"].values)},
                fixed={n: bool(v) for n, v in zip(names, ds["fixed"].values)},
                free_names=tuple(str(n) for n in ds["free_param"].values),
                covariance=np.asarray(ds["covariance"].values, float),
                correlation=np.asarray(ds["correlation"].values, float),
                frequency=np.asarray(ds["frequency"].values, float),
                z_data=np.asarray(ds["Z"].values, complex),
                z_model=np.asarray(ds["Z_model"].values, complex),
                weighting=str(ds.attrs["weighting"]),
                chi2=float(ds.attrs["chi2"]),
                converged=bool(ds.attrs["converged"]),
                message=str(ds.attrs["message"]),
                n_evaluations=int(ds.attrs.get("n_evaluations", 0)),
                warnings=(warnings,) if isinstance(warnings, str) else tuple(str(w) for w in warnings),
                n_starts=int(ds.attrs.get("n_starts", 1)),
                elapsed_s=float(ds.attrs.get("elapsed_s", 0.0)),
                at_bound=tuple(n for n, b in zip(names, ds["at_bound"].values) if bool(b)),
                unidentified_groups=parameter_groups(ds.attrs.get("unidentified_groups", ())),
                registry=registry,
                bounds=stored_bounds(ds.attrs.get("bounds")),
                source=saved_source(ds),
                notes=stored_notes(ds.attrs.get("notes", ())),  # (none in a file of older versions)
                **stored_note_values(ds.attrs, warnings),
            )


def stored_notes(notes) -> tuple[str, ...]:
    """A saved result's ``notes`` attribute (a text or a list of texts) as a tuple."""
    return (notes,) if isinstance(notes, str) else tuple(str(n) for n in notes)


_FIT_VARIABLES = ("value", "stderr", "fixed", "at_bound", "covariance", "correlation", "Z", "Z_model")
_FIT_ATTRS = ("model", "weighting", "chi2", "converged", "message", "warnings")


def embedded_fit(fit: FitResult, prefix: str, host_frequency=None, host_z=None) -> xr.Dataset:
    """``fit.to_xarray()`` to merge into another result's dataset (a refinement's final fit, a
    diagnosis' baseline): every variable, dimension and attribute named ``prefix`` + its own
    name (``final_fit_value`` over ``final_fit_param``, ...), so the host's names stay as they
    are. The frequency dimension is the host's own ``frequency`` and ``Z`` is left to the host
    where the fit's points and data are the host's (``host_frequency``, ``host_z``); otherwise
    they are prefixed too. `fit_from_embedded` reads it back."""
    ds = fit.to_xarray()
    shared = host_frequency is not None and np.array_equal(np.asarray(host_frequency, float), fit.frequency) and host_z is not None and np.array_equal(np.asarray(host_z), fit.z_data)
    if shared:
        ds = ds.drop_vars("Z")
    renamed = {name: prefix + name for name in ds.variables if not (shared and name == "frequency")}
    out = ds.rename(renamed)
    out.attrs = {prefix + k: v for k, v in ds.attrs.items() if k not in ("impedax_kind", NETCDF_ADVICE)}  # (the host's Dataset names how it is written)
    return out


def fit_from_embedded(ds: xr.Dataset, prefix: str, *, registry: Registry | None = None) -> FitResult:
    """The `FitResult` that `embedded_fit` stored in ``ds`` under ``prefix`` (``ds`` as returned
    or read back with `impedax.io.read_netcdf`)."""
    names = {name: name[len(prefix):] for name in ds.variables if str(name).startswith(prefix)}
    if not names:
        raise DataError(f"no fit stored under {prefix!r} (variables {prefix}value, {prefix}covariance, ...)", path=ds.encoding.get("source"))
    fit_ds = ds[[n for n in names if n in ds.data_vars]].rename(names)
    if "Z" not in fit_ds.variables:  # (the host's points and data: `embedded_fit` left them to it)
        fit_ds["Z"] = ds["Z"]
    fit_ds.attrs = {"impedax_kind": "fit", **{k[len(prefix):]: v for k, v in ds.attrs.items() if k.startswith(prefix)}}
    fit_ds.encoding["source"] = ds.encoding.get("source")
    return FitResult.from_xarray(fit_ds, registry=registry)


RESIDUAL_LONG_NAME = "(Z_model - Z_data)/|Z_data|"
"""The sign of `FitResult.residuals`, model minus data, as the ``long_name`` of ``residual_rel``
(the KK test's and the DRT's are data minus fit: docs/physics.md, "Goodness of fit")."""
# what `FitResult.to_xarray` says of its stderr, covariance and correlation (docs/fitting.md,
# "Standard errors at a bound")
STDERR_NOTE = "NaN: fixed, or at a bound (no symmetric standard error there); inf: a vanishing term's parameter"
COVARIANCE_NOTE = "the linearisation with every free parameter free, the bounds ignored (a vanishing term's parameters at no bound held for the others: no cross terms)"
LINEARISED_STDERR_NAME = "stderr with a parameter at a bound given the linearisation's (bounds ignored): not a ± error there, the scale of chi2's curvature"
PARAMETER_UNIT_NAME = "unit of each parameter (the element specs')"  # (the ``unit`` coordinate of a fit's to_xarray)
CORRELATION_NOTE = "NaN in the rows and columns of parameters without a standard error (at a bound, a vanishing term's)"


def parameter_groups(groups) -> tuple[tuple[str, ...], ...]:
    """Groups of parameter names (lists, e.g. as JSON or netCDF attributes store them) as
    `FitResult.unidentified_groups` holds them."""
    return tuple(tuple(str(n) for n in g) for g in groups)


def shown_stderr(stderr: float, fixed: bool) -> float | None:
    """A parameter's standard error as the JSON and the CSV give it: None when fixed or not
    finite (at a bound, a vanishing term's, an overflowed fit's)."""
    return None if fixed or not math.isfinite(stderr) else stderr


def value_shown_at_bound(name: str, value: float, notes) -> str:
    """A parameter at a bound as the tables write its value (``.5g``), or its bound where the
    fit's ``notes`` put it on a bound 0 or ∞ without a value ("R0 is at its lower bound 0",
    `bound_note` within `NUMERICALLY_ON_FRACTION`; a global fit's "shared R0 is ..."): there
    its digits are where the solver stopped, not what the data say, and a table that prints
    them (REAL exampleDataGamry.DTA with R0 + R1 || CPE1 + R2 || CPE2: "R0 1.2675e-05 at
    bound" beside "R0 is at its lower bound 0"; 5.75e-292 Ω in another run) would contradict the
    note. The JSON, CSV and netCDF keep the value as fitted."""
    for note in notes:
        for bound in ("0", "∞"):
            for side in ("lower", "upper"):
                text = f"{name} is at its {side} bound {bound}"
                if note.removeprefix("shared ") == text or note.removeprefix("shared ").startswith(text + " ("):
                    return bound
    return f"{value:.5g}"


def without_error(sides: np.ndarray, vanished: np.ndarray, free_stderr: np.ndarray, corr: np.ndarray | None = None):
    """What a fit reports of its free parameters' linearised standard errors ``free_stderr``
    (B, K): none (NaN) for those at a bound (``sides`` (B, K) nonzero), inf kept for a
    vanishing term's (``vanished``, `settle_vanishing`); and, given the linearisation's
    correlations ``corr`` (B, K, K), those with the rows and columns of both kinds NaN (the
    diagonal too): a correlation with a parameter without a standard error says nothing
    (docs/fitting.md, "Standard errors at a bound"). The other parameters keep the
    linearisation's: not held at the bound, which would understate them wherever the
    parameter trades against them."""
    sides, vanished = np.asarray(sides), np.asarray(vanished, bool)
    stderr = np.where((sides != 0) & ~vanished, np.nan, free_stderr)
    if corr is None:
        return stderr, None
    none = (sides != 0) | vanished
    corr = np.where(none[..., :, None] | none[..., None, :], np.nan, corr)
    return stderr, corr


# why two parameters of one element correlate, by the pair of their names
_PAIR_REASONS = {
    frozenset(("Q", "alpha")): " (a CPE's Q and α correlate when the data lie far from ω = 1 rad/s{})",
    # (Wo: Z = R coth(x)/x, x = √(jωτ), → R/(jωτ) + R/3 at ωτ ≪ 1, since coth x ≈ 1/x + x/3)
    # (a Gerischer, a Ws or a relaxation has the pair too: a walkthrough's G1 was told of a finite Warburg)
    frozenset(("R", "tau")): " (R and τ of one element correlate where the data see only one of its limits: at ωτ ≫ 1 a finite Warburg or a Gerischer acts as an infinite "
                             "Warburg, of which only R/√τ shows, and a relaxation as R/(jωτ)^α; at ωτ ≪ 1 an open Warburg (Wo) acts as a capacitor τ/R in series with R/3, the others as R alone)",
}
WELL_DETERMINED = 0.1
"""Relative standard errors up to which a correlated CPE's Q and α are called well determined."""


def correlated_note(a: str, b: str, r: float, relative_errors: tuple[float, float] | None = None) -> str:
    """"R0 and R1 are strongly correlated (r = -0.995); …", with why for a pair of one element.
    A CPE's Q and α are called still well determined only when both ``relative_errors`` (the
    linearisation's, |stderr/value|) are finite and at most `WELL_DETERMINED`; otherwise the
    note says their standard errors already hold the correlation, quoting them. Two parameters
    of different elements are told their linearised ± may understate their spread."""
    parts = correlated_note_parts(a, b)
    if parts is not None:
        return f"{parts[0]}{r:+.3f}{parts[1]}"
    ea, eb = (math.nan, math.nan) if relative_errors is None else relative_errors
    errors = f"{format_relative_error(ea)} and {format_relative_error(eb)}"
    well = math.isfinite(ea) and math.isfinite(eb) and max(ea, eb) <= WELL_DETERMINED
    why = _pair_why(a, b).format(f"; both are still well determined (relative errors {errors})" if well else f"; their standard errors ({errors}) already include the correlation" if relative_errors is not None else "")
    return f"{a} and {b} are strongly correlated (r = {r:+.3f}){why}"


@functools.lru_cache(maxsize=1024)
def _pair_why(a: str, b: str) -> str:
    """Why parameters ``a`` and ``b`` correlate, as `correlated_note` says it ("{}" where a CPE's
    pair quotes their relative errors)."""
    (owner_a, _, name_a), (owner_b, _, name_b) = a.rpartition("."), b.rpartition(".")
    why = _PAIR_REASONS.get(frozenset((name_a, name_b)), "; the data barely tell them apart") if owner_a and owner_a == owner_b else "; the data barely tell them apart"
    if why == "; the data barely tell them apart":  # (|r| > CORRELATION_LIMIT: SYNTHETIC two-arc fits, R1 and R2 at r = −0.999, covered the truth at ±2σ in 70 % of copies)
        why += "; in so narrow a valley the linearised ± may understate their spread: impedax sample gives the posterior's"
    return why


@functools.lru_cache(maxsize=1024)
def correlated_note_parts(a: str, b: str) -> tuple[str, str] | None:
    """`correlated_note` of parameters ``a`` and ``b`` as the text before and after its r (``+.3f``),
    None for a pair whose note quotes their relative errors (a CPE's Q and α): built once per
    pair, not once per note (`stack_notes`: ~1,400 notes in a batch of 1,000 REAL battery spectra)."""
    why = _pair_why(a, b)
    return None if "{}" in why else (f"{a} and {b} are strongly correlated (r = ", f"){why}")


def _relative_error(value: float, stderr: float) -> float:
    """|stderr/value|, NaN where the value is 0."""
    return abs(stderr / value) if value else math.nan


def undetermined_note(name: str, relative_error: float) -> str:
    """"R1 has a relative standard error of 126 %: it is not determined by the data" (as the fit
    table writes it, `format_relative_error`); "has no finite standard error" where it is not
    finite."""
    if not math.isfinite(relative_error):
        return f"{name} has no finite standard error: it is not determined by the data"
    return f"{name} has a relative standard error of {format_relative_error(relative_error)}: it is not determined by the data"


def bound_note(name: str, bound: float, side: str, *, value: float | None = None, stderr: float | None = None, unit: str = "", on: bool = False) -> str:
    """The note of a parameter at its ``side`` ("lower"/"upper") bound: on it (`on_bound`; ``on``
    with its ``value``, or no value), "R0 is at its lower bound 0", or at a lower bound 0 that its
    value (in ``unit``) approaches without reaching it (fitted in log space, `Transform.LOG`),
    "W1.sigma = 677 µΩ s^-1/2 runs to its lower bound 0 (...)": a bare "at its lower bound
    0" beside a value that is not 0 read as a contradiction; off it (``value`` and its
    ``stderr`` given: the linearisation's, bounds ignored) but not told from it by the data,
    "R1 = 79.6 MΩ cannot be told from its lower bound 0 (linearised standard error 1.3e+18 Ω,
    bounds ignored)": the numbers as the report writes them (`format_quantity`: SI prefix on the
    leading unit, not "7.96e+07 Ω", "0.000677 Ω s^-1/2"); the result gives a parameter at a bound no standard error (JSON null), so
    the note names the number as the JSON's ``linearised_stderr`` (not "(standard error
    1.3e+18 Ω)" beside the JSON's null)."""
    at = format_bound(bound, unit)
    if value is not None and on and bound == 0 and side == "lower" and value != 0:
        return f"{name} = {format_quantity(value, unit)} runs to its lower bound 0 (fitted in log space, it approaches 0 without reaching it; to the data it is 0)"
    if value is None or on:
        return f"{name} is at its {side} bound {at}"
    return f"{name} = {format_quantity(value, unit)} cannot be told from its {side} bound {at} (linearised standard error {format_quantity(stderr, unit, 2)}, bounds ignored)"


def on_bound(table: ParameterTable, values: np.ndarray, sides: np.ndarray, freq=None, z=None, fraction: float = ON_BOUND_FRACTION) -> np.ndarray:
    """Whether the parameters at a bound (``sides`` (B, K) nonzero, `confirm_bounds`) of fits
    with values (B, P) to spectra ``z`` (B, N) at ``freq`` (N,) are numerically on it: within
    ``fraction`` (`ON_BOUND_FRACTION`) of the bound, or of a bound 0, of the data's scale for
    the unit (a unit without one: only exactly on 0). Without the data (``z`` None) every one
    counts as on. (B, K) bool, false where ``sides`` is 0."""
    sides = np.asarray(sides)
    flagged = sides != 0
    if z is None or not flagged.any():
        return flagged
    free = table.free_index
    v = np.asarray(values, float)[..., free]
    bound = np.where(sides > 0, table.upper[free], table.lower[free])
    scale = np.abs(bound)
    z_abs = np.abs(np.asarray(z))
    for j in np.flatnonzero((flagged & (bound == 0)).any(axis=0)).tolist():
        unit = table.units[free[j]]
        x = data_scales(unit, freq, z_abs)
        with np.errstate(invalid="ignore"):
            s = np.ones(len(v)) if unit == "1" else np.zeros(len(v)) if x is None else np.min(np.where(np.isfinite(x) & (x > 0), x, np.inf), axis=-1)
        scale[:, j] = np.where(bound[:, j] == 0, np.where(np.isfinite(s), s, 0.0), scale[:, j])
    with np.errstate(invalid="ignore"):
        return flagged & (np.abs(v - bound) <= fraction * scale)


def _bound_note_of(table: ParameterTable, b: int, j: int, values: np.ndarray, stderr: np.ndarray, sides: np.ndarray, on: np.ndarray, exactly: np.ndarray) -> str:
    """`bound_note` of free parameter j of fit b (values, stderr (B, P); sides, on (B, K));
    ``exactly`` (B, K): on it within `NUMERICALLY_ON_FRACTION`, its value not given. At a bound
    where its element is a simpler one (``table.reductions``: a CPE's α at 1) the note names the
    simpler model: "CPE2.alpha is at its upper bound 1 (CPE2 with alpha = 1 is a capacitor: the
    model with C2 in its place may be enough)"."""
    i = table.free_index[j]
    side = "upper" if sides[b, j] > 0 else "lower"
    bound = float(table.upper[i] if sides[b, j] > 0 else table.lower[i])
    if exactly[b, j]:
        note = bound_note(table.names[i], bound, side, unit=table.units[i])
    else:
        note = bound_note(table.names[i], bound, side, value=float(values[b, i]), stderr=float(stderr[b, i]), unit=table.units[i], on=bool(on[b, j]))
    reduced_side, simpler = table.reductions.get(table.names[i], (None, ""))
    return f"{note} ({simpler})" if reduced_side == side else note


def bound_sides(table: ParameterTable, values: np.ndarray, stderr: np.ndarray | None) -> np.ndarray:
    """Candidates for a bound, (…, K) over the free parameters: +1 upper, −1 lower, 0 none,
    from values and stderr (…, P): within 1e-4 relative of a nonzero finite bound, or (given
    stderr) within `BOUND_STDERR_FRACTION` standard errors of a finite bound (a series R
    creeping to 0 under the log transform, a CPE α to 1 under the logistic)."""
    free = table.free_index
    v = np.asarray(values, float)[..., free]
    lo, hi = table.lower[free], table.upper[free]
    with np.errstate(invalid="ignore", over="ignore"):
        near_hi = np.isfinite(hi) & (np.abs(v - hi) <= 1e-4 * np.maximum(np.abs(hi), 1e-12))
        near_lo = (lo > 0) & np.isfinite(lo) & (np.abs(v - lo) <= 1e-4 * lo)
        if stderr is not None:
            e = np.asarray(stderr, float)[..., free]
            within = np.isfinite(e) & (e > 0)
            near_hi |= within & np.isfinite(hi) & (np.abs(hi - v) <= BOUND_STDERR_FRACTION * e)
            near_lo |= within & np.isfinite(lo) & (np.abs(v - lo) <= BOUND_STDERR_FRACTION * e)
    return np.where(near_hi, 1, np.where(near_lo, -1, 0)).astype(np.int8)


def confirm_bounds(table: ParameterTable, values: np.ndarray, sides: np.ndarray, chi2_at_x: Callable, n_residuals: int) -> np.ndarray:
    """`bound_sides` candidates (B, K) of fits with values (B, P), kept where setting the
    parameter exactly to its bound raises chi² by at most `BOUND_CHI2_FRACTION` of the reduced
    chi² (a bound optimum lowers it or leaves it). ``chi2_at_x(points (C, K), spectrum (C,))``
    gives the weighted chi² of fit ``spectrum`` at free values ``points`` (weights scaled as
    the solver's, `problem.residual_scale`)."""
    rows, cols = np.nonzero(sides)
    if rows.size == 0:
        return sides
    free = table.free_index
    x = np.asarray(values, float)[:, free]
    fits, local = np.unique(rows, return_inverse=True)
    moved = x[rows].copy()
    moved[np.arange(rows.size), cols] = np.where(sides[rows, cols] > 0, table.upper[free][cols], table.lower[free][cols])
    chi2 = np.asarray(chi2_at_x(np.concatenate([x[fits], moved]), np.concatenate([fits, rows])), float)
    chi2_fit, chi2_bound = chi2[: fits.size][local], chi2[fits.size :]
    chi2_red = chi2_fit / max(n_residuals - free.size, 1)
    with np.errstate(invalid="ignore"):
        # (plus rounding: residuals of relative size 1e-14 each, for fits to exact data)
        keep = np.isfinite(chi2_bound) & (chi2_bound - chi2_fit <= BOUND_CHI2_FRACTION * chi2_red + n_residuals * 1e-28)
    out = sides.copy()
    out[rows[~keep], cols[~keep]] = 0
    return out


BOUND_RESTARTS = 3
"""Restarts from inside the bounds of a fit stopped at a bound while chi² falls inward
(`falling_inward`; `single.restarted_inward`, `batch.restarted_inward`)."""


# fractions of the Newton step along a parameter's valley (its partners following) at which
# `falling_inward` measures chi²: on the SYNTHETIC two-arc copy of its docstring the whole step
# (α₁ 1 → 0.86) raised chi² 31×, a quarter 7 %, a tenth lowered it by 0.6 %, 600× the tolerance
VALLEY_FRACTIONS = (1.0, 1 / 4, 1 / 16, 1 / 64)


def falling_inward(table: ParameterTable, values: np.ndarray, jacobian: np.ndarray, z, z_model, inv_re, inv_im, weighting: str, chi2_at_x: Callable) -> tuple[np.ndarray, np.ndarray]:
    """Free parameters of fits (values (B, P); Jacobians of the weighted residuals (B, 2N, K);
    spectra, models and inverse weights (B, N)) that sit at a bound (`bound_sides`, by their
    linearised standard errors) while chi² falls *inward*: the gradient of chi² points into the
    bounds, and moving the parameter alone (the others held) either by its Newton step or to
    the restart point, at least `starts.INSIDE_FRACTION` of its span inside
    (`starts.inward_start`), or moving it by the Newton step that lets the others follow
    (``−(JᵀJ)⁻¹[:, k]·g_k``, the valley's direction, and `VALLEY_FRACTIONS` of it: the valley
    curves away from the straight step), lowers chi² by more
    than `BOUND_CHI2_FRACTION` of the reduced chi² (rule 2's tolerance, plus rounding). In a
    valley where the parameter is correlated with others (a CPE's α with its Q, started at
    α = 1) the restart point held alone is far up the valley's side, and where the correlation
    is strong even the short Newton step along the parameter alone promises less than the
    tolerance (its gain g_k²/(JᵀJ)_kk against g_k²·((JᵀJ)⁻¹)_kk when the others follow):
    SYNTHETIC two-arc copies in a batch started from a reference optimum at α₁ = 1 stayed
    there, chi² 4 % above their interior optimum (docs/fitting.md, "Convergence and bounds").
    The chi² is measured (``chi2_at_x(points (C, K), fit (C,))``, as `confirm_bounds`), not
    predicted: in the flat valley of a vanishing term the linear model promised a fall the
    steps never give. Such a fit is not at a bound optimum: the solver stopped where its
    bounded coordinate is flat. Returns the sides (B, K) (+1 upper, −1 lower, 0 none) and the
    Newton step of each parameter along it alone (B, K)."""
    jac = np.asarray(jacobian, float)
    b, k = jac.shape[0], jac.shape[-1]
    if not k:
        return np.zeros((b, 0), np.int8), np.zeros((b, 0))
    values = np.asarray(values, float)
    dz = np.asarray(z_model) - np.asarray(z)
    r = np.concatenate([dz.real * np.asarray(inv_re), dz.imag * np.asarray(inv_im)], axis=-1)
    n_res = r.shape[-1]
    with np.errstate(all="ignore"):
        chi2 = np.sum(r**2, axis=-1)
        chi2_red = chi2 / max(n_res - k, 1)
        finite = np.isfinite(chi2) & np.all(np.isfinite(jac), axis=(-2, -1))
        safe = jac if finite.all() and jac.flags.c_contiguous else np.where(finite[:, None, None], jac, 0.0)  # (np.where's copy only where needed)
        g = np.einsum("bmk,bm->bk", safe, np.where(finite[:, None], r, 0.0))  # ½ ∂chi²/∂x
        h = np.einsum("bmk,bmk->bk", safe, safe)  # ½ ∂²chi²/∂x² (Gauss–Newton)
        step = np.where(h > 0, -g / h, 0.0)
        tol = BOUND_CHI2_FRACTION * chi2_red + n_res * 1e-28
        # (JᵀJ)⁻¹ of every fit: the gain of a parameter whose correlated partners follow it,
        # g_k²·((JᵀJ)⁻¹)_kk ≥ g_k²/(JᵀJ)_kk, and the standard errors that place it at a bound
        inverse = covariances(safe, np.ones(b), "sigma")[0]
        gain = g**2 * np.clip(np.nan_to_num(np.einsum("bii->bi", inverse), nan=0.0, posinf=np.inf), 0, None)
        falls = finite[:, None] & (gain > tol[:, None])
        sides = np.zeros((b, k), np.int8)
        rows = np.flatnonzero(falls.any(axis=1))  # (an optimum inside its bounds has none)
        if rows.size:
            cov = inverse[rows] if weighting == "sigma" else inverse[rows] * chi2_red[rows, None, None]
            stderr = np.full((rows.size, values.shape[-1]), np.nan)
            stderr[:, table.free_index] = np.sqrt(np.clip(np.einsum("bii->bi", cov), 0, None))
            sides[rows] = bound_sides(table, values[rows], stderr)
        inward = falls & (sides * g > 0)
    fit_rows, cols = np.nonzero(inward)
    if fit_rows.size:  # the fall measured: each parameter moved alone (to the restart, by its Newton step) and with its partners following
        free = table.free_index
        one = np.zeros((fit_rows.size, k), np.int8)
        one[np.arange(fit_rows.size), cols] = sides[fit_rows, cols]
        moved = inward_start(table, values[fit_rows], one, step[fit_rows])[:, free]
        newton = inward_start(table, values[fit_rows], one, step[fit_rows], fraction=0.0)[:, free]
        with np.errstate(all="ignore"):
            valley = -np.nan_to_num(inverse[fit_rows, :, cols] * g[fit_rows, cols][:, None], nan=0.0, posinf=0.0, neginf=0.0)
        followed = []
        for fraction in VALLEY_FRACTIONS:
            point = values[fit_rows].copy()
            point[:, free] = point[:, free] + fraction * valley
            followed.append(well_inside(point, table, 0.0)[:, free])
        fits = np.unique(fit_rows)
        measured = np.asarray(chi2_at_x(np.concatenate([values[fits][:, free], moved, newton, *followed]), np.concatenate([fits, *[fit_rows] * (2 + len(VALLEY_FRACTIONS))])), float)
        here = measured[: fits.size][np.searchsorted(fits, fit_rows)]
        there = measured[fits.size :].reshape(2 + len(VALLEY_FRACTIONS), fit_rows.size)
        with np.errstate(invalid="ignore"):
            fell = np.any(np.isfinite(there) & (there < here - (BOUND_CHI2_FRACTION * here / max(n_res - k, 1) + n_res * 1e-28)), axis=0)
        inward[fit_rows[~fell], cols[~fell]] = False
    return np.where(inward, sides, 0).astype(np.int8), step


def inward_message(table: ParameterTable, sides) -> str:
    """The message of a fit left at a bound while chi² falls inward (`falling_inward`)."""
    parts = []
    free = table.free_index
    for j in np.flatnonzero(np.asarray(sides)).tolist():
        i = free[j]
        side = "upper" if sides[j] > 0 else "lower"
        bound = float(table.upper[i] if sides[j] > 0 else table.lower[i])
        parts.append(f"{table.names[i]} at its {side} bound {format_bound(bound, table.units[i])}")
    return (
        f"stopped with {' and '.join(parts)} while chi² falls away from the bound (moving inward lowers it): "
        "not the optimum within the bounds; restarts from inside did not leave it — check the bounds or give init inside them"
    )


def vanishing_term_sides(circuit: Circuit, registry: Registry, table: ParameterTable, values: np.ndarray, sides: np.ndarray, freq, z, jacobian=None) -> np.ndarray:
    """Bound sides (B, K) of fits with values (B, P) to spectra z (B, N), without those
    `confirm_bounds` gave only because the parameter's term vanishes: off its bound (not
    `on_bound`), in a term whose share stays below `branches.VANISHING_SHARE` at every
    frequency, where `vanishing_parameters` does not name that side as the one that makes the
    term vanish (it names the other, or neither). Rule 2 of `confirm_bounds` holds there only
    because the term is invisible at any value, the bound included: the parameter is
    undetermined, not at the bound (the idle note says why). The one circuit in two orders,
    whose fits stop at two points of one flat valley, said "R1 = 2.12e+16 Ω cannot be told
    from its lower bound 0" of an open branch R1 + W1 in one order (W1.sigma = 6.6e7 keeps it
    open at R1 = 0) and "R1 … is not determined" in the other (W1.sigma = 1.9e7: CH
    Instruments' example, R0 + (R1 + W1) || CPE1)."""
    sides = np.asarray(sides)
    off = (sides != 0) & ~on_bound(table, values, sides, freq, z)
    if not off.any():
        return sides
    codes = vanishing_parameters(circuit, registry, table, values, freq, off, jacobian)
    return np.where(off & (codes != 0) & (codes != sides), 0, sides).astype(sides.dtype)


def at_bound_names(table: ParameterTable, sides: np.ndarray) -> tuple[str, ...]:
    """The free parameters of one fit whose side (K,) is nonzero."""
    return tuple(n for n, side in zip(table.free_names, np.asarray(sides).tolist()) if side)


DOMINATED_WORDS = "the fit is dominated by them"
"""The words of every `weighting_notes` warning (`is_dominated_note`)."""


def is_dominated_note(text: str) -> bool:
    """Whether a fit's warning ``text`` is a `weighting_notes` one (a fit dominated by a few points)."""
    return DOMINATED_WORDS in text


def dominated_notes(weighting: str, freq, z, inv_re, inv_im) -> list[tuple[str, ...]]:
    """`weighting_notes` of spectra Z (B, N) under ``weighting``, whose inverse weights are
    ``inv_re``, ``inv_im``: `unit` and `proportional` fits are checked, `modulus` and `sigma`
    ones are not (one tuple per spectrum). Single, batch and candidate fits (those of `diagnose`
    and `refine`) all take it from here."""
    z = np.atleast_2d(z)
    if weighting not in ("unit", "proportional"):
        return [()] * len(z)
    return weighting_notes(weighting, freq, *dominant_points(z, np.atleast_2d(inv_re), np.atleast_2d(inv_im)))


def weighting_notes(weighting: str, freq, points: np.ndarray, share) -> list[tuple[str, ...]]:
    """The weighting warning of fits whose weight sits on a few points (`dominant_points`
    over (B, N), shares (B,)): one tuple per fit, empty where the weighting is even."""
    out: list[tuple[str, ...]] = []
    freq = np.asarray(freq, float)
    for row, s in zip(np.atleast_2d(points), np.atleast_1d(share).tolist()):
        if not row.any():
            out.append(())
            continue
        where = ", ".join(format_frequency(f) for f in np.sort(freq[row]))  # (238 kHz, as impedax writes frequencies, not "2.383e+05 Hz")
        out.append((
            f"the {weighting} weighting gives {int(row.sum())} of {row.size} points {s * 100:.0f} % of the weight ({where}): "
            f"{DOMINATED_WORDS}; consider weighting='modulus'",
        ))
    return out


def unused_sigma_notes(has_sigma: bool, weighting: str) -> tuple[str, ...]:
    """The note of a fit whose data carry σ per point (``has_sigma``: a ``sigma`` variable, from
    ``make_spectrum(sigma=...)`` or a file's sigma column) that its ``weighting`` does not use
    (any but ``sigma``): advice, not a warning (`FitResult.notes`). A walkthrough's σ was ignored
    by the Python fit without a word, its |Z|-weighted standard errors 3.4× too large (R_s) and
    0.55× too small (R_p) on noise 10× larger below 10 Hz; the command line said it on stderr."""
    if not has_sigma or weighting == "sigma":
        return ()
    return (
        f"the data carry sigma (σ per point), which this fit's {weighting} weighting does not use: weighting='sigma' "
        "weighs each point by it and takes the standard errors from it, where this weighting scales them to the residuals as if the noise were "
        + ("proportional to |Z|" if weighting == "modulus" else "the same after its weights"),
    )


# a fit's weighted residuals are compared band by band (`uneven_residual_notes`) in bands of this
# many consecutive frequencies (the last band takes the remainder of fewer): a fixed count, not a
# decade, so that one threshold holds at any point density (a band's rms² of 2×8 real residuals
# scatters as χ²₁₆/16 under uniform noise, its rms within 0.5–1.4× of the truth at 99.8 %), and
# fine enough to place noise that changes within two decades (`LOCAL_WINDOW` of the diagnosis's
# noise estimate is 9 for the same reason)
UNEVEN_BAND_POINTS = 8
# ... and a fit is told that the noise its weighting assumes is uneven where the largest band's rms
# exceeds the smallest's by more than this. Measured 2026-12-01 (SYNTHETIC R0 + R1 ∥ CPE1 and
# R0 + R1 ∥ CPE1 + R2 ∥ CPE2, 50 and 60 points over 7 decades, uniform complex noise 0.2–2 % of
# |Z| log-uniform, modulus weighting; 200 batch fits and 50 single fits): the ratio's median 1.55,
# 99th percentile 2.35, largest 2.53, no warning; pure noise in bands of 8 points stays above 4×
# in 0.1 % of spectra of 400 points (50 bands), never at 50. The audit's uneven case (noise 5×
# larger below 1 Hz, 0.2 % and 1 % base): ratio median 6.4, warned in 147 of 150 spectra (98 %)
UNEVEN_RESIDUAL_RATIO = 4.0
# ... checked for these weightings only: theirs is a noise model (σ ∝ |Z|; the stated σ), while
# unit and proportional weights are not meant as one (`weighting_notes` speaks for them)
UNEVEN_CHECKED_WEIGHTINGS = ("modulus", "sigma")
UNEVEN_NOISE_NOTE = "the standard errors assume the noise is uniform after the weighting"
SIGMA_BAND_WORDS = "the data's sigma understates the noise at"
"""The words of `uneven_residual_notes`' warning under sigma weighting (the stated σ misstates the
noise in one band), by which a caller whose σ is known to hold more than noise recognises it."""
SIGMA_OVERSTATES_WORDS = "σ overstates the noise"
"""The words of `sigma_scale_notes`' warning of residuals far below σ, likewise."""
SIGMA_OF_TRIAL_MEANS_WORDS = "σ is the standard error of trial means"
"""The words of `sigma_scale_notes`' note of residuals far below a σ that is the standard error of
trial means (`trial_means_of_sigma`), in place of `SIGMA_OVERSTATES_WORDS`."""


SIGMA_SOURCES_ATTR = "sigma_sources"
"""The attr of a remainder (`sirin.remaining_impedance`) that says what its ``sigma`` is made of,
as data: input name ("total", "skin", "touchscreen") → `SIGMA_FROM_TRIALS` (the standard error
of its trials' mean) or `SIGMA_FROM_OWN` (its own stated sigma: one spectrum), written only
when the remainder has a sigma (a remainder saved by older versions carries the words of
``sigma_method`` alone, from which its provenance is read back)."""
SIGMA_FROM_TRIALS = "trial scatter"
SIGMA_FROM_OWN = "own sigma"
SIGMA_FROM_NONE = "none"
"""`sirin.trial_mean`'s ``sigma_from``, and the values of `SIGMA_SOURCES_ATTR`: the error of a
mean over trials, of one spectrum's own sigma, or of one spectrum without (unknown)."""


def sigma_sources(attrs) -> dict[str, str] | None:
    """A remainder's `SIGMA_SOURCES_ATTR` (input → `SIGMA_FROM_TRIALS` or `SIGMA_FROM_OWN`), also
    as ``xr.open_dataset`` leaves it (impedax's "json:" text of a dict attr); None without one (a
    spectrum not from `sirin.remaining_impedance`, or a remainder saved by older versions)."""
    value = (attrs or {}).get(SIGMA_SOURCES_ATTR)
    if isinstance(value, str) and value.startswith("json:"):
        import json

        try:
            value = json.loads(value[len("json:"):])
        except ValueError:
            return None
    return {str(k): str(v) for k, v in value.items()} if isinstance(value, dict) else None


def names_in_words(names) -> str:
    """``names`` as a sentence lists them: "total, skin and touchscreen"."""
    names = list(names)
    return names[0] if len(names) == 1 else f"{', '.join(names[:-1])} and {names[-1]}"


def trial_means_of_sigma(attrs) -> str | None:
    """What a spectrum's σ is the standard error of, by its attrs, when it is one of means over
    trials (``sigma_method`` naming the SEM, as `sirin.remaining_impedance` writes it, with its
    ``n_trials_total`` of two trials or more, and ``n_trials_skin``, ``n_trials_touchscreen``):
    "30 total, 30 skin, 30 touchscreen spectra"; an input of one spectrum that gave its stated
    sigma is named by that provenance, in `diagnosis.noise.sigma_origin`'s words: "30 total spectra,
    and the stated sigma of skin and touchscreen (one spectrum each), added in quadrature" (not
    "1 skin, 1 touchscreen" spectra of trial means); None
    otherwise (a sigma column, whose origin impedax does not know). Read from the remainder's
    `SIGMA_SOURCES_ATTR`; a remainder saved by older versions has none, and its ``sigma_method``
    words are read instead. A total of one spectrum with its stated sigma, less skin and screen
    means over trials, gives None, as docs/models.md says of gap's fits: only the total's trials
    put the contact's variation between touches into σ, and σ is then mostly the total's stated
    sigma of one touch (on a SYNTHETIC contact, 93 % of σ² at a stated 0.02 % of |Z|, the skin and
    screen means over 30 trials of a 5 % spread the rest), so residuals far below it do say that
    σ overstates the noise, as the fit's general note has it (such a σ is not named
    trial means)."""
    attrs = attrs or {}
    counts = {name: attrs.get(f"n_trials_{name}") for name in ("total", "skin", "touchscreen")}
    counts = {name: int(n) for name, n in counts.items() if n is not None}
    sources = sigma_sources(attrs)
    if sources is not None:
        means = [name for name, source in sources.items() if source == SIGMA_FROM_TRIALS]
        stated = [name for name, source in sources.items() if source == SIGMA_FROM_OWN]
        if sources.get("total") != SIGMA_FROM_TRIALS:  # (the total of one spectrum: see above)
            return None
        words = ", ".join(f"{counts[name]} {name}" if name in counts else name for name in means) + " spectra"
        return f"{words}, and the stated sigma of {names_in_words(stated)} (one spectrum{'' if len(stated) == 1 else ' each'}), added in quadrature" if stated else words
    method = str(attrs.get("sigma_method", ""))  # (a remainder saved by older versions: its words)
    if "sem" not in method.lower():
        return None
    stated = re.search(r"the stated sigma of (.+?) \((one spectrum[^)]*)\)", method)
    stated_names = re.findall(r"\b(total|skin|touchscreen)\b", stated.group(1)) if stated else []
    if counts.get("total", 0) < 2:
        return None
    means = ", ".join(f"{n} {name}" for name, n in counts.items() if name not in stated_names) + " spectra"
    return f"{means}, and the stated sigma of {stated.group(1)} ({stated.group(2)}), added in quadrature" if stated else means


# a fit whose residuals are, in rms, at most this fraction of |Z| matches its data to rounding
# (SYNTHETIC data without noise: 1e-16–1e-13 after a converged fit); the notes that judge the
# residuals' statistics (uneven bands, the F-test of a sharing) have no noise to judge there
ROUNDING_RESIDUAL = 1e-10


def at_rounding(z, z_model) -> np.ndarray:
    """Per fit z_model (B, N) of spectra z (B, N): whether its residuals, rms of |ΔZ|/|Z|, are at
    most `ROUNDING_RESIDUAL` (the data matched to rounding)."""
    z, z_model = np.atleast_2d(z), np.atleast_2d(z_model)
    with np.errstate(all="ignore"):
        rms = np.sqrt(np.mean(np.abs((z_model - z) / np.abs(z)) ** 2, axis=-1))
    return np.isfinite(rms) & (rms <= ROUNDING_RESIDUAL)


def residual_band_rms(freq, z, z_model, inv_re, inv_im) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The rms of the weighted residuals ((ΔRe·inv_re, ΔIm·inv_im), both counted) of fits
    z_model (B, N) of spectra z (B, N) in bands of `UNEVEN_BAND_POINTS` consecutive frequencies
    (ascending; a last band of fewer joins the one before): (B, bands) rms, and each band's
    lowest and highest frequency [Hz]."""
    freq = np.asarray(freq, float)
    order = np.argsort(freq)
    z, z_model = np.atleast_2d(z)[:, order], np.atleast_2d(z_model)[:, order]
    inv_re = np.broadcast_to(np.atleast_2d(inv_re), z.shape)[:, order]
    inv_im = np.broadcast_to(np.atleast_2d(inv_im), z.shape)[:, order]
    n_bands = max(freq.size // UNEVEN_BAND_POINTS, 1)
    edges = np.arange(n_bands + 1) * UNEVEN_BAND_POINTS
    edges[-1] = freq.size
    with np.errstate(all="ignore"):  # (an overflowed fit's rms is inf: no note)
        dz = z_model - z
        squared = (dz.real * inv_re) ** 2 + (dz.imag * inv_im) ** 2
        rms = np.stack([np.sqrt(np.mean(squared[:, a:b], axis=-1) / 2.0) for a, b in zip(edges[:-1], edges[1:])], axis=-1)
    f = freq[order]
    return rms, f[edges[:-1]], f[edges[1:] - 1]


def uneven_residual_notes(freq, z, z_model, inv_re, inv_im, weighting: str, misfit=None, *, has_sigma: bool = False, trial_means: str | None = None) -> list[tuple[str, ...]]:
    """The warning of each fit z_model (B, N) of spectra z (B, N) whose weighted residuals
    (inverse weights inv_re, inv_im as `problem.weights`) are over `UNEVEN_RESIDUAL_RATIO`× larger
    in rms in one band of frequencies than in another (`residual_band_rms`): the standard errors
    assume the weighting's noise is the same everywhere, so they are wrong there (an audit's
    SYNTHETIC R0 + R1 ∥ CPE1 with noise 5× larger below 1 Hz: R1's 1σ interval held the truth
    in 42 % of spectra, the sigma weighting's in 65–71 %). Only for `UNEVEN_CHECKED_WEIGHTINGS`,
    none for a fit that matches its data to rounding (`at_rounding`: no noise to be uneven),
    and none where ``misfit`` (`misfit_notes`, one tuple per fit) has a note other than that the
    data limit the fit (`DATA_LIMIT_NOTE`, whose noise may be the uneven one): a model that misses
    structure concentrates its residuals where it fails, and that note says so and where to look;
    one over the data's σ already asks for the sigma weighting.
    The text names the bands and the threshold, not the fit's ratio, so that a batch's fit
    gives a single fit's text (as `misfit_notes`), and whether the quiet band lies at lower or
    higher frequencies, so that a batch's grouped line holds fits of one direction only (its
    bands' envelopes would overlap were spectra loud at the low end and at the high end one
    kind: "larger at 21 mHz – 9.9 kHz than at 21 mHz – 4.36 Hz", REAL battery cycles). Its advice follows the weighting: under
    ``modulus`` to weigh by σ (``has_sigma``: the data carry one, which the fit did not use), the
    fit's and the sampler's way alike (the sampler's default noise model is the same σ ∝ |Z|, so
    it is no remedy); under ``sigma`` that the stated σ misstates the noise in one of the bands,
    or, where σ is the standard error of trial means (``trial_means``, `trial_means_of_sigma`),
    that the fit of the mean can take the trials' variation it holds up in one band and not in
    another (SYNTHETIC Sirin example of seed 4: its σ is not to be "checked" as a sigma
    column). The note is a `notes.Note` tagged `notes.UNEVEN_NOISE` (`UNEVEN_NOISE_NOTE` is its
    words), and `notes.SIGMA_RESIDUAL` where weighted by σ (what σ is, or that it misstates the
    noise in a band; `SIGMA_BAND_WORDS`, `SIGMA_OF_TRIAL_MEANS_WORDS` are its words)."""
    z = np.atleast_2d(z)
    out: list[tuple[str, ...]] = [()] * len(z)
    if weighting not in UNEVEN_CHECKED_WEIGHTINGS or np.asarray(freq).size < 2 * UNEVEN_BAND_POINTS:
        return out
    rms, lo, hi = residual_band_rms(freq, z, z_model, inv_re, inv_im)
    # (the rule for every fit at once; text for those it flags)
    louds, quiets = np.argmax(rms, axis=-1), np.argmin(rms, axis=-1)
    every = np.arange(len(rms))
    uneven = np.all(np.isfinite(rms), axis=-1) & ~at_rounding(z, z_model) & (rms[every, louds] > UNEVEN_RESIDUAL_RATIO * rms[every, quiets])
    for i in np.flatnonzero(uneven).tolist():
        if misfit is not None and misfit[i] and not _data_limit_note(misfit[i][0]):
            continue
        loud, quiet = int(louds[i]), int(quiets[i])
        loud_band, quiet_band = f"{format_frequency(lo[loud])} – {format_frequency(hi[loud])}", f"{format_frequency(lo[quiet])} – {format_frequency(hi[quiet])}"
        if weighting == "sigma" and trial_means:
            remedy = (f"{SIGMA_OF_TRIAL_MEANS_WORDS} ({trial_means}), which holds how the trials differ as well as the noise, and the fit of the mean "
                      "can take that difference up into its parameters in one band and not in another, so residuals uneven against σ need not mean "
                      "that σ misstates the noise there; fit each trial for the parameters' spread between trials (impedax remaining --trials)")
        elif weighting == "sigma":
            remedy = (f"{SIGMA_BAND_WORDS} {loud_band} or overstates it at {quiet_band}: check the sigma column "
                      "there (impedax sample --noise sigma takes σ as stated too)")
        else:
            # (both ways of giving σ, in words the command line's phrasing leaves alone: its report and its JSON say the same)
            remedy = ("if the noise is larger there, weigh by σ: the data carry a sigma column, which this weighting does not use (impedax fit --weighting sigma; impedax sample --noise sigma)"
                      if has_sigma else
                      "if the noise is larger there, give sigma (a sigma column of the file or a 'sigma' variable of a netCDF file; in Python, make_spectrum(sigma=...)) "
                      "and weigh by it (impedax fit --weighting sigma; impedax sample --noise sigma)")
        out[i] = (Note(
            f"the weighted residuals are over {UNEVEN_RESIDUAL_RATIO:g}× larger (rms) at {loud_band} than at the {'lower' if lo[quiet] < lo[loud] else 'higher'} frequencies {quiet_band}: "
            f"{UNEVEN_NOISE_NOTE} ({weighting} weighting), so they are not to be trusted; {remedy}; "
            "if the model misses something there, a diagnosis (impedax diagnose) shows what",
            (UNEVEN_NOISE, *([SIGMA_RESIDUAL] if weighting == "sigma" else [])),  # (under σ its remedy says what σ is, or that σ misstates the noise there)
        ),)
    return out


def _data_limit_note(note) -> bool:
    """Whether a misfit note (`misfit_notes`) says the data limit the fit: its `notes.DATA_LIMIT`
    tag, or, a plain text, `DATA_LIMIT_NOTE` in its words."""
    return has_tag(tags_of(note), DATA_LIMIT) if isinstance(note, Note) else DATA_LIMIT_NOTE in note


# a fit weighted by the data's σ is told that σ misstates the noise (`sigma_scale_notes`) where its
# weighted residuals are, in rms, this many times σ or more, or this many times fewer: its standard
# errors take σ as stated (χ² not rescaled), so they are off by that factor. Below 1.5× the note
# would mostly repeat what χ²'s own scatter allows on small spectra and tell a user little
SIGMA_SCALE_FACTOR = 1.5
# ... and only where χ²_red also lies outside the range that residuals of the stated σ reach in
# 99.8 % of spectra (χ²_ν/ν, ν = 2N − free parameters): at ν = 10 it is 0.15–2.96, so a few
# points cannot trigger the note by chance
SIGMA_SCALE_TAIL = 0.001
"""Each tail's probability outside `chi2_red_range`."""


def chi2_red_range(dof: int) -> tuple[float, float]:
    """The `SIGMA_SCALE_TAIL` and 1 − `SIGMA_SCALE_TAIL` quantiles of χ²_ν/ν (ν = ``dof``)."""
    from scipy.special import chdtri  # (the inverse of χ²'s survival function)

    return float(chdtri(dof, 1.0 - SIGMA_SCALE_TAIL)) / dof, float(chdtri(dof, SIGMA_SCALE_TAIL)) / dof


def sigma_scale_notes(z, z_model, inv_re, inv_im, weighting: str, n_free: int | None, misfit=None, chain_chi2_red=None, trial_means: str | None = None, *, blamed=None) -> list[tuple[str, ...]]:
    """The warning of each fit z_model (B, N) weighted by the data's σ (``inv_re`` = ``inv_im``
    = 1/σ) whose χ²_red lies outside `chi2_red_range` and whose residuals are at least
    `SIGMA_SCALE_FACTOR`× σ, or that many times below it, in rms (√χ²_red): the standard errors
    take σ as stated, so they are √χ²_red times too small (σ understated) or too large
    (overstated). A walkthrough's SYNTHETIC R0 + R1 ∥ C1 with σ stated 3× too small: χ²_red
    7.2, R0 6.5 stderr from the truth, and no word of it. Over σ it is left out where ``misfit``
    (`misfit_notes`) blames the model (which then explains the excess); ``n_free`` None (a
    shared fit's spectrum) or fewer than one degree of freedom: no note. ``chain_chi2_red`` (B,;
    `sigma_misstated`'s, NaN where not judged): where it marks σ as misstating the noise (a
    Kramers–Kronig-consistent model weighted by the same σ also exceeds it), the note over σ says
    so and does not offer a missing effect as the other cause. ``trial_means``
    (`trial_means_of_sigma`): σ is the standard error of means over those trials, which holds how
    the trials differ, smooth in frequency, as well as the noise; a fit of the mean takes most of
    that difference up into its parameters, so residuals far below σ are expected, and the note
    says what σ is instead of calling it overstated with standard errors "too large" (SYNTHETIC
    Sirin example: residuals 0.3× its SEM, "3.4× too large" said, where the trials' own spread
    of C_gap, fitted per trial, 5.2 pF as standard error of their mean, is 7× the fit's 0.74 pF).
    ``blamed`` (one bool per fit): which of ``misfit``'s notes blame the model; None: their
    `notes.MODEL_MISFIT` tags (`misfit_notes`), or, plain texts, their words
    (`warnings_blame_model`). A note of residuals below σ (what σ is, or that σ overstates the
    noise) is a `notes.Note` tagged `notes.SIGMA_RESIDUAL` (`SIGMA_OF_TRIAL_MEANS_WORDS`,
    `SIGMA_OVERSTATES_WORDS` are its words)."""
    z = np.atleast_2d(z)
    out: list[tuple[str, ...]] = [()] * len(z)
    dof = 2 * z.shape[-1] - (n_free or 0)
    if weighting != "sigma" or n_free is None or dof < 1:
        return out
    low, high = chi2_red_range(dof)
    with np.errstate(all="ignore"):
        dz = np.atleast_2d(z_model) - z
        chi2_red = np.sum((dz.real * inv_re) ** 2 + (dz.imag * inv_im) ** 2, axis=-1) / dof
    for i, c in enumerate(np.broadcast_to(chi2_red, (len(z),)).tolist()):
        if not math.isfinite(c):
            continue
        factor = math.sqrt(c)
        chain = np.nan if chain_chi2_red is None else float(np.broadcast_to(chain_chi2_red, (len(z),))[i])
        model_blamed = bool(blamed[i]) if blamed is not None else misfit is not None and _blames_model(misfit[i][:1])
        slip = sigma_unit_slip(z[i], 1.0 / np.broadcast_to(np.atleast_2d(inv_re), z.shape)[i], factor)
        if slip:  # (before the model is blamed: a σ in the wrong unit weighs the points wrongly, and the misfit may be that)
            out[i] = (
                f"the residuals are {format_factor(factor)}× the data's sigma in rms (χ²_red {c:.3g}, where residuals of the stated σ give {low:.2f}–{high:.2f}): "
                f"σ looks given in the wrong unit ({slip}), not understated by a noise a model could miss by: σ is in Ω, per point, for Re and Im alike, "
                f"and a relative σ is given as sigma = rel·|Z| (e.g. make_spectrum(f, Z, sigma={_relative_example(z[i], 1.0 / np.broadcast_to(np.atleast_2d(inv_re), z.shape)[i])} * abs(Z)); a file's sigma column in Ω); "
                f"until then the standard errors, which take σ as stated, are {format_factor(factor)}× too small, and the points are weighed by a wrong noise, so the fit's other warnings may be that weighting's",
            )
        elif c > high and factor >= SIGMA_SCALE_FACTOR and not model_blamed and math.isfinite(chain):
            out[i] = (
                f"the residuals are {format_factor(factor)}× the data's sigma in rms (χ²_red {c:.3g}, where residuals of the stated σ give {low:.2f}–{high:.2f}), and a "
                f"Kramers–Kronig-consistent model weighted by the same σ (the KK test's Voigt chain) leaves χ²_red {chain:.3g} too: σ misstates the noise, "
                f"not the model: it understates it (in some band, or everywhere), and the standard errors, which take σ as stated, are then about {format_factor(factor)}× too small; "
                "correct the sigma column (or weigh by modulus), then fit again",
            )
        elif c > high and factor >= SIGMA_SCALE_FACTOR and not model_blamed:
            out[i] = (
                f"the residuals are {format_factor(factor)}× the data's sigma in rms (χ²_red {c:.3g}, where residuals of the stated σ give {low:.2f}–{high:.2f}): "
                f"either σ understates the noise, and the standard errors, which take σ as stated, are then {format_factor(factor)}× too small, "
                "or the model misses something (a diagnosis, impedax diagnose, shows what)",
            )
        elif c < low and factor <= 1.0 / SIGMA_SCALE_FACTOR and trial_means:
            out[i] = (Note(
                f"the residuals are {format_factor(factor)}× the data's sigma in rms (χ²_red {c:.3g}, where residuals of the stated σ give {low:.2f}–{high:.2f}): "
                f"{SIGMA_OF_TRIAL_MEANS_WORDS} ({trial_means}; the data's sigma_method), which holds how the trials differ as well as the noise; "
                "a fit of the mean takes a difference smooth in frequency (a contact that changes from touch to touch, a cell from cycle to cycle) up into its parameters, so residuals "
                "below σ are expected here (unless the model follows the noise with too many parameters). The standard errors take σ as independent from "
                "point to point, which such a difference is not, so they do not give the parameters' spread between trials: fit each trial for that "
                "(impedax remaining --trials, then impedax fit; impedax gap's hierarchical model for a contact's gap)", (SIGMA_RESIDUAL,)),
            )
        elif c < low and factor <= 1.0 / SIGMA_SCALE_FACTOR:
            out[i] = (Note(
                f"the residuals are {format_factor(factor)}× the data's sigma in rms (χ²_red {c:.3g}, where residuals of the stated σ give {low:.2f}–{high:.2f}): "
                f"{SIGMA_OVERSTATES_WORDS} (or the model follows the noise with too many parameters), and the standard errors, which take σ as stated, are then {format_factor(1 / factor)}× too large",
                (SIGMA_RESIDUAL,)),
            )
    return out


def _blames_model(notes) -> bool:
    """Whether ``notes`` blame the model: their `notes.MODEL_MISFIT` tags (`misfit_notes`'
    `notes.Note`s), or, plain texts, their words (`warnings_blame_model`)."""
    if any(isinstance(n, Note) for n in notes):
        return any(has_tag(tags_of(n), MODEL_MISFIT) for n in notes)
    return warnings_blame_model(notes)


# ... and told that σ looks given in the wrong unit (`sigma_unit_slip`) where its residuals are this
# many times σ in rms or more: a model that misses by 10 % rms against a σ of 0.1 % of |Z| (an
# impedance analyser's accuracy) reaches it; a walkthrough's σ = 0.03 (meant as 3 %) on 2 kΩ–5 MΩ
# gave 2.6e6–3e6×, and was told that σ understates the noise or the model misses something
SIGMA_UNIT_SLIP_FACTOR = 100.0
# ... and σ is, in median, below this fraction of |Z|: 0.01 %, ten times below 0.1 %, a typical
# specified accuracy of impedance analysers, so not a noise that real data reach
SIGMA_UNIT_SLIP_FRACTION = 1e-4
# ... or σ looks like a fraction of |Z|: every σ below 1 (Ω) while |Z| is, in median, at least
# this many ohms (a relative 0.01–0.05 read as ohms then lies below 0.05 % of |Z|)
SIGMA_RELATIVE_Z = 100.0


def sigma_unit_slip(z, sigma, factor: float) -> str | None:
    """Why σ (Ω, per point) of spectrum z looks given in the wrong unit for a fit whose weighted
    residuals are ``factor``× σ in rms (√χ²_red): at least `SIGMA_UNIT_SLIP_FACTOR` and σ either
    below `SIGMA_UNIT_SLIP_FRACTION` of |Z| in median or all below 1 while |Z| is, in median, at
    least `SIGMA_RELATIVE_Z` (a relative σ read as ohms); None when it does not."""
    if not factor >= SIGMA_UNIT_SLIP_FACTOR:
        return None
    modulus, sigma = np.abs(np.asarray(z)), np.asarray(sigma, float)
    with np.errstate(all="ignore"):
        fraction = float(np.median(sigma / modulus))
    relative = bool(np.all(sigma < 1.0)) and float(np.median(modulus)) >= SIGMA_RELATIVE_Z
    if relative:
        return f"σ is {value_span(sigma)} Ω, all below 1 Ω, while |Z| is {value_span(modulus)} Ω: a fraction of |Z| read as ohms"
    if fraction < SIGMA_UNIT_SLIP_FRACTION:
        return f"σ is in median {fraction:.2g} of |Z|, below what an impedance analyser resolves"
    return None


def _relative_example(z, sigma) -> str:
    """The relative σ of `sigma_unit_slip`'s example: the data's σ when all are below 1 (read as
    the fraction meant), else 0.01."""
    sigma = np.asarray(sigma, float)
    return f"{float(np.median(sigma)):.3g}" if np.all(sigma < 1.0) else "0.01"


# a fit's misfit is compared with what the data allow (`misfit_notes`) from this rms_rel on:
# below it the comparison costs more (a Kramers–Kronig fit, ~0.5 ms per spectrum in a batch,
# `kk.kk_misfits`: a batch of well-fitted spectra at 1 % would pay it for every one) than it tells. At 5 %, AutoEIS's
# real battery cycle 0 fitted with R0 + R1 ∥ CPE1 + Wo1, at 3.2 % where a Kramers–Kronig-consistent
# model reaches 0.25 %, would be told nothing
MISFIT_CHECKED_FROM = 0.02
# ... and a batch's fit that misses the data grossly (`gross_misfits`: above `MISFIT_RATIO_MAX`
# × that) gets its own rung of starts from this rms_rel on
GROSS_MISFIT_FROM = 0.05
# ... and called a model's failure above this multiple of a Kramers–Kronig-consistent model's
# misfit (the start ladder climbs from 1.2×: `starts.KK_MISFIT_FACTOR`)
MISFIT_RATIO_MAX = 5.0
# ... and a fit whose residuals are the noise the data's sigma states (mean (ΔRe² + ΔIm²)/2σ²
# at most this) gets no note that noise limits it: 10 of 10 SYNTHETIC 50 Ω spectra with 4 %
# noise and their sigma said so, though the stated σ already explains the misfit
SIGMA_EXPLAINED = 2.0
# ... and a fit whose residuals exceed that noise by more than this (mean (ΔRe² + ΔIm²)/2σ²:
# residuals over twice σ in rms), on data a Kramers–Kronig-consistent model fits within the noise
# σ states (the KK test's rms_rel at most √`SIGMA_EXPLAINED` × the rms_rel σ implies,
# √mean(2σ²/|Z|²)), is told that the misfit is the model's, not the data's: for the right model
# and σ the mean is χ²/2N ≈ 1 ± √(2/2N) (± 0.32 at 10 points), so 4 is 9 standard deviations
# off even there, and a σ understated up to 2× in rms keeps the note that noise limits the fit.
# A SYNTHETIC R0 + R1 ∥ CPE1 spectrum (α = 0.97, 1 % noise and that σ) fitted with
# R0 + R1 ∥ C1 reached 2.85× the KK misfit with the mean at 5.1, and was told its noise limited it
SIGMA_EXCEEDED = 2.0 * SIGMA_EXPLAINED
MODEL_MISSES_STRUCTURE = "the model misses structure the data hold"
MISFIT_IS_MODELS = "the misfit is this model's"
DIAGNOSIS_ADVICE = "a diagnosis (impedax diagnose) shows where it fails and which effect is missing"
"""How a fit's misfit note that blames the model ends; ``impedax fit`` follows such a note with the
``impedax diagnose`` command to run (`cli.fit`; any such note, not only the hint of a misfit that looks
small)."""
MODEL_MISFIT_MARKS = (MODEL_MISSES_STRUCTURE, MISFIT_IS_MODELS)
"""Phrases of the `misfit_notes` that blame the model, not the data (their text is built from
them). Whether a fit's notes blame the model is a tag set where they are made
(`notes.MODEL_MISFIT`, `FitResult.warning_tags`, `BatchFitResult.warning_tags`); these phrases
tell it only of warnings without tags (`warnings_blame_model`: a result file written without them)."""


def warnings_blame_model(warnings) -> bool:
    """Whether one of a fit's warnings says its model misses structure the data hold
    (`MODEL_MISFIT_MARKS`), by their words: for warnings without the tags their fit carries
    (`FitResult.warning_tags`, `fit_blames_model`), such as those of a file written without them."""
    return any(mark in w for w in warnings for mark in MODEL_MISFIT_MARKS)


def note_value_attrs(fit, flag=bool) -> dict:
    """What ``fit``'s warnings say, as a saved result's attributes (a fit's `.nc`, a posterior's
    stored start fit): ``warning_tags`` (`FitResult.warning_tags`, None where not known), and the
    values read from them by the files of earlier versions: ``model_misfit`` and ``uneven_noise``
    as ``flag`` (int in netCDF attributes), ``data_limit_note``, ``data_limit_hint``,
    ``misfit_note`` and ``sigma_residual_notes`` (where the tags are not known: the words'
    answer, `fit_blames_model`, `fit_data_limit`, `fit_uneven_noise`, `fit_blaming_note`,
    `fit_sigma_residual_notes`). `stored_note_values` reads them back."""
    limit, hint = fit_data_limit(fit)
    tags = getattr(fit, "warning_tags", None)
    return {"warning_tags": tags_attr(tags), "model_misfit": flag(fit_blames_model(fit)), "data_limit_note": limit, "data_limit_hint": hint, "uneven_noise": flag(fit_uneven_noise(fit)),
            "misfit_note": fit_blaming_note(fit) if tags is None else _first_tagged(fit.warnings, tags, MISFIT), "sigma_residual_notes": list(fit_sigma_residual_notes(fit))}


def stored_note_values(attrs, warnings=None) -> dict:
    """`FitResult`'s ``warning_tags`` from saved attributes (`note_value_attrs`) of a fit with
    ``warnings`` (None: ``attrs["warnings"]``): as stored, or, in a file written before they
    were (which stored ``model_misfit``, ``data_limit_note``, ... instead), built from those
    values (`tags_from_values`); None in a file that holds neither (an older version's), so that
    the fit read back is judged by its warnings' words."""
    warnings = attrs.get("warnings", ()) if warnings is None else warnings
    warnings = (warnings,) if isinstance(warnings, str) else tuple(str(w) for w in warnings)
    tags = stored_tags(attrs.get("warning_tags"), len(warnings))
    if tags is None:
        tags = tags_from_values(warnings, **{key: attrs.get(key) for key in _NOTE_VALUE_KEYS})
    return {"warning_tags": tags}


_NOTE_VALUE_KEYS = ("model_misfit", "data_limit_note", "data_limit_hint", "misfit_note", "uneven_noise", "sigma_residual_notes")
"""The attributes in which files written before `FitResult.warning_tags` hold what the warnings say."""


def tags_from_values(warnings, *, model_misfit=None, data_limit_note=None, data_limit_hint=None, misfit_note=None, uneven_noise=None, sigma_residual_notes=None) -> tuple[tuple[str, ...], ...] | None:
    """The tags of ``warnings`` from the values a file written before `FitResult.warning_tags`
    holds (`note_value_attrs`' other keys; None: the file lacks it), None where it holds none:
    the notes they name are found among the warnings by their text (the misfit note, the note
    that the data limit the fit, the σ notes) and, for the two flags, by their words (the note
    that blames the model where ``misfit_note`` is "", `MODEL_MISFIT_MARKS`; the uneven-noise
    note, `UNEVEN_NOISE_NOTE`). A value the file lacks (written by a version that stored some of
    them) is the words' answer, as it was for such a file (`fit_blames_model`, `fit_data_limit`,
    `fit_uneven_noise`, `fit_sigma_residual_notes`; the misfit note: the one that blames the
    model, `fit_blaming_note`, or else the one that says the data limit the fit)."""
    if all(v is None for v in (model_misfit, data_limit_note, misfit_note, uneven_noise, sigma_residual_notes)):
        return None
    words = _Untagged(tuple(warnings))
    model_misfit = fit_blames_model(words) if model_misfit is None else model_misfit
    if data_limit_note is None:
        data_limit_note, data_limit_hint = fit_data_limit(words)
    misfit_note = (fit_blaming_note(words) or data_limit_note or "") if misfit_note is None else misfit_note  # (the misfit note: one that blames the model, or says the data limit the fit)
    uneven_noise = fit_uneven_noise(words) if uneven_noise is None else uneven_noise
    sigma_residual_notes = fit_sigma_residual_notes(words) if sigma_residual_notes is None else sigma_residual_notes
    tags = [[] for _ in warnings]

    def mark(index, *new):
        if index is not None:
            tags[index] += [t for t in new if t not in tags[index]]

    def at(text):
        return next((i for i, w in enumerate(warnings) if text and w == text), None)

    def worded(words):
        return next((i for i, w in enumerate(warnings) if any(x in w for x in words)), None)

    mark(at(misfit_note), MISFIT)
    if bool(model_misfit):
        mark(at(misfit_note) if misfit_note else worded(MODEL_MISFIT_MARKS), MISFIT, MODEL_MISFIT)
    if data_limit_note:
        mark(at(data_limit_note), DATA_LIMIT, *([sign_hint_tag(str(data_limit_hint))] if data_limit_hint else []))
    if bool(uneven_noise):
        mark(worded((UNEVEN_NOISE_NOTE,)), UNEVEN_NOISE)
    for note in stored_notes(sigma_residual_notes):
        mark(at(note), SIGMA_RESIDUAL)
    return tuple(tuple(t) for t in tags)


def warning_tags_by_words(warnings) -> tuple[tuple[str, ...], ...]:
    """The tags of ``warnings`` as their words say them (`tags_from_values` with nothing stored:
    the misfit note is the one that blames the model, `MODEL_MISFIT_MARKS`, or else the one that
    says the data limit the fit, `DATA_LIMIT_NOTE`; the uneven-noise and σ notes by their words),
    for warnings whose tags are not known."""
    words = _Untagged(tuple(str(w) for w in warnings))
    return tags_from_values(words.warnings, model_misfit=fit_blames_model(words))


def fit_warning_tags(fit) -> tuple[tuple[str, ...], ...]:
    """The tags of each of ``fit``'s warnings, in their order: its `FitResult.warning_tags`, or,
    where they are not known (None: a fit built by hand, a file written without them, warnings
    replaced alone), those the words say (`warning_tags_by_words`). A JSON's ``warning_tags``."""
    tags = getattr(fit, "warning_tags", None)
    return warning_tags_by_words(fit.warnings) if tags is None else tuple(tuple(t) for t in tags)


@dataclass(frozen=True)
class _Untagged:
    """Warnings without tags: what the accessors (`fit_blames_model`, ...) read by their words."""

    warnings: tuple[str, ...]
    warning_tags = None


def with_warnings(fit, warnings):
    """``fit`` with ``warnings`` in place of its own: `notes.Note`s (its `FitResult.tagged_warnings`
    filtered, reordered or extended, new ones tagged or not) keep their tags; a fit whose tags are
    not known and that gets no tagged note keeps none (one that gets one: its own warnings tagged
    as their words say, `tags_from_values`)."""
    from dataclasses import replace

    warnings = tuple(warnings)
    known = getattr(fit, "warning_tags", None) is not None or any(tags_of(w) for w in warnings)
    if known and getattr(fit, "warning_tags", None) is None:  # (its own warnings tagged as their words say: their answers stay those of the words)
        said = note_value_attrs(fit)
        own = dict(zip(fit.warnings, tags_from_values(fit.warnings, **{key: said[key] for key in _NOTE_VALUE_KEYS})))
        warnings = tuple(w if tags_of(w) else Note(w, own.get(w, ())) for w in warnings)
    return replace(fit, warnings=tuple(str(w) for w in warnings), warning_tags=notes_tags(warnings) if known else None, _tags_given_with=None)  # (the tags given with these warnings: theirs, `notes.carried_over`)


def _first_tagged(warnings, tags, tag: str) -> str:
    """The first of ``warnings`` whose ``tags`` hold ``tag``, "" none."""
    return next((w for w, t in zip(warnings, tags) if has_tag(t, tag)), "")


def fit_data_limit(fit) -> tuple[str, str]:
    """(the warning, its sign hint's end) of ``fit``'s note that the data, not only the model,
    limit it (`misfit_notes`): the warning tagged `notes.DATA_LIMIT` and its `notes.SIGN_HINT`
    tag's end, set where the note is made, or, where the tags are not known (None: a fit built by
    hand, a file written without them), the warning holding `DATA_LIMIT_NOTE` and its end from
    "; " `SIGN_HINT_LEAD` on, by their words; ("", "") where it has no such note among its warnings."""
    tags = getattr(fit, "warning_tags", None)
    if tags is None:
        note = next((w for w in fit.warnings if DATA_LIMIT_NOTE in w), "")
        at = note.find(f"; {SIGN_HINT_LEAD}")
        return note, note[at:] if at >= 0 else ""
    return next(((w, tag_detail(t, SIGN_HINT)) for w, t in zip(fit.warnings, tags) if has_tag(t, DATA_LIMIT)), ("", ""))


def fit_uneven_noise(fit) -> bool:
    """Whether ``fit``'s warnings say its weighted residuals are uneven across the band
    (`uneven_residual_notes`): a warning tagged `notes.UNEVEN_NOISE`, set where the note is made,
    or, where the tags are not known (None: a fit built by hand, a file written without them),
    `UNEVEN_NOISE_NOTE` in its words."""
    tags = getattr(fit, "warning_tags", None)
    return any(UNEVEN_NOISE_NOTE in w for w in fit.warnings) if tags is None else any(has_tag(t, UNEVEN_NOISE) for t in tags)


def fit_sigma_residual_notes(fit) -> tuple[str, ...]:
    """``fit``'s warnings that read residuals below the data's σ, or uneven against it, as what σ
    is or a σ misstating the noise (`sigma_scale_notes`, `uneven_residual_notes` under σ
    weighting): those tagged `notes.SIGMA_RESIDUAL`, set where the notes are made, or, where the
    tags are not known (None: a fit built by hand, a file written without them), those holding
    `SIGMA_OVERSTATES_WORDS`, `SIGMA_OF_TRIAL_MEANS_WORDS` or `SIGMA_BAND_WORDS`, by their words."""
    tags = getattr(fit, "warning_tags", None)
    if tags is None:
        return tuple(w for w in fit.warnings if any(words in w for words in (SIGMA_OVERSTATES_WORDS, SIGMA_OF_TRIAL_MEANS_WORDS, SIGMA_BAND_WORDS)))
    return tuple(w for w, t in zip(fit.warnings, tags) if has_tag(t, SIGMA_RESIDUAL))


def fit_blaming_note(fit) -> str:
    """The warning of ``fit`` that blames its model for missing structure the data hold (its
    misfit note, `misfit_notes`, or the note `compare` puts in its place), "" where none does:
    the warning tagged `notes.MODEL_MISFIT`, set where the note is made, or, where the tags are
    not known (None: a fit built by hand, a file written without them), the first warning
    holding one of `MODEL_MISFIT_MARKS`, by their words."""
    tags = getattr(fit, "warning_tags", None)
    if tags is None:
        return next((w for w in fit.warnings if any(mark in w for mark in MODEL_MISFIT_MARKS)), "")
    return _first_tagged(fit.warnings, tags, MODEL_MISFIT)


def fit_blames_model(fit) -> bool:
    """Whether ``fit``'s warnings blame its model for missing structure the data hold: a warning
    tagged `notes.MODEL_MISFIT` (set where the note is made, `misfit_notes`), or, where the tags
    are not known (None: a fit built by hand, a file written without them),
    `warnings_blame_model` of its words."""
    tags = getattr(fit, "warning_tags", None)
    return warnings_blame_model(fit.warnings) if tags is None else any(has_tag(t, MODEL_MISFIT) for t in tags)


# the end of the note that the data, not only the model, limit a fit (`misfit_notes`): `comparison.compare`
# replaces it where another model fits the same data significantly better (the note is found by its
# `notes.DATA_LIMIT` tag; this phrase finds it only in a fit without tags: `fit_data_limit`)
DATA_LIMIT_NOTE = "the data's noise, drift or artifacts limit the fit, not only the model (see impedax kk)"
# ... followed, when the KK test says the imaginary part may be stored with the opposite sign
# (`io.sign_check.sign_hint`), by this and the hint (`comparison` keeps it when it replaces the note)
SIGN_HINT_LEAD = "hint: "
# the note, in place of one blaming the model, on a fit whose data the KK test's sign hint explains
# (`io.sign_check.sign_hint`), followed by `SIGN_HINT_LEAD` and the hint: a walkthrough's SYNTHETIC
# finger spectrum (C_s + C_i + R_sc || C_sc + R_f, 1 % noise) stored as conj(Z), Z'' > 0 at 61 of 61
# points, ended at rms_rel 107 % with C_s = 7.6e114 F and was told the model missed structure
SIGN_CAUSE_NOTE = (
    "the misfit is most likely how the data store the sign, not the model: a passive circuit does not follow them as stored, "
    "and a diagnosis would look in vain for a missing effect"
)
# the share of the points at which Z'' > 0 (or Z' < 0) from which a fit blamed on the model has its
# data's signs checked (the KK test of Z and conj(Z), ~50 ms; `misfit_notes`): it asks the KK
# test's rule (`io.sign_check.sign_hint`), whose every path needs data stored with the wrong sign
# at most points, and spares correctly signed capacitive data, which have neither
SIGNS_IN_DOUBT_SHARE = 0.5


def signs_in_doubt(z) -> bool:
    """Whether a spectrum ``z`` (N,) has Z'' > 0 or Z' < 0 at at least `SIGNS_IN_DOUBT_SHARE`
    of its points: only then may the KK test's sign hint explain a misfit (`misfit_notes`)."""
    z = np.asarray(z, complex)
    return bool(z.size) and bool(np.mean(z.imag > 0) >= SIGNS_IN_DOUBT_SHARE or np.mean(z.real < 0) >= SIGNS_IN_DOUBT_SHARE)
# ... where the fit's weighting is not the data's sigma, the end of that note instead: a fit that
# weighs points by |Z| spends its misfit where σ is large against |Z| (a remainder's noisy high
# frequencies), so its residuals may exceed σ for the right model (a user's SYNTHETIC gap
# remainder, R_EP ∥ CPE_EP ∥ C_gap: R_EP at 4.6e13 Ω under modulus, χ²_red 0.87 under sigma)
SIGMA_EXCEEDED_UNWEIGHTED = (
    "this fit weighs the points by another rule than their sigma, so its residuals need not follow that noise: refit with the sigma weighting "
    "(impedax fit --weighting sigma; impedax sample --noise sigma) before looking for a missing effect"
)
# ... and a fit of data that pass the KK test (the chain's misfit is their noise) is told its
# misfit is its own above this multiple of the chain's rms_rel: χ²_red ≈ 4 against that noise,
# decisive on any spectrum of 20 points or more (at 5×,
# Meyer's RC-skin model on SYNTHETIC CPE-skin data with 1 % noise, at 2.7×, would be told the data's
# noise limited it)
MODEL_MISFIT_OVER_CONSISTENT = 2.0
# ... and below that multiple, when the fit's number of free parameters is known, by the rule a
# diagnosis names a missing effect with (`diagnosis.DELTA_AIC_MIN`, `diagnosis.NOISE_FRACTION_MIN`),
# with the chain in the candidate's place: its χ² (rms_rel², the same 1/|Z| weighting) at least
# this much above the chain's, a share of the noise's own ...
MODEL_MISFIT_NOISE_SHARE = 0.25
# ... and its AIC (Gaussian, 2N real residuals, parameters counted) worse than the chain's by more
# than this (without it a fit at 1.6× the chain's rms_rel, χ² 2.6×, would be told the data's
# noise limited it while `impedax diagnose` named the missing effect: SYNTHETIC R0 + R1 ∥ CPE1 data,
# α = 0.97, 1 % noise, fitted with R0 + R1 ∥ C1)
MODEL_MISFIT_DELTA_AIC = 10.0


def misfit_beyond_noise(rms_worse: float, rms_better: float, n_points: int, extra_params: int) -> bool:
    """Whether a fit at rms_rel ``rms_worse`` misses by more than the noise what another fit of
    the same N = ``n_points`` points reaches with ``extra_params`` more parameters (rms_rel
    ``rms_better``): χ² ratio (rms_worse/rms_better)² ≥ 1 + `MODEL_MISFIT_NOISE_SHARE` and
    ΔAIC = 2N ln χ²-ratio − 2·extra_params (Gaussian, Re and Im of each point) above
    `MODEL_MISFIT_DELTA_AIC`."""
    if not rms_better > 0:
        return False
    ratio = (rms_worse / rms_better) ** 2
    return bool(ratio >= 1.0 + MODEL_MISFIT_NOISE_SHARE and 2 * n_points * math.log(ratio) - 2 * extra_params > MODEL_MISFIT_DELTA_AIC)


def misfit_beyond_chain(rms: float, kk: float, n_points: int, n_free: int | None, chain_params: int | None) -> bool:
    """Whether a fit at rms_rel ``rms`` of data that pass the Kramers–Kronig test misses what its
    Voigt chain (rms_rel ``kk``, ``chain_params`` linear parameters) reaches by more than their
    noise: rms above `MODEL_MISFIT_OVER_CONSISTENT` × kk, or, with the fit's ``n_free`` free
    parameters known, `misfit_beyond_noise` against the chain (χ² ratio and ΔAIC, the chain's
    extra parameters counted)."""
    if rms > MODEL_MISFIT_OVER_CONSISTENT * kk:
        return True
    if n_free is None or chain_params is None:
        return False
    return misfit_beyond_noise(rms, kk, n_points, chain_params - n_free)


def known_kk_misfits(freq, z, rows: np.ndarray, known: KKChains | None) -> np.ndarray:
    """`starts.attainable_misfit` of spectra ``z[rows]``, from and into ``known`` (one fit call's
    memory of the KK test's chains, `kk.KKChains`: a batch asks up to three times, `gross_misfits`
    before its extra starts, `misfit_notes` after and its full KK test, `kk.kk_verdicts`, of the
    same chains, at ~0.5–1.4 ms per spectrum in a batch)."""
    return (KKChains() if known is None else known).misfits(freq, z, rows)


def _checked_misfits(freq, z, z_model, known: KKChains | None, checked_from: float | None = None):
    """rms_rel (B,) of fits z_model of spectra z, the indices of those at ``checked_from``
    (default `MISFIT_CHECKED_FROM`) or more, and their KK test's misfits (`known_kk_misfits`)."""
    z, z_model = np.atleast_2d(z), np.atleast_2d(z_model)
    rms = rms_rel_of(z_model, z)
    checked = np.flatnonzero(np.isfinite(rms) & (rms >= (MISFIT_CHECKED_FROM if checked_from is None else checked_from)))
    return rms, checked, (known_kk_misfits(freq, z, checked, known) if checked.size else np.zeros(0))


def within_stated_noise(z, z_model, sigma, weighting: str | None, n_free: int | None) -> np.ndarray:
    """Whether each fit z_model (B, N) of spectra z weighted by their ``sigma`` (B, N; σ of Re and
    of Im; ``weighting`` "sigma") leaves residuals the stated noise explains: χ²_red = χ²/ν
    (χ² = Σ (ΔRe² + ΔIm²)/σ², ν = 2N − ``n_free``, 2N for a shared fit's None) at most the upper
    end of `chi2_red_range`, the bound above which `sigma_scale_notes` says the residuals exceed
    σ. Such a model is adequate at the stated noise, so the misfit warning does not blame it
    (`misfit_notes`), whatever a Kramers–Kronig chain, which follows the noise itself, reaches.
    False for every fit under another weighting or without σ: that fit did not minimise σ's χ²."""
    z = np.atleast_2d(z)
    out = np.zeros(len(z), bool)
    if weighting != "sigma" or sigma is None:
        return out
    dof = 2 * z.shape[-1] - (n_free or 0)
    if dof < 1:
        return out
    with np.errstate(all="ignore"):
        dz = np.atleast_2d(z_model) - z
        chi2_red = np.sum((dz.real**2 + dz.imag**2) / np.atleast_2d(np.asarray(sigma, float)) ** 2, axis=-1) / dof
    return np.isfinite(chi2_red) & (chi2_red <= chi2_red_range(dof)[1])


# a single fit under |Z| weighting below `MISFIT_CHECKED_FROM` gets a hint (not a warning: a
# batch, which pays the Kramers–Kronig fit per spectrum, checks no fit below it, and a spectrum's
# warnings are the same alone and in a batch) from this rms_rel on: below it the misfit is at
# most ~2–3× a good instrument's noise
MISFIT_HINT_FROM = 0.002


def misfit_hint(fit) -> str | None:
    """A hint for a single fit weighted by |Z| whose rms_rel lies between `MISFIT_HINT_FROM` and
    `MISFIT_CHECKED_FROM` (where `misfit_notes` begins) and is above `MISFIT_RATIO_MAX` × what
    the Kramers–Kronig test's Voigt chain reaches (`starts.attainable_misfit`, ~0.5 ms): the
    model misses structure the data hold though its misfit looks small (REAL ZPlot file,
    `R0 + R1 || CPE1`: 1.35 % against the chain's 0.137 %, a lead inductance missing; a
    beginner's walkthrough kept its values). None otherwise."""
    if fit.weighting != "modulus":
        return None
    rows, ratio, chain = misfit_hint_spectra(fit.frequency, np.asarray(fit.z_data)[None], [fit.rms_rel])
    if not rows.size:
        return None
    return (f"rms_rel {fit.rms_rel * 100:.3g} % is {ratio[0]:.3g}× the {chain[0] * 100:.3g} % a Kramers–Kronig-consistent model reaches: "
            "the model misses structure the data hold, small as the misfit looks (a diagnosis shows where and what)")


def misfit_hint_spectra(freq, z, rms_rel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The spectra of a stack z (B, N) whose fits weighted by |Z|, of rms_rel (B,), earn
    `misfit_hint`'s hint (the rule of it, for one spectrum and for a batch's): rms_rel from `MISFIT_HINT_FROM` to `MISFIT_CHECKED_FROM` and above
    `MISFIT_RATIO_MAX` × what the Kramers–Kronig test's Voigt chain reaches on that spectrum
    (`starts.attainable_misfit`, fitted for those in the range only). Returns their indices, the
    ratios and the chains' rms_rel."""
    rms_rel = np.asarray(rms_rel, float)
    with np.errstate(invalid="ignore"):
        rows = np.flatnonzero((rms_rel >= MISFIT_HINT_FROM) & (rms_rel < MISFIT_CHECKED_FROM))
    if not rows.size:
        return rows, np.empty(0), np.empty(0)
    chain = attainable_misfit(freq, np.asarray(z)[rows])
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(chain > 0, rms_rel[rows] / chain, np.nan)
        hinted = ratio > MISFIT_RATIO_MAX
    return rows[hinted], ratio[hinted], chain[hinted]


def gross_misfits(freq, z, z_model, known: KKChains | None = None, *, sigma=None, weighting: str | None = None, n_free: int | None = None) -> np.ndarray:
    """Indices of the fits of spectra z (B, N) that miss the data grossly: rms_rel at least
    `GROSS_MISFIT_FROM` and above `MISFIT_RATIO_MAX` × the KK test's misfit (`known_kk_misfits`,
    with ``known``), and, given the data's ``sigma`` and the fits' ``weighting`` and ``n_free``,
    residuals beyond the stated noise (not `within_stated_noise`), as `misfit_notes` rules."""
    rms, checked, kk = _checked_misfits(freq, z, z_model, known, GROSS_MISFIT_FROM)
    gross = checked[(kk > 0) & (rms[checked] > MISFIT_RATIO_MAX * kk)]
    return gross[~within_stated_noise(z, z_model, sigma, weighting, n_free)[gross]]


# a fit weighted by the data's σ whose χ²_red exceeds the stated noise is said to miss what a
# Kramers–Kronig-consistent model weighted by the same σ reaches (`sigma_misstated`) only above
# this multiple of that model's χ²_red (the 2× rms rule of `MODEL_MISFIT_OVER_CONSISTENT`, in χ²).
# Measured 2026-12-02 on SYNTHETIC R_s + R_p ∥ CPE_p (51 points, 1 Hz–100 kHz, noise 3 % below
# 10 Hz and 0.3 % above, the σ bands swapped; seeds 0–19): fit/chain χ²_red 0.86–2.14, the chain's
# own 5.0–35, none blamed; with the right σ and C_p for the CPE: 1,042–2,299. The Gaussian AIC rule of
# `misfit_beyond_noise` is no guide here: with σ misstated the chain spends its many parameters on
# the points σ weighs most, and the rule blamed the right model
SIGMA_CHAIN_CHI2_RATIO = MODEL_MISFIT_OVER_CONSISTENT**2


def sigma_misstated(freq, z, z_model, sigma, weighting: str | None, n_free: int | None) -> tuple[np.ndarray, np.ndarray]:
    """For each fit z_model (B, N) of spectra z weighted by their stated ``sigma`` (B, N; σ of
    Re and of Im; ``weighting`` "sigma") whose χ²_red exceeds the stated noise (above
    `chi2_red_range` and `SIGMA_SCALE_FACTOR`² : the fits `sigma_scale_notes` speaks of): the
    χ²_red that the Kramers–Kronig test's Voigt chain reaches under the same σ weighting
    (`kk.kk_sigma_misfits`; NaN for the other fits), and whether σ, not the model, is what the
    residuals exceed: the chain's χ²_red is beyond that range too (no KK-consistent model meets
    this σ) and the fit's is at most `SIGMA_CHAIN_CHI2_RATIO` × the chain's. A walkthrough's
    SYNTHETIC R_s + R_p ∥ CPE_p with the σ of two noise bands swapped: fit χ²_red 23, the chain's
    20, and it was told the misfit was the model's (the chain's rms_rel was set against the mean
    stated σ/|Z|, which the too-large σ dominated). ((B,) bool, (B,) χ²_red)."""
    z = np.atleast_2d(z)
    chain = np.full(len(z), np.nan)
    misstated = np.zeros(len(z), bool)
    if weighting != "sigma" or sigma is None:
        return misstated, chain
    sigma = np.broadcast_to(np.asarray(sigma, float), z.shape)
    dof = 2 * z.shape[-1] - (n_free or 0)
    if dof < 1:
        return misstated, chain
    with np.errstate(all="ignore"):
        dz = np.atleast_2d(z_model) - z
        chi2_red = np.sum((dz.real**2 + dz.imag**2) / sigma**2, axis=-1) / dof
    exceeds = np.isfinite(chi2_red) & (chi2_red > chi2_red_range(dof)[1]) & (chi2_red >= SIGMA_SCALE_FACTOR**2)
    rows = np.flatnonzero(exceeds)
    if not rows.size:
        return misstated, chain
    chain_rows, params = kk_sigma_misfits(freq, z[rows], sigma[rows])
    chain[rows] = chain_rows
    for k, i in enumerate(rows.tolist()):
        c = chain_rows[k]
        if math.isfinite(c) and c > max(chi2_red_range(max(2 * z.shape[-1] - int(params[k]), 1))[1], SIGMA_SCALE_FACTOR**2) and chi2_red[i] <= SIGMA_CHAIN_CHI2_RATIO * c:
            misstated[i] = True
    return misstated, np.where(misstated, chain, np.nan)


def sign_notes_first(notes: tuple[str, ...]) -> tuple[str, ...]:
    """A fit's ``notes`` with those that hold the Kramers–Kronig test's sign hint (`misfit_notes`,
    `SIGN_HINT_LEAD`) first: a sign stored flipped is the cause, and the other warnings (a
    parameter at its bound, uneven residuals and their advice to weigh by σ) its consequences.
    A walkthrough's REAL BioLogic spectrum stored as conj(Z) got the hint at the end of its
    fourth warning, after two bound warnings and one on uneven residuals."""
    signed = tuple(n for n in notes if f"; {SIGN_HINT_LEAD}" in n)
    return signed + tuple(n for n in notes if f"; {SIGN_HINT_LEAD}" not in n) if signed else tuple(notes)


def misfit_notes(freq, z, z_model, known: KKChains | None = None, sigma=None, attrs=None, weighting: str | None = None, n_free: int | None = None, misstated=None) -> list[tuple[str, ...]]:
    """The misfit warning of each fit of spectra z (B, N) with models z_model (B, N) whose
    rms_rel is at least `MISFIT_CHECKED_FROM`: set against the rms_rel of the linear
    Kramers–Kronig test's Voigt chain (`starts.attainable_misfit`), either the model misses
    structure the data hold (above `MISFIT_RATIO_MAX` × that) or the data themselves are that
    far from any Kramers–Kronig-consistent model (noise, drift; `DATA_LIMIT_NOTE`). One tuple
    per fit; the text holds the data's figure, not the fit's, so that a batch's fit in another
    local minimum on the same side of the rule gives the single fit's note. With the data's
    ``sigma`` (B, N; σ of Re and of Im) the second note is left out where the residuals are the
    noise σ states (mean of (ΔRe² + ΔIm²)/2σ² at most `SIGMA_EXPLAINED`): nothing is left to say
    then; and it becomes a note that the misfit is the model's where that mean is above
    `SIGMA_EXCEEDED` while the Voigt chain fits within the noise σ states: the stated noise
    cannot be what limits the fit (the note holds the threshold, not the fit's mean, as above).
    No note at all for a fit weighted by σ whose χ²_red the stated noise explains
    (`within_stated_noise`): the Voigt chain fits the noise itself, so its rms_rel may lie far
    below that of an adequate model (a walkthrough's SYNTHETIC gap remainder, R_EP ∥ CPE_EP ∥
    C_gap, χ²_red 0.35, was told it missed structure at 2.65 % against the chain's 0.34 %).
    Where that note would be given, the full KK test is run (`kk.kk_verdicts`): when the data
    pass it (their residuals from the chain are noise, so the chain's misfit is the noise) and
    the fit's misfit is beyond the chain's by more than that noise (`misfit_beyond_chain`: rms_rel
    above `MODEL_MISFIT_OVER_CONSISTENT` × the chain's, or, with the fits' ``n_free`` free
    parameters, the rule a diagnosis names a missing effect by), the misfit is this model's, and
    the note says so;
    else the note that the data limit the fit, ending with the KK test's hint when the data fail
    it almost everywhere but conj(Z) passes (``attrs``: the data's, for how to fix the file): a
    Z'' stored with the opposite sign, not noise or drift, then limits it. A note that would blame
    the model is replaced by `SIGN_CAUSE_NOTE` and that hint where the KK test gives one (asked
    where `signs_in_doubt`): the stored sign, not a missing effect, is then the likely cause
    (conjugated SYNTHETIC finger data are otherwise told the model misses structure). ``weighting``: the
    fits'; one other than ``sigma`` minimised another χ² than σ's, so residuals beyond σ may be
    that weighting's, and the note over σ says to refit with ``sigma`` rather than blame the model
    (`SIGMA_EXCEEDED_UNWEIGHTED`). ``n_free``: the fits' number of free parameters (None: a
    shared fit's, not one spectrum's; the 2× rule alone then, as for a weighting other than
    ``modulus``, whose fit does not minimise the rms_rel the rule weighs). ``misstated`` (B,
    bool; `sigma_misstated`'s, computed when not given): fits weighted by σ whose residuals a
    Kramers–Kronig-consistent model weighted by the same σ exceeds σ by as well: σ misstates the
    noise, so no note blames the model; such a fit gets the note that the data limit it
    (`sigma_scale_notes` and `uneven_residual_notes`, which that note leaves in place, say what is
    wrong with σ). ``known``: the fit call's `kk.KKChains` (its chains are fitted
    once for the misfits and the full test). Each note is a `notes.Note` tagged `notes.MISFIT`,
    and `notes.MODEL_MISFIT` where it blames the model (`MODEL_MISFIT_MARKS` are its words),
    `notes.DATA_LIMIT` where it says the data limit the fit (`DATA_LIMIT_NOTE`), `notes.SIGN_HINT`
    with the end holding the sign hint ("; " `SIGN_HINT_LEAD` and the hint) where it has one."""
    known = KKChains() if known is None else known
    rms, checked, kks = _checked_misfits(freq, z, z_model, known)
    at_noise = within_stated_noise(z, z_model, sigma, weighting, n_free)
    sigma_wrong = np.zeros(rms.size, bool)  # (`sigma_misstated`: σ, not the model, is what the residuals exceed)
    if checked.size and weighting == "sigma" and sigma is not None:
        sigma_wrong = np.reshape(sigma_misstated(freq, z, z_model, sigma, weighting, n_free)[0] if misstated is None else np.asarray(misstated, bool), rms.shape)
    explained = np.zeros(rms.size, bool)
    ratio, noise_rms = np.full(rms.size, np.nan), np.full(rms.size, np.nan)
    if sigma is not None:
        with np.errstate(all="ignore"):
            dz = np.asarray(z_model) - np.asarray(z)
            variance = 2.0 * np.asarray(sigma, float) ** 2
            ratio = np.reshape(np.mean((dz.real**2 + dz.imag**2) / variance, axis=-1), rms.shape)
            noise_rms = np.reshape(np.sqrt(np.mean(variance / np.abs(np.asarray(z)) ** 2, axis=-1)), rms.shape)  # (the rms_rel σ implies)
        explained = np.isfinite(ratio) & (ratio <= SIGMA_EXPLAINED)
    out: list[tuple[str, ...]] = [()] * rms.size
    blamed = [False] * rms.size  # (the notes that blame the model: tagged MODEL_MISFIT)
    data_limited: dict[int, float] = {}  # spectrum → its KK chain's rms_rel
    hints = [""] * rms.size  # (the sign hint's end of a note: tagged SIGN_HINT)
    for i, kk in zip(checked.tolist(), kks.tolist()):
        if not kk > 0 or at_noise[i]:  # (σ-weighted residuals the stated noise explains: nothing to blame)
            continue
        if explained[i] and not rms[i] > MISFIT_RATIO_MAX * kk:
            continue
        if rms[i] > MISFIT_RATIO_MAX * kk and not sigma_wrong[i]:
            out[i] = (
                f"{MODEL_MISSES_STRUCTURE}: its rms_rel is over {MISFIT_RATIO_MAX:g}× the {kk * 100:.2g} % a Kramers–Kronig-consistent model "
                f"({KK_CHAIN_WORDS}) reaches; {DIAGNOSIS_ADVICE}",
            )
            blamed[i] = True
        elif ratio[i] > SIGMA_EXCEEDED and kk <= math.sqrt(SIGMA_EXPLAINED) * noise_rms[i] and weighting not in (None, "sigma"):
            out[i] = (
                f"the misfit exceeds the noise the data's sigma states (mean (ΔRe² + ΔIm²)/2σ² above {SIGMA_EXCEEDED:g}) while a Kramers–Kronig-consistent "
                f"model ({KK_CHAIN_WORDS}) reaches {kk * 100:.2g} % (rms_rel), within that noise ({noise_rms[i] * 100:.2g} %); {SIGMA_EXCEEDED_UNWEIGHTED}",
            )
        elif ratio[i] > SIGMA_EXCEEDED and kk <= math.sqrt(SIGMA_EXPLAINED) * noise_rms[i] and not sigma_wrong[i]:
            out[i] = (
                f"the misfit exceeds the noise the data's sigma states (mean (ΔRe² + ΔIm²)/2σ² above {SIGMA_EXCEEDED:g}) while a Kramers–Kronig-consistent "
                f"model ({KK_CHAIN_WORDS}) reaches {kk * 100:.2g} % (rms_rel), within that noise ({noise_rms[i] * 100:.2g} %): {MISFIT_IS_MODELS}, "
                f"not the data's noise; {DIAGNOSIS_ADVICE}",
            )
            blamed[i] = True
        else:
            out[i] = (
                f"the data are {kk * 100:.2g} % (rms_rel) from any Kramers–Kronig-consistent model ({KK_CHAIN_WORDS}), within {MISFIT_RATIO_MAX:g}× "
                f"of this fit's misfit: {DATA_LIMIT_NOTE}",
            )
            data_limited[i] = kk
    rows = np.atleast_2d(z)
    # the fits blamed on the model whose data's stored signs may be the cause instead (`SIGNS_IN_DOUBT_SHARE`)
    sign_suspects = [i for i in checked.tolist() if out[i] and i not in data_limited and signs_in_doubt(rows[i])]
    tested = list(data_limited) + sign_suspects
    if tested:  # (the full KK test, and conj(Z)'s only where it fails almost everywhere)
        n_points = rows.shape[-1]
        same_metric = weighting in (None, "modulus")  # (the chain's 1/|Z| weighting: another one's fit need not minimise rms_rel)
        for i, (valid, hint, chain_params) in zip(tested, known.verdicts(freq, rows, tested, attrs)):
            if i not in data_limited:
                if hint:
                    out[i], blamed[i], hints[i] = (f"{SIGN_CAUSE_NOTE}; {SIGN_HINT_LEAD}{hint}",), False, f"; {SIGN_HINT_LEAD}{hint}"
                continue
            kk = data_limited[i]
            if valid and not sigma_wrong[i] and misfit_beyond_chain(rms[i], kk, n_points, n_free if same_metric else None, chain_params):
                beyond = (
                    f"this fit's rms_rel is over {MODEL_MISFIT_OVER_CONSISTENT:g}× that" if rms[i] > MODEL_MISFIT_OVER_CONSISTENT * kk
                    else f"this fit's χ² is over {1 + MODEL_MISFIT_NOISE_SHARE:g}× the chain's, its AIC more than {MODEL_MISFIT_DELTA_AIC:g} worse with the parameters counted"
                )
                out[i] = (
                    f"{MISFIT_IS_MODELS}: the data pass the Kramers–Kronig test (their {kk * 100:.2g} % rms_rel from its Voigt chain is their noise) "
                    f"and {beyond}; {DIAGNOSIS_ADVICE}",
                )
                blamed[i] = True
            elif hint:
                out[i] = (f"{out[i][0]}; {SIGN_HINT_LEAD}{hint}",)
                hints[i] = f"; {SIGN_HINT_LEAD}{hint}"
    # (a data-limited note stays one unless the model was blamed instead)
    return [tuple(Note(text, (MISFIT, *([MODEL_MISFIT] if blamed[i] else []), *([DATA_LIMIT] if i in data_limited and not blamed[i] else []),
                              *([sign_hint_tag(hints[i])] if hints[i] else []))) for text in notes) for i, notes in enumerate(out)]


REMAINDER_ATTRS = ("total", "skin", "touchscreen")
"""The attrs naming the three spectra a remainder Z_total − Z_skin − Z_TS was subtracted from
(``impedax remaining``, ``impedax gap --remaining``): data that carry them are a remainder, whose
Re Z < 0 comes from the subtraction, not from the instrument."""
def is_remainder(attrs) -> bool:
    """Whether a spectrum's attrs mark it a remainder of a subtraction (`REMAINDER_ATTRS`)."""
    return all(k in attrs for k in REMAINDER_ATTRS)


def unidentified_group_note(group, ratio: float) -> str:
    """The warning on one near-null direction's parameters ``group`` (`statistics.null_sets`)
    with the smallest-to-largest singular-value ``ratio``: single, batch and global fits say it
    in these words."""
    if len(group) == 1:
        return f"{group[0]} is not determined by the data (near-singular Jacobian, singular-value ratio {ratio:.1e}): Z hardly changes with it"
    return (
        f"{', '.join(group)} are not separately determined by the data (near-singular Jacobian, "
        f"singular-value ratio {ratio:.1e}): only a combination of them changes Z; fix one of them{_one_element_reason(group)}"
    )


def _one_element_reason(group) -> str:
    """Why a group of two parameters of one element goes together, where `_PAIR_REASONS` says
    so without numbers (R and τ: an element seen in one of its limits), else "". On REAL battery
    cycle 64 a G at τ = 8.6e8 s (its W limit) would otherwise be told only to fix R or τ."""
    if len(group) != 2:
        return ""
    (owner_a, _, name_a), (owner_b, _, name_b) = (str(n).rpartition(".") for n in group)
    why = _PAIR_REASONS.get(frozenset((name_a, name_b)), "") if owner_a and owner_a == owner_b else ""
    return "" if "{}" in why else why


def diagnose_identifiability(names, values, stderr, corr, null_sets, ratio, at_bound=()) -> list[str]:
    """Identifiability warnings: one for each group of ``null_sets`` (kept as data in
    `FitResult.unidentified_groups`), then correlations and large relative errors."""
    notes = []
    flagged: set[frozenset] = set()
    for group in null_sets:
        notes.append(unidentified_group_note(group, ratio))
        flagged.add(frozenset(group))
    # (none with a parameter at a bound or a vanishing term's: its correlation is the
    # linearisation's at a constrained point, and the result gives it none)
    unreported = {n for n in names if n in at_bound or np.isinf(stderr[n])}
    for i, j in np.argwhere(np.abs(corr) > CORRELATION_LIMIT).tolist():  # in (i, j) order
        if i < j and not any({names[i], names[j]} <= g for g in flagged) and not {names[i], names[j]} & unreported:
            rel = (_relative_error(values[names[i]], stderr[names[i]]), _relative_error(values[names[j]], stderr[names[j]]))
            notes.append(correlated_note(names[i], names[j], corr[i, j], rel))
    for n in names:
        v, e = values[n], stderr[n]
        if n not in at_bound and undetermined(v, e) and not any(n in g for g in flagged):
            notes.append(undetermined_note(n, abs(e / v)))
    return notes


EXACT_RMS_REL = 1e-10
"""A fit whose rms_rel is below this matches its data to rounding: exact (noise-free) data."""


KK_CHAIN_WORDS = "the KK test's Voigt chain fitted to every point as this fit is"
"""How the misfit notes name the model they compare a fit with (`kk.KKChains`): a least-squares
chain on every point, as the fit is. `impedax kk`'s rms_rel can be higher: it leaves stray points
out of its chain and measures them against it (REAL Gamry data: 4.8 % here, 5.21 % there)."""


def settled_codes(code, z_model, z) -> np.ndarray:
    """Solver codes (`SolverStatus`, …) with a fit stopped at its step limit counted converged
    where it matches its data to rounding (rms_rel below `EXACT_RMS_REL`): on exact data a term
    vanishing toward its natural bound (R1 → 0, in log space) lowers χ² in proportion at every
    step and never meets the relative stopping rule, though nothing the data can tell is left to
    change (Z = 5 Ω at 30 frequencies fitted with R0 + R1 ∥ C1 runs to the step limit at rms_rel
    1.9e-12, and is not told "raise --max-steps"). Single and batch fits alike."""
    code = np.asarray(code)
    exact = (code == SolverStatus.MAX_STEPS) & (rms_rel_of(z_model, z) < EXACT_RMS_REL)
    return np.where(exact, int(SolverStatus.CONVERGED), code)


def fit_notes(
    table: ParameterTable, values: dict, stderr: dict, corr, null_sets, ratio, *, finite: bool, converged: bool, message: str, sides=None, freq=None, z=None,
) -> tuple[str, ...]:
    """The warnings of a fit: not converged, identifiability (`diagnose_identifiability`; no
    relative-error note for a parameter at a bound), parameters at a bound (``sides`` (K,),
    `confirm_bounds`; by default the candidates of `bound_sides` without stderr; worded by
    `on_bound` against the spectrum ``z`` (N,) at ``freq``)."""
    free_names = table.free_names
    free = table.free_index
    if sides is None:
        sides = bound_sides(table, np.array([values[n] for n in table.names]), None)
    at_bound = at_bound_names(table, sides)
    notes = diagnose_identifiability(list(free_names), values, stderr, corr, null_sets, ratio, at_bound) if finite else []
    x = np.array([[values[n] for n in table.names]])
    if finite:  # (a group's note comes first in `diagnose_identifiability`, one per group)
        for k, note in same_arc_notes(table, x[0], null_sets).items():
            notes[k] = note
    e = np.array([[stderr[n] for n in table.names]])
    sides = np.asarray(sides)[None]
    z_rows = None if z is None else np.asarray(z)[None]
    on, exactly = on_bound(table, x, sides, freq, z_rows), on_bound(table, x, sides, freq, z_rows, NUMERICALLY_ON_FRACTION)
    notes += [_bound_note_of(table, 0, j, x, e, sides, on, exactly) for j in np.flatnonzero(sides[0]).tolist()]
    if finite:
        notes += [note for _, note in near_bound_notes(table, x, e, sides)]
    notes += [note for _, note in resistor_like_notes(table, x, freq)]
    notes += [note for _, note in warburg_like_notes(table, x, freq)]
    notes += [note for _, note in arc_beyond_band_notes(table, x, freq, _settled(table, x, e, sides))]
    if not converged:
        notes.insert(0, f"fit did not converge: {message}")
    return tuple(notes)


def near_bound_notes(table: ParameterTable, values: np.ndarray, stderr: np.ndarray, sides: np.ndarray) -> list[tuple[int, str]]:
    """(fit, note) for each free parameter of fits with values and stderr (B, P) that is not at a
    bound (``sides`` (B, K) zero) and not undetermined, yet within `BOUND_STDERR_FRACTION`
    standard errors of a finite bound (`bound_sides`: R0 = 0.00125 ± 0.00109 Ω beside 0, α =
    0.99995 ± 0.0006 beside 1): its ± interval crosses the bound, where no value lies, so it is
    not the symmetric interval it reads as; a statistician's audit found 103 of 122 such R0
    values (true 1 mΩ) reported without a word. The note names the posterior as the honest one.
    Value and error read as in the report (`format_uncertain`: "W1.sigma = 2.8 ± 1.4 mΩ s^-1/2"
    of a REAL Autolab fit, not "0.00275 ± 0.0014 Ω s^-1/2"). A value within 1e-4 of
    its bound yet more standard errors from it is said by its distance, rounded to its error, and
    named the simpler model where the bound reduces its element: "CPE1.alpha lies (8.4 ± 1.6)e-15
    below its upper bound 1, on it to 1 part in 10⁴ or better (CPE1 with alpha = 1 is a
    capacitor: …)" (REAL data.ods, an exact spectrum). A standard error of exactly 0 is none to
    speak of (a global fit's shared parameter in each spectrum's notes, whose group says it
    once: "CPE2.alpha = 1 ± 0 lies within 2 standard errors" is not printed for each of the REAL
    130 battery cycles)."""
    values, stderr = np.atleast_2d(values), np.atleast_2d(stderr)
    candidates = bound_sides(table, values, stderr)
    near = (candidates != 0) & (np.asarray(sides) == 0) & ~undetermined_mask(table, values, stderr, sides) & (stderr[..., table.free_index] != 0)
    out = []
    for b, j in np.argwhere(near).tolist():
        i = table.free_index[j]
        value, error = float(values[b, i]), float(stderr[b, i])
        # the side `bound_sides` found: α = 1 − 8e-15 ± 1.5e-15 is within 1e-4 of its upper bound 1,
        # not 2 standard errors of it, and is not to be said near its lower bound 0 (REAL data.ods)
        side, bound = ("upper", float(table.upper[i])) if candidates[b, j] > 0 else ("lower", float(table.lower[i]))
        at = format_bound(bound, table.units[i])
        if abs(bound - value) > BOUND_STDERR_FRACTION * error:  # (within 1e-4 of it, more standard errors away: `bound_sides`)
            # its distance from the bound, not the value's 16 digits: "CPE1.alpha = 0.9999999999999916 ±
            # 0.0000000000000015 lies 8.4e-15 from its upper bound 1" (REAL data.ods)
            reduced_side, simpler = table.reductions.get(table.names[i], (None, ""))
            out.append((b, (
                f"{table.names[i]} lies {format_uncertain(abs(bound - value), error, table.units[i])} {'below' if side == 'upper' else 'above'} its {side} bound {at}"
                + (", on it to 1 part in 10⁴ or better" if bound else "") + (f" ({simpler})" if reduced_side == side else "")
            )))
            continue
        out.append((b, (
            f"{table.names[i]} = {format_uncertain(value, error, table.units[i])} lies within {BOUND_STDERR_FRACTION:g} standard errors of its {side} bound {at}: "
            "the ± is not symmetric there (no value lies beyond the bound)" + SAMPLE_ADVICE
        )))
    return out


def resistor_like_notes(table: ParameterTable, values: np.ndarray, freq=None) -> list[tuple[int, str]]:
    """(fit, note) for each free CPE exponent of fits with values (B, P) below
    `RESISTOR_LIKE_ALPHA` (``table.resistor_like``): the CPE acts nearly as a resistor, Z =
    (jω)^−α/Q of phase −απ/2, whose value 1/(Q ω^α) still varies with frequency (given at the
    ends of ``freq`` [Hz]); the note names the R that may take its place, as the α = 1 bound note
    names the C (`reductions.reducing_bounds`)."""
    values = np.atleast_2d(np.asarray(values, float))
    out = []
    for alpha_name, (element, q_name, resistor) in table.resistor_like.items():
        a, q = table.names.index(alpha_name), table.names.index(q_name)
        for b in np.flatnonzero(values[:, a] < RESISTOR_LIKE_ALPHA).tolist():
            alpha, big_q = float(values[b, a]), float(values[b, q])
            varies = ""
            if freq is not None and np.size(freq) and big_q > 0:
                f_lo, f_hi = float(np.min(freq)), float(np.max(freq))
                r_of = lambda f: 1 / (big_q * (2 * math.pi * f) ** alpha)  # noqa: E731
                varies = f", {format_quantity(r_of(f_hi), 'Ohm')} at {format_frequency(f_hi)} to {format_quantity(r_of(f_lo), 'Ohm')} at {format_frequency(f_lo)}"
            simpler = f"; the model with {resistor} in its place may be enough" if resistor is not None else ""
            out.append((b, (
                f"{alpha_name} = {alpha:.2g} is below {RESISTOR_LIKE_ALPHA:g}: {element} acts nearly as a resistor (Z = (jω)^−α/Q, phase −{90 * alpha:.2g}°), "
                f"one whose value 1/(Q ω^α) still varies with frequency{varies}{simpler}"
            )))
    return out


def warburg_like_notes(table: ParameterTable, values: np.ndarray, freq=None) -> list[tuple[int, str]]:
    """(fit, note) for each free τ of a Wo, Ws or G (``table.warburg_like``) of fits with values
    (B, P) that acts as a semi-infinite Warburg over the whole band of ``freq`` [Hz]: within
    `WARBURG_LIKE_DEVIATION` of it at the lowest frequency, where they differ most
    (`reductions.warburg_deviation`). The note names the W that may take its place with its
    σ = R/√(2τ), as the α = 1 bound note names a CPE's C. On REAL battery cycle 64 a G at
    τ = 8.6e8 s would otherwise be told only that R and τ go together."""
    if freq is None or not np.size(freq):
        return []
    values = np.atleast_2d(np.asarray(values, float))
    omega_min = 2 * math.pi * float(np.min(freq))
    out = []
    for tau_name, (element, r_name, warburg, sigma_unit, symbol) in table.warburg_like.items():
        t, r = table.names.index(tau_name), table.names.index(r_name)
        deviation = warburg_deviation(symbol, omega_min * values[:, t])
        for b in np.flatnonzero(deviation <= WARBURG_LIKE_DEVIATION).tolist():
            tau, resistance = float(values[b, t]), float(values[b, r])
            out.append((b, (
                f"{element} acts as a semi-infinite Warburg over the whole band (ω_min·τ = {omega_min * tau:.2g}: its Z is within {float(deviation[b]):.1g} of R/√(jωτ)): "
                f"the model with {warburg} in its place, σ = R/√(2τ) = {format_quantity(resistance / math.sqrt(2 * tau), sigma_unit)}, may be enough, with one parameter fewer"
            )))
    return out


def _settled(table: ParameterTable, values: np.ndarray, stderr: np.ndarray, sides) -> np.ndarray:
    """(B, P) True for the parameters of fits with values and stderr (B, P) and bound sides (B, K)
    that are neither at a bound nor undetermined (fixed ones included): those whose value says
    something (`arc_beyond_band_notes` holds no other against the band)."""
    values = np.atleast_2d(values)
    settled = np.ones(values.shape, bool)
    settled[:, table.free_index] = (np.asarray(sides) == 0) & ~undetermined_mask(table, values, np.atleast_2d(stderr), sides)
    return settled


SAME_TAU_RTOL = 0.01
"""Two R ∥ C (or R ∥ CPE of one α) blocks whose τ agree within this relative tolerance, their
parameters in one near-null direction of the fit, are one arc to the data (`same_arc_notes`)."""


def same_arc_notes(table: ParameterTable, values: np.ndarray, null_sets) -> dict[int, str]:
    """{position of a group in ``null_sets``: its note} for each near-null group holding every
    parameter of two arcs (``table.arcs``) that relax at the same τ within `SAME_TAU_RTOL` (and
    share α, for R ∥ CPE), at one fit's ``values`` (P,): the data see one arc where the model has
    two, and fixing one parameter, as the group's note advises, leaves the rest undetermined.
    On the REAL ZPlot file R0 + R1 || C1 + R2 || C2 ended with both at τ = 15.6 µs, and --fix
    R2=10 as advised sends C2 to 3e10 F (a walkthrough)."""
    out = {}
    at = {n: float(values[table.names.index(n)]) for n in table.names}
    arcs = [(r, c, symbol, params, float(arc_taus(symbol, at[r], *(at[n] for n in params)))) for r, c, symbol, params in table.arcs]
    for k, group in enumerate(null_sets):
        members = set(group)
        for i, j in itertools.combinations(range(len(arcs)), 2):
            (r1, c1, s1, p1, tau1), (r2, c2, s2, p2, tau2) = arcs[i], arcs[j]
            same = s1 == s2 and np.isfinite(tau1) and np.isfinite(tau2) and abs(tau1 - tau2) <= SAME_TAU_RTOL * max(tau1, tau2)
            if s1 == "CPE":
                same = same and abs(at[p1[1]] - at[p2[1]]) <= SAME_TAU_RTOL
            if same and {r1, *p1, r2, *p2} <= members:
                out[k] = (
                    f"{r1} || {c1} and {r2} || {c2} relax at the same τ = {format_quantity(tau1, 's')} ({format_frequency(1 / (2 * math.pi * tau1))}): "
                    f"the data see one arc where the model has two, so {', '.join(group)} are not separately determined; drop one of the two arcs "
                    "(fixing one of its parameters leaves the others undetermined)"
                )
                break
    return out


def arc_beyond_band_notes(table: ParameterTable, values: np.ndarray, freq=None, settled=None) -> list[tuple[int, str]]:
    """(fit, note) for each R ∥ C or R ∥ CPE block (``table.arcs``) of fits with values (B, P)
    whose relaxation frequency 1/(2πτ) lies outside the band of ``freq`` [Hz] by more than
    `arcs.BEYOND_BAND_FACTOR`: the data see one flank of it, and its C (above the band) or its
    R (below) is an extrapolation of the model (`arcs.ArcBeyondBand`). On the REAL ZPlot file
    (3 kHz–300 kHz) refine's R_relax ∥ C_relax relaxes at 2.24 MHz. ``settled``
    (B, P): a block with a parameter not settled (`_settled`: at a bound, undetermined) is left
    to the notes that say so (an open branch's R1 at ∞ has no relaxation frequency to speak of)."""
    if freq is None or not np.size(freq) or not table.arcs:
        return []
    values = np.atleast_2d(np.asarray(values, float))
    settled = np.ones(values.shape, bool) if settled is None else np.atleast_2d(settled)
    band = (float(np.min(freq)), float(np.max(freq)))
    out = []
    for r_name, c_name, symbol, params in table.arcs:
        tau = arc_taus(symbol, values[:, table.names.index(r_name)], *(values[:, table.names.index(n)] for n in params))
        with np.errstate(all="ignore"):
            f = 1 / (2 * math.pi * tau)
        block = [table.names.index(n) for n in (r_name, *params)]
        outside = np.isfinite(tau) & (tau > 0) & ((f > band[1] * BEYOND_BAND_FACTOR) | (f < band[0] / BEYOND_BAND_FACTOR)) & settled[:, block].all(axis=1)
        for b in np.flatnonzero(outside).tolist():
            arc = ArcBeyondBand(r_name, c_name, float(tau[b]), band)
            out.append((b, f"{arc.elements}: {arc.sentence()}; {arc.remedy()}"))
    return out


def stack_notes(
    table: ParameterTable, values: np.ndarray, stderr: np.ndarray, corr: np.ndarray, sides: np.ndarray | None = None, *, freq=None, z=None,
    null_sets=None, ratios=None,
) -> dict[int, tuple[str, ...]]:
    """`fit_notes` of a stack of converged fits: values and stderr (B, P), correlations
    (B, K, K), bound sides (B, K), spectra z (B, N) at ``freq`` (as `fit_notes`), and for fits
    with near-null directions their groups ``null_sets`` (one list of groups per fit, empty for
    the others; None: none has any) and singular-value ``ratios`` (B,) (`statistics.null_sets`).
    The conditions are evaluated for all fits at once and text is built only for the notes due,
    in `fit_notes`' order; fits without notes are left out of the returned {row: notes}. (A
    batch's ~35 of 130 REAL battery cycles with a near-null direction under Wo took 13.8 ms a
    call as one `fit_notes` each.)"""
    names = table.free_names
    free = table.free_index
    v, e = values[:, free], stderr[:, free]
    notes: dict[int, list[str]] = collections.defaultdict(list)
    upper_triangle = np.triu(np.ones((len(names),) * 2, bool), 1)
    with np.errstate(all="ignore"):
        relative_error = np.abs(e / v)
    if sides is None:
        sides = bound_sides(table, values, None)
    grouped, same_group = _group_notes(table, values, null_sets, ratios, notes)  # (first, as `diagnose_identifiability`'s)
    unreported = (np.asarray(sides) != 0) | np.isinf(e)  # (as `diagnose_identifiability`)
    reported_pair = ~(unreported[:, :, None] | unreported[:, None, :] | same_group)
    correlated = np.argwhere((np.abs(corr) > CORRELATION_LIMIT) & upper_triangle & reported_pair)
    pairs = {(i, j): correlated_note_parts(names[i], names[j]) for i, j in set(map(tuple, correlated[:, 1:].tolist()))}
    for (b, i, j), r in zip(correlated.tolist(), corr[tuple(correlated.T)].tolist()):
        parts = pairs[i, j]  # (most pairs' note differs by r alone: its text around r built once)
        notes[b].append(f"{parts[0]}{r:+.3f}{parts[1]}" if parts is not None else correlated_note(names[i], names[j], r, (float(relative_error[b, i]), float(relative_error[b, j]))))
    unknown = undetermined_mask(table, values, stderr, sides) & ~grouped
    for b, i in np.argwhere(unknown).tolist():
        notes[b].append(undetermined_note(names[i], float(relative_error[b, i])))
    on, exactly = on_bound(table, values, sides, freq, z), on_bound(table, values, sides, freq, z, NUMERICALLY_ON_FRACTION)
    exact_notes: dict[tuple[int, bool], str] = {}  # (a parameter exactly on a bound: its note names no value, one text per parameter and side)
    for (b, i), exact in zip(np.argwhere(sides != 0).tolist(), exactly[sides != 0].tolist()):
        key = (i, bool(sides[b, i] > 0))
        if not exact:
            notes[b].append(_bound_note_of(table, b, i, values, stderr, sides, on, exactly))
        else:
            notes[b].append(exact_notes[key] if key in exact_notes else exact_notes.setdefault(key, _bound_note_of(table, b, i, values, stderr, sides, on, exactly)))
    for b, note in near_bound_notes(table, values, stderr, sides):
        notes[b].append(note)
    for b, note in resistor_like_notes(table, values, freq):
        notes[b].append(note)
    for b, note in warburg_like_notes(table, values, freq):
        notes[b].append(note)
    for b, note in arc_beyond_band_notes(table, values, freq, _settled(table, values, stderr, sides)):
        notes[b].append(note)
    return {b: tuple(n) for b, n in notes.items()}


def _group_notes(table: ParameterTable, values: np.ndarray, null_sets, ratios, notes) -> tuple[np.ndarray, np.ndarray]:
    """Append to ``notes`` ({row: list}) each near-null group's note of fits with values (B, P)
    (`stack_notes`' ``null_sets`` and ``ratios``), as `fit_notes` words them (`same_arc_notes` in
    place of `unidentified_group_note` where it has one); return which free parameters (B, K) and
    which pairs of them (B, K, K) a group of their fit holds, of whom no undetermined or correlated
    note is said (`diagnose_identifiability`)."""
    index = {n: k for k, n in enumerate(table.free_names)}
    k = len(index)
    grouped, same_group = np.zeros((len(values), k), bool), np.zeros((len(values), k, k), bool)
    for b, groups in enumerate(() if null_sets is None else null_sets):
        if not groups:
            continue
        same_arc = same_arc_notes(table, values[b], groups)
        for g, group in enumerate(groups):
            notes[b].append(same_arc[g] if g in same_arc else unidentified_group_note(group, ratios[b]))
            columns = np.array([index[n] for n in group], int)
            grouped[b, columns] = True
            same_group[b, columns[:, None], columns[None, :]] = True
    return grouped, same_group


def user_bounds_text(fit: "FitResult") -> str:
    """``fit``'s user bounds (`FitResult.bounds`) in words, each end in its parameter's unit
    (`data.format_bound`): "R1 within 1 mΩ..10 mΩ, CPE1.alpha within 0.5..0.9" (the "bounded
    in" line of ``impedax compare`` and `Comparison.report`, a diagnosis' note; not
    "R1 within 0.001..0.01"). A model's label keeps the plain numbers
    (`comparison.bounds_text`: it names the model)."""
    specs = fit.circuit.parameter_specs(fit.registry)
    return ", ".join(f"{n} within {format_bound(lo, specs[n].unit)}..{format_bound(hi, specs[n].unit)}" for n, (lo, hi) in fit.bounds.items())


def user_bounds(table: ParameterTable, circuit: Circuit, registry: Registry) -> dict[str, tuple[float, float]]:
    """The bounds the user set (``bounds=``) on free parameters: those of ``table`` that differ
    from the element's natural ones (`ParameterSpec.narrowed_sides`)."""
    specs = circuit.parameter_specs(registry)
    out = {}
    for i, name in enumerate(table.names):
        if table.fixed[i]:
            continue
        lo, hi = float(table.lower[i]), float(table.upper[i])
        if specs[name].narrowed_sides(lo, hi):
            out[name] = (lo, hi)
    return out


def fit_result(
    circuit, table: ParameterTable, freq, z, out: SolverOutput, weighting: str, n_starts: int, elapsed: float, registry: Registry,
    *, chi2_at_x: Callable | None = None, extra_notes: tuple[str, ...] = (), start: str = "the data-driven start", weights=None, starts_words: str | None = None,
) -> FitResult:
    """The `FitResult` of one spectrum's `SolverOutput`: uncertainties, status and warnings.
    ``chi2_at_x`` (as `confirm_bounds`, for this spectrum as number 0) lets parameters be
    found at a bound by their standard errors; without it only values within 1e-4 of a nonzero
    bound are. ``extra_notes`` (e.g. `weighting_notes`) follow the others. ``weights`` (the
    inverse weights (Re, Im) of the residuals, (N,) each) lets a converged fit be checked for a
    parameter at a bound while chi² falls inward (`falling_inward`): such a fit is reported not
    converged, and the parameter not at its bound. ``starts_words``: what a multistart's
    ``n_starts`` starts were (`single.starts_words`), after "best of N starts: " in the message.
    The tags of ``extra_notes`` (`notes.Note`s: `data_notes`') are the fit's
    `FitResult.warning_tags`; its own warnings have none."""
    names = table.names
    free_names = table.free_names
    x = out.x
    chi2 = float(out.chi2)
    finite = np.isfinite(chi2) and np.all(np.isfinite(out.z_model))
    n = 2 * len(freq)
    k = len(free_names)
    chi2_red = chi2 / (n - k) if n > k else math.nan
    z_model = np.asarray(out.z_model)
    if finite:
        cov, corr, null_sets, ratio = uncertainties(out.jacobian, chi2_red, weighting, free_names)
        stderr_free = np.sqrt(np.clip(np.diag(cov), 0, None)) if k else np.zeros(0)
    else:
        # overflow: nothing is determined; say so with infinities, never NaN dressed as a result
        chi2 = math.inf
        z_model = np.where(np.isfinite(z_model), z_model, np.inf)
        cov, corr, null_sets, ratio = np.diag(np.full(k, np.inf)), np.eye(k), [], 0.0
        stderr_free = np.full(k, np.inf)
    values = {nm: float(v) for nm, v in zip(names, x)}
    stderr = {nm: math.nan for nm in names}
    stderr.update({nm: float(e) for nm, e in zip(free_names, stderr_free)})
    solver_code = SolverStatus(int(out.code))
    code = SolverStatus(int(settled_codes(solver_code, z_model, z)))
    converged = bool(finite and code == SolverStatus.CONVERGED)
    if not finite:
        message = "the model's impedance or weighted residuals are not finite (overflow) at every start; check bounds, fixed values and the frequency range"
    elif code == SolverStatus.CONVERGED:
        origin = f"from {start}" if n_starts == 1 else f"best of {n_starts} starts" + (f": {starts_words}" if starts_words else "")
        steps = f"{int(out.steps)} step{'' if int(out.steps) == 1 else 's'}"
        message = (f"converged in {steps} ({origin})" if solver_code == SolverStatus.CONVERGED else
                   f"fits the data to rounding (rms_rel {float(rms_rel_of(z_model, z)):.1e}) after {steps}, where a term still vanishing toward its bound changes Z by less ({origin})")
    else:
        message = code.message
    x_all = np.array([values[nm] for nm in names])[None]
    if finite and chi2_at_x is not None:
        sides = confirm_bounds(table, x_all, bound_sides(table, x_all, np.array([stderr[nm] for nm in names])[None]), chi2_at_x, n)[0]
        if k:
            sides = vanishing_term_sides(circuit, registry, table, x_all, sides[None], freq, np.asarray(z)[None], np.asarray(out.jacobian)[None])[0]
        if converged and weights is not None and k:
            inward = falling_inward(table, x_all, np.asarray(out.jacobian)[None], np.asarray(z)[None], z_model[None], np.asarray(weights[0])[None], np.asarray(weights[1])[None], weighting, chi2_at_x)[0][0]
            if inward.any():  # not a bound optimum: the solver stopped where its coordinate is flat
                sides = np.where(inward != 0, 0, sides).astype(np.int8)
                converged, message = False, inward_message(table, inward)
    else:
        sides = bound_sides(table, x_all, None)[0]
    # a term that changes Z by < 1e-6: its parameters at the natural bound that explains it, or undetermined
    free_values, free_stderr = np.array([values[nm] for nm in free_names])[None], np.array([stderr[nm] for nm in free_names])[None]
    candidates = vanishing_candidates(np.asarray(sides)[None], free_values, free_stderr)
    vanishing = vanishing_parameters(circuit, registry, table, x_all, freq, candidates, np.asarray(out.jacobian)[None])[0] if finite and k else np.zeros(k, np.int8)
    sides, free_stderr, vanished = settle_vanishing(vanishing[None], np.asarray(sides)[None], free_values, free_stderr)
    sides = sides[0]
    if finite and k:  # the others' errors hold a vanishing term's parameters at no bound at their values (`held_covariances`)
        held = vanishing_term_mask(circuit, registry, table, x_all, freq, np.asarray(out.jacobian)[None]) & (sides == 0)
        if held.any():
            cov, corr = (a[0] for a in held_covariances(np.asarray(out.jacobian)[None], chi2_red, weighting, cov[None], corr[None], held))
            free_stderr = np.where(held | vanished, free_stderr, np.sqrt(np.clip(np.diag(cov), 0, None)))
    free_stderr = unidentified_stderr(free_names, null_sets, sides, free_stderr[0])[None]  # (undetermined whatever χ²_red is)
    stderr.update(zip(free_names, free_stderr[0].tolist()))
    # the warnings speak of the linearisation (a bound note off its bound quotes its standard error)
    notes = fit_notes(table, values, stderr, corr, null_sets, ratio, finite=finite, converged=converged, message=message, sides=sides, freq=freq, z=z)
    if finite:
        e_all = np.array([stderr[nm] for nm in names])[None]
        notes += idle_branch_notes(circuit, registry, table, x_all, undetermined_mask(table, x_all, e_all, np.asarray(sides)[None]) | vanished, freq).get(0, ())
        # ... the result gives no standard error, nor correlations, to a parameter at a bound or a vanishing term's
        shown, shown_corr = without_error(np.asarray(sides)[None], vanished, free_stderr, np.asarray(corr)[None])
        stderr.update(zip(free_names, shown[0].tolist()))
        corr = shown_corr[0]
    notes += tuple(extra_notes)
    return FitResult(
        circuit=circuit,
        values=values,
        stderr=stderr,
        fixed={nm: bool(f) for nm, f in zip(names, table.fixed)},
        free_names=free_names,
        covariance=cov,
        correlation=corr,
        frequency=np.asarray(freq),
        z_data=np.asarray(z),
        z_model=z_model,
        weighting=weighting,
        chi2=chi2,
        converged=converged,
        message=message,
        n_evaluations=int(out.steps_total),
        warnings=tuple(str(n) for n in notes),
        n_starts=n_starts,
        elapsed_s=elapsed,
        at_bound=at_bound_names(table, sides),
        unidentified_groups=parameter_groups(null_sets),
        registry=registry,
        bounds=user_bounds(table, circuit, registry),
        warning_tags=notes_tags(notes),
    )
