"""``impedax fit DATA --model MODEL``: least-squares fit with uncertainties."""

from __future__ import annotations

import sys


# the names of `impedax.fitting.WEIGHTINGS`, here so that building the parser does not import
# the fitting code (and JAX): `impedax --help` starts at once (tests/test_cli_basic.py checks)
WEIGHTING_NAMES = ("unit", "modulus", "proportional", "sigma")


def add_weighting_option(p, help_text: str) -> None:
    p.add_argument("--weighting", default="modulus", choices=WEIGHTING_NAMES, help=help_text)


def add_fit_options(p) -> None:
    """Options shared by fit-like commands (fit, compare, diagnose, refine), ``--quiet``
    (`common.add_quiet_option`) among them: each prints progress lines."""
    from .common import add_quiet_option, number_option

    add_weighting_option(p, "residual weighting (default modulus: both parts divided by |Z|, relative errors, the weighting of impedax sample's --noise proportional; "
                            "proportional: Re divided by |Re Z| and Im by |Im Z|; see impedax.fitting.WEIGHTINGS)")
    p.add_argument("--fmin", type=number_option, help="ignore data below this frequency [Hz]")
    p.add_argument("--fmax", type=number_option, help="ignore data above this frequency [Hz]")
    add_exclude_option(p)
    add_quiet_option(p)


def add_exclude_option(p, *, of_every_file: bool = False) -> None:
    """``--exclude F,F``, as `impedax.cli.common.exclude_points` reads it (fit, compare,
    diagnose, refine, kk, drt, sample: the points refine and diagnose masked can be left out of each;
    gap and remaining, ``of_every_file``: of each input file, `gap.files_without_points`);
    repeated, the lists join (not the last one alone)."""
    import argparse

    class Joined(argparse.Action):
        def __call__(self, parser, namespace, values, option_string=None):
            before = getattr(namespace, self.dest, None)
            setattr(namespace, self.dest, f"{before},{values}" if before else values)

    p.add_argument("--exclude", metavar="F,F", action=Joined, help="leave out these measured frequencies [Hz], comma-separated (5.34,56.2,1.12M), or --exclude repeated: each names the nearest "
                   "measured frequency within 0.5 %%, so values copied from a report match (the masked points diagnose and refine print)"
                   + ("; left out of every input file whose band holds them, before the subtraction and every fit (a frequency beyond a file's band is left to the others)" if of_every_file else ""))


def add_max_steps_option(p, default: int, what: str) -> None:
    """``--max-steps N``: the Levenberg–Marquardt step limit of ``what``."""
    p.add_argument("--max-steps", type=int, default=default, metavar="N", help=f"Levenberg–Marquardt step limit of {what} (default {default})")


def check_max_steps(n: int) -> int:
    from ..errors import ParameterError

    if n < 1:
        raise ParameterError(f"--max-steps must be at least 1, got {n}")
    return n


def note_solver_step_limit(n: int, command: str) -> None:
    """One stderr note when ``--max-steps N`` of ``diagnose`` or ``refine`` is below
    `SCREEN_STEPS` (40), the Levenberg–Marquardt steps every start of a fit is screened for:
    a solver limit that small is no sensible one, and under ``refine`` it most likely meant its
    number of effects (``--max-effects``; ``--max-steps`` was that number before issue 14, and
    ``impedax.refine(max_steps=3)`` is refused for it). The value is still used as the step limit."""
    import sys

    from ..fitting.least_squares.solvers import SCREEN_STEPS

    if n < SCREEN_STEPS:
        # (diagnose adds no effect: its note says what the limit does, not refine's option)
        meant = "the number of effects refine may add is --max-effects" if command == "refine" else "so few steps stop most fits before they converge"
        print(
            f"impedax {command}: note: --max-steps {n} is the solver's step limit per fit (below the {SCREEN_STEPS} steps each start is screened for); {meant}",
            file=sys.stderr,
        )


def add_bound_option(p, where: str = "", *, with_init: bool = True) -> None:
    """``--bound NAME=LO:HI ...`` (several after one, or repeated), read by `common.parse_bounds` and
    `common.checked_bound_options`: the ``bounds=`` of `impedax.fit`, `impedax.sample`, `diagnose`
    and `refine` (``with_init=False`` for the commands without ``--init``)."""
    init_rule = ", and an --init value must lie inside" if with_init else ""
    p.add_argument("--bound", action="append", metavar="NAME=LO:HI", help=f"fit a parameter within LO..HI{where} (several after one --bound, R1=10:1k R0=:10, or --bound repeated; SI prefixes; "
                   f"an empty side keeps the element's own bound: R0=:10, R0=1m:); not with --fix of the same NAME{init_rule}")


def add_shared_options(p) -> None:
    """``--shared NAME[,NAME]`` and ``--over DIM[,DIM]``: a global fit with parameters shared
    across the spectra along DIM (docs/fitting.md, "Shared parameters")."""
    p.add_argument("--shared", action="append", metavar="NAME[,NAME]", help="parameters with one value across the spectra along --over (a global fit; repeatable)")
    p.add_argument("--over", metavar="DIM[,DIM]", help="the data dimension(s) the --shared parameters are shared over (default: the data's only extra dimension)")


def shared_arguments(args) -> dict:
    """The ``shared``/``over`` keywords of `impedax.fit` from ``--shared``/``--over`` (empty when
    neither was given)."""
    from ..errors import ParameterError
    from .common import comma_names

    if args.shared is None and args.over is None:
        return {}
    if args.shared is None:
        raise ParameterError("--over needs --shared NAME[,NAME]: the parameters to share")
    names = comma_names(args.shared)
    if not names:
        raise ParameterError("--shared: no parameter names given")
    over = None if args.over is None else [d.strip() for d in args.over.split(",") if d.strip()]
    return {"shared": names, "over": over}


def register(sub) -> None:
    from .common import add_figure_flag, add_model_argument, add_output_options, add_select_option, data_help, result_out_help

    p = sub.add_parser("fit", help="least-squares fit of a circuit to a spectrum", description="Fit MODEL to the spectrum in DATA (CSV, netCDF or an instrument file). Data with extra dimensions (trials, ...) are fitted together.")
    p.add_argument("data", metavar="DATA", help=data_help("spectrum file"))
    add_select_option(p)
    add_model_argument(p)
    p.add_argument("--fix", action="append", metavar="NAME=VALUE", help="hold a parameter fixed; several after one --fix (--fix R1=1M R0=20) or --fix repeated")
    p.add_argument("--init", action="append", metavar="NAME=VALUE", help="starting value; several after one --init (--init R1=43k C2=5u) or --init repeated; others are guessed from the data")
    add_bound_option(p)
    add_shared_options(p)
    add_fit_options(p)
    add_max_steps_option(p, 400, "each fit")
    add_output_options(p, plot="save data vs model with residuals", out=result_out_help("the result (.nc: parameters, covariance, spectra)") + "; .tex a LaTeX table of value ± standard error (several spectra: a row each)", out_metavar="FILE.csv|.json|.nc|.tex")
    p.add_argument("--plot-params", nargs="+", metavar="NAME", help="the parameters --plot draws for several spectra, in that order (default: every free one)")
    p.add_argument("--residual-map", metavar="FIG.png", help="for several spectra: save every fit's residuals (real, imaginary; relative to |Z|, or in units of σ under --weighting sigma) as maps over the spectra and frequency, --exclude's frequencies as hatched rows, "
                   "where a missing effect shows as one pattern at the same frequencies in spectrum after spectrum (docs/fitting.md)")
    add_figure_flag(p, "--residual-map")
    p.add_argument("--plot-x", metavar="DIM", help="for several spectra: --plot draws each parameter against DIM's numeric coordinate (e.g. voltage), with error bars, one series per label of the other dimensions (default: the spectra side by side)")
    p.set_defaults(run=run)


def run(args) -> int:
    from pathlib import Path

    from .. import BatchFitResult, FitResult, fit, parse
    from ..fitting.least_squares.result import misfit_hint
    from ..errors import ParameterError
    from .common import check_bounds, check_parameter_names, to_terminal, checked_bound_options, command_line_words, command_provenance, data_source, exclude_points, figure_options, figure_writer, latex_writer, load_selected, note_skipped_rows, note_unused_sigma, parse_assignments, parse_bounds, plan_outputs, print_result, progress_printer, result_writer, skipped_rows, WithSummaryKeys, LATEX_SUFFIX

    outputs = plan_outputs([("--out", args.out, "fit"), ("--plot", args.plot, "figure"), ("--residual-map", args.residual_map, "figure")], inputs=[args.data], stdout="--json" if args.json else None)
    latex = bool(args.out) and Path(args.out).suffix.lower() == LATEX_SUFFIX
    max_steps = check_max_steps(args.max_steps)
    sharing = shared_arguments(args)
    init, fixed = parse_assignments(args.init, "--init"), parse_assignments(args.fix, "--fix")
    # names checked before the data are read, with the command line's hint (`closest_name`:
    # --fix CPE1.a → CPE1.alpha; r1 → R1); bounds are the fit's to check
    circuit = parse(args.model, args.registry)
    names = circuit.parameter_names(args.registry)
    given_bounds = parse_bounds(args.bound)
    for flag, given in (("--init", init), ("--fix", fixed), ("--bound", given_bounds)):
        check_parameter_names(given, names, flag, args.model, args.registry, paper=getattr(args, "paper_model", None))
    check_bounds(fixed, circuit.parameter_specs(args.registry), "--fix")  # (before the data are read: nothing printed before the refusal)
    check_bounds({k: v for k, v in init.items() if k not in given_bounds}, circuit.parameter_specs(args.registry), "--init")
    bounds = checked_bound_options(given_bounds, circuit.parameter_specs(args.registry), init=init, fixed=fixed)
    paper = getattr(args, "paper_model", None)
    plot_params = args.plot_params
    if plot_params is not None:
        if not args.plot:
            raise ParameterError("--plot-params picks the parameters of the figure --plot FILE.png draws: give --plot too")
        check_parameter_names(plot_params, names, "--plot-params", args.model, args.registry, paper=paper)
    loaded = load_selected(args.data, args.select, readers=args.readers)
    data = exclude_points(loaded, args.exclude)
    # (the frequencies --exclude left out: --residual-map marks their rows, where its neighbours' cells had covered them)
    left_out = sorted(set(loaded["frequency"].values.tolist()) - set(data["frequency"].values.tolist()))
    progress = progress_printer(quiet=args.quiet)  # (a batch of 3 cycles took 15 s without a word, 28 s on a first run)
    n_spectra = int(data["Z"].size // max(data.sizes.get("frequency", 1), 1))
    if args.residual_map and n_spectra == 1:
        raise ParameterError(f"--residual-map maps the residuals of several spectra, and {args.data} holds one: --plot FIG.png draws its data against the model with the residuals")
    if latex and n_spectra == 1:  # (several: a row per spectrum, `BatchFitResult.to_latex`; a list or range that picks one, --select cycle=0:20 of cycles 0, 64, 129: that spectrum, fitted alone, as compare takes it; a batch of one has no LaTeX table)
        data = data.isel({d: 0 for d in data["Z"].dims if d != "frequency"})
    if plot_params is not None and n_spectra == 1:
        raise ParameterError(f"--plot-params picks the parameter panels of a figure of several spectra, and {args.data} holds one (its figure is data against model, no parameter panels): leave --plot-params out")
    if args.plot_x is not None:  # (checked before the fit, as every argument)
        check_plot_x(args.plot_x, data, args.data, given_plot=bool(args.plot))
    if paper:  # (a paper model's values start the fit, --init over them; said once, after every check: a refusal is the only line)
        from .common import paper_start, paper_start_note

        print(paper_start_note("fit", paper, args.model, args.paper_values, init, fixed=fixed, bounded=given_bounds), file=sys.stderr)
        init = paper_start(args.paper_values, init, held=[*fixed, *given_bounds])
    try:  # (fit says its stages: the first line, then a batch's start search, local fits, statistics)
        result = fit(args.model, data, init=init, fixed=fixed, bounds=bounds or None, weighting=args.weighting, fmin=args.fmin, fmax=args.fmax, max_steps=max_steps, progress=progress, registry=args.registry, **sharing)
    finally:
        progress.close()
    source = data_source(data)
    record = command_provenance(args, source=source, data_files=[args.data])
    # (hints: a single fit's misfit that looks small and is many times what the data allow, `misfit_hint`)
    hint = misfit_hint(result) if isinstance(result, FitResult) else None
    batch_hints = result.misfit_hints() if isinstance(result, BatchFitResult) else None
    read = WithSummaryKeys(result, {"skipped_rows": skipped_rows(data), **({"paper_model": paper} if paper else {}), **({"hints": [hint] if hint else []} if isinstance(result, FitResult) else {}),
                                    # (a batch's hint under a single fit's key too: the text of the report's "hint:" line)
                                    **({"misfit_hints": batch_hints, "hints": [batch_hints["note"]] if batch_hints else []} if isinstance(result, BatchFitResult) else {})})  # (the JSON's, as inspect --json's)
    outputs.save({"--out": latex_writer(result) if latex else result_writer(read, source, record), "--plot": figure_writer(result.plot if plot_params is None and args.plot_x is None else lambda: result.plot(params=plot_params, x=args.plot_x), source, **figure_options(args)),
                  "--residual-map": figure_writer(lambda: result.plot_residual_map(excluded=left_out or None), source, **figure_options(args))})
    if outputs.uses_stdout:  # (the report, which ends with the result's notes, is not printed: σ unused is said on stderr)
        note_unused_sigma(data, "fit", args.weighting == "sigma", "--weighting sigma")
    else:  # (the report and the JSON carry the result's notes: σ the weighting does not use, once)
        with to_terminal(not args.json, table_head="parameter "):  # (wrapped at words on a terminal, as diagnose's report; the table kept)
            # (a batch's report groups its warnings by kind, naming the spectra, and ends with the hints computed above, not again; a global fit's too)
            given_hints = {"misfit_hints": batch_hints} if isinstance(result, BatchFitResult) else {}
            print_result(read, args.json, source, record, command="fit", written=args.out, **given_hints)
            if not args.json:
                note_skipped_rows(data, "fit", args.data)
                if hint:
                    import shlex

                    from .common import fit_command

                    print(f"next: {fit_command(args, data=data, program='impedax diagnose')} --model {shlex.quote(args.model)} (where the model fails and what it misses; the hint above)")
                elif isinstance(result, FitResult) and result.misses_structure:  # (a warning says the model misses structure: REAL Gamry, R0 + R1 || C1 at 30.1 %)
                    import shlex

                    from .common import fit_command

                    print(f"next: {fit_command(args, data=data, program='impedax diagnose')} --model {shlex.quote(args.model)} (where the model fails and what it misses; the warning above)")
                if batch_hints is not None:  # (the report's hint names the worst spectrum; its diagnosis)
                    from .common import diagnose_command

                    across = "" if args.residual_map else "; --residual-map FIG.png on this command maps where it fails across all of them"
                    print(f"next: {diagnose_command(args, data, batch_hints['worst']['labels'], args.model)} (where the model fails on the worst of those spectra and what it misses{across})")
                elif isinstance(result, BatchFitResult) and (worst := _worst_missing_structure(result)) is not None:  # (REAL battery cycles at 29–40 %)
                    from .common import diagnose_command

                    across = "" if args.residual_map else "; --residual-map FIG.png on this command maps where it fails across all of them"
                    print(f"next: {diagnose_command(args, data, worst, args.model)} (where the model fails on the worst of the spectra whose warnings say it misses structure, and what it misses{across})")
    if isinstance(result, FitResult) and not result.converged:  # (the report's status line says it; stderr too, as with --json)
        print(f"impedax fit: warning: the fit did not converge: {command_line_words(result.message, 'fit')}", file=sys.stderr)
    return 0


def check_plot_x(dim: str, data, path: str, *, given_plot: bool) -> None:
    """``--plot-x DIM``'s checks before the fit: --plot is given, and DIM is a dimension of the
    spectra of ``data`` (read from ``path``) with a numeric coordinate (`BatchFitResult.plot`'s
    ``x``); `ParameterError` naming what to give otherwise."""
    from ..errors import ParameterError
    from ..plotting.fit import numeric_coordinate

    if not given_plot:
        raise ParameterError("--plot-x draws the parameters of the figure --plot FILE.png writes against a dimension: give --plot too")
    dims = [d for d in data["Z"].dims if d != "frequency"]
    if not dims or data["Z"].size == data.sizes["frequency"]:
        raise ParameterError(f"--plot-x {dim}: {path} holds one spectrum (its figure is data against model, no parameter panels): leave --plot-x out")
    if dim not in dims:
        raise ParameterError(f"--plot-x {dim}: not a dimension of the spectra of {path} ({', '.join(dims)})")
    if not numeric_coordinate(data, dim):
        raise ParameterError(f"--plot-x {dim}: {dim} has no numeric coordinate in {path} to draw against (its labels are not numbers): leave --plot-x out")


def _worst_missing_structure(batch) -> dict | None:
    """The labels of the spectrum with the largest rms_rel among those whose model misses
    structure the data hold (`BatchFitResult.misses_structure`), None when there is none."""
    import numpy as np

    flags = batch.misses_structure.transpose(*batch.dims).values.reshape(-1)
    if not flags.any():
        return None
    rms = batch.dataset["rms_rel"].transpose(*batch.dims).values.reshape(-1)
    return list(batch.spectrum_keys())[int(np.argmax(np.where(flags, np.nan_to_num(rms, nan=-np.inf), -np.inf)))][1]
