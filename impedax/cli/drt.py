"""``impedax drt DATA``: the distribution of relaxation times — how many arcs, at which τ?"""

from __future__ import annotations


def _lam(text: str):
    from ..errors import ParameterError

    if text == "auto":
        return "auto"
    try:
        value = float(text)
    except ValueError:
        raise ParameterError(f"--lam {text!r}: expected 'auto' or a positive number") from None
    return value


def register(sub) -> None:
    from .common import add_select_option

    p = sub.add_parser(
        "drt",
        help="distribution of relaxation times (Tikhonov, Gaussian RBFs): peaks, R_inf, L, credible band",
        description="Compute the distribution of relaxation times of a spectrum by Tikhonov regularisation on a Gaussian RBF basis, "
        "lambda chosen by (modified) GCV or the L-curve; a file of several spectra gets the DRT of each (one line each). See docs/drt.md.",
    )
    p.add_argument("data", metavar="DATA", help="spectrum file (any format impedax reads); a file of several spectra gets a DRT of each, or pick one with --select")
    add_select_option(p)
    p.add_argument("--lam", default="auto", metavar="auto|VALUE", help="regularisation parameter: 'auto' (default; chosen by --lam-method) or a positive number used as given")
    p.add_argument("--lam-method", choices=("gcv", "lcurve"), default="gcv", help="how 'auto' chooses lambda (default: gcv)")
    p.add_argument("--method", choices=("tikhonov",), default="tikhonov", help="DRT method (default: tikhonov)")
    p.add_argument("--signed", action="store_true", help="allow negative gamma (inductive loops, negative capacitances)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE.png", help="save gamma vs tau with peaks and band, and the fit on Nyquist/Bode")
    p.add_argument("--out", metavar="FILE.nc|.csv", help="save gamma, its band and the fit (netCDF) or gamma over tau (CSV)")
    p.set_defaults(run=run)


def run(args) -> int:
    from ..fitting.drt import drt
    from ..fitting.grid import ResultGrid
    from ..fitting.problem import open_spectrum
    from .common import emit_json, figure_writer, load_selected, plan_outputs

    outputs = plan_outputs([("--out", args.out, "drt"), ("--plot", args.plot, "figure")], inputs=[args.data], stdout="--json" if args.json else None)
    # a file of several spectra: the DRT of each in one solve (`DRTBatchResult`), or one (--select)
    data = open_spectrum(load_selected(args.data, args.select)).data
    result = drt(data, method=args.method, lam=_lam(args.lam), lam_method=args.lam_method, signed=args.signed)
    outputs.save({"--out": lambda path: _save(result, path), "--plot": figure_writer(result.plot)})
    if outputs.uses_stdout:
        return 0
    batch = isinstance(result, ResultGrid)
    if args.json:
        if batch:
            emit_json({"dims": list(result.dims), "n_spectra": len(result), "spectra": [{"labels": where, **one.summary()} for where, one in zip(result.labels(), result.results)]})
        else:
            emit_json(result.summary())
        return 0
    print(result.report())
    if batch:
        for where, one in zip(result.labels(), result.results):
            peaks = "; ".join(f"{p.tau_s:.3g} s ({p.r_ohm:.3g} Ω)" for p in one.peaks) or "none"
            print(f"  {', '.join(f'{d}={v}' for d, v in where.items())}: rms_rel {one.rms_rel * 100:.3g} %, R_inf {one.r_inf_ohm:.4g} Ω, peaks {peaks}")
    return 0


def _save(result, path) -> None:
    """The DRT as netCDF (`to_xarray`, complex variables as Re and Im) or as CSV: γ over τ,
    for several spectra one block per spectrum after columns of its labels."""
    import numpy as np

    from ..io.atomic import atomic_path

    if str(path).lower().endswith(".nc"):
        ds = result.to_xarray()
        # netCDF3 has no complex type: store Re and Im
        for name in [n for n in ds.data_vars if np.iscomplexobj(ds[n].values)]:
            ds[f"{name}_real"], ds[f"{name}_imag"] = ds[name].real, ds[name].imag
            ds = ds.drop_vars(name)
        with atomic_path(path) as tmp:
            ds.to_netcdf(tmp, engine="scipy")
        return
    from ..fitting.grid import ResultGrid

    places, results = (result.labels(), result.results) if isinstance(result, ResultGrid) else ([{}], (result,))
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(",".join([*places[0], "tau_s", "gamma_ohm", "gamma_q05_ohm", "gamma_q95_ohm"]) + "\n")
            for where, one in zip(places, results):
                first = [str(v) for v in where.values()]
                for row in zip(one.tau, one.gamma, one.gamma_q05, one.gamma_q95):
                    fh.write(",".join(first + [f"{v:.10g}" for v in row]) + "\n")
