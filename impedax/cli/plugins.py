"""``--plugin FILE.py``: a user's own circuit elements and file readers on the command line.

A plugin is a Python file, executed as a module. Every `impedax.ElementSpec` it holds at its
top level (alone, in a tuple or list such as ``ELEMENTS``, or in a `impedax.Registry` of its own)
is registered into the registry the command uses, and every `impedax.io.Reader` (alone, in a
tuple or list, e.g. the ``register_reader(...)`` tuple of docs/io.md) is tried before the
built-in readers. Built-in specs and readers it imports are not counted. The files come from
``IMPEDAX_PLUGINS`` (`PLUGINS_ENV`, ``os.pathsep``-separated) and then every ``--plugin``, in
that order; a file named twice is read once. Bad input (no such file, a syntax error, an
exception while executing it, a symbol declared twice, a file declaring nothing) is one
`ParameterError` naming the file (and line), exit 2 in the command line.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib.machinery
import importlib.util
import os
import sys
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Collection, Iterable, Mapping, Sequence

from ..errors import ParameterError

if TYPE_CHECKING:
    from ..circuits import Registry
    from ..io import Reader

__all__ = ["PLUGIN_OPTION", "PLUGINS_ENV", "PLUGIN_AFTER", "Plugins", "plugin_files", "load_plugins", "add_plugin_option"]

PLUGIN_OPTION = "--plugin"
PLUGINS_ENV = "IMPEDAX_PLUGINS"
# the dest of a command's own --plugin (after the command's name), joined to the program's
# (before it) by `impedax.cli._load_plugins`: argparse would let the one replace the other
PLUGIN_AFTER = "plugin_after_command"


@dataclass(frozen=True)
class Plugins:
    """What the plugin ``files`` add: the element ``registry`` (the default one with theirs),
    the ``readers`` `impedax.io.load` tries (None: the built-in ones), and which file declared
    each element symbol (``elements``) and reader (``reader_files``)."""

    files: tuple[str, ...] = ()
    registry: "Registry | None" = None
    readers: "tuple[Reader, ...] | None" = None
    elements: Mapping[str, str] = field(default_factory=dict)
    reader_files: Mapping[str, str] = field(default_factory=dict)


def add_plugin_option(parser, *, after_command: bool = False) -> None:
    """``--plugin FILE.py`` (repeatable), the program's (``impedax --plugin F fit ...``) or,
    ``after_command``, a command's (``impedax fit ... --plugin F``)."""
    import argparse

    parser.add_argument(
        PLUGIN_OPTION, action="append", metavar="FILE.py", **({"dest": PLUGIN_AFTER, "default": argparse.SUPPRESS} if after_command else {}),
        help=f"a Python file of your own circuit elements (ElementSpec) and file readers (impedax.io.Reader), read before the command runs "
             f"(repeatable; also ${PLUGINS_ENV}, files separated by {os.pathsep!r}); docs/circuits.md, \"Your elements on the command line\"",
    )


def plugin_files(given: Sequence[str] | None, environ: Mapping[str, str] | None = None) -> list[str]:
    """The plugin files of a run: those of `PLUGINS_ENV` then ``given`` (``--plugin``), each once
    (by its resolved path), empty entries skipped."""
    environ = os.environ if environ is None else environ
    listed = [p for p in environ.get(PLUGINS_ENV, "").split(os.pathsep) if p.strip()] + list(given or ())
    seen, out = set(), []
    for path in listed:
        key = os.path.realpath(path)
        if key not in seen:
            seen.add(key)
            out.append(path)
    return out


# modules already executed, by (resolved path, mtime, size): a second run in one process (tests,
# Python calling `impedax.cli.main`) reuses the same element functions, so compiled solvers,
# cached by registry, are reused too
_EXECUTED: dict[tuple[str, int, int], ModuleType] = {}


def _where(path: str, from_environment: Collection[str] = ()) -> str:
    """How a message names plugin ``path``: ``--plugin FILE``, or ``$IMPEDAX_PLUGINS FILE`` for
    a file listed there (a variable set long ago was named as an option never typed)."""
    return f"${PLUGINS_ENV} {path}" if path in from_environment else f"{PLUGIN_OPTION} {path}"


def _line_in(exc: BaseException, path: Path) -> int | None:
    """The line of ``path`` nearest to where ``exc`` was raised (its innermost frame in the file)."""
    target = os.path.realpath(path)
    lines = [f.lineno for f in traceback.extract_tb(exc.__traceback__) if os.path.realpath(f.filename) == target]
    return lines[-1] if lines else None


def _execute(path_text: str, where: str) -> ModuleType:
    """The module of plugin file ``path_text`` (named ``where`` in messages, `_where`), executed
    (once per content, `_EXECUTED`)."""
    path = Path(path_text)
    if not path.is_file():
        raise ParameterError(f"{where}: no such file" if not path.exists() else f"{where}: not a file")
    stat = path.stat()
    key = (os.path.realpath(path), stat.st_mtime_ns, stat.st_size)
    if key in _EXECUTED:
        return _EXECUTED[key]
    # a module name of its own per file, so two plugins named alike do not replace each other
    name = f"impedax_plugin_{hashlib.sha1(key[0].encode()).hexdigest()[:10]}_{''.join(c if c.isalnum() else '_' for c in path.stem)}"
    loader = importlib.machinery.SourceFileLoader(name, str(path))
    spec = importlib.util.spec_from_loader(name, loader)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # (dataclasses and pickling look their module up by name)
    # its folder first on the import path while it runs, as Python puts a script's: a plugin
    # imports the modules beside it (``from formulas import dc``) from any working folder (not
    # only from its own folder: from another, ModuleNotFoundError)
    folder = os.path.dirname(os.path.abspath(path))
    sys.path.insert(0, folder)
    try:
        # what it prints goes to stderr: standard output carries the command's JSON or CSV (a
        # plugin's print("loaded") would come before them, and a pipe's reader fail)
        with contextlib.redirect_stdout(sys.stderr):
            loader.exec_module(module)
    except SyntaxError as exc:
        sys.modules.pop(name, None)
        line = f", line {exc.lineno}" if exc.lineno else ""
        if exc.filename and os.path.realpath(exc.filename) != os.path.realpath(path):  # (a module it imports)
            raise ParameterError(f"{where}, line {_line_in(exc, path) or '?'}: it imports {exc.filename}, which has a syntax error{line}: {exc.msg}") from None
        raise ParameterError(f"{where}{line}: syntax error: {exc.msg}") from None
    except (Exception, SystemExit) as exc:
        sys.modules.pop(name, None)
        line = _line_in(exc, path)
        what = f"{type(exc).__name__}: {exc}"
        raise ParameterError(f"{where}{f', line {line}' if line else ''}: executing it raised {what}") from None
    finally:
        sys.path.remove(folder)  # (the first entry equal to it: the one put there)
    _EXECUTED[key] = module
    return module


def _declared(module: ModuleType, kind: type, builtin: Iterable) -> list:
    """The ``kind`` instances ``module`` holds at its top level: alone, in a tuple or list, or
    among a `Registry`'s specs; in order, each once, the ``builtin`` ones left out."""
    from ..circuits import Registry

    builtin = list(builtin)
    found: list = []
    for name, value in vars(module).items():
        if name.startswith("__"):
            continue
        items = value.specs if isinstance(value, Registry) else value if isinstance(value, (tuple, list)) else (value,)
        for item in items:
            if isinstance(item, kind) and not any(item is b or item == b for b in builtin) and not any(item is f for f in found):
                found.append(item)
    return found


def _claims(spec) -> list[tuple[str, str]]:
    """What an element spec claims in a registry: its symbol and aliases, its CDC letter and its
    impedance.py symbol, each as (what, text)."""
    claims = [("element symbol", s) for s in (spec.symbol, *spec.aliases)]
    return claims + [(what, s) for what, s in (("CDC letter", spec.cdc), ("impedance.py symbol", spec.impedance_py)) if s is not None]


def _quiet_reader(reader, where: str):
    """``reader`` with its ``origin`` ``where`` (`_where`: ``impedax.load`` names it, with the line
    that raised, in the one `DataError` a failing read or sniff becomes), printing to stderr, not
    stdout: a sniff's or read's ``print`` would come before ``inspect --json``'s JSON (the loader,
    not a wrapper here, turns the read's exceptions into that message)."""
    import dataclasses

    return dataclasses.replace(reader, read=_quiet(reader.read), sniff=_quiet(reader.sniff), origin=where)


# each plugin formula's quiet wrapper (`_quiet_formula`), by the formula: the same wrapper for a
# second run in one process, so that its registry equals the first's and compiled solvers are reused
_QUIET: dict = {}


def _quiet_formula(formula):
    """``formula`` printing to stderr, not stdout: a user's formula runs while JAX traces it,
    and a ``print`` there (a debugging line) would come before the command's JSON or CSV.
    The wrapper keeps the formula's signature and names it (``__wrapped__``) for
    the messages that give its file and line."""
    if formula is None:
        return None
    try:
        return _QUIET[formula]
    except KeyError:
        pass
    except TypeError:  # (a callable object that is not hashable: wrapped each time)
        return _quiet(formula)
    _QUIET[formula] = _quiet(formula)
    return _QUIET[formula]


def _quiet(formula):
    @functools.wraps(formula)
    def quiet(*args, **kwargs):
        with contextlib.redirect_stdout(sys.stderr):
            return formula(*args, **kwargs)

    return quiet


def _quiet_spec(spec):
    """``spec`` with its impedance and admittance formulas `_quiet_formula`."""
    import dataclasses

    return dataclasses.replace(spec, impedance=_quiet_formula(spec.impedance), admittance=_quiet_formula(spec.admittance))


def load_plugins(files: Sequence[str], from_environment: Collection[str] = ()) -> Plugins:
    """Execute each plugin file (`_execute`) and collect its element specs and readers
    (`_declared`) into a `Plugins`: the specs registered into `impedax.DEFAULT_REGISTRY` in
    order, the readers tried first (`impedax.io.register_reader`). `ParameterError` naming the
    file (as ``$IMPEDAX_PLUGINS FILE`` for those of ``from_environment``, else ``--plugin
    FILE``) for a symbol, CDC letter or impedance.py symbol declared twice, two readers of one
    name, or a file that declares neither."""
    from ..circuits import DEFAULT_REGISTRY, ElementSpec
    from ..errors import CircuitError
    from ..io import READERS, Reader

    if not files:
        return Plugins(registry=DEFAULT_REGISTRY)
    registry, own = DEFAULT_REGISTRY, []
    claimed: dict[tuple[str, str], tuple[str | None, str]] = {claim: (None, spec.name) for spec in DEFAULT_REGISTRY for claim in _claims(spec)}
    elements: dict[str, str] = {}
    reader_files: dict[str, str] = {}
    for path in files:
        where = _where(path, from_environment)
        module = _execute(path, where)
        specs = [_quiet_spec(spec) for spec in _declared(module, ElementSpec, DEFAULT_REGISTRY.specs)]
        own_readers = _declared(module, Reader, READERS)
        if not specs and not own_readers:
            raise ParameterError(f"{where}: declares no ElementSpec and no impedax.io.Reader at its top level (docs/circuits.md \"Adding an element\", docs/io.md)")
        for spec in specs:
            for what, text in _claims(spec):
                if (what, text) in claimed:
                    owner, name = claimed[(what, text)]
                    raise ParameterError(
                        f"{where}: {what} {text!r} of element {spec.name!r} is "
                        + (f"impedax's built-in {name}: choose another" if owner is None else f"declared twice in this file ({name} has it)" if owner == path else f"declared in {owner} too ({name})")
                    )
            try:
                registry = registry.register(spec)
            except CircuitError as exc:
                raise ParameterError(f"{where}: {exc}") from None
            claimed.update({claim: (path, spec.name) for claim in _claims(spec)})
            elements[spec.symbol] = path
        for reader in own_readers:
            if reader.name in reader_files:
                raise ParameterError(f"{where}: a reader named {reader.name!r} is declared in {reader_files[reader.name]} too")
            reader_files[reader.name] = path
            own.append(reader)
    own = [_quiet_reader(reader, _where(reader_files[reader.name], from_environment)) for reader in own]
    # each plugin's readers before the built-in ones, in the order given (`register_reader`: one
    # named as a built-in replaces it)
    readers = (*own, *(r for r in READERS if r.name not in reader_files)) if own else None
    return Plugins(files=tuple(files), registry=registry, readers=readers, elements=elements, reader_files=reader_files)
