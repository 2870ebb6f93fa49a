"""Diagnosis of a fit: where the model fails, which physical effect is missing, and a
refinement loop that adds effects until the residuals are noise (docs/diagnosis.md).

1. Noise level σ (relative, per component): from the data's ``sigma`` (trial scatter) when
   present, else from the Kramers–Kronig residuals (`kk_test`), floored at `NOISE_FLOOR`.
2. Failing bands: runs of one sign in Re or Im of the relative residual whose normalised sum
   of squares Σ(r/σ)² exceeds the χ² quantile 1 − `RUN_P` for the run length (≥ 3 points);
   each is described in words (data vs model: resistive/capacitive/inductive, phase, slope).
3. Candidates: every effect of the catalog (`impedax.fitting.diagnosis.effects`) proposes augmented
   circuits, fitted together warm-started through `fit_candidates` (one compilation) and
   ranked by ΔAIC; a candidate with more parameters outranks a simpler one only when it
   lowers AIC by more than `DELTA_AIC_MIN` (the same rule as the verdict).
4. Verdict: ``data_invalid`` when the KK test fails badly, ``missing_effect`` when a candidate is
   significant (ΔAIC < −`DELTA_AIC_MIN` and it explains at least `NOISE_FRACTION_MIN` of the
   noise variance) or the residuals are structured beyond the noise with nothing to fix them,
   ``adequate`` otherwise. Only significant candidates are listed as suggestions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np
import xarray as xr

from ...circuits import Circuit, DEFAULT_REGISTRY
from ...data import make_spectrum, validate_spectrum
from ...errors import DataError, FitError, ImpedaxError, ParameterError
from .effects import DEFAULT_EFFECTS, BaselineContext, EffectCatalog, Proposal, format_frequency
from ..least_squares.single import FitResult
from ..least_squares.candidates import fit_candidates

__all__ = [
    "Diagnosis", "Suggestion", "FailingBand", "Refinement", "RefinementStep", "diagnose", "refine", "failing_bands",
    "DELTA_AIC_MIN", "NOISE_FRACTION_MIN", "NOISE_RATIO_MAX", "RUN_P", "NOISE_FLOOR", "KK_INVALID_FRACTION",
]

# --- documented thresholds (docs/diagnosis.md) ---
DELTA_AIC_MIN = 10.0
"""A candidate must lower AIC by more than this (Burnham & Anderson: ΔAIC > 10 ⇒ essentially no
support for the worse model)."""
NOISE_FRACTION_MIN = 0.25
"""... and lower the mean squared relative residual by at least this fraction of the noise
variance 2σ² (so a large N cannot make a negligible improvement 'significant')."""
NOISE_RATIO_MAX = 1.5
"""rms_rel/(√2 σ) above this with failing bands ⇒ the residuals are not noise."""
RUN_P = 1e-3
"""False-alarm probability of one run of one sign (χ² test of the run against the noise)."""
NOISE_FLOOR = 1e-3
"""Relative noise floor (0.1 %): below this, misfits are instrument accuracy, not physics."""
KK_INVALID_FRACTION = 0.2
"""The KK test 'fails badly' when it flags at least this fraction of the points (or the KK
residuals exceed 3× the noise floor of 2 % at a minimum)."""
KK_INVALID_RMS = 0.02
BASELINE_STEPS = 300
"""Levenberg–Marquardt step limit of the baseline's cold starts (warm candidates: ``max_steps``)."""


@dataclass(frozen=True)
class FailingBand:
    """A frequency band [Hz] where the residuals are structured, with a description."""

    f_min: float
    f_max: float
    pattern: str
    components: tuple[str, ...]
    score: float  # Σ(r/σ)² over the band divided by its point count
    data_problem: bool = False  # inside a band the KK test flags as not KK-consistent

    def as_json(self) -> dict:
        return {"f_min": self.f_min, "f_max": self.f_max, "pattern": self.pattern, "components": list(self.components), "data_problem": self.data_problem}


@dataclass(frozen=True, eq=False)
class Suggestion:
    """A candidate circuit (one effect at one placement) and its fit."""

    effect: str
    added: str
    where: str
    fit: FitResult
    delta_aic: float
    delta_bic: float
    significant: bool
    explanation: str
    fixed_bands: tuple[tuple[float, float], ...] = ()

    @property
    def model(self) -> str:
        return self.fit.model

    @property
    def rms_rel(self) -> float:
        return self.fit.rms_rel

    @property
    def aic(self) -> float:
        return self.fit.aic

    def as_json(self) -> dict:
        return {
            "effect": self.effect, "model": self.model, "rms_rel": self.rms_rel, "aic": self.aic, "delta_aic": self.delta_aic,
            "delta_bic": self.delta_bic, "explanation": self.explanation, "added": self.added, "where": self.where,
            "significant": self.significant, "bic": self.fit.bic, "chi2_red": self.fit.chi2_red,
            "fixed_bands": [list(b) for b in self.fixed_bands],
        }


@dataclass(frozen=True, eq=False)
class Diagnosis:
    """Outcome of `diagnose`: the baseline fit, KK test, noise, failing bands, ranked
    candidates (``suggestions``: the significant ones, best first; ``candidates``: all) and the
    ``verdict`` (``adequate``, ``missing_effect`` or ``data_invalid``) with its ``reason``."""

    baseline: FitResult
    kk: object | None
    noise: np.ndarray
    noise_source: str
    failing_bands: tuple[FailingBand, ...]
    candidates: tuple[Suggestion, ...]
    verdict: str
    reason: str
    notes: tuple[str, ...] = ()
    thresholds: Mapping[str, float] = field(default_factory=dict)

    @property
    def suggestions(self) -> tuple[Suggestion, ...]:
        return tuple(s for s in self.candidates if s.significant) if self.verdict == "missing_effect" else ()

    @property
    def best(self) -> Suggestion | None:
        return self.suggestions[0] if self.suggestions else None

    @property
    def noise_level(self) -> float:
        """Median relative noise σ per component."""
        return float(np.median(self.noise))

    @property
    def noise_ratio(self) -> float:
        """rms_rel / (√2 σ): ≈ 1 when the residuals are noise."""
        return _noise_ratio(self.baseline, self.noise)

    def summary(self) -> dict:
        """The JSON of ``impedax diagnose --json`` (keys fixed by the issue; extra keys added)."""
        b = self.baseline
        kk = self.kk
        return {
            "model": b.model,
            "baseline": {"rms_rel": b.rms_rel, "chi2_red": b.chi2_red, "aic": b.aic, "bic": b.bic, "n_points": b.n_points, "n_params": b.n_params},
            "kk": {
                "valid": bool(kk.valid) if kk is not None else None,
                "rms_rel": float(kk.rms_rel) if kk is not None else None,
                "bad_bands": [[float(lo), float(hi)] for lo, hi in kk.bad_bands] if kk is not None else [],
                "noise_estimate": float(kk.noise_estimate) if kk is not None else None,
            },
            "noise": {"level": self.noise_level, "source": self.noise_source, "ratio": self.noise_ratio},
            "failing_bands": [band.as_json() for band in self.failing_bands],
            "verdict": self.verdict,
            "reason": self.reason,
            "suggestions": [s.as_json() for s in self.suggestions],
            "candidates": [{"effect": s.effect, "model": s.model, "rms_rel": s.rms_rel, "aic": s.aic, "delta_aic": s.delta_aic, "delta_bic": s.delta_bic, "significant": s.significant} for s in self.candidates],
            "thresholds": dict(self.thresholds),
            "notes": list(self.notes),
        }

    def report(self) -> str:
        """The diagnosis as a short story (the default text of ``impedax diagnose``)."""
        b = self.baseline
        lines = [f"model {b.model}: rms_rel {b.rms_rel * 100:.3g} %, chi2_red {b.chi2_red:.3g}, AIC {b.aic:.1f} ({b.n_points} points, {b.n_params} free parameters)"]
        if self.kk is not None:
            kk_text = "the data are Kramers–Kronig consistent" if self.kk.valid else "the data are NOT Kramers–Kronig consistent in " + ", ".join(f"{format_frequency(lo)}–{format_frequency(hi)}" for lo, hi in self.kk.bad_bands)
            lines.append(f"data: {kk_text} (KK rms_rel {self.kk.rms_rel * 100:.3g} %).")
        lines.append(f"noise: σ ≈ {self.noise_level * 100:.3g} % per component ({self.noise_source}); the residuals are {self.noise_ratio:.3g}× the noise.")
        if self.failing_bands:
            lines.append("where the model fails:")
            for band in self.failing_bands:
                tag = " [data problem: KK flags this band]" if band.data_problem else ""
                lines.append(f"  {format_frequency(band.f_min)} – {format_frequency(band.f_max)}: {band.pattern}{tag}")
        else:
            lines.append("the residuals show no structure beyond the noise.")
        lines.append(f"verdict: {self.verdict.upper()} — {self.reason}")
        if self.suggestions:
            lines.append("what is missing (best first):")
            for i, s in enumerate(self.suggestions[:5], 1):
                lines.append(f"  {i}. [{s.effect}] {s.explanation}")
                lines.append(f"     model {s.model}   rms_rel {s.rms_rel * 100:.3g} %   ΔAIC {s.delta_aic:+.1f}   ΔBIC {s.delta_bic:+.1f}")
        elif self.candidates and self.verdict == "adequate":
            top = self.candidates[0]
            lines.append(f"no effect improves the fit significantly (best: {top.effect}, ΔAIC {top.delta_aic:+.1f}, rms_rel {top.rms_rel * 100:.3g} %).")
        for n in self.notes:
            lines.append(f"note: {n}")
        return "\n".join(lines)

    def plot(self, *, title: str | None = None):
        """Nyquist, Bode and residual panels of the baseline with the failing bands shaded and
        the best suggestion overlaid (matplotlib Figure)."""
        from ...plotting import plot_spectrum

        b = self.baseline
        bands = [(band.f_min, band.f_max) for band in self.failing_bands]
        fig = plot_spectrum((b.frequency, b.z_data), (b.frequency, b.z_model), title=title or f"{b.model}: {self.verdict} (rms_rel {b.rms_rel * 100:.3g} %)", bands=bands, model_label="baseline")
        best = self.best
        if best is not None:
            axes = fig.axes
            z = best.fit.z_model
            axes[0].plot(z.real, -z.imag, "-", color="tab:green", lw=1.2, label=f"+ {best.effect}")
            axes[1].loglog(b.frequency, np.abs(z), "-", color="tab:green", lw=1.2)
            axes[2].semilogx(b.frequency, np.degrees(np.angle(z)), "-", color="tab:green", lw=1.2)
            if len(axes) > 3:
                r = best.fit.residuals * 100
                axes[3].semilogx(b.frequency, np.abs(r), "-", color="tab:green", lw=1.0, label=f"|res| with {best.effect}")
                axes[3].legend(fontsize=8, ncol=3)
            axes[0].legend(fontsize=8)
        return fig

    def to_xarray(self) -> xr.Dataset:
        """Baseline spectra, residuals, noise and band mask over frequency; candidates over
        ``candidate``; verdict and thresholds in attrs."""
        b = self.baseline
        mask = np.zeros(b.frequency.size, bool)
        for band in self.failing_bands:
            mask |= (b.frequency >= band.f_min) & (b.frequency <= band.f_max)
        return xr.Dataset(
            {
                "Z": ("frequency", b.z_data, {"units": "ohm"}),
                "Z_model": ("frequency", b.z_model, {"units": "ohm"}),
                "residual_rel": ("frequency", b.residuals),
                "noise_rel": ("frequency", self.noise, {"long_name": "relative noise per component"}),
                "failing": ("frequency", mask),
                "candidate_model": ("candidate", [s.model for s in self.candidates]),
                "candidate_effect": ("candidate", [s.effect for s in self.candidates]),
                "rms_rel": ("candidate", [s.rms_rel for s in self.candidates]),
                "delta_aic": ("candidate", [s.delta_aic for s in self.candidates]),
                "delta_bic": ("candidate", [s.delta_bic for s in self.candidates]),
                "significant": ("candidate", [s.significant for s in self.candidates]),
            },
            coords={"frequency": ("frequency", b.frequency, {"units": "Hz"}), "candidate": np.arange(len(self.candidates))},
            attrs={"model": b.model, "verdict": self.verdict, "reason": self.reason, "noise_source": self.noise_source, "baseline_rms_rel": b.rms_rel, "baseline_aic": b.aic, **{f"threshold_{k}": v for k, v in self.thresholds.items()}},
        )


# --- noise and failing bands -----------------------------------------------------------------


def _noise_ratio(fit: FitResult, noise: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.abs(fit.residuals) ** 2 / (2 * noise**2))))


def _runs(sign: np.ndarray):
    """(start, stop) of maximal runs of equal sign."""
    start = 0
    for i in range(1, sign.size + 1):
        if i == sign.size or sign[i] != sign[start]:
            yield start, i
            start = i


def _structured_mask(e: np.ndarray, p: float = RUN_P, min_len: int = 3) -> np.ndarray:
    """Points in runs of one sign whose Σe² exceeds the χ²(L) quantile 1 − p (e sorted by f)."""
    from scipy import stats  # (imported here: scipy.stats costs half a second at import)

    out = np.zeros(e.size, bool)
    for i, j in _runs(np.sign(e)):
        length = j - i
        if length >= min_len and np.sum(e[i:j] ** 2) > stats.chi2.ppf(1 - p, length):
            # trim the run's tails where the misfit is below the noise: the band is where it shows
            a, b = i, j
            while a < b and abs(e[a]) < 1:
                a += 1
            while b > a and abs(e[b - 1]) < 1:
                b -= 1
            out[a:b] = True
    return out


def _edges(f_sorted: np.ndarray, i: int, j: int) -> tuple[float, float]:
    """Band edges halfway (in log f) to the neighbouring points, clipped to the data."""
    lo = f_sorted[i] if i == 0 else math.sqrt(f_sorted[i] * f_sorted[i - 1])
    hi = f_sorted[j - 1] if j == f_sorted.size else math.sqrt(f_sorted[j - 1] * f_sorted[j])
    return float(lo), float(hi)


def _slope(f, y):
    ok = np.isfinite(y) & (y > 0)
    if ok.sum() < 3 or np.log10(f[ok].max() / f[ok].min()) < 0.5:
        return math.nan
    return float(np.polyfit(np.log10(f[ok]), np.log10(y[ok]), 1)[0])


def _where(f, i, j, n) -> str:
    lo, hi = f[i], f[j - 1]
    if i == 0 and j < n:
        return f"below {format_frequency(math.sqrt(hi * f[j]))}"
    if j == n and i > 0:
        return f"above {format_frequency(math.sqrt(lo * f[i - 1]))}"
    if i == 0 and j == n:
        return "over the whole band"
    return f"between {format_frequency(lo)} and {format_frequency(hi)}"


def _describe(f, zd, zm, i, j, n) -> str:
    """Words for how the data differ from the model over sorted points i..j-1."""
    where = _where(f, i, j, n)
    d, m = zd[i:j], zm[i:j]
    ph_d, ph_m = np.degrees(np.angle(d)), np.degrees(np.angle(m))
    # a resistive-vs-capacitive sub-band at one end of the band is the clearest story
    for flip, text in (((np.abs(ph_d) < 30) & (np.abs(ph_m) > 50), "resistive"), ((np.abs(ph_m) < 30) & (np.abs(ph_d) > 50), "capacitive")):
        idx = np.flatnonzero(flip)
        if idx.size >= 2 and (idx[0] == 0 or idx[-1] == j - i - 1):
            a, b = i + idx[0], i + idx[-1] + 1
            sub = _where(f, a, b, n) if (a == 0 or b == n) else _where(f, a, b, n)
            other = "capacitive" if text == "resistive" else "resistive"
            rest = f"; over the rest of {format_frequency(f[i])}–{format_frequency(f[j - 1])} the phases differ by up to {np.max(np.abs(ph_d - ph_m)):.0f}°" if b - a < j - i else ""
            return f"{sub} the data are {text} (phase {np.mean(ph_d[a - i:b - i]):.0f}°) while the model is {other} ({np.mean(ph_m[a - i:b - i]):.0f}°){rest}"
    mag = float(np.mean(np.abs(d) / np.abs(m)) - 1) * 100
    if np.mean(d.imag > 0) >= 0.5 and np.mean(d.imag) > np.mean(m.imag) and np.mean(m.imag > 0) < 0.5:
        return f"positive Z'' {where} the model cannot make: the data turn inductive (phase up to {ph_d.max():+.0f}°)"
    pd, pm = float(np.mean(ph_d)), float(np.mean(ph_m))
    parts = []
    if abs(pd) < 30 and abs(pm) > 50:
        parts.append(f"{where} the data are resistive (phase {pd:.0f}°) while the model is capacitive ({pm:.0f}°)")
    elif abs(pm) < 30 and abs(pd) > 50:
        parts.append(f"{where} the data are capacitive (phase {pd:.0f}°) while the model is resistive ({pm:.0f}°)")
    elif abs(pd - pm) >= 2:
        kind = "more resistive" if abs(pd) < abs(pm) else "more capacitive"
        parts.append(f"{where} the data are {kind} than the model (phase {pd:.0f}° vs {pm:.0f}°)")
    else:
        parts.append(f"{where} the data and the model differ in magnitude at the same phase")
    if abs(mag) >= 1:
        parts.append(f"|Z| is {abs(mag):.2g} % {'above' if mag > 0 else 'below'} the model")
    sd, sm = _slope(f[i:j], -d.imag), _slope(f[i:j], -m.imag)
    if np.isfinite(sd) and np.isfinite(sm) and abs(sd - sm) > 0.15:
        parts.append(f"−Z'' falls as f^{sd:.2f} where the model's falls as f^{sm:.2f}")
    # a band that holds the model's −Z'' peak with a lower, wider data peak: a depressed arc
    k_m = int(np.argmax(-zm.imag))
    if i < k_m < j - 1 and -zm.imag[k_m] > 0 and np.max(-d.imag) < 0.98 * -zm.imag[k_m]:
        drop = (1 - np.max(-d.imag) / -zm.imag[k_m]) * 100
        return f"the model's arc is too symmetric: the data are depressed (peak −Z'' {drop:.2g} % lower, spread over a wider band) {where}; " + "; ".join(parts[1:] or parts)
    return "; ".join(parts)


def failing_bands(fit: FitResult, noise, *, kk_bad_bands: Sequence[tuple[float, float]] = (), p: float = RUN_P) -> tuple[FailingBand, ...]:
    """Bands where the residuals of ``fit`` are structured relative to ``noise`` (relative σ per
    component, scalar or per point): runs of one sign in Re or Im with Σ(r/σ)² above the
    χ²(L) quantile 1 − ``p``; gaps of one point are closed. Each band gets a description."""
    order = np.argsort(fit.frequency)
    f = fit.frequency[order]
    sigma = np.broadcast_to(np.asarray(noise, float), fit.frequency.shape)[order]
    r = fit.residuals[order]
    e_re, e_im = r.real / sigma, r.imag / sigma
    m_re, m_im = _structured_mask(e_re, p), _structured_mask(e_im, p)
    mask = m_re | m_im
    for k in range(1, mask.size - 1):  # close single-point gaps
        if not mask[k] and mask[k - 1] and mask[k + 1]:
            mask[k] = True
    bands = []
    zd, zm = fit.z_data[order], fit.z_model[order]
    for i, j in _runs(mask.astype(int)):
        if not mask[i]:
            continue
        lo, hi = _edges(f, i, j)
        comps = tuple(c for c, m in (("real", m_re), ("imag", m_im)) if m[i:j].any())
        score = float(np.mean(e_re[i:j] ** 2 + e_im[i:j] ** 2) / 2)
        data_problem = any(blo <= f[i] * 1.0001 and f[j - 1] <= bhi * 1.0001 for blo, bhi in kk_bad_bands)
        bands.append(FailingBand(lo, hi, _describe(f, zd, zm, i, j, f.size), comps, score, data_problem))
    return tuple(bands)


# --- diagnosis -------------------------------------------------------------------------------


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


def _explain(effect, p: Proposal, base: FitResult, cand: FitResult, d_aic: float, fixed) -> str:
    band_text = ""
    if fixed:
        band_text = " and removes the misfit " + ", ".join(f"{format_frequency(lo)}–{format_frequency(hi)}" for lo, hi in fixed)
    return (
        f"{effect.title}: {effect.physics}. Adding {p.added} {p.where} lowers rms_rel from {base.rms_rel * 100:.3g} % "
        f"to {cand.rms_rel * 100:.3g} % (ΔAIC {d_aic:+.1f}){band_text}."
    )


def _proposed_circuits(circuit: Circuit, z_data, freq, effects: EffectCatalog, registry) -> list[Circuit]:
    """The circuits the catalog proposes for ``circuit`` (they depend on its structure only)."""
    order = np.argsort(freq)
    ctx = BaselineContext(circuit, circuit.defaults(registry), freq[order], z_data[order], z_data[order] * (1 + 1e-3), registry)
    seen, out = {str(circuit)}, []
    for effect in effects:
        for p in effect.propose(circuit, ctx):
            if str(p.circuit) not in seen:
                seen.add(str(p.circuit))
                out.append(p.circuit)
    return out


def _shapes(circuits: Sequence[Circuit], registry):
    """(layout, candidate count, free-parameter count) of one compiled candidate solver."""
    from ...circuits import ProgramLayout
    from ..least_squares.candidates import _C_BUCKET, _K_BUCKETS, _bucket

    layout = ProgramLayout.covering(circuits, registry)
    n = -(-len(circuits) // _C_BUCKET) * _C_BUCKET
    k = _bucket(max(len(c.parameter_names(registry)) for c in circuits), _K_BUCKETS)
    return layout, n, k


def _covers(layout, circuits, registry) -> bool:
    from ...circuits import ProgramLayout

    need = ProgramLayout.covering(circuits, registry)
    return need.n_nodes <= layout.n_nodes and all(a <= b for a, b in zip(need.capacities, layout.capacities))


def _fit_baseline(data, circuit, effects, *, weighting, n_starts, seed):
    """Fit the user's circuit with the same compiled solver the candidates will use (every
    padded slot a copy of the circuit with its own random starts): one compilation in all."""
    from ...circuits import parse
    from ...io import load

    ds = load(data) if not isinstance(data, xr.Dataset) else data
    source = str(ds.attrs.get("source", data if isinstance(data, str) else "data"))
    validate_spectrum(ds, source=source)
    if any(d != "frequency" for d in ds["Z"].dims):
        raise DataError("diagnose takes one spectrum; select or average the extra dimensions (trial, session, ...) first", path=source)
    circuit = parse(circuit)
    freq = np.asarray(ds["frequency"].values, float)
    z = np.asarray(ds["Z"].values, complex)
    proposed = _proposed_circuits(circuit, z, freq, effects, DEFAULT_REGISTRY)
    shapes = _shapes([circuit] + proposed, DEFAULT_REGISTRY)
    copies = shapes[1]
    fits = fit_candidates(
        [circuit] * copies, ds, weighting=weighting, n_starts=n_starts, max_steps=BASELINE_STEPS, seeds=[seed + i for i in range(copies)],
        single_phase=True, layout=shapes[0], pad_to=shapes[1], k_pad=shapes[2],
    )
    best = min(fits, key=lambda r: r.chi2 if np.isfinite(r.chi2) else np.inf)
    return best, ds, shapes


def _rank(cands: list[Suggestion]) -> list[Suggestion]:
    """Best first by AIC, with the same parsimony rule as the verdict: a candidate with more
    free parameters outranks a simpler one only if it lowers AIC by more than `DELTA_AIC_MIN`."""
    rest = sorted(cands, key=lambda s: s.delta_aic)
    out = []
    while rest:
        best_aic = rest[0].delta_aic
        close = [s for s in rest if s.delta_aic <= best_aic + DELTA_AIC_MIN]
        pick = min(close, key=lambda s: (s.fit.n_params, s.delta_aic))
        out.append(pick)
        rest.remove(pick)
    return out


def diagnose(
    fit_or_data,
    circuit: Circuit | str | None = None,
    *,
    data: xr.Dataset | None = None,
    effects: EffectCatalog = DEFAULT_EFFECTS,
    kk=None,
    noise: float | None = None,
    weighting: str = "modulus",
    n_starts: int = 4,
    max_steps: int = 100,
    seed: int = 0,
) -> Diagnosis:
    """Diagnose a fit: where the model fails, which effect of ``effects`` is missing, verdict.

    ``fit_or_data``: a `FitResult` (then ``data`` may give the Dataset it was fitted to, for its
    ``sigma``), or a spectrum Dataset/path together with ``circuit`` (fitted first with
    ``weighting``). ``kk``: a `KKResult` to reuse (default: `kk_test` of the fitted spectrum);
    ``noise``: a relative noise level to use instead of the estimate. Candidates are fitted
    warm-started together (``n_starts`` starts each, ``max_steps`` Levenberg–Marquardt steps).
    Thresholds and rules: module docstring and docs/diagnosis.md. Returns a `Diagnosis`.
    """
    from ..kk import kk_test

    if n_starts < 1 or max_steps < 1:
        raise ParameterError("n_starts and max_steps must be at least 1")
    if isinstance(fit_or_data, FitResult):
        base = fit_or_data
        if circuit is not None:
            raise ParameterError("give either a FitResult or data with a circuit, not both")
        shapes = None
    else:
        from ..least_squares.batch import BatchFitResult

        if isinstance(fit_or_data, BatchFitResult):
            raise ParameterError("diagnose takes the fit of one spectrum; fit a trial mean or select one spectrum of the batch")
        if circuit is None:
            raise ParameterError("diagnose(data, circuit): the circuit to diagnose is missing")
        if data is not None:
            raise ParameterError("give the data once")
        base, data, shapes = _fit_baseline(fit_or_data, circuit, effects, weighting=weighting, n_starts=n_starts, seed=seed)
    spectrum, sigma = _spectrum_of(base, data)
    notes: list[str] = []
    if kk is None:
        try:
            kk = kk_test(spectrum[["Z"]])
        except ImpedaxError as err:
            kk = None
            notes.append(f"Kramers–Kronig test not run: {err}")
    # noise level, relative per component
    if noise is not None:
        if not (np.isfinite(noise) and noise > 0):
            raise ParameterError(f"noise must be a positive relative level, got {noise!r}")
        sigma_rel = np.full(base.n_points, float(noise))
        source = "given"
    elif sigma is not None:
        sigma_rel = sigma / np.abs(base.z_data)
        source = "the data's sigma (trial scatter)"
    elif kk is not None and np.isfinite(kk.noise_estimate):
        sigma_rel = np.full(base.n_points, float(kk.noise_estimate))
        source = "Kramers–Kronig residuals"
    else:
        sigma_rel = np.full(base.n_points, base.rms_rel / math.sqrt(2))
        source = "the fit's own residuals (no KK test, no sigma)"
    sigma_rel = np.maximum(sigma_rel, NOISE_FLOOR)
    thresholds = {"delta_aic_min": DELTA_AIC_MIN, "noise_fraction_min": NOISE_FRACTION_MIN, "noise_ratio_max": NOISE_RATIO_MAX, "run_p": RUN_P, "noise_floor": NOISE_FLOOR, "kk_invalid_fraction": KK_INVALID_FRACTION}

    # is it the data?
    if kk is not None and not kk.valid:
        flagged = float(np.mean(kk.flagged))
        if flagged >= KK_INVALID_FRACTION or kk.rms_rel > max(3 * float(np.median(sigma_rel)), KK_INVALID_RMS):
            bands = failing_bands(base, sigma_rel, kk_bad_bands=kk.bad_bands)
            reason = (
                f"the data themselves are not Kramers–Kronig consistent ({flagged * 100:.0f} % of the points flagged, KK rms_rel {kk.rms_rel * 100:.2g} %): "
                "drift, movement or a non-stationary sample during the sweep; no circuit should be asked to fit them. Repeat or trim the measurement."
            )
            return Diagnosis(base, kk, sigma_rel, source, bands, (), "data_invalid", reason, tuple(notes), thresholds)
        notes.append("the KK test flags " + ", ".join(f"{format_frequency(lo)}–{format_frequency(hi)}" for lo, hi in kk.bad_bands) + ": misfits there may be data problems")

    kk_bad = kk.bad_bands if kk is not None else ()
    bands = failing_bands(base, sigma_rel, kk_bad_bands=kk_bad)
    order = np.argsort(base.frequency)
    undetermined = frozenset(k for k in base.free_names if not (np.isfinite(base.stderr[k]) and abs(base.stderr[k]) <= abs(base.values[k])))
    ctx = BaselineContext(base.circuit, base.values, base.frequency[order], base.z_data[order], base.z_model[order], base.registry, undetermined)
    proposals: list[tuple[object, Proposal]] = []
    seen = {str(base.circuit)}
    for effect in effects:
        for p in effect.propose(base.circuit, ctx):
            key = str(p.circuit)
            if key in seen:
                continue
            seen.add(key)
            proposals.append((effect, p))
    proposals = [(e, p) for e, p in proposals if len(p.circuit.parameter_names(base.registry)) < 2 * base.n_points]
    fixed = {k: v for k, v in base.values.items() if base.fixed[k]}
    circuits = [base.circuit] + [p.circuit for _, p in proposals]
    inits = [[dict(base.values), ctx.start()]] + [list(p.starts) for _, p in proposals]
    if shapes is None or not _covers(shapes[0], circuits, base.registry):
        shapes = _shapes(circuits, base.registry)
    try:
        fits = fit_candidates(
            circuits, spectrum, init=inits, fixed=fixed or None, weighting=base.weighting, n_starts=n_starts, seed=seed,
            registry=base.registry, single_phase=True, layout=shapes[0], pad_to=shapes[1], k_pad=shapes[2], max_steps=BASELINE_STEPS, step_limit=max_steps,
        )
    except FitError as err:
        raise FitError(f"diagnosis: the candidate fits failed: {err}") from None
    refit = fits[0]
    if refit.chi2 < base.chi2 * (1 - 1e-6):
        notes.append(f"the baseline refit found a better optimum (rms_rel {base.rms_rel * 100:.3g} % → {refit.rms_rel * 100:.3g} %); it is used as the baseline")
        base = refit
        bands = failing_bands(base, sigma_rel, kk_bad_bands=kk_bad)
    noise_var = float(np.mean(2 * sigma_rel**2))
    base_ms = float(np.mean(np.abs(base.residuals) ** 2))
    cands = []
    for (effect, p), cf in zip(proposals, fits[1:]):
        if not np.isfinite(cf.chi2):
            continue
        d_aic, d_bic = cf.aic - base.aic, cf.bic - base.bic
        drop = (base_ms - float(np.mean(np.abs(cf.residuals) ** 2))) / noise_var
        significant = bool(d_aic < -DELTA_AIC_MIN and drop >= NOISE_FRACTION_MIN)
        after = failing_bands(cf, sigma_rel)
        fixed_bands = tuple((b.f_min, b.f_max) for b in bands if not any(a.f_min < b.f_max and a.f_max > b.f_min for a in after))
        cands.append(Suggestion(effect.id, p.added, p.where, cf, d_aic, d_bic, significant, _explain(effect, p, base, cf, d_aic, fixed_bands), fixed_bands))
    cands = _rank(cands)
    ratio = _noise_ratio(base, sigma_rel)
    model_bands = [b for b in bands if not b.data_problem]
    if any(s.significant for s in cands):
        verdict = "missing_effect"
        best = next(s for s in cands if s.significant)
        reason = f"the residuals are {ratio:.3g}× the noise" + (f" and structured in {len(model_bands)} band(s)" if model_bands else "") + f"; adding {best.effect} ({best.added}) lowers AIC by {-best.delta_aic:.1f}."
    elif model_bands and ratio > NOISE_RATIO_MAX:
        verdict = "missing_effect"
        reason = f"the residuals are {ratio:.3g}× the noise and structured in {len(model_bands)} band(s), but no effect in the catalog fixes them significantly."
    else:
        verdict = "adequate"
        reason = (
            f"the residuals are {ratio:.3g}× the noise" + (" with no structured band" if not model_bands else " (small structure only)")
            + f", and no effect lowers AIC by more than {DELTA_AIC_MIN:g} while explaining at least {NOISE_FRACTION_MIN:.0%} of the noise variance."
        )
    return Diagnosis(base, kk, sigma_rel, source, bands, tuple(cands), verdict, reason, tuple(notes), thresholds)


# --- refinement loop -------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class RefinementStep:
    """One model of the loop: its fit, what was added to get it, and its diagnosis."""

    fit: FitResult
    added: str | None
    effect: str | None
    diagnosis: Diagnosis | None

    @property
    def model(self) -> str:
        return self.fit.model

    def as_json(self) -> dict:
        return {"model": self.model, "rms_rel": self.fit.rms_rel, "aic": self.fit.aic, "added": self.added, "effect": self.effect, "bic": self.fit.bic, "chi2_red": self.fit.chi2_red, "verdict": self.diagnosis.verdict if self.diagnosis else None}


@dataclass(frozen=True, eq=False)
class Refinement:
    """Outcome of `refine`: the steps (first: the user's model), the final model and verdict."""

    steps: tuple[RefinementStep, ...]
    verdict: str

    @property
    def final(self) -> FitResult:
        return self.steps[-1].fit

    @property
    def final_model(self) -> str:
        return self.final.model

    def summary(self) -> dict:
        """The JSON of ``impedax refine --json``."""
        return {"steps": [s.as_json() for s in self.steps], "final_model": self.final_model, "verdict": self.verdict}

    def table(self) -> str:
        lines = [f"{'step':>4}  {'rms_rel':>9}  {'AIC':>9}  added / model"]
        for i, s in enumerate(self.steps):
            what = f"+ {s.added} [{s.effect}]" if s.added else "(start)"
            lines.append(f"{i:>4}  {s.fit.rms_rel * 100:>8.3g}%  {s.fit.aic:>9.1f}  {what}")
            lines.append(f"{'':>4}  {'':>9}  {'':>9}  {s.model}")
        return "\n".join(lines)

    def report(self) -> str:
        first, last = self.steps[0].fit, self.final
        lines = [self.table(), ""]
        if len(self.steps) > 1:
            lines.append(f"rms_rel fell from {first.rms_rel * 100:.3g} % to {last.rms_rel * 100:.3g} % in {len(self.steps) - 1} step(s); AIC {first.aic:.1f} → {last.aic:.1f}.")
        last_d = self.steps[-1].diagnosis
        lines.append(f"verdict: {self.verdict.upper()}" + (f" — {last_d.reason}" if last_d is not None else ""))
        return "\n".join(lines)

    def plot(self, *, title: str | None = None):
        """Error per step (rms_rel, log scale) and the relative residuals of every step vs
        frequency, with the final diagnosis's failing bands shaded (matplotlib Figure)."""
        import matplotlib.pyplot as plt

        n = len(self.steps)
        fig = plt.figure(figsize=(11, 3.2 + 2.0 * min(n, 5)), layout="constrained")
        grid = fig.add_gridspec(min(n, 5), 2, width_ratios=[1, 1.6])
        ax = fig.add_subplot(grid[:, 0])
        rms = [s.fit.rms_rel * 100 for s in self.steps]
        ax.semilogy(range(n), rms, "o-", color="tab:blue")
        for i, s in enumerate(self.steps):
            ax.annotate(s.effect or "start", (i, rms[i]), textcoords="offset points", xytext=(4, 6), fontsize=8)
        last_d = self.steps[-1].diagnosis
        if last_d is not None:
            ax.axhline(last_d.noise_level * math.sqrt(2) * 100, color="grey", ls="--", lw=0.8, label="noise level √2σ")
            ax.legend(fontsize=8)
        ax.set_xlabel("refinement step")
        ax.set_ylabel("rms_rel [%]")
        ax.set_xticks(range(n))
        ax.grid(alpha=0.3, which="both")
        shown = list(range(n))[-5:] if n > 5 else list(range(n))
        for row, i in enumerate(shown):
            s = self.steps[i]
            a = fig.add_subplot(grid[row, 1])
            r = s.fit.residuals * 100
            a.semilogx(s.fit.frequency, r.real, "o-", ms=2.5, lw=0.7, label="Re")
            a.semilogx(s.fit.frequency, r.imag, "s-", ms=2.5, lw=0.7, label="Im")
            a.axhline(0, color="k", lw=0.5)
            if s.diagnosis is not None:
                for band in s.diagnosis.failing_bands:
                    a.axvspan(band.f_min, band.f_max, color="tab:red", alpha=0.12)
            a.set_title(f"step {i}: {s.model}  (rms_rel {s.fit.rms_rel * 100:.3g} %)", fontsize=8)
            a.set_ylabel("res. [%]", fontsize=8)
            a.grid(alpha=0.3)
            if row == 0:
                a.legend(fontsize=7, ncol=2)
        fig.axes[-1].set_xlabel("frequency [Hz]")
        fig.suptitle(title or f"refinement: {self.steps[0].model} → {self.final_model} ({self.verdict})")
        return fig

    def to_xarray(self) -> xr.Dataset:
        """Per-step model, rms_rel, AIC, BIC, added element, and residuals over (step, frequency)."""
        f = self.steps[0].fit.frequency
        return xr.Dataset(
            {
                "model": ("step", [s.model for s in self.steps]),
                "added": ("step", [s.added or "" for s in self.steps]),
                "effect": ("step", [s.effect or "" for s in self.steps]),
                "rms_rel": ("step", [s.fit.rms_rel for s in self.steps]),
                "aic": ("step", [s.fit.aic for s in self.steps]),
                "bic": ("step", [s.fit.bic for s in self.steps]),
                "residual_rel": (("step", "frequency"), np.stack([s.fit.residuals for s in self.steps])),
                "Z": ("frequency", self.steps[0].fit.z_data, {"units": "ohm"}),
            },
            coords={"step": np.arange(len(self.steps)), "frequency": ("frequency", f, {"units": "Hz"})},
            attrs={"final_model": self.final_model, "verdict": self.verdict},
        )


def refine(
    data,
    circuit: Circuit | str,
    *,
    max_steps: int = 4,
    effects: EffectCatalog = DEFAULT_EFFECTS,
    weighting: str = "modulus",
    noise: float | None = None,
    n_starts: int = 4,
    seed: int = 0,
) -> Refinement:
    """Refine ``circuit`` on ``data``: diagnose → add the best significant effect → refit, until
    the verdict is not ``missing_effect`` (or no suggestion remains) or ``max_steps`` effects
    were added. Returns a `Refinement` (steps with model, rms_rel, AIC and what was added)."""
    from ...io import load

    if not isinstance(max_steps, int) or max_steps < 0:
        raise ParameterError(f"max_steps must be a non-negative integer, got {max_steps!r}")
    ds = load(data) if not isinstance(data, xr.Dataset) else data
    steps: list[RefinementStep] = []
    added = effect = None
    verdict = "missing_effect"
    current = None
    for i in range(max_steps + 1):
        if current is None:
            d = diagnose(ds, circuit, effects=effects, noise=noise, weighting=weighting, n_starts=n_starts, seed=seed)
        else:
            d = diagnose(current, data=ds, effects=effects, kk=steps[0].diagnosis.kk, noise=noise, n_starts=n_starts, seed=seed)
        steps.append(RefinementStep(d.baseline, added, effect, d))
        verdict = d.verdict
        if d.verdict != "missing_effect" or d.best is None or i == max_steps:
            break
        best = d.best
        current, added, effect = best.fit, best.added, best.effect
    return Refinement(tuple(steps), verdict)
