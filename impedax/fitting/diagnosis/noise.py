"""The noise model of a diagnosis and the data's own problems (docs/diagnosis.md, sections 1–2).

σ_k, the relative standard deviation per component at frequency k that the residuals are judged
against, has two parts:

* the measurement noise σ_meas,k: the data's ``sigma`` (a sigma column, or a remainder's
  standard error of trial means or stated sigma, as `sigma_origin` words it) where they have it, else
  a local robust estimate from the first differences of the Kramers–Kronig residuals in a
  window of `LOCAL_WINDOW` frequencies (heteroscedastic: noise that grows toward low frequency
  is seen where it is);
* a model-discrepancy floor δ (one number per spectrum): the part of the KK residuals that is
  not noise, i.e. how far even the most flexible KK-consistent model (the Voigt chain of the
  KK test) stays from the data, times `DISCREPANCY_FACTOR` (a circuit of a few physical
  elements cannot follow the data as closely as the KK test's chain of relaxations). It is zero on
  data whose KK residuals are noise.

σ_k = max(√(σ_meas,k² + δ²), `NOISE_FLOOR`). So "adequate" means "no effect of the catalog
explains what is left", not "the residuals are at the instrument noise".
"""

from __future__ import annotations

import math
import re
from typing import NamedTuple

import numpy as np

from ..kk import KKResult, kk_test, rejudged
from ..least_squares.result import SIGMA_FROM_OWN, SIGMA_FROM_TRIALS, names_in_words, sigma_sources

__all__ = ["NoiseModel", "noise_model", "sigma_origin", "kk_indices", "kk_outliers", "kk_judged_locally", "OUTLIER_MAX_FRACTION", "OUTLIER_MAX_RUN", "OUTLIER_MIN_RATIO", "NOISE_FLOOR", "DISCREPANCY_FACTOR", "LOCAL_WINDOW", "GLOBAL_SHARE", "LOCAL_SOURCE"]

NOISE_FLOOR = 1e-3
"""Relative noise floor (0.1 %): below this, misfits are instrument accuracy, not physics."""
DISCREPANCY_FACTOR = 3.0
"""δ = this × the structured (non-noise) rms of the KK residuals per component."""
LOCAL_WINDOW = 9
"""Frequencies per window of the local noise estimate (first differences of the KK residuals)."""
OUTLIER_MAX_FRACTION = 0.15
"""A failed KK test is put down to a few erratic points (`kk_outliers`) when leaving out at most
this fraction of the points makes it pass."""
OUTLIER_MAX_RUN = 3
"""... and those points are erratic ones only when no more than this many are adjacent: a longer
run is a step change or drift of the sample during the sweep, not a few bad points."""
OUTLIER_MIN_RATIO = 4.0
"""... and each stands out from the scatter of the rest: its KK residual |Δ| (when it was left
out) at least this × the rms |Δ| of the points kept. Complex Gaussian noise exceeds 4× its rms
with probability e⁻¹⁶ ≈ 1e-7 per point; the erratic points of the evaluation set stand at 5–12×,
while a drift along the sweep that a few left-out points hide stands at 2–3× (SYNTHETIC)."""
GLOBAL_SHARE = 0.7
"""The local estimate is not taken below this fraction of the KK test's global estimate (a
median of a few differences scatters; a quiet stretch must not read as noise-free)."""

LOCAL_SOURCE = "Kramers–Kronig residuals, local (per frequency)"
"""`NoiseModel.source` when σ_meas is the local estimate (`local_noise`)."""


class NoiseModel(NamedTuple):
    """σ per point and component (``sigma_rel``, relative), its measurement part, the
    model-discrepancy floor δ and where the measurement part came from (in words)."""

    sigma_rel: np.ndarray
    measurement: np.ndarray
    discrepancy: float
    source: str


def kk_indices(kk: KKResult, frequency: np.ndarray) -> np.ndarray | None:
    """Index into the KK result of each of ``frequency`` (None when one is missing)."""
    f_kk = np.asarray(kk.frequency, float)
    idx = np.array([int(np.argmin(np.abs(f_kk - f))) for f in frequency], dtype=int)
    return idx if np.allclose(f_kk[idx], frequency, rtol=1e-9) else None


def _running(values: np.ndarray, half: int, reduce) -> np.ndarray:
    n = values.shape[-1]
    return np.array([reduce(values[..., max(0, i - half): min(n, i + half + 1)]) for i in range(n)])


def local_noise(kk: KKResult, *, exclude: np.ndarray | None = None) -> np.ndarray:
    """Measurement noise per frequency of the KK test's spectrum (the KK result's order): the
    robust scale 1.4826·median|d|/√2 of the first differences d of Δ' and Δ'' over the points
    not flagged (or not in ``exclude``, a mask in the KK result's order) in frequency order,
    in windows of `LOCAL_WINDOW`, 3-point smoothed, inflated by √(2N/(2N − P)) for the
    P = n_rc + 3 KK parameters, not below `GLOBAL_SHARE` × the global estimate; interpolated in
    log f onto the points left out."""
    f = np.asarray(kk.frequency, float)
    order = np.argsort(f)
    left_out = np.asarray(kk.flagged if exclude is None else exclude, bool)
    usable = order[~left_out[order]]
    global_est = float(kk.noise_estimate) if np.isfinite(kk.noise_estimate) else 0.0
    if usable.size < 4:
        return np.full(f.size, global_est)
    d = np.abs(np.stack([np.diff(kk.residuals_real[usable]), np.diff(kk.residuals_imag[usable])]))
    half = LOCAL_WINDOW // 2
    # difference j sits between usable points j and j+1; point i takes differences i-half .. i+half-1
    scale = np.array([1.4826 * np.median(d[:, max(0, i - half): min(d.shape[1], i + half)]) / math.sqrt(2) for i in range(usable.size)])
    scale = _running(scale, 1, np.mean)
    n = 2 * f.size
    p = min(int(kk.n_rc) + 3, n - 1)
    scale = np.maximum(scale * math.sqrt(n / (n - p)), GLOBAL_SHARE * global_est)
    out = np.empty(f.size)
    out[:] = np.interp(np.log(f), np.log(f[usable]), scale)
    return out


def _discrepancy(kk: KKResult, measurement_kk: np.ndarray) -> float:
    """δ: `DISCREPANCY_FACTOR` × √(max(mean Δ²/2 · 2N/(2N − P) − mean σ_meas² · (1 + 3/√N_u), 0))
    over the N_u unflagged points (the margin 3/√N_u keeps the scatter of a mean of squares of
    pure noise from reading as structure)."""
    good = ~np.asarray(kk.flagged, bool)
    n_u = int(good.sum())
    if n_u < 4:
        return 0.0
    ms_kk = float(np.mean((kk.residuals_real[good] ** 2 + kk.residuals_imag[good] ** 2) / 2))
    n = 2 * kk.frequency.size
    p = min(int(kk.n_rc) + 3, n - 1)
    ms_noise = float(np.mean(measurement_kk[good] ** 2))
    excess = ms_kk * n / (n - p) - ms_noise * (1 + 3 / math.sqrt(n_u))
    return DISCREPANCY_FACTOR * math.sqrt(excess) if excess > 0 else 0.0


def _usable(local: np.ndarray | None) -> bool:
    """Is ``local`` (a `local_noise` estimate, or None) finite at two points or more?"""
    return local is not None and bool(np.all(np.isfinite(local))) and local.size >= 2


def sigma_origin(attrs) -> str:
    """What a spectrum's ``sigma`` is, by its attrs, in words that follow where it came from:
    a remainder's (``sigma_method``, as `sirin.remaining_impedance` writes it) is "the standard
    error of trial means" (with the counts ``n_trials_*`` when they are there), "the stated sigma
    of the one spectrum", or which inputs gave a standard error of their trial means and which
    their own stated sigma; a `sirin.trial_mean` (``n_trials``, ``sigma_from``) likewise; else
    ``"sigma column"`` (a column of the file or ``make_spectrum(sigma=...)``, whose origin impedax
    does not know). A sigma column is not called "trial scatter", nor is every
    remainder's sigma, a single input's own sigma among them. A
    remainder's provenance is read from its ``sigma_sources`` (`result.sigma_sources`); one saved
    by an older version has none, and the words of its ``sigma_method`` are read instead."""
    attrs = attrs or {}
    sources = sigma_sources(attrs)
    if sources:
        return _origin_of_sources(sources, attrs)
    method = str(attrs.get("sigma_method", ""))
    if method.startswith("not available"):  # (the remainder has none: this sigma came from elsewhere)
        return "sigma column"
    mean_of = re.search(r"over the trials of (.+?);", method)
    stated_of = re.search(r"the stated sigma of (.+?) \(one spectrum", method)
    if "the stated sigma of the one spectrum" in method or ("n_trials" in attrs and attrs.get("sigma_from") == "own sigma"):
        return "the stated sigma of the one spectrum"
    if stated_of:
        means = f"the standard error of the trial means of {mean_of.group(1)} and " if mean_of else ""
        return f"{means}the stated sigma of {stated_of.group(1)}, added in quadrature"
    if "sem" in method.lower() or "trial" in method.lower() or "n_trials" in attrs or "n_trials_total" in attrs:
        counts = [f"{int(attrs[f'n_trials_{name}'])} {name}" for name in ("total", "skin", "touchscreen") if f"n_trials_{name}" in attrs]
        return "the standard error of trial means" + (f" of {', '.join(counts)} spectra" if counts else "")
    return "sigma column"


def _origin_of_sources(sources: dict[str, str], attrs) -> str:
    """`sigma_origin`'s words from a remainder's ``sigma_sources`` (input → what its error is)
    and its counts ``n_trials_<input>``."""
    means = [name for name, source in sources.items() if source == SIGMA_FROM_TRIALS]
    stated = [name for name, source in sources.items() if source == SIGMA_FROM_OWN]
    if not means:
        return "the stated sigma of the one spectrum" if len(stated) == 1 and len(sources) == 1 else f"the stated sigma of {names_in_words(stated)}, added in quadrature"
    if stated:
        return f"the standard error of the trial means of {names_in_words(means)} and the stated sigma of {names_in_words(stated)}, added in quadrature"
    counts = [f"{int(attrs[f'n_trials_{name}'])} {name}" for name in means if f"n_trials_{name}" in attrs]
    return "the standard error of trial means" + (f" of {', '.join(counts)} spectra" if counts else "")


def noise_model(frequency: np.ndarray, z_data: np.ndarray, *, noise: float | None, sigma: np.ndarray | None, kk: KKResult | None, fallback_rms: float, floor_kk: KKResult | None = None, sigma_kind: str = "sigma column") -> NoiseModel:
    """The `NoiseModel` at ``frequency``: a ``noise`` level given by the user (used as it is,
    no discrepancy floor), else the data's ``sigma`` (relative to |Z|), else the
    local KK estimate (`local_noise`, interpolated in log f), else ``fallback_rms``/√2 (the
    fit's own residuals; ``sigma_kind``: what the sigma is, `sigma_origin`, which the source
    names); plus the discrepancy floor δ from the KK residuals (`_discrepancy`)
    over the points ``floor_kk`` (default ``kk``) does not flag: the diagnosis passes the KK
    test as it flagged them, so that points cleared by its local judgement
    (`kk_judged_locally`) count for σ_meas but cannot raise δ (at the edge of a flagged run
    their local scatter is taken across the gap)."""
    n = frequency.size
    if noise is not None:
        meas = np.full(n, float(noise))
        return NoiseModel(np.maximum(meas, NOISE_FLOOR), meas, 0.0, "given")
    local = local_noise(kk) if kk is not None else None
    usable = _usable(local)
    if sigma is not None:
        meas, source = np.asarray(sigma, float) / np.abs(z_data), "the data's sigma column" if sigma_kind == "sigma column" else f"the data's sigma ({sigma_kind})"
    elif usable:
        order = np.argsort(kk.frequency)
        meas = np.interp(np.log(frequency), np.log(np.asarray(kk.frequency, float)[order]), local[order])
        source = LOCAL_SOURCE
    else:
        meas, source = np.full(n, fallback_rms / math.sqrt(2)), "the fit's own residuals (no KK test, no sigma)"
    floor_kk = kk if floor_kk is None else floor_kk
    floor_local = local if floor_kk is kk else local_noise(floor_kk)
    delta = _discrepancy(floor_kk, floor_local) if _usable(floor_local) else 0.0
    if delta > 0:
        source += f" + model-discrepancy floor {delta * 100:.2g} %"
    return NoiseModel(np.maximum(np.sqrt(meas**2 + delta**2), NOISE_FLOOR), meas, delta, source)


def kk_judged_locally(kk: KKResult) -> KKResult:
    """The failed KK test ``kk`` judged again against the local noise of each point
    (`local_noise`, `kk.rejudged`): `kk_test` scales every point by one global noise
    estimate, so where the noise grows toward low frequency (×6 across the band, as in skin
    and electrochemical data) the noisier end reads as bad and was masked or blamed on the
    data (SYNTHETIC: 6 of 60 points of a battery spectrum at 0.3 % noise, among them the ones
    that tell a Warburg from an arc). Drift stands out from the local scatter as from the
    global one: first differences barely see a smooth drift. The local scatter is taken
    without the points beyond the rule's single-point threshold (erratic points would inflate
    it: three adjacent ones are half a window's differences), judged first against the global
    scale, then twice against the local one. A point is judged against the smallest local
    scale at or below its frequency, never below the global one: scatter that grows toward
    low frequency is honoured; the global judgement stands where the data are quieter than
    the median, and where the scatter grows toward the top of the band, where instruments
    reach their limits (impedance.py's PowerSuite example: KK residuals of 2–16 %
    over its top three decades, where its phase turns the real part negative at 1–2 MHz)."""
    magnitude = np.hypot(kk.residuals_real, kk.residuals_imag)
    floor, point = kk.thresholds["noise_floor"], kk.thresholds["point"]
    exclude = magnitude > point * kk.threshold_scale
    for _ in range(2):
        exclude = magnitude > point * np.maximum(local_noise(kk, exclude=exclude), floor)
    local = local_noise(kk, exclude=exclude)
    order = np.argsort(kk.frequency)
    vouched = np.empty_like(local)
    vouched[order] = np.minimum.accumulate(local[order])  # the smallest at or below each frequency
    return rejudged(kk, np.maximum(vouched, kk.threshold_scale))


def _longest_run(mask: np.ndarray) -> int:
    """The longest run of True in ``mask`` (points in the spectrum's order)."""
    best = run = 0
    for m in mask:
        run = run + 1 if m else 0
        best = max(best, run)
    return best


def kk_outliers(spectrum, kk: KKResult, *, max_fraction: float, rounds: int = 4) -> tuple[np.ndarray, KKResult] | None:
    """Locate the points behind a failed KK test: the worst points (|Δ| at least half the
    largest, at most 10 % of the points per round) are left out and the KK test repeated on the
    rest, until it passes; no more than `OUTLIER_MAX_RUN` of them may be adjacent (in the
    spectrum's order, frequency-sorted for a sweep), and each must stand out from the rest's
    scatter (`OUTLIER_MIN_RATIO`). Returns (bool mask of the points left out, in the spectrum's
    order; the KK result of the rest), or None when the test does not pass with at most
    ``max_fraction`` of the points left out, or the points left out do not stand out (then the
    problem is not a few points)."""
    f_all = np.asarray(spectrum["frequency"].values, float)
    out = np.zeros(f_all.size, bool)
    out_mag = np.zeros(f_all.size)  # |Δ| of each point left out, in the round it was left out
    current = kk
    for _ in range(rounds):
        if current.valid:
            return (out, current) if _stand_out(current, f_all, out, out_mag) else None
        keep_idx = np.nonzero(~out)[0]
        idx = kk_indices(current, f_all[keep_idx])
        if idx is None:
            return None
        mag = np.hypot(current.residuals_real, current.residuals_imag)[idx]
        limit = max(1, int(0.1 * f_all.size))
        worst = np.argsort(-mag)[:limit]
        worst = worst[mag[worst] >= 0.5 * mag.max()]
        out[keep_idx[worst]] = True
        out_mag[keep_idx[worst]] = mag[worst]
        if out.mean() > max_fraction or (~out).sum() < 8 or _longest_run(out) > OUTLIER_MAX_RUN:
            return None
        current = kk_test(spectrum.isel(frequency=np.nonzero(~out)[0])[["Z"]])
    return (out, current) if current.valid and _stand_out(current, f_all, out, out_mag) else None


def _stand_out(kept: KKResult, f_all: np.ndarray, out: np.ndarray, out_mag: np.ndarray) -> bool:
    """Does every point left out (``out``, its |Δ| ``out_mag``) stand out from the KK residuals
    of the points kept (`OUTLIER_MIN_RATIO` × their rms |Δ|)?"""
    if not out.any():
        return True
    idx = kk_indices(kept, f_all[~out])
    if idx is None:
        return False
    rms = float(np.sqrt(np.mean(np.hypot(kept.residuals_real, kept.residuals_imag)[idx] ** 2)))
    return bool(np.all(out_mag[out] >= OUTLIER_MIN_RATIO * rms))
