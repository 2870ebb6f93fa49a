"""Linear Kramers–Kronig test: is a spectrum causal, linear and stationary?

A spectrum is fitted by a chain of M Voigt (R∥C) elements whose time constants are fixed and
log-spaced over the measured range, plus a series resistance (and optionally a series
inductance and capacitance). Every such circuit obeys the Kramers–Kronig relations, and the fit
is linear in its parameters, so it is one least-squares solve per M. Residuals well above the
noise, or structured ones, mark frequency bands where the data are not KK-consistent: drift
during the sweep, electrodermal activity, movement — data problems, not model problems.

Method: Schönleber, Klotz, Ivers-Tiffée, "A Method for Improving the Robustness of linear
Kramers-Kronig Validity Tests", Electrochimica Acta 131 (2014) 20–27 (eqs 7–13 and the µ
criterion, eq 21); the validity rule (noise estimate, thresholds, bands) is impedax's own and is
described in `kk_test` and docs/kk.md.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import math
from dataclasses import dataclass, field
from typing import Mapping, NamedTuple

import numpy as np
import xarray as xr

from ..arguments import EXCLUDE_RTOL, MAX_BASIS, checked_arguments, count, flag, instance_of, real, shown
from ..constants import CONCLUSIVE_POINTS_MIN
from ..data import checked_frequencies, column_width, concise_repr, report_text, counted, format_band, format_frequency, format_percent_column, label_text
from ..errors import DataError, ImpedaxError, ParameterError
from ..io.netcdf import result_dataset
from .grid import ResultGrid, refuse_result_names
from .problem import frequency_and_z, frequency_z_and_sigma
from .statistics import KK_RESIDUAL_NOISE, difference_noise, non_passive, non_passive_words, residual_noise
from .frozen import FrozenResult, freeze_fields

__all__ = ["KKResult", "KKBatchResult", "ValidityGrid", "kk_test", "kk_test_batch", "passing_band", "retested_band", "band_name", "band_points", "kk_misfits", "kk_sigma_misfits", "kk_verdicts", "KKChains", "NOISE_SOURCES", "noise_shapes", "rejudged", "DEFAULT_THRESHOLDS", "CONCLUSIVE_POINTS_MIN", "RULE_NAMES", "BAND_MERGE_DECADES", "band_rules", "band_rule_counts", "bad_band_lines", "note_and_hint_lines", "points_text", "thresholds_for", "left_out_options", "frequency_text"]


# Validity rule (see `kk_test`): scale = max(noise_estimate, noise_floor).
DEFAULT_THRESHOLDS: Mapping[str, float] = {
    "point": 5.0,  # one point with |Δ| > 5·scale is bad
    "run": 3.0,  # ... or `run_length` consecutive points with |Δ| > 3·scale
    "run_length": 3,
    "window_mean": 4.5,  # ... or the mean of Δ' or Δ'' over `window` neighbours > 4.5·scale/sqrt(window)
    "window": 9,
    "noise_floor": 2e-3,  # relative; below this, residuals are Voigt-approximation error, not data problems
    "reference_points": 61,  # the thresholds above hold up to this many points; raised beyond (`thresholds_for`)
}


def thresholds_for(rules: Mapping[str, float], n_points: int) -> dict[str, float]:
    """The thresholds applied to a spectrum of ``n_points`` frequencies.

    Each test looks at about N positions, so with fixed thresholds its false alarms would grow
    in proportion to N. Beyond ``reference_points`` (N_ref) each threshold t is raised so that
    the expected number of false alarms per spectrum stays that of N_ref points: a Gaussian or
    Rayleigh tail falls as exp(−t²/2), so t² grows by 2 ln(N/N_ref) for the point and window
    tests and by (2/L) ln(N/N_ref) for a run of L points (each of the L points pays its share).
    ``reference_points`` of the returned rule is max(N, N_ref), so applying it again changes
    nothing.
    """
    applied = dict(rules)
    n_ref = rules["reference_points"]
    if n_points <= n_ref:
        return applied
    growth = 2.0 * math.log(n_points / n_ref)
    applied["point"] = math.sqrt(rules["point"] ** 2 + growth)
    if "window_mean" in rules:  # (Z-HIT has no window test)
        applied["window_mean"] = math.sqrt(rules["window_mean"] ** 2 + growth)
    applied["run"] = math.sqrt(rules["run"] ** 2 + growth / max(int(rules["run_length"]), 1))
    applied["reference_points"] = float(n_points)
    return applied



# JSON key → attribute of `KKResult` (`KKResult.summary`, ``impedax kk --json``)
_JSON_KEYS = {
    "valid": "valid", "rms_rel": "rms_rel", "bad_bands": "bad_bands", "n_rc": "n_rc", "mu": "mu", "mu_reached": "mu_reached",
    "noise_estimate": "noise_estimate", "frequency_hz": "frequency", "residuals_real": "residuals_real", "residuals_imag": "residuals_imag",
    "conclusive": "conclusive", "chain_error": "chain_error", "non_passive_hz": "non_passive_frequencies",
}
# per band its flagged measured frequencies, the options that leave the
# failing points out, and whether only marginal isolated points are left
_JSON_KEYS_ADDED = {"bad_band_frequencies_hz": "band_frequencies", "suggested_options": "suggested_options", "marginal_points_only": "marginal_points_only",
                    "stray_points_hz": "stray_frequencies", "passing_band_hz": "passing_band", "passing_rms_rel": "passing_rms_rel"}
# added keys (never renamed): the method, units in the name (``_hz``; ``_rel`` = a fraction of |Z|)
# and the rules that flagged each band with their levels (`KKResult.summary`)

NON_PASSIVE_LEAVE_OUT = "leave them out (data.drop_sel(frequency=result.non_passive_frequencies))"
"""How the linear test's and Z-HIT's note on points with Re Z < 0 (`KKResult.non_passive_note`)
ends, in Python's words; ``impedax kk`` says ``leave them out with --fmin/--fmax``
(`cli.common.command_line_words`)."""

RETEST_WITHOUT_THEM = "kk_test(data.drop_sel(frequency=result.excludable_frequencies))"
TRIMMED_DATA_TOO = "fit, diagnose and refine take the data so trimmed"
BAND_CUT_AT_END = {True: "data.where(data.frequency >= f, drop=True)", False: "data.where(data.frequency <= f, drop=True)"}  # (low end: True; impedax kk says --fmin, --fmax)
"""The report's ``next:`` step in Python's words (`KKResult.next_step` without the command line,
which ``impedax kk`` gives: the run's command with ``--exclude``/``--fmin``/``--fmax``; the options
alone would be words no Python call takes)."""


DIAGNOSE_MASKING = ("diagnose and refine leave KK-flagged points out by themselves only where the test passes without them (a few erratic points) "
                    "or where they are a short run at an end of the band, and say so; otherwise they keep them in every fit, as the data's problem")
"""What the ``next:`` step says diagnose and refine do with the points it suggests leaving out
(`diagnosis.kk_outliers`, `diagnosis.end_runs`, `diagnosis.KK_MASK_MAX_FRACTION`). It does not
say refine leaves them out by itself: on REAL BioLogic refine keeps all four points in every fit
(without them the test still fails)."""


FEW_BAND_POINTS = 3
"""A band of at most this many flagged points is "a few points": the report names their measured
frequencies (which ``--exclude`` takes; the band's edges lie between points), and one inside the
range is left out by ``--exclude`` in `KKResult.suggested_options`. More points in a row inside
the range are a disturbance during the sweep, not stray points (docs/kk.md, "What to do")."""

MARGINAL_POINT_RATIO = 1.2
"""An isolated point whose |Δ| is below this multiple of the point rule's level (6 s for the 5 s
level) is marginal: when every bad band is one such point, the report says to stop leaving points
out (`KKResult.marginal_points_only`). On BioLogic's REAL file the points flagged after the first
round of exclusions were at 5.03 s, each exclusion letting the chain refit and another point of
the scatter's tail cross 5 s (docs/kk.md, "When to stop")."""

NEGATIVE_SHARE_FAR = 2.0
"""µ is far below c when the negative resistances' share Σ|R_k<0|/Σ|R_k≥0| = 1 − µ is at least
this many times the 1 − c the cut-off allows (µ ≤ 0.7 for c = 0.85): the chain has gone well past
the onset of negative R where Schönleber's rule stops (a reading of µ, no paper value). REAL
exampleData.csv without the series C: M = 32, µ = 0.038, 16 of 32 R negative; SYNTHETIC
100 Ω + 1 kΩ‖1 ms at 0.5 % noise, 61 points, seeds 0–4: µ 0.52–0.82 at M = 18–20, all valid
(impedax's M is the first with µ < c that fits the data, docs/kk.md "Choosing M"; `KKResult.mu_words`)."""

PASSING_BAND_EVERY_SPLIT = 8
"""When the test fails and no point can be left out by the rules of `KKResult.excludable_frequencies`
(a band at an end too wide, or a band inside), `kk_test(find_passing_band=True)` tests again
without points at the ends: every split between the low and the high end of up to this many
points in all (at most 44 tests), then a staircase through the larger trims (one test per step:
a trim that passes is narrowed at the high end, one that fails widened at the low end; at most
two tests per point), keeping at least half of the points and `CONCLUSIVE_POINTS_MIN`. The fewest
points left out win, then the lowest rms_rel. On the REAL files of impedance.py and AutoEIS
(2026-12-03): Parstat passes at 10 Hz–2.51 kHz without its 6 highest points (0.31 %, where the
whole fails at 18.9 %), PowerSuite without its 2 highest (2.5 %), CH Instruments without its 20
lowest and its highest (0.26 %), the trims a test of every split finds too; Gamry passes on no
such band (under 0.5 s of search)."""

EDGE_DECADES = 0.5
"""The end of a passing band (`KKResult.passing_band`) checked for what the points left out
may have left in it: its points within this many decades of the cut (`passing_edge`)."""

EDGE_EXCESS = 5.0
"""… stand off the band's chain by more than this many times the median |Δ| of the band's
other points (rms over the edge's points): the disturbance reaches into the band below the
test's levels. A SYNTHETIC drift of Re Z (10 Ω + 100 Ω ∥ 100 µF plus a drift 109 % of |Z| at
10 mHz, 7 % at 316 mHz, 0 from 1 Hz; exact data) passes on 316 mHz–100 kHz, its lowest half
decade 0.41–0.89 % off the chain against a median of 0.018 % under the 0.2 % floor, and R1
fitted there is 0.9 % (4.7 σ) high where --fmin 1 gives it exactly; at 0.3 % noise the noise
hides the edge and nothing is said (4 of 4 seeds; tests/test_kk_passing_edge.py)."""

RULE_NAMES = ("point", "run", "window")
"""The validity rules (`kk_test`), as `KKResult.band_rules` names them."""


def band_name(points) -> str:
    """A bad band in a report, by its flagged measured frequencies [Hz] (ascending): each of them
    for a band of at most `FEW_BAND_POINTS` (``the point at 5.34 Hz``: ``--exclude`` takes them),
    else the lowest and highest (``15.9 mHz – 2.02 kHz``; the band's edges, ``bad_bands``, lie
    halfway to the neighbouring points, where the figure shades)."""
    if len(points) <= FEW_BAND_POINTS:
        return f"the point{'s' if len(points) > 1 else ''} at {', '.join(format_frequency(float(f)) for f in points)}"
    return format_band(float(points[0]), float(points[-1]), " – ")


@dataclass(frozen=True, eq=False)
class KKResult(FrozenResult):
    """Outcome of the linear Kramers–Kronig test on one spectrum (arrays in the data's order).

    ``residuals_real``/``residuals_imag`` are Δ = (Z_data − Z_kk)/|Z_data| (dimensionless);
    ``rms_rel = sqrt(mean |Δ|²)``; ``noise_estimate`` is the robust per-component standard
    deviation of the random part of Δ; ``bad_bands`` are [(f_min, f_max)] in Hz;
    ``chain_error`` is the default reference chain's own misfit on these frequencies
    (`chain_error` of `reference_rc`), a floor of ``threshold_scale``; ``noise_from``:
    ``"sigma"`` when the chain was weighted by the data's stated σ and each point judged against
    its own ``point_scale``, ``"residuals"`` when every point was judged against one scale; ``sign_hint``: why and how
    the imaginary part may be stored with the opposite sign (`io.sign_check.sign_hint`), or None.
    """

    __repr__ = concise_repr  # (the generated one printed every array)
    __str__ = report_text  # (print(result): its report)

    frequency: np.ndarray
    impedance: np.ndarray
    kk_impedance: np.ndarray
    residuals_real: np.ndarray
    residuals_imag: np.ndarray
    flagged: np.ndarray
    n_rc: int
    mu: float
    mu_reached: bool
    rms_rel: float
    noise_estimate: float
    threshold_scale: float
    valid: bool
    bad_bands: tuple[tuple[float, float], ...]
    time_constants: np.ndarray
    resistances: np.ndarray
    series_resistance: float
    series_inductance: float
    inverse_series_capacitance: float
    c: float
    thresholds: Mapping[str, float] = field(default_factory=lambda: dict(DEFAULT_THRESHOLDS))
    chain_error: float = 0.0
    sign_hint: str | None = None  # `io.sign_check.sign_hint`: Z'' may be stored with the opposite sign
    n_rc_given: bool = False  # M was fixed by ``n_rc=`` (not chosen by the µ rule)
    # the measured frequencies [Hz] of the stray points left out of the chain's
    # fit, ascending (`kk_test`; docs/kk.md, "Stray points"); they are judged like the others
    stray_frequencies: np.ndarray = field(default_factory=lambda: np.zeros(0))
    # each point's scale max(σ/|Z|, floors) when judged by the data's stated σ
    # (data order; ``threshold_scale`` is then its median), None when judged by ``noise_estimate``
    point_scale: np.ndarray | None = None
    noise_from: str = "residuals"  # "sigma": the chain weighted by 1/σ and each point judged by its σ (`kk_test`'s ``noise``)
    # `kk_test(find_passing_band=True)` of a failed test with no point to leave
    # out by the bands' rules: the lowest and highest measured frequency [Hz] of the band, left by
    # leaving points out at the ends, on which the test passes, and its rms_rel there; None when not
    # searched or none found (`PASSING_BAND_EVERY_SPLIT`)
    passing_band: tuple[float, float] | None = None
    passing_rms_rel: float | None = None
    # the passing band's end(s) toward the points left out, when their |Δ|
    # against its chain stands out (`EDGE_EXCESS`): lowest and highest frequency [Hz] of those
    # points, their smallest and largest |Δ| and the band's other points' median |Δ| (fractions
    # of |Z|); None otherwise (`passing_edge_words`)
    passing_edge: tuple[float, float, float, float, float] | None = None

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    def predict(self, freq) -> np.ndarray:
        """The KK fit's impedance [Ω] at ``freq`` [Hz]: R_0 + jωL + (1/C)/(jω) + Σ R_k/(1 +
        jωτ_k) (Schönleber 2014 eq 7; L and 1/C zero when not fitted)."""
        omega = 2 * np.pi * checked_frequencies(freq)
        voigt = 1.0 / (1.0 + 1j * omega[..., None] * self.time_constants) @ self.resistances
        return self.series_resistance + 1j * omega * self.series_inductance - 1j * self.inverse_series_capacitance / omega + voigt

    @property
    def non_passive_frequencies(self) -> np.ndarray:
        """The frequencies [Hz] of the points whose Re Z < 0 beyond the noise
        (`statistics.non_passive`, against `non_passive_noise`): no passive circuit reaches
        them, the Voigt chain with signed resistances does. `diagnose` and `refine` leave them
        out before their own test."""
        return np.sort(self.frequency[non_passive(self.impedance, noise=self.non_passive_noise)])

    @property
    def non_passive_noise(self) -> np.ndarray | None:
        """σ [Ω] of each component at each point that Re Z < 0 is judged against
        (`statistics.non_passive`): the robust noise estimate of the residuals
        (``noise_estimate``, first differences) × |Z|; None where it is not finite."""
        if not math.isfinite(self.noise_estimate):
            return None
        return self.noise_estimate * np.abs(self.impedance)

    @property
    def conclusive(self) -> bool:
        """Whether the spectrum has enough frequencies (`CONCLUSIVE_POINTS_MIN`) for the test to
        tell data problems from the Voigt chain's own misfit: on 6 points the chain holds 3 RC
        elements, leaves 20 % on data a circuit fits exactly, and reads that as noise."""
        return self.frequency.size >= CONCLUSIVE_POINTS_MIN

    def to_xarray(self) -> xr.Dataset:
        """Residuals, KK fit and flags over ``frequency``; scalars and settings as variables/attrs.
        ``residuals_real``/``residuals_imag`` = Re/Im (Z − Z_kk)/|Z| (data minus model)."""
        f = ("frequency", self.frequency, {"units": "Hz"})
        lo = np.array([b[0] for b in self.bad_bands], dtype=float)
        hi = np.array([b[1] for b in self.bad_bands], dtype=float)
        return result_dataset(xr.Dataset(
            {
                "Z": ("frequency", self.impedance, {"units": "ohm", "long_name": "measured impedance"}),
                "Z_kk": ("frequency", self.kk_impedance, {"units": "ohm", "long_name": "fitted Kramers-Kronig (Voigt chain) impedance"}),
                "residuals_real": ("frequency", self.residuals_real, {"units": "1", "long_name": RESIDUAL_LONG_NAMES[0]}),
                "residuals_imag": ("frequency", self.residuals_imag, {"units": "1", "long_name": RESIDUAL_LONG_NAMES[1]}),
                "flagged": ("frequency", self.flagged, {"long_name": "point flagged as not KK-consistent (a bad band may hold unflagged points)"}),
                "point_scale": ("frequency", np.array(self.scale_per_point, float), {"units": "1", "long_name": POINT_SCALE_LONG_NAME}),
                "stray": ("frequency", self.stray_points, {"long_name": STRAY_LONG_NAME}),
                "bad_band_f_min": ("band", lo, {"units": "Hz"}),
                "bad_band_f_max": ("band", hi, {"units": "Hz"}),
                "time_constant": ("rc", self.time_constants, {"units": "s"}),
                "resistance": ("rc", self.resistances, {"units": "ohm"}),
                "n_rc": ((), self.n_rc),
                "mu": ((), self.mu),
                "rms_rel": ((), self.rms_rel, {"units": "1"}),
                "noise_estimate": ((), self.noise_estimate, {"units": "1"}),
                "valid": ((), self.valid),
                "conclusive": ((), self.conclusive),
            },
            coords={"frequency": f},
            attrs={
                "impedax_kind": "kk",  # impedax inspect names the file a KK test's, as other results
                "method": "linear Kramers-Kronig test (Schoenleber et al. 2014), impedax validity rule",
                "c": self.c,
                "series_resistance_ohm": self.series_resistance,
                "series_inductance_h": self.series_inductance,
                "inverse_series_capacitance_per_f": self.inverse_series_capacitance,
                "chain_error": self.chain_error,
                "noise_from": self.noise_from,
                **({} if self.passing_band is None else {"passing_band_hz": list(self.passing_band), "passing_rms_rel": self.passing_rms_rel}),
                **{f"threshold_{k}": v for k, v in self.thresholds.items()},
            },
        ).copy(deep=True))

    def summary(self) -> dict:
        """The JSON of ``impedax kk --json`` (the keys are the public contract)."""
        out = {"method": "linear", **{key: getattr(self, attribute) for key, attribute in _JSON_KEYS.items()}}
        out["bad_bands"] = [[lo, hi] for lo, hi in self.bad_bands]
        levels = self.rule_levels
        out.update({
            "bad_bands_hz": [[lo, hi] for lo, hi in self.bad_bands], "bad_band_rules": [list(r) for r in self.band_rules],
            "noise_estimate_rel": self.noise_estimate, "chain_error_rel": self.chain_error, "threshold_scale_rel": self.threshold_scale,
            "point_threshold_rel": levels["point"], "run_threshold_rel": levels["run"], "run_length": int(self.thresholds["run_length"]),
            "window_threshold_rel": levels["window"], "window": int(self.thresholds["window"]), "sign_hint": self.sign_hint,
            # the report's notes on what the verdict rests on, and what to heed
            # (the key fit, compare and sample give): every note, and the sign hint
            "notes": self.notes, "warnings": list(self.warnings),
            # "sigma": the chain weighted by the data's σ and each point judged by
            # its σ/|Z| (the threshold keys then hold the median point's levels); "residuals": one noise estimate
            "noise_from": self.noise_from,
        })
        out.update({key: getattr(self, attribute) for key, attribute in _JSON_KEYS_ADDED.items()})
        out["bad_band_frequencies_hz"] = [list(f) for f in self.band_frequencies]
        # per band, its lowest and highest flagged measured frequency: the range
        # the text names (``bad_bands_hz`` keep the edges halfway to the neighbours)
        out["measured_bands_hz"] = [[lo, hi] for lo, hi in self.measured_bands]
        out["passing_band_hz"] = None if self.passing_band is None else list(self.passing_band)
        # the passing band's end that still stands off its chain (`passing_edge`)
        edge = self.passing_edge
        out["passing_edge"] = None if edge is None else {"band_hz": [edge[0], edge[1]], "offset_min_rel": edge[2], "offset_max_rel": edge[3], "median_rest_rel": edge[4],
                                                        "words": self.passing_edge_words()}
        return out

    def to_table(self) -> list[dict[str, object]]:
        """One row per frequency, in the data's order (``impedax kk --out FILE.csv``,
        `impedax.io.write_result`): ``frequency_hz``, the measured and the
        KK-fitted impedance (``z_real_ohm``, ``z_imag_ohm``, ``z_kk_real_ohm``,
        ``z_kk_imag_ohm``), the residuals Δ', Δ'' (fractions of |Z|, data minus fit as
        ``residuals_real``/``residuals_imag``) and ``flagged``."""
        return [
            {"frequency_hz": float(f), "z_real_ohm": float(z.real), "z_imag_ohm": float(z.imag), "z_kk_real_ohm": float(k.real), "z_kk_imag_ohm": float(k.imag),
             "residual_real": float(dr), "residual_imag": float(di), "flagged": bool(flag)}
            for f, z, k, dr, di, flag in zip(self.frequency, self.impedance, self.kk_impedance, self.residuals_real, self.residuals_imag, self.flagged)
        ]

    @property
    def notes(self) -> list[str]:
        """The caveats the report states besides the numbers (the JSON's ``notes`` and
        ``warnings``): too few frequencies for the test (`conclusive`), sparse data whose
        residuals are judged against the chain's own misfit (`sparse_note`), points with Re Z < 0
        (`non_passive_note`)."""
        notes = [] if self.conclusive else [f"inconclusive: {self.frequency.size} frequencies are too few for the test (it needs {CONCLUSIVE_POINTS_MIN})"]
        return notes + [n for n in (self.sparse_note, self.non_passive_note) if n]

    @property
    def warnings(self) -> tuple[str, ...]:
        """What to heed, as `FitResult.warnings` (the JSON's ``warnings``): every note, then the
        sign hint (a flipped sign of Im Z)."""
        return tuple(self.notes) + ((self.sign_hint,) if self.sign_hint else ())

    @property
    def sparse_note(self) -> str | None:
        """On data too sparse for the Voigt chain to fit a single relaxation within the noise
        (``chain_error`` above the noise estimate and the floor): the residuals are judged against
        that misfit, not the noise. None otherwise."""
        if self.chain_error <= max(self.noise_estimate if math.isfinite(self.noise_estimate) else 0.0, self.thresholds["noise_floor"]):
            return None
        decades = math.log10(self.frequency.max() / self.frequency.min())
        return (f"sparse data: at {self.frequency.size / decades:.2g} points a decade the Voigt chain fits a single relaxation only to "
                f"{self.chain_error * 100:.2g} % rms; residuals are judged against that, not the noise")

    @property
    def non_passive_note(self) -> str | None:
        """On points with Re Z < 0 beyond the noise (`non_passive_frequencies`), which this test
        keeps and diagnose and refine leave out; None when there are none."""
        bad = self.non_passive_frequencies
        if not bad.size:
            return None
        where = ", ".join(format_frequency(f) for f in bad[:6]) + (", …" if bad.size > 6 else "")
        noise_from = KK_RESIDUAL_NOISE if self.non_passive_noise is not None else None
        return (f"{bad.size} of {self.frequency.size} points have {non_passive_words(noise_from, self.frequency.size)} ({where}), which no passive circuit reaches; they are "
                "part of this test (impedax diagnose and refine leave them out before theirs: their verdicts may differ); " + NON_PASSIVE_LEAVE_OUT)

    @property
    def rule_levels(self) -> dict[str, float]:
        """The level of each rule as a fraction of |Z| (scale s = ``threshold_scale``): |Δ| above
        ``point`` at one point, above ``run`` at ``run_length`` consecutive points, or the mean of
        Δ' or Δ'' over ``window`` points above ``window``."""
        t, s = self.thresholds, self.threshold_scale
        return {"point": t["point"] * s, "run": t["run"] * s, "window": t["window_mean"] * s / math.sqrt(t["window"])}

    @property
    def scale_per_point(self) -> np.ndarray:
        """The scale s each point was judged against (data order): ``point_scale`` when judged by
        the stated σ, else ``threshold_scale`` at every point."""
        return np.broadcast_to(self.threshold_scale if self.point_scale is None else self.point_scale, self.frequency.shape)

    @property
    def stray_points(self) -> np.ndarray:
        """Which points (data order) the chain was fitted without as stray (`stray_frequencies`)."""
        return np.isin(self.frequency, self.stray_frequencies)

    def _rule_masks(self) -> tuple[np.ndarray, dict[str, np.ndarray], np.ndarray]:
        """(this result's flags, each rule's flags, the frequencies) in frequency order, at
        each point's scale (`scale_per_point`): the arguments of `band_rule_counts`."""
        order = np.argsort(self.frequency)
        scale = self.threshold_scale if self.point_scale is None else self.point_scale[order]
        masks = _rule_masks(self.residuals_real[order], self.residuals_imag[order], scale, self.thresholds)
        return np.asarray(self.flagged, bool)[order], masks, self.frequency[order]

    @property
    def band_rules(self) -> tuple[tuple[str, ...], ...]:
        """For each of ``bad_bands``, the rules (`RULE_NAMES`) that flagged points in it."""
        return band_rules(*self._rule_masks())

    @property
    def measured_bands(self) -> tuple[tuple[float, float], ...]:
        """For each of ``bad_bands``, its lowest and highest flagged frequency [Hz], as measured:
        the band a report names beside the points it counts (the edges of ``bad_bands`` lie
        halfway to the neighbours: REAL Gamry's band ended at 2.26 kHz, between the flagged
        2.02 kHz and 2.53 kHz, and the report named "15.9 mHz–2.26 kHz" beside "52 points
        (15.9 mHz–2.02 kHz)", one finding as two ranges)."""
        return tuple((points[0], points[-1]) for points in self.band_frequencies if points)

    def measured_bands_text(self) -> str:
        """`measured_bands` in words: ``15.9 mHz–2.02 kHz``, several joined by commas."""
        return ", ".join(format_band(lo, hi) for lo, hi in self.measured_bands)

    @property
    def band_frequencies(self) -> tuple[tuple[float, ...], ...]:
        """For each of ``bad_bands``, the measured frequencies [Hz] of its flagged points, ascending
        (the band's edges lie halfway to the neighbours; ``--exclude`` takes these)."""
        flag, _, freq = self._rule_masks()
        return band_points(freq, flag)

    @property
    def excludable_frequencies(self) -> np.ndarray:
        """The measured frequencies [Hz] whose removal `suggested_options` proposes: every point
        from an end of the data through a band at that end (``--fmin``/``--fmax``), and the flagged
        points of each band of at most `FEW_BAND_POINTS` inside the range (``--exclude``). Empty
        when the test passed, when the sign hint explains the failure, or when that would leave
        fewer than half of the points or fewer than `CONCLUSIVE_POINTS_MIN` (leaving points out is
        then no remedy). When those rules leave nothing out and a ``passing_band`` was found,
        the points outside it."""
        by_bands = self._excludable_by_bands()
        if by_bands.size or self.passing_band is None:
            return by_bands
        lo, hi = self.passing_band
        return np.sort(self.frequency[(self.frequency < lo) | (self.frequency > hi)])

    @property
    def searches_passing_band(self) -> bool:
        """Whether `kk_test(find_passing_band=True)` searches a passing band for this result
        (`retested_band`): the test failed, conclusively, not by the sign, not by marginal points
        alone, and the bands' rules leave no point out (a result that holds its band already too)."""
        return not (self.valid or self.sign_hint or not self.conclusive or self._excludable_by_bands().size or self.marginal_points_only)

    def _excludable_by_bands(self) -> np.ndarray:
        """`excludable_frequencies` by the bad bands' rules alone."""
        if self.valid or self.sign_hint:
            return np.zeros(0)
        drop, freq = self._dropped_by_bands()
        left = freq.size - np.count_nonzero(drop)
        if left < max(CONCLUSIVE_POINTS_MIN, freq.size / 2):
            return np.zeros(0)
        return freq[drop]

    def _dropped_by_bands(self) -> tuple[np.ndarray, np.ndarray]:
        """(the points the bands' rules would leave out, the frequencies), in frequency order:
        every point from an end through a band at that end, the flagged points of a band of at
        most `FEW_BAND_POINTS` inside; before `_excludable_by_bands` asks what that leaves."""
        flag, _, freq = self._rule_masks()
        drop = np.zeros(freq.size, bool)
        for i, j in _band_spans(flag, freq):
            if i == 0 or j == freq.size:
                drop[i:j] = True
            elif np.count_nonzero(flag[i:j]) <= FEW_BAND_POINTS:
                drop[i:j] |= flag[i:j]
        return drop, freq

    @property
    def suggested_options(self) -> list[str]:
        """The command-line words that leave `excludable_frequencies` out, as every command that
        reads a spectrum takes them (``["--fmin", "12", "--exclude", "56.2,123"]``: the masked
        points' options of diagnose and refine, `left_out_options`); [] when none."""
        drop = self.excludable_frequencies
        keep = np.setdiff1d(self.frequency, drop)
        return [word for option in left_out_options(keep, drop) for word in option]

    @property
    def marginal_points_only(self) -> bool:
        """Whether every bad band is one point flagged by the point rule alone with |Δ| below
        `MARGINAL_POINT_RATIO` times its level: the tail of the data's own scatter, where leaving
        points out one at a time need not end (docs/kk.md, "When to stop")."""
        if self.valid:
            return False
        flag, masks, freq = self._rule_masks()
        order = np.argsort(self.frequency)
        size = (np.hypot(self.residuals_real, self.residuals_imag) / self.scale_per_point)[order]  # (in units of each point's s)
        level = self.thresholds["point"] * MARGINAL_POINT_RATIO
        return all(j - i == 1 and not masks["run"][i] and not masks["window"][i] and size[i] < level for i, j in _band_spans(flag, freq))

    def passing_edge_words(self) -> str:
        """What `passing_edge` says, with the options that cut `EDGE_DECADES` further in."""
        f_lo, f_hi, d_lo, d_hi, median = self.passing_edge
        lo, hi = self.passing_band
        low_end = f_lo <= lo * 10**EDGE_DECADES and lo > self.frequency.min()
        inner = (lo * 10**EDGE_DECADES, hi) if low_end else (lo, hi / 10**EDGE_DECADES)
        kept = self.frequency[(self.frequency >= inner[0]) & (self.frequency <= inner[1])]
        conditions = [f"data.frequency {'>=' if name == '--fmin' else '<='} {value}" for name, value in left_out_options(kept, np.setdiff1d(self.frequency, kept))]
        # (Python's words; impedax kk says --fmin 1 --fmax …, `cli.common.command_line_words`)
        options = f"data.where({conditions[0]}, drop=True)" if len(conditions) == 1 else f"data.where(({conditions[0]}) & ({conditions[1]}), drop=True)"
        spread = f"{d_lo * 100:.2g}–{d_hi * 100:.2g} %" if f"{d_lo * 100:.2g}" != f"{d_hi * 100:.2g}" else f"{d_hi * 100:.2g} %"
        return (f"its {'lowest' if low_end else 'highest'} points ({format_band(f_lo, f_hi)}) still stand {spread} off its chain, against a median of "
                f"{median * 100:.2g} % for the rest: what was left out may reach into the band, below the test's levels; check that a fit on it agrees with one "
                f"a half decade further in ({options})")

    def next_step(self, command: str | None = None) -> list[str]:
        """The report's closing lines when the test failed: ``command`` (the run's own command
        line, the options that leave the failing points out, `suggested_options`, merged into it)
        or without it the Python call that tests the data without them (`RETEST_WITHOUT_THEM`);
        that ``impedax refine`` leaves them out by
        itself; when to stop (`marginal_points_only`); and the bands that leaving points out does
        not mend. [] when the test passed, was inconclusive, or the sign hint explains it."""
        if self.valid or self.sign_hint or not self.conclusive:
            return []
        words = self.suggested_options
        size = np.hypot(self.residuals_real, self.residuals_imag) / self.scale_per_point
        lines = []
        if self.marginal_points_only:
            where = ", ".join(f"{format_frequency(float(f))} at {s:.3g} s" for f, s in sorted(zip(self.frequency[self.flagged], size[self.flagged])))
            lines.append(f"next: stop leaving points out: {'the point is' if np.count_nonzero(self.flagged) == 1 else 'each point is'} isolated and just over the point level "
                         f"({where}; level {self.thresholds['point']:.3g} s): the tail of the data's own scatter; without it the chain refits and another such point "
                         "may cross the level (docs/kk.md, \"When to stop\"). Fit with or without it")
        elif words and not self._excludable_by_bands().size:  # (the band found by testing again without points at the ends)
            lo, hi = self.passing_band
            low, high = int(np.count_nonzero(self.frequency < lo)), int(np.count_nonzero(self.frequency > hi))
            ends = " and ".join(x for x in (f"the {points_text(low)} below it" if low else "", f"the {points_text(high)} above it" if high else "") if x)
            lines.append(f"next: the test passes on {format_band(lo, hi)} (KK rms_rel {self.passing_rms_rel * 100:.2g} %), leaving out {ends}: "
                         f"trim the measurement to it: {command or RETEST_WITHOUT_THEM}")
            cleared = np.asarray(self.flagged, bool) & (self.frequency >= lo) & (self.frequency <= hi)
            if cleared.any():  # (the bad band reaches into the passing one: why the same points pass there)
                order = np.argsort(self.frequency)  # (named by their bands: REAL CH Instruments' two, not the 4.64 Hz–82.5 kHz between their ends)
                where = ", ".join(format_band(points[0], points[-1]) for points in band_points(self.frequency[order], cleared[order]))
                lines.append(f"  the {points_text(int(cleared.sum()))} flagged within it ({where}) pass there: "
                             f"fitted to every point, the chain was pulled off them by {ends}")
            if self.passing_edge is not None:
                lines.append(f"  {self.passing_edge_words()}")
            lines.append("  impedax fit, diagnose and refine take the same options" if command else f"  {TRIMMED_DATA_TOO}")
        elif words:
            lines.append(f"next: leave them out and test again: {command or RETEST_WITHOUT_THEM}")
            lines.append(f"  {'impedax fit, diagnose and refine take the same options' if command else TRIMMED_DATA_TOO}; {DIAGNOSE_MASKING}")
        spans = _band_spans(*self._rule_masks()[::2])
        inside = [f for f, (i, j) in zip(self.band_frequencies, spans) if len(f) > FEW_BAND_POINTS and i > 0 and j < self.frequency.size]
        if self.passing_band is not None and not self._excludable_by_bands().size:
            inside = []  # (the trim leaves them out too)
        if inside:
            what = ", ".join(band_name(f) for f in inside)
            lines.append(f"{'  ' if lines else 'next: '}{what}: too many points to leave out one by one: a disturbance during the sweep (drift, movement); measure again, or fit knowing it (docs/kk.md, \"What to do\")")
        elif not words and not self.marginal_points_only:  # (bands at the ends too wide to leave out: REAL Gamry, 52 of 72 points from the low end)
            drop, _ = self._dropped_by_bands()
            kept = drop.size - int(np.count_nonzero(drop))
            at_ends = [(f, i == 0) for f, (i, j) in zip(self.band_frequencies, spans) if i == 0 or j == self.frequency.size]
            if at_ends:
                what = ", ".join(band_name(f) for f, _ in at_ends)
                ends = " and ".join("low" if low else "high" for _, low in at_ends)
                how = (f"the {np.count_nonzero(drop)} of {drop.size} points from the {ends} end{'s' if len(at_ends) > 1 else ''} through {'them' if len(at_ends) > 1 else 'it'} "
                       f"({' and '.join(BAND_CUT_AT_END[low] for _, low in at_ends)})")
            else:
                what, how = "the bands", f"their {np.count_nonzero(drop)} of {drop.size} points"
            short = "fewer than half of the points" if kept < drop.size / 2 else f"fewer than the {CONCLUSIVE_POINTS_MIN} the test needs"
            lines.append(f"{'  ' if lines else 'next: '}{what}: leaving out {how} would keep {kept}, {short}: "
                         "a disturbance over much of the sweep (drift, movement); measure again, or fit knowing it (docs/kk.md, \"What to do\")")
        return lines

    def report(self, command: str | None = None) -> str:
        """A few lines: M, µ, rms_rel, noise, verdict, the rules' levels and the bad bands with the
        rules that flagged each (and the measured frequencies of a band of at most
        `FEW_BAND_POINTS`), the sign hint, and when the test failed what to do (`next_step`:
        ``command``, the run's command line with the suggested options, in place of the options
        alone)."""
        verdict = "valid (KK-consistent)" if self.valid else "NOT valid: data are not KK-consistent"
        if self.conclusive and self.marginal_points_only:  # (beside "next: stop leaving points out", which calls them the scatter's tail)
            verdict = (f"NOT valid by the point rule alone, and only just: {'an isolated point' if np.count_nonzero(self.flagged) == 1 else 'isolated points'} barely over its level, "
                       "the tail of the data's own scatter more than a sign that the data are not KK-consistent")
        if not self.conclusive:
            verdict = f"inconclusive: {self.frequency.size} frequencies are too few for the test (it needs {CONCLUSIVE_POINTS_MIN})" + ("" if self.valid else "; it flags the bands below")
        mu_note = "" if self.mu_reached else f" (µ ≥ c = {self.c:g} at the M given)" if self.n_rc_given else (
            # (docs/kk.md, "Choosing M": no M from M_fit up had µ < c and fitted the data)
            f" (no M tried had µ < c = {self.c:g} while fitting the data; M = M_fit, the smallest M that fits them, is used)"
        )
        # (what M, µ and rms_rel are, in a few words: a beginner's walkthrough met them unexplained)
        misfit_words = ("about what a sound model can reach" if self.valid else
                        # (next to "NOT valid" the figure is no promise: it holds the failing points' misfit)
                        "failing points included: no circuit is expected to fit closer, and reaching it would not make the data sound")
        if self.sparse_note:  # (on a sparse grid the figure is the chain's own approximation: a circuit may fit far closer)
            misfit_words = (f"on these sparse points mostly the chain's own approximation, which fits one exact relaxation only to {self.chain_error * 100:.2g} %: "
                            "no bound for a circuit, which may fit far closer")
        elif not self.conclusive:
            misfit_words = "from too few points to say what a sound model can reach"
        lines = [
            f"linear KK test: M = {self.n_rc} RC elements, µ = {self.mu:.3f}{mu_note}{self.mu_words}",
            "  (a chain of M R‖C in series, which is Kramers–Kronig consistent by construction, fitted to the data: Schönleber et al. 2014; docs/kk.md)",
            f"rms_rel = {self.rms_rel * 100:.3g} % (the chain's misfit relative to |Z|: {misfit_words}), noise estimate = {self.noise_estimate * 100:.3g} %",
            f"verdict: {verdict}",
        ]
        if self.stray_frequencies.size:
            where = ", ".join(format_frequency(float(f)) for f in self.stray_frequencies)
            kept = [f for f in self.frequency[self.flagged] if f not in set(self.stray_frequencies)]  # (flagged against that chain, not lone spikes of the chain with them)
            also = (f"; {', '.join(format_frequency(float(f)) for f in sorted(kept))}, kept in it, fail{'s' if len(kept) == 1 else ''} against it too"
                    if kept and len(kept) <= FEW_BAND_POINTS else "")
            lines.append(f"left out of the chain's fit as stray (lone spikes over the point level): {where}; judged against the chain without them{also} (docs/kk.md, \"Stray points\")")
        if self.noise_from == "sigma":
            scale = self.scale_per_point
            lines.insert(3, f"noise: the data's sigma (the chain weighted by 1/σ; each point judged against its own σ/|Z|, {scale.min() * 100:.3g}–{scale.max() * 100:.3g} %; "
                            "kk_test(noise='residuals') judges by the noise estimate instead)")  # (impedax kk says --noise residuals: `cli.common.command_line_words`)
        if self.sparse_note:
            lines.append(self.sparse_note)
        if self.bad_bands:
            lines.append(self._rules_text())
            t, levels = self.thresholds, self.rule_levels
            if self.noise_from == "sigma":  # (each point's own level: in units of its s)
                level = {"point": f"{t['point']:.3g} s", "run": f"{t['run']:.3g} s", "window": f"{t['window_mean'] / math.sqrt(t['window']):.3g} s"}
            else:
                level = {rule: f"{value * 100:.3g} %" for rule, value in levels.items()}
            lines += bad_band_lines(self.band_frequencies, band_rule_counts(*self._rule_masks()), {
                "point": f"with |Δ| > {level['point']} (point rule)", "run": f"in runs of ≥ {int(t['run_length'])} with |Δ| > {level['run']} (run rule)",
                "window": f"under a {int(t['window'])}-point mean of Δ' or Δ'' > {level['window']} (window rule)"})
        lines += note_and_hint_lines(self.non_passive_note, self.sign_hint)
        lines += self.next_step(command)
        return "\n".join(lines)

    @property
    def mu_words(self) -> str:
        """The report's words on µ once µ < c: how many R_k are negative and their share
        Σ|R_k<0|/Σ|R_k≥0| = 1 − µ (Schönleber 2014, eq 21), read as the onset of negative R (what
        the µ rule looks for) or, at `NEGATIVE_SHARE_FAR` times the 1 − c the cut-off allows or more,
        as a chain that may follow the noise; "" when µ ≥ c (the report's note says why)."""
        if not self.mu_reached or self.mu >= self.c:
            return ""
        r = self.resistances
        positive = float(np.sum(r[r >= 0]))
        share = f"Σ|R<0| = {-np.sum(r[r < 0]) / positive * 100:.0f} % of Σ R≥0" if positive > 0 else "none positive"
        counts = f"{np.count_nonzero(r < 0)} of {r.size} R negative, {share}"
        if 1 - self.mu >= NEGATIVE_SHARE_FAR * (1 - self.c):
            why = "" if self.n_rc_given else "; no smaller M both fitted the data and had µ < c, docs/kk.md \"Choosing M\""
            return f" (µ far below c = {self.c:g}: many negative R ({counts}): the chain may follow the noise at this M, or make up with negative R for its fixed τ grid missing the data's time constants, as on noise-free data{why})"
        if self.n_rc_given:
            return f" (µ < c = {self.c:g}: {counts})"
        return f" (µ < c = {self.c:g}: negative R are starting to appear ({counts}), Schönleber's sign that the chain follows the data, not yet their noise)"

    def _rules_text(self) -> str:
        """One line: the scale s and the level of each rule (`rule_levels`)."""
        t, levels = self.thresholds, self.rule_levels
        noise = self.noise_estimate if math.isfinite(self.noise_estimate) else 0.0
        if self.noise_from == "sigma":
            return (f"rules (on |Δ| = |Z − Z_kk|/|Z|, s = each point's σ/|Z| (at least the {t['noise_floor'] * 100:.3g} % floor and the chain's error), median {self.threshold_scale * 100:.3g} %): "
                    f"point |Δ| > {t['point']:.3g} s; run of ≥ {int(t['run_length'])} with |Δ| > {t['run']:.3g} s; "
                    f"window: mean of Δ' or Δ'' over {int(t['window'])} points > {t['window_mean'] / math.sqrt(t['window']):.3g} s (s averaged over the window)")
        why = "the noise estimate" if self.threshold_scale == noise else "the sparse data's chain error" if self.threshold_scale == self.chain_error else f"the {t['noise_floor'] * 100:.3g} % floor"
        return (
            f"rules (on |Δ| = |Z − Z_kk|/|Z|, s = {self.threshold_scale * 100:.3g} %, {why}): point |Δ| > {t['point']:.3g} s = {levels['point'] * 100:.3g} %; "
            f"run of ≥ {int(t['run_length'])} with |Δ| > {t['run']:.3g} s = {levels['run'] * 100:.3g} %; "
            f"window: mean of Δ' or Δ'' over {int(t['window'])} points > {levels['window'] * 100:.3g} %"
        )

    def _repr_html_(self) -> str:
        from ..plotting.html import result_html

        rows = [{"quantity": k, "value": v} for k, v in (("RC elements M", self.n_rc), ("µ", self.mu), ("rms_rel [%]", f"{self.rms_rel * 100:.3g}"), ("noise estimate [%]", f"{self.noise_estimate * 100:.3g}"), ("valid", bool(self.valid)))]
        rows += [{"quantity": "bad band", "value": band_name(points)} for points in self.band_frequencies]
        return result_html("linear Kramers–Kronig test", rows)

    def plot(self, *, title: str | None = None):
        """Nyquist and Bode of data vs KK fit, and the residuals Δ', Δ'' and |Δ| [%] vs frequency
        with the point and run levels and the bad bands shaded, each named by the rule that flagged
        it (`plotting.kk.plot_kk`). Returns a Figure."""
        from ..plotting.kk import plot_kk

        return plot_kk(self, title=title)


RESIDUAL_LONG_NAMES = ("(Z'_data - Z'_kk)/|Z_data|", "(Z''_data - Z''_kk)/|Z_data|")
"""The sign of ``residuals_real``/``residuals_imag``, data minus KK fit (Boukamp's; a circuit
fit's residuals are model minus data: docs/physics.md), as their ``long_name``s."""
POINT_SCALE_LONG_NAME = "scale s each point's residuals were judged against, relative to |Z_data| (its sigma/|Z| when judged by sigma, else the one noise estimate's)"
"""``point_scale``'s ``long_name`` (`KKResult.scale_per_point`): the flags' thresholds are multiples of it."""

STRAY_LONG_NAME = "stray point left out of the Voigt chain's fit (Z_kk, resistance) and judged against the chain without it"
"""``stray``'s ``long_name`` (`KKResult.stray_points`)."""

BATCH_RESULT_NAMES = frozenset({
    "frequency", "band", "rc", "Z", "Z_kk", "residuals_real", "residuals_imag", "flagged", "point_scale", "stray", "bad_band_f_min", "bad_band_f_max", "time_constant", "resistance",
    "n_rc", "mu", "rms_rel", "noise_estimate", "valid", "conclusive", "series_resistance", "series_inductance", "inverse_series_capacitance",
})
"""The dimensions and variables of `KKBatchResult.to_xarray`'s Dataset: `kk_test_batch` refuses a
batch dimension of one of these names (`grid.refuse_result_names`), where ``to_xarray`` had
failed with xarray's "conflicting sizes for dimension 'rc'"."""


# the most rows a batch's notebook table shows (`ValidityGrid._html_table`), as pandas' 60
HTML_ROWS = 60


class ValidityGrid(ResultGrid):
    """What the batches of the validity tests (`KKBatchResult`, `zhit.ZHITBatchResult`) share:
    the verdict counts, ``valid`` and ``rms_rel`` over ``dims``, a table row per spectrum (text,
    notebook, CSV) and the report's last lines, the sign hint and the ``next:`` command for the
    first failing spectrum. ``_COUNT_COLUMN``: a per-spectrum count the table adds after the
    noise, as (header, attribute), or None."""

    _COUNT_COLUMN = None  # (no annotation: a class constant, not a dataclass field of the results)

    def _verdict_counts(self) -> tuple[int, int]:
        """(inconclusive, valid and conclusive) spectra: the counts of the report's first line and the repr."""
        few = sum(not r.conclusive for r in self.results)
        return few, sum(bool(r.valid) and r.conclusive for r in self.results)

    @property
    def valid(self) -> np.ndarray:
        return self.per_spectrum("valid", bool)

    @property
    def rms_rel(self) -> np.ndarray:
        return self.per_spectrum("rms_rel")

    def to_table(self) -> list[dict[str, object]]:
        """Each spectrum's ``to_table`` after a column per dimension (its label)."""
        return [{**where, **row} for where, r in zip(self.labels(), self.results) for row in r.to_table()]

    def _stacked(self, get, width: int | None = None, dtype=float) -> np.ndarray:
        """``get(result)`` of every spectrum as one array over ``dims`` (then the per-spectrum
        shape), each padded with NaN to ``width`` when given (bands, RC elements): `to_xarray`'s."""
        rows = [np.asarray(get(r), dtype=dtype) for r in self.results]
        if width is not None:
            rows = [np.pad(v, (0, width - v.size), constant_values=np.nan) for v in rows]
        return np.stack(rows).reshape(*self.shape, *rows[0].shape)

    def _band_variables(self, n_band: int) -> dict:
        """`to_xarray`'s bad bands of every spectrum, (*dims, band) padded with NaN to ``n_band``."""
        dims = (*self.dims, "band")
        return {"bad_band_f_min": (dims, self._stacked(lambda r: [b[0] for b in r.bad_bands], n_band), {"units": "Hz"}),
                "bad_band_f_max": (dims, self._stacked(lambda r: [b[1] for b in r.bad_bands], n_band), {"units": "Hz"})}

    def _verdict_variables(self) -> dict:
        """`to_xarray`'s verdict of every spectrum over ``dims``: rms_rel, noise estimate, valid, conclusive."""
        return {"rms_rel": (self.dims, self.rms_rel, {"units": "1"}), "noise_estimate": (self.dims, self.per_spectrum("noise_estimate"), {"units": "1"}),
                "valid": (self.dims, self.valid), "conclusive": (self.dims, self.per_spectrum("conclusive", bool))}

    def _coordinates(self) -> dict:
        """`to_xarray`'s coordinates: the frequencies [Hz] and the batch's labels."""
        return {"frequency": ("frequency", self.results[0].frequency, {"units": "Hz"}), **{d: (d, np.asarray(v)) for d, v in self.coords.items()}}

    def _spectrum_names(self) -> list[str]:
        """Each spectrum as the report names it: ``cycle=3`` (``trial=2, session=1`` over several dimensions)."""
        return [", ".join(f"{d}={label_text(v)}" for d, v in w.items()) for w in self.labels()]  # (soc=0.3, not soc=0.30000000000000004)

    def _table_lines(self, names: list[str]) -> list[str]:
        """The report's table: a header and, per spectrum, its name, verdict, rms_rel, noise
        estimate, `_COUNT_COLUMN` and bad bands with the rules that flagged each."""
        width = column_width(names, "spectrum")
        head, attribute = self._COUNT_COLUMN or ("", "")
        lines = [f"{'spectrum':<{width}}  {'verdict':<9} {'rms_rel':>10} {'noise':>10}{f' {head:>3}' if head else ''}  bad bands [rules that flagged them]"]
        # (3 significant digits, each column's decimal points lined up)
        rms, noise = format_percent_column([r.rms_rel for r in self.results]), format_percent_column([r.noise_estimate for r in self.results])
        for name, r, rms_text, noise_text in zip(names, self.results, rms, noise):
            bands = "; ".join(f"{band_name(points)} [{', '.join(rules)}]" for points, rules in zip(r.band_frequencies, r.band_rules)) or "none"
            count = f" {getattr(r, attribute):>3}" if head else ""
            lines.append(f"{name:<{width}}  {_verdict_word(r):<9} {rms_text:>8} % {noise_text:>8} %{count}  {bands}")
        return lines

    def _html_rows(self) -> list[dict]:
        """The notebook table: per spectrum its labels, verdict, rms_rel, noise estimate, `_COUNT_COLUMN` and bad bands."""
        head, attribute = self._COUNT_COLUMN or ("", "")
        return [{**where, "verdict": _verdict_word(r), "rms_rel [%]": f"{r.rms_rel * 100:.3g}", "noise [%]": f"{r.noise_estimate * 100:.3g}",
                 **({head: getattr(r, attribute)} if head else {}), "bad bands": "; ".join(band_name(points) for points in r.band_frequencies) or "none"}
                for where, r in zip(self.labels(), self.results)]

    def _html_table(self) -> tuple[list[dict], list[str]]:
        """The notebook's rows and the line saying what they leave out: every spectrum up to
        `HTML_ROWS`; beyond, only those not valid or inconclusive (up to `HTML_ROWS` of them):
        1,000 SYNTHETIC spectra filled a notebook with 1,000 rows of "valid"."""
        rows = self._html_rows()
        if len(rows) <= HTML_ROWS:
            return rows, []
        failing = [row for row, r in zip(rows, self.results) if not (r.valid and r.conclusive)]
        shown = failing[:HTML_ROWS]
        which = f"the first {len(shown)} of the {len(failing)}" if len(failing) > len(shown) else f"the {len(shown)}"
        return shown, [f"{len(rows)} spectra: the table shows {which} not valid or inconclusive ({len(rows) - len(failing)} valid not shown); report() and to_xarray() hold every spectrum"]

    def _non_passive_lines(self, names: list[str]) -> list[str]:
        """The spectra with points Re Z < 0 beyond the noise (up to 3 named) and the first one's note."""
        passive = [i for i, r in enumerate(self.results) if r.non_passive_note]
        if not passive:
            return []
        listed = ", ".join(names[i] for i in passive[:3]) + (", …" if len(passive) > 3 else "")
        return [f"note: in {len(passive)} of {counted(len(self.results), 'spectrum', 'spectra')} ({listed}) points have Re Z < 0, which no passive circuit reaches: "
                f"{names[passive[0]]}: {self.results[passive[0]].non_passive_note}"]

    def _hint_lines(self, names: list[str]) -> list[str]:
        """The first sign hint, naming the spectra that have one (up to 3)."""
        hints = [r.sign_hint for r in self.results]
        with_hint = [i for i, h in enumerate(hints) if h]
        if not with_hint:
            return []
        listed = ", ".join(names[i] for i in with_hint[:3]) + (", …" if len(with_hint) > 3 else "")
        return [f"hint: in {len(with_hint)} of {counted(len(hints), 'spectrum', 'spectra')} ({listed}): {hints[with_hint[0]]}"]

    def _first_failure(self, data_path: str | None) -> tuple[int, str, str, str, str] | None:
        """For the ``next:`` line: how many spectra failed (conclusively, without a sign hint), the
        first one's name, the file to name (``data_path``, quoted; "FILE" for "-" or None), the
        first one's ``--select`` words and what to do for "FILE"; None when none failed."""
        failed = [i for i, r in enumerate(self.results) if r.conclusive and not r.valid and not r.sign_hint]
        if not failed:
            return None
        import shlex

        where = self.labels()[failed[0]]
        selects = " ".join(f"--select {shlex.quote(f'{d}={label_text(v)}')}" for d, v in where.items())  # (0.3, as the table names it)
        path = shlex.quote(str(data_path)) if data_path not in (None, "-") else "FILE"
        save = "" if path != "FILE" else " (save the data to FILE first: standard input is read once)"
        return len(failed), self._spectrum_names()[failed[0]], path, selects, save


def _verdict_word(result) -> str:
    """A spectrum's verdict in a batch's table: valid, NOT valid, or too few (inconclusive)."""
    return ("valid" if result.valid else "NOT valid") if result.conclusive else "too few"


@dataclass(frozen=True, eq=False)
class KKBatchResult(ValidityGrid):
    """KK tests of every spectrum of a Dataset with extra dimensions (trial, session, ...).

    ``results`` holds one `KKResult` per spectrum in C order over ``dims``; index with
    ``batch[i, j]`` (integer positions) and see ``valid``/``rms_rel`` as arrays over ``dims``.
    """

    results: tuple[KKResult, ...]
    _COUNT_COLUMN = ("M", "n_rc")  # (the table's column of each chain's number of RC elements)

    def __repr__(self) -> str:
        """One line: how many spectra over which dimensions, and the verdicts (the generated
        repr printed every spectrum's arrays)."""
        few, consistent = self._verdict_counts()
        inconclusive = f", {few} inconclusive" if few else ""
        return (f"KKBatchResult({counted(len(self.results), 'spectrum', 'spectra')} over {', '.join(self.dims)}: "
                f"{consistent} KK-consistent, {len(self.results) - few - consistent} not{inconclusive})")

    @property
    def n_rc(self) -> np.ndarray:
        return self.per_spectrum("n_rc", int)

    def summary(self) -> dict:
        """The JSON of ``impedax kk --json`` for several spectra: ``method`` ("linear", as
        `ZHITBatchResult.summary` has it), ``dims``, ``sizes``,
        ``n_spectra``, ``n_valid`` (inconclusive spectra count as valid), ``n_conclusive``,
        ``n_inconclusive`` and ``spectra`` (each spectrum's ``labels``, then the keys of
        `KKResult.summary`); ``warnings``: the spectra's warnings, each once."""
        few = sum(not r.conclusive for r in self.results)
        spectra = [{"labels": where, **r.summary()} for where, r in zip(self.labels(), self.results)]
        return {"method": "linear", "dims": list(self.dims), "sizes": dict(zip(self.dims, map(int, self.shape))), "n_spectra": len(self.results), "n_valid": sum(bool(r.valid) for r in self.results),
                "n_conclusive": len(self.results) - few, "n_inconclusive": few, "spectra": spectra,
                "warnings": sorted({w for row in spectra for w in row["warnings"]})}

    def to_xarray(self) -> xr.Dataset:
        """Each spectrum's `KKResult.to_xarray()` stacked over ``dims`` (bands and RC elements
        padded with NaN); ``residuals_real``/``residuals_imag`` = Re/Im (Z − Z_kk)/|Z| (data minus model)."""
        shape, dims = self.shape, self.dims
        n_band = max([len(r.bad_bands) for r in self.results] + [0])
        n_rc = max(r.n_rc for r in self.results)
        stack = self._stacked

        per_freq = (*dims, "frequency")
        first = self.results[0]
        ds = xr.Dataset(
            {
                "Z": (per_freq, np.stack([r.impedance for r in self.results]).reshape(*shape, -1), {"units": "ohm"}),
                "Z_kk": (per_freq, np.stack([r.kk_impedance for r in self.results]).reshape(*shape, -1), {"units": "ohm"}),
                "residuals_real": (per_freq, stack(lambda r: r.residuals_real), {"units": "1", "long_name": RESIDUAL_LONG_NAMES[0]}),
                "residuals_imag": (per_freq, stack(lambda r: r.residuals_imag), {"units": "1", "long_name": RESIDUAL_LONG_NAMES[1]}),
                "flagged": (per_freq, stack(lambda r: r.flagged).astype(bool)),
                "point_scale": (per_freq, stack(lambda r: r.scale_per_point), {"units": "1", "long_name": POINT_SCALE_LONG_NAME}),
                "stray": (per_freq, stack(lambda r: r.stray_points).astype(bool), {"long_name": STRAY_LONG_NAME}),
                **self._band_variables(n_band),
                "time_constant": ((*dims, "rc"), stack(lambda r: r.time_constants, n_rc), {"units": "s"}),
                "resistance": ((*dims, "rc"), stack(lambda r: r.resistances, n_rc), {"units": "ohm"}),
                "n_rc": (dims, self.n_rc),
                "mu": (dims, self.per_spectrum("mu")),
                **self._verdict_variables(),
                "series_resistance": (dims, self.per_spectrum("series_resistance"), {"units": "ohm"}),
                "series_inductance": (dims, self.per_spectrum("series_inductance"), {"units": "H"}),
                "inverse_series_capacitance": (dims, self.per_spectrum("inverse_series_capacitance"), {"units": "1/F"}),
            },
            coords=self._coordinates(),
        )
        # (the settings, shared by every spectrum; each spectrum's series R, L and 1/C are variables)
        ds.attrs.update({k: v for k, v in first.to_xarray().attrs.items() if not k.startswith(("series", "inverse_series"))})
        return result_dataset(ds.copy(deep=True))

    def _repr_html_(self) -> str:
        """In a notebook: the verdict counts and a row per spectrum (its labels, verdict, rms_rel,
        noise estimate, M and bad bands), as the report's table."""
        from ..plotting.html import result_html

        rows, left_out = self._html_table()
        return result_html("linear Kramers–Kronig test", rows, lines=[self.report().splitlines()[0], *left_out])

    def plot(self, *, title: str | None = None):
        """Every spectrum's |Δ| as a map over the spectra and frequency, the flagged points
        circled, and each test's rms_rel and noise estimate below (`plotting.kk.plot_validity_batch`;
        ``impedax kk FILE --plot`` on a file of several spectra). Returns a matplotlib Figure."""
        from ..plotting.kk import plot_validity_batch

        few, consistent = self._verdict_counts()
        magnitudes = [np.hypot(r.residuals_real, r.residuals_imag) for r in self.results]
        return plot_validity_batch(self, magnitudes, residual="|Δ| = |Z − Z_kk|/|Z|", title=title or (
            f"linear KK test of {counted(len(self.results), 'spectrum', 'spectra')} over {', '.join(self.dims)}: {consistent} KK-consistent, {len(self.results) - few - consistent} not"
            + (f", {few} inconclusive" if few else "")))

    def report(self, data_path: str | None = None) -> str:
        """The KK test of every spectrum, one line per spectrum (each bad band with the rules that
        flagged it), once, the hint of the first spectrum that has one, and, when a spectrum
        failed, a ``next:`` line: ``impedax kk DATA_PATH --select …`` tests the first failing
        one alone and names the points to leave out (``data_path``: the file the run read; "-"
        or None: save the data to a file first). What ``impedax kk`` prints for several spectra
        (the JSON: `summary`)."""
        batch, lines = self, []
        few, consistent = batch._verdict_counts()
        lines.append(f"linear KK test of {counted(len(batch.results), 'spectrum', 'spectra')} over {', '.join(batch.dims)}: {consistent} KK-consistent, {len(batch.results) - few - consistent} not"
                     + (f", {few} inconclusive (too few frequencies to tell)" if few else "")
                     + ("; noise: the data's sigma (each point judged against its σ; noise='residuals' for one estimate)" if any(r.noise_from == "sigma" for r in batch.results) else ""))
        names = batch._spectrum_names()
        lines += batch._table_lines(names)
        if any(r.bad_bands for r in batch.results):
            t = batch.results[0].thresholds
            by_sigma = sum(r.noise_from == "sigma" for r in batch.results)
            scale = ("s: each point's σ/|Z| from the data's sigma, at least " if by_sigma == len(batch.results) else
                     "s: the largest of the noise estimate, " if not by_sigma else "s: each point's σ/|Z| where the data's sigma was used, else the largest of the noise estimate, ")
            lines.append(f"rules: point = one |Δ| > {t['point']:.3g} s, run = ≥ {int(t['run_length'])} consecutive |Δ| > {t['run']:.3g} s, window = a {int(t['window'])}-point mean "
                         f"of Δ' or Δ'' > {t['window_mean'] / math.sqrt(t['window']):.3g} s ({scale}{t['noise_floor'] * 100:.3g} % and the chain's own error; the levels: impedax kk --select)")
        lines += batch._non_passive_lines(names) + batch._hint_lines(names)
        failure = batch._first_failure(data_path)
        if failure:
            n_failed, name, path, selects, save = failure
            lines.append(f"next: impedax kk {path} {selects} tests {name} alone ({n_failed} of {len(batch.results)} not valid) and names the points to leave out{save}; "
                         "impedax refine leaves each spectrum's KK-flagged points out by itself")
        return "\n".join(lines)


def _mu_limit(c) -> float:
    """``c``, the µ criterion's limit, as a float: any real number (a NumPy or JAX scalar, a
    `Fraction`, a `Decimal`: `arguments.real`) strictly between 0 and 1."""
    try:
        value = real()(c, "c")
    except ParameterError:
        value = None
    if value is None or not 0.0 < value < 1.0:
        raise ParameterError(f"c must be between 0 and 1 (exclusive), got {shown(c)}")
    return value


def _check_options(freq: np.ndarray, c: float, max_rc, n_rc, n_series: int) -> int:
    n_points = freq.size
    c = _mu_limit(c)
    limit = n_points - n_series  # keep at least n_points extra equations (2N real equations)
    if limit < 1:
        raise DataError(f"the KK test needs at least {n_series + 1} frequencies, got {n_points}")
    if n_rc is not None and max_rc is not None:
        raise ParameterError(f"n_rc={n_rc!r} fixes the number of RC elements and max_rc={max_rc!r} caps the search for it: give one of them")
    if n_rc is not None:
        if not isinstance(n_rc, (int, np.integer)) or not 1 <= n_rc <= limit:
            raise ParameterError(f"n_rc must be an integer from 1 to {limit} for {n_points} frequencies, got {n_rc!r}")
        return int(n_rc)
    if max_rc is None:
        return reference_rc(freq, n_series)
    if not isinstance(max_rc, (int, np.integer)) or not 1 <= max_rc <= limit:
        raise ParameterError(f"max_rc must be an integer from 1 to {limit} for {n_points} frequencies, got {max_rc!r}")
    return int(max_rc)


REFERENCE_RC_PER_DECADE = 3.5
"""RC elements per decade of τ of the reference chain, at least: a single relaxation between two
of its time constants is then approximated to 0.074 % rms (`chain_error`; 0.22 % at 3 per
decade, 0.63 % at 2.5, 0.025 % at 4), below the 0.2 % noise floor."""


def reference_rc(freq: np.ndarray, n_series: int) -> int:
    """M_ref, the most flexible chain tried: N/2, raised to `REFERENCE_RC_PER_DECADE` per decade
    of the band when the data are sparser than about 7 points a decade; never above N − n_series
    (N further equations) or 100."""
    n_points = freq.size
    decades = math.log10(freq.max() / freq.min()) if n_points > 1 else 0.0
    dense_enough = math.ceil(REFERENCE_RC_PER_DECADE * decades) + 1
    return max(1, min(max(n_points // 2, dense_enough), n_points - n_series, 100))


CHAIN_ERROR_POINTS = 1000


def chain_error(freq: np.ndarray, m: int, inductance: bool, capacitance: bool) -> float:
    """The Voigt chain's own misfit on exactly KK-consistent data: the largest rms relative
    residual of the M-element chain (with its series terms) fitted to a single relaxation
    1/(1 + jωτ) on these frequencies, τ at 9 positions between the chain's two central time
    constants (the worst place for a relaxation). Residuals of this size are the chain's
    approximation, not the data's inconsistency. Beyond `CHAIN_ERROR_POINTS` frequencies it is
    evaluated on that many log-spaced over the same band (memory stays bounded; at such
    densities the misfit depends on the chain's spacing alone).
    Remembered per frequencies and chain (`_chain_error`): every KK test of a batch fit's checked
    spectra, and each test of their conj(Z), asks for the same one."""
    freq = np.asarray(freq, dtype=np.float64)
    return _chain_error(freq.tobytes(), freq.shape, int(m), bool(inductance), bool(capacitance))


@functools.lru_cache(maxsize=64)
def _chain_error(freq_bytes: bytes, shape: tuple[int, ...], m: int, inductance: bool, capacitance: bool) -> float:
    """`chain_error` of frequencies given as their bytes (hashable, for the cache)."""
    freq = np.frombuffer(freq_bytes, dtype=np.float64).reshape(shape)
    tau = _time_constants(freq, m)
    if m < 2:
        return 0.0
    if freq.size > CHAIN_ERROR_POINTS:
        freq = np.geomspace(freq.min(), freq.max(), CHAIN_ERROR_POINTS)
    omega = 2 * np.pi * freq
    k = (m - 1) // 2
    design = _design(omega, tau, inductance, capacitance)
    worst = 0.0
    for t in tau[k] * (tau[k + 1] / tau[k]) ** np.linspace(0.0, 1.0, 9):
        z = 1.0 / (1.0 + 1j * omega * t)
        weighted = design / np.abs(z)[:, None]
        coef, *_ = np.linalg.lstsq(np.vstack([weighted.real, weighted.imag]), np.concatenate([(z / np.abs(z)).real, (z / np.abs(z)).imag]), rcond=None)
        worst = max(worst, float(np.sqrt(np.mean(np.abs((design @ coef - z) / np.abs(z)) ** 2))))
    return worst


def _time_constants(freq: np.ndarray, m: int) -> np.ndarray:
    """τ_k log-spaced from 1/ω_max to 1/ω_min (Schönleber 2014, eq 12); one RC sits at their
    geometric mean."""
    tau_min, tau_max = 1.0 / (2 * np.pi * freq.max()), 1.0 / (2 * np.pi * freq.min())
    if m == 1:
        return np.array([math.sqrt(tau_min * tau_max)])
    return tau_min * (tau_max / tau_min) ** (np.arange(m) / (m - 1))


# Rows of the design matrix handled at once by the streamed QR: bounds the work array to about
# _BLOCK_ELEMENTS floats whatever the number of points (memory linear in N, never N×M×M).
_BLOCK_ELEMENTS = 2_000_000


def _series_columns(omega: np.ndarray, inductance: bool, capacitance: bool) -> list[np.ndarray]:
    columns = [np.ones_like(omega, dtype=complex)]
    if inductance:
        columns.append(1j * omega)
    if capacitance:
        columns.append(-1j / omega)
    return columns


def _design(omega: np.ndarray, tau: np.ndarray, inductance: bool, capacitance: bool) -> np.ndarray:
    """Complex design matrix (n, P) of a block of angular frequencies: R_0, (L), (1/C), then
    R_k/(1 + jωτ_k) (Schönleber 2014 eq 7)."""
    voigt = 1.0 / (1.0 + 1j * omega[:, None] * tau[None, :])
    return np.concatenate([np.stack(_series_columns(omega, inductance, capacitance), axis=1), voigt], axis=1)


def _block_rows(n_spectra: int, n_columns: int) -> int:
    return max(16, _BLOCK_ELEMENTS // (2 * n_spectra * n_columns))


def _streamed_qr(omega, z, tau, inductance, capacitance, noise_shape=None):
    """R factor of the weighted, stacked system [A | b] for a stack of spectra z (B, N), built
    block by block (TSQR: the R of the rows so far is stacked on the next block and
    re-factorised), so the full (2N, P) matrix never exists. Rows [Re; Im] weighted by 1/|Z|
    (Schönleber 2014 eq 13), or, given ``noise_shape`` (B, N), by 1/(|Z|·noise_shape): the stated
    σ/|Z| over its median (`noise_shapes`), so weights ∝ 1/σ on the scale of relative ones.
    Returns (B, P+1, P+1)."""
    n_spectra, n = z.shape
    p = (1 + int(inductance) + int(capacitance)) + tau.size
    r = None  # (the first block is factorised alone: stacking zero rows on it costs a third more)
    step = _block_rows(n_spectra, p + 1)
    for start in range(0, n, step):
        stop = min(start + step, n)
        weight = 1.0 / np.abs(z[:, start:stop])  # (B, n_b)
        if noise_shape is not None:
            weight = weight / noise_shape[:, start:stop]
        design = _design(omega[start:stop], tau, inductance, capacitance)
        b = z[:, start:stop] * weight
        n_b = stop - start
        rows = np.empty((n_spectra, 2 * n_b, p + 1))
        np.multiply(design.real[None], weight[:, :, None], out=rows[:, :n_b, :p])
        np.multiply(design.imag[None], weight[:, :, None], out=rows[:, n_b:, :p])
        rows[:, :n_b, p], rows[:, n_b:, p] = b.real, b.imag
        r_new = np.linalg.qr(rows if r is None else np.concatenate([r, rows], axis=1), mode="r")
        r = np.zeros((n_spectra, p + 1, p + 1))
        r[:, : r_new.shape[1]] = r_new
    return r


def _solve_streamed(omega, z, tau, inductance, capacitance, noise_shape=None):
    """Weighted linear least squares of one M for a stack of spectra z (B, N).

    The columns are scaled to unit norm (the ω/|Z| inductance column and the RC columns then
    share one scale) and the small triangular system is solved as by SVD
    (`_pseudo_inverse_solution`), which also handles a rank-deficient design (e.g. nearly
    coincident frequencies). Returns coefficients (B, P) and the residual sum of squares
    Σ|Δ|² (B,).
    """
    r_aug = _streamed_qr(omega, z, tau, inductance, capacitance, noise_shape)
    p = r_aug.shape[-1] - 1
    r, qtb, rho = r_aug[:, :p, :p], r_aug[:, :p, p], r_aug[:, p, p]
    scale = np.linalg.norm(r, axis=1)  # column norms of R = column norms of the weighted A
    scale = np.where(scale > 0, scale, 1.0)
    r_scaled = r / scale[:, None, :]
    y = np.zeros_like(qtb)
    # well-conditioned systems (all here: cond ≤ 2e4 on the 130 real battery cycles) by LU on the
    # triangular R (no pivoting happens: back substitution), with R⁻¹ beside the solution: ‖R‖_F‖R⁻¹‖_F ≥ cond₂(R), so below 1/(P·eps)
    # no singular value is cut and the SVD's answer is the same to rounding, at half its cost
    sure = np.zeros(len(r), bool)
    try:
        with np.errstate(all="ignore"):
            solution = np.linalg.solve(r_scaled, np.concatenate([qtb[:, :, None], np.broadcast_to(np.eye(p), r.shape)], axis=2))
            bound = np.linalg.norm(r_scaled, axis=(1, 2)) * np.linalg.norm(solution[:, :, 1:], axis=(1, 2))
        sure = np.isfinite(bound) & (bound * p * np.finfo(float).eps < 1)
        y[sure] = solution[sure, :, 0]
    except np.linalg.LinAlgError:  # (an exactly singular R in the stack)
        pass
    if not sure.all():
        y[~sure] = _pseudo_inverse_solution(r_scaled[~sure], qtb[~sure])
    x = y / scale
    unexplained = np.einsum("bpq,bq->bp", r, x) - qtb
    rss = rho**2 + np.sum(unexplained**2, axis=1)
    return x, rss


def _pseudo_inverse_solution(r, qtb) -> np.ndarray:
    """y = R⁺ Qᵀb for triangular systems r (B, P, P): singular values below P·eps of the largest
    cut (a rank-deficient design), by back substitution where none is."""
    p = r.shape[-1]
    s = np.linalg.svd(r, compute_uv=False)
    keep = s > s[:, :1] * p * np.finfo(float).eps
    full = keep.all(axis=1)
    y = np.zeros_like(qtb)
    y[full] = np.linalg.solve(r[full], qtb[full][:, :, None])[:, :, 0]
    if not full.all():
        u, s_cut, vt = np.linalg.svd(r[~full])
        kept = keep[~full]
        w = np.where(kept, np.einsum("bqp,bq->bp", u, qtb[~full]) / np.where(kept, s_cut, 1.0), 0.0)
        y[~full] = np.einsum("bpq,bp->bq", vt, w)
    return y


def _evaluate(omega, tau, coefficients, inductance, capacitance) -> np.ndarray:
    """Z_kk at every frequency of one spectrum, block by block."""
    out = np.empty(omega.size, dtype=complex)
    step = _block_rows(1, coefficients.size)
    for start in range(0, omega.size, step):
        stop = min(start + step, omega.size)
        out[start:stop] = _design(omega[start:stop], tau, inductance, capacitance) @ coefficients
    return out


def _fits_like_reference(rss, n_params, rss_ref, n_params_ref, n_points, floor) -> np.ndarray:
    """Is a fit with P parameters not underfitted? Its residual sum of squares exceeds the most
    flexible fit's (P_ref parameters) by no more than noise would: RSS − RSS_ref ≤
    σ̂²(ΔP + 3√(2ΔP)) with σ̂² = RSS_ref/(2N − P_ref) and ΔP = P_ref − P (the χ²(ΔP) bound of
    nested least squares, three standard deviations above its mean), or its implied noise
    level sqrt(RSS/(2N − P)) is below the noise floor. The bound tightens as N grows, so the
    Voigt chain's own approximation error stays below what the validity rule can detect at any
    point density."""
    dof_ref = max(2 * n_points - n_params_ref, 1)
    sigma2 = rss_ref / dof_ref
    extra = max(n_params_ref - n_params, 0)
    allowed = sigma2 * (extra + 3.0 * math.sqrt(2.0 * extra))
    implied = np.sqrt(rss / max(2 * n_points - n_params, 1))
    return (rss - rss_ref <= allowed) | (implied <= floor)


# On more points than the thresholds' `reference_points`, a chain counts as not underfitted by
# its implied noise level only below this share of the noise floor. The chain's misfit is a
# ripple with a period of its τ spacing; on dense data the 9-point window sits inside one
# period and its mean is the ripple itself, which the window rule flags from about the floor
# (1,000 noise-free points of one RC arc over 8 decades: M = 23 left 0.26 % where M = 24
# leaves 0.05 %, and the consistent spectrum failed; so did 10,000 points with 0.1 % noise).
# On fewer points the window spans the ripple and averages it out: the floor itself holds.
DENSE_CHAIN_FLOOR_SHARE = 0.5

SPIKE_SHARE_MAX = 0.1
"""Stray points — over the point rule's level (|Δ| > 5 s) and a local peak of |Δ| — are left out of
the Voigt chain's fit, and every point judged against that fit again (`kk_test`), while they are
at most this share of the spectrum: their pull on the least-squares chain otherwise flags their
neighbours (a +20 % point on 41 points of an RC arc at 0.5 % noise, SYNTHETIC, seeds 0–9 at
three places: a band of that point alone in 0 of 30 before, 30 of 30 after). More are a
disturbance the chain is judged on as a whole."""

SPIKE_ROUNDS = 3
"""Rounds of leaving stray points out (`SPIKE_SHARE_MAX`): a point whose pull hid a smaller one
shows it in the next round; bounded, so dense data cost at most this many more chain fits."""


STRAY_PEAK_RATIO = 2.0
"""A stray point's |Δ| is at least this many times each neighbour's (in frequency order): a lone
spike, not the top of a drift (whose neighbours share its size: a random walk over the lowest
decade of an R ∥ CPE arc, SYNTHETIC, peaked at 20.8 s between 11.1 s and 19.8 s, where a +20 %
point stood at 25.5 s between 2.2 s and 5.2 s)."""


def _peaks(size, order) -> np.ndarray:
    """Whether each |Δ| (data order) is at least `STRAY_PEAK_RATIO` times its neighbours' in
    frequency order."""
    ranked = np.asarray(size)[order]
    peak = np.ones(ranked.size, bool)
    peak[1:] &= ranked[1:] >= STRAY_PEAK_RATIO * ranked[:-1]
    peak[:-1] &= ranked[:-1] >= STRAY_PEAK_RATIO * ranked[1:]
    out = np.empty_like(peak)
    out[order] = peak
    return out


def _neighbours_off(size, left_out, order, level) -> bool:
    """Whether a stray point's neighbour (in frequency order, not itself left out) stays over the
    point level (``level``: the point rule's |Δ|, per point or one) against the chain fitted
    without the stray points: the point was the edge of a drift, not a lone spike. A drift of
    8 % over the lowest 15 of 71 points (SYNTHETIC) has its end point at 10 mHz, 2.4 times its
    neighbour, like "a lone spike", while that neighbour stays 1.7 times the point level."""
    ranked_out = left_out[order]
    ranked_size = np.asarray(size)[order]
    ranked_level = np.broadcast_to(np.asarray(level, float), ranked_size.shape)[order] if np.ndim(level) else np.full(ranked_size.shape, float(level))
    for i in np.flatnonzero(ranked_out):
        for j in (i - 1, i + 1):
            if 0 <= j < ranked_size.size and not ranked_out[j] and ranked_size[j] > ranked_level[j]:
                return True
    return False


_SCAN_AFTER_FIT = 20  # M values tried above the smallest non-underfitted M for µ < c


def _kk_arrays(freq, z, *, c, max_rc, n_rc, inductance, capacitance, floor, noise_shape=None):
    """Fit candidate M for a stack z (B, N) and pick one per spectrum.

    M = ``n_rc`` when given. Otherwise the most flexible chain (M = max_rc) is fitted first as
    the reference; the smallest M that is not underfitted (`_fits_like_reference`), M_fit, is
    found by bisection (the residual falls with M, mostly), and M_fit, M_fit + 1, ... (at most
    ``_SCAN_AFTER_FIT`` further values) are tried until one has µ < c and is not underfitted
    either (the residual does not fall monotonically: with a lead inductance, M = 9 can leave
    6.9 % where M = 8 leaves 1.5 %). Without such an M, M_fit is used. About 10 + (M − M_fit)
    solves instead of one per M: the cost stays bounded at 10⁶ points. Returns per spectrum
    (M, µ, µ-criterion met, τ, coefficients [R_0, (L), (1/C), R_1..R_M], Z_kk). ``noise_shape``
    (B, N): the σ weighting's (`_streamed_qr`), None for 1/|Z|.
    """
    batch, n = z.shape
    n_series = 1 + int(inductance) + int(capacitance)
    m_top = _check_options(np.asarray(freq, dtype=np.float64), c, max_rc, n_rc, n_series)
    omega = 2 * np.pi * np.asarray(freq, dtype=np.float64)
    tau_top = _time_constants(freq, m_top)
    solved = {}  # (M, spectrum) → (coefficients, RSS, µ)

    def solve(m, spectra, tau=None):
        """Coefficients, RSS and µ of M = m for the listed spectra (each pair solved once)."""
        todo = [i for i in spectra if (m, i) not in solved]
        if todo:
            shape = None if noise_shape is None else noise_shape[todo]
            coef, rss = _solve_streamed(omega, z[todo], _time_constants(freq, m) if tau is None else tau, inductance, capacitance, shape)
            solved.update({(m, i): (coef[k], rss[k], mu) for k, (i, mu) in enumerate(zip(todo, _mu(coef[:, n_series:]).tolist()))})

    solve(m_top, range(batch), tau_top)
    rss_top = np.array([solved[(m_top, i)][1] for i in range(batch)])

    def fitted(m, i):
        return bool(_fits_like_reference(solved[(m, i)][1], n_series + m, rss_top[i], n_series + m_top, n, floor))

    def mu_of(m, i):
        return solved[(m, i)][2]

    if n_rc is not None:
        best = [m_top] * batch
    else:
        lo, hi = np.ones(batch, int), np.full(batch, m_top)  # smallest fitted M lies in [lo, hi]
        while np.any(lo < hi):
            mids = {}
            for i in np.flatnonzero(lo < hi):
                mids.setdefault(int((lo[i] + hi[i]) // 2), []).append(int(i))
            for m, spectra in mids.items():
                solve(m, spectra)
                for i in spectra:
                    if fitted(m, i):
                        hi[i] = m
                    else:
                        lo[i] = m + 1
        best = [int(m) for m in hi]
        pending = list(range(batch))
        for step in range(_SCAN_AFTER_FIT + 1):
            groups: dict[int, list[int]] = {}
            for i in pending:
                m = int(hi[i]) + step
                if m <= m_top:
                    groups.setdefault(m, []).append(i)
            pending = []
            for m, spectra in groups.items():
                solve(m, spectra)
                for i in spectra:
                    if mu_of(m, i) < c and fitted(m, i):
                        best[i] = m
                    else:
                        pending.append(i)
            if not pending:
                break
    chosen = []
    for i, m in enumerate(best):
        tau = tau_top if m == m_top else _time_constants(freq, m)
        coef = solved[(m, i)][0]
        mu = mu_of(m, i)
        chosen.append((m, mu, bool(mu < c), tau, coef, _evaluate(omega, tau, coef, inductance, capacitance)))
    return chosen


def _mu(resistances: np.ndarray) -> np.ndarray:
    """µ = 1 − Σ|R_k<0| / Σ|R_k≥0| (Schönleber 2014, eq 21); 0 when no R_k is positive."""
    neg = np.sum(np.where(resistances < 0, -resistances, 0.0), axis=-1)
    pos = np.sum(np.where(resistances >= 0, resistances, 0.0), axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(pos > 0, 1.0 - neg / np.where(pos > 0, pos, 1.0), 0.0)


def _rule_masks(residual_real, residual_imag, scale, thresholds) -> dict[str, np.ndarray]:
    """Each rule's flags (`RULE_NAMES`) from Δ in frequency order; ``scale`` is one number or one
    per frequency (in frequency order)."""
    m = np.hypot(residual_real, residual_imag)
    masks = {"point": m > thresholds["point"] * scale, "run": long_runs(m > thresholds["run"] * scale, int(thresholds["run_length"]))}
    # slow, smooth deviations (drift) hide under the point thresholds but not in a local mean
    width = int(thresholds["window"])
    covered = np.zeros(m.size, bool)
    if 1 < width <= m.size:
        kernel = np.ones(width) / width
        window_scale = scale if np.ndim(scale) == 0 else np.convolve(scale, kernel, mode="valid")
        limit = thresholds["window_mean"] * window_scale / math.sqrt(width)
        starts = np.zeros(m.size - width + 1, bool)
        # the mean of the window's points the point rule left alone: one point far off, flagged
        # itself, does not drag its 2·width − 2 neighbours into a band
        kept = (~masks["point"]).astype(float)
        count = np.convolve(kept, np.ones(width), mode="valid")
        for component in (residual_real, residual_imag):
            total = np.convolve(np.asarray(component) * kept, np.ones(width), mode="valid")
            starts |= np.abs(total) > limit * count
        # every point of a window whose mean is too large: a point is covered when one of the
        # `width` windows containing it starts a flagged window
        covered = np.convolve(starts.astype(float), np.ones(width), mode="full")[: m.size] > 0.5
    masks["window"] = covered
    return masks


def _bad_bands(freq, residual_real, residual_imag, order, scale, thresholds):
    """Flags (data order) and bands [(f_min, f_max)] from Δ in frequency order; ``scale`` is
    one number or one per frequency (in frequency order)."""
    masks = _rule_masks(residual_real[order], residual_imag[order], scale, thresholds)
    flag = masks["point"] | masks["run"] | masks["window"]
    # join bands separated by a single unflagged point: one noisy dip does not split a drift band
    if flag.size > 2:
        gap = ~flag[1:-1] & flag[:-2] & flag[2:]
        flag[1:-1] |= gap
    flagged = np.empty_like(flag)
    flagged[order] = flag
    return flagged, bands_of_flags(freq[order], flag)


def band_rule_counts(flag, masks, freq_sorted=None) -> list[dict[str, int]]:
    """For each band of ``flag`` (frequency order), how many of its points each rule of ``masks``
    (name → flags, frequency order) flagged. With ``freq_sorted`` the bands are those of
    `bands_of_flags` (runs joined across gaps narrower than `BAND_MERGE_DECADES`); without, runs
    of True."""
    return [{name: int(np.count_nonzero(np.asarray(mask, bool)[i:j])) for name, mask in masks.items()} for i, j in _band_spans(flag, freq_sorted)]


def band_rules(flag, masks, freq_sorted=None) -> tuple[tuple[str, ...], ...]:
    """For each band of ``flag``, the names of the rules of ``masks`` that flagged points in it
    (`band_rule_counts`)."""
    return tuple(tuple(name for name, n in counts.items() if n) for counts in band_rule_counts(flag, masks, freq_sorted))


def bad_band_lines(band_frequencies, band_counts, rule_words: Mapping[str, str]) -> list[str]:
    """A validity test's report line per bad band (the linear KK test's and Z-HIT's): its name
    (`band_name`, from its flagged measured frequencies) and, for each rule that flagged points in
    it (``band_counts``: per band, rule → count, `band_rule_counts`), how many and the rule's
    words (``rule_words``: rule → "with |Δ| > 1.2 % (point rule)", in the order said)."""
    lines = []
    for points, counts in zip(band_frequencies, band_counts):
        said = "; ".join(f"{points_text(counts[rule])} {words}" for rule, words in rule_words.items() if counts[rule])
        lines.append(f"  bad band: {band_name(points)}" + (f": {said}" if said else ""))
    return lines


def note_and_hint_lines(non_passive_note: str, sign_hint: str) -> list[str]:
    """A validity test's report lines after its bad bands: the note on points with Re Z < 0 and
    the sign hint, each where there is one."""
    return ([f"note: {non_passive_note}"] if non_passive_note else []) + ([f"hint: {sign_hint}"] if sign_hint else [])


def points_text(n: int) -> str:
    """``1 point``, ``3 points``."""
    return f"{n} point{'' if n == 1 else 's'}"


def zero_impedance_text(freq, z) -> str:
    """``Z is exactly zero at 500 Hz`` (the first three such frequencies; for several spectra, in
    how many): the start of the message that refuses such data."""
    zero = np.abs(np.reshape(z, (-1, np.size(freq)))) == 0
    at = np.flatnonzero(zero.any(axis=0))
    at = at[np.argsort(np.asarray(freq)[at])]
    where = ", ".join(format_frequency(float(freq[i])) for i in at[:3]) + (f" and {at.size - 3} more" if at.size > 3 else "")
    spectra = f" (in {int(zero.any(axis=1).sum())} of {zero.shape[0]} spectra)" if zero.shape[0] > 1 else ""
    return f"Z is exactly zero at {where}{spectra}"


def rejudged(result: KKResult, scale) -> KKResult:
    """``result`` judged again by its own rule (``result.thresholds``) against ``scale``, a
    relative σ per frequency (the data's order, floored at the rule's ``noise_floor``) in
    place of the one global noise estimate: a point stays flagged only when it fails both
    ways (a local scale can clear a point, never add one); bad bands and validity follow, the
    Voigt fit and its residuals are unchanged. For noise that varies along the band: `kk_test`
    scales every point by the median scatter, so the noisier end of a spectrum whose noise
    grows toward low frequency reads as bad."""
    from ..io.sign_check import FAILED_SHARE

    scale = np.maximum(np.broadcast_to(np.asarray(scale, float), result.frequency.shape), result.thresholds["noise_floor"])
    order = np.argsort(result.frequency)
    flagged, _ = _bad_bands(result.frequency, result.residuals_real, result.residuals_imag, order, scale[order], result.thresholds)
    flagged &= np.asarray(result.flagged, bool)
    bands = bands_of_flags(result.frequency[order], flagged[order])
    # (a sign hint says how many points fail: it holds only while that many still do)
    hint = result.sign_hint if bands and np.mean(flagged) >= FAILED_SHARE else None
    return dataclasses.replace(result, flagged=flagged, bad_bands=bands, valid=not bands, sign_hint=hint)


def long_runs(above, run_length: int) -> np.ndarray:
    """Flags of every point in a run of at least ``run_length`` consecutive True ``above``."""
    above = np.asarray(above, bool)
    if above.size == 0:
        return np.zeros(0, bool)
    edges = np.diff(np.concatenate([[0], above.astype(np.int8), [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    long = stops - starts >= run_length
    marks = np.zeros(above.size + 1, np.int64)
    np.add.at(marks, starts[long], 1)
    np.add.at(marks, stops[long], -1)
    return np.cumsum(marks[:-1]) > 0


BAND_MERGE_DECADES = 0.05
"""Flagged points less than this apart in log₁₀ f share a band (`bands_of_flags`), whatever lies
between them: on 10⁴–10⁵ points noise splits a drift's flags into hundreds of runs. One good
point puts 0.1 decade between bad ones at 20 points a decade, so spectra of up to 20 points a
decade keep their bands; a third of Z-HIT's smoothing scale (0.17 decade, `zhit.BIN_PER_DECADE`):
a systematic residual does not leave a level and come back that fast (docs/kk.md, "Bands on
dense spectra")."""


def _band_spans(flag, freq_sorted=None) -> list[tuple[int, int]]:
    """[first, stop) of each band of ``flag`` (frequency order): runs of flagged points, joined when
    the flagged points either side of a gap are less than `BAND_MERGE_DECADES` apart (runs alone
    without ``freq_sorted``)."""
    at = np.flatnonzero(np.asarray(flag, bool))
    if at.size == 0:
        return []
    join = np.diff(at) == 1
    if freq_sorted is not None:
        join |= np.diff(np.log10(np.asarray(freq_sorted, dtype=float)[at])) < BAND_MERGE_DECADES
    breaks = np.flatnonzero(~join)
    first, last = at[np.concatenate([[0], breaks + 1])], at[np.concatenate([breaks, [at.size - 1]])]
    return list(zip(first.tolist(), (last + 1).tolist()))


def _between(lo: float, hi: float, *, lo_open: bool, hi_open: bool, near: float) -> str:
    """The shortest text of a number in the interval from ``lo`` to ``hi`` (each end open or
    closed), rounded from ``near``."""
    for digits in range(1, 18):
        text = f"{near:.{digits}g}"
        v = float(text)
        if (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi):
            return text.replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")
    return repr(float(near))


def frequency_text(f: float, measured) -> str:
    """``f`` [Hz] as ``--exclude`` takes it: the shortest text (3 digits or more) whose nearest
    measured frequency (of ``measured``) is ``f`` within `EXCLUDE_RTOL`."""
    measured = np.asarray(measured, float)
    for digits in range(3, 18):
        text = f"{f:.{digits}g}"
        v = float(text)
        nearest = measured[np.argmin(np.abs(np.log(measured / v)))] if measured.size else f
        if nearest == f and abs(v / f - 1) <= EXCLUDE_RTOL:
            return text.replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")
    return repr(float(f))


def left_out_options(kept, masked) -> list[tuple[str, str]]:
    """The ``impedax fit`` options that leave out the ``masked`` frequencies [Hz] of a fit on
    ``kept`` ones: ``--fmin``/``--fmax`` for the masked points at the ends of the band,
    ``--exclude F,F`` for those inside it (`frequency_text`). Empty when nothing is masked."""
    kept = np.sort(np.asarray(kept, float))
    masked = np.sort(np.asarray(masked, float))
    if not masked.size or not kept.size:
        return []
    lo, hi = kept[0], kept[-1]
    options = []
    below, above = masked[masked < lo], masked[masked > hi]
    if below.size:
        options.append(("--fmin", _between(below[-1], lo, lo_open=True, hi_open=False, near=lo)))
    if above.size:
        options.append(("--fmax", _between(hi, above[0], lo_open=False, hi_open=True, near=hi)))
    inside = masked[(masked > lo) & (masked < hi)]
    if inside.size:
        measured = np.concatenate([kept, masked])
        options.append(("--exclude", ",".join(frequency_text(f, measured) for f in inside)))
    return options


def band_points(freq_sorted, flag) -> tuple[tuple[float, ...], ...]:
    """For each band of ``flag`` (frequency order; the bands of `bands_of_flags`), the measured
    frequencies [Hz] of its flagged points, ascending: what a report names (`band_name`)."""
    freq_sorted = np.asarray(freq_sorted, dtype=float)
    flag = np.asarray(flag, bool)
    return tuple(tuple(float(f) for f in freq_sorted[i:j][flag[i:j]]) for i, j in _band_spans(flag, freq_sorted))


def bands_of_flags(freq_sorted, flag) -> tuple[tuple[float, float], ...]:
    """Flagged points (in frequency order) as bands (f_min, f_max) [Hz]: runs of them, joined
    across gaps narrower than `BAND_MERGE_DECADES`; the edges lie halfway in log f to the
    neighbouring good points, so a single point has a width."""
    flag = np.asarray(flag, bool)
    freq_sorted = np.asarray(freq_sorted, dtype=float)
    bands = []
    for i, stop in _band_spans(flag, freq_sorted):
        j = stop - 1
        lo = freq_sorted[i] if i == 0 else math.sqrt(freq_sorted[i - 1] * freq_sorted[i])
        hi = freq_sorted[j] if j == flag.size - 1 else math.sqrt(freq_sorted[j] * freq_sorted[j + 1])
        bands.append((float(lo), float(hi)))
    return tuple(bands)


@checked_arguments(
    max_rc=count(1, MAX_BASIS, optional=True), n_rc=count(1, MAX_BASIS, optional=True), inductance=flag, capacitance=flag,
    thresholds=instance_of(Mapping, optional=True, what="a mapping name → number"), find_passing_band=flag,
)
def kk_test(
    data,
    *,
    c: float = 0.85,
    max_rc: int | None = None,
    n_rc: int | None = None,
    inductance: bool = True,
    capacitance: bool = True,
    thresholds: Mapping[str, float] | None = None,
    noise: str = "auto",
    find_passing_band: bool = False,
) -> KKResult:
    """Linear Kramers–Kronig test of one spectrum (Schönleber et al. 2014).

    Fits Z_kk(ω) = R_0 + Σ_k R_k/(1 + jωτ_k) [+ jωL] [+ 1/(jωC)] with τ_k log-spaced from
    1/(2π f_max) to 1/(2π f_min), by linear least squares on Re and Im weighted by 1/|Z|. M: the
    smallest that is not underfitted against the most flexible chain (``max_rc``, default
    `reference_rc`: N/2, or 3.5 per decade on sparse data) and has µ = 1 − Σ|R_k<0|/Σ|R_k≥0| < ``c``
    (Schönleber's µ criterion; docs/kk.md, "Choosing M"), unless ``n_rc`` fixes it. Residuals
    Δ = (Z_data − Z_kk)/|Z_data| per frequency.

    Validity rule (impedax): ``noise_estimate`` σ̂ = 1.4826·median|first differences of Δ' and Δ''
    in frequency order|/√2, inflated by sqrt(2N/(2N−P)); scale s = max(σ̂, noise_floor = 0.2 %,
    ``chain_error``, the default reference chain's own misfit of one relaxation on these
    frequencies, whatever ``max_rc`` or ``n_rc``).
    A point is bad when |Δ| > 5 s; every point of a run of ≥ 3 consecutive frequencies with
    |Δ| > 3 s is bad; and the 9 points of any window where the mean of Δ' or of Δ'' exceeds
    4.5 s/3 are bad (slow drift). Bad points (single good gaps closed) form ``bad_bands``: runs,
    joined when less than `BAND_MERGE_DECADES` (0.05 decade) apart (the flags stay as they are),
    edges halfway in log f to the good neighbours; ``valid`` is True when there are none. The
    window means leave out the points the point rule flags, and lone spikes over the point level
    (`STRAY_PEAK_RATIO`) are left out of the chain's fit and every point judged against it again
    (`SPIKE_ROUNDS`, `SPIKE_SHARE_MAX`; not with ``n_rc``): one point far off is a band of that
    point, not of its neighbours (docs/kk.md, "The validity rule", 5). On 100
    synthetic spectra per case at 0.5 % and 2 % noise (RC, R-CPE, Randles, two arcs, finger EDL)
    none was flagged. Override with ``thresholds={"point", "run", "run_length", "window_mean",
    "window", "noise_floor"}``.

    ``data``: a spectrum Dataset with only the ``frequency`` dimension, or a (frequency, Z)
    pair; for extra dimensions use `kk_test_batch`. ``inductance`` adds a series L (leads), and
    ``capacitance`` a series C (needed when the data are capacitive at the lowest frequency, e.g.
    blocking electrodes). Raises DataError/ParameterError on bad input.

    ``noise``: where each point's noise comes from. ``"sigma"``: the data's
    stated σ (their ``sigma`` variable, σ of Re and of Im in Ω): the chain is weighted by 1/σ
    (scaled to relative weights, `noise_shapes`) instead of 1/|Z|, and each point's |Δ| is judged
    against its own scale max(σ/|Z|, noise_floor, ``chain_error``) instead of the one global
    estimate (`KKResult.point_scale`; the estimate is still reported). ``"residuals"``: the
    global estimate, whatever the data carry. ``"auto"`` (default): ``"sigma"`` when
    the data carry σ. Noise that differs between bands (SYNTHETIC R_s + R_p ∥ CPE, 3 % below
    10 Hz, 0.3 % above, with that σ: 0 of 12 spectra passed by the residuals, 12 of 12 by σ).
    `KKResult.noise_from` says which was used.

    ``find_passing_band``: when the test fails and the bands' rules leave no
    point out (`KKResult.excludable_frequencies`: a failing band at an end too wide to drop, or
    one inside), test again without points at the ends (`PASSING_BAND_EVERY_SPLIT`, at most one
    tests per point beyond the first 44) and report the widest band found on which the test passes
    (`KKResult.passing_band`, its rms_rel `passing_rms_rel`); its points outside are then the
    ones to leave out. ``impedax kk`` on one spectrum does this.
    """
    freq, z, dims, _, source, sigma = frequency_z_and_sigma(data)
    if dims:
        raise DataError(
            f"Z has extra dimensions {dims}; kk_test takes one spectrum: use impedax.kk_test_batch(data) for one test per spectrum, or reduce them first (e.g. data.mean({dims[0]!r}))",
            path=source,
        )
    options = dict(c=c, max_rc=max_rc, n_rc=n_rc, inductance=inductance, capacitance=capacitance, thresholds=thresholds, noise=noise)
    sigma = None if sigma is None else sigma[None, :]
    result = _run(freq, z[None, :], (), (), {}, **options, source=source, attrs=data.attrs if isinstance(data, xr.Dataset) else None, sigma=sigma).results[0]
    found = retested_band(result, freq, z, sigma=None if sigma is None else sigma[0], **options) if find_passing_band else None
    if found is None:
        return result
    lo, hi, passed = found
    return dataclasses.replace(result, passing_band=(lo, hi), passing_rms_rel=passed.rms_rel,
                               passing_edge=_passing_edge(passed, cut_low=lo > freq.min(), cut_high=hi < freq.max()))


def _passing_edge(passed: KKResult, *, cut_low: bool, cut_high: bool) -> tuple[float, float, float, float, float] | None:
    """`KKResult.passing_edge` of the test ``passed`` on a passing band cut at its low and/or
    high end: the points within `EDGE_DECADES` of a cut whose rms |Δ| exceeds `EDGE_EXCESS` ×
    the median |Δ| of the band's other points (the low end first); None otherwise."""
    f = passed.frequency
    size = np.hypot(passed.residuals_real, passed.residuals_imag)
    for cut, edge in ((cut_low, f <= f.min() * 10**EDGE_DECADES), (cut_high, f >= f.max() / 10**EDGE_DECADES)):
        rest = size[~edge]
        if not cut or not edge.any() or rest.size < CONCLUSIVE_POINTS_MIN:
            continue
        median = float(np.median(rest))
        if math.sqrt(float(np.mean(size[edge] ** 2))) > EDGE_EXCESS * median:
            return float(f[edge].min()), float(f[edge].max()), float(size[edge].min()), float(size[edge].max()), median
    return None


def retested_band(result: KKResult, freq, z, *, sigma=None, **options) -> tuple[float, float, KKResult] | None:
    """The band `kk_test(find_passing_band=True)` (and so ``impedax kk``) names for its test
    ``result`` of (``freq`` [Hz], ``z`` [Ω]): `passing_band` keeping at least half of the points,
    searched only when the test failed and the bands' rules leave no point out; None otherwise or
    when none passes. ``diagnose`` names the same band (one trim for one spectrum)."""
    if not result.searches_passing_band:
        return None
    return passing_band(freq, z, sigma=sigma, min_points=max(CONCLUSIVE_POINTS_MIN, math.ceil(np.size(freq) / 2)), **options)


def passing_band(freq, z, *, sigma=None, min_points: int = CONCLUSIVE_POINTS_MIN, **options) -> tuple[float, float, KKResult] | None:
    """The widest band, left by leaving points out at the ends of (``freq`` [Hz], ``z`` [Ω]),
    on which the test passes (`PASSING_BAND_EVERY_SPLIT`: every split of up to 8 points in all,
    then a staircase; the fewest points left out, then the lowest rms_rel), keeping at least
    ``min_points``: its lowest and highest frequency and its test; None when none passes.
    ``sigma``: the data's stated σ per point [Ω] or None; ``options``: `kk_test`'s."""
    order = np.argsort(freq)
    f, zs = np.asarray(freq, float)[order], np.asarray(z, complex)[order]
    stated = None if sigma is None else np.asarray(sigma, float)[order]
    options = _options_of_kk_test(options)
    n = f.size
    most = n - max(int(min_points), CONCLUSIVE_POINTS_MIN)
    tested: dict[tuple[int, int], KKResult | None] = {}

    def test(low: int, high: int) -> KKResult | None:
        if (low, high) not in tested:
            keep = slice(low, n - high)
            try:
                result = _run(f[keep], zs[keep][None, :], (), (), {}, **options, sign_check=False, sigma=None if stated is None else stated[keep][None, :]).results[0]
            except ImpedaxError:  # (a chain the user's max_rc or n_rc cannot give on fewer points)
                result = None
            tested[low, high] = result if result is not None and result.valid else None
        return tested[low, high]

    for total in range(1, min(most, PASSING_BAND_EVERY_SPLIT) + 1):
        passed = [(r.rms_rel, low, r) for low in range(total + 1) if (r := test(low, total - low)) is not None]
        if passed:
            _, low, result = min(passed, key=lambda p: p[:2])
            return float(f[low]), float(f[n - 1 - (total - low)]), result
    found = []
    low, high = 0, most
    while low <= most:
        high = min(high, most - low)
        if low + high <= PASSING_BAND_EVERY_SPLIT:  # (tested above: none passed)
            low += 1
            continue
        result = test(low, high)
        if result is None:
            low += 1
            continue
        found.append((low + high, result.rms_rel, low, high, result))
        if high == 0:
            break
        high -= 1
    if not found:
        return None
    _, _, low, high, result = min(found, key=lambda p: p[:4])
    return float(f[low]), float(f[n - 1 - high]), result


def kk_test_batch(data, **options) -> KKBatchResult:
    """`kk_test` of every spectrum of a Dataset with extra dimensions (trial, session, ...).

    All spectra are solved together (one batched QR per M), each stopping at its own M.
    Takes the keyword options of `kk_test` (same defaults, same validity rule); returns a
    `KKBatchResult`. A batch dimension named as a variable or dimension of its Dataset
    (`BATCH_RESULT_NAMES`: ``rc``, ``band``, ``mu``, …) is a `DataError`, before any test.
    """
    freq, z, dims, coords, source, sigma = frequency_z_and_sigma(data)
    refuse_result_names(dims, BATCH_RESULT_NAMES, "a KK batch result", source=source)
    return _run(freq, z, z.shape[:-1], dims, coords, **_options_of_kk_test(options), source=source, attrs=data.attrs if isinstance(data, xr.Dataset) else None, sigma=sigma)


def _options_of_kk_test(options: Mapping) -> dict:
    """``options`` checked against `kk_test`'s keywords, with its defaults filled in
    (``find_passing_band`` is one spectrum's: refused)."""
    if options.get("find_passing_band"):
        raise ParameterError("kk_test_batch: find_passing_band searches one spectrum at a time: give kk_test one spectrum (data.isel(...) or data.sel(...)) for it")
    options = {k: v for k, v in options.items() if k != "find_passing_band"}
    try:
        bound = inspect.signature(kk_test).bind(None, **options)
    except TypeError as exc:
        raise ParameterError(f"kk_test_batch: {exc} (it takes the options of kk_test)") from None
    bound.apply_defaults()
    return {name: value for name, value in bound.arguments.items() if name not in ("data", "find_passing_band")}


kk_test_batch.__signature__ = inspect.signature(kk_test).replace(return_annotation="KKBatchResult")


def kk_misfits(data, **options) -> np.ndarray:
    """The ``rms_rel`` of `kk_test_batch`'s Voigt-chain fits (shape: the extra dimensions),
    without its flags, bands and sign check (~20 % less work), for a yardstick of what a
    Kramers–Kronig-consistent model leaves (the start ladder and the misfit notes)."""
    freq, z, _, _, source, sigma = frequency_z_and_sigma(data)
    flat = z.reshape(-1, freq.size)
    _, chosen, _ = _chosen_chains(freq, flat, **_options_of_kk_test(options), source=source, sigma=None if sigma is None else sigma.reshape(flat.shape))
    return np.array([_rms_rel(zi, z_kk) for zi, (*_, z_kk) in zip(flat, chosen)], float).reshape(z.shape[:-1])


def kk_verdicts(freq, z, attrs=None) -> list[tuple[bool | None, str | None, int | None]]:
    """`kk_test_batch`'s (default options) ``valid``, ``sign_hint`` and chain size for each
    spectrum of z (B, N): whether its residuals from the Voigt chain are noise (the data are
    Kramers–Kronig-consistent within their own noise), why and how its imaginary part may be
    stored with the opposite sign (`io.sign_check.sign_hint`; ``attrs``: the data's, for how to
    fix the file; conj(Z) is tested only for a spectrum whose own test fails almost
    everywhere), and the number of the chain's linear parameters (M resistances, R_0, L and 1/C);
    (None, None, None) where the test cannot run. For the note that the data limit a fit
    (`least_squares.result.misfit_notes`)."""
    return KKChains().verdicts(freq, z, range(len(np.atleast_2d(z))), attrs)


class _KeptChain(NamedTuple):
    impedance: np.ndarray  # (N,) the spectrum as the test read it
    chain: tuple  # `_kk_arrays`'s (M, µ, µ-criterion met, τ, coefficients, Z_kk)
    rms_rel: float  # its misfit (`kk_misfits`)


class KKChains:
    """One fit call's memory of the Voigt chains of `kk_misfits` and `kk_verdicts` (default
    options): row of the call's stack of spectra z (B, N) → its chain, each fitted once, when
    first asked for, and shared by both (fitting each checked spectrum's chain twice, once for its
    rms_rel and once in the full test, would cost 30 + 27 ms of a ~300 ms warm batch call on
    1,000 noisy copies of a REAL battery cycle, 21 spectra checked).
    The spectra asked for together are fitted as one stack (`kk_test_batch`'s batched solves);
    the answers are those functions' on the same rows to rounding (the stack's blocks differ
    with its size). Every call must pass the same ``freq`` and ``z`` (the rows index them)."""

    def __init__(self) -> None:
        self._chains: dict[int, _KeptChain | None] = {}  # row → its chain; None where the test cannot run
        self._read: tuple | None = None  # (frequencies, source) as the test read them

    def _fitted(self, freq, z, rows) -> list[_KeptChain | None]:
        rows = [int(i) for i in np.atleast_1d(rows)]
        missing = list(dict.fromkeys(i for i in rows if i not in self._chains))
        if missing:
            try:
                f, flat, _, _, source = frequency_and_z((np.asarray(freq, float), np.atleast_2d(z)[missing]))
                flat = flat.reshape(-1, f.size)
                _, chosen, _ = _chosen_chains(f, flat, **_options_of_kk_test({}), source=source)
                self._read = (f, source)
                self._chains.update((i, _KeptChain(zi, chain, _rms_rel(zi, chain[-1]))) for i, zi, chain in zip(missing, flat, chosen))
            except ImpedaxError:
                self._chains.update((i, None) for i in missing)
        return [self._chains[i] for i in rows]

    def misfits(self, freq, z, rows) -> np.ndarray:
        """`kk_misfits` of the spectra z[rows] (z: B, N; 0 where the test cannot run, as
        `least_squares.starts.attainable_misfit`)."""
        return np.array([0.0 if kept is None else kept.rms_rel for kept in self._fitted(freq, z, rows)], float)

    def misfit(self, row: int) -> float | None:
        """The rms_rel of row's chain when it was fitted (as `misfits`), else None."""
        if int(row) not in self._chains:
            return None
        kept = self._chains[int(row)]
        return 0.0 if kept is None else kept.rms_rel

    def verdicts(self, freq, z, rows, attrs=None) -> list[tuple[bool | None, str | None, int | None]]:
        """`kk_verdicts` of the spectra z[rows] (z: B, N), judged against the chains kept (the
        ones `misfits` gave), fitting those not yet asked for."""
        rows = [int(i) for i in np.atleast_1d(rows)]
        kept = self._fitted(freq, z, rows)
        out: list[tuple[bool | None, str | None, int | None]] = [(None, None, None)] * len(rows)
        ok = [k for k, chain in enumerate(kept) if chain is not None]
        if not ok:
            return out
        options = _options_of_kk_test({})
        f, source = self._read
        flat = np.stack([kept[k].impedance for k in ok])
        try:
            batch = _run(f, flat, flat.shape[:-1], ("spectrum",), {}, **options, source=source, attrs=attrs, chosen=[kept[k].chain for k in ok])
        except ImpedaxError:
            return out
        series = 1 + int(bool(options["inductance"])) + int(bool(options["capacitance"]))
        for k, r in zip(ok, batch.results):
            out[k] = (bool(r.valid), r.sign_hint, int(r.n_rc) + series)
        return out


def kk_sigma_misfits(freq, z, sigma) -> tuple[np.ndarray, np.ndarray]:
    """χ²_red = Σ (ΔRe² + ΔIm²)/σ² / (2N − P) of `kk_test`'s Voigt chain weighted by the stated
    ``sigma`` (B, N; σ of Re and of Im [Ω]) for each spectrum of z (B, N), and P, the chain's
    linear parameters (M resistances, R_0, L and 1/C): what a Kramers–Kronig-consistent model
    reaches under the same σ weighting as a fit's (`least_squares.result.misfit_notes`). Near 1
    when σ states the noise; far above it when σ understates the noise somewhere, whatever the
    model. NaN where the test cannot run."""
    z = np.atleast_2d(np.asarray(z, complex))
    sigma = np.broadcast_to(np.asarray(sigma, float), z.shape)
    options = {**_options_of_kk_test({}), "noise": "sigma"}
    try:
        _, chosen, _ = _chosen_chains(np.asarray(freq, float), z, **options, sigma=sigma)
    except ImpedaxError:
        return np.full(len(z), np.nan), np.zeros(len(z), int)
    series = 1 + int(bool(options["inductance"])) + int(bool(options["capacitance"]))
    params = np.array([m + series for m, *_ in chosen], int)
    dz = np.stack([z_kk for *_, z_kk in chosen]) - z
    with np.errstate(all="ignore"):
        chi2 = np.sum((dz.real**2 + dz.imag**2) / sigma**2, axis=-1)
    return chi2 / np.maximum(2 * z.shape[-1] - params, 1), params


def _rms_rel(z, z_kk) -> float:
    return float(np.sqrt(np.mean(np.abs((z - z_kk) / np.abs(z)) ** 2)))


NOISE_SOURCES = ("auto", "sigma", "residuals")
"""The ``noise`` option of `kk_test`: where each point's noise comes from."""


def noise_shapes(relative_sigma) -> np.ndarray:
    """σ/|Z| (B, N) over each spectrum's median: the chain's σ weights 1/(|Z|·shape) are 1/σ up
    to a constant that keeps them on the scale of the 1/|Z| ones (the noise floor and the
    underfit bound of `_fits_like_reference` keep their meaning)."""
    rel = np.atleast_2d(np.asarray(relative_sigma, float))
    return rel / np.median(rel, axis=-1, keepdims=True)


def _relative_sigma(noise, sigma, z, source=None) -> np.ndarray | None:
    """The stated σ/|Z| (B, N) the test judges by (``noise``, `NOISE_SOURCES`), or None for the
    residuals' own estimate."""
    if not isinstance(noise, str) or noise not in NOISE_SOURCES:
        raise ParameterError(f"noise must be one of {', '.join(repr(n) for n in NOISE_SOURCES)}, got {shown(noise)}")
    if noise == "residuals" or (sigma is None and noise == "auto"):
        return None
    if sigma is None:
        raise DataError("noise='sigma' needs a 'sigma' variable in the data (σ of Re and of Im in Ω: a sigma column, or make_spectrum(sigma=...))", path=source)
    sigma = np.broadcast_to(np.asarray(sigma, float), np.shape(z))
    if not np.all(np.isfinite(sigma) & (sigma > 0)):
        raise DataError("the data's sigma must be finite and positive at every point for the KK test to weigh by it", path=source)
    return sigma / np.abs(z)


def _chosen_chains(freq, z, *, c, max_rc, n_rc, inductance, capacitance, thresholds, noise="auto", source=None, sigma=None, chosen=None):
    """The validated thresholds (for N points), `_kk_arrays`'s chain of each spectrum z (batch, N),
    and the stated σ/|Z| (batch, N) the chains were weighted by (`_relative_sigma`; None: 1/|Z|).
    ``chosen``: the chains, fitted already with these options (`KKChains`), not fitted again."""
    c = _mu_limit(c)
    rules = dict(DEFAULT_THRESHOLDS)
    for key, value in (thresholds or {}).items():
        if key not in rules:
            raise ParameterError(f"unknown threshold {key!r}; known: {', '.join(rules)}")
        try:  # (any real number, as c: a NumPy scalar too; not a bool)
            rules[key] = real(positive=True)(value, f"threshold {key}")
        except ParameterError:
            raise ParameterError(f"threshold {key} must be a positive number, got {shown(value)}") from None
    for name, flag in (("inductance", inductance), ("capacitance", capacitance)):
        if not isinstance(flag, (bool, np.bool_)):
            raise ParameterError(f"{name} must be True or False, got {flag!r}")
    if np.any(np.abs(z) == 0):
        raise DataError(f"{zero_impedance_text(freq, z)}; the 1/|Z| weighting needs |Z| > 0", path=source)
    relative_sigma = _relative_sigma(noise, sigma, z, source)
    shape = None if relative_sigma is None else noise_shapes(relative_sigma)
    dense = freq.size > rules["reference_points"]  # (before `thresholds_for` raises it to N)
    rules = thresholds_for(rules, freq.size)
    floor = rules["noise_floor"] * (DENSE_CHAIN_FLOOR_SHARE if dense else 1.0)
    try:
        if chosen is not None:
            return rules, list(chosen), relative_sigma
        return rules, _kk_arrays(freq, z, c=c, max_rc=max_rc, n_rc=n_rc, inductance=bool(inductance), capacitance=bool(capacitance), floor=floor, noise_shape=shape), relative_sigma
    except DataError as error:  # (too few frequencies): name the data
        if error.path is None and source is not None:
            raise DataError(str(error), path=source) from None
        raise


def _run(freq, z, shape, dims, coords, *, c, max_rc, n_rc, inductance, capacitance, thresholds, noise="auto", source=None, attrs=None, sign_check=True, sigma=None, chosen=None) -> KKBatchResult:
    """The tests of the spectra ``z`` (batch, N); ``sign_check``: each result's ``sign_hint``
    (`io.sign_check.sign_hint`, the test of conj(Z) with the same options; ``attrs``: the data's, for
    how to fix the file); ``sigma``: the data's stated σ (batch, N) [Ω] or None, used as ``noise``
    says (`kk_test`); ``chosen``: each spectrum's chain, fitted already (`KKChains`)."""
    flat = z.reshape(-1, freq.size)
    sigma = None if sigma is None else np.broadcast_to(np.asarray(sigma, float), z.shape).reshape(flat.shape)
    rules, chosen, relative_sigma = _chosen_chains(freq, flat, c=c, max_rc=max_rc, n_rc=n_rc, inductance=inductance, capacitance=capacitance, thresholds=thresholds,
                                                   noise=noise, source=source, sigma=sigma, chosen=chosen)
    order = np.argsort(freq)
    n_series = 1 + int(inductance) + int(capacitance)
    # the default reference chain's misfit, whatever chain the user chose: a short one of their
    # own is judged as strictly as the default one, not excused by its own coarseness
    chain_floor = chain_error(freq, reference_rc(freq, n_series), bool(inductance), bool(capacitance))
    floor = max(rules["noise_floor"], chain_floor)
    dense = freq.size > {**DEFAULT_THRESHOLDS, **(thresholds or {})}["reference_points"]
    chain_floor_share = rules["noise_floor"] * (DENSE_CHAIN_FLOOR_SHARE if dense else 1.0)  # (the floor of `_chosen_chains`)
    results = []
    for row, (zi, (m, mu, reached, taus, coef, z_kk)) in enumerate(zip(flat, chosen)):
        # each point's own scale from the stated σ (`kk_test`'s ``noise``), else one for all
        stated = None if relative_sigma is None else np.maximum(relative_sigma[row], floor)
        shape_row = None if relative_sigma is None else noise_shapes(relative_sigma[row])
        residual = (zi - z_kk) / np.abs(zi)
        noise_level = residual_noise(residual.real, residual.imag, order, coef.size)
        scale = stated if stated is not None else max(noise_level, floor) if math.isfinite(noise_level) else floor
        # stray points far off pull the least-squares chain toward them and their neighbours off
        # it: the chain (M chosen again: such a point also loosens the χ² bound) is fitted without
        # them, every point judged against it (`SPIKE_SHARE_MAX`, `SPIKE_ROUNDS`)
        left_out = np.zeros(freq.size, bool)
        whole = (m, mu, reached, taus, coef, z_kk, residual, noise_level, scale)  # (the chain of every point, `_neighbours_off`)
        for _ in range(SPIKE_ROUNDS):
            size = np.hypot(residual.real, residual.imag)
            stray = (size > rules["point"] * scale) & ~left_out & _peaks(size, order)
            if n_rc is not None or not stray.any() or np.count_nonzero(left_out | stray) > SPIKE_SHARE_MAX * freq.size or (
                    max_rc is not None and max_rc > np.count_nonzero(~(left_out | stray)) - n_series):
                break
            left_out |= stray
            (m, mu, reached, taus, coef, _), = _kk_arrays(freq[~left_out], zi[None, ~left_out], c=_mu_limit(c), max_rc=max_rc, n_rc=n_rc, inductance=bool(inductance),
                                                          capacitance=bool(capacitance), floor=chain_floor_share,
                                                          noise_shape=None if shape_row is None else shape_row[:, ~left_out])
            z_kk = _evaluate(2 * np.pi * freq, taus, coef, bool(inductance), bool(capacitance))
            residual = (zi - z_kk) / np.abs(zi)
            noise_level = residual_noise(residual.real, residual.imag, order, coef.size)
            scale = stated if stated is not None else max(noise_level, floor) if math.isfinite(noise_level) else floor
        if left_out.any() and _neighbours_off(np.hypot(residual.real, residual.imag), left_out, order, rules["point"] * scale):
            left_out[:] = False  # (the edge of a drift, not a lone spike: judged with the rest, on the whole chain)
            m, mu, reached, taus, coef, z_kk, residual, noise_level, scale = whole
        flagged, bands = _bad_bands(freq, residual.real, residual.imag, order, scale if stated is None else scale[order], rules)
        results.append(
            KKResult(
                frequency=freq.copy(),
                impedance=zi.copy(),
                kk_impedance=z_kk,
                residuals_real=residual.real.copy(),
                residuals_imag=residual.imag.copy(),
                flagged=flagged,
                n_rc=int(m),
                mu=mu,
                mu_reached=reached,
                n_rc_given=n_rc is not None,
                rms_rel=_rms_rel(zi, z_kk),
                noise_estimate=noise_level,
                threshold_scale=scale if stated is None else float(np.median(stated)),
                point_scale=None if stated is None else stated.copy(),
                noise_from="residuals" if stated is None else "sigma",
                valid=not bands,
                bad_bands=bands,
                time_constants=taus.copy(),
                resistances=coef[n_series:].copy(),
                series_resistance=float(coef[0]),
                series_inductance=float(coef[1]) if inductance else 0.0,
                inverse_series_capacitance=float(coef[n_series - 1]) if capacitance else 0.0,
                c=float(c),
                thresholds=rules,
                chain_error=chain_floor,
                stray_frequencies=np.sort(freq[left_out]),
            )
        )
    if sign_check:
        from ..io.sign_check import sign_hint

        def retest(f, z_conj, row_sigma=None):
            options = dict(c=c, max_rc=max_rc, n_rc=n_rc, inductance=inductance, capacitance=capacitance, thresholds=thresholds, noise=noise, source=source, sign_check=False)
            return _run(f, z_conj[None, :], (), (), {}, **options, sigma=row_sigma).results[0]

        results = [dataclasses.replace(r, sign_hint=sign_hint(r, retest if sigma is None else (lambda f, zc, s=sigma[i]: retest(f, zc, s[None, :])), "the KK test", attrs))
                   for i, r in enumerate(results)]
    return KKBatchResult(dims=dims, shape=shape, coords=coords, results=tuple(results))
