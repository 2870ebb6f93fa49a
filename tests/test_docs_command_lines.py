"""Every ``impedax …`` command line of the fenced shell blocks of README.md and docs/*.md, as a
user copies it: parsed by impedax's own argparse parser (fast: a flag renamed in the CLI fails
`make test` at once), and run in-process (slow) in an empty folder holding what a clone of the
repository holds under the paths the docs name (tests/fixtures, benchmarks/data, examples/data)
and a stand-in for each file of the user's own that the docs name (`STAND_INS`). A line runs
to exit code 0, or to the code and message its block shows below it (``impedax X: error: …``:
exit 2). The lines of one block run in order in one folder, as a user runs them: a file that one
line writes (``stack … --out days.nc``) is there for the next (``fit days.nc``)."""

from __future__ import annotations

import functools
import glob
import json
import re
import shlex
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from cli_run import run

ROOT = Path(__file__).resolve().parent.parent
DOC_FILES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
# the languages of the fenced blocks that show shell commands or their output ("" is a bare ```)
SHELL_FENCES = {"", "sh", "bash", "console", "shell", "text"}
# the folders of the repository that docs' command lines name, linked into the folder they run in
REPOSITORY_FOLDERS = ("tests/fixtures", "benchmarks/data", "examples/data")


@dataclass(frozen=True)
class DocLine:
    """One ``impedax …`` command line of a fenced block: where it stands, as written
    (continuation lines joined), its words after ``impedax`` (shell comment dropped), the shell
    comment, and the output lines its block shows below it (a ``$`` block's lines up to the
    next ``$``)."""

    doc: str
    line: int
    block: int
    text: str
    words: tuple[str, ...]
    comment: str
    shown: tuple[str, ...]

    @property
    def where(self) -> str:
        return f"{self.doc}:{self.line}"

    @property
    def command(self) -> str:
        return self.words[0]

    @property
    def synopsis(self) -> bool:
        """A usage synopsis (``impedax fit DATA --model M [--json] …``), not a line to run."""
        return any(w.startswith("[") for w in self.words)


def _blocks(path: Path):
    """(line of the opening fence, language, [(line number, text)]) of each fenced block."""
    fence, start, body = None, 0, []
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        opening = re.match(r"^\s*(`{3,}|~{3,})\s*([\w+-]*)", line)
        if opening and fence is None:
            fence, start, language, body = opening.group(1), number, opening.group(2).lower(), []
        elif fence is not None and line.strip().startswith(fence) and not line.strip().strip(fence[0]):
            yield start, language, body
            fence = None
        elif fence is not None:
            body.append((number, line))


def _comment(text: str) -> str:
    """The shell comment of ``text`` (from a ``#`` that begins a word outside quotes), or ""."""
    quote = None
    for k, char in enumerate(text):
        if quote:
            quote = None if char == quote else quote
        elif char in "'\"":
            quote = char
        elif char == "#" and (k == 0 or text[k - 1].isspace()):
            return text[k + 1:].strip()
    return ""


def doc_lines() -> list[DocLine]:
    """Every ``impedax …`` command line of the shell blocks of README.md and docs/*.md: in a
    block with ``$`` prompts the prompted lines (the others are their output), else every line
    that starts with ``impedax `` at its first column (an indented one is output text); and the
    command of a report's ``next: … impedax …`` line shown in such a block, up to its
    parenthesised comment."""
    found = []
    for path in DOC_FILES:
        doc = path.relative_to(ROOT).as_posix()
        for block, language, body in _blocks(path):
            if language not in SHELL_FENCES:
                continue
            prompted = any(text.startswith("$ ") for _, text in body)
            k = 0
            while k < len(body):
                number, text = body[k]
                k += 1
                command = text[2:] if prompted and text.startswith("$ ") else (None if prompted else text)
                if text.startswith("next: ") and "impedax " in text:  # (a report's advice, to be pasted as it is)
                    command = text[text.index("impedax "):].split(" (")[0]
                if command is None or not command.startswith("impedax "):
                    continue
                while command.rstrip().endswith("\\") and k < len(body):
                    command = command.rstrip()[:-1] + " " + body[k][1].strip()
                    k += 1
                shown = []
                while prompted and k < len(body) and not body[k][1].startswith("$ "):
                    shown.append(body[k][1])
                    k += 1
                words = tuple(shlex.split(command, comments=True))[1:]
                found.append(DocLine(doc, number, block, command.strip(), words, _comment(command), tuple(shown)))
    return found


LINES = doc_lines()

# Lines not run, each with its reason (a line's doc and the start of its text; each entry must
# match exactly one line). "long: parsed only": the run takes minutes; the fast test parses it.
NOT_RUN = {
    ("README.md", "impedax gap out/total_sliding.nc"): "long: parsed only (the hierarchical NUTS model of 30 trials, minutes)",
    ("docs/io.md", "impedax refine cycles.nc"): "long: parsed only (refine of a REAL battery cycle: 365 s on the 2-core machine at load 12)",
}


def _labels(path: str, dim: str) -> list[str]:
    import impedax as ix

    return [str(v) for v in ix.load(path)[dim].values]


# What a line's comment (or the sentence after its block) says it prints or writes, checked on
# its run: (doc, start of the line) → (the claim, a check of (stdout, stderr) in the line's folder).
CLAIMS = {
    ("docs/io.md", "impedax fit cycles.nc"): ("31 spectra, batch fit", lambda out, err: json.loads(out)["n_spectra"] == 31),
    ("docs/io.md", "impedax kk cycles.nc --select cycle=3,5,9"): (
        "three lines, in that order", lambda out, err: re.findall(r"^cycle=(\d+) ", out, re.M) == ["3", "5", "9"]),
    ("docs/io.md", "impedax drt cycles.nc --select cycle=100:"): (
        "cycle 100 and every later one", lambda out, err: re.findall(r"^  cycle=(\d+):", out, re.M) == [str(c) for c in range(100, 130)]),
    ("docs/kk.md", "impedax kk cycles.nc  "): (
        "a file of several spectra: one line each", lambda out, err: re.findall(r"^cycle=(\d+) ", out, re.M) == [str(c) for c in range(130)]),
    ("docs/io.md", "impedax stack data/day*.csv --dim day --out"): (
        "labels day01 … day10", lambda out, err: _labels("days.nc", "day") == [f"day{d:02d}" for d in range(1, 11)]),
    ("docs/io.md", "impedax stack data/day*.csv --dim day --coords"): (
        "labels 1 … 10", lambda out, err: _labels("days.nc", "day") == [str(d) for d in range(1, 11)]),
    ("docs/io.md", "impedax stack glass.nc"): (
        "Z over (material, voltage, frequency), 9 spectra",
        lambda out, err: _labels("edl.nc", "material") == ["glass", "wood", "paper"] and _labels("edl.nc", "voltage") == ["50.0", "100.0", "150.0"]),
}

# The files of the user's own that the docs name, each stood in for by a file of the same kind:
# name in the folder → (what stands in, why). A shipped file is copied; "synthetic: …" is made by
# `_make_synthetic`.
STAND_INS = {
    "cell.z": ("tests/fixtures/real/exampleDataZPlot.z", "README's own measurement: the REAL ZPlot file its next paragraph quotes"),
    "cell.csv": ("tests/fixtures/real/exampleData.csv", "docs/io.md's spectrum CSV: impedance.py's REAL example CSV"),
    "spectrum.csv": ("tests/fixtures/real/exampleData.csv", "a spectrum CSV: impedance.py's REAL example CSV"),
    "data.ods": ("tests/fixtures/real/data.ods", "docs/io.md's spreadsheet of 4 sheets: the shipped REAL one its message quotes"),
    "cycles.nc": ("benchmarks/data/autoeis_battery_130.nc", "docs/io.md's 130-cycle battery file: the REAL AutoEIS cycles"),
    "out/total_sliding.nc": ("synthetic: total_sliding", "the demo's SYNTHETIC files, as `impedax demo` writes them"),
    "out/skin.nc": ("synthetic: skin", "the demo's SYNTHETIC files"),
    "out/touchscreen.nc": ("synthetic: touchscreen", "the demo's SYNTHETIC files"),
    "TOTAL.nc": ("synthetic: total_sliding", "docs/models.md's three contact files: the demo's SYNTHETIC ones"),
    "SKIN.nc": ("synthetic: skin", "the demo's SYNTHETIC skin file"),
    "TS.nc": ("synthetic: touchscreen", "the demo's SYNTHETIC touchscreen file"),
    "PAD.nc": ("synthetic: total_sliding", "a single contact's trials: the demo's SYNTHETIC total"),
    "glass.nc": ("synthetic: material glass", "docs/io.md's per-material files over voltage 50, 100, 150"),
    "wood.nc": ("synthetic: material wood", "docs/io.md's per-material files over voltage"),
    "paper.nc": ("synthetic: material paper", "docs/io.md's per-material files over voltage"),
    "edl.nc": ("synthetic: edl", "docs/io.md's file over material and voltage (9 spectra)"),
    "data/day*.csv": ("synthetic: days", "docs/io.md's corrosion test, day01.csv … day10.csv"),
    "run1.csv": ("synthetic: gerischer", "docs/circuits.md's measurement for the plugin element"),
    "lab.py": ("docs/circuits.md: the ```python block that starts '# lab.py'", "the plugin file the docs show"),
}

_SYNTHETIC_FREQUENCY = np.logspace(5, -1, 31)


def _spectrum(r0, r1, q, alpha, frequency=_SYNTHETIC_FREQUENCY):
    """Z of R0 + R1 || CPE (Q [F s^(α−1)], α) at ``frequency``: SYNTHETIC, noise-free."""
    omega = 2 * np.pi * frequency
    return r0 + r1 / (1 + r1 * q * (1j * omega) ** alpha)


def _make_synthetic(what: str, path: Path) -> None:
    """The SYNTHETIC stand-in ``what`` of `STAND_INS`, written to ``path`` (``days``: the ten
    day files in ``path``'s folder)."""
    import impedax as ix
    from impedax.models import example_spectra

    if what in ("total_sliding", "skin", "touchscreen"):
        ix.save(example_spectra()[what], path)
    elif what.startswith("material "):
        scale = {"glass": 1.0, "wood": 3.0, "paper": 10.0}[what.split()[1]]
        voltages = [50.0, 100.0, 150.0]
        z = np.array([_spectrum(50.0, 1e4 * scale / (1 + v / 100), 1e-9, 0.9) for v in voltages])
        ix.save(ix.make_spectrum(_SYNTHETIC_FREQUENCY, z, dims="voltage", coords={"voltage": voltages}, attrs={"synthetic": "yes"}), path)
    elif what == "edl":
        for material in ("glass", "wood", "paper"):
            _make_synthetic(f"material {material}", path.parent / f"_{material}.nc")
        ix.save(ix.stack_files([path.parent / f"_{m}.nc" for m in ("glass", "wood", "paper")], dim="material",
                               coords=["glass", "wood", "paper"]), path)
        for material in ("glass", "wood", "paper"):
            (path.parent / f"_{material}.nc").unlink()
    elif what == "days":
        path.parent.mkdir(exist_ok=True)
        for day in range(1, 11):
            ix.save(ix.make_spectrum(_SYNTHETIC_FREQUENCY, _spectrum(20.0, 500.0 * (1 + 0.1 * day), 2e-5, 0.85), attrs={"synthetic": "yes"}),
                    path.parent / f"day{day:02d}.csv")
    elif what == "gerischer":
        omega = 2 * np.pi * _SYNTHETIC_FREQUENCY
        ix.save(ix.make_spectrum(_SYNTHETIC_FREQUENCY, 10.0 + 200.0 / np.sqrt(1 + 1j * omega * 2e-3), attrs={"synthetic": "yes"}), path)
    else:
        raise AssertionError(what)


def _python_file(doc: str, name: str) -> str:
    """The ```python block of ``doc`` whose first line is the comment ``# NAME …``."""
    for _, language, body in _blocks(ROOT / doc):
        if language == "python" and body and body[0][1].startswith(f"# {name}"):
            return "\n".join(text for _, text in body) + "\n"
    raise AssertionError(f"{doc} has no ```python block that starts '# {name}'")


@pytest.fixture(scope="module")
def stand_ins(tmp_path_factory) -> Path:
    """A folder of every stand-in of `STAND_INS`, made once."""
    folder = tmp_path_factory.mktemp("stand_ins")
    for name, (source, _) in STAND_INS.items():
        target = folder / name
        target.parent.mkdir(parents=True, exist_ok=True)
        if source.startswith("synthetic: "):
            _make_synthetic(source.removeprefix("synthetic: "), target)
        elif source.startswith("docs/"):
            target.write_text(_python_file(source.split(":")[0], name), encoding="utf-8")
        else:
            shutil.copyfile(ROOT / source, target)
    return folder


def _workspace(stand_ins: Path, folder: Path) -> Path:
    """``folder`` as a user's clone of the repository looks to the docs' lines: the shipped
    data folders linked under their paths, and a copy of every stand-in."""
    for relative in REPOSITORY_FOLDERS:
        (folder / relative).parent.mkdir(parents=True, exist_ok=True)
        (folder / relative).symlink_to(ROOT / relative, target_is_directory=True)
    shutil.copytree(stand_ins, folder, dirs_exist_ok=True)
    return folder


def _expanded(words) -> list[str]:
    """The words as the shell gives them: a word with ``*`` becomes the files it matches, sorted."""
    out = []
    for word in words:
        out += (sorted(glob.glob(word)) or [word]) if "*" in word else [word]
    return out


def _shown_error(line: DocLine) -> str | None:
    """The error message the block shows below ``line`` (``impedax X: error: …``), or None."""
    for text in line.shown:
        if text.startswith(f"impedax {line.command}: error: ") or text.startswith("impedax: error: "):
            return text
    return None


def _message_parts(shown: str) -> list[str]:
    """The parts of a shown message between the docs' ellipses ("..." or "…"), each to be found
    in the printed message in this order."""
    return [part.strip() for part in re.split(r"\.\.\.|…", shown) if part.strip(" ;,.()")]


def _not_run_reason(line: DocLine) -> str | None:
    return next((reason for (doc, start), reason in NOT_RUN.items() if line.doc == doc and line.text.startswith(start)), None)


# ---------------------------------------------------------------------------------------------
# fast: the lines are found, and every one parses


def test_the_docs_hold_the_command_lines_this_module_checks():
    """The extraction finds the lines (a change of the docs' fences must not leave it checking
    nothing), and every entry of `NOT_RUN` and `STAND_INS` names something that is there."""
    assert len(LINES) >= 40, [line.where for line in LINES]
    assert {line.doc for line in LINES} >= {"README.md", "docs/kk.md", "docs/io.md", "docs/models.md"}
    for doc, start in [*NOT_RUN, *CLAIMS]:
        assert sum(line.doc == doc and line.text.startswith(start) for line in LINES) == 1, (doc, start)
    words = {word for line in LINES for word in line.words}
    for name in STAND_INS:
        assert name in words, name


@functools.cache
def _parser(command: str | None):
    """impedax's parser with ``command`` built in full (None: every command)."""
    from impedax.cli import build_parser

    return build_parser(command)


def _options(command: str) -> set[str]:
    """The option words of ``impedax COMMAND`` (and impedax's own, such as ``--plugin``)."""
    parser = _parser(command)
    sub = next(a for a in parser._actions if a.dest == "command").choices[command]
    return set(sub._option_string_actions) | set(parser._option_string_actions)


def _parsed(words: list[str]):
    """``impedax *words`` through impedax's parser (no run): (namespace, unknown words); argparse's
    refusal is its SystemExit."""
    return _parser(words[0]).parse_known_args(words)


@pytest.mark.parametrize("line", [line for line in LINES if not line.synopsis], ids=lambda line: line.where)
def test_each_command_line_parses(line, capsys):
    """Each line is a command of impedax whose options its parser takes (a line shown failing
    fails later, when it reads its file or model)."""
    try:
        args, unknown = _parsed(list(line.words))
    except SystemExit:
        pytest.fail(f"{line.where}: {line.text}\n{capsys.readouterr().err}")
    assert unknown == [], f"{line.where}: {line.text}: not options of impedax {line.command}: {unknown}"
    assert args.command == line.command


@pytest.mark.parametrize("line", [line for line in LINES if line.synopsis], ids=lambda line: line.where)
def test_each_synopsis_names_options_of_its_command(line):
    """A usage synopsis (``impedax fit DATA --model M [--json] …``) names only options its
    command has."""
    flags = _flags(line.text)
    assert flags, line.text
    assert flags <= _options(line.command), f"{line.where}: not options of impedax {line.command}: {sorted(flags - _options(line.command))}"


def _flags(text: str) -> set[str]:
    return set(re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", text))


def inline_spans() -> list[tuple[str, int, str]]:
    """(doc, line, text) of every inline code span of README.md and docs/*.md outside the fenced
    blocks that starts ``impedax `` (a span wrapped over lines joined)."""
    spans = []
    for path in DOC_FILES:
        lines = path.read_text(encoding="utf-8").splitlines()
        for start, _, body in _blocks(path):  # (the blocks' lines blanked, the line numbers kept)
            for number in range(start, (body[-1][0] if body else start) + 2):
                lines[number - 1] = ""
        text = "\n".join(lines)
        for span in re.finditer(r"(?<!`)`(impedax [^`]+)`(?!`)", text):
            spans.append((path.relative_to(ROOT).as_posix(), text.count("\n", 0, span.start()) + 1, " ".join(span.group(1).split())))
    return spans


# inline spans that show impedax refusing a word (its message explained beside them): the doc, the span
SHOWN_REFUSED = {
    ("docs/bayesian.md", "impedax sample --weighting sigma"),
    ("docs/migrating.md", "impedax fit FILE --model 'R0-p(R1,CPE1)' --bounds CPE1_1=0.5:1"),
    ("docs/robustness.md", "impedax gap --fix"),
    ("docs/robustness.md", "impedax compare FILE --models A"),
    ("docs/robustness.md", "impedax info R1 --bogus"),
    ("docs/robustness.md", "impedax fitt {good} --model R1"),
    ("docs/robustness.md", "impedax fit {good} --model R1 --maxsteps 5"),
    ("docs/robustness.md", "impedax inspect {good} --bogus"),
    ("docs/robustness.md", "impedax demo --bogus"),
    ("docs/robustness.md", "impedax bogus"),
}
# the words after ``impedax`` that stand for any command in the docs' prose, or are no command
# (``impedax netCDF``, the format's name)
NOT_COMMANDS = {"COMMAND", "CMD", "netCDF"}


def test_each_inline_command_names_a_command_and_its_options():
    """Every inline ``impedax CMD …`` span of the docs' prose (a command line, an option or a
    message quoted) names a command of impedax and only options it has, but the spans that show
    impedax refusing them (`SHOWN_REFUSED`)."""
    spans = inline_spans()
    assert len(spans) >= 300, len(spans)
    commands = set(next(a for a in _parser(None)._actions if a.dest == "command").choices)
    wrong = []
    for doc, number, text in spans:
        words = text.split()[1:]
        while words and words[0] == "--plugin":  # (impedax's own option before the command)
            words = words[2:]
        command = words[0].rstrip(":,") if words else ""
        if command in NOT_COMMANDS or (doc, text) in SHOWN_REFUSED:
            continue
        if command not in commands:
            wrong.append(f"{doc}:{number}: `{text}`: {command!r} is no command of impedax")
        elif _flags(text) - _options(command):
            wrong.append(f"{doc}:{number}: `{text}`: not options of impedax {command}: {sorted(_flags(text) - _options(command))}")
    assert not wrong, "\n".join(wrong)
    assert {(doc, text) for doc, _, text in spans} >= SHOWN_REFUSED, SHOWN_REFUSED - {(doc, text) for doc, _, text in spans}


# ---------------------------------------------------------------------------------------------
# slow: every block's lines run in order in a folder of their own


def _blocks_to_run():
    by_block: dict[tuple[str, int], list[DocLine]] = {}
    for line in LINES:
        if not line.synopsis:
            by_block.setdefault((line.doc, line.block), []).append(line)
    return [pytest.param(lines, id=f"{doc}:{block}") for (doc, block), lines in by_block.items()]


def _json_words(comment: str) -> list[str]:
    """The quoted words of a ``--json`` line's comment that shows its JSON (``{"method":
    "linear", "valid", …}``): each a key of the printed JSON or one of its text values."""
    return re.findall(r'"(\w+)"', comment) if "{" in comment else []


@pytest.mark.slow
@pytest.mark.parametrize("lines", _blocks_to_run())
def test_each_block_runs_as_written(lines, stand_ins, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(_workspace(stand_ins, tmp_path))
    failures = []
    for line in lines:
        if _not_run_reason(line):
            continue
        written = [w for option, w in zip(line.words, line.words[1:]) if option in ("--out", "-o") and w != "-"]
        for path in written:  # (a stand-in of that name goes: what is read after the run is the line's)
            Path(path).unlink(missing_ok=True)
        code, out, err = run(_expanded(line.words), capsys)
        shown = _shown_error(line)
        expected = 2 if shown else 0
        if code != expected:
            failures.append(f"{line.where}: {line.text}\n  exit {code}, the docs say {expected}\n  {err.strip()[-2000:]}")
            continue
        if shown:
            printed = err.strip().splitlines()[0] if err.strip() else ""
            position = 0
            for part in _message_parts(shown):
                found = printed.find(part, position)
                if found < 0:
                    failures.append(f"{line.where}: {line.text}\n  shown:   {shown}\n  printed: {printed}\n  (missing: {part!r})")
                    break
                position = found + len(part)
        if code == 0 and not all(Path(path).is_file() for path in written):
            failures.append(f"{line.where}: {line.text}\n  exit 0 and no {written}")
        claim, holds = next((claim for (doc, start), claim in CLAIMS.items() if line.doc == doc and line.text.startswith(start)), (None, None))
        if claim and not holds(out, err):
            failures.append(f"{line.where}: {line.text}\n  the docs say {claim!r}; printed:\n{out[:1500]}")
        for word in _json_words(line.comment) if "--json" in line.words else []:
            summary = json.loads(out)
            if word not in summary and word not in {v for v in summary.values() if isinstance(v, str)}:
                failures.append(f"{line.where}: {line.text}\n  the comment's {word!r} is no key (nor text value) of the JSON: {sorted(summary)}")
    assert not failures, "\n\n".join(failures)
