"""What a user review of the command line found, each with the case that showed it:

- an output named without an extension (``--plot out``) is written as the default format
  (PNG, CSV) at that name, for every command, and no error names impedax's temporary file;
- an unknown option gets the closest option of the command, its message first and the command's short usage line after it;
- the text says what the JSON says: each model's warnings under `compare`'s table, a batch
  fit's warnings grouped by kind with their spectra, the element a refinement step removed,
  the warning of a fit that did not converge, in the command line's words (``--max-steps``);
- rms_rel in percent in every command's text;
- messages and help that say what happens (a band outside the data, a λ given with --lam,
  inspect's sheets, drt and kk help);
- figures whose titles are not cut, and batch figures marked with the spectra's labels.

The spectra are written here from closed forms (R0 + R1 ∥ C1 with noise), except where the
review's real files are the case (`examples/data/autoeis_battery_cycles.nc`, three battery
cycles; `tests/fixtures/real/`)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

ROOT = Path(__file__).resolve().parent.parent
CYCLES = ROOT / "examples" / "data" / "autoeis_battery_cycles.nc"
REAL = ROOT / "tests" / "fixtures" / "real"
PNG = b"\x89PNG\r\n\x1a\n"

F = np.geomspace(1e-1, 1e5, 41)
R0, C1 = 10.0, 1e-6


def rc(r1: float, rng, noise: float = 1e-3) -> np.ndarray:
    """R0 + R1 ∥ C1 from its transfer function, with complex noise."""
    z = R0 + r1 / (1 + 1j * 2 * np.pi * F * r1 * C1)
    return z * (1 + noise * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)))


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """One spectrum (CSV) and a stack of three over ``trial`` labelled a, b, c (netCDF)."""
    rng = np.random.default_rng(11)
    folder = tmp_path_factory.mktemp("review")
    one = folder / "one.csv"
    ix.save(ix.make_spectrum(F, rc(400.0, rng)), one)
    stack = ix.make_spectrum(F, np.stack([rc(r1, rng) for r1 in (100.0, 400.0, 1600.0)]), dims=("trial",))
    stack = stack.drop_vars("trial", errors="ignore").assign_coords(trial=["a", "b", "c"])
    three = folder / "three.nc"
    ix.save(stack, three)
    return {"one": str(one), "three": str(three)}


def no_temporaries(folder: Path) -> None:
    left = [p.name for p in folder.iterdir() if p.name.startswith(".")]
    assert left == [], left


# --- 1. outputs without an extension; errors name the user's path ------------------------------

@pytest.mark.parametrize(
    "command",
    [
        pytest.param(["fit", "{one}", "--model", "R0 + R1 || C1", "--plot", "{out}"], id="fit-plot"),
        pytest.param(["kk", "{one}", "--plot", "{out}"], id="kk-plot"),
        pytest.param(["simulate", "R0 + R1 || C1", "--plot", "{out}"], id="simulate-plot"),
        pytest.param(["inspect", "{one}", "--plot", "{out}"], id="inspect-plot"),
        pytest.param(["sample", "{one}", "--model", "R0 + R1 || C1", "--steps", "50", "--quiet", "--corner", "{out}"], id="sample-corner"),
    ],
)
def test_a_figure_named_without_an_extension_is_a_png_at_that_name(files, tmp_path, command, capsys):
    """Before: ``ValueError: Format 'tmp' is not supported`` and a traceback (the temporary
    copy's extension chose the format)."""
    out = tmp_path / "o6"
    args = [a.format(out=out, **files) for a in command]
    assert main(args) == 0, capsys.readouterr().err
    assert out.read_bytes()[:8] == PNG
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o6"]


def test_a_spectrum_named_without_an_extension_is_csv_at_that_name(files, tmp_path, capsys):
    """Before: ``error: .../.p9.staged.m1pjcfnt.tmp: unknown output format '.tmp'``."""
    out = tmp_path / "p9"
    assert main(["inspect", files["one"], "--out", str(out)]) == 0, capsys.readouterr().err
    assert out.read_text().startswith("frequency_hz,z_real_ohm,z_imag_ohm")
    np.testing.assert_allclose(ix.load(out)["Z"].values, ix.load(files["one"])["Z"].values, rtol=1e-12)
    no_temporaries(tmp_path)


def test_the_unknown_extension_message_says_what_no_extension_means(files, tmp_path, capsys):
    assert main(["fit", files["one"], "--model", "R1", "--plot", str(tmp_path / "x.csv")]) == 2
    assert "(or none: written as PNG)" in capsys.readouterr().err


def test_a_csv_of_several_spectra_is_refused_naming_the_users_file_and_the_way_out(files, tmp_path, capsys):
    """Before: ``error: /tmp/.../.x.csv.staged.llh2tqj0.csv: CSV holds one spectrum…``."""
    out = tmp_path / "x.csv"
    assert main(["inspect", files["three"], "--out", str(out), "--plot", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert ".staged." not in err and err.count("\n") == 1
    assert str(out) in err and "--select trial=LABEL" in err and ".nc" in err
    assert list(tmp_path.iterdir()) == []


def test_a_writers_error_names_the_users_path_never_the_temporary(tmp_path):
    """Whatever a writer raises about the file it was given names the user's path."""
    from impedax.cli.common import naming_target
    from impedax.errors import DataError

    def writer(path):
        raise DataError(f"cannot hold this (wrote to {path})", path=path)

    for name in ("plain", "plain.png"):
        staged = tmp_path / f".{name}.staged.abc.{'tmp' if name == 'plain' else 'png'}"
        with pytest.raises(DataError) as info:
            naming_target(writer, str(tmp_path / name))(staged)
        assert str(info.value).count(str(tmp_path / name)) == 2 and ".staged." not in str(info.value) and ".impedax-" not in str(info.value)
        assert info.value.path == str(tmp_path / name)
    no_temporaries(tmp_path)


# --- 2. an unknown option --------------------------------------------------------------------

@pytest.mark.parametrize(
    "args, first_line, usage",
    [
        (["fit", "{one}", "--model", "R1", "--maxsteps", "5"], "impedax fit: error: unrecognized arguments: --maxsteps 5; did you mean --max-steps?", "usage: impedax fit [options] DATA (impedax fit --help lists them)"),
        (["fit", "{one}", "--model", "R1", "--max_steps=5"], "impedax fit: error: unrecognized arguments: --max_steps=5; did you mean --max-steps?", "usage: impedax fit [options] DATA (impedax fit --help lists them)"),
        (["kk", "{one}", "--maxrc", "3"], "impedax kk: error: unrecognized arguments: --maxrc 3; did you mean --max-rc?", "usage: impedax kk [options] DATA (impedax kk --help lists them)"),
        (["info", "R1", "--bogus"], "impedax info: error: unrecognized arguments: --bogus", "usage: impedax info [options] [MODEL] (impedax info --help lists them)"),
        (["simulate", "R1", "--points", "ten"], "impedax simulate: error: argument --points: invalid int value: 'ten'", "usage: impedax simulate [options] [MODEL] (impedax simulate --help lists them)"),
        (["fitt", "{one}"], "impedax: error: argument COMMAND: invalid choice: 'fitt'; did you mean fit? (choose from ", "usage: impedax [options] COMMAND ... (impedax --help lists them)"),
    ],
)
def test_a_usage_error_is_its_message_first_then_one_short_usage_line(files, args, first_line, usage, capsys):
    """Before: the top-level ``usage: impedax [-h] [--version] COMMAND ...`` and no hint; then
    (until 2026-12-01) the command's whole usage block (nine lines for fit) above the message and
    its hint. Now the message with the closest option first, the short usage line after it."""
    with pytest.raises(SystemExit) as info:
        main([a.format(**files) for a in args])
    assert info.value.code == 2
    lines = capsys.readouterr().err.splitlines()
    assert lines[0].startswith(first_line) and lines[1:] == [usage], lines
    if "did you mean" not in first_line:
        assert "did you mean" not in lines[0]


@pytest.mark.parametrize(
    "args, hint",
    [
        (["fit", "{one}", "R0 + R1 || C1"], "required: --model; a circuit follows --model: impedax fit DATA --model 'R0 + R1 || C1'"),
        (["fit", "R0-p(R1,C1)", "{one}"], "required: --model; a circuit follows --model: impedax fit DATA --model 'R0-p(R1,C1)'"),
        (["sample", "{one}", "--weighting", "modulus", "R1"], "required: --model; a circuit follows --model: impedax sample DATA --model R1"),
        (["compare", "{one}", "R0 + R1 || C1", "R0 + R1 || CPE1"],
         "required: --model; a circuit follows its own --model: impedax compare DATA --model 'R0 + R1 || C1' --model 'R0 + R1 || CPE1'"),
        (["refine", "{one}", "R0 + R1 || C1"], "unrecognized arguments: R0 + R1 || C1; a circuit follows --model: impedax refine DATA --model 'R0 + R1 || C1'"),
    ],
)
def test_a_circuit_given_without_model_is_shown_after_it(files, args, hint, capsys):
    """A walkthrough (2026-12-04): ``impedax fit DATA 'R0 + R1 || CPE1'`` was told only
    "the following arguments are required: --model", and ``refine`` (whose --model is optional)
    "unrecognized arguments"; now the command as it should have been typed."""
    with pytest.raises(SystemExit) as info:
        main([a.format(**files) for a in args])
    first = capsys.readouterr().err.splitlines()[0]
    assert info.value.code == 2 and first.replace("the following arguments are required", "required").endswith(hint), first


@pytest.mark.parametrize("args", [["fit", "{one}"], ["fit", "{one}", "--fmax", "5e3"], ["fit", "{one}", "--weighting", "modulus"], ["fit", "{one}", "{one}"]])
def test_no_circuit_hint_where_no_word_reads_as_a_circuit(files, args, capsys):
    """An option's value (5e3, modulus) and an existing file are no circuit."""
    with pytest.raises(SystemExit) as info:
        main([a.format(**files) for a in args])
    first = capsys.readouterr().err.splitlines()[0]
    assert info.value.code == 2 and "--model" in first and "a circuit follows" not in first, first


@pytest.mark.parametrize(
    "args, first_line",
    [
        (["compare", "{one}", "--model", "R0", "--model", "R0 + R1 || C1", "--shared", "R0"], "impedax compare: error: unrecognized arguments: --shared R0"),
        (["fit", "{one}", "--model", "R0 + R1 || C1", "--corner-params", "R1,C1"], "impedax fit: error: unrecognized arguments: --corner-params R1,C1"),
    ],
)
def test_an_unknown_options_value_is_no_circuit(files, args, first_line, capsys):
    """A hostile walkthrough (2026-12-08): ``compare ... --shared R0`` (an option of fit, not of
    compare) was told "…; a circuit follows --model: impedax compare DATA --model R0", reading the
    option's value R0 as a circuit typed without its --model, which the command had."""
    with pytest.raises(SystemExit) as info:
        main([a.format(**files) for a in args])
    first = capsys.readouterr().err.splitlines()[0]
    assert info.value.code == 2 and first == first_line, first


@pytest.mark.parametrize("command", ["fit", "diagnose", "refine", "sample", "simulate", "info", "draw"])
def test_a_second_model_is_refused_where_the_command_takes_one(files, command, capsys):
    """argparse kept the last --model in silence: ``diagnose --model A --model B`` diagnosed B
    (a walkthrough, 2026-12-04). compare takes several (its own test files)."""
    data = [files["one"]] if command in ("fit", "diagnose", "refine", "sample") else []
    with pytest.raises(SystemExit) as info:
        main([command, *data, "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1"])
    first = capsys.readouterr().err.splitlines()[0]
    assert info.value.code == 2
    several = "; impedax compare fits several to one spectrum" if data else ""  # (simulate, info and draw fit nothing)
    assert first == f"impedax {command}: error: --model given twice ('R0 + R1 || C1' and 'R0 + R1 || CPE1'): impedax {command} takes one model{several}"


def test_the_program_names_the_misspelt_flag_and_its_hint_on_the_first_line_of_stderr():
    # the real program (exit status, stderr as a terminal shows it) on a REAL file
    import subprocess
    import sys

    data = Path(__file__).parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc"
    run = subprocess.run(
        [sys.executable, "-m", "impedax", "fit", str(data), "--model", "R0+R1||C1", "--max-stesp", "5"],
        capture_output=True, text=True, timeout=120,
    )
    assert run.returncode == 2 and run.stdout == ""
    first, *rest = run.stderr.splitlines()
    assert first == "impedax fit: error: unrecognized arguments: --max-stesp 5; did you mean --max-steps?"
    assert rest == ["usage: impedax fit [options] DATA (impedax fit --help lists them)"]


# --- 3. the text says what the JSON says ----------------------------------------------------

def test_compare_lists_each_models_warnings_under_the_table(files, capsys):
    """Before: the table alone, while the JSON held each model's warnings (CHInstruments: a
    9-parameter model ranked best with 5 warnings)."""
    args = ["compare", files["one"], "--model", "R0 + R1 || C1", "--model", "R0 + R1 || C1 + R2"]
    assert main(args) == 0
    text = capsys.readouterr().out
    models = json_out(args + ["--json"], capsys)["models"]
    warned = [m for m in models if m["warnings"]]
    assert warned, "the case needs a model with warnings"
    assert "\nwarnings:\n" in text
    for m in warned:
        assert f"  {m['model']}" in text
        for w in m["warnings"]:
            assert f"    - {w}" in text


def test_compare_prints_no_warning_section_when_there_is_none(files, capsys):
    assert main(["compare", files["one"], "--model", "R0 + R1 || C1", "--model", "R0 + C1"]) == 0
    out = capsys.readouterr().out
    models = json_out(["compare", files["one"], "--model", "R0 + R1 || C1", "--model", "R0 + C1", "--json"], capsys)["models"]
    assert ("warnings:" in out) == any(m["warnings"] for m in models)


def json_out(args, capsys):
    assert main(args) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.slow  # (12 s, the suite's budget; a joint fit's grouped kinds: test_fit_roundtrip.py; each spectrum's warnings: test_batch_json.py)
def test_a_batch_fit_shows_its_warnings_grouped_with_their_spectra(capsys):
    """Before: the batch's text had no warning at all, its JSON three (the review's case)."""
    args = ["fit", str(CYCLES), "--model", "R0 + R1 || CPE1 + R2 || CPE2 + W1"]
    assert main(args) == 0
    text = capsys.readouterr().out
    summary = json_out(args + ["--json"], capsys)
    assert summary["warnings"]
    lines = [ln for ln in text.splitlines() if ln.startswith("warning (")]
    assert lines
    for ln in lines:
        assert re.match(r"warning \((all 3 spectra|[12] of 3 spectra: (all but )?cycles? [0-9, ]+)\): ", ln), ln
    # every JSON text is in a line, up to the numbers that a group shows as a range
    for w in summary["warnings"]:
        template = re.sub(r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?", "#", w)
        assert any(re.sub(r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?( to [-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)?", "#", ln.split("): ", 1)[1]) == template for ln in lines), w


@pytest.mark.slow  # (the suite's 15-minute budget, 2026-12-01: make test-all runs it)
def test_a_batch_fit_s_report_in_python_shows_its_warnings_grouped():
    """Before: only the command line printed a batch's warnings; ``print(result.report())`` in
    Python showed none."""
    result = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + W1", ix.load(CYCLES))
    lines = [ln for ln in result.report().splitlines() if ln.startswith("warning (")]
    assert result.summary()["warnings"] and lines
    assert all(re.match(r"warning \((all 3 spectra|1 of 3 spectra: cycle [0-9]+|2 of 3 spectra: all but cycle [0-9]+)\): ", ln) for ln in lines)  # (more than half: the others named, since 2026-12-01)


def test_grouped_warnings_merge_numbers_into_ranges_and_name_the_spectra():
    from impedax.cli.common import command_line_words
    from impedax.warning_groups import grouped_warnings

    warnings = {
        "cycle=0": ("A.Q and A.alpha are strongly correlated (r = -0.993)", "B is at its upper bound 1"),
        "cycle=64": ("A.Q and A.alpha are strongly correlated (r = -0.990)", "B is at its upper bound 1"),
        "cycle=129": ("B is at its upper bound 1", "fit did not converge: raise max_steps"),
    }
    lines = grouped_warnings(warnings, 3)
    assert lines[0] == "warning (all 3 spectra): B is at its upper bound 1"
    assert "warning (2 of 3 spectra: cycle 0, 64): A.Q and A.alpha are strongly correlated (r = -0.993 to -0.990)" in lines
    assert "warning (1 of 3 spectra: cycle 129): fit did not converge: raise max_steps" in lines  # (the API's words; the CLI's below)
    assert "raise --max-steps" in command_line_words("\n".join(lines))
    many = {f"trial={i}, session=1": (f"P{i} is at its lower bound 0",) for i in range(40)}
    lines = grouped_warnings(many, 40)
    assert len(lines) == 13 and lines[-1].startswith("... and 28 more kinds of warning")
    # a global fit's own notes are under a key that names no spectrum: given as it is (before:
    # "warning (1 of 2 spectra: shared over trial): ...")
    lines = grouped_warnings({"trial=0": ("R1 is at its lower bound 0",), "shared over trial": ("shared R0 is at its lower bound 0",)}, 2)
    assert "warning (shared over trial): shared R0 is at its lower bound 0" in lines
    assert "warning (1 of 2 spectra: trial 0): R1 is at its lower bound 0" in lines


def test_a_warning_of_most_spectra_names_the_others_and_one_finding_worded_two_ways_is_one_kind():
    from impedax.warning_groups import LABELS_SHOWN, grouped_warnings, warning_kinds

    keys = [f"cycle={i}" for i in range(130)]
    bound = "CPE2.alpha is at its upper bound 1"
    # as on AutoEIS's 130 battery cycles: at the bound in all but cycles 8 and 14
    warnings = {k: (bound,) for k in keys if k not in ("cycle=8", "cycle=14")}
    well = "A.Q and A.alpha are strongly correlated (r = -0.99{}) (a CPE's Q and α correlate far from 1 rad/s; both are still well determined (relative errors {} % and 2 %))"
    held = "A.Q and A.alpha are strongly correlated (r = -0.99{}) (a CPE's Q and α correlate far from 1 rad/s; their standard errors ({} % and 2 %) already include the correlation)"
    for i, k in enumerate(("cycle=0", "cycle=3", "cycle=4", "cycle=14")):
        text = (held if k in ("cycle=4", "cycle=14") else well).format(i + 1, 5 + 10 * i)
        warnings[k] = warnings.get(k, ()) + (text,)
    lines = grouped_warnings(warnings, 130, spectra=keys)
    assert lines[0] == f"warning (128 of 130 spectra: all but cycle 8, 14): {bound}"
    assert lines[1] == (
        "warning (4 of 130 spectra: cycle 0, 3, 4, 14): A.Q and A.alpha are strongly correlated (r = -0.994 to -0.991) "
        "(a CPE's Q and α correlate far from 1 rad/s; both are still well determined (relative errors 5 to 15 % and 2 %)); "
        "in cycle 4, 14: (a CPE's Q and α correlate far from 1 rad/s; their standard errors (25 to 35 % and 2 %) already include the correlation)"
    )
    assert len(lines) == 2
    # without every spectrum's key, or for half or fewer, the spectra it applies to as before
    assert grouped_warnings(warnings, 130)[0].startswith("warning (128 of 130 spectra: cycle 0, 1, 2, 3, 4, 5, 6, 7, ... (128 in all))")
    half = {k: (bound,) for k in keys[:65]}
    assert grouped_warnings(half, 130, spectra=keys)[0].startswith("warning (65 of 130 spectra: cycle 0, 1,")
    # many exceptions are capped as the spectra are
    most = {k: (bound,) for k in keys[:100]}
    assert grouped_warnings(most, 130, spectra=keys)[0] == f"warning (100 of 130 spectra: all but cycle {', '.join(str(i) for i in range(100, 100 + LABELS_SHOWN))}, ... (30 in all)): {bound}"
    # the JSON: one kind, each wording with its spectra; each spectrum's own text kept whole
    kind = [k for k in warning_kinds(warnings) if k["warning"].startswith("A.Q")]
    assert len(kind) == 1 and kind[0]["n_spectra"] == 4
    assert [w["spectra"] for w in kind[0]["wordings"]] == [["cycle=0", "cycle=3"], ["cycle=4", "cycle=14"]]
    assert "already include" in warnings["cycle=4"][-1] and "(r = -0.993)" in warnings["cycle=4"][-1]


def test_a_fit_that_did_not_converge_says_so_in_the_command_lines_words(files, capsys):
    """Before: the text's status line only, saying ``raise max_steps``; now a warning on
    stderr as with --json, and ``--max-steps`` in both (the JSON in the command's words too,
    since 2026-12-06: `json_in_command_words`)."""
    args = ["fit", str(REAL / "exampleDataBioLogic.mpt"), "--model", "R0 + R1 || CPE1", "--max-steps", "1"]
    assert main(args) == 0
    captured = capsys.readouterr()
    assert "NOT converged" in captured.out and "--max-steps" in captured.out and not re.search(r"(?<!-)max_steps", captured.out)
    assert "impedax fit: warning: the fit did not converge" in captured.err and "raise --max-steps" in captured.err
    summary = json_out(args + ["--json"], capsys)
    assert any(w.startswith("fit did not converge") and "--max-steps" in w and not re.search(r"(?<!-)max_steps", w) for w in summary["warnings"])


def test_a_refinement_step_that_replaces_an_element_says_which(files, monkeypatch, capsys):
    """Before: ``+ R_relax4 || C_relax3 [extra_relaxation]`` while the JSON had
    ``"removed": ["R_relax3"]``; the text and the figure now name it."""
    from impedax.fitting.diagnosis.refinement import Refinement, RefinementStep

    data = ix.load(files["one"])
    first = ix.fit("R0 + R1 || C1 + R_relax3 || C_x", data)
    second = ix.fit("R0 + R1 || C1 + R_relax4 || C_relax3 + C_x", data)
    refinement = Refinement(
        steps=(RefinementStep(first, None, None, None), RefinementStep(second, "R_relax4 || C_relax3", "extra_relaxation", None, removed=("R_relax3",))),
        verdict="adequate",
    )
    monkeypatch.setattr("impedax.fitting.refine", lambda *a, **k: refinement)
    assert main(["refine", files["one"], "--model", "R0 + R1 || C1"]) == 0
    assert "+ R_relax4 || C_relax3 [extra_relaxation], − R_relax3" in capsys.readouterr().out
    fig = refinement.plot()
    assert any("− R_relax3" in t.get_text() for t in fig.axes[0].texts)


# --- 4. rms_rel in percent --------------------------------------------------------------------

def test_fit_and_compare_print_rms_rel_in_percent_like_the_other_commands(files, capsys):
    """Before: ``rms_rel    0.2944`` in fit and compare, ``29.4 %`` in kk, diagnose, refine."""
    rms = json_out(["fit", files["one"], "--model", "R0 + R1 || C1", "--json"], capsys)["rms_rel"]
    assert main(["fit", files["one"], "--model", "R0 + R1 || C1"]) == 0
    assert f"rms_rel    {rms * 100:.3g} %" in capsys.readouterr().out
    assert main(["compare", files["one"], "--model", "R0 + R1 || C1", "--model", "R0 + C1"]) == 0
    row = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("R0 + R1 || C1 "))
    # (three significant digits kept in the table, 0.120 %, since 2026-11-30; the decimal points lined up since 2026-12-07)
    cell = re.search(r" (\S+) +% ", row).group(1)
    assert len(cell.replace(".", "").lstrip("0")) >= 3 and float(cell) == pytest.approx(rms * 100, abs=0.5 * 10.0 ** -len(cell.split(".")[-1]))
    assert main(["fit", files["three"], "--model", "R0 + R1 || C1"]) == 0
    assert re.search(r"median rms_rel [0-9.]+ %", capsys.readouterr().out)


# --- 5. wording -------------------------------------------------------------------------------

def test_a_band_outside_the_data_says_where_the_data_are(files, capsys):
    """Before: ``no frequencies between fmin=1000000.0 and fmax=None``."""
    assert main(["fit", files["one"], "--model", "R1", "--fmin", "1e6"]) == 2
    err = capsys.readouterr().err
    assert "no frequencies at or above --fmin = 1 MHz (the data span 100 mHz–100 kHz)" in err and "None" not in err
    assert main(["fit", files["one"], "--model", "R1", "--fmin", "10", "--fmax", "11"]) == 2
    assert "no frequencies from --fmin = 10 Hz to --fmax = 11 Hz" in capsys.readouterr().err


def test_a_lambda_given_with_lam_is_reported_as_given(files, capsys):
    """Before: ``λ = 0.001 by fixed``."""
    assert main(["drt", files["one"], "--lam", "1e-3"]) == 0
    out = capsys.readouterr().out
    assert "λ = 0.001 as given" in out and "by fixed" not in out


XLSX = REAL / "data.xlsx"


def test_inspect_of_sheets_lists_each_sheets_reading_once(capsys):
    """Before: one long line per attribute and a second ``sheet:`` line repeating the labels."""
    assert main(["inspect", str(XLSX)]) == 0
    out = capsys.readouterr().out
    assert sum(ln.lstrip().startswith("sheet:") for ln in out.splitlines()) == 1
    assert "  sign convention:\n    sheet header-variant-1: " in out


def test_inspect_of_a_picked_sheet_says_only_that_sheets_conventions(capsys):
    """Before: every sheet's sign convention and units after ``--select sheet=...``."""
    assert main(["inspect", str(XLSX), "--select", "sheet=header-variant-2"]) == 0
    out = capsys.readouterr().out
    assert "  sign convention: column '-Zim' holds -Z''; negated to Z''\n" in out
    assert "header-variant-1" not in out and "header-variant-3" not in out
    summary = json_out(["inspect", str(XLSX), "--select", "sheet=header-variant-2", "--json"], capsys)
    assert summary["sign_convention"] == "column '-Zim' holds -Z''; negated to Z''"


def test_inspect_counts_skipped_ranges_in_good_english(capsys):
    """Before: ``skipped rows (1 ranges)``."""
    assert main(["inspect", str(REAL / "exampleDataParstat.txt")]) == 0
    assert "  skipped rows (1 range):\n" in capsys.readouterr().out


def test_inspects_preview_names_the_spectrum_it_shows(files):
    """Before: ``— first of 3 trial`` (and ``first of 4 sheet``); then the first only, named
    (``— trial=a, the first of 3 spectra``); now all three, named in the legend."""
    from impedax.cli.inspect import _preview

    fig = _preview(ix.load(files["three"]), "netCDF")
    assert fig._suptitle.get_text().endswith("— 3 spectra")
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()] == ["a", "b", "c"]


def test_help_says_what_drt_and_kk_do(capsys):
    """Before: drt's DATA "with one spectrum, or one picked with --select" (a file of several
    gets a DRT each) and kk's --max-rc "default N/2" (the code caps it at 100)."""
    for command in ("drt", "kk"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "a file of several spectra gets a DRT of each" in text
    assert "default: N/2 for N frequencies, at most 100" in text


# --- 6. figures -------------------------------------------------------------------------------

def outside_the_figure(fig) -> list[str]:
    """The texts of ``fig`` (titles, suptitle, annotations) that reach beyond its edges."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    box = fig.bbox
    texts = list(fig.texts) + [t for ax in fig.axes for t in (ax.title, *ax.texts)]
    out = []
    for t in texts:
        if not t.get_text() or not t.get_visible():
            continue
        e = t.get_window_extent(renderer)
        if e.x0 < box.x0 - 1 or e.x1 > box.x1 + 1 or e.y0 < box.y0 - 1 or e.y1 > box.y1 + 1:
            out.append(t.get_text())
    return out


@pytest.mark.slow  # (an end-to-end run of ~10 s: make test-all; the fast suite's 15-minute budget)
def test_the_refinement_figure_keeps_every_title_inside(files):
    """Before: the suptitle and the step titles of long models ran off the figure (the
    review's refine of cycle 129)."""
    from impedax.fitting.diagnosis.refinement import Refinement, RefinementStep

    data = ix.load(files["one"])
    models = [
        "R0 + R1 || C1",
        "R0 + (R1 + (R_relax + R_relax2 || C_relax2) || C_relax) || CPE1 + R_relax3 || CPE_relax",
        "R0 + (R1 + (R_relax + (R_relax2 + R_relax4 || C_relax3) || C_relax2) || C_relax) || CPE1 + CPE_relax + L_lead + C_stray",
    ]
    fits = [ix.fit(m, data, max_steps=5) for m in models]
    steps = [RefinementStep(fits[0], None, None, None)] + [RefinementStep(f, "X", "extra_relaxation", None) for f in fits[1:]]
    fig = Refinement(steps=tuple(steps), verdict="adequate").plot()
    assert outside_the_figure(fig) == []


def test_the_batch_fit_figure_marks_the_spectra_with_their_labels():
    """Before: the x axis read 0.0, 0.5, ..., 2.0 for the cycles 0, 64, 129."""
    batch = ix.fit("R0 + R1 || CPE1", ix.load(CYCLES))
    fig = batch.plot()
    panels = [ax for ax in fig.axes if ax.get_visible() and not ax.get_title().startswith("data (○) and fits")]  # (not the Nyquist panel)
    assert len(panels) == len(fig.axes) - 1 == 5
    for ax in panels:
        assert [t.get_text() for t in ax.get_xticklabels()] == ["0", "64", "129"] and ax.get_xlabel() == "cycle"
    assert [line.get_label() for line in fig.axes[-1].lines if line.get_marker() == "o"] == ["0", "64", "129"]  # the Nyquist legend: the same labels
    assert outside_the_figure(fig) == []


def test_fit_plot_params_draws_those_panels_and_refuses_what_it_cannot(files, tmp_path, capsys):
    """``impedax fit STACK --plot F.png --plot-params R1`` (added 2026-12-01): the batch figure's
    R1 and rms_rel panels only; an unknown name, no --plot, or one spectrum: exit 2 before the fit."""
    out = tmp_path / "batch.png"
    assert main(["fit", files["three"], "--model", "R0 + R1 || C1", "--plot", str(out), "--plot-params", "R1", "--json"]) == 0
    assert out.stat().st_size > 0
    capsys.readouterr()
    for args, message in (
        (["--plot", str(tmp_path / "x.png"), "--plot-params", "R1", "C2"], "--plot-params: unknown parameter 'C2' for model 'R0 + R1 || C1'"),
        (["--plot-params", "R1"], "--plot-params picks the parameters of the figure --plot FILE.png draws: give --plot too"),
    ):
        assert main(["fit", files["three"], "--model", "R0 + R1 || C1", *args]) == 2
        err = capsys.readouterr().err
        assert message in err and "Traceback" not in err
    assert main(["fit", files["one"], "--model", "R0 + R1 || C1", "--plot", str(tmp_path / "y.png"), "--plot-params", "R1"]) == 2
    assert "holds one" in capsys.readouterr().err and not (tmp_path / "y.png").exists() and not (tmp_path / "x.png").exists()
