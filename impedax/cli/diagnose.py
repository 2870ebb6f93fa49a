"""``impedax diagnose DATA --model MODEL``: where the model fails and which effect is missing."""

from __future__ import annotations

import sys


def register(sub) -> None:
    from .fit import add_max_steps_option

    p = add_spectrum_command(
        sub,
        "diagnose",
        help="where a model fails and which physical effect is missing",
        description="Fit MODEL to DATA, test the data (Kramers-Kronig), find the bands where the residuals are structured, "
        "try every effect of the catalog at every sensible place (one batched fit) and rank them by AIC. See docs/diagnosis.md.",
        plot_help="save data vs model with the failing bands shaded and the best suggestion",
        out_help="the diagnosis (.csv: the baseline's parameters, then the candidates with ΔAIC)",
        run=run,
    )
    add_max_steps_option(p, 100, "the candidate fits (the baseline fit keeps its own)")


def add_spectrum_command(sub, name: str, *, help: str, description: str, plot_help: str, out_help: str, run, model_default: str | None = None):
    """A diagnosis command on one spectrum with a model (diagnose, refine): DATA, --model
    (required unless ``model_default``), --fix, --bound, the fit options, --effects, --noise, --json, --plot,
    --out; runs ``run(args)``."""
    from .common import add_model_argument, add_output_options, add_select_option, data_help, result_out_help
    from .fit import add_bound_option, add_fit_options

    p = sub.add_parser(name, help=help, description=description)
    p.add_argument("data", metavar="DATA", help=data_help("spectrum file with one spectrum, or one picked with --select"))
    add_select_option(p, several=False)
    add_model_argument(p, default=model_default)
    p.add_argument("--fix", action="append", metavar="NAME=VALUE", help="hold a parameter of MODEL fixed (several after one --fix, C_i=1.7n R_e=20, or --fix repeated; SI prefixes), in the baseline fit "
                   "and in every candidate that keeps the parameter; the commands printed carry it")
    add_bound_option(p, " in the baseline fit and in every candidate that keeps the parameter", with_init=False)
    add_fit_options(p)
    p.add_argument("--effects", metavar="ID,ID", help="only these effects (comma-separated ids; default: all)")
    p.add_argument("--noise", metavar="REL", help="relative noise level per component: a fraction of |Z| (0.05) or a percentage (5%%); default: from sigma or the KK residuals, which need 10 frequencies: on fewer give it")
    p.add_argument("--keep-all-points", action="store_true", help="leave no point out as not Kramers-Kronig consistent: every fit takes every point of the band "
                   "(but those with Re Z < 0); the data's KK problem is still reported, apart from the verdict (Python: mask=False)")
    add_output_options(p, json="machine-readable output", plot=plot_help, out=result_out_help(out_help))
    p.set_defaults(run=run)
    return p


def effects_option(text):
    from ..errors import ParameterError
    from ..fitting import DEFAULT_EFFECTS

    if text is None:
        return DEFAULT_EFFECTS
    known = ', '.join(e.id for e in DEFAULT_EFFECTS.effects)
    items = [t.strip() for t in text.split(",")]
    ids = [t for t in items if t]
    if not ids:
        raise ParameterError(f"--effects {text!r} names no effect: leave it out for all of them, or give ids from {known}")
    if len(ids) < len(items):  # ("diffusion,,constant_phase": a dropped id, as --select refuses its empty item, not taken silently)
        empty = items.index("")
        raise ParameterError(f"--effects {text!r}: item {empty + 1} of {len(items)} is empty; give effect ids separated by single commas, from {known}")
    return DEFAULT_EFFECTS.select(ids)


def fixed_option(args) -> dict[str, float]:
    """``--fix NAME=VALUE`` as ``fixed=`` (`common.parse_assignments`), its names checked
    against ``--model``'s parameters before the data are read (`common.check_parameter_names`:
    --fix C_I=1n → did you mean C_i?) and each value against its element's bounds
    (`common.check_bounds`), as impedax fit checks them."""
    from .. import parse
    from .common import check_bounds, check_parameter_names, parse_assignments

    fixed = parse_assignments(args.fix, "--fix")
    if fixed:
        circuit = parse(args.model, args.registry)
        check_parameter_names(fixed, circuit.parameter_names(args.registry), "--fix", args.model, args.registry, paper=getattr(args, "paper_model", None))
        check_bounds(fixed, circuit.parameter_specs(args.registry), "--fix")
    return fixed


def bounds_option(args, fixed: dict[str, float]) -> dict[str, tuple[float, float]]:
    """``--bound NAME=LO:HI`` as ``bounds=`` (`common.parse_bounds`), checked before the data are
    read as impedax fit checks it: names against ``--model``'s parameters
    (`common.check_parameter_names`), then the ends (`common.checked_bound_options`: LO ≥ HI,
    outside the element's range, narrowing nothing, a parameter also in ``fixed``, --fix)."""
    from .. import parse
    from .common import check_parameter_names, checked_bound_options, parse_bounds

    given = parse_bounds(args.bound)
    if not given:
        return {}
    circuit = parse(args.model, args.registry)
    check_parameter_names(given, circuit.parameter_names(args.registry), "--bound", args.model, args.registry, paper=getattr(args, "paper_model", None))
    return checked_bound_options(given, circuit.parameter_specs(args.registry), fixed=fixed)


def fitting_function(name: str):
    """``impedax.fitting``'s ``name`` (diagnose, refine), imported when it is called: the import
    (JAX) takes seconds on a loaded machine, which `run_spectrum_command` says it begins."""
    def analyse(*args, **kwargs):
        from .. import fitting

        return getattr(fitting, name)(*args, **kwargs)

    return analyse


def run(args) -> int:
    from .common import fit_command, note_skipped_rows, print_result

    outputs, data, result, read, source, record = run_spectrum_command(args, "diagnose", fitting_function("diagnose"))
    if not outputs.uses_stdout:
        with to_terminal(not args.json):
            print_result(read, args.json, source, record, command="diagnose", fit_command=fit_command(args, kept=result.baseline.frequency, masked=result.masked_points, data=data))
        if not args.json:
            note_skipped_rows(data, "diagnose", args.data)
    return 0


from ..progress import terminal_text as terminal_text  # (the reports' and the progress lines' wrapping: `to_terminal`)
from .common import to_terminal as to_terminal  # (where it lives: every command's report is wrapped so)


def run_spectrum_command(args, command: str, analyse, **settings):
    """What ``impedax diagnose`` and ``impedax refine`` share: the outputs planned and the options
    checked before the data are read (--max-steps, --noise, --effects, --fix, --bound), the one
    spectrum read (--select, --exclude), ``analyse(data, model, ..., **settings)`` run with a
    progress printer, and its result and figure written (--out, --plot). Returns the planned
    outputs, the data, the result, the result with the JSON's extra keys, the source and the
    provenance record."""
    from .common import command_provenance, data_source, exclude_points, figure_options, figure_writer, load_selected, plan_outputs, progress_printer, relative_noise, result_writer, shown_path, skipped_rows, WithSummaryKeys
    from .fit import check_max_steps, note_solver_step_limit

    outputs = plan_outputs([("--out", args.out, "result"), ("--plot", args.plot, "figure")], inputs=[args.data], stdout="--json" if args.json else None)
    max_steps = check_max_steps(args.max_steps)
    noise = relative_noise(args.noise)
    # the first line, before the fitting code is imported (the solver's step limit and --effects'
    # catalog need it) and the baseline fit compiles: a diagnose run on a loaded 2-core machine
    # said nothing for 17–21 s
    paper = getattr(args, "paper_model", None)
    progress = progress_printer(quiet=args.quiet)
    try:
        progress(f"{'diagnosing' if command == 'diagnose' else 'refining'} {args.model} on {shown_path(args.data)}: loading the fitting code, then the baseline fit "
                 "(a circuit's first fit compiles its solvers)")
        note_solver_step_limit(max_steps, command)
        effects = effects_option(args.effects)
        fixed = fixed_option(args)
        bounds = bounds_option(args, fixed)
        data = exclude_points(load_selected(args.data, args.select, single=f"impedax {command}", readers=args.readers), args.exclude)
        if paper:  # (the name read as its circuit; the baseline fit guesses its start as for any circuit: the decisions are the circuit's. Said after the checks and the data: a refusal is the only line)
            from .common import paper_start_note

            print(paper_start_note(command, paper, args.model, args.paper_values, starts=False), file=sys.stderr)
        result = analyse(data, args.model, effects=effects, noise=noise, weighting=args.weighting, fmin=args.fmin, fmax=args.fmax, max_steps=max_steps, progress=progress,
                         fixed=fixed or None, bounds=bounds or None, registry=args.registry, mask=not args.keep_all_points, **settings)
        source = data_source(data)
        record = command_provenance(args, source=source, data_files=[args.data])
        read = WithSummaryKeys(result, {"skipped_rows": skipped_rows(data), **({"paper_model": paper} if paper else {})})  # (the JSON's, as fit's and inspect --json's)
        if args.plot:  # (refine's figure, a residual panel per step with each model's curve, took 39 s after its last line on a 2-core machine at load 8, REAL CH Instruments)
            progress(f"drawing {args.plot}")
        outputs.save({"--out": result_writer(read, source, record), "--plot": figure_writer(result.plot, source, **figure_options(args))})
    finally:
        progress.close()
    return outputs, data, result, read, source, record
