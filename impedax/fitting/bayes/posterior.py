"""The result of a Bayesian fit: `Posterior`, its summaries, propagation and storage.

A `Posterior` holds the draws of one run of `impedax.sample` and everything needed to read
them again: quantiles and HDI (`Posterior.quantiles`), the ``impedax sample --json`` summary
and the text report, uncertainty propagation to any JAX function of the parameters
(`Posterior.derive`), posterior predictive impedance, and a `to_xarray` / `from_xarray` pair
for netCDF. Figures are drawn by `impedax.plotting.bayes` (imported when asked for).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import Callable, Mapping, Sequence

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from ...circuits import Circuit, DEFAULT_REGISTRY, Registry, compile_circuit, parse
from ...data import checked_frequencies, column_width, concise_repr, exact_number, report_text, unit_text
from ...errors import DataError, ParameterError
from ...io.netcdf import result_dataset
from ..derived import bind_frequency, called, draw_indices, draws_band, needs_freq
from ..least_squares import FitResult
from ..least_squares.branches import left_to_priors
from ..least_squares.result import PARAMETER_UNIT_NAME, bounds_attr, fit_warning_tags, note_value_attrs, shown_stderr, stored_bounds, stored_note_values, without_sample_advice
from ..frozen import FrozenResult, KeyHintDict, freeze_fields
from .chain import capped_at, length_text
from .evidence import EvidenceDoubt, WaicDoubt, evidence_doubt_of_notes, model_comparison_notes_of, short_chain_waic_note, waic_doubts
from .diagnostics import NO_STRAGGLERS, PiledUp, WalkerDraws, Stragglers, chain_warnings, draws_table, figure, interval_warnings, kept_walkers, straggler_warnings, tied_to_bound, walkers_text
from .logprob import NOISE_MODELS, NOISE_TITLES, NoiseModel
from .priors import Prior
from .reparam import Reparametrization, implausible_gap_notes, rebuild

__all__ = ["Posterior", "chain_figures"]

SUMMARY_QUANTILES = ("median", "q05", "q16", "q84", "q95")  # per parameter in the JSON summary

PREDICTIVE_COPIES = 10
"""Noisy copies of each draw in a figure's posterior predictive band: 4,000 samples per frequency
where one copy of 400 draws left the band's edges jagged by their sampling error."""


def checked_copies(copies) -> None:
    """`ParameterError` unless ``copies`` (noisy copies of each draw in a predictive) is a positive integer."""
    if not isinstance(copies, (int, np.integer)) or isinstance(copies, bool) or copies < 1:
        raise ParameterError(f"copies must be a positive integer, got {copies!r}")


def sigma_between(freq, data_frequency, data_sigma) -> np.ndarray:
    """The data's σ [Ω] (…, data frequency) at ``freq``: interpolated in log f, the end values beyond."""
    log_f, log_data_f = np.log(np.asarray(freq, float)), np.log(np.asarray(data_frequency, float))
    sigma = np.asarray(data_sigma, float)
    return np.stack([np.interp(log_f, log_data_f, row) for row in sigma.reshape(-1, sigma.shape[-1])]).reshape(*sigma.shape[:-1], log_f.size)


def with_noise(z: np.ndarray, sigma: np.ndarray, seed: int) -> np.ndarray:
    """``z`` with the likelihood's noise: N(0, σ²) on Re and Im alike, independent draws (``seed``)."""
    rng = np.random.default_rng(seed)
    return z + sigma * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape))


def chain_figures(autocorr: Mapping[str, float], ess: Mapping[str, float], name: str) -> dict[str, float | None]:
    """A table row's ``autocorr`` (τ [steps]) and ``ess`` of parameter ``name``, None where
    unknown (the JSON's null; an empty CSV cell)."""
    known = lambda x: float(x) if math.isfinite(x) else None  # noqa: E731
    return {"autocorr": known(autocorr[name]), "ess": known(ess[name])}


def _quantiles_by_name(q: xr.Dataset, names) -> dict[str, dict[str, float]]:
    return {n: {k: float(q[k].sel(param=n)) for k in SUMMARY_QUANTILES} for n in names}


UNDETERMINED_MARK = "← NOT DETERMINED"
UNDETERMINED_ROWS = ("not determined by the data (the least-squares start's rule: an unidentified group, a relative standard error above 100 %, or a term that vanishes from Z, such as a resistor open at ∞); "
                     "their intervals show where the priors take over, not a measurement: fix one of a group from another measurement, or report what the data fix")
"""The report's mark on a row of `Posterior.undetermined` and the line under its table (of
several rows; one row's: `UNDETERMINED_ROW`)."""
UNDETERMINED_ROW = ("not determined by the data (the least-squares start's rule: an unidentified group, a relative standard error above 100 %, or a term that vanishes from Z, such as a resistor open at ∞); "
                    "its interval shows where the priors take over, not a measurement: fix it (or another of its group) from another measurement, or report what the data fix")
"""`UNDETERMINED_ROWS` of a single row (not "their intervals" of one parameter)."""
EDGE_SET_MARK = "← AT PRIOR EDGE"
EDGE_SET_ROWS = ("their draws pile up against an edge of their prior or bound: that edge, not the data, sets one end of their intervals, "
                 "so their medians are no measurement either; the warnings say which end and what to do, or report only the end the data set")
"""The report's mark on a row of `PiledUp.set_by_prior_edge` the start fit's rule leaves out
(not `UNDETERMINED_MARK`, whose line does not explain a pile-up: REAL
exampleDataGamry.DTA's R0) and the line under its table, of several rows; one
row's: `EDGE_SET_ROW`."""
EDGE_SET_ROW = ("its draws pile up against an edge of its prior or bound: that edge, not the data, sets one end of its interval, "
                "so its median is no measurement either; the warnings say which end and what to do, or report only the end the data set")
"""`EDGE_SET_ROWS` of a single row (REAL exampleDataGamry.DTA's R0 alone, not "their
draws … their intervals … their medians")."""


def fixed_rows(fixed: Mapping[str, float], specs) -> list[dict[str, object]]:
    """`Posterior.to_table`'s rows of the parameters held fixed: the value in every quantile
    column (a point mass), the unit from ``specs``, no τ or ESS, ``fixed`` true."""
    return [{"name": n, **{k: float(v) for k in SUMMARY_QUANTILES}, "unit": specs[n].unit if n in specs else "", "autocorr": None, "ess": None, "undetermined": False, "fixed": True}
            for n, v in fixed.items()]


def marked_rows(undetermined: Sequence[str], set_by_edge: Sequence[str]) -> tuple[dict[str, str], list[str]]:
    """The marks a posterior's report puts on its rows ({name: mark}) and the lines under its
    table: `UNDETERMINED_MARK` on those the start fit's rule leaves undetermined (``undetermined``),
    `EDGE_SET_MARK` on the others whose draws pile up at a prior's or bound's edge (``set_by_edge``,
    `PiledUp.set_by_prior_edge`), each group with its reason."""
    piled = [n for n in set_by_edge if n not in undetermined]
    groups = ((list(undetermined), UNDETERMINED_ROW, UNDETERMINED_ROWS), (piled, EDGE_SET_ROW, EDGE_SET_ROWS))
    lines = [f"← {', '.join(names)}: {one if len(names) == 1 else several}" for names, one, several in groups if names]
    return {**{n: UNDETERMINED_MARK for n in undetermined}, **{n: EDGE_SET_MARK for n in piled}}, lines


def _mark_columns(mark: str | None) -> dict[str, bool]:
    """A table row's columns ``undetermined`` and ``at_prior_edge`` for the report's ``mark`` on it."""
    return {"undetermined": mark == UNDETERMINED_MARK, "at_prior_edge": mark == EDGE_SET_MARK}


def last_at_prior_edge(rows: Sequence[Mapping[str, object]]) -> list[dict[str, object]]:
    """``rows`` with the column ``at_prior_edge`` last (false where a row has none: a fixed
    parameter's): added after ``fixed``, the CSV's columns before it keep their places."""
    return [{**{k: v for k, v in row.items() if k != "at_prior_edge"}, "at_prior_edge": bool(row.get("at_prior_edge", False))} for row in rows]


def with_warning_columns(rows: Sequence[Mapping[str, object]], chain_converged: bool, warnings: Sequence[str]) -> list[dict[str, object]]:
    """``rows`` (a posterior's table) with the columns ``chain_converged`` (the JSON's key) and
    ``warnings`` (joined by "; ", "" if none, as `FitResult.to_table`'s) last, the same on every
    row: a CSV of a short or stuck chain says so (the JSON and netCDF hold the warnings)."""
    warned = "; ".join(warnings)
    return [{**row, "chain_converged": bool(chain_converged), "warnings": warned} for row in rows]


_RUN_COLUMNS = ("at_prior_edge", "chain_converged", "warnings")
"""The table's columns a notebook view leaves out: the mark folded into ``undetermined``, the
run's warnings printed under the table."""


def html_rows(table: Sequence[Mapping[str, object]]) -> list[dict[str, object]]:
    """A notebook view's rows of ``table`` (`Posterior.to_table`'s): the unit as the report writes
    it (Ω) and, in the column ``undetermined``, the report's mark on that row (``at_prior_edge``'s
    folded in); not the run's columns (`with_warning_columns`: the view lists the warnings)."""
    def mark(row) -> str:
        return UNDETERMINED_MARK if row["undetermined"] else EDGE_SET_MARK if row.get("at_prior_edge") else ""

    return [{**{k: v for k, v in row.items() if k not in _RUN_COLUMNS}, "unit": unit_text(row["unit"]), "undetermined": mark(row)} for row in table]


DERIVED_FROM_UNDETERMINED = "its interval shows where the priors take over, not a measurement; fix one of them at a value you know"


@dataclass(frozen=True, eq=False)
class Posterior(WalkerDraws, PiledUp, FrozenResult):
    """Draws from the posterior of a circuit's parameters given one spectrum. Immutable.

    ``draws`` (walker, draw, param) are natural values of the sampled parameters ``names``
    (free circuit parameters, the physical ones of a reparametrization, ``sigma_rel``);
    ``log_prob`` their log-posterior in the sampled space; ``fit`` the least-squares start.
    Diagnostics: ``acceptance`` per walker, ``autocorr`` (integrated autocorrelation time in
    sampler steps), ``ess`` (effective sample size), ``chain_converged``, ``warnings``;
    ``settings`` holds the run's walkers, steps (those that ran), burn, thin, seed and, for
    ``steps="auto"``, ``steps_mode``, ``step_cap`` and ``stopped``; ``stragglers`` the walkers
    whose draws were left out (`find_stragglers`: ``draws``, ``log_prob`` and ``acceptance`` hold
    the other walkers'). Model comparison: ``log_evidence`` (Laplace, at the MAP) and ``waic``
    (deviance scale: lower is better); ``log_evidence_unreliable_reason`` why the log evidence is
    undefined or unreliable (`evidence.EvidenceDoubt`, None when sound: the cause of its note, as
    a value); ``model_comparison_notes`` which of ``notes`` speak only to comparing models (the
    Laplace evidence's and WAIC's).
    """

    __repr__ = concise_repr  # (the generated one printed every array)
    __str__ = report_text  # (print(result): its report)

    circuit: Circuit
    names: tuple[str, ...]
    units: tuple[str, ...]
    log_scale: tuple[bool, ...]
    draws: np.ndarray
    log_prob: np.ndarray
    acceptance: np.ndarray
    priors: dict[str, Prior]
    noise: NoiseModel
    fit: FitResult
    fixed: dict[str, float]
    frequency: np.ndarray
    z_data: np.ndarray
    sigma: np.ndarray | None
    log_evidence: float
    waic: float
    p_waic: float
    map_values: dict[str, float]
    notes: tuple[str, ...] = ()
    settings: dict = field(default_factory=dict)
    reparametrization: Reparametrization | None = None
    registry: Registry | None = field(default=None, repr=False)  # None: the default registry
    user_bounds: dict[str, tuple[float, float]] = field(default_factory=dict)  # sampled circuit parameters' bounds narrowed by the user (`sample(bounds=...)` or init's)
    stragglers: Stragglers = NO_STRAGGLERS  # the run's walkers left out of the draws (`find_stragglers`)
    log_evidence_unreliable_reason: EvidenceDoubt | None = None  # (`LaplaceEvidence.reason`: `impedax.compare` reads it here, not from the notes' words)
    model_comparison_notes: tuple[str, ...] = ()  # the notes of ``notes`` from `laplace_evidence` and `waic` (`impedax gap` picks them out here, not by their words)

    def __post_init__(self):
        object.__setattr__(self, "noise", NoiseModel(self.noise))
        if self.log_evidence_unreliable_reason is not None:
            object.__setattr__(self, "log_evidence_unreliable_reason", EvidenceDoubt(self.log_evidence_unreliable_reason))
        if self.registry is None:
            object.__setattr__(self, "registry", DEFAULT_REGISTRY)
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @functools.cached_property
    def bounds(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """(lower, upper) bounds of the sampled parameters: the user's (``user_bounds``), else the
        circuit's, the reparametrization's, (0, ∞) for ``sigma_rel``."""
        specs = self.circuit.parameter_specs(self.registry)
        rp = self.reparametrization
        physical = {n: (lo, hi) for n, lo, hi in zip(rp.names, rp.lower, rp.upper)} if rp is not None else {}
        natural = {n: (s.lower, s.upper) for n, s in specs.items()} | physical
        pairs = [self.user_bounds.get(n, natural.get(n, (0.0, math.inf))) for n in self.names]
        return tuple(float(lo) for lo, _ in pairs), tuple(float(hi) for _, hi in pairs)

    @property
    def waic_note(self) -> str:
        """What the report says beside WAIC and p_waic when the kept chain is too short to estimate
        τ (the chain-length warning's rule: `evidence.short_chain_waic_note`), "" otherwise."""
        return short_chain_waic_note(self.n_draws, self.settings.get("thin", 1))

    @property
    def waic_unreliable_reason(self) -> WaicDoubt | None:
        """Why WAIC is no score to compare models by, None when it is one: `WaicDoubt.UNDEFINED`
        (not finite), `WaicDoubt.SHORT_CHAIN` (a chain too short to estimate τ, `waic_note`) or
        `WaicDoubt.HIGH_P_WAIC` (p_waic over 2 × the sampled parameters, WAIC's own warning),
        the first that applies (`evidence.waic_doubts`, the rule those notes follow, of ``waic``,
        ``p_waic``, the number of sampled parameters and ``n_draws``; not read from any words).
        A `str`: "undefined", "short_chain", "high_p_waic"."""
        reasons = waic_doubts(self.waic, self.p_waic, len(self.names), self.n_draws)
        return reasons[0] if reasons else None

    @functools.cached_property
    def warnings(self) -> tuple[str, ...]:
        """Diagnostics that need attention (straggler walkers left out, chain length, acceptance,
        correlations, draws piled up against a prior's edge, linearised standard errors far from
        the posterior's widths, fit notes): `own_warnings`, then the least-squares start's
        (each as ``least-squares start: …``)."""
        return self.own_warnings + tuple(f"least-squares start: {without_sample_advice(w)}" for w in self.fit.warnings)

    @functools.cached_property
    def own_warnings(self) -> tuple[str, ...]:
        """`warnings` without the least-squares start's: the sampling's own."""
        out = straggler_warnings(self.stragglers, self.n_walkers + len(self.stragglers.walkers))
        out += chain_warnings(self.names, self.log_scale, self._sampled_space, self.autocorr, self.settings.get("thin", 1), self.mean_acceptance, step_cap=capped_at(self.settings), steps=self.settings.get("steps"))
        out.extend(self._prior_edges.warnings)
        out.extend(self._interval_warnings())
        out.extend(implausible_gap_notes(self.reparametrization, {n: float(np.median(self.draws[..., i])) for i, n in enumerate(self.names)}))
        out.extend(self.notes)
        return tuple(out)

    def _interval_warnings(self) -> list[str]:
        """`interval_warnings` for the sampled circuit parameters free in the start fit."""
        q = self.quantiles()
        free = set(self.fit.free_names)
        linearised = self.fit.linearised_stderr
        names = [n for n in self.names if n in free]
        return interval_warnings(
            {n: float(linearised.get(n, math.nan)) for n in names},
            {n: 0.5 * float(q["q84"].sel(param=n) - q["q16"].sel(param=n)) for n in names},
            chain_converged=self.chain_converged,
            at_bound=self.fit.at_bound,
            piled_up=[n for n in names if n in self._prior_edges.piled_up],
            tied=tied_to_bound(self.fit.free_names, self.fit.covariance, self.fit.at_bound, self.undetermined),
        )

    # -- parameter draws ------------------------------------------------------------------
    def parameter_draws(self) -> KeyHintDict:
        """Flat draws of every parameter: sampled, fixed (repeated) and circuit parameters
        derived through the reparametrization (a new dict; a missing key: `MissingKey`)."""
        flat = self.samples
        n = self.n_walkers * self.n_draws
        out = KeyHintDict((name, np.full(n, value)) for name, value in self.fixed.items())
        out.update(flat)
        if self.reparametrization is not None:
            rp = self.reparametrization
            derived = rp.circuit_values({k: flat[k] for k in rp.names})
            out.update({k: np.asarray(v, float) for k, v in derived.items()})
        return out

    def circuit_samples(self) -> KeyHintDict:
        """Flat draws of the circuit's parameters (derived ones included; a new dict, a missing
        key: `MissingKey`)."""
        everything = self.parameter_draws()
        return KeyHintDict((n, everything[n]) for n in self.circuit.parameter_names(self.registry))

    def quantiles(self, *, circuit: bool = False) -> xr.Dataset:
        """median, q05, q16, q84, q95, mean, sd and the 90 % HDI per parameter (``circuit=True``:
        the circuit's parameters, derived through the reparametrization)."""
        return draws_table(self.circuit_samples() if circuit else self.samples)

    @property
    def undetermined(self) -> tuple[str, ...]:
        """The sampled parameters the least-squares start found the data do not determine: in an
        unidentified group (`FitResult.unidentified_groups`: C_EP and C_gap of R_EP ∥ C_EP ∥ C_gap,
        which change Z only together) or with a relative standard error above 100 %
        (the fits' rule), or run to a bound by a term that vanishes from Z (an infinite standard
        error: R2 open at ∞) (`branches.left_to_priors`); a reparametrized parameter through the
        one it replaces (u for C_gap). Their intervals are where the priors take over, not a measurement:
        on a SYNTHETIC pad (C_EP = 2 nF, C_gap = 120 pF, 1 % noise) u's 90 % interval was 1.8–9.4 µm
        and the truth 30 µm)."""
        fit = self.fit
        loose = {n for group in fit.unidentified_groups for n in group}
        loose |= {n for n in fit.free_names if left_to_priors(fit.values[n], fit.stderr[n], n in fit.at_bound)}
        rp = self.reparametrization
        stands_for = dict(zip(rp.names, rp.replaces)) if rp is not None and len(rp.names) == len(rp.replaces) else {}
        return tuple(n for n in self.names if n in loose or stands_for.get(n) in loose)

    def summary(self) -> dict:
        """The JSON summary used by ``impedax sample --json`` (``undetermined``: `undetermined`)."""
        q = self.quantiles()
        params = _quantiles_by_name(q, self.names)
        for n in self.names:
            params[n].update(hdi90=[float(q["hdi90_low"].sel(param=n)), float(q["hdi90_high"].sel(param=n))], unit=self.units[self.names.index(n)], prior=str(self.priors[n]))
        out = {
            "model": self.model,
            "params": params,
            "acceptance": self.mean_acceptance,
            "autocorr": dict(self.autocorr),
            "ess": dict(self.ess),
            "warnings": list(self.warnings),
            # (the kept chain is at least 50 τ long for every parameter, τ known: false where the chain-length warning fires)
            "chain_converged": self.chain_converged,
            # (parallel to warnings: none for the sampling's own, the start fit's tags for its "least-squares start: …")
            "warning_tags": [[] for _ in self.own_warnings] + [list(t) for t in fit_warning_tags(self.fit)],
            "undetermined": list(self.undetermined),
            "piled_up": self.piled_up,
            "at_prior_edge": self.at_prior_edge,  # (the rows the report marks AT PRIOR EDGE)
            "straggler_walkers": list(self.stragglers.walkers),  # (the run's walkers left out of the draws; as the .nc's attribute)
            "strong_correlations": [c.to_attr() for c in self.strong_correlations],  # (the correlation warnings' pairs and r)
            "log_evidence": self.log_evidence,
            "waic": self.waic,
            "p_waic": self.p_waic,
            "waic_note": self.waic_note or None,  # (beside WAIC of a chain too short to estimate τ; null otherwise)
            "waic_unreliable_reason": None if self.waic_unreliable_reason is None else self.waic_unreliable_reason.value,  # (why WAIC is no score to compare models by, `WaicDoubt`; null when it is one)
            "log_evidence_unreliable_reason": None if self.log_evidence_unreliable_reason is None else self.log_evidence_unreliable_reason.value,  # (why the log evidence is undefined or unreliable, `EvidenceDoubt`; null when sound)
            "noise": self.noise.value,
            "sigma_origin": self.settings.get("sigma_origin"),  # (what the data's σ is under noise 'sigma', `diagnosis.noise.sigma_origin`'s words; null otherwise)
            "walkers": self.n_walkers + len(self.stragglers.walkers),  # (the run's, stragglers included)
            "walkers_kept": self.n_walkers,  # (the walkers whose draws the posterior holds, `straggler_walkers` left out)
            "draws": self.n_draws,
            "draws_total": self.n_walkers * self.n_draws,
            "steps": self.settings.get("steps"),
            "steps_mode": self.settings.get("steps_mode", "fixed"),
            "step_cap": self.settings.get("step_cap"),
            "stopped": self.settings.get("stopped"),
            "burn": self.settings.get("burn"),
            "thin": self.settings.get("thin"),
            "seed": self.settings.get("seed"),
            "map": dict(self.map_values),
            # (the least-squares fit the walkers started around, its ± beside the posterior's intervals, not only
            # in a warning when they differ 2×)
            "start_fit": {
                "model": self.fit.model, "weighting": self.fit.weighting, "rms_rel": self.fit.rms_rel,
                "values": dict(self.fit.values), "stderr": {n: shown_stderr(e, self.fit.fixed[n]) for n, e in self.fit.stderr.items()},
                "at_bound": list(self.fit.at_bound), "converged": self.fit.converged,
            },
            "fixed": {n: float(v) for n, v in self.fixed.items()},  # (the report's "(fixed)" rows; the .nc's attribute)
            "user_bounds": bounds_attr(self.user_bounds),  # (bounds=, --bound, as the .nc's attribute and fit --json)
        }
        if self.reparametrization is not None:
            cq = self.quantiles(circuit=True)
            out["circuit_params"] = _quantiles_by_name(cq, self.reparametrization.replaces)
        return out

    def _reparametrization_lines(self) -> list[str]:
        """The report's ``reparam`` line: which sampled quantities stand in for which circuit
        parameters, and the map with its constants (`Reparametrization.description`: for the
        air gap, C_gap = ε0·ε_r·A/u with the area and permittivity used); none without one."""
        rp = self.reparametrization
        if rp is None:
            return []
        what = f"{', '.join(rp.names)} in place of {', '.join(rp.replaces)}"
        return [f"reparam    {what}: {rp.description}" if rp.description else f"reparam    {what}"]

    def report(self) -> str:
        """A readable table of the posterior."""
        q = self.quantiles()
        width = column_width([*self.names, *self.fixed], "parameter")
        units = [unit_text(u) for u in self.units]
        specs = self.circuit.parameter_specs(self.registry)
        fixed_units = [unit_text(specs[n].unit) if n in specs else "" for n in self.fixed]
        unit_width = max([4, *map(len, units), *map(len, fixed_units)])
        lines = [
            f"model      {self.model}",
            f"noise      {self.noise}: {NOISE_MODELS[self.noise]}" + (f"; here {self.settings['sigma_origin']}" if self.settings.get("sigma_origin") else ""),
            f"sampler    emcee, {walkers_text(self.n_walkers, self.stragglers)}, {self.settings.get('steps')} steps ({length_text(self.settings)}burn {self.settings.get('burn')}, thin {self.settings.get('thin')}), {self.n_walkers * self.n_draws} draws, acceptance {self.mean_acceptance:.3f}",
            *self._reparametrization_lines(),
            self._evidence_line(),
            *([f"           {self.waic_note}"] if self.waic_note else []),
            "",
            f"{'parameter':<{width}}  {'median':>11}  {'q05':>11}  {'q95':>11}  {'τ [steps]':>9}  {'ESS':>7}  {'unit':<{unit_width}}  prior",
        ]
        marks, footnotes = marked_rows(self.undetermined, self.set_by_prior_edge)
        for i, n in enumerate(self.names):
            lines.append(
                f"{n:<{width}}  {float(q['median'][i]):>11.5g}  {float(q['q05'][i]):>11.5g}  {float(q['q95'][i]):>11.5g}  {figure(self.autocorr[n], '9.3g'):>9}  {figure(self.ess[n], '7.0f'):>7}  {units[i]:<{unit_width}}  {self.priors[n]}"
                + (f"  {marks[n]}" if n in marks else "")
            )
        for (n, value), unit in zip(self.fixed.items(), fixed_units):  # (derived quantities such as the force depend on them too)
            lines.append(f"{n:<{width}}  {exact_number(value):>11}  {'(fixed)':>11}  {'':>11}  {'':>9}  {'':>7}  {unit:<{unit_width}}".rstrip())
        lines.extend(footnotes)
        for w in self.warnings:
            lines.append(f"warning: {w}")
        return "\n".join(lines)

    # -- propagation ----------------------------------------------------------------------
    def derive(self, fn: Callable, freq=None, *, draws: bool = False, max_draws: int | None = None) -> xr.Dataset:
        """Evaluate ``fn(params[, freq])`` (a JAX function of the parameters dict, with every
        parameter by name: circuit, physical and ``sigma_rel``) over all draws in one vmapped
        call. Returns a Dataset with ``median``, ``q05``, ``q16``, ``q84``, ``q95``, ``mean``,
        ``sd`` (and ``draws`` over ``sample`` when ``draws=True``); ``freq`` defaults to the data's
        frequencies when ``fn`` takes one. ``max_draws`` evaluates an
        evenly spaced subset instead of every draw. Where ``fn`` depends on parameters the data
        do not determine (`undetermined`: its derivative in them at the median draw is not zero),
        ``attrs["undetermined"]`` names them and ``attrs["warning"]`` says the interval is the
        priors'."""
        if freq is None and needs_freq(fn):
            freq = self.frequency
        params = self.parameter_draws()
        band = draws_band(fn, freq, params, self.model, draws=draws, max_draws=max_draws, method="posterior draws")
        loose = self.undetermined
        if loose:
            at = {k: jnp.asarray(np.median(np.asarray(v, float))) for k, v in params.items()}
            slopes = called(jax.jacfwd(bind_frequency(fn, freq)), at, list(params), self.model, fn)
            used = [n for n in loose if n in slopes and bool(np.any(np.asarray(slopes[n]) != 0))]
            if used:
                band.attrs["undetermined"] = ", ".join(used)
                band.attrs["warning"] = "; ".join(filter(None, [band.attrs.get("warning"), f"it depends on {', '.join(used)}, which the data do not determine (Posterior.undetermined): {DERIVED_FROM_UNDETERMINED}"]))
        return band

    def predict(self, freq=None, *, max_draws: int = 400, noise: bool = False, copies: int = 1, seed: int = 0) -> np.ndarray:
        """Model impedance [Ω] (draws, frequency) over an evenly spaced subset of the draws.
        With ``noise`` each draw also carries the likelihood's noise, so the result is the
        posterior predictive of new measurements: σ = sigma_rel·|Z_model| (``proportional``;
        |Z_model| stands in for |Z_data| between the data's frequencies) or the data's σ
        interpolated in log f (``sigma``), on Re and Im alike; ``copies`` noisy copies of each
        draw (rows: draws × copies) make the predictive quantiles smoother."""
        freq = self.frequency if freq is None else checked_frequencies(freq)
        if noise:
            checked_copies(copies)
        params = self.circuit_samples()
        total = self.n_walkers * self.n_draws
        pick = draw_indices(total, max_draws)
        compiled = compile_circuit(self.circuit, self.registry)
        fn = jax.jit(jax.vmap(lambda p, f: compiled(p, f), in_axes=(0, None)))
        z = np.asarray(fn({k: jnp.asarray(v[pick]) for k, v in params.items()}, jnp.asarray(freq)))
        if not noise:
            return z
        z, pick = np.repeat(z, copies, axis=0), np.repeat(pick, copies)
        if self.noise == NoiseModel.PROPORTIONAL:
            sigma = self.parameter_draws()["sigma_rel"][pick][:, None] * np.abs(z)
        else:
            sigma = np.broadcast_to(sigma_between(freq, self.frequency, self.sigma), z.shape)
        return with_noise(z, sigma, seed)

    def to_table(self) -> list[dict[str, object]]:
        """The tidy table: one row per sampled parameter with name, median, q05, q16, q84, q95,
        unit, and (as the JSON's keys) ``autocorr`` (τ [steps]) and ``ess``
        (None, an empty cell, where unknown) (`impedax.io.write_result` .csv); with a
        reparametrization, the circuit parameters it replaces follow (derived from the draws;
        no τ or ESS of their own: empty). Last (the name of `FitResult.to_table`'s
        column) ``undetermined``: the row the text report marks NOT DETERMINED (`undetermined`;
        not the rows piled up at a prior's edge); a replaced parameter's by the
        one that replaces it. Then (as `FitResult.to_table`'s rows and column) a
        row per fixed parameter, its value in every quantile column, and the column ``fixed``
        (true on those rows), as the report lists them. Then
        ``at_prior_edge``: the row the report marks AT PRIOR EDGE (`at_prior_edge`); last, the
        same on every row, ``chain_converged`` and ``warnings`` (`with_warning_columns`)."""
        q = self.quantiles()
        marks, _ = marked_rows(self.undetermined, self.set_by_prior_edge)
        rows = [
            {"name": n, **{k: float(q[k].sel(param=n)) for k in SUMMARY_QUANTILES}, "unit": u, **chain_figures(self.autocorr, self.ess, n), **_mark_columns(marks.get(n))}
            for n, u in zip(self.names, self.units)
        ]
        rp = self.reparametrization
        if rp is not None:
            cq = self.quantiles(circuit=True)
            specs = self.circuit.parameter_specs(self.registry)
            replaced_by = dict(zip(rp.replaces, rp.names)) if len(rp.names) == len(rp.replaces) else {}

            def mark_of(n):  # (the replacing parameter's; of several, NOT DETERMINED before AT PRIOR EDGE)
                found = [marks[m] for m in ([replaced_by[n]] if n in replaced_by else rp.names) if m in marks]
                return UNDETERMINED_MARK if UNDETERMINED_MARK in found else found[0] if found else None

            rows += [{"name": n, **{k: float(cq[k].sel(param=n)) for k in SUMMARY_QUANTILES}, "unit": specs[n].unit, "autocorr": None, "ess": None,
                      **_mark_columns(mark_of(n))} for n in rp.replaces]
        rows = [{**row, "fixed": False} for row in rows] + fixed_rows(self.fixed, self.circuit.parameter_specs(self.registry))
        return with_warning_columns(last_at_prior_edge(rows), self.chain_converged, self.warnings)

    def _evidence_line(self) -> str:
        """The report's line of Laplace ln Z and WAIC, "undefined" for a figure that is not
        finite and "(see the warnings)" said once (not twice when both are undefined)."""
        laplace = f"Laplace ln Z = {self.log_evidence:.2f}" if math.isfinite(self.log_evidence) else None
        waic = f"WAIC = {self.waic:.2f} (p_waic {self.p_waic:.3g})" if math.isfinite(self.waic) else None
        if laplace is None and waic is None:
            return "evidence   Laplace ln Z and WAIC undefined (see the warnings)"
        return f"evidence   {laplace or 'Laplace ln Z undefined (see the warnings)'}    {waic or 'WAIC undefined (see the warnings)'}"

    def _repr_html_(self) -> str:
        from ...plotting.html import result_html

        lines = [
            f"emcee: {self.n_walkers} walkers × {self.n_draws} draws, acceptance {self.mean_acceptance:.3f}; "
            + (f"Laplace ln Z {self.log_evidence:.2f}" if math.isfinite(self.log_evidence) else "Laplace ln Z undefined")
            + (f", WAIC {self.waic:.2f}" if math.isfinite(self.waic) else ", WAIC undefined"),
            *([self.waic_note] if self.waic_note else []),
            *marked_rows(self.undetermined, self.set_by_prior_edge)[1],
            *self.warnings,
        ]
        # (the text report's mark on the rows, not a yes/no cell)
        return result_html(f"{self.model}: posterior", html_rows(self.to_table()), lines=lines)

    # -- figures (drawn by impedax.plotting.bayes) -----------------------------------------
    def plot(self, *, title: str | None = None, n_lines: int = 40, figsize: tuple[float, float] | None = None):
        """Data with posterior bands: Nyquist (draws as thin lines) and Bode |Z| and phase with
        the 68 % and 90 % credible bands of the model and the 90 % posterior predictive band
        (model and noise: where new measurements fall) (matplotlib Figure; ``figsize`` (width,
        height) [in] in place of the size that follows the spectrum's shape)."""
        from ...plotting.bayes import plot_posterior_bands

        f = np.geomspace(self.frequency.min(), self.frequency.max(), 200)
        return plot_posterior_bands(
            self.frequency, self.z_data, f, self.predict(f), n_lines=n_lines, z_predictive=self.predict(f, noise=True, copies=PREDICTIVE_COPIES),
            title=title or f"{self.model}: posterior bands ({self.n_walkers * self.n_draws} draws; {NOISE_TITLES[self.noise]})", figsize=figsize,  # (the noise model named)
        )

    def corner(self, *, truths: Mapping[str, float] | None = None, bins: int = 30, max_points: int = 4000, params: Sequence[str] | None = None):
        """Corner plot: marginal histograms on the diagonal, titled with the median and 90 %
        interval, and pairwise scatter below it, in the parameters' units (log axes for a
        log-sampled parameter over decades; `impedax.plotting.bayes.plot_corner`). ``truths``
        (name → value) draws reference lines; ``params``: the parameters to draw, in that order
        (default every one). An unknown name, a truth that is not a number, ``bins`` < 1 are a
        `ParameterError`."""
        from ...plotting.bayes import plot_corner

        return plot_corner(self.draws, self.names, self.log_scale, units=self.units, truths=truths, bins=bins, max_points=max_points, title=f"{self.model}: posterior ({NOISE_TITLES[self.noise]})", params=params)

    def trace(self, *, params: Sequence[str] | None = None):
        """Trace plot: each parameter's kept draws of every walker against the step, with the
        walkers' median (`impedax.plotting.bayes.plot_trace`; matplotlib Figure): drift, a stuck
        walker or a median still moving show a chain that has not converged. ``params``: the
        parameters to draw, in that order (default every one)."""
        from ...plotting.bayes import plot_trace

        return plot_trace(
            self.draws, self.names, self.log_scale, units=self.units, first_step=self.settings.get("burn", 0), thin=self.settings.get("thin", 1),
            autocorr=self.autocorr, title=f"{self.model}: posterior draws ({NOISE_TITLES[self.noise]})", params=params,
        )

    # -- storage --------------------------------------------------------------------------
    def to_xarray(self) -> xr.Dataset:
        """Draws (walker, draw, param), log_prob, diagnostics, summaries, the least-squares
        start (``fit_*``, ``Z_fit``; its ``fit_rms_rel``, as a joint posterior's) and the data;
        ``unit`` along ``param`` gives each sampled parameter's unit (as a fit's Dataset does);
        `Posterior.from_xarray` rebuilds the posterior from it."""
        q = self.quantiles()
        fr = self.fit
        names = list(fr.values)
        free = list(fr.free_names)
        data = {
            "draws": (("walker", "draw", "param"), self.draws),
            "log_prob": (("walker", "draw"), self.log_prob),
            "acceptance": ("walker", self.acceptance),
            "autocorr": ("param", [self.autocorr[n] for n in self.names], {"units": "steps"}),
            "ess": ("param", [self.ess[n] for n in self.names]),
            "log_scale": ("param", np.asarray(self.log_scale, bool)),
            "map": ("param", [self.map_values[n] for n in self.names]),
            "Z": ("frequency", self.z_data, {"units": "ohm"}),
            "fit_value": ("circuit_param", [fr.values[n] for n in names]),
            "fit_stderr": ("circuit_param", [fr.stderr[n] for n in names]),
            "fit_fixed": ("circuit_param", [fr.fixed[n] for n in names]),
            "fit_covariance": (("free_param", "free_param_2"), fr.covariance),
            "fit_correlation": (("free_param", "free_param_2"), fr.correlation),
            "Z_fit": ("frequency", fr.z_model, {"units": "ohm"}),
            # (a joint posterior's name for its start's: `SharedPosterior.to_xarray`)
            "fit_rms_rel": ((), fr.rms_rel, {"long_name": "rms of the least-squares start's relative residual |Z_fit − Z|/|Z|"}),
        }
        data.update({k: ("param", q[k].values) for k in q.data_vars})
        if self.sigma is not None:
            data["sigma"] = ("frequency", self.sigma, {"units": "ohm"})
        attrs = {
            "impedax_kind": "posterior",
            "model": self.model,
            "noise": self.noise.value,
            "units": list(self.units),
            "priors": {n: [p.kind.value, p.a, p.b] for n, p in self.priors.items()},
            "fixed": dict(self.fixed),
            "settings": dict(self.settings),
            "log_evidence": self.log_evidence,
            "waic": self.waic,
            "p_waic": self.p_waic,
            "notes": list(self.notes),
            "log_evidence_unreliable_reason": None if self.log_evidence_unreliable_reason is None else self.log_evidence_unreliable_reason.value,
            "model_comparison_notes": list(self.model_comparison_notes),
            "warnings": list(self.warnings),
            "reparametrization": self.reparametrization.describe() if self.reparametrization is not None else None,
            "fit": {"weighting": fr.weighting, "chi2": fr.chi2, "converged": fr.converged, "message": fr.message, "n_evaluations": fr.n_evaluations, "warnings": list(fr.warnings), **note_value_attrs(fr), "n_starts": fr.n_starts, "elapsed_s": fr.elapsed_s, "at_bound": list(fr.at_bound), "unidentified_groups": [list(g) for g in fr.unidentified_groups], "bounds": bounds_attr(fr.bounds)},
            "user_bounds": bounds_attr(self.user_bounds),
            "straggler_walkers": list(self.stragglers.walkers),
            "stragglers": self.stragglers.to_attr(),
        }
        coords = {
            "walker": kept_walkers(self.n_walkers, self.stragglers),  # (the run's numbering: stragglers left out)
            "draw": np.arange(self.n_draws),
            "param": list(self.names),
            "unit": ("param", list(self.units), {"long_name": PARAMETER_UNIT_NAME}),  # (as a fit's Dataset names its parameters' units)
            "circuit_param": names,
            "free_param": free,
            "free_param_2": free,
            "frequency": ("frequency", self.frequency, {"units": "Hz"}),
        }
        return result_dataset(xr.Dataset(data, coords=coords, attrs=attrs).copy(deep=True))

    @classmethod
    def from_xarray(cls, ds: xr.Dataset, *, reparametrization: Reparametrization | None = None, registry: Registry | None = None) -> "Posterior":
        """Rebuild a posterior from `Posterior.to_xarray` output, read back by `impedax.load` or
        opened as stored (``xr.open_dataset`` of a file `impedax.write_result` wrote: its JSON
        attributes and split complex variables are decoded here). A custom reparametrization
        must be passed again (its functions are not stored); ``registry`` None: the default one."""
        from ...io.netcdf import damaged_result, saved_result  # (io is imported only here: rarely needed)

        registry = DEFAULT_REGISTRY if registry is None else registry
        # (a joint or hierarchical file: named, with its reader; a missing part: named)
        ds = saved_result(ds, "posterior", variables=_REQUIRED_VARIABLES, attrs=_REQUIRED_ATTRS)
        with damaged_result("posterior", ds):
            return cls._rebuild(ds, reparametrization, registry)

    @classmethod
    def _rebuild(cls, ds: xr.Dataset, reparametrization, registry: Registry) -> "Posterior":
        circuit = parse(ds.attrs["model"], registry)
        rp = reparametrization
        if rp is None and ds.attrs.get("reparametrization"):
            rp = rebuild(ds.attrs["reparametrization"])
        fa = ds.attrs["fit"]
        names = [str(n) for n in ds["circuit_param"].values]
        fr = FitResult(
            circuit=circuit,
            values={n: float(v) for n, v in zip(names, ds["fit_value"].values)},
            stderr={n: float(v) for n, v in zip(names, ds["fit_stderr"].values)},
            fixed={n: bool(v) for n, v in zip(names, ds["fit_fixed"].values)},
            free_names=tuple(str(n) for n in ds["free_param"].values),
            covariance=np.asarray(ds["fit_covariance"].values, float),
            correlation=np.asarray(ds["fit_correlation"].values, float),
            frequency=np.asarray(ds["frequency"].values, float),
            z_data=np.asarray(ds["Z"].values, complex),
            z_model=np.asarray(ds["Z_fit"].values, complex),
            weighting=fa["weighting"],
            chi2=float(fa["chi2"]),
            converged=bool(fa["converged"]),
            message=fa["message"],
            n_evaluations=int(fa["n_evaluations"]),
            warnings=tuple(fa["warnings"]),
            n_starts=int(fa["n_starts"]),
            elapsed_s=float(fa["elapsed_s"]),
            at_bound=tuple(str(n) for n in fa.get("at_bound", ())),  # (a file written by an older version: none)
            unidentified_groups=tuple(tuple(str(n) for n in g) for g in fa.get("unidentified_groups", ())),  # (a file written by an older version: none)
            registry=registry,
            bounds=stored_bounds(fa.get("bounds")),  # (a file written by an older version: none)
            **stored_note_values(fa),  # (a file written by an older version lacks them: its warnings' words)
        )
        sampled = [str(n) for n in ds["param"].values]
        notes = tuple(ds.attrs.get("notes", ()))
        return cls(
            circuit=circuit,
            names=tuple(sampled),
            units=tuple(ds.attrs["units"]),
            log_scale=tuple(bool(v) for v in ds["log_scale"].values),
            draws=np.asarray(ds["draws"].values, float),
            log_prob=np.asarray(ds["log_prob"].values, float),
            acceptance=np.asarray(ds["acceptance"].values, float),
            priors={n: Prior(*v) for n, v in ds.attrs["priors"].items()},
            noise=ds.attrs["noise"],
            fit=fr,
            fixed={k: float(v) for k, v in ds.attrs["fixed"].items()},
            frequency=np.asarray(ds["frequency"].values, float),
            z_data=np.asarray(ds["Z"].values, complex),
            sigma=np.asarray(ds["sigma"].values, float) if "sigma" in ds else None,
            log_evidence=float(ds.attrs["log_evidence"]) if ds.attrs["log_evidence"] is not None else math.nan,
            waic=float(ds.attrs["waic"]) if ds.attrs["waic"] is not None else math.nan,
            p_waic=float(ds.attrs["p_waic"]) if ds.attrs["p_waic"] is not None else math.nan,
            map_values={n: float(v) for n, v in zip(sampled, ds["map"].values)},
            notes=notes,
            settings=dict(ds.attrs["settings"]),
            reparametrization=rp,
            registry=registry,
            user_bounds=stored_bounds(ds.attrs.get("user_bounds")),  # (a file written by an older version: none)
            stragglers=Stragglers.from_attr(ds.attrs.get("stragglers")),  # (a file written by an older version: none)
            # (a file written by an older version holds them only in the notes' words: read by their leads)
            log_evidence_unreliable_reason=ds.attrs["log_evidence_unreliable_reason"] if "log_evidence_unreliable_reason" in ds.attrs else evidence_doubt_of_notes(notes),
            model_comparison_notes=tuple(ds.attrs["model_comparison_notes"]) if "model_comparison_notes" in ds.attrs else model_comparison_notes_of(notes),
        )


_REQUIRED_VARIABLES = (
    "draws", "log_prob", "acceptance", "log_scale", "map", "param", "frequency", "Z", "Z_fit", "circuit_param", "free_param",
    "fit_value", "fit_stderr", "fit_fixed", "fit_covariance", "fit_correlation",
)
_REQUIRED_ATTRS = ("model", "units", "priors", "noise", "fixed", "fit", "settings", "log_evidence", "waic", "p_waic")
