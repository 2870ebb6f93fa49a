"""``impedax demo``: the main job on the embedded SYNTHETIC data (``make demo``)."""

from __future__ import annotations


def register(sub) -> None:
    from .common import add_quiet_option

    p = sub.add_parser(
        "demo", help="the whole story on the embedded data: fit, diagnose, refine, gap thickness, force (writes out/)",
        description="The whole story on the embedded SYNTHETIC finger data (Sirin et al.'s setup): a naive fit, its diagnosis and refinement, "
        "the air-gap thickness with its posterior, and the electrostatic force; figures and a report in --out (default out/).",
    )
    p.add_argument("--out", default="out", help="output folder (default out/)")
    p.add_argument("--fast", action="store_true", help="short MCMC chains (used by the tests and CI)")
    add_quiet_option(p)  # (2026-12-03: every command takes --quiet, so a pipeline can pass it to each)
    p.set_defaults(run=run)


def run(args) -> int:
    from ..demo import run_demo
    from .common import check_output_folder

    check_output_folder(args.out)  # a file, a file on the way, a read-only folder: refused before anything is made
    run_demo(args.out, fast=args.fast, quiet=args.quiet)
    return 0
