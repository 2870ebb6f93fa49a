"""The warnings of a batch of fits as a few lines of text: one line per kind of warning (texts
that differ only in their numbers, or in the wording inside their brackets, are one kind, the
numbers shown as ranges), naming the spectra it applies to (or, when it applies to more than
half, the spectra it does not). `BatchFitResult.report` and the command line print them (no JAX here:
the command line's messages use it before anything heavy is imported)."""

from __future__ import annotations

import re
from typing import Mapping, Sequence

__all__ = ["grouped_warnings", "grouped_warning_tags", "warning_kinds", "MORE_KINDS", "labels_text", "label_shown", "key_shown", "scope_key", "WARNING_GROUPS_SHOWN", "LABELS_SHOWN"]

WARNING_GROUPS_SHOWN = 12  # kinds of warning a batch's text lists
LABELS_SHOWN = 8  # labels of a dimension shown in messages
# a number; not the power of ten a value and its error share, "(8.4 ± 1.6)e-15", which belongs to
# the wording: notes of 10x different scales were ranged as one, "(3.2 to 8.4 ± 0.5 to 1.6)e-14 to 15"
_NUMBER = re.compile(r"(?<![\w.])(?<![eE][-+])[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def label_shown(label) -> str:
    """A label as text writes it: as ``str``, but a float that ``str`` writes with binary noise
    to 12 significant digits (np.arange(6) * 0.1 labelled a spectrum "soc=0.30000000000000004",
    now "soc=0.3"; 0.5 and 0.0 stay as they are), also when it comes as that text (a spectrum's
    key, "0.30000000000000004": exactly the float's shortest form, so other text is left alone).
    For reports and messages; JSON keeps the exact value."""
    text = str(label)
    if isinstance(label, bool) or not isinstance(label, (float, str)):
        return text
    try:
        value = float(text)
    except ValueError:
        return text
    if repr(value) != text or value != value or value in (float("inf"), float("-inf")) or float(f"{value:.12g}") == value:
        return text
    short = f"{value:.12g}"
    return short if any(c in short for c in ".en") else f"{short}.0"


# a spectrum's key's labels: "d=LABEL" up to the next ", " or the end (`key_shown`)
_KEY_LABEL = re.compile(r"(?<==)([^=,]+)(?=, |$)")


def key_shown(key: str) -> str:
    """A spectrum's key ("cycle=3, soc=0.30000000000000004") with each label as `label_shown`
    writes it ("cycle=3, soc=0.3"), for text; the key itself stays what warnings are filed under."""
    return _KEY_LABEL.sub(lambda m: label_shown(m.group(1)), key)


def labels_text(labels: Sequence) -> str:
    """The first `LABELS_SHOWN` labels of a dimension (each as `label_shown` writes it), and how many there are when more."""
    labels = list(labels)
    shown = ", ".join(label_shown(v) for v in labels[:LABELS_SHOWN])
    return shown + (f", ... ({len(labels)} in all)" if len(labels) > LABELS_SHOWN else "")


# a quantity in a warning's text: a number, a space and a unit of `_SCALED_UNITS` with an SI
# prefix (``1.58 kHz``, as `impedax.data.format_frequency` writes frequencies; ``677 µΩ s^-1/2``,
# ``2.81 nF s^(α-1)``, as `impedax.data.format_quantity` writes parameters); the same quantity
# with another prefix is the same wording (`_template`), and a range of it is one value scale.
# Not only Hz: on the REAL 130 battery cycles above 3 kHz, "W1.sigma = 1.14 µΩ s^-1/2 runs to
# its lower bound 0" and the same note in nΩ and mΩ are one kind of warning, not three.
# The compound units first, so that a quantity takes its whole unit.
_SCALED_UNITS = ("Ω s^-1/2", "F s^(α-1)", "Hz", "Ω", "F", "H", "s")
_PREFIXES = {"T": 1e12, "G": 1e9, "M": 1e6, "k": 1e3, "": 1.0, "m": 1e-3, "µ": 1e-6, "u": 1e-6, "n": 1e-9, "p": 1e-12, "f": 1e-15}  # (SI prefixes, as impedax.data.SI_PREFIXES)
_QUANTITY = re.compile(r"(?<![\w.])([-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?) (" + "|".join(p for p in _PREFIXES if p) + r")?(" + "|".join(map(re.escape, _SCALED_UNITS)) + r")(?!\w)")
# a band of them: two quantities joined by a dash (``1 Hz – 5.01 Hz``, ``1 Hz–5 Hz``)
_BAND = re.compile(_QUANTITY.pattern + r"( ?[–-] ?)" + _QUANTITY.pattern)
# a value and its standard error, the prefix of the unit on both (``121 ± 66 mΩ``, as
# `impedax.data.format_uncertain` writes them): one scale, as a quantity's
_UNCERTAIN = re.compile(r"(?<![\w.(])([-+]?\d+(?:\.\d+)?) ± " + _QUANTITY.pattern[len(r"(?<![\w.])"):])
# what `_spread` reads: bands, then values with their errors, then lone quantities, then plain numbers
_SLOT = re.compile(f"(?P<band>{_BAND.pattern})|(?P<uncertain>{_UNCERTAIN.pattern})|(?P<quantity>{_QUANTITY.pattern})|(?P<number>{_NUMBER.pattern})")


def _quantity(number: str, prefix: str | None, unit: str) -> tuple[float, str, str]:
    """A quantity as (its value in ``unit``, its number as written, its prefixed unit)."""
    return float(number) * _PREFIXES[prefix or ""], number, (prefix or "") + unit


def _slots(text: str) -> tuple[list[str], list[tuple]]:
    """``text`` cut at its bands, quantities and numbers (`_SLOT`): the text between them (one
    more piece than slots), and each slot as ("band", low, high, dash), ("uncertain", value,
    error), ("quantity", q) or ("number", text), a quantity as `_quantity` gives it."""
    pieces, slots, start = [], [], 0
    for m in _SLOT.finditer(text):
        pieces.append(text[start : m.start()])
        start = m.end()
        if m.group("band"):
            low, high = _BAND.match(m.group("band")).groups()[:3], _BAND.match(m.group("band")).groups()[4:]
            slots.append(("band", _quantity(*low), _quantity(*high), _BAND.match(m.group("band")).group(4)))
        elif m.group("uncertain"):
            value, error, prefix, unit = _UNCERTAIN.match(m.group("uncertain")).groups()
            slots.append(("uncertain", _quantity(value, prefix, unit), _quantity(error, prefix, unit)))
        elif m.group("quantity"):
            slots.append(("quantity", _quantity(*_QUANTITY.match(m.group("quantity")).groups())))
        else:
            slots.append(("number", m.group("number")))
    return pieces + [text[start:]], slots


def _quantity_range(quantities) -> str:
    """Quantities (`_quantity`) as their range, the unit written once where both ends have it
    (``1.58–10 kHz``) and at each end where not (``800 Hz – 1.2 kHz``); one quantity where all
    are equal in value."""
    low, high = min(quantities), max(quantities)
    if low[0] == high[0]:
        return f"{low[1]} {low[2]}"
    if low[2] == high[2]:
        return f"{low[1]}–{high[1]} {low[2]}"
    return f"{low[1]} {low[2]} – {high[1]} {high[2]}"


def _band_range(bands) -> str:
    """Bands (low, high, dash) of one place in several spectra's warnings as one band: each
    spectrum's band written as it is where all are the same (``1 Hz – 5.01 Hz``); else the band
    that holds them all, then how its ends vary over the spectra, each end once with its unit
    (``1.58–100 kHz (the spectra's lower ends 1.58–10 kHz, upper ends 7.94–100 kHz)``)."""
    lows, highs = [b[0] for b in bands], [b[1] for b in bands]
    if len({q[0] for q in lows}) == 1 and len({q[0] for q in highs}) == 1:
        low, high, dash = bands[0]
        return f"{low[1]} {low[2]}{dash}{high[1]} {high[2]}"
    varying = [f"{end} ends {_quantity_range(qs)}" for end, qs in (("lower", lows), ("upper", highs)) if len({q[0] for q in qs}) > 1]
    return f"{_quantity_range([min(lows), max(highs)])} (the spectra's {', '.join(varying)})"


def _uncertain_range(pairs) -> str:
    """Values with their errors (two `_quantity`s) of one place in several spectra's warnings:
    in one prefix, each side's numbers ranged and the unit once (``121 to 170 ± 66 to 150 mΩ``,
    as before quantities other than Hz were read); in several, the values' range then the
    errors', each with its units (``61.5 nΩ – 121 mΩ ± 3 nΩ – 66 mΩ``)."""
    units = {error[2] for _, error in pairs}
    if len(units) == 1:
        ranged = [n[0] if len(set(n)) == 1 else f"{min(n, key=float)} to {max(n, key=float)}" for n in ([v[1] for v, _ in pairs], [e[1] for _, e in pairs])]
        return f"{ranged[0]} ± {ranged[1]} {units.pop()}"
    return f"{_quantity_range([v for v, _ in pairs])} ± {_quantity_range([e for _, e in pairs])}"


def _spread(texts: Sequence[str]) -> str:
    """One text for warnings that differ only in their numbers (and the SI prefixes of their
    quantities, `_template`): the numbers that differ become their range (``r = -0.993 to
    -0.990``), a quantity's with its unit once (``1.58–10 kHz``) and a band's as one band with
    how its ends vary (`_band_range`; not each end ranged number by number:
    "at 1.58 to 10 kHz – 7.94 to 100 kHz")."""
    if len(set(texts)) == 1:
        return texts[0]
    cut = [_slots(t) for t in texts]
    pieces, first = cut[0]
    if any(len(slots) != len(first) or [s[0] for s in slots] != [s[0] for s in first] for _, slots in cut):
        return texts[0]  # (not one wording: not reached, `_template` groups only texts of one)
    out = [pieces[0]]
    for i, piece in enumerate(pieces[1:]):
        column = [slots[i] for _, slots in cut]
        kind = column[0][0]
        if kind == "band":
            out.append(_band_range([s[1:] for s in column]))
        elif kind == "uncertain":
            out.append(_uncertain_range([s[1:] for s in column]))
        elif kind == "quantity":
            quantities = [s[1] for s in column]
            out.append(f"{quantities[0][1]} {quantities[0][2]}" if len(set(quantities)) == 1 else _quantity_range(quantities))
        else:
            numbers = [s[1] for s in column]
            ordered = sorted(numbers, key=float)
            out.append(numbers[0] if len(set(numbers)) == 1 else f"{ordered[0]} to {ordered[-1]}")
        out.append(piece)
    return "".join(out)


def _spectra_text(places: Sequence[str]) -> str:
    """Spectra named ``dim=label`` (one dimension: ``cycle 0, 64``) or ``a=1, b=2`` (several:
    joined with ``;``), the first `LABELS_SHOWN` and how many there are when more."""
    parts = [p.split("=", 1) for p in places]
    one_dim = all(len(p) == 2 and ", " not in p[1] for p in parts) and len({p[0] for p in parts}) == 1
    if one_dim:
        return f"{parts[0][0]} {labels_text([p[1] for p in parts])}"
    shown = "; ".join(key_shown(p) for p in places[:LABELS_SHOWN])
    return shown + (f"; ... ({len(places)} in all)" if len(places) > LABELS_SHOWN else "")


_SCOPE = re.compile(r"shared over (?P<over>[^()]*?)(?: \((?P<label>.*)\))?")  # (`scope_key`)


def scope_key(over: Sequence[str], label: str = "") -> str:
    """The key a global fit files its own notes under: ``shared over trial``, and with the labels
    of the group it is the fit of when the data have dimensions not shared over
    (``shared over cycle (group=a)``); not a spectrum's key, though it may hold ``=``."""
    return f"shared over {', '.join(over)}" + (f" ({label})" if label else "")


def _is_spectrum(key: str) -> bool:
    """Whether a warnings key names a spectrum (``cycle=3``), not a global fit (`scope_key`)."""
    return "=" in key and not _SCOPE.fullmatch(key)


def _scopes_text(scopes: Sequence[str]) -> str:
    """Global fits' keys (`scope_key`) as one text: each dimension set shared over once, with the
    groups it is over as spectra are named (`_spectra_text`): ``shared over cycle (group a, b)``
    for "shared over cycle (group=a)" and "shared over cycle (group=b)" (not counted as spectra
    with their labels cut at "=": "2 of 6 spectra: shared over cycle (group a), b)")."""
    by_over: dict[str, list[str]] = {}
    for key in scopes:
        m = _SCOPE.fullmatch(key)
        by_over.setdefault(m.group("over"), []).append(m.group("label") or "")
    parts = []
    for over, labels in by_over.items():
        labelled = [label for label in labels if label]
        parts.append(f"shared over {over}" + (f" ({_spectra_text(labelled)})" if labelled else ""))
    return "; ".join(parts)


def _places_text(places: Sequence[str]) -> str:
    """Keys of warnings named as `_spectra_text` names spectra, and global fits' keys as
    `_scopes_text`, the spectra first."""
    spectra = [p for p in places if _is_spectrum(p)]
    scopes = [p for p in places if not _is_spectrum(p)]
    return "; ".join(([_spectra_text(spectra)] if spectra else []) + ([_scopes_text(scopes)] if scopes else []))


def _segments(text: str) -> list[str] | None:
    """``text`` cut into the pieces outside and inside its top-level brackets, alternately (the
    first outside, possibly empty): ``"a (b (c)) d"`` → ``["a ", "(b (c))", " d"]``; None when its
    brackets do not pair up."""
    pieces, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch == "(":
            if depth == 0:
                pieces.append(text[start:i])
                start = i
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth < 0:
                return None
            if depth == 0:
                pieces.append(text[start : i + 1])
                start = i + 1
    return None if depth else pieces + [text[start:]]


def _template(text: str) -> str:
    """A text with its numbers as ``#`` and its quantities as ``# Hz`` whatever their SI prefix
    (`_QUANTITY`; ``1 Hz`` and ``1.58 kHz`` are one kind of warning): texts of one wording have
    one template."""
    return _NUMBER.sub("#", _QUANTITY.sub(lambda m: "# " + m.group(3), text))


def _kind_key(text: str) -> str:
    """The kind of a warning: its template outside its top-level brackets, each bracket's
    wording ignored (``(…)``), so one finding worded two ways by a detail in brackets is one kind
    (a CPE's correlated Q and α "both are still well determined (...)" or "their standard errors
    (...) already include the correlation", by the relative errors' side of
    `WELL_DETERMINED`); the whole template where the brackets do not pair up."""
    pieces = _segments(text)
    if pieces is None:
        return _template(text)
    return "".join(_template(p) if i % 2 == 0 else "(…)" for i, p in enumerate(pieces))


def _wordings(members: Sequence[tuple[str, str]]) -> list[list[tuple[str, str]]]:
    """The members of one kind by wording (template), the most frequent first."""
    groups: dict[str, list[tuple[str, str]]] = {}
    for place, text in members:
        groups.setdefault(_template(text), []).append((place, text))
    return sorted(groups.values(), key=len, reverse=True)


def _kind_text(members: Sequence[tuple[str, str]]) -> str:
    """One text for a kind: the numbers that differ as ranges (`_spread`); when it has several
    wordings, the most frequent one's brackets, the numbers outside them over every member, and
    after ``;`` each other wording's differing brackets with the spectra they are of
    (``…; in cycle 4, 14: (… their standard errors (10 %) already include the correlation)``)."""
    wordings = _wordings(members)
    if len(wordings) == 1:
        return _spread([t for _, t in members])
    cut = [[_segments(t) for _, t in w] for w in wordings]
    first = cut[0]
    out = []
    for i in range(len(first[0])):
        if i % 2 == 0 or all(_template(c[i]) == _template(first[0][i]) for w in cut for c in w):  # (outside, or one wording for all)
            out.append(_spread([c[i] for w in cut for c in w]))
        else:
            out.append(_spread([c[i] for c in first]))
    text = "".join(out)
    for wording, pieces in zip(wordings[1:], cut[1:]):
        differ = [i for i in range(1, len(first[0]), 2) if _template(pieces[0][i]) != _template(first[0][i])]
        places = list(dict.fromkeys(place for place, _ in wording))
        where = _places_text(places)
        text += f"; in {where}: " + " ".join(_spread([c[i] for c in pieces]) for i in differ)
    return text


def _kinds(warnings: Mapping[str, Sequence[str]]) -> list[list[tuple[str, str]]]:
    """The (spectrum, text) pairs of each kind of warning (texts equal but for their numbers
    and the wording in their brackets, `_kind_key`), the most frequent kind first."""
    groups: dict[str, list[tuple[str, str]]] = {}
    for place, texts in warnings.items():
        for text in dict.fromkeys(texts):
            groups.setdefault(_kind_key(text), []).append((place, text))
    return sorted(groups.values(), key=len, reverse=True)


def warning_kinds(warnings: Mapping[str, Sequence[str]]) -> list[dict]:
    """The warnings of a batch's spectra by kind, for JSON: each kind's text with the numbers
    that differ as ranges (as `grouped_warnings` prints it), the spectra it applies to and
    their number (and ``scope``: the keys that name no spectrum, a global fit's "shared over
    trial"); the most frequent kind first, every kind. A kind worded in several ways (by a
    detail in brackets, `_kind_key`) also has ``wordings``: each wording's text (numbers as
    ranges) and its spectra, the most frequent first; the wordings are one kind, not a kind each."""
    out = []
    for members in _kinds(warnings):
        places = list(dict.fromkeys(place for place, _ in members))
        spectra = [p for p in places if _is_spectrum(p)]  # (a global fit's own notes are filed under `scope_key`s)
        kind = {"warning": _kind_text(members), "spectra": spectra, "n_spectra": len(spectra)}
        if len(spectra) < len(places):
            kind["scope"] = [p for p in places if not _is_spectrum(p)]
        wordings = _wordings(members)
        if len(wordings) > 1:
            kind["wordings"] = [{"warning": _spread([t for _, t in w]), "spectra": list(dict.fromkeys(p for p, _ in w))} for w in wordings]
        out.append(kind)
    return out


MORE_KINDS = "... and {n} more kinds of warning (the result's warnings, and the JSON's, list every text)"


def grouped_warnings(warnings: Mapping[str, Sequence[str]], n_spectra: int, *, head: str = "warning", more: str = MORE_KINDS, spectra: Sequence[str] | None = None) -> list[str]:
    """The warnings of a batch's spectra (``{"cycle=0": (text, ...), ...}``) as text lines:
    one per kind of warning (`_kind_key`) with the spectra it applies to, the most frequent
    first, at most `WARNING_GROUPS_SHOWN`; a key that names no spectrum (a global fit's
    ``"shared over trial"``) is given as it is. ``spectra``: every spectrum's key, in order
    (`BatchFitResult.spectrum_keys`); given, a kind that applies to more than half of them names
    the others (``128 of 130 spectra: all but cycle 8, 14``); the only spectrum of a batch of
    one is named by its labels (``warning (cycle 0): ...``). ``head`` begins each line
    (``warning (2 of 3 spectra: ...): TEXT``); ``more`` is the closing line past the kinds
    shown, ``{n}`` their number."""
    ordered = _kinds(warnings)
    lines = []
    for members in ordered[:WARNING_GROUPS_SHOWN]:
        places = list(dict.fromkeys(place for place, _ in members))
        spectra_of = [p for p in places if _is_spectrum(p)]
        scopes = [p for p in places if not _is_spectrum(p)]
        if not spectra_of:  # not spectra: global fits' own notes (`scope_key`)
            where = _scopes_text(scopes)
        elif len(spectra_of) == n_spectra:
            # (one spectrum: named by its labels, as a batch's other lines name theirs; "the 1
            # spectrum" would say neither which nor that it is the only one)
            where = _spectra_text(spectra_of) if n_spectra == 1 else f"all {n_spectra} spectra"
        elif spectra is not None and 2 * len(spectra_of) > n_spectra and (others := [p for p in spectra if p not in set(spectra_of)]):
            where = f"{len(spectra_of)} of {n_spectra} spectra: all but {_spectra_text(others)}"
        else:
            where = f"{len(spectra_of)} of {n_spectra} spectra: {_spectra_text(spectra_of)}"
        if spectra_of and scopes:
            where += f"; {_scopes_text(scopes)}"
        lines.append(f"{head} ({where}): {_kind_text(members)}")
    if len(ordered) > WARNING_GROUPS_SHOWN:
        lines.append(more.format(n=len(ordered) - WARNING_GROUPS_SHOWN))
    return lines


def grouped_warning_tags(warnings: Mapping[str, Sequence[str]], tags: Mapping[str, Sequence[Sequence[str]]]) -> list[tuple[str, ...]]:
    """The tags of each line of `grouped_warnings` (same ``warnings``, in the same order; ``tags``:
    each spectrum's tags of its warnings, parallel to them): a kind's line carries the tags of the
    warnings it stands for, each once, in their order; the line past the kinds shown, those of
    the kinds it counts. A joint posterior's ``warning_tags`` (`SharedPosterior.summary`)."""
    of = {(place, text): tuple(t) for place, texts in warnings.items() for text, t in zip(texts, tags.get(place, ()))}

    def union(members) -> tuple[str, ...]:
        return tuple(dict.fromkeys(t for member in members for t in of.get(member, ())))

    ordered = _kinds(warnings)
    out = [union(members) for members in ordered[:WARNING_GROUPS_SHOWN]]
    if len(ordered) > WARNING_GROUPS_SHOWN:
        out.append(union(m for members in ordered[WARNING_GROUPS_SHOWN:] for m in members))
    return out
