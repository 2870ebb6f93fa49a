"""Progress of a long computation, said to whoever asked for it: ``fit(..., progress=print)``
sets a callback for the call (`progress_to`), and the stages deep inside it (a batch's start
search, its local fits, its statistics) say what they begin (`say`) without a callback
threaded through every function between. A public call given no callback reports on stderr once it has
run `PROGRESS_AFTER_S` (`reported`), as the command line does. No JAX here."""

from __future__ import annotations

import contextlib
import contextvars
import functools
import io
import re
from typing import Callable, Iterator

__all__ = ["progress_to", "say", "silenced", "reporting", "reported", "reports_progress", "quiet_beneath", "progress_printer", "PROGRESS_AFTER_S", "DelayedPrinter", "SilentPrinter",
           "terminal_text", "terminal_width", "terminal_line", "MIN_TERMINAL_WIDTH"]

PROGRESS_AFTER_S = 2.0
"""Progress lines go to stderr once a run has taken this long (the CLI's and, by default, a
Python call's: `reported`)."""

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


def reporting() -> bool:
    """Whether an enclosing call has set a callback (`progress_to`, `silenced`)."""
    return _CALLBACK.get() is not None


@contextlib.contextmanager
def reported(progress) -> Iterator[Callable[[str], None] | None]:
    """The progress callback of a public call given ``progress``: a function is the caller's
    own; False, none (`SilentPrinter`); None outside any reporting call (`reporting`), lines on
    stderr once the call has run `PROGRESS_AFTER_S` (`progress_printer`), as the command line
    prints them: a first batch fit or a diagnosis would run 12-50 s silent in Python; None inside one, None (its callback stays). Within the block the
    calls beneath report nothing of their own (`silenced`) unless they are given this callback:
    a diagnosis says its stages, not those of each fit it makes, as on the command line."""
    if progress is None and reporting():
        yield None
        return
    printer = SilentPrinter() if progress is False else (progress_printer(PROGRESS_AFTER_S) if progress is None else progress)
    try:
        with silenced():
            yield printer
    finally:
        close = getattr(printer, "close", None)
        if progress is None and close is not None:
            close()


def reports_progress(function):
    """``function`` (a public call with a keyword ``progress``) given its callback by `reported`
    when no enclosing call reports (None: stderr after `PROGRESS_AFTER_S`; False: nothing); within
    an enclosing call, its ``progress`` as given (False: nothing)."""

    @functools.wraps(function)
    def call(*args, progress=None, **kwargs):
        if reporting():
            if progress is False:
                with silenced():
                    return function(*args, progress=None, **kwargs)
            return function(*args, progress=progress, **kwargs)
        with reported(progress) as printer:
            return function(*args, progress=printer, **kwargs)

    return call


def quiet_beneath(function):
    """``function`` (a public call that says its own progress: a sampler's lines) with the calls
    beneath it reporting nothing of their own (`silenced`) unless it gives them a callback, as
    before `reported` (its start fit would say "fitting …" after the sampler's own line)."""

    @functools.wraps(function)
    def call(*args, **kwargs):
        if reporting():
            return function(*args, **kwargs)
        with silenced():
            return function(*args, **kwargs)

    return call


MIN_TERMINAL_WIDTH = 40
"""Terminals narrower than this get every line as it is (`terminal_width`): wrapped to fewer
columns, a report would be more breaks than words."""

# a command inside a report line, after the prose that introduces it ("to apply 1. …: impedax fit FILE --model …")
_COMMAND = re.compile(r": (impedax (?:fit|refine) .*)$")
# the space between a number and its unit ("390 mHz", "2.8 %", "41.9 Ω"), which a wrapped line keeps
_UNIT_SPACE = re.compile(r"(\d) (?=(?:%|[pnµmkMG]?(?:Hz|Ω|F|H|s|V|A)\b))")
# a shell-quoted word of a command within prose ("next: impedax diagnose F --model 'R0 + R1 || C1'
# (where …)"), which a wrapped line keeps whole: broken at its blanks, a pasted line splits the model
_QUOTED = re.compile(r"(?<=[\s=])'[^'\s][^']*'(?=[\s),;]|$)")


def terminal_width(stream) -> int | None:
    """The columns of the terminal ``stream`` writes to: the environment's ``COLUMNS`` where set
    (as `shutil.get_terminal_size` reads it), else the terminal's own size (80 when it cannot be
    read); None when ``stream`` is no terminal (a pipe, a file, a closed or replaced stream) or
    one narrower than `MIN_TERMINAL_WIDTH`: its lines are then written as they are."""
    import os

    try:
        if not stream.isatty():
            return None
    except (AttributeError, ValueError):
        return None
    try:
        width = int(os.environ.get("COLUMNS", "0"))
    except ValueError:
        width = 0
    if width <= 0:
        try:
            width = os.get_terminal_size(stream.fileno()).columns
        except (AttributeError, ValueError, OSError, io.UnsupportedOperation):
            width = 80
    return width if width >= MIN_TERMINAL_WIDTH else None


def terminal_text(text: str, width: int) -> str:
    """The report ``text`` for a terminal ``width`` columns wide: each longer line's prose wrapped
    at words, its further lines hanging 4 columns under its own indentation; a command that ends a
    line (`_COMMAND`) on lines of its own, broken before its options, each line but the last
    ending in `` \\`` so that a shell pasted it reads one command. Lines within ``width`` stay as
    they are. The reports' lines ran to 700 characters on the REAL example files, which a
    terminal breaks mid-word (``impedax.cli.common.to_terminal``; progress lines:
    `terminal_line`)."""
    import textwrap

    out = []
    for line in text.splitlines():
        if len(line) <= width:
            out.append(line)
            continue
        indent = " " * (len(line) - len(line.lstrip(" ")))
        found = _COMMAND.search(line)
        prose, command = (line[:found.start() + 1], found.group(1)) if found else (line, "")
        if len(prose) > width:  # (a number kept with its unit: "near 390" and "mHz" on two lines read badly)
            kept = _QUOTED.sub(lambda m: m.group(0).replace(" ", "\u00a0"), _UNIT_SPACE.sub("\\1\u00a0", prose))
            out += [part.replace("\u00a0", " ") for part in textwrap.wrap(kept, width, subsequent_indent=indent + "    ", break_long_words=False, break_on_hyphens=False)]
        else:
            out.append(prose)
        if command:
            words = re.split(r" (?=--)", command)
            current = indent + "    " + words[0]
            for word in words[1:]:
                if len(current) + 1 + len(word) + 2 > width:
                    out.append(current + " \\")
                    current = indent + "      " + word
                else:
                    current += " " + word
            out.append(current)
    return "\n".join(out)


def terminal_line(line: str, width: int | None, lead: int = 0) -> str:
    """A progress ``line`` for a terminal ``width`` columns wide (`terminal_width`; None: as it
    is): wrapped as the reports are (`terminal_text`), its first ``lead`` characters (the time
    "[  1.5 s] " of a timed line) counted as indentation, so that its further lines hang under
    its text. The lines of diagnose, refine, gap and sample ran to 200 characters on stderr."""
    if width is None or len(line) <= width:
        return line
    return line[:lead] + terminal_text(" " * lead + line[lead:], width)[lead:]


def progress_printer(after_s: float = PROGRESS_AFTER_S, stream=None, *, quiet: bool = False):
    """A progress callback that prints its lines to stderr (``stream``) once ``after_s`` seconds
    have passed. The lines said before then are printed, in order and with their own times, at
    ``after_s`` or at the first line after it, whichever comes first (the first diagnosis says
    its line at 0 s and may run for several seconds): a slow run is never silent past
    ``after_s``, and every run starts with the same lines (keeping only the last of them,
    refine of AutoEIS's battery cycle 10 would begin at "[  1.8 s]   the DRT of the data…",
    without its step 0 and baseline lines). Its ``close()`` ends the wait; a line is printed at
    most once. ``quiet``: a printer that prints nothing (`SilentPrinter`)."""
    if quiet:
        return SilentPrinter()
    return DelayedPrinter(after_s, stream)


class SilentPrinter:
    """The progress callback of ``--quiet`` and ``progress=False``: every line dropped."""

    def __call__(self, text: str) -> None:
        pass

    def close(self) -> None:
        pass


class DelayedPrinter:
    """`progress_printer`'s callback: lines on stderr (``stream``) once ``after_s`` seconds have passed."""

    def __init__(self, after_s: float, stream=None) -> None:
        import threading
        import time

        self._clock = time.monotonic
        self._start = self._clock()
        self._after_s = after_s
        self._stream = stream
        self._lock = threading.Lock()
        self._pending: list[tuple[float, str]] = []  # the lines said before ``after_s``
        self._timer = threading.Timer(after_s, self._flush)
        self._timer.daemon = True
        self._timer.start()

    def _print(self, elapsed: float, text: str) -> None:
        import sys

        stream = self._stream or sys.stderr
        time = f"[{elapsed:5.1f} s] "
        print(terminal_line(time + text, terminal_width(stream), len(time)), file=stream, flush=True)  # (wrapped on a terminal only)

    def _flush(self) -> None:
        with self._lock:
            for line in self._pending:
                self._print(*line)
            self._pending = []

    def __call__(self, text: str) -> None:
        elapsed = self._clock() - self._start
        with self._lock:
            if elapsed > self._after_s:
                for line in self._pending:  # the timer has not run yet
                    self._print(*line)
                self._pending = []
                self._print(elapsed, text)
            else:
                self._pending.append((elapsed, text))

    def close(self) -> None:
        """No line after this: the run is over (its result is about to be printed)."""
        self._timer.cancel()
        with self._lock:
            self._pending = []
