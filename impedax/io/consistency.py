"""Redundant columns of a table that disagree: |Z| and the phase beside Z' and Z''.

Many instruments write both (EC-Lab's ``Re(Z)/Ohm``, ``-Im(Z)/Ohm``, ``|Z|/Ohm``,
``Phase(Z)/deg``; CH Instruments' ``Z'/ohm``, ``Z"/ohm``, ``Z/ohm``, ``Phase/deg``). Z is read from
Z' and Z''; the other two then say the same, up to the rounding of the printed digits:
|Z| = |Z' + jZ''| and φ = atan2(Z'', Z') (in the data model, Z'' < 0 for a capacitor). A |Z|
1000× off (kΩ beside Ω) or a phase of the other sign (Z'' or the phase stored with the other
sign than the header says) means one of the columns is not what its name says, and so maybe Z
itself: `polar_columns_note` says so, and `polar_columns_flipped_phase` names a phase column of
the other sign (for `sign_check`, which reads it rather than the note's words). Nothing read
changes."""

from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

__all__ = ["CHECK_ALL_ROWS", "SAMPLE_ROWS", "MISMATCH_FLOOR", "PHASE_FLOOR_DEG", "FLIPPED_PHASE_KEY", "OPPOSITE_SIGN_WORDS", "float_cells", "polar_columns_attrs",
           "polar_columns_note", "printed_resolution"]

#: Relative |Z| disagreement below which no row is looked at (a float32 instrument's 6e-8 and
#: any rounding beyond 6 significant digits: immaterial to a fit).
MISMATCH_FLOOR = 1e-6
#: Phase disagreement [deg] below which no row is looked at.
PHASE_FLOOR_DEG = 1e-4
#: A table of at most this many rows is checked on every row; a longer one on `SAMPLE_ROWS` rows
#: spread through it, and on every row when one of them disagrees (a unit mix-up or a flipped
#: sign holds on every row, and reading a long table costs no more than before).
CHECK_ALL_ROWS = 20_000
SAMPLE_ROWS = 2_000
#: Margin on the rounding bound (half a unit of each cell's last printed digit).
ROUNDING_MARGIN = 1.5
#: ``attrs[FLIPPED_PHASE_KEY]``: the header name of a phase column that holds the opposite sign
#: of atan2(Z'', Z') of Z as read (a string: netCDF keeps it), set only then. `sign_check` cites
#: the column from it, not from the note's words.
FLIPPED_PHASE_KEY = "polar_columns_flipped_phase"
#: Why the note says a phase column disagrees when it holds the opposite sign.
OPPOSITE_SIGN_WORDS = ("it holds the opposite sign of atan2(Z'', Z') (the phase stored as -phase, or Z'' with the other sign "
                       "than its header says: check which, since Z is read from Z' and Z'')")


def printed_resolution(cell: str) -> float:
    """One unit of the last printed digit of a number cell: ``'1.234E+02'`` → 0.01, ``'-1.6'`` →
    0.1, ``'120'`` → 1, ``'6,5'`` (a decimal comma) → 0.1."""
    mantissa, _, exponent = cell.strip().strip('"').lower().replace(",", ".").partition("e")
    dot = mantissa.find(".")
    decimals = len(mantissa) - dot - 1 if dot >= 0 else 0
    try:
        shift = int(exponent) if exponent else 0
    except ValueError:
        shift = 0
    return 10.0 ** (shift - decimals)


def float_cells(columns: dict[str, np.ndarray]) -> Callable[[np.ndarray], dict[str, list[str]]]:
    """The ``printed`` argument of `polar_columns_attrs` for a file that stores numbers, not text
    (JSON, HDF5, binary): each value as the shortest text that reads back to it in its own
    dtype, whose last digit is the rounding the file's double (or float32) allows."""
    columns = {role: np.asarray(values) for role, values in columns.items()}

    def printed(rows: np.ndarray) -> dict[str, list[str]]:
        return {role: [str(values[i]) for i in rows] for role, values in columns.items()}

    return printed


def _factor_text(ratio: float) -> str:
    """What a median ratio |Z| column / |Z'+jZ''| says: a power of ten (within 1 %) is a unit
    mix-up, ``1000× |Z'+jZ''|``; another ratio is given as it is."""
    power = float(np.round(np.log10(ratio))) if ratio > 0 else 0.0
    if power != 0 and abs(ratio / 10.0 ** power - 1) < 0.01:
        times = f"{10.0 ** power:g}× |Z'+jZ''|" if power > 0 else f"|Z'+jZ''| / {10.0 ** -power:g}"
        return f"it holds {times} (median ratio), a unit mix-up (kΩ and Ω, or mΩ?)"
    return f"it holds {ratio:.4g}× |Z'+jZ''| (median ratio)"


def _wrapped(deg: np.ndarray) -> np.ndarray:
    """An angle difference [deg] brought into (-180, 180]; NaN for a cell that is not finite, without
    numpy's RuntimeWarning (a mutated REAL test_data.txt with an infinite phase printed one)."""
    with np.errstate(invalid="ignore"):
        return -((-deg + 180.0) % 360.0 - 180.0)


def polar_columns_note(*args, **kwargs) -> str | None:
    """``attrs["polar_columns_note"]`` of `polar_columns_attrs` (the same arguments), or ``None``
    when the columns agree."""
    return polar_columns_attrs(*args, **kwargs).get("polar_columns_note")


def polar_columns_attrs(
    z: np.ndarray,
    modulus: np.ndarray | None,
    phase_deg: np.ndarray | None,
    lines: Sequence[int],
    names: dict[str, str],
    scales: dict[str, float],
    printed: Callable[[np.ndarray], dict[str, Sequence[str]]],
    file_name: str,
    *,
    position: str = "line",
) -> dict[str, str]:
    """``{"polar_columns_note": …}``: where the |Z| column (``modulus`` [Ω]) or the phase column
    (``phase_deg``, in degrees and in the data model's sign) disagrees with Z = Z' + jZ'' beyond
    the rounding of the file's printed digits, and ``{FLIPPED_PHASE_KEY: phase column's name}``
    beside it when the phase column holds the opposite sign; ``{}`` when they agree. ``names``:
    the columns' header names by role (real, imag, modulus, phase); ``scales``: each one's factor
    to Ω or degrees; ``printed(rows)``: the printed cells of those rows by role, asked only for
    rows that differ by more than `MISMATCH_FLOOR` (|Z|) or `PHASE_FLOOR_DEG`; ``lines``: each
    row's place in the file, which ``position`` names: 'line' of a text file, 'row' of a
    spreadsheet (as its program numbers them), 'point' of a file of arrays (counted as points,
    and no column to rename is suggested: its names are the format's)."""
    z = np.asarray(z)
    notes = []
    attrs: dict[str, str] = {}
    rows_word = "points" if position == "point" else "rows"
    first_at = "at point" if position == "point" else f"on {position}"
    rename = "" if position == "point" else ": name the column '{}'"  # (a file of arrays has no header to edit)
    abs_z = np.abs(z)
    if modulus is not None:
        with np.errstate(divide="ignore", invalid="ignore"):
            rel = np.abs(modulus - abs_z) / np.maximum(abs_z, np.finfo(float).tiny)
        text = _disagreement(rel > MISMATCH_FLOOR, z, printed, scales, lines, "modulus", modulus)
        if text:
            rows, first = text
            ratio = float(np.median(modulus[rows] / np.maximum(abs_z[rows], np.finfo(float).tiny)))
            notes.append(f"column {names['modulus']!r} disagrees with |Z'+jZ''| from {names['real']!r} and {names['imag']!r} on "
                         f"{rows.size} of {z.size} {rows_word}, first {first_at} {lines[first]} of {file_name} ({modulus[first]:.6g} Ω there, "
                         f"|Z'+jZ''| {abs_z[first]:.6g} Ω): {_factor_text(ratio)}")
    if phase_deg is not None:
        angle = np.degrees(np.angle(z))
        off = np.abs(_wrapped(phase_deg - angle))
        text = _disagreement(off > PHASE_FLOOR_DEG, z, printed, scales, lines, "phase", phase_deg)
        if text:
            rows, first = text
            flipped = float(np.median(np.abs(_wrapped(phase_deg[rows] + angle[rows]))))
            as_radians = float(np.median(np.abs(_wrapped(phase_deg[rows] - np.radians(angle[rows])))))
            as_degrees_in_rad = float(np.median(np.abs(_wrapped(phase_deg[rows] - angle[rows] * 180 / np.pi))))  # (``angle`` is in degrees already)
            if flipped < 0.01 * max(float(np.median(off[rows])), 1e-12) or flipped < 0.05:
                why = OPPOSITE_SIGN_WORDS
                attrs[FLIPPED_PHASE_KEY] = names["phase"]
            elif as_radians < 0.05:
                why = "its values are radians read as degrees" + rename.format("Phase (rad)")
            elif as_degrees_in_rad < 0.05 * 180 / np.pi:
                why = "its values are degrees read as radians" + rename.format("Phase (deg)")
            else:
                why = f"off by up to {float(off[rows].max()):.3g}°"
            notes.append(f"column {names['phase']!r} disagrees with atan2(Z'', Z') from {names['real']!r} and {names['imag']!r} on "
                         f"{rows.size} of {z.size} {rows_word}, first {first_at} {lines[first]} of {file_name} ({phase_deg[first]:.6g}° there as read, "
                         f"atan2 {angle[first]:.6g}°): {why}")
    if not notes:
        return {}
    return {"polar_columns_note": "; ".join(notes) + ". Z is read from Z' and Z'' alone.", **attrs}


def _disagreement(candidate: np.ndarray, z, printed, scales, lines, role: str, value: np.ndarray) -> tuple[np.ndarray, int] | None:
    """The rows (indices) among ``candidate`` where ``value`` of ``role`` ('modulus' [Ω] or
    'phase' [deg]) differs from Z's beyond half a unit of the last printed digit of each cell
    involved (× `ROUNDING_MARGIN`), and the first of them; ``None`` when there is none."""
    rows = np.flatnonzero(candidate)
    if rows.size == 0:
        return None
    cells = printed(rows)
    half = {r: 0.5 * np.array([printed_resolution(c) for c in cells[r]]) * abs(scales[r]) for r in ("real", "imag", role)}
    zr, zi = np.abs(z[rows].real), np.abs(z[rows].imag)
    abs_z = np.maximum(np.abs(z[rows]), np.finfo(float).tiny)
    if role == "modulus":
        bound = half["modulus"] + (zr * half["real"] + zi * half["imag"]) / abs_z
        off = np.abs(value[rows] - np.abs(z[rows]))
    else:
        bound = half["phase"] + np.degrees((zi * half["real"] + zr * half["imag"]) / abs_z ** 2)
        off = np.abs(_wrapped(value[rows] - np.degrees(np.angle(z[rows]))))
    bad = rows[off > ROUNDING_MARGIN * bound + 1e-12 * np.maximum(np.abs(value[rows]), 1.0)]
    return (bad, int(bad[0])) if bad.size else None
