"""``impedax compare DATA --model M1 --model M2 ...``: fit several models and rank them, on one
spectrum or spectrum by spectrum over several (`BatchComparison`)."""

from __future__ import annotations

import math
import sys
from dataclasses import replace


def register(sub) -> None:
    from .common import add_plot_option, add_select_option, data_help
    from .fit import add_bound_option, add_fit_options, add_max_steps_option

    p = sub.add_parser(
        "compare", help="fit several models to one spectrum (or to each of several) and compare them",
        description="Fit each MODEL to DATA and compare rms_rel, reduced chi², AIC, AICc, BIC, Akaike weights and F-tests of nested models; "
        "AIC ranks (under --weighting sigma AIC = chi² + 2k, the sigma taken as the known noise; else n ln(chi²/n) + 2k). "
        "A file of several spectra (or a --select leaving several) is compared spectrum by spectrum: each model's wins, "
        "and its AIC summed over the spectra (their joint AIC, the spectra being independent).",
    )
    p.add_argument("data", metavar="DATA", help=data_help("spectrum file: one spectrum, or several (compared spectrum by spectrum and summed)"))
    add_select_option(p)
    p.add_argument("--model", action="append", required=True, metavar="MODEL", help="circuit text, or in impedance.py's, AutoEIS's, CDC or EC-Lab notation, or a paper model's name (meyer, meyer-rc, meyer-cpe: the thesis's eq 3.13 values its starting values); give two or more")
    p.add_argument("--fix", action="append", metavar="NAME=VALUE", help="hold a parameter fixed in every model that has it; several after one --fix (--fix R1=1M R0=20) or --fix repeated")
    p.add_argument("--init", action="append", metavar="NAME=VALUE", help="starting value in every model that has the parameter; several after one --init (--init R1=43k C2=5u) or --init repeated")
    add_bound_option(p, " in every model that has the parameter")
    add_fit_options(p)
    add_max_steps_option(p, 400, "each model's fit")
    p.add_argument("--json", action="store_true", help="print the comparison as JSON")
    add_plot_option(p, "save data with every model's fit and residuals (several spectra: each model's ΔAIC per spectrum)")
    p.add_argument(
        "--out", metavar="FILE.csv|.json|.nc",
        help="also write the comparison to FILE: .csv one row per model (the table's columns; several spectra: per spectrum and model), .json the --json document, "
        ".nc (several spectra) the comparison with every model's fits, read back with BatchComparison.from_xarray; '-' the JSON to standard output",
    )
    p.set_defaults(run=run)


def run(args) -> int:
    from .. import compare, fit, parse
    from ..data import counted, format_bound
    from ..errors import ParameterError
    from ..fitting.least_squares.result import user_bounds_text
    from ..fitting.batch_comparison import FIT_COMMAND_WORDS
    from ..fitting.problem import open_spectrum
    from ..arguments import closest_name
    from .common import check_bounds, checked_bound_options, command_provenance, data_source, each_spectrum_written, emit_json, exclude_points, figure_options, figure_writer, impedax_text, IMPEDANCE_PY_NOTATION, json_in_command_words, load_selected, note_impedance_py_weighting, note_skipped_rows, note_unused_sigma, parse_assignments, parse_bounds, plan_outputs, progress_printer, resolve_paper_model, result_writer, skipped_rows, with_source, WithSummaryKeys
    from .fit import check_max_steps

    if len(args.model) < 2:
        raise ParameterError("compare needs at least two --model options")
    resolve_paper_model(args)  # (each MODEL may name a paper model: its circuit, its values the starting values)
    read = [(m, None) if paper else impedax_text(m, "compare", args.registry) for m, paper in zip(args.model, args.paper_model)]
    args.model = [text for text, _ in read]
    if any(notation == IMPEDANCE_PY_NOTATION for _, notation in read):  # (the weighting said once)
        note_impedance_py_weighting("compare", args.weighting)
    circuits = [parse(m, args.registry) for m in args.model]  # all syntax errors before any fitting
    refuse_same_circuits(args.model, circuits, args.registry)
    given = {"--init": parse_assignments(args.init, "--init"), "--fix": parse_assignments(args.fix, "--fix"), "--bound": parse_bounds(args.bound)}
    names = [c.parameter_names(args.registry) for c in circuits]
    everywhere = sorted({n for ns in names for n in ns})
    for flag, values in given.items():  # a name no model has is a typo
        for name in values:
            if not any(name in ns for ns in names):
                close = closest_name(name, everywhere)
                raise ParameterError(f"{flag}: no model has a parameter {name!r}" + (f"; did you mean {close}?" if close else "") + f" (parameters: {', '.join(everywhere)})")
    # each model's bounds, checked against its own elements (a name every model has is one element's parameter)
    bounds = [checked_bound_options({k: v for k, v in given["--bound"].items() if k in ns}, c.parameter_specs(args.registry), init=given["--init"], fixed=given["--fix"]) for c, ns in zip(circuits, names)]
    for c, ns in zip(circuits, names):  # (each fixed value within its element's bounds, before the data are read: no note printed before the refusal)
        check_bounds({k: v for k, v in given["--fix"].items() if k in ns}, c.parameter_specs(args.registry), "--fix")
        check_bounds({k: v for k, v in given["--init"].items() if k in ns and k not in given["--bound"]}, c.parameter_specs(args.registry), "--init")
    outputs = plan_outputs([("--out", out_path(args.out), "result"), ("--plot", args.plot, "figure")], inputs=[args.data], stdout="--json" if args.json else None)
    max_steps = check_max_steps(args.max_steps)
    data = open_spectrum(exclude_points(load_selected(args.data, args.select, readers=args.readers), args.exclude)).data
    note_unused_sigma(data, "compare", args.weighting == "sigma", "--weighting sigma")
    extra = [d for d in data["Z"].dims if d != "frequency"]
    if extra and math.prod(data.sizes[d] for d in extra) == 1:  # (a list or range that picks one: that spectrum, as before)
        data = data.isel({d: 0 for d in extra})
        extra = []
    out_path(args.out, several=bool(extra))  # (.nc: a comparison over several spectra only, said before any fit)

    def own(flag, ns):
        return {k: v for k, v in given[flag].items() if k in ns} or None

    for paper, values, text, ns in zip(args.paper_model, args.paper_values, args.model, names):  # (said once per named model, before any fit)
        if paper:
            from .common import paper_start_note

            print(paper_start_note("compare", paper, text, values, own("--init", ns) or {}, fixed=own("--fix", ns) or (), bounded=own("--bound", ns) or ()), file=sys.stderr)

    def start(i, ns):
        """Model ``i``'s --init; a paper model's values under it (`paper_start`)."""
        init = own("--init", ns)
        if not args.paper_model[i]:
            return init
        from .common import paper_start

        return paper_start(args.paper_values[i], init or {}, held=[*given["--fix"], *given["--bound"]])

    progress = progress_printer(quiet=args.quiet)  # (three models took 6-12 s without a word)
    fits: list = [None] * len(circuits)
    started_from: dict[int, int] = {}
    held = [own("--fix", ns) for ns in names]  # (each model's --fix: what nests, as the comparison judges it)
    try:
        for step, i in enumerate(nesting_order(circuits, args.registry, held)):
            c, ns, own_bounds = circuits[i], names[i], bounds[i]
            init = start(i, ns)
            contained = None if init is not None else largest_contained(i, circuits, fits, args.registry, held)
            if contained is not None:  # (its optimum carried in: the larger model never ends above it, `fit(init=)`)
                started_from[i], init = contained, fits[contained]
            also = f", also from the optimum of {circuits[contained]}, which it contains" if contained is not None else ""
            progress(f"fitting model {step + 1} of {len(circuits)}: {c}" + (f" to {counted(math.prod(data.sizes[d] for d in extra), 'spectrum', 'spectra')}" if extra else "") + also)
            options = dict(weighting=args.weighting, fmin=args.fmin, fmax=args.fmax, max_steps=max_steps, fixed=own("--fix", ns), bounds=own_bounds or None, registry=args.registry)
            fits[i] = fit(c, data, init=init, **options)
            if contained is not None and not extra:  # (one spectrum: its own search too, the lower kept; a batch solves both starts itself)
                default = fit(c, data, **options)
                # (the start carried in is no start the user gave: its message names where it came from)
                fits[i] = default if default.chi2 < fits[i].chi2 else replace(fits[i], message=fits[i].message.replace("the given start", f"the optimum of {circuits[contained]}").replace("every free parameter given", "every free parameter set by it"))
    finally:
        progress.close()
    started = [{"model": str(circuits[i]), "from": str(circuits[j])} for i, j in sorted(started_from.items())]
    comparison = WithSummaryKeys(compare(fits), {"skipped_rows": skipped_rows(data), "started_from_contained": started,
                                                      # (each model a paper model's name gave: its circuit → the name)
                                                      **({"paper_model": {str(c): p for c, p in zip(circuits, args.paper_model) if p}} if any(args.paper_model) else {})})  # (the JSON's, as fit's and inspect --json's)
    # (--out: .csv `Comparison.to_table`, .json `Comparison.summary`, as `impedax.io.write_result` writes them; a `BatchComparison`'s alike)
    source = data_source(data)
    record = command_provenance(args, source=source, data_files=[args.data])
    outputs.save({"--out": result_writer(comparison, source, record), "--plot": figure_writer(comparison.plot, source, **figure_options(args))})
    if args.json:
        emit_json(with_source(json_in_command_words(comparison.summary(), "compare"), source, record))
    elif extra and not outputs.uses_stdout:  # several spectra: the `BatchComparison`'s report
        pick = f"--select {extra[0]}=LABEL" + (" for each dimension" if len(extra) > 1 else "")
        where = each_spectrum_written(args.out, rows="a row per spectrum and model", netcdf="each model's criteria and fits over the spectra") or "--out FILE.csv (a row per spectrum and model) or --json's spectra"  # (not the options the run used)
        report = comparison.report(each_spectrum_where=f"{where}; one spectrum's full comparison: {pick}")
        warned = [batch.model for batch in comparison.batches if any(batch.warnings.values())]
        if warned:  # (the command that lists them, with this run's file and options, not "impedax fit FILE --model MODEL")
            import shlex

            from .common import fit_command

            # (each warned model's command, "; " between them)
            commands = "; ".join(f"{fit_command(args)} --model {shlex.quote(model)}" for model in warned)
            report = report.replace(f"each batch's report() lists them; from the command line, {FIT_COMMAND_WORDS}", f"impedax fit lists them: {commands}")
        print(report)
        hints = comparison.best_misfit_hints()
        if hints is not None:  # (the report's line says it; the command for its worst spectrum)
            from .common import diagnose_command

            print(f"next: {diagnose_command(args, data, hints['worst']['labels'], comparison.batches[comparison.labels.index(hints['worst']['model'])].model)} (where the best model fails on the worst of those spectra and what it misses)")
    elif not outputs.uses_stdout:  # (--out -: the JSON went to standard output)
        from .common import to_terminal

        lines = comparison.table(warnings_below=True).split("\n")
        rows = 1 + len(comparison.fits)  # (the header and a row per model keep their columns; the lines under them are wrapped at words on a terminal)
        print("\n".join(lines[:rows]))
        with to_terminal(True):
            if lines[rows:]:
                print("\n".join(lines[rows:]))
            for fit_result in comparison.fits:  # (the table's rows do not show what was held)
                held = {n: v for n, v in fit_result.values.items() if fit_result.fixed.get(n) and n in given["--fix"]}
                if held:
                    specs = fit_result.circuit.parameter_specs(fit_result.registry)  # (the values with their units, as the bounds below: "R0 = 14 mΩ", not "0.014")
                    print(f"held fixed in {fit_result.model}: " + ", ".join(f"{n} = {format_bound(v, specs[n].unit)}" for n, v in held.items()))
                if fit_result.bounds:  # (--bound: the table's rows do not show them either)
                    print(f"bounded in {fit_result.model}: " + user_bounds_text(fit_result))
            print("\n".join(warning_lines(comparison)))
            if comparison.best_misfit_hint() is not None:  # (the table's line says it; the command that shows what is missing)
                import shlex

                from .common import fit_command

                print(f"next: {fit_command(args, data=data, program='impedax diagnose')} --model {shlex.quote(comparison.best)} (where the best model fails and what it misses)")
    if not args.json and not outputs.uses_stdout:
        note_skipped_rows(data, "compare", args.data)
    return 0


def nesting_order(circuits, registry, held=None) -> list[int]:
    """The positions of ``circuits`` in the order to fit them: a model after every model nested
    in it (`comparison.nested_as_held`, ``held``: each model's parameters held by ``--fix``, name
    → value; each contains more of the others than any model nested in it does), the order given
    among the rest. A held parameter the reduction needs breaks the nesting, as the comparison
    judges it (``--fix L1=3u``: R0 + R1 || CPE1 + L1 no longer contains R0 + R1 || C1, though its
    circuit does)."""
    contained = [sum(j != i and _nested(j, i, circuits, registry, held) for j in range(len(circuits))) for i in range(len(circuits))]
    return sorted(range(len(circuits)), key=lambda i: (contained[i], i))


def largest_contained(i: int, circuits, fits, registry, held=None) -> int | None:
    """Of the models already fitted (``fits[j]`` not None), the one with the most parameters
    that model ``i`` contains with the parameters each holds (``held``, `nesting_order`; a W
    where it has a Wo, an element fewer), or None: model ``i`` also starts from its optimum. On
    the 130 REAL battery cycles the Wo model fitted from its default starts ended above the W
    model's χ² on 58 cycles (up to 1.40×), though a Wo at τ → ∞ is that W."""
    nested = [j for j, f in enumerate(fits) if f is not None and j != i and _nested(j, i, circuits, registry, held)]
    return max(nested, key=lambda j: (len(circuits[j].parameter_names(registry)), -j)) if nested else None


def _nested(j: int, i: int, circuits, registry, held) -> bool:
    """Whether model ``j`` is nested in model ``i`` with the parameters each holds (``held``:
    one mapping per model, or None for none), by the comparison's rule (`nested_as_held`)."""
    from ..fitting.comparison import nested_as_held

    held = held or [{}] * len(circuits)
    return nested_as_held(circuits[j], held[j] or {}, circuits[i], held[i] or {}, registry)


OUT_SUFFIXES = (".csv", ".json")
BATCH_OUT_SUFFIXES = (".nc",)  # (a comparison over several spectra only: `BatchComparison.from_xarray` reads it back)


def out_path(path: str | None, several: bool = True) -> str | None:
    """``--out``: a FILE whose extension is not .csv or .json (or .nc, for a comparison over
    several spectra: ``several``) is refused before any fit (`DataError`, exit 2); None and ``-``
    (the JSON to standard output) pass as given."""
    from pathlib import Path

    from ..errors import DataError
    from ..io.atomic import check_file_name

    if path is None or path == "-" or not path.strip():
        return path  # (`plan_outputs` says "empty file name")
    check_file_name(path, "compare.csv", "--out")
    suffix = Path(path).suffix.lower()
    if suffix in BATCH_OUT_SUFFIXES and not several:
        raise DataError(f"--out: {suffix} is for a comparison over several spectra (a file of several, or a --select leaving several); for one spectrum use .csv (one row per model) or .json (the --json document)", path=path)
    if suffix not in (*OUT_SUFFIXES, *BATCH_OUT_SUFFIXES):
        raise DataError(f"--out: unknown extension {suffix or '(none)'!r} for a comparison; use .csv (one row per model) or .json (the --json document), or .nc over several spectra", path=path)
    return path


def refuse_same_circuits(texts, circuits, registry=None) -> None:
    """`ParameterError` (before any fitting) when two ``--model`` give one circuit: the same
    canonical text (``str(parse(m))``), or the same `Circuit.structure_key` under other element names.
    Both would fit alike and split the Akaike weight between them (0.5/0.5)."""
    from ..errors import ParameterError

    key_registry = () if registry is None else (registry,)
    for j in range(len(circuits)):
        for i in range(j):
            a, b = texts[i], texts[j]
            if str(circuits[i]) == str(circuits[j]):
                same = f"--model {a!r} is given twice" + ("" if a == b else f" (again as {b!r})")
                raise ParameterError(f"{same}; compare needs different circuits")
            if circuits[i].structure_key(*key_registry) == circuits[j].structure_key(*key_registry):
                raise ParameterError(
                    f"--model {a!r} and --model {b!r} are the same circuit (the same elements connected alike, under other names); "
                    "they would fit alike and split the Akaike weight: compare needs different circuits"
                )


WARNINGS_SHOWN = 8  # warnings listed per model under the table (--json has them all)


def warning_lines(comparison) -> list[str]:
    """Each model's warnings under the comparison's table (the JSON's ``warnings`` of each
    model): the model, then one indented line per warning; none when no model has any. A
    warning every model has (the data's own Kramers–Kronig misfit, quoted alike for each) is
    listed once, under "every model"."""
    from .common import command_line_words

    common, own_of = comparison.warnings_by_model()
    lines = []
    if common:
        lines.append(f"  every model: {len(common)} warning(s)")
        lines += [f"    - {command_line_words(w, 'compare')}" for w in common]
    for i, (r, own) in enumerate(zip(comparison.fits, own_of)):
        if not own:
            continue
        best = " (best by AIC)" if i == comparison.best_index else ""
        lines.append(f"  {r.model}{best}: {len(own)} warning(s)" + (" besides those of every model" if common else ""))
        lines += [f"    - {command_line_words(w, 'compare')}" for w in own[:WARNINGS_SHOWN]]
        if len(own) > WARNINGS_SHOWN:
            lines.append(f"    ... and {len(own) - WARNINGS_SHOWN} more (--json lists them all)")
    return ["", "warnings:", *lines] if lines else []
