"""``impedax refine DATA [--model MODEL]``: add the missing effects one by one until the fit is adequate."""

from __future__ import annotations

# what --model defaults to (refine's `REFINE_START`; written out here so that the CLI's help needs
# no import of the fitting package, tests/test_cli_basic.py checks the two agree)
MODEL_DEFAULT = "R0 + R1 || C1"

def register(sub) -> None:
    from .diagnose import add_spectrum_command
    from .fit import add_max_steps_option

    p = add_spectrum_command(
        sub,
        "refine",
        help="diagnose, add the best missing effect, refit; repeat until adequate",
        description="Repeat diagnose -> apply the best significant effect -> refit until the verdict is adequate or --max-effects effects were added; "
        "prints the table of steps (the error falls step by step). The final model is refitted from scratch, as impedax fit does, or, where that ends "
        "worse than the loop's fit, from the loop's values, and the report then ends with the impedax fit --init command that reproduces it. See docs/diagnosis.md.",
        plot_help="save the data with the first and the last model (Nyquist), rms_rel per step and the residuals of every step",
        out_help="the refinement (.csv: the final fit's parameters, each row with final_model and verdict)",
        run=run,
        model_default=MODEL_DEFAULT,
    )
    p.add_argument("--max-effects", type=int, default=4, metavar="N", help="most effects to add (default 4)")
    add_max_steps_option(p, 100, "the candidate fits of every step (the baseline fit keeps its own)")


def run(args) -> int:
    from ..errors import ParameterError
    from .common import note_skipped_rows, print_result, to_terminal
    from .diagnose import fitting_function, run_spectrum_command

    if args.max_effects < 0:
        raise ParameterError(f"--max-effects must be 0 or more, got {args.max_effects}")
    outputs, data, result, read, source, record = run_spectrum_command(args, "refine", fitting_function("refine"), max_effects=args.max_effects)
    if not outputs.uses_stdout:
        with to_terminal(not args.json):
            print_result(read, args.json, source, record, command="refine")
            line = reproduce_line(result, args, data)
            if line and not args.json:
                print(line)
        if not args.json:
            note_skipped_rows(data, "refine", args.data)
    return 0


def reproduce_line(refinement, args=None, data=None) -> str | None:
    """The ``impedax fit`` command that reproduces the final fit (on the run's file and points:
    `fit_command`, with the --fmin/--fmax/--exclude that leave out the masked points): from its
    values when a fit of the final model from scratch ends at another optimum
    (``Refinement.final_from_values``; a note of another path said so of its own model, and had
    printed this line), else from scratch when points were masked (a fit of the file's every
    point differs) or when it holds fixed values or bounds of the user's (--fix, --bound, which the
    command carries; from values, each start strictly inside its bounds); else None
    (``impedax fit`` of the final model reproduces it). ``data``: the
    spectrum refined, so that a --select list or range that picked it is given as its label."""
    from ..data import counted
    from ..fitting.diagnosis.diagnosis import bound_words, restart_words
    from .common import fit_command

    final = refinement.final
    command = fit_command(args, kept=final.frequency, masked=refinement.masked_points, data=data)
    masked = len(refinement.masked_points)
    without = f"; without the {counted(masked, 'masked point')}" if masked else ""
    bounded = bound_words(final)
    if refinement.final_from_values:
        starts = restart_words(final) if bounded else " ".join(f"--{'fix' if final.fixed[k] else 'init'} {k}={v:.6g}" for k, v in final.values.items())
        return f"to reproduce the final fit from its values (a fit from scratch ends at another optimum; the notes give both{without}): {command} --model '{final.model}' {starts}"
    fixed = " ".join(f"--fix {k}={v:.6g}" for k, v in final.values.items() if final.fixed[k])
    if masked or fixed or bounded:
        how = ([f"without the {counted(masked, 'masked point')}"] if masked else []) + (["its fixed values held"] if fixed else []) + (["within your bounds"] if bounded else []) + [f"rms_rel {final.rms_rel * 100:.3g} %"]
        return f"to reproduce the final fit ({', '.join(how)}): {command} --model '{final.model}'" + (f" {fixed}" if fixed else "") + bounded
    return None
