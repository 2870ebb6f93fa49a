"""What README.md and docs/*.md state as facts of the command line, checked against what the
commands do, so that a claim cannot rot silently when a command changes."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from cli_run import run

DOCS = Path(__file__).resolve().parent.parent / "docs"


def _written_summary_keys() -> dict[str, set[str]]:
    """The keys docs/robustness.md ("JSON for programs") gives the `--json` summaries of `stack`,
    `simulate` and `remaining`: those every one has, and each command's besides (parenthesised
    words are descriptions and values, not keys)."""
    text = (DOCS / "robustness.md").read_text(encoding="utf-8")
    start = text.index("`stack`, `simulate` and `remaining` write files")
    paragraph = text[start : text.index("\n\n", start)]
    common_text, besides_text = paragraph.split("Every one has", 1)[1].split("Besides:", 1)
    besides_text = besides_text.split(". As\n", 1)[0]

    def keys(words: str) -> set[str]:
        while re.search(r"\([^()]*\)", words):
            words = re.sub(r"\([^()]*\)", "", words)
        return set(re.findall(r"`([a-z_]+)`", words))

    common = keys(common_text)
    pieces = re.split(r"`(stack|simulate|remaining)`", besides_text)
    return {command: common | keys(words) for command, words in zip(pieces[1::2], pieces[2::2])}


def test_the_json_summaries_of_the_writing_commands_have_the_keys_the_docs_list(tmp_path, capsys):
    """`impedax stack|simulate|remaining --out F --json` print exactly the keys docs/robustness.md
    lists (SYNTHETIC spectra: R0 + R1 ‖ C1 written with numpy, three trials of it for the single
    contact `remaining` takes alone). Until 2026-12-06 the docs left out stack's
    `frequencies_left_out` and remaining's `single_contact`."""
    documented = _written_summary_keys()
    assert set(documented) == {"stack", "simulate", "remaining"}
    freq = np.logspace(5, 0, 21)
    z = 10 + 100 / (1 + 2j * np.pi * freq * 1e-4)
    day1, day2 = tmp_path / "day1.csv", tmp_path / "day2.csv"
    ix.save(ix.make_spectrum(freq, z), day1)
    ix.save(ix.make_spectrum(freq, 1.1 * z), day2)
    trials = tmp_path / "pad.nc"
    ix.save(ix.make_spectrum(freq, np.stack([z, 1.02 * z, 0.98 * z]), dims="trial"), trials)
    commands = {
        "stack": ["stack", day1, day2, "--dim", "day", "--out", tmp_path / "days.nc"],
        "simulate": ["simulate", "R0 + R1 || C1", "--out", tmp_path / "sim.csv"],
        "remaining": ["remaining", trials, "--out", tmp_path / "rem.nc"],
    }
    for command, argv in commands.items():
        code, out, err = run([*argv, "--json"], capsys)
        assert code == 0, err
        printed = set(json.loads(out))
        assert printed == documented[command], (command, "undocumented:", printed - documented[command], "missing:", documented[command] - printed)


def _gap_table_keys() -> set[str]:
    """The top-level keys of docs/models.md's "Keys and units of the gap JSON" table: its first
    column, but the nested keys (in parentheses, after `parent:`, or `parent.key`)."""
    text = (DOCS / "models.md").read_text(encoding="utf-8")
    start = text.index("| key | unit |", text.index("**Keys and units of the gap JSON**"))
    keys = set()
    for row in text[start : text.index("\n\n", start)].splitlines()[2:]:
        cell = re.sub(r"\([^()]*\)", "", row.split("|")[1]).split(":")[0]
        keys |= {key for key in re.findall(r"`([a-z_0-9.]+)`", cell) if "." not in key}
    return keys


@pytest.mark.slow  # (an emcee run of the gap analysis: ~10–20 s on the 2-core machine)
def test_the_gap_json_keys_are_in_the_docs_table_of_keys_and_units(tmp_path, capsys):
    """Every top-level key of `impedax gap --json` (the SYNTHETIC shipped example, `--pooled`,
    a short chain) has its row in docs/models.md's table of keys and units, and every top-level
    key of the table is in the JSON (`provenance`, every command's, is docs/io.md's). Until
    2026-12-06 `edl_chi2_red`, `interval_covers`, `v0_from` and `v0_carried` were described in
    the prose only."""
    from impedax.models import example_spectra

    paths = []
    for name, spectrum in example_spectra().items():
        if name in ("total_sliding", "skin", "touchscreen"):
            paths.append(tmp_path / f"{name}.nc")
            ix.save(spectrum, paths[-1])
    code, out, err = run(["gap", *paths, "--area", "130e-6", "--pooled", "--steps", "200", "--json", "-q"], capsys)
    assert code == 0, err
    printed = set(json.loads(out)) - {"provenance"}
    documented = _gap_table_keys()
    assert printed - documented == set(), printed - documented
    assert documented - printed == set(), documented - printed
