"""The checks of `gap_analysis`'s three inputs (total, skin, touchscreen) before any fit, each a
`DataError` naming the file (the data's ``source``) and how to fix it (docs/models.md,
"Inputs of the gap analysis"):

* sign: the physics of the gap analysis assumes passive, capacitive spectra, −Z'' > 0 over the
  band, for the total, the skin and the screen alike. A file whose trial mean has Z'' > 0 at
  more than half of its frequencies (`MAX_POSITIVE_SHARE`), or Z' < 0 there, looks stored with
  the opposite sign (`impedax.io.sign_check`: the same hint `impedax inspect` prints) and is
  refused: subtracting a conjugated spectrum gives a gap thickness off by any factor.
* frequencies: each file's frequencies are sorted (a descending sweep is the same grid) and the
  three grids must agree within `SWEEP_RTOL`, the tolerance the readers merge sweeps with;
  otherwise the file whose grid differs from the other two is named, with the first frequency
  that differs, and a constant ratio of 2π (rad/s read as Hz) or 10³ (kHz) is said as such.
  Grids that agree are all given the total's frequencies.
* identity: two of the three holding the same spectra (the same file given twice) are refused.

A single contact (an electroadhesive gripper pad, whose measured impedance is the
contact's own) gives neither skin nor touchscreen (None): the total is checked alone. Exactly one
of them is refused (`is_single_contact`, `ONE_PART_REFUSED`).

Every extra dimension of a file is averaged as replicates. A dimension whose name says nothing
of replicates (`REPLICATE_DIM_WORDS`: ``voltage``, ``material``) may be a condition, which the
average would mix: `condition_notes` warns of each and names ``--select DIM=LABEL``.

The drive V0 follows the data (`drive_voltage`): total spectra that carry one
voltage (a scalar coordinate or attribute whose name says voltage: `VOLTAGE_NAME_WORDS`, as a
``--select voltage=500`` leaves it) are analysed at that voltage, taken as the drive's peak
amplitude, unless V0 is given.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..data import label_value
from ..errors import IN_MEMORY, DataError, ParameterError
from ..fitting.least_squares.result import is_remainder
from ..io.sign_check import negative_real_evidence, negative_real_hint, opposite_sign_hint, swapped_evidence
from ..io.table import SWEEP_RTOL
from .sirin import SIRIN_DRIVE_V, joined_names

__all__ = ["GAP_INPUTS", "ONE_PART_REFUSED", "is_single_contact", "check_spectra", "present_inputs", "MAX_POSITIVE_SHARE", "REPLICATE_DIM_WORDS", "VOLTAGE_NAME_WORDS", "NOT_DRIVE_WORDS", "V0_SOURCES", "CarriedVoltage", "DriveVoltage", "carried_voltages", "check_gap_inputs", "condition_notes", "drive_voltage", "is_voltage_name", "position_notes", "spectra_used"]

GAP_INPUTS = ("total", "skin", "touchscreen")
MAX_POSITIVE_SHARE = 0.5
"""A gap input whose trial mean has Z'' > 0 (or Z' < 0) at more than this share of its
frequencies is refused as stored with the opposite sign."""
REPLICATE_DIM_WORDS = ("trial", "repeat", "repetition", "replicate", "rep", "cycle", "sweep", "session", "run", "scan", "measurement", "touch", "location", "site")
"""A dimension is taken for replicates without a word when a word of its name is one of these
(the name split at non-letters and at a lower-to-upper case change, a plural ``s`` dropped:
``trial``, ``trials``, ``trial_id``, ``sweepIndex``): the trials and sessions of docs/models.md,
the readers' ``sweep`` and ``cycle``, and their usual synonyms; ``location`` and ``site``: Sirin et al.
measured the touchscreen at 5 locations × 10 trials and the stationary total at five sites, to
cover the screen, and averaged them (such a file draws no condition warning).
``electrode`` is none: the paper's skin electrodes (hydrogel, metal) are a condition. Any other
dimension with more than one spectrum is averaged with a warning (`condition_notes`)."""
_SHOWN_LABELS = 5  # labels a condition warning lists before "…"
# the slips that scale a grid by a constant: (what the slip multiplies the numbers by, how the
# message writes the factor, what the slipped file holds)
_RATIOS = ((2 * math.pi, "2π", "angular frequency ω in rad/s stored as frequency in Hz: divide it by 2π (impedax reads the column as Hz)"),
           (1e-3, "1000", "kHz (or ms) where Hz is read: give the frequencies in Hz"))


def _named(name: str, data: xr.Dataset) -> str:
    source = data.attrs.get("source")
    return f"{name} ({source})" if source and source != "memory" else name  # (make_spectrum's default)


def _mean_spectrum(data: xr.Dataset) -> np.ndarray:
    z = data["Z"].transpose(..., "frequency").values
    return z.reshape(-1, z.shape[-1]).mean(axis=0)


def _check_sign(name: str, data: xr.Dataset) -> None:
    """`DataError` when ``data``'s trial mean looks stored with the opposite sign."""
    freq = np.asarray(data["frequency"].values, float)
    z = _mean_spectrum(data)
    n = z.size
    what = _named(name, data)
    real = negative_real_evidence(freq, z)
    positive = int(np.count_nonzero(z.imag > 0))
    if real is None and np.count_nonzero(z.real < 0) > MAX_POSITIVE_SHARE * n:
        real = f"Z' < 0 at {int(np.count_nonzero(z.real < 0))} of {n} points, which no passive impedance has"
    if real:
        hint = negative_real_hint(real, imaginary_too=positive > MAX_POSITIVE_SHARE * n, swapped=swapped_evidence(freq, z))
        raise DataError(f"{what}: {hint}; the gap analysis needs every spectrum as measured (passive, Z' > 0)")
    if positive > MAX_POSITIVE_SHARE * n:
        evidence = f"Z'' > 0 at {positive} of {n} points of the trial mean, where a {name} spectrum is capacitive (−Z'' > 0 over the band)"
        raise DataError(f"{what}: {opposite_sign_hint(evidence, data.attrs)}; the gap analysis assumes passive capacitive spectra and subtracts them, so a flipped sign gives a gap thickness off by any factor")


def _differs(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape != b.shape or bool(np.any(np.abs(a / b - 1) > SWEEP_RTOL))


def _first_difference(a: np.ndarray, b: np.ndarray) -> int:
    n = min(a.size, b.size)
    bad = np.flatnonzero(np.abs(a[:n] / b[:n] - 1) > SWEEP_RTOL)
    return int(bad[0]) if bad.size else n


def _ratio_note(odd: np.ndarray, other: np.ndarray, odd_name: str = "its", other_name: str = "the other two's") -> str:
    """A constant ratio of 2π or 10³ between the grids (either way), said as the likely slip,
    of the grid the slip explains: ω in rad/s is 2π × the Hz values, kHz read as Hz 1/1000 of
    them. ``odd_name``, ``other_name``: the two grids' owners, possessive."""
    if odd.shape != other.shape:
        return ""
    ratio = odd / other
    for slip, said, cause in _RATIOS:
        for value, slipped in ((slip, odd_name), (1 / slip, other_name)):
            if np.all(np.abs(ratio / value - 1) <= SWEEP_RTOL):
                word = "times" if value > 1 else "divided by"
                return f"; they are {other_name} {word} {said} at every point: {slipped} frequencies look like {cause}"
    return ""


def _grid_text(freq: np.ndarray) -> str:
    if freq.size == 1:  # (not "1 points, 0.031623–0.031623 Hz")
        return f"1 point, {freq[0]:.6g} Hz"
    return f"{freq.size} points, {freq[0]:.6g}–{freq[-1]:.6g} Hz" if freq.size else "no points"


def _outward(value: float, up: bool) -> str:
    """``value`` to 6 significant digits, rounded away from the band it bounds (up for its top),
    so that a band written with it keeps its end points."""
    text = f"{value:.6g}"
    if (float(text) < value) if up else (float(text) > value):
        unit = 10.0 ** (math.floor(math.log10(abs(value))) - 5)
        text = f"{float(text) + (unit if up else -unit):.6g}"
    return text


def _shared_band_note(grids: dict[str, np.ndarray]) -> str:
    """Where the grids agree point for point on the band all of them cover (a file measured over a
    narrower band than the others): the options that keep that band (`impedax gap`/`impedax
    remaining` --fmin/--fmax, Python ``data.where(…, drop=True)``, which holds in either order of
    the points: ``sel(frequency=slice(…))`` keeps nothing of a descending grid), else ""."""
    low = max(float(g.min()) for g in grids.values())
    high = min(float(g.max()) for g in grids.values())
    if not high >= low:
        return ""
    inside = [g[(g >= low * (1 - SWEEP_RTOL)) & (g <= high * (1 + SWEEP_RTOL))] for g in grids.values()]
    if any(_differs(g, inside[0]) for g in inside[1:]) or inside[0].size < 2:
        return ""
    options = " ".join(f"{o} {v:g}" for o, v, cut in (("--fmin", low, any(g.min() < low * (1 - SWEEP_RTOL) for g in grids.values())),
                                                      ("--fmax", high, any(g.max() > high * (1 + SWEEP_RTOL) for g in grids.values()))) if cut)
    return (f"; the grids agree on the {inside[0].size} frequencies {low:.6g}–{high:.6g} Hz that all of them cover: "
            f"impedax gap and impedax remaining keep that band with {options} (Python: each "
            f"data.where((data.frequency >= {_outward(low, up=False)}) & (data.frequency <= {_outward(high, up=True)}), drop=True))")


def _check_grids(named: dict[str, xr.Dataset]) -> None:
    """`DataError` naming the odd one out when the three sorted grids do not agree within
    `SWEEP_RTOL` (the majority of three; all three named when each differs)."""
    grids = {k: np.asarray(d["frequency"].values, float) for k, d in named.items()}
    names = list(grids)
    pairs = {(a, b): not _differs(grids[a], grids[b]) for i, a in enumerate(names) for b in names[i + 1:]}
    if all(pairs.values()):
        return
    agreeing = [p for p, same in pairs.items() if same]
    tolerance = f"within {SWEEP_RTOL:g} relative, the tolerance within which sweeps of one file merge"
    if agreeing:
        a, b = agreeing[0]
        odd = next(n for n in names if n not in (a, b))
        f_odd, f_ref = grids[odd], grids[a]
        i = _first_difference(f_odd, f_ref)
        if i < min(f_odd.size, f_ref.size):
            first = f"first differing at point {i + 1}: {f_odd[i]:.6g} Hz where {a} and {b} have {f_ref[i]:.6g} Hz"
        else:
            first = f"the first {i} frequencies agree, then {'it' if f_odd.size > f_ref.size else 'they'} go on"
        raise DataError(
            f"{_named(odd, named[odd])}: its frequencies differ from those of {a} and {b}, which agree "
            f"({odd}: {_grid_text(f_odd)}; {a} and {b}: {_grid_text(f_ref)}; {first}){_ratio_note(f_odd, f_ref)}; "
            f"measure all three on one frequency grid ({tolerance}){_shared_band_note(grids)}"
        )
    listed = "; ".join(f"{_named(n, named[n])}: {_grid_text(grids[n])}" for n in names)
    firsts = []
    for a, b in pairs:
        i = _first_difference(grids[a], grids[b])
        if i < min(grids[a].size, grids[b].size):
            slip = _ratio_note(grids[a], grids[b], a + "'s", b + "'s")
            firsts.append(f"{a} and {b} first differ at point {i + 1} ({grids[a][i]:.6g} vs {grids[b][i]:.6g} Hz){slip}")
    raise DataError(f"the frequencies of all three files differ ({listed}; {'; '.join(firsts)}); measure all three on one frequency grid ({tolerance}){_shared_band_note(grids)}")


def _check_distinct(named: dict[str, xr.Dataset]) -> None:
    """`DataError` when two inputs come from the same file or hold the same spectra."""
    names = list(named)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            da, db = named[a], named[b]
            pa, pb = da.attrs.get("path"), db.attrs.get("path")
            same_file = pa is not None and pa == pb and pa != "-"
            za, zb = da["Z"].transpose(..., "frequency").values, db["Z"].transpose(..., "frequency").values
            if same_file or (za.shape == zb.shape and np.array_equal(za, zb)):
                said = f"{a} and {b} are the same file, {pa}" if same_file else f"{_named(a, da)} and {_named(b, db)} hold identical spectra"
                raise DataError(
                    f"{said}: the gap analysis needs three different measurements "
                    "(TOTAL: finger on the screen, SKIN: the skin alone, TS: the touchscreen alone), given in that order"
                )


ONE_PART_REFUSED = (
    "give both the skin and the touchscreen spectra (the remainder total − skin − touchscreen, Sirin et al.), "
    "or neither (a single contact, e.g. a gripper pad on its target: the total is the contact's own impedance, nothing subtracted)"
)
"""Why a gap analysis with exactly one of skin and touchscreen is refused: the two are the
parts in series with the contact in Sirin et al.'s chain, and one alone says neither which
part was measured nor that the other is negligible."""


def is_single_contact(skin, touchscreen) -> bool:
    """True when neither ``skin`` nor ``touchscreen`` is given (None): a single contact, whose
    total is the contact's impedance; False when both are; exactly one is a `ParameterError`
    (`ONE_PART_REFUSED`)."""
    if (skin is None) != (touchscreen is None):
        given, missing = ("skin", "touchscreen") if touchscreen is None else ("touchscreen", "skin")
        raise ParameterError(f"a {given} spectrum without a {missing} spectrum: {ONE_PART_REFUSED}")
    return skin is None


def is_remainder_file(attrs) -> bool:
    """Whether a spectrum's ``attrs`` mark it a remainder Z_total − Z_skin − Z_TS that impedax
    wrote (`impedax remaining`, `gap --remaining`, the demo's remaining_impedance.nc): the paths
    of the three it came from (`REMAINDER_ATTRS`) or the trial counts of skin and touchscreen,
    and not a single contact's trial mean (``single_contact``)."""
    if str(attrs.get("single_contact", "0")) not in ("0", "False", "false"):
        return False
    return is_remainder(attrs) or ("n_trials_skin" in attrs and "n_trials_touchscreen" in attrs) or _subtracted_in_csv(attrs)


# the commands whose CSV spectrum is a remainder when its `source` column names a skin and a touchscreen
REMAINDER_COMMANDS = ("impedax remaining", "impedax gap")


def _subtracted_in_csv(attrs) -> bool:
    """Whether a CSV that impedax wrote is a remainder: a CSV keeps no attrs, but its provenance
    columns (`read_csv` lists them in ``other_columns``) say the command and the files; their first
    row, read from ``path``, names a skin and a touchscreen in ``source`` under `REMAINDER_COMMANDS`
    (else `impedax gap rem.csv` of `impedax remaining --out rem.csv` would be analysed as a single
    contact, with an overstated force, where rem.nc is refused)."""
    import csv
    from pathlib import Path

    columns = [c.strip() for c in str(attrs.get("other_columns", "")).split(",")]
    path = attrs.get("path")
    if "command" not in columns or "source" not in columns or not path or not Path(str(path)).is_file():
        return False
    try:
        with open(path, newline="", encoding="utf-8") as handle:
            header = handle.readline()
            rows = csv.DictReader([header, handle.readline()], delimiter="\t" if "\t" in header else ",")
            row = next(rows, None) or {}
    except (OSError, UnicodeDecodeError, csv.Error):
        return False
    source = str(row.get("source") or "")
    return str(row.get("command") or "").strip() in REMAINDER_COMMANDS and "skin=" in source and "touchscreen=" in source


def check_not_a_remainder(total, skin, touchscreen) -> None:
    """Refuse a remainder given as a single contact's total (`is_remainder_file`): its gap would
    take the whole drive V0, where it takes V0·Z_R/Z_total, and the force would be overstated (17 % at
    its peak, 2.6× at 2.5 kHz on the demo's remaining_impedance.nc, with no frequency dependence
    left). A `DataError` naming the file and the three spectra to give."""
    if skin is not None or touchscreen is not None or not is_remainder_file(total.attrs):
        return
    source = total.attrs.get("source") or total.attrs.get("path")
    made_from = [f"{k} {total.attrs[k]}" for k in ("total", "skin", "touchscreen") if k in total.attrs]
    raise DataError(
        "this is a remainder Z_total − Z_skin − Z_TS (" + (f"made from {', '.join(made_from)}" if made_from else "its provenance columns say so" if _subtracted_in_csv(total.attrs) else "its attributes say so")
        + "), not a single contact's total: the gap voltage is V0·Z_R/Z_total, so the force needs the total it was subtracted from. "
        "Give the three spectra (impedax gap TOTAL SKIN TOUCHSCREEN; impedax demo writes its own as total_sliding.nc, skin.nc and touchscreen.nc); "
        "the remainder alone is for impedax fit and sample (C_gap, whence u = ε0 ε_gap A / C_gap)",
        path=source,
    )


def check_spectra(total, skin, touchscreen) -> None:
    """Each input given (the total always; skin and touchscreen unless None) is a spectrum
    Dataset (`impedax.data.validate_spectrum`), else one `DataError` naming the input and what it
    is (`gap_analysis(None)` or a file name in place of a Dataset too, not an
    AttributeError from inside the checks)."""
    from ..arguments import shown
    from ..data import validate_spectrum

    for name, data in zip(GAP_INPUTS, (total, skin, touchscreen)):
        if data is None and name != "total":
            continue
        if not isinstance(data, xr.Dataset):
            read = " (a file name: read it with impedax.load first)" if isinstance(data, str) else ""
            raise DataError(f"{name}: expected a spectrum Dataset with complex 'Z' over 'frequency' (impedax.load, impedax.make_spectrum), got {shown(data)} ({type(data).__name__}){read}")
        source = str(data.attrs.get("source") or IN_MEMORY)
        validate_spectrum(data, source=name if source == IN_MEMORY else source)  # (a file's own name: `validate_spectrum` then says what changed since it was read)


def present_inputs(total, skin, touchscreen) -> dict[str, xr.Dataset]:
    """The inputs given, by name (`GAP_INPUTS`): the total alone for a single contact."""
    return {name: data for name, data in zip(GAP_INPUTS, (total, skin, touchscreen)) if data is not None}


def check_gap_inputs(total: xr.Dataset, skin: xr.Dataset | None, touchscreen: xr.Dataset | None) -> tuple[xr.Dataset, xr.Dataset | None, xr.Dataset | None]:
    """The three inputs checked (module docstring) and sorted by frequency, skin and screen on
    the total's frequencies; a `DataError` names the file at fault. ``skin`` and ``touchscreen``
    None: a single contact, the total checked alone (its sign), and None, None returned; exactly
    one of them None is a `ParameterError` (`is_single_contact`)."""
    is_single_contact(skin, touchscreen)
    given = present_inputs(total, skin, touchscreen)
    named = {name: data.sortby("frequency") for name, data in given.items()}
    for name, data in given.items():
        named[name].attrs = dict(data.attrs)
    _check_distinct(named)
    _check_grids(named)
    for name, data in named.items():
        _check_sign(name, data)
    freq = named["total"]["frequency"].values
    parts = (named[name].assign_coords(frequency=freq) if name in named else None for name in ("skin", "touchscreen"))
    return (named["total"], *parts)


def _label(data: xr.Dataset, dims: list[str], index: tuple[int, ...]):
    """The spectrum at ``index``'s label(s) as `label_value` gives them (text, a number, a date as
    ISO text), or its position along a dimension without labels."""
    values = [label_value(data[d].values[i]) if d in data.coords else i for d, i in zip(dims, index)]
    return values[0] if len(values) == 1 else values


def spectra_used(total: xr.Dataset, skin: xr.Dataset | None, touchscreen: xr.Dataset | None) -> dict[str, dict]:
    """Per input, the spectra (trials) the analysis uses: ``count``; ``dims``, the trial
    dimensions; ``labels``, one per spectrum (its label along the one dimension, or the list of
    its labels along ``dims``; a position where a dimension has no labels); ``by_position``, the
    dimensions a ``--select`` picked by position because the file has no labels along them
    (where another file's labels were meant, a different spectrum); ``source``, the file and
    selection. Only the inputs given (the total alone for a single contact)."""
    out = {}
    for name, data in present_inputs(total, skin, touchscreen).items():
        dims = [d for d in data["Z"].dims if d != "frequency"]
        shape = tuple(data.sizes[d] for d in dims)
        labels = [_label(data, dims, index) for index in np.ndindex(*shape)] if dims else []
        positional = [d for d in str(data.attrs.get("selected_by_position", "")).split(",") if d]
        out[name] = {"count": int(np.prod(shape)) if dims else 1, "dims": dims, "labels": labels, "by_position": positional, "source": data.attrs.get("source")}
    return out


def _name_words(dim: str) -> list[str]:
    """The words of a dimension name (`REPLICATE_DIM_WORDS`): split at non-letters and at a
    lower-to-upper case change, lower case, a plural ``s`` dropped."""
    words = re.findall(r"[A-Z]?[a-z]+|[A-Z]+(?![a-z])", re.sub(r"[^A-Za-z]+", " ", dim))
    return [w.lower()[:-1] if len(w) > 3 and w.lower().endswith("s") else w.lower() for w in words]


def is_replicate_dim(dim: str) -> bool:
    """True when a word of ``dim``'s name says it holds replicates (`REPLICATE_DIM_WORDS`)."""
    return any(w in REPLICATE_DIM_WORDS for w in _name_words(str(dim)))


def condition_notes(total: xr.Dataset, skin: xr.Dataset | None, touchscreen: xr.Dataset | None, *, default_v0: float | None = None) -> list[str]:
    """A warning for each extra dimension with more than one spectrum whose name says nothing
    of replicates (`is_replicate_dim`: ``voltage``, ``material``): the analysis averages it as
    replicates, so conditions would be mixed into one remainder (and, in ``impedax gap``, under
    one drive V0). Each names the files that have it, its labels, and ``--select DIM=LABEL``.
    ``default_v0`` [V]: the gap analysis's V0 is that default (none given, none carried,
    `drive_voltage`), said in the warning of a dimension of the total whose name says voltage."""
    found: dict[str, dict] = {}
    for name, data in present_inputs(total, skin, touchscreen).items():
        for dim in data["Z"].dims:
            if dim == "frequency" or data.sizes[dim] < 2 or is_replicate_dim(dim):
                continue
            entry = found.setdefault(dim, {"files": [], "labels": None})
            entry["files"].append(name)
            if entry["labels"] is None:
                entry["labels"] = [label_value(v) for v in data[dim].values] if dim in data.coords else list(range(data.sizes[dim]))
                entry["positions"] = dim not in data.coords
    notes = []
    for dim, entry in found.items():
        labels = [format(v, ".12g") if isinstance(v, float) else str(v) for v in entry["labels"]]
        shown = ", ".join(labels[:_SHOWN_LABELS] + (["…"] if len(labels) > _SHOWN_LABELS else []))
        what = f"{len(labels)} {'positions' if entry['positions'] else 'labels'}: {shown}"
        files = joined_names(entry["files"])
        notes.append(
            f"{dim} ({what}) of {files} is averaged as replicates together with the trials, although its name is none of a replicate dimension "
            f"({', '.join(REPLICATE_DIM_WORDS)}): if {dim} is a condition (a voltage, a material), the spectra of different conditions are mixed into one remainder; "
            f"analyse one at a time with --select {dim}=LABEL (Python: data.sel({dim}=LABEL)), e.g. --select {dim}={labels[0]}"
            + (f"; the force is computed at the default V0 = {default_v0:g} V, not at any of these voltages: a --select of one {dim} sets V0 to it, "
               "or give --v0 (Python: v0)" if default_v0 is not None and "total" in entry["files"] and is_voltage_name(dim) else "")
        )
    return notes


def position_notes(trials: dict[str, dict]) -> list[str]:
    """A warning for each dimension a ``--select`` picked by position in some files and by label
    in others (`spectra_used`): the same text then names different spectra."""
    notes = []
    dims = {d for used in trials.values() for d in used["by_position"]}
    for dim in sorted(dims):
        by_position = [n for n, used in trials.items() if dim in used["by_position"]]
        by_label = [n for n, used in trials.items() if dim in used["dims"] and dim not in used["by_position"]]
        if by_label:
            notes.append(
                f"--select {dim}=…: {' and '.join(by_position)} {'has' if len(by_position) == 1 else 'have'} no labels along {dim}, so the selection picked "
                f"0-based positions there but labels in {' and '.join(by_label)}: check that the same trials were meant (the report's 'spectra used')"
            )
    return notes


VOLTAGE_NAME_WORDS = ("voltage", "volt", "v")
"""A coordinate or attribute names a voltage when a word of its name (`_name_words`) is one of
these: ``voltage``, ``drive_voltage``, ``V0``, ``v_drive``, ``Volts``."""
NOT_DRIVE_WORDS = ("dc", "bias", "offset", "rms", "mv", "pp", "ocv", "ocp", "limit", "compliance", "max", "min", "range")
"""... and is still not the drive amplitude V0 when a word of its name is one of these: a DC bias
or offset (Gamry's ``VDC``, read as ``dc_voltage_v``), an rms or peak-to-peak value, or the
potentiostat's small-signal amplitude (Gamry's ``VAC``, ``ac_voltage_mv_rms``), a limit."""
_VOLTAGE_UNITS = {"V": 1.0, "volt": 1.0, "volts": 1.0, "kV": 1e3, "mV": 1e-3}  # a voltage label's units attribute → volts
_NUMBER_IN_VOLTS = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(kV|mV|V)?\s*$")  # "500", "500 V", "0.5 kV"
V0_SOURCES = ("data", "given", "default")
"""Where the gap analysis's V0 came from (`DriveVoltage.source`, the JSON's ``v0_from``)."""
V0_REL_TOL = 1e-3
"""A given V0 and the voltage the spectra carry agree within this relative tolerance (a label
of 500 and ``--v0 500.2``); beyond it a warning names both."""


def is_voltage_name(name: str) -> bool:
    """True when ``name`` says a drive voltage: a word of it in `VOLTAGE_NAME_WORDS`, none in
    `NOT_DRIVE_WORDS`."""
    words = _name_words(str(name))
    not_drive = any(w in NOT_DRIVE_WORDS or w + "s" in NOT_DRIVE_WORDS for w in words)  # (the words lose a final s: "bias" is "bia")
    return any(w in VOLTAGE_NAME_WORDS for w in words) and not not_drive


def _format_volts(voltage: float) -> str:
    """A voltage [V] to 4 significant digits, without trailing zeros (``500``, ``99.3``)."""
    return f"{voltage:.4g}"


@dataclass(frozen=True)
class CarriedVoltage:
    """A voltage the spectra carry: ``name`` (a scalar coordinate, or an attribute when
    ``attribute``), the ``label`` as stored and its ``value`` in volts (NaN when it is no number,
    or its units are not volts)."""

    name: str
    label: object
    value: float
    attribute: bool = False

    @property
    def text(self) -> str:
        """``voltage = 500`` (``V0 = 0.5 kV``): the name and label as the data hold them."""
        label = format(self.label, ".12g") if isinstance(self.label, float) else str(self.label)
        return f"{self.name} = {label}"

    @property
    def text_in_volts(self) -> str:
        """`text`, then the value in volts where the label alone does not give it (a label 0.5
        with units kV: ``voltage = 0.5, 500 V``)."""
        plain = _in_volts(self.label, None) == self.value
        return self.text if plain or not math.isfinite(self.value) else f"{self.text}, {_format_volts(self.value)} V"


def _in_volts(label, units) -> float:
    """``label`` (a number, or text such as ``"500 V"``) in volts given the ``units`` attribute
    (None: volts); NaN when it is no number or the units are no volts."""
    scale = 1.0 if units is None else _VOLTAGE_UNITS.get(str(units).strip())
    if scale is None:
        return math.nan
    if isinstance(label, (bool, np.bool_)):
        return math.nan
    if isinstance(label, (int, float, np.integer, np.floating)):
        return float(label) * scale
    match = _NUMBER_IN_VOLTS.match(str(label))
    if not match:
        return math.nan
    return float(match.group(1)) * (_VOLTAGE_UNITS[match.group(2)] if match.group(2) else scale)


def carried_voltages(data: xr.Dataset) -> list[CarriedVoltage]:
    """The voltages ``data`` carries (`is_voltage_name`): coordinates of one value (a scalar
    coordinate, as ``--select voltage=500`` or ``data.sel(voltage=500)`` leaves it, or a
    dimension of one label), then number or text attributes (``V0: 500``), each once."""
    out, seen = [], set()
    for name, coord in data.coords.items():
        if name == "frequency" or coord.size != 1 or not is_voltage_name(name):
            continue
        label = label_value(coord.values.reshape(-1)[0])
        out.append(CarriedVoltage(str(name), label, _in_volts(label, coord.attrs.get("units", coord.attrs.get("unit")))))
        seen.add(str(name))
    for name, label in data.attrs.items():
        if name in seen or not isinstance(label, (str, int, float, np.integer, np.floating)) or isinstance(label, (bool, np.bool_)) or not is_voltage_name(name):
            continue
        label = label_value(label) if not isinstance(label, str) else label
        out.append(CarriedVoltage(str(name), label, _in_volts(label, None), attribute=True))
    return out


@dataclass(frozen=True)
class DriveVoltage:
    """The drive amplitude V0 [V] of a gap analysis (`drive_voltage`): ``value``; ``source``, one
    of `V0_SOURCES`; ``carried``, the voltage the total spectra carry (None: none, or several
    that disagree); ``warnings``, what the report and the JSON repeat; ``selected``, the carried
    voltage is that of a ``--select``."""

    value: float
    source: str
    carried: CarriedVoltage | None = None
    warnings: tuple[str, ...] = ()
    selected: bool = False  # (the carried voltage is that of a --select: the note says "the selected total spectra")

    @property
    def note(self) -> str | None:
        """The one line ``impedax gap`` prints on stderr when V0 comes from the data."""
        if self.source != "data":
            return None
        return f"V0 = {_format_volts(self.value)} V, the voltage the {'selected ' if self.selected else ''}total spectra carry ({self.carried.text_in_volts}), taken as the drive's peak amplitude; give --v0 to override"

    @property
    def description(self) -> str:
        """Where V0 came from, for the report: the data's voltage is taken as the drive's peak
        amplitude, the amplitude of eq 1 (docs/physics.md)."""
        if self.source == "data":
            return (f"{_format_volts(self.value)} V, the voltage the total spectra carry ({self.carried.text_in_volts}), "
                    "taken as the drive's peak amplitude (eq 1); --v0 (Python: v0) overrides it")
        if self.source == "given":
            return f"{_format_volts(self.value)} V as given (--v0; Python: v0), the drive's peak amplitude"
        return f"{_format_volts(self.value)} V, the default (Sirin et al.'s drive): the total spectra carry no one voltage; --v0 (Python: v0) sets it"

    def summary(self) -> dict:
        """The JSON's ``v0_from`` and ``v0_carried`` (``name``, ``label``, ``value_v``; None)."""
        c = self.carried
        return {"v0_from": self.source, "v0_carried": None if c is None else {"name": c.name, "label": c.label, "value_v": c.value if math.isfinite(c.value) else None}}


def drive_voltage(total: xr.Dataset, v0: float | None = None) -> DriveVoltage:
    """The drive amplitude V0 [V] of the gap analysis of ``total`` (docs/models.md, "The drive
    V0 follows the data"): ``v0`` when given (a warning naming both when the total carries
    another voltage, beyond `V0_REL_TOL`); else the one voltage the total spectra carry
    (`carried_voltages`), taken as the peak amplitude of eq 1; else `SIRIN_DRIVE_V`, with a
    warning when the total carries voltages that cannot serve (several that disagree, a label
    that is no positive number of volts)."""
    carried = carried_voltages(total)
    values = {c.value for c in carried if math.isfinite(c.value)}
    one = carried[0] if carried and len(values) == 1 and all(math.isfinite(c.value) for c in carried) else None
    listed = ", ".join(c.text for c in carried)
    if v0 is not None:
        v0 = float(v0)
        if one is not None and not math.isclose(v0, one.value, rel_tol=V0_REL_TOL):
            return DriveVoltage(v0, "given", one, (
                f"v0 = {_format_volts(v0)} V (--v0; Python: v0) differs from the voltage the total spectra carry ({one.text_in_volts}): "
                f"the force is computed at the given {_format_volts(v0)} V; leave --v0 out to analyse at the data's {_format_volts(one.value)} V",))
        return DriveVoltage(v0, "given", one)
    default = SIRIN_DRIVE_V
    if one is not None and one.value > 0:
        selected = f"{one.name}=" in str(total.attrs.get("selection", ""))  # (`select_spectra` records ``DIM=LABEL``)
        return DriveVoltage(one.value, "data", one, selected=selected)
    if not carried:
        return DriveVoltage(default, "default")
    why = (f"voltages that disagree ({listed})" if len(values) > 1
           else f"{listed}, which is no positive drive amplitude in volts")
    return DriveVoltage(default, "default", None, (f"the total spectra carry {why}: V0 is the default {default:g} V; give --v0 (Python: v0)",))
