"""`impedax drt --out -` writes the CSV of γ over τ where `impedax kk --out -` writes the JSON
(docs/io.md); each --help says what '-' writes (kk's run checked here on the REAL BioLogic file).
A guard: both said it already on 2026-12-06."""

import json

from cli_run import run

DATA = "tests/fixtures/real/exampleDataBioLogic.mpt"


def _out_help(command, capsys):
    text = " ".join(run([command, "--help"], capsys)[1].split())
    return text[text.index("--out FILE"):]


def test_kk_help_and_run_say_json(capsys):
    assert "'-' the JSON to standard output" in _out_help("kk", capsys)
    code, out, _ = run(["kk", DATA, "--out", "-"], capsys)
    assert code == 0 and json.loads(out)["method"] == "linear"


def test_drt_help_says_csv(capsys):
    """(what the run writes: tests/test_robustness_outputs.py, the CSV on standard output)"""
    assert "'-' the CSV to standard output (--json prints the JSON)" in _out_help("drt", capsys)
