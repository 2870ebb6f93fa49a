"""``impedax diagnose DATA --model MODEL``: where the model fails and which effect is missing."""

from __future__ import annotations


def register(sub) -> None:
    p = add_spectrum_command(
        sub,
        "diagnose",
        help="where a model fails and which physical effect is missing",
        description="Fit MODEL to DATA, test the data (Kramers-Kronig), find the bands where the residuals are structured, "
        "try every effect of the catalog at every sensible place (one batched fit) and rank them by AIC. See docs/diagnosis.md.",
    )
    add_diagnosis_options(p, plot_help="save data vs model with the failing bands shaded and the best suggestion")
    p.set_defaults(run=run)


def add_spectrum_command(sub, name: str, *, help: str, description: str):
    """A command on one spectrum with a model (diagnose, refine): DATA, --model, the fit options."""
    from .common import add_model_argument
    from .fit import add_fit_options

    p = sub.add_parser(name, help=help, description=description)
    p.add_argument("data", metavar="DATA", help="spectrum file with one spectrum")
    add_model_argument(p)
    add_fit_options(p)
    return p


def add_diagnosis_options(p, *, plot_help: str) -> None:
    """Options shared by diagnose and refine: --effects, --noise, --json, --plot."""
    p.add_argument("--effects", metavar="ID,ID", help="only these effects (comma-separated ids; default: all)")
    p.add_argument("--noise", type=float, metavar="REL", help="relative noise level per component (default: from sigma or the KK residuals)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE.png", help=plot_help)


def effects_option(text):
    from ..fitting import DEFAULT_EFFECTS

    if not text:
        return DEFAULT_EFFECTS
    return DEFAULT_EFFECTS.select([t.strip() for t in text.split(",") if t.strip()])


def emit_result(result, args) -> None:
    """Save ``result.plot()`` to --plot, then print ``result.summary()`` as JSON (--json) or
    ``result.report()``."""
    from .common import emit_json

    if args.plot:
        from ..plotting import save_figure

        save_figure(result.plot(), args.plot)
    if args.json:
        emit_json(result.summary())
    else:
        print(result.report())


def run(args) -> int:
    from ..fitting import diagnose
    from ..io.atomic import check_writable

    if args.plot:
        check_writable(args.plot)
    effects = effects_option(args.effects)
    result = diagnose(args.data, args.model, effects=effects, noise=args.noise, weighting=args.weighting, fmin=args.fmin, fmax=args.fmax)
    emit_result(result, args)
    return 0
