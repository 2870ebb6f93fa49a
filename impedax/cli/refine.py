"""``impedax refine DATA --model MODEL``: add the missing effects one by one until the fit is adequate."""

from __future__ import annotations


def register(sub) -> None:
    from .common import add_model_argument

    p = sub.add_parser(
        "refine",
        help="diagnose, add the best missing effect, refit; repeat until adequate",
        description="Repeat diagnose -> apply the best significant effect -> refit until the verdict is adequate or --max-steps effects were added; "
        "prints the table of steps (the error falls step by step). See docs/diagnosis.md.",
    )
    p.add_argument("data", metavar="DATA", help="spectrum file with one spectrum")
    add_model_argument(p)
    p.add_argument("--max-steps", type=int, default=4, metavar="N", help="most effects to add (default 4)")
    from .fit import add_weighting_option

    add_weighting_option(p, "fit weighting (as impedax fit; default modulus)")
    p.add_argument("--effects", metavar="ID,ID", help="only these effects (comma-separated ids; default: all)")
    p.add_argument("--noise", type=float, metavar="REL", help="relative noise level per component (default: from sigma or the KK residuals)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE.png", help="save rms_rel per step and the residuals of every step")
    p.set_defaults(run=run)


def run(args) -> int:
    from .. import load
    from ..io.atomic import check_writable
    from ..errors import ParameterError
    from ..fitting import refine
    from .common import emit_json
    from .diagnose import effects_option

    if args.plot:
        check_writable(args.plot)
    if args.max_steps < 0:
        raise ParameterError(f"--max-steps must be 0 or more, got {args.max_steps}")
    effects = effects_option(args.effects)
    data = load(args.data)
    if any(d != "frequency" for d in data["Z"].dims):
        from ..errors import DataError

        raise DataError("the data hold several spectra (extra dimensions); refine one spectrum (average or select trials first)", path=args.data)
    result = refine(data, args.model, max_steps=args.max_steps, effects=effects, weighting=args.weighting, noise=args.noise)
    if args.plot:
        from ..plotting import save_figure

        save_figure(result.plot(), args.plot)
    if args.json:
        emit_json(result.summary())
    else:
        print(result.report())
    return 0
