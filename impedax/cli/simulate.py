"""``impedax simulate MODEL --param NAME=VALUE ...``: a model's spectrum as CSV."""

from __future__ import annotations

import sys

import numpy as np

from .common import (JSON_SUMMARY_HELP, data_help, add_model_argument, add_select_option, append_title_line, check_band_options, add_quiet_option, add_output_options, check_json_with_spectrum_out, check_memory, check_points, command_provenance, emit_json, figure_options, figure_writer,
                     load_selected, model_and_values, number_option, paper_circuit, paper_model, plan_outputs, spectrum_summary, spectrum_writer)
from .common import PAPER_MODELS as PAPER_MODELS  # (the names MODEL takes in every command: `common.paper_model`)

DEFAULT_FMIN, DEFAULT_FMAX = 1.0, 1e6  # Hz: the band without --fmin, --fmax (or --frequencies)

# memory per frequency while simulating and writing CSV: the frequencies, the complex impedance
# and JAX's intermediates, and the CSV text with its line list (measured about 0.4 kB)
POINT_BYTES = 1024

#: The longest circuit text `--plot` writes in its legends; a longer one, which would run past
#: the half-width |Z| panel, is named there "model" (the figure's title names it whole, and a
#: ``--title`` is followed by it).
LEGEND_MODEL_CHARS = 40

def register(sub) -> None:
    p = sub.add_parser("simulate", help="write a model's spectrum as CSV", description=("Evaluate MODEL (a circuit, or a paper's model by name: meyer, meyer-cpe, "
                                "Meyer's finger-on-screen circuit with the thesis's eq 3.13 values as defaults) at log-spaced frequencies (both ends included; or at a spectrum file's own, --frequencies FILE) and write frequency_hz,z_real_ohm,z_imag_ohm: "
                                "those three columns on standard output; a --out FILE.csv adds the provenance columns after them (impedax_version, "
                                "written_utc, command, source, data_files, then setting_* for each option: docs/io.md, \"Provenance\"); "
                                "impedax reads the file back as a spectrum."))
    add_model_argument(p, positional=True)
    p.set_defaults(circuit_model=False)  # (run reads another notation itself, after a paper model's name: meyer-cpe is no impedance.py series)
    p.add_argument("--param", action="append", metavar="NAME=VALUE", help="parameter value; several after one --param (--param R0=10 C1=1u) or --param repeated; unspecified ones take their defaults")
    p.add_argument("--fmin", type=number_option, default=None, help=f"lowest frequency [Hz] (default {DEFAULT_FMIN:g})")
    p.add_argument("--fmax", type=number_option, default=None, help=f"highest frequency [Hz] (default {DEFAULT_FMAX:g})")
    p.add_argument("--points", type=int, default=None, help="number of frequencies (default 61; 1 when --fmin equals --fmax)")
    p.add_argument("--frequencies", metavar="FILE", default=None,
                   help=data_help("evaluate at the frequencies of spectrum FILE (any format impedax reads, e.g. a measurement; in its order, "
                                  "each value as read) in place of --fmin/--fmax/--points"))
    add_select_option(p, several=True)  # (with --frequencies: a file of sweeps on different grids is read one sweep alone)
    add_output_options(p, json=JSON_SUMMARY_HELP + " (needs --out FILE): written, model, parameters, parameter_units, defaulted, frequencies, ...", plot="also save Nyquist/Bode plots", out="output file (.csv or .nc); stdout when omitted or '-'", out_metavar="FILE.csv")
    add_quiet_option(p)  # (every command takes --quiet, so a pipeline can pass it to each)
    p.set_defaults(run=run)


def run(args) -> int:
    from .. import make_spectrum
    from ..circuits import compile_circuit
    from ..data import log_frequencies
    from ..errors import ParameterError
    from ..io import write_csv

    paper, paper_values = paper_model(args.model)
    if paper is not None:
        args.model = paper_circuit(paper)
    else:
        from .common import read_impedance_py_model

        args.circuit_model = True
        read_impedance_py_model(args, "simulate")
    circuit, specs, given = model_and_values(args.model, args.param, "--param", args.registry, paper=paper)
    check_json_with_spectrum_out(args.json, args.out, "simulate")
    outputs = plan_outputs([("--out", args.out, "spectrum"), ("--plot", args.plot, "figure")], inputs=[args.frequencies] if args.frequencies else (),
                           stdout="--json" if args.json else None)
    if args.frequencies is not None:
        band = [flag for flag, value in (("--fmin", args.fmin), ("--fmax", args.fmax), ("--points", args.points)) if value is not None]
        if band:
            raise ParameterError(f"{', '.join(band)}: give either --frequencies FILE (its frequencies) or --fmin/--fmax/--points (a log-spaced band), not both")
        freq = load_selected(args.frequencies, args.select, readers=args.readers)["frequency"].values.astype(float)
        points = freq.size
    else:
        if args.select:
            raise ParameterError("--select picks spectra of the --frequencies FILE; without --frequencies there is none to pick from")
        args.fmin = DEFAULT_FMIN if args.fmin is None else args.fmin
        args.fmax = DEFAULT_FMAX if args.fmax is None else args.fmax
        check_band_options(args.fmin, args.fmax)  # (the option named: log_frequencies' message named none)
        points = check_points(args.points, args.fmin, args.fmax, default=61)
        check_memory("--points", points * POINT_BYTES, f"a spectrum of {points} frequencies")
        freq = log_frequencies(args.fmin, args.fmax, points)
    params = {**circuit.defaults(args.registry), **paper_values, **given}
    defaulted = [n for n in specs if n not in given]
    fn = compile_circuit(circuit, args.registry)
    z = np.asarray(fn(params, freq))
    bad = np.flatnonzero(~np.isfinite(z))
    if bad.size:
        raise ParameterError(f"the model's impedance is not finite (overflow) at {freq[bad[0]]:g} Hz and {bad.size - 1} other frequencies; check the parameter values ({', '.join(f'{n}={params[n]:g}' for n in specs)})")
    attrs = {"model": str(circuit), "synthetic": "simulated by impedax simulate", **({"paper_model": paper} if paper else {})}
    ds = make_spectrum(freq, z, attrs=attrs, source="impedax simulate")
    text = str(circuit)
    in_legend = len(text) <= LEGEND_MODEL_CHARS

    def figure():
        from ..plotting import dense_model, plot_spectrum, wrap_model

        # (drawn on a dense grid over the band, as a fit's model: 61 points over 7 decades drew arcs as chords)
        fig = plot_spectrum(model=dense_model(freq, z, lambda grid: np.asarray(fn(params, grid))), model_label=text if in_legend else "model")
        append_title_line(fig, text, wrap_model)  # (the title: the circuit, wrapped to the figure's width)
        return fig

    # (no data file made it but --frequencies', whose frequencies it takes)
    record = command_provenance(args, points_used=points, params_used=params, **({"data_files": [args.frequencies]} if args.frequencies else {}))
    # (a --title in place of the circuit keeps it on the next line when no legend names it)
    plot = figure_writer(figure, **figure_options(args), subtitle=None if in_legend else text)
    written = outputs.save({"--out": spectrum_writer(lambda: ds, record, args.out), "--plot": plot})
    if args.json:  # (what a pipeline reads of the run; docs/robustness.md, "JSON for programs")
        emit_json({"command": "simulate", "written": [p for p in written if p != "-"], "model": str(circuit), "parameters": {n: float(params[n]) for n in specs},
                   "parameter_units": {n: specs[n].unit for n in specs}, "defaulted": defaulted, **({"paper_model": paper} if paper else {}), **spectrum_summary(ds), "provenance": record})
    elif not args.out:
        sys.stdout.write(write_csv(ds))
    if defaulted:  # (said once the spectrum is out: not before an error)
        from ..data import format_bound

        # (each with its unit in SI prefixes, as format_bound writes a value exactly: C1 = 1 µF, not C1=1e-06)
        values = ", ".join(f"{n} = {format_bound(float(params[n]), specs[n].unit)}" for n in defaulted)
        if paper:
            print(f"impedax simulate: {paper} is {circuit} with the thesis's eq 3.13 values: {values}", file=sys.stderr)
        else:
            print(f"impedax simulate: defaults used for {values}", file=sys.stderr)
    return 0
