"""Progress lines on stderr are wrapped to the terminal's width when stderr is a terminal, as the
reports on stdout are (`impedax.cli.diagnose.terminal_text`): the timed lines of diagnose and
refine (`progress.DelayedPrinter`), the lines that say what a sampler, gap or sample, begins
(`fitting.bayes.progress.announce`); the step line a terminal rewrites in place
(`ProgressLine`) is cut to the width instead, as a wrapped one would leave its first lines
behind at every rewrite. A pipe or a file gets every line as it was. No sampling here."""

from __future__ import annotations

import io
import sys

import pytest

from impedax.progress import DelayedPrinter, terminal_width

LONG = ("fitting 13 candidate circuits of 5 effects, then refitting the 5 leading candidates whose fits are still poor from 32 further starts each "
        "(a circuit's first fit compiles its solvers)")


class _Terminal(io.StringIO):
    """A stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def _words(text: str) -> list[str]:
    return text.split()


@pytest.fixture
def columns(monkeypatch):
    def set_to(n: int) -> int:
        monkeypatch.setenv("COLUMNS", str(n))
        return n

    return set_to


def test_timed_lines_are_wrapped_on_a_terminal_under_their_text(columns):
    width = columns(60)
    stream = _Terminal()
    printer = DelayedPrinter(0.0, stream)
    printer("  " + LONG)  # (refine's lines of a step are indented under it)
    printer.close()
    lines = stream.getvalue().splitlines()
    assert len(lines) > 2 and all(len(line) <= width for line in lines), lines
    assert lines[0].startswith("[") and "s]   fitting 13" in lines[0], lines[0]
    lead = lines[0].index("fitting")  # (the text's column: the time, then its own indentation)
    assert all(line.startswith(" " * (lead + 4)) and not line[lead + 4].isspace() for line in lines[1:]), lines
    assert _words(stream.getvalue())[3:] == _words(LONG)  # (every word, in order, after "[", "0.0", "s]")


def test_timed_lines_to_a_pipe_are_as_they_were(columns):
    columns(60)
    stream = io.StringIO()
    printer = DelayedPrinter(0.0, stream)
    printer(LONG)
    printer.close()
    (line,) = stream.getvalue().splitlines()
    assert line.endswith("] " + LONG)


def test_a_narrow_terminal_or_none_gives_no_width(columns):
    columns(39)
    assert terminal_width(_Terminal()) is None  # (as the reports: below 40 columns they are left as they are)
    columns(100)
    assert terminal_width(_Terminal()) == 100 and terminal_width(io.StringIO()) is None


def test_a_sampler_s_announcements_are_wrapped_on_a_terminal(columns, monkeypatch):
    from impedax.fitting.bayes.progress import announce

    width = columns(50)
    text = "impedax sample: " + LONG
    monkeypatch.setattr(sys, "stderr", _Terminal())
    announce(text, True)
    lines = sys.stderr.getvalue().splitlines()
    assert len(lines) > 2 and all(len(line) <= width for line in lines) and _words(sys.stderr.getvalue()) == _words(text), lines
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    announce(text, True)
    assert sys.stderr.getvalue() == text + "\n"


def test_the_step_line_rewritten_in_place_is_cut_to_the_width(columns, monkeypatch):
    from impedax.fitting.bayes.progress import ProgressLine

    width = columns(40)
    monkeypatch.setattr(sys, "stderr", _Terminal())
    bar = ProgressLine(100, True, label="impedax hierarchical (4 chains, warm-up 500 + draws 500)", interactive=True)
    bar.t0 -= 5.0  # (shown from a second on)
    bar.update(10)
    bar.update(100)
    bar.close()
    shown = [part for part in sys.stderr.getvalue().split("\r") if part]
    assert shown and all(len(part.rstrip("\n")) <= width - 1 for part in shown), shown  # (the cursor stays on the line)
    assert all(part.startswith("impedax hierarchical") for part in shown) and shown[-1].endswith("\n")
    assert "…" in shown[0]


def test_the_command_line_s_printer_wraps_on_a_terminal_stderr(columns, monkeypatch):
    """diagnose and refine print through `cli.common.progress_printer` to ``sys.stderr`` as it is
    when a line is printed."""
    from impedax.cli.common import progress_printer

    width = columns(70)
    monkeypatch.setattr(sys, "stderr", _Terminal())
    printer = progress_printer(0.0)
    printer(LONG)
    printer.close()
    lines = sys.stderr.getvalue().splitlines()
    assert len(lines) > 1 and all(len(line) <= width for line in lines), lines
