"""The reports of fit, kk, drt and compare are wrapped at words on a terminal, as diagnose's and
refine's were (`impedax.cli.common.to_terminal`): on an 80-column terminal the REAL ZPlot file's
fit ran to 150 characters a line, kk's to 190, compare's notes to 300 (walkthrough 2026-12-07).
The words are those printed into a pipe, in the same order; the tables of compare and sample
keep their rows whole (sample's prior column runs past 80: wrapped, its rows broke in two); a
shell-quoted model in a "next:" line is not broken at its blanks."""

import io
import sys
from pathlib import Path

import pytest

from impedax.cli import main
from impedax.progress import terminal_text

ZPLOT = str(Path(__file__).resolve().parent / "fixtures" / "real" / "exampleDataZPlot.z")


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def printed(monkeypatch, argv, tty: bool) -> str:
    out = _Terminal() if tty else io.StringIO()
    monkeypatch.setattr(sys, "stdout", out)
    assert main(argv) == 0
    return out.getvalue()


@pytest.mark.parametrize("argv, table_rows", [
    (["fit", ZPLOT, "--model", "R0 + R1 || CPE1", "-q"], 0),
    (["kk", ZPLOT, "-q"], 0),
    (["drt", ZPLOT, "-q"], 0),
    (["compare", ZPLOT, "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "-q"], 3),
], ids=["fit", "kk", "drt", "compare"])
def test_a_report_on_an_80_column_terminal(monkeypatch, argv, table_rows):
    monkeypatch.setenv("COLUMNS", "80")
    piped = printed(monkeypatch, argv, tty=False)
    shown = printed(monkeypatch, argv, tty=True)
    assert max(map(len, piped.splitlines())) > 80  # (else there is nothing to wrap)
    lines = shown.splitlines()
    assert lines[:table_rows] == piped.splitlines()[:table_rows]
    assert all(len(line) <= 80 for line in lines[table_rows:]), [line for line in lines if len(line) > 80]
    assert [w for w in shown.split() if w != "\\"] == piped.split()


def test_samples_table_keeps_its_rows_and_the_rest_is_wrapped(monkeypatch):
    monkeypatch.setenv("COLUMNS", "80")
    argv = ["sample", ZPLOT, "--model", "R0 + R1 || C1", "--steps", "40", "-q"]
    piped, shown = printed(monkeypatch, argv, tty=False).splitlines(), printed(monkeypatch, argv, tty=True).splitlines()
    head = piped.index(next(line for line in piped if line.startswith("parameter ")))
    rows = piped[head: head + 5]  # (the header, R0, R1, C1, sigma_rel)
    assert [line.split()[0] for line in rows] == ["parameter", "R0", "R1", "C1", "sigma_rel"] and max(map(len, rows)) > 80
    assert shown[shown.index(rows[0]): shown.index(rows[0]) + 5] == rows
    assert all(len(line) <= 80 for line in shown if line not in rows)
    assert " ".join(shown).split() == " ".join(piped).split()


def test_a_quoted_model_is_kept_whole():
    line = "next: impedax diagnose /data/some/long/folder/exampleDataGamry.DTA --model 'R0 + R1 || C1' (where the model fails and what it misses)"
    wrapped = terminal_text(line, 80).splitlines()
    assert len(wrapped) > 1 and any("'R0 + R1 || C1'" in each for each in wrapped), wrapped
    assert " ".join(" ".join(wrapped).split()) == line
    assert terminal_text("the data's phase is 2° above the model's " * 4, 80).count("\n") >= 1  # (an apostrophe in prose is no quote: the line still wraps)


class _Logged(io.StringIO):
    """Standard output (a terminal or a pipe) or error, each write logged as (stream, text)."""

    def __init__(self, log, name, tty):
        super().__init__()
        self.log, self.name, self.tty = log, name, tty

    def write(self, text):
        self.log.append((self.name, text))
        return super().write(text)

    def isatty(self):
        return self.tty


def test_a_note_on_stderr_keeps_its_place_after_the_report(monkeypatch):
    """The REAL Parstat file's 781 DC rows are named on stderr after fit's report: into a pipe
    the note followed the report, on a terminal it came first (the wrapped report was held back
    until the block ended). Now it comes where it was printed on both."""
    monkeypatch.setenv("COLUMNS", "80")
    parstat = str(Path(ZPLOT).with_name("exampleDataParstat.txt"))
    orders = {}
    for tty in (False, True):
        log = []
        monkeypatch.setattr(sys, "stdout", _Logged(log, "out", tty))
        monkeypatch.setattr(sys, "stderr", _Logged(log, "err", False))
        assert main(["fit", parstat, "--model", "R0 + R1 || CPE1", "-q"]) == 0
        text = "".join(t for _, t in log)
        note = text.index("rows skipped as no impedance points")
        assert text.index("parameter ") < note  # (the report's table before the note)
        orders[tty] = [name for name, t in log if t.strip()]
    collapse = lambda names: [n for k, n in enumerate(names) if k == 0 or names[k - 1] != n]
    assert collapse(orders[True]) == collapse(orders[False])
