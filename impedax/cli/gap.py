"""``impedax gap TOTAL [SKIN TOUCHSCREEN] --area A``: the Sirin et al. workflow end to end; with
the total alone, a single contact (a gripper pad), nothing subtracted."""

from __future__ import annotations

import sys


GAP_OUT_HELP = (
    "save the gap result: .csv a table of C_gap [F] and u [m], one row per method (Bayesian, the paper's), each column named with its unit "
    "(c_gap_f, u_m, u_low_m, ..., gap_voltage_v [V] and force_max_n [N] at force_max_frequency_hz, the force maximum; the JSON gives u in µm and "
    "the gap voltage and force over frequency), sampling_unreliable and the warnings (one per line) on the bayes row, "
    "then a bayes_parameter row per EDL parameter (value, low, high, unit, fit_value, fit_stderr); .json the --json summary; "
    ".nc the force bands with the gap summary as attributes, the EDL parameters and the draws of u (netCDF; read it back with impedax.io.read_netcdf); '-' the JSON to standard output. "
    "Each records impedax's version, these options and the input files (docs/io.md, Provenance); single_contact (CSV column, JSON key, .nc attribute) says whether skin and screen were subtracted"
)


BAND_HELP = ("keep only the frequencies from --fmin to --fmax [Hz] of every input file before the subtraction "
             "(within 1e-3 relative of the ends): a band all files share, when one was measured over a narrower one")


def add_band_options(p) -> None:
    """``--fmin``/``--fmax`` of ``impedax gap`` and ``impedax remaining`` (`files_in_band`)."""
    from .common import number_option

    p.add_argument("--fmin", type=number_option, help="lowest frequency kept [Hz]; " + BAND_HELP)
    p.add_argument("--fmax", type=number_option, help="highest frequency kept [Hz]; " + BAND_HELP)


def files_in_band(datasets: list, paths: list[str], fmin: float | None, fmax: float | None) -> list:
    """Each spectrum of ``datasets`` (read from ``paths``) narrowed to ``fmin``–``fmax`` [Hz]
    (None: no bound; the ends taken within `SWEEP_RTOL`, the grids' tolerance), so that files
    measured over different bands meet on the one they share (the grids are checked after, as
    always); a file with no frequency left is a `ParameterError` naming it and its band."""
    import numpy as np

    from ..errors import ParameterError
    from ..io.table import SWEEP_RTOL

    if fmin is None and fmax is None:
        return datasets
    low = -np.inf if fmin is None else fmin * (1 - SWEEP_RTOL)
    high = np.inf if fmax is None else fmax * (1 + SWEEP_RTOL)
    out = []
    for data, path in zip(datasets, paths):
        if data is None:
            out.append(data)
            continue
        freq = np.asarray(data["frequency"].values, float)
        keep = np.flatnonzero((freq >= low) & (freq <= high))
        if not keep.size:
            band = " and ".join(f"{o} {v:g} Hz" for o, v in (("--fmin", fmin), ("--fmax", fmax)) if v is not None)
            raise ParameterError(f"{band} {'leave' if fmin is not None and fmax is not None else 'leaves'} no frequency of {path} ({freq.size} points, {freq.min():g}–{freq.max():g} Hz)")
        narrowed = data.isel(frequency=keep)
        narrowed.attrs = dict(data.attrs)
        out.append(narrowed)
    return out


def files_without_points(datasets: list, paths: list[str], text: str | None) -> list:
    """Each spectrum of ``datasets`` (read from ``paths``) without the frequencies of
    ``--exclude F,F,...`` (`common.exclude_points`: each the nearest measured one within
    `EXCLUDE_RTOL`), before the subtraction and every fit of ``impedax gap``. A frequency
    beyond a file's measured band is left to the others (a file measured over a narrower band,
    met with --fmin/--fmax); one that names no point of a file whose band holds it, or of no
    file at all, is a `ParameterError` naming the file(s)."""
    import numpy as np

    from ..arguments import EXCLUDE_RTOL
    from ..errors import ParameterError
    from .common import exclude_frequency, exclude_items, exclude_points

    if text is None:
        return datasets
    items = exclude_items(text)
    values = [exclude_frequency(item) for item in items]  # (an option's error, before any file's)
    out, named = [], set()
    for data, path in zip(datasets, paths):
        if data is None:
            out.append(data)
            continue
        freq = np.asarray(data["frequency"].values, float)
        low, high = freq.min() * (1 - EXCLUDE_RTOL), freq.max() * (1 + EXCLUDE_RTOL)
        inside = [item for item, value in zip(items, values) if low <= value <= high]
        named.update(inside)
        if not inside:
            out.append(data)
            continue
        try:
            kept = exclude_points(data, ",".join(inside))
        except ParameterError as error:
            raise ParameterError(f"{path}: {error}") from None
        kept.attrs = dict(data.attrs)
        out.append(kept)
    beyond = [item for item in items if item not in named]
    if beyond:
        bands = "; ".join(f"{path} {d.frequency.values.min():g}–{d.frequency.values.max():g} Hz" for d, path in zip(datasets, paths) if d is not None)
        raise ParameterError(f"--exclude {', '.join(beyond)}: beyond the measured band of every input file ({bands})")
    return out


def _ep_branch(value: str) -> str:
    """--ep as its element symbol (``Q``, the circuit language's alias of CPE → ``CPE``; any case),
    `models.gap.ep_branch_name`; the rest refused with the aliases named."""
    import argparse

    from ..models.gap import EP_BRANCHES, ep_branch_aliases, ep_branch_name

    name = ep_branch_name(value)
    if name not in EP_BRANCHES:
        raise argparse.ArgumentTypeError(f"invalid choice: {value!r} (choose from {', '.join(map(repr, EP_BRANCHES))}; or {ep_branch_aliases()}, its alias in the circuit language)")
    return name


def register(sub) -> None:
    from .common import SELECT_SYNTAX_HELP, accept_negative_numbers, add_output_options, add_quiet_option, data_help, number_option
    from ..arguments import GAP_MIN_STEPS
    from .fit import add_exclude_option
    from .sample import steps_option

    p = sub.add_parser(
        "gap",
        help="air-gap thickness, gap voltage and force from three spectra (Sirin et al.), or one of a single contact",
        description="Subtract skin and touchscreen from the total impedance (given the total alone: a single contact, "
        "e.g. an electroadhesive gripper pad, whose total is the contact's impedance and takes the whole drive), fit the EDL parallel model, "
        "sample the gap thickness u and print it with its 90 % credible interval next to the paper's method. "
        "Default (--method hierarchical): every total trial gets its own u and EP branch drawn from a population, "
        "with noise from the trial scatter and a sampled discrepancy floor; u is the population median, "
        "reported with the spread between trials and a new trial's interval. --pooled: one model on the trial means (their SEM only). "
        "Force bands use the PEAK convention of Sirin eq 1.",
    )
    accept_negative_numbers(p)  # (--area -1e-4: the value, refused by name, not argparse's "expected one argument")
    p.add_argument("total", metavar="DATA_TOTAL", help=data_help("finger-on-screen spectra (trials as an extra dimension)"))
    p.add_argument("skin", metavar="DATA_SKIN", nargs="?", help=data_help("skin spectra; leave out with DATA_TS for a single contact (nothing subtracted)"))
    p.add_argument("touchscreen", metavar="DATA_TS", nargs="?", help=data_help("touchscreen spectra; given with DATA_SKIN or not at all"))
    p.add_argument("--area", type=number_option, required=True, help="apparent contact area A [m²], e.g. 130e-6; outside 1e-6–1e-2 m² (1–10 000 mm², a fingertip) it is refused as a likely unit slip unless --no-area-check")
    p.add_argument("--no-area-check", action="store_true", help="analyse any positive --area, e.g. a contact other than a fingertip: one outside 1e-6–1e-2 m² gives a warning instead of an error")
    p.add_argument("--v0", type=number_option, help="drive amplitude V0 [V], peak; default: the one voltage the total spectra carry (a --select voltage=500 "
                   "or a scalar coordinate or attribute named voltage, V0, drive_voltage, ... in V), else 75 (Sirin et al.)")
    p.add_argument("--eps-gap", type=number_option, metavar="EPS", help="relative permittivity ε_gap of the gap's medium in u = ε0 ε_gap A/C_gap and the force "
                   "(default 1.00059, air, as Sirin et al.); e.g. 3.4 for a polyimide film in a gripper pad's gap; at least 1")
    p.add_argument("--ep", type=_ep_branch, metavar="{CPE,C}", choices=("CPE", "C"), default="CPE", help="electrode-polarization branch: R_EP || CPE_EP (default; Q, the circuit language's alias of CPE, names it too) or R_EP || C_EP (its C_EP and C_gap are seen only as their sum, so C gives u's lower bound: analysed as R_EP || C_gap)")
    p.add_argument("--method", choices=("hierarchical", "pooled"), help="hierarchical model over the trials (default) or the pooled analysis of the trial means")
    p.add_argument("--pooled", action="store_true", help="same as --method pooled")
    p.add_argument(
        "--steps", type=steps_option, default="auto", metavar="N|auto",
        help="MCMC draws per chain after as many warm-up steps (hierarchical; auto: 500) or emcee steps (pooled; auto: until the chain is "
        f"50 autocorrelation times long, as impedax sample); at least {GAP_MIN_STEPS} (default auto)",
    )
    p.add_argument("--cutoff-hz", type=number_option, metavar="HZ", help="the paper method's cutoff [Hz]: C_gap = mean |Y_R|/ω over the frequencies at and above HZ "
                   "(Sirin §2.3; default 30, the paper's); positive and at most the data's highest frequency (below the band: every point, with a warning)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument(
        "--select", action="append", metavar="DIM=LABEL",
        help="narrow each of the input files that has dimension DIM to the spectra whose DIM is LABEL, e.g. one session of a "
        "file over session and trial; the remaining dimensions (and a list's or range's DIM) are the trials. " + SELECT_SYNTAX_HELP,
    )
    add_quiet_option(p)
    add_band_options(p)
    add_exclude_option(p, of_every_file=True)
    p.add_argument("--remaining", metavar="FILE.nc|.csv", help="also save the trial-mean remainder total − skin − touchscreen that the EDL model is fitted to (a single contact: the total's trial mean, nothing subtracted, attr single_contact 1), as a spectrum (with sigma) that impedax fit reads; impedax remaining writes it without the sampling")
    add_output_options(p, plot="save impedance, gap posterior and force bands", out=GAP_OUT_HELP)
    p.set_defaults(run=run)


def run(args) -> int:
    from ..arguments import relative_permittivity_number
    from ..constants import EPSILON_AIR
    from ..errors import ParameterError
    from ..fitting.bayes.chain import AUTO_STEPS, auto_step_cap
    from ..models.gap import HIERARCHICAL_AUTO_DRAWS, check_cutoff, check_fingertip_area, gap_analysis
    from ..models.gap_inputs import check_not_a_remainder, condition_notes, drive_voltage
    from ..models.sirin import SIRIN_CUTOFF_HZ
    from .sample import check_steps
    from .common import check_band_options, shown_path, check_distinct_paths, contact_paths, check_memory, command_provenance, figure_options, figure_writer, load_selected_files, plan_outputs, print_result, remainder_with_paths, result_writer, spectrum_writer

    if args.pooled and args.method == "hierarchical":  # (argparse's exclusive groups let a default-valued --method through)
        raise ParameterError("--pooled and --method hierarchical contradict each other: give one")
    args.method = "pooled" if args.pooled else args.method or "hierarchical"
    paths = contact_paths(args, "gap")
    if not args.area > 0:
        raise ParameterError(f"--area must be positive (m²), got {args.area:g}")
    if args.v0 is not None and not args.v0 > 0:
        raise ParameterError(f"--v0 must be positive (V), got {args.v0:g}")
    eps_gap = EPSILON_AIR if args.eps_gap is None else relative_permittivity_number(args.eps_gap, "--eps-gap")
    if not args.no_area_check:
        check_fingertip_area(args.area)  # (an option's error before any file's: gap_analysis checks it again)
    check_band_options(args.fmin, args.fmax)
    cutoff = SIRIN_CUTOFF_HZ if args.cutoff_hz is None else args.cutoff_hz
    check_cutoff(cutoff)  # (gap_analysis's own check and words, cutoff_hz read as --cutoff-hz: before any file is read)
    if args.fmax is not None and args.fmax < cutoff:  # (the paper's C_gap reads |Y_R|/ω at and above the cutoff: gap_analysis's cutoff_hz)
        given = f" (--cutoff-hz {cutoff:g})" if args.cutoff_hz is not None else ""
        raise ParameterError(f"--fmax {args.fmax:g} Hz leaves no frequency above {cutoff:g} Hz{given}, where the paper's method reads C_gap = |Y_R|/ω "
                             f"(Sirin §2.3: the remainder is the gap's capacitance there) and the EDL model's C_gap shows; keep --fmax above {cutoff:g} Hz")
    steps = args.steps
    check_steps(steps)  # (as impedax sample's --steps)
    outputs = plan_outputs(
        [("--out", args.out, "result"), ("--plot", args.plot, "figure"), ("--remaining", args.remaining, "spectrum")],
        inputs=list(paths.values()), stdout="--json" if args.json else None,
    )
    # a chain keeps every step of every walker (chain): about 64 walkers × 8 parameters × 8 bytes, kept three times
    # (--steps auto: emcee's cap, pooled; HIERARCHICAL_AUTO_DRAWS, hierarchical)
    auto_length = auto_step_cap(64) if args.method == "pooled" else HIERARCHICAL_AUTO_DRAWS
    length = auto_length if steps == AUTO_STEPS else steps
    check_memory("--steps", length * 64 * 10 * 8 * 3, f"a gap-thickness chain of {'up to ' if steps == AUTO_STEPS and args.method == 'pooled' else ''}{length} steps")
    read = files_without_points(load_selected_files(list(paths.values()), args.select, args.readers), list(paths.values()), args.exclude)  # (before the band, as fit takes them)
    total, skin, touchscreen = (*files_in_band(read, list(paths.values()), args.fmin, args.fmax), None, None)[:3]  # (a single contact: the total alone)
    check_distinct_paths(paths)  # (after reading: a bad file is named first)
    try:
        check_cutoff(cutoff, total)  # (the band --fmin/--fmax/--exclude left; gap_analysis checks it again, here before the notes on the drive; below the band: its warning)
    except ParameterError as error:
        if args.cutoff_hz is not None:
            raise
        raise ParameterError(f"{error} (--cutoff-hz not given: {cutoff:g} Hz is the paper's default; give a lower one)") from None
    check_not_a_remainder(total, skin, touchscreen)  # (gap_analysis checks it again; here before the notes on the drive)
    drive = drive_voltage(total, args.v0)  # (gap_analysis finds the same; said here once, before minutes of sampling)
    if drive.note:
        print(f"impedax gap: note: {drive.note}", file=sys.stderr)
    for note in [*drive.warnings, *condition_notes(total, skin, touchscreen, default_v0=drive.value if drive.source == "default" else None)]:  # (the report and JSON repeat them)
        print(f"impedax gap: warning: {note}", file=sys.stderr)
    result = gap_analysis(total, skin, touchscreen, area=args.area, v0=args.v0, ep=args.ep, steps=steps, seed=args.seed, method=args.method, progress=not args.quiet, check_area=not args.no_area_check, eps_gap=eps_gap, cutoff_hz=cutoff)
    source = shown_path(args.total) + (f" [{', '.join(args.select)}]" if args.select else "")  # (the figure's default title: the total file and the selection)
    used = {**(getattr(result, "settings", None) or {}), "v0": getattr(result, "v0", args.v0)}  # (--v0 as run: given, the data's or the default)
    record = command_provenance(args, source=paths, data_files=list(paths.values()), **{f"{k}_used": v for k, v in used.items()})
    outputs.save({"--out": result_writer(result, provenance=record), "--plot": figure_writer(result.plot, source, **figure_options(args)), "--remaining": spectrum_writer(lambda: remainder_with_paths(result.remaining, paths), record, args.remaining)})
    if not outputs.uses_stdout:
        from .common import to_terminal

        with to_terminal(not args.json):  # (wrapped at words on a terminal, as diagnose's report)
            print_result(result, args.json, provenance=record, command="gap")
    if args.remaining:  # (as impedax remaining says of its --out: 2026-12-06, gap --remaining FILE.csv said nothing)
        from .common import csv_sigma_note

        note = csv_sigma_note(result.remaining, None if args.remaining == "-" else args.remaining, "--remaining")
        if note:
            print(f"impedax gap: note: {note}", file=sys.stderr)
    if args.json and (result.warnings or getattr(result, "alarms", ())):
        print(f"impedax gap: {_json_pointer(result.warnings, getattr(result, 'alarms', ()))}", file=sys.stderr)
    return 0


def _json_pointer(warnings, alarms) -> str:
    """The stderr line of ``--json``: how many warnings and, by name, the alarms (`GapAnalysis.alarms`:
    the states that void the result), and the JSON keys that hold them. The line named the
    warnings only, while the JSON's ``alarms`` held SAMPLING UNRELIABLE (a walkthrough on the
    SYNTHETIC demo data, 2026-12-06)."""
    parts = [f"{len(warnings)} warning(s), see the JSON 'warnings'"] if warnings else []
    if alarms:
        names = ", ".join(_alarm_name(a) for a in alarms)
        parts.append(f"{'and ' if parts else ''}{len(alarms)} alarm{'s' if len(alarms) > 1 else ''}: {names}; see the JSON 'alarms'")
    return " ".join(parts) if len(parts) < 2 else f"{parts[0]}, {parts[1]}"


def _alarm_name(alarm: str) -> str:
    """An alarm's name: its leading capitalised words ("SAMPLING UNRELIABLE", "PAPER METHOD: NO AIR GAP")."""
    words = []
    for part in alarm.split(": "):
        if part != part.upper():
            break
        words.append(part)
    return ": ".join(words) or alarm
