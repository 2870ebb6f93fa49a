"""``impedax refine DATA --model MODEL``: add the missing effects one by one until the fit is adequate."""

from __future__ import annotations


def register(sub) -> None:
    from .diagnose import add_spectrum_command

    p = add_spectrum_command(
        sub,
        "refine",
        help="diagnose, add the best missing effect, refit; repeat until adequate",
        description="Repeat diagnose -> apply the best significant effect -> refit until the verdict is adequate or --max-steps effects were added; "
        "prints the table of steps (the error falls step by step). See docs/diagnosis.md.",
        plot_help="save rms_rel per step and the residuals of every step",
        out_help="the refinement (.csv: the final fit's parameters)",
        run=run,
    )
    p.add_argument("--max-steps", type=int, default=4, metavar="N", help="most effects to add (default 4)")


def run(args) -> int:
    from ..errors import ParameterError
    from ..fitting import refine
    from .common import figure_writer, plan_outputs, print_result, result_writer
    from .diagnose import effects_option

    outputs = plan_outputs([("--out", args.out, "result"), ("--plot", args.plot, "figure")], inputs=[args.data], stdout="--json" if args.json else None)
    if args.max_steps < 0:
        raise ParameterError(f"--max-steps must be 0 or more, got {args.max_steps}")
    effects = effects_option(args.effects)
    result = refine(args.data, args.model, max_steps=args.max_steps, effects=effects, weighting=args.weighting, noise=args.noise, fmin=args.fmin, fmax=args.fmax)
    outputs.save({"--out": result_writer(result), "--plot": figure_writer(result.plot)})
    if not outputs.uses_stdout:
        print_result(result, args.json)
    return 0
