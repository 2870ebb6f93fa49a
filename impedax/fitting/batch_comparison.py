"""Model comparison over many spectra: several batches of fits (one circuit each, `fit` of a
stack of spectra) ranked spectrum by spectrum and over the whole stack (docs/fitting.md,
"Comparing models over many spectra")."""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Sequence

import numpy as np
import xarray as xr

from ..data import column_width, concise_repr, format_percent_column, report_text
from ..errors import FitsNotComparable
from ..io.netcdf import NETCDF_ADVICE, result_dataset
from .comparison import DECISIVE_DELTA_AIC, NESTED_WORSE_REL, common_source, NOISE_F, SAME_FIT_RMS, criteria_tie, WEAK_DELTA_AIC, Comparison, akaike_weights, compare, criteria, weightings_differ, fit_label, labelled_warnings, nested_as_held, register_batch_compare, unique_labels
from .least_squares import BatchFitResult, SharedFitResult
from .least_squares.batch import SPECTRA_AS_ROWS, labels_by_keyword, labels_key, labels_shown, spectra_named
from .least_squares.result import BOUND_CHI2_FRACTION, MISFIT_CHECKED_FROM, MISFIT_RATIO_MAX, data_difference, misfit_hint_spectra
from .frozen import FrozenResult, freeze_fields

__all__ = ["BatchComparison", "compare_batches", "PER_SPECTRUM_CRITERIA", "SUM_NOTE"]

PER_SPECTRUM_CRITERIA = ("rms_rel", "chi2", "chi2_red", "aic", "aicc", "bic", "delta_aic", "akaike_weight", "converged")
"""Each spectrum's row for each model: the columns of a single `Comparison`'s table."""

FIT_COMMAND_WORDS = "impedax fit FILE --model MODEL"
"""The command a batch comparison's report names for its fits' warnings; `impedax compare`
writes its own file, options and first warned model in its place."""

SUM_NOTE = "AIC summed over the spectra: the spectra are independent, so the joint log-likelihood, the parameter count and the joint AIC are sums"
"""What the summed AIC is (Burnham & Anderson 2002, §2.2: AIC = −2 ln L + 2K with ln L and K
summed over independent data sets; each spectrum keeps its own noise scale)."""


BATCH_PREFIX = "batch{}_"
"""What `BatchComparison.to_xarray` names each batch's variables, dimensions and attributes
with, ``.format(position)``: ``batch0_value``."""

_COMPARISON_ATTRS = ("aic_form", "weighting", "note")  # (`compare_batches`'s own attrs of ``dataset``)

EACH_SPECTRUM_WHERE = "comparison.to_table() or summary()['spectra']; one spectrum's full comparison: comparison_of(DIM=LABEL)"
"""Where `BatchComparison.report` sends the reader beyond `SPECTRA_AS_ROWS` spectra."""


@dataclass(frozen=True)
class SpectrumStatistics(FrozenResult):
    """One spectrum's fit in a batch as `criteria` reads a fit: N frequencies (``n_points``),
    k free parameters, χ², its ``weighting`` and the AIC and BIC the batch computed with the
    formula of `FitResult.aic` (`statistics.information_criteria`)."""

    n_points: int
    n_params: int
    chi2: float
    aic: float
    bic: float
    weighting: str

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)


def _spectra_flat(batch: BatchFitResult, dims: Sequence[str], name: str) -> np.ndarray:
    """``batch.dataset[name]`` over ``dims`` (the first batch's order), flattened in C order."""
    return np.asarray(batch.dataset[name].transpose(*dims).values).ravel()


def _label_view(batch: BatchFitResult) -> SimpleNamespace:
    """What `fit_label` reads of a fit, from a batch: its model, fixed values (the same in every
    spectrum), user bounds."""
    ds = batch.dataset
    names = [str(p) for p in ds["param"].values]
    fixed = {n: bool(f) for n, f in zip(names, ds["fixed"].values)}
    first = ds["value"].transpose("param", *batch.dims).values.reshape(len(names), -1)[:, 0]
    return SimpleNamespace(model=batch.model, values={n: float(v) for n, v in zip(names, first)}, fixed=fixed, bounds=batch.user_bounds())


def _refuse_other_data(batches: Sequence[BatchFitResult]) -> None:
    """`FitsNotComparable` unless every batch is of the same spectra (dimensions, sizes, labels,
    frequencies and impedances, `data_difference`) with the same weighting; a shared (joint) fit,
    whose spectra share parameters, has no per-spectrum AIC to compare."""
    for i, b in enumerate(batches):
        if isinstance(b, SharedFitResult):
            raise FitsNotComparable(f"fits[{i}] ({b.model}) is a shared fit: its spectra share parameters, so it has no AIC of its own per spectrum; compare batches of independent fits (fit without shared=)")
    ref = batches[0]
    dims = ref.dims
    for i, b in enumerate(batches[1:], 1):
        which = f"fits[0] ({ref.model}) and fits[{i}] ({b.model})" if b.model != ref.model else f"fits[0] and fits[{i}] (both {b.model})"
        if set(b.dims) != set(dims) or any(b.dataset.sizes[d] != ref.dataset.sizes[d] for d in dims):
            def shape(x):
                return " × ".join(f"{d} ({x.dataset.sizes[d]})" for d in x.dims)
            raise FitsNotComparable(f"{which} were fitted to different spectra: {shape(ref)} against {shape(b)}; compare batches of the same spectra")
        for d in dims:
            ours, theirs = (x.dataset[d].values.tolist() if d in x.dataset.coords else None for x in (ref, b))
            if ours != theirs:
                raise FitsNotComparable(f"{which} were fitted to different spectra: their labels along {d} differ ({ours[:5] if ours else 'none'} against {theirs[:5] if theirs else 'none'}); compare batches of the same spectra")
        z_ref = ref.dataset["Z"].transpose(*dims, "frequency").values.reshape(ref.n_spectra, -1)
        z = b.dataset["Z"].transpose(*dims, "frequency").values.reshape(b.n_spectra, -1)
        f_ref, f = ref.dataset["frequency"].values, b.dataset["frequency"].values
        for s, key in enumerate(_keys(ref)):
            difference = data_difference(f, z[s], f_ref, z_ref[s])
            if difference is not None:
                raise FitsNotComparable(f"{which} were fitted to different data: at {key}, {difference} (fmin/fmax or another file?); compare batches of the same spectra")
        if b.weighting != ref.weighting:
            raise weightings_differ(ref, i, b)


def _labels(batch: BatchFitResult) -> list[dict]:
    """Each spectrum's labels ({dimension: label}, as its JSON rows give them), in C order
    (`BatchFitResult.spectrum_keys`)."""
    return [labels for _, labels in batch.spectrum_keys()]


def _keys(batch: BatchFitResult) -> list[str]:
    """Each spectrum's `labels_key` ("cycle=64, cell=a": what its warnings are filed under), in C order."""
    return [key for key, _ in batch.spectrum_keys()]


def compare_batches(batches: Sequence[BatchFitResult]) -> "BatchComparison":
    """`compare` of batches of fits to the same spectra (`compare` calls it when given batches).

    For each spectrum the single comparison's criteria (`criteria`: AIC, AICc, BIC; ΔAIC and
    Akaike weights, `akaike_weights`), and for each model the number of spectra it is best on by
    AIC and its AIC summed over the spectra (`SUM_NOTE`: the joint AIC of independent spectra is
    the sum) with that sum's Δ and Akaike weight, and its median ΔAIC. A batch over the same
    dimensions in another order (a stack transposed) is lined up with the first
    (`BatchFitResult.transpose`); its labels must match. Fewer than two batches
    is a `FitsNotComparable`; one batch is a comparison of one model, as `compare` of one fit: each
    spectrum's criteria and their sum, nothing ranked (its report says so)."""
    batches = list(batches)
    if not batches:
        raise FitsNotComparable("compare of batches needs at least one batch of fits: got none")
    _refuse_other_data(batches)
    ref = batches[0]
    dims = ref.dims
    # the same dimensions in another order (a stack transposed): lined up with the first batch,
    # so that a spectrum's position, key and warnings are the same in every batch
    batches = [b.transpose(*dims) for b in batches]
    n_points = int(ref.dataset.sizes["frequency"])
    labels = unique_labels([fit_label(_label_view(b)) for b in batches])
    columns: dict[str, list[np.ndarray]] = {c: [] for c in PER_SPECTRUM_CRITERIA}
    forms = set()
    for b in batches:
        k = int((~b.dataset["fixed"].values.astype(bool)).sum())
        chi2, aic, bic = (_spectra_flat(b, dims, v).astype(float) for v in ("chi2", "aic", "bic"))
        ics = [criteria(SpectrumStatistics(n_points, k, *values, b.weighting)) for values in zip(chi2, aic, bic)]
        forms |= {c["aic_form"] for c in ics}
        columns["rms_rel"].append(_spectra_flat(b, dims, "rms_rel").astype(float))
        columns["chi2"].append(chi2)
        columns["chi2_red"].append(_spectra_flat(b, dims, "chi2_red").astype(float))
        for name in ("aic", "aicc", "bic"):
            columns[name].append(np.array([c[name] for c in ics]))
        columns["converged"].append(_spectra_flat(b, dims, "converged").astype(bool))
    aic = np.array(columns["aic"])  # (model, spectrum)
    delta, weight = np.full(aic.shape, math.nan), np.full(aic.shape, math.nan)
    for s in range(aic.shape[1]):
        delta[:, s], weight[:, s] = akaike_weights(aic[:, s])
    columns["delta_aic"], columns["akaike_weight"] = list(delta), list(weight)
    shape = tuple(ref.dataset.sizes[d] for d in dims)
    coords = {d: ref.dataset[d].values for d in dims if d in ref.dataset.coords}
    data = {c: (("model", *dims), np.array(v).reshape(len(batches), *shape)) for c, v in columns.items()}
    with np.errstate(invalid="ignore"):
        aic_sum = aic.sum(axis=1)
    delta_sum, weight_sum = akaike_weights(aic_sum)
    data.update(
        circuit=("model", [b.model for b in batches]), n_params=("model", [int((~b.dataset["fixed"].values.astype(bool)).sum()) for b in batches]),
        aic_sum=("model", aic_sum), delta_aic_sum=("model", delta_sum), akaike_weight_sum=("model", weight_sum),
    )
    ds = xr.Dataset(data, coords={"model": labels, **coords}, attrs={"aic_form": forms.pop() if len(forms) == 1 else "mixed", "weighting": ref.weighting, "note": SUM_NOTE})
    ds["rms_rel"].attrs["units"] = "1"
    return BatchComparison(tuple(batches), ds)


def _lead_text(model: dict) -> str:
    """A model's lead over its wins as the report prints it: ``372 (152–527)``, ``—`` without
    a lead (no wins, or only rivals that reduce to it)."""
    if model["lead_median"] is None:
        return "—"
    return f"{model['lead_median']:.1f} ({model['lead_min']:.1f}–{model['lead_max']:.1f})"


@dataclass(frozen=True, eq=False)
class BatchComparison(FrozenResult):
    """Several models compared over the same spectra: ``dataset`` holds each spectrum's
    `PER_SPECTRUM_CRITERIA` over (model, *the batches' dimensions), and per model ``circuit``,
    ``n_params`` and ``aic_sum`` (`SUM_NOTE`), with its ``delta_aic_sum`` and
    ``akaike_weight_sum``. The best model has the lowest summed AIC; ``batches`` are the fits,
    in the order given, each over the first one's dimension order (`BatchFitResult.transpose`).
    Immutable."""

    __repr__ = concise_repr
    __str__ = report_text  # (print(result): its report)

    batches: tuple[BatchFitResult, ...]
    dataset: xr.Dataset

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def source(self) -> str | None:
        """Where the data came from (`common_source` of the batches): what `impedax.write_result` records."""
        return common_source(self.batches)

    @property
    def labels(self) -> list[str]:
        """Each model's label (`fit_label`: its text, with its fixed values and bounds)."""
        return [str(m) for m in self.dataset["model"].values]

    @property
    def dims(self) -> tuple[str, ...]:
        return self.batches[0].dims

    @property
    def n_spectra(self) -> int:
        return self.batches[0].n_spectra

    @property
    def best_index(self) -> int:
        """Position of the model with the lowest summed AIC; of sums tied to the solver's
        tolerance (`criteria_tie` over all n = 2N·spectra values: two writings of one impedance
        function), the one with fewer free parameters, then the first given, as
        `Comparison.best_index`: not the solver's rounding."""
        aic = np.where(np.isnan(self.dataset["aic_sum"].values), np.inf, self.dataset["aic_sum"].values)
        low = int(np.argmin(aic))
        if not np.isfinite(aic[low]):
            return low
        n = 2 * int(self.batches[0].dataset.sizes["frequency"]) * self.n_spectra
        chi2 = self._per_spectrum("chi2").sum(axis=1)
        form = self.dataset.attrs["aic_form"]
        tied = [m for m in range(aic.size) if np.isfinite(aic[m]) and criteria_tie(float(aic[m]), float(aic[low]), form, float(max(chi2[m], chi2[low])), n)]
        k = self.dataset["n_params"].values
        return min(tied, key=lambda m: (int(k[m]), m))

    @property
    def best(self) -> str:
        return self.batches[self.best_index].model

    def _per_spectrum(self, name: str) -> np.ndarray:
        """``dataset[name]`` as (model, spectrum), spectra in C order."""
        return self.dataset[name].transpose("model", *self.dims).values.reshape(len(self.batches), -1)

    def _reduces_to_winner(self, best: np.ndarray) -> np.ndarray:
        """(model, spectrum): whether model m reduces to that spectrum's winner, as
        `Comparison.reduces_to_best_indices` decides for one spectrum: m contains the winner
        (`nested_as_held`, more free parameters) and their F-test, F = ((χ²_s − χ²_c)/Δk)/(χ²_c/(n − k_c)),
        n = 2N, gives F ≤ `NOISE_F` (its extra parameters, e.g. a CPE's α on its bound 1, lower χ²
        no more than noise alone would). Its ΔAIC is then the 2 per parameter AIC charges, not
        a rival's."""
        chi2 = self._per_spectrum("chi2")
        k = self.dataset["n_params"].values
        n = 2 * int(self.batches[0].dataset.sizes["frequency"])
        out = np.zeros(chi2.shape, bool)
        for w in range(len(self.batches)):
            for m in range(len(self.batches)):
                if m == w or k[m] <= k[w] or not _nested(self.batches[w], self.batches[m]):
                    continue
                with np.errstate(divide="ignore", invalid="ignore"):
                    f_value = np.maximum(chi2[w] - chi2[m], 0.0) / (k[m] - k[w]) / (chi2[m] / (n - k[m]))
                out[m] |= (best == w) & (f_value <= NOISE_F)
        return out

    def _winners(self) -> tuple[np.ndarray, np.ndarray]:
        """Each spectrum's best model by AIC (its position; −1 when no model has a finite AIC)
        and the runner-up's ΔAIC (NaN with one model). Of AICs tied with the spectrum's lowest
        to the solver's tolerance (`criteria_tie` over its n = 2N values: two writings of one
        impedance function), the one with fewer free parameters, then the first given, as
        `best_index` picks of the sums: not the solver's rounding, which split such a pair's
        wins between them."""
        aic = np.where(np.isnan(self._per_spectrum("aic")), np.inf, self._per_spectrum("aic"))
        finite = np.isfinite(aic).any(axis=0)
        lowest = np.argmin(aic, axis=0)
        spectra = np.arange(aic.shape[1])
        chi2 = self._per_spectrum("chi2")
        n = 2 * int(self.batches[0].dataset.sizes["frequency"])
        with np.errstate(invalid="ignore"):
            tied = np.isfinite(aic) & criteria_tie(aic, aic[lowest, spectra][None, :], self.dataset.attrs["aic_form"], np.maximum(chi2, chi2[lowest, spectra][None, :]), n)
        models = np.arange(len(self.batches))
        order = np.where(tied, self.dataset["n_params"].values[:, None] * len(self.batches) + models[:, None], np.iinfo(np.int64).max)  # (fewer parameters, then the order given)
        best = np.where(finite, np.argmin(order, axis=0), -1)
        delta = self._per_spectrum("delta_aic")
        runner_up = np.full(best.shape, math.nan)
        if len(self.batches) > 1:
            masked = np.where(np.arange(len(self.batches))[:, None] == best[None, :], np.inf, np.where(np.isnan(delta), np.inf, delta))
            runner_up = np.where(finite, masked.min(axis=0), math.nan)
        return best, runner_up

    def _same_as_winner(self, best: np.ndarray) -> np.ndarray:
        """(model, spectrum): whether model m's fit of that spectrum is the winner's fit, as
        `comparison._same_fit` decides for one spectrum: as many parameters, χ² within 1e-6
        (relative) and model spectra within `SAME_FIT_RMS` of their misfit rms_rel (or 1e-9):
        two writings of one impedance function (``R0 + R1 || C1`` and ``R1 || C1 + R0``), whose
        ΔAIC ≈ 0 is rounding, not a rival's lead."""
        chi2, rms, k = self._per_spectrum("chi2"), self._per_spectrum("rms_rel"), self.dataset["n_params"].values
        out = np.zeros(chi2.shape, bool)
        z_data = self.batches[0].dataset["Z"].transpose(*self.dims, "frequency").values.reshape(chi2.shape[1], -1)
        z_models = [b.dataset["Z_model"].transpose(*self.dims, "frequency").values.reshape(chi2.shape[1], -1) for b in self.batches]
        for w in range(len(self.batches)):
            for m in range(len(self.batches)):
                if m == w or k[m] != k[w]:
                    continue
                with np.errstate(all="ignore"):
                    close = np.abs(chi2[m] - chi2[w]) <= 1e-6 * np.maximum(np.maximum(chi2[m], chi2[w]), 1e-300)
                    apart = np.sqrt(np.mean(np.abs((z_models[m] - z_models[w]) / np.abs(z_data)) ** 2, axis=-1))
                out[m] |= (best == w) & close & (apart < np.maximum(SAME_FIT_RMS * np.maximum(rms[m], rms[w]), 1e-9))
        return out

    def _leads(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each spectrum's winner (as `_winners`), the reduces-to mask (`_reduces_to_winner`)
        and the winner's lead: the ΔAIC of the nearest rival that neither reduces to it nor is
        its own fit in another writing (`_same_as_winner`; inf when every rival is one of those;
        NaN with one model or no finite AIC)."""
        best, runner_up = self._winners()
        reduces = self._reduces_to_winner(best)
        delta = self._per_spectrum("delta_aic")
        rival = np.where((np.arange(len(self.batches))[:, None] == best[None, :]) | reduces | self._same_as_winner(best) | np.isnan(delta), np.inf, delta)
        lead = np.where(np.isnan(runner_up), math.nan, rival.min(axis=0))
        return best, reduces, lead

    def not_at_optimum(self) -> list[dict]:
        """The pairs where a model fits some spectra worse than a model it contains (`nested_as_held`):
        ``complex`` and ``simple`` (labels), ``spectra`` (how many: its χ² above the smaller
        model's by more than the solver's tolerance, `comparison.NESTED_WORSE_REL`, or than the
        fall a bound takes for none, `BOUND_CHI2_FRACTION` of its reduced χ², where one of its
        parameters the smaller model lacks sits at a bound, as the single comparison's F-test
        reads it), ``worst_chi2_ratio`` and ``note``. Its fits there did not reach their optimum,
        which is at most the smaller model's: ``fit(LARGER, data, init=smaller_batch)`` starts
        each spectrum there too (``impedax compare`` does so itself)."""
        chi2, chi2_red = self._per_spectrum("chi2"), self._per_spectrum("chi2_red")
        k = self.dataset["n_params"].values
        out = []
        for c, big in enumerate(self.batches):
            names = [str(p) for p in big.dataset["param"].values]
            at_bound = big.dataset["at_bound"].transpose("param", *self.dims).values.reshape(len(names), -1)
            for s, small in enumerate(self.batches):
                if s == c or k[c] <= k[s] or not _nested(small, big):
                    continue
                small_names = [str(p) for p in small.dataset["param"].values]
                small_at_bound = small.dataset["at_bound"].transpose("param", *self.dims).values.reshape(len(small_names), -1)
                extra_at_bound = np.zeros(chi2.shape[1], bool)  # (`boundary_parameters`: at a bound the smaller model does not hold it at)
                for j, n in enumerate(names):
                    held = small_at_bound[small_names.index(n)].astype(bool) if n in small_names else np.zeros(chi2.shape[1], bool)
                    extra_at_bound |= at_bound[j].astype(bool) & ~held
                excess = np.where(extra_at_bound, np.maximum(NESTED_WORSE_REL * chi2[s], BOUND_CHI2_FRACTION * chi2_red[c]), NESTED_WORSE_REL * chi2[s])
                with np.errstate(invalid="ignore"):
                    worse = chi2[c] - chi2[s] > excess
                if worse.any():
                    ratio = float(np.max(chi2[c][worse] / chi2[s][worse]))
                    count = int(worse.sum())
                    out.append({"complex": self.labels[c], "simple": self.labels[s], "spectra": count, "worst_chi2_ratio": ratio,
                                "note": f"{self.labels[c]} fits worse than {self.labels[s]}, which it contains, on {count} of {self.n_spectra} spectra (χ² up to {ratio:.4g}×): "
                                        f"its fits there did not reach their optimum; fit it with init= the {self.labels[s]} batch to start each spectrum there too (impedax compare does so)"})
        return out

    def models(self) -> list[dict]:
        """Per model: ``model``, ``label``, ``n_params``, ``wins`` (spectra it is best on by AIC;
        a tie to the solver's tolerance goes to the fewer parameters, then the first given, `_winners`),
        ``weak_wins`` (of those, the ones where a rival that does not reduce to it,
        `_reduces_to_winner`, is less than `WEAK_DELTA_AIC` behind), ``decisive_wins`` (every such
        rival at least `DECISIVE_DELTA_AIC` behind: essentially no support, Burnham & Anderson
        2002, §2.6; a win with no such rival, every rival reducing to it or its fit in another
        writing (`_same_as_winner`), is not decisive: it is
        counted in ``wins_over_reducing_only``), ``lead_median``, ``lead_min``, ``lead_max``
        (the lead over its wins, `_leads`; null without wins or where only reducing rivals
        trail), ``aic_sum`` with ``delta_aic_sum`` and ``akaike_weight_sum``,
        ``median_delta_aic``, ``converged_fraction`` and ``rms_rel_median``."""
        best, _, lead = self._leads()
        delta, rms, converged = self._per_spectrum("delta_aic"), self._per_spectrum("rms_rel"), self._per_spectrum("converged")
        ds = self.dataset
        out = []
        for m, label in enumerate(self.labels):
            mine = best == m
            leads = lead[mine & np.isfinite(lead)]
            out.append({
                "model": str(ds["circuit"].values[m]), "label": label, "n_params": int(ds["n_params"].values[m]),
                "wins": int(mine.sum()), "weak_wins": int((mine & (lead < WEAK_DELTA_AIC)).sum()), "decisive_wins": int((mine & np.isfinite(lead) & (lead >= DECISIVE_DELTA_AIC)).sum()),
                "wins_over_reducing_only": int((mine & np.isinf(lead)).sum()),
                "lead_median": float(np.median(leads)) if leads.size else None, "lead_min": float(leads.min()) if leads.size else None, "lead_max": float(leads.max()) if leads.size else None,
                "aic_sum": float(ds["aic_sum"].values[m]), "delta_aic_sum": float(ds["delta_aic_sum"].values[m]), "akaike_weight_sum": float(ds["akaike_weight_sum"].values[m]),
                "median_delta_aic": float(np.nanmedian(delta[m])) if np.isfinite(delta[m]).any() else math.nan,
                "converged_fraction": float(np.mean(converged[m])), "rms_rel_median": float(np.nanmedian(rms[m])),
                "spectra_with_warnings": sum(1 for ws in self.batches[m].warnings.values() if ws),
            })
        return out

    def spectra(self) -> list[dict]:
        """Per spectrum: its labels along every batch dimension (as a batch's JSON rows:
        each dimension, then ``labels``), ``best`` and ``best_label`` (by AIC; None when no
        model has a finite AIC), ``runner_up_delta_aic``, ``reduces_to_best`` (the labels of the
        models that reduce to the best, `_reduces_to_winner`: their ΔAIC is AIC's charge for
        parameters that do nothing), ``same_fit_as_best`` (the labels of the models whose fit is
        the best one's in another writing, `_same_as_winner`), ``lead`` (the nearest other
        rival's ΔAIC; null when every rival is one of those), ``weak_evidence`` (that lead below `WEAK_DELTA_AIC`) and
        ``models``: each model's `PER_SPECTRUM_CRITERIA` with its ``model``, ``label``,
        ``misses_structure`` (`BatchFitResult.misses_structure` on that spectrum, as a batch fit's
        rows) and ``warnings`` (its fit's warnings on that spectrum,
        `BatchFitResult.warnings`; [] if none) with their ``warning_tags``, in their order
        (`BatchFitResult.spectrum_warning_tags`, as a batch fit's rows give them)."""
        best, runner_up = self._winners()
        _, reduces, lead = self._leads()
        same = self._same_as_winner(best)
        values = {c: self._per_spectrum(c) for c in PER_SPECTRUM_CRITERIA}
        warned = [[list(batch.warnings.get(key, ())) for key in _keys(batch)] for batch in self.batches]
        tags = [[[list(t) for t in batch.spectrum_warning_tags(key)] for key in _keys(batch)] for batch in self.batches]
        misses = [batch.misses_structure.transpose(*batch.dims).values.reshape(-1) for batch in self.batches]  # (C order, as `_labels`)
        rows = []
        for s, labels in enumerate(_labels(self.batches[0])):
            b = int(best[s])
            rows.append({
                **labels, "labels": labels,
                "best": self.batches[b].model if b >= 0 else None, "best_label": self.labels[b] if b >= 0 else None,
                "runner_up_delta_aic": float(runner_up[s]), "reduces_to_best": [self.labels[m] for m in np.flatnonzero(reduces[:, s])],
                "same_fit_as_best": [self.labels[m] for m in np.flatnonzero(same[:, s])],
                "lead": float(lead[s]) if np.isfinite(lead[s]) else None, "weak_evidence": bool(lead[s] < WEAK_DELTA_AIC),
                "models": [{"model": batch.model, "label": label, **{c: (bool(values[c][m, s]) if c == "converged" else float(values[c][m, s])) for c in PER_SPECTRUM_CRITERIA},
                            "misses_structure": bool(misses[m][s]), "warnings": warned[m][s], "warning_tags": tags[m][s]}
                           for m, (batch, label) in enumerate(zip(self.batches, self.labels))],
            })
        return rows

    def summary(self) -> dict:
        """The JSON of ``impedax compare --json`` for several spectra: ``models`` (`models`),
        ``spectra`` (`spectra`), ``best``/``best_label`` (lowest summed AIC), ``ranked_by``
        ("aic_sum"), ``aic_form`` (`criteria`), ``weighting``, ``sizes`` (dimension → number of
        spectra), ``n_spectra``, ``weak_spectra`` (spectra whose winner leads by less than
        `WEAK_DELTA_AIC`), ``note`` (`SUM_NOTE`) and ``not_at_optimum`` (`not_at_optimum`: models
        that fit some spectra worse than a model they contain) and ``warnings``
        (each model's distinct warnings over the spectra, "LABEL: warning", `labelled_warnings`;
        which spectra: ``spectra[].models[].warnings``)."""
        spectra = self.spectra()
        return {
            "models": self.models(), "spectra": spectra, "best": self.best, "best_label": self.labels[self.best_index], "ranked_by": "aic_sum",
            "aic_form": self.dataset.attrs["aic_form"], "weighting": self.dataset.attrs["weighting"], "dims": list(self.dims),
            "sizes": {d: int(self.dataset.sizes[d]) for d in self.dims}, "n_spectra": self.n_spectra,
            "weak_spectra": sum(r["weak_evidence"] for r in spectra), "weak_threshold": WEAK_DELTA_AIC, "note": SUM_NOTE,
            "not_at_optimum": self.not_at_optimum(),
            "best_misfit_hints": self.best_misfit_hints(),  # (None unless a winner still misses structure, small as its misfit looks)
            # (each model's distinct warnings over the spectra, as a batch fit's JSON, with its label)
            "warnings": labelled_warnings((label, sorted({w for ws in batch.warnings.values() for w in ws})) for batch, label in zip(self.batches, self.labels)),
        }

    def best_misfit_hints(self) -> dict | None:
        """The spectra whose winner (by its own AIC) misses structure the data hold, small as
        its misfit looks, as `Comparison.best_misfit_hint` says it of one spectrum: weighted by
        |Z|, rms_rel from `MISFIT_HINT_FROM` (0.2 %) to `MISFIT_CHECKED_FROM` (2 %, where each
        fit's own warning takes over) and above `MISFIT_RATIO_MAX` (5) × what the Kramers–Kronig
        test's Voigt chain reaches on that spectrum (`misfit_hint_spectra`: the chain fitted for
        those spectra only). None when there is none. Keys: ``spectra`` (how many),
        ``by_model`` (winner label → how many), ``worst`` (``labels``, ``model`` (label),
        ``rms_rel``, ``chain_rms_rel``, ``ratio``: the spectrum of the largest ratio), ``note``
        (the report's line) and ``labels`` (every such spectrum's labels, in the batch's order,
        which the note names too; as `BatchFitResult.misfit_hints`)."""
        if self.dataset.attrs["weighting"] != "modulus" or "Z" not in self.batches[0].dataset:
            return None
        best, _ = self._winners()
        rms = self._per_spectrum("rms_rel")
        winner_rms = np.where(best >= 0, rms[np.maximum(best, 0), np.arange(rms.shape[1])], np.nan)
        data = self.batches[0].dataset
        z = data["Z"].transpose(*self.dims, "frequency").values.reshape(rms.shape[1], -1)
        rows, ratio, chain = misfit_hint_spectra(data["frequency"].values, z, winner_rms)
        if not rows.size:
            return None
        worst = int(np.argmax(ratio))
        labels = _labels(self.batches[0])[rows[worst]]
        by_model = {self.labels[m]: int(np.sum(best[rows] == m)) for m in np.unique(best[rows])}
        where = ", ".join(f"{d}={v}" for d, v in labels.items())
        hinted = [_labels(self.batches[0])[i] for i in sorted(rows.tolist())]
        note = (f"the best model misses structure the data hold on {len(rows)} of {self.n_spectra} spectra ({spectra_named(hinted)}), small as the misfits look "
                f"(rms_rel below {MISFIT_CHECKED_FROM * 100:g} % and over {MISFIT_RATIO_MAX:g}× what a Kramers–Kronig-consistent model reaches: "
                + ", ".join(f"{label} on {n}" for label, n in by_model.items())
                + f"); the worst, {where}: {self.labels[best[rows[worst]]]} at {winner_rms[rows[worst]] * 100:.3g} %, {ratio[worst]:.3g}× the chain's {chain[worst] * 100:.3g} % "
                "(a diagnosis of that spectrum shows where and what)")
        return {"spectra": int(len(rows)), "by_model": by_model,
                "worst": {"labels": labels, "model": self.labels[best[rows[worst]]], "rms_rel": float(winner_rms[rows[worst]]), "chain_rms_rel": float(chain[worst]), "ratio": float(ratio[worst])},
                "note": note, "labels": hinted}

    def to_table(self) -> list[dict]:
        """One row per spectrum and model (``compare --out FILE.csv``): the spectrum's labels,
        ``model`` (the label), ``circuit``, `PER_SPECTRUM_CRITERIA` and ``best`` (whether it is
        that spectrum's best by AIC), then ``warnings`` (that fit's warnings joined by "; ", as
        `spectra`' list; "" if none) and ``misses_structure`` (`spectra`')."""
        best, _ = self._winners()
        return [{**{d: v for d, v in r["labels"].items()}, **{k: v for k, v in m.items() if k not in ("model", "label", "warnings", "misses_structure")}, "model": m["label"], "circuit": m["model"], "best": bool(best[s] == j), "warnings": "; ".join(m["warnings"]),
                 "misses_structure": m["misses_structure"]}  # (last, after the columns readers count by position)
                for s, r in enumerate(self.spectra()) for j, m in enumerate(r["models"])]

    def to_xarray(self) -> xr.Dataset:
        """``dataset`` (the criteria over (model, *dims), the sums over model) and each batch of
        fits in full (`BatchFitResult.to_xarray`, its variables, dimensions other than the
        batch's and ``frequency``, and attributes named `BATCH_PREFIX` + its own: ``batch0_value``
        over ``batch0_param``, ...), ``impedax_kind`` "batch_comparison":
        `BatchComparison.from_xarray` reads it back."""
        keep = {*self.dims, "frequency"}
        parts = [self.dataset.copy(deep=True)]
        for i, batch in enumerate(self.batches):
            prefix = BATCH_PREFIX.format(i)
            saved = batch.to_xarray()
            renamed = saved.rename({n: prefix + str(n) for n in (*saved.variables, *saved.dims) if n not in keep})
            renamed.attrs = {prefix + k: v for k, v in saved.attrs.items() if k != NETCDF_ADVICE}  # (the comparison's Dataset names how it is written)
            parts.append(renamed)
        out = xr.merge(parts, combine_attrs="drop", join="exact", compat="identical")
        return result_dataset(out.assign_attrs({**self.dataset.attrs, **{k: v for part in parts[1:] for k, v in part.attrs.items()}, "impedax_kind": "batch_comparison", "n_batches": len(self.batches)}))

    @classmethod
    def from_xarray(cls, ds: xr.Dataset, *, registry=None) -> "BatchComparison":
        """Rebuild a comparison from `BatchComparison.to_xarray` output: as returned, read back by
        `impedax.io.read_netcdf`, or opened as stored (``xr.open_dataset`` of a file
        `impedax.write_result` or ``impedax compare ... --out FILE.nc`` wrote); each batch as its
        own ``from_xarray`` rebuilds it (``registry``: the one the circuits' elements are in).
        A file that is not a complete saved comparison of batches raises one `DataError` naming it."""
        from ..io.netcdf import damaged_result, saved_result  # (io is imported only here: rarely needed)

        ds = saved_result(ds, "batch_comparison", variables=(*PER_SPECTRUM_CRITERIA, "circuit", "n_params", "aic_sum"), attrs=("n_batches", "aic_form"))
        with damaged_result("batch_comparison", ds):
            batches = []
            for i in range(int(ds.attrs["n_batches"])):
                prefix = BATCH_PREFIX.format(i)
                own = [n for n in ds.data_vars if str(n).startswith(prefix)]
                if not own:
                    raise ValueError(f"no batch of fits stored under {prefix!r}")
                one = ds[own]
                one = one.rename({n: str(n)[len(prefix):] for n in (*one.variables, *one.dims) if str(n).startswith(prefix)})
                one.attrs = {k[len(prefix):]: v for k, v in ds.attrs.items() if k.startswith(prefix)}
                if "source" in ds.attrs or "saved_from" in ds.attrs:  # (the data's file, which `write_result` records once)
                    one.attrs.update({k: ds.attrs[k] for k in ("source", "saved_from") if k in ds.attrs})
                one.encoding["source"] = ds.encoding.get("source")
                kind = SharedFitResult if one.attrs.get("impedax_kind") == SharedFitResult._KIND else BatchFitResult
                batches.append(kind.from_xarray(one, registry=registry))
            own = [n for n in ds.data_vars if not any(str(n).startswith(BATCH_PREFIX.format(i)) for i in range(len(batches)))]
            dataset = ds[own].drop_vars([c for c in ds[own].coords if c not in ("model", *batches[0].dims)])
            dataset.attrs = {k: v for k, v in ds.attrs.items() if k in _COMPARISON_ATTRS}
            return cls(tuple(batches), dataset)

    @labels_by_keyword
    def comparison_of(self, **labels) -> Comparison:
        """The single-spectrum `Comparison` (F-tests, warnings, notes) of the spectrum with
        ``labels`` (one per batch dimension, as `BatchFitResult.fit_of`): each batch's
        `fit_of` that spectrum, compared. Labels by keyword only (`labels_by_keyword`)."""
        return compare([b.fit_of(**labels) for b in self.batches])

    def report(self, *, each_spectrum_where: str = EACH_SPECTRUM_WHERE) -> str:
        """The models' table (k, wins, summed AIC with its Δ and weight, median ΔAIC,
        converged, median rms_rel), the summed AIC's note, then up to `SPECTRA_AS_ROWS` spectra
        one row each (the best, the runner-up's ΔAIC, each model's ΔAIC); beyond, where each
        spectrum's is (``each_spectrum_where``: the command line names its options)."""
        models = self.models()
        width = column_width(self.labels, "model")
        noun = "spectrum" if self.n_spectra == 1 else "spectra"
        sizes = " × ".join(f"{d} ({self.dataset.sizes[d]})" for d in self.dims)
        alone = " (one model: nothing is ranked; its wins and weight are those of a model without rivals)" if len(models) == 1 else ""
        lines = [f"comparison of {len(models)} {'model' if len(models) == 1 else 'models'} over {self.n_spectra} {noun} ({sizes}), weighting {self.dataset.attrs['weighting']}{alone}", ""]
        leads = [_lead_text(m) for m in models]
        lead_width = column_width(leads, "lead: median (range)")
        lines.append(f"{'model':<{width}}  {'k':>2}  {'wins':>9}  {'decisive':>8}  {'lead: median (range)':<{lead_width}}  {'ΣAIC':>11}  {'ΔΣAIC':>9}  {'weight':>6}  {'converged':>9}  {'median rms_rel':>14}")
        best = self.best_index
        rms = format_percent_column([m["rms_rel_median"] for m in models])  # (3 significant digits, the decimal points lined up)
        for i, (m, lead, percent) in enumerate(zip(models, leads, rms)):
            wins = f"{m['wins']}/{self.n_spectra}"
            line = (f"{m['label']:<{width}}  {m['n_params']:>2}  {wins:>9}  {m['decisive_wins']:>8}  {lead:<{lead_width}}  {m['aic_sum']:>11.2f}  {m['delta_aic_sum']:>9.2f}  {m['akaike_weight_sum']:>6.3f}  "
                    f"{m['converged_fraction'] * 100:>7.0f} %  {percent:>12} %")
            lines.append(line + ("   ← best by summed AIC" if i == best else ""))
        lines += ["", SUM_NOTE + f"; wins count the spectra each model is best on by its own AIC; its lead there is the ΔAIC of the nearest rival "
                  f"that neither reduces to it nor is its fit in another writing (— where no rival is left), decisive from {DECISIVE_DELTA_AIC:g} (Burnham & Anderson 2002: essentially no support for the rival)"]
        reduced = self._reduced_lines()
        lines += reduced + [pair["note"] for pair in self.not_at_optimum()]
        hints = self.best_misfit_hints()
        if hints is not None:
            lines.append(hints["note"])
        weak = [m for m in models if m["weak_wins"]]
        if weak:
            lines.append(f"won by less than ΔAIC {WEAK_DELTA_AIC:g} (the data barely tell the models apart there): " + ", ".join(f"{m['weak_wins']} of {m['label']}'s {m['wins']}" for m in weak))
        warned = [m for m in models if m["spectra_with_warnings"]]
        if warned:
            lines.append("fits with warnings: " + ", ".join(f"{m['label']} on {m['spectra_with_warnings']} {'spectrum' if m['spectra_with_warnings'] == 1 else 'spectra'}" for m in warned) + f" (each batch's report() lists them; from the command line, {FIT_COMMAND_WORDS})")
        if self.n_spectra <= SPECTRA_AS_ROWS:
            lines += ["", *self._spectrum_lines()]
        else:
            lines += ["", f"each spectrum's winner and criteria: {each_spectrum_where}"]
        return "\n".join(lines)

    def _reduced_lines(self) -> list[str]:
        """A line per (model, winner) pair where the model is the winner's fit in another
        writing on some spectra (`_same_as_winner`) and where it reduces to the winner
        (`_reduces_to_winner`), as the single comparison's `Comparison.reduces_to_best` says it."""
        best, reduces, _ = self._leads()
        kinds = (
            (self._same_as_winner(best), "is the same fit as {winner} on {spectra} (two writings of one impedance function: as many parameters, the same χ² and model "
                                         "spectrum): not a rival; such a tie goes to the fewer parameters, then the first given"),
            (reduces, "reduces to {winner} on {spectra}: its extra parameters lower χ² no more than noise alone would (e.g. a CPE's α on its bound 1), so its ΔAIC "
                      "there is the 2 per parameter AIC charges, not a rival's lead"),
        )
        lines = []
        for mask, text in kinds:
            for m, label in enumerate(self.labels):
                for w, winner in enumerate(self.labels):
                    count = int((mask[m] & (best == w)).sum())
                    if count:
                        lines.append(f"{label} " + text.format(winner=winner, spectra=f"{count} {'spectrum' if count == 1 else 'spectra'}"))
        return lines

    def _spectrum_lines(self) -> list[str]:
        """One row per spectrum: its labels (`labels_key`), the best model, the runner-up's ΔAIC,
        each model's ΔAIC."""
        rows = self.spectra()
        heads = [labels_shown(r["labels"]) for r in rows]
        lead = column_width(heads, "spectrum")
        best_width = column_width((r["best_label"] or "—" for r in rows), "best")
        columns = [f"ΔAIC {i + 1}" for i in range(len(self.labels))]
        lines = ["each spectrum's best model by AIC (ΔAIC i: model i of the table above, in its order; lead: the nearest rival that neither reduces to the best nor is its fit):",
                 f"{'spectrum':<{lead}}  {'best':<{best_width}}  {'lead':>7}  " + "  ".join(f"{c:>8}" for c in columns)]
        for head, r in zip(heads, rows):
            lead_text = "—" if r["lead"] is None else f"{r['lead']:.2f}"
            cells = "  ".join(f"{m['delta_aic']:>8.2f}" for m in r["models"])
            unrivalled = [f"{', '.join(r['same_fit_as_best'])} the same fit"] * bool(r["same_fit_as_best"]) + [f"{', '.join(r['reduces_to_best'])} reduces to it"] * bool(r["reduces_to_best"])
            mark = "   (weak)" if r["weak_evidence"] else ("   (" + "; ".join(unrivalled) + ")" if unrivalled and r["lead"] is None else "")
            lines.append(f"{head:<{lead}}  {(r['best_label'] or '—'):<{best_width}}  {lead_text:>7}  {cells}{mark}")
        return lines

    def _repr_html_(self) -> str:
        """The notebook display: a row per model (label, k, wins, summed AIC, its Δ and weight,
        median ΔAIC) and the summed AIC's note."""
        from ..plotting.html import result_html

        best = self.best_index
        rows = [{"model": m["label"], "k": m["n_params"], "wins": f"{m['wins']}/{self.n_spectra}", "ΣAIC": f"{m['aic_sum']:.2f}", "ΔΣAIC": f"{m['delta_aic_sum']:.2f}",
                 "weight": f"{m['akaike_weight_sum']:.3f}", "median ΔAIC": f"{m['median_delta_aic']:.2f}", "": "← best" if i == best else ""} for i, m in enumerate(self.models())]
        return result_html(f"comparison of {len(rows)} models over {self.n_spectra} spectra: best {self.labels[best]}", rows, lines=[SUM_NOTE])

    def plot(self, *, figsize: tuple[float, float] | None = None):
        """Each model's ΔAIC per spectrum (Figure; `plotting.comparison.plot_batch_comparison`;
        ``figsize`` (width, height) [in])."""
        from ..plotting.comparison import plot_batch_comparison

        return plot_batch_comparison(self, figsize=figsize)


register_batch_compare(compare_batches)


def _nested(small: BatchFitResult, big: BatchFitResult) -> bool:
    """Whether the batch ``big``'s model contains ``small``'s as the two hold their parameters
    (`comparison.nested_as_held`; a held value per spectrum compared spectrum by spectrum)."""

    def held(batch):
        ds = batch.dataset
        return {str(p): ds["value"].sel(param=p).values for p in ds["param"].values if bool(ds["fixed"].sel(param=p).all())}

    return nested_as_held(small.circuit, held(small), big.circuit, held(big), big.registry)
