"""Model comparison: rms_rel, reduced chi², AIC, AICc, BIC, ΔAIC, Akaike weights and, for
nested models fitted to the same data, the F-test of the extra parameters (docs/fitting.md,
"Comparing models")."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import numpy as np
import xarray as xr

from ..arguments import checked_arguments, sequence_of
from ..circuits import DEFAULT_REGISTRY, Circuit, Registry
from ..circuits.nesting import embedding
from ..data import column_width, concise_repr, format_percent_column, format_quantity, report_text
from ..errors import FitError, FitsNotComparable
from ..io.netcdf import result_dataset
from .least_squares import BatchFitResult, FitResult
from .least_squares.branches import idle_note_reduced, undetermined_names
from .bayes.evidence import EvidenceDoubt, WaicDoubt
from .least_squares.notes import MISFIT, MODEL_MISFIT, Note, sign_hint_tag
from .least_squares.result import BOUND_CHI2_FRACTION, value_shown_at_bound, data_difference, SIGN_HINT_LEAD, fit_data_limit, misfit_hint, user_bounds_text, with_warnings
from .frozen import FrozenResult, freeze_fields
from .problem import WEIGHTING_SCALES, WEIGHTINGS
from .statistics import KNOWN_SIGMA, UNKNOWN_VARIANCE, known_noise_criteria

__all__ = ["compare", "Comparison", "WEAK_DELTA_AIC", "is_nested", "nested_as_held", "boundary_parameters", "boundary_limits", "unidentified_limits", "chi_bar_squared_p_value", "undetermined_names", "criteria", "akaike_weights", "KNOWN_SIGMA", "UNKNOWN_VARIANCE", "TIE_CHI2_REL", "criteria_tie", "SIGMA_CHI2_RED_RANGE", "register_batch_compare"]


def fit_label(fit: FitResult) -> str:
    """A fit's name in a comparison: its model, followed by its fixed values and its bounds
    (``bounds=``, `bounds_text`) when it has any (``R0 + R1 || CPE1 [CPE1.alpha=1]``,
    ``R0 + R1 || CPE1 [R1 within 10..50]``), so the same circuit fitted free, with a parameter
    held or with one bounded reads as that many models (a bounded fit read ``M (2)``, the label
    of the same fit given twice)."""
    held = [f"{n}={fit.values[n]:g}" for n, is_fixed in fit.fixed.items() if is_fixed]
    held += bounds_text(fit)
    return f"{fit.model} [{', '.join(held)}]" if held else fit.model


def bounds_text(fit: FitResult) -> list[str]:
    """``fit``'s user bounds (`FitResult.bounds`) as ``NAME within LO..HI`` in plain numbers, as
    a model's label and the table's ``bounds`` column hold them (the report's "bounded in" line
    writes them with units: `user_bounds_text`)."""
    return [f"{n} within {lo:g}..{hi:g}" for n, (lo, hi) in fit.bounds.items()]


def unique_labels(labels: Sequence[str]) -> list[str]:
    """``labels`` with a repeated one numbered from its second use (``M (2)``): rows and the
    xarray coordinate name each fit once."""
    seen: dict[str, int] = {}
    out = []
    for label in labels:
        seen[label] = seen.get(label, 0) + 1
        out.append(label if seen[label] == 1 else f"{label} ({seen[label]})")
    return out


SIGMA_CHI2_RED_RANGE = (0.5, 2.0)
"""Under ``weighting="sigma"`` the table says so when the lowest reduced χ² of the models is
outside this range: the sigma do not describe the scatter about the best-fitting model, and ΔAIC
are about χ²_red times those of the unknown-variance form (n ln(χ²_a/χ²_b) ≈ Δχ²/χ²_red). Above
it, about no model; below it, the line names the models below it when others are not."""


WEAK_DELTA_AIC = 4.0
"""The best model's lead is weak when a rival is less than this far behind in AIC: Burnham &
Anderson (2002, Model Selection and Multimodel Inference, §2.6) give models within ΔAIC 2 of the
best "substantial support" and those 4–7 behind "considerably less"; below 4 the data barely tell
the two apart (a SYNTHETIC Meyer finger with a CPE skin at α = 0.99, 1 % noise: ΔAIC 2.66 for the
CPE, BIC for the capacitor)."""
UNRELIABLE_MARK = "*"
"""The table's mark on a log evidence its posterior's warnings call unreliable (a footnote line
under the table says so)."""


TIE_CHI2_REL = 1e-6
"""Two information criteria tie when they differ by no more than a relative change of χ² this
size would make them: the solver's tolerance, as `NESTED_WORSE_REL` (one optimum reached from two
starts or in two writings; `_same_fit` calls fits with χ² this close one fit). The solver stops
when a step lowers χ² by less than 1e-8 of it (`lm_iteration`'s rtol), so the χ² of one optimum
differ by about that and more; on BioLogic's real file ``R0 + R1 || CPE1`` and ``R0 + CC1`` (one
impedance function) gave AICs 5.7e-13 apart, which picked "best" by rounding."""


def criteria_tie(value: float, other: float, aic_form: str, chi2: float, n: int) -> bool:
    """Whether the information criteria ``value`` and ``other`` (AIC, AICc or BIC of fits to the
    same n real values) tie: they differ by at most the change a relative change `TIE_CHI2_REL`
    of χ² makes, n·TIE_CHI2_REL under `UNKNOWN_VARIANCE` (d(n ln χ²) = n dχ²/χ²) and
    χ²·TIE_CHI2_REL under `KNOWN_SIGMA` (``chi2``: the larger of the two fits')."""
    scale = n if aic_form == UNKNOWN_VARIANCE else chi2
    return abs(value - other) <= TIE_CHI2_REL * scale


def significant(x: float, digits: int = 3) -> str:
    """``x`` to ``digits`` significant digits, trailing zeros kept (1.00 next to 1.02, where
    ``:.3g`` printed 1), without a dangling point (100, not 100.)."""
    text = f"{x:#.{digits}g}"
    return text[:-1] if text.endswith(".") else text


def criteria(fit: FitResult) -> dict:
    """``aic``, ``bic``, ``aicc`` and ``aic_form`` of ``fit`` over its n = 2N real data values
    and k free parameters. Under ``weighting="sigma"`` (`KNOWN_SIGMA`): AIC = χ² + 2k,
    BIC = χ² + k ln n; otherwise (`UNKNOWN_VARIANCE`) the fit's own, n ln(χ²/n) + 2k and
    n ln(χ²/n) + k ln n. AICc = AIC + 2k(k + 1)/(n − k − 1) (Hurvich & Tsai 1989), NaN where
    n − k − 1 ≤ 0 (undefined). ``fit``: a `FitResult`, or anything with its ``n_points``,
    ``n_params``, ``chi2``, ``weighting``, ``aic`` and ``bic`` (a batch's spectrum,
    `batch_comparison.SpectrumStatistics`)."""
    n, k, chi2 = 2 * fit.n_points, fit.n_params, float(fit.chi2)
    if fit.weighting == "sigma":
        (aic, bic), form = known_noise_criteria(chi2, n, k), KNOWN_SIGMA
    else:
        aic, bic, form = float(fit.aic), float(fit.bic), UNKNOWN_VARIANCE
    aicc = aic + 2 * k * (k + 1) / (n - k - 1) if n - k - 1 > 0 else math.nan
    return {"aic": aic, "bic": bic, "aicc": aicc, "aic_form": form}


def akaike_weights(values) -> tuple[np.ndarray, np.ndarray]:
    """Δ_i = IC_i − min IC and w_i = exp(−Δ_i/2)/Σ_j exp(−Δ_j/2) of information criteria
    ``values``; a NaN value (AICc undefined) has NaN Δ and weight and is left out of the sum."""
    x = np.asarray(values, float)
    delta, weights = np.full(x.shape, math.nan), np.full(x.shape, math.nan)
    ok = ~np.isnan(x)
    if ok.any():
        delta[ok] = x[ok] - x[ok].min()
        w = np.exp(-delta[ok] / 2)
        weights[ok] = w / w.sum()
    return delta, weights


def is_nested(simple: Circuit, complex_: Circuit, registry: Registry = DEFAULT_REGISTRY) -> bool:
    """Whether ``simple`` is a special case of ``complex_``: ``complex_`` with elements removed
    (a series element set to 0, a parallel branch opened) and/or replaced by the simpler
    elements they contain in a limit (a capacitor for a CPE at α = 1, a W for a Wo at τ → ∞:
    `ElementSpec.limits`; `impedax.circuits.nesting.embedding`)."""
    return len(list(simple.elements())) <= len(list(complex_.elements())) and embedding(simple, complex_, registry) is not None


def nested_as_held(simple: Circuit, simple_held: Mapping[str, object], complex_: Circuit, complex_held: Mapping[str, object], registry: Registry = DEFAULT_REGISTRY) -> bool:
    """`is_nested` for fits that hold parameters fixed (``*_held``: name → value, or values
    over spectra): each parameter ``complex_`` holds must be held alike in ``simple``, on the
    element of ``simple`` it stands for (same kind, `embedding`) and at the same value. A held
    parameter of an element ``simple`` lacks, or reaches only through a limit, breaks the
    nesting: the reduction needs it at its bound or limit, which a held value does not reach
    (``R0 + R1 || CPE1 + L1`` with L1 held at 100 µH does not contain ``R0 + R1 || C1``: an
    F-test between them would compare models that are not nested)."""
    if not is_nested(simple, complex_, registry):
        return False
    if not complex_held:
        return True
    standing = {}  # a parameter of ``complex_`` → the one of ``simple`` it stands for
    for small, large, limit in embedding(simple, complex_, registry):
        if limit is None:
            standing.update(zip(registry[large.symbol].parameter_names(large.name), registry[small.symbol].parameter_names(small.name)))
    for name, value in complex_held.items():
        counterpart = standing.get(name)
        if counterpart not in simple_held or not np.allclose(np.asarray(simple_held[counterpart], float), np.asarray(value, float), rtol=1e-12, atol=0.0):
            return False
    return True


def held_values(fit: FitResult) -> dict[str, float]:
    """The parameters ``fit`` holds fixed, name → value."""
    return {n: fit.values[n] for n, held in fit.fixed.items() if held}


@dataclass(frozen=True, eq=False)
class Comparison(FrozenResult):
    """The comparison table, one row per model in the order given; ``best`` has the lowest AIC
    (AIC ranks; ``aic_form`` says which AIC, `criteria`; `best_aicc_index` the lowest AICc)."""

    __repr__ = concise_repr  # (the generated one printed every row of the table in full)
    __str__ = report_text  # (print(result): its report)

    rows: tuple[dict, ...]
    f_tests: tuple[dict, ...]
    fits: tuple[FitResult, ...]
    aic_form: str = UNKNOWN_VARIANCE  # `KNOWN_SIGMA` under weighting="sigma" (`criteria`)

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def source(self) -> str | None:
        """Where the data came from (`common_source` of the fits): what `impedax.write_result` records."""
        return common_source(self.fits)

    def _lowest(self, indices, column: str = "aic") -> int | None:
        """The position among ``indices`` of the lowest ``column`` (an information criterion),
        ties (`criteria_tie`) broken by the fewer free parameters, then the order given: which
        of two fits of one optimum is "best" is not left to the solver's rounding."""
        indices = list(indices)
        if not indices:
            return None
        low = min(self.rows[i][column] for i in indices)
        tied = [i for i in indices if criteria_tie(self.rows[i][column], low, self.aic_form, self.rows[i]["chi2"], 2 * self.fits[0].n_points)]
        return min(tied, key=lambda i: (self.rows[i]["n_params"], i))

    @property
    def best_index(self) -> int:
        """Position of the best model by AIC in ``rows`` and ``fits`` (models may repeat: the
        same circuit fixed and free); of AICs tied to the solver's tolerance (`criteria_tie`),
        the model with fewer free parameters, then the one given first."""
        return self._lowest(range(len(self.rows)))

    def tied_with_best_indices(self) -> list[int]:
        """Positions of the other models whose AIC ties with the best one's (`criteria_tie`): the
        data cannot rank them, and `best_index` chose by the tie-break."""
        best = self.best_index
        aic, chi2, n = self.rows[best]["aic"], self.rows[best]["chi2"], 2 * self.fits[0].n_points
        return [i for i, r in enumerate(self.rows) if i != best and criteria_tie(r["aic"], aic, self.aic_form, max(r["chi2"], chi2), n)]

    @property
    def best_label_with_ties(self) -> str:
        """The best model's label, with the models tied with it: ``X (tied with Y)`` (the plot's title)."""
        tied = [self.rows[i]["label"] for i in self.tied_with_best_indices()]
        return self.rows[self.best_index]["label"] + (f" (tied with {', '.join(tied)})" if tied else "")

    @property
    def best_determined_index(self) -> int | None:
        """Position of `best_determined`, or None (ties broken as `best_index`)."""
        return self._lowest(i for i, f in enumerate(self.fits) if not undetermined_names(f))

    @property
    def best(self) -> str:
        return self.rows[self.best_index]["model"]

    @property
    def best_aicc_index(self) -> int | None:
        """Position of the lowest AICc, or None when no model has one (n − k − 1 ≤ 0)."""
        return self._lowest((i for i, r in enumerate(self.rows) if not math.isnan(r["aicc"])), "aicc")

    @property
    def best_determined(self) -> str | None:
        """The model of lowest AIC among the fits that leave no parameter undetermined
        (`undetermined_names`); None when every fit leaves one."""
        i = self.best_determined_index
        return None if i is None else self.rows[i]["model"]

    def summary(self) -> dict:
        """The JSON of ``impedax compare --json`` (and ``--out FILE.json``): each model's fit
        summary (parameters, warnings) with its row (the row's ``aic`` and ``bic`` are the
        comparison's, `criteria`), the best models, the F-tests, which AIC ranks and ``warnings``
        (every model's, `labelled_warnings`)."""
        i = self.best_aicc_index
        j = self.best_determined_index
        models = [{**f.summary(), **r, "aic_form": self.aic_form} for f, r in zip(self.fits, self.rows)]
        return {
            "models": models, "best": self.best, "best_determined": self.best_determined,
            "f_tests": [dict(t) for t in self.f_tests], "ranked_by": "aic", "aic_form": self.aic_form, "best_aicc": None if i is None else self.rows[i]["model"],
            # (the models' labels: the model text with the fixed values, `fit_label`)
            "best_label": self.rows[self.best_index]["label"], "best_determined_label": None if j is None else self.rows[j]["label"],
            "best_aicc_label": None if i is None else self.rows[i]["label"],
            "weak_evidence": self.weak_evidence(),  # (None when the best model's lead is clear)
            "reduces_to_best": self.reduces_to_best(),  # (None when no model reduces to the best)
            "tied_with_best": [self.rows[i]["label"] for i in self.tied_with_best_indices()],  # ([] when no AIC ties the best's)
            "best_misfit_hint": self.best_misfit_hint(),  # (None unless the best still misses structure, small as its misfit looks)
            "undetermined_best": self.undetermined_best(),  # (None unless the best leaves a parameter undetermined)
            "warnings": labelled_warnings((m["label"], m["warnings"]) for m in models),  # (as every command's JSON has it)
        }

    def undetermined_best(self) -> dict | None:
        """What the table says when the best model by AIC leaves a parameter undetermined, or
        None when it does not. Keys: ``best`` (label), ``undetermined`` (its parameters),
        ``reduced`` (the circuits without an idle term that its fit's warnings name,
        `idle_note_reduced`), ``best_determined`` (the label of `best_determined`, or None) with
        its ``delta_aic``, ``far_worse`` (that ΔAIC is at least `DECISIVE_DELTA_AIC`), ``note``.
        A model with every parameter determined that far behind is no alternative: on CH
        Instruments' REAL file the table named R0 + R1 || C1 + R2 || C2, at 20.8 % against the
        best's 7.51 % (ΔAIC 297), where the best's own warning named R0 + CPE1 + W1, the model
        without its idle R1, which fits the same."""
        best = self.best_index
        names = undetermined_names(self.fits[best])
        if not names:
            return None
        reduced = list(dict.fromkeys(r for r in map(idle_note_reduced, _warning_texts(self.fits[best])) if r))
        determined = self.best_determined_index
        label = self.rows[best]["label"]
        delta = None if determined is None else self.rows[determined]["delta_aic"]
        far_worse = delta is not None and delta >= DECISIVE_DELTA_AIC
        note = f"{label} leaves {', '.join(names)} undetermined"
        if reduced:
            note += f": the data hold {' or '.join(reduced)}, the model without {'it' if len(names) == 1 else 'them'}, which fits the same (its warnings say so)"
        if determined is None:
            note += "; so does every other model" if len(self.rows) > 1 else "; there is no other model"
        elif far_worse:
            note += (f"; the best model with every parameter determined, {self.rows[determined]['label']}, fits far worse (ΔAIC {delta:.2f}), "
                     + ("so compare the reduced model, not that one" if reduced else "no alternative to it: reduce the best model as its warnings say"))
        else:
            note += f"; the best model with every parameter determined is {self.rows[determined]['label']} (ΔAIC {delta:.2f})"
        return {"best": label, "undetermined": list(names), "reduced": reduced,
                "best_determined": None if determined is None else self.rows[determined]["label"], "delta_aic": delta, "far_worse": far_worse, "note": note}

    def best_misfit_hint(self) -> str | None:
        """The hint that the best model misses structure the data hold, small as its misfit
        looks (`least_squares.result.misfit_hint`: a single fit weighted by |Z| with rms_rel
        from 0.2 % to 2 % and above 5× a Kramers–Kronig-consistent model's); None otherwise.
        Above 2 % the best fit's own warning says it. On impedance.py's REAL exampleData the
        best of three battery models fits at 1.14 %, 6.3× the 0.18 % the Voigt chain reaches,
        and the comparison said nothing of it: the best of the models given is not yet
        adequate, and a diagnosis shows what is missing."""
        fit = self.fits[self.best_index]
        return misfit_hint(fit) if isinstance(fit, FitResult) else None

    def to_table(self) -> list[dict]:
        """One row per model, as ``compare --out FILE.csv`` writes them: the columns of the table
        with chi2, the AICc deltas and weights, the undetermined parameters and the user's bounds
        (``bounds``, `bounds_text`; both ``;``-joined), and the ``weighting`` (what chi2 and AIC
        are against), then ``warnings`` (the fit's, joined by "; ", "" if none,
        as a single fit's and a batch comparison's tables have them)."""
        return [{**r, "undetermined": ";".join(undetermined_names(f)), "bounds": ";".join(bounds_text(f)), "weighting": f.weighting, "warnings": "; ".join(f.warnings)}
                for r, f in zip(self.rows, self.fits)]

    def weak_evidence(self) -> dict | None:
        """How weakly the data prefer the best model by AIC, or None when its lead is clear: a
        rival less than `WEAK_DELTA_AIC` behind, or picked by BIC, or — when every row has a
        reliable log evidence (posteriors) — by the log evidence. The rival is the model BIC
        picks, else the one the log evidence picks, else the runner-up by AIC; a fit that is the
        best's own (``same_fit_as``) is no rival, nor one that reduces to it (`reduces_to_best`:
        its ΔAIC = 2Δk is all AIC can say for the smaller model, not a weak lead). Keys: ``best``, ``rival`` (labels),
        ``delta_aic`` (the rival's), ``threshold``, ``bic_prefers`` and
        ``log_evidence_prefers`` (a label other than the best's, or None), ``note`` (the
        table's line)."""
        best = self.best_index
        reduced = self.reduces_to_best_indices()
        others = [i for i, r in enumerate(self.rows) if i != best and r.get("same_fit_as") != self.rows[best]["label"] and i not in reduced]
        if not others:
            return None
        label = lambda i: self.rows[i]["label"]  # noqa: E731
        by_bic = min(range(len(self.rows)), key=lambda i: self.rows[i]["bic"])
        bic_rival = by_bic if by_bic in others and self.rows[by_bic]["bic"] < self.rows[best]["bic"] else None
        evidence_rival = None
        if all(r.get("log_evidence_reliable") for r in self.rows):
            by_evidence = max(range(len(self.rows)), key=lambda i: self.rows[i]["log_evidence"])
            evidence_rival = by_evidence if by_evidence in others and self.rows[by_evidence]["log_evidence"] > self.rows[best]["log_evidence"] else None
        runner_up = min(others, key=lambda i: self.rows[i]["aic"])
        rival = next(i for i in (bic_rival, evidence_rival, runner_up) if i is not None)
        delta = self.rows[rival]["delta_aic"]
        if not delta < WEAK_DELTA_AIC and bic_rival is None and evidence_rival is None:
            return None
        reasons = [f"ΔAIC {delta:.2f}" + (f" < {WEAK_DELTA_AIC:g}" if delta < WEAK_DELTA_AIC else "")]
        reasons += [f"BIC prefers {label(bic_rival)}"] if bic_rival is not None else []
        reasons += [f"the log evidence prefers {label(evidence_rival)}"] if evidence_rival is not None else []
        note = f"the data barely tell {label(best)} from {label(rival)}: {' and '.join(reasons) if delta < WEAK_DELTA_AIC else ', but '.join(reasons)}"
        return {
            "best": label(best), "rival": label(rival), "delta_aic": float(delta), "threshold": WEAK_DELTA_AIC,
            "bic_prefers": None if bic_rival is None else label(bic_rival), "log_evidence_prefers": None if evidence_rival is None else label(evidence_rival), "note": note,
        }

    def reduces_to_best_indices(self) -> list[int]:
        """Positions of the models whose F-test with the best one, or with a model tied with it
        (`tied_with_best_indices`), says they reduce to it: ``"reason": "reduces_to_simple"``
        (`_boundary_note`: an extra parameter on its bound, χ² no lower), or a valid test with
        F ≤ `NOISE_F` (the extra parameters lower χ² no more than noise alone would)."""
        return sorted(self._reduced_to_best())

    def _reduced_to_best(self) -> dict[int, int]:
        """{position of a model that reduces to the best or to a model tied with it: position of
        that model} (`reduces_to_best_indices`), the best preferred."""
        best = self.best_index
        ties = [best] + self.tied_with_best_indices()
        position = {r["label"]: i for i, r in enumerate(self.rows)}
        out: dict[int, int] = {}
        for t in self.f_tests:
            simple, complex_ = position.get(t.get("simple_label")), position.get(t.get("complex_label"))
            if simple not in ties or complex_ is None or complex_ in ties:
                continue
            if t.get("reason") == "reduces_to_simple" or (t.get("valid", True) and t["f"] <= NOISE_F):
                if complex_ not in out or ties.index(simple) < ties.index(out[complex_]):
                    out[complex_] = simple
        # the same fit as a model that reduces (``same_fit_as``): its χ² is that model's, no lower
        # than the best's, though no F-test nests it (REAL ZPlot: R0 + R1 || C1 + R2 || C2, its two
        # arcs at one τ, is R0 + R1 || CPE1 + W1's fit, which reduces to R0 + R1 || CPE1; it was the
        # best's "rival" by ΔAIC 2.00, the penalty of one extra parameter)
        grown = True
        while grown:
            grown = False
            for i, r in enumerate(self.rows):
                j = position.get(r.get("same_fit_as"))
                if i not in out and i not in ties and j in out and r["n_params"] >= self.rows[best]["n_params"]:
                    out[i], grown = out[j], True
        return out

    def reduces_to_best(self) -> dict | None:
        """The models that reduce to the best one (`reduces_to_best_indices`), or None. Their
        χ² is no lower, so their ΔAIC is the 2 per extra parameter AIC charges, the clearest lead
        AIC gives a smaller model (Burnham & Anderson 2002, §3.2; Arnold 2010, J. Wildl. Manage.
        74:1175, on uninformative parameters). Their Akaike weights stay as computed (the
        standard exp(−ΔAIC/2), normalised) and are that penalty, not support: the line says so,
        and `weak_evidence` does not count them. Keys: ``best``, ``rivals`` (labels),
        ``delta_aic`` (theirs), ``note`` (the table's line)."""
        targets = self._reduced_to_best()
        reduced = sorted(targets)
        if not reduced:
            return None
        best = self.rows[self.best_index]["label"]
        names = [self.rows[i]["label"] for i in reduced]
        one = len(reduced) == 1
        deltas = ", ".join(f"{self.rows[i]['delta_aic']:.2f}" for i in reduced)
        weights = ", ".join(f"{self.rows[i]['akaike_weight']:.3f}" for i in reduced)
        into = sorted(set(targets.values()))
        to = " and ".join(self.rows[j]["label"] + ("" if j == self.best_index else f" (tied with the best, {best})") for j in into)
        note = (
            f"{names[0] if one else ', '.join(names[:-1]) + ' and ' + names[-1]} {'reduces' if one else 'reduce'} to {to}: the extra {'element lowers' if one else 'elements lower'} χ² "
            f"no more than noise alone would, so {'it adds' if one else 'they add'} nothing; ΔAIC {deltas} {'is' if one else 'are'} about the 2 per extra parameter AIC charges, the clearest lead it gives "
            f"the smaller model, and the Akaike weight{'' if one else 's'} {weights} {'is' if one else 'are'} that penalty, not support"
        )
        # ("reduces_to": for each rival, the label of the model it reduces to, the best or one tied with it)
        return {"best": best, "rivals": names, "delta_aic": [float(self.rows[i]["delta_aic"]) for i in reduced], "note": note,
                "reduces_to": [self.rows[targets[i]]["label"] for i in reduced]}

    def _best_mark(self, *, warnings_below: bool) -> str:
        """The table's mark of the best model by AIC, saying when its fit did not converge or has
        warnings (an undetermined parameter, a gross misfit): the lowest AIC is then no
        endorsement; and when another model gives the same fit (`SAME_FIT_RMS`).
        ``warnings_below``: `report` lists the warnings under the table; `table` alone does not,
        and points to `report`."""
        best = self.best_index
        warnings = self.fits[best].warnings
        n = len({w for ws in warnings.values() for w in ws}) if isinstance(warnings, Mapping) else len(warnings)
        where = "below" if warnings_below else "(report() lists them)"
        mark = "   ← best" + (f" by AIC, with {n} warning(s) {where}" if n else "")
        if not self.rows[best]["converged"]:
            mark += " (its fit did not converge)"
        same = self.rows[best].get("same_fit_as")
        if same:
            mark += f"; tied with {same}: the same fit, the data cannot tell them apart"
        tied = [self.rows[i]["label"] for i in self.tied_with_best_indices() if self.rows[i]["label"] != same]
        if tied:
            mark += f"; {'' if same else 'tied '}with the same AIC as {', '.join(tied)} (to the solver's tolerance): best by the fewer parameters, then the order given"
        return mark

    def report(self) -> str:
        """The table, the bounds each fit had (``bounded in LABEL: R1 within 10 Ω..50 Ω``, as
        ``impedax compare`` prints them), then the warnings every model has (once) and each
        model's others."""
        lines = [self.table(warnings_below=True)] + self._bounded_lines()
        common, own = self.warnings_by_model()
        if common:
            lines += ["every model:"] + [f"  - {w}" for w in common]
        for row, warnings in zip(self.rows, own):
            if warnings:
                lines += [f"{row['label']}" + (" (besides those of every model):" if common else ":")] + [f"  - {w}" for w in warnings]
        return "\n".join(lines)

    def warnings_by_model(self) -> tuple[list[str], list[list[str]]]:
        """The warnings every model has (the data's own Kramers–Kronig misfit, quoted alike for
        each), and each model's others, in the order of `fits` (a batch's warnings flattened)."""
        texts = [_warning_texts(fit) for fit in self.fits]
        common = [w for w in texts[0] if all(w in t for t in texts[1:])] if len(texts) > 1 else []
        return common, [[w for w in t if w not in common] for t in texts]

    def table(self, *, warnings_below: bool = False) -> str:
        """The models side by side (rms_rel, χ²_red, AIC, AICc, BIC, ΔAIC, Akaike weight), the
        criteria's notes and the F-tests; `report` adds each model's warnings. The best model's
        mark counts its warnings and says where they are: ``warnings_below`` when the caller
        prints them under the table (`report`, ``impedax compare``), else it points to
        ``report()``."""
        extra = [c for c in ("log_evidence", "waic") if any(c in r for r in self.rows)]
        width = column_width((r["label"] for r in self.rows), "model")
        head = f"{'model':<{width}}  {'k':>2}  {'rms_rel':>10}  {'chi2_red':>10}  {'AIC':>9}  {'AICc':>9}  {'BIC':>9}  {'ΔAIC':>7}  {'weight':>6}" + "".join(f"  {c:>12}" for c in extra)
        lines = [head]
        best = self.best_index
        rms = format_percent_column([r["rms_rel"] for r in self.rows])  # (3 significant digits, the decimal points lined up)
        for i, (r, percent) in enumerate(zip(self.rows, rms)):
            aicc = "—" if math.isnan(r["aicc"]) else f"{r['aicc']:.2f}"
            line = f"{r['label']:<{width}}  {r['n_params']:>2}  {percent:>8} %  {r['chi2_red']:>10.4g}  {r['aic']:>9.2f}  {aicc:>9}  {r['bic']:>9.2f}  {r['delta_aic']:>7.2f}  {r['akaike_weight']:>6.3f}"
            line += "".join(f"  {self._extra_cell(r, c):>12}" for c in extra)
            if i == best:
                line += self._best_mark(warnings_below=warnings_below)
            else:
                line += "   (did not converge)" if not r["converged"] else ""
                line += f"   (the same fit as {r['same_fit_as']})" if r.get("same_fit_as") else ""
            lines.append(line)
        undetermined = self.undetermined_best()
        if undetermined is not None:
            lines.append(undetermined["note"])
        weak = self.weak_evidence()
        if weak is not None:
            lines.append(weak["note"])
        reduced = self.reduces_to_best()
        if reduced is not None:
            lines.append(reduced["note"])
        hint = self.best_misfit_hint()
        if hint is not None:
            lines.append(f"{self.rows[best]['label']} (the best): {hint}")
        unreliable = [r["label"] for r in self.rows if r.get("log_evidence_reliable") is False]
        waic_doubts = [r["label"] for r in self.rows if r.get("waic_reliable") is False]
        if unreliable:  # (WAIC named as the way out only where every model's is sound)
            lines.append(f"{UNRELIABLE_MARK} log evidence unreliable or undefined by the posterior's own warnings (listed with the model's): {', '.join(unreliable)}"
                         + ("; compare these models by WAIC" if not waic_doubts else ""))
        if waic_doubts:
            lines.append(f"{UNRELIABLE_MARK} WAIC undefined, from a chain too short to estimate τ, or unreliable by the posterior's own warnings (listed with the model's): "
                         f"{', '.join(waic_doubts)}; do not compare models by it")
        lines += self._criteria_lines()
        for t in self.f_tests:
            test = (f"F = {t['f']:.3g}, p = {t['p_value']:.3g}" + (f" ({t['note']})" if t.get("note") else "")) if t.get("valid", True) else f"no test: {t['note']}"
            lines.append(f"F-test {t.get('simple_label', t['simple'])}  ⊂  {t.get('complex_label', t['complex'])}: {test}")
        return "\n".join(lines)

    @staticmethod
    def _extra_cell(row: dict, column: str) -> str:
        """A posterior column's cell: the value, marked `UNRELIABLE_MARK` when it is a log
        evidence or a WAIC the row calls unreliable (``log_evidence_reliable``, ``waic_reliable``);
        "undefined" for a value that is not finite and "—" in a least-squares fit's row, which has
        none (not "nan", as the AICc column writes "—")."""
        if column not in row:
            return "—"
        value = f"{row[column]:.2f}" if math.isfinite(row[column]) else "undefined"
        return value + UNRELIABLE_MARK if row.get(f"{column}_reliable") is False else value

    def _criteria_lines(self) -> list[str]:
        """What the table says of its criteria: the AIC of known noise under sigma weighting (and
        when the sigma do not describe the scatter, `SIGMA_CHI2_RED_RANGE`: about every model,
        or about the models named), the models without
        an AICc, and a best by AICc other than the best by AIC."""
        lines = []
        n = 2 * self.fits[0].n_points
        scale = WEIGHTING_SCALES.get(self.fits[0].weighting)
        if scale:  # (the weighting named, as a fit's report names it)
            lines.append(f"weighting {self.fits[0].weighting}: chi2_red relative to {scale}, not to the noise; AIC = n ln(χ²/n) + 2k, BIC = n ln(χ²/n) + k ln n")
        if self.aic_form == KNOWN_SIGMA:
            lines.append("AIC = χ² + 2k and BIC = χ² + k ln n: the data's sigma taken as the known noise (weighting sigma)")
            finite = [r for r in self.rows if math.isfinite(r["chi2_red"])]
            lowest = min((r["chi2_red"] for r in finite), default=math.nan)
            low, high = SIGMA_CHI2_RED_RANGE
            if lowest > high or lowest < low:
                side = "understate" if lowest > high else "overstate"
                scale = f"these ΔAIC are about {lowest:.3g}× those of the unknown-variance form n ln(χ²/n) + 2k; check the sigma, or compare with another weighting"
                below = [r for r in finite if r["chi2_red"] < low]
                if lowest > high or len(below) == len(finite):  # (above the range: the lowest is, so every model is)
                    lines.append(f"the lowest reduced χ² is {lowest:.3g}: the sigma {side} the scatter about every model, and {scale}")
                else:  # (below it: only some may be, not every model)
                    named = lambda rs: ", ".join(f"{r['label']} {r['chi2_red']:.3g}" for r in rs)  # noqa: E731
                    lines.append(
                        f"the lowest reduced χ² is {lowest:.3g}: the sigma overstate the scatter about {named(below)}, "
                        f"not about the other models ({named([r for r in finite if r['chi2_red'] >= low])}); {scale}"
                    )
        for r in self.rows:
            if math.isnan(r["aicc"]):
                k = r["n_params"]
                lines.append(f"AICc is undefined for {r['label']}: n − k − 1 = {n - k - 1} with n = {n} real data values and k = {k} (it needs n ≥ k + 2); left out of the AICc weights")
        i = self.best_aicc_index
        if i is not None and i != self.best_index and not self.rows[i]["aicc"] >= self.rows[self.best_index]["aicc"]:  # (NaN: the best by AIC has none)
            lines.append(f"by AICc (small-sample correction) the best is {self.rows[i]['label']} (AICc weight {self.rows[i]['akaike_weight_aicc']:.3f}); the ranking above is by AIC")
        return lines

    def _bounded_lines(self) -> list[str]:
        """``bounded in LABEL: R1 within 10 Ω..50 Ω`` for each fit with bounds of the user's (in
        their units, `user_bounds_text`; the label keeps its plain numbers)."""
        return [f"bounded in {row['label']}: {user_bounds_text(fit)}" for row, fit in zip(self.rows, self.fits) if fit.bounds]

    def to_xarray(self) -> xr.Dataset:
        """The criteria of each model over ``model`` (its label; ``circuit`` the model's text),
        as the report's table (rms_rel, chi2_red, AIC, AICc, BIC, ΔAIC, Akaike weights, ...), and
        the F-tests over ``f_test`` (``f_test_simple``, ``f_test_complex``, F, degrees of freedom,
        p, valid, note); ``impedax_kind`` "comparison". The fits themselves are not in it."""
        # the coordinate "model" holds the labels (`fit_label`: a fit with fixed values named by
        # them, so each fit has its own); the variable "circuit" the models' text; "bounds" and
        # "undetermined" as in `to_table` (``;``-joined, "" for none); "same_fit_as" the label or ""
        # (not None, which a file reads back as NaN, a float, where no model tied)
        cols = [c for c in self.rows[0] if c not in ("model", "label")]
        data = {c: ("model", [r.get(c, math.nan) for r in self.rows]) for c in cols}
        data["same_fit_as"] = ("model", np.array([r.get("same_fit_as") or "" for r in self.rows], str))
        data["circuit"] = ("model", [r["model"] for r in self.rows])
        table = self.to_table()
        for column in ("bounds", "undetermined"):
            data[column] = ("model", [row[column] for row in table])
        # the F-tests of the report over ``f_test``: the models by their labels,
        # F, its degrees of freedom, p, whether it holds and the note ("" for none)
        tests = self.f_tests
        data.update({
            "f_test_simple": ("f_test", np.array([t["simple_label"] for t in tests], str)), "f_test_complex": ("f_test", np.array([t["complex_label"] for t in tests], str)),
            "f_test_f": ("f_test", np.array([t["f"] for t in tests], float)), "f_test_df1": ("f_test", np.array([t["df1"] for t in tests], int)),
            "f_test_df2": ("f_test", np.array([t["df2"] for t in tests], int)),
            "f_test_p_value": ("f_test", np.array([math.nan if t["p_value"] is None else t["p_value"] for t in tests], float)),
            "f_test_valid": ("f_test", np.array([t["valid"] for t in tests], bool)), "f_test_note": ("f_test", np.array([t["note"] or "" for t in tests], str)),
        })
        # ``impedax_kind``: `impedax.load` of the written .nc names it, not "no variable 'Z'"
        return result_dataset(xr.Dataset(data, coords={"model": [r["label"] for r in self.rows]}, attrs={"impedax_kind": "comparison", "aic_form": self.aic_form}).copy(deep=True))

    def _repr_html_(self) -> str:
        """The notebook display, as `FitResult`'s: a row per model (its label, k, rms_rel,
        reduced χ², AIC, ΔAIC, Akaike weight, BIC), the best mark, what the table says under
        its rows and the F-tests, the user's bounds (as `report`), and the figure of `plot`."""
        from ..plotting.html import result_html

        best = self.best_index
        rows = [
            {"model": r["label"], "k": r["n_params"], "rms_rel [%]": significant(r['rms_rel'] * 100), "chi2_red": f"{r['chi2_red']:.4g}", "AIC": f"{r['aic']:.2f}",
             "ΔAIC": f"{r['delta_aic']:.2f}", "weight": f"{r['akaike_weight']:.3f}", "BIC": f"{r['bic']:.2f}",
             "": self._best_mark(warnings_below=True).strip() if i == best else ("did not converge" if not r["converged"] else "")}
            for i, r in enumerate(self.rows)
        ]
        lines = self.table(warnings_below=True).splitlines()[len(self.rows) + 1 :] + self._bounded_lines()  # (the lines under the table's rows: best determined, criteria, F-tests; then the bounds, as `report`)
        for fit, row in zip(self.fits, self.rows):  # each model's warnings, as `report`
            warnings = [w for ws in fit.warnings.values() for w in ws] if isinstance(fit.warnings, Mapping) else list(fit.warnings)
            lines += [f"{row['label']}: {w}" for w in warnings]
        return result_html(f"comparison of {len(self.rows)} model{'s' if len(self.rows) != 1 else ''}: best {self.best_label_with_ties}", rows, lines=lines, figure=self.plot)

    def plot(self, *, figsize: tuple[float, float] | None = None):
        """Data with every model's fit, and each model's relative residuals (Figure;
        `plotting.comparison.plot_comparison`; ``figsize`` (width, height) [in])."""
        from ..plotting.comparison import plot_comparison

        return plot_comparison(self, figsize=figsize)


_batch_compare: Callable | None = None
"""`batch_comparison.compare_batches`, registered by that module (`register_batch_compare`) for
`compare` of batches: this module may not import it, since it imports this one."""


def register_batch_compare(compare_batches: Callable) -> None:
    """Let `compare` hand batches of fits to ``compare_batches``."""
    global _batch_compare
    _batch_compare = compare_batches


def common_source(fits) -> str | None:
    """Where the data of ``fits`` came from when every one says the same (their ``source``,
    `FitResult.source`), else None."""
    sources = {getattr(f, "source", None) for f in fits}
    return sources.pop() if len(sources) == 1 else None


def weightings_differ(ref, i: int, other) -> FitsNotComparable:
    """The error of `compare` when fits[``i``] (``other``) was fitted with another weighting than
    fits[0] (``ref``): both named with their models and weightings, and the choices."""
    return FitsNotComparable(f"fits[0] ({ref.model}, weighting '{ref.weighting}') and fits[{i}] ({other.model}, weighting '{other.weighting}') were fitted with different weightings, "
                             f"so their χ² and AIC are not on one scale; fit both with one weighting (choose one of {', '.join(WEIGHTINGS)})")


@checked_arguments(fits=sequence_of(FitResult, BatchFitResult, attribute="fit", what="FitResult (or Posterior, or BatchFitResult)"))
def compare(fits: Sequence) -> "Comparison | BatchComparison":  # (BatchComparison: batch_comparison.py)
    """Compare least-squares fits of several models to the same data.

    Columns: rms_rel, chi2_red, AIC, AICc, BIC (`criteria`: χ² + 2k under ``weighting="sigma"``,
    n ln(χ²/n) + 2k otherwise; AICc = AIC + 2k(k + 1)/(n − k − 1), NaN where undefined), ΔAIC
    (to the lowest) and Akaike weights w_i = exp(−ΔAIC_i/2)/Σ exp(−ΔAIC_j/2), the same from
    AICc (``delta_aicc``, ``akaike_weight_aicc``), and an F-test for each nested pair:
    F = ((χ²_s − χ²_c)/(k_c − k_s)) / (χ²_c/(n − k_c)), its p from the F distribution, or, where the
    smaller model is the larger one at a limit on the edge of its space (a W for a Wo at τ → ∞,
    `boundary_limits`), from the chi-bar-squared mixture (`chi_bar_squared_p_value`, Self & Liang
    1987: half the F-test's p for one such limit; ``note`` says so; where a limit leaves a parameter
    not identified, `unidentified_limits`, ``note`` says its p is typically too small, Davies
    1977, 1987), not made (``valid`` false, ``reason``
    and ``note`` say why) when the larger model fits worse, sits with a parameter at its bound
    (`boundary_parameters`) or fits to rounding. AIC ranks. Items may also be posteriors
    with a ``fit`` attribute; their ``log_evidence`` and ``waic`` become extra columns.

    Items that are batches of fits (`BatchFitResult`: ``fit`` of a stack of spectra, one per
    model, all of the same spectra with the same weighting) give a `BatchComparison`
    (`batch_comparison.compare_batches`): each spectrum's criteria, each model's wins and its
    AIC summed over the spectra (their joint AIC, the spectra being independent).
    """
    items = list(fits)
    if len(items) < 1:
        raise FitsNotComparable("compare needs at least one fit")
    batches = [isinstance(x, BatchFitResult) for x in items]
    if any(batches):
        if not all(batches):
            i, j = batches.index(True), batches.index(False)
            raise FitsNotComparable(f"compare takes fits of one spectrum or batches of fits of many, not both: fits[{i}] is a {type(items[i]).__name__} of {items[i].n_spectra} spectra, "
                           f"fits[{j}] a fit of one spectrum; for that spectrum use batch.fit_of(DIM=LABEL)")
        if _batch_compare is None:  # (not reached: impedax.fitting imports batch_comparison, which registers it)
            raise FitError("compare of batches needs impedax.fitting.batch_comparison imported")
        return _batch_compare(items)
    results = [_with_posterior_warnings(x) for x in items]
    ref = results[0]
    for i, r in enumerate(results[1:], 1):
        difference = data_difference(r.frequency, r.z_data, ref.frequency, ref.z_data)
        if difference is not None:
            which = f"fits[0] ({ref.model}) and fits[{i}] ({r.model})" if r.model != ref.model else f"fits[0] and fits[{i}] (both {r.model})"
            raise FitsNotComparable(f"{which} were fitted to different data: {difference} (fmin/fmax or another spectrum?); compare fits of the same spectrum")
        if r.weighting != ref.weighting:
            raise weightings_differ(ref, i, r)
    ics = [criteria(r) for r in results]
    delta, weights = akaike_weights([c["aic"] for c in ics])
    delta_c, weights_c = akaike_weights([c["aicc"] for c in ics])
    rows = []
    labels = unique_labels([fit_label(r) for r in results])
    for i, (item, r, c) in enumerate(zip(items, results, ics)):
        row = {
            "model": r.model, "label": labels[i], "n_params": r.n_params, "rms_rel": r.rms_rel, "chi2": r.chi2, "chi2_red": r.chi2_red, "aic": c["aic"], "aicc": c["aicc"], "bic": c["bic"],
            "delta_aic": float(delta[i]), "akaike_weight": float(weights[i]), "delta_aicc": float(delta_c[i]), "akaike_weight_aicc": float(weights_c[i]), "converged": r.converged,
        }
        for extra in ("log_evidence", "waic"):
            value = getattr(item, extra, None)
            if value is not None:
                row[extra] = float(value() if callable(value) else value)
        if "log_evidence" in row:
            reason = _evidence_unreliable_reason(item)
            row["log_evidence_reliable"] = math.isfinite(row["log_evidence"]) and reason is None
            row["log_evidence_unreliable_reason"] = reason  # (`Posterior.log_evidence_unreliable_reason`; None when sound)
        if "waic" in row:
            reason = _waic_unreliable_reason(item, row["waic"])
            row["waic_reliable"] = reason is None
            row["waic_unreliable_reason"] = reason  # (`Posterior.waic_unreliable_reason`; None when reliable)
        rows.append(row)
    for j, r in enumerate(results):  # a fit another model also gives: the data cannot tell them apart
        twin = next((rows[i]["label"] for i in range(len(results)) if i != j and _same_fit(results[i], r)), None)
        rows[j]["same_fit_as"] = twin
    tests = []
    n = 2 * ref.n_points
    for i, s in enumerate(results):
        for j, c in enumerate(results):
            if i == j or s.n_params >= c.n_params or not nested_as_held(s.circuit, held_values(s), c.circuit, held_values(c), c.registry):
                continue
            dk = c.n_params - s.n_params
            denom = c.chi2 / (n - c.n_params)
            f_value = max(s.chi2 - c.chi2, 0.0) / dk / denom if denom > 0 else math.inf
            limits = boundary_limits(s.circuit, c.circuit, c.registry)
            unidentified = unidentified_limits(s.circuit, c.circuit, c.registry)
            notes = ([_mixture_note(limits, labels[i], labels[j])] if limits else []) + ([_unidentified_note(unidentified, labels[i], labels[j], mixture=bool(limits))] if unidentified else [])
            test = {"simple": s.model, "complex": c.model, "f": float(f_value), "df1": dk, "df2": n - c.n_params, "p_value": chi_bar_squared_p_value(f_value, dk, n - c.n_params, len(limits)),
                    "valid": True, "note": "; ".join(notes) or None, "simple_label": labels[i], "complex_label": labels[j], "reason": None, "at_bound": [],
                    "boundary_limits": limits, "unidentified_limits": unidentified}
            on_boundary = boundary_parameters(s, c)
            # with a parameter at its bound, a hair of excess is the bound's, not a fit short of its
            # optimum: a start on the bound is nudged inside (`fit_of`), and α = 0.999999 left χ²
            # 2e-6–2e-5 above R ∥ C's on SYNTHETIC R ∥ C spectra; the bound rule's own tolerance
            excess = max(NESTED_WORSE_REL * s.chi2, BOUND_CHI2_FRACTION * c.chi2_red) if on_boundary else NESTED_WORSE_REL * s.chi2
            if c.chi2 - s.chi2 > excess:
                test.update(valid=False, reason="not_at_optimum", note=f"{labels[j]} fits worse than {labels[i]}, which it contains: its fit did not reach its optimum; "
                            f"fit it with init= the {labels[i]} fit to start there too (impedax compare does so)")
            elif on_boundary:
                test.update(valid=False, at_bound=on_boundary, **_boundary_note(s, c, labels[i], labels[j], on_boundary))
            elif c.chi2_red < EXACT_CHI2_RED:
                test.update(valid=False, reason="exact_fit", note=f"{labels[j]} fits the data to rounding (chi2_red {c.chi2_red:.1e}): noise-free data, nothing to test against")
            tests.append(test)
    results = [_model_not_data(r, i, results, labels, tests, [row["aic"] for row in rows]) for i, r in enumerate(results)]
    return Comparison(tuple(rows), tuple(tests), tuple(results), ics[0]["aic_form"])


def _waic_unreliable_reason(item, value: float) -> str | None:
    """Why a posterior's WAIC ``value`` is no score to compare models by, None when it is one:
    its ``waic_unreliable_reason`` (`Posterior.waic_unreliable_reason`: not finite, from a chain
    too short to estimate τ, or p_waic over twice the parameters, the rule of its notes, not read
    from their words), or "undefined" for a value that is not finite of an item without one."""
    reason = getattr(item, "waic_unreliable_reason", None)
    return WaicDoubt(reason).value if reason is not None else None if math.isfinite(value) else WaicDoubt.UNDEFINED.value


def _evidence_unreliable_reason(item) -> str | None:
    """Why a posterior's Laplace log evidence is undefined or unreliable, None when it is sound:
    its ``log_evidence_unreliable_reason`` (`Posterior.log_evidence_unreliable_reason`, the cause
    `laplace_evidence` gave beside its note, not read from the note's words)."""
    reason = getattr(item, "log_evidence_unreliable_reason", None)
    return None if reason is None else EvidenceDoubt(reason).value


def _own_warnings(item) -> list[str]:
    """The warnings of a posterior (an item with a ``fit``) that are its own, not its start
    fit's (``least-squares start: …``, which the fit itself carries): `Posterior.own_warnings`
    (an item without them: its warnings less those that begin so); [] for a fit."""
    fit = getattr(item, "fit", None)
    if fit is None or fit is item:
        return []
    own = getattr(item, "own_warnings", None)
    if own is not None:
        return list(own)
    return [w for w in getattr(item, "warnings", ()) if not w.startswith("least-squares start: ")]


def _with_posterior_warnings(item) -> FitResult:
    """The fit a comparison row stands for: ``item`` itself, or a posterior's least-squares start
    with the posterior's own warnings (`_own_warnings`: draws piled up against a prior's edge, a
    Laplace log evidence its shape makes unreliable, a short chain) added to the fit's, so the
    comparison lists them with the model's other warnings."""
    fit = getattr(item, "fit", item)
    own = _own_warnings(item)
    if not own or isinstance(fit.warnings, Mapping):
        return fit
    return with_warnings(fit, fit.tagged_warnings + tuple(w for w in own if w not in fit.warnings))


NOISE_F = 1.0
"""A model nested over the best one reduces to it (`Comparison.reduces_to_best`) when their
valid F-test has F at most this: extra parameters that do nothing lower χ² by about Δk·σ² on
average (F has mean df2/(df2 − 2) ≈ 1 under the null), so a smaller fall is the noise's, and
ΔAIC ≥ Δk (SYNTHETIC R0 + R1 ∥ C1 data, 1 % noise: R0 + R1 ∥ C1 + W1 gives F = 0.0145, ΔAIC 1.99)."""
SAME_FIT_RMS = 1e-3
"""Two fits are one fit when they have as many parameters, χ² within 1e-6 (relative) and model
spectra whose difference (rms, relative to |Z_data|) is below this fraction of their misfit
rms_rel (or below 1e-9): two writings of one impedance function (two arcs in series and the
ladder form), which would split the Akaike weight and the "best" by rounding."""
NESTED_WORSE_REL = 1e-6
"""A model that contains another fits worse only when its χ² exceeds the other's by more than
this fraction: below, the two are one optimum to the solver's tolerance (a term at its bound,
W1.sigma = 0, leaves the smaller model; χ² 1.6e-8 apart on BioLogic's file), not a fit short of
its optimum (the test is then not made for that bound, `boundary_parameters`)."""
EXACT_CHI2_RED = 1e-20
"""Below this reduced χ² a fit is exact to rounding (noise-free data): an F-test compares
rounding errors."""


_LIMIT_RE = re.compile(r"\s*([A-Za-z_]\w*)\s*(?:->|=)\s*(inf|[-+]?[0-9.]+(?:e[-+]?[0-9]+)?)\b")
"""The parameter and its value at the start of an `ElementLimit`'s ``where`` ("tau -> inf", "alpha = 1")."""


def boundary_limits(simple: Circuit, complex_: Circuit, registry: Registry = DEFAULT_REGISTRY) -> list[str]:
    """The limits by which ``simple`` sits in ``complex_`` (`embedding`) at the boundary of
    ``complex_``'s parameter space, each taking one parameter away: a Wo's τ → ∞ (a W), a CPE's
    α = 1 (a capacitor, α ∈ (0, 1]), an HN's β = 1; as "element: where" ("Wo1: tau -> inf").
    There the smaller model is a point on the edge of the larger one's space, and each such limit
    makes the reference distribution of F a mixture (`chi_bar_squared_p_value`). A limit that
    takes more than one parameter away (a Cole–Cole at τ → 0, a resistor: α is then not
    identified) is not counted: no mixture of this kind holds there."""
    out = []
    for small, large, limit in embedding(simple, complex_, registry) or ():
        if limit is None:
            continue
        spec, simpler = registry[large.symbol], registry[small.symbol]
        match = _LIMIT_RE.match(limit.where)
        if match is None or len(spec.parameters) - len(simpler.parameters) != 1:
            continue
        name, value = match.group(1), math.inf if match.group(2) == "inf" else float(match.group(2))
        parameter = next((p for p in spec.parameters if (p.suffix or spec.symbol.lower()) == name), None)
        if parameter is not None and value in (parameter.lower, parameter.upper):
            out.append(f"{large.name}: {limit.where}")
    return out + _removed_elements(simple, complex_, registry)


def _removed_elements(simple: Circuit, complex_: Circuit, registry: Registry) -> list[str]:
    """The elements of ``complex_`` that ``simple`` lacks and whose one parameter, with bounds
    (0, ∞), takes it away at a bound: a series element at Z → 0 (W1.sigma -> 0, R0 -> 0), a
    parallel branch at Z → ∞ (C1 -> 0, R1 -> inf), as "W1 removed: sigma -> 0". The smaller model
    is then the larger one on the edge of its space as much as at a CPE's α = 1: W1.sigma ≥ 0
    and the null σ = 0, so F's reference is the chi-bar-squared mixture too. Counted only where
    a sibling of the element (or a part of one) stays: a removed block such as R2 || C2 (R2 -> 0
    leaves C2 unidentified) takes more than one parameter away, and no mixture of this kind holds."""
    from ..circuits.tree import Element, Parallel

    pairs = embedding(simple, complex_, registry)
    if pairs is None:
        return []
    kept = {large.name for _, large, _ in pairs}
    out: list[str] = []

    def walk(node) -> None:
        if isinstance(node, Element):
            return
        for child in node.children:
            if isinstance(child, Element):
                spec = registry[child.symbol]
                others = [e.name for c in node.children if c is not child for e in c.elements()]
                if (child.name not in kept and len(spec.parameters) == 1 and any(n in kept for n in others)
                        and spec.parameters[0].lower == 0.0 and spec.parameters[0].upper == math.inf):
                    end = _vanishing_end(spec, opens=isinstance(node, Parallel))
                    if end is not None:
                        out.append(f"{child.name} removed: {spec.parameters[0].suffix or child.name} -> {end}")
            else:
                walk(child)

    walk(complex_)
    return out


def _vanishing_end(spec, opens: bool) -> str | None:
    """Which end of a one-parameter element's range removes it: "0" or "inf", where its impedance
    goes to 0 (in series) or to ∞ (``opens``: a parallel branch), at ω = 1 rad/s; None when
    neither end does so."""
    z = {end: abs(complex(spec.impedance(1.0, value))) for end, value in (("0", 1e-12), ("inf", 1e12))}
    small, large = min(z, key=z.get), max(z, key=z.get)
    if z[small] == z[large]:
        return None
    return large if opens else small


def unidentified_limits(simple: Circuit, complex_: Circuit, registry: Registry = DEFAULT_REGISTRY) -> list[str]:
    """The limits by which ``simple`` sits in ``complex_`` (`embedding`) that leave parameters of
    ``complex_`` not identified, the ones `boundary_limits` does not count: a removed block or
    element of several parameters, taken away by the first of its parameters (in the order
    written) whose bound does so, a series part at Z → 0 and a parallel branch at Z → ∞ ("R2 ||
    C2 removed: C2 is not identified when R2 -> 0"), and an element reduced by one of its limits
    to an element with two or more parameters fewer ("CC1 reduced to R1: CC1.alpha is not
    identified when CC1.tau -> 0"). Under ``simple`` such a parameter has no value, and neither F
    nor a chi-bar-squared mixture is the statistic's reference distribution (Davies 1977,
    Biometrika 64, 247; 1987, Biometrika 74, 33): the plain F-test's p is typically too small."""
    from ..circuits.tree import Element, Parallel

    pairs = embedding(simple, complex_, registry)
    if pairs is None:
        return []
    out = []
    for small, large, limit in pairs:
        spec = registry[large.symbol]
        free = [] if limit is None else _left_free(registry[small.symbol], spec, limit)
        if free:
            names, named = spec.parameter_names(large.name), _limit_parameter(spec, limit.where)
            where = limit.where if named is None else names[named] + limit.where[_LIMIT_RE.match(limit.where).end(1):]  # ("CC1.tau -> 0")
            out.append(f"{large.name} reduced to {small.name}: {_not_identified([names[k] for k in free])} when {where}")
    kept = {large.name for _, large, _ in pairs}

    def walk(node) -> None:
        for child in node.children:
            if not any(e.name in kept for e in child.elements()):
                way = _vanishing(child, isinstance(node, Parallel), registry)
                free = [] if way is None else [n for e in child.elements() for n in registry[e.symbol].parameter_names(e.name) if n not in way[1]]
                if free:
                    out.append(f"{child} removed: {_not_identified(free)} when {' and '.join(way[0])}")
            elif not isinstance(child, Element):
                walk(child)

    if not isinstance(complex_, Element):
        walk(complex_)
    return out


def _not_identified(names: Sequence[str]) -> str:
    return f"{' and '.join(names)} {'is' if len(names) == 1 else 'are'} not identified"


def _left_free(simpler, spec, limit) -> list[int]:
    """Positions of ``spec``'s parameters that its ``limit`` (to the element ``simpler``) leaves
    free: neither the parameter its ``where`` names nor one that ``simpler``'s parameters set
    (`ElementLimit.values` at the defaults, each doubled in turn: a CC at τ → 0 sets α = 1 for
    any R)."""
    given = tuple(float(p.default) for p in simpler.parameters)
    base = limit.values(given, 1.0, 1e3)
    moved = set()
    for i in range(len(given)):
        bumped = limit.values(tuple(2 * v if k == i else v for k, v in enumerate(given)), 1.0, 1e3)
        moved |= {j for j, (a, b) in enumerate(zip(base, bumped)) if float(a) != float(b)}
    return [j for j in range(len(spec.parameters)) if j not in moved and j != _limit_parameter(spec, limit.where)]


def _limit_parameter(spec, where: str) -> int | None:
    """The position of the parameter of ``spec`` that a limit's ``where`` names first ("tau -> 0":
    τ), or None."""
    match = _LIMIT_RE.match(where)
    return None if match is None else next((j for j, p in enumerate(spec.parameters) if (p.suffix or spec.symbol.lower()) == match.group(1)), None)


def _vanishing(node, opens: bool, registry: Registry) -> tuple[list[str], list[str]] | None:
    """How ``node`` is taken away at bounds of its parameters: shorted (Z → 0, in series) or,
    ``opens``, opened (Z → ∞, a parallel branch), as (the limits, "R2 -> 0", and the parameters
    they set); None when no bound does so. A series node opens, and a parallel one shorts, when
    one part does (the first that can); a series node shorts, and a parallel one opens, when
    every part does."""
    from ..circuits.tree import Element, Parallel

    if isinstance(node, Element):
        spec = registry[node.symbol]
        found = _vanishing_parameter(spec, opens)
        if found is None:
            return None
        name = spec.parameter_names(node.name)[found[0]]
        return [f"{name} -> {found[1]}"], [name]
    if isinstance(node, Parallel) == opens:
        parts = [_vanishing(c, opens, registry) for c in node.children]
        return None if None in parts else ([t for p in parts for t in p[0]], [n for p in parts for n in p[1]])
    return next((way for c in node.children if (way := _vanishing(c, opens, registry)) is not None), None)


VANISHED = 1e-6
"""An element is taken away by a parameter at a bound when that parameter, 1e12 times nearer the
bound than its default (the others at theirs), moves |Z| by this factor or more toward 0
(shorted) or ∞ (opened) at ω = 0.01, 1 and 100 rad/s."""


def _vanishing_parameter(spec, opens: bool) -> tuple[int, str] | None:
    """The first parameter of ``spec`` (its position, and "0" or "inf") whose bound 0 or ∞ shorts
    the element or, ``opens``, opens it (`VANISHED`); None when none does."""
    defaults = [float(p.default) for p in spec.parameters]
    omegas = (1e-2, 1.0, 1e2)

    def size(values) -> list[float]:
        return [abs(complex(spec.impedance(w, *values))) for w in omegas]

    base = size(defaults)
    for i, p in enumerate(spec.parameters):
        for end, factor, bound in (("0", 1e-12, p.lower), ("inf", 1e12, p.upper)):
            if bound != (0.0 if end == "0" else math.inf):
                continue
            z = size([v * factor if k == i else v for k, v in enumerate(defaults)])
            if all((b <= VANISHED * x) if opens else (x <= VANISHED * b) for x, b in zip(z, base)):
                return i, end
    return None


def chi_bar_squared_p_value(f_value: float, df1: int, df2: int, n_boundary: int = 0) -> float:
    """The p-value of F (``df1``, ``df2``) when ``n_boundary`` of the df1 constraints put the
    smaller model on the boundary of the larger one's space (`boundary_limits`). The statistic
    T = df1·F is then a chi-bar-squared mixture (Self & Liang 1987, J. Am. Stat. Assoc. 82, 605;
    Stram & Lee 1994, Biometrics 50, 1171): P(T ≥ t) = Σ_j C(q, j) 2⁻ᑫ P(d_j·F_{d_j, df2} ≥ t), d_j = df1 − q + j, a term
    with d_j = 0 (the point mass at T = 0) adding nothing; for one boundary constraint and
    df1 = 1, half the F-test's p. The weights C(q, j) 2⁻ᑫ take the boundary parameters'
    estimates as uncorrelated. ``n_boundary`` 0: the F-test's own p, F.sf(F, df1, df2), by
    `scipy.special.fdtrc` (what scipy.stats.f.sf computes, F < 0 taken as 0; scipy.special
    imports in a fifth of the time scipy.stats takes, ~1 s of every compare process)."""
    from scipy.special import fdtrc

    q = min(int(n_boundary), int(df1))
    t = float(f_value) * df1
    if q and t <= 0:  # (no fall in χ²: the point mass at T = 0 counts, P(T ≥ 0) = 1)
        return 1.0
    total = 0.0
    for j in range(q + 1):
        d = df1 - q + j
        if d > 0:
            total += math.comb(q, j) / 2**q * float(fdtrc(d, df2, max(t / d, 0.0)))
    return total


def _mixture_note(limits: Sequence[str], simple_label: str, complex_label: str) -> str:
    """The note of a valid F-test whose smaller model sits on the boundary of the larger one's space."""
    mixture = "the 50:50 chi-bar-squared mixture (Self & Liang 1987)" if len(limits) == 1 else "the chi-bar-squared mixture (Self & Liang 1987)"
    return f"{simple_label} is {complex_label} at the edge of its parameter space ({'; '.join(limits)}): p is from {mixture}, not the plain F distribution"


def _unidentified_note(limits: Sequence[str], simple_label: str, complex_label: str, *, mixture: bool) -> str:
    """The note of a valid F-test whose smaller model is the larger one only at a limit that
    leaves a parameter not identified (`unidentified_limits`)."""
    reference = "the chi-bar-squared mixture" if mixture else "the plain F distribution"
    return (f"{simple_label} is {complex_label} only where a parameter is not identified ({'; '.join(limits)}): {reference} is not p's reference distribution there "
            "(Davies 1977, 1987), and p is typically too small; weigh the two by AIC too")


def boundary_parameters(simple: FitResult, complex_: FitResult) -> list[str]:
    """The free parameters of ``complex_`` at a bound (`FitResult.at_bound`: CPE2.alpha at 1,
    L0 at 0) that ``simple`` does not hold at that bound under the same name. The smaller model
    is the larger one with such a parameter on the edge of its space, where neither F nor the
    likelihood ratio follows its distribution (Self & Liang 1987: the LRT of one parameter on
    its bound is a 50:50 mixture of χ²₀ and χ²₁), so the F-test is not made. Compared by name,
    not by the parameter's role: an extra element named as one of the smaller model's is counted
    too (an invalid test said so is the safe side)."""
    return [n for n in complex_.at_bound if n not in simple.at_bound]


def _boundary_note(simple: FitResult, complex_: FitResult, simple_label: str, complex_label: str, names: Sequence[str]) -> dict:
    """``reason`` and ``note`` of an F-test not made because ``names`` of the larger model sit at
    a bound (`boundary_parameters`): "reduces_to_simple" when its χ² is no lower than the smaller
    model's by more than the solver's tolerance (`NESTED_WORSE_REL`) or than the fall the bound
    rule takes for no fall (`BOUND_CHI2_FRACTION` of the reduced χ²: L0 within two standard
    errors of 0 on a SYNTHETIC arc lowered χ² by 0.006 of it): the extra element does nothing;
    else "at_bound"."""
    where = ", ".join(_value_at_bound(complex_, n) for n in names)
    at = "is at its bound" if len(names) == 1 else "are at their bounds"
    why = "an F-test with a parameter on its bound does not follow the F distribution (Self & Liang 1987)"
    if simple.chi2 - complex_.chi2 <= max(NESTED_WORSE_REL * simple.chi2, BOUND_CHI2_FRACTION * complex_.chi2_red):
        return {"reason": "reduces_to_simple",
                "note": f"{complex_label} reduces to {simple_label}: {where} {at} and its χ² is no lower, so the extra element does nothing; {why}"}
    return {"reason": "at_bound", "note": f"{where} {at} in {complex_label}: {why}; compare the two by AIC"}


def _value_at_bound(fit: FitResult, name: str) -> str:
    """A parameter of ``fit`` at its bound as a boundary note names it: "R1 → ∞" at an infinite
    upper bound (not the float the solver stopped at, "R1 = 2.11e+167"); "R0 = 0" where the
    fit's own note puts it on its bound 0 (`value_shown_at_bound`; REAL exampleDataGamry.DTA,
    not "R0 = 1.27e-05 is at its bound" beside "R0 is at its lower bound 0");
    else its value with its unit as the fit's notes write it ("R0 = 87.4 µΩ", `format_quantity`;
    a bare "8.74e-05" before)."""
    value = fit.values[name]
    if value > AT_INFINITY:
        return f"{name} → ∞"
    shown = value_shown_at_bound(name, value, getattr(fit, "warnings", ()))
    if shown in ("0", "∞"):
        return f"{name} = {shown}"
    circuit = getattr(fit, "circuit", None)
    unit = circuit.parameter_specs(fit.registry)[name].unit if circuit is not None else ""
    return f"{name} = {format_quantity(value, unit)}"


AT_INFINITY = 1e30
"""A parameter at a bound whose value exceeds this sits at its infinite upper bound (a resistor
run open, fitted in log space to 1e+167 on a REAL file): the notes write it as → ∞."""


SIGNIFICANTLY_BETTER_P = 0.01
"""A model fits the data significantly better than one nested in it when their F-test's p is
below this: the nested one's misfit is its own, and `_model_not_data` says so in place of its
note that the data limit the fit (a SYNTHETIC R0 + R1 ∥ CPE1 spectrum, α = 0.97 with 1 % noise,
fitted with R0 + R1 ∥ C1 at 2.85× the KK misfit gave p = 1e-39)."""
CLEARLY_LOWER_RMS = 1.5
"""Without a valid F-test (models not nested, or the larger one short of its optimum) another
model fits clearly better when its rms_rel is at most 1/this of the fit's and its AIC is lower:
χ² 2.25× lower, which k extra parameters on n real values give the noise alone only with
k > 0.56 n (χ² shrinks as (n − k)/n), and a likelihood ratio n ln 2.25 ≥ 16 from 10 points on."""
DECISIVE_DELTA_AIC = 10.0
"""Without a valid F-test another model also fits clearly better when its AIC is lower by at
least this: Burnham & Anderson (2002, Model Selection and Multimodel Inference, §2.6) give a model
ΔAIC > 10 behind the best essentially no support, the standard evidence between non-nested models
(R_EP ∥ C_gap against CPE_EP ∥ C_gap: rms_rel only 1.29× apart, ΔAIC 61)."""


def labelled_warnings(models) -> list[str]:
    """The top-level ``warnings`` of a comparison's JSON: each model's warnings, in the order of
    ``models`` (pairs of a label and its warnings), as "LABEL: warning"; [] when no model has any,
    so that a program's ``warnings == []`` check means what it means in every command."""
    return [f"{label}: {w}" for label, warnings in models for w in warnings]


def _warning_texts(fit) -> list[str]:
    """A fit's warnings as one list (a batch's flattened over its spectra)."""
    return [w for ws in fit.warnings.values() for w in ws] if isinstance(fit.warnings, Mapping) else list(fit.warnings)


def _model_not_data(fit: FitResult, i: int, results: Sequence[FitResult], labels: Sequence[str], tests: Sequence[dict], aics: Sequence[float]) -> FitResult:
    """``fit`` (``results[i]``) with its note that the data limit the fit (`misfit_notes`,
    `DATA_LIMIT_NOTE`) replaced by one naming the model of the comparison that fits the same
    data significantly better (a valid F-test with p below `SIGNIFICANTLY_BETTER_P`, else an
    rms_rel `CLEARLY_LOWER_RMS` × lower with a lower AIC, or an AIC lower by `DECISIVE_DELTA_AIC`):
    the comparison's own numbers then
    say the misfit is this model's, and the note sent the user to the data (its sign hint, if
    any, is kept). The note and its hint are found by the tags the fit carries
    (`FitResult.warning_tags`: `notes.DATA_LIMIT`, `notes.SIGN_HINT`), not by their words; a fit
    without them (a file written without them) is read by the words (`result.fit_data_limit`).
    The new note is tagged `notes.MISFIT` and `notes.MODEL_MISFIT`. Unchanged otherwise,
    and for fits whose warnings are per spectrum (a mapping)."""
    warnings = fit.warnings
    if isinstance(warnings, Mapping):
        return fit
    limit, hint = fit_data_limit(fit)  # (a value set where the note is made; its words only for a fit without it)
    if not limit:
        return fit
    better = []  # (strength, j, evidence): the lowest p, else the largest rms_rel factor
    for j, other in enumerate(results):
        if j == i or not other.converged:
            continue
        test = next((t for t in tests if t["simple_label"] == labels[i] and t["complex_label"] == labels[j] and t["valid"]), None)
        if test is not None:
            if test["p_value"] < SIGNIFICANTLY_BETTER_P:
                better.append((0, test["p_value"], j, f"F-test p = {test['p_value']:.2g}"))
        elif aics[j] < aics[i] and (fit.rms_rel >= CLEARLY_LOWER_RMS * other.rms_rel or aics[i] - aics[j] >= DECISIVE_DELTA_AIC):
            better.append((1, other.rms_rel / fit.rms_rel, j, f"ΔAIC {aics[j] - aics[i]:.1f}"))
    if not better:
        return fit
    _, _, j, evidence = min(better)
    note = (
        f"{labels[j]} fits these data significantly better (rms_rel {results[j].rms_rel * 100:.3g} % against {fit.rms_rel * 100:.3g} %, {evidence}): "
        "the misfit is this model's, not the data's noise; a diagnosis (impedax diagnose) shows where it fails and which effect is missing"
    )
    blaming = Note(note + hint, (MISFIT, MODEL_MISFIT, *([sign_hint_tag(hint)] if hint else [])))  # (the misfit note, which blames the model: `FitResult.misses_structure`)
    return with_warnings(fit, tuple(blaming if w == limit else w for w in fit.tagged_warnings))


def _sign_hint_of(note: str) -> str:
    """The end of a note that the data limit the fit that holds the KK test's sign hint
    (`misfit_notes`, `SIGN_HINT_LEAD`), or "", by its words: it stays true when another model
    fits better (`FitResult.data_limit_hint` holds it as a value, `result.fit_data_limit`)."""
    at = note.find(f"; {SIGN_HINT_LEAD}")
    return note[at:] if at >= 0 else ""


def _same_fit(a: FitResult, b: FitResult) -> bool:
    if a.n_params != b.n_params or not abs(a.chi2 - b.chi2) <= 1e-6 * max(a.chi2, b.chi2, 1e-300):
        return False
    with np.errstate(all="ignore"):
        rms = float(np.sqrt(np.mean(np.abs((a.z_model - b.z_model) / np.abs(a.z_data)) ** 2)))
    return rms < max(SAME_FIT_RMS * max(a.rms_rel, b.rms_rel), 1e-9)
