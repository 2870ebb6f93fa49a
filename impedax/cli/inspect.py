"""``impedax inspect FILE [--json] [--out FILE.csv|.nc] [--plot FILE]``: what impedax reads
from a spectrum file and how — the format recognised, the sign convention and units applied,
rows skipped (and why), how a header-less table was interpreted — with an optional Nyquist/Bode
preview."""

from __future__ import annotations

# what a file saved from data built in Python (``attrs["saved_from"]`` the marker `IN_MEMORY`,
# "memory") is said to come from (the REAL benchmarks/data/autoeis_battery_130.nc would
# otherwise show "saved_from: memory")
_SAVED_IN_SESSION = "data built in a Python session (impedax.make_spectrum), not read from a file"

_HOW_KEYS = ("sign_convention", "units", "sweeps", "interpretation", "phase_unit_note", "polar_columns_note", "decimal_mark", "point_count_note",
             "frequency_plan_note")
# attrs that repeat a line printed under another key (the flipped phase column is named in the
# polar-columns note): kept in the JSON's "attrs", not listed again in the text
_SAID_IN_ANOTHER_LINE = ("polar_columns_flipped_phase",)


def register(sub) -> None:
    from .common import add_quiet_option

    from .common import add_output_options, add_select_option, data_help

    p = sub.add_parser(
        "inspect",
        help="show what impedax reads from a spectrum file, and how",
        description="Read FILE (any format impedax knows: see docs/io.md) and say what was read and how: format, sign "
        "convention, units, skipped rows. --out converts it to canonical CSV or netCDF; --plot writes a Nyquist/Bode preview.",
    )
    p.add_argument("file", metavar="FILE", help=data_help("spectrum file"))
    add_select_option(p)
    add_output_options(p, json="machine-readable output", plot="write a Nyquist and Bode preview of the data", out="also save the spectrum in impedax's canonical form; '-' the CSV to standard output", out_metavar="FILE.csv|.nc")
    add_quiet_option(p)  # (every command takes --quiet, so a pipeline can pass it to each)
    p.set_defaults(run=run)


def run(args) -> int:
    import numpy as np

    from ..data import format_frequency
    from ..errors import IN_MEMORY, DataError
    from ..io.loader import NETCDF_SUFFIXES
    from ..io.netcdf import RESULT_KINDS, result_kind
    from .common import Output, command_provenance, data_source, dimension_labels, emit_json, figure_options, figure_writer, labels_text, load_selected, plan_outputs, spectrum_writer, with_source

    outputs = plan_outputs([("--out", args.out, "spectrum"), ("--plot", args.plot, "figure")], inputs=[args.file], stdout="--json" if args.json else None)
    ds = load_selected(args.file, args.select, warn=False, readers=args.readers)  # (its report shows the notes)
    extra = [d for d in ds["Z"].dims if d != "frequency"]
    if args.out and extra and Output("--out", args.out, "spectrum").suffix().lower() not in NETCDF_SUFFIXES:
        n = " × ".join(str(ds.sizes[d]) for d in extra)
        picked = _picked_dims(ds)
        holder = "the selection" if picked else args.file
        first = dimension_labels(ds, extra[0])[0]
        pick = f"select one label, e.g. --select {extra[0]}={first}" if extra[0] in picked else f"pick one with --select {extra[0]}=LABEL"
        raise DataError(f"--out: a CSV file holds one spectrum, and {holder} holds {n} over {', '.join(extra)}: give --out a .nc name, or {pick}", path=args.out)
    freq = ds["frequency"].values
    z = ds["Z"].values
    kind = result_kind(ds)
    skipped = [str(s) for s in ds.attrs.get("skipped_rows", [])]
    summary = {
        "file": str(ds.attrs.get("path", args.file)) if args.file == "-" else str(args.file),
        "format": ds.attrs.get("format", "netCDF"),
        "data_format": ds.attrs.get("data_format"),  # (for a netCDF file, the format its data were first read from, else null)
        "dims": {k: int(v) for k, v in ds["Z"].sizes.items()},
        "points": int(freq.size),  # (the frequencies, of each spectrum)
        # the impedance points held over every spectrum: `points` × the spectra along the other
        # dimensions (a table of 3 sweeps of 5 frequencies: 15 rows), `points` for one spectrum
        "rows": int(z.size),
        "frequency_min_hz": float(freq.min()),
        "frequency_max_hz": float(freq.max()),
        "z_abs_min_ohm": float(np.abs(z).min()),
        "z_abs_max_ohm": float(np.abs(z).max()),
        "has_sigma": "sigma" in ds,
        "sign_convention": str(ds.attrs.get("sign_convention", "impedax data model: Z = Z' + jZ''")),
        # (a saved result's own ``units`` are its parameters': its spectrum is in Hz and ohm)
        "units": "Hz, ohm" if kind else str(ds.attrs.get("units", "Hz, ohm")),
        # each column used by its role (frequency, z_real, z_imag or z_modulus
        # and z_phase, sigma): {"column", "unit", "scale" to Hz/Ω/deg, "negated"}, as the reader
        # recorded it; {} when it recorded none
        "columns": _columns(ds),
        # files stacked into one series whose columns differ (Hz in one, kHz in
        # another: "columns" is {} then): each file's record as "columns" holds it, by file path
        # as in attrs "sources"; {} when the files agree or nothing was stacked
        "columns_by_file": _columns_by_file(ds),
        # files stacked with --common-frequencies: the frequencies [Hz] each file
        # lost, by file path; {} when none was left out or nothing was stacked
        "frequencies_left_out": _frequencies_left_out(ds),
        "skipped_rows": skipped,
        # the labels `--select DIM=LABEL` picks a spectrum by (positions where a dimension has none)
        "labels": {d: dimension_labels(ds, d) for d in extra},
        "attrs": {k: v for k, v in ds.attrs.items() if isinstance(v, (str, int, float, bool))},
        "sign_hint": _sign_hint(ds, extra),
        # points with Re Z < 0 beyond 5 % of |Z| (or the data's sigma), which no passive cell
        # gives, in any spectrum (`passivity.non_passive`); the note as a fit words it,
        # null when none (or when the sign hint says Z' < 0 nearly everywhere)
        **_non_passive(ds, extra),
        # [low, high] Hz of each step of the sorted frequencies at least GAP_RATIO times both
        # steps beside it (log scale): a point skipped; [] when none
        "frequency_gaps_hz": [[lo, hi] for lo, hi, _ in _gaps(freq)],
        # the frequencies [Hz] where Z is exactly 0 (in any spectrum), a point the instrument
        # wrote as 0,0, which the KK test, the DRT and fits weighted by |Z| refuse; [] when none
        "zero_impedance_hz": _zero_frequencies(freq, z),
        # the first and last rows as read, in the file's order (of the first spectrum of several):
        # the values themselves, to set beside the file
        "first_point": _point(ds, extra, 0),
        "last_point": _point(ds, extra, -1),
    }
    if kind:  # a saved result (impedax fit/sample --out FILE.nc): its data are what is shown
        # (read_with: the call that reads it, naming registry= for an element of the user's own)
        summary.update({"result_kind": kind, "result": RESULT_KINDS[kind][0], "parameter_units": _parameter_units(ds), "read_with": _read_with(kind, ds)})
    record = command_provenance(args, source=data_source(ds), data_files=[args.file])
    outputs.save({"--out": spectrum_writer(lambda: ds, record, args.out), "--plot": figure_writer(lambda: _preview(ds, summary["format"], summary["file"]), **figure_options(args))})
    if outputs.uses_stdout:
        return 0
    if args.json:
        emit_json(with_source(summary, data_source(ds), record))
        return 0
    held = f" holding a saved {summary['result']} (its data shown here; read it in full with {summary['read_with']})" if kind else ""
    first = f" (its data first read from {summary['data_format']})" if summary["data_format"] else ""
    print(f"{summary['file']}: {summary['format']}{first}{held}, {_points_text(summary)}, dims {summary['dims']}")
    for key in _HOW_KEYS:
        if key in ds.attrs or key in ("sign_convention", "units"):
            print(f"  {key.replace('_', ' ')}:{_per_spectrum(summary[key] if key in summary else ds.attrs[key], ds, extra)}")
    if kind and summary["parameter_units"]:
        print("  parameter units: " + ", ".join(f"{n} [{u}]" for n, u in summary["parameter_units"].items()))
    whose = f" (of the first spectrum, {_first_labels(ds, extra)})" if extra else ""
    print(f"  as read{whose}: first point {_point_text(summary['first_point'])}; last point {_point_text(summary['last_point'])}")
    if summary["has_sigma"]:
        sigma = ds["sigma"].values
        source = summary["columns"].get("sigma")
        named = f", from column {source['column']!r}" + ("" if source.get("scale", 1) == 1 else f" ×{source['scale']:g}") if source else ""
        print(f"  sigma: a standard deviation of Z per point, {np.nanmin(sigma):.3g}–{np.nanmax(sigma):.3g} Ω{named} "
              "(fits weight by it with --weighting sigma; diagnose takes it as the noise)")
    picked = _picked_dims(ds)
    for d, labels in summary["labels"].items():
        counted = f"{len(labels)} spectr{'um' if len(labels) == 1 else 'a'} ({labels_text(labels)})"
        print(f"  {d}: {counted}, selected by --select {picked[d]}" if d in picked else f"  {d}: {counted}; pick one with --select {d}=LABEL")
    print("  skipped rows: none" if not skipped else f"  skipped rows ({len(skipped)} range{'' if len(skipped) == 1 else 's'}):")
    for line in skipped[:20]:
        print(f"    {line}")
    if len(skipped) > 20:
        print(f"    ... and {len(skipped) - 20} more")
    for path, frequencies in summary["frequencies_left_out"].items():
        print(f"  left out of {path} by the stack (not in every file): {labels_text([format_frequency(f) for f in frequencies])}")
    for key, value in summary["attrs"].items():
        # (a dimension's labels are listed above: the reader's text of them would repeat it)
        if key not in ("format", "data_format", "source", "path", *_HOW_KEYS, *_SAID_IN_ANOTHER_LINE) and not (key in extra and _repeats_labels(str(value), key, summary["labels"][key])):
            print(f"  {key}: {_provenance_text(value) if key == 'provenance' else _SAVED_IN_SESSION if key == 'saved_from' and value == IN_MEMORY else str(value).splitlines()[0] if str(value) else ''}")
    gaps = _gaps(freq)
    if gaps:
        print("  frequency gaps: " + "; ".join(f"{format_frequency(lo)}–{format_frequency(hi)} ({text})" for lo, hi, text in gaps))
    if summary["zero_impedance_hz"]:
        print(f"  Z = 0: {_zero_text(summary['zero_impedance_hz'], freq.size)}")
    if summary["non_passive_note"]:
        print(f"  Re Z < 0: {summary['non_passive_note']}")
    if summary["sign_hint"]:
        print(f"  hint: {summary['sign_hint']}")
    if not kind and args.file != "-":
        import argparse

        from .common import fit_command

        # (the file, --select and --plugin of this run; the points where Z = 0 left out, as kk and drt refuse them)
        zero = summary["zero_impedance_hz"]
        run = argparse.Namespace(**{**vars(args), "data": args.file, "exclude": ",".join(f"{f:.6g}" for f in zero) or None})
        print(_next_line(run, ds, every_point_zero=len(zero) == freq.size))
    return 0


def _repeats_labels(text: str, dim: str, labels) -> bool:
    """Whether the attribute ``dim`` says no more than the labels along ``dim`` (a workbook's
    ``sheet A: A; sheet B: B``), which the report lists already. Files stacked along a dimension
    named as one of their attributes (``impedax stack --dim instrument``) keep theirs in the
    report: ``instrument dfr: Metrohm Autolab (FRA); ...``."""
    parts = {f"{dim} {label}: {label}" for label in labels}
    return text in {str(label) for label in labels} or all(part in parts for part in text.split("; "))


def _provenance_text(value) -> str:
    """A saved file's provenance record (JSON text, `impedax.io.provenance`) as one line to read:
    the command, when and by which impedax, its settings given, the data files; the text as it
    is when it is not such a record (``--json`` keeps the JSON itself, ``\\u2026`` escapes and
    nulls included)."""
    import json

    try:
        record = json.loads(str(value))
    except ValueError:
        return str(value).splitlines()[0] if str(value) else ""
    if not isinstance(record, dict):
        return str(value)
    made = ", ".join(str(record[k]) for k in ("command", "written_utc") if record.get(k))
    version = f"impedax {record['impedax_version']}" if record.get("impedax_version") else ""
    settings = record.get("settings") if isinstance(record.get("settings"), dict) else {}
    def shown(v) -> str:
        if isinstance(v, dict):
            return "(" + " ".join(f"{k}={shown(x)}" for k, x in v.items()) + ")"
        if isinstance(v, (list, tuple)):
            return " ".join(shown(x) for x in v)
        return f"{v:g}" if isinstance(v, float) else str(v)

    given = ", ".join(f"{k}={shown(v)}" for k, v in settings.items() if v not in (None, False, [], {}, ""))
    files = record.get("data_files") or []
    parts = [f"{made or 'impedax'}{f' ({version})' if version else ''}", f"settings {given}" if given else "", f"data {', '.join(map(str, files))}" if files else ""]
    return "; ".join(p for p in parts if p)


def _columns(ds) -> dict[str, dict]:
    """The reader's record of the columns it read (``attrs["columns"]``, `impedax.io` readers),
    as JSON values; {} when there is none (a file of several spectra whose columns differ)."""
    return _column_record(ds.attrs.get("columns"))


def _column_record(record) -> dict[str, dict]:
    """A record of columns (role → {"column", "unit", "scale", "negated"}) as JSON values; {}
    for anything else."""
    if not isinstance(record, dict):
        return {}
    return {str(role): {str(k): (v.item() if hasattr(v, "item") else v) for k, v in entry.items()} for role, entry in record.items() if isinstance(entry, dict)}


def _frequencies_left_out(ds) -> dict[str, list[float]]:
    """``attrs["frequencies_left_out"]`` (`impedax.stack_files` with ``common_frequencies``) as
    JSON values: file path → the frequencies [Hz] the stack left out of it."""
    record = ds.attrs.get("frequencies_left_out")
    if not isinstance(record, dict):
        return {}
    return {str(path): [float(f) for f in frequencies] for path, frequencies in record.items() if isinstance(frequencies, (list, tuple))}


def _columns_by_file(ds) -> dict[str, dict[str, dict]]:
    """``attrs["columns_by_file"]`` (`impedax.stack_files`, files whose columns differ) as JSON
    values: file path → that file's record (`_column_record`); {} when there is none."""
    records = ds.attrs.get("columns_by_file")
    if not isinstance(records, dict):
        return {}
    return {str(path): _column_record(record) for path, record in records.items()}


def _point(ds, extra, position: int) -> dict[str, float]:
    """The point at ``position`` of the first spectrum along ``frequency`` (file order), as
    ``{"frequency_hz", "z_real_ohm", "z_imag_ohm"}``."""
    z = ds["Z"].isel({d: 0 for d in extra}).values
    return {"frequency_hz": float(ds["frequency"].values[position]), "z_real_ohm": float(z[position].real), "z_imag_ohm": float(z[position].imag)}


def _point_text(point: dict[str, float]) -> str:
    """``f = 200 kHz: Z' = 1597 Ω, Z'' = -2.14 Ω`` (Z'' with its sign as impedax holds it)."""
    from ..data import format_quantity

    return f"f = {format_quantity(point['frequency_hz'], 'Hz')}: Z' = {point['z_real_ohm']:.6g} Ω, Z'' = {point['z_imag_ohm']:.6g} Ω"


def _first_labels(ds, extra) -> str:
    """``cycle 1, trial a``: the labels of the first spectrum of several."""
    from .common import dimension_labels

    return ", ".join(f"{d} {dimension_labels(ds, d)[0]}" for d in extra)


def _parameter_units(ds) -> dict[str, str]:
    """The units of a saved result's parameters, by name: its ``unit`` coordinate along
    ``param`` (what a fit's ``to_xarray`` stores), else its attrs ``units``, one per ``param``
    (the attrs alone would show ``{}`` for a saved fit)."""
    names = ds["param"].values if "param" in ds.coords else ()
    if "unit" in ds.coords and ds["unit"].dims == ("param",):
        return {str(n): str(u) for n, u in zip(names, ds["unit"].values)}
    units = ds.attrs.get("units")
    if isinstance(units, str) or units is None or len(units) != len(names):
        return {}
    return {str(n): str(u) for n, u in zip(names, units)}


def _foreign_models(ds) -> list[str]:
    """The circuit texts of a saved result (its attrs ``model``, ``*_model``) that the default
    element registry cannot parse: they use an element of the user's own, whose registry the
    reader call needs (``registry=``; ``--plugin FILE.py`` on the command line)."""
    from .. import DEFAULT_REGISTRY, parse
    from ..errors import CircuitSyntaxError

    foreign = []
    for key, text in ds.attrs.items():
        if (key == "model" or key.endswith("_model")) and isinstance(text, str) and text.strip():
            try:
                parse(text, DEFAULT_REGISTRY)
            except CircuitSyntaxError:
                foreign.append(text)
    return foreign


def _points_text(summary: dict) -> str:
    """``21 frequencies 3 kHz–300 kHz, |Z| 148.2 Ω–628.8 Ω`` (frequencies as impedax writes them,
    `format_band`, |Z| with its SI prefix: not "3000–3e+05 Hz", nor for REAL
    exampleDataParstat.txt "10–1e+04 Hz, |Z| 0.0165–0.03349 Ω"); for one point ``1 frequency,
    1 Hz, |Z| 3.606 Ω`` (not "1 frequencies 1–1 Hz, |Z| 3.606–3.606 Ω"); for several spectra
    their rows too, ``…, 15 rows (3 spectra of 5 frequencies)``."""
    from ..data import format_band, format_quantity

    low, high = (format_quantity(summary[k], "Ω", 4) for k in ("z_abs_min_ohm", "z_abs_max_ohm"))
    count = "1 frequency," if summary["points"] == 1 else f"{summary['points']} frequencies"
    spectra = summary["rows"] // summary["points"]
    rows = f", {summary['rows']} rows ({spectra} spectra of {count.rstrip(',')})" if spectra > 1 else ""
    return f"{count} {format_band(summary['frequency_min_hz'], summary['frequency_max_hz'])}, |Z| {low if low == high else f'{low}–{high}'}{rows}"


def _read_with(kind: str, ds) -> str:
    """The call that reads the saved result ``ds`` of ``kind`` in full (`reader_call`), with
    ``registry=`` and the command line's ``--plugin FILE.py`` named when its circuit uses an
    element the default registry lacks (`_foreign_models`)."""
    from ..io.netcdf import reader_call

    call = reader_call(kind)
    foreign = _foreign_models(ds) if call.endswith("(impedax.io.read_netcdf(path))") else []
    if not foreign:
        return call
    return (f"{call[:-1]}, registry=REGISTRY) (its model {foreign[0]!r} uses an element not in the default registry: REGISTRY is the one "
            "that declares it; on the command line, --plugin FILE.py)")


def _picked_dims(ds) -> dict[str, str]:
    """The dimensions a ``--select`` list or range kept, each with its ``DIM=LABELS`` (from the
    data's ``source``, ``path [cycle=3:5, trial=1]``)."""
    source = str(ds.attrs.get("source", ""))
    if not source.endswith("]") or " [" not in source:
        return {}
    items = [item.strip() for item in source.rsplit(" [", 1)[1][:-1].split(", ")]
    extra = [d for d in ds["Z"].dims if d != "frequency"]
    return {d: item for item in items for d in [item.partition("=")[0]] if d in extra}


def _sign_hint(ds, extra) -> str | None:
    """`io.sign_check.negative_real_hint` when Z' < 0 at nearly all points
    (`io.sign_check.negative_real_evidence`), else `io.sign_check.opposite_sign_hint` when
    Z'' > 0 at nearly all points while |Z| falls (`io.sign_check.positive_imaginary_evidence`);
    in how many spectra for a file of several."""
    from ..io.sign_check import imaginary_flipped_too, negative_real_evidence, negative_real_hint, opposite_sign_hint, positive_imaginary_evidence, swapped_evidence

    freq = ds["frequency"].values
    spectra = ds["Z"].transpose(*extra, "frequency").values.reshape(-1, freq.size)

    def counted(found: list[str]) -> str:
        return found[0] if len(spectra) == 1 else f"in {len(found)} of {len(spectra)} spectra, e.g. {found[0]}"

    real = [(e, z) for e, z in ((negative_real_evidence(freq, z), z) for z in spectra) if e]
    if real:
        first_z = real[0][1]
        return negative_real_hint(counted([e for e, _ in real]), imaginary_too=imaginary_flipped_too(freq, first_z), swapped=swapped_evidence(freq, first_z))
    found = [e for e in (positive_imaginary_evidence(freq, z) for z in spectra) if e]
    return opposite_sign_hint(counted(found), ds.attrs) if found else None


#: A step between two neighbouring frequencies (log scale) at least this many times both steps
#: beside it is a gap (`_gaps`): a skipped point doubles a step; a sweep whose density changes has
#: no step larger than both of its neighbours.
GAP_RATIO = 1.8


def _gaps(freq) -> list[tuple[float, float, str]]:
    """(low, high, words) of each gap of the sorted frequencies ``freq`` [Hz] (`GAP_RATIO`), in
    rising order; words: ``0.20 decade, where the steps beside it are 0.10: a point skipped?``.
    None below 5 frequencies."""
    import numpy as np

    grid = np.unique(np.asarray(freq, float))
    if grid.size < 5:
        return []
    steps = np.diff(np.log10(grid))
    beside = np.maximum(np.r_[steps[1], steps[:-1]], np.r_[steps[1:], steps[-2]])  # (the larger neighbour; at an end, the one)
    found = []
    for i in np.flatnonzero(steps >= GAP_RATIO * beside):
        skipped = max(1, round(steps[i] / beside[i]) - 1)
        found.append((float(grid[i]), float(grid[i + 1]), f"{steps[i]:.2f} decade, where the steps beside it are {beside[i]:.2f}: "
                                                          f"{'a point' if skipped == 1 else f'{skipped} points'} skipped?"))
    return found


def _zero_frequencies(freq, z) -> list[float]:
    """The frequencies [Hz], ascending, where Z is exactly 0 in any spectrum of ``z``."""
    import numpy as np

    zero = (np.reshape(z, (-1, freq.size)) == 0).any(axis=0)
    return sorted(float(f) for f in freq[zero])


def _zero_text(zero_hz: list[float], n_points: int) -> str:
    """``at 3.16 Hz: the KK test, the DRT and fits weighted by |Z| refuse it; leave it out with
    --exclude 3.1623`` (the first five), or, at every point, that there is nothing to analyse."""
    from ..data import format_frequency

    if len(zero_hz) == n_points:
        return f"at every one of the {n_points} points: nothing was recorded; no analysis takes it"
    shown = zero_hz[:5]
    where = ", ".join(format_frequency(f) for f in shown) + (f" and {len(zero_hz) - 5} more" if len(zero_hz) > 5 else "")
    them = "it" if len(zero_hz) == 1 else "them"
    return (f"at {where}: the KK test, the DRT and fits weighted by |Z| refuse such a point; leave {them} out with "
            f"--exclude {','.join(f'{f:.6g}' for f in zero_hz)}")


def _non_passive(ds, extra) -> dict:
    """``non_passive_frequencies_hz`` (sorted, of every spectrum) and ``non_passive_note``: the
    points with Re Z < 0 beyond the noise (`passivity.non_passive`: 5 % of |Z|, or the
    data's sigma), in a fit's words (`passivity.non_passive_notes`); in how many spectra for several. None
    and [] when there are none, or when Z' < 0 nearly everywhere (the sign hint says that)."""
    import numpy as np

    from ..passivity import non_passive, non_passive_notes
    from .common import dimension_labels

    freq = ds["frequency"].values
    z = ds["Z"].transpose(*extra, "frequency").values.reshape(-1, freq.size)
    sigma = ds["sigma"].transpose(*extra, "frequency").values.reshape(-1, freq.size) if "sigma" in ds else None
    bad = non_passive(z, sigma)
    if not bad.any() or _sign_hint(ds, extra):
        return {"non_passive_frequencies_hz": [], "non_passive_note": None}
    first = int(np.flatnonzero(bad.any(axis=1))[0])
    note = non_passive_notes(freq, z[first], None if sigma is None else sigma[first])[0]
    if len(z) > 1:
        labels = [f"{d} {dimension_labels(ds, d)[i]}" for d, i in zip(extra, np.unravel_index(first, [ds.sizes[d] for d in extra]))]
        note = f"in {int(bad.any(axis=1).sum())} of {len(z)} spectra; {', '.join(labels)}: {note}"
    return {"non_passive_frequencies_hz": sorted(float(f) for f in freq[bad.any(axis=0)]), "non_passive_note": note}


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


# most spectra the preview of a file of several draws (evenly spread over them, the title says which)
PREVIEW_SPECTRA = 10


def _preview(ds, fmt, name: str | None = None):
    """Nyquist and Bode figure of the spectrum, or of the spectra of a file of several (up to
    `PREVIEW_SPECTRA`, evenly spread, coloured in order and named by their labels), titled with
    the file's name (``name``, the file as the command was given it, ``<stdin>`` for ``-``: not
    every reader records a path; without it the reader's ``path``), the selection, if any, and
    the format, wrapped to the figure's width."""
    import math

    import numpy as np

    from ..plotting import characters_across, plot_spectra, plot_spectrum, wrap_model
    from .common import dimension_labels, literal_text, short_source

    name = name if name is not None else str(ds.attrs.get("path", ""))
    source = str(ds.attrs.get("source", ""))
    shown = short_source(source) if "[" in source else short_source(name) if name else ""  # (a --select pick: its labels)
    head = f"{literal_text(shown)}: {fmt}" if shown else str(fmt)
    width = characters_across(11.0 - 0.4, 12)
    extra = [d for d in ds["Z"].dims if d != "frequency"]
    if not extra:
        return plot_spectrum(ds, title=wrap_model(head, width), data_label="data")
    n = math.prod(ds.sizes[d] for d in extra)
    stacked = ds["Z"].stack(_spectrum=extra).transpose("_spectrum", "frequency")
    positions = np.unique(np.linspace(0, n - 1, min(n, PREVIEW_SPECTRA)).round().astype(int))
    grid = np.indices([ds.sizes[d] for d in extra]).reshape(len(extra), -1).T
    labels = [", ".join(str(dimension_labels(ds, d)[k]) for d, k in zip(extra, grid[i])) for i in positions]
    freq = ds["frequency"].values
    spectra = [(freq, stacked.values[i]) for i in positions]
    drawn = f"{n} spectr{'um' if n == 1 else 'a'}" if len(positions) == n else f"{len(positions)} of {n} spectra, evenly spread (pick others with --select)"
    return plot_spectra(spectra, labels, title=wrap_model(f"{head} — {drawn}", width), legend_title=", ".join(extra))


def _next_line(run, data, *, every_point_zero: bool = False) -> str:
    """The report's last line: what to run next on these points. ``impedax kk`` then ``impedax
    drt``; on fewer points than the DRT takes (`DRT_POINTS_MIN`), a fit of at most 2N real
    parameters, not ``impedax kk`` (1 point is too few for it); below `CONCLUSIVE_POINTS_MIN`
    the KK test's verdict is inconclusive, and the line says so."""
    from ..constants import CONCLUSIVE_POINTS_MIN, DRT_POINTS_MIN
    from .common import fit_command

    n = int(data.sizes["frequency"])
    if every_point_zero:
        return "next: nothing to analyse: Z is 0 at every point; measure again"
    kk, drt, fit = (fit_command(run, data=data, program=f"impedax {name}") for name in ("kk", "drt", "fit"))
    if n < DRT_POINTS_MIN:
        return (f"next: {n} frequenc{'y is' if n == 1 else 'ies are'} too few for impedax kk (a verdict needs {CONCLUSIVE_POINTS_MIN}) and impedax drt "
                f"(it needs {DRT_POINTS_MIN}): measure more frequencies, or fit a circuit of at most {2 * n} parameters (2 real numbers a point): "
                f"{fit} --model {'R0' if n == 1 else repr('R0 + C1') if n == 2 else repr('R0 + R1 || C1')}")
    few = f" (with {n} frequencies its verdict is inconclusive: it needs {CONCLUSIVE_POINTS_MIN})" if n < CONCLUSIVE_POINTS_MIN else ""
    return f"next: {kk} (are the data themselves sound?){few}, then {drt} (how many arcs; it ends with a starting circuit to fit)"
