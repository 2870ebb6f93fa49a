"""Programs kept across processes: a jitted function exported once (`jax.export`, its lowered
StableHLO) and stored beside JAX's persistent compilation cache, so a fresh process neither
traces nor lowers it again; the persistent cache then supplies its executable.

Tracing and lowering a solver is most of what a warm process waits for in a short command
(`impedax diagnose` of a 3-element circuit: 0.9 s of its ~3 s; benchmarks/README.md). Active
only where JAX's persistent cache is (``jax_compilation_cache_dir``, set by the command line
from ``IMPEDAX_CACHE_DIR``); elsewhere a `StoredProgram` is the jitted function itself.

A stored program is found by a key of everything its trace depends on: the caller's name and
static configuration (what the function closes over), the arguments' tree, shapes and dtypes,
the devices, JAX's version, and a digest of impedax's own source files (any edit of the
package gives new keys). A file that cannot be read or called is ignored and replaced.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import importlib.util
import os
import pickle
import re
import tempfile
from pathlib import Path
from typing import Any, Callable, Sequence

import jax
import numpy as np

_SUBDIR = "impedax-exported"

QUICK_COMPILE = {"xla_cpu_use_fusion_emitters": False}
"""XLA options for programs that run briefly, where the compile is the user's wait: the older
elemental code generation instead of the fusion emitters. A fresh single fit's programs
compile in ~40 % less time and run as fast (benchmarks/README.md, "Quick compilation of the
single-fit programs"). Long-running programs (batch lanes, the candidate queue) keep XLA's
defaults: there the option costs a fifth to a third of the run time."""


@functools.lru_cache(maxsize=1)
def _source_digest() -> str:
    """SHA-256 of impedax's Python sources (paths and contents), JAX's and jaxlib's versions."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(str(path.relative_to(root)).encode())
        h.update(path.read_bytes())
    import jaxlib

    h.update(f"jax {jax.__version__} jaxlib {jaxlib.__version__}".encode())
    return h.hexdigest()


@functools.lru_cache(maxsize=1)
def _can_serialize() -> bool:
    """`jax.export` serialises with the flatbuffers package (a dependency of impedax)."""
    return importlib.util.find_spec("flatbuffers") is not None


def _directory() -> Path | None:
    """Where programs are stored: beside JAX's persistent cache, when there is one."""
    cache = jax.config.jax_compilation_cache_dir
    return Path(cache) / _SUBDIR if cache and _can_serialize() else None


class StoredProgram:
    """``jitted`` called as usual; with a persistent cache, through its exported program.

    ``name`` and ``static`` (a repr-able value of everything ``jitted`` closes over that
    changes its trace) name the program; ``shardings(args)``, when given, returns one sharding
    per positional argument (a prefix for its tree) for programs that run on several devices
    (`solvers.over_devices`). ``compiler_options`` (XLA options, e.g. `QUICK_COMPILE`) apply
    to the compilation of ``jitted`` and of the stored program alike; ``jitted`` may then be a
    plain function."""

    def __init__(self, name: str, static: Any, jitted: Callable, shardings: Callable[[Sequence], Sequence] | None = None, compiler_options: dict | None = None):
        self.name, self.static, self.shardings, self.compiler_options = name, static, shardings, compiler_options
        self._traced = jitted  # exported without the options: jax.export rejects them on an inner jit
        self.jitted = jitted if compiler_options is None else jax.jit(jitted, compiler_options=compiler_options)
        self._calls: dict = {}

    def __call__(self, *args):
        directory = _directory()
        if directory is None:
            return self.jitted(*args)
        leaves, in_tree = jax.tree_util.tree_flatten(args)
        if any(isinstance(a, jax.core.Tracer) for a in leaves):  # called inside a trace
            return self._traced(*args)
        call, out_tree = self._lookup(directory, args, leaves, in_tree)
        if call is None:
            return self.jitted(*args)
        return jax.tree_util.tree_unflatten(out_tree, call(*leaves))

    def for_arguments(self, *args) -> Callable:
        """``self`` for many calls with arguments of the tree, shapes and dtypes of ``args``
        (emcee's thousands of calls of a log-posterior): the program is found once here, where
        `__call__` checks every call's arguments (tens of µs a call). Arguments of another
        shape are refused by the program (JAX's shape error), never silently miscomputed."""
        directory = _directory()
        if directory is None:
            return self.jitted
        leaves, in_tree = jax.tree_util.tree_flatten(args)
        call, out_tree = self._lookup(directory, args, leaves, in_tree)
        if call is None:
            return self.jitted
        return lambda *a: jax.tree_util.tree_unflatten(out_tree, call(*jax.tree_util.tree_leaves(a)))

    def _lookup(self, directory: Path, args, leaves, in_tree):
        """(the call of the stored program, its output tree) for these arguments, kept per
        signature; (None, None) when it cannot be stored (`_program`)."""
        avals = tuple((np.shape(a), _dtype(a).str) for a in leaves)
        signature = (in_tree, avals)
        if signature not in self._calls:
            self._calls[signature] = self._program(directory, args, leaves, in_tree, avals)
        return self._calls[signature]

    def _leaf_shardings(self, args) -> list | None:
        if self.shardings is None:
            return None
        per_arg = self.shardings(args)
        return [s for arg, s in zip(args, per_arg) for _ in jax.tree_util.tree_leaves(arg)]

    def _program(self, directory: Path, args, leaves, in_tree, avals):
        """(the call of the stored program, its output tree), exported and stored when new;
        (None, None) when this program cannot be exported (the jitted function serves)."""
        devices = jax.devices()
        try:
            key = _stable_repr((self.name, self.static, avals, len(devices), devices[0].platform, jax.config.jax_enable_x64, _source_digest())) + repr(in_tree)
        except _NotStorable:
            return None, None
        path = directory / f"{self.name}-{hashlib.sha256(key.encode()).hexdigest()[:32]}.bin"
        shardings = self._leaf_shardings(args)
        read = _read(path)
        if read is None:
            try:
                exported, out_tree = self._export(leaves, in_tree, shardings)
                blob = exported.serialize()
            except Exception:  # an operation jax.export does not support: plain jit
                return None, None
            _write(path, (blob, out_tree))
            exported = jax.export.deserialize(blob)  # as a later process will read it
        else:
            exported, out_tree = read
        placed = {} if shardings is None else {"in_shardings": shardings}
        call = jax.jit(exported.call, compiler_options=self.compiler_options, **placed)
        return call, out_tree

    def _export(self, leaves, in_tree, shardings):
        out_tree = []

        def flat(*flat_args):
            out = self._traced(*jax.tree_util.tree_unflatten(in_tree, flat_args))
            out_leaves, tree = jax.tree_util.tree_flatten(out)
            out_tree.append(tree)
            return out_leaves

        fn = jax.jit(flat, in_shardings=shardings) if shardings is not None else jax.jit(flat)
        specs = [jax.ShapeDtypeStruct(np.shape(a), _dtype(a)) for a in leaves]
        exported = jax.export.export(fn)(*specs)
        return exported, out_tree[0]


def _dtype(leaf) -> np.dtype:
    """An argument's dtype: an array's own, a Python scalar's as NumPy has it (float64, int64)."""
    return np.dtype(leaf.dtype) if hasattr(leaf, "dtype") else np.result_type(leaf)


class _NotStorable(Exception):
    """The key would not tell apart programs that trace differently (`_stable_repr`)."""


def _stable_repr(value) -> str:
    """A text of ``value`` that is the same in every process and tells apart what traces
    differently: dataclasses field by field (a circuit's own ``repr`` may leave fields out),
    arrays by their bytes, impedax's functions by module, name and captured values (the source
    digest covers their code), no memory addresses. Raises `_NotStorable` for a function from
    outside impedax (a user's element): its code and the globals it reads are not in the key."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        fields = ", ".join(f"{f.name}={_stable_repr(getattr(value, f.name))}" for f in dataclasses.fields(value))
        return f"{type(value).__module__}.{type(value).__qualname__}({fields})"
    if isinstance(value, (tuple, list)):
        return type(value).__name__ + "(" + ", ".join(_stable_repr(v) for v in value) + ")"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_stable_repr(k)}: {_stable_repr(v)}" for k, v in sorted(value.items(), key=lambda kv: repr(kv[0]))) + "}"
    if isinstance(value, np.ndarray):
        return f"ndarray({value.shape}, {value.dtype.str}, {hashlib.sha256(np.ascontiguousarray(value).tobytes()).hexdigest()})"
    if isinstance(value, functools.partial):
        return f"partial({_stable_repr(value.func)}, {_stable_repr(value.args)}, {_stable_repr(value.keywords)})"
    if callable(value) and not isinstance(value, type) and hasattr(value, "__qualname__"):
        module = getattr(value, "__module__", None) or ""
        if module != "impedax" and not module.startswith("impedax."):
            raise _NotStorable(f"{module}.{value.__qualname__}")
        cells = tuple(c.cell_contents for c in (getattr(value, "__closure__", None) or ()))
        bound = getattr(value, "__self__", None)
        return f"{module}.{value.__qualname__}" + (f"[{_stable_repr(cells)}]" if cells else "") + (f"@{_stable_repr(bound)}" if bound is not None else "")
    return re.sub(r" at 0x[0-9a-fA-F]+", "", repr(value))


def _read(path: Path):
    """(the exported program, its output tree) stored at ``path``, or None."""
    try:
        with open(path, "rb") as fh:
            blob, out_tree = pickle.load(fh)
        return jax.export.deserialize(bytearray(blob)), out_tree
    except Exception:  # missing, cut short, or not a stored program: exported again
        return None


def _write(path: Path, stored) -> None:
    """Atomically (a temporary file renamed), so concurrent processes never read half a file;
    a failure (a full disk, a read-only cache) leaves nothing behind and is not an error, and
    an interrupt (Ctrl-C, SIGTERM's `Interrupted`) leaves no temporary file either."""
    tmp = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".tmp")
        with os.fdopen(fd, "wb") as fh:
            pickle.dump(stored, fh)
        # a plain rename, not io.atomic's writer: an entry stays private (0600), a link planted in a shared cache is replaced, never written through, a read-only entry replaced, never refused
        os.replace(tmp, path)
    except BaseException as exc:
        if tmp is not None and os.path.exists(tmp):
            os.remove(tmp)
        if not isinstance(exc, Exception):
            raise
