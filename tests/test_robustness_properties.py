"""Property tests over the whole input space: random command lines and random Python objects.

The table-driven harness (tests/test_robustness.py) checks the bad inputs we thought of; these
draw argv from commands × flags × values (garbage included) and arbitrary Python objects for the
API's arguments. The property: never a traceback. The CLI exits 0 or 2 (2 with one message);
the API returns or raises an `ImpedaxError` with a message under 300 characters.

Default runs draw few examples (the `robustness` settings below) so the suite stays fast; the
``slow`` variants draw many more (``pytest -m slow``).
"""

from __future__ import annotations

import unicodedata

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import impedax as ix
from impedax.cli import main

FAST = settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck), database=None)
THOROUGH = settings(max_examples=400, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck), database=None)

GOOD_CSV = "frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(
    f"{f:.6g},{(100 + 1 / (2j * np.pi * f * 1e-6)).real:.6g},{(100 + 1 / (2j * np.pi * f * 1e-6)).imag:.6g}\n" for f in np.geomspace(1, 1e5, 21)
)

garbage = st.text(min_size=0, max_size=12)  # any characters (controls, RTL marks, letters of every script)
numbers = st.sampled_from(["0", "-1", "1", "2.5", "1e400", "nan", "inf", "-inf", "1e-300", "20", "abc", ""])
models = st.one_of(st.sampled_from(["R1 + C1", "R1 || C1", "R1 + С1", "(R1", "R1 + R1", "CPE1", "", "Ρ1"]), garbage)
params = st.one_of(st.sampled_from(["R1=5", "R1=-5", "C1=abc", "X=1", "R1", "=", "R1=nan"]), garbage)

# (command, positional arguments, {flag: values}); in a default run the cheap commands (info,
# simulate, draw, inspect) may run for real and the others always get one token that makes them
# fail before any work, so that the run stays fast; the slow variant lets every command run.
COMMANDS = {
    "info": (lambda d: [d["model"]], {"--json": None}),
    "simulate": (lambda d: [d["model"]], {"--param": params, "--fmin": numbers, "--fmax": numbers, "--points": st.sampled_from(["-1", "0", "3", "x", "1e3"]), "--out": st.sampled_from(["{tmp}/o.csv", "{tmp}/o.xyz", "{tmp}/no/o.csv"])}),
    "draw": (lambda d: [d["model"]], {"-o": st.sampled_from(["{tmp}/o.svg", "{tmp}/o.bad", "{tmp}"]), "--param": params}),
    "inspect": (lambda d: [d["data"]], {"--json": None}),
    "fit": (lambda d: [d["data"]], {"--model": models, "--fix": params, "--init": params, "--weighting": st.sampled_from(["unit", "modulus", "x"]), "--fmin": numbers, "--fmax": numbers, "--max-steps": numbers, "--json": None}),
    "kk": (lambda d: [d["data"]], {"--method": st.sampled_from(["linear", "zhit", "x"]), "--c": numbers, "--max-rc": numbers, "--no-inductance": None, "--json": None}),
    "drt": (lambda d: [d["data"]], {"--lam": st.one_of(numbers, st.just("auto")), "--lam-method": st.sampled_from(["gcv", "lcurve", "x"]), "--signed": None, "--json": None}),
    "force": (lambda d: [d["paper"]], {"--param": params, "--fmin": numbers, "--fmax": numbers, "--points": st.sampled_from(["-1", "0", "5", "x"]), "--json": None}),
    "compare": (lambda d: [d["data"]], {"--model": models, "--weighting": st.sampled_from(["unit", "x"]), "--fmin": numbers, "--json": None}),
    "sample": (lambda d: [d["data"]], {"--model": models, "--steps": st.sampled_from(["-1", "0", "x", "20"]), "--walkers": numbers, "--seed": numbers, "--prior": params, "--quiet": None}),
    "diagnose": (lambda d: [d["data"]], {"--model": models, "--effects": st.sampled_from(["bogus", "series_resistance", ""]), "--noise": numbers, "--max-steps": numbers}),
    "refine": (lambda d: [d["data"]], {"--model": models, "--effects": st.sampled_from(["bogus", ""]), "--max-steps": numbers}),
    "gap": (lambda d: [d["data"], d["data"], d["data"]], {"--area": numbers, "--v0": numbers, "--steps": numbers, "--ep": st.sampled_from(["C", "CPE", "x"])}),
    "demo": (lambda d: [], {"--fast": None}),
}
COSTLY = {"fit", "kk", "drt", "force", "sample", "diagnose", "refine", "gap", "compare", "demo"}
DATA = ["{tmp}/good.csv", "{tmp}/missing.csv", "{tmp}/garbage.bin", "{tmp}", "{tmp}/empty.csv"]


@st.composite
def command_lines(draw, *, cheap_only: bool):
    command = draw(st.sampled_from(sorted(COMMANDS)))
    positionals, flags = COMMANDS[command]
    chosen = {"model": draw(models), "data": draw(st.sampled_from(DATA)), "paper": draw(st.sampled_from(["meyer", "vezzoli", "x"]))}
    argv = [command, *positionals(chosen)]
    for flag in draw(st.lists(st.sampled_from(sorted(flags)), max_size=4)):
        values = flags[flag]
        argv += [flag] if values is None else [flag, draw(values)]
    if command == "demo":  # (a valid demo runs for minutes; its outputs are tests/test_robustness_outputs.py's)
        argv.append("--bogus")
    elif cheap_only and command in COSTLY:  # fail before any work: an unknown flag or a missing file
        argv.insert(draw(st.integers(1, len(argv))), draw(st.sampled_from(["--bogus", "{tmp}/missing.csv"])))
    if draw(st.booleans()):
        argv.insert(draw(st.integers(0, len(argv))), draw(garbage))
    return argv


def _cli_never_tracebacks(argv, tmp_path, capsys):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse: usage errors (2) and --help (0)
        code = exc.code
    out, err = capsys.readouterr()
    assert code in (0, 2, None), (argv, code, err[-500:])
    assert "Traceback" not in err and "Traceback" not in out, (argv, err[-2000:])
    if code == 2:
        errors = [line for line in err.splitlines() if "error:" in line]
        assert len(errors) == 1, (argv, err[-1000:])
        if "usage:" not in err:  # (argparse's own messages echo arguments raw; impedax's escape them)
            assert not [ch for ch in err if ch != "\n" and unicodedata.category(ch) in ("Cc", "Cf")], (argv, repr(err[-500:]))


@pytest.fixture
def cli_folder(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cli")
    (folder / "good.csv").write_text(GOOD_CSV)
    (folder / "garbage.bin").write_bytes(bytes(range(256)) * 4)
    (folder / "empty.csv").write_bytes(b"")
    return folder


@FAST
@given(argv=command_lines(cheap_only=True))
def test_random_command_lines_never_traceback(argv, cli_folder, capsys):
    _cli_never_tracebacks(argv, cli_folder, capsys)


@pytest.mark.slow
@THOROUGH
@given(argv=command_lines(cheap_only=False))
def test_random_command_lines_never_traceback_thorough(argv, cli_folder, capsys):
    _cli_never_tracebacks(argv, cli_folder, capsys)


# --- the Python API ---------------------------------------------------------------------------

objects = st.recursive(
    st.one_of(
        st.none(), st.booleans(), st.integers(), st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=8),
        st.binary(max_size=8), st.complex_numbers(), st.just(np.array([1.0, 2.0])), st.just(np.array(["a"])), st.just(object()),
    ),
    lambda inner: st.one_of(st.lists(inner, max_size=3), st.tuples(inner, inner), st.dictionaries(st.one_of(st.text(max_size=4), st.integers()), inner, max_size=3)),
    max_leaves=6,
)

_GOOD = None


def good_spectrum():
    global _GOOD
    if _GOOD is None:
        freq = np.geomspace(1, 1e5, 21)
        _GOOD = ix.make_spectrum(freq, 100 + 1 / (2j * np.pi * freq * 1e-6))
    return _GOOD


API_ARGUMENTS = {  # function → (the call with one argument replaced by a random object)
    "fit-data": lambda x: ix.fit("R1 + C1", x, n_starts=1),
    "fit-init": lambda x: ix.fit("R1 + C1", good_spectrum(), init=x, n_starts=1),
    "fit-fixed": lambda x: ix.fit("R1 + C1", good_spectrum(), fixed=x, n_starts=1),
    "fit-bounds": lambda x: ix.fit("R1 + C1", good_spectrum(), bounds=x, n_starts=1),
    "fit-seed": lambda x: ix.fit("R1 + C1", good_spectrum(), seed=x, n_starts=1),
    "fit-fmin": lambda x: ix.fit("R1 + C1", good_spectrum(), fmin=x, n_starts=1),
    "fit-weighting": lambda x: ix.fit("R1 + C1", good_spectrum(), weighting=x, n_starts=1),
    "fit-circuit": lambda x: ix.fit(x, good_spectrum(), n_starts=1),
    "sample-steps": lambda x: ix.sample("R1 + C1", good_spectrum(), steps=x, walkers=8, progress=False) if not (isinstance(x, int) and x > 50) else None,
    "sample-seed": lambda x: ix.sample("R1 + C1", good_spectrum(), steps=10, walkers=8, seed=x, progress=False),
    "sample-priors": lambda x: ix.sample("R1 + C1", good_spectrum(), steps=10, walkers=8, priors=x, progress=False),
    "diagnose-effects": lambda x: ix.diagnose(good_spectrum(), "R1 + C1", effects=x),
    "diagnose-data": lambda x: ix.diagnose(x, "R1 + C1"),
    "kk-data": lambda x: ix.kk_test(x),
    "kk-n-rc": lambda x: ix.kk_test(good_spectrum(), n_rc=x),
    "drt-lam": lambda x: ix.drt(good_spectrum(), lam=x),
    "compare-fits": lambda x: ix.compare(x),
    "parse-text": lambda x: ix.parse(x),
    "make-spectrum-z": lambda x: ix.make_spectrum([1.0, 2.0], x),
    "gap-thickness": lambda x: ix.models.gap_thickness(x),
}


def _api_only_impedax_errors(function, value):
    try:
        API_ARGUMENTS[function](value)
    except ix.ImpedaxError as exc:
        message = str(exc)
        assert len(message) < 400, message  # (circuit errors: 300 plus the caret line's padding)
        assert not [ch for ch in message if ch != "\n" and unicodedata.category(ch) in ("Cc", "Cf")], repr(message)


@FAST
@given(function=st.sampled_from(sorted(API_ARGUMENTS)), value=objects)
def test_random_api_arguments_raise_only_impedax_errors(function, value):
    _api_only_impedax_errors(function, value)


@pytest.mark.slow
@THOROUGH
@given(function=st.sampled_from(sorted(API_ARGUMENTS)), value=objects)
def test_random_api_arguments_raise_only_impedax_errors_thorough(function, value):
    _api_only_impedax_errors(function, value)


# --- files --------------------------------------------------------------------------------------

TABLE_CHARACTERS = b"0123456789.,;\t -+eE\r\n\"'abcfzZHRIm()|/#"
FILE_SUFFIXES = (".txt", ".csv", ".dta", ".mpt", ".z", ".json", ".idf")
FILES = settings(max_examples=300, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck), database=None)


@st.composite
def file_contents(draw) -> bytes:
    """Random bytes; random text from a table's characters (bare carriage returns among them);
    or a good table with up to 4 bytes replaced by those characters."""
    kind = draw(st.sampled_from(["bytes", "table characters", "mangled table"]))
    if kind == "bytes":
        return draw(st.binary(max_size=400))
    if kind == "table characters":
        return bytes(draw(st.lists(st.sampled_from(TABLE_CHARACTERS), max_size=400)))
    table = bytearray(GOOD_CSV.encode())
    for _ in range(draw(st.integers(1, 4))):
        table[draw(st.integers(0, len(table) - 1))] = draw(st.sampled_from(TABLE_CHARACTERS))
    return bytes(table)


def _load_gives_a_spectrum_or_a_data_error(content, suffix, tmp_path_factory):
    path = tmp_path_factory.mktemp("load") / f"data{suffix}"
    path.write_bytes(content)
    try:
        ds = ix.load(path)
    except ix.DataError as exc:
        assert path.name in str(exc), str(exc)  # (names the file)
    else:
        assert np.iscomplexobj(ds["Z"].values) and (ds["frequency"].values > 0).all()


@FILES
@given(content=file_contents(), suffix=st.sampled_from(FILE_SUFFIXES))
def test_random_files_load_or_raise_data_errors(content, suffix, tmp_path_factory):
    """``ix.load`` on any bytes under any extension: a spectrum, or a DataError naming the file
    (a bare carriage return in a first line once escaped as the csv module's own error)."""
    _load_gives_a_spectrum_or_a_data_error(content, suffix, tmp_path_factory)


@pytest.mark.slow
@settings(FILES, max_examples=4000)
@given(content=file_contents(), suffix=st.sampled_from(FILE_SUFFIXES))
def test_random_files_load_or_raise_data_errors_thorough(content, suffix, tmp_path_factory):
    _load_gives_a_spectrum_or_a_data_error(content, suffix, tmp_path_factory)
