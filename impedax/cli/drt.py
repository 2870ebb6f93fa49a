"""``impedax drt DATA``: the distribution of relaxation times — how many arcs, at which τ?"""

from __future__ import annotations


def _lam(text: str):
    from ..errors import ParameterError

    if text == "auto":
        return "auto"
    try:
        value = float(text)
    except ValueError:
        # (a rule's name given where λ goes: --lam gcv is told more than "expected 'auto' …"; ix.drt(lam="gcv") names lam_method alike)
        rule = f"; the rule that chooses λ is --lam-method {text.lower()} (with --lam auto, the default)" if text.lower() in ("gcv", "lcurve") else ""
        raise ParameterError(f"--lam {text!r}: expected 'auto' or a positive number{rule}") from None
    return value


def _fraction(text: str) -> float:
    """--min-peak-fraction: a number in [0, 1)."""
    import argparse

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number (a share of the DRT's area, e.g. 0.05)") from None
    if not 0 <= value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} must be at least 0 and below 1 (a share of the DRT's area, e.g. 0.05)")
    return value


def register(sub) -> None:
    from .common import add_plot_option, add_quiet_option, add_select_option, data_help, number_option
    from .fit import add_exclude_option

    p = sub.add_parser(
        "drt",
        help="distribution of relaxation times (Tikhonov, Gaussian RBFs): peaks, R_inf, L, credible band",
        description="Compute the distribution of relaxation times of a spectrum by Tikhonov regularisation on a Gaussian RBF basis, "
        "lambda chosen by (modified) GCV or the L-curve; a file of several spectra gets the DRT of each (one line each). "
        "The report ends with a starting circuit read off the peaks and the 'impedax fit' command that fits it. See docs/drt.md.",
    )
    p.add_argument("data", metavar="DATA", help=data_help("spectrum file (any format impedax reads); a file of several spectra gets a DRT of each, or pick one with --select"))
    add_select_option(p)
    p.add_argument("--lam", default="auto", metavar="auto|VALUE", help="regularisation parameter, relative to max|Z|^2: 'auto' (default; chosen by --lam-method, never below 1e-4) or a positive number used as given")
    p.add_argument("--lam-method", choices=("gcv", "lcurve"), default="gcv", help="how 'auto' chooses lambda (default: gcv)")
    p.add_argument("--method", choices=("tikhonov",), default="tikhonov", help="DRT method (default: tikhonov)")
    p.add_argument("--signed", action="store_true", help="allow negative gamma (inductive loops, negative capacitances)")
    p.add_argument(
        "--min-peak-fraction", type=_fraction, default=0.1, metavar="F",
        help="peaks holding less than this share of the DRT's area are dropped (default 0.1); a resolved peak "
        "(gamma falls below 10 %% of its height on both sides) needs half of it. See docs/drt.md, 'Peaks'",
    )
    p.add_argument("--fmin", type=number_option, help="ignore data below this frequency [Hz]")
    p.add_argument("--fmax", type=number_option, help="ignore data above this frequency [Hz]")
    add_exclude_option(p)
    p.add_argument("--json", action="store_true", help="machine-readable output")
    add_plot_option(p, "save gamma vs tau with peaks and band, and the fit on Nyquist/Bode (several spectra: every gamma(tau), gamma mapped over the spectra and tau with each one's peaks, and each fit's rms_rel beside the noise's)")
    p.add_argument("--out", metavar="FILE.csv|.json|.nc", help="save gamma over tau with its band (CSV), the --json summary (JSON) or gamma, its band and the fit (netCDF), as impedax.write_result does; '-' the CSV to standard output (--json prints the JSON)")
    add_quiet_option(p)
    p.set_defaults(run=run)


def run(args) -> int:
    from ..fitting.drt import drt
    from ..fitting.problem import open_spectrum
    from .common import check_band_options, command_line_words, command_provenance, data_source, emit_json, exclude_points, figure_options, figure_writer, InCommandWords, load_selected, note_skipped_rows, plan_outputs, progress_printer, skipped_rows, with_source, WithSummaryKeys

    outputs = plan_outputs([("--out", args.out, "drt"), ("--plot", args.plot, "figure")], inputs=[args.data], stdout="--json" if args.json else None)
    # a file of several spectra: the DRT of each in one solve (`DRTBatchResult`), or one (--select)
    check_band_options(args.fmin, args.fmax)
    data = exclude_points(load_selected(args.data, args.select, readers=args.readers), args.exclude)
    loaded = data
    if args.fmin is not None or args.fmax is not None:
        from ..fitting.problem import select_band

        data = select_band(data, args.fmin, args.fmax, data_source(data) or args.data)  # (<stdin> for -, and any --select)
    source = data_source(data)  # (the file and any --select: the JSON's ``source``, as kk's and fit's)
    data = open_spectrum(data).data
    progress = progress_printer(quiet=args.quiet)  # (130 cycles took 7 s without a word; printed only past PROGRESS_AFTER_S)
    n_spectra = int(data["Z"].size // data.sizes["frequency"])
    # (closed on every way out: a printer left open after an error prints its pending line 2 s
    # later, into whatever runs next in the process, e.g. a test of `fit -q`)
    try:
        progress(f"DRT of {n_spectra} spectr{'um' if n_spectra == 1 else 'a'}: solving, then peaks and credible bands")
        from .common import band_named

        with band_named(loaded, data, args.fmin, args.fmax):
            result = drt(data, method=args.method, lam=_lam(args.lam), lam_method=args.lam_method, signed=args.signed, min_peak_fraction=args.min_peak_fraction)
        if args.plot:  # (the slowest output: ~1 s for 130 curves)
            progress(f"drawing {args.plot}")
        record = command_provenance(args, source=source, data_files=[args.data])
        kk_note = _kk_note(result, data, args)
        # (the JSON's, as inspect --json's; suggestion_withheld: the text's "none while …" reason,
        # where suggested_model still holds γ's circuit)
        # (the notes in the command's words, as fit's: --signed, --lam auto where the Python API says signed=True, lam='auto')
        read = InCommandWords(WithSummaryKeys(result, {"skipped_rows": skipped_rows(data), "kk_note": kk_note, "suggestion_withheld": suggestion_withheld(result)}), "drt")
        outputs.save({"--out": lambda path: _save(read, path, source, record), "--plot": figure_writer(result.plot, source, **figure_options(args))})
    finally:
        progress.close()
    if outputs.uses_stdout:
        return 0
    if args.json:
        emit_json(with_source(read.summary(), source, record))
    else:
        from .common import to_terminal

        with to_terminal(True):  # (wrapped at words on a terminal, as diagnose's report)
            print(command_line_words(result.report(), "drt"))
            if kk_note:
                print(f"note: {kk_note}")
            print(_suggestion_line(result, args, data))
            note_skipped_rows(data, "drt", args.data)
    return 0


def _kk_note(result, data, args) -> str | None:
    """Where the data fail the linear KK test (`impedax.kk_test`, default options), said beside
    the DRT, or None: γ fitted to a drift or disturbance holds it as peaks, so the peaks there are
    no evidence of arcs (a walkthrough's drifting spectrum gets a third arc from the DRT, and
    otherwise no word of the data). Not said when the DRT gives a sign hint (the hint is the cause),
    nor for a spectrum too short for a conclusive test."""
    import shlex

    from ..data import format_frequency, format_time, label_text
    from ..fitting.kk import kk_test, kk_test_batch

    results = getattr(result, "results", (result,))
    if all(r.sign_hint for r in results):
        return None
    extra = [d for d in data["Z"].dims if d != "frequency"]
    tests = kk_test_batch(data).results if extra else (kk_test(data),)
    failed = [i for i, (r, t) in enumerate(zip(results, tests)) if t.conclusive and not t.valid and not r.sign_hint]
    if not failed:
        return None
    # (the run's --fmin/--fmax/--exclude too: the test above ran on the points the DRT took; a
    # command naming the file alone, on REAL BioLogic with --exclude 5.34,56.2,123,270, would flag those four where
    # the note names 15.2 Hz)
    command = f"impedax kk {shlex.quote(str(args.data))}" + "".join(f" --select {shlex.quote(s)}" for s in (args.select or ())) + "".join(
        f" {flag} {shlex.quote(str(value))}" for flag, value in (("--fmin", args.fmin), ("--fmax", args.fmax), ("--exclude", args.exclude)) if value is not None)
    if not extra:
        bands = tests[0].bad_bands  # (the shaded bands, edges halfway to the neighbours: a peak between a flagged point and the next lies there; the text names the flagged points)
        inside = [p for p in results[0].peaks if any(lo <= p.frequency_hz <= hi for lo, hi in bands)]
        listed = ", ".join(f"τ = {format_time(p.tau_s)} (f = {format_frequency(p.frequency_hz)})" for p in inside)
        peaks = f"; the peak{'s' if len(inside) > 1 else ''} at {listed} {'lie' if len(inside) > 1 else 'lies'} there" if inside else ""
        return (f"the data fail the Kramers–Kronig test at {tests[0].measured_bands_text()} ({command} says which points and what to do): "  # (not "what to leave out": on REAL Gamry kk finds none worth leaving out)
                f"γ there holds their drift or disturbance as well as any relaxation{peaks}")
    labels = result.labels()
    named = "; ".join(", ".join(f"{d}={label_text(v)}" for d, v in labels[i].items()) for i in failed[:3]) + ("; …" if len(failed) > 3 else "")
    return (f"{len(failed)} of {len(results)} spectra fail the Kramers–Kronig test ({named}; {command} lists their bands): "
            "their γ holds drift or disturbance as well as any relaxation")


def suggestion_withheld(result) -> str | None:
    """Why the report gives no starting circuit (the text's "none …", JSON
    ``suggestion_withheld``), else None: every spectrum's sign looks flipped (a circuit read off
    conj(Z) starts a fit of the wrong data), or λ over-smooths every one (peaks too broad and too
    few). The JSON's ``suggested_model`` is still the circuit read off γ."""
    results = getattr(result, "results", (result,))
    if all(r.sign_hint for r in results):
        return "while the sign looks flipped (the warning above); correct it, then run impedax drt again"
    if all(r.over_smoothed for r in results):
        return "while λ over-smooths the data (the warning above); run impedax drt again with a smaller --lam, or --lam auto"
    return None


def _suggestion_line(result, args, data) -> str:
    """The report's last line: the starting circuit read off the DRT and the ``impedax fit``
    command that fits it (`DRTResult.suggested_circuit`) to the points the DRT took (the run's
    --select, --fmin/--fmax, --exclude and --plugin: `common.fit_command`); for several spectra
    the circuit most of them suggest, with the starts of the first of those
    (`suggest.most_common_suggestion`)."""
    from ..fitting.drt.suggest import most_common_suggestion
    from .common import fit_command

    withheld = suggestion_withheld(result)
    if withheld:
        return f"starting circuit from the DRT: none {withheld}"
    results = getattr(result, "results", (result,))
    suggestion, count = most_common_suggestion(results)
    share = "" if len(results) == 1 else f" (the one {count} of {len(results)} spectra suggest, starts from the first of them)"
    return f"starting circuit from the DRT{share}: {suggestion.model} — fit it with: {fit_command(args, data=data)} {suggestion.fit_options()}"


def _save(result, path, source: str | None = None, provenance=None) -> None:
    """``--out``: `impedax.write_result`, the same files as in Python (.csv γ over τ, a column
    per dimension first for several spectra; .json the summary, .nc the lossless dataset, each
    naming the data's ``source`` and ``provenance`` as ``--json`` does; the CSV with the
    provenance columns, docs/io.md "Provenance")."""
    from pathlib import Path

    from ..io.export import write_result

    if provenance is not None and Path(path).suffix.lower() == ".csv":
        result = _WarningsLast(result, provenance)
    write_result(result, path, source=source, provenance=provenance)  # (a .nc's prose in the command's words: ``result``'s `common.InCommandWords`)


class _WarningsLast:
    """``result`` whose table (`DRTResult.to_table`) has the provenance columns before its
    ``warnings``, which stays the last column: the CSV's columns up to the provenance are where
    files of older versions, without ``warnings``, have them; every other attribute is the result's."""

    def __init__(self, result, provenance):
        self._result, self._provenance = result, provenance

    def to_table(self) -> list[dict]:
        from ..io.provenance import provenance_columns

        columns = provenance_columns(self._provenance)
        return [{**{k: v for k, v in row.items() if k != "warnings"}, **columns, "warnings": row["warnings"]} for row in self._result.to_table()]

    def __getattr__(self, name: str):
        return getattr(self._result, name)
