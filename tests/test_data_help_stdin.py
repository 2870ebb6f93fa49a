"""Every argument naming a spectrum file to read says in its --help, in one wording, that '-' reads
standard input: until 2026-12-06 only inspect's FILE did, where fit, sample, kk, drt, compare, diagnose,
refine, gap, remaining, stack and simulate --frequencies read '-' as well."""

import argparse

import pytest

from impedax.cli import build_parser

from cli_run import run

SAID = "'-' reads standard input, recognised by content as a file is (a reader of your own that goes by the extension does not claim it)"
READING = {"fit", "sample", "kk", "drt", "compare", "diagnose", "refine", "gap", "remaining", "inspect", "stack", "simulate"}


def _data_arguments() -> dict[str, list[str]]:
    """Each command's arguments that name spectrum files to read: positionals DATA…/FILE, and --frequencies."""
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    found = {}
    for name, parser in sub.choices.items():
        names = [a.metavar for a in parser._actions if not a.option_strings and str(a.metavar).startswith(("DATA", "FILE"))]
        names += [a.option_strings[-1] for a in parser._actions if "--frequencies" in a.option_strings]
        if names:
            found[name] = names
    return found


ARGUMENTS = _data_arguments()


def test_every_command_that_reads_a_spectrum_is_found():
    assert set(ARGUMENTS) == READING
    assert ARGUMENTS["gap"] == ARGUMENTS["remaining"] == ["DATA_TOTAL", "DATA_SKIN", "DATA_TS"]


@pytest.mark.parametrize("command", sorted(READING))
def test_each_data_argument_says_what_dash_reads(capsys, command):
    code, out, _ = run([command, "--help"], capsys)
    assert code == 0
    text = " ".join(out.split())
    assert text.count(SAID) == len(ARGUMENTS[command]), (command, ARGUMENTS[command])
