"""The progress indication of the samplers (emcee's runs, the hierarchical NUTS run)."""

from __future__ import annotations

import sys
import time

LOG_INTERVAL = 1.0
"""Seconds between two progress lines when stderr is not a terminal (a log file, a pipe, CI):
each report is a line of its own there, so one a second (not every half second, as on a
terminal) keeps a log readable while it still moves visibly (at 10 s, a 20 000-step run looked
stuck at one step for 10 s)."""


class ProgressLine:
    """Progress of a run on stderr, shown only once the run has taken a second: one line
    rewritten in place every half second on a terminal; elsewhere (``interactive`` false: a
    log file or a pipe) a full line every `LOG_INTERVAL` (1) seconds and one at the end. A step
    costs one clock reading and two comparisons.
    ``interactive`` None: whether stderr is a terminal."""

    def __init__(self, total: int, enabled: bool, label: str = "impedax sample", interactive: bool | None = None):
        self.total, self.enabled, self.label = total, enabled, label
        self.interactive = _is_terminal(sys.stderr) if interactive is None else interactive
        self.done = 0
        self.t0 = time.perf_counter()
        self.last: float | None = None
        self.shown = False
        self.first: tuple[float, int] | None = None  # (time, steps) at the first report: compilation comes before it

    def update(self, done: int) -> None:
        if not self.enabled:
            return
        now = time.perf_counter() - self.t0
        if self.first is None:
            self.first = (now, done)
        interval = 0.5 if self.interactive else LOG_INTERVAL
        if now < 1.0 or (self.last is not None and now - self.last < interval and done < self.total):
            return
        self.last = now
        since, steps = now - self.first[0], done - self.first[1]
        left = f", ~{(self.total - done) * since / steps:.0f} s left" if since > 0 and steps > 0 and done < self.total else ""
        text = f"{self.label}: step {done}/{self.total} ({100 * done / self.total:.0f}%), {now:.0f} s{left}"
        sys.stderr.write(f"\r{text} " if self.interactive else text + "\n")
        sys.stderr.flush()
        self.shown = True

    def advance(self) -> None:
        """One more step done (for runs that report steps one at a time)."""
        self.done += 1
        self.update(self.done)

    def close(self) -> None:
        if self.shown and self.interactive:
            sys.stderr.write("\n")
            sys.stderr.flush()


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # a replaced or closed stream
        return False
