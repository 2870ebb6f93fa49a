"""``impedax kk DATA``: linear Kramers–Kronig test — is the spectrum itself causal and stationary?"""

from __future__ import annotations


def register(sub) -> None:
    from .common import add_plot_option, add_quiet_option, add_select_option, data_help, number_option
    from .fit import add_exclude_option

    p = sub.add_parser(
        "kk",
        help="linear Kramers-Kronig test of a spectrum (data problems vs model problems)",
        description="Fit a Kramers-Kronig-consistent Voigt chain (Schoenleber et al. 2014) and report where the data are not KK-consistent (drift, movement, non-stationarity). See docs/kk.md.",
    )
    p.add_argument("data", metavar="DATA", help=data_help("spectrum file; a file of several spectra is tested spectrum by spectrum (one line each, by either method), or pick one with --select"))
    p.add_argument("--method", choices=("linear", "zhit"), default="linear", help="linear: Voigt-chain KK test (default); zhit: |Z| reconstructed from the phase (Z-HIT, docs/drt.md; --c, --max-rc, --no-inductance and --no-capacitance set the linear test's chain and are refused with it)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    add_plot_option(p, "save data vs KK fit and the residuals with bad bands shaded (several spectra: every spectrum's residual mapped over the spectra and frequency)")
    p.add_argument("--out", metavar="FILE.csv|.json|.nc", help="save the test, as impedax.write_result does: .csv a row per frequency (data, KK fit, residuals, flagged; "
                   "a column per dimension first for several spectra), .json the --json summary, .nc the full result as netCDF; '-' the JSON to standard output")
    p.add_argument("--c", type=float, default=None, help="µ cut-off (default 0.85; linear test only)")
    p.add_argument("--max-rc", type=int, default=None, metavar="M", help="largest number of RC elements tried (default: N/2 for N frequencies, at most 100; on data sparser than about 7 points a decade, 3.5 per decade of the band; linear test only)")
    p.add_argument("--no-inductance", action="store_true", help="no series inductance in the KK model (linear test only)")
    p.add_argument("--no-capacitance", action="store_true", help="no series capacitance in the KK model (linear test only)")
    p.add_argument("--noise", choices=("auto", "sigma", "residuals"), default=None,
                   help="each point's noise: sigma = the data's sigma column (the chain weighted by 1/σ, each point judged against its σ), residuals = one estimate "
                        "from the residuals; auto (default) = sigma when the data carry one (linear test only; docs/kk.md)")
    p.add_argument("--fmin", type=number_option, help="ignore data below this frequency [Hz]")
    p.add_argument("--fmax", type=number_option, help="ignore data above this frequency [Hz]")
    add_exclude_option(p)
    add_select_option(p)
    # (the test prints no progress lines, 2.5 s of CPU for the 130 REAL battery cycles: --quiet is
    # taken as the other analysis commands take it, so that a pipeline passing it to each of them
    # runs)
    add_quiet_option(p)
    p.set_defaults(run=run)


# the options of the linear test's Voigt chain: Z-HIT has no chain, and refuses them
LINEAR_ONLY = ("--c", "--max-rc", "--no-inductance", "--no-capacitance", "--noise")


def run(args) -> int:
    from ..errors import ParameterError
    from ..fitting import kk_test, kk_test_batch, zhit, zhit_batch
    from .common import (check_band_options, command_line_words, command_provenance, data_source, emit_json, exclude_points, figure_options, figure_writer, json_in_command_words,
                         load_selected, note_skipped_rows, plan_outputs, result_writer, skipped_rows, with_source, WithSummaryKeys)

    if args.method == "zhit":
        given = [flag for flag, value in zip(LINEAR_ONLY, (args.c, args.max_rc, args.no_inductance or None, args.no_capacitance or None, args.noise)) if value is not None]
        if given:
            raise ParameterError(
                f"{', '.join(given)} set{'s' if len(given) == 1 else ''} the linear test's Voigt chain; --method zhit has none: "
                f"leave {'it' if len(given) == 1 else 'them'} out, or drop --method zhit"
            )
    outputs = plan_outputs([("--out", args.out, "result"), ("--plot", args.plot, "figure")], inputs=[args.data], stdout="--json" if args.json else None)
    # a file of several spectra: every one tested (one table row each), as `fit` fits them
    # all, by either method (Z-HIT too), and --plot maps their residuals
    data = exclude_points(load_selected(args.data, args.select, readers=args.readers), args.exclude)
    loaded = data
    if args.fmin is not None or args.fmax is not None:
        from ..fitting.problem import select_band

        check_band_options(args.fmin, args.fmax)
        data = select_band(data, args.fmin, args.fmax, data_source(data) or args.data)  # (<stdin> for -, and any --select)
    options = dict(c=0.85 if args.c is None else args.c, max_rc=args.max_rc, inductance=not args.no_inductance, capacitance=not args.no_capacitance, noise=args.noise or "auto")
    source = data_source(data)
    record = command_provenance(args, source=source, data_files=[args.data], **({} if args.method == "zhit" else {"c": options["c"]}))  # (Z-HIT has no c)
    several = any(d != "frequency" for d in data["Z"].dims)
    from .common import band_named

    with band_named(loaded, data, args.fmin, args.fmax):
        if args.method == "zhit":
            result = zhit_batch(data) if several else zhit(data)
        else:
            result = kk_test_batch(data, **options) if several else kk_test(data, **options, find_passing_band=True)
    # the reader's skipped rows in the JSON, as inspect --json gives them; --out as
    # fit's and drt's (docs/io.md lists kk --out)
    command, options = _next_command(args, result, data) if not several and args.method == "linear" else (None, None)
    if command and args.data == "-":
        command += "  (with the data saved to a file, named in place of -: standard input is read once)"
    added = {"skipped_rows": skipped_rows(data)} if options is None else {"skipped_rows": skipped_rows(data), "suggested_options": options}
    read = WithSummaryKeys(result, added)
    outputs.save({"--out": result_writer(read, source, record), "--plot": figure_writer(lambda: result.plot(), source, **figure_options(args))})  # (a batch's: its residuals mapped)
    if outputs.uses_stdout:
        return 0
    # (the notes in the command's words, as fit's and diagnose's: --noise residuals, --fmin/--fmax where
    # the Python API says kk_test(noise='residuals') and data.drop_sel(...); --out FILE.json alike, `result_writer`)
    if args.json:
        emit_json(with_source(json_in_command_words(read.summary(), "kk"), source, record))
        return 0
    from .common import to_terminal

    with to_terminal(True):  # (wrapped at words on a terminal, as diagnose's report)
        if several:
            print(command_line_words(result.report(args.data), "kk"))
        else:
            print(command_line_words(result.report(command) if args.method == "linear" else result.report(), "kk"))
            if args.method == "linear" and result.valid and result.conclusive and not result.sign_hint:
                # (the next step as impedax inspect names it, on the points tested: a
                # valid verdict names the next step too)
                from .common import fit_command

                stdin = "; with the data saved to a file, named in place of -: standard input is read once" if args.data == "-" else ""
                print(f"next: {fit_command(args, data=data, program='impedax drt')} (how many arcs; it ends with a starting circuit to fit{stdin})")
    note_skipped_rows(data, "kk", args.data)
    return 0


def _next_command(args, result, data) -> tuple[str | None, list[str]]:
    """The ``impedax kk`` command that tests the spectrum again without the points the test
    suggests leaving out (`KKResult.excludable_frequencies`), this run's options kept and its
    --fmin/--fmax/--exclude merged with the new ones (`common.run_options`), and those three as
    words (the JSON's ``suggested_options`` on the command line: to give in place of the run's);
    (None, []) when there is nothing to leave out."""
    import numpy as np
    import shlex

    from .common import fit_command, run_options

    drop = result.excludable_frequencies
    if not drop.size:
        return None, []
    kept = np.setdiff1d(result.frequency, drop)
    chain = [("--c", args.c), ("--max-rc", args.max_rc), ("--no-inductance", args.no_inductance or None), ("--no-capacitance", args.no_capacitance or None), ("--noise", args.noise)]
    command = fit_command(args, kept=kept, masked=drop, data=data, program="impedax kk") + "".join(
        f" {flag}" if value is True else f" {flag} {shlex.quote(str(value))}" for flag, value in chain if value is not None)
    words = [str(w) for flag, value in run_options(args, kept=kept, masked=drop, data=data) if flag in ("--fmin", "--fmax", "--exclude") and value is not None for w in (flag, value)]
    return command, words
