"""``impedax draw MODEL -o FILE.png|.svg|.pdf [--param NAME=VALUE]...``: the circuit's schematic."""

from __future__ import annotations


def register(sub) -> None:
    from .common import add_quiet_option

    from .common import add_model_argument

    p = sub.add_parser("draw", help="draw a model's circuit diagram", description="Draw the schematic of MODEL (series in a row, parallel branches stacked) with element names and, optionally, values. Needs schemdraw (pip install impedax[draw]).")
    add_model_argument(p, positional=True)
    p.add_argument("-o", "--out", required=True, metavar="FILE.png|.svg|.pdf", help="output file (.png, .svg or .pdf; a name without an extension is a PNG under that name); written atomically")
    p.add_argument("--param", action="append", metavar="NAME=VALUE", help="value to print under its element, e.g. a fitted value; several after one --param (--param R0=10 C1=1u) or --param repeated")
    add_quiet_option(p)  # (2026-12-03: every command takes --quiet, so a pipeline can pass it to each)
    p.set_defaults(run=run)


def run(args) -> int:
    from ..diagram import save_circuit_diagram
    from .common import model_and_values, plan_outputs

    circuit, _, given = model_and_values(args.model, args.param, "--param", args.registry)
    outputs = plan_outputs([("--out", args.out, "diagram")])
    outputs.save({"--out": lambda path: save_circuit_diagram(circuit, path, values=given, registry=args.registry)})  # (says "wrote FILE" on stderr)
    return 0
