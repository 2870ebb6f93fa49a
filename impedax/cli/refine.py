"""``impedax refine DATA --model MODEL``: add the missing effects one by one until the fit is adequate."""

from __future__ import annotations

PROGRESS_AFTER_S = 2.0
"""Progress lines go to stderr once a run has taken this long."""


def register(sub) -> None:
    from .diagnose import add_spectrum_command
    from .fit import add_max_steps_option

    p = add_spectrum_command(
        sub,
        "refine",
        help="diagnose, add the best missing effect, refit; repeat until adequate",
        description="Repeat diagnose -> apply the best significant effect -> refit until the verdict is adequate or --max-effects effects were added; "
        "prints the table of steps (the error falls step by step). The final model is refitted from scratch, as impedax fit does. See docs/diagnosis.md.",
        plot_help="save rms_rel per step and the residuals of every step",
        out_help="the refinement (.csv: the final fit's parameters)",
        run=run,
    )
    p.add_argument("--max-effects", type=int, default=4, metavar="N", help="most effects to add (default 4)")
    add_max_steps_option(p, 100, "the candidate fits of every step (the baseline fit keeps its own)")


def progress_printer(after_s: float = PROGRESS_AFTER_S):
    """A progress callback that prints its lines to stderr once ``after_s`` seconds have passed."""
    import sys
    import time

    start = time.monotonic()

    def say(text: str) -> None:
        elapsed = time.monotonic() - start
        if elapsed > after_s:
            print(f"[{elapsed:5.1f} s] {text}", file=sys.stderr, flush=True)

    return say


def run(args) -> int:
    from ..errors import ParameterError
    from ..fitting import refine
    from .common import figure_writer, load_selected, plan_outputs, print_result, result_writer
    from .diagnose import effects_option
    from .fit import check_max_steps

    outputs = plan_outputs([("--out", args.out, "result"), ("--plot", args.plot, "figure")], inputs=[args.data], stdout="--json" if args.json else None)
    if args.max_effects < 0:
        raise ParameterError(f"--max-effects must be 0 or more, got {args.max_effects}")
    solver_steps = check_max_steps(args.max_steps)
    effects = effects_option(args.effects)
    data = load_selected(args.data, args.select, single="impedax refine")
    result = refine(
        data, args.model, max_effects=args.max_effects, solver_steps=solver_steps, effects=effects, weighting=args.weighting, noise=args.noise,
        fmin=args.fmin, fmax=args.fmax, progress=progress_printer(),
    )
    outputs.save({"--out": result_writer(result), "--plot": figure_writer(result.plot)})
    if not outputs.uses_stdout:
        print_result(result, args.json)
    return 0
