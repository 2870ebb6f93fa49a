"""Progress of a long computation, said to whoever asked for it: ``fit(..., progress=print)``
sets a callback for the call (`progress_to`), and the stages deep inside it (a batch's start
search, its local fits, its statistics) say what they begin (`say`) without a callback
threaded through every function between. No JAX here."""

from __future__ import annotations

import contextlib
import contextvars
from typing import Callable, Iterator

__all__ = ["progress_to", "say", "silenced"]

_CALLBACK: contextvars.ContextVar[Callable[[str], None] | None] = contextvars.ContextVar("impedax_progress", default=None)


@contextlib.contextmanager
def progress_to(callback: Callable[[str], None] | None) -> Iterator[None]:
    """Within the block, `say` calls ``callback`` with each line (None: the callback set around
    this block, if any, stays: a nested call without its own says to the outer one)."""
    if callback is None:
        yield
        return
    token = _CALLBACK.set(callback)
    try:
        yield
    finally:
        _CALLBACK.reset(token)


def say(text: str) -> None:
    """Tell the callback of the enclosing `progress_to`, if any, that ``text`` begins."""
    callback = _CALLBACK.get()
    if callback is not None:
        callback(text)


def silenced() -> contextlib.AbstractContextManager[None]:
    """Within the block, `say` says nothing: a stage made of smaller runs of the same code (a
    batch's start search fits its reference spectrum as a batch of one) is said once, by itself."""
    return progress_to(_quiet)


def _quiet(text: str) -> None:
    """`silenced`'s callback."""
