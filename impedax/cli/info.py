"""``impedax info MODEL``: the parameters of a circuit with units, defaults and bounds."""

from __future__ import annotations


def register(sub) -> None:
    from .common import add_quiet_option

    from .common import add_model_argument

    p = sub.add_parser("info", help="list a model's parameters", description="List the parameters of MODEL with units, defaults and bounds.")
    add_model_argument(p, positional=True)
    p.add_argument("--json", action="store_true", help="machine-readable output")
    add_quiet_option(p)  # (every command takes --quiet, so a pipeline can pass it to each)
    p.set_defaults(run=run)


#: Where a paper model's values (`common.PAPER_MODELS`, Meyer's) come from: the thesis's eq 3.13,
#: but for the cpe variant's CPE_sc (impedax's choice, docs/physics.md and docs/models.md).
PAPER_VALUE_SOURCE = "Meyer 2012 thesis, eq 3.13"
PAPER_VALUE_SOURCES = {
    "CPE_sc.Q": "|Z| of eq 3.13's C_sc = 2.2 nF at 1 kHz for this alpha",
    "CPE_sc.alpha": "impedax's choice for the fractional Fig 5.3 variant",
}
PAPER_DEFAULTS_LINE = "the values of Meyer's 2012 thesis: simulate's defaults, the starting values of the commands that fit"


def run(args) -> int:
    from .. import parse
    from ..data import column_width, unit_text
    from .common import emit_json

    registry = args.registry  # (the default one with the --plugin files' elements)
    circuit = parse(args.model, registry)
    paper = getattr(args, "paper_model", None)  # (a paper model's name: its values are simulate's defaults and fit's starts)
    paper_values = getattr(args, "paper_values", None) or {}
    rows = []
    for e in circuit.elements():
        spec = registry[e.symbol]
        for p in spec.parameters:
            rows.append({
                "name": p.full_name(e.name), "element": e.name, "element_kind": spec.name,
                "unit": p.unit, "default": p.default, "lower": p.lower, "upper": p.upper,
                "upper_inclusive": p.upper_inclusive, "description": p.description,
            })
            if paper:
                name = p.full_name(e.name)
                rows[-1].update(paper_value=float(paper_values[name]), paper_value_source=PAPER_VALUE_SOURCES.get(name, PAPER_VALUE_SOURCE))
    # each kind of element in the circuit, once, in order, with its formula (a
    # user's element and a built-in Gerischer or Havriliak–Negami too, not by name only)
    kinds = list({registry[e.symbol].symbol: registry[e.symbol] for e in circuit.elements()}.values())  # (an alias, Q1 beside CPE2, is its element's kind)
    elements = [{"symbol": spec.symbol, "element_kind": spec.name, "equation": spec.equation} for spec in kinds]
    if args.json:
        emit_json({"model": str(circuit), "parameters": rows, "elements": elements, **({"paper_model": paper} if paper else {})})
        return 0
    print(f"model: {paper} = {circuit}" if paper else f"model: {circuit}")
    if paper:
        import textwrap

        print(textwrap.fill(f"default: {PAPER_DEFAULTS_LINE} (source in [ ]; the elements' own defaults are --json's \"default\")", 80, subsequent_indent="  ", break_on_hyphens=False))
    # (each column as wide as its widest entry: fixed widths of 14 and 15 put a row of R and C
    # past 80 columns, "R_sc  Ω" then 17 blanks)
    specs = [p for e in circuit.elements() for p in registry[e.symbol].parameters]
    defaults = [f"{r['paper_value'] if paper else r['default']:.4g}" for r in rows]
    width = column_width((r["name"] for r in rows), "parameter")
    unit_width = column_width((unit_text(r["unit"]) for r in rows), "unit")
    default_width = column_width(defaults, "default")
    bounds_width = column_width((p.bounds_text() for p in specs), "bounds")
    print(f"{'parameter':<{width}}  {'unit':<{unit_width}}  {'default':>{default_width}}  {'bounds':<{bounds_width}}  description")
    for r, p, default in zip(rows, specs, defaults):
        described = f"{r['element_kind']}: {r['description']}" if r["description"].strip() else r["element_kind"]  # (a user's element may declare none)
        source = f" [{r['paper_value_source'].removeprefix('Meyer 2012 thesis, ')}]" if paper else ""  # (the "default:" line names the thesis)
        print(f"{r['name']:<{width}}  {unit_text(r['unit']):<{unit_width}}  {default:>{default_width}}  {p.bounds_text():<{bounds_width}}  {described}{source}")
    symbol_width = column_width((k["symbol"] for k in elements), "element")
    kind_width = column_width((k["element_kind"] for k in elements), "kind")
    print(f"{'element':<{symbol_width}}  {'kind':<{kind_width}}  equation (ω = 2πf)")
    for k in elements:
        print(f"{k['symbol']:<{symbol_width}}  {k['element_kind']:<{kind_width}}  {k['equation']}")
    return 0
