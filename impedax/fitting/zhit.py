"""Z-HIT: the modulus |Z| reconstructed from the phase, a second opinion next to the linear
Kramers–Kronig test.

For a causal, stable, linear (minimum-phase) impedance, ln|Z| and the phase φ are a Hilbert
pair; the approximation of Ehm, Göhr, Kaus, Röseler, Schiller (ACH Models in Chemistry 137
(2000) 145; Schiller et al., "Z-HIT", Electrochim. Acta 2001) reads, with x = ln ω:

    ln|Z(x₀)| ≈ C + (2/π) ∫_{x_s}^{x₀} φ(x) dx + γ₁ dφ/dx |_{x₀},   γ₁ = −π/6.

The phase is smoothed by a penalised cubic spline (`scipy.interpolate.make_smoothing_spline`,
Σ(φ_k − s(x_k))² + λ∫s''² dx with λ = 0.1 at 10 points per decade, proportional to the point
density), which gives the integral and the derivative; GCV's λ follows the phase noise into the
derivative term and doubles the residuals at 1 % noise, while this λ also smooths the
first-order approximation error at sharp R‖C corners (2.7 % → 1.1 % on an exact R‖C). Above
`BIN_PER_DECADE` points a decade the spline is fitted to the phase's means over bins of 0.01
decade, weighted by their counts (the same sum of squares to within the phase's bend over a bin;
fitted to every point, the spline's system is ill-conditioned there and its cost grows). The
unknown constant C is the median of ln|Z| − (the rest) over all points (robust to a drifting band).

At the band's ends the slope is one-sided: the spline's natural end condition (s'' = 0) holds it
flat where the phase still bends (a lead inductance at the top: 5.7 % at 100 kHz on an exact
spectrum). Within `END_LAYER` of either end the slope is also taken from a local cubic through
the phase of the last `END_REACH` (tricube weights), which follows the bend but is noisier; each
such point keeps the reconstruction nearer its measured |Z|, so it is flagged only when both
disagree (the noise estimate is taken before: this can clear an end point, never add one).

Residuals (|Z| − |Z|_ZHIT)/|Z| above the noise mark bands where modulus and phase disagree —
typically drift during a slow low-frequency sweep, which the phase hides and |Z| shows. Beyond
`REFERENCE_POINTS` points the rules' factors rise as the linear test's (`kk.thresholds_for`), so
the false alarms per spectrum do not grow with the number of points.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from ..arguments import checked_arguments, count, real
from ..data import concise_repr, counted, format_frequency, label_value, report_text
from ..errors import DataError, ParameterError
from ..io.netcdf import result_dataset
from .kk import CONCLUSIVE_POINTS_MIN, DEFAULT_THRESHOLDS, NON_PASSIVE_LEAVE_OUT, ValidityGrid, bad_band_lines, band_name, band_points, band_rule_counts, band_rules, bands_of_flags, long_runs, note_and_hint_lines, thresholds_for, zero_impedance_text
from .grid import refuse_result_names
from .problem import frequency_and_z
from .statistics import difference_noise, non_passive, non_passive_words
from .frozen import FrozenResult, freeze_fields

__all__ = ["ZHITResult", "ZHITBatchResult", "zhit", "zhit_batch", "END_LAYER", "END_REACH", "CONCLUSIVE_PER_DECADE_MIN", "BIN_PER_DECADE", "REFERENCE_POINTS"]

_GAMMA_1 = -math.pi / 6.0

ZHIT_RESIDUAL_NOISE = "Z-HIT's residuals"
"""`statistics.non_passive_words`' name of the noise Z-HIT's residuals show (`ZHITResult.noise_estimate`)."""

END_LAYER = 0.6
"""ln ω (0.26 decade): the points this close to either end of the band take the local slope when
it brings the reconstruction nearer their |Z| (module docstring)."""
END_REACH = 1.5
"""ln ω (0.65 decade): the half-width of the local cubic's tricube window."""
_END_DEGREE = 3

BIN_PER_DECADE = 100
"""Above this many points a decade (on average) the phase is smoothed, and its end slopes fitted,
as its means over bins of 1/`BIN_PER_DECADE` decade weighted by their counts (`_binned`). With
λ ∝ density the spline's equivalent kernel has the scale (λ/density)^¼ ≈ 0.17 decade at any
density (Silverman, Ann. Stat. 12 (1984) 898; first zero at 0.6 decade), 17 bins. Fitted to
every point, the ratio of its penalty to its data terms (λ/h³, spacing h) grows as the
density⁴: on an exact R‖C over 1 mHz–1 MHz its phase was 5 mrad off at 10⁵ points and 0.16 rad
at 2·10⁵ (scipy 1.17); and the end points' local cubics, one a point, cost O(N²)."""

_BINS_MIN = 10

REFERENCE_POINTS = int(DEFAULT_THRESHOLDS["reference_points"])
"""``point`` and ``run`` hold up to this many points; beyond, they are raised as the linear
test's (`kk.thresholds_for`), so the false alarms per spectrum do not grow with N."""

CONCLUSIVE_PER_DECADE_MIN = 2.0
"""Below this many points a decade (or `kk.CONCLUSIVE_POINTS_MIN` points in all) the phase's
integral and slope rest on too few points: exact R‖C, R‖CPE, two-arc and Randles spectra at 1–1.8
points a decade leave up to 4–16 %, against ≤ 3.4 % from 2 a decade up (`ZHITResult.conclusive`)."""


@dataclass(frozen=True, eq=False)
class ZHITResult(FrozenResult):
    """Z-HIT of one spectrum (arrays in the data's order).

    ``modulus``: |Z| reconstructed from the phase [Ω]; ``residuals``: (|Z| − modulus)/|Z|
    (fractions); ``rms_rel``: sqrt(mean residual²); ``noise_estimate``: robust σ of the
    residuals; ``threshold``: the point threshold (``point`` × max(noise, floor)), and
    ``run_threshold`` the level of the run rule (``run_length`` points above it), both fractions of
    |Z|; ``flagged``/``bad_bands`` [(f_min, f_max) Hz]: where |Z| and the phase disagree;
    ``band_rules``: the rules ("point", "run") that flagged each band; ``end_slope_local``: the
    end points whose reconstruction took the local slope; ``valid``: no bad band; ``sign_hint``:
    why and how the imaginary part may be stored with the opposite sign, or None.
    """

    __repr__ = concise_repr  # (the generated one printed every array)
    __str__ = report_text  # (print(result): its report)

    frequency: np.ndarray
    impedance: np.ndarray
    modulus: np.ndarray
    residuals: np.ndarray
    rms_rel: float
    noise_estimate: float
    threshold: float
    flagged: np.ndarray
    bad_bands: tuple[tuple[float, float], ...]
    valid: bool
    offset: float
    run_threshold: float = math.nan
    run_length: int = 3
    band_rules: tuple[tuple[str, ...], ...] = ()
    end_slope_local: np.ndarray | None = field(default=None)
    sign_hint: str | None = None  # `io.sign_check.sign_hint`: Z'' may be stored with the opposite sign
    noise_floor: float = 0.01  # s = max(noise_estimate, noise_floor): the floor `zhit` was given

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def band_frequencies(self) -> tuple[tuple[float, ...], ...]:
        """For each of ``bad_bands``, the measured frequencies [Hz] of its flagged points, ascending
        (the band's edges lie halfway to the neighbours), as `KKResult.band_frequencies`."""
        order = np.argsort(self.frequency)
        return band_points(self.frequency[order], np.asarray(self.flagged, bool)[order])

    @property
    def measured_bands(self) -> tuple[tuple[float, float], ...]:
        """For each of ``bad_bands``, its lowest and highest flagged frequency [Hz], as measured:
        the range the report names (`KKResult.measured_bands`)."""
        return tuple((points[0], points[-1]) for points in self.band_frequencies if points)

    @property
    def conclusive(self) -> bool:
        """Whether there are enough frequencies (`kk.CONCLUSIVE_POINTS_MIN`, and
        `CONCLUSIVE_PER_DECADE_MIN` a decade) for the verdict to mean something."""
        n = self.frequency.size
        decades = math.log10(self.frequency.max() / self.frequency.min()) if n > 1 else 0.0
        return n >= CONCLUSIVE_POINTS_MIN and n - 1 >= CONCLUSIVE_PER_DECADE_MIN * decades

    def to_xarray(self) -> xr.Dataset:
        """The data ``Z``, |Z| reconstructed from the phase (``modulus_zhit``), the residuals
        (|Z| − |Z|_ZHIT)/|Z| (data minus reconstruction), flags over ``frequency``; bad bands over ``band``; rms_rel, the
        noise estimate and the verdict as scalars; thresholds in attrs (``impedax_kind``
        "zhit"; written by `impedax.write_result`, read back by `impedax.io.read_netcdf`)."""
        end_local = self.end_slope_local if self.end_slope_local is not None else np.zeros(self.frequency.size, bool)
        return result_dataset(xr.Dataset(
            {
                "Z": ("frequency", self.impedance, {"units": "ohm"}),
                "modulus_zhit": ("frequency", self.modulus, {"units": "ohm", "long_name": "|Z| reconstructed from the phase"}),
                "residuals": ("frequency", self.residuals, {"units": "1", "long_name": "(|Z| - |Z|_ZHIT)/|Z|"}),
                "flagged": ("frequency", self.flagged),
                "end_slope_local": ("frequency", end_local, {"long_name": "end point reconstructed with the local-cubic phase slope"}),
                "bad_band_f_min": ("band", np.array([b[0] for b in self.bad_bands], float), {"units": "Hz"}),
                "bad_band_f_max": ("band", np.array([b[1] for b in self.bad_bands], float), {"units": "Hz"}),
                "rms_rel": ((), self.rms_rel, {"units": "1"}),
                "noise_estimate": ((), self.noise_estimate, {"units": "1"}),
                "valid": ((), self.valid),
                "conclusive": ((), self.conclusive),
            },
            coords={"frequency": ("frequency", self.frequency, {"units": "Hz"})},
            attrs={"impedax_kind": "zhit", "method": "Z-HIT, first order (Ehm et al. 2000), smoothing-spline phase", "offset_ln_ohm": self.offset,
                   "point_threshold": self.threshold, "run_threshold": self.run_threshold, "run_length": self.run_length},
        ).copy(deep=True))

    def summary(self) -> dict:
        """The JSON of ``impedax kk --method zhit --json`` (the keys are the public contract;
        fractions of |Z| unless the key names a unit)."""
        end_local = self.end_slope_local if self.end_slope_local is not None else np.zeros(self.frequency.size, bool)
        return {
            "method": "zhit", "valid": self.valid, "conclusive": self.conclusive, "rms_rel": self.rms_rel,
            "bad_bands": [[lo, hi] for lo, hi in self.bad_bands], "bad_bands_hz": [[lo, hi] for lo, hi in self.bad_bands],
            "bad_band_rules": [list(r) for r in self.band_rules],
            "noise_estimate": self.noise_estimate, "noise_estimate_rel": self.noise_estimate, "point_threshold_rel": self.threshold, "run_threshold_rel": self.run_threshold, "run_length": self.run_length,
            "frequency_hz": self.frequency, "modulus_zhit_ohm": self.modulus, "residuals_modulus": self.residuals,
            "end_slope_local_hz": np.sort(self.frequency[end_local]), "sign_hint": self.sign_hint,
            "notes": self.notes, "warnings": self.notes + ([self.sign_hint] if self.sign_hint else []),  # (as the linear test's)
            # s = max(noise estimate, floor), what the rules' levels are multiples of
            "noise_floor_rel": self.noise_floor, "threshold_scale_rel": max(self.noise_estimate, self.noise_floor),
            # (as the linear test's) per band its flagged measured frequencies, and
            # their lowest and highest: the range the text names (``bad_bands_hz`` keep the edges)
            "bad_band_frequencies_hz": [list(f) for f in self.band_frequencies], "measured_bands_hz": [[lo, hi] for lo, hi in self.measured_bands],
            "non_passive_hz": self.non_passive_frequencies,  # (as the linear test's: points with Re Z < 0)
        }

    def to_table(self) -> list[dict[str, object]]:
        """One row per frequency, in the data's order (``impedax kk --method zhit --out
        FILE.csv``): ``frequency_hz``, ``z_abs_ohm`` (|Z| measured),
        ``modulus_zhit_ohm`` (reconstructed from the phase), ``residual_modulus`` and ``flagged``."""
        return [
            {"frequency_hz": float(f), "z_abs_ohm": float(abs(z)), "modulus_zhit_ohm": float(m), "residual_modulus": float(r), "flagged": bool(flag)}
            for f, z, m, r, flag in zip(self.frequency, self.impedance, self.modulus, self.residuals, self.flagged)
        ]

    @property
    def notes(self) -> list[str]:
        """The caveats on the verdict (the JSON's ``notes`` and ``warnings``, as
        `KKResult.notes`): too few frequencies for Z-HIT (`conclusive`), points with Re Z < 0
        (`non_passive_note`)."""
        notes = [] if self.conclusive else [
            f"inconclusive: {self.frequency.size} frequencies are too few for Z-HIT (it needs {CONCLUSIVE_POINTS_MIN}, and {CONCLUSIVE_PER_DECADE_MIN:g} a decade)"]
        return notes + ([self.non_passive_note] if self.non_passive_note else [])

    @property
    def non_passive_frequencies(self) -> np.ndarray:
        """The frequencies [Hz] of the points whose Re Z < 0 beyond the noise (`statistics.non_passive`
        against the noise estimate × |Z|), ascending: no passive circuit reaches them, and their phase
        lies beyond −90°, which Z-HIT's integral carries into |Z| (REAL PowerSuite: 1.12 MHz and
        2 MHz, behind most of its rms_rel of 119 %)."""
        noise = self.noise_estimate * np.abs(self.impedance) if math.isfinite(self.noise_estimate) else None
        return np.sort(self.frequency[non_passive(self.impedance, noise=noise)])

    @property
    def non_passive_note(self) -> str | None:
        """On points with Re Z < 0 (`non_passive_frequencies`), as the linear test's
        `KKResult.non_passive_note`; None when there are none."""
        bad = self.non_passive_frequencies
        if not bad.size:
            return None
        where = ", ".join(format_frequency(f) for f in bad[:6]) + (", …" if bad.size > 6 else "")
        noise_from = ZHIT_RESIDUAL_NOISE if math.isfinite(self.noise_estimate) else None
        return (f"{bad.size} of {self.frequency.size} points have {non_passive_words(noise_from, self.frequency.size)} ({where}), which no passive circuit reaches; "
                "they are part of this test (impedax diagnose and refine leave them out before theirs); " + NON_PASSIVE_LEAVE_OUT)

    @property
    def rules_text(self) -> str:
        """The rules' levels and the scale s they rest on, naming the floor when it, not the
        noise estimate, sets s (the reconstruction's own error at sharp corners: `zhit`)."""
        scale = max(self.noise_estimate, self.noise_floor)
        why = (f"the {self.noise_floor * 100:.3g} % floor (noise_floor: Z-HIT's own approximation error, up to ≈ 1–1.5 % at ideal R‖C corners), "
               f"above the noise estimate" if self.noise_floor >= self.noise_estimate else "the noise estimate")
        return (f"rules (on |residual| = (|Z| − |Z| from the phase)/|Z|, s = {scale * 100:.3g} %, {why}): point |residual| > {self.point_multiple:.3g} s = {self.threshold * 100:.3g} %; "
                f"run of ≥ {self.run_length} with |residual| > {self.run_threshold / scale:.3g} s = {self.run_threshold * 100:.3g} %")

    @property
    def point_multiple(self) -> float:
        """The point rule's multiple of s (5, raised beyond `REFERENCE_POINTS` frequencies)."""
        return self.threshold / max(self.noise_estimate, self.noise_floor)

    def report(self) -> str:
        """rms_rel, noise estimate, verdict, the rules' levels and their scale, the bad bands with
        the rule that flagged each."""
        verdict = "valid (|Z| and phase consistent)" if self.valid else "NOT valid: |Z| and phase disagree"
        if not self.conclusive:
            verdict = (f"inconclusive: {self.frequency.size} frequencies are too few for Z-HIT (it needs {CONCLUSIVE_POINTS_MIN}, "
                       f"and {CONCLUSIVE_PER_DECADE_MIN:g} a decade)") + ("" if self.valid else "; it flags the bands below")
        lines = [f"Z-HIT: rms_rel = {self.rms_rel * 100:.3g} %, noise estimate = {self.noise_estimate * 100:.3g} %", f"verdict: {verdict}", self.rules_text]
        order = np.argsort(self.frequency)
        masks = _rule_masks(np.abs(self.residuals[order]), self.threshold, self.run_threshold, self.run_length)
        flag = np.asarray(self.flagged, bool)[order]
        lines += bad_band_lines(self.band_frequencies, band_rule_counts(flag, masks, self.frequency[order]), {  # (as the linear test writes them)
            "point": f"with |residual| > {self.threshold * 100:.3g} % (point rule)", "run": f"in runs of ≥ {self.run_length} with |residual| > {self.run_threshold * 100:.3g} % (run rule)"})
        lines += note_and_hint_lines(self.non_passive_note, self.sign_hint)
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        """In a notebook: rms_rel, the noise estimate, the verdict and the bad bands (the report's numbers)."""
        from ..plotting.html import result_html

        rows = [{"quantity": k, "value": v} for k, v in (("rms_rel [%]", f"{self.rms_rel * 100:.3g}"), ("noise estimate [%]", f"{self.noise_estimate * 100:.3g}"),
                                                         ("valid", bool(self.valid)), ("conclusive", bool(self.conclusive)))]
        rows += [{"quantity": "bad band", "value": band_name(points)} for points in self.band_frequencies]
        return result_html("Z-HIT (|Z| from the phase)", rows, lines=[*(f"note: {n}" for n in self.notes), *([f"hint: {self.sign_hint}"] if self.sign_hint else [])])

    def plot(self, *, title: str | None = None):
        """|Z| measured vs reconstructed, phase, and the residual with both rules' levels and the
        bad bands (`plotting.drt.plot_zhit`, `plotting.kk.add_rule_levels`)."""
        from ..plotting.drt import plot_zhit
        from ..plotting.kk import add_rule_levels

        fig = plot_zhit(self, title=title)
        add_rule_levels(fig.axes[2], point=self.threshold, run=self.run_threshold, run_length=self.run_length,
                        bands=self.bad_bands, band_rules=self.band_rules, signed=True)
        return fig



BATCH_RESULT_NAMES = frozenset({
    "frequency", "band", "Z", "modulus_zhit", "residuals", "flagged", "end_slope_local", "bad_band_f_min", "bad_band_f_max",
    "rms_rel", "noise_estimate", "valid", "conclusive", "point_threshold", "run_threshold",
})
"""The variables and dimensions of `ZHITBatchResult.to_xarray`: no batch dimension may have one of these names."""


@dataclass(frozen=True, eq=False)
class ZHITBatchResult(ValidityGrid):
    """Z-HIT of every spectrum of a Dataset with extra dimensions (cycle, trial, ...), as
    `kk.KKBatchResult` holds the linear test's: one `ZHITResult` per spectrum in C order over
    ``dims``; ``batch[i, j]`` (integer positions) gives one, ``valid`` and ``rms_rel`` are arrays
    over ``dims``."""

    results: tuple[ZHITResult, ...]

    def __repr__(self) -> str:
        few, consistent = self._verdict_counts()
        inconclusive = f", {few} inconclusive" if few else ""
        return (f"ZHITBatchResult({counted(len(self.results), 'spectrum', 'spectra')} over {', '.join(self.dims)}: "
                f"{consistent} valid, {len(self.results) - few - consistent} not{inconclusive})")

    __str__ = report_text

    def summary(self) -> dict:
        """The JSON of ``impedax kk --method zhit --json`` for several spectra, as the linear
        test's (`KKBatchResult.summary`): ``method`` ("zhit"), ``dims``, ``sizes``, ``n_spectra``,
        ``n_valid`` (inconclusive spectra count as valid), ``n_conclusive``, ``n_inconclusive``,
        ``spectra`` (each spectrum's ``labels``, then the keys of `ZHITResult.summary`) and
        ``warnings`` (the spectra's, each once)."""
        few, _ = self._verdict_counts()
        spectra = [{"labels": where, **r.summary()} for where, r in zip(self.labels(), self.results)]
        return {"method": "zhit", "dims": list(self.dims), "sizes": dict(zip(self.dims, map(int, self.shape))), "n_spectra": len(self.results),
                "n_valid": sum(bool(r.valid) for r in self.results), "n_conclusive": len(self.results) - few, "n_inconclusive": few, "spectra": spectra,
                "warnings": sorted({w for row in spectra for w in row["warnings"]})}

    def to_xarray(self) -> xr.Dataset:
        """Each spectrum's `ZHITResult.to_xarray()` stacked over ``dims`` (bad bands padded with
        NaN; ``residuals`` = (|Z| − modulus_zhit)/|Z|, data minus reconstruction), with each spectrum's rule levels as variables (``point_threshold``, ``run_threshold``:
        fractions of |Z|, as its own scale s sets them)."""
        dims = self.dims
        n_band = max(len(r.bad_bands) for r in self.results)
        stack = self._stacked

        per_freq = (*dims, "frequency")
        first = self.results[0]
        ds = xr.Dataset(
            {
                "Z": (per_freq, stack(lambda r: r.impedance, dtype=complex), {"units": "ohm"}),
                "modulus_zhit": (per_freq, stack(lambda r: r.modulus), {"units": "ohm", "long_name": "|Z| reconstructed from the phase"}),
                "residuals": (per_freq, stack(lambda r: r.residuals), {"units": "1", "long_name": "(|Z| - |Z|_ZHIT)/|Z|"}),
                "flagged": (per_freq, stack(lambda r: r.flagged, dtype=bool)),
                "end_slope_local": (per_freq, stack(lambda r: r.end_slope_local if r.end_slope_local is not None else np.zeros(r.frequency.size, bool), dtype=bool),
                                    {"long_name": "end point reconstructed with the local-cubic phase slope"}),
                **self._band_variables(n_band),
                **self._verdict_variables(),
                "point_threshold": (dims, self.per_spectrum("threshold"), {"units": "1"}),
                "run_threshold": (dims, self.per_spectrum("run_threshold"), {"units": "1"}),
            },
            coords=self._coordinates(),
            attrs={"impedax_kind": "zhit", "method": first.to_xarray().attrs["method"], "run_length": first.run_length, "noise_floor": first.noise_floor},
        )
        return result_dataset(ds.copy(deep=True))

    def _repr_html_(self) -> str:
        """In a notebook: the verdict counts and a row per spectrum (its labels, verdict, rms_rel,
        noise estimate and bad bands), as the report's table."""
        from ..plotting.html import result_html

        rows, left_out = self._html_table()
        return result_html("Z-HIT", rows, lines=[self.report().splitlines()[0], *left_out])

    def plot(self, *, title: str | None = None):
        """Every spectrum's |residual| as a map over the spectra and frequency, the flagged
        points circled, and each spectrum's rms_rel and noise estimate below
        (`plotting.kk.plot_validity_batch`; ``impedax kk FILE --method zhit --plot`` on a file
        of several spectra). Returns a matplotlib Figure."""
        from ..plotting.kk import plot_validity_batch

        few, consistent = self._verdict_counts()
        return plot_validity_batch(self, [np.abs(r.residuals) for r in self.results], residual="||Z| − |Z|_ZHIT|/|Z|", title=title or (
            f"Z-HIT of {counted(len(self.results), 'spectrum', 'spectra')} over {', '.join(self.dims)}: {consistent} valid, {len(self.results) - few - consistent} not"
            + (f", {few} inconclusive" if few else "")))

    def report(self, data_path: str | None = None) -> str:
        """Z-HIT of every spectrum, one line each (verdict, rms_rel, noise estimate, bad bands with
        the rules that flagged them), the rules once, the spectra with points Re Z < 0 and the
        first sign hint, and, when a spectrum failed, a ``next:`` line: ``impedax kk DATA_PATH
        --method zhit --select …`` shows the first failing one alone (``data_path``: the file
        the run read; "-" or None: save the data to a file first)."""
        few, consistent = self._verdict_counts()
        lines = [f"Z-HIT of {counted(len(self.results), 'spectrum', 'spectra')} over {', '.join(self.dims)}: {consistent} valid (|Z| and phase consistent), "
                 f"{len(self.results) - few - consistent} not" + (f", {few} inconclusive (too few frequencies to tell)" if few else "")]
        names = self._spectrum_names()
        lines += self._table_lines(names)
        if any(r.bad_bands for r in self.results):
            r0 = self.results[0]
            lines.append(f"rules: point = one |residual| > {r0.point_multiple:.3g} s, run = ≥ {r0.run_length} consecutive |residual| > {r0.run_threshold / max(r0.noise_estimate, r0.noise_floor):.3g} s "
                         f"(residual = (|Z| − |Z| from the phase)/|Z|; s: each spectrum's noise estimate, at least the {r0.noise_floor * 100:.3g} % floor of Z-HIT's own error; the levels: impedax kk --method zhit --select)")
        lines += self._non_passive_lines(names) + self._hint_lines(names)
        failure = self._first_failure(data_path)
        if failure:
            n_failed, name, path, selects, save = failure
            lines.append(f"next: impedax kk {path} --method zhit {selects} --plot FIG.png shows {name} alone ({n_failed} of {len(self.results)} not valid){save}")
        return "\n".join(lines)


def _rule_masks(magnitude, threshold, run_threshold, run_length) -> dict[str, np.ndarray]:
    """Each rule's flags from |residual| in frequency order: above ``threshold`` at one point, or
    above ``run_threshold`` at ``run_length`` consecutive points."""
    return {"point": magnitude > threshold, "run": long_runs(magnitude > run_threshold, int(run_length))}

def _local_slopes(x: np.ndarray, phase: np.ndarray, at: np.ndarray, weights: np.ndarray | None = None) -> np.ndarray:
    """dφ/dx at each of ``at`` from a tricube-weighted cubic through the phase within
    `END_REACH` of it (at least its 5 nearest points); ``weights``: each point's count when the
    phase is binned (`_binned`)."""
    out = np.empty(at.size)
    for i, a in enumerate(at):
        d = x - a
        near = np.abs(d) <= END_REACH
        if near.sum() < _END_DEGREE + 2:
            near = np.zeros(x.size, bool)
            near[np.argsort(np.abs(d))[: _END_DEGREE + 2]] = True
        u = np.abs(d[near]) / (np.abs(d[near]).max() * (1 + 1e-9))
        root_w = (1 - u**3) ** 1.5
        if weights is not None:
            root_w = root_w * np.sqrt(weights[near])
        design = np.vander(d[near], _END_DEGREE + 1, increasing=True)
        out[i] = np.linalg.lstsq(design * root_w[:, None], phase[near] * root_w, rcond=None)[0][1]
    return out


def _binned(x: np.ndarray, phase: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Means of x and of the phase over bins 1/`BIN_PER_DECADE` decade wide (x sorted), and each
    bin's count: the weights of the smoothing spline's sum of squares (`BIN_PER_DECADE`)."""
    index = np.floor((x - x[0]) / (math.log(10.0) / BIN_PER_DECADE)).astype(np.int64)
    starts = np.flatnonzero(np.diff(index, prepend=index[0] - 1))
    counts = np.diff(np.append(starts, x.size)).astype(float)
    return np.add.reduceat(x, starts) / counts, np.add.reduceat(phase, starts) / counts, counts


def _end_slopes(x: np.ndarray, phase: np.ndarray, ends: np.ndarray, binned) -> np.ndarray:
    """The local cubic's slope (`_local_slopes`) at the points ``ends`` of x; from the binned phase
    (``binned``: `_binned`'s output, or None) at the bin means near either end and at the two end
    points, interpolated linearly in between (the slope of a 0.65-decade cubic barely changes
    over a bin of 0.01 decade): one fit a bin instead of one a point over 0.65 decade."""
    if binned is None:
        return _local_slopes(x, phase, x[ends])
    xb, phase_b, counts = binned
    margin = END_LAYER + 2 * math.log(10.0) / BIN_PER_DECADE
    nodes = np.unique(np.concatenate([[x[0], x[-1]], xb[(xb - x[0] < margin) | (x[-1] - xb < margin)]]))
    return np.interp(x[ends], nodes, _local_slopes(xb, phase_b, nodes, counts))


@checked_arguments(noise_floor=real(positive=True), point=real(positive=True), run=real(positive=True), run_length=count(1, 10_000))
def zhit(data, *, noise_floor: float = 0.01, point: float = 5.0, run: float = 3.0, run_length: int = 3) -> ZHITResult:
    """Z-HIT reconstruction of |Z| from the phase of one spectrum (see the module docstring).

    ``data``: a spectrum Dataset with only the ``frequency`` dimension, a file path, or a
    (frequency, Z) pair. A point is bad when |residual| > ``point`` × s, and every point of a run
    of ≥ ``run_length`` with |residual| > ``run`` × s, where s = max(noise estimate,
    ``noise_floor``) (the floor covers the first-order approximation error itself: on exact spectra
    up to ≈ 1–1.5 % at ideal R‖C corners and on a Randles circuit, less on R‖CPE and HN); bad
    points form bands as the linear test's (`kk.bands_of_flags`: runs, joined when less than
    0.05 decade apart). On more
    than `REFERENCE_POINTS` frequencies ``point`` and ``run`` are raised: t² by 2 ln(N/61), and by
    (2/``run_length``) ln(N/61) for runs (``result.threshold`` and ``run_threshold`` hold the levels applied).
    Raises DataError/ParameterError on bad input.
    """
    for name, value in (("noise_floor", noise_floor), ("point", point), ("run", run)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ParameterError(f"{name} must be a positive number, got {value!r}")
    if not isinstance(run_length, (int, np.integer)) or run_length < 1:
        raise ParameterError(f"run_length must be a positive integer, got {run_length!r}")
    freq, z, dims, _, source = frequency_and_z(data)
    if dims:
        raise DataError(f"zhit takes one spectrum; these data have extra dimensions {dims}: use impedax.zhit_batch(data) for one test per spectrum (as kk_test_batch), or select one first (data.isel({dims[0]}=0), data.sel({dims[0]}=label)) or average them", path=source)
    options = dict(noise_floor=noise_floor, point=point, run=run, run_length=run_length)
    return _checked_zhit(freq, z, source, data.attrs if isinstance(data, xr.Dataset) else None, options)


@checked_arguments(noise_floor=real(positive=True), point=real(positive=True), run=real(positive=True), run_length=count(1, 10_000))
def zhit_batch(data, *, noise_floor: float = 0.01, point: float = 5.0, run: float = 3.0, run_length: int = 3) -> ZHITBatchResult:
    """`zhit` of every spectrum of a Dataset (or file) with extra dimensions (cycle, trial, ...),
    with `zhit`'s options, each spectrum judged by its own noise estimate; a `ZHITBatchResult`.
    A batch dimension named as a variable or dimension of its Dataset (`BATCH_RESULT_NAMES`) is
    a `DataError` before any test; data of one spectrum give a grid of one."""
    freq, z, dims, coords, source = frequency_and_z(data)
    refuse_result_names(dims, BATCH_RESULT_NAMES, "a Z-HIT batch result", source=source)
    attrs = data.attrs if isinstance(data, xr.Dataset) else None
    options = dict(noise_floor=float(noise_floor), point=float(point), run=float(run), run_length=int(run_length))
    shape = z.shape[:-1]
    results = []
    for index in np.ndindex(*shape):
        where = ", ".join(f"{d}={label_value(coords[d][i]) if d in coords else i}" for d, i in zip(dims, index))
        results.append(_checked_zhit(freq, z[index], source, attrs, options, where=f"spectrum {where}: " if where else ""))
    return ZHITBatchResult(dims=tuple(dims), shape=tuple(shape), coords=coords, results=tuple(results))


def _checked_zhit(freq: np.ndarray, z: np.ndarray, source, attrs, options: dict, where: str = "") -> ZHITResult:
    """`zhit` of one spectrum's frequencies [Hz] and impedances [Ω] with ``options`` checked:
    enough points, no zero |Z| (a `DataError` naming ``source`` and, in a batch, ``where``: the
    spectrum's labels); the sign hint from the data's ``attrs``."""
    if freq.size < 6:
        raise DataError(f"Z-HIT needs at least 6 frequencies, got {freq.size}", path=source)
    if np.any(np.abs(z) == 0):
        raise DataError(f"{where}{zero_impedance_text(freq, z)}; ln|Z| is undefined there", path=source)
    from ..io.sign_check import sign_hint

    def test(f, values):
        return _zhit(f, values, **options)

    result = test(freq, z)
    return dataclasses.replace(result, sign_hint=sign_hint(result, test, "Z-HIT", attrs))


def _zhit(freq, z, *, noise_floor: float, point: float, run: float, run_length: int) -> ZHITResult:
    """`zhit` of checked frequencies and impedances."""
    from scipy.interpolate import make_smoothing_spline

    order = np.argsort(freq)
    x = np.log(2 * np.pi * freq[order])
    phase = np.unwrap(np.angle(z[order]))
    decades = (x[-1] - x[0]) / math.log(10.0)
    smoothing = 0.01 * x.size / max(decades, 1e-12)  # 0.1 at 10 points per decade
    binned = _binned(x, phase) if x.size > BIN_PER_DECADE * decades else None
    if binned is not None and binned[0].size < _BINS_MIN:  # (a band narrower than 0.1 decade: few points to fit, no need)
        binned = None
    if binned is None:
        spline = make_smoothing_spline(x, phase, lam=smoothing)
    else:  # Σ n_b (φ̄_b − s(x̄_b))²: the same sum of squares (and λ) to within the phase's bend over a bin
        spline = make_smoothing_spline(binned[0], binned[1], w=binned[2], lam=smoothing)
    integral = spline.antiderivative()(x)
    slope = spline.derivative()(x)
    shape = (2.0 / math.pi) * (integral - integral[0]) + _GAMMA_1 * slope
    measured = np.abs(z[order])
    offset = float(np.median(np.log(measured) - shape))
    residual_sorted = (measured - np.exp(offset + shape)) / measured
    noise = difference_noise(np.diff(residual_sorted))  # (before the end points' choice: it only lowers |residual|)
    # the end points' one-sided slope: keep the local cubic's where it is nearer the data
    ends = (x - x[0] < END_LAYER) | (x[-1] - x < END_LAYER)
    local_shape = shape[ends] + _GAMMA_1 * (_end_slopes(x, phase, ends, binned) - slope[ends])
    local_residual = (measured[ends] - np.exp(offset + local_shape)) / measured[ends]
    nearer = np.abs(local_residual) < np.abs(residual_sorted[ends])
    end_local = np.zeros(x.size, bool)
    end_local[np.flatnonzero(ends)[nearer]] = True
    shape[end_local] = local_shape[nearer]
    residual_sorted[end_local] = local_residual[nearer]
    modulus_sorted = np.exp(offset + shape)
    scale = max(noise, noise_floor)
    rules = thresholds_for({"point": point, "run": run, "run_length": run_length, "reference_points": REFERENCE_POINTS}, x.size)
    point, run = rules["point"], rules["run"]
    m = np.abs(residual_sorted)
    masks = _rule_masks(m, point * scale, run * scale, run_length)
    flag = masks["point"] | masks["run"]
    bands = bands_of_flags(freq[order], flag)
    modulus = np.empty_like(modulus_sorted)
    modulus[order] = modulus_sorted
    residual = np.empty_like(residual_sorted)
    residual[order] = residual_sorted
    flagged = np.empty_like(flag)
    flagged[order] = flag
    local = np.empty_like(end_local)
    local[order] = end_local
    return ZHITResult(
        frequency=freq.copy(), impedance=z.copy(), modulus=modulus, residuals=residual,
        rms_rel=float(np.sqrt(np.mean(residual**2))), noise_estimate=noise, threshold=point * scale,
        flagged=flagged, bad_bands=bands, valid=not bands, offset=offset, run_threshold=run * scale, run_length=int(run_length),
        band_rules=band_rules(flag, masks, freq[order]), end_slope_local=local, noise_floor=float(noise_floor),
    )
