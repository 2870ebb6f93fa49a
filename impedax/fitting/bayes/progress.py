"""The one-line progress indication of the samplers (emcee's run, the hierarchical NUTS run)."""

from __future__ import annotations

import sys
import time


class ProgressLine:
    """A one-line progress indication on stderr, shown only once a run has taken a second."""

    def __init__(self, total: int, enabled: bool, label: str = "impedax sample"):
        self.total, self.enabled, self.label = total, enabled, label
        self.done = 0
        self.t0 = time.perf_counter()
        self.last = 0.0
        self.shown = False
        self.first: tuple[float, int] | None = None  # (time, steps) at the first report: compilation comes before it

    def update(self, done: int) -> None:
        if not self.enabled:
            return
        now = time.perf_counter() - self.t0
        if self.first is None:
            self.first = (now, done)
        if now < 1.0 or (now - self.last < 0.5 and done < self.total):
            return
        self.last = now
        since, steps = now - self.first[0], done - self.first[1]
        left = f", ~{(self.total - done) * since / steps:.0f} s left" if since > 0 and steps > 0 else ""
        sys.stderr.write(f"\r{self.label}: step {done}/{self.total} ({100 * done / self.total:.0f}%), {now:.0f} s{left} ")
        sys.stderr.flush()
        self.shown = True

    def advance(self) -> None:
        """One more step done (for runs that report steps one at a time)."""
        self.done += 1
        self.update(self.done)

    def close(self) -> None:
        if self.shown:
            sys.stderr.write("\n")
            sys.stderr.flush()
