"""``impedax diagnose DATA --model MODEL``: where the model fails and which effect is missing."""

from __future__ import annotations


def register(sub) -> None:
    from .common import add_model_argument
    from .fit import add_fit_options, add_max_steps_option

    p = sub.add_parser(
        "diagnose",
        help="where a model fails and which physical effect is missing",
        description="Fit MODEL to DATA, test the data (Kramers-Kronig), find the bands where the residuals are structured, "
        "try every effect of the catalog at every sensible place (one batched fit) and rank them by AIC. See docs/diagnosis.md.",
    )
    p.add_argument("data", metavar="DATA", help="spectrum file with one spectrum")
    add_model_argument(p)
    add_fit_options(p)
    add_max_steps_option(p, 100, "the candidate fits (the baseline fit keeps its own)")
    p.add_argument("--effects", metavar="ID,ID", help="only these effects (comma-separated ids; default: all)")
    p.add_argument("--noise", type=float, metavar="REL", help="relative noise level per component (default: from sigma or the KK residuals)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE.png", help="save data vs model with the failing bands shaded and the best suggestion")
    p.set_defaults(run=run)


def effects_option(text):
    from ..fitting import DEFAULT_EFFECTS

    if not text:
        return DEFAULT_EFFECTS
    return DEFAULT_EFFECTS.select([t.strip() for t in text.split(",") if t.strip()])


def run(args) -> int:
    from ..fitting import diagnose
    from ..fitting.problem import open_spectrum
    from ..io.atomic import check_writable
    from .common import emit_json
    from .fit import check_max_steps

    if args.plot:
        check_writable(args.plot)
    effects = effects_option(args.effects)
    data = open_spectrum(args.data, fmin=args.fmin, fmax=args.fmax, single="diagnose").data
    result = diagnose(data, args.model, effects=effects, noise=args.noise, weighting=args.weighting, max_steps=check_max_steps(args.max_steps))
    if args.plot:
        from ..plotting import save_figure

        save_figure(result.plot(), args.plot)
    if args.json:
        emit_json(result.summary())
    else:
        print(result.report())
    return 0
