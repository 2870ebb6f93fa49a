"""The warnings of a batch of fits as a few lines of text: one line per kind of warning (texts
that differ only in their numbers are one kind, the numbers shown as ranges), naming the
spectra it applies to. `BatchFitResult.report` and the command line print them (no JAX here:
the command line's messages use it before anything heavy is imported)."""

from __future__ import annotations

import re
from typing import Mapping, Sequence

__all__ = ["grouped_warnings", "warning_kinds", "MORE_KINDS", "labels_text", "WARNING_GROUPS_SHOWN", "LABELS_SHOWN"]

WARNING_GROUPS_SHOWN = 12  # kinds of warning a batch's text lists
LABELS_SHOWN = 8  # labels of a dimension shown in messages
_NUMBER = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def labels_text(labels: Sequence) -> str:
    """The first `LABELS_SHOWN` labels of a dimension, and how many there are when more."""
    labels = list(labels)
    shown = ", ".join(str(v) for v in labels[:LABELS_SHOWN])
    return shown + (f", ... ({len(labels)} in all)" if len(labels) > LABELS_SHOWN else "")


def _spread(texts: Sequence[str]) -> str:
    """One text for warnings that differ only in their numbers: the numbers that differ
    become their range (``r = -0.993 to -0.990``)."""
    if len(set(texts)) == 1:
        return texts[0]
    numbers = [_NUMBER.findall(t) for t in texts]
    pieces = _NUMBER.split(texts[0])
    out = [pieces[0]]
    for i, piece in enumerate(pieces[1:]):
        column = [n[i] for n in numbers]
        if len(set(column)) == 1:
            out.append(column[0])
        else:
            ordered = sorted(column, key=float)
            out.append(f"{ordered[0]} to {ordered[-1]}")
        out.append(piece)
    return "".join(out)


def _spectra_text(places: Sequence[str]) -> str:
    """Spectra named ``dim=label`` (one dimension: ``cycle 0, 64``) or ``a=1, b=2`` (several:
    joined with ``;``), the first `LABELS_SHOWN` and how many there are when more."""
    parts = [p.split("=", 1) for p in places]
    one_dim = all(len(p) == 2 and ", " not in p[1] for p in parts) and len({p[0] for p in parts}) == 1
    if one_dim:
        return f"{parts[0][0]} {labels_text([p[1] for p in parts])}"
    shown = "; ".join(places[:LABELS_SHOWN])
    return shown + (f"; ... ({len(places)} in all)" if len(places) > LABELS_SHOWN else "")


def _kinds(warnings: Mapping[str, Sequence[str]]) -> list[list[tuple[str, str]]]:
    """The (spectrum, text) pairs of each kind of warning (texts equal but for their numbers),
    the most frequent kind first."""
    groups: dict[str, list[tuple[str, str]]] = {}
    for place, texts in warnings.items():
        for text in dict.fromkeys(texts):
            groups.setdefault(_NUMBER.sub("#", text), []).append((place, text))
    return sorted(groups.values(), key=len, reverse=True)


def warning_kinds(warnings: Mapping[str, Sequence[str]]) -> list[dict]:
    """The warnings of a batch's spectra by kind, for JSON: each kind's text with the numbers
    that differ as ranges (as `grouped_warnings` prints it), the spectra it applies to and
    their number (and ``scope``: the keys that name no spectrum, a global fit's "shared over
    trial"); the most frequent kind first, every kind."""
    out = []
    for members in _kinds(warnings):
        places = list(dict.fromkeys(place for place, _ in members))
        spectra = [p for p in places if "=" in p]  # (a global fit's own notes are filed under "shared over trial")
        kind = {"warning": _spread([t for _, t in members]), "spectra": spectra, "n_spectra": len(spectra)}
        if len(spectra) < len(places):
            kind["scope"] = [p for p in places if "=" not in p]
        out.append(kind)
    return out


MORE_KINDS = "... and {n} more kinds of warning (the result's warnings, and the JSON's, list every text)"


def grouped_warnings(warnings: Mapping[str, Sequence[str]], n_spectra: int, *, head: str = "warning", more: str = MORE_KINDS) -> list[str]:
    """The warnings of a batch's spectra (``{"cycle=0": (text, ...), ...}``) as text lines:
    one per kind of warning with the spectra it applies to, the most frequent first, at most
    `WARNING_GROUPS_SHOWN`; a key that names no spectrum (a global fit's ``"shared over
    trial"``) is given as it is. ``head`` begins each line (``warning (2 of 3 spectra: ...):
    TEXT``); ``more`` is the closing line past the kinds shown, ``{n}`` their number."""
    ordered = _kinds(warnings)
    lines = []
    for members in ordered[:WARNING_GROUPS_SHOWN]:
        places = list(dict.fromkeys(place for place, _ in members))
        if not any("=" in p for p in places):  # not spectra: a global fit's own notes ("shared over trial")
            where = "; ".join(places)
        else:
            where = ("the 1 spectrum" if n_spectra == 1 else f"all {n_spectra} spectra") if len(places) == n_spectra else f"{len(places)} of {n_spectra} spectra: {_spectra_text(places)}"
        lines.append(f"{head} ({where}): {_spread([t for _, t in members])}")
    if len(ordered) > WARNING_GROUPS_SHOWN:
        lines.append(more.format(n=len(ordered) - WARNING_GROUPS_SHOWN))
    return lines
