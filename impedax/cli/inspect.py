"""``impedax inspect FILE [--json] [--out FILE.csv|nc] [--plot FILE.png]``: what impedax reads
from a spectrum file and how — the format recognised, the sign convention and units applied,
rows skipped (and why), how a header-less table was interpreted — with an optional Nyquist/Bode
preview."""

from __future__ import annotations

_HOW_KEYS = ("sign_convention", "units", "sweeps", "interpretation", "phase_unit_note", "decimal_mark", "point_count_note")


def register(sub) -> None:
    from .common import add_output_options, add_select_option

    p = sub.add_parser(
        "inspect",
        help="show what impedax reads from a spectrum file, and how",
        description="Read FILE (any format impedax knows: see docs/io.md) and say what was read and how: format, sign "
        "convention, units, skipped rows. --out converts it to canonical CSV or netCDF; --plot writes a Nyquist/Bode preview.",
    )
    p.add_argument("file", metavar="FILE", help="spectrum file")
    add_select_option(p)
    add_output_options(p, json="machine-readable output", plot="write a Nyquist and Bode preview of the data", out="also save the spectrum in impedax's canonical form", out_metavar="FILE.csv|nc")
    p.set_defaults(run=run)


def run(args) -> int:
    import numpy as np

    from ..errors import DataError
    from ..io.loader import NETCDF_SUFFIXES
    from .common import Output, dimension_labels, emit_json, figure_writer, labels_text, load_selected, plan_outputs, spectrum_writer

    outputs = plan_outputs([("--out", args.out, "spectrum"), ("--plot", args.plot, "figure")], inputs=[args.file], stdout="--json" if args.json else None)
    ds = load_selected(args.file, args.select, warn=False)  # (its report shows the notes)
    extra = [d for d in ds["Z"].dims if d != "frequency"]
    if args.out and extra and Output("--out", args.out, "spectrum").suffix().lower() not in NETCDF_SUFFIXES:
        n = " × ".join(str(ds.sizes[d]) for d in extra)
        raise DataError(
            f"--out: a CSV file holds one spectrum, and {args.file} holds {n} over {', '.join(extra)}: "
            f"give --out a .nc name, or pick one with --select {extra[0]}=LABEL", path=args.out,
        )
    freq = ds["frequency"].values
    z = ds["Z"].values
    skipped = [str(s) for s in ds.attrs.get("skipped_rows", [])]
    summary = {
        "file": str(ds.attrs.get("path", args.file)) if args.file == "-" else str(args.file),
        "format": ds.attrs.get("format", "netCDF"),
        "dims": {k: int(v) for k, v in ds["Z"].sizes.items()},
        "points": int(freq.size),
        "frequency_min_hz": float(freq.min()),
        "frequency_max_hz": float(freq.max()),
        "z_abs_min_ohm": float(np.abs(z).min()),
        "z_abs_max_ohm": float(np.abs(z).max()),
        "has_sigma": "sigma" in ds,
        "sign_convention": str(ds.attrs.get("sign_convention", "impedax data model: Z = Z' + jZ''")),
        "units": str(ds.attrs.get("units", "Hz, ohm")),
        "skipped_rows": skipped,
        # the labels `--select DIM=LABEL` picks a spectrum by (positions where a dimension has none)
        "labels": {d: dimension_labels(ds, d) for d in extra},
        "attrs": {k: v for k, v in ds.attrs.items() if isinstance(v, (str, int, float, bool))},
        "sign_hint": _sign_hint(ds, extra),
    }
    outputs.save({"--out": spectrum_writer(lambda: ds), "--plot": figure_writer(lambda: _preview(ds, summary["format"], summary["file"]))})
    if outputs.uses_stdout:
        return 0
    if args.json:
        emit_json(summary)
        return 0
    print(f"{summary['file']}: {summary['format']}, {summary['points']} frequencies "
          f"{summary['frequency_min_hz']:.4g}–{summary['frequency_max_hz']:.4g} Hz, "
          f"|Z| {summary['z_abs_min_ohm']:.4g}–{summary['z_abs_max_ohm']:.4g} Ω, dims {summary['dims']}")
    for key in _HOW_KEYS:
        if key in ds.attrs or key in ("sign_convention", "units"):
            print(f"  {key.replace('_', ' ')}:{_per_spectrum(summary[key] if key in summary else ds.attrs[key], ds, extra)}")
    if summary["has_sigma"]:
        sigma = ds["sigma"].values
        print(f"  sigma: a standard deviation of Z per point, {np.nanmin(sigma):.3g}–{np.nanmax(sigma):.3g} Ω "
              "(fits weight by it with --weighting sigma; diagnose takes it as the noise)")
    for d, labels in summary["labels"].items():
        print(f"  {d}: {len(labels)} spectra ({labels_text(labels)}); pick one with --select {d}=LABEL")
    print("  skipped rows: none" if not skipped else f"  skipped rows ({len(skipped)} range{'' if len(skipped) == 1 else 's'}):")
    for line in skipped[:20]:
        print(f"    {line}")
    if len(skipped) > 20:
        print(f"    ... and {len(skipped) - 20} more")
    for key, value in summary["attrs"].items():
        # (a dimension's labels are listed above: the reader's text of them would repeat it)
        if key not in ("format", "source", "path", *_HOW_KEYS, *extra):
            print(f"  {key}: {str(value).splitlines()[0] if str(value) else ''}")
    if summary["sign_hint"]:
        print(f"  hint: {summary['sign_hint']}")
    return 0


def _sign_hint(ds, extra) -> str | None:
    """`io.sign_check.negative_real_hint` when Z' < 0 at nearly all points
    (`io.sign_check.negative_real_evidence`), else `io.sign_check.opposite_sign_hint` when
    Z'' > 0 at nearly all points while |Z| falls (`io.sign_check.positive_imaginary_evidence`);
    in how many spectra for a file of several."""
    from ..io.sign_check import negative_real_evidence, negative_real_hint, opposite_sign_hint, positive_imaginary_evidence

    freq = ds["frequency"].values
    spectra = ds["Z"].transpose(*extra, "frequency").values.reshape(-1, freq.size)

    def counted(found: list[str]) -> str:
        return found[0] if len(spectra) == 1 else f"in {len(found)} of {len(spectra)} spectra, e.g. {found[0]}"

    real = [(e, z) for e, z in ((negative_real_evidence(freq, z), z) for z in spectra) if e]
    if real:
        first_z = real[0][1]
        return negative_real_hint(counted([e for e, _ in real]), imaginary_too=positive_imaginary_evidence(freq, first_z) is not None)
    found = [e for e in (positive_imaginary_evidence(freq, z) for z in spectra) if e]
    return opposite_sign_hint(counted(found), ds.attrs) if found else None


def _per_spectrum(text: str, ds, extra) -> str:
    """`` text`` as read, or, when the reader joined each spectrum's own text along the only
    extra dimension (``sheet A: ...; sheet B: ...``), one indented line per spectrum."""
    from .common import dimension_labels, part_of_joined

    if len(extra) != 1:
        return " " + text
    labels = [str(v) for v in dimension_labels(ds, extra[0])]
    prefixes = [f"{extra[0]} {label}: " for label in labels]
    parts = [part_of_joined(text, prefixes, i) for i in range(len(labels))]
    if any(p is None for p in parts):
        return " " + text
    return "".join(f"\n    {prefix}{part}" for prefix, part in zip(prefixes, parts))


def _preview(ds, fmt, name: str | None = None):
    """Nyquist and Bode figure of the spectrum (the first one when the file holds several),
    titled with ``name``, the file as the command was given it (``<stdin>`` for ``-``): not
    every reader records a path in the data (the netCDF reader does not). Without ``name``,
    the reader's ``path``, if any."""
    import math

    from ..plotting import plot_spectrum
    from .common import dimension_labels

    name = name if name is not None else str(ds.attrs.get("path", ""))
    first = ds
    note = ""
    extra = [d for d in ds["Z"].dims if d != "frequency"]
    if extra:
        first = ds.isel({d: 0 for d in extra})
        n = math.prod(ds.sizes[d] for d in extra)
        label = ", ".join(f"{d}={dimension_labels(ds, d)[0]}" for d in extra)
        note = f" — {label}, the first of {n} spectra (pick another with --select)"
    elif "[" in str(ds.attrs.get("source", "")):  # a --select pick: its labels
        note = " — " + str(ds.attrs["source"]).rsplit("[", 1)[1].rstrip("]")
    return plot_spectrum(first, title=f"{name}: {fmt}{note}" if name else f"{fmt}{note}", data_label="data")
