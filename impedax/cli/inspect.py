"""``impedax inspect FILE [--json] [--out FILE.csv|nc]``: what impedax reads from a spectrum file."""

from __future__ import annotations


def register(sub) -> None:
    p = sub.add_parser("inspect", help="show what impedax reads from a spectrum file", description="Read FILE (CSV/TSV, netCDF, Gamry .DTA, BioLogic .mpt, ZPlot .z, Autolab NOVA text, LabOne CSV/HDF5) and summarise it; --out converts it to canonical CSV or netCDF.")
    p.add_argument("file", metavar="FILE", help="spectrum file")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--out", metavar="FILE.csv|nc", help="also save the spectrum in impedax's canonical form")
    p.set_defaults(run=run)


def run(args) -> int:
    import numpy as np

    from ..io.atomic import check_writable
    from ..io import load, save
    from .common import emit_json

    if args.out:
        check_writable(args.out)
    ds = load(args.file)
    freq = ds["frequency"].values
    z = ds["Z"].values
    summary = {
        "file": str(args.file),
        "format": ds.attrs.get("format", "netCDF"),
        "dims": {k: int(v) for k, v in ds["Z"].sizes.items()},
        "points": int(freq.size),
        "frequency_min_hz": float(freq.min()),
        "frequency_max_hz": float(freq.max()),
        "z_abs_min_ohm": float(np.abs(z).min()),
        "z_abs_max_ohm": float(np.abs(z).max()),
        "has_sigma": "sigma" in ds,
        "attrs": {k: v for k, v in ds.attrs.items() if isinstance(v, (str, int, float, bool))},
    }
    if args.out:
        save(ds, args.out)
    if args.json:
        emit_json(summary)
        return 0
    print(f"{summary['file']}: {summary['format']}, {summary['points']} frequencies "
          f"{summary['frequency_min_hz']:.4g}–{summary['frequency_max_hz']:.4g} Hz, "
          f"|Z| {summary['z_abs_min_ohm']:.4g}–{summary['z_abs_max_ohm']:.4g} Ω, dims {summary['dims']}")
    for key, value in summary["attrs"].items():
        if key not in ("format", "source", "path"):
            print(f"  {key}: {str(value).splitlines()[0] if str(value) else ''}")
    if args.out:
        print(f"wrote {args.out}")
    return 0
