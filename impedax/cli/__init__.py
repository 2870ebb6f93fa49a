"""The ``impedax`` command line. Each command lives in its own module ``impedax.cli.NAME``
with ``register(subparsers)``; `main` turns impedax's own errors into one message and exit 2,
and SIGINT/SIGTERM into one line ("interrupted; nothing written") and exit 130/143, with every
temporary file removed.
"""

from __future__ import annotations

import argparse
import atexit
import contextlib
import gc
import importlib
import os
import re
import shlex
import signal
import sys
import threading
from typing import NoReturn

from ..progress import silenced
from .plugins import PLUGIN_OPTION, add_plugin_option

_COMMAND_MODULES = ("simulate", "info", "fit", "compare", "sample", "kk", "drt", "diagnose", "refine", "force", "gap", "remaining", "draw", "inspect", "stack", "demo")
# each command's one-line help, for ``impedax --help`` without importing any command (and JAX);
# tests/test_cli_basic.py checks it against what the modules register
COMMAND_HELP = {
    "simulate": "write a model's spectrum as CSV",
    "info": "list a model's parameters",
    "fit": "least-squares fit of a circuit to a spectrum",
    "compare": "fit several models to one spectrum (or to each of several) and compare them",
    "sample": "Bayesian fit (emcee): posterior draws, credible intervals, diagnostics",
    "kk": "linear Kramers-Kronig test of a spectrum (data problems vs model problems)",
    "drt": "distribution of relaxation times (Tikhonov, Gaussian RBFs): peaks, R_inf, L, credible band",
    "diagnose": "where a model fails and which physical effect is missing",
    "refine": "diagnose, add the best missing effect, refit; repeat until adequate",
    "force": "electrostatic force spectrum of Meyer's or Vezzoli's model",
    "gap": "air-gap thickness, gap voltage and force from three spectra (Sirin et al.), or one of a single contact",
    "remaining": "the remaining impedance total − skin − touchscreen (or a single contact's trial mean) as a spectrum file, as impedax gap fits it",
    "draw": "draw a model's circuit diagram",
    "inspect": "show what impedax reads from a spectrum file, and how",
    "stack": "several files of one spectrum each as one series (a new dimension) in a netCDF file",
    "demo": "the whole story on the embedded data: fit, diagnose, refine, gap thickness, force (writes out/)",
}


def _configure_jax_cache() -> None:
    """Persistent XLA compilation cache, so a fresh process does not recompile the fitters."""
    from .. import use_compilation_cache

    use_compilation_cache()


class CommandLineParser(argparse.ArgumentParser):
    """argparse's parser whose usage error is one message: ``impedax fit: error: unrecognized
    arguments: --max-step 5; did you mean --max-steps?`` first, then one short usage line
    naming the positional arguments and ``--help`` (exit 2). argparse printed its whole usage
    block first (nine lines for ``impedax fit``), so the message and its hint came last, under
    it. Each command's parser is of this class too (``add_subparsers`` makes its parent's)."""

    def short_usage(self) -> str:
        """``usage: impedax fit [options] DATA (impedax fit --help lists them)``."""
        formatter = self._get_formatter()
        formatter.add_usage(None, [a for a in self._actions if not a.option_strings], [], prefix="")
        positionals = " ".join(formatter.format_help().split()).removeprefix(self.prog).strip()
        return f"usage: {self.prog} [options] {positionals} ({self.prog} --help lists them)".replace("  ", " ")

    def parse_known_args(self, args=None, namespace=None):
        self._words = list(sys.argv[1:] if args is None else args)  # (for `error`'s hint on a required option)
        return super().parse_known_args(args, namespace)

    def error(self, message: str) -> NoReturn:
        hint = self._misspelt_required_hint(message) + self._circuit_without_option_hint(message) + self._dash_value_hint(message) + self._dash_file_hint(message)
        self.exit(2, f"{self.prog}: error: {message}{hint}\n{self.short_usage()}\n")

    def _dash_file_hint(self, message: str) -> str:
        """``; -data.csv is a file, but a word that starts with '-' reads as an option: write
        ./-data.csv`` when a required argument is missing and a word taken for an unknown option
        names an existing file (``impedax inspect -data.csv`` said only "required: FILE")."""
        if not message.startswith("the following arguments are required"):
            return ""
        files = [w for w in getattr(self, "_words", ()) if w.startswith("-") and w not in self._option_string_actions and os.path.isfile(w)]
        if not files:
            return ""
        return f"; {files[0]} is a file, but a word that starts with '-' reads as an option: write ./{files[0]}"

    def _dash_value_hint(self, message: str) -> str:
        """``; its value -1% starts with '-', which reads as an option: write --noise=-1%`` when
        argparse found no value after an option because the next word starts with '-' (a
        negative value it does not take for a number: ``--noise -1%``)."""
        found = re.match(r"argument (\S+): expected one argument", message)
        if found is None:
            return ""
        words = getattr(self, "_words", [])
        for option, value in zip(words, words[1:]):
            if option in found.group(1).split("/") and value.startswith("-") and value not in self._option_string_actions:
                return f"; its value {value} starts with '-', which reads as an option: write {option}={value}"
        return ""

    def _circuit_without_option_hint(self, message: str) -> str:
        """``; a circuit follows --model: impedax fit DATA --model 'R0 + R1 || C1'`` when
        ``--model`` is missing and a word given where no option takes it reads as a circuit
        (``impedax fit data.csv 'R0 + R1 || C1'``, `circuit_words`); argparse said only
        "required: --model"."""
        if not message.startswith("the following arguments are required") or "--model" not in message:
            return ""
        loose, taker = [], None  # (words no option takes; the option whose value comes next)
        for word in getattr(self, "_words", ()):
            action = self._option_string_actions.get(word)
            if taker is None and not word.startswith("-"):
                loose.append(word)
            taker = action if action is not None and action.nargs != 0 else None
        return model_option_hint(self.prog, circuit_words(loose))

    def _misspelt_required_hint(self, message: str) -> str:
        """``; did you mean --model? (--models is not an option of impedax compare)`` when a
        required option is missing and an unknown option word given is a slip of one
        (`closest_options`): argparse refuses the missing option before it gets to the unknown
        ones, so ``compare --models A`` was told only "required: --model"."""
        if not message.startswith("the following arguments are required"):
            return ""
        known = set(self._option_string_actions)
        options = [o for o in self._option_string_actions if o.startswith("--")]
        unknown = [w for w in getattr(self, "_words", ()) if w.startswith("--") and w.split("=", 1)[0] not in known]
        hints = closest_options(unknown, options)
        if not hints:
            return ""
        words = ", ".join(w.split("=", 1)[0] for w in unknown)
        return f"; did you mean {' or '.join(hints)}? ({words} {'is not an option' if len(unknown) == 1 else 'are not options'} of {self.prog})"


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser of every command; given ``command``, only that one is built in full (its
    module imported) and the others are listed by name and help."""
    parser = CommandLineParser(prog="impedax", description="Equivalent-circuit modeling and fitting of impedance spectra.")
    from .. import __version__

    parser.add_argument("--version", action="version", version=f"impedax {__version__}")
    add_plugin_option(parser)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name in _COMMAND_MODULES:
        if command is None or name == command:
            importlib.import_module(f"{__name__}.{name}").register(sub)
            add_plugin_option(sub.choices[name], after_command=True)
        else:
            sub.add_parser(name, help=COMMAND_HELP[name])
    return parser


def _load_plugins(args) -> None:
    """The plugin files of ``$IMPEDAX_PLUGINS`` and every ``--plugin`` (`impedax.cli.plugins`),
    executed: ``args.plugin`` becomes their list, ``args.registry`` the element registry with
    theirs and ``args.readers`` the readers `impedax.io.load` tries (None: the built-in ones)."""
    from .plugins import PLUGIN_AFTER, load_plugins, plugin_files

    files = plugin_files([*(getattr(args, "plugin", None) or ()), *vars(args).pop(PLUGIN_AFTER, ())])
    plugins = load_plugins(files, from_environment=plugin_files([]))  # (those named as $IMPEDAX_PLUGINS' in messages)
    args.plugin, args.registry, args.readers = files, plugins.registry, plugins.readers


def _first_word(argv: list[str]) -> str | None:
    """The first argument that is not an option nor the value of ``--plugin`` before the
    command (the command, as typed), or None."""
    words = iter(argv)
    for a in words:
        if a == PLUGIN_OPTION:
            next(words, None)
        elif not a.startswith("-"):
            return a
    return None


def _command_of(argv: list[str]) -> str:
    """The command named in ``argv`` ("" when none: ``--help``, ``--version``, errors)."""
    first = _first_word(argv)
    return first if first in _COMMAND_MODULES else ""


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM arrived while `main` ran a command in a process it does not own."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def _atomic_writes():
    """`impedax.io.atomic` if a command has loaded it (else nothing was written, and no
    temporary exists: ``impedax --help`` does not import the io layer for this)."""
    return sys.modules.get(__name__.rsplit(".", 1)[0] + ".io.atomic")


def _written_count() -> int:
    atomic = _atomic_writes()
    return len(atomic.written_outputs()) if atomic is not None else 0


def _remove_temporaries() -> None:
    atomic = _atomic_writes()
    if atomic is not None:
        atomic.remove_temporaries()


def _interrupted_line(command: str, written_before: int) -> str:
    atomic = _atomic_writes()
    written = atomic.written_outputs()[written_before:] if atomic is not None else ()
    what = "nothing written" if not written else f"already written: {', '.join(written)}"
    return f"impedax{' ' + command if command else ''}: interrupted; {what}"


@contextlib.contextmanager
def _signal_handlers(command: list[str], *, own_process: bool):
    """SIGINT and SIGTERM while a command runs: every temporary file and folder is removed
    (`impedax.io.atomic.remove_temporaries`) by the handler itself. When impedax owns the
    process (the ``impedax`` program), the handler then prints one line and ends the process
    with 128 + the signal number at once, so no library on the stack (emcee, dask, JAX) gets to
    print a traceback; called from Python, it raises `Interrupted` instead."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    fired = []
    written_before = _written_count()

    def handler(signum, frame):
        if fired:  # a second Ctrl-C while cleaning up changes nothing
            return
        fired.append(signum)
        _remove_temporaries()
        if own_process:
            # first return over a progress line the interrupt cut short (sample, gap; cleared on a terminal)
            clear = "\r\033[K" if sys.stderr.isatty() else "\r"
            with contextlib.suppress(OSError, ValueError):
                os.write(2, (clear + _interrupted_line(command[0], written_before) + "\n").encode())
            os._exit(128 + signum)
        raise Interrupted(signum)

    previous = {s: signal.signal(s, handler) for s in _SIGNALS}
    try:
        yield
    finally:
        for s, old in previous.items():
            signal.signal(s, old)


GC_THRESHOLDS = (50_000, 10, 10)
"""The cyclic garbage collector's thresholds in the ``impedax`` program: a collection per 50,000
new objects instead of Python's 700. With the default, a fresh `impedax fit` spent 0.23–0.32 s
in collections that scan the million objects of JAX, xarray and pandas, three of them full;
now 0.09–0.12 s, and a whole `refine` peaks at the same memory (benchmarks/README.md, "The
garbage collector")."""


def main(argv: list[str] | None = None) -> int:
    """Run one ``impedax`` command; returns the exit code (0 done, 2 bad input, 130/143
    interrupted by SIGINT/SIGTERM). Without ``argv`` it reads ``sys.argv`` and acts as the
    program: the garbage collector's thresholds are `GC_THRESHOLDS`, an interrupt ends the
    process at once (`_signal_handlers`), and so does the end of the command (`_end_program`)."""
    own_process = argv is None
    if own_process:
        gc.set_threshold(*GC_THRESHOLDS)
    argv = sys.argv[1:] if argv is None else list(argv)
    command = [""]
    written_before = _written_count()
    with _signal_handlers(command, own_process=own_process):
        try:
            with silenced():  # (each command gives its own printer to the calls it reports; the others say nothing)
                code = _run(argv, command)
        except KeyboardInterrupt as exc:
            _remove_temporaries()
            signum = exc.signum if isinstance(exc, Interrupted) else signal.SIGINT
            print(_interrupted_line(command[0], written_before), file=sys.stderr)
            code = 128 + signum
    if own_process:
        _end_program(code)
    return code


def _end_program(code: int) -> NoReturn:
    """End the ``impedax`` program with exit status ``code``, skipping the interpreter's
    teardown. Every output is written and closed by then; standard output and error are
    flushed and the exit handlers run (JAX's, temporary folders'), as at a normal exit. What is
    skipped is freeing every module and object one by one, JAX's compiled programs among them,
    which takes 0.2–0.5 s after a fit (benchmarks/README.md, "The program ends without the
    interpreter's teardown")."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError):
            stream.flush()
    atexit._run_exitfuncs()
    os._exit(code)


def _repeated_file(subparser: argparse.ArgumentParser, argv: list[str]) -> str | None:
    """The error when an option that takes one file (``--out``, ``--plot``, ``-o``, ...: its
    value named FILE…, FIG… or OUT…) is given more than once, naming each value; else None.
    argparse keeps the last, so ``impedax fit DATA --out a.csv --out a.json`` would write a.json
    alone and say nothing of a.csv: the command stops (exit 2)."""
    for action in subparser._actions:
        metavar = action.metavar if isinstance(action.metavar, str) else ""
        if not action.option_strings or not isinstance(action, argparse._StoreAction) or not metavar.startswith(("FILE", "FIG", "OUT")):
            continue
        given = []
        for k, word in enumerate(argv):
            for flag in action.option_strings:
                if word == flag and k + 1 < len(argv):
                    given.append(argv[k + 1])
                elif flag.startswith("--") and word.startswith(flag + "="):
                    given.append(word[len(flag) + 1:])
        if len(given) > 1:
            flag = action.option_strings[-1]
            return (f"{flag} given {len(given)} times ({', '.join(given)}): it takes one file, and only the last would be written or read; "
                    f"give {flag} once (a result in several formats: run the command once per file, or write the others with impedax.write_result)")
    return None


def _refuse_empty_file(subparser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """Exit 2 naming the argument that names a spectrum file to read (DATA, FILE, DATA_SKIN …,
    --frequencies) when it is empty, ``impedax kk "$DATA"`` of an unset variable, not
    "'.': is a directory, not a spectrum file" (pathlib reads '' as the current folder)."""
    for action in subparser._actions:
        named = action.option_strings[-1] if action.option_strings else action.metavar
        if not (named == "--frequencies" or (not action.option_strings and str(named).startswith(("DATA", "FILE")))):
            continue
        value = getattr(args, action.dest, None)
        if value == "" or (isinstance(value, list) and "" in value):
            subparser.error(f"argument {named}: empty file name: no spectrum file was named (an unset shell variable, \"$DATA\" with nothing in it?)")


def _subparser(parser: argparse.ArgumentParser, command: str) -> argparse.ArgumentParser:
    return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices[command]


# the commands that analyse every spectrum of one DATA file: a series from files of one
# spectrum each is `impedax stack`'s output (named when such a command is given several files)
SERIES_COMMANDS = ("fit", "kk", "drt", "compare")
#: Commands of one spectrum file whose second file is told to run the command once per file (`_refuse_unknown`).
ONE_FILE_COMMANDS = ("inspect", "diagnose", "refine", "sample")
#: Commands of up to three files (total, skin, touchscreen) whose fourth is told how trials go in one file.
CONTACT_COMMANDS = ("gap", "remaining")


def _model_parameters(model) -> list[tuple[list[str], dict[str, str]]]:
    """(parameter names, impedance.py symbols) of each circuit of ``model`` (``args.model``: a
    text, or a list of them for compare), impedax or impedance.py text; those that do not read
    are left out."""
    from .. import circuits

    out = []
    for text in [model] if isinstance(model, str) else list(model or []):
        if not isinstance(text, str):
            continue
        try:
            circuit = circuits.parse(text)
        except Exception:
            try:
                circuit = circuits.from_impedance_py(text)
            except Exception:
                continue
        out.append((list(circuit.parameter_names()), dict(circuits.DEFAULT_REGISTRY.impedance_py_symbols)))
    return out


def _impedax_assignment(item: str, parameters: list[tuple[list[str], dict[str, str]]]) -> str:
    """A NAME=... word with an impedance.py parameter name (``CPE1_1=0.5:1``) written with the
    impedax name it means in the model (``CPE1.alpha=0.5:1``, `impedance_py_parameter`)."""
    from ..arguments import impedance_py_parameter

    name, _, rest = item.partition("=")
    for known, symbols in parameters:
        if name in known:
            return item
        meant = impedance_py_parameter(name, known, symbols)
        if len(meant) == 1:
            return f"{meant[0]}={rest}"
    return item


OPTION_HINT_CUTOFF = 0.7
"""The least difflib ratio of an unknown option to the one `_refuse_unknown` names: its "--" is
shared by all, so difflib's 0.6 would name --dpi for --fix (0.6) and --plot for --prior (0.62) on
`impedax gap`; the slips it is for score ≥ 0.85 (--maxsteps 0.95, --quite 0.86, --fmx 0.91).
The ratio is taken of the letters alone, without the dashes (`closest_options`): with them
--fix would score 0.73 against --fmin, one of gap's band options; without,
0.57, while --quite (0.8), --stps (0.89) and --fmx (0.86) keep their hints."""


def closest_options(words: list[str], options: list[str]) -> list[str]:
    """The option of ``options`` each unknown option word of ``words`` is a slip of (the same
    letters but for dashes, underscores and case, else difflib's closest at `OPTION_HINT_CUTOFF`),
    each once; words that are no options are passed over."""
    import difflib

    def squeezed(option: str) -> str:
        return option.lstrip("-").replace("-", "").replace("_", "").lower()

    hints = []
    for item in words:
        if not item.startswith("-") or item == "-":
            continue
        name = item.split("=", 1)[0]
        same = [o for o in options if squeezed(o) == squeezed(name)]
        by_letters = {squeezed(o): o for o in reversed(options)}  # (the first option of a spelling wins)
        close = same or [by_letters[m] for m in difflib.get_close_matches(squeezed(name), list(by_letters), n=1, cutoff=OPTION_HINT_CUTOFF)]
        if close and close[0] not in hints:
            hints.append(close[0])
    return hints


# a word that reads as circuit text: element names joined by +, ||, | or -, with parentheses or
# impedance.py's p(...,...), s(...,...); no ".", "/", "=" (a file name, a path, a NAME=VALUE)
_CIRCUIT_WORD_RE = re.compile(r"[A-Za-z][A-Za-z0-9_]*(?:\s*(?:\+|\|\||\||-|,|\(|\))\s*[A-Za-z0-9_()\s]*)+|[A-Za-z]+_?[0-9]+")


def circuit_words(words) -> list[str]:
    """The words of ``words`` that read as circuit text and name no existing file:
    ``R0 + R1 || C1``, ``R0-p(R1,C1)``, ``R1``."""
    return [w for w in words if _CIRCUIT_WORD_RE.fullmatch(w.strip()) and any(c.isalpha() for c in w) and not os.path.exists(w)]


def _loose_words(unknown: list[str]) -> list[str]:
    """The words of argparse's unrecognized ones that no unknown option takes: ``R0`` of
    ``compare ... --shared R0`` is the value of ``--shared`` (no option of compare), not a circuit
    given without its ``--model``."""
    return [w for i, w in enumerate(unknown) if not w.startswith("-") and not (i and unknown[i - 1].startswith("--") and "=" not in unknown[i - 1])]


def model_option_hint(prog: str, circuits: list[str]) -> str:
    """``; a circuit follows --model: impedax fit DATA --model 'R0 + R1 || C1'`` (each after its
    own --model when there are several), or "" for no ``circuits``."""
    if not circuits:
        return ""
    given = " ".join(f"--model {shlex.quote(c)}" for c in circuits)
    if prog.split()[-1] in NO_DATA_COMMANDS:  # (impedax info R0 R1: info reads no DATA; one circuit, quoted)
        return f"; {prog} takes one circuit and no data file: quote a circuit of several words as one ({prog} 'R0 + R1 || C1'), or run {prog} once per circuit"
    return f"; a circuit follows {'its own ' if len(circuits) > 1 else ''}--model: {prog} DATA {given}"


SAMPLE_NOISE_WORDS = ("--noise proportional (σ_k = sigma_rel·|Z_k|, sigma_rel sampled: the noise model of impedax fit's --weighting modulus) "
                      "or --noise sigma (the data's own sigma, as --weighting sigma)")
"""impedax sample's noise models in the words of fit's weightings, for a ``--weighting`` given to
sample (`_refuse_unknown`) and a weighting's name given as its ``--noise`` (`sample.noise_model_option`)."""

NO_DATA_COMMANDS = ("info",)
"""Commands with a --model that read no data file (`model_option_hint`)."""


def _refuse_unknown(parser: argparse.ArgumentParser, command: str, unknown: list[str], model=None) -> NoReturn:
    """Exit 2 with "unrecognized arguments" naming the closest option of that command for each
    unknown one (``--maxsteps`` → ``--max-steps``), then the command's own short usage line
    (`CommandLineParser.error`).
    A NAME=VALUE word is shown after the option named (else the first that takes one), with
    the impedax name of an impedance.py parameter name of ``model`` (``args.model``)."""

    sub = _subparser(parser, command)
    options = [o for action in sub._actions for o in action.option_strings if o.startswith("--")]
    hints = closest_options(unknown, options)
    hint = f"; did you mean {' or '.join(hints)}?" if hints else ""
    assignments = [item for item in unknown if _ASSIGNMENT_RE.match(item)]
    takers = [o for o in ASSIGNMENT_OPTIONS if o in sub._option_string_actions]
    if assignments and takers:
        parameters = _model_parameters(model)
        assignments = [_impedax_assignment(item, parameters) for item in assignments]
    if assignments and PARAM_OPTION in takers:  # (a value without its --param)
        hint += f"; a parameter value follows {PARAM_OPTION}: {PARAM_OPTION} {' '.join(assignments)} (or {PARAM_OPTION} before each)"
    elif assignments and takers:  # (fit R1=5: which of --init, --fix, ... was meant is the user's to say, unless a misspelt one is named)
        example = next((h for h in hints if h in takers), takers[0])
        hint += f"; a NAME=VALUE follows its option ({', '.join(takers)}): e.g. {example} {' '.join(assignments)}"
    if "--model" in sub._option_string_actions:  # (refine DATA 'R0 + R1 || C1': its --model is optional)
        hint += model_option_hint(sub.prog, circuit_words(_loose_words(unknown)))
    if command == "sample" and any(item.split("=", 1)[0] == "--weighting" for item in unknown):  # (fit's option, reached for on sample)
        hint += f"; impedax sample has no --weighting: its noise model is {SAMPLE_NOISE_WORDS}"
    files = [item for item in unknown if not item.startswith("-") and os.path.isfile(item)]
    if files and command in SERIES_COMMANDS:  # (fit day01.csv day02.csv: one DATA per run)
        hint += f"; {command} reads one DATA file: join files of one spectrum each into one series with impedax stack FILE ... --out SERIES.nc, then impedax {command} SERIES.nc"
    elif files and command in ONE_FILE_COMMANDS:  # (inspect a.csv b.csv: more than "unrecognized arguments: b.csv")
        what = "" if command == "inspect" else "DATA "
        hint += f"; {command} reads one {what}file: run impedax {command} once per file"
    elif files and command in CONTACT_COMMANDS:
        hint += (f"; {command} reads at most three files, DATA_TOTAL [DATA_SKIN DATA_TS]: the trials of one contact go in one file as an extra "
                 "dimension (impedax stack TRIAL_FILE ... --dim trial --out TOTAL.nc)")
    sub.error(f"unrecognized arguments: {' '.join(unknown)}{hint}")


def _refuse_unknown_command(parser: argparse.ArgumentParser, argv: list[str]) -> None:
    """Exit 2 naming the closest command when the first word is none (``fitt`` → ``fit``);
    argparse's own message lists them all, with no hint."""
    import difflib

    first = _first_word(argv)
    if first is None or first in _COMMAND_MODULES:
        return
    close = difflib.get_close_matches(first, list(_COMMAND_MODULES), n=1, cutoff=0.6)
    if close:
        parser.error(f"argument COMMAND: invalid choice: {first!r}; did you mean {close[0]}? (choose from {', '.join(_COMMAND_MODULES)})")


# a NAME=VALUE word: a parameter name (R0, C_s, CPE_sc.Q) then "="; a MODEL never holds "="
_ASSIGNMENT_RE = re.compile(r"[A-Za-z_][\w.]*=")
PARAM_OPTION = "--param"
# the options whose value is one NAME=... word and that may be followed by more of them
# (``--init R1=43k C2=5u``), each read as if its option were repeated (`_spread_params`)
ASSIGNMENT_OPTIONS = (PARAM_OPTION, "--init", "--fix", "--bound", "--prior")


def _spread_params(argv: list[str], options: tuple[str, ...] = ASSIGNMENT_OPTIONS) -> list[str]:
    """``--param A=1 B=2`` as ``--param A=1 --param B=2`` (the README's ``--param NAME=VALUE
    ...``), and the same for every option of ``options`` (``--init``, ``--fix``, ``--bound``,
    ``--prior``): each NAME=... word right after such an option's value gets that option of its
    own, up to the first other word or ``--``. Not argparse's ``nargs="+"``, which would also
    take a MODEL written after the values (``simulate --param R0=5 R0``) as one more value."""
    out: list[str] = []
    spreading = None  # the option whose values are being spread
    pending = None  # an option of ``options`` whose value comes next
    words = iter(argv)
    for word in words:
        if word == "--":
            return out + [word, *words]
        if pending and not word.startswith("-"):  # (its value: argparse refuses an option there)
            out.append(word)
            spreading, pending = pending, None
            continue
        # (a word that names an existing file is a spectrum file, even when it reads run=3.csv)
        if spreading and _ASSIGNMENT_RE.match(word) and not os.path.exists(word):
            out += [spreading, word]
            continue
        out.append(word)
        spreading = next((o for o in options if word.startswith(o + "=")), None)
        pending = word if word in options else None
    return out


def _run(argv: list[str], command: list[str]) -> int:
    from ..errors import ImpedaxError

    name = _command_of(argv)
    parser = build_parser(name)
    _refuse_unknown_command(parser, argv)
    if name:
        spread = tuple(o for o in ASSIGNMENT_OPTIONS if o in _subparser(parser, name)._option_string_actions)
        argv = _spread_params(argv, spread) if spread else argv
    args, unknown = parser.parse_known_args(argv)  # (``--version`` and ``--help`` end here, before NumPy is imported)
    from .common import option_words, positional_model, read_impedance_py_model, unused_figure_options

    command[0] = args.command
    if unknown:
        _refuse_unknown(parser, args.command, unknown, getattr(args, "model", None))
    positional_model(_subparser(parser, args.command), args)
    _refuse_empty_file(_subparser(parser, args.command), args)
    repeated = _repeated_file(_subparser(parser, args.command), argv)
    if repeated:
        print(f"impedax {args.command}: error: {repeated}", file=sys.stderr)
        return 2
    for note in unused_figure_options(_subparser(parser, args.command), args):
        print(f"impedax {args.command}: note: {note}", file=sys.stderr)
    _configure_jax_cache()
    try:
        _load_plugins(args)
        read_impedance_py_model(args, args.command)
        return int(args.run(args) or 0)
    except ImpedaxError as exc:
        # (in the command line's words: ``--max-rc must be ...``, where Python says max_rc)
        print(f"impedax {args.command}: error: {option_words(args.command, exc)}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        return 0
