"""The whole Sirin et al. workflow: from three measured spectra to the air-gap thickness, the
gap voltage and the electrostatic force, with uncertainty.

1. remaining impedance Z_R = Z_total − Z_skin − Z_TS from the trial means, with the SEM
   propagated (eq 5; `remaining_impedance`);
2. the paper's estimate: C_gap = mean |Y_R|/ω above the cutoff, u = ε0 ε_gap A/C_gap, bounds
   from the lowest and highest impedances (`paper_gap_estimate`);
3. least-squares fits of the naive model (C_gap alone) and of the EDL parallel model with the
   electrode-polarization branch (`remainder_circuit(ep)`; ``ep="C"``: R_EP || C_EP || C_gap
   holds two ideal capacitors in parallel, which no impedance tells apart, so it is analysed
   as R_EP || C_gap with C_gap standing for C_EP + C_gap: `IDENTIFIED_C_REMAINDER`);
4. Bayesian sampling of the EDL model with the gap thickness u itself as a parameter
   (C_gap = ε0 ε_gap A/u; `gap_thickness_reparametrization`). ``method="hierarchical"``
   (default): every total trial's remainder (`trial_remainders`) gets its own u and EP
   branch, drawn from a log-normal population (`impedax.fitting.bayes.hierarchical`), with the
   noise from the trial scatter plus a sampled discrepancy floor; u is the population median,
   reported with the spread between trials and the interval of a new trial.
   ``method="pooled"``: one EDL model on the trial mean with its SEM (the earlier analysis);
5. the gap voltage and the PEAK force of eq 1, F = ½ ε0 A |ΔV_gap|²/u², over frequency for a
   drive of amplitude V0, as posterior bands, with and without the EP branch. The bands carry the
   posterior of the remainder only: they condition on the area A being exact and on the skin and
   screen trial means (their errors are not propagated).

A single contact (skin and touchscreen None; ``impedax gap PAD.csv``): an
electroadhesive gripper pad on its target, whose measured impedance is the contact's own,
R_EP ∥ CPE_EP ∥ C_gap. Nothing is subtracted (step 1 gives the total's trial means with their
SEM), and the drive V0 falls across the contact alone: with z_skin = z_ts = 0 in the node
voltages of eq 1, I = V0/Z_R and ΔV = V0, so C_gap, parallel to the EP branch, carries the whole
V0 and F = ½ ε0 ε_gap A V0²/u² at every frequency, with EP and without.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from typing import Callable, Mapping, Sequence

import numpy as np
import xarray as xr

from ..progress import quiet_beneath
from ..circuits import DEFAULT_REGISTRY, parse
from ..data import concise_repr, point_text, report_text, format_band, format_frequency, format_percent, format_quantity, si_prefix
from ..arguments import GAP_MIN_STEPS, MAX_WALKERS, checked_arguments, choice, count, flag, real, relative_permittivity_number, seed, shown
from ..errors import IN_MEMORY, CircuitError, DataError, ParameterError
from ..io.netcdf import result_dataset
from ..constants import C_GAP_BOUNDS_F, EPSILON_0, EPSILON_AIR
from ..fitting.bayes.chain import AUTO_STEPS, steps_rule
from ..fitting.bayes.diagnostics import CHAIN_TAU_MULTIPLE
from ..fitting.bayes.reparam import AREA_UNIT_ADVICE, PLAUSIBLE_GAP_M
from ..fitting.kk import KKChains
from ..fitting.least_squares.branches import undetermined_names
from ..fitting.least_squares.result import GROSS_MISFIT_FROM, MISFIT_RATIO_MAX, REMAINDER_ATTRS, SIGMA_FROM_OWN, SIGMA_FROM_TRIALS, SUBTRACTION_CAUSE, fit_blaming_note, fit_data_limit, fit_sigma_residual_notes, gross_misfits, known_kk_misfits, listed_frequencies, names_in_words, sigma_sources, within_stated_noise
from ..fitting.statistics import non_passive
from ..fitting.frozen import FrozenResult, freeze_fields
from .gap_inputs import DriveVoltage, check_gap_inputs, check_spectra, check_not_a_remainder, condition_notes, drive_voltage, is_single_contact, position_notes, present_inputs, spectra_used
from .peak import FORCE_PLATEAU_REL, FORCE_PLATEAU_SPAN, band_end_words, force_plateau, grid_edge_slope  # noqa: F401 (FORCE_PLATEAU_SPAN: kept importable as gap.FORCE_PLATEAU_SPAN)
from .plausible import AIR_BREAKDOWN_V, DRIVE_VOLTAGE_V, FINGERTIP_AREA_M2
from .sirin import SIRIN_AREA, SIRIN_CUTOFF_HZ, PaperGapEstimate, gap_force_peak, gap_voltage, paper_gap_estimate, remainder_circuit, remaining_impedance, trial_mean, trial_remainders

__all__ = ["GapAnalysis", "gap_analysis", "gap_remainder", "REMAINDER_KINDS", "GAP_TABLE_COLUMNS", "GAP_METHODS", "FORCE_BRANCHES", "GAP_MIN_STEPS", "FINGERTIP_AREA_M2", "IDENTIFIED_C_REMAINDER", "C_GAP_BOUNDS_F", "HIERARCHICAL_AUTO_DRAWS", "GAP_DRAW_ALIASES", "GAP_SAVED_DRAWS", "GAP_VARIABLE_LABELS", "gap_bounds", "check_fingertip_area", "force_maximum_text", "force_maximum_shape", "force_conditions_of"]

FORCE_BRANCHES = ("with_ep", "without_ep")
"""The force bands' ``branch`` labels: with the electrode-polarization branch, and C_gap alone."""
GAP_METHODS = ("hierarchical", "pooled")
_EP_PER_TRIAL = ("R_EP", "CPE_EP.Q", "C_EP")  # the contact's EP branch varies with each trial

FORCE_CONVENTION = "peak"  # eq 1 at the voltage amplitude; the time average is half of it
FORCE_CONDITIONS = "A taken as exact; skin and screen as their trial means, without their errors"
SINGLE_CONTACT_FORCE_CONDITIONS = "A taken as exact; a single contact: the drive V0 across the contact alone (no skin or screen in series)"
"""`FORCE_CONDITIONS` of a single contact (`GapAnalysis.single_contact`)."""


def force_conditions_of(remaining: xr.Dataset) -> str:
    """What the force bands of a remainder Z_total − Z_skin − Z_TS condition on: `FORCE_CONDITIONS`,
    with skin or screen "as measured (one spectrum)" where its file held one (attrs
    ``n_trials_skin``, ``n_trials_touchscreen``; not "as their trial means" of one sweep each)."""
    single = [name for name, short in (("skin", "skin"), ("touchscreen", "screen")) if int(remaining.attrs.get(f"n_trials_{name}", 2)) == 1]
    if not single:
        return FORCE_CONDITIONS
    if len(single) == 2:
        return "A taken as exact; skin and screen as measured (one spectrum each), without their errors"
    one, other = ("skin", "screen") if single == ["skin"] else ("screen", "skin")
    return f"A taken as exact; {one} as measured (one spectrum), {other} as its trial mean, without their errors"
SINGLE_CONTACT_NOTE = (
    "single contact (no skin or touchscreen given): the EDL model is fitted to the total itself, nothing subtracted, "
    "and the drive V0 falls across the contact alone"
)
"""The report's ``mode`` line and the CSV's and figure's word for a single-contact analysis."""
GAP_TABLE_COLUMNS = (
    "method", "c_gap_f", "c_gap_low_f", "c_gap_high_f", "u_m", "u_low_m", "u_high_m", "gap_identified", "u_lower_bound_m", "u_lower_bound_withheld",
    "force_max_frequency_hz", "gap_voltage_v", "gap_voltage_low_v", "gap_voltage_high_v",
    "force_max_n", "force_max_low_n", "force_max_high_n", "force_upper_bound_max_n", "v0_v", "v0_from", "sampling_unreliable", "n_warnings", "warnings", "alarms", "single_contact",
)
"""The columns of `GapAnalysis.to_table` (``impedax gap --out FILE.csv``), each quantity's SI
unit in its name (``_f`` farad, ``_m`` metre, ``_v`` volt, ``_n`` newton, ``_hz`` hertz);
``u_lower_bound_withheld`` says why u is not determined and yet no bound is given
(`GapAnalysis.gap_bound_withheld`); ``gap_voltage_v`` (low, high: its 90 % interval) the
amplitude of the gap voltage at ``force_max_frequency_hz``, where the median force with EP is
largest; ``force_max_n`` (low, high) the PEAK force there (`GapAnalysis.force_at_max`),
``force_upper_bound_max_n`` the largest force the data allow when u is not determined,
``sampling_unreliable`` the report's "SAMPLING UNRELIABLE", ``warnings`` and ``alarms`` (`GapAnalysis.alarms`)
one per line in one cell, ``n_warnings`` how many warnings, ``v0_v`` the drive V0 the forces are for and
``v0_from`` where it came from (data, given, default; the JSON's); ``single_contact``
true when nothing was subtracted (`GapAnalysis.single_contact`)."""

HIERARCHICAL_AUTO_DRAWS = 500
# the names `GapAnalysis.draws` takes besides the parameters': those of its properties `gap` and `c_gap`
GAP_DRAW_ALIASES = {"gap": "u", "u": "u", "c_gap": "C_gap", "C_gap": "C_gap"}
# draws of u kept in a saved gap analysis (.nc): enough for the posterior panel's histogram and
# its 5/95 % quantiles to 1 % (2000 draws of the default 4 chains × 500), a file of 32 kB at most
GAP_SAVED_DRAWS = 4000
"""``steps="auto"`` in the hierarchical method: NUTS draws per chain (and warm-up steps)."""
NAIVE_RUNAWAY_RMS_REL = 0.99
"""A naive fit (C_gap alone) with rms_rel at or above this misses the data entirely (a model
curve far from every point gives rms_rel → 1): it has run away."""
IDENTIFIED_C_REMAINDER = "R_EP || C_gap"
"""What ``ep="C"`` is analysed as. In R_EP || C_EP || C_gap the two ideal capacitors add,
1/Z = 1/R_EP + jω(C_EP + C_gap) at every frequency, so any data fit every split of the sum
equally well: C_gap alone is set by the prior (the least-squares split by its start), and u by
the prior's bound. The sum is what the data give; calling all of it C_gap (C_EP = 0, as the
paper's |Y_R|/ω above the cutoff does) gives the smallest u this model allows: a lower bound on u
and an upper bound on the force (the gap voltage does not depend on the split)."""
EP_ALPHA_IDEAL = 0.95
"""An EP CPE whose exponent α has its posterior median at or above this is (nearly) an ideal
capacitor in parallel with C_gap: only their sum is determined, and u is not (`_gap_identification`)."""
_BOUND_FACTOR = 2.0  # draws of u within this factor of a prior bound count as "at the bound" ...
_BOUND_SHARE = 0.1  # ... and this share of them means the posterior piles up there
NO_AIR_GAP = "NO AIR GAP"
"""The alarm of a u at a bound of its prior or outside `PLAUSIBLE_GAP_M` (`GapAnalysis.alarms`)."""


@dataclass(frozen=True, eq=False)
class GapAnalysis(FrozenResult):
    """Result of `gap_analysis`. Lengths in m and capacitances in F inside; `summary` gives µm.

    ``method`` ``"hierarchical"``: u is the population median of the trials' gap thicknesses
    (``hierarchical`` holds the `HierarchicalPosterior`; ``posterior`` is None); its interval
    includes the trial-to-trial variation of the contact and the model discrepancy, and
    `gap_spread` / `gap_new_trial` give the spread between trials and where a new trial's u
    falls. ``"pooled"``: one model on the trial means; its interval reflects only the noise of
    the means (their SEM), not the variation of the contact between trials.

    ``force`` holds the PEAK force [N] bands over frequency (``median``, ``q05``, ``q95``) with
    the EP branch (``with_ep``) and without it (``without_ep``, same C_gap draws), and the
    amplitude of the gap voltage |ΔV_gap| [V] from the same draws (``gap_voltage_median``,
    ``gap_voltage_q05``, ``gap_voltage_q95``; `gap_voltage_at_force_max`); the bands
    condition on ``area`` being exact and on the skin and screen trial means (no error).

    ``single_contact``: no skin or touchscreen was given, so ``remaining`` is the total's trial
    mean itself and the force's drive falls across the contact alone (module docstring).
    """

    __repr__ = concise_repr  # (the generated one printed every array and Dataset)
    __str__ = report_text  # (print(result): its report)

    remaining: xr.Dataset
    paper: PaperGapEstimate
    naive_fit: object
    edl_fit: object
    posterior: object
    force: xr.Dataset
    area: float
    v0: float
    ep: str
    warnings: tuple[str, ...] = field(default=())
    method: str = "pooled"
    hierarchical: object = None
    model_requested: str | None = None
    trials: dict | None = None  # `gap_inputs.spectra_used`: per input, the spectra analysed
    gap_lower_bound: float | None = None
    """None when the data determine u; else the smallest u [m] the data allow (C_gap standing
    for all the capacitance C_EP + C_gap: `IDENTIFIED_C_REMAINDER`), and u itself is not
    determined (``ep="C"``, or an EP branch the fit cannot tell from C_gap)."""
    gap_bound_withheld: str | None = None
    """Why u is not determined and yet no lower bound is given (`gap_lower_bound` None): the
    model the bound would come from (`IDENTIFIED_C_REMAINDER`) misses the remainder grossly
    (`_misfit_text`), so its capacitance is no sum of C_EP and C_gap and bounds nothing."""
    edl_misfit: str | None = None
    """How the EDL model misses the trial-mean remainder grossly (`_misfit_text`), else None:
    then u, its interval and the force rest on a model the data reject."""
    force_upper_bound: xr.DataArray | None = None
    """With `gap_lower_bound`: the PEAK force [N] over ``frequency`` with EP at u = that bound
    (`_force_upper_bound`): eq 1 goes as 1/u², so u ≥ the bound gives F ≤ this, the largest force
    the data allow; else None (u determined, or no bound)."""
    drive: DriveVoltage | None = None
    """Where ``v0`` came from (`gap_inputs.drive_voltage`: the voltage the total spectra carry,
    the one given, or the default); None: given."""
    single_contact: bool = False
    """True when skin and touchscreen were None: nothing subtracted."""
    settings: dict | None = None
    """What `gap_analysis` ran with, defaults included: ``eps_gap``, ``cutoff_hz``, ``seed``,
    ``steps`` (hierarchical: draws per chain; pooled: emcee steps, as run when ``"auto"``),
    ``steps_requested``, ``warmup`` and ``chains`` (hierarchical), ``walkers`` (pooled)."""

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def gap_identified(self) -> bool:
        """False when the data do not determine u apart from the EP branch (a lower bound,
        `gap_lower_bound`, or none where its model misfits: `gap_bound_withheld`): ``ep="C"``,
        or a fit/posterior that cannot split C_gap from the EP element (`_gap_identification`);
        and when the sampled u is no air gap (`gap_implausible`: at a bound
        of its prior, or outside `PLAUSIBLE_GAP_M`)."""
        return self._split_determined and self.gap_implausible is None

    @property
    def _split_determined(self) -> bool:
        """The data tell C_gap from the EP branch: no `gap_lower_bound`, no `gap_bound_withheld`."""
        return self.gap_lower_bound is None and self.gap_bound_withheld is None

    @property
    def _u_piled_bounds(self) -> list[tuple[str, float, float, float]]:
        """The prior bounds of u its draws pile up at (`_piled_bounds`, the rule of the warning
        "the posterior of u piles up at the … bound of its prior")."""
        eps_gap = (self.settings or {}).get("eps_gap", EPSILON_AIR)
        return _piled_bounds(self.draws("u"), *gap_bounds(self.area, eps_gap))

    @property
    def _u_piled_by_sampling(self) -> tuple[str, ...]:
        """The sides ("lower", "upper") at whose prior edge the sampling itself found u's draws
        piled up (`Posterior.piled_up`, the rule of its warning "u piles up against its upper
        bound"; hierarchical: u's population median). Its rule (`prior_edges`) reads a flat
        posterior over decades that `_piled_bounds` does not: REAL exampleDataBioLogic.mpt as a
        single contact samples u flat over 0.058 µm–460 mm, warned by the sampling, which
        `_piled_bounds` alone would report as a gap thickness with ``gap_identified: true``."""
        source = self.hierarchical if self.hierarchical is not None else self.posterior
        side = getattr(source, "piled_up", {}).get("u") if source is not None else None
        return ("lower", "upper") if side == "both" else (side,) if side else ()

    @property
    def gap_implausible(self) -> str | None:
        """Why the sampled u is no air gap, else None: ≥ `_BOUND_SHARE` of its draws lie within
        `_BOUND_FACTOR` of a bound of its prior (`_piled_bounds`: the prior, not the data, sets u
        and C_gap), or its median lies outside `PLAUSIBLE_GAP_M` (1 nm–1 mm). Then
        `gap_identified` is False and `alarms` says so (a u = 1.15 m piled up at the upper bound is no
        "gap thickness u" with ``gap_identified: true``)."""
        median = self.gap["value"]
        low, high = PLAUSIBLE_GAP_M
        piled = {side: c_bound for side, _, c_bound, _ in self._u_piled_bounds}
        for side in self._u_piled_by_sampling:  # (C_gap at u's lower bound is its upper end, `C_GAP_BOUNDS_F`)
            piled.setdefault(side, C_GAP_BOUNDS_F[1] if side == "lower" else C_GAP_BOUNDS_F[0])
        reasons = [f"piles up at the {side} bound of its prior (C_gap = {format_quantity(c_bound, 'F')}: the prior sets it, not the data)" for side, c_bound in piled.items()]
        if not low <= median <= high:
            reasons.append(f"lies outside the air gaps a contact can hold ({format_quantity(low, 'm')}–{format_quantity(high, 'm')})")
        return f"u = {format_quantity(median, 'm')} (posterior median) " + " and ".join(reasons) if reasons else None

    @property
    def paper_gap_implausible(self) -> str | None:
        """Why the paper method's u is no air gap (outside `PLAUSIBLE_GAP_M`), else None; `alarms`
        says so (a u = 0.05 nm, not "u = 0.000 µm")."""
        low, high = PLAUSIBLE_GAP_M
        u = self.paper.gap
        if low <= u <= high:
            return None
        return f"the paper method's u = {format_quantity(u, 'm')} (C_gap = {format_quantity(self.paper.c_gap, 'F')}) lies outside the air gaps a contact can hold ({format_quantity(low, 'm')}–{format_quantity(high, 'm')})"

    def _all_draws(self) -> dict[str, np.ndarray]:
        """Posterior draws of every parameter (hierarchical: of a typical trial, the population
        medians; pooled: the emcee draws), u [m] and C_gap [F] among them."""
        if self.hierarchical is not None:
            return self.hierarchical.population_parameters()
        return self.posterior.parameter_draws()

    def draws(self, name: str) -> np.ndarray:
        """Posterior draws of ``u`` [m] (also named ``"gap"``, as the property `gap`), ``C_gap``
        [F] (also ``"c_gap"``) or another parameter of the EDL model, e.g. ``"R_EP"``
        (hierarchical: population medians). Another name is a `ParameterError` listing these."""
        values = self._all_draws()
        key = GAP_DRAW_ALIASES.get(name, name)
        if key not in values:
            names = ", ".join([*GAP_DRAW_ALIASES, *(n for n in values if n not in GAP_DRAW_ALIASES.values())])
            raise ParameterError(f"GapAnalysis.draws: no draws named {name!r}; the names are {names}")
        return np.asarray(values[key])

    @property
    def edl_parameters(self) -> dict[str, dict[str, object]]:
        """Every parameter of the EDL model with its uncertainty: ``value``, ``q05``, ``q95``
        the posterior median and 90 % interval (hierarchical: of the population median, a typical
        trial's value), ``unit``, and ``fit_value``, ``fit_stderr`` the least-squares fit on the
        trial-mean remainder (None for u, which the fit does not have)."""
        units = {row["name"]: row["unit"] for row in self.edl_fit.to_table()}
        units["u"] = "m"
        fitted, stderr = dict(self.edl_fit.values), dict(self.edl_fit.stderr)
        out = {}
        for name, draws in self._all_draws().items():
            q05, q50, q95 = np.quantile(np.asarray(draws, float), [0.05, 0.5, 0.95])
            out[name] = {"value": float(q50), "q05": float(q05), "q95": float(q95), "unit": units.get(name),
                         "fit_value": fitted.get(name), "fit_stderr": stderr.get(name)}
        return out

    def u_draws(self, max_draws: int = GAP_SAVED_DRAWS) -> np.ndarray:
        """The draws of u [m], thinned evenly to at most ``max_draws`` (what ``.nc`` saves)."""
        u = np.asarray(self.draws("u"), float)
        return u[:: max(1, -(-u.size // max_draws))]

    def _quantiles(self, name: str) -> dict[str, float]:
        q05, q50, q95 = np.quantile(self.draws(name), [0.05, 0.5, 0.95])
        return {"value": float(q50), "q05": float(q05), "q95": float(q95)}

    @property
    def gap_spread(self) -> dict[str, float] | None:
        """Spread of u between trials (hierarchical): ``relative`` (sd of ln u: median, q05,
        q95) and ``sd_m`` (≈ population median × relative sd, m). None when pooled."""
        if self.hierarchical is None:
            return None
        rel = self.hierarchical.spread_between_trials("u")
        return {"relative": {k: rel[k] for k in ("value", "q05", "q95")}, "sd_m": rel["value"] * self.gap["value"]}

    @property
    def gap_new_trial(self) -> dict[str, float] | None:
        """90 % predictive interval of u [m] for a new trial (hierarchical); None when pooled."""
        if self.hierarchical is None:
            return None
        q = self.hierarchical.new_trial("u")
        return {"value": q["value"], "q05": q["q05"], "q95": q["q95"]}

    @property
    def averages_trials(self) -> bool:
        """Whether the remainder is a mean over trials: some input holds more than one spectrum
        (the figure's data legend: a single sweep is no "mean of trials")."""
        return _several_spectra(self.remaining)

    @property
    def paper_has_bounds(self) -> bool:
        """False when total, skin and screen are one spectrum each: the paper's bounds (from the
        lowest- and highest-impedance trials) then equal its estimate and are no interval. The same
        inputs as `averages_trials`: an input of several spectra has a lowest and a highest one."""
        return self.averages_trials

    @property
    def paper_bounds_no_interval(self) -> bool:
        """True when a warning says the paper's bounds are no interval for its u (`_paper_interval_notes`:
        u outside them, or them much narrower than the single trials' spread; `_paper_bound_notes`:
        u far outside them)."""
        return any(w.startswith(("the paper method's bounds ", "the paper method's u = ")) for w in self.warnings)

    @property
    def c_gap(self) -> dict[str, float]:
        """Posterior median and 90 % interval of C_gap [F]."""
        return self._quantiles("C_gap")

    @property
    def gap(self) -> dict[str, float]:
        """Posterior median and 90 % interval of the gap thickness u [m]."""
        return self._quantiles("u")

    @property
    def _drive(self) -> DriveVoltage:
        """Where ``v0`` came from; a result made without it (read back from a file written by an
        older version, or built by hand) had it given."""
        return self.drive or DriveVoltage(self.v0, "given")

    def summary(self) -> dict:
        """The JSON used by ``impedax gap --json``."""
        gap_um = {k: v * 1e6 for k, v in self.gap.items()}
        with_ep = self.force.sel(branch="with_ep")
        spread, new = self.gap_spread, self.gap_new_trial
        return {
            "method": self.method,
            "c_gap": self.c_gap,
            "gap_um": gap_um,
            "gap_um_population": gap_um if self.hierarchical is not None else None,
            "interval_covers": self._interval_covers(),  # (what gap_um's q05–q95 holds; pooled: the trial means' noise only)
            "gap_um_spread": spread["sd_m"] * 1e6 if spread else None,
            "gap_spread_relative": spread["relative"] if spread else None,
            "gap_um_new_trial": {k: new[k] * 1e6 for k in ("q05", "q95")} if new else None,
            "discrepancy": self.hierarchical.summary()["discrepancy"] if self.hierarchical is not None else None,
            "force_n": {
                "frequency_hz": self.force["frequency"].values,
                "median": with_ep["median"].values,
                "q05": with_ep["q05"].values,
                "q95": with_ep["q95"].values,
            },
            "force_without_ep_n": {  # (the same frequencies as force_n: both branches are one force band over "frequency")
                "frequency_hz": self.force["frequency"].values,
                **{k: self.force.sel(branch="without_ep")[k].values for k in ("median", "q05", "q95")},
            },
            "gap_voltage_v": self._voltage_band("with_ep"),
            "gap_voltage_without_ep_v": self._voltage_band("without_ep"),
            "convention": FORCE_CONVENTION,
            "paper_method": {
                "c_gap": self.paper.c_gap,
                "c_gap_f": self.paper.c_gap,  # (the same F, its unit named)
                "gap_um": self.paper.gap * 1e6,
                "gap_bounds_um": [self.paper.gap_lower * 1e6, self.paper.gap_upper * 1e6] if self.paper_has_bounds else None,
                "gap_trials_um": [self.paper.gap_trial_min * 1e6, self.paper.gap_trial_max * 1e6] if np.isfinite(self.paper.gap_trial_min) else None,
                "gap_implausible": self.paper_gap_implausible,
                "cutoff_hz": self.paper.cutoff_hz,  # (the mean |Y_R|/ω is over the frequencies at and above it)
            },
            "force_conditions": self.force_conditions,
            "model": self.edl_fit.model,
            "model_requested": self.model_requested if self.model_requested is not None else self.edl_fit.model,
            "naive_rms_rel": self.naive_fit.rms_rel,
            "edl_rms_rel": self.edl_fit.rms_rel,
            "edl_chi2_red": self.edl_fit.chi2_red,  # (against the remainder's sigma under sigma weighting, the trial means' SEM)
            "area_m2": self.area,
            "v0": self.v0,
            **self._drive.summary(),
            "trials": self.trials,
            "warnings": list(self.warnings),
            "gap_identified": self.gap_identified,
            "gap_implausible": self.gap_implausible,  # (why u is no air gap, else null; gap_identified is then false)
            "gap_um_lower_bound": None if self.gap_lower_bound is None else self.gap_lower_bound * 1e6,
            "gap_bound_withheld": self.gap_bound_withheld,
            "edl_misfit": self.edl_misfit,
            "force_determined": self.gap_identified,
            "force_upper_bound_n": self._force_bound_summary(),
            "sampling": self._sampling_summary(),
            "pooled_sampling": self._pooled_chain_summary(),  # (--pooled: the emcee chain's figures, the report's sampling line; null when hierarchical)
            "edl_parameters": self.edl_parameters,
            "settings": dict(self.settings) if self.settings is not None else None,
            # (the verdicts the report states, and keys with their unit beside the older ones without)
            "force_max_n": self.force_at_max("with_ep"),
            "force_max_without_ep_n": self.force_at_max("without_ep"),
            "sampling_unreliable": self._sampling_unreliable(),
            "alarms": list(self.alarms),
            "c_gap_f": self.c_gap,
            "v0_v": self.v0,
            "single_contact": self.single_contact,  # (true when nothing was subtracted)
        }

    def _whole_drive_text(self) -> str:
        """A single contact whose C_gap takes the whole drive V0 at every frequency (C_gap
        parallel to the rest of the model, as in the EDL models: the gap-voltage band is V0
        within 1e-6): then the force is one value over frequency, with EP and without, and the
        report's "max … at" names the first frequency only."""
        if "gap_voltage_median" not in self.force:
            return ""
        volts = np.asarray(self.force["gap_voltage_median"].values, float)
        if not np.allclose(volts, self.v0, rtol=1e-6, atol=0.0):
            return ""
        return "; C_gap, parallel to the EP branch, carries the whole V0 at every frequency, so the force, F = ½ ε0 ε_gap A V0²/u², is the same at every frequency, with EP and without"

    @property
    def force_conditions(self) -> str:
        """What the force bands condition on (`FORCE_CONDITIONS`; a single contact's:
        `SINGLE_CONTACT_FORCE_CONDITIONS`)."""
        return SINGLE_CONTACT_FORCE_CONDITIONS if self.single_contact else force_conditions_of(self.remaining)

    def _force_bound_summary(self) -> dict | None:
        """The JSON's ``force_upper_bound_n``: the force [N] at u's lower bound over the force's
        frequencies (``frequency_hz``, ``value``) and its largest value (``max``, at
        ``max_frequency_hz``); None without a bound (`force_upper_bound`)."""
        bound = self.force_upper_bound
        if bound is None:
            return None
        i = int(np.argmax(bound.values))
        return {"frequency_hz": bound["frequency"].values, "value": bound.values, "max": float(bound.values[i]), "max_frequency_hz": float(bound["frequency"][i])}

    def _voltage_band(self, branch: str) -> dict | None:
        """The JSON's ``gap_voltage_v`` / ``gap_voltage_without_ep_v``: |ΔV_gap| [V] over the
        force's frequencies (``frequency_hz``, ``median``, ``q05``, ``q95``); None for a force
        band made without it."""
        if "gap_voltage_median" not in self.force:
            return None
        band = self.force.sel(branch=branch)
        return {"frequency_hz": self.force["frequency"].values, **{k: band[f"gap_voltage_{k}"].values for k in ("median", "q05", "q95")}}

    @checked_arguments(branch=choice(FORCE_BRANCHES))  # (another branch: this message, not xarray's KeyError)
    def gap_voltage_at_force_max(self, branch: str = "with_ep") -> dict[str, float] | None:
        """The amplitude of the gap voltage |ΔV_gap| [V] (``value`` its posterior median,
        ``q05``, ``q95``) at ``frequency_hz``, where the median PEAK force of ``branch``
        (``"with_ep"`` or ``"without_ep"``) is largest: the voltage behind the reported force
        maximum (eq 1, F = ½ ε0 ε_gap A |ΔV_gap|²/u²). None for a force band made without it."""
        if "gap_voltage_median" not in self.force:
            return None
        band = self.force.sel(branch=branch)
        i = int(np.argmax(band["median"].values))
        return {"frequency_hz": float(self.force["frequency"][i]), "value": float(band["gap_voltage_median"][i]),
                "q05": float(band["gap_voltage_q05"][i]), "q95": float(band["gap_voltage_q95"][i])}

    @checked_arguments(branch=choice(FORCE_BRANCHES))  # (another branch: this message, not xarray's KeyError)
    def force_at_max(self, branch: str = "with_ep") -> dict:
        """The PEAK force [N] (``value`` the posterior median, ``q05``, ``q95`` its 90 % band) at
        ``frequency_hz``, where the median force of ``branch`` (``"with_ep"`` or ``"without_ep"``)
        is largest on the force's frequency grid: the report's "force (peak …) max", the CSV's
        ``force_max_n`` and the JSON's ``force_max_n`` (eq 1, F = ½ ε0 ε_gap A |ΔV_gap|²/u²),
        with ``band_edge``, ``plateau_hz`` and ``edge_slope`` (`force_maximum_shape`)."""
        band = self.force.sel(branch=branch)
        shape = force_maximum_shape(band["median"])
        i = shape["index"]
        return {"frequency_hz": float(self.force["frequency"][i]), "value": float(band["median"][i]),
                "q05": float(band["q05"][i]), "q95": float(band["q95"][i]),
                # ("fmin"/"fmax" when the largest force is at an end of the band, "flat" when it is the same
                # at every frequency, else null; the plateau it lies on, else null)
                "band_edge": shape["band_edge"], "plateau_hz": list(shape["plateau_hz"]) if shape["plateau_hz"] else None,
                # (d ln F/d ln f over the grid's step at that end of the band, as impedax force's peak.edge_slope; else null)
                "edge_slope": shape["edge_slope"]}

    def _sampling_summary(self) -> dict | None:
        """Hierarchical: the NUTS diagnostics (divergent transitions of all draws, the largest
        R-hat and the smallest ESS of every sampled quantity: μ and the spreads, the shared
        parameters and δ, `HierarchicalPosterior.mixing`, as its warnings and report line read
        them; ``acceptance``, NUTS's mean acceptance probability, which the report's sampling
        line gives); None when pooled."""
        post = self.hierarchical
        if post is None:
            return None
        rhat, ess = post.mixing()
        return {"divergences": post.divergences, "draws": post.n_draws, "rhat_max": max(rhat.values()), "ess_min": min(ess.values()), "rhat": rhat, "ess": ess,
                "acceptance": float(post.mean_acceptance)}

    def _sampling_unreliable(self) -> bool:
        """Hierarchical: more than `SAMPLING_DIVERGENT_MAX` of the draws divergent, or an R-hat
        not below `SAMPLING_RHAT_MAX` (the report's "SAMPLING UNRELIABLE")."""
        d = self._sampling_summary()
        return d is not None and (d["divergences"] > SAMPLING_DIVERGENT_MAX * d["draws"] or not d["rhat_max"] < SAMPLING_RHAT_MAX)

    def _sampling_alarm(self) -> str:
        d = self._sampling_summary()
        return f"SAMPLING UNRELIABLE: {d['divergences']} divergent transitions of {d['draws']} draws, R-hat up to {d['rhat_max']:.3f}, ESS down to {d['ess_min']:.0f}"

    @property
    def alarms(self) -> tuple[str, ...]:
        """The states that void the result, as the report's first lines name them, short (the
        figure's red banner): "MODEL DOES NOT FIT" (`edl_misfit`), "SAMPLING UNRELIABLE"
        (hierarchical NUTS diagnostics), "NO AIR GAP" (`gap_implausible`) and
        "PAPER METHOD: NO AIR GAP" (`paper_gap_implausible`); empty when none holds. A u the
        data do not split from the EP branch is marked apart (`gap_identified`)."""
        out = []
        if self.edl_misfit is not None:
            out.append("MODEL DOES NOT FIT: u, its interval and the force rest on a model the data reject")
        if self._sampling_unreliable():
            out.append(f"{self._sampling_alarm()}: the bands may be wrong")
        if self.gap_implausible is not None:
            out.append(f"{NO_AIR_GAP}: {self.gap_implausible}; u, C_gap and the force are no measurement")
        if self.paper_gap_implausible is not None:
            out.append(f"PAPER METHOD: {NO_AIR_GAP}: {self.paper_gap_implausible}; its u and C_gap are no measurement")
        return tuple(out)

    def to_table(self) -> list[dict[str, object]]:
        """The table of ``--out FILE.csv``: one row per ``method``, bayes (C_gap and u their
        posterior medians, low/high the 90 % credible interval) and paper (the paper's method:
        u's low/high its bounds from the lowest/highest impedances, None with one trial of each;
        C_gap none). Every column name carries its SI unit (`GAP_TABLE_COLUMNS`: ``_f`` farad,
        ``_m`` metre; the JSON's ``gap_um`` are the same u in µm); ``gap_identified`` and
        ``u_lower_bound_m`` (the bound u ≥ when u is not determined) and ``u_lower_bound_withheld``
        (why there is none although u is not determined) on the bayes row. Then one
        ``bayes_parameter`` row per parameter of the EDL model (`edl_parameters`): ``parameter``,
        ``value``, ``low``, ``high`` (posterior median, 90 % interval), ``unit`` (SI, the element's),
        ``fit_value``, ``fit_stderr`` (the least-squares fit on the trial mean).
        The bayes row also gives the gap voltage at the force maximum with EP
        (`gap_voltage_at_force_max`: ``gap_voltage_v``, ``_low_v``, ``_high_v`` at
        ``force_max_frequency_hz``), the PEAK force there (`force_at_max`:
        ``force_max_n``, ``_low_n``, ``_high_n``), ``force_upper_bound_max_n`` (`force_upper_bound`'s
        largest value, else empty), ``sampling_unreliable``, ``n_warnings`` and the ``warnings`` and
        ``alarms`` (`alarms`), one per line in the cell."""
        p = self.paper
        c, g = self.c_gap, self.gap
        low, high = (p.gap_lower, p.gap_upper) if self.paper_has_bounds else (None, None)
        v = self.gap_voltage_at_force_max() or dict.fromkeys(("frequency_hz", "value", "q05", "q95"))
        force = self.force_at_max("with_ep")
        bayes = {
            "method": "bayes", "c_gap_f": c["value"], "c_gap_low_f": c["q05"], "c_gap_high_f": c["q95"], "u_m": g["value"], "u_low_m": g["q05"], "u_high_m": g["q95"],
            "gap_identified": self.gap_identified, "u_lower_bound_m": self.gap_lower_bound, "u_lower_bound_withheld": self.gap_bound_withheld,
            "force_max_frequency_hz": force["frequency_hz"], "gap_voltage_v": v["value"], "gap_voltage_low_v": v["q05"], "gap_voltage_high_v": v["q95"],
            "force_max_n": force["value"], "force_max_low_n": force["q05"], "force_max_high_n": force["q95"],
            "force_upper_bound_max_n": None if self.force_upper_bound is None else float(self.force_upper_bound.max()),
            "v0_v": self.v0, "v0_from": self._drive.source,  # (the drive the forces are for, and where it came from)
            # (verdicts as cells of the row they qualify, one per line: no comment line, which csv.DictReader would take for the header,
            # and no extra rows, which would break reading the rows after bayes and paper as the parameters)
            "sampling_unreliable": self._sampling_unreliable(), "n_warnings": len(self.warnings), "warnings": "\n".join(self.warnings), "alarms": "\n".join(self.alarms),
            "single_contact": self.single_contact,
        }
        return [
            bayes,
            {"method": "paper", **dict.fromkeys(GAP_TABLE_COLUMNS[1:]), "c_gap_f": p.c_gap, "u_m": p.gap, "u_low_m": low, "u_high_m": high},
            *({"method": "bayes_parameter", "parameter": name, "value": q["value"], "low": q["q05"], "high": q["q95"], "unit": q["unit"],
               "fit_value": q["fit_value"], "fit_stderr": q["fit_stderr"]} for name, q in self.edl_parameters.items()),
        ]

    def report(self) -> str:
        g, c, p = self.gap, self.c_gap, self.paper
        peak = self.force.sel(branch="with_ep")["median"]
        bare = self.force.sel(branch="without_ep")["median"]  # (C_gap alone: the JSON's force_without_ep_n)
        band = _gap_range(g["q05"], g["q95"])
        if self.gap_identified:
            head, interval = "gap thickness u", f"90 % credible interval {band}"
        elif self._prior_set:  # (the range first, then what it is not: after "not of the gap" it read as the gap's)
            head, interval = "sampled u (prior-set)", f"90 % interval of the draws: {band}, set by the priors, not a range of the gap"
        else:
            head, interval = "sampled u (NO AIR GAP)" if self.gap_implausible is not None else "sampled u", f"90 % interval of the draws: {band}, not a range of the gap"
        if self.hierarchical is not None:
            spread, new = self.gap_spread, self.gap_new_trial
            lines = [
                f"{head} = {_gap_length(g['value'])}  (population median of the trials; {interval}, hierarchical Bayesian, {self.edl_fit.model})",
                f"between trials  u varies by {spread['relative']['value'] * 100:.1f} % (sd of ln u; 90 %: {spread['relative']['q05'] * 100:.1f}–{spread['relative']['q95'] * 100:.1f} %), ≈ {spread['sd_m'] * 1e6:.3f} µm",
                f"a new trial     u in {new['q05'] * 1e6:.3f}–{new['q95'] * 1e6:.3f} µm (90 % predictive interval)",
            ]
        else:
            lines = [f"{head} = {_gap_length(g['value'])}  ({interval}, {self._pooled_noise_text()}; {self.edl_fit.model})"]
        bounds = f"(bounds {_gap_range(p.gap_lower, p.gap_upper)} from the lowest/highest impedances{'; no interval for u, see the warning' if self.paper_bounds_no_interval else ''})" if self.paper_has_bounds else "bounds n/a (one trial)"
        lines += [
            f"paper method    u = {_gap_length(p.gap)}{f' ({NO_AIR_GAP})' if self.paper_gap_implausible is not None else ''}  {bounds}",
            f"C_gap{' (prior-set)' if self._prior_set else '          '} = {_capacitance_with_interval(c)}; paper method {format_quantity(p.c_gap, 'F', CAPACITANCE_DIGITS)} (mean |Y_R|/ω at and above {p.cutoff_hz:g} Hz, Sirin §2.3)",
            f"fits            naive C_gap: rms_rel {format_percent(self.naive_fit.rms_rel)};  {self.edl_fit.model}: rms_rel {format_percent(self.edl_fit.rms_rel)}{_edl_chi2_text(self.edl_fit, self.remaining)}",
            self._sampling_line(),
            f"force (peak, V0 = {self.v0:.4g} V){self._force_qualifier()} with EP: {force_maximum_text(peak)}; without EP: {force_maximum_text(bare)}",
            self._force_interval_line(),
            f"force bands     {self.force_conditions} (A = {self.area:g} m², i.e. {self.area * 1e6:g} mm²)",
        ]
        if self.single_contact:
            lines.insert(next(k for k, line in enumerate(lines) if line.startswith("paper method")), f"mode            {SINGLE_CONTACT_NOTE}{self._whole_drive_text()}")
        voltages = [(what, self.gap_voltage_at_force_max(branch)) for what, branch in (("with EP", "with_ep"), ("without EP", "without_ep"))]
        if all(v is not None for _, v in voltages):
            lines.insert(-1, "gap voltage     |ΔV_gap| (amplitude) at each force maximum: " + "; ".join(
                f"{what}: {_volts_with_interval(v)} at {format_frequency(v['frequency_hz'])}" for what, v in voltages))
        lines.append(f"drive V0        {self._drive.description}")
        lines.append(f"gap medium      {medium_text((self.settings or {}).get('eps_gap', EPSILON_AIR))}")
        bound_line = self._force_bound_line()
        if bound_line:
            lines.insert(next(k for k, line in enumerate(lines) if line.startswith("force (peak")) + 1, bound_line)
        if self.trials:
            lines.append("spectra used    " + "; ".join(_trials_text(k, v) for k, v in self.trials.items()))
        if self.gap_lower_bound is not None:
            lines.insert(0, (
                f"GAP NOT DETERMINED: C_gap and the EP branch are seen only as their sum, so the data give only a LOWER BOUND u ≥ {_gap_length(self.gap_lower_bound)} "
                "(all the capacitance counted as C_gap); the u and interval below are set by the priors and the split, not the data"
            ))
        elif self.gap_bound_withheld is not None:
            lines.insert(0, (
                f"GAP NOT DETERMINED, AND NO BOUND: C_gap and the EP branch are not told apart, and {self.gap_bound_withheld}; "
                "the u and interval below are set by the priors and the split, not the data"
            ))
        if self.paper_gap_implausible is not None:
            lines.insert(0, f"PAPER METHOD: {NO_AIR_GAP}: {self.paper_gap_implausible}; its u and C_gap below are no measurement")
        if self.gap_implausible is not None:
            lines.insert(0, f"{NO_AIR_GAP}: {self.gap_implausible}; u, C_gap and the force below are no measurement: {self._implausible_advice()}")
        if self.edl_misfit is not None:
            lines.insert(0, (
                f"MODEL DOES NOT FIT: {self.edl_misfit}; u, its interval and the force below rest on a model the data reject: "
                + ("check the file (impedax diagnose on it) before reading any of them" if self.single_contact else "check the three files (impedax remaining, impedax diagnose on the remainder) before reading any of them")
            ))
        if self._sampling_unreliable():
            lines.insert(0, (
                f"{self._sampling_alarm()}: "
                "the interval below may be wrong; rerun with more draws (--steps 2000) or another --seed, or use --pooled (the trial means)"
            ))
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines)

    @property
    def _prior_set(self) -> bool:
        """u and C_gap are set by the priors, not by the data: u piled up at a bound of its prior
        (`_u_piled_bounds`), or not split from the EP branch, but with ``--ep C``, whose C_gap is the
        summed capacitance C_EP + C_gap."""
        if self._u_piled_bounds:
            return True
        return not self._split_determined and not (self.ep == "C" and self.edl_fit.model == IDENTIFIED_C_REMAINDER)

    def _implausible_advice(self) -> str:
        """What to check when u is no air gap (`gap_implausible`): the area's unit first, unless the
        paper's method gives an air gap at this area, which a unit slip would not (`_area_advice`)."""
        files = "the spectrum" if self.single_contact else "the three spectra"
        if self.paper_gap_implausible is None:
            return f"{_area_unit_ruled_out(self.paper.gap, self.area)}: check {files} and the model"
        return f"{AREA_UNIT_ADVICE}, A = {self.area:g} m² ({self.area * 1e6:g} mm²; 200 mm² is 200e-6 m²), then {files}"

    def _force_qualifier(self) -> str:
        """What the sampled force line is when u is not determined: with ``--ep C`` the force at
        the summed capacitance's gap (u at its smallest, so the force at its largest); else the
        force of a u the priors set, no estimate (docs/models.md, "The force when u is not
        determined")."""
        if self.gap_identified:
            return ""
        if self._prior_set:
            return " of the prior-set u, NO ESTIMATE of the force:"
        if self._split_determined:
            return " of a u that is no air gap, NO ESTIMATE of the force:"
        if self.gap_bound_withheld is not None:  # (the summed capacitance's model misses the data: its gap bounds nothing, as the report's alarm says)
            return " at the gap of the summed capacitance, which bounds nothing here (u may lie below it), NO ESTIMATE of the force nor its bound:"
        return " at the gap of the summed capacitance (u's smallest value, so the force's largest),"

    def _sampling_line(self) -> str:
        """The report's ``sampling`` line: hierarchical, the NUTS figures of `_sampling_summary`
        (every sampled quantity's R-hat and ESS), the mean acceptance and the verdict of its checks
        (SAMPLING UNRELIABLE's rule); pooled, emcee's walkers, steps, burn, acceptance, the
        largest τ [steps], the smallest ESS and how many τ the kept chain is (50 needed)."""
        head = "sampling        "
        if self.hierarchical is not None:
            d = self._sampling_summary()
            verdict = (f"FAILED its checks (R-hat < {SAMPLING_RHAT_MAX:g}, at most {SAMPLING_DIVERGENT_MAX * 100:.0f} % divergent): see SAMPLING UNRELIABLE above"
                       if self._sampling_unreliable() else f"passed its checks (R-hat < {SAMPLING_RHAT_MAX:g}, at most {SAMPLING_DIVERGENT_MAX * 100:.0f} % divergent)")
            return (f"{head}hierarchical NUTS, {d['draws']} draws: {d['divergences']} divergent, R-hat up to {d['rhat_max']:.3f}, ESS down to {d['ess_min']:.0f} "
                    f"(of every sampled quantity), mean acceptance {d['acceptance']:.2f}: {verdict}")
        c = self._pooled_chain_summary()
        stopped = {"converged": f", automatic: stopped at {CHAIN_TAU_MULTIPLE} τ", "cap": ", automatic: stopped at its cap"}.get(c["stopped"], "")
        line = f"{head}emcee, {c['walkers']} walkers × {c['steps']} steps (burn {c['burn']}{stopped}), acceptance {c['acceptance']:.2f}, "
        if c["chain_tau"] is None:
            return line + "τ unknown: the chain is too short to estimate it (see the warning)"
        enough = f" (≥ {CHAIN_TAU_MULTIPLE} τ)" if c["chain_converged"] else f", under the {CHAIN_TAU_MULTIPLE} τ it needs (see the warning)"
        return line + f"τ up to {c['autocorr_max_steps']:.3g} steps, ESS down to {c['ess_min']:.0f}: the kept chain is {c['chain_tau']:.3g} τ long{enough}"

    def _pooled_chain_summary(self) -> dict | None:
        """Pooled: the emcee chain's figures (the JSON's ``pooled_sampling``, the report's
        ``sampling`` line): ``walkers``, ``steps``, ``burn``, ``stopped`` (``"converged"``,
        ``"cap"``, null for a fixed length), ``acceptance`` (mean fraction), ``autocorr_max_steps``
        (the largest τ [steps]) and ``ess_min`` (null where τ is unknown), ``chain_tau`` (the kept
        chain, steps − burn, in units of that τ; null when unknown) and ``chain_converged`` (≥ 50 τ
        for every parameter); None when hierarchical."""
        post = self.posterior
        if self.hierarchical is not None or post is None:
            return None
        settings = post.settings
        steps, burn = int(settings["steps"]), int(settings["burn"])
        tau = np.array([np.nan if t is None else t for t in post.autocorr.values()], float)
        ess = np.array([np.nan if e is None else e for e in post.ess.values()], float)
        known = bool(tau.size and np.all(np.isfinite(tau)))
        return {"walkers": int(post.n_walkers), "steps": steps, "burn": burn, "stopped": settings.get("stopped"), "acceptance": float(post.mean_acceptance),
                "autocorr_max_steps": float(np.max(tau)) if known else None, "ess_min": float(np.min(ess)) if known else None,
                "chain_tau": (steps - burn) / float(np.max(tau)) if known else None, "chain_converged": bool(post.chain_converged)}

    def _force_interval_line(self) -> str:
        """The report's ``force 90 %`` line: the 90 % band of the PEAK force at each branch's
        maximum (`force_at_max`, the CSV's ``force_max_low_n``/``force_max_high_n``), in the SI
        prefix of its median: ``with EP 337–369 mN at 31.6 Hz; without EP …``; "of the draws, no
        estimate" when u is not determined (the force line's NO ESTIMATE)."""
        parts = []
        for what, branch in (("with EP", "with_ep"), ("without EP", "without_ep")):
            q = self.force_at_max(branch)
            scale, prefix = si_prefix(abs(q["value"])) if q["value"] else (1.0, "")
            parts.append(f"{what} {q['q05'] / scale:.3g}–{q['q95'] / scale:.3g} {prefix}N at {format_frequency(q['frequency_hz'])}")
        what = "credible band of the peak force" if self.gap_identified else "interval of the draws' peak force (no estimate: see the force line)"
        return f"force 90 %      {what} at each maximum: " + "; ".join(parts)

    def _force_bound_line(self) -> str | None:
        """The report's ``force bound`` line when u is not determined: the largest force the data
        allow (`force_upper_bound`), or that there is none."""
        if self.gap_identified:
            return None
        if self.force_upper_bound is None:
            return "force bound     none: u has no lower bound here, so the data bound the force neither (eq 1 goes as 1/u²)"
        bound = self._force_bound_summary()
        return (
            f"force bound     F ≤ {format_quantity(bound['max'], 'N')} (peak, with EP, largest at {format_frequency(bound['max_frequency_hz'])}): "
            f"eq 1 at u's lower bound {_gap_length(self.gap_lower_bound)}, the smallest u and so the largest force the data allow (F ∝ 1/u²)"
        )

    def _interval_covers(self) -> str:
        """What u's 90 % interval holds (``interval_covers`` in the JSON): the hierarchical one the
        spread between trials and the model discrepancy; the pooled one the noise of the trial means
        only (`_pooled_noise_text`): an interval for these trials' mean u, not for the population's.
        SYNTHETIC Sirin example of seed 1: pooled 2.759–2.775 µm holds the 30 trials' true mean u,
        2.764 µm, not the median 2.789 µm they were drawn about (their u scatter by 6.4 %); the
        hierarchical 2.705–2.815 µm holds both."""
        if self.hierarchical is not None:
            return "the population median of the trials' u: the spread between trials and the model discrepancy included"
        return self._pooled_noise_text() + "; an interval for these trials' mean u, not for the population's (impedax gap without --pooled gives that)"

    def _pooled_noise_text(self) -> str:
        """What the pooled interval's noise is: the trial means' SEM (``sigma`` of the
        remainder; with one spectrum per file, their stated sigma), else, with an input of a single spectrum, noise proportional to |Z| at a
        level sampled from the fit's residuals (`impedax.fitting.sample`'s ``proportional``)."""
        if "sigma" in self.remaining and not self.averages_trials:  # (one spectrum per file, each with its sigma)
            return "Bayesian on one spectrum per file, weighted by their stated sigma: their noise only, not a spread between trials"
        if "sigma" in self.remaining:
            return "Bayesian on the trial means: their noise only, not the spread between trials"
        proportional = "noise ∝ |Z| at a sampled level (sigma_rel: the fit's residual scatter), not a measured noise nor a spread between trials"
        if not self.averages_trials:
            return f"Bayesian on one spectrum per file: {proportional}"
        return f"Bayesian on the trial means without their SEM (an input holds a single spectrum): {proportional}"

    @checked_arguments(true_gap=real(positive=True, optional=True))  # (text or -1: this message, not a TypeError or -1 drawn as a gap)
    def plot(self, *, true_gap: float | None = None, figsize: tuple[float, float] | None = None):
        """Remaining impedance with both fits, the posterior of u against the paper's bounds
        (and ``true_gap`` [m] when known, e.g. for synthetic data), and the force bands with and
        without the EP branch (matplotlib Figure; ``figsize`` (width, height) [in], default
        15 × 4.6)."""
        from ..plotting.models import plot_gap_analysis

        return plot_gap_analysis(self, true_gap=true_gap, figsize=figsize)

    def to_xarray(self) -> xr.Dataset:
        """The force bands with the gap summary as attrs (what ``--out FILE.nc`` writes): C_gap
        and u quantiles, the paper method (``paper_gap_um``, ``paper_gap_lower_um``,
        ``paper_gap_upper_um`` — NaN with one spectrum per file — and ``paper_c_gap_pf``) and
        ``warnings``, one string with a warning per line (``n_warnings`` of them), the
        ``setting_*`` it ran with (`settings`), the EDL parameters over ``parameter``
        (``parameter_value``, ``_q05``, ``_q95``, ``_fit_value``, ``_fit_stderr``, ``_unit``:
        `edl_parameters`) and u's draws ``u_draws`` [m] over ``draw`` (`u_draws`, at most
        `GAP_SAVED_DRAWS`); every variable has a ``long_name`` and, where it
        has one unit, ``units`` (`GAP_VARIABLE_LABELS`), and the attrs
        ``sampling_unreliable`` (1/0) and ``alarms`` (`alarms`, one per line); ``impedax_kind``
        ``"gap_analysis"`` marks the file (``impedax.load`` refuses it as a spectrum and names
        `impedax.io.read_netcdf`, which reads it)."""
        out = self.force.copy()
        for key, value in self.summary().items():
            if key in ("c_gap", "gap_um", "gap_um_new_trial") and value is not None:
                for k, v in value.items():
                    out.attrs[f"{key}_{k}"] = v
        out.attrs.update({"impedax_kind": "gap_analysis", "convention": FORCE_CONVENTION, "model": self.edl_fit.model, "model_requested": self.summary()["model_requested"], "area_m2": self.area, "v0": self.v0, "v0_from": self._drive.source, "method": self.method})
        if self.gap_spread is not None:
            out.attrs["gap_spread_relative"] = self.gap_spread["relative"]["value"]
        p, bounds = self.paper, self.paper_has_bounds
        out.attrs.update({
            "paper_gap_um": p.gap * 1e6,
            "paper_gap_lower_um": p.gap_lower * 1e6 if bounds else float("nan"),
            "paper_gap_upper_um": p.gap_upper * 1e6 if bounds else float("nan"),
            "paper_c_gap_pf": p.c_gap * 1e12,
            "gap_identified": int(self.gap_identified),
            "gap_um_lower_bound": float("nan") if self.gap_lower_bound is None else self.gap_lower_bound * 1e6,
            "force_upper_bound_max_n": float("nan") if self.force_upper_bound is None else float(self.force_upper_bound.max()),
            "n_warnings": len(self.warnings),
            "warnings": "\n".join(self.warnings),
            "sampling_unreliable": int(self._sampling_unreliable()),
            "alarms": "\n".join(self.alarms),
            "single_contact": int(self.single_contact),
        })
        out.attrs.update({f"setting_{k}": v for k, v in (self.settings or {}).items() if v is not None})
        table = self.edl_parameters
        out = out.assign_coords(parameter=list(table))
        for key in ("value", "q05", "q95", "fit_value", "fit_stderr"):
            out[f"parameter_{key}"] = ("parameter", [np.nan if q[key] is None else float(q[key]) for q in table.values()])
        out["parameter_unit"] = ("parameter", [q["unit"] or "" for q in table.values()])
        out["parameter_value"].attrs["description"] = "posterior median (hierarchical: of the population median); q05/q95 the 90 % interval; fit_* the least-squares fit on the trial mean"
        out["u_draws"] = ("draw", self.u_draws(), {"units": "m", "description": f"posterior draws of the gap thickness u, thinned evenly to at most {GAP_SAVED_DRAWS}"})
        return result_dataset(_labelled(out).copy(deep=True))


# what each variable of a saved gap analysis (`GapAnalysis.to_xarray`) is: long_name and SI units
# (None: the variable has no single unit, as the parameters' own, or is text)
_FORCE_BAND = "PEAK force (Sirin eq 1 at the drive amplitude v0) over frequency, {}"
_VOLTAGE_BAND = "amplitude |ΔV_gap| of the voltage across C_gap for a drive of amplitude v0 (Sirin §2.4), {}"
GAP_VARIABLE_LABELS = {
    "frequency": ("frequency", "Hz"),
    "branch": ("remainder model of the force: with_ep (the EDL model) or without_ep (C_gap alone)", None),
    "median": (_FORCE_BAND.format("posterior median"), "N"),
    "q05": (_FORCE_BAND.format("5 % quantile (lower end of the 90 % band)"), "N"),
    "q95": (_FORCE_BAND.format("95 % quantile (upper end of the 90 % band)"), "N"),
    "gap_voltage_median": (_VOLTAGE_BAND.format("posterior median"), "V"),
    "gap_voltage_q05": (_VOLTAGE_BAND.format("5 % quantile"), "V"),
    "gap_voltage_q95": (_VOLTAGE_BAND.format("95 % quantile"), "V"),
    "parameter": ("parameter of the EDL model", None),
    "parameter_value": ("posterior median of the parameter (its unit: parameter_unit)", None),
    "parameter_q05": ("5 % posterior quantile of the parameter (its unit: parameter_unit)", None),
    "parameter_q95": ("95 % posterior quantile of the parameter (its unit: parameter_unit)", None),
    "parameter_fit_value": ("least-squares value on the trial-mean remainder (its unit: parameter_unit)", None),
    "parameter_fit_stderr": ("standard error of the least-squares value (its unit: parameter_unit)", None),
    "parameter_unit": ("SI unit of the parameter", None),
    "u_draws": ("posterior draws of the gap thickness u", "m"),
}
"""What `GapAnalysis.to_xarray` labels each variable with: ``long_name``, and ``units`` where the
variable has one (the force's ``median``, ``q05``, ``q95`` among them, named as a force)."""


def _labelled(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` with `GAP_VARIABLE_LABELS`' ``long_name`` and ``units`` on each variable it has
    (the attrs already there kept, but for these two)."""
    for name, (long_name, units) in GAP_VARIABLE_LABELS.items():
        if name in ds.variables:
            ds[name].attrs.update({"long_name": long_name, **({"units": units} if units else {})})
    return ds


def _gap_length(u: float, digits: int | None = None) -> str:
    """A gap thickness u [m] as the report gives it: within `PLAUSIBLE_GAP_M` in µm, to 3
    decimals (``2.805 µm``) or to ``digits`` significant digits (bounds 0.126–0.134, not
    0.13–0.13); else with the SI prefix of its size, ``1.15 m``, ``50.6 pm`` (not
    "1150016.575 µm" and "0.000 µm", as in a resistive remainder's notes)."""
    low, high = PLAUSIBLE_GAP_M
    if low <= u <= high:
        return f"{_micrometres(u, digits)} µm"
    return format_quantity(u, "m") if digits is None else format_quantity(u, "m", digits)


def _micrometres(u: float, digits: int | None = None) -> str:
    """u [m] in µm without the unit: to 3 decimals (``2.805``), or to 3 significant digits below
    0.1 µm, where 3 decimals keep fewer (``0.00594``; the REAL Gamry file's paper u, not
    "0.006 µm" beside its 4-digit C_gap); to ``digits`` significant digits if given."""
    if digits is not None:
        return f"{u * 1e6:.{digits}g}"
    return f"{u * 1e6:.3f}" if u >= 1e-7 else f"{u * 1e6:.3g}"


def _gap_range(low: float, high: float, digits: int | None = None) -> str:
    """``2.797–2.814 µm`` (``2.15–2.21 µm`` to 3 ``digits``), or ``1.14 m–1.15 m`` when an end
    is no air gap (`_gap_length`)."""
    a, b = PLAUSIBLE_GAP_M
    if a <= low <= b and a <= high <= b:
        return f"{_micrometres(low, digits)}–{_micrometres(high, digits)} µm"
    return f"{_gap_length(low, digits)}–{_gap_length(high, digits)}"


CAPACITANCE_DIGITS = 4
"""Significant digits of C_gap in the report: 221.3 pF (90 %: 220.9–221.8 pF), as the 0.1 pF it had."""


def _capacitance_with_interval(q: Mapping[str, float]) -> str:
    """``221.3 pF (90 %: 220.9–221.8 pF)``, ``1.001 fF (90 %: 1–1.008 fF)``: C_gap [F] and its
    interval in the SI prefix of its median (`si_prefix`), `CAPACITANCE_DIGITS` significant
    (not "0.0 pF (90 %: 0.0–0.0 pF)" for 1 fF)."""
    scale, prefix = si_prefix(abs(q["value"])) if q["value"] else (1e-12, "p")
    n = CAPACITANCE_DIGITS
    return f"{q['value'] / scale:.{n}g} {prefix}F (90 %: {q['q05'] / scale:.{n}g}–{q['q95'] / scale:.{n}g} {prefix}F)"


def _volts_with_interval(q: Mapping[str, float]) -> str:
    """``71.00 V (90 %: 70.95–71.05 V)``: a voltage and its interval to the fewest significant
    digits, 3 or 4 (`VOLTAGE_DIGITS_MAX`), that tell the interval's ends apart; ends alike to 4
    digits are printed once, ``100.0 V (90 %: ≈ 100.0 V)`` (not "99.999927 V (90 %:
    99.999925–99.999928 V)", a precision no measured V0 has)."""
    apart = _distinct_digits(q["q05"], q["q95"])
    digits = apart or VOLTAGE_DIGITS_MAX
    if not apart:
        return f"{_volts(q['value'], digits)} V (90 %: ≈ {_volts(q['q95'], digits)} V)"
    return f"{_volts(q['value'], digits)} V (90 %: {_volts(q['q05'], digits)}–{_volts(q['q95'], digits)} V)"


FLAT_FORCE_REL = 1e-3
"""A force whose median varies over the band by less than this fraction of its maximum is flat
(`force_maximum_text`): a single contact's force without EP is ½ ε0 ε_gap A V0²/u² at every
frequency, to rounding."""


def _flat(values: np.ndarray) -> bool:
    """Whether a median force over frequency is flat (`FLAT_FORCE_REL`)."""
    return bool(values.size > 1 and np.all(np.isfinite(values)) and values.max() - values.min() <= FLAT_FORCE_REL * abs(values.max()))


def force_maximum_shape(median: xr.DataArray) -> dict:
    """Where the median force over frequency is largest and what kind of maximum it is:
    ``index`` of the grid's largest value, ``band_edge`` ``"fmin"`` or ``"fmax"`` when that is an
    end of the band (the force may still rise past it), ``"flat"`` for a force the same at every
    frequency (`FLAT_FORCE_REL`; as `impedax force` says it: a single contact's is no "fmin")
    else None, and ``plateau_hz`` (low, high): the contiguous frequencies about it
    within `FORCE_PLATEAU_REL` of it, when they span more than `FORCE_PLATEAU_SPAN`, else None;
    ``edge_slope``: d ln F/d ln f over the grid's step at that end of the band (`grid_edge_slope`),
    None for a maximum inside the band or a flat force (as `impedax force`'s
    ``peak.edge_slope``)."""
    values, freq = np.asarray(median.values, float), np.asarray(median["frequency"].values, float)
    i = int(np.argmax(values))
    edge = ("fmin" if freq[i] == freq.min() else "fmax") if values.size > 1 and freq[i] in (freq.min(), freq.max()) else None
    if _flat(values):
        edge = "flat"
    slope = grid_edge_slope(freq, values, i) if edge in ("fmin", "fmax") else None
    return {"index": i, "band_edge": edge, "plateau_hz": force_plateau(freq, values, i), "edge_slope": slope}


def force_maximum_text(median: xr.DataArray) -> str:
    """``max 408 mN at 31.6 Hz`` of a median force over frequency; a flat one (`FLAT_FORCE_REL`)
    ``2.835 N at every frequency (1 Hz–100 kHz)``: its maximum's frequency is rounding's choice
    (a single contact's force without EP, not "max 2.835 N at 1 Hz"); one on a
    plateau (`force_maximum_shape`) ``412 mN on a plateau over 1 Hz–22.4 Hz (within 1 %;
    largest at 1 Hz, the band's lower end)``; one at an end of the band says what the grid's last
    step there shows (`band_end_words`, as `impedax force` does): ``max 56.2 N at 1 Hz, the band's
    lower end, and still rises below it (∝ f^-0.41 there)``, or ``…, where it has levelled off: it
    changes by 0.3 % per decade there (it may still rise below 1 Hz, as slowly)`` (not
    always ``(it may rise past it)``). The maximum of the grid's medians, not refined
    between grid points as `impedax force` refines a model's force (`impedax.models.force_maximum`):
    a median over posterior draws has no value between them. `impedax gap`'s report and
    `impedax demo`'s "peak force with EP" write it so."""
    values, freq = np.asarray(median.values, float), np.asarray(median["frequency"].values, float)
    shape = force_maximum_shape(median)
    i = shape["index"]
    if shape["band_edge"] == "flat":
        return f"{format_quantity(float(values[i]), 'N')} at every frequency ({format_band(float(freq.min()), float(freq.max()))})"
    end = {"fmin": "the band's lower end", "fmax": "the band's upper end"}.get(shape["band_edge"])
    if shape["plateau_hz"] is not None:
        low, high = shape["plateau_hz"]
        return (f"{format_quantity(float(values[i]), 'N')} on a plateau over {format_band(low, high)} (within {FORCE_PLATEAU_REL * 100:.0f} %; "
                f"largest at {format_frequency(float(freq[i]))}{', ' + end if end else ''})")
    if end:
        side = "below" if shape["band_edge"] == "fmin" else "above"
        return f"max {format_quantity(float(values[i]), 'N')} at {format_frequency(float(freq[i]))}, {end}, {band_end_words(shape['edge_slope'], side, format_frequency(float(freq[i])))}"
    return f"max {format_quantity(float(values[i]), 'N')} at {format_frequency(float(freq[i]))}"


def _trials_text(name: str, used: dict) -> str:
    """``total 10 (sweep 0, 1, 2, …, 9)``: how many spectra of an input were analysed, and which."""
    labels = ["/".join(map(str, v)) if isinstance(v, list) else str(v) for v in used["labels"]]
    shown = ", ".join(labels if len(labels) <= 8 else labels[:3] + ["…"] + labels[-2:])
    what = "/".join(f"{d} position" if d in used.get("by_position", ()) else d for d in used["dims"])
    _, selected, selection = str(used.get("source") or "").partition(" [")  # (`select_spectra`'s ``path [DIM=LABEL]``)
    picked = f" [selected {selection}" if selected else ""
    return f"{name} {used['count']}" + (f" ({what} {shown})" if labels else "") + picked


def medium_text(eps_gap: float) -> str:
    """The report's ``gap medium`` line: the relative permittivity ε_gap of u = ε0 ε_gap A/C_gap
    and of the force (eq 1), and where it came from: air's 1.00059 (Sirin et al.), the default,
    or given (``impedax gap --eps-gap``; Python ``eps_gap``), e.g. a dielectric film in a
    gripper pad's gap. u scales with it: the same C_gap gives 3.4× the gap in a film of ε_r 3.4."""
    used = "in u = ε0 ε_gap A/C_gap and the force (eq 1)"
    if eps_gap == EPSILON_AIR:
        return f"ε_gap = {eps_gap:g} (air, the default: Sirin et al.), {used}; --eps-gap (Python: eps_gap) sets another medium's"
    return f"ε_gap = {eps_gap:.6g} (given: --eps-gap; Python: eps_gap), {used}"


def gap_bounds(area: float, eps_gap: float = EPSILON_AIR) -> tuple[float, float]:
    """Prior bounds (lower, upper) of u [m] for ``area`` [m²]: u = ε0 ε_gap A / C_gap at the
    upper and lower ends of `C_GAP_BOUNDS_F`, so every area gives the same bounds on C_gap."""
    from ..fitting.bayes.reparam import gap_thickness_bounds

    return gap_thickness_bounds(area, eps_gap)


def _gap_steps(value, name):
    """``steps`` of the gap analysis: ``"auto"`` or at least `GAP_MIN_STEPS` (`steps_rule`)."""
    value = steps_rule(value, name)
    if value != AUTO_STEPS and value < GAP_MIN_STEPS:
        raise ParameterError(f"{name} must be at least {GAP_MIN_STEPS}, got {value}")
    return value


EP_BRANCHES = ("C", "CPE")
"""The electrode-polarization branches of `gap_analysis` (``ep``): R_EP || C_EP or R_EP || CPE_EP."""


def ep_branch_name(value):
    """``value`` as an EP branch's element symbol of `EP_BRANCHES` when it is one of them or an
    alias the circuit language gives it, any case (``"Q"``, the CPE's alias → ``"CPE"``); else
    ``value`` as it is (for the refusal to name)."""
    if not isinstance(value, str):
        return value
    for spec in DEFAULT_REGISTRY.specs:
        if spec.symbol in EP_BRANCHES and value.casefold() in (s.casefold() for s in (spec.symbol, *spec.aliases)):
            return spec.symbol
    return value


def ep_branch_aliases() -> str:
    """The aliases the circuit language gives `EP_BRANCHES`, for a refusal: "Q for CPE"."""
    return ", ".join(f"{a} for {spec.symbol}" for symbol in EP_BRANCHES for spec in DEFAULT_REGISTRY.specs if spec.symbol == symbol for a in spec.aliases)


def _ep_rule(value, name):
    """`ep_branch_name`, then one of `EP_BRANCHES`, else refused with their aliases named."""
    branch = ep_branch_name(value)
    if branch not in EP_BRANCHES:
        raise ParameterError(f"unknown {name} {shown(value)} (choose one of {', '.join(EP_BRANCHES)}; or {ep_branch_aliases()}, its alias in the circuit language)")
    return branch


_cutoff_rule = real(positive=True)


def check_cutoff(cutoff_hz: float, total: xr.Dataset | None = None) -> list[str]:
    """``cutoff_hz`` of `gap_analysis` (the paper method's, Sirin §2.3) checked against the
    ``total`` spectra (None: the number alone): a `ParameterError` naming ``cutoff_hz`` when it is
    not a positive finite number or lies above the highest frequency (no point is left for the
    paper's mean); a cutoff below the band is taken (the mean then runs over every point) and the
    list holds the warning that says so, else it is empty."""
    cutoff_hz = _cutoff_rule(cutoff_hz, "cutoff_hz")
    if total is None:
        return []
    freq = np.asarray(total["frequency"].values, float)
    low, high = float(freq.min()), float(freq.max())
    if cutoff_hz > high:
        raise ParameterError(f"cutoff_hz must be at most {high:g} Hz, the highest frequency of the total spectra ({low:g}–{high:g} Hz), got {cutoff_hz:g}: "
                             "the paper's C_gap is the mean |Y_R|/ω over the frequencies at and above it")
    if cutoff_hz < low:
        return [f"the paper method's cutoff {format_frequency(cutoff_hz)} lies below the band of the total spectra ({format_band(low, high)}): "
                f"its C_gap is the mean |Y_R|/ω over every measured frequency, where electrode polarization may add to it (Sirin §2.3 reads it above {format_frequency(SIRIN_CUTOFF_HZ)})"]
    return []


@quiet_beneath
@checked_arguments(
    area=real(positive=True), v0=real(positive=True, optional=True), ep=_ep_rule, eps_gap=relative_permittivity_number, cutoff_hz=_cutoff_rule,
    steps=_gap_steps, walkers=count(2, MAX_WALKERS, optional=True), seed=seed, progress=flag, check_area=flag,
)
def gap_analysis(
    total: xr.Dataset,
    skin: xr.Dataset | None = None,
    touchscreen: xr.Dataset | None = None,
    *,
    area: float = SIRIN_AREA,
    v0: float | None = None,
    ep: str = "CPE",
    eps_gap: float = EPSILON_AIR,
    cutoff_hz: float = SIRIN_CUTOFF_HZ,
    steps: int | str = AUTO_STEPS,
    walkers: int | None = None,
    seed: int = 0,
    progress: bool = True,
    remainder=None,
    edl_fit=None,
    method: str = "hierarchical",
    chains: int = 4,
    warmup: int | None = None,
    check_area: bool = True,
) -> GapAnalysis:
    """Run the Sirin workflow (module docstring) on three spectrum Datasets with trial
    dimensions, all on one frequency grid; ``skin`` and ``touchscreen`` None (the default): a
    single contact, nothing subtracted (the total is the contact's impedance; the drive V0 falls
    across it alone), exactly one of them None a `ParameterError`. ``ep`` picks the EP branch of the EDL model (any case):
    ``"CPE"`` (R_EP || CPE_EP || C_gap, default) or ``"C"`` (R_EP || C_EP || C_gap: two ideal
    capacitors in parallel are identified only as their sum, so it is fitted and sampled as
    `IDENTIFIED_C_REMAINDER`, R_EP || C_gap with C_gap standing for C_EP + C_gap, and a warning says that u
    is then the smallest gap this model allows; ``model_requested`` in the summary keeps the model
    asked for). ``remainder`` replaces
    the EDL model by any circuit holding a ``C_gap`` (e.g. the result of `impedax.refine`), and
    ``edl_fit`` reuses a least-squares fit of it. ``method``: ``"hierarchical"`` (default; needs
    ≥ 3 total trials; ``steps`` draws per chain after ``warmup`` (default ``steps``) NUTS
    adaptation steps in each of ``chains`` chains; ``"auto"`` (default) is
    `HIERARCHICAL_AUTO_DRAWS`) or ``"pooled"`` (emcee on the trial means, ``steps`` steps;
    ``"auto"``, the default, runs until the chain is 50 autocorrelation times long, as
    `impedax.fitting.sample`); a number of ``steps`` is at least `GAP_MIN_STEPS`. u is sampled within `gap_bounds` (C_gap within
    `C_GAP_BOUNDS_F` for any area). ``v0``: the drive's peak amplitude [V] of the force (eq 1);
    None (default): the one voltage the total spectra carry (a scalar coordinate or attribute
    whose name says voltage, as ``total.sel(voltage=500)`` leaves it), else `SIRIN_DRIVE_V`
    (`gap_inputs.drive_voltage`; ``summary()["v0_from"]`` says which). ``progress``: what runs and a progress line on stderr.
    ``check_area``: refuse an ``area`` [m²] outside `FINGERTIP_AREA_M2` (a mistyped
    unit); False analyses any positive area, with a warning when it lies outside that range
    (``impedax gap --no-area-check``). A remainder with Re Z < 0 at more than half of its
    frequencies is refused before any fit (DataError: the files are likely in the wrong order).
    Returns a `GapAnalysis`; its warnings say when the posterior of u piles up at a prior bound,
    when the naive fit ran away, and when the paper's estimate lies far outside its own bounds.
    """
    from ..fitting import fit, gap_thickness_reparametrization, sample
    from ..fitting.bayes.progress import announce

    if not area > 0:
        raise DataError(f"area must be positive (m²), got {area}")
    notes = [] if check_area else _fingertip_area_notes(area)
    if check_area:
        check_fingertip_area(area)
    if method not in GAP_METHODS:
        raise ParameterError(f"unknown gap method {method!r}; use one of {', '.join(GAP_METHODS)}")
    _check_single_edl_fit(edl_fit)
    single = is_single_contact(skin, touchscreen)
    check_spectra(total, skin, touchscreen)  # (Datasets of spectra, before any check reads them)
    check_not_a_remainder(total, skin, touchscreen)
    total, skin, touchscreen = check_gap_inputs(total, skin, touchscreen)  # (sign, grids, distinct: DataError naming the file)
    drive = drive_voltage(total, v0)
    v0 = drive.value
    notes += list(drive.warnings) + _drive_voltage_notes(v0, drive.source)
    trials = spectra_used(total, skin, touchscreen)
    notes += condition_notes(total, skin, touchscreen, default_v0=v0 if drive.source == "default" else None) + position_notes(trials)
    remaining = _checked_remainder(total, skin, touchscreen)
    notes += _subtraction_notes(remaining)
    if method == "hierarchical":
        _check_hierarchical_trials(remaining)
    notes += check_cutoff(cutoff_hz, total)
    paper = paper_gap_estimate(total, skin, touchscreen, area=area, cutoff_hz=cutoff_hz, eps_gap=eps_gap)
    weighting = "sigma" if "sigma" in remaining else "modulus"
    requested = remainder_circuit(ep) if remainder is None else parse(remainder)
    circuit = requested
    if remainder is None and ep == "C":
        circuit = parse(IDENTIFIED_C_REMAINDER)
        if edl_fit is not None and str(getattr(edl_fit, "circuit", "")) != str(circuit):
            raise ParameterError(f"ep='C' is analysed as {IDENTIFIED_C_REMAINDER} (C_EP and C_gap are identified only as their sum); edl_fit must be a fit of that circuit, not of {requested}")
        notes.append(_merged_capacitors_note())
    if "C_gap" not in circuit.element_names:
        raise CircuitError(f"the remainder model {circuit} has no element named C_gap")
    if edl_fit is not None and str(getattr(edl_fit, "circuit", "")) != str(circuit):  # (before any fit: else the sampling's init= refused it, in words the caller never used)
        inputs = "total, None, None" if single else "total, skin, touchscreen"
        raise ParameterError(f"edl_fit is a fit of {getattr(edl_fit, 'circuit', type(edl_fit).__name__)}; gap_analysis samples {circuit} (the EDL model of ep={ep!r}"
                             f"{', remainder=' if remainder is not None else ''}): pass a fit of that circuit, ix.fit('{circuit}', "
                             f"ix.models.remaining_impedance({inputs}), weighting='{weighting}'), or leave edl_fit out")
    notes += _paper_bound_notes(paper, remaining) + _paper_interval_notes(paper, remaining)
    announce("gap: fitting the naive model (C_gap alone) to the trial mean …", progress)
    naive = fit(remainder_circuit(None), remaining, weighting=weighting)
    notes += _naive_runaway_notes(naive, single)
    if edl_fit is None:
        announce(f"gap: fitting the EDL model {circuit} to the trial mean …", progress)
    edl = edl_fit if edl_fit is not None else fit(circuit, remaining, weighting=weighting)
    u_lower, u_upper = gap_bounds(area, eps_gap)
    reparametrization = gap_thickness_reparametrization("C_gap", area=area, eps_r=eps_gap, lower=u_lower, upper=u_upper)
    if method == "hierarchical":
        draws = HIERARCHICAL_AUTO_DRAWS if steps == AUTO_STEPS else steps
        warm = draws if warmup is None else warmup
        result = _hierarchical(total, skin, touchscreen, remaining, paper, naive, edl, circuit, reparametrization, area=area, v0=v0, ep=ep, eps_gap=eps_gap, steps=draws, warmup=warm, chains=chains, seed=seed, progress=progress, notes=notes, model_requested=str(requested))
        used = {"eps_gap": eps_gap, "cutoff_hz": cutoff_hz, "seed": seed, "steps": draws, "steps_requested": steps, "warmup": warm, "chains": chains}
        return replace(result, trials=trials, settings=used, drive=drive, single_contact=single)
    posterior = sample(
        circuit,
        remaining,
        noise="sigma" if weighting == "sigma" else "proportional",
        reparametrization=reparametrization,
        init=edl,
        steps=steps,
        walkers=walkers,
        seed=seed,
        progress=progress,
    )
    freq = remaining["frequency"].values
    z_skin, z_ts = _series_impedances(skin, touchscreen)
    bands = []
    for branch, model in (("with_ep", str(circuit)), ("without_ep", "C_gap")):
        q = posterior.derive(lambda p, f, m=model: gap_force_peak(p, f, z_skin, z_ts, area=area, v0=v0, remainder=m, eps_gap=eps_gap), freq)
        v = posterior.derive(lambda p, f, m=model: _gap_voltage_amplitude(p, f, z_skin, z_ts, v0=v0, remainder=m), freq)  # (the same draws as the force)
        bands.append(_band_dataset(q, v, freq))
    force = _branches(bands)
    u_draws = posterior.parameter_draws()["u"]
    restating = _bound_notes(u_draws, reparametrization, area, single)  # (left out under the alarm NO AIR GAP, which says them: `_no_air_gap_said_once`)
    notes += restating + _gap_breakdown_notes(force, float(np.median(u_draws)), area, eps_gap)
    sampled = _sampling_notes(_gap_sampling_warnings(posterior), reparametrization, posterior.parameter_draws()["u"])
    known_kk = KKChains()
    sampled = _prior_edge_advice(sampled, posterior.piled_up, posterior.parameter_draws())
    notes += _edl_fit_warnings(edl, remaining, known_kk) + [f"sampling: {w}" for w in _correlation_advice(sampled, posterior.strong_correlations, posterior.parameter_draws(), circuit, single, weighting=weighting)]
    comparison = _estimate_bound_notes("Bayesian gap thickness", float(np.median(u_draws)), paper, remaining, f"; draws span {_gap_range(u_draws.min(), u_draws.max(), 3)}")
    notes += comparison
    restating += comparison
    lower, withheld, merged = _identification(ep, str(requested), circuit, posterior.parameter_draws(), edl, posterior.piled_up, notes, remaining, area, eps_gap, known_kk)
    bound_force = _force_upper_bound(merged, lower, freq, z_skin, z_ts, area=area, v0=v0, eps_gap=eps_gap)
    notes = _area_advice(notes, paper, lower is None and withheld is None, _single(remaining))
    misfit = _misfit_text(edl, remaining, known_kk)
    used = {"eps_gap": eps_gap, "cutoff_hz": cutoff_hz, "seed": seed, "steps": posterior.settings.get("steps"), "steps_requested": steps, "walkers": posterior.settings.get("walkers", posterior.n_walkers)}
    return _no_air_gap_said_once(GapAnalysis(remaining, paper, naive, edl, posterior, force, area, v0, ep, tuple(notes), model_requested=str(requested), trials=trials, gap_lower_bound=lower, gap_bound_withheld=withheld, edl_misfit=misfit, settings=used, force_upper_bound=bound_force, drive=drive, single_contact=single), restating)


def _series_impedances(skin: xr.Dataset | None, touchscreen: xr.Dataset | None) -> tuple:
    """Z_skin and Z_TS [Ω] in series with the contact for the gap voltage (`gap_voltage`): the
    trial means over frequency, or 0.0 and 0.0 for a single contact (nothing in series)."""
    if skin is None:
        return 0.0, 0.0
    return trial_mean(skin)["Z"].values, trial_mean(touchscreen)["Z"].values


def _gap_sampling_warnings(posterior) -> list[str]:
    """The pooled sampling's ``posterior``'s warnings the gap analysis may pass on: its own
    (`Posterior.own_warnings`: not the least-squares start's, as the EDL fit's own are), less the
    Laplace evidence's and WAIC's (`Posterior.model_comparison_notes`), which speak to comparing
    models, and the gap analysis compares none (``impedax gap`` would otherwise say "Do not
    compare models by this WAIC"). Told apart as `impedax.sample` made them, not by
    their words."""
    comparing = set(posterior.model_comparison_notes)
    return [w for w in posterior.own_warnings if w not in comparing]


def _sampling_notes(warnings, reparametrization=None, u_draws=None) -> list[str]:
    """The pooled sampling's warnings the gap analysis passes on, of those it may (``warnings``,
    `_gap_sampling_warnings`). With the sampling's
    ``reparametrization`` and ``u_draws`` [m]: nor its note that u is no air gap
    (`implausible_gap_notes`), which the alarm NO AIR GAP always says then (the same median, the
    same `PLAUSIBLE_GAP_M`); and the cause it gives of u piled up at a bound is the gap analysis's
    (`_gap_bound_cause`), not `gap_thickness_reparametrization`'s, whose "then the bounds
    (lower=, upper=)" named keywords neither `gap_analysis` nor ``impedax gap`` takes (REAL
    exampleDataBioLogic.mpt and exampleData.csv as single contacts)."""
    kept = list(warnings)
    if reparametrization is None:
        return kept
    from ..fitting.bayes.reparam import implausible_gap_notes

    name = reparametrization.names[0]
    said = set(implausible_gap_notes(reparametrization, {name: float(np.median(np.asarray(u_draws, float)))}))
    cause = dict(reparametrization.bound_causes).get(name)
    ours = _gap_bound_cause(dict(reparametrization.constants))
    return [w.replace(cause, ours) if cause else w for w in kept if w not in said]


def _gap_bound_cause(constants: Mapping[str, float]) -> str:
    """What u at a bound of its prior means in the gap analysis, in Python's words (``impedax
    gap`` reads "--area" for "area="): C_gap at an end of `C_GAP_BOUNDS_F`, the range every gap
    analysis gives it at any area and that no option widens (`gap_bounds`), so the area's unit
    is the first suspect (`AREA_UNIT_ADVICE`), then the data."""
    area, eps = constants["area"], constants["eps_r"]
    low, high = C_GAP_BOUNDS_F
    return (
        f"C_gap = ε0·ε_gap·A/u with A = {area:g} m² ({area * 1e6:g} mm²) and ε_gap = {eps:g}: u at a bound means C_gap at {format_quantity(high, 'F')} or "
        f"{format_quantity(low, 'F')}, the ends of the range the gap analysis allows C_gap at any area (no option widens it); "
        f"{AREA_UNIT_ADVICE} ({GAP_AREA_KEYWORD} in m²; 200 mm² is 200e-6), then the data"
    )


GAP_AREA_KEYWORD = "area="
"""How `_gap_bound_cause` names the area: `gap_analysis`'s keyword; ``impedax gap`` says its
option, --area (`cli.common.command_line_words`)."""


def _prior_edge_advice(warnings, piled_up: Mapping[str, str], draws: Mapping[str, np.ndarray]) -> list[str]:
    """``warnings`` of the pooled sampling with the advice of each prior-edge warning of an EDL
    parameter ("— give R_EP a prior that says how large it can be", `diagnostics.prior_edges`),
    which neither ``impedax gap`` nor `gap_analysis` can follow (they take no prior), replaced by
    what the pile-up means for u: u's correlation r with the parameter (log space, as
    `_correlation_advice`) and how much knowing it would narrow u's interval at most,
    1 − √(1 − r²); for the EP CPE's Q at its lower end, that u is then not determined
    (`_gap_identification`'s reason, which the warning "u is NOT determined" gives). The warnings are known by ``piled_up`` (`Posterior.piled_up`: name → side), each
    advice built as the sampler words it. REAL exampleDataGamry.DTA as a single contact has R_EP
    piled up at its prior's upper end."""
    u = np.log(np.asarray(draws["u"], float))
    out = []
    for w in warnings:
        for name, side in piled_up.items():
            if name == "u" or name not in draws:
                continue
            sides = ("lower", "upper") if side == "both" else (side,)
            for one in sides:
                advice = f" — give {name} a prior that says how {'small' if one == 'lower' else 'large'} it can be"
                if not w.endswith(advice):
                    continue
                x = np.asarray(draws[name], float)
                x = np.log(x) if np.all(x > 0) else x
                r = float(np.corrcoef(u, x)[0, 1]) if np.std(x) > 0 and np.std(u) > 0 else 0.0
                narrowing = 1.0 - math.sqrt(1.0 - min(1.0, r * r))
                if one == "lower" and name.endswith(".Q") and "EP" in name:  # (`_gap_identification`'s reason: the EP CPE vanishes)
                    w = w[: -len(advice)] + "; the gap analysis takes no prior: the EP CPE vanishing leaves C_gap and the EP branch not told apart (the warning 'u is NOT determined')"
                    continue
                w = (w[: -len(advice)] + f"; the gap analysis takes no prior: u's correlation with {name} in the draws (log space) is "
                     f"{r:+.2f}, so bounding {name} would narrow u's interval by at most {narrowing * 100:.0f} % (√(1 − r²))")
        out.append(w)
    return out


U_CORRELATION_MATTERS = 0.25
"""A pair of correlated parameters matters to u when knowing either exactly would narrow u's
interval by this share or more: 1 − √(1 − r²) ≥ 0.25, |r| ≥ 0.66 between u and it (the
conditional sd of a Gaussian; on the walkthrough's SYNTHETIC set, r = −0.42 for R_EP predicted
9 %, and R_EP fixed at its median narrowed the interval by 11 %)."""


def _check_single_edl_fit(edl_fit) -> None:
    """Refuse an ``edl_fit`` that is a batch of fits (of a remainder that kept condition dims,
    `remaining_impedance` with ``over``): the analysis takes one condition's spectra."""
    dims = tuple(getattr(edl_fit, "dims", ()) or ()) if edl_fit is not None else ()
    if dims:
        raise ParameterError(
            f"edl_fit is a batch of fits over {', '.join(map(str, dims))} (condition dims kept by remaining_impedance(..., over=...)); gap_analysis analyses one condition: "
            f"pass that condition's total, skin and touchscreen (data.sel({dims[0]}=LABEL); impedax gap --select {dims[0]}=LABEL) and a fit of its remainder"
        )


def _correlation_advice(warnings, correlations, draws: Mapping[str, np.ndarray], circuit, single: bool = False, *, weighting: str = "modulus") -> list[str]:
    """``warnings`` of the pooled sampling with the advice of each correlation warning
    (`diagnostics.CORRELATION_ADVICE`: ``--fix``, ``--prior``, options ``impedax gap`` does not
    have) replaced by what it means for u and what a user of the gap analysis can do: u's
    correlation r with each of the pair (in log space) and how much knowing it would narrow u's
    interval, 1 − √(1 − r²) (`U_CORRELATION_MATTERS`), and the Python call that fixes one. A
    correlation warning is known as the `StrongCorrelation.warning` of one of the posterior's
    ``correlations`` (`Posterior.strong_correlations`: the pair and r), not by matching its words.
    ``single``: a single contact, whose call passes the total alone. ``weighting``: that of the
    analysis's own EDL fit, the χ² of its sampling's noise model (``"sigma"`` for a remainder
    with SEM, noise ``sigma``; ``"modulus"`` for noise proportional to |Z|), which the call's fit
    passes so that it starts the sampling as that fit does (without it the call's
    ``ix.fit`` would be weighted by |Z| and the sampling warn that init needs weighting 'sigma')."""
    inputs = "total" if single else "total, skin, touchscreen"
    u = np.log(np.asarray(draws["u"], float))
    q05, q50, q95 = np.exp(np.quantile(u, [0.05, 0.5, 0.95]))
    by_warning = {c.warning: c for c in correlations}
    out = []
    for w in warnings:
        found = by_warning.get(w)
        pair = (found.first, found.second) if found is not None else ()
        if found is None or "u" in pair or not all(n in draws for n in pair):
            out.append(w)
            continue
        rs = {}
        for name in pair:
            x = np.asarray(draws[name], float)
            x = np.log(x) if np.all(x > 0) else x
            rs[name] = float(np.corrcoef(u, x)[0, 1]) if np.std(x) > 0 and np.std(u) > 0 else 0.0
        narrowing = 1.0 - math.sqrt(1.0 - min(1.0, max(r * r for r in rs.values())))
        correlations = " and ".join(f"{r:+.2f} with {n}" for n, r in rs.items())
        verdict = ("this matters little to u" if narrowing < U_CORRELATION_MATTERS else "this widens u's interval") + (
            f": u's interval {_gap_range(q05, q95)} (±{(q95 - q05) / (2 * q50) * 100:.2f} %) already carries it, u's correlation (log space) is {correlations}, "
            f"so knowing either exactly would narrow it by at most {narrowing * 100:.0f} % (√(1 − r²))"
        )
        out.append(
            f"{found.finding}; {verdict}; impedax gap has no --fix or --prior: in Python, fix one in the EDL fit the pooled sampling starts from, "
            f"ix.models.gap_analysis({inputs}, area=…, method='pooled', edl_fit=ix.fit('{circuit}', ix.models.remaining_impedance({inputs if not single else 'total, None, None'}), fixed={{'{found.first}': …}}, weighting='{weighting}'))"
        )
    return out


# the hierarchical sampling is called unreliable (the report's first line, the figure's banner)
# with more divergent transitions than this share of the draws, or an R-hat not below
# SAMPLING_RHAT_MAX (1.05: between the 1.1 of Gelman et al., Bayesian Data Analysis 3rd ed.,
# and the 1.01 of Vehtari et al. 2021, Bayesian Analysis 16:667)
SAMPLING_DIVERGENT_MAX = 0.01
SAMPLING_RHAT_MAX = 1.05
RETRY_TARGET_ACCEPT = 0.99
"""NUTS's target acceptance when a hierarchical run had more than `SAMPLING_DIVERGENT_MAX` of its
draws divergent (`sampled_with_retry`), the remedy Stan's manual gives (adapt_delta). Measured on
a walkthrough's SYNTHETIC gripper set (3 repeats of one truth, 1.5 % noise, 4 chains × 500
draws; 2026-12-02): 72, 75 and 29 divergent of 2000 at 0.85 (R-hat up to 1.08, ESS down to 27 for
the population median of R_EP), 20, 33 and 23 at 0.95, 7 and 2 at 0.99 (100 V and 300 V; R-hat
1.014 and 1.036, ESS 221 and 182), u the same within 0.1 %; a 0.99 run took 1.3–2.4× the time of a
0.85 one (a shared, loaded machine); fully centred sampling was worse (410 divergent at 0.95)."""


_TARGET_ACCEPT_ADVICE = re.compile(r"sample with a higher target_accept= \(smaller steps: [^)]*\) or a longer warmup= \(the default \d+\)")
_MORE_DRAWS_ADVICE = re.compile(r"run more draws per chain \((\d+) now\): draws=\d+, or more chains \((\d+) now\): chains=\d+")
WARMUP_WORDS = ", unless warmup= is given"
"""Where the gap's sampling advice names ``warmup=``, which ``impedax gap`` has no option for
(its --steps sets both): the command leaves these words out (`cli.common.command_line_words`)."""


def hierarchical_advice_of_gap(warning: str, steps: int) -> str:
    """A warning of the hierarchical sampling (`HierarchicalPosterior.warnings`) with its remedy
    in the words of `gap_analysis`, which takes no target acceptance: divergent transitions → a
    longer warm-up, ``steps=`` twice ``steps`` (the draws per chain, after as many warm-up steps;
    ``impedax gap --steps N``), and that the analysis itself samples again with smaller steps
    (`sampled_with_retry`); R-hat or ESS → more draws per chain, the same ``steps=``, or more
    chains, ``chains=`` twice theirs (Python only: ``impedax gap`` has no --chains), not "a higher target_accept", which neither
    ``impedax gap`` nor `gap_analysis` takes, nor "impedax gap: --steps" in Python; the
    posterior's own warnings name `sample_hierarchical`'s keywords (``draws=``, ``warmup=``)."""
    longer = f"steps={2 * int(steps)}"
    warning = _TARGET_ACCEPT_ADVICE.sub(
        f"sample with a longer warm-up, {longer} (as many warm-up steps as draws per chain{WARMUP_WORDS}); the gap analysis itself samples again "
        f"with smaller steps (target acceptance {RETRY_TARGET_ACCEPT:g}) when over {SAMPLING_DIVERGENT_MAX * 100:g} % of the draws diverge", warning)
    return _MORE_DRAWS_ADVICE.sub(lambda m: f"run more draws per chain ({m.group(1)} now): {longer}, or more chains ({m.group(2)} now): chains={2 * int(m.group(2))}", warning)


def sampled_with_retry(sample: Callable, progress=None) -> tuple:
    """``sample(target_accept)`` (a hierarchical posterior) at `hierarchical.TARGET_ACCEPT`, and
    where more than `SAMPLING_DIVERGENT_MAX` of its draws diverged once more at
    `RETRY_TARGET_ACCEPT` (smaller steps), said on the progress line; the run with fewer
    divergent transitions is kept. Returns it and the notes that say what was done: a run the
    report calls reliable then does not hide that the first one was not."""
    from ..fitting.bayes.hierarchical import TARGET_ACCEPT
    from ..fitting.bayes.progress import announce

    post = sample(TARGET_ACCEPT)
    if not post.divergences > SAMPLING_DIVERGENT_MAX * post.n_draws:
        return post, []
    first = f"{post.divergences} divergent transitions of {post.n_draws} draws at NUTS's target acceptance {TARGET_ACCEPT:g}"
    announce(f"gap: {first}: sampling again at {RETRY_TARGET_ACCEPT:g} (smaller steps) …", progress)
    again = sample(RETRY_TARGET_ACCEPT)
    kept = again if again.divergences <= post.divergences else post
    outcome = f"{again.divergences} divergent" + ("; these draws are kept" if kept is again else "; the first run's draws are kept (fewer divergent)")
    return kept, [f"sampling: {first}; sampled again at {RETRY_TARGET_ACCEPT:g} (smaller steps): {outcome}"]


# the paper's u is called far outside its own bounds beyond max(this × u, the bounds' width):
# the extreme trials need not bracket the means' u. On SYNTHETIC Sirin-style sets from
# `tests/spectra.sirin_measurements` (seeds 0–39 each) u lay outside in 22 of 40 without trial
# scatter (by up to 1.0 %), 12 and 8 of 40 with 1 % and 3 % scatter (1.3 %, 3.6 %), up to 9.1 %
# with 10 %; the shipped example's stationary total by 1.6 %: none of them a wrong file
PAPER_BOUND_SLACK = 0.10


def _far_outside(u: float, low: float, high: float) -> bool:
    """``u`` [m] lies beyond the paper's bounds ``low``–``high`` by more than their width and
    `PAPER_BOUND_SLACK` × u."""
    miss = low - u if u < low else u - high if u > high else 0.0
    return miss > max(PAPER_BOUND_SLACK * u, high - low)


def _paper_bound_notes(paper: PaperGapEstimate, remaining: xr.Dataset) -> list[str]:
    """A warning when the paper's u (from the trial means) lies far outside its own bounds (from
    the lowest- and highest-impedance trials): beyond their width and `PAPER_BOUND_SLACK` × u."""
    u, low, high = paper.gap, paper.gap_lower, paper.gap_upper
    if not _several_spectra(remaining) or not _far_outside(u, low, high):
        return []
    return [
        f"the paper method's u = {_gap_length(u, 3)} lies far outside its own bounds {_gap_range(low, high, 3)} "
        f"(by more than their width and {PAPER_BOUND_SLACK * 100:.0f} % of u): the lowest- and highest-impedance trials are far from bracketing the trial means, "
        + ("so those bounds are no interval for u; check the file's trials (one may be of another contact)" if _single(remaining)
           else "so those bounds are no interval for u; check the three files (TOTAL SKIN SCREEN: the right measurements, in that order)")
    ]


def _single(remaining: xr.Dataset) -> bool:
    """The remainder is a single contact's total, nothing subtracted (`remaining_impedance`)."""
    return bool(remaining.attrs.get("single_contact", 0))


# the paper's bounds are called much narrower than the trials' own spread of u below this share
# of it (the range of u over single total trials, each minus the mean skin and screen): on the
# SYNTHETIC walkthrough set (12 trials; skin scatter 20 %, u 5 %) the bounds were 0.008 µm wide
# against a 0.5 µm range of single-trial u (1.6 %)
PAPER_BOUND_NARROW = 0.25


def _paper_interval_notes(paper: PaperGapEstimate, remaining: xr.Dataset) -> list[str]:
    """A warning that the paper's bounds are no interval for u when its u lies outside them, or
    when they are narrower than `PAPER_BOUND_NARROW` × the range of single-trial u: the lowest
    (highest) skin and screen are subtracted from the lowest (highest) total, so the extremes of
    the three sets offset each other. Left to `_paper_bound_notes` when u is far outside."""
    u, low, high = paper.gap, paper.gap_lower, paper.gap_upper
    if not _several_spectra(remaining) or _far_outside(u, low, high):
        return []
    spread = paper.gap_trial_max - paper.gap_trial_min  # NaN with one total spectrum
    outside = not low <= u <= high
    narrow = bool(np.isfinite(spread)) and (high - low) < PAPER_BOUND_NARROW * spread
    if not (outside or narrow):
        return []
    found = []
    if outside:
        found.append(f"lie {'below' if u > high else 'above'} its u = {_gap_length(u, 4)}")
    if narrow:
        found.append(f"are {_gap_length(high - low, 4)} wide while single total trials{'' if _single(remaining) else ' (each minus the mean skin and screen)'} give u = {_gap_range(paper.gap_trial_min, paper.gap_trial_max, 4)}")
    why = ("since they come from the lowest- and highest-impedance trials alone, and the trial means need not lie between them; " if _single(remaining) else
           "since the paper subtracts the lowest-impedance skin and screen from the lowest-impedance total (and the highest from the highest), "
           "so the extremes of the three sets offset each other; ")
    return [
        f"the paper method's bounds {_gap_range(low, high, 4)} {' and '.join(found)}: they are no interval for u, "
        + why + "read the Bayesian interval for u, or the single trials' range for its scatter (docs/models.md, \"The paper's bounds\")"
    ]


# with one spectrum per input the paper method has no bounds, and the Bayesian u is set against
# its u itself: they are said to disagree beyond this ratio (either way). The paper's u, from
# mean |Y_R|/ω above the cutoff, counts the EP branch's admittance as C_gap's and so lies below
# the truth: 0.82× on the SYNTHETIC pad of tests/test_gap_single_contact.py (EP admittance equal
# to ωC_gap at 30 Hz, α = 0.6), while on the REAL Gamry file (exampleDataGamry.DTA, A = 1 cm²,
# no air gap) the two are 360× apart
GAP_METHODS_RATIO_MAX = 10.0


METHODS_DISAGREE = "the two methods disagree"
"""The words of the warnings that set the Bayesian u against the paper method's (`_estimate_bound_notes`)."""


def _no_air_gap_said_once(result: "GapAnalysis", restating: Sequence[str]) -> "GapAnalysis":
    """``result`` without the warnings of ``restating`` when the alarm NO AIR GAP holds of its
    Bayesian u (`GapAnalysis.gap_implausible`): the alarm says that u is no measurement, why (at a
    bound of its prior, outside the air gaps a contact holds) and what to check, and those
    warnings only said it again — u piled up at its prior's bound (`_bound_notes`, the alarm's own
    rule `_piled_bounds`), and the Bayesian u set against the paper method's (`_estimate_bound_notes`,
    `METHODS_DISAGREE`: "check that the spectrum is of an air-gap contact and that the model fits
    it", beside NO AIR GAP and MODEL DOES NOT FIT on the REAL exampleData.csv as a single contact).
    Kept without the alarm: where only the paper's u is no air gap, the comparison
    questions the Bayesian u, which no alarm does. The JSON keeps every key (``warnings`` holds fewer)."""
    if result.gap_implausible is None:
        return result
    dropped = set(restating)
    return replace(result, warnings=tuple(w for w in result.warnings if w not in dropped))


def _estimate_bound_notes(what: str, u: float, paper: PaperGapEstimate, remaining: xr.Dataset, detail: str = "") -> list[str]:
    """A warning when a Bayesian u [m] lies far outside the paper method's bounds, by the rule of
    `_far_outside`: those bounds come from two extreme trials and need not contain even the
    paper's own u, so a small miss says nothing. With one spectrum per input (no bounds): when
    u and the paper's u differ by more than `GAP_METHODS_RATIO_MAX`×."""
    if not _several_spectra(remaining):
        return _estimate_ratio_notes(what, u, paper, detail, single=_single(remaining))
    if not _far_outside(u, paper.gap_lower, paper.gap_upper):
        return []
    return [f"the {what} {_gap_length(u, 3)} lies far outside the paper method's bounds ({_gap_range(paper.gap_lower, paper.gap_upper, 3)}{detail}): {METHODS_DISAGREE} (the figure's air-gap thickness panel shows both)"]


def _estimate_ratio_notes(what: str, u: float, paper: PaperGapEstimate, detail: str = "", *, single: bool = True) -> list[str]:
    """A warning when a Bayesian u [m] and the paper method's u differ by more than
    `GAP_METHODS_RATIO_MAX`× (one spectrum per input: the paper has no bounds to hold u against)."""
    low, high = sorted((u, paper.gap))
    if not (np.isfinite(high) and low > 0) or high <= GAP_METHODS_RATIO_MAX * low:
        return []
    return [
        f"the {what} {_gap_length(u, 3)} and the paper method's u = {_gap_length(paper.gap, 3)} differ {high / low:.3g}× "
        f"(over {GAP_METHODS_RATIO_MAX:g}×; one spectrum{'' if single else ' per file'}, so the paper method has no bounds{detail}): {METHODS_DISAGREE} — the paper's u reads C_gap as "
        f"mean |Y_R|/ω above {format_frequency(paper.cutoff_hz)}, which holds only where C_gap carries the current, and the Bayesian u is the EDL model's "
        f"C_gap over the whole band: check that {'the spectrum is' if single else 'the spectra are'} of an air-gap contact and that the model fits it (the figure's air-gap thickness panel shows both)"
    ]


def _naive_runaway_notes(naive, single: bool = False) -> list[str]:
    """A warning when the naive fit (C_gap alone) ran away: rms_rel ≥ `NAIVE_RUNAWAY_RMS_REL`
    or C_gap outside `C_GAP_BOUNDS_F`. ``single``: a single contact, whose data are the spectrum
    itself, not a remainder (REAL data.dfr read alone is no "this remainder")."""
    c = float(naive.values["C_gap"])
    low, high = C_GAP_BOUNDS_F
    if naive.rms_rel < NAIVE_RUNAWAY_RMS_REL and low <= c <= high:
        return []
    return [
        f"the naive fit (C_gap alone) ran away: C_gap = {c:.3g} F (physical range {low:g}–{high:g} F), rms_rel {naive.rms_rel * 100:.0f} %: "
        f"a lone capacitor cannot describe this {'spectrum' if single else 'remainder'} at all, so that fit and its C_gap mean nothing (the EDL model's fit is the one to read)"
    ]


def check_fingertip_area(area: float) -> None:
    """A plausible fingertip contact area [m²] (`FINGERTIP_AREA_M2`), else a ParameterError."""
    low, high = FINGERTIP_AREA_M2
    if not low <= area <= high:
        raise ParameterError(
            f"area = {area:g} m² ({area * 1e6:g} mm²) is not a plausible contact area (a fingertip's is {low:g}–{high:g} m², i.e. "
            f"{low * 1e6:g}–{high * 1e6:g} mm²): the area is in m², and an SI prefix scales m² (130m is 0.13 m²), so 130 mm² is 130e-6; "
            "for a contact other than a fingertip (a gripper pad, an electrode), --no-area-check (Python: gap_analysis(..., check_area=False)) analyses any positive area, with a warning"
        )


def _fingertip_area_notes(area: float) -> list[str]:
    """With the check off: a warning when ``area`` lies outside `FINGERTIP_AREA_M2`."""
    low, high = FINGERTIP_AREA_M2
    if low <= area <= high:
        return []
    return [
        f"area = {area:g} m² ({area * 1e6:g} mm²) is outside the plausible fingertip contact ({low:g}–{high:g} m²); analysed as given "
        "because the area check is off (--no-area-check; Python: check_area=False): u = ε0 ε_gap A/C_gap scales with it"
    ]


def _drive_voltage_notes(v0: float, source: str = "given") -> list[str]:
    """A warning when the drive amplitude ``v0`` [V] lies outside `DRIVE_VOLTAGE_V`: the force of
    eq 1 scales with V0² and has no breakdown of the air gap in it. ``source``: where it came
    from (`gap_inputs.V0_SOURCES`)."""
    low, high = DRIVE_VOLTAGE_V
    if low <= v0 <= high:
        return []
    why = (
        f"above the largest drive of the papers ({high:g} V, Vezzoli et al. across a 90 µm insulator; Sirin et al. 75 V, Meyer 140 V): "
        "the air gap carries part of V0, and a µm air gap breaks down at a few hundred volts (Paschen minimum about 330 V in air at 1 atm), which eq 1's force does not model"
        if v0 > high
        else f"below {low:g} V, no electroadhesion drive (Sirin et al. 75 V): likely a unit slip (an SI prefix scales volts: 75m is 0.075 V)"
    )
    said = "the voltage the total spectra carry" if source == "data" else "--v0"
    return [f"v0 = {v0:g} V ({said}) is {why}; analysed as given: the force scales with V0²"]


# the most significant digits a voltage interval of `_gap_breakdown_notes` is printed with; ends
# that agree to these many are printed once, "≈ 941 V" (a band 0.1 % wide says nothing more)
VOLTAGE_DIGITS_MAX = 4


def _distinct_digits(low: float, high: float) -> int:
    """The fewest significant digits, 3 to `VOLTAGE_DIGITS_MAX`, that print ``low`` and
    ``high`` apart ("941–941 V" hid a real interval), or 0 when they agree to all of those."""
    return next((n for n in range(3, VOLTAGE_DIGITS_MAX + 1) if f"{low:.{n}g}" != f"{high:.{n}g}"), 0)


def _volts(voltage: float, digits: int) -> str:
    """``voltage`` [V] to ``digits`` significant digits; beyond 3 with its trailing zeros kept, so
    the ends of one interval read alike (940.6–941.0 V, not 940.6–941 V)."""
    return f"{voltage:.{digits}g}" if digits <= 3 else f"{voltage:#.{digits}g}".rstrip(".")


def _gap_breakdown_notes(force: xr.Dataset, u: float, area: float, eps_gap: float) -> list[str]:
    """A warning when the amplitude of the air gap's voltage |ΔV_gap| at the peak of the median
    force (with EP) exceeds `AIR_BREAKDOWN_V`, air's Paschen minimum: such a gap breaks down. Read
    from the force's gap-voltage band (``gap_voltage_median``, ``_q05``, ``_q95``: the same draws
    as the force, Sirin §2.4's node voltages), so the warning also comes when only the upper end
    of the 90 % interval crosses the threshold (the posterior puts more than 5 % on a spark). A
    band without the gap voltage gives the median alone, from eq 1 solved for it:
    V_gap = u √(2F/(ε0 ε_gap A)) with ``u`` the median gap [m]."""
    band = force.sel(branch="with_ep")
    peak = band["median"]
    i = int(np.argmax(peak.values))
    if "gap_voltage_median" in band:
        v_median, v_low, v_high = (float(band[f"gap_voltage_{k}"][i]) for k in ("median", "q05", "q95"))
    else:
        v_median = u * math.sqrt(2.0 * float(peak[i]) / (EPSILON_0 * eps_gap * area))
        v_low = v_high = math.nan
    apart = _distinct_digits(v_low, v_high) if math.isfinite(v_high) else 3
    digits = apart or VOLTAGE_DIGITS_MAX
    where = f"at the force's peak ({format_frequency(float(peak['frequency'][i]))}) the air gap carries {_volts(v_median, digits)} V"
    interval = "" if not math.isfinite(v_high) else f" (90 % interval {_volts(v_low, digits)}–{_volts(v_high, digits)} V)" if apart else f" (90 % interval ≈ {_volts(v_high, digits)} V)"
    threshold = f"the ~{AIR_BREAKDOWN_V:g} V at which air breaks down (Paschen minimum, 1 atm)"
    unmodelled = "which eq 1's force does not model; check --v0 (Python: v0)"
    if v_median > AIR_BREAKDOWN_V:
        return [f"{where}{interval} across u = {_gap_length(u, 3)}, above {threshold}: the gap would spark, {unmodelled}"]
    if v_high > AIR_BREAKDOWN_V:
        return [
            f"{where}{interval} across u = {_gap_length(u, 3)}: the median is below {threshold}, but the upper end of the 90 % interval "
            f"({_volts(v_high, digits)} V) is above it: the gap may spark (more than 5 % of the posterior), {unmodelled}"
        ]
    return []


def _merged_capacitors_note(*, withheld: bool = False) -> str:
    """The warning of ``ep="C"`` (see `IDENTIFIED_C_REMAINDER`); ``withheld``: the merged model
    misses the remainder (`_identification`), so its promise of a bound is taken back (else
    "the force its upper bound" would stand under "GAP NOT DETERMINED, AND NO BOUND")."""
    promise = ("u is then the smallest gap thickness this model allows (larger if part of the capacitance belongs to the EP branch) and the force its upper bound"
               + (" — not here: that model misses the remainder, so its u bounds nothing and the force drawn from it is no estimate nor bound (the report's first lines say why)" if withheld else ""))
    return (
        f"--ep C (Python: ep='C'): in R_EP || C_EP || C_gap the two ideal capacitors are seen only as their sum (1/Z = 1/R_EP + jω(C_EP + C_gap) at every frequency), "
        f"so the data cannot split it; analysed as {IDENTIFIED_C_REMAINDER} with C_gap standing for C_EP + C_gap, as the paper's method counts it: {promise}; "
        "--ep CPE (the default) has an EP branch the data tell from C_gap"
    )


REMAINDER_KINDS = ("mean", "trials")
"""``gap_remainder``'s ``kind``: the trial-mean remainder (what the least-squares fits and the
pooled sampling fit) or every total trial's remainder (what the hierarchical model fits)."""


def _checked_remainder(total: xr.Dataset, skin: xr.Dataset | None, touchscreen: xr.Dataset | None) -> xr.Dataset:
    """`remaining_impedance` of inputs already through `check_gap_inputs`, refused when its sign
    says the files are in the wrong order (`_check_remainder_sign`), with the inputs' paths as
    its `REMAINDER_ATTRS` (each input's ``source`` as `impedax.load` sets it, else its ``path``,
    else `IN_MEMORY`): a fit of it, the EDL fit of `gap_analysis` too, then blames Re Z < 0 on
    the subtraction, not on the instrument. A single contact (skin and touchscreen None) gets the
    total's path alone: nothing was subtracted, so it is no remainder (`is_remainder`)."""
    remaining = remaining_impedance(total, skin, touchscreen)
    _check_remainder_sign(remaining)
    given = present_inputs(total, skin, touchscreen)
    return remaining.assign_attrs({name: str(ds.attrs.get("source") or ds.attrs.get("path") or IN_MEMORY) for name, ds in given.items() if name in REMAINDER_ATTRS})


def gap_remainder(total: xr.Dataset, skin: xr.Dataset | None = None, touchscreen: xr.Dataset | None = None, *, kind: str = "mean") -> tuple[xr.Dataset, list[str]]:
    """The remaining impedance Z_R = Z_total − Z_skin − Z_TS (Sirin eq 5) exactly as
    `gap_analysis` fits it, with no fit or sampling (``impedax remaining``), and the warnings
    on the inputs (a ``--select`` read by position in some files only).

    The inputs pass the same checks (`check_gap_inputs`: sign, frequency grids, distinct files;
    the remainder's sign). ``kind`` ``"mean"``: `remaining_impedance`, the trial means with
    ``sigma`` from their SEMs (the EDL least-squares fit and ``method="pooled"``); ``"trials"``:
    `trial_remainders`, each total trial minus the skin and screen means, with the total's
    trial dimensions (``method="hierarchical"``; its error modes are left out: a spectrum file
    holds Z and sigma only). A spectrum Dataset in Ω over Hz, as `impedax.save` writes it.
    ``skin`` and ``touchscreen`` None: a single contact, the total's trial means (or trials)
    themselves, as `gap_analysis` fits them then."""
    if kind not in REMAINDER_KINDS:
        raise ParameterError(f"unknown remainder kind {kind!r}; use one of {', '.join(REMAINDER_KINDS)}")
    is_single_contact(skin, touchscreen)
    check_spectra(total, skin, touchscreen)  # (as `gap_analysis`: None or a file name gets this message, not an AttributeError)
    # (a remainder given as a single contact's total is refused here as by `gap_analysis`:
    # `impedax remaining` of it would write a "single contact" file that `gap` then reads, its force
    # 412 mN flat over frequency where the contact's peaks at 352 mN)
    check_not_a_remainder(total, skin, touchscreen)
    notes = position_notes(spectra_used(total, skin, touchscreen))
    total, skin, touchscreen = check_gap_inputs(total, skin, touchscreen)
    notes = condition_notes(total, skin, touchscreen) + notes
    remaining = _checked_remainder(total, skin, touchscreen)
    if kind == "mean":
        return remaining, notes + _subtraction_notes(remaining)
    trials = trial_remainders(total, skin, touchscreen)
    trials = trials.drop_vars([v for v in ("common_error_modes", "trial_error_modes") if v in trials])
    trials.attrs.update({k: v for k, v in remaining.attrs.items() if k.startswith("n_trials_") or k in REMAINDER_ATTRS or k == "single_contact"})
    # (what the file's sigma is, as the trial means' remainder says it; `impedax remaining --trials --json` gives it, not "")
    trials.attrs["sigma_method"] = "not available: one remainder per total trial, as measured; the scatter between them is the noise impedax gap's hierarchical model estimates"
    return trials, notes + _subtraction_notes(trials)


def _subtraction_notes(remaining: xr.Dataset) -> list[str]:
    """A note naming the frequencies where the remainder (of any trial) has Re Z < 0 beyond its
    sigma (`non_passive`): no passive contact gives that, the subtraction does
    (`SUBTRACTION_CAUSE`), and a fit would otherwise blame the instrument."""
    z = remaining["Z"]
    sigma = remaining["sigma"].broadcast_like(z).values if "sigma" in remaining else None
    bad = xr.DataArray(non_passive(z.values, sigma), dims=z.dims).any([d for d in z.dims if d != "frequency"])
    if not bad.any():
        return []
    trials = [d for d in z.dims if d != "frequency"]
    cause = "the measurement itself: nothing was subtracted from this single contact (impedax inspect and impedax diagnose on the file say more)" if _single(remaining) else SUBTRACTION_CAUSE
    return [
        f"the remainder has Re Z < 0 beyond its sigma at {int(bad.sum())} of {bad.size} frequencies ({listed_frequencies(remaining['frequency'].values, bad.values)})"
        + (" in some trials" if trials else "")
        + f", which no passive contact gives: the cause is {cause}. A fit will flag these points; "
        + SUBTRACTION_LEAVE_OUT + (f", or fit the trial means ({TRIAL_MEANS_CALL})" if trials else "")
    ]


SUBTRACTION_LEAVE_OUT = "leave them out (data.drop_sel(frequency=[...]) of each input spectrum, or a narrower band of all)"
TRIAL_MEANS_CALL = "gap_remainder(..., kind='mean')"
"""The remedies of the note on a remainder's Re Z < 0 (`_subtraction_notes`) in Python's words;
``impedax gap`` and ``impedax remaining`` say "leave them out (--exclude F,F or --fmin/--fmax, which
impedax gap, remaining and fit take)" and "impedax remaining without --trials"
(`cli.common.command_line_words`), not impedax fit --exclude alone."""


# the share of a remainder's frequencies with Im Z > 0 from which it is refused (`_check_remainder_sign`):
# a contact with no air gap leaves noise about zero there (the SYNTHETIC stationary example: 19 of 61)
INDUCTIVE_REMAINDER_SHARE = 0.9


def _check_remainder_sign(remaining: xr.Dataset) -> None:
    """The remainder of a passive contact has Re Z ≥ 0; at most half of the points may dip below
    (noise where Im Z dominates). More means the three spectra are swapped (DataError). Its Im Z
    is < 0 (the gap's capacitance in series): > 0 at `INDUCTIVE_REMAINDER_SHARE` of the points or
    more, the skin or screen spectrum is not of the total's contact (DataError)."""
    negative = int(np.sum(np.real(remaining["Z"].values) < 0))
    if negative > remaining.sizes["frequency"] / 2 and _single(remaining):
        raise DataError(f"the single contact's total has Re Z < 0 at {negative} of {remaining.sizes['frequency']} frequencies, which no passive contact has: check the file's sign convention (impedax inspect)")
    if negative > remaining.sizes["frequency"] / 2:
        raise DataError(f"the remainder total − skin − screen has Re Z < 0 at {negative} of {remaining.sizes['frequency']} frequencies: check the order of the files (TOTAL SKIN SCREEN)")
    # (the air gap is a capacitance in series: −Im Z_R > 0. A screen file of another rig, |Z| up to
    # 1.2 GΩ against the total's 60 MΩ, gave Im Z_R > 0 at every frequency and minutes of sampling
    # ending in MODEL DOES NOT FIT at rms_rel 100 %; walkthrough 2026-12-07)
    inductive = int(np.sum(np.imag(remaining["Z"].values) > 0))
    if inductive >= INDUCTIVE_REMAINDER_SHARE * remaining.sizes["frequency"] and not _single(remaining):
        raise DataError(f"the remainder total − skin − screen has Im Z > 0 at {inductive} of {remaining.sizes['frequency']} frequencies, where the air gap's capacitance makes it "
                        "capacitive (Im Z < 0): the skin and screen spectra together exceed the total's reactance; check that the three files are of one rig and "
                        "contact, in the order TOTAL SKIN SCREEN (impedax inspect each)")


def _sem_of_varying_trials(fitted, remaining: xr.Dataset) -> bool:
    """Whether ``fitted`` weighs the remainder by its ``sigma`` and that sigma is the standard error
    of means over two or more trials (`remaining_impedance`): it then holds the contact's variation
    between trials (u, R_EP and CPE_EP differ from touch to touch), not the measurement noise
    alone, and one model of the mean absorbs most of that variation."""
    return fitted.weighting == "sigma" and "sigma" in remaining and int(remaining.attrs.get("n_trials_total", 0)) >= 2


def _edl_fit_warnings(edl, remaining: xr.Dataset, known_kk: KKChains | None = None) -> list[str]:
    """The EDL fit's warnings for the gap analysis, each as ``EDL fit: …``, without those that
    read residuals below the trial means' SEM as a σ misstating the noise (`SIGMA_OVERSTATES_WORDS`,
    and the uneven-band warning under sigma weighting, `SIGMA_BAND_WORDS`) when that sigma is the
    SEM of varying trials (`_sem_of_varying_trials`): there residuals far below it are expected,
    smallest where the variation dominates the SEM (SYNTHETIC Sirin example, seed 1, drawn from
    the model itself: residuals 0.36× the SEM, "σ overstates the noise" warned; the fit
    itself says what such a σ is, `SIGMA_OF_TRIAL_MEANS_WORDS`, left out too). The report's
    fits line states the χ²_red and why instead (`GapAnalysis.report`). With the remainder's KK chains
    ``known_kk``: the note of a misfit near the alarm's (`_near_misfit_note`) in place of the fit's
    own note that the data limit it (`DATA_LIMIT_NOTE`), when it holds; and without the fit's note
    that the model misses structure the data hold (`MODEL_MISSES_STRUCTURE`) where the alarm MODEL
    DOES NOT FIT (`_misfit_text`) says it (both below one another on the SYNTHETIC shipped example's
    stationary total, `--pooled`). These notes and the σ notes are found by values the fit sets
    where it makes them (`result.fit_data_limit`, `result.fit_blaming_note`,
    `result.fit_sigma_residual_notes`), not by their words, which decide only for a fit without
    them."""
    expected = _sem_of_varying_trials(edl, remaining)
    near = _near_misfit_note(edl, remaining, known_kk) if known_kk is not None else None
    alarmed = known_kk is not None and _misfit_text(edl, remaining, known_kk) is not None  # (MODEL DOES NOT FIT says the fit's own misfit note: once)
    blaming = fit_blaming_note(edl) if alarmed else ""  # (values the fit sets where it makes the note; its words only for a fit without them)
    sigma_notes = set(fit_sigma_residual_notes(edl)) if expected else set()  # (values the fit sets where it makes the notes; its words only for a fit without them)
    kept = [w for w in edl.warnings if w not in sigma_notes and not (blaming and w == blaming)]
    if near is None:
        return [f"EDL fit: {w}" for w in kept]
    limit, _ = fit_data_limit(edl)
    return [f"EDL fit: {w}" for w in kept if not (limit and w == limit)] + [near]  # (the note gives the data's KK figure: said once)


NEAR_MISFIT_RATIO = MISFIT_RATIO_MAX / 2
"""The EDL fit's rms_rel (at least `GROSS_MISFIT_FROM`) over this multiple of what a
Kramers–Kronig-consistent model reaches, but not over `MISFIT_RATIO_MAX` (MODEL DOES NOT FIT), is
named in a note (`_near_misfit_note`): informational, no alarm, `gap_identified` unchanged. On
SYNTHETIC single contacts (numpy, tests' formulas) no spectrum of R_EP ∥ CPE_EP ∥ C_gap
(80 + 60, noise 0.2–5 %) nor of that contact with C_gap a CPE of α 0.97–1 and a series resistance
of 0.1–5 % of |Z| (60) reached it at rms_rel ≥ 5 % (largest ratio there 1.23); 11 of 80 ionic
conductors between blocking electrodes, R_b ∥ C_b + CPE_dl in series (the REAL Gamry file's shape),
fell between it and `MISFIT_RATIO_MAX`; the Gamry file itself at 4.96× (23.8 % against 4.8 %)."""


def _near_misfit_note(fitted, remaining: xr.Dataset, known_kk: KKChains) -> str | None:
    """A note when the EDL fit misses the remainder by rms_rel ≥ `GROSS_MISFIT_FROM` and over
    `NEAR_MISFIT_RATIO` × what a Kramers–Kronig-consistent model reaches, short of the alarm's
    `MISFIT_RATIO_MAX` (`_misfit_text`), naming the misfit, the share of its square the data's own
    distance from such a model leaves to the model (1 − (kk/rms)²) and the parameters the fit
    leaves undetermined (`undetermined_names`). REAL exampleDataGamry.DTA as a single contact:
    23.8 % against 4.8 % (4.96×), R_EP not determined, u = 2.19 µm reported with no alarm and
    ``gap_identified`` true, the EDL fit's one note saying the data's noise limits the fit;
    that note (`DATA_LIMIT_NOTE`) gives way to this one. None otherwise, and where
    the fit weighted by the remainder's sigma stays within its stated noise."""
    freq, z = remaining["frequency"].values, remaining["Z"].values
    rms = float(fitted.rms_rel)
    if not rms >= GROSS_MISFIT_FROM or _misfit_text(fitted, remaining, known_kk) is not None:
        return None
    sigma = remaining["sigma"].values if "sigma" in remaining else None
    if within_stated_noise(z[None], np.asarray(fitted.z_model)[None], None if sigma is None else sigma[None], fitted.weighting, len(fitted.free_names))[0]:
        return None
    kk = float(known_kk_misfits(freq, z[None], np.array([0]), known_kk)[0])
    if not (kk > 0 and rms > NEAR_MISFIT_RATIO * kk):
        return None
    loose = [n for n in undetermined_names(fitted) if n != "C_gap"]  # (their standard errors: the fit's own warnings)
    loose_text = f", and the fit leaves {names_in_words(loose)} undetermined" if loose else ""
    what = "the spectrum" if _single(remaining) else "the remainder"
    return (
        f"{fitted.model} misses {what} by {format_percent(rms)} (rms_rel), {rms / kk:.3g}× the {format_percent(kk)} a Kramers–Kronig-consistent model reaches: "
        f"under the {MISFIT_RATIO_MAX:g}× at which the gap analysis says MODEL DOES NOT FIT, but the data's own distance from such a model accounts for only "
        f"{(kk / rms) ** 2 * 100:.0f} % of the misfit's square{loose_text}; u, C_gap and the force rest on that fit "
        f"(no alarm; impedax diagnose on {what} shows where the model misses it)"
    )


def _edl_chi2_text(fitted, remaining: xr.Dataset) -> str:
    """The EDL fit's χ²_red against the trial means' SEM, and why it lies below 1 (`_edl_fit_warnings`);
    a sigma that also holds the stated sigma of a file of one spectrum is said so, naming the
    files, as the remainder's ``sigma_sources`` record them (`sirin.remaining_impedance`,
    not "against the trial means' SEM", nor ``sigma_method``'s words searched
    for "stated sigma"; `gap_analysis` makes its remainder, so it always has the sources)."""
    if not _sem_of_varying_trials(fitted, remaining):
        return ""
    sources = sigma_sources(remaining.attrs) or {}
    means = [name for name, source in sources.items() if source == SIGMA_FROM_TRIALS]
    stated = [name for name, source in sources.items() if source == SIGMA_FROM_OWN]
    if stated:
        against = (f"the remainder's sigma (the SEM of the trial means of {names_in_words(means)} with the stated sigma of {names_in_words(stated)}, "
                   f"one spectrum{' each' if len(stated) > 1 else ''})")
    else:
        against = "the trial means' SEM" if sources else "the remainder's sigma"
    return (f" (χ²_red {fitted.chi2_red:.3g} against {against}"
            + (", below 1 as expected: the SEM holds the contact's variation between trials, which the fit of the mean absorbs)" if fitted.chi2_red < 1 else ")"))


def _check_hierarchical_trials(remaining: xr.Dataset) -> None:
    """The hierarchical model needs ≥ 3 total trials; checked before any fit."""
    n_trials = int(remaining.attrs.get("n_trials_total", 0))
    if n_trials == 1:
        raise DataError("total: a single spectrum; per-trial remainders need trials as an extra dimension; use --pooled (Python: method='pooled') for single spectra")
    if n_trials < 3:
        raise DataError(f"the hierarchical gap analysis needs at least 3 total trials, got {n_trials}; use --pooled (Python: method='pooled')")


def _check_trials_hold_a_gap(batch, total: xr.Dataset) -> None:
    """A `DataError` naming the trials, before the hierarchical sampling, when the EDL fits of at
    least half the total trials (``batch``) put C_gap at its lower bound 0: u = ∞ there (no air
    gap), so the trials' median, the centre of u's population prior, is no gap. On the REAL
    battery cycles 0, 64 and 129 all three fits end so; without this the sampling runs for a minute and then
    fails with "prior lognormal:inf,2: both numbers must be finite". A stray trial
    or two in another mode are left to the median."""
    c_gap = batch.values("C_gap")
    at_zero = [index for index in np.ndindex(*c_gap.shape) if not c_gap.values[index] > 0]
    if 2 * len(at_zero) < c_gap.size:
        return
    labels = [point_text(c_gap, c_gap.dims, index) for index in at_zero]
    shown = "; ".join(labels if len(labels) <= 8 else labels[:3] + ["…"] + labels[-2:])
    raise DataError(
        f"the EDL fits of {len(at_zero)} of the {c_gap.size} total trials ({shown}) put C_gap at its lower bound 0 (u = ∞: no air gap), so the trials' median, "
        "on which the hierarchical model centres the population of u, is no gap; use --pooled (Python: method='pooled'), which reports what the trials' mean holds",
        path=total.attrs.get("source"),
    )


def trial_remainder_sigma(total: xr.Dataset, skin: xr.Dataset | None, touchscreen: xr.Dataset | None) -> np.ndarray | None:
    """The noise sd [Ω] (frequency,) of one total trial's remainder Z_total,t − mean Z_skin −
    mean Z_TS, for Re and Im alike: σ_k² = s_total,k² + SEM_skin,k² + SEM_TS,k², the total
    trials' own scatter (sample sd) plus the two subtracted means' standard errors (each as
    `remaining_impedance` pools Re and Im: √((σ_Re² + σ_Im²)/2)). It matches the hierarchical
    likelihood's noise, |Z_tk| ν_k from the trials' scatter plus the shared error of the
    subtracted means (`impedax.fitting.bayes.hierarchical`), so the per-trial least-squares fits
    that centre its priors weight the points as it does. None when σ is zero at some frequency
    (no input scatters there: a zero sd cannot weight a fit). A single contact (skin and
    touchscreen None): the total trials' scatter alone."""
    means = [trial_mean(ds) for ds in present_inputs(total, skin, touchscreen).values()]
    n_total = means[0].attrs["n_trials"]
    if n_total < 2:
        return None
    scale = (n_total, 1, 1)  # the total's SEM × √n is one trial's sd; the subtracted means keep their SEM (zip stops at the inputs given)
    # (a subtracted input of one spectrum adds nothing, its stated sigma neither: the likelihood has no error modes of it)
    var = sum(k * (m["sigma_real"].values ** 2 + m["sigma_imag"].values ** 2) / 2.0 for k, m in zip(scale, means) if m.attrs["sigma_from"] == "trial scatter")
    sigma = np.sqrt(var)
    return sigma if bool(np.all(sigma > 0)) else None


# the per-trial fits centre the hierarchical priors of μ at their median, N(ln θ̂, 2²): a median
# this many prior sds (in ln) from the fit of the trial mean puts that fit outside the prior's
# 95 % range (±1.96 sd), where the sampler can hardly reach it
_CENTRE_OFF_SDS = 1.96


def _per_trial_centre_notes(batch, edl, reparametrization, per_trial) -> list[str]:
    """A warning for each per-trial quantity whose per-trial fits' median lies beyond
    `_CENTRE_OFF_SDS` prior sds (ln) of the EDL fit of the trial mean: that median centres the
    prior of its population median, which then barely reaches the pooled value (noise-dominated
    trials fitted to R_EP ~ 1e12 Ω for 5e7 Ω on SYNTHETIC data weighted by |Z|). None for a
    quantity the fit of the trial mean leaves undetermined or at a bound: it has no value to miss."""
    from ..fitting.bayes.hierarchical import MU_PRIOR_SD
    from ..fitting.least_squares.branches import undetermined

    values = {str(p): batch.dataset["value"].sel(param=p).values.ravel() for p in batch.dataset["param"].values}
    pooled = {k: np.asarray([v], float) for k, v in edl.values.items()}
    if reparametrization is not None and reparametrization.inverse is not None:
        values.update(reparametrization.inverse({n: values[n] for n in reparametrization.replaces}, reparametrization.constant_values))
        pooled.update(reparametrization.inverse({n: pooled[n] for n in reparametrization.replaces}, reparametrization.constant_values))
    notes = []
    for name in per_trial:
        trial_values, pooled_value = np.asarray(values[name], float), float(np.asarray(pooled[name]).ravel()[0])
        if not (np.all(trial_values > 0) and pooled_value > 0):
            continue
        if name in edl.at_bound or (name in edl.stderr and bool(undetermined(edl.values[name], edl.stderr[name]))):
            continue  # the trial mean does not determine it (R_EP at 1.9e36 Ω where C_EP is ideal): no value for the prior to miss
        median = float(np.exp(np.median(np.log(trial_values))))
        off = abs(math.log(median / pooled_value)) / MU_PRIOR_SD
        if off > _CENTRE_OFF_SDS:
            notes.append(
                f"the per-trial fits put {name} at {median:.3g} (median of {trial_values.size} trials) but the fit of the trial mean at {pooled_value:.3g}, "
                f"{off:.1f} prior sds (ln) apart: that median centres the prior of the population's {name} (normal in ln, sd {MU_PRIOR_SD:g}), which hardly reaches the mean's value; "
                "single trials may be too noisy for this model (compare --pooled)"
            )
    return notes


def _several_spectra(remaining: xr.Dataset) -> bool:
    """Some input holds more than one spectrum (the inputs given: a single contact's total alone):
    the remainder is a mean over trials (`GapAnalysis.averages_trials`), and the paper's bounds,
    from each input's lowest- and highest-impedance spectrum, are two sets of spectra
    (`GapAnalysis.paper_has_bounds`)."""
    inputs = ("total",) if _single(remaining) else ("total", "skin", "touchscreen")
    return any(remaining.attrs.get(f"n_trials_{k}", 2) > 1 for k in inputs)


def _piled_bounds(u_draws, lower: float, upper: float) -> list[tuple[str, float, float, float]]:
    """(side, bound [m], C_gap there [F], share of the draws) for each prior bound of u,
    ``lower`` and ``upper`` (`gap_bounds`: C_gap at an end of `C_GAP_BOUNDS_F`), that holds ≥
    `_BOUND_SHARE` of ``u_draws`` within a factor `_BOUND_FACTOR`: there the prior, not the
    data, sets u and C_gap = ε0 ε_gap A/u."""
    u = np.asarray(u_draws, dtype=np.float64).ravel()
    c_low, c_high = C_GAP_BOUNDS_F
    out = []
    for side, bound, c_bound, near in (("lower", lower, c_high, u <= lower * _BOUND_FACTOR), ("upper", upper, c_low, u >= upper / _BOUND_FACTOR)):
        share = float(np.mean(near))
        if share >= _BOUND_SHARE:
            out.append((side, float(bound), c_bound, share))
    return out


def _bound_notes(u_draws, reparametrization, area: float, single: bool = False) -> list[str]:
    """A warning for each prior bound of u the draws pile up at (`_piled_bounds`)."""
    return [
        f"the posterior of u piles up at the {side} bound of its prior, u = {_gap_length(bound, 3)} (C_gap = {c_bound:g} F at A = {area:g} m²; {share * 100:.0f} % of the draws within a factor {_BOUND_FACTOR:g} of it): "
        f"u and C_gap are then set by the prior bound, not the data, and are unreliable; check {'the spectrum' if single else 'the three spectra'}"
        for side, bound, c_bound, share in _piled_bounds(u_draws, reparametrization.lower[0], reparametrization.upper[0])
    ]


def _gap_identification(edl, piled_up: Mapping[str, str], alpha_draws, ep_q: str | None = None) -> str | None:
    """Why the data do not determine C_gap apart from the EP element, or None when they do:
    the EDL fit puts C_gap in a group of parameters not separately determined
    (`FitResult.unidentified_groups`); the EP CPE's α has its posterior median at or above
    `EP_ALPHA_IDEAL` (an ideal capacitor in parallel with C_gap: only the sum counts); or the EP
    CPE's Q (``ep_q``) piles up against the lower edge of its prior (``piled_up``, as
    `Posterior.piled_up`: the CPE vanishes and C_gap takes all the capacitance: the fit is left
    with R_EP ∥ C, which an ideal EP capacitor in parallel with C_gap gives too, whatever the
    split; said of the model, not the remainder, which that model may miss: `_misfit_text`)."""
    for group in edl.unidentified_groups:
        if len(group) > 1 and "C_gap" in group:
            return f"{', '.join(group)} are not separately determined"
    if ep_q is not None and piled_up.get(ep_q) in ("lower", "both"):
        return f"the EP CPE vanishes ({ep_q} piles up at the lower end of its prior): the fit is left with R_EP ∥ C_gap, which an ideal EP capacitor beside C_gap gives too"
    if alpha_draws is not None and float(np.median(alpha_draws)) >= EP_ALPHA_IDEAL:
        return f"the EP CPE's α is {float(np.median(alpha_draws)):.3f} (≥ {EP_ALPHA_IDEAL:g}): an ideal capacitor in parallel with C_gap"
    return None


MERGED_FIT_RATIO = 1.1
"""u is not determined when `IDENTIFIED_C_REMAINDER` (R_EP ∥ one capacitor) fits the remainder
with an rms_rel at most this times the EDL model's: the EP element adds nothing a capacitor
beside C_gap would not (an ideal C_EP; the numpy test: 0.4 % against the EDL fit's 3.3 %; a CPE
EP with α = 0.3: 10.7 % against 0.43 % on the shipped example)."""


BOUND_STDERRS = 2.0
"""The lower bound of u takes the summed capacitance at the upper end of its fit's interval,
C + this × stderr (≈ 95 %, as `UNDETERMINED_STDERRS`): the fitted C itself is no bound, and on a
single SYNTHETIC Sirin-style trial (tests/test_models_gap.py, seed 11) its gap lay 0.47 % above
the true u, with a standard error of 0.74 % of C."""
BOUND_QUANTILE = 0.5 * math.erfc(BOUND_STDERRS / math.sqrt(2.0))
"""With ``--ep C`` the bound is this quantile of the sampled u (Φ(−2) ≈ 2.3 %, the same reach as
C + `BOUND_STDERRS` stderr, u being ∝ 1/C): the median, reported before, had half the posterior
of the summed capacitance's gap below it."""


EP_DELTA_AIC = 10.0
"""u is determined all the same, though `IDENTIFIED_C_REMAINDER` comes within `MERGED_FIT_RATIO`
of the EDL model's rms_rel, when the EDL model's AIC lies more than this below its (both fitted
to the same points with the same weighting; 10, as a diagnosis's `DELTA_AIC_MIN`): rms_rel reads
residuals relative to |Z|, which a remainder's uneven noise (a difference of three spectra)
dominates at a few points, where the σ-weighted AIC weighs each point by its noise. On SYNTHETIC
Sirin-style sets (`tests/spectra.sirin_measurements`, 8 trials, 0.5 % noise, α_EP = 0.3, seeds
1000–1009) the ratio was 1.03–1.21, under 1.1 in three sets, which were called undetermined,
and the AIC difference 207–266 in every set."""


def _ep_supported(merged, edl) -> bool:
    """The EDL fit ``edl`` beats ``merged`` (`IDENTIFIED_C_REMAINDER`) by more than `EP_DELTA_AIC`
    on the same points and weighting: the EP element is no capacitor beside C_gap."""
    same = merged.weighting == edl.weighting and np.array_equal(np.asarray(merged.frequency), np.asarray(edl.frequency))
    return bool(same and merged.aic - edl.aic > EP_DELTA_AIC)


def _merged_fit(remaining: xr.Dataset, weighting: str):
    """`IDENTIFIED_C_REMAINDER` fitted to the remainder (C_EP + C_gap, all counted as C_gap)."""
    from ..fitting import fit

    return fit(parse(IDENTIFIED_C_REMAINDER), remaining, weighting=weighting)


_PRIOR_TOP = 0.9  # the sampled u "reaches the upper edge of its prior" when its q95 lies above this share of the prior's range in ln u


def _unidentified_note(reason: str, bound: float, u_draws, u_prior: tuple[float, float]) -> str:
    """The warning when u is not determined and the data give the lower bound ``bound`` [m]:
    eq 1 goes as 1/u², so the bound gives an UPPER bound of the force, and the force of the
    sampled u (``u_draws``, set by the priors; ``u_prior`` the prior's bounds [m], `gap_bounds`)
    is no estimate: the larger u runs, the smaller that force."""
    u = np.asarray(u_draws, float)
    low, u_prior_upper = u_prior
    at_top = math.log(float(np.quantile(u, 0.95)) / low) >= _PRIOR_TOP * math.log(u_prior_upper / low)
    median = float(np.median(u))
    sampled = "the sampled forces come from the prior-set u and are no estimate"
    if median > _BOUND_FACTOR * bound:
        ratio = median / bound
        sampled += (
            f": the sampled u's median, {_gap_length(median)}, lies {ratio:.3g}× above the bound, which puts the force about {ratio * ratio:.3g}× below the largest the data allow"
            + (f" (its draws run to the upper edge of u's prior, {u_prior_upper:.3g} m, where the force is smallest)" if at_top else "")
            + ": a force drawn from it is at best a lower bound, not an upper one"
        )
    return (
        f"u is NOT determined by these data: {reason}, so C_gap and the EP branch are seen only as their sum; "
        f"u ≥ {_gap_length(bound)} (the gap of the summed capacitance, fitted as {IDENTIFIED_C_REMAINDER}, at the upper end C + {BOUND_STDERRS:g} stderr of its fit) is all they give, "
        "and the reported u and its interval come from the priors (JSON gap_identified false, gap_um_lower_bound). "
        "The force is NOT determined either: eq 1 goes as 1/u², so u ≥ that bound gives only an upper bound of the force, the force at u = the bound "
        f"(the report's 'force bound', JSON force_upper_bound_n); {sampled}"
    )


def _force_upper_bound(values: Mapping[str, float] | None, lower: float | None, freq, z_skin, z_ts, *, area: float, v0: float, eps_gap: float) -> xr.DataArray | None:
    """The PEAK force [N] over ``freq`` at u = ``lower`` [m], u's lower bound: eq 1,
    F = ½ ε0 ε_gap A |ΔV_gap|²/u², with the gap voltage of `IDENTIFIED_C_REMAINDER` at ``values``
    (fitted to the remainder: the voltage across C_EP + C_gap, whatever their split). u ≥ ``lower``
    gives F ≤ this. None without a bound."""
    if lower is None or values is None:
        return None
    params = {k: float(v) for k, v in values.items()}
    force = gap_force_peak(params, np.asarray(freq, float), z_skin, z_ts, area=area, v0=v0, remainder=IDENTIFIED_C_REMAINDER, eps_gap=eps_gap, gap=lower)
    return xr.DataArray(np.asarray(force, float), dims="frequency", coords={"frequency": np.asarray(freq, float)}, name="force_upper_bound",
                        attrs={"units": "N", "convention": FORCE_CONVENTION, "description": "peak force at u's lower bound: the largest the data allow (eq 1, F ∝ 1/u²)"})


def _area_unit_ruled_out(paper_gap: float, area: float) -> str:
    """Why the area's unit cannot make u no air gap: at this area the paper's method gives a u
    within `PLAUSIBLE_GAP_M`, which a unit slip of A (10⁶× for mm² read as m²) would move out of
    it. Worded so that it does not call the contact an air gap beside the alarm NO AIR GAP (not
    "…, an air gap", as of a resistive remainder)."""
    low, high = PLAUSIBLE_GAP_M
    return (f"the area's unit is not the cause: at A = {area:g} m² the paper's method gives u = {_gap_length(paper_gap)}, "
            f"within {format_quantity(low, 'm')}–{format_quantity(high, 'm')}, which a unit slip of A (10⁶×) would not")


def _area_advice(notes: list[str], paper: PaperGapEstimate, identified: bool, single: bool = False) -> list[str]:
    """``notes`` with the advice "check the area's unit first" (`AREA_UNIT_ADVICE`, of u at a
    bound of its prior or outside `PLAUSIBLE_GAP_M`) replaced where the area's unit cannot be
    the cause: the paper's method gives an air gap (u within `PLAUSIBLE_GAP_M`) at this area,
    which a unit slip of the area (a factor 10⁶ for mm² as m²) would not. The cause is then u not
    determined (when ``identified`` is False), else the data or the model."""
    low, high = PLAUSIBLE_GAP_M
    if not low <= paper.gap <= high:
        return notes
    instead = (
        f"{_area_unit_ruled_out(paper.gap, paper.area)}: "
        + ("u is not determined by these data (the warning 'u is NOT determined')" if not identified else f"check {'the spectrum' if single else 'the three spectra'} and the model")
    )
    return [note[: note.index(AREA_UNIT_ADVICE)] + instead if AREA_UNIT_ADVICE in note else note for note in notes]


def _force_bands(param_draws: dict, freq, z_skin, z_ts, circuit, *, area, v0, eps_gap) -> xr.Dataset:
    """PEAK force quantiles over ``freq`` from draws of the circuit parameters (vmapped)."""
    import jax
    import jax.numpy as jnp

    draws = {k: jnp.asarray(v) for k, v in param_draws.items()}
    bands = []
    for model in (str(circuit), "C_gap"):
        fn = jax.jit(jax.vmap(lambda p, m=model: gap_force_peak(p, jnp.asarray(freq), z_skin, z_ts, area=area, v0=v0, remainder=m, eps_gap=eps_gap)))
        volts = jax.jit(jax.vmap(lambda p, m=model: _gap_voltage_amplitude(p, jnp.asarray(freq), z_skin, z_ts, v0=v0, remainder=m)))
        quantiles = [dict(zip(("q05", "median", "q95"), np.quantile(np.asarray(g(draws)), [0.05, 0.5, 0.95], axis=0))) for g in (fn, volts)]
        bands.append(_band_dataset(*quantiles, freq))
    return _branches(bands)


def _gap_voltage_amplitude(params, freq, z_skin, z_ts, *, v0, remainder):
    """|ΔV_gap| [V], the amplitude of the voltage across C_gap (`gap_voltage`); pure JAX."""
    import jax.numpy as jnp

    return jnp.abs(gap_voltage(params, freq, z_skin, z_ts, v0=v0, remainder=remainder))


def _band_dataset(force, voltage, freq) -> xr.Dataset:
    """One branch's bands over ``frequency``: the force's ``median``, ``q05``, ``q95`` [N] and the
    gap voltage's ``gap_voltage_median``, ``_q05``, ``_q95`` [V] (mappings of those quantiles)."""
    data = {k: ("frequency", np.asarray(force[k], float)) for k in ("median", "q05", "q95")}
    data.update({f"gap_voltage_{k}": ("frequency", np.asarray(voltage[k], float)) for k in ("median", "q05", "q95")})
    return xr.Dataset(data, coords={"frequency": freq})


def _branches(bands) -> xr.Dataset:
    """The with-EP and without-EP bands (`_band_dataset`) over ``branch``, with their units."""
    force = xr.concat(bands, dim=xr.DataArray(list(FORCE_BRANCHES), dims="branch"))
    for k in ("median", "q05", "q95"):
        force[k].attrs.update(units="N", convention=FORCE_CONVENTION)
        force[f"gap_voltage_{k}"].attrs.update(units="V", description="amplitude |ΔV_gap| of the voltage across C_gap for a drive of amplitude v0 (Sirin §2.4)")
    return force


def _hierarchical(total, skin, touchscreen, remaining, paper, naive, edl, circuit, reparametrization, *, area, v0, ep, eps_gap, steps, warmup, chains, seed, progress, notes=(), model_requested=None) -> GapAnalysis:
    """The hierarchical gap analysis: per-trial remainders, per-trial u and EP branch."""
    from ..fitting import fit
    from ..fitting.bayes.hierarchical import sample_hierarchical
    from ..fitting.bayes.progress import announce

    trials = trial_remainders(total, skin, touchscreen)
    free = set(circuit.parameter_names()) - {"C_gap"}
    per_trial = ("u",) + tuple(n for n in _EP_PER_TRIAL if n in free)
    n_trials = int(np.prod([n for d, n in trials["Z"].sizes.items() if d != "frequency"]))
    announce(f"gap: fitting the EDL model to each of the {n_trials} total trials …", progress)
    batch = fit(circuit, trials, init=dict(edl.values), weighting="modulus")
    strays = _per_trial_centre_notes(batch, edl, reparametrization, per_trial)
    sigma = trial_remainder_sigma(total, skin, touchscreen) if strays else None
    if sigma is not None:  # (|Z| weighting let noise-dominated bands move the trials' fits: weight them as the likelihood does)
        weighted = trials.assign(sigma=(trials["Z"].dims, np.broadcast_to(sigma, trials["Z"].shape).copy(), {"units": "ohm"}))
        batch = fit(circuit, weighted, init=dict(edl.values), weighting="sigma")
        strays = _per_trial_centre_notes(batch, edl, reparametrization, per_trial)
    notes = list(notes) + strays
    _check_trials_hold_a_gap(batch, total)
    announce(f"gap: the hierarchical model, NUTS ({chains} chains, warm-up {warmup} + {steps} draws) …", progress)
    post, retry_notes = sampled_with_retry(
        lambda target: sample_hierarchical(circuit, trials, per_trial=per_trial, reparametrization=reparametrization, init=batch, chains=chains, warmup=warmup, draws=steps, seed=seed, progress=progress, target_accept=target),
        progress,
    )
    notes += retry_notes
    freq = remaining["frequency"].values
    z_skin, z_ts = _series_impedances(skin, touchscreen)
    pop = post.population_parameters()
    step = max(1, post.n_draws // 1000)
    force = _force_bands({k: v[::step] for k, v in pop.items()}, freq, z_skin, z_ts, circuit, area=area, v0=v0, eps_gap=eps_gap)
    restating = _bound_notes(pop["u"], reparametrization, area, _single(remaining))  # (left out under the alarm NO AIR GAP: `_no_air_gap_said_once`)
    notes += restating + _gap_breakdown_notes(force, float(np.median(pop["u"])), area, eps_gap)
    known_kk = KKChains()
    notes += _edl_fit_warnings(edl, remaining, known_kk) + [f"sampling: {hierarchical_advice_of_gap(w, steps)}" for w in post.warnings]
    comparison = _estimate_bound_notes("population gap thickness", float(np.median(pop["u"])), paper, remaining)
    notes += comparison
    restating += comparison
    lower, withheld, merged = _identification(ep, model_requested, circuit, pop, edl, {}, notes, remaining, area, eps_gap, known_kk)  # (the rule reads a single posterior's pile-up; the hierarchical one's, `HierarchicalPosterior.piled_up`, is of population medians, and only its warnings are passed on)
    bound_force = _force_upper_bound(merged, lower, freq, z_skin, z_ts, area=area, v0=v0, eps_gap=eps_gap)
    notes = _area_advice(notes, paper, lower is None and withheld is None, _single(remaining))
    analysis = GapAnalysis(remaining, paper, naive, edl, None, force, area, v0, ep, tuple(notes), method="hierarchical", hierarchical=post, model_requested=model_requested, gap_lower_bound=lower, gap_bound_withheld=withheld,
                           edl_misfit=_misfit_text(edl, remaining, known_kk), force_upper_bound=bound_force, settings={"eps_gap": eps_gap})  # (gap_analysis sets the whole settings)
    return _no_air_gap_said_once(analysis, restating)


def _misfit_text(fitted, remaining: xr.Dataset, known_kk: KKChains) -> str | None:
    """How a least-squares fit of the trial-mean remainder misses it grossly, by the rule of its
    misfit warning (`gross_misfits`: rms_rel ≥ `GROSS_MISFIT_FROM` and over `MISFIT_RATIO_MAX` ×
    what a Kramers–Kronig-consistent model reaches, ``known_kk`` its memory, and, for a fit
    weighted by the remainder's sigma, χ²_red beyond what that noise gives), else None. A single
    contact's is "the spectrum", nothing having been subtracted (not "the remainder",
    as of the REAL data.dfr and Gamry files as single contacts)."""
    freq, z = remaining["frequency"].values, remaining["Z"].values
    sigma = remaining["sigma"].values if "sigma" in remaining else None
    if gross_misfits(freq, z, fitted.z_model, known_kk, sigma=sigma, weighting=fitted.weighting, n_free=len(fitted.free_names)).size == 0:
        return None
    kk = float(known_kk_misfits(freq, z[None], np.array([0]), known_kk)[0])
    return f"{fitted.model} misses {'the spectrum' if _single(remaining) else 'the remainder'} (rms_rel {format_percent(fitted.rms_rel)}, over {MISFIT_RATIO_MAX:g}× the {format_percent(kk)} a Kramers–Kronig-consistent model reaches)"


def _identification(ep, requested, circuit, draws, edl, piled_up, notes, remaining, area, eps_gap, known_kk=None) -> tuple[float | None, str | None, dict | None]:
    """(lower bound of u [m], None) when u is not determined (``notes`` gains why); (None, why
    no bound) when it is not determined but the model of the bound, `IDENTIFIED_C_REMAINDER`,
    misses the remainder grossly (`_misfit_text`: its capacitance is then no C_EP + C_gap, and
    on the SYNTHETIC stationary example, 53 % off, its 0.165 µm lay above the true 0.139 µm);
    (None, None) when u is determined. ``piled_up``: the sampled parameters piled up against a
    prior's edge (`Posterior.piled_up`). ``ep="C"`` (merged capacitors): the sampled u's lower
    end (`BOUND_QUANTILE`) is that bound. ``known_kk``: the remainder's KK chain, once fitted (`kk.KKChains`).
    Third: the values of `IDENTIFIED_C_REMAINDER` fitted to the remainder when there is a bound
    (the force's upper bound takes its gap voltage: `_force_upper_bound`), else None."""
    known_kk = KKChains() if known_kk is None else known_kk
    if ep == "C" and str(circuit) == IDENTIFIED_C_REMAINDER and str(requested) != str(circuit):
        misfit = _misfit_text(edl, remaining, known_kk)
        if misfit is None:
            return float(np.quantile(np.asarray(draws["u"]), BOUND_QUANTILE)), None, dict(edl.values)
        withheld = _withheld_text(misfit)
        notes.insert(0, f"u is NOT determined by --ep C (C_EP and C_gap are seen only as their sum), and no lower bound is given: {withheld}")
        # (--ep C's own note promised u's smallest value and the force's upper bound: not here)
        notes[:] = [_merged_capacitors_note(withheld=True) if n == _merged_capacitors_note() else n for n in notes]
        return None, withheld, None
    if not any(n.startswith(("CPE_EP.", "C_EP")) for n in circuit.parameter_names()):
        return None, None, None  # no EP element beside C_gap to confuse it with
    alpha = next((np.asarray(v) for k, v in draws.items() if k.endswith(".alpha") and "EP" in k), None)
    ep_q = next((k for k in circuit.parameter_names() if k.endswith(".Q") and "EP" in k), None)
    reason = _gap_identification(edl, piled_up, alpha, ep_q)
    merged = _merged_fit(remaining, "sigma" if "sigma" in remaining else "modulus")
    if reason is None and merged.rms_rel <= MERGED_FIT_RATIO * edl.rms_rel and not _ep_supported(merged, edl):
        reason = f"{IDENTIFIED_C_REMAINDER} fits the remainder as well as {circuit} (rms_rel {format_percent(merged.rms_rel)} against {format_percent(edl.rms_rel)}): the EP element acts as a capacitor beside C_gap"
    if reason is None:
        return None, None, None
    misfit = _misfit_text(merged, remaining, known_kk)
    if misfit is not None:
        withheld = _withheld_text(misfit)
        notes.insert(0, f"u is NOT determined by these data: {reason}, and no lower bound is given: {withheld}; the reported u and its interval come from the priors (JSON gap_identified false, gap_um_lower_bound null, gap_bound_withheld), and the force drawn from them is no estimate and bounds nothing")
        return None, withheld, None
    c_sum, c_stderr = float(merged.values["C_gap"]), float(merged.stderr["C_gap"])
    if not np.isfinite(c_stderr):
        withheld = f"the capacitance of {IDENTIFIED_C_REMAINDER} fitted to the remainder has no standard error, so its upper end, which the bound needs, is unknown"
        notes.insert(0, f"u is NOT determined by these data: {reason}, and no lower bound is given: {withheld} (JSON gap_identified false, gap_um_lower_bound null, gap_bound_withheld)")
        return None, withheld, None
    bound = EPSILON_0 * eps_gap * area / (c_sum + BOUND_STDERRS * c_stderr)
    notes.insert(0, _unidentified_note(reason, bound, draws["u"], gap_bounds(area, eps_gap)))
    return bound, None, dict(merged.values)


def _withheld_text(misfit: str) -> str:
    """Why no lower bound of u is given: the model of the bound misfits (``misfit``)."""
    return (
        f"the bound would come from {IDENTIFIED_C_REMAINDER} (all the capacitance as C_gap), but {misfit}: "
        "its capacitance is a compromise over a curve it does not follow, not C_EP + C_gap, and bounds nothing (u may lie below it)"
    )
