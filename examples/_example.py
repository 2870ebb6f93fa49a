"""Shared plumbing of the example scripts: the command line and atomic figure output.

Every example takes the output folder as its first argument (default ``out/examples/``),
``--fast`` for a quicker, coarser run (used by the smoke test), ``--dpi`` for the PNG
resolution (the README gallery uses ``--dpi 100``) and ``--format pdf`` (or svg, eps) for
vector figures in place of PNG.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # examples write files; they never open windows

import matplotlib.pyplot as plt  # noqa: E402

from impedax.io.atomic import atomic_path  # noqa: E402
from impedax.cli import _configure_jax_cache  # noqa: E402

DEFAULT_OUT = Path("out/examples")
# the figure formats --format offers (matplotlib writes each without extra software)
FIGURE_FORMATS = ("png", "pdf", "svg", "eps")


def parse_args(description: str, argv=None) -> argparse.Namespace:
    """``out`` (folder, created if missing), ``fast`` and ``dpi`` from the command line."""
    parser = argparse.ArgumentParser(description=description.strip().splitlines()[0])
    parser.add_argument("out", nargs="?", type=Path, default=DEFAULT_OUT, help="folder for the PNG files (default: out/examples/)")
    parser.add_argument("--fast", action="store_true", help="coarser grids and fewer fit starts (smoke test)")
    parser.add_argument("--dpi", type=int, default=120, help="resolution of the PNG files (default: 120)")
    parser.add_argument("--format", choices=FIGURE_FORMATS, default=None, help="write every figure in this format in place of the one its name gives (PNG)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    _configure_jax_cache()  # the CLI's persistent compilation cache: reruns skip the fitters' compile
    return args


def save(fig, args: argparse.Namespace, name: str) -> Path:
    """Write ``fig`` to ``args.out/name`` atomically (temp file + rename), close it, print the
    path. The format follows the name's extension, or ``--format`` (which replaces it)."""
    path = args.out / name
    if getattr(args, "format", None):
        path = path.with_suffix(f".{args.format}")
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=args.dpi, format=path.suffix.lstrip(".").lower() or "png")
    plt.close(fig)
    print(f"wrote {path}")
    return path


def decade_grid(ax) -> None:
    """Light major and minor grid lines (log axes read by decade)."""
    ax.grid(alpha=0.35, which="major")
    ax.grid(alpha=0.12, which="minor")
