"""Points no passive circuit reaches: the rule of Re Z < 0 beyond the noise and its words, which
fits, the KK test, the gap analysis and `impedax inspect` share. NumPy and SciPy only: `impedax
inspect` applies it without importing JAX."""

from __future__ import annotations

import numpy as np

from .data import format_frequency

__all__ = ["NON_PASSIVE_MARGIN", "NON_PASSIVE_CHANCE", "chance_depth", "non_passive", "NOISE_OF_SIGMA", "FIT_RESIDUAL_NOISE", "KK_RESIDUAL_NOISE",
           "non_passive_words", "top_of_band", "SUBTRACTION_CAUSE", "listed_frequencies", "non_passive_notes"]


# a point is not passive when Re Z < 0 by more than noise could make it: below −5 % of |Z|
# (a capacitive point, Re Z ≈ 0, at 1 % noise per component goes there once in 3·10⁶), and,
# where the noise is known (the data's σ, or one estimated from a fit's residuals), below
# −`chance_depth` σ as well (a subtracted remainder's noisy top decade; a SYNTHETIC finger
# spectrum, Re Z ≈ 0.3 % of |Z| at 31.6 Hz, with ~2 % noise per component: the 5 % rule alone
# flagged a point or two in a batch of 24 by chance, and a fit called it an artifact at the top of the band)
NON_PASSIVE_MARGIN = 0.05
NON_PASSIVE_CHANCE = 0.01
"""The chance that Gaussian noise alone puts any of a spectrum's points (Re Z ≈ 0 at each, the
worst case) below −`chance_depth` σ: one spectrum in 100."""


def chance_depth(n_points: int) -> float:
    """The depth k (in σ of each point's noise) that one of ``n_points`` Gaussian draws goes
    below by chance with probability `NON_PASSIVE_CHANCE`: Φ(−k) = NON_PASSIVE_CHANCE / N
    (Bonferroni; 3.59 at N = 61, 3.06 at N = 9)."""
    from scipy.special import ndtri

    return float(-ndtri(NON_PASSIVE_CHANCE / max(int(n_points), 1)))


def non_passive(z, sigma=None, noise=None) -> np.ndarray:
    """Points (bool, z's shape) whose real part is negative beyond the noise:
    Re Z < −max(`NON_PASSIVE_MARGIN`·|Z|, k·σ), σ the data's ``sigma`` (Ω, per point), else
    ``noise`` (Ω, per point: an estimate, e.g. `fit_noise`), k = `chance_depth` of the points
    of a spectrum (z's last axis). A passive one-port has Re Z(jω) ≥ 0, so no circuit of
    passive elements reaches them: measurement artifacts (an instrument's phase error near the
    top of its band is the usual one)."""
    z = np.asarray(z)
    margin = NON_PASSIVE_MARGIN * np.abs(z)
    scale = sigma if sigma is not None else noise
    if scale is not None:
        margin = np.maximum(margin, chance_depth(z.shape[-1] if z.ndim else 1) * np.asarray(scale, float))
    return z.real < -margin


NOISE_OF_SIGMA = "the data's sigma"
"""`non_passive_words`' name of the noise the data state."""
FIT_RESIDUAL_NOISE = "the fit's residuals"
"""... of the noise a fit's residuals show (`fit_noise`)."""
KK_RESIDUAL_NOISE = "the KK test's residuals"
"""... of the noise the Kramers–Kronig test's residuals show (`KKResult.non_passive_noise`)."""


def non_passive_words(noise_from: str | None, n_points: int) -> str:
    """What `non_passive` counted, in words: "Re Z < 0 by more than 5 % of |Z|" and, with a
    noise (``noise_from``: "the data's sigma", "the fit's residuals"), by more than k σ of it."""
    words = f"Re Z < 0 by more than {NON_PASSIVE_MARGIN * 100:g} % of |Z|"
    if noise_from:
        words += f" and {chance_depth(n_points):.2g}σ of the noise ({noise_from}; noise alone goes that deep in fewer than 1 of {1 / NON_PASSIVE_CHANCE:.0f} spectra)"
    return words


def top_of_band(freq, mask) -> bool:
    """Whether the points ``mask`` all lie in the top decade of the band of ``freq``, where an
    instrument's phase error is the usual cause of Re Z < 0."""
    freq = np.asarray(freq, float)
    picked = freq[np.asarray(mask, bool)]
    return bool(picked.size) and bool(np.min(picked) >= np.max(freq) / 10)


SUBTRACTION_CAUSE = (
    "the subtraction Z_total − Z_skin − Z_TS (the skin and touchscreen spectra's series resistance "
    "scatters between trials by more than the remainder's real part there)"
)


def listed_frequencies(freq, mask, shown: int = 6) -> str:
    """The first ``shown`` frequencies where ``mask`` holds, as impedax writes frequencies
    (`impedax.data.format_frequency`: "702 kHz, 1 MHz", not "7.017e+05 Hz,
    1e+06 Hz"), then "…" when there are more."""
    picked = np.sort(np.asarray(freq, float)[np.asarray(mask, bool)])
    return ", ".join(format_frequency(f) for f in picked[:shown]) + (", …" if picked.size > shown else "")


def non_passive_notes(freq, z, sigma=None, *, remainder: bool = False, noise=None) -> tuple[str, ...]:
    """A note naming the points with Re Z < 0 beyond the noise (`non_passive`: below −5 % of |Z|
    and −k σ, σ the data's ``sigma`` or else the ``noise`` a fit's residuals show,
    `impedax.fitting.statistics.fit_noise`), which no passive circuit reaches, saying what was
    counted (`non_passive_words`): an instrument's phase error when they lie in the top decade
    of the band (`top_of_band`), a measurement artifact where they lie elsewhere; in a remainder
    (``remainder``, `impedax.fitting.least_squares.result.is_remainder`) the subtraction's scatter. (The
    5 % rule alone, said as "Re Z < 0", would flag a noisy SYNTHETIC finger spectrum's 31.6 Hz
    point, 1 of its 13 with Re Z < 0, and blame the top of the band.)"""
    bad = non_passive(z, sigma, noise)
    if not bad.any():
        return ()
    noise_from = NOISE_OF_SIGMA if sigma is not None else FIT_RESIDUAL_NOISE if noise is not None and np.any(np.asarray(noise) > 0) else None
    head = (f"{int(bad.sum())} of {bad.size} points have {non_passive_words(noise_from, bad.size)} ({listed_frequencies(freq, bad)}), "
            "which no passive circuit reaches: ")
    if remainder:
        return (head + f"in a remainder, the cause is {SUBTRACTION_CAUSE}; leave them out (fmin/fmax, or impedax fit --exclude); a remainder of the trial means (impedax remaining without --trials) scatters less",)
    if top_of_band(freq, bad):
        return (head + "a measurement artifact (often a phase error at the top of the instrument's band); leave them out (fmin/fmax) or check the file's sign convention",)
    return (
        head + "a measurement artifact below the top decade of the band, where an instrument's phase error seldom lies: check those points "
        "(an outlier, a sign convention changing within the file) and leave them out (impedax fit --exclude, or fmin/fmax)",
    )
