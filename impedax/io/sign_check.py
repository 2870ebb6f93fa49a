"""Is the imaginary part (or the real part, or all of Z) stored with the opposite sign? A check
of a spectrum's sign convention that the KK test, Z-HIT and `impedax inspect` share (NumPy only:
no fitting imported, so `inspect` stays light and the layers run one way).

A file whose imaginary column holds −Z'' under a header that says Z'' (or the reverse, or a
phase column of the other sign) reads as conj(Z): capacitive data then have Z'' > 0 while |Z|
falls with frequency, which no passive circuit does (its impedance is minimum-phase: ln|Z| and
the phase rise and fall together, `zhit`), and the KK test fails across the whole band while
passing on conj(Z). A negated real column gives Z' < 0 throughout, which no passive impedance
has; conj(Z) passes the test there too but keeps Z' < 0, so that case has a hint of its own.
"""

from __future__ import annotations

import math
import re
from typing import Callable

import numpy as np

from .consistency import FLIPPED_PHASE_KEY

__all__ = [
    "POSITIVE_SHARE", "FAILED_SHARE", "positive_imaginary_evidence", "negative_real_evidence", "conjugate_evidence", "opposite_sign_hint",
    "negative_real_hint", "imaginary_flipped_too", "swapped_evidence", "bode_misfit", "sign_hint", "values_sign_hint",
]

POSITIVE_SHARE = 0.9
"""Z'' > 0 at at least this share of the points ("nearly all")."""
FAILED_SHARE = 0.8
"""A validity test fails "(almost) everywhere" when it flags at least this share of the points."""
RESISTIVE_PHASE = 0.02
"""Points whose |Z''| is below this share of |Z| (a phase within ~1.1° of a resistor's: a DC
plateau, a series resistance's end) say nothing of the sign of the imaginary part: their noise
sets it. The share of `positive_imaginary_evidence` is counted over the others (a flipped arc
with a resistive plateau at 1 mHz: Z'' > 0 at 87.7 % of all points, at every one of the others)."""
_FALLING = 0.25
"""|Z| falls with frequency when Δln|Z| over the band is below −this × (2/π)∫φ d ln ω (for
minimum-phase data the two are about equal)."""


def positive_imaginary_evidence(freq, z) -> str | None:
    """Why ``z`` looks conjugated from its values alone, or None: Z'' > 0 at nearly all points
    (`POSITIVE_SHARE`; of those not nearly resistive, `RESISTIVE_PHASE`) while |Z| falls with
    frequency (an inductive spectrum's rises)."""
    freq = np.asarray(freq, float)
    z = np.asarray(z, complex)
    keep = np.isfinite(freq) & np.isfinite(z) & (freq > 0) & (np.abs(z) > 0)
    freq, z = freq[keep], z[keep]
    if freq.size < 3 or np.ptp(np.log(freq)) == 0:
        return None
    telling = np.abs(z.imag) >= RESISTIVE_PHASE * np.abs(z)
    positive = int(np.count_nonzero(telling & (z.imag > 0)))
    if telling.sum() < 3 or positive < POSITIVE_SHARE * telling.sum():
        return None
    order = np.argsort(freq)
    x = np.log(freq[order])
    phase = np.angle(z[order])
    rise = float(np.polyfit(x, np.log(np.abs(z[order])), 1)[0] * (x[-1] - x[0]))  # Δln|Z| of a straight-line fit
    expected = (2 / math.pi) * float(np.sum((phase[1:] + phase[:-1]) / 2 * np.diff(x)))  # > 0: the phase says |Z| rises
    if not (expected > 0 and rise < -_FALLING * expected):
        return None
    shown = f"{positive} of {freq.size} points" if telling.all() else f"{positive} of the {int(telling.sum())} points not nearly resistive (|Z''| at least {RESISTIVE_PHASE:g}·|Z|)"
    return f"Z'' > 0 at {shown} while |Z| falls with frequency, which no passive circuit does"


def negative_real_evidence(freq, z) -> str | None:
    """Why the real part of ``z`` looks stored with the opposite sign, or None: Z' < 0 at
    nearly all points (`POSITIVE_SHARE`), which no passive impedance has (its Z' ≥ 0 at every
    frequency: it dissipates power)."""
    z = np.asarray(z, complex)
    keep = np.isfinite(np.asarray(freq, float)) & np.isfinite(z)
    z = z[keep]
    if z.size < 3:
        return None
    negative = int(np.count_nonzero(z.real < 0))
    if negative < POSITIVE_SHARE * z.size:
        return None
    return f"Z' < 0 at {negative} of {z.size} points, which no passive impedance has"


def imaginary_flipped_too(freq, z) -> bool:
    """With Z' < 0 nearly everywhere (`negative_real_evidence`): whether Z'' is negated too (the
    whole of Z is: −Z). Asked of the spectrum with its real part put right, −conj(Z), whose
    phase is a passive cell's if only Z' was flipped; ``z`` itself has a phase near ±180° there,
    which `positive_imaginary_evidence` reads as |Z| that should rise (a REAL-shaped −Z got the
    real-part hint, whose fix gave conj(Z))."""
    return positive_imaginary_evidence(freq, -np.conj(np.asarray(z, complex))) is not None


SWAP_MARGIN = 1 / 3
"""Z' and Z'' are taken for each other's columns (`swapped_evidence`) when |Z| follows the phase
of Z'' + jZ' at most this share of the misfit it has to the phase of −Z (`bode_misfit`): on
every REAL file of tests/fixtures/real, swapped or negated, the right reading's misfit was 1/6.8
of the wrong one's or less."""


def bode_misfit(freq, z) -> float:
    """The median over the band of |d ln|Z|/d ln ω − (2/π)φ|, each between neighbouring
    frequencies: how far ``z`` is from Bode's gain–phase relation, which a minimum-phase
    impedance (a passive cell's) follows about (0.01–0.05 on the REAL files; 0.4–0.9 for the
    same data with Z' and Z'' exchanged)."""
    freq = np.asarray(freq, float)
    z = np.asarray(z, complex)
    order = np.argsort(freq)
    x, z = np.log(freq[order]), z[order]
    slope = np.diff(np.log(np.abs(z))) / np.diff(x)
    phase = np.angle(z)
    return float(np.median(np.abs(slope - (2 / math.pi) * (phase[1:] + phase[:-1]) / 2)))


def swapped_evidence(freq, z) -> str | None:
    """Why Z' and Z'' of ``z`` look stored in each other's columns, or None: Z' < 0 and Z'' > 0
    nearly everywhere (`negative_real_evidence`, `POSITIVE_SHARE`), the signature of a swap of
    capacitive data as of −Z, and |Z| follows the phase of Z'' + jZ' rather than that of −Z
    (`bode_misfit` below `SWAP_MARGIN` of the other's); the two give the same |Z| and the
    phases φ and −(90° − |φ|), so only the gain–phase relation tells them apart."""
    freq = np.asarray(freq, float)
    z = np.asarray(z, complex)
    keep = np.isfinite(freq) & np.isfinite(z) & (freq > 0) & (np.abs(z) > 0)
    freq, z = freq[keep], z[keep]
    if np.unique(freq).size < 4 or negative_real_evidence(freq, z) is None or np.count_nonzero(z.imag > 0) < POSITIVE_SHARE * z.size:
        return None
    swapped, negated = bode_misfit(freq, z.imag + 1j * z.real), bode_misfit(freq, -z)
    if not swapped < SWAP_MARGIN * negated:
        return None
    return (f"Z'' > 0 at {int(np.count_nonzero(z.imag > 0))} of {z.size} points too, and |Z| follows the phase of Z'' + jZ' "
            f"(Bode's gain–phase relation: median misfit {swapped:.2g}, against {negated:.2g} for −Z)")


def negative_real_hint(evidence: str | None, imaginary_too: bool = False, swapped: str | None = None) -> str | None:
    """The hint for ``evidence`` (`negative_real_evidence`), or None; ``imaginary_too``: Z'' looks
    negated as well (`positive_imaginary_evidence`), the whole of Z is (−Z: the current's sign,
    or its leads, swapped); ``swapped`` (`swapped_evidence`, first): Z' and Z'' look stored in
    each other's columns (such a file would otherwise get the real-part hint, whose fix gives
    conj(Z) of the other reading)."""
    if not evidence:
        return None
    if swapped:
        return (f"Z' and Z'' may be stored in each other's columns: {evidence}, {swapped}; if so, exchange the two columns' names in the header, "
                "or in Python take data.assign(Z=data['Z'].imag + 1j * data['Z'].real)")
    if imaginary_too:
        return (f"Z may be stored with the opposite sign (−Z: the current's sign or leads swapped): {evidence}, and Z'' > 0 while |Z| falls; "
                "if so, correct the sign of both columns in the file, or in Python take data.assign(Z=-data['Z'])")
    return (f"the real part may be stored with the opposite sign (−Z'): {evidence}; if so, correct the sign of that column in the file, "
            "or in Python take data.assign(Z=-data['Z'].conj())")


def conjugate_evidence(result, retest: Callable[[np.ndarray, np.ndarray], object], name: str = "the KK test") -> str | None:
    """Why the data look conjugated to a validity test, or None: ``result`` (a `KKResult` or
    `ZHITResult`) flags at least `FAILED_SHARE` of the points and ``retest(frequency, conj(Z))``
    is valid (and conj(Z) is not negative-real: conjugating leaves Z' as it is,
    `negative_real_evidence`)."""
    flagged = np.asarray(result.flagged, bool)
    if result.valid or flagged.size == 0 or flagged.mean() < FAILED_SHARE:
        return None
    if negative_real_evidence(result.frequency, result.impedance):
        return None
    other = retest(result.frequency, np.conj(result.impedance))
    if not other.valid:
        return None
    return f"{name} fails at {int(flagged.sum())} of {flagged.size} points (rms_rel {result.rms_rel * 100:.3g} %) but passes on conj(Z) (rms_rel {other.rms_rel * 100:.3g} %)"


def opposite_sign_hint(evidence: str | None, attrs=None) -> str | None:
    """The hint for ``evidence`` (`positive_imaginary_evidence`, `conjugate_evidence`), or None,
    with the fix that fits how the reader took the column (``attrs``: the data's attributes)."""
    if not evidence:
        return None
    return f"the imaginary part may be stored with the opposite sign (−Z''): {evidence}{_phase_column_agrees(attrs or {})}; {_fix(attrs or {})}, or in Python take data.assign(Z=data['Z'].conj())"


def _phase_column_agrees(attrs) -> str:
    """``; the file's own phase column 'Phase (deg)' says so too …`` when the reader found the
    file's phase column of the other sign than Z read (``attrs["polar_columns_flipped_phase"]``,
    its name: `consistency.polar_columns_attrs`; read from that, not from the words of
    ``polar_columns_note``, which may change); ``""`` otherwise."""
    name = attrs.get(FLIPPED_PHASE_KEY)
    if not isinstance(name, str) or not name:
        return ""
    return f"; the file's own phase column {name!r} says so too: it holds the opposite sign of atan2(Z'', Z') of Z as read"


_SIGN_NOTES = (  # how `io.table.Layout.notes` writes which column held Z'' (or the phase)
    (re.compile(r"column (['\"])(?P<name>.+)\1 holds Z'' \(negative for capacitive data\), taken as stored"), False),
    (re.compile(r"column (['\"])(?P<name>.+)\1 holds -Z''; negated to Z''"), True),
    (re.compile(r"Z = \|Z\|·exp\(j·phase\) from (['\"]).+?\1 and (['\"])(?P<name>.+)\2(?P<negated>; the file stores -phase)?"), None),
)


def _fix(attrs) -> str:
    """How to read the column with the other sign: rename it in the header (a leading '-'
    negates), add a header to a header-less table, or, for other formats, correct the file."""
    if "no header" in str(attrs.get("interpretation", "")):
        return "if so, add a header line that names it, e.g. frequency,Z',-Z'' (impedax negates a column whose name starts with '-')"
    text = str(attrs.get("sign_convention", ""))
    for pattern, negated in _SIGN_NOTES:
        match = pattern.fullmatch(text)
        if match is None:
            continue
        name = match.group("name")
        if negated is None:
            negated = match.group("negated") is not None
        if negated:
            return f"if so, rename the column {name!r} to {name[1:]!r} in the header (its leading '-' makes impedax negate it)"
        return f"if so, rename the column {name!r} to {'-' + name!r} in the header (impedax negates a column whose name starts with '-')"
    return "if so, correct the sign in the file (in a table, a column whose name starts with '-', e.g. -Z'', is negated on reading)"



def sign_hint(result, retest: Callable[[np.ndarray, np.ndarray], object], name: str, attrs=None) -> str | None:
    """`negative_real_hint` for a validity test's ``result`` whose Z' < 0 nearly everywhere
    (`negative_real_evidence`); else `opposite_sign_hint` when it fails almost everywhere and
    ``retest`` passes conj(Z) (`conjugate_evidence`), or Z'' > 0 nearly everywhere while |Z|
    falls (`positive_imaginary_evidence`)."""
    real = negative_real_evidence(result.frequency, result.impedance)
    if real:
        return negative_real_hint(real, imaginary_too=imaginary_flipped_too(result.frequency, result.impedance),
                                  swapped=swapped_evidence(result.frequency, result.impedance))
    evidence = conjugate_evidence(result, retest, name) or positive_imaginary_evidence(result.frequency, result.impedance)
    return opposite_sign_hint(evidence, attrs)


def values_sign_hint(freq, z, attrs=None) -> str | None:
    """`sign_hint` from a spectrum's values alone, for an analysis with no validity test to
    repeat on conj(Z) (the DRT): `negative_real_hint` when Z' < 0 nearly everywhere, else
    `opposite_sign_hint` when Z'' > 0 nearly everywhere while |Z| falls; None otherwise."""
    real = negative_real_evidence(freq, z)
    if real:
        return negative_real_hint(real, imaginary_too=imaginary_flipped_too(freq, z), swapped=swapped_evidence(freq, z))
    return opposite_sign_hint(positive_imaginary_evidence(freq, z), attrs)
