"""The ``impedax`` command line. Each command lives in its own module ``impedax.cli.NAME``
with ``register(subparsers)``; `main` turns impedax's own errors into one message and exit 2.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

_COMMAND_MODULES = ("simulate", "info", "fit", "compare", "sample", "kk", "drt", "diagnose", "refine", "force", "gap", "draw", "inspect", "demo")
# each command's one-line help, for ``impedax --help`` without importing any command (and JAX);
# tests/test_cli_basic.py checks it against what the modules register
COMMAND_HELP = {
    "simulate": "write a model's spectrum as CSV",
    "info": "list a model's parameters",
    "fit": "least-squares fit of a circuit to a spectrum",
    "compare": "fit several models to one spectrum and compare them",
    "sample": "Bayesian fit (emcee): posterior draws, credible intervals, diagnostics",
    "kk": "linear Kramers-Kronig test of a spectrum (data problems vs model problems)",
    "drt": "distribution of relaxation times (Tikhonov, Gaussian RBFs): peaks, R_inf, L, credible band",
    "diagnose": "where a model fails and which physical effect is missing",
    "refine": "diagnose, add the best missing effect, refit; repeat until adequate",
    "force": "electrostatic force spectrum of Meyer's or Vezzoli's model",
    "gap": "air-gap thickness, gap voltage and force from three spectra (Sirin et al.)",
    "draw": "draw a model's circuit diagram",
    "inspect": "show what impedax reads from a spectrum file, and how",
    "demo": "the whole story on the embedded data: fit, diagnose, refine, gap thickness, force (writes out/)",
}


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


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser of every command; given ``command``, only that one is built in full (its
    module imported) and the others are listed by name and help."""
    parser = argparse.ArgumentParser(prog="impedax", description="Equivalent-circuit modeling and fitting of impedance spectra.")
    from .. import __version__

    parser.add_argument("--version", action="version", version=f"impedax {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name in _COMMAND_MODULES:
        if command is None or name == command:
            importlib.import_module(f"{__name__}.{name}").register(sub)
        else:
            sub.add_parser(name, help=COMMAND_HELP[name])
    return parser


def _command_of(argv: list[str]) -> str:
    """The command named in ``argv`` ("" when none: ``--help``, ``--version``, errors)."""
    first = next((a for a in argv if not a.startswith("-")), "")
    return first if first in _COMMAND_MODULES else ""


def main(argv: list[str] | None = None) -> int:
    from ..errors import ImpedaxError

    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(_command_of(argv))
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
