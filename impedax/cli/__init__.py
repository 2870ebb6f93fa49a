"""The ``impedax`` command line. Each command lives in its own module ``impedax.cli.NAME``
with ``register(subparsers)``; `main` turns impedax's own errors into one message and exit 2.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

_COMMAND_MODULES = ("simulate", "info", "fit", "compare", "sample", "kk", "drt", "diagnose", "refine", "force", "gap", "draw", "inspect", "demo")


def _configure_jax_cache() -> None:
    """Persistent XLA compilation cache, so a fresh process does not recompile the fitters."""
    import jax

    cache = os.environ.get("IMPEDAX_CACHE_DIR") or os.path.join(os.path.expanduser("~"), ".cache", "impedax", "jax")
    try:
        os.makedirs(cache, exist_ok=True)
    except OSError:
        return
    jax.config.update("jax_compilation_cache_dir", cache)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.2)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="impedax", description="Equivalent-circuit modeling and fitting of impedance spectra.")
    from .. import __version__

    parser.add_argument("--version", action="version", version=f"impedax {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name in _COMMAND_MODULES:
        importlib.import_module(f"{__name__}.{name}").register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    from ..errors import ImpedaxError

    parser = build_parser()
    args = parser.parse_args(argv)
    _configure_jax_cache()
    try:
        return int(args.run(args) or 0)
    except ImpedaxError as exc:
        print(f"impedax {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("impedax: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
