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


README = DOCS.parent / "README.md"


def _number(text: str) -> tuple[float, float]:
    """A number as the README prints it and half a unit of its last digit (what rounding allows)."""
    decimals = len(text.split(".")[1]) if "." in text else 0
    return float(text.replace("−", "-")), 0.5 * 10.0**-decimals


def test_the_readme_quick_start_python_runs_and_prints_what_its_comments_say(tmp_path, monkeypatch):
    """README.md's quick-start block (SYNTHETIC: a spectrum computed from the circuit it parses,
    saved and read back) runs as written in an empty folder, and its comment on
    `parameter_names()` is what it prints."""
    text = README.read_text(encoding="utf-8")
    block = re.search(r"```python\n(import numpy as np\nimport impedax as ix\n\nix\.use_compilation_cache.*?)```", text, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    cache_calls: list = []  # (the real call would point JAX's cache for the whole test process at tmp_path)
    monkeypatch.setattr(ix, "use_compilation_cache", lambda path=None: cache_calls.append(path))
    printed: list = []
    scope = {"print": printed.append}
    exec(block, scope)
    commented = re.search(r"print\(circuit\.parameter_names\(\)\)\s+# (\(.*?\))", block).group(1)
    assert printed == [eval(commented)]
    assert (tmp_path / "spectrum.csv").is_file() and scope["data"].sizes["frequency"] == 61 and cache_calls == [None]


@pytest.mark.slow  # (a fit, a KK test and a diagnosis of 12 candidates: ~10 s)
def test_the_readme_quick_start_numbers_on_the_real_zplot_file():
    """The numbers README.md's quick start gives for the REAL ZPlot file, read from the README and
    checked to the digits it prints: the fit's rms_rel, the KK test's, the residuals over the
    noise, the lead inductance the diagnosis adds, the rms_rel it reaches and its ΔAIC."""
    text = " ".join(README.read_text(encoding="utf-8").split())
    sentence = text[text.index("On the REAL Scribner ZPlot file") :]
    pattern = (r"ends at rms_rel ([\d.]+) % while `kk` reaches ([\d.]+) %.*?the residuals are ([\d.]+)× the noise.*?"
               r"\(L_lead = ([\d.]+) µH\) lowers rms_rel to ([\d.]+) % \(ΔAIC ([−\d.]+)\)")
    fit_rms, kk_rms, ratio, inductance_uh, best_rms, delta_aic = map(_number, re.search(pattern, sentence).groups())
    data = ix.load(DOCS.parent / "tests" / "fixtures" / "real" / "exampleDataZPlot.z")
    fit = ix.fit("R0 + R1 || CPE1", data, progress=False)
    assert abs(100 * fit.rms_rel - fit_rms[0]) <= fit_rms[1]
    assert abs(100 * ix.kk_test(data).rms_rel - kk_rms[0]) <= kk_rms[1]
    d = ix.diagnose(data, "R0 + R1 || CPE1", progress=False)
    best = d.suggestions[0]
    assert best.effect == "series_inductance" and d.verdict == "missing_effect"
    assert abs(d.noise_ratio - ratio[0]) <= ratio[1]
    assert abs(1e6 * best.fit.values["L_lead"] - inductance_uh[0]) <= inductance_uh[1]
    assert abs(100 * best.fit.rms_rel - best_rms[0]) <= best_rms[1]
    assert abs(best.delta_aic - delta_aic[0]) <= delta_aic[1]


def test_the_readme_element_table_is_the_registry():
    """README.md's table of elements names every symbol of the default registry (an alias in its
    row: `CPE (alias Q)`) and, per element X, the parameters `X`, `X.Q`, ... the registry declares,
    in its order."""
    text = README.read_text(encoding="utf-8")
    start = text.index("| symbol | element | impedance |")
    rows = text[start : text.index("\n\n", start)].splitlines()[2:]
    symbols = set()
    for row in rows:
        cells = [cell.strip() for cell in row.strip("|").split("|")]
        row_symbols = re.findall(r"\b([A-Z][A-Za-z]*)\b", cells[0])
        symbols |= set(row_symbols)
        spec = ix.DEFAULT_REGISTRY[row_symbols[0]]
        assert tuple(re.findall(r"`([^`]+)`", cells[3])) == spec.parameter_names("X"), row
    assert symbols == set(ix.DEFAULT_REGISTRY.symbols())


@pytest.mark.slow  # (a refinement of the REAL ZPlot file and a fit from scratch: ~30 s)
def test_refine_help_says_how_the_final_fit_is_made_as_the_real_zplot_run_makes_it(capsys):
    """`impedax refine --help` said the final model "is refitted from scratch, as impedax fit
    does"; on the REAL ZPlot file from the default start the final fit is `ix.fit` from the
    loop's values (0.153 %), better than the fit of the final model from scratch (0.213 %), and
    the help says that case too."""
    code, out, _ = run(["refine", "--help"], capsys)
    assert code == 0
    help_text = " ".join(out.split())
    assert "refitted from scratch, as impedax fit does, or, where that ends worse than the loop's fit, from the loop's values" in help_text
    data = ix.load(DOCS.parent / "tests" / "fixtures" / "real" / "exampleDataZPlot.z")
    refinement = ix.refine(data, progress=False)
    scratch = ix.fit(refinement.final.circuit, data, progress=False)
    assert refinement.final_from_values and refinement.final.rms_rel < 0.99 * scratch.rms_rel


def test_the_fit_signature_docs_fitting_md_gives_is_ix_fit_s():
    """docs/fitting.md opens with `impedax.fit(...)`'s signature: its keywords, in order, with the
    defaults it writes (registry's by name), are those of `ix.fit` (until 2026-12-06 it left out
    `progress=None`)."""
    import inspect

    text = " ".join((DOCS / "fitting.md").read_text(encoding="utf-8").split())
    written = re.search(r"`impedax\.fit\((circuit, data, \*, .*?)\)`", text).group(1)
    documented = [part.strip() for part in written.split(",")]
    assert [d.split("=")[0] for d in documented if d != "*"] == list(inspect.signature(ix.fit).parameters)
    for entry in documented:
        if "=" in entry:
            name, default = entry.split("=", 1)
            expected = inspect.signature(ix.fit).parameters[name].default
            assert default == ("DEFAULT_REGISTRY" if expected is ix.DEFAULT_REGISTRY else repr(expected).replace("'", '"')), entry


def _heading_anchors(path: Path) -> set[str]:
    """The anchors GitHub gives the headings of a Markdown file: lower case, punctuation but `-`
    and `_` dropped, spaces as `-`, a repeated heading suffixed `-1`, `-2`, ..."""
    anchors, seen = set(), {}
    text = re.sub(r"```.*?```", "", path.read_text(encoding="utf-8"), flags=re.S)
    for heading in re.findall(r"^#+\s+(.*)$", text, flags=re.M):
        slug = re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")
        anchors.add(slug if slug not in seen else f"{slug}-{seen[slug]}")
        seen[slug] = seen.get(slug, 0) + 1
    return anchors


def test_every_link_of_the_docs_leads_somewhere():
    """Each relative link of README.md, docs/*.md and benchmarks/*.md names a file of the
    repository and, into a Markdown file, a heading it has (a renamed section leaves no link
    that lands at the top of the page)."""
    root = DOCS.parent
    broken = []
    for page in [root / "README.md", *sorted((root / "benchmarks").glob("*.md")), *sorted(DOCS.glob("*.md"))]:
        text = re.sub(r"```.*?```", "", page.read_text(encoding="utf-8"), flags=re.S)
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"[a-z]+:", target):
                continue
            path, _, anchor = target.partition("#")
            linked = (page.parent / path).resolve() if path else page
            if not linked.exists() or (anchor and linked.suffix == ".md" and anchor not in _heading_anchors(linked)):
                broken.append(f"{page.relative_to(root)}: {target}")
    assert not broken, broken


@pytest.mark.slow  # (two batch fits of the 130 REAL cycles: ~20 s)
def test_the_readme_medians_over_all_130_battery_cycles():
    """README.md's benchmark paragraph quotes impedance.py's and impedax's medians over the cycles
    both tools fitted (a spread of the 130, benchmarks/README.md) and, since 2026-12-06, the
    medians a user's batch fit of all 130 REAL cycles gives; the latter are checked here to the
    digits printed (numpy's median of the batch's rms_rel)."""
    text = " ".join(README.read_text(encoding="utf-8").split())
    with_w, with_wo = map(_number, re.search(r"The medians over all 130 cycles, .*? are ([\d.]+) % with `W1` and ([\d.]+) % with `Wo1`", text).groups())
    cycles = ix.load(DOCS.parent / "benchmarks" / "data" / "autoeis_battery_130.nc")
    for tail, (quoted, tolerance) in (("W1", with_w), ("Wo1", with_wo)):
        batch = ix.fit(f"R0 + R1 || CPE1 + R2 || CPE2 + {tail}", cycles, progress=False)
        assert abs(100 * float(np.median(batch.to_xarray()["rms_rel"].values)) - quoted) <= tolerance, tail


@pytest.mark.slow  # (a short emcee run among the commands: ~10 s)
def test_the_commands_robustness_md_says_have_warnings_have_the_key(tmp_path, capsys):
    """docs/robustness.md ("JSON for programs") names the commands whose `--json` has a top-level
    `warnings` list; each has it (SYNTHETIC R0 + R1 ‖ C1 spectrum), and `compare`, which it says
    has one too (each model's `models[].warnings` with its label; until 2026-12-06 it had none:
    a program's `warnings == []` check raised KeyError there)."""
    text = " ".join((DOCS / "robustness.md").read_text(encoding="utf-8").split())
    sentence = re.search(r"never renamed or removed\. (.*?) have it:", text).group(1)
    commands = [word for word in re.findall(r"`(\w+)`", sentence) if word not in ("warnings", "notes")]
    assert {"fit", "kk", "drt"} <= set(commands)
    freq = np.logspace(5, -1, 25)
    path = tmp_path / "rc.csv"
    ix.save(ix.make_spectrum(freq, 10 + 100 / (1 + 2j * np.pi * freq * 1e-3)), path)
    model = ["--model", "R0 + R1 || C1"]
    argv = {"fit": model, "sample": [*model, "--steps", "100"], "drt": [], "kk": [], "diagnose": model, "refine": ["--max-effects", "1"],
            "compare": [*model, "--model", "R0 + R1 || CPE1"]}
    for command in commands:
        code, out, err = run([command, path, *argv[command], "--json", "-q"], capsys)
        assert code == 0, (command, err)
        assert isinstance(json.loads(out).get("warnings"), list), command
    code, out, err = run(["compare", path, *argv["compare"], "--json", "-q"], capsys)
    printed = json.loads(out)
    assert code == 0 and printed["warnings"] == [f"{m['label']}: {w}" for m in printed["models"] for w in m["warnings"]]
    assert "has a top-level `warnings` too" in text


def test_robustness_md_says_which_refine_notes_are_warnings():
    """docs/robustness.md ("JSON for programs") said refine's `warnings` is its `notes`; a further
    path's note that it changed nothing is information, not a warning, and `Refinement.warnings`
    leaves it out (docs/diagnosis.md says so): the page now says it too. Stand-in step (no fit)."""
    from types import SimpleNamespace

    from impedax.fitting.diagnosis.refinement import Refinement, RefinementStep

    text = " ".join((DOCS / "robustness.md").read_text(encoding="utf-8").split())
    assert "`warnings` is `notes` (refine)" not in text
    assert "refine: the sign hint, its notes but a further path's saying it changed nothing" in text
    diagnosis = SimpleNamespace(sign_hint=None, beyond_catalog=False, verdict="adequate", noise_ratio=1.0, effects_left_out=())
    unchanged, heeded = "the second path changes nothing: the first path's end is kept.", "the final model still misses an effect"
    refinement = Refinement((RefinementStep(SimpleNamespace(model="R0"), None, None, diagnosis),), "adequate", (unchanged, heeded))
    assert refinement.warnings == [heeded] and list(refinement.notes) == [unchanged, heeded]
