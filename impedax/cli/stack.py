"""``impedax stack FILE [FILE ...] [--dim NAME] [--coords V1 V2 ...] --out OUT.nc``: one
spectrum per file (day01.csv … day10.csv), or files of spectra over the same dimensions, as one
netCDF over a new dimension, which ``impedax fit OUT.nc --model ...`` fits as a batch
(`impedax.io.stack_files`)."""

from __future__ import annotations

import sys


def register(sub) -> None:
    from .common import add_quiet_option

    from .common import JSON_SUMMARY_HELP, data_help

    p = sub.add_parser(
        "stack",
        help="several files of one spectrum each as one series (a new dimension) in a netCDF file",
        description="Read each FILE (any format impedax knows; one spectrum each) and write them as one netCDF file with Z over "
        "(NAME, frequency), in the order given, which impedax fit, kk and drt then analyse as a batch. Files that each hold "
        "spectra over the same dimensions (per-material files over voltage) give Z over (NAME, those dimensions, frequency), "
        "the spectra lined up by their labels. The files must share "
        "one frequency grid (within 0.1 %), or, with --common-frequencies, the frequencies every file has are kept and the rest left out. Labels along NAME: --coords, else the file names without extension.",
    )
    p.add_argument("files", nargs="+", metavar="FILE", help=data_help("spectrum files, one spectrum each (or each over the same dimensions), in the order of the series"))
    p.add_argument("--dim", default="file", metavar="NAME", help="name of the new dimension (default: file), e.g. day: an ASCII letter, then letters, digits, _, - and .; no Python keyword, nan or inf")
    p.add_argument("--coords", nargs="+", metavar="V", help="one label per FILE, in order: numbers when every one reads as a number (1 2 3, 0.5 1.5), else text; default: the file names without extension (day01)")
    p.add_argument("--common-frequencies", action="store_true",
                   help="files whose grids differ (a point skipped in one sweep): keep the frequencies every file has (within 0.1 %%) and leave out the rest, "
                   "naming them; measured points only, nothing interpolated; a file that would keep under half its points is refused")
    p.add_argument("--out", required=True, metavar="OUT.nc", help="the stacked spectra (netCDF: .nc, .nc4, .cdf); written whole or not at all")
    p.add_argument("--json", action="store_true", help=JSON_SUMMARY_HELP + ": written, files, dim, labels, dims, spectra, frequencies, ...")
    add_quiet_option(p)  # (every command takes --quiet, so a pipeline can pass it to each)
    p.set_defaults(run=run)


def run(args) -> int:
    from pathlib import Path

    from ..data import counted, format_frequency
    from ..errors import DataError
    from ..io.atomic import check_file_name
    from ..io.loader import NETCDF_SUFFIXES
    from ..io.stack import check_dimension_name, stack_files
    from .common import command_provenance, data_source, emit_json, labels_text, plan_outputs, spectrum_summary, spectrum_writer, with_source

    check_dimension_name(args.dim)  # (before --out is planned; stack_files' own check, one message in Python and here)
    check_file_name(args.out, "series.nc", "--out")
    if Path(args.out).suffix.lower() not in NETCDF_SUFFIXES:
        raise DataError(f"--out: a stack of spectra is written as netCDF: give a {', '.join(NETCDF_SUFFIXES)} name (a CSV file holds one spectrum)", path=args.out)
    outputs = plan_outputs([("--out", args.out, "spectrum")], inputs=args.files)
    stacked = stack_files(args.files, dim=args.dim, coords=args.coords, readers=args.readers, common_frequencies=args.common_frequencies)
    left_out = stacked.attrs.get("frequencies_left_out", {})
    for path, frequencies in left_out.items():
        print(f"note: {path}: {counted(len(frequencies), 'frequency', 'frequencies')} not in every file left out ({labels_text([format_frequency(f) for f in frequencies])})", file=sys.stderr)
    record = command_provenance(args, source=data_source(stacked), data_files=args.files)
    written = outputs.save({"--out": spectrum_writer(lambda: stacked, record)})
    labels = stacked[args.dim].values.tolist()
    if args.json:  # (what a pipeline reads of the run; docs/robustness.md, "JSON for programs")
        emit_json(with_source({"command": "stack", "written": list(written), "files": [str(f) for f in args.files], "dim": args.dim, "labels": labels, **spectrum_summary(stacked),
                               "frequencies_left_out": left_out},
                              data_source(stacked), record))
        return 0
    shown = ", ".join(map(str, labels)) if len(labels) <= 6 else f"{', '.join(map(str, labels[:3]))}, …, {labels[-1]}"
    others = [d for d in stacked["Z"].dims if d not in (args.dim, "frequency")]  # (the files' own dimensions, each file over them)
    n = stacked["Z"].size // stacked.sizes["frequency"]
    over = f" × {' × '.join(f'{d} ({stacked.sizes[d]})' for d in others)}" if others else ""
    print(f"impedax stack: {counted(n, 'spectrum', 'spectra')} at {stacked.sizes['frequency']} frequencies along {args.dim!r} ({shown}){over}; "
          f"fit them as a batch: impedax fit {args.out} --model MODEL", file=sys.stderr)
    return 0
