"""What a fit's warnings say, as values set where they are made: each warning's tags
(`WARNING_TAGS`), so that other code (`compare`, the sampler, the gap analysis, a batch's
`misses_structure`) knows that a warning blames the model, or says that the data limit the fit,
without reading its words. The note makers (`result.misfit_notes`, `uneven_residual_notes`,
`sigma_scale_notes`) return `Note`s, texts that carry their tags; a fit keeps the tags of its
warnings in the same order (`FitResult.warning_tags`, `BatchFitResult.warning_tags` per spectrum;
docs/fitting.md, "What a warning says")."""

from __future__ import annotations

from typing import Iterable

__all__ = [
    "Note", "with_tag", "MISFIT", "MODEL_MISFIT", "DATA_LIMIT", "SIGN_HINT", "UNEVEN_NOISE", "SIGMA_RESIDUAL", "WARNING_TAGS", "tags_of", "has_tag", "tag_detail",
    "sign_hint_tag", "tagged", "notes_tags", "stored_tags", "tags_attr", "carried_over",
]

MISFIT = "misfit"
"""The misfit note of `result.misfit_notes` (or the note `compare` puts in its place), whatever it says."""
MODEL_MISFIT = "model_misfit"
"""Blames the model: it misses structure the data hold (`result.MODEL_MISFIT_MARKS` are its words)."""
DATA_LIMIT = "data_limit"
"""Says that the data's noise, drift or artifacts limit the fit, not only the model (`result.DATA_LIMIT_NOTE`)."""
SIGN_HINT = "sign_hint"
"""Ends with the Kramers–Kronig test's sign hint; the tag holds that end ("; " `result.SIGN_HINT_LEAD`
and the hint) after "=" (`sign_hint_tag`, `tag_detail`)."""
UNEVEN_NOISE = "uneven_noise"
"""Says that the weighted residuals are uneven across the band (`result.uneven_residual_notes`)."""
SIGMA_RESIDUAL = "sigma_residual"
"""Reads residuals below the data's σ, or uneven against it, as what σ is or as a σ misstating the
noise (`result.sigma_scale_notes`, `result.uneven_residual_notes` under sigma weighting)."""
WARNING_TAGS = (MISFIT, MODEL_MISFIT, DATA_LIMIT, SIGN_HINT, UNEVEN_NOISE, SIGMA_RESIDUAL)
"""Every tag a warning may carry; a warning may carry several (a data-limited misfit note with
a sign hint: `MISFIT`, `DATA_LIMIT`, `SIGN_HINT`)."""


class Note(str):
    """A warning's text that carries its ``tags`` (`WARNING_TAGS`). It is the text wherever a
    text is used (compared, joined, printed); a new text made from it (``note + "…"``, an
    f-string) is a new warning without tags."""

    tags: tuple[str, ...]

    def __new__(cls, text: str, tags: Iterable[str] = ()):
        note = super().__new__(cls, text)
        note.tags = tuple(tags)
        return note

    def __reduce__(self):  # (pickled with its tags: a batch's blocks under dask)
        return (Note, (str(self), self.tags))


def tags_of(warning) -> tuple[str, ...]:
    """The tags ``warning`` carries (a `Note`'s), () for a plain text."""
    return getattr(warning, "tags", ())


def has_tag(tags: Iterable[str], tag: str) -> bool:
    """Whether ``tags`` (one warning's) hold ``tag``, with or without a detail (`tag_detail`)."""
    return any(t == tag or t.startswith(tag + "=") for t in tags)


def tag_detail(tags: Iterable[str], tag: str) -> str:
    """The detail ``tag`` holds among ``tags`` ("tag=detail"), "" without one."""
    return next((t[len(tag) + 1:] for t in tags if t.startswith(tag + "=")), "")


def with_tag(notes, tag: str) -> tuple[str, ...]:
    """Those of ``notes`` whose tags hold ``tag``."""
    return tuple(n for n in notes if has_tag(tags_of(n), tag))


def sign_hint_tag(end: str) -> str:
    """The `SIGN_HINT` tag of a note that ends with ``end`` ("; hint: …")."""
    return f"{SIGN_HINT}={end}"


def tagged(warnings, tags) -> tuple[str, ...]:
    """``warnings`` as `Note`s with ``tags`` (one tuple per warning, `FitResult.warning_tags`);
    None: as they are."""
    if tags is None:
        return tuple(warnings)
    return tuple(Note(w, t) for w, t in zip(warnings, tags))


def notes_tags(notes) -> tuple[tuple[str, ...], ...]:
    """The tags of each of ``notes`` (`tags_of`)."""
    return tuple(tags_of(n) for n in notes)


def tags_attr(tags) -> list[list[str]] | None:
    """One fit's `FitResult.warning_tags` as a saved result's attribute (lists; None: not known)."""
    return None if tags is None else [list(t) for t in tags]


def stored_tags(stored, n_warnings: int) -> tuple[tuple[str, ...], ...] | None:
    """`tags_attr`'s lists read back (netCDF may store one warning's tags as a text, or none as an
    empty list); None where missing or not one entry per warning (a file edited since)."""
    if stored is None:
        return None
    if isinstance(stored, str):
        stored = [stored]
    rows = [(t,) if isinstance(t, str) else tuple(str(x) for x in t) for t in stored]
    return tuple(rows) if len(rows) == n_warnings else None


def carried_over(warnings, tags, given_with) -> bool:
    """Whether ``tags`` came with a result's other warnings, not its ``warnings``: ``given_with``
    is the (warnings, tags) the result it was made from held (`dataclasses.replace` copies it;
    None: a new result, or one `result.with_warnings` made), and the tags are those unchanged
    while the warnings are not (other words, another order). Such tags describe other words: the
    result keeps none (its words decide) or, for `Note`s, theirs."""
    return given_with is not None and tags is not None and tags == given_with[1] and warnings != given_with[0]
