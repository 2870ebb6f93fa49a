"""``impedax remaining TOTAL [SKIN TOUCHSCREEN] --out FILE``: the remainder Z_total − Z_skin − Z_TS
that ``impedax gap`` fits (Sirin eq 5), written as a spectrum file, with no fit or sampling; the
total alone is a single contact, its trial means (or trials) as ``impedax gap PAD`` fits them."""

from __future__ import annotations

import sys


def register(sub) -> None:
    from .common import add_quiet_option

    from .common import JSON_SUMMARY_HELP, SELECT_SYNTAX_HELP, data_help
    from .fit import add_exclude_option
    from .gap import add_band_options

    p = sub.add_parser(
        "remaining",
        help="the remaining impedance total − skin − touchscreen (or a single contact's trial mean) as a spectrum file, as impedax gap fits it",
        description="Subtract the skin and touchscreen spectra from the total (Sirin eq 5) with impedax gap's checks "
        "(sign, one frequency grid, three different files) and write the remainder as a spectrum that impedax fit, "
        "compare, diagnose, refine, sample and drt read. The total alone is a single contact (a gripper pad): nothing is subtracted, "
        "the remainder is its trial means, as impedax gap PAD fits them. Default: the trial means with sigma from their standard errors "
        "(a file of one spectrum adds its own sigma column; without one the remainder has no sigma, and the line says which file lacks it), "
        "what gap's least-squares fits and --pooled fit; --trials: every total trial minus the skin and screen means, "
        "what gap's hierarchical model fits (the total's trial dimensions, so .nc). No fit, no sampling.",
    )
    p.add_argument("total", metavar="DATA_TOTAL", help=data_help("finger-on-screen spectra (trials as an extra dimension)"))
    p.add_argument("skin", metavar="DATA_SKIN", nargs="?", help=data_help("skin spectra; leave out with DATA_TS for a single contact (nothing subtracted)"))
    p.add_argument("touchscreen", metavar="DATA_TS", nargs="?", help=data_help("touchscreen spectra; given with DATA_SKIN or not at all"))
    p.add_argument("--trials", action="store_true", help="one remainder per total trial (Z_total,t − mean Z_skin − mean Z_TS) instead of the trial means; needs --out FILE.nc")
    p.add_argument(
        "--select", action="append", metavar="DIM=LABEL",
        help="narrow each of the three files that has dimension DIM to the spectra whose DIM is LABEL, as impedax gap --select. " + SELECT_SYNTAX_HELP,
    )
    p.add_argument(
        "--out", metavar="FILE.nc|.csv",
        help="the remainder as a spectrum: .nc (netCDF, also .nc4, .cdf) or .csv (frequency_hz,z_real_ohm,z_imag_ohm,sigma_ohm; "
        ".txt and a name without extension are the same CSV, .tsv tab-separated); another extension is refused before any work; "
        "CSV to standard output when omitted or '-'",
    )
    add_band_options(p)
    add_exclude_option(p, of_every_file=True)
    p.add_argument("--json", action="store_true", help=JSON_SUMMARY_HELP + " (needs --out FILE): written, kind, n_trials, dims, spectra, frequencies, has_sigma, warnings, ...")
    add_quiet_option(p)  # (every command takes --quiet, so a pipeline can pass it to each)
    p.set_defaults(run=run)


def sigma_phrase(remaining) -> str:
    """The end of the line on stderr: what the remainder's sigma is made of, read from its
    ``sigma_sources`` (input → "trial scatter" or "own sigma", `sirin.remaining_impedance`) and said
    in `sirin.sigma_words`' words when an input gave its own stated sigma; or why there is none
    (``sigma_method``, which then names the input). The remainder is made here, so it has the
    sources whenever it has a sigma; the choice reads them, not ``sigma_method``'s words."""
    from ..fitting.least_squares.result import SIGMA_FROM_OWN, sigma_sources
    from ..models.sirin import sigma_words

    if "sigma" not in remaining:
        return f", no sigma: {str(remaining.attrs.get('sigma_method', '')).removeprefix('not available: ')}"
    sources = sigma_sources(remaining.attrs) or {}
    made = f", sigma: {sigma_words(sources)}" if SIGMA_FROM_OWN in sources.values() else ", sigma from their standard errors"
    return made + ": fit with --weighting sigma to use it"


def run(args) -> int:
    from pathlib import Path

    from ..errors import ParameterError
    from ..io import write_csv
    from ..fitting.least_squares.result import sigma_sources
    from ..models.gap import gap_remainder
    from .gap import files_in_band, files_without_points
    from .common import check_band_options, csv_sigma_note, check_distinct_paths, command_line_words, check_json_with_spectrum_out, command_provenance, contact_paths, emit_json, load_selected_files, plan_outputs, remainder_with_paths, spectrum_summary, spectrum_writer

    paths = contact_paths(args, "remaining")
    out = None if args.out == "-" else args.out
    if args.trials and (out is None or Path(out).suffix.lower() != ".nc"):
        raise ParameterError(f"--trials writes one spectrum per total trial, which only netCDF holds: give --out FILE.nc (got {'standard output' if out is None else out})")
    check_json_with_spectrum_out(args.json, out, "remaining")
    check_band_options(args.fmin, args.fmax)
    outputs = plan_outputs([("--out", out, "spectrum")], inputs=list(paths.values()), stdout="--json" if args.json else None)
    read = files_without_points(load_selected_files(list(paths.values()), args.select, args.readers), list(paths.values()), args.exclude)  # (as impedax gap takes them)
    total, skin, touchscreen = (*files_in_band(read, list(paths.values()), args.fmin, args.fmax), None, None)[:3]  # (a single contact: the total alone)
    check_distinct_paths(paths)
    remaining, notes = gap_remainder(total, skin, touchscreen, kind="trials" if args.trials else "mean")
    remaining = remainder_with_paths(remaining, paths)
    record = command_provenance(args, source=paths, data_files=list(paths.values()))  # (as impedax gap records them)
    written = outputs.save({"--out": spectrum_writer(lambda: remaining, record)})
    if out is None:
        sys.stdout.write(write_csv(remaining))
    for note in notes:  # (in the command's words: --exclude where Python says data.drop_sel)
        print(f"impedax remaining: warning: {command_line_words(note, 'remaining')}", file=sys.stderr)
    note = csv_sigma_note(remaining, out, "--out")
    if note:
        print(f"impedax remaining: note: {note}", file=sys.stderr)
    if args.json:  # (what a pipeline reads of the run; docs/robustness.md, "JSON for programs")
        emit_json({"command": "remaining", "written": list(written), "kind": "trials" if args.trials else "mean",
                   "n_trials": {k: int(remaining.attrs[f"n_trials_{k}"]) for k in paths}, "single_contact": len(paths) == 1, **spectrum_summary(remaining),
                   "sigma_method": str(remaining.attrs.get("sigma_method", "")),  # (what sigma is made of, or why there is none)
                   "sigma_sources": sigma_sources(remaining.attrs) or {},  # (the same as data, input → "trial scatter" or "own sigma"; {} without a sigma)
                   "warnings": [command_line_words(str(n), "remaining") for n in notes], "source": paths, "provenance": record})
        return 0
    n_trials = {k: int(remaining.attrs[f"n_trials_{k}"]) for k in paths}
    averaged = any(n > 1 for n in n_trials.values())  # (one sweep each: not "from 1 total spectra (their trial mean…)")
    counts = ", ".join(f"{n} {k}" for k, n in n_trials.items()) + (" spectra" if averaged else " spectrum")
    sigma = sigma_phrase(remaining)
    if len(paths) == 1:
        what = "the total's trials, nothing subtracted" if args.trials else ("their trial mean" if averaged else "one spectrum, nothing averaged") + sigma
        print(f"impedax remaining: a single contact, Z_total at {remaining.sizes['frequency']} frequencies from {counts} ({what})", file=sys.stderr)
        return 0
    what = "every total trial minus the skin and screen means" if args.trials else ("trial means" if averaged else "one spectrum each") + sigma
    print(f"impedax remaining: Z_total − Z_skin − Z_TS at {remaining.sizes['frequency']} frequencies from {counts} ({what})", file=sys.stderr)
    return 0
