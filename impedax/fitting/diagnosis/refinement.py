"""The refinement loop: diagnose → add the best significant effect → refit, until the model is
adequate (docs/diagnosis.md, section 6). The final model is refitted from scratch with `fit`,
so the result reproduces with ``impedax fit`` of the final model string."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, replace
from typing import Callable, Mapping

import numpy as np
import xarray as xr

from ...progress import reports_progress
from ...arguments import MAX_SOLVER_STEPS, MAX_STARTS, checked_arguments, choice, count, flag, frequency, instance_of, noise_fraction, parameter_bounds, parameter_values, seed as seed_rule
from ...circuits import Circuit, DEFAULT_REGISTRY, Element, Registry, parse
from ...data import concise_repr, counted, report_text, format_percent_column, format_quantity
from ...errors import CircuitError, ParameterError
from ...io.netcdf import result_dataset
from ..least_squares import FitResult, fit
from ..least_squares.candidates import fit_candidates
from ..least_squares.result import BOUND_CHI2_FRACTION, RESIDUAL_LONG_NAME, bounds_attr, embedded_fit, fit_from_embedded
from ..least_squares.starts import values_inside
from ..parameters import ParameterTable
from ..reductions import capacitor_name
from ..problem import WEIGHTINGS, check_argument_order, circuit_parameters, open_spectrum
from ..arcs import ArcBeyondBand, arcs_beyond_band
from ..frozen import FrozenResult, freeze_fields
from .bands import format_frequency
from .catalog import EffectCatalog
from .diagnosis import CANDIDATE_STEPS, DELTA_AIC_MIN, KEPT_PASSING_LEAD, KK_MASK_MAX_FRACTION, NOISE_FRACTION_MIN, Diagnosis, DRTMemo, Verdict, beyond_catalog_words, diagnose, left_out_options, left_out_words, noise_variance_explained, non_passive_points, ranked_size, require_points_for_diagnosis, undetermined_parameters, unidentified_note, verdict_scope_words
from .effects import DEFAULT_EFFECTS, added_resistors, placement
from .unsupported import unsupported_terms
from .vanishing import share_words, vanished_parameters, vanished_terms

__all__ = ["Refinement", "RefinementStep", "refine", "capacitor_name"]

# the note of a refinement that does not start again on the band the KK test passes (it would leave
# out more than `KK_MASK_MAX_FRACTION`); the report leaves it to the verdict when that says so
NOT_RESTARTED_WORDS = "refine does not start again there"


@dataclass(frozen=True, eq=False)
class RefinementStep(FrozenResult):
    """One model of the loop: its fit, what was added to get it, its diagnosis, and the
    elements the step left out (`Suggestion.removed`); a step of `_simplified` or `_pruned`
    adds nothing (``added`` and ``effect`` None) and lists the element(s) it took out, and a
    step of `_pruned` that put a simpler element in place of one (a CPE at α = 1 → a C) has
    ``added`` that element, ``effect`` None and ``removed`` the one it replaced. ``same_fit``:
    the models of the other suggestions of the previous step's diagnosis that fit the data as
    well within the noise (`Diagnosis.same_fits`): equally valid alternatives to this step.
    ``vanished``: those of ``removed`` that fell to zero where the suggestion kept them
    (`Suggestion.vanished`), which the choice between paths counts as kept (`_path_size`)."""

    __repr__ = concise_repr  # (the generated one printed every array)

    fit: FitResult
    added: str | None
    effect: str | None
    diagnosis: Diagnosis | None
    removed: tuple[str, ...] = ()
    same_fit: tuple[str, ...] = ()
    where: str = ""  # the suggestion's placement in words (`Suggestion.where`), with why it left an element out
    vanished: tuple[str, ...] = ()

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def model(self) -> str:
        return self.fit.model

    @property
    def noise_ratio(self) -> float | None:
        """The residuals against the noise the step's verdict was judged on (`Diagnosis.noise_ratio`,
        √(mean |r|²/2σ²), docs/diagnosis.md section 2): ≈ 1 where they are noise, so the fall
        from one step to the next is the step's gain beyond the noise; None without a diagnosis."""
        return None if self.diagnosis is None else float(self.diagnosis.noise_ratio)

    @property
    def removal_reasons(self) -> dict[str, str]:
        """Why an effect step left each of its ``removed`` elements out (name → reason), read
        from its placement text, where `diagnosis._left_out` (and the stray capacitance's
        proposal) put it: "…, and R0 left out (it fell to 3.63 µΩ: the data do not reach a
        series-resistance plateau)". Empty for a step that adds nothing (`_simplified` and
        `_pruned` give their reasons as notes)."""
        reasons = {}
        for name in self.removed if self.added and self.effect else ():
            head = f"{name} left out ("
            at = self.where.find(head)
            if at < 0:
                continue
            start = at + len(head)
            depth = 1
            for end in range(start, len(self.where)):  # (to the matching parenthesis: a reason may hold its own)
                depth += {"(": 1, ")": -1}.get(self.where[end], 0)
                if depth == 0:
                    reasons[name] = self.where[start:end]
                    break
        return reasons

    @property
    def change(self) -> str:
        """What the step did, in words: ``+ R_s [series_resistance]`` (with ``, − R_relax3``
        when the effect replaced an element), ``− CPE_relax [simplified]`` (an element taken out
        again, `_simplified`, or a vanished term pruned, `_pruned`), ``CPE1 → C1 [simplified]``
        (`_pruned`) or ``(start)``."""
        if self.added and self.effect is None:  # a simpler element in place of one (`_pruned`)
            return f"{', '.join(self.removed)} → {self.added} [simplified]"
        if self.added:  # an effect may replace an element: the step takes that one out
            return f"+ {self.added} [{self.effect}]" + (f", − {', '.join(self.removed)}" if self.removed else "")
        return f"− {', '.join(self.removed)} [simplified]" if self.removed else "(start)"

    @property
    def band(self) -> tuple[float, float]:
        """The lowest and highest frequency [Hz] of the points the step's fit used (its
        diagnosis judged it on them): after a start again on the band the KK test passes
        (`_on_valid_band`) every step's, step 0's too, is that band, narrower than the data's."""
        f = self.fit.frequency
        return float(np.min(f)), float(np.max(f))

    def as_json(self) -> dict:
        return {"model": self.model, "rms_rel": self.fit.rms_rel, "aic": self.fit.aic, "added": self.added, "effect": self.effect, "bic": self.fit.bic, "chi2_red": self.fit.chi2_red, "verdict": self.diagnosis.verdict if self.diagnosis else None, "removed": list(self.removed), "same_fit": list(self.same_fit), "where": self.where or None, "removal_reasons": self.removal_reasons, "vanished": list(self.vanished),
                "noise_ratio": self.noise_ratio,  # (the table's ×noise column)
                # the points the step's fit used: their band [Hz] and number (a start again on the KK band narrows step 0's too)
                "band_hz": list(self.band), "n_points": int(self.fit.frequency.size)}


@dataclass(frozen=True, eq=False)
class Refinement(FrozenResult):
    """Outcome of `refine`: the steps (first: the user's model), the final model and verdict."""

    __repr__ = concise_repr  # (the generated one printed every array)
    __str__ = report_text  # (print(result): its report)

    steps: tuple[RefinementStep, ...]
    verdict: Verdict
    notes: tuple[str, ...] = ()
    masked_points: tuple[float, ...] = ()  # frequencies [Hz] left out of every fit (KK-flagged, or Re Z < 0)
    final_from_values: bool = False  # a fit of the final model from scratch ends at another optimum than the final fit (`_reproduced`): reproduce it from its values
    # the verdict of `diagnose` of the same data, model and options (refine's first diagnosis, on
    # every point of the band it was given), and the sentence that says why this verdict differs
    # from it (`_diagnose_verdict_words`), None when it does not or differs as refine's purpose
    diagnose_verdict: Verdict | None = None
    diagnose_note: str | None = None
    # refine started again on the band the KK test passes (`_on_valid_band`): that band [Hz], the
    # points in it and the points of the data left out, and why (its note, the first of ``notes``);
    # None when every step is on the data refine was given
    restart: Mapping | None = None

    def __post_init__(self):
        object.__setattr__(self, "verdict", Verdict(self.verdict))
        if self.diagnose_verdict is not None:
            object.__setattr__(self, "diagnose_verdict", Verdict(self.diagnose_verdict))
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def final(self) -> FitResult:
        return self.steps[-1].fit

    @property
    def source(self) -> str | None:
        """Where the data came from (the first step's `FitResult.source`): what `impedax.write_result` records."""
        return self.steps[0].fit.source if self.steps else None

    @property
    def final_model(self) -> str:
        return self.final.model

    @property
    def verdict_band(self) -> tuple[float, float]:
        """The lowest and highest frequency [Hz] of the points the verdict was judged on: the
        final fit's, without ``masked_points``."""
        f = self.final.frequency
        return float(np.min(f)), float(np.max(f))

    @property
    def beyond_band(self) -> tuple[ArcBeyondBand, ...]:
        """The arcs of the final fit outside the band it saw (`arcs.arcs_beyond_band`): the
        data see one flank of each, not the arc. Those a step added (``extra_relaxation``), and
        the start's too: from ``R0 + R1 || C1`` the REAL ZPlot file ends with
        R1 ∥ C1 at 2.24 MHz above its 3 kHz–300 kHz, R0 left out, which the report names.
        An arc with a parameter the data do not determine is left to that line of the report."""
        final = self.final
        loose = undetermined_parameters(final) | vanished_parameters(final)
        return tuple(a for a in arcs_beyond_band(final.circuit, final.values, final.registry, final.frequency)
                     if a.resistor not in loose and not any(n == a.capacitance or n.startswith(f"{a.capacitance}.") for n in loose))

    @property
    def verdict_scope(self) -> str:
        """The band and the number of points the verdict was judged on when points were left
        out (`diagnosis.verdict_scope_words`): `` on 2.53 kHz – 200 kHz (20 of 72 points; the
        other 52 left out as not Kramers–Kronig consistent)``; empty when none were."""
        start = self.steps[0].diagnosis
        return verdict_scope_words(self.final.frequency, self.masked_points, getattr(start, "not_passive_points", ()))

    @property
    def data_line(self) -> str:
        """The report's line on the data, apart from the verdict on the model: where the first
        diagnosis' KK test fails and whether those points were left out or kept in every fit
        (`Diagnosis.kk_flagged_kept`); empty when the test passed or did not run."""
        start = self.steps[0].diagnosis if self.steps else None
        kk = getattr(start, "kk", None)
        if kk is None or kk.valid or not getattr(kk, "conclusive", True):
            return ""
        flagged = int(np.sum(np.asarray(kk.flagged, bool)))
        bands = kk.measured_bands_text()
        kept = getattr(start, "kk_flagged_kept", None)
        if kept and getattr(self.steps[-1].diagnosis, "kk_valid_band", None) is not None:  # (the verdict names the band it passes, for the final model)
            kept = kept.partition(KEPT_PASSING_LEAD)[0]
        left = len(self.masked_points) - len(getattr(start, "not_passive_points", ()))
        how = f"; {kept}" if kept else f"; the KK test flags {flagged} of {kk.frequency.size} points" + (f", {counted(left, 'point')} left out of every fit (masked, below)" if left > 0 else "")
        at = "" if kept and f"({bands})" in kept else f" at {bands}"  # (the band once: the kept points' note names the same range)
        return f"data: NOT Kramers–Kronig consistent{at} (KK rms_rel {kk.rms_rel * 100:.3g} %){how}."

    def summary(self) -> dict:
        """The JSON of ``impedax refine --json``: the steps, the final model with its parameters
        (``final_params``, as ``impedax fit --json``'s ``params``) and what they do not determine,
        and of the last diagnosis ``beyond_catalog`` and ``noise_ratio`` (`Diagnosis`)."""
        final = self.final
        last = self.steps[-1].diagnosis
        return {
            "steps": [s.as_json() for s in self.steps], "final_model": self.final_model, "verdict": self.verdict,
            "weighting": final.weighting,  # (every step's rms_rel, AIC and chi2_red are of it)
            "final_rms_rel": final.rms_rel, "n_params": final.n_params, "final_params": final.summary()["params"], "final_at_bound": list(final.at_bound),
            "final_user_bounds": bounds_attr(final.bounds),  # (the bounds=, --bound, the final fit kept, as fit --json's user_bounds)
            "undetermined": sorted(undetermined_parameters(final) | vanished_parameters(final)),
            "masked_points": [float(f) for f in self.masked_points], "notes": list(self.notes),
            "beyond_catalog": last.beyond_catalog if last is not None else False, "noise_ratio": last.noise_ratio if last is not None else None,
            "nothing_missing": self.nothing_missing,  # (the report's "nothing is missing" / "nothing more is missing" line)
            "final_from_values": self.final_from_values,
            "final_converged": bool(final.converged),  # (the final fit's, as fit --json's converged)
            # what to heed before trusting the final model, the key fit, compare and
            # sample give (`warnings`)
            "warnings": self.warnings,
            # the last diagnosis' reason for the verdict (the report's verdict line), the data's sign hint
            # (`Diagnosis.sign_hint`: with it the verdict is data_invalid) and the catalog's effects effects= left out
            "reason": last.reason if last is not None else None, "sign_hint": self.sign_hint,
            # which AIC the reason's ΔAIC is, against the steps' "aic" (`verdict_aic_note`), or null
            "verdict_aic_note": self.verdict_aic_note,
            "effects_left_out": list(last.effects_left_out) if last is not None else [],
            # what the verdict was judged on: the band [Hz] of the final fit's points, their number and how many every fit left out
            "verdict_band_hz": list(self.verdict_band), "n_points_judged": int(final.frequency.size), "n_points_left_out": len(self.masked_points),
            # the data's problem, apart from the verdict on the model: the report's "data:" line, or null
            "data_problem": self.data_line or None,
            # the added arcs the final fit puts outside the band it saw
            "final_beyond_band": [a.as_json() for a in self.beyond_band],
            # what diagnose of the same data, model and options says (refine's first diagnosis on every point), and the
            # report's sentence on why "verdict" differs from it, or null (`_diagnose_verdict_words`)
            "diagnose_verdict": self.diagnose_verdict, "diagnose_verdict_note": self.diagnose_note,
            # refine started again on the band the KK test passes: {"band_hz", "n_points_kept", "n_points_left_out", "reason"},
            # the band every step (step 0 too) is on; null when the steps are on the data refine was given
            "restart": None if self.restart is None else dict(self.restart),
        }

    @property
    def sign_hint(self) -> str | None:
        """The first diagnosis' `Diagnosis.sign_hint`: Z'' (or Z) may be stored with the
        opposite sign; None when the values look right."""
        return next((s.diagnosis.sign_hint for s in self.steps if s.diagnosis is not None and s.diagnosis.sign_hint), None)

    @property
    def warnings(self) -> list[str]:
        """What to heed before trusting the final model (JSON ``warnings``): the sign hint, the
        notes but those saying a further path changed nothing (information, not a warning), and
        the last diagnosis' warning of an adequate verdict beyond the catalog
        (`diagnosis.beyond_catalog_words`: a refine --effects ending at 12 % has it)."""
        last = self.steps[-1].diagnosis if self.steps else None
        beyond = [beyond_catalog_words(last.noise_ratio, last.effects_left_out)] if last is not None and last.beyond_catalog and self.verdict == last.verdict else []
        return ([self.sign_hint] if self.sign_hint else []) + [n for n in self.notes if UNCHANGED_WORDS not in n] + beyond

    def to_table(self) -> list[dict[str, object]]:
        """The tidy table of the final model's parameters (`FitResult.to_table`), then on every
        row ``final_model`` and ``verdict``, the JSON's (``refine --out
        FILE.csv`` names the final model beside its parameters, not only the starting one,
        ``setting_model``)."""
        return [{**row, "final_model": self.final_model, "verdict": str(self.verdict)} for row in self.final.to_table()]

    def _repr_html_(self) -> str:
        from ...plotting.html import result_html

        rows = [{"step": i, "change": s.change, "model": s.model, "rms_rel [%]": f"{s.fit.rms_rel * 100:.3g}", "AIC": s.fit.aic, "×noise": "–" if s.noise_ratio is None else f"{s.noise_ratio:.3g}"} for i, s in enumerate(self.steps)]
        return result_html(f"refinement: {self.final_model}", rows, lines=[f"verdict: {self.verdict}{self.verdict_scope}"])

    @property
    def verdict_aic_note(self) -> str | None:
        """Which AIC the verdict's "lowers AIC by …" is, beside the table's: the ranking's ΔAIC
        over the residuals divided by the noise model's σ_k (docs/diagnosis.md, section 5), on which
        every step is decided, and the same candidate's ΔAIC between the fits' own AICs under the
        run's weighting, the table's (AIC = n ln(χ²/n) + 2k); None unless the last diagnosis
        names an effect. Under proportional weighting on REAL Autolab the verdict said 36.6 where
        the table's AICs of the same step differ by about 10, read as a contradiction."""
        last = self.steps[-1].diagnosis
        if last is None or self.verdict != last.verdict or last.verdict != Verdict.MISSING_EFFECT or last.best is None:
            return None
        best, base = last.best, last.baseline
        own = best.fit.aic - base.aic
        return (f"(that ΔAIC, {best.delta_aic:.1f}, is the ranking's, over the residuals divided by the noise, on which refine decides every step; "
                f"between the fits' own AICs under {base.weighting} weighting, as in the table, adding {best.effect} is ΔAIC {own:.1f}: {base.aic:.1f} → {best.fit.aic:.1f})")

    @property
    def nothing_missing(self) -> bool:
        """The last diagnosis says nothing is missing (`Diagnosis.nothing_missing`) and the
        verdict is its: the final model follows the data to their noise."""
        last = self.steps[-1].diagnosis if self.steps else None
        return bool(last is not None and last.verdict == self.verdict and last.nothing_missing)

    @property
    def restart_line(self) -> str:
        """The report's line, under the table, that every step (step 0 too) is on the band refine
        started again on (`restart`), not on all the points `diagnose` judges; empty when it did not."""
        if self.restart is None:
            return ""
        lo, hi = self.restart["band_hz"]
        kept, left = self.restart["n_points_kept"], self.restart["n_points_left_out"]
        return (f"every step, step 0 too, is on {format_frequency(lo)} – {format_frequency(hi)} ({kept} of {kept + left} points): "
                "refine started again where the KK test passes (the first note says why)")

    def table(self) -> str:
        """One row per step: rms_rel, AIC, the residuals against the noise its verdict was judged
        on (``×noise``, `RefinementStep.noise_ratio`: whether a step's gain is beyond the noise)
        and what it changed, with the model under it."""
        lines = [f"{'step':>4}  {'rms_rel':>10}  {'AIC':>9}  {'×noise':>7}  change / model"]
        rms = format_percent_column([s.fit.rms_rel for s in self.steps])  # (3 significant digits, the decimal points lined up)
        for i, (s, percent) in enumerate(zip(self.steps, rms)):
            ratio = f"{s.noise_ratio:.3g}×" if s.noise_ratio is not None else "–"
            lines.append(f"{i:>4}  {percent:>8} %  {s.fit.aic:>9.1f}  {ratio:>7}  {s.change}")
            lines.append(f"{'':>4}  {'':>10}  {'':>9}  {'':>7}  {s.model}")
        return "\n".join(lines)

    def report(self) -> str:
        first, last = self.steps[0].fit, self.final
        # (the weighting named, as fit, diagnose and compare name it)
        lines = [f"refinement of {first.model} under {first.weighting} weighting (rms_rel and AIC of each step's fit)", self.table()]
        if self.restart is not None:
            lines.append(self.restart_line)
        lines.append("")
        if len(self.steps) > 1:
            before, after = f"{first.rms_rel * 100:.3g}", f"{last.rms_rel * 100:.3g}"
            # (a step that only simplified leaves rms_rel as it was: "fell from 1.4 % to 1.4 %" would read oddly)
            moved = (f"fell from {before} % to {after} %" if last.rms_rel < first.rms_rel else f"rose from {before} % to {after} %") if before != after else f"stayed at {after} %"
            n_steps = len(self.steps) - 1
            # (a step of a pair adds two effects, which max_effects counts: "in 3 steps" beside "its limit of
            # 4 added effects" read as a contradiction on REAL VersaStudio)
            n_added = sum(effect_count(s.effect) for s in self.steps)
            added = f" ({n_added} effect{'' if n_added == 1 else 's'} added)" if n_added > n_steps else ""
            lines.append(f"rms_rel {moved} in {n_steps} step{'' if n_steps == 1 else 's'}{added}; AIC {first.aic:.1f} → {last.aic:.1f}.")
        last_d = self.steps[-1].diagnosis
        data_line = self.data_line
        if data_line:
            lines.append(data_line)
        heading = last_d.verdict_heading if last_d is not None and last_d.verdict == self.verdict else self.verdict.upper()
        lines.append(f"verdict: {heading}{self.verdict_scope}" + (f" — {last_d.reason}" if last_d is not None else ""))
        aic_line = self.verdict_aic_note
        if aic_line:
            lines.append(aic_line)
        if self.diagnose_note:
            lines.append(self.diagnose_note)
        if self.nothing_missing:
            ratio = f"the residuals are {last_d.noise_ratio:.3g}× the noise"
            kept = f" on the {last.frequency.size} points kept" if self.masked_points else ""  # (the verdict line names them)
            lines.append(f"nothing is missing: {first.model} follows the data to their noise{kept} as given ({ratio}); refine added no effect." if len(self.steps) == 1 else
                         f"nothing more is missing: the final model follows the data to their noise{kept} ({ratio}).")  # (named on the next line)
        lines += self._final_lines()
        # (the verdict's "(refine does not: the trim leaves out 72 % …)" says what the note on not
        # starting again says: on REAL Gamry and CH Instruments the note came again under it; the JSON keeps it)
        said = last_d is not None and last_d.verdict == self.verdict and "(refine does not: " in last_d.reason
        lines += [f"note: {n}" for n in self.notes if not (said and NOT_RESTARTED_WORDS in n)]
        return "\n".join(lines)

    def _final_lines(self) -> list[str]:
        """The report's account of the final fit: its parameters (value, relative standard
        error or why there is none), the parameters the data do not determine, and the points
        every fit left out, by which ``impedax fit`` of the file differs."""
        final = self.final
        specs = final.circuit.parameter_specs(final.registry)
        loose = undetermined_parameters(final) | vanished_parameters(final)
        shown = []
        for n, v in final.values.items():
            e = final.stderr.get(n, math.nan)
            how = "fixed" if final.fixed[n] else "at its bound" if n in final.at_bound else f"± {e / abs(v) * 100:.2g} %" if math.isfinite(e) and v else "no error"
            shown.append(f"{n} = {format_quantity(v, specs[n].unit)} ({how})")
        lines = [f"final fit {final.model}: " + ", ".join(shown)]
        for arc in self.beyond_band:  # (an added arc the data see one flank of: not offered as a relaxation they resolve)
            step = next((i for i, s in enumerate(self.steps) if s.added and s.effect and arc.resistor in added_resistors(s.effect, s.added, self.final.circuit, self.final.registry)), None)
            lines.append(f"{f'step {step} adds' if step is not None else 'the final model has'} {arc.elements}, outside the band: {arc.sentence()}; {arc.remedy()}")
        for i, step in enumerate(self.steps):
            reasons = step.removal_reasons
            if step.removed and step.added and step.effect:  # (an effect step that took an element out says why, as every simplification's note does)
                lines.append(f"step {i} leaves out " + "; ".join(f"{n} ({reasons[n]})" if n in reasons else f"{n} ({step.where})" for n in step.removed))
            if step.same_fit:
                lines.append(f"step {i} has an alternative, the same fit within the noise (the data cannot tell them apart): {'; '.join(step.same_fit)}")
        if loose:
            lines.append(f"undetermined in the final fit: {', '.join(sorted(loose))} (the data do not fix {'it' if len(loose) == 1 else 'them'}; see impedax fit of the final model)")
        if self.masked_points:
            listed = ", ".join(format_frequency(f) for f in self.masked_points[:6]) + (", …" if len(self.masked_points) > 6 else "")
            lines.append(
                f"masked: {counted(len(self.masked_points), 'point')} left out of every fit as the data's own problem ({listed}); impedax fit of the file keeps them, "
                f"so its values and rms_rel differ, unless told: {left_out_words(left_out_options(final.frequency, self.masked_points))}"
            )
        return lines

    def plot(self, *, title: str | None = None):
        """The data with the first and the last step's model (Nyquist), the error per step
        (rms_rel, log scale) and the relative residuals of the last five steps vs frequency, with
        the failing bands shaded (matplotlib Figure; `impedax.plotting.diagnosis`)."""
        from ...plotting.diagnosis import plot_refinement

        return plot_refinement(self, title=title)

    def to_xarray(self) -> xr.Dataset:
        """Per-step model, rms_rel, AIC, BIC, added element, and residuals over (step, frequency)
        (``residual_rel`` = (Z_model − Z)/|Z| of each step's fit, model minus data);
        the final fit in full (values, stderr, covariance, ...: `FitResult.to_xarray` with its
        names prefixed ``final_fit_``, read back by `Refinement.final_fit_of`); the points every
        fit left out in ``masked_points_hz`` (the data's own problem: ``Z`` holds only the
        kept ones); ``impedax_kind`` "refinement"; ``diagnose_verdict`` and
        ``diagnose_verdict_note`` as the JSON's ("" where null); ``restart_band_hz`` and
        ``restart_reason``, the JSON's ``restart`` band and reason ([] and "" where null)."""
        f = self.steps[0].fit.frequency
        z = self.steps[0].fit.z_data
        ds = xr.Dataset(
            {
                "model": ("step", [s.model for s in self.steps]),
                "added": ("step", [s.added or "" for s in self.steps]),
                "effect": ("step", [s.effect or "" for s in self.steps]),
                "rms_rel": ("step", [s.fit.rms_rel for s in self.steps]),
                "aic": ("step", [s.fit.aic for s in self.steps]),
                "bic": ("step", [s.fit.bic for s in self.steps]),
                "residual_rel": (("step", "frequency"), np.stack([s.fit.residuals for s in self.steps]), {"units": "1", "long_name": RESIDUAL_LONG_NAME}),
                "Z": ("frequency", self.steps[0].fit.z_data, {"units": "ohm"}),
            },
            coords={"step": np.arange(len(self.steps)), "frequency": ("frequency", f, {"units": "Hz"})},
            attrs={"final_model": self.final_model, "verdict": str(self.verdict),
                   "diagnose_verdict": "" if self.diagnose_verdict is None else str(self.diagnose_verdict), "diagnose_verdict_note": self.diagnose_note or "",
                   "restart_band_hz": [] if self.restart is None else list(self.restart["band_hz"]), "restart_reason": "" if self.restart is None else self.restart["reason"]},
        )
        ds = xr.merge([ds, embedded_fit(self.final, FINAL_FIT_PREFIX, f, z)], combine_attrs="no_conflicts")
        return result_dataset(ds.assign_attrs(impedax_kind="refinement", masked_points_hz=[float(x) for x in self.masked_points], notes=list(self.notes)).copy(deep=True))

    @staticmethod
    def final_fit_of(ds: xr.Dataset, *, registry: Registry | None = None) -> FitResult:
        """The final fit stored by `Refinement.to_xarray` (as returned or read back with
        `impedax.io.read_netcdf`), as a `FitResult`."""
        return fit_from_embedded(ds, FINAL_FIT_PREFIX, registry=registry)


UNCHANGED_WORDS = " changes nothing: "
"""What the note of a further path that changed nothing says (`_second_path`): information,
not one of `Refinement.warnings`."""

MAIN_PATH = "the refinement"
"""How `_reproduced`'s note names the path it refits: the refinement's own (greedy) path."""
SIDE_PATH = "this path"
"""... or a further path of `_second_path` (its note is prefixed "second path: " and so on)."""


def _reproduced(ds: xr.Dataset, last: FitResult, *, n_starts: int, seed: int, say=lambda text: None, whose: str = MAIN_PATH) -> tuple[FitResult, str | None]:
    """The final model fitted from scratch with `fit` (what ``impedax fit`` of its model string
    does on the same points); when the loop's warm fit is better, or as good (χ² within 1e-6)
    with fewer undetermined parameters, `fit` started from it.

    When the two optima are within `DELTA_AIC_MIN` of each other (a 13-parameter battery model
    reached two at ΔAIC 0.15) the note says the data do not tell them apart, not that the fit
    from scratch stops short.

    A parameter running to a natural bound (a resistor running open) can stop short of it from
    scratch: on CHInstruments' spectrum R1 stopped at 1e14 Ω, leaving R1, C1 and R_relax2
    undetermined, where the loop's fit reached 5e259 Ω (at the bound, by which
    `undetermined_parameters` holds it) at the same χ² to 1e-9. Its term has then vanished:
    `_pruned` takes it out of the final model. ``say``: told before the fit from the loop's
    values (the two fits of a 12-parameter model took 10 s on a loaded machine: not silently).

    ``whose``: the path ``last`` ends, as the note names it (`MAIN_PATH`, or `SIDE_PATH` for a
    path `_second_path` compares with the kept one: its values are not the refinement's, and
    whether they are reported is that comparison's to say).

    Both fits keep ``last``'s fixed values and the user's bounds (`FitResult.bounds`); the
    start from its values is moved strictly inside those bounds (`starts.values_inside`: an
    optimum pressed against a bound sits on it, where `fit` takes no start)."""
    fixed = {k: v for k, v in last.values.items() if last.fixed[k]} or None
    bounds = dict(last.bounds) or None
    scratch = fit(last.circuit, ds, fixed=fixed, bounds=bounds, weighting=last.weighting, registry=last.registry, seed=seed)
    loose = undetermined_parameters(scratch) - undetermined_parameters(last)
    if scratch.chi2 <= last.chi2 * (1 + 1e-6) and not loose:
        return scratch, None
    say(f"  refitting {last.model} from {whose}'s values (from scratch: rms_rel {scratch.rms_rel * 100:.3g} %)")
    start = last
    if bounds:
        table = ParameterTable.build(last.circuit, registry=last.registry, fixed=fixed, bounds=bounds)
        start = values_inside({k: v for k, v in last.values.items() if not last.fixed[k]}, table)
    warm = fit(last.circuit, ds, init=start, fixed=fixed, bounds=bounds, weighting=last.weighting, registry=last.registry, seed=seed)
    if loose and warm.chi2 <= scratch.chi2 * (1 + 1e-6) and len(undetermined_parameters(warm)) < len(undetermined_parameters(scratch)):
        return warm, f"fit of {last.model} from scratch reaches rms_rel {scratch.rms_rel * 100:.3g} % with {', '.join(sorted(loose))} undetermined; started from {whose}'s values it reaches {warm.rms_rel * 100:.3g} % with every parameter it had determined (pass init=)"
    if warm.chi2 <= scratch.chi2:
        gap = scratch.aic - warm.aic
        if gap <= DELTA_AIC_MIN:  # (two optima the data do not tell apart: the scratch fit does not stop short)
            return warm, (
                f"fit of {last.model} from scratch reaches rms_rel {scratch.rms_rel * 100:.3g} %, which the data do not tell apart from "
                f"{whose}'s {warm.rms_rel * 100:.3g} % (ΔAIC {gap:.2g}); "
                + ("the refinement's values are reported" if whose == MAIN_PATH else f"{whose} ends at its own values")
                + " (pass init=)"
            )
        return warm, f"fit of {last.model} from scratch reaches rms_rel {scratch.rms_rel * 100:.3g} %; started from {whose}'s values it reaches {warm.rms_rel * 100:.3g} % (pass init=)"
    return scratch, None


FINAL_FIT_PREFIX = "final_fit_"
"""The names of the final fit's variables, dimensions and attributes in `Refinement.to_xarray`
(``final_fit_value``, ``final_fit_covariance``, ...): apart from the per-step ones."""

BRANCH_WINDOW = 40.0
"""`refine`'s second path starts from the first diagnosis' best suggestion at another placement
(or of another effect) when it is within this much AIC of the chosen one."""

SAME_OPTIMUM_AIC = 0.1
"""Two ends of one circuit (`_same_network`) whose AIC differs by at most this are one optimum
(the notes print AIC to 0.1): a further path ending there is kept only when it keeps elements of
the starting circuit the kept end left out (in the user's names: SYNTHETIC Meyer data, C_sc
kept as CPE_sc beside R_s, where the other path had R_relax ∥ CPE_relax for them), and is
otherwise left out of the report, whatever the paths count as kept on the way. On REAL Gamry
above 2.5 kHz the third path ends at the first path's circuit at AIC −448.7 too and would be kept
"at a better optimum", for the first path counting R0, which fell to zero on it, as kept."""

PATH_LABELS = ("second path", "third path", "fourth path", "fifth path", "sixth path", "seventh path")
"""The names of `_second_path`'s further paths, in the order the notes report them (the greedy
path is "the first path"): a path the report leaves out (the kept end's circuit under other
names) passes its name on to the next, so the notes never skip one."""

REUSE_CHI2_RTOL = 1e-6
"""A refine path that reaches a model another path diagnosed reuses that diagnosis when the
earlier fit's χ² is at most this much (relatively) above the path's own fit."""


def _first_step_text(s) -> str:
    """A path's first step in a note: the effect, what it adds and where (a pair of effects
    without its placement, which names each addition at length: the diagnosis shows it)."""
    return f"{s.effect} ({s.added})" if "+" in s.effect else f"{s.effect} ({s.added}, {s.where})"


def _addition_text(s) -> str:
    """What a path's first step adds and where, without the effect's name: ``R_relax ||
    CPE_relax nested in series with R1 (…)`` (a pair: what it adds only, `_first_step_text`)."""
    return s.added if "+" in s.effect else f"{s.added}, {s.where}"


def _removal_words(s) -> str:
    """What a start's ``where`` says after its placement of the elements it left out (``, and R0
    left out (it fell to …)``, `diagnosis`'s derived candidates), or ""."""
    cuts = [s.where.find(f", and {name} left out (") for name in getattr(s, "removed", ())]
    return s.where[min(c for c in cuts if c >= 0):] if any(c >= 0 for c in cuts) else ""


def _starts_compared(alt, kept, label: str = "second path", kept_label: str = "the first path") -> str:
    """How the further path ``label``'s start ``alt`` differs from ``kept``, the start of the path
    whose end it is compared with (``kept_label``: the first path, or a further path kept before
    it), each with the model it gives: two sentences. On the REAL VersaStudio file the third
    path's note, compared with the kept second path's end, tells how the second path started,
    not the first. Of one effect, the effect is named once and the two additions told
    apart, not "starting from extra_relaxation (…) instead of extra_relaxation (…)"
    (Gamry's real file), the same name twice for two placements. Where
    both added the same at the same place, the note says so, with no "but": on REAL Gamry from
    ``R0 + R1 || CPE1`` not "too, but added R_relax || CPE_relax, nested in series with R1
    …", then the same words for the first path, whose only difference was R0 left out."""
    holder = kept_label[:1].upper() + kept_label[1:]
    if alt.effect == DRT_EFFECT:
        return (f"The {label} started from the circuit the data's DRT reads (impedax drt), {alt.fit.model}, in place of the starting circuit."
                + (f" {holder} started from {_first_step_text(kept)}, giving {kept.fit.model}." if kept is not None else ""))
    if alt.effect != kept.effect:
        return (f"The {label} started from {_first_step_text(alt)}, giving {alt.fit.model}. "
                f"{holder} started from {_first_step_text(kept)}, giving {kept.fit.model}.")
    placed = [_addition_text(s).removesuffix(_removal_words(s)) for s in (alt, kept)]
    if alt.added == kept.added and placed[0] == placed[1]:
        return (f"The {label} started from {alt.effect} too and added {_addition_text(alt)}, giving {alt.fit.model}. "
                f"{holder} added the same{_removal_words(kept)}, giving {kept.fit.model}.")
    return (f"The {label} started from {alt.effect} too, but added {_addition_text(alt)}, giving {alt.fit.model}. "
            f"{holder} added {_addition_text(kept)}, giving {kept.fit.model}.")


DRT_EFFECT = "drt_circuit"
"""The ``effect`` of a refine step that puts the circuit the data's DRT reads in place of the
user's (`_DRTStart`)."""


def effect_count(effect: str | None) -> int:
    """How many effects a step adds: none for the start, two for a pair (its effect is "a+b"),
    none for the DRT's circuit (`_DRTStart`: a start read off the data, not an effect of the
    catalog; the path from it adds up to ``max_effects`` effects, as the first path does)."""
    return 0 if effect is None or effect == DRT_EFFECT else effect.count("+") + 1


@dataclass(frozen=True, eq=False)
class _DRTStart:
    """A further path's start at the circuit the data's DRT reads (`Diagnosis.drt_circuit` of the
    first diagnosis), shaped as a `Suggestion` for `_greedy`: ``fit`` its fit on the diagnosis'
    points, ``added`` its elements the user's circuit does not have, ``removed`` the user's
    elements it does not have."""

    __repr__ = concise_repr

    fit: FitResult
    added: str
    removed: tuple[str, ...]
    where: str
    effect: str = DRT_EFFECT
    vanished: tuple[str, ...] = ()


def _drt_start(first: Diagnosis, steps: list[RefinementStep], limit: int) -> _DRTStart | None:
    """The start of a path from the circuit the data's DRT reads, when the first diagnosis named
    one (`Diagnosis.drt_circuit`: better than its best suggestion, or as good with fewer
    parameters) and the greedy path ``steps`` still ends ``missing_effect`` (with effects allowed
    at all: ``limit`` ≥ 1); else None. A suggestion is one change to the user's circuit, and the
    greedy path can spend its effects standing in for what the DRT reads at once: on REAL
    exampleData.csv from R0 + R1 ∥ C1 the greedy path stops at its limit of 4 effects at 0.805 %
    (AIC −1342.5), still missing an effect, where the path from the DRT's R0 + L1 + R1 ∥ CPE1 + W1
    ends adequate at 0.608 % (AIC −1412.8)."""
    last = steps[-1].diagnosis
    if limit < 1 or last is None or last.verdict != Verdict.MISSING_EFFECT or first.drt_circuit is None:
        return None
    named = first.drt_circuit
    own, theirs = first.baseline.circuit.element_names, named.fit.circuit.element_names
    removed = tuple(n for n in own if n not in theirs)
    # (each element left out with its reason in the words `RefinementStep.removal_reasons` reads)
    where = f"the circuit the data's DRT reads (impedax drt) in place of {first.baseline.model}" + "".join(f", and {n} left out (not in the circuit the data's DRT reads)" for n in removed)
    return _DRTStart(named.fit, ", ".join(n for n in theirs if n not in own), removed, where)


def unfollowed_effect_note(steps: list[RefinementStep], best) -> str:
    """Why refine ends on a model whose own diagnosis names an effect ``best`` (its verdict) that
    refine did not add, below its limit: the step taken from it was dropped (`_finish`), after a
    simplifying step too (`_after_simplifying` goes on from one). REAL Autolab under proportional
    weighting ends "MISSING_EFFECT — adding extra_relaxation lowers AIC by 36.6", and this says
    why."""
    last = steps[-1]
    if len(steps) > 1 and last.effect is None:
        why = (f"refine simplified the model in its last step ({last.change.removesuffix(' [simplified]')}), went on from it, and the step it took "
               "was dropped (see the note on what the data do not determine)")
    else:
        why = "the step refine took from it was dropped (see the note on what the data do not determine)"
    return (
        f"the final model still misses {best.effect} ({best.added}) by its own diagnosis, which refine did not add: {why}; "
        f"a diagnosis of {last.model} shows it, and refine from that model tries it"
    )


def _after_simplifying(steps: list[RefinementStep], limit: int, diagnosed, say, notes: list[str], finished, simplify) -> list[RefinementStep]:
    """``steps`` continued greedily from a last step that simplified the model (`_simplified`,
    `_pruned`: it adds no effect) while that model's own diagnosis names a significant effect
    within ``limit``, as from any other step: the simpler model is the same fit with fewer
    parameters, and its candidates differ (an arc beside a C, where the CPE at α = 1 it
    replaced left the arc's parameters undetermined). The continued path is finished
    (``finished``: refitted from scratch, a last step dropped when that leaves parameters
    undetermined) and simplified again (``simplify``); each round adds an effect, so at most
    ``limit`` rounds. Else REAL Autolab under proportional weighting ends "MISSING_EFFECT — adding
    extra_relaxation (R_relax2 ∥ C_relax2) lowers AIC by 36.6" after CPE3 → C3 with 3 of its
    4 effects used."""
    for _ in range(limit):
        last = steps[-1]
        if len(steps) < 2 or last.effect is not None or last.diagnosis is None:
            break
        best = _best_within(last.diagnosis, limit - sum(effect_count(s.effect) for s in steps))
        if best is None:
            break
        went_on = finished(_greedy(steps, best, limit, diagnosed, say, "after simplifying, "), "")
        if len(went_on) <= len(steps):  # (every step it took was dropped: `_finish`'s note says why)
            break
        added = [s.added for s in went_on[len(steps):]]
        notes.append(
            f"refine went on after simplifying ({last.change.removesuffix(' [simplified]')}): the simpler model's own diagnosis still names "
            f"{best.effect} ({best.added}), which lowers AIC by {-best.delta_aic:.1f}, within the limit of {counted(limit, 'effect')}; it added {', '.join(added)}"
        )
        steps = simplify(went_on)
    return steps


def _best_within(diagnosis: Diagnosis, room: int):
    """The best significant suggestion of ``diagnosis`` adding at most ``room`` effects (a pair
    ranked first gives way to the best single effect when one effect is left), or None."""
    if diagnosis.verdict != Verdict.MISSING_EFFECT or diagnosis.best is None:
        return None
    if effect_count(diagnosis.best.effect) <= room:
        return diagnosis.best
    return next((s for s in diagnosis.suggestions if effect_count(s.effect) <= room), None)


def _with_alternatives(steps: list[RefinementStep]) -> list[RefinementStep]:
    """``steps`` with each effect step's ``same_fit``: the models of the suggestions of the step
    before's diagnosis that are the same fit within the noise as the one the step took
    (`Diagnosis.same_fits`), so that the report names what the data could not tell from it."""
    out = list(steps)
    for i in range(1, len(out)):
        step, before = out[i], out[i - 1].diagnosis
        if step.effect is None or before is None:
            continue
        taken = next((s for s in before.suggestions if s.added == step.added and s.effect == step.effect and s.fit.model == step.model), None)
        if taken is not None:
            out[i] = replace(step, same_fit=tuple(t.model for t in before.same_fits(taken)))
    return out


def _greedy(steps: list[RefinementStep], best, limit: int, diagnosed, say, label: str) -> list[RefinementStep]:
    """``steps`` continued greedily: add ``best`` (a `Suggestion` of the last step's diagnosis),
    diagnose the new model, add its best significant suggestion, ... until the verdict is not
    ``missing_effect`` or ``limit`` effects were added (a pair counts as two)."""
    steps = list(steps)
    added = sum(effect_count(s.effect) for s in steps)
    while best is not None and added + effect_count(best.effect) <= limit:
        say(f"{label}step {len(steps)}: diagnosing {best.fit.model}")
        d = diagnosed(best.fit, steps[-1].diagnosis.solver_shape)
        steps.append(RefinementStep(d.baseline, best.added, best.effect, d, tuple(best.removed), where=getattr(best, "where", "") or "", vanished=tuple(getattr(best, "vanished", ()))))
        added += effect_count(best.effect)
        best = _best_within(d, limit - added)
    return steps


def _second_path(steps: list[RefinementStep], picked, limit: int, diagnosed, say, notes: list[str], finished) -> list[RefinementStep]:
    """A second look at the first choice ``picked`` (the suggestion the greedy path started from)
    when the greedy path added two effects or more (a lead pair in one step counts as two): the
    first diagnosis' best significant suggestion at another placement or of another effect
    (within `BRANCH_WINDOW` of AIC; of a lead pair, from the effect under its L, which starts a
    path too: `_lead_base`) is continued greedily too, and the better final model is
    kept (lower AIC by more than `DELTA_AIC_MIN`, or as good with fewer parameters, or as good
    with as many while leaving out fewer elements: a subset of the other's). Parameters are
    counted as the ranking counts them (`_path_size`): a series resistance that fell to zero and
    was left out counts as kept. A first
    step that fits a large misfit in the wrong place (a Warburg at the end where it belongs
    behind the charge transfer) is otherwise compensated by later, wrong additions. The paths
    are compared as they end after ``finished`` (the final refit from scratch, which may drop
    a last step); returns the kept path, finished.

    A suggestion that leaves a baseline element out ranks after the significant ones that keep
    them (`diagnosis._rank`) even when it fits far better. When it lowers AIC by more than
    `DELTA_AIC_MIN` below the chosen one, a path starts from it too, however many steps the
    greedy path took, and is compared last, so that a path keeping the user's elements wins a
    tie (C_i + R_sc ∥ C_sc with a series resistance and a CPE missing: the paths that keep C_sc
    can stall at 16–17 % where leaving it out reaches the noise).

    With two effects missing, the right one alone may leave its own parameters undetermined
    (they make up for the other), so it is never a suggestion. When a candidate with only
    undetermined parameters against it fits better by more than `DELTA_AIC_MIN` than the chosen
    one and than every suggestion of its own effect, a path starts from the best such candidate
    as well; its end must have every parameter determined (`_finish` drops a last step that
    does not). On a SYNTHETIC finger with its series resistance and electrode polarization
    missing, R_EP ∥ CPE_EP ∥ C_gap alone reached 2.2 % with R_EP undetermined, a further arc
    2.5 %; the arc's path ended at 0.72 % with 10 parameters, the electrode polarization's at
    the generating circuit, 0.69 % with 8. Where R_EP ∥ C_gap (one parameter fewer, determined)
    was a suggestion, its path led elsewhere (an arc standing in for the CPE) and the full
    R_EP ∥ CPE_EP ∥ C_gap, 39 lower in AIC, had started none.

    When the first choice left a baseline element out, a path starts from the same candidate
    with that element kept (`_kept_in_place`). When the greedy path ends ``adequate``, paths
    start from cheaper effects too (`_cheaper_starts`): an element of three parameters can
    stand in for two of one each. When the greedy path ends ``missing_effect`` and the first
    diagnosis named the circuit the data's DRT reads, a path starts from that circuit too
    (`_drt_start`), compared last.

    An end with more parameters is kept only when it also explains a quarter of the noise
    variance more (`NOISE_FRACTION_MIN`), unless those parameters are elements of the starting
    circuit the path before left out: they go only when that costs at most `DELTA_AIC_MIN` of AIC
    (the rule of `_simplified`). On a SYNTHETIC coated metal a first step left R0 = 20 Ω out
    (undetermined beside an ideal C1); the path keeping it ended 24 lower in AIC and was dropped.

    A circuit and a renamed copy of it (`Circuit.structure_key`: the same elements connected
    alike, series and parallel parts in any order) are one model: a start that is the first
    choice's or an earlier start's circuit under other names starts no path, and a path that
    ends at the kept end's circuit is not compared with it (no note; the first-found names
    stay) unless the rules below keep it (a better fit, or a tie that keeps more of the user's
    elements). From C_gap on the SYNTHETIC Sirin remainder, the path of C_gap → CPE_gap reached
    R_EP ∥ C_EP ∥ CPE_gap, the kept R_EP ∥ CPE_EP ∥ C_gap, and was noted as a tie."""
    first = steps[0].diagnosis
    # a lead pair stands for the suggestion under its L (`_lead_base`): that suggestion starts a path
    # too, and the window is measured from it, as the lead's own gain tells no first effect from another
    # (a path whose one step took a lead pair has added two effects: it gets the second look too)
    base = _lead_base(first, picked)
    reference = picked if base is None else base
    second_look = len(steps) >= 3 or (base is not None and len(steps) >= 2)
    alternatives = [s for s in first.suggestions if s is not base and s is not picked and (placement(s.where) != placement(reference.where) or s.effect != reference.effect) and s.delta_aic <= reference.delta_aic + BRANCH_WINDOW][:1] if second_look else []
    alternatives = ([base] if base is not None and second_look else []) + alternatives
    leaving = [s for s in first.suggestions if s.removed and not picked.removed and s.delta_aic < reference.delta_aic - DELTA_AIC_MIN and all(s is not t for t in alternatives)] if len(steps) >= 2 else []
    hidden = [
        c for c in first.candidates
        if c.undetermined and c.fit.converged and c.delta_aic < reference.delta_aic - DELTA_AIC_MIN
        and all(c.delta_aic < s.delta_aic - DELTA_AIC_MIN for s in first.suggestions if s.effect == c.effect)
    ] if len(steps) >= 2 else []
    keeping = _kept_in_place(first, picked, alternatives + hidden + leaving) if len(steps) >= 2 else []
    cheaper = _cheaper_starts(steps, picked, alternatives + hidden + leaving + keeping)
    drt = _drt_start(first, steps, limit)
    steps = finished(steps, "")
    starts = [alt for alt in alternatives + sorted(hidden, key=lambda c: c.delta_aic)[:1] + leaving[:1] + keeping + cheaper if effect_count(alt.effect) <= limit]  # (a pair over the limit would start no path)
    starts += [drt] if drt is not None else []  # (compared last: a path keeping the user's elements wins a tie)
    # a start that is the first choice or an earlier start under other names would only repeat that path
    starts = _distinct_networks(starts, picked)
    if starts:  # (together they may take several times the first path: the progress says what follows, and why)
        say(f"the first path ends at {steps[-1].model}; {counted(len(starts), 'further path')} from other first steps {'follows' if len(starts) == 1 else 'follow'}, "
            "each refined as the first was and its end compared with the end kept")
    # the paths are numbered as the notes report them (a path not reported passes its number on),
    # and each note names the path whose end it is compared with: the one kept so far
    holder, holder_start, reported = "the first path", picked, 0
    for number, alt in enumerate(starts, 1):
        if reported >= len(PATH_LABELS):
            break
        label = PATH_LABELS[reported]
        # progress names the path by its place among the starts, never by a report label, which
        # it gets only once compared: a path left out passes its label on (Gamry, --fmin 2.3e3:
        # "third path" announced twice, "fourth path" that the report never named)
        trial = f"further path {number} of {len(starts)}"
        own_notes = len(notes)
        other = finished(_greedy(steps[:1], alt, limit, diagnosed, say, f"{trial}, "), f"{label}: ", f"{trial}: ")
        a, b = steps[-1].fit, other[-1].fit
        # sizes as the ranking counts them (`ranked_size`): a resistor that fell to zero and was left out counts as kept
        size_a, size_b = _path_size(steps), _path_size(other)
        tie = abs(b.aic - a.aic) <= DELTA_AIC_MIN and size_b == size_a
        restored = sorted(_elements_left_out(steps) - _elements_left_out(other))
        # an element the other path keeps only as a vanished term (R0 at 0) is not kept: the pruning
        # takes it out again (Gamry's file: a tie kept the second path for its R0 = 9e-40 Ω, which
        # the pruning then left out, back at the first path's end, the note saying the reverse)
        kept_more = _elements_left_out(other) < _elements_left_out(steps) and bool(set(restored) - _vanishing_elements(b))
        better = b.aic < a.aic - DELTA_AIC_MIN or (b.aic <= a.aic + DELTA_AIC_MIN and size_b < size_a) or (tie and kept_more)
        # one circuit at one optimum: kept only for keeping elements of the starting circuit the holder left out
        same_optimum = _same_network(a, b) and b.aic >= a.aic - SAME_OPTIMUM_AIC
        better = (tie and kept_more) if same_optimum else better
        if _same_network(a, b) and not better:  # one model, under the same or other names, and not to be kept: nothing to compare, the first-found stays
            del notes[own_notes:]  # (its refit's notes speak of a path the report does not name)
            say(f"{trial}: ends at {holder}'s end, {a.model}, as one circuit; left out of the report")
            continue
        reported += 1
        say(f"{trial}: the report's {label}")
        # more parameters are kept by the rules that add one: AIC and a quarter of the noise variance;
        # but parameters that are the user's own elements, which the path before left out, are kept by
        # the rule that takes an element out (`_simplified`): it goes only when that costs at most DELTA_AIC_MIN
        # (a restored resistor that fell to zero on the path before is in that path's size already)
        own = better and bool(restored) and 0 < size_b - size_a <= _parameter_count(b, set(restored) - set(_vanished_on(steps)))
        slight = better and size_b > size_a and not own and noise_variance_explained(a, b, first) < NOISE_FRACTION_MIN
        better = better and not slight
        # a path whose every step was dropped (`_finish`) ends where every path starts: the start, not a model of its own
        end = (f"It drops every step it took (its note above). It ends at the start, {other[-1].model} (AIC {b.aic:.1f}, {_size_words(other)})" if len(other) == 1
               else f"It ends at {other[-1].model} (AIC {b.aic:.1f}, {_size_words(other)})")
        # short sentences, the result first (not one sentence of ~90 words): what the path changed, the two ends, why, then where the two paths started
        sentences = [
            (f"the {label} ends at {holder}'s circuit at {'the same' if same_optimum else 'a better'} optimum, which is kept." if _same_network(a, b) else f"the {label} is kept in place of {holder}'s end.")
            if better else f"the {label}{UNCHANGED_WORDS}{holder}'s end is kept.",
            f"{end}, against {holder}'s end {steps[-1].model} (AIC {a.aic:.1f}, {_size_words(steps)}).",
        ]
        if better and b.aic > a.aic:  # (kept by parsimony: the note names the rule beside the higher AIC)
            sentences.append(f"Its AIC is {b.aic - a.aic:.1f} higher, within {DELTA_AIC_MIN:g}, where the data barely tell the two apart, "
                             f"and it has {counted(size_a - size_b, 'fewer parameter')}: the simpler is kept.")
        if slight:
            sentences.append(f"It fits better by AIC, but with {counted(size_b - size_a, 'more parameter')} it explains under {NOISE_FRACTION_MIN * 100:.0f} % of the noise variance more.")
        if tie:
            sentences.append(f"The data do not tell the two apart (AIC within {DELTA_AIC_MIN:g}, as many parameters)"
                             + (f"; it keeps {', '.join(restored)}, which {holder} left out." if better else "."))
        if own:
            sentences.append(f"It keeps {', '.join(restored)}, the starting circuit's, which {holder} left out: leaving {'them' if len(restored) > 1 else 'it'} out costs "
                             f"{a.aic - b.aic:.1f} of AIC, more than {DELTA_AIC_MIN:g}, the most refine lets an element go for.")
        sentences.append(_starts_compared(alt, holder_start, label, holder))
        notes.append(" ".join(sentences))
        if better:
            steps, holder, holder_start = other, f"the {label}", alt
    return steps


def _lead_base(first: Diagnosis, picked):
    """The suggestion of ``first`` that ``picked`` adds a series inductance to, when ``picked`` is
    such a pair (`diagnosis._lead_behind`: ``constant_phase+series_inductance``), else None (also
    when there is no ``picked``: the greedy path took no step). The pair's ΔAIC is mostly the
    lead's (impedance.py's REAL Autolab spectrum from ``R0 + R1 || C1``: CPE1 −42.6 alone and
    −280.0 with L_lead, Ws_d −42.1): measured from the pair, no other first effect was within
    `BRANCH_WINDOW`, and the path from Ws_d, which ends 74 lower in AIC, was never tried."""
    head, _, last = (picked.effect or "").rpartition("+") if picked is not None else ("", "", "")
    if last != "series_inductance" or not head:
        return None
    circuit = picked.fit.circuit

    def under(s) -> bool:  # picked's circuit is s's with one element more, the lead, and nothing moved
        extra = set(circuit.element_names) - set(s.fit.circuit.element_names)
        return len(extra) == 1 and str(circuit.without(extra.pop())) == str(s.fit.circuit)

    return next((s for s in first.suggestions if s.effect == head and under(s)), None)


def _vanishing_elements(fit: FitResult) -> set[str]:
    """The elements of ``fit``'s circuit in a term that vanished (`vanishing.vanished_terms`: a
    resistor at 0 in series, a branch that carries nothing), which `_pruned` leaves out."""
    terms = vanished_terms(fit)  # (none unless a parameter is flagged: most fits end here)
    names = set(fit.circuit.element_names) if terms else set()
    return {e for _, reduced, _ in terms for e in names - set(reduced.element_names)}


def _vanished_on(path: list[RefinementStep]) -> tuple[str, ...]:
    """The series resistances the steps of ``path`` left out because they fell to zero
    (`RefinementStep.vanished`) and that its end does not have again."""
    end = getattr(getattr(path[-1].fit, "circuit", None), "element_names", ())
    return tuple(dict.fromkeys(name for step in path for name in step.vanished if name not in end))


def _path_size(path: list[RefinementStep]) -> int:
    """The size `_second_path` compares the ends of its paths by: the end's free parameters, with
    each resistance that fell to zero on the way and was left out counted as kept
    (`diagnosis.ranked_size`, the ranking's count). By the fit's own count, on a
    SYNTHETIC Meyer finger with CPE skin, the path from W_d with R_f fallen to zero (4 parameters,
    AIC −754.1) would be kept in place of the first path's CPE_sc (5, AIC −754.2), the truth, "as good
    with fewer parameters", although the ranking puts CPE_sc first for counting R_f as kept."""
    return ranked_size(path[-1].fit, _vanished_on(path))


def _size_words(path: list[RefinementStep]) -> str:
    """A path end's size in a note: ``5 parameters``, or ``4 parameters, 5 counting R_f, which
    fell to zero and was left out, as kept``."""
    fell = _vanished_on(path)
    words = f"{path[-1].fit.n_params} parameters"
    return words + (f", {_path_size(path)} counting {', '.join(fell)}, which fell to zero and {'was' if len(fell) == 1 else 'were'} left out, as kept" if fell else "")


def _parameter_count(fit, elements) -> int:
    """How many of ``fit``'s free parameters belong to ``elements`` (names: ``R0``, or ``CPE1``
    for ``CPE1.Q`` and ``CPE1.alpha``)."""
    return sum(1 for name in fit.free_names if name.split(".")[0] in set(elements))


def _network(fit) -> str | None:
    """``fit``'s circuit without its element names (`Circuit.structure_key`), or None for a fit
    without a circuit."""
    circuit = getattr(fit, "circuit", None)
    return circuit.structure_key(getattr(fit, "registry", DEFAULT_REGISTRY)) if isinstance(circuit, Circuit) else None


def _same_network(a, b) -> bool:
    """Whether the fits ``a`` and ``b`` are of one circuit, under the same or other element
    names (`Circuit.structure_key`: the elements' kinds and how they connect, series and
    parallel parts in any order)."""
    key = _network(a)
    return key is not None and key == _network(b)


def _distinct_networks(suggestions: list, picked=None) -> list:
    """``suggestions`` less each one whose circuit is ``picked``'s or an earlier one's, under
    the same or other names (`_same_network`), unless it leaves out fewer of the user's
    elements (its ``removed`` a proper subset: a path in the user's names): the first-found stays."""
    seen, out = [picked] if picked is not None else [], []
    for s in suggestions:
        if not any(_same_network(s.fit, t.fit) and not set(s.removed) < set(t.removed) for t in seen):
            seen.append(s)
            out.append(s)
    return out


def _kept_in_place(first: Diagnosis, picked, taken) -> list:
    """When the first choice ``picked`` left a baseline element out (a branch that carried next
    to no current, a series resistance that fell to zero): the same candidate with that
    element kept, if it converged within `BRANCH_WINDOW` of AIC and starts no other path
    (usually it is no suggestion: it leaves parameters undetermined). Once a second
    missing effect is added, the element may carry current again; the path ends at the
    circuit that keeps it (its end must have every parameter determined, `_finish`). On a
    SYNTHETIC battery lacking its lead inductance and its Warburg, the inductance without R2
    (R2 ∥ CPE2 acting as a plain CPE, which took the diffusion tail) led to an arc standing in
    for the Warburg at 10 parameters; with R2 kept, the Warburg follows behind R2 and the path
    ends at 9, lower by 2 in AIC."""
    if picked is None or not picked.removed:
        return []
    element, shorter = picked.removed[-1], tuple(picked.removed[:-1])
    parents = [
        c for c in first.candidates
        if c.effect == picked.effect and tuple(c.removed) == shorter and c.fit.converged and c.delta_aic <= picked.delta_aic + BRANCH_WINDOW and all(c is not t for t in taken)
        and element in c.fit.circuit.element_names and str(c.fit.circuit.without(element)) == str(picked.fit.circuit)
    ]
    return sorted(parents, key=lambda c: c.delta_aic)[:1]


def _elements_left_out(path: list[RefinementStep]) -> set[str]:
    """The elements the steps of ``path`` left out (a C turned into a CPE is changed, not left out)."""
    return {name for step in path for name in step.removed}


CHEAPER_PATHS = 2
"""At most this many paths of cheaper effects (`_cheaper_starts`)."""


def _cheaper_starts(steps: list[RefinementStep], picked, taken) -> list:
    """When the greedy path ends ``adequate``: the first diagnosis' best significant suggestion
    of each other effect that adds fewer parameters than the first choice ``picked`` (the
    suggestion the greedy path started from) and starts no other
    path (at most `CHEAPER_PATHS`, the best ranked first). One element of many parameters can
    stand in for two effects of one each: on a SYNTHETIC Meyer finger lacking its series
    resistance and its CPE, a nested R ∥ CPE (three parameters) reached the noise in one step,
    where R_f and C_sc → CPE_sc (one each) reach it in two with a parameter fewer; on a
    Randles cell lacking its CPE and its Warburg, R ∥ CPE in series and then a Warburg ended
    at 7 parameters, C1 → CPE1 and then W behind R1 at the generating 5. A path is kept only
    when it ends as good with fewer parameters, or better (`_second_path`)."""
    first = steps[0].diagnosis
    if len(steps) < 2 or steps[-1].diagnosis is None or steps[-1].diagnosis.verdict != Verdict.ADEQUATE:
        return []
    best_per_effect: dict[str, object] = {}  # (suggestions are ranked best first)
    for s in first.suggestions:
        if s.effect != picked.effect and s.fit.n_params < picked.fit.n_params and all(s is not t for t in taken):
            best_per_effect.setdefault(s.effect, s)
    return list(best_per_effect.values())[:CHEAPER_PATHS]


def _finish(steps: list[RefinementStep], used: xr.Dataset, *, n_starts: int, seed: int, say, notes: list[str], label: str, progress_label: str | None = None, reproduced=None) -> list[RefinementStep]:
    """``steps`` with the last model refitted from scratch on ``used`` (`_reproduced`); while that
    fit leaves parameters undetermined that the start's fit determined, the last step is dropped
    and the one before refitted instead (a path may start from a candidate with undetermined
    parameters, `_second_path`). ``reproduced``: `_reproduced` or a memo of it. ``label``
    starts the notes (a side path's report label), ``progress_label`` the progress line
    (``label`` when None)."""
    reproduced = reproduced or _reproduced
    # a side path's note speaks of that path's values, not of the refinement's (which it may not keep)
    whose = {"whose": SIDE_PATH} if label else {}
    steps = list(steps)
    say(f"{label if progress_label is None else progress_label}refitting the final model {steps[-1].model} from scratch")
    final, note = reproduced(used, steps[-1].fit, n_starts=n_starts, seed=seed, **whose)
    new_undetermined = undetermined_parameters(final) - undetermined_parameters(steps[0].fit)
    while new_undetermined and len(steps) > 1:
        notes.append(f"{label}{final.model}: the data do not determine {', '.join(sorted(new_undetermined))} when fitted from scratch; the step that added {steps[-1].added} is dropped")
        steps.pop()
        final, note = reproduced(used, steps[-1].fit, n_starts=n_starts, seed=seed, **whose)
        new_undetermined = undetermined_parameters(final) - undetermined_parameters(steps[0].fit)
    if note:
        notes.append(label + note)
    steps[-1] = replace(steps[-1], fit=final)
    return steps


def _removable(steps: list[RefinementStep]) -> list[str]:
    """The elements of the last model that refine added and may take out again: every element
    new to the path, except one that took the place of an element of the user's model (C → CPE,
    W → Wo: taking it out would take out the user's element)."""
    kept = set(steps[0].fit.circuit.element_names)  # the user's elements and what replaced them
    for before, after in zip(steps, steps[1:]):
        old, new = set(before.fit.circuit.element_names), set(after.fit.circuit.element_names)
        replaced = old - new - set(after.removed)
        if replaced & kept:
            kept |= new - old
    return [name for name in steps[-1].fit.circuit.element_names if name not in kept]


def _simplified(steps: list[RefinementStep], used: xr.Dataset, *, n_starts: int, seed: int, diagnosed, reproduced, say, notes: list[str]) -> list[RefinementStep]:
    """``steps`` ending ``adequate``, followed by simpler models while one is adequate too: the
    last model without one element refine added (`_removable`; out of a parallel block its
    branch opens, out of a series chain it is shorted), fitted from the last model's values,
    is kept when its AIC is at most `DELTA_AIC_MIN` above the last model's (the rule by which
    the element would not have been added), every parameter stays determined, and its own
    diagnosis is ``adequate``; the lowest AIC first, one element per step, until none is.

    Greedy additions can end on an element that stood in for an effect added later: on a
    SYNTHETIC finger lacking its series resistance and its electrode polarization, a further
    R ∥ CPE came first (standing in for both), then R_EP ∥ CPE_EP; without CPE_relax the
    R ∥ CPE is the series resistance, 2 parameters fewer and AIC lower by 3.7, which the
    forward steps alone never reach."""
    steps, start = list(steps), steps[0].fit
    while steps[-1].diagnosis is not None and steps[-1].diagnosis.verdict == Verdict.ADEQUATE and len(steps) > 1:
        last = steps[-1].fit
        names = _removable(steps)
        if not names:
            break
        say(f"simplifying: fitting {last.model} without each of {', '.join(names)}")
        shorter = []
        for name in names:
            try:
                shorter.append((name, last.circuit.without(name)))
            except CircuitError:  # (the element is the whole circuit)
                continue
        # in the last diagnosis' compiled solver (it held larger circuits), from the last model's values
        fixed = {k: v for k, v in last.values.items() if last.fixed[k]} or None
        fits = fit_candidates([c for _, c in shorter], used, init=[{k: last.values[k] for k in c.parameter_names(last.registry)} for _, c in shorter],
                              fixed=fixed, bounds=dict(last.bounds) or None, weighting=last.weighting, n_starts=n_starts, seed=seed, registry=last.registry, shape=steps[-1].diagnosis.solver_shape)
        trials = [(trial.aic, name, trial) for (name, _), trial in zip(shorter, fits) if np.isfinite(trial.aic) and trial.aic <= last.aic + DELTA_AIC_MIN]
        for _, name, trial in sorted(trials, key=lambda t: t[0]):
            final, note = reproduced(used, trial, n_starts=n_starts, seed=seed)
            if undetermined_parameters(final) - undetermined_parameters(start):
                continue
            say(f"simplifying: diagnosing {final.model}")
            d = diagnosed(final, steps[-1].diagnosis.solver_shape)
            if d.verdict != Verdict.ADEQUATE:
                continue
            notes.append(
                f"{last.model} without {name} ({final.model}) is adequate too, with {counted(last.n_params - final.n_params, 'parameter')} fewer "
                f"(AIC {last.aic:.1f} → {final.aic:.1f}): {name} is taken out again"
                + (f"; {note}" if note else "")
            )
            steps.append(RefinementStep(final, None, None, d, (name,)))
            break
        else:
            break
    return steps


VALID_BAND_MISS_FACTOR = 15.0
"""The points outside the KK-passing run are left out as the data's own problem (`_on_valid_band`)
only while the model refined on the run misses them by at most this many times their own
Kramers–Kronig misfit (rms, relative): beyond, they are data a Kramers–Kronig-consistent model
follows and the run's model does not, not drift. Measured on the two REAL files where the rule
acts (2026-12-01): Gamry's (KK 5.6 % rms outside 2.5 kHz, up to 13 %) the run's model misses
by 35.5 %, 6.3×, and is kept; AutoEIS's test_data.txt (KK 0.70 % below 0.78 Hz) by 32 %, 46×,
where the whole band's path ended at 0.61 % on every point."""


def _on_valid_band(ds: xr.Dataset, band: xr.Dataset, steps: list[RefinementStep], circuit, *, say, **options) -> tuple[Refinement | None, str]:
    """`refine` of ``circuit`` again on ``band``, the run of points the KK test passes, when a
    step of the path ``steps`` on all of ``ds`` ended ``data_invalid`` (the misfit left is the
    data's own over at least `KK_INVALID_FRACTION` of the points) while its model still misses
    that run clearly (`Diagnosis.misses_run_band`). The points outside the run are in the
    result's ``masked_points`` (its report prints the ``--fmin``/``--fmax`` that leave them
    out) and a note says why. The case behind it: on Gamry's real file the KK test
    fails at 16 mHz–2.26 kHz (1–12 % misfit) and passes above (0.46 %); after one step the whole
    band's path stops ``data_invalid`` at 6.64 % with a model 6.45 % off the passing band (its C1 wanted
    a CPE); with ``--fmin 2.3e3`` it ends ``adequate`` at 0.516 %. Returns the refinement on the
    run and its note, or None and a note why the whole band's path stands: the run's final model
    misses the points outside by more than `VALID_BAND_MISS_FACTOR` × their KK misfit."""
    stop = steps[-1]
    lo, hi = stop.diagnosis.kk_run_band
    f = ds["frequency"].values
    outside = tuple(sorted(float(x) for x in f if not lo <= x <= hi))
    trim = left_out_words(left_out_options(band["frequency"].values, outside))
    path = " → ".join(s.fit.model for s in steps)
    run = (stop.fit.frequency >= lo) & (stop.fit.frequency <= hi)
    missed = float(np.sqrt(np.mean(np.abs(stop.fit.residuals[run]) ** 2)))
    say(f"starting again on the {band.sizes['frequency']} points the KK test passes ({format_frequency(lo)}–{format_frequency(hi)}; {trim})")
    again = refine(band, circuit, progress=say, **options)
    left = ~((f >= lo) & (f <= hi))
    z = ds["Z"].values
    off = float(np.sqrt(np.mean(np.abs((np.asarray(again.final.predict(f[left])) - z[left]) / z[left]) ** 2)))
    kk = stop.diagnosis.kk
    at = np.isin(np.asarray(kk.frequency), f[left]) if kk is not None else np.zeros(0, bool)
    kk_off = float(np.sqrt(np.mean(np.asarray(kk.residuals_real)[at] ** 2 + np.asarray(kk.residuals_imag)[at] ** 2))) if at.any() else math.nan
    if math.isfinite(kk_off) and off > VALID_BAND_MISS_FACTOR * kk_off:
        return None, (
            f"on the {band.sizes['frequency']} points the KK test passes ({format_frequency(lo)}–{format_frequency(hi)}) refine ends at {again.final.model} "
            f"(rms_rel {again.final.rms_rel * 100:.3g} % there; {trim}), but that model misses the {len(outside)} points outside by {off * 100:.3g} % rms, "
            f"{off / kk_off:.0f}× their own Kramers–Kronig misfit ({kk_off * 100:.2g} %): they are data a Kramers–Kronig-consistent model follows, not the data's own problem, "
            "so the path on every point stands"
        )
    note = (
        f"on all {f.size} points the path {path} ended data_invalid after {counted(len(steps) - 1, 'step')}: the misfit left is the data's own over much of the band "
        f"(the KK test fails outside {format_frequency(lo)}–{format_frequency(hi)}), but {stop.fit.model} still misses the {band.sizes['frequency']} points it passes"
        + f" by {missed * 100:.3g} % rms: refine started again on those points ({trim}; the {len(outside)} outside are left out as the data's own problem)"
    )
    masked = tuple(sorted(set(outside) | set(again.masked_points)))
    # the first step's diagnosis carries them too, with their measured Z: the figures mark them
    start = again.steps[0].diagnosis
    measured = dict(zip(start.masked_points, start.masked_impedance)) | {float(x): complex(v) for x, v in zip(f, ds["Z"].values) if not lo <= x <= hi}
    first = replace(again.steps[0], diagnosis=replace(start, masked_points=masked, masked_impedance=tuple(measured[x] for x in masked)))
    restart = {"band_hz": [float(lo), float(hi)], "n_points_kept": int(band.sizes["frequency"]), "n_points_left_out": len(outside), "reason": note}
    return Refinement((first,) + tuple(again.steps[1:]), again.verdict, (note,) + again.notes, masked, final_from_values=again.final_from_values, restart=restart), note


def _named_band_instead(ds: xr.Dataset, stop: Diagnosis, run_band: tuple[float, float]) -> tuple[float, float, xr.Dataset] | None:
    """The band the verdict names (`Diagnosis.kk_valid_band`, impedax kk's) with its points, when
    it is not ``run_band`` (the one refine acts on) and leaves out more than `KK_MASK_MAX_FRACTION`
    of the points too: refine's note then names it (REAL CH Instruments: 4.64 Hz–82.5 kHz, not the
    run 825 Hz–46.4 kHz); None otherwise."""
    named = stop.kk_valid_band
    if named is None or tuple(named) == tuple(run_band):
        return None
    f = ds["frequency"].values
    band = ds.isel(frequency=np.nonzero((f >= named[0]) & (f <= named[1]))[0])
    if 1 - band.sizes["frequency"] / ds.sizes["frequency"] <= KK_MASK_MAX_FRACTION:
        return None
    return named[0], named[1], band


def _capacitors(fit: FitResult) -> list[tuple[str, str, Circuit, dict[str, float]]]:
    """The CPEs of ``fit`` whose α is at its upper bound 1 (``at_bound``): each one an ideal
    capacitor C = Q (Z = 1/(Q (jω)^α)). As (CPE name, the C's name, the circuit with the C in
    its place, starting values of that circuit from ``fit``'s)."""
    out = []
    registry = fit.registry
    for e in fit.circuit.elements():
        if registry[e.symbol].symbol != "CPE":
            continue
        q, alpha = registry[e.symbol].parameter_names(e.name)
        if alpha not in fit.at_bound or fit.values[alpha] < 0.5 or fit.fixed[q]:  # (α at 1, not at 0)
            continue
        name = capacitor_name(e.name, fit.circuit.element_names)
        circuit = fit.circuit.replace(e.name, Element("C", name))
        init = {k: v for k, v in fit.values.items() if k not in (q, alpha)}
        init[registry["C"].parameter_names(name)[0]] = fit.values[q]
        out.append((e.name, name, circuit, init))
    return out


def _pruned(steps: list[RefinementStep], used: xr.Dataset, *, n_starts: int, seed: int, diagnosed, reproduced, say, notes: list[str]) -> list[RefinementStep]:
    """``steps`` followed by the final model without what its fit's own flags say is not there:
    a term that vanished (`vanishing.vanished_terms`: out of a parallel block the branch opens, out of a
    series chain it is shorted) and a CPE whose α is at its bound 1, replaced by a C
    (`_capacitors`). Each simpler model is fitted from the last model's values and refitted as
    the final model is (`reproduced`); it is kept when its χ² is at most `BOUND_CHI2_FRACTION`
    of the reduced χ² above the last model's (the rule by which the fit put the parameter at its
    bound: the data cannot tell the two apart, and with fewer parameters its AIC is lower), no
    parameter is undetermined that the last model determined, and it gets its own diagnosis;
    one change per step, until none is left. Whatever the verdict: the final model is one
    ``impedax fit`` reproduces with every parameter it keeps determined.

    When nothing vanished, a term the data do not support (`unsupported.unsupported_terms`: an
    arc seen on one flank only, an element holding an undetermined parameter) is taken out
    the same way when the simpler model's AIC is not higher, and an ``adequate`` end stays
    ``adequate``: the term bought no fit for its parameters.

    On CHInstruments' spectrum refine ended at R0 + R1 || C1 + (R_relax + R_relax2 ||
    CPE_relax2) || CPE_relax with R1 = 1.8e255 Ω (at its bound ∞: R1 carried 7e-252 of the
    current through R1 || C1), reproducible only from those values; without R1 it reaches the
    same rms_rel from scratch, one parameter fewer. On exampleData.csv (max_effects 6) CPE1,
    which had taken C1's place, ended at α = 1: C1 in its place fits as well, AIC lower by 2."""
    steps = list(steps)
    while True:
        last = steps[-1].fit
        changes = []  # (added, removed, circuit, init, why)
        for branch, reduced, names in vanished_terms(last):
            held = ", ".join(f"{n} at its bound" if n in last.at_bound else f"{n} (a vanishing term's)" for n in names)
            what = share_words(branch)
            removed = tuple(e for e in last.circuit.element_names if e not in reduced.element_names)
            changes.append((None, removed, reduced, {k: v for k, v in last.values.items() if k in reduced.parameter_names(last.registry)},
                            f"{branch.element} {what} {branch.block} over the band ({held}): its term vanished, and {{final}}, the model without it,"))
        for cpe, c, circuit, init in _capacitors(last):
            changes.append((c, (cpe,), circuit, init, f"{cpe}.alpha is at its upper bound 1, where {cpe} is an ideal capacitor: {{final}}, with {c} in its place,"))
        by_aic = not changes  # (what vanished first: taking it out changes no fit)
        if by_aic:
            # (the simplest first: a redundant arc goes whole, not its R in one step and its C in the next)
            for term in sorted(unsupported_terms(last), key=lambda t: len(t.reduced.parameter_names(last.registry))):
                changes.append((None, term.removed, term.reduced, {k: v for k, v in last.values.items() if k in term.reduced.parameter_names(last.registry)},
                                f"{term.why}: {{final}}, without {', '.join(term.removed)},"))
        if not changes:
            break
        what = "a term the data do not support" if by_aic else "what vanished or is at a bound"
        say(f"pruning: fitting {last.model} without {what} ({'; '.join(', '.join(r) for _, r, _, _, _ in changes)})")
        kept = False
        fixed_all = {k: v for k, v in last.values.items() if last.fixed[k]}
        for added, removed, circuit, init, why in changes:
            names = set(circuit.parameter_names(last.registry))
            fixed = {k: v for k, v in fixed_all.items() if k in names} or None
            bounds = {k: v for k, v in last.bounds.items() if k in names} or None  # (the user's, kept where the parameter is)
            start = {k: v for k, v in init.items() if k not in (fixed or {})}
            try:  # (a value on its bound is no start: the fit guesses that one)
                table = ParameterTable.build(circuit, registry=last.registry, bounds=bounds)
                start = {k: v for k, v in start.items() if table.lower[table.names.index(k)] < v < table.upper[table.names.index(k)]}
                trial = fit(circuit, used, init=start, fixed=fixed, bounds=bounds, weighting=last.weighting, registry=last.registry, n_starts=1, seed=seed)
            except (ParameterError, CircuitError):
                continue
            if by_aic and not trial.aic <= last.aic + DELTA_AIC_MIN:  # (far above from the last model's values: no refit from scratch)
                continue
            say(f"pruning: refitting {trial.model} from scratch")
            final, note = reproduced(used, trial, n_starts=n_starts, seed=seed)
            tolerance = BOUND_CHI2_FRACTION * last.chi2_red + 2 * last.n_points * 1e-28  # (`result.confirm_bounds`)
            as_good = final.aic <= last.aic if by_aic else final.chi2 <= last.chi2 + tolerance
            if not (np.isfinite(final.chi2) and as_good and final.n_params < last.n_params):
                continue
            if undetermined_parameters(final) - undetermined_parameters(last):
                continue
            say(f"pruning: diagnosing {final.model}")
            d = diagnosed(final, steps[-1].diagnosis.solver_shape) if steps[-1].diagnosis is not None else None
            if by_aic and steps[-1].diagnosis is not None and steps[-1].diagnosis.verdict == Verdict.ADEQUATE and (d is None or d.verdict != Verdict.ADEQUATE):
                continue
            # the notes' fits from their values concern models no longer final: only the final's reproduce line is due
            notes[:] = [n.replace(" (pass init=)", "") for n in notes]
            change = f"{', '.join(removed)} is replaced by {added}" if added else f"{', '.join(removed)} {'is' if len(removed) == 1 else 'are'} taken out"
            notes.append(
                why.replace("{final}", final.model) + f" {'is as good by AIC as' if by_aic else 'fits as well as'} {last.model} (rms_rel {last.rms_rel * 100:.3g} % → {final.rms_rel * 100:.3g} %, "
                f"AIC {last.aic:.1f} → {final.aic:.1f}) with {counted(last.n_params - final.n_params, 'parameter')} fewer: {change}"
                + (f"; {note}" if note else "")
            )
            steps.append(RefinementStep(final, added, None, d, removed))
            kept = True
            break
        if not kept:
            break
    return steps


REFINE_START = "R0 + R1 || C1"
"""refine's circuit when none is given: a series resistance and one ideal arc, from which it
adds what the data need (the start of the real-spectra study, docs/diagnosis.md)."""


MIN_CANDIDATE_STEPS = 10
"""``max_steps`` is refine's number of effects (``max_effects``) in older versions: a value below this
given without ``max_effects`` is refused with a message naming ``max_effects`` rather than run
as a step limit no candidate fit could converge within (with ``max_effects`` given, it is a step
limit whatever its size, as ``impedax refine --max-steps`` passes it)."""


@reports_progress
@checked_arguments(
    circuit_parameters=circuit_parameters, max_steps=count(1, MAX_SOLVER_STEPS, optional=True), max_effects=count(0, 64, optional=True, why="each effect adds one element"),
    solver_steps=count(1, MAX_SOLVER_STEPS, optional=True), effects=instance_of(EffectCatalog, what="an EffectCatalog (e.g. impedax.DEFAULT_EFFECTS)"),
    weighting=choice(WEIGHTINGS), noise=noise_fraction, registry=instance_of(Registry), fmin=frequency, fmax=frequency,
    n_starts=count(1, MAX_STARTS), seed=seed_rule, drt_evidence=flag, fixed=parameter_values(), bounds=parameter_bounds, mask=flag,
)
def refine(
    data,
    circuit: Circuit | str = REFINE_START,
    *,
    max_steps: int | None = None,
    max_effects: int | None = None,
    solver_steps: int | None = None,
    effects: EffectCatalog = DEFAULT_EFFECTS,
    weighting: str = "modulus",
    noise: float | None = None,
    registry: Registry = DEFAULT_REGISTRY,
    fmin: float | None = None,
    fmax: float | None = None,
    n_starts: int = 4,
    seed: int = 0,
    drt_evidence: bool = True,
    progress: Callable[[str], None] | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    mask: bool = True,
) -> Refinement:
    """Refine ``circuit`` (default `REFINE_START`) on ``data``: diagnose → add the best
    significant effect → refit, until the verdict is not ``missing_effect`` (or no suggestion
    remains) or ``max_effects`` (default 4; ``--max-effects`` of the CLI) effects were added.
    ``max_steps`` (default 100): the Levenberg–Marquardt step limit of the candidate fits of
    every step, as ``max_steps`` of `fit` and `diagnose` and ``--max-steps`` of the CLI (the
    baseline fit keeps its own); it was once the number of effects, so a value below
    `MIN_CANDIDATE_STEPS` without ``max_effects`` is a ParameterError naming ``max_effects``.
    ``solver_steps`` is the step limit's older name (with a FutureWarning).
    ``registry`` parses the circuit; only the points with ``fmin`` ≤ f ≤ ``fmax`` are used, at
    every step, less the points the first diagnosis masks (KK-flagged); ``drt_evidence`` as in
    `diagnose`; ``progress`` is called with a line of text as each step starts, and indented
    as each stage of a step's diagnosis starts. ``fixed`` (name → value, as `fit`'s) holds at
    every step in every model that still has the parameter (the first diagnosis' baseline fit
    holds it, and each later fit keeps its start's fixed values); ``bounds`` (name → (lower,
    upper), as `fit`'s) are kept the same way, as a FitResult's bounds are, the final refit
    included (an element replaced, C → CPE, drops its bound). The final model is refitted with `fit` on the
    same points (reproducible with ``impedax fit``); a last step whose refit leaves parameters
    undetermined is dropped; an ``adequate`` end loses the elements it added that an adequate
    model can do without (`_simplified`); then any end loses a term its fit's flags say
    vanished (a resistor run open) and has a C in place of a CPE at α = 1 (`_pruned`). ``mask``:
    False keeps every point (but those with Re Z < 0) in every fit, as `diagnose`'s
    ``mask=False`` and ``impedax refine --keep-all-points``: nothing is left out as not
    Kramers–Kronig consistent, and refine does not start again on the band the KK test passes.
    Returns a `Refinement`."""
    check_argument_order("refine", data, circuit)
    if solver_steps is not None:
        if max_steps is not None:
            raise ParameterError("give max_steps (the step limit of the candidate fits; solver_steps is its older name), not both")
        warnings.warn(f"refine(solver_steps={solver_steps}) is now refine(max_steps={solver_steps}), as in fit and diagnose", FutureWarning, stacklevel=3)
        max_steps = solver_steps
    if max_steps is not None and max_steps < MIN_CANDIDATE_STEPS and max_effects is None:
        raise ParameterError(
            f"refine(max_steps={max_steps}): max_steps is the step limit of the candidate fits (as in fit, diagnose and impedax refine --max-steps); "
            f"the number of effects to add is max_effects (max_effects={max_steps}); a step limit below {MIN_CANDIDATE_STEPS} needs max_effects given too"
        )
    limit = 4 if max_effects is None else max_effects
    solver_steps = CANDIDATE_STEPS if max_steps is None else max_steps
    say = progress or (lambda text: None)
    ds = open_spectrum(data, fmin=fmin, fmax=fmax, single="refine").data
    # (too few points are refine's to name, before its first diagnosis says "diagnose needs …")
    parsed = parse(circuit, registry) if isinstance(circuit, str) else circuit
    require_points_for_diagnosis(int((~non_passive_points(ds)).sum()), len(parsed.parameter_names(registry)), "refine", source=ds.attrs.get("source"), fmin=fmin, fmax=fmax)
    say(f"step 0: diagnosing {circuit}")

    def within(text: str) -> None:  # (a diagnosis' stages, under the step that runs it: none silent for long)
        say(f"  {text}")

    # the DRTs of the run's spectra, each solved once: the data's (the same at every step) and a
    # model's met again (a step's baseline is the fit the step before proposed)
    drts = DRTMemo()
    first = diagnose(ds, circuit, effects=effects, noise=noise, weighting=weighting, registry=registry, n_starts=n_starts, max_steps=solver_steps, seed=seed, drt_evidence=drt_evidence, progress=within, drt_memo=drts, fixed=fixed, bounds=bounds, mask=mask)
    masked = first.masked_points
    # the KK test as the first diagnosis got it (before its local judgement, which every step
    # redoes): the discrepancy floor δ takes that test's flags, so each step has the first's noise
    kk = first.kk_of_kept or first.kk_as_tested or first.kk

    # paths often meet (a second path reaching a model the first diagnosed): a model diagnosed
    # before, at a fit at least as good, is not diagnosed again, and a fit refitted from
    # scratch before is not refitted again; the greedy steps from it are then the same
    diagnoses: dict[str, Diagnosis] = {}
    refits: dict[int, tuple] = {}

    def diagnosed(current: FitResult, shape) -> Diagnosis:
        known = diagnoses.get(str(current.circuit))
        if known is not None and known.baseline.chi2 <= current.chi2 * (1 + REUSE_CHI2_RTOL):
            return known
        # every step through one compiled solver and on the first step's points (mask=False)
        d = diagnose(current, data=ds, effects=effects, kk=kk, noise=noise, n_starts=n_starts, max_steps=solver_steps, seed=seed, drt_evidence=drt_evidence, solver_shape=shape, mask=False, progress=within, drt_memo=drts)
        diagnoses[str(current.circuit)] = d
        return d

    def reproduced(used, fit, *, whose=MAIN_PATH, **options):
        known = refits.get(id(fit))
        # (a refit noted for one path is redone for another: its note names the path)
        if known is None or known[0] is not fit or (known[1][1] is not None and known[2] != whose):
            refits[id(fit)] = (fit, _reproduced(used, fit, say=say, whose=whose, **options), whose)  # (the fit kept: its id stays its own)
            out = refits[id(fit)][1][0]
            # a refit is its own refit: a path whose end went back to the start hands the start
            # step, refitted, to the next path, which may end there too
            refits.setdefault(id(out), (out, (out, None), whose))
        return refits[id(fit)][1]

    used = ds if not masked else ds.sel(frequency=[f for f in ds["frequency"].values if float(f) not in set(masked)])
    # (the first diagnosis' note on parameters its baseline does not determine apart: refine's report shows no diagnosis' notes)
    notes: list[str] = [unidentified_note(first.baseline)] if first.baseline.unidentified_groups else []

    def finished(path, label, progress_label=None):
        return _finish(path, used, n_starts=n_starts, seed=seed, say=say, notes=notes, label=label, progress_label=progress_label, reproduced=reproduced)

    picked = _best_within(first, limit)
    steps = _greedy([RefinementStep(first.baseline, None, None, first)], picked, limit, diagnosed, say, "")
    stop = steps[-1].diagnosis
    if mask and stop.verdict == Verdict.DATA_INVALID and stop.misses_run_band and stop.kk_run_band is not None:
        # the misfit left is the data's own over much of the band, but the model still misses the
        # band the KK test passes: judge it there (`_on_valid_band`), not give up on the whole,
        # when what it leaves out is at most the share a diagnosis leaves out (`KK_MASK_MAX_FRACTION`)
        lo, hi = stop.kk_run_band
        band = ds.isel(frequency=np.nonzero((ds["frequency"].values >= lo) & (ds["frequency"].values <= hi))[0])
        outside = 1 - band.sizes["frequency"] / ds.sizes["frequency"]
        if 0 < band.sizes["frequency"] < ds.sizes["frequency"] and outside > KK_MASK_MAX_FRACTION:
            named = _named_band_instead(ds, stop, (lo, hi))  # (the verdict's band, impedax kk's, when it too leaves out more than that share)
            if named is not None:
                lo, hi, band = named
                outside = 1 - band.sizes["frequency"] / ds.sizes["frequency"]
            notes.append(
                f"the KK test passes only {format_frequency(lo)}–{format_frequency(hi)} ({band.sizes['frequency']} of {ds.sizes['frequency']} points), where {stop.baseline.model} "
                f"misses the data clearly; {NOT_RESTARTED_WORDS}: it would leave out {outside * 100:.0f} % of the points, more than the "
                f"{KK_MASK_MAX_FRACTION * 100:.0f} % it leaves out as not Kramers–Kronig consistent (KK_MASK_MAX_FRACTION), so every point is kept and the data's problem is "
                "reported beside the verdict (impedax refine --fmin/--fmax judges that band alone)"
            )
        elif 0 < band.sizes["frequency"] < ds.sizes["frequency"]:  # (each start again drops points: it ends)
            restarted, why = _on_valid_band(
                ds, band, steps, circuit, say=say, max_steps=solver_steps, max_effects=limit, effects=effects, weighting=weighting, noise=noise, registry=registry,
                n_starts=n_starts, seed=seed, drt_evidence=drt_evidence, fixed=fixed, bounds=bounds,
            )
            if restarted is not None:
                return _with_diagnose_verdict(restarted, first, ds, restarted=True)
            notes.append(why)
    # (data whose stored sign the KK test doubts (`Diagnosis.sign_hint`) end at that verdict: no
    # model is simplified or pruned on them; else conjugated SYNTHETIC finger data would lose C_s, R_sc
    # and C_sc as "vanishing" before the verdict names the sign)
    if not (stop.verdict == Verdict.DATA_INVALID and stop.sign_hint):
        def simplify(path):
            path = _simplified(path, used, n_starts=n_starts, seed=seed, diagnosed=diagnosed, reproduced=reproduced, say=say, notes=notes)
            return _pruned(path, used, n_starts=n_starts, seed=seed, diagnosed=diagnosed, reproduced=reproduced, say=say, notes=notes)

        steps = simplify(_second_path(steps, picked, limit, diagnosed, say, notes, finished))
        steps = _after_simplifying(steps, limit, diagnosed, say, notes, finished, simplify)
    steps = _with_alternatives(steps)
    last = steps[-1].diagnosis
    if last.verdict == Verdict.MISSING_EFFECT and last.best is not None and sum(effect_count(s.effect) for s in steps) + effect_count(last.best.effect) > limit:
        notes.append(
            f"refine stopped at its limit of {counted(limit, 'added effect')} (max_effects; --max-effects of impedax refine) while the last model "
            f"still misses an effect ({last.best.effect}, see the verdict): a higher limit goes on"
        )
    elif last.verdict == Verdict.MISSING_EFFECT and last.best is not None:
        notes.append(unfollowed_effect_note(steps, last.best))
    # the final fit is reproduced from its values when its own refit kept the warm start (`_reproduced`
    # noted it): another path's note says nothing of the final model
    from_values = any(out is steps[-1].fit and note is not None for _, (out, note), _ in refits.values())
    # only the final model's note points to the command printed last; other paths' notes name their own models
    own = f"fit of {steps[-1].fit.model} from scratch"
    notes = [n if from_values and own in n else n.replace(" (pass init=)", "") for n in notes]
    return _with_diagnose_verdict(Refinement(tuple(steps), last.verdict, tuple(notes), masked, final_from_values=from_values), first, ds)


def _with_diagnose_verdict(refinement: Refinement, first: Diagnosis, ds: xr.Dataset, *, restarted: bool = False) -> Refinement:
    """``refinement`` with the verdict of ``first`` (refine's first diagnosis: `diagnose` of the same
    data, model and options, on every point of the band) and, when its own verdict differs, the
    sentence that says why (`_diagnose_verdict_words`)."""
    note = _diagnose_verdict_words(refinement, first, ds.sizes["frequency"], restarted=restarted)
    return replace(refinement, diagnose_verdict=first.verdict, diagnose_note=note)


def _diagnose_verdict_words(refinement: Refinement, first: Diagnosis, n_points: int, *, restarted: bool) -> str | None:
    """Why refine's verdict differs from diagnose's on the same data, model and options, in one
    sentence; None when it does not. Refine's step 0 is that diagnosis (the same points, noise,
    weighting and starts); its verdict judges the final model, after the steps that added what
    each diagnosis proposed, or, ``restarted``, the final model of a refine started again on the
    points the KK test passes (`_on_valid_band`). On REAL Gamry data from ``R0 + R1 || C1``
    diagnose says MISSING_EFFECT (extra_relaxation) and refine, after adding it, DATA_INVALID:
    read side by side, without this sentence, two contradictory verdicts. None too for refine's
    purpose fulfilled: diagnose proposes an effect, refine adds it (and maybe more) and ends
    ADEQUATE on the same points, which needs no sentence."""
    if refinement.verdict == first.verdict:
        return None
    if not restarted and first.verdict == Verdict.MISSING_EFFECT and refinement.verdict == Verdict.ADEQUATE:
        return None
    start = first.baseline.model
    said = f"diagnose of {start} (impedax diagnose, with the same options) says {first.verdict.upper()}"
    if first.verdict == Verdict.MISSING_EFFECT and first.best is not None:
        said += f" (adding {first.best.effect})"
    final = refinement.final
    if restarted:
        judged = first.baseline.frequency.size
        on = f"all {n_points} points" if judged == n_points else f"{judged} of the {n_points} points"
        lo, hi = refinement.verdict_band
        return (f"{said} on {on}; refine started again where the KK test passes ({format_frequency(lo)}–{format_frequency(hi)}; "
                f"the first note says why), and this verdict judges its final model {final.model} on those points.")
    n_steps = len(refinement.steps) - 1
    if n_steps == 0:  # (the start refitted from scratch at the end, `_reproduced`, and diagnosed again)
        return f"{said}, as refine's step 0 does; this verdict judges the start's final fit, refitted from scratch (rms_rel {final.rms_rel * 100:.3g} %), not diagnose's fit of it."
    return (f"{said}, as refine's step 0 does; this verdict judges the final model {final.model}, "
            f"after the {n_steps} step{'' if n_steps == 1 else 's'} that followed, not the start.")
