"""The progress indication of the samplers (emcee's runs, the hierarchical NUTS run)."""

from __future__ import annotations

import sys
import time

from ...progress import terminal_line, terminal_width

LOG_INTERVAL = 1.0
"""Seconds between two progress lines when stderr is not a terminal (a log file, a pipe, CI):
each report is a line of its own there, so one a second (not every half second, as on a
terminal) keeps a log readable while it still moves visibly (at 10 s, a 20 000-step run looked
stuck at one step for 10 s)."""

LOG_SPACING = 0.1
"""Beyond `LOG_INTERVAL`, the lines in a log are at least this fraction of the run's time so far
(from its first step: a compilation before it does not count) apart,
so that their number grows with the logarithm of the run's length: a 400 s run (the Sirin example
with its long chains) wrote 400 lines at one a second, and writes 45 so."""


def announce(text: str, enabled) -> None:
    """One line saying what a run does before its first step (a start fit, a compilation:
    seconds without a progress line): on stderr when ``enabled`` is true, to ``enabled`` when it
    is a function of one line of text (``progress=print``, as `fit` takes it)."""
    if callable(enabled):
        enabled(text)
    elif enabled:
        sys.stderr.write(terminal_line(text, terminal_width(sys.stderr)) + "\n")  # (wrapped on a terminal only, as the reports on stdout)
        sys.stderr.flush()


class ProgressLine:
    """Progress of a run on stderr, shown only once the run has taken a second: one line
    rewritten in place every half second on a terminal; elsewhere (``interactive`` false: a
    log file or a pipe) a full line every `LOG_INTERVAL` (1) seconds, or every `LOG_SPACING` of
    the time since the first step when that is longer, and one at the end. A step
    costs one clock reading and two comparisons.
    ``interactive`` None: whether stderr is a terminal. ``enabled`` a function of one line of
    text (``progress=print``): each report is handed to it as a log's line would be written.

    A run of unknown length (``total`` the most steps it may take, ``open_ended`` true: emcee's
    ``steps="auto"``) shows the steps so far and the current estimate of the steps it needs
    (`set_target`) instead of a percentage, and the time to that estimate as the least time left
    ("≥ ~8 s left", from a second on): the estimate grows as τ's does, and τ must settle after it.

    ``settle``: the number of first steps that cost more than the rest (a NUTS warm-up before its
    first mass-matrix adaptation takes long trajectories: on the demo's hierarchical run, steps
    1–96 0.31 s each, steps 96–800 0.048 s). Until they are done the time left, from the rate so
    far, says so ("~223 s left at the warm-up's pace (faster from step 100)", not
    "≤ ~223 s left", a bound that grew 7× in a run on a busy machine); from then on it uses the rate since
    step ``settle`` alone (on the demo: "~43 s left" at step 152, 30 s before the end, where the
    rate since step 1 said ~146 s)."""

    def __init__(self, total: int, enabled, label: str = "impedax sample", interactive: bool | None = None, *, open_ended: bool = False, settle: int = 0):
        self.total, self.enabled, self.label, self.open_ended, self.settle = total, bool(enabled), label, open_ended, settle
        self.callback = enabled if callable(enabled) else None
        self.settled: tuple[float, int] | None = None  # (time, steps) when ``settle`` steps were first done
        self.interactive = False if self.callback is not None else (_is_terminal(sys.stderr) if interactive is None else interactive)
        self.done = 0
        self.target: int | None = None  # (open-ended runs) the steps the run needs, as last estimated
        self.target_note = ""
        self.t0 = time.perf_counter()
        self.last: float | None = None
        self.shown = False
        self.first: tuple[float, int] | None = None  # (time, steps) at the first report: compilation comes before it

    def set_target(self, steps: int | None, note: str = "") -> None:
        """The steps an open-ended run needs as estimated now and what the estimate is (``note``,
        e.g. "50 τ"); None with a ``note``: what the run waits for instead of a step count
        (None alone: not estimated yet)."""
        self.target, self.target_note = steps, note

    def update(self, done: int, *, final: bool = False) -> None:
        if not self.enabled:
            return
        now = time.perf_counter() - self.t0
        if self.first is None:
            self.first = (now, done)
        if self.settle and self.settled is None and done >= self.settle:
            self.settled = (now, done)
        self.done = done
        interval = 0.5 if self.interactive else max(LOG_INTERVAL, LOG_SPACING * (now - self.first[0]))
        last_step = final or done >= self.total
        if now < 1.0 or (self.last is not None and now - self.last < interval and not last_step):
            return
        self.last = now
        if self.callback is not None:
            self.callback(self.text(done, now))
        else:
            sys.stderr.write(f"\r{_in_place(self.text(done, now), terminal_width(sys.stderr))} " if self.interactive else self.text(done, now) + "\n")
            sys.stderr.flush()
        self.shown = True

    def text(self, done: int, now: float) -> str:
        """The progress line after ``done`` steps and ``now`` seconds."""
        since, steps = now - self.first[0], done - self.first[1]
        rate = since / steps if since > 0 and steps > 0 else None
        if not self.open_ended:
            pace = ""
            if self.settle:
                if self.settled is not None and done > self.settled[1]:
                    rate = (now - self.settled[0]) / (done - self.settled[1])
                else:  # (the costly first steps in the rate: more than is left, likely, but not a bound: a busier machine slows them further)
                    pace = f" at the warm-up's pace (faster from step {self.settle})"
            left = f", ~{(self.total - done) * rate:.0f} s left{pace}" if rate is not None and done < self.total else ""
            return f"{self.label}: step {done}/{self.total} ({100 * done / self.total:.0f} %), {now:.0f} s{left}"
        if self.target is None:
            goal = f"{self.target_note or 'steps needed not yet estimated'}; at most {self.total}"
        else:
            goal = f"≈{min(self.target, self.total)} needed{' for ' + self.target_note if self.target_note else ''}; at most {self.total}"
        # the time to the estimate is the least left, not the time left: the estimate grows as
        # τ's does and τ must settle after it ("~0 s left" was shown at 4 s of a 12 s run)
        least = (min(self.target, self.total) - done) * rate if rate is not None and self.target is not None else 0.0
        left = f", ≥ ~{least:.0f} s left" if least >= 1.0 else ""
        return f"{self.label}: step {done} ({goal}), {now:.0f} s{left}"

    def advance(self) -> None:
        """One more step done (for runs that report steps one at a time)."""
        self.update(self.done + 1)

    def close(self) -> None:
        """End the line; an open-ended run that stopped early reports its last step first
        (once the line has been shown)."""
        if self.shown and self.open_ended and self.done < self.total:
            self.update(self.done, final=True)
        if self.shown and self.interactive:
            sys.stderr.write("\n")
            sys.stderr.flush()


def _in_place(text: str, width: int | None) -> str:
    """A step line rewritten in place (``\\r``) on a terminal ``width`` columns wide (None: as it
    is), cut to fit with its space after it, ending in "…": a line the terminal wraps leaves its
    first rows behind at each rewrite (the hierarchical line ran to 130 characters), which
    wrapping it as `announce`'s lines are would do too."""
    if width is None or len(text) + 1 < width:
        return text
    return text[: width - 3] + "…"


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # a replaced or closed stream
        return False
